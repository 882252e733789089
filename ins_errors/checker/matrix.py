"""Check a hand-coded F and G against the derived linear model, entry by entry.

The derived linearisation of a model is sampled along the checker's motions (a static
base, a cruise and a manoeuvre, :func:`motions`), carried into the researcher's declared
convention (:mod:`~ins_errors.checker.conventions`: ``ż = (Ṫ + T F) T⁻¹ z + T G w``) and
restricted to the researcher's states, in their order. Each entry of F and G is then
compared with the hand's at every sample.

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
  term`` and a term that is present but wrong is a ``mistake, small effect``.

Then both linear models are propagated on each motion for 1 h and 24 h from each initial
error (and each error source of G) at its typical magnitude, and the position and
attitude error differences are reported (:func:`propagate_effects`), each against its
rounding floor (:func:`rounding_floor`): a difference below it is no effect, and no
initial error or source is named for it. A difference that follows a growing mode of the
hand model past :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings is marked as
exponential growth with the mode's e-folding time (:func:`_motion_growth`,
:func:`~ins_errors.checker.growth.mark_growth`, the equation checker's rule).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from ins_errors.checker import motion_store, propagation_store
from ins_errors.checker.conventions import BiasState, Convention, convention
from ins_errors.checker.extreme import first_largest
from ins_errors.checker.growth import growth_rate, hours_tag, mark_growth
from ins_errors.checker.kinds import (
    COEFFICIENT,
    DECLARED,
    EXTRA,
    MISTAKE,
    OMITTED,
    SIGN,
    SMALL_MISTAKE,
    SYMBOL,
)
from ins_errors.checker.kinds import severity as classify_severity
from ins_errors.checker.matrix_input import (
    HandMatrices,
    evaluate_function,
    load_hand,
    read_matrix_file,
    split_spec,
)
from ins_errors.checker.matrix_slips import Entry, index_slips
from ins_errors.checker.navigation import navigation_arrays, require_description
from ins_errors.checker.typical import (
    _earth,
    magnitude_override,
    schuler_magnitudes,
    typical_magnitude,
)
from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.numeric.blas_threads import import_limited, one_blas_thread

DEFAULT_THRESHOLD = 1e-3
"""Relative size separating a dropped small term from a mistake."""
AGREEMENT = 1e-6
"""Relative size at or below which two entries agree (rounding, constants' last digits)."""
PARTIAL = 0.05
"""A hand/model ratio within this of 1 is an approximation (within this of −1: a wrong sign)."""
HOURS = 24.0
"""Length of every motion, h."""
STEP = 60.0
"""Sample step of every motion, s: samples at t = 0, 60, …, 86 400 s."""
EFFECT_HOURS = (1.0, 24.0)
"""Times at which the propagated models are compared, h."""
ARCSEC = np.pi / (180 * 3600)
EPS = float(np.finfo(float).eps)
"""Machine epsilon of the propagation (float64)."""
APPROXIMATED = "approximated"
"""Kind of a coefficient the hand writes within :data:`PARTIAL` of the model's (a small
part of it left out: a constant radius for R_N + h, a constant g): an omission."""
LEFT_OUT = "state left out"
"""Kind of the coupling to a convention state the hand model does not have."""


# --------------------------------------------------------------------------------------
# Motions
# --------------------------------------------------------------------------------------
@dataclass
class Motion:
    """A motion sampled for the matrix check.

    Attributes
    ----------
    label : str
        ``static``, ``cruise`` or ``manoeuvre``.
    description : str
        One line.
    times : numpy.ndarray, shape (K,)
        Sample times, s.
    x, u : numpy.ndarray
        Ideal states (n, K) and inputs (nu, K).
    p : numpy.ndarray
        Parameters.
    navigation : dict
        Navigation arrays (:data:`~ins_errors.checker.navigation.FIELDS`), trailing axis K.
    kept : dict
        What checks along this motion computed from it and may reuse (the derived model
        in a convention, :func:`derived_in_convention`); read-only arrays.
    """

    label: str
    description: str
    times: np.ndarray
    x: np.ndarray
    u: np.ndarray
    p: np.ndarray
    navigation: dict[str, np.ndarray]
    kept: dict = field(default_factory=dict, repr=False, compare=False)


def _profiles(model, hours: float):
    """(label, profile) of the three motions for ``model``."""
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.motion_spec import default_legs

    lat, lon = np.radians(50.0), np.radians(30.0)
    static = ("static", tr.static_profile(lat, lon, np.radians(30.0), 0.0))
    if any(o.name == "heading" for o in model.outputs):
        return [static,
                ("cruise", tr.great_circle_profile(lat, lon, np.radians(60.0), 250.0, 10_000.0)),
                ("manoeuvre", tr.manoeuvre_profile(lat, lon, np.radians(60.0), 200.0,
                                                   default_legs(200.0, 3000.0,
                                                                int(np.ceil(hours))),
                                                   3000.0))]
    # models without a heading output follow geographic velocities: an eastward cruise
    # along the parallel, and a manoeuvre that weaves north and south, speeds up and
    # slows down, climbs and descends (it stays within a few degrees of latitude)
    t = np.arange(0.0, hours * 3600.0 + 1201.0, 600.0)
    cruise = tr.sampled_profile(t, 0 * t, 250.0 + 0 * t, lat, lon, 0.0, 10_000.0 + 0 * t)
    cruise.description = "eastward cruise along the parallel φ 50°, 250 m/s, h 10 km"
    weave = tr.sampled_profile(t, 100.0 * np.sin(2 * np.pi * t / 7200.0),
                               200.0 + 50.0 * np.cos(2 * np.pi * t / 3600.0), lat, lon, 0.0,
                               6000.0 + 3000.0 * np.sin(2 * np.pi * t / 5400.0))
    weave.description = ("manoeuvre from φ 50°: v_N 100 sin(2πt/2 h), v_E 200 + 50 cos(2πt/1 h)"
                         " m/s, h 6 ± 3 km")
    return [static, ("cruise", cruise), ("manoeuvre", weave)]


def _weave(t: np.ndarray) -> tuple[np.ndarray, ...]:
    """Commands of the strapdown manoeuvre: S-turns, speed and height changes, all day.

    Returns (V, dV, r, dr, v_D, dv_D): ground speed, turn rate (rad/s, to the right), down
    velocity and their rates (see :class:`ins_errors.numeric.strapdown_truth.Flight`).
    """
    w_turn, w_speed, w_climb = 2 * np.pi / 1200.0, 2 * np.pi / 3600.0, 2 * np.pi / 4800.0
    r0, dv, climb = 0.01, 30.0, 5.0
    return (220.0 + dv * np.sin(w_speed * t), dv * w_speed * np.cos(w_speed * t),
            r0 * np.cos(w_turn * t), -r0 * w_turn * np.sin(w_turn * t),
            -climb * np.cos(w_climb * t), climb * w_climb * np.sin(w_climb * t))


def _strapdown_runs(model, hours: float, step: float, p: np.ndarray):
    """(label, Trajectory) of the three flights of a strapdown model."""
    from ins_errors.numeric import strapdown_truth as st

    lat, lon = np.radians(50.0), np.radians(30.0)
    flights = [
        ("static", st.static(lat, lon, 0.0, heading=np.radians(30.0))),
        ("cruise", st.great_circle(lat, lon, np.radians(60.0), 250.0, 10_000.0)),
        ("manoeuvre", st.Flight(lat, lon, 5000.0, np.radians(60.0), _weave,
                                "weaving flight from φ 50°, λ 30°, course 60°: turn rate "
                                "0.57 cos(2πt/20 min) °/s (bank up to 13°), speed 220 ± 30 m/s "
                                "(period 1 h), height 5 ± 3.8 km (period 80 min)")),
    ]
    return [(label, flight.description, st.trajectory(model, flight, hours * 3600.0, step, p=p))
            for label, flight in flights]


def _parameter_items(parameters: Mapping[str, float] | None) -> tuple[tuple[str, float], ...]:
    """``parameters`` as sorted (name, float) pairs (hashable; () for none)."""
    return tuple(sorted((str(k), float(v)) for k, v in (parameters or {}).items()))


def motions(model, hours: float = HOURS, step: float = STEP, ellipsoid: str | None = None,
            parameters: Mapping[str, float] | None = None) -> list[Motion]:
    """The checker's motions for ``model``, sampled every ``step`` s for ``hours`` h.

    Static base at φ 50°, λ 30°; a cruise at 250 m/s and 10 km (a great circle leaving at
    track 60° for models with a heading, an eastward cruise along the parallel otherwise);
    a manoeuvre with turns, speed changes, climbs and descents. ``ellipsoid`` (e.g.
    ``"wgs84"``) replaces the model's default Earth shape; ``parameters`` (name -> SI
    value, e.g. damping gains; default: none)
    replace the model's defaults in every sample's parameter vector, where the derived
    model is evaluated.
    """
    require_description(model)
    return list(_motions(model.key, float(hours), float(step), ellipsoid,
                         _parameter_items(parameters)))


@lru_cache(maxsize=8)
@one_blas_thread
def _motions(model_key: str, hours: float, step: float, ellipsoid: str | None,
             parameters: tuple[tuple[str, float], ...] = ()) -> tuple[Motion, ...]:
    """Motions of :func:`motions`, kept for the next check in the same process (and on
    disk for the next process: :mod:`~ins_errors.checker.motion_store`, whose key holds
    the parameter vector)."""
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    p = model.parameter_vector(ellipsoid=ellipsoid, **dict(parameters))
    name = motion_store.key(model, hours, step, ellipsoid, p)
    flown = motion_store.load(name)
    if flown is None:
        flown = _fly(model, hours, step, p)
        motion_store.store(name, flown)
    return tuple(Motion(label, description, a["times"], a["x"], a["u"], a["p"],
                        navigation_arrays(model, a["x"], a["u"], a["p"]))
                 for label, description, a in flown)


def _fly(model, hours: float, step: float, p: np.ndarray
         ) -> list[tuple[str, str, dict[str, np.ndarray]]]:
    """(label, description, {times, x, u, p}) of each motion, flown."""
    from ins_errors.checker import strapdown_description
    from ins_errors.numeric import trajectories as tr

    if model.name == "strapdown_ned" or strapdown_description.describes(model):
        runs = _strapdown_runs(model, hours, step, p)
    else:
        runs = [(label, profile.description,
                 tr.trajectory(model, profile, hours * 3600.0, step, p=p))
                for label, profile in _profiles(model, hours)]
    out = []
    for label, description, run in runs:
        steps = np.arange(run.n_steps + 1)
        x = (np.repeat(run.truth[:, :1], steps.size, axis=1) if run.constant
             else run.truth)
        arrays = {"times": run.times, "x": x, "u": run.inputs_at(steps), "p": run.parameters}
        # C order, as read back from the store: a check on flown motions and one on
        # stored motions do the same arithmetic
        out.append((label, description, {f: np.ascontiguousarray(a, dtype=float)
                                          for f, a in arrays.items()}))
    return out


def unchecked_gains(model, convention_name: str, rows: Iterable[str], motion: Motion
                    ) -> list[str]:
    """The model's damping gains (``Parameter(..., damping_gain=True)``) at 0 in
    ``motion.p`` that enter the given rows of the derived model in the convention: the
    terms they multiply are 0 there, so a check of those rows does not see them.

    A gain enters a row when setting it to 1 (SI) alone changes the row of F or G at the
    motion's first sample (the ideal motion is the same: a damping loop closes on a
    difference that is 0 in ideal work).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    convention_name : str
        The convention of the rows (``model``: the model's own error states).
    rows : iterable of str
        State names of the convention the check compares (others are ignored).
    motion : Motion
        A motion of :func:`motions`, with the parameters the check used.

    Returns
    -------
    list of str
        The gains' names, in the model's order.
    """
    p = np.asarray(motion.p, dtype=float)
    zero = [k for k, info in enumerate(model.parameters)
            if info.damping_gain and p[..., k].flat[0] == 0]
    conv = convention(model, convention_name)
    wanted = [conv.names.index(r) for r in rows if r in conv.names]
    if not zero or not wanted:
        return []
    first = replace(motion, times=motion.times[:1], x=motion.x[:, :1], u=motion.u[:, :1],
                    navigation={}, kept={})
    base_f, base_g = _derived_in_convention(model, conv, first)
    found = []
    for k in zero:
        probe = p.copy()
        probe[..., k] = 1.0
        f, g = _derived_in_convention(model, conv, replace(first, p=probe, kept={}))
        if (np.any(f[:, wanted] != base_f[:, wanted])
                or np.any(g[:, wanted] != base_g[:, wanted])):
            found.append(model.parameters[k].name)
    return found


# --------------------------------------------------------------------------------------
# Derived model in the convention
# --------------------------------------------------------------------------------------
def derived_in_convention(model, conv: Convention, motion: Motion
                          ) -> tuple[np.ndarray, np.ndarray]:
    """The derived F and G carried into ``conv``: shapes (K, nz, nz) and (K, nz, nw).

    Kept on the motion for the next check of the same model in the same convention
    (read-only arrays).
    """
    key = ("derived", model.key, conv.name, conv.biases)
    if key not in motion.kept:
        F, G = (_with_bias_states(model, conv, *derived_in_convention(model, conv.base, motion))
                if conv.biases else _derived_in_convention(model, conv, motion))
        F.setflags(write=False)
        G.setflags(write=False)
        motion.kept[key] = (F, G)
    return motion.kept[key]


def _with_bias_states(model, conv: Convention, F: np.ndarray, G: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """The derived model with ``conv.biases`` as states: ``[[F, G[:, b]], [0, D]]``.

    Parameters
    ----------
    conv : Convention
        With bias states (:meth:`~ins_errors.checker.conventions.Convention.with_biases`).
    F, G : ndarray, shapes (K, nz, nz) and (K, nz, nw)
        The derived model in ``conv.base``.

    Returns
    -------
    F, G : ndarray, shapes (K, nz + nb, nz + nb) and (K, nz + nb, nw)
        A bias state's column of F is its source's column of G, its row is ``ḃ = D b``
        (D = 0 for a random constant, −1/τ for a Gauss–Markov bias); its source's column
        of G is zero (the source enters through the state, not as an input).
    """
    src_names = [s.name for s in model.sources]
    columns = [src_names.index(b.name) for b in conv.biases]
    k, nz, nw = G.shape
    nb = len(columns)
    Fa = np.zeros((k, nz + nb, nz + nb))
    Fa[:, :nz, :nz] = F
    Fa[:, :nz, nz:] = G[:, :, columns]
    Fa[:, np.arange(nz, nz + nb), np.arange(nz, nz + nb)] = [b.rate for b in conv.biases]
    Ga = np.zeros((k, nz + nb, nw))
    Ga[:, :nz, :] = G
    Ga[:, :, columns] = 0.0
    return Fa, Ga


def _derived_in_convention(model, conv: Convention, motion: Motion
                           ) -> tuple[np.ndarray, np.ndarray]:
    F = np.moveaxis(model.state_matrix(motion.x, motion.u, motion.p), -1, 0)
    G = np.moveaxis(model.source_matrix(motion.x, motion.u, motion.p), -1, 0)
    if conv.transform is None:
        return F, G
    T, T_dot = conv.matrices(model, motion.x, motion.p, motion.u)
    if conv.lift is not None:  # onto the model's own state manifold (T L = I)
        Fz = (T_dot + T @ F) @ np.moveaxis(conv.lift(motion.x, motion.p), -1, 0)
    elif T.shape[1] == T.shape[2]:
        Fz = np.swapaxes(np.linalg.solve(np.swapaxes(T, 1, 2),
                                         np.swapaxes(T_dot + T @ F, 1, 2)), 1, 2)
    else:  # a direction of x_e the convention does not see (quaternion norm): T⁺
        Fz = (T_dot + T @ F) @ np.linalg.pinv(T)
    return Fz, T @ G


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
        ``dropped small term`` (the severities of :mod:`~ins_errors.checker.classify`).
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

    @property
    def entry(self) -> str:
        """``F[row, column]``."""
        return f"{self.matrix}[{self.row}, {self.column}]"


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
    position_difference, position_model : float
        Horizontal position error: |hand − model| and |model|, m.
    attitude_difference, attitude_model : float
        Attitude error (norm of the three angles): |hand − model| and |model|, rad.
    position_floor, attitude_floor : float
        Rounding floor of the differences on this motion at this time (the same for every
        case; :func:`rounding_floor`), m and rad: a difference at or below it is no effect.
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
    position_difference: float
    position_model: float
    attitude_difference: float
    attitude_model: float
    position_floor: float = 0.0
    attitude_floor: float = 0.0
    e_folding: float | None = None
    growing_mode: str | None = None
    exponential: bool = False

    @property
    def position_above_rounding(self) -> bool:
        """The position difference is above its rounding floor."""
        return self.position_difference > self.position_floor

    @property
    def attitude_above_rounding(self) -> bool:
        """The attitude difference is above its rounding floor."""
        return self.attitude_difference > self.attitude_floor


@dataclass(frozen=True)
class AloneEffect:
    """Effect of one finding alone after 24 h: the derived model with only that entry
    replaced by the hand's (:func:`finding_effects`).

    Attributes
    ----------
    position : float
        Largest horizontal position change over every case and motion, m (rounding
        included: compare with ``position_floor``).
    attitude : float
        Largest attitude change, rad.
    motion : str or None
        Motion where the position change above its floor is largest; None when it is
        below the floor on every motion (no motion is named for rounding).
    position_floor, attitude_floor : float
        Rounding floors (:func:`rounding_floor`): of the motion named, or the largest over
        the motions when the change is below them everywhere; m and rad.
    e_folding : float or None
        When the entry alone gives a growing mode the derived model lacks, past
        :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings after 24 h: its
        e-folding time, s (the fastest over the motions; ``motion`` is that motion).
        The change is then said to grow exponentially instead of being given as a figure.
    growing_mode : str or None
        ``"hand"`` (a mode the entry adds) or ``"model"``, with ``e_folding``.
    """

    position: float
    attitude: float
    motion: str | None
    position_floor: float
    attitude_floor: float
    e_folding: float | None = None
    growing_mode: str | None = None

    @property
    def exponential(self) -> bool:
        """The change grows exponentially (``e_folding`` is set)."""
        return self.e_folding is not None

    @property
    def position_above_rounding(self) -> bool:
        """The position change is above its rounding floor on some motion."""
        return self.motion is not None

    @property
    def attitude_above_rounding(self) -> bool:
        """The attitude change is above its rounding floor on some motion."""
        return self.attitude > self.attitude_floor


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
    """

    hours: tuple[float, ...]
    height: tuple[float, ...]
    floor: tuple[float, ...]
    case: tuple[str | None, ...]
    motion: tuple[str | None, ...]
    exponential: tuple[bool, ...]
    e_folding: float | None = None
    growing_mode: str | None = None


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
        would swamp every other difference).
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

    @property
    def mistakes(self) -> list[EntryFinding]:
        """Findings classed as mistakes."""
        return [f for f in self.findings if f.severity in (MISTAKE, SMALL_MISTAKE)]

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


def _classify(h: np.ndarray, m: np.ndarray, mag: float, scale: np.ndarray, threshold: float,
              left_out: bool, motion_of: np.ndarray | None = None
              ) -> tuple[str, str, str] | None:
    """(kind, severity, detail) of one entry's samples, or None when they agree.

    ``motion_of`` (S,) gives the motion of each sample (default: one motion).
    """
    if motion_of is None:
        motion_of = np.zeros(h.shape, dtype=int)
    ratio = np.abs(h - m) * mag / scale
    size = float(ratio.max())
    if size <= AGREEMENT:
        return None
    tiny = AGREEMENT * scale
    hand_zero = np.all(np.abs(h) * mag <= tiny)
    model_zero = np.all(np.abs(m) * mag <= tiny)
    detail = ""
    if left_out:
        kind = LEFT_OUT
    elif hand_zero:
        kind = OMITTED
    elif model_zero:
        kind = EXTRA
    else:
        both = (np.abs(m) * mag > tiny) & (np.abs(h) * mag > tiny)
        only_hand = (np.abs(m) * mag <= tiny) & (np.abs(h) * mag > tiny)
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
            kind, detail = COEFFICIENT, f"hand/model = {np.median(q):.6g} at every sample"
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
    for term in candidates:
        c = np.concatenate([term.values[k] for k in labels])
        for sign in (1.0, -1.0):
            rest = _classify(h, m - sign * c, mag, scale, threshold, False, motion_of)
            if rest is None:
                return term, ""
            kind, severity, _ = rest
            if fallback is None and severity not in (MISTAKE, SMALL_MISTAKE):
                size = float((np.abs(h - (m - sign * c)) * mag / scale).max())
                fallback = (term, f"what remains is a {severity} ({kind}), size {size:.2g}")
    return fallback


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
             used: set[int] | None = None, source_sizes: np.ndarray | None = None) -> None:
    """Classify every entry of the hand's rows into ``report.findings``.

    ``declared``: (matrix, row, column) -> the declared terms in force for that entry
    (:class:`DeclaredTerm`); ``used`` receives the declarations that explain a finding.
    ``source_sizes``: typical size of every model error source, SI, in the model's
    order (default: the fixed ones of
    :func:`~ins_errors.checker.typical.typical_magnitude`).
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
    findings = []
    compared = 0
    entry_terms = None  # the derived entries' terms (SymPy), built for the first that needs them
    for a, i in enumerate(rows):
        terms = [np.abs(Fz[:, i, :]) * state_mag, np.abs(Fh_full[:, a, :]) * state_mag,
                 np.abs(Gz[:, i, :]) * source_mag]
        if Gh is not None:
            terms.append(np.abs(Gh[:, a, :]) * source_mag[src_cols])
        scale = np.max(np.concatenate(terms, axis=1), axis=1)
        scale = np.where(scale > 0, scale, np.inf)
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
                                sample_motion)
            if verdict is None:
                continue
            kind, severity, detail = verdict
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
            elif (kind == COEFFICIENT and matrix == "F"  # a term of a sum left out?
                  and i < n_own and j < n_own):  # (not in a bias state's row or column)
                if entry_terms is None:
                    from ins_errors.checker.matrix_terms import EntryTerms

                    entry_terms = EntryTerms(model, conv.base, motion_list)
                found = _term_left_out(entry_terms, i, j, h, m, mag, scale)
                if found is not None:
                    kind, detail = OMITTED, found
                    severity = classify_severity(OMITTED, float(ratio.max()),
                                                 report.threshold)
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
    findings.sort(key=lambda f: (f.severity not in (MISTAKE, SMALL_MISTAKE), -f.size))
    report.findings = findings
    report.compared = compared


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

    found = left_out(terms.terms(i, j), h, m, mag, scale, AGREEMENT)
    if found is None:
        return None
    missing = sum(t.values for t in found)
    share = float(np.abs(missing).max() / np.abs(m).max())
    return (f"term left out: {' and '.join(t.describe() for t in found)}, up to "
            f"{share:.2g} of the entry's largest value")


# --------------------------------------------------------------------------------------
# Propagation of both linear models
# --------------------------------------------------------------------------------------
def _taylor_steps(A: np.ndarray, dt: float) -> np.ndarray:
    """exp(A dt) for a batch (K, n, n): scaling and squaring with a degree-10 Taylor sum.

    ``result = Σ_k term_k``, ``term_k = term_{k-1} @ M / k`` (``M = A dt / 2^s``), then
    ``s`` squarings; evaluated in place (the stacks are megabytes: fresh arrays for each
    operation cost as much as the products), the same operations in the same order.
    """
    M = A * dt
    norm = np.max(np.sum(np.abs(M), axis=-1))
    squarings = max(0, int(np.ceil(np.log2(norm / 0.25)))) if norm > 0.25 else 0
    M /= 2**squarings
    result = np.empty_like(M)
    result[...] = np.eye(A.shape[-1])
    term, spare = result.copy(), np.empty_like(M)
    for k in range(1, 11):
        np.matmul(term, M, out=spare)
        spare /= k
        term, spare = spare, term
        result += term
    for _ in range(squarings):
        np.matmul(result, result, out=spare)
        result, spare = spare, result
    return result


_KEPT_TRANSITIONS: OrderedDict[tuple, tuple[np.ndarray, ...]] = OrderedDict()
KEEP_TRANSITIONS = 256
"""Propagations kept for the next check in the same process (a few kB each)."""


def _transition(A: np.ndarray, times: np.ndarray, at: list[float]) -> list[np.ndarray]:
    """Φ(t) of ``ẏ = A(t) y`` (A sampled on the uniform grid ``times``) at times ``at``.

    A constant A (one sample repeated) uses the matrix exponential directly; otherwise each
    step uses the exponential of the mean of A at its two ends (second order).

    Kept for the next check in the same process, by the content of ``A``, ``times`` and
    ``at`` (checks of the same model on the same motions propagate the same derived model,
    and mostly the same single-entry changes of it), and on disk for the next process
    (:mod:`~ins_errors.checker.propagation_store`); the kept matrices are read-only.
    """
    key = (A.shape, A.dtype.str, _digest(A), _digest(np.asarray(times, dtype=float)),
           tuple(float(t) for t in at))
    kept = _KEPT_TRANSITIONS.get(key)
    if kept is None:
        stored = propagation_store.name(key)
        kept = propagation_store.load(stored)
        if kept is None or len(kept) != len(at) or kept[0].shape != A.shape[1:]:
            kept = tuple(_transition_of(A, times, at))
            propagation_store.store(stored, kept)
        for phi in kept:
            phi.setflags(write=False)
        _KEPT_TRANSITIONS[key] = kept
        while len(_KEPT_TRANSITIONS) > KEEP_TRANSITIONS:
            _KEPT_TRANSITIONS.popitem(last=False)
    else:
        _KEPT_TRANSITIONS.move_to_end(key)
    return list(kept)


def _digest(array: np.ndarray) -> bytes:
    """SHA-1 of an array's bytes (half the time of BLAKE2b on these stacks: ~2 ms for a
    day's 1441 steps of 15 × 15, against ~10 ms for the propagation it may save)."""
    return hashlib.sha1(np.ascontiguousarray(array).data, usedforsecurity=False).digest()


def _transition_of(A: np.ndarray, times: np.ndarray, at: list[float]) -> list[np.ndarray]:
    """:func:`_transition`, computed (within :func:`check_matrices`' one-thread limit,
    which the import extends to SciPy's own BLAS)."""
    expm = import_limited("scipy.linalg").expm

    # a model with an exponentially growing mode overflows to inf / nan: the report says
    # it grows exponentially and writes no number, so the floating-point warnings of
    # that overflow (numpy's and SciPy's matrix products) tell nothing more
    with np.errstate(over="ignore", invalid="ignore"):
        if np.all(A[:1] == A):
            return [expm(A[0] * t) for t in at]
        return _stepped_transition(A, times, at)


def _stepped_transition(A: np.ndarray, times: np.ndarray, at: list[float]
                        ) -> list[np.ndarray]:
    """:func:`_transition_of` of a time-varying A: each step the exponential of the mean
    of A at its two ends."""
    dt = float(times[1] - times[0])
    mean = A[1:] + A[:-1]
    mean *= 0.5
    steps = _taylor_steps(mean, dt)
    wanted = {round(t / dt): t for t in at}
    out: dict[float, np.ndarray] = {}
    phi, spare = np.eye(A.shape[-1]), np.empty(A.shape[1:])
    for k in range(steps.shape[0] + 1):
        if k in wanted:
            out[wanted[k]] = phi.copy()
        if k < steps.shape[0]:
            np.matmul(steps[k], phi, out=spare)
            phi, spare = spare, phi
    return [out[t] for t in at]


def _augmented(F: np.ndarray, G: np.ndarray, scale: np.ndarray, held: list[int]
               ) -> np.ndarray:
    """[[F, G], [0, 0]] in scaled variables (each state / source over its magnitude), with
    the rows and columns of the ``held`` states zeroed (they keep their initial value and
    feed nothing)."""
    k, n, m = G.shape
    A = np.zeros((k, n + m, n + m))
    A[:, :n, :n] = F
    A[:, :n, n:] = G
    A[:, held, :] = 0.0
    A[:, :, held] = 0.0
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
                   [names.index(v) for v in conv.vertical], cases)

    def derived(self, Fz: np.ndarray, Gz: np.ndarray, motion: Motion, at: list[float]
                ) -> list[np.ndarray]:
        """Response of the derived model to each unit case, in scaled variables (each
        state or source over its typical magnitude): (n_z + m, n_h + m) at each time, every
        convention state included (:meth:`si` gives the hand's states in SI)."""
        n_z, n_h, m = Fz.shape[1], len(self.rows), len(self.src_cols)
        phis = _transition(_augmented(Fz, Gz[:, :, self.src_cols],
                                      np.concatenate([self.mags_z, self.mags_src]),
                                      self.held_z), motion.times, at)
        embed = np.zeros((n_z + m, n_h + m))
        embed[self.rows, np.arange(n_h)] = 1.0
        embed[n_z:, n_h:] = np.eye(m)
        # an overflowed transition (inf) times embed's zeros is nan: the exponential
        # growth is reported as such (mark_growth), as in _transition
        with np.errstate(over="ignore", invalid="ignore"):
            return [phi @ embed for phi in phis]

    def si(self, scaled: np.ndarray) -> np.ndarray:
        """The hand's states (SI) of a scaled derived response: (n_h, n_h + m)."""
        return scaled[self.rows] * self.mags_h[:, None]

    def hand(self, Fh: np.ndarray, Gh: np.ndarray | None, motion: Motion, at: list[float]
             ) -> list[np.ndarray]:
        """The same for the hand model, in scaled variables: (n_h + m, n_h + m)."""
        Gh = np.zeros((*Fh.shape[:2], 0)) if Gh is None else Gh
        return _transition(_augmented(Fh, Gh, np.concatenate([self.mags_h, self.mags_src]),
                                      self.held_h), motion.times, at)

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


