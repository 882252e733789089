r"""Orthodromic gyro-stabilised-platform INS (source 000, KPI lab manual, 2010).

The platform holds two accelerometers along the *orthodromic* trihedron ξηζ (ζ up,
ξ along the great circle at track angle χ from north, η to its left) over an ellipsoidal
Earth. The computer integrates six direction cosines ``u_ij`` between ξηζ and the
Greenwich frame (Poisson equations) and the horizontal absolute velocities V_ξ, V_η
(apparent accelerations corrected for transport/Coriolis terms and horizontal
gravitation); the platform is torqued with the commanded absolute rates ω_ξ, ω_η and
ω_ζ = U sin φ (azimuth corrected by U sin φ only).

The manual writes the algorithm as a rectangle-method difference scheme with step τ;
here it is encoded in continuous time (the scheme is its explicit-Euler discretisation,
reproduced exactly by :mod:`ins_errors.numeric`).

Modelling choices where the manual is silent or inconsistent (also printed at the top of
``generated/orthodromic/error_equations.md``):

* ``R_N`` is used but never defined; we take the meridian radius in the manual's own
  style, R_N = (a + h)(1 − e²)/√(1 − e² sin²φ)³, next to its R_E = (a + h)/√(1 − e² sin²φ).
* the velocity difference equations print ``+ g̃' + Δa`` outside the factor τ; in
  continuous time the only consistent reading is inside (accelerations are integrated).
* the third accelerometer row ``a_z`` is misprinted and unused (two accelerometers).
* platform kinematics are exact (z-y-x angles of the platform relative to the trihedron,
  specific force resolved through the exact rotation, :mod:`ins_errors.models.platform`);
  the manual's small-angle form α̇ = α × ω + (ω_cmd − ω) + drift, fᵖ = f − α × f (ω the
  true trihedron's absolute rate) is kept as the selectable ``small_angle`` platform.
  Both give the same error equations; the refined terms include the rotation's own.
* λ and χ use the four-quadrant arctangent of the manual's ratios; sin φ ≡ u31.
* height and vertical velocity reach the computer from outside without error
  (h̃ = h, Ṽ_ζ = V_ζ: the manual's ΔV_ζ terms vanish), as there is no vertical channel.
"""

from __future__ import annotations

from dataclasses import dataclass

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
    platform_rates,
)

# --------------------------------------------------------------------------------------
# Names (public API: keep stable)
# --------------------------------------------------------------------------------------
DIRECTION_COSINES = ("u11", "u21", "u31", "u12", "u22", "u32")
_DC_LATEX = {n: f"u_{{{n[1:]}}}" for n in DIRECTION_COSINES}

