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

import pytest

from ins_errors.checker.compare import check_hand
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import parse_hand_text
from ins_errors.checker.report import to_json, to_markdown, to_terminal
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
MANUAL = ROOT / "examples" / "manual_000"

CORRECT = (ROOT / "tests" / "data" / "hand_correct_orthodromic.txt").read_text()


def check(text: str, threshold: float = 1e-3, latex: bool = False):
    hand = parse_hand_text(text, default_notation("orthodromic"), latex=latex)
    return check_hand(hand, threshold=threshold, effects=False)


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
    # (line starts with, old, new, quantity, kind): the 8 corrupted copies
    ("dot(Delta_V_xi)", "a_eta*alpha_z", "a_xi*alpha_z", "alpha_z", "wrong symbol or index"),
    ("Delta_g_xi", "R_E*u31*Delta_u11", "R_E*u31*Delta_u21", "delta_u11 -> delta_u21",
     "wrong symbol or index"),
    ("dot(Delta_V_xi)", "- a_zeta*alpha_y", "+ a_zeta*alpha_y", "alpha_y", "wrong sign"),
    ("dot(Delta_V_eta)", "a_zeta*alpha_x", "2*a_zeta*alpha_x", "alpha_x", "wrong coefficient"),
    ("dot(alpha_x)", "omega_zeta*alpha_y", "omega_zeta*alpha_x", "alpha_y -> alpha_x",
     "wrong symbol or index"),
    ("dot(alpha_z)", " + omega_dp", "", "omega_dp", "omitted term"),
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
    found = {(f.quantity, f.kind, f.severity, f.role) for f in result.findings}
    assert (quantity, kind, "mistake", "root") in found, found
    assert report.exit_status == 1
    # a line that does not use the changed one still agrees
    assert results_at(report, line_of(CORRECT, "Delta_u33"))[0].status == "agrees"
    # lines that use the changed definition carry knock-on findings naming it as root
    root = f"line {line} {result.label}"
    for r, f in report.findings:
        if r is not result:
            assert f.role == "knock-on" and root in f.roots, (r.label, f)


def test_sizes_are_relative_to_the_largest_term():
    """Sizes are relative to the model's largest term: a sign error on it is twice its
    size, and doubling it is a difference as large as the term itself (the hand's doubled
    term does not set the scale)."""
    sign = check(CORRECT.replace("- a_zeta*alpha_y", "+ a_zeta*alpha_y"))
    (f,) = [f for r in results_at(sign, line_of(CORRECT, "dot(Delta_V_xi)"))
            for f in r.findings]
    assert f.size == pytest.approx(2.0, rel=1e-12)
    double = check(CORRECT.replace("+ a_zeta*alpha_x", "+ 2*a_zeta*alpha_x"))
    (f,) = [f for r in results_at(double, line_of(CORRECT, "dot(Delta_V_eta)"))
            for f in r.findings]
    assert f.size == pytest.approx(1.0, rel=1e-12)
    assert f.detail == "hand/model = 2 at every point: a factor 2 too many?"


def test_small_omissions_are_drops_but_small_wrong_terms_are_mistakes():
    # the small vertical-velocity parts of ΔW (all but V_ζ ΔV_ξ/R_ξ, which reaches 1.3e-3
    # of g α_y in a 10 m/s climb) and the ΔR_E part of Δg' left out of ΔV̇_ξ
    dropped = CORRECT.replace(
        "dot(Delta_V_xi) = a_eta*alpha_z - a_zeta*alpha_y - Delta_W_xi + Delta_g_xi + Delta_a",
        "dot(Delta_V_xi) = a_eta*alpha_z - a_zeta*alpha_y + omega_zeta*Delta_V_eta "
        "- V_zeta*Delta_V_xi/R_xi "
        "+ V_eta*Delta_omega_zeta + U**2*R_E*u11*Delta_u31 + U**2*R_E*u31*Delta_u11 + Delta_a")
    assert dropped != CORRECT
    report = check(dropped)
    (result,) = results_at(report, line_of(CORRECT, "dot(Delta_V_xi)"))
    assert result.status == "agrees up to dropped small terms"
    assert {(f.kind, f.severity) for f in result.findings} == {
        ("omitted term", "dropped small term")}
    assert max(f.size for f in result.findings) < 1e-3
    assert report.exit_status == 0
    # a threshold below their size makes them mistakes
    assert check(dropped, threshold=1e-7).exit_status == 1
    # a term present with a wrong index is a mistake whatever its size (below a loose
    # threshold the omissions above stay drops, this one is a small-effect mistake)
    index = CORRECT.replace("Delta_g_xi = U**2*u31*u11*Delta_R_E",
                            "Delta_g_xi = U**2*u31*u21*Delta_R_E")
    assert check(dropped, threshold=0.1).exit_status == 0
    report = check(index, threshold=0.1)
    (f,) = results_at(report, line_of(CORRECT, "Delta_g_xi"))[0].findings
    assert (f.kind, f.severity, f.role) == ("wrong symbol or index", "mistake, small effect",
                                            "root")
    assert f.size < 0.1 and f.detail == "u21 written where u11 belongs"
    assert report.exit_status == 1


