"""The matrix check's motions: a static base, a cruise and a manoeuvre, sampled.

Each motion is flown once per model, length and step (:func:`motions`), kept for the next
check in the same process and on disk for the next process
(:mod:`~ins_errors.checker.motion_store`). Platform models fly the trajectories of
:mod:`~ins_errors.numeric.trajectories`; strapdown models (``strapdown_ned`` and model
files that describe themselves, :mod:`~ins_errors.checker.strapdown_description`) fly the
exact rigid-body flights of :mod:`~ins_errors.numeric.strapdown_truth`.

A model that cannot follow a moving motion (a wander-azimuth INS whose wander angle is
fixed in its initial-state map rather than started at a parameter the flight carries,
off a meridian: its flight is refused with a
:class:`~ins_errors.numeric.trajectories.MotionError`) is
checked on the motions it can fly; the others are listed with the one-line refusal
(:func:`flown_motions`). A model that cannot fly the static base is refused.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ins_errors.checker import motion_store
from ins_errors.checker.navigation import adapter_name, navigation_arrays, require_description
from ins_errors.numeric.blas_threads import one_blas_thread

HOURS = 24.0
"""Length of every motion, h."""
STEP = 60.0
"""Sample step of every motion, s: samples at t = 0, 60, …, 86 400 s."""


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


def _strapdown_flights():
    """(label, Flight) of the three flights of a strapdown model."""
    from ins_errors.numeric import strapdown_truth as st

    lat, lon = np.radians(50.0), np.radians(30.0)
    return [
        ("static", st.static(lat, lon, 0.0, heading=np.radians(30.0))),
        ("cruise", st.great_circle(lat, lon, np.radians(60.0), 250.0, 10_000.0)),
        ("manoeuvre", st.Flight(lat, lon, 5000.0, np.radians(60.0), _weave,
                                "weaving flight from φ 50°, λ 30°, course 60°: turn rate "
                                "0.57 cos(2πt/20 min) °/s (bank up to 13°), speed 220 ± 30 m/s "
                                "(period 1 h), height 5 ± 3.8 km (period 80 min)")),
    ]


def parameter_items(parameters: Mapping[str, float] | None, model=None
                    ) -> tuple[tuple[str, float], ...]:
    """``parameters`` as sorted (name, float) pairs (hashable; () for none).

    Each value takes one number in SI units, as
    :meth:`~ins_errors.numeric.model.Model.parameter_vector` does: with ``model`` a value
    that is not one is refused there, in its line (``k_h1 takes a number in SI units
    (1/s), got '0.03/s'; convert text with ins_errors.units.parse_quantity(...)``).
    Without it text is kept, for the model to refuse it so when the motions are flown
    (:func:`flown_motions`); an array or another object is refused here.

    Raises
    ------
    InsErrorsError
        Not a mapping, or a value that is no number (one line naming it).
    """
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric.model import si_number

    if parameters is None:
        return ()
    if not isinstance(parameters, Mapping):
        raise InsErrorsError(f"parameters takes a mapping of names to SI values, got "
                             f"{type(parameters).__name__} {parameters!r:.60}")
    if model is not None:
        model.parameter_vector(**{str(k): v for k, v in parameters.items()})
    items = []
    for name, value in parameters.items():
        if isinstance(value, str):  # the model's line, with its unit, when it is flown
            items.append((str(name), value))
            continue
        items.append((str(name), si_number(value, f"parameter {name}", "SI units")))
    return tuple(sorted(items))


def motions(model, hours: float = HOURS, step: float = STEP, ellipsoid: str | None = None,
            parameters: Mapping[str, float] | None = None) -> list[Motion]:
    """The checker's motions for ``model`` that it can fly, sampled every ``step`` s for
    ``hours`` h (those it cannot: :func:`flown_motions`).

    Static base at φ 50°, λ 30°; a cruise at 250 m/s and 10 km (a great circle leaving at
    track 60° for models with a heading, an eastward cruise along the parallel otherwise);
    a manoeuvre with turns, speed changes, climbs and descents. ``ellipsoid`` (e.g.
    ``"wgs84"``) replaces the model's default Earth shape; ``parameters`` (name -> SI
    value, e.g. damping gains; default: none)
    replace the model's defaults in every sample's parameter vector, where the derived
    model is evaluated.
    """
    return flown_motions(model, hours, step, ellipsoid, parameters)[0]


def flown_motions(model, hours: float = HOURS, step: float = STEP,
                  ellipsoid: str | None = None,
                  parameters: Mapping[str, float] | None = None,
                  require_navigation: bool = True
                  ) -> tuple[list[Motion], list[str]]:
    """The motions of :func:`motions` the model can fly, and those it cannot.

    With ``require_navigation=False`` a model without a navigation description flies
    them too (``ins-errors matrices`` in its own error states): its motions have no
    navigation arrays (``navigation`` is ``{}``), and a moving motion its flight refuses
    for any reason of the motion's (a :class:`~ins_errors.numeric.trajectories.MotionError`
    other than an Earth parameter's: a model without an east velocity follows a static
    base only) is not flown, with that reason.

    Returns
    -------
    flown : list of Motion
        The static base first, then the moving motions the model follows.
    skipped : list of str
        ``"label: reason"`` of each moving motion the model cannot follow (the one-line
        refusal of its flight, a :class:`~ins_errors.numeric.trajectories.MotionError`),
        in the motions' order.

    Raises
    ------
    InsErrorsError
        A model without a navigation description (unless ``require_navigation`` is
        False); the static base's refusal; any other error of a flight (bad Earth
        parameters, a state that is NaN along it, ...).
    """
    if require_navigation:
        require_description(model)
    flown, skipped = _motions(model.key, float(hours), float(step), ellipsoid,
                              parameter_items(parameters, model))
    return list(flown), list(skipped)


@lru_cache(maxsize=8)
@one_blas_thread
def _motions(model_key: str, hours: float, step: float, ellipsoid: str | None,
             parameters: tuple[tuple[str, float], ...] = ()
             ) -> tuple[tuple[Motion, ...], tuple[str, ...]]:
    """Motions of :func:`flown_motions` (flown, skipped), kept for the next check in the
    same process (and on disk for the next process, the skipped ones with their reasons:
    :mod:`~ins_errors.checker.motion_store`, whose key holds the parameter vector)."""
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    p = model.parameter_vector(ellipsoid=ellipsoid, **dict(parameters))
    name = motion_store.key(model, hours, step, ellipsoid, p)
    stored = motion_store.load(name)
    if stored is None:
        stored = _fly(model, hours, step, p)
        motion_store.store(name, *stored)
    flown, skipped = stored
    described = adapter_name(model) is not None
    return (tuple(Motion(label, description, a["times"], a["x"], a["u"], a["p"],
                         navigation_arrays(model, a["x"], a["u"], a["p"]) if described
                         else {})
                  for label, description, a in flown),
            tuple(skipped))


def _cannot_follow(error: Exception, described: bool = True) -> bool:
    """True for the refusal of a flight that a correct model cannot fly (a
    :class:`~ins_errors.numeric.trajectories.PathDependentStateError`: a wander angle off
    a meridian that no parameter starts), not for any other refusal: a model that cannot
    follow a flight for another reason (its Earth is not the flight's, its inputs do not
    solve) is more likely wrong than limited, and its check stops saying why. A model
    without a navigation description (``described`` False) is not checked along the
    motions, only written along them (``ins-errors matrices``): any refusal of the
    motion's (a :class:`~ins_errors.numeric.trajectories.MotionError`: no east velocity
    to cruise with, no heading for a great circle), but not of its Earth parameters,
    leaves that motion out."""
    from ins_errors.numeric.trajectories import (
        EarthParameterError,
        MotionError,
        PathDependentStateError,
    )

    if not described:
        return isinstance(error, MotionError) and not isinstance(error, EarthParameterError)
    return isinstance(error, PathDependentStateError)


def _fly(model, hours: float, step: float, p: np.ndarray
         ) -> tuple[list[tuple[str, str, dict[str, np.ndarray]]], list[str]]:
    """(label, description, {times, x, u, p}) of each motion the model flies, and
    ``"label: reason"`` of each moving motion it cannot follow (:func:`_cannot_follow`).

    Raises
    ------
    InsErrorsError
        The static base's refusal, or any error of a flight other than a refusal to
        follow it.
    """
    from ins_errors.checker import strapdown_description
    from ins_errors.numeric import strapdown_truth as st
    from ins_errors.numeric import trajectories as tr

    if strapdown_description.is_strapdown(model):
        plans = [(label, flight.description,
                  lambda flight=flight: st.trajectory(model, flight, hours * 3600.0, step,
                                                      p=p))
                 for label, flight in _strapdown_flights()]
    else:
        plans = [(label, profile.description,
                  lambda profile=profile: tr.trajectory(model, profile, hours * 3600.0,
                                                        step, p=p))
                 for label, profile in _profiles(model, hours)]
    out, skipped = [], []
    described = adapter_name(model) is not None
    for label, description, fly in plans:
        try:
            run = fly()
            steps = np.arange(run.n_steps + 1)
            x = (np.repeat(run.truth[:, :1], steps.size, axis=1) if run.constant
                 else run.truth)
            arrays = {"times": run.times, "x": x, "u": run.inputs_at(steps),
                      "p": run.parameters}
        except Exception as error:
            if label == "static" or not _cannot_follow(error, described):
                raise
            skipped.append(f"{label}: {error}")
            continue
        # C order, as read back from the store: a check on flown motions and one on
        # stored motions do the same arithmetic
        out.append((label, description, {f: np.ascontiguousarray(a, dtype=float)
                                          for f, a in arrays.items()}))
    return out, skipped
