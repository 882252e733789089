"""What a budget tells an engineer: a grid too large refused up front, and hints that
fit a budget spec."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from ins_errors.analysis import budget as bd
from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent

FLIGHT = """
    title = "two hours on a great circle"
    sigma_level = 2
    operating_time = "2 h"
    step = "60 s"
    [motion]
    kind = "great_circle"
    latitude = "50 deg"
    longitude = "30 deg"
    heading = "45 deg"
    height = "10 km"
    speed = "250 m/s"
    [items.position_error]
    value = "1.85 km/h"
    times = ["1 h", "2 h"]
    [items.ground_speed_error]
    value = "0.8 m/s"
    every = "30 min"
    [items.vertical_error]
    value = "30 arcsec"
    every = "30 min"
    [items.heading_drift]
    value = "0.02 deg/h"
    times = ["2 h"]
    [sources.gyro_drift_z]
    fixed = "0.008 deg/h"
"""


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


# ------------------------------------------------------------------------------------
# 2. A grid too large at rest is refused before any work
# ------------------------------------------------------------------------------------
def test_a_static_grid_too_large_is_refused_up_front(tmp_path, capsys, monkeypatch):
    """A month at 0.01 s at rest ran 33 s to 8 GB and died in numpy (exit 1, a
    traceback); a moving base was refused by a memory check. The same check now refuses
    the static base, in one line, before its motion is built."""
    from ins_errors.analysis import covariance
    from ins_errors.numeric import linear_system, trajectories

    spec = write(tmp_path, """
        sigma_level = 2
        operating_time = "30 d"
        step = "0.01 s"
        [motion]
        kind = "static"
        latitude = "50 deg"
        [items.position_error]
        value = "3.7 km/h"
        every = "1 h"
    """)
    monkeypatch.setattr(linear_system, "physical_memory", lambda: 16e9)
    for module, name in ((trajectories, "trajectory"), (bd, "static_system"),
                         (covariance, "static_system")):
        monkeypatch.setattr(module, name, lambda *a, **k: pytest.fail("built"))
    assert main(["budget", "orthodromic", "--spec", str(spec)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"at {30 * 86400 * 100 + 1:,} grid times need about" in err
    assert "choose a step of at least" in err


# ------------------------------------------------------------------------------------
# 4. Hints that fit a budget spec
# ------------------------------------------------------------------------------------
def test_a_model_with_none_of_the_items_is_not_told_to_remove_them(capsys):
    """The Schuler loop was told to copy the spec without every one of its item tables,
    which leaves a spec that is refused; now it is told that none of the items fits."""
    assert main(["budget", str(ROOT / "examples" / "own_model" / "schuler_loop.py")]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "without its" not in line and "leave them out" not in line
    assert "all the items of the built-in 802m spec" in line
    assert "a spec needs at least one item its model can check" in line
    assert "cannot be budgeted" in line


def test_a_model_that_cannot_fly_the_spec_motion_is_told_the_spec_way_out(tmp_path,
                                                                          capsys):
    """A budget spec has no motion file: the hint names the static base in the spec."""
    spec = write(tmp_path, FLIGHT.replace("gyro_drift_z", "gyro_drift_up"), "np.toml")
    assert main(["budget", "north_pointing", "--spec", str(spec)]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "motion file of" not in line and "has no motion file" in line
    assert 'set kind = "static" in np.toml\'s [motion]' in line
    assert line.endswith("leave out its heading and speed")
    # the way out works
    fixed = write(tmp_path, FLIGHT.replace("gyro_drift_z", "gyro_drift_up")
                  .replace('"great_circle"', '"static"').replace('heading = "45 deg"', "")
                  .replace('speed = "250 m/s"', ""), "np_static.toml")
    assert main(["budget", "north_pointing", "--spec", str(fixed)]) == 0
    capsys.readouterr()
