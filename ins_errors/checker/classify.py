"""Classify a discrepancy on two axes: what it is, and how much it matters.

*What it is* (the ``kind``): an omitted term, an extra term, a wrong sign, a wrong
coefficient of the same form (with the ratio when it is constant), a wrong symbol or
index (``u21`` written for ``u11``, a coefficient put on the wrong error quantity), a
wrong function (``cos 2λ`` where no function belongs) or a wrong exponent. Symbol,
function and exponent slips are found by trying the one-place changes that would make
the hand coefficient equal the model's at every reference point.

*How much it matters* (the size, relative to the largest term of the model's side of the
equation, so a wrong term the hand adds cannot shrink another finding) gives the
``severity``: a term that is present but wrong is a ``"mistake"`` whatever its size
(``"mistake, small effect"`` below the threshold); only an omission of a small term is
a ``"dropped small term"``; an omission the author declared (``@neglect``) is a
``"declared drop"``.

*Where it comes from* (the ``role``): each line is compared as written, with the
declared simplifications applied, and isolated (the definitions it uses corrected, each
hand-only helper replaced by the value its simplest use needs): what the declarations
explain is a declared drop, what isolation removes is a *knock-on* of the definitions it
names as roots, what remains is the line's own (*root*) finding
(:func:`line_findings`, :func:`assign_roots`, :func:`helpers`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import lru_cache
from itertools import combinations
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp

from ins_errors.checker.kinds import (  # noqa: F401 (also names of this module)
    COEFFICIENT,
    DECLARED,
    DEFINITION,
    DROPPED,
    EXPONENT,
    EXTRA,
    FUNCTION,
    KINDS,
    LEFT_SIDE,
    MISTAKE,
    NOT_ERROR,
    OMITTED,
    SEVERITIES,
    SIGN,
    SMALL_MISTAKE,
    SYMBOL,
    severity,
)
from ins_errors.checker.parse import HandEquation, HandFile, Problem
from ins_errors.checker.ratio_names import factor_name, ratio_text, trig_factor
from ins_errors.checker.sides import (
    HandSide,
    ModelSide,
    UnresolvedError,
    identified,
    model_expr,
    model_side,
)
from ins_errors.symbolic.symbol_order import sorted_symbols

if TYPE_CHECKING:
    from ins_errors.checker.compare import Comparison, EquationResult, Item

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
        Largest ratio, over the reference points, of the discrepancy to the largest term
        of the model's side of the equation at that point (of the hand's where the model
        has none).
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
    part : bool
        A knock-on that is only part of its coefficient's difference: the line gets the
        same coefficient wrong on its own as well (a root finding for the same quantity
        comes with it). Its size and kind are those of the difference the definitions
        make (as written against isolated); ``hand``/``model`` are the whole
        coefficients.
    pair : tuple of str
        One finding of two lines (:mod:`~ins_errors.checker.line_pairs`: a mirror pair,
        a term in the wrong row): the other half's line (``"line 30 dot(delta_v_N)"``)
        and quantity; empty otherwise. The half that carries the detail and the pair's
        effect has ``merged`` False.
    merged : bool
        This finding is the other half of the pair named by ``pair``: listed under that
        finding, not counted again.
    at_rest : bool
        The two coefficients agree at the static base, where the moving points show the
        difference (a term of a moving base); False when the file is compared at one
        motion only.
    effect : dict
        Effect on the error trajectory (see :mod:`ins_errors.checker.effect`), if
        computed: ``point``; for each time (``1h``, ``24h``) the worst single case's
        ``position_…`` (m) and ``attitude_…`` (rad), their rounding floors
        ``position_floor_…``, ``attitude_floor_…`` and the cases ``position_case_…``,
        ``attitude_case_…`` (None at or below the floor); ``e_folding_s`` (s) when the
        mistake adds a growing mode; ``overflow_…`` (True, the figures inf) when the
        propagation with the mistake overflows floating point.
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
    part: bool = False
    effect: dict = field(default_factory=dict, compare=False)
    pair: tuple[str, ...] = ()
    merged: bool = False
    at_rest: bool = field(default=False, compare=False)

    @property
    def is_mistake(self) -> bool:
        """True for mistakes of any size."""
        return self.severity in (MISTAKE, SMALL_MISTAKE)


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
    return list(_candidates(expr, tuple(known)))


@lru_cache(maxsize=4096)
def _candidates(expr: sp.Expr, known: tuple[sp.Symbol, ...]
                ) -> tuple[tuple[str, str, sp.Expr], ...]:
    """:func:`candidates`: a pure function of its arguments, kept for the next check in
    the same process (a coefficient diagnosed again builds its substitutions once)."""
    out: list[tuple[str, str, sp.Expr]] = []
    for symbol in sorted_symbols(expr.free_symbols):
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
        if _bare(expr, f):  # divided instead of multiplied: cos φ/(R + h) for 1/((R + h) cos φ)
            out.append((EXPONENT, f"{f} multiplies where it divides (exponent 1 where -1 "
                                  "belongs)", expr.xreplace({f: 1 / f})))
    for power in sorted(expr.atoms(sp.Pow), key=sp.default_sort_key):
        if power.exp.is_Rational and not power.base.is_Symbol:
            for e in _exponent_changes(power.exp):
                text = f"exponent {power.exp} where {e} belongs"
                if power.exp == -1 and e == 1 and isinstance(power.base, sp.Function):
                    text = f"{power.base} divides where it multiplies ({text})"
                out.append((EXPONENT, text, expr.xreplace({power: power.base ** e})))
    return tuple(out)


def _bare(expr: sp.Basic, f: sp.Expr) -> bool:
    """True if ``f`` occurs in ``expr`` as a plain factor (not as the base of a power)."""
    if expr == f:
        return True
    if expr.is_Pow:
        return (expr.base != f and _bare(expr.base, f)) or _bare(expr.exp, f)
    return any(_bare(a, f) for a in expr.args)


def diagnose(hand_expr: sp.Expr, model_expr: sp.Expr, hs: np.ndarray, ms: np.ndarray,
             tiny: float, evaluate: Callable[[list[sp.Expr]], np.ndarray | None],
             known: list[sp.Symbol], term_split: Callable | None = None,
             proportional: bool = False, hand_tiny: float | None = None,
             model_tiny: float | None = None,
             factors: list[tuple[str, float]] | None = None) -> tuple[str, str]:
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
    hand_tiny, model_tiny : float, optional
        Below these the hand's (the model's) values are zero: a side has a term unless
        it is negligible against that side's own terms (default ``tiny``). A model term of
        1 against a hand's 1e15 is a wrong coefficient, not an extra term.
    factors : list of (str, float), optional
        Named factors a constant ratio is compared with
        (:func:`~ins_errors.checker.ratio_names.factors`: 2, 1/2, the Earth radius and
        gravity): a ratio that is one is named, ``hand/model = 1.56961e-07 = 1/R (R =
        6.371e+06 m) at every point: a factor 1/R too many?``.

    A constant ratio at a single reference point (``@scope static base``) says nothing
    of a constant factor: there a function slip that makes the hand's coefficient the
    model's (:func:`function_at_one_point`) is named first, with the ratio it gives,
    as a question (``hand/model = cot(phi) at the one reference point: cos(phi) written
    where sin(phi) belongs?``).
    """
    hand_tiny = tiny if hand_tiny is None else hand_tiny
    model_tiny = tiny if model_tiny is None else model_tiny
    if np.all(np.abs(hs) <= hand_tiny):
        return OMITTED, ""
    if np.all(np.abs(ms) <= model_tiny):
        return EXTRA, ""
    scale = np.maximum(np.abs(hs), np.abs(ms))
    if np.all(np.abs(hs + ms) <= TOLERANCE * scale):
        return SIGN, ""
    # a part of the model's coefficient left out (K₂ written for 1 + K₂) is an omitted
    # term even where the two keep a constant ratio (the gain is a constant)
    split = term_split(hand_expr, model_expr) if term_split else None
    if split is not None and split[1] == 0:
        return OMITTED, f"part of the coefficient is missing: {_short(split[0])}"
    if split is not None and split[0] == 0:
        return EXTRA, f"extra part of the coefficient: {_short(split[1])}"
    usable = np.abs(ms) > model_tiny
    ratios = hs[usable] / ms[usable]
    if ratios.size and np.all(np.abs(ratios - ratios[0]) <= TOLERANCE * abs(ratios[0])):
        exponent = exponent_that_fits(hand_expr, ms, tiny, evaluate)
        if exponent is not None:
            return EXPONENT, exponent
        where = "at the one reference point" if ms.size == 1 else "at every point"
        if ms.size == 1:
            swapped = function_at_one_point(hand_expr, ms, tiny, evaluate)
            if swapped is not None:
                return FUNCTION, swapped
        # an exact factor (2, 1/2, R, g) first, then an exact trigonometric one, then a
        # unit factor matched to its rounding (cot 1° = 57.290 is within 1e-4 of the
        # degree's 57.296: the exact name wins)
        if factor_name(float(ratios[0]), factors or [], units=False) is None:
            trig = trig_factor_that_fits(hand_expr, model_expr, ratios, usable, evaluate,
                                         where)
            if trig is not None:
                return COEFFICIENT, trig
        return COEFFICIENT, ratio_text(float(ratios[0]), factors or [], where)
    changed = change_that_fits(hand_expr, ms, tiny, evaluate, known,
                               proportional=proportional,
                               where="at the one reference point" if ms.size == 1
                               else "at every point")
    if changed is not None:
        return changed
    if split is not None and len(sp.sstr(split[0])) + len(sp.sstr(split[1])) < 160:
        return COEFFICIENT, (f"model has {_short(split[0])} where the hand has "
                             f"{_short(split[1])}")
    return COEFFICIENT, ""


