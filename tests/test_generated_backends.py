"""Generated numpy == generated CasADi == SymPy evaluated in memory (relative 1e-10)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from tests.helpers import random_points


def _close(a, b, rtol=1e-10, atol=1e-15):
    """Relative agreement on the largest entry; atol covers static-base exact zeros that
    come out as rounding residue (1e-18) of cancelling terms."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.abs(a - b).max() <= rtol * np.abs(b).max() + atol


@pytest.fixture(scope="module")
def references(orthodromic, orthodromic_error_model):
    """The in-memory variation lambdified once for both motions: the first-order
    functions, the second-order term and the real right-hand side."""
    error_model = orthodromic_error_model
    d = orthodromic.symbolic
    lambdas = {name: sp.lambdify([d.x, d.u, d.p], getattr(error_model, name), "numpy")
               for name in ("state_matrix", "source_matrix", "output_matrix", "ideal_rhs",
                            "outputs")}
    second = sp.lambdify([d.x, d.u, d.p, d.xe, d.w], error_model.second_order, "numpy")
    real = sp.lambdify([d.real_states, d.x, d.u, d.w, d.p], error_model.real_rhs, "numpy")
    return lambdas, second, real


@pytest.mark.parametrize("moving", [False, True], ids=["static", "moving"])
def test_backends_agree(orthodromic, references, moving):
    lambdas, second, real = references
    rng = np.random.default_rng(7)
    for x, u, p in random_points(orthodromic, 6, seed=11 + moving, moving=moving):
        for name, fn in lambdas.items():
            got_np = getattr(orthodromic.numpy, name)(x, u, p)
            ref = np.asarray(fn(x, u, p), float).reshape(got_np.shape)
            got_ca = np.asarray(orthodromic.casadi.function(name)(x, u, p)).reshape(ref.shape)
            assert _close(got_np, ref), name
            assert _close(got_ca, ref), name
        xe = rng.normal(size=11) * np.r_[np.full(6, 1e-4), 0.1, 0.1, np.full(3, 1e-4)]
        w = rng.normal(size=26) * 1e-5
        ref = np.asarray(second(x, u, p, xe, w), float).ravel()
        assert _close(orthodromic.numpy.second_order(x, u, p, xe, w), ref)
        ca = np.asarray(orthodromic.casadi.function("second_order")(x, u, p, xe, w)).ravel()
        assert _close(ca, ref)
        xr = np.r_[x, 0, 0, 0] + xe
        ref = np.asarray(real(xr, x, u, w, p), float).ravel()
        assert _close(orthodromic.numpy.real_rhs(xr, x, u, w, p), ref)
        assert _close(np.asarray(orthodromic.casadi.function("real_rhs")(xr, x, u, w, p)).ravel(),
                      ref)


def test_numpy_functions_broadcast_over_a_trajectory(orthodromic):
    points = random_points(orthodromic, 5, seed=3, moving=True)
    X = np.stack([x for x, _, _ in points], axis=1)
    U = np.stack([u for _, u, _ in points], axis=1)
    p = points[0][2]
    F = orthodromic.numpy.state_matrix(X, U, p[:, None])
    assert F.shape == (11, 11, 5)
    for k, (x, u, _) in enumerate(points):
        np.testing.assert_array_equal(F[:, :, k], orthodromic.numpy.state_matrix(x, u, p))
