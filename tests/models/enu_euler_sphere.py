r"""Test fixture: a researcher's own strapdown INS, ENU local-level navigation on a
sphere, Euler-angle attitude (its error equations in ENU: data/convention/enu_euler_ok.txt).

Frames: n = ENU (x east, y north, z up); body b = right-forward-up (x right wing,
y nose, z up), as in Chinese/ENU texts (Yan Gongmin PSINS).
Euler angles: C_b^n = Rz(yaw) Rx(theta) Ry(gam), with
  yaw   : rotation about up, positive COUNTER-clockwise seen from above
          (yaw = -heading, heading clockwise from north),
  theta : pitch about body x (right), nose up positive,
  gam   : roll about body y (forward), right wing down positive.

    omega_nb^b = omega_ib^b - C_n^b (omega_ie^n + omega_en^n)
    [theta, gam, yaw]' = M(theta, gam)^-1 omega_nb^b
    v' = C_b^n f^b - (2 omega_ie + omega_en) x v + (0, 0, -g)
    lat' = v_N/(R+h), lon' = v_E/((R+h) cos lat), h' = v_U
  omega_ie^n = (0, U cos lat, U sin lat)
  omega_en^n = (-v_N/(R+h), v_E/(R+h), v_E tan lat/(R+h))
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
    Variable("theta", "rad", "pitch Euler angle (about body x, right)", r"\theta"),
    Variable("gam", "rad", "roll Euler angle (about body y, forward)", r"\gamma"),
    Variable("yaw", "rad", "yaw Euler angle, counter-clockwise from north", r"\psi"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_U", "m/s", "up velocity", "v_U"),
    Variable("lat", "rad", "latitude", "L"),
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
    Parameter("U", "rad/s", "Earth rate", r"\Omega", EARTH_RATE),
)
SOURCES = (
    *(error_source(f"gyro_bias_{a}", "rad/s", "deg/h", "constant", None, rf"\varepsilon_{a}",
                   f"bias of the {a} gyro") for a in AXES),
    *(error_source(f"accel_bias_{a}", "m/s**2", "ug", "constant", None, rf"\nabla_{a}",
                   f"bias of the {a} accelerometer") for a in AXES),
)
OUTPUTS = (
    Variable("latitude", "rad", "latitude", "L"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height", "h"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_U", "m/s", "up velocity", "v_U"),
    Variable("roll", "rad", "roll", r"\gamma"),
    Variable("pitch", "rad", "pitch", r"\theta"),
    Variable("heading", "rad", "heading clockwise from north", r"\psi_h"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", "L_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_U0", "m/s", "initial up velocity", "v_{U0}"),
    Variable("roll", "rad", "initial roll", r"\gamma_0"),
    Variable("pitch", "rad", "initial pitch", r"\theta_0"),
    Variable("heading", "rad", "initial heading (clockwise from north)", r"\psi_{h0}"),
)
SYMBOL = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES,
                                      *INITIAL_CONDITIONS)}


def rot(axis: int, a):
    c, s = sp.cos(a), sp.sin(a)
    if axis == 0:
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def cbn(theta, gam, yaw):
    """Body (RFU) -> ENU."""
    return rot(2, yaw) * rot(0, theta) * rot(1, gam)


def euler_rate_matrix(theta, gam):
    """omega_nb^b = M @ [theta', gam', yaw']."""
    ex, ey, ez = sp.Matrix([1, 0, 0]), sp.Matrix([0, 1, 0]), sp.Matrix([0, 0, 1])
    Ry, Rx = rot(1, gam), rot(0, theta)
    col_theta = Ry.T * ex
    col_gam = ey
    col_yaw = Ry.T * Rx.T * ez
    return sp.Matrix.hstack(col_theta, col_gam, col_yaw)


def navigator(eq: Mechanisation, state, rate, force) -> list:
    R, g, U = SYMBOL["R"], SYMBOL["g"], SYMBOL["U"]
    theta, gam, yaw, vE, vN, vU, lat, _lon, h = state
    r = eq.let("r", R + h, "r")
    w_ie = sp.Matrix([0, eq.let("Omega_N", U * sp.cos(lat), r"\Omega_N"),
                      eq.let("Omega_U", U * sp.sin(lat), r"\Omega_U")])
    w_en = sp.Matrix([eq.let("rho_E", -vN / r, r"\rho_E"),
                      eq.let("rho_N", vE / r, r"\rho_N"),
                      eq.let("rho_U", vE * sp.tan(lat) / r, r"\rho_U")])
    C = cbn(theta, gam, yaw)
    w_nb = sp.Matrix(rate) - C.T * (w_ie + w_en)
    M = euler_rate_matrix(theta, gam)
    ang_dot = sp.simplify(M.inv()) * w_nb
    v = sp.Matrix([vE, vN, vU])
    v_dot = C * sp.Matrix(force) - (2 * w_ie + w_en).cross(v) + sp.Matrix([0, 0, -g])
    return [*ang_dot, *v_dot, vN / r, vE / (r * sp.cos(lat)), vU]


def output_map(eq: Mechanisation, state, inputs) -> sp.Matrix:
    theta, gam, yaw, vE, vN, vU, lat, lon, h = state
    return sp.Matrix([lat, lon, h, vE, vN, vU, gam, theta, -yaw])


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
    start = sp.Matrix([c["pitch"], c["roll"], -c["heading"], c["v_E0"], c["v_N0"], c["v_U0"],
                       c["latitude"], c["longitude"], c["height"]])
    return ModelDefinition(
        name="enu_euler_sphere", title="Strapdown ENU on a sphere, Euler angles",
        source="test fixture: an ENU researcher's own model",
        states=STATES, error_states=error_states_of(STATES, ()),
        real_states=x_c, inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES,
        outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=ideal_rhs, real_rhs=real_rhs, output_map=output_map,
        initial_state=start, initial_real_state=start,
        domain=((sp.cos(x[6]) ** 2 - 1e-12, "latitude at a pole"),
                (sp.cos(x[0]) ** 2 - 1e-6, "pitch at +-90 deg (Euler singularity)")),
        initial_domain=((sp.cos(c["latitude"]) ** 2 - 1e-12, "initial latitude at a pole"),),
    )