def exponent_that_fits(hand_expr: sp.Expr, target: np.ndarray, tiny: float,
                       evaluate: Callable[[list[sp.Expr]], np.ndarray | None]
                       ) -> str | None:
    """The one-place exponent change of a symbol in ``hand_expr`` (``R**2`` for ``R``,
    ``sqrt(R)``, or a bare ``R``) that makes it equal ``target`` (values), as its detail;
    None if none does. A constant ratio of two coefficients that an exponent of a
    parameter explains (hand/model = 1/R) is that slip, not a factor."""
    powers = sorted((p for p in hand_expr.atoms(sp.Pow)
                     if p.base.is_Symbol and p.exp.is_Rational), key=sp.default_sort_key)
    bases = {p.base for p in powers}
    options = [(f"exponent {p.exp} of {p.base} where {e} belongs",
                hand_expr.xreplace({p: p.base ** e}))
               for p in powers for e in _exponent_changes(p.exp)]
    options += [(f"exponent 1 of {x} where {e} belongs", hand_expr.xreplace({x: x ** e}))
                for x in sorted_symbols(hand_expr.free_symbols - bases)
                for e in _exponent_changes(sp.S.One)]
    if not options:
        return None
    values = evaluate([expr for _, expr in options])
    if values is None:
        return None
    scale = np.maximum(np.abs(target), tiny)
    for (text, _), v in zip(options, values, strict=True):
        if np.all(np.isfinite(v)) and np.all(np.abs(v - target) <= TOLERANCE * scale):
            return text
    return None


ONE_POINT = 1e-9
"""Relative agreement of a function slip at a single reference point
(:func:`function_at_one_point`): one number only, so tighter than :data:`TOLERANCE`."""

RATIO_NAMES = {("cos", "sin"): "cot", ("sin", "cos"): "tan"}
"""hand/model of a function written for another, by name (cos for sin: cot)."""


def function_at_one_point(hand_expr: sp.Expr, target: np.ndarray, tiny: float,
                          evaluate: Callable[[list[sp.Expr]], np.ndarray | None]
                          ) -> str | None:
    """The detail of a function slip (sin for cos, a factor cos φ that should not be
    there, ...: the ``wrong function`` changes of :func:`candidates`) that makes
    ``hand_expr`` equal ``target`` at a single reference point, to :data:`ONE_POINT`,
    naming the ratio it gives: ``hand/model = cot(phi) at the one reference point:
    cos(phi) written where sin(phi) belongs?``; None if none does. One point cannot
    tell a function slip from a constant factor, hence the question."""
    options = [(text, changed, f) for f in sorted(
        hand_expr.atoms(sp.sin, sp.cos, sp.tan, sp.cot), key=sp.default_sort_key)
        for kind, text, changed in candidates(hand_expr, [])
        if kind == FUNCTION and text.startswith(f"{f} ")]
    if not options:
        return None
    values = evaluate([changed for _, changed, _ in options])
    if values is None:
        return None
    scale = np.maximum(np.abs(target), tiny)
    for (text, changed, f), v in zip(options, values, strict=True):
        if not (np.all(np.isfinite(v)) and np.all(np.abs(v - target) <= ONE_POINT * scale)):
            continue
        wanted = _replacement(hand_expr, changed, f)
        ratio = (RATIO_NAMES.get((f.func.__name__, wanted.func.__name__))
                 if wanted is not None and wanted.is_Function else None)
        shown = (f"{ratio}({f.args[0]})" if ratio else
                 sp.sstr(f) if wanted is None or wanted == 1 else sp.sstr(f / wanted))
        return f"hand/model = {shown} at the one reference point: {text}?"
    return None


