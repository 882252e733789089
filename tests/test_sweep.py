"""Sweeps: the [sweep] grid, physics per grid point, the store, resuming, bad input.

The Dask runs (identical results on a 2-worker cluster, a worker killed mid-run) are in
tests/test_distributed.py.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import textwrap
import warnings

import numpy as np
import pytest

pytest.importorskip("zarr")  # the store needs the 'distributed' extra (in 'dev')

from ins_errors import units
from ins_errors.analysis import sweep as sw
from ins_errors.analysis import sweep_report as sr
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.scenario import load_scenario

G = 9.81

BASE = """
title = "bias tilt"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "1 h"
step = "1 s"
record = "60 s"
method = "rk4"
[[case]]
accel_bias_x = "100 ug"
"""


def same_values(a, b) -> bool:
    """Equal arrays, NaN equal to NaN; text (the failure reasons, read as another string
    type from NetCDF than from Zarr) compared as text."""
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind in "fc" or b.dtype.kind in "fc":
        return np.array_equal(a, b, equal_nan=True)
    if a.dtype.kind in "iub" and b.dtype.kind in "iub":
        return np.array_equal(a, b)
    return a.shape == b.shape and [str(v) for v in a.ravel()] == [str(v) for v in b.ravel()]


def scenario_file(tmp_path, sweep: str, base: str = BASE, name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(base) + textwrap.dedent(sweep))
    return path


def test_static_bias_tilt_and_second_order_residual_across_the_grid(tmp_path, capsys):
    """At rest an accelerometer bias b swings the platform through 2b/g (Schuler; 1 h is
    past half a period), at every latitude; the linear model's miss is second order, so
    the linear/direct ratio grows in proportion to b."""
    path = scenario_file(tmp_path, """
        [sweep]
        latitude = ["10 deg", "80 deg"]
        accel_bias_x = ["50 ug", "200 ug"]
    """)
    store = tmp_path / "bias.zarr"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial", "--json",
                 "--no-progress", "--plot", str(tmp_path / "p.png"), "--figure",
                 "max_direct:alpha_y", "--against", "accel_bias_x"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["points"] == 4 and data["computed"] == 4 and data["reused"] == 0
    rows = data["summary"]
    assert [r["latitude"] for r in rows] == pytest.approx(np.radians([10, 10, 80, 80]))
    assert [r["accel_bias_x"] for r in rows] == pytest.approx(
        np.array([50e-6, 200e-6, 50e-6, 200e-6]) * 9.80665)
    for r in rows:
        assert r["max_direct"]["alpha_y"] == pytest.approx(2 * r["accel_bias_x"] / G,
                                                           rel=0.015)
    for small, large in ((rows[0], rows[1]), (rows[2], rows[3])):
        assert large["worst_linear_ratio"] / small["worst_linear_ratio"] == pytest.approx(
            4.0, rel=0.01)
    assert (tmp_path / "p.png").stat().st_size > 1000
    # the store is a labelled xarray dataset with units
    import xarray as xr

    with warnings.catch_warnings():
        warnings.simplefilter("error")           # consolidated metadata, no warning
        ds = xr.open_zarr(store, chunks=None)
    assert ds["direct"].dims == ("point", "time", "quantity")
    assert ds["time"].attrs["units"] == "s" and ds["latitude"].attrs["units"] == "rad"
    assert ds["quantity_unit"].sel(quantity="delta_v_N").item() == "m/s"
    assert ds["time"].values[-1] == 3600.0 and int(ds["done"].sum()) == 4


def test_monte_carlo_draws_are_seeded_per_draw(tmp_path):
    """Draw k adds the same Gaussian value at every grid point; the tilt follows 2b/g of
    that draw's bias; another seed gives other draws (stored as NetCDF this time)."""
    sweep = """
        [sweep]
        latitude = ["30 deg", "60 deg"]
        draws = 3
        seed = 5
        [sweep.random]
        accel_bias_y = "100 ug"
    """
    base = BASE.replace('accel_bias_x = "100 ug"', 'accel_bias_y = "0 ug"')
    scenario = load_scenario(scenario_file(tmp_path, sweep, base))
    result = sw.run_sweep(scenario, tmp_path / "mc.zarr", engine="serial")
    ds = result.dataset
    assert list(ds["draw"].values) == [0, 1, 2, 0, 1, 2]
    bias = ds["source_value"].sel(source="accel_bias_y").values
    assert np.array_equal(bias[:3], bias[3:]) and len(set(bias[:3])) == 3
    assert not np.any(ds["source_value"].drop_sel(source="accel_bias_y").values)
    alpha_x = ds["max_direct"].sel(quantity="alpha_x").values
    assert alpha_x == pytest.approx(2 * np.abs(bias) / G, rel=0.015)
    # over the draws of each latitude: RMS of the tilt = 2 RMS(b)/g
    stats = sr.over_draws(ds)
    assert [row["draws"] for row in stats] == [3, 3]
    assert [row["latitude"] for row in stats] == pytest.approx(np.radians([30, 60]))
    for row in stats:
        assert row["rms_max_direct"]["alpha_x"] == pytest.approx(
            2 * np.sqrt(np.mean(bias[:3] ** 2)) / G, rel=0.015)
    other = load_scenario(scenario_file(tmp_path, sweep.replace("seed = 5", "seed = 6"),
                                        base, name="t.toml"))
    again = sw.run_sweep(other, tmp_path / "mc6.nc", engine="serial").dataset
    assert not np.any(again["source_value"].sel(source="accel_bias_y").values[:3] == bias[:3])


