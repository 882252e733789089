"""Two findings of two error-state lines that are one slip: a mirror pair, a wrong row.

The equation checker compares each line alone, so one slip that changes two lines reads
as two root mistakes, each with an effect of its own that the slip does not have:

* **a mirror pair**: an antisymmetric term (the Coriolis ``2Ω sin φ`` of the two
  horizontal velocity lines, a ``[ω×]``) left out or written with the wrong sign
  changes the coefficient of b in the line of a and that of a in the line of b by
  exactly opposite amounts (a, b error states of one unit). Either alone breaks the
  antisymmetry: on a static base each omitted Coriolis term alone gives 3.5 km after a
  day, the two together (a Foucault rotation left out) far less.
* **a term in the wrong row**: a term of the line of X written in the line of Y (a gyro
  drift in the latitude line instead of the tilt line): an extra term in Y and an
  omitted one in X, in the same quantity, by exactly opposite amounts. The move changes
  the error differently from either alone (6.31 km after 1 h, not 2.85 or 3.46 km, for
  the single-axis Schuler loop).

Both are found among the root findings of error-state lines, exactly at every reference
point (to :data:`EXACT` of the larger difference), and unique; the pair is one finding:
the one kept (the larger of a mirror pair, the line where a moved term is written) names
the other (:attr:`~ins_errors.checker.classify.Finding.pair`) and gets the pair's effect
(:func:`~ins_errors.checker.effect.add_effects`); the other stays in its line, marked
:attr:`~ins_errors.checker.classify.Finding.merged`, and is not counted again.
"""

from __future__ import annotations

from dataclasses import replace
from itertools import combinations
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ins_errors.checker import classify as cl
from ins_errors.checker.kinds import SMALL_MISTAKE
from ins_errors.checker.kinds import severity as classify_severity
from ins_errors.checker.sides import UnresolvedError

if TYPE_CHECKING:
    from ins_errors.checker.compare import Comparison, EquationResult

EXACT = 1e-9
"""Relative agreement (of the larger of the two differences at each point) of two
differences that are exactly opposite."""
STATE = "error state "
"""How an error-state line's target begins."""
MIRROR = frozenset({cl.OMITTED, cl.EXTRA, cl.SIGN, cl.COEFFICIENT})
"""Kinds that may be half of a mirror pair."""
ROW = frozenset({cl.OMITTED, cl.EXTRA, cl.COEFFICIENT})
"""Kinds that may be half of a term in the wrong row."""


def _candidates(results: list[EquationResult], items: dict, comparison: Comparison
                ) -> list[tuple[EquationResult, cl.Finding, str, np.ndarray]]:
    """(result, finding, row state, hand − model at the points) of every root finding
    of an error-state line on one quantity (the line's own part: its definitions
    corrected, as its effect is measured)."""
    names = {b.name for b in comparison.basis}
    out = []
    for result in results:
        if not result.target.startswith(STATE):
            continue
        item = items.get((id(result.equation), result.form))
        if item is None or item.hand_isolated is None or item.model_declared is None:
            continue
        own = [g for g in result.findings
               if g.role == cl.ROOT and g.quantity in names and np.isfinite(g.size)
               and g.severity != cl.DECLARED and g.kind in MIRROR | ROW]
        if not own:
            continue
        try:
            h = comparison.linear_parts(item.hand_isolated)[0]
            m = comparison.linear_parts(item.model_declared)[0]
            symbol = {str(b): b for b in comparison.symbols}
            values = comparison.evaluate([h.get(symbol[g.quantity], sp.S.Zero)
                                          - m.get(symbol[g.quantity], sp.S.Zero)
                                          for g in own])
        except (UnresolvedError, KeyError):
            continue
        row = result.target.removeprefix(STATE)
        out += [(result, g, row, v) for g, v in zip(own, values, strict=True)
                if np.any(v != 0)]
    return out


