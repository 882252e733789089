r"""Test fixture: a strapdown INS mechanised in the Earth-fixed frame (ECEF), as Groves
(2013, section 5.3) writes it, on a sphere of radius R with point-mass gravity.

    Ċ_b^e = C_b^e [ω_ib^b×] − [Ω_ie^e×] C_b^e           (body FRD → ECEF)
    v̇^e  = C_b^e f^b + g^e(r) − 2 Ω_ie^e × v^e
    ṙ^e  = v^e
    g^e  = −μ r / |r|³ − Ω_ie^e × (Ω_ie^e × r),  Ω_ie^e = (0, 0, U)

Its navigation outputs are geocentric latitude and longitude, height over the sphere,
NED velocity and roll, pitch, heading of C_b^n = C_e^n C_b^e: it describes itself, so the
φ/ψ conventions and the Earth-fixed convention ``psi_ecef`` carry it. Gyro and
accelerometer biases are its error sources.
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

AXES = "xyz"
ENTRIES = [f"C{row}{col}" for row in "XYZ" for col in AXES]
STATES = (
    *(Variable(e, "1", f"C_b^e entry {e[1]}/{e[2]}", f"C_{{{e[1]}{e[2]}}}") for e in ENTRIES),
    *(Variable(f"v_{k}", "m/s", f"ECEF velocity {k}", f"v_{k}") for k in "XYZ"),
    *(Variable(f"r_{k}", "m", f"ECEF position {k}", f"r_{k}") for k in "XYZ"),
)
INPUTS = (
    *(Variable(f"omega_{a}", "rad/s", f"body rate about {a}", rf"\omega_{a}") for a in AXES),
    *(Variable(f"f_{a}", "m/s**2", f"specific force along {a}", f"f_{a}") for a in AXES),
)
PARAMETERS = (
    Parameter("R", "m", "radius of the spherical Earth", "R", 6_371_000.0),
    Parameter("mu", "m**3/s**2", "Earth's gravitational constant", r"\mu", 3.986004418e14),
    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),
)
SOURCES = (
    *(error_source(f"gyro_bias_{a}", "rad/s", "deg/h", "constant", None, rf"b_{{g{a}}}",
                   f"bias of the {a} gyro") for a in AXES),
    *(error_source(f"accel_bias_{a}", "m/s**2", "ug", "constant", None, rf"b_{{a{a}}}",
                   f"bias of the {a} accelerometer") for a in AXES),
)
ANGLES = (("roll", r"\gamma"), ("pitch", r"\theta"), ("heading", r"\psi"))
OUTPUTS = (
    Variable("latitude", "rad", "geocentric latitude", r"\varphi"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height above the sphere", "h"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_D", "m/s", "down velocity", "v_D"),
    *(Variable(name, "rad", name, latex) for name, latex in ANGLES),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
    Variable("v_D0", "m/s", "initial down velocity", "v_{D0}"),
    *(Variable(name, "rad", f"initial {name}", f"{latex}_0") for name, latex in ANGLES),
)
SYMBOL = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES,
                                      *INITIAL_CONDITIONS)}


def cross_matrix(w) -> sp.Matrix:
    return sp.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def ecef_to_ned(lat, lon) -> sp.Matrix:
    """C_e^n at geocentric latitude and longitude."""
    sl, cl, so, co = sp.sin(lat), sp.cos(lat), sp.sin(lon), sp.cos(lon)
    return sp.Matrix([[-sl * co, -sl * so, cl], [-so, co, 0], [-cl * co, -cl * so, -sl]])


def attitude(roll, pitch, heading) -> sp.Matrix:
    """C_b^n of z-y-x Euler angles."""
    def turn(axis: int, angle) -> sp.Matrix:
        c, s = sp.cos(angle), sp.sin(angle)
        i, j = [k for k in range(3) if k != axis]
        m = sp.eye(3)
        m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
        return m if axis != 1 else m.T
    return turn(2, heading) * turn(1, pitch) * turn(0, roll)


def navigator(eq: Mechanisation, state, rate, force) -> list:
    """The on-board computer in ECEF."""
    mu, U = SYMBOL["mu"], SYMBOL["U"]
    C = sp.Matrix(3, 3, list(state[:9]))
    v, r = sp.Matrix(state[9:12]), sp.Matrix(state[12:15])
    earth = sp.Matrix([0, 0, U])
    rho = eq.let("rho", sp.sqrt(r[0]**2 + r[1]**2 + r[2]**2), r"\rho")
    gravity = -mu / rho**3 * r - earth.cross(earth.cross(r))
    C_dot = C * cross_matrix(rate) - cross_matrix(earth) * C
    v_dot = C * sp.Matrix(force) + gravity - 2 * earth.cross(v)
    return [*C_dot, *v_dot, *v]


def output_map(eq: Mechanisation, state, inputs) -> sp.Matrix:
    C = sp.Matrix(3, 3, list(state[:9]))
    v = sp.Matrix(state[9:12])
    x, y, z = state[12:15]
    lat, lon = sp.atan2(z, sp.sqrt(x**2 + y**2)), sp.atan2(y, x)
    to_ned = ecef_to_ned(lat, lon)
    v_n, C_bn = to_ned * v, to_ned * C
    return sp.Matrix([lat, lon, sp.sqrt(x**2 + y**2 + z**2) - SYMBOL["R"], *v_n,
                      sp.atan2(C_bn[2, 1], C_bn[2, 2]), sp.asin(-C_bn[2, 0]),
                      sp.atan2(C_bn[1, 0], C_bn[0, 0])])


def build() -> ModelDefinition:
    x = [v.symbol for v in STATES]
    rate = [SYMBOL[f"omega_{a}"] for a in AXES]
    force = [SYMBOL[f"f_{a}"] for a in AXES]
    gyros = [w + SYMBOL[f"gyro_bias_{a}"] for w, a in zip(rate, AXES, strict=True)]
    accels = [f + SYMBOL[f"accel_bias_{a}"] for f, a in zip(force, AXES, strict=True)]
    computed = computed_symbols(STATES)
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    c = SYMBOL
    lat, lon = c["latitude"], c["longitude"]
    to_ecef = ecef_to_ned(lat, lon).T
    r = SYMBOL["R"] + c["height"]
    start = sp.Matrix([
        *(to_ecef * attitude(c["roll"], c["pitch"], c["heading"])),
        *(to_ecef * sp.Matrix([c["v_N0"], c["v_E0"], c["v_D0"]])),
        r * sp.cos(lat) * sp.cos(lon), r * sp.cos(lat) * sp.sin(lon), r * sp.sin(lat)])
    return ModelDefinition(
        name="ecef_ins", title="Strapdown INS in ECEF (sphere, point-mass gravity)",
        source="Groves 2013, section 5.3 (ECEF mechanisation)",
        states=STATES, error_states=error_states_of(STATES, ()),
        real_states=computed, inputs=INPUTS, parameters=PARAMETERS,
        sources=SOURCES, outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal, real=real,
        ideal_rhs=sp.Matrix(navigator(ideal, x, rate, force)),
        real_rhs=sp.Matrix(navigator(real, computed, gyros, accels)),
        output_map=output_map, initial_state=start, initial_real_state=start,
        domain=((x[12]**2 + x[13]**2 - 1.0, "on the polar axis"),),
        initial_domain=((sp.cos(lat)**2 - 1e-12, "initial latitude at a pole"),),
    )
