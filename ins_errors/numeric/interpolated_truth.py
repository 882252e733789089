"""A fast true motion: the model's truth on a coarse grid, interpolated to the run's steps.

The fine truth (:class:`~ins_errors.numeric.trajectories.ProfileTruth`) integrates the
truth equations with RK4 at half the run's step and evaluates the inputs (a small
least-squares solve) at every half step: about ten model evaluations per 100 Hz step.
The motion itself changes on time scales of seconds to hours, so this module computes
it on a coarse grid instead and interpolates:

* the run is cut into *intervals* of about :data:`INTERVAL` seconds whose ends include
  every break of the profile (:attr:`Profile.breaks`: leg joins, ramp ends, spline
  knots), so that the motion is smooth (analytic) inside every interval; an interval
  whose commands the polynomial would not resolve (hard turns, a fast weave: the last
  Chebyshev coefficient of the commands through its nodes above
  :data:`REFINE_RELATIVE`) is halved, up to :data:`MAX_SPLITS` times;
* in each interval the true state is integrated with RK4 from Chebyshev–Lobatto node to
  node (:data:`DEGREE` steps, compiled, the nodes' inputs evaluated there);
* the true state and the inputs at the run's step times (and midpoints) are the
  polynomials of degree :data:`DEGREE` through the node values (barycentric Lagrange
  form, evaluated as one small matrix product per interval), so nothing step-sized
  except the chunk being handed out is ever stored.

Per 100 Hz step this costs a few nanoseconds instead of about two microseconds. The
interpolation error of every interval is estimated from its last Chebyshev coefficient
(:attr:`InterpolatedTruth.error_estimate`, a warning above :data:`WARN_RELATIVE`); the
tests compare the states, the inputs and the error runs with the fine truth. A chunk's
numbers do not depend on the chunk size: intervals, compiled batches and the matrix
products are fixed by the grid alone.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from ins_errors.errors import DomainError
from ins_errors.numeric.integrators import DenseCall, casadi_step, native_functions
from ins_errors.numeric.model import Model, load_model
from ins_errors.numeric.trajectories import (
    MotionError,
    TruthChunk,
    _kinematics,
    truth_parameters,
)

DEGREE = 7
"""Degree of the interpolating polynomial in every interval (DEGREE + 1 nodes)."""

INTERVAL = 10.0
"""Longest coarse interval, s (shorter next to the profile's breaks)."""

MIN_STEPS = 50
"""The interpolated truth is used only when an interval holds at least this many steps
(below that the fine truth costs about as much and is exact to the scheme)."""

BATCH = 128
"""Intervals integrated per compiled call."""

REFINE_RELATIVE = 1e-10
"""An interval is halved when the last Chebyshev coefficient of a command (speed, height,
their rates) through its nodes exceeds this fraction of the largest command of that unit
over its block of intervals."""

MAX_SPLITS = 5
"""Most times an interval is halved (10 s down to about 0.3 s)."""

_COMMAND_UNITS = ([0, 1, 3, 6], [0, 1, 3, 6], [2], [0, 1, 3, 6], [4, 5, 7], [4, 5, 7],
                  [0, 1, 3, 6], [4, 5, 7])
"""Commands (v1, v2, h, V_zeta and their rates) of the same unit as each command."""

WARN_RELATIVE = 1e-6
"""A warning is given when an interval's estimated interpolation error exceeds this
fraction of the size of the quantities of the same unit over its block of intervals.
The error curves (real minus ideal work, both along the same true motion) are affected
far less than the motion itself: a 120-s turn of a motion file estimated at 4.7e-7
changed them by 1e-11 of their size against the fine truth, a hidden kink estimated at
up to 0.036 by at most 1.5e-3 (a small latitude error over two minutes)."""

TRUTH_FINE_HOW = '--truth fine (truth = "fine" in a scenario\'s [run])'
"""How a user asks for the fine truth, as the warning says it."""

_NODES = 0.5 * (1.0 - np.cos(np.pi * np.arange(DEGREE + 1) / DEGREE))
"""Chebyshev–Lobatto nodes on [0, 1], increasing."""

_WEIGHTS = np.array([(-1.0) ** i * (0.5 if i in (0, DEGREE) else 1.0)
                     for i in range(DEGREE + 1)])
"""Barycentric weights of the Chebyshev–Lobatto nodes."""

_CHEBYSHEV = np.array([[(2.0 / DEGREE) * np.cos(np.pi * k * i / DEGREE)
                        * (0.5 if i in (0, DEGREE) else 1.0) * (0.5 if k in (0, DEGREE) else 1.0)
                        for i in range(DEGREE + 1)] for k in range(DEGREE + 1)])
"""Node values -> Chebyshev coefficients (discrete cosine transform of type I)."""


def lagrange_matrix(theta: np.ndarray) -> np.ndarray:
    """Values at ``theta`` (shape (m,), in [0, 1]) of the Lagrange polynomials of the
    nodes, shape (m, DEGREE + 1): ``values = B @ node_values``."""
    theta = np.asarray(theta, dtype=float)
    diff = theta[:, None] - _NODES[None, :]
    exact = diff == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = _WEIGHTS / diff
        B = terms / terms.sum(axis=1, keepdims=True)
    hit = exact.any(axis=1)
    B[hit] = exact[hit].astype(float)
    return B


# --------------------------------------------------------------------------------------
# The compiled node-to-node integration
# --------------------------------------------------------------------------------------
SUBSTEPS = 1
"""RK4 steps from one node to the next."""

GAP_COLUMNS = 1 + 8 * (2 * SUBSTEPS + 1)
"""One row of the gap stream (the way from one node to the next): its length h, then the
commands (values and rates, 8 numbers each) at the ends and midpoints of its RK4
substeps, ``t + i h / (2 SUBSTEPS)``, ``i = 0..2 SUBSTEPS``."""


@lru_cache(maxsize=16)
def _gap_function(model_name: str, frame: str, p: tuple[float, ...]) -> DenseCall:
    """Compiled ``(x, gaps (G, GAP_COLUMNS)) -> (x after each gap (G, n), [u, margin]
    (G, nu + 1))``: RK4 substeps from node to node, the inputs at the nodes."""
    model = load_model(model_name)
    kin = _kinematics(model_name, frame)
    margins = model.casadi.function("domain_margins")
    n = len(model.states)
    par = ca.DM(list(p))
    x, g = ca.SX.sym("x", n), ca.SX.sym("g", GAP_COLUMNS)
    none = ca.SX(0, 1)

    def rhs(z, commands, _):
        return kin.truth_rhs(z, commands, none, par)

    x1 = x
    for i in range(SUBSTEPS):
        x1 = casadi_step(rhs, "rk4", x1, g[1 + 16 * i:1 + 16 * i + 24], None, g[0] / SUBSTEPS)
    c1 = g[-8:]
    u1 = kin.inputs(x1, c1[:4], c1[4:], par)
    m1 = ca.mmin(margins(x1, u1, par))
    out = ca.cse(ca.vertcat(x1, u1, m1))  # shared subexpressions computed once
    gap = ca.Function("truth_gap", [x, g], [out[:n], out[n:]])
    batch = gap.mapaccum("truth_gaps", BATCH * DEGREE)
    return native_functions([batch])[0]


# --------------------------------------------------------------------------------------
# The coarse grid
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Plan:
    """The coarse intervals of a run.

    Attributes
    ----------
    start, length : numpy.ndarray, shape (J,)
        Start time and length of every interval, s.
    first_half : numpy.ndarray, shape (J + 1,)
        First half-step index ``q`` (time ``q τ / 2``) owned by every interval; the last
        entry is ``2 N + 1`` (the end point belongs to the last interval).
    regular : numpy.ndarray, shape (J,)
        Steps of an interval that starts on a step and holds a whole number of them
        (its evaluation matrices depend on that number only), else 0.
    times : numpy.ndarray, shape (J + 1,)
        The knots (interval ends), s.
    steps : numpy.ndarray, shape (J + 1,)
        Step index of every knot on the step grid, -1 for a knot between steps.
    """

    start: np.ndarray
    length: np.ndarray
    first_half: np.ndarray
    regular: np.ndarray
    times: np.ndarray
    steps: np.ndarray


def _plan_of_knots(times: np.ndarray, steps: np.ndarray, tau: float, q_first: int,
                   q_last: int) -> Plan:
    """The :class:`Plan` of knots ``times`` (s) with step indices ``steps`` (-1: off the
    grid); the first and the last interval end at half steps ``q_first``, ``q_last``."""
    first_half = np.where(steps >= 0, 2 * steps, np.ceil(2.0 * times / tau)).astype(np.int64)
    first_half[0], first_half[-1] = q_first, q_last
    on_grid = (steps[:-1] >= 0) & (steps[1:] >= 0)
    regular = np.where(on_grid, np.diff(steps), 0)
    return Plan(times[:-1], np.diff(times), first_half, regular, times, steps)


def _split(times: np.ndarray, steps: np.ndarray, split: np.ndarray,
           tau: float) -> tuple[np.ndarray, np.ndarray]:
    """Knots with the intervals marked in ``split`` cut in two (at a step where one is
    inside, so that halves of whole steps share their evaluation matrices)."""
    new_times, new_steps = [], []
    for j in np.flatnonzero(split):
        k_a, k_b, t_a, t_b = steps[j], steps[j + 1], times[j], times[j + 1]
        if k_a >= 0 and k_b >= 0 and k_b - k_a >= 2:
            k = (k_a + k_b) // 2
        else:
            k = round(0.5 * (t_a + t_b) / tau)
            if not t_a < k * tau < t_b:
                k = -1
        new_times.append(k * tau if k >= 0 else 0.5 * (t_a + t_b))
        new_steps.append(k)
    order = np.argsort(np.concatenate([times, new_times]), kind="stable")
    return (np.concatenate([times, new_times])[order],
            np.concatenate([steps, np.array(new_steps, dtype=steps.dtype)])[order])


def named_columns(model: Model) -> tuple[list[str], list[list[int]]]:
    """Names of a truth chunk's columns (the model's states, then its inputs) and, for
    each column, the columns of the same unit (the scale an interpolation error is judged
    against)."""
    names = [s.name for s in model.states] + [i.name for i in model.inputs]
    units = [s.unit for s in model.states] + [i.unit for i in model.inputs]
    return names, [[k for k, other in enumerate(units) if other == unit] for unit in units]


def chosen_truth(truth: str, breaks: Sequence[float] | None, n_steps: int, tau: float,
                 what: str) -> str:
    """Resolve a requested truth to ``"fine"`` or ``"interpolated"``.

    ``"auto"`` picks the interpolated truth when the motion's breaks are known and every
    interval of the coarse grid (at most :data:`INTERVAL` long, ending at each break)
    holds at least :data:`MIN_STEPS` steps; otherwise the fine truth.

    Parameters
    ----------
    truth : {"auto", "fine", "interpolated"}
    breaks : sequence of float or None
        Times of the motion's leg joins and knots, s (None: unknown).
    n_steps : int
    tau : float
        Step, s.
    what : str
        The motion's name in the error message ("a profile whose ...").

    Raises
    ------
    MotionError
        ``"interpolated"`` asked for a motion whose breaks are unknown.
    """
    if truth == "interpolated" and breaks is None:
        raise MotionError(f"the interpolated truth needs {what} whose breaks are known")
    if truth != "auto":
        return truth
    if breaks is None:
        return "fine"
    duration = n_steps * tau
    points = np.asarray(breaks, dtype=float)
    inside = np.count_nonzero((points > 0.0) & (points < duration))
    intervals = np.ceil(duration / INTERVAL) + inside
    if INTERVAL / tau >= MIN_STEPS and n_steps >= MIN_STEPS * intervals:
        return "interpolated"
    return "fine"


def carried_batches(fn: DenseCall, carry: np.ndarray, rows: np.ndarray, size: int,
                    carried: int, extra: int) -> tuple[np.ndarray, np.ndarray]:
    """Call a compiled interval integrator over ``rows`` in batches of ``size``.

    ``fn([carry, batch], [ends, out])`` integrates the batch's rows one after another
    from ``carry``: ``ends`` (size, carried) holds the carried values at the end of each
    row, ``out`` (size, extra) anything else per row. The last batch is padded with
    copies of its last row of zero length (column 0), and each batch starts from the
    previous batch's last end.

    Returns
    -------
    ends : numpy.ndarray, shape (len(rows), carried)
    out : numpy.ndarray, shape (len(rows), extra)
    """
    count = rows.shape[0]
    ends_all, out_all = np.empty((count, carried)), np.empty((count, extra))
    carry = np.ascontiguousarray(carry)
    for a in range(0, count, size):
        b = min(a + size, count)
        batch = rows[a:b]
        if b - a < size:
            pad = np.repeat(batch[-1:], size - (b - a), axis=0)
            pad[:, 0] = 0.0
            batch = np.vstack([batch, pad])
        ends, out = np.empty((size, carried)), np.empty((size, extra))
        fn([carry, np.ascontiguousarray(batch)], [ends, out])
        ends_all[a:b], out_all[a:b] = ends[:b - a], out[:b - a]
        carry = np.ascontiguousarray(ends[b - a - 1])
    return ends_all, out_all


class NodePath:
    """Quantities along a run, integrated interval by interval and read at any times.

    The run ``[0, t_end]`` is cut into intervals ending at given edges (leg joins, the
    samples of a motion file) and at most :data:`INTERVAL` long. On each interval the
    quantities are the degree-:data:`DEGREE` polynomial through their values at the
    Chebyshev–Lobatto nodes, read at any times by barycentric interpolation
    (:func:`lagrange_matrix`). A subclass integrates the node values of consecutive
    intervals from the value at their start (:meth:`_nodes`); they are computed
    :attr:`BLOCK` intervals at a time when a read reaches them. Two blocks are held and
    the start of every block reached is kept, chained from the end of the block before,
    so a reread (a Monte Carlo draw) gets the same bits and a long run needs memory for
    two blocks only.

    Parameters
    ----------
    edges : numpy.ndarray, shape (E,)
        Times that end an interval, s (clipped to the run; 0 and ``t_end`` are added).
    t_end : float
        End of the run, s.
    start : numpy.ndarray, shape (m,)
        The quantities at t = 0.

    Attributes
    ----------
    knots : numpy.ndarray, shape (J + 1,)
        Interval ends, s.
    count : int
        Intervals J.
    starts : list of numpy.ndarray, shape (m,) each
        The quantities at the start of every block reached so far.
    """

    BLOCK = 128
    """Intervals of one block."""

    def __init__(self, edges: np.ndarray, t_end: float, start: np.ndarray):
        t_end = float(t_end)
        edges = np.unique(np.clip(np.concatenate([[0.0, t_end], np.asarray(edges, float)]),
                                  0.0, t_end))
        lengths = np.diff(edges)
        parts = np.maximum(np.ceil(lengths / INTERVAL - 1e-9), 1).astype(int)
        first = np.repeat(np.cumsum(parts) - parts, parts)
        self.knots = np.append(np.repeat(edges[:-1], parts) + np.repeat(lengths / parts, parts)
                               * (np.arange(parts.sum()) - first), t_end)
        self.count = self.knots.size - 1
        self.starts = [np.asarray(start, dtype=float).copy()]
        self.held: dict[int, np.ndarray] = {}

    def __getstate__(self) -> dict:
        """Pickled without the held blocks (a Monte Carlo worker computes its own)."""
        return {**self.__dict__, "held": {}}

    def _nodes(self, first: np.ndarray, start: np.ndarray, length: np.ndarray,
               t: np.ndarray) -> np.ndarray:
        """Node values (J, DEGREE + 1, m) of consecutive intervals starting at times
        ``start`` (J,) of lengths ``length`` (J,), s, their nodes at times ``t``
        (J (DEGREE + 1),), integrated from ``first`` (m,), the value at ``start[0]``."""
        raise NotImplementedError

    def _interpolated(self, weights: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """Values (m, k) from the Lagrange weights (k, DEGREE + 1) of k times and the
        node values (k, DEGREE + 1, m) of their intervals."""
        return np.einsum("ki,kim->mk", weights, nodes)

    def _block(self, b: int) -> np.ndarray:
        """Node values of block ``b``'s intervals, shape (J, DEGREE + 1, m)."""
        if b in self.held:
            return self.held[b]
        while len(self.starts) <= b:  # the blocks before b, in order
            self.starts.append(self._block(len(self.starts) - 1)[-1, -1].copy())
        j0, j1 = b * self.BLOCK, min((b + 1) * self.BLOCK, self.count)
        start, length = self.knots[j0:j1], np.diff(self.knots[j0:j1 + 1])
        t = (start[:, None] + length[:, None] * _NODES[None, :]).ravel()
        nodes = self._nodes(self.starts[b], start, length, t)
        if len(self.held) >= 2:
            del self.held[next(iter(self.held))]
        self.held[b] = nodes
        return nodes

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """The quantities (m, T) at times ``t`` (T,), s."""
        t = np.asarray(t, dtype=float)
        j = np.clip(np.searchsorted(self.knots, t, side="right") - 1, 0, self.count - 1)
        theta = (t - self.knots[j]) / (self.knots[j + 1] - self.knots[j])
        weights = lagrange_matrix(theta)  # (T, DEGREE + 1)
        out = np.empty((self.starts[0].size, t.size))
        blocks = j // self.BLOCK
        for b in np.unique(blocks):
            at = np.flatnonzero(blocks == b)
            nodes = self._block(int(b))[j[at] - b * self.BLOCK]  # (k, DEGREE + 1, m)
            out[:, at] = self._interpolated(weights[at], nodes)
        return out


def plan(n_steps: int, tau: float, breaks: Sequence[float], interval: float = INTERVAL) -> Plan:
    """Cut ``[0, N τ]`` into intervals of at most ``interval`` s ending at every break.

    Breaks within a millionth of a step of a step time are moved onto it.
    """
    duration = n_steps * tau
    per = max(1, int(np.floor(interval / tau + 1e-9)))
    # knots as (step index or None, time)
    edges: list[tuple[int | None, float]] = [(0, 0.0)]
    breaks = np.unique(np.asarray(breaks, dtype=float))
    inner = [float(b) for b in breaks[(breaks > 0.0) & (breaks < duration)]]
    for b in [*inner, duration]:
        k = round(b / tau)
        on_grid = abs(b / tau - k) < 1e-6
        edges.append((k, k * tau) if on_grid else (None, b))
    knots: list[tuple[int | None, float]] = [edges[0]]
    for k_end, t_end in edges[1:]:
        k_begin, t_begin = knots[-1]
        # grid knots every `per` steps from the segment's start
        first = (k_begin if k_begin is not None else int(np.ceil(t_begin / tau)))
        k = first + per
        while (k * tau) < t_end - 1e-6 * tau and (k_end is None or k < k_end):
            knots.append((k, k * tau))
            k += per
        if t_end > knots[-1][1]:
            knots.append((k_end, t_end))
    times = np.array([t for _, t in knots])
    steps = np.array([-1 if k is None else k for k, _ in knots], dtype=np.int64)
    return _plan_of_knots(times, steps, tau, 0, 2 * n_steps + 1)


# --------------------------------------------------------------------------------------
# Blocks of intervals and the chunks handed out
# --------------------------------------------------------------------------------------
class _Block:
    """Node values of consecutive intervals and their evaluation on the half-step grid
    (half step ``q`` at time ``q τ / 2``: even ``q`` are the step times, odd the midpoints)."""

    def __init__(self, plan_: Plan, first: int, stop: int, nodes: np.ndarray, tau: float):
        self.nodes = nodes  # (J, DEGREE + 1, n + nu)
        self.q0, self.q1 = int(plan_.first_half[first]), int(plan_.first_half[stop])
        self.groups: list[tuple[int, int, slice, int]] = []  # (q_a, q_b, intervals, m)
        self._plan, self._first, self._tau = plan_, first, tau
        j = first
        while j < stop:
            q_a = int(plan_.first_half[j])
            m = int(plan_.regular[j])
            k = j
            while (m and k < stop and plan_.regular[k] == m
                   and plan_.first_half[k + 1] - plan_.first_half[k] == 2 * m):
                k += 1
            k = max(k, j + 1)
            self.groups.append((q_a, int(plan_.first_half[k]), slice(j - first, k - first),
                                m if k > j + 1 or plan_.first_half[j + 1] - q_a == 2 * m else 0))
            j = k
        self._cache: dict[tuple[str, int], np.ndarray] = {}

    def first(self, parity: int) -> int:
        """The block's first half step of the given parity."""
        return self.q0 + (parity - self.q0) % 2

    def evaluate(self, columns: slice, key: str, parity: int) -> np.ndarray:
        """Values of node columns ``columns`` at the block's half steps of ``parity``,
        shape (rows, c), the first row at :meth:`first`."""
        if (key, parity) not in self._cache:
            first = self.first(parity)
            rows = (self.q1 - first + 1) // 2
            out = np.empty((rows, columns.stop - columns.start))
            for q_a, q_b, intervals, m in self.groups:
                if m:
                    B = _regular_matrix(m, parity)
                else:
                    j = self._first + intervals.start
                    q = np.arange(q_a + (parity - q_a) % 2, q_b, 2)
                    theta = (q * (self._tau / 2.0) - self._plan.start[j]) / self._plan.length[j]
                    B = lagrange_matrix(theta)
                row = (q_a + (parity - q_a) % 2 - first) // 2
                count = intervals.stop - intervals.start
                target = out[row:row + count * B.shape[0]].reshape(count, B.shape[0], -1)
                np.matmul(B, self.nodes[intervals, :, columns], out=target)
            out.flags.writeable = False  # chunks hand out views of it
            self._cache[key, parity] = out
        return self._cache[key, parity]


@lru_cache(maxsize=64)
def _regular_matrix(m: int, parity: int) -> np.ndarray:
    """Evaluation matrix of an interval of ``m`` whole steps at its steps (parity 0) or
    midpoints (parity 1), shape (m, DEGREE + 1)."""
    return lagrange_matrix((np.arange(m) + 0.5 * parity) / m)


class _Chunk(TruthChunk):
    """A :class:`TruthChunk` whose arrays are interpolated when first read."""

    def __init__(self, start: int, m: int, blocks: list[_Block], n: int, nu: int):
        self.start, self._m, self._blocks, self._n, self._nu = start, m, blocks, n, nu
        self._values: dict[str, np.ndarray] = {}

    def _rows(self, key: str, columns: slice, q_first: int, q_last: int) -> np.ndarray:
        """Half steps q_first, q_first + 2, ..., q_last of a quantity, shape (rows, c)."""
        parity = q_first % 2
        pieces = []
        for block in self._blocks:
            first = block.first(parity)
            lo, hi = max(q_first, first), min(q_last, block.q1 - 1)
            if lo > hi:
                continue
            values = block.evaluate(columns, key, parity)
            pieces.append(values[(lo - first) // 2:(hi - first) // 2 + 1])
        return pieces[0] if len(pieces) == 1 else np.concatenate(pieces)

    def _get(self, name: str) -> np.ndarray:
        if name not in self._values:
            n, nu, s, m = self._n, self._nu, self.start, self._m
            columns = slice(0, n) if name == "truth" else slice(n, n + nu)
            key = "x" if name == "truth" else "u"
            if name == "midpoints":
                rows = self._rows(key, columns, 2 * s + 1, 2 * (s + m) - 1)
            else:
                rows = self._rows(key, columns, 2 * s, 2 * (s + m))
            self._values[name] = np.ascontiguousarray(rows).T
        return self._values[name]

    @property
    def truth(self) -> np.ndarray:
        """True states at the step times, shape (n, m + 1)."""
        return self._get("truth")

    @property
    def inputs(self) -> np.ndarray:
        """Inputs at the step times, shape (nu, m + 1)."""
        return self._get("inputs")

    @property
    def midpoints(self) -> np.ndarray:
        """Inputs at the step midpoints, shape (nu, m)."""
        return self._get("midpoints")

    @property
    def size(self) -> int:
        """Number of steps m."""
        return self._m


class InterpolatedTruth:
    """A :class:`Profile` followed by a model's ideal equations on a coarse grid and
    interpolated to the run's steps (a :class:`MotionSource`).

    Parameters
    ----------
    model : Model
    profile : Profile
        A profile whose :attr:`~Profile.breaks` are known.
    frame : str
        Frame of the profile's commands.
    tau : float
        Step, s.
    n_steps : int
        Steps N.
    p : numpy.ndarray
        Model parameters.
    x0 : numpy.ndarray, shape (n,)
        True state at t = 0.

    Attributes
    ----------
    error_estimate : numpy.ndarray, shape (n + nu,)
        Largest estimated interpolation error of every state and input over the intervals
        generated so far (SI): the magnitude of the last Chebyshev coefficient of each
        interval (the coefficients decay, so the omitted ones are smaller: a cautious
        estimate; the tests measure the error against the fine truth).
    worst : float
        Largest ratio of that estimate to the size of the quantities of the same unit
        over a block of intervals.
    """

    kind = "interpolated"
    """How this source computes the truth (:attr:`Trajectory.truth_kind`)."""

    def __init__(self, model: Model, profile, frame: str, tau: float, n_steps: int,
                 p: np.ndarray, x0: np.ndarray):
        self.model_name, self.profile, self.frame = model.key, profile, frame
        self.tau, self.n_steps, self.p = float(tau), int(n_steps), tuple(float(v) for v in p)
        self.x0 = np.asarray(x0, dtype=float)
        self.n, self.nu = len(model.states), len(model.inputs)
        self.plan = plan(self.n_steps, self.tau, profile.breaks)
        self.error_estimate = np.zeros(self.n + self.nu)
        self.names, self._same_unit = named_columns(model)
        self._warned = False
        self.worst = 0.0

    # -- coarse integration ------------------------------------------------------------
    def _blocks(self) -> Iterator[_Block]:
        fn = _gap_function(self.model_name, self.frame,
                           truth_parameters(self.model_name, self.frame, self.p))
        plan_, n, nu, d = self.plan, self.n, self.nu, DEGREE
        J = len(plan_.start)
        x = self.x0.copy()
        previous = np.concatenate(self.start())  # node 0 of the first interval
        for j0 in range(0, J, BATCH):
            j1 = min(j0 + BATCH, J)
            sub, gaps = self._refined(plan_.times[j0:j1 + 1], plan_.steps[j0:j1 + 1],
                                      int(plan_.first_half[j0]), int(plan_.first_half[j1]))
            count = len(sub.start)
            xs, ys = self._call(fn, x, gaps)
            times = (sub.start[:, None] + sub.length[:, None] * _NODES[1:]).ravel()
            self._check(ys, xs, times)
            x = xs[-1].copy()
            nodes = np.empty((count, d + 1, n + nu))
            nodes[:, 1:, :n] = xs.reshape(count, d, n)
            nodes[:, 1:, n:] = ys[:, :nu].reshape(count, d, nu)
            nodes[0, 0] = previous
            nodes[1:, 0] = nodes[:-1, d]
            previous = nodes[-1, d].copy()
            tail = np.abs(np.einsum("i,jic->jc", _CHEBYSHEV[-1], nodes))
            np.maximum(self.error_estimate, tail.max(axis=0), out=self.error_estimate)
            self._warn_if_coarse(tail, nodes, sub.start)
            yield _Block(sub, 0, count, nodes, self.tau)

    def start(self) -> tuple[np.ndarray, np.ndarray]:
        """True state (n,) and inputs (nu,) at t = 0, the first column of the first chunk
        (the inputs from a gap of zero length); raises if the motion starts outside the
        model's domain."""
        fn = _gap_function(self.model_name, self.frame,
                           truth_parameters(self.model_name, self.frame, self.p))
        first = self._gaps(np.array([0.0]), np.array([0.0]))[0][:1]
        first[:, 0] = 0.0
        xs, ys = self._call(fn, self.x0, first)
        self._check(ys[:1], xs[:1], 0.0)
        return self.x0.copy(), ys[0, :self.nu].copy()

    def _refined(self, times: np.ndarray, steps: np.ndarray, q_first: int,
                 q_last: int) -> tuple[Plan, np.ndarray]:
        """The intervals between knots ``times`` (a block of the coarse plan), halved
        where the profile's commands are not resolved to :data:`REFINE_RELATIVE` (at
        most :data:`MAX_SPLITS` times), and their gap rows."""
        for depth in range(MAX_SPLITS + 1):
            start, length = times[:-1], np.diff(times)
            gaps, commands = self._gaps(start, length)
            if depth == MAX_SPLITS:
                break
            nodes = commands[:, ::2 * SUBSTEPS]  # (J, DEGREE + 1, 8)
            tail = np.abs(np.einsum("i,jic->jc", _CHEBYSHEV[-1], nodes))
            largest = np.abs(nodes).max(axis=(0, 1))
            size = np.array([largest[group].max() for group in _COMMAND_UNITS])
            split = ((tail > REFINE_RELATIVE * size).any(axis=1)
                     & (length >= 2.0 * self.tau))
            if not split.any():
                break
            times, steps = _split(times, steps, split, self.tau)
        return _plan_of_knots(times, steps, self.tau, q_first, q_last), gaps

    def _gaps(self, start: np.ndarray, length: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Gap rows (J·DEGREE, GAP_COLUMNS) of intervals at ``start`` of ``length`` (s),
        and the commands at the ends and midpoints of their RK4 steps (J, ., 8)."""
        d = DEGREE
        S = 2 * SUBSTEPS
        fractions = (_NODES[:-1, None] + np.diff(_NODES)[:, None] * np.arange(S) / S).ravel()
        t = (start[:, None] + length[:, None] * np.append(fractions, 1.0)[None, :]).ravel()
        values, rates = self.profile.commands(t)
        commands = np.vstack([values, rates]).T
        bad = ~np.all(np.isfinite(commands), axis=1)
        if bad.any():
            raise DomainError(f"motion commands are NaN or infinite at "
                              f"t = {t[int(np.argmax(bad))]:.6g} s")
        commands = commands.reshape(len(start), S * d + 1, 8)
        rows = np.empty((len(start), d, GAP_COLUMNS))
        rows[:, :, 0] = length[:, None] * np.diff(_NODES)[None, :]
        for i in range(S + 1):
            rows[:, :, 1 + 8 * i:9 + 8 * i] = commands[:, i:i + S * d:S]
        return rows.reshape(-1, GAP_COLUMNS), commands

    def _call(self, fn: DenseCall, x: np.ndarray, gaps: np.ndarray):
        """Integrate the gaps from ``x`` in compiled batches (the last one padded)."""
        return carried_batches(fn, x, gaps, BATCH * DEGREE, self.n, self.nu + 1)

    def _warn_if_coarse(self, tail: np.ndarray, nodes: np.ndarray, starts: np.ndarray) -> None:
        """Warn once if an interval's interpolation error may exceed :data:`WARN_RELATIVE`
        of the size of the quantities of its unit over the block (the motion changes too
        fast for the intervals)."""
        largest = np.abs(nodes).max(axis=(0, 1))
        size = np.broadcast_to([largest[group].max() for group in self._same_unit], tail.shape)
        ratio = tail / np.where(size > 0, size, 1.0)
        self.worst = max(self.worst, float(ratio.max()))
        if self._warned:
            return
        coarse = tail > WARN_RELATIVE * size
        if coarse.any():
            j, c = np.argwhere(coarse)[0]
            self._warned = True
            warnings.warn(f"ins-errors: the interpolated true motion may be off by about "
                          f"{tail[j, c] / size[j, c]:.1e} of {self.names[c]} near "
                          f"t = {starts[j]:.6g} s (the motion changes there faster than its "
                          "intervals resolve: a corner or a fast turn); the error curves, "
                          "real minus ideal work along the same motion, are affected far "
                          "less; to be sure, rerun with a truth integrated at every step: "
                          f"{TRUTH_FINE_HOW}", RuntimeWarning, stacklevel=4)

    @staticmethod
    def _check(ys: np.ndarray, xs: np.ndarray, times) -> None:
        bad = ~(ys[:, -1] > 0) | ~np.all(np.isfinite(xs), axis=1) | \
            ~np.all(np.isfinite(ys), axis=1)
        if bad.any():
            t = float(np.atleast_1d(times)[int(np.argmax(bad))])
            raise DomainError(f"the true motion leaves the model's domain at t = {t:.6g} s "
                              "(e.g. passes a pole)")

    # -- the MotionSource interface ------------------------------------------------------
    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """Chunks of at most ``size`` steps (see :class:`MotionSource`)."""
        blocks = self._blocks()
        held: list[_Block] = []
        for start in range(0, self.n_steps, size):
            m = min(size, self.n_steps - start)
            q_last = 2 * (start + m)
            held = [b for b in held if b.q1 > 2 * start]
            while not held or held[-1].q1 <= q_last:
                held.append(next(blocks))
            yield _Chunk(start, m, list(held), self.n, self.nu)
