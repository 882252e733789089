"""A sweep store as a user reads it with xarray: its failure reasons as ordinary text (the
five operations a cluster user runs on a store with a failed point), CF units that pint
reads, the judged quantities of the last command on disk, and a size said (and checked)
before the store is written.

Was: ``failure`` read back from Zarr as NumPy's StringDType, so ``ds.where(...)`` raised
``DTypePromotionError``; ``units`` of the error curves was a sentence; a rerun with
other ``[outputs] quantities`` left the old list on disk; nothing said how large a store
would be before a 29-GB one was written.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import textwrap
from pathlib import Path

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
zarr = pytest.importorskip("zarr")

from ins_errors.analysis import store as st  # noqa: E402
from ins_errors.analysis import sweep as sw  # noqa: E402
from ins_errors.analysis import sweep_report as sr  # noqa: E402
from ins_errors.cli import main  # noqa: E402
from ins_errors.scenario import load_scenario  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent

POLE = """\
title = "pole"
model = "orthodromic"
[motion]
kind = "great-circle"
latitude = "50 deg"
heading = "0 deg"
[run]
duration = "10 min"
step = "1 s"
record = "60 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
[sweep]
latitude = ["10 deg", "89.5 deg"]
accel_bias_x = ["100 ug"]
"""
"""A flight north at 250 m/s: from 89.5° N it reaches the pole after about 220 s, so
point 1 fails on its own input (a real failure, not a made-up one); point 0 runs."""

POLE_REASON = "the true motion leaves the model's domain"


def _raw(path: Path, name: str) -> np.ndarray:
    """A data variable as Zarr stores it (read without xarray): the reference."""
    return np.asarray(zarr.open_group(str(path), mode="r", zarr_format=2)[name][:])


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    """The failing sweep in a Zarr store and in a NetCDF store, and the reason."""
    folder = tmp_path_factory.mktemp("pole")
    path = folder / "pole.toml"
    path.write_text(POLE, encoding="utf-8")
    made = {}
    for name in ("s.zarr", "s.nc"):
        result = sw.run_sweep(load_scenario(path), folder / name, engine="serial")
        assert result.failed == [1]
        made[name] = folder / name
    reason = st.failure_reasons(xr.open_zarr(made["s.zarr"], chunks=None))[1]
    assert reason.startswith(POLE_REASON)
    return made["s.zarr"], made["s.nc"], reason


def _opened(stores, how: str):
    zarr_store, nc_store, _ = stores
    if how == "zarr":  # as a user on a cluster opens it: lazily, with dask
        return xr.open_zarr(zarr_store)
    if how == "zarr loaded":
        return xr.open_zarr(zarr_store).load()
    return xr.open_dataset(nc_store)


OPENED = ["zarr", "zarr loaded", "netcdf"]


@pytest.mark.parametrize("how", OPENED)
def test_where_done_with_drop_keeps_every_done_point_and_its_reason(stores, how):
    """``ds.where(ds.done, drop=True)``: both points are done (the failed one with its
    reason). On a store opened lazily, xarray needs the condition computed for
    ``drop=True`` (its own rule for dask arrays, whatever the variable's type)."""
    ds = _opened(stores, how)
    done = ds.done.compute() if how == "zarr" else ds.done
    kept = ds.where(done, drop=True)
    assert kept.sizes["point"] == 2
    assert list(kept.failure.values) == ["", stores[2]]
    expected = _raw(stores[0], "direct")[0]
    assert np.array_equal(kept.direct.values[0], expected)


@pytest.mark.parametrize("how", OPENED)
def test_where_the_failure_is_empty_masks_the_failed_point(stores, how):
    """``ds.where(ds.failure == "")``: the point that ran keeps its numbers, the failed
    one is NaN throughout, its reason masked; with ``drop=True`` (loaded) only the point
    that ran is left."""
    ds = _opened(stores, how)
    masked = ds.where(ds.failure == "")
    direct = masked.direct.values
    assert np.array_equal(direct[0], _raw(stores[0], "direct")[0])
    assert np.isnan(direct[1]).all()
    failure = masked.failure.values
    assert failure[0] == "" and not isinstance(failure[1], str)  # masked (NaN)
    ran = ds.load().where(ds.failure.compute() == "", drop=True)
    assert ran.point.values.tolist() == [0] and list(ran.failure.values) == [""]


@pytest.mark.parametrize("how", OPENED)
def test_to_dataframe_carries_each_points_reason(stores, how):
    """``ds.to_dataframe()``: every row of the failed point carries its reason, every
    row of the other point empty text; the numbers are those stored."""
    ds = _opened(stores, how)
    frame = ds.to_dataframe()
    by_point = frame.reset_index().groupby("point")["failure"].unique()
    assert list(by_point[0]) == [""] and list(by_point[1]) == [stores[2]]
    direct = frame.reset_index().set_index(["point", "time", "quantity"])["direct"]
    direct = direct[~direct.index.duplicated()]  # (one row per source too)
    first = _raw(stores[0], "direct")[0]
    quantities = [str(q) for q in ds.quantity.values]
    times = ds.time.values
    got = np.array([[direct[(0, t, q)] for q in quantities] for t in times])
    assert np.array_equal(got, first)


@pytest.mark.parametrize("how", OPENED)
@pytest.mark.filterwarnings("ignore:variable failure has data in the form of a dask array")
def test_to_netcdf_writes_a_file_that_reads_back_the_same(stores, how, tmp_path):
    """``ds.to_netcdf("x.nc")``: the file reads back with the reasons and the numbers
    (of a lazily opened store xarray warns that it loads ``failure`` to size its text,
    as docs/cluster.md says)."""
    ds = _opened(stores, how)
    ds.to_netcdf(tmp_path / "x.nc")
    with xr.open_dataset(tmp_path / "x.nc") as back:
        assert list(back.failure.values) == ["", stores[2]]
        for name in ("direct", "max_direct", "source_value"):
            assert np.array_equal(back[name].values, ds[name].values, equal_nan=True), name
        assert back.direct.attrs == ds.direct.attrs


@pytest.mark.parametrize("how", OPENED)
def test_sel_of_one_point_gives_its_reason_as_text(stores, how):
    """``ds.sel(point=k)``: the failed point's reason (a 0-d text), the other's empty."""
    ds = _opened(stores, how)
    assert ds.sel(point=1).failure.values[()] == stores[2]
    assert ds.sel(point=0).failure.values[()] == ""
    assert ds.sel(point=[1, 0]).failure.values.tolist() == [stores[2], ""]
    assert np.isnan(ds.sel(point=1).direct.values).all()


def test_the_failure_variable_is_text_xarray_combines_with_nan(stores):
    """Read as Python text (object), not StringDType: reindexing and filling, which
    bring in NaN, work too."""
    ds = xr.open_zarr(stores[0])
    assert ds.failure.dtype == object
    grown = ds.load().reindex(point=[0, 1, 2])
    assert grown.failure.values[1] == stores[2] and not isinstance(grown.failure.values[2],
                                                                      str)
    assert list(grown.failure.fillna("").values) == ["", stores[2], ""]


def test_the_python_shown_in_cluster_md_runs_on_a_store_with_a_failed_point(stores,
                                                                            tmp_path):
    """docs/cluster.md's Python lines, run as written in a folder whose out/sweep.zarr
    is a store with a failed point."""
    page = (ROOT / "docs" / "cluster.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", page, re.M | re.S)
    assert blocks, "docs/cluster.md shows no Python"
    (tmp_path / "out").mkdir()
    shutil.copytree(stores[0], tmp_path / "out" / "sweep.zarr")
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for block in blocks:
            exec(compile(block, "docs/cluster.md", "exec"), {})
    finally:
        os.chdir(cwd)


# ---------------------------------------------------------------------------------------
def _layout(points: int = 3) -> st.Layout:
    return st.Layout(points, np.arange(3) * 10.0, ("alpha_x",), ("rad",),
                     ("gyro_drift_z",), ("rad/s",),
                     {"latitude": (np.linspace(0.1, 0.3, points), {"units": "rad"})},
                     ("direct", "linear"), {"title": "t"}, "e" * 32)


def test_a_longer_reason_widens_the_variable_and_every_reason_reads_back_whole(tmp_path):
    """Reasons of 14 and 3000 bytes (non-ASCII): both read back whole through the
    consolidated metadata xr.open_zarr uses; a reason beyond 4096 bytes keeps its start
    and says that it was cut and how long it was (never cut silently)."""
    store = st.SweepStore.open(tmp_path / "s.zarr", _layout())
    short, long = "short: 89.5° N", "a long reason φ " * 176 + "end"
    assert len(long.encode()) > 2900
    store.fail(0, short)
    store.fail(2, long)
    metadata = json.loads((tmp_path / "s.zarr" / ".zmetadata").read_text())["metadata"]
    assert metadata["failure/.zarray"]["shape"] == [3, len(long.encode())]
    with xr.open_zarr(tmp_path / "s.zarr") as ds:
        assert list(ds.failure.values) == [short, "", long]
    reopened = st.SweepStore.open(tmp_path / "s.zarr", _layout())
    assert reopened.failure == [short, "", long]
    huge = "x" * 5000 + " the end"
    reopened.fail(1, huge)
    with xr.open_zarr(tmp_path / "s.zarr") as ds:
        kept = str(ds.failure.values[1])
    assert kept.startswith("x" * 4000) and kept.endswith("[cut: the reason has 5,008 bytes]")
    assert len(kept.encode()) <= 4096 and reopened.failure[1] == kept
    # a failed point run again loses its reason
    rng = np.random.default_rng(1)
    reopened.write(0, {"direct": rng.standard_normal((3, 1)),
                       "linear": rng.standard_normal((3, 1)),
                       "max_direct": rng.standard_normal(1),
                       "linear_ratio": rng.standard_normal(1),
                       "excited": np.ones(1, dtype="i1"),
                       "integration_error": rng.standard_normal(1),
                       "source_value": rng.standard_normal(1)})
    with xr.open_zarr(tmp_path / "s.zarr") as ds:
        assert list(ds.failure.values) == ["", kept, long]


def _old_failure_form(path: Path) -> None:
    """Rewrite a store's ``failure`` as stores were written before: variable-length text
    (Zarr's vlen-utf8, one chunk per point), its reasons kept."""
    group = zarr.open_group(str(path), mode="r+", zarr_format=2)
    reasons = st.failure_reasons(xr.open_zarr(path, chunks=None))
    del group["failure"]
    old = group.create_array("failure", shape=(len(reasons),), chunks=(1,), dtype=str,
                             fill_value=None,
                             attributes={"_ARRAY_DIMENSIONS": ["point"],
                                         "long_name": "why the point failed", "units": "1"})
    for k, reason in enumerate(reasons):
        if reason:
            old[k] = reason
    zarr.consolidate_metadata(str(path), zarr_format=2)
    metadata = json.loads((path / "failure" / ".zarray").read_text())
    assert metadata["dtype"] == "|O" and metadata["filters"] == [{"id": "vlen-utf8"}]


FLAKY = """\
title = "flaky"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "60 s"
step = "1 s"
record = "60 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
[sweep]
latitude = {grid}
"""


def _flaky(monkeypatch, bad=("latitude = 20 deg", "latitude = 40 deg")):
    real = sw.run_point

    def flaky(job):
        if job.label in bad:
            raise sw.PointError(job.label, f"made-up failure of {job.label} °")
        return real(job)

    monkeypatch.setattr(sw, "run_point", flaky)


def test_a_store_with_the_earlier_text_variable_resumes_extends_and_merges(tmp_path,
                                                                           monkeypatch):
    """A store written before (failure as vlen-utf8) resumes (a new failure is recorded
    in it, as text), is extended (rewritten with the new variable, reasons kept) and its
    shards merge (into the new variable)."""
    _flaky(monkeypatch)
    path = tmp_path / "f.toml"
    path.write_text(FLAKY.format(grid='["10 deg", "20 deg", "30 deg"]'), encoding="utf-8")
    store = tmp_path / "old.zarr"

    def stop(index: int) -> None:
        if index == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):  # points 0 and 1 stored, 1 failed
        sw.run_sweep(load_scenario(path), store, engine="serial", on_result=stop)
    _old_failure_form(store)
    resumed = sw.run_sweep(load_scenario(path), store, engine="serial")
    assert (resumed.computed, resumed.reused, resumed.failed) == (1, 2, [1])
    assert json.loads((store / "failure" / ".zarray").read_text())["dtype"] == "|O"
    assert sr.failures(resumed.dataset)[0]["reason"] == "made-up failure of latitude = 20 deg °"
    # extended by a point that fails: the store is rewritten in the new form
    path.write_text(FLAKY.format(grid='["10 deg", "20 deg", "30 deg", "40 deg"]'),
                    encoding="utf-8")
    extended = sw.run_sweep(load_scenario(path), store, engine="serial")
    assert (extended.computed, extended.reused, extended.failed) == (1, 3, [1, 3])
    assert json.loads((store / "failure" / ".zarray").read_text())["dtype"] == "|S1"
    ds = xr.open_zarr(store)
    assert ds.where(ds.failure == "").failure.values[0] == ""
    assert sorted(st.failure_reasons(ds)) == ["", "", "made-up failure of latitude = 20 deg °",
                                             "made-up failure of latitude = 40 deg °"]
    # shards in the earlier form merge into the new form
    parts = []
    for index in (1, 2):
        part = tmp_path / f"part_{index}.zarr"
        sw.run_sweep(load_scenario(path), part, engine="serial",
                     shard=sw.parse_shard(f"{index}/2"))
        _old_failure_form(part)
        parts.append(part)
    merged = sw.merge_shards(load_scenario(path), parts, tmp_path / "all.zarr")
    assert merged.failed == [1, 3]
    with xr.open_zarr(tmp_path / "all.zarr") as ds:
        assert ds.failure.dtype == object
        assert list(ds.failure.values) == ["", "made-up failure of latitude = 20 deg °", "",
                                           "made-up failure of latitude = 40 deg °"]


# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("which", [0, 1])
def test_every_units_attribute_is_a_unit_of_the_right_kind(stores, which):
    """Every ``units`` attribute (data variables and coordinates) is a unit pint reads,
    of the dimension the variable has: time in s, latitude an angle, the swept
    accelerometer bias an acceleration, ratios and flags pure numbers. Variables over
    quantities or sources (one unit each) have none, and name the coordinate that gives
    each quantity's unit, whose entries are units of the quantities' kinds; text has
    none."""
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    ds = _opened(stores, "zarr" if which == 0 else "netcdf")
    dimension = {name: str(ureg.parse_units(var.attrs["units"]).dimensionality)
                 for name, var in ds.variables.items() if "units" in var.attrs}
    assert dimension["time"] == "[time]"
    assert dimension["latitude"] == "dimensionless"  # rad
    assert ureg.parse_units(ds.latitude.attrs["units"]) == ureg.radian
    assert dimension["accel_bias_x"] == "[length] / [time] ** 2"
    for name in ("linear_ratio", "refined_ratio", "excited", "done"):
        assert dimension[name] == "dimensionless", name
    mixed = {"direct", "linear", "refined", "max_direct", "integration_error"}
    for name in mixed:
        assert "units" not in ds[name].attrs and "quantity_unit" in ds[name].attrs["comment"]
    assert "units" not in ds.source_value.attrs and "source_unit" in \
        ds.source_value.attrs["comment"]
    for name in ("failure", "point_key", "quantity", "quantity_unit", "source"):
        assert "units" not in ds[name].attrs, name
    unit = dict(zip([str(q) for q in ds.quantity.values],
                    [str(u) for u in ds.quantity_unit.values], strict=True))
    assert ureg.parse_units(unit["delta_latitude"]) == ureg.radian
    assert str(ureg.parse_units(unit["delta_v_N"]).dimensionality) == "[length] / [time]"
    for text in [*unit.values(), *(str(u) for u in ds.source_unit.values)]:
        ureg.parse_units(text)  # each one a unit


