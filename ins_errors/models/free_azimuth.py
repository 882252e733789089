r"""Free-azimuth platform INS of the IS-1-72A (source 002), formulas rebuilt.

Every displayed formula of source 002 was lost; the prose survives and describes the
design. The equations below are rebuilt from that design (the derivation, step by step,
is in ``docs/free_azimuth_derivation.md``; the rebuilt ideal equations are checked by
simulation in ``tests/test_free_azimuth.py``: a perfect system on a great-circle flight
reproduces the true coordinates).

Design, as the source describes it:

* the gyro-stabilised platform is *free in azimuth*: the external computer sends no
  azimuth command, and the constant azimuth drift is not compensated. Its horizontal
  axes x, y therefore follow a *reference trihedron* ξ'η'ζ' whose vertical ζ' is the
  geocentric vertical and whose absolute rate about ζ' is zero;
* the horizontal channels are closed through the constant tuning radius
  R = 6 411 000 m: the integrators hold the absolute horizontal velocity components
  V_x, V_y along ξ', η' and the electronics torque the platform with
  ω_x = −V_y/R, ω_y = V_x/R (the rates "coming from the integrators");
* the Earth is a sphere; coordinates are reckoned in an orthodromic system: orthodromic
  latitude Φ, longitude Λ, and the angle A between the orthodromic meridian and the
  reference trihedron, integrated by (8.35).

The orthodromic system is fixed to the Earth by its origin (geographic latitude φ_o,
longitude λ_o, where Φ = Λ = 0) and the azimuth N_o of the orthodrome there (the
orthodromic equator Φ = 0 is the great circle through the origin at azimuth N_o). The
Earth axis then has the constant orthodromic components
k = (sin φ_o, cos φ_o cos N_o, cos φ_o sin N_o) (toward the origin, along the orthodrome,
toward the orthodromic pole).

Modelling choices (also printed at the top of ``generated/free_azimuth/error_equations.md``):

* the navigation sphere is the sphere of the tuning radius R: the ideal work is flight
  over that sphere, so that a perfect system reproduces the true coordinates exactly.
  The height is not modelled; the vertical velocity V_h enters only the transport
  terms of the velocity integrators (the source: "as V_z we use V_h; the vertical
  acceleration is neglected").
* gravitation is radial (spherical Earth): it has no horizontal component along the
  geocentric reference, so the velocity equations are V̇_x = f_x − ω_y V_h,
  V̇_y = f_y + ω_x V_h (absolute velocity, reference with zero azimuth rate: no separate
  Coriolis term).
* the computer's own estimate of the platform deviation (the lost (8.34)) is not
  modelled: the platform deviation α from the reference trihedron is the error state.
  The constant horizontal drift is compensated by the electronics: the sources
  ``gyro_drift_x``/``gyro_drift_y`` are the residual after compensation;
  ``gyro_drift_z`` is the full (uncompensated) azimuth drift.
* the gravity levelling offsets α0 = 2α_g, β0 = 2β_g of the source are provided by
  :func:`levelling_offsets` as values of the initial-tilt sources (first order in the
  flattening: the gravity vertical deviates from the geocentric one by f sin 2φ toward
  the pole; α_g, β_g are its half-angle projections on the platform axes).
* the outputs are the geographic (= geocentric on the sphere) latitude and longitude,
  the true azimuth of the reference axis ξ' (true heading = gyro heading + this), and
  the north/east relative velocities.
"""

from __future__ import annotations

import math

import sympy as sp

from ins_errors.modeling import (
    EARTH_RATE,
    ELLIPSOIDS,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    error_source,
    error_states_of,
    on_platform,
)
from ins_errors.modeling import platform_rates as kinematic_rates

# --------------------------------------------------------------------------------------
# Names (public API: keep stable)
# --------------------------------------------------------------------------------------
TUNING_RADIUS = 6_411_000.0
"""Platform tuning radius R of the IS-1-72A, m (source 002)."""

