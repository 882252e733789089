"""True IMU signals of a strapdown INS from a planned flight (model ``strapdown_ned``).

A flight is planned as a horizontal ground speed ``V(t)``, a commanded turn rate
``r(t)`` (on top of the geodesic), a vertical speed and an attitude that follows the
flight path: heading = course ψ, pitch = flight-path angle ``atan(−v_D / V)``, roll =
coordinated bank ``atan(V r / g₀)``. The course obeys ``ψ̇ = v_E tan φ / (R_E + h) + r``:
with ``r = 0`` the vehicle flies along a geodesic of the ellipsoid ("great circle").

A motion file (a ``"geographic"`` :func:`~ins_errors.numeric.trajectories.sampled_profile`:
cubic splines of v_N(t), v_E(t) and h(t) through the file's samples) is flown as the
kinematic models fly it: the velocity is the splines' (v_D = −ḣ), and latitude and
longitude are integrated from it on the model's Earth (:func:`flight_from_profile`,
:class:`FileFlightCommands`; such a :class:`Flight` is ``geographic``). Its attitude
follows the flight path by the same rules: heading = course ``ψ = atan2(v_E, v_N)``,
pitch ``atan(−v_D / V)`` and the coordinated bank ``atan(V r / g₀)`` with ``r`` the
turn rate *on top of the geodesic*, ``r = ψ̇ − v_E tan φ / (R_E + h)`` (the rule of the
planned flights, so a file that follows a great circle flies wings level, as the
planned great circle does; ``r`` depends on the position, so it is computed with the
kinematics, not given as a command of time). ``ψ̇``, ``ψ̈`` and ``ṙ`` are analytic from
the splines' first and second derivatives, which a cubic spline has continuous: the
body rates and specific forces are continuous, their rates jump at the samples (the
flight's breaks). A file whose ground speed falls below :data:`MIN_FILE_SPEED` within
the run (course undefined), or a run longer than the file, is refused before any work.

Latitude, longitude, height and course are integrated, and at the times where the
signals are needed the exact rigid-body kinematics give the true body rate and specific
force. Two ways (:mod:`ins_errors.numeric.strapdown_stream`, both streamed chunk by
chunk): ``truth="fine"`` integrates with an adaptive 8th-order Runge–Kutta method at a
relative tolerance of 1e-13 (:func:`scipy.integrate.solve_ivp`, DOP853 with dense
output) and evaluates the kinematics at every step time and step midpoint;
``truth="interpolated"`` (the default at small steps) solves on the nodes of coarse
intervals ending at the flight's leg joins and interpolates to the steps. The kinematics:

* ``ω_ib^b = ω_nb^b + C_n^b ω_in^n``, with ``ω_nb^b`` from the Euler-angle rates and
  ``ω_in^n = ω_ie^n + ω_en^n`` (Earth rate plus transport rate);
* ``f^b = C_n^b (v̇^n + (2 ω_ie^n + ω_en^n) × v^n − (0, 0, γ(φ, h)))``,

with the radii of curvature and the normal gravity of :mod:`ins_errors.models.earth`
and the parameters of the model (so the true motion is an exact solution of the model's
ideal-work equations up to the integration tolerance). The height reference of the
vertical damping loop is the true height.

Example
-------
>>> import numpy as np
>>> from ins_errors import load_model
>>> from ins_errors.numeric import strapdown_truth as st
>>> model = load_model("strapdown_ned")
>>> flight = st.great_circle(np.radians(50), np.radians(30), np.radians(60), 250.0)
>>> traj = st.trajectory(model, flight, duration=600.0, tau=0.01)
>>> traj.inputs.shape
(7, 60001)
"""

from __future__ import annotations

import math
import warnings
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ins_errors.errors import DomainError
from ins_errors.models.earth import normal_gravity, radii_of_curvature
from ins_errors.numeric.integrators import step_count
from ins_errors.numeric.model import Model
from ins_errors.numeric.trajectories import (
    Leg,
    MotionError,
    Profile,
    Trajectory,
    angle_text,
    check_height,
    check_track_angle,
    latitude_text,
    motion_number,
    run_arguments,
    smoothstep,
)

MODEL = "strapdown_ned"
"""The model whose inputs this module generates."""

BANK_GRAVITY = 9.80665
"""g₀ of the coordinated-bank rule roll = atan(V r / g₀), m/s² (a choice of the flight)."""


@dataclass
class Flight:
    """A planned flight for a strapdown INS.

    Attributes
    ----------
    latitude, longitude, height : float
        Start point (rad, rad, m).
    course : float
        Initial course (= heading), rad from north towards east.
    commands : callable
        ``commands(t) -> (V, dV, r, dr, v_D, dv_D)``, each shape (T,): horizontal ground
        speed (m/s) and its rate, commanded turn rate (rad/s, positive to the right)
        and its rate, down velocity (m/s) and its rate. For a ``geographic`` flight
        ``commands(t) -> (v_N, v_E, v_D, dv_N, dv_E, dv_D, ddv_N, ddv_E)`` (m/s, m/s²,
        m/s³; :class:`FileFlightCommands`).
    description : str
        One line for reports.
    static : bool
        True for a vehicle at rest (constant inputs).
    roll, pitch : float
        Attitude of a vehicle at rest, rad (moving flights follow the flight path).
    breaks : sequence of float, optional
        Times (s) where the commands may lose smoothness (leg joins); between them the
        commands are smooth (analytic). ``()`` for a flight smooth throughout, None when
        unknown: only a flight with known breaks gets the fast interpolated truth
        (:class:`~ins_errors.numeric.strapdown_stream.InterpolatedFlight`).
    geographic : bool
        True for a flight whose commands are the geographic velocity (a motion file):
        its course is ``atan2(v_E, v_N)`` of the commands, not integrated (the fourth
        component of the integrated position, the course of the other flights, stays at
        :attr:`course`).
    """

    latitude: float
    longitude: float
    height: float
    course: float
    commands: Callable[[np.ndarray], tuple[np.ndarray, ...]]
    description: str
    static: bool = False
    roll: float = 0.0
    pitch: float = 0.0
    breaks: Sequence[float] | None = None
    geographic: bool = False

    def __post_init__(self) -> None:
        for name in ("latitude", "longitude", "height", "course", "roll", "pitch"):
            value = getattr(self, name)
            if not np.isfinite(value):
                raise MotionError(f"flight {name} must be finite, got {value}")
        check_track_angle(self.course, "flight course")
        check_track_angle(self.longitude, "flight longitude", "30° east, -30° west")
        if abs(self.latitude) >= np.pi / 2:
            raise MotionError(f"flight latitude {angle_text(self.latitude)} is at or beyond "
                              "a pole: longitude is undefined there")
        if abs(self.pitch) >= np.pi / 2:
            raise MotionError(f"pitch {np.degrees(self.pitch):g}° is at or beyond ±90°: roll "
                              "and heading are undefined there")


