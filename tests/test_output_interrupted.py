"""A report folder holds one run's files, never a mix of two (long-flight probe).

Ctrl-C while ``compare --out DIR`` wrote curves.mat over an earlier compare's DIR left
the new curves.csv beside the earlier curves.mat (and ``run``: the new report, plots
and curves.csv beside the earlier curves.mat), said only as ``ins-errors: interrupted``:
a MATLAB user loaded the old curves without knowing. A run that stops before it has
written every file is now taken back: the folder holds the earlier run's files again,
byte for byte, and one line says so. The interruptions are injected (a
``KeyboardInterrupt`` raised where a file is written), in a process of its own.

Only the process that made an undo folder takes it back, on its own failure path (the
command line's, or a ``with OutputFolder(...)`` block an exception leaves): never a
later run into the folder, which refuses another process's undo folder (reviewer: a pid
reused by another process, or two runs into one folder, reverted a finished run), and
never at a normal exit (an API caller who never calls finish() keeps its files).
"""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from ins_errors.output import (
    DONE_PREFIX,
    JOURNAL,
    KEPT,
    MANIFEST,
    UNDO_PREFIX,
    OutputError,
    OutputFolder,
    take_back,
)


def _contents(folder) -> dict[str, bytes]:
    """Every entry of ``folder`` (a subfolder as None), by name."""
    return {p.name: (None if p.is_dir() else p.read_bytes()) for p in folder.iterdir()}


def _earlier_run(folder, names=("report.md", "curves.csv", "curves.mat")) -> dict:
    out = OutputFolder(folder)
    for name in names:
        out.write_text(name, f"earlier {name}\n")
    out.finish()
    return _contents(folder)


def _python(code: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code), *args],
                          capture_output=True, text=True, timeout=300)


INTERRUPTED_WRITE = """
    import sys
    from ins_errors.output import OutputFolder

    def stop(path):
        raise KeyboardInterrupt

    with OutputFolder(sys.argv[1], force=True) as out:
        out.write_text("report.md", "new report")
        out.write_text("curves.csv", "new curves")
        out.write_text("notes.txt", "ins-errors' notes.txt")
        out.write_with("curves.mat", stop)   # Ctrl-C while curves.mat is written
"""


def test_an_interrupted_run_leaves_the_earlier_files_byte_for_byte(tmp_path):
    folder = tmp_path / "out"
    before = _earlier_run(folder)
    done = _python(INTERRUPTED_WRITE, str(folder))
    assert done.returncode != 0 and "KeyboardInterrupt" in done.stderr
    assert _contents(folder) == before  # no new curves.csv beside the earlier curves.mat
    (line,) = [x for x in done.stderr.splitlines() if x.startswith("ins-errors:")]
    assert str(folder) in line and "earlier files" in line


def test_a_strangers_files_survive_an_interrupted_forced_run(tmp_path):
    """With --force a stranger's file of a name ins-errors writes is replaced by a
    finished run (as before), and is back as it was after an interrupted one."""
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "notes.txt").write_text("the user's own notes")
    (folder / "data.bin").write_bytes(b"\x00\x01")
    before = _contents(folder)
    done = _python(INTERRUPTED_WRITE, str(folder))
    assert done.returncode != 0
    assert _contents(folder) == before


def test_an_interrupted_first_run_leaves_no_folder(tmp_path):
    folder = tmp_path / "new" / "out"
    (tmp_path / "new").mkdir()
    done = _python(INTERRUPTED_WRITE, str(folder))
    assert done.returncode != 0
    assert not folder.exists()


def _killed_run(folder) -> subprocess.CompletedProcess:
    """A run into ``folder`` killed outright (SIGKILL) after writing three files."""
    done = _python("""
        import os, signal, sys
        from ins_errors.output import OutputFolder

        out = OutputFolder(sys.argv[1])
        out.write_text("report.md", "killed report")
        out.write_text("curves.csv", "killed curves")
        out.write_text("case_1.png", "killed plot")
        os.kill(os.getpid(), signal.SIGKILL)
    """, str(folder))
    assert done.returncode == -signal.SIGKILL
    return done


def _undo_folders(folder) -> list:
    return [p for p in folder.iterdir() if p.name.startswith(UNDO_PREFIX)]


