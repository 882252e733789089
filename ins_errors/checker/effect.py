"""Does it matter? The effect of each mistake on the 1 h and 24 h error (placeholder)."""

from __future__ import annotations


def add_effects(report, d, side, comparison, identify, prepared, resolver) -> None:
    """Attach effects to the report's mistakes (not computed yet)."""
    return None
