"""Sweeps split between jobs and the checks around them.

* ``--shard I/N`` runs a fixed share of the points into a store of its own, ``--merge``
  joins the shards' stores into the store of the whole sweep, bit for bit;
* a store is written by one process at a time (a second one stops with one line);
* the worst ratio judges the ``[outputs] quantities`` as ``run`` does;
* plot options, the size of the sweep and a store of another sweep are refused before
  any point runs, naming what is wrong.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("zarr")  # the store needs the 'distributed' extra (in 'dev')

import xarray as xr

from ins_errors.analysis import store as st
from ins_errors.analysis import sweep as sw
from ins_errors.cli import main
from ins_errors.scenario import load_scenario
from tests.helpers import FLIGHT_10_MIN

ROOT = Path(__file__).resolve().parent.parent

FLIGHT = FLIGHT_10_MIN + """[outputs]
quantities = ["delta_latitude", "delta_longitude", "delta_v_N"]
"""

GRID = """
[sweep]
latitude = ["20 deg", "40 deg", "60 deg"]
heading = { start = "0 deg", stop = "90 deg", count = 3 }
"""

DRAWS = """
[sweep]
latitude = ["30 deg", "60 deg"]
draws = 4
seed = 7
[sweep.random]
accel_bias_y = "100 ug"
gyro_drift_x = "0.01 deg/h"
"""


def write(tmp_path, text: str, name: str = "s.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def opened(path: Path):
    """A store as it is on disk, no decoding (a folder with Zarr, a file with NetCDF)."""
    if path.suffix == ".nc":
        with xr.open_dataset(path, mask_and_scale=False) as data:
            return data.load()
    return xr.open_zarr(path, chunks=None, consolidated=False, mask_and_scale=False)


def assert_bit_identical(a, b) -> None:
    """Every variable and coordinate of two stores equal, bit for bit (NaN where NaN),
    and the same attributes."""
    assert sorted(a.variables) == sorted(b.variables)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        assert x.dtype == y.dtype and x.shape == y.shape, name
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), name
            assert np.array_equal(x.view(np.uint64), y.view(np.uint64)), name  # the bits
        else:
            assert np.array_equal(x, y), name
    assert a.attrs == b.attrs


@pytest.mark.parametrize("sweep, suffix, count", [(GRID, ".zarr", 3), (DRAWS, ".nc", 3)],
                         ids=["grid-zarr", "monte-carlo-netcdf"])
def test_shards_on_different_engines_merge_into_the_whole_sweeps_store(tmp_path, capsys,
                                                                       sweep, suffix,
                                                                       count):
    """Shard I of N runs the points I-1, I-1+N, ...; the merge of the shards' stores
    (run on different engines, given in any order) is the store of the whole sweep,
    every variable equal to the bit; Monte Carlo draws are split like any point."""
    path = write(tmp_path, FLIGHT + sweep)
    whole = tmp_path / f"whole{suffix}"
    assert main(["sweep", str(path), "--engine", "serial", "--store", str(whole),
                 "--no-progress", "--json"]) == 0
    total = json.loads(capsys.readouterr().out)["points"]
    engines = ["serial", "pool", "serial"]
    parts = []
    for index in range(1, count + 1):
        part = tmp_path / f"part_{index}{suffix}"
        parts.append(part)
        assert main(["sweep", str(path), "--shard", f"{index}/{count}", "--store",
                     str(part), "--engine", engines[index - 1], "--workers", "2",
                     "--no-progress", "--json"]) == 0
        out, err = capsys.readouterr()
        report = json.loads(out)
        mine = list(range(index - 1, total, count))
        assert report["shard"] == f"{index}/{count}" and report["sweep_points"] == total
        assert report["points"] == report["computed"] == len(mine)
        assert [row["point"] for row in report["summary"]] == mine
        store_line, start = err.splitlines()[:2]  # the store holds the shard's points
        assert store_line.startswith(f"ins-errors: store: {len(mine)} points, about ")
        assert start.startswith(f"ins-errors: sweep 'flight', shard {index}/{count}: "
                                f"{len(mine)} of the {total} points, {len(mine)} to compute")
        done = opened(part)["done"].values
        assert [k for k in range(total) if done[k]] == mine
    if "draws" in sweep:  # the draws of one grid point are split like any points:
        draw = opened(parts[0])["draw"].values  # shard 1 of 3 has points 0, 3 and 6
        assert [int(draw[k]) for k in range(0, total, count)] == [0, 3, 2]
    merged = tmp_path / f"all{suffix}"
    assert main(["sweep", str(path), "--merge", *map(str, parts[::-1]), "--store",
                 str(merged), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["points"], report["merged"], report["computed"]) == (total, total, 0)
    assert_bit_identical(opened(whole), opened(merged))
    assert not list(tmp_path.glob("*.lock")) and not list(tmp_path.glob("*.creating"))
    assert not list(tmp_path.glob("*.partial.zarr"))
    # merging again finds everything in place and changes nothing
    assert main(["sweep", str(path), "--merge", *map(str, parts), "--store", str(merged),
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["merged"] == 0
    assert_bit_identical(opened(whole), opened(merged))


def test_a_failed_point_is_carried_by_its_shard_into_the_merge(tmp_path, capsys):
    """A point over the pole fails in its shard (exit 3, the store complete); the
    merged store records it as the whole sweep's store does."""
    path = write(tmp_path, FLIGHT + '[sweep]\nlatitude = ["10 deg", "89.5 deg", "30 deg"]\n')
    assert main(["sweep", str(path), "--engine", "serial", "--store",
                 str(tmp_path / "whole.zarr"), "--no-progress"]) == 3
    statuses = [main(["sweep", str(path), "--engine", "serial", "--shard", f"{i}/2",
                      "--store", str(tmp_path / f"p{i}.zarr"), "--no-progress"])
                for i in (1, 2)]
    assert statuses == [0, 3]  # point 1 is shard 2's
    capsys.readouterr()
    assert main(["sweep", str(path), "--merge", str(tmp_path / "p1.zarr"),
                 str(tmp_path / "p2.zarr"), "--store", str(tmp_path / "all.zarr")]) == 3
    assert "point 1 (latitude = 89.5 deg)" in capsys.readouterr().err
    assert_bit_identical(opened(tmp_path / "whole.zarr"), opened(tmp_path / "all.zarr"))


