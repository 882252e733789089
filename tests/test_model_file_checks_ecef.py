"""Authoring mistakes in an ECEF strapdown model file are refused in one line (exit 2).

The model is tests/models/ecef_ins.py (C_b^e, v^e, r^e; point-mass gravity μ/|r|²,
centrifugal Ω×(Ω×r), Coriolis 2Ω×v), copied with one deliberate mistake:

* a real work that lacks the centrifugal or the Coriolis term, or carries an extra
  0.01 U² r_X, does not reduce to the ideal work. At the Earth's values these terms are
  real physics (U² R = 0.034 m/s², 2 U v = 0.015 m/s² at 100 m/s), but at the states the
  check draws (|r| ~ 0.5 m) with μ at its default the gravity is ~1e15 m/s², and all
  three were under the tolerance: the check now also draws the parameters;
* a unit whose scale to SI is not 1 (an Earth rate in deg/h, μ in km³/s², a position in
  km) was used as if SI (U = 15.041 "deg/h" is 15 rad/s: a Schuler period of 0.42 s);
* a 3 x 3 matrix inside the list of a right-hand side gave SymPy's bare "mismatched
  dimensions";
* a sum 1 + R/|r|² (1 and 1/m) was blamed on the sum around it.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from ins_errors.cli import main
from tests.helpers import fresh_model_cache

ECEF = Path(__file__).resolve().parent / "models" / "ecef_ins.py"


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Generated code of model files goes to a fresh cache per test."""
    return fresh_model_cache(tmp_path, monkeypatch)


def variant(tmp_path: Path, *replacements: tuple[str, str], name: str = "my_ecef.py") -> Path:
    """A copy of the ECEF model file with text replacements."""
    text = ECEF.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new)
    target = tmp_path / name
    target.write_text(text, encoding="utf-8")
    return target


