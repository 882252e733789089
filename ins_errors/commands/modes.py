"""``ins-errors modes MODEL``: the static-base modes of a model's error equations.

Example::

    ins-errors modes strapdown_ned --latitude 45deg
    ins-errors modes strapdown_ned -p k_h1=0.0293/s -p k_h2=4.42e-4/s^2 --json

The static base is built as ``ins-errors compare MODEL --motion static`` builds it (same
options, same defaults); F is evaluated there and its eigenvalues named (Schuler,
Foucault split, Earth, vertical channel, integrators, ...) against the textbook values
of the model's own g, R and Ω (:mod:`ins_errors.analysis.modes`).
"""

from __future__ import annotations

import argparse

from ins_errors.json_output import emit
from ins_errors.time_text import duration_text

FORMULAS = {
    "Schuler − Foucault": "2π/(ω̄ − Ω|sin φ|), ω̄ = √(g/R + Ω² sin² φ)",
    "Schuler + Foucault": "2π/(ω̄ + Ω|sin φ|)",
    "Schuler": "2π√(R/g)",
    "Earth": "2π/Ω (the sidereal day, 23.93 h: a turn against the stars, not the 24-h "
             "solar day)",
    "vertical channel (growing)": "e-folding time √(R/2g)",
    "vertical channel (decaying)": "time constant √(R/2g)",
}
"""The textbook formula of each named mode (by its name without the word on its
damping), for the notes under the table."""

NATURAL_FORMULAS = {
    "Schuler − Foucault": "natural period 2π/(ω̄_ζ − Ω_ζ)",
    "Schuler + Foucault": "natural period 2π/(ω̄_ζ + Ω_ζ)",
    "Schuler": "natural period 2π√(R/g)",
    "Earth": "natural period 2π/Ω",
}
"""The same for a damped or growing row: its natural period 2π/|λ| is compared (a damping
gain leaves the loop's natural frequency alone; the damped Foucault pair:
:meth:`~ins_errors.analysis.mode_references.References.split`)."""

DAMPED_SPLIT = ("Ω_ζ = Ω|sin φ|/√(1 − ζ²), ω̄_ζ = √(g/R + Ω_ζ²), ζ the row's damping ratio "
                "(ζ = 0: the undamped pair)")