def _opposite(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether ``a = −b`` at every point, to :data:`EXACT` of the larger."""
    return bool(np.all(np.abs(a + b) <= EXACT * np.maximum(np.abs(a), np.abs(b))))


def _short(value: str, limit: int = 60) -> str:
    return value if len(value) <= limit else value[:limit - 3] + "..."


def _term(coefficient: str, quantity: str) -> str:
    """``gyro_drift``, ``-g*psi``, ``(U*sin(phi))*alpha_N``: a coefficient (SymPy text)
    times its quantity."""
    if coefficient in ("1", "-1"):
        return coefficient[:-1] + quantity
    if any(c in coefficient.lstrip("-") for c in "+- "):
        return f"({_short(coefficient)})*{quantity}"
    return f"{coefficient}*{quantity}"


def pair_findings(results: list[EquationResult], items: dict, comparison: Comparison,
                  threshold: float) -> None:
    """Merge each mirror pair and each term written in the wrong row (see the module
    docstring) into one finding, in place.

    Parameters
    ----------
    results : list of EquationResult
        Every form checked, with its findings (roots assigned).
    items : dict
        ``(id(equation), form)`` -> the prepared :class:`~ins_errors.checker.compare.Item`
        (its ``hand_isolated`` and ``model_declared``).
    comparison : Comparison
        Evaluates coefficients at the reference points.
    threshold : float
        The check's, for the severity of a term in the wrong row (a mistake whatever its
        size, as every slip of a symbol or index).
    """
    found = _candidates(results, items, comparison)
    units = {b.name: b.unit for b in comparison.basis}
    pairs = []  # (kept, other, mirror?)
    for x, y in combinations(found, 2):
        (rx, gx, row_x, dx), (ry, gy, row_y, dy) = x, y
        if rx is ry or row_x == row_y or not _opposite(dx, dy):
            continue
        if not (gx.is_mistake or gy.is_mistake):
            continue  # two dropped small terms stay two lines, as drops are listed
        if (gx.quantity == row_y and gy.quantity == row_x and units.get(row_x)
                and units.get(row_x) == units.get(row_y)
                and gx.kind in MIRROR and gy.kind in MIRROR):
            kept, other = (x, y) if gx.size >= gy.size else (y, x)
            pairs.append((kept, other, True))
        elif gx.quantity == gy.quantity and gx.kind in ROW and gy.kind in ROW:
            # which way the term moved: written (extra) in one line, missing in the other
            ways = [(a, b) for a, b in ((x, y), (y, x))
                    if a[1].kind == cl.EXTRA or b[1].kind == cl.OMITTED]
            if len(ways) == 1:
                pairs.append((*ways[0], False))
    unique = [p for p in pairs
              if sum(any(q[0][1] is g or q[1][1] is g for g in (p[0][1], p[1][1]))
                     for q in pairs) == 1]
    for (rk, gk, _, _), (ro, go, _, _), mirror in unique:
        where = f"line {ro.equation.line} {ro.label}"
        everywhere = ("at the one reference point" if len(comparison.points) == 1
                      else "at every point")
        if mirror:
            said = (f"one finding with its mirror, {where} on {go.quantity} (hand "
                    f"{_short(go.hand)}, model {_short(go.model)}, {go.kind}): hand − model "
                    f"there is exactly minus hand − model here {everywhere}, as an "
                    "antisymmetric term (a [ω×] such as Coriolis) with a wrong sign or left "
                    "out gives; the effect is the pair's together")
            kind = gk.kind
            severity = (cl.MISTAKE if cl.MISTAKE in (gk.severity, go.severity)
                        else SMALL_MISTAKE if SMALL_MISTAKE in (gk.severity, go.severity)
                        else gk.severity)
            detail = f"{gk.detail}; {said}" if gk.detail else said
            size = gk.size
        else:
            detail = (f"the term {_term(gk.hand, gk.quantity)} belongs in row "
                      f"{ro.label} ({where}), not row {rk.label}: written in the wrong "
                      f"row (there: hand {_short(go.hand)}, model {_short(go.model)}, "
                      f"{go.kind}); the effect is the move's, both lines together")
            kind = cl.SYMBOL
            size = max(gk.size, go.size)
            severity = classify_severity(cl.SYMBOL, size, threshold)
        kept = replace(gk, kind=kind, severity=severity, detail=detail, size=size,
                       pair=(where, go.quantity), at_rest=gk.at_rest and go.at_rest)
        other = replace(go, merged=True, pair=(f"line {rk.equation.line} {rk.label}",
                                               gk.quantity),
                        detail=(f"the other half of the finding of line "
                                f"{rk.equation.line} {rk.label} on {gk.quantity} "
                                + ("(its mirror)" if mirror else
                                   "(the term written there belongs here)")
                                + "; one finding with it, its effect there"))
        rk.findings = [kept if g is gk else g for g in rk.findings]
        ro.findings = [other if g is go else g for g in ro.findings]


__all__ = ["pair_findings"]