def propagate_effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
                      motion_list: list[Motion], hours: tuple[float, ...] = EFFECT_HOURS,
                      responses: dict | None = None) -> list[Effect]:
    """Propagate the hand and the derived model; differences per initial error/source,
    with the rounding floor of each motion and time (:func:`rounding_floor`).

    ``responses``, if given, receives the derived model's scaled responses by (motion,
    time) (:func:`finding_effects` starts from them).
    """
    prop = _Propagation.of(report, conv, model)
    report.held = [v for v in conv.vertical if v in report.states]
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
        position = conv.position(motion.navigation)  # (3, nz, K)
        attitude = conv.attitude(motion.navigation)
        rows: list[Effect] = []
        growth: dict = {}  # worst position difference and floor at each time
        for t, scaled_h, scaled_z in zip(at, hand, derived, strict=True):
            k = _steps(motion, t)
            P = position[:2, prop.rows, k]
            A = attitude[:, prop.rows, k]
            resp_h, resp_z = scaled_h[:n_h] * prop.mags_h[:, None], prop.si(scaled_z)
            floor_p = prop.floors([scaled_h, scaled_z], k, P)
            floor_a = prop.floors([scaled_h, scaled_z], k, A)
            for c, case, text in prop.cases:
                diff = resp_h[:, c] - resp_z[:, c]
                rows.append(Effect(
                    motion.label, t / 3600.0, case, text, float(np.linalg.norm(P @ diff)),
                    float(np.linalg.norm(P @ resp_z[:, c])), float(np.linalg.norm(A @ diff)),
                    float(np.linalg.norm(A @ resp_z[:, c])), floor_p, floor_a))
            tag = hours_tag(t / 3600.0)
            growth[f"position_{tag}"] = max((e.position_difference for e in rows
                                             if e.hours == t / 3600.0), default=0.0)
            growth[f"position_floor_{tag}"] = floor_p
        last = _steps(motion, at[-1])
        mark_growth(growth, _motion_growth(sampled.Fh[motion.label], prop.held_h, last),
                    _motion_growth(sampled.Fz[motion.label], prop.held_z, last),
                    tuple(t / 3600.0 for t in at))
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


