r"""A strapdown INS mechanised in the Earth-fixed frame (ECEF), written as a model file.

The navigation equations of P. D. Groves, *Principles of GNSS, Inertial, and Multisensor
Integrated Navigation Systems*, 2nd ed., Artech House, 2013, section 5.3 (Earth-frame
navigation equations), in continuous time:

    Ċ_b^e = C_b^e [ω_ib^b×] − [ω_ie^e×] C_b^e                    attitude, body → ECEF
    v̇^e  = C_b^e f_ib^b + γ^e(r^e) − ω_ie^e × (ω_ie^e × r^e) − 2 ω_ie^e × v^e
    ṙ^e  = v^e

with ω_ie^e = (0, 0, ω_ie), the body axes forward-right-down, and γ^e the gravitation
of a point mass with the J2 term (Groves, chapter 2):

    γ^e = −μ/|r|³ (x (1 + k (1 − 5 z²/|r|²)), y (1 + k (1 − 5 z²/|r|²)),
                   z (1 + k (3 − 5 z²/|r|²))),       k = 3/2 J2 a² / |r|²

Its states are the nine entries of C_b^e, the ECEF velocity and the ECEF position. Its
outputs are the navigation solution a user reads: geodetic latitude and height on the
WGS-84 ellipsoid from r^e by Bowring's formula (one step from the parametric latitude θ),

    p = √(x² + y²),  b = a √(1 − e²),  e'² = e² / (1 − e²),  θ = atan2(a z, b p)
    φ = atan2(z + e'² b sin³θ, p − e² a cos³θ),   h = p cos φ + z sin φ − a √(1 − e² sin²φ)

the longitude λ = atan2(y, x), the NED velocity C_e^n v^e and the roll, pitch and heading
of C_b^n = C_e^n C_b^e. With these outputs, the inputs ω_x..z, f_x..z and the Earth's
``a`` and ``e2`` among its parameters it describes itself as a strapdown INS: it flies
the strapdown motions and has the φ/ψ conventions, ``psi_ecef`` (Groves' ψ^e, δv^e, δr^e)
among them (``ins-errors models`` says so). Its error sources are the gyro and
accelerometer biases: the real work is the same computer fed ω + b_g and f + b_a.
"""

from __future__ import annotations

import sympy as sp

from ins_errors.modeling import (
    EARTH_RATE,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    error_source,
    error_states_of,
)

BODY = "xyz"
ECEF = "XYZ"
STATES = (
    *(Variable(f"C{e}{b}", "1", f"C_b^e entry {e}{b}", f"C_{{{e}{b}}}")
      for e in ECEF for b in BODY),
    *(Variable(f"v_{e}", "m/s", f"ECEF velocity {e}", f"v_{e}") for e in ECEF),
    *(Variable(f"r_{e}", "m", f"ECEF position {e}", f"r_{e}") for e in ECEF),
)
INPUTS = (
    *(Variable(f"omega_{b}", "rad/s", f"body rate about {b}", rf"\omega_{b}") for b in BODY),
    *(Variable(f"f_{b}", "m/s**2", f"specific force along {b}", f"f_{b}") for b in BODY),
)
PARAMETERS = (
    Parameter("a", "m", "WGS-84 semi-major axis", "a", 6_378_137.0),
    Parameter("e2", "1", "WGS-84 first eccentricity squared", "e^2", 6.69437999014e-3),
    Parameter("mu", "m**3/s**2", "Earth's gravitational constant", r"\mu", 3.986004418e14),
    Parameter("J2", "1", "second zonal harmonic of the gravity field", "J_2", 1.082627e-3),
    Parameter("omega_ie", "rad/s", "Earth rate", r"\omega_{ie}", EARTH_RATE),
)
SOURCES = (
    *(error_source(f"gyro_bias_{b}", "rad/s", "deg/h", "constant", None, rf"b_{{g{b}}}",
                   f"bias of the {b} gyro") for b in BODY),
    *(error_source(f"accel_bias_{b}", "m/s**2", "ug", "constant", None, rf"b_{{a{b}}}",
                   f"bias of the {b} accelerometer") for b in BODY),
)
ANGLES = (("roll", r"\gamma"), ("pitch", r"\theta"), ("heading", r"\psi"))
OUTPUTS = (
    Variable("latitude", "rad", "geodetic latitude (Bowring)", r"\varphi"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height above the ellipsoid", "h"),
    *(Variable(f"v_{d}", "m/s", f"{word} velocity", f"v_{d}")
      for d, word in (("N", "north"), ("E", "east"), ("D", "down"))),
    *(Variable(name, "rad", name, latex) for name, latex in ANGLES),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial geodetic latitude", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    *(Variable(f"v_{d}0", "m/s", f"initial {d} velocity", f"v_{{{d}0}}") for d in "NED"),
    *(Variable(name, "rad", f"initial {name}", f"{latex}_0") for name, latex in ANGLES),
)
S = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES,
                                 *INITIAL_CONDITIONS)}
a, e2, mu, J2, omega_ie = (S[p.name] for p in PARAMETERS)
EARTH = sp.Matrix([0, 0, omega_ie])


