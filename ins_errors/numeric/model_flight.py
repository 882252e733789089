"""Planned flights for any model fed body rates and specific forces (a strapdown INS of
one's own, written as a model file).

The flight generator of :mod:`ins_errors.numeric.strapdown_truth` plans a flight (great
circle, manoeuvre, legs) and gives, at any time, its exact navigation quantities

    ν = (φ, λ, h, v_N, v_E, v_D, roll, pitch, heading)

and their rates ν̇. Another model's true motion along that flight comes from the
model's own equations:

1. its initial conditions ``c`` are read from ν by name (:data:`CONDITIONS`: latitude,
   longitude, height or h, the velocities v_N/v_N0, v_E/v_E0, v_D/v_D0 or v_U/v_U0 = −v_D,
   roll, pitch, heading), and ċ from ν̇ alike;
2. its true state is its own initial-state map ``x = x0(c, p)`` at every time, and the
   state's rate ``ẋ = ∂x0/∂c ċ`` (exact, by automatic differentiation);
3. its inputs solve its own ideal work ``f(x, u) = ẋ`` in the least-squares sense (two
   Gauss–Newton steps from the prior of :mod:`ins_errors.numeric.static_rest`: exact for
   the affine ``f`` of an INS, whose instruments' signals enter linearly; where the
   residual is still too large, e.g. a compensation ``f + k f²``, the steps go on from
   the inputs found until it converges, :data:`REFINE_ROUNDS`); inputs the equations do
   not determine keep their prior.

A state that no navigation quantity sets but the path flown moves (the wander angle of
a wander-azimuth INS, ``α̇ = λ̇ sin φ`` off a meridian) is started by the initial-state
map at a parameter (``alpha0``): such parameters (:func:`carried_parameters`) move along
the flight. Where the ideal work cannot follow the flight with them held, their rates
are solved with the inputs, ``f(x0(c, q), u) = ∂x0/∂c ċ + ∂x0/∂q q̇``, and integrated
(:class:`CarriedPath`); a flight that keeps them still (the static base, a meridian) is
flown exactly as without them.

The residual ``f(x, u) − ẋ`` is checked against :data:`FLIGHT_TOLERANCE` of the terms it
sums: a model whose position equations use another Earth than the flight's, or whose
state is not a function of the navigation quantities (and of parameters the flight
carries), is refused in one line naming the state and the time. The flight is planned
on the model's own Earth: the semi-major axis (or sphere radius), eccentricity and Earth
rate read from its parameters by name (:mod:`ins_errors.earth_constants`).

For ``strapdown_ned`` itself this reproduces the strapdown truth's body rates, specific
forces and height reference (the test suite compares them).
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ins_errors.errors import DomainError
from ins_errors.numeric import interpolated_truth as it
from ins_errors.numeric.model import Model

NAVIGATION = ("latitude", "longitude", "height", "v_N", "v_E", "v_D", "roll", "pitch",
              "heading")
"""The navigation quantities ν of a planned flight, in this order (rad, rad, m, m/s ×3,
rad ×3)."""

CONDITIONS: dict[str, tuple[int, float]] = {
    "latitude": (0, 1.0), "longitude": (1, 1.0), "height": (2, 1.0), "h": (2, 1.0),
    "v_N": (3, 1.0), "v_N0": (3, 1.0), "v_E": (4, 1.0), "v_E0": (4, 1.0),
    "v_D": (5, 1.0), "v_D0": (5, 1.0), "v_U": (5, -1.0), "v_U0": (5, -1.0),
    "roll": (6, 1.0), "pitch": (7, 1.0), "heading": (8, 1.0)}
"""Initial-condition names read from the flight: (index in ν, sign)."""

FLIGHT_TOLERANCE = 1e-9
"""Largest |f_i(x, u) − ẋ_i| relative to the sum of the magnitudes of its terms
(|f_i(x, 0)| + Σ_j |∂f_i/∂u_j u_j| + |ẋ_i|) for which the model follows the flight."""

ABSOLUTE_TOLERANCE = 1e-12
"""… or below this (SI per second), for rows whose terms all vanish."""

CHUNK = 1024
"""Columns of one compiled call."""

REFINE_ROUNDS = 10
"""Further calls (two Gauss–Newton steps each) from the inputs found, at the times whose
residual is still too large (inputs that enter the equations non-linearly, e.g.
``f + k f²``); they stop as soon as the largest excess no longer halves. An affine model
needs none."""

MIN_FLIGHT_RADIUS = 100e3
"""Smallest Earth radius a flight is planned on, m: on a sphere of metres the flight's
course turns hundreds of radians a second and its integration never ends."""

DEFAULT_EARTH = {"e2": 0.0}
"""Eccentricity of a flight when the model has no such parameter (a sphere); without an
Earth-rate parameter the flight takes WGS-84's (its kinematics do not use it)."""


