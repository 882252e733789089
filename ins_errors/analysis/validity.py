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

A sweep whose runs fail (the direct run leaves the model's domain at the largest
magnitudes, a motion through a pole) is a result, not the end of the map: it is run again
one magnitude at a time from the smallest, up to the first that fails, and its
:class:`SourceValidity` keeps the magnitudes below that one and the one-line reason
(status ``"failed"`` when none ran). The other sweeps are not touched.
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

MAX_JUDGED_VALUES = 2**25
"""Values a sweep's runs may keep (about 270 MB: the states of its ideal, direct, linear
and refined runs and their error curves, per magnitude and recorded sample). Within it
every step is recorded, so that each ratio is that of the largest differences over every
step; a longer run is judged on every k-th step, the smallest k that fits
(:func:`judged_stride`), and the map says so."""


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
        The magnitudes that ran, SI (all of the task's unless it failed; see
        ``failure``).
    quantity : str or None
        The error quantity followed (largest linear residual at the typical size).
    linear_ratio, refined_ratio : list of float
        |linear − direct| and |refined − direct| over |direct|, per magnitude.
    linear_slope, refined_slope : float or None
        Fitted log–log slopes (None when fewer than two points are in :data:`FIT_RANGE`).
    linear_fit, refined_fit : dict or None
        What each slope is fitted to (:class:`SlopeFit`): ``"magnitudes"``, the smallest
        and largest magnitude of its points, SI; ``"local_slopes"``, the smallest and
        largest slope between neighbouring points. None without a slope.
    magnitude_1pct, magnitude_10pct : float or None
        Magnitudes (SI) at which the linear residual is 1 % and 10 % of the error.
    status : str
        ``"ok"``, ``"exactly linear"`` (residual at the rounding floor everywhere),
        ``"not fitted"``, ``"not excited"`` (no error at all), ``"not seen by the linear
        model"`` (direct errors, but linear errors exactly zero at every magnitude) or
        ``"failed"`` (no magnitude ran: see ``failure``). A sweep that failed from some
        magnitude on has the status of the magnitudes below it.
    note : str
        Why a slope is missing (e.g. the refined residual never rises above the direct
        run's rounding).
    failure : str
        One-line reason why the sweep failed (the error of its first failing run); empty
        when every magnitude ran.
    failed_magnitudes : list of float
        The task's magnitudes without a result, SI, ascending: the first that failed
        and every larger one (empty when every magnitude ran).
    failed_at : float or None
        The magnitude (SI) whose run, alone, failed with ``failure``; None when the
        failure is not one magnitude's (the true motion itself failed, or the batch
        failed otherwise than by leaving the model's domain) or nothing failed.
    extrapolated : dict of str to str
        ``"magnitude_1pct"`` / ``"magnitude_10pct"`` -> how that magnitude lies beyond
        what ran: ``"extrapolated"`` (the fitted line outside the magnitudes swept) or
        ``"past half a turn"`` (an angle source's magnitude beyond π rad, 180°, which no
        angle error has: 200° is −160°). The magnitude itself stays the fit's, SI.
    judged_every_s : float or None
        Interval of the samples the ratios' largest differences are taken over, s: the
        step (every step), or a multiple of it for a run longer than
        :data:`MAX_JUDGED_VALUES` allows (:func:`judged_stride`); None when the true
        motion failed before any run.
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
    linear_fit: dict[str, list[float]] | None = None
    refined_fit: dict[str, list[float]] | None = None
    magnitude_1pct: float | None = None
    magnitude_10pct: float | None = None
    status: str = "ok"
    note: str = ""
    failure: str = ""
    failed_magnitudes: list[float] = field(default_factory=list)
    failed_at: float | None = None
    extrapolated: dict[str, str] = field(default_factory=dict)
    judged_every_s: float | None = None

    @property
    def failed(self) -> bool:
        """True when some magnitude of the sweep has no result (see ``failure``)."""
        return bool(self.failure)

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
                   truth: str = "auto",
                   start: Mapping[str, str] | None = None) -> list[ValidityTask]:
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
    start : mapping of str to str, optional
        Where every motion starts, as a motion description writes it (``latitude``,
        ``longitude``, ``heading``, ``speed``, ``height`` -> text with unit, e.g.
        ``{"latitude": "30 deg"}``); each motion takes the settings that apply to it
        (:func:`applicable`); default: the motions' defaults.
    """
    from ins_errors.numeric.motion_spec import in_si

    check_run(hours, step)
    names = list(sources) if sources else [s.name for s in model.sources]
    for name in names:
        model.index("sources", name)
    typical = {name: typical_magnitude(model, name) for name in names}
    return [ValidityTask(model.key, motion, name, tuple(f * typical[name] for f in factors),
                         float(hours), float(step), method,
                         tuple((parameters or {}).items()), truth,
                         tuple(sorted(in_si({"kind": motion,
                                             **applicable(start, motion)}).items())),
                         typical[name])
            for motion in motions for name in names]


def check_run(hours: float, step: float) -> None:
    """Refuse a run length or step that no sweep could use, before any work.

    Parameters
    ----------
    hours : float
        Length of each run, h (> 0).
    step : float
        Integration step, s (> 0, a whole number of them in the run).

    Raises
    ------
    InsErrorsError
        Not positive or not finite (``--hours``), or a step the run cannot be cut into
        (:class:`~ins_errors.errors.StepError`, naming the nearest run lengths that can).
    """
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric.integrators import step_count

    if not (math.isfinite(hours) and hours > 0):
        raise InsErrorsError(f"--hours must be positive, got {hours:g}")
    step_count(hours * 3600.0, step)


def applicable(start: Mapping[str, str] | None, motion: str) -> dict[str, str]:
    """The settings of ``start`` that a motion of kind ``motion`` uses (a static base has
    no speed: :data:`~ins_errors.numeric.motion_spec.APPLIES_TO`)."""
    from ins_errors.numeric.motion_spec import APPLIES_TO

    return {key: text for key, text in (start or {}).items()
            if motion in APPLIES_TO.get(key, (motion,))}


def motion_problems(model, motions, step: float,
                    parameters: Mapping[str, float] | None = None,
                    truth: str = "auto",
                    start: Mapping[str, str] | None = None) -> dict[str, str]:
    """The motions of ``motions`` that ``model`` cannot follow, each with the reason
    (each from ``start``, as :func:`validity_tasks` builds them).

    Each moving motion is tried for one step of ``step`` s (what the sweep would build
    first), so the answer is the trajectory code's own: e.g. a north-channel model
    without an east velocity follows a static base only, a model without a heading
    output no great circle.

    Returns
    -------
    dict of str to str
        Motion kind -> one-line reason (empty when the model follows them all).

    Raises
    ------
    EarthParameterError
        The model's Earth parameters make any flight impossible.
    """
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.motion_spec import in_si, motion_profile

    p = model.parameter_vector(**dict(parameters or {}))
    problems = {}
    for motion in motions:
        profile = motion_profile(in_si({"kind": motion, **applicable(start, motion)}))
        if profile.static:
            continue
        try:
            tr.trajectory(model, profile, step, step, p=p, truth=truth)
        except tr.EarthParameterError:
            raise  # the parameters are wrong, not the motion: no other motion helps
        except tr.MotionError as error:
            problems[motion] = str(error)
    return problems


@dataclass(frozen=True)
class SlopeFit:
    """A log–log line through some of a sweep's points.

    Attributes
    ----------
    slope, intercept : float
        log(ratio) = slope · log(magnitude) + intercept (magnitude SI).
    magnitudes : tuple of float
        The smallest and largest magnitude (SI) of the points the line is fitted to.
    local_slopes : tuple of float
        The smallest and largest slope between neighbouring fitted points: far apart,
        the points follow no single power law and the slope is an average.
    """

    slope: float
    intercept: float
    magnitudes: tuple[float, float]
    local_slopes: tuple[float, float]


SPREAD_NOTED = 1.0
"""Local slopes of a fit further apart than this are said under the map's table: the
fitted slope then averages different powers (a rounding floor at the small magnitudes,
higher orders at the large ones)."""


def _fit(magnitudes: np.ndarray, ratios: np.ndarray) -> SlopeFit | None:
    """The line of log(ratio) against log(magnitude).

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
    local = np.diff(np.log(r[keep])) / np.diff(np.log(m[keep]))  # keep runs downwards
    return SlopeFit(float(slope), float(intercept), (float(m[keep[-1]]), float(m[keep[0]])),
                    (float(local.min()), float(local.max())))


