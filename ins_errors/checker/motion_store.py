"""The matrix check's flown motions, kept on disk for the next ``ins-errors check``.

Every matrix or ``@convention`` check flies the same three motions of its model (a day
at 60-s samples: for the strapdown model a fine numerical integration of each flight,
about a second of CPU), and a researcher runs the check again and again on their own
file. The flown samples (times, ideal states, inputs, parameters) are stored once per
model, length, step, Earth shape and code version in ``$INS_ERRORS_CACHE/motions``
(or ``motions/`` next to the compiled loops in the user cache folder), as ``.npz``
files, and read back exactly (the same bits: the reports cannot change). A motion the
model cannot follow is stored as such, with its one-line reason (a file holds the whole
set: the motions flown and those not flown), so the next check skips it too, saying why.

The key holds everything the samples follow from: the model's generated numeric code
(its file's bytes), the request, the parameter vector, the source of the checker's
motion definitions, of the numeric package that flies them and of the Earth model and
units it uses, and the versions of Python, NumPy, SciPy and CasADi. Any change there
is a new key (the stale file is never read); only the :data:`KEEP` most recently used
files are kept. A file that cannot be read or written is no error: the motions are
then flown as before; a damaged one (cut short, altered: each file is sealed,
:func:`ins_errors.numeric.cache.write_entry`) is said in one line and flown again.
"""

from __future__ import annotations

import hashlib
import io
import os
import sys
from collections.abc import Sequence
from functools import cache
from pathlib import Path

import numpy as np

KEEP = 16
"""Stored motion sets kept (the most recently used)."""
FIELDS = ("times", "x", "u", "p")
"""Arrays stored per motion (see :class:`ins_errors.checker.check_motions.Motion`)."""


def folder() -> Path:
    """``$INS_ERRORS_CACHE/motions``, or ``motions`` next to the compiled loops."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("motions")


@cache
def code_version() -> str:
    """Hash of the source files and library versions the flown samples follow from (read
    once per process): checker/check_motions.py and what it flies and reads with
    (checker/navigation.py, checker/strapdown_description.py, numeric/*.py,
    models/earth.py, units.py), this module (the file's layout), and
    checker/transition.py, whose propagations the same version keys
    (:mod:`~ins_errors.checker.propagation_store`)."""
    from importlib.metadata import PackageNotFoundError, version

    from ins_errors.numeric.cache import code_digest

    package = Path(__file__).resolve().parent.parent
    checker = package / "checker"
    files = [*(checker / f"{name}.py" for name in ("check_motions", "navigation",
                                                    "strapdown_description", "transition",
                                                    "motion_store")),
             *sorted((package / "numeric").glob("*.py")),
             package / "models" / "earth.py", package / "units.py"]
    versions = [sys.version, np.__version__]
    for name in ("scipy", "casadi"):
        try:
            versions.append(f"{name} {version(name)}")
        except PackageNotFoundError:
            versions.append(f"{name} -")
    return code_digest(((path.name, path) for path in files), versions)


def key(model, hours: float, step: float, ellipsoid: str | None, p: np.ndarray) -> str:
    """The file name (without suffix) of one request's motions."""
    digest = hashlib.sha256()
    digest.update(code_version().encode())
    digest.update(Path(model.numpy.__file__).read_bytes())
    digest.update(repr((model.key, float(hours), float(step), ellipsoid)).encode())
    digest.update(np.ascontiguousarray(p, dtype=float).tobytes())
    return f"{model.name}_{digest.hexdigest()[:32]}"


def load(name: str) -> tuple[list[tuple[str, str, dict[str, np.ndarray]]], list[str]] | None:
    """The stored motions ``(label, description, arrays)`` and those not flown
    (``"label: reason"``), or None if not stored (or stored without the motions not
    flown: never a partial set read as the whole)."""
    from ins_errors.numeric.cache import read_entry

    path = folder() / f"{name}.npz"
    raw = read_entry(path, "flying the motions again")
    if raw is None:
        return None
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            labels = [str(s) for s in data["labels"]]
            descriptions = [str(s) for s in data["descriptions"]]
            out = [(label, text, {f: data[f"{i}_{f}"] for f in FIELDS})
                   for i, (label, text) in enumerate(zip(labels, descriptions, strict=True))]
            skipped = [str(s) for s in data["skipped"]]
        os.utime(path)  # most recently used
    except (OSError, KeyError, ValueError):
        return None
    return out, skipped


def store(name: str, motions: list[tuple[str, str, dict[str, np.ndarray]]],
          skipped: Sequence[str] = ()) -> None:
    """Store ``motions`` and the motions not flown, ``skipped`` (``"label: reason"``),
    under ``name`` (atomically) and drop the oldest beyond :data:`KEEP`."""
    from ins_errors.numeric.cache import drop_least_recent, write_entry

    target = folder()
    arrays = {"labels": np.array([m[0] for m in motions], dtype=str),
              "descriptions": np.array([m[1] for m in motions], dtype=str),
              "skipped": np.array(list(skipped), dtype=str)}
    for i, (_, _, fields) in enumerate(motions):
        arrays.update({f"{i}_{f}": np.asarray(fields[f]) for f in FIELDS})
    data = io.BytesIO()
    np.savez(data, **arrays)
    try:
        write_entry(target / f"{name}.npz", data.getvalue())
        drop_least_recent(target.glob("*.npz"), KEEP)
    except OSError:
        pass  # no store: the next check flies the motions again
