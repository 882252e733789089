r"""A marine INS probe's own model: a ship's north-pointing (geometric/semi-analytic)
platform INS with damped Schuler loops and a gyrocompassed azimuth.

External velocity reference V_ref = V + dV_log (ship's log / GNSS velocity).
Horizontal channels damped through gains K1 (velocity integrator, 1/s) and K2 (platform
torquing, dimensionless): damped loop s^2 + K1 s + (g/R)(1 + K2).
Azimuth gyrocompassed: azimuth torquer fed K3 (V~_N - V_ref_N)/R.

Earth a sphere of radius R, constant g, sea level (no vertical channel).
Platform angles alpha_E, alpha_N, alpha_U: small rotations of the platform about E, N, U.
"""

from __future__ import annotations

import sympy as sp

from ins_errors.modeling import (
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
    computed_symbols,
    error_source,
    error_states_of,
)

STATES = (
    Variable("V_N", "m/s", "north velocity over ground", "V_N"),
    Variable("V_E", "m/s", "east velocity over ground", "V_E"),
    Variable("phi", "rad", "latitude", r"\varphi"),
    Variable("lam", "rad", "longitude", r"\lambda"),
)
ANGLES = (
    Variable("alpha_E", "rad", "platform rotation about east (north-channel tilt)", r"\alpha_E"),
    Variable("alpha_N", "rad", "platform rotation about north (east-channel tilt)", r"\alpha_N"),
    Variable("alpha_U", "rad", "platform azimuth error", r"\alpha_U"),
)
INPUTS = (
    Variable("a_N", "m/s**2", "north apparent acceleration", "a_N"),
    Variable("a_E", "m/s**2", "east apparent acceleration", "a_E"),
)
PARAMETERS = (
    Parameter("R", "m", "Earth radius (sphere)", "R", 6_371_000.0),
    Parameter("g", "m/s**2", "gravity", "g", 9.80665),
    Parameter("U", "rad/s", "Earth rate", r"\Omega", 7.292115e-5),
    Parameter("K1", "1/s", "velocity damping gain on (V~ - V_log) in dV/dt", "K_1",
              3.4745e-3, damping_gain=True, example="3.47e-3/s",
              example_gives="zeta 0.7 with K2 = 3"),
    Parameter("K2", "1", "torquing damping gain on (V~ - V_log)/R", "K_2",
              3.0, damping_gain=True, example="3", example_gives="42-min loop"),
    Parameter("K3", "1", "gyrocompass gain: azimuth torque K3 (V~_N - V_log_N)/R", "K_3",
              20.0, damping_gain=True, example="20", example_gives="~1-h gyrocompass"),
)
SOURCES = (
    error_source("gyro_drift_east", "rad/s", "deg/h", "constant", None, r"\varepsilon_E",
                 "drift of the east gyro"),
    error_source("gyro_drift_north", "rad/s", "deg/h", "constant", None, r"\varepsilon_N",
                 "drift of the north gyro"),
    error_source("gyro_drift_up", "rad/s", "deg/h", "constant", None, r"\varepsilon_U",
                 "drift of the azimuth gyro"),
    error_source("accel_bias_north", "m/s**2", "ug", "constant", None, r"\nabla_N",
                 "bias of the north accelerometer"),
    error_source("accel_bias_east", "m/s**2", "ug", "constant", None, r"\nabla_E",
                 "bias of the east accelerometer"),
    error_source("log_bias_north", "m/s", "m/s", "constant", None, r"\delta V_{rN}",
                 "bias of the log / reference velocity, north"),
    error_source("log_bias_east", "m/s", "m/s", "constant", None, r"\delta V_{rE}",
                 "bias of the log / reference velocity, east"),
    error_source("initial_tilt_east", "rad", "arcsec", "initial", None, r"\alpha_{E0}",
                 "initial tilt about east"),
    error_source("initial_tilt_north", "rad", "arcsec", "initial", None, r"\alpha_{N0}",
                 "initial tilt about north"),
    error_source("initial_azimuth_error", "rad", "arcmin", "initial", None, r"\alpha_{U0}",
                 "initial azimuth error"),
)
OUTPUTS = (
    Variable("latitude", "rad", "latitude", r"\varphi"),
    Variable("longitude", "rad", "longitude", r"\lambda"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", r"\varphi_0"),
    Variable("longitude", "rad", "initial longitude", r"\lambda_0"),
    Variable("v_N", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_E", "m/s", "initial east velocity", "v_{E0}"),
)

V_N, V_E, phi, lam = (v.symbol for v in STATES)
V_Nc, V_Ec, phi_c, lam_c = computed_symbols(STATES)
aE_, aN_, aU_ = (v.symbol for v in ANGLES)
a_N, a_E = (v.symbol for v in INPUTS)
R, g, U, K1, K2, K3 = (v.symbol for v in PARAMETERS)
epsE, epsN, epsU, nabN, nabE, dVrN, dVrE, t0E, t0N, t0U = (v.symbol for v in SOURCES)


def outputs(eq, state, inputs):
    vn, ve, la, lo = state
    return sp.Matrix([la, lo, vn, ve])


def build() -> ModelDefinition:
    ideal = Mechanisation()
    rho = ideal.let("rho", 2 * U * sp.sin(phi) + V_E * sp.tan(phi) / R, r"\rho")
    w_E = ideal.let("omega_E", -V_N / R, r"\omega_E")
    w_N = ideal.let("omega_N", U * sp.cos(phi) + V_E / R, r"\omega_N")
    w_U = ideal.let("omega_U", U * sp.sin(phi) + V_E * sp.tan(phi) / R, r"\omega_U")
    ideal_rhs = sp.Matrix([
        a_N - rho * V_E,
        a_E + rho * V_N,
        V_N / R,
        V_E / (R * sp.cos(phi)),
    ])

    real = Mechanisation(computed=True)
    # accelerometers on the misaligned platform (first order in the angles), vertical g
    f_N = real.let("f_N", a_N + aE_ * g - aU_ * a_E + nabN, "f_N")
    f_E = real.let("f_E", a_E - aN_ * g + aU_ * a_N + nabE, "f_E")
    dvN = real.let("dv_N", V_Nc - (V_N + dVrN), r"\Delta_N")  # computed minus log
    dvE = real.let("dv_E", V_Ec - (V_E + dVrE), r"\Delta_E")
    rho_c = real.let("rho", 2 * U * sp.sin(phi_c) + V_Ec * sp.tan(phi_c) / R, r"\rho")
    c_E = real.let("omega_E", -V_Nc / R - K2 * dvN / R, r"\omega_E")
    c_N = real.let("omega_N", U * sp.cos(phi_c) + V_Ec / R + K2 * dvE / R, r"\omega_N")
    c_U = real.let("omega_U", U * sp.sin(phi_c) + V_Ec * sp.tan(phi_c) / R + K3 * dvN / R,
                   r"\omega_U")
    real_rhs = sp.Matrix([
        f_N - rho_c * V_Ec - K1 * dvN,
        f_E + rho_c * V_Nc - K1 * dvE,
        V_Nc / R,
        V_Ec / (R * sp.cos(phi_c)),
        c_E - w_E + epsE - (w_N * aU_ - w_U * aN_),
        c_N - w_N + epsN - (w_U * aE_ - w_E * aU_),
        c_U - w_U + epsU - (w_E * aN_ - w_N * aE_),
    ])

    lat0, lon0, vn0, ve0 = (v.symbol for v in INITIAL_CONDITIONS)
    return ModelDefinition(
        name="marine_ins",
        title="Ship's damped north-pointing platform INS with gyrocompassing",
        source="probe",
        states=STATES,
        error_states=error_states_of(STATES, list(ANGLES)),
        real_states=[V_Nc, V_Ec, phi_c, lam_c, aE_, aN_, aU_],
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal,
        real=real,
        ideal_rhs=ideal_rhs,
        real_rhs=real_rhs,
        output_map=outputs,
        initial_state=sp.Matrix([vn0, ve0, lat0, lon0]),
        initial_real_state=sp.Matrix([vn0, ve0, lat0, lon0, t0E, t0N, t0U]),
        groups=(("Velocity and position", ["delta_V_N", "delta_V_E", "delta_phi", "delta_lam"]),
                ("Platform", ["alpha_E", "alpha_N", "alpha_U"])),
        notes="Damped Schuler loops, gyrocompassed azimuth.",
        domain=((sp.cos(phi), "latitude at a pole"), (R, "R must be positive"),
                (g, "g must be positive")),
        initial_domain=((sp.cos(lat0), "latitude at a pole"),),
    )