TRIG_ATOMS = (sp.sin, sp.cos, sp.tan, sp.cot, sp.sec, sp.csc)
"""The trigonometric functions whose arguments :func:`trig_factor_that_fits` tries."""


def trig_factor_that_fits(hand_expr: sp.Expr, model_expr: sp.Expr, ratios: np.ndarray,
                          usable: np.ndarray,
                          evaluate: Callable[[list[sp.Expr]], np.ndarray | None],
                          where: str) -> str | None:
    """``"hand/model = 0.8391 = cot(phi) WHERE: a factor tan(phi) missing?"`` when the
    constant ratio is, at every point used, a trigonometric function of an angle either
    coefficient holds (or its inverse: :func:`~ins_errors.checker.ratio_names.
    trig_factor`); None otherwise. Only the angles of the two coefficients are tried,
    to :data:`~ins_errors.checker.ratio_names.EXACT`: one number (a single reference
    point) could match some function of any angle.

    Parameters
    ----------
    hand_expr, model_expr : sympy.Expr
        The two coefficients, in model symbols.
    ratios : numpy.ndarray, shape (used,)
        hand/model at the points where the model's coefficient is not zero.
    usable : numpy.ndarray of bool, shape (points,)
        Those points.
    evaluate : callable
        ``evaluate(exprs)`` -> values, shape (len(exprs), points), or None.
    where : str
        ``at every point`` or ``at the one reference point``.
    """
    angles = sorted({f.args[0] for e in (hand_expr, model_expr)
                     for f in e.atoms(*TRIG_ATOMS)}, key=sp.default_sort_key)
    if not angles or not ratios.size:
        return None
    values = evaluate([g(a) for a in angles for g in (sp.sin, sp.cos)])
    if values is None:
        return None
    values = np.real(np.asarray(values))
    for k, angle in enumerate(angles):
        s, c = values[2 * k][usable], values[2 * k + 1][usable]
        named = {trig_factor(float(r), float(si), float(co), sp.sstr(angle))
                 for r, si, co in zip(ratios, s, c, strict=True)}
        if len(named) == 1 and None not in named:
            shown, says = named.pop()
            return f"hand/model = {ratios[0]:.6g} = {shown} {where}: {says}"
    return None


def _replacement(hand_expr: sp.Expr, changed: sp.Expr, f: sp.Expr) -> sp.Expr | None:
    """What ``f`` was replaced by in ``changed`` (a one-place change of ``hand_expr``)."""
    for g in (sp.S.One, sp.sin(f.args[0]), sp.cos(f.args[0]), sp.tan(f.args[0]),
              f.func(f.args[0] / 2)):
        if hand_expr.xreplace({f: g}) == changed:
            return g
    return None


def change_that_fits(hand_expr: sp.Expr, target: np.ndarray, tiny: float,
                     evaluate: Callable[[list[sp.Expr]], np.ndarray | None],
                     known: list[sp.Symbol], limit: int = 60, proportional: bool = False,
                     where: str = "at every point") -> tuple[str, str] | None:
    """The one-place change of ``hand_expr`` that makes it equal ``target`` (values), or
    proportional to it, as (kind, detail; a proportional one with the ratio ``where``:
    ``at every point``, ``at the one reference point``); None if none does."""
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
                best = (kind, f"{text}; then hand/model = {r[0]:.6g} {where}")
    return best


def _short(expr: sp.Expr, limit: int = 120) -> str:
    text = sp.sstr(expr)
    return text if len(text) <= limit else text[:limit - 3] + "..."


# -- declared simplifications ----------------------------------------------------------
class Declarations:
    """The ``@neglect`` lines: variations dropped (model side) and terms left out."""

    def __init__(self, hand: HandFile, resolver: HandSide, side: ModelSide):
        self.hand = hand
        self.dropped: list[frozenset[str]] = []
        self.terms: list[list[sp.Expr]] = []
        self.used = [False] * len(hand.declarations)
        self.side = side
        self.zeroed: list[frozenset[sp.Symbol]] = []
        plain = {v.name for v in (*side.d.states, *side.d.inputs, *side.d.parameters)}
        for declaration in hand.declarations:
            names, terms, zeroed = set(), [], set()
            for item, text in zip(declaration.items, declaration.texts, strict=True):
                if isinstance(item, sp.Symbol) and resolver.variation_base(item.name) is None \
                        and not resolver.is_variational(item):
                    meaning = resolver.model_meaning(item.name)
                    if meaning is not None and meaning.is_Symbol and meaning.name in plain:
                        zeroed.add(meaning)  # a quantity neglected: h against R (h << R)
                        continue
                base = (resolver.variation_base(item.name) if isinstance(item, sp.Symbol)
                        else None)
                if base is not None:
                    meaning = resolver.model_meaning(base)
                    inner = ({s.name for s in meaning.free_symbols} & side.intermediates
                             if meaning is not None else set())
                    if base in side.intermediates:
                        inner = {base}
                    if not inner:
                        hand.problems.append(Problem(declaration.line, None, (
                            f"@neglect {text}: {base} has no variation in the model "
                            "(not an intermediate quantity)")))
                    names |= inner
                    continue
                try:
                    resolver.trace = set()
                    terms.append(resolver.resolve(item, len(hand.sections) - 1, ()))
                except UnresolvedError as error:
                    hand.problems.append(Problem(declaration.line, None,
                                                 f"@neglect {text}: {error.message}"))
            self.dropped.append(frozenset(names))
            self.terms.append(terms)
            self.zeroed.append(frozenset(zeroed))
        self.term_values: list[list[dict]] = []

    def finish(self, comparison: Comparison, identify: dict) -> None:
        """Evaluate the declared terms' coefficients at the reference points."""
        for terms in self.terms:
            evaluated = []
            for term in terms:
                try:
                    parts, _ = comparison.linear_parts(term.xreplace(identify))
                    evaluated.append({b: comparison.evaluate([c])[0] for b, c in parts.items()})
                except UnresolvedError:
                    continue
            self.term_values.append(evaluated)

    def dropped_for(self, eq: HandEquation) -> frozenset[str]:
        return frozenset().union(*(self.dropped[k] for k in eq.declarations))

    def zeroed_for(self, eq: HandEquation, expanded: dict[sp.Symbol, sp.Expr]
                   ) -> dict[sp.Symbol, sp.Expr]:
        """The substitution that sets the quantities ``eq``'s declarations neglect
        (``@neglect h : h << R``) to 0 on both sides: each such quantity, and each named
        intermediate whose expression holds one (``r_E`` = R_E + h becomes R_E), by its
        expression with them at 0 (``expanded``: the model's named intermediates as
        expressions of states, inputs and parameters). Empty when none is declared."""
        zero = frozenset().union(*(self.zeroed[k] for k in eq.declarations))
        if not zero:
            return {}
        rule: dict[sp.Symbol, sp.Expr] = {s: sp.S.Zero for s in zero}
        for symbol, expr in expanded.items():
            if expr.free_symbols & zero:
                rule[symbol] = expr.xreplace(rule)
        return rule

    def explains_term(self, eq: HandEquation, quantity: str, difference: np.ndarray,
                      comparison: Comparison) -> bool:
        """True if a declared term of ``eq``'s scope is the model-minus-hand difference."""
        for k in eq.declarations:
            for values in self.term_values[k] if k < len(self.term_values) else []:
                for b, v in values.items():
                    if str(b) != quantity:
                        continue
                    scale = np.maximum(np.abs(v), np.abs(difference))
                    if np.all(np.abs(np.abs(difference) - np.abs(v)) <= 1e-6 * np.maximum(
                            scale, 1e-300)):
                        self.used[k] = True
                        return True
        return False

    def mark(self, eq: HandEquation) -> None:
        for k in eq.declarations:
            if self.dropped[k] or self.zeroed[k]:
                self.used[k] = True

    def texts(self) -> list[str]:
        return [f"line {d.line}: {', '.join(d.texts)}" + (f" ({d.reason})" if d.reason else "")
                for d in self.hand.declarations]

    def idle(self) -> list[str]:
        return [f"line {d.line}: {', '.join(d.texts)}"
                for d, used in zip(self.hand.declarations, self.used, strict=True) if not used]


