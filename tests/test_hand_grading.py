"""Grading a class's hand files: what students' editors write is read as they meant it,
several files are checked in one command, and a grading script always gets JSON.

- a UTF-8 byte-order mark (Windows Notepad) before the first line is no character of the
  file: hand files, mapping files, ``@convention`` detection, scenario and spec TOML;
- legal LaTeX the parser refused: TeX's one-token ``\\frac`` arguments (``\\frac12``),
  ``\\dfrac`` / ``\\tfrac``, a left side written ``\\frac{\\mathrm{d}X}{\\mathrm{d}t}``, a
  typeset minus sign and multiplication signs (also in text files), each compared with
  the form the parser always read;
- a second equation of the same error state in one section is an input problem naming
  both lines, as a second definition is;
- ``ins-errors check MODEL FILE FILE ...`` and its ``--json`` array; ``--json`` of an
  empty file prints a JSON object with the problem.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp

from ins_errors.checker.compare import check_hand, check_hand_file
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import (
    parse_hand_text,
    parse_latex_expression,
    parse_text_expression,
    read_mapping_file,
)
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
CORRECT = ROOT / "tests" / "data" / "hand_correct_north_pointing.txt"
MODEL = "north_pointing"
BOM = "\ufeff"


@pytest.fixture(scope="module")
def notation():
    return default_notation(MODEL)


def _equations(hand) -> list[tuple[str, list[str]]]:
    return [(str(e.lhs), [str(f) for f in e.forms]) for e in hand.equations]


# --------------------------------------------------------------------------------------
# byte-order mark
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(("first", "latex"), [
    ("dot(delta_latitude) = delta_v_N/(R + h)", False),
    ("# a comment first", False),
    (r"$$\dot{\delta\varphi} = \frac{\delta v_N}{R + h}$$", True),
    ("% a comment first", True),
])
def test_a_byte_order_mark_is_no_character_of_the_file(notation, first, latex):
    rest = (r"\dot{\alpha}_E = \varepsilon_E" if latex else "dot(alpha_E) = gyro_drift_east")
    text = f"{first}\r\n{rest}\r\n"
    plain = parse_hand_text(text, notation, latex=latex)
    marked = parse_hand_text(BOM + text, notation, latex=latex)
    assert not plain.problems
    assert not marked.problems, [str(p) for p in marked.problems]
    assert _equations(marked) == _equations(plain)
    assert [e.columns for e in marked.equations] == [e.columns for e in plain.equations]


def test_a_notepad_file_is_checked_like_the_same_file_without_the_mark(tmp_path):
    marked = tmp_path / "notepad.txt"
    marked.write_text(CORRECT.read_text(encoding="utf-8"), encoding="utf-8-sig")
    assert marked.read_bytes()[:3] == b"\xef\xbb\xbf"
    plain = check_hand_file(CORRECT, model=MODEL)
    report = check_hand_file(marked, model=MODEL)
    assert plain.exit_status == 0
    assert report.exit_status == 0, [str(p) for p in report.problems]
    assert [r.label for r in report.results] == [r.label for r in plain.results]


def test_other_text_inputs_with_a_byte_order_mark(tmp_path):
    from ins_errors.commands.check import _declares_convention
    from ins_errors.scenario import load_scenario
    from ins_errors.specs import load_spec

    mapping = tmp_path / "map.txt"
    mapping.write_text("@alias D = R\n", encoding="utf-8-sig")
    assert read_mapping_file(mapping).aliases == {"D": "R"}
    convention = tmp_path / "phi.txt"
    convention.write_text("@convention phi\ndot(phi_N) = 0\n", encoding="utf-8-sig")
    assert _declares_convention(convention)
    for source, load in ((ROOT / "examples" / "specs" / "gyro_drift_fixed.toml", load_spec),
                         (ROOT / "examples" / "lab_000_task1_gyro_drift.toml",
                          load_scenario)):
        copies = []
        for folder, encoding in (("plain", "utf-8"), ("marked", "utf-8-sig")):
            (tmp_path / folder).mkdir(exist_ok=True)
            copies.append(tmp_path / folder / source.name)
            copies[-1].write_text(source.read_text(encoding="utf-8"), encoding=encoding)
        plain, marked = (load(copy) for copy in copies)
        where = ("path", "file", "base")  # the copies' own places
        assert {k: v for k, v in vars(marked).items() if k not in where} == {
            k: v for k, v in vars(plain).items() if k not in where}


# --------------------------------------------------------------------------------------
# LaTeX the parser refused
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(("written", "reference"), [
    (r"\frac12 \delta v_N", r"\frac{1}{2} \delta v_N"),
    (r"\frac1{R + h}\delta v_N", r"\frac{1}{R + h}\delta v_N"),
    (r"\frac{\delta v_N}2", r"\frac{\delta v_N}{2}"),
    (r"\frac 3 4", r"\frac{3}{4}"),
    (r"\frac\pi2 \alpha_N", r"\frac{\pi}{2} \alpha_N"),
    (r"\frac1R \delta v_N", r"\frac{1}{R} \delta v_N"),
    (r"\frac1\Omega \alpha_N", r"\frac{1}{\Omega} \alpha_N"),
    (r"\frac12 \cdot 2\frac{\delta v_E}{R + h}", r"\frac{\delta v_E}{R + h}"),
    (r"\dfrac{\delta v_N}{R + h}", r"\frac{\delta v_N}{R + h}"),
    (r"\tfrac{\delta v_N}{R + h}", r"\frac{\delta v_N}{R + h}"),
    ("\u2212\\frac{\\delta v_N}{R + h}", r"-\frac{\delta v_N}{R + h}"),
    ("a_N \u2212 f_U\\alpha_N", r"a_N - f_U\alpha_N"),
    ("2 \u00d7 \\Omega \u22c5 \\sin\\varphi \u00b7 \\delta v_N",
     r"2 \cdot \Omega \cdot \sin\varphi \cdot \delta v_N"),
])
def test_legal_latex_reads_as_its_braced_form(notation, written, reference):
    expected, _ = parse_latex_expression(reference, notation)
    got, _ = parse_latex_expression(written, notation)
    assert sp.simplify(got - expected) == 0, (got, expected)


def test_tex_single_token_fraction_values(notation):
    half, _ = parse_latex_expression(r"\frac12", notation)
    assert half == sp.Rational(1, 2)
    # TeX takes one digit: \frac123 is (1/2)*3
    three_halves, _ = parse_latex_expression(r"\frac123", notation)
    assert three_halves == sp.Rational(3, 2)


@pytest.mark.parametrize(("written", "reference"), [
    ("dot(delta_v_N) = a_N \u2212 f_U*alpha_E", "dot(delta_v_N) = a_N - f_U*alpha_E"),
    ("dot(delta_v_N) = 2\u00d7U\u22c5sin(phi)\u00b7delta_v_E",
     "dot(delta_v_N) = 2*U*sin(phi)*delta_v_E"),
])
def test_typeset_operators_in_a_text_file(notation, written, reference):
    hand = parse_hand_text(written, notation)
    assert not hand.problems, [str(p) for p in hand.problems]
    expected = parse_hand_text(reference, notation)
    assert _equations(hand) == _equations(expected)
    # one character for one: the columns are those of the characters written
    assert hand.equations[0].columns == expected.equations[0].columns
    assert parse_text_expression("a \u2212 b", notation)[0] == sp.Symbol("a") - sp.Symbol("b")


@pytest.mark.parametrize("left", [
    r"\frac{\mathrm{d}\,\delta\varphi}{\mathrm{d}t}",
    r"\frac{d\,\delta\varphi}{dt}",
    r"\frac{d\delta\varphi}{dt}",
    r"\dfrac{\mathrm{d}\delta\varphi}{\mathrm{d}t}",
    r"\frac{d}{dt}\delta\varphi",
])
def test_a_derivative_on_the_left_is_the_time_derivative(notation, left):
    right = r"\frac{\delta v_N}{R + h}"
    reference = parse_hand_text(rf"$$\dot{{\delta\varphi}} = {right}$$", notation, latex=True)
    text = f"$${left} = {right}$$"
    hand = parse_hand_text(text, notation, latex=True)
    assert not hand.problems, [str(p) for p in hand.problems]
    assert _equations(hand) == _equations(reference)
    # the state is placed at its own letter, as in \dot{\delta\varphi}
    shown = rf"$$\dot{{\delta\varphi}} = {right}$$"
    assert reference.equations[0].columns["delta_latitude"] == shown.index(r"\varphi") + 1
    assert hand.equations[0].columns["delta_latitude"] == text.index(r"\varphi") + 1


@pytest.mark.parametrize(("text", "column", "words"), [
    (r"\dot\alpha_N = \frac{a}", 24, r"\frac needs two arguments"),
    (r"\dot\alpha_N = \frac", 17, r"\frac needs two arguments"),
    (r"\dot\alpha_N = \frac+2", 21, "expected an argument in braces"),
    (r"\frac{\mathrm{d}\,\delta\varphi}{\mathrm{d}s} = 1", 1,
     r"left-hand side '\frac{\mathrm{d}\,\delta\varphi}{\mathrm{d}s}' must be one quantity"),
    (r"\frac{\mathrm{d}\,\delta\varphi}{\mathrm{d}t}\alpha_N = 1", 1,
     r"left-hand side '\frac{\mathrm{d}\,\delta\varphi}{\mathrm{d}t}\alpha_N' must be"),
])
def test_malformed_latex_is_one_line_with_line_and_column(notation, text, column, words):
    hand = parse_hand_text("% first\n" + text, notation, latex=True)
    assert len(hand.problems) == 1
    problem = hand.problems[0]
    assert (problem.line, problem.column) == (2, column)
    assert words in problem.message
    assert "\n" not in problem.message and "\\\\" not in problem.message
    assert "  " not in problem.message  # no blanked \mathrm{d}


def test_an_upright_letter_is_the_letter_and_a_text_note_stays_a_note(notation):
    hand = parse_hand_text(r"$$\dot{\delta\varphi} = \frac{\delta v_N}{R + h} \quad "
                           r"\mathrm{for\ orthodromic\ orientation}$$", notation, latex=True)
    assert not hand.problems
    assert hand.equations[0].note == r"for\ orthodromic\ orientation"


# --------------------------------------------------------------------------------------
# a repeated equation of a state
# --------------------------------------------------------------------------------------
LATITUDE = "dot(delta_latitude) = Delta_v_N/r_N - V_N/r_N**2*Delta_r_N"


def _with_second(line: str, after: str = LATITUDE) -> str:
    text = CORRECT.read_text(encoding="utf-8")
    assert after in text
    return text.replace(after, after + "\n" + line, 1)


def _line_of(text: str, line: str) -> int:
    return text.splitlines().index(line) + 1


@pytest.mark.parametrize("second", [
    LATITUDE,                                                    # the same line again
    "dot(delta_latitude) = Delta_v_N/R",                         # another right side
    "dot(Delta_phi) = Delta_v_N/r_N - V_N/r_N**2*Delta_r_N",      # another spelling
])
def test_a_second_equation_of_a_state_is_an_input_problem(notation, second):
    text = _with_second(second)
    report = check_hand(parse_hand_text(text, notation, name="dup.txt"), model=MODEL)
    first_line = _line_of(text, LATITUDE)
    second_line = first_line + 1
    problems = [p for p in report.problems if "dot(delta_latitude)" in p.message]
    assert len(problems) == 1, [str(p) for p in report.problems]
    assert problems[0].line == second_line
    assert f"first at line {first_line}" in problems[0].message
    assert report.exit_status == 2
    # both lines are still checked
    assert {r.equation.line for r in report.results} >= {first_line, second_line}


def test_an_alternative_form_or_another_section_may_restate_a_state(notation):
    alternative = _with_second("@alt " + LATITUDE)
    report = check_hand(parse_hand_text(alternative, notation), model=MODEL)
    assert not report.problems and report.exit_status == 0
    sections = CORRECT.read_text(encoding="utf-8") + "\n@section restated\n" + LATITUDE + "\n"
    report = check_hand(parse_hand_text(sections, notation), model=MODEL)
    assert not report.problems and report.exit_status == 0


# --------------------------------------------------------------------------------------
# several files, and JSON whatever the file holds
# --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def class_files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("class")
    correct = folder / "anna.txt"
    correct.write_text(CORRECT.read_text(encoding="utf-8"), encoding="utf-8")
    wrong = folder / "boris.txt"
    wrong.write_text(CORRECT.read_text(encoding="utf-8").replace(
        "-alpha_N*f_U", "+alpha_N*f_U"), encoding="utf-8")
    empty = folder / "chen.txt"
    empty.write_text("# nothing handed in\n", encoding="utf-8")
    return correct, wrong, empty


def test_several_files_in_one_command(class_files, capsys):
    singles = []
    for path in class_files:
        status = main(["check", MODEL, str(path)])
        singles.append((status, capsys.readouterr()))
    assert [s for s, _ in singles] == [0, 1, 2]
    status = main(["check", MODEL, *map(str, class_files)])
    out, err = capsys.readouterr()
    assert status == 2  # the worst
    headers = [f"==> {path} <==" for path in class_files]
    assert [line for line in out.splitlines() if line.startswith("==> ")] == headers
    # each file's own report, under its header
    parts = out.split("==> ")[1:]
    for part, (_, single) in zip(parts, singles, strict=True):
        assert part.split("\n", 1)[1].strip() == single.out.strip()
    assert err.strip().splitlines()[-1] == singles[2][1].err.strip().splitlines()[-1]
    assert "no equations to check" in err


def test_several_files_as_one_json_array(class_files, capsys):
    status = main(["check", MODEL, *map(str, class_files), "--json"])
    out, _ = capsys.readouterr()
    assert status == 2
    array = json.loads(out)
    assert [item["path"] for item in array] == [str(p) for p in class_files]
    assert [item["exit_status"] for item in array] == [0, 1, 2]
    for path, item in zip(class_files, array, strict=True):
        main(["check", MODEL, str(path), "--json"])
        alone = json.loads(capsys.readouterr().out)
        assert {k: v for k, v in item.items() if k != "path"} == alone


def test_json_of_a_file_with_no_equation(class_files, capsys):
    empty = class_files[2]
    status = main(["check", MODEL, str(empty), "--json"])
    out, err = capsys.readouterr()
    assert status == 2
    data = json.loads(out)
    assert data["exit_status"] == 2 and data["file"] == empty.name
    assert data["equations"] == [] and data["summary"]["input_problems"] == 1
    assert set(data["summary"]) == set(json.loads(_json_of(class_files[0], capsys))["summary"])
    assert "no equations to check" in data["problems"][0]["message"]
    assert len(err.strip().splitlines()) == 1 and "no equations to check" in err


def _json_of(path: Path, capsys) -> str:
    main(["check", MODEL, str(path), "--json"])
    return capsys.readouterr().out


@pytest.mark.parametrize("extra", [["--report", "r.md"], ["--matrix", "F.py:f"]])
def test_several_files_refuse_what_takes_one(class_files, capsys, extra):
    status = main(["check", MODEL, *map(str, class_files[:2]), *extra])
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1
    assert ("--report r.md" if "--report" in extra else "--matrix") in err


def test_the_terminal_quantity_column_is_as_wide_as_its_longest_entry(tmp_path, capsys):
    """An instructor's grade sheet read 'delta_v_N -> delta': the index slip's quantity was
    cut at 18 characters."""
    lines = CORRECT.read_text(encoding="utf-8").splitlines()
    (k,) = [i for i, line in enumerate(lines) if line.startswith("dot(delta_latitude) =")]
    assert "Delta_v_N/r_N" in lines[k]
    lines[k] = lines[k].replace("Delta_v_N/r_N", "Delta_v_E/r_N")
    slip = tmp_path / "index.txt"
    slip.write_text("\n".join(lines) + "\n", encoding="utf-8")
    assert main(["check", MODEL, str(slip)]) == 1
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if f"{k + 1:>4}  dot(" in line)
    assert "delta_v_N -> delta_v_E wrong symbol or index" in row, row