def finding_effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
                    motion_list: list[Motion], hours: float = EFFECT_HOURS[-1],
                    responses: dict | None = None) -> dict[str, AloneEffect]:
    """Effect of each finding alone: the derived model with only that entry replaced by
    the hand's, propagated like :func:`propagate_effects` (entries of held vertical-channel
    states are left out). ``responses``: the derived model's scaled responses by (motion,
    time) from :func:`propagate_effects`, if at hand (the same numbers; not computed
    again).

    On each motion the change is compared with its rounding floor (:func:`rounding_floor`
    of both propagations); the motion named is the one with the largest change above its
    floor, and none when the change is below the floor on every motion.

    Returns
    -------
    dict
        ``finding.entry`` -> :class:`AloneEffect` (largest horizontal position change, m;
        largest attitude change, rad; motion; floors), over every case.
    """
    prop = _Propagation.of(report, conv, model)
    names = conv.names
    src_names = [s.name for s in model.sources]
    # entry -> [(motion, position, attitude, position floor, attitude floor, growth)]
    per_motion: dict[str, list[tuple[str, float, float, float, float, dict]]] = {}
    for motion in motion_list:
        at = _times(motion, (hours,))
        if not at:
            continue
        Fz, Gz = sampled.Fz[motion.label], sampled.Gz[motion.label]
        known = (responses or {}).get((motion.label, at[0]))
        [base] = [known] if known is not None else prop.derived(Fz, Gz, motion, at)
        k = _steps(motion, at[0])
        P = conv.position(motion.navigation)[:2, prop.rows, k]
        A = conv.attitude(motion.navigation)[:, prop.rows, k]
        columns = [c for c, _, _ in prop.cases]
        base_si = prop.si(base)
        base_growth = _motion_growth(Fz, prop.held_z, k)
        for f in report.findings:
            if f.row in conv.vertical or f.column in conv.vertical:
                continue  # held in the propagation: no effect to show
            a, i = report.states.index(f.row), names.index(f.row)
            F2, G2 = Fz.copy(), Gz
            if f.matrix == "F":
                j = names.index(f.column)
                F2[:, i, j] = (sampled.Fh[motion.label][:, a, report.states.index(f.column)]
                               if f.column in report.states else 0.0)
            else:
                G2 = Gz.copy()
                G2[:, i, src_names.index(f.column)] = (
                    sampled.Gh[motion.label][:, a, report.sources.index(f.column)])
            [changed] = prop.derived(F2, G2, motion, at)
            diff = (prop.si(changed) - base_si)[:, columns]
            position = float(np.linalg.norm(P @ diff, axis=0).max(initial=0.0))
            floor_p = prop.floors([base, changed], k, P)
            growth = {f"position_{hours_tag(at[0] / 3600.0)}": position,
                      f"position_floor_{hours_tag(at[0] / 3600.0)}": floor_p}
            mark_growth(growth, _motion_growth(F2, prop.held_z, k), base_growth,
                        (at[0] / 3600.0,))
            per_motion.setdefault(f.entry, []).append((
                motion.label, position,
                float(np.linalg.norm(A @ diff, axis=0).max(initial=0.0)),
                floor_p, prop.floors([base, changed], k, A), growth))
    return {entry: _alone(rows) for entry, rows in per_motion.items()}