# -- hand-only helpers ------------------------------------------------------------------
@dataclass
class Needed:
    """The value a hand-only helper must have, from its simplest use."""

    expr: sp.Expr
    description: str
    line: int


def helpers(hand: HandFile, prepared: list[list[Item]], resolver: HandSide,
             comparison: Comparison, identify: dict, declared: Declarations
             ) -> dict[str, Needed]:
    """Needed value of each hand-only helper (ideal quantity with no model meaning)."""
    helpers: dict[str, list[HandEquation]] = {}
    for eq, items in zip(hand.equations, prepared, strict=True):
        if isinstance(eq.lhs, sp.Symbol) and items and items[0].target == "hand-only definition" \
                and resolver.variation_base(eq.lhs.name) is None:
            helpers.setdefault(eq.lhs.name, []).append(eq)
    needed: dict[str, Needed] = {}
    for name, definitions in helpers.items():
        ids = {id(e) for e in definitions}
        uses = []
        for eq, items in zip(hand.equations, prepared, strict=True):
            for item in items:
                if item.key is None or item.ideal or item.hand is None or not (item.deps & ids):
                    continue
                form = eq.forms[item.form]
                uses.append((len(form.free_symbols), sp.count_ops(form), eq, item))
        for _, _, eq, item in sorted(uses, key=lambda u: (u[0], u[1], u[2].line)):
            found = _solve_helper(name, eq, item, resolver, comparison, identify, declared)
            if found is not None:
                needed[name] = found
                break
    return needed


def _solve_helper(name: str, eq: HandEquation, item: Item, resolver: HandSide,
                  comparison: Comparison, identify: dict, declared: Declarations
                  ) -> Needed | None:
    """The helper value that makes ``eq`` agree with the model (None if not unique)."""
    helper = sp.Symbol(name, real=True)
    resolver.symbolic = {name}
    try:
        hand = resolver.resolve(eq.forms[item.form], eq.section,
                                (resolver.definition_key(eq),) if isinstance(
                                    eq.lhs, sp.Symbol) else ())
    except UnresolvedError:
        return None
    finally:
        resolver.symbolic = set()
    side = model_side(resolver.model.d, declared.dropped_for(eq))
    model = identified(model_expr(side, item.key), identify)
    try:
        h, _ = comparison.linear_parts(hand)
        m, _ = comparison.linear_parts(model, trusted=True)
    except UnresolvedError:
        return None
    candidates = []
    for b, coefficient in h.items():
        c1 = sp.diff(coefficient, helper)
        if c1 == 0 or sp.diff(c1, helper) != 0:
            continue
        c0 = coefficient.xreplace({helper: sp.S.Zero})
        candidates.append((m.get(b, sp.S.Zero) - c0) / c1)
    if not candidates:
        return None
    values = comparison.try_evaluate(candidates)
    if values is None or not np.all(np.isfinite(values)):
        return None
    if not np.all(np.abs(values - values[0]) <= 1e-6 * np.maximum(np.abs(values[0]), 1e-300)):
        return None
    form = eq.forms[item.form]
    shown = f"{eq.label} = {sp.sstr(form)}"
    what = f"the value line {eq.line} ({shown}) needs"
    if isinstance(eq.lhs, sp.Symbol) and resolver.variation_base(eq.lhs.name):
        rest = sp.simplify(form / sp.Symbol(name))
        if rest.is_Symbol and resolver.variation_base(rest.name):
            what = (f"d{resolver.variation_base(eq.lhs.name)}/d"
                    f"{resolver.variation_base(rest.name)}, as line {eq.line} ({shown}) "
                    "needs")
    return Needed(candidates[0], what, eq.line)


def set_status(result: EquationResult) -> None:
    findings = result.findings
    if any(f.is_mistake for f in findings):
        result.status = "mistake"
    elif any(f.severity == DROPPED for f in findings):
        result.status = "agrees up to dropped small terms"
    elif findings:
        result.status = "agrees up to declared drops"
    else:
        result.status = "agrees"


