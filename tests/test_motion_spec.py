"""How motions from a description (CLI, scenario, spec) are named."""


def test_the_standard_manoeuvre_is_described_by_its_pattern_not_its_leg_count():
    # its legs cover a day whatever the run's length: "120 legs" on a 1-h run misled
    from ins_errors.numeric.motion_spec import STANDARD_MANOEUVRE, default_legs, motion_profile
    from ins_errors.numeric.trajectories import manoeuvre_profile

    text = motion_profile({"kind": "manoeuvre"}).description
    assert text.startswith(STANDARD_MANOEUVRE) and "legs" not in text
    own = manoeuvre_profile(0.8, 0.5, 0.0, 200.0, default_legs(200.0, 0.0, hours=1))
    assert own.description.startswith("manoeuvring flight of 5 legs")


def test_a_manoeuvre_is_described_with_its_speed_height_and_track(capsys):
    # a sizing probe's UAV at 50 m/s and 3 km read "standard manoeuvre (...) from φ=45°,
    # λ=10°": a great circle's line gives them, a manoeuvre's gave none; and its 10 min
    # read "0.166667 h"
    from ins_errors.cli import main

    assert main(["compare", "strapdown_ned", "--motion", "manoeuvre", "--speed", "50m/s",
                 "--height", "3000m", "--heading", "90deg", "--latitude", "45deg",
                 "--longitude", "10deg", "--duration", "10min", "-s",
                 "gyro_bias_x=0.01deg/h"]) == 0
    title = capsys.readouterr().out.splitlines()[0]
    assert "from φ=45°, λ=10°, track 90°, 50 m/s, h=3000 m; 10 min, τ = 1 s" in title, title


def test_a_run_length_is_written_exactly_in_hours_minutes_or_seconds():
    from ins_errors.units import format_duration

    assert [format_duration(s) for s in (600.0, 5400.0, 86400.0, 604800.0, 1000.0, 90.0,
                                         36.0, 3600.0, 0.5)] == [
        "10 min", "1 h 30 min", "24 h", "168 h", "1000 s", "90 s", "36 s", "1 h", "0.5 s"]


def test_the_standard_manoeuvre_says_its_first_turn_is_to_the_left():
    # its "90° turn" turned heading 90° to ~0° (roll negative): a left turn, unsaid
    import numpy as np

    from ins_errors.numeric.motion_spec import STANDARD_MANOEUVRE, default_legs
    from ins_errors.numeric.trajectories import manoeuvre_profile

    profile = manoeuvre_profile(0.8, 0.5, 0.0, 200.0, default_legs(200.0, 0.0, hours=1))
    (v_xi, v_eta, _, _), _ = profile.commands(np.array([0.0, 600.0]))
    # track frame: v_η is to the left of ξ; after the first leg all of the speed is there
    assert v_xi[0] > 199.0 and abs(v_xi[1]) < 1e-6 and v_eta[1] > 199.0
    assert "90° left turn" in STANDARD_MANOEUVRE and "45° right turns" in STANDARD_MANOEUVRE
