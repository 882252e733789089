"""The words of ``ins-errors transfer``: W(s) in factored form, the long run, the report.

Everything the text (and the JSON's text fields: ``factored``, ``factor``,
``gain_display_unit``, ``long_run.text``, ``convention``) says of a
:class:`~ins_errors.analysis.transfer.TransferFunction` is written here, from its
numbers; :mod:`ins_errors.analysis.transfer` computes them. Values are in the display
units of the source and the output, an angle in the arcsec, arcmin or deg it reads best
in, times as :func:`~ins_errors.time_text.duration_text` writes periods elsewhere.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ins_errors.analysis.transfer import CHECK_LIMIT
from ins_errors.analysis.transfer_reduction import CANCEL, TOLERANCE
from ins_errors.time_text import duration_text

if TYPE_CHECKING:
    from ins_errors.analysis.transfer import Factor, TransferFunction, TransferFunctions

CONVENTION = ("W(s) = h (sI − F)⁻¹ g, s in 1/s: h the output's row of H, g the source's "
              "column of G (a constant source: size b gives Y(s) = b·W(s)/s) or of the "
              "initial-error map (an initial error: size b gives Y(s) = b·W(s))")
"""The convention, as the command and the JSON state it."""

CLOSE_ROOTS = 1e-4
"""Two roots of W closer than this share of their size are printed with the digits that
tell them apart (:func:`digits`): at 4 digits they would look equal."""

SUPERSCRIPTS = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def superscript(power: int) -> str:
    """``"²"`` for 2; empty for 1."""
    return "" if power == 1 else str(power).translate(SUPERSCRIPTS)


# --------------------------------------------------------------------------------------
# Units and factors
# --------------------------------------------------------------------------------------
def unit_term(unit: str) -> str:
    """A unit as a term of a quotient: ``(m/s)`` for ``m/s``, ``ug`` as it is."""
    return f"({unit})" if "/" in unit or " " in unit else unit


def ratio_unit(output: str, source: str, per_seconds: int = 0) -> str:
    """The unit of ``output`` per ``source`` per s^``per_seconds``, an output unit equal
    to the source's cancelled.

    Parameters
    ----------
    output, source : str
        Display units (``"arcmin"``, ``"m/s"``).
    per_seconds : int
        The power of 1/s (negative: of s).

    Returns
    -------
    str
        ``"arcmin/ug/s²"``, ``"(m/s)/arcsec"``; for the same unit above and below
        ``"1/s³"``, ``"1"``, or ``"s"`` for a power −1.
    """
    same = output == source
    if per_seconds < 0 and same:
        return f"s{superscript(-per_seconds)}"
    head = "1" if same else f"{unit_term(output)}/{unit_term(source)}"
    return head if per_seconds == 0 else f"{head}/s{superscript(per_seconds)}"


def gain_unit(pair: TransferFunction) -> str:
    """The unit of the gain in display units: the output's per the source's per
    s^:attr:`~ins_errors.analysis.transfer.TransferFunction.seconds_power`
    (``"arcmin/ug/s²"``, ``"1/s³"``)."""
    return ratio_unit(pair.output_display, pair.source_display, pair.seconds_power)


def factor_text(factor: Factor, digits: int = 4) -> str:
    """The factor in s, real form: ``s²``, ``(s + 1.755e-03)``, ``(s² + (1.186e-03)²)``,
    ``(s² + 4.2e-04 s + (1.2e-03)²)``, with its power; ``digits`` after the point."""
    v, power = factor.value, superscript(factor.multiplicity)
    if v == 0:
        return f"s{power}"
    if not v.imag:
        sign = "+" if v.real < 0 else "−"
        return f"(s {sign} {abs(v.real):.{digits}e}){power}"
    if not v.real:
        return f"(s² + ({v.imag:.{digits}e})²){power}"
    sign = "+" if v.real < 0 else "−"
    return (f"(s² {sign} {abs(2 * v.real):.{digits}e} s + ({abs(v):.{digits}e})²)"
            f"{power}")


def digits(pair: TransferFunction) -> int:
    """Digits after the point the roots are printed with: 4, or as many as tell apart
    two of W's roots (a zero and a pole, two poles) within :data:`CLOSE_ROOTS` of each
    other's size (+ 2, at most 12)."""
    values = [f.value for f in (*pair.zeros, *pair.poles) if f.value != 0]
    closest = min((abs(a - b) / max(abs(a), abs(b))
                   for k, a in enumerate(values) for b in values[k + 1:]
                   if a != b), default=1.0)
    if closest >= CLOSE_ROOTS:
        return 4
    return int(min(12, math.ceil(-math.log10(max(closest, 1e-16))) + 2))


