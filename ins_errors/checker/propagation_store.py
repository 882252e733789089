"""The matrix check's propagations, kept on disk for the next ``ins-errors check``.

A matrix check propagates the derived model, the hand model and the derived model with
each finding's entry replaced, over a day of samples (a product of ~1,440 step
exponentials each, :func:`ins_errors.checker.transition.transitions`). The next check of
the same model along the same motions propagates mostly the same matrices again (the
derived model always; the hand's entries until the researcher changes them). Each
result is stored under the content of its inputs (the digests of the sampled matrix
stack, of the sample times and the requested instants: the key the process already
keeps them under) and the code version (:func:`~ins_errors.checker.motion_store.
code_version`), in ``transitions/`` beside the stored motions, and read back exactly.

At most :data:`KEEP` files are kept (a few kB each); the oldest are dropped by the first
store of each process. A file that cannot be read or written is no error: the
propagation is then computed as before; a damaged one (cut short, altered: each file is
sealed, :func:`ins_errors.numeric.cache.write_entry`) is said in one line and computed
again.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
from pathlib import Path

import numpy as np

from ins_errors.checker.motion_store import code_version

KEEP = 4096
"""Stored propagations kept (the most recently used; ~2-8 kB each)."""

_pruned: list[bool] = []


def folder() -> Path:
    """``$INS_ERRORS_CACHE/transitions``, or ``transitions`` next to the compiled loops
    (beside the stored motions)."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("transitions")


def name(key: tuple) -> str:
    """File name (without suffix) of the propagation kept in process under ``key``."""
    digest = hashlib.sha256(code_version().encode())
    digest.update(repr(key).encode())
    return digest.hexdigest()[:40]


def load(name: str) -> tuple[np.ndarray, ...] | None:
    """The stored transition matrices, or None if not stored."""
    from ins_errors.numeric.cache import read_entry

    path = folder() / f"{name}.npy"
    raw = read_entry(path, "propagating again")
    if raw is None:
        return None
    try:
        stack = np.load(io.BytesIO(raw), allow_pickle=False)
    except (OSError, ValueError):
        return None
    if stack.ndim != 3:
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # most recently used
    return tuple(np.array(phi) for phi in stack)


def store(name: str, phis: tuple[np.ndarray, ...]) -> None:
    """Store ``phis`` under ``name`` (atomically); the first store of a process drops the
    oldest files beyond :data:`KEEP`."""
    from ins_errors.numeric.cache import write_entry

    target = folder()
    data = io.BytesIO()
    np.save(data, np.array(phis))
    try:
        write_entry(target / f"{name}.npy", data.getvalue())
        if not _pruned:
            _pruned.append(True)
            prune(target, KEEP)
    except OSError:
        pass  # not stored: computed again next time


def prune(target: Path, keep: int) -> None:
    """Delete all but the ``keep`` most recently used files of ``target``."""
    from ins_errors.numeric.cache import drop_least_recent

    drop_least_recent(target.glob("*.npy"), keep)
