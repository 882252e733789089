r"""Inertial vertical on the Krasovsky spheroid in orthodromic coordinates (source 004).

Artyukhovsky & Studenikin, "On one methodological error of the inertial vertical".
The platform holds the *geodetic* vertical (frame ξηζ, ζ along the ellipsoid normal);
its horizontal axes follow the orthodromic meridian. The computer works with the
"geodetic orthodromic" coordinates Φ = Φ1 + ν1, Λ = Λ1 + ν2 / cos Φ of (5) and the
*spherical* formulas evaluated with them:

* the orthodrome: direction cosines n_ij (1) of the start frame ξ¹η¹ζ¹ from the start
  longitude λ0, geocentric latitude φ0 and orthodrome angle N0, on the Earth axes
  ξ0η0ζ0 (η0 along the Earth's angular velocity);
* the current frame: m_ij (2) = Table 2 (Φ, Λ) × n; with (5), sin B = −m_32,
  cos B sin N = m_12, cos B cos N = m_22 (B geodetic latitude, N orthodrome angle);
* the deflection of the normal from the radius, (3) ν1 = μ cos N, ν2 = −μ sin N, with
  μ(B) = c sin 2B − ½ c² sin 4B (4) and c = (a² − b²)/(a² + b²);
* the accelerometer readings and the platform correction rates (9), with
  R = a(1 − c sin² B); dead reckoning Φ̇ = −W_η / R, Λ̇ = W_ξ / (R cos Φ).

Ideal work: this computer fed the true apparent accelerations along the geodetic axes
(platform on the geodetic vertical). Real work: the same computer fed accelerometers on
the misaligned platform, with gyro drifts, accelerometer biases and initial errors. The
purely geometric methodological error of formula (10) (dead reckoning of this kind
yields the geocentric Φ1, Λ1) is studied against a direct simulation over the spheroid
in :mod:`ins_errors.studies.spheroid_error`.

Modelling choices (also printed at the top of ``generated/geodetic_vertical/error_equations.md``):

* Table (1) is not orthonormal as printed; we use n11 = cos λ0 cos N0 + sin λ0 sin φ0 sin N0
  and n22 = cos φ0 cos N0 (the translator's correction: with it n nᵀ = I, det n = 1), all
  other entries as printed.
* The printed tables are kept as they are, including their orientation: Table 2 gives
  Φ̇ = −W_η / R (as the paper's dead-reckoning formula), and with η0 along the Earth's
  angular velocity the paper's latitude is the one with sin φ = −m_32 (its identity
  "−m_32 = sin φ"); the Earth-rate terms of (7) and (9) are then ω(m_12, m_22, m_32),
  exactly the printed ω cos B sin N, ω cos B cos N, −ω sin B.
* (9) is encoded as printed, with V_c read as V_ζ; the transport terms V_ζ W / R of (8),
  absent from (9), stay absent. The ν terms of the correction rates are kept.
* μ/cos B is expanded algebraically (2c sin B − 2c² sin B cos 2B), so ν1, ν2 need no
  square roots; sin B = −m_32, cos B = √(1 − m_32²).
* the outputs: geodetic latitude B, longitude L of the normal (sin L cos B = m_31,
  cos L cos B = m_33), orthodrome angle N, and the velocity along geographic north
  −(sin N, cos N) and east = north × up on the ξη axes.
"""

from __future__ import annotations

import sympy as sp

from ins_errors.modeling import (
    EARTH_RATE,
    ELLIPSOIDS,
    ErrorSource,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    error_states_of,
    on_platform,
    platform_rates,
)