def factored_text(pair: TransferFunction) -> str:
    """``W(s) = K [unit] · zeros / poles`` in display units (``W(s) = 0`` when the
    source does not reach the output); roots with :func:`digits`."""
    if pair.is_zero:
        return "W(s) = 0"
    shown = digits(pair)
    numerator = " ".join(factor_text(f, shown) for f in pair.zeros) or "1"
    denominator = " ".join(factor_text(f, shown) for f in pair.poles)
    if len(pair.poles) > 1:
        denominator = f"({denominator})"
    return f"W(s) = {pair.gain_display:.4e} [{gain_unit(pair)}] · {numerator} / {denominator}"


# --------------------------------------------------------------------------------------
# The long run
# --------------------------------------------------------------------------------------
def _display_value(pair: TransferFunction, value_si: float, per_hours: int = 0) -> str:
    """An output value (per h^per_hours) in the output's display unit; an angle in the
    arcsec, arcmin or deg it reads best in."""
    from ins_errors.units import parse_quantity, readable_angle_unit

    value = value_si * 3600.0 ** per_hours
    factor, unit = pair.display_factors[0], pair.output_display
    if unit in ("arcsec", "arcmin", "deg"):
        unit = readable_angle_unit(value, unit, down=True)
        factor = 1.0 / parse_quantity(f"1 {unit}", pair.output_unit)
    per = "" if per_hours == 0 else f"/h{superscript(per_hours)}"
    return f"{value * factor:.4g} {unit}{per}"


def magnitude_text(pair: TransferFunction) -> str:
    """The source's size in its display unit (``"1 ug"``)."""
    size = pair.display_factors[1]
    return f"{pair.magnitude / size:.4g} {pair.source_display}"


YEAR = 365.25 * 86400.0
"""s."""

CENTURY = 100 * YEAR
"""An e-folding time beyond which a growing term is said to be unseen in any run, s."""


def long_run_text(pair: TransferFunction) -> str:
    """The long run in words, with its number in the output's display unit."""
    run = pair.long_run
    what = (("constant source " if pair.source_kind != "initial" else "initial error ")
            + f"{pair.source} = {magnitude_text(pair)}")
    if run.kind == "none":
        return f"{pair.output} does not respond to {pair.source} (W = 0)"
    if run.kind != "exponential":
        return f"{what}: {pair.output} {_run_words(pair, run)}"
    growth = run.growth
    power = f" · t{superscript(run.power)}" if run.power else ""
    text = (f"{what}: {pair.output} grows exponentially, ≈ "
            f"{_display_value(pair, run.coefficient * pair.magnitude, run.power)}"
            f"{power} · e^(t/{duration_text(growth.time_constant_s)}), the "
            f"{growth.name} mode"
            + (f" (period {duration_text(growth.period_s)})" if growth.period_s else "")
            + (f" (an e-folding time of {growth.time_constant_s / YEAR:.2g} years: no run "
               "sees it grow)" if growth.time_constant_s > CENTURY else ""))
    rest = run.rest
    if rest is None or rest.kind == "none":
        return text
    text += f"; beside it {pair.output} {_run_words(pair, rest)}"
    if run.overtakes_s is not None:
        size = _display_value(pair, rest.bounded_size * abs(pair.magnitude))
        text += ("; the growing term reaches these terms' largest size (" + size
                 + (": level plus amplitudes" if rest.oscillations else "") + ") "
                 + ("from the start" if run.overtakes_s == 0 else
                    f"after about {duration_text(run.overtakes_s)}"))
    return text


