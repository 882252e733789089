"""Do a model's outputs read back what its initial-state map was given?

A model file's initial-state map takes navigation quantities (latitude, heading, v_N, …)
and its outputs give them back. When the two disagree (a heading clockwise from north
given to the map, a yaw counter-clockwise read out as ``heading``), a comparison runs
and reports every error of that output with the wrong sign, or an offset, and nothing
looks wrong. ``ins-errors check`` refuses such a model along its motions
(:func:`ins_errors.checker.strapdown_description.validate`, property 2);
:func:`refuse_mismatch` makes the same check at the start of a run, for ``compare`` and
``run``: the initial-state map is given the run's own initial conditions, and those
shifted by :data:`SHIFTS` (a static base at heading 0 would hide a sign), and each
output named as a navigation quantity must read back what it was given. Cost: two
evaluations of the generated numpy functions (well under a millisecond).
"""

from __future__ import annotations

import math

import numpy as np

from ins_errors.errors import InsErrorsError

SHIFTS = {"latitude": 0.01, "longitude": 0.02, "height": 10.0, "v_N": 1.5, "v_E": 2.5,
          "v_D": 0.25, "roll": 0.05, "pitch": 0.04, "heading": 0.6}
"""Shifts (SI) of the navigation quantities for the second read-back: away from the
zeros and symmetries of a static base (heading 0, speed 0), small enough to stay in
every model's domain."""

TOLERANCE = 1e-7
"""Largest change of a quantity (rad, m, m/s; relative to 1 + its size) between what the
map was given and what the output reads (as ``check``'s
:data:`~ins_errors.checker.strapdown_description.ROUND_TRIP_TOLERANCE`)."""

ANGLES = {"latitude", "longitude", "roll", "pitch", "heading"}
"""Quantities compared on the circle."""


def _pairs(model) -> list[tuple[int, int, float, str, str]] | None:
    """(condition row, output index, output sign / condition sign, navigation quantity,
    output name) of each navigation quantity that both an initial condition sets and an
    output reads; None when an initial condition is not a navigation quantity (the map
    then takes more than a flight sets: nothing to compare)."""
    from ins_errors.checker.strapdown_description import ALTERNATIVES, NAVIGATION_OUTPUTS
    from ins_errors.numeric.model_flight import CONDITIONS

    columns = {}
    for row, condition in enumerate(model.initial_conditions):
        if condition.name not in CONDITIONS:
            return None
        column, sign = CONDITIONS[condition.name]
        columns[column] = (row, sign)
    names = [o.name for o in model.outputs]
    pairs = []
    for column, quantity in enumerate(NAVIGATION_OUTPUTS):
        if column not in columns:
            continue
        for candidate, sign in ((quantity, 1.0), *ALTERNATIVES.get(quantity, ())):
            if candidate in names:
                row, condition_sign = columns[column]
                pairs.append((row, names.index(candidate), sign * condition_sign, quantity,
                              candidate))
                break
    return pairs


CONVENTIONS = {"heading": "heading from north, clockwise",
               "roll": "roll, pitch, heading z-y-x", "pitch": "roll, pitch, heading z-y-x",
               "v_N": "v_N north, v_E east, v_D down or v_U up, in m/s"}
"""What each quantity's convention is, as the refusal says it (latitude, longitude and
height: in rad and m)."""


def _shown(value: float, quantity: str) -> str:
    """A value as the message shows it: an angle in degrees, else SI with its unit."""
    if quantity in ANGLES:
        return f"{math.degrees(value):.6g}°"
    return f"{value:.6g} {'m' if quantity == 'height' else 'm/s'}"


def refuse_mismatch(model, trajectory) -> None:
    """Refuse, in one line, a model whose outputs do not read back what its
    initial-state map is given, at the start of ``trajectory``.

    Parameters
    ----------
    model : Model
    trajectory : Trajectory
        Its ``initial_conditions``, ``start_inputs`` and ``parameters`` are read.

    Raises
    ------
    InsErrorsError
        Naming the output, the value given and the value read back.
    """
    pairs = _pairs(model)
    c0 = np.asarray(getattr(trajectory, "initial_conditions", ()), dtype=float)
    if not pairs or c0.shape != (len(model.initial_conditions),):
        return
    u = np.asarray(trajectory.start_inputs, dtype=float)
    p = np.asarray(trajectory.parameters, dtype=float)
    shifted = c0.copy()
    for row, _, sign, quantity, _ in pairs:
        shifted[row] += SHIFTS[quantity] * (1.0 if sign > 0 else -1.0)
    for c in (c0, shifted):
        with np.errstate(all="ignore"):
            try:
                x = np.asarray(model.numpy.initial_state(c, u, p), dtype=float).reshape(-1)
                out = np.asarray(model.numpy.outputs(x, u, p), dtype=float).reshape(-1)
            except (ArithmeticError, ValueError, TypeError):
                continue  # not evaluable here: the run's own checks say why
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(out))):
            continue
        for row, index, sign, quantity, name in pairs:
            given, read = c[row] * sign, out[index]
            change = read - given
            if quantity in ANGLES:
                change = (change + math.pi) % (2 * math.pi) - math.pi
            if abs(change) > TOLERANCE * (1.0 + abs(given)):
                raise InsErrorsError(
                    f"model {model.name!r}: its output {name!r} does not read back what its "
                    f"initial-state map was given ({_shown(given, quantity)} given, "
                    f"{_shown(read, quantity)} read back): the outputs and the initial "
                    "conditions must use the same conventions ("
                    + CONVENTIONS.get(quantity if quantity[:2] != "v_" else "v_N",
                                      "latitude, longitude in rad, height in m") + ")")
