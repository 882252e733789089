"""Term-by-term audit of hand-written error equations against the mechanical variation.

Both sides of every hand equation are brought to a linear combination of the *basis*:
the model's error states and the error sources the hand file considers (after the
notation's identifications, e.g. ``Delta_a`` for both accelerometer biases). The hand
side goes through the hand file's own definitions (its ΔW, Δg', D, ...); a variation the
hand file uses but never defines (ΔR_η, ΔV_ζ) is taken from the model and listed. The
mechanical side goes through the model's varied intermediates
(:func:`~ins_errors.symbolic.variation.structured_variation`).

The coefficient of each basis quantity is then compared numerically at the reference
points (:mod:`~ins_errors.checker.reference`). A term's size is
``|coefficient| × typical magnitude`` of its quantity; each discrepancy is measured
relative to the largest term of its equation at the same point (the largest ratio over
the points is reported) and classed:

* ``"dropped small term"`` below the threshold (default 1e-3);
* ``"mistake"`` at or above it.

Its kind says what differs: ``missing term``, ``extra term``, ``sign error``, ``wrong
coefficient`` (with the ratio when it is constant), ``wrong variable`` (a coefficient
that belongs to one quantity written on another), ``not an error quantity`` (a term with
no error in it), ``left-hand side without Δ`` and ``wrong definition`` (an ideal quantity
such as ``R_E = ...`` whose value differs from the model's).

Where the expressions are small, agreeing equations are also compared symbolically.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import sympy as sp

from ins_errors.checker.notation import Notation, default_notation
from ins_errors.checker.parse import DOT, TILDE, HandEquation, HandFile, Problem
from ins_errors.checker.reference import (
    ReferencePoint,
    reference_points,
    typical_magnitude,
)
from ins_errors.errors import InsErrorsError
from ins_errors.modeling import ModelDefinition
from ins_errors.models import definition as model_definition
from ins_errors.symbolic.variation import output_mechanisations, structured_variation

DEFAULT_THRESHOLD = 1e-3
"""Relative size below which a discrepancy counts as a deliberately dropped small term."""
AGREEMENT = 1e-9
"""Relative size below which two coefficients are taken as equal (rounding)."""

Severity = Literal["dropped small term", "mistake"]


class _UnresolvedError(Exception):
    """Internal: a symbol or definition the checker cannot resolve."""

    def __init__(self, symbol: str | None, message: str):
        message = " ".join(message.splitlines())  # reports are one line per problem
        super().__init__(message)
        self.symbol = symbol
        self.message = message


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


@dataclass(frozen=True)
class Finding:
    """One discrepancy between a hand equation and the model.

    Attributes
    ----------
    quantity : str
        Basis quantity whose coefficient differs (``"(none)"`` for a term with no error).
    kind : str
        ``missing term``, ``extra term``, ``sign error``, ``wrong coefficient``,
        ``wrong variable``, ``not an error quantity``, ``left-hand side without Δ``.
    severity : {"dropped small term", "mistake"}
    size : float
        Largest ratio, over the reference points, of the discrepancy to the equation's
        largest term at that point.
    point : str
        Reference point where that ratio is reached.
    hand : str
        Hand coefficient (SymPy text, model symbols).
    model : str
        Model coefficient.
    detail : str
        One-line explanation (ratio, where a misplaced term belongs, ...).
    """

    quantity: str
    kind: str
    severity: Severity
    size: float
    point: str
    hand: str
    model: str
    detail: str = ""


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
        delta_V_xi"``, ``"output v_N"``), or why it is not compared.
    status : str
        ``"agrees"``, ``"agrees up to dropped small terms"``, ``"mistake"``,
        ``"hand-only definition"``, ``"tautology"``, ``"input error"``.
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
    from_model : dict
        Variation symbol -> lines where the hand file uses it without defining it (the
        model's variation was used on the hand side).
    unused : list of str
        Hand definitions no other line uses (and that have no model counterpart).
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

    @property
    def findings(self) -> list[tuple[EquationResult, Finding]]:
        """Every (result, finding) pair, in file order."""
        return [(r, f) for r in self.results for f in r.findings]

    @property
    def mistakes(self) -> list[tuple[EquationResult, Finding]]:
        """Findings classed as mistakes."""
        return [(r, f) for r, f in self.findings if f.severity == "mistake"]

    @property
    def exit_status(self) -> int:
        """0: no mistake; 1: at least one mistake; 2: input problems (whatever else)."""
        if self.problems:
            return 2
        return 1 if self.mistakes else 0


# --------------------------------------------------------------------------------------
# The model side
# --------------------------------------------------------------------------------------
class _ModelSide:
    """Flat variations and ideal meanings of every model name."""

    def __init__(self, d: ModelDefinition):
        self.d = d
        self.state_names = [v.name for v in d.states]
        self.error_states = {v.name: v.symbol for v in d.error_states}
        self.error_of_state = {v.name: d.error_states[i].symbol
                               for i, v in enumerate(d.states)}
        self.error_units = {v.name: v.unit for v in d.error_states}
        self.sources = {v.name: v for v in d.sources}
        self.source_symbols = {v.name: v.symbol for v in d.sources}
        self.delta_of: dict[str, sp.Expr] = {}
        self.state_rhs: dict[str, sp.Expr] = {}
        known: dict[sp.Symbol, sp.Expr] = {}
        for line in structured_variation(d):
            rhs = line.rhs.xreplace(known)
            if line.kind == "intermediate":
                known[line.lhs] = rhs
                self.delta_of.setdefault(line.name, rhs)
            elif line.kind == "state":
                self.state_rhs[line.name] = rhs
            else:
                self.delta_of.setdefault(line.name, rhs)
        self.symbols: dict[str, sp.Symbol] = {}
        for group in (d.states, d.inputs, d.parameters):
            self.symbols.update({v.name: v.symbol for v in group})
        true_mech, true_out, _, _ = output_mechanisations(d)
        for mech in (d.ideal, true_mech):
            for df in mech.definitions:
                self.symbols.setdefault(df.symbol.name, df.symbol)
        self.intermediates = {name for name in self.symbols
                              if name not in {v.name for v in (*d.states, *d.inputs,
                                                               *d.parameters)}}
        self.outputs = {v.name: expr for v, expr in zip(d.outputs, true_out, strict=True)}

    def ideal(self, name: str) -> sp.Expr | None:
        """Ideal value of a model name in model symbols, or None."""
        if name in self.symbols:
            return self.symbols[name]
        if name in self.outputs:
            return self.outputs[name]
        return None

    def delta_of_symbol(self, symbol: sp.Symbol) -> sp.Expr:
        """Variation of one ideal model symbol (zero for inputs and parameters)."""
        name = symbol.name
        if name in self.error_of_state:
            return self.error_of_state[name]
        if name in self.intermediates:
            return self.delta_of[name]
        return sp.S.Zero

    def vary(self, expr: sp.Expr) -> sp.Expr:
        """First-order variation of an ideal expression in model symbols (chain rule)."""
        total = sp.S.Zero
        for symbol in sorted(expr.free_symbols, key=sp.default_sort_key):
            delta = self.delta_of_symbol(symbol)
            if delta != 0:
                total += sp.diff(expr, symbol) * delta
        return total

    def delta(self, name: str) -> sp.Expr | None:
        """Variation of a model name (state, intermediate, output), or None."""
        if name in self.error_of_state:
            return self.error_of_state[name]
        if name in self.delta_of:
            return self.delta_of[name]
        if name in self.outputs:
            return self.vary(self.outputs[name])
        return None


# --------------------------------------------------------------------------------------
# The hand side
# --------------------------------------------------------------------------------------
class _HandSide:
    """Resolves hand symbols through the hand file's definitions and the notation."""

    def __init__(self, model: _ModelSide, notation: Notation, hand: HandFile):
        self.model = model
        self.notation = notation
        self.hand = hand
        self.definitions: list[dict[str, HandEquation]] = [{} for _ in hand.sections]
        self.duplicates: set[int] = set()
        self.broken: dict[int, str] = {}
        self.used_definitions: set[int] = set()
        self.from_model: dict[str, set[int]] = {}
        self.sources_used: set[str] = set()
        self._alias_cache: dict[str, sp.Expr] = {}
        self.current_line = 0
        self.keep_ideal = False
        for eq in hand.equations:
            if eq.alternative or not isinstance(eq.lhs, sp.Symbol):
                continue
            key = self.definition_key(eq)
            table = self.definitions[eq.section]
            if key in table:
                first = table[key]
                self.duplicates.add(id(eq))
                hand.problems.append(Problem(
                    eq.line, eq.column,
                    f"duplicate definition of {key} (first at line {first.line}); the "
                    "first is used, this one is checked on its own (mark printed "
                    "alternatives with @alt)"))
                continue
            table[key] = eq

    # -- classification -----------------------------------------------------------------
    def is_source(self, name: str) -> bool:
        return name in self.notation.sources or name in self.model.sources

    def knows(self, name: str) -> bool:
        """True if ``name`` has a meaning (model name, alias, hand definition...)."""
        return (name in self.notation.aliases or self.model.ideal(name) is not None
                or name in self.model.error_of_state or self.is_source(name)
                or name in self.model.error_states or self.visible(name, None) is not None)

    def variation_base(self, name: str) -> str | None:
        """``X`` if ``name`` spells the variation of X (``Delta_X`` or ``dX``)."""
        if self.is_source(name) or name in self.model.error_states:
            return None
        if name.startswith("Delta_") and len(name) > 6:
            return name[6:]
        if (name.startswith("d") and len(name) > 1
                and self.visible(name, None) is None and self.model.ideal(name) is None
                and name not in self.notation.aliases):
            base = self.notation.spellings.get(name[1:], name[1:])
            if (base in self.notation.aliases or self.model.ideal(base) is not None
                    or base in self.model.error_of_state):
                return base
        return None

    def is_variational(self, expr: sp.Expr) -> bool:
        """True if ``expr`` contains an error quantity (variation, error state, source)."""
        if expr.atoms(TILDE):
            return True
        for symbol in expr.free_symbols:
            name = symbol.name
            if (self.is_source(name) or name in self.model.error_states
                    or self.variation_base(name) is not None):
                return True
        return False

    def definition_key(self, eq: HandEquation) -> str:
        """Name a definition provides: ``Delta_X`` for variations (incl. ``dX``)."""
        name = eq.lhs.name
        base = self.variation_base(name)
        if base is not None:
            return f"Delta_{base}"
        model_meaning = name in self.notation.aliases or self.model.ideal(name) is not None
        if model_meaning and any(self.is_variational(f) for f in eq.forms):
            return f"Delta_{name}"  # printed without Δ
        return name

    def visible(self, key: str, section: int | None) -> HandEquation | None:
        """The definition of ``key`` seen from ``section`` (None: any section)."""
        sections = range(len(self.definitions) - 1, -1, -1) if section is None else range(
            section, -1, -1)
        for s in sections:
            if key in self.definitions[s]:
                return self.definitions[s][key]
        return None

    # -- resolution ---------------------------------------------------------------------
    def alias(self, name: str, trail: tuple[str, ...] = ()) -> sp.Expr:
        """Model expression of a notation alias (aliases may use other aliases)."""
        if name in self._alias_cache:
            return self._alias_cache[name]
        if name in trail:
            raise _UnresolvedError(name, f"alias {name} refers to itself")
        from ins_errors.checker.parse import parse_text_expression

        text = self.notation.aliases[name]
        try:
            expr, _ = parse_text_expression(text, Notation())
        except Exception as error:
            raise _UnresolvedError(name, f"alias {name} = {text!r} cannot be parsed: "
                                    f"{getattr(error, 'message', error)}") from None
        replace = {}
        for symbol in expr.free_symbols:
            model = self.model.ideal(symbol.name)
            if model is not None:
                replace[symbol] = model
            elif symbol.name in self.notation.aliases:
                replace[symbol] = self.alias(symbol.name, (*trail, name))
            else:
                raise _UnresolvedError(symbol.name, f"alias {name} = {text!r} uses "
                                  f"{symbol.name!r}, which is not a model name")
        result = expr.xreplace(replace)
        self._alias_cache[name] = result
        return result

    def model_meaning(self, name: str) -> sp.Expr | None:
        """Ideal value of ``name`` in model symbols via the notation, or None."""
        if name in self.notation.aliases:
            return self.alias(name)
        return self.model.ideal(name)

    def basis_symbol(self, name: str) -> sp.Symbol:
        if name in self.notation.sources:
            self.sources_used.add(name)
            return sp.Symbol(name, real=True)
        if name in self.model.sources:
            self.sources_used.add(name)
            return self.model.source_symbols[name]
        return self.model.error_states[name]

    def resolve(self, expr: sp.Expr, section: int, trail: tuple[str, ...]) -> sp.Expr:
        """Bring a hand expression to basis + ideal model symbols."""
        tildes = {f: f.args[0] + sp.Symbol(f"Delta_{f.args[0]}") for f in expr.atoms(TILDE)}
        if tildes:
            expr = expr.xreplace(tildes)
        if expr.atoms(DOT):
            raise _UnresolvedError(None, "a time derivative dot(...) is only allowed on the "
                                    "left-hand side")
        replace = {s: self.symbol(s.name, section, trail)
                   for s in sorted(expr.free_symbols, key=sp.default_sort_key)}
        return expr.xreplace(replace)

    def symbol(self, name: str, section: int, trail: tuple[str, ...]) -> sp.Expr:
        """Meaning of one hand symbol (basis, hand definition, model quantity)."""
        if self.is_source(name) or name in self.model.error_states:
            return self.basis_symbol(name)
        base = self.variation_base(name)
        if base is not None:
            return self.variation(base, section, trail)
        eq = self.visible(name, section)
        if eq is not None and self.definition_key(eq) == name:
            if self.keep_ideal:
                return sp.Symbol(name, real=True)
            return self.use_definition(eq, name, section, trail)
        meaning = self.model_meaning(name)
        if meaning is not None:
            return sp.Symbol(name, real=True) if self.keep_ideal else meaning
        raise _UnresolvedError(name, self.unknown_message(name))

    def display_form(self, expr: sp.Expr, section: int, trail: tuple[str, ...]
                     ) -> sp.Expr | None:
        """``expr`` with its variations resolved but its ideal symbols kept (D, R_eta)."""
        self.keep_ideal = True
        try:
            return self.resolve(expr, section, trail)
        except _UnresolvedError:
            return None
        finally:
            self.keep_ideal = False

    def use_definition(self, eq: HandEquation, key: str, section: int,
                       trail: tuple[str, ...]) -> sp.Expr:
        if key in trail:
            raise _UnresolvedError(key, f"definition of {key} (line {eq.line}) refers to itself "
                                   f"through {' -> '.join((*trail, key))}")
        if id(eq) in self.broken:
            raise _UnresolvedError(key, f"uses {key}, whose definition (line {eq.line}) has an "
                                   "error")
        self.used_definitions.add(id(eq))
        form = self.defining_form(eq)
        try:
            return self.resolve(form, eq.section, (*trail, key))
        except _UnresolvedError as error:
            if not trail:
                raise
            raise _UnresolvedError(key, f"uses {key} (line {eq.line}), which cannot be "
                                   f"resolved: {error.message}") from None

    def defining_form(self, eq: HandEquation) -> sp.Expr:
        """First form of a chain that is not the quantity restated by name."""
        key = self.definition_key(eq)
        for form in eq.forms:
            if not self.tautology(form, key):
                return form
        return eq.forms[0]

    def tautology(self, form: sp.Expr, key: str) -> bool:
        """True if ``form`` is ``key`` itself (``tilde(W) - W`` for ``Delta_W``)."""
        tildes = {f: f.args[0] + sp.Symbol(f"Delta_{f.args[0]}") for f in form.atoms(TILDE)}
        expanded = sp.expand(form.xreplace(tildes))
        return sp.expand(expanded - sp.Symbol(key)) == 0

    def variation(self, base: str, section: int, trail: tuple[str, ...]) -> sp.Expr:
        """Meaning of ``Delta_base`` on the hand side."""
        key = f"Delta_{base}"
        eq = self.visible(key, section)
        if eq is not None:
            return self.use_definition(eq, key, section, trail)
        if base in self.model.error_of_state:
            return self.model.error_of_state[base]
        meaning = self.model_meaning(base)
        if meaning is None:
            aux = self.visible(base, section)
            if aux is None:
                raise _UnresolvedError(key, self.unknown_message(key))
            keep, self.keep_ideal = self.keep_ideal, False
            try:
                meaning = self.use_definition(aux, base, section, trail)
            finally:
                self.keep_ideal = keep
        self.from_model.setdefault(key, set()).add(self.current_line)
        return self.model.vary(meaning)

    def known_names(self) -> list[str]:
        names = set(self.notation.aliases) | set(self.notation.sources)
        names |= set(self.model.symbols) | set(self.model.outputs)
        names |= set(self.model.error_states) | set(self.model.sources)
        names |= {f"Delta_{n}" for n in (*self.model.symbols, *self.model.outputs,
                                        *self.notation.aliases)}
        for table in self.definitions:
            names |= set(table)
        return sorted(names)

    def unknown_message(self, name: str) -> str:
        close = difflib.get_close_matches(name, self.known_names(), n=3, cutoff=0.6)
        hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
        return f"unknown symbol {name!r}{hint}"