# --------------------------------------------------------------------------------------
# Names (public API: keep stable)
# --------------------------------------------------------------------------------------
STATES = (
    Variable("Phi", "rad", "geodetic orthodromic latitude Φ (5)", r"\Phi"),
    Variable("Lam", "rad", "geodetic orthodromic longitude Λ (5)", r"\Lambda"),
    Variable("W_xi", "m/s", "relative velocity along ξ (along the orthodrome)", r"W_\xi"),
    Variable("W_eta", "m/s", "relative velocity along η (orthodromic meridian)", r"W_\eta"),
)
PLATFORM_ANGLES = (
    Variable("alpha_x", "rad", "platform misalignment about ξ", r"\alpha_x"),
    Variable("alpha_y", "rad", "platform misalignment about η", r"\alpha_y"),
    Variable("alpha_z", "rad", "platform misalignment in azimuth", r"\alpha_z"),
)
ERROR_STATES = error_states_of(STATES, PLATFORM_ANGLES)
INPUTS = (
    Variable("a_xi", "m/s**2", "true apparent acceleration j_ξ along ξ", r"j_\xi"),
    Variable("a_eta", "m/s**2", "true apparent acceleration j_η along η", r"j_\eta"),
    Variable("a_zeta", "m/s**2", "true apparent acceleration j_ζ along the normal (≈ g)",
             r"j_\zeta"),
    Variable("V_zeta", "m/s", "vertical velocity V_ζ (given from outside)", r"V_\zeta"),
)
PARAMETERS = (
    Parameter("a", "m", "semi-major axis of the ellipsoid", "a",
              ELLIPSOIDS["krasovsky"].semi_major_axis),
    Parameter("e2", "1", "first eccentricity squared (c = e²/(2 − e²))", "e^{2}",
              ELLIPSOIDS["krasovsky"].eccentricity_squared),
    Parameter("U", "rad/s", "Earth rotation rate ω", r"\omega", EARTH_RATE),
    Parameter("orth_latitude", "rad", "geocentric latitude φ0 of the orthodrome's start point",
              r"\varphi_0", 0.0),
    Parameter("orth_longitude", "rad", "longitude λ0 of the orthodrome's start point",
              r"\lambda_0", 0.0),
    Parameter("orth_angle", "rad", "orthodrome angle N0 at the start point", "N_0", 0.0),
)
OUTPUTS = (
    Variable("latitude", "rad", "geodetic latitude B", "B"),
    Variable("longitude", "rad", "longitude L", "L"),
    Variable("orthodrome_angle", "rad", "orthodrome angle N", "N"),
    Variable("v_N", "m/s", "north relative velocity", "v_N"),
    Variable("v_E", "m/s", "east relative velocity", "v_E"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial geodetic latitude B0", "B_0"),
    Variable("longitude", "rad", "initial longitude L0", "L_0"),
    Variable("v_N", "m/s", "initial north relative velocity", r"v_{N0}"),
    Variable("v_E", "m/s", "initial east relative velocity", r"v_{E0}"),
)


MODE_NOTES = {
    "Earth": (
        "not 2π/Ω on the ellipsoid, and not a slip of this code: the correction rates (9) "
        "keep the deflection terms (W_ξ/R) tg Φ ν2, −(W_ξ/R) tg Φ ν1 and −(W_η/R) ν2, "
        "which the dead reckoning Φ̇ = −W_η/R, Λ̇ = W_ξ/(R cos Φ) lacks, so a velocity "
        "error turns the platform and the trihedron of the reckoned (Φ, Λ) at different "
        "rates, and the platform's error against that trihedron no longer just turns with "
        "the Earth: ω ≈ Ω √(1 + μ (tg Φ cos N sin² B + sin² N sin B cos B)); on the "
        "default orthodrome (the meridian: N = 0, Φ = B) the period is shorter by "
        "≈ c sin⁴ B (0.084 % at 45°, 0.316 % at 80°); exactly 2π/Ω with e2 = 0"),
    "Schuler": (
        "the north channel runs on R = a(1 − c sin² B) of (9), not on a radius of "
        "curvature, and the east channel, through −(W_ξ/R) tg Φ ν1 in Ω_η, on "
        "R/(1 − ν1 tg Φ); on the default orthodrome (the meridian) the pair is the "
        "textbook one for the geometric mean of the two, ≈ a, rather than √(R_M R_N) "
        "(−0.17 % at 80°); exactly the textbook periods with e2 = 0"),
}
"""Why ``ins-errors modes`` finds this mechanisation's Earth and Schuler periods off the
textbook values on the ellipsoid (see ``tests/test_modes.py`` for the independent check)."""


def _src(name, unit, display, kind, latex, text) -> ErrorSource:
    return ErrorSource(name, unit, text, latex, kind=kind, display_unit=display)


SOURCES = (
    _src("initial_tilt_x", "rad", "arcsec", "initial", r"\alpha_{x0}",
         "initial platform misalignment about ξ"),
    _src("initial_tilt_y", "rad", "arcsec", "initial", r"\alpha_{y0}",
         "initial platform misalignment about η"),
    _src("initial_azimuth_error", "rad", "arcmin", "initial", r"\alpha_{z0}",
         "initial platform azimuth misalignment"),
    _src("initial_velocity_error_xi", "m/s", "m/s", "initial", r"\Delta W_{\xi 0}",
         "error of the initial velocity W_ξ"),
    _src("initial_velocity_error_eta", "m/s", "m/s", "initial", r"\Delta W_{\eta 0}",
         "error of the initial velocity W_η"),
    _src("initial_Phi_error", "rad", "arcmin", "initial", r"\Delta\Phi_0",
         "error of the initial orthodromic latitude"),
    _src("initial_Lam_error", "rad", "arcmin", "initial", r"\Delta\Lambda_0",
         "error of the initial orthodromic longitude"),
    _src("gyro_drift_x", "rad/s", "deg/h", "constant", r"\omega_{dx}",
         "constant drift of the gyro about ξ"),
    _src("gyro_drift_y", "rad/s", "deg/h", "constant", r"\omega_{dy}",
         "constant drift of the gyro about η"),
    _src("gyro_drift_z", "rad/s", "deg/h", "constant", r"\omega_{dz}",
         "constant drift of the azimuth gyro"),
    _src("accel_bias_x", "m/s**2", "ug", "constant", r"\Delta j_\xi",
         "zero offset of the ξ accelerometer"),
    _src("accel_bias_y", "m/s**2", "ug", "constant", r"\Delta j_\eta",
         "zero offset of the η accelerometer"),
)

_sym = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES, *PLATFORM_ANGLES)}
a, e2, omega = _sym["a"], _sym["e2"], _sym["U"]
phi0, lam0, N0 = _sym["orth_latitude"], _sym["orth_longitude"], _sym["orth_angle"]


