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
units of the Schuler loop (:func:`~ins_errors.analysis.modes.schuler_loop_scales`) and F divided by
its norm, a direction being zero below
:data:`~ins_errors.analysis.transfer_reduction.TOLERANCE`
(:mod:`~ins_errors.analysis.transfer_reduction` does the numbers). The poles are the
eigenvalues of the minimal F; the zeros those of its zero dynamics; the gain K its first
non-zero Markov parameter h F^(r−1) g (r the relative degree), so that::

    W(s) = K (s − z₁)…(s − z_(n−r)) / ((s − p₁)…(s − p_n))

Two computed roots are one repeated root only within
:data:`~ins_errors.analysis.transfer_reduction.GROUP_SAFETY` times their accuracy (a
Jordan block's rounding split), so a close but distinct pair (the Foucault split within
1e-4° of the equator) stays two. A zero within
:data:`~ins_errors.analysis.transfer_reduction.CANCEL` of a pole (or within their
accuracies) cancels it too, a real root only a real one and a pair only a pair.

A growing mode is never cancelled for being weak: its part in the response, however
small, overtakes every bounded term. F's growing modes (strapdown_ned's undamped
vertical channel) are split off the rest
(:class:`~ins_errors.analysis.transfer_reduction.GrowingSplit`: an ordered Schur form
made block diagonal), and a pair keeps each one the source reaches and the output
sees beyond rounding, with a zero beside it where the rest of W nearly cancels it (at
0.5° from the equator, 5e-10 of the pole away); its residue comes from the split (on
balanced states), not from the factored form, whose K Π(p − z)/Π(p − q) loses the
digits of p − z. A pair whose every other part is below the tolerance keeps the
growing part alone (:attr:`TransferFunction.negligible`). Each pole is named as
``modes`` names F's eigenvalue it is (Schuler, Schuler ± Foucault, Earth, vertical
channel, integrator, ...), and each mode of F the pair does not see is listed as
cancelled.

W = 0 is proved by the Markov parameters h Fᵏ g, k < n, against their componentwise
bounds (:func:`~ins_errors.analysis.transfer_reduction.markov_zero`) and, where F has
a growing mode, by its residue being zero to rounding too; a reduction that
finds nothing where they say otherwise is not taken, except for a W below the tolerance
of what the norms allow (``negligible``, :class:`_Reference`).

The factored form is checked against h (iωI − F)⁻¹ g of the whole F at frequencies
across the band (:attr:`TransferFunction.check_error`); a form off by more than
:data:`CHECK_LIMIT` is made again with a finer tolerance, then on balanced states
(:data:`REDUCTIONS`: near the equator couplings go with sin φ, near a pole F's entries
with tan φ), and a pair none brings within :data:`REFUSE_LIMIT` is refused in one line.

The long run of the response to a source of size b follows from the partial fractions
of Y(s) (:meth:`TransferFunction.partial_fractions`): a pole of Y at 0 of order m ≥ 2
makes it grow as t^(m−1); of order 1 it oscillates about (or settles at) the constant
lim s→0 s·Y(s), b·W(0) for a constant source; a pole in the right half-plane makes it
grow exponentially, and beside it the other terms are kept as a bounded response's
(:attr:`LongRun.rest`: an undamped vertical channel's growth starts at 1e-6 of the
Schuler oscillations about ∇/g and overtakes them only after hours,
:attr:`LongRun.overtakes_s`). The words, the factored form and the report are
:mod:`ins_errors.analysis.transfer_text`'s.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ins_errors.analysis.modes import ZERO, Mode, StaticModes, static_modes
from ins_errors.analysis.transfer_reduction import (
    TOLERANCE,
    Reduction,
    group_tolerance,
    markov_zero,
)
from ins_errors.errors import DomainError, InsErrorsError, name_list, unknown_name
from ins_errors.numeric.model import Model, as_model

