r"""A researcher's own strapdown INS, a model file as a new user wrote it: ENU navigation
frame, RFU body axes, quaternion attitude, WGS-84 ellipsoid, Somigliana normal gravity
with inverse-square height dependence, barometer-damped vertical channel (gains c_1, c_2
flagged as damping gains, 0 by default), gyro/accel biases and scale factors, baro bias.

    q̇ = ½ q ⊗ (0, ω_ib^b) − ½ (0, ω_in^n) ⊗ q          (body RFU → ENU, scalar first)
    ω_ie^n = U (0, cos φ, sin φ)
    ω_en^n = (−v_N/(R_N+h), v_E/(R_E+h), v_E tan φ/(R_E+h))
    v̇ = C f − (2ω_ie + ω_en) × v + (0, 0, −γ) − (0, 0, c_2 (h − h_ref))
    φ̇ = v_N/(R_N+h), λ̇ = v_E/((R_E+h) cos φ), ḣ = v_U − c_1 (h − h_ref)
    γ = γ_e (1 + k sin²φ)/√(1 − e² sin²φ) · (a/(a+h))²
"""

from __future__ import annotations

import sympy as sp

from ins_errors.modeling import (
    EARTH_RATE,
    ELLIPSOIDS,
    WGS84_EQUATORIAL_GRAVITY,
    WGS84_SOMIGLIANA_K,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    error_source,
    error_states_of,
    radii_of_curvature,
)

AXES = "xyz"   # x right, y forward, z up (RFU)
W = ELLIPSOIDS["wgs84"]

STATES = (
    Variable("q0", "1", "quaternion RFU->ENU scalar", "q_0"),
    Variable("q1", "1", "quaternion vector 1", "q_1"),
    Variable("q2", "1", "quaternion vector 2", "q_2"),
    Variable("q3", "1", "quaternion vector 3", "q_3"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_U", "m/s", "up velocity", "v_U"),
    Variable("lat", "rad", "geodetic latitude", r"\varphi"),
    Variable("lon", "rad", "longitude", r"\lambda"),
    Variable("h", "m", "height", "h"),
)
INPUTS = (
    *(Variable(f"omega_{a}", "rad/s", f"body rate about {a} (RFU)", rf"\omega_{a}") for a in AXES),
    *(Variable(f"f_{a}", "m/s**2", f"specific force along {a} (RFU)", f"f_{a}") for a in AXES),
    Variable("h_ref", "m", "barometric height (true height in ideal work)", r"h_{b}"),
)
PARAMETERS = (
    Parameter("a", "m", "WGS-84 semi-major axis", "a", W.semi_major_axis),
    Parameter("e2", "1", "WGS-84 eccentricity squared", "e^2", W.eccentricity_squared),
    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),
    Parameter("gamma_e", "m/s**2", "equatorial normal gravity", r"\gamma_e",
              WGS84_EQUATORIAL_GRAVITY),
    Parameter("gk", "1", "Somigliana k", "k", WGS84_SOMIGLIANA_K),
    Parameter("c_1", "1/s", "baro loop gain on dh/dt", "c_1", 0.0,
              damping_gain=True, example="0.0293/s", example_gives="a 300-s loop"),
    Parameter("c_2", "1/s**2", "baro loop gain on dv_U/dt", "c_2", 0.0,
              damping_gain=True, example="4.42e-4/s^2", example_gives="a 300-s loop"),
)
SOURCES = (
    *(error_source(f"gyro_bias_{a}", "rad/s", "deg/h", "constant", None, rf"b_{{g{a}}}",
                   f"bias of the {a} gyro") for a in AXES),
    *(error_source(f"gyro_scale_{a}", "1", "ppm", "constant", None, rf"s_{{g{a}}}",
                   f"scale-factor error of the {a} gyro") for a in AXES),
    *(error_source(f"accel_bias_{a}", "m/s**2", "ug", "constant", None, rf"b_{{a{a}}}",
                   f"bias of the {a} accelerometer") for a in AXES),
    *(error_source(f"accel_scale_{a}", "1", "ppm", "constant", None, rf"s_{{a{a}}}",
                   f"scale-factor error of the {a} accelerometer") for a in AXES),
    error_source("baro_bias", "m", "m", "constant", None, r"b_h", "barometer bias"),
    error_source("initial_heading_error", "rad", "arcmin", "initial", None, r"\delta\psi_0",
                 "initial heading error"),
    error_source("initial_tilt_error", "rad", "arcsec", "initial", None, r"\delta\theta_0",
                 "initial pitch error"),
)
ANGLES = (("roll", r"\gamma"), ("pitch", r"\theta"), ("heading", r"\psi"))
OUTPUTS = (
    Variable("latitude", "rad", "latitude", r"\varphi"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height", "h"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_U", "m/s", "up velocity", "v_U"),
    *(Variable(n, "rad", n, tex) for n, tex in ANGLES),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_U0", "m/s", "initial up velocity", "v_{U0}"),
    *(Variable(n, "rad", f"initial {n}", f"{tex}_0") for n, tex in ANGLES),
)
S = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES, *INITIAL_CONDITIONS)}


