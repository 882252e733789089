r"""Bias states written in LaTeX under ``@convention``: ``\dot{b}_{gx} = 0`` (or TeX's
``\dot b_{gx}``) makes the source a bias state exactly as ``dot(gyro_bias_x) = 0`` does,
and ``@markov`` takes the source as the file spells it (``b_{gz}``).

The spellings are the model's own LaTeX of its sources (``ins-errors models MODEL``):
``b_{gx}`` … for strapdown_ned, ``\varepsilon_x`` … for the example model file
strapdown_sphere.py. Reference: the textbook φ-angle attitude rows with the radii held
fixed (tests/data/convention), with the gyro biases as states, one of them a Gauss–Markov
bias of τ = 1 h, and a sign slipped in a bias column: the text file and its LaTeX
transcription must give the same report, entry by entry.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ins_errors.checker.convention_equations import check_convention_file, to_json
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data" / "convention"
SPHERE = str(ROOT / "examples" / "strapdown" / "strapdown_sphere.py")
FAST = {"hours": 2.0, "step": 600.0, "effects": False}

TEXT_BIAS = ["dot(gyro_bias_x) = 0", "dot(gyro_bias_y) = 0", "@markov gyro_bias_z = 1 h",
             "dot(gyro_bias_z) = -gyro_bias_z/3600"]


def _latex_bias(b: str) -> list[str]:
    """The LaTeX lines of TEXT_BIAS, ``b`` the sources' spelling up to the axis
    (``b_{g``: ``b_{gx}``), once braced (``\\dot{b}_{gx}``), once not (``\\dot b_{gy}``)."""
    base, _, sub = b.partition("_")
    return [rf"\dot{{{base}}}_{sub}x}} = 0", rf"\dot {b}y}} = 0", f"@markov {b}z}} = 1 h",
            rf"\dot{{{base}}}_{sub}z}} = -\frac{{{b}z}}}}{{3600}}"]


def _files(tmp_path: Path, spelling: str) -> tuple[Path, Path]:
    text = (DATA / "phi_attitude_textbook.txt").read_text().replace(
        "C33*gyro_bias_z", "-C33*gyro_bias_z")
    latex = (DATA / "phi_attitude_textbook.tex").read_text().replace(
        r"C_{33}\,b_{gz}", r"-C_{33}\,b_{gz}")
    latex = latex.replace("b_{g", spelling)
    if spelling != "b_{g":  # the example model file writes the Earth rate U, not \Omega
        latex = latex.replace(r"\Omega", "U")
    txt, tex = tmp_path / "bias.txt", tmp_path / "bias.tex"
    txt.write_text("\n".join([text.rstrip("\n"), *TEXT_BIAS]) + "\n", encoding="utf-8")
    tex.write_text("\n".join([latex.rstrip("\n"), *_latex_bias(spelling)]) + "\n",
                   encoding="utf-8")
    return txt, tex


def _rounded(value):
    """A JSON report with its numbers to 9 digits (the two files' expressions are the
    same, their SymPy forms may round differently in the last bits)."""
    if isinstance(value, float):
        return float(f"{value:.9g}")
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items() if k not in ("hand", "lines")}
    if isinstance(value, list):
        return [_rounded(v) for v in value]
    return value


@pytest.mark.parametrize("model, spelling", [("strapdown_ned", "b_{g"),
                                             (SPHERE, r"\varepsilon_{")])
def test_latex_bias_lines_give_the_text_report(tmp_path, model, spelling):
    txt, tex = _files(tmp_path, spelling)
    text = check_convention_file(txt, model, **FAST)
    latex = check_convention_file(tex, model, **FAST)
    assert [b.name for b in latex.report.bias_states] == [
        "gyro_bias_x", "gyro_bias_y", "gyro_bias_z"]
    assert [b.tau for b in latex.report.bias_states] == [None, None, 3600.0]
    assert _rounded(to_json(latex)) == _rounded(to_json(text))
    # the bias rows agree (0, 0, −1/τ), the slipped sign is found where it is
    assert [(f.row, f.column, f.kind) for f in latex.report.mistakes] == [
        ("phi_D", "gyro_bias_z", "wrong sign")]
    assert latex.report.compared == 6 * 12
    lines = tex.read_text().splitlines()
    assert latex.lines["gyro_bias_y"][0] == 1 + lines.index(_latex_bias(spelling)[1])


@pytest.mark.parametrize("model, shown", [("strapdown_ned", r"\dot{b}_{gx}"),
                                          (SPHERE, r"\dot{\varepsilon}_x")])
def test_a_latex_left_side_that_is_no_state_names_the_latex_spelling(tmp_path, capsys,
                                                                     model, shown):
    path = tmp_path / "bad.tex"
    path.write_text("@convention phi\n\\dot{\\delta b}_{gx} = 0\n", encoding="utf-8")
    assert main(["check", model, str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert f"bias state (dot(gyro_bias_x), in LaTeX {shown})" in err
    assert "\n" not in err and "line 2" in err


def test_markov_names_a_source_by_its_text_spelling(tmp_path):
    text = (DATA / "phi_attitude_textbook.txt").read_text()
    path = tmp_path / "spelled.txt"
    path.write_text(text + "@markov b_gz = 1 h\ndot(gyro_bias_z) = -gyro_bias_z/3600\n")
    check = check_convention_file(path, **FAST)
    assert [b.tau for b in check.report.bias_states] == [3600.0]
    assert not check.report.mistakes
    assert "gyro_bias_z" in check.lines