# --------------------------------------------------------------------------------------
# Commands of the flights: module-level callables (a closure cannot be pickled, and a
# trajectory carries its flight to the worker processes of a Monte Carlo run)
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class GeodesicCommands:
    """Level flight along the geodesic at a constant ground speed (0 m/s: at rest).

    Attributes
    ----------
    speed : float
        m/s.
    """

    speed: float

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, ...]:
        zero = np.zeros(t.shape)
        if not self.speed:
            return zero, zero, zero, zero, zero, zero
        return np.full(t.shape, self.speed), zero, zero, zero, zero, zero


@dataclass(frozen=True)
class FlightLegCommands:
    """The commands of :func:`manoeuvre`.

    Attributes
    ----------
    starts : tuple of (float, float, float, float, Leg)
        Per leg: start (s), length (s), ground speed (m/s) and height (m) at its start,
        and the leg.
    speed : float
        Ground speed before the first leg, m/s.
    """

    starts: tuple
    speed: float

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, ...]:
        starts = self.starts
        V, dV = np.full(t.shape, self.speed), np.zeros(t.shape)
        r, dr = np.zeros(t.shape), np.zeros(t.shape)
        vD, dvD = np.zeros(t.shape), np.zeros(t.shape)
        for j, (start, length, vs, hs, leg) in enumerate(starts):
            # a leg sets every value from its start on and the next leg overwrites them
            # from its own start: a leg with no time before the next start changes nothing
            following = starts[j + 1][0] if j + 1 < len(starts) else np.inf
            if not np.any((t >= start) & (t < following)):
                continue
            s, ds, dds = smoothstep((t - start) / length)
            active = t >= start
            V = np.where(active, vs + (leg.speed - vs) * s, V)
            dV = np.where(active, (leg.speed - vs) * ds / length, dV)
            inside = active & (t < start + length)
            r = np.where(inside, -leg.turn * ds / length, np.where(active, 0.0, r))
            dr = np.where(inside, -leg.turn * dds / length**2, np.where(active, 0.0, dr))
            vD = np.where(inside, -(leg.height - hs) * ds / length, np.where(active, 0.0, vD))
            dvD = np.where(inside, -(leg.height - hs) * dds / length**2,
                           np.where(active, 0.0, dvD))
        return V, dV, r, dr, vD, dvD


@dataclass(frozen=True, eq=False)
class ProfileFlightCommands:
    """The commands of :func:`flight_from_profile`: ground speed, turn rate and down
    velocity of a track-frame profile's commands, and their rates.

    Attributes
    ----------
    profile_commands : callable
        The profile's ``commands`` (:class:`~ins_errors.numeric.trajectories.Profile`).
    known : numpy.ndarray, shape (m,)
        The start and the profile's breaks, s, increasing.
    step : float
        Step of the differences of the turn rate, s.
    """

    profile_commands: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    known: np.ndarray
    step: float = 1e-3

    def turn(self, t: np.ndarray) -> tuple[np.ndarray, ...]:
        """The profile's values and rates, the ground speed and the turn rate at ``t``."""
        values, rates = self.profile_commands(t)
        v1, v2, dv1, dv2 = values[0], values[1], rates[0], rates[1]
        speed = np.hypot(v1, v2)
        return values, rates, speed, -(v1 * dv2 - v2 * dv1) / speed**2

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, ...]:
        known, step, turn = self.known, self.step, self.turn
        values, rates, speed, r = turn(t)
        last = np.searchsorted(known, t, side="right") - 1
        forward = (last < 0) | (t - known[np.maximum(last, 0)] < 2 * step)
        after = np.minimum(last + 1, known.size - 1)
        backward = ~forward & (last + 1 < known.size) & (known[after] - t < 2 * step)
        rows = np.where(forward[:, None], _FORWARD,
                        np.where(backward[:, None], -_FORWARD, _CENTRAL))
        offsets = np.where(forward[:, None], _AHEAD,
                           np.where(backward[:, None], -_AHEAD, _AROUND))
        r_near = turn((t[:, None] + step * offsets).ravel())[3].reshape(offsets.shape)
        dr = (rows[:, 0] * r + np.einsum("ij,ij->i", rows[:, 1:], r_near)) / (12 * step)
        dspeed = (values[0] * rates[0] + values[1] * rates[1]) / speed
        return speed, dspeed, r, dr, -values[3], -rates[3]


MIN_FILE_SPEED = 0.01
"""Smallest ground speed of a motion file a strapdown INS flies, m/s: below it the course
``atan2(v_E, v_N)`` (the heading) is undefined or turns without bound."""

SPEED_CHECKS = 8
"""Points per interval between two samples (besides the samples) where the ground speed
of a motion file is checked against :data:`MIN_FILE_SPEED`."""


@dataclass(frozen=True, eq=False)
class FileFlightCommands:
    """The commands of a motion file's flight (:func:`flight_from_profile`): the geographic
    velocity of the file's cubic splines and its first and second rates, analytic.

    Attributes
    ----------
    splines : tuple of scipy.interpolate.CubicSpline
        v_N, v_E (m/s) and h (m) against time (s), those of the
        :class:`~ins_errors.numeric.trajectories.SplineCommands` of the file.
    start, end : float
        First and last sample time, s.
    source : str
        The file for messages (``motion file PATH (N samples, ...)``).
    """

    splines: tuple
    start: float
    end: float
    source: str = "the motion file"

    def _check(self, t: np.ndarray) -> None:
        if t.size and (t.min() < self.start - 1e-9 or t.max() > self.end + 1e-9):
            raise MotionError(f"the run ({t.min():g}–{t.max():g} s) leaves the sampled motion "
                              f"({self.start:g}–{self.end:g} s)")

    def __call__(self, t: np.ndarray) -> tuple[np.ndarray, ...]:
        """(v_N, v_E, v_D, dv_N, dv_E, dv_D, ddv_N, ddv_E) at times ``t`` (T,), each (T,)."""
        self._check(t)
        vN, vE, h = self.splines
        return (vN(t), vE(t), -h(t, 1), vN(t, 1), vE(t, 1), -h(t, 2), vN(t, 2), vE(t, 2))

    def check_run(self, t_end: float) -> None:
        """Refuse a run over ``[0, t_end]`` (s) that leaves the file or along which the
        ground speed falls below :data:`MIN_FILE_SPEED` (one line naming the time).

        Raises
        ------
        MotionError
        """
        if self.start > 1e-9 or t_end > self.end + 1e-9:
            raise MotionError(f"the run (0–{t_end:g} s) leaves the sampled motion "
                              f"({self.start:g}–{self.end:g} s)")
        x = self.splines[0].x
        knots = np.concatenate([x[x < t_end], [t_end]])
        fractions = np.arange(SPEED_CHECKS + 1) / (SPEED_CHECKS + 1)
        for first in range(0, knots.size - 1, 65536):  # in pieces: bounded memory
            part = knots[first:first + 65537]
            t = (part[:-1, None] + np.diff(part)[:, None] * fractions).ravel()
            if first + 65536 >= knots.size - 1:
                t = np.append(t, t_end)
            speed = np.hypot(self.splines[0](t), self.splines[1](t))
            slow = speed < MIN_FILE_SPEED
            if slow.any():
                k = int(np.argmax(slow))
                raise MotionError(f"the motion file's ground speed is {speed[k]:.3g} m/s at "
                                  f"t = {t[k]:.6g} s: a strapdown INS heads along the course "
                                  f"atan2(v_E, v_N), undefined below {MIN_FILE_SPEED:g} m/s")


