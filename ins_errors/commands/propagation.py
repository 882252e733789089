"""``ins-errors propagation``: the error-propagation experiment of 001 (and 000, task 4).

Examples::

    ins-errors propagation --out out/propagation
    ins-errors propagation --latitude 49deg --drift "0.05 deg/h" --hours 48 --out out/p49
    ins-errors propagation --orthodromic --latitude 50deg

JSON (``--json``): ``periods_s`` maps mode name -> period, s, with the Foucault-split
pair named by size in either hemisphere: ``"Schuler − Foucault"`` is always the longer
period 2π/(ω̄ − Ω|sin φ|), ``"Schuler + Foucault"`` the shorter; ``gravity_m_s2`` and
``radius_m`` are the g (a_ζ with --orthodromic) and R those periods come from. Per source,
``reduced_vs_full`` is the worst relative difference of the reduced closed forms over the
quantities both models have (0: same to rounding), ``reduced_vs_full_quantity`` its
quantity and ``not_in_reduced`` the quantities the reduced model leaves at zero.
"""

from __future__ import annotations

import argparse

import numpy as np

from ins_errors.commands import hours
from ins_errors.json_output import emit
from ins_errors.user_paths import user_path

_EXPERIMENT_OPTIONS = (("--drift", "0.1 deg/h", "gyro drift"),
                       ("--bias", "1e-4 g", "accelerometer bias"),
                       ("--velocity", "0.1 m/s", "initial velocity error"),
                       ("--position", "0.0005 deg", "initial position error"),
                       ("--level", "20 arcsec", "initial level error"),
                       ("--azimuth", "5 arcmin", "initial azimuth error"))
