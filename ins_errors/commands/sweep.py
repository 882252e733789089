"""``ins-errors sweep SCENARIO.toml``: run a scenario over its ``[sweep]`` grid."""

from __future__ import annotations

import argparse

from ins_errors.commands.run import SCENARIO_TRUTH_HELP, TRUTHS
from ins_errors.json_output import emit


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run a scenario over the parameter grid of its [sweep] table",
        description="Run the direct, linear (and refined) runs of a scenario at every point "
                    "of its [sweep] grid (motion, duration, step, source magnitudes, Monte "
                    "Carlo draws), one task per point, on Dask (a local cluster of this "
                    "machine's cores, or --scheduler), streaming results into a store. "
                    "Running the same command again after an interruption computes only "
                    "the points the store lacks. A point that fails on its own bad input "
                    "(e.g. a motion that reaches a pole) is stored with its reason and "
                    "no data, the others run on, and the command lists the failed points "
                    "and exits with status 2.")
    parser.add_argument("scenario", help="scenario file with a [sweep] table")
    parser.add_argument("--store", metavar="PATH",
                        help="result store: *.zarr (filled as points finish) or *.nc "
                             "(NetCDF, written when complete); default "
                             "<scenario name>.zarr here")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="address of a running Dask scheduler, e.g. tcp://HOST:8786 "
                             "(default: [sweep] scheduler, else a local cluster)")
    parser.add_argument("--engine", choices=("auto", "dask", "pool", "serial"),
                        default="auto",
                        help="where points run: dask, a local process pool, or serial in "
                             "this process (default: dask when installed, else pool)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="workers of the local cluster or pool (default: CPU cores)")
    parser.add_argument("--json", action="store_true",
                        help="print every point's summary as JSON")
    parser.add_argument("--plot", metavar="PNG",
                        help="plot a figure against one or two swept parameters")
    parser.add_argument("--figure", default="worst_linear_ratio",
                        help="figure to plot: worst_linear_ratio, worst_refined_ratio, "
                             "max_direct:QUANTITY, linear_ratio:QUANTITY, "
                             "refined_ratio:QUANTITY (default worst_linear_ratio)")
    parser.add_argument("--against", metavar="P[,Q]",
                        help="swept parameter(s) on the plot's axes (default: the first "
                             "one or two)")
    parser.add_argument("--truth", choices=TRUTHS, default=None, help=SCENARIO_TRUTH_HELP)
    parser.add_argument("--retry-failed", action="store_true",
                        help="run again the points the store records as failed (by "
                             "default a resumed sweep keeps them: the same input fails "
                             "the same way)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the sweep; 0 when every point ran, 2 when a point failed (listed on stderr,
    and in the JSON under ``"failed"``)."""
    from ins_errors.analysis import sweep as sw
    from ins_errors.model_parameters import parameters_record
    from ins_errors.numeric.model import load_model
    from ins_errors.scenario import load_scenario

    scenario = load_scenario(args.scenario)
    if scenario.sweep is None:
        raise sw.SweepError(f"{args.scenario}: no [sweep] table (ins-errors run runs a "
                            "scenario without one)")
    if args.truth is not None:  # the command line overrides the file
        scenario.truth = args.truth
    if args.workers is not None and args.workers < 1:
        raise sw.SweepError(f"--workers must be at least 1, got {args.workers}")
    if args.plot:
        from ins_errors.output import check_figure

        check_figure(args.plot)  # before any point runs
    store = args.store or sw.default_store(args.scenario)
    result = sw.run_sweep(scenario, store, engine=args.engine, scheduler=args.scheduler,
                          workers=args.workers, progress=not args.no_progress,
                          retry_failed=args.retry_failed)
    data = result.dataset
    plotted = None
    if args.plot:
        swept = sw.swept_names(data)
        against = (args.against.split(",") if args.against else swept[:2])
        plotted = sw.plot(data, args.figure, [a.strip() for a in against], args.plot)
    where = result.engine.where if result.engine is not None else "nothing to run"
    if args.json:
        model = load_model(scenario.model)
        emit({"store": str(result.store), "points": result.points,
              "computed": result.computed, "reused": result.reused,
              "engine": where, "plot": None if plotted is None else str(plotted),
              "truth": scenario.truth,
              "parameters": parameters_record(model, scenario.parameters),
              "swept": {name: data[name].attrs.get("units", "1")
                        for name in sw.swept_names(data)},
              "summary": sw.summary(data),
              "over_draws": sw.over_draws(data),
              "failed": sw.failures(data)}, ensure_ascii=False)
        return _failed(data)
    print(f"{scenario.title}: {result.points} points, {result.computed} computed "
          f"({where}), {result.reused} read back from the store")
    print(sw.table(data, scenario.quantities))
    over = sw.draws_table(data, scenario.quantities)
    if over:
        print(f"\nover the {scenario.sweep.draws} draws of each point:")
        print(over)
    print(f"store: {result.store}")
    if plotted is not None:
        print(f"plot written to {plotted}")
    return _failed(data)


def _failed(data) -> int:
    """Say which points failed (one line each, on stderr) and give the exit status: 2
    (bad input) when any did, else 0."""
    import sys

    from ins_errors.analysis import sweep as sw

    text = sw.failures_text(data)
    if not text:
        return 0
    print(f"ins-errors: {text}", file=sys.stderr)
    return 2
