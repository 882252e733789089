"""Naming the entries of an error matrix (F, G) that are not finite.

A derivative 0/0 (``d|V|/dV`` at V = 0, a term through a kink) leaves the linear error
equations without a value at a point: every command that evaluates F or G there refuses
it in one line naming the entries, as ``F[delta_V_N, delta_V_E]``, rather than printing
numpy's warnings about the generated code and failing later in other words.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

NAMED_ENTRIES = 6
"""Entries that are not finite which a refusal names one by one (then how many more)."""

WHY = ("the linear error equations have no value there (a derivative 0/0 or through a "
       "kink, such as d|V|/dV at V = 0)")
"""What a matrix that is not finite at a point means for the linear error model."""


def nonfinite_entries(symbol: str, matrix: np.ndarray, rows: Sequence[str],
                      columns: Sequence[str], used: np.ndarray | None = None) -> str | None:
    """The entries of ``matrix`` that are NaN or infinite, as text, or None.

    Parameters
    ----------
    symbol : str
        The matrix's name in the text (``"F"``, ``"G"``).
    matrix : numpy.ndarray
        Shape (len(rows), len(columns)) (or any shape of that size).
    rows, columns : sequence of str
        Names of its rows and columns (error states, error sources).
    used : numpy.ndarray, optional
        Shape (len(columns),): only these columns are looked at (a source not in use).

    Returns
    -------
    str or None
        ``"F[a, b], F[c, d] and F[e, f]"`` (the first :data:`NAMED_ENTRIES`, then how
        many more); None when every entry looked at is finite.
    """
    bad = ~np.isfinite(np.asarray(matrix, dtype=float).reshape(len(rows), len(columns)))
    if used is not None:
        bad &= np.asarray(used, dtype=bool)[None, :]
    if not bad.any():
        return None
    entries = [f"{symbol}[{rows[r]}, {columns[c]}]" for r, c in zip(*np.nonzero(bad),
                                                                     strict=True)]
    if len(entries) > NAMED_ENTRIES:
        entries = [*entries[:NAMED_ENTRIES], f"{len(entries) - NAMED_ENTRIES} more"]
    return " and ".join([", ".join(entries[:-1]), entries[-1]] if len(entries) > 1
                        else entries)
