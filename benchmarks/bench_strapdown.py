"""strapdown_ned: derive time, and direct vs linear vs refined over 24 h at 100 Hz.

Printed by ``make bench``, never asserted. Issue 11 asks for the linear model within
1e-3 (relative to the largest direct error of each quantity) and the refined (second
order) model within 1e-5 at small errors, on a static base, a great circle and a
manoeuvre.

"Small errors" here (``strapdown_ned.SMALL_ERRORS``) are every one of the 33 sources at
once, at a tenth of a 1 nmi/h navigation-grade IMU and alignment: gyro biases 0.001 deg/h,
accelerometer biases 5 µg, scale factors 5 ppm (gyro) / 10 ppm (accelerometer),
misalignments 0.5 / 1 arcsec, initial roll and pitch 2 arcsec, heading 0.2 arcmin,
velocity 5 mm/s, position 0.5 m, signs mixed. The navigation-grade set itself
(``strapdown_ned.NAVIGATION_GRADE``, ten times larger) is printed too: the linear
model's error grows with the error size. The vertical
channel is damped (600 s loop, damping 0.7; undamped it diverges by e^150 in 24 h).

Run alone with ``python -m benchmarks.bench_strapdown [--quick]`` (quick: 2 h).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

G0 = 9.80665
R0 = 6_371_000.0


def bench_derive() -> None:
    """Wall time of deriving and writing strapdown_ned's generated package."""
    from derive.model_files import write_model
    from ins_errors.models import definition

    start, cpu = time.perf_counter(), time.process_time()
    d = definition("strapdown_ned")
    built = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        summary = write_model(d, Path(folder))
    done = time.perf_counter()
    print(f"  derive strapdown_ned: build {built - start:.2f} s, vary + generate "
          f"{done - built:.2f} s, {summary.operations} operations, total {done - start:.2f} s "
          f"(CPU {time.process_time() - cpu:.2f} s)")


def flights():
    from ins_errors.numeric import strapdown_truth as st

    return {
        "static": st.static(np.radians(45.0), heading=np.radians(30.0)),
        "great circle": st.great_circle(np.radians(50.0), np.radians(30.0), np.radians(60.0),
                                        250.0, 10_000.0),
        "manoeuvre": st.standard_manoeuvre(),
    }


def bench_comparison(hours: float) -> None:
    from ins_errors.models.strapdown_ned import NAVIGATION_GRADE, SMALL_ERRORS
    from ins_errors.numeric import strapdown_truth as st
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model

    model = load_model("strapdown_ned")
    w0 = 2 * np.pi / 600.0
    p = model.parameter_vector(k_h1=2 * 0.7 * w0, k_h2=w0**2 + 2 * G0 / R0)
    print(f"  {hours:g} h at 100 Hz, RK4, all 33 sources at once; ratio = max|model − direct|"
          " / max|direct| per quantity, worst excited quantity shown")
    for name, flight in flights().items():
        start, cpu = time.perf_counter(), time.process_time()
        traj = st.trajectory(model, flight, hours * 3600.0, 0.01, p=p)
        truth_s, truth_cpu = time.perf_counter() - start, time.process_time() - cpu
        start, cpu = time.perf_counter(), time.process_time()
        small, nav = compare(model, traj, [SMALL_ERRORS, NAVIGATION_GRADE], method="rk4",
                             record_interval=60.0)
        run_s, run_cpu = time.perf_counter() - start, time.process_time() - cpu
        for label, c, goal in (("small", small, True), ("nav-grade", nav, False)):
            wl, wr = c.worst_linear, c.worst_refined
            verdict = ""
            if goal:
                ok = wl.linear_ratio <= 1e-3 and wr.refined_ratio <= 1e-5
                verdict = "  goals 1e-3 / 1e-5: " + ("met" if ok else "NOT met")
            print(f"  {name:<13} {label:<10} linear {wl.linear_ratio:.2e} ({wl.quantity})  "
                  f"refined {wr.refined_ratio:.2e} ({wr.quantity}){verdict}")
        peaks = ", ".join(f"{m.quantity} {m.max_direct:.3g}" for m in small.metrics)
        print(f"  {'':<13} small-error peaks (SI): {peaks}")
        made = "set up (streamed: generated during the runs)" if traj.is_streamed else "built"
        print(f"  {'':<13} truth {made} {truth_s:.1f} s (CPU {truth_cpu:.1f} s), direct + "
              f"linear + refined {run_s:.1f} s (CPU {run_cpu:.1f} s)")
        del traj


def main(quick: bool = False) -> None:
    bench_derive()
    bench_comparison(2.0 if quick else 24.0)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
