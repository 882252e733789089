"""Checks a model definition must pass before it is varied or turned into code.

A mistake in a model file (a symbol that is used but never declared, a right-hand side
with the wrong number of rows, a state without an equation, a real work that does not
reduce to the ideal work when every error is off) would otherwise surface as a SymPy
traceback deep in the variation, or worse, as generated code that runs and is wrong.
:func:`check_definition` finds these and raises one
:class:`~ins_errors.errors.ModelDefinitionError` naming the model, the quantity and the
step ("checking the definition"). :func:`check_units` and :func:`check_dimensions` (units
that parse and are coherent SI, display units that convert, equations in the right units)
need the units library and run for model files and entry points; a test runs them on
every built-in model.
"""

from __future__ import annotations

import difflib
import math
import random
import re
from collections.abc import Callable, Iterable, Sequence

import sympy as sp
from sympy.core.function import AppliedUndef

from ins_errors.errors import ModelDefinitionError
from ins_errors.modeling import (
    ErrorSource,
    Mechanisation,
    ModelDefinition,
    Parameter,
    Variable,
)

STEP = "checking the definition"
SOURCE_KINDS = ("constant", "initial")
"""The kinds of error source (:class:`~ins_errors.modeling.ErrorSource`)."""


def _fail(label: str, quantity: str, problem: str) -> ModelDefinitionError:
    return ModelDefinitionError(f"{label}: {quantity}: {problem} (step: {STEP})")


def _names(symbols: Iterable[sp.Basic]) -> str:
    return ", ".join(sorted(str(s) for s in symbols))


def _function_names(applied: Iterable[sp.Basic]) -> str:
    return ", ".join(sorted({str(f.func) for f in applied}))


def _undefined_functions(label: str, quantity: str, expression: sp.Basic) -> None:
    undefined = expression.atoms(AppliedUndef)
    if undefined:
        raise _fail(label, quantity,
                    f"uses undefined function(s) {_function_names(undefined)}: write the "
                    "formula with SymPy functions (sp.sin, sp.sqrt, ...)")


NON_FINITE = {sp.zoo: "zoo (complex infinity)", sp.nan: "nan (not a number)",
              sp.oo: "oo (infinity)", -sp.oo: "-oo (minus infinity)"}
"""SymPy's non-finite numbers and how messages name them: ``V/R + sp.zoo``, ``log(0)``
(zoo), ``0/0`` or ``oo - oo`` (nan), ``float("inf")`` (oo) in a formula would become
``math.nan`` or ``math.inf`` in the generated code."""


def non_finite(*exprs: sp.Basic) -> list[str]:
    """The names (:data:`NON_FINITE`) of the non-finite numbers in ``exprs``, in the
    order of that table; empty if there is none.

    Each distinct subtree is visited once (closed equations repeat their subtrees many
    times).
    """
    found: set[sp.Basic] = set()
    seen: set[sp.Basic] = set()
    stack = [e for e in exprs if isinstance(e, sp.Basic)]
    while stack:
        e = stack.pop()
        if e in seen:
            continue
        seen.add(e)
        if e in NON_FINITE:
            found.add(e)
        stack.extend(e.args)
    return [text for number, text in NON_FINITE.items() if number in found]


def _finite(label: str, quantity: str, expression: sp.Basic) -> None:
    """Refuse a formula that holds a non-finite number (:func:`non_finite`)."""
    bad = non_finite(expression)
    if bad:
        shown = sp.sstr(expression)
        shown = shown if len(shown) <= 80 else shown[:77] + "..."
        raise _fail(label, quantity, f"is not finite: it contains {', '.join(bad)} "
                                     f"({shown}); a division by zero, log(0) or an "
                                     "infinite number in the formula?")


_SEQUENCES = (
    ("states", Variable), ("error_states", Variable), ("inputs", Variable),
    ("parameters", Parameter), ("sources", ErrorSource), ("outputs", Variable),
    ("initial_conditions", Variable))
"""The fields of a :class:`ModelDefinition` that are sequences of names, with the class
of their items."""


def _type_name(value: object) -> str:
    text = repr(value)
    text = text if len(text) <= 40 else text[:37] + "..."
    return f"{type(value).__name__} {text}"


def _check_types(label: str, d: ModelDefinition) -> None:
    """Refuse arguments of the wrong type (``states=5``, a string for a list, a symbol
    where a Variable belongs) in one line naming the field, before any check uses them."""
    for name in ("name", "title", "source", "notes"):
        if not isinstance(getattr(d, name), str):
            raise _fail(label, name, f"must be a str, got {_type_name(getattr(d, name))}")
    for group, kind in _SEQUENCES:
        value = getattr(d, group)
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            raise _fail(label, group, f"must be a list or tuple of {kind.__name__}, got "
                                      f"{_type_name(value)}")
        for k, item in enumerate(value):
            if not isinstance(item, kind):
                hint = (" (made with error_source(...))" if kind is ErrorSource else
                        " (with its default value)" if kind is Parameter else "")
                article = "an" if kind.__name__[0] in "AEIOU" else "a"
                raise _fail(label, f"{group}[{k}]", f"must be {article} {kind.__name__}{hint}, "
                                                    f"got {_type_name(item)}")
            for field_name in ("name", "unit", "description", "latex"):
                if not isinstance(getattr(item, field_name), str):
                    raise _fail(label, f"{group}[{k}]", f"{field_name} must be a str, got "
                                f"{_type_name(getattr(item, field_name))}")
    real = d.real_states
    if isinstance(real, (str, bytes)) or not isinstance(real, Sequence):
        raise _fail(label, "real_states", "must be a list or tuple of SymPy symbols "
                                          f"(computed_symbols(...) and the extra error states' "
                                          f"symbols), got {_type_name(real)}")
    for k, item in enumerate(real):
        if not isinstance(item, sp.Symbol):
            raise _fail(label, f"real_states[{k}]", f"must be a SymPy symbol, got "
                                                    f"{_type_name(item)}")
    for name in ("ideal", "real"):
        if not isinstance(getattr(d, name), Mechanisation):
            raise _fail(label, name, f"must be a Mechanisation, got "
                                     f"{_type_name(getattr(d, name))}")
    if not callable(d.output_map):
        raise _fail(label, "output_map", "must be a function output_map(mechanisation, "
                                         f"state, inputs), got {_type_name(d.output_map)}")
    for name in ("groups", "domain", "initial_domain"):
        value = getattr(d, name)
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            raise _fail(label, name, f"must be a list or tuple of pairs, got "
                                     f"{_type_name(value)}")
    for k, item in enumerate(d.groups):
        if not (isinstance(item, Sequence) and len(item) == 2 and isinstance(item[0], str)
                and isinstance(item[1], Sequence) and not isinstance(item[1], str)
                and all(isinstance(m, str) for m in item[1])):
            raise _fail(label, f"groups[{k}]", "must be a pair (title, list of error-state "
                                               f"names), got {_type_name(item)}")


