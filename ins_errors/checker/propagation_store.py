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

At most :data:`KEEP` files are kept (a few kB each): a store that takes the folder past
it (as this process counts: its first store counts the folder, later ones add their new
files) counts again and drops the least recently used beyond :func:`kept_after_prune`,
a quarter below the bound, so the folder is listed about once per ``KEEP / 4`` stores,
not at each (a listing of 4096 files takes ~30 ms, a propagation ~10 ms). Processes
storing at once each count only their own files between listings, so together they may
pass the bound by what the others stored since; the next store past it drops them.
(The oldest were once dropped by the first store of each process only: a matrix check
that stored more after it left the folder above the bound, 4107 files of 4096.)
A file that cannot be read or written is no error: the propagation is then computed as
before; a damaged one (cut short, altered: each file is sealed,
:func:`ins_errors.numeric.cache.write_entry`) is said in one line and computed again.
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
"""Stored propagations kept at most (the most recently used; ~2-8 kB each)."""

_counted: list[int] = []
"""The files this process last counted in the folder, plus its new files stored since
(empty until its first store)."""


def kept_after_prune() -> int:
    """Files a prune leaves: the most recently used three quarters of :data:`KEEP`."""
    return KEEP - KEEP // 4


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
    """Store ``phis`` under ``name`` (atomically); a store that takes the folder past
    :data:`KEEP` files (as this process counts them) drops the least recently used down
    to :func:`kept_after_prune`."""
    from ins_errors.numeric.cache import write_entry

    target = folder()
    path = target / f"{name}.npy"
    data = io.BytesIO()
    np.save(data, np.array(phis))
    try:
        new = not path.exists()
        write_entry(path, data.getvalue())
        if not _counted:  # the first store of this process: count the folder
            _counted.append(prune(target, KEEP, down_to=kept_after_prune()))
        elif new:
            _counted[0] += 1
        if _counted[0] > KEEP:  # count again (others may have pruned or stored)
            _counted[0] = prune(target, KEEP, down_to=kept_after_prune())
    except OSError:
        pass  # not stored (or not pruned): computed again next time


def prune(target: Path, keep: int, down_to: int | None = None) -> int:
    """Delete all but the ``keep`` most recently used files of ``target`` (all but
    ``down_to`` when there are more than ``keep``); returns the files left."""
    from ins_errors.numeric.cache import drop_least_recent

    paths = list(target.glob("*.npy"))
    if len(paths) <= keep:
        return len(paths)
    left = keep if down_to is None else min(down_to, keep)
    drop_least_recent(paths, left)
    return left
