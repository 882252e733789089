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


def _latitude_setting(args: argparse.Namespace, modes) -> tuple[str | None, float] | None:
    """Where the base's latitude comes from: (None, φ) for ``--latitude``, (parameter
    name, φ) for a model whose latitude is a parameter (``-p phi0=...``: its
    :attr:`~ins_errors.analysis.modes.StaticModes.latitude_source`); None for a model
    without one. φ in rad."""
    if modes.latitude is not None:
        return None, float(modes.latitude)
    source = modes.latitude_source or ""
    if source.startswith("parameter ") and modes.references.latitude is not None:
        return source.removeprefix("parameter "), float(modes.references.latitude)
    return None


def _moved(args: argparse.Namespace, parameter: str | None, text: str
           ) -> tuple[argparse.Namespace, str]:
    """The options with the latitude set to ``text`` (``--latitude``, or the latitude
    parameter's ``-p NAME=`` item replaced or added), and that setting as typed."""
    if parameter is None:
        return argparse.Namespace(**{**vars(args), "latitude": text}), f"--latitude {text}"
    items = [item for item in args.parameter if item.partition("=")[0].strip() != parameter]
    setting = f"{parameter}={text}"
    return (argparse.Namespace(**{**vars(args), "parameter": [*items, setting]}),
            f"-p {setting}")


def _nearby(args: argparse.Namespace, refusal: UnresolvedPairError) -> str:
    """The advice after a refused pair: the nearest latitude of :data:`NEARBY_DEGREES`
    (either side, short of a pole) at which the same pair is resolved, or that none is
    (or that the model has no latitude to move). The latitude moved is the base's
    (``--latitude``) or, for a model whose latitude is a parameter, that parameter's
    (``-p phi0=...``)."""
    from ins_errors.analysis.transfer import transfer_at_base
    from ins_errors.commands.modes import static_modes_from_options
    from ins_errors.errors import InsErrorsError

    setting = _latitude_setting(args, static_modes_from_options(args)[2])
    if setting is None:
        return "the model has no latitude to move (neither the base's nor a parameter)"
    parameter, latitude = setting
    for step in NEARBY_DEGREES:
        for sign in (1, -1):
            degrees = float(np.degrees(latitude)) + sign * step
            if abs(degrees) >= 90.0:
                continue
            moved, typed = _moved(args, parameter, f"{degrees:.10g}deg")
            try:
                model, _, modes = static_modes_from_options(moved)
                transfer_at_base(model, modes, [refusal.source], [refusal.output])
            except InsErrorsError:  # refused there too, or no base there
                continue
            return f"the same pair is resolved at {typed}"
    where = "this latitude" if parameter is None else f"this {parameter}"
    return f"nor is it within {NEARBY_DEGREES[-1]:g}° of {where} on either side"


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
