r"""Reading a researcher's hand file, second round (a probe of one's own derivations).

* A trailing equation number is not a factor: ``... + \nabla (2)`` was read as 2∇ (a
  wrong coefficient "hand/model = 2"), ``(1)`` passed silently; amsmath's ``\tag``,
  ``\label``, ``\nonumber``, ``\notag`` are ignored.
* ``\dot{V}`` of a true state is said to be the true state's rate, with the error's.
* ``@convention`` files: the Earth rate as texts write it (``\Omega``, ``\Omega_{ie}``,
  ``\omega_{ie}``) is ``U`` whatever the model's LaTeX of it; names are looked up as
  written (``0\cdot\Xi``), with the column, close names, the latitude's name and the
  model's own notation of its sources; ``@neglect h`` holds the height at 0; a refused
  file's ``--json`` has the convention keys and the problem's line and column.

References are independent of the code under test: the Schuler loop's error equations
δV' = −gψ + ∇, δφ' = δV/R, ψ' = δV/R + ε (the model's own docstring, textbook), the
φ-angle equations of a sphere written out by hand, and the model's height state.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp

from ins_errors.checker.compare import check_hand_file
from ins_errors.checker.convention_equations import check_convention_file
from ins_errors.checker.notation import Notation, default_notation
from ins_errors.checker.parse import parse_hand_text
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError

ROOT = Path(__file__).resolve().parent.parent
SCHULER = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
SPHERE = str(ROOT / "examples" / "strapdown" / "strapdown_sphere.py")
FAST = {"hours": 2.0, "step": 600.0, "effects": False}

SCHULER_TEX = [r"\Delta\dot{V} = -g \psi + \nabla",
               r"\Delta\dot{\varphi} = \frac{\Delta V}{R}",
               r"\dot{\psi} = \frac{\Delta V}{R} + \varepsilon"]
"""The Schuler loop's error equations (textbook), one per line."""


def _schuler(tmp_path, lines: list[str], suffix: str = ".tex"):
    path = tmp_path / f"loop{suffix}"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return check_hand_file(path, model=SCHULER)


def _statuses(report) -> dict[int, str]:
    return {r.equation.line: r.status for r in report.results}


# -- equation numbers --------------------------------------------------------------------
@pytest.mark.parametrize("number, written", [
    ("2", r" (2)"), ("1", r" (1)"), ("2", r" \qquad (2)"), ("3.14", r"\quad(3.14)"),
    ("2", r", \quad (2)"), ("4a", r"\;(4a)")])
def test_a_trailing_equation_number_is_refused_not_multiplied_in(tmp_path, number, written):
    """``\\nabla (2)`` was 2∇: "wrong coefficient hand/model = 2" (and ``(1)`` passed);
    ``\\qquad (2)`` said "no '='". Now one problem at the number's column, saying how to
    write an equation number and a factor; the other lines are checked as before."""
    first = SCHULER_TEX[0] + written
    report = _schuler(tmp_path, [first, *SCHULER_TEX[1:]])
    [problem] = report.problems
    assert problem.line == 1
    assert problem.column == first.rindex("(") + 1
    assert "looks like an equation number" in problem.message
    assert f"\\tag{{{number}}}" in problem.message
    assert f"{number} \\cdot ..." in problem.message  # how a factor is written
    assert "\n" not in problem.message
    assert 1 not in _statuses(report)  # not compared: no verdict on a misread line
    assert not report.mistakes
    assert _statuses(report) == {2: "agrees", 3: "agrees"}
    assert report.exit_status == 2


def test_a_trailing_number_in_a_text_file_is_refused_too(tmp_path):
    report = _schuler(tmp_path, ["dot(Delta_V) = -g*psi + accel_bias  (2)",
                                 "dot(Delta_phi) = Delta_V/R"], suffix=".txt")
    [problem] = report.problems
    assert (problem.line, problem.column) == (1, len("dot(Delta_V) = -g*psi + accel_bias  ") + 1)
    assert "equation number" in problem.message and "# (2)" in problem.message
    assert "2*..." in problem.message


@pytest.mark.parametrize("label", [r"\tag{2}", r"\tag*{A.1}", r"\label{eq:dV}",
                                   r"\nonumber", r"\notag", r"\qquad \tag{2}"])
def test_equation_numbering_commands_are_ignored(tmp_path, label):
    """amsmath's numbering was refused as unsupported LaTeX; the equations agree."""
    report = _schuler(tmp_path, [f"{SCHULER_TEX[0]} {label}",
                                 f"{SCHULER_TEX[1]} {label}", SCHULER_TEX[2]])
    assert report.problems == []
    assert _statuses(report) == {1: "agrees", 2: "agrees", 3: "agrees"}
    assert report.exit_status == 0


