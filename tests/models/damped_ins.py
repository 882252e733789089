r"""A north-pointing local-level platform INS whose horizontal channels are damped by an
external velocity reference (log, Doppler, odometer): a damped-INS researcher's model
file (a probe's), kept for the tests of damped Schuler modes (tests/test_modes_damped.py).

Sphere of radius R, Earth rate U, level at height 0 (no vertical channel). The reference
velocity is v_ref = (1 + s_r) v + δv_ref (true velocity, scale error, bias).

Computer (real work), d = v~ − v_ref the velocity disagreement:
    dv~_E/dt = f~_E + turn v~_N − k_v d_E
    dv~_N/dt = f~_N − turn v~_E − k_v d_N
    ω_cmd_E = −(v~_N + k_p d_N)/R,  ω_cmd_N = U cos φ~ + (v~_E + k_p d_E)/R,
    ω_cmd_U = U sin φ~ + v~_E tan φ~ / R
With k_p = 0 the two horizontal channels at rest, as one complex error, obey
s² + (k_v + 2iU sin φ) s + g/R = 0 (a single channel without Earth rate:
s² + k_v s + (1 + k_p) g/R; ζ = k_v/(2√(g/R)), 0.5 for k_v = 1.24e-3/s).
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
    on_platform,
    platform_rates,
)

STATES = (
    Variable("V_E", "m/s", "east ground velocity", "V_E"),
    Variable("V_N", "m/s", "north ground velocity", "V_N"),
    Variable("phi", "rad", "latitude", r"\varphi"),
    Variable("lam", "rad", "longitude", r"\lambda"),
)
ANGLES = (
    Variable("alpha_E", "rad", "platform error angle about east (level)", r"\alpha_E"),
    Variable("alpha_N", "rad", "platform error angle about north (level)", r"\alpha_N"),
    Variable("alpha_U", "rad", "platform error angle about up (azimuth)", r"\alpha_U"),
)
INPUTS = (
    Variable("a_E", "m/s**2", "true specific force along east (0 at rest)", "a_E"),
    Variable("a_N", "m/s**2", "true specific force along north (0 at rest)", "a_N"),
)
PARAMETERS = (
    Parameter("R", "m", "Earth radius (sphere)", "R", 6_371_000.0),
    Parameter("U", "rad/s", "Earth rotation rate", r"\Omega", EARTH_RATE),
    Parameter("g", "m/s**2", "gravity", "g", 9.80665),
    Parameter("k_v", "1/s", "velocity damping gain: k_v (v~ - v_ref) fed back into dv~/dt",
              "k_v", 0.0, damping_gain=True, example="1.24e-3/s",
              example_gives="Schuler damping ratio 0.5"),
    Parameter("k_p", "1",
              "platform correction gain: k_p (v~ - v_ref)/R added to the torquing command",
              "k_p", 0.0, damping_gain=True, example="0.5",
              example_gives="Schuler frequency x sqrt(1.5)"),
)
SOURCES = (
    error_source("gyro_drift_east", "rad/s", "deg/h", "constant", None, r"\varepsilon_E",
                 "east gyro drift"),
    error_source("gyro_drift_north", "rad/s", "deg/h", "constant", None, r"\varepsilon_N",
                 "north gyro drift"),
    error_source("gyro_drift_up", "rad/s", "deg/h", "constant", None, r"\varepsilon_U",
                 "azimuth gyro drift"),
    error_source("accel_bias_east", "m/s**2", "ug", "constant", None, r"\nabla_E",
                 "east accelerometer bias"),
    error_source("accel_bias_north", "m/s**2", "ug", "constant", None, r"\nabla_N",
                 "north accelerometer bias"),
    error_source("ref_velocity_error_east", "m/s", "m/s", "constant", None, r"\delta v_{rE}",
                 "constant error of the external reference east velocity"),
    error_source("ref_velocity_error_north", "m/s", "m/s", "constant", None, r"\delta v_{rN}",
                 "constant error of the external reference north velocity"),
    error_source("ref_scale_error", "1", "ppm", "constant", None, r"s_r",
                 "scale-factor error of the external velocity reference"),
    error_source("initial_velocity_error_north", "m/s", "m/s", "initial", None, r"\delta v_{N0}",
                 "initial north velocity error"),
    error_source("initial_tilt_east", "rad", "arcsec", "initial", None, r"\alpha_{E0}",
                 "initial platform tilt about east"),
    error_source("initial_tilt_north", "rad", "arcsec", "initial", None, r"\alpha_{N0}",
                 "initial platform tilt about north"),
    error_source("initial_azimuth_error", "rad", "arcmin", "initial", None, r"\alpha_{U0}",
                 "initial platform azimuth error"),
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
    Variable("v_N", "m/s", "initial north velocity", r"v_{N0}"),
    Variable("v_E", "m/s", "initial east velocity", r"v_{E0}"),
)

S = {v.name: v.symbol for v in (*INPUTS, *PARAMETERS, *SOURCES)}
R, U, g, k_v, k_p = S["R"], S["U"], S["g"], S["k_v"], S["k_p"]


def rates(eq, s, d_E, d_N):
    v_E, v_N, lat, _ = s
    wE = eq.let("omega_E", -(v_N + k_p * d_N) / R, r"\omega_E")
    wN = eq.let("omega_N", U * sp.cos(lat) + (v_E + k_p * d_E) / R, r"\omega_N")
    wU = eq.let("omega_U", U * sp.sin(lat) + v_E * sp.tan(lat) / R, r"\omega_U")
    return wE, wN, wU


def computer(eq, s, f_E, f_N, vref_E, vref_N):
    v_E, v_N, lat, _ = s
    d_E = eq.let("d_E", v_E - vref_E, "d_E")
    d_N = eq.let("d_N", v_N - vref_N, "d_N")
    turn = eq.let("turn", 2 * U * sp.sin(lat) + v_E * sp.tan(lat) / R, r"\omega_t")
    rhs = [f_E + turn * v_N - k_v * d_E, f_N - turn * v_E - k_v * d_N,
           v_N / R, v_E / (R * sp.cos(lat))]
    return rhs, rates(eq, s, d_E, d_N)


def outputs(eq, s, inputs):
    v_E, v_N, lat, lon = s
    return sp.Matrix([lat, lon, v_N, v_E])


def build() -> ModelDefinition:
    x = [v.symbol for v in STATES]
    xc = computed_symbols(STATES)
    alpha = [v.symbol for v in ANGLES]
    a_E, a_N = S["a_E"], S["a_N"]
    v_E, v_N, lat, _ = x

    ideal = Mechanisation()
    ideal_rhs, omega = computer(ideal, x, a_E, a_N, v_E, v_N)
    f_U = g - v_E**2 / R - v_N**2 / R - 2 * U * sp.cos(lat) * v_E
    fE, fN, _ = on_platform(alpha, (a_E, a_N, f_U))
    fE, fN = fE + S["accel_bias_east"], fN + S["accel_bias_north"]
    sr = S["ref_scale_error"]
    vrefE = (1 + sr) * v_E + S["ref_velocity_error_east"]
    vrefN = (1 + sr) * v_N + S["ref_velocity_error_north"]
    real = Mechanisation(computed=True)
    real_rhs, omega_c = computer(real, xc, fE, fN, vrefE, vrefN)
    drift = (S["gyro_drift_east"], S["gyro_drift_north"], S["gyro_drift_up"])
    platform = platform_rates(alpha, [w + d for w, d in zip(omega_c, drift, strict=True)], omega)

    c = {v.name: v.symbol for v in INITIAL_CONDITIONS}
    lat0, lon0, vN0, vE0 = c["latitude"], c["longitude"], c["v_N"], c["v_E"]
    return ModelDefinition(
        name="damped_ins",
        title="Local-level INS with externally velocity-damped horizontal channels",
        source="probe: externally damped INS",
        states=STATES,
        error_states=error_states_of(STATES, ANGLES),
        real_states=[*xc, *alpha],
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal, real=real,
        ideal_rhs=sp.Matrix(ideal_rhs),
        real_rhs=sp.Matrix([*real_rhs, *platform]),
        output_map=outputs,
        initial_state=sp.Matrix([vE0, vN0, lat0, lon0]),
        initial_real_state=sp.Matrix([vE0, vN0 + S["initial_velocity_error_north"], lat0, lon0,
                                      S["initial_tilt_east"], S["initial_tilt_north"],
                                      S["initial_azimuth_error"]]),
        groups=(("Velocity", ["delta_V_E", "delta_V_N"]), ("Position", ["delta_phi", "delta_lam"]),
                ("Platform", ["alpha_E", "alpha_N", "alpha_U"])),
        domain=((sp.cos(lat) ** 2 - 1e-12, "latitude at a pole"), (R, "R must be positive"),
                (g, "g must be positive")),
        initial_domain=((sp.cos(lat0) ** 2 - 1e-12, "initial latitude at a pole"),),
        notes="Horizontal channels damped by an external velocity reference (gains k_v, k_p).",
    )
