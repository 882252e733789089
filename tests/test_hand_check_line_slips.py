"""Slips of one hand line, sized and named as one mistake each.

The expected sizes are worked out here from the physics of a north-pointing INS on a
sphere of radius R at height h (typical magnitudes from one attitude error θ: velocity
errors √(gR)·θ, angles θ), not read from the checker.
"""

from __future__ import annotations

import math

import pytest

from ins_errors.checker import classify as cl
from ins_errors.checker.compare import check_hand
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import parse_hand_text

R_EARTH, G, CRUISE_H = 6371000.0, 9.80665, 10000.0  # the reference sphere, gravity, cruise


def _check(text: str, model: str = "north_pointing", **kwargs):
    hand = parse_hand_text(text, default_notation(model))
    return check_hand(hand, model=model, effects=False, **kwargs)


def _by_quantity(report) -> dict[str, cl.Finding]:
    return {f.quantity: f for _, f in report.findings}


def test_a_wrong_extra_term_does_not_shrink_an_index_slip_on_the_same_line():
    # the model: dot(δφ) = δv_N/(R + h), one term; δv_E written for δv_N moves all of it,
    # so the slip is as large as the equation: size 1, a mistake (not "small effect")
    alone = _by_quantity(_check("dot(delta_latitude) = delta_v_E/(R + h)\n"))
    slip = alone["delta_v_N -> delta_v_E"]
    assert slip.size == pytest.approx(1.0, rel=1e-9) and slip.severity == cl.MISTAKE
    # the same slip with a large wrong term beside it (g·α_E, 1e4 times the model's term):
    # the slip keeps its size, and the extra term is sized against the model's term too
    both = _by_quantity(_check("dot(delta_latitude) = g*alpha_E + delta_v_E/(R + h)\n"))
    slip = both["delta_v_N -> delta_v_E"]
    assert slip.kind == cl.SYMBOL and slip.severity == cl.MISTAKE
    assert slip.size == pytest.approx(1.0, rel=1e-9)
    extra = both["alpha_E"]
    # g θ against √(gR) θ/(R + h): largest at the cruise height
    expected = G * (R_EARTH + CRUISE_H) / math.sqrt(G * R_EARTH)
    assert extra.kind == cl.EXTRA and extra.size == pytest.approx(expected, rel=1e-6)
