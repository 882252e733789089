"""What a CI job or a batch system does to the command: processes started together on an
empty cache, SIGTERM while a Dask cluster starts, a closed or ASCII-only standard output,
a stop after the last point, ``cache clear`` and a read-only cache's order (a CI/DevOps
probe)."""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from ins_errors.cli import main
from ins_errors.numeric import cache
from tests.helpers import SLOW_SWEEP

ROOT = Path(__file__).resolve().parent.parent


def _environment(cache_folder: Path, **more: str) -> dict[str, str]:
    """This process's environment for a child that imports this checkout, with the cache
    ``cache_folder``."""
    return dict(os.environ, INS_ERRORS_CACHE=str(cache_folder), **more,
                PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT),
                                                         os.environ.get("PYTHONPATH")])))


# --------------------------------------------------------------------------------------
# pint's parsed units, several processes on one empty cache
# --------------------------------------------------------------------------------------
NAUTICAL_MILE = ("from ins_errors.units import registry\n"
                 "print(float(registry().Quantity(1, 'nautical_mile').to('m').magnitude))\n")
"""A child's code: the units registry (from the cache), one conversion printed."""

HELD_WRITER = """import pathlib, pickle, sys, time
import flexcache.flexcache as written
held, release = map(pathlib.Path, sys.argv[1:3])

class HeldPickle:   # pint's cache writes its files through flexcache's pickle.dump
    def __getattr__(self, name):
        return getattr(pickle, name)

    @staticmethod
    def dump(value, file):
        data = pickle.dumps(value)
        file.write(data[:len(data) // 2])
        file.flush()
        if not held.exists():   # the first file half written: held there
            held.write_text("held")
            while not release.exists():
                time.sleep(0.01)
        file.write(data[len(data) // 2:])

written.pickle = HeldPickle()
""" + NAUTICAL_MILE


def _wait_for(path: Path, process: subprocess.Popen, seconds: float = 120) -> None:
    deadline = time.monotonic() + seconds
    while not path.exists() and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert path.exists(), process.communicate(timeout=60)


def _units_sets(cache_folder: Path) -> list[Path]:
    return sorted(p for p in (cache_folder / "units").iterdir())


