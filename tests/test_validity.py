"""Validity map: slopes of the linear (1) and refined (2) residuals, 1 % magnitudes.

The slopes are what a correct first-order model must give (a second-order residual);
the 1 % magnitude read off the fitted line is checked by an independent direct run at
that magnitude.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from ins_errors import units
from ins_errors.analysis import validity
from ins_errors.analysis.validity import (
    ValidityTask,
    run_validity_task,
    typical_magnitude,
    validity_tasks,
)
from ins_errors.cli import main
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import compare
from ins_errors.numeric.model import load_model
from ins_errors.numeric.motion_spec import motion_profile


@pytest.fixture(scope="module")
def azimuth_sweep(orthodromic):
    (task,) = validity_tasks(orthodromic, ["static"], ["initial_azimuth_error"], hours=4.0,
                             step=10.0)
    return task, run_validity_task(task)


def test_slopes_of_a_clean_first_order_model(azimuth_sweep):
    _, result = azimuth_sweep
    assert result.status == "ok"
    assert result.linear_slope == pytest.approx(1.0, abs=0.1)
    assert result.refined_slope == pytest.approx(2.0, abs=0.2)
    assert result.magnitude_1pct < result.magnitude_10pct


def test_one_percent_magnitude_agrees_with_a_direct_run(orthodromic, azimuth_sweep):
    task, result = azimuth_sweep
    trajectory = tr.trajectory(orthodromic, motion_profile({"kind": "static"}),
                               task.hours * 3600.0, task.step)
    (c,) = compare(orthodromic, trajectory, [{task.source: result.magnitude_1pct}],
                   record_interval=300.0, refined=False, integration_error=False,
                   validity_threshold=None)
    # the fitted line (slope 0.993 over the decades) puts it within 1.2 % (measured)
    assert c.metric(result.quantity).linear_ratio == pytest.approx(0.01, rel=0.05)


def test_a_source_with_no_effect_is_reported_not_excited(orthodromic):
    """An accelerometer scale error sees no specific force horizontally on a static base."""
    m = typical_magnitude(orthodromic, "accel_scale_error_x")
    result = run_validity_task(ValidityTask("orthodromic", "static", "accel_scale_error_x",
                                            (m, 10 * m), hours=1.0, step=10.0))
    assert result.status == "not excited" and result.linear_slope is None


def test_a_task_runs_without_pint_and_gives_the_bits_of_the_motion_kind(orthodromic,
                                                                         monkeypatch):
    """A task carries its motion in exact SI text and its source's typical size (a worker
    needs no pint); the result is that of the motion kind and typical size worked out
    in the worker."""
    (task,) = validity_tasks(orthodromic, ["great-circle"], ["gyro_drift_x"], hours=1.0,
                             step=10.0, factors=(1.0, 10.0, 100.0))
    assert task.typical == typical_magnitude(orthodromic, "gyro_drift_x")
    expected = run_validity_task(dataclasses.replace(task, motion_si=(), typical=None))

    def refuse():
        raise AssertionError("pint was asked for a unit")

    monkeypatch.setattr(units, "registry", refuse)
    assert run_validity_task(task).to_dict() == expected.to_dict()


def test_cli_json_and_plot(capsys, tmp_path, monkeypatch):
    from ins_errors.analysis import validity_plot

    legends = []
    saved = validity_plot.save_figure

    def keep(fig, path, dpi):
        legends.append([t.get_text() for t in fig.axes[0].get_legend().get_texts()])
        return saved(fig, path, dpi)

    monkeypatch.setattr(validity_plot, "save_figure", keep)
    out = tmp_path / "map"
    status = main(["validity", "orthodromic", "--source", "gyro_drift_x", "--motion",
                   "static", "--hours", "4", "--step", "10s", "--json", "--plot", "--out",
                   str(out), "--no-progress"])
    text, err = capsys.readouterr()
    assert status == 0, err
    (row,) = json.loads(text)["sources"]
    assert row["source"] == "gyro_drift_x" and row["motion"] == "static"
    assert row["linear_slope"] == pytest.approx(1.0, abs=0.1)
    assert np.all(np.diff(row["linear_ratio"][:5]) > 0)
    assert (out / "gyro_drift_x.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((out / "results.json").read_text())["model"] == "orthodromic"
    # the triangles at the 1 % and 10 % magnitudes are named in the legend (they were not)
    assert any(label.startswith("static: 1 %, 10 % magnitudes") for label in legends[0])


def test_cli_unknown_source_is_one_line(capsys):
    status = main(["validity", "orthodromic", "--source", "gyro_drift_q", "--no-progress"])
    _, err = capsys.readouterr()
    assert status == 2 and err.count("\n") == 1 and "gyro_drift_q" in err


def test_every_built_in_source_has_a_typical_size():
    """A plain 'ins-errors validity MODEL' sweeps every source of the model, so each
    built-in model's sources must be quoted in a unit with a typical size."""
    for name in ("orthodromic", "north_pointing", "free_azimuth", "geodetic_vertical",
                 "strapdown_ned"):
        model = load_model(name)
        for source in model.sources:
            assert validity.typical_magnitude(model, source.name) > 0, (name, source.name)


