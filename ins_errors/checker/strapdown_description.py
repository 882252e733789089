"""The navigation description and the φ/ψ conventions of any strapdown model, from its
own equations (a researcher's strapdown INS written as a model file).

A hand-coded F and G (``check MODEL --matrix``) is a function of the navigation solution,
and a textbook F is written in φ- or ψ-angle states, not in a model's own states (a
direction-cosine matrix, a quaternion, …, in NED or ENU, with any body axes). A model
*describes itself* when it has

* the outputs ``latitude``, ``longitude``, ``height`` (or ``h``), ``v_N``, ``v_E``,
  ``v_D`` (or ``v_U``), ``roll``, ``pitch``, ``heading`` (:data:`NAVIGATION_OUTPUTS`),
  functions of its state;
* the inputs ``omega_x``, ``omega_y``, ``omega_z`` (body rate, rad/s) and ``f_x``,
  ``f_y``, ``f_z`` (specific force, m/s²) (:data:`IMU_INPUTS`), along its own body axes;
* an Earth radius parameter (``a`` or ``R``, with ``e2`` for an ellipsoid; the names of
  :mod:`ins_errors.earth_constants`) and an initial-state map from the navigation
  quantities (:mod:`ins_errors.numeric.model_flight`: its moving flights need it too).

Everything else is read from its equations, so no axis convention is assumed:

* its attitude ``C_bn`` (body → NED) is the matrix through which its accelerometers
  drive its NED velocity, ``C(x) = ∂(v̇_NED)/∂f_b = H_v ∂f/∂f_b`` (``H_v`` the Jacobian
  of the velocity outputs), so ``f_n = C_bn f_b`` holds in the navigation description
  whatever its body axes (forward-right-down, right-forward-up, …);
* the φ-angle rows of its error state are the skew part of ``−δC Cᵀ``, the velocity
  rows ``H_v``, the position rows the Jacobian of latitude, longitude and height; every
  convention of ``strapdown_ned`` follows from them as for ``strapdown_ned``
  (:func:`ins_errors.models.strapdown_conventions.convention_blocks`), with ``Ṫ`` by
  exact differentiation along the ideal flow;
* a model's error state may have directions a convention does not see (the six of a
  direction-cosine matrix beyond its three angles, the norm of a quaternion). The
  derived F in the convention is ``(Ṫ + T F) L`` with the *lift* ``L = K (T K)⁻¹``, ``K``
  the tangent of the model's initial-state map at the current navigation solution (and
  at the current value of a parameter a flight carries, such as a wander angle's
  ``alpha0``: :func:`carried_values`): the
  error state of a convention state on the model's own state manifold (orthonormal
  matrices, unit quaternions), which its equations keep. (``(T K)⁻¹`` also absorbs the
  sign of a quaternion that the initial-state map gives as −q once the heading has
  wrapped.)
"""

from __future__ import annotations

import hashlib
from functools import cache, lru_cache

import casadi as ca
import numpy as np

from ins_errors.earth_constants import earth_parameter_names
from ins_errors.errors import InsErrorsError

NAVIGATION_OUTPUTS = ("latitude", "longitude", "height", "v_N", "v_E", "v_D", "roll",
                      "pitch", "heading")
"""The outputs a strapdown model describes itself with, in the order of the navigation
quantities ν of :mod:`ins_errors.numeric.model_flight`; :data:`ALTERNATIVES` may stand
for some of them."""

ALTERNATIVES = {"height": (("h", 1.0),), "v_D": (("v_U", -1.0),)}
"""Other outputs that give a navigation quantity: (name, sign)."""

IMU_INPUTS = ("omega_x", "omega_y", "omega_z", "f_x", "f_y", "f_z")
"""Body rate (rad/s) and specific force (m/s²) inputs, body axes x, y, z."""


def _outputs(model) -> list[tuple[int, float]] | None:
    """(index, sign) of the output giving each navigation quantity, or None."""
    names = [o.name for o in model.outputs]
    out = []
    for name in NAVIGATION_OUTPUTS:
        for candidate, sign in ((name, 1.0), *ALTERNATIVES.get(name, ())):
            if candidate in names:
                out.append((names.index(candidate), sign))
                break
        else:
            return None
    return out


def missing(model) -> list[str]:
    """What ``model`` lacks to describe itself (empty when it does)."""
    from ins_errors.earth_constants import RADIUS_NAMES

    lacks = []
    outputs = {o.name for o in model.outputs}
    absent = [n + "".join(f" (or {a})" for a, _ in ALTERNATIVES.get(n, ()))
              for n in NAVIGATION_OUTPUTS
              if n not in outputs and not any(a in outputs for a, _ in ALTERNATIVES.get(n, ()))]
    if absent:
        lacks.append(f"the outputs {', '.join(absent)}")
    inputs = {i.name for i in model.inputs}
    absent = [n for n in IMU_INPUTS if n not in inputs]
    if absent:
        lacks.append(f"the inputs {', '.join(absent)}")
    if earth_parameter_names(model.parameters).radius is None:
        lacks.append(f"an Earth radius parameter ({' or '.join(RADIUS_NAMES)}, m)")
    if len(model.error_states) != len(model.states):
        lacks.append("one error state per state (no extra real-work states)")
    if not lacks and _outputs_use_inputs(model):
        lacks.append("navigation outputs that are functions of the state alone (its "
                     "outputs depend on its inputs)")
    return lacks


