"""Speed of the issue-6 studies: methodological 24-h runs and the spheroid survey.

Printed, never asserted. ``--quick`` runs 2 h instead of 24 h and a 2-h survey.
"""

from __future__ import annotations

import time


def _timed(label: str, call) -> None:
    wall, cpu = time.perf_counter(), time.process_time()
    call()
    print(f"  {label:<44} wall {time.perf_counter() - wall:7.2f} s   "
          f"cpu {time.process_time() - cpu:7.2f} s")


def main(quick: bool = False) -> None:
    from ins_errors.studies import methodological, spheroid_error

    hours = 2.0 if quick else 24.0
    for name in methodological.STUDIES:
        # first call includes building the simplified computer symbolically
        for scenario in methodological.SCENARIOS:
            _timed(f"{name} {scenario} {hours:g} h (RK4, 20 s)",
                   lambda n=name, s=scenario: methodological.run(n, s, duration=hours * 3600.0,
                                                                 tau=20.0))
    survey_hours = 2.0 if quick else 6.0
    _timed(f"spheroid survey, 16 flights x 2 modes, {survey_hours:g} h",
           lambda: spheroid_error.survey(duration=survey_hours * 3600.0))
