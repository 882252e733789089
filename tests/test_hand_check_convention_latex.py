r"""LaTeX under ``@convention`` (strapdown_ned, φ convention): the convention's states as
they are printed (``\delta v_E``, ``\delta r_N``, ``\dot{\delta v}_N``), the model's own
LaTeX of its sources (``b_{gx}``) and ``\omega_{in,D}`` are read without ``@name`` lines.

Reference: the textbook φ-angle attitude equation with the radii of curvature held fixed
(Titterton and Weston, ch. 12), as a researcher typed it; the same equation in the text
syntax gives the same findings.
"""

from __future__ import annotations

from pathlib import Path

from ins_errors.checker.convention_equations import check_convention_file

FAST = {"hours": 2.0, "step": 600.0, "effects": False}

DATA = Path(__file__).parent / "data" / "convention"


def _entries(check) -> list[tuple]:
    return sorted((f.row, f.column, f.kind, f.severity) for f in check.report.findings)


def test_printed_latex_names_are_read_and_agree_with_the_text_form():
    tex, txt = DATA / "phi_attitude_textbook.tex", DATA / "phi_attitude_textbook.txt"
    latex, text = check_convention_file(tex, **FAST), check_convention_file(txt, **FAST)
    assert latex.report.compared == text.report.compared == 3 * 12
    assert _entries(latex) == _entries(text)
    # radii held fixed: only dropped small terms (the change of R_N, R_E with latitude)
    assert latex.exit_status == 0
    assert {f.severity for f in latex.report.findings} == {"dropped small term"}
    assert {f.column for f in latex.report.findings} == {"dr_N"}


def test_dot_of_a_printed_variation(tmp_path):
    r"""``\dot{\delta v}_N`` (how the generated equations print a rate) is dot(dv_N)."""
    path = tmp_path / "v.tex"
    path.write_text("@convention phi\n@scope static base\n"
                    r"\dot{\delta v}_N = f_E \phi_D - f_D \phi_E - (2\omega_{ie,E}"
                    r" + \omega_{en,E}) \delta v_D + (2\omega_{ie,D} + \omega_{en,D})"
                    r" \delta v_E - \frac{v_E \delta v_E \tan L}{R_E + h}" "\n")
    check = check_convention_file(path, **FAST)
    assert list(check.lines) == ["dv_N"]
    assert check.lines["dv_N"][0] == 3
    # on the static base (v = 0) this velocity equation is exact, entry by entry
    assert check.report.findings == []
    assert check.report.compared == 9