def test_interrupted_sweep_resumes_with_only_the_unfinished_points(tmp_path, monkeypatch,
                                                                   capsys):
    path = scenario_file(tmp_path, """
        [sweep]
        latitude = ["20 deg", "40 deg", "60 deg"]
        accel_bias_x = ["50 ug", "100 ug"]
    """, BASE.replace('"1 h"', '"5 min"')).as_posix()
    runs: list = []
    real = sw.run_point

    def counted(job):
        runs.append(job)
        return real(job)

    monkeypatch.setattr(sw, "run_point", counted)
    clean = sw.run_sweep(load_scenario(path), tmp_path / "clean.zarr", engine="serial")
    assert len(runs) == 6
    runs.clear()

    def interrupt(index: int) -> None:
        if index == 2:
            raise KeyboardInterrupt

    store = tmp_path / "broken.zarr"
    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(load_scenario(path), store, engine="serial", on_result=interrupt)
    assert len(runs) == 3
    runs.clear()
    # the same command again: the three stored points are read back, three are computed
    assert main(["sweep", path, "--store", str(store), "--engine", "serial", "--json",
                 "--no-progress"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["computed"], data["reused"]) == (3, 3)
    assert len(runs) == 3
    resumed = sw.run_sweep(load_scenario(path), store, engine="serial")
    assert (resumed.computed, resumed.reused, len(runs)) == (0, 6, 3)
    for name in clean.dataset.data_vars:
        assert same_values(clean.dataset[name].values, resumed.dataset[name].values), name


@pytest.mark.parametrize("sweep, message", [
    ("[sweep]\nlatitud = ['10 deg']\n", "did you mean 'latitude'"),
    ("[sweep]\nlatitude = ['10']\n", "needs a unit"),
    ("[sweep]\nlatitude = ['nan']\n", "'nan' is not a finite number"),
    # TOML numbers without a unit are refused as in [run], [motion], [[case]], specs
    ("[sweep]\nlatitude = [0.5, 0.8]\n",
     "s.toml [sweep] latitude: 0.5 has no unit; give an angle"),
    ("[sweep]\nheading = { start = 0, stop = 1, count = 2 }\n",
     "s.toml [sweep] heading: 1 has no unit; give an angle"),
    ("[sweep]\naccel_bias_x = [0.0001]\n",
     "s.toml [sweep] accel_bias_x: 0.0001 has no unit; give an acceleration"),
    ("[sweep]\nduration = [3600]\n", "s.toml [sweep] duration: 3600 has no unit; give a time"),
    ("[sweep]\ndraws = 2\n[sweep.random]\ngyro_drift_y = 0.01\n",
     "s.toml [sweep.random] gyro_drift_y: 0.01 has no unit; give an angular rate"),
    ("[sweep]\nlatitude = []\n", "non-empty list"),
    ("[sweep]\nheading = { start = '0 deg', stop = '9 deg' }\n", "count = N"),
    ("[sweep]\ndraws = 5\n", "go together"),
    ("[sweep]\ndraws = 5\n[sweep.random]\ngyro_drift = '1 deg/h'\n", "gyro_drift_x"),
    ("[sweep]\nduration = ['0 h']\n", "positive"),
    ("[sweep]\nduration = ['90.5 s']\n", "whole number"),
    ("[sweep]\nseed = 3\n", "no parameter grid"),
    ("sweep = 3\n", "must be a table"),
])
def test_bad_sweep_tables_are_one_line_errors(tmp_path, capsys, sweep, message):
    base = BASE if not sweep.startswith("sweep =") else "sweep = 3\n" + BASE
    path = scenario_file(tmp_path, "" if sweep.startswith("sweep =") else sweep, base)
    assert main(["sweep", str(path), "--engine", "serial", "--store",
                 str(tmp_path / "x.zarr")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


POLE = (BASE.replace('kind = "static"', 'kind = "great-circle"\nheading = "0 deg"')
        .replace('"1 h"', '"10 min"'))
"""A flight north at 250 m/s (the default speed): from 89.5° N it reaches the pole after
about 56 km, 220 s, inside the 10-min run; from 10°, 30° or 60° it does not."""


@pytest.mark.parametrize("engine", ["serial", "pool"])
def test_a_point_over_the_pole_is_stored_as_failed_and_the_others_run(tmp_path, capsys,
                                                                      monkeypatch, engine):
    """One point whose motion reaches the pole does not stop the sweep: the other three
    run and are stored bit-identical to a sweep without the bad point, the failed point
    keeps its reason and NaN data, the command lists it and exits 3, and running the same
    command again runs nothing (the same input fails the same way)."""
    bad = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '89.5 deg', '30 deg', "
                                  "'60 deg']\n", POLE, name="bad.toml")
    good = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '30 deg', '60 deg']\n",
                         POLE, name="good.toml")
    store = tmp_path / "bad.zarr"
    assert main(["sweep", str(bad), "--engine", engine, "--workers", "2", "--store",
                 str(store), "--no-progress"]) == 3
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert lines[0].startswith("ins-errors: store: 4 points, about ")
    assert lines[1] == ("ins-errors: sweep 'bias tilt', 4 points, 4 to compute, 0 already "
                        f"in {store}")
    assert lines[2] == ("ins-errors: 1 of 4 points failed (stored without "
                        "results; --retry-failed runs them again):")
    assert lines[3].startswith("  point 1 (latitude = 89.5 deg): the true "
                               "motion leaves the model's domain at t = ")
    assert len(lines) == 4
    assert "4 points, 4 computed" in out and "failed" in out   # the table's row says so
    reference = sw.run_sweep(load_scenario(good), tmp_path / "good.zarr",
                             engine="serial").dataset
    import xarray as xr

    data = xr.open_zarr(store, chunks=None)
    assert list(data["done"].values) == [1, 1, 1, 1]
    reasons = [str(v) for v in data["failure"].values]
    assert reasons[0] == reasons[2] == reasons[3] == ""
    assert reasons[1].startswith("the true motion leaves the model's domain")
    assert "\n" not in reasons[1]
    for name in reference.data_vars:
        kept = data[name].values[[0, 2, 3]]
        assert same_values(kept, reference[name].values), name
        if name != "failure" and data[name].dtype.kind == "f":
            assert np.all(np.isnan(data[name].values[1])), name
    assert not np.any(data["excited"].values[1])
    # --json: the failed point with its parameters and reason; the same command again
    # runs nothing
    runs: list = []
    real = sw.run_point
    monkeypatch.setattr(sw, "run_point", lambda job: runs.append(job) or real(job))
    assert main(["sweep", str(bad), "--engine", "serial", "--store", str(store),
                 "--json"]) == 3
    report = json.loads(capsys.readouterr().out)
    assert runs == [] and (report["computed"], report["reused"]) == (0, 4)
    [failed] = report["failed"]
    assert failed["point"] == 1 and failed["latitude"] == pytest.approx(np.radians(89.5))
    assert failed["label"] == "latitude = 89.5 deg" and failed["reason"] == reasons[1]
    assert [r["failure"] for r in report["summary"]] == [None, reasons[1], None, None]
    assert report["summary"][1]["worst_linear_ratio"] is None
    # asked to, it runs the failed point again (only it), which fails the same way
    assert main(["sweep", str(bad), "--engine", "serial", "--store", str(store),
                 "--retry-failed", "--json"]) == 3
    assert json.loads(capsys.readouterr().out)["failed"] == [failed]
    assert [job.label for job in runs] == ["latitude = 89.5 deg"]


