"""Both sides of a hand equation in model terms: the model side and the hand side.

:class:`ModelSide` flattens the model's structured variation
(:func:`~ins_errors.symbolic.variation.structured_variation`) into one expression per
intermediate quantity, error-state line and output, in the basis quantities (error states
and sources) and the ideal model symbols; declared simplifications drop chosen
intermediate variations. :class:`HandSide` resolves a hand equation through the hand
file's own definitions and the notation (aliases, sources, spellings) to the same terms,
and can *isolate* a line: every definition it uses replaced by the correct one.
"""

from __future__ import annotations

from functools import lru_cache

import sympy as sp

from ins_errors.checker.notation import Notation
from ins_errors.checker.parse import DOT, TILDE, HandEquation, HandFile, Problem
from ins_errors.errors import close_names
from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.symbol_order import sorted_symbols
from ins_errors.symbolic.variation import output_mechanisations, structured_variation


class UnresolvedError(Exception):
    """A symbol or definition the checker cannot resolve (becomes an input problem)."""

    def __init__(self, symbol: str | None, message: str):
        message = " ".join(message.splitlines())  # reports are one line per problem
        super().__init__(message)
        self.symbol = symbol
        self.message = message


@lru_cache(maxsize=16384)
def tilde_variations(expr: sp.Expr) -> dict[sp.Expr, sp.Expr]:
    """``tilde(X)`` -> ``X + Delta_X`` for each real-work value in ``expr`` (read only).

    Kept per expression: walking a tree for a function class is slow in SymPy (each
    node's class check goes through the function metaclass), and a hand form is asked
    for its real-work values several times per check.
    """
    return {f: f.args[0] + sp.Symbol(f"Delta_{f.args[0]}") for f in expr.atoms(TILDE)}


@lru_cache(maxsize=16384)
def _symbols_of(expr: sp.Expr) -> tuple[sp.Symbol, ...]:
    """Free symbols of a hand form in SymPy's canonical order (kept per form: each is
    resolved several times per check, and again in the next check of the same line)."""
    return tuple(sorted_symbols(expr.free_symbols))


@lru_cache(maxsize=16384)
def _substituted(expr: sp.Expr, rule: tuple[tuple[sp.Symbol, sp.Expr], ...]) -> sp.Expr:
    """``expr.xreplace(dict(rule))``: a hand form in model terms.

    A pure function of its arguments, kept for the next use in the same process: a
    form's symbols stand for large model expressions, and rebuilding the form's sums
    and products around them is most of resolving it; the same definition is resolved
    for each line that uses it, for the line's display and isolated forms, and again in
    every check of the same (or a slightly edited) hand file. A kept result is the
    object handed out before, so the rules of the forms that use it hit as well.
    """
    return expr.xreplace(dict(rule))


@lru_cache(maxsize=16384)
def _has_dot(expr: sp.Expr) -> bool:
    """Whether ``expr`` holds a time derivative ``dot(...)`` (kept per expression)."""
    return bool(expr.atoms(DOT))


