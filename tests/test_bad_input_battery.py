"""A battery of bad inputs: every one gives one line naming the problem and exit status 2.

Each command-line case runs the real entry point (:func:`ins_errors.cli.main`) in a
scratch folder; a traceback, a second line, another status or a stack of output files
left behind is a failure. Every registered subcommand (including ones added later) is
also fed an unknown option and, if it takes a model, an unknown model name. The public
API cases check that the library raises :class:`ins_errors.InsErrorsError` with a
one-line message.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

import ins_errors
from ins_errors.cli import build_parser, main

ROOT = Path(__file__).resolve().parent.parent
GOOD_SOURCE = "gyro_drift_x=0.01deg/h"
SCENARIO = """model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "1 h"
step = "1 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
"""


FILES: dict[str, str | bytes] = {
    "binary.toml": bytes(range(256)) * 4,
    "invalid.toml": "model = \n[run\n",
    "empty.csv": "",
    "header_only.csv": "t,v_N,v_E\n",
    "two_samples.csv": "t,v_N,v_E\n0,0,100\n100,0,100\n",
    "one_sample.csv": "t,v_N,v_E\n0,0,100\n",
    "stops.csv": "t,v_N,v_E\n0,0,100\n600,0,100\n1200,0,0\n1800,0,100\n3600,0,100\n",
    "no_t.csv": "time,v_N,v_E\n0,1,2\n10,1,2\n",
    "latitude_list.toml": SCENARIO.replace('"50 deg"', '["30 deg", "60 deg"]'),
    "nan_row.csv": "t,v_N,v_E\n0,0,100\n1200,nan,100\n2400,0,100\n3600,0,100\n",
    "bare_duration.toml": SCENARIO.replace('duration = "1 h"', "duration = 24"),
    "bare_source.toml": SCENARIO.replace('"0.01 deg/h"', '"0.01"'),
    "unknown_key.toml": SCENARIO.replace("[run]", "[run]\nduraton = \"1 h\""),
    "unknown_source.toml": SCENARIO.replace("gyro_drift_x", "gyro_drift_q"),
    "unknown_model.toml": SCENARIO.replace("orthodromic", "orthodromik"),
    "pole.toml": SCENARIO.replace('"50 deg"', '"90 deg"'),
    "nan.toml": SCENARIO.replace('"0.01 deg/h"', '"nan deg/h"'),
    "wrong_unit.toml": SCENARIO.replace('"0.01 deg/h"', '"0.01 m/s"'),
    "no_case.toml": SCENARIO.split("[[case]]")[0],
    "bad_method.toml": SCENARIO.replace('step = "1 s"', 'step = "1 s"\nmethod = "rk5"'),
    "bad_grid.toml": SCENARIO.replace('step = "1 s"', 'step = "7 s"'),
    "tiny_step.toml": SCENARIO.replace('step = "1 s"', 'step = "1e-9 s"'),
    "case_not_table.toml": SCENARIO.replace("[[case]]", "[case]"),
    "bad_motion.toml": SCENARIO.replace('kind = "static"', 'kind = "hovering"'),
    "spec_bare.toml": 'title = "x"\noperating_time = 8\n',
    "a_file": "not a folder\n",
    "good.toml": SCENARIO,
    "backwards.toml": SCENARIO.replace('kind = "static"',
                                       'kind = "great-circle"\nspeed = "-250 m/s"'),
    "hand.txt": "dot(alpha_x) = \n",
    "empty.txt": "",
    "empty.mat": "",
    "garbage.mat": bytes(range(7, 200)),
    "garbage.npz": "not an archive\n",
    "text_in_motion.csv": "t,v_N,v_E\n0,0,100\n1200,fast,100\n2400,0,100\n3600,0,100\n",
    "short_row.csv": "t,v_N,v_E\n0,0,100\n1200,100\n2400,0,100\n3600,0,100\n",
    "speed_at_rest.toml": SCENARIO.replace('kind = "static"',
                                           'kind = "static"\nspeed = "250 m/s"'),
    "file_at_rest.toml": SCENARIO.replace('kind = "static"',
                                          'kind = "static"\nfile = "short_row.csv"'),
    "speed_with_file.toml": SCENARIO.replace(
        'kind = "static"', 'kind = "file"\nfile = "nan_row.csv"\nspeed = "100 m/s"'),
    "legs_on_great_circle.toml": SCENARIO.replace('kind = "static"', 'kind = "great-circle"')
    + '[[motion.legs]]\nduration = "10 min"\nturn = "90 deg"\n',
    "heading_beyond_a_turn.toml": SCENARIO.replace('kind = "static"', 'kind = "great-circle"'
                                                   '\nheading = "1e300 deg"'),
    "threshold_1000.toml": SCENARIO.replace("[run]", "[run]\nvalidity_threshold = 1000"),
}

LONG = "a" * 300
"""A file name longer than any file system allows (255 bytes)."""

MANUAL = str(ROOT / "examples" / "manual_000" / "equations.tex")
SWEEP = str(ROOT / "examples" / "sweep_latitude_heading.toml")
MATRIX = ["check", "strapdown_ned", "--convention", "psi", "--matrix"]

CLI_CASES: dict[str, list[str]] = {
    # front door
    "no-such-command": ["frobnicate"],
    "no-command": [],
    "unknown-option": ["models", "--colour"],
    # models
    "models-unknown": ["models", "orthodromik"],
    # run
    "run-missing-file": ["run", "missing.toml"],
    "run-folder-as-file": ["run", "."],
    "run-binary": ["run", "binary.toml"],
    "run-invalid-toml": ["run", "invalid.toml"],
    "run-bare-duration": ["run", "bare_duration.toml"],
    "run-bare-source": ["run", "bare_source.toml"],
    "run-unknown-key": ["run", "unknown_key.toml"],
    "run-unknown-source": ["run", "unknown_source.toml"],
    "run-unknown-model": ["run", "unknown_model.toml"],
    "run-pole": ["run", "pole.toml"],
    "run-nan": ["run", "nan.toml"],
    "compare-bare-nan-latitude": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--latitude",
                                  "nan"],
    "run-wrong-unit": ["run", "wrong_unit.toml"],
    "run-no-case": ["run", "no_case.toml"],
    "run-bad-method": ["run", "bad_method.toml"],
    "run-bad-grid": ["run", "bad_grid.toml"],
    "run-absurd-steps": ["run", "tiny_step.toml"],
    "run-case-not-array": ["run", "case_not_table.toml"],
    "run-bad-motion": ["run", "bad_motion.toml"],
    "run-out-is-a-file": ["run", "good.toml", "--out", "a_file"],
    "run-negative-speed": ["run", "backwards.toml"],
    "run-latitude-list": ["run", "latitude_list.toml"],
    "run-out-foreign-folder": ["run", "good.toml", "--out", "."],
    # compare
    "compare-no-source": ["compare", "orthodromic"],
    "compare-bare-number": ["compare", "orthodromic", "-s", "gyro_drift_x=0.01"],
    "compare-unknown-source": ["compare", "orthodromic", "-s", "gyro_drift=0.01deg/h"],
    "compare-no-equals": ["compare", "orthodromic", "-s", "gyro_drift_x"],
    "compare-twice": ["compare", "orthodromic", "-s", GOOD_SOURCE, "-s", GOOD_SOURCE],
    "compare-wrong-unit": ["compare", "orthodromic", "-s", "gyro_drift_x=1m"],
    "compare-pole": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--latitude", "90deg"],
    "compare-bare-latitude": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--latitude", "50"],
    "compare-absurd-steps": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--step", "1e-9s",
                             "--hours", "1"],
    "compare-zero-step": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--step", "0s"],
    "compare-hours-and-duration": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                   "1", "--duration", "1 h"],
    "compare-bad-hours": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours", "soon"],
    "compare-empty-motion-file": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                  "--motion-file", "empty.csv"],
    "compare-header-only-motion": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                   "--motion-file", "header_only.csv"],
    "compare-motion-lacks-t": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                               "--motion-file", "no_t.csv"],
    "compare-binary-motion": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                              "--motion-file", "binary.toml"],
    "compare-bad-motion-kind": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--motion",
                                "orbit"],
    "compare-negative-speed": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--motion",
                               "great-circle", "--speed", "-250m/s", "--hours", "1"],
    "compare-flight-without-heading": ["compare", "north_pointing", "-s",
                                       "accel_bias_east=100ug", "--motion", "great-circle",
                                       "--hours", "1"],
    "compare-strapdown-over-the-pole": ["compare", "strapdown_ned", "-s", "accel_bias_x=100ug",
                                        "--motion", "great-circle", "--heading", "0deg",
                                        "--hours", "6", "--step", "10s", "--no-refined"],
    "compare-below-the-centre": ["compare", "strapdown_ned", "-s", "accel_bias_x=100ug",
                                 "--motion", "great-circle", "--height", "-7000km",
                                 "--hours", "1"],
    "compare-two-sample-motion-file": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                       "--motion-file", "two_samples.csv"],
    "compare-motion-file-for-strapdown-stops": ["compare", "strapdown_ned", "-s",
                                                "gyro_bias_x=0.01deg/h", "--hours", "1",
                                                "--motion-file", "stops.csv"],
    "compare-nan-in-motion-file": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                   "1", "--motion-file", "nan_row.csv"],
    "compare-pole-flight": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--motion",
                            "great-circle", "--heading", "0deg", "--hours", "6",
                            "--step", "10s"],
    # budget
    "budget-missing-spec": ["budget", "orthodromic", "--spec", "missing.toml"],
    "budget-binary-spec": ["budget", "orthodromic", "--spec", "binary.toml"],
    "budget-bare-spec-number": ["budget", "orthodromic", "--spec", "spec_bare.toml"],
    "budget-plot-at-alone": ["budget", "orthodromic", "--plot-at", "x.png"],
    "budget-plot-under-a-file": ["budget", "orthodromic", "--plot", "a_file/budget.png"],
    "budget-mc-one-run": ["budget", "orthodromic", "--monte-carlo", "1"],
    # check
    "check-missing-file": ["check", "orthodromic", "missing.txt"],
    "check-empty-file": ["check", "orthodromic", "empty.txt"],
    "check-binary-file": ["check", "orthodromic", "binary.toml"],
    "check-unknown-model": ["check", "orthodromik", "hand.txt"],
    "check-report-is-a-folder": ["check", "orthodromic",
                                 str(ROOT / "examples" / "manual_000" / "equations.txt"),
                                 "--report", "."],
    "check-empty-mat": [*MATRIX, "empty.mat"],
    "check-garbage-mat": [*MATRIX, "garbage.mat"],
    "check-garbage-npz": [*MATRIX, "garbage.npz"],
    "check-report-name-too-long": ["check", "orthodromic", MANUAL, "--report", LONG + ".md"],
    # output names longer than the file system allows
    "run-out-name-too-long": ["run", "good.toml", "--out", LONG],
    "compare-out-name-too-long": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours", "1",
                                  "--out", LONG],
    "compare-plot-name-too-long": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                   "1", "--plot", LONG + ".png"],
    "compare-markdown-name-too-long": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                       "--hours", "1", "--markdown", LONG + ".md"],
    "sweep-store-name-too-long": ["sweep", SWEEP, "--store", LONG + ".zarr"],
    "propagation-out-name-too-long": ["propagation", "--hours", "1", "--out", LONG],
    "compare-plot-without-suffix": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                    "1", "--plot", "noext"],
    "budget-plot-without-suffix": ["budget", "orthodromic", "--plot", "noext"],
    "sweep-plot-without-suffix": ["sweep", SWEEP, "--store", "s.zarr", "--plot", "noext"],
    "compare-speed-at-rest": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours", "1",
                              "--speed", "250m/s"],
    "compare-speed-with-motion-file": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                       "--motion-file", "text_in_motion.csv", "--speed",
                                       "100m/s"],
    "compare-text-in-motion-file": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                    "1", "--motion-file", "text_in_motion.csv"],
    "compare-short-row-in-motion-file": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                         "--hours", "1", "--motion-file", "short_row.csv"],
    # motion settings the kind does not use (dropped silently by the scenario files)
    "run-speed-at-rest": ["run", "speed_at_rest.toml"],
    "run-file-at-rest": ["run", "file_at_rest.toml"],
    "run-speed-with-motion-file": ["run", "speed_with_file.toml"],
    "run-legs-on-a-great-circle": ["run", "legs_on_great_circle.toml"],
    # headings beyond a turn (the header printed χ=1e+300°)
    "compare-heading-beyond-a-turn": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                      "1", "--heading", "1e300deg"],
    "compare-track-beyond-a-turn": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours",
                                    "1", "--motion", "great-circle", "--heading", "-400deg"],
    "run-heading-beyond-a-turn": ["run", "heading_beyond_a_turn.toml"],
    "compare-longitude-beyond-a-turn": ["compare", "orthodromic", "-s", GOOD_SOURCE,
                                        "--hours", "1", "--longitude", "1e300deg"],
    # zero gravity on the equator: normal gravity and the bank rule divide by it
    "compare-zero-gravity": ["compare", "strapdown_ned", "-s", "accel_bias_x=100ug",
                             "--parameter", "gamma_e=0m/s^2", "--hours", "1"],
    "compare-negative-gravity": ["compare", "strapdown_ned", "-s", "accel_bias_x=100ug",
                                 "--parameter", "gamma_e=-9.78m/s^2", "--hours", "1"],
    # a ratio of 1000 (100000 %): said "must be a positive ratio"
    "compare-threshold-1000": ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours", "1",
                               "--validity-threshold", "1000"],
    "run-threshold-1000": ["run", "threshold_1000.toml"],
    # a 30° initial tilt on the small-angle platform: said "between t = -60 s and 0 s"
    "compare-small-angle-tilt": ["compare", "orthodromic", "-s", "initial_tilt_x=30deg",
                                 "--platform", "small-angle", "--hours", "1"],
    "compare-small-angle-tilt-north-pointing": ["compare", "north_pointing", "-s",
                                                "initial_tilt_east=30deg", "--platform",
                                                "small-angle", "--hours", "1"],
    # study
    "study-unknown": ["study", "coriolisis"],
    "study-bare-latitude": ["study", "coriolis", "--latitude", "50"],
    "study-zero-step": ["study", "coriolis", "--step", "0 s"],
    "study-absurd-steps": ["study", "spheroid", "--step", "1e-9s", "--hours", "1"],
    "study-plot-is-a-file": ["study", "coriolis", "--plot", "a_file"],
    # propagation
    "propagation-out-is-a-file": ["propagation", "--out", "a_file"],
    "propagation-bare-drift": ["propagation", "--drift", "0.1"],
    "propagation-pole": ["propagation", "--latitude", "90deg"],
    "propagation-negative-hours": ["propagation", "--hours", "-1"],
    "propagation-absurd-steps": ["propagation", "--step", "1e-9s", "--hours", "1"],
    "propagation-foreign-folder": ["propagation", "--hours", "1", "--out", "."],
    "propagation-orthodromic-euler": ["propagation", "--orthodromic", "--hours", "1",
                                      "--method", "euler"],
    "propagation-orthodromic-drift": ["propagation", "--orthodromic", "--hours", "1",
                                      "--drift", "1 deg/h"],
    "propagation-zero-drift": ["propagation", "--hours", "1", "--drift", "0deg/h"],
}


def _run(argv: list[str], capsys) -> tuple[int, str, str]:
    try:
        status = main(argv)
    except SystemExit as stop:  # argparse usage errors
        status = stop.code
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def _assert_one_line(status: int, err: str, argv: list[str]) -> None:
    lines = err.strip().splitlines()
    assert status == 2, f"{argv}: status {status}, stderr {err!r}"
    assert len(lines) == 1, f"{argv}: expected one line, got {err!r}"
    assert lines[0].startswith("ins-errors: error: "), lines[0]  # one prefix for every error
    assert "Traceback" not in err


def _write_files(folder: Path) -> None:
    for name, content in FILES.items():
        target = folder / name
        if isinstance(content, bytes):
            target.write_bytes(content)
        else:
            target.write_text(content, encoding="utf-8")


def _state_of(folder: Path) -> dict[str, tuple[int, int]]:
    """Name -> (size, modification time) of each entry of ``folder``."""
    return {e.name: (e.stat().st_size, e.stat().st_mtime_ns) for e in os.scandir(folder)}


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """A fresh folder holding :data:`FILES`, the current folder during the test."""
    _write_files(tmp_path)
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture(scope="module")
def _shared_files(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("files")
    _write_files(folder)
    return folder


@pytest.fixture
def inputs(_shared_files, monkeypatch):
    """The current folder during a test whose calls must write nothing: :data:`FILES`,
    written once for the module (a folder per test made most of these tests' cost). An
    entry the test added, removed or changed fails it, and the folder is made afresh."""
    before = _state_of(_shared_files)
    monkeypatch.chdir(_shared_files)
    yield _shared_files
    if _state_of(_shared_files) != before:
        for entry in _shared_files.iterdir():
            shutil.rmtree(entry) if entry.is_dir() else entry.unlink()
        _write_files(_shared_files)
        pytest.fail("the call added, removed or changed files in the current folder")


def test_the_battery_is_large():
    assert len(CLI_CASES) + len(API_CASES) >= 40
    commands = {argv[0] for argv in CLI_CASES.values() if argv}
    assert {"models", "run", "compare", "budget", "check", "study", "propagation"} <= commands


@pytest.mark.parametrize("argv", CLI_CASES.values(), ids=CLI_CASES.keys())
def test_bad_command_line(argv, inputs, capsys):
    before = sorted(p.name for p in inputs.iterdir())
    status, _out, err = _run(argv, capsys)
    _assert_one_line(status, err, argv)
    print(err.strip())
    assert sorted(p.name for p in inputs.iterdir()) == before, "a failed run left files"


NAMED = {
    # a negative speed is refused as accuracy specs refuse it, not flown backwards under
    # a header that reads "track 90°, -250 m/s"
    "compare-negative-speed": "--speed must be >= 0 m/s, got -250 m/s",
    "run-negative-speed": "great-circle speed must be >= 0 m/s, got -250 m/s",
    # a model without a heading output flies static bases and north/east motion files
    "compare-flight-without-heading": "use a static base or a motion file of north and east",
    # due north from 50° at 250 m/s: over the pole after about 4.9 h (the steps jump past
    # it; the numbers after it meant nothing, with exit status 0)
    "compare-strapdown-over-the-pole": "the true flight reaches a pole",
    # --orthodromic ran RK4 and its own magnitudes whatever these said (the README said
    # --method euler selected the rectangle method there too)
    "propagation-orthodromic-euler": "--method applies to the 001 experiment",
    "propagation-orthodromic-drift": "--drift applies to the 001 experiment",
    # printed "RuntimeWarning: All-NaN slice" with source paths and rows of nan
    "propagation-zero-drift": "--drift is zero",
    "compare-below-the-centre": "--height -7000 km is beyond ±100 km, the heights "
                                "ins-errors accepts, whatever the model (below the Earth's "
                                "centre)",
    "compare-nan-in-motion-file": "v_N is NaN or infinite in sample 2 of 4",
    # it asked for a unit, suggesting 'nan deg'
    "compare-bare-nan-latitude": "'nan' is not a finite number",
    # the file's own key names, not pydantic's (it said motion.latitude.str = [...])
    "run-latitude-list": "motion.latitude must be one value with its unit (e.g. '50 deg'",
    # a traceback of scipy's MatReadError, exit 1 (a "mistake found" to CI)
    "check-empty-mat": "matrix file 'empty.mat' is not a readable .mat file",
    "check-garbage-mat": "matrix file 'garbage.mat' is not a readable .mat file",
    # said the file held "pickled data"
    "check-garbage-npz": "matrix file 'garbage.npz' is not a readable .npz file",
    # tracebacks of OSError: [Errno 36], exit 1; the name shortened, its length said
    "check-report-name-too-long": "(303 characters): File name too long",
    "run-out-name-too-long": "(300 characters): File name too long",
    "compare-out-name-too-long": "(300 characters): File name too long",
    "compare-plot-name-too-long": "(304 characters): File name too long",
    "compare-markdown-name-too-long": "(303 characters): File name too long",
    "sweep-store-name-too-long": "(305 characters): File name too long",
    "propagation-out-name-too-long": "(300 characters): File name too long",
    # matplotlib read the temporary file's random suffix: "Format 'cthilzch' is not ..."
    "compare-plot-without-suffix": "'noext': it has no suffix; end the name with the "
                                   "format, such as .png, .pdf or .svg",
    # refused before the allocation and before any sweep point runs (was: after them)
    "budget-plot-without-suffix": "'noext': it has no suffix; end the name with the format",
    "sweep-plot-without-suffix": "'noext': it has no suffix; end the name with the format",
    # silently ignored
    "compare-speed-at-rest": "--speed applies to --motion great-circle or manoeuvre, and "
                             "the base is static",
    "compare-speed-with-motion-file": "and --motion-file gives the motion",
    # said "v_N is NaN or infinite in sample 2 of 4"
    "compare-text-in-motion-file": "column v_N, sample 2 (line 3): 'fast' is not a number",
    "compare-short-row-in-motion-file": "line 3 has 2 values, the header 3 columns",
    # printed the whole help with exit status 0
    "no-command": "give a command, e.g. 'ins-errors models' (usage: ins-errors",
    # worded as the command line's --speed
    "run-speed-at-rest": "motion speed applies to kind great-circle or manoeuvre, and the "
                         "base is static: leave speed out or choose kind 'great-circle' or "
                         "'manoeuvre'",
    "run-file-at-rest": "motion file applies to kind file, and the base is static: leave "
                        "file out",
    "run-speed-with-motion-file": "motion speed applies to kind great-circle or manoeuvre, "
                                  "and the file gives the motion",
    "run-legs-on-a-great-circle": "motion legs apply to kind manoeuvre, and the kind is "
                                  "great-circle",
    "compare-heading-beyond-a-turn": "--heading 1e+300° is outside [-360°, 360°]",
    "compare-track-beyond-a-turn": "--heading -400° is outside [-360°, 360°]",
    "run-heading-beyond-a-turn": "motion track 1e+300° is outside [-360°, 360°]",
    "compare-longitude-beyond-a-turn": "--longitude 1e+300° is outside [-360°, 360°]",
    "compare-zero-gravity": "normal gravity on the equator gamma_e must be positive",
    "compare-negative-gravity": "normal gravity on the equator gamma_e must be positive",
    "compare-threshold-1000": "--validity-threshold '1000': the ratio 1000 (100000 %) is "
                              "outside the accepted range, above 0 and below 10 (1000 % of "
                              "the error",
    "run-threshold-1000": "validity_threshold = 1000: the ratio 1000 (100000 %) is outside "
                          "the accepted range, above 0 and below 10 (1000 % of the error",
    "compare-small-angle-tilt": "starts outside its domain (t = 0 s, the initial errors): "
                                "platform angle alpha_x = 30° exceeds 0.5 rad (28.65°), "
                                "beyond the small-angle platform matrix",
    "compare-small-angle-tilt-north-pointing": "(t = 0 s, the initial errors): platform "
                                               "angle alpha_E = 30° exceeds 0.5 rad",
    # a cubic spline needs four samples: said before the profile's internal shape check
    "compare-two-sample-motion-file": "has 2 row(s) of samples; a sampled motion needs at "
                                      "least 4",
    # a scenario's model, case and motion errors name the file (a student could not tell
    # which of their files held the typo)
    "run-unknown-model": "unknown_model.toml: unknown model",
    "run-unknown-source": "unknown_source.toml [[case]] 1: unknown source of orthodromic",
    "run-pole": "pole.toml [motion]: motion latitude",
    # a strapdown INS heads along the file's course: undefined where the vehicle stops
    "compare-motion-file-for-strapdown-stops": "ground speed is 0 m/s at t = 1200 s: a "
                                               "strapdown INS heads along the course",
}
"""Cases whose one line must say this (what to do, not only what failed)."""


@pytest.mark.parametrize("case", NAMED)
def test_the_line_names_the_problem_and_the_way_out(case, inputs, capsys):
    _status, _out, err = _run(CLI_CASES[case], capsys)
    assert NAMED[case] in err


def test_a_manoeuvre_leg_with_a_negative_speed_is_refused():
    from ins_errors.numeric import trajectories as tr

    legs = [tr.Leg(600.0, 200.0, 0.0, 0.0), tr.Leg(600.0, -50.0, 0.0, 0.0)]
    with pytest.raises(tr.MotionError, match="manoeuvre leg speed must be >= 0 m/s"):
        tr.manoeuvre_profile(0.8, 0.5, 0.0, 250.0, legs)
    with pytest.raises(tr.MotionError, match="manoeuvre speed must be >= 0 m/s"):
        tr.manoeuvre_profile(0.8, 0.5, 0.0, -250.0, legs[:1])


def _subcommands() -> dict[str, object]:
    parser = build_parser()
    action = next(a for a in parser._actions if a.dest == "command")
    return dict(action.choices)


@pytest.mark.parametrize("name", sorted(_subcommands()))
def test_every_subcommand_refuses_an_unknown_option(name, inputs, capsys):
    status, _out, err = _run([name, "--no-such-option"], capsys)
    _assert_one_line(status, err, [name])


def test_an_unknown_option_points_to_its_commands_help_and_a_split_unit_is_named(capsys):
    """Unknown arguments were reported by the top level ('see ins-errors --help', which
    lists no options); a unit split from its value by a space was just 'deg/h'."""
    status, _out, err = _run(["compare", "orthodromic", "-s", "gyro_drift_x=0.01", "deg/h"],
                             capsys)
    assert status == 2 and err.startswith("ins-errors: error: compare: unrecognized "
                                          "arguments: deg/h; a value and its unit go")
    assert err.rstrip().endswith("(see 'ins-errors compare --help')")
    for hours in ("2", "1"):  # (pint reads a bare 1 as the dimensionless unit)
        status, _out, err = _run(["run", "x.toml", "--hours", hours], capsys)
        assert status == 2 and "(see 'ins-errors run --help')" in err and "unit" not in err


@pytest.mark.parametrize("name", sorted(n for n, p in _subcommands().items()
                                        if any(a.dest == "model" and not a.option_strings
                                               for a in p._actions)))
def test_every_model_taking_subcommand_names_close_models(name, inputs, capsys):
    sub = _subcommands()[name]
    positionals = [a for a in sub._actions if not a.option_strings and a.dest != "help"]
    argv = [name] + ["orthodromik" if a.dest == "model" else "hand.txt"
                     for a in positionals if a.nargs in (None, 1, "?", "*", "+")]
    status, _out, err = _run(argv, capsys)
    _assert_one_line(status, err, argv)
    assert "orthodromic" in err


@pytest.mark.parametrize("argv", [
    ["run", "pole.toml"],
    ["compare", "orthodromic", "-s", GOOD_SOURCE, "--plot", "out.png"],
    ["budget", "orthodromic", "--plot", "budget.png"],
    ["study", "coriolis", "--plot", "plots"],
    ["propagation", "--out", "p001"],
], ids=lambda argv: argv[0])
def test_missing_matplotlib_is_one_line_before_computing(argv, inputs, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    status, out, err = _run(argv, capsys)
    _assert_one_line(status, err, argv)
    assert "install ins-errors[plots]" in err
    assert not out  # nothing computed, nothing printed


SMALL_PLOTS = '[outputs]\nquantities = ["alpha_y"]\n'
"""One quantity in the report's tables and plots: these tests are about the folder."""


def test_existing_report_folder_is_replaced_cleanly(scratch, capsys):
    """A re-run replaces the report and removes its stale files, leaves others alone."""
    two_cases = SCENARIO.replace('duration = "1 h"', 'duration = "10 min"').replace(
        "[[case]]", SMALL_PLOTS + "[[case]]") + '[[case]]\ngyro_drift_y = "0.01 deg/h"\n'
    Path("two.toml").write_text(two_cases, encoding="utf-8")
    assert _run(["run", "two.toml", "--out", "rep", "--no-progress"], capsys)[0] == 0
    assert (scratch / "rep" / "case_2.png").exists()
    (scratch / "rep" / "notes.txt").write_text("mine", encoding="utf-8")
    one_case = two_cases.split("[[case]]\ngyro_drift_y")[0]
    Path("two.toml").write_text(one_case, encoding="utf-8")
    assert _run(["run", "two.toml", "--out", "rep", "--no-progress"], capsys)[0] == 0
    left = sorted(p.name for p in (scratch / "rep").iterdir() if not p.name.startswith("."))
    assert left == ["case_1.png", "curves.csv", "curves.mat", "notes.txt", "report.html",
                    "report.md", "results.json"]
    assert not list((scratch / "rep").glob(".*.tmp*"))


def test_force_writes_into_a_foreign_folder_leaving_its_files(scratch, capsys):
    short = SCENARIO.replace('duration = "1 h"', 'duration = "10 min"').replace(
        "[[case]]", SMALL_PLOTS + "[[case]]")
    Path("short.toml").write_text(short, encoding="utf-8")
    status, _out, err = _run(["run", "short.toml", "--out", ".", "--no-progress"], capsys)
    assert status == 2 and "--force" in err
    status, _out, _err = _run(["run", "short.toml", "--out", ".", "--force", "--no-progress"],
                              capsys)
    assert status == 0
    assert (scratch / "report.md").exists() and (scratch / "a_file").read_text() == FILES[
        "a_file"]


def test_a_named_file_is_replaced_with_a_note(scratch, capsys):
    argv = ["compare", "orthodromic", "-s", GOOD_SOURCE, "--hours", "0.5", "--no-refined",
            "--markdown", "a_file"]
    status, out, err = _run(argv, capsys)
    assert status == 0 and "replaced a_file" in err
    assert (scratch / "a_file").read_text(encoding="utf-8").strip() in out


# --------------------------------------------------------------------------------------
# The public API
# --------------------------------------------------------------------------------------
def _orthodromic():
    return ins_errors.load_model("orthodromic")


def _state(model):
    c = model.initial_condition_vector(latitude=0.8)
    u = model.input_vector(a_zeta=9.81)
    return model.initial_state(c, u), u


def _api_load_scenario(path):
    from ins_errors.scenario import load_scenario

    return load_scenario(path)


def _api_load_spec(path):
    from ins_errors.specs import load_spec

    return load_spec(path)


def _api_motion(description):
    from ins_errors.numeric.motion_spec import motion_profile

    return motion_profile(description)


def _api_quantity(text, unit):
    from ins_errors.units import parse_quantity

    return parse_quantity(text, unit, "value")


def _api_trajectory(duration, tau):
    from ins_errors.numeric import trajectories as tr

    model = _orthodromic()
    return tr.trajectory(model, tr.static_profile(0.8, 0.5, 0.0), duration, tau)


def _api_simulate(sources, run=None):
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.simulate import simulate

    model = _orthodromic()
    static = tr.trajectory(model, tr.static_profile(0.8), 600.0, 10.0)
    return (run or simulate)(model, static, sources)


def _api_compare(sources):
    from ins_errors.numeric.compare import compare

    return _api_simulate(sources, compare)


def _api_static_trajectory(model=None, duration=600.0, p=None):
    from ins_errors.numeric import trajectories as tr

    return tr.trajectory(model or _orthodromic(), tr.static_profile(0.8), duration, 10.0, p=p)


def _api_strapdown_latitude(degrees):
    model = ins_errors.load_model("strapdown_ned")
    u = model.input_vector(f_z=-9.8)
    x = model.initial_state(model.initial_condition_vector(latitude=0.8), u)
    x[model.index("states", "lat")] = np.radians(degrees)
    return model.state_matrix(x, u)


def _api_write_into_file():
    from ins_errors.output import OutputFolder

    return OutputFolder("a_file")


def _api_write_text_into_folder():
    from ins_errors.output import write_text

    return write_text(".", "x")


def _api_hand_file(path):
    from ins_errors.checker.notation import Notation
    from ins_errors.checker.parse import read_hand_file

    return read_hand_file(path, Notation())


API_CASES = {
    "load_model-unknown": lambda: ins_errors.load_model("orthodromik"),
    "source_vector-unknown": lambda: _orthodromic().source_vector(gyro_drift_q=1.0),
    "source_vector-nan": lambda: _orthodromic().source_vector(gyro_drift_x=np.nan),
    "parameter_vector-ellipsoid": lambda: _orthodromic().parameter_vector(ellipsoid="wgs-84"),
    # values in SI get the rule values read from text get (parse_parameters)
    "parameter_vector-negative-e2": lambda: ins_errors.load_model(
        "strapdown_ned").parameter_vector(e2=-0.1),
    "parameter_vector-negative-gain": lambda: ins_errors.load_model(
        "strapdown_ned").parameter_vector(k_h1=-0.01),
    "state_matrix-shape": lambda: _orthodromic().state_matrix(_state(_orthodromic())[0][:5],
                                                              _state(_orthodromic())[1]),
    "initial_state-pole": lambda: _orthodromic().initial_state(
        _orthodromic().initial_condition_vector(latitude=np.pi / 2),
        _orthodromic().input_vector()),
    "load_scenario-binary": lambda: _api_load_scenario("binary.toml"),
    "load_scenario-bare": lambda: _api_load_scenario("bare_duration.toml"),
    "load_spec-binary": lambda: _api_load_spec("binary.toml"),
    "motion-kind": lambda: _api_motion({"kind": "orbit"}),
    "motion-bare-latitude": lambda: _api_motion({"latitude": "50"}),
    "quantity-bare": lambda: _api_quantity("0.01", "rad/s"),
    "quantity-garbage": lambda: _api_quantity("ten deg", "rad"),
    "trajectory-absurd": lambda: _api_trajectory(3600.0, 1e-9),
    "trajectory-grid": lambda: _api_trajectory(3600.0, 7.0),
    "simulate-no-cases": lambda: _api_simulate([]),
    "compare-no-cases": lambda: _api_compare([]),
    "simulate-sources-too-short": lambda: _api_simulate(np.zeros(5)),
    "simulate-sources-as-rows": lambda: _api_simulate([[0.0] * 26]),
    "simulate-sources-text": lambda: _api_simulate("gyro_drift_x"),
    "simulate-not-a-trajectory": lambda: _api_simulate(None, lambda m, _t, w: __import__(
        "ins_errors.numeric.simulate", fromlist=["simulate"]).simulate(m, "traj", w)),
    "trajectory-p-too-short": lambda: _api_static_trajectory(p=np.ones(2)),
    "trajectory-p-batch": lambda: _api_static_trajectory(p=np.ones((3, 2))),
    "trajectory-p-nan": lambda: _api_static_trajectory(p=np.full(3, np.nan)),
    "trajectory-e2-above-1": lambda: _api_static_trajectory(
        p=_orthodromic().parameter_vector(e2=1.5)),
    "trajectory-zero-duration": lambda: _api_static_trajectory(duration=0.0),
    "trajectory-not-a-model": lambda: _api_static_trajectory(model=3),
    "state_matrix-batch-axes": lambda: _orthodromic().state_matrix(
        np.repeat(_state(_orthodromic())[0][:, None], 4, axis=1),
        np.repeat(_state(_orthodromic())[1][:, None], 3, axis=1)),
    "initial_state-beyond-pole": lambda: _orthodromic().initial_state(
        _orthodromic().initial_condition_vector(latitude=np.radians(100)),
        _orthodromic().input_vector()),
    "state_matrix-latitude-beyond-pole": lambda: _api_strapdown_latitude(100.0),
    "ideal_rhs-complex": lambda: _orthodromic().ideal_rhs(_state(_orthodromic())[0] + 0j,
                                                          _state(_orthodromic())[1]),
    "source_vector-text": lambda: _orthodromic().source_vector(gyro_drift_x="0.01 deg/h"),
    "parameter_vector-text": lambda: _orthodromic().parameter_vector(a="abc"),
    "source_vector-array": lambda: _orthodromic().source_vector(gyro_drift_x=np.ones(2)),
    "index-unknown-kind": lambda: _orthodromic().index("nope", "x"),
    "static_profile-text": lambda: __import__(
        "ins_errors.numeric.trajectories", fromlist=["x"]).static_profile("50"),
    "strapdown-static-text": lambda: __import__(
        "ins_errors.numeric.strapdown_truth", fromlist=["x"]).static(0.8, "0"),
    "strapdown-negative-speed": lambda: __import__(
        "ins_errors.numeric.strapdown_truth", fromlist=["x"]).great_circle(0.8, 0, 0, -250.0),
    "resolvent-numpy": lambda: __import__(
        "ins_errors.symbolic.analytic", fromlist=["x"]).resolvent(np.eye(2)),
    "static_analyses-unknown": lambda: __import__(
        "ins_errors.symbolic.static_base", fromlist=["x"]).static_analyses("nope"),
    "output-folder-is-file": _api_write_into_file,
    "output-file-is-folder": _api_write_text_into_folder,
    "hand-file-binary": lambda: _api_hand_file("binary.toml"),
    "static_profile-heading-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.trajectories", fromlist=["x"]).static_profile(0.8, 0.0, 7.0),
    "great_circle-longitude-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.trajectories", fromlist=["x"]).great_circle_profile(
        0.8, -1e3, 0.5, 250.0),
    "great_circle-track-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.trajectories", fromlist=["x"]).great_circle_profile(
        0.8, 0.0, 1e300, 250.0),
    "manoeuvre-track-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.trajectories", fromlist=["x"]).manoeuvre_profile(
        0.8, 0.0, -20.0, 250.0, []),
    "sampled-heading-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.trajectories", fromlist=["x"]).sampled_profile(
        np.arange(4.0), np.zeros(4), np.zeros(4), 0.8, 0.0, 1e3),
    "strapdown-course-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.strapdown_truth", fromlist=["x"]).great_circle(0.8, 0, 1e3, 250.0),
    "strapdown-longitude-beyond-a-turn": lambda: __import__(
        "ins_errors.numeric.strapdown_truth", fromlist=["x"]).static(0.8, 1e3),
    "motion-speed-at-rest": lambda: _api_motion({"kind": "static", "speed": "250 m/s"}),
    "parameter_vector-zero-gravity": lambda: ins_errors.load_model(
        "strapdown_ned").parameter_vector(gamma_e=0.0),
}


