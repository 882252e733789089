"""``ins-errors compare``: units at the edge, JSON, plots, Markdown, one-line errors."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import main

DEG_PER_HOUR = np.pi / 180.0 / 3600.0


def run(capsys, *args):
    status = main(["compare", "orthodromic", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_json_plot_and_markdown(capsys, tmp_path):
    plot, table = tmp_path / "out.png", tmp_path / "out.md"
    status, out, err = run(capsys, "--source", "gyro_drift_x=0.01deg/h", "--motion", "static",
                           "--hours", "2", "--step", "10s", "--plot", str(plot),
                           "--markdown", str(table), "--json")
    assert status == 0, err
    report = json.loads(out)
    # the default record of a 2-h run: a 240th of it (30 s) rather than 60 s
    assert report["record_s"] == 30.0 and report["step_s"] == 10.0
    assert len(report["cases"][0]["metrics"]) and 7200.0 / report["record_s"] == 240
    assert report["truth"] == "auto" and report["truth_used"] == "static"  # at rest: exact
    (case,) = report["cases"]
    assert case["sources"]["gyro_drift_x"] == pytest.approx(0.01 * DEG_PER_HOUR, rel=1e-12)
    assert case["worst_linear_ratio"] <= 0.01
    assert case["worst_refined_ratio"] < case["worst_linear_ratio"]
    names = [m["quantity"] for m in case["metrics"]]
    assert {"alpha_x", "delta_latitude", "delta_longitude", "delta_heading", "delta_v_N",
            "delta_v_E"} <= set(names)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert err.strip() == f"plot written to {plot}"  # beside the JSON, not in it
    text = table.read_text()
    assert "gyro_drift_x = 0.01 deg/h" in text
    # people read display units (arcmin), the JSON stays SI with its unit stated
    row = next(line for line in text.splitlines() if line.startswith("| `delta_latitude` |"))
    assert row.split("|")[2].strip() == "arcmin"
    (metric,) = [m for m in case["metrics"] if m["quantity"] == "delta_latitude"]
    assert metric["unit"] == "rad"
    assert float(row.split("|")[3]) == pytest.approx(metric["max_direct"] * 180 / np.pi * 60,
                                                     rel=1e-3)


def test_separate_cases_and_moving_motions(capsys, tmp_path):
    plot = tmp_path / "cases.svg"
    status, out, err = run(capsys, "-s", "accel_bias_y=10ug", "-s", "initial_tilt_x=10arcsec",
                           "--separately", "--motion", "great-circle", "--speed", "900 km/h",
                           "--heading", "45deg", "--duration", "90 min", "--step", "2 s",
                           "--plot", str(plot), "--no-refined")
    assert status == 0, err
    assert (tmp_path / "cases_1.svg").exists() and (tmp_path / "cases_2.svg").exists()
    assert out.strip().endswith(f"plots written to {tmp_path / 'cases_1.svg'} … cases_2.svg "
                                "(one per case)")
    assert "accel_bias_y = 10 ug" in out and "initial_tilt_x = 10 arcsec" in out
    assert "great circle" in out
    status, out, err = run(capsys, "-s", "accel_scale_error_x=100ppm", "--motion", "manoeuvre",
                           "--hours", "1", "--json", "--method", "rk4")
    assert status == 0, err
    case = json.loads(out)["cases"][0]
    assert case["sources"]["accel_scale_error_x"] == pytest.approx(1e-4)
    assert case["worst_linear_ratio"] <= 0.01


def test_own_motion_from_a_csv_file(capsys, tmp_path):
    t = np.arange(0.0, 3700.0, 10.0)
    v_n, v_e = 200.0 * np.cos(t / 900.0), 200.0 * np.sin(t / 900.0)  # slow circling
    table = tmp_path / "motion.csv"
    np.savetxt(table, np.column_stack([t, v_n, v_e, 1000 + 0 * t]), delimiter=",",
               header="t,v_N,v_E,h", comments="")
    status, out, err = run(capsys, "-s", "gyro_drift_y=0.01deg/h", "--motion-file", str(table),
                           "--hours", "1", "--json")
    assert status == 0, err
    report = json.loads(out)
    # the motion names the file and the start values the run depends on (two runs of
    # one file from different latitudes read differently)
    assert report["motion"].startswith(f"motion file {table} (370 samples, geographic frame)")
    assert "from φ=50°" in report["motion"]
    assert report["cases"][0]["worst_linear_ratio"] <= 0.01
    status, out, err = run(capsys, "-s", "gyro_drift_y=0.01deg/h", "--motion-file", str(table),
                           "--hours", "1", "--json", "--latitude", "30deg")
    assert status == 0 and "from φ=30°" in json.loads(out)["motion"], err
    bad = tmp_path / "bad.csv"
    bad.write_text("time,v_N,v_E\n0,1,2\n")
    status, _out, err = run(capsys, "-s", "gyro_drift_y=0.01deg/h", "--motion-file", str(bad))
    assert status == 2 and "lacks column(s) t" in err
    status, _out, err = run(capsys, "-s", "gyro_drift_y=0.01deg/h", "--motion-file",
                            str(table), "--hours", "2")
    assert status == 2 and "leaves the sampled motion" in err


def test_truth_option_fine_and_interpolated_agree(capsys):
    """``--truth``: the interpolated truth (coarse Chebyshev intervals) gives the direct
    errors of the fine truth (integrated at every step) to far below any linear-vs-direct
    difference. Reference: tests/test_interpolated_truth.py measures the interpolated
    direct errors within 1.8e-9 of the fine ones relative to their size (asserted < 1e-7
    there); the same bound is used here on a 20 min great circle at a 1 s step."""
    from ins_errors.numeric.trajectories import TRUTHS

    reports = {}
    for truth in TRUTHS:
        status, out, err = run(capsys, "-s", "gyro_drift_x=0.01deg/h", "-s",
                               "accel_bias_y=10ug", "--motion", "great-circle", "--duration",
                               "20 min", "--step", "1s", "--no-refined", "--json",
                               "--truth", truth)
        assert status == 0, err
        reports[truth] = json.loads(out)
        assert reports[truth]["truth"] == truth
    fine, fast, auto = ([(m["max_direct"], m["linear_difference"])
                         for m in reports[t]["cases"][0]["metrics"]] for t in
                        ("fine", "interpolated", "auto"))
    fine, fast = np.array(fine), np.array(fast)
    assert fine[:, 0].min() > 0  # every quantity excited
    size = fine[:, :1]  # max direct error of each quantity
    change = np.abs(fast - fine)  # of the max direct error and of max |linear - direct|
    assert (change / size).max() < 1e-7
    assert (change[:, 1] / fine[:, 1]).max() < 1e-2  # far below linear-vs-direct
    assert not np.array_equal(fast, fine)  # the option reached the truth: two computations
    # at 1 s an interval of about 10 s holds fewer than MIN_STEPS steps: auto is fine,
    # and the JSON says which truth it used
    assert np.array_equal(np.array(auto), fine)
    assert [reports[t]["truth_used"] for t in TRUTHS] == [
        "fine" if t == "auto" else t for t in TRUTHS]


def test_unknown_truth_is_a_one_line_usage_error(capsys):
    with pytest.raises(SystemExit) as exit_:
        run(capsys, "-s", "gyro_drift_x=0.01deg/h", "--truth", "bogus")
    assert exit_.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "--truth" in lines[0] and "'bogus'" in lines[0]
    assert "interpolated" in lines[0]  # the choices are named

@pytest.mark.parametrize(("args", "message"), [
    (["-s", "gyro_drft_x=0.01deg/h"], "did you mean 'gyro_drift_x'"),
    (["-s", "gyro_drift_x=0.01deg/h", "--step", "0"], "step must be a positive"),
    (["-s", "gyro_drift_x=0.01deg/h", "--step=-1s"], "step must be a positive"),
    (["-s", "gyro_drift_x=0.01deg/h", "--hours", "1", "--step", "7s"],
     "not a whole number of steps of 7 s"),
    (["-s", "gyro_drift_x=0.01deg/h", "--hours", "1", "--record", "7s"], "recording interval"),
    (["-s", "gyro_drift_x=0.01m/s"], "do not convert to rad/s"),
    (["-s", "gyro_drift_x=nan"], "not a finite number"),
    (["-s", "gyro_drift_x"], "expected NAME=VALUE"),
    ([], "give at least one --source"),
    (["-s", "gyro_drift_x=1e5deg/h", "--hours", "2"], r"left its domain between t = \d+ s"),
    (["-s", "gyro_drift_x=1deg/h", "--latitude", "90deg"], "pole"),
])
def test_bad_input_gives_one_line_and_status_2(capsys, args, message):
    status, _out, err = run(capsys, *args)
    assert status == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ins-errors: error: ")
    assert re.search(message, lines[0]), lines[0]


def test_unknown_model_and_entry_point():
    done = subprocess.run([sys.executable, "-m", "ins_errors.cli", "compare", "orthodromc",
                           "-s", "gyro_drift_x=1deg/h"], capture_output=True, text=True)
    assert done.returncode == 2
    assert "did you mean 'orthodromic'" in done.stderr
    assert "Traceback" not in done.stderr


def test_repeated_source_and_bare_angle_are_refused(capsys):
    from ins_errors.cli import main

    assert main(["compare", "orthodromic", "-s", "gyro_drift_x=1deg/h", "-s",
                 "gyro_drift_x=0.001deg/h", "--hours", "1"]) == 2
    assert "given twice" in capsys.readouterr().err
    assert main(["compare", "orthodromic", "-s", "gyro_drift_x=1deg/h", "--latitude", "50",
                 "--hours", "1"]) == 2
    assert "needs a unit" in capsys.readouterr().err


def test_out_writes_the_curves_as_csv_and_mat(capsys, tmp_path):
    """``--out DIR``: curves.csv and curves.mat hold the very curves of the comparison
    (the same files as ``run`` writes), under the folder rules of ins_errors.output."""
    import csv

    from scipy.io import loadmat

    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import motion_profile

    out = tmp_path / "curves"
    args = ["-s", "gyro_drift_x=0.01deg/h", "-s", "accel_bias_y=50ug", "--separately",
            "--duration", "30 min", "--step", "10s", "--no-refined"]
    status, _out, err = run(capsys, *args, "--out", str(out))
    assert status == 0, err
    # the same comparison, computed here through the library
    model = load_model("orthodromic")
    trajectory = tr.trajectory(model, motion_profile({"kind": "static", "latitude": "50deg",
                                                      "longitude": "30deg"}), 1800.0, 10.0)
    expected = compare(model, trajectory,
                       [{"gyro_drift_x": 0.01 * DEG_PER_HOUR}, {"accel_bias_y": 50e-6 * 9.80665}],
                       record_interval=10.0, refined=False)
    with open(out / "curves.csv", encoding="utf-8", newline="") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    assert header[:2] == ["case", "t [s]"]
    assert not any(".refined" in name for name in header)
    assert body.shape == (2 * 181, len(header))   # 30 min recorded every 10 s by default
    mat = loadmat(out / "curves.mat", squeeze_me=True, struct_as_record=False)
    for k, comparison in enumerate(expected, 1):
        mine = body[body[:, 0] == k]
        np.testing.assert_array_equal(mine[:, 1], comparison.times)
        assert comparison.times[-1] == 1800.0
        for run_name in ("direct", "linear"):
            for quantity, curve in getattr(comparison, run_name).items():
                column = next(i for i, name in enumerate(header)
                              if name.startswith(f"{quantity}.{run_name} ["))
                np.testing.assert_array_equal(mine[:, column], curve)  # repr: round trip
                np.testing.assert_array_equal(
                    getattr(getattr(mat[f"case_{k}"], run_name), quantity), curve)
    # a gyro drift tilts the platform: alpha_x grows, it is not a column of zeros
    assert np.max(np.abs(expected[0].direct["alpha_x"])) > 1e-7
    # again into the same folder: replaced, a file of someone else's is left alone
    (out / "notes.txt").write_text("mine")
    status, _out, err = run(capsys, *args, "--out", str(out))
    assert status == 0, err
    assert sorted(p.name for p in out.iterdir()) == [".ins-errors-files.json", "curves.csv",
                                                      "curves.mat", "notes.txt"]
    # a folder ins-errors did not write is refused before computing, unless --force
    stranger = tmp_path / "stranger"
    stranger.mkdir()
    (stranger / "data.txt").write_text("x")
    status, _out, err = run(capsys, *args, "--out", str(stranger))
    assert status == 2 and "--force" in err and len(err.strip().splitlines()) == 1
    status, _out, err = run(capsys, *args, "--out", str(stranger), "--force")
    assert status == 0 and (stranger / "curves.csv").exists() and (stranger / "data.txt").exists()


SCHULER_LOOP = str(Path(__file__).resolve().parents[1] / "examples" / "own_model"
                   / "schuler_loop.py")


def _compare_json(capsys, model, *args):
    assert main(["compare", model, *args, "--hours", "1", "--step", "10s", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    return report["motion"], [{k: v for k, v in c.items() if k != "label"}
                              for c in report["cases"]]


def test_the_header_states_only_the_references_the_run_depends_on(capsys, tmp_path):
    """The tutorial's single-axis Schuler loop has no longitude, heading or height
    anywhere (its inputs: a_N; initial conditions: latitude, v_N): the header (compare's,
    and run's report.md) names the latitude only, and a longitude or height given to
    compare, which nothing of the run would use, is refused (one line, exit 2). The
    free-azimuth model has no height input, but its truth's vertical specific force is
    gravity at that height: its results change with h and the header keeps it; the
    north-pointing model at rest has no heading."""
    source = ["--source", "accel_bias=100ug"]
    motion, cases = _compare_json(capsys, SCHULER_LOOP, *source)
    for option, value in (("--longitude", "-70deg"), ("--height", "3000m")):
        assert main(["compare", SCHULER_LOOP, *source, "--hours", "1", "--step", "10s",
                     option, value]) == 2
        err = capsys.readouterr().err
        assert f"has no {option[2:]}" in err and f"leave {option} out" in err
    assert "φ=50°" in motion
    assert not any(part in motion for part in ("λ", "χ", "h=")), motion
    source = ["--source", "accel_bias_x=100ug"]
    low, cases = _compare_json(capsys, "free_azimuth", *source)
    high, other = _compare_json(capsys, "free_azimuth", *source, "--height", "3000m")
    assert other != cases and "h=0 m" in low and "h=3000 m" in high
    assert "χ=" in low and "λ=" in low
    north, _ = _compare_json(capsys, "north_pointing", "--source", "accel_bias_east=100ug")
    assert "χ=" not in north and "λ=" in north and "h=0 m" in north
    # the run header of a scenario, in report.md
    scenario = tmp_path / "loop.toml"
    scenario.write_text(f'title = "loop"\nmodel = {json.dumps(SCHULER_LOOP)}\n'
                        '[motion]\nkind = "static"\nlatitude = "40 deg"\nlongitude = "10 deg"\n'
                        'height = "500 m"\n[run]\nduration = "1 h"\nstep = "10 s"\n'
                        '[[case]]\naccel_bias = "100 ug"\n', encoding="utf-8")
    # a longitude or height the model has not is refused in the file as on the command line
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 2
    assert "[motion] longitude: model 'schuler_loop' has no longitude" in capsys.readouterr().err
    scenario.write_text(scenario.read_text(encoding="utf-8").replace(
        'longitude = "10 deg"\nheight = "500 m"\n', ""), encoding="utf-8")
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()
    report = (tmp_path / "out" / "report.md").read_text(encoding="utf-8")
    assert "| motion | static base at φ=40° |" in report
