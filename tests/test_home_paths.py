"""``~`` in a path means the home folder on every command, as it does for a model file.

A shell expands ``~/m/eq.txt`` only unquoted and standing alone: ``"~/m/eq.txt"`` and
``--matrix=~/m/psi.py:psi`` reach the program with the ``~`` in them. The model argument
took it (``check "~/m/my_sd.py"`` worked) while the hand file, ``--matrix``, ``--report``
and the other paths said the file did not exist. Here HOME is a scratch folder, the
files are put in it, and the commands are given ``~`` paths.
"""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import build_parser, main

ROOT = Path(__file__).resolve().parent.parent

PATH_DESTS = {"file", "matrix", "write_samples", "mapping", "report", "out", "plot",
              "plot_at", "markdown", "motion_file", "spec", "store", "merge", "scenario"}
"""Options and arguments whose value is a file or folder the user names."""
PATH_METAVAR = re.compile(r"FILE|DIR|PATH|PNG|CSV|PART|\.npz|\.mat")


@pytest.fixture
def home(tmp_path, monkeypatch):
    """A scratch home folder (HOME) with a folder ``m`` in it; the current folder is
    elsewhere, so a path taken literally (``./~/m/...``) is not found by chance."""
    folder = tmp_path / "home"
    (folder / "m").mkdir(parents=True)
    monkeypatch.setenv("HOME", str(folder))
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    assert os.path.expanduser("~") == str(folder)
    return folder


def _subparsers(parser):
    """Every (command words, parser) of the command line, nested ones included."""
    found = []
    for action in parser._actions:
        choices = getattr(action, "choices", None)
        for name, sub in (choices.items() if isinstance(choices, dict) else ()):
            if hasattr(sub, "_actions"):
                found.append(([name], sub))
                found += [([name, *words], inner) for words, inner in _subparsers(sub)]
    return found


def _path_actions():
    for words, sub in _subparsers(build_parser()):
        for action in sub._actions:
            if action.nargs == 0 or action.choices is not None:
                continue  # a switch, or a choice of names (study --scenario)
            if action.dest in PATH_DESTS or PATH_METAVAR.search(str(action.metavar or "")):
                yield " ".join(words), action


def test_every_path_option_of_every_command_expands_home(home):
    """Each option (and argument) that names a file or folder reads ``~/x`` as the home
    folder's x; a new option of the kind fails here until it uses the shared helper
    (:mod:`ins_errors.user_paths`)."""
    seen = set()
    for command, action in _path_actions():
        name = action.option_strings[0] if action.option_strings else action.dest
        seen.add((command, name))
        convert = action.type
        assert callable(convert), f"{command} {name}: its value is taken as typed (no ~)"
        value = convert("~/m/x.py:f")
        assert os.fspath(value) == str(home / "m" / "x.py:f"), (command, name, value)
        assert os.fspath(convert("./rel")) in ("./rel", "rel"), (command, name)
    # the options the probe named, on the commands it used
    for expected in [("check", "file"), ("check", "--matrix"), ("check", "--report"),
                     ("check", "--write-samples"), ("check", "--mapping"),
                     ("compare", "--motion-file"), ("compare", "--out"),
                     ("compare", "--plot"), ("compare", "--markdown"),
                     ("budget", "--spec"), ("budget", "--plot"), ("budget", "--plot-at"),
                     ("budget", "--plot-time"), ("budget", "--report"),
                     ("run", "scenario"),
                     ("run", "--out"), ("sweep", "scenario"), ("sweep", "--store"),
                     ("sweep", "--merge"), ("matrices", "--out"), ("validity", "--out"),
                     ("derive", "--out"), ("propagation", "--out"), ("study", "--plot")]:
        assert expected in seen, expected


def test_check_reads_a_matrix_model_under_home(home, capsys):
    """The probe's command: ``--matrix "~/m/psi_model.py:psi_model"`` (and ``--matrix=~/...``,
    which no shell expands) checks the file; its Markdown report goes under home too."""
    shutil.copy(ROOT / "examples/strapdown/psi_model.py", home / "m" / "psi_model.py")
    status = main(["check", "strapdown_ned", "--matrix=~/m/psi_model.py:psi_model",
                   "--convention", "psi", "--report=~/m/psi.md"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    assert "does not exist" not in captured.err
    report = (home / "m" / "psi.md").read_text(encoding="utf-8")
    assert "psi_model.py:psi_model" in report


def test_check_reads_a_hand_file_under_home(home, capsys):
    """A text hand file, quoted: checked as the same file given by its full path."""
    source = ROOT / "tests/data/hand_correct_north_pointing.txt"
    shutil.copy(source, home / "m" / "phi.txt")
    assert main(["check", "north_pointing", str(source)]) == 0
    plain = capsys.readouterr().out
    assert main(["check", "north_pointing", "~/m/phi.txt", "--report", "~/m/phi.md"]) == 0
    captured = capsys.readouterr()
    assert captured.out == plain.replace(source.name, "phi.txt")
    assert "not found" not in captured.err
    assert (home / "m" / "phi.md").is_file()
    # a missing one is named by the path that was looked for, home written out
    assert main(["check", "north_pointing", "~/m/absent.txt"]) == 2
    error = capsys.readouterr().err
    assert str(home / "m" / "absent.txt") in error and "~" not in error


def test_compare_reads_a_motion_file_and_writes_under_home(home, capsys):
    shutil.copy(ROOT / "examples/strapdown/turn_and_climb.csv", home / "m" / "motion.csv")
    status = main(["compare", "orthodromic", "--motion-file=~/m/motion.csv",
                   "--source", "gyro_drift_x=0.01deg/h", "--duration", "120s",
                   "--no-refined", "--no-progress", "--out=~/curves",
                   "--markdown", "~/m/tables.md"])
    assert status == 0, capsys.readouterr().err
    assert (home / "curves" / "curves.csv").is_file()
    assert (home / "m" / "tables.md").read_text(encoding="utf-8").strip()


def test_budget_spec_and_matrices_out_under_home(home, capsys):
    """``budget --spec ~/...`` reads the spec there (its fixed gyro drift exceeds the
    spec: exit 1, the spec's own answer), ``matrices --out ~/...`` writes there."""
    shutil.copy(ROOT / "examples/specs/gyro_drift_fixed.toml", home / "m" / "spec.toml")
    assert main(["budget", "orthodromic", "--spec", "~/m/spec.toml", "--json"]) == 1
    assert capsys.readouterr().out.lstrip().startswith("{")
    assert main(["matrices", "strapdown_ned", "--hours", "1", "--out", "~/m/F.npz"]) == 0
    with np.load(home / "m" / "F.npz") as stored:
        assert "states" in stored.files


def test_a_scenario_motion_file_under_home(home, tmp_path):
    """A scenario's ``file = "~/m/motion.csv"`` means home as its ``model`` does; the
    scenario keeps the path written out, so every reader (run, sweep) finds the file."""
    from ins_errors.scenario import load_scenario

    shutil.copy(ROOT / "examples/strapdown/turn_and_climb.csv", home / "m" / "motion.csv")
    scenario_file = tmp_path / "s.toml"
    scenario_file.write_text('model = "orthodromic"\n[motion]\nkind = "file"\n'
                             'file = "~/m/motion.csv"\n[run]\nstep = "1 s"\n'
                             '[[case]]\ngyro_drift_x = "0.01 deg/h"\n', encoding="utf-8")
    scenario = load_scenario(scenario_file)
    assert scenario.motion["file"] == str(home / "m" / "motion.csv")
    assert scenario.duration == pytest.approx(1200.0)  # the file's 20 min
