"""Derive step: transfer functions, modes and closed-form responses at a static base.

For every model with a static-base setup (:mod:`ins_errors.symbolic.static_base`) this
writes

* ``generated/<model>/transfer_functions.md``: the static-base F of each variant, the
  terms a simplification drops, det(sI − F) and its modes (periods), the resolvent
  (sI − F)⁻¹ and the closed-form time responses to every error source (LaTeX);
* ``generated/<model>/closed_forms.py``: numpy functions of those closed forms
  (``responses_<variant>(t, x, u, p)``, ``frequencies_<variant>(x, u, p)``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from ins_errors.models import definition
from ins_errors.symbolic.analytic import (
    S,
    StaticAnalysis,
    T,
    factor_lists_remembered,
    factor_product,
)
from ins_errors.symbolic.codegen import Argument, FunctionSpec, emit_numpy_function, prepare
from ins_errors.symbolic.documents import to_latex
from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.simplifications import simplification
from ins_errors.symbolic.static_base import (
    LATEX,
    OMEGA_BAR,
    OMEGA_MINUS,
    OMEGA_N,
    OMEGA_PLUS,
    OMEGA_S,
    OMEGA_U,
    SETUPS,
    StaticSetup,
    VariantResult,
    static_analyses,
    static_matrices,
)

from .model_files import NUMPY_PRELUDE

_HEADER = ("GENERATED FILE: do not edit by hand.",
           "Written by `make derive` (python -m derive, step derive/transfer_functions.py)",
           "from ins_errors/models/{model}.py via ins_errors/symbolic/static_base.py.",
           "Edit those and run `make derive` again.")

def _header(model: str, markdown: bool) -> str:
    lines = [line.format(model=model) for line in _HEADER]
    if markdown:
        return "<!--\n" + "\n".join(lines) + "\n-->\n"
    return "".join(f"# {line}\n" for line in lines)


@functools.cache
def _setup(model: str) -> StaticSetup:
    """The model's static setup, built once per process."""
    return SETUPS[model]()


def _names(model: str) -> dict[sp.Symbol, str]:
    d = definition(model)
    names = d.latex_names()
    names.update(LATEX)
    names.update({S: "s", T: "t"})
    names.setdefault(sp.Symbol("phi", real=True), r"\varphi")  # a static base's latitude
    return names


def _matrix_latex(M: sp.Matrix, names: dict[sp.Symbol, str]) -> str:
    rows = [" & ".join(to_latex(e, names) for e in M.row(i)) for i in range(M.rows)]
    return r"\begin{bmatrix}" + r" \\ ".join(rows) + r"\end{bmatrix}"


def _period_text(analysis: StaticAnalysis, model: str) -> list[str]:
    names = _names(model)
    rows = []
    for mode in analysis.modes:
        if mode.symbol is None:
            rows.append(f"| integrator | $s^{{{mode.multiplicity}}}$ | – |")
            continue
        w = to_latex(mode.symbol, names)
        rows.append(f"| {mode.name} | $(s^2 + {w}^2)^{{{mode.multiplicity}}}$ | "
                    f"$2\\pi/{w}$ |")
    return ["| mode | factor | period |", "|---|---|---|", *rows]


def _mode_product(a: StaticAnalysis) -> sp.Expr:
    """det(sI − F) written as the product of its modes (integrators s, s² + ω²)."""
    product = sp.Poly(a.characteristic, S).LC()
    for mode in a.modes:
        factor = S if mode.symbol is None else S**2 + mode.symbol**2
        product *= sp.Pow(factor, mode.multiplicity, evaluate=False) if mode.multiplicity > 1 \
            else factor
    return product


