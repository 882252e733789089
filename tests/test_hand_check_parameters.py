"""``ins-errors check -p NAME=VALUE``: model parameters in the checker, and the damping
gains left at 0.

A term multiplied by a parameter that is 0 is 0 at every point where the checker
evaluates the model and the hand file, whatever its sign or factor: strapdown_ned's
height line is ``δḣ = −δv_D − k_h1 δh`` (the barometer loop closes on the height
difference), and with the default k_h1 = 0 a hand line with ``+7 k_h1 δh`` agrees. With
``-p k_h1=0.03/s`` the term is a number (−0.03/s against the hand's +0.21/s), so a wrong
sign or factor is found; without it, a warning says the gain's terms are not checked and
how to set it. The same parameters reach the matrix check and ``@convention`` files,
whose derived model is evaluated along motions flown (and stored) with them. Setting a
parameter to its default changes no report, bit for bit.
"""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pytest

from ins_errors.cli import main
from ins_errors.model_lookup import definition_of, resolve

ROOT = Path(__file__).resolve().parents[1]
PSI_MODEL = f"{ROOT / 'examples' / 'strapdown' / 'psi_model.py'}:psi_model"
ENU_MODEL = Path(__file__).resolve().parent / "models" / "enu_strapdown.py"
DAMPED = ["-p", "k_h1=0.0293/s", "-p", "k_h2=4.42e-4/s^2"]


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    status = main(["check", *argv])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def _hand(tmp_path, text: str, name: str = "hand.txt") -> str:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return str(path)


def _findings(out: str) -> list[dict]:
    return [f for eq in json.loads(out)["equations"] for f in eq["findings"]]


def test_a_damping_term_is_checked_when_its_gain_is_set(tmp_path, capsys):
    hand = _hand(tmp_path, "dot(delta_h) = -delta_v_D + k_h1*delta_h\n")  # sign slip
    status, out, err = _run(capsys, "strapdown_ned", hand, "--json", "-p", "k_h1=0.03/s")
    assert status == 1
    (finding,) = _findings(out)
    assert (finding["quantity"], finding["kind"], finding["class"]) == (
        "delta_h", "wrong sign", "mistake")
    assert json.loads(out)["parameters"] == {"k_h1": {"value": 0.03, "unit": "1/s"}}
    assert "warning" not in err
    # the gain and its sign slip give the height loop a mode growing ×e every 1/(2 k_h1)
    # (hand +k_h1 against the model's −k_h1, at the static base nothing else in the row)
    effect = finding["effect"]
    assert effect["exponential_1h"] and effect["growing_mode"] == "hand"
    assert effect["e_folding_s"] == pytest.approx(1 / 0.03, rel=0.05)


def test_a_gain_left_at_zero_is_named_in_one_warning(tmp_path, capsys):
    hand = _hand(tmp_path, "dot(delta_h) = -delta_v_D + 7*k_h1*delta_h\n")
    status, out, err = _run(capsys, "strapdown_ned", hand)
    assert status == 0                       # 7·0 = −0: the term cannot be compared
    (line,) = err.splitlines()
    assert line.startswith("ins-errors: warning: terms multiplied by a damping gain at 0 "
                           "are not checked")
    assert "k_h1 is 0" in line and "`-p k_h1=0.0293/s`" in line and "k_h2" not in line
    status, out, err = _run(capsys, "strapdown_ned", hand, "--json", "-p", "k_h1=0.0293/s")
    assert status == 1 and err == ""
    (finding,) = _findings(out)
    assert finding["quantity"] == "delta_h" and finding["class"] == "mistake"
    assert "hand/model = -7" in finding["detail"]
    # a line that holds no gain gets no warning (the attitude lines of the same model)
    hand = _hand(tmp_path, "dot(delta_lon) = delta_v_E/((R_E + h)*cos(lat))\n", "lon.txt")
    _, _, err = _run(capsys, "strapdown_ned", hand)
    assert "warning" not in err


def test_a_model_files_own_gains_and_examples(tmp_path, capsys):
    # the barometer bias enters the ENU file's height line as +c_1 b_h
    hand = _hand(tmp_path, "dot(delta_h) = delta_v_U - c_1*delta_h - c_1*baro_bias\n")
    status, _, err = _run(capsys, str(ENU_MODEL), hand)
    assert status == 0 and "`-p c_1=0.0293/s` (a 300-s loop)" in err
    status, out, err = _run(capsys, str(ENU_MODEL), hand, "--json", "-p", "c_1=0.0293/s")
    assert status == 1 and err == ""
    (finding,) = _findings(out)
    assert (finding["quantity"], finding["kind"]) == ("baro_bias", "wrong sign")


def test_the_warning_of_a_gain_without_example():
    from ins_errors.commands.check import unchecked_gains_warning

    gain = SimpleNamespace(name="k", default=0.0, damping_gain=True, example="",
                           example_gives="")
    other = SimpleNamespace(name="R", default=6.4e6, damping_gain=False, example="",
                            example_gives="")
    model = SimpleNamespace(name="m", parameters=(other, gain))
    assert unchecked_gains_warning(model, {}) == (
        "terms multiplied by a damping gain at 0 are not checked; the damping gain k is 0 "
        "(undamped): set it (`-p k=…`)")
    assert unchecked_gains_warning(model, {"k": 0.1}) is None
    assert unchecked_gains_warning(model, {}, names=[]) is None


