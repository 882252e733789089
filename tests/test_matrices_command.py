"""``ins-errors matrices``: the derived F(t), G(t) in a convention, written for a filter
designer. References: the matrix check reading the file back (every entry agrees), and
the textbook φ-angle blocks F[δv, φ] = [f^n×], G = [−C_b^n, 0; 0, C_b^n] from the written
true states of a direction-cosine model file (its first nine states are C_b^n)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.io import loadmat

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parents[1]
SPHERE_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"


def test_the_written_matrices_pass_the_check_against_the_model(tmp_path, capsys):
    out = tmp_path / "fg.npz"
    assert main(["matrices", "strapdown_ned", "--convention", "psi", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "F (1441, 9, 9) and G (1441, 9, 33) in psi" in said, said
    data = np.load(out)
    assert [str(s) for s in data["states"]][:3] == ["psi_N", "psi_E", "psi_D"]
    assert data["x_cruise"].shape == (1441, 10) and data["t_manoeuvre"][-1] == 86_400.0
    status = main(["check", "strapdown_ned", "--matrix", str(out), "--convention", "psi"])
    said = capsys.readouterr().out
    assert status == 0 and "378 entries compared: 378 agree" in said, said


def _skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def test_a_model_file_in_phi_with_bias_states_is_the_textbook_model(tmp_path, capsys):
    out = tmp_path / "fg.mat"
    biases = "gyro_bias_x,gyro_bias_y,gyro_bias_z,accel_bias_x,accel_bias_y,accel_bias_z"
    assert main(["matrices", str(SPHERE_FILE), "--convention", "phi", "--motion", "cruise",
                 "--motion", "manoeuvre", "--hours", "1", "--step", "30s",
                 "--bias-states", biases, "--out", str(out)]) == 0
    capsys.readouterr()
    data = loadmat(out)
    assert "F_static" not in data and "G_cruise" not in data and "sources" not in data
    for motion in ("cruise", "manoeuvre"):
        F, x, u = data[f"F_{motion}"], data[f"x_{motion}"], data[f"u_{motion}"]
        assert F.shape == (121, 15, 15) and data[f"t_{motion}"].ravel()[-1] == 3600.0
        C = x[:, :9].reshape(-1, 3, 3)
        f_n = np.einsum("kij,kj->ki", C, u[:, 3:6])
        F_vphi = np.array([_skew(f) for f in f_n])
        assert np.abs(F[:, 3:6, 0:3] - F_vphi).max() < 1e-12 * np.abs(F_vphi).max()
        Z = np.zeros_like(C)
        G_book = np.concatenate([np.concatenate([-C, Z], axis=2),
                                 np.concatenate([Z, C], axis=2), np.zeros((len(C), 3, 6))],
                                axis=1)
        assert np.abs(F[:, :9, 9:] - G_book).max() < 1e-14
        assert not F[:, 9:, :].any()


@pytest.mark.parametrize("args, said", [
    (["orthodromic"], "has no convention but its own error states"),
    (["strapdown_ned", "--convention", "phy"], "did you mean 'phi'"),
    (["strapdown_ned", "--bias-states", "gyro_bias_q"], "gyro_bias_q"),
    (["strapdown_ned", "--step", "0s"], "--step '0s' must be positive"),
    (["strapdown_ned", "--bias-states", "gyro_bias_x", "--markov", "gyro_bias_y=300s"],
     "'gyro_bias_y' is not a bias state"),
    (["strapdown_ned", "--bias-states", "gyro_bias_x", "--markov", "gyro_bias_x=-3s"],
     "must be positive"),
    (["strapdown_ned", "--bias-states", "gyro_bias_x", "--markov", "gyro_bias_x"],
     "expected NAME=VALUE, e.g. gyro_bias_x=300s"),
    (["strapdown_ned", "--out-ignored"], None),
    (["strapdown_ned", "--no-out"], "matrices needs --out FILE.npz or FILE.mat"),
])
def test_bad_input_is_one_line_and_exit_2(args, said, tmp_path, capsys):
    if said is None:  # an unknown option: argparse's usage error, exit 2
        with pytest.raises(SystemExit) as stop:
            main(["matrices", *args])
        assert stop.value.code == 2
        return
    out = [] if "--no-out" in args else ["--out", str(tmp_path / "x.npz")]
    status = main(["matrices", *[a for a in args if a != "--no-out"], *out])
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert status == 2 and len(err) == 1 and said in err[0] and not captured.out, err
    assert not (tmp_path / "x.npz").exists()
    assert main(["matrices", "strapdown_ned", "--out", str(tmp_path / "x.txt")]) == 2
    assert "must end in .npz or .mat" in capsys.readouterr().err


def test_a_gauss_markov_bias_state_has_its_row_minus_one_over_tau(tmp_path, capsys):
    """A filter designer's biases are first-order Gauss-Markov processes (the probe's
    τ = 300 s): `--markov NAME=TIME` gives the state ḃ = −b/τ; every other entry is that
    of the random-constant bias state."""
    constant, markov = tmp_path / "c.npz", tmp_path / "m.npz"
    common = ["matrices", "strapdown_ned", "--convention", "phi", "--motion", "static",
              "--hours", "1", "--bias-states", "gyro_bias_x,accel_bias_y"]
    assert main([*common, "--out", str(constant)]) == 0
    assert main([*common, "--markov", "gyro_bias_x=5 min", "--out", str(markov)]) == 0
    capsys.readouterr()
    c, m = np.load(constant), np.load(markov)
    states = [str(s) for s in m["states"]]
    i, j = states.index("gyro_bias_x"), states.index("accel_bias_y")
    assert np.all(m["F_static"][:, i, i] == -1 / 300.0)
    assert np.all(m["F_static"][:, j, j] == 0.0)
    expected = c["F_static"].copy()
    expected[:, i, i] = -1 / 300.0
    np.testing.assert_array_equal(m["F_static"], expected)


def test_a_file_with_gauss_markov_states_passes_the_check_it_was_written_for(tmp_path,
                                                                              capsys):
    """The round trip with a Gauss-Markov bias state: the file says which states are
    Gauss-Markov and their τ, so `check --matrix` expects the −1/τ rows it holds."""
    out = tmp_path / "m.npz"
    assert main(["matrices", "strapdown_ned", "--convention", "phi", "--bias-states",
                 "gyro_bias_x,accel_bias_y", "--markov", "gyro_bias_x=5 min",
                 "--out", str(out)]) == 0
    data = np.load(out)
    assert [str(s) for s in data["markov_states"]] == ["gyro_bias_x"]
    assert data["markov_tau"].tolist() == [300.0]
    capsys.readouterr()
    status = main(["check", "strapdown_ned", "--matrix", str(out), "--convention", "phi"])
    said = capsys.readouterr().out
    assert status == 0 and "entries compared" in said and "disagree" not in said, said



def test_the_json_records_parameters_as_every_command_does(tmp_path, capsys):
    """`parameters` is name -> {value, unit} in every command's JSON (docs/json.md); this
    command wrote a bare SI number."""
    assert main(["matrices", "strapdown_ned", "--motion", "static", "--hours", "1",
                 "-p", "k_h1=0.6/min", "--out", str(tmp_path / "fg.npz"), "--json"]) == 0
    parameters = json.loads(capsys.readouterr().out)["parameters"]
    assert parameters == {"k_h1": {"value": pytest.approx(0.01, rel=1e-15), "unit": "1/s"}}