STATES = (
    Variable("Phi", "rad", "orthodromic latitude Φ", r"\Phi"),
    Variable("Lam", "rad", "orthodromic longitude Λ", r"\Lambda"),
    Variable("A", "rad", "angle A from the orthodromic trihedron ξη to the reference ξ'η'",
             "A"),
    Variable("V_x", "m/s", "absolute horizontal velocity along the reference axis ξ'", "V_x"),
    Variable("V_y", "m/s", "absolute horizontal velocity along the reference axis η'", "V_y"),
)
PLATFORM_ANGLES = (
    Variable("alpha_x", "rad", "platform deviation about x (≈ξ') from the reference", r"\alpha"),
    Variable("alpha_y", "rad", "platform deviation about y (≈η') from the reference", r"\beta"),
    Variable("alpha_z", "rad", "platform deviation in azimuth from the reference", r"\delta"),
)
ERROR_STATES = error_states_of(STATES, PLATFORM_ANGLES)
INPUTS = (
    Variable("a_x", "m/s**2", "true apparent acceleration along the reference axis ξ'", "a_x"),
    Variable("a_y", "m/s**2", "true apparent acceleration along the reference axis η'", "a_y"),
    Variable("a_zeta", "m/s**2", "true apparent acceleration along the vertical (≈ +g at rest)",
             r"a_\zeta"),
    Variable("V_zeta", "m/s", "vertical velocity V_h (given from outside)", "V_h"),
)
PARAMETERS = (
    Parameter("R", "m", "platform tuning radius = radius of the navigation sphere", "R",
              TUNING_RADIUS),
    Parameter("U", "rad/s", "Earth rotation rate", "U", EARTH_RATE),
    Parameter("orth_latitude", "rad", "geographic latitude φ_o of the orthodromic origin",
              r"\varphi_o", 0.0),
    Parameter("orth_longitude", "rad", "longitude λ_o of the orthodromic origin",
              r"\lambda_o", 0.0),
    Parameter("orth_azimuth", "rad", "azimuth N_o of the orthodrome at its origin (from north)",
              "N_o", math.pi / 2),
)
OUTPUTS = (
    Variable("latitude", "rad", "geographic (geocentric) latitude φ", r"\varphi"),
    Variable("longitude", "rad", "longitude λ", r"\lambda"),
    Variable("heading", "rad", "true azimuth ψ of the reference axis ξ'", r"\psi"),
    Variable("v_N", "m/s", "north relative velocity", "v_N"),
    Variable("v_E", "m/s", "east relative velocity", "v_E"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude φ0", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude λ0", r"\lambda_0"),
    Variable("heading", "rad", "initial true azimuth ψ0 of the reference axis ξ'", r"\psi_0"),
    Variable("v_N", "m/s", "initial north relative velocity", r"v_{N0}"),
    Variable("v_E", "m/s", "initial east relative velocity", r"v_{E0}"),
)



SOURCES = (
    error_source("initial_tilt_x", "rad", "arcsec", "initial", 1, r"\alpha_0",
                 "initial platform deviation about x (gravity levelling: 2α_g)"),
    error_source("initial_tilt_y", "rad", "arcsec", "initial", 1, r"\beta_0",
                 "initial platform deviation about y (gravity levelling: 2β_g)"),
    error_source("initial_azimuth_error", "rad", "arcmin", "initial", 2, r"\delta_0",
                 "initial platform azimuth deviation from the reference trihedron"),
    error_source("initial_A_error", "rad", "arcmin", "initial", 2, r"\Delta A_0",
                 "error of the initial angle A set into the computer"),
    error_source("initial_velocity_error_x", "m/s", "m/s", "initial", 3, r"\Delta V_{x0}",
                 "error of the initial velocity integrator x"),
    error_source("initial_velocity_error_y", "m/s", "m/s", "initial", 3, r"\Delta V_{y0}",
                 "error of the initial velocity integrator y"),
    error_source("initial_Phi_error", "rad", "arcmin", "initial", 4, r"\Delta\Phi_0",
                 "error of the initial orthodromic latitude"),
    error_source("initial_Lam_error", "rad", "arcmin", "initial", 4, r"\Delta\Lambda_0",
                 "error of the initial orthodromic longitude"),
    error_source("gyro_drift_x", "rad/s", "deg/h", "constant", 5, r"\omega_{dx}",
                 "residual (uncompensated part of the) drift of the gyro about x"),
    error_source("gyro_drift_y", "rad/s", "deg/h", "constant", 5, r"\omega_{dy}",
                 "residual (uncompensated part of the) drift of the gyro about y"),
    error_source("gyro_drift_z", "rad/s", "deg/h", "constant", 6, r"\omega_{dz}",
                 "azimuth drift (not compensated in this system)"),
    error_source("accel_bias_x", "m/s**2", "ug", "constant", 7, r"\Delta a_x",
                 "zero offset of the x accelerometer"),
    error_source("accel_bias_y", "m/s**2", "ug", "constant", 7, r"\Delta a_y",
                 "zero offset of the y accelerometer"),
    error_source("velocity_integrator_offset_x", "m/s**2", "ug", "constant", 8, r"\delta_{1x}",
                 "zero offset of the first (velocity) integrator x, at its input"),
    error_source("velocity_integrator_offset_y", "m/s**2", "ug", "constant", 8, r"\delta_{1y}",
                 "zero offset of the first (velocity) integrator y, at its input"),
    error_source("position_integrator_offset_Phi", "rad/s", "deg/h", "constant", 9,
                 r"\delta_{2\Phi}",
                 "zero offset of the second integrator of (8.35): rate added to Φ̇"),
    error_source("position_integrator_offset_Lam", "rad/s", "deg/h", "constant", 9,
         r"\delta_{2\Lambda}", "zero offset of the second integrator of (8.35): rate added to Λ̇"),
    error_source("accel_scale_error_x", "1", "ppm", "constant", 10, r"k_{ax}",
                 "scale-factor error of the x accelerometer"),
    error_source("accel_scale_error_y", "1", "ppm", "constant", 10, r"k_{ay}",
                 "scale-factor error of the y accelerometer"),
    error_source("velocity_integrator_gain_error_x", "1", "ppm", "constant", 11, r"k_{1x}",
                 "gain error of the first (velocity) integrator x"),
    error_source("velocity_integrator_gain_error_y", "1", "ppm", "constant", 11, r"k_{1y}",
                 "gain error of the first (velocity) integrator y"),
    error_source("position_integrator_gain_error_Phi", "1", "ppm", "constant", 12, r"k_{2\Phi}",
                 "gain error of the second integrator of Φ"),
    error_source("position_integrator_gain_error_Lam", "1", "ppm", "constant", 12, r"k_{2\Lambda}",
                 "gain error of the second integrator of Λ"),
    error_source("correction_gain_error_x", "1", "ppm", "constant", 13, r"k_{cx}",
                 "gain error of the correction loop about x (tuning 1/R)"),
    error_source("correction_gain_error_y", "1", "ppm", "constant", 13, r"k_{cy}",
                 "gain error of the correction loop about y (tuning 1/R)"),
)

