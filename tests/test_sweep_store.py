"""The sweep store itself: what a point's write stores is what reads back, bit for bit."""

from __future__ import annotations

import sys

import numpy as np
import pytest

pytest.importorskip("zarr")  # the store needs the 'distributed' extra (in 'dev')

from ins_errors.analysis.store import Layout, SweepStore


def _layout(points: int = 3) -> Layout:
    times = np.arange(6) * 10.0
    return Layout(points, times, ("alpha_x", "dv_n"), ("rad", "m/s"),
                  ("accel_bias_x", "gyro_drift_z"), ("m/s^2", "rad/s"),
                  {"latitude": (np.linspace(0.1, 0.3, points),
                                {"units": "rad", "swept": 1})},
                  ("direct", "linear"), {"title": "t", "swept": ["latitude"]},
                  "f" * 32)


def _point(rng, rows: int) -> dict[str, np.ndarray]:
    return {"direct": rng.standard_normal((rows, 2)), "linear": rng.standard_normal((rows, 2)),
            "max_direct": rng.standard_normal(2), "linear_ratio": rng.standard_normal(2),
            "excited": np.array([1, 0], dtype="i1"),
            "integration_error": rng.standard_normal(2),
            "source_value": rng.standard_normal(2)}


@pytest.mark.parametrize("zarr_sync", ["zarr's", "missing"])
def test_points_written_in_any_order_read_back_to_the_bit_and_unwritten_stay_empty(
        tmp_path, monkeypatch, zarr_sync):
    """Points written out of order (one with a shorter run) read back exactly, padded
    with NaN after their end; the point never written is NaN with ``done`` 0, and a
    reopened store knows which points are done. The same where a Zarr release no longer
    has the (non-public) ``zarr.core.sync`` the store uses to run its writes together."""
    if zarr_sync == "missing":
        monkeypatch.setitem(sys.modules, "zarr.core.sync", None)  # import raises ImportError
        with pytest.raises(ImportError):
            from zarr.core.sync import sync  # noqa: F401
    layout = _layout()
    rng = np.random.default_rng(7)
    written = {2: _point(rng, 6), 0: _point(rng, 4)}
    store = SweepStore.open(tmp_path / "s.zarr", layout)
    for index, values in written.items():
        store.write(index, values)
    data = store.dataset().load()
    assert data["done"].values.tolist() == [1, 0, 1]
    for index, values in written.items():
        for name, value in values.items():
            got = data[name].values[index]
            if name in layout.curves:
                assert np.isnan(got[len(value):]).all(), name
                got = got[:len(value)]
            assert got.dtype == value.dtype and np.array_equal(got, value), name
    for name in ("direct", "max_direct", "source_value"):
        assert np.isnan(data[name].values[1]).all(), name
    assert data["excited"].values[1].tolist() == [0, 0]
    assert SweepStore.open(tmp_path / "s.zarr", layout).done.tolist() == [True, False, True]


