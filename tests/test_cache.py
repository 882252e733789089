"""The compiled-loop cache: size limit with least-recently-used eviction, per-checkout
clearing, and the ``ins-errors cache`` commands of docs/cache.md."""

from __future__ import annotations

import os
import re
import shlex
from pathlib import Path

import casadi as ca
import pytest

from ins_errors.cli import main
from ins_errors.numeric import cache
from ins_errors.numeric import integrators as integ

CACHE_PAGE = (Path(__file__).resolve().parent.parent / "docs" / "cache.md").read_text(
    encoding="utf-8")


def _library(folder: Path, name: str, size: int, age: float) -> Path:
    path = folder / f"loop_{name}.so"
    path.write_bytes(b"\0" * size)
    t = 1_700_000_000 - age
    os.utime(path, (t, t))
    return path


def test_eviction_removes_the_least_recently_used_first(tmp_path):
    old = _library(tmp_path, "old", 400, age=300)
    middle = _library(tmp_path, "middle", 400, age=200)
    new = _library(tmp_path, "new", 400, age=100)
    removed = cache.evict(tmp_path, limit=900, keep=old)  # 'old' is the one just made
    assert removed == [middle]
    assert old.exists() and new.exists() and not middle.exists()
    assert cache.evict(tmp_path, limit=799) == [old]


def test_compiling_beyond_the_limit_keeps_the_newest_loop(tmp_path, monkeypatch):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    monkeypatch.setenv("INS_ERRORS_CACHE_LIMIT", "0.000001")  # 1 byte: room for one
    x = ca.SX.sym("x")
    first = integ.compile_library([ca.Function("probe_a", [x], [x + 1])])
    if first is None:
        pytest.skip("no C compiler")
    second = integ.compile_library([ca.Function("probe_b", [x], [x * 2])])
    assert sorted(tmp_path.glob(cache.PATTERN)) == [second]
    assert not first.exists()


def test_clear_checkout_keeps_loops_another_checkout_uses(tmp_path):
    mine_only = _library(tmp_path, "mine", 10, age=30)
    shared = _library(tmp_path, "shared", 10, age=20)
    theirs = _library(tmp_path, "theirs", 10, age=10)
    me = tmp_path / "owners" / cache.checkout_id()
    other = tmp_path / "owners" / "0123456789abcdef"
    for folder, libraries in ((me, (mine_only, shared)), (other, (shared, theirs))):
        folder.mkdir(parents=True)
        for library in libraries:
            (folder / library.name).touch()
    assert cache.clear(tmp_path, checkout_only=True) == (1, 10)
    assert not mine_only.exists() and shared.exists() and theirs.exists()
    assert not me.exists()
    assert cache.clear(tmp_path) == (2, 20)
    assert not list(tmp_path.glob(cache.PATTERN))


def test_documented_cache_commands_run(tmp_path, monkeypatch, capsys):
    section = CACHE_PAGE.split("# Compiled loops and their cache", 1)[1].split("\n## ", 1)[0]
    lines = re.findall(r"^ins-errors (cache[^#\n]*?)\s*(?:#.*)?$", section, re.M)
    assert len(lines) == 3
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    _library(tmp_path, "abc", 1000, age=5)
    for line in lines:
        assert main(shlex.split(line)) == 0
    out = capsys.readouterr().out
    assert "libraries: 1, 0.0 MB" in out and "removed 1 compiled library (0.0 MB)" in out
    assert not list(tmp_path.glob(cache.PATTERN))


def test_a_bad_size_limit_is_one_line(monkeypatch, capsys):
    monkeypatch.setenv("INS_ERRORS_CACHE_LIMIT", "lots")
    assert main(["cache", "info"]) == 2
    assert "INS_ERRORS_CACHE_LIMIT must be a size in MB" in capsys.readouterr().err


def test_a_cache_folder_the_user_named_is_never_silently_replaced(tmp_path, monkeypatch):
    """$INS_ERRORS_CACHE naming a file is refused in one line (as `cache info` refuses
    it); the default folder, when it cannot be written, falls back to a temporary one
    (tests/test_cache_read_only.py: said once, when a loop is compiled there)."""
    from ins_errors.errors import InsErrorsError

    not_a_folder = tmp_path / "cachefile"
    not_a_folder.write_text("x")
    monkeypatch.setenv("INS_ERRORS_CACHE", str(not_a_folder))
    with pytest.raises(InsErrorsError, match=r"INS_ERRORS_CACHE=.*cachefile.* cannot be the "
                                             r"cache folder \(it is a file\): point it"):
        integ._writable(cache.directory())
    monkeypatch.delenv("INS_ERRORS_CACHE")
    used = integ._writable(not_a_folder / "casadi")  # said when a loop is compiled there
    assert used.is_dir() and used != not_a_folder / "casadi"
