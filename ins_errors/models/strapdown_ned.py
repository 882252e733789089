r"""Strapdown INS in a local-level north-east-down (NED) frame on the WGS-84 ellipsoid.

The common modern inertial navigator: gyros and accelerometers fixed to the body, a
computer that integrates

* the attitude quaternion ``q`` of the body (b) relative to the local-level NED frame
  (n), scalar first, ``q̇ = ½ q ⊗ (0, ω_ib^b) − ½ (0, ω_in^n) ⊗ q`` with
  ``ω_in^n = ω_ie^n + ω_en^n`` (Earth rate plus transport rate); the direction-cosine
  matrix C_b^n is the quadratic form of ``q`` divided by |q|² (no small-angle shortcut
  anywhere);
* the ground velocity ``v^n = (v_N, v_E, v_D)``,
  ``v̇^n = C_b^n f^b − (2 ω_ie^n + ω_en^n) × v^n + (0, 0, γ(φ, h))``, γ the normal
  gravity of the ellipsoid with its height dependence;
* geodetic latitude, longitude and height, ``φ̇ = v_N / (R_N + h)``,
  ``λ̇ = v_E / ((R_E + h) cos φ)``, ``ḣ = −v_D``;
* a vertical channel with an optional second-order damping loop on an external height
  reference ``h_ref`` (a barometer): ``ḣ = −v_D − k₁ (h − h_ref)`` and
  ``v̇_D = ... + k₂ (h − h_ref)``. With ``k₁ = k₂ = 0`` (the default) the channel is
  undamped and diverges with the time constant √(R / 2g) ≈ 9.5 min, as physics says;
  ``k₁ = 2ζω₀``, ``k₂ = ω₀² + 2γ/R`` give a loop of natural frequency ω₀ and damping ζ.

Ideal work: this computer fed the true body rates ω_ib^b and specific force f^b (the
inputs). Real work: the same computer fed the IMU outputs
``ω̃ = (I + S_g + M_g) ω + b_g`` and ``f̃ = (I + S_a + M_a) f + b_a`` (scale factors S on
the diagonal, axis misalignments M off it, biases b), started from an initial state with
roll, pitch, heading, velocity and position errors. The error state is the difference of
the computed and the true state in the model's own coordinates: ``δq`` (4 components),
``δv^n``, ``δφ``, ``δλ``, ``δh``. The exact maps to the φ-angle, ψ-angle and modified
velocity-error conventions, and to position errors in NED metres, are in
:mod:`ins_errors.models.strapdown_conventions`.

Modelling choices (also printed at the top of ``generated/strapdown_ned/error_equations.md``):

* attitude as the quaternion q = (q0, q1, q2, q3) of body → NED, scalar first; the
  specific force is resolved with C_bⁿ = C(q) / |q|², C(q) the quadratic form of q: the
  exact direction cosines of a quaternion of any length, so a drift of |q| (a rectangle
  step grows it by (ωτ)²/4) does not leak into the velocities. |q| is a first integral of
  the continuous equations, so the error δq stays orthogonal to q (to first order) and
  carries three attitude degrees of freedom.
* gravity is normal gravity along the ellipsoid normal (no deflection of the vertical),
  Somigliana's formula continued to height h by the second-order series of NIMA
  TR8350.2 (4-3); the radii of curvature are those of the same ellipsoid.
* IMU errors: ω̃_i = (1 + s_i) ω_i + Σ_j m_ij ω_j (j ≠ i) + b_i for the gyros (and alike for the
  accelerometers), s the scale-factor error, m_ij the misalignment of sensor axis i
  towards body axis j, b the bias; all constant.
* initial errors: the computed start attitude is the quaternion of (roll + δroll,
  pitch + δpitch, heading + δheading) (Z-Y-X Euler angles), position errors are given in
  metres along north, east, down at the true start point (δφ = δN / (R_N + h),
  δλ = δE / ((R_E + h) cos φ), δh = −δD).
* outputs: latitude, longitude, height, v_N, v_E, v_D and roll = atan2(C32, C33),
  pitch = atan2(−C31, √(C32² + C33²)), heading = atan2(C21, C11).
"""

from __future__ import annotations

import sympy as sp