# --------------------------------------------------------------------------------------
# Comparison
# --------------------------------------------------------------------------------------
def _linear_parts(expr: sp.Expr, basis: list[sp.Symbol]
                  ) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
    """Coefficients of the basis quantities in ``expr`` and its constant part.

    Error equations are linear in the errors: a coefficient is the derivative by its
    quantity with every quantity at zero. A term that is not linear (α², sin α, α·β) is
    an input problem, not a coefficient to compare.

    Raises
    ------
    _UnresolvedError
        If ``expr`` is not linear in the basis quantities or has a non-finite part.
    """
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise _UnresolvedError(None, "a term is not finite (division by zero?)")
    present = [b for b in basis if b in expr.free_symbols]
    zero = {b: sp.S.Zero for b in present}
    coefficients = {}
    for b in present:
        derivative = sp.diff(expr, b)
        if any(q in derivative.free_symbols and sp.diff(derivative, q) != 0 for q in present):
            raise _UnresolvedError(b.name, f"not linear in the error quantity {b.name}: "
                                   "error equations must be linear in the errors")
        coefficients[b] = derivative.xreplace(zero)
    return coefficients, expr.xreplace(zero)


def _display(expr: sp.Expr, limit: int = 200) -> str:
    """Canonical (expanded when cheap) text of a coefficient, shortened to ``limit``."""
    if expr == 0:
        return "0"
    if sp.count_ops(expr) < 300:
        expr = sp.expand_mul(expr)
    text = sp.sstr(expr)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _term_difference(hand: sp.Expr, model: sp.Expr) -> tuple[sp.Expr, sp.Expr] | None:
    """(terms only the model has, terms only the hand has), if both expand cheaply."""
    if sp.count_ops(hand) > 60 or sp.count_ops(model) > 60:
        return None
    hand_terms = sp.Add.make_args(sp.expand(hand))
    model_terms = sp.Add.make_args(sp.expand(model))
    missing = [t for t in model_terms if t not in hand_terms]
    extra = [t for t in hand_terms if t not in model_terms]
    return sp.Add(*missing), sp.Add(*extra)


