"""True motion that feeds a model's ideal-work equations consistently.

A motion is given the way a flight is planned: the relative (ground) velocity, either in
the model's track frame (``v_xi`` along the trihedron's ξ axis, ``v_eta`` to its left) or
geographically (``v_N``, ``v_E``), with the height ``h(t)`` and the vertical velocity
``V_zeta = dh/dt``, starting from a latitude, longitude and heading. From it this module
computes, *with the model's own generated functions*, the true state and the true
apparent accelerations the ideal-work equations need:

* the consistent state ``X(x, cmd)`` is the model's ``initial_state`` evaluated at the
  position and heading read from the state (its ``outputs`` named like the initial
  conditions) and the commanded relative velocity; its state velocities are thus
  exactly what the model's own output equations turn back into ``cmd``;
* the apparent accelerations (inputs named ``a_*`` that enter the ideal equations) solve
  ``f(x, u) = dX/dt`` in the least-squares sense, ``dX/dt`` being the exact (automatic)
  time derivative of ``X`` along the flow and the commanded rates: ``a = V̇ + W − g'``.
  They are the specific forces *the model's own* ideal work needs, on its own Earth:
  for a tangent-plane INS (x/y in metres, no latitude output) the commanded v_N, v_E
  are velocities in its plane and ``a_*`` hold its own Coriolis and centrifugal terms
  (the truth is the model's ideal work; its flat Earth's error against the ellipsoid is
  not an error source of its own);
* the vertical apparent acceleration ``a_zeta`` (not used by the ideal horizontal
  channels) is ``dV_zeta/dt − v_E²/(R_E + h) − v_N²/(R_N + h) − 2 U cos φ v_E + γ(φ, h)``
  with the normal gravity γ(φ, h) of the model's ellipsoid
  (:func:`ins_errors.models.earth.normal_gravity`).

The true state is integrated with RK4 at half the run's step (compiled loop) and the
inputs are sampled at the step times and at their midpoints (for RK4 runs). A static
base needs no integration: its inputs are constant.

Conventions (orthodromic model): heading χ from north towards east, η = ζ × ξ (to the
left), so ``v_N = v_ξ cos χ + v_η sin χ`` and ``v_E = v_ξ sin χ − v_η cos χ``.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache, lru_cache
from typing import Protocol, runtime_checkable

import casadi as ca
import numpy as np

from ins_errors.earth_constants import FIRST_COSMIC_VELOCITY
from ins_errors.errors import DomainError, InsErrorsError, ShapeError
from ins_errors.models.earth import (
    STANDARD_GRAVITY,
    earth_shape,
    normal_gravity,
    radii_of_curvature,
)
from ins_errors.numeric.integrators import (
    CompiledLoop,
    DenseCall,
    StepError,
    native_functions,
    step_count,
)
from ins_errors.numeric.model import Model, si_number

COMMANDS = ("v1", "v2", "h", "V_zeta")
"""Order of a command vector: two horizontal relative velocities, height, vertical speed."""

MAX_SAMPLES = 300_000_000
"""Largest number of floats (2.4 GB) sampled for a moving trajectory."""

# Somigliana normal gravity constants: equatorial gravity (m/s²) and the k coefficient.


class MotionError(InsErrorsError):
    """A motion the model cannot follow or a badly specified motion."""


class PathDependentStateError(MotionError):
    """A flight a model cannot fly because one of its states moves along a direction no
    navigation quantity sets and depends on the path flown (a wander angle off a
    meridian), and no parameter of its initial-state map starts that state (a wander
    angle started at a parameter such as ``alpha0`` is carried:
    :class:`~ins_errors.numeric.model_flight.CarriedPath`): the static base, and flights
    that keep that state still, work."""


class EarthParameterError(MotionError):
    """A flight the model's Earth parameters make impossible (an Earth radius of metres,
    an eccentricity of 1 or more): the parameters are wrong, not the motion."""


REFERENCES = ("latitude", "longitude", "heading", "height")
"""The reference values of a motion's start that a description may state (the heading
being the track angle of the model's trihedron)."""


def _description(*parts: tuple[str | None, str]) -> dict:
    """``description`` and ``parts`` of a :class:`Profile` from its pieces."""
    return {"description": "".join(text for _, text in parts), "parts": parts}


# --------------------------------------------------------------------------------------
# Motion profiles (commands as functions of time)
# --------------------------------------------------------------------------------------
@dataclass
class Profile:
    """Commanded relative velocity, height and vertical speed as functions of time.

    Attributes
    ----------
    frame : {"track", "geographic"}
        ``"track"``: (v1, v2) = (v_ξ, v_η) in the model's trihedron; ``"geographic"``:
        (v1, v2) = (v_N, v_E).
    commands : callable
        ``commands(t) -> (values, rates)``, ``t`` shape (T,), each result shape (4, T):
        values (v1, v2, h, V_zeta) in m/s and m, and their time derivatives.
    latitude, longitude, heading : float
        Start point and initial heading, rad.
    description : str
        One line for reports.
    static : bool
        True for a vehicle at rest.
    breaks : sequence of float or numpy.ndarray, optional
        Times (s) where the commands may lose smoothness (leg joins, ramp ends, spline
        knots); between them the commands are smooth (analytic). ``()`` for a motion
        smooth throughout, None when unknown: only a profile with known breaks gets the
        fast interpolated truth (:mod:`ins_errors.numeric.interpolated_truth`).
    parts : tuple of (str or None, str)
        The description in pieces that join to it: each piece's text and the reference
        value it states (one of :data:`REFERENCES`, or None for the other words), so
        :meth:`describe` can leave out the values a model does not depend on. A value's
        piece carries the words that lead to it (" at φ=50°", ", λ=30°"), so that any
        subset reads as a phrase ("static base, h=0 m", or "static base" for a model
        that depends on none of them).
    """

    frame: str
    commands: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    latitude: float
    longitude: float
    heading: float
    description: str
    static: bool = False
    breaks: Sequence[float] | np.ndarray | None = None
    parts: tuple[tuple[str | None, str], ...] = ()

    def describe(self, references: Collection[str] | None = None) -> str:
        """The description with only the reference values in ``references`` (names of
        :data:`REFERENCES`; None: all of them, i.e. :attr:`description`)."""
        if references is None or not self.parts:
            return self.description
        return "".join(text for reference, text in self.parts
                       if reference is None or reference in references)

    def __post_init__(self) -> None:
        if self.frame not in ("track", "geographic"):
            raise MotionError(f"motion frame must be 'track' or 'geographic', got {self.frame!r}")
        for name in ("latitude", "longitude", "heading"):
            value = getattr(self, name)
            if not np.isfinite(value):
                raise MotionError(f"motion {name} must be finite, got {value}")
        check_track_angle(self.heading, "motion heading")
        check_track_angle(self.longitude, "motion longitude", "30° east, -30° west")
        if abs(self.latitude) >= np.pi / 2:
            raise MotionError(f"motion latitude {angle_text(self.latitude)} is at or beyond "
                              "a pole, where north, east and longitude are undefined (and "
                              "the built-in models divide by cos φ)")


def static_profile(latitude: float, longitude: float = 0.0, heading: float = 0.0,
                   h: float = 0.0) -> Profile:
    """A vehicle at rest at (φ, λ, h) with its trihedron at track angle ``heading`` (rad)."""
    latitude, longitude, heading = _angles(latitude=latitude, longitude=longitude,
                                           heading=heading)
    h = motion_number(h, "motion height", "m")
    check_height(h, "motion height")

    return Profile("track", SteadyCommands(0.0, h), latitude, longitude, heading,
                   static=True, breaks=(),
                   **_description((None, "static base"),
                                  ("latitude", f" at φ={latitude_text(latitude)}°"),
                                  ("longitude", f", λ={np.degrees(longitude):.4g}°"),
                                  ("heading", f", χ={np.degrees(heading):.4g}°"),
                                  ("height", f", h={h:g} m")))


def great_circle_profile(latitude: float, longitude: float, track: float, speed: float,
                         h: float = 0.0) -> Profile:
    """Constant ground speed along the trihedron's ξ axis (a great circle), constant height.

    Parameters
    ----------
    latitude, longitude, track : float
        Start point and initial track angle (from north towards east), rad.
    speed : float
        Ground speed, m/s.
    h : float
        Height, m.
    """
    latitude, longitude, track = _angles(latitude=latitude, longitude=longitude, track=track)
    speed = motion_number(speed, "great-circle speed", "m/s")
    h = motion_number(h, "motion height", "m")
    _check_speed(speed, "great-circle speed")
    check_height(h, "motion height")

    return Profile("track", SteadyCommands(speed, h), latitude, longitude, track, breaks=(),
                   **_description((None, "great circle"),
                                  ("latitude", f" from φ={latitude_text(latitude)}°"),
                                  ("longitude", f", λ={np.degrees(longitude):.4g}°"),
                                  ("heading", f", track {np.degrees(track):.4g}°"),
                                  (None, f", {speed:g} m/s"), ("height", f", h={h:g} m")))


