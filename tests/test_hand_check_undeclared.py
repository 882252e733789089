"""Simplifications of a plain hand file: neglecting the height against the radius
(``@neglect h : h << R``), and one undeclared omission reported as one root.

The expected findings are worked out here from the physics of a north-pointing INS on a
sphere of radius R at height h, not read from the checker: writing 1/R for 1/(R + h) makes
a coefficient differ by the relative amount h/(R + h).
"""

from __future__ import annotations

import pytest

from ins_errors.checker import classify as cl
from ins_errors.checker.compare import check_hand
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import parse_hand_text

H_DROP = (
    "# the height neglected against the Earth radius everywhere\n"
    "@neglect h : h << R\n"
    "dot(Delta_phi) = Delta_v_N/R\n"
    "dot(alpha_E) = -Delta_v_N/R + (Omega*sin(phi) + V_E*tan(phi)/R)*alpha_N"
    " - (Omega*cos(phi) + V_E/R)*alpha_U + epsilon_E\n")
R_EARTH, CRUISE_H = 6371000.0, 10000.0  # the reference points' sphere and cruise height


def _check(text: str, model: str = "north_pointing", **kwargs):
    hand = parse_hand_text(text, default_notation(model))
    return check_hand(hand, model=model, effects=False, **kwargs)


def _found(report) -> set[tuple[int, str, str, str]]:
    return {(r.equation.line, f.quantity, f.kind, f.severity) for r, f in report.findings}


def test_neglecting_the_height_declares_every_radius_sum():
    report = _check(H_DROP)
    # the model's 1/(R + h) terms: delta_v_N in both lines, the transport rates V_E/(R + h)
    # on alpha_N and alpha_U of the alpha_E line
    assert _found(report) == {
        (3, "delta_v_N", cl.OMITTED, cl.DECLARED), (4, "delta_v_N", cl.OMITTED, cl.DECLARED),
        (4, "alpha_N", cl.OMITTED, cl.DECLARED), (4, "alpha_U", cl.OMITTED, cl.DECLARED)}
    assert report.exit_status == 0 and not report.idle_declarations
    # the latitude line has one term: its size is the relative difference h/(R + h)
    size = next(f.size for r, f in report.findings if r.equation.line == 3)
    assert size == pytest.approx(CRUISE_H / (R_EARTH + CRUISE_H), rel=1e-6)


def test_a_sign_slip_beside_the_neglected_height_is_exactly_that_mistake():
    slipped = H_DROP.replace("- (Omega*cos(phi) + V_E/R)*alpha_U",
                             "+ (Omega*cos(phi) + V_E/R)*alpha_U")
    report = _check(slipped)
    assert [(r.equation.line, f.quantity, f.kind) for r, f in report.mistakes] == [
        (4, "alpha_U", cl.SIGN)]
    assert {(r.equation.line, f.quantity) for r, f in report.findings
            if f.severity == cl.DECLARED} == {(3, "delta_v_N"), (4, "delta_v_N"),
                                              (4, "alpha_N")}


def test_without_the_declaration_the_height_terms_are_found():
    report = _check(H_DROP.replace("@neglect h : h << R\n", ""))
    assert {(r.equation.line, f.quantity) for r, f in report.mistakes} == {
        (2, "delta_v_N"), (3, "delta_v_N"), (3, "alpha_N"), (3, "alpha_U")}
    assert all(f.kind == cl.COEFFICIENT for _, f in report.mistakes)


def test_a_neglected_quantity_keeps_the_lines_before_it():
    # the declaration holds from its line on: the line before it keeps its finding
    text = ("dot(Delta_phi) = Delta_v_N/R\n@neglect h : h << R\n"
            "dot(alpha_E) = -Delta_v_N/R + (Omega*sin(phi) + V_E*tan(phi)/R)*alpha_N"
            " - (Omega*cos(phi) + V_E/R)*alpha_U + epsilon_E\n")
    report = _check(text)
    assert {(r.equation.line, f.quantity, f.severity) for r, f in report.findings
            if r.equation.line == 1} == {(1, "delta_v_N", cl.MISTAKE)}
    assert all(f.severity == cl.DECLARED for r, f in report.findings if r.equation.line == 3)
