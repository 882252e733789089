"""The task engine's choices: Dask when installed, the process pool without it (saying how
to install Dask), clear one-line errors for impossible requests."""

from __future__ import annotations

import pytest

from ins_errors.analysis import engine
from ins_errors.cli import main
from ins_errors.errors import UnknownNameError


def square(offset: int, x: int) -> int:
    return offset + x * x


@pytest.mark.parametrize("kind", ["serial", "pool"])
def test_results_reach_their_task_index(kind):
    seen = {}
    stats = engine.run_tasks(square, [(k,) for k in range(7)], engine=kind, workers=2,
                             shared=(100,), on_result=seen.__setitem__)
    assert seen == {k: 100 + k * k for k in range(7)}
    assert stats.computed == 7 and stats.engine == kind


def test_without_dask_the_pool_runs_and_says_how_to_install_dask(monkeypatch, capsys):
    monkeypatch.setattr(engine, "dask_available", lambda: False)
    assert engine.choose_engine("auto") == "pool"
    err = capsys.readouterr().err
    assert "pip install 'ins-errors[distributed]'" in err and err.count("\n") == 1
    with pytest.raises(engine.EngineError, match=r"ins-errors\[distributed\]"):
        engine.choose_engine("auto", "tcp://127.0.0.1:8786")
    with pytest.raises(engine.EngineError, match="needs Dask"):
        engine.choose_engine("dask")


def test_impossible_requests_are_one_line_errors(tmp_path, capsys):
    with pytest.raises(engine.EngineError, match="needs the dask engine"):
        engine.choose_engine("pool", "tcp://127.0.0.1:8786")
    with pytest.raises(UnknownNameError, match="did you mean 'dask'"):
        engine.choose_engine("dusk")
    path = tmp_path / "s.toml"
    path.write_text('model = "orthodromic"\n[[case]]\ngyro_drift_x = "0.01 deg/h"\n'
                    '[sweep]\nlatitude = ["10 deg"]\n')
    assert main(["sweep", str(path), "--engine", "pool", "--scheduler",
                 "tcp://127.0.0.1:8786", "--store", str(tmp_path / "s.zarr")]) == 2
    assert not (tmp_path / "s.zarr").exists()   # refused before anything is written
    assert main(["sweep", str(path), "--workers", "0"]) == 2
    err = capsys.readouterr().err
    assert "needs the dask engine" in err and "--workers must be at least 1" in err