class _Readable:
    """Rewrite printed forms of one variant in its shortest named quantities.

    Each factor of a product (a partial-fraction coefficient, a coefficient of s in an
    adjugate entry) is tried as written and with Ω_N² = Ω² − Ω_U² (Ω the Earth mode's
    symbol) and, where the parametrisation has the Foucault pair, ω̄ = (ω₊ + ω₋)/2,
    Ω_U = (ω₊ − ω₋)/2, each expanded and factored; the form with the fewest operations
    is kept (so Ω_U − ω̄ reads −ω₋ and Ω_N² − 2Ω_U ω̄ − ω̄² reads Ω² − ω₊²). Then
    ω₊ ω₋ = ω_s², and a product divided by Ω_N has Ω_N, Ω_U written Ω cos φ, Ω sin φ and
    trigsimp'd (Ω/Ω_N reads 1/cos φ). Every rule is an identity of the parametrisation,
    so the printed forms equal the analysed ones (tests/test_analytic_documents.py
    evaluates them against numpy's inverse and scipy's expm).
    """

    def __init__(self, analysis) -> None:
        par = analysis.parametrisation
        self.definitions = par.definitions
        earth = [m for m in analysis.modes if m.symbol is not None and m.name == "Earth"]
        self.earth = earth[0].symbol if earth else None
        self.split = {OMEGA_PLUS, OMEGA_MINUS, OMEGA_BAR} <= set(par.definitions)
        self._factors: dict[sp.Expr, sp.Expr] = {}
        self._monomials: dict[sp.Expr, sp.Expr] = {}
        self._factored: dict[sp.Expr, sp.Expr] = {}

    def definitions_shown(self) -> dict[sp.Symbol, sp.Expr]:
        """Every symbol the printed forms use -> its definition (ω_s included, in the
        model's symbols: ω_s² = ω̄² − Ω_U² = ω₊ω₋)."""
        out = dict(self.definitions)
        if self.split:
            out[OMEGA_S] = self.to_model(sp.sqrt(OMEGA_BAR**2 - OMEGA_U**2))
        return out

    def to_model(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` with the parametrisation's symbols replaced by their definitions."""
        for _ in range(len(self.definitions) + 1):
            if not expr.free_symbols & self.definitions.keys():
                break
            expr = expr.xreplace(self.definitions)
        return expr

    def factor(self, f: sp.Expr) -> sp.Expr:
        """The shortest identical form of one sum (see the class)."""
        if f in self._factors:
            return self._factors[f]
        candidates = [f]
        g = f
        if self.earth is not None and f.has(OMEGA_N):
            g = sp.expand(f.subs(OMEGA_N**2, self.earth**2 - OMEGA_U**2))
            candidates += [g, factor_product(g)]
        if self.split and f.has(OMEGA_BAR):
            h = sp.expand(g.xreplace({OMEGA_BAR: (OMEGA_PLUS + OMEGA_MINUS) / 2,
                                      OMEGA_U: (OMEGA_PLUS - OMEGA_MINUS) / 2}))
            k = sp.expand(h.subs(OMEGA_PLUS * OMEGA_MINUS, OMEGA_S**2))
            candidates += [h, factor_product(h), k, factor_product(k)]
        # the first of the shortest, then of those with the fewest symbols
        best = min(candidates, key=lambda e: (sp.count_ops(e), len(e.free_symbols)))
        self._factors[f] = best
        return best

    def product(self, term: sp.Expr) -> sp.Expr:
        """One product with its sums rewritten, ω₊ω₋ = ω_s², 1/Ω_N as trigonometry."""
        factors = []
        for arg in sp.Mul.make_args(term):
            base, exponent = arg.as_base_exp()
            if base.is_Add and not base.has(T) and exponent.is_Integer:
                factors.append(self.factor(base) ** exponent)
            else:
                factors.append(arg)
        term = sp.Mul(*factors)
        if self.split:
            powers = term.as_powers_dict()
            pair = min(powers.get(OMEGA_PLUS, 0), powers.get(OMEGA_MINUS, 0))
            if pair > 0:
                term = term / (OMEGA_PLUS * OMEGA_MINUS) ** pair * OMEGA_S ** (2 * pair)
        if term.as_powers_dict().get(OMEGA_N, 0) < 0 and OMEGA_N in self.definitions:
            monomial, rest = sp.S.One, sp.S.One
            for arg in sp.Mul.make_args(term):
                if arg.as_base_exp()[0] in (OMEGA_N, OMEGA_U):
                    monomial *= arg
                else:
                    rest *= arg
            if monomial not in self._monomials:
                self._monomials[monomial] = sp.trigsimp(monomial.xreplace(
                    {q: self.definitions[q] for q in (OMEGA_N, OMEGA_U)}))
            term = rest * self._monomials[monomial]
        return term

    def response(self, expr: sp.Expr) -> sp.Expr:
        """A time response: a sum of products, each rewritten."""
        return sp.Add(*[self.product(t) for t in sp.Add.make_args(expr)])

    def polynomial(self, expr: sp.Expr) -> list[tuple[int, sp.Expr]]:
        """A polynomial in s: (power, coefficient factored and rewritten), highest first."""
        terms = []
        for monomial, c in sp.collect(sp.expand(expr), S, evaluate=False).items():
            base, k = monomial.as_base_exp()
            terms.append((0 if base == 1 else int(k), c))
        out = []
        for k, c in sorted(terms, key=lambda term: -term[0]):
            if c not in self._factored:
                self._factored[c] = self.product(factor_product(c))
            out.append((k, self._factored[c]))
        return out


@dataclass
class ShownForms:
    """What ``transfer_functions.md`` prints for one variant, as SymPy objects.

    Attributes
    ----------
    state_matrix : sympy.Matrix
        F in the model's symbols (parameters the analysis fixed to numbers kept as
        symbols: their values are in the document's constants table).
    characteristic : sympy.Expr
        Δ(s) = det(sI − F) as the product of its modes.
    definitions : dict
        Every parametrisation symbol the forms use -> its definition (in the model's
        symbols or in other such symbols).
    adjugate : dict
        (i, j) -> adj_ij(s) as its terms (power of s, coefficient), highest power
        first: the printed nonzero entries (empty when not printed).
    zero_adjugate : list of (i, j)
        The entries left out because they are identically zero.
    responses : dict or None
        Source name -> {error-state index: x_i(t) for a unit source}, the nonzero
        entries (None when the variant's responses are not printed).
    """

    state_matrix: sp.Matrix
    characteristic: sp.Expr
    definitions: dict[sp.Symbol, sp.Expr]
    adjugate: dict[tuple[int, int], list[tuple[int, sp.Expr]]]
    zero_adjugate: list[tuple[int, int]]
    responses: dict[str, dict[int, sp.Expr]] | None


def shown_forms(model: str, result: VariantResult) -> ShownForms:
    """The forms the document prints for one variant of ``model``."""
    setup = _setup(model)
    trees = SharedTrees()
    readable = _Readable(result.analysis)
    with factor_lists_remembered():
        return _shown_forms(model, result, setup, trees, readable)


def _shown_forms(model: str, result: VariantResult, setup, trees: SharedTrees,
                 readable: _Readable) -> ShownForms:
    a = result.analysis
    par = a.parametrisation
    if setup.display_point is not None:
        F = static_matrices(model, setup.display_point, setup.initial_point)[0]
        if result.variant.simplification:
            F = simplification(result.variant.simplification).apply(
                F, [v.name for v in definition(model).error_states])[0]
        shown_F = F
    else:
        shown_F = a.state_matrix.applyfunc(lambda e: sp.expand(par.to_model(e, trees)))
    adjugate, zero = {}, []
    if setup.print_resolvent:
        for i in range(a.adjugate.rows):
            for j in range(a.adjugate.cols):
                if a.adjugate[i, j] == 0:
                    zero.append((i, j))
                else:
                    adjugate[i, j] = readable.polynomial(a.adjugate[i, j])
    responses = None
    if result.variant.factored:
        responses = {name: {i: readable.response(e) for i, e in enumerate(a.responses[name])
                            if e != 0}
                     for name in result.sources}
    return ShownForms(shown_F, _mode_product(result.analysis), readable.definitions_shown(),
                      adjugate, zero, responses)


def _polynomial_latex(terms: list[tuple[int, sp.Expr]], names) -> str:
    """c_n s^n + ... + c_0, highest power first (each coefficient in parentheses if a sum)."""
    text = ""
    for power, coefficient in terms:
        monomial = {0: "", 1: " s"}.get(power, f" s^{{{power}}}")
        c = to_latex(coefficient, names)
        if coefficient.is_Add:
            c = f"\\left({c}\\right)"
        elif coefficient == 1 and power:
            c = ""
        elif coefficient == -1 and power:
            c = "-"
        if text and not c.startswith("-"):
            text += " + "
        elif text:
            text += " "
        text += (c + monomial).strip()
    return text


def _constants(model: str) -> list[str]:
    """The table of the model's parameters: fixed before the analysis, or symbolic."""
    d = definition(model)
    setup = _setup(model)
    names = _names(model)
    rows = ["| symbol | meaning | value in this document |", "|---|---|---|"]
    for q in d.parameters:
        unit = "" if q.unit == "1" else f" {q.unit}"
        if q.name in setup.baked:
            value = (f"{setup.baked[q.name]:.10g}{unit}: the analysis is derived for this "
                     "value only")
        else:
            value = f"symbolic (default {q.default:.10g}{unit})"
        rows.append(f"| ${names[q.symbol]}$ | {q.description} | {value} |")
    return rows


def _definitions_text(forms: ShownForms, model: str) -> list[str]:
    names = _names(model)
    rows = ["| symbol | definition |", "|---|---|"]
    for symbol, value in forms.definitions.items():
        rows.append(f"| ${to_latex(symbol, names)}$ | ${to_latex(value, names)}$ |")
    return rows


def _entry_names(indices, states: list[str], names) -> str:
    return ", ".join(f"$\\operatorname{{adj}}_{{{i + 1}{j + 1}}}$" for i, j in indices)


def markdown(model: str, results: list[VariantResult],
             shown: list[ShownForms] | None = None) -> str:
    """The ``transfer_functions.md`` document of one model.

    Parameters
    ----------
    model : str
        The model's name.
    results : list of VariantResult
        The analysed variants, in document order.
    shown : list of ShownForms, optional
        ``shown_forms(model, result)`` of each result, when the caller has them already
        (computed here otherwise; the text is the same).

    Returns
    -------
    str
        The document.
    """
    d = definition(model)
    setup = _setup(model)
    names = _names(model)
    states = [v.name for v in d.error_states]
    out = [f"# Transfer functions and closed-form responses of `{model}` (static base)", "",
           f"{d.title}. Source: {d.source}.", "",
           setup.description, "",
           "Derived mechanically: F, G and the initial-error matrix come from the variation "
           "of the model's real-work equations (see `error_equations.md`), evaluated at the "
           "static base; (sI − F)⁻¹ is exact over the rational functions of the "
           "coefficients; the time responses come from partial fractions in z = s² and the "
           "table 1/(s²+ω²) → sin ωt/ω, s/(s²+ω²) → cos ωt, 1/s^n → t^(n−1)/(n−1)!. Every "
           "response is to a *unit* source (1 in SI units) with every other source zero; "
           "constant sources start at t = 0 (step), initial errors are x(0). The printed "
           "forms are rewritten with identities of the parametrisation (e.g. ω₊ω₋ = ω_s², "
           "Ω_N² + Ω_U² = Ω²) and checked numerically against the model's own F "
           "(tests/test_analytic_documents.py).", "",
           "Constants (the model's parameters):", "", *_constants(model), ""]
    if shown is None:
        shown = [shown_forms(model, result) for result in results]
    for result, forms in zip(results, shown, strict=True):
        a = result.analysis
        par = a.parametrisation
        out += [f"## {result.variant.title}", "",
                f"Variant `{result.variant.name}`. Parametrisation: {par.description}.", ""]
        if result.variant.simplification:
            out += ["Terms dropped from the full model (named simplification "
                    f"`{result.variant.simplification}`):", "",
                    "| equation | term | coefficient in the full model | reason |",
                    "|---|---|---|---|"]
            for term, value in result.dropped:
                eq = names[sp.Symbol(term.equation, real=True)]
                var = names[sp.Symbol(term.variable, real=True)]
                out.append(f"| $\\dot{{{eq}}}$ | ${to_latex(value, names)}\\,{var}$ | "
                           f"${to_latex(value, names)}$ | {term.reason} |")
            out.append("")
        out += ["State matrix at the static base (rows and columns: "
                + ", ".join(f"`{n}`" for n in states) + "):", "",
                f"$$ F = {_matrix_latex(forms.state_matrix, names)} $$", "",
                "Characteristic polynomial and its modes:", "",
                f"$$ \\Delta(s) = \\det(sI - F) = {to_latex(forms.characteristic, names)} $$",
                "", *_period_text(a, model), "",
                "Symbols of the parametrisation:", "", *_definitions_text(forms, model), ""]
        if setup.print_resolvent:
            out += ["### Resolvent (sI − F)⁻¹ = adj(sI − F) / Δ(s)", "",
                    "Entry C_ij is the Laplace transform of error state i for a unit "
                    "initial value of error state j; its numerator adj_ij(s) is listed "
                    "(Δ(s) above). Entries not listed are identically zero: "
                    + (_entry_names(forms.zero_adjugate, states, names) or "none") + ".", ""]
            for (i, j), terms in forms.adjugate.items():
                out += [f"$$ \\operatorname{{adj}}_{{{i + 1}{j + 1}}} = "
                        f"[{names[sp.Symbol(states[i], real=True)]} \\leftarrow "
                        f"{names[sp.Symbol(states[j], real=True)]}(0)] = "
                        f"{_polynomial_latex(terms, names)} $$", ""]
        else:
            out += ["(sI − F)⁻¹ is not printed for this model: its parameters are fixed to "
                    "numbers before the analysis, and its "
                    f"{len(states)}×{len(states)} entries would print as long rational "
                    "numbers. `ins_errors.symbolic.static_base.static_analyses"
                    f"({model!r})[0].analysis.resolvent` holds it exactly.", ""]
        for limit, at in zip(result.variant.limits, result.limits, strict=True):
            definitions = [f"${to_latex(k, names)} = {to_latex(v, names)}$"
                           for k, v in at.parametrisation.definitions.items()]
            out += [f"### Limit `{limit.name}`", "", limit.description, "",
                    f"Parametrisation there: {at.parametrisation.description} ("
                    + ", ".join(definitions) + "). Characteristic polynomial and modes:", "",
                    f"$$ \\Delta(s) = {to_latex(_mode_product(at), names)} $$", "",
                    *_period_text(at, model), "",
                    f"Emitted as `_forms_{result.variant.name}_{limit.name}` in "
                    "`closed_forms.py`; the denominators of the general forms are listed "
                    "there (`DENOMINATORS`), and a point where one vanishes with no limit "
                    "derived for it is refused (ValueError) instead of giving NaN.", ""]
        if forms.responses is None:
            out += ["### Time responses", "",
                    "The closed-form time responses of this variant are emitted to "
                    f"`closed_forms.py` (`responses_{result.variant.name}`) with their "
                    "partial-fraction coefficients left as cancelled rational functions: "
                    "factoring and printing them would slow `make derive` for little "
                    "reading value. Each response is a combination of "
                    + ", ".join(f"sin/cos({m.name})" for m in a.modes if m.symbol is not None)
                    + " and polynomials in t (integrators). Evaluate them with "
                    f"`ins_errors.numeric.closed_forms.closed_forms({model!r}, latitude)"
                    ".responses(t)`.", ""]
            continue
        out += ["### Time responses to each error source", "",
                "For each source, the error states not listed stay identically zero.", ""]
        for source in d.sources:
            shown = forms.responses[source.name]
            kind = "constant (step at t = 0)" if source.kind == "constant" else "initial error"
            out += [f"#### `{source.name}` (${source.latex}$, {kind})", ""]
            silent = [d.error_states[i].latex for i in range(len(states)) if i not in shown]
            for i, expr in shown.items():
                out += [f"$$ {d.error_states[i].latex}(t) = {source.latex}\\,\\left("
                        f"{to_latex(expr, names)}\\right) $$", ""]
            if silent:
                out += ["Identically zero: " + ", ".join(f"${x}(t)$" for x in silent) + ".",
                        ""]
    return "\n".join(out) + "\n"


