r"""An externally velocity-damped local-level platform INS (a test model).

A north-pointing platform on a sphere of radius R turning with the Earth (rate U), at
height 0 (no vertical channel). An external reference (a log, an odometer, a Doppler
radar) gives the velocity v_ref = v + δv_ref; the computer feeds the disagreement
d = ṽ − v_ref back into its velocity (gain k_v) and into the platform's torquing
command (gain k_p):

    dṽ_E/dt = f̃_E + ρ̃ ṽ_N − k_v d_E,      dṽ_N/dt = f̃_N − ρ̃ ṽ_E − k_v d_N,
    ω_E = −(ṽ_N + k_p d_N)/R,   ω_N = U cos φ̃ + (ṽ_E + k_p d_E)/R,
    ω_U = U sin φ̃ + ṽ_E tan φ̃ / R,          ρ̃ = 2U sin φ̃ + ṽ_E tan φ̃ / R,

with f̃ the specific force resolved on the misaligned platform (the exact rotation of
its angles α_E, α_N, α_U). One horizontal channel at U = 0 has the characteristic
polynomial s² + k_v s + (1 + k_p) g/R: with k_v = 1.24e-3/s and k_p = 0 a Schuler loop
of damping ratio 0.5. Both gains default to 0 (the undamped platform).
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
    Variable("alpha_E", "rad", "platform angle about east", r"\alpha_E"),
    Variable("alpha_N", "rad", "platform angle about north", r"\alpha_N"),
    Variable("alpha_U", "rad", "platform azimuth angle", r"\alpha_U"),
)
INPUTS = (
    Variable("a_E", "m/s**2", "east specific force of the motion", "a_E"),
    Variable("a_N", "m/s**2", "north specific force of the motion", "a_N"),
)
PARAMETERS = (
    Parameter("R", "m", "radius of the spherical Earth", "R", 6_371_000.0),
    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),
    Parameter("g", "m/s**2", "gravity", "g", 9.80665),
    Parameter("k_v", "1/s", "velocity damping gain on v~ - v_ref", "k_v", 0.0,
              damping_gain=True, example="1.24e-3/s", example_gives="damping ratio 0.5"),
    Parameter("k_p", "1", "torquing gain on (v~ - v_ref)/R", "k_p", 0.0,
              damping_gain=True, example="0.5", example_gives="Schuler rate x sqrt(1.5)"),
)
SOURCES = (
    error_source("gyro_drift_east", "rad/s", "deg/h", "constant", None, r"\varepsilon_E",
                 "drift of the east gyro"),
    error_source("accel_bias_north", "m/s**2", "ug", "constant", None, r"\nabla_N",
                 "bias of the north accelerometer"),
    error_source("ref_velocity_error_east", "m/s", "m/s", "constant", None, r"\delta v_{rE}",
                 "error of the reference's east velocity"),
    error_source("ref_velocity_error_north", "m/s", "m/s", "constant", None,
                 r"\delta v_{rN}", "error of the reference's north velocity"),
    error_source("initial_tilt_east", "rad", "arcsec", "initial", None, r"\alpha_{E0}",
                 "initial platform angle about east"),
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

R, U, g, k_v, k_p = (q.symbol for q in PARAMETERS)
a_E, a_N = (v.symbol for v in INPUTS)
eps_E, nab_N, dvr_E, dvr_N, tilt_E = (s.symbol for s in SOURCES)


def _computer(eq: Mechanisation, state, f_E, f_N, ref_E, ref_N):
    """Velocity, position and platform-command rates of the computer in ``eq``."""
    v_E, v_N, lat, _ = state
    d_E = eq.let("d_E", v_E - ref_E, "d_E")
    d_N = eq.let("d_N", v_N - ref_N, "d_N")
    rho = eq.let("rho", 2 * U * sp.sin(lat) + v_E * sp.tan(lat) / R, r"\rho")
    rates = [f_E + rho * v_N - k_v * d_E, f_N - rho * v_E - k_v * d_N,
             v_N / R, v_E / (R * sp.cos(lat))]
    command = [eq.let("omega_E", -(v_N + k_p * d_N) / R, r"\omega_E"),
               eq.let("omega_N", U * sp.cos(lat) + (v_E + k_p * d_E) / R, r"\omega_N"),
               eq.let("omega_U", U * sp.sin(lat) + v_E * sp.tan(lat) / R, r"\omega_U")]
    return rates, command


def _outputs(eq, state, inputs):
    v_E, v_N, lat, lon = state
    return sp.Matrix([lat, lon, v_N, v_E])


def build() -> ModelDefinition:
    x = [v.symbol for v in STATES]
    xc = computed_symbols(STATES)
    alpha = [v.symbol for v in ANGLES]
    v_E, v_N, lat, _ = x

    ideal = Mechanisation()
    ideal_rhs, trihedron = _computer(ideal, x, a_E, a_N, v_E, v_N)  # (ref = v: d = 0)
    f_up = g - (v_E**2 + v_N**2) / R - 2 * U * sp.cos(lat) * v_E
    f_E, f_N, _ = on_platform(alpha, (a_E, a_N, f_up))
    real = Mechanisation(computed=True)
    real_rhs, command = _computer(real, xc, f_E, f_N + nab_N, v_E + dvr_E, v_N + dvr_N)
    drift = (eps_E, 0, 0)
    angles = platform_rates(alpha, [w + e for w, e in zip(command, drift, strict=True)],
                            trihedron)
    c = [v.symbol for v in INITIAL_CONDITIONS]
    lat0, lon0, v_N0, v_E0 = c
    return ModelDefinition(
        name="velocity_damped_ins",
        title="Local-level platform INS damped by an external velocity reference",
        source="test model",
        states=STATES,
        error_states=error_states_of(STATES, ANGLES),
        real_states=[*xc, *alpha],
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal,
        real=real,
        ideal_rhs=sp.Matrix(ideal_rhs),
        real_rhs=sp.Matrix([*real_rhs, *angles]),
        output_map=_outputs,
        initial_state=sp.Matrix([v_E0, v_N0, lat0, lon0]),
        initial_real_state=sp.Matrix([v_E0, v_N0, lat0, lon0, tilt_E, 0, 0]),
        groups=(("Velocity", ["delta_V_E", "delta_V_N"]),
                ("Position", ["delta_phi", "delta_lam"]),
                ("Platform", ["alpha_E", "alpha_N", "alpha_U"])),
        domain=((sp.cos(lat) ** 2 - 1e-12, "latitude at a pole"), (R, "R must be positive"),
                (g, "g must be positive")),
        initial_domain=((sp.cos(lat0) ** 2 - 1e-12, "initial latitude at a pole"),),
        notes="Horizontal channels damped by an external velocity reference (k_v, k_p).",
    )
