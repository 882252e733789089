r"""Compare a hand file's real-work lines with the model's real work, to first order.

Real-work lines (``@realwork`` sections, :mod:`ins_errors.checker.parse`) are the
instrument model and the computer as the author wrote them, not error equations:

accelerometer outputs ``a_x``, ``a_y``, ``a_z``
    compared with the platform rotation applied to the true apparent acceleration
    ``(a_ξ, a_η, a_ζ)``: the model's exact rotation
    (:func:`ins_errors.models.platform.on_platform`) expanded to first order in the
    platform angles α, the three the model declares
    (:attr:`~ins_errors.modeling.ModelDefinition.platform_angles`, in the order x, y, z,
    whatever their names; a model without three is not compared). Each coefficient (the
    zero-order part and the coefficient of each α) is compared as a polynomial in the
    accelerations; a wrong coefficient is classed like an error-equation finding
    (omitted, extra, wrong sign, wrong symbol or index, wrong coefficient) and sized at
    the checker's reference points with the typical platform angle.
difference-scheme updates ``X_{k+1} = X_k + τ(...)``
    the increment ``X_{k+1} − X_k`` of an integrated quantity must be proportional to
    the step τ; a term added outside τ (the manual's ``+ g̃' + Δa``) is a rate added to a
    value, a mistake of kind :data:`STEP`. The rate inside τ is not compared with the
    model here (its variation is what the error-equation lines check).

Any other real-work line is listed as not compared.
"""

from __future__ import annotations

from functools import cache, lru_cache

import numpy as np
import sympy as sp

from ins_errors.checker import classify as cl
from ins_errors.checker.extreme import first_largest
from ins_errors.checker.parse import DOT, TILDE, HandEquation, HandFile
from ins_errors.models.platform import on_platform

STEP = "outside the time step"
"""Kind of a finding: a term of a difference-scheme update not multiplied by τ."""

OUTPUTS = ("a_x", "a_y", "a_z")
"""Accelerometer outputs on the platform axes x, y, z."""

ACCELERATIONS = tuple(sp.Symbol(n) for n in ("a_xi", "a_eta", "a_zeta"))
TAU = sp.Symbol("tau")


def platform_angles(d) -> tuple[str, ...]:
    """The names of the platform angles a model declares, x, y, z (rad; empty for a
    strapdown INS): :attr:`~ins_errors.modeling.ModelDefinition.platform_angles`, the
    symbols a hand file's real-work lines use for them (``alpha_x`` or ``alpha_E``, or
    any other name a model gives them)."""
    return tuple(v.name for v in d.platform_angles)


def first_order_outputs(angles: tuple[str, ...]) -> list[sp.Expr]:
    """Platform-axis outputs of the true apparent acceleration, to first order in α.

    Parameters
    ----------
    angles : tuple of 3 str
        Names of the platform angles about x, y, z (rad), e.g. ``("alpha_x", "alpha_y",
        "alpha_z")`` (:func:`platform_angles`).

    Returns
    -------
    list of 3 sympy.Expr
        ``a_x, a_y, a_z`` in terms of ``a_xi, a_eta, a_zeta`` (m/s²) and the angles:
        the exact rotation's Taylor expansion.
    """
    return list(_first_order_outputs(tuple(angles)))


@cache
def _first_order_outputs(angles: tuple[str, ...]) -> tuple[sp.Expr, ...]:
    """:func:`first_order_outputs`, expanded once per process and set of names."""
    symbols = [sp.Symbol(n) for n in angles]
    exact = on_platform(symbols, ACCELERATIONS, "exact")
    zero = dict.fromkeys(symbols, 0)
    return tuple(sp.expand(e.subs(zero) + sum(sp.diff(e, a).subs(zero) * a for a in symbols))
                 for e in exact)


def _by_name(expr: sp.Expr) -> sp.Expr:
    """Plain symbols (no assumptions), so hand and model names meet."""
    return expr.xreplace({s: sp.Symbol(s.name) for s in expr.free_symbols})


@lru_cache(maxsize=1024)
def _split(expr: sp.Expr, angles: tuple[str, ...]) -> dict[str, sp.Expr]:
    """``{"(value)": zero-order part, "alpha_x": its coefficient, ...}`` for the platform
    angles named ``angles`` (a pure function, kept for the next line and check: read
    only)."""
    symbols = [sp.Symbol(n) for n in angles]
    zero = dict.fromkeys(symbols, 0)
    parts = {"(value)": sp.expand(expr.subs(zero))}
    for a in symbols:
        parts[a.name] = sp.expand(sp.diff(expr, a).subs(zero))
    return parts


