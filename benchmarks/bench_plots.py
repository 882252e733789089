"""CPU seconds of the report figures (issue 16): what drawing costs a user per report.

Printed, never asserted. Each figure is timed in this process after a warm-up figure
(matplotlib imported, fonts loaded); "first" builds the figure, a "later" call refills
the figure the previous call kept. ``--quick`` uses a 2-h scenario instead of 24 h.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

SCENARIO = """title = "figure benchmark"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "{hours} h"
step = "10 s"
record = "60 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
[[case]]
gyro_drift_z = "0.01 deg/h"
"""


def _cpu(call) -> float:
    start = time.process_time()
    call()
    return time.process_time() - start


def _comparison_figures(folder: Path, hours: float) -> None:
    from ins_errors.numeric import plots
    from ins_errors.scenario import load_scenario, run_scenario

    path = folder / "scenario.toml"
    path.write_text(SCENARIO.format(hours=hours), encoding="utf-8")
    result = run_scenario(load_scenario(path))
    cases = result.comparisons
    shown = plots.shared_quantities(cases)
    plots.plot_comparisons(cases[:1], [folder / "warm.png"], quantities=["alpha_x"])

    def report(name: str) -> None:
        plots.plot_comparisons(cases, [folder / f"{name}_{k}.png" for k in range(len(cases))],
                               quantities=shown)

    plots._SPARE_FIGURES.figures.clear()  # (the first call builds its figure)
    first = _cpu(lambda: report("first"))
    later = min(_cpu(lambda: report("later")) for _ in range(3))
    print(f"  comparison figures, {len(cases)} cases x {len(shown)} rows x 2 panels, "
          f"{len(cases[0].times)} samples: first call {first:.2f} s CPU, "
          f"later call {later:.2f} s CPU")


def _propagation_figures(folder: Path, hours: float) -> None:
    from ins_errors.output import OutputFolder
    from ins_errors.studies import propagation

    result = propagation.run(propagation.Experiment(duration=hours * 3600.0))
    out = OutputFolder(folder / "propagation")
    cpu = _cpu(lambda: propagation.plot(result, out))
    out.finish()   # the run's files kept, its undo copies discarded
    print(f"  propagation figures, {len(result.curves)} sources x 7 panels, "
          f"{len(result.times)} samples: {cpu:.2f} s CPU")


def main(quick: bool = False) -> None:
    import matplotlib

    matplotlib.use("Agg")
    hours = 2.0 if quick else 24.0
    with tempfile.TemporaryDirectory() as scratch:
        _comparison_figures(Path(scratch), hours)
        _propagation_figures(Path(scratch), hours)


if __name__ == "__main__":
    import sys

    main(quick="--quick" in sys.argv[1:])
