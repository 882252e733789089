"""Terminal, Markdown and JSON forms of a :class:`~ins_errors.checker.matrix.MatrixReport`.

A propagated difference at or below its rounding floor
(:func:`~ins_errors.checker.matrix.rounding_floor`) is written as ``< floor`` and "no
effect above rounding", naming no initial error, source or motion: which one reaches the
largest rounding difference changes with the last bits of the arithmetic. A difference
that follows a growing mode past :data:`~ins_errors.checker.growth.GROWTH_SHOWN`
e-foldings is said to grow exponentially, with the mode's e-folding time, instead of a
figure like 1e48 m (:func:`~ins_errors.checker.growth.growth_text`, the equation
checker's words).
"""

from __future__ import annotations

import math

from ins_errors.checker.extreme import first_largest_item
from ins_errors.checker.growth import growth_text
from ins_errors.checker.kinds import DECLARED, SMALL_MISTAKE
from ins_errors.checker.matrix import ARCSEC, Effect, EntryFinding, MatrixReport
from ins_errors.checker.up_states import as_written, written_text
from ins_errors.markdown_cells import one_line, table_cell

NO_EFFECT = "no effect above rounding"
"""What the report says for a difference at or below its rounding floor."""


def _hours(seconds: float) -> str:
    return f"{seconds / 3600:.3g} h"


def _where(f: EntryFinding) -> str:
    others = ", ".join(f"{k} {v:.2g}" for k, v in f.per_motion.items())
    return f"largest on {f.motion} at t = {_hours(f.time)} (per motion: {others})"


def below(floor: float, unit: str) -> str:
    """``< floor`` rounded up to one significant digit (``< 3e-11 m``, ``< 2e-09″``)."""
    sep = "" if unit == "″" else " "
    if not floor > 0:
        return f"0{sep}{unit}"
    digit = 10.0 ** math.floor(math.log10(floor))
    return f"< {math.ceil(floor / digit * (1 - 1e-9)) * digit:.0e}{sep}{unit}"


NOT_READ = "{} n/a"
"""What the report says for a figure the hand's states do not hold (a position
difference of a model without position states: not measured, so no figure)."""

NOT_ASSESSED = "effect not assessed: the vertical channel is held"
"""What the report says for a finding of a horizontal row in a vertical-channel column."""


def length_text(metres: float) -> str:
    """``"28.3 km"``, ``"354 m"``: a length in m or km, three significant digits."""
    return f"{metres / 1000:.3g} km" if abs(metres) >= 1000 else f"{metres:.3g} m"


def vertical_text(r: MatrixReport, f: EntryFinding) -> str:
    """The effect of a vertical-channel finding on the height error
    (:class:`~ins_errors.checker.matrix.VerticalEffect`), ``NOT_ASSESSED`` for a
    horizontal row's vertical column, '' otherwise."""
    e = r.vertical_effects.get(f.entry)
    if e is None:
        return (NOT_ASSESSED if r.effects and f.column in r.vertical and f.block is None
                else "")
    parts = []
    for n, hours in enumerate(e.hours):
        if e.exponential[n]:
            parts.append(f"{hours:g} h: {growth_text(e.e_folding, e.growing_mode)}")
        elif e.motion[n] is None:
            parts.append(f"{hours:g} h: {NO_EFFECT} ({below(e.floor[n], 'm')})")
        else:
            own = e.derived[n] if n < len(e.derived) else None
            of = (f"; {_share(e.height[n] / own)} of the derived model's own "
                  f"{length_text(own)}" if own else "")
            parts.append(f"{hours:g} h: {length_text(e.height[n])} ({e.case[n]}, "
                         f"{e.motion[n]}{of})")
    return (("the pair together: " if f.pair is not None else "")
            + "height error, vertical channel not held: " + "; ".join(parts))


