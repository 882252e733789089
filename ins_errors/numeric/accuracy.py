"""Integration error of a run, estimated by step doubling, and a step that would do.

Direct and linear runs use the same scheme and step, so their integration errors largely
cancel in the linear-vs-direct comparison: a good agreement says nothing about whether
either curve is right. Every comparison therefore runs the same cases once more with the
step doubled (on every other sample of the same motion; the dropped samples are exactly
the midpoints RK4 needs) and estimates the error of the fine run by Richardson's rule

    error(τ) ≈ (y_τ − y_2τ) / (2^p − 1),

p being the order of the scheme (1 for the rectangle method, 4 for RK4). The estimate is
asymptotic: when it is large (tens of per cent), it says the step is far too large rather
than how large the error is.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ins_errors.numeric.integrators import whole_steps
from ins_errors.numeric.trajectories import Trajectory, TruthChunk

ORDERS: dict[str, int] = {"euler": 1, "rk4": 4}
"""Order of accuracy of each integration scheme."""

DIFFERENCE_SHARE = 0.1
"""Warn when the integration error exceeds this share of the linear-vs-direct difference."""

ERROR_SHARE = 0.01
"""Warn when the integration error exceeds this share of the error being computed."""


class EveryOtherStep:
    """A :class:`~ins_errors.numeric.trajectories.MotionSource` giving every other sample
    of a trajectory: the grid of step 2τ, whose midpoints are the dropped samples."""

    def __init__(self, fine: Trajectory, half: int):
        self.fine, self.half = fine, half

    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """Chunks of at most ``size`` coarse steps (from fine chunks of ``2 size``)."""
        for chunk in self.fine.chunks(2 * size):
            start = chunk.start // 2
            m = min(chunk.size // 2, self.half - start)
            if m <= 0:
                return
            yield TruthChunk(start, chunk.truth[:, :2 * m + 1:2],
                             chunk.inputs[:, :2 * m + 1:2], chunk.inputs[:, 1:2 * m:2])


def coarsened(trajectory: Trajectory) -> Trajectory | None:
    """The same motion on the grid of step 2τ (the first ``2⌊N/2⌋`` steps).

    Returns None when the run has fewer than two steps.
    """
    half = trajectory.n_steps // 2
    if half < 1:
        return None
    t = trajectory
    if t.constant:
        return Trajectory(t.model, 2 * t.tau, half, t.truth[:, :1], t.inputs[:, :1],
                          t.midpoints[:, :1], t.parameters, t.initial_conditions, True,
                          t.description)
    return Trajectory.streamed(t.model, 2 * t.tau, half, EveryOtherStep(t, half),
                               t.start_state, t.start_inputs, t.parameters,
                               t.initial_conditions, t.description)


def halved(trajectory: Trajectory, method: str) -> Trajectory | None:
    """The same motion on the grid of step τ/2 (``2N`` steps), or None when it cannot be
    built from what the trajectory holds.

    A static base is the same column at any step; a profile's or a strapdown flight's
    truth (fine or interpolated) is generated again at τ/2; for the rectangle method,
    which reads the inputs at the steps only, the inputs and midpoints of the run at τ
    interleave into the steps of the run at τ/2 (its own midpoints, never read, repeat
    the inputs).
    """
    from ins_errors.numeric.interpolated_truth import InterpolatedTruth
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.trajectories import ProfileTruth

    t = trajectory
    if t.constant:
        return Trajectory(t.model, t.tau / 2, 2 * t.n_steps, t.truth[:, :1], t.inputs[:, :1],
                          t.midpoints[:, :1], t.parameters, t.initial_conditions, True,
                          t.description)
    source = t.source
    flight = getattr(source, "flight", None)
    if flight is not None:  # a strapdown flight (fine or interpolated): generated again
        from ins_errors.numeric import strapdown_truth

        return strapdown_truth.trajectory(load_model(t.model), flight, t.duration, t.tau / 2,
                                          t.parameters, truth=source.kind, stream=True)
    if type(source) in (ProfileTruth, InterpolatedTruth):
        model = load_model(source.model_name)
        again = type(source)(model, source.profile, source.frame, t.tau / 2, 2 * t.n_steps,
                             np.asarray(source.p, dtype=float), source.x0)
        return Trajectory.streamed(t.model, t.tau / 2, 2 * t.n_steps, again, t.start_state,
                                   t.start_inputs, t.parameters, t.initial_conditions,
                                   t.description)
    if method == "euler":
        return Trajectory.streamed(t.model, t.tau / 2, 2 * t.n_steps, Interleaved(t),
                                   t.start_state, t.start_inputs, t.parameters,
                                   t.initial_conditions, t.description)
    return None


class Interleaved:
    """A :class:`~ins_errors.numeric.trajectories.MotionSource` on the grid of step τ/2
    made of the inputs and midpoints of a trajectory of step τ (for the rectangle method,
    which never reads midpoints: those repeat the inputs, the states are held)."""

    def __init__(self, coarse: Trajectory):
        self.coarse = coarse

    def chunks(self, size: int) -> Iterator[TruthChunk]:
        """Chunks of at most ``size`` steps of τ/2 (from chunks of ``size // 2`` steps)."""
        for chunk in self.coarse.chunks(max(1, size // 2)):
            m = chunk.size
            inputs = np.empty((chunk.inputs.shape[0], 2 * m + 1))
            inputs[:, ::2], inputs[:, 1::2] = chunk.inputs, chunk.midpoints
            truth = np.repeat(chunk.truth, 2, axis=1)[:, :2 * m + 1]
            yield TruthChunk(2 * chunk.start, truth, inputs, inputs[:, :-1].copy())


def motion_breaks(trajectory: Trajectory) -> np.ndarray | None:
    """Times (s) where the motion of ``trajectory`` is less smooth than elsewhere, or None.

    A motion file's cubic splines have a third derivative that jumps at every sample, a
    manoeuvre's commands change law at every leg join: RK4 keeps its order there only
    when a step ends on the break. These are the :attr:`Profile.breaks` of the
    trajectory's profile (or :attr:`Flight.breaks` of a strapdown flight); None when the
    trajectory does not say (arrays of its own, a static base), an empty array when the
    motion is smooth throughout.
    """
    source = trajectory.source
    owner = getattr(source, "flight", None) or getattr(source, "profile", None)
    breaks = getattr(owner, "breaks", None)
    return None if breaks is None else np.asarray(breaks, dtype=float)


BREAK_TOLERANCE = 1e-6
"""A break within this share of a step of a grid point counts as on that point."""


def breaks_on_grid(breaks: np.ndarray | None, tau: float,
                   n_steps: int) -> tuple[np.ndarray, np.ndarray]:
    """The breaks strictly inside a run of ``n_steps`` steps of ``tau``, split by where
    they fall on its grid.

    Parameters
    ----------
    breaks : numpy.ndarray or None
        Break times, s (:func:`motion_breaks`); None or empty: none.
    tau : float
        Step, s.
    n_steps : int
        Steps of the run.

    Returns
    -------
    on_grid : numpy.ndarray of int
        Step indices ``j`` (``0 < j < n_steps``) of the breaks at ``j τ``.
    straddled : numpy.ndarray of float
        Times, s, of the breaks strictly inside a step.
    """
    if breaks is None or len(breaks) == 0:
        return np.zeros(0, dtype=int), np.zeros(0)
    steps = np.unique(np.asarray(breaks, dtype=float)) / tau
    nearest = np.round(steps)
    on = np.abs(steps - nearest) <= BREAK_TOLERANCE
    inside = (steps > BREAK_TOLERANCE) & (steps < n_steps - BREAK_TOLERANCE)
    return nearest[on & inside].astype(int), steps[~on & inside] * tau


DENSE_BREAKS = 0.05
"""Breaks straddled in more than this share of a run's steps cost RK4 its order.

A step across a break (a jump in a derivative of the motion) has a larger local error
than the others; a few of them (a manoeuvre's leg joins) are lost among the thousands of
steps of a run, and step doubling still measures the error (within 10 % on the standard
manoeuvre at τ = 4 s, whose steps straddle three of its joins). A motion file's samples
are straddled at every step of a run at twice their spacing: there they make the error,
and an estimate from such a run is orders of magnitude too large."""


def dense(straddled: int, steps: int) -> bool:
    """Whether ``straddled`` breaks in a run of ``steps`` steps cost it its order
    (:data:`DENSE_BREAKS`)."""
    return straddled > DENSE_BREAKS * max(steps, 1)


def straddled_by(on_grid: np.ndarray, factor: int, n_steps: int) -> int:
    """How many breaks of ``on_grid`` (step indices on the grid of τ) the grid of
    ``factor`` τ straddles over its first ``factor ⌊N/factor⌋`` steps."""
    spanned = on_grid[on_grid < factor * (n_steps // factor)]
    return int(np.count_nonzero(spanned % factor))


def spacing(breaks: np.ndarray) -> float | None:
    """The spacing ``d`` (s) that every break is a whole multiple of, taken as the
    smallest gap between two breaks; None when the breaks are not all on such a grid."""
    points = np.unique(np.asarray(breaks, dtype=float))
    if points.size < 2:
        return None
    d = float(np.min(np.diff(points)))
    k = points / d
    if d <= 0 or np.any(np.abs(k - np.round(k)) > BREAK_TOLERANCE):
        return None
    return d


def coarse_stride(stride: int, n_steps: int) -> int:
    """Recording stride of the doubled-step run that shares the most samples with the
    fine run recorded every ``stride`` steps of ``n_steps``."""
    return sampling(stride, 2, n_steps)[0]


def sampling(stride: int, factor: int, n_steps: int) -> tuple[int, np.ndarray, np.ndarray]:
    """How a run at ``factor`` τ (over the first ``factor ⌊N/factor⌋`` steps) records to
    share samples with the run at τ recorded every ``stride`` steps of ``n_steps``.

    Returns
    -------
    coarse : int
        Recording stride of the coarse run, in its own steps.
    fine_i, coarse_i : numpy.ndarray of int
        Indices of the fine and of the coarse recorded samples taken at the same times
        (all the fine ones when every fine sample lies on the coarse grid).
    """
    m = n_steps // factor
    want = math.lcm(stride, factor) // factor
    coarse = want if m >= 1 and m % want == 0 else 1
    fine_i, coarse_i = common_samples(stride, coarse, n_steps, factor)
    return coarse, fine_i, coarse_i


def common_samples(stride: int, coarse: int, n_steps: int,
                   factor: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the fine and of the coarse recorded samples taken at the same times.

    Parameters
    ----------
    stride : int
        Fine steps between fine samples.
    coarse : int
        Coarse steps (of ``factor`` fine steps) between coarse samples.
    n_steps : int
        Fine steps of the run.
    factor : int
        Coarse step over fine step.
    """
    every = math.lcm(stride, factor * coarse)
    steps = np.arange(0, factor * (n_steps // factor) + 1, every)
    return steps // stride, steps // (factor * coarse)


def richardson(fine: np.ndarray, coarse: np.ndarray, method: str) -> np.ndarray:
    """Estimated error of ``fine`` from the same run at twice the step."""
    return (fine - coarse) / (2 ** ORDERS[method] - 1)


def order_observed(fine_gap: float, coarse_gap: float) -> float | None:
    """Order of convergence shown by three runs at h, 2h and 4h: ``log2`` of the gap
    between the two coarser over the gap between the two finer (None if either is 0)."""
    if not (fine_gap > 0 and coarse_gap > 0):
        return None
    return math.log2(coarse_gap / fine_gap)


ORDER_TOLERANCE = 0.5
"""The estimate counts as asymptotic while the observed order is within this of the
scheme's order."""

RELEVANT = 1e-6
"""Integration errors below this share of the error are not judged by their observed
order (rounding and cancellations make it meaningless there)."""


def typable_step(needed: float, interval: float,
                 spacing: float | None = None) -> tuple[float, str]:
    """The largest step of at most three significant digits, at or below ``needed``, that
    divides ``interval`` (the recording interval, so also the run) to the accuracy the
    command line checks, with its text (typing the text back gives the same step).

    Parameters
    ----------
    needed : float
        Largest acceptable step, s (> 0).
    interval : float
        Recording interval, s (a whole number of steps of the run).
    spacing : float, optional
        A length, s, the step must divide as well: the spacing of the motion's breaks
        (:func:`spacing`), so that the step keeps them.
    """
    top = math.floor(math.log10(needed))
    for decade in range(top, top - 16, -1):
        best = None
        for digits in (1, 2, 3):
            unit = 10.0 ** (decade - digits + 1)
            for mantissa in range(min(int(needed / unit * (1 + 1e-12)), 10 ** digits - 1),
                                  0, -1):
                value = float(f"{mantissa * unit:.{digits}g}")
                if value < 10.0 ** decade * (1 - 1e-12):
                    break
                text = np.format_float_positional(value, unique=True, trim="-")
                value = float(text)
                if value > needed * (1 + 1e-12):
                    continue
                if whole_steps(interval, value) is None:  # as step_count checks it
                    continue
                if spacing is not None and whole_steps(spacing, value) is None:
                    continue
                if best is None or value > best[0]:
                    best = (value, text)
                break
        if best is not None:
            return best
    text = repr(needed)
    return needed, text


def step_that_would_do(tau: float, error: float, target: float, method: str) -> float:
    """A step ``τ/k`` (k whole, so it still divides the run) whose integration error,
    scaled by the scheme's order with a 25 % margin, stays below ``target``."""
    if not error > target > 0:
        return tau
    k = math.ceil((1.25 * error / target) ** (1.0 / ORDERS[method]))
    return tau / k


CHECK_LABEL = "integration-error check"
"""What the progress bars of the reruns at other steps are labelled with."""


def rerun_label(factor: float, tau: float) -> str:
    """The progress label of one rerun of the integration-error check, e.g.
    ``"integration-error check: run at 2τ = 2 s"``.

    Parameters
    ----------
    factor : float
        The rerun's step over the run's: 2 or 4 (coarser), 1/2 or 1/4 (finer).
    tau : float
        The run's step τ, s.
    """
    ratio = f"{factor:g}τ" if factor >= 1 else f"τ/{1 / factor:g}"
    return f"{CHECK_LABEL}: run at {ratio} = {factor * tau:g} s"