HEIGHT_LIMIT = 100_000.0
"""m: the largest |height| of a motion (±100 km, the edge of the atmosphere: aircraft,
balloons, sounding rockets), for every model. Gravity enters the built-in models as
normal gravity continued from
the ellipsoid with the second-order series γ₀(1 − 2h/a + 3h²/a²)
(:func:`~ins_errors.models.earth.normal_gravity`: the motion generators' ``a_zeta``,
strapdown_ned's γ). Against the inverse-square law γ₀ a²/(a + h)² it is off by
4(h/a)³ to leading order: 1.6e-5 of γ (0.15 mm/s², about 15 µg) at 100 km, where its
vertical gradient, the vertical channel's instability, is off by 6(h/a)² = 0.15 %; at
1000 km the series is 1.7 % off and at 10 000 km it gives 51 m/s² for 1.5 m/s². Beyond
the limit a height is refused (:class:`HeightError`) before anything runs, also for a
model file with gravity of its own (a constant g); a model file of a small planet still
has its run-time domain check of R + h."""


class HeightError(MotionError, DomainError):
    """A height beyond :data:`HEIGHT_LIMIT`, the heights a motion may reach (the edge of
    the atmosphere; normal gravity, which the built-in models use, holds within it)."""


def motion_number(value: object, what: str, unit: str) -> float:
    """One real number in SI ``unit``, or a :class:`MotionError` line naming ``what``."""
    return si_number(value, what, unit, MotionError, MotionError)


def _angles(**angles: object) -> list[float]:
    values = [motion_number(value, f"motion {name}", "rad") for name, value in angles.items()]
    for name, value in zip(angles, values, strict=True):
        if name in ("heading", "track"):
            check_track_angle(value, f"motion {name}")
        elif name == "longitude":
            check_track_angle(value, f"motion {name}", "30° east, -30° west")
    return values


MAX_TRACK_ANGLE = 2.0 * np.pi
"""rad: the largest |heading|, |track angle| or |longitude| a motion may start with (one
turn either way). Any direction or meridian is within it; a larger value is a mistake (a
unit or an exponent), and its sine and cosine lose every digit (cos 1e300 is rounding
noise)."""


def angle_text(value: float) -> str:
    """An angle (rad) in degrees for a message, with the radians it was given as when
    they look like degrees passed where radians belong: a whole number of radians past
    one turn and up to 1000 (``"2864.79° (50 rad)"``; an angle the command line
    converted from degrees, ``400deg`` = 6.98 rad, is said in degrees alone)."""
    shown = f"{np.degrees(value):g}°"
    looks_like_degrees = 2 * np.pi < abs(value) <= 1000 and value == round(value)
    return f"{shown} ({value:g} rad)" if looks_like_degrees else shown


def latitude_text(latitude: float) -> str:
    """A latitude (rad) in degrees for a description, without the ``°``: four significant
    digits, more where four would move it towards a pole by more than 1 % of its distance
    from it (``89.9999``, not ``90``: near a pole the error equations go with sec φ)."""
    degrees = float(np.degrees(latitude))
    distance = 90.0 - abs(degrees)
    for digits in range(4, 16):
        text = f"{degrees:.{digits}g}"
        if abs((90.0 - abs(float(text))) - distance) <= 0.01 * distance:
            return text
    return f"{degrees:.16g}"


def check_track_angle(value: float, what: str, example: str = "90° for due east") -> None:
    """Refuse a heading, track angle or longitude (rad) outside [−360°, 360°], naming
    ``what`` (``example``: a sensible value, for the message).

    Raises
    ------
    MotionError
        One line giving the value in degrees and the accepted range.
    """
    if not np.isfinite(value):
        raise MotionError(f"{what} must be finite, got {value}")
    if abs(value) > MAX_TRACK_ANGLE:
        raise MotionError(f"{what} {angle_text(value)} is outside [-360°, 360°]: give "
                          f"it within one turn (e.g. {example})")


def check_height(h: float, what: str) -> None:
    """Refuse a height (m) that is not finite or is beyond :data:`HEIGHT_LIMIT`.

    Parameters
    ----------
    h : float
        Height above the ellipsoid, m.
    what : str
        Where it comes from, for the message (``"motion height"``, ``"spec motion.height"``).

    Raises
    ------
    MotionError
        For a height that is NaN or infinite.
    HeightError
        One line naming ``what``, the height and the limit.
    """
    if not np.isfinite(h):
        raise MotionError(f"{what} must be finite, got {h}")
    if abs(h) > HEIGHT_LIMIT:
        if h <= -6_378_137.0:
            why = "below the Earth's centre"
        else:
            there, limit = _series_errors(h), _series_errors(np.copysign(HEIGHT_LIMIT, h))
            why = (f"there the height series of normal gravity, which the built-in models "
                   f"use, is {there[0]} % off the inverse-square law "
                   f"and its vertical gradient, which drives the vertical channel, "
                   f"{there[1]} %")
            if there != limit:
                why += f" ({limit[0]} % and {limit[1]} % at the limit)"
        raise HeightError(f"{what} {h / 1000:g} km is beyond ±{HEIGHT_LIMIT / 1000:g} km, "
                          f"the heights ins-errors accepts, whatever the model ({why})")


def _series_errors(h: float) -> tuple[str, str]:
    """How far (in %, two digits) normal gravity's height series γ₀(1 − 2h/a + 3h²/a²)
    and its vertical gradient are off the inverse-square law at height ``h`` (m; a:
    WGS-84's semi-major axis): the text of :func:`check_height`'s refusal."""
    x = h / 6_378_137.0
    return (f"{100 * abs((1 - 2 * x + 3 * x * x) * (1 + x) ** 2 - 1):.2g}",
            f"{100 * 6 * x * x:.2g}")


MAX_SPEED = FIRST_COSMIC_VELOCITY
"""m/s: the largest ground speed of a motion, the first cosmic velocity √(g a) ≈ 7.91 km/s
(standard gravity, WGS-84 a; :data:`~ins_errors.earth_constants.FIRST_COSMIC_VELOCITY`).
A vehicle faster than that along the Earth's surface needs more centripetal acceleration
v²/R than gravity gives: it would be in orbit, and nothing holds a height at such a speed
(the motions do). A faster speed is a unit slip (km/h or km/s for m/s) or a typing
error."""

MAX_MANOEUVRE_ACCELERATION = 100.0 * STANDARD_GRAVITY
"""m/s²: the largest lateral (v·ψ̇), along-track (v̇) or vertical (ḧ) acceleration of a
manoeuvre leg, 100 g. Fighter aircraft sustain about 9 g and guided missiles turn at 30 to
60 g (whose INS errors under g-sensitive and scale-factor errors are a research subject of
their own); no navigated vehicle turns, speeds up or pulls up harder for the length of a
leg, so a leg asking for more is a mistake (a turn of 36000° in 10 s at 250 m/s asks for
3000 g at its peak)."""

MAX_TURN_RATE = np.radians(1000.0)
"""rad/s: the largest course rate ψ̇ of a manoeuvre leg, 1000°/s, whatever its speed
(also at rest, where a turn has no lateral acceleration). It is beyond the measuring range
of navigation gyros (about 400–1000°/s) and beyond any aircraft's roll rate."""


def _check_speed(speed: float, what: str) -> None:
    """Refuse a ground speed that is not a finite number in [0, :data:`MAX_SPEED`] m/s
    (one line, naming it)."""
    if not np.isfinite(speed):
        raise MotionError(f"{what} must be finite, got {speed}")
    if speed < 0:
        raise MotionError(f"{what} must be >= 0 m/s, got {speed:g} m/s (to fly the other "
                          "way, turn the track by 180°)")
    if speed > MAX_SPEED:
        raise MotionError(speed_beyond(speed, what))


def speed_beyond(speed: float, what: str) -> str:
    """The one-line reason a ground speed (m/s) above :data:`MAX_SPEED` is refused."""
    centripetal = speed ** 2 / 6_378_137.0
    return (f"{what} {speed:g} m/s is beyond {MAX_SPEED:.0f} m/s, the first cosmic "
            f"velocity √(g a): faster, the centripetal acceleration v²/R ({centripetal:.3g} "
            f"m/s²) exceeds gravity (9.81 m/s²) and no vehicle holds a height; a unit slip "
            f"(km/h for m/s)?")


_RAMP = np.linspace(0.0, 1.0, 2001)
"""Points of a leg (as fractions of its duration) its peak accelerations are taken at."""


