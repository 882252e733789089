"""Validity map of the orthodromic model (26 sources, static base and great circle, 24 h,
eight magnitudes each) on a local process pool: wall time, and the slopes it found.

Goal of the issue: "a few minutes on 2 cores". Also prints the rectangle method's
Schuler-envelope error after 24 h at τ = 1 s and 10 s (against the matrix exponential),
the reason the default scheme is RK4.
"""

from __future__ import annotations

import os
import time

import numpy as np


def _rectangle_envelope() -> None:
    import ins_errors
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.simulate import linear_exact, simulate

    model = ins_errors.load_model("orthodromic")
    source = {"accel_bias_x": 100 * 9.80665e-6}
    for tau in (1.0, 10.0):
        traj = tr.trajectory(model, tr.static_profile(np.radians(50), np.radians(30)),
                             86400.0, tau)
        for method in ("euler", "rk4"):
            sim = simulate(model, traj, [source], method=method, record_interval=60.0,
                           parts=("linear",))
            lin = sim.linear_errors()["delta_v_N"][:, 0]
            exact = linear_exact(model, traj, [source], record_interval=60.0)["delta_v_N"][:, 0]
            last = slice(-120, None)
            envelope = np.abs(lin[last]).max() / np.abs(exact[last]).max()
            print(f"  {method:5s} τ = {tau:4g} s: 24-h Schuler envelope {envelope:.4f} × exact, "
                  f"max error {np.abs(lin - exact).max() / np.abs(exact).max():.2e} of the peak")


def main(quick: bool = False) -> None:
    import ins_errors
    from ins_errors.analysis.validity import validity_map, validity_tasks

    _rectangle_envelope()
    model = ins_errors.load_model("orthodromic")
    hours = 4.0 if quick else 24.0
    tasks = validity_tasks(model, hours=hours)
    start, cpu = time.perf_counter(), time.process_time()
    results = validity_map(tasks, engine="pool")
    wall = time.perf_counter() - start
    print(f"  validity map: {len(tasks)} sweeps ({hours:g} h each) in {wall:.1f} s wall on "
          f"{os.cpu_count()} core(s) (parent CPU {time.process_time() - cpu:.1f} s)")
    ok = [r for r in results if r.status == "ok"]
    lin = [r.linear_slope for r in ok]
    ref = [r.refined_slope for r in ok if r.refined_slope is not None]
    print(f"  {len(ok)} excited sweeps: linear slopes {min(lin):.3f}..{max(lin):.3f}, "
          f"refined slopes {min(ref):.3f}..{max(ref):.3f} ({len(ref)} measurable)")
    others = sorted({(r.status, r.source) for r in results if r.status != "ok"})
    print(f"  not fitted: {', '.join(f'{s} ({st})' for st, s in others)}")
