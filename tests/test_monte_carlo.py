"""Monte Carlo runs: stated sampling error, reproducibility, direct runs vs the budget."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from ins_errors.analysis import budget as bd
from ins_errors.analysis import covariance as cv
from ins_errors.analysis import monte_carlo as mc
from ins_errors.errors import InsErrorsError
from ins_errors.numeric import trajectories as tr
from ins_errors.specs import load_spec

PHI = np.radians(50.0)


def test_stated_sampling_error_matches_the_spread_of_sample_rms(orthodromic):
    """The RMS of N draws scatters by 1/sqrt(2N) around σ (checked over 400 batches)."""
    system = cv.static_system(orthodromic, PHI, duration=20.0, step=10.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    sources = [cv.SourceStatistics("initial_tilt_x", "constant", 2e-4)]
    runs, batches = 50, 400
    result = mc.linear_monte_carlo(system, sources, fn, runs * batches, seed=3)
    tilt = result.samples[0, result.names.index("alpha_x")].reshape(batches, runs)
    ratios = np.sqrt(np.mean(tilt**2, axis=1)) / 2e-4
    # the spread itself is estimated from 400 values: ±3.5 % (1σ)
    assert np.std(ratios) == pytest.approx(mc.sampling_error(runs), rel=0.15)
    assert np.mean(ratios) == pytest.approx(1.0, abs=4 * mc.sampling_error(runs * batches))


def test_direct_runs_do_not_depend_on_batching_or_workers(orthodromic):
    """Draws are seeded one by one: other task sizes on a process pool give the same
    samples (Dask against one process: tests/test_distributed.py)."""
    motion = tr.trajectory(orthodromic, tr.static_profile(PHI), 600.0, 1.0)
    sources = [cv.SourceStatistics("gyro_drift_y", "constant", 1e-7),
               cv.SourceStatistics("accel_bias_x", "constant", 1e-4)]
    one = mc.direct_monte_carlo(orthodromic, motion, sources, 12, seed=4, batch=5,
                                workers=1, record_interval=60.0, progress=False)
    two = mc.direct_monte_carlo(orthodromic, motion, sources, 12, seed=4, batch=6,
                                workers=2, engine="pool", record_interval=60.0, progress=False)
    assert np.array_equal(one.sources, two.sources)
    assert one.names == two.names
    assert np.allclose(one.values, two.values, rtol=1e-12, atol=1e-300)
    assert np.any(one.values != 0)


def test_direct_runs_reproduce_the_allocated_budget(orthodromic, tmp_path):
    """Sample 2σ of direct runs at the allocated magnitudes vs the covariance's 2σ."""
    path = tmp_path / "spec.toml"
    path.write_text(textwrap.dedent("""
        sigma_level = 2
        operating_time = "1 h"
        step = "60 s"
        [motion]
        latitude = "50 deg"
        [items.position_error]
        value = "3.7 km/h"
        [items.ground_speed_error]
        value = "4 m/s"
        [items.vertical_error]
        value = "0.1 deg"
        [items.heading_drift]
        value = "0.1 deg/h"
    """))
    spec = load_spec(path)
    allocation = bd.allocate(bd.unit_budget(orthodromic, spec))
    budget = allocation.budget
    sigma = {s.name: float(v) for s, v in zip(budget.sources, allocation.sigma, strict=True)
             if np.isfinite(v)}
    statistics = [cv.SourceStatistics(name, "constant", value) for name, value in sigma.items()]
    motion = bd.spec_trajectory(orthodromic, spec, tau=1.0)
    runs = 400
    errors = mc.direct_monte_carlo(orthodromic, motion, statistics, runs, seed=9,
                                   method="rk4", record_interval=60.0, workers=1,
                                   progress=False)
    rows, sample = bd.direct_rows(orthodromic, budget, errors)
    predicted = bd.evaluate(orthodromic, spec, sigma)
    lookup = {r.label: v for r, v in zip(predicted.rows, predicted.values, strict=True)}
    assert len(rows) == len(budget.rows)
    ratios = np.array([v / lookup[r.label] for r, v in zip(rows, sample, strict=True)])
    assert np.max(np.abs(ratios - 1)) < 4 * mc.sampling_error(runs)
    # the binding item (position after 1 h) is met in the sample within sampling error
    position = [v / r.limit for r, v in zip(rows, sample, strict=True)
                if r.item == "position_error"]
    assert position[0] < 1 + 4 * mc.sampling_error(runs)