def run_validity_task(task: ValidityTask) -> SourceValidity:
    """Run one sweep: direct, linear and refined at every magnitude, in one batch.

    A sweep whose runs fail with one of the tool's own errors
    (:class:`~ins_errors.errors.InsErrorsError`) is returned as such, never raised: when
    the batch leaves the model's domain (:class:`~ins_errors.errors.DomainError`), the
    magnitudes are run again one at a time from the smallest, up to the first that fails
    (each case's arithmetic is the same alone as in a batch, so those that ran give the
    numbers they would in a batch of their own), and the result is that of the
    magnitudes below it, with ``failure`` and ``failed_magnitudes`` set; any other error
    (e.g. the true motion reaches a pole) fails the whole sweep (status ``"failed"``).
    """
    from ins_errors.errors import DomainError, InsErrorsError
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import motion_profile

    model = load_model(task.model)
    info = model.source(task.source)
    result = SourceValidity(task.source, task.motion, info.unit,
                            info.display_unit or info.unit, list(task.magnitudes), None)
    ascending = sorted(task.magnitudes)
    try:
        profile = motion_profile(dict(task.motion_si) or {"kind": task.motion})
        trajectory = tr.trajectory(model, profile, task.hours * 3600.0, task.step,
                                   p=model.parameter_vector(**dict(task.parameters)),
                                   truth=task.truth)
    except InsErrorsError as error:
        return _failed(result, [], [], ascending, error, None)
    # the ratios are those of the largest differences over every step (a 5-min record
    # missed the peaks between its samples: 1.6 % of a damped INS's ratio)
    stride = judged_stride(model, trajectory.n_steps, len(task.magnitudes))
    result.judged_every_s = stride * task.step

    def run(magnitudes):
        return compare(model, trajectory, [{task.source: m} for m in magnitudes],
                       method=task.method, record_interval=stride * task.step,
                       integration_error=False, validity_threshold=None,
                       labels=[f"{task.source} = {m!r} {info.unit}" for m in magnitudes],
                       warn=False)

    size = typical_magnitude(model, task.source) if task.typical is None else task.typical

    def explained(result: SourceValidity) -> SourceValidity:
        if result.status == "not excited":
            result.note = unexcited_note(model, trajectory, task.source)
        return result

    try:
        return explained(_analyse(result, task.magnitudes, run(task.magnitudes), size))
    except DomainError:
        pass  # one magnitude at a time, below
    except InsErrorsError as error:
        return _failed(result, [], [], ascending, error, None)
    ran: list = []
    for k, magnitude in enumerate(ascending):
        try:
            (comparison,) = run([magnitude])
        except InsErrorsError as error:
            return explained(_failed(result, ascending[:k], ran, ascending[k:], error,
                                     magnitude, size))
        ran.append(comparison)
    return explained(_analyse(result, ascending, ran, size))  # (each ran alone)


