"""Messages of a ``@convention`` check (strapdown_ned): one line naming the real problem
for a misused vector line, a hint for a file that forgets ``@convention``, and the
terminal report's cosmetics (``hand 0``, findings in line order)."""

from __future__ import annotations

import pytest

from ins_errors.checker.convention_equations import check_convention_file, to_terminal
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError

FAST = {"hours": 2.0, "step": 600.0, "effects": False}


@pytest.mark.parametrize("line, expected, wrong", [
    ("dot(dw) = -cross(omega_in, phi)",
     "dot(dw): 'dw' is neither a state of the convention nor a vector of its states",
     "unknown function"),
    ("dot(phi_N) = cross(omega_in, phi)",
     "dot(phi_N) is one component, but its right-hand side uses cross()", "unknown function"),
    ("dot(phi_N) = omega_in_D*phi_E + skew(omega_in)*phi", "uses skew()", "unknown function"),
])
def test_vector_notation_outside_a_vector_line_names_the_problem(tmp_path, line, expected,
                                                                 wrong):
    path = tmp_path / "bad.txt"
    path.write_text(f"@convention phi\n{line}\n")
    with pytest.raises(InsErrorsError) as error:
        check_convention_file(path, **FAST)
    text = str(error.value)
    assert expected in text and wrong not in text and "\n" not in text
    assert "line 2" in text


def test_convention_names_without_convention_get_a_hint(tmp_path, capsys):
    path = tmp_path / "nocnv.txt"
    path.write_text("dot(phi_N) = omega_in_D*phi_E\n")
    assert main(["check", "strapdown_ned", str(path)]) == 2
    out = capsys.readouterr().err  # nothing of the file was checked: its problem, on stderr
    assert "add the line '@convention phi'" in out


def test_a_zero_entry_prints_as_0_and_findings_come_in_line_order(tmp_path):
    """On the static base ω_en = 0: the hand's −ω_en,D is −0.0 in floating point; the
    report says ``hand 0``. The later line's major mistake is listed after the earlier
    line's smaller one."""
    path = tmp_path / "order.txt"
    path.write_text("@convention phi\n@scope static base\n"
                    "dot(dv_N) = f_E*phi_D - f_D*phi_E - omega_en_D*dv_E"
                    " - (2*omega_ie_E + omega_en_E)*dv_D\n"
                    "dot(phi_E) = omega_in_N*phi_D + omega_in_D*phi_N - dv_N/(R_N + h)\n")
    check = check_convention_file(path, **FAST)
    text = to_terminal(check)
    assert "hand -0" not in text and "hand 0," in text
    by_line = text.split("Findings by line of the hand file:")[1].splitlines()
    numbers = [int(row.split()[1].rstrip(":")) for row in by_line if row.strip()
               .startswith("line ")]
    assert numbers == sorted(numbers) and set(numbers) == {3, 4}
    # the worst finding (of line 4) comes first in the report's own order
    assert check.report.findings[0].row == "phi_E"


def test_trial_changes_that_divide_by_zero_leave_no_numpy_warning(capsys):
    """A journal reviewer's φ-model with slips (a probe's file): the one-place changes
    tried for a symbol slip (v_E where R_E belongs ...) divide by zero at rest and
    printed ten numpy RuntimeWarnings with lambdify's code on stderr."""
    import warnings
    from pathlib import Path

    path = Path(__file__).resolve().parent / "data" / "convention" / \
        "phi_paper_with_slips.txt"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        check = check_convention_file(path, effects=False)
    assert check.report.findings  # the slips are still found
    assert "RuntimeWarning" not in capsys.readouterr().err
    # its `@neglect v_E*dh/((R_E + h)**2*cos(lat))` (line 22) is a term of the longitude
    # rate: it explains F[dlon, dh], not F[dv_D, dh], whose difference (the gravity
    # gradient written 2g/(R_E + h)) was merely as small and was called its declared drop
    found = {(f.matrix, f.row, f.column): f for f in check.report.findings}
    assert found[("F", "dlon", "dh")].severity == "declared drop"
    assert found[("F", "dv_D", "dh")].severity != "declared drop"
    assert "declares" not in found[("F", "dv_D", "dh")].detail
