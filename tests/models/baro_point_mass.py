r"""Test fixture: a strapdown INS on a sphere with point-mass gravity and a baro-damped
vertical channel (the external height reference ``h_ref`` is an input).

Local-level NED navigation on a sphere of radius R, attitude as the direction-cosine
matrix T (body → NED), gravity of a point mass μ/r² along the down axis (no centrifugal
term), a second-order damping loop on the height difference h − h_ref:

    Ṫ = T [ω×] − [(Ω + ρ)×] T,   Ω = U (cos φ, 0, −sin φ),
    ρ = (v_E, −v_N, −v_E tan φ) / r,   r = R + h
    v̇ = T f − (2Ω + ρ) × v + (0, 0, μ/r² + k₂ (h − h_ref))
    φ̇ = v_N / r,  λ̇ = v_E / (r cos φ),  ḣ = −v_D − k₁ (h − h_ref)

Its gravity at height h is μ/(R + h)² whatever the gains: the loop adds nothing when the
reference reads the true height.
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
STATES = (
    *(Variable(f"T{r}{c}", "1", f"attitude matrix entry {r}/{c}", f"T_{{{r}{c}}}")
      for r in "NED" for c in AXES),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_D", "m/s", "down velocity", "v_D"),
    Variable("lat", "rad", "latitude", r"\varphi"),
    Variable("lon", "rad", "longitude", r"\lambda"),
    Variable("h", "m", "height", "h"),
)
INPUTS = (
    *(Variable(f"omega_{a}", "rad/s", f"body rate about {a}", rf"\omega_{a}") for a in AXES),
    *(Variable(f"f_{a}", "m/s**2", f"specific force along {a}", f"f_{a}") for a in AXES),
    Variable("h_ref", "m", "external height reference (baro) of the damping loop", "h_{ref}"),
)
PARAMETERS = (
    Parameter("R", "m", "radius of the spherical Earth", "R", 6_371_000.0),
    Parameter("mu", "m**3/s**2", "Earth's gravitational constant", r"\mu", 3.986004418e14),
    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),
    Parameter("k1", "1/s", "damping gain on dh/dt", "k_1", 0.0, damping_gain=True),
    Parameter("k2", "1/s**2", "damping gain on dv_D/dt", "k_2", 0.0, damping_gain=True),
)
SOURCES = (
    *(error_source(f"gyro_bias_{a}", "rad/s", "deg/h", "constant", None, rf"\varepsilon_{a}",
                   f"bias of the {a} gyro") for a in AXES),
    *(error_source(f"accel_bias_{a}", "m/s**2", "ug", "constant", None, rf"\nabla_{a}",
                   f"bias of the {a} accelerometer") for a in AXES),
)
ANGLES = (("roll", r"\gamma"), ("pitch", r"\theta"), ("heading", r"\psi"))
OUTPUTS = (
    Variable("latitude", "rad", "latitude", r"\varphi"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height", "h"),
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


def cross_matrix(w: sp.Matrix) -> sp.Matrix:
    """[w×]."""
    return sp.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def attitude(roll, pitch, heading) -> sp.Matrix:
    """Body → NED matrix of z-y-x Euler angles."""
    cr, sr, cp, sp_, cy, sy = (sp.cos(roll), sp.sin(roll), sp.cos(pitch), sp.sin(pitch),
                               sp.cos(heading), sp.sin(heading))
    return (sp.Matrix([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
            * sp.Matrix([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
            * sp.Matrix([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))


def navigator(eq: Mechanisation, state, rate, force) -> list:
    """The on-board computer: state derivatives from gyro and accelerometer signals."""
    R, mu, U, k1, k2 = (SYMBOL[n] for n in ("R", "mu", "U", "k1", "k2"))
    T = sp.Matrix(3, 3, list(state[:9]))
    v = sp.Matrix(state[9:12])
    lat, h = state[12], state[14]
    r = eq.let("r", R + h, "r")
    earth = sp.Matrix([U * sp.cos(lat), 0, -U * sp.sin(lat)])
    transport = sp.Matrix([v[1] / r, -v[0] / r, -v[1] * sp.tan(lat) / r])
    dh = eq.let("delta_h", h - SYMBOL["h_ref"], r"\delta h")
    T_dot = T * cross_matrix(sp.Matrix(rate)) - cross_matrix(earth + transport) * T
    v_dot = (T * sp.Matrix(force) - (2 * earth + transport).cross(v)
             + sp.Matrix([0, 0, mu / r ** 2 + k2 * dh]))
    return [*T_dot, *v_dot, v[0] / r, v[1] / (r * sp.cos(lat)), -v[2] - k1 * dh]


def output_map(eq: Mechanisation, state, inputs) -> sp.Matrix:
    T = sp.Matrix(3, 3, list(state[:9]))
    v_n, v_e, v_d, lat, lon, h = state[9:]
    return sp.Matrix([lat, lon, h, v_n, v_e, v_d, sp.atan2(T[2, 1], T[2, 2]),
                      sp.asin(-T[2, 0]), sp.atan2(T[1, 0], T[0, 0])])


def build() -> ModelDefinition:
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    rate = [SYMBOL[f"omega_{a}"] for a in AXES]
    force = [SYMBOL[f"f_{a}"] for a in AXES]
    gyros = [w + SYMBOL[f"gyro_bias_{a}"] for w, a in zip(rate, AXES, strict=True)]
    accels = [f + SYMBOL[f"accel_bias_{a}"] for f, a in zip(force, AXES, strict=True)]
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    c = SYMBOL
    start = sp.Matrix([*attitude(c["roll"], c["pitch"], c["heading"]), c["v_N0"], c["v_E0"],
                       c["v_D0"], c["latitude"], c["longitude"], c["height"]])
    return ModelDefinition(
        name="baro_point_mass", title="Strapdown NED, point-mass gravity, baro loop (test)",
        source="test fixture",
        states=STATES, error_states=error_states_of(STATES, ()),
        real_states=x_c, inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES,
        outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=sp.Matrix(navigator(ideal, x, rate, force)),
        real_rhs=sp.Matrix(navigator(real, x_c, gyros, accels)), output_map=output_map,
        initial_state=start, initial_real_state=start,
        domain=((sp.cos(x[12]) ** 2 - 1e-12, "latitude at a pole"),),
        initial_domain=((sp.cos(c["latitude"]) ** 2 - 1e-12, "initial latitude at a pole"),),
    )
