"""Speed of the error-budget machinery (printed by ``make bench``, never asserted).

Goals (issue 7): 24 h of static-base covariance at 1 s output in <= 0.1 s; a Monte Carlo
of 1000 one-hour direct runs at 100 Hz in <= 60 s on a 2-core machine.

Run alone with ``python -m benchmarks.bench_budget [--quick]``.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

GOAL_COVARIANCE_24H = 0.1
GOAL_MONTE_CARLO = 60.0


def _cpu() -> float:
    """CPU seconds of this process and its finished children (worker processes)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _best(function, repeats: int = 5) -> tuple[float, float]:
    """Best wall time of ``repeats`` calls, and the CPU time of that call."""
    best = (np.inf, np.inf)
    for _ in range(repeats):
        start, cpu = time.perf_counter(), _cpu()
        function()
        best = min(best, (time.perf_counter() - start, _cpu() - cpu))
    return best


def _line(label: str, seconds: tuple[float, float], goal: float | None = None) -> None:
    wall, cpu = seconds
    extra = f"  goal {goal:g} s, ratio {wall / goal:.2f}" if goal else ""
    print(f"  {label:<58} {wall:8.3f} s wall {cpu:8.3f} s CPU{extra}")


def bench_covariance() -> None:
    from ins_errors.analysis import covariance as cv
    from ins_errors.numeric.model import load_model

    model = load_model("orthodromic")
    system = cv.static_system(model, np.radians(50.0), duration=86400.0, step=1.0)
    sources = [cv.SourceStatistics(s.name, "constant", 1e-6) for s in model.sources]
    everything = cv.state_and_output_functionals(model, system)
    outputs = cv.Functionals(everything.names[11:], everything.units[11:],
                             everything.C_x[11:], everything.C_b[11:])
    print("covariance, static base, 24 h at 1 s output (86 401 times), 26 random constants:")
    _line("5 navigation outputs + 2 rates (total variance)",
          _best(lambda: cv.propagate(system, sources, outputs, by_source=False)),
          GOAL_COVARIANCE_24H)
    _line("11 error states + 7 outputs (total variance)",
          _best(lambda: cv.propagate(system, sources, everything, by_source=False)),
          GOAL_COVARIANCE_24H)
    _line("7 outputs, per source (86 401 x 7 x 26 array)",
          _best(lambda: cv.propagate(system, sources, outputs), repeats=2))
    noisy = [*sources[:-2], cv.SourceStatistics(sources[-2].name, "white", 1e-6),
             cv.SourceStatistics(sources[-1].name, "markov", 1e-6, 3600.0)]
    _line("7 outputs, total, with one white and one Markov source",
          _best(lambda: cv.propagate(system, noisy, outputs, by_source=False)))


def bench_budget() -> None:
    from ins_errors.analysis import budget as bd
    from ins_errors.numeric.model import load_model
    from ins_errors.specs import default_spec_path, load_spec

    model = load_model("orthodromic")
    spec = load_spec(default_spec_path())
    print("budget against the built-in 802m spec (8 h, 60 s grid, 26 sources):")
    _line("unit budget + allocation", _best(lambda: bd.allocate(bd.unit_budget(model, spec)),
                                            repeats=3))


def bench_monte_carlo(runs: int = 1000) -> None:
    from ins_errors.analysis import covariance as cv
    from ins_errors.analysis.monte_carlo import direct_monte_carlo
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.model import load_model

    model = load_model("orthodromic")
    motion = tr.trajectory(model, tr.static_profile(np.radians(50.0)), 3600.0, 0.01)
    sources = [cv.SourceStatistics("gyro_drift_x", "constant", 0.01 * np.pi / 180 / 3600),
               cv.SourceStatistics("accel_bias_y", "constant", 1e-4),
               cv.SourceStatistics("initial_azimuth_error", "constant", 5e-4)]
    direct_monte_carlo(model, motion, sources, 2, batch=50, workers=1, progress=False)
    seconds = _best(lambda: direct_monte_carlo(model, motion, sources, runs, batch=50,
                                               progress=False), repeats=1)
    print(f"direct Monte Carlo, static base, 1 h at 100 Hz (Euler), {runs} runs:")
    _line(f"{runs} runs, batches of 50, all CPUs", seconds,
          GOAL_MONTE_CARLO * runs / 1000)


def main(quick: bool = False) -> None:
    """Run every budget benchmark (``quick``: 100 Monte Carlo runs instead of 1000)."""
    print(f"  (load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs: other work "
          "slows these figures)")
    bench_covariance()
    bench_budget()
    bench_monte_carlo(100 if quick else 1000)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