def _outputs_use_inputs(model) -> bool:
    """True when the model's navigation outputs depend on its inputs."""
    from ins_errors.numeric.model_flight import uses_inputs

    return uses_inputs(model.casadi.function("outputs"), [i for i, _ in _outputs(model)])


ORTHONORMAL_TOLERANCE = 1e-6
"""Largest |C Cᵀ − I| of the attitude read from a model's equations."""

ROUND_TRIP_TOLERANCE = 1e-7
"""Largest change of a navigation quantity (rad, m, m/s; relative to 1 + its size) when
the model's initial-state map is given what its outputs read."""

INVARIANCE_TOLERANCE = 1e-8
"""Largest part of an error state's rate, relative to the row's terms, that leaves the
span of the initial-state map (:func:`validate`)."""


class UnspannedStateError(InsErrorsError):
    """A state of a strapdown model that the navigation errors drive but no navigation
    quantity sets, and that feeds them back (property 3 of :func:`validate`).

    Its message is the matrix check's; :meth:`budget_message` is the budget's.

    Parameters
    ----------
    model_name, state : str
        The model and its worst state.
    share : float
        The part of that state's rate off the span of the initial-state map, relative
        to its terms.
    """

    def __init__(self, model_name: str, state: str, share: float):
        self.model_name, self.state, self.share = model_name, state, share
        super().__init__(self._words("so a φ/ψ convention would drop it; check the hand "
                                     "model in the model's own states (--convention model)"))

    def _words(self, remedy: str) -> str:
        return (f"model {self.model_name!r}: its error state leaves what its initial-state "
                f"map spans: {self.state!r} changes with the navigation errors "
                f"({self.share:.3g} of its rate) but no navigation quantity sets it, "
                + remedy)

    def budget_message(self) -> str:
        """The refusal in the budget's words: its attitude items (``vertical_error``,
        ``heading_error``, ``heading_drift``) read the φ-angle, which this state
        escapes; its other items do not."""
        return self._words("so the φ-angle of the spec's attitude items (vertical_error, "
                           "heading_error, heading_drift) does not follow it; budget a "
                           "spec without them")


def validate(model, parts: tuple[str, str, str, str], x: np.ndarray, u: np.ndarray,
             p: np.ndarray) -> None:
    """Refuse, in one line, a strapdown model the conventions cannot carry along ``x``.

    Three properties the construction of the module docstring rests on, checked at every
    sample:

    1. the attitude read from its equations is a rotation: ``C Cᵀ = I`` and ``det C = 1``
       (its accelerometer inputs in m/s² along right-handed body axes);
    2. its outputs read back what its initial-state map sets: ν(x0(S ν(x))) = ν(x)
       (the same angle conventions in both);
    3. its error state stays in the span of the initial-state map's tangent K: the part
       of ``F K − K̇`` off that span, ``(I − L T)(F K − K̇)``, vanishes (a state no
       navigation quantity sets, e.g. the integrator of a third-order height loop,
       would be driven and dropped), or the directions it takes are unseen by the
       convention and stay so (:func:`_unseen`: a wander angle).

    Parameters
    ----------
    model : Model
    parts : tuple of str
        (model key, attitude, velocity, position) of the convention.
    x, u : numpy.ndarray, shape (n, K), (nu, K)
        True states and inputs.
    p : numpy.ndarray, shape (np,)

    Raises
    ------
    InsErrorsError
        Naming the property, the worst state or quantity and its size.
    """
    p = np.asarray(p, dtype=float)
    nu, C = _along(_navigation_function(model.key), x, p)
    C = np.moveaxis(C, -1, 0)
    gram = np.abs(C @ np.swapaxes(C, 1, 2) - np.eye(3)).max()
    if not gram <= ORTHONORMAL_TOLERANCE or not np.all(np.linalg.det(C) > 0):
        raise InsErrorsError(
            f"model {model.name!r}: the attitude through which its accelerometers drive its "
            f"NED velocity is not a rotation (|C Cᵀ − I| up to {gram:.3g}, det C "
            f"{np.linalg.det(C).min():.3g}): the φ/ψ conventions need specific-force inputs "
            "f_x..z in m/s² along right-handed body axes")
    nu = nu[:, 0]
    back = _along(_round_trip_function(model.key), x, p)[0][:, 0]
    change = back - nu
    angles = [0, 1, 6, 7, 8]  # latitude, longitude, roll, pitch, heading
    change[angles] = (change[angles] + np.pi) % (2 * np.pi) - np.pi
    relative = np.abs(change) / (1.0 + np.abs(nu))
    if not relative.max() <= ROUND_TRIP_TOLERANCE:
        k, j = np.unravel_index(int(np.nanargmax(np.where(np.isfinite(relative), relative,
                                                          np.inf))), relative.shape)
        raise InsErrorsError(
            f"model {model.name!r}: its output {NAVIGATION_OUTPUTS[k]!r} does not read back "
            f"what its initial-state map was given ({nu[k, j]:.6g} read, {back[k, j]:.6g} "
            "after the map): the outputs and the initial conditions must use the same "
            "conventions (heading from north, clockwise; roll, pitch, heading z-y-x)")
    xdot = np.asarray(model.numpy.ideal_rhs(x, u, p), dtype=float)
    moved = carried_values(model, x, p)
    K, T = _evaluated(parts, TANGENT, x, moved), _evaluated(parts, TRANSFORM, x, p)
    K_dot = _tangent_rate(model, parts, x, xdot, p, moved)
    L = _lift(K, T)
    F = np.moveaxis(np.asarray(model.state_matrix(x, u, p), dtype=float), -1, 0)
    D = _carried_directions(model, parts, x, xdot, p, moved, T, F)
    off = _off_span(F @ K - K_dot, L, T, D)
    scale = (np.abs(F) @ np.abs(K) + np.abs(K_dot)).max(axis=(0, 2)) + 1e-300
    defect = np.abs(off).max(axis=(0, 2)) / scale
    if not defect.max() <= INVARIANCE_TOLERANCE and not _unseen(parts, x, xdot, p, T, F, K,
                                                                 K_dot, L, D):
        k = int(np.nanargmax(np.where(np.isfinite(defect), defect, np.inf)))
        raise UnspannedStateError(model.name, model.states[k].name, float(defect[k]))


