"""``ins-errors check MODEL FILE --report FILE.tex``: the findings as a LaTeX fragment.

The coefficients are read back from the LaTeX with SymPy's own ``parse_latex`` (lark
backend) and compared with the findings' SymPy text; the structure and the escaping are
checked by a small LaTeX scanner written here, not by the module's escaper; the counts
are those of ``--json``.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import pytest
import sympy as sp

from ins_errors.checker.compare import check_hand_file
from ins_errors.checker.report import ordered
from ins_errors.checker.report_latex import LatexNames, to_latex
from ins_errors.cli import main
from ins_errors.model_lookup import definition_of, resolve

ROOT = Path(__file__).resolve().parent.parent
MANUAL = ROOT / "examples" / "manual_000" / "equations.tex"
SPECIALS = "_ % & # $ { } ~ ^ \\"


@pytest.fixture(scope="module")
def manual():
    definition = definition_of(resolve("orthodromic"))
    report = check_hand_file(MANUAL, model=definition)
    names = LatexNames(definition)
    return report, names, to_latex(report, definition, names=names)


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


# -- (1) every coefficient reads back as the finding's ------------------------------------

_FUNCTIONS = {name: getattr(sp, name) for name in
              ("sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "exp", "log",
               "sqrt", "Abs")}


def _sympy_text(text: str) -> sp.Expr:
    """The finding's text with every name a plain Symbol (``tilde(X)`` one symbol)."""
    local = {name: sp.Symbol(name) for name in re.findall(r"[A-Za-z_]\w*", text)}
    local.update(_FUNCTIONS)
    local["pi"] = sp.pi
    local["tilde"] = lambda s: sp.Symbol(f"tilde({s.name})")
    return sp.parse_expr(text, local_dict=local, global_dict={
        "Integer": sp.Integer, "Float": sp.Float, "Rational": sp.Rational,
        "Symbol": sp.Symbol, "Function": sp.Function})


def _longest_whole_prefix(text: str) -> sp.Expr:
    """A shortened text (``... + c/(u11**2 +...``): the longest prefix ending before a
    `` + `` or `` - `` that reads."""
    body = text[:-3]
    for match in sorted(re.finditer(r" [+-] ", body), key=lambda m: -m.start()):
        try:
            return _sympy_text(body[:match.start()])
        except (SyntaxError, TypeError, ValueError, sp.SympifyError):
            continue
    raise AssertionError(f"no whole term in {text!r}")


def _math_cells(tex: str) -> list[str]:
    return re.findall(r"\\\((.*?)\\\)", tex)


def _read_cell(cell: str, used: dict[str, str]) -> sp.Expr:
    from sympy.parsing.latex import parse_latex

    placeholders = {}
    spelled = {}
    for k, (name, latex) in enumerate(sorted(used.items())):
        code = "".join("abcdefghij"[int(c)] for c in str(k))
        placeholders[latex] = f"Q_{{{code}}}"
        spelled[sp.Symbol(f"Q_{{{code}}}")] = sp.Symbol(name)
    pattern = re.compile("|".join(re.escape(s) for s in sorted(placeholders, key=len,
                                                                 reverse=True)))
    text = pattern.sub(lambda m: placeholders[m.group()], cell)
    return parse_latex(text, backend="lark").xreplace(spelled)


def test_every_coefficient_reads_back_as_the_findings(manual):
    report, names, tex = manual
    cells = _math_cells(tex)
    texts = [c for _, pairs in ordered(report) for _, f in pairs for c in (f.hand, f.model)]
    assert len(cells) == len(texts) > 100
    shortened = 0
    covered: set[sp.Symbol] = set()
    read = 0
    for cell, text in dict.fromkeys(zip(cells, texts, strict=True)):
        # parse_latex is slow (about 0.3 s a cell): every shortened cell is read back,
        # the others where they bring a symbol no cell read so far had, so every name of
        # the model's notation the report uses is read back at least once
        if text.endswith("..."):
            shortened += 1
            assert cell.endswith(r" + \dots"), cell
            cell, expected = cell[:-len(r" + \dots")], _longest_whole_prefix(text)
        else:
            expected = _sympy_text(text)
            if expected.free_symbols <= covered:
                continue
        covered |= expected.free_symbols
        got = _read_cell(cell, names.used)
        assert sp.simplify(got - expected) == 0, (text, cell)
        read += 1
    assert shortened  # the manual's v_N/v_E lines have coefficients the report shortens
    assert read >= 10