def _alone(r: MatrixReport, f: EntryFinding) -> str:
    """The effect of this difference alone (a mirror pair's: both entries) after 24 h,
    or ''."""
    vertical = vertical_text(r, f)
    if vertical:
        return vertical
    if f.entry not in r.finding_effects:
        return ""
    e = r.finding_effects[f.entry]
    if e.not_assessed:
        return e.not_assessed
    alone = "the pair together after 24 h" if f.pair is not None else "alone after 24 h"
    if e.exponential:
        return (f"{alone}: {growth_text(e.e_folding, e.growing_mode)} "
                f"(fastest on {e.motion})")
    attitude = (NOT_READ.format("attitude") if e.attitude is None
                else f"{e.attitude / ARCSEC:.3g}″" if e.attitude_above_rounding
                else below(e.attitude_floor / ARCSEC, "″"))
    if e.position is None:
        if e.attitude is None or e.attitude_above_rounding:
            where = f" (largest on {e.motion})" if e.motion else ""
            return f"{alone}: {NOT_READ.format('position')}, {attitude}{where}"
        return (f"{alone}: {NOT_READ.format('position')}, attitude {NO_EFFECT} "
                f"({attitude})")
    if not e.position_above_rounding:
        if not e.attitude_above_rounding:
            return (f"{alone}: {NO_EFFECT} "
                    f"({below(e.position_floor, 'm')}, {attitude})")
        return (f"{alone}: position {NO_EFFECT} "
                f"({below(e.position_floor, 'm')}), {attitude}")
    return f"{alone}: {e.position:.3g} m, {attitude} (largest on {e.motion})"


ROUNDING = 1e-12
"""An entry whose term (value × typical size) is at most this share of its row's largest
term at the sample shown is rounding, printed as ``0 (rounding)`` (a derived entry of
2.7e-23 beside terms of 1e-8: the last bits of a sum that is 0)."""


def entry_value(f: EntryFinding, value: float) -> str:
    """One of a finding's two entries (``f.hand`` or ``f.model``) as the reports print
    it: ``-5.99523e-05``, or ``0 (rounding)`` when its term is at most :data:`ROUNDING`
    of the row's largest term at that sample (the sample's |hand − model| × size over
    the finding's size gives that term's scale)."""
    difference = abs(f.hand - f.model)
    if value != 0 and difference > 0 and abs(value) * f.size / difference <= ROUNDING:
        return "0 (rounding)"
    return f"{value + 0.0:.6g}"


def _finding_line(r: MatrixReport, f: EntryFinding) -> str:
    detail = f"; {f.detail}" if f.detail else ""
    alone = _alone(r, f)
    return (f"{f.entry}{as_written(f.matrix, f.row, f.column, r.written)}: {f.kind}, "
            f"size {f.size:.2g} of the row's largest term "
            f"({size_words(r, f)}); hand {entry_value(f, f.hand)}, model "
            f"{entry_value(f, f.model)} "
            f"(Δ term {f.absolute:.2g} {f.unit}){detail}; {_where(f)}"
            + (f"; {alone}" if alone else ""))


def size_words(r: MatrixReport, f: EntryFinding) -> str:
    """The size class of a finding in words: ``major``, ``significant``, ``small`` (a
    dropped small term), and for a mistake below the threshold ``small, below the
    threshold 0.001: still a mistake, the term is there but wrong`` (a term there but
    wrong is a mistake whatever its size: the word "small" alone would contradict the
    heading it is listed under)."""
    if f.severity == SMALL_MISTAKE:
        return (f"small, below the threshold {r.threshold:g}: still a mistake, the term is "
                "there but wrong")
    return f.size_class


def _small_mistakes(r: MatrixReport) -> str:
    """``" (2 of them below the threshold 0.001: ...)"`` after the count of mistakes, ``""``
    when none is below the threshold."""
    n = sum(1 for f in r.mistakes if f.severity == SMALL_MISTAKE)
    if not n:
        return ""
    return (f" ({n} of them below the threshold {r.threshold:g}: a term there but wrong "
            "is a mistake whatever its size; only a small term left out is a dropped small "
            "term)")


