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
    assert progress_bar(100, "steps") is None
    monkeypatch.setattr("sys.stderr", _Terminal())
    bar = progress_bar(100, "steps")
    bar.update(100)
    bar.close()


def _slow_stages(monkeypatch) -> list[tuple[str, bool]]:
    """Record every stage (label, enabled) and hold each open long enough to be drawn."""
    from contextlib import contextmanager

    real, seen = progress.stage, []

    @contextmanager
    def held(label, enabled=True):
        seen.append((label, enabled))
        with real(label, enabled):
            yield
            time.sleep(0.05)

    monkeypatch.setattr(progress, "stage", held)
    monkeypatch.setattr(progress, "SHOW_AFTER", 0.0)
    return seen


@pytest.mark.parametrize("terminal", [True, False])
def test_the_reruns_after_the_bar_show_their_progress_on_a_terminal_only(terminal,
                                                                           monkeypatch):
    """After the run's bar, the integration-error and validity runs were silent; the
    reruns of the integration-error check then showed a status without a total. Each
    now has a bar over its own steps, labelled as the check's: an hour at τ = 10 s
    recorded every 60 s (an even stride) is run again at 2τ (3600 s / 20 s = 180 steps)
    and 4τ (90 steps)."""
    import numpy as np

    from ins_errors import load_model
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare

    stream = _Terminal() if terminal else io.StringIO()
    monkeypatch.setattr("sys.stderr", stream)
    seen = _slow_stages(monkeypatch)
    model = load_model("orthodromic")
    motion = tr.trajectory(model, tr.static_profile(np.radians(50.0)), 3600.0, 10.0)
    compare(model, motion, [{"accel_bias_y": 1e-4}], record_interval=60.0, refined=False,
            progress=True)
    labels = [label for label, enabled in seen if enabled]
    assert any("validity" in label for label in labels)
    drawn = stream.getvalue()
    assert ("validity" in drawn) is terminal
    assert drawn == "" or terminal
    if terminal:
        import re

        lines = drawn.split("\r")
        # the first bar says the check's reruns follow (its 100 % was taken for the end:
        # a week's static run spent 45 % of its time after it)
        for label, total in (("direct and linear runs (then the integration-error check's "
                              "reruns):", 360),
                             ("integration-error check: run at 2τ = 20 s:", 180),
                             ("integration-error check: run at 4τ = 40 s:", 90)):
            bar = next(line for line in lines if line.startswith(label))
            assert float(re.search(r"/(\S+) \[", bar).group(1)) == total, bar


def test_a_rerun_label_names_the_check_and_the_step():
    from ins_errors.numeric.accuracy import rerun_label

    assert rerun_label(2, 1.0) == "integration-error check: run at 2τ = 2 s"
    assert rerun_label(0.5, 0.16) == "integration-error check: run at τ/2 = 0.08 s"
    assert rerun_label(0.25, 0.1) == "integration-error check: run at τ/4 = 0.025 s"


@pytest.mark.parametrize("terminal", [True, False])
def test_writing_a_report_shows_a_status_on_a_terminal_only(terminal, monkeypatch, tmp_path):
    """Plots, pages and curve files: over a minute of silence for a week's report."""
    from ins_errors.report import write_report
    from ins_errors.scenario import load_scenario, run_scenario

    scenario = tmp_path / "s.toml"
    scenario.write_text('title = "t"\nmodel = "orthodromic"\n[run]\nduration = "10 min"\n'
                        'step = "10 s"\nrecord = "60 s"\nrefined = false\n[[case]]\n'
                        'accel_bias_y = "50 ug"\n'
                        # one plotted quantity: the figure is not what this is about
                        '[outputs]\nquantities = ["alpha_x"]\n', encoding="utf-8")
    result = run_scenario(load_scenario(scenario))
    stream = _Terminal() if terminal else io.StringIO()
    monkeypatch.setattr("sys.stderr", stream)
    _slow_stages(monkeypatch)
    write_report(result, tmp_path / "out")
    drawn = stream.getvalue()
    assert all((name in drawn) is terminal for name in ("case_1.png", "report.md",
                                                        "curves.csv"))
    assert drawn == "" or terminal


