"""The cache's settings and a cache folder that cannot be written (docs/cache.md).

A bad ``$INS_ERRORS_CACHE_LIMIT`` is refused before any work whether the cache holds the
loops a command needs or not; a read-only cache (a shared cache mounted read-only on a
cluster) lends what it holds, and what it lacks is made in a private folder, said once.
"""

from __future__ import annotations

import os
import subprocess
import tempfile
import warnings
from pathlib import Path

import casadi as ca
import pytest

from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.numeric import cache
from ins_errors.numeric import integrators as integ

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"

COMPARE = ["compare", "orthodromic", "--source", "accel_bias_x=100ug", "--motion",
           "great-circle", "--hours", "1", "--step", "5s", "--no-progress", "--json"]


@pytest.fixture
def private_place(tmp_path, monkeypatch) -> Path:
    """This user's private folder below ``tmp_path`` (returned, not yet made), with this
    process's notices not yet given."""
    temporary = tmp_path / "tmp"
    temporary.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temporary))
    monkeypatch.setenv("TMPDIR", str(temporary))
    monkeypatch.setattr(cache, "_PRIVATE", None)
    monkeypatch.setattr(cache, "_LINKED", set())
    monkeypatch.setattr(cache, "_PRIVATE_FOR", {})
    monkeypatch.setattr(cache, "_PRIVATE_NOTICE_GIVEN", False)
    monkeypatch.delenv(cache.PRIVATE_NOTICE_VARIABLE, raising=False)
    return temporary / f"ins-errors-{os.getuid()}"


@pytest.fixture
def read_only():
    """``read_only(folder)`` makes ``folder`` and everything in it read-only for this
    process: by permissions, or for root (whom permissions do not stop) by a read-only
    bind mount, as a shared cache is mounted; skips where neither can be done."""
    mounted: list[Path] = []
    locked: list[Path] = []

    def make(folder: Path) -> None:
        if os.geteuid() == 0:
            try:
                for options in (["--bind"], ["-o", "remount,bind,ro"]):
                    subprocess.run(["mount", *options, str(folder), str(folder)],
                                   check=True, capture_output=True)
                    if options == ["--bind"]:
                        mounted.append(folder)
            except (OSError, subprocess.CalledProcessError):
                pytest.skip("no read-only folder can be made here (root without mount)")
        else:
            for path in sorted([folder, *(p for p in folder.rglob("*") if p.is_dir())],
                               reverse=True):
                path.chmod(0o555)
                locked.append(path)
        if os.access(folder, os.W_OK):
            pytest.skip("no read-only folder can be made here")

    yield make
    for folder in mounted:
        subprocess.run(["umount", str(folder)], check=False, capture_output=True)
    for path in locked:
        path.chmod(0o755)


# --------------------------------------------------------------------------------------
# INS_ERRORS_CACHE_LIMIT
# --------------------------------------------------------------------------------------
def test_a_bad_size_limit_is_refused_before_any_work_with_a_warm_or_a_cold_cache(
        tmp_path, monkeypatch, capsys):
    """Was: exit 0 and silence when the loops were cached, exit 2 after compiling them
    when they were not."""
    assert main(COMPARE) == 0  # the session's cache now holds the loops: warm
    capsys.readouterr()
    warm = os.environ.get("INS_ERRORS_CACHE")
    cold = tmp_path / "cold"
    for value in ("abc", "-1", "nan", "inf"):
        monkeypatch.setenv("INS_ERRORS_CACHE_LIMIT", value)
        for folder in (warm, str(cold)):
            if folder is None:
                monkeypatch.delenv("INS_ERRORS_CACHE", raising=False)
            else:
                monkeypatch.setenv("INS_ERRORS_CACHE", folder)
            assert main(COMPARE) == 2, (value, folder)
            out, err = capsys.readouterr()
            assert out == ""
            assert err.startswith("ins-errors: error: INS_ERRORS_CACHE_LIMIT must be a size")
            assert repr(value) in err and err.count("\n") == 1
    assert not list(cold.rglob(cache.PATTERN))  # nothing was compiled


def test_the_library_checks_the_limit_also_for_a_cached_loop(tmp_path, monkeypatch):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    x = ca.SX.sym("x")
    functions = [ca.Function("probe_limit", [x], [3 * x])]
    if integ.compile_library(functions) is None:
        pytest.skip("no C compiler")
    monkeypatch.setenv("INS_ERRORS_CACHE_LIMIT", "-1")
    with pytest.raises(InsErrorsError, match="INS_ERRORS_CACHE_LIMIT must be a size"):
        integ.compile_library(functions)