# ---------------------------------------------------------------------------------------
JUDGED = """\
title = "judged"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "10 min"
step = "1 s"
record = "60 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
accel_bias_y = "100 ug"
[outputs]
quantities = {quantities}
[sweep]
latitude = ["10 deg", "60 deg"]
"""


@pytest.mark.parametrize("suffix", [".zarr", ".nc"])
def test_the_store_keeps_the_judged_quantities_of_the_last_command(tmp_path, capsys,
                                                                   suffix):
    """The same sweep run again with other [outputs] quantities reuses every point; the
    store then says the new list, and its summary read back later is the one the command
    printed (the old list stayed on disk, so it differed)."""
    store = tmp_path / f"s{suffix}"
    reports = []
    for quantities in ('["delta_latitude"]', '["alpha_x", "delta_v_E"]'):
        path = tmp_path / "j.toml"
        path.write_text(JUDGED.format(quantities=quantities), encoding="utf-8")
        assert main(["sweep", str(path), "--store", str(store), "--engine", "serial",
                     "--no-progress", "--json"]) == 0
        reports.append(json.loads(capsys.readouterr().out))
    assert reports[1]["reused"] == 2 and reports[1]["computed"] == 0
    assert reports[0]["summary"] != reports[1]["summary"]
    data = xr.open_zarr(store) if suffix == ".zarr" else xr.open_dataset(store)
    with data:
        assert json.loads(data.attrs["judged_quantities"]) == ["alpha_x", "delta_v_E"]
        assert json.loads(json.dumps(sr.summary(data))) == reports[1]["summary"]