@pytest.mark.parametrize("writer_ends", ["finishes", "is killed"])
def test_a_set_of_parsed_units_half_written_by_another_process_is_never_read(
        tmp_path, writer_ends):
    """Was: one process parsing pint's definitions wrote the set in place, its note
    first, and a process started with it read a file half written, said
    "ins-errors: the cache entry '.../units/<hash>' is damaged ... parsing pint's unit
    definitions again" and deleted the folder the other was writing (3-4 of 12-15
    trials of four processes started together). Here the writer is held with its first
    file half written: the reader says nothing and converts; the writer, let go or
    killed, leaves one whole set, which a third process reads without writing."""
    cache_folder = tmp_path / "cache"
    held, release = tmp_path / "held", tmp_path / "release"
    env = _environment(cache_folder)
    writer = subprocess.Popen([sys.executable, "-c", HELD_WRITER, str(held), str(release)],
                              cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    try:
        _wait_for(held, writer)
        reader = subprocess.run([sys.executable, "-c", NAUTICAL_MILE], cwd=tmp_path,
                                env=env, capture_output=True, text=True, timeout=300)
        if writer_ends == "finishes":
            release.write_text("go")
            out, err = writer.communicate(timeout=300)
            assert (writer.returncode, out, err) == (0, "1852.0\n", "")
        else:
            writer.kill()
            writer.wait(timeout=60)
    finally:
        if writer.poll() is None:
            writer.kill()
            writer.wait()
    assert (reader.returncode, reader.stdout, reader.stderr) == (0, "1852.0\n", "")
    whole = [p for p in _units_sets(cache_folder) if (p / "installation.txt").is_file()]
    assert len(whole) == 1
    files = {p.name: p.stat().st_mtime_ns for p in whole[0].iterdir()}
    again = subprocess.run([sys.executable, "-c", NAUTICAL_MILE], cwd=tmp_path, env=env,
                           capture_output=True, text=True, timeout=300)
    assert (again.returncode, again.stdout, again.stderr) == (0, "1852.0\n", "")
    assert {p.name: p.stat().st_mtime_ns for p in whole[0].iterdir()} == files
    if writer_ends == "finishes":   # the writer's own scratch folder is gone with it
        assert _units_sets(cache_folder) == whole


# --------------------------------------------------------------------------------------
# SIGTERM while a local Dask cluster starts
# --------------------------------------------------------------------------------------
SWEEP = SLOW_SWEEP


@pytest.mark.parametrize("sent_to", ["process", "group"])
def test_sigterm_while_the_workers_of_a_dask_cluster_start_is_one_line(tmp_path, sent_to):
    """``timeout 3.5 ins-errors sweep ... --engine dask --workers 2`` (SIGTERM to the
    process, then to its group) with the workers still starting printed the right line,
    then "Exception ignored in atexit callback: <function close_clusters>" and an
    ``AssertionError: Status.init`` traceback: Dask closed at exit the cluster whose
    start the stop had cut short. The workers' start is held here (each nanny waits
    1.5 s before it starts its worker) and the signal sent meanwhile; the child is
    started as a terminal starts it (SIGINT at Python's handler)."""
    pytest.importorskip("distributed")
    psutil = pytest.importorskip("psutil")
    (tmp_path / "sweep.toml").write_text(SWEEP, encoding="utf-8")
    code = ("import asyncio, signal, sys\n"
            "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
            "from distributed import nanny\n"
            "starts = nanny.Nanny.start_unsafe\n"
            "async def held(self):\n"
            "    with open('started', 'w') as file:\n"
            "        file.write('started')\n"
            "    await asyncio.sleep(1.5)\n"
            "    return await starts(self)\n"
            "nanny.Nanny.start_unsafe = held\n"
            "from ins_errors.cli import main\n"
            "sys.exit(main(['sweep', 'sweep.toml', '--engine', 'dask', '--workers', '2',"
            " '--store', 's.zarr', '--no-progress']))\n")
    env = _environment(tmp_path / "cache")
    env.pop("INS_ERRORS_CACHE")   # this suite's warm cache: no compile in the child
    process = subprocess.Popen([sys.executable, "-c", code], cwd=tmp_path, env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    children: list = []
    try:
        _wait_for(tmp_path / "started", process)
        children = psutil.Process(process.pid).children(recursive=True)
        (os.killpg if sent_to == "group" else os.kill)(process.pid, signal.SIGTERM)
        out, err = process.communicate(timeout=120)
        _, alive = psutil.wait_procs(children, timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 128 + signal.SIGTERM, err
    lines = err.splitlines()   # the sweep's two notes, then the one line: nothing else
    assert lines[-1] == "ins-errors: terminated (signal 15) before any point was stored"
    assert all(line.startswith("ins-errors: ") for line in lines), err
    assert out == "" and alive == []


# --------------------------------------------------------------------------------------
# standard output closed, or of an encoding without the characters written
# --------------------------------------------------------------------------------------
def test_a_closed_standard_output_or_error_is_written_nothing(tmp_path):
    """``ins-errors compare ... >&-`` gave "AttributeError: 'NoneType' object has no
    attribute 'write'" and a traceback (Python starts with ``sys.stdout`` None); with
    standard error closed, an error line went to standard output. Now the command runs
    and writes nothing there, with its exit status."""
    env = _environment(tmp_path / "cache")
    env.pop("INS_ERRORS_CACHE")

    def run(arguments: list[str], closed: int) -> subprocess.CompletedProcess:
        command = shlex.join([sys.executable, "-m", "ins_errors", *arguments])
        return subprocess.run(["sh", "-c", f"exec {command} {closed}>&-"], cwd=tmp_path,
                              env=env, capture_output=True, text=True, timeout=300)

    compared = run(["compare", "orthodromic", "--source", "gyro_drift_x=0.01deg/h",
                    "--hours", "1", "--step", "10s", "--no-progress"], closed=1)
    assert (compared.returncode, compared.stdout, compared.stderr) == (0, "", "")
    refused = run(["modes", "no_such_model"], closed=2)
    assert (refused.returncode, refused.stdout, refused.stderr) == (2, "", "")
    shown = run(["modes", "orthodromic"], closed=2)
    assert shown.returncode == 0 and "φ=50°" in shown.stdout


def test_characters_an_ascii_standard_output_lacks_are_written_as_escapes(tmp_path):
    """``PYTHONIOENCODING=ascii ins-errors modes orthodromic`` ended in a
    UnicodeEncodeError traceback on φ; each such character is now written as its
    Python escape, as Python writes standard error, the rest as it is."""
    env = _environment(tmp_path / "cache", PYTHONIOENCODING="ascii")
    env.pop("INS_ERRORS_CACHE")
    done = subprocess.run([sys.executable, "-m", "ins_errors", "modes", "orthodromic"],
                          cwd=tmp_path, env=env, capture_output=True, timeout=300)
    assert (done.returncode, done.stderr) == (0, b"")
    utf8 = subprocess.run([sys.executable, "-m", "ins_errors", "modes", "orthodromic"],
                          cwd=tmp_path, env={**env, "PYTHONIOENCODING": "utf-8"},
                          capture_output=True, timeout=300)
    assert done.stdout.decode("ascii") == utf8.stdout.decode("utf-8").encode(
        "ascii", "backslashreplace").decode("ascii")
    assert "\\u03c6=50\\xb0" in done.stdout.decode("ascii")


# --------------------------------------------------------------------------------------
# small things
# --------------------------------------------------------------------------------------
def test_a_stop_after_every_point_is_stored_says_they_all_are(tmp_path, monkeypatch,
                                                               capsys):
    """A SIGTERM after the last point was stored said "28 of the 28 points are in
    t.zarr; the same command runs the others" (there are none)."""
    from ins_errors.analysis import sweep_report
    from ins_errors.analysis.engine import Terminated

    (tmp_path / "sweep.toml").write_text(
        SWEEP.replace('"4 h"', '"10 min"').replace(
            'latitude = ["10 deg", "20 deg", "30 deg", "40 deg", "50 deg"]\n'
            'heading = { start = "0 deg", stop = "90 deg", count = 4 }',
            'latitude = ["10 deg", "20 deg", "30 deg"]'), encoding="utf-8")

    def stopped(*args, **kwargs):   # the stop comes as the figure is drawn
        raise Terminated

    monkeypatch.setattr(sweep_report, "plot", stopped)
    store = tmp_path / "t.zarr"
    assert main(["sweep", str(tmp_path / "sweep.toml"), "--store", str(store), "--engine",
                 "serial", "--no-progress", "--plot", str(tmp_path / "s.png")]) == 143
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line == f"ins-errors: terminated (signal 15): the sweep's 3 points are all in {store}"


def _library(folder: Path, name: str, age: float) -> Path:
    path = folder / f"loop_{name}.so"
    path.write_bytes(b"\0" * 100)
    then = time.time() - age
    os.utime(path, (then, then))
    return path


def test_cache_clear_leaves_no_owners_folder_and_counts_in_words(tmp_path, monkeypatch,
                                                                   capsys):
    """``cache clear`` left ``owners/<checkout>/`` behind (empty), and said "removed 1
    compiled libraries"."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    library = _library(tmp_path, "a", age=5)
    cache.register(library)
    gone = tmp_path / "owners" / "0123456789abcdef" / "loop_deleted_by_hand.so"
    gone.parent.mkdir(parents=True)
    gone.touch()   # the mark of a library deleted by hand
    assert (tmp_path / "owners" / cache.checkout_id() / library.name).exists()
    assert main(["cache", "clear"]) == 0
    out = capsys.readouterr().out
    assert not (tmp_path / "owners").exists() and not library.exists()
    assert f"removed 1 compiled library (0.0 MB) from {tmp_path}\n" in out
    assert "removed 1 files" not in out and "removed 0 file " not in out


def test_a_read_only_caches_loops_keep_their_times(tmp_path):
    """A loop of a read-only cache is used through its link in the private folder; the
    link's touch set the loop's own time (the owner of a file may, even in a folder that
    cannot be written), so the read-only cache's order changed, which docs/cache.md says
    it does not. A loop of a writable cache is still marked used."""
    shared, private = tmp_path / "shared", tmp_path / "private"
    shared.mkdir()
    private.mkdir()
    library = _library(shared, "a", age=3600)
    before = library.stat().st_mtime_ns
    link = private / library.name
    link.symlink_to(library)
    cache.touch(link)
    assert library.stat().st_mtime_ns == before
    assert not (private / "owners").exists()
    cache.touch(library)   # the writable cache's own loop: used now
    assert library.stat().st_mtime_ns > before
    assert (shared / "owners" / cache.checkout_id() / library.name).exists()
