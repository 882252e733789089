"""Transfer functions of any model's error equations at a static base, numerically.

At rest the error equations ``ẋe = F xe + G w``, ``ye = H xe`` have constant
coefficients, and each error source reaches each output through one rational function
of the Laplace variable s (in 1/s)::

    W(s) = h (sI − F)⁻¹ g

with h the output's row of H (or a unit row: an error state read directly) and g the
source's column: of G for a constant source, of the initial-error map E
(``xe(0) = E w``) for an initial error. The conventions, as the command prints them:

* a constant source of size b gives ``Y(s) = b W(s)/s``: W is the transform of the
  response to a unit impulse of the source, W/s that of a unit constant source;
* an initial error of size b gives ``Y(s) = b W(s)``: W is the transform of the response
  to a unit initial error.

The static base and F are those of ``ins-errors modes`` (:func:`~ins_errors.analysis.
modes.modes_at_rest`, whose :class:`~ins_errors.analysis.modes.RestPoint` gives the
state, inputs, parameters and initial conditions G, H and E are evaluated at).

What a pair does not see is cancelled before W is factored: its minimal realisation
keeps the controllable part of (F, g) (an orthonormal Krylov basis of g, F g, F² g, ...)
and of that the part h observes (the same on (Fᵀ, hᵀ)), on the states measured in the
units of the Schuler loop (:func:`~ins_errors.analysis.modes._scales`) and F divided by
its norm, a direction being zero below :data:`TOLERANCE`. The poles are the eigenvalues
of the minimal F; the zeros those of its zero dynamics; the gain K its first non-zero
Markov parameter h F^(r−1) g (r the relative degree), so that::

    W(s) = K (s − z₁)…(s − z_(n−r)) / ((s − p₁)…(s − p_n))

Two computed roots are one repeated root only within :data:`GROUP_SAFETY` times their
accuracy (a Jordan block's rounding split), so a close but distinct pair (the Foucault
split within 1e-4° of the equator) stays two. A zero within :data:`CANCEL` of a pole
(or within their accuracies) cancels it too. Each pole is named as ``modes`` names F's
eigenvalue it is (Schuler, Schuler ± Foucault, Earth, vertical channel, integrator,
...), and each mode of F the pair does not see is listed as cancelled.

W = 0 is proved by the Markov parameters h Fᵏ g, k < n, against their componentwise
bounds (:func:`markov_zero`); a reduction that finds nothing where they say otherwise is
not taken, except for a W below :data:`TOLERANCE` of what the norms allow (``negligible``,
:class:`_Reference`).

The factored form is checked against h (iωI − F)⁻¹ g of the whole F at frequencies
across the band (:attr:`TransferFunction.check_error`); a form off by more than
:data:`CHECK_LIMIT` is made again with a finer tolerance, then on balanced states
(:data:`REDUCTIONS`: near the equator couplings go with sin φ, near a pole F's entries
with tan φ), and a pair none brings within :data:`REFUSE_LIMIT` is refused in one line.

The long run of the response to a source of size b follows from the partial fractions
of Y(s) (:meth:`TransferFunction.partial_fractions`): a pole of Y at 0 of order m ≥ 2
makes it grow as t^(m−1); of order 1 it oscillates about (or settles at) the constant
lim s→0 s·Y(s), b·W(0) for a constant source; a pole in the right half-plane makes it
grow exponentially.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ins_errors.analysis.modes import ZERO, Mode, StaticModes, static_modes
from ins_errors.errors import DomainError, InsErrorsError, unknown_name
from ins_errors.numeric.model import Model, as_model

TOLERANCE = 1e-9
"""A direction of the Krylov bases (what a source reaches, what an output sees) and a
Markov parameter are zero below this share, with the states in the units of the Schuler
loop and F divided by its norm (so every entry is at most 1): the first, coarsest
reduction tried (:data:`REDUCTIONS`)."""

REDUCTIONS = ((False, TOLERANCE), (False, 1e-12), (True, 1e-12))
"""The reductions tried in turn, (balanced, tolerance), until one passes the check
(:data:`CHECK_LIMIT`): the states in the units of the Schuler loop, then with a finer
tolerance (a coupling weaker than 1e-9, as near the equator where it goes with sin φ),
then also balanced (a diagonal similarity that evens out F's rows and columns, LAPACK
gebal, its factors within 2^±:data:`BALANCE_LIMIT`: near a pole F's entries grow as
tan φ)."""

BALANCE_LIMIT = 20
"""The balancing factors are kept within 2^±this (a state nothing depends on would get
an unbounded one)."""

CANCEL = 1e-9
"""A zero closer to a pole than this share of the pole's size cancels it (a pole and a
zero at 0 are one root already, :data:`~ins_errors.analysis.modes.ZERO`): the mode's
part in W is then at the level of the roots' rounding (a weakly reachable and weakly
seen mode that the Krylov bases kept, e.g. strapdown_ned's vertical channel in a
horizontal output near the equator)."""

SLOW_DECAY = 1.0
"""A damped oscillation whose decay time is at least this many of its periods (damping
ratio below about 0.16) is listed in the long run with its amplitude and decay time: it
rings for several periods, and a lightly damped Schuler pair (ζ ~ 1e-4 from a damped
vertical channel) for months."""

CLOSE_ROOTS = 1e-4
"""Two roots of W closer than this share of their size are printed with the digits that
tell them apart (:attr:`TransferFunction.digits`): at 4 digits they would look equal."""

CHECK_FREQUENCIES = 9
"""Frequencies across the band at which the factored form is checked against the whole
F's h (iωI − F)⁻¹ g."""

CHECK_LIMIT = 1e-6
"""A reduction is taken when its factored form agrees with the whole F's
h (iωI − F)⁻¹ g to this share of the larger of its size and 1e-3 of the size the rounding
of F's, g's and h's entries can give it (:class:`_Reference`; so a W below 1e-9 of that
passes as zero); a W = 0 must moreover be proved by its Markov parameters
(:func:`markov_zero`); else
the next one of :data:`REDUCTIONS` is tried, and the best is kept (the command says
so)."""

REFUSE_LIMIT = 1e-3
"""A pair whose best factored form is further than this from the whole F's is refused
(:class:`~ins_errors.errors.DomainError`): F is too ill-conditioned at the base."""

CHECK_FLOOR = TOLERANCE / CHECK_LIMIT
"""The share of the componentwise bound below which the check measures W against that
share (1e-3: a difference below 1e-9 of the bound passes)."""

CONVENTION = ("W(s) = h (sI − F)⁻¹ g, s in 1/s: h the output's row of H, g the source's "
              "column of G (a constant source: size b gives Y(s) = b·W(s)/s) or of the "
              "initial-error map (an initial error: size b gives Y(s) = b·W(s))")
"""The convention, as the command and the JSON state it."""

