"""Exponential growth of an error difference: found from eigenvalues, said in words.

Shared by the equation checker's effects (:mod:`~ins_errors.checker.effect`) and the
matrix check's (:mod:`~ins_errors.checker.matrix`): when a mistake gives the linear error
equations a growing mode the model lacks (an eigenvalue with a larger positive real part,
a sign-flipped Schuler loop), the difference it makes after a day is a figure like
1e48 m, which says nothing but "it grows". Past :data:`GROWTH_SHOWN` e-foldings over the
time compared the effect is given as exponential growth with the e-folding time of that
mode (:func:`growth_text`) instead. No SymPy here (the matrix check does not load it).
"""

from __future__ import annotations

import numpy as np

from ins_errors.numeric.linear_system import growth_rate

GROWTH_SHOWN = 10.0
"""E-foldings of a growing mode the model lacks (its rate times the time compared) from
which the effect is given as exponential growth instead of a figure (a factor of 2e4
over the model)."""

HOURS = (1.0, 24.0)
"""Times compared by default, h."""


def mark_growth(effect: dict, hand: float, model: float,
                hours: tuple[float, ...] = HOURS, quantity: str = "position") -> None:
    """Mark the times at which an effect grows exponentially.

    ``hand``, ``model``: largest real parts of the eigenvalues (1/s, :func:`growth_rate`)
    of F with and without the mistake. A growing mode the mistake adds (``hand`` above the
    model's and past :data:`GROWTH_SHOWN` e-foldings over the last of ``hours``) makes the
    difference grow at its rate; a growing mode of the model itself (an undamped vertical
    channel) only where the difference did grow by that much since the first time (a
    mistake the mode does not see keeps its figure).

    Parameters
    ----------
    effect : dict
        Holds ``<quantity>_<h>h`` and ``<quantity>_floor_<h>h`` for each time of ``hours``
        (``<h>`` the whole hours; None where the model has no such figure); receives
        ``e_folding_s`` (s), ``growing_mode`` (``"hand"`` or ``"model"``) and
        ``exponential_<h>h`` (bool) when a mode grows.
    hand, model : float
        Growth rates, 1/s.
    hours : tuple of float
        The times compared, h, increasing.
    quantity : str
        The figure a growing mode of the model itself is judged by (``"position"``, or
        ``"attitude"`` for a model without a position); without that figure only a mode
        the mistake adds is marked.
    """
    span = hours[-1] * 3600.0
    if hand > max(model, 0.0) and (hand - max(model, 0.0)) * span > GROWTH_SHOWN:
        rate, whose = hand, "hand"
    elif model * span > GROWTH_SHOWN:
        rate, whose = model, "model"
    else:
        return
    effect["e_folding_s"] = 1.0 / rate
    effect["growing_mode"] = whose
    first = effect.get(f"{quantity}_{hours_tag(hours[0])}")
    for h in hours:
        tag = hours_tag(h)
        grows = rate * h * 3600.0 > GROWTH_SHOWN
        if whose == "model":
            value = effect.get(f"{quantity}_{tag}")
            grows = grows and first is not None and value is not None and value > np.exp(
                GROWTH_SHOWN) * max(first, effect[f"{quantity}_floor_{tag}"])
        effect[f"exponential_{tag}"] = bool(grows)


def hours_tag(hours: float) -> str:
    """The suffix of a time's keys in :func:`mark_growth`'s dict: ``24h`` for 24 h (whole
    hours)."""
    return f"{int(hours)}h"


def growth_text(e_folding_s: float, whose: str | None = "hand") -> str:
    """``grows exponentially, ×e every 13.4 min`` (with ``(the model's own mode)`` for a
    mode of the model itself)."""
    own = " (the model's own mode)" if whose == "model" else ""
    return f"grows exponentially, ×e every {e_folding_s / 60:.3g} min{own}"


__all__ = ["GROWTH_SHOWN", "growth_rate", "growth_text", "hours_tag", "mark_growth"]
