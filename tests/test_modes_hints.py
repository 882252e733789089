"""Notes under the modes table for model-file slips an ENU researcher made and the
table alone did not explain:

* gravity with the wrong sign in the velocity equation: no Schuler row, a real root
  +√(g/R) (e-folding 13.4 min) instead of the pair ±i√(g/R);
* the Earth's rate written in deg/h as rad/s (15.041): Ω is 206 265 times the Earth's;
* the Earth period (23.93 h) is the sidereal day, which a student takes for 24 h;
* a growing term whose e-folding time is centuries is said to be unseen in any run.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import main
from tests.helpers import edited_model_file

ROOT = Path(__file__).resolve().parents[1]
LOOP = ROOT / "examples" / "own_model" / "schuler_loop.py"


@pytest.fixture(scope="module")
def flipped(tmp_path_factory) -> Path:
    """The tutorial's Schuler loop with gravity of the wrong sign in its accelerometer."""
    return edited_model_file(LOOP, tmp_path_factory.mktemp("model"),
                             "a_N * sp.cos(psi) - g * sp.sin(psi) + bias",
                             "a_N * sp.cos(psi) + g * sp.sin(psi) + bias", "schuler_gsign")


def _modes(capsys, *args) -> str:
    assert main(["modes", *map(str, args)]) == 0
    return capsys.readouterr().out


def test_gravity_of_the_wrong_sign_is_named(flipped, capsys):
    out = _modes(capsys, flipped)
    (line,) = [x for x in out.splitlines() if x.startswith("no Schuler row, but")]
    rate = np.sqrt(9.80665 / 6_371_000.0)            # √(g/R) of the file's parameters
    assert f"{rate:.4e} 1/s" in line and "wrong sign" in line
    assert "no Schuler row" not in _modes(capsys, LOOP)


def test_an_earth_rate_in_deg_per_hour_given_as_rad_per_second_is_named(capsys):
    out = _modes(capsys, "north_pointing", "-p", "U=15.041rad/s")
    (line,) = [x for x in out.splitlines() if "times the Earth's rate" in x]
    assert f"{15.041 / 7.292115e-5:.4g} times" in line and "deg/h" in line
    assert "times the Earth's rate" not in _modes(capsys, "north_pointing")


def test_the_earth_period_is_called_the_sidereal_day(capsys):
    assert "the sidereal day, 23.93 h" in _modes(capsys, "north_pointing")


def test_a_growth_over_centuries_is_said_to_be_unseen(flipped, capsys):
    # g = 1e-13 m/s²: √(g/R) = 1.25e-10 1/s, an e-folding time of 253 years
    assert main(["transfer", str(flipped), "-s", "accel_bias", "--output", "latitude",
                 "-p", "g=1e-13m/s**2"]) == 0
    (line,) = [x for x in capsys.readouterr().out.splitlines() if x.startswith("long run")]
    years = 1 / np.sqrt(1e-13 / 6_371_000.0) / (365.25 * 86400)
    assert f"an e-folding time of {years:.2g} years: no run sees it grow" in line
    assert main(["transfer", str(flipped), "-s", "accel_bias", "--output", "latitude"]) == 0
    assert "no run sees it grow" not in capsys.readouterr().out