def test_a_killed_runs_undo_folder_is_refused_until_force(tmp_path, capsys):
    """SIGKILL gives no time to take anything back: the undo folder stays, and a later
    run into the folder is refused (it cannot know that run is gone) in one line naming
    it, before computing too; --force discards the undo folder (the folder holds the
    mix until the forced run finishes, then only its files)."""
    from ins_errors.cli import main

    folder = tmp_path / "out"
    _earlier_run(folder)
    _killed_run(folder)
    mix = _contents(folder)
    assert (folder / "curves.csv").read_text() == "killed curves"
    (undo,) = _undo_folders(folder)
    journal = json.loads((undo / JOURNAL).read_text())
    for create in (False, True):
        with pytest.raises(OutputError) as refused:
            OutputFolder(folder, create=create)
        line = str(refused.value)
        assert f"process {journal['pid']} on host {journal['host']}" in line
        assert undo.name in line and "--force" in line and "\n" not in line
    assert _contents(folder) == mix  # refusing changes nothing
    argv = ["compare", "orthodromic", "--hours", "0.25", "--step", "60s", "--source",
            "gyro_drift_x=0.01deg/h", "--out", str(folder)]
    capsys.readouterr()
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"process {journal['pid']}" in err[0], err
    forced = OutputFolder(folder, force=True)
    assert not _undo_folders(folder)
    assert (folder / "curves.csv").read_text() == "killed curves"  # the mix, for now
    forced.write_text("report.md", "forced")
    forced.finish()
    assert set(_contents(folder)) == {"report.md", MANIFEST}


def test_a_reused_pid_never_reverts_a_later_finished_run(tmp_path):
    """Reviewer: the killed run's pid, now another process's, kept its undo folder
    aside; a later run finished beside it, and once that process ended the next open
    took the old undo folder back over the finished files. Simulated with the journal:
    the killed run's pid is set to a process that runs."""
    folder = tmp_path / "out"
    _earlier_run(folder)
    _killed_run(folder)
    (undo,) = _undo_folders(folder)
    stranger = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    try:
        journal = json.loads((undo / JOURNAL).read_text())
        (undo / JOURNAL).write_text(json.dumps({**journal, "pid": stranger.pid}))
        with pytest.raises(OutputError, match=f"process {stranger.pid} "):
            OutputFolder(folder)
        later = OutputFolder(folder, force=True)
        later.write_text("report.md", "later report")
        later.write_text("curves.csv", "later curves")
        later.finish()
        finished = _contents(folder)
    finally:
        stranger.kill()
        stranger.wait()
    again = OutputFolder(folder)  # that pid is free again
    assert _contents(folder) == finished
    assert again.previous == ["report.md", "curves.csv"]