def refusal(path: Path, capsys) -> str:
    """The one line `ins-errors models FILE` refuses the file with (exit status 2)."""
    assert main(["models", str(path)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ins-errors: error: "), captured.err
    assert "Traceback" not in captured.err
    return lines[0]


def accepted(path: Path, capsys) -> None:
    assert main(["models", str(path)]) == 0, capsys.readouterr().err
    capsys.readouterr()


CENTRIFUGAL = "gravity = -mu / rho**3 * r - earth.cross(earth.cross(r))"
CORIOLIS = "- 2 * earth.cross(v)"
REAL_RHS = "real_rhs=sp.Matrix(navigator(real, computed, gyros, accels)),"
REAL_WORK_MISTAKES = {
    "no_centrifugal": [(CENTRIFUGAL, "gravity = -mu / rho**3 * r - (0 if eq.computed else 1) "
                                     "* earth.cross(earth.cross(r))")],
    "no_coriolis": [(CORIOLIS, "- (0 if eq.computed else 2) * earth.cross(v)")],
    "not_ideal": [(REAL_RHS, "real_rhs=sp.Matrix(navigator(real, computed, gyros, accels)) "
                             "+ sp.Matrix([0] * 9 + [SYMBOL['U']**2 * computed[12] / 100] "
                             "+ [0] * 5),")],
}


def test_real_work_without_centrifugal_or_coriolis_term_is_refused(tmp_path, capsys):
    """Each mistake leaves a term of the velocity rows that no error source multiplies:
    refused naming the row. The same terms written another way (-Ω×(Ω×r) as
    U² (r_X, r_Y, 0), -2Ω×v as 2U (v_Y, -v_X, 0)) are the same real work
    at every value of every symbol and pass: drawing the parameters refuses no right
    model."""
    for name, replacements in REAL_WORK_MISTAKES.items():
        line = refusal(variant(tmp_path, *replacements, name=f"{name}.py"), capsys)
        assert "does not reduce to the ideal work" in line, line
        assert re.search(r"real-work equation for 'delta_v_[XY]'", line), line
    rewritten = variant(
        tmp_path,
        (CENTRIFUGAL, "gravity = -mu / rho**3 * r + (sp.Matrix([U**2 * r[0], U**2 * r[1], "
                      "0]) if eq.computed else -earth.cross(earth.cross(r)))"),
        (CORIOLIS, "- (sp.Matrix([-2 * U * v[1], 2 * U * v[0], 0]) if eq.computed "
                   "else 2 * earth.cross(v))"),
        name="rewritten.py")
    accepted(rewritten, capsys)
    accepted(ECEF, capsys)


def test_earth_rate_in_deg_per_hour_is_refused_with_the_si_default(tmp_path, capsys):
    """U declared in deg/h with 15.041 would be taken as 15.041 rad/s. The line names U
    and its unit, says to declare rad/s and gives the default in rad/s, which is the
    sidereal rate 2π/86164.1 s = 7.2921e-5 rad/s (15.041 deg/h = 15.041 π/180/3600)."""
    path = variant(tmp_path, ('Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE)',
                              'Parameter("U", "deg/h", "Earth rate", "U", 15.041)'))
    line = refusal(path, capsys)
    assert "parameter 'U': unit 'deg/h' is not coherent SI" in line, line
    assert "declare 'rad/s'" in line and "-p U=15.041deg/h" in line, line
    suggested = float(re.search(r"15.041 deg/h is ([0-9.e+-]+) rad/s", line).group(1))
    assert suggested == pytest.approx(2 * math.pi / 86164.1, rel=1e-4)
    # the suggestion, written into the file, is accepted
    fixed = variant(tmp_path, ('Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE)',
                               f'Parameter("U", "rad/s", "Earth rate", "U", {suggested!r})'),
                    name="fixed.py")
    accepted(fixed, capsys)


@pytest.mark.parametrize(("old", "new", "words"), [
    ('Parameter("mu", "m**3/s**2"', 'Parameter("mu", "km**3/s**2"',
     ["parameter 'mu': unit 'km**3/s**2'", "1e+09 m**3/s**2", "declare 'm**3/s**2'"]),
    ('Variable(f"r_{k}", "m"', 'Variable(f"r_{k}", "km"',
     ["state 'r_X': unit 'km'", "(1 km = 1000 m)", "declare 'm'"]),
    ('error_source(f"gyro_bias_{a}", "rad/s", "deg/h"',
     'error_source(f"gyro_bias_{a}", "deg/h", "deg/h"',
     ["error source 'gyro_bias_x': unit 'deg/h'", "declare 'rad/s'",
      "keep 'deg/h' as its display unit"]),
    ('Variable("height", "m", "initial height", "h_0")',
     'Variable("height", "km", "initial height", "h_0")',
     ["initial condition 'height': unit 'km'", "declare 'm'"]),
], ids=["mu_km3", "state_km", "source_deg_h", "initial_km"])
def test_unit_not_coherent_si_is_refused(old, new, words, tmp_path, capsys):
    """Only dimensions were compared, so km for a state whose rate is a velocity in m/s,
    or μ in km³/s² (g = 0.0218 m/s² at the default 3.986e14), passed."""
    line = refusal(variant(tmp_path, (old, new)), capsys)
    assert "is not coherent SI" in line, line
    for word in words:
        assert word in line, (word, line)


def test_matrix_inside_the_list_of_a_right_hand_side_is_named(tmp_path, capsys):
    """[C_dot, *v_dot, *v] with a 3 x 3 C_dot: SymPy says only "mismatched dimensions".
    Given to sp.Matrix in build(), the line names the file's line (ideal_rhs) and the
    entry; given as the right-hand side itself, the check names ideal_rhs and its shape,
    15 x 1."""
    mixed = ("return [*C_dot, *v_dot, *v]", "return [C_dot, *v_dot, *v]")
    line = refusal(variant(tmp_path, mixed), capsys)
    assert "mismatched dimensions" not in line, line
    assert "ideal_rhs=sp.Matrix(navigator(ideal, x, rate, force))" in line, line
    assert "a list of 7 entries: entry 1 is a 3 x 3 matrix, the others scalars" in line, line
    assert "unpack a matrix into the list with *" in line, line
    direct = variant(tmp_path, mixed, ("sp.Matrix(navigator(", "(navigator("), name="direct.py")
    line = refusal(direct, capsys)
    assert "ideal_rhs: must be a column (15 x 1, one expression per state), got a list of " \
           "7 entries: entry 1 is a 3 x 3 matrix" in line, line


def test_inconsistent_sum_is_named_where_it_is(tmp_path, capsys):
    """A gravity factor 1 + R/|r|² (a J2 factor written a/r² for a²/r²) adds a pure
    number and a quantity in 1/m: the line names that sum, not the sum of the specific
    force (m/s²) and the gravity (1/s²) around it. Written right, 1 + R²/(100 |r|²) is a
    pure number and passes."""
    line = refusal(variant(tmp_path, (CENTRIFUGAL, CENTRIFUGAL.replace(
        "* r -", '* (1 + SYMBOL["R"] / rho**2) * r -'))), capsys)
    assert "has a sum of 1 (a pure number) and R/rho**2 (1/m)" in line, line
    assert "f_x" not in line, line
    accepted(variant(tmp_path, (CENTRIFUGAL, CENTRIFUGAL.replace(
        "* r -", '* (1 + sp.Rational(1, 100) * SYMBOL["R"]**2 / rho**2) * r -')),
        name="right.py"), capsys)
