"""Classify a discrepancy on two axes: what it is, and how much it matters.

*What it is* (the ``kind``): an omitted term, an extra term, a wrong sign, a wrong
coefficient of the same form (with the ratio when it is constant), a wrong symbol or
index (``u21`` written for ``u11``, a coefficient put on the wrong error quantity), a
wrong function (``cos 2λ`` where no function belongs) or a wrong exponent. Symbol,
function and exponent slips are found by trying the one-place changes that would make
the hand coefficient equal the model's at every reference point.

*How much it matters* (the size, relative to the equation's largest term) gives the
``severity``: a term that is present but wrong is a ``"mistake"`` whatever its size
(``"mistake, small effect"`` below the threshold); only an omission of a small term is
a ``"dropped small term"``; an omission the author declared (``@neglect``) is a
``"declared drop"``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

OMITTED = "omitted term"
EXTRA = "extra term"
SIGN = "wrong sign"
COEFFICIENT = "wrong coefficient"
SYMBOL = "wrong symbol or index"
FUNCTION = "wrong function"
EXPONENT = "wrong exponent"
NOT_ERROR = "not an error quantity"
LEFT_SIDE = "left-hand side without Δ"
DEFINITION = "wrong definition"
KINDS = (OMITTED, EXTRA, SIGN, COEFFICIENT, SYMBOL, FUNCTION, EXPONENT, NOT_ERROR,
         LEFT_SIDE, DEFINITION)
"""What a difference can be."""

MISTAKE = "mistake"
SMALL_MISTAKE = "mistake, small effect"
DROPPED = "dropped small term"
DECLARED = "declared drop"
SEVERITIES = (MISTAKE, SMALL_MISTAKE, DROPPED, DECLARED)
"""How much it matters; the first two are mistakes."""

ROOT = "root"
KNOCK_ON = "knock-on"
"""Roles: a root finding is the line's own; a knock-on comes from a definition it uses."""

TOLERANCE = 1e-6
"""Relative agreement for "constant ratio" and "the change makes it agree"."""


@dataclass(frozen=True)
class Finding:
    """One discrepancy between a hand equation and the model.

    Attributes
    ----------
    quantity : str
        Basis quantity whose coefficient differs (``"(none)"`` for a term with no
        error, ``"(value)"`` for an ideal definition, ``"a -> b"`` for a term written on
        the wrong quantity).
    kind : str
        What it is (:data:`KINDS`).
    severity : str
        How much it matters (:data:`SEVERITIES`).
    size : float
        Largest ratio, over the reference points, of the discrepancy to the equation's
        largest term at that point.
    point : str
        Reference point where that ratio is reached.
    hand, model : str
        Hand and model coefficients (SymPy text).
    detail : str
        One-line explanation.
    role : str
        ``"root"`` (the line's own) or ``"knock-on"`` (from definitions it uses).
    roots : tuple of str
        For a knock-on: the definitions it comes from (``"line 49 Delta_R_E"``).
    effect : dict
        Effect on the error trajectory (see :mod:`ins_errors.checker.effect`), if
        computed: ``{"point", "position_1h", "position_24h", "attitude_1h",
        "attitude_24h"}`` in m and rad.
    """

    quantity: str
    kind: str
    severity: str
    size: float
    point: str
    hand: str
    model: str
    detail: str = ""
    role: str = ROOT
    roots: tuple[str, ...] = ()
    effect: dict = field(default_factory=dict, compare=False)

    @property
    def is_mistake(self) -> bool:
        """True for mistakes of any size."""
        return self.severity in (MISTAKE, SMALL_MISTAKE)


def severity(kind: str, size: float, threshold: float) -> str:
    """Severity of a finding: omissions of small terms are drops, everything else a mistake."""
    if size >= threshold:
        return MISTAKE
    return DROPPED if kind == OMITTED else SMALL_MISTAKE


def _siblings(symbol: sp.Symbol, known: list[sp.Symbol]) -> list[sp.Symbol]:
    """Symbols one index or axis away: ``u11``/``u21``, ``a_xi``/``a_eta``."""
    name = symbol.name
    parts = name.split("_")
    out = []
    for other in known:
        o = other.name
        if o == name:
            continue
        oparts = o.split("_")
        if len(oparts) != len(parts):
            continue
        differ = [i for i, (a, b) in enumerate(zip(parts, oparts, strict=True)) if a != b]
        if len(differ) != 1:
            continue
        a, b = parts[differ[0]], oparts[differ[0]]
        if len(parts) == 1 and not (len(a) == len(b) and sum(x != y for x, y in zip(
                a, b, strict=True)) == 1 and any(c.isdigit() for c in a)):
            continue
        out.append(other)
    return out


def _exponent_changes(exp: sp.Rational) -> list[sp.Rational]:
    half = sp.Rational(1, 2)
    return [e for e in (exp + half, exp - half, exp + 1, exp - 1, -exp) if e != exp and e != 0]


