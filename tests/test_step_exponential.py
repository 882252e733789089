"""Batched step exponentials against SciPy's expm and a 40-digit reference."""

from __future__ import annotations

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


def _van_loan_blocks(orthodromic, steps: tuple[np.ndarray, np.ndarray], kind: str
                     ) -> tuple[np.ndarray, int]:
    """Van Loan matrices [[-A, BQBᵀ], [0, Aᵀ]] of one unit noise source at 1 s steps."""
    F, traj_G = steps
    names = [s.name for s in orthodromic.sources]
    name = "gyro_drift_x" if kind == "white" else "accel_bias_x"
    source = cv.SourceStatistics(name, kind, 1.0, None if kind == "white" else 300.0)
    A, BQBt, _ = cv._noise_system(F, traj_G[..., names.index(name)], source,
                                  np.zeros((1, F.shape[-1])), np.zeros(1))
    N = A.shape[-1]
    M = np.zeros((len(A), 2 * N, 2 * N))
    M[:, :N, :N] = -A
    M[:, :N, N:] = BQBt
    M[:, N:, N:] = np.swapaxes(A, -1, -2)
    return M, N


@pytest.mark.parametrize("kind, k", [("white", 0), ("markov", 599)])
def test_van_loan_noise_covariance_equals_a_40_digit_reference(orthodromic, one_second_steps,
                                                               kind, k):
    """The exponential alone is the same series as exp_and_integral (to the bit); on the
    Van Loan blocks of a white gyro noise (‖M‖ ~ 10, ‖M²‖ ~ 10: squarings) at the first
    step and a Markov accelerometer noise at the last, the added covariance Qd = Φ X₁₂
    matches 40 digits to 1e-14 of its largest entry (SciPy's expm of the same blocks is
    ~1e-15 .. 1e-14 off too)."""
    M, N = _van_loan_blocks(orthodromic, one_second_steps, kind)
    X = se.exponential(M, 1.0)
    assert np.array_equal(X, se.exp_and_integral(M, 1.0)[0])
    with mpmath.workdps(40):
        exact = mpmath.expm(mpmath.matrix(M[k]))
        phi_t = exact[N:, N:].T
        Qd_exact = np.array((phi_t * exact[:N, N:]).tolist(), dtype=float)
    Qd = X[k, N:, N:].T @ X[k, :N, N:]
    assert np.abs(Qd - Qd_exact).max() <= 1e-14 * np.abs(Qd_exact).max()
    assert np.abs(X[k, N:, N:] - np.array(exact[N:, N:].tolist(), dtype=float)).max() \
        <= 1e-14