def _off_span(moved: np.ndarray, L: np.ndarray, T: np.ndarray,
              D: np.ndarray | None) -> np.ndarray:
    """The part ``(I − L T) m`` of ``m`` (K, n, 9) off the span of the initial-state
    map's tangent, less its part along the carried parameters' directions ``D``
    (K, n, m) when given (the state they start: :func:`_carried_directions`)."""
    off = moved - L @ (T @ moved)
    if D is not None:
        Dt = np.swapaxes(D, 1, 2)
        off = off - D @ np.linalg.solve(Dt @ D, Dt @ off)
    return off


def _carried_directions(model, parts: tuple[str, str, str, str], x: np.ndarray,
                        xdot: np.ndarray, p: np.ndarray, moved: np.ndarray, T: np.ndarray,
                        F: np.ndarray) -> np.ndarray | None:
    """The directions ``∂x0/∂q`` (K, n, m) of the carried parameters at every sample
    (None for a model without them), once they are checked to stay unseen by the
    convention, ``(Ṫ + T F) ∂x0/∂q = 0`` entry by entry against its terms (a wander
    angle: turning the position matrix about the vertical and counter-turning the
    attitude and velocity is a symmetry of the equations that changes no navigation
    quantity).

    Raises
    ------
    UnspannedStateError
        A carried parameter's state feeds the navigation errors.
    """
    carried = _carried(model, x, p)
    if not carried:
        return None
    values = moved if moved.ndim == 2 else np.repeat(moved[:, None], x.shape[-1], axis=1)
    D = np.moveaxis(_along(_carried_functions(model.key, carried)[0], x, values)[1], -1, 0)
    T_dot = np.moveaxis(_along(_functions(*parts)[1], x, xdot, p)[0], -1, 0)
    feed = (T_dot + T @ F) @ D
    terms = (np.abs(T_dot) + np.abs(T) @ np.abs(F)) @ np.abs(D)
    terms = terms + INVARIANCE_TOLERANCE * terms.max(axis=(0, 2), keepdims=True)
    share = (np.abs(feed) / (terms + 1e-300)).max(axis=(0, 1))
    if not share.max() <= INVARIANCE_TOLERANCE:
        k = int(np.nanargmax(np.where(np.isfinite(share), share, np.inf)))
        raise UnspannedStateError(model.name, model.parameters[carried[k]].name,
                                  float(share[k]))
    return D


