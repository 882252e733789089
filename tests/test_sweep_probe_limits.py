"""A sweep too large is refused from the sizes its file writes, before any grid value is
built (a count of 10**9 took 22.6 GB and minutes before the point count refused it)."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from ins_errors.analysis import sweep as sw
from ins_errors.cli import main
from ins_errors.scenario import load_scenario

BASE = """title = "limits"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "60 s"
step = "1 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
[sweep]
"""


@pytest.mark.parametrize("grid, factors", [
    ('latitude = { start = "0 deg", stop = "80 deg", count = 1000000000000 }\n',
     "1,000,000,000,000 points (1,000,000,000,000 latitude)"),
    ('heading = { start = "0 deg", stop = "90 deg", count = 1000 }\n'
     'latitude = { start = "0 deg", stop = "80 deg", count = 1000 }\n',
     "1,000,000 points (1,000 heading × 1,000 latitude)"),
    ('latitude = ["10 deg", "20 deg"]\ndraws = 1000000000000\n'
     '[sweep.random]\naccel_bias_x = "1 ug"\n',
     "2,000,000,000,000 points (2 latitude × 1,000,000,000,000 draws)"),
])
def test_a_huge_grid_is_refused_before_any_axis_is_built(tmp_path, grid, factors):
    small = tmp_path / "small.toml"
    small.write_text(BASE + 'latitude = ["10 deg"]\n', encoding="utf-8")
    load_scenario(small)  # the model and the units loaded: not counted below
    path = tmp_path / "huge.toml"
    path.write_text(BASE + grid, encoding="utf-8")
    tracemalloc.start()
    try:
        with pytest.raises(sw.SweepError) as refused:
            load_scenario(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert f"the sweep has {factors}, more than the 100,000 a sweep may have" in str(
        refused.value)
    assert "[sweep]" in str(refused.value)
    assert peak < 5e6, peak  # nothing of the axis' size (the list would be 8 TB)


def test_a_long_list_is_refused_before_its_values_are_read(tmp_path, capsys,
                                                          monkeypatch):
    values = ", ".join(f'"{k * 1e-6:.6f} deg"' for k in range(100_001))
    path = tmp_path / "list.toml"
    path.write_text(BASE + f"latitude = [{values}]\n", encoding="utf-8")
    read: list = []
    real = sw._value
    monkeypatch.setattr(sw, "_value", lambda *a: read.append(a) or real(*a))
    assert main(["sweep", str(path), "--store", str(tmp_path / "x.zarr")]) == 2
    err = capsys.readouterr().err
    assert "the sweep has 100,001 points (100,001 latitude)" in err
    assert err.count("\n") == 1 and read == []


@pytest.mark.parametrize("grid, named", [
    ('latitude = ["45 deg", "2700 arcmin"]\n',
     "'45 deg' and '2700 arcmin' are the same value (within 1e-12, relative)"),
    ('gyro_drift_x = ["0.01 deg/h", "0.02 deg/h", "36 arcsec/h"]\n',
     "'0.01 deg/h' and '36 arcsec/h' are the same value"),
    ('latitude = ["45 deg", "30 deg", "45 deg"]\n', "'45 deg' is listed twice"),
    ('latitude = { start = "10 deg", stop = "600 arcmin", count = 3 }\n',
     "start '10 deg' and stop '600 arcmin' are the same value"),
])
def test_grid_values_equal_within_rounding_are_refused_naming_both(tmp_path, grid,
                                                                   named):
    """Was: 45 deg and 2700 arcmin (one unit in the last place apart in radians) ran as
    two points, the table showing identical rows."""
    path = tmp_path / "dup.toml"
    path.write_text(BASE + grid, encoding="utf-8")
    with pytest.raises(sw.SweepError, match=r"same value|listed twice") as refused:
        load_scenario(path)
    assert named in str(refused.value) and "[sweep]" in str(refused.value)


def test_a_range_of_one_point_with_another_stop_is_refused(tmp_path, capsys):
    """count = 1 runs start alone: a stop other than it was dropped without a word (the
    sweep ran heading 0 only); with start == stop it is one value written as a range."""
    path = tmp_path / "one.toml"
    path.write_text(BASE + 'heading = { start = "0 deg", stop = "90 deg", count = 1 }\n',
                    encoding="utf-8")
    assert main(["sweep", str(path), "--store", str(tmp_path / "x.zarr")]) == 2
    err = capsys.readouterr().err
    assert err == (f"ins-errors: error: {path} [sweep] heading: a range of one point "
                   "(count = 1) has no stop: '90 deg' would never run; write the value alone "
                   "(heading = ['0 deg']) or count = 2 or more\n")
    assert not (tmp_path / "x.zarr").exists()
    path.write_text(BASE + 'heading = { start = "5 deg", stop = "300 arcmin", count = 1 }\n',
                    encoding="utf-8")
    [heading] = load_scenario(path).sweep.parameters
    assert heading.values == pytest.approx((np.radians(5),), rel=1e-15)


def test_an_extension_takes_the_stored_value_for_one_within_rounding(tmp_path, capsys):
    """A store of latitude 45 deg extended by a grid writing 2700 arcmin reuses the
    stored point (was: computed again as a point of its own beside it)."""
    import json

    from ins_errors.units import parse_quantity

    store = str(tmp_path / "s.zarr")
    first = tmp_path / "first.toml"
    first.write_text(BASE.replace('"60 s"', '"60 s"\nrecord = "60 s"')
                     + 'latitude = ["45 deg"]\n', encoding="utf-8")
    assert main(["sweep", str(first), "--store", store, "--engine", "serial",
                 "--no-progress", "--json"]) == 0
    stored = json.loads(capsys.readouterr().out)["summary"][0]
    second = tmp_path / "second.toml"
    second.write_text(BASE.replace('"60 s"', '"60 s"\nrecord = "60 s"')
                      + 'latitude = ["2700 arcmin", "30 deg"]\n', encoding="utf-8")
    assert parse_quantity("2700 arcmin", "rad") != parse_quantity("45 deg", "rad")
    assert main(["sweep", str(second), "--store", store, "--engine", "serial",
                 "--no-progress", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["computed"], out["reused"], out["store_others"]) == (1, 1, 0)
    again = out["summary"][0]
    assert again["latitude"] == stored["latitude"] == parse_quantity("45 deg", "rad")
    assert again["max_direct"] == stored["max_direct"]