def static(latitude: float, longitude: float = 0.0, height: float = 0.0, roll: float = 0.0,
           pitch: float = 0.0, heading: float = 0.0) -> Flight:
    """A vehicle at rest at (φ, λ, h) with the given attitude (rad)."""
    latitude, longitude, roll, pitch, heading = (
        motion_number(v, f"flight {k}", "rad") for k, v in (
            ("latitude", latitude), ("longitude", longitude), ("roll", roll),
            ("pitch", pitch), ("heading", heading)))
    height = motion_number(height, "flight height", "m")
    check_height(height, "flight height")

    return Flight(latitude, longitude, height, heading, GeodesicCommands(0.0),
                  f"static base at φ={latitude_text(latitude)}°, λ={np.degrees(longitude):.4g}°,"
                  f" h={height:g} m, roll/pitch/heading = {np.degrees(roll):.3g}°/"
                  f"{np.degrees(pitch):.3g}°/{np.degrees(heading):.4g}°",
                  static=True, roll=roll, pitch=pitch)


def great_circle(latitude: float, longitude: float, course: float, speed: float,
                 height: float = 0.0) -> Flight:
    """Level flight along a geodesic at constant ground speed (m/s) and height (m)."""
    latitude, longitude, course = (
        motion_number(v, f"flight {k}", "rad") for k, v in (
            ("latitude", latitude), ("longitude", longitude), ("course", course)))
    height = motion_number(height, "flight height", "m")
    check_height(height, "flight height")
    speed = motion_number(speed, "great-circle speed", "m/s")
    if not np.isfinite(speed) or speed <= 0:
        raise MotionError(f"great-circle speed must be > 0 m/s, got {speed:g} m/s")

    return Flight(latitude, longitude, height, course, GeodesicCommands(float(speed)),
                  f"great circle from φ={latitude_text(latitude)}°, "
                  f"λ={np.degrees(longitude):.4g}°, course {np.degrees(course):.4g}°, "
                  f"{speed:g} m/s, h={height:g} m", breaks=())


def manoeuvre(latitude: float, longitude: float, course: float, speed: float,
              legs: Sequence[Leg], height: float = 0.0) -> Flight:
    """A flight of smooth legs: turns (coordinated bank), speed changes, climbs, descents.

    Within each leg the ground speed, the course change (``Leg.turn``, rad, positive to
    the left as in :class:`~ins_errors.numeric.trajectories.Leg`) and the height move to
    their end values along a C² ramp, so velocities, attitude and their rates are
    continuous. After the last leg the flight continues along the geodesic.
    """
    latitude, longitude, course = (
        motion_number(v, f"flight {k}", "rad") for k, v in (
            ("latitude", latitude), ("longitude", longitude), ("course", course)))
    height = motion_number(height, "flight height", "m")
    check_height(height, "flight height")
    speed = motion_number(speed, "manoeuvre speed", "m/s")
    if not np.isfinite(speed) or speed <= 0:
        raise MotionError(f"manoeuvre speed must be > 0 m/s, got {speed:g} m/s")
    if len(legs) == 0:
        raise MotionError("a manoeuvre needs at least 1 leg, got none (an empty list of "
                          "legs)")
    starts, t0, v0, h0 = [], 0.0, float(speed), float(height)
    for leg in legs:
        if not leg.duration > 0:
            raise MotionError(f"manoeuvre leg duration must be positive, got {leg.duration}")
        if not leg.speed > 0:
            raise MotionError(f"manoeuvre leg speed must be > 0 m/s, got {leg.speed:g} m/s")
        check_height(leg.height, "manoeuvre leg height")
        starts.append((t0, float(leg.duration), v0, h0, leg))
        t0, v0, h0 = t0 + leg.duration, float(leg.speed), float(leg.height)

    return Flight(latitude, longitude, height, course,
                  FlightLegCommands(tuple(starts), float(speed)),
                  f"manoeuvring flight of {len(legs)} legs from φ={latitude_text(latitude)}°,"
                  f" λ={np.degrees(longitude):.4g}°",
                  breaks=tuple(float(start + length) for start, length, *_ in starts))


def standard_manoeuvre(latitude: float = np.radians(50.0), longitude: float = np.radians(30.0),
                       course: float = np.radians(90.0)) -> Flight:
    """The manoeuvre of the comparisons: take-off speed, climbs, turns and accelerations.

    Fifteen minutes of legs (accelerate 100 → 200 m/s while climbing to 3 km, a 90° left
    turn, a 180° right turn while accelerating to 250 m/s, a descent to 2 km with a
    deceleration, a 90° left turn), then geodesic cruise.
    """
    legs = [Leg(120.0, 200.0, 0.0, 3000.0), Leg(90.0, 200.0, np.radians(90.0), 3000.0),
            Leg(180.0, 250.0, np.radians(-180.0), 3000.0), Leg(150.0, 220.0, 0.0, 2000.0),
            Leg(90.0, 220.0, np.radians(90.0), 2000.0), Leg(270.0, 230.0, 0.0, 2000.0)]
    return manoeuvre(latitude, longitude, course, 100.0, legs)


_AROUND = np.array([-2.0, -1.0, 1.0, 2.0])
_CENTRAL = np.array([0.0, 1.0, -8.0, 8.0, -1.0])
"""Weights (×1/12) of r at 0 and at the steps ``_AROUND``: the centred difference."""
_AHEAD = np.array([1.0, 2.0, 3.0, 4.0])
_FORWARD = np.array([-25.0, 48.0, -36.0, 16.0, -3.0])
"""Weights (×1/12) of r at 0 and at the steps ``_AHEAD``: the one-sided difference (its
mirror, steps and weights negated, looks back)."""