LEGITIMATE = [
    # (format, right-hand side, expected in the symbols a, b, e, x)
    ("latex", r"a (1 - e^2) b", "a*(1 - e**2)*b"),
    ("latex", r"a\,(2 + b)", "a*(2 + b)"),
    ("latex", r"\cos (2)", "cos(2)"),
    ("latex", r"\frac{a}{b} \cdot (2)", "2*a/b"),
    ("latex", r"a - (2)", "a - 2"),
    ("latex", r"a(2)", "2*a"),  # no space: a product, as always
    ("text", "a*(1 - e**2)*b", "a*(1 - e**2)*b"),
    ("text", "sqrt (2)*a", "sqrt(2)*a"),
    ("text", "a*sqrt (2)", "sqrt(2)*a"),
    ("text", "a + (2)", "a + 2"),
]


def test_only_a_number_ending_the_line_after_spacing_is_an_equation_number():
    """``a (2)`` ending a line is refused; a parenthesised number after an operator, a
    bracket or a function, or with no space before it, is arithmetic, read as before."""
    for form, refused in (("latex", r"\dot{x} = a (2)"), ("text", "dot(x) = a (2)")):
        hand = parse_hand_text(refused + "\n", Notation(), latex=form == "latex")
        assert "equation number" in hand.problems[0].message and not hand.equations
    names = {n: sp.Symbol(n) for n in "abex"}
    for form, rhs, expected in LEGITIMATE:
        lhs = r"\dot{x}" if form == "latex" else "dot(x)"
        hand = parse_hand_text(f"{lhs} = {rhs}\n", Notation(), latex=form == "latex")
        assert hand.problems == [], rhs
        [eq] = hand.equations
        assert sp.simplify(eq.forms[0] - sp.sympify(expected, locals=names)) == 0, rhs


# -- the rate of a true state ----------------------------------------------------------
def test_the_rate_of_a_true_state_is_said_to_be_one_with_the_errors_rate(tmp_path):
    """``\\dot{V}`` said "V is not a state of the model" (V is one): now the line says it is
    the true state's rate and how the error's is written; both forms it gives agree."""
    report = _schuler(tmp_path, [r"\dot{V} = -g \psi + \nabla", *SCHULER_TEX[1:]])
    [problem] = report.problems
    assert problem.line == 1
    assert "rate of the true state V" in problem.message
    assert "is not a state" not in problem.message
    assert r"\Delta\dot{V} or \dot{\Delta V}" in problem.message
    for written in (r"\Delta\dot{V}", r"\dot{\Delta V}"):  # what it suggests works
        fixed = _schuler(tmp_path, [f"{written} = -g \\psi + \\nabla", *SCHULER_TEX[1:]])
        assert fixed.problems == [] and fixed.exit_status == 0
    text = _schuler(tmp_path, ["dot(phi) = Delta_V/R"], suffix=".txt")
    [problem] = text.problems
    assert "rate of the true state phi" in problem.message
    assert "dot(Delta_phi) or dot(delta_phi)" in problem.message


def test_true_states_come_from_the_models_definition():
    """Every model's true states, none of its error states or sources."""
    for model in ("north_pointing", "orthodromic", SCHULER):
        notation = default_notation(model)
        from ins_errors.checker.notation import _definition

        d = _definition(model)
        assert set(notation.true_states) == {v.name for v in d.states}
        assert not set(notation.true_states) & {v.name for v in (*d.error_states,
                                                                  *d.sources)}


def test_an_unknown_earth_rate_spelling_in_a_plain_file_is_told_the_models_name(tmp_path):
    path = tmp_path / "eq.txt"
    path.write_text("dot(Delta_V_xi) = Omega*alpha_x\n", encoding="utf-8")
    report = check_hand_file(path, model="orthodromic")
    [problem] = report.problems
    assert "unknown symbol 'Omega'; the Earth rate of model 'orthodromic' is U" in \
        problem.message


# -- @convention files: names ----------------------------------------------------------
PHI_E_ROW = (r"\dot{\phi}_E = \omega_N\phi_D - \omega_D\phi_N - \frac{\delta v_N}{R + h} "
             r"+ \frac{v_N}{(R+h)^2}\delta h - C_{21}\varepsilon_x - C_{22}\varepsilon_y "
             r"- C_{23}\varepsilon_z")
"""The φ-angle east row on a sphere (φ̇ = −ω_in × φ + δω_in − C_b^n δω_ib), in the
sphere model's notation (its gyro biases are ε_x, ε_y, ε_z)."""


