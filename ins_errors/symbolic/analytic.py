r"""Laplace-domain analysis of a time-invariant linear error model ẋ = F x + G w.

For a static base the error equations have constant coefficients, and everything the
classical texts derive by hand follows mechanically:

* the resolvent (sI − F)⁻¹ (:func:`resolvent`), exact over the field of rational
  functions of the coefficients (SymPy ``DomainMatrix``, fast for sparse F);
* the characteristic polynomial det(sI − F) (:func:`characteristic_polynomial`) and its
  factorisation into integrators ``s`` and undamped oscillators ``s² + ω²``
  (:func:`split_modes`): periods 2π/ω (Schuler, Earth, Foucault-split Schuler);
* closed-form time responses to each initial error (X(s) = (sI − F)⁻¹ x₀) and each
  constant source (X(s) = (sI − F)⁻¹ g / s) by partial fractions in z = s²
  (:func:`inverse_laplace`): a rational X(s) whose poles are all 0 or ±iω splits into
  A(s²) + s B(s²), and the terms c/(s² + ω²)^m, c s/(s² + ω²)^m, c/s^n come from a table
  (sin, cos, t·sin, polynomials in t). This avoids SymPy's general inverse transform.

Trigonometric coefficients make the factorisation fail over the rationals (it needs
sin² + cos² = 1). A :class:`Parametrisation` first rewrites F in symbols in which the
characteristic polynomial splits (e.g. Ω_N = Ω cos φ, Ω_U = Ω sin φ, ω_s² = g/R, or the
two Foucault-split frequencies ω₊, ω₋ with ω₊ω₋ = ω_s², ω₊ − ω₋ = 2Ω_U), and carries the
definitions of those symbols back to the model's own symbols for numerics and documents.
"""

from __future__ import annotations

import contextlib
import functools
import math
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache

import sympy as sp
from sympy.core.mul import _keep_coeff
from sympy.polys.domains import FractionField
from sympy.polys.matrices import DomainMatrix
from sympy.polys.polyerrors import CoercionFailed
from sympy.polys.rings import PolyElement

from ins_errors.errors import InsErrorsError
from ins_errors.symbolic.shared_trees import SharedTrees

S = sp.Symbol("s")
"""Laplace variable."""
T = sp.Symbol("t", nonnegative=True)
"""Time since the start, s."""
Z = sp.Symbol("z")
"""z = s², the variable of the partial fractions."""


class AnalysisError(InsErrorsError):
    """The error model does not have the structure the closed-form analysis needs."""


# --------------------------------------------------------------------------------------
# Parametrisation and modes
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Frequency:
    """A named natural frequency ω > 0 the analysis may find.

    Attributes
    ----------
    symbol : sympy.Symbol
        Positive symbol used in the closed forms (``sin(ω t)``).
    squared : sympy.Expr
        ω² in the parametrisation's symbols (matched against the roots z = −ω²).
    name : str
        ``"Schuler"``, ``"Earth"``, ...
    """

    symbol: sp.Symbol
    squared: sp.Expr
    name: str


@dataclass(frozen=True)
class Parametrisation:
    """Rewrite of the coefficients of F in which det(sI − F) splits over s².

    Attributes
    ----------
    rewrite : callable
        ``rewrite(expr) -> expr`` applied to every entry of F (e.g. sin φ → Ω_U/Ω).
    definitions : mapping
        Each new symbol -> its expression in the model's symbols or in other new symbols
        (for numerics and for the documents).
    frequencies : sequence of Frequency
        The natural frequencies to name; a root that matches none gets ``omega_<k>``
        (and the name ``"mode <k>"``). A frequency symbol that is not a model symbol
        needs an entry in ``definitions``.
    description : str
        One line for the documents.
    """

    rewrite: Callable[[sp.Expr], sp.Expr] = lambda e: e
    definitions: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)
    frequencies: Sequence[Frequency] = ()
    description: str = ""

    def to_model(self, expr: sp.Expr, trees: SharedTrees | None = None) -> sp.Expr:
        """Substitute the definitions (repeatedly), giving ``expr`` in the model's symbols.

        ``trees`` (optional) substitutes each distinct subtree once across calls.
        """
        trees = trees or SharedTrees()
        rule = dict(self.definitions)
        for _ in range(len(self.definitions) + 1):
            if not trees.free_symbols(expr) & rule.keys():
                return expr
            expr = trees.xreplace(expr, rule)
        raise AnalysisError("parametrisation definitions are circular")


@dataclass(frozen=True)
class Mode:
    """One factor of the characteristic polynomial: ``s`` or ``s² + ω²``, to a power.

    Attributes
    ----------
    name : str
        ``"integrator"`` for s, else the frequency's name.
    symbol : sympy.Symbol or None
        ω (None for an integrator).
    squared : sympy.Expr
        ω² in the parametrisation's symbols (0 for an integrator).
    multiplicity : int
        Power of the factor in det(sI − F).
    """

    name: str
    symbol: sp.Symbol | None
    squared: sp.Expr
    multiplicity: int

    @property
    def period(self) -> sp.Expr | None:
        """2π/ω, s (None for an integrator)."""
        return None if self.symbol is None else 2 * sp.pi / self.symbol


