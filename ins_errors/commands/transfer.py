"""``ins-errors transfer MODEL --source NAME``: transfer functions at a static base.

Example::

    ins-errors transfer examples/own_model/schuler_loop.py --source accel_bias
    ins-errors transfer north_pointing --source gyro_drift_east --output latitude --json

The static base is that of ``ins-errors modes`` (same options, same defaults); for each
source and output W(s) = h (sI − F)⁻¹ g is reduced to what the pair sees, factored, its
poles named as ``modes`` names them, and the long run of the response to a constant
source (an initial error) said in words (:mod:`ins_errors.analysis.transfer`).
"""

from __future__ import annotations

import argparse
import sys

from ins_errors.commands.modes import add_static_base_options
from ins_errors.json_output import emit
from ins_errors.user_paths import expand_user


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "transfer", help="transfer functions W(s) of error sources to outputs, static base",
        description="Build the static base as 'modes' does and give, for each error source "
                    "and output, W(s) = h (sI − F)⁻¹ g (g: the source's column of G, or of "
                    "the initial-error map for an initial error) with the modes the pair "
                    "does not see cancelled, in factored form: its gain in the output's "
                    "display unit per the source's, its zeros and its poles named "
                    "(Schuler, Foucault, Earth, vertical channel, integrator) with their "
                    "periods, and how the response to a constant source (an initial "
                    "error) behaves in the long run: the power of t it grows with, or the "
                    "value it oscillates about. A constant source of size b gives "
                    "Y(s) = b·W(s)/s, an initial error Y(s) = b·W(s).")
    parser.add_argument("model", help="model name (e.g. strapdown_ned) or model file (my_ins.py)")
    parser.add_argument("--source", "-s", action="append", default=[], metavar="NAME[=VALUE]",
                        help="error source (repeatable, at least one); with =VALUE (and "
                             "its unit) the size the long-run values are given for "
                             "(default: one of its display unit, e.g. 1 ug)")
    parser.add_argument("--output", action="append", default=None, metavar="NAME",
                        help="output, or an error state read directly (e.g. a tilt; "
                             "repeatable; default: every output of the model)")
    add_static_base_options(parser)
    parser.add_argument("--plot", type=expand_user, metavar="FILE",
                        help="write the Bode plot (magnitude and phase of each pair over the "
                             "band of the modes) to FILE (png, pdf, svg)")
    parser.add_argument("--json", action="store_true", help="machine-readable output (SI)")
    parser.set_defaults(func=run)


def _sources(model, items: list[str]) -> tuple[list[str], dict[str, float]]:
    """The source names and the sizes given with ``=VALUE`` (SI)."""
    from ins_errors.analysis.validity import source_example
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import check_source, name_value_pairs
    from ins_errors.units import parse_quantity

    if not items:
        example = source_example(model).split("=")[0]
        raise InsErrorsError(f"give at least one --source NAME, e.g. --source {example}")
    given = name_value_pairs(items, "--source", f"--source {source_example(model)}",
                             optional=True)
    sizes: dict[str, float] = {}
    for name, text in given.items():
        info = model.source(name)  # an unknown name: one line with suggestions
        if text is not None:
            sizes[name] = check_source(info, parse_quantity(text, info.unit, name), text)
    return list(given), sizes


def _times(factor) -> str:
    if factor.value == 0:
        return "–"
    if factor.period_s is not None:
        text = f"period {_duration(factor.period_s)}"
        if factor.time_constant_s is not None:
            word = "e-folding" if factor.value.real > 0 else "decay"
            text += f", {word} {_duration(factor.time_constant_s)}"
        return text
    word = "e-folding" if factor.value.real > 0 else "time constant"
    return f"{word} {_duration(factor.time_constant_s)}"


def _duration(seconds: float) -> str:
    from ins_errors.time_text import duration_text

    return duration_text(seconds)


def _cancelled(pair) -> str:
    if not pair.cancelled:
        return "none cancelled"
    names = ", ".join(f"{f.name}" + (f" ×{f.multiplicity}" if f.multiplicity > 1 else "")
                      for f in pair.cancelled)
    return f"cancelled: {names}"


def pair_text(pair) -> str:
    """One pair's section: heading, factored W, its pole factors, the long run."""
    from ins_errors.analysis.transfer import CHECK_LIMIT, TOLERANCE, long_run_text

    head = f"#### {pair.source} → {pair.output}"
    if pair.is_zero and pair.negligible:
        return (f"{head}\n\nW(s) ≈ 0: {pair.source} reaches {pair.output} only below "
                f"{TOLERANCE:g} of the size the norms of F, g and h allow (a coupling "
                f"weaker than the reductions' tolerance; every mode cancelled)")
    if pair.is_zero:
        return (f"{head}\n\nW(s) = 0: {pair.source} does not reach {pair.output} (its "
                f"Markov parameters h Fᵏ g, k < {pair.full_order}, are zero to rounding; "
                f"every mode cancelled)")
    lines = [f"{head}: order {pair.order} of {pair.full_order} ({_cancelled(pair)})", "",
             pair.factored_text(), "",
             "| pole factor | mode | period or time |", "|---|---|---|"]
    lines += [f"| {f.text(pair.digits)} | {f.name} | {_times(f)} |" for f in pair.poles]
    lines += ["", f"long run: {long_run_text(pair)}"]
    if pair.check_error > CHECK_LIMIT:
        lines.append(f"(the factored form differs from h (iωI − F)⁻¹ g of the whole F by "
                     f"{pair.check_error:.1e} of its size within the band: the reduction's "
                     f"tolerance cut a weak coupling)")
    return "\n".join(lines)


def text(result) -> str:
    """The whole report: convention, every pair, the notes."""
    from ins_errors.analysis.transfer import CANCEL, CHECK_LIMIT, CONVENTION, TOLERANCE

    parts = [f"convention: {CONVENTION}"]
    parts += [pair_text(pair) for pair in result.pairs]
    parts.append(
        "gains in the output's display unit per the source's display unit, per second to "
        "the power the form's degrees leave (s in 1/s); the poles are F's eigenvalues "
        "named as 'ins-errors modes' names them; a mode of F the pair does not reach or "
        f"see is cancelled (Krylov bases on the states in the units of the Schuler loop, "
        f"tolerance {TOLERANCE:g} of F's norm, finer or on balanced states where the "
        f"factored form is not within {CHECK_LIMIT:g} of h (iωI − F)⁻¹ g; a zero within "
        f"{CANCEL:g} of a pole's size cancels it)")
    return "\n\n".join(parts)


def run(args: argparse.Namespace) -> int:
    from ins_errors.analysis.transfer import transfer_at_base
    from ins_errors.commands.modes import static_modes_from_options
    from ins_errors.model_parameters import parameters_record

    if args.plot:
        from ins_errors.output import check_figure, require_matplotlib

        require_matplotlib("--plot")
        check_figure(args.plot)
    model, parameters, modes = static_modes_from_options(args)
    names, sizes = _sources(model, args.source)
    result = transfer_at_base(model, modes, names, args.output, sizes)
    written = None
    if args.plot:
        from ins_errors.analysis.transfer_plot import plot_bode

        written = plot_bode(result, args.plot)
    if args.json:
        emit({**result.to_dict(), "parameters": parameters_record(model, parameters)})
        if written is not None:  # beside the JSON, not inside it
            print(f"plot written to {written}", file=sys.stderr)
        return 0
    print(f"### {model.name}: transfer functions, {result.modes.base}\n")
    print(text(result))
    if written is not None:
        print(f"\nplot written to {written}")
    return 0