def _summary(r: MatrixReport) -> str:
    declared = len(declared_drops(r))
    vertical = len(r.without_vertical)
    dropped = len(r.findings) - len(r.mistakes) - declared - vertical
    return (f"{r.compared} entries compared: {r.compared - len(r.findings)} agree, "
            + (f"{declared} declared drop{'s' * (declared != 1)}, " if declared
               or r.declarations else "")
            + (f"{vertical} coupling{'s' * (vertical != 1)} to the vertical channel "
               "the hand leaves out, " if vertical else "")
            + f"{dropped} dropped small term{'s' * (dropped != 1)}, "
            f"{len(r.mistakes)} mistake{'s' * (len(r.mistakes) != 1)}{_small_mistakes(r)}")


def without_vertical_text(r: MatrixReport) -> str:
    """What a horizontal-only hand model's couplings to the vertical channel mean (one
    paragraph), '' for any other hand."""
    found = sorted(r.without_vertical, key=lambda f: -f.size)
    if not found:
        return ""
    listed = ", ".join(f"{f.entry} {f.size:.2g}" for f in found)
    return (f"the hand has no vertical channel (no {', '.join(r.vertical)}): a "
            "horizontal-only model. The effect comparison holds the derived model's "
            "vertical channel (it keeps its initial errors and feeds nothing), as the hand "
            f"does without it, so its {len(found)} coupling{'s' * (len(found) != 1)} to "
            f"that channel are not assessed (size of each against its row's largest term: "
            f"{listed}). Not a mistake (exit status 0 unless other findings are); they "
            "carry the vertical errors into the horizontal ones where no height aid (a "
            "baro-altimeter) keeps those small")


def declared_drops(r: MatrixReport) -> list[EntryFinding]:
    """Findings the hand's ``@neglect`` lines explain (declared drops)."""
    return [f for f in r.findings if f.severity == DECLARED]


def worst_effects(r: MatrixReport) -> list[tuple[str, float, Effect, Effect]]:
    """(motion, hours, worst position case, worst attitude case) for each motion/time."""
    keys = []
    for e in r.effects:
        if (e.motion, e.hours) not in keys:
            keys.append((e.motion, e.hours))
    out = []
    for motion, hours in keys:
        group = [e for e in r.effects if (e.motion, e.hours) == (motion, hours)]
        out.append((motion, hours,
                    first_largest_item(group, lambda e: e.position_difference or 0.0),
                    first_largest_item(group, lambda e: e.attitude_difference or 0.0)))
    return out


def _share(ratio: float) -> str:
    return f"{ratio:.1%}" if ratio < 10 else f"{ratio:.2g}×"


def _effect_rows(r: MatrixReport) -> list[list[str]]:
    rows = []
    for motion, hours, p, a in worst_effects(r):
        if p.exponential:  # a figure like 1e48 m says only this
            rows.append([motion, f"{hours:g} h", growth_text(p.e_folding, p.growing_mode),
                         "–", "–", "grows exponentially", "–"])
            continue
        if p.position_difference is None:
            position = ["n/a", "–", "–"]
        elif p.position_above_rounding:
            share = p.position_difference / p.position_model if p.position_model else 0.0
            position = [f"{p.position_difference:.3g} m",
                        _share(share) if p.position_model else "–",
                        f"{p.case} ({p.magnitude})"]
        else:
            position = [below(p.position_floor, "m"), "–", NO_EFFECT]
        attitude = (["n/a", "–"] if a.attitude_difference is None
                    else [f"{a.attitude_difference / ARCSEC:.3g}″", f"{a.case} ({a.magnitude})"]
                    if a.attitude_above_rounding
                    else [below(a.attitude_floor / ARCSEC, "″"), NO_EFFECT])
        rows.append([motion, f"{hours:g} h", *position, *attitude])
    return rows