@pytest.mark.parametrize("against", [None, "latitude"])
def test_plot_of_a_sweep_whose_every_point_failed_says_there_is_nothing_to_plot(
        tmp_path, capsys, against):
    """Every point reaches the pole: --plot (a colour map over two swept parameters, or
    a line over one) has no value to draw. Was: an IndexError traceback, exit 1, neither
    the table nor the failed points printed; now the same table and list as without
    --plot, one line saying nothing was plotted, exit 3 (the failed points), no file."""
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['89.5 deg', '89.7 deg']\n"
                                   "accel_bias_x = ['50 ug', '100 ug']\n", POLE)
    store, png = tmp_path / "s.zarr", tmp_path / "map.png"
    command = ["sweep", str(path), "--engine", "serial", "--store", str(store),
               "--no-progress"]
    assert main(command) == 3
    plain_out, plain_err = capsys.readouterr()
    assert main([*command, "--plot", str(png),
                 *(["--against", against] if against else [])]) == 3
    out, err = capsys.readouterr()
    assert out == plain_out.replace("4 computed (this process), 0 read back",
                                    "0 computed (nothing to run), 4 read back")
    assert out.count("failed") == 4   # the table's rows
    lines = err.splitlines()
    assert lines[2] == f"ins-errors: nothing to plot, {png} not written: every point failed"
    assert lines[3:] == plain_err.splitlines()[2:]   # the failed points, as without --plot
    assert lines[3].startswith("ins-errors: 4 of 4 points failed")
    assert not png.exists()


def test_a_failed_point_that_runs_again_is_stored_like_the_others(tmp_path, monkeypatch,
                                                                  capsys):
    """A point recorded as failed and run again with --retry-failed gets its results and
    loses its failure; a NetCDF store keeps its partial Zarr folder while a point has
    failed and is rewritten without the failure."""
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '30 deg']\n",
                         BASE.replace('"1 h"', '"2 min"'))
    clean = sw.run_sweep(load_scenario(path), tmp_path / "clean.zarr",
                         engine="serial").dataset
    real = sw.run_point

    def flaky(job):
        if job.label == "latitude = 30 deg":
            raise sw.PointError(job.label, "a made-up failure")
        return real(job)

    monkeypatch.setattr(sw, "run_point", flaky)
    store = tmp_path / "s.nc"
    result = sw.run_sweep(load_scenario(path), store, engine="serial")
    assert result.failed == [1] and store.exists()
    assert (tmp_path / "s.nc.partial.zarr").exists()
    assert list(result.dataset["failure"].values) == ["", "a made-up failure"]
    assert main(["sweep", str(path), "--engine", "serial", "--store", str(store)]) == 3
    assert "point 1 (latitude = 30 deg): a made-up failure" in capsys.readouterr().err
    monkeypatch.setattr(sw, "run_point", real)
    again = sw.run_sweep(load_scenario(path), store, engine="serial", retry_failed=True)
    assert (again.computed, again.reused, again.failed) == (1, 1, [])
    assert not (tmp_path / "s.nc.partial.zarr").exists()
    for name in clean.data_vars:
        assert same_values(clean[name].values, again.dataset[name].values), name


