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
of its equation at the same point (the largest ratio over the points is reported).

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

import difflib
from collections.abc import Iterable
from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from ins_errors.checker import classify as cl
from ins_errors.checker.classify import Finding
from ins_errors.checker.notation import Notation, default_notation
from ins_errors.checker.parse import DOT, TILDE, HandEquation, HandFile, Problem
from ins_errors.checker.reference import (
    DEFAULT_ATTITUDE,
    Magnitudes,
    ReferencePoint,
    reference_points,
    schuler_magnitudes,
)
from ins_errors.errors import InsErrorsError
from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.variation import output_mechanisations, structured_variation

DEFAULT_THRESHOLD = 1e-3
"""Relative size separating small effects from mistakes."""
AGREEMENT = 1e-9
"""Relative size below which two coefficients are taken as equal (rounding)."""

__all__ = ["AGREEMENT", "DEFAULT_THRESHOLD", "BasisQuantity", "CheckReport", "EquationResult",
           "Finding", "check_hand", "check_hand_file"]


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

    @property
    def findings(self) -> list[tuple[EquationResult, Finding]]:
        """Every (result, finding) pair, in file order."""
        return [(r, f) for r in self.results for f in r.findings]

    @property
    def mistakes(self) -> list[tuple[EquationResult, Finding]]:
        """Findings classed as mistakes (of any size, roots and knock-ons)."""
        return [(r, f) for r, f in self.findings if f.is_mistake]

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
# The model side
# --------------------------------------------------------------------------------------
_LINES: dict[int, tuple] = {}


def _structured(d: ModelDefinition) -> list:
    """:func:`structured_variation` of ``d``, computed once per definition."""
    entry = _LINES.get(id(d))
    if entry is None or entry[0] is not d:
        entry = (d, structured_variation(d))
        _LINES[id(d)] = entry
    return entry[1]


