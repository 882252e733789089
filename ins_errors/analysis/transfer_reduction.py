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

from collections.abc import Sequence
from typing import NamedTuple

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

SPLIT_ROUNDING = 10.0
"""The growing modes' block (:class:`GrowingSplit`) is reduced at this many ulps (times
n and 1 + ‖X‖, the size of the split's rounding) of the unit-length source column and
output row: a growing mode is dropped from a pair only where the source's reach or the
output's view of it is zero to rounding (strapdown_ned's vertical channel in a
horizontal output at the equator), never because it is weak."""

GROUP_SAFETY = 100.0
"""Two computed roots are one (repeated) root when they are closer than this many times
the larger of their first-order accuracies κ δ ‖M‖ (:func:`roots_and_accuracies`). A
repeated root of a minimal realisation is a Jordan block, which rounding splits into roots
a few times their κ δ ‖M‖ apart; two distinct roots are apart by far more than theirs (the two
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
    modes : sequence of complex, optional
        F's eigenvalues as :mod:`~ins_errors.analysis.modes` groups them (Im >= 0, 1/s):
        a root's real part below ``group_tolerance`` is kept where the mode it is at
        has one (:func:`_close_groups`).
    """

    def __init__(self, F: np.ndarray, factors: np.ndarray, group_tolerance: float,
                 balanced: bool = False, tolerance: float = TOLERANCE,
                 modes: Sequence[complex] = ()):
        self.F, self.factors, self.balanced = F, factors, balanced
        self.modes = tuple(modes)
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
        self.split = GrowingSplit.of(self.A, group_tolerance / self.rho)
        self._residues: Reduction | None = None

    def _unit(self, g: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """(b, c, |b| |c|): g and h on this reduction's states, of unit length."""
        b, c = self.D * g, h / self.D
        size = float(np.linalg.norm(b)) * float(np.linalg.norm(c))
        if size == 0.0:
            return b, c, 0.0
        return b / np.linalg.norm(b), c / np.linalg.norm(c), size

    @property
    def residue_reduction(self) -> Reduction:
        """The balanced reduction of the same F, whose growing block gives the growing
        modes' residues: near a pole F's tan φ entries make the unbalanced split lose
        3 to 6 digits of them (1.8e-3 at 89.9999°, 4e-8 balanced)."""
        if self.balanced:
            return self
        if self._residues is None:
            self._residues = Reduction(self.F, self.factors, self.group_tolerance, True,
                                       self.tolerance, self.modes)
        return self._residues

    def growing_residues(self, g: np.ndarray, h: np.ndarray
                         ) -> list[tuple[complex, complex]]:
        """(eigenvalue, residue of W there), 1/s and SI, of each simple growing mode of F
        the pair reaches and sees beyond rounding (:meth:`GrowingSplit.residues`); empty
        without one."""
        source = self.residue_reduction
        if source.split is None:
            return []
        b, c, size = source._unit(g, h)
        if size == 0.0:
            return []
        return [(source.rho * v, size * r) for v, r in source.split.residues(b, c)]

    def factor(self, g: np.ndarray, h: np.ndarray) -> Factored:
        """The factored form of h (sI − F)⁻¹ g (:class:`Factored`; gain 0 for W = 0).

        Where F has growing modes (:class:`GrowingSplit`) they are kept in the pair
        whenever the source reaches them and the output sees them beyond rounding; when
        the rest of W is below the tolerance W is their part alone.

        Parameters
        ----------
        g : ndarray, shape (n,)
            The source's column (SI).
        h : ndarray, shape (n,)
            The output's row (SI).
        """
        b, c, size = self._unit(g, h)
        if size == 0.0:
            return Factored(0.0, 0, [], [])
        kept = 0
        if self.split is None:
            A, b, c, defect = minimal_realisation(self.A, b, c, self.tolerance)
        else:
            A, b, c, defect, kept = self.split.minimal_realisation(b, c, self.tolerance)
        if A.shape[0] == 0:
            return Factored(0.0, 0, [], [])
        degree, markov = relative_degree(A, b, c, self.tolerance)
        alone = degree == 0 and kept > 0
        if alone:  # the rest below the tolerance: the growing part alone
            A, b, c = A[:kept, :kept], b[:kept], c[:kept]
            degree, markov = relative_degree(A, b, c, 0.0)
        if degree == 0:
            return Factored(0.0, 0, [], [])
        zeros, zero_errors = roots_and_accuracies(
            zero_dynamics_matrix(A, b, c, degree, markov), defect)
        poles, pole_errors = roots_and_accuracies(A, defect)
        gain = size * markov * self.rho ** (degree - 1)
        tol = self.group_tolerance
        zero_groups = _close_groups(self.rho * zeros, self.rho * zero_errors, tol, self.modes,
                                    zeros=True)
        pole_groups = _close_groups(self.rho * poles, self.rho * pole_errors, tol, self.modes)
        zero_groups, pole_groups = _cancel(zero_groups, pole_groups, CANCEL, tol)
        residues = ()
        if kept:
            residues = _growing_residues(pole_groups, self.growing_residues(g, h), tol)
        return Factored(gain, degree, sorted(zero_groups, key=_root_order),
                        sorted(pole_groups, key=_root_order), residues, alone)


class Factored(NamedTuple):
    """One pair's W(s) = K (s − z₁)…/((s − p₁)…), 1/s.

    Attributes
    ----------
    gain : float
        K, SI (0 for W = 0).
    degree : int
        The relative degree (0 for W = 0).
    zeros, poles : list of (complex, int)
        (root with Im >= 0, multiplicity), by increasing size.
    residues : tuple of (complex, complex)
        (pole, residue of W there, SI) of each simple growing pole, from the growing
        modes' own block (:meth:`Reduction.growing_residues`): exact where the factored
        form's K Π(p − z)/Π(p − q) is not, as beside a zero that nearly cancels the pole.
    growing_only : bool
        W is the growing modes' part alone: every Markov parameter of the rest is below
        the reduction's tolerance.
    """

    gain: float
    degree: int
    zeros: list
    poles: list
    residues: tuple = ()
    growing_only: bool = False


class GrowingSplit:
    """F's growing modes (real part above the zero of the roots) split off the rest.

    An ordered real Schur form A = U T Uᵀ puts them first, and the solution X of the
    Sylvester equation T₁₁ X − X T₂₂ = −T₁₂ makes T block diagonal, so that
    W(s) = c₁ (sI − T₁₁)⁻¹ b₁ + c₂ (sI − T₂₂)⁻¹ b₂: the growing modes' part on their own,
    computed to the rounding of the transformations, however weakly the source reaches
    or the output sees them. The rest is reduced as before (Krylov bases to the
    reduction's tolerance); the growing block only to :data:`SPLIT_ROUNDING` ulps,
    because a growing mode's part in the response, however small, overtakes every
    bounded term: it is dropped only where it is zero to rounding.

    Attributes
    ----------
    U : ndarray, shape (n, n)
        The Schur vectors, the growing modes' first.
    T : ndarray, shape (n, n)
        The block-diagonal form (T₁₁ growing, k × k; T₂₂ the rest).
    X : ndarray, shape (k, n − k)
        The Sylvester solution.
    k : int
        The number of growing eigenvalues.
    defect : float
        The Sylvester residual's size (at least the rounding of the split).
    rounding : float
        Below this a unit-length b's or c's part in the growing block is zero.
    """

    def __init__(self, U: np.ndarray, T: np.ndarray, X: np.ndarray, k: int, defect: float):
        self.U, self.T, self.X, self.k, self.defect = U, T, X, k, defect
        self.rounding = SPLIT_ROUNDING * np.finfo(float).eps * len(T) * (
            1.0 + float(np.linalg.norm(X, 2)))

    @classmethod
    def of(cls, A: np.ndarray, tol: float) -> GrowingSplit | None:
        """The split of ``A`` (‖A‖ ≤ 1) at real part ``tol``; None without a growing
        eigenvalue (or where the Schur reordering cannot separate them)."""
        from scipy.linalg import LinAlgError, schur, solve_sylvester

        values = np.linalg.eigvals(A)
        count = int(np.sum(values.real > tol))
        if not count or count == len(A):
            return None
        try:
            T, U, k = schur(A, output="real", sort=lambda re, im: re > tol)
        except LinAlgError:  # a real part at tol itself: the reordering cannot tell
            return None
        if k != count:
            return None
        T11, T12, T22 = T[:k, :k], T[:k, k:], T[k:, k:]
        X = solve_sylvester(T11, -T22, -T12)
        residual = float(np.linalg.norm(T11 @ X - X @ T22 + T12, 2))
        T = T.copy()
        T[:k, k:] = 0.0
        n = len(A)
        defect = max(residual, n * np.finfo(float).eps * (1.0 + float(np.linalg.norm(X, 2))))
        return cls(U, T, X, k, defect)

    def _parts(self, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, ...]:
        """(b₁, c₁, b₂, c₂): b and c on the growing block and on the rest."""
        k = self.k
        b_hat, c_hat = self.U.T @ b, c @ self.U
        return (b_hat[:k] - self.X @ b_hat[k:], c_hat[:k], b_hat[k:],
                c_hat[:k] @ self.X + c_hat[k:])

    def minimal_realisation(self, b: np.ndarray, c: np.ndarray, tolerance: float
                            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, int]:
        """The minimal realisation of c (sI − A)⁻¹ b (:func:`minimal_realisation`),
        block diagonal: first the growing block's, reduced to :attr:`rounding`, then the
        rest's, reduced to ``tolerance``; the last item is the growing block's order."""
        b1, c1, b2, c2 = self._parts(b, c)
        A1, b1, c1, defect1 = minimal_realisation(self.T[:self.k, :self.k], b1, c1,
                                                  self.rounding)
        A2, b2, c2, defect2 = minimal_realisation(self.T[self.k:, self.k:], b2, c2,
                                                  tolerance)
        m1, m2 = len(b1), len(b2)
        A = np.zeros((m1 + m2, m1 + m2))
        A[:m1, :m1], A[m1:, m1:] = A1, A2
        return (A, np.concatenate([b1, b2]), np.concatenate([c1, c2]),
                max(defect1, defect2, self.defect), m1)

    def residues(self, b: np.ndarray, c: np.ndarray) -> list[tuple[complex, complex]]:
        """(eigenvalue, residue of c (sI − A)⁻¹ b there) of each eigenvalue of the
        growing block that b reaches and c sees beyond :attr:`rounding`, where they are
        all simple (none where a repeated one leaves only the factored form)."""
        b1, c1, _, _ = self._parts(b, c)
        A1, b1, c1, _ = minimal_realisation(self.T[:self.k, :self.k], b1, c1, self.rounding)
        if not len(b1):
            return []
        values, vectors = np.linalg.eig(A1)
        if len(set(np.round(values, 12))) < len(values):
            return []
        left = np.linalg.inv(vectors)
        return [(complex(v), complex((c1 @ vectors[:, j]) * (left[j] @ b1)))
                for j, v in enumerate(values)]


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


def _cancel(zeros: list[tuple[complex, int, float, float]],
            poles: list[tuple[complex, int, float, float]], share: float,
            tol: float = 0.0) -> tuple[list[tuple[complex, int]], list[tuple[complex, int]]]:
    """Zeros and poles (root, multiplicity, reach, accuracy) without the pairs that cancel.

    A zero cancels a pole of its own kind (both real, or both a conjugate pair: a real
    root cannot stand for a pair's two) when they are one root to within the rounding
    of the computation, the sum of their accuracies (equal, at 0), or within ``share`` of
    the pole's size: that mode's part in W is then at most about ``share`` of the
    response, and it does not grow. A growing pole (real part above ``tol``) is never
    cancelled here: its part in the response, however small, overtakes every bounded
    term, and the growing modes' block was reduced to rounding already
    (:class:`GrowingSplit`), so a zero beside it (the rest of W nearly cancelling it)
    stays beside it."""
    zeros, kept = [list(z) for z in zeros], []
    for pole, count, _, error in poles:
        if pole.real > tol:
            kept.append((pole, count))
            continue
        for zero in zeros:
            if not zero[1] or bool(zero[0].imag) != bool(pole.imag):
                continue
            if abs(zero[0] - pole) <= max(share * abs(pole), error + zero[3]):
                common = min(zero[1], count)
                zero[1] -= common
                count -= common
        if count:
            kept.append((pole, count))
    return [(z, m) for z, m, _, _ in zeros if m], kept


def _growing_residues(poles: list[tuple[complex, int]],
                      growing: list[tuple[complex, complex]], tol: float
                      ) -> tuple[tuple[complex, complex], ...]:
    """(pole, residue of W, SI) of each simple growing pole of ``poles`` (1/s), from
    ``growing`` ((eigenvalue, residue), 1/s and SI): the nearest eigenvalue with
    Im >= 0, within 1e-6 of the pole's size."""
    out = []
    candidates = [(v, r) for v, r in growing if v.imag >= 0]
    for pole, count in poles:
        if pole.real <= tol or count != 1 or not candidates:
            continue
        value, residue = min(candidates, key=lambda item: abs(item[0] - pole))
        if abs(value - pole) <= 1e-6 * abs(pole):
            out.append((pole, complex(residue)))
    return tuple(out)


def roots_and_accuracies(M: np.ndarray, defect: float) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues of ``M`` and the accuracy of each.

    The accuracy is the smaller of the first-order bound κ δ ‖M‖ (κ the eigenvalue's
    condition number, 1/|yᴴx| of its unit left and right eigenvectors) on ``M`` as it is
    and on ``M`` balanced (a diagonal similarity evening out its rows and columns, as
    LAPACK's eigensolver does before it starts, its factors within
    2^±:data:`BALANCE_LIMIT`: a zero dynamics matrix near a pole has a
    few entries far larger than the rest, which make κ δ ‖M‖ of the unbalanced matrix
    overstate the error by 1e4), and of δ^(1/m) ‖M‖, m the number of computed
    eigenvalues within δ^(1/n) ‖M‖ of it (how far a δ ‖M‖ perturbation moves the roots
    of an m × m Jordan block: the bound where the eigenvectors are parallel, κ infinite,
    as for a double zero computed exactly). δ is the relative size of what made ``M``
    (``defect``, at least the rounding of n operations); ‖M‖ at least 1."""
    from scipy.linalg import eig, matrix_balance

    if M.shape[0] == 0:
        return np.zeros(0, dtype=complex), np.zeros(0)
    values, left, right = eig(M, left=True, right=True)
    with np.errstate(invalid="ignore"):  # scipy casts its unused permutation
        scale = matrix_balance(M, permute=False, separate=True)[1][0]
    scale = np.clip(scale, 2.0 ** -BALANCE_LIMIT, 2.0 ** BALANCE_LIMIT)
    balanced = M * scale[None, :] / scale[:, None]
    n = len(M)
    delta = max(defect, n * np.finfo(float).eps)
    first_order = np.full(n, np.inf)
    sizes = []
    for x, y, matrix in ((right, left, M), (right / scale[:, None], left * scale[:, None],
                                            balanced)):
        overlap = np.abs(np.sum(y.conj() * x, axis=0))
        with np.errstate(divide="ignore", invalid="ignore"):
            kappa = np.linalg.norm(x, axis=0) * np.linalg.norm(y, axis=0) / overlap
        kappa = np.where(overlap > 0, kappa, np.inf)
        size = max(float(np.linalg.norm(matrix, 2)), 1.0)
        sizes.append(size)
        first_order = np.minimum(first_order, kappa * delta * size)
    size = min(sizes)
    cluster = size * delta ** (1.0 / n)
    count = np.sum(np.abs(values[:, None] - values[None, :]) <= cluster, axis=1)
    jordan = np.where(count > 1, size * delta ** (1.0 / count), np.inf)
    return values, np.minimum(np.minimum(first_order, jordan), sizes[0])


def _damped_mode(value: complex, modes: Sequence[complex], tol: float,
                 zero: bool = False, reach: float = 0.0) -> bool:
    """Whether an oscillating root keeps its real part below ``tol``.

    A pole: where the eigenvalue of F nearest to it (of ``modes``, 1/s, Im >= 0), within
    100 ``tol`` (the distance at which a pole is named after a mode), has a real part
    below ``tol`` that ``modes`` keeps: its damping (or growth), above what rounding
    leaves of it on the whole F (:mod:`~ins_errors.analysis.modes`). A zero (``zero``):
    where its real part is above its ``reach`` and F has such a lightly damped mode: the
    residue at that mode's pole goes with p − z, and near a pole strapdown_ned's heading
    and longitude have zeros 1.6e-5 and 4.5e-4 1/s from the Schuler pairs damped by
    ~1e-8 1/s, whose own real parts zeroed put W off by 6e-4 and 3e-5 of its peak."""
    if not len(modes):
        return False
    if zero:  # beside a lightly damped pair: its real part sets the pair's residue
        return abs(value.real) > reach and any(0.0 < abs(m.real) <= tol for m in modes)
    nearest = min(modes, key=lambda m: abs(m - value))
    return 0.0 < abs(nearest.real) <= tol and abs(nearest - value) <= 100 * tol


def _close_groups(values: np.ndarray, errors: np.ndarray, tol: float,
                  modes: Sequence[complex] = (), zeros: bool = False
                  ) -> list[tuple[complex, int, float, float]]:
    """(root with Im >= 0, multiplicity, reach, accuracy) of each distinct root, by
    increasing size: roots within :data:`GROUP_SAFETY` times the larger of their
    accuracies (the reach) are one (their mean: a Jordan block's split roots average to
    it; its accuracy the largest of theirs), a real or imaginary part below ``tol`` or
    the reach is zero (and groups so made one root are one), except the real part of an
    oscillating root at a mode of F (``modes``, F's eigenvalues as ``modes`` gives them)
    whose real part ``modes`` keeps: that mode's damping (a Schuler pair damped by
    1e-8 1/s beside a damped vertical loop's 0.02 1/s near a pole), which the reduced
    matrices cannot tell from their rounding, the whole F can."""
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
                group[3] = max(group[3], error)
                break
        else:
            groups.append([[value], 1, reach, error])
    out = []
    for members, _, reach, error in groups:
        mean = complex(np.mean(members))
        cut = max(tol, reach)
        imag = 0.0 if abs(mean.imag) <= cut else abs(mean.imag)
        keep = bool(imag) and _damped_mode(complex(mean.real, imag), modes, tol, zeros,
                                           reach)
        mean = complex(0.0 if abs(mean.real) <= cut and not keep else mean.real, imag)
        for k, (value, count, other_reach, other_error) in enumerate(out):
            if value == mean:  # two groups made one root by the zero (both at 0)
                out[k] = (value, count + len(members), max(reach, other_reach),
                          max(error, other_error))
                break
        else:
            out.append((mean, len(members), reach, error))
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