def test_a_store_made_before_failures_were_recorded_resumes(tmp_path):
    """A store without the failure variable (as made before it existed) is read as no
    point failed, gains the variable on resuming and records a failure in it."""
    import zarr

    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '89.5 deg']\n", POLE)
    store = tmp_path / "old.zarr"

    def stop(index: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(load_scenario(path), store, engine="serial", on_result=stop)
    group = zarr.open_group(str(store), mode="r+", zarr_format=2)
    del group["failure"]
    zarr.consolidate_metadata(str(store), zarr_format=2)
    assert "failure" not in zarr.open_group(str(store), mode="r").array_keys()
    result = sw.run_sweep(load_scenario(path), store, engine="serial")
    assert (result.computed, result.reused, result.failed) == (1, 1, [1])
    assert sr.failures(result.dataset)[0]["label"] == "latitude = 89.5 deg"


def test_store_of_another_sweep_is_refused(tmp_path, capsys):
    """Other grid values extend a store; any other setting (here the case's bias, not
    swept) is another sweep, refused in one line naming it."""
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '20 deg']\n",
                         BASE.replace('"1 h"', '"2 min"'))
    store = str(tmp_path / "s.zarr")
    assert main(["sweep", str(path), "--store", store, "--engine", "serial"]) == 0
    capsys.readouterr()
    other = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '30 deg']\n",
                          BASE.replace('"1 h"', '"2 min"').replace('"100 ug"', '"50 ug"'),
                          name="o.toml")
    assert main(["sweep", str(other), "--store", store, "--engine", "serial"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "holds another sweep: [[case]] 1 accel_bias_x is " \
        "0.000980665 m/s**2 there, 0.0004903325 m/s**2 here; a store takes other [sweep] " \
        "grid values only" in err, err
    assert "[sweep] latitude" not in err  # the grid may change
    assert main(["sweep", str(tmp_path / "s.toml").replace("s.toml", "missing.toml")]) == 2
    plain = tmp_path / "plain.toml"
    plain.write_text(BASE)
    assert main(["sweep", str(plain)]) == 2
    assert "no [sweep] table" in capsys.readouterr().err


@pytest.mark.parametrize("store, message", [
    ("a_file/x.zarr", "cannot write the sweep store"),        # a parent that is a file
    ("not_netcdf.nc", "is not a readable NetCDF sweep store"),  # a .nc that is not one
    ("x.txt", "has suffix '.txt': name it *.zarr (a Zarr folder"),  # no such format
    ("results", "has no suffix: name it *.zarr (a Zarr folder"),
])
def test_a_store_that_cannot_be_made_or_read_is_one_line(tmp_path, capsys, store, message):
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "not_netcdf.nc").write_text("garbage")
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '20 deg']\n",
                         BASE.replace('"1 h"', '"2 min"'))
    status = main(["sweep", str(path), "--store", str(tmp_path / store), "--engine",
                   "serial"])
    err = capsys.readouterr().err
    assert status == 2 and message in err and len(err.strip().splitlines()) == 1, err
    if "suffix" in message:  # refused before anything was made
        assert "*.nc (a NetCDF file" in err and not (tmp_path / store).exists()


def test_colour_map_cells_are_centred_on_the_swept_values(tmp_path, monkeypatch):
    """A two-parameter map draws one cell per grid value with the value inside it: every
    inner cell edge halfway between neighbours, the outer edges as far beyond the first
    and last values (those centred in their cells), and a tick at every value run (with
    edges at the first and last values, a 2 x 2 map showed each value at a corner of its
    cell)."""
    from ins_errors import output

    figures = []
    saved = output.save_figure
    monkeypatch.setattr(output, "save_figure",
                        lambda figure, path, **kw: figures.append(figure) or saved(
                            figure, path, close=False, **kw))
    latitudes, biases = [10.0, 30.0, 80.0], [50.0, 200.0]  # deg, ug (uneven on purpose)
    path = scenario_file(tmp_path, f"""
        [sweep]
        latitude = {[f"{v:g} deg" for v in latitudes]}
        accel_bias_x = {[f"{v:g} ug" for v in biases]}
    """, BASE.replace('"1 h"', '"2 min"').replace('"60 s"', '"1 min"'))
    data = sw.run_sweep(load_scenario(path), tmp_path / "map.zarr", engine="serial").dataset
    sr.plot(data, "worst_linear_ratio", ["latitude", "accel_bias_x"], tmp_path / "map.png")
    [figure] = figures
    ax = figure.axes[0]
    [mesh] = ax.collections
    corners = mesh.get_coordinates()  # (rows + 1, columns + 1, 2) cell corners
    for values, limits, edges, ticks in (
            (latitudes, ax.get_xlim(), corners[0, :, 0], ax.get_xticks()),
            (biases, ax.get_ylim(), corners[:, 0, 1], ax.get_yticks())):
        assert limits == pytest.approx((edges[0], edges[-1]), rel=1e-12)
        assert list(edges[1:-1]) == pytest.approx([(a + b) / 2
                                                   for a, b in itertools.pairwise(values)])
        centres = [(lo + hi) / 2 for lo, hi in itertools.pairwise(edges)]
        assert (centres[0], centres[-1]) == pytest.approx((values[0], values[-1]))
        assert all(lo < v < hi for (lo, hi), v in zip(itertools.pairwise(edges), values,
                                                      strict=True))
        assert list(ticks) == pytest.approx(values)
    import matplotlib.pyplot as plt

    plt.close(figure)


def test_sweep_summary_reports_each_points_integration_error(tmp_path, capsys):
    """Every point keeps compare's step-doubling estimate: negligible with RK4 at 10 s;
    with the rectangle method at 10 s about the growth of its Schuler swing,
    (1 + ω²τ²)^(t/2τ) − 1 with ω² = g/R (2.8 % in an hour)."""
    base = BASE.replace('step = "1 s"', 'step = "10 s"')
    path = scenario_file(tmp_path, '[sweep]\nstep = ["10 s"]\n', base=base)
    assert main(["sweep", str(path), "--store", str(tmp_path / "r.zarr"), "--engine",
                 "serial", "--no-progress"]) == 0
    assert "integ. err/err" in capsys.readouterr().out
    assert main(["sweep", str(path), "--store", str(tmp_path / "r2.zarr"), "--engine",
                 "serial", "--json", "--no-progress"]) == 0
    [row] = json.loads(capsys.readouterr().out)["summary"]
    assert row["worst_integration_error_ratio"] < 1e-6
    assert set(row["integration_error"]) == set(row["max_direct"])
    euler = scenario_file(tmp_path, '[sweep]\nstep = ["10 s"]\n', name="e.toml",
                          base=base.replace('method = "rk4"', 'method = "euler"'))
    assert main(["sweep", str(euler), "--store", str(tmp_path / "e.zarr"), "--engine",
                 "serial", "--json", "--no-progress"]) == 0
    [row] = json.loads(capsys.readouterr().out)["summary"]
    tau, t = 10.0, 3600.0
    growth = (1 + G / 6.371e6 * tau**2) ** (t / (2 * tau)) - 1
    assert 0.5 < row["worst_integration_error_ratio"] / growth < 2.0


