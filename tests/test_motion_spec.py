"""How motions from a description (CLI, scenario, spec) are named."""


def test_the_standard_manoeuvre_is_described_by_its_pattern_not_its_leg_count():
    # its legs cover a day whatever the run's length: "120 legs" on a 1-h run misled
    from ins_errors.numeric.motion_spec import STANDARD_MANOEUVRE, default_legs, motion_profile
    from ins_errors.numeric.trajectories import manoeuvre_profile

    text = motion_profile({"kind": "manoeuvre"}).description
    assert text.startswith(STANDARD_MANOEUVRE) and "legs" not in text
    own = manoeuvre_profile(0.8, 0.5, 0.0, 200.0, default_legs(200.0, 0.0, hours=1))
    assert own.description.startswith("manoeuvring flight of 5 legs")