def _unseen(parts: tuple[str, str, str, str], x: np.ndarray, xdot: np.ndarray,
            p: np.ndarray, T: np.ndarray, F: np.ndarray, K: np.ndarray, K_dot: np.ndarray,
            L: np.ndarray, D: np.ndarray | None = None) -> bool:
    """True when the error-state directions that leave the span of the initial-state map
    (:func:`validate`) stay unseen by the convention.

    Those directions are the columns of ``off = (I − L T) m``, ``m = F K − K̇`` (shape
    (K, n, 9)); they are in the null space of ``T`` by construction (``T L = I``) and
    stay unseen when the convention's states do not change with them,
    ``(Ṫ + T F) off = 0``: an error along them then never reaches the navigation errors
    and the derived ``(Ṫ + T F) L`` is exact whatever part of the error lies along them.
    The wander angle of a wander-azimuth INS is such a direction (turning its position
    matrix about the vertical and counter-turning its attitude and velocity is a
    symmetry of its equations that changes no navigation quantity); the integrator of a
    third-order height loop is not (it drives the vertical velocity). Tested at every
    sample, each entry of ``(Ṫ + T F) off`` against the magnitude of the terms it sums,
    those of ``off`` and ``m`` included, with a floor of the tolerance times the largest
    of its row (:data:`INVARIANCE_TOLERANCE`; rounding leaves about 1e-16 of them).
    """
    T_dot = np.moveaxis(_along(_functions(*parts)[1], x, xdot, p)[0], -1, 0)
    moved = F @ K - K_dot
    off = _off_span(moved, L, T, D)
    feed = (T_dot + T @ F) @ off
    sizes = np.abs(F) @ np.abs(K) + np.abs(K_dot)  # of the terms of m, entry by entry
    terms = ((np.abs(T_dot) + np.abs(T) @ np.abs(F))
             @ (sizes + np.abs(L) @ (np.abs(T) @ sizes)))
    terms = terms + INVARIANCE_TOLERANCE * terms.max(axis=(0, 2), keepdims=True)  # row's
    excess = np.abs(feed) - INVARIANCE_TOLERANCE * terms
    return bool(np.all(excess <= 0.0))


def describes(model) -> bool:
    """True when ``model`` is a strapdown model with the outputs, inputs and Earth of
    the module's description (:func:`missing` is empty)."""
    return not missing(model)


def is_strapdown(model) -> bool:
    """True for a strapdown INS the φ-angle conventions and strapdown flights carry: the
    built-in ``strapdown_ned``, or a model file that describes itself (:func:`describes`)."""
    return model.name == "strapdown_ned" or describes(model)


def navigation(model, x: np.ndarray, u: np.ndarray, p: np.ndarray) -> dict[str, np.ndarray]:
    """The navigation description (:data:`~ins_errors.checker.navigation.FIELDS`) of a
    strapdown model along states ``x`` (n, K) and inputs ``u`` (nu, K)."""
    from ins_errors.models.earth import EARTH_RATE, radii_of_curvature

    k = x.shape[-1]
    nav, C = _along(_navigation_function(model.key), x, np.asarray(p, dtype=float))
    lat, lon, h, vN, vE, vD = nav[:6, 0]
    value = dict(zip((q.name for q in model.parameters), np.asarray(p, dtype=float),
                     strict=True))
    radius, eccentricity, rate, _ = earth_parameter_names(model.parameters)
    a = value[radius]
    e2 = value[eccentricity] if eccentricity else 0.0
    U = value[rate] if rate else EARTH_RATE
    r_n, r_e = radii_of_curvature(lat, a, e2)
    zeros = np.zeros(k)
    index = {i.name: j for j, i in enumerate(model.inputs)}
    return {
        "latitude": lat, "longitude": lon, "height": h, "v_ned": np.array([vN, vE, vD]),
        "C_bn": C,
        "omega_ie_n": np.array([U * np.cos(lat), zeros, -U * np.sin(lat)]),
        "omega_en_n": np.array([vE / (r_e + h), -vN / (r_n + h),
                                -vE * np.tan(lat) / (r_e + h)]),
        "gravity": gravity(model, x, p),
        "R_N": r_n, "R_E": r_e, "a": np.full(k, a), "e2": np.full(k, e2),
        "earth_rate": np.full(k, U),
        "f_b": u[[index[n] for n in IMU_INPUTS[3:]]],
        "omega_ib_b": u[[index[n] for n in IMU_INPUTS[:3]]],
    }


def _symbols(model):
    """CasADi symbols and expressions of a model's navigation: ``x``, ``p``, the
    navigation quantities ν(x) (9,), the NED velocity rows ``H_v`` (3, n) and the
    attitude ``C(x) = H_v ∂f/∂f_b`` (3, 3)."""
    n, n_u, n_p = len(model.states), len(model.inputs), len(model.parameters)
    x, p = ca.SX.sym("x", n), ca.SX.sym("p", n_p)
    outputs = model.casadi.function("outputs")(x, ca.DM.zeros(n_u), p)
    nu = ca.vertcat(*[sign * outputs[i] for i, sign in _outputs(model)])
    H_v = ca.jacobian(nu[3:6], x)
    u = ca.SX.sym("u", n_u)
    names = [i.name for i in model.inputs]
    forces = [names.index(name) for name in IMU_INPUTS[3:]]
    J = ca.jacobian(model.casadi.function("ideal_rhs")(x, u, p), u)[:, forces]
    C = H_v @ ca.substitute(J, u, ca.DM.zeros(n_u))  # affine in u: J does not depend on it
    return x, p, nu, H_v, C


