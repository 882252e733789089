"""A step not well under F's fastest period is warned about, with a step that resolves it.

A 1-h step over an hour of a Schuler loop ran one step and said only "integration error
not estimated". The reference period is the textbook one, not the code's eigenvalues:
2π √(R/g) for the single-axis Schuler loop of examples/own_model (its parameters R and
g), 84.4 min.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

from ins_errors.cli import main
from ins_errors.numeric.model import load_model

ROOT = Path(__file__).resolve().parents[1]
LOOP = str(ROOT / "examples" / "own_model" / "schuler_loop.py")


def _case(capsys, *args: str) -> dict:
    assert main(["compare", *args, "--no-progress", "--no-refined", "--json"]) == 0
    [case] = json.loads(capsys.readouterr().out)["cases"]
    return case


def _too_long(case: dict) -> list[str]:
    return [w for w in case["warnings"] if w.startswith("step too long")]


def test_an_hour_step_of_a_schuler_loop_is_warned_with_its_period_and_a_step(capsys):
    model = load_model(LOOP)
    p = dict(zip((q.name for q in model.parameters), model.parameter_vector(), strict=True))
    period = 2 * math.pi * math.sqrt(p["R"] / p["g"])  # s, the textbook Schuler period
    [warning] = _too_long(_case(capsys, LOOP, "-s", "accel_bias=100ug", "--step", "1h",
                                "--hours", "1"))
    assert f"({period / 60:.3g} min at the start)" in warning, warning
    assert f"τ = 3600 s is {3600 / period:.2g} of its period" in warning
    named = float(re.search(r"τ = ([0-9.]+) s \(20 a period\)", warning)[1])
    assert period / 25 <= named <= period / 20 and 3600 % named == 0, named
    # the step named runs without the warning; one just over a tenth of the period warns
    assert not _too_long(_case(capsys, LOOP, "-s", "accel_bias=100ug", "--step",
                               f"{named:g}s", "--hours", "1"))
    over = math.ceil(period / 10 / 10) * 10  # s, the first multiple of 10 s above T/10
    for step, warned in ((over, True), (over - 10, False)):
        case = _case(capsys, LOOP, "-s", "accel_bias=100ug", "--step", f"{step}s",
                     "--duration", f"{8 * step}s")
        assert bool(_too_long(case)) is warned, (step, case["warnings"])


def test_the_probes_orthodromic_hour_step_is_warned(capsys):
    """The probe's command: one step of an hour on the orthodromic model at rest (F's
    fastest period 80.7 min: Schuler's split by Foucault's rate at 50°)."""
    [warning] = _too_long(_case(capsys, "orthodromic", "-s", "gyro_drift_y=0.01deg/h",
                                "--step", "1h", "--hours", "1"))
    assert "80.7 min at the start" in warning
