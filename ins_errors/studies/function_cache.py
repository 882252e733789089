"""casadi functions derived from SymPy at run time, kept on disk between processes.

A methodological study's simplified computer takes about 1 s CPU of SymPy work to
derive in each new process. Its casadi functions are kept, in casadi's own
serialisation, in ``$INS_ERRORS_CACHE/functions`` (or the user cache folder next to the
compiled loops): one JSON file per name and key. The key is the SHA-256 of every Python
source file of the package together with the versions of SymPy and casadi, so that a
changed model, code generator or library gives another key and a kept file is never
used for other code. At most :data:`KEEP_VERSIONS` files of one name are kept (the
least recently used are deleted), a few tens of kB each. A file that cannot be read is
derived again, and so is a damaged one (cut short, altered: each file is sealed,
:func:`ins_errors.numeric.cache.write_entry`; said in one line); a cache folder that
cannot be written only costs the derivation.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
from collections.abc import Mapping, Sequence
from functools import cache
from pathlib import Path

import casadi as ca

FORMAT = 2
"""Version of the file layout (part of the key)."""

KEEP_VERSIONS = 8
"""Files of one name kept in the folder: other source versions, e.g. the checkouts of one
user sharing the cache (~45 kB a file)."""


def cache_directory() -> Path:
    """``$INS_ERRORS_CACHE/functions``, or ``functions`` next to the compiled loops'
    folder in the user cache."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("functions")


@cache
def source_key() -> str | None:
    """SHA-256 (32 hex digits) of the package's Python sources and of the SymPy and
    casadi versions; None when the package has no source files to hash (then nothing
    is kept). Read once per process: the code that runs is the code imported."""
    from importlib.metadata import version

    package = Path(__file__).resolve().parents[1]
    sources = sorted(package.rglob("*.py"))
    if Path(__file__).resolve() not in sources:
        return None
    digest = hashlib.sha256(f"format {FORMAT}; casadi {ca.__version__}; "
                            f"sympy {version('sympy')}".encode())
    for path in sources:
        data = path.read_bytes()
        digest.update(f"\n{path.relative_to(package).as_posix()} {len(data)}\n".encode())
        digest.update(data)
    return digest.hexdigest()[:32]


def _file(name: str) -> Path | None:
    key = source_key()
    return None if key is None else cache_directory() / f"{name}-{key}.json"


def read(name: str, names: Sequence[str]) -> tuple[ca.Function, ...] | None:
    """The functions ``names`` kept under ``name`` for this source key, or None when
    there is no readable file."""
    path = _file(name)
    if path is None:
        return None
    from ins_errors.numeric.cache import read_entry

    raw = read_entry(path, "deriving the functions again")
    if raw is None:
        return None
    try:
        data = json.loads(raw.decode("utf-8"))
        functions = tuple(ca.Function.deserialize(data[n]) for n in names)
    except (OSError, ValueError, KeyError, TypeError, RuntimeError):
        return None
    if any(f.is_null() for f in functions):  # e.g. an empty string deserialises to NULL
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # last use, for the pruning order
    return functions


def write(name: str, functions: Mapping[str, ca.Function]) -> None:
    """Keep ``functions`` under ``name`` for this source key (atomically; best effort)."""
    path = _file(name)
    if path is None:
        return
    from ins_errors.numeric.cache import drop_least_recent, write_entry

    text = json.dumps({n: f.serialize() for n, f in functions.items()})
    pattern = re.compile(re.escape(name) + r"-[0-9a-f]{32}\.json")
    try:
        write_entry(path, text.encode("utf-8"))
        # the least recently used other versions of ``name`` beyond KEEP_VERSIONS go
        drop_least_recent((p for p in path.parent.iterdir()
                           if p != path and pattern.fullmatch(p.name)), KEEP_VERSIONS - 1)
    except OSError:
        pass  # not kept: derived again next time