SUPERSCRIPTS = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def superscript(power: int) -> str:
    """``"²"`` for 2; empty for 1."""
    return "" if power == 1 else str(power).translate(SUPERSCRIPTS)


@dataclass(frozen=True)
class Factor:
    """One real factor of W's numerator or denominator.

    Attributes
    ----------
    value : complex
        The root, 1/s (of a conjugate pair the one with positive imaginary part).
    multiplicity : int
        How many times it (a pair: the pair) is a root.
    name : str or None
        For a pole: the mode of F it is, as ``modes`` names it; None for a zero.
    """

    value: complex
    multiplicity: int
    name: str | None = None

    @property
    def period_s(self) -> float | None:
        """2π/Im, s, of an oscillating root; else None."""
        return 2 * np.pi / self.value.imag if self.value.imag else None

    @property
    def time_constant_s(self) -> float | None:
        """1/|Re|, s, of a root off the imaginary axis; else None."""
        return 1.0 / abs(self.value.real) if self.value.real else None

    @property
    def roots(self) -> list[tuple[complex, int]]:
        """(root, multiplicity), the conjugate of a complex root included."""
        if self.value.imag:
            return [(self.value, self.multiplicity), (self.value.conjugate(), self.multiplicity)]
        return [(self.value, self.multiplicity)]

    @property
    def degree(self) -> int:
        """Its degree in s."""
        return self.multiplicity * (2 if self.value.imag else 1)

    def text(self, digits: int = 4) -> str:
        """The factor in s, real form: ``s²``, ``(s + 1.755e-03)``, ``(s² + (1.186e-03)²)``,
        ``(s² + 4.2e-04 s + (1.2e-03)²)``, with its power; ``digits`` after the point."""
        v, power = self.value, superscript(self.multiplicity)
        if v == 0:
            return f"s{power}"
        if not v.imag:
            sign = "+" if v.real < 0 else "−"
            return f"(s {sign} {abs(v.real):.{digits}e}){power}"
        if not v.real:
            return f"(s² + ({v.imag:.{digits}e})²){power}"
        sign = "+" if v.real < 0 else "−"
        return (f"(s² {sign} {abs(2 * v.real):.{digits}e} s + ({abs(v):.{digits}e})²)"
                f"{power}")

    def to_dict(self) -> dict:
        return {"real": self.value.real, "imag": self.value.imag,
                "multiplicity": self.multiplicity, "name": self.name,
                "period_s": self.period_s, "time_constant_s": self.time_constant_s,
                "factor": self.text()}


@dataclass(frozen=True)
class Oscillation:
    """An oscillation of the long-run response: undamped, or damped slowly (decay time
    at least its period, :data:`SLOW_DECAY`).

    Attributes
    ----------
    name : str
        The mode (``"Schuler"``, ``"Earth"``, ...).
    period_s : float
        Its period, s.
    amplitude : float
        Its amplitude (at the start, of a damped one) in the response to a unit source
        (output SI unit per source SI unit), >= 0.
    decay_s : float or None
        The time its amplitude takes to fall by e, s (1/|Re λ|); None when undamped.
    """

    name: str
    period_s: float
    amplitude: float
    decay_s: float | None = None


@dataclass(frozen=True)
class LongRun:
    """How the response to a source of size b behaves after a long time.

    Attributes
    ----------
    kind : str
        ``"exponential"`` (a pole in the right half-plane), ``"power"`` (a pole of Y at 0
        of order ≥ 2: grows as t^power), ``"resonance"`` (a repeated undamped pair),
        ``"constant"`` (oscillates about, or settles at, ``coefficient``), ``"zero"``
        (oscillates about or settles at zero) or ``"none"`` (W = 0).
    power : int
        The power of t of the leading term (0 for a constant).
    coefficient : float or None
        Of a unit source: the leading term is ``b · coefficient · t^power`` (output SI
        unit per source SI unit per s^power); of the exponential kind, the size of the
        growing term ``b · coefficient · t^power · e^(t/T)`` (its amplitude for a growing
        oscillation); None for a resonance.
    oscillations : tuple of Oscillation
        The undamped oscillations about it (simple poles on the imaginary axis).
    growth : Factor or None
        The fastest growing pole (exponential kind) or the repeated pair (resonance).
    settles : bool
        True when every pole of Y other than 0 is damped (the response settles).
    settling_s : float or None
        When every damped term has fallen below 1 % of the value the response settles
        at (of its largest term where that is zero), s (None without a damped term).
    """

    kind: str
    power: int
    coefficient: float | None
    oscillations: tuple[Oscillation, ...] = ()
    growth: Factor | None = None
    settles: bool = False
    settling_s: float | None = None


