"""Sweeps over model parameters: a damping-gain study of a velocity-damped Schuler loop.

The fixture tests/models/damped_schuler.py is a single-axis Schuler loop whose computed
velocity is pulled towards a reference velocity with the gain k_v; its error loop has
the characteristic polynomial s² + k_v s + g/R. A constant reference velocity error δv_r
drives the tilt ψ (and the latitude error, which follows the same equation) through

    ψ(s) = k_v δv_r / (R s (s² + k_v s + g/R)),

whose inverse transform by the roots p₁, p₂ of that polynomial is the reference the
swept points are checked against (written here, not taken from the tool): the residual
Schuler oscillation damps out and the tilt settles at k_v δv_r / g, the sensitivity to
the reference error that grows with the gain.
"""

from __future__ import annotations

import importlib.util
import json
import textwrap
import types
import warnings
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("zarr")  # the store needs the 'distributed' extra (in 'dev')

from ins_errors.analysis import sweep as sw
from ins_errors.cli import main
from ins_errors.scenario import load_scenario

MODEL = str(Path(__file__).resolve().parent / "models" / "damped_schuler.py")
R, G = 6_371_000.0, 9.80665  # the fixture's defaults

BASE = f"""
title = "damping gain against the reference velocity error"
model = "{MODEL}"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "6 h"
step = "10 s"
record = "60 s"
[parameters]
k_v = "1.24e-3 1/s"   # what a single run would use; the grid replaces it
[[case]]
ref_velocity_error = "1 m/s"
[outputs]
quantities = ["psi", "delta_latitude", "delta_v_N"]
"""


