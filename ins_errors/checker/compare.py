"""Term-by-term audit of hand-written error equations against the mechanical variation.

Both sides of every hand equation are brought to a linear combination of the *basis*:
the model's error states and the error sources the hand file considers (after the
notation's identifications, e.g. ``Delta_a`` for both accelerometer biases). The hand
side goes through the hand file's own definitions (its ΔW, Δg', D, ...); a variation the
hand file uses but never defines (ΔR_η, ΔV_ζ) is taken from the model and listed. The
mechanical side goes through the model's varied intermediates
(:func:`~ins_errors.symbolic.variation.structured_variation`).

The coefficient of each basis quantity is compared numerically at the reference points
(:mod:`~ins_errors.checker.reference`); a term's size is ``|coefficient| × typical
magnitude`` of its quantity, and a discrepancy is measured relative to the largest term
of the model's side of its equation at the same point (the largest ratio over the points
is reported): the truth's scale, which a wrong term of the hand's cannot change.

Each line is compared three times:

1. as written, against the model's variation;
2. against the model with the author's declared simplifications (``@neglect``) applied:
   what disappears is a *declared drop*;
3. *isolated*: every definition the line uses (the hand's ΔR_E, its helper D, ...)
   replaced by the correct one: what remains is the line's *own* finding (a root), what
   disappeared is a *knock-on* of the wrong definitions it uses.

A helper defined only in the hand file (the manual's D) is checked against the value
its simplest use needs (``ΔR_E = D Δφ`` needs D = dR_E/dφ). What each difference is and
how much it matters: :mod:`~ins_errors.checker.classify`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from itertools import combinations

import numpy as np
import sympy as sp

from ins_errors.checker import classify as cl
from ins_errors.checker.classify import Finding
from ins_errors.checker.extreme import at_least, first_largest
from ins_errors.checker.line_pairs import pair_findings
from ins_errors.checker.notation import Notation, default_notation
from ins_errors.checker.parse import HandEquation, HandFile, Problem
from ins_errors.checker.ratio_names import earth_factors
from ins_errors.checker.reference import (
    DEFAULT_ATTITUDE,
    STATIC_BASE,
    Magnitudes,
    ReferencePoint,
    reference_points,
    schuler_magnitudes,
)
from ins_errors.checker.sides import (
    HandSide,
    ModelSide,
    UnresolvedError,
    identified,
    model_expr,
    model_side,
    tilde_variations,
)
from ins_errors.checker.tree_values import TreeValues, UnsupportedError
from ins_errors.errors import InsErrorsError, close_names
from ins_errors.modeling import ModelDefinition
from ins_errors.numeric.blas_threads import one_blas_thread
from ins_errors.symbolic.symbol_order import sorted_symbols

DEFAULT_THRESHOLD = 1e-3
"""Relative size separating small effects from mistakes."""
AGREEMENT = 1e-9
"""Relative size below which two coefficients are taken as equal (rounding)."""
ZERO_NOTE = "{z} is 0 at every reference point, so the values there cannot show it"
"""Why a difference found through a derivative has no size."""

__all__ = ["AGREEMENT", "DEFAULT_THRESHOLD", "BasisQuantity", "CheckReport", "EquationResult",
           "Finding", "check_hand", "check_hand_file"]


# --------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BasisQuantity:
    """One error quantity the equations are compared on.

    Attributes
    ----------
    name : str
        Error-state name, model source name or hand source symbol (``Delta_a``).
    unit : str
        SI unit.
    magnitude : float
        Typical size (SI) used to weigh its terms.
    magnitude_text : str
        The same, as people write it (``"0.01 deg/h"``).
    stands_for : tuple of str
        Model sources a hand source symbol stands for (empty otherwise).
    """

    name: str
    unit: str
    magnitude: float
    magnitude_text: str
    stands_for: tuple[str, ...] = ()


@dataclass
class EquationResult:
    """The outcome for one form of one hand equation.

    Attributes
    ----------
    equation : HandEquation
    form : int
        Index of the checked form within the printed chain.
    target : str
        What the line is compared with (``"intermediate omega_xi"``, ``"error state
        delta_V_xi"``, ``"output v_N"``, ``"value dR_E/dphi needed by line 49"``), or why
        it is not compared.
    status : str
        ``"agrees"``, ``"agrees up to dropped small terms"``, ``"agrees up to declared
        drops"``, ``"mistake"``, ``"hand-only definition"``, ``"tautology"``,
        ``"input error"``.
    findings : list of Finding
    notes : list of str
    """

    equation: HandEquation
    form: int
    target: str
    status: str
    findings: list[Finding] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def label(self) -> str:
        """Left-hand side, with the form number for chains."""
        suffix = f" (form {self.form + 1})" if len(self.equation.forms) > 1 else ""
        return f"{self.equation.label}{suffix}"

    @property
    def reference(self) -> str:
        """``"line 49 Delta_R_E"``: how other findings name this line."""
        return f"line {self.equation.line} {self.label}"


@dataclass
class CheckReport:
    """Everything the checker found in one hand file.

    Attributes
    ----------
    model : str
    hand_name : str
    hand_format : str
    threshold : float
    points : list of ReferencePoint
    basis : list of BasisQuantity
    sections : list of str
    results : list of EquationResult
    problems : list of Problem
        Input problems (parse errors, unknown symbols, duplicates, ...), sorted by line.
    out_of_scope : list of str
        Model error sources the hand file never mentions (set to zero on both sides).
    unchecked_sources : list of str
        Those of them that the model's side of a compared line contains: terms the
        file leaves out without the check seeing them.
    unchecked_gains : list of str
        The model's damping gains at 0 that a compared line holds (on either side):
        the terms they multiply are not checked (``ins-errors check`` warns, naming how
        to set them).
    from_model : dict
        Variation symbol -> lines where the hand file uses it without defining it (the
        model's variation was used on the hand side).
    unused : list of str
        Hand definitions no other line uses (and that have no model counterpart).
    magnitudes : str
        Where the typical magnitudes come from (one line).
    skipped_motions : list of str
        Motions the model cannot fly (or that the scope excludes), with the reason.
    scope : str or None
        Motion class the file limits itself to (``@scope``).
    declarations : list of str
        The declared simplifications, as written.
    idle_declarations : list of str
        Declared simplifications that explain no finding.
    omissions : list of Omission
        Variations the file drops without declaring them, each the root of the findings
        it explains (:func:`~ins_errors.checker.classify.undeclared_variations`).
    scope_advice : str
        One sentence advising ``@scope static base`` when the file looks like a
        static-base derivation that does not say so (:func:`static_base_advice`), else
        ``""``.
    """

    model: str
    hand_name: str
    hand_format: str
    threshold: float
    points: list[ReferencePoint]
    basis: list[BasisQuantity]
    sections: list[str]
    results: list[EquationResult]
    problems: list[Problem]
    out_of_scope: list[str]
    from_model: dict[str, list[int]]
    unused: list[str]
    magnitudes: str = ""
    skipped_motions: list[str] = field(default_factory=list)
    scope: str | None = None
    declarations: list[str] = field(default_factory=list)
    idle_declarations: list[str] = field(default_factory=list)
    unchecked_sources: list[str] = field(default_factory=list)
    unchecked_gains: list[str] = field(default_factory=list)
    omissions: list[cl.Omission] = field(default_factory=list)
    scope_advice: str = ""

    @property
    def findings(self) -> list[tuple[EquationResult, Finding]]:
        """Every (result, finding) pair, in file order."""
        return [(r, f) for r in self.results for f in r.findings]

    @property
    def mistakes(self) -> list[tuple[EquationResult, Finding]]:
        """Findings classed as mistakes (of any size, roots and knock-ons); the other
        half of a pair (:attr:`~ins_errors.checker.classify.Finding.merged`) is counted
        with the finding that names it."""
        return [(r, f) for r, f in self.findings if f.is_mistake and not f.merged]

    def merged_with(self, result: EquationResult, finding: Finding
                    ) -> list[tuple[EquationResult, Finding]]:
        """The other half of ``finding``'s pair (:mod:`~ins_errors.checker.line_pairs`),
        listed under it; empty for a finding of one line."""
        if not finding.pair or finding.merged:
            return []
        return [(r, f) for r, f in self.findings if f.merged
                and f.pair == (f"line {result.equation.line} {result.label}",
                               finding.quantity)]

    @property
    def root_mistakes(self) -> list[tuple[EquationResult, Finding]]:
        """Mistakes that are a line's own (not carried in from a definition it uses)."""
        return [(r, f) for r, f in self.mistakes if f.role == cl.ROOT]

    def knock_ons(self, root: EquationResult) -> list[tuple[EquationResult, Finding]]:
        """Findings carried from ``root`` into the lines that use it."""
        return [(r, f) for r, f in self.findings
                if f.role == cl.KNOCK_ON and root.reference in f.roots]

    @property
    def exit_status(self) -> int:
        """0: no mistake; 1: at least one mistake; 2: input problems (whatever else)."""
        if self.problems:
            return 2
        return 1 if self.mistakes else 0


# --------------------------------------------------------------------------------------
# Comparison
# --------------------------------------------------------------------------------------
def _linear_parts(expr: sp.Expr, basis: list[sp.Symbol], trusted: bool = False
                  ) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
    """Coefficients of the basis quantities in ``expr`` and its constant part.

    Error equations are linear in the errors: a coefficient is the derivative by its
    quantity with every quantity at zero. A term that is not linear (α², sin α, α·β) is
    an input problem, not a coefficient to compare. ``trusted`` expressions (the model's
    own variation, linear by construction) are split by substitution instead, which is
    much cheaper on their deep expression trees.

    Raises
    ------
    UnresolvedError
        If ``expr`` is not linear in the basis quantities or has a non-finite part.
    """
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise UnresolvedError(None, "a term is not finite (division by zero?)")
    free = expr.free_symbols
    present = [b for b in basis if b in free]
    zero = {b: sp.S.Zero for b in present}
    coefficients = {}
    if trusted:  # linear by construction (the model's variation): substitute, no diff
        return _split_by_substitution(expr, present)
    for b in present:
        derivative = sp.diff(expr, b)
        if any(q in derivative.free_symbols and sp.diff(derivative, q) != 0 for q in present):
            raise UnresolvedError(b.name, f"not linear in the error quantity {b.name}: "
                                   "error equations must be linear in the errors")
        coefficients[b] = derivative.xreplace(zero)
    return coefficients, expr.xreplace(zero)


def _split_by_substitution(expr: sp.Expr, present: list[sp.Symbol]
                           ) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
    """Coefficients and constant part of a linear ``expr`` by substitution.

    The same expressions as ``expr.xreplace(zero)`` and ``expr.xreplace({**zero, b: 1})
    - constant`` (``zero``: every quantity of ``present`` set to 0), built the way
    :meth:`sympy.Basic.xreplace` builds them, but each distinct subtree is visited once
    per substitution and the subtrees without ``b`` reuse the constant part's result:
    the model's variations share most of their subtrees.
    """
    keys = set(present)
    inside: dict[int, frozenset] = {}  # id(node) -> quantities of ``present`` in it

    def scan(node) -> frozenset:
        found = inside.get(id(node))
        if found is None:
            if node in keys:
                found = frozenset((node,))
            else:
                found = frozenset().union(*(scan(a) for a in node.args
                                            if getattr(a, "_xreplace", None) is not None))
            inside[id(node)] = found
        return found

    scan(expr)
    zero = {b: sp.S.Zero for b in present}

    def replace(node, rule: dict, wanted, memo: dict, fallback):
        """``node.xreplace(rule)`` for the nodes holding ``wanted`` (see above)."""
        if node in rule:
            return rule[node]
        held = inside[id(node)]
        if not held or (wanted is not None and wanted not in held):
            return fallback(node)
        done = memo.get(id(node))
        if done is None:
            args = tuple(replace(a, rule, wanted, memo, fallback)
                         if getattr(a, "_xreplace", None) is not None else a
                         for a in node.args)
            done = node.func(*args)  # held is not empty: something was replaced
            memo[id(node)] = done
        return done

    constants: dict[int, sp.Expr] = {}

    def constant_of(node):
        return replace(node, zero, None, constants, lambda n: n)

    constant = constant_of(expr)
    coefficients = {}
    for b in present:
        coefficients[b] = replace(expr, {**zero, b: sp.S.One}, b, {}, constant_of) - constant
    return coefficients, constant


@lru_cache(maxsize=16384)
def _display(expr: sp.Expr, limit: int = 200) -> str:
    """Canonical (expanded when cheap) text of a coefficient, shortened to ``limit``."""
    if expr == 0:
        return "0"
    if sp.count_ops(expr) < 300:
        expr = sp.expand_mul(expr)
    text = sp.sstr(expr)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _term_difference(hand: sp.Expr, model: sp.Expr, limit: int = 150
                     ) -> tuple[sp.Expr, sp.Expr] | None:
    """(terms only the model has, terms only the hand has), if both expand cheaply."""
    if sp.count_ops(hand) > limit or sp.count_ops(model) > limit:
        return None
    hand_terms = sp.Add.make_args(sp.expand(hand))
    model_terms = sp.Add.make_args(sp.expand(model))
    missing = [t for t in model_terms if t not in hand_terms]
    extra = [t for t in hand_terms if t not in model_terms]
    _drop_equal_sums(missing, extra)
    _drop_equal_sums(extra, missing)
    return sp.Add(*missing), sp.Add(*extra)


def _drop_equal_sums(many: list[sp.Expr], few: list[sp.Expr], largest: int = 8) -> None:
    """Remove (in place) each term of ``few`` that two or three terms of ``many`` add up
    to, and those terms: expanding ``U cos φ (R + h)/(R + h)`` writes one term of the
    hand's as ``R U cos φ/(R + h) + U h cos φ/(R + h)``, which is no difference."""
    if len(many) < 2 or len(many) > largest:
        return
    # a numeric look first (every symbol at an arbitrary value): only a group whose sum
    # has the term's value is simplified (cancel on every group took seconds a file)
    symbols = sorted(set().union(*(t.free_symbols for t in (*many, *few))),
                     key=sp.default_sort_key)
    point = {x: sp.Float(0.37 + 0.113 * k) for k, x in enumerate(symbols)}

    def value(expr: sp.Expr) -> complex | None:
        try:
            return complex(expr.xreplace(point))
        except (TypeError, ValueError, ZeroDivisionError):
            return None

    values = {t: value(t) for t in many}
    for term in list(few):
        target = value(term)
        if target is None or target == 0:
            continue
        for size in (2, 3):
            match = next((group for group in combinations(many, size)
                          if all(values[t] is not None for t in group)
                          and abs(sum(values[t] for t in group) - target)
                          <= 1e-9 * abs(target)
                          and sp.cancel(sp.Add(*group) / term) == 1), None)
            if match is not None:
                few.remove(term)
                for part in match:
                    many.remove(part)
                break


@lru_cache(maxsize=16384)
def _shared_linear_parts(expr: sp.Expr, basis: tuple[sp.Symbol, ...], trusted: bool
                         ) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
    """:func:`_linear_parts`, kept for the next check in the same process.

    A pure function of its arguments (SymPy expressions compare by structure, symbols
    with their assumptions), so a repeated check, or one of a file that differs in a few
    lines, splits only what is new. The coefficient dictionaries are shared: read only.
    """
    return _linear_parts(expr, list(basis), trusted)


@lru_cache(maxsize=16384)
def _shown(expr: sp.Expr, rule: tuple[tuple[sp.Expr, sp.Expr], ...]) -> sp.Expr:
    """``expr.xreplace(dict(rule))``: a coefficient in the notation's terms, kept for the
    next check in the same process."""
    return expr.xreplace(dict(rule))


@lru_cache(maxsize=16384)
def _identical(hand: sp.Expr, model: sp.Expr, basis: tuple[sp.Symbol, ...], limit: int
               ) -> bool | None:
    """:meth:`Comparison.identical` (a pure function as well, kept likewise)."""
    h, hc = _shared_linear_parts(hand, basis, True)
    m, mc = _shared_linear_parts(model, basis, True)
    pairs = [(h.get(b, sp.S.Zero), m.get(b, sp.S.Zero)) for b in set(h) | set(m)]
    pairs.append((hc, mc))
    size = 0
    for a, b in pairs:  # counts are never negative: stop as soon as the sum is too big
        size += sp.count_ops(a) + sp.count_ops(b)
        if size > limit:
            return None
    return all(sp.expand(a - b) == 0 for a, b in pairs)


class Comparison:
    def __init__(self, points: list[ReferencePoint], basis: list[BasisQuantity],
                 symbols: dict[str, sp.Symbol], threshold: float,
                 values: dict[sp.Expr, np.ndarray], tree: TreeValues | None = None):
        self.points = points
        self.arguments = sorted_symbols(points[0].values)
        self.arrays = [np.array([p.values[s] for p in points]) for s in self.arguments]
        self.basis = basis
        self.symbols = [symbols[b.name] for b in basis]
        self._basis_key = tuple(self.symbols)
        self.magnitude = {symbols[b.name]: b.magnitude for b in basis}
        self.threshold = threshold
        self._parts: dict[sp.Expr, tuple[dict[sp.Symbol, sp.Expr], sp.Expr]] = {}
        self.display_model: dict[sp.Symbol, sp.Expr] = {}
        self._zeros: dict[sp.Symbol, sp.Expr] | None = None
        self.expand_model: dict[sp.Symbol, sp.Expr] = {}
        """The model's named intermediate quantities as expressions of its states,
        inputs and parameters (:func:`_expanded_intermediates`), for telling which terms
        of a coefficient differ."""
        self._values = values
        self._tree = TreeValues(self.arguments, self.arrays) if tree is None else tree
        self.zero_checked = True
        self.factors: list[tuple[str, float]] = []
        """Named factors a constant ratio is compared with
        (:func:`~ins_errors.checker.ratio_names.earth_factors`)."""
        self.fixed: frozenset[str] = frozenset()
        """Names of the model's parameters (a parameter that is 0 is the model's choice,
        not a motion that hides a term)."""
        """Look for differences hidden by quantities that are 0 at every point
        (:meth:`hidden_by_zero`); off for a file that declares a scope."""

    def linear_parts(self, expr: sp.Expr, trusted: bool = True
                     ) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
        """Coefficients and constant part of ``expr`` (cached).

        Hand forms are checked for linearity when they are read (``_check_linear``) and
        the model's variation is linear by construction, so by default the split is by
        substitution.
        """
        if expr not in self._parts:
            self._parts[expr] = _shared_linear_parts(expr, self._basis_key, trusted)
        return self._parts[expr]

    def prefetch(self, pairs: list[tuple]) -> None:
        """Evaluate the coefficients of many equations in one vectorised call.

        ``pairs``: (hand, model) pairs.
        """
        wanted = []
        for hand, model, *_ in pairs:
            try:
                h, hc = self.linear_parts(hand)
                m, mc = self.linear_parts(model, trusted=True)
            except UnresolvedError:
                continue  # reported with its own equation
            wanted += [*h.values(), *m.values(), hc - mc]
        known = set(self.arguments)
        todo = list(dict.fromkeys(e for e in wanted if e not in self._values
                                  and e.free_symbols <= known))
        if todo:
            self._compute(todo)

    def raw(self, exprs: list[sp.Expr]) -> np.ndarray:
        """Complex values of ``exprs`` at every point, shape (len(exprs), points)."""
        missing = [e for e in dict.fromkeys(exprs) if e not in self._values]
        if missing:
            stray = set().union(*(e.free_symbols for e in missing)) - set(self.arguments)
            if stray:
                name = sorted(stray, key=sp.default_sort_key)[0]
                raise UnresolvedError(str(name), f"{name} has no value at the reference "
                                                  "points")
            self._compute(missing)
        return np.array([self._values[e] for e in exprs])

    def _compute(self, exprs: list[sp.Expr]) -> None:
        """Evaluate ``exprs`` (symbols: the points' only) into the kept values.

        Node by node with the values of the subtrees met before
        (:class:`~ins_errors.checker.tree_values.TreeValues`); an expression with a node
        it does not evaluate, in one compiled function.
        """
        with np.errstate(all="ignore"):
            try:
                values = [self._tree.value(e) for e in exprs]
            except UnsupportedError:
                function = sp.lambdify(self.arguments, exprs, modules="numpy", cse=True,
                                       docstring_limit=0)
                values = function(*self.arrays)
        for expr, value in zip(exprs, values, strict=True):
            self._values[expr] = np.broadcast_to(np.asarray(value, dtype=complex),
                                                 (len(self.points),))

    def evaluate(self, exprs: list[sp.Expr]) -> np.ndarray:
        """Real values of ``exprs`` at every reference point, shape (len(exprs), points)."""
        return self.checked(self.raw(exprs))

    def try_evaluate(self, exprs: list[sp.Expr]) -> np.ndarray | None:
        """Values of candidate expressions (NaN where not finite or not real)."""
        try:
            values = self.raw(exprs)
        except (UnresolvedError, TypeError, ValueError, ZeroDivisionError):
            return None
        bad = ~np.isfinite(values) | (np.abs(values.imag) > 1e-9 * np.maximum(
            np.abs(values.real), 1e-300))
        return np.where(bad, np.nan, values.real)

    def identical(self, hand: sp.Expr, model: sp.Expr, limit: int = 400) -> bool | None:
        """True if every coefficient is the same expression (expanded), None if too big."""
        return _identical(hand, model, self._basis_key, limit)

    @staticmethod
    def checked(values: np.ndarray) -> np.ndarray:
        """Real parts, after checking the values are finite and real."""
        if not np.all(np.isfinite(values)):
            raise UnresolvedError(None, "a coefficient is not finite at a reference point "
                                         "(division by zero?)")
        if np.any(np.abs(values.imag) > 1e-9 * np.maximum(np.abs(values.real), 1e-300)):
            raise UnresolvedError(None, "a coefficient is complex at a reference point")
        return values.real

    def differences(self, hand: sp.Expr, model: sp.Expr, trusted: bool = False,
                    reference: sp.Expr | None = None) -> tuple[dict, np.ndarray, np.ndarray]:
        """Per basis quantity: discrepancy data; also the scale and the constant part.

        A discrepancy's size is relative to the scale at each point: the largest term of
        the model's side there (of ``reference`` if given, else of ``model``), the
        truth's scale, so a large wrong term the hand adds cannot make another finding
        look small. Where the model's side has no term at all, the largest term of
        either side.
        """
        h, hc = self.linear_parts(hand)
        m, mc = self.linear_parts(model, trusted=True)
        quantities = [b for b in self.symbols if b in h or b in m]
        exprs = [h.get(b, sp.S.Zero) for b in quantities] + [
            m.get(b, sp.S.Zero) for b in quantities] + [hc - mc]
        values = self.evaluate(exprs)
        k = len(quantities)
        hv, mv, constant = values[:k], values[k:2 * k], values[2 * k]
        weights = np.array([self.magnitude[b] for b in quantities]).reshape(-1, 1)
        largest = np.max(np.abs(np.concatenate([hv, mv])) * np.concatenate(
            [weights, weights]), axis=0) if k else np.zeros(len(self.points))
        # each side's own largest term: what is negligible on that side (a model term of
        # 1 is no "extra term" of a hand that writes 1e15 for it)
        hand_largest = np.max(np.abs(hv) * weights, axis=0) if k else largest
        model_largest = np.max(np.abs(mv) * weights, axis=0) if k else largest
        truth = model_largest if reference is None else self.largest_term(reference)
        scale = np.where(truth > 0, truth, largest)
        safe = np.where(scale > 0, scale, np.inf)
        raw: dict[sp.Symbol, dict] = {}
        for i, b in enumerate(quantities):
            ratios = np.abs(hv[i] - mv[i]) * weights[i] / safe
            j = first_largest(ratios)
            if ratios[j] > AGREEMENT:
                raw[b] = {"size": float(ratios[j]), "point": self.points[j].label,
                          "hand": hv[i], "model": mv[i], "largest": largest,
                          "hand_largest": hand_largest, "model_largest": model_largest,
                          "hand_expr": h.get(b, sp.S.Zero), "model_expr": m.get(b, sp.S.Zero),
                          "ratios": ratios}
        return raw, scale, constant

    def largest_term(self, expr: sp.Expr) -> np.ndarray:
        """Largest |coefficient| × typical magnitude of the terms of ``expr`` (a model
        side) at each point, shape (points,)."""
        parts, _ = self.linear_parts(expr, trusted=True)
        quantities = [b for b in self.symbols if b in parts]
        if not quantities:
            return np.zeros(len(self.points))
        values = self.evaluate([parts[b] for b in quantities])
        weights = np.array([self.magnitude[b] for b in quantities]).reshape(-1, 1)
        return np.max(np.abs(values) * weights, axis=0)

    def compare(self, hand: sp.Expr, model: sp.Expr, hand_display: sp.Expr | None = None,
                diagnose: bool = True, trusted: bool = False,
                reference: sp.Expr | None = None) -> list[Finding]:
        """Findings of one equation (both sides already in basis + model symbols).

        ``hand_display`` is the hand side with its own ideal symbols kept, used only to
        show the hand coefficients in the researcher's notation. ``trusted``: the hand
        side is known to be linear (an isolated form of a line already checked).
        ``reference``: the model side whose largest term sizes the findings, when
        ``model`` is not it (:meth:`differences`).
        """
        raw, largest, constant = self.differences(hand, model, trusted, reference)
        shown = (self.linear_parts(hand_display, trusted=True)[0] if hand_display is not None
                 else self.linear_parts(hand)[0])
        rule = tuple(self.display_model.items())
        for b, info in raw.items():
            info["hand_shown"] = _shown(shown.get(b, sp.S.Zero), rule)
            info["model_shown"] = _shown(info["model_expr"], rule)
        findings = self.pair_wrong_variables(raw)
        for b, info in raw.items():
            findings.append(self.finding(b, info, diagnose))
        findings += self.hidden_by_zero(hand, model, shown, rule, set(raw) | {
            s for f in findings for s in self.symbols if s.name in f.quantity.split(" -> ")})
        safe = np.where(largest > 0, largest, np.inf)
        ratios = np.where(largest > 0, np.abs(constant) / safe,
                          np.where(constant == 0, 0.0, np.inf))
        j = first_largest(ratios)
        if ratios[j] > AGREEMENT:
            _, hc = self.linear_parts(hand)
            findings.append(Finding("(none)", cl.NOT_ERROR, cl.MISTAKE, float(ratios[j]),
                                    self.points[j].label, _display(hc), "0",
                                    "a term that contains no error quantity (an ideal value "
                                    "where a variation belongs?)"))
        return findings

    def zero_everywhere(self) -> frozenset[sp.Symbol]:
        """Point quantities other than parameters that are 0 at every reference point
        (inputs of motions the model cannot fly, a vertical velocity on level points, ...)."""
        if not hasattr(self, "_zero"):
            self._zero = frozenset(s for s, a in zip(self.arguments, self.arrays, strict=True)
                                   if np.all(a == 0) and s.name not in self.fixed)
        return self._zero

    def hidden_by_zero(self, hand: sp.Expr, model: sp.Expr, shown: dict, rule: tuple,
                       skip: set) -> list[Finding]:
        """Coefficients that agree at every point only because a quantity they depend on
        is 0 there: their first derivatives in that quantity differ (a wrong term times
        ``a_N`` when every point has a_N = 0). Each is a mistake without a size (its value
        at the points is right; :data:`ZERO_NOTE`)."""
        zero = self.zero_everywhere() if self.zero_checked else frozenset()
        if not zero:
            return []
        h, _ = self.linear_parts(hand)
        m, _ = self.linear_parts(model, trusted=True)
        findings = []
        for b in self.symbols:
            if b in skip or (b not in h and b not in m):
                continue
            hb, mb = h.get(b, sp.S.Zero), m.get(b, sp.S.Zero)
            for z in sorted((hb.free_symbols | mb.free_symbols) & zero, key=sp.default_sort_key):
                dh, dm = sp.diff(hb, z), sp.diff(mb, z)
                if dh == dm:
                    continue
                values = self.try_evaluate([dh, dm])
                if values is None or not np.all(np.isfinite(values)):
                    continue
                vh, vm = values
                scale = np.maximum(np.abs(vh), np.abs(vm))
                if not np.any(np.abs(vh - vm) > 1e-9 * scale):
                    continue
                j = first_largest(np.abs(vh - vm) / np.where(scale > 0, scale, 1.0))
                if np.all(np.abs(vm) <= 1e-12 * scale):
                    kind, what = cl.EXTRA, "a term the model does not have"
                elif np.all(np.abs(vh) <= 1e-12 * scale):
                    kind, what = cl.OMITTED, "the model's term is left out"
                elif np.all(np.abs(vh + vm) <= 1e-9 * scale):
                    kind, what = cl.SIGN, "the term has the wrong sign"
                else:
                    kind, what = cl.COEFFICIENT, "the term's coefficient differs"
                findings.append(Finding(
                    str(b), kind, cl.MISTAKE, math.inf, self.points[j].label,
                    _display(_shown(shown.get(b, sp.S.Zero), rule)),
                    _display(_shown(mb, rule)),
                    f"in {z}: {what} (d/d{z} hand {_display(dh, 60)}, model "
                    f"{_display(dm, 60)}); {ZERO_NOTE.format(z=z)}",
                    at_rest=self.rest is not None))
                break
        return findings

    def finding(self, b: sp.Symbol, info: dict, diagnose: bool = True) -> Finding:
        hs, ms, largest = info["hand"], info["model"], info["largest"]
        tiny = 1e-12 * largest / self.magnitude[b]
        sides = {"hand_tiny": 1e-12 * info.get("hand_largest", largest) / self.magnitude[b],
                 "model_tiny": 1e-12 * info.get("model_largest", largest) / self.magnitude[b]}
        if diagnose:
            kind, detail = cl.diagnose(
                info["hand_expr"], info["model_expr"], hs, ms, tiny, self.try_evaluate,
                self.arguments, self._split, factors=self.factors, **sides)
        else:  # the cheap, numeric part only (omitted, extra, sign, constant ratio)
            kind, detail = cl.diagnose(info["hand_expr"], info["model_expr"], hs, ms, tiny,
                                       lambda exprs: None, [], factors=self.factors,
                                       **sides)
        return Finding(str(b), kind, cl.severity(kind, info["size"], self.threshold),
                       info["size"], info["point"], _display(info["hand_shown"]),
                       _display(info["model_shown"]), detail,
                       at_rest=self.agrees_at_rest(info))

    @property
    def rest(self) -> int | None:
        """Index of the static-base point when the file is compared on moving points
        too, else None (a file of one motion class: nothing to tell apart)."""
        motions = {p.motion for p in self.points}
        if STATIC_BASE not in motions or len(motions) < 2:
            return None
        return next(i for i, p in enumerate(self.points) if p.motion == STATIC_BASE)

    def agrees_at_rest(self, info: dict) -> bool:
        """Whether a discrepancy (:meth:`differences`) is below :data:`AGREEMENT` at the
        static base (:attr:`rest`): a term of the motion."""
        rest = self.rest
        return rest is not None and bool(info["ratios"][rest] <= AGREEMENT)

    def _split(self, hand: sp.Expr, model: sp.Expr):
        """(terms only the model has, terms only the hand has), shown in the notation.

        As written first: a part cleanly left out or added (one side 0) is told in the
        model's own names. Otherwise with the model's named quantities written out
        (:attr:`expand_model`): ``−ρ − V_E tan φ/R`` against a hand's ``−(2U sin φ +
        V_E tan φ/R)`` differs in ``V_E tan φ/R``, not in "−ρ where the hand has
        −2U sin φ"."""
        split = _term_difference(hand, model)
        clean = split is not None and (split[0] == 0 or split[1] == 0)
        if not clean and self.expand_model:
            # with the parameters that are 0 at every point set to 0 (a sphere's ecc2:
            # R/√(1 − e² sin²φ) + h is the hand's R + h there)
            zero = self._zero_parameters()
            expanded = _term_difference(hand.xreplace(self.expand_model).xreplace(zero),
                                        model.xreplace(self.expand_model).xreplace(zero))
            split = expanded if expanded is not None else split
        if split is None:
            return None
        return tuple(part.xreplace(self.display_model) for part in split)

    def pair_wrong_variables(self, raw: dict) -> list[Finding]:
        """Merge a deficit on A and an equal excess on B into one 'wrong symbol'."""
        findings = []
        for a in list(raw):
            for b in list(raw):
                if a == b or a not in raw or b not in raw:
                    continue
                da = raw[a]["hand"] - raw[a]["model"]
                db = raw[b]["hand"] - raw[b]["model"]
                scale = max(np.max(np.abs(da)), np.max(np.abs(db)))
                if scale == 0 or not np.all(np.abs(da + db) <= 1e-6 * scale):
                    continue
                # the model's term is lost on one quantity and found on the other
                lost, got = self._lost_and_got(raw, a, b)
                first = raw[a] if at_least(raw[a]["size"], raw[b]["size"]) else raw[b]
                term = raw[lost]["model_expr"] - raw[lost]["hand_expr"]
                if self.expand_model:  # the model's named quantities written out, if shorter
                    out = sp.expand(term.xreplace(self.expand_model))
                    term = min((term, out), key=lambda e: len(sp.sstr(e)))
                moved = _display(term.xreplace(self.display_model))
                findings.append(Finding(
                    f"{lost} -> {got}", cl.SYMBOL,
                    cl.severity(cl.SYMBOL, first["size"], self.threshold),
                    first["size"], first["point"], _display(raw[got]["hand_shown"]),
                    _display(raw[lost]["model_shown"]),
                    f"the model's term ({moved})*{lost} is written on {got}",
                    at_rest=self.agrees_at_rest(raw[a]) and self.agrees_at_rest(raw[b])))
                del raw[a], raw[b]
        return findings

    def _zero_parameters(self) -> dict[sp.Symbol, sp.Expr]:
        """The model's parameters that are 0 at every reference point, mapped to 0."""
        if self._zeros is None:
            self._zeros = {s: sp.S.Zero for s in self.arguments if s.name in self.fixed
                           and all(p.values.get(s, 1.0) == 0 for p in self.points)}
        return self._zeros

    def _lost_and_got(self, raw: dict, a: sp.Symbol, b: sp.Symbol
                      ) -> tuple[sp.Symbol, sp.Symbol]:
        """Which of two quantities lost the model's term (the hand lacks it there) and
        which got it. Both readings fit the numbers (one difference is minus the other),
        so: the one whose hand coefficient is 0, else the one whose hand coefficient is
        the model's with a part left out (the model's named quantities written out),
        else the one with the larger model coefficient."""
        for x, y in ((a, b), (b, a)):
            if raw[x]["hand_expr"] == 0 and raw[y]["hand_expr"] != 0:
                return x, y
        for x, y in ((a, b), (b, a)):
            split = self._split(raw[x]["hand_expr"], raw[x]["model_expr"])
            if split is not None and split[1] == 0 and split[0] != 0:
                return x, y
        return ((a, b) if at_least(float(np.sum(np.abs(raw[a]["model"]))),
                                   float(np.sum(np.abs(raw[b]["model"])))) else (b, a))

    def compare_values(self, hand: sp.Expr, model: sp.Expr, what: str = "the ideal value"
                       ) -> list[Finding]:
        """Findings of an ideal (non-error) definition: its value at the points."""
        h, m = self.evaluate([hand, model])
        scale = np.maximum(np.abs(h), np.abs(m))
        ratios = np.where(scale > 0, np.abs(h - m) / np.where(scale > 0, scale, 1), 0.0)
        j = first_largest(ratios)
        if ratios[j] <= AGREEMENT:
            return []
        tiny = 1e-12 * float(np.max(scale))
        kind, detail = cl.diagnose(hand, model, h, m, tiny, self.try_evaluate, self.arguments,
                                   proportional=True)
        if kind == cl.COEFFICIENT and not detail:
            detail = f"{what} differs"
        elif kind == cl.COEFFICIENT:
            detail = f"{what}: {detail}"
        return [Finding("(value)", kind if kind != cl.COEFFICIENT or "ratio" in detail
                        or "=" in detail else cl.DEFINITION,
                        cl.severity(cl.DEFINITION, float(ratios[j]), self.threshold),
                        float(ratios[j]), self.points[j].label,
                        _display(hand.xreplace(self.display_model)),
                        _display(model.xreplace(self.display_model)), detail)]


# --------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------
def _basis(model: ModelSide, notation: Notation, sources_used: Iterable[str],
           magnitudes: Magnitudes
           ) -> tuple[list[BasisQuantity], dict[sp.Symbol, sp.Expr], list[str]]:
    """Basis quantities, the model-side identification and the out-of-scope sources."""
    basis = []
    for name, unit in model.error_units.items():
        magnitude, text = magnitudes.of(unit)
        basis.append(BasisQuantity(name, unit, magnitude, text))
    used = set(sources_used)
    identify: dict[sp.Symbol, sp.Expr] = {}
    covered: set[str] = set()
    for hand_name, targets in notation.sources.items():
        if hand_name not in used:
            continue
        units = {model.sources[t].unit for t in targets if t in model.sources}
        missing = [t for t in targets if t not in model.sources]
        if missing:
            raise InsErrorsError(f"@source {hand_name}: unknown model error source "
                                 f"{missing[0]!r}")
        if len(units) != 1:
            raise InsErrorsError(f"@source {hand_name}: the sources {', '.join(targets)} "
                                 "have different units")
        magnitude, text = magnitudes.of(units.pop())
        basis.append(BasisQuantity(hand_name, model.sources[targets[0]].unit, magnitude, text,
                                   tuple(targets)))
        for t in targets:
            identify[model.source_symbols[t]] = sp.Symbol(hand_name, real=True)
        covered.update(targets)
    for name, source in model.sources.items():
        if name in used and name not in covered:
            magnitude, text = magnitudes.of(source.unit)
            basis.append(BasisQuantity(name, source.unit, magnitude, text))
            covered.add(name)
    out = [name for name in model.sources if name not in covered]
    for name in out:
        identify[model.source_symbols[name]] = sp.S.Zero
    return basis, identify, out


_SHARED: dict[tuple, tuple] = {}


def _points(d: ModelDefinition, scope: str | None,
            parameters: Mapping[str, float] | None = None):
    """Reference motions, the evaluated-coefficient cache and the node values
    (:class:`~ins_errors.checker.tree_values.TreeValues`), kept per definition, scope and
    parameter values set."""
    key = ("points", id(d), scope, tuple(sorted((parameters or {}).items())))
    entry = _SHARED.get(key)
    if entry is None or entry[0] is not d:
        motions = reference_points(d, scope, parameters)
        tree = None
        if motions.points:
            arguments = sorted_symbols(motions.points[0].values)
            tree = TreeValues(arguments, [np.array([p.values[s] for p in motions.points])
                                          for s in arguments])
        entry = (d, motions, {}, tree)
        _SHARED[key] = entry
    return entry[1], entry[2], entry[3]


def resolve_model(model: str | ModelDefinition) -> ModelDefinition:
    """The definition of a model: a built-in name, a model file (``./my_ins.py``), an
    installed entry point (see :mod:`ins_errors.model_lookup`), or a definition."""
    if isinstance(model, ModelDefinition):
        return model
    from ins_errors.model_lookup import definition_of, resolve

    return definition_of(resolve(model))


@one_blas_thread
def check_hand(hand: HandFile, model: str | ModelDefinition = "orthodromic",
               threshold: float = DEFAULT_THRESHOLD, mapping: Notation | None = None,
               magnitudes: dict[str, str] | None = None, effects: bool = True,
               parameters: Mapping[str, float] | None = None) -> CheckReport:
    """Check every equation of a parsed hand file against the model's variation.

    Parameters
    ----------
    hand : HandFile
        From :func:`~ins_errors.checker.parse.read_hand_file` (its own ``@alias``
        / ``@source`` entries apply on top of the model's default notation and ``mapping``).
    model : str or ModelDefinition
        Registered model name, or a model definition (e.g. from a model file).
    threshold : float
        Relative size separating small effects from mistakes (0 < threshold < 1).
    mapping : Notation, optional
        Extra notation entries (from a mapping file).
    magnitudes : dict, optional
        SI unit or ``"attitude"`` -> quantity text; overrides the hand file's
        ``@magnitude`` lines and the Schuler-consistent defaults.
    effects : bool
        Compute each mistake's effect on the 1 h / 24 h error (see
        :mod:`~ins_errors.checker.effect`).
    parameters : mapping of str to float, optional
        Model parameter values (SI; ``-p NAME=VALUE``,
        :func:`ins_errors.model_parameters.parse_parameters`) replacing the defaults
        wherever the check evaluates the model and the file: the reference points, the
        typical sizes (Earth radius, gravity) and the effects. A term multiplied by a
        parameter at 0 (an open damping loop's gain) is 0 at every point and so never
        checked: :attr:`CheckReport.unchecked_gains` names the damping gains left at 0
        that a compared line holds.

    Returns
    -------
    CheckReport

    Raises
    ------
    InsErrorsError
        If the file holds no equation at all, or the threshold is out of range.
    """
    if not 0 < threshold < 1:
        raise InsErrorsError(f"threshold must be between 0 and 1, got {threshold}")
    if not hand.equations and not hand.real_work and not hand.problems:
        raise InsErrorsError(f"{hand.name}: no equations to check (an empty hand file "
                             "cannot be said to agree with anything)")
    if hand.convention is not None:
        raise InsErrorsError(f"{hand.name}: a file with '@convention {hand.convention}' is "
                             "checked by ins_errors.checker.convention_equations "
                             "(`ins-errors check MODEL FILE` does this)")
    if hand.markov:
        raise InsErrorsError(f"{hand.name}: @markov {next(iter(hand.markov))} applies to "
                             "a bias state of a file with '@convention NAME' (equations in "
                             "a convention's states)")
    d = resolve_model(model)
    if hand.real_work:  # the real-work updates' variations are error-state lines too
        from dataclasses import replace

        from ins_errors.checker.realwork import platform_angles, update_variations

        hand = replace(hand, equations=[*hand.equations,
                                        *update_variations(hand, platform_angles(d))])
    side = model_side(d)
    motions, values, tree = _points(d, hand.scope, parameters)
    if not motions.points:
        raise InsErrorsError(f"model {d.name!r} cannot fly any reference motion of scope "
                             f"{hand.scope!r}: {'; '.join(motions.skipped)}")
    wanted = {**hand.magnitudes, **(magnitudes or {})}
    attitude = wanted.pop("attitude", DEFAULT_ATTITUDE)
    sizes = schuler_magnitudes(d, attitude, wanted, parameters)
    notation = default_notation(d)
    if mapping is not None:
        notation = notation.merged(mapping)
    notation = notation.merged(hand.notation)
    resolver = HandSide(side, notation, hand)

    # first pass: resolve every equation (this also finds the sources in use)
    prepared = []
    for eq in hand.equations:
        resolver.current_line = eq.line
        prepared.append(_prepare(eq, resolver, side))
    declared = cl.Declarations(hand, resolver, side)
    basis, identify, out_of_scope = _basis(side, notation, resolver.sources_used, sizes)
    symbols = {b.name: (side.error_states.get(b.name) or side.source_symbols.get(b.name)
                        or sp.Symbol(b.name, real=True)) for b in basis}
    comparison = Comparison(motions.points, basis, symbols, threshold, values, tree)
    comparison.zero_checked = hand.scope is None  # a scope limits the claim to its points
    comparison.factors = earth_factors(d, parameters)
    comparison.fixed = frozenset(p.name for p in d.parameters)  # 0 by the model's choice
    comparison.display_model = _reciprocal_aliases(side, notation)
    comparison.expand_model = _expanded_intermediates(d)
    declared.finish(comparison, identify)

    comparison.prefetch([(item.hand, identified(model_expr(side, item.key), identify))
                         for items in prepared for item in items
                         if item.hand is not None and item.key is not None
                         and not item.ideal and not item.status])
    needed = cl.helpers(hand, prepared, resolver, comparison, identify, declared)
    _complete(hand, prepared, resolver, comparison, identify, declared, needed)
    results = []
    for eq, items in zip(hand.equations, prepared, strict=True):
        for item in items:
            results.append(_evaluate(eq, item, comparison, identify, hand, resolver,
                                     declared, needed))
    cl.assign_roots(results, prepared, hand)
    cl.line_slips(results, prepared, hand, resolver, comparison, declared, needed, threshold)
    pair_findings(results, {(id(eq), it.form): it for eq, its in zip(
        hand.equations, prepared, strict=True) for it in its}, comparison, threshold)
    if hand.real_work:
        from ins_errors.checker.realwork import check_real_work, platform_angles

        angles = platform_angles(d)  # the model's, whatever their names
        angle = next((b.magnitude for b in basis if b.name in angles), sizes.of("rad")[0])
        results = sorted(results + check_real_work(hand, comparison.points, angle,
                                                   threshold, angles),
                         key=lambda r: r.equation.line)
    unused = [f"{r.equation.label} (line {r.equation.line})" for r in results
              if r.status in ("hand-only definition", "mistake", "agrees") and r.form == 0
              and r.target.startswith("value") is False and r.target == "hand-only definition"
              and id(r.equation) not in resolver.used_definitions]
    unused += [f"{r.equation.label} (line {r.equation.line})" for r in results
               if r.form == 0 and r.target.startswith("value ")
               and id(r.equation) not in resolver.used_definitions]
    hand.problems.sort(key=lambda p: (p.line, p.column or 0))
    report = CheckReport(
        model=d.name, hand_name=hand.name, hand_format=hand.format, threshold=threshold,
        points=comparison.points, basis=basis, sections=hand.sections, results=results,
        problems=list(hand.problems), out_of_scope=out_of_scope,
        from_model={k: sorted(v) for k, v in sorted(resolver.from_model.items())},
        unused=unused, magnitudes=sizes.origin, skipped_motions=list(motions.skipped),
        scope=hand.scope, declarations=declared.texts(),
        idle_declarations=declared.idle(),
        unchecked_sources=_unchecked_sources(side, prepared, out_of_scope),
        unchecked_gains=_unchecked_gains(d, prepared, resolver, parameters))
    if effects and report.findings:
        from ins_errors.checker.effect import add_effects

        # a mistake that makes a fast growing mode (a damping gain's sign slip) overflows
        # the 24 h propagation to inf / nan: the effect says it grows exponentially and
        # writes no number, so the floating-point warnings of that overflow tell nothing
        with np.errstate(over="ignore", invalid="ignore"):
            add_effects(report, d, side, comparison, identify, prepared, resolver,
                        parameters)
    if report.findings:  # after the effects: each line keeps the effect of its own part
        report.omissions = cl.undeclared_variations(
            report.results, prepared, hand, resolver, comparison, identify, declared,
            threshold)
        report.scope_advice = static_base_advice(report, prepared, comparison)
    return report


def _motion_quantities(comparison: Comparison) -> frozenset[str]:
    """Names of the point quantities other than parameters that are 0 at the static base
    and not at every point (velocities, height, accelerations): what a derivation for a
    moving base writes."""
    rest = comparison.rest
    if rest is None:
        return frozenset()
    return frozenset(s.name for s, a in zip(comparison.arguments, comparison.arrays,
                                            strict=True)
                     if a[rest] == 0 and np.any(a != 0) and s.name not in comparison.fixed)


def static_base_advice(report: CheckReport, prepared: list[list[Item]],
                       comparison: Comparison) -> str:
    """Advice to add ``@scope static base`` when the file looks like a static-base
    derivation that does not say so, else ``""``; marks the omissions it covers
    (:attr:`~ins_errors.checker.classify.Omission.at_rest`).

    The file has no ``@scope``, it is compared at the static base and at moving points,
    none of its equations holds a quantity of the motion (a velocity, the height: a
    quantity 0 at rest, :func:`_motion_quantities`), and some of its mistakes are 0 at
    rest (:attr:`~ins_errors.checker.classify.Finding.at_rest`): the moving-base terms a
    static-base derivation leaves out. An undeclared dropped variation whose findings
    are all 0 at rest is then one of them, not a ``@neglect`` to write in the model's
    names.
    """
    motion = _motion_quantities(comparison)
    if report.scope is not None or not motion:
        return ""
    written = {s.name for items in prepared for item in items
               if item.hand_display is not None for s in item.hand_display.free_symbols}
    if written & motion:
        return ""
    for o in report.omissions:
        members = [f for _, f in report.findings
                   if f.role == cl.KNOCK_ON and o.reference in f.roots]
        o.at_rest = bool(members) and all(f.at_rest for f in members)
    roots = [f for _, f in report.root_mistakes]
    counted = roots + [o for o in report.omissions if o.is_mistake]
    at_rest = [f for f in roots if f.at_rest] + [o for o in report.omissions
                                                 if o.is_mistake and o.at_rest]
    if not at_rest:
        return ""
    n, m = len(at_rest), len(counted)
    which = (f"{n} of the {m} root mistakes" if n < m else "the root mistake" if m == 1
             else f"all {m} root mistakes")
    return (f"{which[0].upper()}{which[1:]} {'are' if n > 1 else 'is'} 0 at rest "
            "(the static base) and the file's equations hold no velocity or height: "
            "moving-base terms a derivation for a static base leaves out. If it holds on "
            f"a static base only, say so with `{cl.SCOPE_STATIC}` (the file is then "
            "compared at the static base alone).")


def _unchecked_gains(d: ModelDefinition, prepared: list[list[Item]], resolver: HandSide,
                     parameters: Mapping[str, float] | None) -> list[str]:
    """The model's damping gains (``Parameter(..., damping_gain=True)``) left at 0 that
    the hand's or the model's side of a compared line holds, in the model's order: the
    terms they multiply are 0 at every reference point, whatever their sign or factor."""
    values = dict(parameters or {})
    zero = {v.symbol: v.name for v in d.parameters
            if v.damping_gain and float(values.get(v.name, v.default)) == 0}
    if not zero:
        return []
    held: set[sp.Symbol] = set()
    for items in prepared:
        for item in items:
            if item.hand is None or item.key is None or item.status:
                continue
            held |= item.hand.free_symbols
            held |= (item.key[1] if item.ideal
                     else model_expr(resolver.model, item.key)).free_symbols
    return [name for symbol, name in zero.items() if symbol in held]


def _unchecked_sources(side: ModelSide, prepared: list[list[Item]], out: list[str]
                       ) -> list[str]:
    """The sources of ``out`` (never mentioned by the file) that the model's side of a
    compared line contains, in the model's order."""
    wanted = {side.source_symbols[name]: name for name in out}
    reached: set[str] = set()
    for items in prepared:
        for item in items:
            if item.key is None or item.ideal or item.status or item.hand is None:
                continue
            try:
                symbols = model_expr(side, item.key).free_symbols
            except (KeyError, UnresolvedError):
                continue
            reached.update(wanted[s] for s in symbols if s in wanted)
    return [name for name in out if name in reached]


def _expanded_intermediates(d) -> dict[sp.Symbol, sp.Expr]:
    """Each named intermediate quantity of the ideal work (``ρ``), as the expression of
    states, inputs and parameters it stands for (earlier ones substituted in later ones).

    A hand coefficient written out (``−(2U sin φ + V_E tan φ/R)``) and the model's with
    a name in it (``−ρ − V_E tan φ/R``) then split into the terms that really differ
    (``−V_E tan φ/R`` left out), not "the model has −ρ where the hand has −2U sin φ".
    """
    expanded: dict[sp.Symbol, sp.Expr] = {}
    for definition in d.ideal.definitions:
        expanded[definition.symbol] = definition.expression.xreplace(expanded)
    return expanded


def _reciprocal_aliases(side: ModelSide, notation: Notation) -> dict[sp.Symbol, sp.Expr]:
    """Show model reciprocals in the notation's terms: ``inv_R_eta`` -> ``1/R_eta``."""
    from ins_errors.checker.parse import parse_text_expression

    shown = {}
    for name, text in notation.aliases.items():
        try:
            expr, _ = parse_text_expression(text, Notation())
        except Exception:
            continue
        if expr.is_Pow and expr.exp == -1 and expr.base.is_Symbol:
            model = side.symbols.get(expr.base.name)
            if model is not None:
                shown[model] = 1 / sp.Symbol(name, real=True)
    return shown


@dataclass
class Item:
    form: int
    target: str
    hand: sp.Expr | None = None
    hand_display: sp.Expr | None = None
    key: tuple | None = None
    ideal: bool = False
    status: str = ""
    notes: list[str] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    problem: str | None = None
    deps: frozenset[int] = frozenset()
    model_full: sp.Expr | None = None
    model_declared: sp.Expr | None = None
    hand_declared: sp.Expr | None = None
    hand_isolated: sp.Expr | None = None


def _convention_hint(model: str, name: str) -> str:
    """``; phi_N is a state of convention 'phi' ...: add the line '@convention phi'`` when
    ``name`` is a state of one of ``model``'s conventions, else ''."""
    from ins_errors.checker.conventions import REGISTRY

    builder = REGISTRY.get(model)
    found = [c for c, conv in (builder() if builder else {}).items() if name in conv.names]
    if not found:
        return ""
    return (f"; {name} is a state of convention{'s' * (len(found) > 1)} "
            f"{', '.join(repr(c) for c in found)}: add the line '@convention {found[0]}'"
            + (" (or another of them)" if len(found) > 1 else ""))


def _target(eq: HandEquation, resolver: HandSide, side: ModelSide
            ) -> tuple[str, tuple | None, bool, list[Finding], list[str]]:
    """(description, model key or None, ideal?, findings, notes) of a left side."""
    lhs = eq.lhs
    if isinstance(lhs, sp.Function):  # dot(X)
        inner = lhs.args[0].name
        base = resolver.variation_base(inner)
        if base is not None and base in side.error_of_state:
            name = side.error_of_state[base].name
        elif inner in side.error_states:
            name = inner
        else:
            shown = base or inner
            names = list(side.error_states) + [f"Delta_{s}" for s in side.state_names]
            close = close_names(inner, names, cutoff=0.6)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise UnresolvedError(inner, f"equation for dot({inner}), but {shown} is not a state "
                                     f"of the model {side.d.name!r}{hint} (error states: "
                                     f"{', '.join(side.error_states)})"
                                     + _convention_hint(side.d.name, inner))
        return f"error state {name}", ("state", name), False, [], []
    key = resolver.definition_key(eq)
    name = lhs.name
    if name in side.error_states or (key.startswith("Delta_")
                                     and key[6:] in side.error_of_state):
        raise UnresolvedError(name, f"{name} is an error state: give its equation as "
                                f"dot({name})")
    if key.startswith("Delta_"):
        base = key[6:]
        meaning = resolver.model_meaning(base)
        if meaning is None and base in side.delta_of:  # a real-work-only intermediate
            return f"intermediate {base}", ("delta", base), False, [], []
        if meaning is None:
            if resolver.visible(base, eq.section) is not None:
                return "hand-only definition", None, False, [], []
            close = close_names(base, resolver.known_names(), cutoff=0.6)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise UnresolvedError(name, f"{base} is not a quantity of the model or the "
                                         f"notation{hint} (declare it with '@alias {base} = "
                                         "...' to have its variation checked)")
        findings, notes = [], []
        if resolver.variation_base(name) is None:  # printed without Δ
            findings.append(Finding(
                "(left-hand side)", cl.LEFT_SIDE, cl.MISTAKE, float("inf"), "",
                name, key, f"the right-hand side is a variation: read as {key}"))
        if base in resolver.notation.aliases:
            what, model = f"alias {base} = {resolver.notation.aliases[base]}", ("vary", meaning)
        elif base in side.intermediates:
            what, model = f"intermediate {base}", ("delta", base)
        elif base in side.outputs:
            what, model = f"output {base}", ("delta", base)
        else:
            what, model = f"model quantity {base}", ("vary", meaning)
        return what, model, False, findings, notes
    meaning = resolver.model_meaning(name)
    if meaning is not None:
        return f"ideal value of {name}", ("ideal", meaning), True, [], []
    return "hand-only definition", None, False, [], []


def _prepare(eq: HandEquation, resolver: HandSide, side: ModelSide) -> list[Item]:
    items = []
    try:
        target, key_model, ideal, findings, notes = _target(eq, resolver, side)
    except UnresolvedError as error:
        _report(eq, resolver, error)
        return [Item(0, "", status="input error", problem=error.message)]
    key = resolver.definition_key(eq) if isinstance(eq.lhs, sp.Symbol) else eq.label
    for k, form in enumerate(eq.forms):
        item = Item(k, target, key=key_model, ideal=ideal, findings=list(findings),
                     notes=list(notes))
        if isinstance(eq.lhs, sp.Symbol) and resolver.tautology(form, key):
            item.status = "tautology"
            item.notes.append(f"this form restates {key} by name; nothing to compare")
            items.append(item)
            continue
        try:
            trail = (key,) if isinstance(eq.lhs, sp.Symbol) else ()
            _check_linear(form, resolver)
            resolver.trace = set()
            item.hand = resolver.resolve(form, eq.section, trail)
            item.deps = frozenset(resolver.trace)
            item.hand_display = resolver.display_form(form, eq.section, trail)
        except UnresolvedError as error:
            _report(eq, resolver, error)
            if k == 0 and isinstance(eq.lhs, sp.Symbol):
                resolver.broken[id(eq)] = error.message
            item.status, item.problem = "input error", error.message
        items.append(item)
    return items


def _check_linear(form: sp.Expr, resolver: HandSide) -> None:
    """Refuse a form that is not linear in its error quantities (α², sin α, α·β, 1/0).

    Every definition a form uses is checked on its own line, and the model's variation
    is linear by construction, so checking the printed form suffices: the resolved sides
    can then be split into coefficients by substitution (cheap) instead of by
    differentiation of deep expressions.
    """
    tildes = tilde_variations(form)
    if tildes:
        form = form.xreplace(tildes)
    if form.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise UnresolvedError(None, "a term is not finite (division by zero?)")
    errors = tuple(s for s in sorted_symbols(form.free_symbols)
                   if resolver.is_variational(s))
    b = _first_nonlinear(form, errors)
    if b is not None:
        raise UnresolvedError(b.name, f"not linear in the error quantity {b.name}: "
                               "error equations must be linear in the errors")


@lru_cache(maxsize=16384)
def _first_nonlinear(form: sp.Expr, errors: tuple[sp.Symbol, ...]) -> sp.Symbol | None:
    """The first of ``errors`` whose derivative still holds one of them, or None.

    A pure function of its arguments, kept for the next check in the same process. A
    form that is a sum of products with at most one error factor each (the usual hand
    line) is linear by its structure alone: its derivatives hold no error quantity, so
    the answer is None without differentiating.
    """
    degree = _degree(form, frozenset(errors), {})
    if degree is not None and degree <= 1:
        return None
    for b in errors:
        derivative = sp.diff(form, b)
        if any(q in derivative.free_symbols and sp.diff(derivative, q) != 0 for q in errors):
            return b
    return None


def _degree(node: sp.Basic, errors: frozenset, memo: dict) -> int | None:
    """Polynomial degree of ``node`` in ``errors`` read off its tree, or None.

    Sums take the largest degree of their terms, products the sum, a power of a
    polynomial part with a positive integer exponent multiplies it; any other node is of
    degree 0 if none of its arguments holds an error quantity. None: an error quantity
    inside a function, a denominator or a non-integer power (not a polynomial).
    """
    key = id(node)
    if key in memo:
        return memo[key]
    if node.is_Symbol:
        degree = 1 if node in errors else 0
    elif node.is_Add or node.is_Mul:
        degrees = [_degree(a, errors, memo) for a in node.args]
        degree = (None if None in degrees
                  else max(degrees) if node.is_Add else sum(degrees))
    elif node.is_Pow:
        base, exp = _degree(node.base, errors, memo), _degree(node.exp, errors, memo)
        if base is None or exp is None or exp > 0:
            degree = None
        elif base == 0:
            degree = 0
        elif node.exp.is_Integer and node.exp > 0:
            degree = base * int(node.exp)
        else:
            degree = None
    else:
        degrees = [_degree(a, errors, memo) for a in node.args]
        degree = 0 if all(d == 0 for d in degrees) else None
    memo[key] = degree
    return degree


def _report(eq: HandEquation, resolver: HandSide, error: UnresolvedError) -> None:
    column = eq.columns.get(error.symbol, eq.column) if error.symbol else eq.column
    resolver.hand.problems.append(Problem(eq.line, column, f"{eq.label}: {error.message}"))


# -- evaluation of one line ------------------------------------------------------------
def _evaluate(eq: HandEquation, item: Item, comparison: Comparison,
              identify: dict[sp.Symbol, sp.Expr], hand: HandFile, resolver: HandSide,
              declared: cl.Declarations, needed: dict[str, cl.Needed]) -> EquationResult:
    result = EquationResult(eq, item.form, item.target or "not compared", item.status or "",
                            list(item.findings), list(item.notes))
    if item.status in ("input error", "tautology"):
        if item.problem:
            result.notes.append(item.problem)
        return result
    if item.key is None:
        name = eq.lhs.name if isinstance(eq.lhs, sp.Symbol) else ""
        if name in needed:
            return _evaluate_helper(eq, item, result, comparison, needed[name], hand)
        result.status = "hand-only definition"
        result.notes.append("no counterpart in the model; checked through the lines that "
                            "use it")
        return result
    if item.form > 0 or eq.alternative:
        result.notes.append("alternative printed form: checked, not used as the definition")
    try:
        if item.ideal:
            if any(s.name in comparison.magnitude or s in comparison.magnitude
                   for s in item.hand.free_symbols):
                raise UnresolvedError(None, "mixes ideal values and error quantities")
            result.findings += comparison.compare_values(item.hand, item.key[1])
        else:
            result.findings += cl.line_findings(eq, item, comparison, identify, resolver,
                                              declared, needed, result)
    except UnresolvedError as error:
        hand.problems.append(Problem(eq.line, eq.column, f"{eq.label}: {error.message}"))
        result.status = "input error"
        result.notes.append(error.message)
        return result
    cl.set_status(result)
    if result.status == "agrees" and not item.ideal:
        model = identified(model_expr(resolver.model, item.key), identify)
        if comparison.identical(item.hand, model):
            result.notes.insert(0, "identical symbolically")
    return result


def _evaluate_helper(eq: HandEquation, item: Item, result: EquationResult,
                     comparison: Comparison, need: cl.Needed, hand: HandFile
                     ) -> EquationResult:
    """A hand-only helper compared with the value its simplest use needs."""
    result.target = f"value {need.description}"
    if item.hand is None:
        return result
    try:
        result.findings += comparison.compare_values(item.hand, need.expr,
                                                     f"the value line {need.line} needs")
    except UnresolvedError as error:
        hand.problems.append(Problem(eq.line, eq.column, f"{eq.label}: {error.message}"))
        result.status = "input error"
        return result
    cl.set_status(result)
    return result


def _complete(hand: HandFile, prepared: list[list[Item]], resolver: HandSide,
              comparison: Comparison, identify: dict, declared: cl.Declarations,
              needed: dict[str, cl.Needed]) -> None:
    """Model sides (exact, with declared drops) and isolated hand side of every line."""
    pairs = []
    for eq, items in zip(hand.equations, prepared, strict=True):
        for item in items:
            if item.hand is None or item.key is None or item.ideal or item.status:
                continue
            item.model_full = identified(model_expr(resolver.model, item.key), identify)
            dropped = declared.dropped_for(eq)
            side = model_side(resolver.model.d, dropped) if dropped else resolver.model
            item.model_declared = identified(model_expr(side, item.key), identify)
            item.hand_isolated = item.hand
            item.hand_declared = item.hand
            if item.deps:
                resolver.isolate = side
                resolver.needed = {k: v.expr for k, v in needed.items()}
                try:
                    trail = ((resolver.definition_key(eq),) if isinstance(eq.lhs, sp.Symbol)
                             else ())
                    item.hand_isolated = resolver.resolve(eq.forms[item.form], eq.section,
                                                          trail)
                except UnresolvedError:
                    pass
                finally:
                    resolver.isolate, resolver.needed = None, {}
            zero = declared.zeroed_for(eq, comparison.expand_model)
            if zero:  # quantities neglected (h << R): both sides with them at 0
                item.model_declared = item.model_declared.xreplace(zero)
                item.hand_declared = item.hand.xreplace(zero)
                item.hand_isolated = item.hand_isolated.xreplace(zero)
            pairs += [(item.hand_declared, item.model_declared),
                      (item.hand_isolated, item.model_declared,
                       item.hand_isolated is not item.hand)]
    comparison.prefetch(pairs)


def check_hand_file(path, model: str | ModelDefinition = "orthodromic",
                    threshold: float = DEFAULT_THRESHOLD, latex: bool | None = None,
                    mapping_path=None, latex_backend: str = "lalr",
                    magnitudes: dict[str, str] | None = None, effects: bool = True,
                    parameters: Mapping[str, float] | None = None) -> CheckReport:
    """Read a hand file (and optional mapping file) and check it.

    Parameters
    ----------
    path : str or Path
        Hand file; LaTeX if ``latex`` or its suffix is ``.tex``.
    model : str or ModelDefinition
        Registered model name or a model definition.
    threshold : float
        Relative size separating small effects from mistakes.
    latex : bool, optional
        Force the format (default: from the suffix).
    mapping_path : str or Path, optional
        Mapping file with ``@alias`` / ``@source`` lines.
    latex_backend : {"lalr", "sympy"}
        Parser of LaTeX arithmetic (see :data:`~ins_errors.checker.parse.LATEX_BACKENDS`).
    magnitudes : dict, optional
        Typical-magnitude overrides (see :func:`check_hand`).
    effects : bool
        Compute each mistake's effect on the 1 h / 24 h error.
    parameters : mapping of str to float, optional
        Model parameter values set (SI; see :func:`check_hand`).
    """
    from ins_errors.checker.parse import read_hand_file, read_mapping_file

    d = resolve_model(model)  # unknown model: clear error before reading anything
    mapping = read_mapping_file(mapping_path) if mapping_path is not None else None
    notation = default_notation(d)
    if mapping is not None:
        notation = notation.merged(mapping)
    hand = read_hand_file(path, notation, latex=latex, latex_backend=latex_backend)
    return check_hand(hand, model=d, threshold=threshold, mapping=mapping,
                      magnitudes=magnitudes, effects=effects, parameters=parameters)
