"""A motion kind is spelled the same way everywhere it is named: scenario files, budget
spec files and every ``--motion`` option take the kinds and their aliases of one table
(:data:`~ins_errors.numeric.motion_spec.MOTION_ALIASES`), and a near miss, the US
spelling ``maneuver`` included, is refused in one line naming the kind it is close to."""

from __future__ import annotations

import textwrap

import pytest

from ins_errors.cli import build_parser, main
from ins_errors.errors import UnknownNameError
from ins_errors.numeric.motion_spec import MOTION_ALIASES, MOTION_KINDS, motion_profile
from ins_errors.specs import parse_spec

SPELLINGS = [(written, kind) for written, kind in
             [*((k, k) for k in MOTION_KINDS), *MOTION_ALIASES.items()] if kind != "file"]
"""Every way of writing a planned motion (not a motion file), and the kind it names."""

OPTIONS = [["compare", "orthodromic"], ["validity", "orthodromic", "--source", "gyro_drift_x"],
           ["matrices", "strapdown_ned", "--out", "m.npz"]]
"""The commands with a --motion option (matrices calls its great circle 'cruise')."""


def _spec(kind: str) -> dict:
    return {"operating_time": "1 h", "motion": {"kind": kind, "speed": "250 m/s"},
            "items": {"position_error_absolute": {"value": "5 km"}}}


@pytest.mark.parametrize("written, kind", SPELLINGS)
def test_every_spelling_is_read_alike_in_files_and_options(written, kind):
    """great_circle was taken by scenario and spec files and refused by --motion."""
    motion = motion_profile({"kind": written, "latitude": "40 deg", "heading": "30 deg"})
    same = motion_profile({"kind": kind, "latitude": "40 deg", "heading": "30 deg"})
    assert motion.description == same.description
    assert parse_spec(_spec(written)).motion.kind == kind.replace("-", "_")
    parser = build_parser()
    for command in OPTIONS[:2]:
        assert parser.parse_args([*command, "--motion", written]).motion in (kind, [kind])


@pytest.mark.parametrize("command", OPTIONS, ids=[c[0] for c in OPTIONS])
@pytest.mark.parametrize("written, close", [("maneuver", "manoeuvre"),
                                            ("manouevre", "manoeuvre"),
                                            ("statc", "static")])
def test_a_near_miss_of_motion_names_the_kind_it_is_close_to(command, written, close,
                                                             capsys):
    """--motion maneuver was refused with argparse's list of choices alone."""
    with pytest.raises(SystemExit) as stop:  # an argparse usage error
        main([*command, "--motion", written])
    assert stop.value.code == 2
    out, err = capsys.readouterr()
    assert not out and err.count("\n") == 1
    assert f"unknown motion kind {written!r}; did you mean {close!r}" in err


def test_files_suggest_the_same_kind(tmp_path):
    scenario = tmp_path / "s.toml"
    scenario.write_text(textwrap.dedent("""
        model = "orthodromic"
        [motion]
        kind = "maneuver"
        [run]
        duration = "1 h"
        [[case]]
        gyro_drift_x = "0.01 deg/h"
    """))
    from ins_errors.scenario import load_scenario

    for read in (lambda: load_scenario(scenario), lambda: parse_spec(_spec("maneuver"))):
        with pytest.raises(UnknownNameError, match="did you mean 'manoeuvre'"):
            read()
