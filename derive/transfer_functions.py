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

from pathlib import Path

import sympy as sp

from ins_errors.models import definition
from ins_errors.symbolic.analytic import S, T
from ins_errors.symbolic.codegen import Argument, FunctionSpec, emit_numpy_function, prepare
from ins_errors.symbolic.documents import to_latex
from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.static_base import LATEX, SETUPS, VariantResult, static_analyses

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


def _names(model: str) -> dict[sp.Symbol, str]:
    d = definition(model)
    names = d.latex_names()
    names.update(LATEX)
    names.update({S: "s", T: "t"})
    return names


def _matrix_latex(M: sp.Matrix, names: dict[sp.Symbol, str]) -> str:
    rows = [" & ".join(to_latex(e, names) for e in M.row(i)) for i in range(M.rows)]
    return r"\begin{bmatrix}" + r" \\ ".join(rows) + r"\end{bmatrix}"


def _period_text(result: VariantResult, model: str) -> list[str]:
    names = _names(model)
    par = result.analysis.parametrisation
    rows = []
    for mode in result.analysis.modes:
        if mode.symbol is None:
            rows.append(f"| integrator | $s^{{{mode.multiplicity}}}$ | – | – |")
            continue
        w = to_latex(mode.symbol, names)
        value = (f"${w} = {to_latex(par.to_model(mode.symbol), names)}$"
                 if mode.symbol in par.definitions else f"${w}$ (model parameter)")
        rows.append(f"| {mode.name} | $(s^2 + {w}^2)^{{{mode.multiplicity}}}$ | {value} | "
                    f"$2\\pi/{w}$ |")
    return ["| mode | factor | frequency | period |", "|---|---|---|---|", *rows]


def _mode_product(result: VariantResult) -> sp.Expr:
    """det(sI − F) written as the product of its modes (integrators s, s² + ω²)."""
    a = result.analysis
    product = sp.Poly(a.characteristic, S).LC()
    for mode in a.modes:
        factor = S if mode.symbol is None else S**2 + mode.symbol**2
        product *= sp.Pow(factor, mode.multiplicity, evaluate=False) if mode.multiplicity > 1 \
            else factor
    return product


def _shorten(expr: sp.Expr, modes, trees: SharedTrees) -> sp.Expr:
    """Write each mode's ω² (e.g. Ω_N² + Ω_U²) as its symbol squared (Ω²), for reading.

    ``expr.subs`` (through ``trees``: the same result, each subtree once).
    """
    for mode in modes:
        if mode.symbol is not None and mode.squared.is_Add:
            expr = trees.subs(expr, mode.squared, mode.symbol**2)
    return expr


def markdown(model: str, results: list[VariantResult]) -> str:
    """The ``transfer_functions.md`` document of one model."""
    d = definition(model)
    setup = SETUPS[model]()
    names = _names(model)
    states = [v.name for v in d.error_states]
    trees = SharedTrees()
    out = [f"# Transfer functions and closed-form responses of `{model}` (static base)", "",
           f"{d.title}. Source: {d.source}.", "",
           setup.description, "",
           "Derived mechanically: F, G and the initial-error matrix come from the variation "
           "of the model's real-work equations (see `error_equations.md`), evaluated at the "
           "static base; (sI − F)⁻¹ is exact over the rational functions of the "
           "coefficients; the time responses come from partial fractions in z = s² and the "
           "table 1/(s²+ω²) → sin ωt/ω, s/(s²+ω²) → cos ωt, 1/s^n → t^(n−1)/(n−1)!. Every "
           "response is to a *unit* source (1 in SI units) with every other source zero; "
           "constant sources start at t = 0 (step), initial errors are x(0).", ""]
    for result in results:
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
        shown_F = a.state_matrix.applyfunc(lambda e, par=par: sp.expand(par.to_model(e, trees)))
        delta = _mode_product(result)
        out += ["State matrix at the static base (rows and columns: "
                + ", ".join(f"`{n}`" for n in states) + "):", "",
                f"$$ F = {_matrix_latex(shown_F, names)} $$", "",
                "Characteristic polynomial and its modes:", "",
                f"$$ \\Delta(s) = \\det(sI - F) = {to_latex(delta, names)} $$", "",
                *_period_text(result, model), ""]
        if setup.print_resolvent:
            out += ["### Resolvent (sI − F)⁻¹ = adj(sI − F) / Δ(s)", "",
                    "Entry C_ij is the Laplace transform of error state i for a unit "
                    "initial value of error state j; its numerator adj_ij(s) is listed "
                    "(Δ(s) above).", ""]
        for i, row_name in enumerate(states if setup.print_resolvent else ()):
            for j, col_name in enumerate(states):
                entry = a.adjugate[i, j]
                if entry != 0:
                    numerator = sp.collect(_shorten(entry, a.modes, trees), S)
                    out += [f"$$ \\operatorname{{adj}}_{{{i + 1}{j + 1}}} = "
                            f"[{names[sp.Symbol(row_name, real=True)]} \\leftarrow "
                            f"{names[sp.Symbol(col_name, real=True)]}(0)] = "
                            f"{to_latex(numerator, names)} $$", ""]
        if not result.variant.factored:
            out += ["### Time responses", "",
                    "The closed-form time responses of this variant are emitted to "
                    f"`closed_forms.py` (`responses_{result.variant.name}`) with their "
                    "partial-fraction coefficients left as cancelled rational functions: "
                    "factoring and printing them would slow `make derive` for little "
                    "reading value. Each response is a combination of "
                    + ", ".join(f"sin/cos({m.name})" for m in a.modes if m.symbol is not None)
                    + " and polynomials in t (integrators); the Laplace-domain forms above "
                    "are exact.", ""]
            continue
        out += ["### Time responses to each error source", ""]
        for source in d.sources:
            column = a.responses[source.name]
            kind = "constant (step at t = 0)" if source.kind == "constant" else "initial error"
            out += [f"#### `{source.name}` (${source.latex}$, {kind})", ""]
            for i, state in enumerate(d.error_states):
                if column[i] != 0:
                    out += [f"$$ {state.latex}(t) = {source.latex}\\,\\left("
                            f"{to_latex(_shorten(column[i], a.modes, trees), names)}\\right) $$",
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
    setup = SETUPS[model]()
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
    src.append(_CHECKS)

    def checked_function(spec: FunctionSpec) -> str:
        text = emit_numpy_function(prepare(spec, trees))
        t = "t" if spec.arguments[0] is t_arg else "None"
        return text.replace("    _batch = ", f"    _check_arguments({spec.name!r}, x, u, p, "
                            f"{t})\n    _batch = ", 1)

    for result in results:
        a = result.analysis
        name = result.variant.name
        variants.append(name)
        matrix = sp.Matrix.hstack(*[a.responses[s] for s in result.sources])
        matrix = matrix.applyfunc(lambda e, a=a: a.in_model_symbols(e, trees))
        spec = FunctionSpec(f"responses_{name}", [t_arg, x_arg, u_arg, p_arg], matrix,
                            f"Closed-form responses of variant {name!r}: unit source -> "
                            f"error state.\n\n    {checked.format(', and for times t < 0')}",
                            "error state i for unit source j")
        src.append("\n" + checked_function(spec) + "\n")
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
               f"_DOMAIN = {tuple(message for _, message in conditions)!r}\n")
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