"""What the damped Foucault pair's formulas write, said after the first of them."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "modes", help="static-base modes of the error equations: Schuler, Earth, vertical",
        description="Build the static base as 'compare --motion static' does, evaluate F "
                    "there and list its eigenvalues as modes: Schuler (split by the "
                    "Foucault coupling), Earth rate, vertical channel, integrators, damped "
                    "and growing modes, each with its period or time constant, the "
                    "textbook value from the model's own g, R and Ω, and the error states "
                    "that take part.")
    parser.add_argument("model", help="model name (e.g. strapdown_ned) or model file (my_ins.py)")
    add_static_base_options(parser)
    parser.add_argument("--json", action="store_true", help="machine-readable output (SI)")
    parser.set_defaults(func=run)


def add_static_base_options(parser: argparse.ArgumentParser) -> None:
    """The options of the static base (``--latitude``, ``--longitude``, ``--heading``,
    ``--height``, ``--parameter``/``-p``), as ``modes`` takes them; read them with
    :func:`static_modes_from_options`."""
    parser.add_argument("--latitude", default=None,
                        help="latitude of the base (default 50deg; refused for a model "
                             "without a latitude, naming its own setting, e.g. -p phi0=...)")
    parser.add_argument("--longitude", default=None,
                        help="longitude of the base (default 30deg; for a model with one)")
    parser.add_argument("--heading", default=None,
                        help="track angle of the model's trihedron (a strapdown body's "
                             "heading; default 0deg), for models with a heading output")
    parser.add_argument("--height", default=None,
                        help="height of the base (default 0m; for a model with one)")
    parser.add_argument("--parameter", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="model parameter with unit, as for 'ins-errors compare', e.g. "
                             "strapdown_ned's k_h1=0.0293/s (repeatable)")


def _eigenvalue(value: complex) -> str:
    if value == 0:
        return "0"
    if not value.imag:
        return f"{value.real:+.4e}"
    real = f"{value.real:.3e} " if value.real else ""
    return f"{real}±{value.imag:.4e}i"


def _times(mode) -> str:
    if mode.kind == "integrator":
        return "–"
    if mode.period_s is None:
        word = "e-folding" if mode.eigenvalue.real > 0 else "time constant"
        doubling = (f" (doubling {duration_text(mode.doubling_time_s)})"
                    if mode.doubling_time_s else "")
        return f"{word} {duration_text(mode.time_constant_s)}{doubling}"
    text = f"period {duration_text(mode.period_s)}"
    if mode.natural_period_s is not None:
        text += f" (natural {duration_text(mode.natural_period_s)})"
    if mode.time_constant_s is not None:
        word = "e-folding" if mode.eigenvalue.real > 0 else "decay"
        text += f", ζ = {mode.damping_ratio:.3g}, {word} {duration_text(mode.time_constant_s)}"
    return text


def _percent(ratio: float) -> str:
    """A relative difference in %, three decimals; rounding noise shown as 0."""
    return "0.000 %" if abs(ratio) < 5e-6 else f"{100 * ratio:+.3f} %"


def _count(mode) -> str:
    if mode.independent_directions is not None and (mode.independent_directions
                                                     < mode.multiplicity):
        return f"{mode.multiplicity} ({mode.independent_directions} directions)"
    return str(mode.multiplicity)


def _rows(modes, reference: bool) -> list[str]:
    """A Markdown table of ``modes`` (with the textbook columns where ``reference``)."""
    head = "| mode | λ (1/s) | × | period or time | textbook | off by | error states |"
    rule = "|---|---|---:|---|---:|---:|---|"
    if not reference:
        head = head.replace(" textbook | off by |", "")
        rule = rule.replace("---:|---:|", "", 1)
    lines = [head, rule]
    for mode in modes:
        ref = mode.reference
        textbook = "–" if ref is None else duration_text(ref.seconds)
        off = "–" if ref is None else _percent(ref.relative_difference)
        if mode.note:
            off += " (see note)"
        states = ", ".join(f"{name} {share:.2f}" for name, share in mode.states())
        middle = f" {textbook} | {off} |" if reference else ""
        lines.append(f"| {mode.name} | {_eigenvalue(mode.eigenvalue)} | {_count(mode)} | "
                     f"{_times(mode)} |{middle} {states} |")
    return lines


def table(result) -> str:
    """The modes as a Markdown table with its notes."""
    lines = _rows(result.modes, True)
    from ins_errors.analysis.modes import UNREAD_WORDS, UNSEEN_WORDS

    for words, reached in ((UNREAD_WORDS, True), (UNSEEN_WORDS, False)):
        group = [m for m in result.unseen_modes if m.reached == reached]
        if group:
            lines += ["", f"Modes {words}:", "", *_rows(group, False)]
    refs = result.references
    known = [f"{label} = {value} ({c.source})" for label, c, value in (
        ("g", refs.g, refs.g and f"{refs.g.value:.6g} m/s²"),
        ("R", refs.R, refs.R and f"{refs.R.value / 1000:.6g} km"),
        ("Ω", refs.Omega, refs.Omega and f"{refs.Omega.value:.7g} rad/s")) if c is not None]
    missing = [label for label, c in (("g", refs.g), ("R", refs.R), ("Ω", refs.Omega))
               if c is None]
    notes = ["", "textbook values from " + ("; ".join(known) if known else "nothing")
             + (f"; the model has no {', '.join(missing)}, so the modes that need "
                f"{'it' if len(missing) == 1 else 'them'} are named by kind only"
                if missing else "")]
    if result.latitude_source not in (None, "base"):
        from ins_errors.numeric.trajectories import latitude_text

        notes.append(f"the model has no latitude: the Foucault split Ω|sin φ| is taken at "
                     f"φ = {latitude_text(refs.latitude)}° ({result.latitude_source})")
    elif refs.latitude is None and refs.Omega is not None:
        notes.append("the model has no latitude (and no latitude parameter): no Foucault "
                     "split is named")
    formulas = _formulas(result)
    if formulas:
        notes.append("formulas: " + "; ".join(f"{name}: {text}" for name, text in formulas))
    if result.foucault_period_s is not None:
        notes.append(_foucault_note(result))
    if result.turning is not None:
        notes.append(_turning_note(result))
    notes += [note for note in (_diverging_schuler_note(result), _earth_rate_note(result))
              if note]
    explained: dict[str, list[str]] = {}
    for mode in result.modes:
        if mode.note:
            explained.setdefault(mode.note, []).append(mode.name)
    notes += [f"note on {', '.join(dict.fromkeys(names))} (from the model): {text}"
              for text, names in explained.items()]
    if any(m.independent_directions is not None and m.independent_directions < m.multiplicity
           for m in result.modes):
        notes.append("integrators: fewer independent directions than zero eigenvalues is a "
                     "Jordan chain of F (an error that grows in proportion to time)")
    if refs.g is not None and refs.R is not None:
        measure = (f"in the units of the Schuler loop (angles in rad, dimensionless states "
                   f"as angles, lengths over R, longitudes times the cosine of their "
                   f"latitude (as distances over R), velocities over √(gR) = "
                   f"{(refs.g.value * refs.R.value) ** 0.5 / 1000:.3g} km/s)")
    else:
        measure = "in " + ", ".join(sorted(set(result.scales.values())))
    notes.append("error states: each state's size in the mode relative to the largest, "
                 f"{measure}; below 10 % left out (--json lists all)")
    return "\n".join(lines + notes)


def _formulas(result) -> list[tuple[str, str]]:
    """(row name, textbook formula) of each named row, once per name, in the order of
    :data:`FORMULAS`; a row compared by its natural period gets :data:`NATURAL_FORMULAS`."""
    out: dict[str, str] = {}
    defined = False
    for base in FORMULAS:
        for mode in result.modes:
            if mode.base_name != base or mode.reference is None or mode.name in out:
                continue
            if mode.reference.quantity != "natural_period":
                out[mode.name] = FORMULAS[base]
                continue
            out[mode.name] = NATURAL_FORMULAS[base]
            if "Ω_ζ" in out[mode.name] and not defined:
                out[mode.name] += f", {DAMPED_SPLIT}"
                defined = True
    return list(out.items())


EARTH_RATE = 7.292115e-5
"""The Earth's rate against the stars, rad/s (a model's Ω far from it is named)."""


def _earth_rate_note(result) -> str | None:
    """A note where the model's Ω is far from the Earth's (a factor 2 or more): a planet
    of its own, or a unit slip (15.041 deg/h written as rad/s is 206 265 times it)."""
    omega = result.references.Omega
    if omega is None or not omega.value or 0.5 < abs(omega.value) / EARTH_RATE < 2:
        return None
    ratio = abs(omega.value) / EARTH_RATE
    slip = ("; 15.041 in deg/h is the Earth's rate: a deg/h value given as rad/s?"
            if abs(ratio / 206264.8 - 1) < 0.01 else "")
    return (f"Ω = {omega.value:.6g} rad/s is {ratio:.4g} times the Earth's rate "
            f"{EARTH_RATE} rad/s ({omega.source}){slip}")


def _diverging_schuler_note(result) -> str | None:
    """Where no row is named Schuler but a real root grows at about √(g/R): the
    horizontal loop diverges where it should oscillate, the sign of gravity in its
    equations flipped (an ENU model's up taken for NED's down, or the reverse)."""
    from ins_errors.analysis.modes import BAND

    rate = result.references.schuler
    if rate is None or any(m.base_name == "Schuler" for m in result.modes):
        return None
    for mode in result.modes:
        value = mode.eigenvalue
        if value.real > 0 and abs(value.imag) < 1e-3 * value.real and \
                1 / BAND < value.real / rate < BAND:
            return (f"no Schuler row, but a real mode grows at {value.real:.4e} 1/s, about "
                    f"√(g/R) = {rate:.4e} rad/s (e-folding {duration_text(1 / value.real)}): "
                    "the horizontal loop diverges where it should oscillate, as it does "
                    "when gravity has the wrong sign in the velocity equations (an ENU "
                    "model's up taken for NED's down, or the reverse); check the sign of g "
                    "there")
    return None


def _turning_note(result) -> str:
    """What the modes of an F that turns at rest describe, and what they do not."""
    period = duration_text(result.turning.period_s)
    return (f"F changes at rest: {result.turning.words()}; these are the modes of F "
            f"frozen at the base's start: they describe the error states over times short "
            f"against {period}. Beyond, the turning modulates what the outputs show (a "
            f"Schuler oscillation read through an angle turning at that rate is split by "
            f"it, as Schuler ± Foucault in the latitude, longitude and heading of a "
            f"free-azimuth INS): fly the base (ins-errors compare {result.model} ... "
            f"--hours N) for the long run")


def _foucault_note(result) -> str:
    """The Foucault period under the table, and what it is in this model's modes: the
    turning of the Schuler oscillation's plane where a Foucault-split pair is named (with
    the period from that pair, damped or not), else what the Schuler rows are instead
    (none, one, two split by another amount or damped differently, more), with the
    model's note where it has one: facts of these modes only, no guessed cause."""
    from ins_errors.analysis.modes import BAND, FOUCAULT_MATCH, NAMED_DAMPING
    from ins_errors.numeric.closed_forms import SPLIT_MODES
    from ins_errors.numeric.trajectories import latitude_text

    refs = result.references
    head = (f"Foucault period 2π/(Ω|sin φ|) = {duration_text(result.foucault_period_s)} at "
            f"φ = {latitude_text(refs.latitude)}°")
    measured = result.foucault_period_from_modes_s
    if measured is not None:
        damped = any(m.time_constant_s is not None for m in result.modes
                     if m.base_name in SPLIT_MODES)
        return (f"{head}: the plane of the Schuler oscillation turns once in it; from the "
                f"split pair, 2π/((ω₊ − ω₋)/2) = {duration_text(measured)}"
                + (" (ω± = Im λ: damped, the pair's half difference is still the turning "
                   "rate)" if damped else ""))
    rows = [m for m in result.modes if m.base_name == "Schuler"]
    pairs = [m for m in rows for _ in range(m.multiplicity)]
    words = {m.name.removeprefix(m.base_name) for m in rows}
    if not rows and refs.schuler is None:
        found = "no row here is named Schuler (the model lacks g or R)"
    elif not rows:
        found = (f"no row here is named Schuler: no oscillation has |λ| within a factor "
                 f"{BAND:g} of √(g/R) = {refs.schuler:.4e} rad/s with |ζ| < "
                 f"{NAMED_DAMPING:g}")
    elif len(pairs) == 2 and len(words) == 2:
        found = (f"the two Schuler rows here are damped differently (ζ = "
                 f"{rows[0].damping_ratio:.3g}, {rows[1].damping_ratio:.3g})")
    elif len(pairs) == 2:
        half = abs(pairs[1].eigenvalue.imag - pairs[0].eigenvalue.imag) / 2
        found = (f"no two Schuler rows here differ by Ω|sin φ| (within "
                 f"{100 * FOUCAULT_MATCH:g} %): half the difference of their Im λ is "
                 f"{half:.4g} rad/s, Ω|sin φ| = {refs.foucault:.4g} rad/s")
    elif len(pairs) == 1:
        found = "one Schuler row here, and no second one to pair it with"
    else:
        found = f"{len(pairs)} Schuler pairs here, not two"
    noted = any(m.note for m in rows)
    return (f"{head}, the time in which the meridian turns once about the vertical against "
            f"inertial space; {found}, so no Schuler ± Foucault pair is named: the turning "
            "is not resolved as a pair in these modes"
            + ("; see the model's note" if noted else ""))