def qmul(p, r):
    p0, p1, p2, p3 = p
    r0, r1, r2, r3 = r
    return [p0 * r0 - p1 * r1 - p2 * r2 - p3 * r3,
            p0 * r1 + p1 * r0 + p2 * r3 - p3 * r2,
            p0 * r2 - p1 * r3 + p2 * r0 + p3 * r1,
            p0 * r3 + p1 * r2 - p2 * r1 + p3 * r0]


def dcm(q):
    q0, q1, q2, q3 = q
    return sp.Matrix([
        [q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
        [2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)],
        [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2]])


def euler_q(roll, pitch, heading):
    """C_b^n = Rz(−ψ) Rx(θ) Ry(γ) for RFU body, ENU nav."""
    qz = [sp.cos(-heading / 2), 0, 0, sp.sin(-heading / 2)]
    qx = [sp.cos(pitch / 2), sp.sin(pitch / 2), 0, 0]
    qy = [sp.cos(roll / 2), 0, sp.sin(roll / 2), 0]
    return qmul(qmul(qz, qx), qy)


def computer(eq, s, omega, f, h_ref):
    a, e2, U = S["a"], S["e2"], S["U"]
    q, (vE, vN, vU), (lat, _lon, h) = s[:4], s[4:7], s[7:]
    RN0, RE0 = radii_of_curvature(lat, a, e2, xp=sp)
    RN = eq.let("R_N", RN0, "R_N")
    RE = eq.let("R_E", RE0, "R_E")
    s2 = sp.sin(lat) ** 2
    gamma = eq.let("gamma", S["gamma_e"] * (1 + S["gk"] * s2) / sp.sqrt(1 - e2 * s2)
                   * (a / (a + h)) ** 2, r"\gamma")
    wie = [0, U * sp.cos(lat), U * sp.sin(lat)]
    wen = [eq.let("rho_E", -vN / (RN + h), r"\rho_E"),
           eq.let("rho_N", vE / (RE + h), r"\rho_N"),
           eq.let("rho_U", vE * sp.tan(lat) / (RE + h), r"\rho_U")]
    win = [wie[i] + wen[i] for i in range(3)]
    body = qmul(q, [0, *omega])
    nav = qmul([0, *win], q)
    dq = [(b - n) / 2 for b, n in zip(body, nav, strict=True)]
    C = dcm(q)
    n2 = sum(c**2 for c in q)
    fn = [eq.let(f"f_{c}", sum(C[i, j] * f[j] for j in range(3)) / n2, f"f_{c}")
          for i, c in enumerate("ENU")]
    cor = sp.Matrix([2 * wie[i] + wen[i] for i in range(3)]).cross(sp.Matrix([vE, vN, vU]))
    dh_err = eq.let("dh_baro", h - h_ref, r"\delta h_b")
    dvE = fn[0] - cor[0]
    dvN = fn[1] - cor[1]
    dvU = fn[2] - cor[2] - gamma - S["c_2"] * dh_err
    return [*dq, dvE, dvN, dvU, vN / (RN + h), vE / ((RE + h) * sp.cos(lat)),
            vU - S["c_1"] * dh_err]


def output_map(eq, s, inputs):
    C = dcm(s[:4])
    vE, vN, vU, lat, lon, h = s[4:]
    return sp.Matrix([lat, lon, h, vE, vN, vU, sp.atan2(-C[2, 0], C[2, 2]),
                      sp.asin(C[2, 1]), sp.atan2(C[0, 1], C[1, 1])])


def build():
    x = [v.symbol for v in STATES]
    xc = computed_symbols(STATES)
    om = [S[f"omega_{a}"] for a in AXES]
    fb = [S[f"f_{a}"] for a in AXES]
    gyr = [(1 + S[f"gyro_scale_{a}"]) * w + S[f"gyro_bias_{a}"]
           for w, a in zip(om, AXES, strict=True)]
    acc = [(1 + S[f"accel_scale_{a}"]) * v + S[f"accel_bias_{a}"]
           for v, a in zip(fb, AXES, strict=True)]
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    ideal_rhs = sp.Matrix(computer(ideal, x, om, fb, S["h_ref"]))
    real_rhs = sp.Matrix(computer(real, xc, gyr, acc, S["h_ref"] + S["baro_bias"]))
    c = S
    x0 = sp.Matrix([*euler_q(c["roll"], c["pitch"], c["heading"]), c["v_E0"], c["v_N0"],
                    c["v_U0"], c["latitude"], c["longitude"], c["height"]])
    xr0 = sp.Matrix([*euler_q(c["roll"], c["pitch"] + c["initial_tilt_error"],
                              c["heading"] + c["initial_heading_error"]),
                     c["v_E0"], c["v_N0"], c["v_U0"], c["latitude"], c["longitude"], c["height"]])
    return ModelDefinition(
        name="enu_baro_strapdown",
        title="ENU/RFU quaternion strapdown INS, WGS-84, baro-damped",
        source="own", states=STATES, error_states=error_states_of(STATES, ()),
        real_states=xc, inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES,
        outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=ideal_rhs, real_rhs=real_rhs, output_map=output_map,
        initial_state=x0, initial_real_state=xr0,
        domain=((sp.cos(x[7]) ** 2 - 1e-12, "latitude at a pole"),),
        initial_domain=((sp.cos(c["latitude"]) ** 2 - 1e-12, "initial latitude at a pole"),),
    )