def condition_matrix(model: Model) -> np.ndarray:
    """``S`` with ``c = S ν`` for the model's initial conditions, shape (nc, 9).

    Raises
    ------
    MotionError
        One line naming the initial conditions a flight cannot set.
    """
    from ins_errors.numeric.trajectories import MotionError

    S = np.zeros((len(model.initial_conditions), len(NAVIGATION)))
    missing = []
    for row, condition in enumerate(model.initial_conditions):
        if condition.name in CONDITIONS:
            column, sign = CONDITIONS[condition.name]
            S[row, column] = sign
        else:
            missing.append(condition.name)
    if missing:
        raise MotionError(
            f"a moving flight cannot set the initial condition(s) {', '.join(missing)} of "
            f"model {model.name!r}: it sets {', '.join(sorted(CONDITIONS))}")
    return S


def flight_earth(model: Model, p: np.ndarray):
    """The Earth a flight of ``model`` is planned on, from its parameters by name.

    Returns
    -------
    strapdown_truth.FlightEarth
        Semi-major axis (or sphere radius), eccentricity and Earth rate of the model; the
        normal gravity of WGS-84 (the flight's kinematics do not use it).

    Raises
    ------
    MotionError
        The model has no Earth radius parameter (m) named as
        :data:`~ins_errors.earth_constants.RADIUS_NAMES`.
    EarthParameterError
        Its radius is below :data:`MIN_FLIGHT_RADIUS` or its eccentricity² outside [0, 1).
    """
    from ins_errors.earth_constants import RADIUS_NAMES, earth_parameter_names
    from ins_errors.models.earth import (
        EARTH_RATE,
        WGS84_EQUATORIAL_GRAVITY,
        WGS84_GRAVITY_M,
        WGS84_SOMIGLIANA_K,
    )
    from ins_errors.numeric.strapdown_truth import FlightEarth
    from ins_errors.numeric.trajectories import EarthParameterError, MotionError

    value = {i.name: float(v) for i, v in zip(model.parameters, p, strict=True)}
    radius, eccentricity, rate, _ = earth_parameter_names(model.parameters)
    if radius is None:
        raise MotionError(f"model {model.name!r} has no Earth radius parameter (m) named "
                          f"{', '.join(RADIUS_NAMES)}: a moving flight is planned on the "
                          "model's own Earth")
    if not (np.isfinite(value[radius]) and value[radius] >= MIN_FLIGHT_RADIUS):
        raise EarthParameterError(f"parameter {radius} = {value[radius]:g} m of model "
                          f"{model.name!r}: a flight needs a planet-sized Earth (radius at "
                          f"least {MIN_FLIGHT_RADIUS / 1e3:g} km)")
    if eccentricity and not (0.0 <= value[eccentricity] < 1.0):
        raise EarthParameterError(f"model {model.name!r}: the eccentricity² {eccentricity} = "
                          f"{value[eccentricity]:g} must be in [0, 1) for a flight")
    return FlightEarth(value[radius],
                  value[eccentricity] if eccentricity else DEFAULT_EARTH["e2"],
                  value[rate] if rate else EARTH_RATE,
                  WGS84_EQUATORIAL_GRAVITY, WGS84_SOMIGLIANA_K, WGS84_GRAVITY_M)