@dataclass(frozen=True)
class TransferFunction:
    """The transfer function of one source to one output, factored.

    Attributes
    ----------
    source, output : str
        Their names (the output may be an error state).
    source_kind : str
        ``"constant"`` or ``"initial"``.
    source_unit, output_unit : str
        SI units.
    source_display, output_display : str
        The units the command shows them in.
    gain : float
        K of W(s) = K Π(s − z)/Π(s − p), SI: output unit per source unit per
        s^(relative degree) (per s^(relative degree − 1) for an initial error).
    relative_degree : int
        Number of poles minus number of zeros (0 for W = 0).
    zeros, poles : tuple of Factor
        By increasing size; the poles named after F's modes.
    full_order : int
        Number of error states (F's order).
    cancelled : tuple of Factor
        The modes of F the pair does not see (not controllable from the source or not
        observable at the output), named.
    magnitude : float
        Size b of the source for :attr:`long_run`'s words, SI.
    check_error : float
        Largest difference between the factored form and the whole F's
        h (iωI − F)⁻¹ g over :data:`CHECK_FREQUENCIES` frequencies of the band, relative
        to the larger of the latter's size and :data:`CHECK_FLOOR` of the size rounding
        can give it (:class:`_Reference`); at least 1 for a W = 0 its Markov parameters
        do not prove (:func:`markov_zero`).
    display_factors : tuple of float
        (factor turning the output's SI value into its display unit, one display unit
        of the source in SI).
    negligible : bool
        W = 0 not exactly (its Markov parameters are not all zero to rounding) but below
        :data:`TOLERANCE` of the size the norms allow (:class:`_Reference`): a coupling
        weaker than the reductions' tolerance.
    """

    source: str
    output: str
    source_kind: str
    source_unit: str
    output_unit: str
    source_display: str
    output_display: str
    gain: float
    relative_degree: int
    zeros: tuple[Factor, ...]
    poles: tuple[Factor, ...]
    full_order: int
    cancelled: tuple[Factor, ...]
    magnitude: float
    check_error: float = 0.0
    display_factors: tuple[float, float] = field(default=(1.0, 1.0), repr=False)
    negligible: bool = False

    @property
    def order(self) -> int:
        """Degree of W's denominator: the order of the minimal realisation."""
        return sum(f.degree for f in self.poles)

    @property
    def is_zero(self) -> bool:
        """True when the source does not reach the output at all."""
        return self.gain == 0.0

    def __call__(self, s) -> np.ndarray:
        """W(s) from the factored form, s complex (1/s), any shape."""
        s = np.asarray(s, dtype=complex)
        value = np.full(s.shape, complex(self.gain))
        for factor in self.zeros:
            for root, count in factor.roots:
                value = value * (s - root) ** count
        for factor in self.poles:
            for root, count in factor.roots:
                value = value / (s - root) ** count
        return value

    # -- the response ------------------------------------------------------------------
    def _response_roots(self) -> tuple[list[tuple[complex, int]], list[tuple[complex, int]]]:
        """(zeros, poles) of Y(s)/b, each (root, multiplicity), conjugates included: W's,
        with a pole at 0 more for a constant source (or a zero at 0 fewer)."""
        zeros = [r for f in self.zeros for r in f.roots]
        poles = [r for f in self.poles for r in f.roots]
        if self.source_kind != "initial":
            at_zero = [k for k, (root, _) in enumerate(zeros) if root == 0]
            if at_zero:
                k = at_zero[0]
                zeros[k] = (0j, zeros[k][1] - 1)
            else:
                found = [k for k, (root, _) in enumerate(poles) if root == 0]
                if found:
                    poles[found[0]] = (0j, poles[found[0]][1] + 1)
                else:
                    poles.append((0j, 1))
        return ([(r, m) for r, m in zeros if m > 0], poles)

    @cached_property
    def partial_fractions(self) -> list[tuple[complex, np.ndarray]]:
        """Y(s)/b = Σ_p Σ_j r_pj / (s − p)^j: (p, [r_p1, ..., r_pm]) for every pole p of
        Y (conjugates included), per unit source, SI; y(t)/b = Σ r_pj t^(j−1)/(j−1)!
        e^(pt) (:meth:`response`). Empty for W = 0."""
        if self.is_zero:
            return []
        zeros, poles = self._response_roots()
        out = []
        for k, (pole, m) in enumerate(poles):
            series = np.zeros(m, dtype=complex)
            series[0] = self.gain
            for root, count in zeros:
                for _ in range(count):
                    series = _times_series(series, np.array([pole - root, 1.0]))
            for j, (other, count) in enumerate(poles):
                if j == k:
                    continue
                d = pole - other
                inverse = np.array([(-1.0) ** i / d ** (i + 1) for i in range(m)])
                for _ in range(count):
                    series = _times_series(series, inverse)
            if not pole.imag:  # a real pole of a real rational function: real residues
                series = series.real.astype(complex)
            out.append((pole, series[::-1].copy()))  # r_1 (1/(s − p)) first
        return out

    def response(self, t, magnitude: float | None = None) -> np.ndarray:
        """y(t) of a source of size ``magnitude`` (SI; default :attr:`magnitude`),
        from the partial fractions: constant from t = 0 for a constant source, the
        initial error at t = 0 for an initial one; t in s, any shape; output SI unit."""
        t = np.asarray(t, dtype=float)
        b = self.magnitude if magnitude is None else float(magnitude)
        total = np.zeros(t.shape, dtype=complex)
        for pole, coefficients in self.partial_fractions:
            exponential = np.exp(pole * t)
            for j, r in enumerate(coefficients):
                total = total + r * t ** j / math.factorial(j) * exponential
        return b * total.real

    @cached_property
    def long_run(self) -> LongRun:
        """How the response to a constant source (an initial error) behaves for large t."""
        if self.is_zero:
            return LongRun("none", 0, 0.0, settles=True)
        fractions = dict(self.partial_fractions)
        unstable = [f for f in self.poles if f.value.real > 0]
        if unstable:
            fastest = max(unstable, key=lambda f: f.value.real)
            leading = fractions[fastest.value][-1]
            size = float(leading.real if not fastest.value.imag else 2 * abs(leading))
            return LongRun("exponential", fastest.multiplicity - 1,
                           size / math.factorial(fastest.multiplicity - 1), growth=fastest)
        resonant = [f for f in self.poles if f.value.imag and not f.value.real
                    and f.multiplicity > 1]
        oscillations = tuple(
            Oscillation(f.name or "oscillation", f.period_s, 2 * abs(fractions[f.value][0]),
                        f.time_constant_s)
            for f in self.poles if f.value.imag and f.multiplicity == 1
            and (not f.value.real or (f.value.real < 0
                                      and f.time_constant_s >= SLOW_DECAY * f.period_s)))
        settles = all(f.value.real < 0 for f in self.poles if f.value != 0)
        at_zero = fractions.get(0j)
        settling = self._settling(fractions, at_zero)
        if resonant:
            biggest = max(resonant, key=lambda f: f.multiplicity)
            power = biggest.multiplicity - 1
            coefficient = None
            if at_zero is not None and len(at_zero) - 1 >= power:  # a t^m of its own
                power = len(at_zero) - 1
                coefficient = float(at_zero[-1].real) / math.factorial(power)
            return LongRun("resonance", power, coefficient, oscillations, growth=biggest,
                           settling_s=settling)
        if at_zero is None:
            return LongRun("zero", 0, 0.0, oscillations, settles=settles,
                           settling_s=settling)
        m = len(at_zero)
        coefficient = float(at_zero[-1].real) / math.factorial(m - 1)
        return LongRun("constant" if m == 1 else "power", m - 1, coefficient, oscillations,
                       settles=settles, settling_s=settling)

    def _settling(self, fractions: dict, at_zero) -> float | None:
        """When every damped term of the response is below 1 % of the value it settles
        at (of the largest term's size where that is zero or it grows), s: the latest
        τ ln(size/(0.01 · scale)) of the damped poles (None without a damped term)."""
        terms = []
        for f in self.poles:
            if f.value.real < 0:
                size = float(np.abs(fractions[f.value]).sum()) * (2 if f.value.imag else 1)
                if size > 0:
                    terms.append((f.time_constant_s, size))
        if not terms:
            return None
        if at_zero is not None and len(at_zero) == 1 and at_zero[0] != 0:
            scale = abs(at_zero[0])
        else:
            scale = max(2 * float(np.abs(r).sum()) for _, r in fractions.items())
        return max(tau * max(math.log(size / (0.01 * scale)), 0.0) for tau, size in terms)

    # -- display -----------------------------------------------------------------------
    @property
    def seconds_power(self) -> int:
        """The power of 1/s in the gain's unit: the relative degree (one less for an
        initial error, whose W carries one s more)."""
        return self.relative_degree - (1 if self.source_kind == "initial" else 0)

    @property
    def gain_display(self) -> tuple[float, str]:
        """(K, its unit) in the output's display unit per the source's display unit,
        per s^:attr:`seconds_power`: ``(2.657e-04, "arcmin/ug/s²")``."""
        output_factor, source_size = self.display_factors
        power = self.seconds_power
        per = "" if power == 0 else f"/s{superscript(power)}"
        return (self.gain * output_factor * source_size,
                f"{_unit_term(self.output_display)}/{_unit_term(self.source_display)}{per}")

    @property
    def digits(self) -> int:
        """Digits after the point the roots are printed with: 4, or as many as tell apart
        two of W's roots (a zero and a pole, two poles) within :data:`CLOSE_ROOTS` of
        each other's size (+ 2, at most 12)."""
        values = [f.value for f in (*self.zeros, *self.poles) if f.value != 0]
        closest = min((abs(a - b) / max(abs(a), abs(b))
                       for k, a in enumerate(values) for b in values[k + 1:]
                       if a != b), default=1.0)
        if closest >= CLOSE_ROOTS:
            return 4
        return int(min(12, math.ceil(-math.log10(max(closest, 1e-16))) + 2))

    def factored_text(self) -> str:
        """``W(s) = K [unit] · zeros / poles`` in display units (``W(s) = 0`` when the
        source does not reach the output); roots with :attr:`digits`."""
        if self.is_zero:
            return "W(s) = 0"
        value, unit = self.gain_display
        digits = self.digits
        numerator = " ".join(f.text(digits) for f in self.zeros) or "1"
        denominator = " ".join(f.text(digits) for f in self.poles)
        if len(self.poles) > 1:
            denominator = f"({denominator})"
        return f"W(s) = {value:.4e} [{unit}] · {numerator} / {denominator}"

    def to_dict(self) -> dict:
        value, unit = self.gain_display
        run = self.long_run
        return {
            "source": self.source, "output": self.output, "source_kind": self.source_kind,
            "source_unit": self.source_unit, "output_unit": self.output_unit,
            "source_display_unit": self.source_display,
            "output_display_unit": self.output_display,
            "gain": self.gain, "gain_display": value, "gain_display_unit": unit,
            "relative_degree": self.relative_degree, "order": self.order,
            "full_order": self.full_order, "factored": self.factored_text(),
            "zeros": [f.to_dict() for f in self.zeros],
            "poles": [f.to_dict() for f in self.poles],
            "cancelled": [f.to_dict() for f in self.cancelled],
            "partial_fractions": [
                {"pole": {"real": p.real, "imag": p.imag},
                 "coefficients": [{"real": r.real, "imag": r.imag} for r in coefficients]}
                for p, coefficients in self.partial_fractions],
            "check_error": self.check_error, "negligible": self.negligible,
            "magnitude": self.magnitude,
            "long_run": {
                "kind": run.kind, "power": run.power, "coefficient": run.coefficient,
                "value": None if run.coefficient is None else run.coefficient * self.magnitude,
                "settles": run.settles, "settling_s": run.settling_s,
                "growth": None if run.growth is None else run.growth.to_dict(),
                "oscillations": [{"name": o.name, "period_s": o.period_s,
                                  "amplitude": abs(o.amplitude * self.magnitude),
                                  "decay_s": o.decay_s}
                                 for o in run.oscillations],
                "text": long_run_text(self)},
        }