def line_findings(eq: HandEquation, item: Item, comparison: Comparison, identify: dict,
                   resolver: HandSide, declared: Declarations,
                   needed: dict[str, Needed], result: EquationResult) -> list[Finding]:
    """Findings of one line: as written, with declared drops, isolated (see module doc).

    Only differences from the exact model count; the declared and isolated comparisons
    say what each one is: a declared drop (gone once the declaration is applied), a
    knock-on (gone once the definitions the line uses are correct) or the line's own.
    A difference that isolation changes without removing is both: the line's own
    finding (what remains) and a knock-on *part* (what the definitions add, from the
    line as written against the line isolated), so a definition's mistake reaches every
    line that uses it, whatever else the line gets wrong.
    """
    full = comparison.compare(item.hand, item.model_full, item.hand_display, diagnose=False)
    if not full:
        return []
    hand_declared = item.hand if item.hand_declared is None else item.hand_declared
    dropped = hand_declared is not item.hand or (
        item.model_declared is not item.model_full and item.model_declared != item.model_full)
    with_declared = (comparison.compare(hand_declared, item.model_declared, item.hand_display,
                                        diagnose=False) if dropped else full)
    declared_quantities = {f.quantity for f in with_declared}
    own = {f.quantity: f for f in comparison.compare(
        item.hand_isolated, item.model_declared, item.hand_display,
        trusted=item.hand_isolated is not item.hand)}
    names = {b.name: s for b, s in zip(comparison.basis, comparison.symbols, strict=True)}
    raw = None
    parts: dict[str, Finding] | None = None
    findings = []
    for f in full:
        if f.quantity not in declared_quantities:
            declared.mark(eq)
            findings.append(replace(f, severity=DECLARED, kind=OMITTED,
                                    detail="left out by the file's declared simplification"))
            continue
        mine = own.get(f.quantity)
        if mine is None:
            shown = next(g for g in with_declared if g.quantity == f.quantity)
            findings.append(replace(shown, role=KNOCK_ON))
            continue
        if eq.declarations and f.quantity in names:
            if raw is None:
                raw = comparison.differences(hand_declared, item.model_declared)[0]
            info = raw.get(names[f.quantity])
            if info is not None and declared.explains_term(
                    eq, f.quantity, info["model"] - info["hand"], comparison):
                findings.append(replace(mine, severity=DECLARED, kind=OMITTED,
                                        detail="a term the file declares it leaves out"))
                continue
        findings.append(mine)
        if item.hand_isolated is hand_declared:
            continue
        if parts is None:  # what the definitions the line uses change, term by term
            parts = {g.quantity: g for g in comparison.compare(
                hand_declared, item.hand_isolated, item.hand_display, diagnose=False,
                trusted=True, reference=item.model_declared)}
        part = parts.get(f.quantity)
        if part is not None and part.severity != DROPPED:
            shown = next(g for g in with_declared if g.quantity == f.quantity)
            findings.append(replace(
                part, role=KNOCK_ON, part=True, hand=shown.hand, model=shown.model,
                detail="the part of this coefficient's difference that the definitions "
                       "used bring (the line's own part is listed as its own)"))
    return findings


def assign_roots(results: list[EquationResult], prepared: list[list[Item]],
                  hand: HandFile) -> None:
    """Name, for each knock-on finding, the wrong definitions it comes from."""
    by_equation: dict[int, EquationResult] = {}
    for r in results:
        if r.form == 0 or id(r.equation) not in by_equation:
            by_equation.setdefault(id(r.equation), r)
    items = {}
    for eq, its in zip(hand.equations, prepared, strict=True):
        for it in its:
            items[(id(eq), it.form)] = it
    for r in results:
        item = items.get((id(r.equation), r.form))
        if item is None or not any(f.role == KNOCK_ON for f in r.findings):
            continue
        sources = [by_equation[i] for i in sorted(item.deps, key=lambda i: by_equation[i]
                                                  .equation.line if i in by_equation else 0)
                   if i in by_equation]
        wrong = [s for s in sources if any(f.role == ROOT and f.is_mistake
                                           for f in s.findings)]
        dropping = [s for s in sources if s.findings and s not in wrong]
        updated = []
        for f in r.findings:
            if f.role != KNOCK_ON:
                updated.append(f)
                continue
            if f.part and not wrong:
                continue  # the line's own finding for this quantity says it all
            if wrong:
                updated.append(replace(f, roots=tuple(s.reference for s in wrong)))
            elif dropping:
                classes = {g.severity for s in dropping for g in s.findings}
                severity = f.severity
                if classes == {DECLARED}:
                    severity = DECLARED
                elif classes <= {DECLARED, DROPPED} and f.severity != MISTAKE:
                    severity = DROPPED
                updated.append(replace(f, roots=tuple(s.reference for s in dropping),
                                       severity=severity,
                                       kind=OMITTED if severity in (DECLARED, DROPPED)
                                       else f.kind))
            else:
                updated.append(replace(f, role=ROOT))
        r.findings = updated
        set_status(r)


# -- one undeclared omission behind several findings ------------------------------------
SCOPE_STATIC = "@scope static base"
"""The directive that limits a file to the static base."""


@dataclass
class Omission:
    """A variation of named intermediates the file drops without declaring it.

    Every finding it groups disappears exactly once the model side drops these
    variations too, as ``@neglect`` would (:func:`undeclared_variations`); the findings
    become its knock-ons, all of its class.

    Attributes
    ----------
    variations : tuple of str
        The variations as the file would declare them (``"Delta_R_N"``).
    quantities : tuple of str
        The quantities varied, in the file's names (``"R_N"``).
    along : tuple of str
        What they vary with: the states (or sources) of their variations (``"phi"``).
    lines : tuple of int
        The lines whose findings it explains.
    severity : str
        Its class, by the largest of its findings: an undeclared omission is judged by
        size (:data:`DROPPED` below the threshold, :data:`MISTAKE` above).
    size : float
        The largest size of its findings.
    point : str
        Where that size is reached.
    at_rest : bool
        Every finding it groups is 0 at rest, in a file whose equations hold no quantity
        of the motion (:func:`~ins_errors.checker.compare.static_base_advice`): the
        moving-base terms a static-base derivation leaves out, which ``@scope static
        base`` declares (:attr:`advice`).
    meanings : tuple of str
        What the quantities the file never writes are, as the model defines them
        (``"turn_rate = 2*U*sin(phi) + V_E*tan(phi)/r_E"``): a name of the model's own
        means nothing to the file's reader otherwise.
    """

    variations: tuple[str, ...]
    quantities: tuple[str, ...]
    along: tuple[str, ...]
    lines: tuple[int, ...]
    severity: str
    size: float
    point: str
    at_rest: bool = False
    meanings: tuple[str, ...] = ()

    @property
    def reference(self) -> str:
        """How its knock-ons name it (their ``roots``)."""
        return f"the undeclared drop of {', '.join(self.variations)}"

    @property
    def title(self) -> str:
        """``the variation of R_N, R_E with phi is dropped (not declared): explains
        lines 3, 5, 8``."""
        meaning = f" (the model's {'; '.join(self.meanings)})" if self.meanings else ""
        return (f"the variation of {', '.join(self.quantities)}{meaning} with "
                f"{', '.join(self.along)} is dropped (not declared): explains "
                f"line{'s' * (len(self.lines) > 1)} {', '.join(map(str, self.lines))}")

    @property
    def neglect(self) -> str:
        """The ``@neglect`` line that would declare it."""
        return (f"@neglect {', '.join(self.variations)} : variation of "
                f"{', '.join(self.quantities)} with {', '.join(self.along)} neglected")

    @property
    def advice(self) -> str:
        """How the file would declare it: ``@scope static base (...)`` for the
        moving-base terms of a static-base derivation (:attr:`at_rest`), else the
        ``@neglect`` line (:attr:`neglect`)."""
        if self.at_rest:
            return (f"{SCOPE_STATIC} (every finding below is 0 at rest: moving-base terms a "
                    "static-base derivation leaves out)")
        return self.neglect

    @property
    def is_mistake(self) -> bool:
        return self.severity in (MISTAKE, SMALL_MISTAKE)


