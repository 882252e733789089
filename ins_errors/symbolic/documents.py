"""Readable Markdown/LaTeX of a model's error equations, grouped the way papers group them."""

from __future__ import annotations

import re

import sympy as sp
from sympy.printing.latex import LatexPrinter

from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.term_order import FastTermOrder
from ins_errors.symbolic.variation import (
    VariedEquation,
    output_mechanisations,
    structured_variation,
)


def latex_symbol_names(d: ModelDefinition, lines: list[VariedEquation]) -> dict[sp.Symbol, str]:
    """LaTeX spelling of every symbol that appears in the structured variation."""
    names = d.latex_names()
    true_mech, _, _, _ = output_mechanisations(d)
    names.update({df.symbol: df.latex for df in true_mech.definitions})
    for line in lines:
        if line.kind == "intermediate":
            names[line.lhs] = line.latex
            names.setdefault(sp.Symbol(line.name, real=True), line.latex.replace(r"\Delta ", "", 1))
    return names


class _LatexPrinter(FastTermOrder, LatexPrinter):
    """SymPy's LaTeX printer, sums ordered by :mod:`~ins_errors.symbolic.term_order`."""


_VARIATION_SIGNS = (r"\delta", r"\Delta")
r"""LaTeX that reads as "the variation of" the symbol after it (the hand checker's, and a
reader's, reading of ``\delta \omega_y``)."""


def to_latex(expr: sp.Expr, names: dict[sp.Symbol, str]) -> str:
    r"""LaTeX of ``expr`` with the model's own notation: ``sp.latex(expr,
    symbol_names=names, mul_symbol=None)``, the same text, except that a symbol spelled
    by a variation sign alone (free_azimuth's azimuth angle δ of source 002) is braced,
    ``{\delta} \omega_y``: the product, not the variation of ω_y, to a reader and to
    ``ins-errors check`` alike."""
    names = {k: f"{{{v}}}" if v in _VARIATION_SIGNS else v for k, v in names.items()}
    return _LatexPrinter({"symbol_names": names, "mul_symbol": None}).doprint(expr)


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(row) + " |" for row in rows]
    return out


_ROLE = re.compile(r":(?:mod|func|class|data|meth|attr):`~?([^`]+)`")


def markdown_text(text: str) -> str:
    """Docstring prose (reStructuredText, where a model's notes are written) for a Markdown
    document: a cross-reference role (``:mod:`ins_errors.models.platform```) becomes the
    code span of its target, which Markdown shows (the role's text was shown literally)."""
    return _ROLE.sub(r"`\1`", text)


def error_equations_markdown(d: ModelDefinition) -> str:
    """The ``error_equations.md`` document of one model."""
    lines = structured_variation(d)
    names = latex_symbol_names(d, lines)
    by_name = {line.name: line for line in lines if line.kind == "state"}
    out = [f"# Error equations of the model `{d.name}`", "",
           f"{d.title}. Source: {d.source}.", "",
           "Derived mechanically by varying the real-work equations around the ideal work "
           "(first order). Each line varies one formula of the mechanisation with respect to "
           f"its direct arguments; Δ marks the difference computed − true{_extra_states(d)}. "
           "Coefficients are ideal-work quantities.", ""]
    if d.notes:
        out += ["## Modelling choices", "", markdown_text(d.notes), ""]
    out += ["## Names", "", "Error states:", ""]
    out += _table(["name", "symbol", "unit", "meaning"],
                  [[f"`{v.name}`", f"${v.latex}$", v.unit, v.description]
                   for v in d.error_states])
    out += ["", "Error sources:", ""]
    factors = any(s.factor for s in d.sources)  # numbers of the source document's list
    out += _table(["name", "symbol", "kind", "unit (SI / quoted in)",
                   *(["manual factor"] if factors else []), "meaning"],
                  [[f"`{s.name}`", f"${s.latex}$", s.kind, f"{s.unit} / {s.display_unit}",
                    *([str(s.factor or "–")] if factors else []), s.description]
                   for s in d.sources])
    out += ["", "## Variations of the intermediate quantities", ""]
    out += _equations([line for line in lines if line.kind == "intermediate"
                       and not _is_output_intermediate(line, d)], names)
    grouped: set[str] = set()
    for title, members in d.groups:
        out += ["", f"## {title}", ""]
        out += _equations([by_name[m] for m in members], names)
        grouped.update(members)
    rest = [line for name, line in by_name.items() if name not in grouped]
    if rest:
        out += ["", "## Other states", ""]
        out += _equations(rest, names)
    output_lines = [line for line in lines if _is_output_intermediate(line, d)
                    or (line.kind == "output" and not line.rhs.is_Symbol)]
    if output_lines:  # models whose outputs are states have nothing to add here
        out += ["", "## Output errors", ""]
        out += _equations(output_lines, names)
    return "\n".join(out) + "\n"


def _extra_states(d: ModelDefinition) -> str:
    """How the introduction names the error states beyond ``Δ<state>``
    (:attr:`~ins_errors.modeling.ModelDefinition.extra_error_states`: platform angles,
    a damping loop's integrators): ", α the platform misalignment" for a model with the
    source documents' small-angle platform variant, each one's symbol and meaning for
    other models, nothing for a model without (a strapdown INS)."""
    extra = d.extra_error_states
    if not extra:
        return ""
    if d.has_small_angle_platform:
        return ", α the platform misalignment"
    return "".join(f", ${v.latex}$ the {v.description}" for v in extra)


def _is_output_intermediate(line: VariedEquation, d: ModelDefinition) -> bool:
    real = {definition.symbol.name[:-2] for definition in d.real.definitions}
    return line.kind == "intermediate" and line.name not in real


def _equations(lines: list[VariedEquation], names: dict[sp.Symbol, str]) -> list[str]:
    out = []
    for line in lines:
        lhs = line.latex
        out.append(f"$$ {lhs} = {to_latex(line.rhs, names)} $$")
        out.append("")
    return out
