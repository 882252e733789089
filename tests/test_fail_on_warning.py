"""``--fail-on-warning``: CI fails on a run that warns without parsing its JSON.

``compare`` and ``run`` exit 0 whatever they warn about; with the option they exit 1
when the run warned about its results, once their usual output is written: a case's
warning (validity, integration error, ...) or a warning about the results shown on
stderr (the interpolated true motion's). Notes, and a clean run, keep 0.
"""

from __future__ import annotations

import json
import warnings

from ins_errors.cli import main
from tests.helpers import COARSE_RECTANGLE

VALIDITY = ["compare", "north_pointing", "--source", "initial_azimuth_error=20deg",
            "--hours", "2", "--step", "10s", "--no-progress"]
"""A 20° azimuth error: linear − direct is 40 % of the error, far beyond the 5 %."""

CLEAN = ["compare", "north_pointing", "--source", "initial_azimuth_error=1arcmin",
         "--hours", "2", "--step", "10s", "--no-progress"]
"""The same run at 1 arcmin: linear, well integrated, no warning."""

SCENARIO = COARSE_RECTANGLE


def test_compare_fails_on_a_validity_warning_after_its_output(capsys):
    assert main([*VALIDITY, "--json"]) == 0                 # without the option: 0
    plain = json.loads(capsys.readouterr().out)
    assert main([*VALIDITY, "--json", "--fail-on-warning"]) == 1
    captured = capsys.readouterr()
    result = json.loads(captured.out)                      # the output, whole
    assert result["cases"] == plain["cases"]
    [case] = result["cases"]
    assert case["warnings"] and case["warnings"][0].startswith(
        "linear model beyond its validity")
    assert captured.err.splitlines()[-1] == (
        "ins-errors: exit status 1 (--fail-on-warning): the run gave 1 warning")
    assert main([*VALIDITY, "--fail-on-warning"]) == 1      # the table too
    assert "**warning**" in capsys.readouterr().out


def test_compare_without_a_warning_exits_0(capsys):
    assert main([*CLEAN, "--json", "--fail-on-warning"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["cases"][0]["warnings"] == []
    assert "fail-on-warning" not in captured.err


def test_run_fails_on_an_integration_error_warning_after_its_report(tmp_path, capsys):
    scenario = tmp_path / "coarse.toml"
    scenario.write_text(SCENARIO, encoding="utf-8")
    out = tmp_path / "report"
    assert main(["run", str(scenario), "--out", str(out), "--no-progress",
                 "--fail-on-warning"]) == 1
    assert "fail-on-warning" in capsys.readouterr().err
    [case] = json.loads((out / "results.json").read_text(encoding="utf-8"))["cases"]
    assert case["warnings"][0].startswith("integration error too large at τ = 60 s")
    assert (out / "report.md").is_file() and (out / "report.html").is_file()
    # a scenario that runs clean keeps 0
    clean = tmp_path / "clean.toml"
    clean.write_text(SCENARIO.replace('"60 s"', '"10 s"').replace('"euler"', '"rk4"')
                     .replace('"100 ug"', '"10 ug"'), encoding="utf-8")
    assert main(["run", str(clean), "--out", str(tmp_path / "clean"), "--no-progress",
                 "--fail-on-warning"]) == 0


def _warning_during_the_truth(monkeypatch, text: str) -> None:
    """Make the true motion's computation show ``text`` as a warning on stderr (as the
    interpolated truth does when a motion changes faster than its intervals)."""
    from ins_errors.numeric import trajectories

    original = trajectories.trajectory

    def warning(*args, **kwargs):
        warnings.warn(text, RuntimeWarning, stacklevel=2)
        return original(*args, **kwargs)

    monkeypatch.setattr(trajectories, "trajectory", warning)


def test_a_warning_about_the_results_on_stderr_counts_and_a_note_does_not(monkeypatch,
                                                                          capsys):
    off = ("ins-errors: the interpolated true motion may be off by about 3.0e-06 of V_E "
           "near t = 100 s (the motion changes there faster than its intervals resolve)")
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        _warning_during_the_truth(monkeypatch, off)
        assert main([*CLEAN, "--fail-on-warning"]) == 1
        err = capsys.readouterr().err
        assert off in err and "the run gave 1 warning" in err
        monkeypatch.undo()
        _warning_during_the_truth(monkeypatch, "ins-errors: note: the motion file was read")
        assert main([*CLEAN, "--fail-on-warning"]) == 0


def test_the_machine_notices_do_not_count(monkeypatch, tmp_path):
    """No C compiler (or no disk space to compile), a damaged cache entry and a cache
    folder that cannot be written: the same results, slower, made again or kept
    elsewhere. Their own words, as the product shows them."""
    from ins_errors.commands.warning_status import watched_warnings
    from ins_errors.numeric import cache, integrators

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        # shown to nobody (the suite's own summary would list them): watched only
        warnings.showwarning = lambda *args, **kwargs: None
        with watched_warnings() as shown:
            _give_the_notices(monkeypatch, tmp_path, integrators, cache)
    assert shown == ["ins-errors: the interpolated true motion may be off"]


def test_every_machine_notice_is_one_class_the_api_can_silence(monkeypatch, tmp_path):
    """``InsErrorsNotice``: one filter silences the machine's notices and leaves the
    warnings about the results."""
    from ins_errors import InsErrorsNotice
    from ins_errors.numeric import cache, integrators

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        _give_the_notices(monkeypatch, tmp_path, integrators, cache)
    notices = [w for w in seen if issubclass(w.category, InsErrorsNotice)]
    assert len(notices) == 4 == len(seen) - 1
    assert all(issubclass(w.category, RuntimeWarning) for w in seen)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", InsErrorsNotice)
        _give_the_notices(monkeypatch, tmp_path, integrators, cache)
    assert [str(w.message) for w in seen] == [
        "ins-errors: the interpolated true motion may be off"]


def _give_the_notices(monkeypatch, tmp_path, integrators, cache) -> None:
    """The four machine notices and one warning about the results."""
    monkeypatch.setattr(integrators, "_NOTICE_GIVEN", False)
    integrators._vm_notice("cc: command not found")
    monkeypatch.setattr(integrators, "_NOTICE_GIVEN", False)
    integrators._vm_notice("No space left on device", full=tmp_path)
    monkeypatch.setattr(cache, "_DAMAGE_SAID", set())
    cache.report_damaged(tmp_path / "loop_0.so", "compiling it again")
    monkeypatch.setattr(cache, "_PRIVATE_NOTICE_GIVEN", False)
    monkeypatch.delenv(cache.PRIVATE_NOTICE_VARIABLE, raising=False)
    cache._private_notice(tmp_path / "read_only", tmp_path / "private")
    warnings.warn("ins-errors: the interpolated true motion may be off", RuntimeWarning,
                  stacklevel=1)
