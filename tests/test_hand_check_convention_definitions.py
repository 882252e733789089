r"""Definitions in a ``@convention`` file: ``NAME = expression`` lines before the rows
(strapdown_ned, φ convention).

Reference: the textbook φ-angle attitude equation (Titterton and Weston, ch. 12) of
examples/strapdown/phi_attitude.txt, which agrees with the derived model entry by entry.
examples/strapdown/phi_attitude_defined.txt writes the same equation the way the book
does, with the transport rate ρ, the latitude error δL = δr_N/(R_N + h), the change of
the radii and the rate variations δω_ie, δω_en defined first: substituted, it is the
same equation, so its verdicts and entries must be those of phi_attitude.txt, and a
mistake slipped into a definition must show at exactly the entries that use it.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ins_errors.checker.convention_equations import (
    check_convention_file,
    to_json,
    to_terminal,
)
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "strapdown"
DATA = Path(__file__).parent / "data" / "convention"
FAST = {"hours": 2.0, "step": 600.0, "effects": False}
DEFINED = EXAMPLES / "phi_attitude_defined.txt"


def _entries(check) -> list[tuple]:
    return sorted((f.matrix, f.row, f.column, f.kind, f.severity)
                  for f in check.report.findings)


def _variant(tmp_path: Path, source: Path, old: str, new: str) -> Path:
    text = source.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / source.name
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def _line(path: Path, start: str) -> int:
    return next(n for n, text in enumerate(path.read_text().splitlines(), start=1)
                if text.startswith(start))


def test_the_defined_form_agrees_like_the_plain_one():
    defined = check_convention_file(DEFINED, **FAST)
    plain = check_convention_file(EXAMPLES / "phi_attitude.txt", **FAST)
    assert defined.report.findings == plain.report.findings == []
    assert defined.report.compared == plain.report.compared == 3 * 12
    assert sorted(defined.lines) == sorted(plain.lines) == ["phi_D", "phi_E", "phi_N"]
    assert list(defined.definitions)[:2] == ["Omega", "rho_N"]  # Omega is the file's own


def test_the_same_sign_slip_gives_the_same_finding_in_both_forms(tmp_path):
    """−ω_in,D φ_N of the east row written +: the plain file's sign-error example; the
    defined file with the same slip (w_D is ω_in,D) reports the same entry, kind and size."""
    plain = check_convention_file(EXAMPLES / "phi_attitude_sign_error.txt", **FAST)
    path = _variant(tmp_path, DEFINED, "- w_D*phi_N", "+ w_D*phi_N")
    defined = check_convention_file(path, **FAST)
    assert _entries(defined) == _entries(plain) == [
        ("F", "phi_E", "phi_N", "wrong sign", "mistake")]
    [f], [g] = defined.report.findings, plain.report.findings
    assert f.size == pytest.approx(g.size, rel=1e-9)
    assert (f.hand, f.model) == pytest.approx((g.hand, g.model), rel=1e-9)
    assert defined.line_of(f) == _line(path, "dot(phi_E)")
    assert [d.label for d in defined.via_of(f)] == [
        f"Omega, line {_line(path, 'Omega =')}", f"rho_D, line {_line(path, 'rho_D =')}",
        f"w_D, line {_line(path, 'w_D =')}"]


def test_a_wrong_radius_in_a_definition_shows_where_it_is_used(tmp_path):
    """R_N for R_E in ρ_N = v_E/(R_E + h): ρ_N enters ω_in,N only, which the cross
    product −ω_in × φ puts in F[φ_E, φ_D] and F[φ_D, φ_E]; nowhere else. ρ_N changes by
    (R_E − R_N)/(R_N + h), about 0.3 % at 50°, on the moving flights (v_E ≠ 0); ω_in,N
    by less (U cos φ is unchanged)."""
    path = _variant(tmp_path, DEFINED, "rho_N = v_E/(R_E + h)", "rho_N = v_E/(R_N + h)")
    check = check_convention_file(path, **FAST)
    assert {(f.row, f.column) for f in check.report.findings} == {
        ("phi_E", "phi_D"), ("phi_D", "phi_E")}
    rho = _line(path, "rho_N =")
    for f in check.report.findings:
        assert f"rho_N, line {rho}" in [d.label for d in check.via_of(f)]
        assert f.per_motion["static"] < 1e-12  # v_E = 0: ρ_N vanishes with either radius
        assert 1e-4 < abs(f.hand / f.model - 1) < 5e-3
    text = to_terminal(check)
    shown = [row for row in text.splitlines() if "F[phi_E, phi_D]" in row and "via" in row]
    assert shown and shown[0].lstrip().startswith(f"line {_line(path, 'dot(phi_E)')}:")
    assert f"rho_N, line {rho}" in shown[0]
    finding = next(g for g in to_json(check)["findings"] if g["column"] == "phi_D")
    assert {"name": "rho_N", "line": rho} in finding["via"]


def test_a_sign_slip_in_a_state_combination_flips_every_entry_it_feeds(tmp_path):
    """dh = +dr_D (the height is up, δr_D down): dr_D enters the rows through dh alone
    (in δω_en), so all three F[φ, dr_D] entries have the wrong sign, via dh's line."""
    path = _variant(tmp_path, DEFINED, "dh = -dr_D", "dh = dr_D")
    check = check_convention_file(path, **FAST)
    assert _entries(check) == [("F", row, "dr_D", "wrong sign", "mistake")
                               for row in ("phi_D", "phi_E", "phi_N")]
    dh = _line(path, "dh =")
    assert all(f"dh, line {dh}" in [d.label for d in check.via_of(f)]
               for f in check.report.findings)


