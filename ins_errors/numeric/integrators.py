"""Fixed-step integrators: the manual's rectangle method, RK4, compiled CasADi loops.

Everything here is model-independent: a right-hand side is either a numpy callable
``f(z, u) -> dz/dt`` or a :class:`casadi.Function` ``f(z, u, w, p) -> dz/dt`` (state,
inputs, per-case constants, fixed constants), and the inputs are sampled on the step grid.

Schemes
-------
``"euler"`` (the rectangle method of the source documents)
    ``z[k+1] = z[k] + τ f(z[k], u[k])``: exactly the difference equations the lab manual
    prints for the ideal and the real work.
``"rk4"``
    Classical fourth order Runge-Kutta; the inputs are needed at the step times and at
    the midpoints ``t[k] + τ/2``.

Compiled path
-------------
:class:`CompiledLoop` builds the one-step map as a CasADi function and generates its C
code; a small loop written here in C (not by CasADi) repeats it ``record_every`` times
per recorded sample and ``chunk`` samples per call, keeping the state in two buffers.
It is compiled once with the machine's C compiler, without fused multiply-add
contraction (:data:`IEEE_FLAGS`: every operation rounded as IEEE 754 says, so the
compiled loop gives the bits of the CasADi virtual machine), into a shared library cached
on disk (``$INS_ERRORS_CACHE`` or ``~/.cache/ins-errors/casadi``; read only, with new
loops in a private temporary folder, if that is not writable; size-limited, least
recently used first out:
:mod:`ins_errors.numeric.cache`)
and calls it on numpy buffers in place through :mod:`ctypes` (:class:`NativeFunction`).
Where no compiler works it falls back to the CasADi virtual machine and says so once
(a :class:`RuntimeWarning`); ``jit=False`` or the environment variable
``INS_ERRORS_NO_JIT`` choose the VM on purpose. A long run is a Python loop over chunks,
which is where progress is shown (tqdm, on a terminal) and where a caller may look at
the samples recorded so far and stop the run (``run(check=...)``: a run that left its
domain stops within a piece instead of running to its end). The domain margin (e.g.
1 − u31²) is computed at every recorded sample.

Time-invariant linear systems (a static base) can instead be stepped exactly with the
matrix exponential: :func:`exact_discretisation`.
"""

from __future__ import annotations

import ctypes
import errno
import hashlib
import math
import os
import platform
import re
import shutil
import signal
import subprocess
import threading
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cache as cache_function
from pathlib import Path
from typing import Literal

import casadi as ca
import numpy as np

from ins_errors.errors import InsErrorsError, InsErrorsNotice, ShapeError
from ins_errors.numeric import cache

Method = Literal["euler", "rk4"]
METHODS: tuple[str, ...] = ("euler", "rk4")
"""Names of the integration schemes."""


class StepError(InsErrorsError):
    """A step size, duration or recording interval that does not fit together."""


# --------------------------------------------------------------------------------------
# Grid checks
# --------------------------------------------------------------------------------------
def check_method(method: str) -> str:
    """Return ``method`` if it is a known scheme, else raise a one-line error."""
    if method not in METHODS:
        from ins_errors.errors import unknown_name

        raise unknown_name("integration method", method, METHODS)
    return method


MAX_STEPS = 1_000_000_000
"""Most steps one run may take: 115 days at 100 Hz, 11.6 days at 1 kHz. The memory of a
run does not grow with its steps (the true motion is streamed in chunks, the records are
what is recorded), but its time does: at about half a microsecond a step, a run this long
takes about ten minutes of CPU (a strapdown RK4 run with its linear twin, about half an
hour), so more is taken for a mistyped step or duration and refused before anything runs."""


STEP_TOLERANCE = 1e-6
"""How far, in steps, a duration may be from a whole number of steps and still count as
one (it is then taken as exactly that many). Absolute in steps, so a run of tens of
millions of steps is not rounded by a sizeable fraction of a step; far above the rounding
error of ``duration / τ`` for durations and steps typed in decimal (a few units in the
last place of the quotient: at most about 1e-7 step at :data:`MAX_STEPS`, which
:func:`whole_steps` allows for as well)."""


def whole_steps(duration: float, tau: float) -> int | None:
    """``duration / tau`` when it is a whole number of steps to :data:`STEP_TOLERANCE`
    (plus the rounding error of the quotient), else None.

    Parameters
    ----------
    duration : float
        Length, s (>= 0, finite).
    tau : float
        Step, s (> 0, finite).
    """
    steps = duration / tau
    n = round(steps)
    # duration and τ are each within half an ulp of what was typed, the quotient adds
    # another: 8 ulp of the quotient bounds that rounding with room
    if abs(steps - n) > STEP_TOLERANCE + 8 * np.spacing(abs(steps)):
        return None
    return int(n)


def _duration_text(n: int, tau: float) -> str:
    """``n τ`` as the shortest decimal text that reads back as ``n`` whole steps of τ."""
    value = n * tau
    for digits in range(6, 18):
        text = f"{value:.{digits}g}"
        if whole_steps(float(text), tau) == n:
            return text
    return repr(value)


def _exact_text(value: float) -> str:
    """The shortest decimal text of ``value`` that reads back as the same float."""
    return np.format_float_positional(value, unique=True, trim="-")


def step_count(duration: float, tau: float, what: str = "duration") -> int:
    """Number of steps of size ``tau`` in ``duration``.

    The duration must be a whole number of steps, to :data:`STEP_TOLERANCE` of a step
    (:func:`whole_steps`): a run never ends between two steps of the difference scheme.

    Parameters
    ----------
    duration : float
        Length of the run, s (>= 0).
    tau : float
        Step, s (> 0).
    what : str
        Name of the duration in error messages.

    Raises
    ------
    StepError
        Zero, negative or non-finite step; negative duration; duration not a multiple
        of the step (the message names the nearest durations that are); more than
        :data:`MAX_STEPS` steps.
    """
    tau, duration = float(tau), float(duration)
    if not np.isfinite(tau) or tau <= 0.0:
        raise StepError(f"integration step must be a positive number of seconds, got {tau:g}")
    if not np.isfinite(duration) or duration < 0.0:
        raise StepError(f"{what} must be a non-negative number of seconds, got {duration:g}")
    steps = duration / tau
    if steps > MAX_STEPS:
        raise StepError(f"{what} {duration:g} s in steps of {tau:g} s is {steps:.3g} steps, "
                        f"more than the {MAX_STEPS:.0e} one run may take: use a longer step "
                        "or a shorter run")
    n = whole_steps(duration, tau)
    if n is None:
        nearest = _nearest_text(math.floor(steps), math.ceil(steps), tau)
        raise StepError(f"{what} {_exact_text(duration)} s is not a whole number of steps "
                        f"of {_exact_text(tau)} s ({steps:.10g} steps); the nearest that "
                        f"are: {nearest}; or choose a step that divides it")
    return n


def _nearest_text(below: int | None, above: int | None, tau: float) -> str:
    """``"3598 s or 3605 s"``: the lengths of ``below`` and ``above`` whole steps of
    ``tau`` that are positive (None: none), as text that reads back as those steps."""
    return " or ".join(f"{_duration_text(k, tau)} s" for k in (below, above)
                       if k is not None and k > 0)


