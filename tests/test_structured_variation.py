"""The paper-style listing (Δω_ξ = ..., ΔV̇_ξ = ... ΔW_ξ ...) says the same as F and G.

Each line of the structured variation only varies one formula; substituting the lines
into each other must give exactly the closed first-order model F xe + G w, evaluated
independently by the generated code.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import ins_errors
from ins_errors.symbolic.variation import flatten, ideal_intermediate_values, structured_variation


def _generic_points(model, count: int, seed: int):
    """Random admissible (x, u, p) of any model, from its own initial-state map."""
    rng = np.random.default_rng(seed)
    p = model.parameter_vector()
    ranges = {"latitude": (-1.2, 1.2), "longitude": (-3, 3), "heading": (-3, 3),
              "v_N": (-200, 200), "v_E": (-200, 200), "a_zeta": (8, 12), "h": (0, 5000),
              "V_zeta": (-10, 10)}
    points = []
    while len(points) < count:
        c = np.array([rng.uniform(*ranges.get(i.name, (0, 0))) for i in model.initial_conditions])
        u = np.array([rng.uniform(*ranges.get(i.name, (-3, 3) if i.name.startswith("a_")
                                              else (0, 0))) for i in model.inputs])
        if np.all(model.numpy.initial_domain_margins(c, u, p) > 0):
            x = model.initial_state(c, u, p)
            if np.all(model.numpy.domain_margins(x, u, p) > 0):
                points.append((x, u, p))
    return points


@pytest.mark.parametrize("name", ins_errors.available_models())
def test_flattened_listing_equals_closed_matrices(name):
    model = ins_errors.load_model(name)
    d = model.symbolic
    lines = structured_variation(d)
    flat = flatten(lines)
    values = ideal_intermediate_values(d)
    names = [v.name for v in d.error_states]
    expressions = [flat[name] for name in names]
    # the ideal intermediate symbols are evaluated first, each from its closed expression
    # (those it uses before it), then the listing: numerically the same as substituting
    # them into the listing, without printing each closed expression once per use
    order: list[sp.Symbol] = []

    def visit(expr: sp.Expr) -> None:
        for symbol in sorted(expr.free_symbols & values.keys(), key=sp.default_sort_key):
            if symbol not in order:
                visit(values[symbol])
                order.append(symbol)

    for expr in expressions:
        visit(expr)
    evaluate = sp.lambdify([d.x, d.u, d.p, d.xe, d.w], expressions, "numpy",
                           cse=lambda exprs: ([(s, values[s]) for s in order], exprs))
    rng = np.random.default_rng(2)
    for x, u, p in _generic_points(model, 5, seed=77):
        xe = rng.normal(size=len(names))
        w = rng.normal(size=len(d.w))
        expected = model.state_matrix(x, u, p) @ xe + model.source_matrix(x, u, p) @ w
        got = np.array(evaluate(x, u, p, xe, w), dtype=float)
        np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


def test_listing_reads_like_the_manual(orthodromic):
    """Spot checks against the manual's correct lines (independent of the code)."""
    lines = {line.name: line for line in structured_variation(orthodromic.symbolic)}
    s = {name: sp.Symbol(name, real=True) for name in (
        "U", "delta_u31", "alpha_x", "alpha_y", "alpha_z", "omega_xi", "omega_eta",
        "omega_zeta", "Delta_omega_xi", "gyro_drift_x", "correction_gain_error_x")}
    # Δω_ζ = U cos φ Δφ = U Δu31
    assert sp.simplify(lines["omega_zeta"].rhs - s["U"] * s["delta_u31"]) == 0
    # α̇_x = −ω_η α_z + ω_ζ α_y + Δω_ξ + drift (+ the correction-loop gain term)
    expected = (-s["omega_eta"] * s["alpha_z"] + s["omega_zeta"] * s["alpha_y"]
                + s["Delta_omega_xi"] + s["gyro_drift_x"]
                + s["correction_gain_error_x"] * s["omega_xi"])
    assert sp.expand(lines["alpha_x"].rhs - expected) == 0
