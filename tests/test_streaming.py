"""A moving truth streamed in chunks gives exactly the stored truth, and a run fed by it
exactly the run fed by the stored arrays, while its memory stays bounded.

The stored trajectory is the previous code path (the whole grid integrated at once); the
streamed one is cut into awkward chunk sizes so every boundary case is crossed.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from ins_errors.numeric import simulate as simulate_module
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate
from tests.helpers import assert_chunks_join_into

DEG = np.pi / 180.0
LEGS = [tr.Leg(100.0, 280.0, 60 * DEG, 2500.0), tr.Leg(150.0, 200.0, -90 * DEG, 500.0)]
CASES = [{"gyro_drift_x": 1e-6, "accel_bias_y": 1e-4}, {"initial_azimuth_error": 1e-3}]


@pytest.fixture(scope="module")
def motions(orthodromic):
    profile = tr.manoeuvre_profile(55 * DEG, 37 * DEG, 30 * DEG, 200.0, LEGS, h=500.0)
    stored = tr.trajectory(orthodromic, profile, 300.0, 0.25, stream=False)
    streamed = tr.trajectory(orthodromic, profile, 300.0, 0.25, stream=True)
    return stored, streamed


def test_chunks_join_into_the_stored_truth(motions):
    stored, streamed = motions
    assert not stored.is_streamed and streamed.is_streamed
    assert_chunks_join_into(streamed, stored, (7, 250, 5000))


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_runs_fed_in_chunks_equal_runs_fed_the_stored_arrays(orthodromic, motions, method,
                                                             monkeypatch):
    stored, streamed = motions
    whole = simulate(orthodromic, stored, CASES, method=method, record_interval=2.5)
    monkeypatch.setattr(simulate_module, "STREAM_STEPS", 50)  # pieces of 40 steps
    pieces = simulate(orthodromic, streamed, CASES, method=method, record_interval=2.5)
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(getattr(pieces, part), getattr(whole, part)), part
    assert np.array_equal(pieces.recorded_inputs, stored.inputs[:, ::10])
    direct_whole, direct_pieces = whole.direct_errors(), pieces.direct_errors()
    assert np.array_equal(direct_pieces.values, direct_whole.values)
    assert np.abs(direct_whole["delta_latitude"]).max() > 1e-9  # errors really grew


class ArraySource:
    """A user's own truth generator: here, chunks cut from stored arrays."""

    def __init__(self, trajectory):
        self.trajectory = trajectory

    def chunks(self, size):
        t = self.trajectory
        for start in range(0, t.n_steps, size):
            stop = min(start + size, t.n_steps)
            yield tr.TruthChunk(start, t.truth[:, start:stop + 1], t.inputs[:, start:stop + 1],
                                t.midpoints[:, start:stop])


def test_a_user_motion_source_feeds_the_runs(orthodromic, motions):
    stored, _ = motions
    source = ArraySource(stored)
    assert isinstance(source, tr.MotionSource)
    own = tr.Trajectory.streamed(orthodromic.name, stored.tau, stored.n_steps, source,
                                 stored.truth[:, 0], stored.inputs[:, 0], stored.parameters,
                                 stored.initial_conditions, "my motion")
    a = simulate(orthodromic, own, CASES, record_interval=5.0, method="euler")
    b = simulate(orthodromic, stored, CASES, record_interval=5.0, method="euler")
    assert np.array_equal(a.real, b.real) and np.array_equal(a.linear, b.linear)


def test_a_long_streamed_run_keeps_memory_bounded(orthodromic):
    """6 h at 10 Hz: storing the truth would take about 130 MB (74 numbers a step)."""
    profile = tr.great_circle_profile(50 * DEG, 30 * DEG, 40 * DEG, 250.0, 5000.0)
    tracemalloc.start()
    try:
        traj = tr.trajectory(orthodromic, profile, 6 * 3600.0, 0.1)
        sim = simulate(orthodromic, traj, {"gyro_drift_x": 1e-7}, record_interval=60.0,
                       parts=("real", "linear"), method="euler")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert traj.is_streamed and sim.ideal.shape == (8, 361, 1)
    assert peak < 40e6, f"peak {peak / 1e6:.0f} MB"


def test_error_equations_along_a_streamed_motion_equal_the_stored_ones(orthodromic, motions):
    from ins_errors.numeric.linear_system import system_from_trajectory

    stored, streamed = motions
    a = system_from_trajectory(orthodromic, stored, 2.5)
    b = system_from_trajectory(orthodromic, streamed, 2.5)
    assert streamed.is_streamed  # not stored on the way
    for name in ("F", "G", "H", "E", "x", "u"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
