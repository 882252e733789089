"""The standard manoeuvre lasts as long as the run (long-flight probe).

``default_legs`` built 24 h of legs and the flight went straight after them, while the
header of a week's run still said "standard manoeuvre (every hour a 90° left turn ...)":
the largest |a_η| was about 1 m/s² in every 2-h block up to 24 h and 0.03 m/s² after.
The legs are now flown again and again; a run of 24 h or less is the same numbers as
before, bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from ins_errors.errors import InsErrorsError
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.model import load_model
from ins_errors.numeric.motion_spec import STANDARD_MANOEUVRE, default_legs, motion_profile

DAY = 86400.0
SPEED, HEIGHT = 200.0, 3000.0
DESCRIPTION = {"kind": "manoeuvre", "latitude": "50 deg", "longitude": "30 deg",
               "speed": f"{SPEED} m/s", "height": f"{HEIGHT} m"}


def _one_day():
    """The standard manoeuvre as it was built before: one day of legs, then straight."""
    return tr.manoeuvre_profile(np.radians(50.0), np.radians(30.0), np.radians(90.0), SPEED,
                                default_legs(SPEED, HEIGHT), HEIGHT, name=STANDARD_MANOEUVRE)


def _hourly_peak_turn(profile, hours: float) -> np.ndarray:
    """The largest |commanded cross-track acceleration| v·dψ/dt (m/s²) in each hour."""
    t = np.arange(0.0, hours * 3600.0, 5.0)
    values, rates = profile.commands(t)
    v1, v2, dv1, dv2 = values[0], values[1], rates[0], rates[1]
    lateral = np.abs(v1 * dv2 - v2 * dv1) / np.hypot(v1, v2)
    return lateral.reshape(int(hours), -1).max(axis=1)


def test_the_manoeuvre_turns_every_hour_of_a_week():
    peaks = _hourly_peak_turn(motion_profile(DESCRIPTION), 168)
    # a 90° turn in 600 s on the C² ramp: peak rate 1.875 × (π/2)/600 s at 200 m/s
    expected = 1.875 * (np.pi / 2) / 600.0 * SPEED
    assert peaks == pytest.approx(expected, rel=1e-3)


def test_later_days_repeat_the_first_one():
    profile = motion_profile(DESCRIPTION)
    t = np.linspace(0.0, DAY, 7919)
    first_values, first_rates = profile.commands(t)
    for day in (1, 6, 29):
        values, rates = profile.commands(t + day * DAY)
        # (t + 29 days is t to about 4e-10 s: the commands to that much)
        np.testing.assert_allclose(values, first_values, rtol=0, atol=1e-8)
        np.testing.assert_allclose(rates, first_rates, rtol=0, atol=1e-8)


def test_a_day_or_less_is_the_same_numbers_as_before():
    repeated, once = motion_profile(DESCRIPTION), _one_day()
    assert repeated.description == once.description
    t = np.concatenate([np.linspace(0.0, DAY, 100_003), [599.9999, 600.0, DAY]])
    for new, old in zip(repeated.commands(t), once.commands(t), strict=True):
        assert np.array_equal(new, old)
    assert tr.covering(repeated, DAY).breaks == once.breaks
    model = load_model("orthodromic")
    short = [tr.trajectory(model, profile, 7200.0, 5.0) for profile in (repeated, once)]
    for name in ("truth", "inputs"):
        assert np.array_equal(getattr(short[0], name), getattr(short[1], name))


def test_the_joins_of_a_long_run_are_all_breaks():
    """The interpolated truth and the strapdown flight cut their intervals at every
    join: a two-day run knows the joins of its second day too."""
    profile = tr.covering(motion_profile(DESCRIPTION), 2 * DAY)
    breaks = np.asarray(profile.breaks)
    joins = np.cumsum([leg.duration for leg in default_legs(SPEED, HEIGHT, hours=48)])
    assert set(joins) <= set(breaks)
    assert np.all(np.diff(breaks) > 0)


def test_a_long_kinematic_run_keeps_manoeuvring():
    """The probe's measure on the true inputs of a 26-h run: the largest |a_η| of the
    hours after the first day is that of the first hours (within the few per cent the
    day's drift in latitude and the transport terms make), not the 0.03 m/s² of a
    straight flight."""
    model = load_model("orthodromic")
    run = tr.trajectory(model, motion_profile(DESCRIPTION), 26 * 3600.0, 60.0)
    a_eta = np.abs(run.inputs[[i.name for i in model.inputs].index("a_eta")])
    first, later = a_eta[: 2 * 60].max(), a_eta[24 * 60:].max()
    assert later == pytest.approx(first, rel=0.1) and first > 0.5


def test_legs_that_do_not_close_are_not_repeated():
    legs = [tr.Leg(600.0, 220.0, np.radians(30.0), 1000.0)]
    with pytest.raises(InsErrorsError, match="again and again"):
        tr.manoeuvre_profile(0.8, 0.5, 0.0, 200.0, legs, 1000.0, repeat=True)
