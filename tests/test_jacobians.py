"""The derived matrices against central finite differences of the model's own functions.

F and G must equal the derivatives of the real-work right-hand side around the ideal
motion; H those of the outputs; E those of the initial real state. The second-order term
must take the residual of the linear model from O(ε²) to O(ε³).
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.helpers import central_difference, random_points, row_relative_error, source_steps

# finite-difference steps per error-state component: direction cosines, velocities, angles
STATE_STEPS = np.r_[np.full(6, 1e-6), 1e-3, 1e-3, np.full(3, 1e-6)]





@pytest.mark.parametrize("moving", [False, True], ids=["static", "moving"])
def test_state_and_source_matrices_equal_finite_differences(orthodromic, moving):
    model = orthodromic
    n_w = len(model.sources)
    for x, u, p in random_points(model, 12, seed=100 + moving, moving=moving):
        xr0 = np.r_[x, 0.0, 0.0, 0.0]
        w0 = np.zeros(n_w)
        F_fd = central_difference(lambda xr: model.numpy.real_rhs(xr, x, u, w0, p),  # noqa: B023
                                   xr0, STATE_STEPS)
        G_fd = central_difference(lambda w: model.numpy.real_rhs(xr0, x, u, w, p),  # noqa: B023
                                   w0, source_steps(model))
        assert row_relative_error(F_fd, model.state_matrix(x, u, p)) < 1e-6
        assert row_relative_error(G_fd, model.source_matrix(x, u, p)) < 1e-6


def test_real_work_reduces_to_ideal_work_without_errors(orthodromic):
    model = orthodromic
    for x, u, p in random_points(model, 10, seed=5, moving=True):
        real = model.real_rhs(np.r_[x, 0, 0, 0], x, u, np.zeros(len(model.sources)), p)
        ideal = model.ideal_rhs(x, u, p)
        np.testing.assert_allclose(real[:8], ideal, rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(real[8:], 0.0, atol=1e-18)


def test_output_matrix_equals_finite_differences(orthodromic):
    model = orthodromic
    for x, u, p in random_points(model, 10, seed=9, moving=True):
        H_fd = central_difference(lambda xx: model.numpy.outputs(xx, u, p),  # noqa: B023
                                   x, STATE_STEPS[:8])
        H = model.output_matrix(x, u, p)
        assert np.all(H[:, 8:] == 0)
        assert row_relative_error(H_fd, H[:, :8]) < 1e-6


def test_initial_error_matrix_equals_finite_differences(orthodromic):
    model = orthodromic
    p = model.parameter_vector()
    rng = np.random.default_rng(4)
    for _ in range(10):
        c = model.initial_condition_vector(latitude=rng.uniform(-1.3, 1.3),
                                           longitude=rng.uniform(-3, 3),
                                           heading=rng.uniform(-3, 3),
                                           v_N=rng.uniform(-200, 200), v_E=rng.uniform(-200, 200))
        u = model.input_vector(h=rng.uniform(0, 5000))
        E_fd = central_difference(lambda w: model.numpy.initial_real_state(c, u, w, p),  # noqa: B023
                                   np.zeros(len(model.sources)), source_steps(model))
        assert row_relative_error(E_fd, model.initial_error_matrix(c, u, p)) < 1e-6
        # with no errors the real system starts exactly on the true state, platform level
        start = model.initial_real_state(c, u, np.zeros(len(model.sources)), p)
        np.testing.assert_allclose(start, np.r_[model.initial_state(c, u, p), 0, 0, 0],
                                   rtol=1e-14, atol=1e-12)


def test_second_order_term_removes_the_quadratic_residual(orthodromic):
    """f~(x + εxe, εw) − f(x) − ε(F xe + G w) is O(ε²); minus ε²S it is O(ε³)."""
    model = orthodromic
    rng = np.random.default_rng(21)
    for x, u, p in random_points(model, 6, seed=31, moving=True):
        xe = rng.normal(size=11) * np.r_[np.full(6, 1e-3), 1.0, 1.0, np.full(3, 1e-3)]
        w = rng.normal(size=len(model.sources)) * source_steps(model) * 1e3
        F, G = model.state_matrix(x, u, p), model.source_matrix(x, u, p)
        S = model.second_order(x, u, xe, w, p)
        ideal = np.r_[model.ideal_rhs(x, u, p), 0, 0, 0]
        lin_residuals, refined_residuals = [], []
        for eps in (1e-1, 5e-2):
            real = model.numpy.real_rhs(np.r_[x, 0, 0, 0] + eps * xe, x, u, eps * w, p)
            linear = real - ideal - eps * (F @ xe + G @ w)
            lin_residuals.append(np.abs(linear).max())
            refined_residuals.append(np.abs(linear - eps**2 * S).max())
        # halving ε: quadratic residual falls ~4x, cubic ~8x
        assert 3.5 < lin_residuals[0] / lin_residuals[1] < 4.5
        assert refined_residuals[0] / refined_residuals[1] > 7.0
        assert refined_residuals[0] < 0.1 * lin_residuals[0]