class _Comparison:
    def __init__(self, points: list[ReferencePoint], basis: list[BasisQuantity],
                 symbols: dict[str, sp.Symbol], threshold: float):
        self.points = points
        self.arguments = sorted(points[0].values, key=sp.default_sort_key)
        self.arrays = [np.array([p.values[s] for p in points]) for s in self.arguments]
        self.basis = basis
        self.symbols = [symbols[b.name] for b in basis]
        self.magnitude = {symbols[b.name]: b.magnitude for b in basis}
        self.threshold = threshold
        self._parts: dict[sp.Expr, tuple[dict[sp.Symbol, sp.Expr], sp.Expr]] = {}
        self.display_model: dict[sp.Symbol, sp.Expr] = {}
        self._values: dict[sp.Expr, np.ndarray] = {}

    def severity(self, size: float) -> Severity:
        return "mistake" if size >= self.threshold else "dropped small term"

    def linear_parts(self, expr: sp.Expr) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
        if expr not in self._parts:
            self._parts[expr] = _linear_parts(expr, self.symbols)
        return self._parts[expr]

    def prefetch(self, pairs: list[tuple[sp.Expr, sp.Expr]]) -> None:
        """Evaluate the coefficients of many equations in one vectorised call."""
        wanted = []
        for hand, model in pairs:
            try:
                h, hc = self.linear_parts(hand)
                m, mc = self.linear_parts(model)
            except _UnresolvedError:
                continue  # reported with its own equation
            wanted += [*h.values(), *m.values(), hc - mc]
        known = set(self.arguments)
        todo = list(dict.fromkeys(e for e in wanted if e not in self._values
                                  and e.free_symbols <= known))
        if not todo:
            return
        function = sp.lambdify(self.arguments, todo, modules="numpy", cse=True)
        with np.errstate(all="ignore"):
            values = function(*self.arrays)
        for expr, value in zip(todo, values, strict=True):
            self._values[expr] = np.broadcast_to(np.asarray(value, dtype=complex),
                                                 (len(self.points),))

    def evaluate(self, exprs: list[sp.Expr]) -> np.ndarray:
        """Values of ``exprs`` at every reference point, shape (len(exprs), points)."""
        if all(e in self._values for e in exprs):
            return self.checked(np.array([self._values[e] for e in exprs]))
        stray = set().union(*(e.free_symbols for e in exprs)) - set(self.arguments)
        if stray:
            name = sorted(stray, key=sp.default_sort_key)[0]
            raise _UnresolvedError(str(name), f"{name} has no value at the reference points")
        function = sp.lambdify(self.arguments, exprs, modules="numpy", cse=True)
        with np.errstate(all="ignore"):
            values = [np.broadcast_to(np.asarray(v, dtype=complex), (len(self.points),))
                      for v in function(*self.arrays)]
        return self.checked(np.array(values))

    def identical(self, hand: sp.Expr, model: sp.Expr, limit: int = 400) -> bool | None:
        """True if every coefficient is the same expression (expanded), None if too big."""
        h, hc = self.linear_parts(hand)
        m, mc = self.linear_parts(model)
        pairs = [(h.get(b, sp.S.Zero), m.get(b, sp.S.Zero)) for b in set(h) | set(m)]
        pairs.append((hc, mc))
        if sum(sp.count_ops(a) + sp.count_ops(b) for a, b in pairs) > limit:
            return None
        return all(sp.expand(a - b) == 0 for a, b in pairs)

    @staticmethod
    def checked(values: np.ndarray) -> np.ndarray:
        """Real parts, after checking the values are finite and real."""
        if not np.all(np.isfinite(values)):
            raise _UnresolvedError(None, "a coefficient is not finite at a reference point "
                                         "(division by zero?)")
        if np.any(np.abs(values.imag) > 1e-9 * np.maximum(np.abs(values.real), 1e-300)):
            raise _UnresolvedError(None, "a coefficient is complex at a reference point")
        return values.real

    def compare(self, hand: sp.Expr, model: sp.Expr, hand_display: sp.Expr | None = None
                ) -> list[Finding]:
        """Findings of one equation (both sides already in basis + model symbols).

        ``hand_display`` is the hand side with its own ideal symbols kept, used only to
        show the hand coefficients in the researcher's notation.
        """
        h, hc = self.linear_parts(hand)
        m, mc = self.linear_parts(model)
        shown = _linear_parts(hand_display, self.symbols)[0] if hand_display is not None else h
        model_shown = {b: e.xreplace(self.display_model) for b, e in m.items()}
        quantities = [b for b in self.symbols if b in h or b in m]
        exprs = [h.get(b, sp.S.Zero) for b in quantities] + [
            m.get(b, sp.S.Zero) for b in quantities] + [hc - mc]
        values = self.evaluate(exprs)
        k = len(quantities)
        hv, mv, constant = values[:k], values[k:2 * k], values[2 * k]
        weights = np.array([self.magnitude[b] for b in quantities]).reshape(-1, 1)
        largest = np.max(np.abs(np.concatenate([hv, mv])) * np.concatenate(
            [weights, weights]), axis=0) if k else np.zeros(len(self.points))
        safe = np.where(largest > 0, largest, np.inf)
        raw: dict[sp.Symbol, dict] = {}
        for i, b in enumerate(quantities):
            ratios = np.abs(hv[i] - mv[i]) * weights[i] / safe
            j = int(np.argmax(ratios))
            if ratios[j] > AGREEMENT:
                raw[b] = {"size": float(ratios[j]), "point": self.points[j].label,
                          "hand": hv[i], "model": mv[i], "largest": largest,
                          "hand_expr": h.get(b, sp.S.Zero), "model_expr": m.get(b, sp.S.Zero),
                          "hand_shown": shown.get(b, sp.S.Zero).xreplace(self.display_model),
                          "model_shown": model_shown.get(b, sp.S.Zero)}
        findings = self.pair_wrong_variables(raw)
        for b, info in raw.items():
            findings.append(self.finding(b, info))
        ratios = np.where(largest > 0, np.abs(constant) / safe,
                          np.where(constant == 0, 0.0, np.inf))
        j = int(np.argmax(ratios))
        if ratios[j] > AGREEMENT:
            findings.append(Finding("(none)", "not an error quantity", "mistake",
                                    float(ratios[j]), self.points[j].label, _display(hc), "0",
                                    "a term that contains no error quantity (an ideal value "
                                    "where a variation belongs?)"))
        return findings

    def finding(self, b: sp.Symbol, info: dict) -> Finding:
        hs, ms, largest = info["hand"], info["model"], info["largest"]
        tiny = 1e-12 * largest / self.magnitude[b]
        hand_zero = bool(np.all(np.abs(hs) <= tiny))
        model_zero = bool(np.all(np.abs(ms) <= tiny))
        detail = ""
        if hand_zero:
            kind = "missing term"
        elif model_zero:
            kind = "extra term"
        elif np.all(np.abs(hs + ms) <= 1e-6 * np.maximum(np.abs(hs), np.abs(ms))):
            kind = "sign error"
        else:
            kind = "wrong coefficient"
            usable = np.abs(ms) > tiny
            ratios = hs[usable] / ms[usable]
            split = _term_difference(info["hand_expr"], info["model_expr"])
            if split is not None:
                split = tuple(part.xreplace(self.display_model) for part in split)
                if any(len(sp.sstr(part)) > 120 for part in split):
                    split = None
            if ratios.size and np.all(np.abs(ratios - ratios[0]) <= 1e-6 * abs(ratios[0])):
                detail = f"hand/model = {ratios[0]:.6g} at every point"
            elif split is not None and split[1] == 0:
                kind = "missing term"
                detail = f"part of the coefficient is missing: {_display(split[0])}"
            elif split is not None and split[0] == 0:
                kind = "extra term"
                detail = f"extra part of the coefficient: {_display(split[1])}"
            elif split is not None:
                detail = f"model has {_display(split[0])} where the hand has {_display(split[1])}"
        return Finding(str(b), kind, self.severity(info["size"]), info["size"], info["point"],
                       _display(info["hand_shown"]), _display(info["model_shown"]), detail)

    def pair_wrong_variables(self, raw: dict) -> list[Finding]:
        """Merge a deficit on A and an equal excess on B into one 'wrong variable'."""
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
                lost, got = (a, b) if np.sum(np.abs(raw[a]["model"])) >= np.sum(
                    np.abs(raw[b]["model"])) else (b, a)
                first = raw[a] if raw[a]["size"] >= raw[b]["size"] else raw[b]
                moved = _display((raw[lost]["model_expr"] - raw[lost]["hand_expr"]).xreplace(
                    self.display_model))
                findings.append(Finding(
                    f"{lost} -> {got}", "wrong variable", self.severity(first["size"]),
                    first["size"], first["point"], _display(raw[got]["hand_shown"]),
                    _display(raw[lost]["model_shown"]),
                    f"the model's term ({moved})*{lost} is written on {got}"))
                del raw[a], raw[b]
        return findings

    def compare_values(self, hand: sp.Expr, model: sp.Expr) -> list[Finding]:
        """Findings of an ideal (non-error) definition: its value at the points."""
        h, m = self.evaluate([hand, model])
        scale = np.maximum(np.abs(h), np.abs(m))
        ratios = np.where(scale > 0, np.abs(h - m) / np.where(scale > 0, scale, 1), 0.0)
        j = int(np.argmax(ratios))
        if ratios[j] <= AGREEMENT:
            return []
        return [Finding("(value)", "wrong definition", self.severity(float(ratios[j])),
                        float(ratios[j]), self.points[j].label, _display(hand), _display(model),
                        "the ideal value differs")]


