"""What the differences between a hand-coded and the derived linear model do.

Both models are propagated from each initial error and error source at its typical
magnitude (:func:`propagate_effects`); each finding alone is put into the derived model
and propagated (:func:`finding_effects`); findings of vertical-channel rows are assessed
with that channel free (:func:`vertical_effects`). Every difference is weighed against
its rounding floor (:func:`rounding_floor`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ins_errors.checker import held_channel
from ins_errors.checker.check_motions import Motion
from ins_errors.checker.conventions import Convention
from ins_errors.checker.extreme import first_largest
from ins_errors.checker.growth import growth_rate, hours_tag, mark_growth
from ins_errors.checker.transition import transitions

if TYPE_CHECKING:
    from ins_errors.checker.matrix import EntryFinding, MatrixReport, _Sampled

EFFECT_HOURS = (1.0, 24.0)
"""Times at which the propagated models are compared, h."""
EPS = float(np.finfo(float).eps)
"""Machine epsilon of the propagation (float64)."""
@dataclass(frozen=True)
class Effect:
    """Difference of the two propagated linear models for one initial error or source.

    Attributes
    ----------
    motion : str
    hours : float
    case : str
        ``initial <state>`` or ``source <name>``, each at its typical magnitude.
    magnitude : str
        That magnitude, as people write it.
    position_difference, position_model : float or None
        Horizontal position error: |hand − model| and |model|, m; None when the hand's
        states hold no position (:func:`reads`: the difference is not measured).
    attitude_difference, attitude_model : float or None
        Attitude error (norm of the three angles): |hand − model| and |model|, rad; None
        when the hand's states hold no attitude.
    position_floor, attitude_floor : float or None
        Rounding floor of the differences on this motion at this time (the same for every
        case; :func:`rounding_floor`), m and rad: a difference at or below it is no effect
        (None with the difference).
    e_folding : float or None
        E-folding time (s) of a growing mode of this motion's propagation that the
        differences follow (:func:`~ins_errors.checker.growth.mark_growth`; the same for
        every case and time of the motion), None without one.
    growing_mode : str or None
        Whose mode it is: ``"hand"`` (a mode the hand model adds) or ``"model"``.
    exponential : bool
        At this time the difference has grown past
        :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings: it is said to grow
        exponentially instead of being given as a figure.
    """

    motion: str
    hours: float
    case: str
    magnitude: str
    position_difference: float | None
    position_model: float | None
    attitude_difference: float | None
    attitude_model: float | None
    position_floor: float | None = 0.0
    attitude_floor: float | None = 0.0
    e_folding: float | None = None
    growing_mode: str | None = None
    exponential: bool = False

    @property
    def position_above_rounding(self) -> bool:
        """The position difference is measured and above its rounding floor."""
        return (self.position_difference is not None
                and self.position_difference > self.position_floor)

    @property
    def attitude_above_rounding(self) -> bool:
        """The attitude difference is measured and above its rounding floor."""
        return (self.attitude_difference is not None
                and self.attitude_difference > self.attitude_floor)


@dataclass(frozen=True)
class AloneEffect:
    """Effect of one finding alone after 24 h: the derived model with only that entry
    replaced by the hand's (:func:`finding_effects`).

    Attributes
    ----------
    position : float or None
        Largest horizontal position change over every case and motion, m (rounding
        included: compare with ``position_floor``); None when the hand's states hold no
        position (:func:`reads`).
    attitude : float or None
        Largest attitude change, rad; None when the hand's states hold no attitude.
    motion : str or None
        Motion where the position change above its floor is largest (the attitude change
        where no position is measured); None when it is below the floor on every motion
        (no motion is named for rounding).
    position_floor, attitude_floor : float or None
        Rounding floors (:func:`rounding_floor`): of the motion named, or the largest over
        the motions when the change is below them everywhere; m and rad (None with the
        change).
    e_folding : float or None
        When the entry alone gives a growing mode the derived model lacks, past
        :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings after 24 h: its
        e-folding time, s (the fastest over the motions; ``motion`` is that motion).
        The change is then said to grow exponentially instead of being given as a figure.
    growing_mode : str or None
        ``"hand"`` (a mode the entry adds) or ``"model"``, with ``e_folding``.
    not_assessed : str or None
        Why the entry's effect is not measured: its column is a state the hand leaves
        out that no initial error or source of the hand excites (it stays 0 in every
        propagation, so the entry acts on nothing). The figures are then 0 and say
        nothing.
    """

    position: float | None
    attitude: float | None
    motion: str | None
    position_floor: float | None
    attitude_floor: float | None
    e_folding: float | None = None
    growing_mode: str | None = None
    not_assessed: str | None = None

    @property
    def exponential(self) -> bool:
        """The change grows exponentially (``e_folding`` is set)."""
        return self.e_folding is not None

    @property
    def position_above_rounding(self) -> bool:
        """The position change is measured and above its rounding floor on some motion."""
        return self.position is not None and self.motion is not None

    @property
    def attitude_above_rounding(self) -> bool:
        """The attitude change is measured and above its rounding floor on some motion."""
        return self.attitude is not None and self.attitude > self.attitude_floor


@dataclass(frozen=True)
class VerticalEffect:
    """Effect of a finding in a vertical-channel row (``dv_D``, ``dr_D``, ``dh``) on the
    height error, with the vertical channel *not* held (:func:`vertical_effects`).

    The horizontal comparison holds the vertical channel (:attr:`MatrixReport.held`):
    undamped, it grows as e^{t √(2g/R)}, ×e every 9.5 min, in the derived model itself.
    A term of it that the hand writes differently is seen here only: both propagations
    are given their own vertical channel, and the change of the height error is read.

    Attributes
    ----------
    hours : tuple of float
        Times compared, h.
    height : tuple of float
        Largest height-error change at each time over every case and motion, m.
    floor : tuple of float
        Its rounding floor (:func:`rounding_floor`), m.
    case, motion : tuple of (str or None)
        The case (``initial dr_D``, ``source ...``) and motion of the largest change
        above its floor at each time (None at or below the floor, or when it grows
        exponentially).
    exponential : tuple of bool
        At that time the change grows exponentially (past
        :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings, the rule of
        :func:`~ins_errors.checker.growth.mark_growth`): it is given as growth, not a
        figure.
    e_folding : float or None
        E-folding time of that growing mode, s; ``growing_mode`` says whose it is
        (``"model"``: the undamped vertical channel of the model itself; ``"hand"``: a
        faster one the hand's entry gives).
    derived : tuple of (float or None)
        The derived model's own height error (vertical channel free) in the case and on
        the motion named at each time, m: what the change is measured against, as the
        horizontal effects' "of derived" (None where no case is named).
    """

    hours: tuple[float, ...]
    height: tuple[float, ...]
    floor: tuple[float, ...]
    case: tuple[str | None, ...]
    motion: tuple[str | None, ...]
    exponential: tuple[bool, ...]
    e_folding: float | None = None
    growing_mode: str | None = None
    derived: tuple[float | None, ...] = ()


def _augmented(F: np.ndarray, G: np.ndarray, scale: np.ndarray, held: list[int],
               hold: held_channel.Hold | None = None) -> np.ndarray:
    """[[F, G], [0, 0]] in scaled variables (each state / source over its magnitude), with
    the rows and columns of the ``held`` states zeroed (they keep their initial value and
    feed nothing), or with the vertical channel held through ``hold``
    (:class:`~ins_errors.checker.held_channel.Hold`)."""
    k, n, m = G.shape
    A = np.zeros((k, n + m, n + m))
    A[:, :n, :n] = F
    A[:, :n, n:] = G
    A[:, held, :] = 0.0
    A[:, :, held] = 0.0
    if hold is not None:
        A = hold.held(A)
    A *= (1 / scale)[:, None]
    A *= scale[None, :]
    return A


@dataclass
class _Propagation:
    """What both propagations share: names, magnitudes, held states and the cases."""

    rows: list[int]
    src_cols: list[int]
    mags_h: np.ndarray
    mags_src: np.ndarray
    mags_z: np.ndarray
    held_h: list[int]
    held_z: list[int]
    cases: list[tuple[int, str, str]]  # (column of the response, label, magnitude text)
    conv: Convention | None = None  # the vertical channel held through held_channel
    model: object = None
    holds: dict = field(default_factory=dict)  # (motion, "h" / "z") -> Hold or None

    @classmethod
    def of(cls, report: MatrixReport, conv: Convention, model) -> _Propagation:
        names = conv.names
        src_names = [s.name for s in model.sources]
        n_h = len(report.states)
        cases = ([(j, f"initial {s}", report.magnitudes[s][1])
                  for j, s in enumerate(report.states) if s not in conv.vertical]
                 + [(n_h + b, f"source {s}", report.magnitudes[s][1])
                    for b, s in enumerate(report.sources)])
        return cls([names.index(s) for s in report.states],
                   [src_names.index(s) for s in report.sources],
                   np.array([report.magnitudes[s][0] for s in report.states]),
                   np.array([report.magnitudes[s][0] for s in report.sources]),
                   np.array([report.magnitudes[s][0] for s in names]),
                   [report.states.index(v) for v in conv.vertical if v in report.states],
                   [names.index(v) for v in conv.vertical], cases,
                   conv if held_channel.holds(conv) else None, model)

    def hold(self, motion: Motion, side: str) -> held_channel.Hold | None:
        """The operators holding the vertical channel of the hand's (``"h"``) or the
        derived model's (``"z"``) states on ``motion``
        (:func:`~ins_errors.checker.held_channel.hold_on`), None where the vertical
        states are held by index."""
        if self.conv is None:
            return None
        key = (motion.label, side)
        if key not in self.holds:
            rows = self.rows if side == "h" else list(range(len(self.conv.names)))
            self.holds[key] = held_channel.hold_on(self.conv, motion, rows, self.model)
        return self.holds[key]

    def _run(self, A: np.ndarray, scale: np.ndarray, hold: held_channel.Hold | None,
             motion: Motion, at: list[float]) -> list[np.ndarray]:
        phis = transitions(A, motion.times, at)
        start = None if hold is None else hold.start(scale)
        if start is None:
            return phis
        with np.errstate(over="ignore", invalid="ignore"):
            return [phi @ start for phi in phis]

    def derived(self, Fz: np.ndarray, Gz: np.ndarray, motion: Motion, at: list[float]
                ) -> list[np.ndarray]:
        """Response of the derived model to each unit case, in scaled variables (each
        state or source over its typical magnitude): (n_z + m, n_h + m) at each time, every
        convention state included (:meth:`si` gives the hand's states in SI)."""
        n_z, n_h, m = Fz.shape[1], len(self.rows), len(self.src_cols)
        scale = np.concatenate([self.mags_z, self.mags_src])
        hold = self.hold(motion, "z")
        phis = self._run(_augmented(Fz, Gz[:, :, self.src_cols], scale, self.held_z, hold),
                         scale, hold, motion, at)
        embed = np.zeros((n_z + m, n_h + m))
        embed[self.rows, np.arange(n_h)] = 1.0
        embed[n_z:, n_h:] = np.eye(m)
        # an overflowed transition (inf) times embed's zeros is nan: the exponential
        # growth is reported as such (mark_growth), as in transitions
        with np.errstate(over="ignore", invalid="ignore"):
            return [phi @ embed for phi in phis]

    def si(self, scaled: np.ndarray) -> np.ndarray:
        """The hand's states (SI) of a scaled derived response: (n_h, n_h + m)."""
        return scaled[self.rows] * self.mags_h[:, None]

    def hand(self, Fh: np.ndarray, Gh: np.ndarray | None, motion: Motion, at: list[float]
             ) -> list[np.ndarray]:
        """The same for the hand model, in scaled variables: (n_h + m, n_h + m)."""
        Gh = np.zeros((*Fh.shape[:2], 0)) if Gh is None else Gh
        scale = np.concatenate([self.mags_h, self.mags_src])
        hold = self.hold(motion, "h")
        return self._run(_augmented(Fh, Gh, scale, self.held_h, hold), scale, hold, motion,
                         at)

    def growth(self, F: np.ndarray, motion: Motion, side: str, last: int) -> float:
        """:func:`_motion_growth` of F (the hand's, ``"h"``, or one of the derived
        model's, ``"z"``) on ``motion``, its vertical channel held as in the propagation."""
        hold = self.hold(motion, side)
        if hold is not None:
            F = hold.held_states(F)
        return _motion_growth(F, self.held_h if side == "h" else self.held_z, last)

    def floors(self, scaled: list[np.ndarray], steps: int, readout: np.ndarray) -> float:
        """:func:`rounding_floor` of a readout (rows: m or rad per SI unit of the hand's
        states) of responses (scaled) after ``steps`` steps."""
        columns = [c for c, _, _ in self.cases]
        largest = max((float(np.abs(r[:, columns]).max(initial=0.0)) for r in scaled),
                      default=0.0)
        size = max(r.shape[0] for r in scaled)
        return rounding_floor(largest, size, steps,
                              float(np.linalg.norm(np.abs(readout) @ self.mags_h)))


def rounding_floor(largest: float, size: int, steps: int, unit: float) -> float:
    """Rounding floor of a difference of two propagations: ``size·steps·ε·largest·unit``.

    Both models are propagated in scaled variables (each state and source over its typical
    magnitude) as a product of ``steps`` step exponentials of ``size × size`` matrices. The
    forward error of such a product, and so of any of its entries, is bounded by
    γ = size·steps·ε (ε the machine epsilon) times the largest scaled response
    (``largest``); the same bound covers hand entries that equal the derived ones only to
    the last bits (they change each step exponential by a few ε). A readout (horizontal
    position, attitude) of that error is at most γ·largest·``unit``, ``unit`` =
    ‖ |R| m ‖ for the readout rows R and the typical magnitudes m of the states. On the
    static base the transition is one exponential exp(A t), whose forward error grows
    with ‖A t‖ (~ a hundred for a day of Schuler and Earth-rate cycles), well inside
    the same bound for the steps a day has.

    A difference at or below this floor says nothing: which initial error or source
    reaches the largest such difference changes with the last bits of the arithmetic.

    Parameters
    ----------
    largest : float
        Largest |entry| of the scaled responses compared (both models), dimensionless.
    size : int
        Dimension of the propagated (augmented) system.
    steps : int
        Number of steps propagated (at least 1).
    unit : float
        Readout of a unit scaled error, m or rad.

    Returns
    -------
    float
        The floor, m or rad.
    """
    return size * max(steps, 1) * EPS * largest * unit


def _times(motion: Motion, hours: tuple[float, ...]) -> list[float]:
    return [h * 3600.0 for h in hours if h * 3600.0 <= motion.times[-1] + 1e-9]


def _steps(motion: Motion, t: float) -> int:
    return round(t / (motion.times[1] - motion.times[0]))


def reads(conv: Convention, motion_list: list[Motion], rows: list[int]
          ) -> tuple[bool, bool]:
    """Whether the states ``rows`` of ``conv`` hold a horizontal position and an
    attitude: their readouts (:meth:`~ins_errors.checker.conventions.Convention.position`,
    :meth:`~ins_errors.checker.conventions.Convention.attitude`) are not 0 on every
    sample of every motion. A hand model without position states (a velocity and
    attitude model) has no position difference to report: it is not measured, not 0.
    """
    position = any(np.any(conv.position(m.navigation, m.x, m.p)[:2, rows] != 0)
                   for m in motion_list)
    attitude = any(np.any(conv.attitude(m.navigation, m.x, m.p)[:, rows] != 0)
                   for m in motion_list)
    return position, attitude


def _norm(R: np.ndarray, x: np.ndarray, read: bool) -> float | None:
    """|R x| (largest over the columns of a 2-D x), None where nothing is read."""
    if not read:
        return None
    with np.errstate(over="ignore", invalid="ignore"):  # an overflowed x: inf or NaN out
        return float(np.linalg.norm(R @ x, axis=0).max(initial=0.0))


def propagate_effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
                      motion_list: list[Motion], hours: tuple[float, ...] = EFFECT_HOURS,
                      responses: dict | None = None) -> list[Effect]:
    """Propagate the hand and the derived model; differences per initial error/source,
    with the rounding floor of each motion and time (:func:`rounding_floor`); None for
    a readout the hand's states do not hold (:func:`reads`).

    ``responses``, if given, receives the derived model's scaled responses by (motion,
    time) (:func:`finding_effects` starts from them).
    """
    prop = _Propagation.of(report, conv, model)
    report.held = [v for v in conv.vertical if v in report.states]
    if prop.conv is not None:  # held through operators (held_channel)
        report.held = [held_channel.held_text(conv)]
    read_p, read_a = reads(conv, motion_list, prop.rows)
    shown = "position" if read_p else "attitude"  # the figure growth is judged by
    effects = []
    n_h = len(prop.rows)
    for motion in motion_list:
        at = _times(motion, hours)
        if not at:
            continue
        hand = prop.hand(sampled.Fh[motion.label], sampled.Gh.get(motion.label), motion, at)
        derived = prop.derived(sampled.Fz[motion.label], sampled.Gz[motion.label], motion, at)
        if responses is not None:
            responses.update({(motion.label, t): r for t, r in zip(at, derived, strict=True)})
        position = conv.position(motion.navigation, motion.x, motion.p)  # (3, nz, K)
        attitude = conv.attitude(motion.navigation, motion.x, motion.p)
        rows: list[Effect] = []
        growth: dict = {}  # worst position (attitude) difference and floor at each time
        for t, scaled_h, scaled_z in zip(at, hand, derived, strict=True):
            k = _steps(motion, t)
            P = position[:2, prop.rows, k]
            A = attitude[:, prop.rows, k]
            resp_h, resp_z = scaled_h[:n_h] * prop.mags_h[:, None], prop.si(scaled_z)
            floor_p = prop.floors([scaled_h, scaled_z], k, P) if read_p else None
            floor_a = prop.floors([scaled_h, scaled_z], k, A) if read_a else None
            for c, case, text in prop.cases:
                diff = resp_h[:, c] - resp_z[:, c]
                rows.append(Effect(
                    motion.label, t / 3600.0, case, text, _norm(P, diff, read_p),
                    _norm(P, resp_z[:, c], read_p), _norm(A, diff, read_a),
                    _norm(A, resp_z[:, c], read_a), floor_p, floor_a))
            tag = hours_tag(t / 3600.0)
            growth[f"{shown}_{tag}"] = max((getattr(e, f"{shown}_difference") or 0.0
                                            for e in rows if e.hours == t / 3600.0),
                                           default=0.0)
            growth[f"{shown}_floor_{tag}"] = (floor_p if read_p else floor_a) or 0.0
        last = _steps(motion, at[-1])
        mark_growth(growth, prop.growth(sampled.Fh[motion.label], motion, "h", last),
                    prop.growth(sampled.Fz[motion.label], motion, "z", last),
                    tuple(t / 3600.0 for t in at), quantity=shown)
        effects += [replace(e, e_folding=growth.get("e_folding_s"),
                            growing_mode=growth.get("growing_mode"),
                            exponential=growth.get(f"exponential_{hours_tag(e.hours)}",
                                                   False))
                    for e in rows]
    return effects


def _motion_growth(F: np.ndarray, held: list[int], last: int) -> float:
    """Growth rate (1/s, :func:`~ins_errors.checker.growth.growth_rate`) of a propagation
    along a motion: the largest real part of the eigenvalues of the mean of F over the
    samples up to ``last``, the ``held`` states' rows and columns zeroed as in the
    propagation (on the static base F itself, exact; along a motion its average).

    Parameters
    ----------
    F : ndarray, shape (K, n, n)
        F at the samples, 1/s.
    held : list of int
        Held states (vertical channel).
    last : int
        Last sample propagated.
    """
    mean = F[:last + 1].mean(axis=0)
    mean[held, :] = 0.0
    mean[:, held] = 0.0
    return growth_rate(mean)


def with_finding(f: EntryFinding, report: MatrixReport, sampled: _Sampled,
                 conv: Convention, model, motion: str) -> tuple[np.ndarray, np.ndarray]:
    """The derived F and G on ``motion`` with the finding's entries replaced by the
    hand's: its one entry, or for a transposed block (:attr:`EntryFinding.block`) every
    entry of the block as the hand writes it (a column the hand leaves out: 0), or for
    a pair (:attr:`EntryFinding.pair`: a mirror pair, a term in the wrong row) both
    entries.

    Returns
    -------
    F, G : numpy.ndarray, shapes (K, n_z, n_z) and (K, n_z, n_w)
        Copies where changed (every convention state, every model source), SI.
    """
    rows, columns = f.block if f.block is not None else ((f.row,), (f.column,))
    names = conv.names
    F, G = sampled.Fz[motion], sampled.Gz[motion]
    if f.matrix == "F":
        F = F.copy()
        entries = [(row, column) for row in rows for column in columns]
        if f.pair is not None:  # a mirror pair: both entries
            entries.append(f.pair)
        for row, column in entries:
            a, i = report.states.index(row), names.index(row)
            F[:, i, names.index(column)] = (
                sampled.Fh[motion][:, a, report.states.index(column)]
                if column in report.states else 0.0)
    else:
        src_names = [s.name for s in model.sources]
        G = G.copy()
        entries = [(row, column) for row in rows for column in columns]
        if f.pair is not None:  # a term in the wrong row: both entries
            entries.append(f.pair)
        for row, column in entries:
            a, i = report.states.index(row), names.index(row)
            G[:, i, src_names.index(column)] = (
                sampled.Gh[motion][:, a, report.sources.index(column)])
    return F, G


def finding_effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
                    motion_list: list[Motion], hours: float = EFFECT_HOURS[-1],
                    responses: dict | None = None) -> dict[str, AloneEffect]:
    """Effect of each finding alone: the derived model with only that entry replaced by
    the hand's (a transposed block: the whole block, :func:`with_finding`), propagated
    like :func:`propagate_effects` (entries of held vertical-channel states are left
    out). ``responses``: the derived model's scaled responses by (motion,
    time) from :func:`propagate_effects`, if at hand (the same numbers; not computed
    again).

    On each motion the change is compared with its rounding floor (:func:`rounding_floor`
    of both propagations); the motion named is the one with the largest change above its
    floor, and none when the change is below the floor on every motion. A readout the
    hand's states do not hold is None (:func:`reads`); an entry in the column of a state
    the hand leaves out that stays at 0 (above rounding) in every propagation is not
    assessed (:attr:`AloneEffect.not_assessed`).

    Returns
    -------
    dict
        ``finding.entry`` -> :class:`AloneEffect` (largest horizontal position change, m;
        largest attitude change, rad; motion; floors), over every case.
    """
    prop = _Propagation.of(report, conv, model)
    names = conv.names
    read_p, read_a = reads(conv, motion_list, prop.rows)
    shown = "position" if read_p else "attitude"
    # entry -> [(motion, position, attitude, position floor, attitude floor, growth)]
    per_motion: dict[str, list[tuple[str, float | None, float | None, float | None,
                                     float | None, dict]]] = {}
    excited: dict[str, bool] = {}  # a left-out column state: moved above rounding
    for motion in motion_list:
        at = _times(motion, (hours,))
        if not at:
            continue
        Fz, Gz = sampled.Fz[motion.label], sampled.Gz[motion.label]
        known = (responses or {}).get((motion.label, at[0]))
        [base] = [known] if known is not None else prop.derived(Fz, Gz, motion, at)
        k = _steps(motion, at[0])
        P = conv.position(motion.navigation, motion.x, motion.p)[:2, prop.rows, k]
        A = conv.attitude(motion.navigation, motion.x, motion.p)[:, prop.rows, k]
        columns = [c for c, _, _ in prop.cases]
        base_si = prop.si(base)
        base_growth = prop.growth(Fz, motion, "z", k)
        size = rounding_floor(float(np.abs(base[:, columns]).max(initial=0.0)),
                              base.shape[0], k, 1.0)
        for name in report.left_out:
            moved = bool(np.abs(base[names.index(name), columns]).max(initial=0.0) > size)
            excited[name] = excited.get(name, False) or moved
        for f in report.findings:
            if f.block is None and (f.row in conv.vertical or f.column in conv.vertical):
                continue  # held in the propagation: no effect to show
            F2, G2 = with_finding(f, report, sampled, conv, model, motion.label)
            [changed] = prop.derived(F2, G2, motion, at)
            diff = (prop.si(changed) - base_si)[:, columns]
            position, attitude = _norm(P, diff, read_p), _norm(A, diff, read_a)
            floor_p = prop.floors([base, changed], k, P) if read_p else None
            floor_a = prop.floors([base, changed], k, A) if read_a else None
            tag = hours_tag(at[0] / 3600.0)
            growth = {f"{shown}_{tag}": (position if read_p else attitude) or 0.0,
                      f"{shown}_floor_{tag}": (floor_p if read_p else floor_a) or 0.0}
            mark_growth(growth, prop.growth(F2, motion, "z", k), base_growth,
                        (at[0] / 3600.0,), quantity=shown)
            per_motion.setdefault(f.entry, []).append((
                motion.label, position, attitude, floor_p, floor_a, growth))
    out = {entry: _alone(rows, read_p) for entry, rows in per_motion.items()}
    for f in report.findings:
        if f.entry in out and f.matrix == "F" and excited.get(f.column) is False:
            out[f.entry] = replace(out[f.entry], not_assessed=(
                f"effect not assessed: {f.column}, a state the hand leaves out, stays 0 "
                "from every initial error and source of the hand"))
    return out