def _check_names(label: str, d: ModelDefinition) -> None:
    groups: dict[str, Sequence[Variable]] = {
        "states": d.states, "error_states": d.error_states, "inputs": d.inputs,
        "parameters": d.parameters, "sources": d.sources, "outputs": d.outputs,
        "initial_conditions": d.initial_conditions,
    }
    for group, variables in groups.items():
        seen: set[str] = set()
        for v in variables:
            if not isinstance(v, Variable):
                raise _fail(label, group, f"{v!r:.60} is not a Variable")
            if not v.name.isidentifier():
                raise _fail(label, f"{group} {v.name!r}", "name is not a Python identifier")
            if v.name in seen:
                raise _fail(label, f"{group} {v.name!r}", "name used twice")
            seen.add(v.name)
    if not d.states:
        raise _fail(label, "states", "the model has no state")
    if not d.sources:
        raise _fail(label, "sources", "the model has no error source: an error model needs "
                                      "at least one (kind 'constant' or 'initial')")
    for source in d.sources:
        if source.kind not in SOURCE_KINDS:
            close = difflib.get_close_matches(str(source.kind).lower(), SOURCE_KINDS, n=1,
                                              cutoff=0.3)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise _fail(label, f"error source {source.name!r}",
                        f"kind {source.kind!r} is not one of {', '.join(map(repr, SOURCE_KINDS))}"
                        f" ('constant' enters the right-hand side, 'initial' only the "
                        f"initial state){hint}")
    for parameter in d.parameters:
        try:
            value = float(parameter.default)
        except (TypeError, ValueError):
            raise _fail(label, f"parameter {parameter.name!r}",
                        f"default {parameter.default!r:.40} is not a number") from None
        if not math.isfinite(value):
            raise _fail(label, f"parameter {parameter.name!r}",
                        f"default {value} is not a finite number")
    _check_shared_names(label, groups)


RENAMED = {"initial_conditions": "0", "inputs": "_in", "parameters": "_par",
           "sources": "_err", "error_states": "_err_state", "states": "_state"}
"""Groups whose names become SymPy symbols (not the outputs, which are expressions: an
output may share its name with a state or an initial condition), in the order a clash
suggests renaming them, with the suffix suggested (``v_E`` -> ``v_E0``)."""


FILLED_BY_NAME = frozenset({"latitude", "longitude", "height", "h", "roll", "pitch",
                            "heading"})
"""Initial conditions that flights and the static base fill by these names alone (the
velocities are also read as ``v_N0``, ``v_E0``, ...: see
:data:`ins_errors.numeric.model_flight.CONDITIONS`): a state that clashes with one is
the one to rename (an Euler-angle model's ``roll`` state beside the initial ``roll``)."""


def _check_shared_names(label: str, groups: dict[str, Sequence[Variable]]) -> None:
    """Refuse a name used by two groups of :data:`RENAMED`: both would be one symbol (a
    state ``v_E`` and an initial condition ``v_E`` make the current velocity print as
    ``v_{E0}`` and the equations mix the two)."""
    owner: dict[str, str] = {}
    taken = {v.name for group in RENAMED for v in groups[group]}
    for group in reversed(RENAMED):
        for v in groups[group]:
            if v.name not in owner:
                owner[v.name] = group
                continue
            other = owner[v.name]
            renamed = group if list(RENAMED).index(group) < list(RENAMED).index(other) \
                else other
            why = ""
            if renamed == "initial_conditions" and v.name in FILLED_BY_NAME \
                    and "states" in (group, other):
                renamed = "states"
                why = (f" (flights and the static base set the initial condition "
                       f"{v.name!r} by that name)")
            suggestion = v.name + RENAMED[renamed]
            while suggestion in taken:
                suggestion += "_"
            raise _fail(label, f"{_one(other)} {v.name!r} and {_one(group)} {v.name!r}",
                        "one name for two quantities makes them one SymPy symbol; rename "
                        f"one of them, e.g. the {_one(renamed)} to {suggestion!r}{why}")


def _one(group: str) -> str:
    """One member of a group, in words: ``initial_conditions`` -> ``initial condition``."""
    return "error source" if group == "sources" else group.replace("_", " ")[:-1]


def _shape_text(entry: object) -> str:
    """What one entry of a list given to ``sp.Matrix`` is: ``a 3 x 3 matrix``, ``a list
    of 3``, ``a scalar``."""
    if isinstance(entry, sp.MatrixBase):
        return f"a {entry.rows} x {entry.cols} matrix"
    if isinstance(entry, (list, tuple)):
        return f"a {type(entry).__name__} of {len(entry)}"
    return "a scalar"


def mixed_entries(value: object) -> str | None:
    """Say what is wrong with a list that ``sp.Matrix`` cannot make a matrix of because
    it mixes a matrix (or a nested list) with scalars (``[C_dot, *v_dot, *v]`` with a
    3 x 3 ``C_dot``, for which SymPy says only "mismatched dimensions"); None when
    ``value`` is not such a list.

    Parameters
    ----------
    value : object
        What was given to ``sp.Matrix`` (or as a right-hand side, output or initial
        state).

    Returns
    -------
    str or None
        ``"a list of 7 entries: entry 1 is a 3 x 3 matrix, the others scalars; ..."``
        with how to write the column instead.
    """
    if not isinstance(value, (list, tuple)) or not value:
        return None
    kinds = [_shape_text(entry) for entry in value]
    if len(set(kinds)) < 2:
        return None
    common = max(set(kinds), key=kinds.count)
    odd = [f"entry {k + 1} is {kind}" for k, kind in enumerate(kinds) if kind != common]
    shown = ", ".join(odd[:3]) + (f" (and {len(odd) - 3} more)" if len(odd) > 3 else "")
    others = "scalars" if common == "a scalar" else f"{common.removeprefix('a ')} each"
    return (f"a {type(value).__name__} of {len(value)} entries: {shown}, the others "
            f"{others}; a column has one expression per row: unpack a matrix into the "
            "list with * ([*C, ...] gives its entries row by row)")