def scenario_file(tmp_path, sweep: str, base: str = BASE, name: str = "gain.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(base) + textwrap.dedent(sweep))
    return path


def damped_response(k_v: float, dv_r: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tilt ψ(t) (rad) and velocity error δV(t) (m/s) of the damped loop to a reference
    velocity error stepped on at t = 0, by partial fractions over the roots of
    s² + k_v s + g/R (distinct roots: not critically damped)."""
    p1, p2 = np.roots([1.0, k_v, G / R]).astype(complex)
    e1, e2 = np.exp(p1 * t), np.exp(p2 * t)
    psi = k_v * dv_r / R * (1 / (p1 * p2) + e1 / (p1 * (p1 - p2)) + e2 / (p2 * (p2 - p1)))
    dv = k_v * dv_r * (e1 - e2) / (p1 - p2)
    return psi.real, dv.real


def test_gain_sweep_follows_the_damped_loop(tmp_path, capsys):
    """Every point of a k_v grid (written as -p writes gains) runs with its own gain, not
    the [parameters] value the grid replaces: the linear and direct curves of ψ, δφ and
    δV are the closed-form step response, the peak is the damped overshoot
    ss (1 + exp(−πζ/√(1 − ζ²))) and the end value the steady tilt k_v δv_r / g; the store
    labels the points with the gain and its unit."""
    path = scenario_file(tmp_path, """
        [sweep]
        k_v = ["5e-4/s", "1e-3/s", "2e-3/s"]
    """)
    store = tmp_path / "gain.zarr"
    plot = tmp_path / "gain.png"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial", "--json",
                 "--no-progress", "--plot", str(plot), "--figure", "max_direct:psi"]) == 0
    out = json.loads(capsys.readouterr().out)
    gains = np.array([5e-4, 1e-3, 2e-3])
    assert out["swept"] == {"k_v": "1/s"}
    assert out["parameters"] == {}  # the grid replaced [parameters] k_v at every point
    assert [row["k_v"] for row in out["summary"]] == pytest.approx(gains, rel=1e-15)
    assert plot.stat().st_size > 1000

    import xarray as xr

    ds = xr.open_zarr(store, chunks=None)
    # the store's settings, like its parameters, leave out the value the grid replaces
    # (were: "[parameters] k_v": "0.00124", a value no point ran with)
    settings = json.loads(ds.attrs["settings"])
    assert "[parameters] k_v" not in settings and json.loads(ds.attrs["parameters"]) == {}
    assert settings["[sweep] k_v"] == "3 values 0.0005, 0.001, 0.002 1/s"
    assert ds["k_v"].attrs["units"] == "1/s" and ds["k_v"].attrs["display_unit"] == "1/s"
    assert ds["k_v"].attrs["long_name"].startswith("model parameter k_v: velocity damping")
    assert json.loads(ds.attrs["swept"]) == ["k_v"]
    t = ds["time"].values
    names = [str(q) for q in ds["quantity"].values]
    omega = np.sqrt(G / R)
    for k, gain in enumerate(gains):
        psi, dv = damped_response(gain, 1.0, t)
        for curve in ("linear", "direct"):
            values = ds[curve].isel(point=k).values
            for name, reference in (("psi", psi), ("delta_latitude", psi),
                                    ("delta_v_N", dv)):
                got = values[:, names.index(name)]
                assert np.allclose(got, reference, rtol=0, atol=1e-7 * np.abs(reference).max()
                                   ), (gain, curve, name)
        zeta = gain / (2 * omega)
        steady = gain * 1.0 / G
        peak = steady * (1 + np.exp(-np.pi * zeta / np.sqrt(1 - zeta**2)))
        assert out["summary"][k]["max_direct"]["psi"] == pytest.approx(peak, rel=1e-4)
    # after 6 h the lightest damping (ζ = 0.2, e-folding 67 min) has settled to 0.5 %
    ends = ds["direct"].isel(time=-1).sel(quantity="psi").values
    assert ends == pytest.approx(gains / G, rel=5e-3)


def test_a_store_recording_the_replaced_parameter_is_named_by_its_real_difference(
        tmp_path):
    """A store written while settings still recorded the [parameters] value a grid
    replaces ("[parameters] k_v": its 1.24e-3) and refused for another setting is named
    by that setting alone, not also by the value neither sweep ran with."""
    from ins_errors.analysis import store as st

    path = scenario_file(tmp_path, '[sweep]\nk_v = ["5e-4/s", "1e-3/s"]\n')
    scenario = load_scenario(path)
    layout = sw.layout(scenario, sw.grid(scenario))
    settings = dict(layout.attributes["settings"])
    assert "[parameters] k_v" not in settings
    older = {**settings, "[parameters] k_v": "0.00124", "[sweep] seed": "5"}
    store = {"fingerprint": "0" * 32, "settings": json.dumps(older),
             "swept": json.dumps(["k_v"])}
    assert st.mismatch(store, layout) == "another sweep: [sweep] seed is 5 there, 0 here"


def test_gain_map_extends_shards_and_merges_as_other_grids(tmp_path, capsys):
    """A map of the peak tilt over the gain and the reference error is written; the
    same store is extended by another gain (only its points run, the others read back
    bit for bit); shards of the sweep, run apart on the process pool and merged, give
    the store the whole sweep writes on Dask (where installed)."""
    path = scenario_file(tmp_path, """
        [sweep]
        k_v = ["1e-3/s", "2e-3/s"]
        ref_velocity_error = ["1 m/s", "3 m/s"]
    """)
    store = tmp_path / "map.zarr"
    picture = tmp_path / "map.png"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial", "--json",
                 "--no-progress", "--plot", str(picture), "--figure", "max_direct:psi",
                 "--against", "k_v,ref_velocity_error"]) == 0
    rows = json.loads(capsys.readouterr().out)["summary"]
    assert picture.stat().st_size > 1000
    t = np.arange(0, 6 * 3600 + 1, 60.0)
    for row in rows:  # the peak of the closed form, linear in the reference error
        psi, _ = damped_response(row["k_v"], row["ref_velocity_error"], t)
        assert row["max_direct"]["psi"] == pytest.approx(np.abs(psi).max(), rel=1e-6)

    wider = scenario_file(tmp_path, """
        [sweep]
        k_v = ["1e-3/s", "2e-3/s", "0.24 1/min"]
        ref_velocity_error = ["1 m/s", "3 m/s"]
    """, name="wider.toml")
    assert main(["sweep", str(wider), "--store", str(store), "--engine", "pool",
                 "--workers", "2", "--json", "--no-progress"]) == 0
    grown = json.loads(capsys.readouterr().out)
    assert (grown["points"], grown["computed"], grown["reused"]) == (6, 2, 4)
    assert [r["max_direct"] for r in grown["summary"][:4]] == [r["max_direct"] for r in rows]
    assert grown["summary"][4]["k_v"] == pytest.approx(4e-3, rel=1e-15)

    scenario = load_scenario(wider)
    engine = "dask" if importlib.util.find_spec("distributed") else "serial"
    whole = sw.run_sweep(scenario, tmp_path / "whole.zarr", engine=engine, workers=1)
    assert whole.engine.where.startswith("local Dask") or engine == "serial", whole.engine
    whole = whole.dataset
    parts = [tmp_path / f"part_{k}.zarr" for k in (1, 2)]
    for k, part in enumerate(parts, start=1):
        sw.run_sweep(scenario, part, engine="pool", workers=1, shard=sw.Shard(k, 2))
    merged = sw.merge_shards(scenario, parts, tmp_path / "all.zarr").dataset
    for name in ("direct", "linear", "max_direct", "k_v", "ref_velocity_error"):
        assert np.array_equal(merged[name].values, whole[name].values), name
    assert merged.attrs["fingerprint"] == whole.attrs["fingerprint"]


BAD = [
    ('k_vv = ["1e-3/s"]', "unknown key in {f} [sweep] 'k_vv'; did you mean 'k_v'?"),
    ('k_v = ["1e-3/s", "1e-3 m/s"]', "{f} [sweep] k_v: '1e-3 m/s' has units of m / s (a "
                                     "velocity), which do not convert to 1/s"),
    ('k_v = ["1e-3"]', "{f} [sweep] k_v value '1e-3' needs a unit, e.g. '1e-3/s'"),
    ('k_v = ["1e-3/s", "-1e-3/s"]', "{f} [sweep] k_v = -0.001 1/s: a damping gain must be "
                                    "zero (undamped) or positive"),
    ('R = ["6371 km", "50 km"]', "{f} [sweep] R = 50 km: an Earth radius of 50000 m is "
                                 "below 100 km"),
    ('g = ["9.8 m/s^2", "-9.8 m/s^2"]', "{f} [sweep] at the point g = -9.8 m/s^2: "),
    ('k_v = ["1e-3/s", "0.06 1/min"]', "{f} [sweep] k_v: '1e-3/s' and '0.06 1/min' are the "
                                       "same value"),
]


@pytest.mark.parametrize("sweep, message", BAD)
def test_bad_parameter_grids_are_refused_in_one_line(tmp_path, capsys, sweep, message):
    """An unknown parameter (the close name suggested), a value in another unit or
    without one, a value no run can take (a negative gain, a planet below 100 km, a
    gravity outside the model's own domain) and a value given twice are refused in one
    line naming the file and the key, before any store is made."""
    path = scenario_file(tmp_path, f"[sweep]\n{sweep}\n")
    store = tmp_path / "bad.zarr"
    assert main(["sweep", str(path), "--store", str(store), "--engine", "serial",
                 "--no-progress"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith(f"ins-errors: error: {message.format(f=path)}"), err
    assert not store.exists()


def test_a_parameter_named_like_a_scenario_key_is_not_swept(tmp_path):
    """[sweep] height means the motion's height for every model; a model parameter named
    height is set by [parameters] only, which a note says."""
    parameter = types.SimpleNamespace(name="height", unit="m", description="mast height")
    model = types.SimpleNamespace(name="mast", sources=[], parameters=[parameter])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spec = sw.parse_sweep({"height": ["10 m", "20 m"]}, model, "m.toml")
    assert [p.kind for p in spec.parameters] == ["motion"]
    [note] = [str(w.message) for w in caught]
    assert note.startswith("ins-errors: note: m.toml [sweep] height is the motion's height, "
                           "not the parameter height of model 'mast'")


def test_the_published_schema_describes_parameter_grids():
    """An editor checking a scenario against docs/scenario.schema.json takes a grid of a
    model parameter (any name: the model decides) and flags one that is not a grid."""
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((Path(__file__).resolve().parent.parent / "docs" /
                         "scenario.schema.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(schema)
    scenario = {"model": "damped_schuler.py", "case": [{"ref_velocity_error": "1 m/s"}]}
    good = {"k_v": ["5e-4/s", "1e-3/s"], "k_p": {"start": 0, "stop": 1, "count": 3},
            "draws": 2, "seed": 7, "random": {"accel_bias": "10 ug"}}
    assert not list(validator.iter_errors({**scenario, "sweep": good}))
    for bad in ({"k_v": "1e-3/s"}, {"k_v": []}, {"draws": -1}, {"k_v": {"start": 0}}):
        assert list(validator.iter_errors({**scenario, "sweep": bad})), bad


def test_the_documented_vertical_damping_study(tmp_path):
    """examples/sweep_vertical_damping.toml, the gain study docs/scenarios.md shows:
    strapdown_ned's height error under a vertical bias b peaks where a loop of natural
    frequency ω₀ (k_h2 − 2g/R = ω₀²) and damping ζ = k_h1 / (2ω₀) puts its step
    response, b/ω₀² (1 + exp(−πζ/√(1 − ζ²))), and at b/ω₀² when critically damped
    (the documented 3.41 m, 2.34 m, 2.23 m)."""
    example = Path(__file__).resolve().parent.parent / "examples" / "sweep_vertical_damping.toml"
    scenario = load_scenario(example)
    result = sw.run_sweep(scenario, tmp_path / "damping.zarr", engine="serial")
    peaks = result.dataset["max_direct"].sel(quantity="delta_height").values
    gains = result.dataset["k_h1"].values
    a, gravity = 6_378_137.0, 9.81  # WGS-84, the gravity at 50° to 0.05 %
    omega = np.sqrt(scenario.parameters["k_h2"] - 2 * gravity / a)
    steady = 100e-6 * 9.80665 / omega**2
    zeta = gains / (2 * omega)
    assert zeta == pytest.approx([0.2, 0.7, 1.0], abs=1e-3)
    overshoot = np.array([np.exp(-np.pi * z / np.sqrt(1 - z**2)) if z < 1 else 0.0
                          for z in zeta])
    assert peaks == pytest.approx(steady * (1 + overshoot), rel=3e-3)
    # the numbers the docs and the example's comment quote are these runs' and the
    # closed form's
    docs = (example.parent.parent / "docs" / "scenarios.md").read_text(encoding="utf-8")
    said = " ".join(docs.split())
    assert "peaks at {:.2f} m, {:.2f} m and {:.2f} m".format(*peaks) in said
    assert f"b/ω₀² = {steady:.2f} m" in said
    assert f"b/ω₀² = {steady:.2f} m" in example.read_text(encoding="utf-8")
