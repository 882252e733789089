"""Exit statuses a pipeline reads, tried as a shell would run the command.

0 done (no mistake found), 1 a check found a mistake, 2 bad input or an output that
cannot be written (one line on stderr), 141 = 128 + SIGPIPE when the reader of standard
output went away. A CI job under ``set -o pipefail`` took the broken pipe's old status 1,
and a full disk's traceback (also 1), for "mistake found".
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")


ENTRY_POINT = "import sys; from ins_errors.cli import main; sys.exit(main())"
"""What the installed ``ins-errors`` script runs."""


def _command(*argv: str) -> list[str]:
    return [sys.executable, "-c", ENTRY_POINT, *argv]


def _environment(tmp_path: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(
        os.pathsep)
    env.setdefault("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    return env


def test_a_reader_that_stops_gives_128_plus_sigpipe_and_nothing_on_stderr(tmp_path):
    """``ins-errors ... | head -1`` with the reader gone before anything is written (its
    end of the pipe closed at once: deterministic, not a race with ``head``). The status
    is set by the entry point for every command (a clean matrix check, the probe's case,
    gave 1 before); ``models --json`` exits 0 when read to the end (the test below)."""
    process = subprocess.Popen(_command("models", "--json"), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, cwd=tmp_path,
                               env=_environment(tmp_path))
    process.stdout.close()  # the only reader: every write now fails with EPIPE
    err = process.stderr.read()
    status = process.wait(timeout=300)
    assert status == 128 + signal.SIGPIPE == 141
    assert err == b""


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
def test_a_full_disk_under_standard_output_is_one_line_and_status_2(tmp_path):
    with open("/dev/full", "w") as full:
        done = subprocess.run(_command("models", "--json"), stdout=full,
                              stderr=subprocess.PIPE, cwd=tmp_path,
                              env=_environment(tmp_path), timeout=300)
    err = done.stderr.decode()
    assert done.returncode == 2
    assert err == ("ins-errors: error: cannot write to standard output: No space left on "
                   "device\n")


def test_python_dash_m_runs_the_command(tmp_path):
    done = subprocess.run([sys.executable, "-m", "ins_errors", "models", "--json"],
                          capture_output=True, cwd=tmp_path, env=_environment(tmp_path),
                          timeout=300)
    assert done.returncode == 0, done.stderr.decode()
    assert "orthodromic" in {m["name"] for m in json.loads(done.stdout)}


def test_the_readme_lists_the_exit_statuses():
    section = README.split("## Five-minute tour", 1)[1].split("\n## ", 1)[0]
    line = " ".join(section.split("Exit status", 1)[1].split("python -m ins_errors", 1)[0]
                    .split())
    for status, meaning in (("0", "done"), ("1", "mistake"), ("2", "bad input"),
                            ("141", "SIGPIPE")):
        assert f"**{status}**" in line and meaning in line, (status, line)


def test_a_motion_file_with_a_byte_order_mark_reads_as_without(tmp_path, monkeypatch, capsys):
    """Spreadsheet programs write UTF-8 CSV with a BOM; it said "lacks column(s) t (has
    \\ufefft, ...)"."""
    rows = "t,v_N,v_E\n0,0,100\n1200,10,100\n2400,0,120\n3600,0,100\n"
    (tmp_path / "plain.csv").write_text(rows, encoding="utf-8")
    (tmp_path / "bom.csv").write_bytes(b"\xef\xbb\xbf" + rows.encode())
    monkeypatch.chdir(tmp_path)
    results = []
    for name in ("plain.csv", "bom.csv"):
        status = main(["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--hours",
                       "1", "--step", "10s", "--no-refined", "--motion-file", name, "--json"])
        captured = capsys.readouterr()
        assert status == 0, captured.err
        results.append(json.loads(captured.out)["cases"])
    assert results[0] == results[1]


def test_a_matrix_archive_of_python_objects_is_named_so(tmp_path, monkeypatch, capsys):
    """A real .npz holding an object array: not "pickled data", and not "not readable"."""
    import numpy as np

    np.savez(tmp_path / "objects.npz", states=np.array([{"a": 1}], dtype=object))
    monkeypatch.chdir(tmp_path)
    status = main(["check", "strapdown_ned", "--matrix", "objects.npz", "--convention", "psi"])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1
    assert "holds Python objects, not numeric arrays" in err and "pickle" not in err


SMALL_SWEEP = """title = "two latitudes"
model = "orthodromic"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "10 min"
step = "10 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
[sweep]
latitude = ["20 deg", "60 deg"]
"""


@pytest.mark.parametrize("engine", ["pool", "dask"])
def test_no_compiler_is_said_once_per_command_in_one_line(engine, tmp_path):
    """A compiler that fails (``CC=/bin/false``): the notice was printed by every worker
    of the pool and Dask engines, each in Python's warning format (source path, code
    line)."""
    if engine == "dask":
        pytest.importorskip("distributed")
    fails = tmp_path / "cc"
    fails.write_text("#!/bin/sh\nexit 1\n")
    fails.chmod(0o755)
    (tmp_path / "sweep.toml").write_text(SMALL_SWEEP, encoding="utf-8")
    env = _environment(tmp_path)
    env.update(CC=str(fails), INS_ERRORS_CACHE=str(tmp_path / "empty_cache"))
    env.pop("INS_ERRORS_NO_JIT", None)
    done = subprocess.run(_command("sweep", "sweep.toml", "--engine", engine, "--workers",
                                   "2", "--store", "s.zarr", "--no-progress"),
                          capture_output=True, cwd=tmp_path, env=env, timeout=600)
    assert done.returncode == 0, done.stderr.decode()
    lines = done.stderr.decode().splitlines()
    count = "ins-errors: sweep 'two latitudes', 2 points, 2 to compute, 0 already in s.zarr"
    assert lines[0].startswith("ins-errors: store: 2 points, about ")
    assert lines[1] == count  # said before the points run
    assert lines[2:] == [f"ins-errors: no working C compiler ({fails} failed with exit "
                         "status 1); compiled loops run in the CasADi virtual machine "
                         "instead (slower, same results)"]
