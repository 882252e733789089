"""Reading hand-written error equations: SymPy text, LaTeX, directives, bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from ins_errors.checker.notation import ORTHODROMIC
from ins_errors.checker.parse import (
    DOT,
    TILDE,
    HandParseError,
    parse_hand_text,
    parse_latex_expression,
    read_hand_file,
)

ROOT = Path(__file__).resolve().parent.parent
MANUAL = ROOT / "examples" / "manual_000"
S = sp.Symbol


def one(text: str, latex: bool = False):
    hand = parse_hand_text(text, ORTHODROMIC, latex=latex)
    assert not hand.problems, hand.problems
    assert len(hand.equations) == 1
    return hand.equations[0]


def same(a: sp.Expr, b: sp.Expr) -> bool:
    return sp.expand(a - b) == 0


def test_text_spellings_and_derivatives():
    eq = one("Delta_V_xi_dot = w_xi_rel*Delta_u31 - cos(lambda)*e**2 + tilde(W_xi)")
    assert eq.lhs == DOT(S("Delta_V_xi"))
    expected = (S("omega_rel_xi") * S("Delta_u31") - sp.cos(S("lam")) * S("e") ** 2
                + TILDE(S("W_xi")))
    assert same(eq.forms[0], expected)
    assert one("dot(alpha_x) = omega_dp").lhs == DOT(S("alpha_x"))
    assert one("x = a^2").forms[0] == S("a") ** 2  # ^ is a power, as on paper


def test_chains_several_equations_sections_and_directives():
    hand = parse_hand_text(
        "# comment\n"
        "@alias R_big = 2*a\n"
        "@source bias = accel_bias_x, accel_bias_y\n"
        "A = B = C   # chain: two forms\n"
        "@section second\n"
        "x = 1; y = 2\n"
        "@alt x = 3\n", ORTHODROMIC)
    assert not hand.problems
    assert hand.notation.aliases == {"R_big": "2*a"}
    assert hand.notation.sources == {"bias": ("accel_bias_x", "accel_bias_y")}
    assert [e.forms for e in hand.equations] == [[S("B"), S("C")], [1], [2], [3]]
    assert [e.section for e in hand.equations] == [0, 1, 1, 1]
    assert hand.sections[1] == "second"
    assert [e.alternative for e in hand.equations] == [False, False, False, True]
    assert [e.line for e in hand.equations] == [4, 6, 6, 7]


@pytest.mark.parametrize(("latex", "text"), [
    (r"\Delta \dot{V}_\xi = a_\eta \alpha_z - a_\zeta \alpha_y - \Delta W_\xi^{nk} "
     r"+ \Delta g'_\xi + \Delta a;",
     "dot(Delta_V_xi) = a_eta*alpha_z - a_zeta*alpha_y - Delta_W_xi + Delta_g_xi + Delta_a"),
    (r"\dot{\alpha}_y = \omega_\xi \alpha_z - \omega_\zeta \alpha_x + \Delta\omega_\eta "
     r"+ \omega_{dp},",
     "dot(alpha_y) = omega_xi*alpha_z - omega_zeta*alpha_x + Delta_omega_eta + omega_dp"),
    (r"\Delta\omega'_{\xi} = \Delta\omega_{\xi} - \Delta U_{\xi},",
     "Delta_omega_rel_xi = Delta_omega_xi - Delta_U_xi"),
    (r"$$D = \frac{(a+h)e^2 \sin 2\varphi}{(1-e^2 \sin^2 \varphi)^{\frac{3}{2}}}$$",
     "D = (a + h)*e**2*sin(2*phi)/(1 - e**2*sin(phi)**2)**(3/2)"),
    (r"\Delta\lambda = -\frac{1}{\cos^2\varphi \cos 2\lambda} (u_{33}\Delta u_{32} "
     r"- u_{32}\Delta u_{33}),",
     "Delta_lam = -1/(cos(phi)**2*cos(2*lam))*(u33*Delta_u32 - u32*Delta_u33)"),
    (r"x = \operatorname{tg}\varphi \cdot \left[ R_\xi^{-1} \right] + \sqrt{1 - u_{31}^2}",
     "x = tan(phi)*R_xi**(-1) + sqrt(1 - u31**2)"),
    (r"\Delta W_\xi^{nk} = \widetilde{W}_\xi^{nk} - W_\xi^{nk}",
     "Delta_W_xi = tilde(W_xi) - W_xi"),
    (r"\Delta\omega_{\zeta} = U \cos \varphi \Delta\varphi \quad \text{for orthodromic}",
     "Delta_omega_zeta = U*cos(phi)*Delta_phi"),
])
def test_latex_notation_reads_like_the_text_form(latex, text):
    a, b = one(latex, latex=True), one(text)
    assert a.lhs == b.lhs
    assert all(same(x, y) for x, y in zip(a.forms, b.forms, strict=True))


def test_latex_quad_separates_equations_and_keeps_notes():
    hand = parse_hand_text(r"$$\Delta U_{\xi} = U \Delta u_{11}, \quad \Delta U_{\eta} = "
                           r"U \Delta u_{21} \quad \text{(components)}$$", ORTHODROMIC, latex=True)
    assert [e.lhs for e in hand.equations] == [S("Delta_U_xi"), S("Delta_U_eta")]
    assert hand.equations[1].note == "(components)"


def test_both_manual_transcriptions_hold_the_same_equations_line_for_line():
    text = read_hand_file(MANUAL / "equations.txt", ORTHODROMIC)
    latex = read_hand_file(MANUAL / "equations.tex", ORTHODROMIC)
    assert latex.format == "latex" and text.format == "text"
    assert not text.problems and not latex.problems
    assert len(text.equations) == len(latex.equations) >= 55
    assert text.sections == latex.sections
    for a, b in zip(text.equations, latex.equations, strict=True):
        assert (a.line, a.section, a.lhs, a.alternative) == (b.line, b.section, b.lhs,
                                                               b.alternative)
        assert all(same(x, y) for x, y in zip(a.forms, b.forms, strict=True)), a.line


def test_fast_latex_parser_agrees_with_sympy_parse_latex():
    """The LALR arithmetic parser and SymPy's parse_latex (lark) read the same thing."""
    pytest.importorskip("lark")
    samples = [
        r"-\frac{\Delta V_{\eta}}{R_{\eta}} - \frac{\Delta V_{\xi}}{R_o} "
        r"+ \frac{V_{\eta}}{R_{\eta}^2} \Delta R_{\eta}",
        r"u_{11} \left(\frac{\Delta V_\xi}{R_\xi} - U \Delta u_{21} \right) "
        r"- u_{21} \left(- U \Delta u_{11} \right)^{2}",
        r"\frac{3}{2} R_N e^2 \sin 2\varphi \Delta \varphi - 5 \pi",
    ]
    for sample in samples:
        fast, _ = parse_latex_expression(sample, ORTHODROMIC, backend="lalr")
        slow, _ = parse_latex_expression(sample, ORTHODROMIC, backend="sympy")
        assert same(fast, slow), sample


