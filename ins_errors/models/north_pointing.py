r"""North-pointing local-level gyro-platform INS (source 001, lab report on error propagation).

The platform is slaved to the local geographic trihedron t (x east, y north, z up): its
gyros are torqued with the absolute rate of t as the computer knows it. Two horizontal
accelerometers on the platform feed the computer, which integrates the east and north
ground velocities (Coriolis and transport terms compensated) and the latitude and
longitude. Frames as in the report: t true geographic, c computer (computed position),
p platform. The vertical channel is not modelled: the vehicle flies level at a given
height ``h``.

Ideal work: the computer fed the true specific force, platform on t, no errors.
Real work: the computer fed the accelerometer outputs through the misaligned platform
(angles α_E, α_N, α_U of p relative to t), with gyro drifts, accelerometer biases and
wrong initial data.

Modelling choices (also printed at the top of ``generated/north_pointing/error_equations.md``):

* Earth: a sphere of radius ``R`` by default (``ecc2 = 0``); an ellipsoid is selected by
  setting ``R`` to its semi-major axis and ``ecc2`` to its eccentricity squared
  (:func:`ellipsoid_parameters`). Meridian and prime-vertical radii
  R_N = R(1 − e²)/√(1 − e² sin²φ)³, R_E = R/√(1 − e² sin²φ).
* Gravity ``g`` (plumb line, centrifugal part included) is a parameter and is normal to
  the local level, so it has no horizontal component; the true vertical specific force of
  level flight is f_U = g − v_E²/(R_E + h) − v_N²/(R_N + h) − 2U cos φ v_E (the vertical
  acceleration is zero: flying around the curved Earth, and eastward, makes the vehicle
  lighter, the Eötvös effect; an independent ECEF computation checks it). It reaches the
  horizontal channels only through platform tilt.
* Platform kinematics are exact (z-y-x angles of p relative to t, specific force
  resolved through the exact rotation, :mod:`ins_errors.models.platform`); the report's
  small-angle form α̇ = α × ω + (ω_cmd − ω) + drift, fᵖ = f − α × f (ω the absolute rate
  of the true trihedron t, ω_cmd the same formula evaluated by the computer) is the
  selectable ``small_angle`` platform. The vertical accelerometer is not used.
* The report (static base) drops the two Foucault cross-coupling terms ±2U sin φ δv;
  here the full equations are encoded, and the report's reduced model is the named
  simplification ``report_reduced`` of :mod:`ins_errors.symbolic.simplifications`.
"""

from __future__ import annotations

import sympy as sp

from ins_errors.modeling import (
    EARTH_RATE,
    MEAN_RADIUS,
    ErrorSource,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    ellipsoid,
    on_platform,
    platform_rates,
    radii_of_curvature,
)
from ins_errors.modeling import STANDARD_GRAVITY as EARTH_STANDARD_GRAVITY

# --------------------------------------------------------------------------------------
# Names (public API: keep stable)
# --------------------------------------------------------------------------------------
MEAN_EARTH_RADIUS = MEAN_RADIUS
"""Default sphere radius R, m (the mean radius rounded to the kilometre,
:mod:`ins_errors.models.earth`)."""

STANDARD_GRAVITY = EARTH_STANDARD_GRAVITY
"""Default gravity g, m/s² (standard gravity, also the g of '1e-4 g')."""

