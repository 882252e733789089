"""Declared simplifications (``@neglect``) and the ``--json`` summary of a ``@convention``
file (strapdown_ned, φ convention).

The reference row is a researcher's own first-order derivation of the φ-angle north
velocity error equation (ellipsoidal Earth, δω_ie and δω_en through the radii of
curvature): δv̇ = f^n × φ + C_b^n δf − (2ω_ie + ω_en) × δv + v × (2δω_ie + δω_en) + δg,
north row. It agrees with the derived model entry by entry; the textbook drops the
Coriolis term (2ω_ie,D + ω_en,D) δv_E of it.
"""

from __future__ import annotations

import json

import pytest

from ins_errors.checker.convention_equations import check_convention_file, summary_counts
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError

FAST = {"hours": 2.0, "step": 600.0, "effects": False}

RN, RE = "(R_N + h)", "(R_E + h)"
W = "(1 - e2*sin(lat)**2)"
CORIOLIS_E = "(2*omega_ie_D + omega_en_D)*dv_E"
TRANSPORT = (  # v × (2 δω_ie + δω_en), north component
    f"(v_E*(2*(-U*cos(lat)*dr_N/{RN}) + (-dv_E*tan(lat)/{RE} - v_E*dr_N/{RN}/({RE}*cos(lat)**2)"
    f" - v_E*tan(lat)*dr_D/{RE}**2 + v_E*tan(lat)*R_E*e2*sin(lat)*cos(lat)/{W}*dr_N/{RN}/{RE}**2))"
    f" - v_D*((-dv_N/{RN} - v_N*dr_D/{RN}**2"
    f" + v_N*3*R_N*e2*sin(lat)*cos(lat)/{W}*dr_N/{RN}/{RN}**2)))")


def _row(coriolis_e: bool = True) -> str:
    coriolis = ("-((2*omega_ie_E + omega_en_E)*dv_D - " + CORIOLIS_E + ")" if coriolis_e
                else "-((2*omega_ie_E + omega_en_E)*dv_D)")
    return (f"dot(dv_N) = f_E*phi_D - f_D*phi_E + (C11*accel_bias_x + C12*accel_bias_y"
            f" + C13*accel_bias_z) {coriolis} + {TRANSPORT}")


def _file(tmp_path, *lines: str):
    path = tmp_path / "hand.txt"
    path.write_text("\n".join(["@convention phi", *lines]) + "\n")
    return path


def test_the_reference_row_agrees(tmp_path):
    check = check_convention_file(_file(tmp_path, _row()), **FAST)
    assert check.report.findings == []


def test_a_declared_term_left_out_is_a_declared_drop_not_a_mistake(tmp_path):
    undeclared = check_convention_file(_file(tmp_path, _row(coriolis_e=False)), **FAST)
    [f] = undeclared.report.findings
    assert (f.row, f.column, f.severity) == ("dv_N", "dv_E", "mistake")
    assert undeclared.exit_status == 1
    for written in (CORIOLIS_E, "-" + CORIOLIS_E):  # with or without the equation's sign
        path = _file(tmp_path, f"@neglect {written} : Coriolis on δv, textbook",
                     _row(coriolis_e=False))
        check = check_convention_file(path, **FAST)
        [g] = check.report.findings
        assert (g.row, g.column, g.kind, g.severity) == (
            "dv_N", "dv_E", "omitted term", "declared drop")
        assert "declares it leaves out (line 2" in g.detail
        assert g.size == pytest.approx(f.size)
        assert check.exit_status == 0
        assert check.report.idle_declarations == []
        assert summary_counts(check)["findings"]["declared_drops"] == 1


def test_a_declaration_holds_from_its_line_on_and_an_idle_one_is_listed(tmp_path):
    after = check_convention_file(_file(tmp_path, _row(coriolis_e=False),
                                        f"@neglect {CORIOLIS_E}"), **FAST)
    [f] = after.report.findings
    assert f.severity == "mistake"
    assert after.report.idle_declarations == [f"line 3: {CORIOLIS_E}"]


def test_a_declared_term_does_not_hide_a_further_mistake_in_the_same_entry(tmp_path):
    row = _row(coriolis_e=False).replace("-dv_E*tan(lat)", "-2*dv_E*tan(lat)")
    check = check_convention_file(_file(tmp_path, f"@neglect {CORIOLIS_E}", row), **FAST)
    [f] = check.report.findings
    assert (f.column, f.severity) == ("dv_E", "mistake")


@pytest.mark.parametrize("item, message", [
    ("Delta_R_N", "'Delta_R_N' is not a state, error source or named quantity"),
    ("omega_en_D", "no state or error source in it"),
    ("dv_E*dv_N", "not linear"),
    ("dv_E + 1", "a part without a state or error source"),
])
def test_a_neglect_item_without_a_meaning_here_is_refused_in_one_line(tmp_path, item,
                                                                     message):
    path = _file(tmp_path, f"@neglect {item}", _row())
    with pytest.raises(InsErrorsError) as error:
        check_convention_file(path, **FAST)
    text = str(error.value)
    assert message in text and "line 2: @neglect" in text and "\n" not in text


def test_json_has_the_documented_summary(tmp_path, capsys):
    """``check --json`` of a @convention file has ``summary`` with the equation checker's
    keys (docs/hand_check.md)."""
    path = _file(tmp_path, f"@neglect {CORIOLIS_E}", _row(coriolis_e=False),
                 "@scope static base",
                 "dot(phi_E) = omega_in_N*phi_D + omega_in_D*phi_N")  # sign of ω_in,D
    assert main(["check", "strapdown_ned", str(path), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    summary = out["summary"]
    assert summary["equations_by_status"] == {
        "agrees": 0, "agrees_up_to_dropped_small_terms": 0,
        "agrees_up_to_declared_drops": 1, "mistake": 1, "hand_only_definition": 0,
        "tautology": 0, "input_error": 0}
    assert summary["findings"]["mistakes"] == summary["findings"]["root_mistakes"] >= 1
    assert summary["findings"]["declared_drops"] == 1
    assert summary["input_problems"] == 0
    assert out["declarations"] == [f"line 2: {CORIOLIS_E}"]