def _column(label: str, quantity: str, value: object, rows: int, row_names: list[str],
            what: str) -> sp.Matrix:
    """``value`` as a column matrix of ``rows`` SymPy expressions, or a one-line error."""
    try:
        matrix = sp.Matrix(value)
    except (TypeError, ValueError, sp.SympifyError) as error:
        mixed = mixed_entries(value)
        if mixed:
            raise _fail(label, quantity, f"must be a column ({rows} x 1, one expression per "
                                         f"{what[:-1]}), got {mixed}") from None
        raise _fail(label, quantity, f"not a column of SymPy expressions ({error})") from None
    if rows == 0 and matrix.rows == 0:
        return sp.zeros(0, 1)  # sp.Matrix([]) is 0 x 0: the empty column of no outputs
    if matrix.cols != 1:
        raise _fail(label, quantity, f"must be a column ({rows} x 1), got shape "
                                     f"{matrix.rows} x {matrix.cols}")
    if matrix.rows < rows:
        missing = ", ".join(repr(n) for n in row_names[matrix.rows:])
        raise _fail(label, quantity, f"has {matrix.rows} rows for {rows} {what}: no "
                                     f"equation for {missing}")
    if matrix.rows > rows:
        raise _fail(label, quantity, f"has {matrix.rows} rows but the model has only "
                                     f"{rows} {what}")
    return matrix


def _check_symbols(label: str, quantity: str, matrix: sp.Matrix, row_names: list[str],
                   allowed: set[sp.Symbol], hint: str | Callable[[set[sp.Symbol]], str]
                   ) -> None:
    """Refuse a row that is not an expression, uses an undefined function, a non-finite
    number or a symbol outside ``allowed``; ``hint`` says what the symbol may be (or,
    given the undefined symbols, the whole clause after the names)."""
    for i in range(matrix.rows):
        entry = matrix[i, 0]
        if not isinstance(entry, sp.Expr):
            raise _fail(label, f"{quantity} for {row_names[i]!r}",
                        f"{entry!r:.60} is not a SymPy expression")
        _undefined_functions(label, f"{quantity} for {row_names[i]!r}", entry)
        _finite(label, f"{quantity} for {row_names[i]!r}", entry)
        unknown = {s for s in entry.free_symbols if s not in allowed}
        if unknown:
            plain = {s for s in unknown if isinstance(s, sp.Symbol)}
            near = {a.name for a in allowed for s in plain if a.name == s.name}
            why = (f" ({_names(near)} declared, but with other assumptions: make symbols "
                   "with Variable.symbol)") if near else \
                hint(plain) if callable(hint) else f"; it may use {hint}"
            raise _fail(label, f"{quantity} for {row_names[i]!r}",
                        f"uses undefined symbol(s) {_names(unknown)}{why}")


def _intermediates(mech: Mechanisation) -> set[sp.Symbol]:
    return {definition.symbol for definition in mech.definitions}


def _ideal_hint(d: ModelDefinition, unknown: set[sp.Symbol]) -> str:
    """What the undefined symbols of an ideal-work equation are, and what the ideal work
    may use instead (the clause after their names)."""
    n = len(d.states)
    what = {**{s: f"a computed state: the ideal work is written in the true state "
                  f"({v.name})" for s, v in zip(d.real_states[:n], d.states, strict=False)},
            **{s: "an error state: the ideal work has no errors"
               for s in d.real_states[n:]},
            **{s: "an error source: the ideal work has no errors (perfect sensors)"
               for s in d.w},
            **{s: "an intermediate of the real mechanisation: the ideal work uses the "
                  "ideal mechanisation's" for s in _intermediates(d.real)}}
    known = [f"{s} is {what[s]}" for s in sorted(unknown, key=str) if s in what]
    if known:
        return "; " + "; ".join(known)
    return ("; the ideal work may use the states, inputs and parameters and its own "
            "intermediates (let() on the ideal mechanisation)")


_NOT_SMOOTH = (sp.Abs, sp.sign, sp.Heaviside, sp.Max, sp.Min, sp.floor, sp.ceiling,
               sp.frac, sp.Mod, sp.DiracDelta)
"""Functions with a kink or a jump: their second derivative is a DiracDelta, which no
code printer prints, or SymPy has no derivative of them at all."""
_JUMPS = (sp.sign, sp.Heaviside, sp.floor, sp.ceiling, sp.frac, sp.Mod, sp.DiracDelta)
"""Functions of :data:`_NOT_SMOOTH` without a first derivative (a DiracDelta, or none in
SymPy)."""


def intermediate_dependence(*mechanisations: Mechanisation
                            ) -> dict[sp.Symbol, frozenset[sp.Symbol]]:
    """For each intermediate of ``mechanisations`` (in order), the declared symbols it
    depends on through the intermediates before it."""
    depends: dict[sp.Symbol, frozenset[sp.Symbol]] = {}
    for mech in mechanisations:
        for definition in mech.definitions:
            depends[definition.symbol] = frozenset().union(
                *(depends.get(s, {s}) for s in definition.expression.free_symbols))
    return depends


def declared_uses(expression: sp.Basic, depends: dict[sp.Symbol, frozenset[sp.Symbol]]
          ) -> set[sp.Symbol]:
    """The declared symbols ``expression`` depends on, through intermediates."""
    return set().union(*(depends.get(s, {s}) for s in expression.free_symbols))


def _kink(f: sp.Basic) -> str:
    """What is not smooth about a function of :data:`_NOT_SMOOTH`."""
    if isinstance(f, (sp.Max, sp.Min)):
        return "has no derivative where its arguments are equal"
    if isinstance(f, (sp.sign, sp.Heaviside)):
        return "jumps where its argument is zero"
    if isinstance(f, sp.DiracDelta):
        return "is not a function"
    if isinstance(f, _JUMPS):
        return "jumps (SymPy has no derivative of it)"
    return "has no derivative where its argument is zero"


class _Expansion:
    """What an equation's error terms are the derivatives of.

    Parameters
    ----------
    variables : dict
        The symbols they are taken by, each with what it is (``"error source"``).
    point : dict
        Where (symbol -> value; the computed state on the true one, errors zero).
    depends : dict
        The intermediates' dependence (:func:`intermediate_dependence`).
    words : str
        Why a kink there is refused.
    advice : str
        What to write instead, ``{name}`` the refused function's name.
    functions : tuple of type
        The functions refused (:data:`_NOT_SMOOTH` or :data:`_JUMPS`).
    expand : callable
        Substitutes the intermediates into an expression.
    """

    def __init__(self, variables: dict[sp.Symbol, str], point: dict[sp.Symbol, sp.Expr],
                 depends: dict[sp.Symbol, frozenset[sp.Symbol]], words: str, advice: str,
                 functions: tuple[type, ...] = _NOT_SMOOTH,
                 expand: Callable[[sp.Basic], sp.Basic] = lambda e: e):
        self.variables, self.point, self.depends = variables, point, depends
        self.words, self.advice = words, advice
        self.functions, self.expand = functions, expand

    def of(self, expression: sp.Basic) -> str:
        """The variables ``expression`` depends on, in words (empty if none)."""
        used = declared_uses(expression, self.depends) & self.variables.keys()
        return ", ".join(f"{self.variables[s]} {s}" for s in sorted(used, key=str))


