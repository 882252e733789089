"""Which quantities a comparison judges: each on its own, not against another kind.

An azimuth gyro drift on a static base turns the platform about the vertical (α_z grows
to ~11 arcmin in a day) and, through the Earth rate, tilts it about x by a few 0.01
arcmin, oscillating. The tilt shared the unit rad with α_z and the latitude and longitude
errors, and was below 1e-3 of the largest of them: it was marked "excited = no" and left
out of the worst ratio, although it is a first-order effect the linear model reproduces.
The independent evidence of first order: halving the drift halves the tilt.

A quantity moved only at second order is still left out, also when the linear model's
0 is not exact but rounding (an initial velocity error's α_z at rest: 1e-19 rad linear,
1e-7 rad direct): halving the source quarters its direct error.
"""

from __future__ import annotations

import math

import pytest

from ins_errors import load_model
from ins_errors.numeric import compare as cmp
from ins_errors.numeric import trajectories as tr

DEG = math.pi / 180
DRIFT = 0.01 * DEG / 3600  # 0.01 deg/h
VELOCITY = 1.0  # m/s


@pytest.fixture(scope="module")
def runs():
    """Full and half magnitudes, a day at rest at 50° N (rectangle method, τ = 10 s)."""
    model = load_model("orthodromic")
    trajectory = tr.trajectory(model, tr.static_profile(50 * DEG, 30 * DEG), 24 * 3600.0, 10.0)

    def cases(factor):
        return cmp.compare(model, trajectory, [{"gyro_drift_z": factor * DRIFT},
                                               {"initial_velocity_error_xi": factor * VELOCITY}],
                           method="euler", record_interval=60.0, integration_error=False,
                           validity_threshold=None, warn=False)

    return cases(1.0), cases(0.5)


def test_a_small_first_order_tilt_is_judged(runs):
    (full, _), (half, _) = runs
    tilt = full.metric("alpha_x")
    # the situation: a tilt far below the azimuth and position errors of the same unit
    largest = max(m.max_direct for m in full.metrics if m.unit == "rad")
    assert tilt.max_direct < 1e-3 * largest
    # independent evidence that it is first order: half the drift, half the tilt
    assert half.metric("alpha_x").max_direct / tilt.max_direct == pytest.approx(0.5, rel=1e-3)
    assert tilt.excited and not tilt.second_order_only
    assert "alpha_x" in [m.quantity for m in full.excited]
    assert tilt.linear_ratio < 0.01  # the linear model reproduces it
    assert full.worst_linear.linear_ratio >= tilt.linear_ratio
    assert "| `alpha_x` |" in cmp.markdown_table(full)
    row = next(line for line in cmp.markdown_table(full).splitlines() if "`alpha_x`" in line)
    assert row.endswith("| yes |")
    assert "| judged |" in cmp.markdown_table(full)


def test_a_second_order_quantity_with_a_rounding_linear_error_is_not_judged(runs):
    (_, full), (_, half) = runs
    azimuth = full.metric("alpha_z")
    linear = max(abs(full.linear["alpha_z"]))
    assert 0 < linear < 1e-9 * azimuth.max_direct  # rounding, not an exact 0
    assert azimuth.max_direct > cmp.NOISE_FLOOR["rad"]
    # independent evidence that it is second order: half the error, a quarter of α_z
    assert half.metric("alpha_z").max_direct / azimuth.max_direct == pytest.approx(0.25, rel=0.01)
    assert azimuth.second_order_only and not azimuth.excited
    assert full.worst_linear.quantity != "alpha_z" and full.worst_linear.linear_ratio < 0.05
    row = next(line for line in cmp.markdown_table(full).splitlines() if "`alpha_z`" in line)
    assert row.endswith("| no: 2nd order |")
    # 0.00036 arcmin beside tilts of 0.8 arcmin: marked in the table, not warned of
    tilts = max(full.metric(q).max_direct for q in ("alpha_x", "alpha_y"))
    assert azimuth.max_direct < 1e-3 * tilts
    assert not [w for w in full.warnings if "second order" in w]


def test_an_error_at_the_rounding_floor_is_said_so():
    """A source with no effect at rest (an accelerometer scale error: the level
    accelerometers read ~0) leaves every error at rounding level: "no: rounding"."""
    model = load_model("orthodromic")
    trajectory = tr.trajectory(model, tr.static_profile(50 * DEG, 30 * DEG), 3600.0, 10.0)
    (case,) = cmp.compare(model, trajectory, [{"accel_scale_error_x": 1e-5}], method="euler",
                          record_interval=60.0, integration_error=False,
                          validity_threshold=None, warn=False)
    floor = [m for m in case.metrics if m.max_direct <= cmp.NOISE_FLOOR[m.unit]]
    assert floor and not case.excited
    for m in floor:
        row = next(line for line in cmp.markdown_table(case).splitlines()
                   if f"`{m.quantity}`" in line)
        assert row.endswith("| no: rounding |"), row