@cache
def _adapter(model_key: str, determined: tuple[bool, ...], carried: tuple[int, ...] = ()):
    """The model's state and inputs along a flight, compiled and mapped over
    :data:`CHUNK` columns (``p`` shared).

    ``(c, ċ, u_prior, p) -> (x, u, residual, terms)``: the state ``x = x0(c, p)`` of the
    initial-state map and the inputs ``u`` that make the ideal work follow it,
    ``f(x, u, p) = ∂x0/∂c ċ``, two Gauss–Newton steps from ``u_prior`` in the inputs
    ``determined`` (the second step refines an affine ``f`` to rounding; the others keep
    their prior); the residual ``f − ẋ`` and the sizes of its terms
    ``|f(x, 0)| + |∂f/∂u| |u| + |ẋ|`` (n each).

    With carried parameters ``carried`` (indices into ``p``):
    ``(c, ċ, u_prior, q, p) -> (x, u, q̇, residual, terms)``, the state ``x = x0(c, p | q)``
    with those parameters at the column's ``q`` in the initial-state map (the
    mechanisation keeps ``p``), and the steps solve for the inputs and the parameters'
    rates ``q̇`` together: ``f(x, u, p) = ∂x0/∂c ċ + ∂x0/∂q q̇``. Without carried
    parameters the ``q̇`` terms are empty and every expression is the one above."""
    from ins_errors.numeric.integrators import native_functions
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    functions = model.casadi.function
    nc, nu, n_p = len(model.initial_conditions), len(model.inputs), len(model.parameters)
    c, c_rate = ca.SX.sym("c", nc), ca.SX.sym("c_rate", nc)
    prior, p = ca.SX.sym("u_prior", nu), ca.SX.sym("p", n_p)
    q = ca.SX.sym("q", len(carried))
    moved = ca.vertcat(*[q[carried.index(k)] if k in carried else p[k] for k in range(n_p)])
    x = functions("initial_state")(c, prior, moved)
    along = ca.jtimes(x, c, c_rate)
    D = ca.jacobian(x, q)  # (n, 0) without carried parameters
    xs, us = ca.SX.sym("xs", x.size1()), ca.SX.sym("us", nu)
    f_s = functions("ideal_rhs")(xs, us, p)  # the mechanisation keeps its parameters
    rhs = ca.Function("rhs_and_jacobian", [xs, us, p], [f_s, ca.jacobian(f_s, us)])
    keep = [j for j in range(nu) if determined[j]]
    u, q_rate = prior, ca.DM.zeros(len(carried))
    for _ in range(2):  # Gauss–Newton in (u, q̇); the second step refines an affine f
        f, J = rhs(x, u, p)
        A = ca.horzcat(J[:, keep], -D)
        step = ca.solve(A.T @ A, A.T @ (along + D @ q_rate - f))
        u = u + ca.vertcat(*[step[keep.index(j)] if determined[j] else 0
                             for j in range(nu)])
        q_rate = q_rate + step[len(keep):, :]
    f, J = rhs(x, u, p)
    x_rate = along + D @ q_rate
    at_zero, _ = rhs(x, ca.DM.zeros(nu), p)
    terms = ca.fabs(at_zero) + ca.mtimes(ca.fabs(J), ca.fabs(u)) + ca.fabs(x_rate)
    if carried:
        name, inputs, outputs = ("model_flight_carried", [c, c_rate, prior, q, p],
                                 (x, u, q_rate, f - x_rate, terms))
    else:
        name, inputs, outputs = ("model_flight", [c, c_rate, prior, p],
                                 (x, u, f - x_rate, terms))
    # dense: a state the initial-state map sets to a constant (0) has a structural zero
    one = ca.Function(name, inputs, [ca.densify(v) for v in outputs])
    mapped = one.map(f"{name}_chunk", "serial", CHUNK, [len(inputs) - 1], [])
    return native_functions([mapped])[0]


@cache
def _directions(model_key: str) -> ca.Function:
    """``(c, u, p) -> (∂x0/∂c (n, nc), ∂x0/∂p (n, np), ∂f/∂u (n, nu) at x0)``."""
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    c = ca.SX.sym("c", len(model.initial_conditions))
    u, p = ca.SX.sym("u", len(model.inputs)), ca.SX.sym("p", len(model.parameters))
    x0 = model.casadi.function("initial_state")(c, u, p)
    f = model.casadi.function("ideal_rhs")(x0, u, p)
    return ca.Function("initial_directions", [c, u, p],
                       [ca.densify(v) for v in (ca.jacobian(x0, c), ca.jacobian(x0, p),
                                                ca.jacobian(f, u))])