def _shown(expression: sp.Basic) -> str:
    text = sp.sstr(expression)
    return text if len(text) <= 60 else text[:57] + "..."


def _check_smooth(label: str, quantity: str, expression: sp.Basic,
                  expansion: _Expansion) -> None:
    """Refuse a function with a kink or a jump (:data:`_NOT_SMOOTH`) of the variables an
    error model differentiates by, and a ``Piecewise`` whose condition changes right at
    the point it differentiates at (``b > 0`` for an error source ``b``)."""
    for f in sorted(expression.atoms(*expansion.functions), key=sp.default_sort_key):
        of = expansion.of(f)
        if of:
            name = f.func.__name__
            sqrt = " (sqrt(x**2) is Abs(x))" if isinstance(f, sp.Abs) else ""
            raise _fail(label, quantity,
                        f"uses {_shown(f)}, of the {of}{sqrt}: {name} {_kink(f)}, and "
                        f"{expansion.words}; {expansion.advice.format(name=name)}")
    for piecewise in sorted(expression.atoms(sp.Piecewise), key=sp.default_sort_key):
        for pair in piecewise.args:
            for condition in pair.cond.atoms(sp.core.relational.Relational):
                of = expansion.of(condition)
                edge = condition.lhs - condition.rhs
                if of and expansion.expand(edge).xreplace(expansion.point) == 0:
                    raise _fail(label, quantity,
                                f"uses a Piecewise whose condition {_shown(condition)}, of "
                                f"the {of}, changes at zero error, and {expansion.words}; "
                                f"{expansion.advice.format(name='Piecewise')}")


_TAYLOR = ("the error model is a Taylor expansion in the computed state and the error "
           "sources at zero error (a kink has no second-order term)")


def _check_real_work(label: str, d: ModelDefinition, real: sp.Matrix,
                     small: sp.Matrix | None) -> None:
    """Refuse a real work that uses no computed state, and a kink or a jump in the
    computed state or the error sources (:func:`_check_smooth`)."""
    n = len(d.states)
    depends = intermediate_dependence(d.ideal, d.real)
    computed = list(d.real_states[:n])
    names = [v.name for v in d.error_states]
    used = set().union(*(declared_uses(row, depends) for row in real))
    true = [s for s in d.x if s in used]
    if true and not used & set(computed):  # an integrator of inputs uses neither
        def listed(symbols: list[sp.Symbol]) -> str:
            return ", ".join(map(str, symbols[:3])) + (", ..." if len(symbols) > 3 else "")

        raise _fail(label, "real-work equations (real_rhs)",
                    f"use the true state ({listed(true)}) but none of the computed states "
                    f"({listed(computed)}): the real work must be written in the computed "
                    "state x~, the INS's own variables (computed_symbols(STATES)); the true "
                    "state enters only through the sensor inputs (written in the true "
                    "state, the errors have no feedback: F is zero in their columns)")
    expansion = _Expansion(
        {**{s: "computed state" for s in computed},
         **{s: "error state" for s in d.real_states[n:]},
         **{s: "error source" for s in d.w}},
        {**d.at_ideal(), **d.no_errors()}, depends, _TAYLOR,
        "write it smooth there ({name} of the true state, inputs or parameters is fine)",
        expand=lambda e: d.ideal.expand(d.real.expand(e)))
    for definition in d.real.definitions:
        _check_smooth(label, f"intermediate {definition.symbol} of the real mechanisation",
                      definition.expression, expansion)
    for rows, quantity in ((real, "real-work equation (real_rhs)"),
                           (small, "small-angle real-work equation (small_angle_rhs)")):
        for row, name in zip(rows if rows is not None else [], names, strict=False):
            _check_smooth(label, f"{quantity} for {name!r}", row, expansion)


def _check_reduces_to_ideal(label: str, d: ModelDefinition, ideal: sp.Matrix,
                            real: sp.Matrix) -> None:
    """With every error off and the computed state on the true one, the real work must
    give the ideal derivatives and zero for the extra states.

    The identity holds for every value of every symbol, so it is checked at random
    points: three with the parameters at their defaults and the other symbols drawn in
    0.1-0.6, and three with the parameters drawn too. The second kind is needed where
    the defaults make some terms huge beside others (a point-mass gravity mu/|r|**2 with
    the Earth's mu at |r| ~ 0.5 m is ~1e15 m/s**2, so a missing centrifugal or Coriolis
    term of the real work is below the tolerance there). A point where a formula leaves
    its domain gives no verdict."""
    n = len(d.states)
    at_ideal = {**d.at_ideal(), **d.no_errors()}
    expected = ideal.col_join(sp.zeros(len(d.real_states) - n, 1))
    residual = real.xreplace(at_ideal) - expected
    symbols = sorted(residual.free_symbols | expected.free_symbols, key=str)
    defaults = {v.symbol: float(v.default) for v in d.parameters}
    names = [v.name for v in d.error_states]
    try:
        evaluate = sp.lambdify(symbols, [list(residual), list(expected)], modules="math")
    except Exception:  # lambdify cannot print some expression: skip this check
        return
    rng = random.Random(0)
    points = [[defaults.get(s, rng.uniform(0.1, 0.6)) for s in symbols] for _ in range(3)]
    points += [[rng.uniform(0.1, 0.6) for _ in symbols] for _ in range(3)]
    for point in points:
        try:
            values, sizes = evaluate(*point)
        except Exception:  # outside some formula's domain, or not numeric: no verdict
            continue
        for i, (value, size) in enumerate(zip(values, sizes, strict=True)):
            value, size = abs(complex(value)), abs(complex(size))
            if math.isfinite(value) and value > 1e-9 * max(1.0, size):
                raise _fail(label, f"real-work equation for {names[i]!r}",
                            "does not reduce to the ideal work when the computed state is "
                            "the true one and every error source is zero (residual "
                            f"{value:.3g}): a term that is not multiplied by an error "
                            "source or an error state")


