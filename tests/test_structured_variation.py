"""The paper-style listing (Δω_ξ = ..., ΔV̇_ξ = ... ΔW_ξ ...) says the same as F and G.

Each line of the structured variation only varies one formula; substituting the lines
into each other must give exactly the closed first-order model F xe + G w, evaluated
independently by the generated code.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ins_errors.symbolic.variation import flatten, ideal_intermediate_values, structured_variation
from tests.helpers import random_points


def test_flattened_listing_equals_closed_matrices(orthodromic):
    model = orthodromic
    d = model.symbolic
    lines = structured_variation(d)
    flat = flatten(lines)
    values = ideal_intermediate_values(d)
    names = [v.name for v in d.error_states]
    expressions = []
    for name in names:
        expr = flat[name]
        while expr.free_symbols & set(values):
            expr = expr.xreplace(values)
        expressions.append(expr)
    evaluate = sp.lambdify([d.x, d.u, d.p, d.xe, d.w], expressions, "numpy")
    rng = np.random.default_rng(2)
    for x, u, p in random_points(model, 5, seed=77, moving=True):
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