def test_sweep_records_the_model_parameters_it_set(tmp_path, capsys):
    """Like compare/budget/validity/run JSON: --json and the store's attributes carry
    ``parameters`` (name -> SI value and unit; {} when the scenario sets none); the swept
    parameters' units are under ``swept``."""
    import xarray as xr

    short = BASE.replace('"1 h"', '"2 min"').replace('"1 s"', '"60 s"')
    sweep = '[sweep]\nlatitude = ["50 deg"]\n'
    # 6400 km = 6.4e6 m, converted by hand
    cases = {"set": ('[parameters]\na = "6400 km"\n', {"a": {"value": 6.4e6, "unit": "m"}}),
             "none": ("", {})}
    for name, (table, expected) in cases.items():
        path = scenario_file(tmp_path, table + sweep, short,
                             name=f"{name}.toml")
        store = tmp_path / f"{name}.nc"
        assert main(["sweep", str(path), "--store", str(store), "--engine", "serial",
                     "--json", "--no-progress"]) == 0
        data = json.loads(capsys.readouterr().out)
        assert data["parameters"] == expected, name
        assert data["swept"] == {"latitude": "rad"}
        with xr.open_dataset(store) as ds:
            assert sr.model_parameters(ds) == expected, name


def test_points_run_without_pint_and_give_the_bits_of_the_motion_as_written(tmp_path,
                                                                            monkeypatch):
    """A point's job carries its motion in exact SI text too (a worker builds the true
    motion and labels its case without importing pint), with the same numbers as the
    motion as written; the sweep's identity (store fingerprint) is that of the written
    motion alone."""
    path = scenario_file(tmp_path, """
        [sweep]
        latitude = ["35 deg"]
        accel_bias_x = ["70 ug"]
    """, BASE.replace('"static"', '"great-circle"').replace('"1 h"', '"5 min"'))
    jobs = sw.grid(load_scenario(path)).jobs
    written = [dataclasses.replace(job, motion_si=()) for job in jobs]
    assert sw.fingerprint(jobs, {}) == sw.fingerprint(written, {})
    assert dict(jobs[0].motion_si)["longitude"].endswith(" rad")  # the default "30 deg"
    expected = sw.run_point(written[0])

    def refuse():
        raise AssertionError("pint was asked for a unit")

    sw._trajectory.cache_clear()
    monkeypatch.setattr(units, "registry", refuse)
    got = sw.run_point(jobs[0])
    assert sorted(got) == sorted(expected)
    for name, values in expected.items():
        assert np.array_equal(got[name], values, equal_nan=True), name


def test_the_list_of_failed_points_is_capped_for_large_sweeps():
    """25 points of which 13 failed: the first 10 are listed, then how many more."""
    import xarray as xr

    reasons = ["" if k % 2 else f"reason {k}" for k in range(25)]
    data = xr.Dataset({"failure": ("point", np.array(reasons, dtype=object))},
                      coords={"point": np.arange(25),
                              "latitude": ("point", np.radians(np.arange(25.0)),
                                           {"units": "rad", "display_unit": "deg"})},
                      attrs={"swept": json.dumps(["latitude"])})
    lines = sr.failures_text(data).splitlines()
    assert lines[0].startswith("13 of 25 points failed")
    assert lines[1] == "  point 0 (latitude = 0 deg): reason 0"
    assert lines[10] == "  point 18 (latitude = 18 deg): reason 18"
    assert lines[11] == "  ... and 3 more (--json lists them all)" and len(lines) == 12
    assert [r["point"] for r in sr.failures(data)] == list(range(0, 25, 2))


def test_failed_draws_are_not_left_out_of_the_statistics(tmp_path):
    """Over the draws of a grid point, a draw that failed makes the statistics unknown
    (None) and is named, rather than being dropped from the RMS and the largest value."""
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '89.5 deg']\ndraws = 2\n"
                                   "seed = 3\n[sweep.random]\naccel_bias_y = '50 ug'\n", POLE)
    result = sw.run_sweep(load_scenario(path), tmp_path / "d.zarr", engine="serial")
    assert result.failed == [2, 3]
    ok, bad = sr.over_draws(result.dataset)
    assert ok["failed_draws"] == [] and ok["rms_max_direct"]["delta_latitude"] > 0
    assert bad["failed_draws"] == [0, 1] and bad["largest_worst_linear_ratio"] is None
    assert bad["rms_max_direct"]["delta_latitude"] is None
    assert "failed" in sr.draws_table(result.dataset).splitlines()[0]


def test_an_interrupted_sweep_says_what_the_store_keeps(tmp_path, monkeypatch, capsys):
    """Ctrl-C in a sweep printed only "ins-errors: interrupted" (the long-flight probe):
    nothing said that the points done were kept, nor how to go on. The line now says how
    many of the points are in the store (counted here by reading the store back) and
    that the same command runs the others."""
    path = scenario_file(tmp_path, """
        [sweep]
        latitude = ["20 deg", "40 deg", "60 deg"]
    """, BASE.replace('"1 h"', '"5 min"')).as_posix()
    real, runs = sw.run_point, []

    def third_interrupts(job):
        runs.append(job)
        if len(runs) == 3:
            raise KeyboardInterrupt
        return real(job)

    monkeypatch.setattr(sw, "run_point", third_interrupts)
    store = tmp_path / "part.zarr"
    assert main(["sweep", path, "--store", str(store), "--engine", "serial",
                 "--no-progress"]) == 130
    line = capsys.readouterr().err.strip().splitlines()[-1]
    monkeypatch.setattr(sw, "run_point", real)
    kept = sw.run_sweep(load_scenario(path), store, engine="serial").reused
    assert kept == 2
    assert line == (f"ins-errors: interrupted: {kept} of the 3 points are in {store}; "
                    "the same command runs the others")


