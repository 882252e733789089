"""The summary table `make derive` and `ins-errors derive` print says what its columns
are: "errors" and "ops" were unexplained (the error states, the length of xe; SymPy's
operation count of the generated code)."""

from __future__ import annotations

from pathlib import Path

import ins_errors
from ins_errors.cli import main

SCHULER = Path(__file__).resolve().parent.parent / "examples" / "own_model" / "schuler_loop.py"


def test_the_derive_summary_says_what_errors_and_ops_are(tmp_path, capsys):
    assert main(["derive", str(SCHULER), "--out", str(tmp_path / "pkg")]) == 0
    lines = capsys.readouterr().out.splitlines()
    head, row = lines[0].split(), lines[1].split()
    assert head == ["model", "states", "errors", "sources", "outputs", "ops", "seconds"]
    model = ins_errors.load_model(str(SCHULER))
    numbers = dict(zip(head[1:], row[1:], strict=True))
    assert int(numbers["states"]) == len(model.states)
    assert int(numbers["errors"]) == len(model.error_states) != len(model.states)
    assert lines[2] == "errors: error states, the length of xe in ẋe = F xe + G w"
    assert lines[3].startswith("ops: SymPy's operation count of the generated numeric "
                               "functions")
