"""``ins-errors cache info|clear`` see and empty every on-disk store, not only the
compiled loops: notes, model code, pint's units, study functions, flown motions,
propagations (each at the folder its own module writes to) and what interrupted or older
runs left beside the loops."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from ins_errors import model_lookup, units
from ins_errors.checker import motion_store, propagation_store
from ins_errors.cli import main
from ins_errors.numeric import cache
from ins_errors.studies import function_cache
from ins_errors.symbolic import variation_store

ROOT = Path(__file__).resolve().parent.parent

# store name -> (function giving the folder its module writes to, fabricated files)
STORES = {
    "notes": (lambda: cache.directory() / cache.NOTES, {"a1": 11, "b2": 7}),
    "models": (model_lookup.models_cache_directory,
               {"m-0123/__init__.py": 100, "m-0123/numeric.py": 250, "n-4567/x.py": 3}),
    "units": (units.units_cache_directory, {"d4.json": 40, "d4.pickle": 900}),
    "functions": (function_cache.cache_directory, {f"study-{'0' * 32}.json": 4500}),
    "motions": (motion_store.folder, {"orthodromic_ab.npz": 1200}),
    "transitions": (propagation_store.folder, {"t1.npy": 64, "t2.npy": 64, "t3.npy": 80}),
    "variations": (variation_store.folder, {f"orthodromic_{'0' * 32}.pickle": 6400}),
    "leftovers": (cache.directory, {"tmpk2j4/loop.c": 50, "tmpk2j4/loop.so": 70,
                                    "writer_ab12.key": 30, "verified-generated.json": 20}),
}


@pytest.fixture
def filled(tmp_path, monkeypatch):
    """A scratch cache with two compiled libraries (one used by this checkout) and the
    fabricated files of :data:`STORES`."""
    root = tmp_path / "cache"
    monkeypatch.setenv("INS_ERRORS_CACHE", str(root))
    root.mkdir()
    for name, size in (("mine", 1000), ("theirs", 3000)):
        (root / f"loop_{name}.so").write_bytes(b"\0" * size)
    marker = root / "owners" / cache.checkout_id() / "loop_mine.so"
    marker.parent.mkdir(parents=True)
    marker.touch()
    for folder, files in STORES.values():
        for relative, size in files.items():
            path = folder() / relative
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(b"x" * size)
    (root / "keep.txt").write_text("not the cache's")  # no store's: never counted nor removed
    interrupted = root / "tmpk2j4"  # a compile interrupted an hour ago (a younger folder
    hour_ago = time.time() - 3600  # may be one that is only starting: left alone)
    os.utime(interrupted, (hour_ago, hour_ago))
    return root


def _json(argv, capsys):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_info_lists_every_store_with_its_files_and_size(filled, capsys):
    info = _json(["cache", "info"], capsys)
    assert (info["libraries"], info["bytes"]) == (2, 4000)          # the keys kept as before
    assert (info["checkout_libraries"], info["checkout_bytes"]) == (1, 1000)
    rows = {row["name"]: row for row in info["stores"]}
    assert list(rows) == ["loops", *STORES]
    assert (rows["loops"]["files"], rows["loops"]["bytes"]) == (2, 4000)
    assert rows["loops"]["limit"] == {"bytes": cache.limit_bytes()}
    for name, (folder, files) in STORES.items():
        assert rows[name]["folder"] == str(folder())
        assert (rows[name]["files"], rows[name]["bytes"]) == (len(files), sum(files.values()))
    assert rows["motions"]["limit"] == {"files": motion_store.KEEP}
    assert rows["models"]["limit"] == {"versions_per_name": model_lookup.KEEP_VERSIONS}
    every = 2 + sum(len(files) for _, files in STORES.values())
    assert info["total_files"] == every
    assert info["total_bytes"] == 4000 + sum(sum(f.values()) for _, f in STORES.values())

    assert main(["cache", "info"]) == 0
    text = capsys.readouterr().out
    lines = {line.split()[0]: line.split() for line in text.splitlines()
             if line.startswith("  ")}
    for name, (folder, files) in STORES.items():
        assert lines[name][1:4] == [str(folder()), str(len(files)), "files"]
    assert f"total: {every} files" in text


def test_clear_empties_every_store_and_checkout_only_this_checkouts_loops(filled, capsys):
    cleared = _json(["cache", "clear", "--checkout"], capsys)
    assert (cleared["removed"], cleared["bytes_freed"]) == (1, 1000)
    assert [row["name"] for row in cleared["stores"]] == ["loops"]
    assert (filled / "loop_theirs.so").exists()
    kept = {row["name"]: row for row in _json(["cache", "info"], capsys)["stores"]}
    for name, (_, files) in STORES.items():  # nothing else can tell who used an entry
        assert (kept[name]["files"], kept[name]["bytes"]) == (len(files), sum(files.values()))

    cleared = _json(["cache", "clear"], capsys)
    assert (cleared["removed"], cleared["bytes_freed"]) == (1, 3000)
    rows = {row["name"]: row for row in cleared["stores"]}
    for name, (folder, files) in STORES.items():
        assert (rows[name]["removed"], rows[name]["bytes_freed"]) == (
            len(files), sum(files.values()))
        if name != "leftovers":
            assert cache.usage(folder()) == (0, 0)
    assert not list(filled.glob(cache.PATTERN))
    assert sorted(p.name for p in filled.iterdir() if not p.is_dir()) == ["keep.txt"]
    assert not (filled / "tmpk2j4").exists()
    info = _json(["cache", "info"], capsys)
    assert info["total_files"] == 0 and info["total_bytes"] == 0


def test_missing_store_folders_are_empty_stores(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "never-made"))
    info = _json(["cache", "info"], capsys)
    assert [(r["files"], r["bytes"]) for r in info["stores"]] == [(0, 0)] * (1 + len(STORES))
    cleared = _json(["cache", "clear"], capsys)
    assert all(r["removed"] == 0 for r in cleared["stores"])
    assert not (tmp_path / "never-made").exists()


def test_a_cache_folder_that_is_a_file_is_one_line(tmp_path, monkeypatch, capsys):
    (tmp_path / "file").write_text("not a folder")
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "file"))
    for action in ("info", "clear"):
        assert main(["cache", action]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "is not a folder" in err, err


def test_a_cache_folder_that_cannot_be_made_is_refused_as_by_the_other_commands(
        tmp_path, monkeypatch, capsys):
    """A $INS_ERRORS_CACHE that is missing and cannot be made (under a file here; under
    /proc likewise) was shown as empty stores, exit 0, while a command that writes
    there refuses it: info and clear give that command's line, exit 2."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric import integrators as integ

    (tmp_path / "file").write_text("not a folder")
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "file" / "cache"))
    with pytest.raises(InsErrorsError) as refused:  # what a run that compiles a loop says
        integ._writable(cache.directory())
    for action in ("info", "clear"):
        assert main(["cache", action]) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and captured.err == f"ins-errors: error: {refused.value}\n"


