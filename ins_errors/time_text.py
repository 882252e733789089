"""Durations written for a reader: a period, an e-folding time, the length of a run."""

from __future__ import annotations


def duration_text(seconds: float) -> str:
    """A time in s, min, h or days, four significant digits (``"84.41 min"``)."""
    for limit, unit, size in ((120.0, "s", 1.0), (7200.0, "min", 60.0),
                              (172800.0, "h", 3600.0)):
        if seconds < limit:
            return f"{seconds / size:.4g} {unit}"
    return f"{seconds / 86400.0:.4g} days"


def run_length_text(seconds: float) -> str:
    """The length of a run as a title gives it: in hours from an hour on where that is a
    short decimal (``"24 h"``, ``"1.5 h"``, ``"168 h"``), else as :func:`duration_text`
    (``"10 min"`` for 600 s, not ``"0.166667 h"``; ``"90 s"``, not ``"0.025 h"``)."""
    hours = seconds / 3600.0
    if seconds >= 3600.0 and round(hours, 3) == hours:
        return f"{hours:g} h"
    return duration_text(seconds)