# --------------------------------------------------------------------------------------
# Matrices
# --------------------------------------------------------------------------------------
def _domain_matrix(F: sp.Matrix, s: sp.Symbol) -> DomainMatrix:
    return DomainMatrix.from_Matrix(s * sp.eye(F.rows) - F).to_field()


def resolvent(F: sp.Matrix, s: sp.Symbol = S) -> sp.Matrix:
    """(sI − F)⁻¹, every entry a cancelled rational function of ``s``.

    Parameters
    ----------
    F : sympy.Matrix, shape (n, n)
        Constant state matrix (no ``s``, no time).

    Returns
    -------
    sympy.Matrix, shape (n, n)
    """
    _check_square(F)
    return _domain_matrix(F, s).inv().to_Matrix()


def characteristic_polynomial(F: sp.Matrix, s: sp.Symbol = S) -> sp.Expr:
    """det(sI − F), factored (coefficients from SymPy's ``DomainMatrix.charpoly``)."""
    _check_square(F)
    matrix = DomainMatrix.from_Matrix(F).to_field()
    coefficients = matrix.charpoly()
    n = len(coefficients) - 1
    to_sympy = matrix.domain.to_sympy
    return sp.factor(sum(to_sympy(c) * s ** (n - k) for k, c in enumerate(coefficients)))


def _check_square(F: sp.Matrix) -> None:
    if not isinstance(F, sp.MatrixBase):
        raise AnalysisError(f"state matrix must be a SymPy Matrix (sympy.Matrix(F) converts a "
                            f"numpy array), got {type(F).__name__}")
    if F.rows != F.cols:
        raise AnalysisError(f"state matrix must be square, got {F.rows}x{F.cols}")


def _check_oscillating(factor: sp.Expr, squared: sp.Expr) -> None:
    """Refuse a factor s² + ω² unless ω² > 0 follows from the symbols' assumptions.

    ω² < 0 gives real roots ±σ (σ² = −ω²), one growing as exp(σ t); an undecided sign
    may be either, and the sin/cos table would be wrong for one of them.
    """
    if squared.is_positive or sp.factor(squared).is_positive:
        return
    if squared.is_negative or sp.factor(squared).is_negative:
        rate = sp.sqrt(-squared)
        tau = sp.simplify(1 / rate)
        tau_text = f"{float(tau):.6g}" if tau.is_number else str(tau)
        raise AnalysisError(
            f"characteristic factor {factor} has real roots s = ±{rate}: an unstable mode "
            f"growing as exp(t/τ), τ = {tau_text} s; the closed-form table needs roots "
            "0 or ±iω")
    raise AnalysisError(
        f"characteristic factor {factor}: the sign of {squared} is not decided by the "
        "symbols' assumptions (roots ±iω if positive, real and growing if negative): "
        "declare the symbols positive=True")


def split_modes(polynomial: sp.Expr, frequencies: Sequence[Frequency] = (),
                s: sp.Symbol = S) -> list[Mode]:
    """Factor ``polynomial`` into integrators and oscillators ``s² + ω²``.

    Parameters
    ----------
    polynomial : sympy.Expr
        det(sI − F) (or any denominator) in ``s``.
    frequencies : sequence of Frequency
        Named frequencies; each factor s² + a is matched by a − ω² = 0.

    Raises
    ------
    AnalysisError
        If a factor is not ``s`` or ``α s² + β`` (the roots are not 0 or ±iω in the
        given parametrisation), if it is ``s² − σ²`` with σ² > 0 (real roots ±σ: a mode
        growing with time constant 1/σ, named in the message), or if the sign of β in
        ``s² + β`` does not follow from the symbols' assumptions (declare them
        ``positive=True``) and β is not the square of a named frequency.
    """
    _, factors = sp.factor_list(sp.expand(polynomial), s)
    modes: list[Mode] = []
    unnamed = 0
    for factor, power in factors:
        poly = sp.Poly(factor, s)
        if poly.degree() == 0:
            continue
        if poly.degree() == 1 and poly.TC() == 0:
            modes.append(Mode("integrator", None, sp.S.Zero, power))
            continue
        coeffs = poly.all_coeffs()
        if poly.degree() != 2 or coeffs[1] != 0:
            raise AnalysisError(f"characteristic factor {factor} is not s or s² + ω²: "
                                "supply a parametrisation in which it splits")
        squared = sp.cancel(coeffs[2] / coeffs[0])
        match = next((f for f in frequencies
                      if sp.cancel(sp.expand(squared - f.squared)) == 0), None)
        if match is None:  # (a named frequency is a positive symbol: ω² > 0)
            _check_oscillating(factor, squared)
            unnamed += 1
            match = Frequency(sp.Symbol(f"omega_{unnamed}", positive=True), squared,
                              f"mode {unnamed}")
        modes.append(Mode(match.name, match.symbol, squared, power))
    return modes


# --------------------------------------------------------------------------------------
# Inverse Laplace transform by partial fractions in z = s²
# --------------------------------------------------------------------------------------
@cache
def _oscillator_table(power: int, odd: bool) -> sp.Expr:
    """L⁻¹ of 1/(s² + ω²)^m (``odd`` False) or s/(s² + ω²)^m (``odd`` True), ω = W."""
    w = sp.Symbol("W", positive=True)
    t = sp.Symbol("t", positive=True)
    known = {
        (1, False): sp.sin(w * t) / w,
        (1, True): sp.cos(w * t),
        (2, False): (sp.sin(w * t) - w * t * sp.cos(w * t)) / (2 * w**3),
        (2, True): t * sp.sin(w * t) / (2 * w),
    }
    if (power, odd) in known:
        result = known[(power, odd)]
    else:  # rare: higher resonance; SymPy's transform handles these small cases
        result = sp.inverse_laplace_transform((S if odd else 1) / (S**2 + w**2) ** power,
                                              S, t)
        result = sp.simplify(result.subs(sp.Heaviside(t), 1))
    return result


