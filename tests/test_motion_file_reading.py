"""Motion files as flight-test logs come: columns the reader does not read, units in the
header, gaps, repeated or unordered times, a clock that does not start at 0, no duration
given, a height beside a file's own h column."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.numeric.motion_spec import in_si, motion_profile, read_motion_file
from ins_errors.scenario import load_scenario

LAT, LON = np.radians(50.0), np.radians(30.0)


def _log(path, t, columns, header):
    """A CSV log: a header row and one row per time."""
    np.savetxt(path, np.column_stack([t, *columns]), delimiter=",", header=header,
               comments="", fmt="%.6f")
    return path


def _circling(t):
    """A slow circle at 200 m/s: (v_N, v_E), m/s."""
    return 200.0 * np.cos(t / 900.0), 200.0 * np.sin(t / 900.0)


def _compare(capsys, *args):
    status = main(["compare", "orthodromic", "-s", "gyro_drift_y=0.01deg/h", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_columns_the_reader_does_not_read_are_refused(capsys, tmp_path):
    t = np.arange(0.0, 400.0, 10.0)
    v_n, v_e = _circling(t)
    # a log with its position: it ran from the default 50°, 30°, not from 35°, -120°
    latlon = _log(tmp_path / "latlon.csv", t, [35 + 0 * t, -120 + 0 * t, v_n, v_e],
                  "t,lat,lon,v_N,v_E")
    status, _out, err = _compare(capsys, "--motion-file", str(latlon), "--hours", "0.1")
    assert status == 2 and len(err.strip().splitlines()) == 1
    assert "column(s) lat, lon are not read" in err
    assert "t (s), v_N, v_E (m/s) and optionally h (m)" in err and "--latitude" in err
    # a height named alt was dropped: the flight stayed at h = 0
    alt = _log(tmp_path / "alt.csv", t, [v_n, v_e, 1500 + 0 * t], "t,v_N,v_E,alt")
    with pytest.raises(InsErrorsError, match=r"column\(s\) alt are not read.*must be named h"):
        read_motion_file(alt, LAT, LON, 0.0, 0.0)
    # units in the header: bare names, SI values
    units = _log(tmp_path / "units.csv", t, [v_n, v_e], "t [s],v_N [m/s],v_E [m/s]")
    with pytest.raises(InsErrorsError, match=r"bare names with the values in SI.*'t', not "
                                             r"'t \[s\]'"):
        read_motion_file(units, LAT, LON, 0.0, 0.0)
    knots = _log(tmp_path / "knots.csv", t, [v_n, v_e], "t,v_N_kn,v_E_kn")
    with pytest.raises(InsErrorsError, match=r"lacks column.*SI.*'v_N', not 'v_N_kn'"):
        read_motion_file(knots, LAT, LON, 0.0, 0.0)
    twice = _log(tmp_path / "twice.csv", t, [v_n, v_e, v_e], "t,v_N,v_E,v_E")
    with pytest.raises(InsErrorsError, match="v_E appear more than once"):
        read_motion_file(twice, LAT, LON, 0.0, 0.0)
    # the columns in another order read as named
    reordered = _log(tmp_path / "reordered.csv", t, [1000 + 0 * t, v_e, v_n], "t,h,v_E,v_N")
    plain = _log(tmp_path / "plain.csv", t, [v_n, v_e, 1000 + 0 * t], "t,v_N,v_E,h")
    a = read_motion_file(reordered, LAT, LON, 0.0, 0.0).commands(np.array([123.4]))
    b = read_motion_file(plain, LAT, LON, 0.0, 0.0).commands(np.array([123.4]))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_a_gap_in_the_samples_is_noted(capsys, tmp_path):
    t = np.round(np.arange(0.0, 1200.0, 0.1), 1)
    kept = (t < 700.0) | (t > 720.0)  # a 20-s GPS dropout in a 10-Hz log
    v_n, v_e = _circling(t[kept])
    gap = _log(tmp_path / "gap.csv", t[kept], [v_n, v_e], "t,v_N,v_E")
    with pytest.warns(RuntimeWarning, match=r"ins-errors: note: motion file '.*gap.csv' has "
                                            r"no samples for 20.2 s, from t = 699.9 s to "
                                            r"720.1 s \(its samples are usually 0.1 s apart"):
        read_motion_file(gap, LAT, LON, 0.0, 0.0)
    status, out, err = _compare(capsys, "--motion-file", str(gap), "--duration", "600s",
                                "--step", "10s", "--json")
    assert status == 0 and json.loads(out)["duration_s"] == 600.0
    (line,) = err.strip().splitlines()  # one line, without Python's warning format
    assert line.startswith("ins-errors: note: motion file") and "20.2 s" in line
    v_n, v_e = _circling(t)
    whole = _log(tmp_path / "whole.csv", t, [v_n, v_e], "t,v_N,v_E")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_motion_file(whole, LAT, LON, 0.0, 0.0)  # no gap: no note


def test_repeated_and_unordered_times_name_their_line(tmp_path):
    t = np.arange(0.0, 100.0, 1.0)
    v_n, v_e = _circling(t)
    rows = np.column_stack([t, v_n, v_e])
    dup = np.insert(rows, 50, rows[49], axis=0)  # sample 50 (t = 49 s) twice
    path = tmp_path / "dup.csv"
    np.savetxt(path, dup, delimiter=",", header="# a log\nt,v_N,v_E", comments="", fmt="%g")
    # line 1 the comment, 2 the header, sample k on line k + 2
    with pytest.raises(InsErrorsError, match=r"dup.csv': t = 49 s repeats at line 53 \(line "
                                             r"52 has it\); the times must increase"):
        read_motion_file(path, LAT, LON, 0.0, 0.0)
    swapped = rows.copy()
    swapped[[60, 61]] = swapped[[61, 60]]
    path = tmp_path / "swapped.csv"
    np.savetxt(path, swapped, delimiter=",", header="t,v_N,v_E", comments="", fmt="%g")
    with pytest.raises(InsErrorsError, match=r"t goes back from 61 s \(line 62\) to 60 s at "
                                             "line 63"):
        read_motion_file(path, LAT, LON, 0.0, 0.0)


def test_times_must_start_at_zero(capsys, tmp_path):
    t = np.arange(0.0, 400.0, 10.0)
    v_n, v_e = _circling(t)
    late = _log(tmp_path / "late.csv", t + 1000.0, [v_n, v_e], "t,v_N,v_E")
    status, _out, err = _compare(capsys, "--motion-file", str(late), "--duration", "300s",
                                 "--step", "10s")
    assert status == 2 and len(err.strip().splitlines()) == 1
    assert "its times start at 1000 s" in err and "subtract 1000 s" in err
    # before 0 as well: the run started mid-file at t = 0, the first 5 s of the log
    # dropped in silence and the start position applied there, not at the first sample
    early = _log(tmp_path / "early.csv", t - 5.0, [v_n, v_e], "t,v_N,v_E")
    status, _out, err = _compare(capsys, "--motion-file", str(early), "--duration", "300s",
                                 "--step", "10s")
    assert status == 2 and "its times start at -5 s" in err and "add 5 s" in err, err


def test_the_run_lasts_the_file_without_a_duration(capsys, tmp_path):
    t = np.arange(0.0, 2395.0, 5.0)  # 2390 s: not a whole number of 60-s records
    v_n, v_e = _circling(t)
    path = _log(tmp_path / "m.csv", t, [v_n, v_e], "t,v_N,v_E")
    status, out, err = _compare(capsys, "--motion-file", str(path), "--step", "10s", "--json")
    assert status == 0, err
    report = json.loads(out)
    assert report["duration_s"] == 2390.0 and 2390.0 % report["record_s"] == 0
    assert report["cases"][0]["worst_linear_ratio"] <= 0.01
    # the last sample between two steps: the whole steps within the file
    status, out, err = _compare(capsys, "--motion-file", str(path), "--step", "60s", "--json")
    assert status == 0 and json.loads(out)["duration_s"] == 2340.0, err
    # a scenario without [run] duration likewise
    scenario = tmp_path / "s.toml"
    scenario.write_text('model = "orthodromic"\n[motion]\nkind = "file"\nfile = "m.csv"\n'
                        '[run]\nstep = "10 s"\n[[case]]\ngyro_drift_y = "0.01 deg/h"\n')
    parsed = load_scenario(scenario)
    assert parsed.duration == 2390.0 and 2390.0 % parsed.record == 0
    scenario.write_text(scenario.read_text().replace('[run]\n', '[run]\nduration = "1 h"\n'))
    assert load_scenario(scenario).duration == 3600.0  # given: kept (and refused later)


def test_a_height_beside_the_files_own_h_is_refused(capsys, tmp_path):
    t = np.arange(0.0, 400.0, 10.0)
    v_n, v_e = _circling(t)
    with_h = _log(tmp_path / "h.csv", t, [v_n, v_e, 1000 + 0 * t], "t,v_N,v_E,h")
    status, _out, err = _compare(capsys, "--motion-file", str(with_h), "--height", "500m",
                                 "--duration", "300s", "--step", "10s")
    assert status == 2 and err.startswith("ins-errors: error: --height: motion file")
    assert "own column h" in err and len(err.strip().splitlines()) == 1
    scenario = tmp_path / "s.toml"
    scenario.write_text('model = "orthodromic"\n[motion]\nkind = "file"\nfile = "h.csv"\n'
                        'height = "500 m"\n[run]\nduration = "300 s"\nstep = "10 s"\n'
                        '[[case]]\ngyro_drift_y = "0.01 deg/h"\n')
    with pytest.raises(InsErrorsError, match=r"s.toml \[motion\]: motion height: .*own "
                                             "column h"):
        load_scenario(scenario)
    # a file without h takes the height given
    no_h = _log(tmp_path / "no_h.csv", t, [v_n, v_e], "t,v_N,v_E")
    profile = motion_profile({"kind": "file", "file": str(no_h), "height": "500 m"})
    assert profile.commands(np.array([100.0]))[0][2, 0] == 500.0
    # the SI form a sweep's workers read states no height it was not given
    description = {"kind": "file", "file": str(with_h)}
    assert "height" not in in_si(description)
    a, b = motion_profile(in_si(description)), motion_profile(description)
    assert np.array_equal(a.commands(t)[0], b.commands(t)[0])


def test_a_record_that_does_not_divide_the_files_length_says_where_the_length_came_from(
        capsys, tmp_path):
    """No duration was given, so 'the run of 1000 steps' named a length the user never
    typed: the message says it is the file's."""
    t = np.arange(0.0, 1000.6, 0.5)
    v_n, v_e = _circling(t)
    path = _log(tmp_path / "m.csv", t, [v_n, v_e], "t,v_N,v_E")
    status, _out, err = _compare(capsys, "--motion-file", str(path), "--record", "60s")
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert "not a whole number of recording intervals" in err
    assert "the motion file's length, 1000 s" in err and "no --hours or --duration" in err