def undeclared_variations(results: list[EquationResult], prepared: list[list[Item]],
                          hand: HandFile, resolver: HandSide, comparison: Comparison,
                          identify: dict, declared: Declarations, threshold: float
                          ) -> list[Omission]:
    """Group the findings that one undeclared dropped variation explains.

    For each line's own findings (roots, not declared drops) and each named intermediate
    of the model whose variation the line's model side holds, the model side is rebuilt
    with that variation dropped (as ``@neglect Delta_X`` does; two at once where one does
    not suffice): a finding it removes, while the line gains no new one, is explained by
    it. Each variation is taken in turn, the one explaining most findings first; the
    variations that vary with the same error quantities (R_N and R_E with latitude) form
    one omission, kept when it explains two findings or more. Its findings become its
    knock-ons, all of its class (by its largest size: the file does not declare it), and
    so do the knock-ons of a definition whose own findings it explains. ``results`` are
    updated in place.
    """
    side = resolver.model
    d = side.d
    candidates = [name for name, delta in side.delta_of.items()
                  if name in side.intermediates and delta != 0]
    items = {(id(eq), it.form): it for eq, its in zip(hand.equations, prepared, strict=True)
             for it in its}
    explains: dict[tuple[int, str], list[frozenset[str]]] = {}  # (result, quantity) -> sets
    owned: dict[int, EquationResult] = {}
    for index, r in enumerate(results):
        item = items.get((id(r.equation), r.form))
        if item is None or item.key is None or item.ideal or item.hand_isolated is None \
                or item.model_declared is None:
            continue
        own = {f.quantity for f in r.findings if f.role == ROOT and f.severity != DECLARED
               and not f.part and not f.quantity.startswith("(")
               and " -> " not in f.quantity and np.isfinite(f.size)}
        if not own:
            continue
        owned[index] = r
        base = declared.dropped_for(r.equation)
        zero = declared.zeroed_for(r.equation, comparison.expand_model)
        try:
            before = set(comparison.differences(item.hand_isolated, item.model_declared)[0])
        except UnresolvedError:
            continue

        def trial(names: frozenset[str], item=item, base=base, zero=zero, before=before
                  ) -> set[str] | None:
            model = identified(model_expr(model_side(d, base | names), item.key), identify)
            if zero:
                model = model.xreplace(zero)
            if model == item.model_declared:
                return None
            try:
                after = set(comparison.differences(item.hand_isolated, model)[0])
            except UnresolvedError:
                return None
            if after - before:
                return None  # the hand has the variation elsewhere in this line
            return {str(b) for b in before - after}

        touching = []
        for name in candidates:
            if name in base:
                continue
            gone = trial(frozenset((name,)))
            if gone is None:
                continue
            touching.append(name)
            for q in gone & own:
                explains.setdefault((index, q), []).append(frozenset((name,)))
        left = [q for q in own if (index, q) not in explains]
        if left:
            for a, b in combinations(touching, 2):
                gone = trial(frozenset((a, b)))
                for q in (gone or set()) & set(left):
                    explains.setdefault((index, q), []).append(frozenset((a, b)))
    if not explains:
        return []
    # the variation (or pair) explaining most findings first
    chosen: dict[tuple[int, str], frozenset[str]] = {}
    while True:
        counts: dict[frozenset[str], int] = {}
        for key, sets in explains.items():
            if key in chosen:
                continue
            for s in sets:
                counts[s] = counts.get(s, 0) + 1
        if not counts:
            break
        best = min(counts, key=lambda s: (-counts[s], len(s), sorted(s)))
        for key, sets in explains.items():
            if key not in chosen and best in sets:
                chosen[key] = best
    # variations that vary with the same error quantities form one omission
    basis = set(comparison.symbols)

    def along(name: str) -> frozenset[sp.Symbol]:
        return frozenset(side.delta_of[name].free_symbols & basis)

    groups: dict[frozenset, set[tuple[int, str]]] = {}
    names_of: dict[frozenset, set[str]] = {}
    for key, names in chosen.items():
        group = frozenset().union(*(along(n) for n in names))
        groups.setdefault(group, set()).add(key)
        names_of.setdefault(group, set()).update(names)
    omissions = []
    for group, keys in sorted(groups.items(), key=lambda g: min(
            results[i].equation.line for i, _ in g[1])):
        if len(keys) < 2:
            continue
        model_names = [n for n in candidates if n in names_of[group]]
        shown = [_file_name(n, resolver, hand) for n in model_names]
        state_of = {v: k for k, v in side.error_of_state.items()}
        with_ = [state_of.get(b, str(b)) for b in sorted_symbols(group)]
        findings = [(results[i], f) for i, q in sorted(keys) for f in results[i].findings
                    if f.quantity == q and f.role == ROOT and f.severity != DECLARED
                    and not f.part]
        largest = max(findings, key=lambda p: p[1].size)[1]
        omission = Omission(
            tuple(f"Delta_{n}" for n in shown), tuple(shown), tuple(with_),
            tuple(sorted({r.equation.line for r, _ in findings})),
            severity(OMITTED, largest.size, threshold), largest.size, largest.point,
            meanings=_meanings(d, [m for m, f in zip(model_names, shown, strict=True)
                                   if m == f]))
        names = {id(f): [_file_name(n, resolver, hand) for n in model_names
                         if n in chosen[(i, f.quantity)]]
                 for i, q in keys for f in results[i].findings if f.quantity == q}
        _regroup(omission, findings, results, names)
        omissions.append(omission)
    return omissions


MEANING_LENGTH = 80
"""Longest definition an omission's title quotes (a longer one is left to the model's
generated error_equations.md)."""


def _meanings(d, names: list[str]) -> tuple[str, ...]:
    """``name = expression`` of each model intermediate in ``names`` the file does not
    write itself, as the model's ideal work defines it (short ones only)."""
    defined = {df.symbol.name: df.expression for df in d.ideal.definitions}
    out = []
    for name in names:
        if name in defined:
            text = f"{name} = {sp.sstr(defined[name])}"
            if len(text) <= MEANING_LENGTH:
                out.append(text)
    return tuple(out)