@pytest.mark.parametrize("call", API_CASES.values(), ids=API_CASES.keys())
def test_bad_api_call(call, inputs):
    with pytest.raises(ins_errors.InsErrorsError) as raised:
        call()
    message = str(raised.value)
    assert message and "\n" not in message, message


def test_negative_quantities_are_values_not_options(scratch, capsys):
    """``--latitude -45deg`` is a southern latitude, not an unknown option."""
    argv = ["compare", "orthodromic", "-s", GOOD_SOURCE, "--latitude", "-45deg",
            "--hours", "0.5", "--no-refined"]
    status, out, err = _run(argv, capsys)
    assert status == 0, err
    assert "φ=-45°" in out


def test_version(capsys):
    status, out, _err = _run(["--version"], capsys)
    assert status == 0 and out.startswith("ins-errors ") and out.split()[1][0].isdigit()


@pytest.mark.parametrize("name", sorted(_subcommands()))
def test_help_names_only_files_that_exist(name, capsys):
    """Every examples/... path a command's --help names is a file of the project."""
    status, out, _err = _run([name, "--help"], capsys)
    assert status == 0
    for path in re.findall(r"examples/[\w./-]+\w", out):
        assert (ROOT / path).exists(), f"{name} --help names {path}"


def test_one_mapping_is_one_case_in_compare_as_in_simulate():
    """``compare`` takes a single ``{name: value}`` mapping as one case (it iterated over
    the names); the linear run of a drift on a static base follows the direct one."""
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare

    model = _orthodromic()
    static = tr.trajectory(model, tr.static_profile(0.8), 600.0, 10.0)
    one = compare(model, static, {"gyro_drift_x": 1e-8}, refined=False,
                  integration_error=False, validity_threshold=None)
    assert [c.sources for c in one] == [{"gyro_drift_x": 1e-8}]
    assert one[0].worst_linear.linear_ratio < 1e-3