# ---------------------------------------------------------------------------------------
def _on_disk(path: Path) -> tuple[int, int]:
    """Disk space (allocated blocks, bytes) and files and folders of a store, as ``du``
    and a quota of files count them."""
    paths = [path] if path.is_file() else [path, *path.rglob("*")]
    return sum(os.stat(p).st_blocks * 512 for p in paths), len(paths)


SIZED = """\
title = "sized"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "{duration}"
step = "1 s"
record = "{record}"
[[case]]
gyro_drift_x = "0.01 deg/h"
[sweep]
latitude = ["10 deg", "30 deg", "50 deg"]
"""


@pytest.mark.parametrize("duration, record, suffix", [
    ("60 s", "60 s", ".zarr"),  # small chunks: whole blocks
    ("10 min", "1 s", ".zarr"),  # curves of 601 samples: their bytes
    ("10 min", "1 s", ".nc")])
def test_the_size_said_before_the_store_is_written_bounds_the_real_one(
        tmp_path, capsys, duration, record, suffix):
    """The line said before the store is written gives an upper bound of its real size
    (disk blocks as du counts them) within 1.5×, and its files exactly: every chunk is
    counted at its size before compression rounded up to whole blocks, and Blosc shrinks
    error curves of doubles little (measured 1.1–1.2×); a small store is mostly files of
    one block either way. Of a NetCDF store, its file too."""
    path = tmp_path / "s.toml"
    path.write_text(SIZED.format(duration=duration, record=record), encoding="utf-8")
    store = tmp_path / f"s{suffix}"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial",
                 "--no-progress", "--json"]) == 0
    err = capsys.readouterr().err.splitlines()
    said = re.fullmatch(r"ins-errors: store: 3 points, about ([0-9.]+) (kB|MB) in ([0-9,]+) "
                        r"files(?: while filled, then a NetCDF file of ([0-9.]+) (kB|MB))?",
                        err[0])
    assert said, err
    assert err[1].startswith("ins-errors: sweep 'sized', 3 points, 3 to compute")
    scale = {"kB": 1e3, "MB": 1e6}
    scenario = load_scenario(path)
    estimate = st.store_size(sw.layout(scenario, sw.grid(scenario)), 3,
                             netcdf=suffix == ".nc", block=st.block_size(store))
    if suffix == ".zarr":
        size, files = _on_disk(store)
        assert int(said.group(3).replace(",", "")) == files == estimate.files
    else:
        size, _ = _on_disk(store)
        assert float(said.group(4)) * scale[said.group(5)] == pytest.approx(
            estimate.netcdf, rel=0.05)
        estimate = st.StoreSize(3, estimate.netcdf, 1)
    assert size <= estimate.bytes <= 1.5 * size, (size, estimate)


