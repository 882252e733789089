"""``ins-errors sweep SCENARIO.toml``: run a scenario over its ``[sweep]`` grid."""

from __future__ import annotations

import argparse

from ins_errors.commands.run import SCENARIO_TRUTH_HELP, TRUTHS
from ins_errors.json_output import emit
from ins_errors.user_paths import expand_user

EXIT_SOME_FAILED = 3
"""Exit status of a command that finished but some of whose points (``sweep``) or sweeps
(``validity``) failed on their own input, each listed on stderr (and in ``--json`` under
``"failed"``): not 2, which says the command did not run (bad input), so a script tells
"finished, some failed" from "did not run"."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run a scenario over the parameter grid of its [sweep] table",
        description="Run the direct, linear (and refined) runs of a scenario at every point "
                    "of its [sweep] grid (motion, duration, step, source magnitudes, model "
                    "parameters such as a damping gain, Monte Carlo draws), one task per "
                    "point, on Dask (a local cluster of this machine's cores, or "
                    "--scheduler), streaming results into a store. "
                    "Running the same command again after an interruption computes only "
                    "the points the store lacks; run with other [sweep] grid values "
                    "(every other setting the same), it extends the store, computing "
                    "only the points it lacks and reporting this grid's. A point that "
                    "fails on its own bad input "
                    "(e.g. a motion that reaches a pole) is stored with its reason and "
                    "no data, the others run on, and the command lists the failed points "
                    "and exits with status 3 (bad input to the command itself exits 2 "
                    "before any point runs). A sweep can be split between N jobs (a "
                    "SLURM array): each runs --shard I/N into a store of its own, then "
                    "'ins-errors sweep FILE --merge PART... --store ALL' joins their "
                    "stores into the one the whole sweep would have written. It says on "
                    "stderr first how large the store will be (points, bytes, files) "
                    "and how many points it will compute; a store estimated beyond 20 GB "
                    "or 500,000 files, or beyond the free space or files of its file "
                    "system, is refused before anything is written (--allow-large-store "
                    "writes it anyway).")
    parser.add_argument("scenario", type=expand_user, help="scenario file with a [sweep] table")
    parser.add_argument("--store", type=expand_user, metavar="PATH",
                        help="result store: *.zarr (filled as points finish) or *.nc "
                             "(NetCDF, written when complete); default "
                             "<scenario name>.zarr here (of a shard: "
                             "<scenario name>.shard-I-of-N.zarr)")
    parser.add_argument("--shard", metavar="I/N",
                        help="run only shard I of N of the points (1 <= I <= N: the points "
                             "I-1, I-1+N, I-1+2N, ... of the sweep, Monte Carlo draws "
                             "included, on any engine), into a store of its own; e.g. "
                             "--shard $SLURM_ARRAY_TASK_ID/8 in a job array --array=1-8")
    parser.add_argument("--merge", type=expand_user, nargs="+", metavar="PART",
                        help="compute nothing: join the stores of the N shards of this "
                             "sweep (each --shard I/N run) into --store, after checking "
                             "that they belong to this sweep and hold every point once "
                             "(a shard whose points failed, exit status 3, is finished "
                             "and merges; the merge then exits 3 too)")
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
    parser.add_argument("--plot", type=expand_user, metavar="PNG",
                        help="plot a figure against one or two swept parameters")
    parser.add_argument("--figure",
                        help="figure --plot draws: worst_linear_ratio, worst_refined_ratio, "
                             "max_direct:QUANTITY, linear_ratio:QUANTITY, "
                             "refined_ratio:QUANTITY (default worst_linear_ratio)")
    parser.add_argument("--against", metavar="P[,Q]",
                        help="swept parameter(s) on the axes of --plot (default: the first "
                             "one or two)")
    parser.add_argument("--truth", choices=TRUTHS, default=None, help=SCENARIO_TRUTH_HELP)
    parser.add_argument("--retry-failed", action="store_true",
                        help="run again the points the store records as failed (by "
                             "default a resumed sweep keeps them: the same input fails "
                             "the same way)")
    parser.add_argument("--allow-large-store", action="store_true",
                        help="write the store even when its size estimate (said on "
                             "stderr before anything is written) is beyond 20 GB or "
                             "500,000 files, or beyond the free space or files left on "
                             "its file system (refused otherwise, exit status 2)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the sweep; 0 when every point ran, :data:`EXIT_SOME_FAILED` (3) when a point
    failed on its own input (listed on stderr, and in the JSON under ``"failed"``); bad
    input to the command itself raises before any point runs (exit 2).

    Stopped (Ctrl-C, SIGTERM) at any moment, the interruption says how many points the
    store keeps, or that it came before any point was stored."""
    counts = {"points": 0, "before": 0, "stored": 0, "others": 0}
    try:
        return _run(args, counts)
    except KeyboardInterrupt as stop:  # what is kept, and how to go on (the CLI says)
        kept = counts["before"] + counts["stored"]
        if "store" in counts and args.merge is None:
            # the store's own flags: a point written just before the signal, whose count
            # the callback had not yet taken, is kept too (the rerun reuses it); an
            # extended store's flags count the points of its other grids too
            on_disk = _points_on_disk(counts["store"])
            kept = kept if on_disk is None else max(kept, on_disk - counts["others"])
        if kept and kept >= counts["points"] and args.merge is None:
            stop.detail = (f"the sweep's {counts['points']} points are all in "
                           f"{counts['store']}")
        elif kept and args.merge is None:
            stop.detail = (f"{kept} of the {counts['points']} points are in "
                           f"{counts['store']}; the same command runs the others")
        elif args.merge is None:
            stop.when = "before any point was stored"
        raise