NAMED_API = {
    "simulate-no-cases": "give at least one case of error sources",
    "trajectory-p-batch": "parameters p must have shape (3,) [a, e2, U], got (3, 2)",
    # the parameters are the problem, not the "static-base inputs" they made NaN
    "trajectory-p-nan": "trajectory: parameters p contain NaN",
    "trajectory-e2-above-1": "parameters of orthodromic: eccentricity squared must be below 1",
    # as the scenario files refuse it (compare() returned worst_linear None)
    "trajectory-zero-duration": "run duration must be positive, got 0 s",
    "initial_state-beyond-pole": "latitude must be within ±90°",
    "state_matrix-latitude-beyond-pole": "lat must be within ±90°",
    "source_vector-text": "ins_errors.units.parse_quantity('0.01 deg/h', 'rad/s')",
    "state_matrix-batch-axes": "batch axes",
    "static_profile-text": "motion latitude takes a number in SI units (rad), got '50'",
    # worded as the orthodromic models' "great-circle speed must be >= 0 m/s, got ..."
    "strapdown-negative-speed": "great-circle speed must be > 0 m/s, got -250 m/s",
    "static_profile-heading-beyond-a-turn": "motion heading 401.07° (7 rad) is outside",
    "great_circle-longitude-beyond-a-turn": "motion longitude -57295.8° (-1000 rad) is outside",
    "great_circle-track-beyond-a-turn": "motion track 5.72958e+301° is outside [-360°, 360°]",
    "manoeuvre-track-beyond-a-turn": "motion track -1145.92° (-20 rad) is outside [-360°, 360°]",
    "sampled-heading-beyond-a-turn": "motion heading 57295.8° (1000 rad) is outside [-360°, 360°]",
    "strapdown-course-beyond-a-turn": "flight course 57295.8° (1000 rad) is outside [-360°, 360°]",
    "strapdown-longitude-beyond-a-turn": "flight longitude 57295.8° (1000 rad) is outside",
    "motion-speed-at-rest": "motion speed applies to kind great-circle or manoeuvre",
    "parameter_vector-zero-gravity": "gamma_e must be positive",
    "parameter_vector-negative-e2": "e2 = -0.1: the Earth's eccentricity squared must be at "
                                    "least 0",
    "parameter_vector-negative-gain": "k_h1 = -0.01: a vertical damping gain must be zero "
                                      "(undamped) or positive",
}
"""API cases whose one line must say this."""


