"""The numerical reduction behind :mod:`ins_errors.analysis.transfer`: one pair's
W(s) = h (sI − F)⁻¹ g as gain, zeros and poles.

The states are measured in given units (the Schuler loop's, optionally balanced) and F
divided by its norm, so that a tolerance is a share of 1. A pair's minimal realisation
keeps the part of (F, g) the source reaches (an orthonormal Krylov basis of g, F g,
F² g, ...) and of that the part h sees (the same on (Fᵀ, hᵀ)); its poles are the
eigenvalues of the minimal F, its zeros those of its zero dynamics, its gain the first
non-zero Markov parameter. Computed roots within :data:`GROUP_SAFETY` times their
accuracy are one repeated root, and a zero within :data:`CANCEL` of a pole (or within
their accuracies) cancels it. :func:`markov_zero` proves W = 0 from the Markov
parameters against their componentwise bounds.

Nothing here names a mode or writes a word: that is :mod:`ins_errors.analysis.transfer`
(the modes) and :mod:`ins_errors.analysis.transfer_text` (the report).
"""

from __future__ import annotations

import numpy as np

from ins_errors.analysis.modes import ZERO

TOLERANCE = 1e-9
"""A direction of the Krylov bases (what a source reaches, what an output sees) and a
Markov parameter are zero below this share, with the states in the units of the Schuler
loop and F divided by its norm (so every entry is at most 1): the first, coarsest
reduction tried (:data:`~ins_errors.analysis.transfer.REDUCTIONS`)."""

BALANCE_LIMIT = 20
"""The balancing factors are kept within 2^±this (a state nothing depends on would get
an unbounded one)."""

CANCEL = 1e-9
"""A zero closer to a pole than this share of the pole's size cancels it (a pole and a
zero at 0 are one root already, :data:`~ins_errors.analysis.modes.ZERO`): the mode's
part in W is then at the level of the roots' rounding (a weakly reachable and weakly
seen mode that the Krylov bases kept, e.g. strapdown_ned's vertical channel in a
horizontal output near the equator)."""

GROUP_SAFETY = 100.0
"""Two computed roots are one (repeated) root when they are closer than this many times
the larger of their first-order accuracies κ δ ‖M‖ (:func:`_roots`). A repeated root of a
minimal realisation is a Jordan block, which rounding splits into roots a few times
their κ δ ‖M‖ apart; two distinct roots are apart by far more than theirs (the two
Schuler ± Foucault pairs within 1e-4° of the equator, 1e-7 of their size apart, stay
two)."""



def group_tolerance(eigenvalues: np.ndarray) -> float:
    """The size below which a root's real or imaginary part is zero, 1/s:
    :data:`~ins_errors.analysis.modes.ZERO` of F's largest |λ| (``eigenvalues``; the
    smallest positive float when F has none)."""
    radius = float(np.abs(eigenvalues).max()) if len(eigenvalues) else 0.0
    return ZERO * radius if radius > 0 else np.finfo(float).tiny


class Reduction:
    """The minimal realisation and factored form of each pair of one F.

    The states are measured in the units of the Schuler loop (``factors``: x̂ = D x;
    ``balanced``: then evened out by a diagonal similarity, its factors within
    2^±:data:`BALANCE_LIMIT`) and time in units of 1/‖D F D⁻¹‖, so that ``tolerance`` is
    a share of 1.

    Parameters
    ----------
    F : ndarray, shape (n, n)
        The state matrix, SI (1/s in the states' units).
    factors : ndarray, shape (n,)
        Per state, the factor that measures it in the units of the Schuler loop.
    group_tolerance : float
        A root's real or imaginary part below this is zero, 1/s (:func:`group_tolerance`).
    balanced : bool
        Balance the scaled F too.
    tolerance : float
        A Krylov direction or Markov parameter below this share is zero.
    """

    def __init__(self, F: np.ndarray, factors: np.ndarray, group_tolerance: float,
                 balanced: bool = False, tolerance: float = TOLERANCE):
        self.D = np.asarray(factors, dtype=float)
        self.tolerance = tolerance
        scaled = self.D[:, None] * F / self.D[None, :]
        if balanced:
            from scipy.linalg import matrix_balance

            scale = matrix_balance(scaled, permute=False, separate=True)[1][0]
            scale = np.clip(scale, 2.0 ** -BALANCE_LIMIT, 2.0 ** BALANCE_LIMIT)
            self.D = self.D / scale
            scaled = scaled * scale[None, :] / scale[:, None]
        self.rho = float(np.linalg.norm(scaled, 2)) or 1.0
        self.A = scaled / self.rho
        self.group_tolerance = group_tolerance

    def factor(self, g: np.ndarray, h: np.ndarray
               ) -> tuple[float, int, list[tuple[complex, int]], list[tuple[complex, int]]]:
        """(K, relative degree, zeros, poles) of h (sI − F)⁻¹ g, the roots as (root with
        Im >= 0, multiplicity), 1/s, by increasing size; (0, 0, [], []) for W = 0.

        Parameters
        ----------
        g : ndarray, shape (n,)
            The source's column (SI).
        h : ndarray, shape (n,)
            The output's row (SI).
        """
        b, c = self.D * g, h / self.D
        b_size, c_size = float(np.linalg.norm(b)), float(np.linalg.norm(c))
        if b_size == 0.0 or c_size == 0.0:
            return 0.0, 0, [], []
        A, b, c, defect = minimal_realisation(self.A, b / b_size, c / c_size,
                                              self.tolerance)
        if A.shape[0] == 0:
            return 0.0, 0, [], []
        degree, markov = relative_degree(A, b, c, self.tolerance)
        if degree == 0:
            return 0.0, 0, [], []
        zeros, zero_errors = _roots(zero_dynamics_matrix(A, b, c, degree, markov), defect)
        poles, pole_errors = _roots(A, defect)
        gain = b_size * c_size * markov * self.rho ** (degree - 1)
        tol = self.group_tolerance
        zero_groups = _close_groups(self.rho * zeros, self.rho * zero_errors, tol)
        pole_groups = _close_groups(self.rho * poles, self.rho * pole_errors, tol)
        zero_groups, pole_groups = _cancel(zero_groups, pole_groups, CANCEL)
        return (gain, degree, sorted(zero_groups, key=_root_order),
                sorted(pole_groups, key=_root_order))


