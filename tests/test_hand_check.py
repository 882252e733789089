"""The hand-derivation checker against independent hand derivations and the manual.

The reference file below is a hand derivation of the orthodromic INS error equations
written from the physics (chain rule on the manual's ideal-work formulas), not from the
model code: the checker must find it identical to the mechanical variation, find every
mistake injected into it, and class small deliberate drops as such.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker.compare import check_hand
from ins_errors.checker.notation import ORTHODROMIC
from ins_errors.checker.parse import parse_hand_text
from ins_errors.checker.report import to_json, to_markdown, to_terminal
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
MANUAL = ROOT / "examples" / "manual_000"

CORRECT = (ROOT / "tests" / "data" / "hand_correct_orthodromic.txt").read_text()


def check(text: str, threshold: float = 1e-3, latex: bool = False):
    return check_hand(parse_hand_text(text, ORTHODROMIC, latex=latex), threshold=threshold)


def line_of(text: str, start: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith(start))


def results_at(report, line: int):
    return [r for r in report.results if r.equation.line == line]


@pytest.fixture(scope="module")
def correct_report():
    return check(CORRECT)


def test_independent_hand_derivation_agrees_exactly(correct_report):
    report = correct_report
    assert not report.problems
    assert len(report.results) == sum(1 for line in CORRECT.splitlines()
                                      if not line.startswith("#"))
    assert {r.status for r in report.results} == {"agrees"}, [
        (r.equation.line, r.findings) for r in report.results if r.status != "agrees"]
    assert report.exit_status == 0
    # only the sources the file mentions are compared; the rest are listed
    assert {b.name for b in report.basis} >= {"Delta_a", "omega_dp", "alpha_x", "delta_u31"}
    assert "accel_scale_error_x" in report.out_of_scope
    assert set(report.from_model) == {"Delta_R_eta", "Delta_R_o", "Delta_R_xi"}


MISTAKES = [
    # (line starts with, old, new, quantity, kind)
    ("dot(Delta_V_xi)", "a_eta*alpha_z", "a_xi*alpha_z", "alpha_z", "wrong coefficient"),
    ("Delta_g_xi", "R_E*u31*Delta_u11", "R_E*u31*Delta_u21", "delta_u11 -> delta_u21",
     "wrong variable"),
    ("dot(Delta_V_xi)", "- a_zeta*alpha_y", "+ a_zeta*alpha_y", "alpha_y", "sign error"),
    ("dot(Delta_V_eta)", "a_zeta*alpha_x", "2*a_zeta*alpha_x", "alpha_x", "wrong coefficient"),
    ("dot(alpha_x)", "omega_zeta*alpha_y", "omega_zeta*alpha_x", "alpha_y -> alpha_x",
     "wrong variable"),
    ("dot(alpha_z)", " + omega_dp", "", "omega_dp", "missing term"),
    ("Delta_omega_rel_eta", "- U*Delta_u21", "- U*Delta_u21 + U*Delta_u31", "delta_u31",
     "extra term"),
    ("Delta_phi", "Delta_u31/cos(phi)", "Delta_u31/cos(phi) + phi", "(none)",
     "not an error quantity"),
]


@pytest.mark.parametrize(("start", "old", "new", "quantity", "kind"), MISTAKES)
def test_injected_mistakes_are_found_and_classed(start, old, new, quantity, kind):
    line = line_of(CORRECT, start)
    lines = CORRECT.splitlines()
    assert old in lines[line - 1]
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    report = check("\n".join(lines))
    (result,) = results_at(report, line)
    assert result.status == "mistake"
    found = {(f.quantity, f.kind, f.severity) for f in result.findings}
    assert (quantity, kind, "mistake") in found, found
    assert report.exit_status == 1
    # a line that does not use the changed one still agrees
    assert results_at(report, line_of(CORRECT, "Delta_u33"))[0].status == "agrees"


def test_sizes_are_relative_to_the_largest_term():
    """Sign error on the largest term: twice its size; doubled term: half the largest."""
    sign = check(CORRECT.replace("- a_zeta*alpha_y", "+ a_zeta*alpha_y"))
    (f,) = [f for r in results_at(sign, line_of(CORRECT, "dot(Delta_V_xi)"))
            for f in r.findings]
    assert f.size == pytest.approx(2.0, rel=1e-12)
    double = check(CORRECT.replace("+ a_zeta*alpha_x", "+ 2*a_zeta*alpha_x"))
    (f,) = [f for r in results_at(double, line_of(CORRECT, "dot(Delta_V_eta)"))
            for f in r.findings]
    assert f.size == pytest.approx(0.5, rel=1e-12)
    assert f.detail == "hand/model = 2 at every point"


def test_small_deliberate_drops_pass_as_dropped_small_terms():
    # the vertical-velocity part of ΔW and the ΔR_E part of Δg' left out of ΔV̇_ξ
    dropped = CORRECT.replace(
        "dot(Delta_V_xi) = a_eta*alpha_z - a_zeta*alpha_y - Delta_W_xi + Delta_g_xi + Delta_a",
        "dot(Delta_V_xi) = a_eta*alpha_z - a_zeta*alpha_y + omega_zeta*Delta_V_eta "
        "+ V_eta*Delta_omega_zeta + U**2*R_E*u11*Delta_u31 + U**2*R_E*u31*Delta_u11 + Delta_a")
    assert dropped != CORRECT
    report = check(dropped)
    (result,) = results_at(report, line_of(CORRECT, "dot(Delta_V_xi)"))
    assert result.status == "agrees up to dropped small terms"
    assert result.findings and all(f.severity == "dropped small term" for f in result.findings)
    assert max(f.size for f in result.findings) < 1e-3
    assert report.exit_status == 0
    # a threshold below their size makes them mistakes
    strict = check(dropped, threshold=1e-7)
    assert strict.exit_status == 1


# -- the manual's printed equations ------------------------------------------------------
@pytest.fixture(scope="module")
def manual_reports():
    from ins_errors.checker.compare import check_hand_file

    return (check_hand_file(MANUAL / "equations.txt"),
            check_hand_file(MANUAL / "equations.tex"))


def test_latex_and_text_forms_give_the_same_report(manual_reports):
    text, latex = (to_json(r) for r in manual_reports)
    assert (text.pop("file"), latex.pop("file")) == ("equations.txt", "equations.tex")
    assert (text.pop("format"), latex.pop("format")) == ("text", "latex")
    for data in (text, latex):  # LaTeX lines start with $$: columns differ
        for equation in data["equations"]:
            equation.pop("column")
    assert text == latex
    md_text, md_latex = (to_markdown(r).splitlines() for r in manual_reports)
    differing = [i for i, (a, b) in enumerate(zip(md_text, md_latex, strict=True)) if a != b]
    assert len(differing) <= 2  # the title and the summary line name the file


def _finding(report, line, quantity, form=0):
    (result,) = [r for r in results_at(report, line) if r.form == form]
    return {f.quantity: f for f in result.findings}.get(quantity), result


def test_manual_printed_d_is_twice_the_radius_derivative(manual_reports):
    """Independent check: printed D vs a finite difference of R_E(φ) = (a+h)/√(1−e² sin²φ)."""
    a, e2, h, phi, step = 6_378_245.0, 0.0066934216, 0.0, np.radians(50.0), 1e-6
    r_e = lambda p: (a + h) / np.sqrt(1 - e2 * np.sin(p) ** 2)  # noqa: E731
    derivative = (r_e(phi + step) - r_e(phi - step)) / (2 * step)
    printed_d = (a + h) * e2 * np.sin(2 * phi) / (1 - e2 * np.sin(phi) ** 2) ** 1.5
    assert printed_d / derivative == pytest.approx(2.0, rel=1e-6)
    text, _ = manual_reports
    finding, result = _finding(text, line_of(MANUAL.joinpath("equations.txt").read_text(),
                                             "Delta_R_E"), "delta_u31")
    assert result.target == "intermediate R_E"
    assert finding.kind == "wrong coefficient" and finding.severity == "mistake"
    assert finding.detail == "hand/model = 2 at every point"


def test_manual_findings(manual_reports):
    text, _ = manual_reports
    source = MANUAL.joinpath("equations.txt").read_text().splitlines()
    lines = {i: s for i, s in enumerate(source, 1)}

    def line(start, after=0):
        return next(i for i, s in lines.items() if i > after and s.startswith(start))

    expanded = line("@section Error equations (expanded form)")
    # a_ξ α_z printed where a_η α_z belongs, only in the expanded listing
    finding, _ = _finding(text, line("dot(Delta_V_xi)", expanded), "alpha_z")
    assert (finding.kind, finding.severity, finding.hand, finding.model) == (
        "wrong coefficient", "mistake", "a_xi", "a_eta")
    assert _finding(text, line("dot(Delta_V_xi)"), "alpha_z")[0] is None
    # Δλ = ... / (cos²φ cos 2λ): the second printed form is wrong, the first right
    lam = line("Delta_lam", expanded)
    assert _finding(text, lam, "delta_u32", form=0)[1].status == "agrees"
    assert _finding(text, lam, "delta_u32", form=1)[0].severity == "mistake"
    # the expanded v_E is printed without Δ
    assert _finding(text, line("v_E ="), "(left-hand side)")[0].kind == \
        "left-hand side without Δ"
    # ΔW = W̃ − W restates the quantity; D and E are the hand's own helpers
    assert results_at(text, line("Delta_W_xi"))[0].status == "tautology"
    assert results_at(text, line("D ="))[0].status == "hand-only definition"
    assert any(u.startswith("E (line") for u in text.unused)
    # platform equations of the real-work section are right
    assert all(r.status == "agrees" for r in results_at(text, line("dot(alpha_y)")))
    assert text.exit_status == 1 and not text.problems


def test_threshold_moves_the_deliberate_r_drops():
    """The expanded Δu̇11 drops the ΔR terms of Δω: a few 1e-3 of its largest term."""
    source = MANUAL.joinpath("equations.txt").read_text().splitlines()
    printed = next(s for s in source[50:] if s.startswith("dot(Delta_u11)"))
    default, loose = check(printed), check(printed, threshold=1e-2)
    sizes = [f.size for f in default.results[0].findings]
    assert all(1e-4 < s < 1e-2 for s in sizes) and max(sizes) > 1e-3
    assert default.results[0].status == "mistake"
    assert loose.results[0].status == "agrees up to dropped small terms"


# -- bad input ---------------------------------------------------------------------------
BAD = """\
dot(alpha_z) = -omega_xi*alpha_y + omega_eta*alpha_x + U*Delta_u31 + omega_dp
dot(alpha_x) = -omega_eta*alpha_z + omega_zeta*alpha_y + Delta_omega_xj + omega_dp
dot(alpha_y) = omega_xi*alpha_z +* 2
dot(Delta_V_zeta) = a_zeta*alpha_x
Delta_omega_zeta = U*Delta_u31
Delta_omega_zeta = U*Delta_u31
dot(Delta_V_xi) = a_eta*alpha_z + a_zeta*alpha_y + Delta_a
Delta_u11 = Delta_u21
"""


def test_bad_input_is_reported_and_everything_else_checked():
    report = check(BAD)
    problems = {p.line: p for p in report.problems}
    assert set(problems) == {2, 3, 4, 6, 8}
    assert "unknown symbol 'Delta_omega_xj'" in problems[2].message
    assert "did you mean 'Delta_omega_xi'" in problems[2].message
    assert problems[2].column == BAD.splitlines()[1].index("Delta_omega_xj") + 1
    assert problems[3].column == BAD.splitlines()[2].rindex("*") + 1
    assert "V_zeta is not a state" in problems[4].message
    assert "duplicate definition of Delta_omega_zeta (first at line 5)" in problems[6].message
    assert "is an error state" in problems[8].message
    status = {r.equation.line: r.status for r in report.results}
    assert status[1] == "agrees"
    assert status[5] == status[6] == "agrees"  # the duplicate is still checked on its own
    assert status[7] == "mistake"
    assert report.exit_status == 2
    text = to_terminal(report)
    assert "input: line 2, column" in text and "5 input problems" in text


def test_cli_exit_status_report_and_json(tmp_path, capsys):
    good, bad = tmp_path / "good.txt", tmp_path / "bad.txt"
    good.write_text(CORRECT)
    bad.write_text(CORRECT.replace("- a_zeta*alpha_y", "+ a_zeta*alpha_y"))
    assert main(["check", "orthodromic", str(good)]) == 0
    assert "0 with mistakes" in capsys.readouterr().out
    out = tmp_path / "report.md"
    assert main(["check", "orthodromic", str(bad), "--report", str(out)]) == 1
    assert "sign error" in capsys.readouterr().out
    assert "| sign error | 2 |" in out.read_text()
    assert main(["check", "orthodromic", str(bad), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["exit_status"] == 1 and data["summary"]["mistakes"] == 1
    latex = tmp_path / "eq.tex"
    latex.write_text(r"\dot{\alpha}_z = -\omega_\xi \alpha_y + \omega_\eta \alpha_x "
                     r"+ U \Delta u_{31} + \omega_{dp}" "\n")
    assert main(["check", "orthodromic", str(latex)]) == 0
    capsys.readouterr()


@pytest.mark.parametrize(("args", "message"), [
    (["check", "orthodromic", "no/such/file.txt"], "not found"),
    (["check", "orthodromc", "x.txt"], "did you mean 'orthodromic'"),
    (["check", "orthodromic", "x.txt", "--threshold", "5"], "threshold must be between"),
])
def test_cli_bad_arguments_are_one_line_errors(args, message, capsys, tmp_path):
    (tmp_path / "x.txt").write_text("dot(alpha_z) = omega_dp\n")
    args = [str(tmp_path / a) if a == "x.txt" else a for a in args]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and message in err


def test_mapping_file_lets_a_hand_symbol_stand_for_model_sources(tmp_path, capsys):
    mapping = tmp_path / "map.txt"
    mapping.write_text("@source b_acc = accel_bias_x, accel_bias_y\n@alias Rx = 1/inv_R_xi\n")
    hand = tmp_path / "h.txt"
    hand.write_text("dot(Delta_V_eta) = -a_xi*alpha_z + a_zeta*alpha_x - Delta_W_eta "
                    "+ Delta_g_eta + b_acc\n"
                    "Delta_omega_eta = Delta_V_xi/Rx + Delta_V_eta/R_o - V_xi/Rx**2*Delta_Rx "
                    "- V_eta/R_o**2*Delta_R_o\n")
    assert main(["check", "orthodromic", str(hand), "--mapping", str(mapping)]) == 0
    capsys.readouterr()
    mapping.write_text("@source b_acc = accel_bias_q\n")
    assert main(["check", "orthodromic", str(hand), "--mapping", str(mapping)]) == 2
    assert "unknown model error source 'accel_bias_q'" in capsys.readouterr().err


def test_reports_render_without_nan_and_mark_infinite_sizes(manual_reports):
    text, _ = manual_reports
    md = to_markdown(text, "a test")
    assert "nan" not in md.lower().replace("finance", "")
    assert "| — |" in md  # the left-hand side finding has no finite size
    assert all(f.size > 0 and (math.isinf(f.size) or f.size < 10) for _, f in text.findings)


def test_ideal_definitions_are_checked_by_value():
    report = check("R_E = (a + h)/sqrt(1 - e**2*sin(phi)**2)\n"
                   "R_N = a*(1 - e**2)/(1 - e**2*sin(phi)**2)**(3/2)\n")
    good, bad = report.results
    assert (good.target, good.status) == ("ideal value of R_E", "agrees")
    (finding,) = bad.findings
    assert finding.kind == "wrong definition" and finding.severity == "mistake"
    # the height left out: h/a at the 10 km cruise points
    assert finding.size == pytest.approx(10_000 / (6_378_245 + 10_000), rel=1e-6)


def test_variation_of_an_unknown_quantity_is_an_input_problem():
    report = check("Delta_omega_xj = Delta_V_xi/R_xi\nD = 2*a\nDelta_D = 0\n")
    (problem,) = report.problems
    assert problem.line == 1 and "did you mean 'omega_xi'" in problem.message
    assert report.results[2].status == "hand-only definition"  # variation of a helper
    assert report.exit_status == 2


def test_bad_latex_input_names_line_and_column():
    lines = [r"\dot{\alpha}_x = -\omega_\eta \alpha_z + \omega_\zeta \alpha_y "
             r"+ \Delta\omega_{xj} + \omega_{dp}",
             r"\dot{\alpha}_z = -\omega_\xi \alpha_y + \omega_\eta \alpha_x + U \Delta u_{31} "
             r"+ \omega_{dp}",
             r"\Delta \dot{V}_\zeta = a_\zeta \alpha_x",
             r"\Delta \dot{V}_\xi = a_\eta \alpha_z - \frac{a_\zeta \alpha_y"]
    report = check("\n".join(lines), latex=True)
    problems = {p.line: p for p in report.problems}
    assert set(problems) == {1, 3, 4}
    assert problems[1].column == lines[0].index(r"\Delta\omega_{xj}") + 1
    assert "did you mean 'Delta_omega_xi'" in problems[1].message
    assert "V_zeta is not a state" in problems[3].message
    assert problems[4].column == len(lines[3]) + 1  # the missing '}' at the end
    assert [r.status for r in report.results if r.equation.line == 2] == ["agrees"]


@pytest.mark.parametrize("rhs, message", [
    ("alpha_z**2 + omega_zeta*alpha_y", "not linear in the error quantity alpha_z"),
    ("sin(alpha_z)*omega_eta", "not linear in the error quantity alpha_z"),
    ("alpha_z*alpha_y", "not linear"),
    ("1/0*alpha_z", "not finite"),
])
def test_nonlinear_or_infinite_terms_are_input_problems(tmp_path, rhs, message, capsys):
    path = tmp_path / "bad.txt"
    path.write_text(f"dot(alpha_x) = {rhs}\nDelta_omega_zeta = U*Delta_u31\n", encoding="utf-8")
    assert main(["check", "orthodromic", str(path)]) == 2
    out = capsys.readouterr().out
    assert message in out and "Traceback" not in out
    assert "1 agree" in out  # the other equation is still checked