def flight_from_profile(profile: Profile) -> Flight:
    """The strapdown flight of a track-frame motion profile (CLI and scenario motions).

    A :class:`~ins_errors.numeric.trajectories.Profile` in the ``"track"`` frame gives the
    ground velocity (v_ξ, v_η) relative to a trihedron that follows the geodesic, the
    height and the vertical speed. Its speed is ``V = |v|``, its course the trihedron's
    heading minus ``atan2(v_η, v_ξ)`` (v_η to the left), so the commanded turn rate is
    ``r = −d/dt atan2(v_η, v_ξ)``; the rate of ``r`` (needed for the bank rate) is a
    five-point difference over 1-ms steps of the profile's C² commands (fourth order:
    exact for the quartic turn rates of the legs up to rounding), one-sided next to the
    start and to the profile's breaks so that it never straddles a leg join.

    A ``"geographic"`` profile of a motion file
    (:func:`~ins_errors.numeric.trajectories.sampled_profile`) becomes a ``geographic``
    flight of the file's splines (:class:`FileFlightCommands`): its course is the file's
    ``atan2(v_E, v_N)`` (the profile's heading, the start track angle of a kinematic
    model's trihedron, is not used) and its breaks are the sample times.

    Raises
    ------
    MotionError
        For a ``"geographic"`` profile that is not a motion file's cubic splines.
    """
    from ins_errors.numeric.trajectories import SplineCommands

    if profile.static:
        values, _ = profile.commands(np.zeros(1))
        return static(profile.latitude, profile.longitude, float(values[2, 0]),
                      heading=profile.heading)
    if profile.frame != "track":
        if not isinstance(profile.commands, SplineCommands):
            raise MotionError("a strapdown INS flies a geographic motion given as samples "
                              "(a motion file, trajectories.sampled_profile) only: its "
                              "attitude rates need the splines' second derivatives")
        spline = profile.commands
        commands = FileFlightCommands(spline.splines, spline.start, spline.end,
                                      profile.describe(set()) or "the motion file")
        vN, vE, *_ = commands(np.zeros(1))
        # the file's own course is flown: the profile's track angle is not stated
        return Flight(profile.latitude, profile.longitude, float(spline.splines[2](0.0)),
                      float(np.arctan2(vE[0], vN[0])), commands,
                      profile.describe({"latitude", "longitude", "height"}),
                      breaks=tuple(float(b) for b in profile.breaks), geographic=True)

    # the rate of r: five-point differences over 1-ms steps (exact for the legs' quartic
    # turn rates up to rounding), one-sided within two steps after the start or a break
    # and before a break, so that they never straddle a join where r's higher rates jump
    known = np.unique(np.concatenate([[0.0], np.asarray(profile.breaks or (), dtype=float)]))
    commands = ProfileFlightCommands(profile.commands, known)
    values0, _ = profile.commands(np.zeros(1))
    if not np.hypot(values0[0, 0], values0[1, 0]) > 0:
        raise MotionError("a moving strapdown flight must start with a positive speed")
    course = profile.heading - np.arctan2(values0[1, 0], values0[0, 0])
    breaks = None if profile.breaks is None else tuple(float(b) for b in profile.breaks)
    return Flight(profile.latitude, profile.longitude, float(values0[2, 0]), float(course),
                  commands, profile.description, breaks=breaks)


# --------------------------------------------------------------------------------------
# Kinematics
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FlightEarth:
    """The Earth a flight is planned on: its ellipsoid, rotation and normal gravity.

    Attributes
    ----------
    a : float
        Equatorial radius, m (a sphere's radius where ``e2`` is 0).
    e2 : float
        First eccentricity squared.
    U : float
        Earth rate, rad/s.
    gamma_e, k, m : float
        Normal gravity (:func:`~ins_errors.models.earth.normal_gravity`): equatorial
        gravity (m/s²), Somigliana's constant and ω²a²b/GM.
    """

    a: float
    e2: float
    U: float
    gamma_e: float
    k: float
    m: float


def _earth(model: Model, p: np.ndarray) -> FlightEarth:
    value = {i.name: float(v) for i, v in zip(model.parameters, p, strict=True)}
    return FlightEarth(value["a"], value["e2"], value["U"], value["gamma_e"], value["gravity_k"],
                  value["gravity_m"])


def euler_quaternion(roll, pitch, heading) -> np.ndarray:
    """Quaternion body → NED (scalar first) of Z-Y-X Euler angles, shape (4, ...)."""
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp_ = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(heading / 2), np.sin(heading / 2)
    return np.array([cr * cp * cy + sr * sp_ * sy, sr * cp * cy - cr * sp_ * sy,
                     cr * sp_ * cy + sr * cp * sy, cr * cp * sy - sr * sp_ * cy])


def euler_matrix(roll, pitch, heading) -> np.ndarray:
    """C_b^n of Z-Y-X Euler angles, shape (3, 3, ...)."""
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp_ = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(heading), np.sin(heading)
    return np.array([
        [cp * cy, sr * sp_ * cy - cr * sy, cr * sp_ * cy + sr * sy],
        [cp * sy, sr * sp_ * sy + cr * cy, cr * sp_ * sy - sr * cy],
        [-sp_, sr * cp, cr * cp]])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _course_rate(earth: FlightEarth, lat, h, vE, r):
    _, R_E = radii_of_curvature(lat, earth.a, earth.e2)
    return vE * np.tan(lat) / (R_E + h) + r


def _file_course(earth: FlightEarth, commands: tuple[np.ndarray, ...], lat: np.ndarray,
                 h: np.ndarray) -> tuple[np.ndarray, ...]:
    """Ground speed V, its rate, course ψ = atan2(v_E, v_N), its rate, and the turn rate
    on top of the geodesic ``r = ψ̇ − v_E tan φ / (R_E + h)`` and its rate (rad/s²) of a
    geographic flight from its ``commands`` at some times (:class:`FileFlightCommands`)
    and its latitude (rad) and height (m) there, all analytic from the velocity and its
    first and second rates."""
    vN, vE, vD, dvN, dvE, _dvD, ddvN, ddvE = commands
    V2 = vN**2 + vE**2
    V = np.sqrt(V2)
    dV = (vN * dvN + vE * dvE) / V
    psi = np.arctan2(vE, vN)
    dpsi = (vN * dvE - vE * dvN) / V2
    ddpsi = (vN * ddvE - vE * ddvN) / V2 - 2.0 * dpsi * dV / V
    # the geodesic's course rate g = v_E tan φ / (R_E + h) and its rate along the flight
    R_N, R_E = radii_of_curvature(lat, earth.a, earth.e2)
    sin, cos, tan = np.sin(lat), np.cos(lat), np.tan(lat)
    dlat = vN / (R_N + h)
    dR_E = earth.a * earth.e2 * sin * cos / (1.0 - earth.e2 * sin**2) ** 1.5 * dlat
    geodesic = vE * tan / (R_E + h)
    dgeodesic = ((dvE * tan + vE * dlat / cos**2) / (R_E + h)
                 - geodesic * (dR_E - vD) / (R_E + h))
    return V, dV, psi, dpsi, dpsi - geodesic, ddpsi - dgeodesic


