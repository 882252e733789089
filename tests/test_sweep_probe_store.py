"""A sweep store on a disk that fills: one line naming the store and what it keeps, and
the store left to resume (the probe saw 'cannot use: No space left on device', and a
*.nc store left a half-written s.nc.tmp)."""

from __future__ import annotations

import errno
import json

import pytest

from ins_errors.analysis import store as st
from ins_errors.cli import main

TINY = """title = "tiny"
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
latitude = ["10 deg", "20 deg", "30 deg", "40 deg"]
"""


def _write(tmp_path, text: str = TINY):
    path = tmp_path / "tiny.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _sweep(path, store) -> list[str]:
    return ["sweep", str(path), "--store", str(store), "--engine", "serial",
            "--no-progress", "--json"]


def test_a_full_disk_names_the_store_and_the_same_command_resumes(tmp_path, capsys,
                                                                  monkeypatch):
    path = _write(tmp_path)
    store = tmp_path / "s.zarr"
    real = st.SweepStore.write
    written: list = []

    def filling(self, index, values):
        if len(written) == 2:
            raise OSError(errno.ENOSPC, "No space left on device")
        written.append(index)
        real(self, index, values)

    monkeypatch.setattr(st.SweepStore, "write", filling)
    assert main(_sweep(path, store)) == 2
    out, err = capsys.readouterr()
    assert not out and err.count("\n") == 3, err  # the store and start lines, then one
    line = err.splitlines()[-1]
    assert repr(str(store)) in line and "No space left on device" in line, line
    assert "it keeps 2 of the 4 points" in line and "the same command resumes" in line
    monkeypatch.setattr(st.SweepStore, "write", real)
    assert main(_sweep(path, store)) == 0
    again = json.loads(capsys.readouterr().out)
    assert (again["computed"], again["reused"]) == (2, 2)


def test_a_netcdf_store_whose_disk_fills_leaves_no_half_file(tmp_path, capsys,
                                                            monkeypatch):
    xr = pytest.importorskip("xarray")
    path = _write(tmp_path)
    store = tmp_path / "s.nc"
    real = xr.Dataset.to_netcdf

    def full(self, target, *args, **kwargs):
        with open(target, "wb") as half:
            half.write(b"CDF\x01 a half-written file")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    assert main(_sweep(path, store)) == 2
    line = capsys.readouterr().err.splitlines()[-1]
    assert repr(str(store)) in line and "it keeps 4 of the 4 points" in line, line
    assert not (tmp_path / "s.nc.tmp").exists() and not store.exists()
    assert (tmp_path / "s.nc.partial.zarr").is_dir()
    monkeypatch.setattr(xr.Dataset, "to_netcdf", real)
    assert main(_sweep(path, store)) == 0
    again = json.loads(capsys.readouterr().out)
    assert (again["computed"], again["reused"]) == (0, 4)
    assert store.is_file() and not (tmp_path / "s.nc.partial.zarr").exists()


def test_a_default_written_out_is_the_same_sweep_a_real_change_is_not(tmp_path, capsys):
    """Was: '[motion] heading is absent there, 0 deg here' for heading = "0 deg" (the
    default), and likewise [parameters] a at the model's own value."""
    from ins_errors.numeric.model import load_model

    a = dict(zip([i.name for i in load_model("orthodromic").parameters],
                 load_model("orthodromic").parameter_vector(), strict=True))["a"]
    path = _write(tmp_path)
    store = tmp_path / "s.zarr"
    assert main(_sweep(path, store)) == 0
    capsys.readouterr()
    explicit = TINY.replace('latitude = "50 deg"\n', 'latitude = "50 deg"\nheading = "0 deg"\n')
    explicit = explicit.replace("[[case]]", f'[parameters]\na = "{a:.17g} m"\n[[case]]')
    assert main(_sweep(_write(tmp_path, explicit), store)) == 0
    again = json.loads(capsys.readouterr().out)
    assert (again["computed"], again["reused"], again["store_others"]) == (0, 4, 0)
    turned = TINY.replace('latitude = "50 deg"\n', 'latitude = "50 deg"\nheading = "10 deg"\n')
    assert main(_sweep(_write(tmp_path, turned), store)) == 2
    err = capsys.readouterr().err
    assert "holds another sweep: [motion] heading is" in err and "10 deg here" in err, err
    other = explicit.replace(f'a = "{a:.17g} m"', f'a = "{a + 1000:.17g} m"')
    assert main(_sweep(_write(tmp_path, other), store)) == 2
    assert "[parameters] a is" in capsys.readouterr().err