STATES = (
    *(Variable(n, "1", f"direction cosine {n[1]}{n[2]} (trihedron axis {'ξηζ'[int(n[1]) - 1]}"
               f" on Greenwich axis {n[2]})", _DC_LATEX[n]) for n in DIRECTION_COSINES),
    Variable("V_xi", "m/s", "absolute horizontal velocity along ξ (along the great "
             "circle, at track angle χ from north)", r"V_\xi"),
    Variable("V_eta", "m/s", "absolute horizontal velocity along η (to the left of ξ: "
             "west at χ = 0)", r"V_\eta"),
)
PLATFORM_ANGLES = (
    Variable("alpha_x", "rad", "platform misalignment about x (≈ξ)", r"\alpha_x"),
    Variable("alpha_y", "rad", "platform misalignment about y (≈η, to the left of ξ)",
             r"\alpha_y"),
    Variable("alpha_z", "rad", "platform misalignment about z (azimuth) from the computed "
             "orthodromic trihedron; from north: alpha_z + delta_heading", r"\alpha_z"),
)
ERROR_STATES = error_states_of(STATES, PLATFORM_ANGLES)
INPUTS = (
    Variable("a_xi", "m/s**2", "true apparent acceleration along ξ", r"a_\xi"),
    Variable("a_eta", "m/s**2", "true apparent acceleration along η", r"a_\eta"),
    Variable("a_zeta", "m/s**2", "true apparent acceleration along ζ (≈ +g at rest)", r"a_\zeta"),
    Variable("V_zeta", "m/s", "vertical velocity (given from outside)", r"V_\zeta"),
    Variable("h", "m", "height above the ellipsoid (given from outside)", "h"),
)
PARAMETERS = (
    Parameter("a", "m", "semi-major axis of the ellipsoid", "a",
              ELLIPSOIDS["krasovsky"].semi_major_axis),
    Parameter("e2", "1", "first eccentricity squared of the ellipsoid", "e^{2}",
              ELLIPSOIDS["krasovsky"].eccentricity_squared),
    Parameter("U", "rad/s", "Earth rotation rate", "U", EARTH_RATE),
)
OUTPUTS = (
    Variable("latitude", "rad", "geodetic latitude φ", r"\varphi"),
    Variable("longitude", "rad", "longitude λ", r"\lambda"),
    Variable("heading", "rad", "track angle χ of the ξ axis, from north", r"\chi"),
    Variable("omega_N", "rad/s", "relative angular rate about north", r"\omega_N"),
    Variable("omega_E", "rad/s", "relative angular rate about east", r"\omega_E"),
    Variable("v_N", "m/s", "north relative velocity", "v_N"),
    Variable("v_E", "m/s", "east relative velocity", "v_E"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude φ0", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude λ0", r"\lambda_0"),
    Variable("heading", "rad", "initial track angle χ0", r"\chi_0"),
    Variable("v_N", "m/s", "initial north relative velocity", r"v_{N0}"),
    Variable("v_E", "m/s", "initial east relative velocity", r"v_{E0}"),
)



MODE_NOTES = {
    "Schuler": (
        "two channels, each on its own radius, and not a slip: the textbook formula "
        "takes one radius, √(R_M R_N), but this model's channel of the velocity error "
        "along north runs on the meridian radius R_M (the manual's R_N), ω_N² = g/R_M, "
        "and that along east on the prime-vertical radius R_N (the manual's R_E), "
        "ω_E² = g/R_N, at any track angle (g the vertical specific force a_ζ at rest). "
        "Coupled by the Foucault terms ±2Ω sin φ, their frequencies are the roots ω of "
        "(ω² − ω_N²)(ω² − ω_E²) = 4Ω² sin² φ ω², to 3e-5 at every latitude. At the "
        "equator the channels part: north about 2π√(R_M/g) = 84.28 min, east about "
        "2π√(R_N/g) = 84.57 min on the Krasovsky ellipsoid (−0.17 % and +0.17 % against "
        "the textbook; the rows' periods differ from these by that 3e-5, up to 0.003 "
        "min); within a few degrees of it the Foucault split outgrows the "
        "difference of the radii and the pair becomes the textbook ω̄ ± Ω|sin φ| (within "
        "0.01 % beyond about 14°); with e2 = 0 it is the textbook pair exactly (at the "
        "equator one Schuler row ×2)"),
}
"""Why this model's static-base modes differ from the textbook formulas of ``ins-errors
modes`` (:attr:`ins_errors.modeling.ModelDefinition.mode_notes`)."""


