"""The command-line parser is built once per process and reused by every ``main`` call:
a parse must not depend on what was parsed before (defaults, ``set_defaults`` of the
subcommands, ``append`` options' default lists)."""

from __future__ import annotations

import pytest

from ins_errors import cli

ARGVS = [
    ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "-p", "a=1", "--hours", "2"],
    ["study", "coriolis", "--scenario", "static", "--hours", "1"],
    ["compare", "orthodromic"],
    ["budget", "spec.toml", "--parameter", "b=2", "--monte-carlo", "3"],
    ["check", "hand.txt", "--magnitude", "rad=1deg", "--magnitude", "m=1km"],
    ["check", "hand.txt"],
    ["budget", "spec.toml"],
    ["validity", "orthodromic", "--motion", "static"],
    ["validity", "orthodromic"],
    ["models"],
    [],
]


def _fresh(argv: list[str]) -> dict:
    return vars(cli.build_parser().parse_args(argv))


def test_reused_parser_parses_each_command_line_as_a_fresh_parser_does():
    shared = cli._shared_parser()
    assert cli._shared_parser() is shared
    expected = [_fresh(argv) for argv in ARGVS]
    # forwards, backwards, and each line twice in a row: no order leaks into a result
    for order in (range(len(ARGVS)), reversed(range(len(ARGVS))),
                  [i for i in range(len(ARGVS)) for _ in (0, 1)]):
        for i in order:
            assert vars(shared.parse_args(ARGVS[i])) == expected[i], ARGVS[i]


def test_append_options_start_empty_after_a_line_that_gave_them():
    shared = cli._shared_parser()
    first = shared.parse_args(["compare", "orthodromic", "-p", "a=1", "-p", "b=2"])
    assert first.parameter == ["a=1", "b=2"]
    assert shared.parse_args(["compare", "orthodromic"]).parameter == []
    assert shared.parse_args(["budget", "spec.toml"]).parameter == []
    # another command's defaults do not appear in this one's namespace
    assert not hasattr(shared.parse_args(["models"]), "parameter")


def test_version_is_the_installed_one(capsys):
    with pytest.raises(SystemExit) as stop:
        cli.main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"ins-errors {cli.version()}"