def markov_zero(F: np.ndarray, g: np.ndarray, h: np.ndarray,
                tolerance: float = TOLERANCE) -> bool:
    """True when h (sI − F)⁻¹ g is zero: every Markov parameter h Fᵏ g, k < n, within
    ``tolerance`` of its componentwise bound |h| |F|ᵏ |g| (the size rounding of F's, g's
    and h's entries can give it; the same in any units of the states, unlike
    |h| ‖Fᵏ‖ |g|, which near a pole grows with F's tan φ entries while the couplings
    that carry W go with cos φ). A path whose bound is exactly zero is structurally
    absent."""
    v, bound = np.asarray(g, dtype=float), np.abs(g)
    A = np.abs(F)
    for _ in range(len(g)):
        size = float(np.abs(h) @ bound)
        if size and abs(float(h @ v)) > tolerance * size:
            return False
        v, bound = F @ v, A @ bound
        top = float(bound.max()) if bound.size else 0.0
        if top == 0.0:
            return True
        if top > 1e100 or top < 1e-100:  # rescale both alike: the ratio is what counts
            v, bound = v / top, bound / top
    return True


def _root_order(group: tuple[complex, int]) -> tuple[float, float]:
    """Roots by size, the decaying before the growing of the same size."""
    return abs(group[0]), group[0].real


def _cancel(zeros: list[tuple[complex, int, float]], poles: list[tuple[complex, int, float]],
            share: float) -> tuple[list[tuple[complex, int]], list[tuple[complex, int]]]:
    """Zeros and poles (root, multiplicity, accuracy) without the pairs closer than
    ``share`` of the pole's size or than their accuracies together (equal, at 0)."""
    zeros, kept = [list(z) for z in zeros], []
    for pole, count, error in poles:
        for zero in zeros:
            if zero[1] and abs(zero[0] - pole) <= max(share * abs(pole), error + zero[2]):
                common = min(zero[1], count)
                zero[1] -= common
                count -= common
        if count:
            kept.append((pole, count))
    return [(z, m) for z, m, _ in zeros if m], kept