def _points_on_disk(store) -> int | None:
    """How many points the store being filled holds, for the line of a stop; None when
    that cannot be known. The stop may have cut short anything, also the first import
    of the store's libraries (a module left half-imported then fails to import again,
    which gave a traceback instead of the line) or the writing of the store's first
    group (read then, zarr warned of the half-written folder)."""
    import warnings

    try:
        from ins_errors.analysis.store import points_done

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return points_done(store)
    except Exception:
        return None


def _run(args: argparse.Namespace, counts: dict) -> int:
    from ins_errors.analysis import sweep as sw
    from ins_errors.analysis import sweep_report as sr
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
    shard = sw.parse_shard(args.shard) if args.shard is not None else None
    if args.merge is not None and shard is not None:
        raise sw.SweepError("--merge joins the stores of the shards; --shard runs one of "
                            "them: give one of the two")
    if args.merge is not None:
        running = [option for option, given in (
            ("--engine", args.engine != "auto"), ("--workers", args.workers is not None),
            ("--scheduler", args.scheduler is not None)) if given]
        if running:
            raise sw.SweepError(f"--merge computes nothing, so {', '.join(running)} would "
                                "be ignored: give them to the sweep commands of the shards")
    if args.merge is not None and args.retry_failed:
        raise sw.SweepError("--merge computes nothing: give --retry-failed to the sweep "
                            "command of the shard whose failed points should run again, "
                            "then merge")
    figure, against = _plot_request(args, scenario)  # all before any point runs
    count = sw.point_count(scenario)  # refused beyond sw.MAX_POINTS before they are built
    if shard is not None:
        sw.check_shard(shard, count)
    store = args.store or sw.default_store(args.scenario, shard)
    title = scenario.title
    counts["store"] = store
    others: list[int] = []  # of a store extended by this sweep's grid

    def say(points: int, todo: int, total: int) -> None:
        import sys

        counts.update(points=points, before=points - todo, others=sum(others))
        plural = "s" if total != 1 else ""
        how_many = (f"shard {shard}: {points} of the {total} point{plural}" if shard
                    else f"{total} point{plural}")
        doing = (f"{todo} to copy from {len(args.merge)} shard stores" if args.merge
                 else f"{todo} to compute")
        kept = (f" (extended: it keeps {others[0]} point{'s' if others[0] != 1 else ''} "
                "of other grids)" if others else "")
        print(f"ins-errors: sweep {title!r}, {how_many}, {doing}, {points - todo} already "
              f"in {store}{kept}", file=sys.stderr, flush=True)

    def size(estimate) -> None:
        import sys

        print(f"ins-errors: store: {estimate.text}", file=sys.stderr, flush=True)

    if args.merge is not None:
        result = sw.merge_shards(scenario, args.merge, store, on_start=say, on_size=size,
                                 allow_large_store=args.allow_large_store)
    else:
        def stored(_: int) -> None:
            counts["stored"] += 1

        result = sw.run_sweep(scenario, store, engine=args.engine,
                              scheduler=args.scheduler, workers=args.workers,
                              progress=not args.no_progress,
                              retry_failed=args.retry_failed, shard=shard, on_start=say,
                              on_result=stored, on_extend=others.append,
                              on_size=size, allow_large_store=args.allow_large_store)
    data = result.dataset
    plotted = None
    if args.plot:
        plotted = sr.plot(data, figure, against or sr.swept_names(data)[:2], args.plot)
    if args.merge is not None:
        where = f"merged from {len(args.merge)} shard stores"
    else:
        where = result.engine.where if result.engine is not None else "nothing to run"
    if args.json:
        model = load_model(scenario.model)
        emit({"store": str(result.store), "points": result.points,
              "computed": result.computed, "reused": result.reused,
              "store_others": result.others,
              "sweep_points": result.total, "shard": None if shard is None else str(shard),
              "merged": result.merged,
              "engine": where, "plot": None if plotted is None else str(plotted),
              "truth": scenario.truth,
              "parameters": parameters_record(model, sw.fixed_parameters(scenario)),
              "swept": {name: data[name].attrs.get("units", "1")
                        for name in sr.swept_names(data)},
              "summary": sr.summary(data),
              "over_draws": sr.over_draws(data),
              "failed": sr.failures(data)}, ensure_ascii=False)
        if args.plot and plotted is None:
            _nothing_to_plot(data, figure, args.plot)
        return _failed(data)
    if args.merge is not None:
        print(f"{scenario.title}: {_points(result.points)}, {result.merged} copied ({where}), "
              f"{result.reused} already in the store")
    else:
        whose = f" (shard {shard} of {result.total})" if shard is not None else ""
        print(f"{scenario.title}: {_points(result.points)}{whose}, {result.computed} computed "
              f"({where}), {result.reused} read back from the store")
    print(sr.table(data, scenario.quantities))
    over = sr.draws_table(data, scenario.quantities)
    if over:
        print(f"\nover the {scenario.sweep.draws} draws of each point:")
        print(over)
    print(f"store: {result.store}")
    if plotted is not None:
        print(f"plot written to {plotted}")
    elif args.plot:
        _nothing_to_plot(data, figure, args.plot)
    return _failed(data)


