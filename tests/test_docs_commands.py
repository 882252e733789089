"""Every shell command shown in the README, docs and the examples' pages runs, as written.

The commands are extracted from the ```sh blocks of README.md, docs/*.md,
examples/README.md and every examples/**/README.md (pages added later are picked up), so
the pages cannot drift from the program. A command may end with a comment saying
``exit N``; otherwise it must exit 0. It must print something, except a command shown
with exit 2 (bad input), which must print one error line on standard error and nothing on
standard output.

How each kind of line runs, after the set-up the README describes (``make test`` made
``.venv`` and installed the package: the suite itself runs there):

* ``make TARGET``: the set-up itself; the Makefile must have the target.
* ``ins-errors ...``: through the installed entry point's function
  (:func:`ins_errors.cli.main`) in a fresh scratch folder holding a link to examples/,
  without a pre-made ``out/`` (commands create the folders they write into).
  ``ins-errors cache ...`` runs against a scratch compile cache, never the user's.
  A command that reads what an earlier line of its block wrote (a word equal to that
  line's ``--store`` or ``--out`` path, e.g. the shard stores a merge joins) runs after
  that line, in the same scratch folder; the earlier line then runs only there.
  The report folder of an ``ins-errors run examples/NAME.toml --out DIR`` line is handed
  to tests/test_scenarios.py (fixture ``example_reports``), which checks its contents
  instead of running the example a second time. What a command writes goes under
  ``out/`` (as examples/README.md says; ``cache/`` for the cache commands): a file it
  leaves beside ``out/`` would be left untracked in a reader's checkout.
* a block with any other line (``source .venv/bin/activate``...): run whole by bash from
  the repository root, as a reader would paste it.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
from pathlib import Path

import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")),
         ROOT / "examples" / "README.md", *sorted((ROOT / "examples").glob("*/**/README.md"))]
BLOCK = re.compile(r"^```(?:sh|bash|shell|console)\n(.*?)^```", re.M | re.S)
EXIT = re.compile(r"\bexit (?:status )?(\d+)\b")


def _lines(block: str) -> list[tuple[str, int]]:
    """(command, expected status) of each command of a block, continuations joined."""
    joined = re.sub(r"\\\n\s*", " ", block)
    out = []
    for raw in joined.splitlines():
        line = raw.strip()
        if line.startswith("$ "):
            line = line[2:]
        if not line or line.startswith("#"):
            continue
        command, _, comment = line.partition(" #")
        status = EXIT.search(comment)
        out.append((command.strip(), int(status.group(1)) if status else 0))
    return out


def _blocks() -> list[tuple[str, list[tuple[str, int]]]]:
    found = []
    for page in PAGES:
        for block in BLOCK.findall(page.read_text(encoding="utf-8")):
            lines = _lines(block)
            if lines:
                found.append((page.relative_to(ROOT).as_posix(), lines))
    return found


WRITES = ("--store", "--out")
"""Options whose value is a path the command writes."""


def _written(words: list[str]) -> set[str]:
    return {words[k + 1] for k, word in enumerate(words[:-1]) if word in WRITES}


def _chains(lines: list[tuple[str, int]]) -> list[tuple[tuple[str, int], ...]]:
    """The commands of a block, each with the earlier lines it reads from in front (in
    block order); a line another one reads from is not listed on its own."""
    words = [shlex.split(command) for command, _ in lines]
    needs: list[list[int]] = []
    for k, own in enumerate(words):
        reads = set(own) - _written(own)
        direct = [j for j in range(k) if _written(words[j]) & reads]
        closure = set(direct)
        for j in direct:
            closure.update(needs[j])
        needs.append(sorted(closure))
    used = {j for need in needs for j in need}
    return [tuple(lines[j] for j in [*need, k]) for k, need in enumerate(needs)
            if k not in used]


BLOCKS = _blocks()
# one run per distinct command (with the lines it reads from): the same words spaced
# differently (a README line continued with a backslash) are the same command
INS_ERRORS = sorted({tuple((tuple(shlex.split(c)), s) for c, s in chain): chain
                     for _, lines in BLOCKS
                     if all(c.split()[0] in ("ins-errors", "make") for c, _ in lines)
                     for chain in _chains([line for line in lines
                                           if line[0].split()[0] == "ins-errors"])
                     }.values())
MAKE = sorted({command for _, lines in BLOCKS for command, _ in lines
               if command.split()[0] == "make"})
SHELL = [(page, lines) for page, lines in BLOCKS
         if any(c.split()[0] not in ("ins-errors", "make") for c, _ in lines)]


def test_the_pages_have_commands():
    assert len(INS_ERRORS) >= 20
    merges = [chain for chain in INS_ERRORS if "--merge" in chain[-1][0]]
    assert merges and all(len(chain) > 1 for chain in merges)  # after the shards
    assert "make derive" in MAKE and "make test" in MAKE
    assert SHELL, "the README says how to put ins-errors on the PATH"


@pytest.mark.parametrize("command", MAKE)
def test_make_targets_exist(command):
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    for target in command.split()[1:]:
        assert re.search(rf"^{re.escape(target)}:", makefile, re.M), target


@pytest.mark.parametrize("chain", INS_ERRORS, ids=[c[-1][0][:60] for c in INS_ERRORS])
def test_documented_command(chain, tmp_path, monkeypatch, capsys, example_reports):
    os.symlink(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    for command, status in chain:
        _run_documented(command, status, tmp_path, monkeypatch, capsys, example_reports)
    stray = sorted(p.name for p in tmp_path.iterdir() if p.name not in OURS)
    assert not stray, f"{chain[-1][0]}: wrote {stray} outside out/"


OURS = ("examples", "out", "cache")
"""What the scratch folder of a documented command may hold afterwards: the link to the
examples, the outputs and the scratch cache of ``ins-errors cache``."""


def test_the_examples_run_comments_are_documented_commands_writing_under_out():
    """The ``# Run:`` line of an example file is a command a page shows (so it runs
    above, as written) that writes under out/: ``ins-errors run FILE`` alone wrote
    ``report_<name>/`` beside the checkout's files."""
    shown = {tuple(w for w in shlex.split(c) if w != "--no-progress")
             for _, lines in BLOCKS for c, _ in lines}
    comments = []
    for path in sorted((ROOT / "examples").rglob("*")):
        if path.suffix not in (".toml", ".py", ".csv") or "_generated" in str(path):
            continue
        for command in re.findall(r"^# Run: (.*)$", path.read_text(encoding="utf-8"), re.M):
            words = shlex.split(command)
            comments.append(command)
            written = _written(words)
            assert written and all(w.startswith("out/") for w in written), command
            assert tuple(words) in shown, f"{path.name}: {command} is on no page"
    assert len(comments) >= 4