def test_terminal_legend_names_the_points_and_says_what_size_and_effect_are(manual):
    """The terminal report of the manual printed "(cruise 0 km)", "cruise 2000 km",
    "source omega_dp", "< 4e-11″" and a "size" column with none of them defined (the
    Markdown report had the points and the size, the effects nowhere). Now a legend under
    the typical magnitudes says what size and effect are, in the words of the Markdown
    and LaTeX reports' prose, and defines every reference point a finding names, as the
    reports' table of reference points does."""
    from ins_errors.checker.report import to_markdown, to_terminal

    report, _names, tex = manual
    lines = to_terminal(report).splitlines()
    markdown = to_markdown(report)
    plain = re.sub(r"\*\*|\*|`", "", markdown)
    size = next(line for line in lines if line.startswith("size (column): "))
    effect = next(line for line in lines if line.startswith("effect (under a finding): "))
    for line in (size, effect):
        words = line.split(": ", 1)[1]
        assert words in plain  # the same sentence as the reports' prose
        assert words[:40] in re.sub(r"\\(emph|texttt|textbf)\{([^}]*)\}", r"\2", tex)
    assert "source X" in effect and "initial X" in effect and "< x" in effect
    points = next(line for line in lines if line.startswith("reference points: "))
    defined = dict(part.split(" = ", 1)
                   for part in points.removeprefix("reference points: ").split("; "))
    used = {f.effect[key] for _, f in report.findings for key in ("point", "largest_point")
            if f.effect.get(key)} | {f.point for _, f in report.findings if f.point}
    used -= {"every step", "—"}  # (a time-step finding; a finding with no size)
    assert {"static base", "cruise 0 km", "cruise 2000 km", "climb"} <= used
    for label in used:
        assert f"| {label} | {defined[label]} |" in markdown, label
    assert "great-circle cruise" in defined["cruise 0 km"]
    # the legend comes before the table it explains, once
    assert lines.index(points) < lines.index(next(x for x in lines if x.startswith("line ")))
    assert sum(x.startswith("size (column): ") for x in lines) == 1


def test_the_model_notation_is_used(manual):
    _, names, tex = manual
    # the lab manual's symbols, as the orthodromic model spells them
    assert names.used["delta_u31"] == r"{\Delta u_{31}}"
    assert names.used["phi"] == r"{\varphi}"
    assert r"{\omega'_\xi}" in tex and r"{e^{2}}" in tex
    # E, a helper of the file, is a symbol, not Euler's number
    assert sp.Symbol("E") == _sympy_text("E")


# -- (2) structure and escaping ------------------------------------------------------------

_DECODE = {r"\%": "%", r"\_": "_", r"\&": "&", r"\#": "#", r"\$": "$", r"\{": "{",
           r"\}": "}", r"\textbackslash": "\\", r"\textasciitilde": "~",
           r"\textasciicircum": "^"}


def _scan(tex: str) -> str:
    """Walk the LaTeX: braces, math shifts, \\begin/\\end and \\( \\) balance, specials
    appear only where they mean something; return the text of text mode, decoded."""
    depth, math, envs, inline = 0, False, [], False
    decoded = []
    body = [line for line in tex.splitlines() if not line.startswith("%")]
    text = "\n".join(body)
    i = 0
    while i < len(text):
        char = text[i]
        if char == "\\":
            word = re.match(r"\\([A-Za-z]+|.)", text[i:]).group()
            i += len(word)
            if word in (r"\begin", r"\end"):
                name = re.match(r"\{(\w+\*?)\}", text[i:]).group(1)
                if word == r"\begin":
                    envs.append(name)
                else:
                    assert envs and envs.pop() == name, name
            elif word == r"\ensuremath":  # mathematics in text: one balanced group
                assert text[i] == "{"
                level = 0
                for j in range(i, len(text)):
                    level += {"{": 1, "}": -1}.get(text[j], 0)
                    if level == 0:
                        break
                assert level == 0 and "$" not in text[i:j]
                i = j + 1
            elif word == r"\(":
                assert not inline and not math
                inline = True
            elif word == r"\)":
                assert inline
                inline = False
            elif not (math or inline) and word in _DECODE:
                decoded.append(_DECODE[word])
            continue
        if char == "{":
            depth += 1
        elif char == "}":
            depth -= 1
            assert depth >= 0, text[max(0, i - 60):i + 1]
        elif char == "$":
            math = not math
        elif char == "%":
            raise AssertionError(f"a comment in the body: {text[i - 60:i + 20]!r}")
        elif char in "#~":
            raise AssertionError(f"raw {char!r}: {text[max(0, i - 60):i + 20]!r}")
        elif char in "_^" and not (math or inline):
            raise AssertionError(f"raw {char!r} in text: {text[max(0, i - 60):i + 20]!r}")
        elif char == "&":
            assert envs and envs[-1] == "longtable", text[max(0, i - 60):i + 20]
        elif char == "\n" and (math or inline):
            raise AssertionError("mathematics across a line break")
        elif not (math or inline):
            decoded.append(char)
        i += 1
    assert depth == 0 and not math and not inline and not envs
    return "".join(decoded)


