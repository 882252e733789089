"""A sweep over static latitudes: its compiles, with and without run-time constants.

Printed by ``make bench``, never asserted. A static strapdown_ned base at 12 latitudes
(``--quick``: 4), 90 min at 1 s, RK4 with direct, linear and refined runs, one
accelerometer bias and one gyro bias, ``--engine serial``: each point's loops (three:
the runs and the integration-error reruns at 2τ and 4τ) once baked, with the point's
numbers compiled in (a library per latitude), once with the numbers read at run time
(:func:`ins_errors.numeric.simulate.runtime_constant_loops`, which the sweep takes when
its points would need several baked libraries: one per structure). Each runs in its own
process with an empty compile cache (``INS_ERRORS_CACHE``), then again with the cache
filled; CPU seconds include the compiler's. Issue 16 counted 3.5 s of compiling per
latitude against 0.04 s to run a point.

Run alone with ``python -m benchmarks.bench_sweep_compiles [--quick]``.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SCENARIO = """
title = "bench: static latitudes"
model = "strapdown_ned"
[motion]
kind = "static"
[run]
duration = "90 min"
step = "1 s"
record = "60 s"
[[case]]
accel_bias_x = "100 ug"
gyro_bias_y = "0.01 deg/h"
[sweep]
latitude = {{ start = "5 deg", stop = "80 deg", count = {count} }}
"""


def _cpu() -> float:
    return sum(u.ru_utime + u.ru_stime for u in (resource.getrusage(resource.RUSAGE_SELF),
                                                 resource.getrusage(resource.RUSAGE_CHILDREN)))


def _child(mode: str, scenario: str, store: str) -> None:
    """Run the sweep in this process and print its CPU and wall seconds as JSON."""
    from ins_errors.analysis import sweep
    from ins_errors.scenario import load_scenario

    if mode == "baked":   # as if the points shared one set of numbers
        sweep.loop_combinations = lambda jobs: 1
    loaded = load_scenario(scenario)
    wall, cpu = time.perf_counter(), _cpu()
    sweep.run_sweep(loaded, store, engine="serial")
    print(json.dumps({"cpu": _cpu() - cpu, "wall": time.perf_counter() - wall}))


def _run(mode: str, scenario: Path, store: Path, cache: Path) -> dict:
    env = dict(os.environ, INS_ERRORS_CACHE=str(cache))
    out = subprocess.run([sys.executable, "-m", "benchmarks.bench_sweep_compiles", "--child",
                          mode, str(scenario), str(store)], env=env, check=True,
                         capture_output=True, text=True,
                         cwd=Path(__file__).resolve().parent.parent)
    result = json.loads(out.stdout.strip().splitlines()[-1])
    result["libraries"] = len(list(cache.glob("loop_*.so")))
    return result


def main(quick: bool = False) -> None:
    count = 4 if quick else 12
    with tempfile.TemporaryDirectory(prefix="ins-errors-bench-") as scratch:
        folder = Path(scratch)
        scenario = folder / "latitudes.toml"
        scenario.write_text(SCENARIO.format(count=count))
        print(f"static strapdown_ned sweep, {count} latitudes x 90 min at 1 s (RK4, direct + "
              f"linear + refined), --engine serial; {os.cpu_count()} cores, load average "
              f"{os.getloadavg()[0]:.1f}")
        for mode, label in (("baked", "numbers compiled in"),
                            ("shared", "run-time constants")):
            cache = folder / f"cache-{mode}"
            cold = _run(mode, scenario, folder / f"{mode}-cold.zarr", cache)
            warm = _run(mode, scenario, folder / f"{mode}-warm.zarr", cache)
            print(f"  {label:<22} empty cache {cold['cpu']:6.1f} s CPU ({cold['wall']:5.1f} s "
                  f"wall), {cold['libraries']:3d} libraries; cached {warm['cpu']:5.1f} s CPU "
                  f"({warm['cpu'] / count:.2f} s a point)")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        _child(*sys.argv[2:5])
    else:
        main(quick="--quick" in sys.argv)