def test_a_store_that_cannot_be_emptied_is_one_line(filled, monkeypatch, capsys):
    def refuse(folder):
        raise PermissionError(13, "Permission denied", str(folder / "x"))

    monkeypatch.setattr(cache, "empty", refuse)
    assert main(["cache", "clear"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot clear the cache folder" in err
    assert "Permission denied" in err


def test_after_clearing_the_stores_are_rebuilt_and_results_unchanged(tmp_path, monkeypatch,
                                                                    capsys):
    """Real use: a model file's comparison, each in a fresh process, fills loops, notes,
    model code and units; after ``cache clear`` the same command gives the same numbers
    and fills them again. (``cache info`` and ``clear`` only read and delete files: they
    run in this process, against the same folder.)"""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    compare = [sys.executable, "-m", "ins_errors.cli", "compare",
               str(ROOT / "examples/own_model/schuler_loop.py"),
               "--source", "accel_bias=100ug", "--hours", "1", "--step", "60s"]

    def run_compare():
        done = subprocess.run(compare, capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr
        return done.stdout

    def filled_stores():
        capsys.readouterr()
        assert main(["cache", "info", "--json"]) == 0
        info = json.loads(capsys.readouterr().out)
        return {r["name"] for r in info["stores"] if r["files"]}

    first = run_compare()
    assert {"notes", "models", "units"} <= filled_stores()
    assert main(["cache", "clear"]) == 0
    assert filled_stores() == set()
    assert run_compare() == first
    assert {"notes", "models", "units"} <= filled_stores()


def test_documented_table_states_the_bounds_the_code_keeps():
    section = (ROOT / "docs" / "cache.md").read_text(encoding="utf-8").split(
        "# Compiled loops and their cache", 1)[1].split("\n## ", 1)[0]
    rows = {line.split("|")[1].strip(): line.split("|")[4] for line in section.splitlines()
            if line.startswith("| ") and not line.startswith("| store")}
    assert list(rows) == ["loops", *STORES]
    assert f"default {cache.DEFAULT_LIMIT_MB:g}" in rows["loops"]
    assert f"{cache.NOTE_LIMIT} notes" in rows["notes"]
    assert f"{model_lookup.KEEP_VERSIONS} newest" in rows["models"]
    assert f"the {function_cache.KEEP_VERSIONS} most" in rows["functions"]
    assert f"the {motion_store.KEEP} most" in rows["motions"]
    assert (f"at most {propagation_store.KEEP}" in rows["transitions"]
            and f"down to {propagation_store.kept_after_prune()}" in rows["transitions"])
    assert f"the {variation_store.KEEP} most" in rows["variations"]
    assert "none" in rows["leftovers"]



def test_the_transitions_store_stays_within_its_bound_in_one_process(tmp_path, monkeypatch):
    """`cache info` showed 4107 stored propagations against the bound of 4096: the oldest
    were dropped by a process's first store only, and a matrix check stores several.
    Now no store leaves more than KEEP files, a prune keeps the most recently used (a
    read counts as a use), and the folder is listed once per KEEP/4 stores, not at each."""
    import numpy as np

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    monkeypatch.setattr(propagation_store, "KEEP", 8)
    monkeypatch.setattr(propagation_store, "_counted", [], raising=False)  # a new process
    target = propagation_store.folder()
    listings = []
    real_prune = propagation_store.prune

    def counted_prune(*args, **kwargs):
        listings.append(1)
        return real_prune(*args, **kwargs)

    monkeypatch.setattr(propagation_store, "prune", counted_prune)
    start = time.time() - 1000
    for k in range(30):
        propagation_store.store(f"p{k:02d}", (np.full((2, 2), float(k)),))
        os.utime(target / f"p{k:02d}.npy", (start + k, start + k))  # stored in turn
        assert len(list(target.glob("*.npy"))) <= 8, k
    assert {f"p{k:02d}" for k in range(26, 30)} <= {p.stem for p in target.glob("*.npy")}
    assert len(listings) <= 1 + 30 // 2  # the first store's, then one per 2 (KEEP/4)

    for old in target.glob("*.npy"):
        old.unlink()
    monkeypatch.setattr(propagation_store, "_counted", [], raising=False)  # a new process
    for k in range(8):
        propagation_store.store(f"r{k}", (np.eye(2),))
        os.utime(target / f"r{k}.npy", (start + k, start + k))
    assert propagation_store.load("r0") is not None  # used again: now the most recent
    propagation_store.store("r8", (np.eye(2),))  # nine: past the bound, down to six
    assert sorted(p.stem for p in target.glob("*.npy")) == ["r0", "r4", "r5", "r6", "r7",
                                                            "r8"]