def _alone(rows: list[tuple[str, float | None, float | None, float | None, float | None,
                            dict]], by_position: bool = True) -> AloneEffect:
    """One finding's :class:`AloneEffect` from its (motion, position, attitude, floors,
    growth) on each motion (growth: :func:`~ins_errors.checker.growth.mark_growth`'s
    dict; a change that grows exponentially names the motion of the fastest growth).
    The motion is chosen by the position change, or with ``by_position`` False (no
    position measured) by the attitude change."""
    def most(index: int) -> float | None:
        return None if rows[0][index] is None else max(r[index] for r in rows)

    pick, floor_pick = (1, 3) if by_position else (2, 4)
    real = [r for r in rows if r[pick] is not None and r[pick] > r[floor_pick]]
    real_a = [r for r in rows if r[2] is not None and r[2] > r[4]]
    attitude = most(2) if not real_a else max(r[2] for r in real_a)
    floor_a = (most(4) if not real_a else max(r[4] for r in real_a if r[2] == attitude))
    growing = [r for r in rows if any(v is True for k, v in r[5].items()
                                      if k.startswith("exponential_"))]
    if growing:
        fastest = min(growing, key=lambda r: r[5]["e_folding_s"])  # (the first on ties)
        return AloneEffect(fastest[1], attitude, fastest[0], fastest[3], floor_a,
                           fastest[5]["e_folding_s"], fastest[5]["growing_mode"])
    if not real:
        return AloneEffect(most(1), attitude, None, most(3), floor_a)
    best = max(real, key=lambda r: r[pick])  # (the first motion on ties)
    return AloneEffect(best[1], attitude, best[0], best[3], floor_a)