SOURCES = (
    # (1) initial levelling, (2) azimuth alignment
    error_source("initial_tilt_x", "rad", "arcsec", "initial", 1, r"\alpha_{x0}",
                 "initial platform levelling error about x"),
    error_source("initial_tilt_y", "rad", "arcsec", "initial", 1, r"\alpha_{y0}",
                 "initial platform levelling error about y"),
    error_source("initial_azimuth_error", "rad", "arcmin", "initial", 2, r"\alpha_{z0}",
                 "initial platform azimuth alignment error"),
    # (3) initial velocity
    error_source("initial_velocity_error_xi", "m/s", "m/s", "initial", 3, r"\Delta V_{\xi 0}",
                 "error of the initial computed velocity along ξ"),
    error_source("initial_velocity_error_eta", "m/s", "m/s", "initial", 3, r"\Delta V_{\eta 0}",
                 "error of the initial computed velocity along η"),
    # (4) initial coordinates; the computed trihedron's heading as well
    error_source("initial_latitude_error", "rad", "arcmin", "initial", 4, r"\Delta\varphi_0",
                 "error of the initial latitude set into the computer"),
    error_source("initial_longitude_error", "rad", "arcmin", "initial", 4, r"\Delta\lambda_0",
                 "error of the initial longitude set into the computer"),
    error_source("initial_heading_error", "rad", "arcmin", "initial", None, r"\Delta\chi_0",
                 "error of the initial track angle of the computed trihedron"),
    # (5) horizontal gyros, (6) azimuth gyro
    error_source("gyro_drift_x", "rad/s", "deg/h", "constant", 5, r"\omega_{dx}",
                 "constant drift rate of the gyro about platform axis x"),
    error_source("gyro_drift_y", "rad/s", "deg/h", "constant", 5, r"\omega_{dy}",
                 "constant drift rate of the gyro about platform axis y"),
    error_source("gyro_drift_z", "rad/s", "deg/h", "constant", 6, r"\omega_{dz}",
                 "constant drift rate of the azimuth gyro"),
    # (7) accelerometer zero offsets
    error_source("accel_bias_x", "m/s**2", "ug", "constant", 7, r"\Delta a_x",
                 "zero offset of the x accelerometer"),
    error_source("accel_bias_y", "m/s**2", "ug", "constant", 7, r"\Delta a_y",
                 "zero offset of the y accelerometer"),
    # (8) first (velocity) integrators: zero offset at the integrator input
    error_source("velocity_integrator_offset_xi", "m/s**2", "ug", "constant", 8, r"\delta_{1\xi}",
                 "zero offset of the first (velocity) integrator, ξ channel, at its input"),
    error_source("velocity_integrator_offset_eta", "m/s**2", "ug", "constant", 8, r"\delta_{1\eta}",
                 "zero offset of the first (velocity) integrator, η channel, at its input"),
    # (9) second integrators (relative rates -> direction cosines): rate offset
    error_source("position_integrator_offset_xi", "rad/s", "deg/h", "constant", 9,
                 r"\delta_{2\xi}",
                 "zero offset of the second integrator: rate added to ω'_ξ in the Poisson "
                 "equations"),
    error_source("position_integrator_offset_eta", "rad/s", "deg/h", "constant", 9,
                 r"\delta_{2\eta}",
                 "zero offset of the second integrator: rate added to ω'_η in the Poisson "
                 "equations"),
    # (10) accelerometer scale factors
    error_source("accel_scale_error_x", "1", "ppm", "constant", 10, r"k_{ax}",
                 "scale-factor (transfer coefficient) error of the x accelerometer"),
    error_source("accel_scale_error_y", "1", "ppm", "constant", 10, r"k_{ay}",
                 "scale-factor (transfer coefficient) error of the y accelerometer"),
    # (11) first-integrator gains, (12) second-integrator gains
    error_source("velocity_integrator_gain_error_xi", "1", "ppm", "constant", 11, r"k_{1\xi}",
                 "gain error of the first (velocity) integrator, ξ channel"),
    error_source("velocity_integrator_gain_error_eta", "1", "ppm", "constant", 11, r"k_{1\eta}",
                 "gain error of the first (velocity) integrator, η channel"),
    error_source("position_integrator_gain_error_xi", "1", "ppm", "constant", 12, r"k_{2\xi}",
                 "gain error of the second integrator on ω'_ξ"),
    error_source("position_integrator_gain_error_eta", "1", "ppm", "constant", 12, r"k_{2\eta}",
                 "gain error of the second integrator on ω'_η"),
    # (13) correction loop: commanded platform rates
    error_source("correction_gain_error_x", "1", "ppm", "constant", 13, r"k_{cx}",
                 "gain error of the correction (torquing) loop, platform axis x"),
    error_source("correction_gain_error_y", "1", "ppm", "constant", 13, r"k_{cy}",
                 "gain error of the correction (torquing) loop, platform axis y"),
    error_source("correction_gain_error_z", "1", "ppm", "constant", 13, r"k_{cz}",
                 "gain error of the correction (torquing) loop, azimuth axis z"),
)

_sym = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES, *PLATFORM_ANGLES)}
a, e2, U = _sym["a"], _sym["e2"], _sym["U"]