# --------------------------------------------------------------------------------------
# Geometry: tables (1), (2), deflection (3), (4)
# --------------------------------------------------------------------------------------
def flattening_constant() -> sp.Expr:
    """c = (a² − b²)/(a² + b²) in terms of e²."""
    return e2 / (2 - e2)


def start_frame(lat0: sp.Expr = phi0, lon0: sp.Expr = lam0, angle0: sp.Expr = N0) -> sp.Matrix:
    """Table (1): n_ij, rows ξ¹, η¹, ζ¹ on the Earth axes ξ0, η0, ζ0 (orthonormal reading)."""
    s, c = sp.sin, sp.cos
    return sp.Matrix([
        [c(lon0) * c(angle0) + s(lon0) * s(lat0) * s(angle0), c(lat0) * s(angle0),
         s(lat0) * c(lon0) * s(angle0) - s(lon0) * c(angle0)],
        [s(lon0) * s(lat0) * c(angle0) - c(lon0) * s(angle0), c(lat0) * c(angle0),
         c(lon0) * s(lat0) * c(angle0) + s(lon0) * s(angle0)],
        [s(lon0) * c(lat0), -s(lat0), c(lon0) * c(lat0)],
    ])


def orthodromic_table(Phi: sp.Expr, Lam: sp.Expr) -> sp.Matrix:
    """Table 2: the current frame on the start frame, at orthodromic coordinates (Φ, Λ)."""
    s, c = sp.sin, sp.cos
    return sp.Matrix([
        [c(Lam), 0, -s(Lam)],
        [s(Lam) * s(Phi), c(Phi), c(Lam) * s(Phi)],
        [s(Lam) * c(Phi), -s(Phi), c(Lam) * c(Phi)],
    ])