# --------------------------------------------------------------------------------------
# a read-only cache
# --------------------------------------------------------------------------------------
def test_a_read_only_cache_lends_its_loops_and_new_ones_are_compiled_privately(
        tmp_path, monkeypatch, read_only, private_place):
    shared = tmp_path / "shared"
    monkeypatch.setenv("INS_ERRORS_CACHE", str(shared))
    x = ca.SX.sym("x")
    held = [ca.Function("probe_held", [x], [x + 1])]
    made = integ.compile_library(held)
    if made is None:
        pytest.skip("no C compiler")
    read_only(shared)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing is said when nothing is made
        found = integ.compile_library(held)
    assert found.parent == private_place and found.resolve() == made.resolve()
    assert float(ca.external("probe_held", str(found))(2.0)) == 3.0
    with pytest.warns(RuntimeWarning) as notices:
        new = integ.compile_library([ca.Function("probe_new", [x], [2 * x])])
    assert len(notices) == 1
    text = str(notices[0].message)
    assert f"{str(shared)!r} is read-only" in text and str(private_place) in text
    assert new.parent == private_place and not new.is_symlink()
    assert float(ca.external("probe_new", str(new))(2.0)) == 4.0
    assert sorted(p.name for p in shared.glob(cache.PATTERN)) == [made.name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once
        other = integ.compile_library([ca.Function("probe_other", [x], [x - 1])])
    assert other.parent == private_place
    # `cache info` of the private folder counts its own loops, not the links
    assert {e.path.name for e in cache.entries(private_place)} == {new.name, other.name}


def test_a_model_file_is_read_from_a_read_only_cache_and_derived_privately(
        tmp_path, monkeypatch, capsys, read_only, private_place):
    """Was: refused ('cannot be the cache folder (not writable)'), and with a writable
    loops folder, a model file was derived (seconds of SymPy) before failing to write."""
    from ins_errors.numeric.model import _file_model

    shared = tmp_path / "shared"
    monkeypatch.setenv("INS_ERRORS_CACHE", str(shared))
    held, new = tmp_path / "held.py", tmp_path / "new.py"
    held.write_text(SCHULER.read_text(encoding="utf-8"), encoding="utf-8")
    new.write_text(held.read_text(encoding="utf-8") + "\n# another version\n",
                   encoding="utf-8")

    def compare(path: Path) -> str:
        _file_model.cache_clear()  # look the model up again, as a new process does
        assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours",
                     "0.5", "--step", "10s", "--no-progress", "--json"]) == 0
        return capsys.readouterr().err

    assert "deriving" in compare(held)
    read_only(shared)
    assert compare(held) == ""  # found in the read-only cache: nothing made, nothing said
    err = compare(new)
    lines = err.splitlines()
    assert len(lines) == 2 and "deriving model file new.py" in err, err
    assert f"{str(shared)!r} is read-only" in err and str(private_place) in err
    assert [p.name.split("-")[0] for p in (private_place / "models").iterdir()] == [
        "schuler_loop"]
    assert compare(new) == ""  # found in the private folder
    assert len(list((shared / "models").iterdir())) == 1


def test_a_missing_cache_folder_that_cannot_be_made_is_refused(tmp_path, monkeypatch,
                                                               capsys, read_only):
    """A read-only folder is used, but a missing one under it is refused in one line."""
    parent = tmp_path / "parent"
    parent.mkdir()
    read_only(parent)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(parent / "cache"))
    with pytest.raises(InsErrorsError, match=r"cannot be the cache folder \(.+\): point"):
        integ._writable(cache.directory())
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "file"))
    (tmp_path / "file").write_text("x")
    assert main(["models"]) == 2
    err = capsys.readouterr().err
    assert "cannot be the cache folder (it is not a folder)" in err and err.count("\n") == 1


def test_the_private_folder_is_never_one_another_user_can_write(private_place):
    private_place.mkdir(mode=0o777)
    private_place.chmod(0o777)  # whatever the umask: anyone may write in it
    chosen = cache.private_directory()
    assert chosen != private_place and chosen.is_dir()
    assert not chosen.stat().st_mode & 0o077
    # such a folder of one process is removed when it ends (one was left by every run)
    import sys

    code = "from ins_errors.numeric import cache\nprint(cache.private_directory())"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, env=dict(os.environ))
    made = Path(done.stdout.strip())
    assert made.parent == private_place.parent and made != private_place
    assert not made.exists()


def test_a_default_cache_that_cannot_be_made_sends_loops_to_the_private_folder(
        tmp_path, monkeypatch, private_place):
    not_a_folder = tmp_path / "cachefile"
    not_a_folder.write_text("x")
    monkeypatch.delenv("INS_ERRORS_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(not_a_folder))
    x = ca.SX.sym("x")
    with pytest.warns(RuntimeWarning, match="cannot be written; compiled loops and other "
                                            "new work are kept in") as notices:
        made = integ.compile_library([ca.Function("probe_fallback", [x], [x + 2])])
    if made is None:
        pytest.skip("no C compiler")
    assert len(notices) == 1 and made.parent == private_place