# --------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------
def _basis(model: _ModelSide, notation: Notation, sources_used: Iterable[str]
           ) -> tuple[list[BasisQuantity], dict[sp.Symbol, sp.Expr], list[str]]:
    """Basis quantities, the model-side identification and the out-of-scope sources."""
    basis = []
    for name, unit in model.error_units.items():
        magnitude, text = typical_magnitude(unit)
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
        magnitude, text = typical_magnitude(units.pop())
        basis.append(BasisQuantity(hand_name, model.sources[targets[0]].unit, magnitude, text,
                                   tuple(targets)))
        for t in targets:
            identify[model.source_symbols[t]] = sp.Symbol(hand_name, real=True)
        covered.update(targets)
    for name, source in model.sources.items():
        if name in used and name not in covered:
            magnitude, text = typical_magnitude(source.unit)
            basis.append(BasisQuantity(name, source.unit, magnitude, text))
            covered.add(name)
    out = [name for name in model.sources if name not in covered]
    for name in out:
        identify[model.source_symbols[name]] = sp.S.Zero
    return basis, identify, out


_SHARED: dict[int, tuple] = {}


def _shared(d: ModelDefinition) -> tuple[_ModelSide, list[ReferencePoint], dict]:
    """Model side, reference points and evaluated coefficients, kept per definition."""
    entry = _SHARED.get(id(d))
    if entry is None or entry[0] is not d:
        entry = (d, _ModelSide(d), reference_points(d), {})
        _SHARED[id(d)] = entry
    return entry[1], entry[2], entry[3]