def current_frame(Phi: sp.Expr, Lam: sp.Expr) -> sp.Matrix:
    """(2): m = Table 2 × n, the current frame on the Earth axes."""
    return orthodromic_table(Phi, Lam) * start_frame()


# --------------------------------------------------------------------------------------
# The computer: formulas (9) and the dead reckoning
# --------------------------------------------------------------------------------------
def computer(eq: Mechanisation, s: list[sp.Symbol], j_xi: sp.Expr, j_eta: sp.Expr,
             V_zeta: sp.Symbol):
    """Derivatives of (Φ, Λ, W_ξ, W_η) and the platform correction rates (Ω_ξ, Ω_η, Ω_ζ).

    Parameters
    ----------
    eq : Mechanisation
        Where the intermediate quantities are recorded.
    s : list of sympy.Symbol
        (Φ, Λ, W_ξ, W_η): true in ideal work, computed in real work.
    j_xi, j_eta : sympy.Expr
        Accelerometer readings fed to the computer, m/s².
    V_zeta : sympy.Symbol
        Vertical velocity, m/s.
    """
    Phi, Lam, W_xi, W_eta = s
    m = current_frame(Phi, Lam)
    m12 = eq.let("m12", m[0, 1], "m_{12}")  # cos B sin N
    m22 = eq.let("m22", m[1, 1], "m_{22}")  # cos B cos N
    m32 = eq.let("m32", m[2, 1], "m_{32}")  # −sin B
    c = flattening_constant()
    R = eq.let("R", a * (1 - c * m32**2), "R")
    tg = sp.tan(Phi)
    # (3)-(4): ν1 = μ cos N, ν2 = −μ sin N, with μ / cos B expanded
    mu_over_cos = eq.let("mu_over_cosB", 2 * c * (-m32) - 2 * c**2 * (-m32) * (1 - 2 * m32**2),
                         r"\mu/\cos B")
    nu1 = eq.let("nu1", mu_over_cos * m22, r"\nu_1")
    nu2 = eq.let("nu2", -mu_over_cos * m12, r"\nu_2")
    # (9): platform correction rates
    Om_xi = eq.let("Omega_xi", -W_eta / R + omega * m12 + W_xi / R * tg * nu2, r"\Omega_\xi")
    Om_eta = eq.let("Omega_eta", W_xi / R + omega * m22 - W_xi / R * tg * nu1, r"\Omega_\eta")
    Om_zeta = eq.let("Omega_zeta", -W_xi / R * tg + omega * m32 - W_eta / R * nu2,
                     r"\Omega_\zeta")
    # (9): relative accelerations W' from the accelerometer readings (sin B = −m32)
    dW_xi = j_xi - W_xi * W_eta / R * tg + 2 * W_eta * omega * m32 - 2 * V_zeta * omega * m22
    dW_eta = j_eta + W_xi**2 / R * tg - 2 * W_xi * omega * m32 + 2 * V_zeta * omega * m12
    # dead reckoning
    dPhi = -W_eta / R
    dLam = W_xi / (R * sp.cos(Phi))
    return [dPhi, dLam, dW_xi, dW_eta], (Om_xi, Om_eta, Om_zeta)


def navigation_outputs(eq: Mechanisation, s: list[sp.Symbol], inputs: list[sp.Symbol]):
    """B, L, N, v_N, v_E of a state."""
    Phi, Lam, W_xi, W_eta = s
    m = current_frame(Phi, Lam)
    m12, m22, m32 = m[0, 1], m[1, 1], m[2, 1]
    cos_B = eq.let("cos_B", sp.sqrt(m12**2 + m22**2), r"\left(\cos B\right)")
    B = sp.atan2(-m32, cos_B)
    L = sp.atan2(m[2, 0], m[2, 2])
    N = sp.atan2(m12, m22)
    v_N = -(W_xi * m12 + W_eta * m22) / cos_B
    v_E = (-W_xi * m22 + W_eta * m12) / cos_B
    return sp.Matrix([B, L, N, v_N, v_E])


