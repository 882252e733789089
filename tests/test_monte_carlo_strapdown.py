"""``budget --monte-carlo`` on the attitude items of a strapdown INS and of a platform.

The covariance reads a strapdown INS's vertical_error and heading_drift from its φ-angle,
``φ = T_φ(x) δx`` along the ideal states; the direct runs read the same rows along their
own ideal states at their record times, applied to real − ideal. The two are then
independent estimates of one quantity: the sample 2σ of N draws has the relative
standard error 1/√(2N) the report states (less for a root sum of two squares), so each
row's Monte Carlo value lies within twice that of the covariance's (N = 2000: 1.6 %, a
band of 3.2 %; the rows of one set of draws move together, and seed 0 puts strapdown_ned
within 0.9 % and orthodromic within 2.7 %; 8000 draws bring both within 0.7 %). A
platform model reads its platform angles as before.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.analysis import budget as bd
from ins_errors.analysis import budget_attitude as ba
from ins_errors.analysis.monte_carlo import direct_monte_carlo
from ins_errors.cli import main

SPEC = """
title = "attitude of a strapdown INS, Monte Carlo check"
sigma_level = 2
operating_time = "20 min"
step = "60 s"
[motion]
kind = "great-circle"
latitude = "50 deg"
longitude = "30 deg"
heading = "60 deg"
speed = "250 m/s"
height = "10 km"
[items.vertical_error]
value = "0.1 deg"
every = "5 min"
from = "0 h"
[items.heading_drift]
value = "0.1 deg/h"
times = ["10 min", "20 min"]
"""

FIXED = {"initial_roll_error": "20 arcsec", "initial_pitch_error": "20 arcsec",
         "initial_heading_error": "2 arcmin", "gyro_bias_x": "0.01 deg/h",
         "gyro_bias_y": "0.01 deg/h", "gyro_bias_z": "0.01 deg/h",
         "accel_bias_x": "50 ug", "accel_bias_y": "50 ug"}
"""A navigation-grade INS's initial attitude errors, gyro and level accelerometer biases
(strapdown_ned's names); every other source is left out."""

PLATFORM_FIXED = {"initial_azimuth_error": "2 arcmin", "gyro_drift_x": "0.01 deg/h",
                  "gyro_drift_y": "0.01 deg/h", "gyro_drift_z": "0.01 deg/h",
                  "accel_bias_x": "50 ug", "accel_bias_y": "50 ug"}
"""The same for orthodromic (no initial tilts among its sources)."""


def _spec(tmp_path, model, fixed: dict[str, str]) -> str:
    text = SPEC
    for source in model.sources:
        text += (f'\n[sources.{source.name}]\nfixed = "{fixed[source.name]}"\n'
                 if source.name in fixed else f"\n[sources.{source.name}]\ninclude = false\n")
    path = tmp_path / "spec.toml"
    path.write_text(text, encoding="utf-8")
    return str(path)


def _monte_carlo(capsys, model: str, spec: str, runs: int, *options: str) -> dict:
    status = main(["budget", model, "--spec", spec, "--monte-carlo", str(runs),
                   "--mc-duration", "20 min", "--mc-step", "1 s", "--engine", "serial",
                   "--json", *options])
    out = capsys.readouterr().out
    assert status == 0, out
    return json.loads(out)["monte_carlo"]


@pytest.mark.parametrize("name, fixed, options", [
    ("strapdown_ned", FIXED, ("-p", "k_h1=0.0293/s", "-p", "k_h2=4.42e-4/s^2")),
    ("orthodromic", PLATFORM_FIXED, ()),
], ids=["strapdown_ned", "orthodromic"])
def test_monte_carlo_attitude_agrees_with_the_covariance(name, fixed, options, tmp_path,
                                                         capsys):
    spec = _spec(tmp_path, load_model(name), fixed)
    mc = _monte_carlo(capsys, name, spec, 2000, *options)
    rows = {r["row"]: r for r in mc["rows"]}
    assert len([r for r in rows if r.startswith("vertical_error")]) == 5
    assert len([r for r in rows if r.startswith("heading_drift")]) == 2
    for row in rows.values():
        if row["covariance"] == 0:   # orthodromic at t = 0: none of its sources is a tilt
            assert name == "orthodromic" and row["monte_carlo"] == 0.0
            continue
        assert abs(row["ratio"] - 1) <= 2 * mc["relative_sampling_error"], row


def test_strapdown_direct_runs_carry_the_phi_angle(tmp_path):
    """The φ-angle of a direct run is T_φ(x_ideal)(x_real − x_ideal). An initial roll
    error δr alone of a level vehicle turns the computed body frame by δr about its
    forward axis u (NED): C̃_b^n = C_b^n R_x(δr) = (I + [δr u ×]) C_b^n, and with the
    φ-angle's sign C̃_b^n = (I − [φ×]) C_b^n this is φ = −δr u, draw by draw."""
    from ins_errors.analysis.covariance import SourceStatistics
    from ins_errors.specs import load_spec

    model = load_model("strapdown_ned")
    spec = load_spec(_spec(tmp_path, model, FIXED))
    p = model.parameter_vector(k_h1=0.0293, k_h2=4.42e-4)
    trajectory = bd.spec_trajectory(model, spec, tau=1.0, duration=120.0, p=p)
    roll = SourceStatistics("initial_roll_error", "constant", 1e-4)
    errors = direct_monte_carlo(model, trajectory, [roll], 3, engine="serial",
                                record_interval=60.0, progress=False)
    assert errors.names[-3:] == ba.PHI_QUANTITIES
    drawn = errors.sources[[s.name for s in model.sources].index("initial_roll_error")]
    phi_n, phi_e, phi_d = (errors[n][0] for n in ba.PHI_QUANTITIES)
    # the spec's great circle leaves level at track 60°: u = (cos 60°, sin 60°, 0)
    axis = np.radians(60.0)
    assert phi_n == pytest.approx(-drawn * np.cos(axis), rel=1e-6)
    assert phi_e == pytest.approx(-drawn * np.sin(axis), rel=1e-6)
    assert np.max(np.abs(phi_d)) <= 1e-6 * np.max(np.abs(drawn))


def test_platform_direct_runs_are_read_as_before(tmp_path):
    """A platform model's runs report no φ-angle and the rows read α_x, α_y, α_z."""
    from ins_errors.specs import load_spec

    model = load_model("orthodromic")
    spec = load_spec(_spec(tmp_path, model, PLATFORM_FIXED))
    assert ba.attitude_quantities(model) == ba.platform_angles(model)
    sigma = {name: 1.0 for name in PLATFORM_FIXED}
    budget = bd.unit_budget(model, spec)
    trajectory = bd.spec_trajectory(model, spec, tau=1.0, duration=600.0)
    stats = [s for s in budget.statistics(np.array(
        [sigma.get(s.name, 0.0) * 1e-5 for s in budget.sources])) if s.sigma > 0]
    errors = direct_monte_carlo(model, trajectory, stats, 4, engine="serial",
                                record_interval=60.0, progress=False)
    assert not set(ba.PHI_QUANTITIES) & set(errors.names)
    rows, values = bd.direct_rows(model, budget, errors)
    for row, value in zip(rows, values, strict=True):
        k = int(np.argmin(np.abs(errors.times - row.time)))
        if row.item == "vertical_error":
            expected = np.mean(errors["alpha_x"][k] ** 2 + errors["alpha_y"][k] ** 2)
        else:
            expected = np.mean(((errors["alpha_z"][k] - errors["alpha_z"][0]) / row.time) ** 2)
        assert value == 2 * np.sqrt(expected)