def test_a_shard_store_resumes_and_is_kept_to_its_shard(tmp_path, capsys, monkeypatch):
    path = write(tmp_path, FLIGHT + GRID)
    runs: list = []
    real = sw.run_point
    monkeypatch.setattr(sw, "run_point", lambda job: runs.append(job.label) or real(job))
    scenario = load_scenario(path)
    shard = sw.Shard(2, 3)

    def interrupt(index: int) -> None:
        if index == 4:
            raise KeyboardInterrupt

    part = tmp_path / "p2.zarr"
    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(scenario, part, engine="serial", shard=shard, on_result=interrupt)
    assert len(runs) == 2  # points 1 and 4
    runs.clear()
    again = sw.run_sweep(scenario, part, engine="serial", shard=shard)
    assert (again.computed, again.reused, len(runs)) == (1, 2, 1)
    assert not (tmp_path / "p2.zarr.lock").exists()
    for args, message in [
        ([], "holds shard 2/3 of this sweep, not the whole sweep (run without --shard)"),
        (["--shard", "1/3"], "holds shard 2/3 of this sweep, not shard 1/3 (--shard 1/3 "
                             "needs a store of its own)"),
    ]:
        assert main(["sweep", str(path), "--store", str(part), "--engine", "serial",
                     *args]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1, err


@pytest.mark.parametrize("value, message", [
    ("0/0", "--shard 0/0: N, the number of shards, must be at least 1"),
    ("5/3", "--shard 5/3: I must be 1 to 3"),
    ("-1/2", "--shard '-1/2': give I/N"),
    ("1.5/2", "--shard '1.5/2': give I/N"),
    ("text", "--shard 'text': give I/N"),
    ("10/10", "--shard 10/10: the sweep has 9 points, so it splits into at most 9 shards"),
])
def test_bad_shard_values_are_one_line_before_anything_runs(tmp_path, capsys, value,
                                                            message):
    path = write(tmp_path, FLIGHT + GRID)
    assert main(["sweep", str(path), "--shard", value, "--store",
                 str(tmp_path / "x.zarr"), "--engine", "serial"]) == 2
    out, err = capsys.readouterr()
    assert err == f"ins-errors: error: {message}" + err.split(message, 1)[1]
    assert err.count("\n") == 1 and not out and not (tmp_path / "x.zarr").exists()


def test_merges_that_cannot_be_made_say_why(tmp_path, capsys, monkeypatch):
    """Parts of another sweep (named setting), another split, a shard twice, missing or
    unfinished shards (named with their points), a whole store: one line each, exit 2,
    no merged store left behind."""
    path = write(tmp_path, FLIGHT + GRID)
    other = write(tmp_path, (FLIGHT + GRID).replace('"5 s"', '"10 s"'), "other.toml")

    def shard(scenario_path, index, count, name):
        assert main(["sweep", str(scenario_path), "--shard", f"{index}/{count}", "--store",
                     str(tmp_path / name), "--engine", "serial", "--no-progress"]) == 0

    shard(path, 1, 3, "a1.zarr")
    shard(path, 2, 3, "a2.zarr")
    shard(other, 3, 3, "o3.zarr")
    shard(path, 1, 2, "b1.zarr")
    assert main(["sweep", str(path), "--store", str(tmp_path / "whole.zarr"), "--engine",
                 "serial", "--no-progress"]) == 0
    unfinished = tmp_path / "a3.zarr"

    def stop(index: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(load_scenario(path), unfinished, engine="serial",
                     shard=sw.Shard(3, 3), on_result=stop)
    capsys.readouterr()
    cases = [
        (["a1.zarr", "a2.zarr"], "cannot merge: shard 3/3 is missing (3 of the 9 points: 2, "
                                 "5, 8); give its store"),
        (["a1.zarr"], "cannot merge: shards 2/3, 3/3 are missing (6 of the 9 points: 1, 2, "
                      "4, 5, 7, 8); give their stores"),
        (["a1.zarr", "a2.zarr", "a3.zarr"], "'a3.zarr' (shard 3/3) lacks 2 of its 3 points "
                                            "(5, 8): run its sweep command again"),
        (["a1.zarr", "a2.zarr", "o3.zarr"], "'o3.zarr' (shard 3/3) holds another sweep: "
                                            "[run] step is 10.0 s there, 5.0 s here"),
        (["a1.zarr", "b1.zarr"], "'b1.zarr' is shard 1/2 but 'a1.zarr' is shard 1/3"),
        (["a1.zarr", "a1.zarr"], "--merge names 'a1.zarr' twice"),
        (["a2.zarr", "whole.zarr"], "'whole.zarr' holds a whole sweep, not a shard of it"),
        (["a1.zarr", "all.zarr"], "the merged store cannot be one of the shard stores"),
        (["a1.zarr", "nothing.zarr"], "'nothing.zarr': no such shard store"),
    ]
    monkeypatch.chdir(tmp_path)  # undone after the test: later tests read relative paths
    for parts, message in cases:
        assert main(["sweep", str(path), "--merge", *parts, "--store", "all.zarr"]) == 2
        out, err = capsys.readouterr()
        assert message in err and err.count("\n") == 1 and not out, (parts, err)
        assert not (tmp_path / "all.zarr").exists()
    # a shard store written meanwhile by another process is not read
    with st.store_lock(tmp_path / "a2.zarr"):
        assert main(["sweep", str(path), "--merge", "a1.zarr", "a2.zarr", "a3.zarr",
                     "--store", "all.zarr"]) == 2
    err = capsys.readouterr().err
    assert "'a2.zarr' is being written by another process" in err
    # options of a run mean nothing to a merge
    assert main(["sweep", str(path), "--merge", "a1.zarr", "a2.zarr", "--store", "all.zarr",
                 "--engine", "pool", "--workers", "2"]) == 2
    err = capsys.readouterr().err
    assert "--engine, --workers would be ignored" in err and err.count("\n") == 1


def test_a_store_of_another_sweep_is_refused_naming_the_setting(tmp_path, capsys):
    path = write(tmp_path, FLIGHT + DRAWS)
    store = str(tmp_path / "mc.zarr")
    assert main(["sweep", str(path), "--store", store, "--engine", "serial",
                 "--no-progress"]) == 0
    capsys.readouterr()
    for old, new, message in [
        ("seed = 7", "seed = 8", "[sweep] seed is 7 there, 8 here"),
        ('"250 m/s"', '"200 m/s"', "[motion] speed is 250 m/s there, 200 m/s here"),
        ("draws = 4", "draws = 5", "[sweep] draws is 4 there, 5 here"),
        ('accel_bias_x = "100 ug"', 'accel_bias_x = "200 ug"',
         "[[case]] 1 accel_bias_x is 0.000980665 m/s**2 there, 0.00196133 m/s**2 here"),
    ]:
        other = write(tmp_path, (FLIGHT + DRAWS).replace(old, new), "o.toml")
        assert main(["sweep", str(other), "--store", store, "--engine", "serial"]) == 2
        err = capsys.readouterr().err
        assert err == (f"ins-errors: error: {store!r} holds another sweep: {message}; "
                       "a store takes other [sweep] grid values only (every other setting "
                       "the same): remove it or choose another store\n")


def test_a_second_process_on_a_store_being_written_stops_in_one_line(tmp_path, capsys,
                                                                     monkeypatch):
    path = write(tmp_path, FLIGHT + GRID)
    runs: list = []
    monkeypatch.setattr(sw, "run_point", lambda job: runs.append(job))
    for store in ("busy.zarr", "busy.nc"):
        with st.store_lock(tmp_path / store):
            assert main(["sweep", str(path), "--store", str(tmp_path / store), "--engine",
                         "serial"]) == 2
        out, err = capsys.readouterr()
        assert err.startswith(f"ins-errors: error: sweep store {str(tmp_path / store)!r} "
                              f"is being written by another process (process {os.getpid()} "
                              "on host ")
        assert err.count("\n") == 1 and not out and runs == []
        assert not (tmp_path / store).exists()
        assert not list(tmp_path.glob("busy*"))  # nor its lock: removed by its holder


def test_a_store_is_locked_through_a_link_and_its_lock_never_through_one(tmp_path):
    """A link to a store locks the store itself (the lock was named after the path as
    given, so a second process on 'link.zarr' ran beside one on 'store.zarr'); a link
    planted as the lock file is refused, and its target is left untouched (it was
    truncated and given the holder's name)."""
    store, link = tmp_path / "store.zarr", tmp_path / "link.zarr"
    store.mkdir()
    link.symlink_to(store)
    with st.store_lock(store), pytest.raises(st.StoreBusyError), st.store_lock(link):
        pass
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me\n")
    (tmp_path / "other.zarr.lock").symlink_to(victim)
    planted = r"other\.zarr\.lock is a symbolic link"
    with pytest.raises(st.StoreError, match=planted), st.store_lock(tmp_path / "other.zarr"):
        pass
    assert victim.read_text() == "keep me\n"


def test_a_store_whose_making_is_interrupted_leaves_nothing(tmp_path, monkeypatch):
    path = write(tmp_path, FLIGHT + GRID)

    def interrupted(work) -> None:
        work.close()
        raise KeyboardInterrupt

    monkeypatch.setattr(st, "_run_together", interrupted)
    for store in ("x.zarr", "x.nc"):
        with pytest.raises(KeyboardInterrupt):
            sw.run_sweep(load_scenario(path), tmp_path / store, engine="serial")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def _starter(tmp_path: Path, scenario: Path, store: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen([sys.executable, "-m", "ins_errors", "sweep", str(scenario),
                             "--engine", "serial", "--store", store, "--json",
                             "--no-progress"], cwd=tmp_path, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@pytest.mark.parametrize("store", ["race.zarr", "race.nc"])
def test_three_jobs_started_together_on_a_new_store(tmp_path, store):
    """Three copies of one command started at once on a store that does not exist yet:
    each either writes the store or stops in one line saying another process writes it
    (no traceback, no library warning); the store is the sweep's, with nothing left
    beside it."""
    path = write(tmp_path, FLIGHT + GRID)
    started = [_starter(tmp_path, path, store) for _ in range(3)]
    results = [(p.wait(timeout=600), *p.communicate()) for p in started]
    ok = [out for status, out, _ in results if status == 0]
    assert ok, results
    for status, out, err in results:
        lines = err.splitlines()
        assert "Traceback" not in err and "Warning" not in err, err
        if status == 2:
            assert len(lines) == 1 and "is being written by another process" in lines[0]
            assert not out
        else:
            assert status == 0 and lines[0].startswith("ins-errors: store: 9 points, about ")
            assert lines[1].startswith("ins-errors: sweep 'flight', 9 points")
    assert json.loads(ok[0])["points"] == 9
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["s.toml", store])
    data = opened(tmp_path / store)
    assert int(data["done"].sum()) == 9


def test_the_sweeps_worst_ratio_is_that_of_run_over_the_outputs_quantities(tmp_path,
                                                                            capsys):
    """[outputs] quantities says what is judged: a sweep point's worst linear/direct
    ratio is the one ``run`` gives for the same point (the heading's alpha_z, larger,
    is not among them)."""
    path = write(tmp_path, FLIGHT + '[sweep]\nlatitude = ["50 deg"]\n')
    assert main(["sweep", str(path), "--store", str(tmp_path / "one.zarr"), "--engine",
                 "serial", "--json"]) == 0
    [point] = json.loads(capsys.readouterr().out)["summary"]
    plain = write(tmp_path, FLIGHT, "plain.toml")
    assert main(["run", str(plain), "--json", "--out", str(tmp_path / "report")]) == 0
    [case] = json.loads(capsys.readouterr().out)["cases"]
    assert point["worst_linear_quantity"] in ("delta_latitude", "delta_longitude",
                                              "delta_v_N")
    assert point["worst_linear_ratio"] == pytest.approx(case["worst_linear_ratio"],
                                                        rel=1e-9)
    assert point["worst_refined_ratio"] == pytest.approx(case["worst_refined_ratio"],
                                                         rel=1e-9)
    every = max(v for q, v in point["linear_ratio"].items() if v is not None
                and q in ("alpha_x", "alpha_y", "alpha_z"))
    assert every > 2 * point["worst_linear_ratio"]  # judging every quantity differs


@pytest.mark.parametrize("options, message", [
    (["--plot", "p.png", "--against", "speed"], "unknown swept parameter 'speed'"),
    (["--plot", "p.png", "--figure", "bogus"], "unknown figure 'bogus'"),
    (["--plot", "p.png", "--figure", "max_direct:delta_h"], "unknown error quantity"),
    (["--plot", "/proc/p.png"], "/proc/p.png"),
    (["--figure", "bogus"], "--figure chooses what --plot draws: give --plot PNG too"),
    (["--against", "latitude"], "--against chooses what --plot draws"),
    (["--plot", "p.png", "--against", "latitude,latitude"], "names latitude twice"),
    (["--shard", "1/2", "--merge", "a.zarr"], "give one of the two"),
])
def test_output_options_are_checked_before_any_point_runs(tmp_path, capsys, monkeypatch,
                                                          options, message):
    path = write(tmp_path, FLIGHT + GRID)
    runs: list = []
    monkeypatch.setattr(sw, "run_point", lambda job: runs.append(job))
    monkeypatch.chdir(tmp_path)
    assert main(["sweep", str(path), "--store", "x.zarr", "--engine", "serial",
                 *options]) == 2
    out, err = capsys.readouterr()
    assert message in err and err.count("\n") == 1 and not out, err
    assert runs == [] and not (tmp_path / "x.zarr").exists()


def test_the_refined_figure_of_a_sweep_without_it_is_refused_first(tmp_path, capsys):
    path = write(tmp_path, (FLIGHT + GRID).replace('record = "60 s"',
                                                   'record = "60 s"\nrefined = false'))
    assert main(["sweep", str(path), "--store", str(tmp_path / "x.zarr"), "--plot",
                 str(tmp_path / "p.png"), "--figure", "worst_refined_ratio"]) == 2
    assert "runs without the refined model" in capsys.readouterr().err
    assert not (tmp_path / "x.zarr").exists()


@pytest.mark.parametrize("sweep, factors", [
    ('latitude = ["20 deg"]\ndraws = 1000000000\n[sweep.random]\naccel_bias_y = "1 ug"\n',
     "1,000,000,000 points (1 latitude × 1,000,000,000 draws)"),
    ('latitude = { start = "0 deg", stop = "60 deg", count = 2000 }\n'
     'heading = { start = "0 deg", stop = "90 deg", count = 2000 }\n',
     "4,000,000 points (2,000 latitude × 2,000 heading)"),
])
def test_a_sweep_too_large_is_refused_at_once(tmp_path, capsys, sweep, factors):
    path = write(tmp_path, FLIGHT + "[sweep]\n" + sweep)
    started = time.process_time()
    assert main(["sweep", str(path), "--store", str(tmp_path / "x.zarr")]) == 2
    assert time.process_time() - started < 5  # was: 5 GB of points built, and on
    err = capsys.readouterr().err
    assert f"the sweep has {factors}, more than the 100,000 a sweep may have" in err
    assert err.count("\n") == 1 and not (tmp_path / "x.zarr").exists()


def test_the_point_count_is_said_before_the_first_point_runs(tmp_path, capsys,
                                                             monkeypatch):
    path = write(tmp_path, FLIGHT + GRID)
    said: list = []
    real = sw.run_point

    def first(job):
        said.append(capsys.readouterr().err)
        return real(job)

    monkeypatch.setattr(sw, "run_point", first)
    store = tmp_path / "c.zarr"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial",
                 "--json", "--no-progress"]) == 0
    store_line, start = said[0].splitlines()
    assert re.fullmatch(r"ins-errors: store: 9 points, about [0-9.]+ [kMG]B in [0-9,]+ files",
                        store_line), store_line
    assert start == f"ins-errors: sweep 'flight', 9 points, 9 to compute, 0 already in {store}"
