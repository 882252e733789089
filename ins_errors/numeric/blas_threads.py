"""One BLAS thread for work on small matrices.

The error equations have tens of rows (the exponential of an 11 × 11 error-equation
matrix, stacks of 15 × 15 steps, covariance and Monte Carlo products): waking BLAS threads
for them costs far more than they save. On a busy 2-core machine ``scipy.linalg.expm`` of
an 11 × 11 matrix took about 8 ms of CPU with OpenBLAS's threads and 40 µs with one. Used
by the hand checker, covariance propagation and the linear Monte Carlo.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable
from contextlib import ExitStack
from functools import wraps
from importlib import import_module
from types import ModuleType
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

    The limit reaches the BLAS libraries loaded when the call starts; a module that
    brings its own (SciPy bundles a second OpenBLAS) and is imported during the call
    must be imported with :func:`import_limited` for the limit to reach it too.
    """

    @wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        with ExitStack() as limits:
            limits.enter_context(_controller().limit(limits=1, user_api="blas"))
            calls = _open_limits()
            calls.append([limits, len(sys.modules)])
            try:
                return function(*args, **kwargs)
            finally:
                calls.pop()

    return limited


def import_limited(module: str) -> ModuleType:
    """``importlib.import_module(module)``; inside a :func:`one_blas_thread` call, the BLAS
    libraries loaded since that call's limit was set are limited to one thread as well,
    until the call ends.

    For modules imported on first use (so that processes which never use them do not
    pay for the import) that bring their own BLAS: with SciPy's OpenBLAS left threaded,
    each exponential of a 12 × 12 matrix cost about 7 ms of CPU instead of about 0.1 ms.
    """
    loaded = import_module(module)
    calls = _open_limits()
    if calls and calls[-1][1] != len(sys.modules):
        calls[-1][0].enter_context(_controller().limit(limits=1, user_api="blas"))
        calls[-1][1] = len(sys.modules)
    return loaded


_THREAD_STATE = threading.local()


def _open_limits() -> list[list]:
    """This thread's running :func:`one_blas_thread` calls, innermost last: each its
    exit stack of limits and the number of imported modules when the last was set."""
    if not hasattr(_THREAD_STATE, "calls"):
        _THREAD_STATE.calls = []
    return _THREAD_STATE.calls