def _nearest_divisors(n: int, target: float) -> tuple[int | None, int | None]:
    """The largest divisor of ``n`` (> 0) below ``target`` and the smallest above it (None
    where there is none), found among the divisors up to √n and their cofactors."""
    below = above = None
    for d in range(1, math.isqrt(n) + 1):
        if n % d:
            continue
        for divisor in (d, n // d):
            if divisor < target and (below is None or divisor > below):
                below = divisor
            if divisor > target and (above is None or divisor < above):
                above = divisor
    return below, above


def record_stride(record_interval: float | None, tau: float, n_steps: int) -> int:
    """Steps between two recorded samples (``None``: record every step).

    Raises
    ------
    StepError
        If the interval is not a positive multiple of the step or does not divide the run:
        the message names the nearest intervals that are whole steps dividing the run
        and, for a whole number of steps, the nearest durations that are whole intervals
        (as :func:`step_count` names the nearest durations of a step).
    """
    if record_interval is None:
        return 1
    interval, tau = float(record_interval), float(tau)
    steps = interval / tau if tau > 0 else math.nan
    if n_steps > 0 and 0 < steps <= MAX_STEPS and whole_steps(interval, tau) is None:
        nearest = _nearest_text(*_nearest_divisors(n_steps, steps), tau)
        raise StepError(f"recording interval {_exact_text(interval)} s is not a whole "
                        f"number of steps of {_exact_text(tau)} s ({steps:.10g} steps); "
                        f"the nearest that are and divide the run of {n_steps} steps: "
                        f"{nearest}; or choose a step that divides it")
    k = step_count(record_interval, tau, "recording interval")
    if k == 0:
        raise StepError("recording interval must be at least one step")
    if n_steps % k:
        intervals = _nearest_text(*_nearest_divisors(n_steps, k), tau)
        runs = _nearest_text(n_steps // k * k, -(-n_steps // k) * k, tau)
        raise StepError(f"the run of {n_steps} steps ({_duration_text(n_steps, tau)} s) is "
                        f"not a whole number of recording intervals of {k} steps "
                        f"({record_interval:g} s); the nearest intervals that divide it: "
                        f"{intervals}; or the nearest durations that are whole intervals: "
                        f"{runs}")
    return k


# --------------------------------------------------------------------------------------
# numpy schemes (reference implementations; vectorised over trailing batch axes)
# --------------------------------------------------------------------------------------
def euler_step(f: Callable[[np.ndarray, np.ndarray], np.ndarray], z: np.ndarray,
               u: np.ndarray, tau: float) -> np.ndarray:
    """One rectangle-method step ``z + τ f(z, u)``."""
    return z + tau * f(z, u)


def rk4_step(f: Callable[[np.ndarray, np.ndarray], np.ndarray], z: np.ndarray,
             u0: np.ndarray, u_half: np.ndarray, u1: np.ndarray, tau: float) -> np.ndarray:
    """One classical Runge-Kutta step with the inputs at ``t``, ``t + τ/2``, ``t + τ``."""
    k1 = f(z, u0)
    k2 = f(z + 0.5 * tau * k1, u_half)
    k3 = f(z + 0.5 * tau * k2, u_half)
    k4 = f(z + tau * k3, u1)
    return z + tau / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def integrate(f: Callable[[np.ndarray, np.ndarray], np.ndarray], z0: np.ndarray,
              inputs: np.ndarray, tau: float, method: Method = "euler",
              midpoints: np.ndarray | None = None, record_every: int = 1) -> np.ndarray:
    """Integrate ``dz/dt = f(z, u)`` with a plain Python loop (reference, short runs).

    Parameters
    ----------
    f : callable
        ``f(z, u) -> dz/dt``, numpy, broadcasting over trailing axes.
    z0 : numpy.ndarray, shape (nz, ...)
        Initial state.
    inputs : numpy.ndarray, shape (nu, N + 1)
        Inputs at the step times ``t[k] = k τ`` (the last column is used by RK4 only).
    tau : float
        Step, s.
    method : {"euler", "rk4"}
        Scheme.
    midpoints : numpy.ndarray, shape (nu, N), optional
        Inputs at ``t[k] + τ/2`` (required by RK4).
    record_every : int
        Keep every ``record_every``-th state.

    Returns
    -------
    numpy.ndarray, shape (nz, N // record_every + 1, ...)
        The recorded states, the initial state first.
    """
    check_method(method)
    if tau <= 0:
        raise StepError(f"integration step must be a positive number of seconds, got {tau:g}")
    n = inputs.shape[1] - 1
    if method == "rk4" and (midpoints is None or midpoints.shape[1] < n):
        raise StepError("RK4 needs the inputs at the step midpoints")
    z = np.asarray(z0, dtype=float)
    out = [z]
    for k in range(n):
        if method == "euler":
            z = euler_step(f, z, inputs[:, k], tau)
        else:
            z = rk4_step(f, z, inputs[:, k], midpoints[:, k], inputs[:, k + 1], tau)
        if (k + 1) % record_every == 0:
            out.append(z)
    return np.stack(out, axis=1)


def exact_discretisation(F: np.ndarray, G: np.ndarray, tau: float) -> tuple[np.ndarray,
                                                                             np.ndarray]:
    """Exact step of ``ė = F e + G w`` (F, G, w constant) over ``tau``.

    Uses the matrix exponential of the augmented matrix ``[[F, G], [0, 0]] τ``.

    Returns
    -------
    Phi : numpy.ndarray, shape (n, n)
        ``exp(F τ)``.
    Gamma : numpy.ndarray, shape (n, m)
        ``∫_0^τ exp(F s) ds G``, so that ``e[k+1] = Φ e[k] + Γ w``.
    """
    from scipy.linalg import expm

    n, m = G.shape
    block = np.zeros((n + m, n + m))
    block[:n, :n], block[:n, n:] = F, G
    exp = expm(block * tau)
    return exp[:n, :n], exp[:n, n:]


# --------------------------------------------------------------------------------------
# CasADi schemes
# --------------------------------------------------------------------------------------
def casadi_step(rhs: Callable, method: Method, z: ca.SX, u_stream: ca.SX, q: ca.SX,
                tau: ca.SX | float, rotations: Sequence[tuple[int, int, int]] = ()) -> ca.SX:
    """Symbolic one-step map of ``rhs(z, u, q)`` (a casadi.Function or a callable).

    ``u_stream`` is ``u[k]`` for Euler and ``vertcat(u[k], u[k+1/2], u[k+1])`` for RK4.
    ``rotations`` lists ``(angle, sine, cosine)`` indices of ``z`` whose sine and cosine
    components are carried (:mod:`ins_errors.numeric.carried_trig`): wherever the scheme
    moves ``z`` on by an increment, those two components are rotated through the angle's
    increment instead (what ``rhs`` returns for them is not used).
    """
    if method == "euler":
        return _moved(z, tau * rhs(z, u_stream, q), rotations)
    nu = u_stream.shape[0] // 3
    u0, uh, u1 = u_stream[:nu], u_stream[nu:2 * nu], u_stream[2 * nu:]
    k1 = rhs(z, u0, q)
    k2 = rhs(_moved(z, 0.5 * tau * k1, rotations), uh, q)
    k3 = rhs(_moved(z, 0.5 * tau * k2, rotations), uh, q)
    k4 = rhs(_moved(z, tau * k3, rotations), u1, q)
    return _moved(z, tau / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4), rotations)


def _moved(z: ca.SX, increment: ca.SX, rotations: Sequence[tuple[int, int, int]]) -> ca.SX:
    """``z + increment``, the carried sines and cosines rotated by their angle's increment."""
    moved = z + increment
    if not rotations:
        return moved
    from ins_errors.numeric.carried_trig import rotate

    parts = [moved[k] for k in range(moved.shape[0])]
    for angle, sine, cosine in rotations:
        parts[sine], parts[cosine] = rotate(z[sine], z[cosine], increment[angle])
    return ca.vertcat(*parts)


def input_stream(inputs: np.ndarray, midpoints: np.ndarray | None, method: Method) -> np.ndarray:
    """Per-step input columns for a compiled loop.

    Parameters
    ----------
    inputs : numpy.ndarray, shape (nu, N + 1)
        Inputs at the step times.
    midpoints : numpy.ndarray, shape (nu, N) or None
        Inputs at the midpoints (RK4 only).

    Returns
    -------
    numpy.ndarray, shape (nu, N) for Euler or (3 nu, N) for RK4
    """
    if method == "euler":
        return inputs[:, :-1]
    if midpoints is None:
        raise StepError("RK4 needs the inputs at the step midpoints")
    return np.vstack([inputs[:, :-1], midpoints, inputs[:, 1:]])


@dataclass(frozen=True)
class InputRows:
    """A piece of a run's inputs as rows, read by a compiled loop where they lie (no
    stream of :func:`stream_rows` is built; the same numbers reach every step).

    Attributes
    ----------
    steps : numpy.ndarray, shape (N + 1, nu), C order
        Inputs at the step times.
    midpoints : numpy.ndarray, shape (N, nu), C order, or None
        Inputs at the step midpoints (RK4; None for Euler).
    """

    steps: np.ndarray
    midpoints: np.ndarray | None

    def check(self, n_steps: int, nu: int, method: Method) -> None:
        """Raise :class:`StepError` unless the rows fit ``n_steps`` steps of ``nu``
        inputs for ``method``."""
        wanted = [(self.steps, (n_steps + 1, nu))]
        if method != "euler":
            wanted.append((self.midpoints, (n_steps, nu)))
        for array, shape in wanted:
            if (array is None or array.shape != shape or array.dtype != np.float64
                    or not array.flags.c_contiguous):
                raise StepError(f"input rows must be contiguous float arrays of shape "
                                f"{shape}, got {None if array is None else array.shape}")


def stream_rows(inputs: np.ndarray, midpoints: np.ndarray | None, method: Method,
                out: np.ndarray | None = None) -> np.ndarray:
    """The rows of :func:`input_stream`, one per step, as :meth:`CompiledLoop.advance`
    reads them: the same numbers, copied once (no stacked intermediate), into ``out``
    when given (a long run reuses one buffer instead of faulting in fresh pages per piece).

    Parameters
    ----------
    inputs : numpy.ndarray, shape (nu, N + 1)
        Inputs at the step times.
    midpoints : numpy.ndarray, shape (nu, N) or None
        Inputs at the midpoints (RK4 only).
    out : numpy.ndarray, optional
        C-ordered float buffer of the returned shape to fill.

    Returns
    -------
    numpy.ndarray, shape (N, nu) for Euler or (N, 3 nu) for RK4, C order
    """
    nu, n = inputs.shape[0], inputs.shape[1] - 1
    if method != "euler" and midpoints is None:
        raise StepError("RK4 needs the inputs at the step midpoints")
    shape = (n, nu if method == "euler" else 3 * nu)
    if out is None:
        out = np.empty(shape)
    elif out.shape != shape or out.dtype != np.float64 or not out.flags.c_contiguous:
        raise StepError(f"stream buffer must be a contiguous float array of shape {shape}, "
                        f"got {out.shape}")
    if method == "euler":
        out[:] = inputs[:, :-1].T
        return out
    out[:, :nu] = inputs[:, :-1].T
    out[:, nu:2 * nu] = midpoints.T
    out[:, 2 * nu:] = inputs[:, 1:].T
    return out

# --------------------------------------------------------------------------------------
# Compilation with an on-disk cache
# --------------------------------------------------------------------------------------
_NOTICE_GIVEN = False


def cache_directory() -> Path:
    """Where compiled loops are kept (see :mod:`ins_errors.numeric.cache`)."""
    return cache.directory()


def _writable(directory: Path) -> Path:
    """Where compiled loops are looked up and written: ``directory`` if it can be made
    and written, else this user's private folder (which links to the loops a read-only
    ``directory`` holds), said once: :func:`ins_errors.numeric.cache.loops_directory`.

    Raises
    ------
    InsErrorsError
        If ``$INS_ERRORS_CACHE_LIMIT`` is not a size, or ``$INS_ERRORS_CACHE`` names
        something that cannot be a folder: a folder the user chose is not silently
        replaced.
    """
    return cache.loops_directory(directory)


def _cpu_identity() -> str:
    """Machine and CPU model (the cache must not hand one CPU's code to another)."""
    model = platform.processor()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as handle:
            for line in handle:
                if line.startswith(("model name", "flags", "Features")):
                    model += line
    except OSError:
        pass
    return platform.machine() + model


def _compiler() -> str | None:
    name = os.environ.get("CC", "cc")
    return shutil.which(name) or shutil.which("gcc") or shutil.which("clang")


NOTICE_GIVEN_VARIABLE = "INS_ERRORS_VM_NOTICE_GIVEN"
"""Set (to ``1``) for worker processes whose parent has already said that loops run in
the virtual machine: they do not say it again (see :func:`compiler_checked`)."""

PROBE_SOURCE = "int ins_errors_compiler_probe(void) { return 0; }\n"
"""The C source :func:`compiler_checked` compiles (once, then cached) to learn whether
loops compile here."""


def _vm_notice(reason: str, full: Path | None = None) -> None:
    """Say once per process, and not in the workers of a process that said it, that
    compiled loops run in the CasADi virtual machine (a :class:`RuntimeWarning`; the
    command line prints it as one line): for want of a working compiler (``reason``),
    or, when ``full`` is given, for want of space in that folder (a full disk is not a
    broken compiler: the next run with space compiles)."""
    global _NOTICE_GIVEN
    if _NOTICE_GIVEN:
        return
    _NOTICE_GIVEN = True
    import multiprocessing

    if os.environ.get(NOTICE_GIVEN_VARIABLE) and multiprocessing.parent_process() is not None:
        return  # a worker: the process that started it has said so
    why = (f"no space left on the device of {full} to compile a simulation loop ({reason})"
           if full is not None else f"no working C compiler ({reason})")
    warnings.warn(f"ins-errors: {why}; compiled loops run in the CasADi virtual machine "
                  "instead (slower, same results)", InsErrorsNotice, stacklevel=3)


def _out_of_space(error: Exception) -> bool:
    """Whether a failed compile ran out of disk space (``ENOSPC``, raised here or said
    by the compiler or the assembler on its standard error)."""
    if isinstance(error, OSError) and error.errno == errno.ENOSPC:
        return True
    return os.strerror(errno.ENOSPC) in _compiler_said(error)


def _compiler_said(error: Exception) -> str:
    """What a failed compile's process wrote on its standard error (``""``: nothing, or
    no process ran)."""
    stderr = getattr(error, "stderr", None)
    if isinstance(stderr, bytes):
        stderr = stderr.decode(errors="replace")
    return stderr or ""


@contextmanager
def compiler_checked() -> Iterator[None]:
    """Around starting worker processes: learn here whether loops compile, so that a
    missing compiler is said once, by this process, not once by every worker.

    A tiny probe is compiled (once, then found in the cache); when it fails, this
    process gives the notice and the workers started inside the block are told so
    through :data:`NOTICE_GIVEN_VARIABLE`. Nothing is probed when compiling is switched
    off (``$INS_ERRORS_NO_JIT``).
    """
    if not os.environ.get("INS_ERRORS_NO_JIT"):
        compile_source(PROBE_SOURCE, IEEE_FLAGS)
    if not _NOTICE_GIVEN:
        yield
        return
    previous = os.environ.get(NOTICE_GIVEN_VARIABLE)
    os.environ[NOTICE_GIVEN_VARIABLE] = "1"
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop(NOTICE_GIVEN_VARIABLE, None)
        else:
            os.environ[NOTICE_GIVEN_VARIABLE] = previous


def _failure(compiler: str, error: Exception) -> str:
    """Why a compile failed, in a few words: the compiler's first message line."""
    lines = [line.strip() for line in _compiler_said(error).splitlines() if line.strip()]
    if lines:
        return f"{compiler} failed: {lines[0][:120]}"
    if isinstance(error, subprocess.CalledProcessError):
        return f"{compiler} failed with exit status {error.returncode}"
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    return f"{compiler} failed: {text[:120]}"


def compile_library(functions: list[ca.Function], jit: bool = True) -> Path | None:
    """Compile CasADi functions to one shared library in the cache and return its path.

    Parameters
    ----------
    functions : list of casadi.Function
        Functions with distinct names.
    jit : bool
        False: compile nothing.

    Returns
    -------
    pathlib.Path or None
        The library, or None when compiling is off or fails (then a one-time
        :class:`RuntimeWarning` says so, except when switched off on purpose).
    """
    if not jit or os.environ.get("INS_ERRORS_NO_JIT"):
        return None
    return compile_source(lambda: generated_source(functions),
                          key=_functions_key("library", functions))


def generated_source(functions: list[ca.Function]) -> str:
    """C source of CasADi functions (``double``, no header), one translation unit."""
    generator = ca.CodeGenerator("loop.c", {"with_header": False, "casadi_real": "double"})
    for function in functions:
        generator.add(function)
    return generator.dump()


DEFAULT_FLAGS: tuple[str, ...] = ("-O3", "-march=native", "-shared", "-fPIC",
                                  "-ffp-contract=off")
"""C compiler flags of :func:`compile_source` and of the functions
:func:`compile_library` compiles (the true motion's inputs and interpolation, ...):
without fused multiply-add contraction, which C compilers apply by default (GCC across
statements: CasADi's ``a=x*y; a=a+z;`` became one ``fma``, rounded once instead of
twice) wherever the processor has it, so these functions give the bits of the CasADi
virtual machine too (no other flag here changes a result: no fast-math)."""

IEEE_FLAGS: tuple[str, ...] = ("-O1", "-march=native", "-shared", "-fPIC",
                               "-ffp-contract=off", "-fno-math-errno",
                               "-fno-semantic-interposition", "-fno-tree-vectorize")
"""Flags of the simulation loops: every operation rounded on its own as IEEE 754 says
(no fused multiply-add contraction), so a compiled loop gives the bits of the CasADi
virtual machine whatever the compiler inlines; ``errno`` is not set by ``sqrt`` (no
branch around it) and the functions of one library call each other directly. No
vectorisation (it changes no result, only speed): a step's state is read back by the
next step right after it was written, and the vectoriser's pairs of state components
read as one 16-byte load what were two 8-byte stores, which stalls the store-to-load
forwarding on the loop's critical path (a static exact-platform step: ~39 -> ~33 ns).

``-O1``, not ``-O3``: a step is one long block of arithmetic without branches, which the
processor schedules itself, so the higher levels' extra passes gain little at run time
(measured, interleaved in one process: strapdown and platform runs within 5 % of
``-O3``, most a little slower) but take much longer to compile (46 loops of the test suite:
44.7 -> 27.3 s CPU; the whole suite from an empty cache: 310 -> 251 s). The level
changes no result: with these flags every level rounds every operation the same way."""


COMPILE_ATTEMPTS = 3
"""Compiles tried when the scratch folder is deleted under one (``cache clear`` by
another process); a compiler that fails otherwise is not tried again."""


def _compile_step(step: str, scratch: Path) -> None:
    """Called between the steps of a compile (``step`` names the next one): nothing.
    A seam where the tests run another process's work at an exact point."""


def compile_source(source: str | Callable[[], str], flags: Sequence[str] = DEFAULT_FLAGS,
                   key: str | None = None) -> Path | None:
    """Compile C source to a shared library in the cache (once) and return its path.

    Parameters
    ----------
    source : str or callable
        The C source, or a function writing it (called only when the library is not in
        the cache yet and ``key`` is given).
    flags : sequence of str
        Compiler flags.
    key : str, optional
        What the library is cached under instead of the source: a complete description
        of everything the source is written from (:func:`_functions_key`), so that a
        cached library is found without writing its source again. Without it the
        source itself is the key.

    Returns
    -------
    pathlib.Path or None
        None when no compiler works (then a one-time :class:`RuntimeWarning` says so).

    Notes
    -----
    A library is stored sealed (its hash and length appended after its contents,
    :func:`ins_errors.numeric.cache.seal_file`) and renamed into the cache whole; a
    stored one is checked against its seal before it is returned (~1 ms per MB), and one
    that fails (cut short, emptied, altered) is said in one line and compiled again over
    it, never loaded.
    """
    compiler = _compiler()
    if compiler is None:
        _vm_notice("none of $CC, cc, gcc, clang found")
        return None
    flags = list(flags)
    if key is None:
        key = source if isinstance(source, str) else source()
    else:
        key = "described by: " + key   # never the text of a C source
    # -march=native code runs only on this kind of CPU: the CPU is part of the cache key
    digest = hashlib.sha256((key + compiler + " ".join(flags) + ca.__version__
                             + _cpu_identity() + cache.ENTRY_FORMAT).encode())
    name = f"loop_{digest.hexdigest()[:24]}.so"
    directory = _writable(cache_directory())
    library = directory / name
    if library.exists() or library.is_symlink():
        # a library is sealed when stored: one cut short, emptied or altered is never
        # loaded (the loader may kill the process on a short file) but compiled again
        # and renamed over it
        if cache.intact(library):
            cache.touch(library)
            return library
        cache.report_damaged(library, "compiling it again")
    from ins_errors.progress import stage

    for attempt in range(COMPILE_ATTEMPTS):
        vanished = False  # the scratch folder was deleted under the compile
        try:
            with stage("compiling a simulation loop (each kind once: later runs load "
                       "it from the cache)"), \
                    cache.scratch_folder(directory) as scratch:
                try:
                    c_file = scratch / "loop.c"
                    c_file.write_text(source if isinstance(source, str) else source())
                    target = scratch / "loop.so"
                    _compile_step("compile", scratch)
                    # the compiler's own temporary files (assembly, objects) go into the
                    # scratch folder too: a compile cut short (this process stopped
                    # without its process group, the compiler left running) leaves
                    # nothing in the system's temporary folder, only a scratch folder
                    # that the next `ins-errors cache clear` removes
                    subprocess.run([compiler, *flags, "-o", str(target), str(c_file), "-lm"],
                                   check=True, capture_output=True,
                                   timeout=cache.COMPILE_TIMEOUT,
                                   env={**os.environ, "TMPDIR": str(scratch)})
                    cache.seal_file(target)
                    _compile_step("store", scratch)
                    os.replace(target, library)
                except (OSError, subprocess.SubprocessError):
                    vanished = not scratch.is_dir()
                    raise
        except (OSError, subprocess.SubprocessError) as error:
            if getattr(error, "returncode", 0) == -signal.SIGINT:
                raise KeyboardInterrupt from None  # Ctrl-C stopped it: the compiler works
            if cache.intact(library):  # another process finished the same loop meanwhile
                break
            if vanished and attempt + 1 < COMPILE_ATTEMPTS:
                continue  # its scratch folder was deleted (cache clear): not the compiler
            _vm_notice(_failure(compiler, error),
                       directory if _out_of_space(error) else None)
            return None
        break
    cache.register(library)
    return library


@cache_function
def _writer_version() -> str | None:
    """Fingerprint of the code that writes a loop's C source and builds it (the syntax
    trees of this module's writing functions, C templates and flags, and of what they
    use in :mod:`ins_errors.numeric.carried_trig`: see
    :mod:`ins_errors.numeric.writer_key`), so that editing a comment, a docstring or
    code that writes no C keeps every cached library; None when the source files cannot
    be read or parsed. Made once per process: the code that runs is the code imported
    at its start."""
    from ins_errors.numeric.writer_key import installed_fingerprint

    try:
        return installed_fingerprint()
    except (OSError, SyntaxError, ValueError):
        return None


def _functions_key(kind: str, functions: Sequence[ca.Function | None],
                   *settings: object) -> str | None:
    """A complete description of the C source written from ``functions`` and
    ``settings``: the version of the writing code, CasADi's serialisation of each
    function (its whole algorithm, constants to the bit) and the settings' ``repr``
    (arrays by their bytes). None when it cannot be made (a function CasADi cannot
    serialise, unreadable source files): the source itself is then the key."""
    version = _writer_version()
    if version is None:
        return None
    parts = [kind, version]
    try:
        parts += [f.serialize() if f is not None else "-" for f in functions]
    except RuntimeError:
        return None
    for value in settings:
        if isinstance(value, np.ndarray):
            value = (value.dtype.str, value.shape, value.tobytes().hex())
        parts.append(repr(value))
    return hashlib.sha256("\x00".join(parts).encode()).hexdigest()


def compile_functions(functions: list[ca.Function], jit: bool = True) -> list[ca.Function]:
    """Compile CasADi functions to one shared library (cached) and load them.

    Parameters
    ----------
    functions : list of casadi.Function
        Functions with distinct names.
    jit : bool
        False keeps them in the CasADi virtual machine.

    Returns
    -------
    list of casadi.Function
        Compiled (``casadi.external``) versions, or the inputs when compiling is off or
        fails (then a one-time :class:`RuntimeWarning` says so).
    """
    library = compile_library(functions, jit)
    if library is None:
        return functions
    return [ca.external(f.name(), str(library)) for f in functions]


def native_functions(functions: list[ca.Function], jit: bool = True) -> list[DenseCall]:
    """Compiled functions called without copies (:class:`NativeFunction`), or VM wrappers.

    Parameters
    ----------
    functions : list of casadi.Function
        Functions with distinct names and dense inputs and outputs.
    jit : bool
        False keeps them in the CasADi virtual machine (:class:`VirtualFunction`).
    """
    library = compile_library(functions, jit)
    if library is None:
        return [VirtualFunction(f) for f in functions]
    return [NativeFunction(library, f) for f in functions]


@dataclass(frozen=True)
class Signature:
    """Name and dense argument shapes (rows, columns) of a compiled C entry point written
    by hand in the CasADi calling convention (no casadi.Function behind it)."""

    name: str
    inputs: tuple[tuple[int, int], ...]
    outputs: tuple[tuple[int, int], ...]


class DenseCall:
    """A function with dense inputs and outputs, called on numpy buffers.

    Every argument and result is a float64 array whose memory holds the matrix in
    column-major order (a C-ordered array of shape ``(columns, rows)`` does), so the
    numbers are read and written in place.
    """

    def __init__(self, function: ca.Function | Signature):
        if isinstance(function, Signature):
            self.name = function.name
            self.shapes_in, self.shapes_out = list(function.inputs), list(function.outputs)
            return
        for i in range(function.n_in()):
            if not function.sparsity_in(i).is_dense():
                raise ShapeError(f"{function.name()}: input {i} is not dense")
        for i in range(function.n_out()):
            if not function.sparsity_out(i).is_dense():
                raise ShapeError(f"{function.name()}: output {i} is not dense")
        self.name = function.name()
        self.shapes_in = [function.size_in(i) for i in range(function.n_in())]
        self.shapes_out = [function.size_out(i) for i in range(function.n_out())]

    def _check(self, arrays: Sequence[np.ndarray], shapes: list[tuple[int, int]],
               what: str) -> None:
        if len(arrays) != len(shapes):
            raise ShapeError(f"{self.name}: expected {len(shapes)} {what}, got {len(arrays)}")
        for k, (array, (rows, cols)) in enumerate(zip(arrays, shapes, strict=True)):
            if (array.dtype != np.float64 or array.size != rows * cols
                    or not array.flags.c_contiguous):
                raise ShapeError(f"{self.name}: {what} {k} must be a contiguous float64 "
                                 f"array of {rows}x{cols} numbers, got {array.dtype} "
                                 f"{array.shape}")

    def __call__(self, inputs: Sequence[np.ndarray], outputs: Sequence[np.ndarray]) -> None:
        """Evaluate, reading ``inputs`` and writing ``outputs`` in place."""
        raise NotImplementedError


class NativeFunction(DenseCall):
    """A function of a compiled library called through :mod:`ctypes`.

    The generated C entry point reads and writes the numpy buffers directly (no
    conversion to CasADi matrices) and the interpreter lock is released during the call,
    so several calls can run on several cores at once (each call has its own work
    arrays).

    Parameters
    ----------
    library : pathlib.Path
        Shared library made by :func:`compile_library` from ``function``.
    function : casadi.Function or Signature
        The function (for its name and shapes).
    """

    def __init__(self, library: Path, function: ca.Function | Signature):
        super().__init__(function)
        self._library = ctypes.CDLL(str(library))
        self._entry = getattr(self._library, self.name)
        self._entry.restype = ctypes.c_int
        sizes = [ctypes.c_longlong() for _ in range(4)]
        work = getattr(self._library, f"{self.name}_work")
        work.restype = ctypes.c_int
        if work(*[ctypes.byref(s) for s in sizes]):
            raise InsErrorsError(f"{self.name}: the compiled library reports an error")
        n_arg, n_res, n_iw, n_w = (max(int(s.value), 1) for s in sizes)
        # pointer tables (unused entries NULL) and work arrays, made afresh for each call
        # (several threads may call at once); a buffer's address is read from its array
        # interface, the cheapest way numpy offers
        self._args = ctypes.c_void_p * max(n_arg, len(self.shapes_in))
        self._results = ctypes.c_void_p * max(n_res, len(self.shapes_out))
        self._iw = ctypes.c_longlong * n_iw
        self._w = ctypes.c_double * n_w

    def __call__(self, inputs: Sequence[np.ndarray], outputs: Sequence[np.ndarray]) -> None:
        """Evaluate, reading ``inputs`` and writing ``outputs`` in place."""
        self._check(inputs, self.shapes_in, "input")
        self._check(outputs, self.shapes_out, "output")
        status = self._entry(self._args(*[a.__array_interface__["data"][0] for a in inputs]),
                             self._results(*[a.__array_interface__["data"][0]
                                             for a in outputs]),
                             self._iw(), self._w(), 0)
        if status:
            raise InsErrorsError(f"{self.name}: the compiled function failed (status {status})")


class VirtualFunction(DenseCall):
    """The same calling convention as :class:`NativeFunction` in the CasADi VM."""

    def __init__(self, function: ca.Function):
        super().__init__(function)
        self._function = function

    def __call__(self, inputs: Sequence[np.ndarray], outputs: Sequence[np.ndarray]) -> None:
        """Evaluate, reading ``inputs`` and writing ``outputs`` in place."""
        self._check(inputs, self.shapes_in, "input")
        self._check(outputs, self.shapes_out, "output")
        values = self._function.call([ca.DM(a.reshape(c, r).T) for a, (r, c)
                                      in zip(inputs, self.shapes_in, strict=True)])
        for array, value in zip(outputs, values, strict=True):
            array.reshape(-1)[:] = np.asarray(value).ravel(order="F")


def worker_count() -> int:
    """Cores batched cases may use: ``$INS_ERRORS_THREADS``, else 1 in a worker process of
    a pool (its siblings already share the cores), else the cores this process may run
    on."""
    text = os.environ.get("INS_ERRORS_THREADS")
    if text:
        try:
            count = int(text)
        except ValueError:
            raise InsErrorsError(f"INS_ERRORS_THREADS must be a whole number, got {text!r}") \
                from None
        if count < 1:
            raise InsErrorsError(f"INS_ERRORS_THREADS must be at least 1, got {count}")
        return count
    import multiprocessing

    if multiprocessing.parent_process() is not None:
        return 1
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


# --------------------------------------------------------------------------------------
# Compiled loops
# --------------------------------------------------------------------------------------
@dataclass
class LoopResult:
    """Output of :meth:`CompiledLoop.run`.

    Attributes
    ----------
    states : numpy.ndarray, shape (nz, R + 1, B)
        Recorded states (initial state first) for each of the ``B`` batch members.
    margins : numpy.ndarray, shape (R, B)
        Domain margin at the end of each recording interval (a running minimum within a
        compiled chunk); ``> 0``: inside the domain.
    stopped : bool
        The run's ``check`` stopped it early: ``R`` is then the number of samples
        recorded up to the end of the piece where it stopped, not the run's.
    """

    states: np.ndarray
    margins: np.ndarray
    stopped: bool = False


RUN_PIECES = 100
"""A run without an input stream is cut into about this many pieces of whole chunks
(:meth:`CompiledLoop.run`): the progress bar moves and the run's ``check`` looks at the
records between two pieces, so a run that leaves its domain stops within about
1/RUN_PIECES of its length after it left."""

PieceCheck = Callable[[np.ndarray, np.ndarray], bool]
"""``check(states, margins) -> stop``: the states recorded over one piece of a run, shape
(nz, r + 1, b) (the sample before the piece first), and their margins, shape (r, b), of
the ``b`` batch members just run; True stops the run after that piece."""


class CompiledLoop:
    """A fixed-step integration loop compiled once, run many times.

    The step ``τ``, the fixed constants ``p`` and (for a time-invariant motion) the
    inputs ``u`` are baked into the generated C code as numbers, so the compiler folds
    every subexpression that depends on them only (about a quarter of the work of the
    orthodromic equations on a static base). The per-case constants ``w`` (error
    sources) travel with the state in one carried vector ``[z, m, w]`` (``m``: running
    minimum of the domain margin, checked at the end of every recording interval). A
    compiled library is cached on disk under the hash of a complete description of its
    C source (:func:`_functions_key`: the functions, settings and the writing code), so
    the same loop is compiled once per machine and, once cached, found without writing
    its source again. Without a compiler the same loop runs in the CasADi
    virtual machine as ``fold``/``mapaccum``/``map`` graphs, with the same arithmetic.

    With ``runtime_constants`` the numbers CasADi folded into the step (everything
    computed from ``τ``, ``p`` and ``u`` alone) are not written into the C code but read
    from an array at run time (:func:`lift_constants`): the C then depends on the step's
    structure only, and one library serves every loop of that structure, e.g. every
    latitude, heading and parameter value of a sweep, where a baked loop compiles a
    library of its own for each (a few seconds each). Its arithmetic is the baked loop's,
    operation for operation, so it gives the same bits. It runs as fast: CasADi has
    already folded whatever depends on the numbers alone, and what depends on them and
    on the states held at rest (:meth:`_frozen`) is computed once per call of the driver;
    the compiler only reads the numbers from memory instead of its instructions (per
    step against the baked loop, interleaved: a static 24-h orthodromic direct run at
    100 Hz +3 %, the same with linear and refined runs by RK4 −2 %, a static strapdown
    run −1 %, a great circle +1 %, all within the noise). Values that change the
    structure (an exact 0 or 1 that CasADi simplifies away: a heading of 0, a gain of
    0), and each set of states held at rest, make a library of their own.

    The library is built at the first run. For a time-invariant motion, state components
    that one step returns to the last bit and that depend only on such components (the
    ideal work on a static base) can never move: they are written into the C source as
    exact numbers for that run (:meth:`_frozen`), which removes the ideal work's
    operations from the step (a static 24-h exact-platform run: ~31 -> ~27 ns per step)
    with the same bits.

    The compiled functions are called on numpy buffers in place (:class:`NativeFunction`).
    A batch is split into groups, one per core (:func:`worker_count`), run in threads;
    each case's arithmetic is the same whatever the grouping.

    Parameters
    ----------
    rhs : casadi.Function
        ``rhs(z, u, w, p) -> dz/dt`` (state, inputs, per-case constants, fixed constants).
    margin : casadi.Function or None
        ``margin(z, u, w, p) -> scalar``, positive inside the domain (e.g. ``1 - u31²``).
    method : {"euler", "rk4"}
        Scheme.
    record_every : int
        Steps per recorded sample.
    tau : float
        Step, s.
    p : numpy.ndarray
        Fixed constants (model parameters), baked in.
    constant_inputs : numpy.ndarray or None
        One input vector for the whole run (baked in), or None for a per-step stream.
    chunk : int
        Recorded samples per compiled call (a long run is a Python loop over chunks).
    batch : int
        Number of cases run side by side (same inputs, different ``z0`` and ``w``) with
        ``casadi.Function.map``.
    jit : bool
        Compile to C (default) or stay in the CasADi virtual machine.
    workers : int, optional
        Threads a batch is split over (default :func:`worker_count`, at most ``batch``).
    rotations : sequence of (int, int, int), optional
        ``(angle, sine, cosine)`` indices of state components whose sine and cosine are
        carried with the state and rotated each step (see :func:`casadi_step`).
    runtime_constants : bool
        Read the step's numbers from an array at run time instead of compiling them in
        (one library per structure, not per value); the virtual machine runs as without.
    """

    def __init__(self, rhs: ca.Function, margin: ca.Function | None, method: Method,
                 record_every: int, tau: float, p: np.ndarray,
                 constant_inputs: np.ndarray | None = None, chunk: int = 32, batch: int = 1,
                 jit: bool = True, workers: int | None = None,
                 rotations: Sequence[tuple[int, int, int]] = (),
                 runtime_constants: bool = False):
        check_method(method)
        if record_every < 1 or chunk < 1 or batch < 1:
            raise StepError("record_every, chunk and batch must be positive integers")
        self.method, self.record_every, self.chunk, self.batch = method, record_every, chunk, batch
        workers = min(batch, worker_count() if workers is None else max(1, int(workers)))
        self.group = -(-batch // workers)
        self.workers = -(-batch // self.group)
        self.constant_inputs = constant_inputs is not None
        self.runtime_constants = bool(runtime_constants)
        self.nz, self.nu, self.nw = rhs.size1_in(0), rhs.size1_in(1), rhs.size1_in(2)
        nz, nu, nw = self.nz, self.nu, self.nw
        self.n_stream = nu if method == "euler" else 3 * nu
        self.n_carry = nz + 1 + nw
        p_array = np.asarray(p, dtype=float)
        p_num = ca.DM(p_array)
        tau_num = float(tau)
        u_array = None if constant_inputs is None else np.asarray(constant_inputs, dtype=float)

        def f(z, u, w):
            return rhs(z, u, w, p_num)

        carry = ca.SX.sym("carry", self.n_carry)
        z, w = carry[:nz], carry[nz + 1:]
        if self.constant_inputs:
            u_num = ca.DM(u_array)
            stream = u_num if method == "euler" else ca.vertcat(u_num, u_num, u_num)
            extra_in: list[ca.SX] = []
        else:
            stream = ca.SX.sym("u", self.n_stream)
            extra_in = [stream]
        rotations = tuple(rotations)
        # Euler with carried sines and cosines: the compiled step returns the plain
        # update and the angle increments, and the C driver rotates (ins_rotate)
        c_rotations = method == "euler" and bool(rotations)
        graphs: list[tuple[ca.SX | None, ca.SX]] = []

        def graph() -> tuple[ca.SX | None, ca.SX]:
            """``(plain, z_next)``: the step's graphs, built (and CSE'd) when first
            needed, which a loop whose library is in the cache may never be."""
            if not graphs:
                if c_rotations:
                    increment = tau_num * f(z, stream, w)
                    plain = ca.cse(ca.vertcat(z + increment,
                                              *[increment[angle] for angle, _, _ in rotations]))
                    # the same, rotated in the graph
                    graphs.append((plain, ca.cse(_moved(z, increment, rotations))))
                else:
                    graphs.append((None, ca.cse(casadi_step(f, method, z, stream, w, tau_num,
                                                            rotations))))
            return graphs[0]

        u_end = None
        if margin is not None:
            u_end = (ca.DM(u_array) if self.constant_inputs
                     else stream[-nu:])   # the last step's u[k+1] (RK4) or u[k] (Euler)
        self._jit = jit and not os.environ.get("INS_ERRORS_NO_JIT")
        self._graph = graph
        self._carry_sym = carry
        self._virtual_args = (carry, extra_in, margin, constant_inputs, p_num, chunk)
        written: list[tuple[str, str]] = []

        def source() -> tuple[str, str]:
            """The C of the step (and margin) and of the driver, written once."""
            if not written:
                plain, z_next = graph()
                step_c = ca.Function("ins_step_c", [carry, *extra_in],
                                     [plain[:nz], plain[nz:]] if c_rotations else [z_next])
                functions = [step_c]
                if margin is not None:
                    functions.append(ca.Function("ins_margin_c", [carry, *extra_in], [
                        margin(z, u_end, w, p_num)]))
                written.append((_assume_arguments(generated_source(functions)),
                                _driver_source(self, chunk, margin is not None, functions,
                                               rotations if c_rotations else ())))
            return written[0]

        def lifted(held: tuple[int, ...]) -> tuple[str, np.ndarray]:
            """The C of the step, margin and driver with the step's numbers read from an
            array (returned, :func:`lift_constants`), and what depends on them and on the
            ``held`` state components (:meth:`_frozen`) alone computed once per call of
            the driver (``ins_constants_c``), as a baked loop's compiler folds them."""
            plain, z_next = graph()
            outputs = [plain[:nz], plain[nz:]] if c_rotations else [z_next]
            rest = [] if margin is None else [margin(z, u_end, w, p_num)]
            baked = ca.Function("ins_baked", [carry, *extra_in], outputs + rest)
            with _no_simplification():
                exprs, numbers, values = lift_constants(baked, [carry, *extra_in])
                fixed = ca.vertcat(numbers, *[carry[i] for i in held])
                exprs, symbols, parts = ca.extract_parametric(exprs, fixed,
                                                              {"extract_trivial": True})
                hoisted = ca.vertcat(*symbols) if symbols else ca.SX.sym("e", 0)
                functions = [ca.Function("ins_step_c", [carry, *extra_in, hoisted],
                                         exprs[:len(outputs)])]
                if rest:
                    functions.append(ca.Function("ins_margin_c", [carry, *extra_in, hoisted],
                                                 exprs[len(outputs):]))
                functions.append(ca.Function("ins_constants_c", [carry, numbers], [
                    ca.vertcat(*parts) if parts else ca.SX(0, 1)]))
            return (_assume_arguments(generated_source(functions))
                    + _driver_source(self, chunk, margin is not None, functions,
                                     rotations if c_rotations else (), len(values)),
                    values)

        self._source = source if self._jit else None
        self._lifted = lifted if self._jit and self.runtime_constants else None
        self._key = _functions_key("loop", [rhs, margin], method, record_every, tau_num,
                                   p_array, u_array, chunk, self.group,
                                   rotations) if self._jit else None
        self._built: dict[tuple[tuple[int, str], ...], _LoopCalls] = {}
        self._build_lock = threading.Lock()
        # a time-invariant loop may start where part of the state does not move (the
        # ideal work on a static base): which state each next state depends on (made at
        # the first run, :meth:`_frozen`)
        self._probe = self._depends = None

    def _functions(self, frozen: tuple[tuple[int, float], ...] = ()) -> _LoopCalls:
        """The chunk and single-record functions, compiled once per ``frozen`` set.

        ``frozen`` lists ``(index, value)`` of state components the step leaves unchanged
        from the start (:meth:`_frozen`): their values are written into the C source as
        exact (hexadecimal) numbers, so the compiler folds every operation on them alone.
        The compiler folds with IEEE rounding (no fast-math flags), so every remaining
        number is the one the general loop computes.
        """
        key = tuple((i, value.hex()) for i, value in frozen)   # -0.0 is not 0.0 here
        with self._build_lock:
            built = self._built.get(key)
            if built is None:
                built = self._built[key] = self._build(dict(frozen))
            return built

    def _build(self, frozen: dict[int, float]) -> _LoopCalls:
        lifted = self._lifted is not None
        if lifted:
            try:
                built = self._build_lifted(tuple(sorted(frozen)))
            except LiftError:
                lifted = False   # compiled with its numbers written in, as it always was
            else:
                if built is not None:
                    return built
        if self._source is not None and not lifted:
            def source() -> str:
                generated, driver = self._source()
                if frozen:
                    def number(match: re.Match) -> str:
                        value = frozen.get(int(match.group(1)))
                        return match.group(0) if value is None else f"({value.hex()})"

                    generated = re.sub(r"arg\[0\]\[(\d+)\]", number, generated)
                return generated + driver

            key = None if self._key is None else self._key + "".join(
                f" {i}={value.hex()}" for i, value in sorted(frozen.items()))
            library = compile_source(source, IEEE_FLAGS + (NO_FOLDING_FLAGS if frozen else ()),
                                     key=key)
            if library is not None:
                n_in = [(self.n_carry, self.group)]
                chunk_fn, single_fn = (NativeFunction(library, Signature(
                    name, (*n_in, *([(self.n_stream, self.record_every * size)]
                                    if not self.constant_inputs else [])),
                    ((self.n_carry, size * self.group),))) for name, size in
                    (("ins_chunk_f", self.chunk), ("ins_single_f", 1)))
                return chunk_fn, single_fn, _SizedRun(library)
        # the CasADi virtual machine runs the same arithmetic
        carry, extra_in, *rest = self._virtual_args
        chunk_fn, single_fn = self._virtual(carry, extra_in, self._graph()[1], *rest)
        return chunk_fn, single_fn, None

    def _build_lifted(self, held: tuple[int, ...]) -> _LoopCalls | None:
        """The compiled loop with its numbers read at run time (``runtime_constants``).

        The library is cached under its C source (the step's structure: the numbers are
        not in it); which library and numbers this loop takes is kept as a note of the
        cache folder named by the loop's key (its functions, settings and numbers) and
        ``held``, so a loop seen before finds them without building its graph. None when
        no compiler works.

        Raises
        ------
        LiftError
            The step cannot be copied with its numbers as symbols (:func:`lift_constants`).
        """
        name = None if self._key is None else "lifted_" + hashlib.sha256(
            f"{self._key} {held}".encode()).hexdigest()[:32]
        written: list[str] = []

        def source() -> str:
            if not written:
                written.append(self._lifted(held)[0])
            return written[0]

        note = None if name is None else cache.read_note(name)
        key, values = None, None
        if note is not None and note.startswith("lifted\n"):
            key, *lines = note.split("\n")[1:]
            try:
                values = np.array([float.fromhex(v) for v in lines if v])
            except ValueError:
                key = None
        if key is None or values is None:
            text, values = self._lifted(held)
            written.append(text)
            key = "lifted C " + hashlib.sha256(text.encode()).hexdigest()
            if name is not None:
                cache.write_note(name, "lifted\n" + key + "\n"
                                 + "".join(f"{float(v).hex()}\n" for v in values))
        library = compile_source(source, IEEE_FLAGS, key=key)
        if library is None:
            return None
        # the run calls ins_run_n and ins_run_rows, which are given the numbers here (the
        # chunk and single-record entry points would need them as an argument)
        return None, None, _SizedRun(library, np.ascontiguousarray(values, dtype=float))

    def _frozen(self, carry: np.ndarray) -> tuple[tuple[int, float], ...]:
        """State components that stay exactly at their start in every case of a run
        (:meth:`_frozen_probed`), as ``(index, value)``.

        Finding them needs the step's graph, which a loop whose library is cached is
        otherwise never built for (~20 ms for a strapdown step, the most a warm run
        spends outside the loop), so the answer is kept as a note of the cache folder
        (:func:`ins_errors.numeric.cache.write_note`) named by the hash of the loop's
        key (everything its C is written from, :func:`_functions_key`) and the start
        states (it depends on nothing else: never on the per-case constants). The note
        is sealed (:func:`ins_errors.numeric.cache.sealed`): one cut short or altered is
        never read (its numbers would be compiled into the loop), but worked out again
        and written over, said in one line.
        """
        if not (self.constant_inputs and self._jit):
            return ()
        name = None
        if self._key is not None:
            start = np.ascontiguousarray(carry[:, :self.nz])
            name = "frozen_" + hashlib.sha256(
                f"{self._key} {start.shape}".encode() + start.tobytes()).hexdigest()[:32]
            note = cache.read_note(name)
            if note is not None and note.startswith("frozen\n"):
                try:
                    found = tuple((int(i), float.fromhex(v)) for i, v in
                                  (line.split(" ") for line in note.split("\n")[1:] if line))
                except ValueError:
                    found = None
                if found is not None and all(0 <= i < self.nz for i, _ in found):
                    return found
        frozen = self._frozen_probed(carry)
        if name is not None:
            cache.write_note(name, "frozen\n" + "".join(f"{i} {v.hex()}\n"
                                                         for i, v in frozen))
        return frozen

    def _frozen_probed(self, carry: np.ndarray) -> tuple[tuple[int, float], ...]:
        """State components that stay exactly at their start in every case of a run.

        A component is frozen when every case starts it at the same finite value, one step
        returns that value to the last bit, and its next value depends on frozen
        components only (and on the baked-in inputs and constants, never on the error
        sources): then every later step computes it from the same numbers by the same
        operations, so it never moves. Typically the ideal work on a static base.
        """
        if self._probe is None:
            z_next = self._graph()[1]
            self._probe = ca.Function("ins_probe", [self._carry_sym], [z_next])
            rows, cols = ca.jacobian_sparsity(z_next, self._carry_sym).get_triplet()
            self._depends = np.zeros((self.nz, self.n_carry), dtype=bool)
            self._depends[rows, cols] = True
        nz, start = self.nz, carry[:, :self.nz]
        bits = start.view(np.int64)
        candidate = np.all(bits == bits[0], axis=0) & np.isfinite(start[0])
        moved = np.asarray(self._probe(carry[0])).ravel()
        candidate &= moved.view(np.int64) == bits[0]
        frozen = np.concatenate([candidate, np.zeros(self.n_carry - nz, dtype=bool)])
        while True:
            leaves = frozen[:nz] & np.any(self._depends & ~frozen, axis=1)
            if not leaves.any():
                break
            frozen[:nz] &= ~leaves
        return tuple((int(i), float(start[0, i])) for i in np.flatnonzero(frozen))

    def _virtual(self, carry: ca.SX, extra_in: list[ca.SX], z_next: ca.SX,
                 margin: ca.Function | None, constant_inputs: np.ndarray | None,
                 p_num: ca.DM, chunk: int) -> list[DenseCall]:
        """The chunk functions as CasADi fold/mapaccum/map graphs in the virtual machine."""
        nz = self.nz
        step = ca.Function("ins_step", [carry, *extra_in], [ca.vertcat(z_next, carry[nz:])])
        record_every = self.record_every
        block = step.fold(record_every) if record_every > 1 else step
        # domain check once per recording interval, on the last state of the block
        carry_mx = ca.MX.sym("carry", self.n_carry)
        block_in = [carry_mx] + ([ca.MX.sym("u", self.n_stream, record_every)]
                                 if not self.constant_inputs else [])
        out = block(*block_in)
        if margin is not None:
            u_end = (ca.DM(np.asarray(constant_inputs, dtype=float)) if self.constant_inputs
                     else block_in[1][-self.nu:, -1])
            m = ca.fmin(out[nz], margin(out[:nz], u_end, out[nz + 1:], p_num))
            out = ca.vertcat(out[:nz], m, out[nz + 1:])
        block = ca.Function("ins_block", block_in, [out])
        chunked = block.mapaccum("ins_chunk", chunk)
        single = block
        if self.group > 1:
            reduce = [] if self.constant_inputs else [1]
            chunked = chunked.map("ins_chunk_b", "serial", self.group, reduce, [])
            single = block.map("ins_single_b", "serial", self.group, reduce, [])
        return [VirtualFunction(_rename(chunked, "ins_chunk_f")),
                VirtualFunction(_rename(single, "ins_single_f"))]

    # -- running -----------------------------------------------------------------------
    def start(self, z0: np.ndarray, w: np.ndarray) -> np.ndarray:
        """The carried vectors ``[z, m, w]`` of every batch member at the start.

        Parameters
        ----------
        z0 : numpy.ndarray, shape (nz,) or (nz, B)
            Initial state(s).
        w : numpy.ndarray, shape (nw,) or (nw, B)
            Per-case constants (error sources).

        Returns
        -------
        numpy.ndarray, shape (G × group, nz + 1 + nw)
            One row per batch member (padded to whole groups by repeating the last
            member); pass it to :meth:`advance`.
        """
        B = self.batch
        z0 = np.asarray(z0, dtype=float).reshape(self.nz, -1)
        w = np.asarray(w, dtype=float)
        w = w.reshape(self.nw, -1) if w.size else np.zeros((self.nw, 1))
        if z0.shape[1] not in (1, B) or w.shape[1] not in (1, B):
            raise StepError(f"expected {B} batch members, got states {z0.shape[1]}, "
                            f"constants {w.shape[1]}")
        rows = np.vstack([np.broadcast_to(z0, (self.nz, B)), np.full((1, B), np.inf),
                          np.broadcast_to(w, (self.nw, B))]).T
        padded = self.workers * self.group
        if padded > B:
            rows = np.vstack([rows, np.repeat(rows[-1:], padded - B, axis=0)])
        return np.ascontiguousarray(rows)

    def advance(self, carry: np.ndarray, n_steps: int, stream: np.ndarray | InputRows | None,
                states: np.ndarray, margins: np.ndarray) -> None:
        """Integrate ``n_steps`` from ``carry`` (updated in place), recording as it goes.

        Parameters
        ----------
        carry : numpy.ndarray
            From :meth:`start` or a previous :meth:`advance`.
        n_steps : int
            A multiple of ``record_every``.
        stream : numpy.ndarray, shape (n_steps, n_stream), C order, or InputRows or None
            The per-step inputs, one row per step (:func:`stream_rows`), or the inputs
            as rows at the step times and midpoints (:class:`InputRows`: the compiled
            driver reads them as they are, the virtual machine gets them as a stream),
            None for constant inputs.
        states : numpy.ndarray, shape (nz, n_steps // record_every, B)
            Filled with the states at the end of every recording interval.
        margins : numpy.ndarray, shape (n_steps // record_every, B)
            Filled with the domain margins.
        """
        k = self.record_every
        if n_steps % k:
            raise StepError(f"{n_steps} steps are not a whole number of recording "
                            f"intervals of {k} steps")
        functions = self._functions()
        if isinstance(stream, InputRows) and not self.constant_inputs:
            stream.check(n_steps, self.nu, self.method)
            if functions[2] is None:   # the virtual machine reads one stream
                stream = stream_rows(stream.steps.T, None if stream.midpoints is None
                                     else stream.midpoints.T, self.method)
        elif not self.constant_inputs and (
                stream is None or stream.shape != (n_steps, self.n_stream)
                or stream.dtype != np.float64 or not stream.flags.c_contiguous):
            raise StepError(f"input stream must be a contiguous array of shape "
                            f"({n_steps}, {self.n_stream}), got "
                            f"{None if stream is None else stream.shape}")
        self._advance(functions, carry, n_steps // k, stream, states, margins)

    def _advance(self, functions: _LoopCalls, carry: np.ndarray, n_rec: int,
                 stream: np.ndarray | None, states: np.ndarray, margins: np.ndarray) -> None:
        if self.workers == 1:
            self._advance_group(functions, carry, n_rec, stream, states, margins, 0)
            return
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(self.workers) as pool:
            jobs = [pool.submit(self._advance_group, functions, carry, n_rec, stream, states,
                                margins, g) for g in range(self.workers)]
            for job in jobs:
                job.result()

    def _advance_group(self, functions: _LoopCalls, carry: np.ndarray,
                       n_rec: int, stream: np.ndarray | None, states: np.ndarray,
                       margins: np.ndarray, g: int) -> None:
        k, size_g, nz = self.record_every, self.group, self.nz
        chunk_fn, single_fn, sized = functions
        first = g * size_g
        members = slice(first, min(first + size_g, self.batch))
        count = members.stop - members.start
        own = np.ascontiguousarray(carry[first:first + size_g])
        buffers = {}
        done = 0
        while done < n_rec:
            if sized is not None:   # the compiled driver runs any number of records
                size = n_rec - done
            else:
                size = self.chunk if n_rec - done >= self.chunk else 1
            out = buffers.get(size)
            if out is None:
                out = buffers[size] = np.empty((size_g, size, self.n_carry))
            args = [own]
            if isinstance(stream, InputRows):
                args += [stream.steps[done * k:(done + size) * k + 1],
                         None if stream.midpoints is None
                         else stream.midpoints[done * k:(done + size) * k]]
            elif not self.constant_inputs:
                args.append(stream[done * k:(done + size) * k])
            if sized is not None:
                sized(args, out)
            else:
                (chunk_fn if size == self.chunk else single_fn)(args, [out])
            states[:, done:done + size, members] = out[:count, :, :nz].transpose(2, 1, 0)
            margins[done:done + size, members] = out[:count, :, nz].T
            own[:] = out[:, -1]
            own[:, nz] = np.inf
            done += size
        carry[first:first + size_g] = own

    def run(self, z0: np.ndarray, w: np.ndarray, n_steps: int,
            inputs: np.ndarray | None = None, progress: bool | str = False,
            check: PieceCheck | None = None) -> LoopResult:
        """Run the loop, in pieces of whole chunks (about :data:`RUN_PIECES` of them).

        Parameters
        ----------
        z0 : numpy.ndarray, shape (nz,) or (nz, B)
            Initial state(s).
        w : numpy.ndarray, shape (nw,) or (nw, B)
            Per-case constants (error sources).
        n_steps : int
            Number of steps, a multiple of ``record_every``.
        inputs : numpy.ndarray, optional
            The per-step stream ``(n_stream, n_steps)`` from :func:`input_stream`
            (omit for constant inputs).
        progress : bool or str
            Show a tqdm progress bar (a string is used as its label).
        check : callable, optional
            Called after every piece with what it recorded (:data:`PieceCheck`): once it
            returns True, every group of the batch runs to the end of that piece (no
            further) and the result holds the samples up to there (``stopped``). Each
            group's numbers are the same whatever the pieces: only where the run ends
            changes.
        """
        k, B = self.record_every, self.batch
        if n_steps % k:
            raise StepError(f"{n_steps} steps are not a whole number of recording "
                            f"intervals of {k} steps")
        n_rec = n_steps // k
        carry = self.start(z0, w)
        functions = self._functions(self._frozen(carry))
        stream = None
        if not self.constant_inputs:
            inputs = np.asarray(inputs, dtype=float)
            if inputs.shape != (self.n_stream, n_steps):
                raise StepError(f"input stream must have shape ({self.n_stream}, {n_steps}), "
                                f"got {inputs.shape}")
            stream = np.ascontiguousarray(inputs.T)
        states = np.empty((self.nz, n_rec + 1, B))
        margins = np.empty((n_rec, B))
        states[:, 0] = carry[:B, :self.nz].T
        bar = progress_bar(n_steps, progress)
        # progress is shown, and the check made, between pieces of about 1/RUN_PIECES of
        # the run (whole chunks)
        piece = max(self.chunk, -(-n_rec // RUN_PIECES // self.chunk) * self.chunk)

        stop = threading.Event()
        end = [n_rec]   # where every group stops: lowered to a piece's end by the check
        stopped = threading.Event()
        lock = threading.Lock()

        def pieces(g: int | None) -> None:
            """Run the recording in pieces: every group (g None) or group g."""
            members = slice(None) if g is None else slice(
                g * self.group, min((g + 1) * self.group, B))
            done = 0
            while not stop.is_set():
                limit = end[0]
                if done >= limit:
                    break
                size = min(piece, limit - done)
                recorded = states[:, done + 1:done + 1 + size], margins[done:done + size]
                if g is None:
                    self._advance(functions, carry, size,
                                  None if stream is None else stream[done * k:(done + size) * k],
                                  *recorded)
                else:
                    self._advance_group(functions, carry, size, None, *recorded, g)
                if check is not None and check(states[:, done:done + 1 + size, members],
                                               margins[done:done + size, members]):
                    with lock:   # the other groups run up to here, not beyond
                        end[0] = min(end[0], done + size)
                        stopped.set()
                done += size
                if bar is not None and not g:
                    bar.update(size * k)

        try:
            if self.constant_inputs and self.workers > 1:
                # no input stream to share: each thread runs its group from start to end,
                # never waiting for the other groups (the first group shows the progress)
                from concurrent.futures import ThreadPoolExecutor, as_completed

                with ThreadPoolExecutor(self.workers) as pool:
                    jobs = [pool.submit(pieces, g) for g in range(self.workers)]
                    try:
                        for job in as_completed(jobs):
                            job.result()
                    except BaseException:  # an error or Ctrl-C: the others stop too
                        stop.set()
                        raise
            else:
                pieces(None)
        finally:
            if bar is not None:
                bar.close()
        if stopped.is_set():
            return LoopResult(states[:, :end[0] + 1], margins[:end[0]], stopped=True)
        return LoopResult(states, margins)


class _SizedRun:
    """``ins_run_n`` of a compiled loop library: any number of records in one call (the
    chunk functions have a fixed number, so a run's tail took one call per record)."""

    def __init__(self, library: Path, constants: np.ndarray | None = None):
        handle = ctypes.CDLL(str(library))
        self._entry, self._rows = handle.ins_run_n, handle.ins_run_rows
        self._entry.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p,
                                ctypes.c_longlong, ctypes.c_void_p]
        self._rows.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p,
                               ctypes.c_void_p, ctypes.c_longlong, ctypes.c_void_p]
        self._entry.restype = self._rows.restype = ctypes.c_int
        # the numbers of a loop with run-time constants (kept alive with the calls)
        self._constants = constants
        self._numbers = None if constants is None or not constants.size else constants.ctypes.data

    def __call__(self, args: list[np.ndarray | None], out: np.ndarray) -> None:
        """Run ``out.shape[1]`` records from the carried rows ``args[0]`` (and the input
        stream ``args[1]``, or the input rows at the step times ``args[1]`` and at the
        midpoints ``args[2]``, None for Euler: :class:`InputRows`), writing them into
        ``out`` (groups, records, carried vector); the buffers are the loop's own,
        contiguous and of the right shapes."""
        if len(args) > 2:
            mids = None if args[2] is None else args[2].ctypes.data
            status = self._rows(args[0].ctypes.data, args[1].ctypes.data, mids,
                                out.ctypes.data, out.shape[1], self._numbers)
        else:
            stream = args[1].ctypes.data if len(args) > 1 else None
            status = self._entry(args[0].ctypes.data, stream, out.ctypes.data, out.shape[1],
                                 self._numbers)
        if status:
            raise InsErrorsError("ins_run_n: the compiled loop failed")


_LoopCalls = tuple["DenseCall | None", "DenseCall | None", "_SizedRun | None"]
"""The chunk function, the single-record function and, when compiled, ``ins_run_n``
(which a compiled run always uses: a loop with run-time constants has no others)."""

_DRIVER = """
/* The recording loop around ins_step_c, written for this loop (not by CasADi): for
   each of GROUP cases, SIZE recorded samples of K steps each, the state ping-ponging
   between two buffers; after every K steps the domain margin's running minimum and
   the carried vector [z, m, w] are written out. Same arithmetic as CasADi's
   fold/mapaccum/map of ins_step (the virtual-machine path), without their copies.
   With INS_NROT carried angles (Euler), ins_step_c also returns the angle increments and
   ins_rotations moves the sines and cosines on (carried_trig.ROTATE_C).
   Inputs (SPLIT): arg[1] the stream, one row of INS_NS per step; or (split) arg[1] the
   inputs at the step times and arg[2] at the midpoints, rows of INS_NU, whose step row
   [u(k), u(k+1/2), u(k+1)] is copied into u (the same numbers, no stream built).
   With run-time constants (INS_LIFTED: INS_NK numbers in the array constants),
   ins_constants_c computes once per case and call what depends on them (and on the
   states that stay at their start) alone, and the step and the margin read it as their
   last argument. */
#define INS_NZ {nz}
#define INS_NU {nu}
#define INS_NC {nc}
#define INS_NS {ns}
#define INS_K {k}
#define INS_GROUP {group}
#define INS_MARGIN {margin}
#define INS_NROT {nrot}
#define INS_LIFTED {lifted}
#define INS_NK {nk}
#define INS_NE {ne}
{rotate}
#if {inline} && defined(__GNUC__)   /* a small step inlined: increments in registers */
#define INS_FLATTEN __attribute__((flatten))
#else
#define INS_FLATTEN
#endif
INS_FLATTEN static int ins_drive(const casadi_real** arg, casadi_real** res, casadi_int size,
                                 casadi_int chunk, int split,
                                 const casadi_real* constants) {{
  const casadi_real* carry = arg[0];
  const casadi_real* stream = arg[1];
  const casadi_real* mids = split ? arg[2] : 0;
  const casadi_real *a, *h;
  casadi_real* out = res[0];
  casadi_real buf[2][INS_NC], m, value, *o, d[INS_NROT + 1], u[INS_NS + 1];
  casadi_real hoisted[INS_NE + 1];
  const casadi_real* sarg[{sz_arg}];
  casadi_real* sres[{sz_res}];
  casadi_int iw[{sz_iw}];
  casadi_real wk[{sz_w}];
  casadi_int g, r, s, i, whole = size / chunk * chunk;
  int cur;
  (void)stream; (void)value; (void)d; (void)mids; (void)a; (void)h; (void)u;
  (void)hoisted; (void)constants;
  for (g = 0; g < INS_GROUP; ++g) {{
    for (i = 0; i < INS_NC; ++i) buf[0][i] = buf[1][i] = carry[g * INS_NC + i];
    m = buf[0][INS_NZ];
#if INS_LIFTED
    sarg[0] = buf[0];
    sarg[1] = constants;
    sres[0] = hoisted;
    if (ins_constants_c(sarg, sres, iw, wk, 0)) return 1;
    sarg[INS_NS ? 2 : 1] = hoisted;   /* the last argument of the step and the margin */
#endif
    cur = 0;
    for (r = 0; r < size; ++r) {{
      /* the margin is a running minimum over each chunk of records, then over each
         single record of the tail (as one call per chunk and per record gives) */
      if (r && (r >= whole || r % chunk == 0)) m = INFINITY;
      for (s = 0; s < INS_K; ++s) {{
        sarg[0] = buf[cur];
#if INS_NS
        if (split) {{
          a = stream + (r * INS_K + s) * INS_NU;
          for (i = 0; i < INS_NU; ++i) u[i] = a[i];
#if INS_NS > INS_NU
          h = mids + (r * INS_K + s) * INS_NU;
          for (i = 0; i < INS_NU; ++i) u[INS_NU + i] = h[i];
          for (i = 0; i < INS_NU; ++i) u[2 * INS_NU + i] = a[INS_NU + i];
#endif
          sarg[1] = u;
        }} else {{
          sarg[1] = stream + (r * INS_K + s) * INS_NS;
        }}
#endif
        sres[0] = buf[1 - cur];
#if INS_NROT
        sres[1] = d;   /* the angle increments; the driver rotates their sines, cosines */
#endif
        if (ins_step_c(sarg, sres, iw, wk, 0)) return 1;
#if INS_NROT
        ins_rotations(buf[cur], buf[1 - cur], d);
#endif
        cur = 1 - cur;
      }}
#if INS_MARGIN
      sarg[0] = buf[cur];
#if INS_NS
      sarg[1] = split ? u : stream + (r * INS_K + INS_K - 1) * INS_NS;
#endif
      sres[0] = &value;
      if (ins_margin_c(sarg, sres, iw, wk, 0)) return 1;
      m = fmin(m, value);
#endif
      o = out + (g * size + r) * INS_NC;
      for (i = 0; i < INS_NC; ++i) o[i] = buf[cur][i];
      o[INS_NZ] = m;
    }}
  }}
  return 0;
}}
CASADI_SYMBOL_EXPORT int ins_chunk_f(const casadi_real** arg, casadi_real** res,
                                     casadi_int* iw, casadi_real* w, int mem) {{
  (void)iw; (void)w; (void)mem;
  return ins_drive(arg, res, {chunk}, {chunk}, 0, INS_LIFTED ? arg[INS_NS ? 2 : 1] : 0);
}}
CASADI_SYMBOL_EXPORT int ins_single_f(const casadi_real** arg, casadi_real** res,
                                      casadi_int* iw, casadi_real* w, int mem) {{
  (void)iw; (void)w; (void)mem;
  return ins_drive(arg, res, 1, 1, 0, INS_LIFTED ? arg[INS_NS ? 2 : 1] : 0);
}}
CASADI_SYMBOL_EXPORT int ins_run_n(const casadi_real* carry, const casadi_real* stream,
                                   casadi_real* out, long long size,
                                   const casadi_real* constants) {{
  const casadi_real* arg[2];
  casadi_real* res[1];
  arg[0] = carry; arg[1] = stream; res[0] = out;
  return ins_drive(arg, res, (casadi_int)size, {chunk}, 0, constants);
}}
CASADI_SYMBOL_EXPORT int ins_run_rows(const casadi_real* carry, const casadi_real* steps,
                                      const casadi_real* mids, casadi_real* out,
                                      long long size, const casadi_real* constants) {{
  const casadi_real* arg[3];
  casadi_real* res[1];
  arg[0] = carry; arg[1] = steps; arg[2] = mids; res[0] = out;
  return ins_drive(arg, res, (casadi_int)size, {chunk}, 1, constants);
}}
CASADI_SYMBOL_EXPORT int ins_chunk_f_work(casadi_int* sz_arg, casadi_int* sz_res,
                                          casadi_int* sz_iw, casadi_int* sz_w) {{
  *sz_arg = INS_LIFTED ? (INS_NS ? 3 : 2) : 2; *sz_res = 1; *sz_iw = 0; *sz_w = 0;
  return 0;
}}
CASADI_SYMBOL_EXPORT int ins_single_f_work(casadi_int* sz_arg, casadi_int* sz_res,
                                           casadi_int* sz_iw, casadi_int* sz_w) {{
  return ins_chunk_f_work(sz_arg, sz_res, sz_iw, sz_w);
}}
"""


@contextmanager
def _no_simplification() -> Iterator[None]:
    """Inside, CasADi builds every operation as written (no folding or rewriting of
    ``x + 0``, ``a*(b*x)``...): a rebuilt graph keeps the arithmetic it copies."""
    previous = ca.GlobalOptions.getSimplificationOnTheFly()
    ca.GlobalOptions.setSimplificationOnTheFly(False)
    try:
        yield
    finally:
        ca.GlobalOptions.setSimplificationOnTheFly(previous)


class LiftError(InsErrorsError):
    """A graph :func:`lift_constants` cannot copy (an operation it does not know)."""


def lift_constants(function: ca.Function, inputs: Sequence[ca.SX]
                   ) -> tuple[list[ca.SX], ca.SX, np.ndarray]:
    """An SX function's outputs rebuilt operation for operation, its numbers symbols.

    Every instruction of ``function`` is made again on ``inputs`` (its dense input
    vectors) in its order, except that each number (a constant CasADi folded when the
    graph was built: what a baked loop compiles in) becomes a new symbol. Call it inside
    :func:`_no_simplification`, so that nothing is folded or rewritten again: evaluated
    with the numbers, the outputs give the function's bits.

    Returns
    -------
    outputs : list of casadi.SX
        The function's outputs (dense columns) on ``inputs`` and the symbols.
    symbols : casadi.SX, shape (k, 1)
        One symbol per number.
    values : numpy.ndarray, shape (k,)
        The numbers.

    Raises
    ------
    LiftError
        For an instruction that is not a number, an input, an output or an operation of
        one or two arguments (a call of another function).
    """
    args = [[x[j] for j in range(x.numel())] for x in inputs]
    outs: list[list[ca.SX | None]] = [[None] * function.nnz_out(i)
                                      for i in range(function.n_out())]
    work: dict[int, ca.SX] = {}
    symbols: list[ca.SX] = []
    values: list[float] = []
    for k in range(function.n_instructions()):
        op = function.instruction_id(k)
        given, made = function.instruction_input(k), function.instruction_output(k)
        if op == ca.OP_CONST:
            work[made[0]] = ca.SX.sym(f"k_{len(values)}")
            symbols.append(work[made[0]])
            values.append(function.instruction_constant(k))
        elif op == ca.OP_INPUT:
            work[made[0]] = args[given[0]][given[1]]
        elif op == ca.OP_OUTPUT:
            outs[made[0]][made[1]] = work[given[0]]
        elif op not in (ca.OP_CALL, ca.OP_PARAMETER) and len(given) == 2 and len(made) == 1:
            work[made[0]] = ca.SX.binary(op, work[given[0]], work[given[1]])
        elif op not in (ca.OP_CALL, ca.OP_PARAMETER) and len(given) == 1 and len(made) == 1:
            work[made[0]] = ca.SX.unary(op, work[given[0]])
        else:
            raise LiftError(f"lift_constants: instruction {k} of {function.name()} "
                            f"(operation {op}) is not an operation of one or two arguments")
    if any(value is None for out in outs for value in out):
        raise LiftError(f"lift_constants: an output of {function.name()} is never written")
    return ([ca.vertcat(*out) if out else ca.SX(0, 1) for out in outs],
            ca.vertcat(*symbols) if symbols else ca.SX.sym("k", 0), np.array(values))


def _assume_arguments(source: str) -> str:
    """Generated C with every argument and result pointer taken as given.

    CasADi's code tests each pointer before every read (``arg[0]? arg[0][7] : 0``) and
    write (``if (res[0]!=0) res[0][3]=...``), since a caller may pass none; the loop
    driver always passes them all. Without the tests the step is one basic block, which
    lets the compiler pair ``sin`` and ``cos`` of one angle into one ``sincos`` call. The
    arithmetic is untouched (a pattern that does not match is left as it is).
    """
    source = re.sub(r"arg\[(\d+)\]\? arg\[\1\]\[(\d+)\] : 0", r"arg[\1][\2]", source)
    return re.sub(r"if \(res\[(\d+)\]!=0\) res\[\1\]", r"res[\1]", source)


NO_FOLDING_FLAGS: tuple[str, ...] = tuple(
    f"-fno-builtin-{name}" for name in (
        "sin", "cos", "tan", "sincos", "asin", "acos", "atan", "atan2", "sinh", "cosh",
        "tanh", "asinh", "acosh", "atanh", "exp", "exp2", "expm1", "log", "log2", "log10",
        "log1p", "pow", "hypot", "cbrt", "erf", "erfc"))
"""Extra flags of a loop with frozen state (:meth:`CompiledLoop._frozen`): the compiler
would evaluate these functions of its constant arguments with its own correctly rounded
arithmetic, which may differ in the last bit from the C library the general loop calls
at run time; so they stay calls. (+, −, ×, /, sqrt are exact in both.)"""

INLINE_LIMIT = 600
"""Longest step (CasADi instructions) the C driver inlines into its record loop: a
static exact-platform Euler step (~240) gains ~4 % per step at no compile cost, while an
RK4 step of ~1100 compiled three times slower (0.6 s instead of 0.2 s) and one of ~4600
five times (7 s instead of 1.4 s)."""


def _driver_source(loop: CompiledLoop, chunk: int, margin: bool,
                   functions: list[ca.Function],
                   rotations: Sequence[tuple[int, int, int]] = (),
                   numbers: int | None = None) -> str:
    """C source of ``ins_chunk_f`` and ``ins_single_f`` for ``loop`` (see ``_DRIVER``);
    ``rotations``: ``(angle, sine, cosine)`` state indices the driver rotates; ``numbers``:
    how many numbers the step reads at run time (``functions`` then end with
    ``ins_constants_c``), None for a loop with its numbers written in."""
    def most(size: str) -> int:
        return 1 + max(getattr(f, size)() for f in functions)

    rotate = ""
    if rotations:
        from ins_errors.numeric.carried_trig import ROTATE_C

        calls = "".join(f"  ins_rotate(d[{j}], z[{s}], z[{c}], next + {s}, next + {c});\n"
                        for j, (_, s, c) in enumerate(rotations))
        rotate = (ROTATE_C + "static inline void ins_rotations(const casadi_real* z, "
                  "casadi_real* next, const casadi_real* d) {\n" + calls + "}\n")
    # inlining a long step makes the compiler several times slower for little gain
    inline = int(functions[0].n_instructions() <= INLINE_LIMIT)
    lifted = numbers is not None
    return _DRIVER.format(nz=loop.nz, nc=loop.n_carry, nrot=len(rotations), inline=inline,
                          rotate=rotate, lifted=int(lifted), nk=numbers or 0,
                          ne=functions[-1].size1_out(0) if lifted else 0,
                          ns=0 if loop.constant_inputs else loop.n_stream, nu=loop.nu,
                          k=loop.record_every, group=loop.group, margin=int(margin),
                          chunk=chunk, sz_arg=most("sz_arg"), sz_res=most("sz_res"),
                          sz_iw=most("sz_iw"), sz_w=most("sz_w"))


def progress_bar(total: int, progress: bool | str, initial: int = 0):
    """A tqdm bar over ``total`` steps when ``progress`` is set (a string labels it).

    ``initial`` steps are shown as done already and left out of the rate and the ETA
    (e.g. a first piece that also compiled the loop). Nothing is drawn when stderr is
    not a terminal.
    """
    from ins_errors.progress import on_terminal

    if not (progress and on_terminal()):
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit="step", unit_scale=True, leave=False,
                disable=None, desc=progress if isinstance(progress, str) else "integrating")


def _rename(function: ca.Function, name: str) -> ca.Function:
    args = [ca.MX.sym(f"i{i}", function.sparsity_in(i)) for i in range(function.n_in())]
    return ca.Function(name, args, function.call(args))