def test_braces_and_environments_balance(manual):
    _scan(manual[2])


WEIRD = "Weird " + SPECIALS.replace("# ", "") + " [x] title"
"""A section title with every special character but ``#`` (a comment in a hand file; the
file name has it)."""


@pytest.fixture(scope="module")
def weird(tmp_path_factory):
    folder = tmp_path_factory.mktemp("weird")
    name = "eq_%&#${}~^\\x.txt"
    path = folder / name
    path.write_text(
        f"@section {WEIRD}\n"
        "@neglect Delta_R_xi : a reason with 50% & a_b ~ $x$ {y} ^ \\z\n"
        "dot(alpha_y) = omega_xi*alpha_z - omega_zeta*alpha_x + Delta_omega_eta"
        " + 2*omega_dp\n", encoding="utf-8")
    tex = folder / "out" / "r.tex"
    status, out, _ = _run(["check", "orthodromic", str(path), "--report", str(tex),
                             "--json"])
    return name, tex.read_text(encoding="utf-8"), json.loads(out), status


def test_user_text_is_escaped(weird):
    name, tex, data, status = weird
    assert status == 1 and data["summary"]["findings"]["root_mistakes"] >= 1
    text = _scan(tex)
    assert WEIRD in text  # the section title, every special character printed as itself
    assert name in text  # the file name (title, result line)
    assert "a reason with 50% & a_b ~ $x$ {y} ^ \\z" in text


def test_deterministic_no_path(weird, tmp_path):
    _, tex, _, _ = weird
    assert str(tmp_path.parent) not in tex and "/" + "tmp" not in tex
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", tex)


# -- (3) counts as in --json ---------------------------------------------------------------

def _section(tex: str, title: str) -> str:
    start = tex.index(rf"\subsubsection*{{{title}}}")
    end = tex.find(r"\subsubsection*", start + 1)
    return tex[start:end]


def test_counts_equal_the_json(tmp_path):
    tex_path = tmp_path / "findings.tex"
    status, out, _ = _run(["check", "orthodromic", str(MANUAL), "--json", "--report",
                           str(tex_path)])
    assert status == 1
    found = json.loads(out)["summary"]["findings"]
    tex = tex_path.read_text(encoding="utf-8")
    roots = _section(tex, "Root mistakes and their knock-on effects")
    assert roots.count(r"\paragraph{Line ") == found["root_mistakes"] > 0
    assert _section(tex, "Declared drops").count(r"\item ") == found["declared_drops"] > 0
    assert (_section(tex, "Other small drops").count(r"\item ")
            == found["dropped_small_terms"] > 0)
    assert tex.startswith("% ") and r"\documentclass" not in tex
    for package in ("amsmath", "booktabs", "longtable"):
        assert package in tex.splitlines()[1]


def test_markdown_unless_tex(tmp_path):
    path = tmp_path / "f.txt"
    path.write_text("dot(alpha_y) = omega_xi*alpha_z - omega_zeta*alpha_x + Delta_omega_eta"
                    " + omega_dp\n", encoding="utf-8")
    status, _, _ = _run(["check", "orthodromic", str(path), "--report",
                         str(tmp_path / "r.md")])
    assert status == 0
    assert (tmp_path / "r.md").read_text(encoding="utf-8").startswith("# Check of")


# -- (4) bad paths -------------------------------------------------------------------------

def test_report_under_a_file_is_one_line_error(tmp_path):
    (tmp_path / "not_a_folder").write_text("x", encoding="utf-8")
    status, out, err = _run(["check", "orthodromic", str(MANUAL), "--report",
                             str(tmp_path / "not_a_folder" / "missing" / "r.tex")])
    assert status == 2 and not out
    assert err.startswith("ins-errors: error: ") and err.count("\n") == 1
    assert "not a folder" in err


def test_latex_report_of_matrix_check_is_refused(tmp_path):
    status, out, err = _run(["check", "strapdown_ned", "--matrix", "nothing.py:F",
                             "--report", str(tmp_path / "r.tex")])
    assert status == 2 and not out
    assert err.startswith("ins-errors: error: ") and err.count("\n") == 1
    assert "Markdown" in err and not (tmp_path / "r.tex").exists()


def test_latex_report_of_convention_file_is_refused(tmp_path):
    path = tmp_path / "phi.txt"
    path.write_text("@convention phi\ndot(phi_N) = 0\n", encoding="utf-8")
    status, out, err = _run(["check", "strapdown_ned", str(path), "--report",
                             str(tmp_path / "r.tex")])
    assert status == 2 and not out
    assert err.startswith("ins-errors: error: ") and err.count("\n") == 1
    assert "@convention" in err and not (tmp_path / "r.tex").exists()
