"""Hand equations of strapdown_ned in a researcher's convention (``@convention``).

The reference is the textbook φ-angle attitude equation (Titterton and Weston, ch. 12)
written per component, compared with the derived model carried into the φ convention.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ins_errors.checker.convention_equations import check_convention_file
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "strapdown"
FAST = {"hours": 2.0, "step": 600.0, "effects": False}


def _line_of(path: Path, start: str) -> int:
    lines = path.read_text().splitlines()
    return next(n for n, text in enumerate(lines, start=1) if text.startswith(start))


def test_textbook_phi_attitude_equations_agree_on_every_motion():
    check = check_convention_file(EXAMPLES / "phi_attitude.txt", **FAST)
    assert check.report.findings == []
    assert check.exit_status == 0
    # three rows of nine states and three gyro biases, all compared
    assert check.report.compared == 3 * 12
    assert sorted(check.lines) == ["phi_D", "phi_E", "phi_N"]
    assert [label for label, _ in check.report.motions] == ["static", "cruise", "manoeuvre"]


def test_radii_held_fixed_are_dropped_small_terms_only(tmp_path):
    """The common simplification (R_N, R_E constant in δω_en) drops terms, no sign slip."""
    text = (EXAMPLES / "phi_attitude.txt").read_text()
    lines = [line for line in text.splitlines() if not line.startswith("dot(")]
    lines += [
        "dot(phi_N) = omega_in_D*phi_E - omega_in_E*phi_D - U*sin(lat)*dr_N/(R_N + h)"
        " + dv_E/(R_E + h) + v_E*dr_D/(R_E + h)**2"
        " - (C11*gyro_bias_x + C12*gyro_bias_y + C13*gyro_bias_z)",
        "@scope static base",
    ]
    path = tmp_path / "fixed_radii.txt"
    path.write_text("\n".join(lines) + "\n")
    check = check_convention_file(path, **FAST)
    assert check.report.findings == []  # on the static base v = 0: the radii terms vanish
    path.write_text("\n".join(lines[:-1]) + "\n")
    moving = check_convention_file(path, **FAST)
    assert moving.report.findings
    for f in moving.report.findings:
        assert (f.row, f.column) == ("phi_N", "dr_N")
        assert f.size < 1e-3


def test_wrong_sign_is_reported_on_its_line():
    path = EXAMPLES / "phi_attitude_sign_error.txt"
    check = check_convention_file(path, **FAST)
    assert len(check.report.findings) == 1
    f = check.report.findings[0]
    assert (f.matrix, f.row, f.column, f.kind, f.severity) == (
        "F", "phi_E", "phi_N", "wrong sign", "mistake")
    # hand +ω_in,D where −ω_in,D belongs (U sin φ on the static base)
    assert check.line_of(f) == _line_of(path, "dot(phi_E)")
    assert check.exit_status == 1


def test_static_base_entry_is_the_earth_rate(tmp_path):
    """F[phi_E, phi_N] of the derived model is −ω_in,D = U sin φ at rest (φ 50°): the
    east row of −ω_in × φ is ω_in,N φ_D − ω_in,D φ_N."""
    import numpy as np

    path = tmp_path / "one.txt"
    path.write_text("@convention phi\n@scope static base\ndot(phi_E) = 0*phi_N\n")
    check = check_convention_file(path, **FAST)
    f = next(f for f in check.report.findings if f.column == "phi_N")
    assert f.model == pytest.approx(7.292115e-5 * np.sin(np.radians(50.0)), rel=1e-6)


@pytest.mark.parametrize("body, message", [
    ("dot(phi_N) = omega_xx*phi_E", "unknown name 'omega_xx'"),
    ("dot(phi_N) = phi_E**2", "not linear"),
    ("dot(phi_N) = U", "without an error quantity"),
    ("phi_N = phi_E", "left-hand side"),
    ("dot(phi_N) = phi_E\ndot(phi_N) = phi_D", "second equation"),
])
def test_bad_equations_give_one_line_errors(tmp_path, body, message):
    path = tmp_path / "bad.txt"
    path.write_text(f"@convention phi\n{body}\n")
    with pytest.raises(InsErrorsError, match=message):
        check_convention_file(path, **FAST)


def test_cli_unknown_convention_exits_2(tmp_path, capsys):
    path = tmp_path / "bad.txt"
    path.write_text("@convention phy\ndot(phi_N) = phi_E\n")
    assert main(["check", "strapdown_ned", str(path)]) == 2
    err = capsys.readouterr().err
    assert "phy" in err and "Traceback" not in err


def test_vector_line_agrees_and_expands_to_three_rows():
    path = EXAMPLES / "phi_attitude_vector.txt"
    check = check_convention_file(path, **FAST)
    assert check.report.findings == []
    line = _line_of(path, "dot(phi)")
    assert {row: check.lines[row][0] for row in ("phi_N", "phi_E", "phi_D")} == {
        "phi_N": line, "phi_E": line, "phi_D": line}


def test_skew_form_equals_cross_and_a_wrong_cross_sign_is_found(tmp_path):
    text = (EXAMPLES / "phi_attitude_vector.txt").read_text()
    skew = tmp_path / "skew.txt"
    skew.write_text(text.replace("-cross(omega_in, phi)", "-skew(omega_in)*phi"))
    assert check_convention_file(skew, **FAST).report.findings == []
    times = tmp_path / "times.txt"
    times.write_text(text.replace("-cross(omega_in, phi)", "-omega_in × phi"), encoding="utf-8")
    assert check_convention_file(times, **FAST).report.findings == []
    wrong = tmp_path / "wrong.txt"
    wrong.write_text(text.replace("-cross(omega_in, phi)", "+cross(omega_in, phi)"))
    check = check_convention_file(wrong, **FAST)
    # −ω_in × φ has six off-diagonal entries, ω_in,E vanishes on the static base only;
    # each mirror pair (hand − model opposite in the two) is one finding of both
    entries = {(f.row, f.column) for f in check.report.findings} | {
        f.pair for f in check.report.findings}
    assert entries == {(r, c) for r in ("phi_N", "phi_E", "phi_D")
                       for c in ("phi_N", "phi_E", "phi_D") if r != c}
    assert len(check.report.findings) == 3
    assert all(f.kind == "wrong sign" and f.severity == "mistake"
               for f in check.report.findings)
    assert {check.line_of(f) for f in check.report.findings} == {_line_of(wrong, "dot(phi)")}


@pytest.mark.parametrize("body, message", [
    ("dot(phi) = phi_N", "3-vector"),
    ("dot(phi) = cross(omega_xx, phi)", "unknown name 'omega_xx'"),
    ("dot(phi) = cross(omega_in, phi) + C_bn", "cannot evaluate"),
    ("dot(phi) = phi.T", "attribute"),
])
def test_bad_vector_lines_give_one_line_errors(tmp_path, body, message):
    path = tmp_path / "bad.txt"
    path.write_text(f"@convention phi\n{body}\n")
    with pytest.raises(InsErrorsError, match=message):
        check_convention_file(path, **FAST)


@pytest.mark.parametrize("rhs, message", [
    ("__import__('os').system('touch pwned')", "unknown name '__import__'"),
    ("vec(1, 2, 3).__class__", "attribute access is not allowed"),
    ("(phi).__class__.__mro__", "attribute access is not allowed"),
    ("lambda: phi", "unknown name 'lambda'"),
    ("phi[0]", "operator '\\[' is not allowed"),
    ("'phi'", "strings are not allowed in a right-hand side"),
    ("-cross(omega_in, phi", "cannot parse the right-hand side: unclosed parenthesis"),
    ("-cross(omega_in, phi))", "cannot parse the right-hand side: unmatched '\\)'"),
    ("-omega_in × C_bn", "cannot evaluate the right-hand side: a × b needs two 3-vectors"),
])
def test_malicious_or_malformed_vector_rhs_is_refused_in_one_line(tmp_path, monkeypatch,
                                                                 capsys, rhs, message):
    """The right-hand side is read by SymPy's parser over the vector namespace alone: no
    builtins, no attributes, nothing run; every refusal is one line naming the line."""
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "bad.txt"
    path.write_text(f"@convention phi\n# a comment\ndot(phi) = {rhs}\n", encoding="utf-8")
    with pytest.raises(InsErrorsError, match=f"^bad.txt, line 3: {message}"):
        check_convention_file(path, **FAST)
    assert main(["check", "strapdown_ned", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "line 3" in line and "Traceback" not in line
    assert not (tmp_path / "pwned").exists()


def test_a_file_checked_again_reuses_its_row_functions_and_reports_the_same():
    """The rows' numpy functions are kept per expression: a second check of the same
    file compiles nothing new and its report (findings, sizes, effects) is the same."""
    from ins_errors.checker import convention_equations as ce

    path = EXAMPLES / "phi_attitude_sign_error.txt"
    options = {"hours": 2.0, "step": 600.0}
    ce._row_function.cache_clear()
    first = check_convention_file(path, **options)
    built = ce._row_function.cache_info().currsize
    again = check_convention_file(path, **options)
    assert built == 3 and ce._row_function.cache_info().currsize == built
    assert first.report.findings and again.report.findings == first.report.findings
    assert again.report.effects == first.report.effects


def test_meridian_radius_written_as_the_prime_vertical_is_a_symbol_slip(tmp_path):
    """R_E for R_N in dv_N/(R_N + h) of φ̇_E: on the WGS-84 ellipsoid the radii differ by
    under 0.7 %, so the entry alone looks like an approximation; R_N in its place makes
    the line the derived one, so it is a wrong symbol, a mistake at any threshold. The
    radii held fixed (a dropped small term) stay approximations."""
    text = (EXAMPLES / "phi_attitude.txt").read_text()
    written = "- dv_N/(R_N + h) - v_N*dr_D"
    assert text.count(written) == 1
    path = tmp_path / "radius_slip.txt"
    path.write_text(text.replace(written, "- dv_N/(R_E + h) - v_N*dr_D"))
    for threshold in (None, 1e-2):
        check = check_convention_file(path, threshold=threshold, **FAST)
        [f] = check.report.findings
        assert (f.row, f.column, f.kind) == ("phi_E", "dv_N", "wrong symbol or index")
        assert f.detail.startswith("R_E written where R_N belongs")
        assert f.severity == ("mistake" if threshold is None else "mistake, small effect")
        assert check.exit_status == 1
        assert check.line_of(f) == _line_of(path, "dot(phi_E)")
    # the radius a (a sphere) in the same place is an approximation, not a slip
    path.write_text(text.replace(written, "- dv_N/(a + h) - v_N*dr_D"))
    [f] = check_convention_file(path, threshold=1e-2, **FAST).report.findings
    assert (f.kind, f.severity) == ("approximated", "dropped small term")