def _run_words(pair: TransferFunction, run) -> str:
    """What the output does in a long run other than the exponential kind: ``"oscillates
    about 0.2063 arcsec (...); oscillations: ..."``, ``"grows as t², ..."``."""
    waves = "; ".join(f"{o.name} (period {duration_text(o.period_s)}, amplitude "
                      f"{_display_value(pair, abs(o.amplitude * pair.magnitude))}"
                      + (f", decay {duration_text(o.decay_s)}" if o.decay_s else "") + ")"
                      for o in run.oscillations)
    settling = ("" if not run.settling_s else
                f"; each of its damped terms below 1 % of its largest term after about "
                f"{duration_text(run.settling_s)}")
    if run.kind == "resonance":
        text = (f"oscillates with an amplitude growing as "
                f"t{superscript(run.power)} (repeated {run.growth.name} pair, period "
                f"{duration_text(run.growth.period_s)})")
        if run.coefficient is not None:
            text += (f" and grows as t{superscript(run.power)}, ≈ "
                     f"{_display_value(pair, run.coefficient * pair.magnitude, run.power)}"
                     f" · t{superscript(run.power)}")
        return text + (f"; oscillations: {waves}" if waves else "")
    if run.kind == "power":
        value = run.coefficient * pair.magnitude
        head = (f"grows as t{superscript(run.power)}, "
                f"≈ {_display_value(pair, value, run.power)} · t{superscript(run.power)}"
                f" (lim s→0 s{superscript(run.power + 1)}·Y(s)"
                + (f"/{run.power}!)" if run.power > 1 else ")"))
        return head + (f", with oscillations: {waves}" if waves else "") + settling
    value = 0.0 if run.kind == "zero" else run.coefficient * pair.magnitude
    limit = "lim s→0 s·Y(s)" + (" = b·W(0)" if pair.source_kind != "initial" else "")
    if run.settles:
        verb = "settles at"
    elif run.oscillations:
        verb = "oscillates about"
    else:
        verb = "tends to"
    text = f"{verb} {_display_value(pair, value)} ({limit})"
    if run.settles and run.settling_s and value != 0:
        settling = (f", each of its decaying terms below 1 % of that after about "
                    f"{duration_text(run.settling_s)}")
    return text + settling + (f"; oscillations: {waves}" if waves else "")


# --------------------------------------------------------------------------------------
# The report
# --------------------------------------------------------------------------------------
def _times(factor: Factor) -> str:
    """A pole's period and decay (e-folding) time, or its time constant; ``–`` at 0."""
    if factor.value == 0:
        return "–"
    if factor.period_s is not None:
        text = f"period {duration_text(factor.period_s)}"
        if factor.time_constant_s is not None:
            word = "e-folding" if factor.value.real > 0 else "decay"
            text += f", {word} {duration_text(factor.time_constant_s)}"
        return text
    word = "e-folding" if factor.value.real > 0 else "time constant"
    return f"{word} {duration_text(factor.time_constant_s)}"


def _cancelled(pair: TransferFunction) -> str:
    """``"cancelled: integrator, Earth"`` (a repeated mode ``×2``; one the pair keeps
    part of with the count, ``Schuler (1 of 2 pairs)``) or ``"none cancelled"``."""
    if not pair.cancelled:
        return "none cancelled"
    return "cancelled: " + ", ".join(_cancelled_mode(f) for f in pair.cancelled)


def _cancelled_mode(factor: Factor) -> str:
    """A cancelled mode: ``Earth``, ``integrator ×2``, ``Schuler (1 of 2 pairs)``."""
    total = factor.mode_multiplicity
    if total is not None and total > factor.multiplicity:
        what = "pairs" if factor.value.imag else "roots"
        return f"{factor.name} ({factor.multiplicity} of {total} {what})"
    return factor.name + (f" ×{factor.multiplicity}" if factor.multiplicity > 1 else "")


