"""F that becomes 0/0 later along a moving run (a drag c|V|V when the speed passes
through 0 mid-run) is named with its entries and the time in one line, not reported as
the system leaving its domain; the direct run through the same point stays finite.

The motion is built so that the ideal run reaches V = 0 exactly: V_N falls from 8 m/s by
1/32 m/s² with V_E = 0, the drag coefficient is 2⁻¹⁰/m and every sample is a dyadic
rational, so each RK4 stage is exact and V_N is 0 to the bit at 8 / (1/32) = 256 s."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.errors import DomainError
from ins_errors.numeric.compare import compare
from ins_errors.numeric.simulate import simulate
from ins_errors.numeric.trajectories import Trajectory

DRAG_MODEL = str(Path(__file__).resolve().parent / "models" / "velocity_drag.py")
ENTRIES = ("F[delta_V_N, delta_V_N], F[delta_V_N, delta_V_E], F[delta_V_E, delta_V_N] "
           "and F[delta_V_E, delta_V_E]")
SLOPE, START = 1 / 32, 8.0   # m/s², m/s: at rest at START / SLOPE = 256 s


def _through_rest(model, steps: int = 320):
    """The vehicle slows at SLOPE through rest on a 1-s grid; the inputs a_N are the
    motion's acceleration plus the drag c|v|v the model's computer removes."""
    c = 2.0 ** -10
    p = model.parameter_vector(c=c)
    t = np.arange(steps + 1.0)
    v, vm = START - SLOPE * t, START - SLOPE * (t[:-1] + 0.5)
    a, am = -SLOPE + c * np.abs(v) * v, -SLOPE + c * np.abs(vm) * vm
    return Trajectory(model.key, 1.0, steps, np.vstack([v, 0 * v]), np.vstack([a, 0 * a]),
                      np.vstack([am, 0 * am]), p, np.array([START, 0.0]), False,
                      "slowing through rest")


@pytest.mark.parametrize(("parts", "record", "run"), [
    (["linear"], None, "linear"), (["refined"], 32.0, "refined"),
    (["real", "linear", "refined"], 64.0, "linear")])
def test_f_not_finite_mid_run_is_named_with_its_time(parts, record, run):
    model = load_model(DRAG_MODEL)
    motion = _through_rest(model)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        with pytest.raises(DomainError) as raised:
            simulate(model, motion, {"accel_bias_N": 1e-3}, parts=parts,
                     record_interval=record)
    assert not [w for w in seen if issubclass(w.category, RuntimeWarning)]
    line = str(raised.value)
    assert "\n" not in line and "left its domain" not in line
    assert f"F of velocity_drag is not finite at t = {START / SLOPE:g} s" in line
    assert ENTRIES in line and f"the {run} run became NaN" in line
    assert "G[" not in line   # the bias enters as it is: G is finite


def test_the_direct_run_passes_rest_and_compare_names_f():
    model = load_model(DRAG_MODEL)
    motion = _through_rest(model)
    sim = simulate(model, motion, {"accel_bias_N": 1e-3}, parts=["real"])
    assert sim.ideal[0, int(START / SLOPE), 0] == 0.0   # the point is reached exactly
    assert np.all(np.isfinite(sim.real))
    with pytest.raises(DomainError, match=r"^F of velocity_drag is not finite at t = 256 s"):
        compare(model, motion, [{"accel_bias_N": 1e-3}], warn=False)