def check_definition(d: ModelDefinition, label: str | None = None,
                     reduction: bool = True) -> None:
    """Raise a one-line :class:`~ins_errors.errors.ModelDefinitionError` if ``d`` is
    inconsistent.

    Checks, in order: the type of every field (lists of :class:`Variable`, symbols,
    mechanisations, a callable output map); names (identifiers, unique, and no name
    shared by two of the states, error states, inputs, parameters, error sources and
    initial conditions, which would be one SymPy symbol; outputs may share names); the
    kind of each error source (:data:`SOURCE_KINDS`); finite parameter defaults; shapes
    of every right-hand side, output and initial state (one row per state, no missing
    equation); that every symbol used is a declared state, input, parameter, error
    source, initial condition or recorded intermediate, every function a SymPy one and
    every number finite (no ``zoo``, ``nan`` or ``oo``; in the equations, intermediates
    and domain conditions); that the real work uses the computed state if it uses the
    true one (a real work written in ``x`` instead of ``x~`` has no error feedback);
    that no function with a kink or a jump (:data:`_NOT_SMOOTH`, or a ``Piecewise``
    whose condition changes at zero error) takes the computed state, an error state or
    an error source in the real work, an error source in the initial real state, or a
    state in an output without a first derivative (the error model is their Taylor
    expansion); that the document groups name error states; and that the real work
    reduces to the ideal work when the computed state is the true one and every error
    is off.

    Parameters
    ----------
    d : ModelDefinition
        The definition to check.
    label : str, optional
        How messages name the model (default ``model '<name>'``).
    reduction : bool
        Also check that the real work reduces to the ideal work (False: the caller does
        it later with :func:`check_reduces_to_ideal`, e.g. after
        :func:`check_dimensions`, whose verdict on a wrong unit names the cause where a
        residual would not).
    """
    label = label or f"model {d.name!r}"
    _check_types(label, d)
    _check_names(label, d)
    n, ne = len(d.states), len(d.error_states)
    state_names = [v.name for v in d.states]
    error_names = [v.name for v in d.error_states]
    if len(d.real_states) != ne:
        raise _fail(label, "real_states", f"{len(d.real_states)} symbols for {ne} error "
                                          "states (one real-work state per error state)")
    if list(d.real_states[n:]) != [v.symbol for v in d.error_states[n:]]:
        raise _fail(label, "real_states", "after the computed states they must be the "
                                          "symbols of the extra error states, same order")
    if len(set(d.real_states)) != ne:
        raise _fail(label, "real_states", "a symbol appears twice")
    x, u, p, w, c = (set(v) for v in (d.x, d.u, d.p, d.w, d.c))
    ideal_defs, real_defs = _intermediates(d.ideal), _intermediates(d.real)
    ideal = _column(label, "ideal_rhs", d.ideal_rhs, n, state_names, "states")
    real = _column(label, "real_rhs", d.real_rhs, ne, error_names, "error states")
    _check_symbols(label, "ideal-work equation (ideal_rhs)", ideal, state_names,
                   x | u | p | ideal_defs, lambda unknown: _ideal_hint(d, unknown))
    _check_symbols(label, "real-work equation (real_rhs)", real, error_names,
                   set(d.real_states) | x | u | w | p | ideal_defs | real_defs,
                   "a symbol made with sp.Symbol instead of a declared Variable")
    small = None
    if d.small_angle_rhs is not None:
        small = _column(label, "small_angle_rhs", d.small_angle_rhs, ne, error_names,
                        "error states")
        _check_symbols(label, "small-angle real-work equation (small_angle_rhs)", small,
                       error_names, set(d.real_states) | x | u | w | p | ideal_defs | real_defs,
                       "a symbol made with sp.Symbol instead of a declared Variable")
    for mech, allowed, what in ((d.ideal, x | u | p, "ideal"),
                                (d.real, set(d.real_states) | x | u | w | p | ideal_defs,
                                 "real")):
        defined: set[sp.Symbol] = set()
        for definition in mech.definitions:
            _undefined_functions(label, f"intermediate {definition.symbol} of the {what} "
                                        "mechanisation", definition.expression)
            _finite(label, f"intermediate {definition.symbol} of the {what} mechanisation",
                    definition.expression)
            extra = definition.expression.free_symbols - allowed - defined
            if extra:
                raise _fail(label, f"intermediate {definition.symbol} of the {what} "
                                   "mechanisation",
                            f"uses undefined symbol(s) {_names(extra)} (or one defined later)")
            defined.add(definition.symbol)
    try:
        scratch = Mechanisation()
        outputs_raw = d.output_map(scratch, d.x, d.u)
    except (Exception, SystemExit) as error:  # a researcher's function: any failure
        raise _fail(label, "output_map", f"raised {type(error).__name__}: {error}") from None
    out_names = [v.name for v in d.outputs]
    outputs = _column(label, "output_map", outputs_raw, len(d.outputs), out_names, "outputs")
    _check_symbols(label, "output", scratch.expand(outputs), out_names, x | u | p,
                   "a computed-state symbol instead of the state passed to output_map")
    by_state = _Expansion({s: "state" for s in x}, {}, {}, "the output matrix H is the "
                          "derivative of the outputs by the state",
                          "write the output without it (wrap or round it after the run)",
                          _JUMPS)
    for row, name in zip(scratch.expand(outputs), out_names, strict=True):
        _check_smooth(label, f"output {name!r}", row, by_state)
    init = _column(label, "initial_state", d.initial_state, n, state_names, "states")
    _check_symbols(label, "initial_state", init, state_names, c | u | p,
                   "a state instead of an initial condition")
    init_real = _column(label, "initial_real_state", d.initial_real_state, ne, error_names,
                        "error states")
    _check_symbols(label, "initial_real_state", init_real, error_names, c | u | w | p,
                   "a state instead of an initial condition")
    by_source = _Expansion({s: "error source" for s in w}, d.no_errors(), {},
                           "the initial errors are a Taylor expansion in the error "
                           "sources at zero (E is the derivative there)",
                           "write it smooth there ({name} of the initial conditions, "
                           "inputs or parameters is fine)")
    for row, name in zip(init_real, error_names, strict=True):
        _check_smooth(label, f"initial_real_state for {name!r}", row, by_source)
    for conditions, allowed, what in ((d.domain, x | u | p, "domain"),
                                      (d.initial_domain, c | u | p, "initial_domain")):
        for k, item in enumerate(conditions):
            if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[1], str)):
                raise _fail(label, f"{what}[{k}]", "must be a pair (expression, message)")
            _undefined_functions(label, f"{what} condition {item[1]!r}", sp.sympify(item[0]))
            _finite(label, f"{what} condition {item[1]!r}", sp.sympify(item[0]))
            extra = sp.sympify(item[0]).free_symbols - allowed
            if extra:
                raise _fail(label, f"{what} condition {item[1]!r}",
                            f"uses undefined symbol(s) {_names(extra)}")
    _check_real_work(label, d, real, small)
    for title, members in d.groups:
        unknown_members = [m for m in members if m not in error_names]
        if unknown_members:
            raise _fail(label, f"group {title!r}",
                        f"names {', '.join(map(repr, unknown_members))}, not error states")
    if reduction:
        check_reduces_to_ideal(d, label)