def test_the_runs_bar_is_timed_from_after_the_first_compile(monkeypatch):
    """A moving run's bar started before its loop was compiled: "554 step/s, ETA 10:44"
    for a one-hour run. It now starts once the first piece (and its compile) is done,
    counts that piece as done, and still ends at the run's length."""
    import numpy as np

    from ins_errors import load_model
    from ins_errors.numeric import simulate as simulation
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.integrators import CompiledLoop

    monkeypatch.setattr("sys.stderr", _Terminal())
    events, bars = [], []
    real_advance, real_bar = CompiledLoop.advance, simulation.progress_bar

    def advance(self, *args, **kwargs):
        if not events:
            time.sleep(0.3)  # a compile
        real_advance(self, *args, **kwargs)
        events.append(("advanced", time.perf_counter()))

    def bar(total, label, initial=0):
        events.append(("bar", time.perf_counter()))
        made = real_bar(total, label, initial=initial) if initial else real_bar(total, label)
        bars.append(made)
        return made

    monkeypatch.setattr(CompiledLoop, "advance", advance)
    monkeypatch.setattr(simulation, "progress_bar", bar)
    model = load_model("orthodromic")
    profile = tr.great_circle_profile(np.radians(50.0), 0.5, np.radians(90.0), 250.0)
    motion = tr.trajectory(model, profile, 600.0, 0.01, stream=True)
    simulation.simulate(model, motion, [{"accel_bias_y": 1e-4}], record_interval=60.0,
                        parts=("real", "linear"), progress=True)
    kinds = [kind for kind, _ in events]
    assert kinds.count("advanced") >= 2 and kinds[0] == "advanced" and "bar" in kinds
    [made] = bars
    assert made.n == motion.n_steps


@pytest.mark.parametrize("quiet", [False, True])
def test_budget_takes_no_progress_as_compare_and_validity_do(quiet, monkeypatch):
    """`budget` refused --no-progress (exit 2) though `compare` and `validity` take it, so a
    script passing it to all three stopped there. It now hides the covariance
    propagation's status and the --monte-carlo runs' bar on a terminal, and shows them
    without it."""
    from ins_errors.analysis import monte_carlo
    from ins_errors.cli import main

    stream = _Terminal()
    monkeypatch.setattr("sys.stderr", stream)
    seen = _slow_stages(monkeypatch)
    asked = []
    real = monte_carlo.direct_monte_carlo

    def spy(*args, **kwargs):
        asked.append(kwargs.get("progress", True))
        return real(*args, **kwargs)

    monkeypatch.setattr(monte_carlo, "direct_monte_carlo", spy)
    argv = ["budget", "orthodromic", "--json", "--monte-carlo", "4", "--mc-duration",
            "10min", "--mc-step", "1s", "--engine", "serial"]
    assert main(argv + ["--no-progress"] * quiet) == 0
    covariance = [enabled for label, enabled in seen if "covariance" in label]
    assert covariance == [not quiet]
    assert asked and asked[0] is not quiet  # the runs' bar (the rerun's is never shown)
    assert ("propagating the covariance" in stream.getvalue()) is not quiet


@pytest.mark.parametrize("command", [
    ["check", "orthodromic", "examples/manual_000/equations.txt"],
    ["propagation", "--hours", "1", "--step", "60s", "--json"],
    ["study", "gravity_projections", "--hours", "0.5", "--json"]])
def test_no_progress_hides_every_status_of_the_command(command, monkeypatch, tmp_path):
    """`check`, `study` and `propagation` showed status lines but refused --no-progress
    (exit 2); and --no-progress never reached the stages no option reaches (compiling
    a loop: shown on a terminal whatever the command was told). With it, nothing is
    drawn on a terminal, even by a stage that is slow and enabled; after the command,
    progress is drawn again (main called again in the same process)."""
    from pathlib import Path

    from ins_errors.cli import main

    root = Path(__file__).resolve().parent.parent
    command = [str(root / a) if a.startswith("examples/") else a for a in command]
    monkeypatch.chdir(tmp_path)
    stream = _Terminal()
    monkeypatch.setattr("sys.stderr", stream)
    monkeypatch.setattr(progress, "SHOW_AFTER", 0.0)
    real = progress.stage

    def slow(label, enabled=True):  # every stage, also one the command cannot disable
        from contextlib import contextmanager

        @contextmanager
        def held():
            with real(label, True):
                yield
                time.sleep(0.05)
        return held()

    monkeypatch.setattr(progress, "stage", slow)
    assert main([*command, "--no-progress"]) in (0, 1)
    assert "…" not in stream.getvalue()
    with progress.stage("compiling a loop"):   # drawn again once the command ended
        pass
    assert "compiling a loop" in stream.getvalue()
