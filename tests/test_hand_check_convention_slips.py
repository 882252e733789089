r"""Index slips under ``@convention`` (strapdown_ned, φ convention) and in ``--matrix``.

Reference: the φ-angle velocity error equation, north and east rows (Titterton and
Weston, ch. 12), δv̇ = f^n × φ + C_b^n δf − (2ω_ie + ω_en) × δv + v × (2δω_ie + δω_en),
written in tests/data/convention/phi_velocity.txt with its intermediate quantities
defined first; it agrees with the derived model entry by entry. The cross product's
components are (f_E φ_D − f_D φ_E, f_D φ_N − f_N φ_D, …): a slipped index puts a term
on the wrong column. Such a slip is one mistake of kind "wrong symbol or index", found
in both entries it touches, not an extra and an omitted term (or two wrong
coefficients); what is not a slip keeps its kind.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ins_errors.checker.convention_equations import check_convention_file
from ins_errors.checker.matrix import check_matrices

ROOT = Path(__file__).resolve().parents[1]
VELOCITY = Path(__file__).parent / "data" / "convention" / "phi_velocity.txt"
FAST = {"hours": 2.0, "step": 600.0, "effects": False}
SLIP = "wrong symbol or index"
NORTH = "dot(dv_N) = f_E*phi_D - f_D*phi_E"
EAST = "dot(dv_E) = f_D*phi_N - f_N*phi_D"


def _check(tmp_path: Path, old: str, new: str):
    text = VELOCITY.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / "slip.txt"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return check_convention_file(path, **FAST)


def _found(check) -> dict[tuple[str, str, str], tuple[str, str]]:
    return {(f.matrix, f.row, f.column): (f.kind, f.severity) for f in check.report.findings}


def test_the_reference_rows_agree():
    check = check_convention_file(VELOCITY, **FAST)
    assert check.report.findings == []
    assert check.report.compared == 2 * (9 + 3)  # nine states, three accelerometer biases


def test_a_swapped_cross_product_index_is_one_slip(tmp_path):
    """f_D φ_N for f_D φ_E in the north row: F[dv_N, φ_N] holds the derived F[dv_N, φ_E]
    = −f_D (about g: f_D ≈ −g in level flight) and F[dv_N, φ_E] the derived 0."""
    check = _check(tmp_path, NORTH, "dot(dv_N) = f_E*phi_D - f_D*phi_N")
    assert _found(check) == {("F", "dv_N", "phi_N"): (SLIP, "mistake"),
                             ("F", "dv_N", "phi_E"): (SLIP, "mistake")}
    north = check.report.finding("dv_N", "phi_N")
    east = check.report.finding("dv_N", "phi_E")
    assert north.hand == pytest.approx(9.8, rel=0.02) and east.model == pytest.approx(
        9.8, rel=0.02)
    assert "is the derived F[dv_N, phi_E]" in north.detail
    assert "is the derived F[dv_N, phi_N]" in east.detail


@pytest.mark.parametrize("row, columns", [
    ("dot(dv_E) = f_D*phi_D - f_N*phi_N", ("phi_N", "phi_D")),       # both swapped
    ("dot(dv_N) = f_E*phi_N - f_D*phi_D", ("phi_N", "phi_E", "phi_D")),  # rotated
    ("dot(dv_E) = f_D*phi_N - f_N*phi_N", ("phi_N", "phi_D")),       # one term moved
])
def test_permuted_and_moved_terms_are_slips(tmp_path, row, columns):
    old = EAST if row.startswith("dot(dv_E)") else NORTH
    check = _check(tmp_path, old, row)
    name = row[4:8]
    assert _found(check) == {("F", name, c): (SLIP, "mistake") for c in columns}


def test_a_slipped_source_index_is_a_slip_in_g(tmp_path):
    check = _check(tmp_path, "C12*accel_bias_y", "C12*accel_bias_x")
    assert _found(check) == {("G", "dv_N", "accel_bias_x"): (SLIP, "mistake"),
                             ("G", "dv_N", "accel_bias_y"): (SLIP, "mistake")}
    assert "index slip with G[dv_N, accel_bias_y]" in check.report.finding(
        "dv_N", "accel_bias_x", "G").detail


def test_a_slip_through_definitions_names_their_lines(tmp_path):
    """The Coriolis coefficients c_E, c_D (defined lines) put on each other's column."""
    check = _check(tmp_path, "- (c_E*dv_D - c_D*dv_E)", "- (c_E*dv_E - c_D*dv_D)")
    assert _found(check) == {("F", "dv_N", "dv_D"): (SLIP, "mistake"),
                             ("F", "dv_N", "dv_E"): (SLIP, "mistake")}
    lines = VELOCITY.read_text().splitlines()
    for column, defined in (("dv_E", "c_E"), ("dv_D", "c_D")):  # the hand's entry's way
        at = 1 + next(n for n, text in enumerate(lines) if text.startswith(f"{defined} ="))
        assert f"{defined}, line {at}" in [d.label for d in check.via_of(
            check.report.finding("dv_N", column))]


