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
    # the latitude line has one term: its size is the difference 1/R - 1/(R + h) against
    # the model's term 1/(R + h), h/R
    size = next(f.size for r, f in report.findings if r.equation.line == 3)
    assert size == pytest.approx(CRUISE_H / R_EARTH, rel=1e-6)


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


# A north-pointing INS on the ellipsoid with the radii of curvature R_N, R_E held fixed
# with latitude (their latitude derivatives left out), not declared: the one omission
# reaches every delta_latitude coefficient that holds a radius.
ELLIPSOID = """\
@alias R_E = r_E - h
@alias R_N = r_N - h
dot(Delta_v_E) = (2*Omega*sin(phi) + V_E*tan(phi)/(R_E + h))*Delta_v_N + V_N*(2*Omega*cos(phi) + V_E/((R_E + h)*cos(phi)**2))*Delta_phi + V_N*tan(phi)/(R_E + h)*Delta_v_E - f_U*alpha_N + a_N*alpha_U + nabla_E
dot(Delta_v_N) = -(2*Omega*sin(phi) + 2*V_E*tan(phi)/(R_E + h))*Delta_v_E - V_E*(2*Omega*cos(phi) + V_E/((R_E + h)*cos(phi)**2))*Delta_phi + f_U*alpha_E - a_E*alpha_U + nabla_N
dot(Delta_phi) = Delta_v_N/(R_N + h)
dot(Delta_lam) = Delta_v_E/((R_E + h)*cos(phi)) + V_E*sin(phi)/((R_E + h)*cos(phi)**2)*Delta_phi
dot(alpha_E) = -Delta_v_N/(R_N + h) + (Omega*sin(phi) + V_E*tan(phi)/(R_E + h))*alpha_N - (Omega*cos(phi) + V_E/(R_E + h))*alpha_U + epsilon_E
dot(alpha_N) = Delta_v_E/(R_E + h) - Omega*sin(phi)*Delta_phi - (Omega*sin(phi) + V_E*tan(phi)/(R_E + h))*alpha_E - V_N/(R_N + h)*alpha_U + epsilon_N
dot(alpha_U) = tan(phi)*Delta_v_E/(R_E + h) + (Omega*cos(phi) + V_E/((R_E + h)*cos(phi)**2))*Delta_phi + (Omega*cos(phi) + V_E/(R_E + h))*alpha_E + V_N/(R_N + h)*alpha_N + epsilon_U
"""  # noqa: E501
WGS84 = {"ecc2": 0.00669437999014}


def test_one_undeclared_omission_is_one_root_with_its_lines_as_knock_ons():
    report = _check(ELLIPSOID, parameters=WGS84)
    assert len(report.omissions) == 1
    omission = report.omissions[0]
    assert set(omission.quantities) == {"R_N", "R_E"} and omission.along == ("phi",)
    assert omission.lines == (3, 4, 5, 6, 7, 8, 9)
    assert "is dropped (not declared): explains lines 3, 4, 5, 6, 7, 8, 9" in omission.title
    # every finding is one of its knock-ons, of one class: an undeclared omission is
    # judged by its size, below the threshold a dropped small term
    assert omission.severity == cl.DROPPED and omission.size < 1e-3
    assert {(f.kind, f.severity, f.role, f.roots) for _, f in report.findings} == {
        (cl.OMITTED, cl.DROPPED, cl.KNOCK_ON, (omission.reference,))}
    assert {r.equation.line for r, _ in report.findings} == set(omission.lines)
    assert report.exit_status == 0
    # the @neglect line it suggests, written in the file, declares exactly these drops
    declared = _check(omission.neglect + "\n" + ELLIPSOID, parameters=WGS84)
    assert not declared.omissions and not declared.idle_declarations
    assert {(r.equation.line - 1, f.quantity, f.severity) for r, f in declared.findings} == {
        (r.equation.line, f.quantity, cl.DECLARED) for r, f in report.findings}


def test_a_wrong_coefficient_beside_the_omission_stays_its_own_mistake():
    # a factor 2 on a term no radius touches, and one on a term of the omitted coefficient
    slipped = (ELLIPSOID.replace("- f_U*alpha_N + a_N", "- 2*f_U*alpha_N + a_N")
               .replace("- Omega*sin(phi)*Delta_phi", "- 2*Omega*sin(phi)*Delta_phi"))
    report = _check(slipped, parameters=WGS84)
    assert {(r.equation.line, f.quantity, f.role) for r, f in report.mistakes} == {
        (3, "alpha_N", cl.ROOT), (8, "delta_latitude", cl.ROOT)}
    (omission,) = report.omissions
    assert omission.lines == (3, 4, 5, 6, 7, 9)  # line 8's coefficient is wrong besides
    assert report.exit_status == 1


def test_the_report_names_the_omission_and_its_declaration():
    from ins_errors.checker.report import to_json, to_markdown, to_terminal
    from ins_errors.checker.report_latex import to_latex

    report = _check(ELLIPSOID, parameters=WGS84)
    (omission,) = report.omissions
    for text in (to_terminal(report), to_markdown(report)):
        assert omission.neglect in text and "is dropped (not declared)" in text
    assert r"\subsubsection*{Undeclared dropped variations}" in to_latex(report)
    data = to_json(report)
    assert data["summary"]["findings"]["undeclared_drops"] == 1
    assert data["omissions"][0]["lines"] == [3, 4, 5, 6, 7, 8, 9]
