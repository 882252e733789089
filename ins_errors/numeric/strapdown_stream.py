"""The true IMU signals of a strapdown flight, generated chunk by chunk (MotionSources).

Two generators feed :func:`ins_errors.numeric.strapdown_truth.trajectory`; neither stores
more than a chunk of step-sized samples, so a day or a week at 100 Hz needs memory only
for what a run records.

* :class:`FullRateTruth` (``truth="fine"``): the position and course integrated once by
  DOP853 at a relative tolerance of 1e-13 (dense output), the exact kinematics evaluated
  at every step time and midpoint (about 1 µs per sample). The numbers are those the
  trajectory stored whole before it was streamed, bit for bit. A motion file's flight
  (whose velocity's third derivative jumps at every sample, which adaptive steps would
  cross) takes its position from :class:`FilePosition` instead: the compiled node
  integration below on intervals ending at the samples, computed block by block as the
  run reaches them.
* :class:`InterpolatedFlight` (``truth="interpolated"``, the default at small steps): the
  coarse intervals of :mod:`ins_errors.numeric.interpolated_truth` (about 10 s, ending at
  every leg join of the flight, halved where the states or inputs change faster). In
  every interval the position and course are the degree-7 polynomials through the
  Chebyshev–Lobatto nodes that solve the integral form of their equations (Picard
  iteration with the exact integrals of the node polynomials, compiled; Clenshaw–Curtis
  accuracy, the same as the interpolation's), the exact kinematics are evaluated at the
  nodes only, and the states and inputs at the run's steps are the polynomials through
  the node values (a few nanoseconds per step).
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import lru_cache

import casadi as ca
import numpy as np

from ins_errors.errors import DomainError
from ins_errors.models.earth import radii_of_curvature
from ins_errors.numeric import interpolated_truth as it
from ins_errors.numeric.integrators import DenseCall, native_functions
from ins_errors.numeric.model import Model
from ins_errors.numeric.strapdown_truth import Flight, FlightEarth, rigid_body_signals
from ins_errors.numeric.trajectories import TruthChunk

PICARD = 6
"""Picard iterations of an interval's position and course. One iteration multiplies the
error by about L T (T the interval, L the largest rate of the equations' right-hand side
with respect to the position and course: 4e-4 for 10 s at 50° latitude, 0.05 at 85°),
divided by the iteration count's factorial: 6 reach rounding below 85°."""

PICARD_CHANGE = 1e-13
"""An interval is also halved when the last Picard iteration still changed its position
or course by more than this (rad): near a pole, where the iteration converges slowly."""

_COMMANDS = (0, 2, 4)
"""The commands the position and course equations read: V, r, v_D (of the six)."""

_FILE_COMMANDS = (0, 1, 2)
"""… and of a geographic flight (a motion file): v_N, v_E, v_D (of the eight)."""

ROW_COLUMNS = 1 + 3 * (it.DEGREE + 1)
"""One interval row: its length, then (V, r, v_D) (a geographic flight: (v_N, v_E, v_D))
at its nodes."""


def integration_matrix() -> np.ndarray:
    """``S[i, j] = ∫_0^{x_i} ℓ_j(s) ds`` for the Chebyshev–Lobatto nodes ``x`` on [0, 1]
    and their Lagrange polynomials ``ℓ_j``, shape (DEGREE + 1, DEGREE + 1): the
    integrals from 0 to every node of the polynomial through node values ``f`` are
    ``S @ f``."""
    from numpy.polynomial import chebyshev as cheb

    u = 2.0 * it._NODES - 1.0  # on [-1, 1]
    coefficients = cheb.chebfit(u, np.eye(it.DEGREE + 1), it.DEGREE)  # one column per ℓ_j
    integrals = cheb.chebint(coefficients, lbnd=-1.0)
    return 0.5 * cheb.chebval(u, integrals).T  # (x = (u + 1) / 2)


