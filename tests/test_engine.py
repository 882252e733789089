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


def fails(offset: int, x: int) -> int:
    if x == 3:
        raise ZeroDivisionError("a fault in task 3\nwith a second line")
    return offset + x


@pytest.mark.parametrize("kind", ["pool", "dask"])
def test_a_task_that_fails_in_a_worker_is_one_line(kind):
    """Anything a task raises in a worker process (a fault, an argument that cannot be
    sent to it) is an EngineError of one line naming the exception, which the command
    line reports with exit status 2, never a traceback from the other process."""
    if kind == "dask":
        pytest.importorskip("distributed")
    with pytest.raises(engine.EngineError) as raised:
        engine.run_tasks(fails, [(k,) for k in range(5)], engine=kind, workers=2,
                         shared=(100,), label="test")
    assert str(raised.value) == ("a test task failed in a worker process: "
                                 "ZeroDivisionError: a fault in task 3")
    if kind == "pool":   # Dask's cloudpickle sends a local function; the pool cannot
        with pytest.raises(engine.EngineError, match=r"failed in a worker process: .*pickle"):
            engine.run_tasks(square, [(k,) for k in range(2)], engine=kind, workers=2,
                             shared=(lambda: 0,))


def test_an_error_of_the_tools_own_passes_unchanged():
    from ins_errors.errors import InsErrorsError

    error = InsErrorsError("bad input")
    assert engine.task_failure(error, "x") is error


def refuses_three(offset: int, x: int) -> int:
    if x == 3:
        from ins_errors.errors import DomainError

        raise DomainError(f"task {x} is outside the domain")
    return offset + x


@pytest.mark.parametrize("kind", ["serial", "pool"])
def test_a_task_that_refuses_its_input_is_its_outcome_when_asked(kind):
    """With on_failure, a task's own one-line error is reported for its index and every
    other task runs; without it the error stops the call, as any other fault always
    does."""
    from ins_errors.errors import DomainError

    seen, failed = {}, {}
    stats = engine.run_tasks(refuses_three, [(k,) for k in range(6)], engine=kind,
                             workers=2, shared=(100,), on_result=seen.__setitem__,
                             on_failure=failed.__setitem__)
    assert seen == {k: 100 + k for k in range(6) if k != 3}
    assert list(failed) == [3] and isinstance(failed[3], DomainError)
    assert str(failed[3]) == "task 3 is outside the domain"
    assert (stats.computed, stats.failed) == (5, 1)
    with pytest.raises(DomainError, match="task 3 is outside the domain"):
        engine.run_tasks(refuses_three, [(k,) for k in range(6)], engine=kind, workers=2,
                         shared=(100,))
    if kind == "pool":
        with pytest.raises(engine.EngineError, match="ZeroDivisionError: a fault in task 3"):
            engine.run_tasks(fails, [(k,) for k in range(5)], engine=kind, workers=2,
                             shared=(100,), on_failure=failed.__setitem__, label="test")
    else:  # in this process a fault is a programming error: its own traceback
        with pytest.raises(ZeroDivisionError):
            engine.run_tasks(fails, [(k,) for k in range(5)], engine=kind,
                             shared=(100,), on_failure=failed.__setitem__)
    assert list(failed) == [3]