def _time_function(mode: Mode, power: int, odd: bool, t: sp.Symbol) -> sp.Expr:
    """L⁻¹ of 1/(s² + ω²)^m, or s/(s² + ω²)^m if ``odd``; ω = 0 for an integrator."""
    if mode.symbol is None:  # 1/z^m = 1/s^(2m), or s/z^m = 1/s^(2m-1)
        n = 2 * power - (1 if odd else 0)
        return t ** (n - 1) / math.factorial(n - 1)
    w, tt = sp.Symbol("W", positive=True), sp.Symbol("t", positive=True)
    return _oscillator_table(power, odd).xreplace({w: mode.symbol, tt: t})


def inverse_laplace(X: sp.Expr, modes: Sequence[Mode], s: sp.Symbol = S,
                    t: sp.Symbol = T, tidy: Callable[[sp.Expr], sp.Expr] = sp.factor
                    ) -> sp.Expr:
    """Closed-form inverse Laplace transform of a rational ``X(s)`` with poles 0 and ±iω.

    Parameters
    ----------
    X : sympy.Expr
        Strictly proper rational function of ``s``.
    modes : sequence of Mode
        The oscillators its poles belong to (from :func:`split_modes`).
    tidy : callable
        Applied to each partial-fraction coefficient (readability).

    Returns
    -------
    sympy.Expr
        x(t) for t ≥ 0: sums of polynomials in t, sin(ω t), cos(ω t), t sin(ω t), ...

    Notes
    -----
    All polynomial work happens over the field of rational functions of the remaining
    symbols (SymPy ``frac_field``): X = A(z) + s B(z) with z = s², and the coefficient of
    1/(z + ω²)^(m − j) is the j-th Taylor coefficient at z = −ω² of the rest of the
    fraction (residues by power-series division, no ``apart``).
    """
    X = sp.together(X)
    if X == 0:
        return sp.S.Zero
    num, den = sp.fraction(sp.cancel(X))
    symbols = sorted((num.free_symbols | den.free_symbols
                      | set().union(*(sp.sympify(m.squared).free_symbols for m in modes)))
                     - {s}, key=sp.default_sort_key)
    field = sp.QQ.frac_field(*symbols) if symbols else sp.QQ
    num_p, den_p = sp.Poly(num, s, domain=field), sp.Poly(den, s, domain=field)
    return _inverse_laplace_poly(num_p, den_p, field, modes, s, t, tidy)


