"""The cache folder while loops are being compiled, and where ``$INS_ERRORS_CACHE`` points.

``ins-errors cache clear`` run by one process while another compiles deleted the
compile's scratch folder; the compile then said "no working C compiler (... loop.c: No
such file)" and fell back to the virtual machine. The interleavings here are exact: the
other process's step runs inside a stand-in for the compiler call, never by timing.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import casadi as ca
import pytest

from ins_errors.cli import main
from ins_errors.numeric import cache
from ins_errors.numeric import integrators as integ


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache folder; the no-compiler notice recorded instead of warned."""
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    folder = tmp_path / "cache"
    monkeypatch.setenv("INS_ERRORS_CACHE", str(folder))
    notices: list[str] = []
    monkeypatch.setattr(integ, "_vm_notice", lambda reason, full=None: notices.append(reason))
    return folder, notices


def _probe(name: str) -> list[ca.Function]:
    x = ca.SX.sym("x")
    return [ca.Function(name, [x], [3 * x + 1])]


def _around_the_compiler(monkeypatch, before) -> list[Path]:
    """Run ``before(scratch_folder)`` just before each compiler call; returns the scratch
    folders seen."""
    real_run = subprocess.run
    seen: list[Path] = []

    def run(command, *args, **kwargs):
        if isinstance(command, list) and "-o" in command:
            scratch = Path(command[command.index("-o") + 1]).parent
            seen.append(scratch)
            before(scratch)
        return real_run(command, *args, **kwargs)

    monkeypatch.setattr(integ.subprocess, "run", run)
    return seen


def test_clear_while_another_process_compiles_leaves_its_scratch_folder(
        fresh_cache, monkeypatch, capsys):
    folder, notices = fresh_cache
    seen = _around_the_compiler(monkeypatch, lambda scratch: main(["cache", "clear"]))
    library = integ.compile_library(_probe("probe_clear_between"))
    assert notices == []  # no false "no working C compiler"
    assert library is not None and library.is_file()
    assert len(seen) == 1  # compiled once: the folder was left alone, nothing retried
    assert "removed" in capsys.readouterr().out  # the clear did run in between
    function = ca.external("probe_clear_between", str(library))
    assert float(function(2.0)) == 7.0
    assert not list(folder.glob(f"{cache.SCRATCH_PREFIX}*"))  # scratch removed after


def test_a_scratch_folder_deleted_under_a_compile_is_a_retry_not_a_missing_compiler(
        fresh_cache, monkeypatch):
    """Another tool (or an older ins-errors) deleting the folder anyway: compiled again."""
    _folder, notices = fresh_cache
    deleted = []

    def delete_once(scratch: Path) -> None:
        if not deleted:
            deleted.append(scratch)
            shutil.rmtree(scratch)

    seen = _around_the_compiler(monkeypatch, delete_once)
    library = integ.compile_library(_probe("probe_deleted_scratch"))
    assert notices == []
    assert library is not None and library.is_file()
    assert len(seen) == 2 and seen[0] == deleted[0] != seen[1]
    assert float(ca.external("probe_deleted_scratch", str(library))(2.0)) == 7.0


def test_a_broken_compiler_still_falls_back_once(fresh_cache, monkeypatch, tmp_path):
    """The retry is for a vanished folder only: a compiler that fails is not run again."""
    _folder, notices = fresh_cache
    broken = tmp_path / "cc"
    broken.write_text("#!/bin/sh\necho 'cc: internal error' >&2\nexit 1\n")
    broken.chmod(0o755)
    monkeypatch.setattr(integ, "_compiler", lambda: str(broken))
    seen = _around_the_compiler(monkeypatch, lambda scratch: None)
    assert integ.compile_library(_probe("probe_broken_cc")) is None
    assert len(seen) == 1 and len(notices) == 1 and "failed" in notices[0]


def test_clear_removes_the_scratch_folders_of_dead_compiles_only(tmp_path, monkeypatch, capsys):
    folder = tmp_path / "cache"
    folder.mkdir()
    monkeypatch.setenv("INS_ERRORS_CACHE", str(folder))
    old = os.path.getmtime(folder) - 3600
    dead = folder / "tmpdead"  # an interrupted compile: its process (and lock) is gone
    dead.mkdir()
    (dead / "loop.c").write_text("int x;")
    (dead / cache.SCRATCH_LOCK).touch()
    older = folder / "tmpolder"  # an older version's scratch folder: no lock file at all
    older.mkdir()
    (older / "loop.c").write_text("int x;")
    for path in (dead / "loop.c", dead / cache.SCRATCH_LOCK, dead, older / "loop.c", older):
        os.utime(path, (old, old))
    with cache.scratch_folder(folder) as running:
        (running / "loop.c").write_text("int y;")
        for path in (running / "loop.c", running):  # an hour-long compile: held, not young
            os.utime(path, (old, old))
        assert cache.scratch_in_use(running)
        assert not cache.scratch_in_use(dead) and not cache.scratch_in_use(older)
        assert main(["cache", "clear"]) == 0
        assert running.is_dir() and (running / "loop.c").read_text() == "int y;"
        assert not dead.exists() and not older.exists()
    assert not running.exists()
    capsys.readouterr()


def test_a_young_scratch_folder_is_taken_as_in_use(tmp_path):
    """Between making its folder and locking it, a compile holds no lock yet."""
    young = tmp_path / "tmpyoung"
    young.mkdir()
    now = os.path.getmtime(young)
    assert cache.scratch_in_use(young, now=now + 1)
    assert not cache.scratch_in_use(young, now=now + cache.SCRATCH_GRACE + 1)


# --------------------------------------------------------------------------------------
# where $INS_ERRORS_CACHE points


def _cache_folder(capsys) -> str:
    import json

    assert main(["cache", "info", "--json"]) == 0
    return json.loads(capsys.readouterr().out)["folder"]


def test_a_tilde_in_the_cache_variable_is_the_home_folder(tmp_path, monkeypatch, capsys):
    """``INS_ERRORS_CACHE='~/inscache'`` (quoted in a shell, or set by a CI file) made a
    folder named ``~`` in the working folder."""
    home, work = tmp_path / "home", tmp_path / "work"
    home.mkdir()
    work.mkdir()
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.setenv("INS_ERRORS_CACHE", "~/inscache")
    monkeypatch.chdir(work)
    assert _cache_folder(capsys) == str(home / "inscache")
    assert cache.store_directory("models") == home / "inscache" / "models"
    monkeypatch.setenv("CI_CACHE", str(tmp_path / "ci"))
    monkeypatch.setenv("INS_ERRORS_CACHE", "$CI_CACHE/ins")
    assert _cache_folder(capsys) == str(tmp_path / "ci" / "ins")
    assert not (work / "~").exists() and not (work / "$CI_CACHE").exists()


def test_a_relative_cache_variable_is_fixed_where_the_command_starts(
        tmp_path, monkeypatch, capsys):
    first, second = tmp_path / "first", tmp_path / "second"
    first.mkdir()
    second.mkdir()
    monkeypatch.setenv("INS_ERRORS_CACHE", "inscache")
    monkeypatch.chdir(first)
    assert _cache_folder(capsys) == str(first / "inscache")
    monkeypatch.chdir(second)  # the process moves on: the same cache, not a second one
    assert cache.directory() == first / "inscache"
    assert os.environ["INS_ERRORS_CACHE"] == str(first / "inscache")  # workers inherit it
