"""``check_file`` tries writing instead of reading permission bits.

For root every permission bit says yes, so ``--plot /proc/x.png`` passed the check and
failed only after the whole computation. The check now makes (and removes) a scratch
file where the writer will make its own, and opens an existing target for appending
without writing; nothing it tries is left behind.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from ins_errors.cli import main
from ins_errors.output import OutputError, check_file, write_text

PROC = Path("/proc")


def _computing_fails(monkeypatch):
    from ins_errors.numeric import compare

    def refused(*args, **kwargs):
        raise AssertionError("computed before the output was checked")

    monkeypatch.setattr(compare, "compare", refused)


@pytest.mark.skipif(not (PROC / "self").exists(), reason="no /proc file system")
@pytest.mark.parametrize("option, path, message", [
    ("--plot", "/proc/x.png", "folder '/proc' takes no new files"),
    ("--plot", "/proc/sub/x.png", "no folder can be made in '/proc'"),
    ("--markdown", "/proc/version", "cannot write '/proc/version'"),
])
def test_a_place_that_takes_no_files_is_refused_before_computing(capsys, monkeypatch,
                                                                 option, path, message):
    """(Whatever the permission bits say: the test machine's root was let through.)"""
    _computing_fails(monkeypatch)
    argv = ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--hours", "0.1",
            option, path]
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, err
    assert err.startswith("ins-errors: error: cannot write") and message in err, err


def test_an_existing_file_is_left_as_it_was(tmp_path):
    target = tmp_path / "kept.md"
    target.write_bytes(b"old contents\n")
    os.utime(target, ns=(1_000_000_000, 2_000_000_000))
    before = target.stat()
    assert check_file(target) == target
    after = target.stat()
    assert target.read_bytes() == b"old contents\n"
    assert after.st_mtime_ns == before.st_mtime_ns == 2_000_000_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.md"]


def test_a_new_file_is_tried_and_not_left_behind(tmp_path):
    target = tmp_path / "new.png"
    assert check_file(target) == target
    assert not target.exists() and list(tmp_path.iterdir()) == []


def test_missing_folders_are_tried_not_made_and_made_by_the_writer(tmp_path):
    target = tmp_path / "a" / "b" / "x.md"
    check_file(target)
    assert list(tmp_path.iterdir()) == []  # the check makes nothing
    write_text(target, "written\n")  # the writer makes the folders, as before
    assert target.read_text() == "written\n"


def test_a_plot_into_missing_folders_is_still_written(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    argv = ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--hours", "0.1",
            "--plot", "deep/er/x.png"]
    assert main(argv) == 0
    assert (tmp_path / "deep" / "er" / "x.png").stat().st_size > 0
    assert sorted(p.name for p in (tmp_path / "deep" / "er").iterdir()) == ["x.png"]


def test_a_folder_in_the_way_of_the_name_is_still_said(tmp_path):
    (tmp_path / "dir.png").mkdir()
    with pytest.raises(OutputError, match="it is a folder"):
        check_file(tmp_path / "dir.png")


def test_a_name_too_long_for_the_writers_scratch_file_says_so(tmp_path):
    """A 250-character name the file system takes is written through a longer scratch
    name it does not: the refusal blamed the folder ("takes no new files")."""
    name = "a" * (255 - len(".png")) + ".png"
    target = tmp_path / name
    with pytest.raises(OutputError, match="its name is too long") as info:
        check_file(target)
    assert "takes no new files" not in str(info.value)
    assert not list(tmp_path.iterdir())