@pytest.mark.parametrize("argv", [
    ["orthodromic", str(ROOT / "examples" / "manual_000" / "equations.tex")],
    ["strapdown_ned", str(ROOT / "examples" / "strapdown" / "phi_attitude_sign_error.txt")],
], ids=["manual_000", "convention"])
def test_parameters_at_their_defaults_change_no_report(argv, capsys):
    d = definition_of(resolve(argv[0]))
    defaults = [item for p in d.parameters for item in (
        "-p", f"{p.name}={float(p.default)!r}" + ("" if p.unit == "1" else f" {p.unit}"))]
    status, plain, _ = _run(capsys, *argv)
    status_set, plain_set, _ = _run(capsys, *argv, *defaults)
    assert (status_set, plain_set) == (status, plain)
    assert status == 1                        # both examples have mistakes
    _, data, _ = _run(capsys, *argv, "--json")
    _, data_set, _ = _run(capsys, *argv, "--json", *defaults)
    data_set = json.loads(data_set)
    assert set(data_set.pop("parameters")) == {p.name for p in d.parameters}
    assert data_set == json.loads(data)


def test_the_matrix_check_evaluates_the_model_with_the_gains(capsys):
    # the example psi model has no damping loop: undamped it agrees, and says which
    # gains its vertical rows were not checked against
    status, out, err = _run(capsys, "strapdown_ned", "--matrix", PSI_MODEL,
                            "--convention", "psi", "--json")
    assert status == 0
    assert "the damping gains k_h1, k_h2 are 0" in err
    status, out, err = _run(capsys, "strapdown_ned", "--matrix", PSI_MODEL,
                            "--convention", "psi", "--json", *DAMPED)
    assert status == 1 and err == ""
    mistakes = {(f["row"], f["column"]): f for f in json.loads(out)["findings"]
                if f["severity"] == "mistake"}
    # dr_D' = dv_D − k_h1 dr_D, dv_D' = ... − k_h2 dr_D (+ the gravity gradient 2g/R dr_D,
    # which the hand has): the flown motions carry the gains into F
    assert set(mistakes) == {("dr_D", "dr_D"), ("dvc_D", "dr_D")}
    assert mistakes["dr_D", "dr_D"]["kind"] == "omitted term"
    assert mistakes["dr_D", "dr_D"]["model"] == pytest.approx(-0.0293)
    g_over_r = 9.81 / 6.371e6
    assert mistakes["dvc_D", "dr_D"]["model"] == pytest.approx(2 * g_over_r - 4.42e-4,
                                                               rel=0.01)


def test_a_convention_file_is_checked_with_the_gains(tmp_path, capsys):
    # the damped height row in the φ convention's NED metres (dr_D = −δh)
    hand = _hand(tmp_path, "@convention phi\ndot(dr_D) = dv_D - 0.0293*dr_D\n")
    status, out, err = _run(capsys, "strapdown_ned", hand, "--json", "-p", "k_h1=0.0293/s")
    assert status == 0 and err == ""
    assert json.loads(out)["parameters"] == {"k_h1": {"value": 0.0293, "unit": "1/s"}}
    status, out, err = _run(capsys, "strapdown_ned", hand, "--json")
    assert status == 1                       # undamped, the model has no such term
    (finding,) = [f for f in json.loads(out)["findings"] if f["severity"] == "mistake"]
    assert (finding["row"], finding["column"], finding["kind"]) == ("dr_D", "dr_D",
                                                                     "extra term")
    # the row holds k_h1 only: k_h2 (in the dv_D row the file does not give) is not named
    assert "damping gain k_h1 is 0" in err and "k_h2" not in err


def test_bad_parameters_are_refused_in_one_line(tmp_path, capsys):
    hand = _hand(tmp_path, "dot(delta_h) = -delta_v_D\n")
    for argv, message in (
            (["-p", "k_h3=1/s"], "unknown parameter of strapdown_ned 'k_h3'"),
            (["-p", "k_h1=-0.1/s"], "k_h1 = '-0.1/s': a vertical damping gain must be"),
            (["-p", "k_h1=0.1"], "k_h1"),
            (["-p", "k_h1"], "--parameter 'k_h1': expected NAME=VALUE")):
        assert main(["check", "strapdown_ned", hand, *argv]) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and len(captured.err.splitlines()) == 1
        assert message in captured.err


def test_a_flagged_damping_gain_of_a_model_file_must_not_be_negative(capsys):
    # any parameter the model flags as a damping gain, not only strapdown_ned's k_h1/k_h2
    enu = Path(__file__).resolve().parent / "models" / "enu_strapdown.py"
    text = enu.read_text(encoding="utf-8")
    assert "damping_gain=True" in text and '"c_1"' in text
    status = main(["models", str(enu)])  # loads (derives) the model once
    capsys.readouterr()
    assert status == 0
    status = main(["compare", str(enu), "--source", "gyro_bias_x=0.01deg/h", "--hours", "0.1",
                   "-p", "c_1=-0.01/s"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1
    assert "c_1 = '-0.01/s': a damping gain must be zero (undamped) or positive" in err[0]