def _check_leg_motion(number: int, leg: Leg, v_start: float, h_start: float) -> None:
    """Refuse a manoeuvre leg whose peak acceleration or course rate no vehicle reaches
    (:data:`MAX_MANOEUVRE_ACCELERATION`, :data:`MAX_TURN_RATE`), naming the figure.

    The leg blends speed, course and height along :func:`smoothstep` (peak rate 15/8 of
    the mean, peak second derivative 10/√3 of the change over T²)."""
    s, ds, dds = smoothstep(_RAMP)
    T = leg.duration
    v = v_start + (leg.speed - v_start) * s
    rate = leg.turn * ds / T
    turn_rate = float(np.max(np.abs(rate)))
    said = f"manoeuvre leg {number} ({T:g} s"
    if leg.turn:
        said += (f", turn {np.degrees(leg.turn):g}°: {np.degrees(abs(leg.turn) / T):.4g}°/s "
                 f"on average, {np.degrees(turn_rate):.4g}°/s at its peak")
    for name, values in (("lateral (v·ψ̇)", v * rate),
                         ("along-track (v̇)", (leg.speed - v_start) * ds / T),
                         ("vertical (ḧ)", (leg.height - h_start) * dds / T ** 2)):
        peak = float(np.max(np.abs(values)))
        if not peak <= MAX_MANOEUVRE_ACCELERATION:
            raise MotionError(
                f"{said}): its {name} acceleration reaches {peak:.4g} m/s² = "
                f"{peak / STANDARD_GRAVITY:.4g} g, beyond the "
                f"{MAX_MANOEUVRE_ACCELERATION / STANDARD_GRAVITY:g} g any navigated "
                f"vehicle pulls for a leg: "
                f"give the leg more time or a smaller change")
    if not turn_rate <= MAX_TURN_RATE:
        raise MotionError(f"{said}): its course rate is beyond "
                          f"{np.degrees(MAX_TURN_RATE):g}°/s, beyond any vehicle's and any "
                          f"navigation gyro's range: give the leg more time or a smaller turn")


@dataclass(frozen=True)
class Leg:
    """One leg of a manoeuvre: over ``duration`` s, blend smoothly to the end values.

    Attributes
    ----------
    duration : float
        s.
    speed : float
        Ground speed at the end of the leg, m/s.
    turn : float
        Change of course relative to the trihedron's ξ axis during the leg, rad
        (positive to the left).
    height : float
        Height at the end of the leg, m.
    """

    duration: float
    speed: float
    turn: float = 0.0
    height: float = 0.0


