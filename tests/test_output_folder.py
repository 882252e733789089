"""A report folder stays ins-errors' own even when a run is interrupted between files.

The manifest (``.ins-errors-files.json``) must never lag behind what ins-errors has put
in the folder: after Ctrl-C between two files, the same command writes into the folder
again without ``--force`` and leaves exactly the new run's files (plus a stranger's).
"""

from __future__ import annotations

import pytest

from ins_errors.output import MANIFEST, UNDO_PREFIX, OutputError, OutputFolder


def _interrupt(_path):
    raise KeyboardInterrupt


def _names(folder) -> set[str]:
    return {p.name for p in folder.iterdir()}


def _undo(folder) -> set[str]:
    return {p.name for p in folder.iterdir() if p.name.startswith(UNDO_PREFIX)}


def test_interrupted_fresh_run_can_be_rerun_without_force(tmp_path):
    folder = tmp_path / "out"
    first = OutputFolder(folder)
    first.write_text("report.md", "first")
    first.write_text("curves.csv", "t,x\n")
    with pytest.raises(KeyboardInterrupt):
        first.write_with("curves.mat", _interrupt)  # Ctrl-C while curves.mat is written
    # no temporary file left; the new files stay until the run is taken back
    assert _names(folder) - _undo(folder) == {"report.md", "curves.csv", MANIFEST}
    # the rerun is not refused, and what it does not write (curves.csv) is removed
    second = OutputFolder(folder)
    second.write_text("report.md", "second")
    second.write_with("curves.mat", lambda p: p.write_bytes(b"mat"))
    second.finish()
    assert _names(folder) == {"report.md", "curves.mat", MANIFEST}
    assert (folder / "report.md").read_text() == "second"


def test_interrupted_rerun_keeps_strangers_and_removes_the_earlier_runs_files(tmp_path):
    folder = tmp_path / "out"
    complete = OutputFolder(folder)
    for name in ("case_1.png", "case_2.png", "case_3.png"):
        complete.write_text(name, name)
    complete.finish()
    (folder / "notes.txt").write_text("mine")
    interrupted = OutputFolder(folder)
    interrupted.write_text("case_1.png", "new")
    interrupted.write_text("curves.csv", "new")
    with pytest.raises(KeyboardInterrupt):
        interrupted.write_with("curves.mat", _interrupt)
    last = OutputFolder(folder)
    last.write_text("case_1.png", "last")
    last.finish()
    assert _names(folder) == {"case_1.png", "notes.txt", MANIFEST}
    assert (folder / "notes.txt").read_text() == "mine"


def test_a_strangers_folder_is_still_refused(tmp_path):
    (tmp_path / "data.txt").write_text("x")
    with pytest.raises(OutputError, match="--force"):
        OutputFolder(tmp_path)
    forced = OutputFolder(tmp_path, force=True)
    forced.write_text("report.md", "r")
    forced.finish()
    assert _names(tmp_path) == {"data.txt", "report.md", MANIFEST}
