"""A hand file's input problems reach stderr, and a file nothing of which could be checked
gets no report that reads "(no discrepancies)".

The probe: ``check MODEL bad.txt`` whose one line does not parse exited 2 with nothing on
stderr, and stdout said "(no discrepancies)" before the input problem. Every exit
status 2 now comes with one line on stderr per problem, naming the file as given, the
place and what is wrong; a file in which no line could be checked is taken as a file
without equations (stderr only; ``--json`` still gets its object).
"""

from __future__ import annotations

import json
from pathlib import Path

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
GOOD = (ROOT / "tests/data/hand_correct_north_pointing.txt").read_text(encoding="utf-8")
BROKEN = "dot(x) = (a +* b"
UNKNOWN = "dot(delta_v_E) = zorg*delta_v_N"  # parses; a name the model does not have


def _errors(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("ins-errors: error: ")]


def test_a_file_whose_only_line_does_not_parse(tmp_path, capsys):
    bad = tmp_path / "bad.txt"
    bad.write_text(BROKEN + "\n", encoding="utf-8")
    assert main(["check", "north_pointing", str(bad)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # no report of a file nothing of which was checked
    [line] = _errors(captured.err)
    assert line.startswith(f"ins-errors: error: {bad}: line 1, column ")
    assert "cannot parse" in line and "(a +* b" in line


def test_every_problem_of_an_unchecked_file_is_one_line(tmp_path, capsys):
    """Two lines that cannot be checked (one does not parse, one names an unknown
    symbol): two lines on stderr, in file order, each with its line number."""
    bad = tmp_path / "two.txt"
    bad.write_text(f"# comment\n{BROKEN}\n{UNKNOWN}\n", encoding="utf-8")
    report = tmp_path / "report.md"
    assert main(["check", "north_pointing", str(bad), "--report", str(report)]) == 2
    captured = capsys.readouterr()
    assert "(no discrepancies)" not in captured.out and captured.out == ""
    lines = _errors(captured.err)
    assert [line.split(": ")[3].split(",")[0] for line in lines] == ["line 2", "line 3"]
    assert "zorg" in lines[1]
    assert not report.exists()  # as for a file without equations: no report written


def test_json_of_an_unchecked_file_lists_its_problems(tmp_path, capsys):
    bad = tmp_path / "bad.txt"
    bad.write_text(BROKEN + "\n", encoding="utf-8")
    assert main(["check", "north_pointing", str(bad), "--json"]) == 2
    captured = capsys.readouterr()
    data = json.loads(captured.out)
    assert data["exit_status"] == 2
    assert [p["line"] for p in data["problems"]] == [1]
    assert data["summary"]["input_problems"] == 1
    assert not any(e["status"].startswith("agrees") or e["status"] == "mistake"
                   for e in data["equations"])
    assert len(_errors(captured.err)) == 1


def test_one_bad_line_among_good_ones_keeps_the_report(tmp_path, capsys):
    """The good lines are checked and reported (with the problem under "input:"), and
    the problem is also the one line on stderr."""
    lines = GOOD.splitlines()
    mixed = tmp_path / "mixed.txt"
    mixed.write_text("\n".join([*lines, BROKEN]) + "\n", encoding="utf-8")
    assert main(["check", "north_pointing", str(mixed)]) == 2
    captured = capsys.readouterr()
    assert "13 equation forms compared" in captured.out
    assert f"input: line {len(lines) + 1}, column" in captured.out
    [line] = _errors(captured.err)
    assert line.startswith(f"ins-errors: error: {mixed}: line {len(lines) + 1}, column ")


def test_several_files_name_the_unchecked_one(tmp_path, capsys):
    good, bad = tmp_path / "good.txt", tmp_path / "bad.txt"
    good.write_text(GOOD, encoding="utf-8")
    bad.write_text(BROKEN + "\n", encoding="utf-8")
    assert main(["check", "north_pointing", str(good), str(bad)]) == 2
    captured = capsys.readouterr()
    assert f"==> {bad} <==" in captured.out
    assert "(no discrepancies)" not in captured.out.split(f"==> {bad} <==")[1]
    [line] = _errors(captured.err)
    assert line.startswith(f"ins-errors: error: {bad}: line 1")