# -- bad input ---------------------------------------------------------------------------
def test_unparsable_text_line_gives_line_and_column_and_other_lines_survive():
    hand = parse_hand_text("a = 1\n\ndot(alpha_x) = 1 +* 2\nb = 2\n", ORTHODROMIC)
    assert [e.lhs for e in hand.equations] == [S("a"), S("b")]
    (problem,) = hand.problems
    assert (problem.line, problem.column) == (3, 19)
    assert str(problem).startswith("line 3, column 19: cannot parse")


def test_a_long_unparsable_line_is_quoted_around_its_column_only():
    # a generated sum of 200 terms with a slip at its end: the message quoted all 3300
    # characters of it
    body = " + ".join(f"a{i}*delta_V_xi" for i in range(200))
    hand = parse_hand_text(f"dot(alpha_x) = {body} +* 3\n", ORTHODROMIC)
    (problem,) = hand.problems
    text = str(problem)
    assert problem.column == len("dot(alpha_x) = ") + len(body) + 3
    assert len(text) < 160 and "+* 3'" in text and "'…" in text, text


def test_latex_errors_name_the_place():
    hand = parse_hand_text("x = 1\n" r"y = \frac{a}{b" "\n" r"z = a_\xi \foo" "\n", ORTHODROMIC,
                           latex=True)
    assert [e.lhs for e in hand.equations] == [S("x")]
    assert [(p.line, p.column) for p in hand.problems] == [(2, 15), (3, 11)]
    assert "expected '}'" in hand.problems[0].message
    assert r"unsupported LaTeX command \foo" in hand.problems[1].message


def test_a_latex_neglect_item_says_directives_are_text():
    """In a LaTeX file `@neglect \\Delta R_N` gave Python's tokenizer message
    ("unexpected character after line continuation character")."""
    hand = parse_hand_text("@neglect \\Delta R_\\xi : radii held fixed\n"
                           r"\dot{\Delta u_{11}} = 0" "\n", ORTHODROMIC, latex=True)
    (problem,) = hand.problems
    assert problem.line == 1
    assert "@neglect items are written as text, also in a LaTeX file" in problem.message
    assert "continuation" not in problem.message