def _file_name(name: str, resolver: HandSide, hand: HandFile) -> str:
    """The file's name for a model intermediate: an alias of the file's own that stands
    for it (``R_E`` = ``r_E - h``), else the model's name."""
    for alias in hand.notation.aliases:
        try:
            meaning = resolver.alias(alias)
        except UnresolvedError:
            continue
        if {s.name for s in meaning.free_symbols} & resolver.model.intermediates == {name}:
            return alias
    return name


def _regroup(omission: Omission, findings: list[tuple[EquationResult, Finding]],
             results: list[EquationResult], names: dict[int, list[str]]) -> None:
    """Make ``findings`` knock-ons of ``omission`` (its class and kind; ``names``: the
    variations each one lacks), and the knock-ons of a definition left with no finding
    of its own likewise."""
    mine = {id(f) for _, f in findings}
    touched = {id(r): r for r, _ in findings}

    def detail(f: Finding) -> str:
        text = (f"left out with the variation of "
                f"{', '.join(names.get(id(f)) or omission.quantities)}")
        return text + (f"; {f.detail}" if f.detail else "")

    for r in touched.values():
        r.findings = [replace(f, role=KNOCK_ON, roots=(omission.reference,),
                              severity=omission.severity, kind=OMITTED, detail=detail(f))
                      if id(f) in mine else f for f in r.findings]
    cleared = {r.reference for r in touched.values()
               if not any(f.role == ROOT and f.severity != DECLARED for f in r.findings)}
    for r in results:
        if any(f.role == KNOCK_ON and f.roots and set(f.roots) <= cleared
               for f in r.findings):
            r.findings = [replace(f, roots=(omission.reference,), severity=omission.severity,
                                  kind=OMITTED)
                          if f.role == KNOCK_ON and f.roots and set(f.roots) <= cleared
                          else f for f in r.findings]
            touched[id(r)] = r
    for r in touched.values():
        set_status(r)


# -- one slip of a hand line behind several findings ------------------------------------
LINE = "(line)"
"""Quantity of a line's root finding that one symbol change explains (its per-quantity
findings are its knock-ons)."""


def _same_kind(a: str, b: str) -> bool:
    """True if the names ``a`` and ``b`` differ in one index or axis: ``u12``/``u21``,
    ``delta_u11``/``delta_u12``, ``V_N``/``V_E``, ``Delta_omega_rel_xi``/``..._eta`` (not
    ``V_N``/``a_N``: the first part is what the quantity is)."""
    pa, pb = a.split("_"), b.split("_")
    if a == b or len(pa) != len(pb):
        return False
    differ = [i for i, (x, y) in enumerate(zip(pa, pb, strict=True)) if x != y]
    if len(differ) != 1:
        return False
    x, y = pa[differ[0]], pb[differ[0]]
    if any(c.isdigit() for c in x + y):  # u12 / u21: the same letters, other digits
        return (len(x) == len(y) and any(c.isdigit() for c in x)
                and any(c.isdigit() for c in y)
                and all(c == d for c, d in zip(x, y, strict=True)
                        if not (c.isdigit() and d.isdigit())))
    return differ[0] > 0 and x.isalpha() and y.isalpha()


def _line_changes(form: sp.Expr, pool: list[str]
                  ) -> list[tuple[str, sp.Expr, sp.Expr, str, sp.Expr]]:
    """One-place changes of a printed line: (kind, written, belongs, description, change
    of the form) for each symbol of a term (or of the whole line, where it is in several
    terms) replaced by a same-kind name of ``pool`` (:func:`_same_kind`), each sin ↔ cos
    and each trigonometric factor left out."""
    terms = sp.Add.make_args(form)
    out: dict[sp.Expr, tuple[str, sp.Expr, sp.Expr, str, sp.Expr]] = {}
    for term in terms:
        swaps = [(SYMBOL, s, sp.Symbol(o, real=True), None)
                 for s in sorted_symbols(term.free_symbols)
                 for o in pool if _same_kind(s.name, o)]
        for f in sorted(term.atoms(sp.sin, sp.cos, sp.tan, sp.cot), key=sp.default_sort_key):
            if f.func in (sp.sin, sp.cos):
                swaps.append((FUNCTION, f, (sp.cos if f.func == sp.sin else sp.sin)(
                    f.args[0]), None))
            swaps.append((FUNCTION, f, sp.S.One, f"{f} should not be there"))
        for kind, old, new, text in swaps:
            whole = [t for t in terms if t.has(old)]
            for scope in ([term, form] if len(whole) > 1 else [term]):
                change = scope.xreplace({old: new}) - scope
                if change != 0 and change not in out:
                    out[change] = (kind, old, new,
                                   text or f"{old} written where {new} belongs", change)
    return list(out.values())


def _shown_name(name: str, eq: HandEquation, hand: HandFile, notation) -> str:
    """The file's own spelling of a name read through the notation (``Delta_u12`` for
    ``delta_u12``): the one the line writes, else the one the file writes elsewhere."""
    import re

    spellings = [w for w, meaning in notation.spellings.items() if meaning == name]
    for text in (eq.text, *(e.text for e in hand.equations)):
        for written in spellings:
            if re.search(rf"(?<![A-Za-z0-9_]){re.escape(written)}(?![A-Za-z0-9_])", text):
                return written
    return name