def test_latex_definitions_agree_with_the_text_form():
    r"""``\rho_N = \frac{v_E}{R_E + h}``, ``\delta L = ...``, ``\Omega = U`` in LaTeX: the
    textbook rows with the radii held fixed give the text file's findings."""
    latex = check_convention_file(DATA / "phi_attitude_textbook_defined.tex", **FAST)
    text = check_convention_file(DATA / "phi_attitude_textbook.txt", **FAST)
    assert _entries(latex) == _entries(text) and latex.report.findings
    assert [f.size for f in sorted(latex.report.findings, key=lambda f: f.entry)] == \
        pytest.approx([f.size for f in sorted(text.report.findings, key=lambda f: f.entry)])
    assert "Delta_lat" in latex.definitions  # \delta L, L being the latitude


def test_a_definition_in_a_vector_line_and_in_a_declared_term(tmp_path):
    vector = (EXAMPLES / "phi_attitude_vector.txt").read_text()
    path = tmp_path / "vector.txt"
    path.write_text(vector.replace("-cross(omega_in, phi)", "-cross(vec(w_N, w_E, w_D), phi)")
                    .replace("@convention phi", "@convention phi\nw_N = omega_in_N\n"
                             "w_E = omega_in_E\nw_D = -U*sin(lat) + omega_en_D"),
                    encoding="utf-8")
    assert check_convention_file(path, **FAST).report.findings == []
    coriolis = "(2*omega_ie_D + omega_en_D)*dv_E"
    row = ("dot(dv_N) = f_E*phi_D - f_D*phi_E - (2*omega_ie_E + omega_en_E)*dv_D"
           " + 0*dr_N")
    hand = tmp_path / "declared.txt"
    hand.write_text(f"@convention phi\n@scope static base\ncoriolis = {coriolis}\n"
                    f"@neglect coriolis : Coriolis on δv\n{row}\n")
    check = check_convention_file(hand, **FAST)
    [f] = check.report.findings
    assert (f.column, f.severity) == ("dv_E", "declared drop")