def static_modes_from_options(args: argparse.Namespace):
    """The model, the parameters set and the static-base modes the options of
    :func:`add_static_base_options` (and ``args.model``) describe.

    Returns
    -------
    tuple of (Model, dict of str to float, StaticModes)
        The loaded model, the parameters set (name -> SI value) and
        :func:`~ins_errors.analysis.modes.modes_at_rest` of the base, whose ``point``
        holds the state, inputs, parameters and initial conditions at rest.

    Raises
    ------
    InsErrorsError
        An unknown model or parameter, a bad value of an option, a latitude at a pole,
        an option the model has no use for (one line naming it).
    """
    from ins_errors.analysis.modes import modes_at_rest
    from ins_errors.commands import motion_from_options
    from ins_errors.commands.compare import given_references
    from ins_errors.model_parameters import parse_parameter_options
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import refuse_unused_heading

    model = load_model(args.model)
    parameters = parse_parameter_options(model, args.parameter)
    profile = motion_from_options({"kind": "static", "latitude": args.latitude,
                                   "longitude": args.longitude, "heading": args.heading,
                                   "height": args.height})
    if args.heading is not None:
        refuse_unused_heading(model, profile)
    return model, parameters, modes_at_rest(model, profile, parameters,
                                            given=given_references(args))


def run(args: argparse.Namespace) -> int:
    from ins_errors.model_parameters import parameters_record

    model, parameters, result = static_modes_from_options(args)
    if args.json:
        emit({**result.to_dict(), "parameters": parameters_record(model, parameters)})
        return 0
    print(f"### {model.name}: modes of the error equations, {result.base}\n")
    print(table(result))
    return 0