def smoothstep(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """C² ramp 0→1 on [0, 1] with its first and second derivatives."""
    t = np.clip(theta, 0.0, 1.0)
    inside = (theta > 0) & (theta < 1)
    s = t**3 * (10 - 15 * t + 6 * t**2)
    ds = np.where(inside, 30 * t**2 * (1 - t) ** 2, 0.0)
    dds = np.where(inside, 60 * t * (1 - t) * (1 - 2 * t), 0.0)
    return s, ds, dds


def manoeuvre_profile(latitude: float, longitude: float, track: float, speed: float,
                      legs: Sequence[Leg], h: float = 0.0, name: str | None = None,
                      repeat: bool = False) -> Profile:
    """A flight of smooth legs: turns, speed changes, climbs and descents.

    Within each leg the speed, the course ψ (relative to the trihedron's ξ axis) and the
    height move from their start to their end values along a C² ramp, so the commanded
    velocities, V_zeta and their rates are continuous. After the last leg the motion
    continues unchanged (with zero vertical speed), or, with ``repeat``, the legs are
    flown again and again: the commands at ``t`` beyond the legs' total length ``T``
    are those at ``t mod T`` (the same numbers as before up to ``T``), and the
    profile's :attr:`~Profile.breaks` list one round, which :func:`covering` extends
    to a run's length (:func:`trajectory` does).

    Parameters
    ----------
    latitude, longitude, track : float
        Start point and initial track angle, rad.
    speed : float
        Initial ground speed, m/s.
    legs : sequence of Leg
        The legs, in order.
    h : float
        Initial height, m.
    name : str, optional
        What the flight is, for its description (default: "manoeuvring flight of N
        legs").
    repeat : bool
        Fly the legs again and again; they must end at the start's speed and height
        and with a whole number of full turns.

    Raises
    ------
    MotionError
        For a leg no vehicle flies, no legs, or legs to repeat that do not end where
        they start.
    """
    latitude, longitude, track = _angles(latitude=latitude, longitude=longitude, track=track)
    speed = motion_number(speed, "manoeuvre speed", "m/s")
    h = motion_number(h, "motion height", "m")
    _check_speed(speed, "manoeuvre speed")
    check_height(h, "motion height")
    if len(legs) == 0:
        raise MotionError("a manoeuvre needs at least 1 leg, got none (an empty list of "
                          "legs)")
    starts, t0 = [], 0.0
    v0, psi0, h0 = float(speed), 0.0, float(h)
    for leg in legs:
        if not leg.duration > 0:
            raise MotionError(f"manoeuvre leg duration must be positive, got {leg.duration}")
        _check_speed(leg.speed, "manoeuvre leg speed")
        check_height(leg.height, "manoeuvre leg height")
        motion_number(leg.turn, "manoeuvre leg turn", "rad")
        _check_leg_motion(len(starts) + 1, leg, v0, h0)
        starts.append((t0, leg.duration, v0, psi0, h0, leg))
        t0, v0, psi0, h0 = t0 + leg.duration, leg.speed, psi0 + leg.turn, leg.height

    table = np.array([(start, length, vs, leg.speed - vs, ps, leg.turn, hs, leg.height - hs)
                      for start, length, vs, ps, hs, leg in starts]).reshape(-1, 8).T
    period = 0.0
    if repeat:
        turns = psi0 / (2 * np.pi)
        if (not np.isclose(v0, speed, rtol=1e-12, atol=0.0) or not np.isclose(h0, h, rtol=0.0,
                atol=1e-9) or abs(turns - round(turns)) > 1e-12):
            raise MotionError("legs flown again and again must end at the start's speed "
                              f"({float(speed):g} m/s) and height ({float(h):g} m) and with "
                              f"whole turns; they end at {v0:g} m/s, {h0:g} m, after "
                              f"{np.degrees(psi0):g}° of turn")
        period = float(t0)

    return Profile("track", LegCommands(table, float(speed), float(h), period), latitude,
                   longitude,
                   track, breaks=tuple(float(b) for b in np.cumsum([leg.duration for leg in legs])),
                   **_description((None, name or f"manoeuvring flight of {len(legs)} legs"),
                                  ("latitude", f" from φ={latitude_text(latitude)}°"),
                                  ("longitude", f", λ={np.degrees(longitude):.4g}°"),
                                  ("heading", f", track {np.degrees(track):.4g}°"),
                                  (None, f", {float(speed):g} m/s"),
                                  ("height", f", h={float(h):g} m")))


def covering(profile: Profile, duration: float) -> Profile:
    """``profile`` with its breaks listed through a run of ``duration`` s.

    A manoeuvre flown again and again (:func:`manoeuvre_profile` with ``repeat``) lists
    the breaks of one round; a run longer than the round gets a copy whose breaks
    repeat with the round through the end of the run (and the round after it). Any
    other profile, and a run no longer than one round, is returned as it is.

    Parameters
    ----------
    profile : Profile
        The motion.
    duration : float
        Length of the run, s.

    Returns
    -------
    Profile
    """
    period = getattr(profile.commands, "period", 0.0)
    if not period > 0 or profile.breaks is None or not duration > period:
        return profile
    from dataclasses import replace

    one = np.asarray(profile.breaks, dtype=float)
    rounds = int(np.ceil(duration / period)) + 1
    return replace(profile, breaks=tuple(float(b) for b in
                                         (one[None, :] + period * np.arange(rounds)[:, None]
                                          ).ravel()))


def sampled_profile(t: np.ndarray, v1: np.ndarray, v2: np.ndarray, latitude: float,
                    longitude: float, heading: float, h: np.ndarray | float = 0.0,
                    frame: str = "geographic", source: str | None = None) -> Profile:
    """A user motion given as samples, interpolated with cubic splines.

    Parameters
    ----------
    t : numpy.ndarray, shape (T,)
        Increasing sample times, s (the run must stay within them).
    v1, v2 : numpy.ndarray, shape (T,)
        Relative velocity samples, m/s: (v_N, v_E) for ``frame="geographic"``, (v_ξ, v_η)
        for ``frame="track"``.
    latitude, longitude, heading : float
        Start point and the trihedron's initial track angle, rad.
    h : numpy.ndarray or float
        Height samples (or a constant), m; V_zeta is its spline derivative.
    frame : {"geographic", "track"}
        Frame of (v1, v2).
    source : str, optional
        Where the samples come from (a motion file's path as given), for the description.
    """
    from scipy.interpolate import CubicSpline

    t = np.asarray(t, dtype=float)
    arrays = [np.asarray(v1, dtype=float), np.asarray(v2, dtype=float),
              np.broadcast_to(np.asarray(h, dtype=float), t.shape)]
    if t.ndim != 1 or t.size < 4:
        raise ShapeError(f"sampled motion needs at least 4 sample times, got shape {t.shape}")
    if any(a.shape != t.shape for a in arrays):
        raise ShapeError(f"sampled motion: velocity and height samples must have the shape "
                         f"of the times {t.shape}")
    if not np.all(np.diff(t) > 0):
        raise MotionError("sampled motion: times must be strictly increasing")
    names = ("t", "v_N", "v_E", "h") if frame == "geographic" else ("t", "v_xi", "v_eta", "h")
    for name, a in zip(names, (t, *arrays), strict=True):
        if not np.all(np.isfinite(a)):
            row = int(np.argmin(np.isfinite(a)))
            raise DomainError(f"sampled motion: {name} is NaN or infinite in sample {row + 1}"
                              f" of {a.size}")
    for h_end in (np.min(arrays[2]), np.max(arrays[2])):
        check_height(float(h_end), "sampled motion height")
    speeds = np.hypot(arrays[0], arrays[1])
    if speeds.max() > MAX_SPEED:
        row = int(np.argmax(speeds > MAX_SPEED))
        raise MotionError(speed_beyond(float(speeds[row]), f"sampled motion: sample "
                                       f"{row + 1} of {t.size} (t = {t[row]:g} s): ground "
                                       "speed"))
    splines = tuple(CubicSpline(t, a) for a in arrays)
    # the start values a sampled motion depends on besides its samples, as the planned
    # motions state theirs (a constant height is not in the samples)
    origin = f"motion file {source}" if source else "sampled motion"
    constant_height = np.ndim(h) == 0
    return Profile(frame, SplineCommands(splines, float(t[0]), float(t[-1])), latitude,
                   longitude, heading, breaks=t.copy(),
                   **_description((None, f"{origin} ({t.size} samples, {frame} frame)"),
                                  ("latitude", f" from φ={latitude_text(latitude)}°"),
                                  ("longitude", f", λ={np.degrees(longitude):.4g}°"),
                                  ("heading", f", track {np.degrees(heading):.4g}°"),
                                  *((("height", f", h={float(h):g} m"),)
                                    if constant_height else ())))


# --------------------------------------------------------------------------------------
# Commands of the profiles: module-level callables (a closure cannot be pickled, and a
# trajectory carries its profile to the worker processes of a Monte Carlo run)
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SteadyCommands:
    """Constant speed along the trihedron's ξ axis at a constant height (0 m/s: at rest).

    Attributes
    ----------
    speed : float
        m/s.
    height : float
        m.
    """

    speed: float
    height: float

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        values = np.zeros((4, t.size))
        values[0], values[2] = self.speed, self.height
        return values, np.zeros((4, t.size))


@dataclass(frozen=True, eq=False)
class LegCommands:
    """The commands of :func:`manoeuvre_profile`.

    Attributes
    ----------
    table : numpy.ndarray, shape (8, legs)
        Per leg: start (s), length (s), start speed and its change (m/s), start course
        and its change (rad), start height and its change (m).
    speed, height : float
        Speed (m/s) and height (m) before the first leg.
    period : float
        With a positive period (s; the legs' total length) the legs are flown again
        and again: the commands at ``t > period`` are those at ``t mod period`` (exact
        in floating point). 0: after the last leg the motion continues unchanged.
    """

    table: np.ndarray
    speed: float
    height: float
    period: float = 0.0

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self.period > 0 and t.size and t.max() > self.period:  # legs flown again
            t = np.where(t > self.period, np.mod(t, self.period), t)
        # only the last leg begun by t shapes the motion at t: evaluate that leg alone
        leg = np.searchsorted(self.table[0], t, side="right") - 1
        before = leg < 0
        rows = self.table[:, np.maximum(leg, 0)]  # one gather of every leg parameter
        if before.any():  # before the first leg: the initial values, unchanged
            rows[:, before] = 0.0
            rows[1, before], rows[2, before], rows[6, before] = 1.0, self.speed, self.height
        start, length, vs, dv_leg, ps, turn, hs, dh_leg = rows
        s, ds, dds = smoothstep((t - start) / length)
        v = vs + dv_leg * s
        dv = dv_leg * ds / length
        psi = ps + turn * s
        dpsi = turn * ds / length
        hh = hs + dh_leg * s
        dh = dh_leg * ds / length
        ddh = dh_leg * dds / length**2
        cos, sin = np.cos(psi), np.sin(psi)
        values = np.vstack([v * cos, v * sin, hh, dh])
        rates = np.vstack([dv * cos - v * sin * dpsi, dv * sin + v * cos * dpsi, dh, ddh])
        return values, rates


@dataclass(frozen=True, eq=False)
class SplineCommands:
    """The commands of :func:`sampled_profile`: cubic splines of v1, v2 and h.

    Attributes
    ----------
    splines : tuple of scipy.interpolate.CubicSpline
        v1, v2 (m/s) and h (m) against time (s).
    start, end : float
        First and last sample time, s.
    """

    splines: tuple
    start: float
    end: float

    def __call__(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if times.size and (times.min() < self.start - 1e-9 or times.max() > self.end + 1e-9):
            raise MotionError(f"the run ({times.min():g}–{times.max():g} s) leaves the "
                              f"sampled motion ({self.start:g}–{self.end:g} s)")
        v1, v2, h = self.splines
        values = np.vstack([v1(times), v2(times), h(times), h(times, 1)])
        rates = np.vstack([v1(times, 1), v2(times, 1), h(times, 1), h(times, 2)])
        return values, rates


# --------------------------------------------------------------------------------------
# Model-side machinery (CasADi, generic over models)
# --------------------------------------------------------------------------------------
@dataclass
class _Kinematics:
    """CasADi functions that turn commands into consistent states and inputs."""

    consistent_state: ca.Function  # (x, cmd, p) -> X
    inputs: ca.Function  # (x, cmd, rates, p) -> u
    truth_rhs: ca.Function  # (x, [cmd; rates], w (empty), p) -> dx/dt
    initial_state: ca.Function  # (c, cmd, p) -> x0
    track: bool = field(default=True)


@cache
def _kinematics(model_name: str, frame: str) -> _Kinematics:
    from ins_errors.numeric.model import load_model

    model = load_model(model_name)
    fn = model.casadi.function
    ideal, outputs, initial = fn("ideal_rhs"), fn("outputs"), fn("initial_state")
    n, npar = len(model.states), len(model.parameters)
    input_names = [i.name for i in model.inputs]
    output_names = [o.name for o in model.outputs]
    ic_names = [c.name for c in model.initial_conditions]
    i_vn = _velocity_index(model, NORTH)
    if i_vn is None:
        raise MotionError(f"model {model.name!r} has no initial condition v_N (or v_N0): "
                          "the trajectory generators need the north velocity")
    # a north-channel model (no v_E) follows a static base only: checked in trajectory()
    i_ve = _velocity_index(model, EAST)
    # the latitude output serves only the vertical apparent acceleration a_zeta (normal
    # gravity, transport and Coriolis terms at the latitude); the horizontal a_* come
    # from the model's own ideal work, whatever its Earth (a flat tangent plane too)
    i_lat_out = None
    if "a_zeta" in input_names:
        if "latitude" not in output_names:
            raise MotionError(f"model {model.name!r} has an input a_zeta but no output "
                              "latitude: the vertical apparent acceleration is normal "
                              "gravity at the latitude, so a motion needs the latitude "
                              "among the outputs")
        i_lat_out = output_names.index("latitude")
    if frame == "track" and "heading" not in output_names:
        raise MotionError(f"model {model.name!r} cannot fly a great circle, a manoeuvre "
                          "or another track-frame motion (they are steered by the heading, "
                          "which is not among its outputs); use a static base or a motion "
                          "file of north and east velocities")
    i_heading = output_names.index("heading") if frame == "track" else None
    par = {name: k for k, name in enumerate(i.name for i in model.parameters)}

    x = ca.SX.sym("x", n)
    cmd = ca.SX.sym("cmd", 4)
    rates = ca.SX.sym("rates", 4)
    p = ca.SX.sym("p", npar)

    def input_vector(h, V_zeta, accelerations=None, a_zeta=0.0):
        entries = []
        for name in input_names:
            if name == "h":
                entries.append(h)
            elif name == "V_zeta":
                entries.append(V_zeta)
            elif name == "a_zeta":
                entries.append(a_zeta)
            elif name.startswith("a_"):
                entries.append(accelerations[name] if accelerations else ca.SX(0))
            else:
                raise MotionError(f"the trajectory generators do not know how to set input "
                                  f"{name!r} of model {model.name!r}")
        return ca.vertcat(*entries)

    def geographic(y, v1, v2):
        if frame == "geographic":
            return v1, v2
        chi = y[i_heading]
        return (v1 * ca.cos(chi) + v2 * ca.sin(chi), v1 * ca.sin(chi) - v2 * ca.cos(chi))

    # consistent state X(x, cmd): initial_state at the state's own position and heading
    u_kin = input_vector(cmd[2], cmd[3])
    y = outputs(x, u_kin, p)
    v_n, v_e = geographic(y, cmd[0], cmd[1])
    c_entries = []
    for k, name in enumerate(ic_names):
        if k == i_vn:
            c_entries.append(v_n)
        elif k == i_ve:
            c_entries.append(v_e)
        elif name in output_names:
            c_entries.append(y[output_names.index(name)])
        else:
            raise MotionError(f"initial condition {name!r} of model {model.name!r} is "
                              "neither a velocity nor an output: cannot follow a motion")
    X = initial(ca.vertcat(*c_entries), u_kin, p)
    consistent = ca.Function("consistent_state", [x, cmd, p], [X])

    # accelerations: f(x, u(a)) = dX/dt along the flow
    accel_names = [nm for nm in input_names if nm.startswith("a_") and nm != "a_zeta"]
    a_sym = ca.SX.sym("a", len(accel_names))
    u_a = input_vector(cmd[2], cmd[3], dict(zip(accel_names, ca.vertsplit(a_sym), strict=True)))
    f_a = ideal(x, u_a, p)
    B = ca.jacobian(f_a, a_sym)
    f0 = ca.substitute(f_a, a_sym, ca.DM.zeros(len(accel_names)))
    xdot0 = f0  # position/heading rates do not depend on the accelerations
    Xdot = ca.jtimes(X, x, xdot0) + ca.jtimes(X, cmd, rates)
    acc = ca.solve(B.T @ B, B.T @ (Xdot - f0))
    # vertical apparent acceleration (normal gravity + transport/Coriolis), for a model
    # with that input; a horizontal-only model needs no Earth shape or rate here
    a_up = ca.SX(0)
    if "a_zeta" in input_names:
        phi = y[i_lat_out]
        a_ax, e2, U = earth_shape(list(par), ca.vertsplit(p), f"model {model.name!r}")
        R_N, R_E = radii_of_curvature(phi, a_ax, e2, xp=ca)
        gamma = normal_gravity(phi, cmd[2], a_ax, e2, xp=ca)
        a_up = (rates[3] - v_e**2 / (R_E + cmd[2]) - v_n**2 / (R_N + cmd[2])
                - 2 * U * ca.cos(phi) * v_e + gamma)
    u_full = input_vector(cmd[2], cmd[3], dict(zip(accel_names, ca.vertsplit(acc),
                                                   strict=True)), a_up)
    inputs = ca.Function("motion_inputs", [x, cmd, rates, p], [u_full])
    stream = ca.SX.sym("stream", 8)
    none = ca.SX.sym("none", 0)
    truth_rhs = ca.Function("truth_rhs", [x, stream, none, p],
                            [ideal(x, inputs(x, stream[:4], stream[4:], p), p)])
    # initial state from the profile's start
    c0 = ca.SX.sym("c0", 3)  # latitude, longitude, heading
    c_entries = []
    for k, name in enumerate(ic_names):
        if k in (i_vn, i_ve):
            c_entries.append(None)
        elif name in ("latitude", "longitude", "heading"):
            c_entries.append(c0[("latitude", "longitude", "heading").index(name)])
        else:
            raise MotionError(f"initial condition {name!r} cannot be set from a motion")
    chi0 = c0[2]
    if frame == "track":
        vn0 = cmd[0] * ca.cos(chi0) + cmd[1] * ca.sin(chi0)
        ve0 = cmd[0] * ca.sin(chi0) - cmd[1] * ca.cos(chi0)
    else:
        vn0, ve0 = cmd[0], cmd[1]
    c_entries[i_vn] = vn0
    if i_ve is not None:
        c_entries[i_ve] = ve0
    initial_fn = ca.Function("motion_initial_state", [c0, cmd, p],
                             [initial(ca.vertcat(*c_entries), u_kin, p), ca.vertcat(*c_entries)])
    return _Kinematics(consistent, inputs, truth_rhs, initial_fn, frame == "track")


@cache
def references_used(model_key: str, frame: str) -> frozenset[str]:
    """The reference values of a motion's start (:data:`REFERENCES`) that a run of the
    model along a motion in ``frame`` depends on.

    Decided from the generated functions themselves, not from names: a reference is used
    when it reaches, in the CasADi expressions, the true initial state, the true inputs
    (e.g. the height through normal gravity in ``a_zeta``, for a model with no height
    input), the real work's initial state or the initial-error matrix. These are the only
    ways it enters a run: the truth evolves from that state under the commands (the
    height among them) through the same input function, and the direct and linear runs
    see it only through the truth and those initial values. The test is structural, so
    an expression that cancels symbolically still counts as using the reference.
    (A model without a latitude, a tangent-plane INS whose origin latitude is a
    parameter, has no ``"latitude"`` in it.)

    Parameters
    ----------
    model_key : str
        :attr:`Model.key` of the model.
    frame : {"track", "geographic"}
        Frame of the motion's commands as :func:`trajectory` uses it.

    Returns
    -------
    frozenset of str
    """
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    kin = _kinematics(model_key, frame)
    start = ca.SX.sym("start", 3)  # latitude, longitude, heading
    cmd, rates = ca.SX.sym("cmd", 4), ca.SX.sym("rates", 4)  # cmd[2]: the height
    p = ca.SX.sym("p", len(model.parameters))
    w = ca.SX.sym("w", len(model.sources))
    x0, c0 = kin.initial_state(start, cmd, p)
    u0 = kin.inputs(x0, cmd, rates, p)
    function = model.casadi.function
    reached = ca.vertcat(x0, u0, function("initial_real_state")(c0, u0, w, p),
                         ca.vec(function("initial_error_matrix")(c0, u0, p)))
    symbols = dict(zip(REFERENCES, (start[0], start[1], start[2], cmd[2]), strict=True))
    return frozenset(name for name, symbol in symbols.items()
                     if ca.depends_on(reached, symbol))


REFERENCE_WORDS = {"latitude": ("rad", ("latitude",)), "longitude": ("rad", ("longitude",)),
                   "heading": ("rad", ("heading",)), "height": ("m", ("height", "altitude"))}
"""Per reference value of a motion's start: the SI unit and the words of a model
parameter's description that make it the model's own setting of that value (a
tangent-plane INS's "latitude of the tangent-plane origin" phi0)."""


def reference_parameter(model: Model, reference: str):
    """The model parameter that sets ``reference`` (one of :data:`REFERENCES`) in a model
    whose runs do not take it from the motion, or None.

    A parameter counts when its unit is the reference's (``rad`` for the latitude,
    longitude and heading, a length for the height) and its name or description names
    the reference (:data:`REFERENCE_WORDS`).

    Returns
    -------
    ins_errors.numeric.model.Info or None
    """
    from ins_errors.units import same_dimension

    unit, words = REFERENCE_WORDS[reference]
    for parameter in model.parameters:
        text = f"{parameter.name} {parameter.description}".lower()
        # an angle's unit as a model states it ("rad": pint holds radians dimensionless,
        # so a dimension test would take any pure number)
        fits = (parameter.unit == unit if unit == "rad"
                else same_dimension(parameter.unit, unit))
        if fits and any(word in text for word in words):
            return parameter
    return None


def refuse_unused_references(model: Model, motion: Trajectory,
                             given: Mapping[str, tuple[str, str]],
                             setting: str = "-p {name}={value}") -> None:
    """Refuse reference values given for a run that does not depend on them.

    A model without a latitude (a tangent-plane INS whose origin latitude is a parameter)
    runs the same whatever ``--latitude`` says; a value given there was meant for
    something the run does not do, so it is refused rather than reported as used.

    Parameters
    ----------
    model : Model
    motion : Trajectory
        The run's true motion, from :func:`trajectory` (its :attr:`Trajectory.references`;
        None, unknown, refuses nothing).
    given : mapping of str to (str, str)
        Reference name (:data:`REFERENCES`) -> (the option or key it was given as, e.g.
        ``"--latitude"``, and the text given, e.g. ``"10deg"``): only the values a user
        gave explicitly, not defaults.
    setting : str
        How the way out sets a parameter, with ``{name}`` and ``{value}``: an option by
        default, ``'[parameters] {name} = "{value}"'`` for a scenario file.

    Raises
    ------
    MotionError
        One line naming the option, that the model has no such value, and the model's
        parameter that sets it (``-p phi0=10deg``) or that the option is to be left out.
    """
    used = motion.references
    if used is None:
        return
    for reference, (option, text) in given.items():
        if reference in used:
            continue
        parameter = reference_parameter(model, reference)
        value = text.replace(" ", "") if setting.startswith("-p") else text
        way = (f"its parameter {parameter.name} ({parameter.description}) sets it: "
               + setting.format(name=parameter.name, value=value) if parameter is not None
               else f"leave {option} out")
        raise MotionError(f"{option}: model {model.name!r} has no {reference} (its runs do "
                          f"not depend on one), so {option} {text} would be ignored; {way}")


# --------------------------------------------------------------------------------------
# Trajectory: stored or streamed in chunks
# --------------------------------------------------------------------------------------
@dataclass
class TruthChunk:
    """True motion over the steps ``start .. start + m`` of a run's grid.

    Attributes
    ----------
    start : int
        Index of the first step.
    truth : numpy.ndarray, shape (n, m + 1)
        True states at the step times ``(start + j) τ``, ``j = 0..m``.
    inputs : numpy.ndarray, shape (nu, m + 1)
        Inputs at the same times.
    midpoints : numpy.ndarray, shape (nu, m)
        Inputs at ``(start + j + 1/2) τ``, ``j = 0..m-1`` (for RK4).
    """

    start: int
    truth: np.ndarray
    inputs: np.ndarray
    midpoints: np.ndarray

    @property
    def size(self) -> int:
        """Number of steps m."""
        return self.midpoints.shape[1]


@runtime_checkable
class MotionSource(Protocol):
    """A true motion that yields itself in chunks (the public streaming interface).

    Any truth generator (a profile followed by a model's own equations, a strapdown IMU
    simulator, recorded data) can feed the simulations without storing a whole day of
    samples: implement :meth:`chunks` and wrap it in :meth:`Trajectory.streamed`.
    """

    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """Consecutive chunks of at most ``size`` steps covering the whole run, in order;
        each starts at the step where the previous one ended (that step appears in both).
        Every call starts again from the beginning and yields the same numbers."""
        ...


STREAM_BYTES = 64_000_000
"""A moving trajectory whose samples would take more than this many bytes is streamed
(generated chunk by chunk while a simulation runs) instead of stored."""


STORE_CHUNK = 65536
"""Steps generated at a time while a streamed trajectory is stored whole."""


class Trajectory:
    """True motion on a run's step grid, ready for the integrators.

    A trajectory is either *stored* (arrays over the whole grid; one column when
    constant) or *streamed* (a :class:`MotionSource` yields it in chunks whenever it is
    run, so memory does not grow with the duration). Both offer :meth:`chunks`; the
    ``truth``, ``inputs`` and ``midpoints`` arrays of a streamed trajectory are built on
    first use (refused when they would not fit, :data:`MAX_SAMPLES`).

    Parameters
    ----------
    model : str
        :attr:`Model.key` of the model the inputs were computed for (its name for a
        built-in model).
    tau : float
        Step, s.
    n_steps : int
        Number of steps N (the grid has N + 1 points ``t = k τ``).
    truth : numpy.ndarray, shape (n, N + 1) or (n, 1)
        True state at the step times (one column when constant); for a streamed
        trajectory, the initial state (n, 1).
    inputs : numpy.ndarray, shape (nu, N + 1) or (nu, 1)
        Inputs at the step times (one column when constant or streamed).
    midpoints : numpy.ndarray, shape (nu, N) or (nu, 1)
        Inputs at ``t + τ/2`` (for RK4); one column when constant or streamed.
    parameters : numpy.ndarray, shape (np,)
        Model parameters the motion was computed with.
    initial_conditions : numpy.ndarray, shape (nc,)
        ``c`` of the start (latitude, longitude, heading, v_N, v_E...).
    constant : bool
        True for a static base (inputs and state constant: exact time invariance).
    description : str
        One line.
    source : MotionSource, optional
        Makes the trajectory streamed.

    Attributes
    ----------
    references : frozenset of str or None
        The reference values of the motion's start (:data:`REFERENCES`: latitude,
        longitude, heading, height) the run depends on, as :func:`trajectory` found them
        (:func:`references_used`, or the initial conditions a static base fills); None
        when not known (arrays or a source of the caller's own, a strapdown flight).
        :func:`refuse_unused_references` reads it.
    """

    references: frozenset[str] | None = None

    def depending_on(self, references: Collection[str]) -> Trajectory:
        """This trajectory with :attr:`references` set (returns ``self``)."""
        self.references = frozenset(references)
        return self

    def __init__(self, model: str, tau: float, n_steps: int, truth: np.ndarray,
                 inputs: np.ndarray, midpoints: np.ndarray, parameters: np.ndarray,
                 initial_conditions: np.ndarray, constant: bool, description: str,
                 source: MotionSource | None = None):
        self.model, self.tau, self.n_steps = model, float(tau), int(n_steps)
        self.parameters, self.initial_conditions = parameters, initial_conditions
        self.constant, self.description, self.source = constant, description, source
        self._truth, self._inputs, self._midpoints = truth, inputs, midpoints
        self._stored = source is None

    @classmethod
    def streamed(cls, model: str, tau: float, n_steps: int, source: MotionSource,
                 x0: np.ndarray, u0: np.ndarray, parameters: np.ndarray,
                 initial_conditions: np.ndarray, description: str) -> Trajectory:
        """A trajectory generated chunk by chunk by ``source``.

        Parameters
        ----------
        x0 : numpy.ndarray, shape (n,)
            True state at t = 0 (the first column of the first chunk).
        u0 : numpy.ndarray, shape (nu,)
            Inputs at t = 0.
        """
        x0, u0 = np.asarray(x0, dtype=float), np.asarray(u0, dtype=float)
        return cls(model, tau, n_steps, x0[:, None], u0[:, None], u0[:, None], parameters,
                   initial_conditions, False, description, source)

    def __repr__(self) -> str:
        kind = "constant" if self.constant else "stored" if self._stored else "streamed"
        return (f"<Trajectory {self.model!r}: {self.n_steps:,} steps of {self.tau:g} s, "
                f"{kind}: {self.description}>")

    # -- the whole grid ---------------------------------------------------------------
    @property
    def is_streamed(self) -> bool:
        """True while the samples are generated on demand rather than stored."""
        return not self._stored

    @property
    def truth_kind(self) -> str:
        """How the truth was computed: ``"static"`` (at rest: exact, nothing integrated),
        ``"fine"`` or ``"interpolated"`` (see :func:`trajectory`), or ``"given"`` (a
        source or arrays of the caller's own)."""
        if self.constant:
            return "static"
        return getattr(self.source, "kind", "given")

    @property
    def start_state(self) -> np.ndarray:
        """True state at t = 0, shape (n,)."""
        return self._truth[:, 0]

    @property
    def start_inputs(self) -> np.ndarray:
        """Inputs at t = 0, shape (nu,)."""
        return self._inputs[:, 0]

    @property
    def truth(self) -> np.ndarray:
        """True states, shape (n, N + 1) (one column when constant)."""
        self._store()
        return self._truth

    @property
    def inputs(self) -> np.ndarray:
        """Inputs at the step times, shape (nu, N + 1) (one column when constant)."""
        self._store()
        return self._inputs

    @property
    def midpoints(self) -> np.ndarray:
        """Inputs at the step midpoints, shape (nu, N) (one column when constant)."""
        self._store()
        return self._midpoints

    def _store(self) -> None:
        if self._stored:
            return
        n, nu = self._truth.shape[0], self._inputs.shape[0]
        n_values = (self.n_steps + 1) * (n + 2 * nu)
        if n_values > MAX_SAMPLES:
            raise StepError(f"storing a moving trajectory of {self.n_steps:,} steps needs "
                            f"about {8 * n_values / 1e9:.1f} GB; simulations stream it "
                            "without storing it (use a longer step or a shorter run to "
                            "keep it whole)")
        truth = np.empty((n, self.n_steps + 1))
        inputs = np.empty((nu, self.n_steps + 1))
        midpoints = np.empty((nu, self.n_steps))
        truth[:, 0], inputs[:, 0] = self._truth[:, 0], self._inputs[:, 0]  # a run of 0 steps
        for chunk in self.source.chunks(STORE_CHUNK):
            k, m = chunk.start, chunk.size
            truth[:, k:k + m + 1] = chunk.truth
            inputs[:, k:k + m + 1] = chunk.inputs
            midpoints[:, k:k + m] = chunk.midpoints
        self._truth, self._inputs, self._midpoints = truth, inputs, midpoints
        self._stored = True

    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """The motion in consecutive chunks of at most ``size`` steps (see
        :class:`MotionSource`); a stored trajectory is sliced, a streamed one generated."""
        if size < 1:
            raise StepError(f"chunk size must be a positive number of steps, got {size}")
        if not self._stored:
            yield from self.source.chunks(size)
            return
        if self.constant:
            raise StepError("a constant trajectory has no chunks: use its one column")
        for start in range(0, self.n_steps, size):
            stop = min(start + size, self.n_steps)
            yield TruthChunk(start, self._truth[:, start:stop + 1],
                             self._inputs[:, start:stop + 1], self._midpoints[:, start:stop])

    @property
    def times(self) -> np.ndarray:
        """Step times, s, shape (N + 1,)."""
        return np.arange(self.n_steps + 1) * self.tau

    @property
    def duration(self) -> float:
        """Length of the run, s."""
        return self.n_steps * self.tau

    def inputs_at(self, steps: np.ndarray) -> np.ndarray:
        """Inputs at the given step indices, shape (nu, len(steps))."""
        if self.constant:
            return np.repeat(self._inputs[:, :1], len(steps), axis=1)
        return self.inputs[:, steps]

    def full_inputs(self) -> tuple[np.ndarray, np.ndarray]:
        """Inputs at every step time (nu, N + 1) and midpoint (nu, N), expanded if constant."""
        if self.constant:
            return (np.repeat(self._inputs[:, :1], self.n_steps + 1, axis=1),
                    np.repeat(self._midpoints[:, :1], self.n_steps, axis=1))
        return self.inputs, self.midpoints


class ProfileTruth:
    """A :class:`Profile` followed by a model's ideal equations, generated in chunks.

    The truth is integrated with RK4 at half the run's step (compiled loop, commands at
    quarter steps) and the inputs are evaluated at every half step; a chunk's numbers do
    not depend on the chunk size.
    """

    kind = "fine"
    """How this source computes the truth (:attr:`Trajectory.truth_kind`)."""

    def __init__(self, model: Model, profile: Profile, frame: str, tau: float, n_steps: int,
                 p: np.ndarray, x0: np.ndarray):
        self.model_name, self.profile, self.frame = model.key, profile, frame
        self.tau, self.n_steps, self.p, self.x0 = float(tau), n_steps, p, x0

    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """Chunks of at most ``size`` steps (see :class:`MotionSource`)."""
        tau, p = self.tau, truth_parameters(self.model_name, self.frame, self.p)
        loop = _truth_loop(self.model_name, self.frame, tau / 2.0, p)
        carry = loop.start(self.x0, np.zeros(0))
        x_first = np.asarray(self.x0, dtype=float)
        for start in range(0, self.n_steps, size):
            m = min(size, self.n_steps - start)
            # commands at the quarter steps 4 start .. 4 (start + m)
            t_quarter = np.arange(4 * start, 4 * (start + m) + 1) * (tau / 4.0)
            values, rates = self.profile.commands(t_quarter)
            commands = np.vstack([values, rates])
            _check_finite(commands, "motion commands", tau / 4.0, 4 * start)
            stream = np.empty((2 * m, 24))
            stream[:, :8] = commands[:, 0:-1:2].T
            stream[:, 8:16] = commands[:, 1::2].T
            stream[:, 16:] = commands[:, 2::2].T
            n = len(x_first)
            half = np.empty((n, 2 * m + 1, 1))
            margins = np.empty((2 * m, 1))
            half[:, 0, 0] = x_first
            loop.advance(carry, 2 * m, stream, half[:, 1:], margins)
            states = half[:, :, 0]
            bad = ~np.all(np.isfinite(states), axis=0) | np.concatenate(
                [[False], ~(margins[:, 0] > 0)])
            if bad.any():
                k = 2 * start + int(np.argmax(bad))
                raise DomainError(f"the true motion leaves the model's domain at "
                                  f"t = {k * tau / 2:.6g} s (e.g. passes a pole)")
            u_all = _evaluate_inputs(self.model_name, self.frame, p,
                                     np.ascontiguousarray(states.T),
                                     np.ascontiguousarray(commands[:, ::2].T)).T
            _check_finite(u_all, "true inputs", tau / 2, 2 * start)
            yield TruthChunk(start, states[:, ::2], u_all[:, ::2], u_all[:, 1::2])
            x_first = states[:, -1].copy()


def run_arguments(model: Model | str, motion, kind: type, duration: float,
                  p: np.ndarray | None) -> tuple[Model, np.ndarray]:
    """Check the arguments of a true motion's run once, before anything is computed.

    Returns the model (loaded if given by name) and the parameter vector, shape (np,).

    Raises
    ------
    InsErrorsError, StepError, ShapeError, DomainError
        A model or motion of another type, a duration that is not positive (as the
        scenario files refuse it), or parameters of another shape, not finite or outside
        the model's parameter domain.
    """
    from ins_errors.numeric.model import as_model

    model = as_model(model, "trajectory")
    if not isinstance(motion, kind):
        raise InsErrorsError(f"trajectory: the motion must be a {kind.__name__} of "
                             f"{kind.__module__}, got {type(motion).__name__}")
    try:
        seconds = float(duration)
    except (TypeError, ValueError):
        raise StepError(f"run duration must be a number of seconds, got {duration!r:.40}"
                        ) from None
    if not seconds > 0:
        raise StepError(f"run duration must be positive, got {seconds:g} s")
    return model, model.run_parameters(p, "trajectory")


def trajectory(model: Model, profile: Profile, duration: float, tau: float,
               p: np.ndarray | None = None, progress: bool = False,
               stream: bool | None = None, truth: str = "auto") -> Trajectory:
    """Sample a motion profile for ``model`` on the grid ``t = k τ``, ``k = 0..N``.

    Parameters
    ----------
    model : Model
        Loaded model.
    profile : Profile
        The motion (see :func:`static_profile`, :func:`great_circle_profile`,
        :func:`manoeuvre_profile`, :func:`sampled_profile`).
    duration, tau : float
        Length of the run (> 0) and step, s; the duration must be a whole number of steps.
    p : numpy.ndarray, shape (np,), optional
        Parameters, SI (default: the model's defaults, ``model.parameter_vector()``,
        with the model's own Earth: the Krasovsky ellipsoid for ``orthodromic`` and
        ``geodetic_vertical``, WGS-84 for ``strapdown_ned``, a sphere for
        ``north_pointing`` and ``free_azimuth``; ``model.parameter_vector(
        ellipsoid="wgs84")`` takes another).
    progress : bool
        Show progress while integrating a stored true motion.
    stream : bool, optional
        Generate a moving truth chunk by chunk whenever it is run instead of storing it
        (:class:`ProfileTruth`); default: stream when the stored samples would exceed
        :data:`STREAM_BYTES`. A streamed motion that leaves the model's domain is
        reported when it is run.
    truth : {"auto", "interpolated", "fine"}
        How a moving truth is computed. ``"fine"``: RK4 at half the step and the inputs
        evaluated at every half step (:class:`ProfileTruth`); ``"interpolated"``: on
        coarse intervals of about 10 s between the profile's breaks, interpolated to the
        steps by polynomials of degree 7 (:mod:`ins_errors.numeric.interpolated_truth`,
        hundreds of times cheaper per step); ``"auto"`` (default): interpolated when the
        profile's breaks are known and the intervals hold at least
        :data:`~ins_errors.numeric.interpolated_truth.MIN_STEPS` steps (on average,
        counting the breaks), else fine. (The strapdown model's true IMU signals come
        from :mod:`ins_errors.numeric.strapdown_truth`, fine or interpolated alike.)

    Raises
    ------
    StepError, MotionError, DomainError
        Bad grid, a motion the model cannot follow, or a motion through a pole.
    """
    if truth not in TRUTHS:
        from ins_errors.errors import unknown_name

        raise unknown_name("truth", truth, TRUTHS)
    model, p = run_arguments(model, profile, Profile, duration, p)
    model.check_start_latitude(profile.latitude, p, "trajectory")
    profile = covering(profile, float(duration))  # a repeated manoeuvre's joins, all of them
    if model.name == "strapdown_ned":  # body rates and specific force, not a_* inputs
        from ins_errors.numeric import strapdown_truth

        return strapdown_truth.trajectory(model, strapdown_truth.flight_from_profile(profile),
                                          duration, tau, p, truth=truth, stream=stream)
    n_steps = step_count(duration, tau)
    unknown = unset_inputs(model)
    if unknown:  # inputs the kinematics cannot set (body rates, specific forces)
        if profile.static:
            return _static_from_equations(model, profile, float(tau), n_steps, p)
        # a strapdown flight, followed by the model's own equations (model_flight)
        from ins_errors.numeric import strapdown_truth

        return strapdown_truth.trajectory(model, strapdown_truth.flight_from_profile(profile),
                                          duration, tau, p, truth=truth, stream=stream)
    frame = profile.frame
    if profile.static and not any(o.name == "heading" for o in model.outputs):
        frame = "geographic"  # at rest the commands are zero in any frame
    if not profile.static and _velocity_index(model, EAST) is None:
        raise MotionError(f"model {model.name!r} has no east velocity (initial condition "
                          "v_E or v_E0): it follows a static base only")
    try:
        kin = _kinematics(model.key, frame)
    except MotionError:
        if not profile.static:
            raise
        # a model the kinematics cannot serve (e.g. without v_N) may still rest
        return _static_from_equations(model, profile, float(tau), n_steps, p)
    # the description states only the reference values the run depends on
    used = references_used(model.key, frame)
    description = profile.describe(used)
    start = np.array([profile.latitude, profile.longitude, profile.heading])
    values0, rates0 = profile.commands(np.zeros(1))
    x0, c0 = (np.asarray(v).ravel() for v in kin.initial_state(start, values0[:, 0], p))
    u0 = np.asarray(kin.inputs(x0, values0[:, 0], rates0[:, 0], p)).ravel()
    if profile.static:
        _check_finite(u0, "static-base inputs", 0.0)
        # a vehicle at rest may still have a moving state (e.g. a free-azimuth angle that
        # follows the Earth's rotation): only a state at equilibrium is held constant
        if np.abs(model.numpy.ideal_rhs(x0, u0, p)).max() <= STATIC_TOLERANCE:
            return Trajectory(model.key, float(tau), n_steps, x0[:, None], u0[:, None],
                              u0[:, None], p, c0, True, description).depending_on(used)
    source = _truth_source(model, profile, frame, float(tau), n_steps, p, x0, truth)
    # about 74 numbers per step for the orthodromic model while it is built
    n_values = (4 * n_steps + 1) * 8 + (2 * n_steps + 1) * (2 * len(model.states)
                                                          + len(model.inputs))
    if stream is None:
        stream = 8 * n_values > STREAM_BYTES
    if stream:  # (n_steps >= 1: a zero duration was refused above)
        if isinstance(source, ProfileTruth):
            first = next(source.chunks(1))  # checks the start of the motion now
            x_first, u_first = first.truth[:, 0], first.inputs[:, 0]
        else:
            x_first, u_first = source.start()
        return Trajectory.streamed(model.key, tau, n_steps, source, x_first, u_first, p, c0,
                                   description).depending_on(used)
    traj = Trajectory.streamed(model.key, tau, n_steps, source, x0, u0, p, c0, description)
    traj._store()
    return traj.depending_on(used)


KINEMATIC_INPUTS = ("h", "V_zeta", "a_zeta")
"""Inputs the kinematic motion generators set by name, besides the apparent
accelerations ``a_*``."""

NORTH, EAST = ("v_N", "v_N0"), ("v_E", "v_E0")
"""Names of the initial conditions a moving motion sets to the north and east velocity
(``v_N0``, ``v_E0``: a model whose states are named ``v_N``, ``v_E``)."""


def unset_inputs(model: Model) -> list[str]:
    """Inputs of ``model`` the kinematic motion generators cannot set (any name but
    :data:`KINEMATIC_INPUTS` and ``a_*``): such a model (a strapdown INS fed body rates
    and specific forces) rests on a static base solved from its own equations
    (:mod:`ins_errors.numeric.static_rest`) and flies the strapdown flights
    (:mod:`ins_errors.numeric.strapdown_truth`, :mod:`ins_errors.numeric.model_flight`)."""
    return [i.name for i in model.inputs
            if i.name not in KINEMATIC_INPUTS and not i.name.startswith("a_")]


def _velocity_index(model: Model, names: tuple[str, ...]) -> int | None:
    """Index of the first initial condition named one of ``names``, or None."""
    conditions = [c.name for c in model.initial_conditions]
    return next((conditions.index(n) for n in names if n in conditions), None)


def _static_from_equations(model: Model, profile: Profile, tau: float, n_steps: int,
                           p: np.ndarray) -> Trajectory:
    """A static base solved from the model's equations (see
    :mod:`ins_errors.numeric.static_rest`), one constant column."""
    from ins_errors.numeric.static_rest import static_rest

    values, _ = profile.commands(np.zeros(1))
    x0, u0, c0, references = static_rest(model, profile.latitude, profile.longitude,
                                         profile.heading, float(values[2, 0]), p)
    return Trajectory(model.key, tau, n_steps, x0[:, None], u0[:, None], u0[:, None], p, c0,
                      True, profile.describe(references)).depending_on(references)


STATIC_TOLERANCE = 1e-12
"""Largest |dx/dt| (SI per second) for which a state at rest is treated as constant."""

TRUTHS = ("auto", "interpolated", "fine")
"""Ways of computing a moving truth (see :func:`trajectory`)."""


def _truth_source(model: Model, profile: Profile, frame: str, tau: float, n_steps: int,
                  p: np.ndarray, x0: np.ndarray, truth: str) -> MotionSource:
    """The fine or the interpolated truth generator, as ``truth`` asks."""
    from ins_errors.numeric import interpolated_truth as it

    truth = it.chosen_truth(truth, profile.breaks, n_steps, tau,
                            "a profile (a great circle, a manoeuvre or a sampled motion)")
    if truth == "interpolated":
        return it.InterpolatedTruth(model, profile, frame, tau, n_steps, p, x0)
    return ProfileTruth(model, profile, frame, tau, n_steps, p, x0)


@lru_cache(maxsize=64)
def _truth_parameter_mask(model_name: str, frame: str) -> tuple[bool, ...]:
    """Which model parameters the true motion's compiled functions read: its kinematics
    (:func:`_kinematics`: the rates and the inputs it makes) and the domain margins."""
    from ins_errors.numeric.model import load_model

    model = load_model(model_name)
    kin = _kinematics(model_name, frame)
    x = ca.SX.sym("x", len(model.states))
    commands = ca.SX.sym("c", 8)
    par = ca.SX.sym("p", len(model.parameters))
    u = kin.inputs(x, commands[:4], commands[4:], par)
    read = ca.vertcat(kin.truth_rhs(x, commands, ca.SX(0, 1), par), u,
                      model.casadi.function("domain_margins")(x, u, par))
    return tuple(bool(ca.depends_on(read, par[i])) for i in range(par.numel()))


def truth_parameters(model_name: str, frame: str, p) -> tuple[float, ...]:
    """``p`` with the parameters the true motion never reads set to 0.

    The truth's compiled functions (:func:`_truth_loop`, :func:`_inputs_chunk`,
    :func:`ins_errors.numeric.interpolated_truth._gap_function`) have the parameters
    written into their C code and are cached on their values; a parameter they do not
    read (a damping gain, an instrument's scale) changes nothing they compute, so a
    sweep over it flies one compiled truth instead of compiling one per value, with the
    same bits.
    """
    mask = _truth_parameter_mask(model_name, frame)
    return tuple(float(v) if read else 0.0 for v, read in zip(p, mask, strict=True))


@lru_cache(maxsize=16)
def _truth_loop(model_name: str, frame: str, step: float, p: tuple[float, ...]) -> CompiledLoop:
    from ins_errors.numeric.model import load_model

    model = load_model(model_name)
    kin = _kinematics(model_name, frame)
    margins = model.casadi.function("domain_margins")
    x = ca.SX.sym("x", len(model.states))
    stream = ca.SX.sym("s", 8)
    par = ca.SX.sym("p", len(model.parameters))
    none = ca.SX.sym("none", 0)
    u = kin.inputs(x, stream[:4], stream[4:], par)
    margin = ca.Function("truth_margin", [x, stream, none, par], [ca.mmin(margins(x, u, par))])
    return CompiledLoop(kin.truth_rhs, margin, "rk4", 1, step, np.array(p), chunk=256)


_INPUT_CHUNK = 4096


@lru_cache(maxsize=16)
def _inputs_chunk(model_name: str, frame: str, p: tuple[float, ...]) -> DenseCall:
    kin = _kinematics(model_name, frame)
    n = kin.inputs.size1_in(0)
    X, C = ca.SX.sym("X", n), ca.SX.sym("C", 8)
    one = ca.Function("inputs_p", [X, C], [kin.inputs(X, C[:4], C[4:], ca.DM(list(p)))])
    mapped = one.map("motion_inputs_chunk", "serial", _INPUT_CHUNK, [], [])
    return native_functions([mapped])[0]


def _evaluate_inputs(model_name: str, frame: str, p: tuple[float, ...], states: np.ndarray,
                     commands: np.ndarray) -> np.ndarray:
    """Inputs at every row of ``states`` (T, n) and ``commands`` (T, 8), compiled.

    Returns
    -------
    numpy.ndarray, shape (T, nu)
    """
    fn = _inputs_chunk(model_name, frame, p)
    total = states.shape[0]
    nu = fn.shapes_out[0][0]
    out = np.empty((total, nu))
    for start in range(0, total, _INPUT_CHUNK):
        stop = min(start + _INPUT_CHUNK, total)
        pad = _INPUT_CHUNK - (stop - start)
        xs, cs = states[start:stop], commands[start:stop]
        if pad or not xs.flags.c_contiguous or not cs.flags.c_contiguous:
            xs = np.ascontiguousarray(np.vstack([xs, np.repeat(xs[-1:], pad, axis=0)]))
            cs = np.ascontiguousarray(np.vstack([cs, np.repeat(cs[-1:], pad, axis=0)]))
        if pad:
            full = np.empty((_INPUT_CHUNK, nu))
            fn([xs, cs], [full])
            out[start:stop] = full[:stop - start]
        else:
            fn([xs, cs], [out[start:stop]])
    return out


def _check_finite(array: np.ndarray, what: str, dt: float, first: int = 0) -> None:
    """Raise if ``array`` (columns at times ``(first + j) dt``) holds NaN or infinity."""
    bad = ~np.isfinite(np.asarray(array))
    if bad.any():
        column = int(np.argmax(bad.any(axis=0))) if bad.ndim > 1 else 0
        raise DomainError(f"{what} are NaN or infinite at t = {(first + column) * dt:.6g} s")


def consistent_state(model: Model, x: np.ndarray, commands: np.ndarray, frame: str = "track",
                     p: np.ndarray | None = None) -> np.ndarray:
    """The state with the model's velocities set to the commanded relative velocity.

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        State giving position and heading.
    commands : numpy.ndarray, shape (4,)
        (v1, v2, h, V_zeta) in ``frame``.
    """
    p = model.parameter_vector() if p is None else p
    return np.asarray(_kinematics(model.key, frame).consistent_state(x, commands, p)).ravel()
