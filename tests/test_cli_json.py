"""Every subcommand a script may drive offers --json, and its output parses."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent

COMMANDS = {
    "models": ["models", "orthodromic", "--json"],
    "compare": ["compare", "orthodromic", "--source", "gyro_drift_y=0.01deg/h", "--hours", "1",
                "--no-refined", "--json", "--no-progress"],
    "budget": ["budget", "orthodromic", "--json"],
    "check": ["check", "orthodromic", str(ROOT / "examples/manual_000/equations.txt"), "--json"],
    "study": ["study", "nonsphericity", "--hours", "1", "--scenario", "static", "--json"],
    "propagation": ["propagation", "--hours", "1", "--json"],
    "cache": ["cache", "info", "--json"],
}


@pytest.mark.parametrize("name", COMMANDS)
def test_json_output_parses(name, capsys):
    status = main(COMMANDS[name])
    assert status in (0, 1)  # check exits 1: the manual's printed equations have mistakes
    data = json.loads(capsys.readouterr().out)
    assert data


def test_every_subcommand_has_help(capsys):
    from ins_errors.cli import build_parser

    parser = build_parser()
    commands = parser._subparsers._group_actions[0].choices
    assert set(COMMANDS) | {"run"} <= set(commands)
    for name, sub in commands.items():
        text = sub.format_help()
        assert len(sub.description or "") > 40, name
        assert "--json" in text, name