REDUCTIONS = ((False, TOLERANCE), (False, 1e-12), (True, 1e-12))
"""The reductions tried in turn, (balanced, tolerance), until one passes the check
(:data:`CHECK_LIMIT`): the states in the units of the Schuler loop, then with a finer
tolerance (a coupling weaker than 1e-9, as near the equator where it goes with sin φ),
then also balanced (a diagonal similarity that evens out F's rows and columns, LAPACK
gebal, its factors within
2^±:data:`~ins_errors.analysis.transfer_reduction.BALANCE_LIMIT`: near a pole F's
entries grow as tan φ)."""

SLOW_DECAY = 1.0
"""A damped oscillation whose decay time is at least this many of its periods (damping
ratio below about 0.16) is listed in the long run with its amplitude and decay time: it
rings for several periods, and a lightly damped Schuler pair (ζ ~ 1e-4 from a damped
vertical channel) for months."""

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
    mode_multiplicity : int or None
        For a cancelled mode: its multiplicity in F (more than ``multiplicity`` when the
        pair keeps some of it: at the equator one of the two Schuler pairs); None for a
        zero or a pole.
    """

    value: complex
    multiplicity: int
    name: str | None = None
    mode_multiplicity: int | None = None

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

    def to_dict(self) -> dict:
        from ins_errors.analysis.transfer_text import factor_text

        return {"real": self.value.real, "imag": self.value.imag,
                "multiplicity": self.multiplicity, "name": self.name,
                "period_s": self.period_s, "time_constant_s": self.time_constant_s,
                "factor": factor_text(self)}


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
        The undamped oscillations about it (simple poles on the imaginary axis) and the
        slowly damped ones (:data:`SLOW_DECAY`); of the exponential kind, those of
        :attr:`rest`.
    growth : Factor or None
        The fastest growing pole (exponential kind) or the repeated pair (resonance).
    settles : bool
        True when every pole of Y other than 0 is damped (the response settles).
    settling_s : float or None
        When every damped term has fallen below 1 % of the value the response settles
        at (of its largest term where that is zero), s (None without a damped term).
    rest : LongRun or None
        Of the exponential kind: the long run of the other terms (the poles not in the
        right half-plane), which the response follows until the growth overtakes them,
        e.g. the Schuler oscillations about ∇/g beside an undamped vertical channel;
        None otherwise. Its oscillations are also :attr:`oscillations`.
    overtakes_s : float or None
        Of the exponential kind: when the growing term reaches the largest size of the
        other terms (the size of :attr:`rest`'s level plus its undamped amplitudes), s;
        None when those grow too or are zero (0 when it is larger from the start).
    """

    kind: str
    power: int
    coefficient: float | None
    oscillations: tuple[Oscillation, ...] = ()
    growth: Factor | None = None
    settles: bool = False
    settling_s: float | None = None
    rest: LongRun | None = None
    overtakes_s: float | None = None

    @property
    def bounded_size(self) -> float | None:
        """Per unit source, the largest size a bounded long run reaches: the size of the
        level plus the amplitudes of its undamped oscillations (output SI unit per source
        SI unit); None for one that grows."""
        if self.kind not in ("constant", "zero", "none"):
            return None
        level = abs(self.coefficient) if self.kind == "constant" else 0.0
        return level + sum(o.amplitude for o in self.oscillations if o.decay_s is None)


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
        W below :data:`TOLERANCE` of the size the norms allow (:class:`_Reference`), a
        coupling weaker than the reductions' tolerance, yet not zero (its Markov
        parameters are not all zero to rounding): W = 0 is given, or, where the source
        reaches a growing mode that the output sees, that mode's part alone (it
        overtakes every bounded term, and is exact: :attr:`growing_residues`).
    growing_residues : tuple of (complex, complex)
        (pole, residue of W there, SI) of the simple growing poles, from F's growing
        modes split off the rest (:class:`~ins_errors.analysis.transfer_reduction.
        GrowingSplit`): the partial fractions take them instead of the factored form's
        K Π(p − z)/Π(p − q), which loses its digits where a zero nearly cancels the pole
        (strapdown_ned's vertical channel in a horizontal output near the equator).
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
    growing_residues: tuple[tuple[complex, complex], ...] = ()

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
        exact = {p: r for p, r in self.growing_residues}
        exact.update({p.conjugate(): r.conjugate() for p, r in self.growing_residues})
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
            if m == 1 and exact.get(pole) is not None:  # a growing pole: its own residue
                series = np.array([exact[pole] if self.source_kind == "initial"
                                   else exact[pole] / pole])
                if not pole.imag:
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
        rest = self._bounded_run(fractions)
        unstable = [f for f in self.poles if f.value.real > 0]
        if not unstable:
            return rest
        fastest = max(unstable, key=lambda f: f.value.real)
        leading = fractions[fastest.value][-1]
        size = float(leading.real if not fastest.value.imag else 2 * abs(leading))
        power = fastest.multiplicity - 1
        coefficient = size / math.factorial(power)
        overtakes = _overtakes(abs(coefficient), power, fastest.time_constant_s,
                               rest.bounded_size)
        return LongRun("exponential", power, coefficient, rest.oscillations,
                       growth=fastest, rest=rest, overtakes_s=overtakes)

    def _bounded_run(self, fractions: dict) -> LongRun:
        """The long run of the terms of the poles not in the right half-plane (all of
        them when there is none)."""
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
    def gain_display(self) -> float:
        """K in the output's display unit per the source's display unit, per
        s^:attr:`seconds_power` (its unit:
        :func:`~ins_errors.analysis.transfer_text.gain_unit`)."""
        output_factor, source_size = self.display_factors
        return self.gain * output_factor * source_size

    def to_dict(self) -> dict:
        from ins_errors.analysis.transfer_text import factored_text, gain_unit, long_run_text

        run = self.long_run
        return {
            "source": self.source, "output": self.output, "source_kind": self.source_kind,
            "source_unit": self.source_unit, "output_unit": self.output_unit,
            "source_display_unit": self.source_display,
            "output_display_unit": self.output_display,
            "gain": self.gain, "gain_display": self.gain_display,
            "gain_display_unit": gain_unit(self),
            "relative_degree": self.relative_degree, "order": self.order,
            "full_order": self.full_order, "factored": factored_text(self),
            "zeros": [f.to_dict() for f in self.zeros],
            "poles": [f.to_dict() for f in self.poles],
            "cancelled": [{**f.to_dict(), "mode_multiplicity": f.mode_multiplicity}
                          for f in self.cancelled],
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
                "rest": None if run.rest is None else {
                    "kind": run.rest.kind, "power": run.rest.power,
                    "coefficient": run.rest.coefficient,
                    "value": None if run.rest.coefficient is None
                    else run.rest.coefficient * self.magnitude,
                    "size": None if run.rest.bounded_size is None
                    else run.rest.bounded_size * abs(self.magnitude)},
                "overtakes_s": run.overtakes_s,
                "oscillations": [{"name": o.name, "period_s": o.period_s,
                                  "amplitude": abs(o.amplitude * self.magnitude),
                                  "decay_s": o.decay_s}
                                 for o in run.oscillations],
                "text": long_run_text(self)},
        }