# --------------------------------------------------------------------------------------
# The computer (mechanisation algorithm)
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ComputerErrors:
    """Error terms inside the on-board computer (all zero in ideal work)."""

    velocity_offset: tuple[sp.Expr, sp.Expr] = (sp.S.Zero, sp.S.Zero)
    velocity_gain: tuple[sp.Expr, sp.Expr] = (sp.S.Zero, sp.S.Zero)
    position_offset: tuple[sp.Expr, sp.Expr] = (sp.S.Zero, sp.S.Zero)
    position_gain: tuple[sp.Expr, sp.Expr] = (sp.S.Zero, sp.S.Zero)


def reciprocal_radii(u11: sp.Expr, u21: sp.Expr, u31: sp.Expr, h: sp.Expr,
                     ecc2: sp.Expr = e2) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """1/R_ξ, 1/R_η, 1/R_o of the ellipsoid along the trihedron axes (manual)."""
    return ((1 - ecc2 * u31**2 / 2 + ecc2 * u11**2 - h / a) / a,
            (1 - ecc2 * u31**2 / 2 + ecc2 * u21**2 - h / a) / a,
            ecc2 * u11 * u21 / a)


def prime_vertical_radius(u31: sp.Expr, h: sp.Expr, ecc2: sp.Expr = e2) -> sp.Expr:
    """R_E = (a + h)/√(1 − e² sin²φ), as the manual writes it (sin φ = u31)."""
    return (a + h) / sp.sqrt(1 - ecc2 * u31**2)


def meridian_radius(u31: sp.Expr, h: sp.Expr, ecc2: sp.Expr = e2) -> sp.Expr:
    """R_N = (a + h)(1 − e²)/√(1 − e² sin²φ)³ (undefined in the manual; our choice)."""
    return (a + h) * (1 - ecc2) / (1 - ecc2 * u31**2) ** sp.Rational(3, 2)


def commanded_rates(eq: Mechanisation, s: list[sp.Symbol], h: sp.Symbol, ecc2: sp.Expr = e2):
    """Reciprocal radii and commanded absolute/relative rates of the trihedron.

    Returns
    -------
    omega, omega_rel : tuple of 3 sympy.Symbol
        (ω_ξ, ω_η, ω_ζ) and (ω'_ξ, ω'_η, ω'_ζ).
    """
    u11, u21, u31, _u12, _u22, _u32, V_xi, V_eta = s
    # 1/R_ξ, 1/R_η, 1/R_o of the ellipsoid along the trihedron axes
    radii = reciprocal_radii(u11, u21, u31, h, ecc2)
    inv_R_xi = eq.let("inv_R_xi", radii[0], r"R_\xi^{-1}")
    inv_R_eta = eq.let("inv_R_eta", radii[1], r"R_\eta^{-1}")
    inv_R_o = eq.let("inv_R_o", radii[2], r"R_o^{-1}")
    # commanded absolute rates; sin φ = u31
    omega_xi = eq.let("omega_xi", -(V_eta * inv_R_eta + V_xi * inv_R_o), r"\omega_\xi")
    omega_eta = eq.let("omega_eta", V_xi * inv_R_xi + V_eta * inv_R_o, r"\omega_\eta")
    omega_zeta = eq.let("omega_zeta", U * u31, r"\omega_\zeta")
    # relative rates ω' = ω − U·(u11, u21, u31)
    w_rel_xi = eq.let("omega_rel_xi", omega_xi - U * u11, r"\omega'_\xi")
    w_rel_eta = eq.let("omega_rel_eta", omega_eta - U * u21, r"\omega'_\eta")
    w_rel_zeta = eq.let("omega_rel_zeta", omega_zeta - U * u31, r"\omega'_\zeta")
    return (omega_xi, omega_eta, omega_zeta), (w_rel_xi, w_rel_eta, w_rel_zeta)