def check_hand(hand: HandFile, model: str = "orthodromic", threshold: float = DEFAULT_THRESHOLD,
               mapping: Notation | None = None) -> CheckReport:
    """Check every equation of a parsed hand file against the model's variation.

    Parameters
    ----------
    hand : HandFile
        From :func:`~ins_errors.checker.parse.read_hand_file` (its own ``@alias``
        / ``@source`` entries apply on top of the model's default notation and ``mapping``).
    model : str
        Registered model name.
    threshold : float
        Relative size separating "dropped small term" from "mistake" (0 < threshold < 1).
    mapping : Notation, optional
        Extra notation entries (from a mapping file).

    Returns
    -------
    CheckReport
    """
    if not 0 < threshold < 1:
        raise InsErrorsError(f"threshold must be between 0 and 1, got {threshold}")
    d = model_definition(model)
    side, points, values = _shared(d)
    notation = default_notation(model)
    if mapping is not None:
        notation = notation.merged(mapping)
    notation = notation.merged(hand.notation)
    resolver = _HandSide(side, notation, hand)

    # first pass: resolve every equation (this also finds the sources in use)
    prepared = []
    for eq in hand.equations:
        resolver.current_line = eq.line
        prepared.append(_prepare(eq, resolver, side))
    basis, identify, out_of_scope = _basis(side, notation, resolver.sources_used)
    symbols = {b.name: (side.error_states.get(b.name) or side.source_symbols.get(b.name)
                        or sp.Symbol(b.name, real=True)) for b in basis}
    comparison = _Comparison(points, basis, symbols, threshold)
    comparison._values = values
    comparison.display_model = _reciprocal_aliases(side, notation)

    comparison.prefetch([(item.hand, item.model.xreplace(identify))
                         for items in prepared for item in items
                         if item.hand is not None and item.model is not None
                         and not item.ideal and not item.status])
    results = []
    for eq, items in zip(hand.equations, prepared, strict=True):
        for item in items:
            results.append(_evaluate(eq, item, comparison, identify, hand))
    unused = [f"{r.equation.label} (line {r.equation.line})" for r in results
              if r.status == "hand-only definition" and r.form == 0
              and id(r.equation) not in resolver.used_definitions]
    hand.problems.sort(key=lambda p: (p.line, p.column or 0))
    return CheckReport(
        model=model, hand_name=hand.name, hand_format=hand.format, threshold=threshold,
        points=comparison.points, basis=basis, sections=hand.sections, results=results,
        problems=list(hand.problems), out_of_scope=out_of_scope,
        from_model={k: sorted(v) for k, v in sorted(resolver.from_model.items())},
        unused=unused)


