"""Batched step exponentials against SciPy's expm and a 40-digit reference."""

from __future__ import annotations

from math import factorial

import mpmath
import numpy as np
import pytest
from scipy.linalg import expm
from threadpoolctl import threadpool_limits

from ins_errors.analysis import covariance as cv
from ins_errors.errors import InsErrorsError
from ins_errors.numeric import step_exponential as se
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.linear_system import system_from_trajectory


def _step_system(orthodromic, step: float, duration: float):
    """The orthodromic model's error system along a great circle."""
    profile = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(90), 250.0)
    traj = tr.trajectory(orthodromic, profile, duration, step)
    return system_from_trajectory(orthodromic, traj)


def _step_matrices(orthodromic, step: float, duration: float) -> np.ndarray:
    """Per-step F of the orthodromic model along a great circle, shape (K, 11, 11)."""
    return cv._step_matrix(_step_system(orthodromic, step, duration).F)


@pytest.fixture(scope="module")
def one_second_steps(orthodromic) -> tuple[np.ndarray, np.ndarray]:
    """Per-step F (K, 11, 11) and G (K, 11, sources) at 1 s steps over 600 s, shared."""
    system = _step_system(orthodromic, 1.0, 600.0)
    return cv._step_matrix(system.F), cv._step_matrix(system.G)


def _block_exponential(F: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Φ and W as the blocks of expm([[F, I], [0, 0]] h) (Van Loan).

    With one BLAS thread: SciPy's Padé step on a stack of 22 × 22 matrices spends
    ~100× more CPU waking OpenBLAS's threads than computing (600 steps: 3 s vs 0.03 s
    on a busy 2-core machine); the numbers are the same.
    """
    n = F.shape[-1]
    block = np.zeros((*F.shape[:-2], 2 * n, 2 * n))
    block[..., :n, :n] = F
    block[..., :n, n:] = np.eye(n)
    with threadpool_limits(limits=1, user_api="blas"):
        X = expm(block * h)
    return X[..., :n, :n], X[..., :n, n:]


def _norm(M: np.ndarray) -> np.ndarray:
    return np.abs(M).sum(axis=-2).max(axis=-1)


@pytest.mark.parametrize("step, duration", [(1.0, 600.0), (30.0, 1800.0), (600.0, 36000.0)])
def test_batched_exponential_equals_scipy_on_the_model_steps(orthodromic, one_second_steps,
                                                             step, duration):
    """1 s: no scaling (‖(F h)²‖ ~ 1e-3 though ‖F h‖ ~ 10); 30 s and 600 s: squarings."""
    F = (one_second_steps[0] if step == 1.0 else _step_matrices(orthodromic, step, duration))
    Phi, W = se.exp_and_integral(F, step)
    Phi0, W0 = _block_exponential(F, step)
    assert np.max(_norm(Phi - Phi0) / _norm(Phi0)) < 1e-14
    assert np.max(_norm(W - W0) / _norm(W0)) < 1e-14


def test_batched_exponential_equals_a_40_digit_reference_entry_by_entry(one_second_steps):
    """Entry by entry, where SciPy's own small entries are off by up to ~1e-6 relative:
    the first and the last step of the 10-min great circle."""
    F = one_second_steps[0][[0, 599]]
    Phi, W = se.exp_and_integral(F, 1.0)
    n = F.shape[-1]
    for k in range(len(F)):
        block = np.zeros((2 * n, 2 * n))
        block[:n, :n] = F[k]
        block[:n, n:] = np.eye(n)
        with mpmath.workdps(40):
            exact = np.array(mpmath.expm(mpmath.matrix(block)).tolist(), dtype=float)
        for mine, ref in ((Phi[k], exact[:n, :n]), (W[k], exact[:n, n:])):
            nonzero = ref != 0
            assert np.all(mine[~nonzero] == 0)
            assert np.max(np.abs(mine - ref)[nonzero] / np.abs(ref[nonzero])) < 1e-12


def test_truncation_bound_and_choice():
    """The chosen degree meets the bound and the next lower one does not (or is cheaper
    with fewer squarings); a larger norm needs squarings."""
    s, m = se.choose_scaling(9.8, 1.1e-3)          # the orthodromic model at 1 s
    assert (s, m) == (0, 7)
    assert max(se._tails(9.8, 1.1e-3, 7)) <= se.UNIT_ROUNDOFF
    assert max(se._tails(9.8, 1.1e-3, 5)) > se.UNIT_ROUNDOFF
    s, m = se.choose_scaling(50.0, 50.0**2)
    assert s > 0 and max(se._tails(50.0 / 2**s, 50.0**2 / 4**s, m)) <= se.UNIT_ROUNDOFF
    # a random dense matrix of norm ~ 8: against SciPy
    rng = np.random.default_rng(3)
    A = rng.normal(size=(4, 6, 6))
    Phi, W = se.exp_and_integral(A, 1.0)
    Phi0, W0 = _block_exponential(A, 1.0)
    assert np.max(_norm(Phi - Phi0) / _norm(Phi0)) < 1e-13
    assert np.max(_norm(W - W0) / _norm(W0)) < 1e-13
    with pytest.raises(InsErrorsError, match="not finite"):
        se.exp_and_integral(np.full((1, 2, 2), np.nan), 1.0)


def _unit_noise(orthodromic, steps: tuple[np.ndarray, np.ndarray], kind: str
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, b, BQBᵀ) of one unit noise source along the steps: a white gyro noise or a
    Markov accelerometer noise (τ = 300 s)."""
    F, traj_G = steps
    names = [s.name for s in orthodromic.sources]
    name = "gyro_drift_x" if kind == "white" else "accel_bias_x"
    source = cv.SourceStatistics(name, kind, 1.0, None if kind == "white" else 300.0)
    g = traj_G[..., names.index(name)]
    A, BQBt, _ = cv._noise_system(F, g, source, np.zeros((1, F.shape[-1])), np.zeros(1))
    return A, cv._noise_column(F, g, source)[1], BQBt


