"""A file named in an error is named as the user gave it (its folder included), like the
other commands' errors do: ``/dev/null`` read as "null: ..." looked like a file called
null, and "empty.txt: ..." did not say which of several."""

from __future__ import annotations

import os

import pytest

from ins_errors.cli import main


@pytest.mark.skipif(not os.path.exists(os.devnull) or os.devnull != "/dev/null",
                    reason="no /dev/null")
def test_an_empty_hand_file_is_named_by_its_path(tmp_path, monkeypatch, capsys):
    assert main(["check", "orthodromic", "/dev/null"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: /dev/null: no equations to check"), err
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "empty.txt").write_text("# nothing but a comment\n")
    assert main(["check", "orthodromic", "sub/empty.txt"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: sub/empty.txt: no equations to check"), err


def test_a_bad_mapping_file_is_named_by_its_path(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "map.txt").write_text("dot(delta_v_N) = 0\n")
    (tmp_path / "hand.txt").write_text("dot(delta_v_N) = 0\n")
    assert main(["check", "orthodromic", "hand.txt", "--mapping", "sub/map.txt"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("ins-errors: error: sub/map.txt:"), err
    assert err.count("\n") == 1
