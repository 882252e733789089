r"""Test fixture: a single-axis Schuler loop damped by an external velocity reference.

The north channel of a level platform on a sphere of radius R (no Earth rate). A log
(or Doppler) gives the reference velocity v_ref = V + δv_r; the computer feeds the
disagreement back into its velocity with the gain k_v (1/s):

    ideal:  dV/dt = a_N,  dφ/dt = V / R
    real:   f~ = a_N cos ψ − g sin ψ + ∇
            dV~/dt = f~ − k_v (V~ − v_ref),  dφ~/dt = V~ / R
            dψ/dt = V~/R − V/R + ε            (ψ: tilt about west, ε: gyro drift)

To first order δV' = −g ψ − k_v δV + k_v δv_r + ∇ and ψ' = δφ' = δV/R: the loop's
characteristic polynomial is s² + k_v s + g/R (damping ratio k_v / (2 √(g/R))). A
constant reference error δv_r leaves the tilt (and the latitude error) at k_v δv_r / g.
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
    Variable("V", "m/s", "north velocity", "V"),
    Variable("phi", "rad", "latitude", r"\varphi"),
)
TILT = Variable("psi", "rad", "platform tilt about the west axis", r"\psi")
INPUTS = (Variable("a_N", "m/s**2", "true north specific force (0 at rest)", "a_N"),)
PARAMETERS = (
    Parameter("R", "m", "Earth radius (sphere)", "R", 6_371_000.0),
    Parameter("g", "m/s**2", "gravity", "g", 9.80665),
    Parameter("k_v", "1/s", "velocity damping gain on V~ - v_ref", "k_v", 0.0,
              damping_gain=True, example="1.24e-3/s",
              example_gives="Schuler damping ratio 0.5"),
)
SOURCES = (
    error_source("gyro_drift", "rad/s", "deg/h", "constant", None, r"\varepsilon",
                 "constant drift of the gyro about the west axis"),
    error_source("accel_bias", "m/s**2", "ug", "constant", None, r"\nabla",
                 "constant bias of the north accelerometer"),
    error_source("ref_velocity_error", "m/s", "m/s", "constant", None, r"\delta v_r",
                 "constant error of the reference (log) velocity"),
)
OUTPUTS = (
    Variable("latitude", "rad", "latitude", r"\varphi"),
    Variable("v_N", "m/s", "north velocity", "v_N"),
)
INITIAL_CONDITIONS = (
    Variable("latitude", "rad", "initial latitude", r"\varphi_0"),
    Variable("v_N", "m/s", "initial north velocity", "v_{N0}"),
)

V, phi = (v.symbol for v in STATES)
V_c, phi_c = computed_symbols(STATES)
psi = TILT.symbol
(a_N,) = (v.symbol for v in INPUTS)
R, g, k_v = (v.symbol for v in PARAMETERS)
drift, bias, ref_error = (v.symbol for v in SOURCES)


def build() -> ModelDefinition:
    """The damped loop as ideal and real work (the ideal computer's reference is exact)."""
    ideal = Mechanisation()
    omega = ideal.let("omega", V / R, r"\omega")
    ideal_rhs = sp.Matrix([a_N, omega])  # the exact reference: no feedback

    real = Mechanisation(computed=True)
    f = real.let("f", a_N * sp.cos(psi) - g * sp.sin(psi) + bias, "f")
    omega_c = real.let("omega", V_c / R, r"\omega")
    real_rhs = sp.Matrix([f - k_v * (V_c - (V + ref_error)), omega_c,
                          omega_c - omega + drift])

    lat0, v0 = (v.symbol for v in INITIAL_CONDITIONS)
    return ModelDefinition(
        name="damped_schuler",
        title="Single-axis Schuler loop damped by a reference velocity (test fixture)",
        source="tests",
        states=STATES,
        error_states=error_states_of(STATES, [TILT]),
        real_states=[V_c, phi_c, psi],
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal,
        real=real,
        ideal_rhs=ideal_rhs,
        real_rhs=real_rhs,
        output_map=lambda eq, s, u: sp.Matrix([s[1], s[0]]),
        initial_state=sp.Matrix([v0, lat0]),
        initial_real_state=sp.Matrix([v0, lat0, 0]),
        domain=((R, "Earth radius R must be positive"), (g, "gravity g must be positive")),
        initial_domain=((R, "Earth radius R must be positive"),
                        (g, "gravity g must be positive")),
    )