class _SampledCommands:
    """A flight's commands for the position integrator: evaluated in vectorised blocks
    (samples 1/16 s apart) and interpolated by cubic Hermite polynomials from the values
    and their rates (a 15-min manoeuvre then matches the ideal-work equations to 1e-8 m/s
    and 2e-8 m), so the scalar calls of the adaptive integrator stay cheap however many
    legs a flight has.

    The piece of a call is SciPy's :class:`~scipy.interpolate.CubicHermiteSpline` of the
    block, built and evaluated with SciPy's arithmetic (its coefficients from the two
    samples around ``t``; the interval ``x[i] <= t < x[i + 1]``, ``s = t − x[i]`` and the
    power-basis terms summed from the constant one up) on Python floats, and only for the
    interval asked: the same bits at a fraction of the cost (a day-long flight asks about
    70 of each block's 4096 intervals).

    Parameters
    ----------
    flight : Flight
    t_end : float, optional
        Last time asked, s: no block reaches more than one interval beyond it (the
        commands are pointwise functions of time, so a block's length changes no bit).
    """

    SPACING = 0.0625
    BLOCK = 4096
    """Intervals of a full block (256 s): one vectorised call of the flight's commands."""
    KEPT = 2
    """Blocks held (the integrator only moves forward)."""

    def __init__(self, flight: Flight, t_end: float = np.inf):
        self.flight = flight
        self.last_knot = (int(np.ceil(t_end / self.SPACING)) if np.isfinite(t_end)
                          else None)
        self.blocks: dict[int, tuple[float, int, np.ndarray]] = {}

    def _block(self, k: int) -> tuple[float, int, np.ndarray]:
        """Block k: its first knot (s), its last interval and the samples at its knots,
        shape (knots, 6): V, r, v_D and their rates."""
        first = k * self.BLOCK
        count = self.BLOCK
        if self.last_knot is not None:
            count = max(1, min(count, self.last_knot - first))
        grid = first * self.SPACING + self.SPACING * np.arange(count + 1)
        V, dV, r, dr, vD, dvD = self.flight.commands(grid)
        samples = np.stack([V, r, vD, dV, dr, dvD], axis=1).astype(float)
        if not np.all(np.isfinite(samples)):
            raise DomainError(f"the flight's commands are not finite between t = {grid[0]:g}"
                              f" and {grid[-1]:g} s")
        if len(self.blocks) >= self.KEPT:
            del self.blocks[next(iter(self.blocks))]
        self.blocks[k] = (float(grid[0]), count - 1, samples)
        return self.blocks[k]

    def __call__(self, t: float) -> tuple[float, float, float]:
        """(V, r, v_D) at time t."""
        t = float(t)
        k = int(t // (self.SPACING * self.BLOCK))
        block = self.blocks.get(k)
        x0, last, samples = block if block is not None else self._block(k)
        # the knots x0 + i/16 are exact, so this is SciPy's interval x[i] <= t < x[i + 1]
        # (the last one beyond) and s = t − x[i] exactly; h = 1/16
        i = min(max(int((t - x0) / self.SPACING), 0), last)
        h = self.SPACING
        s = t - (x0 + i * h)
        s2 = s * s
        s3 = s2 * s
        y0, r0, v0, dy0, dr0, dv0, y1, r1, v1, dy1, dr1, dv1 = samples[i:i + 2].ravel().tolist()
        # SciPy's piece from (y0, dy0) to (y1, dy1): slope = (y1 − y0)/h,
        # c = (dy0 + dy1 − 2 slope)/h, y0 + dy0 s + ((slope − dy0)/h − c) s² + c/h s³
        slope = (y1 - y0) / h
        c = (dy0 + dy1 - 2 * slope) / h
        V = y0 + dy0 * s + ((slope - dy0) / h - c) * s2 + c / h * s3
        slope = (r1 - r0) / h
        c = (dr0 + dr1 - 2 * slope) / h
        r = r0 + dr0 * s + ((slope - dr0) / h - c) * s2 + c / h * s3
        slope = (v1 - v0) / h
        c = (dv0 + dv1 - 2 * slope) / h
        return V, r, v0 + dv0 * s + ((slope - dv0) / h - c) * s2 + c / h * s3


def _position_rhs(flight: Flight, earth: FlightEarth, t_end: float = np.inf):
    """``rhs(t, y)`` of latitude, longitude, height and course on Python floats (the
    arithmetic of :func:`_course_rate` and
    :func:`~ins_errors.models.earth.radii_of_curvature`, with the C library's sin, cos,
    tan and sqrt)."""
    commands = _SampledCommands(flight, t_end)
    a, e2 = earth.a, earth.e2
    sin, cos, tan, sqrt = math.sin, math.cos, math.tan, math.sqrt
    array = np.array

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        lat, _lon, h, psi = y.tolist()
        V, r, vD = commands(t)
        s = sin(lat)
        w2 = 1 - e2 * (s * s)
        w = sqrt(w2)
        R_N, R_E = a * (1 - e2) / (w2 * w), a / w
        vN, vE = V * cos(psi), V * sin(psi)
        return array([vN / (R_N + h), vE / ((R_E + h) * cos(lat)), -vD,
                      vE * tan(lat) / (R_E + h) + r])

    return rhs


def rigid_body_signals(flight: Flight, earth: FlightEarth, t: np.ndarray, y: np.ndarray,
             navigation: bool = False):
    """True state (10, T), inputs (7, T) and Euler angles (3, T) at times t.

    With ``navigation``, also the navigation quantities (9, T) latitude, longitude,
    height, v_N, v_E, v_D, roll, pitch, heading and their time rates (9, T), the exact
    kinematics the signals are made of (for the flights of other models:
    :mod:`ins_errors.numeric.model_flight`).
    """
    lat, lon, h, psi = y
    if flight.geographic:
        lat, lon, h = y[:3]
        commands = flight.commands(t)
        V, dV, psi, dpsi, r, dr = _file_course(earth, commands, lat, h)
        vN, vE, vD, dvN, dvE, dvD, *_ = commands
        dv = np.array([dvN, dvE, dvD])
    else:
        V, dV, r, dr, vD, dvD = flight.commands(t)
        vN, vE = V * np.cos(psi), V * np.sin(psi)
        dpsi = _course_rate(earth, lat, h, vE, r)
        dv = np.array([dV * np.cos(psi) - vE * dpsi, dV * np.sin(psi) + vN * dpsi, dvD])
    v = np.array([vN, vE, vD])
    if flight.static:
        roll, pitch = np.full(t.shape, flight.roll), np.full(t.shape, flight.pitch)
        droll = dpitch = np.zeros(t.shape)
    else:
        bank = V * r / BANK_GRAVITY
        roll = np.arctan(bank)
        droll = (dV * r + V * dr) / BANK_GRAVITY / (1 + bank**2)
        pitch = np.arctan2(-vD, V)
        dpitch = (-dvD * V + vD * dV) / (V**2 + vD**2)
    heading = psi
    R_N, R_E = radii_of_curvature(lat, earth.a, earth.e2)
    w_ie = np.array([earth.U * np.cos(lat), np.zeros(t.shape), -earth.U * np.sin(lat)])
    w_en = np.array([vE / (R_E + h), -vN / (R_N + h), -vE * np.tan(lat) / (R_E + h)])
    C = euler_matrix(roll, pitch, heading)  # C_b^n
    # body rate relative to NED from the Euler-angle rates
    cr, sr, cp, sp_ = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch)
    w_nb = np.array([droll - dpsi * sp_, dpitch * cr + dpsi * sr * cp,
                     -dpitch * sr + dpsi * cr * cp])
    w_in = w_ie + w_en
    w_ib = w_nb + np.einsum("ji...,j...->i...", C, w_in)
    gamma = normal_gravity(lat, h, earth.a, earth.e2, earth.gamma_e, earth.k, earth.m)
    f_n = dv + _cross(2 * w_ie + w_en, v) - np.array([np.zeros(t.shape), np.zeros(t.shape),
                                                      gamma])
    f_b = np.einsum("ji...,j...->i...", C, f_n)
    state = np.vstack([euler_quaternion(roll, pitch, heading), v, lat, lon, h])
    inputs = np.vstack([w_ib, f_b, h])
    euler = np.array([roll, pitch, heading])
    if not navigation:
        return state, inputs, euler
    nav = np.vstack([lat, lon, h, v, euler])
    rates = np.vstack([vN / (R_N + h), vE / ((R_E + h) * np.cos(lat)), -vD, dv, droll, dpitch,
                       dpsi])
    return state, inputs, euler, nav, rates