def test_a_run_writing_now_is_not_undone_by_nor_undoes_another(tmp_path):
    """Reviewer: run B opened a folder while run A was writing there; when A then
    failed, its take back removed the files it had made new, by then B's finished
    files and manifest, and said the folder held the earlier files again. Now B is
    refused while A runs; B with --force discards A's undo folder, and A's take back
    then touches nothing and says so."""
    folder = tmp_path / "report"
    _earlier_run(folder, ("report.md",))
    driver = textwrap.dedent("""
        import json, sys
        from ins_errors import export
        from ins_errors.cli import main

        def wait(*args, **kwargs):
            print("writing", flush=True)
            sys.stdin.readline()
            raise KeyboardInterrupt
        export.save_curves_mat = wait
        sys.exit(main(json.loads(sys.argv[1])))
    """)
    argv = ["compare", "orthodromic", "--hours", "0.25", "--step", "60s", "--source",
            "gyro_drift_x=0.01deg/h", "--out", str(folder)]
    run_a = subprocess.Popen([sys.executable, "-c", driver, json.dumps(argv)],
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        assert run_a.stdout.readline() == "writing\n"  # A has written curves.csv
        with pytest.raises(OutputError, match=f"process {run_a.pid} .*--force"):
            OutputFolder(folder)
        run_b = OutputFolder(folder, force=True)
        run_b.write_text("curves.csv", "B's curves")
        run_b.write_text("curves.mat", "B's mat")
        run_b.finish()
        finished = {name: data for name, data in _contents(folder).items()
                    if not name.startswith(".curves.mat.")}  # (A's scratch file)
        _, err = run_a.communicate("\n", timeout=300)
    finally:
        run_a.kill()
    assert run_a.returncode == 130, err
    assert _contents(folder) == finished
    assert json.loads((folder / MANIFEST).read_text())["files"] == ["curves.csv",
                                                                     "curves.mat"]
    last = err.strip().splitlines()[-1]
    assert "nothing is taken back" in last and "earlier files again" not in last


def test_of_two_runs_starting_together_the_later_to_write_backs_off(tmp_path):
    """Both opened the folder before either had an undo folder: the one whose undo
    folder comes second sees the other's and is refused, leaving nothing of its own."""
    folder = tmp_path / "out"
    before = _earlier_run(folder)
    late = OutputFolder(folder)
    other = folder / f"{UNDO_PREFIX}other"
    (other / KEPT).mkdir(parents=True)
    (other / JOURNAL).write_text(json.dumps({"pid": 1, "host": "elsewhere",
                                             "started": "now", "made_folder": False,
                                             "created": []}))
    with pytest.raises(OutputError, match="process 1 on host elsewhere"):
        late.write_text("report.md", "late")
    assert _contents(folder) == {**before, other.name: None}


def test_a_take_back_that_cannot_put_a_file_back_keeps_it(tmp_path, capsys):
    """Reviewer: an entry that could not be put back was passed over, then the undo
    folder deleted with the earlier file in it. Injected: a folder where the earlier
    curves.csv goes back."""
    folder = tmp_path / "out"
    before = _earlier_run(folder)
    out = OutputFolder(folder)
    out.write_text("report.md", "new report")
    out.write_text("curves.csv", "new curves")
    (undo,) = _undo_folders(folder)
    (folder / "curves.csv").unlink()
    (folder / "curves.csv").mkdir()
    (folder / "curves.csv" / "inside").write_text("x")
    take_back(undo)
    assert (undo / KEPT / "curves.csv").read_bytes() == before["curves.csv"]
    assert (folder / "report.md").read_bytes() == before["report.md"]  # the rest is back
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "curves.csv" in line and str(undo / KEPT) in line
    with pytest.raises(OutputError, match=undo.name):  # kept, and said so, until --force
        OutputFolder(folder)


def test_an_api_run_never_finished_keeps_its_files_at_exit(tmp_path):
    """Reviewer: a caller of the Python API who never calls finish() lost every file
    it wrote as the interpreter exited (they used to stay)."""
    folder = tmp_path / "out"
    _earlier_run(folder)
    done = _python("""
        import sys
        from ins_errors.output import OutputFolder

        out = OutputFolder(sys.argv[1])
        out.write_text("report.md", "new report")
        out.write_text("extra.txt", "new extra")
    """, str(folder))
    assert done.returncode == 0 and not done.stderr, done.stderr
    contents = _contents(folder)
    assert contents["report.md"] == b"new report" and contents["extra.txt"] == b"new extra"
    assert not _undo_folders(folder) and not any(n.startswith(DONE_PREFIX) for n in contents)
    assert OutputFolder(folder).previous == ["report.md", "curves.csv", "curves.mat",
                                             "extra.txt"]


def test_a_finished_run_leaves_only_its_files(tmp_path):
    """The bookkeeping is gone once a run finishes; the next run replaces its files and
    removes the ones it does not write, as before."""
    folder = tmp_path / "out"
    _earlier_run(folder, ("case_1.png", "case_2.png", "curves.mat"))
    out = OutputFolder(folder)
    out.write_text("case_1.png", "new plot")
    out.write_text("curves.csv", "new curves")
    out.finish()
    assert set(_contents(folder)) == {"case_1.png", "curves.csv", MANIFEST}
    assert json.loads((folder / MANIFEST).read_text())["files"] == ["case_1.png",
                                                                     "curves.csv"]
    assert (folder / "case_1.png").read_text() == "new plot"


def test_a_with_block_an_exception_leaves_is_taken_back_at_once(tmp_path):
    """The Python API: an interrupted write in a notebook, written as a with block,
    leaves the earlier run's files (a block left normally finishes the run)."""
    folder = tmp_path / "out"
    before = _earlier_run(folder)
    with pytest.raises(KeyboardInterrupt), OutputFolder(folder) as out:
        out.write_text("report.md", "new")
        out.write_with("curves.mat", lambda p: (_ for _ in ()).throw(KeyboardInterrupt))
    assert _contents(folder) == before
    with OutputFolder(folder) as out:
        out.write_text("report.md", "new")
    assert set(_contents(folder)) == {"report.md", MANIFEST}


def test_a_run_dropped_unfinished_in_this_process_keeps_its_files_on_the_next_open(
        tmp_path):
    """The Python API without a with block or finish(): the dropped run's files stay
    (as at exit), the next open in this process is not refused, and its finish leaves
    only its own files."""
    folder = tmp_path / "out"
    _earlier_run(folder)
    out = OutputFolder(folder)
    out.write_text("report.md", "new")
    with pytest.raises(KeyboardInterrupt):
        out.write_with("curves.mat", lambda p: (_ for _ in ()).throw(KeyboardInterrupt))
    again = OutputFolder(folder)
    assert (folder / "report.md").read_text() == "new" and not _undo_folders(folder)
    assert again.previous == ["report.md", "curves.csv", "curves.mat"]
    again.write_text("curves.csv", "again")
    again.finish()
    assert set(_contents(folder)) == {"curves.csv", MANIFEST}


@pytest.mark.parametrize("command", ["compare", "run"])
def test_ctrl_c_while_the_curves_are_written_keeps_the_earlier_report(tmp_path, command):
    """The probe's case through the command line: Ctrl-C (here raised where curves.mat
    is written) after an earlier complete run into the same --out folder."""
    folder = tmp_path / "report"
    if command == "compare":
        argv = ["compare", "orthodromic", "--hours", "0.25", "--step", "60s",
                "--out", str(folder)]
        first, second = ["--source", "gyro_drift_x=0.01deg/h"], [
            "--source", "gyro_drift_x=0.02deg/h"]
    else:
        scenario = tmp_path / "s.toml"
        scenario.write_text(textwrap.dedent("""
            title = "drift"
            model = "orthodromic"
            [motion]
            kind = "static"
            latitude = "50 deg"
            [run]
            duration = "15 min"
            step = "60 s"
            [[case]]
            label = "drift"
            gyro_drift_x = "0.01 deg/h"
        """))
        argv = ["run", str(scenario), "--out", str(folder)]
        first, second = [], ["--no-progress"]
    driver = """
        import json, pathlib, sys
        from ins_errors import export
        from ins_errors.cli import main

        argv = json.loads(sys.argv[1])
        assert main(argv[0]) == 0
        folder = pathlib.Path(argv[2])
        print(json.dumps({p.name: p.read_bytes().hex() for p in folder.iterdir()}))

        def stop(*args, **kwargs):
            raise KeyboardInterrupt
        export.save_curves_mat = stop
        sys.exit(main(argv[1]))
    """
    done = _python(driver, json.dumps([argv + first, argv + second, str(folder)]))
    assert done.returncode == 130, done.stderr
    (listing,) = [x for x in done.stdout.splitlines() if x.startswith('{"')]
    before = {name: bytes.fromhex(data) for name, data in json.loads(listing).items()}
    assert {"curves.csv", "curves.mat", MANIFEST} <= set(before)
    assert _contents(folder) == before
    lines = done.stderr.strip().splitlines()
    assert lines[-2] == "ins-errors: interrupted"
    assert lines[-1].startswith(f"ins-errors: --out {folder}: ")
    assert not any(n.startswith((UNDO_PREFIX, DONE_PREFIX)) for n in os.listdir(folder))


def test_write_report_from_python_is_taken_back_when_stopped(tmp_path, monkeypatch):
    """The report writers of the Python API (a scenario's report, the propagation
    studies' reports) take their run back when stopped, as the command line does: an
    earlier report stays byte for byte, never a mix of two runs."""
    from ins_errors import export
    from ins_errors.report import write_report
    from ins_errors.scenario import load_scenario, run_scenario

    scenario = load_scenario(Path(__file__).resolve().parents[1] / "examples"
                             / "lab_000_task1_gyro_drift.toml")
    scenario = dataclasses.replace(scenario, duration=3600.0, step=60.0, record=600.0)
    result = run_scenario(scenario)
    out = tmp_path / "report"
    write_report(result, out)
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    changed = dataclasses.replace(result, comparisons=result.comparisons[:1])

    def stopped(comparisons, path):
        raise KeyboardInterrupt

    monkeypatch.setattr(export, "save_curves_mat", stopped)
    with pytest.raises(KeyboardInterrupt):
        write_report(changed, out)
    after = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    assert after == before
