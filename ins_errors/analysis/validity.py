"""Validity map of a model's linear error equations: how their residual scales.

For each error source and motion, the source's magnitude is swept over decades around a
typical size; direct, linear and refined runs are compared at every magnitude. If the
linear model keeps every first-order term and nothing else is wrong, the relative
linear residual |linear − direct| / |direct| grows in proportion to the magnitude (slope
1 on a log–log plot: a clean second-order residual), and the refined model's residual as
its square (slope 2). From the fitted line come the magnitudes at which the linear
residual reaches 1 % and 10 % of the error.

The work is a list of independent :class:`ValidityTask` (one per source and motion) and
:func:`run_validity_task`, a pure module-level function of one task, so the tasks can be
run in this process, a process pool or on a Dask cluster
(:func:`ins_errors.analysis.engine.run_tasks`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

TYPICAL: dict[str, float] = {"deg/h": 0.01, "ug": 50.0, "arcsec": 20.0, "arcmin": 3.0,
                             "m/s": 0.5, "ppm": 100.0, "m": 10.0}
"""Typical size of a source, by the unit it is quoted in (navigation-grade instruments;
initial position errors of a GNSS-initialised alignment)."""

FACTORS: tuple[float, ...] = (0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0)
"""Magnitudes of the sweep, as multiples of the typical size (the large ones lift the
refined residual of weak sources above the direct run's rounding)."""

FIT_RANGE: tuple[float, float] = (1e-11, 0.3)
"""Residual ratios a slope fit may use: below it the direct run's rounding dominates,
above it strongly nonlinear runs saturate."""

FLOOR_MARGIN = 3.0
"""A point enters a slope fit only when its absolute residual (ratio × magnitude) is at
least this many times the smallest one of the sweep: an absolute floor (rounding of the
direct run, integration) stays constant while a true residual grows with magnitude."""

LINEAR_FLOOR = 1e-8
"""A linear residual below this ratio at every magnitude is rounding: the source acts
exactly linearly (nothing to fit)."""

MOTIONS: tuple[str, ...] = ("static", "great-circle")
"""Motions of a default map."""


@dataclass(frozen=True)
class ValidityTask:
    """One source on one motion: the sweep that :func:`run_validity_task` runs.

    Attributes
    ----------
    model : str
        Model name.
    motion : str
        Motion kind (``"static"``, ``"great-circle"``, ``"manoeuvre"``).
    source : str
        Error-source name.
    magnitudes : tuple of float
        Swept magnitudes, SI.
    hours : float
        Run length, h.
    step : float
        Integration step, s.
    method : str
        Integration scheme.
    parameters : tuple of (str, float)
        Model parameters set for the runs, SI (empty: the model's defaults).
    truth : str
        How a moving truth is computed: ``"auto"``, ``"interpolated"`` or ``"fine"``.
    motion_si : tuple of (str, object)
        The motion's description in exact SI text
        (:func:`ins_errors.numeric.motion_spec.in_si`), read by the worker without pint;
        empty: the defaults of ``motion``.
    typical : float, optional
        The source's :func:`typical_magnitude` (SI); None: worked out by the worker.
    """

    model: str
    motion: str
    source: str
    magnitudes: tuple[float, ...]
    hours: float = 24.0
    step: float = 2.0
    method: str = "rk4"
    parameters: tuple[tuple[str, float], ...] = ()
    truth: str = "auto"
    motion_si: tuple[tuple[str, Any], ...] = ()
    typical: float | None = None


@dataclass
class SourceValidity:
    """The sweep of one source on one motion, and what it says.

    Attributes
    ----------
    source, motion : str
    unit, display_unit : str
        SI unit of the magnitudes and the unit they are quoted in.
    magnitudes : list of float
        SI.
    quantity : str or None
        The error quantity followed (largest linear residual at the typical size).
    linear_ratio, refined_ratio : list of float
        |linear − direct| and |refined − direct| over |direct|, per magnitude.
    linear_slope, refined_slope : float or None
        Fitted log–log slopes (None when fewer than two points are in :data:`FIT_RANGE`).
    magnitude_1pct, magnitude_10pct : float or None
        Magnitudes (SI) at which the linear residual is 1 % and 10 % of the error.
    status : str
        ``"ok"``, ``"exactly linear"`` (residual at the rounding floor everywhere),
        ``"not fitted"``, ``"not excited"`` (no error at all) or ``"not seen by the linear
        model"`` (direct errors, but linear errors exactly zero at every magnitude).
    note : str
        Why a slope is missing (e.g. the refined residual never rises above the direct
        run's rounding).
    """

    source: str
    motion: str
    unit: str
    display_unit: str
    magnitudes: list[float]
    quantity: str | None
    linear_ratio: list[float] = field(default_factory=list)
    refined_ratio: list[float] = field(default_factory=list)
    linear_slope: float | None = None
    refined_slope: float | None = None
    magnitude_1pct: float | None = None
    magnitude_10pct: float | None = None
    status: str = "ok"
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                for k, v in asdict(self).items()}