def _nothing_to_plot(data, figure: str, path) -> None:
    """Say on stderr that --plot wrote nothing (no point has a value of the figure)."""
    import sys

    from ins_errors.analysis import sweep_report as sr

    print(f"ins-errors: {sr.nothing_to_plot(data, figure, path)}", file=sys.stderr)


def _points(count: int) -> str:
    """``"1 point"``, ``"16 points"``."""
    return f"{count} point{'s' if count != 1 else ''}"


def _plot_request(args: argparse.Namespace, scenario) -> tuple[str, list[str] | None]:
    """The figure and axes of ``--plot``, checked before any point runs (the file can be
    written, the figure and the swept parameters exist in this sweep).

    Raises
    ------
    SweepError
        ``--figure`` or ``--against`` without ``--plot``, or a figure or parameter the
        sweep does not have (one line).
    """
    from ins_errors.analysis import sweep as sw
    from ins_errors.analysis import sweep_report as sr

    if not args.plot:
        given = [option for option, value in (("--figure", args.figure),
                                              ("--against", args.against)) if value]
        if given:
            raise sw.SweepError(f"{' and '.join(given)} choose{'s' if len(given) == 1 else ''}"
                                " what --plot draws: give --plot PNG too")
        return "", None
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import error_quantities
    from ins_errors.output import check_figure

    check_figure(args.plot)  # (tried: a place that takes no files is refused now)
    figure = args.figure or "worst_linear_ratio"
    sr.check_figure(figure, error_quantities(load_model(scenario.model))[0],
                    scenario.refined)
    swept = sr.scenario_swept_names(scenario)
    against = sr.check_against(args.against.split(",") if args.against else swept[:2],
                               swept)
    return figure, against


def _failed(data) -> int:
    """Say which points failed (one line each, on stderr) and give the exit status:
    :data:`EXIT_SOME_FAILED` (3: the sweep finished, its store is complete) when any
    did, else 0."""
    import sys

    from ins_errors.analysis import sweep_report as sr

    text = sr.failures_text(data)
    if not text:
        return 0
    print(f"ins-errors: {text}", file=sys.stderr)
    return EXIT_SOME_FAILED
