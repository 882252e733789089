"""How a researcher's symbols map to a model's names (the hand checker's notation).

A hand-written derivation uses its own symbols: the lab manual of source 000 writes
radii ``R_ξ`` where the model uses reciprocals ``1/R_ξ``, one accelerometer error ``Δa``
for both channels, one drift ``ω_dp`` for all three gyros, the Earth-rate components
``U_ξ = U u11``, and direction cosines ``u13, u23`` the model never integrates. A
:class:`Notation` says what each such symbol means in model terms:

* ``aliases``: hand name -> expression in the model's names (ideal quantities). The
  variation of an alias follows by the chain rule, so ``Delta_R_eta`` means
  ``-Delta_inv_R_eta / inv_R_eta**2`` without any extra entry.
* ``sources``: hand error-source symbol -> the model's error sources it stands for; on the
  model side every listed source is set equal to the hand symbol (``Delta_a`` is
  ``accel_bias_x`` in the ξ channel and ``accel_bias_y`` in the η channel).
* ``spellings``: alternative ASCII spellings -> the canonical one (``w_xi`` ->
  ``omega_xi``, ``lambda`` -> ``lam``).
* ``latex_primes``: what a prime means on a LaTeX base letter (``\\omega'`` is the
  relative rate ``omega_rel``, ``g'`` the gravitation projection ``g``).

The names of every model come from its definition (:func:`model_notation`): each state,
error state, input, parameter, error source, output and intermediate quantity is known by
its name and by its LaTeX spelling (``\\delta v_E``, ``\\Omega``, ``\\nabla_E``), so a new
model needs no checker code. A source document's own notation (the manual's
``ORTHODROMIC`` table) comes on top, then a mapping file (``@alias`` / ``@source``
lines, see ``docs/hand_check.md``), then the hand file's own directives.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import sympy as sp

if TYPE_CHECKING:
    from ins_errors.modeling import ModelDefinition


@dataclass
class Notation:
    """Symbol mapping between a hand derivation and a model (see module docstring)."""

    aliases: dict[str, str] = field(default_factory=dict)
    sources: dict[str, tuple[str, ...]] = field(default_factory=dict)
    spellings: dict[str, str] = field(default_factory=dict)
    latex_primes: dict[str, str] = field(default_factory=dict)
    true_states: dict[str, TrueState] = field(default_factory=dict)

    def merged(self, other: Notation) -> Notation:
        """This notation with ``other``'s entries added (``other`` wins on conflicts)."""
        return Notation(
            aliases={**self.aliases, **other.aliases},
            sources={**self.sources, **other.sources},
            spellings={**self.spellings, **other.spellings},
            latex_primes={**self.latex_primes, **other.latex_primes},
            true_states={**self.true_states, **other.true_states},
        )


@dataclass(frozen=True)
class TrueState:
    r"""A state of the model whose rate is not an error equation: ``dot(V)`` of a hand
    file is the true velocity's rate, where an error equation has ``dot(Delta_V)``.

    Attributes
    ----------
    error : str
        The model's name of its error (``delta_V``).
    latex : str
        The state's LaTeX (``V``, ``\varphi``).
    error_latex : str
        The error's LaTeX (``\delta V``).
    """

    error: str
    latex: str
    error_latex: str


_AXES = ("xi", "eta", "zeta")


def _rate_spellings() -> dict[str, str]:
    """``w_xi``, ``omega_xi_rel``, ``w_rel_xi``, ... -> ``omega_xi`` / ``omega_rel_xi``."""
    spellings: dict[str, str] = {}
    for axis in _AXES:
        spellings[f"w_{axis}"] = f"omega_{axis}"
        for spelling in (f"omega_{axis}_rel", f"w_{axis}_rel", f"w_rel_{axis}",
                         f"omega_{axis}_p", f"omegap_{axis}"):
            spellings[spelling] = f"omega_rel_{axis}"
    for axis in ("N", "E"):
        spellings[f"w_{axis}"] = f"omega_{axis}"
    return spellings


ORTHODROMIC = Notation(
    aliases={
        # radii of curvature: the model keeps their reciprocals
        "R_xi": "1/inv_R_xi",
        "R_eta": "1/inv_R_eta",
        "R_o": "1/inv_R_o",
        # Earth-rate components along the trihedron (u_ξ, u_η, u_ζ of the manual)
        "U_xi": "U*u11",
        "U_eta": "U*u21",
        "U_zeta": "U*u31",
        # the direction cosines obtained from cross products (u33 is a model name)
        "u13": "u21*u32 - u22*u31",
        "u23": "u31*u12 - u11*u32",
        # eccentricity (the manual writes e^2)
        "e": "sqrt(e2)",
    },
    sources={
        "Delta_a": ("accel_bias_x", "accel_bias_y"),
        "omega_dp": ("gyro_drift_x", "gyro_drift_y", "gyro_drift_z"),
    },
    spellings={
        "lambda": "lam",
        "varphi": "phi",
        "W_xi_nk": "W_xi",
        "W_eta_nk": "W_eta",
        "g_p_xi": "g_xi",
        "g_p_eta": "g_eta",
        "u_xi": "U_xi",
        "u_eta": "U_eta",
        "u_zeta": "U_zeta",
        "w_dp": "omega_dp",
        **_rate_spellings(),
    },
    latex_primes={"omega": "omega_rel", "g": "g"},
)