def computer(eq: Mechanisation, s: list[sp.Symbol], f_xi: sp.Expr, f_eta: sp.Expr,
             V_zeta: sp.Symbol, h: sp.Symbol, errors: ComputerErrors = ComputerErrors(),
             simplify: frozenset[str] = frozenset()):
    """The on-board algorithm: derivatives of (u11, u21, u31, u12, u22, u32, V_ξ, V_η).

    Parameters
    ----------
    eq : Mechanisation
        Where the intermediate quantities are recorded.
    s : list of sympy.Symbol
        The computer's state (true state in ideal work, computed state in real work).
    f_xi, f_eta : sympy.Expr
        Accelerations fed to the velocity integrators, m/s².
    V_zeta, h : sympy.Symbol
        Vertical velocity (m/s) and height (m), given from outside.
    errors : ComputerErrors
        Integrator offsets and gain errors (zero in ideal work).
    simplify : frozenset of str
        Simplified on-board formulas: ``"sphere"`` (e² = 0 in the radii), ``"no_coriolis"``
        (transport/Coriolis corrections W dropped), ``"no_gravity"`` (g' dropped).

    Returns
    -------
    rhs : list of sympy.Expr
        The eight state derivatives.
    omega : tuple of sympy.Symbol
        Commanded absolute rates (ω_ξ, ω_η, ω_ζ), rad/s, sent to the platform torquers.
    """
    u11, u21, u31, u12, u22, u32, V_xi, V_eta = s
    # methodological variants: "sphere" (e² = 0 on board), "no_coriolis", "no_gravity"
    ecc2 = sp.S.Zero if "sphere" in simplify else e2
    keep_W = sp.S.Zero if "no_coriolis" in simplify else sp.S.One
    keep_g = sp.S.Zero if "no_gravity" in simplify else sp.S.One
    omega, (w_xi, w_eta, w_zeta) = commanded_rates(eq, s, h, ecc2)
    omega_xi, omega_eta, omega_zeta = omega
    # rates as the second integrators see them (gain and zero offset)
    (k2x, k2y), (o2x, o2y) = errors.position_gain, errors.position_offset
    w_xi, w_eta = (1 + k2x) * w_xi + o2x, (1 + k2y) * w_eta + o2y
    # Poisson equations for two rows of the direction-cosine matrix
    du11 = w_zeta * u21 - w_eta * u31
    du21 = w_xi * u31 - w_zeta * u11
    du31 = w_eta * u11 - w_xi * u21
    du12 = w_zeta * u22 - w_eta * u32
    du22 = w_xi * u32 - w_zeta * u12
    du32 = w_eta * u12 - w_xi * u22
    # transport + Coriolis corrections and horizontal gravitation
    R_E = eq.let("R_E", prime_vertical_radius(u31, h, ecc2), "R_E")
    W_xi = eq.let("W_xi", keep_W * (omega_eta * V_zeta - omega_zeta * V_eta), r"W_\xi^{nk}")
    W_eta = eq.let("W_eta", keep_W * (omega_zeta * V_xi - omega_xi * V_zeta), r"W_\eta^{nk}")
    g_xi = eq.let("g_xi", keep_g * U**2 * R_E * u31 * u11, r"g'_\xi")
    g_eta = eq.let("g_eta", keep_g * U**2 * R_E * u31 * u21, r"g'_\eta")
    (k1x, k1y), (o1x, o1y) = errors.velocity_gain, errors.velocity_offset
    dV_xi = (1 + k1x) * (f_xi - W_xi + g_xi + o1x)
    dV_eta = (1 + k1y) * (f_eta - W_eta + g_eta + o1y)
    return [du11, du21, du31, du12, du22, du32, dV_xi, dV_eta], omega