def test_validity_of_a_source_without_typical_size_is_one_line(capsys, monkeypatch):
    """A source quoted in a unit without a typical size (here metres, taken out of the
    table as a model file's own unit would be missing) is refused in one line."""
    monkeypatch.setattr(validity, "TYPICAL", {k: v for k, v in validity.TYPICAL.items()
                                              if k != "m"})
    assert main(["validity", "strapdown_ned", "-s", "initial_position_error_D"]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "no typical size for initial_position_error_D, quoted in 'm'" in line


# strapdown_ned's vertical channel is undamped by default: height errors grow ×e every
# 9.5 min, so over 1.5 h an up accelerometer bias of 500 µg (10 × typical) takes the
# direct run out of the model's domain (height errors of thousands of km), while the
# smaller ones run. One sweep of a map fails; the others must not notice.
FAILING = {"sources": ["accel_bias_z", "gyro_bias_x"], "hours": 1.5, "step": 10.0}


@pytest.fixture(scope="module")
def strapdown_ned():
    return load_model("strapdown_ned")


@pytest.fixture(scope="module")
def failing_map(strapdown_ned):
    """The tasks of a map with a failing sweep, and its results in this process."""
    from ins_errors.analysis.validity import validity_map

    tasks = validity_tasks(strapdown_ned, ["static"], FAILING["sources"],
                           hours=FAILING["hours"], step=FAILING["step"])
    return tasks, validity_map(tasks, engine="serial")


@pytest.fixture(scope="module")
def map_without_the_failing_source(strapdown_ned):
    from ins_errors.analysis.validity import validity_map

    tasks = validity_tasks(strapdown_ned, ["static"], FAILING["sources"][1:],
                           hours=FAILING["hours"], step=FAILING["step"])
    return validity_map(tasks, engine="serial")


def test_a_sweep_that_leaves_the_domain_is_a_result_and_keeps_what_ran(strapdown_ned,
                                                                       failing_map):
    """The failing sweep is reported with its one-line reason; the magnitudes below the
    first one that fails keep their results, which are those of a sweep of just these
    magnitudes (bit for bit: each case's arithmetic is the same alone as in a batch),
    and the first one left out really fails alone (a direct run of its own)."""
    from ins_errors.errors import DomainError
    from ins_errors.numeric.compare import compare

    tasks, (bad, _) = failing_map
    assert bad.failed and bad.status != "failed"  # some ran, and were fitted
    assert bad.failure.startswith("the system left its domain") and "\n" not in bad.failure
    assert "k_h1" in bad.failure  # the reason names the undamped vertical channel
    assert bad.magnitudes and bad.failed_at == bad.failed_magnitudes[0]
    assert max(bad.magnitudes) < bad.failed_at
    assert sorted(bad.magnitudes + bad.failed_magnitudes) == sorted(tasks[0].magnitudes)
    alone = run_validity_task(dataclasses.replace(tasks[0], magnitudes=tuple(bad.magnitudes)))
    assert not alone.failed
    failure_fields = {"failure", "failed_magnitudes", "failed_at"}
    assert ({k: v for k, v in bad.to_dict().items() if k not in failure_fields}
            == {k: v for k, v in alone.to_dict().items() if k not in failure_fields})
    trajectory = tr.trajectory(strapdown_ned, motion_profile({"kind": "static"}),
                               FAILING["hours"] * 3600.0, FAILING["step"])
    with pytest.raises(DomainError, match="left its domain"):
        compare(strapdown_ned, trajectory, [{"accel_bias_z": bad.failed_at}],
                record_interval=300.0, integration_error=False, validity_threshold=None)


@pytest.mark.parametrize("engine", ["serial", "pool"])
def test_the_other_sweeps_of_a_map_with_a_failing_one_are_untouched(
        strapdown_ned, failing_map, map_without_the_failing_source, engine):
    """In one process and in a process pool alike, the map runs every sweep: the others
    are bit-identical to a map without the failing source, and the failing one is the
    same wherever it ran."""
    from ins_errors.analysis.validity import failures, validity_map

    tasks, here = failing_map
    results = here if engine == "serial" else validity_map(tasks, engine=engine, workers=2)
    assert [r.source for r in results] == FAILING["sources"]
    assert results[1].to_dict() == map_without_the_failing_source[0].to_dict()
    assert not results[1].failed and results[1].status == "ok"
    assert results[0].to_dict() == here[0].to_dict()
    (row,) = failures(results)
    assert row["source"] == "accel_bias_z" and row["reason"] == here[0].failure


def test_a_sweep_that_fails_from_its_smallest_magnitude_is_failed(orthodromic):
    """An accelerometer bias 10⁹ times its typical size (4.9e5 m/s², 50 000 g) is beyond
    any run's meaning (10 g): the sweep has no magnitude and status "failed"; the other
    sweep of the map runs as it does alone."""
    from ins_errors.analysis.validity import validity_map

    tasks = validity_tasks(orthodromic, ["static"], ["accel_bias_y", "gyro_drift_x"],
                           hours=0.2, step=10.0, factors=(1e9, 3e9))
    bad, good = validity_map(tasks, engine="serial")
    assert bad.status == "failed" and bad.magnitudes == [] and bad.linear_ratio == []
    assert bad.failed_at == min(tasks[0].magnitudes)
    assert bad.failed_magnitudes == sorted(tasks[0].magnitudes)
    assert "accel_bias_y = 490332 m/s**2 is beyond 10 g" in bad.failure, bad.failure
    assert good.to_dict() == run_validity_task(tasks[1]).to_dict()


def test_cli_lists_the_failed_sweep_and_exits_3(capsys, tmp_path, monkeypatch,
                                                failing_map):
    """Like a sweep's failed points: every sweep is in the output (the failed one with
    its reason, in the JSON under "failed"), stderr has one line per failed sweep after a
    header, and the exit status is 3; the plot marks the magnitudes without a result."""
    from ins_errors.analysis import validity_plot

    _, (bad, good) = failing_map
    args = ["validity", "strapdown_ned", "--motion", "static", "--hours", "1.5",
            "--step", "10s", "--engine", "serial", "--no-progress"]
    args += [a for s in FAILING["sources"] for a in ("-s", s)]
    assert main([*args, "--json"]) == 3
    out, err = capsys.readouterr()
    report = json.loads(out)
    assert [r["source"] for r in report["sources"]] == FAILING["sources"]
    assert report["sources"][0]["failure"] == bad.failure
    assert report["sources"][1] == json.loads(json.dumps(good.to_dict()))
    (failed,) = report["failed"]
    assert failed["source"] == "accel_bias_z" and failed["motion"] == "static"
    assert failed["magnitudes_failed"] == bad.failed_magnitudes
    assert failed["failed_at"] == bad.failed_at and failed["reason"] == bad.failure
    header, line = err.strip().splitlines()
    assert header.startswith("ins-errors: 1 of 2 validity sweeps failed")
    assert line.startswith(f"  accel_bias_z on the static motion: {len(bad.magnitudes)} of "
                           f"{len(bad.magnitudes) + len(bad.failed_magnitudes)} magnitudes ran")
    assert line.endswith(bad.failure)

    drawn = []
    original = validity_plot.plot_validity

    def spy(results, path, title=""):
        drawn.append([r.source for r in results])
        return original(results, path, title)

    monkeypatch.setattr(validity_plot, "plot_validity", spy)
    out_dir = tmp_path / "map"
    assert main([*args, "--plot", "--out", str(out_dir)]) == 3
    out, err = capsys.readouterr()
    row = next(r for r in out.splitlines() if r.startswith("| `accel_bias_z`"))
    assert "failed from" in row
    assert f"* `accel_bias_z` (static): {len(bad.magnitudes)} of" in out
    assert bad.failure in out and err.count("\n") == 2
    assert drawn == [["accel_bias_z"], ["gyro_bias_x"]]
    assert (out_dir / "accel_bias_z.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((out_dir / "results.json").read_text())["failed"] == [failed]


def test_plot_of_a_failed_sweep_marks_the_magnitudes_without_result(tmp_path, monkeypatch,
                                                                     failing_map):
    from ins_errors.analysis import validity_plot

    seen = []

    def keep(fig, path, dpi):
        (ax,) = fig.axes
        seen.append(([t.get_text() for t in ax.get_legend().get_texts()],
                     [t.get_text() for t in ax.texts]))
        return path

    monkeypatch.setattr(validity_plot, "save_figure", keep)
    _, (bad, _) = failing_map
    validity_plot.plot_validity([bad], tmp_path / "bad.png")
    nothing = dataclasses.replace(bad, magnitudes=[], linear_ratio=[], refined_ratio=[],
                                  status="failed", quantity=None)
    validity_plot.plot_validity([nothing], tmp_path / "nothing.png")
    (legend, texts), (legend_none, texts_none) = seen
    assert legend[0].startswith("static: failed, from ")
    assert any(bad.failure.split(";")[0][:40] in t for t in texts)
    assert legend_none == ["static: failed, no magnitude ran"]
    assert any("left its domain" in t for t in texts_none)


@pytest.mark.parametrize("step, hours, message", [
    ("-2s", "1", "integration step must be a positive number of seconds, got -2"),
    ("7s", "1", "duration 3600 s is not a whole number of steps of 7 s"),
    ("10s", "-1", "--hours: must be a positive number of hours, got -1"),
])
def test_a_step_no_run_can_use_is_refused_before_any_sweep(capsys, monkeypatch, step,
                                                           hours, message):
    """The user's own bad input is one line, before any work (not one failed sweep per
    task)."""
    from ins_errors.analysis import validity as module

    def refuse(*args, **kwargs):
        raise AssertionError("a sweep ran")

    monkeypatch.setattr(module, "validity_map", refuse)
    try:
        status = main(["validity", "orthodromic", "-s", "gyro_drift_x", "-s",
                       "accel_bias_x", "--motion", "static", f"--step={step}",
                       f"--hours={hours}", "--no-progress"])
    except SystemExit as usage:   # an option's own type refused it (argparse)
        status = usage.code
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and message in err, err


@pytest.mark.parametrize("radius, said", [("-5m", "R = '-5m': the Earth's radius"),
                                           ("50km", "R = '50km': an Earth radius of "
                                                    "50000 m is below 100 km")])
@pytest.mark.parametrize("motion", [["--motion", "great-circle"], []])
def test_an_impossible_earth_radius_names_the_parameter_not_the_motion(capsys, monkeypatch,
                                                                       motion, radius, said):
    """R = -5 m (or 50 km) is wrong for every flight: no advice to map the static base
    instead, and the default set does not quietly drop the flights."""
    from pathlib import Path

    from ins_errors.analysis import validity as module

    def refuse(*args, **kwargs):
        raise AssertionError("a sweep ran")

    monkeypatch.setattr(module, "validity_map", refuse)
    sphere = Path(__file__).resolve().parents[1] / "examples" / "strapdown" / "strapdown_sphere.py"
    status = main(["validity", str(sphere), "-s", "gyro_bias_x", *motion, "-p", f"R={radius}",
                   "--no-progress"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    assert said in err[0] and "static" not in err[0], err[0]