def _van_loan_blocks(A: np.ndarray, BQBt: np.ndarray) -> np.ndarray:
    """Van Loan matrices [[-A, BQBᵀ], [0, Aᵀ]] of each step, shape (K, 2N, 2N)."""
    N = A.shape[-1]
    M = np.zeros((len(A), 2 * N, 2 * N))
    M[:, :N, :N] = -A
    M[:, :N, N:] = BQBt
    M[:, N:, N:] = np.swapaxes(A, -1, -2)
    return M


def _block_noise(X: np.ndarray, N: int) -> np.ndarray:
    """The added covariance Qd = Φ X₁₂ read off exponentials X of Van Loan blocks."""
    return np.swapaxes(X[..., N:, N:], -1, -2) @ X[..., :N, N:]


_EXACT: dict[bytes, object] = {}


def _exact_exponential(M: np.ndarray):
    """e^M of one matrix at 40 digits (an mpmath matrix), computed once per matrix in this
    module: the two Van Loan tests below share the blocks of their first two cases."""
    key = np.ascontiguousarray(M).tobytes()
    if key not in _EXACT:
        with mpmath.workdps(40):
            _EXACT[key] = mpmath.expm(mpmath.matrix(M))
    return _EXACT[key]


@pytest.mark.parametrize("kind, k", [("white", 0), ("markov", 599)])
def test_van_loan_noise_covariance_equals_a_40_digit_reference(orthodromic, one_second_steps,
                                                               kind, k):
    """The exponential alone is the same series as exp_and_integral (to the bit); on the
    Van Loan blocks of a white gyro noise (‖M‖ ~ 10, ‖M²‖ ~ 10: squarings) at the first
    step and a Markov accelerometer noise at the last, the added covariance Qd = Φ X₁₂
    matches 40 digits to 1e-14 of its largest entry (SciPy's expm of the same blocks is
    ~1e-15 .. 1e-14 off too)."""
    A, _, BQBt = _unit_noise(orthodromic, one_second_steps, kind)
    M, N = _van_loan_blocks(A, BQBt), A.shape[-1]
    X = se.exponential(M, 1.0)
    assert np.array_equal(X, se.exp_and_integral(M, 1.0)[0])
    exact = _exact_exponential(M[k])
    with mpmath.workdps(40):
        phi_t = exact[N:, N:].T
        Qd_exact = np.array((phi_t * exact[:N, N:]).tolist(), dtype=float)
    Qd = _block_noise(X[k], N)
    assert np.abs(Qd - Qd_exact).max() <= 1e-14 * np.abs(Qd_exact).max()
    assert np.abs(X[k, N:, N:] - np.array(exact[N:, N:].tolist(), dtype=float)).max() \
        <= 1e-14


