"""How far the maxima of recorded curves may be below the run's own maxima.

``compare`` reports each quantity's largest error and residual over the *recorded*
samples. When the recording interval Δ is longer than the step, a peak between two
samples is missed: for an oscillation of period T sampled every Δ, the largest sample
can be below its peak by up to ``1 − cos(π Δ / T)`` (the peak halfway between two
samples). The fastest oscillation the errors have is taken as that of F's eigenvalue
with the largest imaginary part |Im λ| = 2π / T at the start of the run. Measured on a
1-h static orthodromic run (F's fastest period 80.7 min, Schuler's split by Foucault's
rate) recorded every 10 min, against the same run recorded at every step: the largest
errors were up to 3.3 % low, the largest linear − direct residuals 7.0 % low, the bound
7.5 %; every 20 min: 27 % low, the bound 29 %.
"""

from __future__ import annotations

import math

import numpy as np

from ins_errors.errors import InsErrorsError

NOTED = 0.01
"""Smallest possible shortfall of the recorded maxima (a fraction of them) that the
comparison's summary names in a note."""

LIGHT_DAMPING = 0.1
"""Largest damping ratio |Re λ|/|λ| of an oscillation whose peaks the maxima may miss: a
damped loop's own oscillation (a vertical channel damped to ζ ≈ 0.7, period 7 min) is
gone within a period or two, and the errors' peaks are the slow oscillations'."""


def start_eigenvalues(model, trajectory) -> np.ndarray:
    """F's eigenvalues at the start of ``trajectory`` (1/s); empty when F cannot be read
    there or is not finite. (Along a moving run F changes; read at the start as the rest
    of the comparison's advice is. Further along, an ideal strapdown run without
    vertical damping has drifted in height after hours and F's eigenvalues there say
    more about that drift than about the errors' oscillations.)"""
    from ins_errors.numeric.linear_system import start_state_matrix

    try:
        with np.errstate(all="ignore"):
            F = start_state_matrix(model, trajectory)
    except (InsErrorsError, ArithmeticError, ValueError):
        return np.zeros(0, dtype=complex)
    if not F.size or not np.all(np.isfinite(F)):
        return np.zeros(0, dtype=complex)
    return np.linalg.eigvals(F)


def fastest_oscillation(values: np.ndarray, lightly_damped: bool = False) -> float:
    """Largest |Im λ| of the eigenvalues ``values`` (rad/s; :func:`start_eigenvalues`),
    of those damped by at most :data:`LIGHT_DAMPING` where ``lightly_damped``; 0 without
    any."""
    if lightly_damped:
        values = values[np.abs(values.real) <= LIGHT_DAMPING * np.abs(values)]
    return float(np.abs(values.imag).max()) if values.size else 0.0


def shortfall(interval: float, omega: float) -> float:
    """``1 − cos(ω Δ / 2)``: the largest fraction by which samples every ``interval``
    (Δ, s) fall below the peak of an oscillation at ``omega`` (ω, rad/s); 1 once Δ
    reaches half the period (the samples may straddle every peak at its zeros)."""
    half = omega * interval / 2
    return 1.0 if half >= math.pi / 2 else 1.0 - math.cos(half)


def note(interval: float, step: float, omega: float) -> str | None:
    """The summary's note when the maxima over samples every ``interval`` (s), a run at
    ``step`` (s), may be :data:`NOTED` or more below the run's own; else None."""
    if not interval > step or omega <= 0:
        return None
    low = shortfall(interval, omega)
    if low < NOTED:
        return None
    from ins_errors.numeric.step_period import period_text
    from ins_errors.units import format_duration

    seconds = 2 * math.pi / omega
    period = period_text(seconds)
    size = ("may miss the peaks entirely (the interval is half F's fastest period, "
            f"{period}, or more)") if low >= 1.0 else (
            f"may be up to about {100 * low:.2g} % low (1 − cos(πΔ/T) for F's fastest "
            f"period T = {period})")
    return (f"maxima are over the recorded samples (every {format_duration(interval)}; "
            f"the step is {format_duration(step)}): a peak between two samples is missed, "
            f"so they {size}; record more often (--record) for "
            "the run's own maxima")
