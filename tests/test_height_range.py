"""Heights beyond ±100 km are refused wherever a height enters: the models' gravity is the
normal-gravity height series γ₀(1 − 2h/a + 3h²/a²), which grows again with height (51.3
m/s² at 10 000 km, where gravitation is 1.5 m/s²); ``modes --height 10000km`` printed that
g and ``compare strapdown_ned --height 1e9m`` blamed a latitude at ±90°."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from ins_errors.analysis import covariance as cv
from ins_errors.cli import main
from ins_errors.errors import DomainError
from ins_errors.models.earth import normal_gravity
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr

A = 6_378_137.0
"""WGS-84 semi-major axis, m."""
PHI = np.radians(50.0)


@pytest.mark.parametrize("height, worst", [(100e3, 2e-5), (-100e3, 2e-5)])
def test_the_height_series_holds_to_its_stated_accuracy_within_the_limit(height, worst):
    """The series' height factor (a sphere: e² = 0, no rotation) against the inverse-square
    law γ_e a²/(a + h)² (Newton, outside a spherical mass): within 1.6e-5 at ±100 km (the
    limit's documented accuracy), 1.7 % off at 1000 km and 34-fold at 10 000 km."""
    assert abs(height) == tr.HEIGHT_LIMIT

    def series(h):
        return normal_gravity(PHI, h, A, 0.0, gamma_e=1.0, k=0.0, m=0.0)

    def newton(h):
        return A**2 / (A + h) ** 2

    for h in np.linspace(0.0, height, 11):
        assert abs(series(h) / newton(h) - 1) <= worst
    assert abs(series(height) / newton(height) - 1) > 1e-5     # the limit is not loose
    assert series(1e6) / newton(1e6) - 1 > 0.015
    assert series(1e7) / newton(1e7) > 30


def _refused(call, *args, **kwargs) -> str:
    with pytest.raises(DomainError) as info:
        call(*args, **kwargs)
    assert isinstance(info.value, tr.MotionError)
    text = str(info.value)
    assert "\n" not in text and "beyond ±100 km" in text
    return text


def test_the_python_api_refuses_a_height_beyond_the_limit_as_a_domain_error(orthodromic):
    over = 1.001 * tr.HEIGHT_LIMIT
    assert "motion height 100.1 km" in _refused(tr.static_profile, PHI, h=over)
    _refused(tr.static_profile, PHI, h=-over)
    _refused(tr.great_circle_profile, PHI, 0.0, 0.0, 250.0, 1e7)
    assert "leg height 200 km" in _refused(
        tr.manoeuvre_profile, PHI, 0.0, 0.0, 200.0, [tr.Leg(60.0, 200.0, 0.0, 2e5)])
    t = np.arange(10.0)
    h = np.full(10, 1000.0)
    h[6] = 2e5                                      # the highest sample, not the lowest
    _refused(tr.sampled_profile, t, 100 + 0 * t, 0 * t, PHI, 0.0, 0.0, h)
    assert "static base height" in _refused(cv.static_system, orthodromic, PHI,
                                            height=1e7)
    _refused(st.static, PHI, height=over)
    _refused(st.great_circle, PHI, 0.0, 0.0, 250.0, height=-over)
    _refused(st.manoeuvre, PHI, 0.0, 0.0, 200.0, [tr.Leg(60.0, 200.0, 0.0, 2e5)])
    # the limit itself is inside
    tr.static_profile(PHI, h=tr.HEIGHT_LIMIT)
    tr.static_profile(PHI, h=-tr.HEIGHT_LIMIT)


def _one_line_error(capsys, argv) -> str:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    return err.removeprefix("ins-errors: error: ")


@pytest.mark.parametrize("argv, start", [
    (["modes", "orthodromic", "--height", "10000km"], "--height 10000 km is beyond ±100 km"),
    (["compare", "strapdown_ned", "-s", "gyro_bias_x=0.01deg/h", "--hours", "0.1",
      "--height", "1e9m"], "--height 1e+06 km is beyond ±100 km"),
    (["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--hours", "0.1",
      "--motion", "great-circle", "--height", "101km"], "--height 101 km is beyond ±100 km"),
])
def test_a_height_option_beyond_the_limit_is_refused_in_one_line(capsys, argv, start):
    err = _one_line_error(capsys, argv)
    assert err.startswith(start), err
    assert "the heights ins-errors accepts, whatever the model" in err


def test_modes_at_the_limit_use_the_gravity_of_that_height(capsys):
    """At 100 km the static base's g is that of a rotating sphere of radius a: gravitation
    (g₀ + ω²a cos²φ)(a/(a + h))² (Newton) less the centrifugal ω²(a + h) cos²φ, to 3e-5
    (measured 8e-6: the flattening's terms), not a value that grows with height."""
    import json

    values = []
    for height in ("0m", "100km"):
        assert main(["modes", "orthodromic", "--height", height, "--latitude", "50deg",
                     "--json"]) == 0
        values.append(json.loads(capsys.readouterr().out)["references"]["g"]["value"])
    g0, g100 = values
    spin = 7.292115e-5**2 * np.cos(PHI) ** 2
    h = 1e5
    assert g100 == pytest.approx((g0 + spin * A) * (A / (A + h)) ** 2 - spin * (A + h),
                                 rel=3e-5)


SCENARIO = """
    model = "orthodromic"
    [motion]
    {motion}
    [run]
    duration = "60 s"
    step = "10 s"
    record = "10 s"
    [[case]]
    gyro_drift_x = "0.01 deg/h"
"""

SPEC = """
    sigma_level = 2
    operating_time = "1 h"
    [motion]
    {motion}
    [items.position_error]
    value = "3.7 km/h"
"""


@pytest.mark.parametrize("motion, words", [
    ('kind = "static"\nlatitude = "50 deg"\nheight = "150 km"',
     "[motion]: motion height 150 km is beyond ±100 km"),
    ('kind = "manoeuvre"\nlatitude = "50 deg"\nspeed = "200 m/s"\n[[motion.legs]]\n'
     'duration = "30 s"\nheight = "300 km"', "manoeuvre leg height 300 km is beyond ±100 km"),
    ('kind = "file"\nfile = "high.csv"\nlatitude = "50 deg"',
     "motion file 'high.csv', line 4: h 200 km is beyond ±100 km"),
])
def test_a_scenario_height_beyond_the_limit_is_refused_in_one_line(tmp_path, capsys,
                                                                  monkeypatch, motion,
                                                                  words):
    monkeypatch.chdir(tmp_path)
    rows = ["t,v_N,v_E,h"] + [f"{t},100,50,{2e5 if t == 2 else 1000.0}" for t in range(80)]
    (tmp_path / "high.csv").write_text("\n".join(rows) + "\n")
    (tmp_path / "s.toml").write_text(textwrap.dedent(SCENARIO).replace(
        "{motion}", motion))
    err = _one_line_error(capsys, ["run", "s.toml", "--no-progress", "--out", "o"])
    assert words in err, err


@pytest.mark.parametrize("motion, words", [
    ('kind = "static"\nlatitude = "50 deg"\nheight = "10000 km"',
     "s.toml: motion.height 10000 km is beyond ±100 km"),
    ('kind = "manoeuvre"\nlatitude = "50 deg"\nspeed = "200 m/s"\n[[motion.legs]]\n'
     'duration = "10 min"\nheight = "500 km"',
     "s.toml: motion.legs: leg 1's height 500 km is beyond ±100 km"),
])
def test_a_spec_height_beyond_the_limit_is_refused_in_one_line(tmp_path, capsys, motion,
                                                              words):
    spec = tmp_path / "s.toml"
    spec.write_text(textwrap.dedent(SPEC).replace("{motion}", motion))
    err = _one_line_error(capsys, ["budget", "orthodromic", "--spec", str(spec)])
    assert words in err, err