def candidates(expr: sp.Expr, known: list[sp.Symbol]) -> list[tuple[str, str, sp.Expr]]:
    """One-place changes of ``expr``: (kind, description, changed expression)."""
    out: list[tuple[str, str, sp.Expr]] = []
    for symbol in sorted(expr.free_symbols, key=sp.default_sort_key):
        for other in _siblings(symbol, known):
            out.append((SYMBOL, f"{symbol} written where {other} belongs",
                        expr.xreplace({symbol: other})))
    for f in sorted(expr.atoms(sp.sin, sp.cos, sp.tan, sp.cot), key=sp.default_sort_key):
        arg = f.args[0]
        options = [(sp.S.One, f"{f} should not be there")]
        for g in (sp.sin, sp.cos, sp.tan):
            if g != f.func:
                options.append((g(arg), f"{f} written where {g(arg)} belongs"))
        if arg.is_Mul and arg.args[0] == 2:
            options.append((f.func(arg / 2), f"{f} written where {f.func(arg / 2)} belongs"))
        for value, text in options:
            out.append((FUNCTION, text, expr.xreplace({f: value})))
    for power in sorted(expr.atoms(sp.Pow), key=sp.default_sort_key):
        if power.exp.is_Rational and not power.base.is_Symbol:
            for e in _exponent_changes(power.exp):
                out.append((EXPONENT, f"exponent {power.exp} where {e} belongs",
                            expr.xreplace({power: power.base ** e})))
    return out


def diagnose(hand_expr: sp.Expr, model_expr: sp.Expr, hs: np.ndarray, ms: np.ndarray,
             tiny: float, evaluate: Callable[[list[sp.Expr]], np.ndarray | None],
             known: list[sp.Symbol], term_split: Callable | None = None,
             proportional: bool = False) -> tuple[str, str]:
    """(kind, detail) of a coefficient that differs.

    Parameters
    ----------
    hand_expr, model_expr : sympy.Expr
        The two coefficients, in model symbols.
    hs, ms : numpy.ndarray, shape (points,)
        Their values at the reference points.
    tiny : float
        Values below this are zero.
    evaluate : callable
        ``evaluate(exprs)`` -> values, shape (len(exprs), points), or None if it cannot.
    known : list of sympy.Symbol
        Symbols that have values (candidates for a wrong symbol).
    term_split : callable, optional
        ``term_split(hand, model)`` -> (only in model, only in hand) or None.
    proportional : bool
        Also accept a one-place change that leaves a constant ratio (reported with it).
    """
    if np.all(np.abs(hs) <= tiny):
        return OMITTED, ""
    if np.all(np.abs(ms) <= tiny):
        return EXTRA, ""
    scale = np.maximum(np.abs(hs), np.abs(ms))
    if np.all(np.abs(hs + ms) <= TOLERANCE * scale):
        return SIGN, ""
    usable = np.abs(ms) > tiny
    ratios = hs[usable] / ms[usable]
    if ratios.size and np.all(np.abs(ratios - ratios[0]) <= TOLERANCE * abs(ratios[0])):
        return COEFFICIENT, f"hand/model = {ratios[0]:.6g} at every point"
    split = term_split(hand_expr, model_expr) if term_split else None
    if split is not None and split[1] == 0:
        return OMITTED, f"part of the coefficient is missing: {_short(split[0])}"
    if split is not None and split[0] == 0:
        return EXTRA, f"extra part of the coefficient: {_short(split[1])}"
    changed = change_that_fits(hand_expr, ms, tiny, evaluate, known,
                               proportional=proportional)
    if changed is not None:
        return changed
    if split is not None and len(sp.sstr(split[0])) + len(sp.sstr(split[1])) < 160:
        return COEFFICIENT, (f"model has {_short(split[0])} where the hand has "
                             f"{_short(split[1])}")
    return COEFFICIENT, ""


def change_that_fits(hand_expr: sp.Expr, target: np.ndarray, tiny: float,
                     evaluate: Callable[[list[sp.Expr]], np.ndarray | None],
                     known: list[sp.Symbol], limit: int = 60, proportional: bool = False
                     ) -> tuple[str, str] | None:
    """The one-place change of ``hand_expr`` that makes it equal ``target`` (values), or
    proportional to it, as (kind, detail); None if none does."""
    if not known:
        return None
    options = candidates(hand_expr, known)[:limit]
    if not options:
        return None
    values = evaluate([expr for _, _, expr in options])
    if values is None:
        return None
    scale = np.maximum(np.abs(target), tiny)
    best = None
    for (kind, text, _), v in zip(options, values, strict=True):
        if not np.all(np.isfinite(v)):
            continue
        if np.all(np.abs(v - target) <= TOLERANCE * scale):
            return kind, text
        usable = np.abs(target) > tiny
        if proportional and best is None and usable.any():
            r = v[usable] / target[usable]
            if np.all(np.abs(r - r[0]) <= TOLERANCE * abs(r[0])) and abs(r[0]) > 0:
                best = (kind, f"{text}; then hand/model = {r[0]:.6g} at every point")
    return best


def _short(expr: sp.Expr, limit: int = 120) -> str:
    text = sp.sstr(expr)
    return text if len(text) <= limit else text[:limit - 3] + "..."