def typical_magnitude(model, source: str) -> float:
    """Typical size of ``source`` (SI) from :data:`TYPICAL` and its quoting unit."""
    from ins_errors.units import parse_quantity

    info = model.source(source)
    shown = info.display_unit or info.unit
    if shown not in TYPICAL:
        from ins_errors.errors import InsErrorsError

        raise InsErrorsError(f"no typical size for {source}, quoted in {shown!r} (known: "
                             f"{', '.join(TYPICAL)}); choose the sources with --source NAME")
    return parse_quantity(f"{TYPICAL[shown]} {shown}", info.unit, source)


def source_example(model) -> str:
    """``NAME=VALUE`` of one of the model's own sources at its typical size, for messages
    (a constant source first, e.g. ``gyro_drift_x=0.01deg/h``)."""
    info = next((s for s in model.sources if s.kind == "constant"), model.sources[0])
    shown = info.display_unit or info.unit
    return f"{info.name}={TYPICAL.get(shown, 1):g}{shown}"


def validity_tasks(model, motions=MOTIONS, sources=None, hours: float = 24.0,
                   step: float = 2.0, method: str = "rk4",
                   factors: tuple[float, ...] = FACTORS,
                   parameters: Mapping[str, float] | None = None,
                   truth: str = "auto") -> list[ValidityTask]:
    """The independent tasks of a validity map: one per source and motion.

    Parameters
    ----------
    model : Model
        Loaded model.
    motions : sequence of str
        Motion kinds.
    sources : sequence of str, optional
        Error sources (default: all of the model's).
    hours, step, method
        Run length (h), integration step (s) and scheme of every run.
    factors : tuple of float
        Magnitudes as multiples of each source's typical size.
    parameters : mapping of str to float, optional
        Model parameters for every run, SI (:mod:`ins_errors.model_parameters`; default:
        the model's own values).
    truth : {"auto", "interpolated", "fine"}
        How the moving truths are computed
        (:func:`ins_errors.numeric.trajectories.trajectory`).
    """
    from ins_errors.numeric.motion_spec import in_si

    names = list(sources) if sources else [s.name for s in model.sources]
    for name in names:
        model.index("sources", name)
    typical = {name: typical_magnitude(model, name) for name in names}
    return [ValidityTask(model.key, motion, name, tuple(f * typical[name] for f in factors),
                         float(hours), float(step), method,
                         tuple((parameters or {}).items()), truth,
                         tuple(sorted(in_si({"kind": motion}).items())), typical[name])
            for motion in motions for name in names]


def motion_problems(model, motions, step: float,
                    parameters: Mapping[str, float] | None = None,
                    truth: str = "auto") -> dict[str, str]:
    """The motions of ``motions`` that ``model`` cannot follow, each with the reason.

    Each moving motion is tried for one step of ``step`` s (what the sweep would build
    first), so the answer is the trajectory code's own: e.g. a north-channel model
    without an east velocity follows a static base only, a model without a heading
    output no great circle.

    Returns
    -------
    dict of str to str
        Motion kind -> one-line reason (empty when the model follows them all).
    """
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.motion_spec import in_si, motion_profile

    p = model.parameter_vector(**dict(parameters or {}))
    problems = {}
    for motion in motions:
        profile = motion_profile(in_si({"kind": motion}))
        if profile.static:
            continue
        try:
            tr.trajectory(model, profile, step, step, p=p, truth=truth)
        except tr.MotionError as error:
            problems[motion] = str(error)
    return problems


def _fit(magnitudes: np.ndarray, ratios: np.ndarray) -> tuple[float, float] | None:
    """Slope and intercept of log(ratio) against log(magnitude).

    Uses the points in :data:`FIT_RANGE` clear of the absolute floor
    (:data:`FLOOR_MARGIN`), from the largest magnitude down for as long as the ratio keeps
    falling (local slope above 1/2).
    """
    order = np.argsort(magnitudes)
    m, r = magnitudes[order], ratios[order]
    absolute = r * m
    positive = absolute[absolute > 0]
    if positive.size == 0:
        return None
    above_floor = absolute >= FLOOR_MARGIN * positive.min()
    inside = np.flatnonzero((r > FIT_RANGE[0]) & (r < FIT_RANGE[1]) & above_floor)
    if inside.size < 2:
        return None
    keep = [inside[-1]]
    for k in inside[-2::-1]:
        if k != keep[-1] - 1 or not r[k] * (m[keep[-1]] / m[k]) ** 0.5 < r[keep[-1]]:
            break
        keep.append(k)
    if len(keep) < 2:
        return None
    slope, intercept = np.polyfit(np.log(m[keep]), np.log(r[keep]), 1)
    return float(slope), float(intercept)


