"""Sweep throughput on Dask, in trajectory-steps per second (printed, never asserted).

A sweep of great-circle flights (latitude x heading, an accelerometer bias, direct +
linear + refined runs, RK4) runs on a local Dask cluster of 1 and then 2 single-threaded
workers (127.0.0.1), and in this process for reference. A trajectory-step is one step of
one grid point's run (its ideal, real, linear and refined systems together); throughput
is the sum of every point's steps over the wall time of the sweep, measured after the
workers have loaded the compiled loop (cluster start-up is printed separately).

Issue 17 sizes the target: 10⁵ day-long runs at 100 Hz are about 10¹³ trajectory-steps.

Run alone with ``python -m benchmarks.bench_sweep [--quick]``.
"""

from __future__ import annotations

import logging
import os
import sys
import tempfile
import textwrap
import time
from pathlib import Path

SCENARIO = """
title = "bench: great-circle flights"
model = "orthodromic"
[motion]
kind = "great-circle"
speed = "250 m/s"
[run]
duration = "{duration}"
step = "0.1 s"
record = "60 s"
method = "rk4"
[[case]]
accel_bias_x = "100 ug"
[sweep]
latitude = {{ start = "10 deg", stop = "60 deg", count = {latitudes} }}
heading = ["0 deg", "45 deg", "90 deg", "135 deg"]
"""


def _scenario(folder: Path, duration: str, latitudes: int):
    from ins_errors.scenario import load_scenario

    path = folder / f"bench_{latitudes}_{duration.replace(' ', '')}.toml"
    path.write_text(textwrap.dedent(SCENARIO.format(duration=duration, latitudes=latitudes)))
    return load_scenario(path)


def _steps(scenario) -> int:
    from ins_errors.analysis.sweep import grid

    return sum(round(j.duration / j.step) for j in grid(scenario).jobs)


def _timed(scenario, store: Path, **engine) -> float:
    from ins_errors.analysis.sweep import run_sweep

    start = time.perf_counter()
    run_sweep(scenario, store, **engine)
    return time.perf_counter() - start


def main(quick: bool = False) -> None:
    from ins_errors.analysis.engine import dask_available

    duration, latitudes = ("10 min", 2) if quick else ("30 min", 4)
    with tempfile.TemporaryDirectory(prefix="ins-errors-bench-") as scratch:
        folder = Path(scratch)
        scenario = _scenario(folder, duration, latitudes)
        warm = _scenario(folder, "1 min", 2)   # same compiled loop, tiny runs
        steps = _steps(scenario)
        points = len(scenario.sweep.parameters[0].values) * 4
        print(f"sweep of {points} great-circle points, {duration} at 0.1 s (RK4, direct + "
              f"linear + refined): {steps:,} trajectory-steps; {os.cpu_count()} cores, "
              f"load average {os.getloadavg()[0]:.1f} (workers share the cores with it)")
        _timed(warm, folder / "warm-serial.zarr", engine="serial")
        seconds = _timed(scenario, folder / "serial.zarr", engine="serial")
        print(f"  {'this process (serial)':<34} {seconds:8.2f} s  "
              f"{steps / seconds:12,.0f} trajectory-steps/s")
        if not dask_available():
            print("  Dask not installed: pip install 'ins-errors[distributed]'")
            return
        from distributed import LocalCluster

        for workers in (1, 2):
            start = time.perf_counter()
            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                              host="127.0.0.1", dashboard_address="127.0.0.1:0",
                              silence_logs=logging.ERROR) as cluster:
                started = time.perf_counter() - start
                address = cluster.scheduler_address
                _timed(warm, folder / f"warm-{workers}.zarr", scheduler=address)
                seconds = _timed(scenario, folder / f"dask-{workers}.zarr",
                                 scheduler=address)
            label = f"Dask, {workers} worker{'s' if workers > 1 else ''}"
            print(f"  {label:<34} {seconds:8.2f} s  {steps / seconds:12,.0f} "
                  f"trajectory-steps/s  (cluster start {started:.1f} s)")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