@pytest.mark.parametrize("body, message", [
    ("phi_N = phi_E", "line 2: left-hand side 'phi_N' is a state of the convention"),
    ("U = 7.29e-5", "line 2: left-hand side 'U' is a named quantity (Earth rotation rate"),
    ("gyro_bias_x = 0", "line 2: left-hand side 'gyro_bias_x' is an error source of the "
     "model"),
    ("Delta_v_N = dv_N", "line 2: left-hand side 'Delta_v_N' is this file's spelling of "
     "'dv_N', a state"),
    ("omega_in = 1", "line 2: left-hand side 'omega_in' is a vector or function of vector "
     "lines"),
    ("dot(phi_N) = rho_N*phi_E\nrho_N = v_E/(R_E + h)",
     "line 2: dot(phi_N) uses rho_N before its definition on line 3"),
    ("a1 = 2*a2\na2 = a1\ndot(phi_N) = a1*phi_E",
     "line 2: a1 and a2 are defined in terms of each other (lines 2 and 3)"),
    ("a1 = a1 + v_E", "line 2: a1 is defined in terms of itself"),
    ("a1 = v_E\na1 = v_N", "line 3: second definition of a1 (first on line 2)"),
    ("x = dv_E*dr_N", "line 2: x is not linear in the states and error sources"),
    ("x = v_E + dv_E", "line 2: x mixes a coefficient (v_E) with states or error sources"),
    ("w = cross(omega_in, phi)", "line 2: the definition of w uses cross(), but a "
     "definition is one scalar"),
    ("x = v_E*foo", "line 2, column 9: unknown name 'foo' in the definition of x"),
    ("@neglect rho_N*dv_E\nrho_N = v_E/(R_E + h)\ndot(phi_N) = rho_N*dv_E",
     "line 2: @neglect rho_N*dv_E uses rho_N before its definition on line 3"),
])
def test_bad_definitions_are_one_line_errors(tmp_path, capsys, body, message):
    path = tmp_path / "bad.txt"
    path.write_text(f"@convention phi\n{body}\n", encoding="utf-8")
    assert main(["check", "strapdown_ned", str(path)]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert f"bad.txt, {message}" in err, err
    assert "\n" not in err and "Traceback" not in err and captured.out == ""


def test_json_lists_the_definitions(tmp_path, capsys):
    path = _variant(tmp_path, DEFINED, "dh = -dr_D", "dh = dr_D")
    assert main(["check", "strapdown_ned", str(path), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["definitions"]["dh"] == _line(path, "dh =")
    assert all({"name": "dh", "line": _line(path, "dh =")} in f["via"]
               for f in out["findings"])


def test_an_alias_in_a_convention_file_is_refused_not_ignored(tmp_path):
    """`@alias` is read by the check of a model's own equations; in a @convention file
    it was silently ignored (the PhD probe's `@alias e = sqrt(e2)`), so the file ran as
    if the line were not there. It is refused, naming the definition line that does the
    same; written that way, the file agrees as before."""
    from ins_errors.errors import InsErrorsError

    aliased = _variant(tmp_path, DEFINED, "Omega = U\n", "@alias Omega = U\n")
    with pytest.raises(InsErrorsError, match=(r"'@alias Omega = U' is not read in a "
                                              r"@convention file; write it as a definition "
                                              r"line, 'Omega = U'")):
        check_convention_file(aliased, **FAST)
    assert check_convention_file(DEFINED, **FAST).report.findings == []


def test_an_up_component_on_the_left_is_the_down_row_negated(tmp_path):
    """An ENU thesis writes dot(phi_U); it was refused with a hint to rewrite it by hand
    (the PhD probe). phi_U is -phi_D exactly: the row is dot(phi_D) = -(...), with the
    same findings as the file written that way."""
    up, down = tmp_path / "enu.txt", tmp_path / "ned.txt"
    up.write_text("@convention phi\ndot(phi_U) = gyro_bias_z\n", encoding="utf-8")
    down.write_text("@convention phi\ndot(phi_D) = -gyro_bias_z\n", encoding="utf-8")
    enu, ned = check_convention_file(up, **FAST), check_convention_file(down, **FAST)
    assert enu.lines == {"phi_D": (2, "dot(phi_U) = gyro_bias_z")}
    shown = [(f.row, f.column, f.kind, f.severity, f.size) for f in enu.report.findings]
    assert shown == [(f.row, f.column, f.kind, f.severity, f.size)
                     for f in ned.report.findings]