def test_a_store_beyond_the_limit_is_refused_before_anything_is_written(tmp_path, capsys,
                                                                        monkeypatch):
    """200 points of a week recorded every second: 604801 samples × 9 quantities × 3
    curves of doubles, 26 GB of curves alone, beyond the 20-GB limit: one line, exit 2,
    nothing made, in a few seconds. (No point may run: were the store not refused, the
    test would otherwise write it.)"""
    def never(job):
        raise AssertionError(f"a point ran: {job.label}")

    monkeypatch.setattr(sw, "run_point", never)
    path = tmp_path / "big.toml"
    path.write_text(textwrap.dedent("""\
        title = "big"
        model = "orthodromic"
        [motion]
        kind = "static"
        latitude = "50 deg"
        [run]
        duration = "7 d"
        step = "1 s"
        record = "1 s"
        [[case]]
        gyro_drift_x = "0.01 deg/h"
        [sweep]
        latitude = { start = "1 deg", stop = "80 deg", count = 200 }
        """), encoding="utf-8")
    assert 200 * 604801 * 9 * 3 * 8 > 26e9
    assert main(["sweep", str(path), "--store", str(tmp_path / "big.zarr"), "--engine",
                 "serial", "--no-progress"]) == 2
    out, err = capsys.readouterr()
    assert not out and err.count("\n") == 1, err
    assert "beyond the limit of 20 GB or 500,000 files" in err and "--allow-large-store" in err
    gigabytes = float(re.search(r"would take about ([0-9.]+) GB", err).group(1))
    assert 26 <= gigabytes <= 1.5 * 26
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.toml"]