def _reciprocal_aliases(side: _ModelSide, notation: Notation) -> dict[sp.Symbol, sp.Expr]:
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
class _Item:
    form: int
    target: str
    hand: sp.Expr | None = None
    hand_display: sp.Expr | None = None
    model: sp.Expr | None = None
    ideal: bool = False
    status: str = ""
    notes: list[str] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    problem: str | None = None


def _target(eq: HandEquation, resolver: _HandSide, side: _ModelSide
            ) -> tuple[str, sp.Expr | None, bool, list[Finding], list[str]]:
    """(description, model expression or None, ideal?, findings, notes) of a left side."""
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
            close = difflib.get_close_matches(inner, names, n=3, cutoff=0.6)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise _UnresolvedError(inner, f"equation for dot({inner}), but {shown} is not a state "
                                     f"of the model {side.d.name!r}{hint} (error states: "
                                     f"{', '.join(side.error_states)})")
        return f"error state {name}", side.state_rhs[name], False, [], []
    key = resolver.definition_key(eq)
    name = lhs.name
    if key.startswith("Delta_") and key[6:] in side.error_of_state:
        raise _UnresolvedError(name, f"{name} is an error state: give its equation as "
                                f"dot({name})")
    if key.startswith("Delta_"):
        base = key[6:]
        meaning = resolver.model_meaning(base)
        if meaning is None:
            if resolver.visible(base, eq.section) is not None:
                return "hand-only definition", None, False, [], []
            close = difflib.get_close_matches(base, resolver.known_names(), n=3, cutoff=0.6)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise _UnresolvedError(name, f"{base} is not a quantity of the model or the "
                                         f"notation{hint} (declare it with '@alias {base} = "
                                         "...' to have its variation checked)")
        findings, notes = [], []
        if resolver.variation_base(name) is None:  # printed without Δ
            findings.append(Finding(
                "(left-hand side)", "left-hand side without Δ", "mistake", float("inf"), "",
                name, key, f"the right-hand side is a variation: read as {key}"))
        if base in resolver.notation.aliases:
            what = f"alias {base} = {resolver.notation.aliases[base]}"
            model = side.vary(meaning)
        elif base in side.intermediates:
            what, model = f"intermediate {base}", side.delta(base)
        elif base in side.outputs:
            what, model = f"output {base}", side.delta(base)
        else:
            what, model = f"model quantity {base}", side.vary(meaning)
        return what, model, False, findings, notes
    meaning = resolver.model_meaning(name)
    if meaning is not None:
        return f"ideal value of {name}", meaning, True, [], []
    return "hand-only definition", None, False, [], []