class _ModelSide:
    """Flat variations and ideal meanings of every model name."""

    def __init__(self, d: ModelDefinition, dropped: frozenset[str] = frozenset()):
        self.d = d
        self.dropped = dropped
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
        for line in _structured(d):
            rhs = line.rhs.xreplace(known)
            if line.kind == "intermediate" and line.name in dropped:
                rhs = sp.S.Zero
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
        self.trace: set[int] = set()
        self.isolate: _ModelSide | None = None
        self.needed: dict[str, sp.Expr] = {}
        self.symbolic: set[str] = set()
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
            if self.keep_ideal or name in self.symbolic:
                return sp.Symbol(name, real=True)
            if self.isolate is not None and name in self.needed:
                return self.needed[name]
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
        self.trace.add(id(eq))
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
        if eq is not None and self.isolate is not None:
            correct = self.correct_variation(base)
            if correct is not None:
                return correct
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
        if self.isolate is None:
            self.from_model.setdefault(key, set()).add(self.current_line)
        return (self.isolate or self.model).vary(meaning)

    def correct_variation(self, base: str) -> sp.Expr | None:
        """The model's variation of ``base`` (in the isolating model side), or None."""
        side = self.isolate
        if base in side.error_of_state:
            return side.error_of_state[base]
        meaning = self.model_meaning(base)
        if meaning is None:
            return None
        if base in side.delta_of and base not in self.notation.aliases:
            return side.delta_of[base]
        return side.vary(meaning)

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
    _UnresolvedError
        If ``expr`` is not linear in the basis quantities or has a non-finite part.
    """
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise _UnresolvedError(None, "a term is not finite (division by zero?)")
    present = [b for b in basis if b in expr.free_symbols]
    zero = {b: sp.S.Zero for b in present}
    coefficients = {}
    if trusted:  # linear by construction (the model's variation): substitute, no diff
        constant = expr.xreplace(zero)
        for b in present:
            coefficients[b] = expr.xreplace({**zero, b: sp.S.One}) - constant
        return coefficients, constant
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


def _term_difference(hand: sp.Expr, model: sp.Expr, limit: int = 150
                     ) -> tuple[sp.Expr, sp.Expr] | None:
    """(terms only the model has, terms only the hand has), if both expand cheaply."""
    if sp.count_ops(hand) > limit or sp.count_ops(model) > limit:
        return None
    hand_terms = sp.Add.make_args(sp.expand(hand))
    model_terms = sp.Add.make_args(sp.expand(model))
    missing = [t for t in model_terms if t not in hand_terms]
    extra = [t for t in hand_terms if t not in model_terms]
    return sp.Add(*missing), sp.Add(*extra)


class _Comparison:
    def __init__(self, points: list[ReferencePoint], basis: list[BasisQuantity],
                 symbols: dict[str, sp.Symbol], threshold: float,
                 values: dict[sp.Expr, np.ndarray]):
        self.points = points
        self.arguments = sorted(points[0].values, key=sp.default_sort_key)
        self.arrays = [np.array([p.values[s] for p in points]) for s in self.arguments]
        self.basis = basis
        self.symbols = [symbols[b.name] for b in basis]
        self.magnitude = {symbols[b.name]: b.magnitude for b in basis}
        self.threshold = threshold
        self._parts: dict[sp.Expr, tuple[dict[sp.Symbol, sp.Expr], sp.Expr]] = {}
        self.display_model: dict[sp.Symbol, sp.Expr] = {}
        self._values = values

    def linear_parts(self, expr: sp.Expr, trusted: bool = True
                     ) -> tuple[dict[sp.Symbol, sp.Expr], sp.Expr]:
        """Coefficients and constant part of ``expr`` (cached).

        Hand forms are checked for linearity when they are read (``_check_linear``) and
        the model's variation is linear by construction, so by default the split is by
        substitution.
        """
        if expr not in self._parts:
            self._parts[expr] = _linear_parts(expr, self.symbols, trusted)
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

    def raw(self, exprs: list[sp.Expr]) -> np.ndarray:
        """Complex values of ``exprs`` at every point, shape (len(exprs), points)."""
        missing = [e for e in dict.fromkeys(exprs) if e not in self._values]
        if missing:
            stray = set().union(*(e.free_symbols for e in missing)) - set(self.arguments)
            if stray:
                name = sorted(stray, key=sp.default_sort_key)[0]
                raise _UnresolvedError(str(name), f"{name} has no value at the reference "
                                                  "points")
            function = sp.lambdify(self.arguments, missing, modules="numpy", cse=True)
            with np.errstate(all="ignore"):
                for e, v in zip(missing, function(*self.arrays), strict=True):
                    self._values[e] = np.broadcast_to(np.asarray(v, dtype=complex),
                                                      (len(self.points),))
        return np.array([self._values[e] for e in exprs])

    def evaluate(self, exprs: list[sp.Expr]) -> np.ndarray:
        """Real values of ``exprs`` at every reference point, shape (len(exprs), points)."""
        return self.checked(self.raw(exprs))

    def try_evaluate(self, exprs: list[sp.Expr]) -> np.ndarray | None:
        """Values of candidate expressions (NaN where not finite or not real)."""
        try:
            values = self.raw(exprs)
        except (_UnresolvedError, TypeError, ValueError, ZeroDivisionError):
            return None
        bad = ~np.isfinite(values) | (np.abs(values.imag) > 1e-9 * np.maximum(
            np.abs(values.real), 1e-300))
        return np.where(bad, np.nan, values.real)

    def identical(self, hand: sp.Expr, model: sp.Expr, limit: int = 400) -> bool | None:
        """True if every coefficient is the same expression (expanded), None if too big."""
        h, hc = self.linear_parts(hand)
        m, mc = self.linear_parts(model, trusted=True)
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

    def differences(self, hand: sp.Expr, model: sp.Expr, trusted: bool = False
                    ) -> tuple[dict, np.ndarray, np.ndarray]:
        """Per basis quantity: discrepancy data; also the largest term and constant part."""
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
        safe = np.where(largest > 0, largest, np.inf)
        raw: dict[sp.Symbol, dict] = {}
        for i, b in enumerate(quantities):
            ratios = np.abs(hv[i] - mv[i]) * weights[i] / safe
            j = int(np.argmax(ratios))
            if ratios[j] > AGREEMENT:
                raw[b] = {"size": float(ratios[j]), "point": self.points[j].label,
                          "hand": hv[i], "model": mv[i], "largest": largest,
                          "hand_expr": h.get(b, sp.S.Zero), "model_expr": m.get(b, sp.S.Zero),
                          "ratios": ratios}
        return raw, largest, constant

    def compare(self, hand: sp.Expr, model: sp.Expr, hand_display: sp.Expr | None = None,
                diagnose: bool = True, trusted: bool = False) -> list[Finding]:
        """Findings of one equation (both sides already in basis + model symbols).

        ``hand_display`` is the hand side with its own ideal symbols kept, used only to
        show the hand coefficients in the researcher's notation. ``trusted``: the hand
        side is known to be linear (an isolated form of a line already checked).
        """
        raw, largest, constant = self.differences(hand, model, trusted)
        shown = (self.linear_parts(hand_display, trusted=True)[0] if hand_display is not None
                 else self.linear_parts(hand)[0])
        for b, info in raw.items():
            info["hand_shown"] = shown.get(b, sp.S.Zero).xreplace(self.display_model)
            info["model_shown"] = info["model_expr"].xreplace(self.display_model)
        findings = self.pair_wrong_variables(raw)
        for b, info in raw.items():
            findings.append(self.finding(b, info, diagnose))
        safe = np.where(largest > 0, largest, np.inf)
        ratios = np.where(largest > 0, np.abs(constant) / safe,
                          np.where(constant == 0, 0.0, np.inf))
        j = int(np.argmax(ratios))
        if ratios[j] > AGREEMENT:
            _, hc = self.linear_parts(hand)
            findings.append(Finding("(none)", cl.NOT_ERROR, cl.MISTAKE, float(ratios[j]),
                                    self.points[j].label, _display(hc), "0",
                                    "a term that contains no error quantity (an ideal value "
                                    "where a variation belongs?)"))
        return findings

    def finding(self, b: sp.Symbol, info: dict, diagnose: bool = True) -> Finding:
        hs, ms, largest = info["hand"], info["model"], info["largest"]
        tiny = 1e-12 * largest / self.magnitude[b]
        if diagnose:
            kind, detail = cl.diagnose(
                info["hand_expr"], info["model_expr"], hs, ms, tiny, self.try_evaluate,
                self.arguments, self._split)
        else:  # the cheap, numeric part only (omitted, extra, sign, constant ratio)
            kind, detail = cl.diagnose(info["hand_expr"], info["model_expr"], hs, ms, tiny,
                                       lambda exprs: None, [])
        return Finding(str(b), kind, cl.severity(kind, info["size"], self.threshold),
                       info["size"], info["point"], _display(info["hand_shown"]),
                       _display(info["model_shown"]), detail)

    def _split(self, hand: sp.Expr, model: sp.Expr):
        split = _term_difference(hand, model)
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
                lost, got = (a, b) if np.sum(np.abs(raw[a]["model"])) >= np.sum(
                    np.abs(raw[b]["model"])) else (b, a)
                first = raw[a] if raw[a]["size"] >= raw[b]["size"] else raw[b]
                moved = _display((raw[lost]["model_expr"] - raw[lost]["hand_expr"]).xreplace(
                    self.display_model))
                findings.append(Finding(
                    f"{lost} -> {got}", cl.SYMBOL,
                    cl.severity(cl.SYMBOL, first["size"], self.threshold),
                    first["size"], first["point"], _display(raw[got]["hand_shown"]),
                    _display(raw[lost]["model_shown"]),
                    f"the model's term ({moved})*{lost} is written on {got}"))
                del raw[a], raw[b]
        return findings

    def compare_values(self, hand: sp.Expr, model: sp.Expr, what: str = "the ideal value"
                       ) -> list[Finding]:
        """Findings of an ideal (non-error) definition: its value at the points."""
        h, m = self.evaluate([hand, model])
        scale = np.maximum(np.abs(h), np.abs(m))
        ratios = np.where(scale > 0, np.abs(h - m) / np.where(scale > 0, scale, 1), 0.0)
        j = int(np.argmax(ratios))
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
def _basis(model: _ModelSide, notation: Notation, sources_used: Iterable[str],
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


def _side(d: ModelDefinition, dropped: frozenset[str] = frozenset()) -> _ModelSide:
    """Model side (with some intermediate variations dropped), kept per definition."""
    key = ("side", id(d), dropped)
    entry = _SHARED.get(key)
    if entry is None or entry[0] is not d:
        entry = (d, _ModelSide(d, dropped))
        _SHARED[key] = entry
    return entry[1]


def _points(d: ModelDefinition, scope: str | None):
    """Reference motions and the evaluated-coefficient cache, kept per definition."""
    key = ("points", id(d), scope)
    entry = _SHARED.get(key)
    if entry is None or entry[0] is not d:
        entry = (d, reference_points(d, scope), {})
        _SHARED[key] = entry
    return entry[1], entry[2]


def resolve_model(model: str | ModelDefinition) -> ModelDefinition:
    """The definition of a model: a built-in name, a model file (``./my_ins.py``), an
    installed entry point (see :mod:`ins_errors.model_lookup`), or a definition."""
    if isinstance(model, ModelDefinition):
        return model
    from ins_errors.model_lookup import definition_of, resolve

    return definition_of(resolve(model))


def check_hand(hand: HandFile, model: str | ModelDefinition = "orthodromic",
               threshold: float = DEFAULT_THRESHOLD, mapping: Notation | None = None,
               magnitudes: dict[str, str] | None = None, effects: bool = True
               ) -> CheckReport:
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
    if not hand.equations and not hand.problems:
        raise InsErrorsError(f"{hand.name}: no equations to check (an empty hand file "
                             "cannot be said to agree with anything)")
    d = resolve_model(model)
    side = _side(d)
    motions, values = _points(d, hand.scope)
    if not motions.points:
        raise InsErrorsError(f"model {d.name!r} cannot fly any reference motion of scope "
                             f"{hand.scope!r}: {'; '.join(motions.skipped)}")
    wanted = {**hand.magnitudes, **(magnitudes or {})}
    attitude = wanted.pop("attitude", DEFAULT_ATTITUDE)
    sizes = schuler_magnitudes(d, attitude, wanted)
    notation = default_notation(d)
    if mapping is not None:
        notation = notation.merged(mapping)
    notation = notation.merged(hand.notation)
    resolver = _HandSide(side, notation, hand)

    # first pass: resolve every equation (this also finds the sources in use)
    prepared = []
    for eq in hand.equations:
        resolver.current_line = eq.line
        prepared.append(_prepare(eq, resolver, side))
    declared = _Declarations(hand, resolver, side)
    basis, identify, out_of_scope = _basis(side, notation, resolver.sources_used, sizes)
    symbols = {b.name: (side.error_states.get(b.name) or side.source_symbols.get(b.name)
                        or sp.Symbol(b.name, real=True)) for b in basis}
    comparison = _Comparison(motions.points, basis, symbols, threshold, values)
    comparison.display_model = _reciprocal_aliases(side, notation)
    declared.finish(comparison, identify)

    comparison.prefetch([(item.hand, _model_expr(side, item.key).xreplace(identify))
                         for items in prepared for item in items
                         if item.hand is not None and item.key is not None
                         and not item.ideal and not item.status])
    needed = _helpers(hand, prepared, resolver, comparison, identify, declared)
    _complete(hand, prepared, resolver, comparison, identify, declared, needed)
    results = []
    for eq, items in zip(hand.equations, prepared, strict=True):
        for item in items:
            results.append(_evaluate(eq, item, comparison, identify, hand, resolver,
                                     declared, needed))
    _assign_roots(results, prepared, hand)
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
        idle_declarations=declared.idle())
    if effects and report.findings:
        from ins_errors.checker.effect import add_effects

        add_effects(report, d, side, comparison, identify, prepared, resolver)
    return report


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
    key: tuple | None = None
    ideal: bool = False
    status: str = ""
    notes: list[str] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    problem: str | None = None
    deps: frozenset[int] = frozenset()
    model_full: sp.Expr | None = None
    model_declared: sp.Expr | None = None
    hand_isolated: sp.Expr | None = None


def _model_expr(side: _ModelSide, key: tuple) -> sp.Expr:
    """The model's expression for a target key (see :func:`_target`)."""
    kind, what = key
    if kind == "state":
        return side.state_rhs[what]
    if kind == "delta":
        return side.delta(what)
    if kind == "vary":
        return side.vary(what)
    return what  # "ideal"


