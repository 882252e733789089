"""The interpolated true motion against the fine one over a day at 100 Hz (issue 16).

For a great circle and a manoeuvre (the flights of ``bench_speed``), the direct and
linear runs are made twice: along the fine truth (RK4 at half the step, inputs at every
half step) and along the interpolated truth (coarse intervals, degree-7 polynomials).
Printed: the CPU seconds of each, and how far apart the direct error curves are
(largest difference over the run, as a fraction of each curve's largest value) next to
the differences between the linear and the direct runs that the toolchain reports.
Nothing is asserted; ``--quick`` flies one hour.

Run alone with ``python -m benchmarks bench_truth [--quick]``.
"""

from __future__ import annotations

import time

import numpy as np

DEG = np.pi / 180.0


def _compare(kind: str, hours: float) -> None:
    from benchmarks.bench_speed import _legs
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import simulate

    model = load_model("orthodromic")
    if kind == "great circle":
        profile = tr.great_circle_profile(50 * DEG, 30 * DEG, 90 * DEG, 250.0, 5000.0)
    else:
        profile = tr.manoeuvre_profile(40 * DEG, -20 * DEG, 70 * DEG, 200.0, _legs(hours),
                                       1000.0)
    cases = [{"gyro_drift_x": 0.01 * DEG / 3600, "accel_bias_y": 1e-4},
             {"initial_azimuth_error": 2e-4}]
    runs, cpu = [], []
    for truth in ("fine", "interpolated"):
        start = time.process_time()
        traj = tr.trajectory(model, profile, hours * 3600.0, 0.01, stream=True, truth=truth)
        runs.append(simulate(model, traj, cases, record_interval=10.0,
                             parts=("real", "linear"), method="euler"))
        cpu.append(time.process_time() - start)
    fine, fast = (r.direct_errors() for r in runs)
    linear = runs[0].linear_errors()
    size = np.abs(fine.values).max(axis=(1, 2))
    excited = size > 0
    apart = np.abs(fast.values - fine.values).max(axis=(1, 2))[excited] / size[excited]
    linear_apart = np.abs(linear.values - fine.values).max(axis=(1, 2))[excited] / size[excited]
    print(f"  {hours:g} h {kind} at 100 Hz, 2 cases, direct + linear: fine truth "
          f"{cpu[0]:.1f} s CPU, interpolated {cpu[1]:.1f} s CPU")
    print(f"    direct error curves, interpolated vs fine truth: at most {apart.max():.1e} "
          f"of each curve")
    print(f"    linear vs direct (what the toolchain reports):   {linear_apart.min():.1e} to "
          f"{linear_apart.max():.1e} of each curve")


def main(quick: bool = False) -> None:
    """Print the comparison for both flights."""
    hours = 1.0 if quick else 24.0
    for kind in ("great circle", "manoeuvre"):
        _compare(kind, hours)


if __name__ == "__main__":
    import sys

    main("--quick" in sys.argv)
