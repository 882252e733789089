"""Check a hand-coded F and G against the derived linear model, entry by entry.

The derived linearisation of a model is sampled along the checker's motions (a static
base, a cruise and a manoeuvre: :mod:`~ins_errors.checker.check_motions`), carried into
the researcher's declared convention (:mod:`~ins_errors.checker.derived_convention`:
``ż = (Ṫ + T F) T⁻¹ z + T G w``) and restricted to the researcher's states, in their
order. Each entry of F and G is then compared with the hand's at every sample.

Sizes follow the hand checker: a term's size is ``|coefficient| × typical magnitude`` of
the state or source it multiplies (:func:`~ins_errors.checker.typical.typical_magnitude`;
a latitude or longitude error is weighed as the position error it is, the typical
position error over the Earth radius: :func:`position_angle_magnitude`);
a discrepancy is measured relative to the largest term of its row (over the hand's and
the model's terms, including every model error source) at the same sample; the largest
ratio over all samples is its *size*, and the sample where it is reached says where along
the motion it matters.

Classes (the vocabulary of :mod:`~ins_errors.checker.classify`):

* ``agrees``: size at most :data:`AGREEMENT`;
* kinds: ``omitted term`` (the hand has nothing), ``extra term`` (the model has nothing),
  ``wrong sign`` (hand/model within :data:`PARTIAL` of −1), ``approximated`` (hand/model
  within :data:`PARTIAL` of 1: part of the coefficient left out, e.g. a constant Earth
  radius for R_N + h, a constant g; where the entry crosses zero, |hand ∓ model| within
  :data:`PARTIAL` of the entry's largest value on each motion), ``wrong coefficient``
  (anything else; a constant ratio is named), ``state left out`` (coupling to a state
  the hand model does not have); an F entry that would be a wrong coefficient but is the
  derived entry less one or two of its terms (:mod:`~ins_errors.checker.matrix_terms`,
  which loads SymPy) is an ``omitted term``, the term named;
* severity: at or above the threshold every kind is a ``mistake``; below it the
  omissions (``omitted term``, ``approximated``, ``state left out``) are a ``dropped small
  term`` and a term that is present but wrong is a ``mistake, small effect``; the
  couplings of a hand model without any vertical-channel state to that channel are
  ``vertical channel left out`` (:data:`NO_VERTICAL`, not a mistake), whatever their size.

Then both linear models are propagated on each motion for 1 h and 24 h from each initial
error (and each error source of G) at its typical magnitude, and the position and
attitude error differences are reported (:mod:`~ins_errors.checker.matrix_effects`),
each against its rounding floor: a difference below it is no effect, and no initial
error or source is named for it. A difference that follows a growing mode of the hand
model past :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings is marked as
exponential growth with the mode's e-folding time
(:func:`~ins_errors.checker.growth.mark_growth`, the equation checker's rule).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from itertools import combinations
from pathlib import Path

import numpy as np

from ins_errors.checker import held_channel
from ins_errors.checker.check_motions import (
    HOURS,
    STEP,
    Motion,
    flown_motions,
    motions,  # noqa: F401  (the checker's motions, as matrix.motions)
    parameter_items,
)
from ins_errors.checker.conventions import NORTH_POSITION, BiasState, Convention, convention
from ins_errors.checker.derived_convention import derived_in_convention
from ins_errors.checker.extreme import first_largest
from ins_errors.checker.kinds import (
    COEFFICIENT,
    DECLARED,
    DROPPED,
    EXTRA,
    MISTAKE,
    OMITTED,
    SIGN,
    SMALL_MISTAKE,
    SYMBOL,
)
from ins_errors.checker.kinds import severity as classify_severity
from ins_errors.checker.matrix_effects import (
    AloneEffect,
    Effect,
    VerticalEffect,
    finding_effects,
    propagate_effects,
    vertical_effects,
)
from ins_errors.checker.matrix_input import (
    HandMatrices,
    callable_hand,
    evaluate_function,
    load_hand,
    read_matrix_file,
    split_spec,
)
from ins_errors.checker.matrix_slips import (
    TRANSPOSED,
    Entry,
    index_slips,
    transposed_block,
    triples,
)
from ins_errors.checker.navigation import require_description
from ins_errors.checker.ratio_names import earth_factors, factor_name, ratio_text, trig_name
from ins_errors.checker.typical import (
    _earth,
    magnitude_override,
    schuler_magnitudes,
    typical_magnitude,
)
from ins_errors.checker.up_states import down_names, in_convention
from ins_errors.errors import InsErrorsError, UnknownNameError, unknown_name
from ins_errors.numeric.blas_threads import one_blas_thread

DEFAULT_THRESHOLD = 1e-3
"""Relative size separating a dropped small term from a mistake."""
AGREEMENT = 1e-6
"""Relative size at or below which two entries agree (rounding, constants' last digits)."""
PARTIAL = 0.05
"""A hand/model ratio within this of 1 is an approximation (within this of −1: a wrong sign)."""
ARCSEC = np.pi / (180 * 3600)
APPROXIMATED = "approximated"
"""Kind of a coefficient the hand writes within :data:`PARTIAL` of the model's (a small
part of it left out: a constant radius for R_N + h, a constant g): an omission."""
LEFT_OUT = "state left out"
"""Kind of the coupling to a convention state the hand model does not have."""
NO_VERTICAL = "vertical channel left out"
"""Severity of a coupling of a horizontal-only hand model (no vertical-channel state of
the convention at all: no dv_D, no dh) to the vertical channel it leaves out: not a
mistake. The effect comparison holds the derived model's vertical channel (its rows and
columns zeroed: it feeds nothing), as the hand does without it, so these couplings have
no effect to assess; one line of the report says so (:attr:`MatrixReport.without_vertical`)."""


# --------------------------------------------------------------------------------------
# Findings
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class EntryFinding:
    """One entry of F or G where the hand model and the derived model differ.

    Attributes
    ----------
    matrix : {"F", "G"}
    row : str
        The equation (state whose derivative the row gives).
    column : str
        The state or error source the entry multiplies.
    kind : str
        ``omitted term``, ``extra term``, ``wrong sign``, ``wrong coefficient`` (with
        ``hand/model = r at every sample`` in ``detail`` for a constant factor),
        ``approximated``, ``state left out``, ``wrong symbol or index`` (a term written on
        the wrong column of its row: :mod:`~ins_errors.checker.matrix_slips`).
    severity : str
        ``mistake``, ``mistake, small effect`` (a wrong term below the threshold) or
        ``dropped small term`` (the severities of :mod:`~ins_errors.checker.classify`),
        or ``vertical channel left out`` (:data:`NO_VERTICAL`).
    size : float
        Largest ratio over the samples of |hand − model| × magnitude to the row's largest
        term.
    size_class : str
        ``major`` (≥ 0.1), ``significant`` (≥ threshold) or ``small``.
    motion : str
        Motion of the sample where ``size`` is reached.
    time : float
        Its time, s.
    hand, model : float
        The two entries at that sample (SI).
    absolute : float
        |hand − model| × magnitude at that sample, in ``unit``.
    unit : str
        Unit of the row's rate (``m/s**2`` for a velocity row).
    per_motion : dict
        Largest ratio on each motion.
    detail : str
        One line (the ratio for a factor, where the term matters).
    block : tuple of (tuple of str) or None
        For a 3×3 block written transposed (one finding for the block, this its largest
        entry): the block's rows and columns (``(("psi_N", "psi_E", "psi_D"),
        ("gyro_bias_x", "gyro_bias_y", "gyro_bias_z"))``); its effect is the whole
        block's. None for a finding of one entry.
    pair : tuple of str or None
        ``(row, column)`` of the other entry merged into this finding, the two differing
        by exactly opposite amounts at every sample (hand − model = +d here, −d there):
        the mirror entry F[column, row] (an antisymmetric term such as a [ω×] of
        Coriolis written with the wrong sign or left out in both, :func:`_merge_pairs`;
        this the larger), or the entry of the same column in the row a term written
        here belongs in (:func:`_merge_rows`). Its effect is the pair's. None otherwise.
    """

    matrix: str
    row: str
    column: str
    kind: str
    severity: str
    size: float
    size_class: str
    motion: str
    time: float
    hand: float
    model: float
    absolute: float
    unit: str
    per_motion: dict[str, float]
    detail: str = ""
    block: tuple[tuple[str, ...], tuple[str, ...]] | None = None
    pair: tuple[str, str] | None = None

    @property
    def entry(self) -> str:
        """``F[row, column]``."""
        return f"{self.matrix}[{self.row}, {self.column}]"


@dataclass
class MatrixReport:
    """Everything the matrix check found.

    Attributes
    ----------
    model, convention, hand_name : str
    states, sources : list of str
        The hand model's states and G's sources.
    threshold : float
    motions : list of (label, description)
        The motions compared along.
    skipped_motions : list of str
        ``"label: reason"`` of each of the checker's motions the model cannot follow (not
        flown, not compared along: a wander-azimuth INS off a meridian); empty when every
        motion is flown or the motions were given.
    magnitudes : dict
        Name -> (typical magnitude SI, text) of every state and source compared.
    findings : list of EntryFinding
        Sorted: mistakes first, then by size.
    compared : int
        Number of entries compared.
    left_out : list of str
        Convention states the hand model does not have.
    out_of_scope : list of str
        Model error sources not in G (not compared; all of them without G).
    effects : list of Effect
    held : list of str
        Vertical-channel states held constant in the propagation (an undamped vertical
        channel diverges with a time constant of about 9.5 min: after 24 h its error
        would swamp every other difference); for states without a vertical channel of
        their own (Earth-fixed states; a strapdown INS's own states, held through its
        φ-angle convention) what is held (:mod:`~ins_errors.checker.held_channel`); for
        a hand model whose vertical channel cannot be held, why it gets no effects.
    finding_effects : dict
        ``entry`` -> :class:`AloneEffect`: the derived model with only that entry replaced
        by the hand's, after 24 h, worst case (:func:`finding_effects`).
    vertical : list of str
        The convention's vertical-channel states (held in ``effects`` and
        ``finding_effects``).
    vertical_effects : dict
        ``entry`` -> :class:`VerticalEffect` of each finding in a vertical-channel row
        (:func:`vertical_effects`); a finding of a horizontal row in a vertical column
        has neither effect (not assessed: the vertical channel is held).
    bias_states : list of BiasState
        Model error sources the hand carries as states (in ``states``; their statistics:
        random constant, or Gauss–Markov with its τ); they are neither in ``sources``
        nor out of scope.
    declarations, idle_declarations : list of str
        The hand's declared simplifications (``@neglect`` of a ``@convention`` file, see
        :class:`DeclaredTerm`), as ``line N: ITEMS (reason)``, and those that explain no
        finding.
    written : dict
        Convention state -> the up component the hand wrote for it (``{"phi_D":
        "phi_U"}``: its row and column read with the sign flipped,
        :mod:`~ins_errors.checker.up_states`); empty when it wrote none.
    convention_hint : str
        With many mistakes (:data:`MANY`), another convention of the model whose states,
        of the same units in the same order, the hand's entries agree with entirely or
        with far fewer mistakes (:func:`_other_convention`): the wrong convention named?
        ``""`` otherwise.
    """

    model: str
    convention: str
    hand_name: str
    states: list[str]
    sources: list[str]
    threshold: float
    motions: list[tuple[str, str]]
    magnitudes: dict[str, tuple[float, str]]
    findings: list[EntryFinding]
    compared: int
    left_out: list[str]
    out_of_scope: list[str]
    effects: list[Effect] = field(default_factory=list)
    held: list[str] = field(default_factory=list)
    finding_effects: dict[str, AloneEffect] = field(default_factory=dict)
    declarations: list[str] = field(default_factory=list)
    idle_declarations: list[str] = field(default_factory=list)
    vertical: list[str] = field(default_factory=list)
    vertical_effects: dict[str, VerticalEffect] = field(default_factory=dict)
    bias_states: list[BiasState] = field(default_factory=list)
    skipped_motions: list[str] = field(default_factory=list)
    convention_hint: str = ""
    written: dict[str, str] = field(default_factory=dict)

    @property
    def mistakes(self) -> list[EntryFinding]:
        """Findings classed as mistakes."""
        return [f for f in self.findings if f.severity in (MISTAKE, SMALL_MISTAKE)]

    @property
    def without_vertical(self) -> list[EntryFinding]:
        """Couplings of a horizontal-only hand model to the vertical channel it leaves
        out (severity :data:`NO_VERTICAL`), largest first; empty otherwise."""
        return [f for f in self.findings if f.severity == NO_VERTICAL]

    @property
    def exit_status(self) -> int:
        """0: no mistake; 1: at least one mistake."""
        return 1 if self.mistakes else 0

    def finding(self, row: str, column: str, matrix: str = "F") -> EntryFinding | None:
        """The finding of one entry, or None if it agrees."""
        for f in self.findings:
            if (f.matrix, f.row, f.column) == (matrix, row, column):
                return f
        return None


def size_class(size: float, threshold: float) -> str:
    """``major`` (≥ 0.1 of the row's largest term), ``significant`` (≥ threshold), ``small``."""
    if size >= 0.1:
        return "major"
    return "significant" if size >= threshold else "small"


def _rate_unit(unit: str) -> str:
    return {"1": "1/s", "rad": "rad/s", "m": "m/s", "m/s": "m/s**2"}.get(unit, f"({unit})/s")


def _within(h: np.ndarray, m: np.ndarray, sign: float, mag: float, scale: np.ndarray,
            motion_of: np.ndarray) -> float | None:
    """Largest |h − sign·m| over the largest |m| on each motion, when it is at most
    :data:`PARTIAL` on every motion (None otherwise).

    A part of a coefficient left out is small against the coefficient where the
    coefficient matters, also where the coefficient itself crosses zero (a transport
    rate −U cos φ − v_E/(R cos² φ) as v_E changes sign) and the sample-by-sample ratio
    means nothing. A motion where both entries are at most the agreement level of
    their row is skipped; one where only the hand has a term is not within.
    """
    worst = 0.0
    for k in np.unique(motion_of):
        on = motion_of == k
        diff = np.abs(h[on] - sign * m[on])
        if np.all(diff * mag <= AGREEMENT * scale[on]):
            continue
        largest = float(np.max(np.abs(m[on])))
        if not float(diff.max()) <= PARTIAL * largest:
            return None
        worst = max(worst, float(diff.max()) / largest)
    return worst


def _sign_on_a_motion(h: np.ndarray, m: np.ndarray, mag: float, scale: np.ndarray,
                      motion_of: np.ndarray, labels: list[str]) -> str:
    """``"hand = −model on motion 'static': ..."`` when the hand entry is minus the
    model's at every sample of one motion where the model's is not 0, else ``""``.

    A sign slip in one term of a sum (Coriolis' 2Ω in an entry that also holds the
    transport rate, after a change of states) is a wrong coefficient on the motions where
    the other terms count, but on the one where that term is the whole entry (at rest)
    the hand's entry is exactly minus the model's: said, the slip is found.
    """
    tiny = AGREEMENT * scale
    for k, label in enumerate(labels):
        on = (motion_of == k) & (np.abs(m) * mag > tiny)
        if on.sum() >= 2 and on.sum() == (motion_of == k).sum() and np.all(
                np.abs(h[on] / m[on] + 1) <= 1e-6):
            return (f"hand = −model on motion {label!r}: the sign of a term that is the whole "
                    "entry there")
    return ""


NEARLY = 0.01
"""Relative spread of hand/model over a motion within which the ratio is named as a
range (:func:`_ratio_by_motion`)."""


def _ratio_by_motion(h: np.ndarray, m: np.ndarray, mag: float, scale: np.ndarray,
                     motion_of: np.ndarray, labels: list[str]) -> str:
    """``"hand/model = 0.5 at every sample on motion 'static', 0.49975 to 0.49986 on
    'cruise', ..."`` for a wrong coefficient whose ratio is constant on one motion at
    least (to 1e-6) and within :data:`NEARLY` of constant on every motion, else ``""``.

    A factor slip in one term of an entry that holds others (g/R for 2g/R in
    F[dv_D, dh], which also holds the transport rate's change with height) is an exact
    factor at rest, where that term is the whole entry, and nearly one on the moving
    motions. A motion where the model's entry is 0 at every sample is left out; where
    it is 0 at a sample and the hand's is not, no ratio is named.
    """
    said = []
    exact = False
    for k, label in enumerate(labels):
        here = motion_of == k
        on = here & (np.abs(m) * mag > AGREEMENT * scale)
        if np.any(here & ~on & (np.abs(h) * mag > AGREEMENT * scale)):
            return ""
        if not on.any():
            continue
        q = h[on] / m[on]
        middle = float(np.median(q))
        spread = float(np.ptp(q))
        if spread <= 1e-6 * abs(middle):
            exact = True
            said.append(f"{middle:.6g} at every sample on {label!r}")
        elif spread <= NEARLY * abs(middle):
            said.append(f"{q.min():.6g} to {q.max():.6g} on {label!r}")
        else:
            return ""
    if not exact or not said:
        return ""
    return ("hand/model = " + ", ".join(said)
            + (" (exact where one term is the whole entry, nearly so where others join "
               "it: a wrong factor of that term?)" if len(said) > 1 else ""))


EVERY_SAMPLE = " at every sample"
"""How the detail of a constant ratio ends (:func:`_classify`)."""


def _named_ratio(h: np.ndarray, m: np.ndarray, mag: float, model_scale: np.ndarray,
                 latitude: np.ndarray, factors: list[tuple[str, float]]) -> str:
    """The detail of a constant hand/model that names it, or ``""``: a factor of the
    Earth radius or gravity, or 2 (:func:`~ins_errors.checker.ratio_names.ratio_text`);
    at one latitude (every sample at the same, ``@scope static base``) a ratio of the
    latitude's functions, tan φ or cot φ (:func:`~ins_errors.checker.ratio_names.
    trig_name`: sin φ and cos φ swapped?). ``latitude`` (S,): rad at each sample (NaN
    where the navigation solution has none); ``model_scale`` (S,): the largest term of
    the model's row, against which its entry is 0."""
    on = np.abs(m) * mag > AGREEMENT * model_scale
    if not on.any():
        return ""
    q = h[on] / m[on]
    ratio = float(np.median(q))
    found = factor_name(ratio, factors)
    if found is not None:
        return ratio_text(ratio, factors, EVERY_SAMPLE.strip())
    lat = latitude[on]
    if np.all(np.isfinite(lat)) and np.ptp(lat) == 0:
        trig = trig_name(q, lat)
        if trig:
            return (f"hand/model = {ratio:.6g} = {trig.split(':')[0]} at every sample, all "
                    f"at one latitude (φ = {np.degrees(lat[0]):.4g}°):{trig.split(':', 1)[1]}")
    return ""


def _trig_on_a_motion(h: np.ndarray, m: np.ndarray, mag: float, model_scale: np.ndarray,
                      latitude: np.ndarray, motion_of: np.ndarray, labels: list[str]) -> str:
    """``"on motion 'static' (φ = 50° throughout) hand/model = cot φ at every sample:
    cos φ written where sin φ belongs?"`` when on a motion at one latitude the ratio is
    one of :data:`~ins_errors.checker.ratio_names.TRIG` (a sin/cos slip of a term that
    is the whole entry at rest, beside terms of the motion elsewhere), else ``""``."""
    for k, label in enumerate(labels):
        on = (motion_of == k) & (np.abs(m) * mag > AGREEMENT * model_scale)
        lat = latitude[on]
        if on.sum() < 2 or not np.all(np.isfinite(lat)) or np.ptp(lat) != 0:
            continue
        trig = trig_name(h[on] / m[on], lat)
        if trig:
            name, says = trig.split(": ", 1)
            return (f"on motion {label!r} (φ = {np.degrees(lat[0]):.4g}° throughout) "
                    f"hand/model = {name} at every sample: {says}")
    return ""


def _classify(h: np.ndarray, m: np.ndarray, mag: float, scale: np.ndarray, threshold: float,
              left_out: bool, motion_of: np.ndarray | None = None,
              hand_scale: np.ndarray | None = None, model_scale: np.ndarray | None = None
              ) -> tuple[str, str, str] | None:
    """(kind, severity, detail) of one entry's samples, or None when they agree.

    ``motion_of`` (S,) gives the motion of each sample (default: one motion).
    ``hand_scale``, ``model_scale`` (S,): the largest term of the hand's (the model's)
    row alone, against which that side's entry is zero (default ``scale``, both sides'):
    a model entry of −1.2e-4/s is a term the model has, also where the hand writes 1000
    for it (a wrong coefficient, not an extra term).
    """
    if motion_of is None:
        motion_of = np.zeros(h.shape, dtype=int)
    ratio = np.abs(h - m) * mag / scale
    size = float(ratio.max())
    if size <= AGREEMENT:
        return None
    hand_tiny = AGREEMENT * (scale if hand_scale is None else hand_scale)
    model_tiny = AGREEMENT * (scale if model_scale is None else model_scale)
    hand_zero = np.all(np.abs(h) * mag <= hand_tiny)
    model_zero = np.all(np.abs(m) * mag <= model_tiny)
    detail = ""
    if left_out:
        kind = LEFT_OUT
    elif hand_zero:
        kind = OMITTED
    elif model_zero:
        kind = EXTRA
    else:
        both = (np.abs(m) * mag > model_tiny) & (np.abs(h) * mag > hand_tiny)
        only_hand = (np.abs(m) * mag <= model_tiny) & (np.abs(h) * mag > hand_tiny)
        q = h[both] / m[both]
        if not only_hand.any() and np.all(np.abs(q + 1) <= PARTIAL):
            kind = SIGN
            if np.any(np.abs(q + 1) > 1e-6):
                detail = f"hand/model between {q.min():.6g} and {q.max():.6g}"
        elif not only_hand.any() and np.all(np.abs(q - 1) <= PARTIAL):
            kind, detail = APPROXIMATED, (f"hand/model between {q.min():.6g} and "
                                            f"{q.max():.6g}")
        elif (not only_hand.any() and q.size
              and np.ptp(q) <= 1e-6 * np.abs(np.median(q))):
            kind, detail = COEFFICIENT, f"hand/model = {np.median(q):.6g}{EVERY_SAMPLE}"
        elif (part := _within(h, m, 1.0, mag, scale, motion_of)) is not None:
            kind, detail = APPROXIMATED, (
                f"hand − model at most {part:.2g} of the entry's largest value on each "
                f"motion (the entry crosses zero: hand/model between {q.min():.3g} and "
                f"{q.max():.3g})")
        elif (part := _within(h, m, -1.0, mag, scale, motion_of)) is not None:
            kind, detail = SIGN, (
                f"hand + model at most {part:.2g} of the entry's largest value on each "
                f"motion (the entry crosses zero)")
        else:
            kind = COEFFICIENT
    # omissions (a whole term, part of a coefficient, a state left out) are drops when
    # small; a term that is present but wrong is a mistake whatever its size
    severity = classify_severity(OMITTED if kind in (APPROXIMATED, LEFT_OUT) else kind, size,
                                 threshold)
    return kind, severity, detail


@dataclass(frozen=True)
class DeclaredTerm:
    """A term the hand declares it leaves out (``@neglect`` of a ``@convention`` file),
    sampled: the same meaning as the equation checker's declared terms
    (:class:`~ins_errors.checker.classify.Declarations`).

    An entry whose difference from the derived one is this term (either sign, as the
    file may write it with or without the equation's sign) to the agreement level of
    its row is a ``declared drop``, not a mistake; when what remains is an omission
    below the threshold, it is still a declared drop, and the detail says what remains.

    Attributes
    ----------
    declaration : int
        Index of the ``@neglect`` line among the file's declarations.
    line : int
        Its line.
    text : str
        The item as written.
    values : dict
        Motion label -> coefficient at the samples, shape (K,), SI.
    """

    declaration: int
    line: int
    text: str
    values: dict[str, np.ndarray]


def _declared_drop(h: np.ndarray, m: np.ndarray, mag: float, scale: np.ndarray,
                   threshold: float, motion_of: np.ndarray, labels: list[str],
                   candidates: list[DeclaredTerm]) -> tuple[DeclaredTerm, str] | None:
    """The declared term that explains an entry's difference, and what remains of it
    (``""`` when nothing does), or None (see :class:`DeclaredTerm`)."""
    fallback = None
    before = float((np.abs(h - m) * mag / scale).max())
    for term in candidates:
        c = np.concatenate([term.values[k] for k in labels])
        for sign in (1.0, -1.0):
            size = float((np.abs(h - (m - sign * c)) * mag / scale).max())
            if not size <= EXPLAINED_SHARE * before:
                # the term does not account for the difference: a term of another row
                # (a declaration holds for every row after it) that is merely as small
                continue
            rest = _classify(h, m - sign * c, mag, scale, threshold, False, motion_of)
            if rest is None:
                return term, ""
            kind, severity, _ = rest
            if fallback is None and severity not in (MISTAKE, SMALL_MISTAKE):
                fallback = (term, f"what remains is a {severity} ({kind}), size {size:.2g}")
    return fallback


EXPLAINED_SHARE = 0.5
"""A declared term explains an entry's difference only when taking it out leaves at most
this share of the difference (an `@neglect` term of the longitude rate, as small as the
gravity-gradient approximation of F[dv_D, dh], was called that entry's declared drop)."""


@dataclass
class _Sampled:
    """Hand and derived matrices on every motion, restricted to the hand's states."""

    Fh: dict[str, np.ndarray]
    Gh: dict[str, np.ndarray]
    Fz: dict[str, np.ndarray]  # full convention, (K, nz, nz)
    Gz: dict[str, np.ndarray]  # (K, nz, nw) every model source


def _compare(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
             motion_list: list[Motion],
             declared: dict[tuple[str, str, str], list[DeclaredTerm]] | None = None,
             used: set[int] | None = None, source_sizes: np.ndarray | None = None,
             parameters: Mapping[str, float] | None = None) -> None:
    """Classify every entry of the hand's rows into ``report.findings``.

    ``declared``: (matrix, row, column) -> the declared terms in force for that entry
    (:class:`DeclaredTerm`); ``used`` receives the declarations that explain a finding.
    ``source_sizes``: typical size of every model error source, SI, in the model's
    order (default: the fixed ones of
    :func:`~ins_errors.checker.typical.typical_magnitude`). ``parameters``: the model
    parameters set (SI), for the radius and gravity a constant ratio is named by
    (:func:`_named_ratio`).
    """
    names = conv.names
    n_own = len(names) - len(conv.biases)
    rows = [names.index(s) for s in report.states]
    src_names = [s.name for s in model.sources]
    src_cols = [src_names.index(s) for s in report.sources]
    state_mag = np.array([report.magnitudes[n][0] for n in names])
    source_mag = (np.array([typical_magnitude(s.unit)[0] for s in model.sources])
                  if source_sizes is None else source_sizes)
    labels = [m.label for m in motion_list]
    # stacked over motions: (S, ...)
    Fz = np.concatenate([sampled.Fz[k] for k in labels])
    Gz = np.concatenate([sampled.Gz[k] for k in labels])
    Fh = np.concatenate([sampled.Fh[k] for k in labels])
    Gh = np.concatenate([sampled.Gh[k] for k in labels]) if report.sources else None
    where = [(m.label, t) for m in motion_list for t in m.times]
    sample_motion = np.concatenate([[k] * m.times.size for k, m in enumerate(motion_list)])
    # hand F embedded in the full convention columns (omitted states: zero)
    Fh_full = np.zeros((Fh.shape[0], len(rows), len(names)))
    Fh_full[:, :, rows] = Fh
    radii_ratio = _radii_ratio(motion_list)
    latitude = np.concatenate([np.broadcast_to(np.asarray(
        m.navigation.get("latitude", np.nan), dtype=float), m.times.shape)
        for m in motion_list])
    factors = earth_factors(model, parameters)
    findings = []
    series: dict[tuple[str, str, str], tuple] = {}  # (matrix, row, column) -> (h, m, mag, scale)
    compared = 0
    entry_terms = None  # the derived entries' terms (SymPy), built for the first that needs them
    scales = np.empty((Fh.shape[0], len(rows)))  # each hand row's largest term
    for a, i in enumerate(rows):
        terms = [np.abs(Fz[:, i, :]) * state_mag, np.abs(Fh_full[:, a, :]) * state_mag,
                 np.abs(Gz[:, i, :]) * source_mag]
        if Gh is not None:
            terms.append(np.abs(Gh[:, a, :]) * source_mag[src_cols])
        scale = np.max(np.concatenate(terms, axis=1), axis=1)
        scale = np.where(scale > 0, scale, np.inf)
        scales[:, a] = scale
        # each side's own row: what is negligible on that side (terms[0], [2]: derived)
        own = {side: np.max(np.concatenate(parts, axis=1), axis=1) for side, parts in (
            ("model", [terms[0], terms[2]]), ("hand", [terms[1], *terms[3:]]))}
        own = {side: np.where(v > 0, v, np.inf) for side, v in own.items()}
        unit = _rate_unit(conv.states[i].unit)
        columns = [("F", j, names[j], Fh_full[:, a, j], Fz[:, i, j], state_mag[j],
                    j not in rows) for j in range(len(names))]
        if Gh is not None:
            columns += [("G", c, src_names[c], Gh[:, a, b], Gz[:, i, c], source_mag[c], False)
                        for b, c in enumerate(src_cols)]
        differing: list[Entry] = []  # this row's findings, for its index slips
        for matrix, j, col_name, h, m, mag, left_out in columns:
            if left_out and np.all(m == 0):
                continue
            compared += 1
            verdict = _classify(h, m, mag, scale, report.threshold, left_out,
                                sample_motion, own["hand"], own["model"])
            if verdict is None:
                continue
            kind, severity, detail = verdict
            named = ""
            if kind == COEFFICIENT and detail.endswith(EVERY_SAMPLE):
                named = _named_ratio(h, m, mag, own["model"], latitude, factors)
                detail = named or detail
            if kind == COEFFICIENT and not detail:
                detail = (_sign_on_a_motion(h, m, mag, scale, sample_motion, labels)
                          or _ratio_by_motion(h, m, mag, scale, sample_motion, labels)
                          or _trig_on_a_motion(h, m, mag, own["model"], latitude,
                                               sample_motion, labels))
            if matrix == "F" and i >= n_own and i == j:  # a bias state's own rate
                detail = _bias_rate_detail(conv.biases[i - n_own], h, detail)
            ratio = np.abs(h - m) * mag / scale
            candidates = (declared or {}).get((matrix, report.states[a], col_name))
            explained = (_declared_drop(h, m, mag, scale, report.threshold, sample_motion,
                                        labels, candidates) if candidates else None)
            if explained is not None:
                term, rest = explained
                kind, severity = OMITTED, DECLARED
                detail = (f"a term the file declares it leaves out (line {term.line}: "
                          f"{term.text})" + (f"; {rest}" if rest else ""))
                if used is not None:
                    used.add(term.declaration)
            elif kind in (APPROXIMATED, COEFFICIENT) and (swap := _radii_swap(
                    h, m, mag, own["hand"], own["model"], radii_ratio,
                    matrix == "F" and col_name in NORTH_POSITION)) is not None:
                kind, detail = SYMBOL, swap
                severity = classify_severity(SYMBOL, float(ratio.max()), report.threshold)
            elif (kind == COEFFICIENT and matrix == "F"  # a term of a sum left out?
                  and i < n_own and j < n_own  # (not in a bias state's row or column)
                  and not named):  # (a factor 1/R too many is no term left out)
                if entry_terms is None:
                    from ins_errors.checker.matrix_terms import EntryTerms

                    entry_terms = EntryTerms(model, conv.base, motion_list)
                found = _term_left_out(entry_terms, i, j, h, m, mag, scale)
                if found is not None:
                    kind, detail = OMITTED, found
                    severity = classify_severity(OMITTED, float(ratio.max()),
                                                 report.threshold)
                else:  # one term of the sum with a wrong factor (2Ω sin φ written Ω sin φ)?
                    scaled = _term_scaled(entry_terms, i, j, h, m, mag, scale, factors)
                    detail = "; ".join(d for d in (detail, scaled) if d)
            series[(matrix, report.states[a], col_name)] = (h, m, mag, scale)
            s = first_largest(ratio)
            per_motion = {lab: float(ratio[sample_motion == k].max())
                          for k, lab in enumerate(labels)}
            if severity != DECLARED and not (matrix == "F" and i >= n_own and i == j):
                differing.append(Entry(len(findings), matrix, col_name, (
                    conv.states[j] if matrix == "F" else model.sources[j]).unit, kind, h, m,
                    mag))
            findings.append(EntryFinding(
                matrix, report.states[a], col_name, kind, severity, float(ratio[s]),
                size_class(float(ratio[s]), report.threshold), where[s][0], float(where[s][1]),
                float(h[s]), float(m[s]), float(abs(h[s] - m[s]) * mag), unit, per_motion,
                detail))
        for n, detail in index_slips(differing, scale, AGREEMENT, report.states[a]).items():
            findings[n] = replace(findings[n], kind=SYMBOL, detail=detail, severity=(
                classify_severity(SYMBOL, findings[n].size, report.threshold)))
    # a 3×3 block written transposed (C_n^b for C_b^n): one finding, not six
    blocks = [("F", Fh_full, Fz, state_mag, triples(report.states), names)]
    if Gh is not None:
        blocks.append(("G", Gh, Gz[:, :, src_cols], source_mag[src_cols],
                       triples(report.sources), report.sources))
    for matrix, hand_m, model_m, mags, col_triples, col_names in blocks:
        for row_triple in triples(report.states):
            r = [report.states.index(n) for n in row_triple]
            for col_triple in col_triples:
                c = [col_names.index(n) for n in col_triple]
                findings, merged = _merge_transposed(
                    findings, matrix, row_triple, col_triple, hand_m[:, r][:, :, c],
                    model_m[:, [rows[k] for k in r]][:, :, c], mags[c], scales[:, r],
                    report.threshold)
                compared -= merged  # the block is one entry compared
    units = {st.name: st.unit for st in conv.states}
    findings, merged = _merge_pairs(findings, series, units, report.threshold)
    compared -= merged  # the pair is one entry compared
    findings, merged = _merge_rows(findings, series, report.threshold)
    compared -= merged
    findings.sort(key=lambda f: (f.severity not in (MISTAKE, SMALL_MISTAKE), -f.size))
    report.findings = findings
    report.compared = compared


def _merge_transposed(findings: list[EntryFinding], matrix: str, row_triple: tuple[str, ...],
                      col_triple: tuple[str, ...], hand: np.ndarray, model: np.ndarray,
                      mags: np.ndarray, scales: np.ndarray, threshold: float
                      ) -> tuple[list[EntryFinding], int]:
    """The findings with those of a transposed 3×3 block merged into one, and the
    number of entries merged away (:func:`~ins_errors.checker.matrix_slips.transposed_block`).

    The one kept is the block's largest difference, of kind ``wrong symbol or index``;
    its detail names the block. ``hand``, ``model`` (S, 3, 3): the block; ``mags`` (3,):
    its columns' typical sizes; ``scales`` (S, 3): its rows' largest terms. A block with
    a declared drop is left as it is.
    """
    inside = [f for f in findings if f.matrix == matrix and f.row in row_triple
              and f.column in col_triple]
    if (not inside or any(f.severity == DECLARED for f in inside)
            or not transposed_block(hand, model, mags, scales, AGREEMENT)):
        return findings, 0
    worst = max(inside, key=lambda f: f.size)
    block = f"{matrix}[{row_triple[0]}..{row_triple[-1]}, {col_triple[0]}..{col_triple[-1]}]"
    kept = replace(worst, kind=SYMBOL, severity=classify_severity(SYMBOL, worst.size, threshold),
                   detail=f"the block {block} {TRANSPOSED} (one finding for its "
                          f"{len(inside)} differing entries; this is the largest)",
                   block=(tuple(row_triple), tuple(col_triple)))
    gone = {id(f) for f in inside if f is not worst}
    return [kept if f is worst else f for f in findings if id(f) not in gone], len(gone)


PAIRED = frozenset({COEFFICIENT, SIGN, OMITTED, EXTRA, APPROXIMATED})
"""Kinds of a finding that may be half of a mirror pair (:func:`_merge_pairs`)."""


def _merge_pairs(findings: list[EntryFinding], series: dict[tuple[str, str, str], tuple],
                 units: dict[str, str], threshold: float
                 ) -> tuple[list[EntryFinding], int]:
    """The findings with each mirror pair of F merged into one, and the number merged
    away.

    F[a, b] and F[b, a] (a, b states of one unit) whose differences are exactly
    opposite, hand − model = d in one and −d in the other to the agreement level of
    both rows at every sample, are one mistake: an antisymmetric term (the
    ``−(2Ω_ie + Ω_en)×`` of δv̇, a ``[ω×]`` of the attitude rows) written with the wrong
    sign or left out, which changes both entries together. Either entry alone breaks
    the antisymmetry and propagates quite differently (a Coriolis sign slip: each alone
    ~60 times the pair's error after a day), so the one kept, the larger, carries the
    pair's effect (:attr:`EntryFinding.pair`) and names its partner. A pair with a
    held vertical-channel state in it (Coriolis' 2Ω_N between dv_E and dv_D) is merged
    too: its effect is the pair's on the height error with that channel free
    (:func:`~ins_errors.checker.matrix_effects.vertical_effects`). A pair with no
    mistake in it (two dropped small terms, a sphere's radius in an [ω×]), blocks,
    index slips and declared drops are left as they are.

    Parameters
    ----------
    findings : list of EntryFinding
    series : dict
        (matrix, row, column) -> (hand, model, typical size of the column, the row's
        largest term), each at the samples, shape (S,) (the size a float).
    units : dict
        State -> unit.
    threshold : float
    """
    def eligible(f: EntryFinding) -> bool:
        return (f.matrix == "F" and f.block is None and f.kind in PAIRED
                and f.severity != DECLARED and f.row != f.column
                and units.get(f.row) is not None and units.get(f.row) == units.get(f.column))

    by_entry = {(f.row, f.column): f for f in findings if eligible(f)}
    gone: set[int] = set()
    kept: dict[int, EntryFinding] = {}
    for (row, column), f in by_entry.items():
        other = by_entry.get((column, row))
        if (other is None or id(f) in gone or id(other) in gone or id(f) in kept
                or not {f.severity, other.severity} & {MISTAKE, SMALL_MISTAKE}):
            continue  # (two dropped small terms stay two lines, as drops are listed)
        h1, m1, mag1, scale1 = series[("F", row, column)]
        h2, m2, mag2, scale2 = series[("F", column, row)]
        d = (h1 - m1) + (h2 - m2)
        if not (np.all(np.abs(d) * mag1 <= AGREEMENT * scale1)
                and np.all(np.abs(d) * mag2 <= AGREEMENT * scale2)):
            continue
        big, small = (f, other) if f.size >= other.size else (other, f)
        severity = (big.severity if big.severity == MISTAKE or small.severity not in
                    (MISTAKE, SMALL_MISTAKE) else small.severity)
        same = (small.kind, small.detail) == (big.kind, big.detail)
        partner = (f"{small.entry} (hand {_value(small, small.hand)}, model "
                   f"{_value(small, small.model)}, "
                   + ("the same kind" if same else small.kind
                      + (f": {small.detail}" if small.detail else "")) + ")")
        said = (f"one finding with its mirror {partner}: hand − model there is exactly "
                "minus hand − model here at every sample, as an antisymmetric term (a "
                "[ω×] such as Coriolis) with a wrong sign or left out gives; the effect "
                "is the pair's together")
        kept[id(big)] = replace(big, severity=severity, pair=(small.row, small.column),
                                detail=f"{big.detail}; {said}" if big.detail else said)
        gone.add(id(small))
    out = [kept.get(id(f), f) for f in findings if id(f) not in gone]
    return out, len(gone)


def _value(f: EntryFinding, value: float) -> str:
    """:func:`~ins_errors.checker.matrix_report.entry_value` (that module imports this
    one)."""
    from ins_errors.checker.matrix_report import entry_value

    return entry_value(f, value)


ROWS = frozenset({COEFFICIENT, OMITTED, EXTRA, APPROXIMATED})
"""Kinds of a finding that may be half of a term written in the wrong row
(:func:`_merge_rows`)."""
WRONG_ROW = "belongs in row"
"""Words of the detail of a term written in the wrong row (:func:`_merge_rows`)."""


def _merge_rows(findings: list[EntryFinding], series: dict[tuple[str, str, str], tuple],
                threshold: float) -> tuple[list[EntryFinding], int]:
    """The findings with each term written in the wrong row merged into one, and the
    number merged away.

    Two entries of one column (of F or of G) in two rows, whose differences are exactly
    opposite, hand − model = t in row Y and −t in row X to the agreement level of both
    rows at every sample, where Y's is an extra term or X's an omitted one (which says
    which way the term moved), are one slip: the term of row X written in row Y (a gyro
    drift in the latitude line instead of the tilt line). Each alone reads as an extra
    term and an omitted one, and propagates differently from the move. The one kept is
    Y's, of kind ``wrong symbol or index`` (a mistake whatever its size), naming X's
    entry in :attr:`EntryFinding.pair`; its effect is the pair's. A column with more
    than one such pairing for an entry is left as it is.
    """
    def eligible(f: EntryFinding) -> bool:
        return (f.block is None and f.pair is None and f.kind in ROWS
                and f.severity in (MISTAKE, SMALL_MISTAKE, DROPPED))

    by_column: dict[tuple[str, str], list[EntryFinding]] = {}
    for f in findings:
        if eligible(f):
            by_column.setdefault((f.matrix, f.column), []).append(f)
    pairs = []
    for (matrix, column), group in by_column.items():
        found = []
        for a, b in combinations(group, 2):
            h1, m1, mag, scale1 = series[(matrix, a.row, column)]
            h2, m2, _, scale2 = series[(matrix, b.row, column)]
            d = (h1 - m1) + (h2 - m2)
            if not (np.all(np.abs(d) * mag <= AGREEMENT * scale1)
                    and np.all(np.abs(d) * mag <= AGREEMENT * scale2)):
                continue
            ways = [(y, x) for y, x in ((a, b), (b, a))
                    if y.kind == EXTRA or x.kind == OMITTED]
            if len(ways) == 1 and {a.severity, b.severity} & {MISTAKE, SMALL_MISTAKE}:
                found.append(ways[0])
        for y, x in found:
            if sum(any(f is g for g in (y, x) for f in p) for p in found) == 1:  # unique
                pairs.append((y, x))
    gone: set[int] = set()
    kept: dict[int, EntryFinding] = {}
    for y, x in pairs:
        size = max(y.size, x.size)
        said = (f"the term of {x.entry} written in row {y.row}: it {WRONG_ROW} {x.row}, "
                f"not {y.row} ({x.entry}: hand {_value(x, x.hand)}, model "
                f"{_value(x, x.model)}, {x.kind}); hand − model there is exactly minus "
                "hand − model here at every sample; the effect is the pair's together")
        kept[id(y)] = replace(y, kind=SYMBOL, size=size,
                              size_class=size_class(size, threshold),
                              severity=classify_severity(SYMBOL, size, threshold),
                              pair=(x.row, x.column), detail=said)
        gone.add(id(x))
    out = [kept.get(id(f), f) for f in findings if id(f) not in gone]
    return out, len(gone)


RADII_SWAP = "hand/model = (R_"
"""How the detail of a radius of curvature written for the other begins
(:func:`_radii_swap`)."""


def _radii_ratio(motion_list: list[Motion]) -> np.ndarray | None:
    """(R_N + h)/(R_E + h) at every sample of the motions (stacked, shape (S,)): the
    meridian over the prime-vertical radius of curvature at the sample's height; None
    when the navigation solution has no radii or they are equal everywhere (a sphere)."""
    parts = []
    for motion in motion_list:
        nav = motion.navigation
        if not all(k in nav for k in ("R_N", "R_E", "height")):
            return None
        k = motion.times.size
        h = np.broadcast_to(np.asarray(nav["height"], dtype=float), (k,))
        r_n = np.broadcast_to(np.asarray(nav["R_N"], dtype=float), (k,)) + h
        r_e = np.broadcast_to(np.asarray(nav["R_E"], dtype=float), (k,)) + h
        with np.errstate(all="ignore"):
            parts.append(r_n / r_e)
    ratio = np.concatenate(parts) if parts else np.empty(0)
    if not ratio.size or not np.all(np.isfinite(ratio)) or np.all(
            np.abs(ratio - 1.0) <= RADII_AGREEMENT):
        return None
    return ratio


RADII_AGREEMENT = 1e-9
"""Relative agreement of hand/model with a ratio of the radii of curvature at every
sample for a radius written for the other."""


def _radii_swap(h: np.ndarray, m: np.ndarray, mag: float, hand_scale: np.ndarray,
                model_scale: np.ndarray, radii: np.ndarray | None, north: bool = False
                ) -> str | None:
    """The detail of an entry whose hand/model is (R_N + h)/(R_E + h) or its inverse at
    every sample (one radius of curvature written where the other belongs), or None.

    Both radii are within 0.7 % of each other on any ellipsoid, so such an entry looks
    like an approximation; the exact ratio at every sample (to
    :data:`RADII_AGREEMENT`, relative) says it is a slip of the radius.

    Parameters
    ----------
    h, m : ndarray, shape (S,)
        Hand and derived entry at the samples.
    mag : float
        Typical magnitude of the column's state or source.
    hand_scale, model_scale : ndarray, shape (S,)
        The largest term of the hand's (the model's) row at each sample.
    radii : ndarray, shape (S,), or None
        (R_N + h)/(R_E + h) at the samples (:func:`_radii_ratio`).
    north : bool
        The column is a north position error (latitude, north metres). There
        hand/model = (R_E + h)/(R_N + h) is also what leaving the change of R_E with
        latitude out of the latitude derivative of sec φ/(R_E + h) gives (the longitude
        rate's: ∂((R_E + h) cos φ)/∂φ = −(R_N + h) sin φ), an approximation: only the
        other ratio is said to be a slip.
    """
    if radii is None:
        return None
    usable = np.abs(m) * mag > AGREEMENT * model_scale
    if usable.sum() < 2 or np.any(np.abs(h[~usable]) * mag > AGREEMENT * hand_scale[~usable]):
        return None
    q = h[usable] / m[usable]
    r = radii[usable]
    for ratio, text in (
            (r, "hand/model = (R_N + h)/(R_E + h) at every sample: the prime-vertical "
                "radius written where the meridian radius belongs"),
            (None if north else 1.0 / r,
             "hand/model = (R_E + h)/(R_N + h) at every sample: the meridian "
             "radius written where the prime-vertical radius belongs")):
        if ratio is None:
            continue
        if np.all(np.abs(q - ratio) <= RADII_AGREEMENT * np.abs(ratio)):
            return text
    return None


def _bias_rate_detail(bias: BiasState, h: np.ndarray, detail: str) -> str:
    """What a bias state's own rate F[b, b] means when the hand's differs from D (0 for
    a random constant, −1/τ for a declared Gauss–Markov bias)."""
    said = [detail] if detail else []
    if np.ptp(h) == 0 and h[0] < 0:
        said.append(f"the hand's rate is −1/τ with τ = {-1.0 / h[0]:.6g} s")
    if bias.tau is None:
        said.append("the derived bias is a random constant (rate 0); a Gauss–Markov bias "
                    "is declared by its correlation time (MARKOV in a Python file, @markov "
                    "in an equation file)")
    else:
        said.append(f"the derived bias is {bias.statistics} as declared (rate "
                    f"{bias.rate:.6g} 1/s)")
    return "; ".join(said)


def _term_left_out(terms, i: int, j: int, h: np.ndarray, m: np.ndarray, mag: float,
                   scale: np.ndarray) -> str | None:
    """The detail of an entry that is the derived one minus one or two of its terms
    (:mod:`~ins_errors.checker.matrix_terms`), or None.

    Parameters
    ----------
    terms : EntryTerms
        The derived entries' terms on the stacked samples.
    i, j : int
        Row and column of the entry among the convention's states.
    h, m : ndarray, shape (S,)
        Hand and derived entry at the samples.
    mag : float
        Typical magnitude of the column's state.
    scale : ndarray, shape (S,)
        The row's largest term at each sample.
    """
    from ins_errors.checker.matrix_terms import left_out

    choices = left_out(terms.terms(i, j), h, m, mag, scale, AGREEMENT)
    if choices is None:
        return None
    missing = sum(t.values for t in choices[0])
    share = float(np.abs(missing).max() / np.abs(m).max())
    said = [" and ".join(t.describe() for t in found) for found in choices]
    # terms equal in value at every sample: the samples cannot tell which is left out
    common = [t for t in choices[0]
              if all(any(u.describe() == t.describe() for u in c) for c in choices)]
    rest = [[t for t in c if t.describe() not in {u.describe() for u in common}]
            for c in choices]
    if len(said) == 1:
        what = f"term left out: {said[0]}"
    elif all(len(r) == 1 for r in rest):
        what = ("term left out" if not common else
                f"terms left out: {' and '.join(t.describe() for t in common)} and")
        what += (f"{',' * (not common)} one of {len(rest)} terms of the entry equal in "
                 f"value at every sample: {' or '.join(r[0].describe() for r in rest)}")
    else:
        what = (f"terms left out, one of {len(said)} choices equal in value at every "
                f"sample: {' or '.join(f'({s})' for s in said)}")
    return f"{what}, up to {share:.2g} of the entry's largest value"


def _term_scaled(terms, i: int, j: int, h: np.ndarray, m: np.ndarray, mag: float,
                 scale: np.ndarray, factors: list[tuple[str, float]]) -> str:
    """The detail of an entry that is the derived one with one of its terms multiplied
    by a constant (:func:`~ins_errors.checker.matrix_terms.scaled`), the factor named
    where it is one (:func:`~ins_errors.checker.ratio_names.ratio_text`: 1/2, a unit
    slip such as 206265 for deg/h in place of rad/s), or ``""``. The parameters as
    :func:`_term_left_out`; ``factors``: the named ones of the model."""
    from ins_errors.checker.matrix_terms import scaled

    choices = scaled(terms.terms(i, j), h, m, mag, scale, AGREEMENT)
    if choices is None:
        return ""
    term, c = choices[0]
    said = ratio_text(c, factors, "at every sample").replace("hand/model", "hand/model of "
                                                             "that term", 1)
    which = (term.describe() if len(choices) == 1 else
             f"one of {len(choices)} terms equal in value at every sample: "
             + " or ".join(t.describe() for t, _ in choices))
    return f"one term of the entry with a wrong factor, the rest agrees: {which}; {said}"


# --------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------
@one_blas_thread
def check_matrices(model_name: str, hand: HandMatrices | str | Path, convention_name: str,
                   threshold: float = DEFAULT_THRESHOLD, hours: float = HOURS,
                   step: float = STEP, effects: bool = True,
                   motion_list: list[Motion] | None = None,
                   ellipsoid: str | None = None,
                   magnitudes: dict[str, str] | None = None,
                   declared: dict[tuple[str, str, str], list[DeclaredTerm]] | None = None,
                   declared_used: set[int] | None = None,
                   parameters: Mapping[str, float] | None = None,
                   skipped_motions: list[str] | None = None,
                   suggest: bool = True) -> MatrixReport:
    """Check a hand-coded F (and G) against the derived model of ``model_name``.

    Parameters
    ----------
    model_name : str
        Model name, model file or entry-point name (as :func:`~ins_errors.load_model`).
    hand : HandMatrices, str / Path, or callable
        Already sampled matrices, ``FILE.py:FUNCTION`` / ``FILE.npz`` / ``FILE.mat``, or
        the function itself (``fn(nav, imu) -> F`` or ``(F, G)``, e.g. defined in a
        notebook; its ``STATES``/``SOURCES``/``MARKOV`` are its attributes ``fn.states``
        ... or the globals beside it, as in a file).
    convention_name : str
        The convention the hand model's states are in (``model``: the model's own).
    threshold : float
        Relative size separating dropped small terms from mistakes (0 < threshold < 1).
    hours, step : float
        Length (h) and sample step (s) of the motions.
    effects : bool
        Also propagate both models (1 h and 24 h, or ``hours`` if shorter).
    motion_list : list of Motion, optional
        Pre-computed motions (default: those of :func:`motions` the model can fly; the
        others are listed in the report's ``skipped_motions``).
    ellipsoid : str, optional
        Earth shape of the motions (default: the model's own).
    magnitudes : dict, optional
        Typical sizes by SI unit (``{"m": "600 m"}``) replacing the fixed ones; with
        ``"attitude"`` (``{"attitude": "20 arcsec"}``) every size follows from it by the
        Schuler relations (:func:`~ins_errors.checker.reference.schuler_magnitudes`).
    declared : dict, optional
        (matrix, row, column) -> terms the hand declares it leaves out there
        (:class:`DeclaredTerm`): a difference they explain is a declared drop.
    declared_used : set, optional
        Receives the indices of the declarations that explain a finding.
    parameters : mapping of str to float, optional
        Model parameter values (SI) replacing the defaults: in the motions flown here
        (``motion_list`` carries its own) and in the Earth radius and gravity of the
        typical sizes (default: none).
    skipped_motions : list of str, optional
        ``"label: reason"`` of the motions not flown, for the report, with a given
        ``motion_list`` (:func:`~ins_errors.checker.check_motions.flown_motions`);
        default: none given.
    suggest : bool
        With many mistakes, try the model's other conventions on the same entries
        (:attr:`MatrixReport.convention_hint`).

    Raises
    ------
    InsErrorsError
        For unknown names, unreadable hand models, wrong shapes, a model without a
        navigation description (:func:`~ins_errors.checker.navigation.require_description`).
    """
    from ins_errors.numeric.model import load_model

    if not 0 < threshold < 1:
        raise InsErrorsError(f"threshold must be between 0 and 1, got {threshold}")
    model = load_model(model_name)
    require_description(model)
    conv = convention(model, convention_name)
    values_set = dict(parameter_items(parameters, model))
    if motion_list is None:
        motion_list, skipped_motions = flown_motions(model, hours, step, ellipsoid,
                                                     values_set)
    if callable(hand) and not isinstance(hand, HandMatrices):
        name, path, states, sources, markov = callable_hand(hand)
        bias_states(down_names(states, conv.base.names, name)[0], sources, markov, conv,
                    model, name)
        hand = evaluate_function(hand, name, path, states, sources, motion_list, markov)
    elif not isinstance(hand, HandMatrices):
        path, function = split_spec(str(hand))
        if function is not None:
            fn, states, sources, markov = load_hand(path, function)
            where = f"{path.name}:{function}"
            bias_states(down_names(states, conv.base.names, where)[0], sources, markov,
                        conv, model, where)
            hand = evaluate_function(fn, where, path, states, sources, motion_list, markov)
        else:
            hand = read_matrix_file(path, motion_list)
    # an east-north-up hand's phi_U, dv_U: the convention's -phi_D, -dv_D
    hand, written = in_convention(hand, conv.base.names)
    conv = conv.with_biases(bias_states(hand.states, hand.sources, hand.markov, conv, model,
                                        hand.name))
    size_of = _magnitudes(model, magnitudes, values_set)
    magnitudes_given, magnitudes = magnitudes, {}
    angles = position_angles(conv, motion_list[0])
    for s in conv.states:
        magnitudes[s.name] = (position_angle_magnitude(model, size_of("m"), values_set)
                              if s.name in angles else size_of(s.unit))
    for s in model.sources:
        magnitudes[s.name] = size_of(s.unit)
    sampled = _Sampled(hand.F, hand.G, {}, {})
    for motion in motion_list:
        sampled.Fz[motion.label], sampled.Gz[motion.label] = derived_in_convention(
            model, conv, motion)
    if conv.vertical and conv.hold is None and _damped(model, motion_list, sampled):
        # a damped vertical channel (its gains set) needs no holding: the effects of the
        # height terms are then propagated like the others
        conv = replace(conv, vertical=())
    used_sources = [s for s in hand.sources]
    report = MatrixReport(
        model=model_name, convention=conv.name, hand_name=hand.name, states=hand.states,
        sources=used_sources, threshold=threshold,
        motions=[(m.label, m.description) for m in motion_list],
        magnitudes={k: v for k, v in magnitudes.items()
                    if k in conv.names or k in used_sources},
        findings=[], compared=0,
        left_out=[n for n in conv.names if n not in hand.states],
        vertical=list(conv.vertical),
        out_of_scope=[s.name for s in model.sources
                      if s.name not in used_sources and s.name not in hand.states],
        bias_states=list(conv.biases), skipped_motions=list(skipped_motions or []),
        written=written)
    # G's columns weighed by the sizes the report lists (--magnitude), as the states are
    _compare(report, sampled, conv, model, motion_list, declared, declared_used,
             np.array([magnitudes[s.name][0] for s in model.sources]), values_set)
    if suggest and len(report.mistakes) >= MANY:
        report.convention_hint = _other_convention(
            report, hand, sampled, conv, model, model_name, motion_list, threshold,
            magnitudes_given, declared, values_set)
    if report.vertical and all(v in report.left_out for v in report.vertical):
        # a horizontal-only hand: its vertical channel is held in the comparison anyway
        report.findings = [replace(f, severity=NO_VERTICAL)
                           if f.kind == LEFT_OUT and f.column in report.vertical else f
                           for f in report.findings]
    unholdable = held_channel.not_holdable(report.states, conv)
    if effects and unholdable:  # part of an Earth-fixed triple: no effects
        report.held = [unholdable]
    elif effects:
        responses: dict = {}  # the derived model's, shared by both
        report.effects = propagate_effects(report, sampled, conv, model, motion_list,
                                           responses=responses)
        report.finding_effects = finding_effects(report, sampled, conv, model, motion_list,
                                                 responses=responses)
        report.vertical_effects = vertical_effects(report, sampled, conv, model, motion_list)
    return report


MANY = 5
"""Mistakes from which the model's other conventions are tried on the same entries
(:func:`_other_convention`)."""
FEWER = 0.25
"""Another convention is named when the entries give at most this share of the
mistakes there."""


def _other_convention(report: MatrixReport, hand: HandMatrices, sampled: _Sampled,
                      conv: Convention, model, model_name: str, motion_list: list[Motion],
                      threshold: float, magnitudes: dict[str, str] | None,
                      declared: dict | None, parameters: Mapping[str, float]) -> str:
    """The hint that the hand's entries are another convention's, or ``""``.

    Equations written in one convention and labelled another (φ-angle equations under
    ``@convention psi_geodetic``, the states renamed) give a mistake in most entries
    and no hint why. Every other convention of the model whose states have the units of
    this one's in the same order (``psi_N``/``phi_N``, ``dvc_N``/``dv_N``) is checked on
    the same sampled entries, each state read as its namesake by position (no effects;
    about a second for a 9-state strapdown model). Rows the hand takes from the derived
    model (a ``@convention`` file's rows it does not give: equal to the derived rows in
    every bit) are left out of both counts. The convention with the fewest mistakes is
    named when it has at most :data:`FEWER` of this one's: ``"these entries agree with
    convention phi_geodetic (0 mistakes, against 24 in psi_geodetic), each state read
    as its namesake in order (psi_N as phi_N, ...): the wrong convention?"``.
    """
    from ins_errors.checker.conventions import conventions

    base = conv.base
    own = _rows_given(hand, sampled, conv, model, motion_list)
    mistakes = sum(1 for f in report.mistakes if f.row in own)
    units = [s.unit for s in base.states]
    best = None
    for name, other in conventions(model).items():
        if name == base.name or [s.unit for s in other.states] != units:
            continue
        rename = dict(zip(base.names, other.names, strict=True))
        relabelled = HandMatrices(hand.name, [rename.get(s, s) for s in hand.states],
                                  hand.sources, hand.F, hand.G, hand.markov)
        moved = {(k[0], rename.get(k[1], k[1]), rename.get(k[2], k[2])): v
                 for k, v in (declared or {}).items()}
        try:
            there = check_matrices(model_name, relabelled, name, threshold, effects=False,
                                   motion_list=motion_list, magnitudes=magnitudes,
                                   declared=moved, declared_used=set(),
                                   parameters=parameters, suggest=False)
        except InsErrorsError:
            continue
        given = {rename.get(s, s) for s in own}
        count = sum(1 for f in there.mistakes if f.row in given)
        if best is None or count < best[0]:
            best = (count, name, rename)
    if best is None or best[0] > FEWER * mistakes:
        return ""
    count, name, rename = best
    changed = [f"{a} as {b}" for a, b in rename.items() if a != b and a in hand.states]
    how = ", ".join(changed[:2]) + (", ..." if len(changed) > 2 else "")
    agree = ("agree with" if count == 0 else "come much closer to")
    return (f"these entries {agree} convention {name} ({count} "
            f"mistake{'s' * (count != 1)}, against {mistakes} in {base.name}), each state "
            f"read as its namesake in order ({how}): the wrong convention?")


def _rows_given(hand: HandMatrices, sampled: _Sampled, conv: Convention, model,
                motion_list: list[Motion]) -> set[str]:
    """The hand's rows that are not the derived model's own in every bit on every
    motion (a ``@convention`` file fills the rows it does not give from the derived
    model)."""
    names = conv.names
    rows = [names.index(s) for s in hand.states]
    src_names = [s.name for s in model.sources]
    cols = [src_names.index(s) for s in hand.sources]
    out = set()
    for a, state in enumerate(hand.states):
        i = names.index(state)
        for motion in motion_list:
            k = motion.label
            same = np.array_equal(sampled.Fh[k][:, a, :], sampled.Fz[k][:, i, rows])
            if same and hand.sources:
                same = np.array_equal(sampled.Gh[k][:, a, :], sampled.Gz[k][:, i, cols])
            if not same:
                out.add(state)
                break
    return out


STABLE_RATE = 1e-7
"""Largest real part (1/s) of the derived F's eigenvalues on the static base for which
its vertical channel is counted as damped: the Schuler and Earth-rate modes have 0, an
undamped vertical channel +1.75e-3. (On a moving base F frozen at a time can have a slow
growing mode its motion never follows, ×e in a day or so: not a test of the channel.)"""


def _damped(model, motion_list: list[Motion], sampled: _Sampled) -> bool:
    """Whether the model's vertical channel is damped on these motions: it has damping
    gains (``Parameter(..., damping_gain=True)``), none of them 0, and the derived F on
    the static base has no growing mode (:func:`_stable`). A neutral channel (a constant
    g, no gains) is not damped: a hand term that makes it grow would swamp the rest."""
    from ins_errors.numeric.linear_system import undamped_gains

    at_rest = [sampled.Fz[m.label] for m in motion_list if m.label == "static"]
    gains = [info for info in model.parameters if info.damping_gain]
    p = np.asarray(motion_list[0].p, dtype=float)
    first = p.reshape(-1, p.shape[-1])[0]   # the parameters (last axis), first sample
    return bool(gains and at_rest and not undamped_gains(model, first) and _stable(at_rest))


def _stable(derived: Iterable[np.ndarray]) -> bool:
    """Whether the derived F, shape (K, n, n) per motion, has no growing mode at the
    start, middle and end of every motion given (:data:`STABLE_RATE`)."""
    from ins_errors.numeric.linear_system import growth_rate

    return all(growth_rate(F[k]) <= STABLE_RATE
               for F in derived for k in {0, F.shape[0] // 2, F.shape[0] - 1})


def position_angles(conv: Convention, motion: Motion) -> list[str]:
    """States of ``conv`` that are a position error written as an angle (latitude and
    longitude errors, rad): those with a position readout in metres per radian."""
    readout = np.abs(conv.position(motion.navigation, motion.x, motion.p)).max(axis=(0, 2))
    return [s.name for s, r in zip(conv.states, readout, strict=True)
            if s.unit == "rad" and r > 1e3]


def position_angle_magnitude(model, position: tuple[float, str],
                             parameters: Mapping[str, float] | None = None
                             ) -> tuple[float, str]:
    """Typical size of a latitude or longitude error: the typical position error over the
    model's Earth radius a (10 m / a = 1.57e-6 rad on the WGS-84 ellipsoid), the same
    position error as a north or east error in metres (for a longitude error, a
    position error of that size times cos φ). ``parameters``: values set (SI)."""
    radius, _ = _earth(model, parameters)  # the parameter a (or R) of the model
    value = position[0] / radius
    return value, f"{value:.3g} rad ({position[1]} / {radius:.0f} m)"


def _magnitudes(model, overrides: dict[str, str] | None,
                parameters: Mapping[str, float] | None = None):
    """Typical size (SI, text) by SI unit: fixed, overridden, or Schuler-consistent."""
    overrides = dict(overrides or {})
    if "attitude" in overrides:  # R and g from the model's parameters (no SymPy)
        attitude = overrides.pop("attitude")
        return schuler_magnitudes(model, attitude, overrides, parameters).of
    fixed: dict[str, tuple[float, str]] = {}
    for unit, text in overrides.items():
        fixed[unit] = (magnitude_override(unit, text), text)
    return lambda unit: fixed[unit] if unit in fixed else typical_magnitude(unit)


def _conventions_of(states: list[str], rate_sources: list[str], model, given: str
                    ) -> list[str]:
    """The conventions of ``model`` other than ``given`` whose states (with the model's
    constant error sources as bias states) hold every name of ``states`` (a hand model
    checked without its ``--convention``)."""
    from ins_errors.checker.conventions import conventions

    try:
        known = conventions(model)
    except InsErrorsError:
        return []
    return [name for name, c in known.items() if name != given
            and all(s in c.names or s in rate_sources for s in states)]


def bias_states(states: list[str], sources: list[str], markov: dict[str, float],
                conv: Convention, model, where: str, label: str = "MARKOV"
                ) -> tuple[BiasState, ...]:
    """The hand's bias states: the model error sources among its ``states``, in the
    model's order of its sources, each with its statistics.

    A state name is one of the convention's vocabulary or a model error source that
    enters the equations (kind ``constant``); that source is then a state, not a column
    of G, and it is a random constant unless ``markov`` gives its correlation time.

    Parameters
    ----------
    states, sources : list of str
        The hand's STATES and SOURCES.
    markov : dict
        Bias state -> correlation time of a first-order Gauss–Markov bias, s (``MARKOV``).
    conv : Convention
        The convention of the hand's other states.
    model : Model
    where : str
        The hand model's name, for messages.
    label : str
        How the correlation times are declared (``MARKOV``, ``@markov``), for messages.

    Raises
    ------
    InsErrorsError
        One line for an unknown name, an initial-error source as a state, a source both
        a state and a column of G, or a correlation time of something that is no bias
        state.
    """
    base = conv.base
    by_name = {s.name: s for s in model.sources}
    rate_sources = [n for n, s in by_name.items() if s.kind == "constant"]
    for s in states:
        if s in base.names:
            continue
        if s not in by_name:
            others = _conventions_of(states, rate_sources, model, base.name)
            if others:  # the states are another convention's: say which
                how = {"MARKOV": "--convention", "@markov": "@convention"}.get(label)
                give = (f"give it ({how} {others[0]})" if how and len(others) == 1
                        else "give it" if len(others) == 1 else "give one of them")
                raise UnknownNameError(
                    f"{where}: {s!r} is no state of convention {base.name!r}; the states "
                    f"are those of convention{'s' * (len(others) > 1)} "
                    f"{', '.join(repr(o) for o in others)}: {give}")
            raise unknown_name(f"state of convention {base.name!r}", s,
                               base.names + rate_sources)  # (bias states too)
        if by_name[s].kind != "constant":
            raise InsErrorsError(
                f"{where}: {s!r} is an initial error of {model.name} (kind "
                f"{by_name[s].kind!r}): it only sets the initial state, so it cannot be a "
                "bias state")
        if s in sources:
            raise InsErrorsError(
                f"{where}: {s!r} is both a state (STATES) and a column of G (SOURCES): a "
                "bias state's column is in F; remove it from SOURCES")
    for s in sources:
        if s not in by_name:
            raise unknown_name(f"error source of {model.name}", s, list(by_name))
    for s in markov:
        if s not in states or s in base.names:
            raise InsErrorsError(
                f"{where}: {label} gives a correlation time for {s!r}, which is not a "
                "bias state (a model error source "
                + ("listed in STATES)" if label == "MARKOV" else "with a line dot(SOURCE))"))
    return tuple(BiasState(s.name, s.unit, s.description, markov.get(s.name))
                 for s in model.sources if s.name in states)