EFFECT_HEADER = ["motion", "after", "position Δ", "of derived", "worst case",
                 "attitude Δ", "worst case"]


def typical_sizes(r: MatrixReport) -> str:
    """The typical magnitudes on one line, names of the same size together
    (``phi_N, phi_E, phi_D 1e-4 rad; dv_N, dv_E, dv_D 0.1 m/s; ...``)."""
    groups: dict[str, list[str]] = {}
    for name, (_, text) in r.magnitudes.items():
        groups.setdefault(text, []).append(name)
    return "; ".join(f"{', '.join(names)} {text}" for text, names in groups.items())


def bias_text(r: MatrixReport, code: bool = False) -> str:
    """The bias states by their statistics, '' without any (``gyro_bias_x, gyro_bias_y
    (random constants); accel_bias_z (Gauss–Markov, τ = 3600 s)``); ``code``: names in
    Markdown backticks."""
    groups: dict[str, list[str]] = {}
    for b in r.bias_states:
        key = "random constants" if b.tau is None else b.statistics
        groups.setdefault(key, []).append(f"`{b.name}`" if code else b.name)
    return "; ".join(f"{', '.join(names)} ({key})" for key, names in groups.items())


def _no_g(r: MatrixReport) -> str:
    return ("no G: the other error sources' columns not compared" if r.bias_states
            else "no G: error-source columns not compared")


def to_terminal(r: MatrixReport) -> str:
    """Plain-text report."""
    lines = [f"Matrix check of {r.hand_name} against {r.model} (convention {r.convention})",
             f"states ({len(r.states)}): {', '.join(r.states)}"]
    if r.written:
        lines.append(f"up components read as the convention's down ones: "
                     f"{written_text(r.written)} (their rows and columns sign-flipped; "
                     "an entry is named in the convention's states, yours beside it)")
    if r.bias_states:
        lines.append(f"bias states ({len(r.bias_states)}, error sources as states: their "
                     f"columns hold G's): {bias_text(r)}")
    if r.sources:
        lines.append(f"sources in G ({len(r.sources)}): {', '.join(r.sources)}")
    else:
        lines.append(_no_g(r))
    if r.left_out:
        lines.append(f"convention states the hand model leaves out: {', '.join(r.left_out)}")
    lines.append("motions: " + "; ".join(f"{k}: {d}" for k, d in r.motions))
    lines += [f"motion not flown: {text}" for text in r.skipped_motions]
    lines.append("typical sizes: " + typical_sizes(r))
    lines.append(_summary(r))
    if r.convention_hint:
        lines.append(f"convention: {r.convention_hint}")
    for title, group in (("Mistakes", r.mistakes), ("Declared drops", declared_drops(r)),
                         ("Dropped small terms",
                          [f for f in r.findings
                           if f not in r.mistakes and f.severity != DECLARED
                           and f not in r.without_vertical])):
        if group:
            lines += ["", f"{title}:"] + [f"  {_finding_line(r, f)}" for f in group]
    if r.without_vertical:
        lines += ["", "Vertical channel left out:", f"  {without_vertical_text(r)}"]
    lines += [f"declaration explains nothing: {text}" for text in r.idle_declarations]
    if r.effects:
        held = (f"; vertical channel held: {', '.join(r.held)}" if r.held else "")
        if r.vertical_effects:
            held += " (its findings' effects on the height error are on their lines)"
        lines += ["", "Effect of the differences (hand − derived, propagated from each initial "
                  f"error and source at its typical size; the worst case{held}):"]
        rows = [EFFECT_HEADER, *_effect_rows(r)]
        widths = [max(len(row[i]) for row in rows) for i in range(len(EFFECT_HEADER))]
        lines += ["  " + "  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip()
                  for row in rows]
    return "\n".join(lines)