@pytest.mark.parametrize("short", ["bytes", "files"])
def test_a_store_beyond_the_room_of_its_file_system_is_refused_unless_allowed(
        tmp_path, capsys, monkeypatch, short):
    """A file system with 1 kB free (or room for 10 files) refuses the store in one line
    naming what it has; --allow-large-store writes it anyway."""
    path = tmp_path / "s.toml"
    path.write_text(SIZED.format(duration="60 s", record="60 s"), encoding="utf-8")
    real = shutil.disk_usage(tmp_path)  # (which reads os.statvfs: taken before)
    block = os.statvfs(tmp_path).f_frsize

    def usage(folder):
        return real._replace(free=1000 if short == "bytes" else real.free)

    class Counts:
        def __init__(self, folder):
            self.f_frsize, self.f_files = block, 10**6
            self.f_favail = 10 if short == "files" else 10**6

    monkeypatch.setattr(st.shutil, "disk_usage", usage)
    monkeypatch.setattr(st.os, "statvfs", Counts)
    command = ["sweep", str(path), "--store", str(tmp_path / "s.zarr"), "--engine", "serial",
               "--no-progress", "--json"]
    assert main(command) == 2
    out, err = capsys.readouterr()
    assert not out and err.count("\n") == 1, err
    assert ("its file system has 1 kB free" if short == "bytes"
            else "its file system has room for 10") in err
    assert not (tmp_path / "s.zarr").exists()
    assert main([*command, "--allow-large-store"]) == 0
    assert json.loads(capsys.readouterr().out)["computed"] == 3