def check_reduces_to_ideal(d: ModelDefinition, label: str | None = None) -> None:
    """Raise one line if the real work of ``d`` (already through
    :func:`check_definition`) does not reduce to its ideal work when the computed state is
    the true one and every error is off.

    Parameters
    ----------
    d : ModelDefinition
        The definition to check.
    label : str, optional
        How messages name the model (default ``model '<name>'``).
    """
    n, ne = len(d.states), len(d.error_states)
    ideal = sp.Matrix(d.ideal_rhs) if n else sp.zeros(0, 1)
    real = sp.Matrix(d.real_rhs) if ne else sp.zeros(0, 1)
    _check_reduces_to_ideal(label or f"model {d.name!r}", d, d.ideal.expand(ideal),
                            d.expand(real))


def check_units(d: ModelDefinition, label: str | None = None) -> None:
    """Raise one line if a unit of ``d`` does not parse or is not coherent SI (``deg/h``,
    ``km``, ``km**3/s**2``: every value is taken as SI, so an Earth rate declared as
    15.041 deg/h would be 15 rad/s), if a parameter's ``example`` is not a finite value in
    its unit (with the unit written), or if an error source's display unit does not
    convert to its SI unit (``"deg/h"`` for an accelerometer bias).

    Kept apart from :func:`check_definition` because it needs the units library (about
    1 s CPU to import), which ``make derive`` of the built-in models does not; model
    files and entry points get it when they are built
    (:func:`~ins_errors.model_files.build_definition`).

    Parameters
    ----------
    d : ModelDefinition
        The definition to check.
    label : str, optional
        How messages name the model (default ``model '<name>'``).
    """
    from ins_errors.units import parse_quantity

    label = label or f"model {d.name!r}"
    groups: dict[str, Sequence[Variable]] = {
        "state": d.states, "error state": d.error_states, "input": d.inputs,
        "parameter": d.parameters, "error source": d.sources, "output": d.outputs,
        "initial condition": d.initial_conditions,
    }
    for group, variables in groups.items():
        for v in variables:
            if v.unit == "1":
                continue
            try:
                parse_quantity(f"1 {v.unit}", v.unit, v.name)
            except Exception:  # the units library raises several types
                raise _fail(label, f"{group} {v.name!r}",
                            f"unit {v.unit!r} is not a unit the units library reads (SI, "
                            "e.g. 'rad', 'm/s', 'm/s**2', 'rad/s', '1')") from None
            scale, si = coherent_si(v.unit)
            if abs(scale - 1.0) > 1e-12:
                raise _fail(label, f"{group} {v.name!r}",
                            f"unit {v.unit!r} is not coherent SI (1 {v.unit} = {scale:.4g} "
                            f"{si}) and every value of a model is taken as SI: declare "
                            f"{si!r}{_keep_unit(v, scale, si)}")
    for parameter in d.parameters:
        if parameter.example_gives and not parameter.example:
            raise _fail(label, f"parameter {parameter.name!r}",
                        f"example_gives {parameter.example_gives!r} without an example value")
        if not parameter.example:
            continue
        try:
            value = parse_quantity(parameter.example, parameter.unit, parameter.name,
                                   numbers_are_si=False)
        except Exception:  # unreadable, without its unit, or another dimension
            value = math.nan
        if not math.isfinite(value):
            wanted = ("a plain number (unit '1')" if parameter.unit == "1"
                      else f"a value in {parameter.unit!r} with its unit")
            raise _fail(label, f"parameter {parameter.name!r}",
                        f"example {parameter.example!r} is not {wanted}, as typed after -p "
                        f"(e.g. {typed_example(parameter.example, parameter.unit)!r})")
    for source in d.sources:
        shown = source.display_unit
        if not shown or shown == source.unit:
            continue
        try:
            parse_quantity(f"1 {shown}", source.unit, source.name)
        except Exception:  # unreadable, or another dimension
            raise _fail(label, f"error source {source.name!r}",
                        f"display unit {shown!r} does not convert to its SI unit "
                        f"{source.unit!r}") from None


def coherent_si(unit: str) -> tuple[float, str]:
    """The scale of ``unit`` to coherent SI and that SI unit as a model declares it:
    ``(4.848e-06, "rad/s")`` for ``"deg/h"``, ``(1e9, "m**3/s**2")`` for
    ``"km**3/s**2"``, ``(1.0, "m/s")`` for ``"m/s"``, ``(0.01, "1")`` for ``"%"``.

    Parameters
    ----------
    unit : str
        A unit the units library reads (``"1"``: none).

    Returns
    -------
    scale : float
        The value in SI of 1 ``unit``: 1 for a coherent SI unit (radians count as SI).
    si : str
        The SI unit of the same dimension, in SymPy's spelling (``"1"``: none).
    """
    from ins_errors.units import _units, registry

    ureg = registry()
    quantity = (1.0 * _units(ureg, unit)).to_base_units()
    return float(quantity.magnitude), f"{quantity.units:~C}" or "1"


def _keep_unit(v: Variable, scale: float, si: str) -> str:
    """How to keep the values of ``v`` quoted in its non-SI unit after declaring ``si``:
    a parameter's default converted and a run's ``-p`` typed in that unit, an error
    source's display unit."""
    from ins_errors.units import typed_value

    if isinstance(v, Parameter):
        typed = typed_value(f"{float(v.default):g}", v.unit).replace(" ", "")
        return (f" and the default in {si} ({float(v.default):g} {v.unit} is "
                f"{float(v.default) * scale:.10g} {si}); a run may still give it in "
                f"{v.unit} (-p {v.name}={typed})")
    if isinstance(v, ErrorSource):
        shown = v.display_unit if v.display_unit and v.display_unit != v.unit else v.unit
        return f" and keep {shown!r} as its display unit (error_source's third argument)"
    return " (the command line still reads values in other units, e.g. 2km or 15deg/h)"


