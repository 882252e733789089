"""The sweep store itself: what a point's write stores is what reads back, bit for bit."""

from __future__ import annotations

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


def test_points_written_in_any_order_read_back_to_the_bit_and_unwritten_stay_empty(tmp_path):
    """Points written out of order (one with a shorter run) read back exactly, padded
    with NaN after their end; the point never written is NaN with ``done`` 0, and a
    reopened store knows which points are done."""
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