CARRY_SHARE = 1e-6
"""Part of a parameter's direction ``∂x0/∂q`` (relative to its length) off the span of the
initial-state map's tangent ``∂x0/∂c``, the inputs' directions ``∂f/∂u`` and the
directions of the parameters already chosen, above which :func:`carried_parameters`
takes it: a parameter that starts a state no navigation quantity and no input sets."""


def carried_parameters(model: Model, c: np.ndarray, p: np.ndarray,
                       u: np.ndarray | None = None) -> tuple[int, ...]:
    """Indices of the parameters that a flight may carry as moving states.

    A state that no navigation quantity sets but the path flown moves (the wander angle
    of a wander-azimuth INS, ``α̇ = λ̇ sin φ``) is started by the initial-state map at a
    parameter (``alpha0``); along a flight that parameter moves with it. A parameter is
    taken when its direction ``∂x0/∂q`` at conditions ``c`` (nc,) leaves the span of the
    tangent ``∂x0/∂c``, of the inputs' directions ``∂f/∂u`` (at inputs ``u``, default
    zero) and of the parameters taken before it (:data:`CARRY_SHARE`): it then sets a
    part of the state that neither the flight nor the inputs can.

    Returns
    -------
    tuple of int
        Indices into ``p``; () for a model with none (every state set by the flight).
    """
    u = np.zeros(len(model.inputs)) if u is None else np.asarray(u, dtype=float)
    tangent, along_p, jacobian = (np.asarray(v, dtype=float) for v in
                                  _directions(model.key)(c, u, np.asarray(p, dtype=float)))
    basis = np.hstack([tangent, jacobian[:, np.any(jacobian != 0.0, axis=0)]])
    chosen: list[int] = []
    for k in range(along_p.shape[1]):
        d = along_p[:, k]
        size = np.linalg.norm(d)
        if not size > 0.0 or not np.all(np.isfinite(d)):
            continue
        off = d - basis @ np.linalg.lstsq(basis, d, rcond=None)[0]
        if np.linalg.norm(off) > CARRY_SHARE * size:
            chosen.append(k)
            basis = np.hstack([basis, d[:, None]])
    return tuple(chosen)


UNSET_SHARE = 0.5
"""Part of a flight's residual off the tangent of the initial-state map above which it is
put down to a state no navigation quantity sets (:meth:`FlightAdapter._unset`)."""


def uses_inputs(function: ca.Function, rows: list[int] | None = None) -> bool:
    """True when rows ``rows`` (default: all) of a model function of (state or initial
    conditions, inputs, parameters) depend on the inputs, e.g. ``initial_state``."""
    first, u, p = (ca.SX.sym(name, function.size1_in(k)) for k, name in enumerate("xup"))
    values = function(first, u, p)
    return any(ca.depends_on(values[i], u) for i in
               (range(values.numel()) if rows is None else rows))


