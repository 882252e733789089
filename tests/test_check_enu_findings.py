"""An ENU researcher's own model file checked with ENU hand models (the enuframe probe).

* ``--matrix`` with ENU state names (``phi_U``, ``dv_U``) reads them as the convention's
  ``-phi_D``, ``-dv_D`` as a ``@convention`` file does: the findings are those of the
  same function converted to NED by hand (a permutation with the up rows negated,
  written in the fixture), and an up row's finding names the entry as written.
* A factor on one term of an entry that holds others (2Ω sin φ written Ω sin φ beside
  the transport rate) and a unit slip (the Earth rate written 15.041, deg/h, where the
  model has rad/s) are named, not left as a bare ``wrong coefficient``.
* A term present but wrong below the threshold is a mistake; the report's words say so
  instead of printing ``(small)`` under ``Mistakes``.

One model file (tests/models/enu_euler_sphere.py: ENU, sphere, constant g, Euler
angles), derived once and cached; the hand files are one line of
data/convention/enu_euler_ok.txt changed each.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from ins_errors.checker.convention_equations import check_convention_file
from ins_errors.checker.convention_equations import to_terminal as convention_terminal
from ins_errors.checker.matrix import check_matrices
from ins_errors.checker.matrix_report import to_terminal
from ins_errors.checker.ratio_names import factor_name
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.modeling import EARTH_RATE

HERE = Path(__file__).resolve().parent
MODEL = str(HERE / "models" / "enu_euler_sphere.py")
MATRIX = HERE / "data" / "enu_matrix.py"
OK = HERE / "data" / "convention" / "enu_euler_ok.txt"
FAST = {"hours": 2.0, "step": 600.0, "effects": False}


def _variant(tmp_path: Path, old: str, new: str, name: str) -> Path:
    """enu_euler_ok.txt with one piece of one line changed (it must be there once)."""
    text = OK.read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / name
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def _key(report) -> list[tuple]:
    return sorted((f.matrix, f.row, f.column, f.kind, f.severity, f.hand, f.model, f.size)
                  for f in report.findings)


@pytest.fixture(scope="module")
def ok_check():
    """The correct ENU hand file (derives the model file once for the module)."""
    return check_convention_file(OK, MODEL, **FAST)


def test_the_correct_enu_file_agrees(ok_check):
    assert ok_check.report.findings == []
    assert ok_check.report.written == {"phi_D": "phi_U", "dv_D": "dv_U"}


# ---------------------------------------------------------------- 1. --matrix in ENU names
@pytest.mark.parametrize("function", ["enu_model", "enu_model_up_slip"])
def test_an_enu_matrix_function_gets_the_findings_of_its_ned_twin(ok_check, function):
    enu = check_matrices(MODEL, f"{MATRIX}:{function}", "phi_geodetic", effects=False)
    ned = check_matrices(MODEL, f"{MATRIX}:{function}_ned", "phi_geodetic", effects=False)
    assert enu.compared == ned.compared == 135
    assert _key(enu) == _key(ned)  # the same entries, kinds, values and sizes
    assert enu.written == {"phi_D": "phi_U", "dv_D": "dv_U"} and ned.written == {}
    if function == "enu_model":
        assert enu.findings == []
        return
    # the Earth-rate term of F[phi_U, dlat] doubled: F[phi_D, dlat] = -F[phi_U, dlat]
    (f,) = enu.findings
    assert (f.matrix, f.row, f.column, f.severity) == ("F", "phi_D", "dlat", "mistake")
    # the file's phi_U row holds 2 U cos φ where U cos φ belongs: the phi_D row -2 U cos φ
    assert "hand/model of that term = 2 at every sample: a factor 2 too many?" in f.detail
    text = to_terminal(enu)
    assert "F[phi_D, dlat] (your F[phi_U, dlat], sign flipped): wrong coefficient" in text
    assert "up components read as the convention's down ones: phi_U = -phi_D, " \
           "dv_U = -dv_D" in text
    assert "(your " not in to_terminal(ned)


def test_an_up_state_beside_its_down_state_is_refused():
    with pytest.raises(InsErrorsError, match=r"^enu_matrix.py:enu_model_both: states "
                       r"'phi_U' and 'phi_D' are one state \(phi_U = -phi_D\): give one "
                       r"of them$"):
        check_matrices(MODEL, f"{MATRIX}:enu_model_both", "phi_geodetic", effects=False)


def test_the_command_checks_an_enu_function(ok_check, capsys):
    status = main(["check", MODEL, "--matrix", f"{MATRIX}:enu_model_up_slip",
                   "--convention", "phi_geodetic", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert status == 1
    assert data["up_components"] == {"phi_U": "phi_D", "dv_U": "dv_D"}
    (f,) = data["findings"]
    assert (f["row"], f["column"], f["as_written"]) == (
        "phi_D", "dlat", "your F[phi_U, dlat], sign flipped")


# ------------------------------------------------- 2. a factor of one term, a unit slip
def test_coriolis_written_once_is_a_factor_half_of_that_term(ok_check, tmp_path):
    path = _variant(tmp_path, "dot(dv_E) = f_N*phi_U - f_U*phi_N + (2*U*sin(lat)",
                    "dot(dv_E) = f_N*phi_U - f_U*phi_N + (U*sin(lat)", "m2.txt")
    check = check_convention_file(path, MODEL, **FAST)
    (f,) = check.report.findings
    assert (f.row, f.column, f.kind) == ("dv_E", "dv_N", "wrong coefficient")
    # the entry is 2U sin φ + v_E tan φ/r: its ratio is 1/2 only at rest
    assert f.per_motion["cruise"] > 0 and f.per_motion["static"] > 0
    assert "one term of the entry with a wrong factor, the rest agrees" in f.detail
    assert "hand/model of that term = 0.5 at every sample: a factor 1/2 too many?" \
        in f.detail, f.detail


def test_the_earth_rate_in_deg_per_hour_is_a_unit_slip(ok_check, tmp_path):
    path = _variant(tmp_path, "dwU = U*cos(lat)*dlat", "dwU = 15.041*cos(lat)*dlat",
                    "m5.txt")
    check = check_convention_file(path, MODEL, **FAST)
    (f,) = check.report.findings
    assert (f.row, f.column, f.kind, f.size_class) == ("phi_D", "dlat",
                                                       "wrong coefficient", "major")
    factor = 15.041 / EARTH_RATE  # the term's hand/model: 15.041 for U
    assert f"hand/model of that term = {factor:.6g} at every sample: a unit slip? " \
           "206265 = rad → arcsec, or rad/s → deg/h" in f.detail, f.detail
    # the hand wrote the up row: named as written, its value minus the file's own
    line = [t for t in convention_terminal(check).splitlines() if t.startswith("  line ")]
    assert line == [line[0]] and "F[phi_D, dlat] (your F[phi_U, dlat], sign flipped)" \
        in line[0]


UNIT_RATIOS = [(180 / math.pi * 3600, "206265"), (15.041 / EARTH_RATE, "206265"),
               (-57.3, "−57.2958"), (math.pi / 180, "1/57.2958"), (3600.0, "3600"),
               (1 / 3600.0, "1/3600"), (1 / 206264.8, "1/206265")]


def test_unit_factors_are_named_and_other_ratios_are_not():
    for ratio, name in UNIT_RATIOS:  # rad ↔ arcsec, deg/h ↔ rad/s, deg ↔ rad, s ↔ h
        found = factor_name(ratio, [])
        assert found is not None and found[0] == name, ratio
        assert found[1].startswith(f"a unit slip? {name.lstrip('−')} = "), found
    for ratio in (57.5, 3610.0, 2.0e5, 1.0, 0.7):  # more than 1e-3 off any of them
        assert factor_name(ratio, []) is None, ratio


# ------------------------------------------------------ 3. small, yet a mistake: words
def test_a_small_extra_term_is_a_mistake_and_the_words_say_so(ok_check, tmp_path):
    # the centripetal acceleration's change with latitude, which a sphere with constant
    # g leaves out, added to the north velocity row's δφ coefficient (Coriolis'):
    # U² r sin φ cos φ δφ, a term there but wrong of size ~3e-5
    path = _variant(tmp_path, "dot(dv_N) = f_U*phi_E - f_E*phi_U",
                    "dot(dv_N) = U**2*r*sin(lat)*cos(lat)*dlat + f_U*phi_E - f_E*phi_U",
                    "small.txt")
    check = check_convention_file(path, MODEL, **FAST)
    (f,) = check.report.findings
    assert (f.row, f.column, f.kind) == ("dv_N", "dlat", "wrong coefficient")
    assert f.size < check.report.threshold and f.severity == "mistake, small effect"
    text = convention_terminal(check)
    summary = [t for t in text.splitlines() if "entries compared" in t]
    assert summary == ["135 entries compared: 134 agree, 0 dropped small terms, 1 mistake "
                       "(1 of them below the threshold 0.001: a term there but wrong is a "
                       "mistake whatever its size; only a small term left out is a dropped "
                       "small term)"]
    listed = text.split("Mistakes:\n", 1)[1].split("\n\n", 1)[0]
    assert "(small)" not in listed
    assert "(small, below the threshold 0.001: still a mistake, the term is there but " \
           "wrong)" in listed