# --------------------------------------------------------------------------------------
# The model side
# --------------------------------------------------------------------------------------
class ModelSide:
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
        self._varied: dict[sp.Expr, sp.Expr] = {}  # vary() of each expression asked for
        self.state_rhs: dict[str, sp.Expr] = {}
        known: dict[sp.Symbol, sp.Expr] = {}
        for line in structured_variation(d):  # (kept per definition)
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
        total = self._varied.get(expr)
        if total is None:
            total = sp.S.Zero
            for symbol in sorted_symbols(expr.free_symbols):
                delta = self.delta_of_symbol(symbol)
                if delta != 0:
                    total += sp.diff(expr, symbol) * delta
            self._varied[expr] = total
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
class HandSide:
    """Resolves hand symbols through the hand file's definitions and the notation."""

    def __init__(self, model: ModelSide, notation: Notation, hand: HandFile):
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
        self.isolate: ModelSide | None = None
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
        self._flag_repeated_state_equations(hand)

    def _flag_repeated_state_equations(self, hand: HandFile) -> None:
        """A second ``dot(X)`` of the same error state in one section is an input
        problem naming both lines, as a repeated definition is (both are still checked;
        a printed alternative form is marked ``@alt``)."""
        first: dict[tuple[int, str], HandEquation] = {}
        for eq in hand.equations:
            if eq.alternative or isinstance(eq.lhs, sp.Symbol):
                continue
            inner = eq.lhs.args[0].name
            base = self.variation_base(inner)
            state = (self.model.error_of_state[base].name
                     if base is not None and base in self.model.error_of_state else inner)
            earlier = first.setdefault((eq.section, state), eq)
            if earlier is not eq:
                hand.problems.append(Problem(
                    eq.line, eq.column,
                    f"second equation of dot({state}) in this section (first at line "
                    f"{earlier.line}); both are checked (mark a printed alternative form "
                    "with @alt)"))

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
        if tilde_variations(expr):
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
            raise UnresolvedError(name, f"alias {name} refers to itself")
        from ins_errors.checker.parse import parse_text_expression

        text = self.notation.aliases[name]
        try:
            expr, _ = parse_text_expression(text, Notation())
        except Exception as error:
            raise UnresolvedError(name, f"alias {name} = {text!r} cannot be parsed: "
                                    f"{getattr(error, 'message', error)}") from None
        replace = {}
        for symbol in expr.free_symbols:
            model = self.model.ideal(symbol.name)
            if model is not None:
                replace[symbol] = model
            elif symbol.name in self.notation.aliases:
                replace[symbol] = self.alias(symbol.name, (*trail, name))
            else:
                raise UnresolvedError(symbol.name, f"alias {name} = {text!r} uses "
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
        tildes = tilde_variations(expr)
        if tildes:
            expr = expr.xreplace(tildes)
        if _has_dot(expr):
            raise UnresolvedError(None, "a time derivative dot(...) is only allowed on the "
                                    "left-hand side")
        rule = tuple((s, self.symbol(s.name, section, trail)) for s in _symbols_of(expr))
        return _substituted(expr, rule)

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
        raise UnresolvedError(name, self.unknown_message(name))

    def display_form(self, expr: sp.Expr, section: int, trail: tuple[str, ...]
                     ) -> sp.Expr | None:
        """``expr`` with its variations resolved but its ideal symbols kept (D, R_eta)."""
        self.keep_ideal = True
        try:
            return self.resolve(expr, section, trail)
        except UnresolvedError:
            return None
        finally:
            self.keep_ideal = False

    def use_definition(self, eq: HandEquation, key: str, section: int,
                       trail: tuple[str, ...]) -> sp.Expr:
        if key in trail:
            raise UnresolvedError(key, f"definition of {key} (line {eq.line}) refers to itself "
                                   f"through {' -> '.join((*trail, key))}")
        if id(eq) in self.broken:
            raise UnresolvedError(key, f"uses {key}, whose definition (line {eq.line}) has an "
                                   "error")
        self.used_definitions.add(id(eq))
        self.trace.add(id(eq))
        form = self.defining_form(eq)
        try:
            return self.resolve(form, eq.section, (*trail, key))
        except UnresolvedError as error:
            if not trail:
                raise
            raise UnresolvedError(key, f"uses {key} (line {eq.line}), which cannot be "
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
        return _tautology(form, key)

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
        if meaning is None and base in self.model.delta_of and self.visible(
                base, section) is None:  # a real-work-only intermediate (f~ = ...)
            if self.isolate is None:
                self.from_model.setdefault(key, set()).add(self.current_line)
            return (self.isolate or self.model).delta_of[base]
        if meaning is None:
            aux = self.visible(base, section)
            if aux is None:
                raise UnresolvedError(key, self.unknown_message(key))
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
        if meaning is None:  # a real-work-only intermediate has only its variation
            return side.delta_of.get(base)
        if base in side.delta_of and base not in self.notation.aliases:
            return side.delta_of[base]
        return side.vary(meaning)

    def known_names(self) -> list[str]:
        names = set(self.notation.aliases) | set(self.notation.sources)
        names |= set(self.model.symbols) | set(self.model.outputs)
        names |= set(self.model.error_states) | set(self.model.sources)
        names |= {f"Delta_{n}" for n in (*self.model.symbols, *self.model.outputs,
                                        *self.notation.aliases, *self.model.delta_of)}
        for table in self.definitions:
            names |= set(table)
        return sorted(names)

    def unknown_message(self, name: str) -> str:
        stem, _, index = name.rpartition("_")
        if stem in self.notation.spellings:  # \nabla_N where the model has one \nabla
            return (f"unknown symbol {name!r}; did you mean {stem!r} "
                    f"({self.notation.spellings[stem]}, which has no index {index!r})?")
        close = close_names(name, self.known_names(), cutoff=0.6)
        hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
        return f"unknown symbol {name!r}{earth_rate_hint(name, self.model.d)}{hint}"


EARTH_RATE_SPELLINGS = ("Omega", "Omega_ie", "omega_ie", "Omega_e", "omega_e", "U",
                        "earth_rate")
"""How texts write the Earth's rotation rate (``\\Omega``, ``\\omega_{ie}``, ``U``):
a hand symbol spelt so that the model does not know is told the model's name for it."""


def earth_rate_hint(name: str, d: ModelDefinition) -> str:
    """``; the Earth rate of model 'm' is U (LaTeX \\Omega)`` for an unknown ``name``
    that texts use for the Earth rate, where the model has an Earth-rate parameter
    (:data:`~ins_errors.earth_constants.EARTH_RATE_NAMES`); '' otherwise."""
    from ins_errors.earth_constants import earth_parameter_names

    if name not in EARTH_RATE_SPELLINGS:
        return ""
    rate = earth_parameter_names(d.parameters).earth_rate
    if rate is None or rate == name:
        return ""
    latex = next(p.latex for p in d.parameters if p.name == rate)
    return f"; the Earth rate of model {d.name!r} is {rate} (in LaTeX {latex})"


@lru_cache(maxsize=16384)
def _tautology(form: sp.Expr, key: str) -> bool:
    """:meth:`HandSide.tautology`: a pure function, kept for the next line and check."""
    tildes = tilde_variations(form)
    plain = form.xreplace(tildes)
    name = sp.Symbol(key)
    if name not in plain.free_symbols:
        # expanding never brings in a symbol, so ``expand(plain) - key`` keeps its ``-key``
        return False
    return sp.expand(sp.expand(plain) - name) == 0


_SHARED: dict[tuple, tuple] = {}


def model_side(d: ModelDefinition, dropped: frozenset[str] = frozenset()) -> ModelSide:
    """Model side (with some intermediate variations dropped), kept per definition."""
    key = ("side", id(d), dropped)
    entry = _SHARED.get(key)
    if entry is None or entry[0] is not d:
        entry = (d, ModelSide(d, dropped))
        _SHARED[key] = entry
    return entry[1]


def model_expr(side: ModelSide, key: tuple) -> sp.Expr:
    """The model's expression for a target key (see :func:`_target`)."""
    kind, what = key
    if kind == "state":
        return side.state_rhs[what]
    if kind == "delta":
        return side.delta(what)
    if kind == "vary":
        return side.vary(what)
    return what  # "ideal"


@lru_cache(maxsize=16384)
def _identified_expr(expr: sp.Expr, rule: tuple[tuple[sp.Symbol, sp.Expr], ...]) -> sp.Expr:
    """``expr.xreplace(dict(rule))``, kept for the next use in the same process."""
    return expr.xreplace(dict(rule))


def identified(expr: sp.Expr, identify: dict[sp.Symbol, sp.Expr]) -> sp.Expr:
    """A model expression with the file's identification applied (``Delta_a`` for both
    accelerometer biases, out-of-scope sources zero): ``expr.xreplace(identify)``.

    Each line's model side is asked for this several times per check (prefetch, the
    exact and declared model sides, the symbolic-identity note, the helpers' and the
    effects' rows), and the deep model trees cost a full walk each time; the result
    is a pure function of its arguments, so it is kept (read only).
    """
    return _identified_expr(expr, tuple(identify.items()))
