"""``ins-errors compare MODEL``: direct vs linear (vs refined) error runs for given sources.

Example::

    ins-errors compare orthodromic --source gyro_drift_x=0.01deg/h --motion static \\
        --hours 24 --plot out.png --out curves/ --json

Every quantity is read with its unit by the units library (``0.01deg/h``, ``10ug``,
``20arcsec``, ``50deg``, ``250m/s``, ``1s``); a bare number is taken in SI.
"""

from __future__ import annotations

import argparse
import sys

from ins_errors.commands import hours, motion_from_options, motion_kinds, warning_status
from ins_errors.commands.run import TRUTHS
from ins_errors.json_output import emit
from ins_errors.user_paths import expand_user

MOTIONS = ("static", "great-circle", "manoeuvre")  # motion_spec.MOTION_KINDS less "file"

RECORDS_AT_LEAST = 240
"""Records a run shorter than 4 h gets by default (its interval a 240th of the run): a
20-min flight's curves were 21 points, its turns straight segments."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "compare", help="compare direct and linear error runs for given error sources",
        description="Integrate the ideal- and real-work equations (direct run) and the "
                    "generated error equations (linear and refined runs) along one true "
                    "motion, and report, per error quantity, the max difference and its "
                    "ratio to the max direct error.")
    parser.add_argument("model", help="model name (e.g. orthodromic) or model file (my_ins.py)")
    parser.add_argument("--source", "-s", action="append", default=[], metavar="NAME=VALUE",
                        help="error source with unit, e.g. gyro_drift_x=0.01deg/h "
                             "(repeatable; see 'ins-errors models MODEL')")
    parser.add_argument("--parameter", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="model parameter with unit, e.g. strapdown_ned's vertical "
                             "damping gains k_h1=0.0047/s and k_h2=1.4e-5/s^2 (repeatable; "
                             "default: the model's values, listed by 'ins-errors models MODEL')")
    parser.add_argument("--separately", action="store_true",
                        help="run each --source as its own case (default: all together); "
                             "one source may then come at several sizes, each a case "
                             "(-s initial_heading_error=1deg -s initial_heading_error=2deg)")
    parser.add_argument("--motion", type=motion_kinds(MOTIONS), choices=MOTIONS,
                        default="static",
                        help="true motion (default: static)")
    parser.add_argument("--motion-file", type=expand_user, metavar="CSV",
                        help="own motion: CSV with a header row and columns t (s, from 0), "
                             "v_N, v_E (m/s) and optionally h (m), no others; overrides "
                             "--motion; the run lasts the file's length unless --hours or "
                             "--duration says otherwise")
    parser.add_argument("--latitude", default=None,
                        help="start latitude (default 50deg; refused for a model without "
                             "a latitude, naming its own setting, e.g. -p phi0=...)")
    parser.add_argument("--longitude", default=None,
                        help="start longitude (default 30deg; for a model with one)")
    parser.add_argument("--heading", default=None,
                        help="initial track angle of the trihedron (default 0deg at rest, "
                             "90deg, due east, when moving: a day's flight then stays clear "
                             "of the poles)")
    parser.add_argument("--speed", default=None,
                        help="ground speed of --motion great-circle or manoeuvre "
                             "(default 250m/s)")
    parser.add_argument("--height", default=None,
                        help="height (default 0m; for a model with one; refused beside a "
                             "--motion-file with its own column h)")
    parser.add_argument("--hours", type=hours, default=None,
                        help="duration in hours (default 24; with --motion-file the "
                             "file's length, from t = 0 to its last sample)")
    parser.add_argument("--duration", default=None,
                        help="duration with unit, e.g. '90 min' (default as --hours)")
    parser.add_argument("--step", default="1s", help="integration step τ (default 1s)")
    parser.add_argument("--record", default=None,
                        help="recording interval (default: 60 s, or less for a run shorter "
                             "than 4 h: about 240 records; the step if longer)")
    parser.add_argument("--method", choices=("rk4", "euler"), default="rk4",
                        help="rk4 (default) or euler = the manual's rectangle method; the "
                             "integration error is estimated either way")
    parser.add_argument("--validity-threshold", default="5%", metavar="RATIO",
                        help="warn when linear − direct exceeds this share of the error "
                             "(default 5%%; '0.05' or '5%%')")
    parser.add_argument("--platform", choices=("exact", "small-angle"), default="exact",
                        help="platform kinematics of the direct run: exact rotation (default) "
                             "or the source documents' small-angle matrix")
    parser.add_argument("--truth", choices=TRUTHS, default="auto",
                        help="how the true motion of a moving run is built: interpolated = "
                             "the exact truth computed on coarse intervals (about 10 s, "
                             "ending at the motion's leg joins) and interpolated to the "
                             "steps by Chebyshev polynomials (much cheaper at small steps); "
                             "fine = the truth integrated at every step; auto (default) = "
                             "the library's choice (interpolated when every interval holds "
                             "enough steps, else fine)")
    parser.add_argument("--no-refined", action="store_true",
                        help="skip the second-order (refined) run")
    parser.add_argument("--plot", type=expand_user, metavar="FILE",
                        help="write overlaid curves (png/pdf/svg); with several cases "
                             "(--separately) one file per case: FILE_1, FILE_2, ...")
    parser.add_argument("--markdown", type=expand_user, metavar="FILE",
                        help="write the Markdown tables")
    parser.add_argument("--out", "-o", type=expand_user, metavar="DIR",
                        help="folder for every curve of every case as curves.csv and MATLAB "
                             "curves.mat (SI units; the same files as 'ins-errors run' writes)")
    parser.add_argument("--force", action="store_true",
                        help="write into a non-empty --out folder that ins-errors did not "
                             "write (only curves.csv and curves.mat are replaced)")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    warning_status.add_option(parser)
    parser.add_argument("--no-progress", action="store_true", help="never show progress bars")
    parser.set_defaults(func=run)


def _sources(model, items: list[str], separately: bool = False) -> list[tuple[str, float]]:
    """The ``--source NAME=VALUE`` items as (name, SI value) pairs, in the order given.

    Without ``separately`` they make one case, so a name given twice is refused (saying
    that ``--separately`` runs each as its own case). With it each item is a case of its
    own, so one source may come at several sizes; two of them that a case label would
    show alike (the same size given twice) are refused, as their cases could not be told
    apart."""
    from ins_errors.analysis.validity import source_example
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import check_source, name_value_pairs
    from ins_errors.units import parse_quantity

    example = source_example(model)
    if not items:
        raise InsErrorsError(f"give at least one --source NAME=VALUE, e.g. --source {example}")
    if separately:  # one item, one case
        pairs = [next(iter(name_value_pairs([item], "--source", example).items()))
                 for item in items]
    else:
        try:
            pairs = list(name_value_pairs(items, "--source", example).items())
        except InsErrorsError as error:
            if "given twice" not in str(error):
                raise
            raise InsErrorsError(f"{error}: the sources given make one case; with "
                                 "--separately each --source is a case of its own, so a "
                                 "source may come at several sizes") from None
    infos = {name: model.sources[model.index("sources", name)] for name, _ in pairs}
    sources = [(name, check_source(infos[name], parse_quantity(text, infos[name].unit, name),
                                   text)) for name, text in pairs]
    if separately:
        from ins_errors.numeric.compare import case_label

        seen: dict[str, str] = {}
        for (name, value), (_, text) in zip(sources, pairs, strict=True):
            label = case_label(model, {name: value})
            if label in seen:
                raise InsErrorsError(f"--source {name}={text} and {name}={seen[label]} are "
                                     f"the same size ({label}): with --separately each is a "
                                     "case, and these two would be the same case; give "
                                     "each size once")
            seen[label] = text
    return sources


def given_references(args: argparse.Namespace) -> dict[str, tuple[str, str]]:
    """The reference values of the motion's start given explicitly on the command line:
    reference name -> (option, text), for
    :func:`~ins_errors.numeric.trajectories.refuse_unused_references`."""
    return {name: (f"--{name}", getattr(args, name)) for name in ("latitude", "longitude",
                                                                   "height", "heading")
            if getattr(args, name, None) is not None}


def parse_ratio(text: str, what: str) -> float:
    """A ratio above 0 and below
    :data:`~ins_errors.units.VALIDITY_RATIO_CEILING`, given as ``0.05`` or ``5%``."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.units import VALIDITY_RATIO_CEILING, ratio_outside

    body = text.strip()
    scale = 0.01 if body.endswith("%") else 1.0
    try:
        value = float(body.rstrip("%")) * scale
    except ValueError:
        raise InsErrorsError(f"{what} {text!r}: expected a ratio such as 0.05 or 5%") from None
    if not 0 < value < VALIDITY_RATIO_CEILING:
        raise InsErrorsError(f"{what} {text!r}: {ratio_outside(value)}")
    return value


