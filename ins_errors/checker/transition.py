"""State transition matrices of a sampled linear model, kept for reuse.

Φ(t) of ``ẏ = A(t) y`` for A sampled on a uniform grid (:func:`transitions`): the matrix
exponential for a constant A, otherwise a product of step exponentials of the mean of A
at each step's two ends (:func:`step_exponentials`). Results are kept in memory for the
next check in the same process and on disk for the next process
(:mod:`~ins_errors.checker.propagation_store`).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict

import numpy as np

from ins_errors.checker import propagation_store
from ins_errors.numeric.blas_threads import import_limited


def step_exponentials(A: np.ndarray, dt: float) -> np.ndarray:
    """exp(A dt) for a batch (K, n, n): scaling and squaring with a degree-10 Taylor sum.

    ``result = Σ_k term_k``, ``term_k = term_{k-1} @ M / k`` (``M = A dt / 2^s``), then
    ``s`` squarings; evaluated in place (the stacks are megabytes: fresh arrays for each
    operation cost as much as the products), the same operations in the same order.
    """
    M = A * dt
    norm = np.max(np.sum(np.abs(M), axis=-1))
    squarings = max(0, int(np.ceil(np.log2(norm / 0.25)))) if norm > 0.25 else 0
    M /= 2**squarings
    result = np.empty_like(M)
    result[...] = np.eye(A.shape[-1])
    term, spare = result.copy(), np.empty_like(M)
    for k in range(1, 11):
        np.matmul(term, M, out=spare)
        spare /= k
        term, spare = spare, term
        result += term
    for _ in range(squarings):
        np.matmul(result, result, out=spare)
        result, spare = spare, result
    return result


_KEPT: OrderedDict[tuple, tuple[np.ndarray, ...]] = OrderedDict()
KEEP = 256
"""Propagations kept for the next check in the same process (a few kB each)."""


def transitions(A: np.ndarray, times: np.ndarray, at: list[float]) -> list[np.ndarray]:
    """Φ(t) of ``ẏ = A(t) y`` (A sampled on the uniform grid ``times``) at times ``at``.

    A constant A (one sample repeated) uses the matrix exponential directly; otherwise each
    step uses the exponential of the mean of A at its two ends (second order).

    Kept for the next check in the same process, by the content of ``A``, ``times`` and
    ``at`` (checks of the same model on the same motions propagate the same derived model,
    and mostly the same single-entry changes of it), and on disk for the next process
    (:mod:`~ins_errors.checker.propagation_store`); the kept matrices are read-only.
    """
    key = (A.shape, A.dtype.str, _digest(A), _digest(np.asarray(times, dtype=float)),
           tuple(float(t) for t in at))
    kept = _KEPT.get(key)
    if kept is None:
        stored = propagation_store.name(key)
        kept = propagation_store.load(stored)
        if kept is None or len(kept) != len(at) or kept[0].shape != A.shape[1:]:
            kept = tuple(_computed(A, times, at))
            propagation_store.store(stored, kept)
        for phi in kept:
            phi.setflags(write=False)
        _KEPT[key] = kept
        while len(_KEPT) > KEEP:
            _KEPT.popitem(last=False)
    else:
        _KEPT.move_to_end(key)
    return list(kept)


def _digest(array: np.ndarray) -> bytes:
    """SHA-1 of an array's bytes (half the time of BLAKE2b on these stacks: ~2 ms for a
    day's 1441 steps of 15 × 15, against ~10 ms for the propagation it may save)."""
    return hashlib.sha1(np.ascontiguousarray(array).data, usedforsecurity=False).digest()


def _computed(A: np.ndarray, times: np.ndarray, at: list[float]) -> list[np.ndarray]:
    """:func:`transitions`, computed (within :func:`check_matrices`' one-thread limit,
    which the import extends to SciPy's own BLAS)."""
    expm = import_limited("scipy.linalg").expm

    # a model with an exponentially growing mode overflows to inf / nan: the report says
    # it grows exponentially and writes no number, so the floating-point warnings of
    # that overflow (numpy's and SciPy's matrix products) tell nothing more
    with np.errstate(over="ignore", invalid="ignore"):
        if np.all(A[:1] == A):
            return [expm(A[0] * t) for t in at]
        return _stepped(A, times, at)


def _stepped(A: np.ndarray, times: np.ndarray, at: list[float]
                        ) -> list[np.ndarray]:
    """:func:`_computed` of a time-varying A: each step the exponential of the mean
    of A at its two ends."""
    dt = float(times[1] - times[0])
    mean = A[1:] + A[:-1]
    mean *= 0.5
    steps = step_exponentials(mean, dt)
    wanted = {round(t / dt): t for t in at}
    out: dict[float, np.ndarray] = {}
    phi, spare = np.eye(A.shape[-1]), np.empty(A.shape[1:])
    for k in range(steps.shape[0] + 1):
        if k in wanted:
            out[wanted[k]] = phi.copy()
        if k < steps.shape[0]:
            np.matmul(steps[k], phi, out=spare)
            phi, spare = spare, phi
    return [out[t] for t in at]
