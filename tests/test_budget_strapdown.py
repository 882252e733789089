"""Budget items on the attitude of a strapdown INS: the level and azimuth components of
its φ-angle (no platform angles), for strapdown_ned and a strapdown model file.

References: the attitude error at the start is the initial attitude error itself (a
level vehicle's roll error is a tilt of the same size, whatever its heading); a
vertical gyro's bias ε turns a level vehicle's azimuth at the rate ε (over an hour at
50° the Earth-rate and Schuler couplings take 1.4 % off the mean rate); a horizontal
accelerometer's bias tilts the computed vertical by up to 2b/g (Schuler,
(b/g)(1 − cos ω_s t)).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.analysis.budget import unit_budget
from ins_errors.cli import main
from ins_errors.specs import default_spec_path, load_spec

SPHERE_FILE = Path(__file__).resolve().parents[1] / "examples" / "strapdown" / \
    "strapdown_sphere.py"


def _unit(model, **parameters):
    spec = load_spec(default_spec_path())
    budget = unit_budget(model, spec, p=model.parameter_vector(**parameters))
    sources = [s.name for s in budget.sources]

    def at(item: str, time: float, source: str) -> float:
        row = next(k for k, r in enumerate(budget.rows)
                   if r.item == item and r.time == time)
        return float(budget.unit_variances[row, sources.index(source)])

    return at


@pytest.mark.parametrize("which", ["strapdown_ned", "file"])
def test_strapdown_attitude_items_read_the_phi_angle(which):
    if which == "file":
        model = load_model(str(SPHERE_FILE))
        at = _unit(model)
        roll, gyro_z, accel_y = None, "gyro_bias_z", "accel_bias_y"
    else:
        model = load_model("strapdown_ned")
        at = _unit(model, k_h1=0.0293, k_h2=4.42e-4)
        roll, gyro_z, accel_y = "initial_roll_error", "gyro_bias_z", "accel_bias_y"
    if roll is not None:
        assert at("vertical_error", 0.0, roll) == pytest.approx(1.0, rel=1e-9)
    # the azimuth turns at the vertical gyro's bias rate (variance per unit variance)
    assert at("heading_drift", 3600.0, gyro_z) == pytest.approx(1.0, rel=0.03)
    # an accelerometer bias tilts by (b/g)(1 − cos ω_s t): 2b/g at half a Schuler period
    g = 9.81
    tilt = np.sqrt(at("vertical_error", 2400.0, accel_y))  # rad per m/s²
    assert tilt * g == pytest.approx(2.0, rel=0.05)


def test_items_a_model_cannot_check_are_named_with_the_way_out(tmp_path, capsys,
                                                              monkeypatch):
    """A strapdown model file without the navigation outputs (no roll output) has
    neither platform angles nor a φ-angle: the default spec's tilt and azimuth items are
    named in one line, and the advice, the same spec without those tables, gives a
    budget."""
    import json
    import re

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = SPHERE_FILE.read_text(encoding="utf-8")
    old = '    *(Variable(name, "rad", name, latex) for name, latex in ANGLES),\n)'
    assert text.count(old) == 1  # the outputs' attitude (the initial conditions keep it)
    text = text.replace(old, '    *(Variable("bank" if name == "roll" else name, "rad", name, '
                             'latex) for name, latex in ANGLES),\n)')
    model = tmp_path / "no_roll.py"
    model.write_text(text, encoding="utf-8")
    assert main(["budget", str(model)]) == 2
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert len(err) == 1
    assert "cannot check the spec items vertical_error, heading_drift" in err[0]
    assert "position_error" not in err[0] and "ground_speed_error" not in err[0]
    assert "without its [items.vertical_error], [items.heading_drift] tables" in err[0]
    assert str(default_spec_path()) in err[0] and "--spec" in err[0]
    spec_text = default_spec_path().read_text()
    for name in ("vertical_error", "heading_drift"):   # each table up to the next one
        spec_text = re.sub(rf"\[items\.{name}\]\n(?:[^\[\n].*\n)*", "", spec_text)
    spec = tmp_path / "802m_strapdown.toml"
    spec.write_text(spec_text)
    assert main(["budget", str(model), "--spec", str(spec), "--json"]) in (0, 1)
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert {r["item"] for r in rows} == {"position_error", "ground_speed_error"}


AT_ALTITUDE = """
title = "a cruise at 10 km"
sigma_level = 1
operating_time = "10 min"
step = "10 s"
[motion]
kind = "great_circle"
speed = "250 m/s"
height = "10000 m"
latitude = "50 deg"
longitude = "30 deg"
heading = "60 deg"
[items.position_error_absolute]
value = "200 km"
times = ["10 min"]
[sources.gyro_bias_x]
fixed = "1 deg/h"
"""


def test_a_strapdown_position_error_at_altitude_is_taken_on_r_plus_h(tmp_path, capsys):
    """A filter designer's 0.16 %: the budget turned δφ, δλ into metres on R_N and R_E cos φ
    alone, its height read from an input named h that a strapdown INS does not have
    (strapdown_ned's height is a state). Reference: the φ convention's exact map to NED
    metres, δr_N = (R_N + h) δφ (models.strapdown_conventions), propagated for the same
    source by the covariance module."""
    import json

    from ins_errors.analysis import covariance as cv
    from ins_errors.checker.conventions import convention
    from ins_errors.numeric import trajectories as tr

    spec = tmp_path / "cruise.toml"
    spec.write_text(AT_ALTITUDE, encoding="utf-8")
    gains = ["-p", "k_h1=0.0293/s", "-p", "k_h2=4.42e-4/s^2"]
    assert main(["budget", "strapdown_ned", "--spec", str(spec), "--at", "10 min",
                 "--json", *gains]) == 0
    c = json.loads(capsys.readouterr().out)["contributions"]
    j = c["sources"].index("gyro_bias_x")
    budget_r = [c["std"][0][c["quantities"].index(q)][j] for q in ("delta_r_N", "delta_r_E")]

    model = load_model("strapdown_ned")
    p = model.parameter_vector(k_h1=0.0293, k_h2=4.42e-4)
    flight = tr.trajectory(model, tr.great_circle_profile(
        np.radians(50.0), np.radians(30.0), np.radians(60.0), 250.0, 10_000.0), 600.0, 10.0,
        p=p)
    phi = convention(model, "phi")
    T = np.moveaxis(phi.transform(flight.truth, p), -1, 0)
    rows = [phi.names.index(n) for n in ("dr_N", "dr_E")]
    functionals = cv.Functionals(("dr_N", "dr_E"), ("m", "m"), T[:, rows],
                                 np.zeros((2, len(model.sources))))
    result = cv.propagate(cv.system_from_trajectory(model, flight),
                          [cv.SourceStatistics("gyro_bias_x", "constant",
                                               np.radians(1.0) / 3600.0)], functionals)
    assert budget_r == pytest.approx(list(result.std[-1]), rel=1e-6)