_sym = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES, *PLATFORM_ANGLES)}
R, U = _sym["R"], _sym["U"]
phi_o, lam_o, N_o = _sym["orth_latitude"], _sym["orth_longitude"], _sym["orth_azimuth"]


# --------------------------------------------------------------------------------------
# Geometry of the orthodromic system
# --------------------------------------------------------------------------------------
def earth_axis_orthodromic() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Unit Earth axis in the Earth-fixed orthodromic frame (X origin, Y along, Z pole)."""
    return (sp.sin(phi_o), sp.cos(phi_o) * sp.cos(N_o), sp.cos(phi_o) * sp.sin(N_o))


def earth_axis_local(Phi: sp.Expr, Lam: sp.Expr) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Unit Earth axis on the local orthodromic trihedron ξ (along), η (to pole), ζ (up)."""
    kX, kY, kZ = earth_axis_orthodromic()
    k_xi = -kX * sp.sin(Lam) + kY * sp.cos(Lam)
    k_eta = -kX * sp.sin(Phi) * sp.cos(Lam) - kY * sp.sin(Phi) * sp.sin(Lam) + kZ * sp.cos(Phi)
    k_zeta = kX * sp.cos(Phi) * sp.cos(Lam) + kY * sp.cos(Phi) * sp.sin(Lam) + kZ * sp.sin(Phi)
    return k_xi, k_eta, k_zeta