def _alone(rows: list[tuple[str, float, float, float, float, dict]]) -> AloneEffect:
    """One finding's :class:`AloneEffect` from its (motion, position, attitude, floors,
    growth) on each motion (growth: :func:`~ins_errors.checker.growth.mark_growth`'s
    dict; a change that grows exponentially names the motion of the fastest growth)."""
    position = max(r[1] for r in rows)
    real = [r for r in rows if r[1] > r[3]]
    real_a = [r for r in rows if r[2] > r[4]]
    attitude = max(r[2] for r in (real_a or rows))
    floor_a = (max(r[4] for r in real_a if r[2] == attitude) if real_a
               else max(r[4] for r in rows))
    growing = [r for r in rows if any(v is True for k, v in r[5].items()
                                      if k.startswith("exponential_"))]
    if growing:
        fastest = min(growing, key=lambda r: r[5]["e_folding_s"])  # (the first on ties)
        return AloneEffect(fastest[1], attitude, fastest[0], fastest[3], floor_a,
                           fastest[5]["e_folding_s"], fastest[5]["growing_mode"])
    if not real:
        return AloneEffect(position, attitude, None, max(r[3] for r in rows), floor_a)
    best = max(real, key=lambda r: r[1])  # (the first motion on ties)
    return AloneEffect(best[1], attitude, best[0], best[3], floor_a)