def _inverse_laplace_poly(num_p: sp.Poly, den_p: sp.Poly, field, modes: Sequence[Mode],
                          s: sp.Symbol, t: sp.Symbol,
                          tidy: Callable[[sp.Expr], sp.Expr] | None,
                          table: _PoleTable | None = None) -> sp.Expr:
    """:func:`inverse_laplace` of num/den given as polynomials in ``s`` over ``field``.

    ``table`` remembers the pole split of each denominator (the responses of one model
    share a few denominators).
    """
    if num_p.is_zero:
        return sp.S.Zero
    # make the denominator even in s: multiply by s if it has an odd power of s
    if any(k % 2 for (k,) in den_p.monoms()):
        num_p, den_p = num_p * sp.Poly(s, s, domain=field), den_p * sp.Poly(s, s, domain=field)
    if any(k % 2 for (k,) in den_p.monoms()):
        raise AnalysisError("denominator is not a polynomial in s² (damped or unstable "
                            "modes): the closed-form table does not apply")
    if num_p.degree() >= den_p.degree():
        raise AnalysisError("response is not strictly proper (impulse at t = 0)")

    def in_z(terms):
        coefficients = {(k // 2,): c for (k,), c in terms}
        return sp.Poly.from_dict(coefficients or {(0,): field.zero}, Z, domain=field)

    num_terms = num_p.rep.terms()  # coefficients in ``field`` (Poly.terms() would
    den_z = in_z(den_p.rep.terms())  # convert them to SymPy and back)
    even = in_z([(m, c) for m, c in num_terms if m[0] % 2 == 0])
    odd = in_z([((m[0] - 1,), c) for m, c in num_terms if m[0] % 2 == 1])
    table = table or _PoleTable(modes, field)
    result = sp.S.Zero
    for part, is_odd in ((even, False), (odd, True)):
        if part.is_zero:
            continue
        terms = table.factored_fractions(part, den_z) if tidy is sp.factor else None
        if terms is None:  # the coefficients as SymPy builds them, then ``tidy``
            terms = []
            for coefficient, mode, power in table.partial_fractions(part, den_z):
                if not coefficient:
                    continue
                coefficient = field.to_sympy(coefficient)
                if tidy is sp.factor:  # the same result, faster on these coefficients
                    coefficient = table.factor_product(coefficient)
                elif tidy:
                    coefficient = tidy(coefficient)
                terms.append((coefficient, mode, power))
        for coefficient, mode, power in terms:
            result += coefficient * _time_function(mode, power, is_odd, t)
    return result


@cache
def _mode_poly(squared: sp.Expr, field) -> sp.Poly:
    return sp.Poly(Z + squared, Z, domain=field)


def _z_poles(den: sp.Poly, modes: Sequence[Mode], field) -> list[tuple[Mode, int]]:
    """Multiplicity of each mode's root z = −ω² in ``den`` (exact division)."""
    poles: list[tuple[Mode, int]] = []
    remaining = den
    for mode in modes:
        factor = _mode_poly(mode.squared, field)
        power = 0
        while remaining.degree() > 0:
            quotient, remainder = remaining.div(factor)
            if not remainder.is_zero:
                break
            remaining, power = quotient, power + 1
        if power:
            poles.append((mode, power))
    if remaining.degree() > 0:
        raise AnalysisError(f"denominator factor {remaining.as_expr()} is not among the modes")
    return poles


def _taylor_head(poly: sp.Poly, point, count: int) -> list[sp.Expr]:
    """``poly.shift(point).all_coeffs()[::-1][:count]``: the lowest Taylor coefficients.

    Runs only the first ``count`` passes of SymPy's Taylor shift (``dup_shift``), which
    are the passes that fix those coefficients: the same arithmetic, so the same values.
    ``point`` is a SymPy expression or already an element of the polynomial's domain
    (then used as it is).
    """
    domain = poly.rep.dom
    a = domain.convert(point)
    f = list(poly.rep.to_list())
    n = len(f) - 1
    if n < 0:
        return [sp.S.Zero]
    for i in range(n, max(n - count, 0), -1):
        for j in range(i):
            f[j + 1] += a * f[j]
    return [domain.to_sympy(c) for c in f[::-1][:count]]


def _ring_element(value, ring):
    """A field element whose denominator is a constant, as an element of ``ring`` (or None)."""
    if not value.denom.is_ground:
        return None
    return value.numer if value.denom == ring.one else value.numer.quo_ground(value.denom.LC)


def _ring_coefficients(poly: sp.Poly, ring) -> list | None:
    """Coefficients of ``poly`` (highest power first) in ``ring``, or None if one of them
    is not a polynomial."""
    out = []
    for c in poly.rep.to_list():
        c = _ring_element(c, ring)
        if c is None:
            return None
        out.append(c)
    return out


def _divide_linear(coefficients: list, point) -> tuple[list, object]:
    """Quotient and remainder of a polynomial (coefficients, highest first) by z − point."""
    out = [coefficients[0]]
    for c in coefficients[1:]:
        out.append(c + point * out[-1])
    return out[:-1], out[-1]


def _ring_taylor_head(coefficients: list, point, count: int, zero) -> list:
    """:func:`_taylor_head` on a coefficient list (highest first): the same passes."""
    f = list(coefficients)
    n = len(f) - 1
    if n < 0:
        return [zero]
    for i in range(n, max(n - count, 0), -1):
        for j in range(i):
            f[j + 1] += point * f[j]
    return f[::-1][:count]


class _PoleTable:
    """Pole split and Taylor coefficients of each denominator, computed once.

    Where the field is a field of rational functions and every coefficient involved is
    a polynomial (the case of :func:`analyse`: numerators and denominators come from
    the polynomial parts of the resolvent, the points z = −ω² are polynomials), the
    divisions by z + ω² and the Taylor coefficients are computed in the field's
    polynomial ring: the same values without a gcd per operation (the field cancels
    every intermediate result). Otherwise in the field itself.
    """

    def __init__(self, modes: Sequence[Mode], field) -> None:
        self.modes, self.field = modes, field
        self.ring = field.field.ring if isinstance(field, FractionField) else None
        self._rests: dict[sp.Poly, list[tuple[Mode, int, sp.Expr, list[sp.Expr]]]] = {}
        self._ring_rests: dict[tuple, list | None] = {}
        self._factor_lists: dict = {}
        self._factor_products: dict[sp.Expr, sp.Expr] = {}

    def factor_product(self, coefficient: sp.Expr) -> sp.Expr:
        """:func:`factor_product` of ``coefficient``, each distinct one computed once (the
        same coefficient recurs across sources and states)."""
        try:
            return self._factor_products[coefficient]
        except KeyError:
            value = self._factor_products[coefficient] = factor_product(coefficient)
            return value

    def _split(self, den: sp.Poly) -> list[tuple[Mode, int, sp.Expr, list[sp.Expr]]]:
        """Per pole of ``den``: (mode, power, point z = −ω², Taylor coefficients there of
        the rest of ``den``)."""
        try:
            return self._rests[den]
        except KeyError:
            pass
        ring_split = self._ring_split(den)
        if ring_split is not None:
            split = [(mode, power, point, [self._to_sympy(c) for c in b])
                     for mode, power, point, b in ring_split]
            self._rests[den] = split
            return split
        split = []
        for mode, power in _z_poles(den, self.modes, self.field):
            factor = _mode_poly(mode.squared, self.field)
            rest = den
            for _ in range(power):
                rest = rest.quo(factor)
            # z = -ω² as an element of the field, converted once for every numerator
            point = self.field.convert(-factor.TC())
            split.append((mode, power, point, _taylor_head(rest, point, power)))
        self._rests[den] = split
        return split

    def _to_sympy(self, value) -> sp.Expr:
        """A ring element as SymPy writes the field element of the same value."""
        if all(c.denominator == 1 for c in value.values()):  # the field's own form
            return value.as_expr()
        return self.field.to_sympy(self.field.field.new(value))

    def _ring_split(self, den: sp.Poly) -> list | None:
        """:meth:`_split` in the polynomial ring, points and Taylor coefficients as ring
        elements; None where it does not apply."""
        if self.ring is None:
            return None
        coefficients = _ring_coefficients(den, self.ring)
        if coefficients is None:
            return None
        key = tuple(coefficients)
        try:
            return self._ring_rests[key]
        except KeyError:
            pass
        poles, remaining = [], coefficients
        for mode in self.modes:
            factor = _mode_poly(mode.squared, self.field)
            point = _ring_element(self.field.convert(-factor.TC()), self.ring)
            if point is None:
                self._ring_rests[key] = None
                return None
            power = 0
            while len(remaining) > 1:
                quotient, remainder = _divide_linear(remaining, point)
                if remainder:
                    break
                remaining, power = quotient, power + 1
            if power:
                poles.append((mode, power, point))
        if len(remaining) > 1:
            leftover = sp.Add(*[self._to_sympy(c) * Z**k
                                for k, c in enumerate(reversed(remaining))])
            raise AnalysisError(f"denominator factor {leftover} is not among the modes")
        split = []
        for mode, power, point in poles:
            rest = coefficients
            for _ in range(power):
                rest, _ = _divide_linear(rest, point)
            split.append((mode, power, point,
                          _ring_taylor_head(rest, point, power, self.ring.zero)))
        self._ring_rests[key] = split
        return split

    def partial_fractions(self, num: sp.Poly, den: sp.Poly) -> list:
        """Partial fractions of num/den in z by residues: (coefficient, mode, power).

        ``den`` = κ Π (z + ω_i²)^(m_i); the coefficient of 1/(z + ω²)^(m − j) is the j-th
        Taylor coefficient at z = −ω² of num/rest, rest being den without that factor.
        """
        numerator = None
        if self._ring_split(den) is not None:
            numerator = _ring_coefficients(num, self.ring)
        out = []
        for mode, power, point, b in self._split(den):
            if numerator is not None:
                a = [self._to_sympy(c) for c in
                     _ring_taylor_head(numerator, point, power, self.ring.zero)]
            elif isinstance(point, PolyElement):  # den split in the ring, num not
                a = _taylor_head(num, self.field.field.new(point), power)
            else:
                a = _taylor_head(num, point, power)
            series: list = []
            for k in range(power):
                acc = a[k] if k < len(a) else self.field.zero
                for i in range(1, k + 1):
                    if i < len(b):
                        acc -= b[i] * series[k - i]
                series.append(acc / b[0])
            out += [(series[j], mode, power - j) for j in range(power)]
        return out

    def factored_fractions(self, num: sp.Poly, den: sp.Poly) -> list | None:
        """:meth:`partial_fractions` with each nonzero coefficient as ``sp.factor`` gives
        it (the same expressions), computed from the coefficient's value: None where the
        ring does not apply.

        The j-th coefficient at a pole of power m is S_j / b₀^(j+1) with
        S_j = a_j b₀^j − Σ_{i=1..j} b_i S_(j−i) b₀^(i−1) (a: Taylor coefficients of num,
        b: of the rest of den), all polynomials. ``sp.factor`` of a rational function is
        its factorisation into SymPy's normalised irreducible factors (primitive, positive
        leading coefficient) times a rational coefficient, whatever expression of it is
        given; each distinct polynomial is factored once (SymPy's ``Poly.factor_list``).
        """
        split = self._ring_split(den)
        if split is None:
            return None
        numerator = _ring_coefficients(num, self.ring)
        if numerator is None:
            return None
        zero = self.ring.zero
        out = []
        for mode, power, point, b in split:
            a = _ring_taylor_head(numerator, point, power, zero)
            b0 = b[0]
            series: list = []
            for k in range(power):
                acc = (a[k] if k < len(a) else zero) * b0**k
                for i in range(1, k + 1):
                    if i < len(b):
                        acc -= b[i] * series[k - i] * b0 ** (i - 1)
                series.append(acc)
            out += [(self._factored(series[j], b0, j + 1), mode, power - j)
                    for j in range(power) if series[j]]
        return out

    def _factored(self, numerator, denominator, power: int) -> sp.Expr:
        """``sp.factor`` of numerator / denominator**power (ring elements)."""
        coefficient, factors = sp.S.One, []
        for value, exponent in ((numerator, 1), (denominator, -power)):
            c, fs = self._factor_list(value)
            coefficient *= c**exponent
            factors += [(f, k * exponent) for f, k in fs]
        return _keep_coeff(coefficient, sp.Mul(*[f**k for f, k in factors]))

    def _factor_list(self, value) -> tuple[sp.Expr, list[tuple[sp.Expr, int]]]:
        """SymPy's factor list of a nonzero ring element: its coefficient, then each
        irreducible factor as an expression with its power.

        Factored once per primitive polynomial with a positive leading coefficient
        (values that differ by a rational factor share their irreducible factors).
        """
        domain = self.ring.domain
        if value.is_ground:
            return domain.to_sympy(value.LC), []
        denominator, value = value.clear_denoms()
        content, value = value.primitive()
        if value.LC < 0:
            content, value = -content, -value
        try:
            coefficient, factors = self._factor_lists[value]
        except KeyError:
            coefficient, factors = sp.Poly(value.as_expr()).factor_list()
            factors = [(f.as_expr(), k) for f, k in factors]
            self._factor_lists[value] = coefficient, factors
        return coefficient * domain.to_sympy(content / denominator), factors


# --------------------------------------------------------------------------------------
# Whole analysis of one static error model
# --------------------------------------------------------------------------------------
@dataclass
class StaticAnalysis:
    """Everything derived from one constant (F, G, x₀) error model.

    Attributes
    ----------
    state_matrix : sympy.Matrix
        F in the parametrisation's symbols.
    characteristic : sympy.Expr
        det(sI − F), factored.
    modes : list of Mode
    resolvent : sympy.Matrix
        (sI − F)⁻¹.
    adjugate : sympy.Matrix
        adj(sI − F) = (sI − F)⁻¹ det(sI − F), polynomial entries in s.
    responses : dict
        Source name -> column (sympy.Matrix, shape (n, 1)) of closed-form responses to a
        unit source: a constant source (column of G, step input) or an initial error
        (column of the initial-error matrix).
    laplace : dict
        Source name -> the same responses in the Laplace domain.
    parametrisation : Parametrisation

    ``resolvent``, ``adjugate`` and ``laplace`` are converted to SymPy when first read
    (``make derive`` prints the adjugate of small models only).
    """

    state_matrix: sp.Matrix
    characteristic: sp.Expr
    modes: list[Mode]
    responses: dict[str, sp.Matrix]
    parametrisation: Parametrisation
    _inverse_parts: _FractionFreeInverse = field(repr=False)
    _determinant: object = field(repr=False)
    _laplace: dict[str, list] = field(repr=False)

    @functools.cached_property
    def _inverse(self) -> DomainMatrix:
        return self._inverse_parts.inverse()

    @functools.cached_property
    def resolvent(self) -> sp.Matrix:
        return self._inverse.to_Matrix()

    @functools.cached_property
    def adjugate(self) -> sp.Matrix:
        return self._inverse_parts.scaled_inverse(self._determinant).to_Matrix()

    @functools.cached_property
    def laplace(self) -> dict[str, sp.Matrix]:
        to_sympy = self._inverse.domain.to_sympy
        return {name: sp.Matrix([to_sympy(e) for e in entries])
                for name, entries in self._laplace.items()}

    @functools.cached_property
    def denominators(self) -> tuple[sp.Expr, ...]:
        """The factors the closed-form responses divide by (:func:`denominator_factors`
        of every response), in the parametrisation's symbols: where one vanishes, the
        forms are 0/0 or infinite."""
        return denominator_factors(e for column in self.responses.values() for e in column)

    def in_model_symbols(self, expr: sp.Expr, trees: SharedTrees | None = None) -> sp.Expr:
        """``expr`` with mode symbols and parametrisation symbols replaced by definitions.

        ``trees`` (optional) substitutes each distinct subtree once across calls.
        """
        trees = trees or SharedTrees()
        expr = trees.xreplace(expr, {m.symbol: sp.sqrt(m.squared) for m in self.modes
                                     if m.symbol is not None and m.name.startswith("mode ")})
        return self.parametrisation.to_model(expr, trees)


def denominator_factors(expressions: Iterable[sp.Expr]) -> tuple[sp.Expr, ...]:
    """The distinct irreducible factors of every denominator in ``expressions``.

    Each base of a negative power (each distinct subtree visited once), factored over
    the rationals; every factor primitive with a positive leading coefficient (so a
    factor and its negative are one), sorted by SymPy's default order.
    """
    bases: set[sp.Expr] = set()
    seen: set[sp.Basic] = set()
    stack = list(expressions)
    while stack:
        node = stack.pop()
        if node in seen or node.is_Atom:
            continue
        seen.add(node)
        if node.is_Pow and node.exp.is_negative:
            bases.add(node.base)
        stack.extend(node.args)
    factors: set[sp.Expr] = set()
    for base in bases:
        for factor, _ in sp.Poly(base).factor_list()[1]:
            factors.add((-factor if factor.LC() < 0 else factor).as_expr())
    return tuple(sorted(factors, key=sp.default_sort_key))


class _FractionFreeInverse:
    """A⁻¹ of a square matrix over a field of rational functions, fraction-free.

    A = A_num / d with A_num over the polynomial ring, and A_num adj = Δ I
    (``DomainMatrix.inv_den``: fraction-free elimination, no polynomial gcd per step),
    so A⁻¹ = d adj / Δ and A⁻¹ B = d (adj B_num) / (Δ d_B). Each entry is then one
    element of the field, which keeps its elements cancelled (numerator and denominator
    coprime, normalised): the same elements as the field's own ``inv``, in less than
    half the time on the sparse 10×10 and 11×11 static-base matrices.
    """

    def __init__(self, A: DomainMatrix) -> None:
        self.field = A.domain
        scale, numerators = A.to_dense().clear_denoms(convert=True)
        self.ring = numerators.domain
        self.scale = scale.element
        self.adjugate, self.denominator = numerators.to_sparse().inv_den()

    def _element(self, numerator, denominator):
        convert = self.field.convert_from
        return convert(numerator, self.ring) / convert(denominator, self.ring)

    def times(self, B: DomainMatrix) -> list[list]:
        """Entries of A⁻¹ B (``B`` over the same field), as a list of rows."""
        scale, numerators = B.to_dense().clear_denoms(convert=True)
        product = (self.adjugate * numerators.convert_to(self.ring).to_sparse()
                   ).to_dense().rep.to_ddm()
        denominator = self.denominator * scale.element
        return [[self._element(entry * self.scale, denominator) for entry in row]
                for row in product]

    def scaled_inverse(self, factor) -> DomainMatrix:
        """A⁻¹ · ``factor`` over the field (``factor`` = det A: the adjugate of A).

        A⁻¹ factor = adj · (d factor / Δ): the scalar is reduced once, and each entry is
        one product of it with a polynomial of adj, reduced by the field, instead of
        d adj_ij / Δ reduced and then multiplied by ``factor`` (two reductions by large
        polynomials per entry). The same field elements.
        """
        ratio = self._element(self.scale, self.denominator) * factor
        convert = self.field.convert_from
        rows = [[ratio * convert(entry, self.ring) for entry in row]
                for row in self.adjugate.to_dense().rep.to_ddm()]
        return DomainMatrix(rows, self.adjugate.shape, self.field)

    def inverse(self) -> DomainMatrix:
        """A⁻¹ over the field."""
        n = self.adjugate.shape[0]
        return DomainMatrix(self.times(DomainMatrix.eye(n, self.field).to_dense()),
                            (n, n), self.field)


def factor_product(expr: sp.Expr) -> sp.Expr:
    """``sp.factor(expr)`` (the same expression) for a product of integer powers of
    polynomials, without SymPy's ``together`` pass.

    ``sp.factor`` first brings its argument over one denominator (``together``), then
    factors each factor of that product and multiplies the irreducible factors back.
    A partial-fraction coefficient is already a product of polynomial powers (numerators
    and inverted denominators), and ``together`` was most of the cost; every factor is
    still factored by SymPy's own ``Poly.factor_list`` and multiplied as ``sp.factor``
    does. Any other expression goes to ``sp.factor`` unchanged.
    """
    from sympy.polys import polyoptions
    from sympy.polys.polytools import _factors_product, _symbolic_factor_list

    if not isinstance(expr, sp.Expr) or isinstance(expr, sp.Number):
        return sp.factor(expr)
    for arg in sp.Mul.make_args(expr):
        base, exponent = arg.as_base_exp()
        if not (exponent.is_Integer and isinstance(base, (sp.Add, sp.Symbol, sp.Number))
                and base.is_polynomial()):
            return sp.factor(expr)
    options = polyoptions.build_options((), {})
    options["fraction"] = True
    coefficient, factors = _symbolic_factor_list(expr, options, "factor")
    return _keep_coeff(coefficient, _factors_product(factors))


@contextlib.contextmanager
def factor_lists_remembered() -> Iterator[None]:
    """``Poly.factor_list`` answers each distinct polynomial once inside the block.

    The partial-fraction coefficients of one analysis share most of their numerator and
    denominator polynomials (817 of them, 78 distinct, for north_pointing), and
    ``sp.factor`` factors each one again. The answers are SymPy's own (a copy of the
    factor list each time, since callers may extend it). Not thread-safe: the block
    swaps a method of ``sympy.Poly`` and restores it on exit.
    """
    original = sp.Poly.factor_list
    if getattr(original, "remembered", False):  # nested: the outer block serves
        yield
        return
    memo: dict[sp.Poly, tuple] = {}

    def factor_list(poly):
        try:
            coeff, factors = memo[poly]
        except KeyError:
            coeff, factors = memo[poly] = original(poly)
        return coeff, list(factors)

    factor_list.remembered = True
    sp.Poly.factor_list = factor_list
    try:
        yield
    finally:
        sp.Poly.factor_list = original


def _split_in_s(element, outer, inner, s: sp.Symbol) -> tuple[sp.Poly, sp.Poly]:
    """Numerator and denominator of an element of QQ(s, p...) as polynomials in s over QQ(p...)."""
    index = outer.symbols.index(s)

    def to_poly(poly_element) -> sp.Poly:
        grouped: dict[int, dict] = {}
        for monom, coeff in poly_element.terms():
            rest = monom[:index] + monom[index + 1:]
            grouped.setdefault(monom[index], {})[rest] = coeff
        ring = inner.field.ring if hasattr(inner, "field") else None
        terms = {}
        for power, coeffs in grouped.items():
            if ring is None:
                value = inner.convert(next(iter(coeffs.values())))
            else:
                value = inner.field(ring.from_dict({m: ring.domain.convert(c, outer.domain)
                                                    for m, c in coeffs.items()}))
            terms[(power,)] = value
        return sp.Poly.from_dict(terms or {(0,): inner.zero}, s, domain=inner)

    return to_poly(element.numer), to_poly(element.denom)


def _over_first_generator(value):
    """``value / x`` for the first generator x of its field (s in :func:`analyse`): the
    element the field's division gives, without its gcd.

    The numerator n and denominator d of a field element are coprime, with integer
    coefficients and d's leading coefficient positive; so gcd(n, d x) is x if x divides
    n and 1 otherwise, and the reduced quotient is (n / x, d) or (n, d x) (d x keeps d's
    leading coefficient, x being the first variable of the lexicographic order).
    """
    numer, denom = value.numer, value.denom
    if not numer:
        return value
    if all(monom[0] for monom in numer.itermonoms()):
        numer = numer.ring.from_dict({(m[0] - 1, *m[1:]): c for m, c in numer.items()})
    else:
        denom = denom.mul_monom((1,) + (0,) * (denom.ring.ngens - 1))
    return value.raw_new(numer, denom)


def _check_rational(M: sp.Matrix, what: str, field) -> None:
    """Refuse (AnalysisError, one line naming the entry) an entry of ``M`` that is not
    an element of ``field``, the rational functions of the analysis's symbols."""
    for (i, j), entry in sorted(M.todok().items()):
        try:
            field.from_sympy(entry)
        except (ValueError, CoercionFailed):
            where = f"entry ({i + 1}, {j + 1})" if M.cols > 1 else f"entry {i + 1}"
            names = ", ".join(str(x) for x in field.symbols[1:]) or "none"
            raise AnalysisError(
                f"{what}: {where} = {entry} is not a rational function of the "
                f"parametrisation's symbols ({names}): F and the source columns must be "
                "rational in them; rewrite square roots, sin and cos into new symbols "
                "with a Parametrisation (e.g. Ω_N = Ω cos φ, Ω_U = Ω sin φ)") from None


def analyse(F: sp.Matrix, columns: Mapping[str, tuple[sp.Matrix, bool]],
            parametrisation: Parametrisation = Parametrisation(),
            s: sp.Symbol = S, t: sp.Symbol = T,
            tidy: Callable[[sp.Expr], sp.Expr] | None = sp.factor) -> StaticAnalysis:
    """Transfer functions, modes and closed-form responses of ẋ = F x (+ sources).

    Parameters
    ----------
    F : sympy.Matrix, shape (n, n)
        Constant state matrix in the model's symbols.
    columns : mapping
        Source name -> (column b of shape (n, 1), is_step). ``is_step`` True: a constant
        source entering as ẋ = F x + b w (X = (sI − F)⁻¹ b / s); False: an initial error
        x(0) = b w (X = (sI − F)⁻¹ b).
    parametrisation : Parametrisation
        Rewrite applied to F and to the columns first.
    tidy : callable or None
        Applied to each partial-fraction coefficient (``sp.factor`` reads best; None is
        fastest and gives expanded rational coefficients).

    Raises
    ------
    AnalysisError
        If an entry of F or of a source column is not a rational function of the
        symbols once the parametrisation has rewritten it (a square root, sin, cos, π
        left in it: the resolvent is computed over the rational functions), naming the
        entry; if a root of det(sI − F) is not 0 or ±iω (:func:`split_modes`): e.g. the
        real roots ±√(2g/R) of the vertical channel, named with their growth time
        constant.
    """
    _check_square(F)
    rewrite = parametrisation.rewrite
    Fp = F.applyfunc(lambda e: sp.cancel(rewrite(e)))
    names = list(columns)
    B = sp.Matrix.hstack(*[columns[n][0] for n in names]).applyfunc(
        lambda e: sp.cancel(rewrite(e)))
    symbols = sorted((Fp.free_symbols | B.free_symbols
                      | set().union(*(sp.sympify(f.squared).free_symbols
                                      for f in parametrisation.frequencies))) - {s},
                     key=sp.default_sort_key)
    outer = sp.QQ.frac_field(s, *symbols)
    _check_rational(Fp, "F", outer)
    for j, name in enumerate(names):
        _check_rational(B[:, j], f"the column of source {name!r}", outer)
    inverse = _FractionFreeInverse(DomainMatrix.from_list_sympy(
        Fp.rows, Fp.cols, (s * sp.eye(Fp.rows) - Fp).tolist()).convert_to(outer))
    characteristic = characteristic_polynomial(Fp, s)
    determinant = outer.from_sympy(sp.expand(characteristic))
    modes = split_modes(characteristic, parametrisation.frequencies, s)
    poles = list(modes)
    if not any(m.symbol is None for m in modes):  # step inputs add a pole at s = 0
        poles.append(Mode("integrator", None, sp.S.Zero, 0))
    inner = sp.QQ.frac_field(*symbols) if symbols else sp.QQ
    Bd = DomainMatrix.from_list_sympy(B.rows, B.cols, B.tolist()).convert_to(outer)
    Xd = inverse.times(Bd)
    table = _PoleTable(poles, inner)
    if tidy is not None and tidy is not sp.factor:  # (sp.factor: see _PoleTable)
        tidy = functools.cache(tidy)  # the same coefficient recurs across sources and states
    responses: dict[str, sp.Matrix] = {}
    laplace: dict[str, list] = {}
    with factor_lists_remembered():
        for j, name in enumerate(names):
            is_step = columns[name][1]
            entries = [_over_first_generator(Xd[i][j]) if is_step else Xd[i][j]
                       for i in range(Fp.rows)]
            laplace[name] = entries
            responses[name] = sp.Matrix([
                _inverse_laplace_poly(*_split_in_s(e, outer, inner, s), inner, poles, s, t,
                                      tidy, table)
                for e in entries])
    return StaticAnalysis(Fp, characteristic, modes, responses, parametrisation, inverse,
                          determinant, laplace)