class FlightAdapter:
    """A model's true states and inputs from a flight's navigation quantities.

    Parameters
    ----------
    model : Model
        A model fed inputs the kinematic motion generators cannot set.
    p : numpy.ndarray, shape (np,)
        Its parameters, SI.
    start : tuple of numpy.ndarray
        ν and ν̇ at t = 0, shape (9,) each: decides which inputs the equations determine
        (the others keep their prior) and which parameters a flight may carry
        (:func:`carried_parameters`).

    Attributes
    ----------
    carried : tuple of int
        The parameters (indices into ``p``) that start a state no navigation quantity
        sets; :meth:`follow` makes them move along a flight (:class:`CarriedPath`).
    path : CarriedPath or None
        Their values along the flight being flown, once :meth:`follow` is called.

    Raises
    ------
    MotionError
        An initial condition the flight cannot set, or an initial-state map that depends
        on the inputs.
    """

    def __init__(self, model: Model, p: np.ndarray, start: tuple[np.ndarray, np.ndarray]):
        from ins_errors.numeric.static_rest import HEIGHT_INPUTS
        from ins_errors.numeric.trajectories import MotionError

        # the model by key (a trajectory carrying this adapter is pickled, a Model not)
        self.model_key, self.model_name = model.key, model.name
        self.states = [(s.name, s.unit) for s in model.states]
        self.parameter_names = [q.name for q in model.parameters]
        self.n_inputs = len(model.inputs)
        self.p = np.ascontiguousarray(p, dtype=float)
        self.S = condition_matrix(model)
        conditions = {c.name for c in model.initial_conditions}
        if "heading" not in conditions and any(o.name == "heading" for o in model.outputs):
            raise MotionError(f"model {model.name!r} has a heading output but no initial "
                              "condition 'heading': a flight could not turn its body along "
                              "the course (it would fly sideways at heading 0); add the "
                              "initial condition 'heading' to its initial-state map")
        if uses_inputs(model.casadi.function("initial_state")):
            raise MotionError(f"model {model.name!r}: its initial state depends on its "
                              "inputs, so a moving flight cannot set it (a static base can)")
        self.height_prior = np.array([i.name in HEIGHT_INPUTS for i in model.inputs])
        self.determined = self._determined(*start)
        self.carried = carried_parameters(model, self.S @ start[0], self.p)
        self.path: CarriedPath | None = None
        self.function = _adapter(self.model_key, self.determined)
        self.carried_function = None

    def __getstate__(self) -> dict:
        """Pickled without the compiled functions (a Monte Carlo run's worker processes
        receive the trajectory): they are found or compiled again on loading."""
        state = self.__dict__.copy()
        del state["function"], state["carried_function"]
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.function = _adapter(self.model_key, self.determined)
        self.carried_function = None

    def follow(self, flight, earth, t_end: float, position) -> None:
        """Carry the parameters :attr:`carried` along ``flight`` (a moving
        :class:`~ins_errors.numeric.strapdown_truth.Flight` on ``earth``) over
        ``[0, t_end]`` s, its latitude, longitude, height and course (4, T) at times
        (T,) given by ``position`` (:class:`CarriedPath`). Nothing for a model without
        such parameters."""
        if self.carried:
            self.path = CarriedPath(self, flight, earth, float(t_end), position)

    def _determined(self, nav: np.ndarray, rate: np.ndarray) -> tuple[bool, ...]:
        """Which inputs the ideal work determines (a non-zero column of ∂f/∂u at the
        start)."""
        from ins_errors.numeric.static_rest import rest_functions

        rest, start = rest_functions(self.model_key)
        c = self.S @ nav
        u = self._prior(c[None, :].T)[:, 0]
        x = np.asarray(start(c, u, self.p), dtype=float).ravel()
        jacobian = np.asarray(rest(x, u, self.p)[1], dtype=float)
        return tuple(bool(v) for v in np.any(jacobian != 0.0, axis=0))

    def _prior(self, c: np.ndarray) -> np.ndarray:
        """Prior inputs (nu, T): the height for height inputs, else zero."""
        nav_height = self.S[:, 2] != 0
        height = (c[nav_height][0] if nav_height.any()
                  else np.zeros(c.shape[1]))
        prior = np.zeros((self.n_inputs, c.shape[1]))
        prior[self.height_prior] = height
        return prior

    def conditions(self, nav: np.ndarray) -> np.ndarray:
        """Initial conditions c (nc,) of navigation quantities ν (9,)."""
        return self.S @ nav

    def _evaluate(self, c: np.ndarray, c_rate: np.ndarray, prior: np.ndarray,
                  q: np.ndarray | None = None) -> list[np.ndarray]:
        """x (T, n), u (T, nu), q̇ (T, m), residual (T, n) and terms (T, n): two
        Gauss–Newton steps from ``prior`` (nu, T) at conditions ``c`` and rates
        ``c_rate`` (nc, T); with ``q`` (m, T), the carried parameters at those values
        and their rates solved too (else m = 0)."""
        total = c.shape[1]
        n, nu = len(self.states), self.n_inputs
        m = 0 if q is None else len(self.carried)
        if q is None:
            function, sources, widths = self.function, (c, c_rate, prior), (n, nu, n, n)
        else:
            if self.carried_function is None:
                self.carried_function = _adapter(self.model_key, self.determined,
                                                 self.carried)
            function, sources = self.carried_function, (c, c_rate, prior, q)
            widths = (n, nu, m, n, n)
        outputs = [np.empty((total, k)) for k in widths]
        for first in range(0, total, CHUNK):
            last = min(first + CHUNK, total)
            columns = [np.zeros((CHUNK, a.shape[0])) for a in sources]
            for array, source in zip(columns, sources, strict=True):
                array[:last - first] = source[:, first:last].T
                array[last - first:] = source[:, last - 1]
            out = [np.empty((CHUNK, k)) for k in widths]
            function([*columns, self.p], out)
            for whole, part in zip(outputs, out, strict=True):
                whole[first:last] = part[:last - first]
        if q is None:
            outputs.insert(2, np.empty((total, 0)))
        return outputs

    def _unset(self, c: np.ndarray, u: np.ndarray, residual: np.ndarray,
               q: np.ndarray | None = None) -> bool:
        """True when the residual ``f(x, u) − ẋ`` (n,) the inputs ``u`` leave at
        conditions ``c`` lies mostly off the tangent of the initial-state map (and off
        the directions of the carried parameters, at their values ``q``): the model
        moves along a state that no navigation quantity sets (a wander angle), not on
        another Earth than the flight's or with inputs too few."""
        if q is None:
            tangent = np.asarray(_directions(self.model_key)(c, u, self.p)[0], dtype=float)
        else:
            p = self.p.copy()
            p[list(self.carried)] = q
            tangent, along_p, _ = (np.asarray(v, dtype=float)
                                   for v in _directions(self.model_key)(c, u, p))
            tangent = np.hstack([tangent, along_p[:, list(self.carried)]])
        on = tangent @ np.linalg.lstsq(tangent, residual, rcond=None)[0]
        return bool(np.linalg.norm(residual - on) > UNSET_SHARE * np.linalg.norm(residual))

    @staticmethod
    def _excess(outputs: list[np.ndarray]) -> np.ndarray:
        """|residual| over its allowance, (T, n) (≤ 1 where the model follows)."""
        residual, terms = outputs[3], outputs[4]
        return np.abs(residual) / np.maximum(FLIGHT_TOLERANCE * terms, ABSOLUTE_TOLERANCE)

    def solved(self, c: np.ndarray, c_rate: np.ndarray, q: np.ndarray | None = None
               ) -> tuple[list[np.ndarray], np.ndarray]:
        """The outputs of :meth:`_evaluate` at conditions ``c`` and rates ``c_rate``
        (nc, T) (and carried parameters ``q`` (m, T)), refined where the residual is
        still too large (:data:`REFINE_ROUNDS`), and their excess (T, n)."""
        outputs = self._evaluate(c, c_rate, self._prior(c), q)
        excess = self._excess(outputs)
        worst = np.inf
        for _ in range(REFINE_ROUNDS):  # inputs that enter the equations non-linearly
            bad = ~np.all(excess <= 1.0, axis=1)
            now = float(np.nanmax(np.where(np.isnan(excess[bad]), np.inf, excess[bad]),
                                  initial=0.0))
            if not bad.any() or not now < 0.5 * worst:  # done, or no longer converging
                break
            worst = now
            again = self._evaluate(c[:, bad], c_rate[:, bad], outputs[1][bad].T,
                                   None if q is None else q[:, bad])
            for whole, part in zip(outputs, again, strict=True):
                whole[bad] = part
            excess[bad] = self._excess(again)
        return outputs, excess

    def __call__(self, nav: np.ndarray, rate: np.ndarray,
                 times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """True states (n, T) and inputs (nu, T) at navigation quantities ``nav`` and
        rates ``rate`` (9, T) at ``times`` (T,), s.

        Where the flight moves a carried parameter (:meth:`follow`), the states are the
        initial-state map at the parameter's value along the flight.

        Raises
        ------
        MotionError
            The model's ideal work cannot follow the flight (naming the state and time).
        DomainError
            NaN or infinite states or inputs.
        """
        from ins_errors.numeric.trajectories import MotionError, PathDependentStateError

        c = self.S @ nav
        c_rate = self.S @ rate
        q = None if self.path is None else self.path(times)
        if q is None or np.array_equal(q, np.repeat(self.p[list(self.carried), None],
                                                      q.shape[1], axis=1)):
            outputs, excess = self.solved(c, c_rate)
            if np.all(excess <= 1.0):
                q = None  # the parameters stay still: the states as without them
        if q is not None:
            outputs, excess = self.solved(c, c_rate, q)
        x, u, residual = outputs[0].T, outputs[1].T, outputs[3].T
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(u))):
            bad = ~(np.all(np.isfinite(x), axis=0) & np.all(np.isfinite(u), axis=0))
            raise DomainError(f"model {self.model_name!r}: its state or inputs along the "
                              f"flight are NaN or infinite at t = "
                              f"{times[int(np.argmax(bad))]:.6g} s")
        excess = excess.T
        if not np.all(excess <= 1.0):
            k, j = np.unravel_index(int(np.argmax(np.where(np.isfinite(excess), excess,
                                                           np.inf))), excess.shape)
            name, unit = self.states[k]
            if self._unset(c[:, j], u[:, j], residual[:, j],
                           None if q is None else q[:, j]):
                carried = ", ".join(self.parameter_names[i] for i in self.carried)
                held = (f"no parameter of its initial-state map that the flight carries "
                        f"({carried}) moves it" if self.carried else
                        "its initial-state map holds it fixed, and at no parameter that "
                        "the flight could carry (a wander angle started at a parameter "
                        "such as alpha0 is carried)")
                raise PathDependentStateError(
                    f"model {self.model_name!r} cannot fly this flight: its {name!r} "
                    f"(d{name}/dt off by {residual[k, j]:.3g} {unit}/s at t = "
                    f"{times[j]:.6g} s) moves along a state that no navigation quantity "
                    f"sets (such as a wander angle), which depends on the path flown and "
                    f"is not flown: {held}; the static base works, and so do flights "
                    "that keep that state still")
            raise MotionError(
                f"model {self.model_name!r} cannot follow the flight: no inputs make its "
                f"{name!r} move as the flight does at t = {times[j]:.6g} s (d"
                f"{name}/dt off by {residual[k, j]:.3g} {unit}/s); its states "
                "must be functions of latitude, longitude, height, velocity and attitude "
                "through its initial-state map, on an Earth with its parameters' radius, "
                "and the solve for its inputs must converge (it did not: inputs that "
                "enter its equations too non-linearly, or none that can)")
        return x, u