def test_bad_monte_carlo_requests(orthodromic):
    motion = tr.trajectory(orthodromic, tr.static_profile(PHI), 60.0, 1.0)
    noise = [cv.SourceStatistics("gyro_drift_x", "white", 1e-6)]
    with pytest.raises(InsErrorsError, match="random constants only") as info:
        mc.direct_monte_carlo(orthodromic, motion, noise, 10, progress=False)
    assert "\n" not in str(info.value)
    with pytest.raises(InsErrorsError, match="runs must be an integer >= 2"):
        mc.direct_monte_carlo(orthodromic, motion, [], 1, progress=False)
    system = cv.static_system(orthodromic, PHI, duration=60.0, step=10.0)
    with pytest.raises(InsErrorsError, match="runs must be"):
        mc.linear_monte_carlo(system, [], cv.state_and_output_functionals(orthodromic, system),
                              0)


def test_cli_monte_carlo(tmp_path, capsys):
    import json

    from ins_errors.cli import main

    # 1300 runs (0.2 s more than 40 in one process): the sampling error of a σ is
    # 1/√(2N) = 1.96 %, so a 10 % bound holds at 5σ (measured: 2.4 % at most)
    assert main(["budget", "orthodromic", "--json", "--monte-carlo", "1300", "--mc-step",
                 "5 s", "--mc-duration", "1 h", "--seed", "2", "--workers", "1"]) == 0
    data = json.loads(capsys.readouterr().out)["monte_carlo"]
    assert data["runs"] == 1300
    assert data["relative_sampling_error"] == pytest.approx(1 / np.sqrt(2 * 1300), rel=1e-9)
    ratios = np.array([r["ratio"] for r in data["rows"]])
    # rows within the first hour: position at 1 h, ground speed and vertical every 5 min
    # from 0 (13 each), heading drift at 1 h
    assert len(ratios) == 1 + 13 + 13 + 1
    assert np.all(np.abs(ratios - 1) < 5 * data["relative_sampling_error"])
    assert main(["budget", "orthodromic", "--monte-carlo", "1"]) == 2
    assert "at least 2 runs" in capsys.readouterr().err


@pytest.mark.parametrize("engine", ["serial", "pool"])
def test_a_draw_that_fails_is_named_and_stops_the_statistics(orthodromic, engine):
    """A gyro drift of 1σ = 0.9 rad/s: one of the 12 draws (seed 0) is large enough for
    the real-work run to leave its domain within 10 min. The Monte Carlo run stops with
    one line naming that draw (found here by running each draw alone), from a batch of
    five other draws on the engine: no statistics without it."""
    from ins_errors.numeric.simulate import simulate

    motion = tr.trajectory(orthodromic, tr.static_profile(PHI), 600.0, 1.0)
    sources = [cv.SourceStatistics("gyro_drift_x", "constant", 0.9)]
    names = [s.name for s in orthodromic.sources]
    w = mc.sample_draws(sources, names, 0, range(12))
    failing = []
    for k in range(12):
        try:
            simulate(orthodromic, motion, w[:, k:k + 1], method="euler",
                     record_interval=60.0, parts=("real",)).direct_errors()
        except InsErrorsError:
            failing.append(k)
    assert len(failing) == 1 and failing[0] >= 5   # not in the first batch of 5
    with pytest.raises(mc.MonteCarloError) as raised:
        mc.direct_monte_carlo(orthodromic, motion, sources, 12, seed=0, batch=5,
                              engine=engine, workers=2, record_interval=60.0,
                              progress=False)
    message = str(raised.value)
    assert message.startswith(f"Monte Carlo draw {failing[0]} (seed 0) failed: the system "
                              "left its domain")
    assert "\n" not in message
