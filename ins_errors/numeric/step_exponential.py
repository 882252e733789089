r"""Batched step exponentials: ``e^{F h}`` and ``∫₀^h e^{F s} ds`` for a stack of F.

A time-varying linear system held constant over each step needs, per step, the transition
``Φ = e^{F h}`` and the integral ``W = ∫₀^h e^{F s} ds`` (the response to a constant
input). SciPy's ``expm`` of the 2n-square block ``[[F, I], [0, 0]] h`` gives both but works
one matrix at a time; here the whole stack is evaluated at once with a truncated Taylor
series of :math:`φ_1(A) = Σ_k A^k/(k+1)!` (``A = F h``), from which ``W = h φ_1(A)`` and
``Φ = I + A φ_1(A)``, with scaling and squaring when the norms call for it.

Truncation bound. With ``A`` scaled by ``2^{-s}`` and the series cut after degree ``m``,
the neglected terms of :math:`φ_1` are bounded in the 1-norm by
:math:`Σ_{k>m} ‖A^k‖/(k+1)!` and those of :math:`e^A` by :math:`Σ_{k>m+1} ‖A^k‖/k!`,
where :math:`‖A^k‖ ≤ ‖A^2‖^{⌊k/2⌋} ‖A‖^{k \bmod 2}` uses the computed largest norms of
``A`` and ``A²`` over the batch. ``(s, m)`` is the cheapest pair for which both bounds are
at most the unit round-off 2⁻⁵³ (absolute; Φ and φ₁ are close to the identity over a
step, so this is below the rounding of their order-one entries). This matters for the
error equations of an INS: ``‖F h‖`` is about g·h (a tilt drives a velocity error) but
``‖(F h)²‖`` only about (ω_s h)², so a few terms suffice at h = 1 s without any scaling,
where a norm-based choice (e.g. SciPy's) would scale and square. Squaring then doubles
the step ``s`` times: ``W ← W + Φ W``, ``Φ ← Φ²``.

The polynomial is evaluated in powers of ``A²`` (Paterson-Stockmeyer with pairs):
``(m + 1)/2 + 1`` batched products for degree ``m`` (odd), e.g. 5 for m = 7.
"""

from __future__ import annotations

from math import factorial

import numpy as np

from ins_errors.errors import DomainError

UNIT_ROUNDOFF = 2.0**-53
"""Truncation target, 1-norm (absolute)."""

MAX_DEGREE = 17
"""Highest degree of the truncated φ₁ series (odd)."""


