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
from importlib import import_module
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
    """Run ``function`` with BLAS limited to one thread (restored afterwards).

    Only the BLAS libraries loaded when the call starts are limited: a module imported
    during the call may bring its own (SciPy bundles a second OpenBLAS), which then runs
    threaded. Use :func:`one_blas_thread_after_importing` for functions that import such a
    module lazily.
    """
    return _limited(function, None)


def one_blas_thread_after_importing(module: str) -> Callable[[Callable[P, R]], Callable[P, R]]:
    """:func:`one_blas_thread`, with ``module`` (e.g. ``"scipy.linalg"``) imported first.

    For functions that import a BLAS-bundling module on first use, so that processes which
    never call them do not pay for the import, and the limit still reaches that module's
    BLAS. With SciPy's OpenBLAS left threaded, each exponential of a 12 × 12 matrix cost
    about 7 ms of CPU instead of about 0.1 ms.
    """

    def decorate(function: Callable[P, R]) -> Callable[P, R]:
        return _limited(function, module)

    return decorate


def _limited(function: Callable[P, R], module: str | None) -> Callable[P, R]:
    @wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        if module is not None:
            import_module(module)
        with _controller().limit(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return limited