def run(args: argparse.Namespace) -> int:
    """The command: 0, or 1 when it warned and ``--fail-on-warning`` is given."""
    with warning_status.watched_warnings() as shown:
        comparisons = _compare(args)
    return warning_status.exit_status(args, comparisons, shown)


def _compare(args: argparse.Namespace) -> list:
    """Run, print and write the comparisons; returns them."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import (
        parameters_record,
        parameters_used,
        parse_parameter_options,
    )
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import (
        CheckedRatio,
        compare,
        markdown_summary,
        markdown_table,
    )
    from ins_errors.numeric.integrators import step_count
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import file_duration, refuse_unused_heading
    from ins_errors.output import OutputFolder, check_figure, check_file
    from ins_errors.progress import stage
    from ins_errors.units import format_duration, parse_quantity

    if args.plot:
        from ins_errors.output import require_matplotlib

        require_matplotlib("--plot")
    if args.plot:
        check_figure(args.plot)
    if args.markdown:
        check_file(args.markdown)
    if args.speed is not None and (args.motion_file or args.motion == "static"):
        where = "--motion-file gives the motion" if args.motion_file else "the base is static"
        raise InsErrorsError(f"--speed applies to --motion great-circle or manoeuvre, and "
                             f"{where}: leave --speed out or choose a moving --motion")
    if args.out:  # refuse a stranger's folder before computing
        OutputFolder(args.out, force=args.force, create=False)
    model = load_model(args.model)
    sources = _sources(model, args.source, args.separately)
    parameters = parse_parameter_options(model, args.parameter)
    if args.hours is not None and args.duration is not None:
        raise InsErrorsError("give either --hours or --duration, not both")
    tau = parse_quantity(args.step, "s", "--step")
    motion = {"kind": "file" if args.motion_file else args.motion,
              "latitude": args.latitude, "longitude": args.longitude,
              "heading": args.heading, "speed": args.speed,
              "height": args.height}
    if args.motion_file:
        motion["file"] = args.motion_file
    profile = motion_from_options(motion, model=model)
    if args.duration is not None:
        duration = parse_quantity(args.duration, "s", "--duration")
        if not duration > 0:  # zero steps run nothing
            raise InsErrorsError(f"--duration must be positive, got {args.duration!r}")
    elif args.hours is None and args.motion_file:  # the file's length
        duration = file_duration(profile, tau) if tau > 0 else 0.0
    else:
        duration = 3600.0 * (24.0 if args.hours is None else args.hours)
    threshold = parse_ratio(args.validity_threshold, "--validity-threshold")
    n_steps = step_count(duration, tau)
    if n_steps == 0:
        raise InsErrorsError("duration must be at least one step")
    if args.record is not None:
        record = parse_quantity(args.record, "s", "--record")
        if not record > 0:
            raise InsErrorsError(f"--record must be positive, got {args.record!r}")
        if args.duration is None and args.hours is None and args.motion_file:
            from ins_errors.numeric.integrators import record_stride

            try:  # said with where the duration came from
                record_stride(record, tau, n_steps)
            except InsErrorsError as error:
                raise type(error)(f"{error} (the run is the motion file's length, "
                                  f"{duration:g} s in whole steps, as no --hours or "
                                  "--duration is given)") from None
    else:  # the largest multiple of the step up to 60 s, and up to a 240th of the run
        # (a short run's curves in as many points as a 4-h one's), that divides the run
        target = min(60.0, duration / RECORDS_AT_LEAST)
        stride = max(1, min(n_steps, int(target / tau + 1e-9)))
        while n_steps % stride:
            stride -= 1
        record = stride * tau
    if args.heading is not None:
        refuse_unused_heading(model, profile)
    progress = not args.no_progress and n_steps >= 100_000
    trajectory = tr.trajectory(model, profile, duration, tau,
                               p=model.parameter_vector(**parameters), progress=progress,
                               truth=args.truth)
    tr.refuse_unused_references(model, trajectory, given_references(args))
    cases = ([{name: value} for name, value in sources] if args.separately
             else [dict(sources)])
    comparisons = compare(model, trajectory, cases, method=args.method, record_interval=record,
                          refined=not args.no_refined, progress=progress,
                          platform=args.platform.replace("-", "_"),
                          validity_threshold=CheckedRatio(threshold), warn=False)
    for comparison in comparisons:  # notes about the motion (a noisy motion file), as run
        comparison.warnings.extend(getattr(trajectory, "notes", ()))
    title = (f"{model.name}: {trajectory.description}; {format_duration(duration)}, "
             f"τ = {tau:g} s, {args.method}")
    tables = "\n".join(markdown_table(c) for c in comparisons)
    text = markdown_summary(comparisons, title) + "\n" + tables  # the warnings in full
    shown = markdown_summary(comparisons, title, brief=True, details=(
        args.markdown if args.markdown else "--json, or --markdown FILE")) + "\n" + tables
    if args.markdown:
        from ins_errors.output import write_text

        write_text(args.markdown, text)
    if args.out:
        from ins_errors.export import write_curves

        folder = OutputFolder(args.out, force=args.force)
        with stage(f"writing curves.csv and curves.mat in {folder.path}",
                   enabled=not args.no_progress):
            write_curves(folder, comparisons)
        folder.finish()
    if args.plot:
        from pathlib import Path

        from ins_errors.numeric.plots import plot_comparisons, shared_quantities

        path = Path(args.plot)
        targets = [path] if len(comparisons) == 1 else [
            path.with_name(f"{path.stem}_{k + 1}{path.suffix}") for k in range(len(comparisons))]
        with stage(f"drawing {targets[0] if len(targets) == 1 else f'{len(targets)} plots'}",
                   enabled=not args.no_progress):
            plot_comparisons(comparisons, targets,
                             quantities=shared_quantities(comparisons),  # one layout for all
                             titles=[f"{c.label}\n{title}" for c in comparisons])
        written = f"plot written to {targets[0]}" if len(targets) == 1 else \
            f"plots written to {targets[0]} … {targets[-1].name} (one per case)"
    if args.json:
        emit({"model": model.name, "motion": trajectory.description, "duration_s": duration,
                   "step_s": tau, "record_s": record, "method": args.method,
                   "truth": args.truth, "truth_used": trajectory.truth_kind,
                   "parameters": parameters_record(model, parameters),
                   "parameters_used": parameters_used(model, trajectory.parameters),
                   "cases": [c.to_dict() for c in comparisons]})
    else:
        print(shown)
    if args.plot:  # beside the JSON, not inside it
        print(written, file=sys.stderr if args.json else sys.stdout)
    return comparisons