def _convention_file(tmp_path, *lines: str, suffix: str = ".tex") -> Path:
    path = tmp_path / f"conv{suffix}"
    path.write_text("\n".join(["@convention phi_geodetic", *lines]) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("earth", [r"\Omega", r"\Omega_{ie}", r"\omega_{ie}"])
def test_the_earth_rate_as_texts_write_it_is_U(tmp_path, earth):
    """strapdown_sphere's LaTeX of U is ``U``: ``\\Omega`` was an unknown name. The file
    agrees written with ``U`` and with each other spelling."""
    for written in ("U", earth):
        path = _convention_file(tmp_path,
                                rf"\omega_N = {written}\cos L + \frac{{v_E}}{{R + h}}",
                                rf"\omega_D = -{written}\sin L - \frac{{v_E\tan L}}{{R + h}}",
                                PHI_E_ROW)
        check = check_convention_file(path, SPHERE, **FAST)
        assert check.report.findings == [] and check.exit_status == 0


def test_the_earth_rate_in_a_text_file(tmp_path):
    path = _convention_file(tmp_path, "dot(dh) = -dv_D + 0*dlat",
                            "dot(dlat) = dv_N/(R + h) - v_N*dh/(R + h)**2 "
                            "+ (Omega - Omega_ie)*dlon", suffix=".txt")
    check = check_convention_file(path, SPHERE, **FAST)
    assert check.report.findings == []


def _refusal(path, model=SPHERE) -> str:
    with pytest.raises(InsErrorsError) as error:
        check_convention_file(path, model, **FAST)
    text = str(error.value)
    assert "\n" not in text
    return text


def test_a_name_multiplied_by_zero_is_still_looked_up(tmp_path):
    """``0\\cdot\\Omega`` passed whatever the name: the 0 took it away before the look-up."""
    line = r"\dot{\delta h} = -\delta v_D + 0\cdot\Xi\,\delta h"
    text = _refusal(_convention_file(tmp_path, line))
    assert f"conv.tex, line 2, column {line.index(chr(92) + 'Xi') + 1}: unknown name 'Xi'" \
        in text
    line = r"\omega_N = 0\cdot\sin\varphi"
    text = _refusal(_convention_file(tmp_path, line, r"\dot{\delta h} = -\delta v_D"))
    assert f"line 2, column {line.index(chr(92) + 'varphi') + 1}: unknown name 'phi' in " \
           "the definition of omega_N: the latitude is L" in text


def test_an_unknown_name_gets_the_column_close_names_and_the_models_sources(tmp_path):
    """``\\delta v_n`` said "unknown name 'Delta_v_n'" with no column, no suggestion and
    "error sources of the model"; ``b_{gx}`` (strapdown_ned's LaTeX) for the sphere's
    ``\\varepsilon_x`` likewise."""
    row = PHI_E_ROW.replace(r"\delta v_N", r"\delta v_n")
    text = _refusal(_convention_file(tmp_path, r"\omega_N = U\cos L", r"\omega_D = 0", row))
    assert f"line 4, column {row.index(chr(92) + 'delta v_n') + 1}: unknown name " \
           "'Delta_v_n'; did you mean 'Delta_v_N' (dv_N)" in text
    row = PHI_E_ROW.replace(r"\varepsilon_x", "b_{gx}")
    text = _refusal(_convention_file(tmp_path, r"\omega_N = U\cos L", r"\omega_D = 0", row))
    assert f"column {row.index('b_{gx}') + 1}: unknown name 'b_gx'" in text
    for source, latex in (("gyro_bias_x", r"\varepsilon_x"), ("accel_bias_z", r"\nabla_z")):
        assert f"{latex} ({source})" in text


def test_the_rate_of_a_named_quantity_points_to_its_errors_row(tmp_path):
    text = _refusal(_convention_file(tmp_path, r"\dot{v}_N = \delta v_D"))
    assert "left-hand side 'dot(v_N)' must be dot(STATE)" in text
    assert "v_N is the true north velocity, a named quantity: the row of its error is " \
        "dot(dv_N)" in text


# -- @convention files: @neglect h ---------------------------------------------------------
SPHERE_PHI = """\
@convention phi_geodetic
{neglect}
r = {radius}
W_N = U*cos(lat) + v_E/r
W_E = -v_N/r
W_D = -U*sin(lat) - v_E*tan(lat)/r
drho_N = dv_E/r - v_E*dh/r**2
drho_E = -dv_N/r + v_N*dh/r**2
B_N = C11*gyro_bias_x + C12*gyro_bias_y + C13*gyro_bias_z
B_E = C21*gyro_bias_x + C22*gyro_bias_y + C23*gyro_bias_z
dot(phi_N) = W_D*phi_E - W_E*phi_D - U*sin(lat)*dlat + drho_N - B_N
dot(phi_E) = W_N*phi_D - W_D*phi_N + drho_E - B_E
dot(dlat) = {sign}dv_N/r - v_N*dh/r**2
dot(dh) = -dv_D
"""
"""A researcher's φ-angle rows of a sphere of radius R (hand derivation: δω_ie, δω_en
through the position errors); ``radius`` R + h as the model, or R for R + h."""


def _sphere(tmp_path, neglect: str = "", radius: str = "R + h", sign: str = "",
            scope: str = ""):
    path = tmp_path / "sphere.txt"
    path.write_text(SPHERE_PHI.format(neglect=neglect, radius=radius, sign=sign) + scope,
                    encoding="utf-8")
    return check_convention_file(path, SPHERE, **FAST)


def test_neglecting_the_height_makes_r_for_r_plus_h_declared_drops(tmp_path):
    """``@neglect h : h << R`` was refused under @convention. The file that writes R for
    R + h: without the declaration the latitude rate's R is a mistake (size h/(R + h),
    0.0016 at 10 km); at h = 0 (the static base alone) it agrees entry by entry; with the
    declaration every finding is a declared drop of the same size, exit 0."""
    exact = _sphere(tmp_path)
    assert exact.report.findings == []
    static = _sphere(tmp_path, radius="R", scope="@scope static base\n")
    assert static.report.findings == []  # the file is the model at h = 0
    plain = _sphere(tmp_path, radius="R")
    by_entry = {f.entry: f for f in plain.report.findings}
    assert by_entry["F[dlat, dv_N]"].severity == "mistake"
    assert by_entry["F[dlat, dv_N]"].size == pytest.approx(10_000 / (6_371_000 + 10_000),
                                                           rel=0.02)
    held = _sphere(tmp_path, neglect="@neglect h : h << R", radius="R")
    assert held.exit_status == 0
    assert {f.entry for f in held.report.findings} == set(by_entry)
    for f in held.report.findings:
        assert (f.kind, f.severity) == ("omitted term", "declared drop")
        assert "(line 2: h, held at 0)" in f.detail
        assert f.size == pytest.approx(by_entry[f.entry].size)
    assert held.report.idle_declarations == []


def test_a_slip_beside_the_neglected_height_stays_a_mistake(tmp_path):
    held = _sphere(tmp_path, neglect="@neglect h : h << R", radius="R", sign="-")
    wrong = [f for f in held.report.findings if f.severity == "mistake"]
    assert [(f.entry, f.kind) for f in wrong] == [("F[dlat, dv_N]", "wrong sign")]
    assert held.exit_status == 1


def test_neglecting_the_height_in_a_file_that_keeps_it_explains_nothing(tmp_path):
    held = _sphere(tmp_path, neglect="@neglect h : h << R")
    assert held.report.findings == []
    assert held.report.idle_declarations == ["line 2: h"]


def test_another_quantity_cannot_be_neglected_and_says_which_can(tmp_path):
    with pytest.raises(InsErrorsError) as error:
        _sphere(tmp_path, neglect="@neglect v_D")
    assert "only the height can be neglected" in str(error.value)


# -- @convention files: the JSON of a refused file -----------------------------------------
def _json(argv, capsys) -> tuple[int, dict, str]:
    status = main(argv)
    captured = capsys.readouterr()
    return status, json.loads(captured.out), captured.err


def test_a_refused_convention_files_json_has_the_convention_keys_and_the_place(tmp_path,
                                                                             capsys):
    from tests.test_json_documented import COMMON, documented, key_paths, matcher

    row = PHI_E_ROW.replace(r"\delta v_N", r"\delta v_n")
    bad = _convention_file(tmp_path, r"\omega_N = U\cos L", r"\omega_D = 0", row)
    status, out, err = _json(["check", SPHERE, str(bad), "--json"], capsys)
    assert status == 2 and out["exit_status"] == 2
    assert out["convention"] == "phi_geodetic" and out["hand"] == "conv.tex"
    assert out["states"][:3] == ["phi_N", "phi_E", "phi_D"]
    [problem] = out["problems"]
    assert (problem["line"], problem["column"]) == (4, row.index(r"\delta v_n") + 1)
    assert problem["message"].startswith("unknown name 'Delta_v_n'")
    assert f"line 4, column {problem['column']}: {problem['message']}" in err
    assert out["summary"]["input_problems"] == 1
    good = _convention_file(tmp_path, r"\dot{\delta h} = -\delta v_D")
    _, checked, _ = _json(["check", SPHERE, str(good), "--json"], capsys)
    assert set(out) - {"problems"} == set(checked)  # the shape of a checked file
    page = documented()
    sections = [COMMON, "check --matrix", "check of a file with @convention"]
    covers = matcher([p for s in sections for p in page[s]])
    assert not [p for p in key_paths(out) if not covers(p, out)]
    # a problem of the whole file: no line
    empty = _convention_file(tmp_path, "% nothing but a comment")
    status, out, _ = _json(["check", SPHERE, str(empty), "--json"], capsys)
    assert status == 2
    assert out["problems"][0]["line"] is None and out["convention"] == "phi_geodetic"
