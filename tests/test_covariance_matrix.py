"""The functionals' whole covariance matrix (``propagate(..., cross=True)``) against a
covariance carried step by step on the full augmented state with SciPy's ``expm`` (one
Van Loan pair for every source at once), and against the sample covariance of linear
Monte Carlo runs."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm as scipy_expm
from threadpoolctl import threadpool_limits

from ins_errors.analysis import covariance as cv
from ins_errors.analysis import monte_carlo as mc
from ins_errors.numeric import trajectories as tr

PHI = np.radians(50.0)
DEG_H = np.radians(1.0) / 3600.0

SOURCES = [cv.SourceStatistics("initial_tilt_x", "constant", 1e-4),
           cv.SourceStatistics("initial_azimuth_error", "constant", 3e-4),
           cv.SourceStatistics("accel_bias_x", "constant", 5e-4),
           cv.SourceStatistics("accel_bias_y", "markov", 3e-4, tau=1200.0),
           cv.SourceStatistics("gyro_drift_x", "constant", 0.01 * DEG_H),
           cv.SourceStatistics("gyro_drift_x", "white", 0.002 * DEG_H * 60.0),
           cv.SourceStatistics("gyro_drift_z", "markov", 0.02 * DEG_H, tau=3600.0)]


def reference_matrices(system: cv.LinearSystem, functionals: cv.Functionals,
                       sources) -> np.ndarray:
    """``C P_k Cᵀ`` at every grid time, P carried on ``(x_e, one value per constant or
    Markov source)`` with every noise in one Van Loan pair per step (F, G held at the
    mean of the step's ends), shape (K + 1, q, q)."""
    n = system.E.shape[0]
    index = list(system.source_names)
    valued = [s for s in sources if s.kind != "white"]
    m = len(valued)
    N = n + m
    K = len(system.times) - 1
    F = np.broadcast_to(system.F, (K + 1, n, n)) if system.F.ndim == 2 else system.F
    G = np.broadcast_to(system.G, (K + 1, *system.G.shape)) if system.G.ndim == 2 \
        else system.G
    C_x = functionals.C_x if functionals.C_x.ndim == 3 else \
        np.broadcast_to(functionals.C_x, (K + 1, *functionals.C_x.shape))
    # the initial covariance: x_e(0) = E b(0), the values unit-scaled by σ
    S = np.zeros((N, m))
    for j, s in enumerate(valued):
        S[:n, j] = system.E[:, index.index(s.name)] * s.sigma
        S[n + j, j] = s.sigma
    P = S @ S.T
    C_b = np.column_stack([functionals.C_b[:, index.index(s.name)] for s in valued])
    out = np.empty((K + 1, C_x.shape[1], C_x.shape[1]))
    for k in range(K + 1):
        C = np.hstack([C_x[k], C_b])
        out[k] = C @ P @ C.T
        if k == K:
            break
        Fk, Gk = 0.5 * (F[k] + F[k + 1]), 0.5 * (G[k] + G[k + 1])
        A = np.zeros((N, N))
        A[:n, :n] = Fk
        Q = np.zeros((N, N))
        for j, s in enumerate(valued):
            A[:n, n + j] = Gk[:, index.index(s.name)]
            if s.kind == "markov":
                A[n + j, n + j] = -1.0 / s.tau
                Q[n + j, n + j] = 2.0 * s.sigma**2 / s.tau
        for s in sources:
            if s.kind == "white":
                g = np.zeros(N)
                g[:n] = Gk[:, index.index(s.name)]
                Q += np.outer(g, g) * s.sigma**2
        block = np.zeros((2 * N, 2 * N))
        block[:N, :N], block[:N, N:], block[N:, N:] = -A, Q, A.T
        with threadpool_limits(limits=1, user_api="blas"):
            V = scipy_expm(block * system.step)
        Phi = V[N:, N:].T
        Qd = Phi @ V[:N, N:]
        P = Phi @ P @ Phi.T + 0.5 * (Qd + Qd.T)
    return out


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    """Largest difference of two stacks of covariance matrices per the product of the
    reference's standard deviations (a correlation-sized error)."""
    std = np.sqrt(np.maximum(np.einsum("kii->ki", b), 0.0))
    scale = std[:, :, None] * std[:, None, :]
    live = scale > 1e-30 * scale.max()
    return float(np.max(np.abs(a - b)[live] / scale[live]))


@pytest.fixture(scope="module")
def static_2h(orthodromic):
    return cv.static_system(orthodromic, PHI, duration=2 * 3600.0, step=60.0, gravity=9.81)


def test_the_static_matrix_is_the_full_state_van_loan_covariance(orthodromic, static_2h):
    functionals = cv.state_and_output_functionals(orthodromic, static_2h)
    c = cv.propagate(static_2h, SOURCES, functionals, cross=True)
    reference = reference_matrices(static_2h, functionals, SOURCES)
    assert c.matrix.shape == reference.shape
    assert _relative(c.matrix, reference) < 1e-9
    # the cross terms are not negligible: the tilt and the velocity error swing together
    rho = c.correlation[-1]
    assert np.max(np.abs(rho - np.diag(np.diag(rho)))) > 0.5


def test_the_variances_are_the_same_numbers_with_or_without_cross(orthodromic, static_2h):
    functionals = cv.state_and_output_functionals(orthodromic, static_2h)
    plain = cv.propagate(static_2h, SOURCES, functionals)
    full = cv.propagate(static_2h, SOURCES, functionals, cross=True)
    assert np.array_equal(plain.unit_variances, full.unit_variances)
    diagonal = np.einsum("kiis->kis", full.unit_covariances)
    np.testing.assert_allclose(diagonal, plain.unit_variances, rtol=1e-10,
                               atol=1e-12 * plain.unit_variances.max())
    np.testing.assert_allclose(np.trace(full.matrix, axis1=1, axis2=2),
                               plain.variance.sum(-1), rtol=1e-10)
    total = cv.propagate(static_2h, SOURCES, functionals, by_source=False, cross=True)
    np.testing.assert_allclose(total.matrix, full.matrix, rtol=1e-12,
                               atol=1e-14 * np.abs(full.matrix).max())


def test_the_moving_matrix_is_the_full_state_van_loan_covariance(orthodromic):
    motion = tr.trajectory(orthodromic, tr.great_circle_profile(PHI, 0.5, np.radians(60),
                                                                250.0), 1200.0, 1.0)
    system = cv.system_from_trajectory(orthodromic, motion, 20.0)
    assert not system.time_invariant
    functionals = cv.state_and_output_functionals(orthodromic, system)
    c = cv.propagate(system, SOURCES, functionals, output_every=3, cross=True)
    reference = reference_matrices(system, functionals, SOURCES)[::3]
    assert _relative(c.matrix, reference) < 1e-9


def test_the_matrix_is_the_sample_covariance_of_monte_carlo_runs(orthodromic, static_2h):
    """Independent of any discretisation of the covariance: RK4 runs of sampled sources
    (constants, white and Markov noise), 4000 of them, agree with the propagated
    correlation coefficients within their sampling error (1/√N ≈ 0.016 per coefficient,
    here four of them)."""
    system = cv.static_system(orthodromic, PHI, duration=3600.0, step=60.0, gravity=9.81)
    functionals = cv.state_and_output_functionals(orthodromic, system)
    c = cv.propagate(system, SOURCES, functionals, cross=True)
    runs = mc.linear_monte_carlo(system, SOURCES, functionals, 4000, seed=11)
    x = runs.samples[-1]                                        # (q, N)
    sample = x @ x.T / x.shape[1]
    std = np.sqrt(np.diag(sample))
    live = std > 0
    sample_rho = sample[np.ix_(live, live)] / np.outer(std[live], std[live])
    assert np.max(np.abs(sample_rho - c.correlation[-1][np.ix_(live, live)])) < 4 / np.sqrt(4000)


def test_a_variances_only_result_says_how_to_get_the_matrix(orthodromic, static_2h):
    functionals = cv.state_and_output_functionals(orthodromic, static_2h)
    c = cv.propagate(static_2h, SOURCES[:1], functionals)
    with pytest.raises(cv.CovarianceError, match=r"cross=True"):
        c.matrix  # noqa: B018
