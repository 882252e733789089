r"""Test fixture: a strapdown INS whose attitude is three Euler angles (z-y-x: yaw ψ,
pitch θ, roll φ), as a student writes it from a textbook: NED navigation frame,
forward-right-down body axes, a spherical Earth and a constant g.

    body rates relative to NED:  (p, q, r) = ω_ib^b − C_nᵀ (ω_ie^n + ω_en^n)
    φ̇ = p + tan θ (q sin φ + r cos φ)
    θ̇ = q cos φ − r sin φ
    ψ̇ = (q sin φ + r cos φ) / cos θ
    v̇ = C_n f − (2 ω_ie^n + ω_en^n) × v + (0, 0, g)
    L̇ = v_N/(R + h),  λ̇ = v_E/((R + h) cos L),  ḣ = −v_D

The rate equations are singular at θ = ±90° (gimbal lock): the model's domain refuses
cos²θ below 1e-6 (|θ| above 89.943°), at the start and along a run. The line marked
``# pitch domain`` is removed by tests that want the same model without that condition.
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

AXES = "xyz"  # forward, right, down

STATES = (
    Variable("phi", "rad", "roll angle", r"\phi"),
    Variable("theta", "rad", "pitch angle", r"\theta"),
    Variable("psi", "rad", "yaw angle (heading)", r"\psi"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_D", "m/s", "down velocity", "v_D"),
    Variable("lat", "rad", "latitude", "L"),
    Variable("lon", "rad", "longitude", r"\lambda"),
    Variable("h", "m", "height", "h"),
)
INPUTS = (
    *(Variable(f"w_{a}", "rad/s", f"angular rate about body {a}", rf"\omega_{a}")
      for a in AXES),
    *(Variable(f"f_{a}", "m/s**2", f"specific force along body {a}", f"f_{a}")
      for a in AXES),
)
PARAMETERS = (
    Parameter("R", "m", "radius of the spherical Earth", "R", 6_371_000.0),
    Parameter("g", "m/s**2", "gravity, constant", "g", 9.80665),
    Parameter("U", "rad/s", "Earth rate", r"\Omega", EARTH_RATE),
)
SOURCES = (
    *(error_source(f"gyro_bias_{a}", "rad/s", "deg/h", "constant", None,
                   rf"\varepsilon_{a}", f"bias of the {a} gyro") for a in AXES),
    *(error_source(f"accel_bias_{a}", "m/s**2", "ug", "constant", None, rf"\nabla_{a}",
                   f"bias of the {a} accelerometer") for a in AXES),
)
OUTPUTS = (
    Variable("latitude", "rad", "latitude", "L"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("height", "m", "height", "h"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_D", "m/s", "down velocity", "v_D"),
    Variable("roll", "rad", "roll", r"\phi"),
    Variable("pitch", "rad", "pitch", r"\theta"),
    Variable("heading", "rad", "heading", r"\psi"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", "L_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("height", "m", "initial height", "h_0"),
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
    Variable("v_D0", "m/s", "initial down velocity", "v_{D0}"),
    Variable("roll", "rad", "initial roll", r"\phi_0"),
    Variable("pitch", "rad", "initial pitch", r"\theta_0"),
    Variable("heading", "rad", "initial heading", r"\psi_0"),
)
SYMBOL = {v.name: v.symbol for v in (*INPUTS, *PARAMETERS, *SOURCES)}
START = {v.name: v.symbol for v in INITIAL_CONDITIONS}
GIMBAL_LOCK = "pitch at ±90°: Euler-angle gimbal lock"
START_LOCK = "initial pitch at gimbal lock"


def body_to_ned(roll, pitch, yaw) -> sp.Matrix:
    """C_n = R_z(ψ) R_y(θ) R_x(φ): body (forward-right-down) to NED."""
    def about(axis: int, angle) -> sp.Matrix:
        c, s = sp.cos(angle), sp.sin(angle)
        i, j = [k for k in range(3) if k != axis]
        m = sp.eye(3)
        m[i, i], m[j, j] = c, c
        m[i, j], m[j, i] = (-s, s) if axis != 1 else (s, -s)
        return m
    return about(2, yaw) * about(1, pitch) * about(0, roll)


def navigation(eq: Mechanisation, x, rates, forces) -> sp.Matrix:
    roll, pitch, yaw, v_n, v_e, v_d, lat, _lon, h = x
    R, g, U = SYMBOL["R"], SYMBOL["g"], SYMBOL["U"]
    radius = eq.let("rho", R + h, r"\rho")
    earth = sp.Matrix([U * sp.cos(lat), 0, -U * sp.sin(lat)])
    transport = sp.Matrix([v_e / radius, -v_n / radius, -v_e * sp.tan(lat) / radius])
    c_n = body_to_ned(roll, pitch, yaw)
    relative = sp.Matrix(rates) - c_n.T * (earth + transport)
    p, q, r = (eq.let(name, relative[k], name) for k, name in enumerate(("p_b", "q_b", "r_b")))
    v = sp.Matrix([v_n, v_e, v_d])
    v_dot = c_n * sp.Matrix(forces) - (2 * earth + transport).cross(v) + sp.Matrix([0, 0, g])
    side = q * sp.sin(roll) + r * sp.cos(roll)
    return sp.Matrix([p + side * sp.tan(pitch), q * sp.cos(roll) - r * sp.sin(roll),
                      side / sp.cos(pitch), *v_dot, v_n / radius,
                      v_e / (radius * sp.cos(lat)), -v_d])


def build() -> ModelDefinition:
    x = [v.symbol for v in STATES]
    computed = computed_symbols(STATES)
    rates = [SYMBOL[f"w_{a}"] for a in AXES]
    forces = [SYMBOL[f"f_{a}"] for a in AXES]
    measured_rates = [SYMBOL[f"w_{a}"] + SYMBOL[f"gyro_bias_{a}"] for a in AXES]
    measured_forces = [SYMBOL[f"f_{a}"] + SYMBOL[f"accel_bias_{a}"] for a in AXES]
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    start = sp.Matrix([START[k] for k in ("roll", "pitch", "heading", "v_N0", "v_E0",
                                          "v_D0", "latitude", "longitude", "height")])
    domain = [(sp.cos(x[6]) ** 2 - 1e-12, "latitude at a pole")]
    initial_domain = [(sp.cos(START["latitude"]) ** 2 - 1e-12, "initial latitude at a pole")]
    domain.append((sp.cos(x[1]) ** 2 - 1e-6, GIMBAL_LOCK))  # pitch domain
    initial_domain.append((sp.cos(START["pitch"]) ** 2 - 1e-6, START_LOCK))  # pitch domain
    return ModelDefinition(
        name="euler_angle_ins", title="Euler-angle strapdown INS (NED, sphere, constant g)",
        source="test fixture",
        states=STATES, error_states=error_states_of(STATES, ()), real_states=computed,
        inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES, outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=navigation(ideal, x, rates, forces),
        real_rhs=navigation(real, computed, measured_rates, measured_forces),
        output_map=lambda eq, x, u: sp.Matrix([x[6], x[7], x[8], x[3], x[4], x[5], x[0],
                                               x[1], x[2]]),
        initial_state=start, initial_real_state=start,
        domain=tuple(domain), initial_domain=tuple(initial_domain),
    )