def judged_stride(model, n_steps: int, cases: int) -> int:
    """Steps between the samples a sweep's ratios are judged on: 1 (every step) when the
    records of ``cases`` magnitudes over ``n_steps`` steps fit :data:`MAX_JUDGED_VALUES`,
    else the smallest stride that divides the run and fits (a record must divide the
    run). Where none lies within four times the least that fits, the largest divisor
    below is taken if it keeps the records within four times the allowance; otherwise
    the smallest divisor above, however coarse (a run of a prime number of steps:
    judged at its ends only, which the map's note says): never beyond four times
    :data:`MAX_JUDGED_VALUES`.

    Parameters
    ----------
    model : Model
    n_steps : int
        Steps of the run.
    cases : int
        Magnitudes run in one batch.

    Returns
    -------
    int
    """
    from ins_errors.numeric.simulate import error_quantities

    n, ne = len(model.states), len(model.error_states)
    per_sample = cases * (n + 3 * ne + 3 * len(error_quantities(model)[0]))
    least = math.ceil((n_steps + 1) * per_sample / MAX_JUDGED_VALUES)
    if least <= 1:
        return 1
    above = next((k for k in range(least, min(n_steps, 4 * least) + 1)
                  if n_steps % k == 0), None)
    if above is not None:
        return above
    below = next(k for k in range(least - 1, 0, -1) if n_steps % k == 0)
    if 4 * below >= least:
        return below
    return next(k for k in range(4 * least + 1, n_steps + 1) if n_steps % k == 0)


