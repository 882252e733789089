"""``--truth`` (and a scenario's ``[run] truth``) on ``run``, ``sweep`` and ``validity``.

The same choice as ``ins-errors compare --truth``: ``fine`` integrates the true motion at
every step, ``interpolated`` computes it on coarse exact intervals and interpolates it by
Chebyshev polynomials, ``auto`` leaves the choice to the library. Reference for the
tolerance: tests/test_interpolated_truth.py measures the interpolated direct errors within
1.8e-9 of the fine ones relative to their size (asserted < 1e-7 there, and here, as in
tests/test_cli_compare.py). At a 1 s step an interval of about 10 s holds fewer than
MIN_STEPS steps, so ``auto`` is the fine truth, bit for bit: that is today's result, and
a run without the option must give it unchanged.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from ins_errors.cli import main
from ins_errors.numeric.trajectories import TRUTHS

SCENARIO = """model = "orthodromic"
[motion]
kind = "great-circle"
[run]
duration = "20 min"
step = "1 s"
record = "60 s"
refined = false
{truth}
[[case]]
gyro_drift_x = "0.01 deg/h"
accel_bias_y = "10 ug"
"""


def _scenario(tmp_path, truth: str = "", extra: str = "", name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(SCENARIO.format(truth=truth) + extra, encoding="utf-8")
    return path


def _agree(fine: np.ndarray, fast: np.ndarray, size: np.ndarray) -> None:
    """Within the interpolation's accuracy, yet two computations."""
    assert size.min() > 0
    assert (np.abs(fast - fine) / size).max() < 1e-7
    assert not np.array_equal(fast, fine)  # the option reached the truth


def test_cli_choices_are_the_librarys():
    from ins_errors.commands import run

    assert run.TRUTHS == TRUTHS