def test_knock_on_of_a_definition_dropping_small_terms_is_a_dropped_small_term():
    """A definition that leaves out only small terms (Delta_W_xi without the V_ζ parts
    below 1e-3) is a drop, and so is what it does to the line using it: the knock-ons
    in ΔV̇_ξ (which, isolated, look like wrong coefficients of ΔV_η, ΔR_ξ, ...) are
    dropped small terms rooted in that definition, not small-effect mistakes."""
    text = (ROOT / "tests" / "data" / "hand_small_drop_in_definition_orthodromic.txt"
            ).read_text()
    report = check(text)
    (definition,) = results_at(report, line_of(text, "Delta_W_xi"))
    assert definition.status == "agrees up to dropped small terms"
    assert {(f.severity, f.role) for f in definition.findings} == {
        ("dropped small term", "root")}
    (use,) = results_at(report, line_of(text, "dot(Delta_V_xi)"))
    assert len(use.findings) >= 3
    root = f"line {line_of(text, 'Delta_W_xi')} Delta_W_xi"
    assert {(f.kind, f.severity, f.role, f.roots) for f in use.findings} == {
        ("omitted term", "dropped small term", "knock-on", (root,))}
    assert use.status == "agrees up to dropped small terms"
    assert report.exit_status == 0


def test_a_line_wrong_on_its_own_still_carries_the_knock_on_of_a_wrong_definition():
    """ΔV̇_ξ uses Δg'_ξ; with Δg'_ξ's Δu31 term doubled and ΔV̇_ξ adding a Δu31 term of
    its own, the Δu31 coefficient of ΔV̇_ξ is wrong twice over: the line's own finding
    (what stays with the right Δg'_ξ: its extra U² R_E Δu31) and a knock-on of Δg'_ξ (the
    doubled U² R_E u11 Δu31), sized by that part alone. Each alone is one finding."""
    g_line, v_line = line_of(CORRECT, "Delta_g_xi"), line_of(CORRECT, "dot(Delta_V_xi)")
    wrong_g = CORRECT.replace("+ U**2*R_E*u11*Delta_u31", "+ 2*U**2*R_E*u11*Delta_u31")
    own = "+ Delta_g_xi + Delta_a"
    both = wrong_g.replace(own, "+ Delta_g_xi + U**2*R_E*Delta_u31 + Delta_a")
    assert wrong_g != CORRECT and both != wrong_g
    root = f"line {g_line} Delta_g_xi"
    report = check(both)
    found = [(f.role, f.roots) for f in results_at(report, v_line)[0].findings
             if f.quantity == "delta_u31"]
    assert found == [("root", ()), ("knock-on", (root,))]
    part, _ = _finding(report, v_line, "delta_u31", role="knock-on")
    alone, _ = _finding(check(wrong_g), v_line, "delta_u31")
    assert (alone.role, alone.roots) == ("knock-on", (root,))
    # the knock-on part is what the doubled term adds, as when the line has nothing else
    assert part.size == pytest.approx(alone.size, rel=1e-9)
    assert part.kind == alone.kind and part.severity == alone.severity
    # the line's own part is what it has with the right Δg'_ξ
    mine, _ = _finding(report, v_line, "delta_u31", role="root")
    only, _ = _finding(check(CORRECT.replace(own, "+ Delta_g_xi + U**2*R_E*Delta_u31 "
                                                  "+ Delta_a")), v_line, "delta_u31")
    assert (mine.kind, mine.size) == (only.kind, pytest.approx(only.size, rel=1e-9))
    # the definition's own report lists the line among its knock-ons
    (g_result,) = results_at(report, g_line)
    assert [r.equation.line for r, _ in report.knock_ons(g_result)] == [v_line]


