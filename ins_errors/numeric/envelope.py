"""Long curves reduced to what a screen can show: per pixel column, the first, last,
smallest and largest sample (the "M4" reduction of Jugel et al., VLDB 2014).

A day recorded every second is 86 400 samples drawn across a few hundred pixel
columns; a line through the four kept samples of each column covers the same pixels
as the line through all of them (no peak is lost: every column keeps its extremes), at a
fraction of the drawing cost. Only the drawn path is reduced; files of curves keep every
sample.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def column_envelopes(x: np.ndarray, curves: Sequence[np.ndarray], columns: int
                     ) -> list[tuple[np.ndarray, np.ndarray]]:
    """The samples of each curve that a plot ``columns`` pixels wide needs.

    Parameters
    ----------
    x : numpy.ndarray, shape (N,)
        Increasing abscissae (e.g. times), shared by the curves.
    curves : sequence of numpy.ndarray, shape (N,) each
        Values.
    columns : int
        Number of columns the range ``x[0] .. x[-1]`` spans on the drawing (pass more
        than the pixel width, e.g. twice, to keep sub-pixel detail for antialiasing).

    Returns
    -------
    list of (x, y), numpy.ndarray of shape (M,) each
        Per curve, the kept samples in their order: in each column its first, last,
        smallest and largest sample (M <= 4 columns). A curve is kept whole when it is
        not longer than that or has non-finite values (NaN gaps are drawn as they are),
        and all are when ``x`` does not increase.
    """
    x = np.asarray(x)
    n = x.size
    if (columns < 1 or n <= 4 * columns or not np.all(np.isfinite(x))
            or not np.all(np.diff(x) > 0)):
        return [(x, np.asarray(y)) for y in curves]
    column = np.minimum(((x - x[0]) * (columns / (x[-1] - x[0]))).astype(np.intp),
                        columns - 1)
    first = np.flatnonzero(np.r_[True, column[1:] != column[:-1]])
    last = np.r_[first[1:], n] - 1
    counts = last - first + 1
    reduced = []
    for y in curves:
        y = np.asarray(y)
        if not np.all(np.isfinite(y)):
            reduced.append((x, y))
            continue
        smallest = _first_where(y == np.repeat(np.minimum.reduceat(y, first), counts), column)
        largest = _first_where(y == np.repeat(np.maximum.reduceat(y, first), counts), column)
        keep = np.unique(np.concatenate([first, last, smallest, largest]))
        reduced.append((x[keep], y[keep]))
    return reduced


def _first_where(mask: np.ndarray, column: np.ndarray) -> np.ndarray:
    """Index of the first true ``mask`` entry of each column (every column has one)."""
    hits = np.flatnonzero(mask)
    return hits[np.r_[True, column[hits[1:]] != column[hits[:-1]]]]