STATES = (
    Variable("V_E", "m/s", "east ground velocity", "V_E"),
    Variable("V_N", "m/s", "north ground velocity", "V_N"),
    Variable("phi", "rad", "latitude φ", r"\varphi"),
    Variable("lam", "rad", "longitude λ", r"\lambda"),
)
PLATFORM_ANGLES = (
    Variable("alpha_E", "rad", "platform error angle about east (level)", r"\alpha_E"),
    Variable("alpha_N", "rad", "platform error angle about north (level)", r"\alpha_N"),
    Variable("alpha_U", "rad", "platform error angle about up (azimuth)", r"\alpha_U"),
)
ERROR_STATES = (
    Variable("delta_v_E", "m/s", "east velocity error", r"\delta v_E"),
    Variable("delta_v_N", "m/s", "north velocity error", r"\delta v_N"),
    Variable("delta_latitude", "rad", "latitude error", r"\delta\varphi"),
    Variable("delta_longitude", "rad", "longitude error", r"\delta\lambda"),
    *PLATFORM_ANGLES,
)
INPUTS = (
    Variable("a_E", "m/s**2", "true specific force along east (0 at rest)", "a_E"),
    Variable("a_N", "m/s**2", "true specific force along north (0 at rest)", "a_N"),
    Variable("h", "m", "height above the Earth model (given from outside)", "h"),
)
PARAMETERS = (
    Parameter("R", "m", "Earth radius (sphere) or semi-major axis (ellipsoid)", "R",
              MEAN_EARTH_RADIUS),
    Parameter("ecc2", "1", "first eccentricity squared (0: sphere)", "e^{2}", 0.0),
    Parameter("U", "rad/s", "Earth rotation rate", r"\Omega", EARTH_RATE),
    Parameter("g", "m/s**2", "gravity (plumb line), normal to the local level", "g",
              STANDARD_GRAVITY),
)
OUTPUTS = (
    Variable("latitude", "rad", "latitude φ", r"\varphi"),
    Variable("longitude", "rad", "longitude λ", r"\lambda"),
    Variable("v_N", "m/s", "north ground velocity", "v_N"),
    Variable("v_E", "m/s", "east ground velocity", "v_E"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude φ0", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude λ0", r"\lambda_0"),
    Variable("v_N", "m/s", "initial north ground velocity", r"v_{N0}"),
    Variable("v_E", "m/s", "initial east ground velocity", r"v_{E0}"),
)


def _src(name, unit, display, kind, latex, text) -> ErrorSource:
    return ErrorSource(name, unit, text, latex, kind=kind, display_unit=display)


SOURCES = (
    _src("gyro_drift_east", "rad/s", "deg/h", "constant", r"\varepsilon_E",
         "constant drift rate of the east gyro (report: Ex)"),
    _src("gyro_drift_north", "rad/s", "deg/h", "constant", r"\varepsilon_N",
         "constant drift rate of the north gyro (report: Ey)"),
    _src("gyro_drift_up", "rad/s", "deg/h", "constant", r"\varepsilon_U",
         "constant drift rate of the azimuth gyro (report: Ez)"),
    _src("accel_bias_east", "m/s**2", "ug", "constant", r"\nabla_E",
         "constant bias of the east accelerometer (report: Dx)"),
    _src("accel_bias_north", "m/s**2", "ug", "constant", r"\nabla_N",
         "constant bias of the north accelerometer (report: Dy)"),
    _src("initial_velocity_error_east", "m/s", "m/s", "initial", r"\delta v_{E0}",
         "error of the initial east velocity set into the computer (report: Dx0)"),
    _src("initial_velocity_error_north", "m/s", "m/s", "initial", r"\delta v_{N0}",
         "error of the initial north velocity set into the computer (report: Dy0)"),
    _src("initial_latitude_error", "rad", "arcmin", "initial", r"\delta\varphi_0",
         "error of the initial latitude set into the computer (report: L0)"),
    _src("initial_longitude_error", "rad", "arcmin", "initial", r"\delta\lambda_0",
         "error of the initial longitude set into the computer (report: N0)"),
    _src("initial_tilt_east", "rad", "arcsec", "initial", r"\alpha_{E0}",
         "initial platform levelling error about east (report: Qx0)"),
    _src("initial_tilt_north", "rad", "arcsec", "initial", r"\alpha_{N0}",
         "initial platform levelling error about north (report: Qy0)"),
    _src("initial_azimuth_error", "rad", "arcmin", "initial", r"\alpha_{U0}",
         "initial platform azimuth alignment error (report: Qz0)"),
)

_sym = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES, *PLATFORM_ANGLES)}
R, ecc2, U, g = _sym["R"], _sym["ecc2"], _sym["U"], _sym["g"]