def vertical_effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
                     motion_list: list[Motion], hours: tuple[float, ...] = EFFECT_HOURS
                     ) -> dict[str, VerticalEffect]:
    """Effect on the height error of each finding in a vertical-channel row, the
    vertical channel not held (:class:`VerticalEffect`).

    The derived model, and the derived model with only that entry replaced by the
    hand's, are propagated with nothing held from each state (the vertical ones
    included) and each source of the hand at its typical size; the largest change of
    the height error over the cases is compared with its rounding floor, and growth
    past :data:`~ins_errors.checker.growth.GROWTH_SHOWN` e-foldings is named with its
    mode (:func:`~ins_errors.checker.growth.mark_growth`: the model's own undamped
    vertical channel, or a faster one of the hand's).
    """
    found = [f for f in report.findings if f.row in conv.vertical]
    if not found:
        return {}
    prop = _Propagation.of(report, conv, model)
    n_h = len(report.states)
    free = replace(prop, held_h=[], held_z=[], cases=(
        [(j, f"initial {s}", report.magnitudes[s][1]) for j, s in enumerate(report.states)]
        + [(n_h + b, f"source {s}", report.magnitudes[s][1])
           for b, s in enumerate(report.sources)]))
    columns = [c for c, _, _ in free.cases]
    names = conv.names
    src_names = [s.name for s in model.sources]
    rows: dict[str, list] = {}  # entry -> [(motion, heights, floors, cases, growth)]
    for motion in motion_list:
        at = _times(motion, hours)
        if not at:
            continue
        Fz, Gz = sampled.Fz[motion.label], sampled.Gz[motion.label]
        base = free.derived(Fz, Gz, motion, at)
        base_growth = _motion_growth(Fz, [], _steps(motion, at[-1]))
        readout = conv.position(motion.navigation)[2:, free.rows, :]  # down, m per unit
        for f in found:
            a, i = report.states.index(f.row), names.index(f.row)
            F2, G2 = Fz.copy(), Gz
            if f.matrix == "F":
                F2[:, i, names.index(f.column)] = (
                    sampled.Fh[motion.label][:, a, report.states.index(f.column)]
                    if f.column in report.states else 0.0)
            else:
                G2 = Gz.copy()
                G2[:, i, src_names.index(f.column)] = (
                    sampled.Gh[motion.label][:, a, report.sources.index(f.column)])
            changed = free.derived(F2, G2, motion, at)
            heights, floors, cases, growth = [], [], [], {}
            for t, b, c in zip(at, base, changed, strict=True):
                k = _steps(motion, t)
                H = readout[:, :, k]
                with np.errstate(over="ignore", invalid="ignore"):
                    change = np.abs(H @ (free.si(c) - free.si(b))[:, columns])[0]
                change = np.where(np.isfinite(change), change, np.inf)
                j = first_largest(change)
                heights.append(float(change[j]))
                floors.append(free.floors([b, c], k, H))
                cases.append(free.cases[j][1])
                tag = hours_tag(t / 3600.0)
                growth[f"position_{tag}"] = heights[-1]
                growth[f"position_floor_{tag}"] = floors[-1]
            mark_growth(growth, _motion_growth(F2, [], _steps(motion, at[-1])), base_growth,
                        tuple(t / 3600.0 for t in at))
            rows.setdefault(f.entry, []).append(
                (motion.label, tuple(t / 3600.0 for t in at), heights, floors, cases, growth))
    return {entry: _vertical(found_rows) for entry, found_rows in rows.items()}


