r"""Covariance propagation through a model's linear error equations (Van Loan).

The error state obeys :math:`\dot x_e = F x_e + G b`, :math:`x_e(0) = E w_0`, where
``b`` holds the error sources (the model's ``w``). Each source is one of

``constant``
    a random constant of 1σ ``sigma`` (bias, drift, scale factor, initial error):
    :math:`\dot b = 0`, :math:`b(0) \sim N(0, \sigma^2)`; "initial" sources of a model act
    only through ``E``, "constant" ones through ``G`` (a source may do both);
``white``
    white noise of density ``sigma`` (PSD σ², units of the source times √s, e.g. a gyro's
    angle random walk in deg/√h) entering through the source's column of ``G``;
``markov``
    first-order Gauss-Markov noise of steady-state 1σ ``sigma`` and correlation time
    ``tau``: :math:`\dot b = -b/\tau + n`, PSD of n = 2σ²/τ, started stationary.

A source may be listed with two or three parts of different kinds (a gyro's constant bias
and its white angle random walk, or a Markov bias instability beside them): the parts are
independent and add in the source's place, the constant as a state of the augmented
system, the white part as process noise through the same column of ``G``, each part's
contribution reported on its own (``Covariance.sources`` lists them in the given order).

Sources are independent, so every second moment is a sum over sources of a term linear in
that source's variance. :func:`propagate` therefore works with *unit* statistics
(σ = 1) and returns, for each requested linear functional of the error state, the
variance each source contributes per unit variance; scaling by σ² and summing gives the
budget (see :class:`Covariance`).

Discretisation is exact for a system held constant over each step (Van Loan 1978):
``expm([[F, G_b], [0, D]] dt)`` gives the transition of the augmented state
``z = (x_e, b)``, and ``expm([[-A, B Q Bᵀ], [0, Aᵀ]] dt)`` the noise covariance added in
a step. Along a moving trajectory F and G are held at the mean of the two ends of each
step, and these are evaluated a few thousand steps at a time with the batched series of
:mod:`ins_errors.numeric.step_exponential` instead of SciPy's ``expm`` step by step: the
augmented transitions, and for a noise (one column b, ``BQBᵀ = b bᵀ``) the same Van Loan
pair from the series of ``e^{Fσ} b`` without the double-size block.
On a time-invariant system (static base) the step transition Φ is computed once and the
powers ``C Φᵏ Z₀`` are formed in blocks with a few matrix products, which is what
makes 24 h at 1 s output take milliseconds; its noise pairs come from the same series as
a moving base's (never from the double-size block, whose ``e^{Δt/τ}`` overflows, or
cancels to nothing, once a Markov source's τ is a small fraction of the step). So a
Markov source is exact for any τ against the step, down to :data:`SHORTEST_TAU_PER_STEP`
of it, below which it is refused as white noise (PSD 2σ²τ) within rounding.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ins_errors.errors import InsErrorsError, ShapeError, unknown_name
from ins_errors.numeric.blas_threads import import_limited, one_blas_thread
from ins_errors.numeric.linear_system import (
    LinearSystem,
    static_system,
    system_from_trajectory,
    trajectory_system,
    uniform_grid,
)
from ins_errors.numeric.step_exponential import (
    exp_and_integral,
    exponential,
    rank_one_noise_step,
)

_SUM_CHUNK = 4_000_000
"""Entries (32 MB) of the per-source covariances :attr:`Covariance.matrix` scales and
sums at a time."""

KINDS = ("constant", "white", "markov")
"""The statistical kinds a source may have."""

SHORTEST_TAU_PER_STEP = 2.0**-53
"""Least correlation time of a Markov source as a fraction of the step (the unit
round-off): any τ above it is propagated exactly (the Van Loan pair of the noise is formed
on a scaled step of at most about τ and doubled, so ``e^{−Δt/τ}`` never overflows);
shorter noise is white to within the rounding of the step itself, and is refused with the
white source of the same effect (density σ·√(2τ)) named instead."""


__all__ = ["KINDS", "Covariance", "CovarianceError", "Functionals", "LinearSystem",
           "SourceStatistics", "power_sequence", "propagate", "state_and_output_functionals",
           "static_system", "system_from_trajectory", "trajectory_system", "uniform_grid",
           "van_loan"]


class CovarianceError(InsErrorsError):
    """Inconsistent input to a covariance computation."""


@dataclass(frozen=True)
class SourceStatistics:
    """How one error source is modelled statistically.

    Attributes
    ----------
    name : str
        The model's source name (e.g. ``"gyro_drift_x"``).
    kind : {"constant", "white", "markov"}
        See the module docstring.
    sigma : float
        1σ of a constant, noise density of white noise (SI unit × √s), steady-state 1σ
        of Gauss-Markov noise. SI units of the source.
    tau : float or None
        Correlation time of Gauss-Markov noise, s (given for a Markov source only).
    """

    name: str
    kind: str = "constant"
    sigma: float = 1.0
    tau: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise CovarianceError(f"source {self.name!r}: kind must be one of "
                                  f"{', '.join(KINDS)}, got {self.kind!r}")
        for name in ("sigma", "tau"):  # text such as "0.01 deg/h": one line, not numpy's
            value = getattr(self, name)
            if value is None:
                continue
            if isinstance(value, str) or np.ndim(value) != 0 or np.iscomplexobj(value):
                raise CovarianceError(
                    f"source {self.name!r}: {name} takes one real number in SI units (the "
                    f"source's SI unit{', s' if name == 'tau' else ''}), got {value!r:.40}"
                    + ("; convert text with ins_errors.units.parse_quantity(text, unit)"
                       if isinstance(value, str) else ""))
        if not np.isfinite(self.sigma) or self.sigma < 0:
            raise CovarianceError(f"source {self.name!r}: sigma must be a finite number "
                                  f">= 0, got {self.sigma!r}")
        if self.kind != "markov" and self.tau is not None:
            raise CovarianceError(f"source {self.name!r}: tau applies only to kind "
                                  f"'markov', not to a {self.kind!r} source (got tau = "
                                  f"{self.tau!r}): leave it out")
        if self.kind == "markov" and (self.tau is None or not np.isfinite(self.tau)
                                      or self.tau <= 0):
            raise CovarianceError(f"source {self.name!r}: a Markov source needs a "
                                  f"correlation time tau > 0 s, got {self.tau!r}")


def short_tau_message(what: str, tau: float, step: float) -> str:
    """One line refusing a Markov correlation time ``tau`` below
    :data:`SHORTEST_TAU_PER_STEP` of the ``step`` (both s)."""
    return (f"{what}: a correlation time of {tau:.3g} s is below 2⁻⁵³ of the {step:g} s "
            f"step, so the noise is white within double precision: give kind = 'white' "
            f"with density σ·√(2τ) instead (white noise of PSD 2σ²τ)")


# --------------------------------------------------------------------------------------
# Discretisation
# --------------------------------------------------------------------------------------
def _step_matrix(matrix: np.ndarray) -> np.ndarray:
    """Per-step value (mean of the ends) of a time-varying matrix, shape (K, ...)."""
    return 0.5 * (matrix[1:] + matrix[:-1])


def augmented_dynamics(F: np.ndarray, G_b: np.ndarray, decay: np.ndarray) -> np.ndarray:
    """Continuous matrix of z = (x_e, b): ``[[F, G_b], [0, diag(decay)]]`` (batched)."""
    n, nb = F.shape[-1], G_b.shape[-1]
    A = np.zeros((*F.shape[:-2], n + nb, n + nb))
    A[..., :n, :n] = F
    A[..., :n, n:] = G_b
    A[..., n:, n:] = np.diag(decay)
    return A


def _expm(matrix: np.ndarray) -> np.ndarray:
    """SciPy's ``expm`` of a square matrix (or a stack of them), imported on first use.

    Importing SciPy's linear algebra costs about 0.2-0.3 s CPU, and the processes that
    import this module for its types (Monte Carlo, sweep and validity tasks on every Dask
    worker, the Dask scheduler unpickling those tasks) never call it. Imported within
    :func:`propagate`'s one-thread limit, which then reaches SciPy's own BLAS too.
    """
    return import_limited("scipy.linalg").expm(matrix)


def van_loan(A: np.ndarray, BQBt: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact discretisation of ``ż = A z + noise`` (noise covariance rate ``B Q Bᵀ``).

    Parameters
    ----------
    A : numpy.ndarray, shape (..., N, N)
    BQBt : numpy.ndarray, shape (..., N, N)
    dt : float
        Step, s.

    Returns
    -------
    Phi, Qd : numpy.ndarray, shape (..., N, N)
        Transition ``expm(A dt)`` and the covariance added over one step,
        ``∫₀^dt e^{As} BQBᵀ e^{Aᵀs} ds``.
    """
    N = A.shape[-1]
    M = np.zeros((*A.shape[:-2], 2 * N, 2 * N))
    M[..., :N, :N] = -A
    M[..., :N, N:] = BQBt
    M[..., N:, N:] = np.swapaxes(A, -1, -2)
    X = _expm(M * dt)
    Phi = np.swapaxes(X[..., N:, N:], -1, -2)
    Qd = Phi @ X[..., :N, N:]
    return Phi, 0.5 * (Qd + np.swapaxes(Qd, -1, -2))