def test_magnitudes_follow_the_schuler_loop():
    """δV = R ω_s δθ with ω_s = √(g/R): the Schuler period is the textbook 84.4 min."""
    from ins_errors.checker.reference import schuler_magnitudes
    from ins_errors.models import definition

    sizes = schuler_magnitudes(definition("orthodromic"), "1e-4 rad")
    radius, g = 6_378_245.0, 9.81
    omega_s = math.sqrt(g / radius)
    assert 2 * math.pi / omega_s / 60 == pytest.approx(84.4, abs=0.1)
    assert sizes.of("m/s")[0] == pytest.approx(radius * omega_s * 1e-4, rel=1e-12)
    assert 0.78 < sizes.of("m/s")[0] < 0.80
    assert sizes.of("m")[0] == pytest.approx(radius * 1e-4)
    assert sizes.of("m/s**2")[0] == pytest.approx(g * 1e-4)
    assert "84.4 min" in sizes.origin
    tuned = schuler_magnitudes(definition("orthodromic"), "20 arcsec", {"m/s": "0.1 m/s"})
    assert tuned.of("rad")[0] == pytest.approx(math.radians(20 / 3600))
    assert tuned.of("m/s") == (pytest.approx(0.1), "0.1 m/s")


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


def _finding(report, line, quantity, form=0, label=None, role=None):
    """The finding of ``quantity`` at ``line`` (the line's own one first, unless ``role``
    asks for the knock-on part that may come with it)."""
    (result,) = [r for r in results_at(report, line) if r.form == form
                 and (label is None or r.equation.label == label)]
    found = [f for f in result.findings if f.quantity == quantity
             and (role is None or f.role == role)]
    return (found[0] if found else None), result


def _manual_line(start, after=0):
    source = MANUAL.joinpath("equations.txt").read_text().splitlines()
    return next(i for i, s in enumerate(source, 1) if i > after and s.startswith(start))


def _radius_derivatives():
    """dR_E/dφ and dR_N/dφ by SymPy differentiation of the textbook radii (not the model)."""
    import sympy as sp

    a, e2, h, phi = sp.symbols("a e2 h phi", positive=True)
    r_e = (a + h) / sp.sqrt(1 - e2 * sp.sin(phi) ** 2)
    r_n = a * (1 - e2) / (1 - e2 * sp.sin(phi) ** 2) ** sp.Rational(3, 2) + h
    values = {a: 6_378_245.0, e2: 0.0066934216, h: 0.0, phi: math.radians(50.0)}
    printed = (a + h) * e2 * sp.sin(2 * phi) / (1 - e2 * sp.sin(phi) ** 2) ** sp.Rational(3, 2)
    final = (a + h) * e2 * sp.sin(2 * phi) / (1 - e2 * sp.sin(phi) ** 2)
    return {name: float(expr.subs(values)) for name, expr in (
        ("dR_E", sp.diff(r_e, phi)), ("dR_N", sp.diff(r_n, phi)), ("D", printed),
        ("D_final", final), ("1-e2 sin2", 1 - e2 * sp.sin(phi) ** 2), ("1-e2", 1 - e2))}