def vertical_effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
                     motion_list: list[Motion], hours: tuple[float, ...] = EFFECT_HOURS
                     ) -> dict[str, VerticalEffect]:
    """Effect on the height error of each finding in a vertical-channel row (or a pair,
    :attr:`EntryFinding.pair`, with an entry in one), the vertical channel not held
    (:class:`VerticalEffect`).

    The derived model, and the derived model with only that entry replaced by the
    hand's, are propagated with nothing held from each state (the vertical ones
    included) and each source of the hand at its typical size; the largest change of
    the height error over the cases is compared with its rounding floor, and growth
    past :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings is named with its
    mode (:func:`~ins_errors.checker.growth.mark_growth`: the model's own undamped
    vertical channel, or a faster one of the hand's).
    """
    found = [f for f in report.findings if f.block is None and (
        f.row in conv.vertical or (f.pair is not None and f.pair[0] in conv.vertical))]
    if not found:
        return {}
    prop = _Propagation.of(report, conv, model)
    n_h = len(report.states)
    free = replace(prop, held_h=[], held_z=[], conv=None, holds={}, cases=(
        [(j, f"initial {s}", report.magnitudes[s][1]) for j, s in enumerate(report.states)]
        + [(n_h + b, f"source {s}", report.magnitudes[s][1])
           for b, s in enumerate(report.sources)]))
    columns = [c for c, _, _ in free.cases]
    rows: dict[str, list] = {}  # entry -> [(motion, heights, floors, cases, growth)]
    for motion in motion_list:
        at = _times(motion, hours)
        if not at:
            continue
        Fz, Gz = sampled.Fz[motion.label], sampled.Gz[motion.label]
        base = free.derived(Fz, Gz, motion, at)
        base_growth = _motion_growth(Fz, [], _steps(motion, at[-1]))
        readout = conv.position(motion.navigation, motion.x, motion.p)[2:, free.rows, :]
        for f in found:
            F2, G2 = with_finding(f, report, sampled, conv, model, motion.label)
            changed = free.derived(F2, G2, motion, at)
            heights, floors, cases, growth, own = [], [], [], {}, []
            for t, b, c in zip(at, base, changed, strict=True):
                k = _steps(motion, t)
                H = readout[:, :, k]
                with np.errstate(over="ignore", invalid="ignore"):
                    change = np.abs(H @ (free.si(c) - free.si(b))[:, columns])[0]
                    derived = np.abs(H @ free.si(b)[:, columns])[0]
                change = np.where(np.isfinite(change), change, np.inf)
                j = first_largest(change)
                heights.append(float(change[j]))
                own.append(float(derived[j]))
                floors.append(free.floors([b, c], k, H))
                cases.append(free.cases[j][1])
                tag = hours_tag(t / 3600.0)
                growth[f"position_{tag}"] = heights[-1]
                growth[f"position_floor_{tag}"] = floors[-1]
            mark_growth(growth, _motion_growth(F2, [], _steps(motion, at[-1])), base_growth,
                        tuple(t / 3600.0 for t in at))
            rows.setdefault(f.entry, []).append(
                (motion.label, tuple(t / 3600.0 for t in at), heights, floors, cases, growth,
                 own))
    return {entry: _vertical(found_rows) for entry, found_rows in rows.items()}