def _reference_store(path, layout: Layout) -> None:
    """The store as xarray writes the coordinates and zarr adds the empty arrays (how the
    store was made before it was built in one go): the reference for the layout."""
    import json

    import xarray as xr
    import zarr

    coords = {"point": ("point", np.arange(layout.points)),
              "time": ("time", np.asarray(layout.times, dtype=float), {"units": "s"}),
              "quantity": ("quantity", list(layout.quantities)),
              "quantity_unit": ("quantity", list(layout.quantity_units)),
              "source": ("source", list(layout.sources)),
              "source_unit": ("source", list(layout.source_units))}
    for name, (values, attrs) in layout.coordinates.items():
        coords[name] = ("point", np.asarray(values), dict(attrs))
    attrs = {k: (v if isinstance(v, (str, int, float)) else json.dumps(v))
             for k, v in layout.attributes.items()}
    attrs["fingerprint"] = layout.fingerprint
    xr.Dataset(coords=coords, attrs=attrs).to_zarr(str(path), mode="w", consolidated=False,
                                                  zarr_format=2)
    group = zarr.open_group(str(path), mode="r+", zarr_format=2)
    P, T, Q, W = layout.points, len(layout.times), len(layout.quantities), len(layout.sources)
    # one unit per quantity (coordinate quantity_unit): no CF units attribute, a comment
    per_quantity = {"comment": "SI: each quantity in its unit, coordinate quantity_unit"}
    arrays = [(c, ("point", "time", "quantity"), (P, T, Q), "f8", np.nan,
               {"long_name": f"{c} error", **per_quantity}) for c in layout.curves]
    arrays += [("max_direct", ("point", "quantity"), (P, Q), "f8", np.nan,
                {"long_name": "max |direct error| over the run", **per_quantity})]
    arrays += [(f"{c}_ratio", ("point", "quantity"), (P, Q), "f8", np.nan,
                {"long_name": f"max |{c} - direct| / max |direct|", "units": "1"})
               for c in layout.curves[1:]]
    arrays += [("excited", ("point", "quantity"), (P, Q), "i1", None,
                {"long_name": "1 where the quantity is excited (its ratios are meaningful)",
                 "units": "1"}),
               ("integration_error", ("point", "quantity"), (P, Q), "f8", np.nan,
                {"long_name": "estimated integration error (step doubling; larger of "
                              "direct and linear)", **per_quantity}),
               ("source_value", ("point", "source"), (P, W), "f8", np.nan,
                {"long_name": "error sources of the point",
                 "comment": "SI: each source in its unit, coordinate source_unit"}),
               ("done", ("point",), (P,), "i1", None,
                {"long_name": "1 once the point's results (or its failure) are written",
                 "units": "1"})]
    for name, dims, shape, dtype, fill, extra in arrays:
        group.create_array(name, shape=shape, chunks=(1, *shape[1:]), dtype=dtype,
                           fill_value=fill,
                           attributes={"_ARRAY_DIMENSIONS": list(dims), **extra})
    # the reasons as NetCDF's character arrays: a row of UTF-8 bytes per point (one chunk
    # of 4096 bytes), 1 byte wide until a reason is written; no fill value (zero bytes:
    # unwritten points read as ""); xarray joins a row and decodes it by _Encoding
    group.create_array("failure", shape=(P, 1), chunks=(1, 4096), dtype="S1",
                       fill_value=None,
                       attributes={"_ARRAY_DIMENSIONS": ["point", "failure_bytes"],
                                   "long_name": "why the point failed (empty: it did not); "
                                                "its data are NaN", "_Encoding": "utf-8"})
    zarr.consolidate_metadata(str(path), zarr_format=2)


def _files(folder) -> dict[str, object]:
    import json

    return {str(f.relative_to(folder)): json.loads(f.read_text()) if f.name.startswith(".")
            else f.read_bytes() for f in sorted(folder.rglob("*")) if f.is_file()}


def test_a_new_store_holds_what_xarray_and_zarr_write_for_its_layout(tmp_path):
    """A new store's files are those of the reference construction (xarray writing the
    coordinates, zarr adding each empty array): same metadata and attributes (JSON),
    same chunk bytes; xarray reads both as identical datasets. Per-point coordinates of
    each kind a grid makes: floats with units, integer case and draw labels, and text;
    refined curves, so every kind of data array is there."""
    import xarray as xr

    layout = _layout(4)
    coordinates = {"latitude": (np.linspace(0.1, 0.4, 4), {"units": "rad", "swept": 1}),
                   "case": (np.array([0, 1, 0, 1]), {"long_name": "case"}),
                   "draw": (np.arange(4), {}),
                   "label": (np.array(["a", "bb", "µ", "d"]), {})}
    layout = Layout(**{**layout.__dict__, "coordinates": coordinates,
                       "curves": ("direct", "linear", "refined"),
                       "times": np.array([0.0, 0.5, 1e-3, 3600.0])})
    SweepStore.open(tmp_path / "new.zarr", layout)
    _reference_store(tmp_path / "ref.zarr", layout)
    new, ref = _files(tmp_path / "new.zarr"), _files(tmp_path / "ref.zarr")
    assert sorted(new) == sorted(ref)
    for name in ref:
        assert new[name] == ref[name], name
    with xr.open_zarr(tmp_path / "new.zarr") as a, xr.open_zarr(tmp_path / "ref.zarr") as b:
        assert a.identical(b)


@pytest.mark.parametrize("suffix", ["zarr", "nc"])
def test_points_done_reads_the_stores_own_flags(tmp_path, suffix):
    """What a stopped sweep says it keeps is read from the store's done flags (a point
    written just before the signal was kept but not yet counted: the message said 1 of
    20, the rerun reused 2); a path without a store reads as None."""
    from ins_errors.analysis.store import points_done

    path = tmp_path / f"s.{suffix}"
    assert points_done(path) is None
    store = SweepStore.open(path, _layout())
    rng = np.random.default_rng(3)
    store.write(2, _point(rng, 6))
    store.write(0, _point(rng, 6))
    assert points_done(path) == 2