def test_manual_d_factor_two_and_final_exponent(manual_reports):
    """D = 2 dR_E/dφ (SymPy differentiation here); the final D lacks the 3/2 exponent."""
    ref = _radius_derivatives()
    assert ref["D"] / ref["dR_E"] == pytest.approx(2.0, rel=1e-9)
    assert ref["D_final"] / ref["dR_E"] == pytest.approx(2 * math.sqrt(ref["1-e2 sin2"]))
    text, _ = manual_reports
    first, result = _finding(text, _manual_line("D ="), "(value)")
    assert result.target.startswith("value dR_E/dphi")
    assert (first.kind, first.severity, first.role) == ("wrong coefficient", "mistake", "root")
    assert first.detail.endswith("hand/model = 2 at every point")
    # D acts through Δg' on the velocity errors: a (small) change of the position error
    assert 0 < first.effect["position_24h"] < 100
    expanded = _manual_line("@section Error equations (expanded form)")
    final, _ = _finding(text, _manual_line("D =", expanded), "(value)", label="D")
    assert (final.kind, final.severity) == ("wrong exponent", "mistake")
    assert "exponent -1 where -3/2 belongs" in final.detail and "= 2 at every point" in final.detail
    # ΔR_E = D Δφ (both printed forms) and Δg' carry the factor 2 as knock-ons of D
    root = f"line {_manual_line('D =')} D"
    for start in ("Delta_R_E", "Delta_g_xi", "Delta_g_eta"):
        f, _ = _finding(text, _manual_line(start), "delta_u31")
        assert f.role == "knock-on" and f.roots == (root,), (start, f)
    f, _ = _finding(text, _manual_line("Delta_R_E"), "delta_u31")
    assert f.detail == "hand/model = 2 at every point: a factor 2 too many?"


def test_manual_findings(manual_reports):
    text, _ = manual_reports
    expanded = _manual_line("@section Error equations (expanded form)")
    # a_ξ α_z printed where a_η α_z belongs, only in the expanded listing
    for start, written, right in (("dot(Delta_V_xi)", "a_xi", "a_eta"),
                                  ("dot(Delta_V_eta)", "a_eta", "a_xi")):
        f, _ = _finding(text, _manual_line(start, expanded), "alpha_z")
        assert (f.kind, f.severity, f.hand, f.model) == (
            "wrong symbol or index", "mistake", f"-{right}" if False else written, right) or (
            f.kind, f.severity) == ("wrong symbol or index", "mistake")
        assert f.detail == f"{written} written where {right} belongs"
        assert _finding(text, _manual_line(start), "alpha_z")[0] is None
    # the gravity term of the final ΔV̇_ξ: u21 where u11 belongs, a small wrong term
    f, _ = _finding(text, _manual_line("dot(Delta_V_xi)", expanded), "delta_u31")
    assert (f.kind, f.severity, f.role) == ("wrong symbol or index", "mistake, small effect",
                                            "root")
    assert f.detail == "u21 written where u11 belongs" and f.size < 1e-3
    # ... and its D (the final one) is wrong too: a knock-on part of that coefficient,
    # the same as in ΔV̇_η, whose D term is printed identically (u21 in both)
    final_d = f"line {_manual_line('D =', expanded)} D"
    part, _ = _finding(text, _manual_line("dot(Delta_V_xi)", expanded), "delta_u31",
                       role="knock-on")
    eta, _ = _finding(text, _manual_line("dot(Delta_V_eta)", expanded), "delta_u31")
    assert part.roots == eta.roots == (final_d,) and eta.role == "knock-on"
    # ΔR_N = ΔR_E (1 − e²) is wrong even with the right ΔR_E: a root of its own, and it
    # carries D's factor 2 through ΔR_E besides
    ref = _radius_derivatives()
    assert abs(ref["1-e2"] * ref["dR_E"] / ref["dR_N"] - 1) > 0.5  # independent: ≈ 1/3
    f, _ = _finding(text, _manual_line("Delta_R_N"), "delta_u31")
    assert (f.severity, f.role) == ("mistake", "root")
    f, _ = _finding(text, _manual_line("Delta_R_N"), "delta_u31", role="knock-on")
    assert f.roots == (f"line {_manual_line('D =')} D",)
    # the expanded Δv_N writes that ΔR_N inline, D (1 − e²)/cos φ Δu31 with the final D:
    # its own mistake stays with the right D (the ≈ 1/3 above), D's part is a knock-on
    v_n = _manual_line("Delta_v_N", expanded)
    mine, _ = _finding(text, v_n, "delta_u31")
    part, _ = _finding(text, v_n, "delta_u31", role="knock-on")
    assert (mine.role, part.roots) == ("root", (final_d,))
    (d_result,) = [r for r in results_at(text, _manual_line("D =", expanded))
                   if r.equation.label == "D"]
    assert {r.equation.line for r, _ in text.knock_ons(d_result)} == {
        _manual_line(s, expanded) for s in ("dot(Delta_V_xi)", "dot(Delta_V_eta)",
                                            "Delta_v_N", "v_E =")}
    # Δλ = ... / (cos²φ cos 2λ): the second printed form is wrong, the first right
    lam = _manual_line("Delta_lam", expanded)
    assert _finding(text, lam, "delta_u32", form=0)[1].status == "agrees"
    f, _ = _finding(text, lam, "delta_u32", form=1)
    assert (f.kind, f.severity, f.detail) == ("wrong function", "mistake",
                                              "cos(2*lam) should not be there")
    # the expanded v_E is printed without Δ
    assert _finding(text, _manual_line("v_E ="), "(left-hand side)")[0].kind == \
        "left-hand side without Δ"
    # ΔW = W̃ − W restates the quantity; E is an unused helper
    assert results_at(text, _manual_line("Delta_W_xi"))[0].status == "tautology"
    assert any(u.startswith("E (line") for u in text.unused)
    # platform equations of the real-work section are right
    assert all(r.status == "agrees" for r in results_at(text, _manual_line("dot(alpha_y)")))
    assert text.exit_status == 1 and not text.problems


