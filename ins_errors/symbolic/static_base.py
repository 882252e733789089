r"""Static-base analyses of each model: the point, the parametrisation, the variants.

On a static base the error equations of every model have constant coefficients, and
:mod:`ins_errors.symbolic.analytic` gives their transfer functions, modes and
closed-form responses. What is model-specific lives here:

* the static-base point (zero ground velocity, consistent true inputs, sphere);
* a :class:`~ins_errors.symbolic.analytic.Parametrisation` in which the characteristic
  polynomial splits into s and s² + ω² factors: Earth-rate components
  Ω_N = Ω cos φ, Ω_U = Ω sin φ, Schuler frequency ω_s = √(g/R), and for the full
  north-pointing model the Foucault-split pair ω± = ω̄ ± Ω_U with ω̄ = √(ω_s² + Ω_U²)
  (the roots of (s² + ω_s²)² + 4Ω_U² s²);
* the variants: the full model and the named simplifications
  (:mod:`ins_errors.symbolic.simplifications`);
* a variant's :class:`Limit` points, where a denominator of its general closed forms
  vanishes inside the domain (the orthodromic forms divide by Ω_U, zero at the
  equator): the analysis repeated there with the point substituted first.

:func:`static_analyses` runs them; ``derive/transfer_functions.py`` prints the results to
``generated/<model>/transfer_functions.md`` and ``generated/<model>/closed_forms.py``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache

import sympy as sp

from ins_errors.errors import unknown_name
from ins_errors.modeling import ModelDefinition
from ins_errors.models import definition
from ins_errors.symbolic.analytic import (
    AnalysisError,
    Frequency,
    Parametrisation,
    StaticAnalysis,
    analyse,
    factor_lists_remembered,
)
from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.simplifications import DroppedTerm, simplification
from ins_errors.symbolic.variation import last_varied

OMEGA_N = sp.Symbol("Omega_N", positive=True)
"""Ω_N = Ω cos φ, rad/s."""
OMEGA_U = sp.Symbol("Omega_U", positive=True)
"""Ω_U = Ω sin φ, rad/s (also the Foucault rate)."""
OMEGA_S = sp.Symbol("omega_s", positive=True)
"""Schuler frequency √(g/R), rad/s."""
OMEGA_BAR = sp.Symbol("omega_bar", positive=True)
"""ω̄ = √(ω_s² + Ω_U²), rad/s: mean of the Foucault-split Schuler pair."""
OMEGA_PLUS = sp.Symbol("omega_plus", positive=True)
"""ω₊ = ω̄ + Ω_U, rad/s."""
OMEGA_MINUS = sp.Symbol("omega_minus", positive=True)
"""ω₋ = ω̄ − Ω_U, rad/s."""

LATEX = {OMEGA_N: r"\Omega_N", OMEGA_U: r"\Omega_U", OMEGA_S: r"\omega_s",
         OMEGA_BAR: r"\bar\omega", OMEGA_PLUS: r"\omega_+", OMEGA_MINUS: r"\omega_-"}
"""LaTeX of the parametrisation symbols."""


@dataclass
class Limit:
    """A static point where a denominator of a variant's closed forms vanishes, analysed
    on its own.

    The general closed forms divide by the partial-fraction denominators of the
    parametrisation (e.g. ω₊² − ω₋² = 4ω̄Ω_U). Where one of them vanishes inside the
    domain (Ω_U = Ω sin φ at the equator, where the Foucault-split pair becomes one
    double Schuler pair) the responses themselves stay finite (F has no Jordan block
    there), but the general forms evaluate 0/0. The analysis is run again with the
    point substituted before the partial fractions: the limit's own closed forms, which
    the generated ``responses_<variant>`` takes where the factor is within ``width`` of
    zero (relative to ``scale``).

    Attributes
    ----------
    name : str
        E.g. ``"equator"``; the generated forms are ``_forms_<variant>_<name>``.
    substitution : dict
        Applied to the values of the setup's ``point`` and ``initial_point`` (e.g.
        φ → 0).
    parametrisation : Parametrisation
        Of the analysis at that point.
    factor : sympy.Expr
        The denominator factor of the general forms that vanishes there, in the general
        parametrisation's symbols (checked to be one of them when derived).
    scale : sympy.Expr
        Its natural size (e.g. Ω for Ω_U = Ω sin φ): the forms switch where
        |factor/scale| <= ``width``.
    width : float
        Where the limit's forms replace the general ones. Near the orthodromic equator
        the general forms keep every response to 4e-12 of its own size down to
        |sin φ| = 1e-150 (below, terms in sin² φ underflow, and below 1e-290 the forms
        overflow); the limit's forms are the φ → 0 limit, off only in the responses
        that vanish at the equator (0 instead of a size ∝ sin φ, below 1e-150 of the
        others).
    description : str
        One sentence for the documents.
    """

    name: str
    substitution: dict[sp.Symbol, sp.Expr]
    parametrisation: Parametrisation
    factor: sp.Expr
    scale: sp.Expr
    width: float
    description: str


@dataclass
class Variant:
    """One static-base error model of a model: full, or with a simplification applied.

    Attributes
    ----------
    name : str
        ``"full"`` or the simplification's name.
    title : str
    parametrisation : Parametrisation
    simplification : str or None
        Name in :data:`~ins_errors.symbolic.simplifications.SIMPLIFICATIONS`.
    factored : bool
        Factor every partial-fraction coefficient (readable, slower); False leaves them
        as cancelled rational functions (used where factoring would slow ``make derive``).
    limits : list of Limit
        Points inside the domain where a denominator of the general closed forms
        vanishes, each analysed on its own.
    """

    name: str
    title: str
    parametrisation: Parametrisation
    simplification: str | None = None
    factored: bool = True
    limits: list[Limit] = field(default_factory=list)


@dataclass
class StaticSetup:
    """A model's static base and the variants analysed there.

    Attributes
    ----------
    model : str
    point : dict
        Substitution of states, inputs and parameters that defines the static base
        (symbols left free, e.g. the latitude, stay free in the results).
    description : str
        One paragraph for the documents.
    variants : list of Variant
    initial_point : dict
        Substitution of the initial conditions ``c`` (for the initial-error matrix).
    print_resolvent : bool
        List the resolvent entries in the document (off for large models).
    baked : dict
        Parameter name -> value substituted before the analysis (numeric-parameter
        substitution where a fully symbolic analysis is too slow); the closed forms hold
        only for these values, and the generated functions refuse others.
    conditions : list of (sympy.Expr, str)
        Static-base conditions beyond the model's domain, as the model's ``domain``:
        a margin in the state, input and parameter symbols (> 0 where it holds) and the
        message the generated closed forms raise when it does not.
    display_point : dict or None
        The static point with the ``baked`` parameters left as symbols, for the F the
        documents print (None: ``point``, which then has no numbers in their place).
    """

    model: str
    point: dict[sp.Symbol, sp.Expr]
    description: str
    variants: list[Variant] = field(default_factory=list)
    initial_point: dict[sp.Symbol, sp.Expr] = field(default_factory=dict)
    baked: dict[str, float] = field(default_factory=dict)
    print_resolvent: bool = True
    conditions: list[tuple[sp.Expr, str]] = field(default_factory=list)
    display_point: dict[sp.Symbol, sp.Expr] | None = None


@dataclass
class VariantResult:
    """A variant analysed: the analysis, the terms its simplification dropped and the
    analysis at each of its :class:`Limit` points (in the order of ``variant.limits``)."""

    variant: Variant
    analysis: StaticAnalysis
    dropped: list[tuple[DroppedTerm, sp.Expr]]
    sources: list[str]
    limits: list[StaticAnalysis] = field(default_factory=list)


# --------------------------------------------------------------------------------------
# north_pointing
# --------------------------------------------------------------------------------------
def _north_pointing() -> StaticSetup:
    d = definition("north_pointing")
    sym = {v.name: v.symbol for v in (*d.states, *d.inputs, *d.parameters)}
    phi, R, U, g = sym["phi"], sym["R"], sym["U"], sym["g"]
    point = {sym["V_E"]: 0, sym["V_N"]: 0, sym["a_E"]: 0, sym["a_N"]: 0, sym["h"]: 0,
             sym["ecc2"]: 0}

    def earth_components(e: sp.Expr) -> sp.Expr:
        e = e.subs(sp.tan(phi), sp.sin(phi) / sp.cos(phi))
        return e.subs({sp.sin(phi): OMEGA_U / U, sp.cos(phi): OMEGA_N / U})

    def reduced_rewrite(e: sp.Expr) -> sp.Expr:
        return earth_components(e).subs(g, R * OMEGA_S**2)

    def full_rewrite(e: sp.Expr) -> sp.Expr:
        return earth_components(e).subs({g: R * (OMEGA_BAR**2 - OMEGA_U**2)})

    base = {OMEGA_N: U * sp.cos(phi), OMEGA_U: U * sp.sin(phi)}
    earth = Frequency(U, OMEGA_N**2 + OMEGA_U**2, "Earth")
    reduced = Parametrisation(
        reduced_rewrite, {**base, OMEGA_S: sp.sqrt(g / R)},
        (Frequency(OMEGA_S, OMEGA_S**2, "Schuler"), earth),
        "Ω_N = Ω cos φ, Ω_U = Ω sin φ, ω_s = √(g/R)")
    full = Parametrisation(
        full_rewrite,
        {OMEGA_PLUS: OMEGA_BAR + OMEGA_U, OMEGA_MINUS: OMEGA_BAR - OMEGA_U,
         OMEGA_BAR: sp.sqrt(g / R + OMEGA_U**2), **base},
        (Frequency(OMEGA_PLUS, (OMEGA_BAR + OMEGA_U) ** 2, "Schuler + Foucault"),
         Frequency(OMEGA_MINUS, (OMEGA_BAR - OMEGA_U) ** 2, "Schuler − Foucault"),
         earth),
        "Ω_N = Ω cos φ, Ω_U = Ω sin φ, ω̄ = √(g/R + Ω_U²), ω± = ω̄ ± Ω_U (Ω_U < 0 south of the "
        "equator, where ω₊ is the lower)")
    return StaticSetup(
        "north_pointing", point,
        "Static base: V_E = V_N = 0, a_E = a_N = 0 (so f_U = g), h = 0, sphere "
        "(ecc2 = 0); the latitude φ stays symbolic.",
        [Variant("full", "Full static-base model (Foucault cross-couplings kept)", full),
         Variant("report_reduced", "Report's reduced model (Foucault cross-couplings "
                 "dropped)", reduced, "report_reduced")],
        baked={"ecc2": 0.0})


# --------------------------------------------------------------------------------------
# orthodromic
# --------------------------------------------------------------------------------------
ORTHODROMIC_RADIUS = 6_378_245
"""Sphere radius of the orthodromic static analysis, m (Krasovsky a, e² = 0)."""
ORTHODROMIC_EARTH_RATE = sp.Rational(7_292_115, 10**11)
"""Earth rate of the orthodromic static analysis, rad/s (NOTES.md)."""
OMEGA_E = sp.Symbol("Omega_E", positive=True)
"""Earth-rate mode frequency of the orthodromic analysis (= the baked U), rad/s."""


def _orthodromic_point(d: ModelDefinition, phi: sp.Symbol, numbers: dict) -> dict:
    """The static point of the orthodromic model with ``numbers`` substituted too."""
    from ins_errors.models.orthodromic import absolute_velocity, direction_cosines

    sym = {v.name: v.symbol for v in (*d.states, *d.inputs, *d.parameters)}
    dc = direction_cosines(phi, 0, 0)
    point = dict(zip((sym[n] for n in ("u11", "u21", "u31", "u12", "u22", "u32")), dc,
                     strict=True))
    velocity = absolute_velocity(dc, 0, 0, 0, 0)
    point[sym["V_xi"]], point[sym["V_eta"]] = (sp.simplify(v.xreplace(numbers))
                                               for v in velocity)
    point.update(numbers)
    # consistent true inputs: the apparent accelerations that keep V constant
    d_ideal = d.ideal_rhs_expanded().xreplace({sym["a_xi"]: 0, sym["a_eta"]: 0})
    d_ideal = d_ideal.xreplace(point)
    point[sym["a_xi"]] = sp.simplify(-d_ideal[6])
    point[sym["a_eta"]] = sp.simplify(-d_ideal[7])
    return point


def _orthodromic() -> StaticSetup:
    d = definition("orthodromic")
    sym = {v.name: v.symbol for v in (*d.states, *d.inputs, *d.parameters)}
    c = {v.name: v.symbol for v in d.initial_conditions}
    phi = sp.Symbol("phi", real=True)
    a_num, U_num = sp.Integer(ORTHODROMIC_RADIUS), ORTHODROMIC_EARTH_RATE
    fixed = {sym["e2"]: 0, sym["h"]: 0, sym["V_zeta"]: 0}
    point = _orthodromic_point(d, phi, {sym["a"]: a_num, sym["U"]: U_num, **fixed})
    a_zeta, a, U = sym["a_zeta"], sym["a"], sym["U"]

    def rewrite(e: sp.Expr) -> sp.Expr:
        e = e.subs(sp.tan(phi), sp.sin(phi) / sp.cos(phi))
        e = e.subs({sp.sin(phi): OMEGA_U / U_num, sp.cos(phi): OMEGA_N / U_num})
        return e.subs(a_zeta, a_num * (OMEGA_BAR**2 - OMEGA_U**2))

    u11, u31 = sym["u11"], sym["u31"]
    full = Parametrisation(  # definitions in a and U: the closed forms refuse other values
        rewrite,
        {OMEGA_PLUS: OMEGA_BAR + OMEGA_U, OMEGA_MINUS: OMEGA_BAR - OMEGA_U,
         OMEGA_BAR: sp.sqrt(a_zeta / a + OMEGA_U**2), OMEGA_N: U * u11,
         OMEGA_U: U * u31, OMEGA_E: U},
        (Frequency(OMEGA_PLUS, (OMEGA_BAR + OMEGA_U) ** 2, "Schuler + Foucault"),
         Frequency(OMEGA_MINUS, (OMEGA_BAR - OMEGA_U) ** 2, "Schuler − Foucault"),
         Frequency(OMEGA_E, OMEGA_N**2 + OMEGA_U**2, "Earth")),
        "Ω_N = U cos φ = U u₁₁, Ω_U = U sin φ = U u₃₁ (ξ north), ω̄ = √(a_ζ/a + Ω_U²), "
        "ω± = ω̄ ± Ω_U (Ω_U < 0 south of the equator, where ω₊ is the lower); a and U "
        "fixed to numbers before the analysis")
    equator = Limit(
        "equator", {phi: 0},
        Parametrisation(
            lambda e: e.subs(a_zeta, a_num * OMEGA_S**2),
            {OMEGA_S: sp.sqrt(a_zeta / a), OMEGA_E: U},
            (Frequency(OMEGA_S, OMEGA_S**2, "Schuler"),
             Frequency(OMEGA_E, U_num**2, "Earth")),
            "φ = 0 (Ω_N = U, Ω_U = 0), ω_s = √(a_ζ/a); a and U fixed to numbers"),
        OMEGA_U, OMEGA_E, 1e-150,
        "The general forms divide by Ω_U = U sin φ (ω₊² − ω₋² = 4ω̄Ω_U: the partial "
        "fractions of the Foucault-split pair), which vanishes at the equator, where the "
        "pair becomes one double Schuler pair s² + ω_s² (no Jordan block: the responses "
        "stay finite, but the general forms evaluate 0/0 there). The analysis is "
        "repeated with φ = 0 substituted before the partial fractions, and "
        "`responses_full` takes these forms where |sin φ| ≤ 1e-150 (down to there the "
        "general ones keep every response to 4e-12 of its size).")
    return StaticSetup(
        "orthodromic", point,
        "Static base with the ξ axis north (χ = 0) at longitude 0, height 0, on the "
        f"sphere of radius a = {ORTHODROMIC_RADIUS} m (e² = 0), U = {float(U_num)} rad/s; "
        "V_ξ, V_η are the absolute velocities of the Earth's rotation there and a_ξ, a_η "
        "the consistent apparent accelerations (V̇ = 0); a_ζ ≈ g stays symbolic, as does "
        "the latitude φ. Numeric-parameter substitution: with a and U symbolic the 11×11 "
        "analysis of all 26 sources takes about twice as long, so they are fixed to the "
        "numbers above before the analysis (the documents print them as the symbols a "
        "and U; the generated closed forms refuse other values).",
        [Variant("full", "Orthodromic INS, static base", full, factored=False,
                 limits=[equator])],
        initial_point={c["latitude"]: phi, c["longitude"]: 0, c["heading"]: 0,
                       c["v_N"]: 0, c["v_E"]: 0},
        baked={"a": float(a_num), "U": float(U_num), "e2": 0.0}, print_resolvent=False,
        display_point=_orthodromic_point(d, phi, fixed),
        conditions=[(a_zeta, "the vertical specific force a_zeta (gravity at rest) must "
                     "be positive")])


SETUPS: dict[str, Callable[[], StaticSetup]] = {
    "north_pointing": _north_pointing,
    "orthodromic": _orthodromic,
}
"""Models with a symbolic static-base analysis."""


# --------------------------------------------------------------------------------------
# Running
# --------------------------------------------------------------------------------------
def static_matrices(name: str, point: dict, initial_point: dict | None = None
                    ) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """F, G and the initial-error matrix E at a static point (first order only).

    The same Jacobians as :func:`~ins_errors.symbolic.variation.vary`, without its
    second-order terms (which the static analysis does not need and which dominate
    its cost). Where :func:`~ins_errors.symbolic.variation.vary` has just derived the
    model (``make derive``), its F, G and E at the ideal point are taken and only the
    static point is substituted: the same matrices, without differentiating again.
    """
    d = definition(name)
    at_ideal, no_errors = d.at_ideal(), d.no_errors()
    varied = last_varied(d)
    with SharedTrees().differentiating() as trees:

        def at(m: sp.Matrix, *rules: dict) -> sp.Matrix:
            for rule in rules:
                m = trees.xreplace_matrix(m, rule)
            return m

        if varied is not None:  # the same Jacobians and the same substitutions, in order
            return (at(varied.state_matrix, point), at(varied.source_matrix, point),
                    at(varied.initial_error_matrix, initial_point or {}, point))
        real_rhs = d.real_rhs_expanded()
        F = at(real_rhs.jacobian(d.real_states), at_ideal, no_errors, point)
        G = at(real_rhs.jacobian(d.w), at_ideal, no_errors, point)
        E = at(d.initial_real_state.jacobian(d.w), no_errors, initial_point or {}, point)
    return F, G, E


def source_columns(d: ModelDefinition, G: sp.Matrix, E: sp.Matrix
                   ) -> dict[str, tuple[sp.Matrix, bool]]:
    """Per source: (column, is_step): G's column for constant sources, E's for initial."""
    columns = {}
    for j, source in enumerate(d.sources):
        if source.kind == "constant":
            columns[source.name] = (G[:, j], True)
        else:
            columns[source.name] = (E[:, j], False)
    return columns


@cache
def static_analyses(name: str) -> list[VariantResult]:
    """Analyse every variant of model ``name`` at its static base (cached).

    Raises
    ------
    UnknownNameError
        If ``name`` has no static-base setup.
    """
    if name not in SETUPS:
        raise unknown_name("model with a static-base analysis", str(name), SETUPS)
    setup = SETUPS[name]()
    d = definition(name)
    F, G, E = static_matrices(name, setup.point, setup.initial_point)
    E = E.applyfunc(sp.simplify)
    if E.free_symbols - F.free_symbols:
        raise ValueError(f"{name}: the initial-error matrix depends on {E.free_symbols}; "
                         "closed forms need it constant")
    columns = source_columns(d, G, E)
    results = []
    with factor_lists_remembered():  # the variants share most polynomials they factor
        for variant in setup.variants:
            dropped: list[tuple[DroppedTerm, sp.Expr]] = []
            Fv = F
            if variant.simplification:
                Fv, dropped = simplification(variant.simplification).apply(
                    F, [v.name for v in d.error_states])
            tidy = sp.factor if variant.factored else None
            analysis = analyse(Fv, columns, variant.parametrisation, tidy=tidy)
            limits = [_limit_analysis(name, setup, variant, limit, analysis, tidy)
                      for limit in variant.limits]
            results.append(VariantResult(variant, analysis, dropped, list(columns), limits))
    return results


def _limit_analysis(name: str, setup: StaticSetup, variant: Variant, limit: Limit,
                    general: StaticAnalysis, tidy) -> StaticAnalysis:
    """The analysis of ``variant`` at ``limit``'s point (its simplification applied too).

    Raises
    ------
    AnalysisError
        If the limit's factor is not a denominator of the general forms (a stale limit).
    """
    factors = general.denominators
    if not any(sp.expand(f - limit.factor) == 0 or sp.expand(f + limit.factor) == 0
               for f in factors):
        raise AnalysisError(f"{name}, variant {variant.name}: the limit {limit.name!r} "
                            f"is for the factor {limit.factor}, which no denominator of "
                            f"the general closed forms has (they have {factors})")
    d = definition(name)
    point = {k: sp.sympify(v).subs(limit.substitution) for k, v in setup.point.items()}
    initial = {k: sp.sympify(v).subs(limit.substitution)
               for k, v in setup.initial_point.items()}
    F, G, E = static_matrices(name, point, initial)
    E = E.applyfunc(sp.simplify)
    if variant.simplification:
        F, _ = simplification(variant.simplification).apply(
            F, [v.name for v in d.error_states])
    return analyse(F, source_columns(d, G, E), limit.parametrisation, tidy=tidy)


def setup(name: str) -> StaticSetup:
    """The static-base setup of model ``name``."""
    if name not in SETUPS:
        raise unknown_name("model with a static-base analysis", str(name), SETUPS)
    return SETUPS[name]()
