"""Derive step: the hand-derivation checker's reports on the manual's printed equations.

Checks the two transcriptions of source 000's error equations (``examples/manual_000/
equations.txt`` in SymPy syntax and ``equations.tex`` in LaTeX, both exactly as printed)
against the orthodromic model and writes

* ``generated/orthodromic/hand_check_manual_000_text.md``
* ``generated/orthodromic/hand_check_manual_000_latex.md``

with the default threshold. The two reports differ only in their title lines: the
LaTeX and text forms of the same equations give the same findings.
"""

from __future__ import annotations

from pathlib import Path

from ins_errors.checker.compare import check_hand_file
from ins_errors.checker.report import to_markdown
from ins_errors.symbolic.shared_trees import SharedTrees

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "manual_000"
REPORTS = (("equations.txt", "hand_check_manual_000_text.md"),
           ("equations.tex", "hand_check_manual_000_latex.md"))
"""(transcription in examples/manual_000, report name under generated/orthodromic)."""


def write_hand_check_reports(generated_root: Path) -> None:
    """Check both transcriptions and write their Markdown reports under ``generated_root``."""
    folder = generated_root / "orthodromic"
    folder.mkdir(parents=True, exist_ok=True)
    with SharedTrees().differentiating():  # the checker's derivatives, each subtree once
        reports = [check_hand_file(EXAMPLES / source, model="orthodromic")
                   for source, _ in REPORTS]
    for (source, target), report in zip(REPORTS, reports, strict=True):
        origin = (f"`make derive` (step derive/hand_check_report.py) from "
                  f"examples/manual_000/{source}")
        (folder / target).write_text(to_markdown(report, origin), encoding="utf-8")