def to_markdown(r: MatrixReport, title: str | None = None) -> str:
    """Markdown report (tables of findings and effects)."""
    out = [f"# {one_line(title or 'Matrix check')}", "",
           f"Hand model `{one_line(r.hand_name)}` against the derived model `{r.model}`, "
           f"convention `{r.convention}`, threshold {r.threshold:g}.", "",
           f"States: {', '.join(f'`{s}`' for s in r.states)}."]
    if r.written:
        out.append(f"Up components read as the convention's down ones: "
                   f"{written_text(r.written)} (their rows and columns sign-flipped).")
    if r.bias_states:
        out.append(f"Bias states (error sources as states: their columns hold G's): "
                   f"{bias_text(r, code=True)}.")
    if r.sources:
        out.append(f"Sources in G: {', '.join(f'`{s}`' for s in r.sources)}.")
    else:
        out.append(_no_g(r)[0].upper() + _no_g(r)[1:] + ".")
    if r.left_out:
        out.append(f"Convention states left out: {', '.join(f'`{s}`' for s in r.left_out)}.")
    out += ["", "Motions:", ""] + [f"* `{k}`: {d}" for k, d in r.motions]
    if r.skipped_motions:
        out += ["", "Motions not flown (the model cannot follow them):", ""]
        out += [f"* `{k}`: {one_line(reason)}" for k, reason in
                (text.split(": ", 1) for text in r.skipped_motions)]
    if r.declarations:
        out.append("Declared simplifications: " + "; ".join(r.declarations) + ".")
    if r.idle_declarations:
        out.append("Declarations that explain nothing: " + "; ".join(r.idle_declarations)
                   + ".")
    out += ["", "Typical magnitudes: " + ", ".join(
        f"`{k}` {v[1]}" for k, v in r.magnitudes.items()) + ".", "", _summary(r) + ".", ""]
    if r.convention_hint:
        out += [f"**Convention.** {r.convention_hint[0].upper()}{r.convention_hint[1:]}.", ""]
    if r.without_vertical:
        out += [without_vertical_text(r)[0].upper() + without_vertical_text(r)[1:] + ".", ""]
    if r.findings:
        out += ["| entry | class | kind | size | largest on | hand | model | detail | "
                "effect alone |",
                "|---|---|---|---|---|---|---|---|---|"]
        for f in r.findings:
            size = "" if f.severity == SMALL_MISTAKE else f" ({f.size_class})"
            out.append(f"| `{f.entry}`{as_written(f.matrix, f.row, f.column, r.written)}"
                       f" | {f.severity}{size} | {f.kind} | "
                       f"{f.size:.2g} | {table_cell(f.motion)}, {_hours(f.time)} | "
                       f"{entry_value(f, f.hand)} | {entry_value(f, f.model)} | "
                       f"{table_cell(f.detail)} | "
                       f"{table_cell(_alone(r, f))} |")
        out.append("")
    if r.effects:
        out += ["## Effect of the differences", "",
                "Both models propagated from each initial error and error source at its "
                "typical size; the worst case" + (
                    f" (vertical channel held: {', '.join(r.held)})" if r.held else "") + ".",
                "",
                "| " + " | ".join(EFFECT_HEADER) + " |",
                "|" + "---|" * len(EFFECT_HEADER)]
        out += ["| " + " | ".join(map(table_cell, row)) + " |" for row in _effect_rows(r)]
        out.append("")
    return "\n".join(out)


