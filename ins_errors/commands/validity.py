"""``ins-errors validity MODEL``: where the linear error equations hold, source by source.

Example::

    ins-errors validity orthodromic --source gyro_drift_x --motion static --hours 6 --json
    ins-errors validity orthodromic --plot --out validity_orthodromic

For each error source (and motion), sweeps its magnitude over decades around a typical
size, runs direct, linear and refined, and reports the log–log slopes of the linear and
refined residuals (1 and 2 for a clean first-order model) and the magnitudes at which
the linear residual reaches 1 % and 10 % of the error.

A sweep that fails (e.g. the direct run leaves the model's domain at the largest
magnitudes) is in the map with its reason and the magnitudes below the first failing one;
the others run on, and the command lists the failed sweeps on stderr, one line each, and
exits with status 3, as ``ins-errors sweep`` does for failed points (bad input to the
command itself exits 2 before any sweep runs).
"""

from __future__ import annotations

import argparse
import sys

from ins_errors.commands import hours, motion_kinds
from ins_errors.commands.run import TRUTHS
from ins_errors.commands.sweep import EXIT_SOME_FAILED
from ins_errors.json_output import dumps, emit
from ins_errors.user_paths import expand_user

MOTIONS = ("static", "great-circle", "manoeuvre")


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "validity", help="validity map: how the linear model's residual scales, per source",
        description="Sweep each error source's magnitude over decades around a typical "
                    "size, run direct, linear and refined, and report the slopes of the "
                    "linear (1 = clean second-order residual) and refined (2) residuals "
                    "against magnitude and the magnitudes where the linear residual "
                    "reaches 1 % and 10 % of the error; one log-log plot per source. A "
                    "sweep that fails (e.g. its largest magnitudes leave the model's "
                    "domain) keeps the magnitudes below the first failing one and its "
                    "reason, the others run on, and the command lists the failed sweeps "
                    "and exits with status 3 (bad input to the command itself exits 2 "
                    "before any sweep runs).")
    parser.add_argument("model", help="model name (e.g. orthodromic) or model file (my_ins.py)")
    parser.add_argument("--motion", action="append", type=motion_kinds(MOTIONS),
                        choices=MOTIONS,
                        help="true motion (repeatable; default: static and great-circle, or "
                             "static only for a model that cannot fly a great circle)")
    parser.add_argument("--source", "-s", action="append", metavar="NAME",
                        help="error source (repeatable; default: every source)")
    parser.add_argument("--parameter", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="model parameter with unit, as for 'ins-errors compare', e.g. "
                             "strapdown_ned's k_h1=0.0047/s (repeatable; used by every run)")
    parser.add_argument("--latitude", default=None,
                        help="start latitude of every motion (default 50deg)")
    parser.add_argument("--longitude", default=None,
                        help="start longitude (default 30deg)")
    parser.add_argument("--heading", default=None,
                        help="initial track angle (default 0deg at rest, 90deg moving)")
    parser.add_argument("--speed", default=None,
                        help="ground speed of the moving motions (default 250m/s)")
    parser.add_argument("--height", default=None, help="height (default 0m)")
    parser.add_argument("--hours", type=hours, default=24.0,
                        help="length of each run in hours (default 24)")
    parser.add_argument("--step", default="2s", help="integration step (default 2s, RK4)")
    parser.add_argument("--truth", choices=TRUTHS, default="auto",
                        help="how the true motion of a moving run is built, as for "
                             "'ins-errors compare --truth': auto (default), interpolated "
                             "or fine")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.add_argument("--plot", action="store_true",
                        help="write one log-log plot per source into --out")
    parser.add_argument("--out", type=expand_user, metavar="DIR",
                        help="folder for results.json and the plots "
                             "(default with --plot: validity_<model>)")
    parser.add_argument("--force", action="store_true",
                        help="write into a non-empty folder ins-errors did not write")
    parser.add_argument("--engine", choices=("serial", "pool", "dask", "auto"),
                        default="auto", help="where the sweeps run (default: Dask when "
                                             "installed, else a local process pool)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run the sweeps on a running Dask scheduler, e.g. "
                             "tcp://HOST:8786 (default: a local cluster of this machine's "
                             "cores)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="workers of the local cluster or pool (default: CPU cores)")
    parser.add_argument("--no-progress", action="store_true", help="never show progress bars")
    parser.set_defaults(func=run)


def _fmt(value, digits: str = ".3g") -> str:
    return "–" if value is None else format(value, digits)


EXTRAPOLATED_MARK = "†"
"""Marks a 1 % or 10 % magnitude read off the fitted line outside the magnitudes swept."""

HALF_TURN_TEXT = "past 180 deg"
"""The cell of an angle source's 1 % or 10 % magnitude past half a turn."""


def magnitude_cell(r, key: str) -> str:
    """The 1 % (``key`` ``"magnitude_1pct"``) or 10 % magnitude of the sweep ``r`` for
    the table: readable (an angle in arcsec, arcmin or deg by its size,
    :func:`~ins_errors.units.format_readable`), marked when extrapolated, and
    :data:`HALF_TURN_TEXT` for an angle past half a turn (the fit's value is in a note)."""
    from ins_errors.units import format_readable

    value = getattr(r, key)
    if value is None:
        return "–"
    how = r.extrapolated.get(key, "")
    if how == "past half a turn":
        return f"{HALF_TURN_TEXT}{EXTRAPOLATED_MARK}"
    text = format_readable(value, r.unit, r.display_unit, 3)
    return text + (EXTRAPOLATED_MARK if how else "")


def table(results, model) -> str:
    """Markdown table of a validity map."""
    from ins_errors.markdown_cells import table_cell
    from ins_errors.units import format_readable

    def shown(r, value):
        return "–" if value is None else format_readable(value, r.unit, r.display_unit, 3)

    lines = ["| source | motion | quantity | linear slope | refined slope | 1 % at "
             "| 10 % at | status |", "|---|---|---|---:|---:|---:|---:|---|"]
    for r in results:
        status = r.status
        if r.failed and r.magnitudes:
            status += f"; failed from {shown(r, r.failed_magnitudes[0])}¹"
        elif r.failed:
            status += "¹"
        lines.append(f"| `{r.source}` | {table_cell(r.motion)} | {r.quantity or '–'} | "
                     f"{_fmt(r.linear_slope)} | {_fmt(r.refined_slope)} | "
                     f"{magnitude_cell(r, 'magnitude_1pct')} | "
                     f"{magnitude_cell(r, 'magnitude_10pct')} | {status} |")
    notes = [f"* `{r.source}` ({r.motion}): {r.note}" for r in results
             if r.status in ("not seen by the linear model", "not excited") and r.note]
    notes += spread_notes(results)
    marked = [r for r in results if r.extrapolated]
    if marked:
        notes += ["", f"{EXTRAPOLATED_MARK} extrapolated: read off the fitted line outside "
                  "the magnitudes swept (the run at the largest is the last measured)"]
        for r in marked:
            for key, how in r.extrapolated.items():
                if how != "past half a turn":
                    continue
                level = "1 %" if key == "magnitude_1pct" else "10 %"
                value = getattr(r, key)
                notes.append(
                    f"* `{r.source}` ({r.motion}): the line reaches {level} only at "
                    f"{format_readable(value, r.unit, r.display_unit, 3)} "
                    f"({value:.3g} rad), past half a turn, a size no angle error has "
                    f"(an error of 200° is one of −160°); up to "
                    f"{shown(r, max(r.magnitudes))}, the largest swept, it stays below")
    failed = [f"* `{r.source}` ({r.motion}): {failure_text(r)}" for r in results if r.failed]
    if failed:
        notes += ["", "¹ failed sweeps (the slopes and magnitudes are those of the "
                  "magnitudes that ran; every magnitude from the first failing one on has "
                  "no result):", *failed]
    return "\n".join(lines) + "\n" + ("\n" + "\n".join(notes) + "\n" if notes else "")


def spread_notes(results) -> list[str]:
    """One line for each slope fitted to points whose neighbouring slopes lie further
    apart than :data:`~ins_errors.analysis.validity.SPREAD_NOTED`: an average of
    different powers, with the range it was fitted over."""
    from ins_errors.analysis.validity import SPREAD_NOTED
    from ins_errors.units import format_readable

    lines = []
    for r in results:
        for which, slope, fit in (("linear", r.linear_slope, r.linear_fit),
                                  ("refined", r.refined_slope, r.refined_fit)):
            if fit is None or fit["local_slopes"][1] - fit["local_slopes"][0] <= SPREAD_NOTED:
                continue
            low, high = (format_readable(value, r.unit, r.display_unit, 3)
                         for value in fit["magnitudes"])
            lines.append(
                f"* `{r.source}` ({r.motion}): the {which} slope {_fmt(slope)} is a line "
                f"through points from {low} to {high} whose slopes between neighbours run "
                f"from {fit['local_slopes'][0]:.2f} to {fit['local_slopes'][1]:.2f}: no "
                "single power law there (e.g. a rounding floor at the small magnitudes, "
                "higher orders at the large ones); the ratios per magnitude are in the JSON")
    return lines


def judged_text(results, step: float) -> str:
    """The line under the map's title saying on which samples its ratios were judged,
    when a run too long to keep at every step was judged on every k-th (empty when
    every sweep was judged at every step)."""
    coarse = sorted({r.judged_every_s for r in results
                     if r.judged_every_s is not None and r.judged_every_s > step * 1.000001})
    if not coarse:
        return ""
    every = " or ".join(f"{k:g} s" for k in coarse)
    return (f"Ratios judged on samples every {every}, not at every step of {step:g} s: "
            "a run this long is not kept at every step (the peaks between samples are "
            "missed; a shorter --hours or a longer --step judges every step).\n\n")


def failure_text(r) -> str:
    """What failed in the sweep ``r`` and why, in one line: which magnitudes ran, the
    one whose run failed, the reason."""
    from ins_errors.units import format_readable

    total = len(r.magnitudes) + len(r.failed_magnitudes)
    ran = (f"{len(r.magnitudes)} of {total} magnitudes ran (up to "
           f"{format_readable(r.magnitudes[-1], r.unit, r.display_unit, 3)})"
           if r.magnitudes else f"none of its {total} magnitudes ran")
    at = ("" if r.failed_at is None else
          f"; the run at {format_readable(r.failed_at, r.unit, r.display_unit, 3)} failed")
    return f"{ran}{at}: {r.failure}"


def _failed(results) -> int:
    """List the failed sweeps on stderr (one line each, the first 10, then how many
    more) and give the exit status: :data:`~ins_errors.commands.sweep.EXIT_SOME_FAILED`
    (3: the map finished) when any failed, else 0."""
    failed = [r for r in results if r.failed]
    if not failed:
        return 0
    from ins_errors.output import failure_list

    count = len(results)
    print(failure_list(f"ins-errors: {len(failed)} of {count} validity sweep"
                       f"{'s' if count != 1 else ''} failed (each keeps the magnitudes below "
                       "its first failing one):",
                       [f"{r.source} on the {r.motion} motion: {failure_text(r)}"
                        for r in failed]), file=sys.stderr)
    return EXIT_SOME_FAILED


START_OPTIONS = ("latitude", "longitude", "heading", "speed", "height")
"""The options that set where (and how fast) every motion of the map starts."""


def _start(args: argparse.Namespace, model, motions: list[str]) -> dict[str, str]:
    """The start options given (name -> text as typed), each checked on every motion it
    applies to (one line naming the option: ``--latitude 95deg is at or beyond a pole``);
    ``--speed`` needs a moving motion."""
    from ins_errors.analysis.validity import applicable
    from ins_errors.commands import motion_from_options
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric.motion_spec import APPLIES_TO

    start = {name: getattr(args, name) for name in START_OPTIONS
             if getattr(args, name) is not None}
    if "speed" in start and not set(motions) & set(APPLIES_TO["speed"]):
        raise InsErrorsError("--speed applies to the moving motions (great-circle, "
                             "manoeuvre), and only static is mapped: leave --speed out or "
                             "add a moving --motion")
    for motion in motions:
        motion_from_options({"kind": motion, **applicable(start, motion)}, model=model)
    return start


def start_text(start: dict[str, str]) -> str:
    """The start settings given, written as the runs' descriptions write them
    (``φ=-70°, h=3000 m``), or empty."""
    from ins_errors.units import parse_quantity

    shown = {"latitude": ("φ={:.4g}°", "deg"), "longitude": ("λ={:.4g}°", "deg"),
             "heading": ("track {:.4g}°", "deg"), "speed": ("{:.4g} m/s", "m/s"),
             "height": ("h={:.4g} m", "m")}
    return ", ".join(shown[key][0].format(parse_quantity(text, shown[key][1], key))
                     for key, text in start.items())


def run(args: argparse.Namespace) -> int:
    from ins_errors.analysis.validity import MOTIONS as DEFAULT_MOTIONS
    from ins_errors.analysis.validity import (
        check_run,
        failures,
        motion_problems,
        validity_map,
        validity_tasks,
    )
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import (
        parameters_record,
        parameters_used,
        parse_parameter_options,
    )
    from ins_errors.numeric.model import load_model
    from ins_errors.output import OutputFolder, require_matplotlib
    from ins_errors.units import parse_quantity

    model = load_model(args.model)
    parameters = parse_parameter_options(model, args.parameter)
    step = parse_quantity(args.step, "s", "--step")
    check_run(args.hours, step)  # (a step no run can use: refused once, not per sweep)
    motions = args.motion or list(DEFAULT_MOTIONS)
    start = _start(args, model, motions)
    problems = motion_problems(model, motions, step, parameters, args.truth, start)
    if problems and args.motion:
        motion, why = next(iter(problems.items()))
        raise InsErrorsError(f"--motion {motion}: {why}; map the static base with "
                             "--motion static")
    if problems:  # the default set: keep what the model can follow, and say so
        motions = [m for m in motions if m not in problems]
        print(f"ins-errors: validity: mapping {', '.join(motions)} only; left out: "
              + "; ".join(f"{m} ({why})" for m, why in problems.items()), file=sys.stderr)
    tasks = validity_tasks(model, motions, args.source, hours=args.hours, step=step,
                           parameters=parameters, truth=args.truth, start=start)
    out_dir = args.out or (f"validity_{model.name}" if args.plot else None)
    if args.plot:
        require_matplotlib("--plot")
    if out_dir is not None:
        OutputFolder(out_dir, force=args.force, create=False)  # refuse before computing
    if args.workers is not None and args.workers < 1:
        raise InsErrorsError(f"--workers must be at least 1, got {args.workers}")
    engine = args.engine if len(tasks) > 1 or args.scheduler else "serial"
    results = validity_map(tasks, engine=engine, progress=not args.no_progress,
                           scheduler=args.scheduler, workers=args.workers)
    payload = {"model": model.name, "hours": args.hours, "step_s": step, "method": "rk4",
               "truth": args.truth, "start": start,
               "parameters": parameters_record(model, parameters),
               "parameters_used": parameters_used(model, model.parameter_vector(**parameters)),
               "sources": [r.to_dict() for r in results], "failed": failures(results)}
    if out_dir is not None:
        out = OutputFolder(out_dir, force=args.force)
        out.write_text("results.json", dumps(payload) + "\n")
        if args.plot:
            from ins_errors.analysis.validity_plot import plot_title, plot_validity

            for name in dict.fromkeys(r.source for r in results):
                sweeps = [r for r in results if r.source == name]
                plot_validity(sweeps, out.file(f"{name}.png"),
                              title=plot_title(model.name, name, args.hours, step,
                                               [r.motion for r in sweeps],
                                               payload["parameters"],
                                               start_text(start)))
        out.finish()
    if args.json:
        emit(payload)
    else:
        print(f"### {model.name}: validity of the linear error equations "
              f"({args.hours:g} h runs, τ = {step:g} s, RK4"
              + (f", {args.truth} truth" if set(motions) - {"static"} else "")
              + (f", {start_text(start)}" if start else "") + ")\n"
              + judged_text(results, step))
        print(table(results, model))
        if out_dir is not None:
            print(f"written: {out_dir}/results.json" + (" and one plot per source"
                                                         if args.plot else ""))
    return _failed(results)
