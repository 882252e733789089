"""A value typed as an option is named by the option in its error: ``ins-errors modes
orthodromic --latitude 95deg`` said "motion latitude 95° is at or beyond a pole", the
name of a scenario file's setting the user never wrote; the propagation study said
"experiment: latitude", and the spheroid study ran, ignoring --latitude altogether."""

from __future__ import annotations

import pytest

from ins_errors.cli import main

COMPARE = ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--hours", "0.1"]


def _one_line_error(capsys, argv) -> str:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith("ins-errors: error: "), err
    return err.removeprefix("ins-errors: error: ")


@pytest.mark.parametrize("command", [
    ["modes", "orthodromic"], COMPARE, [*COMPARE, "--motion", "great-circle"],
    ["propagation"], ["propagation", "--orthodromic"],
    ["study", "coriolis", "--hours", "0.1"],
    ["study", "nonsphericity", "--hours", "0.1", "--scenario", "static"],
])
@pytest.mark.parametrize("latitude", ["95deg", "-90deg"])
def test_a_latitude_at_a_pole_is_named_by_its_option(capsys, command, latitude):
    err = _one_line_error(capsys, [*command, "--latitude", latitude])
    assert err.startswith(f"--latitude {latitude[:-3]}° is at or beyond a pole"), err


@pytest.mark.parametrize("command", [["modes", "orthodromic"], COMPARE,
                                     [*COMPARE, "--motion", "great-circle"]])
@pytest.mark.parametrize("option, value, message", [
    ("--longitude", "400deg", "--longitude 400° is outside [-360°, 360°]"),
    ("--heading", "-400deg", "--heading -400° is outside [-360°, 360°]"),
    ("--height", "-7000km", "--height -7000 km is beyond ±100 km"),
    ("--height", "10000km", "--height 10000 km is beyond ±100 km, the heights ins-errors "
                            "accepts, whatever the model (there the height series of "
                            "normal gravity, which the built-in models use, is 3.4e+03 % "
                            "off the inverse-square law"),
    ("--latitude", "45", "--latitude '45' needs a unit"),
])
def test_a_motion_option_is_named_by_itself(capsys, command, option, value, message):
    err = _one_line_error(capsys, [*command, option, value])
    assert err.startswith(message), err
    assert "motion" not in err.split(":")[0]


def test_a_flights_speed_is_named_by_its_option(capsys):
    for command in ([*COMPARE, "--motion", "great-circle"],
                    ["study", "nonsphericity", "--hours", "0.1", "--scenario", "flight"]):
        err = _one_line_error(capsys, [*command, "--speed", "-3m/s"])
        assert err.startswith("--speed must be >= 0 m/s, got -3 m/s"), err


def test_the_spheroid_study_refuses_a_latitude_it_would_ignore(capsys):
    err = _one_line_error(capsys, ["study", "spheroid", "--hours", "0.1", "--latitude",
                                   "10deg"])
    assert err.startswith("--latitude:") and "leave --latitude out" in err


@pytest.mark.parametrize("scenario", ["static", "flight", "both"])
def test_the_spheroid_study_refuses_a_scenario_it_would_ignore(capsys, scenario):
    """The methodological studies' --scenario was taken and ignored by the spheroid
    study, which flies its own grid of flights."""
    err = _one_line_error(capsys, ["study", "spheroid", "--hours", "0.1", "--scenario",
                                   scenario])
    assert err.startswith("--scenario:") and "leave --scenario out" in err


@pytest.mark.parametrize("name", ["coriolis", "nonsphericity"])
def test_a_study_on_a_static_base_refuses_a_speed_it_would_ignore(capsys, name):
    """--speed with --scenario static was taken and ignored (compare refuses a speed on a
    static base); with a flight among the scenarios it is used."""
    err = _one_line_error(capsys, ["study", name, "--hours", "0.1", "--scenario", "static",
                                   "--speed", "100m/s"])
    assert err.startswith("--speed applies to the flight") and "leave --speed out" in err
