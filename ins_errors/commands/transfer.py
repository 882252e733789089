"""``ins-errors transfer MODEL --source NAME``: transfer functions at a static base.

Example::

    ins-errors transfer examples/own_model/schuler_loop.py --source accel_bias
    ins-errors transfer north_pointing --source gyro_drift_east --output latitude --json

The static base is that of ``ins-errors modes`` (same options, same defaults); for each
source and output W(s) = h (sI − F)⁻¹ g is reduced to what the pair sees, factored, its
poles named as ``modes`` names them, and the long run of the response to a constant
source (an initial error) said in words (:mod:`ins_errors.analysis.transfer` computes,
:mod:`ins_errors.analysis.transfer_text` writes).
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ins_errors.analysis.transfer import UnresolvedPairError

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


NEARBY_DEGREES = (0.01, 0.1, 1.0)
"""How far from a refused base's latitude, degrees, the command looks for one that
resolves the pair (each on both sides, nearest first)."""


def _nearby(args: argparse.Namespace, refusal: UnresolvedPairError) -> str:
    """The advice after a refused pair: the nearest latitude of :data:`NEARBY_DEGREES`
    (either side, short of a pole) at which the same pair is resolved, or that none is
    (or that the base has no latitude to move)."""
    from ins_errors.analysis.transfer import transfer_at_base
    from ins_errors.commands.modes import static_modes_from_options
    from ins_errors.errors import InsErrorsError

    latitude = static_modes_from_options(args)[2].latitude
    if latitude is None:
        return "the base has no latitude to move"
    for step in NEARBY_DEGREES:
        for sign in (1, -1):
            degrees = float(np.degrees(latitude)) + sign * step
            if abs(degrees) >= 90.0:
                continue
            text = f"{degrees:.10g}deg"
            moved = argparse.Namespace(**{**vars(args), "latitude": text})
            try:
                model, _, modes = static_modes_from_options(moved)
                transfer_at_base(model, modes, [refusal.source], [refusal.output])
            except InsErrorsError:  # refused there too, or no base there
                continue
            return f"the same pair is resolved at --latitude {text}"
    return f"nor is it within {NEARBY_DEGREES[-1]:g}° of this latitude on either side"


def run(args: argparse.Namespace) -> int:
    from ins_errors.analysis.transfer import UnresolvedPairError, transfer_at_base
    from ins_errors.analysis.transfer_text import report_text
    from ins_errors.commands.modes import static_modes_from_options
    from ins_errors.errors import DomainError
    from ins_errors.model_parameters import parameters_record

    if args.plot:
        from ins_errors.output import check_figure, require_matplotlib

        require_matplotlib("--plot")
        check_figure(args.plot)
    model, parameters, modes = static_modes_from_options(args)
    names, sizes = _sources(model, args.source)
    try:
        result = transfer_at_base(model, modes, names, args.output, sizes)
    except UnresolvedPairError as refusal:
        raise DomainError(f"{refusal}; {_nearby(args, refusal)}") from None
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
    print(report_text(result))
    if written is not None:
        print(f"\nplot written to {written}")
    return 0