def line_slips(results: list[EquationResult], prepared: list[list[Item]], hand: HandFile,
               resolver: HandSide, comparison: Comparison, declared: Declarations,
               needed: dict[str, Needed], threshold: float) -> None:
    """Group a line's own findings that one symbol change on the line explains.

    A slip in one symbol of a printed line (``u12`` written where ``u21`` belongs, in a
    term whose definition expands into several error quantities) shows on every quantity
    it reaches. For each line with two or more own mistakes (or one unnamed wrong
    coefficient), each same-kind change of one symbol of a term, each sin ↔ cos and each
    trigonometric factor left out (:func:`_line_changes`) is tried, on the line isolated
    (the definitions it uses corrected) and as written: a change that removes every own
    mistake, and brings no new difference, is the line's one root finding (:data:`LINE`,
    kind :data:`SYMBOL` or :data:`FUNCTION`, ``hand`` the name written and ``model`` the
    one that belongs, the largest size of the findings it explains); those findings
    become its knock-ons (their ``roots``: the line itself). A cheap numeric look (the
    change's coefficients against the line's differences at the reference points) picks
    the change; the full comparisons confirm it. ``results`` are updated in place.
    """
    items = {(id(eq), it.form): it for eq, its in zip(hand.equations, prepared, strict=True)
             for it in its}
    pool: list[str] | None = None
    for r in results:
        item = items.get((id(r.equation), r.form))
        if item is None or item.key is None or item.ideal or item.hand_isolated is None \
                or item.model_declared is None:
            continue
        own = [f for f in r.findings if f.role == ROOT and f.is_mistake and not f.part]
        if not own or (len(own) == 1 and not (own[0].kind == COEFFICIENT and (
                not own[0].detail or own[0].detail.startswith("model has")))):
            continue
        quantities = {q for f in own for q in f.quantity.split(" -> ")}
        if not quantities <= {str(b) for b in comparison.symbols}:
            continue  # a constant term, a left-hand side: no symbol change of a term
        if pool is None:
            pool = _name_pool(hand, resolver)
        kept = {q for f in r.findings if f.role == KNOCK_ON and f.is_mistake
                for q in f.quantity.split(" -> ")}
        found = _fitting_change(r.equation, item, quantities, kept, pool, resolver,
                                comparison, declared, needed)
        if found is None:
            continue
        kind, old, new, text = found
        written, belongs = (_shown_name(str(n), r.equation, hand, resolver.notation)
                            for n in (old, new))
        if kind == SYMBOL:
            text = f"{written} written where {belongs} belongs"
        largest = max(own, key=lambda f: f.size)
        root = Finding(LINE, kind, severity(kind, largest.size, threshold), largest.size,
                       largest.point, written, belongs,
                       f"{text} (one change on the line; it explains "
                       f"{len(own)} finding{'s' * (len(own) > 1)}: "
                       f"{', '.join(f.quantity for f in own)})",
                       at_rest=all(f.at_rest for f in own))
        mine = {id(f) for f in own}
        r.findings = [root] + [
            replace(f, role=KNOCK_ON, roots=(r.reference,),
                    detail=f.detail if f.detail.startswith(text)
                    else f"through {text}" + (f"; {f.detail}" if f.detail else ""))
            if id(f) in mine else f for f in r.findings]
        set_status(r)


def _name_pool(hand: HandFile, resolver: HandSide) -> list[str]:
    """Names a slip may have put in a line's place: the file's own and the model's states,
    inputs, parameters and error states."""
    d = resolver.model.d
    names = {s.name for eq in hand.equations for form in eq.forms for s in form.free_symbols}
    names |= {v.name for v in (*d.states, *d.inputs, *d.parameters)}
    names |= set(resolver.model.error_states)
    return sorted(names)


def _fitting_change(eq: HandEquation, item: Item, quantities: set[str], kept: set[str],
                    pool: list[str], resolver: HandSide, comparison: Comparison,
                    declared: Declarations, needed: dict[str, Needed]
                    ) -> tuple[str, sp.Expr, sp.Expr, str] | None:
    """(kind, written, belongs, description) of the one change of ``eq``'s printed form
    (:func:`_line_changes`) that removes the line's own findings (on ``quantities``) and
    brings no new one, or None.

    The change is made on the line isolated (the definitions it uses corrected: what
    remains there is the line's own) and on the line as written (a finding isolation
    removes, with no wrong definition behind it, is the line's own too); ``kept``: the
    quantities of the line's knock-ons from wrong definitions, which stay.
    """
    changes = _line_changes(eq.forms[item.form], pool)
    if not changes:
        return None
    hand_declared = item.hand if item.hand_declared is None else item.hand_declared

    def found(hand: sp.Expr, model: sp.Expr | None = None) -> set[str]:
        return {q for f in comparison.compare(
                    hand, item.model_declared if model is None else model, diagnose=False,
                    trusted=True)
                for q in f.quantity.split(" -> ")}

    def written_found(full: sp.Expr, with_declared: sp.Expr) -> set[str]:
        """The quantities the line as written has findings on that are not declared
        drops (:func:`line_findings`: differences from the exact model that remain with
        the declared simplifications)."""
        return found(full, item.model_full) & found(with_declared)

    try:
        raw, scale, _ = comparison.differences(item.hand_isolated, item.model_declared,
                                               trusted=True)
        isolated = found(item.hand_isolated)
        written = written_found(item.hand, hand_declared)
    except UnresolvedError:
        return None
    zero = declared.zeroed_for(eq, comparison.expand_model)
    trail = (resolver.definition_key(eq),) if isinstance(eq.lhs, sp.Symbol) else ()
    dropped = declared.dropped_for(eq)
    side = model_side(resolver.model.d, dropped) if dropped else resolver.model

    def resolved(change: sp.Expr, isolate: bool, zeroed: bool = True) -> sp.Expr | None:
        """The change in basis and model symbols (None if it does not resolve)."""
        saved = (resolver.trace, set(resolver.used_definitions), set(resolver.sources_used),
                 {k: set(v) for k, v in resolver.from_model.items()}, resolver.current_line)
        if isolate:
            resolver.isolate = side
            resolver.needed = {k: v.expr for k, v in needed.items()}
        resolver.current_line, resolver.trace = eq.line, set()
        try:
            delta = resolver.resolve(change, eq.section, trail)
            return delta.xreplace(zero) if zero and zeroed else delta
        except UnresolvedError:
            return None
        finally:
            resolver.isolate, resolver.needed = None, {}
            (resolver.trace, resolver.used_definitions, resolver.sources_used,
             resolver.from_model, resolver.current_line) = saved

    weights = comparison.magnitude
    own_isolated = quantities & isolated
    for kind, old, new, text, change in changes:
        delta = resolved(change, isolate=True)
        if delta is None:
            continue
        try:
            parts, constant = comparison.linear_parts(delta)
        except UnresolvedError:
            continue
        if constant != 0 or not parts or any(
                parts.get(b, sp.S.Zero) == 0 for b in comparison.symbols
                if str(b) in own_isolated):
            continue  # it leaves an own finding's coefficient as it is
        # a cheap look first: the change's coefficients against the differences
        values = comparison.try_evaluate(list(parts.values()))
        if values is None:
            continue
        fits = True
        for b, v in zip(parts, values, strict=True):
            info = raw.get(b)
            target = (info["model"] - info["hand"]) if (
                info is not None and str(b) in quantities) else 0.0
            if not np.all(np.isfinite(v)) or np.any(
                    np.abs(v - target) * weights.get(b, 1.0) > TOLERANCE * scale):
                fits = False
                break
        if not fits:
            continue
        try:  # the full comparisons: nothing of the line's own is left, nothing new
            after_isolated = found(item.hand_isolated + delta)
            if after_isolated & quantities or after_isolated - isolated:
                continue
            as_written = resolved(change, isolate=False, zeroed=False)
            if as_written is None:
                continue
            after = written_found(item.hand + as_written,
                                  hand_declared + (as_written.xreplace(zero) if zero
                                                   else as_written))
        except UnresolvedError:
            continue
        # what stays is a knock-on of a wrong definition (kept), nothing new
        if (after & quantities) - kept or after - written or (
                after & after_isolated) - (written & isolated):
            continue
        return kind, old, new, text
    return None
