"""`ins-errors validity --latitude ...`: the map of a static base where the user's INS
is, not only at the default 50°.

The linear model of a north-pointing platform misses an initial azimuth error's
second-order terms through the Earth rate's horizontal component Ω cos φ, so where the
linear residual reaches 1 % depends strongly on the latitude. The check is independent
of the map's fit: a `compare` run at the 1 % magnitude the map gives, at the same
latitude, must show a linear residual of 1 % of the error.
"""

from __future__ import annotations

import json

import pytest

from ins_errors.cli import main

COMMON = ["north_pointing", "-s", "initial_azimuth_error", "--motion", "static",
          "--hours", "4", "--engine", "serial", "--no-progress", "--json"]


def _one_percent(latitude: str, capsys) -> float:
    assert main(["validity", *COMMON, "--latitude", latitude]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["start"] == {"latitude": latitude}
    return payload["sources"][0]["magnitude_1pct"]


@pytest.mark.parametrize("latitude", ["20deg", "-70deg"])
def test_the_one_percent_magnitude_holds_at_the_latitude_given(latitude, capsys):
    magnitude = _one_percent(latitude, capsys)
    assert main(["compare", "north_pointing", "--latitude", latitude, "--hours", "4",
                 "--step", "2s", "-s", f"initial_azimuth_error={magnitude!r}rad",
                 "--json"]) == 0
    ratio = json.loads(capsys.readouterr().out)["cases"][0]["worst_linear_ratio"]
    assert ratio == pytest.approx(0.01, rel=0.1)


def test_the_start_is_written_as_the_runs_describe_it(capsys):
    assert main(["validity", *[a for a in COMMON if a != "--json"], "--latitude", "-70deg",
                 "--hours", "1"]) == 0
    assert "1 h runs, τ = 2 s, RK4, φ=-70°)" in capsys.readouterr().out


def test_the_latitude_moves_the_map(capsys):
    # (the map at the default 50° is neither of these)
    low, high = _one_percent("20deg", capsys), _one_percent("70deg", capsys)
    assert high / low > 2


@pytest.mark.parametrize(("args", "said"), [
    (["--latitude", "90deg"], "--latitude 90° is at or beyond a pole"),
    (["--latitude", "nan deg"], "--latitude"),
    (["--speed", "100m/s"], "--speed applies to the moving motions"),
])
def test_bad_start_options_are_one_line(args, said, capsys):
    assert main(["validity", *COMMON, *args]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert said in line, line