def _vertical(rows: list) -> VerticalEffect:
    """One finding's :class:`VerticalEffect` from its rows on each motion (the times of
    the longest motion; the fastest growing mode where one is named)."""
    times = max((r[1] for r in rows), key=len)
    growing = [r for r in rows if "e_folding_s" in r[5]]
    fastest = min(growing, key=lambda r: r[5]["e_folding_s"]) if growing else None
    height, floor, case, motion, exponential, derived = [], [], [], [], [], []
    for n, h in enumerate(times):
        tag = hours_tag(h)
        here = [r for r in rows if len(r[1]) > n]
        grows = [r for r in here if r[5].get(f"exponential_{tag}")]
        above = [r for r in here if r[2][n] > r[3][n]]
        if grows:
            best = min(grows, key=lambda r: r[5]["e_folding_s"])
            height.append(best[2][n])
            floor.append(best[3][n])
            case.append(None)
            motion.append(best[0])
            exponential.append(True)
            derived.append(None)
        elif above:
            best = max(above, key=lambda r: r[2][n])  # (the first motion on ties)
            height.append(best[2][n])
            floor.append(best[3][n])
            case.append(best[4][n])
            motion.append(best[0])
            exponential.append(False)
            derived.append(best[6][n])
        else:
            height.append(max(r[2][n] for r in here))
            floor.append(max(r[3][n] for r in here))
            case.append(None)
            motion.append(None)
            exponential.append(False)
            derived.append(None)
    return VerticalEffect(tuple(times), tuple(height), tuple(floor), tuple(case),
                          tuple(motion), tuple(exponential),
                          fastest[5]["e_folding_s"] if fastest else None,
                          fastest[5]["growing_mode"] if fastest else None, tuple(derived))