def navigation_outputs(eq: Mechanisation, s: list[sp.Symbol], inputs: list[sp.Symbol]):
    """φ, λ, χ, ω_N, ω_E, v_N, v_E computed from a state (manual, end of section 2)."""
    u11, u21, u31, u12, u22, u32, _V_xi, _V_eta = s
    _a_xi, _a_eta, _a_zeta, _V_zeta, h = inputs
    _, (w_xi, w_eta, _w_zeta) = commanded_rates(eq, s, h)
    u33 = eq.let("u33", u11 * u22 - u12 * u21, "u_{33}")
    phi = eq.let("phi", sp.atan2(u31, sp.sqrt(1 - u31**2)), r"\varphi")
    lam = eq.let("lam", sp.atan2(-u32, u33), r"\lambda")
    chi = eq.let("chi", sp.atan2(u21, u11), r"\chi")
    omega_N = eq.let("omega_N", w_xi * sp.cos(chi) + w_eta * sp.sin(chi), r"\omega_N")
    omega_E = eq.let("omega_E", w_xi * sp.sin(chi) - w_eta * sp.cos(chi), r"\omega_E")
    R_E = eq.let("R_E", prime_vertical_radius(u31, h), "R_E")
    R_N = eq.let("R_N", meridian_radius(u31, h), "R_N")
    v_N = -omega_E * R_N
    v_E = omega_N * R_E
    return sp.Matrix([phi, lam, chi, omega_N, omega_E, v_N, v_E])


# --------------------------------------------------------------------------------------
# Initial conditions
# --------------------------------------------------------------------------------------
def direction_cosines(phi: sp.Expr, lam: sp.Expr, chi: sp.Expr) -> list[sp.Expr]:
    """u11, u21, u31, u12, u22, u32 of the trihedron at (φ, λ, χ) (manual's table)."""
    return [
        sp.cos(phi) * sp.cos(chi),
        sp.cos(phi) * sp.sin(chi),
        sp.sin(phi),
        -sp.cos(lam) * sp.sin(chi) + sp.sin(lam) * sp.cos(chi) * sp.sin(phi),
        sp.cos(lam) * sp.cos(chi) + sp.sin(lam) * sp.sin(chi) * sp.sin(phi),
        -sp.sin(lam) * sp.cos(phi),
    ]


def absolute_velocity(dc: list[sp.Expr], chi: sp.Expr, v_N: sp.Expr, v_E: sp.Expr,
                      h: sp.Expr) -> list[sp.Expr]:
    """V_ξ, V_η that make the mechanisation report relative velocity (v_N, v_E).

    Inverts the output equations v_N = −ω_E R_N, v_E = ω_N R_E and the linear relation
    between (V_ξ, V_η) and the commanded rates, so that a run started from these values
    is consistent with the model's own definitions.
    """
    u11, u21, u31 = dc[0], dc[1], dc[2]
    inv_R_xi, inv_R_eta, inv_R_o = reciprocal_radii(u11, u21, u31, h)
    omega_N = v_E / prime_vertical_radius(u31, h)
    omega_E = -v_N / meridian_radius(u31, h)
    w_rel_xi = omega_N * sp.cos(chi) + omega_E * sp.sin(chi)
    w_rel_eta = omega_N * sp.sin(chi) - omega_E * sp.cos(chi)
    # [ω_ξ, ω_η] = M [V_ξ, V_η]
    M = sp.Matrix([[-inv_R_o, -inv_R_eta], [inv_R_xi, inv_R_o]])
    rhs = sp.Matrix([w_rel_xi + U * u11, w_rel_eta + U * u21])
    V = M.adjugate() * rhs / M.det()
    return [V[0], V[1]]