_CHECKS = '''
def _check_arguments(function, x, u, p, t=None):
    """Refuse what the closed forms were not derived for: ValueError, one line."""
    if t is not None and not _np.all(_np.isfinite(t) & (t >= 0)):
        bad = float(t[~(_np.isfinite(t) & (t >= 0))].flat[0])
        raise ValueError(f"{function}: the closed forms hold for finite times t >= 0, "
                         f"got t = {bad!r}")
    for name, value in BAKED.items():
        given = p[_BAKED_INDEX[name]]
        wrong = ~(_np.abs(given - value) <= 1e-12 * abs(value))
        if _np.any(wrong):
            bad = float(_np.broadcast_to(given, wrong.shape)[wrong].flat[0])
            raise ValueError(f"{function}: derived for {name} = {value!r} only "
                             f"({_BAKED_MEANING[name]}), got {name} = {bad!r}")
    margins = _domain_margins(x, u, p)
    for k, message in enumerate(_DOMAIN):
        if not _np.all(margins[k] > 0):
            raise ValueError(f"{function}: {message}")
'''


_EVALUATE = '''
def _evaluate(function, variant, t, x, u, p):
    """The closed forms of ``variant`` at (t, x, u, p) (arguments already checked).

    The general forms, and each limit's own forms (LIMITS) at the points where the
    denominator that vanishes there is within the limit's width of zero; ValueError
    (one line) where the result is still not finite: a denominator of the forms
    vanishes (DENOMINATORS) with no limit derived for it.
    """
    general, margins, limits, denominators = _FORMS[variant]
    with _np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = general(t, x, u, p)
        if limits:
            near = _np.abs(margins(x, u, p))
            for k, (width, forms) in enumerate(limits):
                if _np.any(near[k] <= width):
                    out = _np.where(near[k] <= width, forms(t, x, u, p), out)
        if _np.all(_np.isfinite(out)):
            return out
        values = denominators(x, u, p)
    zero = [name for name, value in zip(DENOMINATORS[variant], values)
            if _np.any(value == 0) or not _np.all(_np.isfinite(value))]
    if zero:
        raise ValueError(f"{function}: the closed forms divide by {', '.join(zero)}, "
                         "zero at this point, where no limiting form is derived (e.g. a "
                         "Schuler frequency equal to the Earth rate)")
    raise ValueError(f"{function}: the closed forms overflow at this point")
'''