RATE_CHECKS = 4
"""Points per interval between two samples of a motion file (the sample and three more,
a quarter of the interval apart) where :func:`file_rates` evaluates the body rate and
specific force."""

NOISE_FLOOR = math.radians(0.1)
"""Smallest typical (median) sample-to-sample part of a motion file's body rate, rad/s
(0.1°/s), that :func:`file_rates` calls noise worth a note: below it the rotation the
noise feeds the gyros is under a thirtieth of a standard-rate turn (3°/s), harmless to
the error analysis however noisy the file."""


def smoothed_samples(values: np.ndarray) -> np.ndarray:
    """The samples lightly smoothed by the binomial filter ``(1, 2, 1) / 4`` (the first
    and last kept), shape as ``values``.

    On evenly spaced samples its gain at frequency ``f`` is ``cos²(π f Δ)`` (Δ the
    sample interval): above 0.9 for motion of ten samples per period or more, zero at the
    Nyquist frequency, where the noise of a differentiated log lives.
    """
    out = np.array(values, dtype=float)
    out[1:-1] = 0.25 * (out[:-2] + 2.0 * out[1:-1] + out[2:])
    return out


@dataclass(frozen=True)
class FileRates:
    """The body rate and specific force a motion file implies along a run
    (:func:`file_rates`).

    Attributes
    ----------
    peak_rate, peak_rate_time : float
        Largest body rate ``|ω_ib^b|`` (rad/s) and its time (s).
    peak_force, peak_force_time : float
        Largest specific force ``|f^b|`` (m/s²) and its time (s).
    noise : float
        Median over the run of ``|ω − ω_s|``, rad/s: the body rate's sample-to-sample
        part, ``ω_s`` being the body rate of the file with its velocities and height
        lightly smoothed (:func:`smoothed_samples`).
    motion : float
        Median over the run of ``|ω_s|``, rad/s: the part the samples resolve.
    """

    peak_rate: float
    peak_rate_time: float
    peak_force: float
    peak_force_time: float
    noise: float
    motion: float

    @property
    def noisy(self) -> bool:
        """True when the body rate is mostly noise: its typical sample-to-sample part
        exceeds both its typical resolved part and :data:`NOISE_FLOOR`."""
        return self.noise > max(self.motion, NOISE_FLOOR)