from ins_errors.modeling import (
    EARTH_RATE,
    ELLIPSOIDS,
    WGS84_EQUATORIAL_GRAVITY,
    WGS84_GRAVITY_M,
    WGS84_SOMIGLIANA_K,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    error_source,
    error_states_of,
    normal_gravity,
    radii_of_curvature,
)

# --------------------------------------------------------------------------------------
# Names (public API: keep stable)
# --------------------------------------------------------------------------------------
AXES = ("x", "y", "z")

STATES = (
    Variable("q0", "1", "attitude quaternion body → NED, scalar part", "q_0"),
    Variable("q1", "1", "attitude quaternion body → NED, first vector part", "q_1"),
    Variable("q2", "1", "attitude quaternion body → NED, second vector part", "q_2"),
    Variable("q3", "1", "attitude quaternion body → NED, third vector part", "q_3"),
    Variable("v_N", "m/s", "north ground velocity", "v_N"),
    Variable("v_E", "m/s", "east ground velocity", "v_E"),
    Variable("v_D", "m/s", "down ground velocity", "v_D"),
    Variable("lat", "rad", "geodetic latitude φ", r"\varphi"),
    Variable("lon", "rad", "longitude λ", r"\lambda"),
    Variable("h", "m", "height above the ellipsoid", "h"),
)
ERROR_STATES = error_states_of(STATES, ())
INPUTS = (
    *(Variable(f"omega_{a}", "rad/s", f"true angular rate ω_ib of the body about its {a} axis",
               rf"\omega_{a}") for a in AXES),
    *(Variable(f"f_{a}", "m/s**2", f"true specific force along the body {a} axis", f"f_{a}")
      for a in AXES),
    Variable("h_ref", "m", "external height reference of the damping loop (true height)",
             r"h_{\mathrm{ref}}"),
)
_WGS84 = ELLIPSOIDS["wgs84"]
LOOP_EXAMPLE = "a 300-s loop, damping 0.7"
"""What the damping gains' example values give (``ins-errors`` suggests them when the
undamped vertical channel grows)."""
PARAMETERS = (
    Parameter("a", "m", "semi-major axis of the ellipsoid", "a", _WGS84.semi_major_axis),
    Parameter("e2", "1", "first eccentricity squared", "e^{2}", _WGS84.eccentricity_squared),
    Parameter("U", "rad/s", "Earth rotation rate", r"\Omega", EARTH_RATE),
    Parameter("gamma_e", "m/s**2", "normal gravity on the equator", r"\gamma_e",
              WGS84_EQUATORIAL_GRAVITY),
    Parameter("gravity_k", "1", "Somigliana constant k of normal gravity", "k",
              WGS84_SOMIGLIANA_K),
    Parameter("gravity_m", "1", "ω²a²b/GM (height dependence of normal gravity)", "m",
              WGS84_GRAVITY_M),
    # the examples: a 300-s loop (ω₀ = 2π/300 s) with ζ = 0.7, k₁ = 2ζω₀, k₂ = ω₀² + 2g/R
    Parameter("k_h1", "1/s", "vertical damping loop: gain on ḣ (0: undamped)", "k_1", 0.0,
              damping_gain=True, example="0.0293/s", example_gives=LOOP_EXAMPLE),
    Parameter("k_h2", "1/s**2", "vertical damping loop: gain on v̇_D (0: undamped)", "k_2", 0.0,
              damping_gain=True, example="4.42e-4/s^2", example_gives=LOOP_EXAMPLE),
)
OUTPUTS = (
    Variable("latitude", "rad", "geodetic latitude", r"\varphi"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height above the ellipsoid", "h"),
    Variable("v_N", "m/s", "north ground velocity", "v_N"),
    Variable("v_E", "m/s", "east ground velocity", "v_E"),
    Variable("v_D", "m/s", "down ground velocity", "v_D"),
    Variable("roll", "rad", "roll angle (Z-Y-X Euler angles body → NED)", r"\gamma"),
    Variable("pitch", "rad", "pitch angle", r"\theta"),
    Variable("heading", "rad", "heading (true, from north towards east)", r"\psi"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial geodetic latitude", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    Variable("v_N0", "m/s", "initial north ground velocity", "v_{N0}"),
    Variable("v_E0", "m/s", "initial east ground velocity", "v_{E0}"),
    Variable("v_D0", "m/s", "initial down ground velocity", "v_{D0}"),
    Variable("roll", "rad", "initial roll", r"\gamma_0"),
    Variable("pitch", "rad", "initial pitch", r"\theta_0"),
    Variable("heading", "rad", "initial heading", r"\psi_0"),
)


MODE_NOTES = {
    "Schuler": (
        "not the textbook pair, and not a slip: the textbook formula leaves out the "
        "vertical channel and the ellipsoid. The Coriolis terms ±2Ω cos φ (δv_E ↔ δv_D) "
        "couple the unstable vertical channel (λ² = ∂γ/∂h) to the east channel and "
        "stiffen it by (2Ω cos φ)² ω_s²/(ω_s² + ∂γ/∂h) ≈ (2Ω cos φ)²/3, and each channel "
        "has its own radius: north ω_N² = g/R_M (meridian radius), east ω_E² = g/R_N + "
        "(2Ω cos φ)² ω_s²/(ω_s² + ∂γ/∂h) (prime vertical; ω_s² = g/√(R_M R_N)). Coupled by "
        "the Foucault terms ±2Ω sin φ, their frequencies are the roots ω of "
        "(ω² − ω_N²)(ω² − ω_E²) = 4Ω² sin² φ ω², which give this model's two Schuler "
        "periods (vertical channel undamped) to 6e-6 at every latitude (−0.050 % and "
        "−0.045 % against the textbook at 50°). Where the Foucault split outgrows the "
        "difference of the radii (|φ| ≥ 15°) that is ω̄ ± Ω|sin φ| with ω̄² = g/R + "
        "Ω² sin² φ + (2Ω cos φ)²/6, again to 6e-6 (2.6e-5 at 5°); at the equator the "
        "channels part, north 2π/ω_N and east 2π/ω_E"),
    "vertical channel": (
        "not √(R/2g), and not a slip: normal gravity falls with height at "
        "∂γ/∂h = (2γ/a)(1 + f + m − 2f sin² φ), not 2g/R (+0.35 % at 50°), and the "
        "Coriolis coupling with the east channel takes (2Ω cos φ)² ∂γ/∂h/(∂γ/∂h + g/R) "
        "≈ (2/3)(2Ω cos φ)² off λ²; together they give this model's λ to 1e-6 "
        "(−0.077 % in the time constant at 50°); with the damping gains k₁, k₂ set the "
        "channel is the loop's, not this"),
}
"""Why this model's static-base modes differ from the textbook formulas of ``ins-errors
modes`` (:attr:`ins_errors.modeling.ModelDefinition.mode_notes`)."""


def _imu_sources(sensor: str, unit: str, bias_display: str, latex: str, what: str):
    rows = [error_source(f"{sensor}_bias_{a}", unit, bias_display, "constant", None,
                         rf"b_{{{latex}{a}}}", f"constant bias of the {a} {what}")
            for a in AXES]
    rows += [error_source(f"{sensor}_scale_error_{a}", "1", "ppm", "constant", None,
                          rf"s_{{{latex}{a}}}", f"scale-factor error of the {a} {what}")
             for a in AXES]
    rows += [error_source(f"{sensor}_misalignment_{i}{j}", "rad", "arcsec", "constant", None,
                          rf"m_{{{latex}{i}{j}}}",
                          f"misalignment of the {i} {what} axis towards body axis {j}")
             for i in AXES for j in AXES if i != j]
    return rows


SOURCES = (
    *_imu_sources("gyro", "rad/s", "deg/h", "g", "gyro"),
    *_imu_sources("accel", "m/s**2", "ug", "a", "accelerometer"),
    error_source("initial_roll_error", "rad", "arcsec", "initial", None, r"\delta\gamma_0",
                 "error of the initial roll"),
    error_source("initial_pitch_error", "rad", "arcsec", "initial", None, r"\delta\theta_0",
                 "error of the initial pitch"),
    error_source("initial_heading_error", "rad", "arcmin", "initial", None, r"\delta\psi_0",
                 "error of the initial heading"),
    *(error_source(f"initial_velocity_error_{c}", "m/s", "m/s", "initial", None,
                   rf"\delta v_{{{c}0}}", f"error of the initial {name} velocity")
      for c, name in (("N", "north"), ("E", "east"), ("D", "down"))),
    *(error_source(f"initial_position_error_{c}", "m", "m", "initial", None,
                   rf"\delta r_{{{c}0}}", f"error of the initial position towards {name}, m")
      for c, name in (("N", "north"), ("E", "east"), ("D", "down"))),
)

_DEG_H, _ARCSEC, _G0 = 3.141592653589793 / 180 / 3600, 3.141592653589793 / 180 / 3600, 9.80665
_SIGN = {"x": 1.0, "y": -0.8, "z": 0.6}
NAVIGATION_GRADE: dict[str, float] = {
    **{f"gyro_bias_{a}": 0.01 * _DEG_H * s for a, s in _SIGN.items()},
    **{f"accel_bias_{a}": 50e-6 * _G0 * s for a, s in _SIGN.items()},
    **{f"gyro_scale_error_{a}": 50e-6 * s for a, s in _SIGN.items()},
    **{f"accel_scale_error_{a}": 100e-6 * s for a, s in _SIGN.items()},
    **{f"gyro_misalignment_{i}{j}": 5 * _ARCSEC * _SIGN[i] * (1 if i < j else -1)
       for i in AXES for j in AXES if i != j},
    **{f"accel_misalignment_{i}{j}": 10 * _ARCSEC * _SIGN[j] * (1 if i < j else -1)
       for i in AXES for j in AXES if i != j},
    "initial_roll_error": 20 * _ARCSEC, "initial_pitch_error": -20 * _ARCSEC,
    "initial_heading_error": 120 * _ARCSEC,
    "initial_velocity_error_N": 0.05, "initial_velocity_error_E": -0.04,
    "initial_velocity_error_D": 0.03,
    "initial_position_error_N": 5.0, "initial_position_error_E": -4.0,
    "initial_position_error_D": 3.0,
}
"""Every error source of a 1 nmi/h navigation-grade INS and its alignment (SI): gyro biases
0.01 deg/h, accelerometer biases 50 µg, scale factors 50 ppm (gyro) and 100 ppm
(accelerometer), misalignments 5 and 10 arcsec, initial roll/pitch 20 arcsec and
heading 2 arcmin, velocity 5 cm/s, position 5 m; signs mixed."""

SMALL_ERRORS: dict[str, float] = {name: value / 10 for name, value in NAVIGATION_GRADE.items()}
"""The "small errors" of the direct-vs-linear comparisons: a tenth of
:data:`NAVIGATION_GRADE`, every source at once."""

_sym = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES)}
a, e2, U = _sym["a"], _sym["e2"], _sym["U"]
k_h1, k_h2 = _sym["k_h1"], _sym["k_h2"]


