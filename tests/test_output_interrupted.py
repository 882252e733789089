"""A report folder holds one run's files, never a mix of two (long-flight probe).

Ctrl-C while ``compare --out DIR`` wrote curves.mat over an earlier compare's DIR left
the new curves.csv beside the earlier curves.mat (and ``run``: the new report, plots
and curves.csv beside the earlier curves.mat), said only as ``ins-errors: interrupted``:
a MATLAB user loaded the old curves without knowing. A run that stops before it has
written every file is now taken back: the folder holds the earlier run's files again,
byte for byte, and one line says so. The interruptions are injected (a
``KeyboardInterrupt`` raised where a file is written), in a process of its own where the
taking back happens as the process ends.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap

import pytest

from ins_errors.output import DONE_PREFIX, MANIFEST, UNDO_PREFIX, OutputFolder


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

    out = OutputFolder(sys.argv[1], force=True)
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


def test_a_killed_run_is_taken_back_when_the_folder_is_next_written(tmp_path):
    """SIGKILL gives no time to take anything back: the undo folder stays, and the next
    run into the folder takes it back before it starts (its files then replace the
    earlier ones as in any run)."""
    folder = tmp_path / "out"
    before = _earlier_run(folder)
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
    assert (folder / "curves.csv").read_text() == "killed curves"  # the mix, for now
    OutputFolder(folder, create=False)  # a check before computing: not refused, no change
    assert (folder / "curves.csv").read_text() == "killed curves"
    OutputFolder(folder)  # the next run opens the folder
    assert _contents(folder) == before


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


def test_a_run_dropped_unfinished_in_this_process_is_taken_back_on_the_next_open(
        tmp_path):
    """The Python API: an interrupted write_report in a notebook, then another one into
    the same folder, starts from the earlier run's files."""
    folder = tmp_path / "out"
    before = _earlier_run(folder)
    out = OutputFolder(folder)
    out.write_text("report.md", "new")
    with pytest.raises(KeyboardInterrupt):
        out.write_with("curves.mat", lambda p: (_ for _ in ()).throw(KeyboardInterrupt))
    del out
    again = OutputFolder(folder)
    assert again.previous == ["report.md", "curves.csv", "curves.mat"]
    assert _contents(folder) == before


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