_LEADING_NUMBER = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)")


def typed_example(example: str, unit: str) -> str:
    """A value of a parameter in SI ``unit`` as typed after ``-p NAME=``, with the leading
    number of ``example`` (1 without one): ``'0.5'`` for unit ``"1"``, ``'0.5/s'`` for
    ``"1/s"``, ``'9.8 m/s^2'`` for ``"m/s**2"``, ``'0.5 rad'`` for ``"rad"`` (the number
    keeps its meaning: ``'0.5 deg'`` would be 57 times smaller).

    Parameters
    ----------
    example : str
        The example as the model file wrote it (``"0.5/s"``, ``"9.8"``).
    unit : str
        The parameter's SI unit (SymPy's spelling, ``m/s**2``).

    Returns
    -------
    str
        The suggestion, in the unit's dimension whatever the example's.
    """
    from ins_errors.units import typed_value

    found = _LEADING_NUMBER.match(example)
    return typed_value(found.group(1) if found else "1", unit)


def unseen_sources(d: ModelDefinition, source_matrix: sp.Matrix,
                   initial_error_matrix: sp.Matrix) -> list[str]:
    """One warning line per error source the first-order error model does not see.

    A source whose column is zero in both G (``source_matrix``) and the initial-error
    matrix E has no first-order effect: either no equation uses it, or it enters only
    at second order or higher (``bias**2``, a model mistake more often than not). The
    linear model then reports no error for it at any magnitude.

    Parameters
    ----------
    d : ModelDefinition
        The model.
    source_matrix, initial_error_matrix : sympy.Matrix, shape (ne, nw)
        Its derived G and E.

    Returns
    -------
    list of str
        ``model 'NAME': error source 'S' ...`` lines (empty when every source is seen).
    """
    unseen = [source for j, source in enumerate(d.sources)
              if all(e == 0 for e in source_matrix[:, j])
              and all(e == 0 for e in initial_error_matrix[:, j])]
    if not unseen:
        return []
    used = set(sp.Matrix(d.real_rhs).free_symbols | sp.Matrix(d.initial_real_state).free_symbols)
    for mech in (d.ideal, d.real):
        for definition in mech.definitions:
            used |= definition.expression.free_symbols
    lines = []
    for source in unseen:
        how = ("enters the equations only at second order or higher"
               if source.symbol in used else "is used in no equation")
        lines.append(f"model {d.name!r}: error source {source.name!r} {how}: its columns of "
                     "G and of the initial errors are zero, so the linear model does not "
                     "see it")
    return lines


