"""``$INS_ERRORS_CACHE`` pointed at a folder laid out as the user cache folder.

The user cache keeps its compiled loops in ``~/.cache/ins-errors/casadi/``; with the
variable set, the loops were looked for in the folder itself. Pointed at
``~/.cache/ins-errors`` (long-flight probe), the 173 MB of loops in its ``casadi/`` were
not shown by ``cache info``, not bounded by the size limit and not removed by ``cache
clear`` ("total: 0 files"), and every loop was compiled again beside them. A folder with
a ``casadi/`` subfolder now keeps its loops there, as the user cache does; loops an
earlier run left in the folder itself are shown and cleared as unused.
"""

from __future__ import annotations

import json

import pytest

from ins_errors.cli import main
from ins_errors.numeric import cache


def _json(argv, capsys):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.fixture
def user_layout(tmp_path, monkeypatch):
    """A copy of a user cache folder (loops in casadi/, other stores beside it), named by
    $INS_ERRORS_CACHE."""
    root = tmp_path / "ins-errors"
    loops = root / "casadi"
    (loops / "notes").mkdir(parents=True)
    (loops / "loop_a.so").write_bytes(b"\0" * 4000)
    (loops / "loop_b.so").write_bytes(b"\0" * 6000)
    (loops / "notes" / "n1").write_text("note")
    (root / "motions").mkdir()
    (root / "motions" / "m.npz").write_bytes(b"m" * 100)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(root))
    return root


def test_the_loops_of_a_user_cache_folder_are_shown_bounded_and_cleared(user_layout,
                                                                          capsys):
    info = _json(["cache", "info"], capsys)
    assert info["folder"] == str(user_layout / "casadi")
    assert (info["libraries"], info["bytes"]) == (2, 10_000)
    rows = {row["name"]: row for row in info["stores"]}
    assert (rows["notes"]["folder"], rows["notes"]["files"]) == (
        str(user_layout / "casadi" / "notes"), 1)
    assert rows["motions"]["files"] == 1
    assert "unused" not in rows
    # the size limit applies to them: the least recently used goes first
    assert cache.evict(cache.directory(), 7000) == [user_layout / "casadi" / "loop_a.so"]
    cleared = _json(["cache", "clear"], capsys)
    assert (cleared["removed"], cleared["bytes_freed"]) == (1, 6000)
    assert not list((user_layout / "casadi").glob("loop_*.so"))
    assert not (user_layout / "casadi" / "notes").exists()


def test_loops_left_in_the_folder_itself_are_shown_and_cleared_as_unused(user_layout,
                                                                          capsys):
    (user_layout / "loop_old.so").write_bytes(b"\0" * 2500)
    (user_layout / "notes").mkdir()
    (user_layout / "notes" / "n").write_text("old note")
    (user_layout / "mine.txt").write_text("not the cache's")
    rows = {r["name"]: r for r in _json(["cache", "info"], capsys)["stores"]}
    assert (rows["unused"]["folder"], rows["unused"]["files"]) == (str(user_layout), 2)
    assert main(["cache", "clear"]) == 0
    assert "of unused from" in capsys.readouterr().out
    assert sorted(p.name for p in user_layout.iterdir()) == ["casadi", "mine.txt",
                                                             "motions"]
    assert not list((user_layout / "motions").iterdir())


def test_a_folder_without_casadi_keeps_its_loops_in_itself(tmp_path, monkeypatch, capsys):
    root = tmp_path / "flat"
    root.mkdir()
    (root / "loop_a.so").write_bytes(b"\0" * 1000)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(root))
    info = _json(["cache", "info"], capsys)
    assert (info["folder"], info["libraries"]) == (str(root), 1)
    assert "unused" not in {r["name"] for r in info["stores"]}