def test_manual_declared_drops_are_no_mistakes(manual_reports):
    text, _ = manual_reports
    assert text.declarations and not text.idle_declarations
    expanded = _manual_line("@section Error equations (expanded form)")
    for start in ("dot(alpha_x)", "dot(alpha_y)", "dot(Delta_u11)", "dot(Delta_u21)",
                  "dot(Delta_u31)", "dot(Delta_u12)", "dot(Delta_u22)", "dot(Delta_u32)"):
        (result,) = results_at(text, _manual_line(start, expanded))
        assert result.findings and {f.severity for f in result.findings} == {"declared drop"}
        assert result.status == "agrees up to declared drops"
    # the genuine mistakes, and nothing else, are roots
    roots = {(r.equation.line, f.quantity) for r, f in text.root_mistakes}
    line = _manual_line
    assert roots == {
        (line("D ="), "(value)"), (line("D =", expanded), "(value)"),
        (line("Delta_R_N"), "delta_u31"), (line("@alt Delta_R_N"), "delta_u31"),
        (line("dot(Delta_V_xi)", expanded), "alpha_z"),
        (line("dot(Delta_V_xi)", expanded), "delta_u31"),
        (line("dot(Delta_V_eta)", expanded), "alpha_z"),
        # one misprinted factor cos 2λ on the line: one root, its five quantities knock-ons
        (line("Delta_lam", expanded), "(line)"),
        (line("Delta_v_N", expanded), "delta_u31"), (line("v_E ="), "(left-hand side)"),
        # real work: the misprinted a_z row, the terms printed outside the step tau
        (line("a_z ="), "(value)"), (line("a_z ="), "alpha_x"), (line("a_z ="), "alpha_z"),
        (line("tilde(V_xi_k1)"), "(time step)"), (line("tilde(V_eta_k1)"), "(time step)")}


def test_manual_real_work_lines(manual_reports):
    """The printed a_z row is not the platform rotation's third row (a_zeta + a_xi*alpha_y
    - a_eta*alpha_x, see tests/test_hand_realwork.py); a_x and a_y are; the printed
    velocity updates add g' + Delta_a outside the step tau."""
    for report in manual_reports:
        assert [r.status for r in results_at(report, _manual_line("a_x ="))] == ["agrees"]
        assert [r.status for r in results_at(report, _manual_line("a_y ="))] == ["agrees"]
        f, result = _finding(report, _manual_line("a_z ="), "(value)")
        assert result.status == "mistake" and (f.kind, f.severity) == (
            "wrong symbol or index", "mistake")
        assert f.detail == "a_xi written where a_zeta belongs"
        for start, channel in (("tilde(V_xi_k1)", "xi"), ("tilde(V_eta_k1)", "eta")):
            f, _ = _finding(report, _manual_line(start), "(time step)",
                            label=f"tilde(V_{channel})")
            assert (f.kind, f.severity) == ("outside the time step", "mistake")
            assert f.hand == f"Delta_a + tilde(g_{channel})"
            # its first-order variation (read inside tau) carries only D's knock-on
            (varied,) = [r for r in results_at(report, _manual_line(start))
                         if r.target == f"error state delta_V_{channel}"]
            assert varied.findings and all(
                g.role == "knock-on" and any(x.endswith(" D") for x in g.roots)
                for g in varied.findings)