def test_swept_values_are_shown_with_the_digits_that_tell_them_apart(tmp_path, capsys):
    """A point at 89.99999° is not named "latitude = 90 deg" (a pole, which the file
    does not sweep), nor 45.000001° "45 deg" beside a point at 45°: the messages and the
    table show each value with the digits that read back as the value written; a value
    that round-trips through radians (15° of a range) keeps its short text."""
    written = ["45", "45.000001", "89.99999"]
    base = BASE.replace('duration = "1 h"', 'duration = "1 min"').replace(
        'step = "1 s"', 'step = "10 s"').replace('record = "60 s"', 'record = "30 s"')
    path = scenario_file(tmp_path, "[sweep]\nlatitude = [" + ", ".join(
        f'"{w} deg"' for w in written) + "]\n", base=base)
    labels = [job.label for job in sw.grid(load_scenario(path)).jobs]
    assert labels == [f"latitude = {w} deg" for w in written]
    assert main(["sweep", str(path), "--engine", "serial", "--store",
                 str(tmp_path / "s.zarr"), "--no-progress"]) == 3
    out, err = capsys.readouterr()
    assert "(latitude = 89.99999 deg): " in err and "= 90 deg" not in err
    lines = out.splitlines()
    start = next(k for k, line in enumerate(lines) if line.lstrip().startswith("latitude"))
    column = [line.split()[0] for line in lines[start + 1:start + 4]]
    assert [float(c) for c in column] == [float(w) for w in written]
    ranged = scenario_file(tmp_path, '[sweep]\nlatitude = { start = "0 deg", stop = "75 deg", '
                           "count = 6 }\n", base=base, name="r.toml")
    assert [job.label for job in sw.grid(load_scenario(ranged)).jobs] == [
        f"latitude = {15 * k} deg" for k in range(6)]


@pytest.mark.parametrize("value, least, text", [
    (89.99999, 6, "89.99999"), (90.0, 6, "90"), (15.000000000000002, 6, "15"),
    (45.000001, 6, "45.000001"), (1e-5, 6, "1e-05"), (0.0, 6, "0"), (2 / 3, 3, "0.6666666667"),
    (0.1 + 0.2, 6, "0.3")])
def test_number_text_keeps_what_tells_the_value_apart(value, least, text):
    assert sw.number_text(value, least) == text


def test_run_refuses_a_sweep_file_and_names_the_command_that_runs_it(tmp_path, capsys):
    """`ins-errors run` on a file with a [sweep] table ran the scenario without its grid,
    saying nothing: it is refused in one line naming `ins-errors sweep`, before any
    work (no report folder is made)."""
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['10 deg', '30 deg']\n")
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert "[sweep]" in captured.err and f"ins-errors sweep {path}" in captured.err
    assert not out.exists()


