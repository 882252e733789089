"""One BLAS thread for work on small matrices.

The error equations have tens of rows (the exponential of an 11 × 11 error-equation
matrix, stacks of 15 × 15 steps, covariance and Monte Carlo products): waking BLAS threads
for them costs far more than they save. On a busy 2-core machine ``scipy.linalg.expm`` of
an 11 × 11 matrix took about 8 ms of CPU with OpenBLAS's threads and 40 µs with one. Used
by the hand checker, covariance propagation and the linear Monte Carlo.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from functools import wraps
from typing import ParamSpec, TypeVar

P = ParamSpec("P")
R = TypeVar("R")

_KEPT: list = [-1, None]  # [number of imported modules at the lookup, controller]


def _controller():
    """The process's BLAS thread pools.

    The lookup costs milliseconds, so it is kept, and repeated only when modules were
    imported since (an import can load another BLAS library, e.g. a second OpenBLAS
    bundled with another package, which must be limited too).
    """
    if _KEPT[0] != len(sys.modules):
        from threadpoolctl import ThreadpoolController

        _KEPT[1] = ThreadpoolController()
        _KEPT[0] = len(sys.modules)
    return _KEPT[1]


def one_blas_thread(function: Callable[P, R]) -> Callable[P, R]:
    """Run ``function`` with BLAS limited to one thread (restored afterwards)."""

    @wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        with _controller().limit(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return limited
