"""Subcommands of the ``ins-errors`` command line, one module each (and the option
types they share)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence


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


def motion_kinds(known: Sequence[str]) -> Callable[[str], str]:
    """``--motion``: an argparse type that reads one of ``known`` or an alias of one as
    scenario files do (:func:`~ins_errors.numeric.motion_spec.motion_kind`:
    ``great_circle`` is ``great-circle``), and refuses another name with the closest
    kinds (``maneuver``: did you mean 'manoeuvre'?), not argparse's bare list."""

    def motion(text: str) -> str:
        import argparse

        from ins_errors.errors import InsErrorsError
        from ins_errors.numeric.motion_spec import motion_kind

        try:
            return motion_kind(text, known)
        except InsErrorsError as error:
            raise argparse.ArgumentTypeError(str(error)) from None

    return motion


MOTION_OPTIONS = {"latitude": "--latitude", "longitude": "--longitude",
                  "heading": "--heading", "track": "--heading", "height": "--height",
                  "speed": "--speed"}
"""The option of the command line that sets each value of a motion description (a
moving motion's heading is its track)."""


def motion_from_options(description, model=None):
    """The profile of a motion the command line describes
    (:func:`~ins_errors.numeric.motion_spec.motion_profile`), its one-line errors naming
    the option the user typed (``--latitude 95° is at or beyond a pole``), not the
    motion setting it fills (``motion latitude``).

    Parameters
    ----------
    description : mapping
        As :func:`~ins_errors.numeric.motion_spec.motion_profile` reads it, filled from
        the options (:data:`MOTION_OPTIONS`).
    model : ins_errors.numeric.model.Model, optional
        Passed on.

    Returns
    -------
    ins_errors.numeric.trajectories.Profile

    Raises
    ------
    InsErrorsError
        As ``motion_profile``; a value of an option is named by the option.
    """
    import re

    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric.motion_spec import motion_profile

    try:
        return motion_profile(description, model=model)
    except InsErrorsError as error:
        text = str(error)
        match = re.match(r"(?:motion|great-circle) (\w+)\b", text)
        if match is None or match.group(1) not in MOTION_OPTIONS:
            raise
        option = MOTION_OPTIONS[match.group(1)]
        raise type(error)(option + text[match.end():]) from None