# --------------------------------------------------------------------------------------
# Quaternion algebra
# --------------------------------------------------------------------------------------
def quaternion_product(p, r) -> list[sp.Expr]:
    """Hamilton product p ⊗ r of scalar-first quaternions."""
    p0, p1, p2, p3 = p
    r0, r1, r2, r3 = r
    return [p0 * r0 - p1 * r1 - p2 * r2 - p3 * r3,
            p0 * r1 + p1 * r0 + p2 * r3 - p3 * r2,
            p0 * r2 - p1 * r3 + p2 * r0 + p3 * r1,
            p0 * r3 + p1 * r2 - p2 * r1 + p3 * r0]


def direction_cosines(q) -> sp.Matrix:
    """C_b^n of a unit quaternion body → NED (scalar first)."""
    q0, q1, q2, q3 = q
    return sp.Matrix([
        [q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
        [2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)],
        [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2],
    ])


def euler_quaternion(roll, pitch, heading) -> list[sp.Expr]:
    """Quaternion body → NED of Z-Y-X Euler angles (heading, then pitch, then roll)."""
    cr, sr = sp.cos(roll / 2), sp.sin(roll / 2)
    cp, s_p = sp.cos(pitch / 2), sp.sin(pitch / 2)
    cy, sy = sp.cos(heading / 2), sp.sin(heading / 2)
    return [cr * cp * cy + sr * s_p * sy,
            sr * cp * cy - cr * s_p * sy,
            cr * s_p * cy + sr * cp * sy,
            cr * cp * sy - sr * s_p * cy]