def skew(w) -> sp.Matrix:
    """[w×], the matrix of the cross product w × (·)."""
    return sp.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def ned_to_ecef(lat, lon) -> sp.Matrix:
    """C_n^e at geodetic latitude and longitude (north, east, down → X, Y, Z)."""
    sl, cl, so, co = sp.sin(lat), sp.cos(lat), sp.sin(lon), sp.cos(lon)
    return sp.Matrix([[-sl * co, -so, -cl * co], [-sl * so, co, -cl * so], [cl, 0, -sl]])


def body_to_ned(roll, pitch, heading) -> sp.Matrix:
    """C_b^n of z-y-x Euler angles (heading, then pitch, then roll)."""
    cr, sr = sp.cos(roll), sp.sin(roll)
    cp, sp_ = sp.cos(pitch), sp.sin(pitch)
    ch, sh = sp.cos(heading), sp.sin(heading)
    return (sp.Matrix([[ch, -sh, 0], [sh, ch, 0], [0, 0, 1]])
            * sp.Matrix([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
            * sp.Matrix([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))


def navigator(eq: Mechanisation, state, rate, force) -> list:
    """Ċ_b^e, v̇^e, ṙ^e of the on-board computer (section 5.3)."""
    C = sp.Matrix(3, 3, list(state[:9]))
    v, r = sp.Matrix(state[9:12]), sp.Matrix(state[12:15])
    size = eq.let("r", sp.sqrt(r.dot(r)), "|r|")
    k = eq.let("k", sp.Rational(3, 2) * J2 * a**2 / size**2, "k")
    zeta = eq.let("zeta", 5 * r[2]**2 / size**2, r"\zeta")
    gravitation = -mu / size**3 * sp.Matrix([r[0] * (1 + k * (1 - zeta)),
                                             r[1] * (1 + k * (1 - zeta)),
                                             r[2] * (1 + k * (3 - zeta))])
    C_dot = C * skew(rate) - skew(EARTH) * C
    v_dot = C * sp.Matrix(force) + gravitation - EARTH.cross(EARTH.cross(r)) \
        - 2 * EARTH.cross(v)
    return [*C_dot, *v_dot, *v]


def navigation_solution(eq: Mechanisation, state, inputs) -> sp.Matrix:
    """Geodetic latitude (Bowring), longitude, height, NED velocity, roll, pitch, heading."""
    C = sp.Matrix(3, 3, list(state[:9]))
    v = sp.Matrix(state[9:12])
    x, y, z = state[12:15]
    p = sp.sqrt(x**2 + y**2)
    b = a * sp.sqrt(1 - e2)
    theta = sp.atan2(z * a, p * b)
    lat = sp.atan2(z + e2 / (1 - e2) * b * sp.sin(theta)**3, p - e2 * a * sp.cos(theta)**3)
    lon = sp.atan2(y, x)
    h = p * sp.cos(lat) + z * sp.sin(lat) - a * sp.sqrt(1 - e2 * sp.sin(lat)**2)
    ecef_to_ned = ned_to_ecef(lat, lon).T
    v_n, C_bn = ecef_to_ned * v, ecef_to_ned * C
    return sp.Matrix([lat, lon, h, *v_n, sp.atan2(C_bn[2, 1], C_bn[2, 2]),
                      sp.asin(-C_bn[2, 0]), sp.atan2(C_bn[1, 0], C_bn[0, 0])])


def initial_state() -> sp.Matrix:
    """C_b^e, v^e, r^e from the geodetic position, NED velocity and Euler angles."""
    lat, lon, h = S["latitude"], S["longitude"], S["height"]
    N = a / sp.sqrt(1 - e2 * sp.sin(lat)**2)  # radius of curvature in the prime vertical
    r = [(N + h) * sp.cos(lat) * sp.cos(lon), (N + h) * sp.cos(lat) * sp.sin(lon),
         (N * (1 - e2) + h) * sp.sin(lat)]
    C_ne = ned_to_ecef(lat, lon)
    v = C_ne * sp.Matrix([S["v_N0"], S["v_E0"], S["v_D0"]])
    C = C_ne * body_to_ned(S["roll"], S["pitch"], S["heading"])
    return sp.Matrix([*C, *v, *r])


def build() -> ModelDefinition:
    """The ECEF INS as ideal work (true instrument outputs) and real work (biased)."""
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    rate = [S[f"omega_{b}"] for b in BODY]
    force = [S[f"f_{b}"] for b in BODY]
    gyros = [w + S[f"gyro_bias_{b}"] for w, b in zip(rate, BODY, strict=True)]
    accels = [f + S[f"accel_bias_{b}"] for f, b in zip(force, BODY, strict=True)]
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    start = initial_state()
    return ModelDefinition(
        name="ecef_strapdown", title="Strapdown INS in ECEF (WGS-84, point mass + J2)",
        source="Groves 2013, section 5.3 (Earth-frame navigation equations)",
        states=STATES, error_states=error_states_of(STATES, ()), real_states=x_c,
        inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES, outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=sp.Matrix(navigator(ideal, x, rate, force)),
        real_rhs=sp.Matrix(navigator(real, x_c, gyros, accels)),
        output_map=navigation_solution, initial_state=start, initial_real_state=start,
        domain=((x[12]**2 + x[13]**2 - 1.0, "on the polar axis"),),
        initial_domain=((sp.cos(S["latitude"])**2 - 1e-12, "initial latitude at a pole"),),
    )