def orthodromic_coordinates(B: sp.Expr, L: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(Φ, Λ) of the normal at geodetic (B, L): spherical formulas, as (5) allows."""
    normal = sp.Matrix([sp.sin(L) * sp.cos(B), -sp.sin(B), sp.cos(L) * sp.cos(B)])
    s_xi, s_eta, s_zeta = start_frame() * normal
    return sp.atan2(-s_eta, sp.sqrt(s_xi**2 + s_zeta**2)), sp.atan2(s_xi, s_zeta)


# --------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------
def build(platform: str = "exact") -> ModelDefinition:
    """Assemble the symbolic definition of the geodetic-vertical INS of source 004.

    ``platform``: ``"exact"`` or the source's ``"small_angle"`` platform kinematics
    (:mod:`ins_errors.models.platform`).
    """
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    alpha = [v.symbol for v in PLATFORM_ANGLES]
    j_xi, j_eta, j_zeta, V_zeta = (v.symbol for v in INPUTS)
    w = _sym

    ideal = Mechanisation()
    ideal_rhs, Om = computer(ideal, x, j_xi, j_eta, V_zeta)
    p_x, p_y, _ = on_platform(alpha, (j_xi, j_eta, j_zeta), platform)
    f_x = p_x + w["accel_bias_x"]
    f_y = p_y + w["accel_bias_y"]
    real = Mechanisation(computed=True)
    computed_rhs, Om_c = computer(real, x_c, f_x, f_y, V_zeta)
    drift = (w["gyro_drift_x"], w["gyro_drift_y"], w["gyro_drift_z"])
    torque = [c + d for c, d in zip(Om_c, drift, strict=True)]
    platform_rhs = platform_rates(alpha, torque, Om, platform)

    B0, L0, vN0, vE0 = (v.symbol for v in INITIAL_CONDITIONS)
    Phi0, Lam0 = orthodromic_coordinates(B0, L0)
    m = current_frame(Phi0, Lam0)
    sin_N, cos_N = m[0, 1] / sp.cos(B0), m[1, 1] / sp.cos(B0)
    W_xi0 = -vN0 * sin_N - vE0 * cos_N
    W_eta0 = -vN0 * cos_N + vE0 * sin_N
    x0 = [Phi0, Lam0, W_xi0, W_eta0]
    initial_real_state = sp.Matrix([
        Phi0 + w["initial_Phi_error"], Lam0 + w["initial_Lam_error"],
        W_xi0 + w["initial_velocity_error_xi"], W_eta0 + w["initial_velocity_error_eta"],
        w["initial_tilt_x"], w["initial_tilt_y"], w["initial_azimuth_error"],
    ])
    m_now = current_frame(x[0], x[1])

    return ModelDefinition(
        name="geodetic_vertical",
        title="Inertial vertical on the spheroid, geodetic orthodromic coordinates",
        source="004: Artyukhovsky & Studenikin, 'On one methodological error of the "
               "inertial vertical'",
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
            ("Platform misalignment", ["alpha_x", "alpha_y", "alpha_z"]),
            ("Velocity errors", ["delta_W_xi", "delta_W_eta"]),
            ("Orthodromic coordinate errors", ["delta_Phi", "delta_Lam"]),
        ),
        domain=(
            (sp.cos(x[0]) ** 2 - 1e-12, "orthodromic latitude at ±90°: Λ̇ divides by cos Φ"),
            (1 - m_now[2, 1] ** 2 - 1e-12,
             "latitude at ±90° (|m32| = 1): the orthodrome angle N is undefined"),
            (a, "a <= 0: the semi-major axis (Earth radius) must be positive"),
            (1 - e2, "eccentricity squared must be below 1"),
        ),
        initial_domain=(
            (sp.cos(B0) ** 2 - 1e-12, "initial latitude at ±90°: N is undefined at a pole"),
            (a, "a <= 0: the semi-major axis (Earth radius) must be positive"),
            (1 - e2, "eccentricity squared must be below 1"),
        ),
        notes=__doc__.split("Modelling choices", 1)[1].split(":", 1)[1].strip(),
        mode_notes=MODE_NOTES,
    )