@pytest.mark.parametrize("case", NAMED_API)
def test_the_api_line_names_the_problem(case, inputs):
    with pytest.raises(ins_errors.InsErrorsError, match=re.escape(NAMED_API[case])):
        API_CASES[case]()


def test_latitude_just_inside_the_pole_is_accepted():
    """The ±90° refusal does not cut into the domain: 89.9° gives the true state."""
    model = _orthodromic()
    x = model.initial_state(model.initial_condition_vector(latitude=np.radians(89.9)),
                            model.input_vector())
    assert x[model.index("states", "u31")] == pytest.approx(np.sin(np.radians(89.9)))


def test_trajectory_takes_a_model_name():
    by_name = _api_static_trajectory(model="orthodromic")
    assert np.array_equal(by_name.start_state, _api_static_trajectory().start_state)


def test_the_real_state_is_listed_by_its_own_names():
    model = _orthodromic()
    x, u = _state(model)
    with pytest.raises(ins_errors.ShapeError, match=r"\[u11, u21, .*, alpha_z\]"):
        model.real_rhs(np.zeros(3), x, u, model.source_vector())


def test_headings_of_a_whole_turn_are_accepted_and_mean_due_north():
    """The ±360° refusal does not cut into the accepted range: a great circle started at
    track ±360° flies the track-0° one (the same start state, the same description but its
    angle)."""
    from ins_errors.numeric import trajectories as tr

    model = _orthodromic()
    runs = [tr.trajectory(model, tr.great_circle_profile(0.8, 0.5, np.radians(angle), 250.0),
                          60.0, 10.0) for angle in (0.0, 360.0, -360.0)]
    for run in runs[1:]:
        assert np.allclose(run.truth, runs[0].truth, rtol=0, atol=1e-9)
    assert tr.static_profile(0.8, 0.0, -2 * np.pi).heading == -2 * np.pi


