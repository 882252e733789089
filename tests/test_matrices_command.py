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
    assert "F (1441, 9, 9) and G (1441, 9, 24) in psi" in said, said  # (no initial errors)
    data = np.load(out)
    assert [str(s) for s in data["states"]][:3] == ["psi_N", "psi_E", "psi_D"]
    assert data["x_cruise"].shape == (1441, 10) and data["t_manoeuvre"][-1] == 86_400.0
    status = main(["check", "strapdown_ned", "--matrix", str(out), "--convention", "psi"])
    said = capsys.readouterr().out
    assert status == 0 and "297 entries compared: 297 agree" in said, said


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
    (["orthodromic", "--convention", "phi"], "has no convention but its own error states"),
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


B15 = "gyro_bias_x,gyro_bias_y,gyro_bias_z,accel_bias_x,accel_bias_y,accel_bias_z"


def _block_sizes(held, reference, states, units, scale):
    """The worst relative block difference of Φ (in typical sizes, against the largest
    entry of the block's rows of Φ − I: what a step does to those states) and of Q
    (against √(Q_ii Q_jj) of the blocks' largest variances), written here from the
    definition."""
    blocks, start = [], 0
    for i in range(1, len(units) + 1):
        if i == len(units) or units[i] != units[start]:
            blocks.append(slice(start, i))
            start = i
    worst = {}
    for name, a, b in (("Phi", held[0], reference[0]), ("Qd", held[1], reference[1])):
        size = 0.0
        if name == "Phi":
            a, b = a * scale[None, None, :] / scale[None, :, None], \
                b * scale[None, None, :] / scale[None, :, None]
            var = None
        else:
            var = np.maximum(np.einsum("kii->ki", a), np.einsum("kii->ki", b))
        for r in blocks:
            for c in blocks:
                d = np.abs(a[:, r, c] - b[:, r, c]).max(axis=(1, 2))
                if var is None:
                    eye = np.eye(a.shape[1])[r]
                    den = np.maximum(np.abs(a[:, r, :] - eye).max(axis=(1, 2)),
                                     np.abs(b[:, r, :] - eye).max(axis=(1, 2)))
                    keep = den > 0
                else:
                    den = np.sqrt(var[:, r].max(axis=1) * var[:, c].max(axis=1))
                    keep = den > 0
                if keep.any():
                    size = max(size, float((d[keep] / den[keep]).max()))
        worst[name] = size
    return worst


