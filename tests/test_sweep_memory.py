"""A process that runs sweep points one after another (a serial sweep, a pool worker)
keeps no trajectory or curves of past points beyond the trajectory cache's few entries.

A moving truth longer than the streaming threshold must stay streamed (a run that stored
it whole kept 74 numbers a step per cached trajectory), and nothing of a point may sit in
a reference cycle (freed only by the next full collection, which a process with many
long-lived objects runs rarely): the cyclic collector is off during the measurement.
Measured with tracemalloc, which numpy reports its buffers to.
"""

from __future__ import annotations

import gc
import textwrap
import tracemalloc

import pytest

from ins_errors.analysis import sweep as sw
from ins_errors.scenario import load_scenario

SCENARIO = """
title = "memory across points"
model = "orthodromic"
[motion]
kind = "great-circle"
latitude = "50 deg"
longitude = "30 deg"
heading = "0 deg"
speed = "250 m/s"
[run]
duration = "{minutes} min"
step = "0.05 s"
record = "60 s"
[[case]]
accel_bias_x = "100 ug"
[sweep]
heading = {{ start = "20 deg", stop = "120 deg", count = 6 }}
"""

CACHED = 4
"""Trajectories the sweep keeps for the next points (sweep._trajectory's cache)."""


STREAM_BYTES = 16_000_000
"""The streaming threshold of these runs: a quarter of the product's, so that runs a
quarter as long (a third of the steps in all) are stored and streamed as the product's
40-min and 2-h runs are (the choice is the same comparison at any threshold)."""


@pytest.mark.parametrize("minutes", [15, 40])
def test_points_run_in_one_process_do_not_accumulate_memory(tmp_path, monkeypatch, minutes):
    """6 points with different headings, each its own trajectory: with the threshold at
    16 MB, 15 min at 0.05 s is stored (18 numbers a step, 2.6 MB), 40 min (74 numbers a
    step while it is built, 28 MB) is streamed. After the cache is full the process holds
    nothing more; in all it holds at most the cached stored truths."""
    from ins_errors.numeric import trajectories

    monkeypatch.setattr(trajectories, "STREAM_BYTES", STREAM_BYTES)
    steps = round(minutes * 60 / 0.05)
    stored = 8 * (13 * (steps + 1) + 5 * steps) if minutes == 15 else 0
    path = tmp_path / "s.toml"
    path.write_text(textwrap.dedent(SCENARIO.format(minutes=minutes)))
    jobs = sw.grid(load_scenario(path)).jobs
    sw._trajectory.cache_clear()
    sw.run_point(jobs[0])  # compiled loops, imports: before the measurement
    sw._trajectory.cache_clear()
    # (no gc.collect() first: with the collector off, garbage made before the measurement
    # stays where it is, and tracemalloc counts only what is allocated after its start;
    # a full collection of the suite's heap costs ~1 s)
    gc.disable()
    tracemalloc.start()
    try:
        held = []
        for job in jobs[1:]:
            out = sw.run_point(job)
            assert out["direct"].shape[0] == minutes + 1
            del out
            held.append(tracemalloc.get_traced_memory()[0])
    finally:
        tracemalloc.stop()
        gc.enable()
        sw._trajectory.cache_clear()
    shown = [round(h / 1e6, 1) for h in held]
    assert held[-1] - held[CACHED - 1] < 1e6, f"held {shown} MB after each point"
    assert held[-1] < CACHED * stored + 2e6, f"held {shown} MB after each point"