# --------------------------------------------------------------------------------------
# Assembly: ideal work, real work
# --------------------------------------------------------------------------------------
def build(simplify: frozenset[str] = frozenset(), platform: str = "exact") -> ModelDefinition:
    """Assemble the symbolic definition of the orthodromic INS.

    ``simplify`` swaps the real-work computer for a simplified one (methodological
    studies, :mod:`ins_errors.studies.methodological`); empty for the registered model.
    ``platform`` is the form of the platform kinematics (``"exact"`` or the manual's
    ``"small_angle"``, :mod:`ins_errors.models.platform`); the exact definition also
    carries the small-angle real-work equations (``small_angle_rhs``).
    """
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    alpha = [v.symbol for v in PLATFORM_ANGLES]
    a_xi, a_eta, a_zeta, V_zeta, h = (v.symbol for v in INPUTS)
    w = _sym

    # Ideal work: the computer fed the true apparent accelerations.
    ideal = Mechanisation()
    ideal_rhs, omega = computer(ideal, x, a_xi, a_eta, V_zeta, h)

    # Real work. Instruments: accelerometers on the misaligned platform.
    a_x, a_y, _ = on_platform(alpha, (a_xi, a_eta, a_zeta), platform)
    f_x = (1 + w["accel_scale_error_x"]) * a_x + w["accel_bias_x"]
    f_y = (1 + w["accel_scale_error_y"]) * a_y + w["accel_bias_y"]
    # Computer fed the instrument outputs, with its integrator errors.
    real = Mechanisation(computed=True)
    errors = ComputerErrors(
        velocity_offset=(w["velocity_integrator_offset_xi"], w["velocity_integrator_offset_eta"]),
        velocity_gain=(w["velocity_integrator_gain_error_xi"],
                       w["velocity_integrator_gain_error_eta"]),
        position_offset=(w["position_integrator_offset_xi"], w["position_integrator_offset_eta"]),
        position_gain=(w["position_integrator_gain_error_xi"],
                       w["position_integrator_gain_error_eta"]),
    )
    computed_rhs, omega_cmd = computer(real, x_c, f_x, f_y, V_zeta, h, errors, simplify)
    # Platform: torqued by the commanded rates through the correction loop, plus drift,
    # relative to the true trihedron turning at ω.
    gains = (w["correction_gain_error_x"], w["correction_gain_error_y"],
             w["correction_gain_error_z"])
    drift = (w["gyro_drift_x"], w["gyro_drift_y"], w["gyro_drift_z"])
    torque = [(1 + k) * wc + d for k, wc, d in zip(gains, omega_cmd, drift, strict=True)]
    platform_rhs = platform_rates(alpha, torque, omega, platform)

    # Initial state: true, and as set into the real system.
    c = {v.name: v.symbol for v in INITIAL_CONDITIONS}
    phi0, lam0, chi0, vN0, vE0 = c.values()
    dc0 = direction_cosines(phi0, lam0, chi0)
    initial_state = sp.Matrix([*dc0, *absolute_velocity(dc0, chi0, vN0, vE0, h)])
    phi0c = phi0 + w["initial_latitude_error"]
    lam0c = lam0 + w["initial_longitude_error"]
    chi0c = chi0 + w["initial_heading_error"]
    dc0c = direction_cosines(phi0c, lam0c, chi0c)
    V0c = absolute_velocity(dc0c, chi0c, vN0, vE0, h)
    initial_real_state = sp.Matrix([
        *dc0c,
        V0c[0] + w["initial_velocity_error_xi"],
        V0c[1] + w["initial_velocity_error_eta"],
        w["initial_tilt_x"], w["initial_tilt_y"], w["initial_azimuth_error"],
    ])

    return ModelDefinition(
        name="orthodromic",
        title="Orthodromic gyro-stabilised-platform INS",
        source="000: KPI lab manual 'Study of the algorithm and errors of an INS' (2010)",
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
        small_angle_rhs=(build(simplify, "small_angle").real_rhs if platform == "exact"
                         else None),
        output_map=navigation_outputs,
        initial_state=initial_state,
        initial_real_state=initial_real_state,
        groups=(
            ("Platform misalignment", ["alpha_x", "alpha_y", "alpha_z"]),
            ("Velocity errors", ["delta_V_xi", "delta_V_eta"]),
            ("Direction-cosine errors", [f"delta_{n}" for n in DIRECTION_COSINES]),
        ),
        domain=(
            (1 - x[2] ** 2 - 1e-12, "latitude at ±90° (|u31| = 1): the formulas divide by cos φ"),
            (a, "semi-major axis a must be positive"),
            (a + h, "a + h <= 0: the Earth radius plus height must be positive"),
            (1 - e2, "eccentricity squared must be below 1"),
        ),
        initial_domain=(
            (sp.cos(phi0) ** 2 - 1e-12,
             "initial latitude at ±90°: the formulas divide by cos φ"),
            (a, "semi-major axis a must be positive"),
            (a + h, "a + h <= 0: the Earth radius plus height must be positive"),
            (1 - e2, "eccentricity squared must be below 1"),
        ),
        notes=__doc__.split("Modelling choices", 1)[1].split(":", 1)[1].strip(),
        mode_notes=MODE_NOTES,
    )