def _check_signals(state: np.ndarray, inputs: np.ndarray, times: np.ndarray) -> None:
    """Raise at the first time where the flight is not finite or reaches a pole."""
    bad = ~(np.all(np.isfinite(state), axis=0) & np.all(np.isfinite(inputs), axis=0))
    # at a pole, or past it: a geodesic through a pole carries φ beyond ±90° (its course
    # is undefined there), so the steps may jump over the pole without coming near it
    bad |= (np.cos(state[7]) ** 2 <= 1e-12) | (np.abs(state[7]) >= np.pi / 2)
    if bad.any():
        raise DomainError(f"the true flight reaches a pole or is not finite at "
                          f"t = {times[int(np.argmax(bad))]:.6g} s")


def flight_signals(flight: Flight, earth: FlightEarth, t: np.ndarray, y: np.ndarray,
                   adapter=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """True states, inputs and Euler angles (3, T) at times ``t`` (T,) of position and
    course ``y`` (4, T), checked: ``strapdown_ned``'s (10, T) and (7, T), or with an
    ``adapter`` (:class:`~ins_errors.numeric.model_flight.FlightAdapter`) its model's."""
    if adapter is None:
        state, inputs, euler = rigid_body_signals(flight, earth, t, y)
        _check_signals(state, inputs, t)
        return state, inputs, euler
    state, inputs, euler, nav, rates = rigid_body_signals(flight, earth, t, y, navigation=True)
    _check_signals(state, inputs, t)
    x, u = adapter(nav, rates, t)
    return x, u, euler


class FullRateTruth:
    """The kinematics at every step and midpoint of a flight integrated by DOP853.

    Parameters
    ----------
    flight : Flight
    earth : FlightEarth
        Ellipsoid, Earth rate and normal gravity of the model's parameters.
    tau : float
        Step, s.
    n_steps : int
        Steps N.
    solution : scipy.integrate.OdeSolution
        Dense output of (latitude, longitude, height, course) over ``[0, N τ]``.
    adapter : FlightAdapter, optional
        Turns the flight into another model's states and inputs
        (:mod:`ins_errors.numeric.model_flight`); None: ``strapdown_ned``'s.
    """

    kind = "fine"
    """How this source computes the truth (:attr:`Trajectory.truth_kind`)."""

    def __init__(self, flight: Flight, earth: FlightEarth, tau: float, n_steps: int, solution,
                 adapter=None):
        self.flight, self.earth, self.tau, self.n_steps = flight, earth, float(tau), n_steps
        self.solution = solution
        self.adapter = adapter

    def start(self) -> tuple[np.ndarray, np.ndarray]:
        """True state (10,) and inputs (7,) at t = 0."""
        state, inputs, _ = self.start_with_euler()
        return state, inputs

    def start_with_euler(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """True state (10,), inputs (7,) and Euler angles (3,) at t = 0."""
        t = np.zeros(1)
        state, inputs, euler = flight_signals(self.flight, self.earth, t, self.solution(t),
                                              self.adapter)
        return state[:, 0], inputs[:, 0], euler[:, 0]

    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """Chunks of at most ``size`` steps (see
        :class:`~ins_errors.numeric.trajectories.MotionSource`)."""
        for start in range(0, self.n_steps, size):
            stop = min(start + size, self.n_steps)
            t = np.arange(start, stop + 1) * self.tau
            state, inputs, _ = flight_signals(self.flight, self.earth, t, self.solution(t),
                                              self.adapter)
            tm = (np.arange(start, stop) + 0.5) * self.tau
            if self.adapter is None:
                _, midpoints, _ = rigid_body_signals(self.flight, self.earth, tm, self.solution(tm))
            else:
                _, midpoints, _ = flight_signals(self.flight, self.earth, tm,
                                                 self.solution(tm), self.adapter)
            yield TruthChunk(start, state, inputs, midpoints)


class FilePosition(it.NodePath):
    """Latitude, longitude, height and course of a geographic flight (a motion file) at
    any times, for :class:`FullRateTruth`.

    The run is cut into intervals ending at the file's samples (and at most
    :data:`~ins_errors.numeric.interpolated_truth.INTERVAL` long); on each the position
    is the degree-7 polynomial through the Chebyshev–Lobatto nodes solved by the compiled
    Picard integration of :class:`InterpolatedFlight` (between two samples the velocity
    is a cubic, so the polynomials resolve the position to rounding: 1e-8 m over 10 min
    of a file sampled every second, where DOP853's steps across the samples lost 1e-7 m,
    and a noisy file's shrank without end), evaluated at the asked times by barycentric
    interpolation. The height is the file's spline itself. The nodes are computed
    :attr:`BLOCK` intervals at a time when the run reaches them, two blocks held and the
    start of every block kept (4 numbers each: the blocks and the rereads of
    :class:`~ins_errors.numeric.interpolated_truth.NodePath`).

    Parameters
    ----------
    flight : Flight
        A geographic flight.
    earth : FlightEarth
    t_end : float
        End of the run, s.
    """

    BLOCK = 4096
    """Intervals of one block."""

    def __init__(self, flight: Flight, earth: FlightEarth, t_end: float):
        self.flight, self.earth = flight, earth
        super().__init__(np.asarray(flight.commands.splines[0].x), t_end,
                         np.array([flight.latitude, flight.longitude, flight.height,
                                   flight.course]))

    def _nodes(self, first: np.ndarray, start: np.ndarray, length: np.ndarray,
               t: np.ndarray) -> np.ndarray:
        """Node values (J, DEGREE + 1, 4) of the position and course (see
        :meth:`NodePath._nodes <ins_errors.numeric.interpolated_truth.NodePath._nodes>`)."""
        count = start.size
        commands = np.vstack(self.flight.commands(t)[:3])
        rows = np.empty((count, ROW_COLUMNS))
        rows[:, 0] = length
        rows[:, 1:] = commands.T.reshape(count, -1)
        function = _interval_function(self.earth.a, self.earth.e2, True)
        _, out = it.carried_batches(function, first, rows, it.BATCH, 4, 4 * it.DEGREE + 1)
        nodes = np.empty((count, it.DEGREE + 1, 4))
        nodes[:, 1:] = out[:, :-1].reshape(count, it.DEGREE, 4)
        nodes[0, 0] = first
        nodes[1:, 0] = nodes[:-1, -1]
        nodes[:, :, 2] = self.flight.commands.splines[2](t).reshape(count, -1)
        return nodes

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """Latitude, longitude, height and course (4, T) at times ``t`` (T,)."""
        out = super().__call__(t)
        out[2] = self.flight.commands.splines[2](np.asarray(t, dtype=float))  # exact
        return out


@lru_cache(maxsize=16)
def _interval_function(a: float, e2: float, geographic: bool = False) -> DenseCall:
    """Compiled ``(y, rows (J, ROW_COLUMNS)) -> (y at the end of each interval (J, 4),
    [y at its nodes 1..DEGREE, change] (J, 4 DEGREE + 1))`` for y = (latitude, longitude,
    height, course), the intervals chained: :data:`PICARD` iterations of
    ``y(x_i) = y(0) + T Σ_j S_ij f(x_j, y(x_j))`` (:func:`integration_matrix`); ``change``
    is the largest change of the last iteration (rad; the height divided by ``a``).
    ``geographic``: the rows hold the velocity (v_N, v_E, v_D) of a motion file and the
    course stays constant (a geographic flight's course is read from its velocity)."""
    d = it.DEGREE
    y, row = ca.SX.sym("y", 4), ca.SX.sym("row", ROW_COLUMNS)
    S = integration_matrix()
    length = row[0]

    def rhs(z, j):
        lat, h, psi = z[0], z[2], z[3]
        R_N, R_E = radii_of_curvature(lat, a, e2, xp=ca)
        if geographic:
            vN, vE, vD = row[1 + 3 * j], row[2 + 3 * j], row[3 + 3 * j]
            return ca.vertcat(vN / (R_N + h), vE / ((R_E + h) * ca.cos(lat)), -vD, 0.0)
        V, r, vD = row[1 + 3 * j], row[2 + 3 * j], row[3 + 3 * j]
        vN, vE = V * ca.cos(psi), V * ca.sin(psi)
        return ca.vertcat(vN / (R_N + h), vE / ((R_E + h) * ca.cos(lat)), -vD,
                          vE * ca.tan(lat) / (R_E + h) + r)

    f0 = rhs(y, 0)
    nodes = previous = [y] * (d + 1)
    for _ in range(PICARD):
        rates = [f0] + [rhs(nodes[j], j) for j in range(1, d + 1)]
        nodes, previous = [y] + [y + length * sum(float(S[i, j]) * rates[j]
                                                  for j in range(d + 1))
                                 for i in range(1, d + 1)], nodes
    # the last iteration's change (height in radians of the equator)
    scale = ca.DM([1.0, 1.0, 1.0 / a, 1.0])
    steps = [(n - m) * scale for n, m in zip(nodes[1:], previous[1:], strict=True)]
    change = ca.mmax(ca.fabs(ca.vertcat(*steps)))
    out = ca.cse(ca.vertcat(*nodes[1:], change))
    interval = ca.Function("strapdown_interval", [y, row], [out[-5:-1], out])
    return native_functions([interval.mapaccum("strapdown_intervals", it.BATCH)])[0]


class InterpolatedFlight(it.InterpolatedTruth):
    """A strapdown flight on the coarse grid of :mod:`~ins_errors.numeric.interpolated_truth`,
    interpolated to the run's steps (a MotionSource).

    Parameters
    ----------
    model : Model
        The model fed (for the names and units of its states and inputs):
        ``strapdown_ned``, or the model of ``adapter``.
    flight : Flight
        A moving flight whose :attr:`Flight.breaks` are known.
    earth : FlightEarth
    tau : float
        Step, s.
    n_steps : int
        Steps N.
    p : numpy.ndarray
        Model parameters.
    adapter : FlightAdapter, optional
        As for :class:`FullRateTruth`.

    Attributes
    ----------
    error_estimate, worst
        As for :class:`~ins_errors.numeric.interpolated_truth.InterpolatedTruth`.
    """

    def __init__(self, model: Model, flight: Flight, earth: FlightEarth, tau: float, n_steps: int,
                 p: np.ndarray, adapter=None):
        self.flight, self.earth, self.adapter = flight, earth, adapter
        self.tau, self.n_steps, self.p = float(tau), int(n_steps), tuple(float(v) for v in p)
        self.y0 = np.array([flight.latitude, flight.longitude, flight.height, flight.course])
        self.n, self.nu = len(model.states), len(model.inputs)
        self.plan = it.plan(self.n_steps, self.tau, flight.breaks)
        self.error_estimate = np.zeros(self.n + self.nu)
        self.names, self._same_unit = it.named_columns(model)
        self._warned = False
        self.worst = 0.0

    def start(self) -> tuple[np.ndarray, np.ndarray]:
        """True state (n,) and inputs (nu,) at t = 0 (the first column of the first chunk)."""
        state, inputs, _ = self.start_with_euler()
        return state, inputs

    def start_with_euler(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """True state (10,), inputs (7,) and Euler angles (3,) at t = 0."""
        t = np.zeros(1)
        state, inputs, euler = flight_signals(self.flight, self.earth, t, self.y0[:, None],
                                              self.adapter)
        return state[:, 0], inputs[:, 0], euler[:, 0]

    def _rows(self, start: np.ndarray, length: np.ndarray) -> np.ndarray:
        """Interval rows (J, ROW_COLUMNS) of intervals at ``start`` of ``length`` (s)."""
        t = (start[:, None] + length[:, None] * it._NODES[None, :]).ravel()
        commands = np.vstack(self.flight.commands(t))
        bad = ~np.all(np.isfinite(commands), axis=0)
        if bad.any():
            raise DomainError(f"flight commands are NaN or infinite at "
                              f"t = {t[int(np.argmax(bad))]:.6g} s")
        rows = np.empty((len(start), ROW_COLUMNS))
        rows[:, 0] = length
        read = _FILE_COMMANDS if self.flight.geographic else _COMMANDS
        rows[:, 1:] = commands[list(read)].T.reshape(len(start), -1)
        return rows

    def _integrate(self, fn: DenseCall, y: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """Position and course at the nodes 1..DEGREE of every interval from ``y`` at
        the first one's start, shape (J, DEGREE, 4), and the last Picard iteration's
        change of every interval (J,), compiled in batches (the last one padded with
        empty intervals)."""
        d, count = it.DEGREE, rows.shape[0]
        _, ys = it.carried_batches(fn, y, rows, it.BATCH, 4, 4 * d + 1)
        return ys[:, :-1].reshape(count, d, 4), ys[:, -1]

    def _nodes(self, fn: DenseCall, y: np.ndarray, first: np.ndarray, times: np.ndarray,
               steps: np.ndarray, q_first: int,
               q_last: int) -> tuple[it.Plan, np.ndarray, np.ndarray, np.ndarray]:
        """Node values of the intervals between knots ``times`` (a block of the coarse
        plan) integrated from position and course ``y`` (4,) where the states and inputs
        are ``first`` (n + nu,), with every interval halved (at most
        :data:`~ins_errors.numeric.interpolated_truth.MAX_SPLITS` times) whose
        polynomials would not resolve the states and inputs: their last Chebyshev
        coefficient above :data:`~ins_errors.numeric.interpolated_truth.REFINE_RELATIVE`
        of the largest value of that unit over the block, or whose last Picard iteration
        still changed the position or course by more than :data:`PICARD_CHANGE`.

        Returns the block's plan, the nodes (J, DEGREE + 1, n + nu), the magnitudes of
        their last Chebyshev coefficients (J, n + nu) and the position and course at the
        block's end (4,).
        """
        d, n, nu = it.DEGREE, self.n, self.nu
        for depth in range(it.MAX_SPLITS + 1):
            start, length = times[:-1], np.diff(times)
            ys, change = self._integrate(fn, y, self._rows(start, length))
            ys = ys.reshape(-1, 4)
            at = (start[:, None] + length[:, None] * it._NODES[1:]).ravel()
            state, inputs, _ = flight_signals(self.flight, self.earth, at, ys.T, self.adapter)
            nodes = np.empty((len(start), d + 1, n + nu))
            nodes[:, 1:, :n] = state.T.reshape(len(start), d, n)
            nodes[:, 1:, n:] = inputs.T.reshape(len(start), d, nu)
            nodes[0, 0] = first
            nodes[1:, 0] = nodes[:-1, d]
            tail = np.abs(np.einsum("i,jic->jc", it._CHEBYSHEV[-1], nodes))
            if depth == it.MAX_SPLITS:
                break
            largest = np.abs(nodes).max(axis=(0, 1))
            size = np.array([largest[group].max() for group in self._same_unit])
            split = (((tail > it.REFINE_RELATIVE * size).any(axis=1) | (change > PICARD_CHANGE))
                     & (length >= 2.0 * self.tau))
            if not split.any():
                break
            times, steps = it._split(times, steps, split, self.tau)
        plan_ = it._plan_of_knots(times, steps, self.tau, q_first, q_last)
        return plan_, nodes, tail, ys[-1].copy()

    def _blocks(self) -> Iterator[it._Block]:
        fn = _interval_function(self.earth.a, self.earth.e2, self.flight.geographic)
        plan_, d = self.plan, it.DEGREE
        J = len(plan_.start)
        y = self.y0.copy()
        previous = np.concatenate(self.start())  # node 0 of the first interval
        for j0 in range(0, J, it.BATCH):
            j1 = min(j0 + it.BATCH, J)
            sub, nodes, tail, y = self._nodes(fn, y, previous, plan_.times[j0:j1 + 1],
                                              plan_.steps[j0:j1 + 1],
                                              int(plan_.first_half[j0]),
                                              int(plan_.first_half[j1]))
            previous = nodes[-1, d].copy()
            np.maximum(self.error_estimate, tail.max(axis=0), out=self.error_estimate)
            self._warn_if_coarse(tail, nodes, sub.start)
            yield it._Block(sub, 0, len(sub.start), nodes, self.tau)