def test_a_step_too_long_for_the_manoeuvre_is_warned_of_with_the_size_of_its_error(
        tmp_path, capsys):
    """The probe: Φ and Qd with F held at each 60 s step's start are tens of % off along
    the manoeuvre (20-minute S-turns). The warning's size is measured against the
    product of the fine-step Φ (and the Q they carry) of a 1 s file over each 60 s step;
    the static base (F constant) gets none; the suggested step keeps it under 1 %."""
    common = ["matrices", "strapdown_ned", "--convention", "psi", "--bias-states", B15,
              "--markov", "gyro_bias_z=1h", "--discrete", "--noise",
              "gyro_bias_z=0.01deg/h,gyro_bias_x=0.003deg/rt-hr", "--hours", "0.5",
              "--motion", "static", "--motion", "manoeuvre"]
    coarse, fine = tmp_path / "c.npz", tmp_path / "f.npz"
    assert main([*common, "--out", str(coarse), "--json"]) == 0
    captured = capsys.readouterr()
    record = json.loads(captured.out)
    warned = captured.err.strip().splitlines()
    assert len(warned) == 1 and warned[0].startswith("ins-errors: warning: manoeuvre: "), \
        warned
    assert record["warnings"] == [warned[0].removeprefix("ins-errors: warning: ")]
    holds = {h["label"]: h for h in record["discrete"]["hold_error"]}
    assert holds["static"]["size"] == 0.0 and holds["static"]["suggested_step_s"] is None
    estimate = holds["manoeuvre"]
    assert estimate["size"] > 0.1 and f"{estimate['size']:.0%}" in warned[0]
    assert main([*common, "--step", "1s", "--out", str(fine)]) == 0
    assert "warning" not in capsys.readouterr().err
    c, f = np.load(coarse), np.load(fine)
    Phi_f, Qd_f = f["Phi_manoeuvre"], f["Qd_manoeuvre"]
    n = Phi_f.shape[1]
    Phi_ref, Qd_ref = np.empty_like(c["Phi_manoeuvre"]), np.empty_like(c["Qd_manoeuvre"])
    for k in range(Phi_ref.shape[0]):
        P, Q = np.eye(n), np.zeros((n, n))
        for j in range(60 * k, 60 * (k + 1)):
            P, Q = Phi_f[j] @ P, Phi_f[j] @ Q @ Phi_f[j].T + Qd_f[j]
        Phi_ref[k], Qd_ref[k] = P, Q
    units = ["rad"] * 3 + ["m/s"] * 3 + ["m"] * 3 + ["rad/s"] * 3 + ["m/s**2"] * 3
    scale = np.array([1e-4] * 3 + [0.1] * 3 + [10.0] * 3 + [4.85e-8] * 3 + [9.8e-4] * 3)
    true = _block_sizes((c["Phi_manoeuvre"], c["Qd_manoeuvre"]), (Phi_ref, Qd_ref),
                        None, units, scale)
    worst = max(true.values())
    assert worst / 3 < estimate["size"] < 3 * worst, (estimate, true)
    # the suggested step: its own estimate under 1 % (the estimate at twice the step
    # shows it falling with the step)
    step = estimate["suggested_step_s"]
    assert estimate["size_twice_step"] > 1.4 * estimate["size"]
    assert 0 < step <= 60 * 0.01 / estimate["size"]
    assert main([*common, "--motion", "manoeuvre", "--step", f"{step:g}s",
                 "--out", str(tmp_path / "s.npz"), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["warnings"] == [] and \
        again["discrete"]["hold_error"][-1]["size"] < 0.01, again["discrete"]


def test_arrays_beyond_the_limit_or_the_memory_are_refused_before_flying(tmp_path, capsys,
                                                                        monkeypatch):
    """The probe's 24 h at 0.01 s (8.6 million samples of 15 states: about 69 GB) ended
    in numpy's MemoryError traceback: now one line, exit 2, before anything is flown;
    the memory figure is checked with a small available memory (never the real case)."""
    from ins_errors.checker import check_motions
    from ins_errors.commands import matrices

    def no_flight(*args, **kwargs):
        raise AssertionError("flown before the size was checked")

    monkeypatch.setattr(check_motions, "flown_motions", no_flight)
    out = tmp_path / "huge.npz"
    args = ["matrices", "strapdown_ned", "--motion", "static", "--hours", "24", "--step",
            "0.01s", "--bias-states", B15, "--discrete", "--noise",
            "gyro_bias_x=0.003deg/rt-hr", "--out", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    # 8 bytes × 8,640,001 × (225 F + 15·18 G + 2·225 Φ, Q + 15 L + 10 x + 12 u + 20)
    expected = 8 * 8_640_001 * (225 + 270 + 450 + 15 + 10 + 12 + 20) / 1e9
    assert len(err) == 1 and "--allow-large" in err[0] and "beyond the limit" in err[0]
    assert f"about {expected:.0f} GB" in err[0], (err, expected)
    monkeypatch.setattr(matrices, "available_memory", lambda: 5 * 10**6)
    small = ["matrices", "strapdown_ned", "--motion", "static", "--hours", "1", "--step",
             "1s", "--out", str(out)]
    assert main(small) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "5 MB available" in err[0], err
    assert not out.exists()


def test_a_memory_error_anywhere_is_one_line_and_exit_2(tmp_path, capsys, monkeypatch):
    from ins_errors.analysis import discrete_model

    def full(*args, **kwargs):
        raise MemoryError("Unable to allocate 43.5 GiB for an array with shape "
                          "(8640000, 15, 15) and data type float64")

    monkeypatch.setattr(discrete_model, "discrete_matrices", full)
    status = main(["matrices", "strapdown_ned", "--motion", "static", "--hours", "1",
                   "--discrete", "--out", str(tmp_path / "x.npz")])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and "out of memory" in err[0] and \
        "43.5 GiB" in err[0], err


@pytest.mark.parametrize("biases, markov, said", [
    ("phi_N,dv_E", [], "'phi_N' is a state of convention 'phi' already"),
    ("phi_N", ["--markov", "phi_N=1h"], "'phi_N' is a state of convention 'phi' already"),
    ("gyro_bias_x,accel_bias_y,gyro_bias_x", [], "'gyro_bias_x' is given twice"),
])
def test_convention_states_and_duplicates_as_bias_states_are_refused(biases, markov, said,
                                                                    tmp_path, capsys):
    status = main(["matrices", "strapdown_ned", "--bias-states", biases, *markov,
                   "--out", str(tmp_path / "x.npz")])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and said in err[0] and "dot(" not in err[0], err


def test_the_api_speaks_of_a_markov_name_without_bias_state_plainly():
    from ins_errors import load_model
    from ins_errors.conventions import model_convention
    from ins_errors.errors import InsErrorsError

    with pytest.raises(InsErrorsError) as error:
        model_convention(load_model("strapdown_ned"), "phi", ["gyro_bias_x"],
                         {"phi_N": 3600.0})
    assert "dot(" not in str(error.value) and "'phi_N'" in str(error.value)


def test_a_gauss_markov_state_without_its_sigma_is_warned_of(tmp_path, capsys):
    """A density but no steady-state σ: the state's row of Qd is zero (nothing drives
    it), which a filter turns into a bias decaying to 0 and overconfidence."""
    out = tmp_path / "gm.npz"
    assert main(["matrices", "strapdown_ned", "--motion", "static", "--hours", "1",
                 "--bias-states", B15, "--markov", "gyro_bias_z=1h", "--discrete",
                 "--noise", "gyro_bias_z=0.003deg/rt-hr", "--out", str(out), "--json"]) == 0
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and "gyro_bias_z" in err[0] and "nothing drives it" in err[0]
    assert json.loads(captured.out)["warnings"] == [err[0].removeprefix(
        "ins-errors: warning: ")]
    data = np.load(out)
    i = [str(s) for s in data["states"]].index("gyro_bias_z")
    assert not data["Qd_static"][:, i, :].any()   # what the warning says
    assert main(["matrices", "strapdown_ned", "--motion", "static", "--hours", "1",
                 "--bias-states", B15, "--markov", "gyro_bias_z=1h", "--discrete",
                 "--noise", "gyro_bias_z=0.003deg/rt-hr,gyro_bias_z=0.01deg/h",
                 "--out", str(out)]) == 0
    assert "warning" not in capsys.readouterr().err


def test_bias_states_keep_the_order_given_and_the_file_still_checks(tmp_path, capsys):
    """A filter's layout is its own: `--bias-states accel_bias_z,gyro_bias_x` gave the
    model's order (gyro first). The order given is kept, F's bias columns are G's columns
    of those sources in that order, and check --matrix reads the file back."""
    out = tmp_path / "o.npz"
    assert main(["matrices", "strapdown_ned", "--convention", "psi", "--bias-states",
                 "accel_bias_z,gyro_bias_x", "--markov", "gyro_bias_x=1h", "--out",
                 str(out), "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    data = np.load(out)
    states = [str(s) for s in data["states"]]
    assert states[9:] == ["accel_bias_z", "gyro_bias_x"]
    assert record["bias_states"] == [
        {"name": "accel_bias_z", "statistics": "constant", "tau_s": None},
        {"name": "gyro_bias_x", "statistics": "markov", "tau_s": 3600.0}]
    # the same columns as G's in a file without bias states
    plain = tmp_path / "p.npz"
    assert main(["matrices", "strapdown_ned", "--convention", "psi", "--out",
                 str(plain)]) == 0
    p = np.load(plain)
    sources = [str(s) for s in p["sources"]]
    for motion in ("static", "manoeuvre"):
        for j, name in enumerate(["accel_bias_z", "gyro_bias_x"]):
            np.testing.assert_array_equal(data[f"F_{motion}"][:, :9, 9 + j],
                                          p[f"G_{motion}"][:, :, sources.index(name)])
    capsys.readouterr()
    status = main(["check", "strapdown_ned", "--matrix", str(out), "--convention", "psi"])
    said = capsys.readouterr().out
    assert status == 0 and "disagree" not in said and "0 mistakes" in said, said


def test_the_file_holds_the_noise_inputs_and_g_holds_no_initial_errors(tmp_path, capsys):
    """A designer re-discretises from L (K, n, q) and noise_densities: Van Loan of F and
    L diag(q²) Lᵀ at a step's start gives the file's Qd; G's columns are the model's
    inputs (the initial errors only set the start: they are no column)."""
    from scipy.linalg import expm

    from ins_errors import load_model

    out = tmp_path / "l.npz"
    assert main(["matrices", "strapdown_ned", "--motion", "cruise", "--hours", "1",
                 "--bias-states", B15, "--markov", "gyro_bias_z=1h", "--discrete",
                 "--noise", "gyro_bias_x=0.003deg/rt-hr,gyro_bias_z=0.01deg/h,"
                 "accel_bias_y=50ug/rtHz", "--out", str(out)]) == 0
    capsys.readouterr()
    d = np.load(out)
    L, q, F = d["L_cruise"], d["noise_densities"], d["F_cruise"]
    assert L.shape == (61, 15, 3) and [str(s) for s in d["noise_sources"]] == [
        "gyro_bias_x", "accel_bias_y", "gyro_bias_z:markov"]
    n, dt, k = 15, 60.0, 30
    Qc = L[k] @ np.diag(q**2) @ L[k].T
    E = expm(np.block([[-F[k], Qc], [np.zeros((n, n)), F[k].T]]) * dt)
    Phi = E[n:, n:].T
    np.testing.assert_allclose(Phi @ E[:n, n:], d["Qd_cruise"][k], rtol=1e-6,
                               atol=1e-9 * np.abs(d["Qd_cruise"][k]).max())
    kinds = {s.name: s.kind for s in load_model("strapdown_ned").sources}
    assert all(kinds[str(s)] == "constant" for s in d["sources"])
    assert d["G_cruise"].shape[2] == sum(k == "constant" for k in kinds.values()) - 6


def test_hourly_samples_of_a_long_cruise_are_the_minute_samples_at_those_times(tmp_path,
                                                                               capsys):
    # the position integration's evaluation budget counted the samples, not the flight:
    # hourly samples of a 12-h cruise were refused as "steps shrink without end" near
    # t = 7.7 h although the same flight integrates in minute samples; the true flight
    # does not depend on how it is sampled
    files = {}
    for step in (60, 3600):
        files[step] = tmp_path / f"c{step}.npz"
        assert main(["matrices", "strapdown_ned", "--motion", "cruise", "--hours", "12",
                     "--step", f"{step}s", "--out", str(files[step])]) == 0, \
            capsys.readouterr().err
    capsys.readouterr()
    fine, coarse = np.load(files[60]), np.load(files[3600])
    assert coarse["t_cruise"].shape == (13,)
    np.testing.assert_array_equal(coarse["t_cruise"], fine["t_cruise"][::60])
    for key in ("x_cruise", "u_cruise", "F_cruise", "G_cruise"):
        want, got = fine[key][::60], coarse[key]
        # each entry against its own size over the flight; entries that are zero up to
        # rounding (1e-15 m/s² of a 10-m/s² specific force) against the array's size
        tolerance = 1e-12 * np.abs(want).max(axis=0) + 1e-15 * np.abs(want).max()
        assert np.all(np.abs(got - want) <= tolerance), key


def test_the_name_lists_of_a_mat_file_read_back_as_matrix_check_md_says(tmp_path, capsys):
    """The .mat file's name lists come back from scipy.io.loadmat as nested object
    arrays; docs/matrix_check.md gives the line that lists them. It reads every list as
    the .npz holds it, a one-name list (one noise source) included."""
    import re

    page = (ROOT / "docs" / "matrix_check.md").read_text(encoding="utf-8")
    line = re.search(r"`(\[str\(c\[0\]\) for c in loadmat\(\"fg\.mat\"\)\[\"states\"\]"
                     r"\.ravel\(\)\])`", page.replace("\n", " ")).group(1)
    common = ["orthodromic", "--motion", "static", "--hours", "0.5", "--step", "60s",
              "--discrete", "--noise", "gyro_drift_x=0.003deg/rt-hr"]
    for suffix in ("npz", "mat"):
        assert main(["matrices", *common, "--out", str(tmp_path / f"fg.{suffix}")]) == 0
    capsys.readouterr()
    npz = np.load(tmp_path / "fg.npz")
    keys = ("states", "sources", "noise_sources", "model_states", "model_inputs",
            "parameter_names")
    for key in keys:
        names = eval(line.replace('"fg.mat"', repr(str(tmp_path / "fg.mat")))
                     .replace('"states"', repr(key)), {"loadmat": loadmat})
        assert names == [str(n) for n in npz[key]], key
    assert len(npz["noise_sources"]) == 1