def _prepare(eq: HandEquation, resolver: _HandSide, side: _ModelSide) -> list[_Item]:
    items = []
    try:
        target, model, ideal, findings, notes = _target(eq, resolver, side)
    except _UnresolvedError as error:
        _report(eq, resolver, error)
        return [_Item(0, "", status="input error", problem=error.message)]
    key = resolver.definition_key(eq) if isinstance(eq.lhs, sp.Symbol) else eq.label
    for k, form in enumerate(eq.forms):
        item = _Item(k, target, model=model, ideal=ideal, findings=list(findings),
                     notes=list(notes))
        if isinstance(eq.lhs, sp.Symbol) and resolver.tautology(form, key):
            item.status = "tautology"
            item.notes.append(f"this form restates {key} by name; nothing to compare")
            items.append(item)
            continue
        try:
            trail = (key,) if isinstance(eq.lhs, sp.Symbol) else ()
            item.hand = resolver.resolve(form, eq.section, trail)
            item.hand_display = resolver.display_form(form, eq.section, trail)
        except _UnresolvedError as error:
            _report(eq, resolver, error)
            if k == 0 and isinstance(eq.lhs, sp.Symbol):
                resolver.broken[id(eq)] = error.message
            item.status, item.problem = "input error", error.message
        items.append(item)
    return items


