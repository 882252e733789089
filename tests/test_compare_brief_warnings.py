"""The terminal's integration-error warning is short, and its advice makes sense.

A student running the manual's rectangle method got, per case, a ~900-character
paragraph on the terminal ending in "about τ ≤ 5.36e-06 s would bring it under" (16
billion steps for a day). The terminal now prints one or two lines: what is wrong, how
big, and a cure one can run: RK4 first when the rectangle step needed is tiny, and no
rectangle step at all past :data:`~ins_errors.numeric.brief_warnings.STEPS` steps for
the run. The full text stays where a reader who wants it looks: the JSON, report.md and
the ``--markdown`` file. The cure is checked by running it: RK4 at the step the line
names gives no integration-error warning.
"""

from __future__ import annotations

import json
import re

from ins_errors.cli import main
from tests.helpers import COARSE_RECTANGLE

RECTANGLE = ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--hours", "2",
             "--step", "10s", "--method", "euler", "--no-progress"]
"""2 h of a gyro drift at rest by the rectangle method at 10 s: its integration error is
5 % of the tilt, some 4e4 times a tenth of linear − direct; the rectangle step that
would do is ~1e-4 s (hundreds of millions of steps)."""

LONGEST_LINE = 400
"""Characters of a short warning at most (two terminal lines of 200)."""

STEP_NAMED = re.compile(r"τ (?:=|≤) ([0-9.e+-]+) s")


def _warnings(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("> **warning**")]


def test_the_terminal_says_rk4_not_an_absurd_rectangle_step_and_rk4_cures_it(tmp_path,
                                                                              capsys):
    markdown = tmp_path / "full.md"
    assert main([*RECTANGLE, "--markdown", str(markdown)]) == 0
    shown = capsys.readouterr().out
    [line] = _warnings(shown)
    assert len(line) <= LONGEST_LINE, line
    assert "integration error too large at τ = 10 s, rectangle method" in line
    assert "--method rk4" in line and "cannot get there" in line
    steps = [float(s) for s in STEP_NAMED.findall(line)]
    assert steps, line
    for step in steps:  # only steps a run can take: none of the rectangle's 1e-4 s
        assert 7200.0 / step <= 1e7, line
    assert f"(the warnings in full: {markdown})" in shown
    # the full warning is kept, the same in the --markdown file and the JSON
    assert main([*RECTANGLE, "--json"]) == 0
    [case] = json.loads(capsys.readouterr().out)["cases"]
    [full] = [w for w in case["warnings"] if w.startswith("integration error")]
    assert len(full) > 2 * len(line) - len("> **warning** (gyro_drift_x = 0.01 deg/h): ")
    assert f"> **warning** (gyro_drift_x = 0.01 deg/h): {full}" in markdown.read_text(
        encoding="utf-8")
    assert case["suggested_method"] == "rk4"
    # the cure, run: RK4 at the step named (the run's own 10 s) does not warn
    rk4 = steps[-1]
    assert main([*RECTANGLE[:-3], "--step", f"{rk4:g}s", "--method", "rk4",
                 "--no-refined", "--no-progress", "--json"]) == 0
    [case] = json.loads(capsys.readouterr().out)["cases"]
    assert not [w for w in case["warnings"] if "integration error" in w], case["warnings"]


SCENARIO = COARSE_RECTANGLE


def test_run_prints_a_short_warning_rk4_first_and_the_report_keeps_the_full_one(
        tmp_path, capsys):
    scenario = tmp_path / "coarse.toml"
    scenario.write_text(SCENARIO, encoding="utf-8")
    out = tmp_path / "report"
    assert main(["run", str(scenario), "--out", str(out), "--no-progress"]) == 0
    shown = capsys.readouterr().out
    [line] = _warnings(shown)
    assert len(line) <= LONGEST_LINE, line
    [case] = json.loads((out / "results.json").read_text(encoding="utf-8"))["cases"]
    [full] = case["warnings"]
    rectangle = case["suggested_step_s"]  # the full warning's rectangle step, kept
    assert f"τ = {rectangle:g} s would bring it under the limit" in full
    assert 7200.0 / rectangle > 1e6  # tiny: RK4 is named first, the step after it
    assert line.index("RK4") < line.index(f"τ = {rectangle:g} s"), line
    assert f"{full}" in (out / "report.md").read_text(encoding="utf-8")
    assert f"(the warnings in full: {out / 'report.md'})" in shown
