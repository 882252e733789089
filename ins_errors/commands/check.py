"""``ins-errors check MODEL FILE``: audit hand-written error equations term by term."""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "check", help="compare hand-written error equations with the model's variation",
        description="Compare a researcher's error equations (SymPy text or LaTeX, one per "
                    "line) with the mechanical variation of MODEL, term by term. Each "
                    "discrepancy is sized along reference motions relative to the largest "
                    "term of its equation and classed 'dropped small term' (below the "
                    "threshold) or 'mistake'. Exit status: 0 no mistake, 1 mistakes found, "
                    "2 input problems. Notation: docs/hand_check.md.")
    parser.add_argument("model", help="model name, e.g. orthodromic")
    parser.add_argument("file", type=Path, help="hand file (.txt SymPy syntax, .tex LaTeX)")
    parser.add_argument("--latex", action="store_true",
                        help="read FILE as LaTeX whatever its suffix")
    parser.add_argument("--threshold", type=float, default=1e-3,
                        help="relative size separating dropped small terms from mistakes "
                             "(default 1e-3)")
    parser.add_argument("--mapping", type=Path,
                        help="mapping file (@alias / @source lines) added to the default "
                             "notation")
    parser.add_argument("--report", type=Path, help="also write the Markdown report here")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--latex-parser", choices=("lalr", "sympy"), default="lalr",
                        help="parser of LaTeX arithmetic: fast LALR grammar (default) or "
                             "SymPy's parse_latex with lark (slow, for cross-checks)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.checker.compare import check_hand_file
    from ins_errors.checker.report import to_json, to_markdown, to_terminal
    from ins_errors.errors import InsErrorsError

    report = check_hand_file(args.file, model=args.model, threshold=args.threshold,
                             latex=True if args.latex else None, mapping_path=args.mapping,
                             latex_backend=args.latex_parser)
    if args.report is not None:
        try:
            args.report.write_text(to_markdown(report, f"`ins-errors check` from "
                                               f"`{args.file.name}`"), encoding="utf-8")
        except OSError as error:
            raise InsErrorsError(f"cannot write report {str(args.report)!r}: "
                                 f"{error.strerror}") from None
    if args.json:
        print(json.dumps(to_json(report), indent=2))
    else:
        print(to_terminal(report))
    return report.exit_status