def frozen_long_run_text(pair: TransferFunction, turning, model: str = "MODEL") -> str:
    """The long run of a pair of ``model`` whose F turns at rest (``turning``: a
    :class:`~ins_errors.analysis.modes.TurningAtRest`): not given, and why."""
    from ins_errors.time_text import duration_text

    return (f"not given: {turning.words()}, so W(s), of F frozen at the start, describes "
            f"the response over times short against {duration_text(turning.period_s)}, "
            f"not its long run (the turning carries a constant source round with it); "
            f"fly it for that: ins-errors compare {model} -s {pair.source} --hours N")


def pair_text(pair: TransferFunction, turning=None, model: str = "MODEL") -> str:
    """One pair's section: heading, factored W, its pole factors, the long run (not
    given where F of ``model`` turns at rest, ``turning``)."""
    head = f"#### {pair.source} → {pair.output}"
    if pair.is_zero and pair.negligible:
        return (f"{head}\n\nW(s) ≈ 0: {pair.source} reaches {pair.output} only below "
                f"{TOLERANCE:g} of the size the norms of F, g and h allow (a coupling "
                f"weaker than the reductions' tolerance; every mode cancelled)")
    if pair.is_zero:
        return (f"{head}\n\nW(s) = 0: {pair.source} does not reach {pair.output} (its "
                f"Markov parameters h Fᵏ g, k < {pair.full_order}, are zero to rounding; "
                f"every mode cancelled)")
    shown = digits(pair)
    form = factored_text(pair)
    if pair.negligible:
        form = form.replace("W(s) = ", "W(s) ≈ ", 1)
    lines = [f"{head}: order {pair.order} of {pair.full_order} ({_cancelled(pair)})", "",
             form, ""]
    if pair.negligible:  # the growing modes' part alone
        lines += [f"(≈: {pair.source} reaches {pair.output} only below {TOLERANCE:g} of "
                  f"the size the norms of F, g and h allow, a coupling weaker than the "
                  f"reductions' tolerance, except through the growing mode, whose part is "
                  f"kept: it overtakes every bounded term)", ""]
    lines += ["| pole factor | mode | period or time |", "|---|---|---|"]
    lines += [f"| {factor_text(f, shown)} | {f.name} | {_times(f)} |" for f in pair.poles]
    lines += ["", "long run: " + (long_run_text(pair) if turning is None
                                 else frozen_long_run_text(pair, turning, model))]
    if pair.check_error > CHECK_LIMIT:
        lines.append(f"(the factored form differs from h (iωI − F)⁻¹ g of the whole F by "
                     f"{pair.check_error:.1e} of its size within the band: the reduction's "
                     f"tolerance cut a weak coupling)")
    return "\n".join(lines)


def report_text(result: TransferFunctions) -> str:
    """The whole report: convention, every pair, the notes."""
    parts = [f"convention: {CONVENTION}"]
    turning = result.modes.turning
    parts += [pair_text(pair, turning, result.modes.model) for pair in result.pairs]
    parts.append(
        "gains in the output's display unit per the source's display unit, per second to "
        "the power the form's degrees leave (s in 1/s); the poles are F's eigenvalues "
        "named as 'ins-errors modes' names them; a mode of F the pair does not reach or "
        f"see is cancelled (Krylov bases on the states in the units of the Schuler loop, "
        f"tolerance {TOLERANCE:g} of F's norm, finer or on balanced states where the "
        f"factored form is not within {CHECK_LIMIT:g} of h (iωI − F)⁻¹ g; a zero within "
        f"{CANCEL:g} of a pole's size cancels it, unless the pole grows: a growing mode "
        f"is split off F and kept wherever the source reaches it and the output sees "
        f"it beyond rounding)")
    return "\n\n".join(parts)
