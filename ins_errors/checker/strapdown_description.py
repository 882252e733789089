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
  the tangent of the model's initial-state map at the current navigation solution: the
  error state of a convention state on the model's own state manifold (orthonormal
  matrices, unit quaternions), which its equations keep. (``(T K)⁻¹`` also absorbs the
  sign of a quaternion that the initial-state map gives as −q once the heading has
  wrapped.)
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

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
    if not any(p.name in RADIUS_NAMES and p.unit == "m" for p in model.parameters):
        lacks.append(f"an Earth radius parameter ({' or '.join(RADIUS_NAMES)}, m)")
    if len(model.error_states) != len(model.states):
        lacks.append("one error state per state (no extra real-work states)")
    return lacks


def describes(model) -> bool:
    """True when ``model`` is a strapdown model with the outputs, inputs and Earth of
    the module's description (:func:`missing` is empty)."""
    return not missing(model)


def _earth_parameters(model) -> tuple[str, str | None, str | None, str | None]:
    """Names of the radius, eccentricity, Earth-rate and gravity parameters (or None)."""
    from ins_errors.earth_constants import (
        EARTH_RATE_NAMES,
        ECCENTRICITY_NAMES,
        GRAVITY_NAMES,
        RADIUS_NAMES,
    )

    units = {p.name: p.unit for p in model.parameters}

    def first(names, unit):
        return next((n for n in names if units.get(n) == unit), None)

    return (first(RADIUS_NAMES, "m"), first(ECCENTRICITY_NAMES, "1"),
            first(EARTH_RATE_NAMES, "rad/s"), first(GRAVITY_NAMES, "m/s**2"))


def navigation(model, x: np.ndarray, u: np.ndarray, p: np.ndarray) -> dict[str, np.ndarray]:
    """The navigation description (:data:`~ins_errors.checker.navigation.FIELDS`) of a
    strapdown model along states ``x`` (n, K) and inputs ``u`` (nu, K)."""
    from ins_errors.models.earth import EARTH_RATE, normal_gravity, radii_of_curvature

    k = x.shape[-1]
    nav, C = _along(_navigation_function(model.key), x, np.asarray(p, dtype=float))
    lat, lon, h, vN, vE, vD = nav[:6, 0]
    value = dict(zip((q.name for q in model.parameters), np.asarray(p, dtype=float),
                     strict=True))
    radius, eccentricity, rate, gravity = _earth_parameters(model)
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
        "gravity": (np.full(k, value[gravity]) if gravity else normal_gravity(lat, h, a, e2)),
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
    radius, eccentricity, _, _ = _earth_parameters(model)
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
                                  nu[0], nu[2], nu[3:6], a, e2)
    T = ca.vertcat(blocks[attitude], blocks[velocity], blocks[position])
    xdot = ca.SX.sym("xdot", n)
    T_dot = (ca.jacobian(ca.vec(T), x) @ xdot).reshape(T.shape)
    S = condition_matrix(model)
    c = ca.SX.sym("c", S.shape[0])
    x0 = model.casadi.function("initial_state")(c, ca.DM.zeros(len(model.inputs)), p)
    K = ca.Function("K", [c, p], [ca.jacobian(x0, c)])(ca.DM(S) @ nu, p) @ ca.DM(S)
    return (ca.Function("transform", [x, p], [ca.densify(T)]),
            ca.Function("transform_rate", [x, xdot, p], [ca.densify(T_dot)]),
            ca.Function("tangent", [x, p], [ca.densify(K)]))


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


def conventions(model) -> dict:
    """The φ/ψ conventions of ``strapdown_ned`` for a model that describes itself, by
    name (see :func:`ins_errors.checker.conventions.conventions`)."""
    from ins_errors.checker.conventions import strapdown_conventions

    key = model.key

    def make(conv):
        parts = (key, conv.attitude, conv.velocity, conv.position)

        def transform(x, p):
            return _along(_functions(*parts)[0], x, np.asarray(p, dtype=float))[0]

        def rate(x, xdot, p):
            return _along(_functions(*parts)[1], x, xdot, np.asarray(p, dtype=float))[0]

        def lift(x, p):
            p = np.asarray(p, dtype=float)
            K = np.moveaxis(_along(_functions(*parts)[2], x, p)[0], -1, 0)  # (K, n, 9)
            T = np.moveaxis(transform(x, p), -1, 0)                       # (K, 9, n)
            # L = K (T K)⁻¹, as solve((T K)ᵀ, Kᵀ)ᵀ
            L = np.linalg.solve(np.swapaxes(T @ K, 1, 2), np.swapaxes(K, 1, 2))
            return np.moveaxis(np.swapaxes(L, 1, 2), 0, -1)

        return transform, rate, lift

    return strapdown_conventions(make)
