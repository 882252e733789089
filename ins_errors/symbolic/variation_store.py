"""Structured variations kept on disk for the next process.

:func:`~ins_errors.symbolic.variation.structured_variation` differentiates every
intermediate, state and output formula of a model and tidies each coefficient: about
0.5 s CPU for ``strapdown_ned``, 0.3 s for ``geodetic_vertical``, paid again by every
process that checks a hand derivation or writes the error-equation documents. The lines
are stored pickled in ``$INS_ERRORS_CACHE/variations`` (or ``variations/`` next to the
compiled loops in the user cache folder); reading them back takes ~0.03 s and gives equal
expressions, node for node (the same classes, arguments and assumptions).

The key holds everything the lines follow from: the definition's content (the
``srepr`` of every formula, symbol, name and LaTeX spelling the variation reads, see
:func:`fingerprint`, ~0.05 s) and the code that varies it (the source of
``symbolic/variation.py``, ``symbolic/shared_trees.py``, ``modeling.py`` and this file,
the versions of Python and SymPy). Any change there is a new key: a stale file is never
read. Only the :data:`KEEP` most recently used files are kept. A file that cannot be
read or written is no error: the lines are then computed as before; a damaged one (cut
short, altered: each file is sealed, :func:`ins_errors.numeric.cache.write_entry`) is
said in one line and computed again.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import pickle
import re
import sys
from functools import cache
from pathlib import Path

import sympy as sp

KEEP = 64
"""Stored variations kept (the most recently used; 5-20 kB each)."""

_SOURCES = ("symbolic/variation.py", "symbolic/shared_trees.py", "modeling.py",
            "symbolic/variation_store.py")
"""Package files (relative to ``ins_errors/``) whose code the lines follow from."""


def folder() -> Path:
    """``$INS_ERRORS_CACHE/variations``, or ``variations`` next to the compiled loops."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("variations")


@cache
def code_version() -> str:
    """Hash of the code the lines follow from (read once per process)."""
    from ins_errors.numeric.cache import code_digest

    package = Path(__file__).resolve().parent.parent
    return code_digest(((relative, package / relative) for relative in _SOURCES),
                       [sys.version, f"sympy {sp.__version__}"])


def fingerprint(d) -> str:
    """Hash of everything :func:`~ins_errors.symbolic.variation.structured_variation`
    reads from the definition ``d``: its real-work states, error states, sources, ideal
    point, real-work intermediates and right-hand sides, the output chains of the true
    and the computed state, and the names and LaTeX spellings of all of them."""
    from ins_errors.symbolic.variation import output_mechanisations

    true_mech, _, computed_mech, computed_out = output_mechanisations(d)
    digest = hashlib.sha256()

    def add(*parts) -> None:
        for part in parts:
            text = repr(part) if isinstance(part, str | int) else sp.srepr(part)
            digest.update(text.encode() + b"\0")
        digest.update(b"\1")

    add(len(d.states), *d.real_states)
    for var in d.error_states:
        add(var.name, var.latex, var.symbol)
    add(*d.w)
    for mapping in (d.at_ideal(), d.no_errors()):
        for symbol, value in mapping.items():
            add(symbol, value)
    for mech in (d.real, true_mech, computed_mech):
        for definition in mech.definitions:
            add(definition.symbol, definition.expression, definition.latex)
        digest.update(b"\2")
    add(*d.real_rhs)
    for var, expr in zip(d.outputs, computed_out, strict=True):
        add(var.name, var.latex, expr)
    for symbol, latex in d.latex_names().items():
        add(symbol, latex)
    return digest.hexdigest()


def key(d) -> str:
    """File name (without suffix) of the lines of definition ``d``."""
    digest = hashlib.sha256(code_version().encode())
    digest.update(fingerprint(d).encode())
    return f"{re.sub(r'[^A-Za-z0-9_.-]', '_', d.name)}_{digest.hexdigest()[:32]}"


def load(name: str) -> list | None:
    """The stored lines, or None if they are not stored (or cannot be read)."""
    from ins_errors.numeric.cache import read_entry

    path = folder() / f"{name}.pickle"
    raw = read_entry(path, "varying the model again")
    if raw is None:
        return None
    try:
        lines = pickle.loads(raw)
    except Exception:  # a damaged or foreign file: computed afresh
        return None
    if not isinstance(lines, list):
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # most recently used
    return lines


def store(name: str, lines: list) -> None:
    """Store ``lines`` under ``name`` (atomically) and drop the oldest beyond :data:`KEEP`."""
    from ins_errors.numeric.cache import drop_least_recent, write_entry

    target = folder()
    try:
        write_entry(target / f"{name}.pickle", pickle.dumps(lines, protocol=4))
        drop_least_recent(target.glob("*.pickle"), KEEP)
    except OSError:
        pass  # not stored: computed again next time
