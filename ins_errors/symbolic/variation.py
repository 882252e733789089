"""Mechanical variation of a model's real-work equations around its ideal work.

Given a :class:`~ins_errors.modeling.ModelDefinition` with ideal-work right-hand side
``f(x, u, p)`` and real-work right-hand side ``f~(x~, x, u, w, p)``, the error state
``xe = x~ - (x, 0)`` obeys, to second order,

    dxe/dt = F(x, u, p) xe + G(x, u, p) w + S(x, u, p; xe, w)

with ``F = df~/dx~`` and ``G = df~/dw`` at ``x~ = (x, 0), w = 0`` and ``S`` the
second-order Taylor term. Output errors are ``ye = H xe (+ second-order term)``.
Initial errors are ``xe(0) = E(c, u, p) w`` (first order in the initial sources).

Two views are produced:

* :func:`vary` — closed matrices (every intermediate substituted), used for numerics;
* :func:`structured_variation` — the variation of each named intermediate in turn
  (Δω_ξ = ..., ΔW_ξ = ..., ΔV̇_ξ = ... ΔW_ξ ...), the way papers print error equations;
  used by the generated documents and by the hand-derivation checker.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Literal

import sympy as sp

from ins_errors.errors import InsErrorsError, ModelDefinitionError
from ins_errors.modeling import Mechanisation, ModelDefinition, accent
from ins_errors.symbolic.shared_trees import SharedTrees


@dataclass
class ErrorModel:
    """Closed-form first- and second-order error model of one INS.

    Attributes
    ----------
    definition : ModelDefinition
        The model it was derived from.
    ideal_rhs : sympy.Matrix, shape (n, 1)
        Ideal-work ``dx/dt`` in ``x, u, p``.
    real_rhs : sympy.Matrix, shape (ne, 1)
        Real-work ``dx~/dt`` in ``x~, x, u, w, p``.
    outputs : sympy.Matrix, shape (ny, 1)
        Outputs of the state ``x`` in ``x, u, p``.
    state_matrix : sympy.Matrix, shape (ne, ne)
        F in ``x, u, p``.
    source_matrix : sympy.Matrix, shape (ne, nw)
        G in ``x, u, p`` (zero columns for initial-error sources).
    output_matrix : sympy.Matrix, shape (ny, ne)
        H in ``x, u, p``.
    second_order : sympy.Matrix, shape (ne, 1)
        Second-order term S in ``x, u, p, xe, w``.
    initial_state : sympy.Matrix, shape (n, 1)
        ``x(0)`` in ``c, u, p``.
    initial_real_state : sympy.Matrix, shape (ne, 1)
        ``x~(0)`` in ``c, u, w, p``.
    initial_error_matrix : sympy.Matrix, shape (ne, nw)
        E in ``c, u, p``: first-order ``xe(0) = E w``.
    """

    definition: ModelDefinition
    ideal_rhs: sp.Matrix
    real_rhs: sp.Matrix
    outputs: sp.Matrix
    state_matrix: sp.Matrix
    source_matrix: sp.Matrix
    output_matrix: sp.Matrix
    second_order: sp.Matrix
    initial_state: sp.Matrix
    initial_real_state: sp.Matrix
    initial_error_matrix: sp.Matrix


def _second_order_term(jacobian: sp.Matrix, variables: list[sp.Symbol],
                       directions: list[sp.Symbol], point: dict[sp.Symbol, sp.Expr],
                       trees: SharedTrees) -> sp.Matrix:
    """½ Σ_jk ∂²f_i/∂v_j∂v_k d_j d_k at ``point``, from the Jacobian ∂f_i/∂v_j.

    Differentiating each nonzero Jacobian entry once more (only by the variables it
    contains) is much cheaper than differentiating the shifted expression twice;
    ``trees`` differentiates and substitutes each distinct subtree once.
    """
    rows = []
    for i in range(jacobian.rows):
        terms = []
        for j, d_j in enumerate(directions):
            entry = jacobian[i, j]
            if entry == 0:
                continue
            for k, v_k in enumerate(variables):
                if k < j or v_k not in trees.free_symbols(entry):
                    continue
                curvature = trees.xreplace(trees.derivative(entry, v_k), point)
                if curvature != 0:
                    weight = 1 if k == j else 2  # symmetric off-diagonal pairs counted once
                    terms.append(weight * curvature * d_j * directions[k])
        # one sum of all terms: the same Add as adding them one by one, without
        # flattening the growing sum again at every term
        rows.append(sp.Add(*terms) / 2)
    return sp.Matrix(len(rows), 1, rows)  # a column also with no rows (no outputs)


def second_order_of(definition: ModelDefinition, real_rhs: sp.Matrix) -> sp.Matrix:
    """Second-order term of the error equations of an (expanded) real-work right-hand side.

    Used for a model's alternative real-work equations (the small-angle platform), whose
    first-order part equals that of ``definition.real_rhs``.
    """
    d = definition
    variables = [*d.real_states, *d.w]
    point = {**d.at_ideal(), **d.no_errors()}
    with SharedTrees().differentiating() as trees:
        return _second_order_term(real_rhs.jacobian(variables), variables, [*d.xe, *d.w],
                                  point, trees)


@contextmanager
def _step(model: str, quantity: str) -> Iterator[None]:
    """Turn a SymPy failure on ``quantity`` into one line naming the model and the step."""
    try:
        yield
    except InsErrorsError:
        raise
    except RecursionError:  # SymPy walks an expression recursively, a level per nesting
        raise ModelDefinitionError(f"model {model!r}: {quantity}: an expression is too "
                                   "deeply nested for SymPy to differentiate "
                                   "(RecursionError): name its inner parts as intermediate "
                                   "quantities with let() (step: variation)") from None
    except Exception as error:  # SymPy on a researcher's expressions: any failure
        text = str(error).strip().splitlines()
        raise ModelDefinitionError(f"model {model!r}: {quantity}: {type(error).__name__}: "
                                   f"{text[0] if text else ''} (step: variation)") from None


def vary(definition: ModelDefinition) -> ErrorModel:
    """Derive the closed first- and second-order error model of ``definition``.

    Every Jacobian and substitution goes through one :class:`SharedTrees` (each distinct
    subtree of the closed equations is differentiated and substituted once; the results
    are SymPy's own).

    Raises
    ------
    ModelDefinitionError
        If SymPy fails on one of the quantities (the message names it).
    """
    global _LAST_VARIED
    with SharedTrees().differentiating() as trees:
        varied = _vary(definition, trees)
    _LAST_VARIED = varied
    return varied


_LAST_VARIED: ErrorModel | None = None
"""The error model :func:`vary` derived last in this process (see :func:`last_varied`)."""


def last_varied(definition: ModelDefinition) -> ErrorModel | None:
    """What :func:`vary` returned for this very ``definition`` object, if it was the last
    model varied in this process (``make derive`` varies a model, then analyses it at a
    static base from the same Jacobians); else None."""
    varied = _LAST_VARIED
    return varied if varied is not None and varied.definition is definition else None


def _vary(d: ModelDefinition, trees: SharedTrees) -> ErrorModel:
    n = len(d.states)
    at_ideal = d.at_ideal()
    no_errors = d.no_errors()
    with _step(d.name, "real-work equations (intermediates substituted)"):
        real_rhs = d.real_rhs_expanded()
    with _step(d.name, "outputs (intermediates substituted)"):
        outputs = d.outputs_expanded()

    def at_point(m: sp.Matrix) -> sp.Matrix:
        return trees.xreplace_matrix(trees.xreplace_matrix(m, at_ideal), no_errors)

    variables = [*d.real_states, *d.w]
    with _step(d.name, "state matrix F and source matrix G"):
        jacobian = real_rhs.jacobian(variables)
        F = at_point(jacobian[:, : len(d.real_states)])
        G = at_point(jacobian[:, len(d.real_states):])
    with _step(d.name, "output matrix H"):
        output_jacobian = outputs.jacobian(d.x)
        H = output_jacobian.row_join(sp.zeros(len(d.outputs), len(d.real_states) - n))

    point = {**at_ideal, **no_errors}
    with _step(d.name, "second-order terms"):
        second = _second_order_term(jacobian, variables, [*d.xe, *d.w], point, trees)

    with _step(d.name, "initial error matrix E"):
        E = trees.xreplace_matrix(d.initial_real_state.jacobian(d.w), no_errors)
    with _step(d.name, "ideal-work equations (intermediates substituted)"):
        ideal_rhs = d.ideal_rhs_expanded()
    _refuse_non_finite(d, F, G, H, second, E)
    return ErrorModel(
        definition=d,
        ideal_rhs=ideal_rhs,
        real_rhs=real_rhs,
        outputs=outputs,
        state_matrix=F,
        source_matrix=G,
        output_matrix=H,
        second_order=second,
        initial_state=d.initial_state,
        initial_real_state=d.initial_real_state,
        initial_error_matrix=E,
    )


def _refuse_non_finite(d: ModelDefinition, F: sp.Matrix, G: sp.Matrix, H: sp.Matrix,
                       second: sp.Matrix, E: sp.Matrix) -> None:
    """Refuse derivatives that are not finite where the errors are zero.

    A formula that is finite itself (checked by
    :func:`~ins_errors.symbolic.consistency.check_definition`) may have an infinite or
    undefined derivative there (``sqrt(psi)`` at ψ = 0); generated code would compute
    ``nan`` from it. The message names the equation and the quantity.
    """
    from ins_errors.symbolic.consistency import non_finite

    errors = [v.name for v in d.error_states]
    sources = [v.name for v in d.sources]
    outputs = [v.name for v in d.outputs]
    checks = (
        (F, "state matrix F", "real-work equation for {row!r}", errors, errors),
        (G, "source matrix G", "real-work equation for {row!r}", errors, sources),
        (H, "output matrix H", "output {row!r}", outputs, errors),
        (E, "initial error matrix E", "initial real state of {row!r}", errors, sources),
    )
    for matrix, what, equation, rows, columns in checks:
        for i in range(matrix.rows):
            for j in range(matrix.cols):
                bad = non_finite(matrix[i, j])
                if bad:
                    row = rows[i]
                    raise ModelDefinitionError(
                        f"model {d.name!r}: {what}: the derivative of the "
                        f"{equation.format(row=row)} by {columns[j]} is not finite where "
                        f"the errors are zero (it contains {', '.join(bad)}): a formula "
                        "such as sqrt(psi) or 1/psi of an error state or source; write one "
                        "that is smooth at zero error (step: variation)")
    for i in range(second.rows):
        bad = non_finite(second[i, 0])
        if bad:
            raise ModelDefinitionError(
                f"model {d.name!r}: second-order terms: the second derivatives of the "
                f"real-work equation for {errors[i]!r} are not finite where the errors are "
                f"zero (they contain {', '.join(bad)}): a formula such as psi**1.5 of "
                "an error state or source; write one that is smooth at zero error "
                "(step: variation)")


# --------------------------------------------------------------------------------------
# Structured (paper-style) variation
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class VariedEquation:
    """One line of a paper-style error listing: ``lhs = rhs``.

    Attributes
    ----------
    name : str
        Name of the varied quantity: an intermediate (``"omega_xi"``), an error state
        (``"alpha_x"``, whose line is its time derivative) or an output (``"latitude"``).
    kind : {"intermediate", "state", "output"}
        What the line defines.
    lhs : sympy.Symbol
        The variation symbol (``Delta_omega_xi``), or the error-state symbol whose
        derivative the line gives.
    rhs : sympy.Expr
        Linear in variation symbols, error states and sources; coefficients are ideal
        quantities (states, inputs, parameters and ideal intermediate symbols).
    latex : str
        LaTeX of the left-hand side.
    """

    name: str
    kind: Literal["intermediate", "state", "output"]
    lhs: sp.Symbol
    rhs: sp.Expr
    latex: str


def delta_symbol(name: str) -> sp.Symbol:
    """Symbol of the variation of the intermediate quantity ``name``."""
    return sp.Symbol(f"Delta_{name}", real=True)


def _plain_name(symbol: sp.Symbol) -> str:
    return symbol.name[:-2] if symbol.name.endswith("_c") else symbol.name


def output_mechanisations(d: ModelDefinition) -> tuple[Mechanisation, sp.Matrix,
                                                       Mechanisation, sp.Matrix]:
    """Output intermediates of the true and of the computed state.

    Returns
    -------
    true_mech, true_outputs, computed_mech, computed_outputs
    """
    n = len(d.states)
    true_mech = Mechanisation()
    true_out = d.output_map(true_mech, d.x, d.u)
    computed_mech = Mechanisation(computed=True)
    computed_out = d.output_map(computed_mech, d.real_states[:n], d.u)
    return true_mech, true_out, computed_mech, computed_out


def ideal_intermediate_values(d: ModelDefinition) -> dict[sp.Symbol, sp.Expr]:
    """Closed expressions (in ``x, u, p``) of every ideal intermediate symbol."""
    true_mech, _, _, _ = output_mechanisations(d)
    values: dict[sp.Symbol, sp.Expr] = {}
    for mech in (d.ideal, true_mech):
        for definition in mech.definitions:
            values[definition.symbol] = mech.expand(definition.expression)
    return values


def structured_variation(d: ModelDefinition) -> list[VariedEquation]:
    """Vary every named intermediate, state derivative and output, one line each.

    The right-hand side of each line is the first-order variation of its defining formula
    with respect to its direct arguments only: computed states contribute their error
    state, computed intermediates their ``Delta_`` symbol, platform angles and error
    sources themselves. Coefficients are evaluated at the ideal point and written with
    the ideal intermediate symbols (R_ξ^{-1}, ω_ξ, ...), as a paper would.

    Computed once per definition object in a process (the error-equation document and
    the hand-derivation checker both read it); the lines are frozen, the list is a copy;
    kept on disk for later processes (:mod:`ins_errors.symbolic.variation_store`).
    """
    entry = _STRUCTURED.get(id(d))
    if entry is None or entry[0] is not d:
        from ins_errors.symbolic import variation_store

        name = variation_store.key(d)
        lines = variation_store.load(name)
        if lines is None or not all(isinstance(line, VariedEquation) for line in lines):
            with SharedTrees().differentiating() as trees:
                lines = _structured_variation(d, trees)
            variation_store.store(name, lines)
        entry = (d, lines)
        _STRUCTURED[id(d)] = entry
    return list(entry[1])


_STRUCTURED: dict[int, tuple[ModelDefinition, list[VariedEquation]]] = {}
"""Per definition (by id, with the definition itself kept to check identity): its lines."""


def _structured_variation(d: ModelDefinition, trees: SharedTrees) -> list[VariedEquation]:
    true_mech, _, computed_mech, computed_out = output_mechanisations(d)
    latex = d.latex_names()
    latex.update({df.symbol: df.latex for df in true_mech.definitions})
    # how each argument varies
    variation: dict[sp.Symbol, sp.Expr] = {}
    for xr, xe in zip(d.real_states, d.xe, strict=True):
        variation[xr] = xe
    variation.update({s: s for s in d.w})
    # ideal value of each real-work symbol
    ideal_of: dict[sp.Symbol, sp.Expr] = dict(d.at_ideal())
    ideal_of.update(d.no_errors())
    lines: list[VariedEquation] = []

    def vary_expression(expr: sp.Expr) -> sp.Expr:
        total = sp.S.Zero
        for arg in sorted(trees.free_symbols(expr) & variation.keys(), key=sp.default_sort_key):
            coefficient = _tidy(trees.xreplace(trees.derivative(expr, arg), ideal_of))
            total += coefficient * variation[arg]
        return total

    def add_definitions(mech: Mechanisation) -> None:
        for definition in mech.definitions:
            name = _plain_name(definition.symbol)
            lhs = delta_symbol(name)
            if definition.symbol in variation:  # defined twice (R_E in outputs)
                continue
            rhs = vary_expression(definition.expression)
            variation[definition.symbol] = lhs
            ideal_of[definition.symbol] = sp.Symbol(name, real=True)
            plain_latex = latex.get(sp.Symbol(name, real=True), definition.latex)
            lines.append(VariedEquation(name, "intermediate", lhs, rhs,
                                        rf"\Delta {plain_latex}"))

    add_definitions(d.real)
    for xe, var, rhs in zip(d.xe, d.error_states, d.real_rhs, strict=True):
        lines.append(VariedEquation(var.name, "state", xe, vary_expression(rhs),
                                    accent(var.latex, "dot")))
    # outputs: intermediates of the computed output chain, then one line per output
    add_definitions(computed_mech)
    for var, expr in zip(d.outputs, computed_out, strict=True):
        lhs = sp.Symbol(f"Delta_{var.name}", real=True)
        lines.append(VariedEquation(var.name, "output", lhs, vary_expression(expr),
                                    rf"\Delta {var.latex}"))
    return lines


@functools.lru_cache(maxsize=4096)
def _tidy(coefficient: sp.Expr) -> sp.Expr:
    """Light simplification of a coefficient (radicals combined), kept cheap."""
    if coefficient.is_number or not coefficient.has(sp.Pow):
        return coefficient
    return sp.factor_terms(sp.together(coefficient))


def flatten(lines: list[VariedEquation]) -> dict[str, sp.Expr]:
    """Substitute the intermediate variations into the state and output lines.

    Returns
    -------
    dict
        Error-state or output name -> expression linear in error states and sources,
        with coefficients in ideal quantities (intermediate symbols kept).
    """
    known: dict[sp.Symbol, sp.Expr] = {}
    flat: dict[str, sp.Expr] = {}
    for line in lines:
        rhs = line.rhs.xreplace(known)
        if line.kind == "intermediate":
            known[line.lhs] = rhs
        else:
            flat[line.name] = rhs
    return flat
