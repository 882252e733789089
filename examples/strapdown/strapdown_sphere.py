r"""A strapdown INS of one's own, written as a model file: NED navigation on a sphere.

Local-level NED navigation on a sphere of radius R with constant gravity g; attitude as
the direction-cosine matrix T (body → NED, rows north, east, down), no damping of the
vertical channel (with a constant g it is neutral at rest; in flight the transport-rate
and Coriolis terms couple it to the horizontal channels and it grows slowly: on compare's
default eastbound great circle at 250 m/s the height error of a 50-µg accelerometer bias
is 36 m over the first 3 h and 1.4 km after a day).

    Ṫ = T [ω×] − [ω_in×] T,   ω_in = Ω + ρ,
    Ω = U (cos φ, 0, −sin φ),  ρ = (v_E, −v_N, −v_E tan φ) / (R + h)
    v̇ = T f − (2Ω + ρ) × v + (0, 0, g)
    φ̇ = v_N / (R + h),  λ̇ = v_E / ((R + h) cos φ),  ḣ = −v_D

The inputs are the true body rate ω (omega_x..z) and specific force f (f_x..z). On the
static base they are solved from these equations (ins_errors.numeric.static_rest); on a
moving flight (great circle, manoeuvre) the flight is planned on this model's sphere and
its states come from the flight's latitude, longitude, height, velocity and attitude
through the initial-state map below, the inputs again solved from the equations
(ins_errors.numeric.model_flight). The real work is the same computer fed the gyros
ω + b_g and accelerometers f + b_a. The initial velocities are named v_N0, v_E0, v_D0
(v_N, v_E, v_D are states).

    ins-errors compare examples/strapdown/strapdown_sphere.py --motion great-circle \
        --hours 1 --source accel_bias_x=100ug
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
ENTRIES = [f"T{row}{col}" for row in "NED" for col in AXES]
STATES = (
    *(Variable(e, "1", f"attitude matrix entry {e[1]}/{e[2]}", f"T_{{{e[1]}{e[2]}}}")
      for e in ENTRIES),
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
)
PARAMETERS = (
    Parameter("R", "m", "radius of the spherical Earth", "R", 6_371_000.0),
    Parameter("g", "m/s**2", "constant gravity", "g", 9.81),
    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),
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
    """[w×]: the matrix with [w×] a = w × a."""
    return sp.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def attitude(roll, pitch, heading) -> sp.Matrix:
    """Body → NED matrix of z-y-x Euler angles."""
    def turn(axis: int, angle) -> sp.Matrix:
        c, s = sp.cos(angle), sp.sin(angle)
        i, j = [k for k in range(3) if k != axis]
        m = sp.eye(3)
        m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
        return m if axis != 1 else m.T
    return turn(2, heading) * turn(1, pitch) * turn(0, roll)


def navigator(eq: Mechanisation, state, rate, force) -> list:
    """The on-board computer: state derivatives from gyro and accelerometer signals."""
    R, g, U = SYMBOL["R"], SYMBOL["g"], SYMBOL["U"]
    T = sp.Matrix(3, 3, list(state[:9]))
    v = sp.Matrix(state[9:12])
    lat, h = state[12], state[14]
    r = eq.let("r", R + h, "r")
    earth = sp.Matrix([eq.let("Omega_N", U * sp.cos(lat), r"\Omega_N"), 0,
                       eq.let("Omega_D", -U * sp.sin(lat), r"\Omega_D")])
    transport = sp.Matrix([eq.let("rho_N", v[1] / r, r"\rho_N"),
                           eq.let("rho_E", -v[0] / r, r"\rho_E"),
                           eq.let("rho_D", -v[1] * sp.tan(lat) / r, r"\rho_D")])
    T_dot = T * cross_matrix(sp.Matrix(rate)) - cross_matrix(earth + transport) * T
    v_dot = T * sp.Matrix(force) - (2 * earth + transport).cross(v) + sp.Matrix([0, 0, g])
    return [*T_dot, *v_dot, v[0] / r, v[1] / (r * sp.cos(lat)), -v[2]]


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
    ideal_rhs = sp.Matrix(navigator(ideal, x, rate, force))
    real_rhs = sp.Matrix(navigator(real, x_c, gyros, accels))
    c = SYMBOL
    T0 = attitude(c["roll"], c["pitch"], c["heading"])
    start = sp.Matrix([*T0, c["v_N0"], c["v_E0"], c["v_D0"], c["latitude"], c["longitude"],
                       c["height"]])
    return ModelDefinition(
        name="strapdown_sphere", title="Strapdown NED on a sphere (a model file)",
        source="textbook NED strapdown mechanisation on a sphere (an example model file)",
        states=STATES, error_states=error_states_of(STATES, ()),
        real_states=x_c, inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES,
        outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=ideal_rhs, real_rhs=real_rhs, output_map=output_map,
        initial_state=start, initial_real_state=start,
        domain=((sp.cos(x[12]) ** 2 - 1e-12, "latitude at a pole"),),
        initial_domain=((sp.cos(c["latitude"]) ** 2 - 1e-12, "initial latitude at a pole"),),
    )