def ellipsoid_parameters(name: str) -> dict[str, float]:
    """Parameter overrides selecting a reference ellipsoid instead of the sphere.

    Parameters
    ----------
    name : str
        ``"krasovsky"`` or ``"wgs84"``.

    Returns
    -------
    dict
        ``{"R": semi-major axis in m, "ecc2": eccentricity squared}``, for
        ``Model.parameter_vector(**ellipsoid_parameters(name))``.
    """
    shape = ellipsoid(name)
    return {"R": shape.semi_major_axis, "ecc2": shape.eccentricity_squared}


# --------------------------------------------------------------------------------------
# The computer (mechanisation algorithm)
# --------------------------------------------------------------------------------------
def trihedron_rates(eq: Mechanisation, s: list[sp.Symbol], h: sp.Symbol):
    """Radii of curvature and absolute rate of the geographic trihedron at state ``s``.

    Returns
    -------
    radii : tuple of 2 sympy.Symbol
        (R_E + h, R_N + h), m.
    omega : tuple of 3 sympy.Symbol
        (ω_E, ω_N, ω_U), rad/s: the rate the platform must turn at to stay level and
        north-pointing (commanded rate when ``s`` is the computed state).
    """
    v_E, v_N, lat, _lon = s
    R_N, R_E = radii_of_curvature(lat, R, ecc2, xp=sp)
    r_E = eq.let("r_E", R_E + h, "{(R_E + h)}")
    r_N = eq.let("r_N", R_N + h, "{(R_N + h)}")
    omega_E = eq.let("omega_E", -v_N / r_N, r"\omega_E")
    omega_N = eq.let("omega_N", U * sp.cos(lat) + v_E / r_E, r"\omega_N")
    omega_U = eq.let("omega_U", U * sp.sin(lat) + v_E * sp.tan(lat) / r_E, r"\omega_U")
    return (r_E, r_N), (omega_E, omega_N, omega_U)


def computer(eq: Mechanisation, s: list[sp.Symbol], f_E: sp.Expr, f_N: sp.Expr,
             h: sp.Symbol):
    """The on-board algorithm: derivatives of (v_E, v_N, φ, λ) and the commanded rates.

    Parameters
    ----------
    eq : Mechanisation
        Where the intermediate quantities are recorded.
    s : list of sympy.Symbol
        The computer's state (true in ideal work, computed in real work).
    f_E, f_N : sympy.Expr
        Specific force fed to the velocity integrators, m/s².
    h : sympy.Symbol
        Height, m (given).

    Returns
    -------
    rhs : list of sympy.Expr
        The four state derivatives.
    omega : tuple of sympy.Symbol
        Absolute rate of the trihedron (ω_E, ω_N, ω_U), rad/s.
    """
    v_E, v_N, lat, _lon = s
    (r_E, r_N), omega = trihedron_rates(eq, s, h)
    # Coriolis + transport: (2U + ω_en) × v, horizontal part, level flight (v_U = 0)
    turn = eq.let("turn_rate", 2 * U * sp.sin(lat) + v_E * sp.tan(lat) / r_E,
                  r"{(2\Omega + \omega_{en})_U}")
    dv_E = f_E + turn * v_N
    dv_N = f_N - turn * v_E
    dlat = v_N / r_N
    dlon = v_E / (r_E * sp.cos(lat))
    return [dv_E, dv_N, dlat, dlon], omega


def navigation_outputs(eq: Mechanisation, s: list[sp.Symbol], inputs: list[sp.Symbol]):
    """Latitude, longitude, north and east velocity of a state (read off directly)."""
    v_E, v_N, lat, lon = s
    return sp.Matrix([lat, lon, v_N, v_E])


def vertical_specific_force(s: list[sp.Expr], h: sp.Expr) -> sp.Expr:
    """True vertical specific force of level flight at height ``h``, m/s²."""
    v_E, v_N, lat, _lon = s
    R_N, R_E = radii_of_curvature(lat, R, ecc2, xp=sp)
    r_E, r_N = R_E + h, R_N + h
    return g - v_E**2 / r_E - v_N**2 / r_N - 2 * U * sp.cos(lat) * v_E


