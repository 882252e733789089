"""Speed of the direct, linear and comparison runs (printed by ``make bench``, never asserted).

Goals (issue 3), on this 2-core machine:

* 24 h direct run at 100 Hz (8.64 M rectangle steps of the ideal + real equations)
  <= 1.0 s, and >= 50x faster than a pure-Python loop over the generated numpy model;
* the linear run over the same 24 h, and the whole 13-factor comparison suite, <= 30 s.

Run alone with ``python -m benchmarks.bench_direct_vs_linear [--quick]``.
"""

from __future__ import annotations

import sys
import time

import numpy as np

DEG = np.pi / 180.0
GOAL_DIRECT = 1.0
GOAL_RATIO = 50.0
GOAL_LINEAR = 30.0
GOAL_SUITE = 30.0


def _timed(function, repeats: int = 3) -> tuple[float, float, object]:
    """Best wall and CPU seconds of ``repeats`` calls, and the last result."""
    best_wall = best_cpu = float("inf")
    result = None
    for _ in range(repeats):
        wall, cpu = time.perf_counter(), time.process_time()
        result = function()
        best_wall = min(best_wall, time.perf_counter() - wall)
        best_cpu = min(best_cpu, time.process_time() - cpu)
    return best_wall, best_cpu, result


def _line(label: str, wall: float, cpu: float | None = None, goal: float | None = None) -> None:
    extra = f" (CPU {cpu:.3f} s)" if cpu is not None else ""
    if goal:
        extra += f"  goal {goal:g} s: {'met' if wall <= goal else 'NOT met'}"
    print(f"  {label:<58} {wall:8.3f} s{extra}")


def python_loop_seconds_per_step(model, traj, w, steps: int) -> float:
    """Pure-Python rectangle loop over the generated numpy functions (ideal + real)."""
    f, fr = model.numpy.ideal_rhs, model.numpy.real_rhs
    p, u, tau = traj.parameters, traj.inputs[:, 0], traj.tau
    x = traj.truth[:, 0].copy()
    xr = model.initial_real_state(traj.initial_conditions, u, w, p)
    start = time.perf_counter()
    for _ in range(steps):
        x, xr = x + tau * f(x, u, p), xr + tau * fr(xr, x, u, w, p)
    return (time.perf_counter() - start) / steps


def bench_direct_and_linear(hours: float) -> None:
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import simulate

    model = load_model("orthodromic")
    tau = 0.01
    traj = tr.trajectory(model, tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG), hours * 3600,
                         tau)
    sources = {"gyro_drift_x": 0.01 * DEG / 3600}
    w = model.source_vector(**sources)
    steps = traj.n_steps
    print(f"static base, {hours:g} h at 100 Hz ({steps:,} steps), record every 1 s:")
    wall = time.perf_counter()
    simulate(model, traj, sources, record_interval=1.0, parts=("real",), method="euler")
    _line("direct (ideal + real), first call incl. build/compile", time.perf_counter() - wall)
    wall, cpu, _ = _timed(lambda: simulate(model, traj, sources, record_interval=1.0,
                                           parts=("real",), method="euler"))
    _line("direct (ideal + real), compiled, best of 3", wall, cpu,
          GOAL_DIRECT * hours / 24)
    per_step = python_loop_seconds_per_step(model, traj, w, 20_000)
    python_total = per_step * steps
    print(f"  {'pure-Python loop over generated numpy (20 000 steps, scaled)':<58} "
          f"{python_total:8.1f} s  ({per_step * 1e6:.1f} µs/step)")
    ratio = python_total / wall
    print(f"  {'speed-up compiled vs pure Python':<58} {ratio:8.0f} x  goal {GOAL_RATIO:g} x: "
          f"{'met' if ratio >= GOAL_RATIO else 'NOT met'}")
    wall_l, cpu_l, _ = _timed(lambda: simulate(model, traj, sources, record_interval=1.0,
                                               parts=("linear",), method="euler"))
    _line("linear error equations (ideal + F e + G w), best of 3", wall_l, cpu_l,
          GOAL_LINEAR * hours / 24)
    wall_a, cpu_a, _ = _timed(lambda: simulate(model, traj, sources, record_interval=1.0,
                                               method="euler"), repeats=1)
    _line("direct + linear + refined in one loop", wall_a, cpu_a)
    short = tr.trajectory(model, tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG), 600.0, tau)
    wall_c, _, _ = _timed(lambda: simulate(model, short, sources, record_interval=1.0,
                                           parts=("real",), method="euler"))
    wall_v, _, _ = _timed(lambda: simulate(model, short, sources, record_interval=1.0,
                                           parts=("real",), jit=False, method="euler"), repeats=1)
    print(f"  {'CasADi VM fallback vs compiled (10 min at 100 Hz)':<58} "
          f"{wall_v / wall_c:8.1f} x slower ({wall_v:.2f} s vs {wall_c:.3f} s)")


