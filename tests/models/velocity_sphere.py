r"""Test fixture: a horizontal navigator on a sphere whose initial velocities are named
v_N0, v_E0 (its states are v_N, v_E).

    v̇_N = a_N,  v̇_E = a_E,  φ̇ = v_N / R,  λ̇ = v_E / (R cos φ)

The inputs a_N, a_E are apparent accelerations the kinematic motion generators set, so
the model follows moving motions given as north and east velocities (a motion file);
it has no heading output, so no great circle. The real work adds accelerometer biases.
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
    Variable("v_N", "m/s", "north velocity", "v_N"),
    Variable("v_E", "m/s", "east velocity", "v_E"),
    Variable("lat", "rad", "latitude", r"\varphi"),
    Variable("lon", "rad", "longitude", r"\lambda"),
)
INPUTS = (
    Variable("a_N", "m/s**2", "north apparent acceleration", "a_N"),
    Variable("a_E", "m/s**2", "east apparent acceleration", "a_E"),
)
PARAMETERS = (Parameter("R", "m", "radius of the sphere", "R", 6_371_000.0),)
SOURCES = (
    error_source("accel_bias_N", "m/s**2", "ug", "constant", None, r"\nabla_N",
                 "bias of the north accelerometer"),
    error_source("accel_bias_E", "m/s**2", "ug", "constant", None, r"\nabla_E",
                 "bias of the east accelerometer"),
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
    Variable("v_N0", "m/s", "initial north velocity", "v_{N0}"),
    Variable("v_E0", "m/s", "initial east velocity", "v_{E0}"),
)
NAMES = {v.name: v.symbol for v in (*STATES, *INPUTS, *PARAMETERS, *SOURCES,
                                     *INITIAL_CONDITIONS)}


def navigator(state, accelerations) -> sp.Matrix:
    v_n, v_e, lat, _ = state
    R = NAMES["R"]
    return sp.Matrix([*accelerations, v_n / R, v_e / (R * sp.cos(lat))])


def build() -> ModelDefinition:
    x, x_c = [v.symbol for v in STATES], computed_symbols(STATES)
    a = [NAMES["a_N"], NAMES["a_E"]]
    measured = [a[0] + NAMES["accel_bias_N"], a[1] + NAMES["accel_bias_E"]]
    n = NAMES
    start = sp.Matrix([n["v_N0"], n["v_E0"], n["latitude"], n["longitude"]])
    return ModelDefinition(
        name="velocity_sphere", title="Horizontal velocity navigator (test fixture)",
        source="tests", states=STATES, error_states=error_states_of(STATES, ()),
        real_states=x_c, inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES,
        outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS, ideal=Mechanisation(),
        real=Mechanisation(computed=True), ideal_rhs=navigator(x, a),
        real_rhs=navigator(x_c, measured),
        output_map=lambda eq, s, u: sp.Matrix([s[2], s[3], s[0], s[1]]),
        initial_state=start, initial_real_state=start,
        domain=((sp.cos(x[2]) ** 2 - 1e-12, "latitude at a pole"),),
        initial_domain=((sp.cos(n["latitude"]) ** 2 - 1e-12, "initial latitude at a pole"),),
    )