def file_rates(flight: Flight, earth: FlightEarth, t_end: float) -> FileRates:
    """Measure the body rate and specific force a motion file's flight implies over
    ``[0, t_end]`` (s), and how much of the rate is noise.

    The flight's attitude follows its velocity (heading = course, pitch = flight-path
    angle, roll = coordinated bank), so the body rate comes from the velocity splines'
    second derivatives and the specific force from their first: noise on the logged
    velocities, which a cubic spline passes through exactly, is differentiated twice.
    Both are evaluated by :func:`rigid_body_signals` at the samples within the run and
    :data:`RATE_CHECKS` − 1 points between each two (and at ``t_end``), the latitude
    integrated from v_N by the trapezoidal rule on those points (the body rate's
    transport part, v/R, is then exact to far below 1e-9 rad/s), once for the file and
    once for the file with its velocities and height smoothed by
    :func:`smoothed_samples`.

    Parameters
    ----------
    flight : Flight
        A ``geographic`` flight (:func:`flight_from_profile` of a motion file).
    earth : FlightEarth
    t_end : float
        End of the run, s.

    Returns
    -------
    FileRates
    """
    from dataclasses import replace

    from scipy.interpolate import CubicSpline

    commands = flight.commands
    x = np.asarray(commands.splines[0].x)
    smooth = replace(flight, commands=FileFlightCommands(
        tuple(CubicSpline(x, smoothed_samples(s(x))) for s in commands.splines),
        commands.start, commands.end, commands.source))
    knots = np.concatenate([x[x < t_end], [t_end]])
    fractions = np.arange(RATE_CHECKS) / RATE_CHECKS
    noise, motion = [], []
    peak = [-1.0, 0.0, -1.0, 0.0]  # rate and time, force and time
    lat0, lon0 = flight.latitude, flight.longitude
    for first in range(0, knots.size - 1, 65536):  # in pieces: bounded memory
        part = knots[first:first + 65537]
        t = (part[:-1, None] + np.diff(part)[:, None] * fractions).ravel()
        if first + 65536 >= knots.size - 1:
            t = np.append(t, t_end)
        h = commands.splines[2](t)
        vN = commands.splines[0](t)
        R_N, _ = radii_of_curvature(lat0, earth.a, earth.e2)
        rate = vN / (R_N + h)
        lat = lat0 + np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1])
                                                        * np.diff(t))])
        y = np.array([lat, np.full(t.shape, lon0), h, np.zeros(t.shape)])
        _, inputs, _ = rigid_body_signals(flight, earth, t, y)
        with np.errstate(all="ignore"):  # a smoothed speed near zero: left out
            _, smoothed, _ = rigid_body_signals(smooth, earth, t, y)
        w, f = np.linalg.norm(inputs[:3], axis=0), np.linalg.norm(inputs[3:6], axis=0)
        k, j = int(np.argmax(w)), int(np.argmax(f))
        if w[k] > peak[0]:
            peak[:2] = float(w[k]), float(t[k])
        if f[j] > peak[2]:
            peak[2:] = float(f[j]), float(t[j])
        ok = np.all(np.isfinite(smoothed[:3]), axis=0)
        noise.append(np.linalg.norm(inputs[:3, ok] - smoothed[:3, ok], axis=0)
                     .astype(np.float32))
        motion.append(np.linalg.norm(smoothed[:3, ok], axis=0).astype(np.float32))
        lat0 = float(lat[-1])
    noise_all, motion_all = np.concatenate(noise), np.concatenate(motion)
    return FileRates(peak[0], peak[1], peak[2], peak[3],
                     float(np.median(noise_all)) if noise_all.size else 0.0,
                     float(np.median(motion_all)) if motion_all.size else 0.0)


def file_note(flight: Flight, earth: FlightEarth, t_end: float) -> str | None:
    """One line when a motion file's body rate over
    ``[0, t_end]`` (s) is mostly noise (:attr:`FileRates.noisy`), naming the file, the
    peak body rate and specific force with their times, and the remedy; None otherwise
    (and for any other flight)."""
    if not flight.geographic or flight.static:
        return None
    rates = file_rates(flight, earth, t_end)
    if not rates.noisy:
        return None
    return (f"{flight.commands.source} implies body rates of up to "
            f"{np.degrees(rates.peak_rate):.4g}°/s (t = {rates.peak_rate_time:.6g} s) and "
            f"specific forces of up to {rates.peak_force:.4g} m/s² "
            f"(t = {rates.peak_force_time:.6g} s), mostly noise (typical sample-to-sample "
            f"part {np.degrees(rates.noise):.3g}°/s against {np.degrees(rates.motion):.3g}°/s"
            f" resolved): the attitude is derived from the velocities' first and second "
            f"derivatives, so smooth or decimate the log's velocities (and height) before "
            f"giving it")


_NOTES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
"""The :func:`file_note` of each flight's commands, per run length: a flight flown again
(the integration error's reruns at other steps) is measured and noted once."""


def _noted_once(flight: Flight, earth: FlightEarth, t_end: float) -> str | None:
    """:func:`file_note`, given as a ``RuntimeWarning`` (``ins-errors: note: ...``) the
    first time a flight of these commands is flown over ``[0, t_end]`` only."""
    if not flight.geographic or flight.static:
        return None
    notes = _NOTES.setdefault(flight.commands, {})
    key = (float(t_end), earth)
    if key not in notes:
        notes[key] = file_note(flight, earth, t_end)
        if notes[key] is not None:  # said, not acted on: the file is flown as given
            warnings.warn(f"ins-errors: note: {notes[key]}", RuntimeWarning, stacklevel=3)
    return notes[key]