@cache
def _navigation_function(model_key: str) -> ca.Function:
    """``(x, p) -> (ν (9, 1), C_bn (3, 3))``."""
    from ins_errors.numeric.model import load_model

    x, p, nu, _, C = _symbols(load_model(model_key))
    return ca.Function("strapdown_navigation", [x, p], [ca.densify(nu), ca.densify(C)])


REST_STEPS = 2
"""Gauss–Newton steps of :func:`gravity` for the inputs at rest (the first solves the
affine equations of an INS, the second refines it to rounding)."""


@cache
def _rest_function(model_key: str) -> ca.Function:
    """``(x, u, p) -> (f (n, 1), ∂f/∂u (n, nu), g (3, 1), prior (nu, 1))`` at the rest
    state of the position of ``x``: the model's ideal right-hand side and its Jacobian,
    the NED velocity rate with the specific-force inputs set to zero and the others at
    ``u``, and the prior inputs of its static base
    (:data:`~ins_errors.numeric.static_rest.HEIGHT_INPUTS` at the height, others zero)."""
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.model_flight import condition_matrix
    from ins_errors.numeric.static_rest import HEIGHT_INPUTS

    model = load_model(model_key)
    x, p, nu, H_v, _ = _symbols(model)
    names = [i.name for i in model.inputs]
    u = ca.SX.sym("u", len(names))
    rest = ca.vertcat(nu[0:3], ca.DM.zeros(3), nu[6:9])
    x0 = model.casadi.function("initial_state")(ca.DM(condition_matrix(model)) @ rest, u, p)
    rhs = model.casadi.function("ideal_rhs")
    f = rhs(x0, u, p)
    forces = [names.index(name) for name in IMU_INPUTS[3:]]
    no_force = ca.vertcat(*[0 if j in forces else u[j] for j in range(len(names))])
    g = ca.Function("H_v", [x, p], [H_v])(x0, p) @ rhs(x0, no_force, p)
    prior = ca.vertcat(*[nu[2] if name in HEIGHT_INPUTS else 0 for name in names])
    return ca.Function("gravity_at_rest", [x, u, p],
                       [ca.densify(v) for v in (f, ca.jacobian(f, u), g, prior)])


