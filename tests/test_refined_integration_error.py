"""Integration error of the refined (second-order) run, estimated by step doubling.

A refined-vs-direct residual at a coarse step may be the model's error or the
integration error of the runs it compares; ``compare`` estimates the refined curve's
integration error in the same rerun that estimates the direct and linear ones. The
estimate is checked against the refined run's actual error, measured against a refined
run at a step 32 times smaller (an own run, not the estimate's machinery), and the
direct and linear estimates are checked to be the same bits with and without the
refined run.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import ins_errors
from ins_errors.cli import main
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import compare, markdown_table, residual
from ins_errors.numeric.simulate import simulate

DEG = np.pi / 180
CASE = {"initial_azimuth_error": 3 * DEG}  # far enough from zero for a refined residual


@pytest.fixture(scope="module")
def north_pointing():
    return ins_errors.load_model("north_pointing")


def _trajectory(model, tau: float):
    return tr.trajectory(model, tr.static_profile(50 * DEG, 30 * DEG), 3600.0, tau)


@pytest.mark.parametrize(("method", "tau"), [("rk4", 30.0), ("euler", 1.0)])
def test_refined_estimate_is_the_refined_runs_actual_error(north_pointing, method, tau):
    (c,) = compare(north_pointing, _trajectory(north_pointing, tau), [CASE], method=method,
                   record_interval=60.0, validity_threshold=None, warn=False)
    fine = simulate(north_pointing, _trajectory(north_pointing, tau / 32), [CASE],
                    method=method, record_interval=60.0, parts=("real", "refined"))
    truth = fine.refined_errors()
    checked = 0
    for k, name in enumerate(truth.names):
        m = c.metric(name)
        actual = float(np.max(np.abs(residual(c.refined[name], truth.values[k, :, 0],
                                              m.unit))))
        if not m.excited:
            continue
        assert actual > 1e3 * np.finfo(float).eps * m.max_direct  # above rounding
        assert m.refined_integration_error == pytest.approx(actual, rel=0.3), name
        checked += 1
    assert checked == len(truth.names)
    # the table shows it beside the linear one
    row = next(line for line in markdown_table(c).splitlines() if "`alpha_E`" in line)
    header = next(line for line in markdown_table(c).splitlines() if "| refined |" in line)
    assert header.split("|").index(" refined ") == header.split("|").index(" linear ") + 1
    assert row.split("|")[header.split("|").index(" refined ")].strip() != "–"


def test_refined_residual_below_its_integration_error_is_warned(north_pointing):
    """The rectangle method at 1 s: the refined-vs-direct difference of alpha_N (1.7e-7
    rad) is smaller than the refined curve's own integration error (about 1.1e-6 rad,
    as measured above): the warning says so, as it does for the linear pair."""
    (c,) = compare(north_pointing, _trajectory(north_pointing, 1.0), [CASE], method="euler",
                   record_interval=60.0, validity_threshold=None, warn=False)
    m = c.metric("alpha_N")
    assert m.refined_integration_error > m.refined_difference
    (text,) = [w for w in c.warnings if w.startswith("integration error too large")]
    note = text[text.index("The refined run's integration error is over its limit too"):]
    assert "a tenth of its refined-vs-direct difference" in note
    # the step it names brings the refined pair's estimate under its limit (order 1)
    need = max(x.refined_runs_integration_error / (0.1 * x.refined_difference)
               for x in c.excited)
    step = float(re.search(r"about τ ≤ (\S+) s would bring it under", note)[1])
    assert step <= 1.0 / need
    # the linear pair's warning and its step are as without the refined run
    (without,) = compare(north_pointing, _trajectory(north_pointing, 1.0), [CASE],
                         method="euler", record_interval=60.0, refined=False,
                         validity_threshold=None, warn=False)
    assert c.suggested_step == without.suggested_step
    assert text.startswith(without.warnings[0])


@pytest.mark.parametrize(("method", "tau", "record"),
                         [("rk4", 30.0, 60.0),    # runs at 2τ and 4τ
                          ("rk4", 30.0, 30.0),    # odd stride: τ/2 and 2τ
                          ("euler", 1.0, 60.0)])
def test_direct_and_linear_estimates_are_unchanged(north_pointing, method, tau, record):
    traj = _trajectory(north_pointing, tau)
    runs = {refined: compare(north_pointing, traj, [CASE], method=method,
                             record_interval=record, refined=refined,
                             validity_threshold=None, warn=False)[0]
            for refined in (True, False)}
    with_refined, without = runs[True], runs[False]
    assert with_refined.integration_steps == without.integration_steps
    assert with_refined.integration_order == without.integration_order
    assert with_refined.worst_integration_ratio == without.worst_integration_ratio
    for m, other in zip(with_refined.metrics, without.metrics, strict=True):
        assert (m.direct_integration_error, m.linear_integration_error) == (
            other.direct_integration_error, other.linear_integration_error)
        assert other.refined_integration_error is None
        assert m.refined_integration_error is not None


def test_json_has_the_refined_estimate(capsys):
    status = main(["compare", "north_pointing", "--source", "initial_azimuth_error=3deg",
                   "--step", "30s", "--hours", "1", "--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    (case,) = json.loads(out)["cases"]
    metric = next(m for m in case["metrics"] if m["quantity"] == "alpha_E")
    assert metric["refined_integration_error"] > 0
    status = main(["compare", "north_pointing", "--source", "initial_azimuth_error=3deg",
                   "--step", "30s", "--hours", "1", "--json", "--no-refined"])
    out, err = capsys.readouterr()
    assert status == 0, err
    (case,) = json.loads(out)["cases"]
    assert all(m["refined_integration_error"] is None for m in case["metrics"])


def test_a_refined_rerun_that_fails_leaves_the_other_estimates(north_pointing, monkeypatch):
    """A refined part that fails at the other step (it left its domain there): that rerun
    is made again without it; no refined estimate, the direct and linear ones as without
    a refined run."""
    import ins_errors.numeric.compare as compare_module
    from ins_errors.errors import DomainError

    traj = _trajectory(north_pointing, 30.0)
    (without,) = compare(north_pointing, traj, [CASE], record_interval=60.0, refined=False,
                         validity_threshold=None, warn=False)
    real = compare_module.simulate

    def failing(model, trajectory, *args, parts=("real", "linear", "refined"), **kwargs):
        if "refined" in parts and trajectory.tau != traj.tau:
            raise DomainError("the system left its domain (refined error state)")
        return real(model, trajectory, *args, parts=parts, **kwargs)

    monkeypatch.setattr(compare_module, "simulate", failing)
    (c,) = compare(north_pointing, traj, [CASE], record_interval=60.0,
                   validity_threshold=None, warn=False)
    assert c.integration_steps == without.integration_steps == (60.0, 120.0)
    assert c.integration_order == without.integration_order
    for m, other in zip(c.metrics, without.metrics, strict=True):
        assert m.refined_integration_error is None
        assert (m.direct_integration_error, m.linear_integration_error) == (
            other.direct_integration_error, other.linear_integration_error)
    assert not any("not estimated" in w for w in c.warnings)


def test_the_report_says_the_refined_curves_are_estimated_too(tmp_path):
    """run's report.md: the sentence on the estimate names the curves it covers."""
    from ins_errors.cli import main

    scenario = tmp_path / "s.toml"
    scenario.write_text('title = "t"\nmodel = "north_pointing"\n[motion]\nkind = "static"\n'
                        'latitude = "45 deg"\n[run]\nduration = "1 h"\nstep = "30 s"\n'
                        'record = "60 s"\n[[case]]\ninitial_azimuth_error = "3 deg"\n')
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 0
    text = (tmp_path / "out" / "report.md").read_text()
    assert "The integration error of the direct, linear and refined curves is estimated" in text
