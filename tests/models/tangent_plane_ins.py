r"""Test fixture (a researcher's own model file, as a probe wrote it): a short-range
local-level platform INS on a rotating flat Earth (local tangent plane).

A three-gyro platform is slaved to the local level (x east, y north, z up) at the
vehicle. Two horizontal accelerometers feed a computer that integrates the east/north
velocity and the position in METRES in the tangent plane of a fixed origin at latitude
phi0 (a parameter: the system is short-range, latitude is never computed). The platform
is torqued with Earth rate at phi0 and the transport rate V/R (Schuler tuning), the
azimuth also with the meridian convergence V_E tan(phi0)/R.

The velocity loop is damped by an external velocity reference V_ref = V + b_ref (e.g. a
Doppler log with bias b_ref) through a proportional gain c_v and an integrator q with
gain c_i (both damping gains, 0 = open loop: a pure Schuler INS).

Ideal work (true specific force a, level platform):

    dV_E/dt = a_E + 2 U sin(phi0) V_N + U^2 x_E
    dV_N/dt = a_N - 2 U sin(phi0) V_E + U^2 sin^2(phi0) x_N
    dx_E/dt = V_E,   dx_N/dt = V_N

Real work: accelerometers on the platform rotated by alpha (z-y-x), scale errors k (ppm),
biases (ug); damping terms -c_v (V~ - V_ref) - q, dq/dt = c_i (V~ - V_ref); platform
small-angle kinematics  d(alpha)/dt = w_cmd + eps - w_l - w_l x alpha.
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

STATES = (
    Variable("V_E", "m/s", "east velocity", "V_E"),
    Variable("V_N", "m/s", "north velocity", "V_N"),
    Variable("x_E", "m", "east position in the tangent plane", "x_E"),
    Variable("x_N", "m", "north position in the tangent plane", "x_N"),
)
EXTRA = (
    Variable("alpha_E", "rad", "platform tilt about east", r"\alpha_E"),
    Variable("alpha_N", "rad", "platform tilt about north", r"\alpha_N"),
    Variable("alpha_U", "rad", "platform azimuth error", r"\alpha_U"),
    Variable("q_E", "m/s**2", "damping integrator, east", "q_E"),
    Variable("q_N", "m/s**2", "damping integrator, north", "q_N"),
)
INPUTS = (
    Variable("a_E", "m/s**2", "true east specific force", "a_E"),
    Variable("a_N", "m/s**2", "true north specific force", "a_N"),
)
PARAMETERS = (
    Parameter("R", "m", "Schuler tuning radius", "R", 6_371_000.0),
    Parameter("g", "m/s**2", "gravity", "g", 9.80665),
    Parameter("U", "rad/s", "Earth rate", r"\Omega", EARTH_RATE),
    Parameter("phi0", "rad", "latitude of the tangent-plane origin", r"\varphi_0",
              0.8726646259971648),
    Parameter("c_v", "1/s", "velocity damping gain", "c_v", 0.0, damping_gain=True,
              example="2e-3/s", example_gives="Schuler loop damping about 0.8"),
    Parameter("c_i", "1/s**2", "velocity damping integrator gain", "c_i", 0.0,
              damping_gain=True, example="1e-6/s^2", example_gives="slow bias integrator"),
)
SOURCES = (
    error_source("gyro_drift_E", "rad/s", "deg/h", "constant", None, r"\varepsilon_E",
                 "drift of the east gyro"),
    error_source("gyro_drift_N", "rad/s", "deg/h", "constant", None, r"\varepsilon_N",
                 "drift of the north gyro"),
    error_source("gyro_drift_U", "rad/s", "deg/h", "constant", None, r"\varepsilon_U",
                 "drift of the azimuth gyro"),
    error_source("accel_bias_E", "m/s**2", "ug", "constant", None, r"\nabla_E",
                 "bias of the east accelerometer"),
    error_source("accel_bias_N", "m/s**2", "ug", "constant", None, r"\nabla_N",
                 "bias of the north accelerometer"),
    error_source("accel_scale_E", "1", "ppm", "constant", None, r"k_E",
                 "scale-factor error of the east accelerometer"),
    error_source("accel_scale_N", "1", "ppm", "constant", None, r"k_N",
                 "scale-factor error of the north accelerometer"),
    error_source("vref_bias_E", "m/s", "m/s", "constant", None, r"b_E",
                 "bias of the external east velocity reference"),
    error_source("vref_bias_N", "m/s", "m/s", "constant", None, r"b_N",
                 "bias of the external north velocity reference"),
    error_source("initial_tilt_E", "rad", "arcsec", "initial", None, r"\alpha_{E0}",
                 "initial tilt about east"),
    error_source("initial_tilt_N", "rad", "arcsec", "initial", None, r"\alpha_{N0}",
                 "initial tilt about north"),
    error_source("initial_azimuth_error", "rad", "arcmin", "initial", None, r"\alpha_{U0}",
                 "initial azimuth error"),
    error_source("initial_position_error_E", "m", "m", "initial", None, r"\delta x_{E0}",
                 "initial east position error"),
    error_source("initial_position_error_N", "m", "m", "initial", None, r"\delta x_{N0}",
                 "initial north position error"),
)
OUTPUTS = (
    Variable("x_E", "m", "east position", "x_E"),
    Variable("x_N", "m", "north position", "x_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
)
INITIAL_CONDITIONS = (
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
)
S = {v.name: v.symbol for v in (*STATES, *EXTRA, *INPUTS, *PARAMETERS, *SOURCES,
                                 *INITIAL_CONDITIONS)}


def level_rate(eq: Mechanisation, V_E, V_N):
    R, U, phi0 = S["R"], S["U"], S["phi0"]
    w_E = eq.let("w_E", -V_N / R, r"\omega_E")
    w_N = eq.let("w_N", U * sp.cos(phi0) + V_E / R, r"\omega_N")
    w_U = eq.let("w_U", U * sp.sin(phi0) + V_E * sp.tan(phi0) / R, r"\omega_U")
    return sp.Matrix([w_E, w_N, w_U])


def velocity_rhs(eq: Mechanisation, V_E, V_N, x_E, x_N, f_E, f_N):
    U, phi0 = S["U"], S["phi0"]
    cor = eq.let("cor", 2 * U * sp.sin(phi0), r"2\Omega\sin\varphi_0")
    return [f_E + cor * V_N + U**2 * x_E,
            f_N - cor * V_E + U**2 * sp.sin(phi0) ** 2 * x_N]


def rot(axis, angle):
    c, s = sp.cos(angle), sp.sin(angle)
    if axis == 0:
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def outputs(eq, state, inputs):
    V_E, V_N, x_E, x_N = state
    return sp.Matrix([x_E, x_N, V_E, V_N])


def build() -> ModelDefinition:
    V_E, V_N, x_E, x_N = (v.symbol for v in STATES)
    V_Ec, V_Nc, x_Ec, x_Nc = computed_symbols(STATES)
    aE, aN, aU, qE, qN = (v.symbol for v in EXTRA)
    a_E, a_N = S["a_E"], S["a_N"]
    g = S["g"]

    ideal = Mechanisation()
    w_l = level_rate(ideal, V_E, V_N)
    ideal_rhs = sp.Matrix([*velocity_rhs(ideal, V_E, V_N, x_E, x_N, a_E, a_N), V_E, V_N])

    real = Mechanisation(computed=True)
    C = rot(2, aU) * rot(1, aN) * rot(0, aE)          # platform -> level
    f_p = C.T * sp.Matrix([a_E, a_N, g])
    f_E = real.let("f_E", (1 + S["accel_scale_E"]) * f_p[0] + S["accel_bias_E"], "f_E")
    f_N = real.let("f_N", (1 + S["accel_scale_N"]) * f_p[1] + S["accel_bias_N"], "f_N")
    dvE = real.let("dvref_E", V_Ec - V_E - S["vref_bias_E"], r"\Delta V^{ref}_E")
    dvN = real.let("dvref_N", V_Nc - V_N - S["vref_bias_N"], r"\Delta V^{ref}_N")
    vel = velocity_rhs(real, V_Ec, V_Nc, x_Ec, x_Nc, f_E, f_N)
    w_c = level_rate(real, V_Ec, V_Nc)
    eps = sp.Matrix([S["gyro_drift_E"], S["gyro_drift_N"], S["gyro_drift_U"]])
    alpha = sp.Matrix([aE, aN, aU])
    alpha_dot = w_c + eps - w_l - w_l.cross(alpha)
    real_rhs = sp.Matrix([
        vel[0] - S["c_v"] * dvE - qE,
        vel[1] - S["c_v"] * dvN - qN,
        V_Ec, V_Nc,
        *alpha_dot,
        S["c_i"] * dvE, S["c_i"] * dvN,
    ])
    v0E, v0N = S["v_E0"], S["v_N0"]
    return ModelDefinition(
        name="tangent_plane_ins",
        title="Short-range damped platform INS on a rotating flat Earth",
        source="probe model (own work)",
        states=STATES,
        error_states=error_states_of(STATES, EXTRA),
        real_states=[V_Ec, V_Nc, x_Ec, x_Nc, aE, aN, aU, qE, qN],
        inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES, outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS, ideal=ideal, real=real,
        ideal_rhs=ideal_rhs, real_rhs=real_rhs, output_map=outputs,
        initial_state=sp.Matrix([v0E, v0N, 0, 0]),
        initial_real_state=sp.Matrix([
            v0E, v0N, S["initial_position_error_E"], S["initial_position_error_N"],
            S["initial_tilt_E"], S["initial_tilt_N"], S["initial_azimuth_error"], 0, 0]),
        groups=(("Velocity and position", ["delta_V_E", "delta_V_N", "delta_x_E", "delta_x_N"]),
                ("Platform", ["alpha_E", "alpha_N", "alpha_U"]),
                ("Damping integrators", ["q_E", "q_N"])),
        domain=((sp.cos(S["phi0"]) ** 2 - 1e-12, "origin latitude phi0 at a pole (tan phi0)"),
                (S["R"], "R must be positive")),
        initial_domain=((sp.cos(S["phi0"]) ** 2 - 1e-12, "origin latitude phi0 at a pole"),),
    )