# --------------------------------------------------------------------------------------
# The computer
# --------------------------------------------------------------------------------------
def computer(eq: Mechanisation, s, omega, f, h_ref) -> list[sp.Expr]:
    """Right-hand side of the NED strapdown mechanisation.

    Parameters
    ----------
    eq : Mechanisation
        Where the intermediate quantities are recorded.
    s : sequence of sympy.Symbol
        (q0, q1, q2, q3, v_N, v_E, v_D, lat, lon, h): true in ideal work, computed in
        real work.
    omega, f : sequence of sympy.Expr
        Body angular rate ω_ib^b (rad/s) and specific force f^b (m/s²) fed to the
        computer.
    h_ref : sympy.Symbol
        Height reference of the vertical damping loop, m.

    Returns
    -------
    list of sympy.Expr
        Time derivatives of ``s``.
    """
    q, (vN, vE, vD), (lat, _lon, h) = s[:4], s[4:7], s[7:]
    R_N_0, R_E_0 = radii_of_curvature(lat, a, e2, xp=sp)
    R_N = eq.let("R_N", R_N_0, "R_N")
    R_E = eq.let("R_E", R_E_0, "R_E")
    gamma = eq.let("gamma", normal_gravity(lat, h, a, e2, _sym["gamma_e"], _sym["gravity_k"],
                                           _sym["gravity_m"], xp=sp), "g")
    # Earth rate and transport rate in NED
    Om_N = eq.let("Omega_N", U * sp.cos(lat), r"\Omega_N")
    Om_D = eq.let("Omega_D", -U * sp.sin(lat), r"\Omega_D")
    rho_N = eq.let("rho_N", vE / (R_E + h), r"\rho_N")
    rho_E = eq.let("rho_E", -vN / (R_N + h), r"\rho_E")
    rho_D = eq.let("rho_D", -vE * sp.tan(lat) / (R_E + h), r"\rho_D")
    # attitude: q̇ = ½ q ⊗ ω_ib^b − ½ ω_in^n ⊗ q
    w_in = [0, Om_N + rho_N, rho_E, Om_D + rho_D]
    body = quaternion_product(q, [0, *omega])
    nav = quaternion_product(w_in, q)
    dq = [(b_k - n_k) / 2 for b_k, n_k in zip(body, nav, strict=True)]
    # velocity: specific force resolved in NED, Coriolis and transport terms, gravity
    C = direction_cosines(q)
    norm2 = eq.let("q_norm2", sum(component**2 for component in q), r"\left|q\right|^{2}")
    f_n = [eq.let(f"f_{c}", sum(C[i, j] * f[j] for j in range(3)) / norm2, f"f_{c}")
           for i, c in enumerate("NED")]
    cN, cE, cD = 2 * Om_N + rho_N, rho_E, 2 * Om_D + rho_D
    height_error = eq.let("delta_h_ref", h - h_ref, r"\delta h_{\mathrm{ref}}")
    dvN = f_n[0] - (cE * vD - cD * vE)
    dvE = f_n[1] - (cD * vN - cN * vD)
    dvD = f_n[2] - (cN * vE - cE * vN) + gamma + k_h2 * height_error
    # position
    dlat = vN / (R_N + h)
    dlon = vE / ((R_E + h) * sp.cos(lat))
    dh = -vD - k_h1 * height_error
    return [*dq, dvN, dvE, dvD, dlat, dlon, dh]