@pytest.mark.parametrize("kind, step, duration, k", [
    ("white", 1.0, 600.0, 0), ("markov", 1.0, 600.0, 599),
    ("white", 600.0, 36000.0, 59), ("markov", 600.0, 36000.0, 0)])
def test_rank_one_noise_step_equals_the_40_digit_van_loan_blocks(orthodromic, one_second_steps,
                                                                 kind, step, duration, k):
    """Φ and Qd of one noise column from the series of e^{Fσ} b, against the exponential
    of the whole Van Loan block [[-A, b bᵀ], [0, Aᵀ]] h at 40 digits: at 1 s (no scaling)
    and at 600 s (squarings and doublings of Qd), to 1e-14 of Qd's largest entry and of
    Φ's largest entry. At every step it agrees with the block's batched series (which is
    itself up to ~2e-13 off the 40 digits at 600 s, SciPy's expm ~3e-11) to 1e-12."""
    if step == 1.0:
        steps = one_second_steps
    else:
        system = _step_system(orthodromic, step, duration)
        steps = cv._step_matrix(system.F), cv._step_matrix(system.G)
    A, b, BQBt = _unit_noise(orthodromic, steps, kind)
    # b bᵀ is BQBᵀ (to the rounding of √(2/τ)²)
    np.testing.assert_allclose(b[..., :, None] * b[..., None, :], BQBt, rtol=1e-15, atol=0)
    Phi, Qd = se.rank_one_noise_step(A, b, step)
    M, N = _van_loan_blocks(A, BQBt), A.shape[-1]
    exact = _exact_exponential(M[k] * step)
    with mpmath.workdps(40):
        phi = exact[N:, N:].T
        Qd_exact = np.array((phi * exact[:N, N:]).tolist(), dtype=float)
        Phi_exact = np.array(phi.tolist(), dtype=float)
    assert np.abs(Qd[k] - Qd_exact).max() <= 1e-14 * np.abs(Qd_exact).max()
    assert np.abs(Phi[k] - Phi_exact).max() <= 1e-14 * np.abs(Phi_exact).max()
    assert np.array_equal(Qd, np.swapaxes(Qd, -1, -2))
    assert np.all(np.linalg.eigvalsh(Qd[k]) >= -1e-14 * np.abs(Qd_exact).max())
    Qd_block = _block_noise(se.exponential(M, step), N)
    scale = np.abs(Qd_block).max(axis=(-2, -1), keepdims=True)
    assert np.all(np.abs(Qd - Qd_block) <= 1e-12 * scale)
    # several noise columns at once: the same transition, one Qd per column
    e = np.zeros_like(b)
    e[:, 0] = 1e-3                                     # a second, different noise
    Phi2, Qd2 = se.rank_one_noise_step(A, np.stack([b, e], axis=-1), step)
    assert Qd2.shape == (len(A), 2, N, N) and np.array_equal(Phi2, Phi)
    assert np.all(np.abs(Qd2[:, 0] - Qd) <= 1e-15 * scale)
    np.testing.assert_allclose(Qd2[:, 1], se.rank_one_noise_step(A, e, step)[1],
                               rtol=0, atol=1e-15 * np.abs(Qd2[:, 1]).max())


def test_moment_degree_meets_its_bound():
    """The chosen degree's neglected terms are below the target, one degree less is not;
    larger norms need more terms; a non-finite noise column is one line."""
    for a1, a2, n in ((9.8, 1.1e-3, 11), (300.0, 0.9, 12), (2.0**10, 1.0, 12)):
        d = se._moment_degree(a1, a2, n)
        beta = [a2 ** (k // 2) * a1 ** (k % 2) / factorial(k) for k in range(120)]
        total = sum(beta)
        assert 2 * sum(beta[d + 1:]) * total <= se.UNIT_ROUNDOFF / n**2
        assert 2 * sum(beta[d:]) * total > se.UNIT_ROUNDOFF / n**2
    assert se._moment_degree(9.8, 1.1e-3, 11) < se._moment_degree(300.0, 0.9, 12)
    with pytest.raises(InsErrorsError, match="noise column is not finite"):
        se.rank_one_noise_step(np.zeros((1, 2, 2)), np.array([[np.nan, 0.0]]), 1.0)