def trajectory(model: Model, flight: Flight, duration: float, tau: float,
               p: np.ndarray | None = None, truth: str = "auto",
               stream: bool | None = None) -> Trajectory:
    """Sample a flight's true state and IMU signals on the grid ``t = k τ``.

    Parameters
    ----------
    model : Model
        The loaded ``strapdown_ned`` model, or any model fed body rates and specific
        forces (inputs the kinematic motions cannot set, e.g. a strapdown model file):
        its states and inputs follow the flight by its own equations
        (:mod:`ins_errors.numeric.model_flight`), the flight planned on its own Earth.
    flight : Flight
        See :func:`static`, :func:`great_circle`, :func:`manoeuvre`, and
        :func:`flight_from_profile` (a motion file: refused here if the run leaves the
        file or its ground speed falls below :data:`MIN_FILE_SPEED`).
    duration, tau : float
        Length of the run and step, s (100 Hz: ``tau=0.01``); the duration must be a
        whole number of steps.
    p : numpy.ndarray, optional
        Model parameters (default: the model's, WGS-84).
    truth : {"auto", "interpolated", "fine"}
        How a moving flight's signals are computed (:mod:`ins_errors.numeric.strapdown_stream`).
        ``"fine"``: the exact kinematics at every step and midpoint of the position
        integrated by DOP853 (a motion file's by
        :class:`~ins_errors.numeric.strapdown_stream.FilePosition`); ``"interpolated"``:
        at the nodes of coarse intervals of about 10 s ending at the flight's leg joins
        (a file's samples), interpolated to the steps by
        polynomials of degree 7 (hundreds of times cheaper per step); ``"auto"``
        (default): interpolated when the flight's breaks are known and the intervals
        hold at least :data:`~ins_errors.numeric.interpolated_truth.MIN_STEPS` steps
        (on average, counting the breaks), else fine.
    stream : bool, optional
        Generate a moving flight chunk by chunk whenever it is run instead of storing it;
        default: stream when the stored samples would exceed
        :data:`~ins_errors.numeric.trajectories.STREAM_BYTES`. A streamed flight that
        reaches a pole is reported when it is run.

    Returns
    -------
    Trajectory
        Truth (n, N + 1), inputs at the steps (nu, N + 1) and midpoints (nu, N), stored or
        streamed (strapdown_ned: n = 10, nu = 7); a static base gives one constant column.
        A moving flight's has ``notes``, a list of one-line notices about the motion:
        a motion file whose body rate is mostly noise (:func:`file_note`, also given as
        a ``RuntimeWarning`` ``ins-errors: note: ...``; the file is flown as given).

    Raises
    ------
    MotionError, StepError, DomainError
        Wrong model, bad grid, or a flight that reaches a pole or pitch ±90°.
    """
    from ins_errors.numeric import interpolated_truth as it
    from ins_errors.numeric import strapdown_stream as ss
    from ins_errors.numeric.trajectories import STREAM_BYTES, TRUTHS

    model, p = run_arguments(model, flight, Flight, duration, p)
    if truth not in TRUTHS:
        from ins_errors.errors import unknown_name

        raise unknown_name("truth", truth, TRUTHS)
    n_steps = step_count(duration, tau)
    if flight.geographic:
        flight.commands.check_run(n_steps * float(tau))
    y0 = np.array([flight.latitude, flight.longitude, flight.height, flight.course])
    adapter = None
    if model.name == MODEL:
        earth = _earth(model, p)
    else:
        from ins_errors.numeric.model_flight import FlightAdapter, flight_earth
        from ins_errors.numeric.trajectories import unset_inputs

        if not unset_inputs(model):
            raise MotionError(f"strapdown flights feed models fed body rates and specific "
                              f"forces; {model.name!r} follows the kinematic motions "
                              "(ins_errors.numeric.trajectories.trajectory)")
        earth = flight_earth(model, p)
        *_, nav0, rate0 = rigid_body_signals(flight, earth, np.zeros(1), y0[:, None],
                                             navigation=True)
        adapter = FlightAdapter(model, p, (nav0[:, 0], rate0[:, 0]))
    if flight.static:
        state, inputs, euler = ss.flight_signals(flight, earth, np.zeros(1), y0[:, None],
                                                 adapter)
        c0 = (_initial_conditions(state[:, 0], euler[:, 0]) if adapter is None
              else adapter.conditions(nav0[:, 0]))
        return Trajectory(model.key, float(tau), n_steps, state, inputs, inputs.copy(), p,
                          c0, True, flight.description)
    note = _noted_once(flight, earth, n_steps * float(tau))
    truth = it.chosen_truth(truth, flight.breaks, n_steps, float(tau),
                            "a flight (a great circle, a manoeuvre or a motion file)")
    position = None
    if truth == "fine" or (adapter is not None and adapter.carried):
        position = (ss.FilePosition(flight, earth, n_steps * tau) if flight.geographic
                    else _position_solution(flight, earth, n_steps * tau, tau).sol)
    if adapter is not None:  # parameters that start a path-dependent state move
        adapter.follow(flight, earth, n_steps * float(tau), position)
    if truth == "interpolated":
        source = ss.InterpolatedFlight(model, flight, earth, float(tau), n_steps, p, adapter)
    else:
        source = ss.FullRateTruth(flight, earth, float(tau), n_steps, position, adapter)
    x0, u0, euler0 = source.start_with_euler()
    c0 = (_initial_conditions(x0, euler0) if adapter is None
          else adapter.conditions(nav0[:, 0]))
    traj = Trajectory.streamed(model.key, tau, n_steps, source, x0, u0, p, c0,
                               flight.description)
    traj.notes = [] if note is None else [note]
    if stream is None:
        stream = 8 * (n_steps + 1) * (len(x0) + 2 * len(u0)) > STREAM_BYTES
    if not stream:  # (n_steps >= 1: a zero duration was refused above)
        traj._store()
    return traj


POSITION_STEP_FACTOR = 50
"""The position integration is refused once its right-hand side has been evaluated this
many times the count the flight itself sets (12 per DOP853 step, one step per
:data:`POSITION_BUDGET_STEP` of its duration plus 10 and one per break between legs),
whatever the sample step: a flight of any planet-sized Earth needs about 1 to 2 times
that count; a sphere of metres or a flight that nears a pole would make the adaptive
steps shrink without end."""

POSITION_BUDGET_STEP = 60.0
"""Step (s) by which the position integration's evaluation budget counts a flight's
duration (a quarter of the flight if shorter). A coarse sample step lengthens DOP853's
maximum step but not the steps its tolerance needs (about 25 s on a day's cruise), so
the budget must not follow the sample step."""


class _TooManyStepsError(Exception):
    """Raised inside the position integration's right-hand side to stop it."""


def position_budget(flight: Flight, t_end: float, tau: float) -> int:
    """Right-hand side evaluations the position integration of ``flight`` over
    ``[0, t_end]`` (s) may spend (:data:`POSITION_STEP_FACTOR`).

    The count follows the flight (its duration in :data:`POSITION_BUDGET_STEP` steps
    and its breaks between legs), not the sample step ``tau`` (s), which is used only
    for a flight shorter than it.
    """
    step = min(POSITION_BUDGET_STEP, t_end / 4 or tau)
    breaks = len(flight.breaks or ())
    return int(POSITION_STEP_FACTOR * 12 * (t_end / step + 10 + breaks))


def _position_solution(flight: Flight, earth: FlightEarth, t_end: float, tau: float):
    """Latitude, longitude, height and course over ``[0, t_end]`` by DOP853 (rtol 1e-13)
    with dense output (``.sol``).

    Raises
    ------
    DomainError
        The integration fails, or its step count explodes (more than
        :data:`POSITION_STEP_FACTOR` times the steps the flight sets,
        :func:`position_budget`).
    """
    from scipy.integrate import solve_ivp

    y0 = np.array([flight.latitude, flight.longitude, flight.height, flight.course])
    max_step = max(tau, min(60.0, t_end / 4 or tau))
    limit = position_budget(flight, t_end, tau)
    inner, calls = _position_rhs(flight, earth, t_end), [0]

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        calls[0] += 1
        if calls[0] > limit:
            raise _TooManyStepsError(t)
        return inner(t, y)

    try:
        solution = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13,
                             atol=1e-15 * np.array([1, 1, 1e7, 1]), dense_output=True,
                             max_step=max_step)
    except _TooManyStepsError as stop:
        raise DomainError(
            f"the true flight could not be integrated: its steps shrink without end near "
            f"t = {stop.args[0]:.6g} s (over {limit} evaluations; an Earth radius of "
            f"{earth.a:g} m is not planet-sized, or the flight nears a pole)") from None
    if not solution.success:
        raise DomainError(f"the true flight could not be integrated: {solution.message}")
    return solution


def _initial_conditions(state: np.ndarray, euler: np.ndarray) -> np.ndarray:
    """c = (latitude, longitude, height, v_N0, v_E0, v_D0, roll, pitch, heading)."""
    return np.array([state[7], state[8], state[9], state[4], state[5], state[6], *euler])