@pytest.mark.parametrize("header, rows, said", [
    ("t,v_N,v_E,", ["0,1,2,", "1,1,2,", "2,1,2,", "3,1,2,"],
     "empty column name (column 4; a comma too many?)"),
    ("t;v_N;v_E", ["0;1;2", "1;1;2", "2;1;2", "3;1;2"],
     "is one column: columns are separated by commas"),
])
def test_a_header_of_another_shape_is_named_as_that(capsys, tmp_path, header, rows, said):
    """A trailing comma gave "column , sample 1 (line 2) is empty" and a semicolon
    header "... is not a number"."""
    path = tmp_path / "m.csv"
    path.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    status, _out, err = _compare(capsys, "--motion-file", str(path))
    assert status == 2 and len(err.strip().splitlines()) == 1 and said in err, err


@pytest.mark.parametrize("column", ["t", "v_N", "v_E", "h"])
@pytest.mark.parametrize("bad", ["nan", "inf", "-1e999"])
def test_a_value_that_is_not_finite_names_the_file_column_and_line(tmp_path, column, bad):
    """NaN or infinity in any column (not only t) is named by the file, the column and
    the file's line, as the reader counts them (comments and blank lines included)."""
    t = np.arange(0.0, 60.0, 1.0)
    v_n, v_e = _circling(t)
    cells = np.column_stack([t, v_n, v_e, np.full(t.size, 100.0)]).astype(str)
    k = 37  # the sample made bad: after a comment line, the header and a blank line
    cells[k, ["t", "v_N", "v_E", "h"].index(column)] = bad
    path = tmp_path / "log.csv"
    path.write_text("# a log\nt,v_N,v_E,h\n\n" + "".join(",".join(row) + "\n"
                                                       for row in cells))
    line = k + 4
    with pytest.raises(InsErrorsError) as error:
        read_motion_file(path, LAT, LON, 0.0, 0.0)
    assert str(error.value) == (f"motion file {str(path)!r}: {column} is NaN or infinite in "
                                f"sample {k + 1} of {t.size} (line {line})")
    assert path.read_text().splitlines()[line - 1].split(",")[
        ["t", "v_N", "v_E", "h"].index(column)] == bad