def test_a_wrong_index_of_a_quantity_is_a_slip(tmp_path):
    """f_E φ_E for f_D φ_E: with f_D for f_E the entry is the derived one."""
    check = _check(tmp_path, NORTH, "dot(dv_N) = f_E*phi_D - f_E*phi_E")
    [f] = check.report.findings
    assert (f.column, f.kind, f.severity) == ("phi_E", SLIP, "mistake")
    assert f.detail.startswith("f_E written where f_D belongs")


@pytest.mark.parametrize("old, new, expected", [
    (NORTH, "dot(dv_N) = f_E*phi_D - 2*f_D*phi_E", {("phi_E", "wrong coefficient")}),
    (NORTH, "dot(dv_N) = f_E*phi_D + f_D*phi_E", {("phi_E", "wrong sign")}),
    ("+ c_D*dv_E", "", None),  # the Coriolis term left out
    (NORTH, "dot(dv_N) = f_N*phi_N - f_D*phi_E", {("phi_D", "omitted term"),
                                                  ("phi_N", "extra term")}),
])
def test_what_is_no_slip_keeps_its_kind(tmp_path, old, new, expected):
    if expected is None:  # '- (c_E*dv_D - c_D*dv_E)' without its second term
        old, new = "- (c_E*dv_D - c_D*dv_E)", "- (c_E*dv_D)"
        expected = {("dv_E", "omitted term")}
    check = _check(tmp_path, old, new)
    assert {(f.column, f.kind) for f in check.report.findings} == expected


def test_the_textbook_psi_model_has_no_slip():
    """The ψ model's 22 drops (R = a, g/R) are approximations, none exactly another
    entry of its row."""
    report = check_matrices("strapdown_ned", str(ROOT / "examples" / "strapdown"
                                                 / "psi_model.py") + ":psi_model", "psi",
                            **FAST)
    assert len(report.findings) == 22 and SLIP not in {f.kind for f in report.findings}


def test_a_hand_coded_matrix_with_swapped_columns(tmp_path):
    """--matrix: the ψ model with f_n × ψ's north row written on swapped columns."""
    module = tmp_path / "swapped.py"
    module.write_text(
        "import sys\n"
        f"sys.path.insert(0, {str(ROOT / 'examples' / 'strapdown')!r})\n"
        "from psi_model import STATES, SOURCES, psi_model\n\n\n"
        "def swapped(nav, imu):\n"
        "    F, G = psi_model(nav, imu)\n"
        "    F[3, [1, 2]] = F[3, [2, 1]]\n"
        "    return F, G\n")
    report = check_matrices("strapdown_ned", f"{module}:swapped", "psi", **FAST)
    slips = {(f.row, f.column) for f in report.findings if f.kind == SLIP}
    assert slips == {("dvc_N", "psi_E"), ("dvc_N", "psi_D")}
    assert len(report.findings) == 24  # the 22 drops and the slip's two entries
