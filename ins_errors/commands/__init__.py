"""Subcommands of the ``ins-errors`` command line, one module each (and the option
types they share)."""

from __future__ import annotations

import math


def hours(text: str) -> float:
    """``--hours``: a positive, finite number of hours (``-1`` was reported as a duration
    of -3600 seconds, a unit the user never typed)."""
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of hours, e.g. 24"
                                         ) from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number of hours, got {text}")
    return value
