"""A step too long for the fastest oscillation of the error equations.

The errors of an INS oscillate at F's periods (Schuler's 84 min, split by Foucault's
rate; a damped loop's own). A run whose step is not well under the fastest of them does
not follow it: RK4 at 10 steps a period keeps its amplitude to 1e-4 a period and its
phase to 8e-3 rad; at fewer, the curves are the scheme's more than the equations'. The
integration-error estimate says so when it can, but not always: a run of one step, or of
so few that the run at twice the step shares no sample with it, has no estimate at all
(a 1-h step over an hour of a Schuler loop ran silently). So :func:`warning` says it in
one line, naming the period (F's eigenvalue with the largest imaginary part at the
start, :func:`~ins_errors.numeric.sampled_maxima.start_eigenvalues`) and a step of
:data:`STEPS_ADVISED` a period.
"""

from __future__ import annotations

import math

STEPS_PER_PERIOD = 10
"""Fewest steps per period of F's fastest oscillation a run takes without a warning."""

STEPS_ADVISED = 20
"""Steps per period the warning's step gives."""


def period_text(seconds: float) -> str:
    """``"80.7 min"``, ``"42 s"``, ``"1.5 h"``: a period to three digits."""
    if seconds >= 7200:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 60:.3g} min" if seconds >= 120 else f"{seconds:.3g} s"


def warning(step: float, omega: float, interval: float,
            spacing: float | None = None) -> str | None:
    """The warning when ``step`` is longer than a :data:`STEPS_PER_PERIOD`-th of the
    period of ``omega``, else None.

    Parameters
    ----------
    step : float
        The run's step, s.
    omega : float
        F's fastest oscillation at the start, rad/s (0: none, no warning).
    interval : float
        The recording interval, s: the step named divides it
        (:func:`~ins_errors.numeric.accuracy.typable_step`).
    spacing : float, optional
        A length (s) the step named divides too (the motion's breaks).
    """
    if not omega > 0 or not step > 0:
        return None
    period = 2 * math.pi / omega
    if step * STEPS_PER_PERIOD <= period * (1 + 1e-12):
        return None
    from ins_errors.numeric import accuracy

    _, text = accuracy.typable_step(period / STEPS_ADVISED, interval, spacing)
    return (f"step too long for F's fastest oscillation: τ = {step:g} s is "
            f"{step / period:.2g} of its period ({period_text(period)} at the start), "
            f"fewer than {STEPS_PER_PERIOD} steps a period, so the runs cannot follow it; "
            f"τ = {text} s ({STEPS_ADVISED} a period) resolves it")