def _noise_factor(Qd: np.ndarray, tolerance: float = 1e-13) -> np.ndarray:
    """A factor W with W Wᵀ = Qd (symmetric PSD), columns for non-negligible modes.

    The states mix units (rad, m/s, ...), so negligible modes are judged on the matrix
    scaled to unit diagonal: a small-but-real variance of one state is never dropped
    because another state's variance is large in SI numbers.
    """
    scale = np.sqrt(np.clip(np.diag(Qd), 0.0, None))
    scale[scale == 0] = 1.0
    values, vectors = np.linalg.eigh(Qd / np.outer(scale, scale))
    keep = values > tolerance * max(values.max(), 0.0)
    if not keep.any():
        return np.zeros((Qd.shape[0], 0))
    return scale[:, None] * vectors[:, keep] * np.sqrt(values[keep])


def power_sequence(Phi: np.ndarray, Z0: np.ndarray, C: np.ndarray, steps: int,
                   reduce: str = "none") -> np.ndarray:
    """``C Φᵏ Z₀`` for k = 0..steps, formed in blocks (time-invariant systems).

    Parameters
    ----------
    Phi : numpy.ndarray, shape (N, N)
    Z0 : numpy.ndarray, shape (N, m)
    C : numpy.ndarray, shape (q, N)
    steps : int
    reduce : {"none", "square-sum"}
        ``"none"`` returns shape (steps+1, q, m); ``"square-sum"`` returns
        ``Σ_m (C Φᵏ Z₀)²``, shape (steps+1, q), without storing the full array
        (:func:`_square_sums`).
    """
    if reduce == "square-sum":
        return _square_sums(Phi, Z0, C, steps)
    total = steps + 1
    block = max(1, int(np.ceil(np.sqrt(total))))
    N, m, q = Phi.shape[0], Z0.shape[1], C.shape[0]
    if m == 0:
        return np.zeros((total, q, 0))
    powers = _powers(Phi, block)
    CP = (C @ powers).reshape(block * q, N)          # rows: (i, q)
    jump = powers[-1] @ Phi                           # Φ^block
    starts = -(-total // block)
    Zs = np.empty((starts, N, m))
    Zs[0] = Z0
    for j in range(1, starts):
        Zs[j] = jump @ Zs[j - 1]
    out = np.empty((total, q, m))
    chunk = max(1, int(4_000_000 // max(1, block * q * m)))
    for j0 in range(0, starts, chunk):
        j1 = min(starts, j0 + chunk)
        Y = CP @ np.moveaxis(Zs[j0:j1], 0, 1).reshape(N, (j1 - j0) * m)
        k0, k1 = j0 * block, min(total, j1 * block)
        Y = Y.reshape(block, q, j1 - j0, m).transpose(2, 0, 1, 3)   # (j, i, q, m)
        out[k0:k1] = Y.reshape(-1, q, m)[: k1 - k0]
    return out


def _powers(Phi: np.ndarray, count: int) -> np.ndarray:
    """``Φ⁰ … Φ^(count−1)``, shape (count, N, N)."""
    powers = np.empty((count, *Phi.shape))
    powers[0] = np.eye(Phi.shape[0])
    for i in range(1, count):
        np.matmul(powers[i - 1], Phi, out=powers[i])
    return powers


def column_factor(Z: np.ndarray, tolerance: float = 1e-12) -> np.ndarray:
    """A factor ``L`` with ``L Lᵀ = Z Zᵀ`` and no more columns than the rank of ``Z``.

    Columns of ``Z`` that are (nearly) combinations of others, e.g. two error sources
    entering the equations in the same place, collapse into one. The rank is judged on
    ``Z`` with rows scaled to unit norm, because the rows mix units (rad, m/s, ...): a
    direction is dropped only if its singular value is below ``tolerance`` times the
    largest one, so it changes no row's second moments by more than ``tolerance²`` of
    their size.

    Parameters
    ----------
    Z : numpy.ndarray, shape (N, m)
    tolerance : float

    Returns
    -------
    numpy.ndarray, shape (N, r), r <= min(N, m); ``Z`` itself when nothing would be saved.
    """
    m = Z.shape[1]
    scale = np.sqrt(np.einsum("ij,ij->i", Z, Z))
    scale[scale == 0] = 1.0
    U, s, _ = np.linalg.svd(Z / scale[:, None], full_matrices=False)
    keep = s > tolerance * s[0] if s.size else s > 0
    if keep.sum() >= m:
        return Z
    return scale[:, None] * (U[:, keep] * s[keep])


def _square_sums(Phi: np.ndarray, Z0: np.ndarray, C: np.ndarray, steps: int) -> np.ndarray:
    """``Σ_m (C Φᵏ Z₀)²`` for k = 0..steps, shape (steps+1, q): the diagonal of
    ``C Φᵏ Z₀Z₀ᵀ Φᵏᵀ Cᵀ``.

    ``Z₀`` is first replaced by a factor of ``Z₀Z₀ᵀ`` with as few columns as its rank
    (:func:`column_factor`). With ``k = j B + i`` (B ≈ √steps) every value is a row of
    ``(Φ^{jB} Z₀)ᵀ`` times a column of ``(C Φⁱ)ᵀ``; these products are taken a few block
    starts ``j`` at a time, laid out (j, m, i, q) so that the sum over the columns of
    ``Z₀`` runs over contiguous rows and the result lands in time order without a
    transpose.
    """
    total = steps + 1
    q = C.shape[0]
    if Z0.shape[1] == 0:
        return np.zeros((total, q))
    Z0 = column_factor(Z0)
    N, m = Z0.shape
    block = max(1, int(np.ceil(np.sqrt(total))))
    powers = _powers(Phi, block)
    CPt = np.ascontiguousarray((C @ powers).reshape(block * q, N).T)   # (N, (i, q))
    jump_t = (powers[-1] @ Phi).T                                      # (Φ^B)ᵀ
    starts = -(-total // block)
    Zt = np.empty((starts, m, N))                                       # (Φ^{jB} Z₀)ᵀ
    Zt[0] = Z0.T
    for j in range(1, starts):
        np.matmul(Zt[j - 1], jump_t, out=Zt[j])
    out = np.empty((starts * block, q))
    rows = out.reshape(starts, block * q)
    # about 2 MB of products at a time: they stay in the cache while squared and summed
    chunk = max(1, 250_000 // (block * q * m))
    for j0 in range(0, starts, chunk):
        j1 = min(starts, j0 + chunk)
        Y = Zt[j0:j1].reshape(-1, N) @ CPt                              # ((j, m), (i, q))
        Y *= Y
        np.sum(Y.reshape(j1 - j0, m, block * q), axis=1, out=rows[j0:j1])
    return out[:total]


# --------------------------------------------------------------------------------------
# Propagation
# --------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Functionals:
    """Linear functionals ``y = C_x x_e + C_b b`` whose variances are wanted.

    Compared by identity (``==`` is ``is``; hashable): it holds arrays, whose ``==``
    has no single truth value.

    Attributes
    ----------
    names, units : tuple of str
    C_x : numpy.ndarray, shape (q, n) or (K+1, q, n)
        Weights on the error state (time-varying when 3-D).
    C_b : numpy.ndarray, shape (q, nw)
        Weights on the sources' current values (constants and Markov states), model
        source order; white sources have no value and are ignored.

    Raises
    ------
    ShapeError
        Names or units that are not one per row of ``C_x``, a ``C_x`` that is neither
        2-D nor 3-D, a ``C_b`` that is not (q, nw).
    CovarianceError
        A NaN or infinite weight (naming the first one's functional). The widths are
        checked against the model's error states and sources by :func:`propagate`.
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    C_x: np.ndarray
    C_b: np.ndarray

    def __post_init__(self) -> None:
        C_x = np.asarray(self.C_x, dtype=float)
        C_b = np.asarray(self.C_b, dtype=float)
        object.__setattr__(self, "C_x", C_x)
        object.__setattr__(self, "C_b", C_b)
        if C_x.ndim not in (2, 3):
            raise ShapeError(f"Functionals: C_x must be (q, n), or (K+1, q, n) when it "
                             f"varies along the grid, got shape {C_x.shape}")
        q = C_x.shape[-2]
        if len(self.names) != q or len(self.units) != q:
            raise ShapeError(f"Functionals: {len(self.names)} names and {len(self.units)} "
                             f"units for the {q} rows of C_x: give one name and one unit "
                             "per functional")
        if C_b.ndim != 2 or C_b.shape[0] != q:
            raise ShapeError(f"Functionals: C_b must be (q, nw) with q = {q} rows, one per "
                             f"functional, got shape {C_b.shape}")
        for label, weights in (("C_x", C_x), ("C_b", C_b)):
            bad = ~np.isfinite(weights)
            if bad.any():
                row = int(np.argwhere(bad)[0][-2])
                raise CovarianceError(f"Functionals: {label} holds {int(bad.sum())} NaN or "
                                      f"infinite weight(s), the first in the row of "
                                      f"{self.names[row]!r}: every weight must be a finite "
                                      "number")


def state_and_output_functionals(model, system: LinearSystem) -> Functionals:
    """Every error state and every output error (through H), in SI units.

    An output whose error is an error state of the same name (``north_pointing``'s
    latitude: ``delta_latitude`` is a state, and H reads it alone) is that state, listed
    once; an output error whose name a state has but which H reads otherwise is named
    ``delta_<output>_output``.
    """
    n, nw = system.E.shape
    states = [i.name for i in model.error_states]
    H = system.H if system.H.ndim == 3 else system.H[None]
    rows, names, units = [], list(states), [i.unit for i in model.error_states]
    for k, output in enumerate(model.outputs):
        name = f"delta_{output.name}"
        if name in states:
            if np.array_equal(H[:, k], np.broadcast_to(np.eye(n)[states.index(name)],
                                                       H[:, k].shape)):
                continue   # the state itself
            name += "_output"
        rows.append(k)
        names.append(name)
        units.append(output.unit)
    if system.H.ndim == 2:
        C_x = np.vstack([np.eye(n), system.H[rows]])
    else:
        C_x = np.concatenate([np.broadcast_to(np.eye(n), (len(system.times), n, n)),
                              system.H[:, rows]], axis=1)
    return Functionals(tuple(names), tuple(units), C_x, np.zeros((len(names), nw)))


@dataclass(frozen=True, eq=False)
class Covariance:
    """Variances of linear functionals, split by source.

    Compared by identity (``==`` is ``is``; hashable): it holds arrays, whose ``==``
    has no single truth value.

    Attributes
    ----------
    times : numpy.ndarray, shape (nt,)
        Output times, s.
    names, units : tuple of str
        Functionals.
    sources : tuple of SourceStatistics
        The statistics the contributions are scaled with.
    unit_variances : numpy.ndarray, shape (nt, q, ns)
        Variance of each functional per unit variance (σ = 1) of each source; for a
        total-only result (``by_source=False``), one column already scaled.
    total_only : bool
        True when only the total was computed (no split by source).
    unit_covariances : numpy.ndarray, shape (nt, q, q, ns), or None
        With ``propagate(..., cross=True)``: the whole covariance matrix of the
        functionals per unit variance of each source (laid out as ``unit_variances``,
        whose entries are its diagonal); None otherwise.

    The numbers to read (properties, in the functionals' SI units):

    ``std``, shape (nt, q)
        Total 1σ of each functional at each time.
    ``variance``, shape (nt, q)
        Total variance (SI units²), the sum of the contributions.
    ``contributions``, shape (nt, q, ns)
        Variance each source contributes (``unit_variances`` times its σ²); (nt, q, 1)
        for a total-only result.
    ``source_names``, tuple of str
        The sources' names, in the order of the contributions' last axis.

    With ``cross=True`` also (the functionals' cross covariances, e.g. a filter's
    initial P or an error ellipse):

    ``matrix``, shape (nt, q, q)
        The total covariance matrix of the functionals (SI units × units).
    ``matrix_contributions``, shape (nt, q, q, ns)
        Each source's part of it (a new array on each use).
    ``correlation``, shape (nt, q, q)
        Correlation coefficients (0 off the diagonal where a variance is 0).

    ``matrix`` and ``correlation`` are formed once, on first use, and kept read-only
    (``.copy()`` one to change it).

    :meth:`index` gives a functional's column (``c.std[:, c.index("delta_v_N")]``).
    """

    times: np.ndarray
    names: tuple[str, ...]
    units: tuple[str, ...]
    sources: tuple[SourceStatistics, ...]
    unit_variances: np.ndarray
    total_only: bool = False
    unit_covariances: np.ndarray | None = None

    @property
    def source_names(self) -> tuple[str, ...]:
        """The sources' names, in the order of :attr:`contributions`' last axis."""
        return tuple(s.name for s in self.sources)

    @property
    def contributions(self) -> np.ndarray:
        """Variance contributed by each source, shape (nt, q, ns), SI units².

        For a total-only result: the total, shape (nt, q, 1).
        """
        if self.total_only:
            return self.unit_variances
        sigma = np.array([s.sigma for s in self.sources])
        return self.unit_variances * sigma**2

    @property
    def variance(self) -> np.ndarray:
        """Total variance, shape (nt, q)."""
        return self.contributions.sum(-1)

    @property
    def std(self) -> np.ndarray:
        """Total 1σ, shape (nt, q) (round-off below zero read as zero)."""
        return np.sqrt(np.maximum(self.variance, 0.0))

    @property
    def matrix_contributions(self) -> np.ndarray:
        """Each source's covariance matrix of the functionals, shape (nt, q, q, ns),
        SI units × units (for a total-only result: the total, shape (nt, q, q, 1))."""
        if self.unit_covariances is None:
            raise CovarianceError("this covariance holds variances only: propagate(..., "
                                  "cross=True) computes the cross covariances")
        if self.total_only:
            return self.unit_covariances
        sigma = np.array([s.sigma for s in self.sources])
        return self.unit_covariances * sigma**2

    @functools.cached_property
    def matrix(self) -> np.ndarray:
        """Total covariance matrix of the functionals, shape (nt, q, q), SI units × units.

        Formed on first use and kept (read-only: the same array on every use). The
        sum over the sources is taken a few thousand times at a time, never through the
        (nt, q, q, ns) array of :attr:`matrix_contributions`.
        """
        if self.unit_covariances is None:
            return self.matrix_contributions          # the one-line refusal
        if self.total_only:
            total = self.unit_covariances[..., 0]
        else:
            unit = self.unit_covariances
            sigma = np.array([s.sigma for s in self.sources])
            total = np.empty(unit.shape[:-1])
            chunk = max(1, _SUM_CHUNK // max(1, unit[0].size))
            for k0 in range(0, len(unit), chunk):     # each entry as in one sum
                total[k0:k0 + chunk] = (unit[k0:k0 + chunk] * sigma**2).sum(-1)
        total.flags.writeable = False
        return total

    @functools.cached_property
    def correlation(self) -> np.ndarray:
        """Correlation coefficients of the functionals, shape (nt, q, q): the matrix
        divided by the product of the two standard deviations (0 where either is 0).

        Formed on first use and kept (read-only), as :attr:`matrix`.
        """
        matrix = self.matrix
        std = np.sqrt(np.maximum(np.einsum("kii->ki", matrix), 0.0))
        scale = std[:, :, None] * std[:, None, :]
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.where(scale > 0, matrix / np.where(scale > 0, scale, 1.0), 0.0)
        rho = np.clip(rho, -1.0, 1.0)
        rho.flags.writeable = False
        return rho

    def index(self, name: str) -> int:
        """Column of the functional ``name``."""
        if name not in self.names:
            raise unknown_name("quantity", name, self.names)
        return self.names.index(name)


def _validate(system: LinearSystem, sources: Sequence[SourceStatistics],
              functionals: Functionals) -> list[int]:
    if not sources:
        raise CovarianceError("no error sources given")
    columns = [system.source_index(s.name) for s in sources]
    parts = [(j, s.kind) for j, s in zip(columns, sources, strict=True)]
    for part in parts:
        if parts.count(part) > 1:
            raise CovarianceError(
                f"source {sources[parts.index(part)].name!r} is listed twice as a "
                f"{part[1]!r} part: a source takes at most one part of each kind "
                f"(e.g. a constant bias and a white noise), which add")
    for s, j in zip(sources, columns, strict=True):
        if s.kind != "constant" and np.any(system.E[:, j] != 0):
            raise CovarianceError(f"source {s.name!r} sets initial errors, so it can only be "
                                  f"a random constant, not {s.kind!r} noise")
        if s.kind != "constant" and system.source_kinds[j] == "initial":
            raise CovarianceError(f"source {s.name!r} is an initial error: kind must be "
                                  "'constant'")
        if s.kind == "markov" and s.tau < system.step * SHORTEST_TAU_PER_STEP:
            raise CovarianceError(short_tau_message(f"source {s.name!r}", s.tau,
                                                    system.step))
    n, nw = system.E.shape
    if functionals.C_x.shape[-1] != n:
        raise ShapeError(f"functionals must weigh {n} error states, got "
                         f"{functionals.C_x.shape}")
    if functionals.C_b.shape[-1] != nw:
        raise ShapeError(f"functionals' C_b must weigh the model's {nw} error sources (one "
                         f"column each, in the order of system.source_names), got "
                         f"{functionals.C_b.shape[-1]} columns")
    if functionals.C_x.ndim == 3 and len(functionals.C_x) != len(system.times):
        raise ShapeError(f"functionals' C_x varies along the grid with "
                         f"{len(functionals.C_x)} samples, but the grid has "
                         f"{len(system.times)} times (one (q, n) matrix each)")
    return columns


def output_stride(output_every, system: LinearSystem) -> int:
    """``output_every`` as a whole number of grid steps that divides the grid's.

    Raises
    ------
    CovarianceError
        One that is no whole number >= 1, or that does not divide the grid's steps (the
        last time, the end of the grid, would be left out): the message names the
        nearest that divide it, as a recording interval that does not divide a run is
        refused (:func:`~ins_errors.numeric.integrators.record_stride`).
    """
    import operator

    from ins_errors.numeric.integrators import _nearest_divisors

    try:
        every = operator.index(output_every)
    except TypeError:
        every = None
    if every is None or isinstance(output_every, bool) or every < 1:
        raise CovarianceError(f"output_every must be a whole number of grid steps >= 1, "
                              f"got {output_every!r}")
    steps = len(system.times) - 1
    if steps % every:
        nearest = " or ".join(str(k) for k in _nearest_divisors(steps, every)
                              if k is not None)
        raise CovarianceError(
            f"output_every {every} does not divide the grid's {steps} steps of "
            f"{system.step:g} s, so the end of the grid ({system.times[-1]:g} s) would "
            f"not be reported; the nearest that divide it: {nearest}")
    return every


@one_blas_thread
def propagate(system: LinearSystem, sources: Sequence[SourceStatistics],
              functionals: Functionals, output_every: int = 1,
              by_source: bool = True, cross: bool = False, warn: bool = True
              ) -> Covariance:
    """Propagate unit-variance statistics of each source to the functionals' variances.

    The matrices are small (tens of rows), so BLAS runs single-threaded here: its
    threads cost more than they save (and the machine's other cores stay free).

    Parameters
    ----------
    system : LinearSystem
        Error equations on a uniform grid.
    sources : sequence of SourceStatistics
        The sources to include (others are taken as zero).
    functionals : Functionals
        What to report.
    output_every : int
        Report every ``output_every``-th grid time (1: every step); it must divide the
        grid's number of steps, so that the end of the grid is reported.
    by_source : bool
        If False, report only the total (faster): ``unit_variances`` then has one column
        holding the total variance with the given sigmas, ``sources`` is empty and
        ``total_only`` is set.
    cross : bool
        Also compute the functionals' cross covariances (``Covariance.matrix``, shape
        (nt, q, q)): q times the memory of the variances, for each source (once in all
        with ``by_source=False``). The variances are the same numbers with or without it.
    warn : bool
        Warn (:class:`~ins_errors.errors.InsErrorsWarning`) when the error equations
        grow exponentially over the grid: a mode of F that grows by
        :data:`~ins_errors.numeric.linear_system.GROWTH_WARNED` e-foldings or more (a
        factor 20), followed along a moving base
        (:func:`~ins_errors.numeric.linear_system.growth_folds`); the line gives its
        e-folding time and names the damping gains left at 0, as ``compare`` and
        ``budget`` do. The budget, which says so in its own words, passes False.

    Returns
    -------
    Covariance

    Raises
    ------
    CovarianceError, ShapeError
        One line for sources the system does not have or cannot take, functionals of
        the wrong widths or sample count, an ``output_every`` that is no whole number
        of steps dividing the grid's.
    """
    covariance = _propagate(system, sources, functionals, output_every, by_source, cross)
    text = growth_text(system) if warn else None
    if text is not None:
        import warnings

        from ins_errors.errors import InsErrorsWarning

        warnings.warn(f"propagate: {text}", InsErrorsWarning, stacklevel=3)
    return covariance


def growth_text(system: LinearSystem) -> str | None:
    """The warning of :func:`propagate` when its equations grow exponentially over the
    grid, or None (:func:`~ins_errors.numeric.linear_system.growth_folds`, worded by
    :func:`~ins_errors.numeric.linear_system.growth_warning` with the system's
    ``damping_remedy``)."""
    from ins_errors.numeric.linear_system import growth_folds, growth_warning

    duration = float(system.times[-1])
    if growth_folds(system, duration) is None:
        return None
    F = system.F if system.time_invariant else system.F[0]
    return growth_warning(F, duration, system.model_name or "MODEL",
                          "the standard deviations are mostly that growth, not what the "
                          "sources do on a stable system", "propagation",
                          system.damping_remedy, static=system.time_invariant)


def _valued_sources(system: LinearSystem, sources: Sequence[SourceStatistics],
                    columns: list[int], functionals: Functionals):
    """The sources that carry a value (constants and Markov sources: all but white
    noise), as the augmented state holds them: their indices in ``sources``, their
    decay rates (−1/τ, 0 for a constant), their columns of G, the initial sensitivities
    of unit values (x_e(0) = E b(0), b(0) = 1), shape (n + m, m), and the functionals'
    weights on them, shape (q, m)."""
    n = system.E.shape[0]
    valued = [i for i, s in enumerate(sources) if s.kind != "white"]
    decay = np.array([0.0 if sources[i].kind == "constant" else -1.0 / sources[i].tau
                      for i in valued])
    cols_b = [columns[i] for i in valued]
    Z0 = np.zeros((n + len(valued), len(valued)))
    Z0[:n] = system.E[:, cols_b]
    Z0[n:] = np.eye(len(valued))
    return valued, decay, cols_b, Z0, functionals.C_b[:, cols_b]


def _on_grid(system: LinearSystem, functionals: Functionals):
    """F, G and the functionals' C_x at every grid time, shapes (K + 1, n, n),
    (K + 1, n, nw), (K + 1, q, n): read-only views where one is constant."""
    K, n, q = len(system.times) - 1, system.E.shape[0], len(functionals.names)
    F = np.broadcast_to(system.F, (K + 1, n, n)) if system.F.ndim == 2 else system.F
    G = np.broadcast_to(system.G, (K + 1, *system.G.shape)) if system.G.ndim == 2 \
        else system.G
    C_x = np.broadcast_to(functionals.C_x, (K + 1, q, n)) if functionals.C_x.ndim == 2 \
        else functionals.C_x
    return F, G, C_x


def _static_noise(system: LinearSystem, functionals: Functionals, column: int,
                  source: SourceStatistics, dt: float):
    """One noise source on a time-invariant system, steps of ``dt``: the transition of
    its noise system (:func:`_noise_column`), a factor of the noise it adds a step, and
    the functionals on its state."""
    A, b = _noise_column(system.F, system.G[:, column], source)
    Cn = _noise_functionals(functionals.C_x, functionals.C_b[:, column], source)
    Phi_n, Qd = (m[0] for m in rank_one_noise_step(A[None], b[None], dt))
    return Phi_n, _noise_factor(Qd), Cn


def _propagate(system: LinearSystem, sources: Sequence[SourceStatistics],
               functionals: Functionals, output_every: int,
               by_source: bool, cross: bool = False) -> Covariance:
    if cross:
        return _propagate_cross(system, sources, functionals, output_every, by_source)
    columns = _validate(system, sources, functionals)
    output_every = output_stride(output_every, system)
    n = system.E.shape[0]
    K = len(system.times) - 1
    dt = system.step
    # augmented states: every constant and Markov source carries a value b_j
    valued, decay, cols_b, Z0, C_b = _valued_sources(system, sources, columns, functionals)
    keep = np.arange(0, K + 1, output_every)
    q = len(functionals.names)
    unit = np.zeros((len(keep), q, len(sources)))
    sigma2 = np.array([s.sigma**2 for s in sources])

    if system.time_invariant and functionals.C_x.ndim == 2:
        # exact discretisation at the output step: Φ(s·dt) = Φ(dt)^s
        keep = np.arange(0, K // output_every + 1) * output_every
        K_out, dt_out = len(keep) - 1, dt * output_every
        unit = np.zeros((len(keep), q, len(sources) if by_source else 1))
        Phi = _expm(augmented_dynamics(system.F, system.G[:, cols_b], decay) * dt_out)
        C = np.hstack([functionals.C_x, C_b])
        if by_source:
            unit[:, :, valued] = power_sequence(Phi, Z0, C, K_out)**2
        elif any(sources[i].kind == "markov" for i in valued):
            Z0s = Z0 * np.sqrt(sigma2[valued])  # exact factor: one column per source
            unit[:, :, 0] = power_sequence(Phi, Z0s, C, K_out, reduce="square-sum")
        elif valued:
            unit[:, :, 0] = _constants_total(Phi, n, system.E[:, cols_b], C_b,
                                             functionals.C_x, sigma2[valued], K_out)
        for i, s in enumerate(sources):
            if s.kind == "constant":
                continue
            Phi_n, factor, Cn = _static_noise(system, functionals, columns[i], s, dt_out)
            y = power_sequence(Phi_n, factor, Cn, K_out, reduce="square-sum")
            var = np.concatenate([np.zeros((1, q)), np.cumsum(y, axis=0)[:-1]])
            if by_source:
                unit[:, :, i] += var
            else:
                unit[:, :, 0] += var * s.sigma**2
    else:
        F, G, C_x = _on_grid(system, functionals)
        chunks = _sensitivity_chunks(F, G, cols_b, decay, dt, Z0, C_x, C_b, keep)
        if not by_source and len(valued) == len(sources) and not np.any(decay):
            # constants only: the total piece by piece, never the whole (nt, q, ns) array
            total = np.zeros((len(keep), q, 1))
            for i0, i1, Y in chunks:      # valued = every source, in order
                np.square(Y, out=Y)
                Y *= sigma2
                total[i0:i1] = Y.sum(-1, keepdims=True)
            return Covariance(system.times[keep], functionals.names, functionals.units, (),
                              total, total_only=True)
        for i0, i1, Y in chunks:
            unit[i0:i1, :, valued] = Y**2
        white = [i for i, s in enumerate(sources) if s.kind == "white"]
        groups = ([white] if white else []) + [[i] for i, s in enumerate(sources)
                                               if s.kind == "markov"]
        for group in groups:   # the white sources together, each Markov source alone
            cols = [columns[i] for i in group]
            unit[:, :, group] += _moving_noise_variance(
                F, G[..., cols], [sources[i] for i in group], dt, C_x,
                functionals.C_b[:, cols], keep)
        if not by_source:
            unit = (unit * sigma2).sum(-1, keepdims=True)
    used = tuple(sources) if by_source else ()
    return Covariance(system.times[keep], functionals.names, functionals.units, used, unit,
                      total_only=not by_source)


def _propagate_cross(system: LinearSystem, sources: Sequence[SourceStatistics],
                     functionals: Functionals, output_every: int,
                     by_source: bool) -> Covariance:
    """:func:`propagate` with the whole covariance matrix of the functionals.

    Each source's unit part is formed by the same discretisation as the variances (the
    sensitivities of the random values, the noise systems' covariances), with the outer
    products of the sensitivities and ``C P Cᵀ`` in place of their squares and
    diagonals; the variances are then those of :func:`propagate` without ``cross``, so
    they do not change with it. The parts come one source at a time
    (:func:`_cross_parts`): by source they fill the (nt, q, q, ns) array, for the total
    only they are scaled and added up as they come, so that array is never formed.
    """
    plain = _propagate(system, sources, functionals, output_every, True)
    keep = np.searchsorted(system.times, plain.times)
    q = len(functionals.names)
    parts = _cross_parts(system, sources, functionals, output_every, keep)
    if not by_source:
        total = np.zeros((len(keep), q, q, 1))
        for i, part in parts:      # in the order of the sources
            part *= sources[i].sigma**2
            total[..., 0] += part
        sigma2 = np.array([s.sigma**2 for s in sources])
        return Covariance(plain.times, plain.names, plain.units, (),
                          (plain.unit_variances * sigma2).sum(-1, keepdims=True),
                          total_only=True, unit_covariances=total)
    unit = np.empty((len(keep), q, q, len(sources)))
    for i, part in parts:
        unit[..., i] = part
    return dataclasses.replace(plain, unit_covariances=unit)


def _cross_parts(system: LinearSystem, sources: Sequence[SourceStatistics],
                 functionals: Functionals, output_every: int, keep: np.ndarray):
    """Each source's unit covariance matrix of the functionals at the grid indices
    ``keep``: yields ``(i, part)`` for the sources in order, part of shape
    (len(keep), q, q), a new array each (the caller may scale it in place).

    The sensitivities of the valued sources (constants, Markov) are kept for all of them,
    (nt, q, m), a q-th of one part each; a source's part is the outer product of its
    column, plus its noise's ``C P Cᵀ`` for a white or Markov one.
    """
    columns = [system.source_index(s.name) for s in sources]
    dt = system.step
    valued, decay, cols_b, Z0, C_b = _valued_sources(system, sources, columns, functionals)
    q = len(functionals.names)
    static = system.time_invariant and functionals.C_x.ndim == 2
    if static:
        K_out, dt_out = len(keep) - 1, dt * output_every
        Y = np.zeros((len(keep), q, 0))
        if valued:
            Phi = _expm(augmented_dynamics(system.F, system.G[:, cols_b], decay) * dt_out)
            Y = power_sequence(Phi, Z0, np.hstack([functionals.C_x, C_b]), K_out)
    else:
        F, G, C_x = _on_grid(system, functionals)
        Y = np.zeros((len(keep), q, len(valued)))
        for i0, i1, Yc in _sensitivity_chunks(F, G, cols_b, decay, dt, Z0, C_x, C_b, keep):
            Y[i0:i1] = Yc
    for i, s in enumerate(sources):
        if s.kind == "white":
            part = np.zeros((len(keep), q, q))
        else:
            j = valued.index(i)
            part = Y[:, :, None, j] * Y[:, None, :, j]        # Y Yᵀ of its column
        if s.kind == "constant":
            yield i, part
            continue
        if static:
            Phi_n, factor, Cn = _static_noise(system, functionals, columns[i], s, dt_out)
            Yn = power_sequence(Phi_n, factor, Cn, K_out)
            Pn = np.einsum("kqr,kpr->kqp", Yn, Yn)
            del Yn
            part[1:] += np.cumsum(Pn, axis=0, out=Pn)[:-1]
        else:
            part += _moving_noise_variance(
                F, G[..., [columns[i]]], [s], dt, C_x,
                functionals.C_b[:, [columns[i]]], keep, full=True)[..., 0]
        yield i, part


def _moving_noise_variance(F: np.ndarray, g: np.ndarray,
                           sources: Sequence[SourceStatistics], dt: float, C_x: np.ndarray,
                           c_b: np.ndarray, keep: np.ndarray, full: bool = False
                           ) -> np.ndarray:
    """Variances of the functionals from unit noise sources along a time-varying system.

    The covariance of each source's noise system (:func:`_noise_column`) is carried step
    by step, ``P_{k+1} = Φ_k P_k Φ_kᵀ + Qd_k``, from ``P_0 = 0``; Φ and Qd of
    :data:`_CHUNK` steps at a time come from the batched series of the noise's column
    (:func:`~ins_errors.numeric.step_exponential.rank_one_noise_step`, the Van Loan pair
    without its double-size block), so the working memory stays a few MB whatever the
    duration. Several white sources share their system matrix: its transition is
    formed once and their covariances are carried side by side.

    Parameters
    ----------
    F : numpy.ndarray, shape (K + 1, n, n)
    g : numpy.ndarray, shape (K + 1, n, r)
        The sources' columns of G at the grid times.
    sources : sequence of SourceStatistics
        ``r`` white sources, or one Markov source (sigma not used: unit statistics).
    dt : float
        Step, s.
    C_x : numpy.ndarray, shape (K + 1, q, n)
    c_b : numpy.ndarray, shape (q, r)
        The functionals' direct dependence on the sources' values (Markov sources).
    keep : numpy.ndarray of int
        Output grid indices, increasing.
    full : bool
        Return the whole ``C P Cᵀ``, shape (len(keep), q, q, r), not its diagonal.

    Returns
    -------
    numpy.ndarray, shape (len(keep), q, r)
    """
    K, n, r = F.shape[0] - 1, F.shape[-1], g.shape[-1]
    markov = sources[0].kind == "markov"
    q = C_x.shape[1]
    var = np.zeros((len(keep), q, q, r) if full else (len(keep), q, r))
    m = n + 1 if markov else n
    P = np.zeros((r, m, m))
    for k0 in range(0, K + 1, _CHUNK):
        k1 = min(K + 1, k0 + _CHUNK)      # covariances P_k0 .. P_{k1-1} in this piece
        s1 = min(K, k1)                   # steps k0 .. s1-1 taken here
        if s1 > k0:
            A, b = _step_matrix(F[k0:s1 + 1]), _step_matrix(g[k0:s1 + 1])
            if markov:
                A, b = _noise_column(A, b[..., 0], sources[0])
                b = b[..., None]
            Phi, Qd = rank_one_noise_step(A, b, dt)              # Qd: (steps, r, m, m)
            Phi_t = np.swapaxes(Phi, -1, -2)
        Ps = np.empty((k1 - k0, r, m, m))
        for k in range(k0, k1):
            Ps[k - k0] = P
            if k < K:
                P = Phi[k - k0] @ P @ Phi_t[k - k0] + Qd[k - k0]
        i0, i1 = (int(i) for i in np.searchsorted(keep, [k0, k1]))
        ks = keep[i0:i1]
        Ck = C_x[ks]
        if markov:
            Ck = np.concatenate([Ck, np.broadcast_to(c_b[:, :1], (len(ks), len(c_b), 1))],
                                axis=-1)
        # diagonal of C P Cᵀ for each source: (kept steps, r, q)
        Ck = Ck[:, None]
        if full:
            var[i0:i1] = np.einsum("krqb,krpb->kqpr", Ck @ Ps[ks - k0], Ck)
            continue
        var[i0:i1] = np.swapaxes(np.einsum("krqb,krqb->krq", Ck @ Ps[ks - k0], Ck), 1, 2)
    return var


def _moving_sensitivities(F: np.ndarray, G: np.ndarray, cols_b: list[int],
                          decay: np.ndarray, dt: float, Z0: np.ndarray, C_x: np.ndarray,
                          C_b: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """``C_k z_k`` of the augmented state along a time-varying system, at ``keep``.

    Parameters
    ----------
    F : numpy.ndarray, shape (K + 1, n, n)
        Error-state matrix at the grid times (held at the mean of its ends over a step).
    G : numpy.ndarray, shape (K + 1, n, nw)
        Source matrix at the grid times.
    cols_b : list of int
        Columns of ``G`` of the valued sources (m of them).
    decay : numpy.ndarray, shape (m,)
        ``-1/τ`` of Markov sources, 0 for constants.
    Z0 : numpy.ndarray, shape (n + m, m)
    C_x : numpy.ndarray, shape (K + 1, q, n)
    C_b : numpy.ndarray, shape (q, m)

    Returns
    -------
    numpy.ndarray, shape (len(keep), q, m)
    """
    Ys = np.zeros((len(keep), C_b.shape[0], len(cols_b)))
    for i0, i1, Y in _sensitivity_chunks(F, G, cols_b, decay, dt, Z0, C_x, C_b, keep):
        Ys[i0:i1] = Y
    return Ys


def _sensitivity_chunks(F: np.ndarray, G: np.ndarray, cols_b: list[int],
                        decay: np.ndarray, dt: float, Z0: np.ndarray, C_x: np.ndarray,
                        C_b: np.ndarray, keep: np.ndarray):
    """:func:`_moving_sensitivities` in pieces: yields ``(i0, i1, Ys[i0:i1])``.

    When every valued source is a constant the sources never change, so only the error
    state is carried: ``x_{k+1} = Φ_k x_k + Γ_k`` with ``Φ_k = e^{F_k dt}`` and
    ``Γ_k = W_k G_b``, ``W_k = ∫₀^dt e^{F_k s} ds`` (the blocks of the exponential of
    ``[[F, I], [0, 0]] dt``, Van Loan), instead of the exponential of the (n + m)-square
    augmented matrix. Φ and W come from a batched series
    (:func:`~ins_errors.numeric.step_exponential.exp_and_integral`) a few thousand steps
    at a time, and the pieces are yielded as they are done, so the working memory is a
    few MB whatever the duration. With a Markov source the augmented transitions
    (:func:`~ins_errors.numeric.step_exponential.exponential`) are also formed a few
    thousand steps at a time, and the sensitivities at ``keep`` yielded at the end.
    """
    K, n, m = F.shape[0] - 1, F.shape[-1], len(cols_b)
    if m == 0:
        return
    if not np.any(decay):
        X = Z0[:n].copy()  # the source rows stay the identity
        every = int(keep[1] - keep[0]) if len(keep) > 1 else 1
        if every < 1 or not np.array_equal(keep, np.arange(keep[0], keep[-1] + 1, every)):
            every = 0
        for k0 in range(0, max(K, 1), _CHUNK):
            k1 = min(K, k0 + _CHUNK)
            Phi, W = exp_and_integral(_step_matrix(F[k0:k1 + 1]), dt)
            Gamma = W @ _step_matrix(G[k0:k1 + 1])[..., cols_b]
            Xs = affine_states(Phi, Gamma, X)                   # states k0 .. k1
            last = k1 + 1 if k1 == K else k1                    # outputs k0 .. last-1
            i0, i1 = (int(i) for i in np.searchsorted(keep, [k0, last]))
            if i1 > i0 and every:          # evenly spaced outputs: views, not copies
                ks = slice(int(keep[i0]), int(keep[i1 - 1]) + 1, every)
                shifted = slice(ks.start - k0, ks.stop - k0, every)
            else:
                ks = keep[i0:i1]
                shifted = ks - k0
            yield i0, i1, C_x[ks] @ Xs[shifted] + C_b
            X = Xs[-1]
        return
    # Markov sources: the augmented transitions, a piece of steps at a time
    Ys = np.zeros((len(keep), C_b.shape[0], m))
    Z = Z0.copy()
    for k0 in range(0, K + 1, _CHUNK):
        k1 = min(K, k0 + _CHUNK)          # steps k0 .. k1-1 taken here
        last = min(K + 1, k0 + _CHUNK)    # sensitivities k0 .. last-1 kept here
        Zs = np.empty((last - k0, *Z.shape))
        Zs[0] = Z
        if k1 > k0:
            Phis = exponential(augmented_dynamics(_step_matrix(F[k0:k1 + 1]),
                                                  _step_matrix(G[k0:k1 + 1])[..., cols_b],
                                                  decay), dt)
            for j in range(1, last - k0):
                np.matmul(Phis[j - 1], Zs[j - 1], out=Zs[j])
            if k1 == last:                # the next piece starts from z_k1
                Z = Phis[-1] @ Zs[-1]
        i0, i1 = (int(i) for i in np.searchsorted(keep, [k0, last]))
        ks = keep[i0:i1]
        C = np.concatenate([C_x[ks], np.broadcast_to(C_b, (len(ks), *C_b.shape))], axis=-1)
        Ys[i0:i1] = C @ Zs[ks - k0]
    yield 0, len(keep), Ys


_CHUNK = 4096
"""Steps whose exponentials are evaluated together (a few MB of arrays)."""


def affine_states(Phi: np.ndarray, Gamma: np.ndarray, X0: np.ndarray) -> np.ndarray:
    """States of ``X_{k+1} = Φ_k X_k + Γ_k`` from ``X_0``, each step a product then a sum.

    Parameters
    ----------
    Phi : numpy.ndarray, shape (K, n, n)
    Gamma : numpy.ndarray, shape (K, n, m)
    X0 : numpy.ndarray, shape (n, m)

    Returns
    -------
    numpy.ndarray, shape (K + 1, n, m)
        ``X_0 … X_K``.
    """
    Xs = np.empty((len(Phi) + 1, *X0.shape))
    Xs[0] = X0
    for P, g, x, y in zip(Phi, Gamma, Xs[:-1], Xs[1:], strict=True):
        np.matmul(P, x, out=y)
        y += g
    return Xs


def _constants_total(Phi: np.ndarray, n: int, E: np.ndarray, C_b: np.ndarray,
                     C_x: np.ndarray, sigma2: np.ndarray, steps: int) -> np.ndarray:
    """Total variance from random constants only, on a reduced state (fast path).

    With constants b, ``x_{k+1} = Φx x_k + Γ b``; the state ``(x, g = Γ b, h = C_b b)``
    evolves with ``Ψ = [[Φx, I, 0], [0, I, 0], [0, 0, I]]``, of dimension 2n + (rows of
    C_b in use) instead of n + (number of sources).
    """
    Phi_x, Gamma = Phi[:n, :n], Phi[:n, n:]
    rows = np.flatnonzero(np.any(C_b != 0, axis=1))
    q, r = C_x.shape[0], len(rows)
    Psi = np.eye(2 * n + r)
    Psi[:n, :n] = Phi_x
    Psi[:n, n:2 * n] = np.eye(n)
    Z0 = np.vstack([E, Gamma, C_b[rows]])
    C = np.zeros((q, 2 * n + r))
    C[:, :n] = C_x
    C[rows, 2 * n + np.arange(r)] = 1.0
    V = Z0 * np.sqrt(sigma2)  # exact factor of the initial covariance, one column a source
    return power_sequence(Psi, V, C, steps, reduce="square-sum")


def _noise_column(F: np.ndarray, g: np.ndarray, source: SourceStatistics
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The system of :func:`_noise_system` as ``(A, b)``: its noise enters through the one
    column ``b`` (``BQBᵀ = b bᵀ``), g itself for a white source, ``√(2/τ)`` on the Markov
    state for a Markov one (shapes (K, N, N) and (K, N))."""
    if source.kind == "white":
        return np.asarray(F), np.asarray(g)
    n = F.shape[-1]
    A = augmented_dynamics(F, g[..., None], np.array([-1.0 / source.tau]))
    b = np.zeros(A.shape[:-1])
    b[..., n] = np.sqrt(2.0 / source.tau)
    return A, b


def _noise_system(F: np.ndarray, g: np.ndarray, source: SourceStatistics,
                  C_x: np.ndarray, c_b: np.ndarray):
    """Small augmented system carrying only one noise source's driving noise (unit σ).

    White noise: state x_e, noise through g with PSD 1. Markov: state (x_e, b),
    ḃ = −b/τ + n with PSD 2/τ and b(0) = 0 (its stationary start is handled with the
    constants). Returns (A, BQBᵀ, C) with C the functionals on that state.
    """
    A, b = _noise_column(F, g, source)
    if source.kind == "white":
        return A, b[..., :, None] * b[..., None, :], C_x
    n = F.shape[-1]
    BQBt = np.zeros(A.shape)
    BQBt[..., n, n] = 2.0 / source.tau   # (b bᵀ, without rounding √(2/τ)²)
    return A, BQBt, _noise_functionals(C_x, c_b, source)


def _noise_functionals(C_x: np.ndarray, c_b: np.ndarray, source: SourceStatistics
                       ) -> np.ndarray | None:
    """The functionals on the state of :func:`_noise_column`: ``C_x`` for a white source,
    ``[C_x, c_b]`` for a Markov one (None when ``C_x`` varies in time)."""
    if source.kind == "white":
        return C_x
    return np.hstack([C_x, c_b[:, None]]) if C_x.ndim == 2 else None