PICARD_ROUNDS = 30
"""Picard iterations of a block of :class:`CarriedPath` at most (a carried parameter
whose rate does not depend on it, such as a wander angle, needs two)."""

PICARD_TOLERANCE = 1e-14
"""A block's Picard iteration has converged when it changes no carried parameter by
more than this, relative to the parameter's size (at least 1)."""


class CarriedPath(it.NodePath):
    """The carried parameters of a model (:func:`carried_parameters`) along a flight.

    Their rates ``q̇`` solve, with the model's inputs, its ideal work along the flight,
    ``f(x0(c, q), u) = ∂x0/∂c ċ + ∂x0/∂q q̇`` (:func:`_adapter`); where the flight
    does not move them (the ideal work follows the flight with the parameters held, as
    :meth:`FlightAdapter.solved` finds to its tolerances) their rate is zero, so a flight
    that keeps them still keeps them at their values, bit for bit. The integral
    ``q(t) = q(0) + ∫ q̇ dt`` is taken on intervals of at most
    :data:`~ins_errors.numeric.interpolated_truth.INTERVAL` (10 s) ending at the flight's
    breaks (leg joins, the samples of a motion file): the degree-7 polynomial through the
    Chebyshev–Lobatto nodes of each (the integration matrix of
    :func:`~ins_errors.numeric.strapdown_stream.integration_matrix`, Clenshaw–Curtis
    accuracy), iterated (Picard) where ``q̇`` depends on ``q``; between the nodes ``q``
    is that polynomial. Measured against an adaptive reference (DOP853 at a relative
    tolerance of 1e-13), a wander angle along a great circle and the manoeuvre is exact
    to about 1e-13 rad over hours (``tests/test_wander_flight.py``).

    The intervals are integrated :attr:`BLOCK` at a time when a run reaches them, two
    blocks held and the start of every block kept (the blocks and the rereads of
    :class:`~ins_errors.numeric.interpolated_truth.NodePath`), so a rerun gets the same
    bits and a long flight needs memory for two blocks only.

    Parameters
    ----------
    adapter : FlightAdapter
    flight : strapdown_truth.Flight
        A moving flight.
    earth : strapdown_truth.FlightEarth
    t_end : float
        End of the run, s.
    position : callable
        Latitude, longitude, height and course (4, T) of the flight at times (T,).
    """

    BLOCK = 128
    """Intervals of one block (1024 nodes: one compiled call)."""

    def __init__(self, adapter: FlightAdapter, flight, earth, t_end: float, position):
        from ins_errors.numeric.strapdown_stream import integration_matrix

        self.adapter, self.flight, self.earth, self.position = adapter, flight, earth, position
        edges = [float(b) for b in flight.breaks] if flight.breaks else []
        if flight.geographic:
            edges += [float(b) for b in np.asarray(flight.commands.splines[0].x)]
        super().__init__(np.asarray(edges, dtype=float), t_end,
                         adapter.p[list(adapter.carried)])
        self.integral = integration_matrix()
        self.integral[0] = 0.0  # node 0 is the interval's start

    def _nodes(self, first: np.ndarray, start: np.ndarray, length: np.ndarray,
               t: np.ndarray) -> np.ndarray:
        """Values (J, DEGREE + 1, m) of the carried parameters at the nodes (see
        :meth:`NodePath._nodes <ins_errors.numeric.interpolated_truth.NodePath._nodes>`):
        their rate solved with the inputs at the nodes and integrated, iterated (Picard)
        where it depends on them."""
        from ins_errors.numeric.strapdown_truth import rigid_body_signals

        *_, nav, rates = rigid_body_signals(self.flight, self.earth, t, self.position(t),
                                            navigation=True)
        adapter = self.adapter
        c, c_rate = adapter.S @ nav, adapter.S @ rates
        _, excess = adapter.solved(c, c_rate)
        still = np.all(excess <= 1.0, axis=1)  # the flight does not move them here
        m, shape = len(adapter.carried), (start.size, it.DEGREE + 1)
        nodes = np.repeat(first[None, None, :], shape[0] * shape[1],
                          axis=1).reshape(*shape, m)
        size = max(1.0, float(np.abs(first).max()))
        for _ in range(PICARD_ROUNDS):
            if still.all():
                break
            outputs, _ = adapter.solved(c, c_rate, nodes.reshape(-1, m).T)
            rate = np.where(still[:, None], 0.0, outputs[2]).reshape(*shape, m)
            rises = length[:, None, None] * np.einsum("ik,jkm->jim", self.integral, rate)
            before = np.cumsum(np.vstack([np.zeros((1, m)), rises[:-1, -1]]), axis=0)
            again = first[None, None, :] + before[:, None, :] + rises
            change = float(np.abs(again - nodes).max())
            nodes = again
            if not np.all(np.isfinite(nodes)):
                raise DomainError(f"model {adapter.model_name!r}: its carried parameters "
                                  f"are NaN or infinite along the flight after "
                                  f"t = {start[0]:.6g} s")
            if change <= PICARD_TOLERANCE * size:
                break
        else:
            raise DomainError(f"model {adapter.model_name!r}: the rate of its carried "
                              "parameters depends on them too strongly for their "
                              f"integration between t = {start[0]:.6g} and "
                              f"{start[-1] + length[-1]:.6g} s to converge")
        return nodes

    def _interpolated(self, weights: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """As :class:`~ins_errors.numeric.interpolated_truth.NodePath`, but an interval
        where the parameters are held gives exactly their value."""
        out = super()._interpolated(weights, nodes)
        flat = np.all(nodes == nodes[:, :1], axis=(1, 2))
        out[:, flat] = nodes[flat, 0].T
        return out
