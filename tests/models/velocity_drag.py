r"""Test fixture: a 2-D velocity damped by quadratic drag, whose F is 0/0 at rest.

The computer integrates the north and east specific forces into the horizontal velocity
V = (V_N, V_E) and damps it with a drag c |V| V, |V| = sqrt(V_N² + V_E²):

    ideal:  dV_N/dt = a_N − c |V| V_N,    dV_E/dt = a_E − c |V| V_E
    real:   the same on the computed velocity, with accelerometer biases ∇_N, ∇_E

The drag is smooth in V except at V = 0, where |V| has a cone: the derivative
∂(|V| V_N)/∂V_N = |V| + V_N²/|V| is 0/0 there, so the generated F is NaN at rest (the
static base) although the equations themselves are finite and the direct run stays in
its domain.
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
    Variable("V_N", "m/s", "north velocity", "V_N"),
    Variable("V_E", "m/s", "east velocity", "V_E"),
)
INPUTS = (
    Variable("a_N", "m/s**2", "north specific force (0 at rest)", "a_N"),
    Variable("a_E", "m/s**2", "east specific force (0 at rest)", "a_E"),
)
PARAMETERS = (Parameter("c", "1/m", "quadratic drag coefficient", "c", 1e-3),)
SOURCES = (
    error_source("accel_bias_N", "m/s**2", "ug", "constant", None, r"\nabla_N",
                 "bias of the north accelerometer"),
    error_source("accel_bias_E", "m/s**2", "ug", "constant", None, r"\nabla_E",
                 "bias of the east accelerometer"),
)
OUTPUTS = (
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
)
INITIAL_CONDITIONS = (
    Variable("v_N", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_E", "m/s", "initial east velocity", "v_{E0}"),
)

V_N, V_E = (v.symbol for v in STATES)
a_N, a_E = (v.symbol for v in INPUTS)
(c,) = (v.symbol for v in PARAMETERS)
bias_N, bias_E = (v.symbol for v in SOURCES)


def velocity(eq: Mechanisation, state, inputs) -> sp.Matrix:
    """The velocity outputs of a (true or computed) state."""
    return sp.Matrix(list(state))


def dynamics(eq: Mechanisation, state, force) -> sp.Matrix:
    """The computer: specific force less quadratic drag."""
    v_n, v_e = state
    speed = eq.let("speed", sp.sqrt(v_n ** 2 + v_e ** 2), "|V|")
    return sp.Matrix([force[0] - c * speed * v_n, force[1] - c * speed * v_e])


def build() -> ModelDefinition:
    """The drag-damped velocity as ideal and real work."""
    v0 = [v.symbol for v in INITIAL_CONDITIONS]
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    return ModelDefinition(
        name="velocity_drag",
        title="2-D velocity with quadratic drag (test: F is 0/0 at rest)",
        source="test fixture",
        states=STATES,
        error_states=error_states_of(STATES, ()),
        real_states=computed_symbols(STATES),
        inputs=INPUTS,
        parameters=PARAMETERS,
        sources=SOURCES,
        outputs=OUTPUTS,
        initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal,
        real=real,
        ideal_rhs=dynamics(ideal, [V_N, V_E], [a_N, a_E]),
        real_rhs=dynamics(real, computed_symbols(STATES), [a_N + bias_N, a_E + bias_E]),
        output_map=velocity,
        initial_state=sp.Matrix(v0),
        initial_real_state=sp.Matrix(v0),
    )