def _single(expr: sp.Expr) -> tuple[sp.Expr, sp.Symbol] | None:
    """``c*a`` with one acceleration symbol a and a number c, else None."""
    terms = sp.Add.make_args(expr)
    if len(terms) != 1:
        return None
    coefficient, rest = terms[0].as_coeff_Mul()
    return (coefficient, rest) if rest in ACCELERATIONS else None


def _kind(hand: sp.Expr, model: sp.Expr) -> tuple[str, str]:
    if hand == 0:
        return cl.OMITTED, f"the term ({model}) is missing"
    if model == 0:
        return cl.EXTRA, f"the term ({hand}) should not be there"
    if sp.expand(hand + model) == 0:
        return cl.SIGN, "the sign is reversed"
    h, m = _single(hand), _single(model)
    if h and m and h[1] != m[1]:
        sign = "" if h[0] == m[0] else " (and the sign)"
        return cl.SYMBOL, f"{h[1]} written where {m[1]} belongs{sign}"
    ratio = sp.simplify(hand / model)
    if ratio.is_number:
        return cl.COEFFICIENT, f"hand/model = {ratio}"
    return cl.COEFFICIENT, "the coefficient differs"


def _values(points: list, expr: sp.Expr) -> np.ndarray:
    """``expr`` (in the accelerations) at every reference point."""
    names = {s.name: s for s in expr.free_symbols}
    out = []
    for p in points:
        given = {names[k.name]: v for k, v in p.values.items() if k.name in names}
        out.append(float(expr.xreplace(given)) if set(given) == set(names.values())
                   else np.nan)
    return np.array(out)


def check_output(eq: HandEquation, points: list, angle: float, threshold: float,
                 angles: tuple[str, ...]):
    """Findings of one accelerometer-output line.

    Parameters
    ----------
    eq : HandEquation
        ``a_x = ...`` (or a_y, a_z).
    points : list of ReferencePoint
        Where the sizes are evaluated (their values of a_xi, a_eta, a_zeta, m/s²).
    angle : float
        Typical platform angle, rad (the size of an α term).
    threshold : float
        Size separating small effects from mistakes.
    angles : tuple of 3 str
        The model's platform angles about x, y, z (:func:`platform_angles`).

    Returns
    -------
    target : str
    findings : list of Finding
    """
    row = OUTPUTS.index(str(eq.lhs))
    model = first_order_outputs(angles)[row]
    hand = sp.expand(_by_name(eq.forms[0]))
    target = (f"real work: accelerometer output {eq.lhs} (row {row + 1} of the platform "
              "rotation, first order in alpha)")
    h, m = _split(hand, angles), _split(model, angles)
    scale = {"(value)": 1.0, **dict.fromkeys(angles, angle)}
    largest = np.zeros(len(points))
    for key in m:
        for side in (h, m):
            largest = np.maximum(largest, np.nan_to_num(np.abs(_values(points, side[key])))
                                 * scale[key])
    safe = np.where(largest > 0, largest, np.inf)
    findings = []
    for key in m:
        difference = sp.expand(h[key] - m[key])
        if difference == 0:
            continue
        kind, detail = _kind(h[key], m[key])
        ratios = np.nan_to_num(np.abs(_values(points, difference))) * scale[key] / safe
        j = first_largest(ratios) if len(ratios) else 0
        size = float(ratios[j]) if len(ratios) else 1.0
        where = points[j].label if points else "-"
        if size == 0.0:
            detail += " (it vanishes at every reference point)"
        findings.append(cl.Finding(key, kind, cl.severity(kind, size, threshold), size,
                                   where, str(h[key]), str(m[key]), detail))
    return target, findings


def check_step(eq: HandEquation, threshold: float):
    """Findings of one difference-scheme update ``X_{k+1} = X_k + τ(...)``."""
    lhs = eq.lhs
    increment = sp.expand(eq.forms[0] - lhs)
    target = f"real work: difference-scheme update of {lhs} (increment proportional to tau)"
    outside = sp.expand(increment.subs(TAU, 0))
    if TAU not in eq.forms[0].free_symbols:
        return target, [cl.Finding("(time step)", cl.OMITTED, cl.MISTAKE, 1.0, "every step",
                                   str(increment), "tau*(...)", "no time step tau in the "
                                   "update")]
    if outside == 0:
        return target, []
    inside = sp.expand(increment - outside).subs(TAU, 1)
    detail = (f"{outside} is added outside tau: a rate added to a value; the consistent "
              f"reading integrates it, tau*({sp.expand(inside + outside)}); the two agree "
              f"only for a step tau of 1 s (per step the printed form adds "
              f"(1 - tau)*({outside}) more)")
    return target, [cl.Finding("(time step)", STEP, cl.MISTAKE, 1.0, "every step", str(outside),
                               "0", detail)]


