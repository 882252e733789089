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


def test_cli_json_and_plot(capsys, tmp_path):
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


def test_a_sweep_that_leaves_the_domain_names_its_source(orthodromic):
    """An accelerometer bias 10⁹ times its typical size (4.9e5 m/s²) makes the direct run
    leave the model's domain: the map stops with one line naming that source's sweep (the
    first one run, in this process), not a bare domain error of an unnamed run."""
    from ins_errors.analysis.validity import validity_map, validity_tasks
    from ins_errors.errors import DomainError

    tasks = validity_tasks(orthodromic, ["static"], ["accel_bias_y", "gyro_drift_x"],
                           hours=0.2, step=10.0, factors=(1.0, 1e9))
    with pytest.raises(DomainError) as raised:
        validity_map(tasks, engine="serial")
    message = str(raised.value)
    assert message.startswith("validity of accel_bias_y on the static motion (")
    assert "the system left its domain" in message and "\n" not in message
