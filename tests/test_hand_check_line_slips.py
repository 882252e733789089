"""Slips of one hand line, sized and named as one mistake each.

The expected sizes are worked out here from the physics of a north-pointing INS on a
sphere of radius R at height h (typical magnitudes from one attitude error θ: velocity
errors √(gR)·θ, angles θ), not read from the checker.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from ins_errors.checker import classify as cl
from ins_errors.checker.compare import check_hand, check_hand_file
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


@pytest.mark.parametrize(("line", "quantity", "detail"), [
    # the model divides by cos φ (dλ/dt = v_E/((R + h) cos φ)); the hand multiplies
    ("dot(delta_longitude) = delta_v_E*cos(phi)/(R + h)"
     " + V_E*sin(phi)/((R + h)*cos(phi)**2)*delta_latitude",
     "delta_v_E", "cos(phi) multiplies where it divides"),
    # the model multiplies by cos φ (the Earth rate's north part U cos φ); the hand divides
    ("dot(alpha_E) = -delta_v_N/(R + h) + alpha_N*(U*sin(phi) + V_E*tan(phi)/(R + h))"
     " - alpha_U*(U/cos(phi) + V_E/(R + h)) + gyro_drift_east",
     "alpha_U", "cos(phi) divides where it multiplies"),
])
def test_divided_instead_of_multiplied_is_named(line, quantity, detail):
    report = _check(line + "\n")
    (f,) = [f for _, f in report.findings]
    assert f.quantity == quantity and f.kind == cl.EXPONENT and f.severity == cl.MISTAKE
    assert f.detail.startswith(detail)


MANUAL = Path(__file__).resolve().parent.parent / "examples" / "manual_000" / "equations.txt"


def _manual_with(tmp_path, old: str, new: str):
    """The manual's listing with one printed term changed, checked."""
    text = MANUAL.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / "slip.txt"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return check_hand_file(path, model="orthodromic")


def _line_roots(report, line: int) -> list[cl.Finding]:
    return [f for r, f in report.root_mistakes if r.equation.line == line]


def test_one_index_slip_on_a_line_is_one_root_mistake(tmp_path):
    # u12 for u21 in the u31 line: the term u21·Δω_rel_ξ expands (through Δω_ξ) into five
    # error quantities, every one of them wrong; one slip, one root
    clean = check_hand_file(MANUAL, model="orthodromic")
    old = "dot(Delta_u31) = u11*Delta_omega_rel_eta - u21*Delta_omega_rel_xi"
    report = _manual_with(tmp_path, old, old.replace("- u21*", "- u12*"))
    (result,) = [r for r in report.results if r.equation.text.startswith("dot(Delta_u31)")
                 and r.equation.section == 2]
    (root,) = _line_roots(report, result.equation.line)
    assert (root.quantity, root.kind, root.severity) == (cl.LINE, cl.SYMBOL, cl.MISTAKE)
    assert root.detail.startswith("u12 written where u21 belongs")
    assert (root.hand, root.model) == ("u12", "u21")
    knock = [f for _, f in report.knock_ons(result) if f.roots == (result.reference,)]
    assert {f.quantity for f in knock} == {"delta_u11", "delta_u21", "delta_u31",
                                           "delta_V_xi", "delta_V_eta"}
    assert root.size == max(f.size for f in knock)
    # the file's other findings are the clean manual's: one root mistake more
    assert len(report.root_mistakes) == len(clean.root_mistakes) + 1


def test_an_error_quantity_slip_hidden_at_the_points_is_one_root(tmp_path):
    # Δu12 for Δu11 in ω_rel_ζ Δu11 of the u21 line: ω_rel_ζ is 0 at every point, so both
    # findings have no size; the slip is still one root, named in the file's spelling
    old = "u11*Delta_omega_rel_zeta + omega_rel_xi*Delta_u31 - omega_rel_zeta*Delta_u11"
    report = _manual_with(tmp_path, old, old.replace("Delta_u11", "Delta_u12"))
    (result,) = [r for r in report.results if r.equation.text.startswith("dot(Delta_u21)")
                 and r.equation.section == 2]
    (root,) = _line_roots(report, result.equation.line)
    assert root.kind == cl.SYMBOL
    assert root.detail.startswith("Delta_u12 written where Delta_u11 belongs")
    assert {f.quantity for _, f in report.knock_ons(result)} == {"delta_u11", "delta_u12"}


def test_a_named_slip_on_two_quantities_counts_once():
    # V_N for V_E before the bracket of the dv_N line reaches dv_E and dlat: one root
    line = ("dot(delta_v_N) = -(2*U*sin(phi) + V_E*tan(phi)/(R + h))*delta_v_E"
            " - V_N*(2*U*cos(phi)*delta_latitude + V_E/((R + h)*cos(phi)**2)*delta_latitude"
            " + tan(phi)/(R + h)*delta_v_E) - a_E*alpha_U + f_U*alpha_E + accel_bias_north\n")
    report = _check(line)
    ((result, root),) = report.root_mistakes
    assert (root.quantity, root.kind) == (cl.LINE, cl.SYMBOL)
    assert root.detail.startswith("V_N written where V_E belongs")
    assert {f.quantity for _, f in report.knock_ons(result)} == {"delta_v_E",
                                                                "delta_latitude"}