"""Options of the 001 experiment: (option, default, what it sets)."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "propagation", help="001 experiment: per-source error propagation, analytic vs "
                            "linear vs direct (static base)",
        description="Run the error-propagation experiment of source 001 on the "
                    "north-pointing INS: every error source alone, closed forms (full and "
                    "the report's reduced model) against linear and direct numeric runs; "
                    "prints the agreement table and writes summary.md and one PNG per "
                    "source with --out. --orthodromic runs source 000, task 4 instead.")
    parser.add_argument("--latitude",
                        help="latitude (default 39deg for the 001 experiment: source 001 "
                             "prints it only partly legible, \"?9°\", read as 39°; "
                             "50deg with --orthodromic, as the other source-000 commands)")
    parser.add_argument("--hours", type=hours, default=24.0, help="duration, h (default 24)")
    parser.add_argument("--step", default="10 s", help="integration step of the numeric runs")
    parser.add_argument("--method", choices=("rk4", "euler"), default=None,
                        help="rk4 (default) or euler = the manual's rectangle method; the "
                             "integration error is estimated either way (not with "
                             "--orthodromic, which runs RK4)")
    for option, default, what in _EXPERIMENT_OPTIONS:
        parser.add_argument(option, default=None,
                            help=f"{what} (default {default}; not with --orthodromic)")
    parser.add_argument("--out", type=user_path, default=None, metavar="DIR",
                        help="write summary.md and the plots into this folder "
                             "(--orthodromic: orthodromic_day.md and its plots)")
    parser.add_argument("--force", action="store_true",
                        help="write into a non-empty --out folder that ins-errors did not "
                             "write (only the experiment's own files are replaced)")
    parser.add_argument("--no-progress", action="store_true",
                        help="never show progress (the status line of its runs)")
    parser.add_argument("--json", action="store_true",
                        help="print the agreement figures as JSON instead of the tables")
    parser.add_argument("--orthodromic", action="store_true",
                        help="000, task 4: every factor of the orthodromic INS over the run")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ins_errors.commands import motion_from_options
    from ins_errors.errors import DomainError, InsErrorsError
    from ins_errors.progress import stage
    from ins_errors.studies import propagation
    from ins_errors.units import parse_quantity

    # the start latitude, its errors (a pole) naming --latitude, before anything runs
    if args.latitude is None:
        args.latitude = "50deg" if args.orthodromic else "39deg"
    latitude = motion_from_options({"kind": "static", "latitude": args.latitude}).latitude
    step = parse_quantity(args.step, "s", "--step")
    duration = args.hours * 3600.0   # positive: its option type (commands.hours)
    if not step > 0:
        raise DomainError(f"--step must be positive, got {args.step!r}")
    record = 300.0 if 300.0 % step == 0 else step
    given = [o for o, _, _ in _EXPERIMENT_OPTIONS if getattr(args, o[2:]) is not None]
    if args.orthodromic and (given or args.method is not None):
        raise InsErrorsError(f"{(given or ['--method'])[0]} applies to the 001 experiment; "
                             "--orthodromic runs every factor of the orthodromic INS at "
                             "its own size, by RK4")
    args.method = args.method or "rk4"
    for option, default, _ in _EXPERIMENT_OPTIONS:
        if getattr(args, option[2:]) is None:
            setattr(args, option[2:], default)
    if args.out is not None:
        from ins_errors.output import OutputFolder, require_matplotlib

        require_matplotlib("the plots of --out")
        OutputFolder(args.out, force=args.force, create=False)  # refuse before computing
    if args.orthodromic:
        with stage("closed forms and numeric runs of every factor"):
            day = propagation.orthodromic_day(latitude, duration, step, record)
        text = day.summary_markdown()
        if args.out is not None:
            written = propagation.write_day_report(day, args.out, force=args.force)
            plots = int(day.excited().sum())  # one each (plot_day)
        if args.json:
            analytic, direct = day.agreement("analytic", "linear"), day.agreement("direct",
                                                                                 "linear")
            _print_json({"latitude_rad": day.latitude, "duration_s": day.duration,
                         "periods_s": day.periods, "gravity_m_s2": day.gravity,
                         "radius_m": day.radius,
                         "sources": [{"source": s, "excited": bool(day.excited()[j]),
                                      "analytic_vs_linear": _finite(analytic[j]),
                                      "direct_vs_linear": _finite(direct[j]),
                                      "integration_error": _finite(day.integration[j]),
                                      "second_order_only": list(day.second_order[j]),
                                      "warnings": day.warnings[j]}
                                     for j, s in enumerate(day.sources)]})
        else:
            print(text, end="")
            if args.out is not None:
                print(f"wrote {written} and {plots} plots")
        return 0
    magnitudes = {field: parse_quantity(getattr(args, option[2:]), unit, option)
                  for (option, _, _), field, unit in zip(
                      _EXPERIMENT_OPTIONS, propagation.MAGNITUDES,
                      ("rad/s", "m/s**2", "m/s", "rad", "rad", "rad"), strict=True)}
    for (option, _, what), value in zip(_EXPERIMENT_OPTIONS, magnitudes.values(),
                                        strict=True):
        if value == 0:
            raise DomainError(f"{option} is zero: every {what} source runs alone at that "
                              "size and is judged by ratios, which a zero source leaves "
                              "0/0; give a non-zero size")
    experiment = propagation.Experiment(
        latitude=latitude, **magnitudes,
        duration=duration, step=step, record_interval=record, method=args.method)
    with stage("closed forms, linear and direct runs of every source"):
        result = propagation.run(experiment)
    if args.out is not None:
        path = propagation.write_report(result, args.out, force=args.force)
        if not args.json:
            print(f"wrote {path} and {len(result.curves)} plots")
    if args.json:
        _print_json({"latitude_rad": experiment.latitude, "duration_s": duration,
                     "step_s": step, "method": args.method, "periods_s": result.periods,
                     "gravity_m_s2": result.gravity, "radius_m": result.radius,
                     "sources": [{"source": c.source, "magnitude_si": c.magnitude,
                                  **{key: _finite(propagation.finite_max(c.agreement(a, b)))
                                     for key, (a, b) in _AGREEMENTS.items()},
                                  "second_order_only": list(c.second_order),
                                  **_reduced(c.reduced_vs_full()),
                                  "integration_error": _finite(c.integration_share()),
                                  "integration_error_si": _per_quantity(c.integration_error),
                                  "warnings": c.warnings}
                                 for c in result.curves]})
    else:
        print(result.summary_markdown(), end="")
    return 0


_AGREEMENTS = {"analytic_vs_linear": ("analytic", "linear"),
               "direct_vs_linear": ("direct", "linear")}


def _reduced(comparison) -> dict:
    """JSON entries of the reduced-vs-full comparison of one source."""
    return {"reduced_vs_full": _finite(comparison.worst()),
            "reduced_vs_full_quantity": comparison.worst_quantity(),
            "not_in_reduced": list(comparison.lacking),
            "only_in_reduced": list(comparison.extra)}


def _per_quantity(errors) -> dict[str, float] | None:
    """Integration error per error quantity (SI, keyed by error state), or None."""
    from ins_errors.studies.propagation import QUANTITIES

    if errors is None:
        return None
    return {q[0]: float(e) for q, e in zip(QUANTITIES, errors, strict=True)}


def _finite(value) -> float | None:
    value = float(value)
    return value if np.isfinite(value) else None


def _print_json(data) -> None:
    emit(data)