def _tails(a1: float, a2: float, m: int) -> tuple[float, float]:
    """1-norm bounds of the neglected terms of φ₁ (degree ``m``) and e^A (degree m+1).

    ``a1 >= ‖A‖``, ``a2 >= ‖A²‖``; requires ``a2 <= 1`` and ``a1 <= 2**10``, so that the
    terms past 40 further ones are below 2**10/41! and the sum is taken that far.
    """
    phi1 = expo = 0.0
    for k in range(m + 1, m + 42):
        bound = a2 ** (k // 2) * a1 ** (k % 2)
        phi1 += bound / factorial(k + 1)
        if k > m + 1:
            expo += bound / factorial(k)
    return phi1, expo


def choose_scaling(a1: float, a2: float) -> tuple[int, int]:
    """Cheapest ``(s, m)``: scaling ``2^{-s}`` and odd degree ``m`` meeting the bound.

    Parameters
    ----------
    a1, a2 : float
        Largest 1-norms of ``A`` and ``A²`` over the batch (unscaled).

    Returns
    -------
    s, m : int
        Number of squarings and degree of the φ₁ series; the cost in batched products is
        ``(m + 1)/2 + 1 + 2 s``.
    """
    if not (np.isfinite(a1) and np.isfinite(a2)):
        raise DomainError("step exponential: the system matrices are not finite (NaN or "
                          "infinite entries)")
    best: tuple[int, int, int] | None = None
    s = 0
    while True:
        a1s, a2s = a1 / 2.0**s, a2 / 4.0**s
        if a2s <= 1.0 and a1s <= 2.0**10:
            for m in range(1, MAX_DEGREE + 1, 2):
                if max(_tails(a1s, a2s, m)) <= UNIT_ROUNDOFF:
                    cost = (m + 1) // 2 + 1 + 2 * s
                    if best is None or cost < best[0]:
                        best = (cost, s, m)
                    break
        # more squarings only pay while they can beat the best cost found
        if best is not None and 2 * (s + 1) + 2 >= best[0]:
            return best[1], best[2]
        s += 1


def _scaled_series(F: np.ndarray, h: float
                   ) -> tuple[np.ndarray, np.ndarray, int, float, float]:
    """``(Φ, φ₁, s, a₁, a₂)`` of the scaled step ``A = F h 2^{-s}``: the series part, before
    squaring, and the largest 1-norms of that ``A`` and ``A²`` over the batch."""
    n = F.shape[-1]
    A = F * h
    A2 = A @ A
    a1 = float(np.abs(A).sum(axis=-2).max())
    a2 = float(np.abs(A2).sum(axis=-2).max())
    s, m = choose_scaling(a1, a2)
    if s:
        A *= 2.0**-s
        A2 *= 4.0**-s
    eye = np.eye(n)
    # φ₁(A) = Σ_k c_k A^k, c_k = 1/(k+1)!, grouped as Σ_j (c_2j I + c_2j+1 A) (A²)^j
    pairs = (m + 1) // 2
    S = A * (1.0 / factorial(2 * pairs))
    S += eye * (1.0 / factorial(2 * pairs - 1))
    for j in range(pairs - 2, -1, -1):
        S = A2 @ S
        S += A * (1.0 / factorial(2 * j + 2))
        S += eye * (1.0 / factorial(2 * j + 1))
    Phi = A @ S
    Phi += eye
    return Phi, S, s, a1 / 2.0**s, a2 / 4.0**s


def exp_and_integral(F: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """``Φ = e^{F h}`` and ``W = ∫₀^h e^{F s} ds`` for each matrix of a stack.

    Parameters
    ----------
    F : numpy.ndarray, shape (K, n, n)
        Continuous-time matrices, 1/s.
    h : float
        Step, s.

    Returns
    -------
    Phi, W : numpy.ndarray, shape (K, n, n)
        Transitions (dimensionless) and integrals (s), each within the truncation bound of
        the module docstring plus rounding.
    """
    F = np.asarray(F, dtype=float)
    if F.shape[0] == 0:
        return np.empty_like(F), np.empty_like(F)
    Phi, S, s, _, _ = _scaled_series(F, h)
    W = S * (h * 2.0**-s)
    for _ in range(s):
        W += Phi @ W
        Phi = Phi @ Phi
    return Phi, W


def exponential(F: np.ndarray, h: float) -> np.ndarray:
    """``Φ = e^{F h}`` alone for each matrix of a stack (the same series, no integral).

    Parameters
    ----------
    F : numpy.ndarray, shape (K, n, n)
        Continuous-time matrices, 1/s.
    h : float
        Step, s.

    Returns
    -------
    numpy.ndarray, shape (K, n, n)
        Transitions, within the truncation bound of the module docstring plus rounding
        (absolute, 1-norm: scale F, or h, so that the entries of Φ are of order one).
    """
    F = np.asarray(F, dtype=float)
    if F.shape[0] == 0:
        return np.empty_like(F)
    Phi, _, s, _, _ = _scaled_series(F, h)
    for _ in range(s):
        Phi = Phi @ Phi
    return Phi


MAX_MOMENTS = 60
"""Highest degree of the series of ``e^{Aσ} b`` (:func:`rank_one_noise_step`); about 30
suffice at the largest scaled norms :func:`choose_scaling` leaves (``‖A‖ = 2**10``)."""


def _moment_degree(a1: float, a2: float, n: int) -> int:
    """Degree ``d`` of the series of ``e^{Aσ} b`` that :func:`rank_one_noise_step` needs.

    With ``‖A^k‖ ≤ a₂^⌊k/2⌋ a₁^(k mod 2) =: β_k`` (``a₂ <= 1``, ``a₁ <= 2**10`` after
    :func:`choose_scaling`), the terms left out of the double sum for ``Qd`` are bounded in
    the 1-norm by ``h ‖b‖₁² · 2 T_d S`` with ``T_d = Σ_{k>d} β_k/k!`` and
    ``S = Σ_k β_k/k!``; ``d`` is the least degree with ``2 T_d S <= u / n²`` (``u`` the
    unit round-off; ``n²`` covers ``‖b‖₁² <= n² max b_i²``, so the bound holds relative to
    the largest entry of ``h b bᵀ``).
    """
    terms = [a2 ** (k // 2) * a1 ** (k % 2) / factorial(k) for k in range(MAX_MOMENTS + 45)]
    total = sum(terms)
    for degree in range(1, MAX_MOMENTS + 1):
        if 2.0 * sum(terms[degree + 1:]) * total <= UNIT_ROUNDOFF / n**2:
            return degree
    raise DomainError("step exponential: the noise-covariance series does not converge "
                      "(scaled norms out of range)")   # unreachable after choose_scaling


def rank_one_noise_step(F: np.ndarray, b: np.ndarray, h: float
                        ) -> tuple[np.ndarray, np.ndarray]:
    r"""Transition and added covariance of ``ẋ = F x + b n`` (unit white ``n``) per step.

    The Van Loan pair of a noise entering through one column ``b``: ``Φ = e^{F h}`` and
    :math:`Q_d = ∫_0^h y(σ) y(σ)^T dσ` with :math:`y(σ) = e^{Fσ} b`. Instead of the
    exponential of the 2n-square block ``[[-F, b bᵀ], [0, Fᵀ]] h``, ``y`` is expanded as
    :math:`Σ_k (σ/h)^k v_k` with :math:`v_k = (F h)^k b / k!` (``d`` matrix-vector
    products), which gives :math:`Q_d = h\, V H V^T` with the Hilbert-type weights
    ``H_jk = 1/(j + k + 1)``; ``Φ`` is the series of :func:`exponential`. With the scaling
    ``s`` of :func:`choose_scaling` both are formed for ``h 2^{-s}`` and doubled ``s``
    times: ``Qd ← Φ Qd Φᵀ + Qd``, ``Φ ← Φ²``. The truncation bound is that of
    :func:`_moment_degree`. Several independent noises through the same F (columns of
    ``b``) share Φ and get one ``Qd`` each.

    Parameters
    ----------
    F : numpy.ndarray, shape (K, n, n)
        Continuous-time matrices, 1/s.
    b : numpy.ndarray, shape (K, n) or (K, n, r)
        The noise's column per step (state units per unit noise, per √s), or the columns
        of ``r`` independent noises.
    h : float
        Step, s.

    Returns
    -------
    Phi : numpy.ndarray, shape (K, n, n)
        Transitions.
    Qd : numpy.ndarray, shape (K, n, n) or (K, r, n, n)
        Added covariances (symmetric), one per noise.
    """
    F = np.asarray(F, dtype=float)
    b = np.asarray(b, dtype=float)
    columns = b if b.ndim == 3 else b[..., None]
    n = F.shape[-1]
    if F.shape[0] == 0:
        return np.empty_like(F), np.empty((0, columns.shape[-1], n, n) if b.ndim == 3
                                          else (0, n, n))
    if not np.all(np.isfinite(b)):
        raise DomainError("noise step: the noise column is not finite (NaN or infinite "
                          "entries)")
    Phi, _, s, a1, a2 = _scaled_series(F, h)
    step = h * 2.0**-s
    degree = _moment_degree(a1, a2, n)
    A = F * step
    v = columns
    moments = [v]
    for k in range(1, degree + 1):
        v = (A @ v) * (1.0 / k)                            # (K, n, r)
        moments.append(v)
    V = np.moveaxis(np.stack(moments, axis=-1), 2, 1)  # (K, r, n, d + 1)
    j = np.arange(degree + 1)
    weights = 1.0 / (j[:, None] + j[None, :] + 1.0)
    Qd = (V @ weights) @ np.swapaxes(V, -1, -2)        # (K, r, n, n)
    Qd *= step
    for _ in range(s):
        Qd = Phi[:, None] @ Qd @ np.swapaxes(Phi, -1, -2)[:, None] + Qd
        Phi = Phi @ Phi
    Qd = 0.5 * (Qd + np.swapaxes(Qd, -1, -2))
    return Phi, (Qd if b.ndim == 3 else Qd[:, 0])