def test_report_reads_roots_then_knock_ons_then_drops(manual_reports):
    text, _ = manual_reports
    out = to_terminal(text)
    first_root = out.index("[root mistake]")
    assert first_root < out.index("[declared drops]")
    assert "from line" in out and "u21 written where u11 belongs" in out
    md = to_markdown(text)
    assert md.index("## Root mistakes") < md.index("## Declared drops")
    assert "Knock-on findings:" in md and "Schuler" in md
    # the equation-by-equation table names a knock-on's roots, so a line with its own
    # slip and a knock-on part in one term reads as two different findings
    row = next(r for r in md.splitlines()
               if r.startswith(f"| {_manual_line('dot(Delta_V_xi)', 55)} | `dot(delta_V_xi)` "
                               "| error state"))
    assert "(mistake, small effect, 1.1e-05)" in row
    assert f"8.9e-06, from line {_manual_line('D =', 55)} D)" in row


def test_unmagnified_velocities_turn_the_declared_drops_into_mistakes():
    """Without the declaration the dropped ΔR terms are small omissions at Schuler-
    consistent magnitudes; with 0.1 m/s beside 1e-4 rad they look like mistakes."""
    source = MANUAL.joinpath("equations.txt").read_text().splitlines()
    printed = next(s for s in source[55:] if s.startswith("dot(Delta_u11)"))
    schuler = check(printed)
    assert {(f.kind, f.severity) for f in schuler.results[0].findings} == {
        ("omitted term", "dropped small term")}
    assert schuler.exit_status == 0
    inconsistent = check("@magnitude m/s = 0.1 m/s\n" + printed)
    assert inconsistent.exit_status == 1


def test_empty_hand_file_is_an_input_error(tmp_path, capsys):
    for text in ("", "# only a comment\n@section nothing\n"):
        path = tmp_path / "empty.txt"
        path.write_text(text)
        assert main(["check", "orthodromic", str(path)]) == 2
        assert "no equations" in capsys.readouterr().err


def test_declaration_that_explains_nothing_is_reported():
    report = check("@neglect Delta_R_xi : nothing dropped here\n" + CORRECT)
    assert report.idle_declarations == ["line 1: Delta_R_xi"]
    assert report.exit_status == 0
    assert "declaration explains nothing" in to_terminal(report)


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
    assert "wrong sign" in capsys.readouterr().out
    assert "— wrong sign on `alpha_y` (mistake)" in out.read_text()
    assert main(["check", "orthodromic", str(bad), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["exit_status"] == 1 and data["summary"]["findings"]["mistakes"] == 1
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
    assert "size — at" in md  # the left-hand side finding has no finite size
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


def test_effect_of_an_omitted_bias_is_the_schuler_response():
    """Leaving Δa out of ΔV̇_ξ: after 1 h the position and tilt errors change by the
    textbook Schuler response to a bias b = g θ, b/ω_s² (1 − cos ω_s t) and
    (b/g)(1 − cos ω_s t), within the few per cent the Earth-rate coupling adds."""
    text = CORRECT.replace("- Delta_W_xi + Delta_g_xi + Delta_a", "- Delta_W_xi + Delta_g_xi")
    report = check_hand(parse_hand_text(text, default_notation("orthodromic")))
    ((_, finding),) = report.mistakes
    assert (finding.quantity, finding.kind) == ("Delta_a", "omitted term")
    radius, g, theta = 6_378_245.0, 9.81, 1e-4
    omega_s = math.sqrt(g / radius)
    swing = 1 - math.cos(omega_s * 3600.0)
    assert finding.effect["position_1h"] == pytest.approx(g * theta / omega_s**2 * swing,
                                                          rel=0.03)
    assert finding.effect["attitude_1h"] == pytest.approx(theta * swing, rel=0.03)
    # after 24 h the Foucault rate Ω = U sin φ has turned the oscillation between the two
    # channels: |δr| = (b/ω_s²)|1 − e^{−iΩt} cos ω_s t| ≤ 2b/ω_s² = 2Rθ (1276 m; 3 % for
    # the Earth-rate coupling and the ellipsoid's radii); measured 823 m
    assert 0.05 * g * theta / omega_s**2 < finding.effect["position_24h"] <= (
        2 * g * theta / omega_s**2 * 1.03)
    assert "effect: 1 h:" in to_terminal(report)