def unexcited_note(model, trajectory, source: str) -> str:
    """Why ``source`` produces no error on ``trajectory``, in one clause.

    A source whose column of G (a constant source) or of the initial-error matrix (an
    initial one) is zero at the start of the motion with the run's parameters, and not
    zero when a damping gain at 0 (``Parameter(..., damping_gain=True)``) is set, acts
    only through that gain: the note names it and how to set it
    (:func:`~ins_errors.numeric.linear_system.undamped_remedy`). Otherwise the terms the
    source enters vanish on this motion (a scale-factor error where the specific force
    along its axis is zero).

    Parameters
    ----------
    model : Model
    trajectory : Trajectory
        The motion of the sweep (its start state, inputs, initial conditions and
        parameters).
    source : str
        The error source.

    Returns
    -------
    str
    """
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric.linear_system import undamped_gains, undamped_remedy

    k = model.index("sources", source)
    p = np.asarray(trajectory.parameters, dtype=float)
    constant = model.sources[k].kind == "constant"

    def column(values: np.ndarray) -> np.ndarray:
        if constant:
            matrix = model.source_matrix(trajectory.start_state, trajectory.start_inputs,
                                         values)
        else:
            matrix = model.initial_error_matrix(trajectory.initial_conditions,
                                                trajectory.start_inputs, values)
        return np.asarray(matrix, dtype=float)[:, k]

    names = [q.name for q in model.parameters]
    gains = undamped_gains(model, p)

    def excites(trial: list[str]) -> bool:
        changed = p.copy()
        changed[[names.index(g) for g in trial]] = 1.0  # (any value but 0)
        return bool(np.any(column(changed)))

    reasons: list[str] = []
    try:
        if gains and not np.any(column(p)):
            reasons = [g for g in gains if excites([g])] or (
                gains if len(gains) > 1 and excites(gains) else [])
    except InsErrorsError:
        reasons = []
    where = "G" if constant else "the initial errors"
    if reasons:
        return (f"not excited: {source} enters only through damping gains, at 0 here (its "
                f"column of {where} is zero){undamped_remedy(model, p, reasons)}")
    return (f"not excited: no magnitude of {source} gives any error on this motion (the "
            "terms it enters vanish here, e.g. a scale-factor error where the specific "
            "force along its axis is zero)")


def _failed(result: SourceValidity, magnitudes: list[float], comparisons: list,
            failed: list[float], error: Exception, failed_at: float | None,
            size: float = 1.0) -> SourceValidity:
    """``result`` of the ``magnitudes`` that ran (with their comparisons; ``size`` the
    typical one, :func:`_analyse`) and of the ``failed`` ones, failed with ``error``
    (its first line)."""
    text = str(error).strip().splitlines()
    if magnitudes:
        _analyse(result, magnitudes, comparisons, size)
    else:
        result.magnitudes, result.status = [], "failed"
    result.failure = text[0] if text else type(error).__name__
    result.failed_magnitudes = [float(m) for m in failed]
    result.failed_at = None if failed_at is None else float(failed_at)
    return result


def _fit_record(fit: SlopeFit) -> dict[str, list[float]]:
    """What a result keeps of a fit besides its slope (JSON-ready)."""
    return {"magnitudes": list(fit.magnitudes), "local_slopes": list(fit.local_slopes)}