def _run_documented(command, status, tmp_path, monkeypatch, capsys, example_reports):
    argv = shlex.split(command)[1:]
    if argv[:1] == ["cache"]:
        monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    try:
        result = main(argv)
    except SystemExit as stop:  # --help, --version
        result = stop.code
    captured = capsys.readouterr()
    assert result == status, f"{command}: {captured.err}"
    if status == 2:  # bad input: one line on standard error, nothing else
        assert captured.err.startswith("ins-errors: error: ") and captured.err.count("\n") == 1
        assert not captured.out
    else:
        assert captured.out.strip(), "the command printed nothing"
    if argv[0] == "run" and argv[1].startswith("examples/") and "--out" in argv:
        example_reports[Path(argv[1]).name] = tmp_path / argv[argv.index("--out") + 1]


@pytest.mark.parametrize("page, lines", SHELL, ids=[p for p, _ in SHELL])
def test_documented_shell_block(page, lines):
    if not (ROOT / ".venv" / "bin" / "activate").exists():
        pytest.skip("no .venv: the suite is not running after the README's set-up")
    script = "set -e\n" + "\n".join(command for command, _ in lines)
    result = subprocess.run(["bash", "-c", script], cwd=ROOT, capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, f"{page}: {result.stderr[-2000:]}"
    assert result.stdout.strip()
