"""Direct vs linear vs refined: metrics per error quantity and a Markdown summary.

For every reported quantity (platform angles, Δφ, Δλ, Δχ, Δω_N, Δω_E, Δv_N, Δv_E for the
orthodromic model) and every case:

* ``max_direct``: max |direct error| over the run;
* ``linear_difference``: max |linear − direct|, and ``linear_ratio`` = that / ``max_direct``;
* ``refined_difference`` and ``refined_ratio`` likewise for the second-order model.

A quantity counts as *excited* when its direct error is above the rounding floor of its
unit (:data:`NOISE_FLOOR`) and at least :data:`EXCITED_FRACTION` of the largest direct
error of the same unit in that case; quantities a source moves only at second order (or
not at all) are reported but do not enter the worst-case ratios (their relative
difference is meaningless: the linear model rightly predicts ~0).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field

import numpy as np

from ins_errors.numeric.model import Model
from ins_errors.numeric.simulate import ErrorCurves, Simulation, simulate
from ins_errors.numeric.trajectories import Trajectory

NOISE_FLOOR: dict[str, float] = {"rad": 1e-10, "rad/s": 1e-14, "m/s": 1e-6, "m": 1e-3, "1": 1e-10}
"""Direct errors below these (SI) are at the level of accumulated double rounding of
quantities of order one (direction cosines) or hundreds of m/s (absolute velocities)."""

EXCITED_FRACTION = 1e-3
"""A quantity is excited when its direct error reaches this fraction of the largest
direct error of the same unit in the same case."""


@dataclass
class Metric:
    """Agreement of the linear and refined runs with the direct run for one quantity."""

    quantity: str
    unit: str
    max_direct: float
    linear_difference: float
    linear_ratio: float
    refined_difference: float | None
    refined_ratio: float | None
    excited: bool


@dataclass
class Comparison:
    """One case (one set of error sources) compared along one trajectory.

    Attributes
    ----------
    label : str
        Human label of the case (e.g. ``gyro_drift_x = 0.01 deg/h``).
    sources : dict of str to float
        Non-zero error sources, SI.
    metrics : list of Metric
        One per reported quantity.
    times : numpy.ndarray, shape (R + 1,)
        Recorded times, s.
    direct, linear, refined : dict of str to numpy.ndarray
        Error curves per quantity, shape (R + 1,) (refined may be empty).
    """

    label: str
    sources: dict[str, float]
    metrics: list[Metric]
    times: np.ndarray = field(repr=False)
    direct: dict[str, np.ndarray] = field(repr=False)
    linear: dict[str, np.ndarray] = field(repr=False)
    refined: dict[str, np.ndarray] = field(repr=False)

    def metric(self, quantity: str) -> Metric:
        """The metric of one quantity."""
        for m in self.metrics:
            if m.quantity == quantity:
                return m
        from ins_errors.errors import unknown_name

        raise unknown_name("error quantity", quantity, [m.quantity for m in self.metrics])

    @property
    def excited(self) -> list[Metric]:
        """Metrics of the excited quantities."""
        return [m for m in self.metrics if m.excited]

    @property
    def worst_linear(self) -> Metric | None:
        """Excited quantity with the largest linear/direct ratio (None if none excited)."""
        return max(self.excited, key=lambda m: m.linear_ratio, default=None)

    @property
    def worst_refined(self) -> Metric | None:
        """Excited quantity with the largest refined/direct ratio."""
        ok = [m for m in self.excited if m.refined_ratio is not None]
        return max(ok, key=lambda m: m.refined_ratio, default=None)

    def to_dict(self) -> dict:
        """JSON-ready summary (no curves)."""
        return {"label": self.label, "sources": self.sources,
                "worst_linear_ratio": _value(self.worst_linear, "linear_ratio"),
                "worst_refined_ratio": _value(self.worst_refined, "refined_ratio"),
                "metrics": [_clean(asdict(m)) for m in self.metrics]}


def _value(metric: Metric | None, attribute: str) -> float | None:
    return None if metric is None else getattr(metric, attribute)


def _clean(row: dict) -> dict:
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
            for k, v in row.items()}


def _ratio(difference: float, reference: float) -> float:
    return difference / reference if reference > 0 else (0.0 if difference == 0 else math.inf)


def metrics_of(direct: ErrorCurves, linear: ErrorCurves, refined: ErrorCurves | None,
               case: int = 0) -> list[Metric]:
    """Per-quantity metrics of one batch member."""
    rows = []
    peaks = {name: float(np.max(np.abs(direct.values[k, :, case])))
             for k, name in enumerate(direct.names)}
    largest: dict[str, float] = {}
    for name, unit in zip(direct.names, direct.units, strict=True):
        largest[unit] = max(largest.get(unit, 0.0), peaks[name])
    for k, (name, unit) in enumerate(zip(direct.names, direct.units, strict=True)):
        d = direct.values[k, :, case]
        peak = peaks[name]
        lin = float(np.max(np.abs(linear.values[k, :, case] - d)))
        ref = None if refined is None else float(np.max(np.abs(refined.values[k, :, case] - d)))
        excited = bool(peak > NOISE_FLOOR.get(unit, 0.0)
                       and peak >= EXCITED_FRACTION * largest[unit])
        rows.append(Metric(name, unit, peak, lin, _ratio(lin, peak), ref,
                           None if ref is None else _ratio(ref, peak), excited))
    return rows


def case_label(model: Model, sources: dict[str, float]) -> str:
    """``name = value display_unit`` for each non-zero source."""
    from ins_errors.units import format_quantity

    parts = []
    for name, value in sources.items():
        info = model.sources[model.index("sources", name)]
        shown = format_quantity(value, info.unit, info.display_unit or info.unit)
        parts.append(f"{name} = {shown}")
    return ", ".join(parts) or "no errors"


def comparisons_of(sim: Simulation, labels: Sequence[str] | None = None) -> list[Comparison]:
    """Compare every batch member of a simulation that ran real, linear (and refined)."""
    direct, linear = sim.direct_errors(), sim.linear_errors()
    refined = sim.refined_errors() if sim.refined is not None else None
    out = []
    names = [s.name for s in sim.model.sources]
    for b in range(sim.sources.shape[1]):
        sources = {n: float(v) for n, v in zip(names, sim.sources[:, b], strict=True) if v != 0}
        label = labels[b] if labels is not None else case_label(sim.model, sources)
        out.append(Comparison(
            label, sources, metrics_of(direct, linear, refined, b), direct.times,
            {n: direct.values[k, :, b] for k, n in enumerate(direct.names)},
            {n: linear.values[k, :, b] for k, n in enumerate(linear.names)},
            {} if refined is None else {n: refined.values[k, :, b]
                                        for k, n in enumerate(refined.names)}))
    return out


def compare(model: Model, trajectory: Trajectory, cases: Sequence[dict[str, float]],
            method: str = "euler", record_interval: float | None = None,
            refined: bool = True, jit: bool = True, progress: bool = False,
            platform: str = "exact") -> list[Comparison]:
    """Run direct, linear (and refined) for several cases in one batch and compare.

    Parameters
    ----------
    model : Model
    trajectory : Trajectory
        The true motion.
    cases : sequence of dict
        Error sources per case, ``{name: SI value}``.
    method : {"euler", "rk4"}
    record_interval : float, optional
        Seconds between recorded samples.
    refined : bool
        Also run the second-order model.
    platform : {"exact", "small_angle"}
        Platform kinematics of the direct run (see :func:`~ins_errors.numeric.simulate.simulate`).

    Returns
    -------
    list of Comparison
        One per case.
    """
    parts = ("real", "linear", "refined") if refined else ("real", "linear")
    sim = simulate(model, trajectory, list(cases), method=method,
                   record_interval=record_interval, parts=parts, jit=jit, progress=progress,
                   platform=platform)
    return comparisons_of(sim)


def _fmt(value: float | None) -> str:
    if value is None:
        return "–"
    if not math.isfinite(value):
        return "∞"
    return f"{value:.3e}"


def markdown_table(comparison: Comparison) -> str:
    """Markdown table of one case: one row per quantity."""
    lines = [f"**{comparison.label}**", "",
             "| quantity | unit | max abs direct | max abs (linear − direct) | ratio "
             "| max abs (refined − direct) | ratio | excited |",
             "|---|---|---:|---:|---:|---:|---:|:---:|"]
    for m in comparison.metrics:
        lines.append(f"| `{m.quantity}` | {m.unit} | {_fmt(m.max_direct)} | "
                     f"{_fmt(m.linear_difference)} | {_fmt(m.linear_ratio)} | "
                     f"{_fmt(m.refined_difference)} | {_fmt(m.refined_ratio)} | "
                     f"{'yes' if m.excited else 'no'} |")
    return "\n".join(lines) + "\n"


def markdown_summary(comparisons: Sequence[Comparison], title: str = "") -> str:
    """Markdown summary: one row per case with the worst excited ratios."""
    lines = [f"### {title}", ""] if title else []
    lines += ["| case | worst linear ratio | quantity | worst refined ratio | quantity |",
              "|---|---:|---|---:|---|"]
    for c in comparisons:
        wl, wr = c.worst_linear, c.worst_refined
        lines.append(f"| {c.label} | {_fmt(_value(wl, 'linear_ratio'))} | "
                     f"{'' if wl is None else '`' + wl.quantity + '`'} | "
                     f"{_fmt(_value(wr, 'refined_ratio'))} | "
                     f"{'' if wr is None else '`' + wr.quantity + '`'} |")
    return "\n".join(lines) + "\n"
