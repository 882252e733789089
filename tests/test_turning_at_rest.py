"""free_azimuth's F turns at rest: its wander angle A takes up the Earth's vertical rate
(Ȧ = −U sin φ, source 002), and F's Earth-rate couplings turn with it. ``modes`` and
``transfer`` read F at the base's start; its long run (``transfer``: "longitude grows as
t, −0.334 arcmin/h" for an x gyro drift) is that of one frozen instant, which the turning
averages away: a run over four turns shows no such growth. They now say F turns, and
``transfer`` gives no long run there."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ins_errors.analysis.modes import static_modes
from ins_errors.analysis.transfer import transfer_functions
from ins_errors.cli import main
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.model import load_model
from ins_errors.numeric.simulate import simulate

PHI, HEADING = np.radians(50.0), np.radians(30.0)
EARTH_RATE = 7.292115e-5   # rad/s, U of the models


def test_the_turning_angle_is_the_wander_angle_at_the_earths_vertical_rate():
    turning = static_modes("free_azimuth", PHI, heading=HEADING).turning
    assert turning is not None and turning.state == "A"
    assert turning.rate == pytest.approx(-EARTH_RATE * np.sin(PHI), rel=1e-9)
    assert turning.period_s / 3600 == pytest.approx(31.24, abs=0.01)


@pytest.mark.parametrize("model", ["orthodromic", "north_pointing", "strapdown_ned",
                                   "geodetic_vertical"])
def test_a_model_whose_state_rests_at_rest_does_not_turn(model):
    assert static_modes(model, PHI).turning is None


def test_the_frozen_long_run_is_not_what_a_long_run_shows():
    free_azimuth = load_model("free_azimuth")
    drift = np.radians(0.01) / 3600.0
    pair = transfer_functions(free_azimuth, ["gyro_drift_x"], ["longitude"], latitude=PHI,
                              heading=HEADING).pair("gyro_drift_x", "longitude")
    frozen = pair.long_run.coefficient * drift          # rad/s: grows as t, frozen
    assert pair.long_run.power == 1 and abs(frozen) > 1e-8
    rest = tr.trajectory(free_azimuth, tr.static_profile(PHI, np.radians(30.0), HEADING),
                         125 * 3600.0, 60.0)                # four turns of A
    run = simulate(free_azimuth, rest, {"gyro_drift_x": drift}, parts=("linear",),
                   record_interval=600.0)
    longitude = run.linear_errors()["delta_longitude"][:, 0]
    slope = np.polyfit(run.times, longitude, 1)[0]
    assert abs(slope) < 0.1 * abs(frozen)


def test_transfer_and_modes_say_so(capsys):
    args = ["-s", "gyro_drift_x=0.01deg/h", "--output", "longitude", "--latitude", "50deg",
            "--heading", "30deg"]
    assert main(["transfer", "free_azimuth", *args]) == 0
    out = capsys.readouterr().out
    (line,) = [x for x in out.splitlines() if x.startswith("long run:")]
    assert line.startswith("long run: not given: its state's angle A turns at rest")
    assert "grows" not in line and "ins-errors compare free_azimuth" in line
    assert main(["transfer", "free_azimuth", *args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["turning_at_rest"]["state"] == "A"
    assert data["pairs"][0]["long_run"]["holds"] is False
    assert main(["transfer", "north_pointing", "-s", "gyro_drift_east", "--output",
                 "latitude", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["turning_at_rest"] is None and data["pairs"][0]["long_run"]["holds"]
    assert main(["modes", "free_azimuth", "--latitude", "50deg"]) == 0
    assert "F changes at rest: its state's angle A turns" in capsys.readouterr().out