@pytest.mark.parametrize(("text", "message"), [
    ("a + b = c", "left-hand side 'a + b' must be one quantity"),
    ("x = just an expression", "cannot parse"),
    ("x + 1", "no '=' in 'x + 1'"),
    ("@frobnicate x", "unknown directive '@frobnicate'"),
    ("@source s = ", "@source needs"),
    ("x = foo.bar", "attribute access"),
    ("x = gamma(2)", "unknown function 'gamma'"),
])
def test_bad_lines_are_reported_not_raised(text, message):
    hand = parse_hand_text(text, ORTHODROMIC)
    assert not hand.equations
    assert len(hand.problems) == 1 and message in hand.problems[0].message


@pytest.mark.parametrize(("text", "latex", "column", "message"), [
    # a product of numbers beyond a double (SymPy made it, the check then said only
    # "a coefficient is not finite")
    ("x = -g*psi + 1e300*1e300*b", False, 14, "1e300*1e300 is about 1e+600, too large"),
    ("x = -g*psi + " + "9" * 400 + "*b", False, 14, "is too large (numbers of a hand file"),
    ("x = 2**(-10**6)*b", False, 5, "2**(-10**6) is about 10^(-3.01e+05), too small"),
    ("x = 10^(10^3)*b", False, 5, "10**(10**3) is about 1e+1000, too large"),
    # a huge power of a quantity (SymPy would expand or differentiate it)
    ("x = (a + b)**(10**10)", False, 5, "the exponent of (a + b)**(10**10) is too large"),
    ("x = a**-101", False, 5, "the exponent of a**-101 is too large (at most 100"),
    (r"x = 10^{400} b", True, None, "10^400 is about 1e+400, too large to compute"),
])
def test_numbers_too_large_to_compute_are_refused_with_their_place(text, latex, column,
                                                                   message):
    hand = parse_hand_text(text, ORTHODROMIC, latex=latex)
    assert not hand.equations
    (problem,) = hand.problems
    assert problem.line == 1 and message in problem.message, problem
    if column is not None:
        assert problem.column == column


def test_powers_are_sized_before_sympy_computes_them():
    """`10**(10**10)` (and LaTeX `10^{10^{10}}`, whose exponent group is computed first)
    kept `check` busy computing an integer of ten billion digits: it never returned.
    In a child process, so that the old behaviour fails by its time limit."""
    code = (
        "import json\n"
        "from ins_errors.checker.notation import ORTHODROMIC\n"
        "from ins_errors.checker.parse import parse_hand_text\n"
        "text = parse_hand_text('x = 1\\ny = -g*psi + 10**(10**10)*b', ORTHODROMIC)\n"
        "tex = parse_hand_text('y = -g \\\\psi + 10^{10^{10}} b', ORTHODROMIC, latex=True)\n"
        "print(json.dumps([str(p) for p in text.problems + tex.problems]))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, cwd=ROOT, check=True)
    text, tex = json.loads(done.stdout)
    assert text.startswith("line 2, column 14: 10**(10**10) is about 10^(1e+10), too large")
    assert tex.startswith("line 1") and "10^10000000000 is about 10^(1e+10)" in tex


def test_an_expression_too_long_to_read_is_a_problem_of_its_line():
    """A sum of 5000 terms on one line was a RecursionError traceback (Python's parser);
    a LaTeX line nested 3000 groups deep likewise (the converter)."""
    long_sum = "x = 1\ny = " + " + ".join(["g*psi"] * 5000) + "\nz = 2\n"
    hand = parse_hand_text(long_sum, ORTHODROMIC)
    assert [e.lhs for e in hand.equations] == [S("x"), S("z")]
    (problem,) = hand.problems
    assert problem.line == 2 and "too long or too deeply nested to read" in problem.message
    deep = "x = " + "{" * 3000 + "a" + "}" * 3000 + "\n"
    (problem,) = parse_hand_text(deep, ORTHODROMIC, latex=True).problems
    assert problem.line == 1 and "too long or too deeply nested to read" in problem.message


def test_missing_file_is_one_clear_error(tmp_path):
    with pytest.raises(HandParseError, match="not found"):
        read_hand_file(tmp_path / "nope.txt", ORTHODROMIC)