def test_a_sweep_of_one_point_says_one_point(tmp_path, capsys):
    """Was: 'bias tilt: 1 points, 1 computed'."""
    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['20 deg']\n",
                         BASE.replace('"1 h"', '"5 min"'))
    assert main(["sweep", str(path), "--engine", "serial", "--store",
                 str(tmp_path / "one.zarr"), "--no-progress"]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("bias tilt: 1 point, 1 computed (this process), 0 read back")
    assert ", 1 point, 1 to compute," in err


def test_a_store_of_the_earlier_judging_rule_is_another_sweep(tmp_path):
    """Quantities were once judged by a share of the largest error of their unit; a store
    made under that rule mixed with points of the new one without a word. The rule is
    part of the sweep's identity and its settings, so such a store is named as differing
    in it."""
    from ins_errors.analysis import store as st

    path = scenario_file(tmp_path, "[sweep]\nlatitude = ['20 deg', '40 deg']\n",
                         BASE.replace('"1 h"', '"5 min"'))
    scenario = load_scenario(path)
    layout = sw.layout(scenario, sw.grid(scenario))
    settings = json.loads(layout.attributes["settings"]) if isinstance(
        layout.attributes["settings"], str) else dict(layout.attributes["settings"])
    assert settings["quantities judged"] == sw.JUDGING
    del settings["quantities judged"]          # what a store of the earlier rule recorded
    older = {"fingerprint": "0" * 32, "settings": json.dumps(settings)}
    assert st.mismatch(older, layout) == (
        f"another sweep: quantities judged is absent there, {sw.JUDGING} here")


EXTEND = BASE.replace('"1 h"', '"5 min"').replace('accel_bias_x = "100 ug"',
                                                  'gyro_drift_x = "0.01 deg/h"')


def _counted(monkeypatch) -> list[str]:
    """The labels of the points run from now on (every point goes through run_point)."""
    runs: list[str] = []
    real = sw.run_point

    def counted(job):
        runs.append(job.label)
        return real(job)

    monkeypatch.setattr(sw, "run_point", counted)
    return runs


def _same_sweep(got, fresh) -> None:
    """Every variable and coordinate of two sweeps' datasets equal to the last bit,
    and their attributes equal."""
    assert set(got.variables) == set(fresh.variables)
    for name in fresh.variables:
        assert got[name].dtype == fresh[name].dtype, name
        assert same_values(got[name].values, fresh[name].values), name
    assert got.attrs == fresh.attrs


@pytest.mark.parametrize("suffix", ["zarr", "nc"])
def test_a_store_extended_by_grid_values_computes_only_the_new_points(tmp_path, capsys,
                                                                      monkeypatch, suffix):
    """A 2-point drift sweep extended to 3 drifts runs one point; its results are those
    of a fresh 3-point sweep to the last bit. The store keeps every point it ran: a
    latitude grid beside the [motion] latitude reuses the points at that latitude, the
    first grid again runs nothing, and a longer run lengthens the store's time axis."""
    runs = _counted(monkeypatch)
    two = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', '0.01 deg/h']\n",
                        EXTEND, name="two.toml")
    three = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', "
                          "'0.005 deg/h', '0.01 deg/h']\n", EXTEND, name="three.toml")
    store = str(tmp_path / f"s.{suffix}")
    assert main(["sweep", str(two), "--store", store, "--engine", "serial",
                 "--no-progress"]) == 0
    assert len(runs) == 2
    runs.clear()
    capsys.readouterr()
    assert main(["sweep", str(three), "--store", store, "--engine", "serial", "--json",
                 "--no-progress"]) == 0
    captured = capsys.readouterr()
    assert runs == ["gyro_drift_x = 0.005 deg/h"]
    assert (f"3 points, 1 to compute, 2 already in {store} (extended: it keeps 0 points "
            "of other grids)") in captured.err
    data = json.loads(captured.out)
    assert (data["points"], data["computed"], data["reused"]) == (3, 1, 2)
    extended = sw.run_sweep(load_scenario(three), store, engine="serial")
    assert (extended.computed, extended.reused, len(runs)) == (0, 3, 1)
    fresh = sw.run_sweep(load_scenario(three), tmp_path / f"fresh.{suffix}",
                         engine="serial")
    _same_sweep(extended.dataset.load(), fresh.dataset.load())
    assert data["summary"] == sr.summary(fresh.dataset)
    runs.clear()
    # a latitude grid: the points at the [motion] latitude (50°) are the stored ones
    wide = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', '0.01 deg/h']"
                         "\nlatitude = ['50 deg', '60 deg']\n", EXTEND, name="wide.toml")
    result = sw.run_sweep(load_scenario(wide), store, engine="serial")
    assert (result.computed, result.reused, result.others) == (2, 2, 1)
    assert runs == ["gyro_drift_x = 0.001 deg/h, latitude = 60 deg",
                    "gyro_drift_x = 0.01 deg/h, latitude = 60 deg"]
    runs.clear()
    longer = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.01 deg/h']\n"
                           "duration = ['5 min', '10 min']\n", EXTEND, name="long.toml")
    result = sw.run_sweep(load_scenario(longer), store, engine="serial")
    assert (result.computed, result.reused, result.others) == (1, 1, 4)
    assert result.dataset.sizes["time"] == 11  # 10 min every 60 s
    fresh = sw.run_sweep(load_scenario(longer), tmp_path / f"long.{suffix}",
                         engine="serial")
    _same_sweep(result.dataset.load(), fresh.dataset.load())
    runs.clear()
    again = sw.run_sweep(load_scenario(two), store, engine="serial")
    assert (again.computed, again.reused, again.others, runs) == (0, 2, 4, [])
    assert again.dataset.sizes["time"] == 6  # its own 5 min, not the store's 10
    kept = sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("s."))
    assert kept == [f"s.{suffix}"]  # no scratch or previous store left beside it


def test_a_store_made_before_points_had_keys_is_extended(tmp_path, monkeypatch):
    """A store without point keys (made before they existed) is matched by rebuilding
    its grid from its coordinates; only the new drift runs, and the sweep is then the
    fresh one."""
    import zarr

    runs = _counted(monkeypatch)
    two = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', '0.01 deg/h']\n",
                        EXTEND, name="two.toml")
    three = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', "
                          "'0.005 deg/h', '0.01 deg/h']\n", EXTEND, name="three.toml")
    store = tmp_path / "old.zarr"
    sw.run_sweep(load_scenario(two), store, engine="serial")
    group = zarr.open_group(str(store), mode="r+", zarr_format=2)
    del group["point_key"]
    attrs = dict(group.attrs)
    attrs["coordinates"] = " ".join(n for n in attrs["coordinates"].split()
                                    if n != "point_key")
    group.attrs.put(attrs)
    zarr.consolidate_metadata(str(store), zarr_format=2)
    runs.clear()
    result = sw.run_sweep(load_scenario(three), store, engine="serial")
    assert (result.computed, result.reused, runs) == (1, 2, ["gyro_drift_x = 0.005 deg/h"])
    fresh = sw.run_sweep(load_scenario(three), tmp_path / "fresh.zarr", engine="serial")
    _same_sweep(result.dataset.load(), fresh.dataset.load())