def bench_factor_suite(hours: float) -> None:
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model
    from ins_errors.units import parse_quantity

    model = load_model("orthodromic")
    small = {"rad/s": "0.01 deg/h", "m/s**2": "10 ug", "rad": "10 arcsec", "m/s": "0.1 m/s",
             "1": "1e-5"}
    cases = [{s.name: parse_quantity(small[s.unit], s.unit)} for s in model.sources]
    legs = []
    for _ in range(4):
        legs += [tr.Leg(600.0, 250.0, 90 * DEG, 1000.0), tr.Leg(900.0, 300.0, 0.0, 4000.0),
                 tr.Leg(900.0, 200.0, -60 * DEG, 2000.0),
                 tr.Leg(1200.0, 250.0, -30 * DEG, 1000.0)]
    motions = {
        "static": (tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG), hours),
        "great circle": (tr.great_circle_profile(50 * DEG, 30 * DEG, 40 * DEG, 250.0, 5000.0),
                         hours),
        "manoeuvre": (tr.manoeuvre_profile(40 * DEG, -20 * DEG, 70 * DEG, 200.0, legs, 1000.0),
                      min(hours, 4.0)),
    }
    print(f"13-factor suite: {len(cases)} sources x 3 motions, τ = 1 s, direct + linear + "
          "refined:")
    worst: dict[str, dict[str, float]] = {}
    total = time.perf_counter()
    for label, (profile, duration) in motions.items():
        start = time.perf_counter()
        traj = tr.trajectory(model, profile, duration * 3600, 1.0)
        middle = time.perf_counter()
        for c in compare(model, traj, cases, record_interval=60.0, warn=False):
            name = next(iter(c.sources))
            ratio = c.worst_linear.linear_ratio if c.worst_linear else float("nan")
            worst.setdefault(name, {})[label] = ratio
        _line(f"{label} ({duration:g} h): trajectory {middle - start:.2f} s + runs",
              time.perf_counter() - start)
    _line("whole suite", time.perf_counter() - total, None, GOAL_SUITE)
    print("\n  worst linear/direct ratio over excited quantities (each judged on its own; "
          "– = not excited):")
    print(f"  {'source':<36} {'factor':>6} " + " ".join(f"{m:>13}" for m in motions))
    for s in model.sources:
        row = " ".join(f"{worst[s.name][m]:13.2e}" if np.isfinite(worst[s.name][m])
                       else f"{'–':>13}" for m in motions)
        print(f"  {s.name:<36} {s.factor or '':>6} {row}")


def main(quick: bool = False) -> None:
    import os

    hours = 1.0 if quick else 24.0
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{os.cpu_count()} CPUs, load average {load:.2f} at start (wall times suffer "
          "when other work shares the cores; CPU times less so)")
    bench_direct_and_linear(hours)
    print()
    bench_factor_suite(hours)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
