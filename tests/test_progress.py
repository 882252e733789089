"""Progress is drawn on a terminal only: a pipe, a log or a test stays clean."""

from __future__ import annotations

import io
import time

import pytest

from ins_errors import progress


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("terminal", [True, False])
def test_stage_draws_only_on_a_terminal(terminal, monkeypatch):
    stream = _Terminal() if terminal else io.StringIO()
    monkeypatch.setattr("sys.stderr", stream)
    monkeypatch.setattr(progress, "SHOW_AFTER", 0.01)
    with progress.stage("compiling a loop"):
        time.sleep(0.3)
    assert ("compiling a loop" in stream.getvalue()) is terminal


def test_quick_stages_draw_nothing(monkeypatch):
    stream = _Terminal()
    monkeypatch.setattr("sys.stderr", stream)
    with progress.stage("instant"):
        pass
    assert stream.getvalue() == ""


def test_counted_bars_follow_the_same_rule(monkeypatch):
    from ins_errors.numeric.integrators import progress_bar

    stream = io.StringIO()
    monkeypatch.setattr("sys.stderr", stream)
    bar = progress_bar(100, "steps")
    bar.update(100)
    bar.close()
    assert stream.getvalue() == ""