NORTH_POINTING = Notation(aliases={"R_E": "r_E - h", "R_N": "r_N - h"})
"""north_pointing names the radii with the height added (``r_E`` = R_E + h, as its
error_equations.md writes them); a paper's R_E and R_N are these less h."""

NOTATIONS: dict[str, Notation] = {"orthodromic": ORTHODROMIC,
                                  "north_pointing": NORTH_POINTING}
"""Notation of each model's source document, on top of the model's own names."""


def _latex_name(latex: str) -> str | None:
    """Symbol name the checker's LaTeX reader gives ``latex`` (None if not one symbol)."""
    from ins_errors.checker.parse import parse_latex_expression

    try:
        expr, _ = parse_latex_expression(latex, Notation())
    except Exception:
        return None
    return expr.name if isinstance(expr, sp.Symbol) else None


def _squared_name(latex: str) -> str | None:
    """``x`` if ``latex`` reads as ``x**2`` (``e^{2}``), else None."""
    from ins_errors.checker.parse import parse_latex_expression

    try:
        expr, _ = parse_latex_expression(latex, Notation())
    except Exception:
        return None
    if expr.is_Pow and expr.exp == 2 and expr.base.is_Symbol:
        return expr.base.name
    return None


def model_notation(d: ModelDefinition) -> Notation:
    """The names a hand file may use for model ``d``, from its definition alone.

    Every model name is accepted as it is; a LaTeX spelling that reads as a different
    symbol (``\\delta v_E`` -> ``Delta_v_E``, ``\\Omega`` -> ``Omega``) becomes a spelling
    of the model name, and a parameter written as a square (``e^{2}`` for ``ecc2``) gives
    an alias for its root (``e = sqrt(ecc2)``).
    """
    names = {v.name for group in (d.states, d.error_states, d.inputs, d.parameters,
                                  d.sources, d.outputs) for v in group}
    from ins_errors.symbolic.variation import output_mechanisations

    true_mech = output_mechanisations(d)[0]
    names |= {df.symbol.name for mech in (d.ideal, true_mech) for df in mech.definitions}
    spellings: dict[str, str] = {}
    aliases: dict[str, str] = {}
    variables = [*d.error_states, *d.states, *d.inputs, *d.parameters, *d.sources,
                 *d.outputs]
    entries = [(v.name, v.latex) for v in variables]
    entries += [(df.symbol.name, df.latex) for mech in (d.ideal, true_mech)
                for df in mech.definitions]
    for name, latex in entries:
        spelled = _latex_name(latex)
        if spelled and spelled != name and spelled not in names:
            spellings.setdefault(spelled, name)
        root = _squared_name(latex)
        if root and root not in names:
            aliases.setdefault(root, f"sqrt({name})")
    others = {v.name for group in (d.error_states, d.sources) for v in group}
    true_states = {v.name: TrueState(e.name, v.latex, e.latex)
                   for v, e in zip(d.states, d.error_states, strict=False)
                   if v.name not in others and v.name not in spellings}
    return Notation(aliases=aliases, spellings=spellings, true_states=true_states)


_MODEL_NOTATIONS: dict[int, tuple] = {}


def _definition(model: str | ModelDefinition) -> ModelDefinition:
    """A model definition from a built-in name, model file or entry point (or itself)."""
    if not isinstance(model, str):
        return model
    from ins_errors.model_lookup import definition_of, resolve

    return definition_of(resolve(model))


def default_notation(model: str | ModelDefinition) -> Notation:
    """The notation of ``model``: its own names, then its source document's notation."""
    d = _definition(model)
    cached = _MODEL_NOTATIONS.get(id(d))
    if cached is None or cached[0] is not d:
        cached = (d, model_notation(d))
        _MODEL_NOTATIONS[id(d)] = cached
    return cached[1].merged(NOTATIONS.get(d.name, Notation()))


def names_table(model: str | ModelDefinition) -> list[tuple[str, str, str]]:
    """(kind, name, LaTeX) of every name a hand file may use for ``model``.

    Hand spellings from the notation are listed as kind ``spelling`` with the model
    name they stand for in place of the LaTeX.
    """
    d = _definition(model)
    rows = []
    for kind, group in (("error state", d.error_states), ("state", d.states),
                        ("input", d.inputs), ("parameter", d.parameters),
                        ("error source", d.sources), ("output", d.outputs)):
        rows += [(kind, v.name, v.latex) for v in group]
    rows += [("intermediate", df.symbol.name, df.latex) for df in d.ideal.definitions]
    notation = default_notation(d)
    rows += [("spelling", k, v) for k, v in sorted(notation.spellings.items())]
    rows += [("alias", k, v) for k, v in sorted(notation.aliases.items())]
    rows += [("source group", k, ", ".join(v)) for k, v in sorted(notation.sources.items())]
    return rows