def _analyse(result: SourceValidity, magnitudes, comparisons, size: float
             ) -> SourceValidity:
    """Fill ``result`` from the comparisons of ``magnitudes`` (SI), the error quantity
    being the one worst followed at the magnitude closest to the typical ``size``."""
    magnitudes = np.array(magnitudes, dtype=float)
    result.magnitudes = magnitudes.tolist()
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
                       f"{result.source} has zero columns in G and in the initial errors "
                       "(no equation uses it, or it enters only at second order)")
        return result
    fit = _fit(magnitudes, linear)
    if fit is None:
        result.status = ("exactly linear" if np.all(linear <= LINEAR_FLOOR) else
                         "not fitted")
        return result
    slope, intercept = fit.slope, fit.intercept
    result.linear_slope = slope
    result.linear_fit = _fit_record(fit)
    refined_fit = _fit(magnitudes, refined)
    result.refined_slope = None if refined_fit is None else refined_fit.slope
    result.refined_fit = None if refined_fit is None else _fit_record(refined_fit)
    if refined_fit is None:
        result.note = ("refined residual stays at the direct run's rounding floor: its "
                       "slope cannot be measured")
    if slope > 0.2:
        result.magnitude_1pct = float(np.exp((math.log(0.01) - intercept) / slope))
        result.magnitude_10pct = float(np.exp((math.log(0.1) - intercept) / slope))
        result.extrapolated = {
            key: how for key, how in (
                (key, beyond_sweep(value, result.unit, magnitudes))
                for key, value in (("magnitude_1pct", result.magnitude_1pct),
                                   ("magnitude_10pct", result.magnitude_10pct)))
            if how}
    return result


HALF_TURN = math.pi
"""rad: no angle error is larger in size (an error of 200° is one of −160°), so a
validity magnitude of an angle source beyond it is not a size the source can have."""


def beyond_sweep(value: float, unit: str, magnitudes) -> str:
    """How a fitted magnitude lies beyond the sweep: ``"past half a turn"`` for an angle
    (SI unit ``rad``) larger than :data:`HALF_TURN`, ``"extrapolated"`` outside the
    magnitudes that ran (SI), else ``""``."""
    if unit == "rad" and abs(value) > HALF_TURN:
        return "past half a turn"
    ran = np.asarray(magnitudes, dtype=float)
    if ran.size and not ran.min() * (1 - 1e-9) <= value <= ran.max() * (1 + 1e-9):
        return "extrapolated"
    return ""


def failed_task(task: ValidityTask, error: Exception) -> SourceValidity:
    """The result of a task that raised ``error`` outside its runs (e.g. in a worker
    that could not load the model): failed, no magnitude ran."""
    from ins_errors.numeric.model import load_model

    info = load_model(task.model).source(task.source)
    result = SourceValidity(task.source, task.motion, info.unit,
                            info.display_unit or info.unit, [], None)
    return _failed(result, [], [], sorted(task.magnitudes), error, None)


def failures(results: list[SourceValidity]) -> list[dict[str, Any]]:
    """The sweeps that failed, in map order: source, motion, the magnitudes that ran and
    those without a result (SI), the magnitude whose run failed (or None) and the
    one-line reason (``"reason"``)."""
    return [{"source": r.source, "motion": r.motion, "unit": r.unit,
             "magnitudes_run": r.magnitudes, "magnitudes_failed": r.failed_magnitudes,
             "failed_at": r.failed_at, "reason": r.failure}
            for r in results if r.failed]


def validity_map(tasks: list[ValidityTask], engine: str = "serial",
                 progress: bool = False, scheduler: str | None = None,
                 workers: int | None = None) -> list[SourceValidity]:
    """Run every task (see :func:`ins_errors.analysis.engine.run_tasks`: ``engine``,
    ``scheduler`` of a running Dask cluster, ``workers`` of a local one), in task order.

    A task that fails is a result too (:func:`run_validity_task`; a task that raises one
    of the tool's own errors outside its runs: :func:`failed_task`), and the others run
    on; :func:`failures` lists them. A fault that is not the task's own (a worker that
    dies repeatedly, a bug) and Ctrl-C stop the map."""
    from ins_errors.analysis.engine import run_tasks

    results: list[SourceValidity | None] = [None] * len(tasks)

    def keep(k: int, result: SourceValidity) -> None:
        results[k] = result

    def failed(k: int, error: Exception) -> None:
        results[k] = failed_task(tasks[k], error)

    run_tasks(run_validity_task, [(t,) for t in tasks],
              engine="dask" if scheduler else engine, scheduler=scheduler,
              workers=workers, on_result=keep, on_failure=failed, progress=progress,
              label="validity sweeps")
    return [r for r in results if r is not None]
