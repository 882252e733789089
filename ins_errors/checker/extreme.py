"""Reported points that do not depend on the last bit of a value.

The checker names the point (or sample, or case) where a discrepancy is largest. The
same coefficient can differ in its last bit depending on the batch of expressions it
was evaluated with (kept values from earlier checks in the same process), so a plain
``argmax`` over an exact tie (e.g. "hand/model = 2 at every point") could name a
different point depending on which checks ran before. These helpers take the *first*
entry, in the fixed order given, whose value is within a relative ``RELATIVE`` of the
largest one: last-bit differences cannot change the choice.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TypeVar

import numpy as np

#: Relative distance from the largest value within which values count as a tie.
RELATIVE = 1e-12

T = TypeVar("T")


def first_largest(values: np.ndarray, relative: float = RELATIVE) -> int:
    """Index of the first value within ``relative`` of the largest.

    Parameters
    ----------
    values : numpy.ndarray, shape (n,)
        Non-empty; NaN and infinity are allowed.
    relative : float
        Tie tolerance relative to the largest magnitude.

    Returns
    -------
    int
        As ``numpy.argmax`` when the largest value is NaN or infinite (its first
        occurrence); otherwise the first index ``i`` with
        ``values[i] >= top - relative * |top|``.
    """
    values = np.asarray(values)
    j = int(np.argmax(values))
    top = values[j]
    if not np.isfinite(top):
        return j
    return int(np.argmax(values >= top - relative * abs(top)))


def at_least(a: float, b: float, relative: float = RELATIVE) -> bool:
    """``a >= b`` where ``a`` within ``relative`` of ``b`` (in magnitude) counts as a tie."""
    return bool(a >= b or a >= b - relative * max(abs(a), abs(b)))


def first_largest_item(items: Sequence[T], key: Callable[[T], float],
                       relative: float = RELATIVE) -> T:
    """The first of ``items`` whose ``key`` is within ``relative`` of the largest key."""
    return items[first_largest(np.array([key(item) for item in items], dtype=float),
                               relative)]
