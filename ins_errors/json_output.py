"""The one JSON writer of every ``--json`` output and JSON results file.

Strict JSON has no NaN or Infinity: Python's :mod:`json` writes them as bare ``NaN`` /
``Infinity`` by default, which JavaScript's ``JSON.parse``, ``jq`` and most other parsers
refuse. Here a number that is not finite (an overflowed propagation, a ratio with no
denominator) is written as ``null``, NumPy scalars and arrays become plain numbers and
lists, and the encoder is told to refuse anything non-finite left over
(``allow_nan=False``), so a new writer cannot slip one through. A negative zero (the
−0/|λ| damping ratio of an undamped mode) is written as ``0.0``.

Every ``--json`` output goes through :func:`emit`, which puts ``"schema_version"``
(:data:`SCHEMA_VERSION`) first in its object (in each object of an array), so a script can
tell which set of keys it reads; ``docs/json.md`` lists every command's keys.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Mapping
from pathlib import PurePath
from typing import IO, Any

SCHEMA_VERSION = 2
"""Version of the keys of every ``--json`` output (``docs/json.md``): raised when a key is
renamed or removed or changes its meaning or unit, not when one is added."""


def plain(value: Any) -> Any:
    """``value`` with every non-finite float replaced by ``None``.

    Parameters
    ----------
    value : Any
        Dictionaries, lists, tuples, NumPy arrays and scalars, paths, strings, numbers,
        booleans and ``None``, nested in any way.

    Returns
    -------
    Any
        The same structure made of built-in types only (tuples and arrays as lists,
        paths as strings), with NaN and ±inf as ``None`` and −0.0 as 0.0.
    """
    if isinstance(value, float):  # + 0.0: a negative zero is written as 0.0
        return value + 0.0 if math.isfinite(value) else None
    if isinstance(value, (str, bool, int)) or value is None:
        return value
    if isinstance(value, Mapping):
        return {(k if isinstance(k, (str, int, float, bool)) else str(k)): plain(v)
                for k, v in value.items()}
    np = sys.modules.get("numpy")  # no NumPy values without NumPy imported
    if np is not None:
        if isinstance(value, np.ndarray):
            return plain(value.tolist())
        if isinstance(value, np.generic):
            return plain(value.item())
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, PurePath):
        return str(value)
    return value


def dumps(value: Any, *, indent: int | None = 2, **options: Any) -> str:
    """Strict JSON text of ``value`` (see :func:`plain`); other options go to
    :func:`json.dumps` (e.g. ``sort_keys``, ``ensure_ascii``)."""
    return json.dumps(plain(value), indent=indent, allow_nan=False, **options)


def versioned(value: Any) -> Any:
    """``value`` with ``"schema_version": SCHEMA_VERSION`` as the first key of the object
    (of each object of a list); anything else unchanged.

    Parameters
    ----------
    value : Any
        A command's ``--json`` output: an object, or an array of objects (several hand
        files, the list of models or studies).

    Returns
    -------
    Any
        A new object (list) when one is changed; ``value`` is left as it is.
    """
    if isinstance(value, Mapping):
        return {"schema_version": SCHEMA_VERSION, **value}
    if isinstance(value, (list, tuple)):
        return [versioned(v) if isinstance(v, Mapping) else v for v in value]
    return value


def emit(value: Any, stream: IO[str] | None = None, **options: Any) -> None:
    """Print a command's ``--json`` output ``value`` (:func:`versioned`) as strict JSON,
    indented by 2, followed by a newline, to ``stream`` (standard output by default)."""
    print(dumps(versioned(value), **options), file=stream if stream is not None else sys.stdout)