def _vertical(rows: list) -> VerticalEffect:
    """One finding's :class:`VerticalEffect` from its rows on each motion (the times of
    the longest motion; the fastest growing mode where one is named)."""
    times = max((r[1] for r in rows), key=len)
    growing = [r for r in rows if "e_folding_s" in r[5]]
    fastest = min(growing, key=lambda r: r[5]["e_folding_s"]) if growing else None
    height, floor, case, motion, exponential = [], [], [], [], []
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
        elif above:
            best = max(above, key=lambda r: r[2][n])  # (the first motion on ties)
            height.append(best[2][n])
            floor.append(best[3][n])
            case.append(best[4][n])
            motion.append(best[0])
            exponential.append(False)
        else:
            height.append(max(r[2][n] for r in here))
            floor.append(max(r[3][n] for r in here))
            case.append(None)
            motion.append(None)
            exponential.append(False)
    return VerticalEffect(tuple(times), tuple(height), tuple(floor), tuple(case),
                          tuple(motion), tuple(exponential),
                          fastest[5]["e_folding_s"] if fastest else None,
                          fastest[5]["growing_mode"] if fastest else None)


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
                   parameters: Mapping[str, float] | None = None) -> MatrixReport:
    """Check a hand-coded F (and G) against the derived model of ``model_name``.

    Parameters
    ----------
    model_name : str
        Model name, model file or entry-point name (as :func:`~ins_errors.load_model`).
    hand : HandMatrices, or str / Path
        Already sampled matrices, or ``FILE.py:FUNCTION`` / ``FILE.npz`` / ``FILE.mat``.
    convention_name : str
        The convention the hand model's states are in (``model``: the model's own).
    threshold : float
        Relative size separating dropped small terms from mistakes (0 < threshold < 1).
    hours, step : float
        Length (h) and sample step (s) of the motions.
    effects : bool
        Also propagate both models (1 h and 24 h, or ``hours`` if shorter).
    motion_list : list of Motion, optional
        Pre-computed motions (default: :func:`motions`).
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
    values_set = dict(_parameter_items(parameters))
    motion_list = (motions(model, hours, step, ellipsoid, values_set) if motion_list is None
                   else motion_list)
    if not isinstance(hand, HandMatrices):
        path, function = split_spec(str(hand))
        if function is not None:
            fn, states, sources, markov = load_hand(path, function)
            bias_states(states, sources, markov, conv, model, f"{path.name}:{function}")
            hand = evaluate_function(fn, f"{path.name}:{function}", path, states, sources,
                                     motion_list, markov)
        else:
            hand = read_matrix_file(path, motion_list)
    conv = conv.with_biases(bias_states(hand.states, hand.sources, hand.markov, conv, model,
                                        hand.name))
    size_of = _magnitudes(model, magnitudes, values_set)
    magnitudes = {}
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
        bias_states=list(conv.biases))
    # G's columns weighed by the sizes the report lists (--magnitude), as the states are
    _compare(report, sampled, conv, model, motion_list, declared, declared_used,
             np.array([magnitudes[s.name][0] for s in model.sources]))
    if effects:
        responses: dict = {}  # the derived model's, shared by both
        report.effects = propagate_effects(report, sampled, conv, model, motion_list,
                                           responses=responses)
        report.finding_effects = finding_effects(report, sampled, conv, model, motion_list,
                                                 responses=responses)
        report.vertical_effects = vertical_effects(report, sampled, conv, model, motion_list)
    return report


def position_angles(conv: Convention, motion: Motion) -> list[str]:
    """States of ``conv`` that are a position error written as an angle (latitude and
    longitude errors, rad): those with a position readout in metres per radian."""
    readout = np.abs(conv.position(motion.navigation)).max(axis=(0, 2))
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