# --------------------------------------------------------------------------------------
# Dimensions
# --------------------------------------------------------------------------------------
_BASE = {"[length]": "m", "[time]": "s", "[mass]": "kg", "[current]": "A",
         "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}
_ANY = "any"  # the dimension of zero: it fits every sum
_SAME = (sp.Abs, sp.Max, sp.Min, sp.re, sp.im)  # result has the dimension of the arguments
_PURE = (sp.sign, sp.floor, sp.ceiling, sp.Heaviside)  # any argument, a pure number out


def _si_text(dims) -> str:
    """A dimension as SI base units: ``m/s**2``, ``1/s``, ``1``."""
    def part(items):
        return "*".join(f"{_BASE.get(k, k)}" + (f"**{v:g}" if v != 1 else "")
                        for k, v in items)
    up = [(k, v) for k, v in sorted(dims.items()) if v > 0]
    down = [(k, -v) for k, v in sorted(dims.items()) if v < 0]
    if not down:
        return part(up) or "1"
    bottom = part(down)
    return f"{part(up) or '1'}/{bottom if len(down) == 1 else f'({bottom})'}"


class _MismatchError(Exception):
    """Terms of one sum (or a function argument) with incompatible dimensions."""


class _Dimensions:
    """Dimension of SymPy expressions from the SI units of their symbols (pint's).

    ``of(expr)`` is a pint dimensionality, :data:`_ANY` for zero, or None when it cannot
    be told (a function it does not know): no verdict then.
    """

    def __init__(self, units: dict[sp.Symbol, str]):
        from ins_errors.units import _units, registry

        self.ureg = registry()
        self.none = self.ureg.dimensionless.dimensionality
        self.symbols = {s: _units(self.ureg, u).dimensionality for s, u in units.items()}
        self.memo: dict[sp.Basic, object] = {}

    def define(self, symbol: sp.Symbol, expression: sp.Basic) -> None:
        dims = self.of(expression)
        if dims is not None and dims is not _ANY:
            self.symbols[symbol] = dims

    def unit(self, text: str):
        from ins_errors.units import _units

        return _units(self.ureg, text).dimensionality

    def _text(self, dims) -> str:
        """A dimension in SI base units, or ``a pure number``."""
        return "a pure number" if dims == self.none else _si_text(dims)

    def _pure(self, args, what: str) -> None:
        for a in args:
            dims = self.of(a)
            if dims is not None and dims is not _ANY and dims != self.none:
                raise _MismatchError(f"{what} of {a}, a quantity in {_si_text(dims)} (the "
                                "argument must be a pure number)")

    def of(self, e: sp.Basic):
        if e in self.memo:
            return self.memo[e]
        dims = self._of(e)
        self.memo[e] = dims
        return dims

    def _of(self, e: sp.Basic):
        if e.is_Number:
            if e == 0:
                return _ANY
            # a decimal or large literal may stand for a quantity whose unit the file does
            # not say (g written 9.80665, a radius 6371000): no verdict rather than a
            # false refusal; small exact numbers (2, 1/2) are pure numbers
            simple = e.is_Rational and abs(e.p) <= 100 and e.q <= 100
            return self.none if simple else None
        if isinstance(e, sp.Symbol):
            return self.symbols.get(e)
        if isinstance(e, sp.NumberSymbol):
            return self.none
        if isinstance(e, sp.Add):
            # a decimal or large number takes the unit of the sum it is in (g - 9.80665);
            # a small exact one (1 + k) is a pure number, so a sum of it and a quantity in
            # 1/m is refused here, where the mistake is, not in the sum around it
            seen = None
            for term in e.args:
                dims = self.of(term)
                if dims is None:
                    if term.is_Number:
                        continue
                    return None
                if dims is _ANY:
                    continue
                if seen is None:
                    seen = (dims, term)
                elif dims != seen[0]:
                    raise _MismatchError(f"a sum of {seen[1]} ({self._text(seen[0])}) and "
                                         f"{term} ({self._text(dims)})")
            return seen[0] if seen else _ANY
        if isinstance(e, sp.Mul):
            out = self.none
            for factor in e.args:
                dims = self.of(factor)
                if dims is None or dims is _ANY:
                    return dims
                out = out * dims
            return out
        if isinstance(e, sp.Pow):
            base, exponent = e.args
            dims = self.of(base)
            if exponent.is_Number:
                return dims if dims is None or dims is _ANY else dims ** float(exponent)
            self._pure([exponent], "an exponent")
            self._pure([base], "the base of a symbolic power")
            return self.none
        if isinstance(e, sp.atan2):
            y, x = (self.of(a) for a in e.args)
            if None not in (y, x) and _ANY not in (y, x) and y != x:
                raise _MismatchError(f"atan2 of {_si_text(y)} and {_si_text(x)}")
            return self.none
        if isinstance(e, _SAME):
            known = [d for d in map(self.of, e.args) if d is not None and d is not _ANY]
            if any(d != known[0] for d in known):
                raise _MismatchError(f"{e.func} of quantities in different units")
            return known[0] if known else _ANY
        if isinstance(e, _PURE):
            return self.none
        if isinstance(e, sp.Piecewise):
            return self._piecewise(e)
        if isinstance(e, sp.Function) and e.func.__module__.startswith("sympy.functions"):
            self._pure(e.args, str(e.func))  # sin, exp, log, asin, ...
            return self.none
        return None  # a function of the author's: no verdict

    def _piecewise(self, e: sp.Piecewise):
        """The dimension shared by the branches of ``e`` (a number among them taking it,
        as in a sum), once its conditions compare quantities of one dimension."""
        for pair in e.args:
            self._condition(pair.cond)
        seen = None
        for pair in e.args:
            dims = self.of(pair.expr)
            if dims is None:
                if pair.expr.is_Number:
                    continue
                return None
            if dims is _ANY:
                continue
            if seen is None:
                seen = (dims, pair.expr)
            elif dims != seen[0]:
                raise _MismatchError(f"a Piecewise with branches in {self._text(seen[0])} "
                                     f"({seen[1]}) and {self._text(dims)} ({pair.expr})")
        return seen[0] if seen else _ANY

    def _condition(self, c: sp.Basic) -> None:
        """Refuse a comparison of two quantities of different dimensions in a condition
        (``V > a_N``); a bare number is a threshold in the unit of the other side."""
        if isinstance(c, sp.core.relational.Relational):
            if c.lhs.is_Number or c.rhs.is_Number:
                return
            a, b = self.of(c.lhs), self.of(c.rhs)
            if None in (a, b) or _ANY in (a, b) or a == b:
                return
            raise _MismatchError(f"a condition {c} comparing {self._text(a)} and "
                                 f"{self._text(b)}")
        for arg in c.args:  # And, Or, Not; True has none
            if isinstance(arg, sp.logic.boolalg.Boolean):
                self._condition(arg)


def check_dimensions(d: ModelDefinition, label: str | None = None) -> None:
    """Raise one line if an equation of ``d`` is dimensionally wrong.

    Every declared name carries an SI unit; from them each intermediate (``let``) gets
    its dimension, and then: each row of the ideal and real work must have the unit of
    its state per second (``dφ/dt = V`` in m/s for a latitude in rad is refused), each
    output and initial state the unit of its name, every sum terms of one dimension, and
    the argument of sin, exp, log, ... a pure number. Radians are pure numbers (as in
    SI), so an angle and a ratio are not told apart. A ``Piecewise`` has the dimension
    of its branches (all one dimension), and each comparison in its conditions compares
    quantities of one dimension (a bare number is a threshold in the other side's unit).
    Expressions with functions of the author's own get no verdict.

    Parameters
    ----------
    d : ModelDefinition
        The definition (already through :func:`check_definition`).
    label : str, optional
        How messages name the model (default ``model '<name>'``).
    """
    label = label or f"model {d.name!r}"
    n = len(d.states)
    units: dict[sp.Symbol, str] = {}
    for group in (d.inputs, d.parameters, d.sources, d.initial_conditions,
                  d.error_states[n:], d.states):
        units.update({v.symbol: v.unit for v in group})
    units.update({s: v.unit for s, v in zip(d.real_states[:n], d.states, strict=True)})
    dims = _Dimensions(units)
    per_second = dims.unit("1/s")

    def judge(quantity: str, expression: sp.Basic, expected, shown: str) -> None:
        try:
            found = dims.of(sp.sympify(expression))
        except _MismatchError as error:
            raise _fail(label, quantity, f"has {error}") from None
        if found is None or found is _ANY or found == expected:
            return
        what = "a pure number (or in rad)" if found == dims.none else f"in {_si_text(found)}"
        raise _fail(label, quantity, f"is {what} but must be in {_si_text(expected)} "
                                     f"({shown})")

    for mech, what in ((d.ideal, "ideal"), (d.real, "real")):
        for definition in mech.definitions:
            try:
                dims.define(definition.symbol, definition.expression)
            except _MismatchError as error:
                raise _fail(label, f"intermediate {definition.symbol} of the {what} "
                                   "mechanisation", f"has {error}") from None
    for rows, variables, quantity in ((d.ideal_rhs, d.states, "ideal-work equation"),
                                      (d.real_rhs, d.error_states, "real-work equation")):
        for expression, v in zip(sp.Matrix(rows), variables, strict=True):
            judge(f"{quantity} for {v.name!r}", expression,
                  dims.unit(v.unit) * per_second, f"the unit of {v.name}, {v.unit}, per second")
    if d.small_angle_rhs is not None:
        for expression, v in zip(sp.Matrix(d.small_angle_rhs), d.error_states, strict=True):
            judge(f"small-angle real-work equation for {v.name!r}", expression,
                  dims.unit(v.unit) * per_second, f"the unit of {v.name}, {v.unit}, per second")
    scratch = Mechanisation()
    outputs = d.output_map(scratch, d.x, d.u)
    for definition in scratch.definitions:
        dims.define(definition.symbol, definition.expression)
    for expression, v in zip(sp.Matrix(outputs), d.outputs, strict=True):
        judge(f"output {v.name!r}", expression, dims.unit(v.unit), f"its unit {v.unit}")
    for rows, variables, quantity in ((d.initial_state, d.states, "initial_state"),
                                      (d.initial_real_state, d.error_states,
                                       "initial_real_state")):
        for expression, v in zip(sp.Matrix(rows), variables, strict=True):
            judge(f"{quantity} for {v.name!r}", expression, dims.unit(v.unit),
                  f"the unit of {v.name}, {v.unit}")