def _report(eq: HandEquation, resolver: _HandSide, error: _UnresolvedError) -> None:
    column = eq.columns.get(error.symbol, eq.column) if error.symbol else eq.column
    resolver.hand.problems.append(Problem(eq.line, column, f"{eq.label}: {error.message}"))


def _evaluate(eq: HandEquation, item: _Item, comparison: _Comparison,
              identify: dict[sp.Symbol, sp.Expr], hand: HandFile) -> EquationResult:
    result = EquationResult(eq, item.form, item.target or "not compared", item.status or "",
                            list(item.findings), list(item.notes))
    if item.status in ("input error", "tautology"):
        if item.problem:
            result.notes.append(item.problem)
        return result
    if item.model is None:
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
                raise _UnresolvedError(None, "mixes ideal values and error quantities")
            result.findings += comparison.compare_values(item.hand, item.model)
        else:
            model = item.model.xreplace(identify)
            result.findings += comparison.compare(item.hand, model, item.hand_display)
    except _UnresolvedError as error:
        hand.problems.append(Problem(eq.line, eq.column, f"{eq.label}: {error.message}"))
        result.status = "input error"
        result.notes.append(error.message)
        return result
    if any(f.severity == "mistake" for f in result.findings):
        result.status = "mistake"
    elif result.findings:
        result.status = "agrees up to dropped small terms"
    else:
        result.status = "agrees"
        if not item.ideal and comparison.identical(item.hand, item.model.xreplace(identify)):
            result.notes.insert(0, "identical symbolically")
    return result


def check_hand_file(path, model: str = "orthodromic", threshold: float = DEFAULT_THRESHOLD,
                    latex: bool | None = None, mapping_path=None,
                    latex_backend: str = "lalr") -> CheckReport:
    """Read a hand file (and optional mapping file) and check it.

    Parameters
    ----------
    path : str or Path
        Hand file; LaTeX if ``latex`` or its suffix is ``.tex``.
    model : str
        Registered model name.
    threshold : float
        Relative size separating "dropped small term" from "mistake".
    latex : bool, optional
        Force the format (default: from the suffix).
    mapping_path : str or Path, optional
        Mapping file with ``@alias`` / ``@source`` lines.
    latex_backend : {"lalr", "sympy"}
        Parser of LaTeX arithmetic (see :data:`~ins_errors.checker.parse.LATEX_BACKENDS`).
    """
    from ins_errors.checker.parse import read_hand_file, read_mapping_file

    model_definition(model)  # unknown model: clear error before reading anything
    mapping = read_mapping_file(mapping_path) if mapping_path is not None else None
    notation = default_notation(model)
    if mapping is not None:
        notation = notation.merged(mapping)
    hand = read_hand_file(path, notation, latex=latex, latex_backend=latex_backend)
    return check_hand(hand, model=model, threshold=threshold, mapping=mapping)
