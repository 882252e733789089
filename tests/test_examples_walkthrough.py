"""Every command of examples/README.md runs and ends with the status the page states."""

from __future__ import annotations

import os
import re
import shlex
from pathlib import Path

import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "examples" / "README.md"
COMMAND = re.compile(r"^\$ ins-errors (.+?)(?:\s+#\s*exit (\d+))?$", re.M)
COMMANDS = COMMAND.findall(PAGE.read_text(encoding="utf-8"))


def test_the_page_has_commands():
    assert len(COMMANDS) >= 10


@pytest.mark.parametrize("line, status", COMMANDS, ids=[c[0][:50] for c in COMMANDS])
def test_walkthrough_command(line, status, tmp_path, monkeypatch, capsys):
    (tmp_path / "out").mkdir()
    os.symlink(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    assert main(shlex.split(line)) == int(status or 0), capsys.readouterr().err
    assert capsys.readouterr().out.strip()
