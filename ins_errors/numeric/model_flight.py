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

The residual ``f(x, u) − ẋ`` is checked against :data:`FLIGHT_TOLERANCE` of the terms it
sums: a model whose position equations use another Earth than the flight's, or whose
state is not a function of the navigation quantities, is refused in one line naming the
state and the time. The flight is planned on the model's own Earth: the semi-major axis
(or sphere radius), eccentricity and Earth rate read from its parameters by name
(:mod:`ins_errors.earth_constants`).

For ``strapdown_ned`` itself this reproduces the strapdown truth's body rates, specific
forces and height reference (the test suite compares them).
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ins_errors.errors import DomainError
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
def _adapter(model_key: str, determined: tuple[bool, ...]):
    """Compiled ``(c, ċ, u_prior, p) -> (x, u, residual, terms)``, mapped over
    :data:`CHUNK` columns (``p`` shared)."""
    from ins_errors.numeric.integrators import native_functions
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    functions = model.casadi.function
    nc, nu = len(model.initial_conditions), len(model.inputs)
    c, c_rate = ca.SX.sym("c", nc), ca.SX.sym("c_rate", nc)
    prior, p = ca.SX.sym("u_prior", nu), ca.SX.sym("p", len(model.parameters))
    x = functions("initial_state")(c, prior, p)
    x_rate = ca.jtimes(x, c, c_rate)
    xs, us = ca.SX.sym("xs", x.size1()), ca.SX.sym("us", nu)
    f_s = functions("ideal_rhs")(xs, us, p)
    rhs = ca.Function("rhs_and_jacobian", [xs, us, p], [f_s, ca.jacobian(f_s, us)])
    keep = [j for j in range(nu) if determined[j]]
    u = prior
    for _ in range(2):  # Gauss–Newton; the second step refines an affine f to rounding
        f, J = rhs(x, u, p)
        J = J[:, keep]
        step = ca.solve(J.T @ J, J.T @ (x_rate - f))
        u = u + ca.vertcat(*[step[keep.index(j)] if determined[j] else 0
                             for j in range(nu)])
    f, J = rhs(x, u, p)
    at_zero, _ = rhs(x, ca.DM.zeros(nu), p)
    terms = ca.fabs(at_zero) + ca.mtimes(ca.fabs(J), ca.fabs(u)) + ca.fabs(x_rate)
    # dense: a state the initial-state map sets to a constant (0) has a structural zero
    one = ca.Function("model_flight", [c, c_rate, prior, p],
                      [ca.densify(v) for v in (x, u, f - x_rate, terms)])
    mapped = one.map("model_flight_chunk", "serial", CHUNK, [3], [])
    return native_functions([mapped])[0]


UNSET_SHARE = 0.5
"""Part of a flight's residual off the tangent of the initial-state map above which it is
put down to a state no navigation quantity sets (:meth:`FlightAdapter._unset`)."""


