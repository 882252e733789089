"""``ins-errors run SCENARIO.toml``: run a scenario file and write a report folder."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ins_errors.commands import warning_status
from ins_errors.json_output import emit
from ins_errors.user_paths import expand_user

TRUTHS = ("auto", "interpolated", "fine")  # trajectories.TRUTHS, without importing numpy
SCENARIO_TRUTH_HELP = ("how the true motion of a moving run is built, as for 'ins-errors "
                       "compare --truth': auto, interpolated or fine (default: the "
                       "scenario's [run] truth, else auto)")
"""--truth of the commands that read a scenario file (run, sweep)."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "run", help="run a scenario file (TOML) and write a report folder",
        description="Run the direct, linear and refined error runs a scenario file describes "
                    "(model, motion, run settings, error-source cases with units) and write "
                    "a report folder: report.md, report.html, one plot per case and "
                    "results.json. See examples/ for scenario files.")
    parser.add_argument("scenario", nargs="?", type=expand_user,
                        help="scenario file, e.g. examples/lab_000_task1_gyro_drift.toml")
    parser.add_argument("--schema", action="store_true",
                        help="print the JSON Schema of scenario files (for editors) and exit")
    parser.add_argument("--out", "-o", type=expand_user, metavar="DIR",
                        help="report folder (default: report_<scenario name> here)")
    parser.add_argument("--json", action="store_true",
                        help="print the results as JSON instead of the summary table")
    parser.add_argument("--force", action="store_true",
                        help="write into a non-empty --out folder that ins-errors did not "
                             "write (only the report's own files are replaced)")
    parser.add_argument("--truth", choices=TRUTHS, default=None, help=SCENARIO_TRUTH_HELP)
    warning_status.add_option(parser)
    parser.add_argument("--no-progress", action="store_true", help="never show progress bars")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """The command: 0, or 1 when it warned and ``--fail-on-warning`` is given."""
    with warning_status.watched_warnings() as shown:
        comparisons = _run(args)
    return warning_status.exit_status(args, comparisons, shown)


def _run(args: argparse.Namespace) -> list | None:
    """Run the scenario, write its report and print its summary; returns the
    comparisons (None for ``--schema``)."""
    from ins_errors.numeric.compare import markdown_summary
    from ins_errors.output import OutputFolder, require_matplotlib
    from ins_errors.report import write_report
    from ins_errors.scenario import load_scenario, run_scenario

    if args.schema:
        from ins_errors.scenario_schema import json_schema

        print(json_schema(), end="")
        return None
    if args.scenario is None:
        from ins_errors.errors import InsErrorsError

        raise InsErrorsError("run needs a SCENARIO file (or --schema)")
    require_matplotlib("the report's plots")
    scenario = load_scenario(args.scenario)
    if scenario.sweep is not None:  # its grid would be silently left out
        from ins_errors.errors import InsErrorsError

        raise InsErrorsError(f"{args.scenario}: it has a [sweep] table, and a sweep file "
                             f"is run with 'ins-errors sweep {args.scenario} --store "
                             "STORE' (without [sweep], 'ins-errors run' runs its scenario)")
    if args.truth is not None:  # the command line overrides the file
        scenario.truth = args.truth
    out = Path(args.out) if args.out else Path(f"report_{Path(args.scenario).stem}")
    OutputFolder(out, force=args.force, create=False)  # refuse a stranger's, before computing
    steps = scenario.duration / scenario.step
    result = run_scenario(scenario, progress=not args.no_progress and steps >= 100_000)
    report = write_report(result, out, force=args.force, progress=not args.no_progress)
    if args.json:
        emit(json.loads((out / "results.json").read_text(encoding="utf-8")))
    else:
        print(markdown_summary(result.comparisons, scenario.title, brief=True,
                               details=str(report)))
        print(f"report: {report} (and report.html, plots, results.json in {out})")
    return result.comparisons
