"""A file named in an error is named as the user gave it (its folder included), like the
other commands' errors do: ``/dev/null`` read as "null: ..." looked like a file called
null, and "empty.txt: ..." did not say which of several."""

from __future__ import annotations

import os

import pytest

from ins_errors.cli import main


@pytest.mark.skipif(not os.path.exists(os.devnull) or os.devnull != "/dev/null",
                    reason="no /dev/null")
def test_an_empty_hand_file_is_named_by_its_path(tmp_path, monkeypatch, capsys):
    assert main(["check", "orthodromic", "/dev/null"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: /dev/null: no equations to check"), err
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "empty.txt").write_text("# nothing but a comment\n")
    assert main(["check", "orthodromic", "sub/empty.txt"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: sub/empty.txt: no equations to check"), err


def test_a_bad_mapping_file_is_named_by_its_path(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "map.txt").write_text("dot(delta_v_N) = 0\n")
    (tmp_path / "hand.txt").write_text("dot(delta_v_N) = 0\n")
    assert main(["check", "orthodromic", "hand.txt", "--mapping", "sub/map.txt"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: sub/map.txt:"), err
    assert err.count("\n") == 1


SCENARIO = """title = "named"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "1 h"
step = "10 s"
record = "60 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
"""


@pytest.mark.parametrize("command", ["run", "sweep"])
@pytest.mark.parametrize("change, problem", [
    (("[[case]]\ngyro_drift_x = \"0.01 deg/h\"\n", ""), "no [[case]]"),
    (('duration = "1 h"', 'duration = "1 furlong"'), "[run] duration"),
    (('step = "10 s"', 'step = "-10 s"'), "[run] step must be positive"),
    (('record = "60 s"', 'record = "70 s"'), "[run]"),
    (('[run]\n', '[run]\nellipsoid = "wgs85"\n'), "ellipsoid 'wgs85'"),
    (('gyro_drift_x = "0.01 deg/h"', 'gyro_drift_x = "0.01 m"'), "[[case]] 1"),
    (('latitude = "50 deg"', 'latitude = "95 deg"'), "[motion]"),
])
def test_a_scenario_file_is_named_by_its_path(tmp_path, monkeypatch, capsys, command,
                                              change, problem):
    """Every refusal of a scenario file names it as typed (folder and ./ included), not
    by its bare name (the sweep's own refusals already did)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    text = SCENARIO.replace(*change) + ("" if command == "run" else
                                        '[sweep]\ngyro_drift_x = ["0.01 deg/h"]\n')
    assert text != SCENARIO
    (tmp_path / "sub" / "s.toml").write_text(text)
    argv = [command, "./sub/s.toml", "--out" if command == "run" else "--store",
            str(tmp_path / ("out" if command == "run" else "s.zarr"))]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: ./sub/s.toml"), err
    assert problem in err and err.count("\n") == 1, err
    assert not (tmp_path / "s.zarr").exists()


@pytest.mark.parametrize("swept, point", [
    ('latitude = ["30 deg", "90 deg"]', "latitude = 90 deg"),
    ('step = ["10 s", "7 s"]', "step = 7 s"),
])
def test_a_swept_value_a_point_cannot_take_names_the_file_and_point(
        tmp_path, monkeypatch, capsys, swept, point):
    """A pole in a [sweep] latitude list (or a step that does not divide the run) is
    refused before any point runs, naming the file, the table and the point."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "s.toml").write_text(SCENARIO + f"[sweep]\n{swept}\n")
    assert main(["sweep", "sub/s.toml", "--store", "s.zarr", "--engine", "serial"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"ins-errors: error: sub/s.toml [sweep] at the point {point}:"), err
    assert err.count("\n") == 1
    assert not (tmp_path / "s.zarr").exists()


def test_a_bad_spec_entry_is_named_with_the_spec_file(monkeypatch, capsys):
    """A spec's bad value named the key alone ("items.position_error: 3.7 has no unit"),
    not which spec file holds it."""
    from pathlib import Path

    monkeypatch.chdir(Path(__file__).resolve().parent.parent)
    assert main(["budget", "orthodromic", "--spec", "examples/specs/malformed.toml"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: examples/specs/malformed.toml: "
                          "items.position_error: 3.7 has no unit"), err
    assert err.count("\n") == 1


def test_a_bad_spec_parameter_is_named_with_the_spec_file_as_typed(tmp_path, monkeypatch,
                                                                   capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "badp.toml").write_text(
        'sigma_level = 1\noperating_time = "1 h"\nstep = "60 s"\n[motion]\nlatitude = '
        '"50 deg"\n[items.position_error_absolute]\nvalue = "1 km"\n[parameters]\n'
        'bogus = "1 m"\n', encoding="utf-8")
    assert main(["budget", "orthodromic", "--spec", "sub/badp.toml"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: sub/badp.toml [parameters]: unknown parameter"), err