def test_run_truth_from_the_command_line_and_the_file(tmp_path, capsys):
    plain = _scenario(tmp_path, extra='[outputs]\nquantities = ["alpha_y"]\n')
    reports = {}
    for truth in (*TRUTHS, None):
        option = [] if truth is None else ["--truth", truth]
        out = tmp_path / f"rep_{truth}"
        assert main(["run", str(plain), "--out", str(out), "--json", "--no-progress",
                     *option]) == 0
        reports[truth] = json.loads(capsys.readouterr().out)
        assert reports[truth]["truth"] == (truth or "auto")
        assert json.loads((out / "results.json").read_text())["truth"] == (truth or "auto")
        used = reports[truth]["truth_used"]
        assert used == truth or truth in ("auto", None)
        shown = truth or "auto"
        shown = shown if used == shown else f"{shown} ({used})"
        assert f"| truth | {shown} |" in (out / "report.md").read_text()
    values = {t: np.array([(m["max_direct"], m["linear_difference"])
                           for m in r["cases"][0]["metrics"]]) for t, r in reports.items()}
    _agree(values["fine"], values["interpolated"], values["fine"][:, :1])
    assert np.array_equal(values["auto"], values["fine"])  # auto at 1 s is fine
    assert reports["auto"]["truth_used"] == reports[None]["truth_used"] == "fine"  # and says so
    assert np.array_equal(values[None], values["auto"])  # no option: today's result
    # the file's key, and the command line over it
    fine_file = _scenario(tmp_path, 'truth = "fine"',
                          '[outputs]\nquantities = ["alpha_y"]\n', name="f.toml")
    assert main(["run", str(fine_file), "--out", str(tmp_path / "f1"), "--json",
                 "--truth", "interpolated"]) == 0
    over = json.loads(capsys.readouterr().out)
    assert over["truth"] == "interpolated" and over["cases"] == reports["interpolated"]["cases"]
    assert main(["run", str(fine_file), "--out", str(tmp_path / "f2"), "--json"]) == 0
    own = json.loads(capsys.readouterr().out)
    assert own["truth"] == "fine" and own["cases"] == reports["fine"]["cases"]


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_bad_truth_in_a_file_or_option_is_one_line(tmp_path, capsys, command):
    bad = _scenario(tmp_path, 'truth = "coarse"', "[sweep]\naccel_bias_y = ['10 ug']\n")
    assert main([command, str(bad), "--out" if command == "run" else "--store",
                 str(tmp_path / "x.zarr")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "'coarse'" in err
    assert all(name in err for name in TRUTHS)  # the allowed values are named
    good = _scenario(tmp_path, name="g.toml", extra="[sweep]\naccel_bias_y = ['10 ug']\n")
    with pytest.raises(SystemExit) as exit_:
        main([command, str(good), "--truth", "bogus"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--truth" in err and "'bogus'" in err and "interpolated" in err


def test_sweep_truth_reaches_every_point_and_the_store(tmp_path, capsys):
    pytest.importorskip("zarr")
    import xarray as xr

    grid = "[sweep]\naccel_bias_y = ['10 ug', '100 ug']\n"
    plain = _scenario(tmp_path, extra=grid)
    rows, stores = {}, {}
    for truth in (*TRUTHS, None):
        option = [] if truth is None else ["--truth", truth]
        stores[truth] = tmp_path / f"{truth}.zarr"
        assert main(["sweep", str(plain), "--store", str(stores[truth]), "--engine",
                     "serial", "--json", "--no-progress", *option]) == 0
        data = json.loads(capsys.readouterr().out)
        assert data["truth"] == (truth or "auto")
        with xr.open_zarr(stores[truth], chunks=None) as ds:
            assert ds.attrs["truth"] == (truth or "auto")
            rows[truth] = ds["direct"].values.copy()
    size = np.abs(rows["fine"]).max(axis=1, keepdims=True)  # per point and quantity
    excited = size > 0
    change = np.abs(rows["interpolated"] - rows["fine"])
    assert excited.sum() >= 6
    assert (change.max(axis=1, keepdims=True)[excited] / size[excited]).max() < 1e-7
    assert not np.array_equal(rows["interpolated"], rows["fine"])
    assert np.array_equal(rows["auto"], rows["fine"])
    assert np.array_equal(rows[None], rows["auto"])
    # another truth is another sweep: its store is not reused for it
    assert main(["sweep", str(plain), "--store", str(stores["fine"]), "--engine", "serial",
                 "--truth", "interpolated"]) == 2
    assert "another sweep" in capsys.readouterr().err
    # the file's key is used, and the option overrides it
    fine_file = _scenario(tmp_path, 'truth = "fine"', grid, name="f.toml")
    assert main(["sweep", str(fine_file), "--store", str(stores["fine"]), "--engine",
                 "serial", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["truth"] == "fine" and data["reused"] == 2  # the same sweep as --truth fine


def test_validity_truth(tmp_path, capsys):
    results = {}
    for truth in (*TRUTHS, None):
        option = [] if truth is None else ["--truth", truth]
        assert main(["validity", "orthodromic", "--source", "accel_bias_x", "--motion",
                     "great-circle", "--hours", "0.5", "--step", "2s", "--json",
                     "--no-progress", *option]) == 0
        report = json.loads(capsys.readouterr().out)
        assert report["truth"] == (truth or "auto")
        (results[truth],) = report["sources"]
    ratios = {t: np.array(r["linear_ratio"]) for t, r in results.items()}
    assert np.array_equal(ratios["auto"], ratios["fine"])
    assert np.array_equal(ratios[None], ratios["auto"])
    assert not np.array_equal(ratios["interpolated"], ratios["fine"])
    # |linear - direct| / |direct| moves by no more than the direct errors' own agreement
    assert np.abs(ratios["interpolated"] - ratios["fine"]).max() < 1e-7
    # at 0.1 s every interval holds enough steps: auto is the interpolated truth
    small = {}
    for truth in ("auto", "interpolated"):
        assert main(["validity", "orthodromic", "--source", "accel_bias_x", "--motion",
                     "manoeuvre", "--hours", "0.05", "--step", "0.1s", "--json",
                     "--no-progress", "--truth", truth]) == 0
        small[truth] = json.loads(capsys.readouterr().out)["sources"]
    assert small["auto"] == small["interpolated"]
    # the table's heading names the truth of a moving run (not of a static one)
    for motion, named in (("manoeuvre", True), ("static", False)):
        assert main(["validity", "orthodromic", "--source", "accel_bias_x", "--motion",
                     motion, "--hours", "0.05", "--step", "2s", "--no-progress",
                     "--truth", "fine"]) == 0
        heading = capsys.readouterr().out.splitlines()[0]
        assert ("fine truth" in heading) == named, heading
    with pytest.raises(SystemExit) as exit_:
        main(["validity", "orthodromic", "--truth", "bogus"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "'bogus'" in err and "interpolated" in err