def _roots(M: np.ndarray, defect: float) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues of ``M`` and the accuracy of each: κ δ ‖M‖, κ the eigenvalue's
    condition number (1/|yᴴx| of its unit left and right eigenvectors) and δ the
    relative size of what made ``M`` (``defect``, at least the rounding of n
    operations)."""
    from scipy.linalg import eig

    if M.shape[0] == 0:
        return np.zeros(0, dtype=complex), np.zeros(0)
    values, left, right = eig(M, left=True, right=True)
    overlap = np.abs(np.sum(left.conj() * right, axis=0))
    with np.errstate(divide="ignore"):
        kappa = np.where(overlap > 0, 1.0 / overlap, np.inf)
    size = max(float(np.linalg.norm(M, 2)), 1.0)
    delta = max(defect, len(M) * np.finfo(float).eps)
    return values, np.minimum(kappa * delta * size, size)


def _close_groups(values: np.ndarray, errors: np.ndarray, tol: float
                  ) -> list[tuple[complex, int, float]]:
    """(root with Im >= 0, multiplicity, accuracy) of each distinct root, by increasing
    size: roots within :data:`GROUP_SAFETY` times the larger of their accuracies are one
    (their mean: a Jordan block's split roots average to it), a real or imaginary part
    below ``tol`` or that accuracy is zero."""
    groups: list[list] = []
    for value, error in sorted(zip(values, errors, strict=True),
                               key=lambda p: (abs(p[0]), p[0].imag)):
        reach = GROUP_SAFETY * error
        if value.imag < -max(tol, reach):
            continue  # counted with its conjugate
        for group in groups:
            if abs(group[0][0] - value) <= max(reach, group[2]):
                group[0].append(value)
                group[2] = max(group[2], reach)
                break
        else:
            groups.append([[value], 1, reach])
    out = []
    for members, _, reach in groups:
        mean = complex(np.mean(members))
        cut = max(tol, reach)
        mean = complex(0.0 if abs(mean.real) <= cut else mean.real,
                       0.0 if abs(mean.imag) <= cut else abs(mean.imag))
        out.append((mean, len(members), reach))
    return sorted(out, key=lambda g: (abs(g[0]), g[0].real))


# --------------------------------------------------------------------------------------
# The numerical pieces (scaled: ‖A‖ ≤ 1, |b| = |c| = 1)
# --------------------------------------------------------------------------------------
def krylov_basis(A: np.ndarray, v: np.ndarray, tolerance: float = TOLERANCE) -> np.ndarray:
    """Orthonormal basis (n, k) of span{v, A v, A² v, ...} (Arnoldi, orthogonalised twice);
    a new direction below ``tolerance`` (× the size of A v) ends it."""
    size = float(np.linalg.norm(v))
    if size <= tolerance:
        return np.zeros((len(v), 0))
    basis = [v / size]
    for _ in range(len(v) - 1):
        w = A @ basis[-1]
        Q = np.column_stack(basis)
        for _ in range(2):
            w = w - Q @ (Q.T @ w)
        size = float(np.linalg.norm(w))
        if size <= tolerance:
            break
        basis.append(w / size)
    return np.column_stack(basis)



def minimal_realisation(A: np.ndarray, b: np.ndarray, c: np.ndarray,
                        tolerance: float = TOLERANCE
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The controllable and observable part of (A, b, c), which has the same
    c (sI − A)⁻¹ b, and how far its bases are from invariant subspaces.

    The controllable subspace is the Krylov space of (A, b); on it, the observable one
    is that of (Aᵀ, cᵀ) (its complement, the unobservable part, is invariant, so the
    projection keeps the transfer function).

    Returns
    -------
    A, b, c : ndarray
        The minimal realisation, shapes (k, k), (k,), (k,).
    defect : float
        ‖A Q − Q Qᵀ A Q‖ (and the same for the observable part): the relative size of
        the perturbation the reduction made (the couplings it cut).
    """
    Q = krylov_basis(A, b, tolerance)
    A1, b1, c1 = Q.T @ A @ Q, Q.T @ b, c @ Q
    P = krylov_basis(A1.T, c1, tolerance)
    defect = 0.0
    if Q.shape[1]:
        defect = float(np.linalg.norm(A @ Q - Q @ A1, 2))
    if P.shape[1]:
        defect = max(defect, float(np.linalg.norm(A1.T @ P - P @ (P.T @ A1.T @ P), 2)))
    return P.T @ A1 @ P, P.T @ b1, c1 @ P, defect


def relative_degree(A: np.ndarray, b: np.ndarray, c: np.ndarray,
                    tolerance: float = TOLERANCE) -> tuple[int, float]:
    """(r, c A^(r−1) b): the first Markov parameter above ``tolerance``; (0, 0) if none
    (W = 0)."""
    v = b.copy()
    for r in range(1, len(b) + 1):
        markov = float(c @ v)
        if abs(markov) > tolerance:
            return r, markov
        v = A @ v
    return 0, 0.0


def zero_dynamics_matrix(A: np.ndarray, b: np.ndarray, c: np.ndarray, degree: int,
                         markov: float) -> np.ndarray:
    """The matrix whose eigenvalues are the invariant zeros of a minimal SISO (A, b, c)
    of relative degree ``degree``: A − b (c A^r)/(c A^(r−1) b) on the kernel of c, c A,
    ..., c A^(r−1) (the motions that keep the output at zero); (0, 0) when r = n."""
    n = len(b)
    if degree >= n:
        return np.zeros((0, 0))
    rows = [c]
    for _ in range(degree):
        rows.append(rows[-1] @ A)
    observability = np.vstack(rows[:degree])
    kernel = np.linalg.svd(observability)[2][degree:].T  # (n, n − r)
    closed = A - np.outer(b, rows[degree]) / markov
    return kernel.T @ closed @ kernel