def navigation_outputs(eq: Mechanisation, s, inputs) -> sp.Matrix:
    """Latitude, longitude, height, v_N, v_E, v_D, roll, pitch, heading of a state."""
    q, (vN, vE, vD), (lat, lon, h) = s[:4], s[4:7], s[7:]
    C = direction_cosines(q)
    roll = sp.atan2(C[2, 1], C[2, 2])
    pitch = sp.atan2(-C[2, 0], sp.sqrt(C[2, 1] ** 2 + C[2, 2] ** 2))
    heading = sp.atan2(C[1, 0], C[0, 0])
    return sp.Matrix([lat, lon, h, vN, vE, vD, roll, pitch, heading])


def imu_outputs(sensor: str, true: list[sp.Symbol]) -> list[sp.Expr]:
    """Readings of a sensor triad: (I + S + M) true + bias, in error-source symbols."""
    out = []
    for i, ai in enumerate(AXES):
        value = (1 + _sym[f"{sensor}_scale_error_{ai}"]) * true[i] + _sym[f"{sensor}_bias_{ai}"]
        for j, aj in enumerate(AXES):
            if i != j:
                value += _sym[f"{sensor}_misalignment_{ai}{aj}"] * true[j]
        out.append(value)
    return out


# --------------------------------------------------------------------------------------
# Assembly
# --------------------------------------------------------------------------------------
def build() -> ModelDefinition:
    """Assemble the symbolic definition of the NED strapdown INS."""
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    omega = [_sym[f"omega_{c}"] for c in AXES]
    f = [_sym[f"f_{c}"] for c in AXES]
    h_ref = _sym["h_ref"]

    ideal = Mechanisation()
    ideal_rhs = computer(ideal, x, omega, f, h_ref)
    real = Mechanisation(computed=True)
    real_rhs = computer(real, x_c, imu_outputs("gyro", omega), imu_outputs("accel", f), h_ref)

    lat0, lon0, h0, vN0, vE0, vD0, roll0, pitch0, heading0 = (
        v.symbol for v in INITIAL_CONDITIONS)
    x0 = [*euler_quaternion(roll0, pitch0, heading0), vN0, vE0, vD0, lat0, lon0, h0]
    R_N0, R_E0 = radii_of_curvature(lat0, a, e2, xp=sp)
    w = _sym
    xr0 = [*euler_quaternion(roll0 + w["initial_roll_error"], pitch0 + w["initial_pitch_error"],
                             heading0 + w["initial_heading_error"]),
           vN0 + w["initial_velocity_error_N"], vE0 + w["initial_velocity_error_E"],
           vD0 + w["initial_velocity_error_D"],
           lat0 + w["initial_position_error_N"] / (R_N0 + h0),
           lon0 + w["initial_position_error_E"] / ((R_E0 + h0) * sp.cos(lat0)),
           h0 - w["initial_position_error_D"]]
    C = direction_cosines(x[:4])
    q_norm = sum(v**2 for v in x[:4])

    return ModelDefinition(
        name="strapdown_ned",
        title="Strapdown INS, local-level NED mechanisation on the WGS-84 ellipsoid",
        source="textbook strapdown mechanisation (Titterton & Weston, 'Strapdown inertial "
               "navigation technology', ch. 3; Savage, 'Strapdown analytics')",
        states=STATES,
        error_states=ERROR_STATES,
        real_states=x_c,
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal,
        real=real,
        ideal_rhs=sp.Matrix(ideal_rhs),
        real_rhs=sp.Matrix(real_rhs),
        output_map=navigation_outputs,
        initial_state=sp.Matrix(x0),
        initial_real_state=sp.Matrix(xr0),
        groups=(
            ("Attitude quaternion errors", ["delta_q0", "delta_q1", "delta_q2", "delta_q3"]),
            ("Velocity errors", ["delta_v_N", "delta_v_E", "delta_v_D"]),
            ("Position errors", ["delta_lat", "delta_lon", "delta_h"]),
        ),
        domain=(
            (sp.cos(x[7]) ** 2 - 1e-12, "latitude at ±90°: λ̇ divides by cos φ"),
            ((C[2, 1] ** 2 + C[2, 2] ** 2) - 1e-12 * q_norm**2,
             "pitch at ±90°: roll and heading are undefined"),
            (q_norm - 1e-6, "attitude quaternion of zero length"),
            (a, "a <= 0: the semi-major axis must be positive"),
            (1 - e2, "eccentricity squared must be below 1"),
            (_sym["gamma_e"], "normal gravity on the equator gamma_e must be positive"),
        ),
        initial_domain=(
            (sp.cos(lat0) ** 2 - 1e-12, "initial latitude at ±90°: longitude is undefined"),
            (sp.cos(pitch0) ** 2 - 1e-12, "initial pitch at ±90°: roll and heading are "
                                          "undefined"),
            (a, "a <= 0: the semi-major axis must be positive"),
            (1 - e2, "eccentricity squared must be below 1"),
            (_sym["gamma_e"], "normal gravity on the equator gamma_e must be positive"),
        ),
        mode_notes=MODE_NOTES,
        notes=__doc__.split("Modelling choices", 1)[1].split(":", 1)[1].strip(),
    )