# --------------------------------------------------------------------------------------
# Assembly: ideal work, real work
# --------------------------------------------------------------------------------------
def build(platform: str = "exact") -> ModelDefinition:
    """Assemble the symbolic definition of the north-pointing INS.

    ``platform``: ``"exact"`` or the report's ``"small_angle"`` platform kinematics
    (:mod:`ins_errors.models.platform`).
    """
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    alpha = [v.symbol for v in PLATFORM_ANGLES]
    a_E, a_N, h = (v.symbol for v in INPUTS)
    w = _sym

    ideal = Mechanisation()
    ideal_rhs, omega = computer(ideal, x, a_E, a_N, h)

    # Instruments: accelerometers on the misaligned platform.
    f_U = ideal.let("f_U", vertical_specific_force(x, h), "f_U")
    f_E, f_N, _ = on_platform(alpha, (a_E, a_N, f_U), platform)
    f_E, f_N = f_E + w["accel_bias_east"], f_N + w["accel_bias_north"]
    real = Mechanisation(computed=True)
    computed_rhs, omega_cmd = computer(real, x_c, f_E, f_N, h)
    # Platform: torqued with the commanded rates, plus drift, relative to t turning at ω.
    drift = (w["gyro_drift_east"], w["gyro_drift_north"], w["gyro_drift_up"])
    torque = [wc + d for wc, d in zip(omega_cmd, drift, strict=True)]
    platform_rhs = platform_rates(alpha, torque, omega, platform)

    c = {v.name: v.symbol for v in INITIAL_CONDITIONS}
    lat0, lon0, vN0, vE0 = c["latitude"], c["longitude"], c["v_N"], c["v_E"]
    initial_state = sp.Matrix([vE0, vN0, lat0, lon0])
    initial_real_state = sp.Matrix([
        vE0 + w["initial_velocity_error_east"],
        vN0 + w["initial_velocity_error_north"],
        lat0 + w["initial_latitude_error"],
        lon0 + w["initial_longitude_error"],
        w["initial_tilt_east"], w["initial_tilt_north"], w["initial_azimuth_error"],
    ])
    lat = x[2]
    pole = "latitude at or beyond ±90°: the formulas divide by cos φ (tan φ, sec φ)"
    common = (
        (R, "Earth radius R must be positive"),
        (g, "gravity g must be positive"),
        (1 - ecc2, "eccentricity squared ecc2 must be below 1"),
        (ecc2 + 1e-300, "eccentricity squared ecc2 must not be negative"),
    )
    return ModelDefinition(
        name="north_pointing",
        title="North-pointing local-level gyro-platform INS",
        source="001: lab report 'Error-propagation characteristics of an INS' "
               "(north-pointing platform, static base)",
        states=STATES,
        error_states=ERROR_STATES,
        real_states=[*x_c, *alpha],
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal,
        real=real,
        ideal_rhs=sp.Matrix(ideal_rhs),
        real_rhs=sp.Matrix([*computed_rhs, *platform_rhs]),
        small_angle_rhs=build("small_angle").real_rhs if platform == "exact" else None,
        output_map=navigation_outputs,
        initial_state=initial_state,
        initial_real_state=initial_real_state,
        groups=(
            ("Velocity errors", ["delta_v_E", "delta_v_N"]),
            ("Position errors", ["delta_latitude", "delta_longitude"]),
            ("Platform error angles", ["alpha_E", "alpha_N", "alpha_U"]),
        ),
        domain=(
            (sp.cos(lat) ** 2 - 1e-12, pole),   # 1e-6 rad (0.206″), as the other models
            *common,
            (R + h, "R + h must be positive: height below the Earth's centre"),
        ),
        initial_domain=(
            (sp.cos(lat0) ** 2 - 1e-12, "initial " + pole),
            *common,
            (R + h, "R + h must be positive: height below the Earth's centre"),
        ),
        notes=__doc__.split("Modelling choices", 1)[1].split(":", 1)[1].strip(),
    )
