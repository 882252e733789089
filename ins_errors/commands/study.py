"""``ins-errors study NAME``: the investigations of the source documents, one call each.

Studies::

    nonsphericity, coriolis, gravity_projections
        000, tasks 3, 5, 6: the on-board computer uses a simplified formula; direct and
        linear runs over 24 h on a static base and in a great-circle flight, with plots.
    spheroid
        004, formula (10) against a direct simulation over the Krasovsky spheroid, and its
        maximum over latitudes and orthodrome angles.

Examples::

    ins-errors study coriolis --scenario both --hours 24 --plot out/
    ins-errors study spheroid --hours 6
    ins-errors study list
"""

from __future__ import annotations

import argparse

from ins_errors.commands import hours, motion_from_options
from ins_errors.json_output import emit
from ins_errors.user_paths import user_path

SPHEROID = "spheroid"
DEFAULT_SPEED = "250 m/s"
"""Ground speed of the flights when no --speed is given."""


def study_names() -> list[str]:
    """Every study name the command accepts."""
    from ins_errors.studies.methodological import STUDIES

    return [*STUDIES, SPHEROID]


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "study", help="run a study of the source documents (methodological errors, (10))",
        description="Run one study: 'nonsphericity', 'coriolis', 'gravity_projections' "
                    "(simplified on-board formulas of 000, tasks 3, 5, 6: direct vs linear, "
                    "static base and flight) or 'spheroid' (004, formula (10) vs a direct "
                    "simulation over the spheroid). 'list' shows them.")
    parser.add_argument("name", help="study name, or 'list'")
    parser.add_argument("--scenario", choices=("static", "flight", "both"), default=None,
                        help="methodological studies: motion (default both)")
    parser.add_argument("--hours", type=hours, default=None,
                        help="duration, h (default 24; spheroid: 6)")
    parser.add_argument("--step", default=None,
                        help="integration step (default 20 s); it must divide the duration, "
                             "and the spheroid study's recording interval follows it")
    parser.add_argument("--method", choices=("rk4", "euler"), default="rk4",
                        help="methodological studies: integration scheme, RK4 (default) or "
                             "the manual's rectangle method ('euler')")
    parser.add_argument("--latitude", default=None,
                        help="methodological studies: start latitude (default 50deg; the "
                             "spheroid study flies its own latitudes)")
    parser.add_argument("--speed", default=None,
                        help="ground speed in flight (default 250 m/s; not with "
                             "--scenario static)")
    parser.add_argument("--plot", type=user_path, default=None, metavar="DIR",
                        help="write PNG plots into this folder")
    parser.add_argument("--force", action="store_true",
                        help="write into a non-empty --plot folder that ins-errors did not "
                             "write (only the study's own plots are replaced)")
    parser.add_argument("--no-progress", action="store_true",
                        help="never show progress (the study's status lines)")
    parser.add_argument("--json", action="store_true", help="machine-readable summary")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.errors import unknown_name
    from ins_errors.numeric.integrators import whole_steps
    from ins_errors.progress import stage
    from ins_errors.units import parse_quantity

    names = study_names()
    if args.name == "list":
        from ins_errors.studies.methodological import STUDIES

        rows = [{"name": s.name, "source": f"000 task {s.task}", "description": s.description}
                for s in STUDIES.values()]
        rows.append({"name": SPHEROID, "source": "004 formula (10)",
                     "description": "formula (10) vs direct simulation over the spheroid"})
        if args.json:
            emit(rows)
        else:
            for row in rows:
                print(f"{row['name']:<22} {row['source']}: {row['description']}")
        return 0
    if args.name not in names:
        raise unknown_name("study", args.name, names)
    folder = None
    if args.plot is not None:
        from ins_errors.output import OutputFolder, require_matplotlib

        require_matplotlib("--plot")
        folder = OutputFolder(args.plot, force=args.force, option="--plot")
    speed = parse_quantity(DEFAULT_SPEED if args.speed is None else args.speed, "m/s",
                           "--speed")
    step = parse_quantity(args.step or "20 s", "s", "--step")
    if not step > 0:
        from ins_errors.errors import InsErrorsError

        raise InsErrorsError(f"--step must be positive, got {args.step!r}")
    if args.name == SPHEROID:
        if args.latitude is not None:
            from ins_errors.errors import InsErrorsError

            raise InsErrorsError("--latitude: the spheroid study flies from a grid of "
                                 "latitudes of its own; leave --latitude out")
        if args.method != "rk4":
            from ins_errors.errors import InsErrorsError

            raise InsErrorsError("--method: the spheroid study integrates by RK4 only; "
                                 "leave --method out")
        if args.scenario is not None:
            from ins_errors.errors import InsErrorsError

            raise InsErrorsError("--scenario: the spheroid study flies its own flights (a "
                                 "grid of start latitudes and courses); leave --scenario out")
        return _spheroid(args, speed, step, folder)
    from ins_errors.studies import methodological

    hours = 24.0 if args.hours is None else args.hours
    scenarios = (("static", "flight") if args.scenario in (None, "both")
                 else (args.scenario,))
    if args.speed is not None and "flight" not in scenarios:  # as compare on a static base
        from ins_errors.errors import InsErrorsError

        raise InsErrorsError("--speed applies to the flight (--scenario flight or both), "
                             "and --scenario static is a static base: leave --speed out or "
                             "choose --scenario flight or both")
    # the start, checked before any run, its errors naming the options
    flight = "flight" in scenarios
    latitude = motion_from_options({
        "kind": "great-circle" if flight else "static",
        "latitude": args.latitude or "50deg",
        "speed": (DEFAULT_SPEED if args.speed is None else args.speed) if flight else None}
    ).latitude
    # every minute (about 84 samples per Schuler period, so plotted peaks are smooth)
    # when a minute is whole steps and the run whole minutes, else every step
    duration = hours * 3600.0
    record = (60.0 if whole_steps(60.0, step) and whole_steps(duration, 60.0) is not None
              else step)
    report = []
    for scenario in scenarios:
        with stage(f"{args.name}: {scenario} runs"):
            result = methodological.run(args.name, scenario, latitude,
                                        duration=duration, tau=step,
                                        record_interval=record, speed=speed,
                                        method=args.method)
        lines = result.summary()
        if folder is not None:
            path = methodological.plot(result, folder.file(f"{args.name}_{scenario}.png"))
            lines.append(f"  plot: {path}")
        report.append({"scenario": scenario, "motion": result.motion,
                       "duration_s": float(result.times[-1]),
                       "equivalent_sources": result.equivalent_sources(),
                       "quantities": result.quantities(),
                       "warnings": result.warnings, "lines": lines})
        if not args.json:
            print("\n".join(lines))
    if folder is not None:
        folder.finish()
    if args.json:
        emit({"study": args.name, "runs": report})
    return 0


def _spheroid(args: argparse.Namespace, speed: float, step: float, folder) -> int:
    from ins_errors.progress import stage
    from ins_errors.studies import spheroid_error

    hours = 6.0 if args.hours is None else args.hours
    with stage("direct flights over the spheroid and formula (10)"):
        result, lines = spheroid_error.survey(duration=hours * 3600.0, speed=speed, step=step)
    if folder is not None:
        path = spheroid_error.plot(result, folder.file("spheroid_formula_10.png"))
        folder.finish()
        lines.append(f"plot: {path}")
    if args.json:
        error = result.integration_error
        emit({"study": SPHEROID, "duration_s": hours * 3600.0, "speed_m_per_s": speed,
              "step_s": step, "flights": result.flights,
              "integration_error_km": None if error is None else
              float(error.max() * result.a / 1000),
              "warnings": result.warnings,
              "formula_10_maximum": spheroid_error.formula_10_maximum(), "lines": lines})
    else:
        print("\n".join(lines))
    return 0