def run_validity_task(task: ValidityTask) -> SourceValidity:
    """Run one sweep: direct, linear and refined at every magnitude, in one batch.

    Raises
    ------
    InsErrorsError
        A run that fails (e.g. the direct run leaves the model's domain at the largest
        magnitudes): the same class, its message prefixed with the source, the motion
        and the magnitudes, so that the map's one line says which sweep failed.
    """
    from ins_errors.errors import InsErrorsError

    try:
        return _run_validity_task(task)
    except InsErrorsError as error:
        if type(error).__init__ is not InsErrorsError.__init__:
            raise  # a class built otherwise than from its message
        unit = _unit_of(task)
        raise type(error)(f"validity of {task.source} on the {task.motion} motion "
                          f"({min(task.magnitudes):.3g} to {max(task.magnitudes):.3g} "
                          f"{unit}): {error}") from None


def _unit_of(task: ValidityTask) -> str:
    from ins_errors.numeric.model import load_model

    return load_model(task.model).source(task.source).unit


def _run_validity_task(task: ValidityTask) -> SourceValidity:
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import motion_profile

    model = load_model(task.model)
    info = model.source(task.source)
    profile = motion_profile(dict(task.motion_si) or {"kind": task.motion})
    trajectory = tr.trajectory(model, profile, task.hours * 3600.0, task.step,
                               p=model.parameter_vector(**dict(task.parameters)),
                               truth=task.truth)
    stride = max(1, min(trajectory.n_steps, round(300.0 / task.step)))
    while trajectory.n_steps % stride:  # the largest stride up to 5 min that divides the run
        stride -= 1
    record = stride * task.step
    cases = [{task.source: m} for m in task.magnitudes]
    comparisons = compare(model, trajectory, cases, method=task.method,
                          record_interval=record, integration_error=False,
                          validity_threshold=None,
                          labels=[f"{task.source} = {m!r} {info.unit}" for m in task.magnitudes])
    magnitudes = np.array(task.magnitudes)
    result = SourceValidity(task.source, task.motion, info.unit,
                            info.display_unit or info.unit, list(task.magnitudes), None)
    size = typical_magnitude(model, task.source) if task.typical is None else task.typical
    typical = int(np.argmin(np.abs(np.log(magnitudes / size))))
    worst = comparisons[typical].worst_linear
    if worst is None:
        result.status = "not excited"
        return result
    result.quantity = worst.quantity
    linear = np.array([c.metric(worst.quantity).linear_ratio for c in comparisons])
    refined = np.array([c.metric(worst.quantity).refined_ratio for c in comparisons])
    result.linear_ratio, result.refined_ratio = linear.tolist(), refined.tolist()
    if not any(np.any(curve) for c in comparisons for curve in c.linear.values()):
        result.status = "not seen by the linear model"
        result.note = (f"the linear errors stay exactly zero at every magnitude: "
                       f"{task.source} has zero columns in G and in the initial errors (no "
                       "equation uses it, or it enters only at second order)")
        return result
    fit = _fit(magnitudes, linear)
    if fit is None:
        result.status = ("exactly linear" if np.all(linear <= LINEAR_FLOOR) else
                         "not fitted")
        return result
    slope, intercept = fit
    result.linear_slope = slope
    refined_fit = _fit(magnitudes, refined)
    result.refined_slope = None if refined_fit is None else refined_fit[0]
    if refined_fit is None:
        result.note = ("refined residual stays at the direct run's rounding floor: its "
                       "slope cannot be measured")
    if slope > 0.2:
        result.magnitude_1pct = float(np.exp((math.log(0.01) - intercept) / slope))
        result.magnitude_10pct = float(np.exp((math.log(0.1) - intercept) / slope))
    return result


def validity_map(tasks: list[ValidityTask], engine: str = "serial",
                 progress: bool = False, scheduler: str | None = None,
                 workers: int | None = None) -> list[SourceValidity]:
    """Run every task (see :func:`ins_errors.analysis.engine.run_tasks`: ``engine``,
    ``scheduler`` of a running Dask cluster, ``workers`` of a local one), in task order."""
    from ins_errors.analysis.engine import run_tasks

    results: list[SourceValidity | None] = [None] * len(tasks)

    def keep(k: int, result: SourceValidity) -> None:
        results[k] = result

    run_tasks(run_validity_task, [(t,) for t in tasks],
              engine="dask" if scheduler else engine, scheduler=scheduler,
              workers=workers, on_result=keep, progress=progress, label="validity sweeps")
    return [r for r in results if r is not None]