def orthodromic_from_geographic(lat: sp.Expr, lon: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(Φ, Λ) of the point at geographic latitude ``lat`` and longitude ``lon`` (sphere)."""
    dl = lon - lam_o
    x1, y1, z = sp.cos(lat) * sp.cos(dl), sp.cos(lat) * sp.sin(dl), sp.sin(lat)
    # on the origin's east/north/up axes
    p_E = y1
    p_N = z * sp.cos(phi_o) - x1 * sp.sin(phi_o)
    p_U = x1 * sp.cos(phi_o) + z * sp.sin(phi_o)
    P_X = p_U
    P_Y = p_E * sp.sin(N_o) + p_N * sp.cos(N_o)
    P_Z = -p_E * sp.cos(N_o) + p_N * sp.sin(N_o)
    return sp.atan2(P_Z, sp.sqrt(P_X**2 + P_Y**2)), sp.atan2(P_Y, P_X)


def geographic_longitude(Phi: sp.Expr, Lam: sp.Expr) -> sp.Expr:
    """Longitude λ of the point (Φ, Λ) (continuous around λ_o)."""
    P_X, P_Y, P_Z = sp.cos(Phi) * sp.cos(Lam), sp.cos(Phi) * sp.sin(Lam), sp.sin(Phi)
    p_E = P_Y * sp.sin(N_o) - P_Z * sp.cos(N_o)
    p_N = P_Y * sp.cos(N_o) + P_Z * sp.sin(N_o)
    p_U = P_X
    return lam_o + sp.atan2(p_E, p_U * sp.cos(phi_o) - p_N * sp.sin(phi_o))


# --------------------------------------------------------------------------------------
# The computer
# --------------------------------------------------------------------------------------
def platform_rates(eq: Mechanisation, s: list[sp.Symbol]):
    """Rates the electronics torque the platform with: (ω_x, ω_y, ω_z = 0), rad/s."""
    _Phi, _Lam, _A, V_x, V_y = s
    omega_x = eq.let("omega_x", -V_y / R, r"\omega_x")
    omega_y = eq.let("omega_y", V_x / R, r"\omega_y")
    return omega_x, omega_y, sp.S.Zero


def relative_velocity(eq: Mechanisation, s: list[sp.Symbol]):
    """Earth axis and relative velocity on the reference and orthodromic axes.

    Returns
    -------
    k : tuple
        (k_ξ, k_η, k_ζ, k_x, k_y): unit Earth axis on the orthodromic and reference axes.
    v : tuple
        (v_x, v_y, v_ξ, v_η): relative velocity, m/s.
    """
    Phi, Lam, A, V_x, V_y = s
    k_xi_e, k_eta_e, k_zeta_e = earth_axis_local(Phi, Lam)
    k_xi = eq.let("k_xi", k_xi_e, r"k_\xi")
    k_eta = eq.let("k_eta", k_eta_e, r"k_\eta")
    k_zeta = eq.let("k_zeta", k_zeta_e, r"k_\zeta")
    k_x = eq.let("k_x", k_xi * sp.cos(A) + k_eta * sp.sin(A), "k_x")
    k_y = eq.let("k_y", -k_xi * sp.sin(A) + k_eta * sp.cos(A), "k_y")
    # relative = absolute − U k × R ζ
    v_x = eq.let("v_x", V_x - U * R * k_y, "v_x")
    v_y = eq.let("v_y", V_y + U * R * k_x, "v_y")
    v_xi = eq.let("v_xi", v_x * sp.cos(A) - v_y * sp.sin(A), r"v_\xi")
    v_eta = eq.let("v_eta", v_x * sp.sin(A) + v_y * sp.cos(A), r"v_\eta")
    return (k_xi, k_eta, k_zeta, k_x, k_y), (v_x, v_y, v_xi, v_eta)


def computer(eq: Mechanisation, s: list[sp.Symbol], f_x: sp.Expr, f_y: sp.Expr,
             V_h: sp.Symbol, errors: dict[str, sp.Expr] | None = None):
    """The IS-1-72A algorithm: derivatives of (Φ, Λ, A, V_x, V_y) and the platform rates.

    Parameters
    ----------
    eq : Mechanisation
        Where the intermediate quantities are recorded.
    s : list of sympy.Symbol
        (Φ, Λ, A, V_x, V_y): true state in ideal work, computed state in real work.
    f_x, f_y : sympy.Expr
        Accelerations fed to the velocity integrators, m/s².
    V_h : sympy.Symbol
        Vertical velocity, m/s.
    errors : dict, optional
        Integrator errors of real work, by source name (offsets and gain errors of the
        velocity integrators and of the integrators of (8.35)); none in ideal work.
    """
    Phi, _Lam, _A, _V_x, _V_y = s
    err = errors or {}

    def e(name: str) -> sp.Expr:
        return err.get(name, sp.S.Zero)

    omega_x, omega_y, _ = platform_rates(eq, s)
    (_k_xi, _k_eta, k_zeta, _k_x, _k_y), (_v_x, _v_y, v_xi, v_eta) = relative_velocity(eq, s)
    # (8.35): orthodromic coordinates and the angle A (reference has no azimuth rate)
    dPhi = (1 + e("position_integrator_gain_error_Phi")) * v_eta / R + e(
        "position_integrator_offset_Phi")
    dLam = (1 + e("position_integrator_gain_error_Lam")) * v_xi / (R * sp.cos(Phi)) + e(
        "position_integrator_offset_Lam")
    dA = -U * k_zeta - v_xi * sp.tan(Phi) / R
    # velocity integrators (absolute velocity, reference frame free in azimuth)
    dV_x = (1 + e("velocity_integrator_gain_error_x")) * (
        f_x - omega_y * V_h + e("velocity_integrator_offset_x"))
    dV_y = (1 + e("velocity_integrator_gain_error_y")) * (
        f_y + omega_x * V_h + e("velocity_integrator_offset_y"))
    return [dPhi, dLam, dA, dV_x, dV_y], (omega_x, omega_y)


def navigation_outputs(eq: Mechanisation, s: list[sp.Symbol], inputs: list[sp.Symbol]):
    """Latitude, longitude, true azimuth of ξ', north and east relative velocity."""
    Phi, Lam, _A, _V_x, _V_y = s
    (k_xi, k_eta, k_zeta, k_x, k_y), (v_x, v_y, _v_xi, _v_eta) = relative_velocity(eq, s)
    cos_lat = eq.let("cos_lat", sp.sqrt(k_xi**2 + k_eta**2), r"\left(\cos\varphi\right)")
    lat = sp.atan2(k_zeta, cos_lat)
    lon = geographic_longitude(Phi, Lam)
    psi = sp.atan2(k_y, k_x)
    v_N = (v_x * k_x + v_y * k_y) / cos_lat
    v_E = (v_x * k_y - v_y * k_x) / cos_lat
    return sp.Matrix([lat, lon, psi, v_N, v_E])


# --------------------------------------------------------------------------------------
# Initial conditions
# --------------------------------------------------------------------------------------
def initial_navigation_state(lat, lon, psi, v_N, v_E) -> list[sp.Expr]:
    """(Φ, Λ, A, V_x, V_y) of a start at (φ, λ) with ξ' at true azimuth ψ, velocity (v_N, v_E)."""
    Phi0, Lam0 = orthodromic_from_geographic(lat, lon)
    k_xi, k_eta, _ = earth_axis_local(Phi0, Lam0)
    chi0 = sp.atan2(k_eta, k_xi)  # true azimuth of the orthodromic axis ξ
    A0 = chi0 - psi
    v_x = v_E * sp.sin(psi) + v_N * sp.cos(psi)
    v_y = -v_E * sp.cos(psi) + v_N * sp.sin(psi)
    V_x = v_x + U * R * sp.cos(lat) * sp.sin(psi)
    V_y = v_y - U * R * sp.cos(lat) * sp.cos(psi)
    return [Phi0, Lam0, A0, V_x, V_y]


def levelling_offsets(latitude: float, heading: float,
                      flattening: float = ELLIPSOIDS["krasovsky"].flattening
                      ) -> tuple[float, float]:
    """Initial platform angles (α0, β0) = (2α_g, 2β_g) after levelling by gravity.

    The gravity (geodetic) vertical deviates from the geocentric one by f sin 2φ toward
    the pole (first order in the flattening f); α_g, β_g are the half-angle projections
    of that deviation on the platform axes x, y, so the platform levelled by gravity
    starts at α0 = 2α_g, β0 = 2β_g from the geocentric reference.

    Parameters
    ----------
    latitude : float
        Latitude of the parking place, rad.
    heading : float
        True azimuth ψ of the platform axis x (reference axis ξ'), rad.
    flattening : float
        Polar flattening of the Earth (Krasovsky by default).

    Returns
    -------
    alpha0, beta0 : float
        Values for the sources ``initial_tilt_x``, ``initial_tilt_y``, rad.
    """
    half = 0.5 * flattening * math.sin(2.0 * latitude)
    alpha_g, beta_g = -half * math.sin(heading), half * math.cos(heading)
    return 2.0 * alpha_g, 2.0 * beta_g


MODE_NOTES = {
    "Schuler": (
        "two channels, not a Foucault pair, and not a slip: the reference axes ξ'η' do not "
        "turn about the vertical (no azimuth command: the wander angle A takes up the "
        "Earth's vertical rate, Ȧ = −U k_ζ) and the integrators hold the absolute "
        "velocity (no Coriolis terms), so nothing splits the Schuler pair by Ω sin φ; "
        "but at rest the platform is torqued at the horizontal Earth rate Ω cos φ about "
        "north, and α̇ = α × ω couples the tilt about the horizontal axis across it (the "
        "channel of the velocity error along north) with the azimuth error α_z (the "
        "gyrocompass coupling), which stiffens that channel: ω² = g/R + Ω² cos² φ (g the "
        "vertical specific force a_ζ at rest, R the model's tuning radius; 84.65 min "
        "against 2π√(R/g) = 84.76 min at −30°, −0.17 % at the equator), exactly, at any "
        "heading; the other channel is the textbook 2π√(R/g). These are the wander-frame "
        "states' modes: the outputs (latitude, longitude, heading) are read through A, "
        "which turns at rest, and show the Schuler oscillation split by ±U sin φ "
        "(Schuler ∓ Foucault, 88.7 and 81.0 min at 50°)"),
}
"""Why this model's static-base modes differ from the textbook formulas of ``ins-errors
modes`` (:attr:`ins_errors.modeling.ModelDefinition.mode_notes`)."""


# --------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------
def build(platform: str = "exact") -> ModelDefinition:
    """Assemble the symbolic definition of the free-azimuth INS.

    ``platform``: ``"exact"`` or the source's ``"small_angle"`` platform kinematics
    (:mod:`ins_errors.models.platform`).
    """
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    alpha = [v.symbol for v in PLATFORM_ANGLES]
    a_x, a_y, a_z, V_h = (v.symbol for v in INPUTS)
    w = _sym

    ideal = Mechanisation()
    ideal_rhs, (Om_x, Om_y) = computer(ideal, x, a_x, a_y, V_h)

    # Instruments on the platform deviated by α from the reference trihedron.
    p_x, p_y, _ = on_platform(alpha, (a_x, a_y, a_z), platform)
    f_x = (1 + w["accel_scale_error_x"]) * p_x + w["accel_bias_x"]
    f_y = (1 + w["accel_scale_error_y"]) * p_y + w["accel_bias_y"]
    real = Mechanisation(computed=True)
    integrators = {name: w[name] for name in w if "_integrator_" in name}
    computed_rhs, (om_x, om_y) = computer(real, x_c, f_x, f_y, V_h, integrators)
    # Platform: torqued in x, y by the integrator rates; free in azimuth (no command).
    cmd = ((1 + w["correction_gain_error_x"]) * om_x, (1 + w["correction_gain_error_y"]) * om_y,
           sp.S.Zero)
    Om = (Om_x, Om_y, sp.S.Zero)
    drift = (w["gyro_drift_x"], w["gyro_drift_y"], w["gyro_drift_z"])
    torque = [c + d for c, d in zip(cmd, drift, strict=True)]
    platform_rhs = kinematic_rates(alpha, torque, Om, platform)

    c = [v.symbol for v in INITIAL_CONDITIONS]
    lat0, lon0, psi0, vN0, vE0 = c
    x0 = initial_navigation_state(lat0, lon0, psi0, vN0, vE0)
    initial_real_state = sp.Matrix([
        x0[0] + w["initial_Phi_error"],
        x0[1] + w["initial_Lam_error"],
        x0[2] + w["initial_A_error"],
        x0[3] + w["initial_velocity_error_x"],
        x0[4] + w["initial_velocity_error_y"],
        w["initial_tilt_x"], w["initial_tilt_y"], w["initial_azimuth_error"],
    ])
    k_xi, k_eta, _ = earth_axis_local(x[0], x[1])

    return ModelDefinition(
        name="free_azimuth",
        title="Free-azimuth platform INS (IS-1-72A), rebuilt",
        source="002: information-processing algorithm of a free-azimuth INS (IS-1-72A)",
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
        initial_state=sp.Matrix(x0),
        initial_real_state=initial_real_state,
        groups=(
            ("Platform deviation (α, β, δ)", ["alpha_x", "alpha_y", "alpha_z"]),
            ("Velocity-integrator errors", ["delta_V_x", "delta_V_y"]),
            ("Orthodromic coordinate errors", ["delta_Phi", "delta_Lam", "delta_A"]),
        ),
        domain=(
            (sp.cos(x[0]) ** 2 - 1e-12,
             "orthodromic latitude at ±90°: (8.35) divides by cos Φ"),
            (k_xi**2 + k_eta**2 - 1e-12,
             "latitude at ±90°: north and east are undefined at the geographic pole"),
            (R, "R <= 0: the tuning radius must be positive"),
        ),
        initial_domain=(
            (sp.cos(lat0) ** 2 - 1e-12, "initial latitude at ±90°: heading is undefined"),
            (R, "R <= 0: the tuning radius must be positive"),
        ),
        mode_notes=MODE_NOTES,
        notes=__doc__.split("Modelling choices", 1)[1].split(":", 1)[1].strip(),
    )
