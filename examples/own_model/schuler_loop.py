r"""Single-axis Schuler loop: the simplest inertial navigator.

A platform carries one accelerometer whose sensitive axis points north. The computer
integrates its output into the north velocity V and the velocity into the latitude φ
(Earth a sphere of radius R), and torques the platform's gyro about the west axis at the
rate V/R it believes the local level turns at, so that the platform stays level while
the vehicle moves.

Ideal work (perfect instruments, level platform):

    dV/dt = a_N                 dφ/dt = V / R

Real work (computed quantities with a tilde, ψ the tilt of the platform about west):

    f~ = a_N cos ψ − g sin ψ + ∇          (accelerometer on the tilted platform, bias ∇)
    dV~/dt = f~                           dφ~/dt = V~ / R
    dψ/dt = V~/R − V/R + ε                (commanded − required level rate, gyro drift ε)

To first order the errors δV = V~ − V, δφ = φ~ − φ obey δV' = −g ψ + ∇,
ψ' = δV/R + ε: a harmonic oscillator of period 2π √(R/g) (84.4 min, Schuler).

Modelling choices: the vertical specific force is g (a vehicle at rest or in slow level
motion); only the north channel is modelled; the tilt enters through the exact cos ψ and
sin ψ, so the direct run differs from the linear one at second order in ψ.
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

# -- names, units, LaTeX -------------------------------------------------------------
STATES = (
    Variable("V", "m/s", "north velocity", "V"),
    Variable("phi", "rad", "latitude", r"\varphi"),
)
TILT = Variable("psi", "rad", "platform tilt about the west axis", r"\psi")
INPUTS = (Variable("a_N", "m/s**2", "true north specific force (0 at rest)", "a_N"),)
PARAMETERS = (
    Parameter("R", "m", "Earth radius (sphere)", "R", 6_371_000.0),
    Parameter("g", "m/s**2", "gravity", "g", 9.80665),
)
SOURCES = (
    error_source("gyro_drift", "rad/s", "deg/h", "constant", None, r"\varepsilon",
                 "constant drift of the gyro about the west axis"),
    error_source("accel_bias", "m/s**2", "ug", "constant", None, r"\nabla",
                 "constant bias of the north accelerometer"),
    error_source("initial_tilt", "rad", "arcsec", "initial", None, r"\psi_0",
                 "platform tilt about west when navigation starts"),
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
R, g = (v.symbol for v in PARAMETERS)
drift, bias, tilt0 = (v.symbol for v in SOURCES)


def outputs(eq: Mechanisation, state: list[sp.Symbol], inputs: list[sp.Symbol]) -> sp.Matrix:
    """Latitude and north velocity of a (true or computed) state."""
    velocity, latitude = state
    return sp.Matrix([latitude, velocity])


def build() -> ModelDefinition:
    """The Schuler loop as ideal and real work."""
    # ideal work: the computer fed the true specific force, the platform level
    ideal = Mechanisation()
    omega = ideal.let("omega", V / R, r"\omega")  # rate of the local level about west
    ideal_rhs = sp.Matrix([a_N, omega])

    # real work: the same computer fed the accelerometer on the tilted platform
    real = Mechanisation(computed=True)
    f = real.let("f", a_N * sp.cos(psi) - g * sp.sin(psi) + bias, "f")
    omega_c = real.let("omega", V_c / R, r"\omega")  # commanded torquing rate
    real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])

    lat0, v0 = (v.symbol for v in INITIAL_CONDITIONS)
    return ModelDefinition(
        name="schuler_loop",
        title="Single-axis Schuler loop (north channel)",
        source="ins-errors tutorial examples/own_model",
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
        output_map=outputs,
        initial_state=sp.Matrix([v0, lat0]),
        initial_real_state=sp.Matrix([v0, lat0, tilt0]),
        groups=(("Velocity and position", ["delta_V", "delta_phi"]), ("Tilt", ["psi"])),
        notes="Vertical specific force g; north channel only; exact cos ψ, sin ψ.",
        domain=((R, "Earth radius R must be positive"), (g, "gravity g must be positive")),
        initial_domain=((R, "Earth radius R must be positive"),),
    )
