"""Checks a model definition must pass before it is varied or turned into code.

A mistake in a model file (a symbol that is used but never declared, a right-hand side
with the wrong number of rows, a state without an equation, a real work that does not
reduce to the ideal work when every error is off) would otherwise surface as a SymPy
traceback deep in the variation, or worse, as generated code that runs and is wrong.
:func:`check_definition` finds these and raises one
:class:`~ins_errors.errors.ModelDefinitionError` naming the model, the quantity and the
step ("checking the definition").
"""

from __future__ import annotations

import difflib
import math
import random
from collections.abc import Iterable, Sequence

import sympy as sp
from sympy.core.function import AppliedUndef

from ins_errors.errors import ModelDefinitionError
from ins_errors.modeling import Mechanisation, ModelDefinition, Variable

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
    # names that become arguments of the same generated function must differ
    for together in (("states", "inputs", "parameters", "sources"),
                     ("initial_conditions", "inputs", "parameters", "sources")):
        owner: dict[str, str] = {}
        for group in together:
            for v in groups[group]:
                if v.name in owner:
                    raise _fail(label, f"{group} {v.name!r}",
                                f"the same name is also one of the {owner[v.name]}")
                owner[v.name] = group


def _column(label: str, quantity: str, value: object, rows: int, row_names: list[str],
            what: str) -> sp.Matrix:
    """``value`` as a column matrix of ``rows`` SymPy expressions, or a one-line error."""
    try:
        matrix = sp.Matrix(value)
    except (TypeError, ValueError, sp.SympifyError) as error:
        raise _fail(label, quantity, f"not a column of SymPy expressions ({error})") from None
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
                   allowed: set[sp.Symbol], hint: str) -> None:
    for i in range(matrix.rows):
        entry = matrix[i, 0]
        if not isinstance(entry, sp.Expr):
            raise _fail(label, f"{quantity} for {row_names[i]!r}",
                        f"{entry!r:.60} is not a SymPy expression")
        _undefined_functions(label, f"{quantity} for {row_names[i]!r}", entry)
        unknown = {s for s in entry.free_symbols if s not in allowed}
        if unknown:
            plain = {s for s in unknown if isinstance(s, sp.Symbol)}
            near = {a.name for a in allowed for s in plain if a.name == s.name}
            why = (f" ({_names(near)} declared, but with other assumptions: make symbols "
                   "with Variable.symbol)") if near else f"; it may use {hint}"
            raise _fail(label, f"{quantity} for {row_names[i]!r}",
                        f"uses undefined symbol(s) {_names(unknown)}{why}")


def _intermediates(mech: Mechanisation) -> set[sp.Symbol]:
    return {definition.symbol for definition in mech.definitions}


def _check_reduces_to_ideal(label: str, d: ModelDefinition, ideal: sp.Matrix,
                            real: sp.Matrix) -> None:
    """With every error off and the computed state on the true one, the real work must
    give the ideal derivatives and zero for the extra states (checked at random points)."""
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
    for _ in range(3):
        point = [defaults.get(s, rng.uniform(0.1, 0.6)) for s in symbols]
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


def check_definition(d: ModelDefinition, label: str | None = None) -> None:
    """Raise a one-line :class:`~ins_errors.errors.ModelDefinitionError` if ``d`` is
    inconsistent.

    Checks, in order: names (identifiers, unique, no clash between arguments of one
    generated function); the kind of each error source (:data:`SOURCE_KINDS`); finite
    parameter defaults; shapes of every right-hand side, output and initial state (one
    row per state, no missing equation); that every symbol used is a declared state,
    input, parameter, error source, initial condition or recorded intermediate, and every
    function a SymPy one (in the equations, intermediates and domain conditions); that
    the document groups name error states; and that the real work reduces to the ideal
    work when the computed state is the true one and every error is off.

    Parameters
    ----------
    d : ModelDefinition
        The definition to check.
    label : str, optional
        How messages name the model (default ``model '<name>'``).
    """
    label = label or f"model {d.name!r}"
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
                   x | u | p | ideal_defs, "a real-work state, an error source or an "
                   "intermediate of the real mechanisation")
    _check_symbols(label, "real-work equation (real_rhs)", real, error_names,
                   set(d.real_states) | x | u | w | p | ideal_defs | real_defs,
                   "a symbol made with sp.Symbol instead of a declared Variable")
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
            extra = definition.expression.free_symbols - allowed - defined
            if extra:
                raise _fail(label, f"intermediate {definition.symbol} of the {what} "
                                   "mechanisation",
                            f"uses undefined symbol(s) {_names(extra)} (or one defined later)")
            defined.add(definition.symbol)
    try:
        scratch = Mechanisation()
        outputs_raw = d.output_map(scratch, d.x, d.u)
    except Exception as error:  # a researcher's function: report any failure
        raise _fail(label, "output_map", f"raised {type(error).__name__}: {error}") from None
    out_names = [v.name for v in d.outputs]
    outputs = _column(label, "output_map", outputs_raw, len(d.outputs), out_names, "outputs")
    _check_symbols(label, "output", scratch.expand(outputs), out_names, x | u | p,
                   "a computed-state symbol instead of the state passed to output_map")
    init = _column(label, "initial_state", d.initial_state, n, state_names, "states")
    _check_symbols(label, "initial_state", init, state_names, c | u | p,
                   "a state instead of an initial condition")
    init_real = _column(label, "initial_real_state", d.initial_real_state, ne, error_names,
                        "error states")
    _check_symbols(label, "initial_real_state", init_real, error_names, c | u | w | p,
                   "a state instead of an initial condition")
    for conditions, allowed, what in ((d.domain, x | u | p, "domain"),
                                      (d.initial_domain, c | u | p, "initial_domain")):
        for k, item in enumerate(conditions):
            if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[1], str)):
                raise _fail(label, f"{what}[{k}]", "must be a pair (expression, message)")
            _undefined_functions(label, f"{what} condition {item[1]!r}", sp.sympify(item[0]))
            extra = sp.sympify(item[0]).free_symbols - allowed
            if extra:
                raise _fail(label, f"{what} condition {item[1]!r}",
                            f"uses undefined symbol(s) {_names(extra)}")
    for title, members in d.groups:
        unknown_members = [m for m in members if m not in error_names]
        if unknown_members:
            raise _fail(label, f"group {title!r}",
                        f"names {', '.join(map(repr, unknown_members))}, not error states")
    _check_reduces_to_ideal(label, d, d.ideal.expand(ideal), d.expand(real))


def check_units(d: ModelDefinition, label: str | None = None) -> None:
    """Raise one line if a unit of ``d`` does not parse, or if an error source's display
    unit does not convert to its SI unit (``"deg/h"`` for an accelerometer bias).

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
