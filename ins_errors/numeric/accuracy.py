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


def coarse_stride(stride: int, n_steps: int) -> int:
    """Recording stride of the doubled-step run that shares the most samples with the
    fine run recorded every ``stride`` steps of ``n_steps``."""
    half = n_steps // 2
    if stride % 2 == 0 and half % (stride // 2) == 0:
        return stride // 2
    if half % stride == 0:
        return stride
    return 1


def common_samples(stride: int, coarse: int, n_steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the fine and of the coarse recorded samples taken at the same times.

    Parameters
    ----------
    stride : int
        Fine steps between fine samples.
    coarse : int
        Coarse steps (of two fine steps) between coarse samples.
    n_steps : int
        Fine steps of the run.
    """
    every = math.lcm(stride, 2 * coarse)
    steps = np.arange(0, 2 * (n_steps // 2) + 1, every)
    return steps // stride, steps // (2 * coarse)


def richardson(fine: np.ndarray, coarse: np.ndarray, method: str) -> np.ndarray:
    """Estimated error of ``fine`` from the same run at twice the step."""
    return (fine - coarse) / (2 ** ORDERS[method] - 1)


def step_that_would_do(tau: float, error: float, target: float, method: str) -> float:
    """A step ``τ/k`` (k whole, so it still divides the run) whose integration error,
    scaled by the scheme's order with a 25 % margin, stays below ``target``."""
    if not error > target > 0:
        return tau
    k = math.ceil((1.25 * error / target) ** (1.0 / ORDERS[method]))
    return tau / k
