"""Matrix check (``ins-errors check MODEL --matrix``): where the time of one check goes.

Prints wall and CPU seconds for the textbook ψ-angle model of ``examples/strapdown`` on
``strapdown_ned``: sampling the three 24-h motions (60 s steps), evaluating the
researcher's function at every sample, carrying the derived F and G into the ψ
convention, comparing the entries, propagating both models and each finding alone.
Nothing is asserted.
"""

from __future__ import annotations

import time
from pathlib import Path

PSI = Path(__file__).resolve().parent.parent / "examples" / "strapdown" / "psi_model.py"


def _timed(label: str, function):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function()
    print(f"  {label:<52} {time.perf_counter() - wall:7.2f} s wall "
          f"{time.process_time() - cpu:7.2f} s CPU")
    return result


def main(quick: bool = False) -> None:
    from ins_errors.checker import matrix as mc
    from ins_errors.checker.conventions import convention
    from ins_errors.checker.matrix_input import evaluate_function, load_function
    from ins_errors.numeric.model import load_model

    hours = 2.0 if quick else 24.0
    model = load_model("strapdown_ned")
    motions = _timed(f"three motions, {hours:g} h at 60 s",
                     lambda: mc.motions(model, hours=hours, step=60.0))
    fn, states, sources = load_function(PSI, "psi_model")
    _timed(f"psi_model at {sum(m.times.size for m in motions)} samples",
           lambda: evaluate_function(fn, "psi_model", PSI, states, sources, motions))
    conv = convention(model, "psi")
    _timed("derived F, G in the psi convention (T, Ṫ exact)",
           lambda: [mc.derived_in_convention(model, conv, m) for m in motions])
    _timed("whole check without propagation",
           lambda: mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                                     motion_list=motions, effects=False))
    report = _timed("whole check with both propagations",
                    lambda: mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                                              motion_list=motions))
    print(f"  {report.compared} entries, {len(report.findings)} findings, "
          f"{len(report.effects)} propagated cases")