def test_an_interrupted_extension_resumes_and_leaves_the_store_whole(tmp_path, monkeypatch):
    """Stopped while its new points run, an extension keeps the store's old points and
    the new ones already run; the same command computes only the rest. Stopped while
    the rewritten store was being put in place, the old store is restored."""
    from ins_errors.analysis import store as st

    runs = _counted(monkeypatch)
    two = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', '0.01 deg/h']\n",
                        EXTEND, name="two.toml")
    four = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', '0.002 deg/h',"
                         " '0.005 deg/h', '0.01 deg/h']\n", EXTEND, name="four.toml")
    store = tmp_path / "s.zarr"
    sw.run_sweep(load_scenario(two), store, engine="serial")
    # stopped between moving the old store aside and putting the new one in place
    real_rename = type(store).rename

    def stop_at_second(self, target):
        if str(self).endswith(".extending"):
            raise KeyboardInterrupt
        return real_rename(self, target)

    monkeypatch.setattr(type(store), "rename", stop_at_second)
    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(load_scenario(four), store, engine="serial")
    monkeypatch.setattr(type(store), "rename", real_rename)
    assert not store.exists() and st.stored_source(store) == store  # restored
    assert sw.run_sweep(load_scenario(two), store, engine="serial").computed == 0
    runs.clear()

    def interrupt(index: int) -> None:
        if len(runs) == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sw.run_sweep(load_scenario(four), store, engine="serial", on_result=interrupt)
    runs.clear()
    result = sw.run_sweep(load_scenario(four), store, engine="serial")
    assert (result.computed, result.reused, len(runs)) == (1, 3, 1)
    fresh = sw.run_sweep(load_scenario(four), tmp_path / "fresh.zarr", engine="serial")
    _same_sweep(result.dataset.load(), fresh.dataset.load())


def test_an_edited_motion_file_is_another_point(tmp_path, monkeypatch):
    """A reviewer: a sweep's identity held a motion file's name, not its contents, so a
    sweep over an edited flight log reused the points of the old one (stale numbers). The
    file's hash is now part of the sweep's settings and of each point's key: a store of
    the old flight is another sweep, said in one line."""
    runs = _counted(monkeypatch)
    flight = tmp_path / "flight.csv"
    rows = ["t,v_N,v_E"] + [f"{t},0,{speed}" for t in range(0, 601, 60)
                             for speed in [200.0]]
    flight.write_text("\n".join(rows) + "\n", encoding="utf-8")
    base = EXTEND.replace('kind = "static"', 'kind = "file"\nfile = "flight.csv"').replace(
        'latitude = "50 deg"', 'latitude = "50 deg"\nlongitude = "30 deg"')
    path = scenario_file(tmp_path, "[sweep]\ngyro_drift_x = ['0.001 deg/h', '0.01 deg/h']\n",
                         base)
    store = tmp_path / "s.zarr"
    sw.run_sweep(load_scenario(path), store, engine="serial")
    assert len(runs) == 2
    runs.clear()
    again = sw.run_sweep(load_scenario(path), store, engine="serial")
    assert (again.computed, runs) == (0, [])  # the same file: reused
    flight.write_text("\n".join(r.replace(",0,200.0", ",100.0,200.0") for r in rows)
                      + "\n", encoding="utf-8")  # now also flying north
    with pytest.raises(InsErrorsError, match=r"another sweep: motion file contents is "
                                             r"sha256 [0-9a-f]{16} there, sha256"):
        sw.run_sweep(load_scenario(path), store, engine="serial")
    assert runs == []
    edited = sw.run_sweep(load_scenario(path), tmp_path / "edited.zarr", engine="serial")
    assert edited.computed == 2
    assert not same_values(edited.dataset["linear"].values, again.dataset["linear"].values)


def test_the_sweeps_ratio_is_named_for_what_it_is(tmp_path, monkeypatch, capsys):
    """The number the table and the colour bar call the worst linear ratio is
    max|linear − direct| / max|direct| of the stored curves (the product's linear ratio,
    as compare and the store name it), and their words say so: "worst lin/dir" and
    "worst linear/direct ratio" read as linear ÷ direct, which is about 1 here."""
    from ins_errors import output

    figures = []
    saved = output.save_figure
    monkeypatch.setattr(output, "save_figure",
                        lambda figure, path, **kw: figures.append(figure) or saved(
                            figure, path, close=False, **kw))
    base = BASE.replace('"1 h"', '"10 min"').replace('"1 s"', '"10 s"').replace(
        'record = "60 s"', 'record = "10 s"')
    path = scenario_file(tmp_path, """
        [sweep]
        latitude = ["20 deg", "70 deg"]
        accel_bias_x = ["100 ug", "400 ug"]
    """, base)
    store = tmp_path / "ratio.zarr"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial",
                 "--no-progress", "--plot", str(tmp_path / "map.png")]) == 0
    out = capsys.readouterr().out
    import xarray as xr

    ds = xr.open_zarr(store, chunks=None)
    direct, linear = ds["direct"].values, ds["linear"].values  # (point, time, quantity)
    excited = ds["excited"].values == 1
    expected = [max(np.abs(linear[k, :, q] - direct[k, :, q]).max()
                    / np.abs(direct[k, :, q]).max()
                    for q in np.flatnonzero(excited[k])) for k in range(4)]
    quotient = [max(np.abs(linear[k, :, q]).max() / np.abs(direct[k, :, q]).max()
                    for q in np.flatnonzero(excited[k])) for k in range(4)]
    assert max(expected) < 1e-2 and min(quotient) > 0.5  # the two readings differ
    lines = out.splitlines()
    start = next(k for k, line in enumerate(lines) if line.lstrip().startswith("latitude"))
    head = lines[start]
    assert "worst linear ratio" in head and "lin/dir" not in head
    shown = [float(line.split()[2]) for line in lines[start + 1:start + 5]]
    assert shown == pytest.approx(expected, rel=1e-3)
    assert ("worst linear ratio: max|linear − direct| / max|direct| of the quantity named"
            in out)
    [figure] = figures
    label = figure.axes[1].get_ylabel()  # the colour bar's
    assert label.splitlines() == ["worst linear ratio", "max|linear − direct| / max|direct|"]
    assert sr.figure_values(ds, "linear_ratio:alpha_y")[1].splitlines() == [
        "alpha_y linear ratio", "max|linear − direct| / max|direct|"]
    assert sr.figure_values(ds, "worst_refined_ratio")[1].splitlines()[1] == (
        "max|refined − direct| / max|direct|")
    import matplotlib.pyplot as plt

    plt.close(figure)
