"""Durations written for a reader: a period or an e-folding time, four significant digits."""

from __future__ import annotations


def duration_text(seconds: float) -> str:
    """A time in s, min, h or days, four significant digits (``"84.41 min"``)."""
    for limit, unit, size in ((120.0, "s", 1.0), (7200.0, "min", 60.0),
                              (172800.0, "h", 3600.0)):
        if seconds < limit:
            return f"{seconds / size:.4g} {unit}"
    return f"{seconds / 86400.0:.4g} days"