def gravity(model, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The model's own gravity (plumb line, m/s²) at the positions of ``x`` (n, K),
    shape (K,).

    The model is put at rest there, as on a static base
    (:func:`ins_errors.numeric.static_rest.static_rest`): its initial-state map given
    the latitude, longitude, height and attitude its outputs read and zero velocity,
    and its inputs solving its ideal work ``f(x0, u) = 0`` in the least-squares sense
    from the static base's prior (the height for a height input, zero for the others),
    so that an external reference such as the height ``h_ref`` of a baro damping loop
    takes its true value and its loop adds nothing. The gravity is then what changes
    its NED velocity with the specific-force inputs set to zero, ``g = H_v f(x0, u)``
    (the Coriolis and transport-rate terms vanish with the velocity): a constant
    parameter ``g``, normal gravity on its ellipsoid, or a point mass μ/r² less the
    centrifugal acceleration, whatever it computes, and what its accelerometers read
    at rest (``ins-errors modes``).
    """
    p = np.asarray(p, dtype=float)
    function = _rest_function(model.key)
    u = _along(function, x, np.zeros((len(model.inputs), x.shape[-1])), p)[3][:, 0, :]
    for _ in range(REST_STEPS):
        f, J, _, _ = _along(function, x, u, p)
        J = np.moveaxis(J, -1, 0)
        rcond = np.finfo(float).eps * max(J.shape[1:])
        u = u - np.einsum("kij,jk->ik", np.linalg.pinv(J, rcond=rcond), f[:, 0, :])
    g = _along(function, x, u, p)[2]
    return np.linalg.norm(g[:, 0, :], axis=0)


@cache
def _functions(model_key: str, attitude: str, velocity: str, position: str
               ) -> tuple[ca.Function, ca.Function, ca.Function]:
    """``T(x, p)``, ``Ṫ(x, ẋ, p)`` and ``K(x, p)`` of a convention (the lift is
    ``K (T K)⁻¹``)."""
    from ins_errors.models import strapdown_conventions as sc
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.model_flight import condition_matrix

    model = load_model(model_key)
    x, p, nu, H_v, C = _symbols(model)
    n = x.numel()
    radius, eccentricity, _, _ = earth_parameter_names(model.parameters)
    names = [q.name for q in model.parameters]
    a = p[names.index(radius)]
    e2 = p[names.index(eccentricity)] if eccentricity else 0.0
    # φ: [φ×] = −δC Cᵀ (skew part), per error state
    dC = ca.jacobian(ca.vec(C), x)
    columns = []
    for k in range(n):
        A = -dC[:, k].reshape((3, 3)) @ C.T
        S = (A - A.T) / 2
        columns.append(ca.vertcat(S[2, 1], S[0, 2], S[1, 0]))
    blocks = sc.convention_blocks(ca.horzcat(*columns), H_v, ca.jacobian(nu[0:3], x),
                                  nu[0], nu[1], nu[2], nu[3:6], a, e2)
    T = ca.vertcat(blocks[attitude], blocks[velocity], blocks[position])
    xdot = ca.SX.sym("xdot", n)
    T_dot = (ca.jacobian(ca.vec(T), x) @ xdot).reshape(T.shape)
    S = condition_matrix(model)
    c = ca.SX.sym("c", S.shape[0])
    x0 = model.casadi.function("initial_state")(c, ca.DM.zeros(len(model.inputs)), p)
    K = ca.Function("K", [c, p], [ca.jacobian(x0, c)])(ca.DM(S) @ nu, p) @ ca.DM(S)
    K_dot = (ca.jacobian(ca.vec(K), x) @ xdot).reshape(K.shape)
    return (ca.Function("transform", [x, p], [ca.densify(T)]),
            ca.Function("transform_rate", [x, xdot, p], [ca.densify(T_dot)]),
            ca.Function("tangent", [x, p], [ca.densify(K)]),
            ca.Function("tangent_rate", [x, xdot, p], [ca.densify(K_dot)]))


@cache
def _round_trip_function(model_key: str) -> ca.Function:
    """``(x, p) -> ν(x0(S ν(x)))`` (9, 1): the navigation quantities read back after the
    initial-state map is given what the outputs read."""
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.model_flight import condition_matrix

    model = load_model(model_key)
    x, p, nu, _, _ = _symbols(model)
    zeros = ca.DM.zeros(len(model.inputs))
    x0 = model.casadi.function("initial_state")(ca.DM(condition_matrix(model)) @ nu, zeros, p)
    outputs = model.casadi.function("outputs")(x0, zeros, p)
    back = ca.vertcat(*[sign * outputs[i] for i, sign in _outputs(model)])
    return ca.Function("round_trip", [x, p], [ca.densify(back)])


def _along(fn: ca.Function, *args: np.ndarray) -> list[np.ndarray]:
    """Evaluate ``fn`` at the K columns of its first argument: results (rows, cols, K)."""
    x = args[0]
    k = x.shape[-1]
    mapped = fn.map(k)
    out = mapped(*[a if a.ndim == 2 else a[:, None] for a in args])
    out = out if isinstance(out, tuple | list) else [out]
    results = []
    for j, value in enumerate(out):
        rows, cols = fn.size_out(j)
        results.append(np.moveaxis(np.asarray(value).reshape(rows, k, cols), 1, 2))
    return results


CARRIED_STEPS = 40
"""Gauss–Newton steps at most of :func:`carried_values` (a wander angle needs about five
from a value a radian away)."""

CARRIED_CHANGE = 1e-13
"""A Gauss–Newton step of :func:`carried_values` below this (relative to the parameter's
size, at least 1) is not taken: the parameter has its value."""


def _carried(model, x: np.ndarray, p: np.ndarray) -> tuple[int, ...]:
    """The carried parameters along samples ``x`` (n, K) of a flight: the flight's own
    decision (:attr:`~ins_errors.numeric.model_flight.FlightAdapter.carried`,
    :func:`~ins_errors.numeric.model_flight.carried_parameters` at the conditions of its
    start), taken at the navigation quantities of the first sample, where every motion a
    check flies begins. A model's initial-state map may start a state at a parameter at
    one point and not at another (a wander angle ``alpha0 sin φ`` is started by nothing at
    the equator), so the check and the flight decide at the same point."""
    p = np.ascontiguousarray(p, dtype=float)
    first = np.ascontiguousarray(np.asarray(x, dtype=float).reshape(x.shape[0], -1)[:, :1])
    nu = np.ascontiguousarray(_along(_navigation_function(model.key), first, p)[0][:, 0, 0])
    return _carried_at(model.key, p.tobytes(), nu.tobytes())


@lru_cache(maxsize=64)
def _carried_at(model_key: str, p: bytes, nu: bytes) -> tuple[int, ...]:
    """:func:`~ins_errors.numeric.model_flight.carried_parameters` at navigation
    quantities ``nu`` (9,) and parameters ``p`` (np,), as float64 bytes."""
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.model_flight import carried_parameters, condition_matrix

    model = load_model(model_key)
    return carried_parameters(model, condition_matrix(model) @ np.frombuffer(nu),
                              np.frombuffer(p))


@cache
def _carried_functions(model_key: str, carried: tuple[int, ...]
                       ) -> tuple[ca.Function, ca.Function, ca.Function]:
    """``fit(x, p) -> (x − x0(S ν(x), p) (n, 1), ∂x0/∂q (n, m))``,
    ``rate(x, ẋ, p) -> (q̇ (m, 1), ẋ − K ċ (n, 1), |ẋ| + |K| |ċ| (n, 1))`` and
    ``tangent_rate(x, q̇, p) -> (∂K/∂q) q̇ (n, 9)`` of the carried parameters ``q``
    (indices ``carried`` into ``p``), ``K = ∂x0/∂c S`` the tangent of the initial-state
    map and ``c = S ν(x)``."""
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.model_flight import condition_matrix

    model = load_model(model_key)
    x, p, nu, _, _ = _symbols(model)
    S = ca.DM(condition_matrix(model))
    c = ca.SX.sym("c", S.shape[0])
    x0 = model.casadi.function("initial_state")(c, ca.DM.zeros(len(model.inputs)), p)
    q = ca.vertcat(*[p[k] for k in carried])
    at = ca.Function("initial", [c, p], [x0, ca.jacobian(x0, c), ca.jacobian(x0, q)])
    x_at, K_c, D = at(S @ nu, p)
    xdot = ca.SX.sym("xdot", x.numel())
    c_rate = S @ (ca.jacobian(nu, x) @ xdot)
    off = xdot - K_c @ c_rate
    q_rate = ca.solve(D.T @ D, D.T @ off)
    terms = ca.fabs(xdot) + ca.mtimes(ca.fabs(K_c), ca.fabs(c_rate))
    q_dot = ca.SX.sym("q_dot", len(carried))
    K = K_c @ S
    K_q = (ca.jacobian(ca.vec(K), q) @ q_dot).reshape(K.shape)
    return (ca.Function("carried_fit", [x, p], [ca.densify(x - x_at), ca.densify(D)]),
            ca.Function("carried_rate", [x, xdot, p],
                        [ca.densify(v) for v in (q_rate, off, terms)]),
            ca.Function("tangent_carried_rate", [x, q_dot, p], [ca.densify(K_q)]))


def carried_values(model, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The parameters at every sample of states ``x`` (n, K), shape (np,) or (np, K).

    A parameter that starts a state no navigation quantity sets (the initial wander
    angle ``alpha0`` of a wander-azimuth INS:
    :func:`~ins_errors.numeric.model_flight.carried_parameters`) moves along a flight
    (:class:`~ins_errors.numeric.model_flight.CarriedPath`); the tangent of the
    initial-state map at a sample is taken at the value that puts the map through the
    sample's state, ``x = x0(S ν(x), p | q)``, found by Gauss–Newton
    from ``p``'s value (:data:`CARRIED_STEPS`, :data:`CARRIED_CHANGE`). ``p`` itself
    when no parameter moves (a model without such parameters, a static base).

    Raises
    ------
    InsErrorsError
        No value of the parameters puts the map through some sample's state.
    """
    p = np.ascontiguousarray(p, dtype=float)
    carried = _carried(model, x, p)
    if not carried:
        return p
    fit = _carried_functions(model.key, carried)[0]
    q = np.repeat(p[list(carried), None], x.shape[-1], axis=1)
    active = np.arange(x.shape[-1])
    for _ in range(CARRIED_STEPS):
        moved = np.repeat(p[:, None], active.size, axis=1)
        moved[list(carried)] = q[:, active]
        r, D = _along(fit, np.ascontiguousarray(x[:, active]), moved)
        D = np.moveaxis(D, -1, 0)
        step = np.linalg.solve(np.swapaxes(D, 1, 2) @ D,
                               np.swapaxes(D, 1, 2) @ np.moveaxis(r, -1, 0))[:, :, 0].T
        size = np.maximum(1.0, np.abs(q[:, active]))
        taken = np.any(~(np.abs(step) <= CARRIED_CHANGE * size), axis=0)
        q[:, active[taken]] += step[:, taken]
        active = active[taken]
        if not active.size:
            break
    else:
        names = ", ".join(model.parameters[k].name for k in carried)
        raise InsErrorsError(f"model {model.name!r}: no value of its parameter(s) {names} "
                             "puts its initial-state map through its state at sample "
                             f"{int(active[0])} of the motion")
    if np.array_equal(q, np.repeat(p[list(carried), None], x.shape[-1], axis=1)):
        return p
    out = np.repeat(p[:, None], x.shape[-1], axis=1)
    out[list(carried)] = q
    return out


def _tangent_rate(model, parts: tuple[str, str, str, str], x: np.ndarray,
                  xdot: np.ndarray, p: np.ndarray, moved: np.ndarray) -> np.ndarray:
    """``K̇`` (K, n, 9) along the ideal flow ``ẋ`` of the tangent ``K`` of the
    initial-state map at the parameters ``moved`` (:func:`carried_values`): its change
    with the navigation quantities and, where the flow moves them (its part off ``K ċ``
    beyond :data:`~ins_errors.numeric.model_flight.FLIGHT_TOLERANCE` of its terms), with
    the carried parameters."""
    from ins_errors.numeric.model_flight import FLIGHT_TOLERANCE

    K_dot = np.moveaxis(_along(_functions(*parts)[3], x, xdot, moved)[0], -1, 0)
    carried = _carried(model, x, p)
    if not carried or moved.ndim == 1:
        return K_dot
    _, rate, tangent_rate = _carried_functions(model.key, carried)
    q_rate, off, terms = (v[:, 0, :] for v in _along(rate, x, xdot, moved))
    moving = np.any(np.abs(off) > FLIGHT_TOLERANCE * terms, axis=0)
    if moving.any():
        extra = _along(tangent_rate, np.ascontiguousarray(x[:, moving]),
                       np.ascontiguousarray(q_rate[:, moving]),
                       np.ascontiguousarray(moved[:, moving]))[0]
        K_dot[moving] += np.moveaxis(extra, -1, 0)
    return K_dot


TRANSFORM, TANGENT = 0, 2
"""Indices of ``T(x, p)`` and ``K(x, p)`` among a convention's :func:`_functions`."""

_EVALUATED: dict = {}
"""The last evaluations of :func:`_evaluated` (a check validates, transforms and lifts
along the same states one after the other)."""


def _evaluated(parts: tuple[str, str, str, str], index: int, x: np.ndarray,
               p: np.ndarray) -> np.ndarray:
    """Function ``index`` of a convention's :func:`_functions` at states ``x`` (n, K),
    shape (K, rows, cols), read-only, kept for the next call at the same states."""
    x = np.ascontiguousarray(x, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    key = (parts, index, x.shape, hashlib.blake2b(x.tobytes(), digest_size=16).digest(),
           p.tobytes())
    if key not in _EVALUATED:
        if len(_EVALUATED) >= 8:
            del _EVALUATED[next(iter(_EVALUATED))]
        value = np.moveaxis(_along(_functions(*parts)[index], x, p)[0], -1, 0)
        value.setflags(write=False)
        _EVALUATED[key] = value
    return _EVALUATED[key]


def _lift(K: np.ndarray, T: np.ndarray) -> np.ndarray:
    """``L = K (T K)⁻¹`` at every sample (K (K, n, 9), T (K, 9, n)), shape (K, n, 9).

    ``T K`` mixes units (radians of latitude per metre of position error beside
    dimensionless attitude entries): its condition number is about the Earth's radius
    in metres, and a plain solve leaves about 1e-8 of rounding in ``L`` (enough to pass
    for a state off the span, :data:`INVARIANCE_TOLERANCE`, with one BLAS and not with
    another). Its columns, then its rows, are scaled to a largest entry of 1 before the
    solve, ``(T K)⁻¹ = C (R T K C)⁻¹ R``, which leaves a condition number near 1 for
    every model here and rounding of about 1e-16.
    """
    M = T @ K
    columns = 1.0 / np.abs(M).max(axis=1, keepdims=True)          # (K, 1, 9)
    rows = 1.0 / np.abs(M * columns).max(axis=2, keepdims=True)   # (K, 9, 1)
    scaled = rows * M * columns
    X = np.linalg.solve(np.swapaxes(scaled, 1, 2), np.swapaxes(K * columns, 1, 2))
    return np.swapaxes(X, 1, 2) * np.swapaxes(rows, 1, 2)


def conventions(model) -> dict:
    """The φ/ψ conventions of ``strapdown_ned`` for a model that describes itself, by
    name (see :func:`ins_errors.checker.conventions.conventions`)."""
    from ins_errors.checker.conventions import strapdown_conventions
    from ins_errors.numeric.model import load_model

    key = model.key

    def make(conv):
        parts = (key, conv.attitude, conv.velocity, conv.position)

        def transform(x, p):
            return np.moveaxis(_evaluated(parts, TRANSFORM, x, p), 0, -1)

        def rate(x, xdot, p):
            return _along(_functions(*parts)[1], x, xdot, np.asarray(p, dtype=float))[0]

        def lift(x, p):
            moved = carried_values(load_model(key), x, p)
            return np.moveaxis(_lift(_evaluated(parts, TANGENT, x, moved),
                                     _evaluated(parts, TRANSFORM, x, p)), 0, -1)

        def check(model, x, u, p):
            validate(model, parts, x, u, p)

        return transform, rate, lift, check

    return strapdown_conventions(make)