def to_json(r: MatrixReport) -> dict:
    """JSON-ready dictionary."""
    return {
        "model": r.model, "convention": r.convention, "hand": r.hand_name,
        "states": r.states, "sources": r.sources, "threshold": r.threshold,
        "bias_states": [{"name": b.name, "statistics": "constant" if b.tau is None
                         else "markov", "tau_s": b.tau, "rate_per_s": b.rate}
                        for b in r.bias_states],
        "left_out": r.left_out, "out_of_scope": r.out_of_scope,
        "motions": [{"label": k, "description": d} for k, d in r.motions],
        "skipped_motions": list(r.skipped_motions),
        "magnitudes": {k: {"si": v[0], "text": v[1]} for k, v in r.magnitudes.items()},
        "compared": r.compared, "exit_status": r.exit_status, "held": r.held,
        "declarations": r.declarations, "idle_declarations": r.idle_declarations,
        "convention_hint": r.convention_hint or None,
        "up_components": {up: down for down, up in r.written.items()},
        "findings": [{"matrix": f.matrix, "row": f.row, "column": f.column, "kind": f.kind,
                      "severity": f.severity, "size": f.size, "size_class": f.size_class,
                      "motion": f.motion, "time_s": f.time, "hand": f.hand, "model": f.model,
                      "absolute": f.absolute, "unit": f.unit, "per_motion": f.per_motion,
                      "detail": f.detail,
                      "as_written": as_written(f.matrix, f.row, f.column,
                                               r.written).strip(" ()") or None,
                      "pair": (None if f.pair is None
                               else f"{f.matrix}[{f.pair[0]}, {f.pair[1]}]"),
                      "effect_alone_24h": (_alone_json(r.finding_effects[f.entry])
                                           if f.entry in r.finding_effects else None),
                      "effect_vertical": (_vertical_json(r.vertical_effects[f.entry])
                                          if f.entry in r.vertical_effects else None),
                      "effect_not_assessed": (
                          NOT_ASSESSED if vertical_text(r, f) == NOT_ASSESSED
                          else r.finding_effects[f.entry].not_assessed
                          if f.entry in r.finding_effects else None)}
                     for f in r.findings],
        "effects": [{"motion": e.motion, "hours": e.hours, "case": e.case,
                     "magnitude": e.magnitude,
                     "position_difference_m": e.position_difference,
                     "position_model_m": e.position_model,
                     "attitude_difference_rad": e.attitude_difference,
                     "attitude_model_rad": e.attitude_model,
                     **_below_json(e, e.position_difference, e.attitude_difference),
                     "exponential": e.exponential, **_growth_json(e)}
                    for e in r.effects],
    }


def _growth_json(e) -> dict:
    """The growing mode of an effect: e-folding time (s), its rate (1/s), whose mode."""
    return {"e_folding_s": e.e_folding,
            "growth_rate_per_s": 1.0 / e.e_folding if e.e_folding else None,
            "growing_mode": e.growing_mode}


def _vertical_json(e) -> dict:
    """``effect_vertical`` of a finding: the height-error change (m) at each time, its
    floor, case and motion, whether it grows exponentially, and the growing mode."""
    return {"hours": list(e.hours), "height_m": list(e.height), "height_floor_m": list(e.floor),
            "height_model_m": list(e.derived),
            "case": list(e.case), "motion": list(e.motion), "exponential": list(e.exponential),
            "e_folding_s": e.e_folding, "growing_mode": e.growing_mode}


def _alone_json(e) -> dict:
    """``effect_alone_24h`` of a finding: the numbers, their floors, whether below, and
    whether it grows exponentially (with the mode's e-folding time and rate)."""
    return {"position_m": e.position, "attitude_rad": e.attitude, "motion": e.motion,
            **_below_json(e, e.position, e.attitude),
            "exponential": e.exponential, **_growth_json(e)}


def _below_json(e, position: float | None, attitude: float | None) -> dict:
    """Floors and whether each figure is below its floor (None for a figure not
    measured: the hand's states hold no position, or no attitude)."""
    return {"position_floor_m": e.position_floor,
            "position_below_rounding": (None if position is None
                                        else not e.position_above_rounding),
            "attitude_floor_rad": e.attitude_floor,
            "attitude_below_rounding": (None if attitude is None
                                        else not e.attitude_above_rounding)}
