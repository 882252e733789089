r"""Test fixture: a wander-azimuth strapdown INS on WGS-84.

Navigation frame w: local level, z down, x turned from north towards east by the wander
angle α; no vertical transport rate (ρ_z = 0), so no tan φ anywhere. States: the
attitude C_b^w (9), the velocity v^w (3), the position matrix P = C_w^e (9) and the
height h; a baro damping loop on h − h_ref (gains k1, k2, open at 0):

    Ċ = C [ω×] − [(Ω + ρ)×] C,     Ω = U (P₂₀, P₂₁, P₂₂),  sin φ = −P₂₂
    v̇ = C f + (0, 0, γ + k₂ (h − h_ref)) − (2Ω + ρ) × v
    Ṗ = P [ρ×],   ḣ = −v_z − k₁ (h − h_ref)
    ρ = (K_xy v_x + K_yy v_y, −(K_xx v_x + K_xy v_y), 0),
    K = I/(R_E + h) + d [[P₂₀², P₂₀P₂₁], [P₂₀P₂₁, P₂₁²]],
    d = R_E e² / ((1 − e² sin²φ)(R_N + h)(R_E + h))

γ is WGS-84 normal gravity with its second-order height series. The initial-state map
starts the wander angle at the parameter α₀; the wander angle then moves as
α̇ = λ̇ sin φ (north turns about the down axis at ρ_D = −λ̇ sin φ, the x axis not at
all), a state no navigation quantity sets (rotating P about its z axis and
counter-rotating C and v changes no output).
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
    *(Variable(f"C{r}{c}", "1", f"attitude C_b^w entry {r}{c}", f"C_{{{r}{c}}}")
      for r in AXES for c in AXES),
    Variable("v_x", "m/s", "wander-x velocity", "v_x"),
    Variable("v_y", "m/s", "wander-y velocity", "v_y"),
    Variable("v_z", "m/s", "down velocity", "v_z"),
    *(Variable(f"P{r}{c}", "1", f"position C_w^e entry {r}{c}", f"P_{{{r}{c}}}")
      for r in "XYZ" for c in AXES),
    Variable("h", "m", "height", "h"),
)
INPUTS = (
    *(Variable(f"omega_{a}", "rad/s", f"body rate about {a}", rf"\omega_{a}") for a in AXES),
    *(Variable(f"f_{a}", "m/s**2", f"specific force along {a}", f"f_{a}") for a in AXES),
    Variable("h_ref", "m", "external height reference (baro) of the damping loop", "h_{ref}"),
)
PARAMETERS = (
    Parameter("a", "m", "WGS-84 semi-major axis", "a", 6378137.0),
    Parameter("e2", "1", "WGS-84 first eccentricity squared", "e^2", 6.69437999014e-3),
    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),
    Parameter("alpha0", "rad", "initial wander angle", r"\alpha_0", 0.5),
    Parameter("k1", "1/s", "damping gain on dh/dt", "k_1", 0.0, damping_gain=True),
    Parameter("k2", "1/s**2", "damping gain on dv_z/dt", "k_2", 0.0, damping_gain=True),
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
    *(Variable(n, "rad", n, latex) for n, latex in ANGLES),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
    Variable("v_D0", "m/s", "initial down velocity", "v_{D0}"),
    *(Variable(n, "rad", f"initial {n}", f"{latex}_0") for n, latex in ANGLES),
)
S = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES, *INITIAL_CONDITIONS)}

GAMMA_E, K_SOMIGLIANA = 9.7803253359, 0.00193185265241
FLATTENING, M_GRAVITY = 1 / 298.257223563, 0.00344978650684


def skew(w) -> sp.Matrix:
    """[w×]."""
    return sp.Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def turn_z(angle) -> sp.Matrix:
    """Rotation about z (C_w^n of a wander angle)."""
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def attitude(roll, pitch, heading) -> sp.Matrix:
    """Body → NED matrix of z-y-x Euler angles."""
    cr, sr, cp, sp_ = sp.cos(roll), sp.sin(roll), sp.cos(pitch), sp.sin(pitch)
    return (turn_z(heading) * sp.Matrix([[cp, 0, sp_], [0, 1, 0], [-sp_, 0, cp]])
            * sp.Matrix([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))


def navigator(eq: Mechanisation, state, rate, force) -> list:
    """The on-board computer: state derivatives from gyro and accelerometer signals."""
    a, e2, U = S["a"], S["e2"], S["U"]
    C = sp.Matrix(3, 3, list(state[:9]))
    v = sp.Matrix(state[9:12])
    P = sp.Matrix(3, 3, list(state[12:21]))
    h = state[21]
    s2 = eq.let("s2", P[2, 2] ** 2, r"\sin^2\varphi")
    W = eq.let("W", sp.sqrt(1 - e2 * s2), "W")
    RE = eq.let("R_E", a / W, "R_E")
    RN = eq.let("R_N", a * (1 - e2) / W ** 3, "R_N")
    d = eq.let("d", RE * e2 / (W ** 2 * (RN + h) * (RE + h)), "d")
    kxx = eq.let("K_xx", 1 / (RE + h) + d * P[2, 0] ** 2, "K_{xx}")
    kyy = eq.let("K_yy", 1 / (RE + h) + d * P[2, 1] ** 2, "K_{yy}")
    kxy = eq.let("K_xy", d * P[2, 0] * P[2, 1], "K_{xy}")
    rho = sp.Matrix([kxy * v[0] + kyy * v[1], -(kxx * v[0] + kxy * v[1]), 0])
    earth = sp.Matrix([U * P[2, i] for i in range(3)])
    gamma = eq.let("gamma", GAMMA_E * (1 + K_SOMIGLIANA * s2) / W
                   * (1 - 2 * h / a * (1 + FLATTENING + M_GRAVITY - 2 * FLATTENING * s2)
                      + 3 * h ** 2 / a ** 2), r"\gamma")
    dh = eq.let("dh_ref", h - S["h_ref"], r"\delta h")
    C_dot = C * skew(sp.Matrix(rate)) - skew(earth + rho) * C
    v_dot = (C * sp.Matrix(force) + sp.Matrix([0, 0, gamma + S["k2"] * dh])
             - (2 * earth + rho).cross(v))
    return [*C_dot, *v_dot, *(P * skew(rho)), -v[2] - S["k1"] * dh]


def output_map(eq: Mechanisation, state, inputs) -> sp.Matrix:
    C = sp.Matrix(3, 3, list(state[:9]))
    P = sp.Matrix(3, 3, list(state[12:21]))
    C_wn = turn_z(sp.atan2(-P[2, 1], P[2, 0]))
    v_n = C_wn * sp.Matrix(state[9:12])
    C_bn = C_wn * C
    return sp.Matrix([sp.atan2(-P[2, 2], sp.sqrt(P[2, 0] ** 2 + P[2, 1] ** 2)),
                      sp.atan2(-P[1, 2], -P[0, 2]), state[21], *v_n,
                      sp.atan2(C_bn[2, 1], C_bn[2, 2]), sp.asin(-C_bn[2, 0]),
                      sp.atan2(C_bn[1, 0], C_bn[0, 0])])


def initial_state() -> sp.Matrix:
    lat, lon = S["latitude"], S["longitude"]
    C_ne = sp.Matrix([
        [-sp.sin(lat) * sp.cos(lon), -sp.sin(lon), -sp.cos(lat) * sp.cos(lon)],
        [-sp.sin(lat) * sp.sin(lon), sp.cos(lon), -sp.cos(lat) * sp.sin(lon)],
        [sp.cos(lat), 0, -sp.sin(lat)]])
    C_wn = turn_z(S["alpha0"])
    C_bw = C_wn.T * attitude(S["roll"], S["pitch"], S["heading"])
    v_w = C_wn.T * sp.Matrix([S["v_N0"], S["v_E0"], S["v_D0"]])
    return sp.Matrix([*C_bw, *v_w, *(C_ne * C_wn), S["height"]])


def build() -> ModelDefinition:
    x = [v.symbol for v in STATES]
    x_c = computed_symbols(STATES)
    rate = [S[f"omega_{a}"] for a in AXES]
    force = [S[f"f_{a}"] for a in AXES]
    gyros = [w + S[f"gyro_bias_{a}"] for w, a in zip(rate, AXES, strict=True)]
    accels = [f + S[f"accel_bias_{a}"] for f, a in zip(force, AXES, strict=True)]
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    start = initial_state()
    return ModelDefinition(
        name="wander_azimuth", title="Wander-azimuth strapdown INS on WGS-84 (test)",
        source="test fixture", states=STATES, error_states=error_states_of(STATES, ()),
        real_states=x_c, inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES,
        outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=sp.Matrix(navigator(ideal, x, rate, force)),
        real_rhs=sp.Matrix(navigator(real, x_c, gyros, accels)), output_map=output_map,
        initial_state=start, initial_real_state=start)
