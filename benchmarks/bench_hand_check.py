"""Hand-derivation checker: parse and check times on the manual's 72-line transcription.

Prints wall and CPU seconds for reading the text and LaTeX transcriptions (LaTeX with the
LALR arithmetic parser and, unless quick, with SymPy's parse_latex lark backend) and for
checking them against the orthodromic model. Nothing is asserted.
"""

from __future__ import annotations

import time
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "manual_000"


def _timed(label: str, function):
    wall, cpu = time.perf_counter(), time.process_time()
    result = function()
    print(f"  {label:<46} {time.perf_counter() - wall:7.2f} s wall "
          f"{time.process_time() - cpu:7.2f} s CPU")
    return result


def main(quick: bool = False) -> None:
    from ins_errors.checker.compare import check_hand
    from ins_errors.checker.notation import ORTHODROMIC
    from ins_errors.checker.parse import read_hand_file
    from ins_errors.models import definition

    _timed("build the orthodromic definition", lambda: definition("orthodromic"))
    text = _timed("read equations.txt (SymPy syntax)",
                  lambda: read_hand_file(EXAMPLES / "equations.txt", ORTHODROMIC))
    latex = _timed("read equations.tex (LALR arithmetic)",
                   lambda: read_hand_file(EXAMPLES / "equations.tex", ORTHODROMIC))
    if not quick:
        _timed("read equations.tex (SymPy parse_latex, lark)",
               lambda: read_hand_file(EXAMPLES / "equations.tex", ORTHODROMIC,
                                      latex_backend="sympy"))
    report = _timed("check text (first: model side, points)", lambda: check_hand(text))
    _timed("check LaTeX (second: shared model side)", lambda: check_hand(latex))
    print(f"  {len(report.results)} equation forms, {len(report.findings)} findings")
