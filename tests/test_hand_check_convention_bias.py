"""Bias states in a ``@convention`` file: ``dot(gyro_bias_x) = 0`` makes the error source a
state, ``@markov SOURCE = TIME`` a first-order Gauss–Markov one.

The reference is the textbook φ-angle attitude equation (Titterton and Weston, ch. 12,
examples/strapdown/phi_attitude.txt), which agrees with the derived model entry by entry
when the gyro biases are G's columns (tests/test_hand_check_convention.py): with the
biases as states the same coefficients sit in F's bias columns, and must agree the same
way; a sign slipped in the bias term is found there, on its line.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ins_errors.checker.convention_equations import check_convention_file, to_json
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "strapdown"
FAST = {"hours": 2.0, "step": 600.0, "effects": False}
GYRO = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z"]


def _file(tmp_path: Path, extra: str, source: str = "phi_attitude.txt",
          replace: tuple[str, str] | None = None) -> Path:
    text = (EXAMPLES / source).read_text(encoding="utf-8")
    if replace is not None:
        assert replace[0] in text
        text = text.replace(*replace)
    path = tmp_path / "hand.txt"
    path.write_text(text + extra, encoding="utf-8")
    return path


@pytest.mark.parametrize("extra, source", [
    ("dot(gyro_bias_x) = 0\ndot(gyro_bias_y) = 0\ndot(gyro_bias_z) = 0\n", "phi_attitude.txt"),
    ("dot(gyro_bias) = vec(0, 0, 0)\n", "phi_attitude_vector.txt"),
])
def test_gyro_bias_states_agree_like_the_g_columns(tmp_path, extra, source):
    check = check_convention_file(_file(tmp_path, extra, source), **FAST)
    report = check.report
    assert [b.name for b in report.bias_states] == GYRO
    assert report.states[-3:] == GYRO and report.sources == []
    assert report.findings == [] and check.exit_status == 0
    # three attitude rows and three bias rows, each over nine states and three biases
    assert report.compared == 6 * 12
    assert sorted(check.lines) == sorted(["phi_N", "phi_E", "phi_D", *GYRO])
    assert to_json(check)["bias_states"][0] == {"name": "gyro_bias_x",
                                                "statistics": "constant", "tau_s": None,
                                                "rate_per_s": 0.0}


def test_a_sign_slip_in_a_bias_column_is_found_on_its_line(tmp_path):
    path = _file(tmp_path, "dot(gyro_bias) = vec(0, 0, 0)\n",
                 replace=("- (C31*gyro_bias_x + C32*gyro_bias_y + C33*gyro_bias_z)",
                          "- (C31*gyro_bias_x + C32*gyro_bias_y - C33*gyro_bias_z)"))
    check = check_convention_file(path, **FAST)
    [f] = check.report.findings
    assert (f.matrix, f.row, f.column, f.kind, f.severity) == (
        "F", "phi_D", "gyro_bias_z", "wrong sign", "mistake")
    assert f.hand == pytest.approx(-f.model) and f.model == pytest.approx(-1.0, abs=0.05)
    assert check.line_of(f) == next(
        n for n, line in enumerate(path.read_text().splitlines(), 1)
        if line.startswith("dot(phi_D)"))


def test_a_declared_markov_bias_agrees_with_its_row(tmp_path):
    agree = check_convention_file(_file(tmp_path, "@markov gyro_bias_z = 1 h\n"
                                        "dot(gyro_bias) = vec(0, 0, -gyro_bias_z/3600)\n"),
                                  **FAST)
    assert agree.report.findings == []
    assert [b.tau for b in agree.report.bias_states] == [None, None, 3600.0]
    # the same row without the declaration: the model's bias is a random constant
    extra = check_convention_file(_file(tmp_path, "dot(gyro_bias) = vec(0, 0, "
                                        "-gyro_bias_z/3600)\n"), **FAST)
    [f] = extra.report.findings
    assert (f.row, f.column, f.kind, f.severity) == ("gyro_bias_z", "gyro_bias_z",
                                                     "extra term", "mistake")
    assert f.hand == pytest.approx(-1 / 3600) and "τ = 3600 s" in f.detail


@pytest.mark.parametrize("extra, message", [
    ("@markov gyro_bias_y = 1 h\ndot(gyro_bias_x) = 0\n",
     "@markov gives a correlation time for 'gyro_bias_y', which is not a bias state"),
    ("@markov gyro_bias_x = 0 s\ndot(gyro_bias_x) = 0\n",
     "a correlation time of 0 is white noise, which cannot be a state"),
    ("dot(initial_roll_error) = 0\n", "or of an error source carried as a bias state"),
    # a duplicate is refused as a duplicate definition is (the last one silently won)
    ("@markov gyro_bias_x = 1 h\n@markov gyro_bias_x = 2 h\ndot(gyro_bias_x) = 0\n",
     "line {second}, column 1: second @markov of gyro_bias_x (first on line {first})"),
    ("@markov gyro_bias_x = 1 h\n@markov b_gx = 2 h\ndot(gyro_bias_x) = 0\n",
     "hand.txt, line {second}: second @markov of gyro_bias_x (first on line {first})"),
    # its errors name their line; white noise says what an @convention file does
    ("dot(gyro_bias_x) = 0\n@markov gyro_bias_x = 0 s\n",
     "hand.txt, line {second}: @markov gyro_bias_x: a correlation time of 0 is white noise, which "
     "cannot be a state: write the source in the rows without a line dot(SOURCE)"),
    ("@markov gyro_bias_x = 3 m\ndot(gyro_bias_x) = 0\n", "hand.txt, line {first}: @markov"),
    ("@markov gyro_bias_y = 1 h\ndot(gyro_bias_x) = 0\n", "hand.txt, line {first}: @markov gives"),
])
def test_bad_bias_lines_are_one_line_errors(tmp_path, capsys, extra, message):
    path = _file(tmp_path, extra)
    first = len((EXAMPLES / "phi_attitude.txt").read_text(encoding="utf-8").splitlines()) + 1
    message = message.format(first=first, second=first + 1)
    assert main(["check", "strapdown_ned", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and "Traceback" not in err, err


def test_a_markov_line_after_its_row_declares_it_as_before(tmp_path):
    # docs/hand_check.md: the place of the @markov line in the file does not matter
    before = check_convention_file(_file(tmp_path, "@markov gyro_bias_z = 1 h\n"
                                         "dot(gyro_bias) = vec(0, 0, -gyro_bias_z/3600)\n"),
                                   **FAST)
    after = check_convention_file(_file(tmp_path, "dot(gyro_bias) = vec(0, 0, "
                                        "-gyro_bias_z/3600)\n@markov gyro_bias_z = 1 h\n"),
                                  **FAST)
    assert after.report.findings == before.report.findings == []
    assert [b.tau for b in after.report.bias_states] == [None, None, 3600.0]


def test_markov_outside_a_convention_file_is_refused(tmp_path, capsys):
    path = tmp_path / "plain.txt"
    path.write_text("@markov gyro_bias_x = 1 h\n"
                    "dot(delta_lat) = delta_v_N/(R_N + h)\n", encoding="utf-8")
    assert main(["check", "strapdown_ned", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "@markov gyro_bias_x applies to a bias state of a file with '@convention" in err