def test_only_the_settings_a_kind_uses_are_written_in_si():
    """Sweep and validity tasks carry a motion as :func:`in_si` writes it: a static base's
    is read back without the speed it does not use (which is refused)."""
    from ins_errors.numeric.motion_spec import in_si, motion_profile

    static = in_si({"kind": "static"})
    assert "speed" not in static and motion_profile(static).static
    assert "speed" in in_si({"kind": "great-circle"})


def test_a_heading_is_meaningful_for_a_motion_file(scratch):
    """A motion file's heading is the trihedron's start track angle, which the orthodromic
    model's errors depend on: it is not refused as the speed is."""
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.motion_spec import motion_profile

    Path("m.csv").write_text("t,v_N,v_E\n0,100,50\n300,100,50\n600,100,50\n900,100,50\n",
                             encoding="utf-8")
    model = _orthodromic()
    chi = model.index("outputs", "heading") if any(
        o.name == "heading" for o in model.outputs) else None
    runs = [tr.trajectory(model, motion_profile({"kind": "file", "file": "m.csv",
                                                 "heading": heading}), 600.0, 10.0)
            for heading in ("0 deg", "45 deg")]
    assert not np.allclose(runs[0].start_state, runs[1].start_state)
    if chi is not None:
        outputs = [model.outputs_of(r.start_state, r.start_inputs) for r in runs]
        assert np.degrees(outputs[1][chi] - outputs[0][chi]) == pytest.approx(45.0)


def test_the_small_angle_refusal_comes_before_the_run():
    """A 30° initial tilt is refused by :func:`simulate` itself (no negative time)."""
    from ins_errors.errors import DomainError
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.simulate import SMALL_ANGLE_LIMIT, simulate

    model = _orthodromic()
    static = tr.trajectory(model, tr.static_profile(0.8), 600.0, 10.0)
    with pytest.raises(DomainError, match=r"t = 0 s, the initial errors\): platform angle "
                                          r"alpha_x = 30° exceeds 0\.5 rad"):
        simulate(model, static, {"initial_tilt_x": np.radians(30.0)}, platform="small_angle")
    just_inside = simulate(model, static, {"initial_tilt_x": 0.99 * SMALL_ANGLE_LIMIT},
                           platform="small_angle")
    assert just_inside.real is not None