def update_variations(hand: HandFile, angles: tuple[str, ...]) -> list[HandEquation]:
    """First-order variations of the real-work updates, as error-equation lines.

    The rate of each update ``X_{k+1} = X_k + τ(...)`` (terms printed outside τ read
    inside) is varied to first order: ``tilde(Y) → Y + ε ΔY``, the model's platform
    angles (``angles``) and ``Delta_*`` error sources scaled by ε, the accelerometer
    outputs replaced by the
    file's own ``a_x``/``a_y`` lines. The ε-coefficient is a line ``dot(Delta_X) = ...``
    that the error-equation comparison checks against the model's variation (with the
    file's definitions of ΔW, Δg', Δω, ... and its declared simplifications).

    Parameters
    ----------
    hand : HandFile
    angles : tuple of str
        Names of the model's platform angles (:func:`platform_angles`; empty for a
        strapdown INS).

    Returns
    -------
    list of HandEquation
        One per update of a ``tilde(X)``, at the update's line and section.
    """
    outputs = {e.lhs: e.forms[0] for e in hand.real_work
               if not e.step and isinstance(e.lhs, sp.Symbol) and e.lhs.name in OUTPUTS}
    lines = []
    for eq in hand.real_work:
        if not (eq.step and eq.lhs.func == TILDE and TAU in eq.forms[0].free_symbols):
            continue
        variation = _varied_rate(eq.forms[0], eq.lhs, tuple(outputs.items()), tuple(angles))
        lines.append(HandEquation(
            line=eq.line, column=eq.column, section=eq.section,
            lhs=DOT(sp.Symbol(f"Delta_{eq.lhs.args[0]}")), forms=[variation],
            text=f"variation of: {eq.text}", note="real-work update, varied to first order",
            columns=eq.columns, declarations=eq.declarations))
    return lines


@lru_cache(maxsize=1024)
def _varied_rate(form: sp.Expr, lhs: sp.Expr, outputs: tuple[tuple[sp.Expr, sp.Expr], ...],
                 angles: tuple[str, ...]) -> sp.Expr:
    """The ε-coefficient of one update's rate (see :func:`update_variations`): a pure
    function of the update, its left side, the file's output lines and the names of the
    platform angles, kept for the next check in the same process."""
    eps = sp.Dummy("epsilon")
    rate = sp.expand(form - lhs).subs(TAU, 1).xreplace(dict(outputs))
    rate = rate.xreplace({s: eps * s for s in rate.free_symbols
                          if s.name in angles or s.name.startswith("Delta_")})
    rate = rate.xreplace({f: f.args[0] + eps * sp.Symbol(f"Delta_{f.args[0]}")
                          for f in rate.atoms(TILDE)})
    return sp.expand(sp.diff(rate, eps).subs(eps, 0))


def check_real_work(hand: HandFile, points: list, angle: float, threshold: float,
                    angles: tuple[str, ...]) -> list:
    """Results of every real-work line of ``hand`` (see the module docstring).

    Parameters
    ----------
    hand : HandFile
    points : list of ReferencePoint
    angle : float
        Typical platform angle, rad.
    threshold : float
    angles : tuple of str
        Names of the model's platform angles, x, y, z (:func:`platform_angles`): the
        accelerometer outputs are compared only for a model with three.

    Returns
    -------
    list of EquationResult
    """
    from ins_errors.checker.compare import EquationResult

    results = []
    for eq in hand.real_work:
        name = str(eq.lhs.args[0] if eq.lhs.func == TILDE else eq.lhs)
        if eq.step:
            target, findings = check_step(eq, threshold)
        elif name in OUTPUTS and eq.lhs.func != TILDE and len(angles) != 3:
            results.append(EquationResult(eq, 0, "real work: not compared", "not compared",
                                          notes=["the model declares no three platform "
                                                 "angles to turn the accelerations by"]))
            continue
        elif name in OUTPUTS and eq.lhs.func != TILDE:
            target, findings = check_output(eq, points, angle, threshold, angles)
        else:
            results.append(EquationResult(eq, 0, "real work: not compared", "not compared",
                                          notes=["only accelerometer outputs and "
                                                 "difference-scheme updates are compared"]))
            continue
        status = ("mistake" if any(f.is_mistake for f in findings) else
                  "agrees up to dropped small terms" if findings else "agrees")
        notes = (["the model's platform carries two accelerometers (x, y): a_z feeds "
                  "nothing, so its mistakes have no effect on the errors"]
                 if name == "a_z" and not eq.step else [])
        results.append(EquationResult(eq, 0, target, status, findings, notes))
    return results
