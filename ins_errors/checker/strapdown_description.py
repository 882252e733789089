"""The navigation description and the φ/ψ conventions of any strapdown model, from its
outputs (a researcher's strapdown INS written as a model file).

A hand-coded F and G (``check MODEL --matrix``) is a function of the navigation solution,
and a textbook F is written in φ- or ψ-angle states, not in a model's own states (a
direction-cosine matrix, a quaternion, …). A model *describes itself* when it has

* the outputs ``latitude``, ``longitude``, ``height`` (or ``h``), ``v_N``, ``v_E``,
  ``v_D``, ``roll``, ``pitch``, ``heading`` (:data:`NAVIGATION_OUTPUTS`), functions of
  its state;
* the inputs ``omega_x``, ``omega_y``, ``omega_z`` (body rate, rad/s) and ``f_x``,
  ``f_y``, ``f_z`` (specific force, m/s²) (:data:`IMU_INPUTS`);
* an Earth radius parameter (``a`` or ``R``, with ``e2`` for an ellipsoid; the names of
  :mod:`ins_errors.earth_constants`) and an initial-state map from the navigation
  quantities (:mod:`ins_errors.numeric.model_flight`: its moving flights need it too).

Then:

* the navigation description (:mod:`ins_errors.checker.navigation`) is read from the
  outputs, ``C_bn`` from roll, pitch and heading (z-y-x), the Earth and transport rates
  and radii from the model's Earth, the gravity from its parameter ``g`` (else WGS-84
  normal gravity on its ellipsoid), ``f_b`` and ``omega_ib_b`` from the inputs;
* every convention of ``strapdown_ned`` (:mod:`ins_errors.models.strapdown_conventions`)
  exists for the model: with ν = the navigation outputs and ``x_ned(ν)`` the
  ``strapdown_ned`` state of the same navigation solution,

      T(x) = T_ned(x_ned(ν(x))) ∂x_ned/∂ν ∂ν/∂x,

  exact to first order, with ``Ṫ`` by exact differentiation along the ideal flow. A
  model's error state may have directions the convention does not see (the six of a
  direction-cosine matrix beyond its three angles). The derived F in the convention is
  ``(Ṫ + T F) L`` with the *lift* ``L = ∂x0/∂ν (T_ned ∂x_ned/∂ν)⁻¹`` (``x0`` the model's
  initial-state map), the error state of a convention state on the model's own state
  manifold (orthonormal matrices, unit quaternions), which the model's equations keep:
  ``T L = I`` because the outputs read back what the initial-state map sets.
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

NAVIGATION_OUTPUTS = ("latitude", "longitude", "height", "v_N", "v_E", "v_D", "roll",
                      "pitch", "heading")
"""The outputs a strapdown model describes itself with (``h`` may stand for ``height``),
in the order of the navigation quantities ν of :mod:`ins_errors.numeric.model_flight`."""

IMU_INPUTS = ("omega_x", "omega_y", "omega_z", "f_x", "f_y", "f_z")
"""Body rate (rad/s) and specific force (m/s²) inputs, body axes x, y, z."""


def _output_indices(model) -> list[int] | None:
    names = [o.name for o in model.outputs]
    out = []
    for name in NAVIGATION_OUTPUTS:
        for candidate in (name, "h") if name == "height" else (name,):
            if candidate in names:
                out.append(names.index(candidate))
                break
        else:
            return None
    return out


def missing(model) -> list[str]:
    """What ``model`` lacks to describe itself (empty when it does)."""
    from ins_errors.earth_constants import RADIUS_NAMES

    lacks = []
    outputs = {o.name for o in model.outputs}
    absent = [n for n in NAVIGATION_OUTPUTS
              if n not in outputs and not (n == "height" and "h" in outputs)]
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
    from ins_errors.numeric.strapdown_truth import euler_matrix

    k = x.shape[-1]
    outputs = np.asarray(model.casadi.function("outputs")(x, u, p), dtype=float)
    outputs = outputs.reshape(-1, k)
    lat, lon, h, vN, vE, vD, roll, pitch, heading = outputs[_output_indices(model)]
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
        "C_bn": euler_matrix(roll, pitch, heading),
        "omega_ie_n": np.array([U * np.cos(lat), zeros, -U * np.sin(lat)]),
        "omega_en_n": np.array([vE / (r_e + h), -vN / (r_n + h),
                                -vE * np.tan(lat) / (r_e + h)]),
        "gravity": (np.full(k, value[gravity]) if gravity else normal_gravity(lat, h, a, e2)),
        "R_N": r_n, "R_E": r_e, "a": np.full(k, a), "e2": np.full(k, e2),
        "earth_rate": np.full(k, U),
        "f_b": u[[index[n] for n in IMU_INPUTS[3:]]],
        "omega_ib_b": u[[index[n] for n in IMU_INPUTS[:3]]],
    }


def _ned_state(nu):
    """``strapdown_ned``'s state (10) of navigation quantities ν (9), CasADi."""
    lat, lon, h, v, roll, pitch, heading = nu[0], nu[1], nu[2], nu[3:6], nu[6], nu[7], nu[8]
    cr, sr = ca.cos(roll / 2), ca.sin(roll / 2)
    cp, sp_ = ca.cos(pitch / 2), ca.sin(pitch / 2)
    cy, sy = ca.cos(heading / 2), ca.sin(heading / 2)
    q = ca.vertcat(cr * cp * cy + sr * sp_ * sy, sr * cp * cy - cr * sp_ * sy,
                   cr * sp_ * cy + sr * cp * sy, cr * cp * sy - sr * sp_ * cy)
    return ca.vertcat(q, v, lat, lon, h)