def _target(eq: HandEquation, resolver: _HandSide, side: _ModelSide
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
            close = difflib.get_close_matches(inner, names, n=3, cutoff=0.6)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise _UnresolvedError(inner, f"equation for dot({inner}), but {shown} is not a state "
                                     f"of the model {side.d.name!r}{hint} (error states: "
                                     f"{', '.join(side.error_states)})")
        return f"error state {name}", ("state", name), False, [], []
    key = resolver.definition_key(eq)
    name = lhs.name
    if name in side.error_states or (key.startswith("Delta_")
                                     and key[6:] in side.error_of_state):
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


def _prepare(eq: HandEquation, resolver: _HandSide, side: _ModelSide) -> list[_Item]:
    items = []
    try:
        target, key_model, ideal, findings, notes = _target(eq, resolver, side)
    except _UnresolvedError as error:
        _report(eq, resolver, error)
        return [_Item(0, "", status="input error", problem=error.message)]
    key = resolver.definition_key(eq) if isinstance(eq.lhs, sp.Symbol) else eq.label
    for k, form in enumerate(eq.forms):
        item = _Item(k, target, key=key_model, ideal=ideal, findings=list(findings),
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
        except _UnresolvedError as error:
            _report(eq, resolver, error)
            if k == 0 and isinstance(eq.lhs, sp.Symbol):
                resolver.broken[id(eq)] = error.message
            item.status, item.problem = "input error", error.message
        items.append(item)
    return items


def _check_linear(form: sp.Expr, resolver: _HandSide) -> None:
    """Refuse a form that is not linear in its error quantities (α², sin α, α·β, 1/0).

    Every definition a form uses is checked on its own line, and the model's variation
    is linear by construction, so checking the printed form suffices: the resolved sides
    can then be split into coefficients by substitution (cheap) instead of by
    differentiation of deep expressions.
    """
    tildes = {f: f.args[0] + sp.Symbol(f"Delta_{f.args[0]}") for f in form.atoms(TILDE)}
    if tildes:
        form = form.xreplace(tildes)
    if form.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise _UnresolvedError(None, "a term is not finite (division by zero?)")
    errors = [s for s in sorted(form.free_symbols, key=sp.default_sort_key)
              if resolver.is_variational(s)]
    for b in errors:
        derivative = sp.diff(form, b)
        if any(q in derivative.free_symbols and sp.diff(derivative, q) != 0 for q in errors):
            raise _UnresolvedError(b.name, f"not linear in the error quantity {b.name}: "
                                   "error equations must be linear in the errors")


def _report(eq: HandEquation, resolver: _HandSide, error: _UnresolvedError) -> None:
    column = eq.columns.get(error.symbol, eq.column) if error.symbol else eq.column
    resolver.hand.problems.append(Problem(eq.line, column, f"{eq.label}: {error.message}"))


# -- declared simplifications ----------------------------------------------------------
class _Declarations:
    """The ``@neglect`` lines: variations dropped (model side) and terms left out."""

    def __init__(self, hand: HandFile, resolver: _HandSide, side: _ModelSide):
        self.hand = hand
        self.dropped: list[frozenset[str]] = []
        self.terms: list[list[sp.Expr]] = []
        self.used = [False] * len(hand.declarations)
        self.side = side
        for declaration in hand.declarations:
            names, terms = set(), []
            for item, text in zip(declaration.items, declaration.texts, strict=True):
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
                except _UnresolvedError as error:
                    hand.problems.append(Problem(declaration.line, None,
                                                 f"@neglect {text}: {error.message}"))
            self.dropped.append(frozenset(names))
            self.terms.append(terms)
        self.term_values: list[list[dict]] = []

    def finish(self, comparison: _Comparison, identify: dict) -> None:
        """Evaluate the declared terms' coefficients at the reference points."""
        for terms in self.terms:
            evaluated = []
            for term in terms:
                try:
                    parts, _ = comparison.linear_parts(term.xreplace(identify))
                    evaluated.append({b: comparison.evaluate([c])[0] for b, c in parts.items()})
                except _UnresolvedError:
                    continue
            self.term_values.append(evaluated)

    def dropped_for(self, eq: HandEquation) -> frozenset[str]:
        return frozenset().union(*(self.dropped[k] for k in eq.declarations))

    def explains_term(self, eq: HandEquation, quantity: str, difference: np.ndarray,
                      comparison: _Comparison) -> bool:
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
            if self.dropped[k]:
                self.used[k] = True

    def texts(self) -> list[str]:
        return [f"line {d.line}: {', '.join(d.texts)}" + (f" ({d.reason})" if d.reason else "")
                for d in self.hand.declarations]

    def idle(self) -> list[str]:
        return [f"line {d.line}: {', '.join(d.texts)}"
                for d, used in zip(self.hand.declarations, self.used, strict=True) if not used]


# -- hand-only helpers ------------------------------------------------------------------
@dataclass
class _Needed:
    """The value a hand-only helper must have, from its simplest use."""

    expr: sp.Expr
    description: str
    line: int


def _helpers(hand: HandFile, prepared: list[list[_Item]], resolver: _HandSide,
             comparison: _Comparison, identify: dict, declared: _Declarations
             ) -> dict[str, _Needed]:
    """Needed value of each hand-only helper (ideal quantity with no model meaning)."""
    helpers: dict[str, list[HandEquation]] = {}
    for eq, items in zip(hand.equations, prepared, strict=True):
        if isinstance(eq.lhs, sp.Symbol) and items and items[0].target == "hand-only definition" \
                and resolver.variation_base(eq.lhs.name) is None:
            helpers.setdefault(eq.lhs.name, []).append(eq)
    needed: dict[str, _Needed] = {}
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


def _solve_helper(name: str, eq: HandEquation, item: _Item, resolver: _HandSide,
                  comparison: _Comparison, identify: dict, declared: _Declarations
                  ) -> _Needed | None:
    """The helper value that makes ``eq`` agree with the model (None if not unique)."""
    helper = sp.Symbol(name, real=True)
    resolver.symbolic = {name}
    try:
        hand = resolver.resolve(eq.forms[item.form], eq.section,
                                (resolver.definition_key(eq),) if isinstance(
                                    eq.lhs, sp.Symbol) else ())
    except _UnresolvedError:
        return None
    finally:
        resolver.symbolic = set()
    side = _side(resolver.model.d, declared.dropped_for(eq))
    model = _model_expr(side, item.key).xreplace(identify)
    try:
        h, _ = _linear_parts(hand, comparison.symbols)
        m, _ = comparison.linear_parts(model, trusted=True)
    except _UnresolvedError:
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
    return _Needed(candidates[0], what, eq.line)


# -- evaluation of one line ------------------------------------------------------------
def _evaluate(eq: HandEquation, item: _Item, comparison: _Comparison,
              identify: dict[sp.Symbol, sp.Expr], hand: HandFile, resolver: _HandSide,
              declared: _Declarations, needed: dict[str, _Needed]) -> EquationResult:
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
                raise _UnresolvedError(None, "mixes ideal values and error quantities")
            result.findings += comparison.compare_values(item.hand, item.key[1])
        else:
            result.findings += _line_findings(eq, item, comparison, identify, resolver,
                                              declared, needed, result)
    except _UnresolvedError as error:
        hand.problems.append(Problem(eq.line, eq.column, f"{eq.label}: {error.message}"))
        result.status = "input error"
        result.notes.append(error.message)
        return result
    _set_status(result)
    if result.status == "agrees" and not item.ideal:
        model = _model_expr(resolver.model, item.key).xreplace(identify)
        if comparison.identical(item.hand, model):
            result.notes.insert(0, "identical symbolically")
    return result


def _set_status(result: EquationResult) -> None:
    findings = result.findings
    if any(f.is_mistake for f in findings):
        result.status = "mistake"
    elif any(f.severity == cl.DROPPED for f in findings):
        result.status = "agrees up to dropped small terms"
    elif findings:
        result.status = "agrees up to declared drops"
    else:
        result.status = "agrees"


def _evaluate_helper(eq: HandEquation, item: _Item, result: EquationResult,
                     comparison: _Comparison, need: _Needed, hand: HandFile
                     ) -> EquationResult:
    """A hand-only helper compared with the value its simplest use needs."""
    result.target = f"value {need.description}"
    if item.hand is None:
        return result
    try:
        result.findings += comparison.compare_values(item.hand, need.expr,
                                                     f"the value line {need.line} needs")
    except _UnresolvedError as error:
        hand.problems.append(Problem(eq.line, eq.column, f"{eq.label}: {error.message}"))
        result.status = "input error"
        return result
    _set_status(result)
    return result


def _complete(hand: HandFile, prepared: list[list[_Item]], resolver: _HandSide,
              comparison: _Comparison, identify: dict, declared: _Declarations,
              needed: dict[str, _Needed]) -> None:
    """Model sides (exact, with declared drops) and isolated hand side of every line."""
    pairs = []
    for eq, items in zip(hand.equations, prepared, strict=True):
        for item in items:
            if item.hand is None or item.key is None or item.ideal or item.status:
                continue
            item.model_full = _model_expr(resolver.model, item.key).xreplace(identify)
            dropped = declared.dropped_for(eq)
            side = _side(resolver.model.d, dropped) if dropped else resolver.model
            item.model_declared = _model_expr(side, item.key).xreplace(identify)
            item.hand_isolated = item.hand
            if item.deps:
                resolver.isolate = side
                resolver.needed = {k: v.expr for k, v in needed.items()}
                try:
                    trail = ((resolver.definition_key(eq),) if isinstance(eq.lhs, sp.Symbol)
                             else ())
                    item.hand_isolated = resolver.resolve(eq.forms[item.form], eq.section,
                                                          trail)
                except _UnresolvedError:
                    pass
                finally:
                    resolver.isolate, resolver.needed = None, {}
            pairs += [(item.hand, item.model_declared),
                      (item.hand_isolated, item.model_declared,
                       item.hand_isolated is not item.hand)]
    comparison.prefetch(pairs)


def _line_findings(eq: HandEquation, item: _Item, comparison: _Comparison, identify: dict,
                   resolver: _HandSide, declared: _Declarations,
                   needed: dict[str, _Needed], result: EquationResult) -> list[Finding]:
    """Findings of one line: as written, with declared drops, isolated (see module doc).

    Only differences from the exact model count; the declared and isolated comparisons
    say what each one is: a declared drop (gone once the declaration is applied), a
    knock-on (gone once the definitions the line uses are correct) or the line's own.
    """
    full = comparison.compare(item.hand, item.model_full, item.hand_display, diagnose=False)
    if not full:
        return []
    dropped = item.model_declared is not item.model_full and item.model_declared != \
        item.model_full
    with_declared = (comparison.compare(item.hand, item.model_declared, item.hand_display,
                                        diagnose=False) if dropped else full)
    declared_quantities = {f.quantity for f in with_declared}
    own = {f.quantity: f for f in comparison.compare(
        item.hand_isolated, item.model_declared, item.hand_display,
        trusted=item.hand_isolated is not item.hand)}
    names = {b.name: s for b, s in zip(comparison.basis, comparison.symbols, strict=True)}
    raw = None
    findings = []
    for f in full:
        if f.quantity not in declared_quantities:
            declared.mark(eq)
            findings.append(replace(f, severity=cl.DECLARED, kind=cl.OMITTED,
                                    detail="left out by the file's declared simplification"))
            continue
        mine = own.get(f.quantity)
        if mine is None:
            shown = next(g for g in with_declared if g.quantity == f.quantity)
            findings.append(replace(shown, role=cl.KNOCK_ON))
            continue
        if eq.declarations and f.quantity in names:
            if raw is None:
                raw = comparison.differences(item.hand, item.model_declared)[0]
            info = raw.get(names[f.quantity])
            if info is not None and declared.explains_term(
                    eq, f.quantity, info["model"] - info["hand"], comparison):
                findings.append(replace(mine, severity=cl.DECLARED, kind=cl.OMITTED,
                                        detail="a term the file declares it leaves out"))
                continue
        findings.append(mine)
    return findings


def _assign_roots(results: list[EquationResult], prepared: list[list[_Item]],
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
        if item is None or not any(f.role == cl.KNOCK_ON for f in r.findings):
            continue
        sources = [by_equation[i] for i in sorted(item.deps, key=lambda i: by_equation[i]
                                                  .equation.line if i in by_equation else 0)
                   if i in by_equation]
        wrong = [s for s in sources if any(f.role == cl.ROOT and f.is_mistake
                                           for f in s.findings)]
        dropping = [s for s in sources if s.findings and s not in wrong]
        updated = []
        for f in r.findings:
            if f.role != cl.KNOCK_ON:
                updated.append(f)
                continue
            if wrong:
                updated.append(replace(f, roots=tuple(s.reference for s in wrong)))
            elif dropping:
                classes = {g.severity for s in dropping for g in s.findings}
                severity = f.severity
                if classes == {cl.DECLARED}:
                    severity = cl.DECLARED
                elif classes <= {cl.DECLARED, cl.DROPPED} and f.severity != cl.MISTAKE:
                    severity = cl.DROPPED
                updated.append(replace(f, roots=tuple(s.reference for s in dropping),
                                       severity=severity,
                                       kind=cl.OMITTED if severity in (cl.DECLARED, cl.DROPPED)
                                       else f.kind))
            else:
                updated.append(replace(f, role=cl.ROOT))
        r.findings = updated
        _set_status(r)


def check_hand_file(path, model: str | ModelDefinition = "orthodromic",
                    threshold: float = DEFAULT_THRESHOLD, latex: bool | None = None,
                    mapping_path=None, latex_backend: str = "lalr",
                    magnitudes: dict[str, str] | None = None, effects: bool = True
                    ) -> CheckReport:
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
    """
    from ins_errors.checker.parse import read_hand_file, read_mapping_file

    d = resolve_model(model)  # unknown model: clear error before reading anything
    mapping = read_mapping_file(mapping_path) if mapping_path is not None else None
    notation = default_notation(d)
    if mapping is not None:
        notation = notation.merged(mapping)
    hand = read_hand_file(path, notation, latex=latex, latex_backend=latex_backend)
    return check_hand(hand, model=d, threshold=threshold, mapping=mapping,
                      magnitudes=magnitudes, effects=effects)