def _unit_term(unit: str) -> str:
    """A unit as a term of a quotient: ``(m/s)`` for ``m/s``, ``ug`` as it is."""
    return f"({unit})" if "/" in unit or " " in unit else unit


def _times_series(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The product of two power series, truncated to the length of ``a``."""
    out = np.zeros(len(a), dtype=complex)
    for i, value in enumerate(a):
        if value == 0:
            continue
        for j in range(min(len(b), len(a) - i)):
            out[i + j] += value * b[j]
    return out


@dataclass(frozen=True)
class TransferFunctions:
    """The transfer functions of some sources to some outputs at one static base.

    Attributes
    ----------
    modes : StaticModes
        The base, F and its named modes (``ins-errors modes``).
    pairs : tuple of TransferFunction
        Source by source, output by output.
    band : tuple of float
        Frequencies covering the modes, rad/s (for the check and the Bode plot).
    """

    modes: StaticModes
    pairs: tuple[TransferFunction, ...]
    band: tuple[float, float]

    def pair(self, source: str, output: str) -> TransferFunction:
        """The transfer function of ``source`` to ``output``.

        Raises
        ------
        UnknownNameError
            If there is no such pair (the pairs are listed).
        """
        for pair in self.pairs:
            if pair.source == source and pair.output == output:
                return pair
        raise unknown_name("source → output pair", f"{source} → {output}",
                           [f"{p.source} → {p.output}" for p in self.pairs])

    def named_modes(self) -> list[Mode]:
        """The modes of F with a field name (not just a kind) that some pair has as a
        pole, by increasing frequency: what the Bode plot marks."""
        used = {f.name for pair in self.pairs for f in pair.poles}
        kinds = {"integrator", "damped", "growing", "oscillation", "damped oscillation",
                 "growing oscillation"}
        return [m for m in self.modes.modes if m.name in used and m.name not in kinds
                and m.eigenvalue != 0]

    def to_dict(self) -> dict:
        base = self.modes
        return {"model": base.model, "base": base.base, "latitude_rad": base.latitude,
                "height_m": base.height, "convention": CONVENTION,
                "band_rad_per_s": list(self.band),
                "pairs": [p.to_dict() for p in self.pairs]}


# --------------------------------------------------------------------------------------
# Building them
# --------------------------------------------------------------------------------------
def transfer_functions(model: Model | str, sources: Sequence[str],
                       outputs: Sequence[str] | None = None,
                       latitude: float = np.radians(50.0), longitude: float = np.radians(30.0),
                       heading: float = 0.0, height: float = 0.0,
                       parameters: Mapping[str, float] | None = None,
                       magnitudes: Mapping[str, float] | None = None) -> TransferFunctions:
    """The transfer functions of ``sources`` to ``outputs`` of ``model`` at a static base.

    Parameters
    ----------
    model : Model or str
        A loaded model, a model name or a model file.
    sources : sequence of str
        Error sources (at least one).
    outputs : sequence of str, optional
        Outputs, or error states read directly (default: every output of the model).
    latitude, longitude : float
        Position of the base, rad (as ``ins-errors modes``: 50°, 30°).
    heading : float
        Track angle of the model's trihedron, rad.
    height : float
        Height of the base, m.
    parameters : mapping of str to float, optional
        Model parameters to set, SI.
    magnitudes : mapping of str to float, optional
        Size of a source for the long-run values, SI (default: one of its display unit,
        e.g. 1 µg).

    Returns
    -------
    TransferFunctions

    Raises
    ------
    InsErrorsError
        No source, an unknown model, source, output or parameter, a latitude at a pole,
        F not finite.

    Examples
    --------
    >>> from ins_errors.analysis.transfer import transfer_functions
    >>> tf = transfer_functions("examples/own_model/schuler_loop.py", ["accel_bias"],
    ...                         ["psi"])  # doctest: +SKIP
    >>> tf.pairs[0].long_run.coefficient  # tilt per unit bias: 1/g  # doctest: +SKIP
    0.10197...
    """
    model = as_model(model, "transfer_functions")
    if not sources:
        raise InsErrorsError(f"transfer_functions: give at least one error source of "
                             f"{model.name}")
    modes = static_modes(model, latitude, longitude, heading, height, parameters)
    return transfer_at_base(model, modes, sources, outputs, magnitudes)


def pair_names(model: Model, sources: Iterable[str], outputs: Iterable[str] | None
               ) -> tuple[list[str], list[str]]:
    """The sources and outputs checked (unknown names refused with suggestions, repeats
    dropped); outputs default to every output of the model.

    Raises
    ------
    UnknownNameError
        A source, output or error state the model does not have.
    InsErrorsError
        No source.
    """
    sources = list(dict.fromkeys(sources))
    if not sources:
        raise InsErrorsError(f"give at least one error source of {model.name}")
    for name in sources:
        model.index("sources", name)
    outputs = [o.name for o in model.outputs] if outputs is None else list(
        dict.fromkeys(outputs))
    known = [o.name for o in model.outputs] + [s.name for s in model.error_states]
    for name in outputs:
        if name not in known:
            raise unknown_name(f"output or error state of {model.name}", name, known)
    if not outputs:
        raise InsErrorsError(f"{model.name} has no outputs: name an error state as the "
                             f"output ({', '.join(s.name for s in model.error_states)})")
    return sources, outputs


def transfer_at_base(model: Model, modes: StaticModes, sources: Sequence[str],
                     outputs: Sequence[str] | None = None,
                     magnitudes: Mapping[str, float] | None = None) -> TransferFunctions:
    """The transfer functions at the base ``modes`` was computed at.

    Parameters
    ----------
    model : Model
        The model of ``modes``.
    modes : StaticModes
        :func:`~ins_errors.analysis.modes.modes_at_rest` of the base (with its ``point``).
    sources, outputs, magnitudes
        As :func:`transfer_functions`.

    Returns
    -------
    TransferFunctions
    """
    from ins_errors.units import display_scale, parse_quantity

    sources, outputs = pair_names(model, sources, outputs)
    given = {k: v for k, v in (magnitudes or {}).items() if k in sources}
    model.source_vector(**given)  # finite, within what a run can mean
    point = modes.point
    if point is None:
        raise InsErrorsError("transfer_at_base: the modes carry no rest point "
                             "(build them with modes_at_rest)")
    F = modes.state_matrix
    G = np.asarray(model.source_matrix(point.x, point.u, point.p), dtype=float)
    E = np.asarray(model.initial_error_matrix(point.c, point.u, point.p), dtype=float)
    H = np.asarray(model.output_matrix(point.x, point.u, point.p), dtype=float)
    output_names = [o.name for o in model.outputs]
    band = frequency_band(modes)
    reductions: dict[int, _Reduction] = {}
    pairs = []
    for source in sources:
        info = model.source(source)
        j = model.index("sources", source)
        column = E[:, j] if info.kind == "initial" else G[:, j]
        shown = info.display_unit or info.unit
        size = 1.0 if shown == info.unit else parse_quantity(f"1 {shown}", info.unit)
        b = float(given.get(source, size))
        for output in outputs:
            if output in output_names:
                row, unit = H[output_names.index(output)], model.outputs[
                    output_names.index(output)].unit
            else:
                k = model.index("error_states", output)
                row, unit = np.eye(len(F))[k], model.error_states[k].unit
            factor, display = display_scale(unit)
            reference = _Reference(F, point.factors, column, row, band)
            tried = []
            if markov_zero(F, column, row):  # proved: no reduction needed
                everything = tuple(Factor(m.eigenvalue, m.multiplicity, m.name)
                                   for m in modes.modes)
                pair = TransferFunction(source, output, info.kind or "constant", info.unit,
                                        unit, shown, display, 0.0, 0, (), (), len(F),
                                        everything, b, 0.0, (factor, size))
                pairs.append(pair)
                continue
            for k, (balanced, tolerance) in enumerate(REDUCTIONS):
                if k not in reductions:
                    reductions[k] = _Reduction(F, point.factors, modes, balanced, tolerance)
                gain, degree, zeros, poles, cancelled = reductions[k].factor(column, row)
                pair = TransferFunction(source, output, info.kind or "constant", info.unit,
                                        unit, shown, display, gain, degree, zeros, poles,
                                        len(F), cancelled, b, 0.0, (factor, size))
                if pair.is_zero:  # not proved zero by its Markov parameters
                    pair = replace(pair, negligible=reference.negligible,
                                   check_error=0.0 if reference.negligible else 1.0)
                else:
                    pair = replace(pair, check_error=reference.error(pair))
                tried.append(pair)
                if pair.check_error <= CHECK_LIMIT:
                    break
            else:
                pair = min(tried, key=lambda p: p.check_error)
            if pair.check_error > REFUSE_LIMIT:
                raise DomainError(
                    f"transfer: {source} → {output} of {model.name} cannot be resolved at "
                    f"the {modes.base}: the factored forms differ from h (iωI − F)⁻¹ g by "
                    f"{pair.check_error:.1e} of its size at best (F too ill-conditioned "
                    "there, e.g. near a pole, where the formulas grow as tan φ)")
            pairs.append(pair)
    return TransferFunctions(modes, tuple(pairs), band)


def frequency_band(modes: StaticModes) -> tuple[float, float]:
    """(lowest, highest) frequency covering F's modes, rad/s: two decades beyond its
    smallest and largest non-zero |λ| (1e-7 to 1e-1 rad/s when F has none)."""
    sizes = np.abs(modes.eigenvalues)
    radius = float(sizes.max()) if sizes.size else 0.0
    sizes = sizes[sizes > ZERO * radius] if radius > 0 else sizes[:0]
    if not sizes.size:
        return 1e-7, 1e-1
    return float(sizes.min() / 100), float(sizes.max() * 100)


class _Reference:
    """h (iωI − F)⁻¹ g of the whole F at :data:`CHECK_FREQUENCIES` frequencies of the
    band (placed off the decades, away from any mode's exact frequency), and the size its
    rounding can reach there: the componentwise bound |h R| |F| |R g| + |h R| |g| +
    |h| |R g| (R = (iωI − F)⁻¹, absolute values entry by entry), by which W moves when
    every entry of F, g and h moves by its own relative share. Unlike a bound on norms
    it does not change when a state is measured in another unit, so a coupling that
    only a badly scaled F (near a pole: entries growing as tan φ against others going
    with cos φ) makes small is not taken for rounding. ``negligible``: W is below
    :data:`TOLERANCE` of the smaller of |h R| |g| and |h| |R g| (2-norms, the states in
    the units of the Schuler loop: how large the output's response to a unit impulse of
    any state is, and the states' response to the source), the largest of the band: a
    coupling weaker than the reductions' tolerance (as one going with sin φ within
    about 1e-7° of the equator)."""

    def __init__(self, F: np.ndarray, factors: np.ndarray, g: np.ndarray, h: np.ndarray,
                 band: tuple[float, float]):
        self.omegas = np.geomspace(band[0] * 1.37, band[1] / 1.41, CHECK_FREQUENCIES)
        scaled = factors[:, None] * F / factors[None, :]
        b, c = factors * g, h / factors
        identity = np.eye(len(F))
        whole, bound, norms = [], [], []
        for w in self.omegas:
            resolvent = 1j * w * identity - scaled
            right = np.linalg.solve(resolvent, b)
            left = np.linalg.solve(resolvent.T, c)
            whole.append(c @ right)
            bound.append(np.abs(left) @ np.abs(scaled) @ np.abs(right)
                         + np.abs(left) @ np.abs(b) + np.abs(c) @ np.abs(right))
            norms.append(min(np.linalg.norm(left) * np.linalg.norm(b),
                             np.linalg.norm(c) * np.linalg.norm(right)))
        self.whole = np.array(whole)
        self.bound = float(max(bound))
        self.size = max(float(np.abs(self.whole).max()), CHECK_FLOOR * self.bound)
        self.negligible = bool(float(np.abs(self.whole).max())
                               <= TOLERANCE * float(max(norms)))

    def error(self, pair: TransferFunction) -> float:
        """The largest difference of ``pair``'s factored form from h (iωI − F)⁻¹ g,
        relative to the larger of the latter's size and :data:`CHECK_FLOOR` of the
        componentwise bound (0 when both are zero)."""
        if self.size == 0.0:
            return 0.0
        return float(np.abs(pair(1j * self.omegas) - self.whole).max() / self.size)


def markov_zero(F: np.ndarray, g: np.ndarray, h: np.ndarray,
                tolerance: float = TOLERANCE) -> bool:
    """True when h (sI − F)⁻¹ g is zero: every Markov parameter h Fᵏ g, k < n, within
    ``tolerance`` of its componentwise bound |h| |F|ᵏ |g| (the size rounding of F's, g's
    and h's entries can give it; the same in any units of the states, unlike
    |h| ‖Fᵏ‖ |g|, which near a pole grows with F's tan φ entries while the couplings
    that carry W go with cos φ). A path whose bound is exactly zero is structurally
    absent."""
    v, bound = np.asarray(g, dtype=float), np.abs(g)
    A = np.abs(F)
    for _ in range(len(g)):
        size = float(np.abs(h) @ bound)
        if size and abs(float(h @ v)) > tolerance * size:
            return False
        v, bound = F @ v, A @ bound
        top = float(bound.max()) if bound.size else 0.0
        if top == 0.0:
            return True
        if top > 1e100 or top < 1e-100:  # rescale both alike: the ratio is what counts
            v, bound = v / top, bound / top
    return True


class _Reduction:
    """The minimal realisation and factored form of each pair of one F.

    The states are measured in the units of the Schuler loop (``factors``: x̂ = D x;
    ``balanced``: then evened out by a diagonal similarity, :data:`REDUCTIONS`) and time
    in units of 1/‖D F D⁻¹‖, so that ``tolerance`` is a share of 1.
    """

    def __init__(self, F: np.ndarray, factors: np.ndarray, modes: StaticModes,
                 balanced: bool = False, tolerance: float = TOLERANCE):
        self.D = np.asarray(factors, dtype=float)
        self.tolerance = tolerance
        scaled = self.D[:, None] * F / self.D[None, :]
        if balanced:
            from scipy.linalg import matrix_balance

            scale = matrix_balance(scaled, permute=False, separate=True)[1][0]
            scale = np.clip(scale, 2.0 ** -BALANCE_LIMIT, 2.0 ** BALANCE_LIMIT)
            self.D = self.D / scale
            scaled = scaled * scale[None, :] / scale[:, None]
        self.rho = float(np.linalg.norm(scaled, 2)) or 1.0
        self.A = scaled / self.rho
        self.modes = modes
        radius = float(np.abs(modes.eigenvalues).max()) if len(modes.eigenvalues) else 0.0
        self.group_tolerance = ZERO * radius if radius > 0 else np.finfo(float).tiny

    def factor(self, g: np.ndarray, h: np.ndarray):
        """(K, relative degree, zeros, poles, cancelled modes) of h (sI − F)⁻¹ g."""
        b, c = self.D * g, h / self.D
        b_size, c_size = float(np.linalg.norm(b)), float(np.linalg.norm(c))
        everything = self._cancelled([])
        if b_size == 0.0 or c_size == 0.0:
            return 0.0, 0, (), (), everything
        A, b, c, defect = _minimal(self.A, b / b_size, c / c_size, self.tolerance)
        if A.shape[0] == 0:
            return 0.0, 0, (), (), everything
        degree, markov = relative_degree(A, b, c, self.tolerance)
        if degree == 0:
            return 0.0, 0, (), (), everything
        zeros, zero_errors = _roots(zero_dynamics_matrix(A, b, c, degree, markov), defect)
        poles, pole_errors = _roots(A, defect)
        gain = b_size * c_size * markov * self.rho ** (degree - 1)
        tol = self.group_tolerance
        zero_groups = _close_groups(self.rho * zeros, self.rho * zero_errors, tol)
        pole_groups = _close_groups(self.rho * poles, self.rho * pole_errors, tol)
        zero_groups, pole_groups = _cancel(zero_groups, pole_groups, CANCEL)
        zero_factors = tuple(Factor(v, m) for v, m in sorted(zero_groups, key=_root_order))
        pole_factors = self._split_names(tuple(
            Factor(v, m, self._name(v)) for v, m in sorted(pole_groups, key=_root_order)))
        return gain, degree, zero_factors, pole_factors, self._cancelled(pole_factors)

    def _split_names(self, poles: tuple[Factor, ...]) -> tuple[Factor, ...]:
        """Two distinct poles that ``modes`` took for one repeated Schuler pair (its
        grouping, 1e-6 of F's largest |λ|, merges the Foucault split within about 1e-4°
        of the equator) are named Schuler − Foucault and Schuler + Foucault when half their
        difference is Ω|sin φ| (within :data:`~ins_errors.analysis.modes.FOUCAULT_MATCH`)."""
        from ins_errors.analysis.modes import FOUCAULT_MATCH

        rate = self.modes.references.foucault
        pair = [k for k, f in enumerate(poles) if f.name == "Schuler" and f.value.imag]
        if len(pair) != 2 or not rate:
            return poles
        low, high = (poles[k] for k in pair)
        half = (high.value.imag - low.value.imag) / 2
        if abs(half - rate) > FOUCAULT_MATCH * rate:
            return poles
        out = list(poles)
        out[pair[0]] = replace(low, name="Schuler − Foucault")
        out[pair[1]] = replace(high, name="Schuler + Foucault")
        return tuple(out)

    def _match(self, value: complex) -> Mode | None:
        best = min(self.modes.modes, key=lambda m: abs(m.eigenvalue - value), default=None)
        if best is not None and abs(best.eigenvalue - value) <= 100 * self.group_tolerance:
            return best
        return None

    def _name(self, value: complex) -> str:
        from ins_errors.analysis.modes import _kind

        mode = self._match(value)
        return mode.name if mode is not None else _kind(value)

    def _cancelled(self, poles: Sequence[Factor]) -> tuple[Factor, ...]:
        """The modes of F (with their multiplicities) not among ``poles``."""
        kept: dict[int, int] = {}
        for pole in poles:
            mode = self._match(pole.value)
            if mode is not None:
                key = self.modes.modes.index(mode)
                kept[key] = kept.get(key, 0) + pole.multiplicity
        out = []
        for k, mode in enumerate(self.modes.modes):
            left = mode.multiplicity - kept.get(k, 0)
            if left > 0:
                out.append(Factor(mode.eigenvalue, left, mode.name))
        return tuple(out)


def _root_order(group: tuple[complex, int]) -> tuple[float, float]:
    """Roots by size, the decaying before the growing of the same size."""
    return abs(group[0]), group[0].real


def _cancel(zeros: list[tuple[complex, int, float]], poles: list[tuple[complex, int, float]],
            share: float) -> tuple[list[tuple[complex, int]], list[tuple[complex, int]]]:
    """Zeros and poles (root, multiplicity, accuracy) without the pairs closer than
    ``share`` of the pole's size or than their accuracies together (equal, at 0)."""
    zeros, kept = [list(z) for z in zeros], []
    for pole, count, error in poles:
        for zero in zeros:
            if zero[1] and abs(zero[0] - pole) <= max(share * abs(pole), error + zero[2]):
                common = min(zero[1], count)
                zero[1] -= common
                count -= common
        if count:
            kept.append((pole, count))
    return [(z, m) for z, m, _ in zeros if m], kept


GROUP_SAFETY = 100.0
"""Two computed roots are one (repeated) root when they are closer than this many times
the larger of their first-order accuracies κ δ ‖M‖ (:func:`_roots`). A repeated root of a
minimal realisation is a Jordan block, which rounding splits into roots a few times
their κ δ ‖M‖ apart; two distinct roots are apart by far more than theirs (the two
Schuler ± Foucault pairs within 1e-4° of the equator, 1e-7 of their size apart, stay
two)."""


def _roots(M: np.ndarray, defect: float) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues of ``M`` and the accuracy of each: κ δ ‖M‖, κ the eigenvalue's
    condition number (1/|yᴴx| of its unit left and right eigenvectors) and δ the
    relative size of what made ``M`` (``defect``, at least the rounding of n
    operations)."""
    from scipy.linalg import eig

    if M.shape[0] == 0:
        return np.zeros(0, dtype=complex), np.zeros(0)
    values, left, right = eig(M, left=True, right=True)
    overlap = np.abs(np.sum(left.conj() * right, axis=0))
    with np.errstate(divide="ignore"):
        kappa = np.where(overlap > 0, 1.0 / overlap, np.inf)
    size = max(float(np.linalg.norm(M, 2)), 1.0)
    delta = max(defect, len(M) * np.finfo(float).eps)
    return values, np.minimum(kappa * delta * size, size)


def _close_groups(values: np.ndarray, errors: np.ndarray, tol: float
                  ) -> list[tuple[complex, int, float]]:
    """(root with Im >= 0, multiplicity, accuracy) of each distinct root, by increasing
    size: roots within :data:`GROUP_SAFETY` times the larger of their accuracies are one
    (their mean: a Jordan block's split roots average to it), a real or imaginary part
    below ``tol`` or that accuracy is zero."""
    groups: list[list] = []
    for value, error in sorted(zip(values, errors, strict=True),
                               key=lambda p: (abs(p[0]), p[0].imag)):
        reach = GROUP_SAFETY * error
        if value.imag < -max(tol, reach):
            continue  # counted with its conjugate
        for group in groups:
            if abs(group[0][0] - value) <= max(reach, group[2]):
                group[0].append(value)
                group[2] = max(group[2], reach)
                break
        else:
            groups.append([[value], 1, reach])
    out = []
    for members, _, reach in groups:
        mean = complex(np.mean(members))
        cut = max(tol, reach)
        mean = complex(0.0 if abs(mean.real) <= cut else mean.real,
                       0.0 if abs(mean.imag) <= cut else abs(mean.imag))
        out.append((mean, len(members), reach))
    return sorted(out, key=lambda g: (abs(g[0]), g[0].real))


# --------------------------------------------------------------------------------------
# The numerical pieces (scaled: ‖A‖ ≤ 1, |b| = |c| = 1)
# --------------------------------------------------------------------------------------
def krylov_basis(A: np.ndarray, v: np.ndarray, tolerance: float = TOLERANCE) -> np.ndarray:
    """Orthonormal basis (n, k) of span{v, A v, A² v, ...} (Arnoldi, orthogonalised twice);
    a new direction below ``tolerance`` (× the size of A v) ends it."""
    size = float(np.linalg.norm(v))
    if size <= tolerance:
        return np.zeros((len(v), 0))
    basis = [v / size]
    for _ in range(len(v) - 1):
        w = A @ basis[-1]
        Q = np.column_stack(basis)
        for _ in range(2):
            w = w - Q @ (Q.T @ w)
        size = float(np.linalg.norm(w))
        if size <= tolerance:
            break
        basis.append(w / size)
    return np.column_stack(basis)


def minimal_realisation(A: np.ndarray, b: np.ndarray, c: np.ndarray,
                        tolerance: float = TOLERANCE
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The controllable and observable part of (A, b, c): the same c (sI − A)⁻¹ b.

    The controllable subspace is the Krylov space of (A, b); on it, the observable one
    is that of (Aᵀ, cᵀ) (its complement, the unobservable part, is invariant, so the
    projection keeps the transfer function).
    """
    Q = krylov_basis(A, b, tolerance)
    A1, b1, c1 = Q.T @ A @ Q, Q.T @ b, c @ Q
    P = krylov_basis(A1.T, c1, tolerance)
    return P.T @ A1 @ P, P.T @ b1, c1 @ P


def _minimal(A: np.ndarray, b: np.ndarray, c: np.ndarray, tolerance: float
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """:func:`minimal_realisation` and how far its bases are from invariant subspaces:
    ‖A Q − Q Qᵀ A Q‖ (and the same for the observable part), the relative size of the
    perturbation the reduction made (the couplings it cut)."""
    Q = krylov_basis(A, b, tolerance)
    A1, b1, c1 = Q.T @ A @ Q, Q.T @ b, c @ Q
    P = krylov_basis(A1.T, c1, tolerance)
    defect = 0.0
    if Q.shape[1]:
        defect = float(np.linalg.norm(A @ Q - Q @ A1, 2))
    if P.shape[1]:
        defect = max(defect, float(np.linalg.norm(A1.T @ P - P @ (P.T @ A1.T @ P), 2)))
    return P.T @ A1 @ P, P.T @ b1, c1 @ P, defect


def relative_degree(A: np.ndarray, b: np.ndarray, c: np.ndarray,
                    tolerance: float = TOLERANCE) -> tuple[int, float]:
    """(r, c A^(r−1) b): the first Markov parameter above ``tolerance``; (0, 0) if none
    (W = 0)."""
    v = b.copy()
    for r in range(1, len(b) + 1):
        markov = float(c @ v)
        if abs(markov) > tolerance:
            return r, markov
        v = A @ v
    return 0, 0.0


def zero_dynamics_matrix(A: np.ndarray, b: np.ndarray, c: np.ndarray, degree: int,
                         markov: float) -> np.ndarray:
    """The matrix whose eigenvalues are the invariant zeros of a minimal SISO (A, b, c)
    of relative degree ``degree``: A − b (c A^r)/(c A^(r−1) b) on the kernel of c, c A,
    ..., c A^(r−1) (the motions that keep the output at zero); (0, 0) when r = n."""
    n = len(b)
    if degree >= n:
        return np.zeros((0, 0))
    rows = [c]
    for _ in range(degree):
        rows.append(rows[-1] @ A)
    observability = np.vstack(rows[:degree])
    kernel = np.linalg.svd(observability)[2][degree:].T  # (n, n − r)
    closed = A - np.outer(b, rows[degree]) / markov
    return kernel.T @ closed @ kernel


def zero_dynamics(A: np.ndarray, b: np.ndarray, c: np.ndarray, degree: int,
                  markov: float) -> np.ndarray:
    """The invariant zeros of a minimal SISO (A, b, c) of relative degree ``degree``
    (the eigenvalues of :func:`zero_dynamics_matrix`)."""
    M = zero_dynamics_matrix(A, b, c, degree, markov)
    return np.linalg.eigvals(M) if M.size else np.zeros(0, dtype=complex)


# --------------------------------------------------------------------------------------
# Words
# --------------------------------------------------------------------------------------
def _display_value(pair: TransferFunction, value_si: float, per_hours: int = 0) -> str:
    """An output value (per h^per_hours) in the output's display unit; an angle in the
    arcsec, arcmin or deg it reads best in."""
    from ins_errors.units import parse_quantity, readable_angle_unit

    value = value_si * 3600.0 ** per_hours
    factor, unit = pair.display_factors[0], pair.output_display
    if unit in ("arcsec", "arcmin", "deg"):
        unit = readable_angle_unit(value, unit, down=True)
        factor = 1.0 / parse_quantity(f"1 {unit}", pair.output_unit)
    per = "" if per_hours == 0 else f"/h{superscript(per_hours)}"
    return f"{value * factor:.4g} {unit}{per}"


def magnitude_text(pair: TransferFunction) -> str:
    """The source's size in its display unit (``"1 ug"``)."""
    size = pair.display_factors[1]
    return f"{pair.magnitude / size:.4g} {pair.source_display}"


def long_run_text(pair: TransferFunction) -> str:
    """The long run in words, with its number in the output's display unit."""
    run = pair.long_run
    what = (("constant source " if pair.source_kind != "initial" else "initial error ")
            + f"{pair.source} = {magnitude_text(pair)}")
    if run.kind == "none":
        return f"{pair.output} does not respond to {pair.source} (W = 0)"
    if run.kind == "exponential":
        growth = run.growth
        power = f" · t{superscript(run.power)}" if run.power else ""
        return (f"{what}: {pair.output} grows exponentially, ≈ "
                f"{_display_value(pair, run.coefficient * pair.magnitude, run.power)}"
                f"{power} · e^(t/{_duration(growth.time_constant_s)}), the {growth.name} "
                "mode" + (f" (period {_duration(growth.period_s)})" if growth.period_s else ""))
    waves = "; ".join(f"{o.name} (period {_duration(o.period_s)}, amplitude "
                      f"{_display_value(pair, abs(o.amplitude * pair.magnitude))}"
                      + (f", decay {_duration(o.decay_s)}" if o.decay_s else "") + ")"
                      for o in run.oscillations)
    settling = ("" if not run.settling_s else
                f"; its damped terms below 1 % of its largest term after about "
                f"{_duration(run.settling_s)}")
    if run.kind == "resonance":
        text = (f"{what}: {pair.output} oscillates with an amplitude growing as "
                f"t{superscript(run.power)} (repeated {run.growth.name} pair, period "
                f"{_duration(run.growth.period_s)})")
        if run.coefficient is not None:
            text += (f" and grows as t{superscript(run.power)}, ≈ "
                     f"{_display_value(pair, run.coefficient * pair.magnitude, run.power)}"
                     f" · t{superscript(run.power)}")
        return text + (f"; oscillations: {waves}" if waves else "")
    if run.kind == "power":
        value = run.coefficient * pair.magnitude
        head = (f"{what}: {pair.output} grows as t{superscript(run.power)}, "
                f"≈ {_display_value(pair, value, run.power)} · t{superscript(run.power)}"
                f" (lim s→0 s{superscript(run.power + 1)}·Y(s)"
                + (f"/{run.power}!)" if run.power > 1 else ")"))
        return head + (f", with oscillations: {waves}" if waves else "") + settling
    value = 0.0 if run.kind == "zero" else run.coefficient * pair.magnitude
    limit = "lim s→0 s·Y(s)" + (" = b·W(0)" if pair.source_kind != "initial" else "")
    if run.settles:
        verb = "settles at"
    elif run.oscillations:
        verb = "oscillates about"
    else:
        verb = "tends to"
    text = f"{what}: {pair.output} {verb} {_display_value(pair, value)} ({limit})"
    if run.settles and run.settling_s and value != 0:
        settling = f", within 1 % after about {_duration(run.settling_s)}"
    return text + settling + (f"; oscillations: {waves}" if waves else "")


def _duration(seconds: float | None) -> str:
    from ins_errors.time_text import duration_text

    return "–" if seconds is None else duration_text(seconds)