@cache
def _tangent(model_key: str) -> ca.Function:
    """``(c, u, p) -> ∂x0/∂c`` (n, nc): the tangent of the model's initial-state map."""
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    c = ca.SX.sym("c", len(model.initial_conditions))
    u, p = ca.SX.sym("u", len(model.inputs)), ca.SX.sym("p", len(model.parameters))
    x0 = model.casadi.function("initial_state")(c, u, p)
    return ca.Function("initial_tangent", [c, u, p], [ca.densify(ca.jacobian(x0, c))])


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
        (the others keep their prior).

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
        self.function = _adapter(self.model_key, self.determined)

    def __getstate__(self) -> dict:
        """Pickled without the compiled function (a Monte Carlo run's worker processes
        receive the trajectory): it is found or compiled again on loading."""
        state = self.__dict__.copy()
        del state["function"]
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.function = _adapter(self.model_key, self.determined)

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

    def _evaluate(self, c: np.ndarray, c_rate: np.ndarray,
                  prior: np.ndarray) -> np.ndarray:
        """Columns (T, 3n + nu) of x, u, residual and terms: two Gauss–Newton steps from
        ``prior`` (nu, T) at conditions ``c`` and rates ``c_rate`` (nc, T)."""
        total = c.shape[1]
        n, nu = len(self.states), self.n_inputs
        outputs = np.empty((total, 2 * n + nu + n))  # x, u, residual, terms per column
        for first in range(0, total, CHUNK):
            last = min(first + CHUNK, total)
            columns = [np.zeros((CHUNK, a.shape[0])) for a in (c, c_rate, prior)]
            for array, source in zip(columns, (c, c_rate, prior), strict=True):
                array[:last - first] = source[:, first:last].T
                array[last - first:] = source[:, last - 1]
            out = [np.empty((CHUNK, k)) for k in (n, nu, n, n)]
            self.function([*columns, self.p], out)
            outputs[first:last] = np.hstack(out)[:last - first]
        return outputs

    def _unset(self, c: np.ndarray, u: np.ndarray, residual: np.ndarray) -> bool:
        """True when the residual ``f(x, u) − ẋ`` (n,) the inputs ``u`` leave at
        conditions ``c`` lies mostly off the tangent of the initial-state map: the model
        moves along a state that no navigation quantity sets (a wander angle), not on
        another Earth than the flight's or with inputs too few."""
        tangent = np.asarray(_tangent(self.model_key)(c, u, self.p), dtype=float)
        on = tangent @ np.linalg.lstsq(tangent, residual, rcond=None)[0]
        return bool(np.linalg.norm(residual - on) > UNSET_SHARE * np.linalg.norm(residual))

    def _excess(self, outputs: np.ndarray) -> np.ndarray:
        """|residual| over its allowance, (T, n) (≤ 1 where the model follows)."""
        n, nu = len(self.states), self.n_inputs
        residual, terms = outputs[:, n + nu:2 * n + nu], outputs[:, 2 * n + nu:]
        return np.abs(residual) / np.maximum(FLIGHT_TOLERANCE * terms, ABSOLUTE_TOLERANCE)

    def __call__(self, nav: np.ndarray, rate: np.ndarray,
                 times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """True states (n, T) and inputs (nu, T) at navigation quantities ``nav`` and
        rates ``rate`` (9, T) at ``times`` (T,), s.

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
        outputs = self._evaluate(c, c_rate, self._prior(c))
        n, nu = len(self.states), self.n_inputs
        excess = self._excess(outputs)
        worst = np.inf
        for _ in range(REFINE_ROUNDS):  # inputs that enter the equations non-linearly
            bad = ~np.all(excess <= 1.0, axis=1)
            now = float(np.nanmax(np.where(np.isnan(excess[bad]), np.inf, excess[bad]),
                                  initial=0.0))
            if not bad.any() or not now < 0.5 * worst:  # done, or no longer converging
                break
            worst = now
            again = self._evaluate(c[:, bad], c_rate[:, bad], outputs[bad, n:n + nu].T)
            outputs[bad], excess[bad] = again, self._excess(again)
        x, u = outputs[:, :n].T, outputs[:, n:n + nu].T
        residual = outputs[:, n + nu:2 * n + nu].T
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
            if self._unset(c[:, j], u[:, j], residual[:, j]):
                raise PathDependentStateError(
                    f"model {self.model_name!r} cannot fly this flight: its {name!r} "
                    f"(d{name}/dt off by {residual[k, j]:.3g} {unit}/s at t = "
                    f"{times[j]:.6g} s) moves along a state that no navigation quantity "
                    "sets (such as a wander angle), which depends on the path flown and "
                    "is not flown: its initial-state map holds it fixed; the static base "
                    "works (for a wander angle, flights along a meridian too)")
            raise MotionError(
                f"model {self.model_name!r} cannot follow the flight: no inputs make its "
                f"{name!r} move as the flight does at t = {times[j]:.6g} s (d"
                f"{name}/dt off by {residual[k, j]:.3g} {unit}/s); its states "
                "must be functions of latitude, longitude, height, velocity and attitude "
                "through its initial-state map, on an Earth with its parameters' radius, "
                "and the solve for its inputs must converge (it did not: inputs that "
                "enter its equations too non-linearly, or none that can)")
        return x, u