def _overtakes(size: float, power: int, time_constant_s: float,
               bounded: float | None) -> float | None:
    """The time t >= 0 at which ``size`` · t^``power`` · e^(t/``time_constant_s``) first
    reaches ``bounded``, s (0 when it is larger from the start); None when ``bounded`` is
    None or zero, or ``size`` zero.

    Parameters
    ----------
    size : float
        The growing term's coefficient, >= 0 (output unit per s^power).
    power : int
        Its power of t.
    time_constant_s : float
        Its e-folding time, s.
    bounded : float or None
        The size it is to reach (output unit).
    """
    if not bounded or not size:
        return None
    target = math.log(bounded / size)
    if power == 0:
        return max(target, 0.0) * time_constant_s

    def excess(t: float) -> float:  # log of the term over ``bounded``; rises with t
        return power * math.log(t) + t / time_constant_s - target

    low, high = 1e-300, time_constant_s
    while excess(high) < 0:
        low, high = high, 2 * high
    for _ in range(200):
        middle = math.sqrt(low * high) if high / low > 4 else 0.5 * (low + high)
        if excess(middle) < 0:
            low = middle
        else:
            high = middle
        if high - low <= 1e-12 * high:
            break
    return high


def _times_series(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The product of two power series, truncated to the length of ``a``."""
    out = np.zeros(len(a), dtype=complex)
    for i, value in enumerate(a):
        if value == 0:
            continue
        for j in range(min(len(b), len(a) - i)):
            out[i + j] += value * b[j]
    return out


@dataclass(frozen=True, eq=False)
class TransferFunctions:
    """The transfer functions of some sources to some outputs at one static base.

    Compared by identity (``==`` is ``is``; hashable): it holds arrays, whose ``==``
    has no single truth value.

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
        from ins_errors.analysis.transfer_text import CONVENTION

        base = self.modes
        pairs = [p.to_dict() for p in self.pairs]
        for pair in pairs:   # a turning F: W(s) of its first instant has no long run
            pair["long_run"]["holds"] = base.turning is None
        return {"model": base.model, "base": base.base, "latitude_rad": base.latitude,
                "height_m": base.height, "convention": CONVENTION,
                "band_rad_per_s": list(self.band),
                "turning_at_rest": None if base.turning is None else base.turning.to_dict(),
                "pairs": pairs}


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
    sources : sequence of str, or str
        Error sources (at least one; one string is one source).
    outputs : sequence of str, or str, optional
        Outputs, or error states read directly (default: every output of the model;
        one string is one output).
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
    sources = name_list(sources, "transfer_functions: sources")  # one string: one name
    if outputs is not None:
        outputs = name_list(outputs, "transfer_functions: outputs")
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
    sources = list(dict.fromkeys(name_list(sources, "sources")))
    if not sources:
        raise InsErrorsError(f"give at least one error source of {model.name}")
    for name in sources:
        model.index("sources", name)
    outputs = [o.name for o in model.outputs] if outputs is None else list(
        dict.fromkeys(name_list(outputs, "outputs")))
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
    tolerance_1_s = group_tolerance(modes.eigenvalues)
    names = _ModeNames(modes, tolerance_1_s)
    eigenvalues = [m.eigenvalue for m in (*modes.modes, *modes.unseen_modes)]
    reductions: dict[int, Reduction] = {}
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
            if 0 not in reductions:
                reductions[0] = Reduction(F, point.factors, tolerance_1_s, *REDUCTIONS[0],
                                          eigenvalues)
            if markov_zero(F, column, row) and not reductions[0].growing_residues(
                    column, row):  # proved, no growing mode reached: no reduction needed
                pair = TransferFunction(source, output, info.kind or "constant", info.unit,
                                        unit, shown, display, 0.0, 0, (), (), len(F),
                                        names.cancelled(()), b, 0.0, (factor, size))
                pairs.append(pair)
                continue
            for k, (balanced, tolerance) in enumerate(REDUCTIONS):
                if k not in reductions:
                    reductions[k] = Reduction(F, point.factors, tolerance_1_s, balanced,
                                              tolerance, eigenvalues)
                form = reductions[k].factor(column, row)
                zeros = tuple(Factor(v, m) for v, m in form.zeros)
                poles = names.poles(form.poles)
                cancelled = names.cancelled(poles)
                pair = TransferFunction(source, output, info.kind or "constant", info.unit,
                                        unit, shown, display, form.gain, form.degree, zeros,
                                        poles, len(F), cancelled, b, 0.0, (factor, size),
                                        growing_residues=form.residues)
                if pair.is_zero or (form.growing_only and reference.negligible):
                    # not proved zero by its Markov parameters; or all but the growing
                    # modes' part (exact, :class:`GrowingSplit`) below the tolerance
                    pair = replace(pair, negligible=reference.negligible,
                                   check_error=0.0 if reference.negligible else 1.0)
                else:
                    pair = replace(pair, check_error=reference.error(pair))
                # the growing modes alone, the rest not negligible, pass a check whose
                # floor is the rounding of the whole resolvent: a finer reduction may
                # keep that rest (small, but physical: near the equator it goes as sin²φ)
                alone = form.growing_only and not reference.negligible
                tried.append((pair, alone))
                if pair.check_error <= CHECK_LIMIT and not alone:
                    break
            else:  # passing forms first, the growing modes alone after the others
                pair = min(tried, key=lambda t: (t[0].check_error > CHECK_LIMIT, t[1],
                                                 t[0].check_error))[0]
            if pair.check_error > REFUSE_LIMIT:
                raise UnresolvedPairError(model.name, modes, source, output, pair.check_error)
            pairs.append(pair)
    return TransferFunctions(modes, tuple(pairs), band)


class UnresolvedPairError(DomainError):
    """A pair no reduction brings within :data:`REFUSE_LIMIT` of h (iωI − F)⁻¹ g at
    the base: its message names the pair, by how much and why, as far as the base
    tells (near a pole F's entries grow as tan φ; near the equator couplings go with
    sin φ; elsewhere roots of W that rounding leaves too close to tell apart).

    Attributes
    ----------
    source, output : str
        The pair.
    error : float
        The best factored form's :attr:`TransferFunction.check_error`.
    """

    def __init__(self, model: str, modes: StaticModes, source: str, output: str,
                 error: float):
        self.source, self.output, self.error = source, output, error
        latitude = modes.references.latitude  # the base's, or the model's parameter's
        if latitude is not None and abs(math.cos(latitude)) < 1e-3:
            why = "near the pole F's entries grow as tan φ"
        elif latitude is not None and abs(math.sin(latitude)) < 1e-6:
            why = "near the equator its couplings go with sin φ, below what rounding resolves"
        else:
            why = ("its poles and zeros, as rounding leaves them, are too close to tell "
                   "apart there")
        super().__init__(
            f"transfer: {source} → {output} of {model} cannot be resolved at the "
            f"{modes.base}: the factored forms differ from h (iωI − F)⁻¹ g by {error:.1e} "
            f"of its size at best ({why})")


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


class _ModeNames:
    """The names of a pair's poles and of the modes it cancels, as ``modes`` names F's
    eigenvalues: a root within 100 × ``tolerance`` (1/s,
    :func:`~ins_errors.analysis.transfer_reduction.group_tolerance`) of a mode is that
    mode; another is named by its kind (integrator, damped, ...)."""

    def __init__(self, modes: StaticModes, tolerance: float):
        self.modes = modes
        self.group_tolerance = tolerance

    def poles(self, roots: Sequence[tuple[complex, int]]) -> tuple[Factor, ...]:
        """The named pole factors of (root, multiplicity), in their order."""
        return self._split_names(tuple(Factor(v, m, self._name(v)) for v, m in roots))

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
        from ins_errors.analysis.modes import kind_of_eigenvalue

        mode = self._match(value)
        return mode.name if mode is not None else kind_of_eigenvalue(value)

    def cancelled(self, poles: Sequence[Factor]) -> tuple[Factor, ...]:
        """The modes of F (with their multiplicities) not among ``poles``: the INS's own
        modes, then those no error reaches or no output sees (:attr:`~ins_errors.analysis.
        modes.StaticModes.unseen_modes`, named "... (constraint direction)" where no
        error reaches them, "... (seen by no output)" where the errors reach them; a pole
        beyond its own mode's multiplicity is taken from them)."""
        kept: dict[int, int] = {}
        for pole in poles:
            mode = self._match(pole.value)
            if mode is not None:
                key = self.modes.modes.index(mode)
                kept[key] = kept.get(key, 0) + pole.multiplicity
        out = []
        extra: list[tuple[complex, int]] = []
        for k, mode in enumerate(self.modes.modes):
            left = mode.multiplicity - kept.get(k, 0)
            if left > 0:
                out.append(Factor(mode.eigenvalue, left, mode.name, mode.multiplicity))
            elif left < 0:
                extra.append((mode.eigenvalue, -left))
        for mode in self.modes.unseen_modes:
            left = mode.multiplicity
            for j, (value, count) in enumerate(extra):
                if count and abs(value - mode.eigenvalue) <= 100 * self.group_tolerance:
                    taken = min(count, left)
                    left -= taken
                    extra[j] = (value, count - taken)
            if left > 0:
                why = "constraint direction" if not mode.reached else "seen by no output"
                out.append(Factor(mode.eigenvalue, left, f"{mode.name} ({why})",
                                  mode.multiplicity))
        return tuple(out)