@cache
def _functions(model_key: str, attitude: str, velocity: str, position: str
               ) -> tuple[ca.Function, ca.Function, ca.Function]:
    """``T(x, p)``, ``Ṫ(x, ẋ, p)`` and ``(K(x, p), A(x, p))`` of a convention, with the
    lift ``L = K A⁻¹``."""
    from ins_errors.models import strapdown_conventions as sc
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.model_flight import condition_matrix

    model = load_model(model_key)
    n, nu_, n_par = len(model.states), len(model.inputs), len(model.parameters)
    x, xdot, p = ca.SX.sym("x", n), ca.SX.sym("xdot", n), ca.SX.sym("p", n_par)
    radius, eccentricity, _, _ = _earth_parameters(model)
    names = [q.name for q in model.parameters]
    ae2 = ca.vertcat(p[names.index(radius)],
                     p[names.index(eccentricity)] if eccentricity else 0.0)
    nu = model.casadi.function("outputs")(x, ca.DM.zeros(nu_), p)[_output_indices(model)]
    nu_sym = ca.SX.sym("nu", 9)
    x_ned = _ned_state(nu_sym)
    x10, ae2_sym = ca.SX.sym("x_ned", 10), ca.SX.sym("ae2", 2)
    blocks = sc._blocks(x10, ae2_sym)
    T_ned = ca.Function("T_ned", [x10, ae2_sym], [ca.vertcat(
        blocks[attitude], blocks[velocity], blocks[position])])(x_ned, ae2_sym)
    A_sym = T_ned @ ca.jacobian(x_ned, nu_sym)  # (9, 9): convention per navigation error
    A = ca.Function("A", [nu_sym, ae2_sym], [A_sym])(nu, ae2)
    T = A @ ca.jacobian(nu, x)
    T_dot = (ca.jacobian(ca.vec(T), x) @ xdot).reshape(T.shape)
    S = condition_matrix(model)
    c = ca.SX.sym("c", S.shape[0])
    x0 = model.casadi.function("initial_state")(c, ca.DM.zeros(nu_), p)
    K = ca.Function("K", [c, p], [ca.jacobian(x0, c)])(ca.DM(S) @ nu, p) @ ca.DM(S)
    return (ca.Function("transform", [x, p], [T]),
            ca.Function("transform_rate", [x, xdot, p], [T_dot]),
            ca.Function("lift_parts", [x, p], [K, A]))


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
            K, A = _along(_functions(*parts)[2], x, np.asarray(p, dtype=float))
            K, A = np.moveaxis(K, -1, 0), np.moveaxis(A, -1, 0)
            return np.moveaxis(np.linalg.solve(np.swapaxes(A, 1, 2),
                                               np.swapaxes(K, 1, 2)).swapaxes(1, 2), 0, -1)

        return transform, rate, lift

    return strapdown_conventions(make)
