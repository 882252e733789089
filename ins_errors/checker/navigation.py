"""The navigation state and IMU outputs a researcher's hand-coded F and G are evaluated at.

A researcher's linear error model is a function of the *navigation solution*, not of a
model's internal states: latitude, velocity, attitude, specific force. This module turns
the ideal states and inputs of a model along a motion into that model-independent
description, one :class:`Navigation` and one :class:`Imu` per sample time, and back into
arrays for writing them out (for users of other languages, see ``docs/matrix_check.md``).

Frames: NED (x north, y east, z down) navigation frame n; body frame b. For a platform
INS the body frame is the stabilised platform itself, so ``C_bn`` is the identity for a
north-pointing platform. Units: SI and radians.

Each model says how its states and inputs give these quantities through a *navigation
adapter* (:data:`ADAPTERS`): a function ``(model, x, u, p) -> dict of arrays`` with the
keys of :data:`FIELDS`, trailing axis K (the samples).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cache
from types import MappingProxyType

import numpy as np

from ins_errors.errors import InsErrorsError

FIELDS: dict[str, str] = {
    "latitude": "geodetic latitude φ, rad",
    "longitude": "longitude λ, rad",
    "height": "height above the ellipsoid h, m",
    "v_ned": "ground velocity (v_N, v_E, v_D), m/s, shape (3,)",
    "C_bn": "direction-cosine matrix body → NED, shape (3, 3)",
    "omega_ie_n": "Earth rate in NED (U cos φ, 0, −U sin φ), rad/s, shape (3,)",
    "omega_en_n": "transport rate in NED (v_E/(R_E+h), −v_N/(R_N+h), −v_E tan φ/(R_E+h)), "
                  "rad/s, shape (3,)",
    "gravity": "magnitude of gravity (plumb line) at the point, m/s²",
    "R_N": "meridian radius of curvature at φ (height not included), m",
    "R_E": "prime-vertical radius of curvature at φ (height not included), m",
    "a": "semi-major axis (sphere radius for a spherical Earth), m",
    "e2": "first eccentricity squared (0 for a sphere)",
    "earth_rate": "Earth rotation rate U, rad/s",
    "f_b": "specific force in the body frame (accelerometer triad output), m/s², shape (3,)",
    "omega_ib_b": "body angular rate relative to inertial space (gyro triad output), rad/s, "
                  "shape (3,)",
}
"""Every quantity of the navigation description, with its meaning and unit."""

IMU_FIELDS = ("f_b", "omega_ib_b")
"""Fields that are IMU outputs (the rest describe the navigation state)."""

VECTOR_FIELDS = {"v_ned": (3,), "C_bn": (3, 3), "omega_ie_n": (3,), "omega_en_n": (3,),
                 "f_b": (3,), "omega_ib_b": (3,)}
"""Shapes of the fields that are not scalars."""


@dataclass(frozen=True)
class Navigation:
    """The ideal navigation state at one sample (see :data:`FIELDS` for every attribute).

    Attributes
    ----------
    t : float
        Time since the start of the motion, s.
    motion : str
        Label of the motion (``"static"``, ``"cruise"``, ``"manoeuvre"``).
    latitude, longitude, height : float
        rad, rad, m.
    v_ned : numpy.ndarray, shape (3,)
        m/s.
    C_bn : numpy.ndarray, shape (3, 3)
        Body → NED.
    omega_ie_n, omega_en_n : numpy.ndarray, shape (3,)
        rad/s.
    gravity, R_N, R_E, a, e2, earth_rate : float
        m/s², m, m, m, 1, rad/s.
    parameters : Mapping of str to float
        The model's parameters by name, SI, read-only: the values the motion is flown
        with (the defaults, or those set with ``-p``), e.g. ``nav.parameters["k_h1"]``
        for a damping gain.
    """

    t: float
    motion: str
    latitude: float
    longitude: float
    height: float
    v_ned: np.ndarray
    C_bn: np.ndarray
    omega_ie_n: np.ndarray
    omega_en_n: np.ndarray
    gravity: float
    R_N: float
    R_E: float
    a: float
    e2: float
    earth_rate: float
    parameters: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def omega_in_n(self) -> np.ndarray:
        """Rate of the navigation frame, ω_ie + ω_en, in NED, rad/s."""
        return self.omega_ie_n + self.omega_en_n


@dataclass(frozen=True)
class Imu:
    """Ideal IMU outputs at one sample.

    Attributes
    ----------
    f_b : numpy.ndarray, shape (3,)
        Specific force in the body frame, m/s².
    omega_ib_b : numpy.ndarray, shape (3,)
        Body rate relative to inertial space, in the body frame, rad/s.
    f_n : numpy.ndarray, shape (3,)
        The same specific force in NED (``C_bn @ f_b``), m/s², for convenience.
    """

    f_b: np.ndarray
    omega_ib_b: np.ndarray
    f_n: np.ndarray


PARAMETERS = "parameters"
"""Key of the navigation arrays holding the model's parameters (name -> SI value), beside
the :data:`FIELDS` (:func:`navigation_arrays`)."""


def samples(arrays: dict[str, np.ndarray], times: np.ndarray, motion: str
            ) -> list[tuple[Navigation, Imu]]:
    """Split navigation arrays (trailing axis K) into K (Navigation, Imu) pairs (the
    model's parameters, :data:`PARAMETERS`, on every ``Navigation``)."""
    out = []
    parameters = MappingProxyType(dict(arrays.get(PARAMETERS, {})))
    for k, t in enumerate(times):
        value = {name: (np.array(arrays[name][..., k]) if name in VECTOR_FIELDS
                        else float(arrays[name][k])) for name in FIELDS}
        f_b, w_b = value.pop("f_b"), value.pop("omega_ib_b")
        nav = Navigation(t=float(t), motion=motion, parameters=parameters, **value)
        out.append((nav, Imu(f_b, w_b, nav.C_bn @ f_b)))
    return out


# --------------------------------------------------------------------------------------
# Adapters: model states and inputs -> navigation arrays
# --------------------------------------------------------------------------------------
@cache
def _intermediates(model_key: str) -> tuple[list[str], Callable]:
    """Names and a numpy function (x, u, p) -> values of a model's ideal intermediates."""
    import sympy as sp

    from ins_errors.numeric.model import load_model
    from ins_errors.symbolic.variation import ideal_intermediate_values

    d = load_model(model_key).symbolic
    closed = ideal_intermediate_values(d)
    names = [s.name for s in closed]
    fn = sp.lambdify([d.x, d.u, d.p], list(closed.values()), "numpy", docstring_limit=0)
    return names, fn


def intermediate_values(model_key: str, x: np.ndarray, u: np.ndarray, p: np.ndarray
                        ) -> dict[str, np.ndarray]:
    """Ideal intermediate quantities of a model (by :attr:`~ins_errors.Model.key`) at
    states ``x`` (n, K)."""
    names, fn = _intermediates(model_key)
    k = x.shape[-1]
    values = fn(list(x), list(u), list(p[:, None] * np.ones(k)))
    return {n: np.broadcast_to(np.asarray(v, dtype=float), (k,)) for n, v in
            zip(names, values, strict=True)}


def _north_pointing(model, x, u, p) -> dict[str, np.ndarray]:
    """North-pointing platform: the body frame is the level, north-pointing platform."""
    k = x.shape[-1]
    par = dict(zip((i.name for i in model.parameters), p, strict=True))
    v_e, v_n, lat, lon = x
    h = u[2]
    mid = intermediate_values(model.key, x, u, p)
    missing = {"omega_E", "omega_N", "omega_U", "r_N", "r_E", "f_U"} - set(mid)
    if missing:
        raise InsErrorsError(f"model {model.name!r} has the states of north_pointing but not "
                             f"its ideal intermediates {', '.join(sorted(missing))}: the "
                             "navigation description of the matrix check reads them")
    w_e, w_n, w_u = mid["omega_E"], mid["omega_N"], mid["omega_U"]
    U = par["U"]
    zeros = np.zeros(k)
    ie = np.array([U * np.cos(lat), zeros, -U * np.sin(lat)])
    in_n = np.array([w_n, w_e, -w_u])  # ENU (E, N, U) -> NED (N, E, D)
    return {
        "latitude": lat, "longitude": lon, "height": h,
        "v_ned": np.array([v_n, v_e, zeros]),
        "C_bn": np.repeat(np.eye(3)[:, :, None], k, axis=2),
        "omega_ie_n": ie, "omega_en_n": in_n - ie,
        "gravity": np.full(k, par["g"]),
        "R_N": mid["r_N"] - h, "R_E": mid["r_E"] - h,
        "a": np.full(k, par["R"]), "e2": np.full(k, par["ecc2"]),
        "earth_rate": np.full(k, U),
        "f_b": np.array([u[1], u[0], -mid["f_U"]]),
        "omega_ib_b": in_n,
    }


def _strapdown_ned(model, x, u, p) -> dict[str, np.ndarray]:
    """Strapdown NED: attitude quaternion body → NED (scalar first), IMU outputs as inputs."""
    from ins_errors.models.earth import normal_gravity, radii_of_curvature

    par = dict(zip((i.name for i in model.parameters), p, strict=True))
    q0, q1, q2, q3 = x[0:4]
    C = np.array([
        [q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
        [2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)],
        [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2]])
    v, lat, lon, h = x[4:7], x[7], x[8], x[9]
    a, e2, U = par["a"], par["e2"], par["U"]
    r_n, r_e = radii_of_curvature(lat, a, e2)
    k = lat.shape[-1]
    ie = np.array([U * np.cos(lat), np.zeros(k), -U * np.sin(lat)])
    en = np.array([v[1] / (r_e + h), -v[0] / (r_n + h), -v[1] * np.tan(lat) / (r_e + h)])
    return {
        "latitude": lat, "longitude": lon, "height": h, "v_ned": v, "C_bn": C,
        "omega_ie_n": ie, "omega_en_n": en,
        "gravity": normal_gravity(lat, h, a, e2, par["gamma_e"], par["gravity_k"],
                                  par["gravity_m"]),
        "R_N": r_n, "R_E": r_e, "a": np.full(k, a), "e2": np.full(k, e2),
        "earth_rate": np.full(k, U), "f_b": u[3:6], "omega_ib_b": u[0:3],
    }


def _strapdown_outputs(model, x, u, p) -> dict[str, np.ndarray]:
    """Any strapdown model, from its navigation outputs and IMU inputs
    (:mod:`ins_errors.checker.strapdown_description`)."""
    from ins_errors.checker import strapdown_description

    return strapdown_description.navigation(model, x, u, p)


STRAPDOWN_OUTPUTS = "strapdown outputs"
"""The adapter of a strapdown model file that describes itself by its outputs."""

ADAPTERS: dict[str, Callable] = {"north_pointing": _north_pointing,
                                 "strapdown_ned": _strapdown_ned,
                                 STRAPDOWN_OUTPUTS: _strapdown_outputs}
"""Navigation adapter of each model that supports hand-coded matrices (by model name),
and of the strapdown models that describe themselves (:data:`STRAPDOWN_OUTPUTS`)."""


SHAPED_LIKE = ("north_pointing",)
"""Built-in models whose navigation adapter also serves a model file (or entry point)
with the same states, inputs and parameters, by name and unit (a modified copy)."""


def _names_units(model) -> tuple:
    return tuple(tuple((i.name, i.unit) for i in group)
                 for group in (model.states, model.inputs, model.parameters))


def adapter_name(model) -> str | None:
    """The built-in model whose navigation adapter describes ``model``, or None.

    A built-in model has its own (:data:`ADAPTERS`); a model file has the adapter of a
    model in :data:`SHAPED_LIKE` whose states, inputs and parameters it shares.
    """
    if model.name in ADAPTERS:
        return model.name
    from ins_errors.checker import strapdown_description
    from ins_errors.numeric.model import load_model

    for name in SHAPED_LIKE:
        if _names_units(model) == _names_units(load_model(name)):
            return name
    if strapdown_description.describes(model):
        return STRAPDOWN_OUTPUTS
    return None


def require_description(model) -> None:
    """Raise one line if ``model`` has no navigation adapter (it cannot be matrix-checked).

    Raises
    ------
    InsErrorsError
        Saying what the model lacks, which models have it and where the docs say so.
    """
    if adapter_name(model) is not None:
        return
    if len(model.error_states) > len(model.states):
        # a platform model (real-work states beyond its own): the strapdown description's
        # outputs and IMU inputs are beside the point
        raise InsErrorsError(
            f"model {model.name!r} cannot be checked with --matrix or --write-samples: a "
            "platform model has the navigation description a hand-coded F and G is "
            "evaluated on only as north_pointing (or a model file with its states, inputs "
            "and parameters); check its F and G rows as an equation file instead, one line "
            "dot(STATE) = ... per row in its own error states (ins-errors check MODEL "
            "FILE.txt; docs/matrix_check.md, 'Which models')")
    from ins_errors.checker import strapdown_description

    built_in = sorted(name for name in ADAPTERS if name != STRAPDOWN_OUTPUTS)
    raise InsErrorsError(
        f"model {model.name!r} cannot be checked with --matrix or --write-samples: a "
        "hand-coded F and G is evaluated on a navigation description (latitude, NED "
        "velocity, attitude, Earth and transport rates, IMU outputs) made from the "
        f"model's states, which the built-in models {' and '.join(built_in)} have, a "
        f"model file with the states, inputs and parameters of {' or '.join(SHAPED_LIKE)}, "
        "and a strapdown model file with navigation outputs, IMU inputs and an Earth radius "
        f"(this model lacks {'; '.join(strapdown_description.missing(model))}; see "
        "docs/matrix_check.md, 'Which models'); check a hand linearisation of this model "
        "as an equation file instead (ins-errors check MODEL FILE.tex)")


def navigation_arrays(model, x: np.ndarray, u: np.ndarray, p: np.ndarray
                      ) -> dict[str, np.ndarray]:
    """The navigation description (:data:`FIELDS`) along states ``x`` (n, K), inputs
    ``u``, with the model's parameters ``p`` by name under :data:`PARAMETERS`.

    Raises
    ------
    InsErrorsError
        If the model has no navigation adapter.
    """
    require_description(model)
    adapter = ADAPTERS[adapter_name(model)]
    p = np.asarray(p, dtype=float)
    arrays = adapter(model, np.asarray(x, dtype=float), np.asarray(u, dtype=float), p)
    values = p if p.ndim == 1 else p[:, 0]  # (constant along the samples)
    arrays[PARAMETERS] = {info.name: float(value) for info, value in
                          zip(model.parameters, values, strict=True)}
    return arrays