def _baked_meaning(name: str, value: float) -> str:
    if name in ("e2", "ecc2") and value == 0:
        return "a spherical Earth"
    return "the value fixed before the analysis"


def closed_form_module(model: str, results: list[VariantResult]) -> str:
    """Source of ``generated/<model>/closed_forms.py``.

    Every function refuses (ValueError, one line naming the value) times t < 0 or not
    finite, parameters other than the ``BAKED`` values the closed forms were derived
    for, and points outside the model's domain (a latitude at a pole, R <= 0, ...) or
    the static base's (:attr:`StaticSetup.conditions`).
    """
    d = definition(model)
    t_arg = Argument("t", [T], "time since the start, s (shape (1, ...)), finite, >= 0")
    x_arg = Argument("x", d.x, "static-base state (only the position matters), SI units")
    u_arg = Argument("u", d.u, "static-base inputs (only the vertical specific force "
                               "matters, where it is an input), SI units")
    p_arg = Argument("p", d.p, "model parameters, SI units; those in BAKED must have "
                               "their BAKED values")
    setup = _setup(model)
    checked = ("Raises ValueError (one line) for parameters other than BAKED and outside\n"
               "    the model's domain (e.g. a latitude at a pole){}.")
    src = [_header(model, markdown=False),
           f'"""Closed-form static-base responses of the model {model!r} (numpy, broadcasting).'
           '\n\nresponses_<variant>(t, x, u, p)[i, j, ...] is error state i at time t for a '
           'unit error source j\n(SI), every other source zero. frequencies_<variant>(x, u, p)'
           ' are the mode frequencies,\nrad/s, in the order of MODES[<variant>]. BAKED: '
           'parameter values the closed forms\nwere derived for; every function refuses '
           '(ValueError) other values, times t < 0\nand points outside the model\'s domain '
           '(a latitude at a pole, ...).\n\nThe checked way in, which builds the static-base '
           'x, u and p from a latitude:\nins_errors.numeric.closed_forms.closed_forms(model, '
           'latitude).responses(t)."""', NUMPY_PRELUDE]
    variants, modes = [], {}
    trees = SharedTrees()
    conditions = [*d.domain, *setup.conditions]
    margins = FunctionSpec("_domain_margins", [x_arg, u_arg, p_arg],
                           sp.Matrix([expr for expr, _ in conditions] or [1]),
                           "Margins of the model's domain and the static base's "
                           "conditions (> 0: inside).", "one margin per entry of _DOMAIN")
    src.append("\n" + emit_numpy_function(prepare(margins, trees)) + "\n")
    src += [_CHECKS, _EVALUATE]

    def checked_function(spec: FunctionSpec) -> str:
        text = emit_numpy_function(prepare(spec, trees))
        t = "t" if spec.arguments[0] is t_arg else "None"
        return text.replace("    _batch = ", f"    _check_arguments({spec.name!r}, x, u, p, "
                            f"{t})\n    _batch = ", 1)

    def emitted(spec: FunctionSpec) -> str:
        return "\n" + emit_numpy_function(prepare(spec, trees)) + "\n"

    def responses(a: StaticAnalysis, sources: list[str]) -> sp.Matrix:
        matrix = sp.Matrix.hstack(*[a.responses[s] for s in sources])
        return matrix.applyfunc(lambda e: a.in_model_symbols(e, trees))

    forms, denominators, limits_record = [], {}, {}
    arguments = [t_arg, x_arg, u_arg, p_arg]
    vanishing = (", for times t < 0, and where a\n    denominator of the forms vanishes "
                 "with no limiting form derived for it\n    (DENOMINATORS, LIMITS)")
    for result in results:
        a = result.analysis
        name = result.variant.name
        variants.append(name)
        spec = FunctionSpec(f"responses_{name}", arguments,
                            sp.zeros(len(d.error_states), len(result.sources)),
                            f"Closed-form responses of variant {name!r}: unit source -> "
                            f"error state.\n\n    {checked.format(vanishing)}",
                            "error state i for unit source j", matrix=True)
        wrapper = emit_numpy_function(prepare(spec, trees))
        head = wrapper[:wrapper.index("    _batch = ")]
        src.append(f"\n{head}    _check_arguments({spec.name!r}, x, u, p, t)\n"
                   f"    return _evaluate({spec.name!r}, {name!r}, t, x, u, p)\n")
        src.append(emitted(FunctionSpec(
            f"_forms_{name}", arguments, responses(a, result.sources),
            f"The general closed forms of variant {name!r} (unchecked: see "
            f"responses_{name}).", "error state i for unit source j", matrix=True)))
        limits = []
        for limit, at in zip(result.variant.limits, result.limits, strict=True):
            src.append(emitted(FunctionSpec(
                f"_forms_{name}_{limit.name}", arguments, responses(at, result.sources),
                f"The closed forms of variant {name!r} derived at the {limit.name} "
                f"(unchecked: see responses_{name}).", "error state i for unit source j",
                matrix=True)))
            limits.append(f"({limit.width!r}, _forms_{name}_{limit.name})")
        shown: dict[str, sp.Expr] = {}  # the general forms' factors, then the limits'
        for analysis in (a, *result.limits):
            for factor in analysis.denominators:
                value = analysis.in_model_symbols(
                    analysis.parametrisation.to_model(factor, trees), trees)
                shown.setdefault(f"{factor} = {value}" if value != factor else str(factor),
                                 value)
        denominators[name] = tuple(shown)
        src.append(emitted(FunctionSpec(
            f"_denominators_{name}", [x_arg, u_arg, p_arg], sp.Matrix(list(shown.values())),
            f"The factors the closed forms of variant {name!r} (and its limits') divide "
            "by.", "one value per entry of DENOMINATORS[variant]")))
        margins_name = "None"
        if result.variant.limits:
            margins_name = f"_limit_margins_{name}"
            src.append(emitted(FunctionSpec(
                margins_name, [x_arg, u_arg, p_arg],
                sp.Matrix([a.in_model_symbols(a.parametrisation.to_model(
                    limit.factor / limit.scale, trees), trees)
                    for limit in result.variant.limits]),
                f"Per limit of variant {name!r}: its vanishing factor over its scale "
                "(its forms are taken where this is within the limit's width of 0).",
                "one margin per limit")))
        limits_record[name] = {limit.name: f"{limit.factor}/{limit.scale} within "
                                            f"{limit.width:g} of 0"
                               for limit in result.variant.limits}
        forms.append(f"    {name!r}: (_forms_{name}, {margins_name}, ("
                     + "".join(f"{x}, " for x in limits) + f"), _denominators_{name}),")
        oscillators = [m for m in a.modes if m.symbol is not None]
        modes[name] = tuple(m.name for m in oscillators)
        freq = sp.Matrix([a.in_model_symbols(a.parametrisation.to_model(m.symbol, trees), trees)
                          for m in oscillators])
        spec = FunctionSpec(f"frequencies_{name}", [x_arg, u_arg, p_arg], freq,
                            f"Mode frequencies of variant {name!r}, rad/s.\n\n    "
                            f"{checked.format('')}",
                            "one frequency per entry of MODES")
        src.append("\n" + checked_function(spec) + "\n")
    parameters = [q.name for q in d.parameters]
    baked_index = {k: parameters.index(k) for k in setup.baked}
    meaning = {k: _baked_meaning(k, v) for k, v in setup.baked.items()}
    src.append(f"\nVARIANTS = {tuple(variants)!r}\nMODES = {modes!r}\n"
               f"SOURCES = {tuple(s.name for s in d.sources)!r}\n"
               f"BAKED = {setup.baked!r}\n"
               f"ERROR_STATES = {tuple(s.name for s in d.error_states)!r}\n"
               f"_BAKED_INDEX = {baked_index!r}\n_BAKED_MEANING = {meaning!r}\n"
               f"_DOMAIN = {tuple(message for _, message in conditions)!r}\n"
               f"DENOMINATORS = {denominators!r}\n"
               f"LIMITS = {limits_record!r}\n"
               "_FORMS = {\n" + "\n".join(forms) + "\n}\n")
    return "\n".join(src)


def model_files(model: str) -> dict[str, str]:
    """File name -> text of the two generated files of one model."""
    results = static_analyses(model)
    return {"transfer_functions.md": _header(model, markdown=True) + "\n"
            + markdown(model, results),
            "closed_forms.py": closed_form_module(model, results)}


def write_transfer_functions(root: Path, model: str) -> None:
    """Write both files of ``model`` (one with a static setup) under ``root/<model>/``."""
    folder = root / model
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in model_files(model).items():
        (folder / name).write_text(text, encoding="utf-8")
