"""Direct vs linear vs refined: metrics per error quantity and a Markdown summary.

For every reported quantity (platform angles, Δφ, Δλ, Δχ, Δω_N, Δω_E, Δv_N, Δv_E for the
orthodromic model) and every case:

* ``max_direct``: max |direct error| over the run;
* ``linear_difference``: max |linear − direct|, and ``linear_ratio`` = that / ``max_direct``;
* ``refined_difference`` and ``refined_ratio`` likewise for the refined run (the truncated
  quadratic error equations; infinite where its outputs are not finite);
* ``direct_integration_error`` and ``linear_integration_error``: the estimated
  integration error of the direct and of the linear error curves (step doubling,
  :mod:`ins_errors.numeric.accuracy`), to be read beside the linear-vs-direct difference;
  ``refined_integration_error`` likewise for the refined curve (when it ran), to be read
  beside the refined-vs-direct difference.

The residual of an angle (unit rad: latitude, longitude, heading, attitude, platform
angles) is a difference on the circle, wrapped to ±π (:func:`residual`): a linear heading
error of +176.8° beside a direct one of −124.3° misses by 58.9°, not by 301°.

Each case also carries ``warnings``: when the integration error exceeds 10 % of the
linear-vs-direct difference (that of the direct and refined runs: 10 % of the
refined-vs-direct difference) or 1 % of the error (naming a step that would do), when
the linear/direct ratio exceeds the validity threshold (5 % by default, naming about
the magnitude at which it would be 1 %, from the measured scaling of runs at smaller
magnitudes), when an initial angle error is given past half a turn, and
when the refined run misses more than the linear one or diverges
(:func:`add_refined_warnings`).

A quantity counts as *excited* (its ratios are judged) when its direct error is above
the rounding floor of its unit (:data:`NOISE_FLOOR`) and the linear model moves it at
first order. Each quantity is judged on its own: it is not compared with the other
quantities of the case (a platform tilt of 0.01 arcmin is no less first order for sharing
the unit rad with a latitude error of 3 arcmin). A quantity whose linear error stays at 0
(to within :data:`SECOND_ORDER_FRACTION` of its direct error) while other quantities of
the case move is one the source moves only at second order on this motion (e.g. a
coupling through tan φ at the equator): it is marked ``second_order_only``, named in a
warning and not judged, instead of a "validity" ratio of 100 % at any magnitude.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field

import numpy as np

from ins_errors.errors import InsErrorsError, name_list, unknown_name
from ins_errors.numeric import (
    accuracy,
    brief_warnings,
    read_back,
    sampled_maxima,
    step_period,
)
from ins_errors.numeric.integrators import whole_steps
from ins_errors.numeric.model import Model, as_model
from ins_errors.numeric.simulate import ErrorCurves, Simulation, error_quantities, simulate
from ins_errors.numeric.trajectories import Trajectory

NOISE_FLOOR: dict[str, float] = {"rad": 1e-10, "rad/s": 1e-14, "m/s": 1e-6, "m": 1e-3, "1": 1e-10}
"""Direct errors below these (SI) are at the level of accumulated double rounding of
quantities of order one (direction cosines) or hundreds of m/s (absolute velocities)."""

SECOND_ORDER_FRACTION = 1e-6
"""A quantity whose largest linear error is at most this fraction of its largest direct
error (exactly 0, or rounding of a coupling that vanishes on the motion: 1e-9 measured)
is moved only at second order: the linear model has nothing of it to judge."""

SECOND_ORDER_NAMED = 1e-3
"""A quantity moved only at second order is named in a warning when its direct error
reaches this fraction of the largest direct error of its kind in the case (platform
angles with platform angles, output errors with output errors of the same unit): a
second-order azimuth of 1e-5 arcsec beside tilts of arcseconds is only marked in the
table."""

VALIDITY_THRESHOLD = 0.05
"""Default linear/direct ratio above which a comparison warns that the linear model is
leaving its validity."""


def validity_ratio(value: float | str | None, what: str = "validity_threshold"
                   ) -> float | None:
    """The validity threshold :func:`compare` takes, as a ratio (None: no check).

    A number is a fraction in (0, 1]: ``0.05`` is 5 %. A larger number is refused (``5``
    would silently be 500 %, a check that never warns), as are 0, negative numbers and
    NaN (which would warn always or never). A string with a unit of ratio is read by
    :func:`~ins_errors.units.parse_quantity` (``"5%"``, ``"5 percent"``, ``"500 ppm"``):
    it may name a ratio above 1, up to
    :data:`~ins_errors.units.VALIDITY_RATIO_CEILING` (as the command line's
    ``--validity-threshold``); a string holding a bare number is read as that number.

    Raises
    ------
    InsErrorsError
        One line naming ``what`` and what it takes.
    """
    if value is None:
        return None
    if isinstance(value, CheckedRatio):
        return float(value)
    fraction = f"{what} is a fraction (0.05 for 5 %) or a percentage ('5%')"
    if isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            from ins_errors.units import VALIDITY_RATIO_CEILING, parse_quantity

            ratio = parse_quantity(value, "1", what)
            if not 0 < ratio < VALIDITY_RATIO_CEILING:
                raise InsErrorsError(f"{what} {value!r} is outside the accepted range, "
                                     f"above 0 % and below {100 * VALIDITY_RATIO_CEILING:g} %"
                                     ) from None
            return ratio
    elif isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InsErrorsError(f"{fraction}, got {type(value).__name__} {value!r:.40}")
    else:
        number = float(value)
    if not 0 < number <= 1:
        percent = (f": for {number:g} % give {number / 100:g} or '{number:g}%'"
                   if 1 < number < 100 else "")
        raise InsErrorsError(f"{what} is a fraction in (0, 1] (0.05 for 5 %), got "
                             f"{value!r:.40}{percent}")
    return number


class CheckedRatio(float):
    """A validity ratio already checked against the command line's range (above 0,
    below :data:`~ins_errors.units.VALIDITY_RATIO_CEILING`: the command line's
    ``--validity-threshold``, a scenario's ``validity_threshold``, up to 1000 %):
    :func:`validity_ratio` takes it as it is, the same bits, above 1 too, where it
    refuses a plain number."""


AGREEMENT_FLOOR = 1e-6
"""Relative linear-vs-direct differences below this count as full agreement: the
integration error is not held against them (only against the error itself)."""


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
    direct_integration_error: float | None = None
    linear_integration_error: float | None = None
    refined_integration_error: float | None = None
    second_order_only: bool = False

    @property
    def integration_error(self) -> float | None:
        """The larger of the direct and linear integration-error estimates (SI): the
        integration error of the two runs whose difference ``linear_difference`` is."""
        errors = [e for e in (self.direct_integration_error, self.linear_integration_error)
                  if e is not None]
        return max(errors) if errors else None

    @property
    def refined_runs_integration_error(self) -> float | None:
        """The larger of the direct and refined integration-error estimates (SI): the
        integration error of the two runs whose difference ``refined_difference`` is;
        None without a refined estimate."""
        if self.refined_integration_error is None or self.direct_integration_error is None:
            return None
        return max(self.direct_integration_error, self.refined_integration_error)


@dataclass(eq=False)
class Comparison:
    """One case (one set of error sources) compared along one trajectory.

    Compared by identity (``==`` is ``is``; hashable): its curves are arrays, whose
    ``==`` has no single truth value. Compare two results' numbers through
    :meth:`to_dict` (the summary, no curves) and ``numpy.array_equal`` on the curves.

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
    warnings : list of str
        One line each: integration error too large (with a step that would do), linear
        model beyond its validity threshold (with the magnitude where it would be 1 %).
    suggested_step : float or None
        A step (s) whose integration error would pass, when the current one does not.
    one_percent_scale : float or None
        Factor on every source magnitude at which the worst linear/direct ratio would be
        1 % (from the measured scaling), when the validity warning was given.
    suggested_method : str or None
        ``"rk4"`` when the rectangle method would need more steps than a run may take and
        ``suggested_step`` is RK4's own step.
    integration_order : float or None
        Order of convergence the runs at three steps show (see
        :func:`add_integration_errors`), None when not measured or the errors are at
        rounding level.
    shown : tuple of str or None
        The quantities the reader asked for (a scenario's ``[outputs] quantities``): the
        worst ratios and the warnings judge only these. None: every quantity.
    integration_steps : tuple of float
        Steps (s) of the runs made again for the integration-error estimate
        (:func:`integration_errors_by_reruns`) that completed, in the order made: first
        the pair's other run, then the one for the observed order. Empty when none was
        made (the warnings say why).
    negligible_cause : str or None
        What an integration-error estimate below
        :data:`~ins_errors.numeric.accuracy.RELEVANT` of the error is, as the third run
        shows (:func:`negligible_cause`): ``"step error"`` (it falls as τ^p, the scheme's
        order), ``"rounding"`` (it does not fall as the step is refined), or None (no
        third run, or an order above the scheme's: not told).
    refined_warning : str or None
        ``"diverged"`` when the refined run's residual exceeds the largest direct error
        and the linear run's residual for some judged quantity, else ``"worse than
        linear"`` when it exceeds twice the linear run's residual (and 1e-6 of the
        error) (:func:`add_refined_warnings`); else None.
    refined_departure : float or None
        Time (s) from which the refined run is off that way (its residual first beyond
        the bound the warning names).
    maxima_note : str or None
        When the run records every few steps and its maxima (over the recorded samples)
        may be 1 % or more below the run's own: by how much at most, for F's fastest
        oscillation at the start (:mod:`ins_errors.numeric.sampled_maxima`); shown as a note, not a
        warning. None otherwise.
    brief : dict of str to str
        The terminal's short form of some of ``warnings`` (the integration-error ones),
        keyed by the full text: what is wrong, how big, the cure that makes sense
        (:mod:`~ins_errors.numeric.brief_warnings`). ``markdown_summary(..., brief=True)``
        prints them; ``warnings``, the report and the JSON keep the full text.
    """

    label: str
    sources: dict[str, float]
    metrics: list[Metric]
    times: np.ndarray = field(repr=False)
    direct: dict[str, np.ndarray] = field(repr=False)
    linear: dict[str, np.ndarray] = field(repr=False)
    refined: dict[str, np.ndarray] = field(repr=False)
    warnings: list[str] = field(default_factory=list)
    suggested_step: float | None = None
    one_percent_scale: float | None = None
    shown: tuple[str, ...] | None = None
    integration_order: float | None = None
    suggested_method: str | None = None
    integration_steps: tuple[float, ...] = ()
    negligible_cause: str | None = None
    refined_warning: str | None = None
    refined_departure: float | None = None
    maxima_note: str | None = None
    brief: dict[str, str] = field(default_factory=dict, repr=False)

    def metric(self, quantity: str) -> Metric:
        """The metric of one quantity."""
        for m in self.metrics:
            if m.quantity == quantity:
                return m
        raise unknown_name("error quantity", quantity, [m.quantity for m in self.metrics])

    @property
    def excited(self) -> list[Metric]:
        """Metrics of the excited quantities (among the shown ones, if chosen)."""
        return [m for m in self.metrics
                if m.excited and (self.shown is None or m.quantity in self.shown)]

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
                "worst_integration_error_ratio": self.worst_integration_ratio,
                "warnings": list(self.warnings),
                "suggested_step_s": self.suggested_step,
                "one_percent_scale": self.one_percent_scale,
                "suggested_method": self.suggested_method,
                "integration_order_observed": self.integration_order,
                "integration_error_negligible": self.integration_negligible,
                "integration_error_at_rounding": self.integration_at_rounding,
                "integration_error_below_relevant": self.negligible_cause,
                "refined_warning": self.refined_warning,
                "refined_departure_s": self.refined_departure,
                "integration_rerun_steps_s": list(self.integration_steps),
                "maxima_note": self.maxima_note,
                "metrics": [_clean(asdict(m)) for m in self.metrics]}

    @property
    def integration_negligible(self) -> bool:
        """True when the integration-error estimate is below
        :data:`~ins_errors.numeric.accuracy.RELEVANT` of the error: it is not judged (no
        warning, ``integration_order`` None), whether it is the scheme's step error or
        rounding (:attr:`negligible_cause` tells them apart where it can)."""
        worst = self.worst_integration_ratio
        return worst is not None and worst < accuracy.RELEVANT

    @property
    def integration_at_rounding(self) -> bool:
        """True when the estimate is negligible (:attr:`integration_negligible`) and the
        runs at three steps show it is rounding, not the scheme's error: it does not
        fall as τ^p when the step is refined (:attr:`negligible_cause`)."""
        return self.integration_negligible and self.negligible_cause == "rounding"

    @property
    def worst_integration_ratio(self) -> float | None:
        """Largest integration-error estimate over the max direct error, excited quantities."""
        ratios = [m.integration_error / m.max_direct for m in self.excited
                  if m.integration_error is not None and m.max_direct > 0]
        return max(ratios) if ratios else None


def _value(metric: Metric | None, attribute: str) -> float | None:
    return None if metric is None else getattr(metric, attribute)


def _clean(row: dict) -> dict:
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
            for k, v in row.items()}


def _ratio(difference: float, reference: float) -> float:
    return difference / reference if reference > 0 else (0.0 if difference == 0 else math.inf)


def residual(curve: np.ndarray, direct: np.ndarray, unit: str) -> np.ndarray:
    """``curve − direct`` of one quantity's curves (a model's, or a run's at another
    step); for an angle (unit rad) the difference on the circle, wrapped to [−π, π).

    The output angles' curves are each wrapped to ±π already (latitude, longitude,
    heading, roll, pitch): their plain difference jumps by 2π where one of them crosses
    ±π and the other does not (a linear longitude error past 180° beside a direct one of
    −124°: 301° apart, 59° on the circle). Platform angles are angles of a rotation,
    where a turn is no error either. Latitude and pitch lie within ±90°, so their direct
    errors stay within ±π: wrapping their residuals changes nothing while a model's
    error is within half a turn of the direct one, and past that the model is far out of
    its range anyway.

    Parameters
    ----------
    curve, direct : numpy.ndarray
        Curves of the same shape, SI.
    unit : str
        SI unit of the quantity (``"rad"``: wrapped).

    Returns
    -------
    numpy.ndarray
        The residual, same shape, SI.
    """
    d = curve - direct
    return (d + np.pi) % (2 * np.pi) - np.pi if unit == "rad" else d


def _largest(values: np.ndarray) -> float:
    """max |values|; infinite when any value is not finite (a refined run whose state
    left its output map's domain, or overflowed)."""
    if not np.all(np.isfinite(values)):
        return math.inf
    return float(np.max(np.abs(values)))


def metrics_of(direct: ErrorCurves, linear: ErrorCurves, refined: ErrorCurves | None,
               case: int = 0) -> list[Metric]:
    """Per-quantity metrics of one batch member.

    Each quantity is judged on its own (see the module's notes): *excited* when its direct
    error is above the rounding floor of its unit and the linear model moves it at first
    order; ``second_order_only`` when it is above the floor, the linear run moves the case
    and leaves this quantity at 0 (to :data:`SECOND_ORDER_FRACTION` of its direct error).
    Residuals of angles are differences on the circle (:func:`residual`); a refined
    residual that is not finite somewhere is infinite.
    """
    rows = []
    # where nothing is linear at all, the source is unseen (add_validity_warnings says so)
    linear_moves = bool(np.any(linear.values[:, :, case]))
    for k, (name, unit) in enumerate(zip(direct.names, direct.units, strict=True)):
        d = direct.values[k, :, case]
        peak = float(np.max(np.abs(d)))
        lin = float(np.max(np.abs(residual(linear.values[k, :, case], d, unit))))
        ref = None if refined is None else _largest(residual(refined.values[k, :, case], d,
                                                             unit))
        large = bool(peak > NOISE_FLOOR.get(unit, 0.0))
        first = float(np.max(np.abs(linear.values[k, :, case]))) > SECOND_ORDER_FRACTION * peak
        second = large and linear_moves and not first
        rows.append(Metric(name, unit, peak, lin, _ratio(lin, peak), ref,
                           None if ref is None else _ratio(ref, peak), large and not second,
                           second_order_only=second))
    return rows


def add_maxima_notes(comparisons: Sequence[Comparison], sim: Simulation,
                     eigenvalues: np.ndarray | None = None) -> None:
    """Set :attr:`Comparison.maxima_note` when the run records every few steps and its
    maxima over the samples may be :data:`~ins_errors.numeric.sampled_maxima.NOTED` or
    more below the run's own (nothing is read when it records every step): the maxima
    miss the peaks of lightly damped oscillations only (a damped loop's own is gone
    within a period or two). ``eigenvalues``: F's at the start, when already read."""
    if sim.stride == 1:
        return
    tau = sim.trajectory.tau
    if eigenvalues is None:
        eigenvalues = sampled_maxima.start_eigenvalues(sim.model, sim.trajectory)
    omega = sampled_maxima.fastest_oscillation(eigenvalues, lightly_damped=True)
    text = sampled_maxima.note(sim.stride * tau, tau, omega)
    for comparison in comparisons:
        comparison.maxima_note = text


def case_label(model: Model, sources: dict[str, float]) -> str:
    """``name = value display_unit`` for each non-zero source (an angle of a degree or
    more in degrees: :func:`~ins_errors.units.format_readable`)."""
    from ins_errors.units import format_readable

    parts = []
    for name, value in sources.items():
        info = model.sources[model.index("sources", name)]
        shown = format_readable(value, info.unit, info.display_unit or info.unit)
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
            method: str = "rk4", record_interval: float | None = None,
            refined: bool = True, jit: bool = True, progress: bool = False,
            platform: str = "exact", integration_error: bool = True,
            validity_threshold: float | str | None = VALIDITY_THRESHOLD,
            labels: Sequence[str] | None = None,
            quantities: Sequence[str] | None = None, warn: bool = True) -> list[Comparison]:
    """Run direct, linear (and refined) for several cases in one batch and compare.

    Parameters
    ----------
    model : Model
    trajectory : Trajectory
        The true motion.
    cases : sequence of dict, dict or numpy.ndarray
        Error sources per case, ``{name: SI value}`` (one mapping is one case; see
        :func:`~ins_errors.numeric.simulate.source_cases`).
    method : {"rk4", "euler"}
        Scheme; ``"euler"`` is the manual's rectangle method.
    record_interval : float, optional
        Seconds between recorded samples.
    refined : bool
        Also run the second-order model.
    progress : bool
        Show a progress bar over the run, then one over each rerun of the
        integration-error check (its steps, labelled ``integration-error check: run at
        2τ = 2 s``) and a one-line status while the validity runs are made (on a
        terminal only).
    platform : {"exact", "small_angle"}
        Platform kinematics of the direct run (see :func:`~ins_errors.numeric.simulate.simulate`).
    integration_error : bool
        Estimate the integration error (one more run at twice the step) and warn when it
        is too large.
    validity_threshold : float, str or None
        Warn when the worst linear/direct ratio exceeds it (one more run at half the
        magnitudes measures the scaling): a fraction in (0, 1] (default 0.05, i.e.
        5 %), or a percentage string such as ``"5%"`` (which may exceed 100 %, up to
        1000 %); None: never. Anything else (``5``, NaN, a negative number) is refused
        (:func:`validity_ratio`).
    labels : sequence of str, optional
        Label of each case; default: :func:`case_label` (which converts each source to
        its display unit through pint, a 0.15-0.5 s import in a process that has no
        other use for it, such as a sweep's worker).
    quantities : sequence of str or str, optional
        The quantities the reader wants (:attr:`Comparison.shown`): the worst ratios and
        the warnings consider only these (one string is one quantity). Default: every
        quantity.
    warn : bool
        Also issue each case's :attr:`Comparison.warnings` as a Python warning
        (:class:`~ins_errors.errors.InsErrorsWarning`, starting with the case's label), so
        a notebook shows them; the command line, which prints them with its tables,
        passes False.

    Returns
    -------
    list of Comparison
        One per case.
    """
    model = as_model(model, "compare")
    validity_threshold = validity_ratio(validity_threshold)  # before any run
    read_back.refuse_mismatch(model, trajectory)  # outputs vs initial-state map, one line
    if quantities is not None:
        quantities = name_list(quantities, "compare: quantities")
        known = error_quantities(model)[0]
        for q in quantities:  # an unknown quantity: one line with suggestions, not a run
            if q not in known:
                raise unknown_name("error quantity", q, known)
    if labels is not None:  # before any run: one label per case
        from ins_errors.errors import ShapeError
        from ins_errors.numeric.simulate import source_cases

        count = source_cases(model, cases).shape[1]
        if isinstance(labels, str) or len(labels) != count:
            shown = "a string" if isinstance(labels, str) else f"{len(labels)} labels"
            raise ShapeError(f"compare: labels must be one per case ({count}), got {shown}")
    parts = ("real", "linear", "refined") if refined else ("real", "linear")
    if progress and integration_error:  # its bar ends before the reruns start: say so
        from ins_errors.numeric.simulate import bar_label

        progress = f"{bar_label(parts)} (then the {accuracy.CHECK_LABEL}'s reruns)"
    sim = simulate(model, trajectory, cases, method=method,
                   record_interval=record_interval, parts=parts, jit=jit, progress=progress,
                   platform=platform)
    comparisons = comparisons_of(sim, labels)
    eigenvalues = sampled_maxima.start_eigenvalues(model, trajectory)
    # the step must resolve every oscillation; the maxima miss only lightly damped ones'
    too_long = step_period.warning(trajectory.tau,
                                   sampled_maxima.fastest_oscillation(eigenvalues),
                                   sim.stride * trajectory.tau)
    for comparison in comparisons if too_long else ():
        comparison.warnings.append(too_long)
    add_maxima_notes(comparisons, sim, eigenvalues)
    add_half_turn_warnings(comparisons, model)
    if quantities is not None:
        for comparison in comparisons:
            for q in quantities:
                comparison.metric(q)  # unknown quantity -> one line, with suggestions
            comparison.shown = tuple(quantities)
    from ins_errors.progress import stage

    if integration_error:  # reruns at other steps (as long as the run itself, or longer)
        # each rerun has a bar over its own steps, labelled as the check's
        add_integration_errors(comparisons, sim, jit=jit, progress=progress)
    if validity_threshold is not None:
        with stage("validity: the runs again at other magnitudes", enabled=progress):
            add_validity_warnings(comparisons, sim, validity_threshold, jit=jit)
    add_refined_warnings(comparisons)
    add_growth_warnings(comparisons, sim)
    add_unexcited_warnings(comparisons, sim, trajectory)
    add_second_order_warnings(comparisons)
    if warn:
        import warnings

        from ins_errors.errors import InsErrorsWarning

        for comparison in comparisons:
            for text in comparison.warnings:
                warnings.warn(f"{comparison.label}: {text}", InsErrorsWarning, stacklevel=2)
    return comparisons


REFINED_DIVERGED = 1.0
"""A refined run whose residual exceeds this share of a judged quantity's largest direct
error (and the linear run's residual) has diverged: it is further from the direct run
than the error itself is from zero."""

REFINED_WORSE = 2.0
"""A refined run whose residual exceeds this factor times the linear run's (and
:data:`AGREEMENT_FLOOR` of the error) misses more than the linear model: its own
quadratic terms add error. Below it the two residuals are of one size (a residual of
higher order than both models: a 10° heading error's latitude, 0.74 % and 0.73 %)."""


def add_refined_warnings(comparisons: Sequence[Comparison]) -> None:
    """Warn where the refined run misses more than the linear one, or diverged.

    The refined run integrates the truncated quadratic error equations
    ``ė₂ = F e₂ + G w + S(x, u, e₂, w)``: an ODE of its own, whose quadratic terms feed
    back (through a damping loop, a Schuler loop) and can run away where the direct run
    stays bounded (a 10 °/h azimuth gyro bias on strapdown_ned with a damped vertical
    channel: a refined height of 2,200 km after 24 h, the direct run's 25 m). A case
    gets one warning when, for a judged quantity (:attr:`Comparison.excited`), the
    refined run *diverged*: its residual exceeds :data:`REFINED_DIVERGED` times the
    largest direct error and the linear run's residual (the refined curve leaves the
    range the direct run spans by more than its width); or else when it *misses more
    than the linear model*: its residual exceeds :data:`REFINED_WORSE` times the linear
    one and :data:`AGREEMENT_FLOOR` of the error (a smaller one is agreement to
    rounding). The warning names the quantity with the largest refined ratio among them
    and the time from which the refined residual is beyond the bound (the larger of the
    direct error's size and the linear run's largest residual for a divergence, the
    linear run's largest residual times :data:`REFINED_WORSE` else), the earliest over
    those quantities; it sets :attr:`Comparison.refined_warning` and
    :attr:`Comparison.refined_departure`.
    """
    for comparison in comparisons:
        if not comparison.refined:
            continue
        judged = [m for m in comparison.excited if m.refined_difference is not None]
        diverged = [m for m in judged if m.refined_ratio > REFINED_DIVERGED
                    and m.refined_difference > m.linear_difference]
        worse = [m for m in judged if m.refined_difference > REFINED_WORSE * m.linear_difference
                 and m.refined_ratio > AGREEMENT_FLOOR]
        if not (diverged or worse):
            continue
        named = diverged or worse
        start = min(_first_beyond(comparison, m, max(m.linear_difference,
                                                     REFINED_DIVERGED * m.max_direct)
                                  if diverged else REFINED_WORSE * m.linear_difference)
                    for m in named)
        worst = max(named, key=lambda m: m.refined_ratio)
        comparison.refined_warning = "diverged" if diverged else "worse than linear"
        comparison.refined_departure = start
        others = len(named) - 1
        more = (f" (and {others} more quantit{'y' if others == 1 else 'ies'})"
                if others else "")
        if diverged:
            reach = ("is not finite (its state left the output map's domain)"
                     if not math.isfinite(worst.refined_difference) else
                     f"reaches {worst.refined_ratio:.3g}× its largest direct error, "
                     f"{_shown_size(worst.refined_difference, worst.unit)} against "
                     f"{_shown_size(worst.max_direct, worst.unit)}")
            comparison.warnings.append(
                f"the refined (second-order) run diverged from about {_when(start)}: "
                f"refined − direct of {worst.quantity} {reach}, linear − direct "
                f"{worst.linear_ratio:.3g}×{more}; its quadratic terms are beyond their "
                "range here (it integrates the truncated quadratic error equations, "
                "which can run away where the direct run stays bounded): trust the direct "
                "run, not the refined ratios")
        else:
            comparison.warnings.append(
                f"the refined (second-order) run misses more than the linear one from "
                f"about {_when(start)}: refined − direct reaches "
                f"{_percent(worst.refined_ratio)} of {worst.quantity}'s largest error, "
                f"linear − direct {_percent(worst.linear_ratio)}{more}; its quadratic "
                "terms are beyond their range here (a second-order term fed back, e.g. "
                "by a damping loop): the refined ratios do not say what a second-order "
                "model would achieve; trust the direct run")


def _first_beyond(comparison: Comparison, metric: Metric, bound: float) -> float:
    """The first recorded time (s) at which the refined residual of ``metric``'s
    quantity exceeds ``bound`` or is not finite (the last time if never)."""
    q = metric.quantity
    gap = np.abs(residual(comparison.refined[q], comparison.direct[q], metric.unit))
    beyond = ~(gap <= bound)  # NaN counts as beyond
    times = comparison.times
    return float(times[int(np.argmax(beyond))] if beyond.any() else times[-1])


def _when(seconds: float) -> str:
    """A time of the run, roughly: ``"15.2 h"``, ``"12.5 min"``, ``"40 s"``."""
    if seconds >= 3600.0:
        return f"{seconds / 3600.0:.3g} h"
    if seconds >= 60.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds:.3g} s"


def add_second_order_warnings(comparisons: Sequence[Comparison]) -> None:
    """Name the (shown) quantities the case moves only at second order
    (:attr:`Metric.second_order_only`): the linear model gives 0 for them (to rounding),
    so their linear/direct ratio is 100 % at any magnitude and is not judged. Only those
    that matter beside their own kind are named (:data:`SECOND_ORDER_NAMED`); the
    others are marked in the table only."""
    for comparison in comparisons:
        largest: dict[tuple[bool, str], float] = {}
        for m in comparison.metrics:
            largest[_kind(m)] = max(largest.get(_kind(m), 0.0), m.max_direct)
        second = [m for m in comparison.metrics if m.second_order_only
                  and (comparison.shown is None or m.quantity in comparison.shown)
                  and m.max_direct >= SECOND_ORDER_NAMED * largest[_kind(m)]]
        if second:
            sizes = ", ".join(f"{m.quantity} {_shown_size(m.max_direct, m.unit)}"
                              for m in second)
            comparison.warnings.append(
                f"moved only at second order on this motion (the linear model gives 0, to "
                f"rounding; the direct run reaches {sizes}): a linear/direct ratio of 100 % at any "
                "magnitude, not judged" + ("; the refined model's ratio shows how well the "
                                            "second-order terms account for it"
                                            if comparison.refined else "")
                + " (a model whose equations are not differentiable on this motion, |x| "
                "or sign(x) at 0, gives the same exact 0 for a first-order effect: "
                "halving the sources then halves, not quarters, the direct error)")


def _kind(metric: Metric) -> tuple[bool, str]:
    """A quantity's kind: a platform angle or an output error (``delta_<output>``), and
    its unit."""
    return metric.quantity.startswith("delta_"), metric.unit


def _shown_size(value: float, unit: str) -> str:
    """A size in the display unit of its SI unit (``"0.12 arcsec"``)."""
    from ins_errors.units import display_scale

    factor, shown = display_scale(unit)
    return f"{value * factor:.3g} {shown}"


def add_unexcited_warnings(comparisons: Sequence[Comparison], sim: Simulation,
                           trajectory: Trajectory) -> None:
    """Say why a case gives no error at all: each of its sources' reason
    (:func:`~ins_errors.analysis.validity.unexcited_note`: a damping gain at 0 that the
    source enters through, or terms that vanish on this motion), instead of a table of
    "no" with no word on it."""
    from ins_errors.analysis.validity import unexcited_note

    names = [s.name for s in sim.model.sources]
    for b, comparison in enumerate(comparisons):
        if comparison.excited or not comparison.metrics:
            continue
        for k in np.flatnonzero(sim.sources[:, b]):
            comparison.warnings.append(unexcited_note(sim.model, trajectory, names[k]))


RK4_HOW = '--method rk4, or method = "rk4" in a scenario\'s [run]'
"""How a warning tells both a command line and a scenario file to use RK4."""

RECTANGLE_STEPS_ADVISED = brief_warnings.STEPS
"""Steps beyond which a rectangle-method step is not suggested (ten million: several
seconds of CPU a run, where RK4 reaches the same accuracy in far fewer steps): RK4's is,
with ``suggested_method`` "rk4"; the terminal's short warning and the full one (JSON,
report.md) draw the same line."""


def add_growth_warnings(comparisons: Sequence[Comparison], sim: Simulation) -> None:
    """Warn when the linear error equations at the start grow exponentially over the run.

    A growing mode (an undamped vertical channel, a sign slip that turns the Schuler loop
    into an exponential) makes every error of the run grow by e^(rate t), whatever the
    sources; the comparison's ratios then say little by themselves. The warning
    (:func:`~ins_errors.numeric.linear_system.growth_warning`) gives the e-folding time
    of F's fastest growing mode at t = 0 and the factor over the run, names the command
    that names the mode and any damping gain left at 0
    (:func:`~ins_errors.numeric.linear_system.undamped_remedy`). On a moving base F
    changes along the motion and a mode of F at the start need not grow along the run:
    a case gets the warning there only when its own linear errors grow at
    :data:`~ins_errors.numeric.linear_system.GROWTH_SEEN` of the mode's rate or more
    (:func:`observed_growth`).

    Parameters
    ----------
    comparisons : sequence of Comparison
        Gets one warning each when the mode grows by
        :data:`~ins_errors.numeric.linear_system.GROWTH_WARNED` (3) e-foldings or more
        over the run.
    sim : Simulation
        The runs (their trajectory's state and inputs at t = 0 give F).
    """
    from ins_errors.model_lookup import command_name
    from ins_errors.numeric.linear_system import (
        GROWTH_SEEN,
        growth_rate,
        growth_warning,
        start_state_matrix,
        undamped_remedy,
    )

    duration = float(sim.times[-1])
    if not comparisons or duration <= 0:
        return
    f = start_state_matrix(sim.model, sim.trajectory)
    text = growth_warning(f, duration, command_name(sim.model),
                          "the ratios say little by themselves",
                          remedy=undamped_remedy(sim.model, sim.trajectory.parameters),
                          static=sim.trajectory.constant)
    if text is None:
        return
    rate = growth_rate(f)
    for comparison in comparisons:
        # on a moving base F changes along the motion: a mode of F frozen at the start
        # (orthodromic's delta_V_eta on an eastbound great circle, ×e every 9 h) need
        # not grow along the run; the warning stands where the run's own linear errors
        # grow at a good part of that rate
        if sim.trajectory.constant or observed_growth(comparison) >= GROWTH_SEEN * rate:
            comparison.warnings.append(text)




def observed_growth(comparison: Comparison) -> float:
    """Growth rate (1/s) of the run's linear errors: for each quantity, the log of its
    largest |error| over the second half of the run over its largest over the first
    half, divided by the half run; the largest over the quantities (−inf where no
    quantity moves in both; +inf where one is finite in the first half and not in the
    second). Whole halves, so that a slow beat (the Earth period, the
    Foucault period) does not read as growth."""
    times = comparison.times
    end = float(times[-1])
    early, late = times <= end / 2, times >= end / 2
    rates = [-math.inf]
    if early.any() and late.any():
        for curve in comparison.linear.values():
            a = float(np.max(np.abs(curve[early])))
            b = float(np.max(np.abs(curve[late])))
            if np.isfinite(a) and not np.isfinite(b):
                rates.append(math.inf)   # overflowed (or NaN) in the second half
            elif a > 0 and b > 0 and np.isfinite(a):
                rates.append(math.log(b / a) / (end / 2))
    return max(rates)


def add_integration_errors(comparisons: Sequence[Comparison], sim: Simulation,
                           jit: bool = True, progress: bool = False) -> None:
    """Estimate each quantity's integration error by step doubling; warn where too large.

    Runs the direct and linear error runs of ``sim`` again at twice its step when every
    recorded sample lies on that grid (an even recording stride), else at half its step
    (a static base, a profile's motion, or any motion under the rectangle method), so
    that the estimate covers every recorded sample, the last one included; it fills
    ``direct_integration_error`` / ``linear_integration_error`` of every metric. When
    ``sim`` ran the refined part, that rerun runs it too and fills
    ``refined_integration_error`` (None where a refined curve is not finite, or where the
    rerun with it fails and is made again without it); the third run below does not
    (the observed order is the direct and linear runs'), nor does any rerun of a
    comparison without a refined run, so those cost what they did. One more
    run at four times the finest step of the pair gives the observed order of the
    scheme: far from the scheme's order, the estimate is outside its asymptotic range and
    the case says so. A case gets a warning (and ``suggested_step``) when, for an excited
    quantity, the larger estimate exceeds 1 % of the error or 10 % of the
    linear-vs-direct difference (the latter only when that difference is above
    :data:`AGREEMENT_FLOOR` of the error), or the larger of the direct and refined
    estimates does either for the refined-vs-direct difference. The estimate itself is
    :func:`integration_errors_by_reruns`, which callers with runs of their own (the
    studies) use as well. With ``progress``, each rerun shows a bar over its own steps
    labelled as the check's (:func:`~ins_errors.numeric.accuracy.rerun_label`), as the
    run itself does (on a terminal only).
    """
    trajectory, method = sim.trajectory, sim.method
    grids: dict[float, Trajectory | None] = {}

    def grid(factor: float) -> Trajectory | None:
        # the doubled-step trajectory is built once for 2τ and 4τ; no recursion: a
        # closure that calls itself is a reference cycle, which kept this trajectory
        # (and its coarser ones) alive after the call until the next full collection
        if factor < 1:  # τ/2, and τ/4 from τ/2
            finer, step = trajectory, 1.0
            while step > factor:
                step /= 2
                if step not in grids:
                    grids[step] = None if finer is None else accuracy.halved(finer, method)
                finer = grids[step]
            return finer
        coarse, step = trajectory, 1.0
        while step < factor:
            step *= 2
            if step not in grids:
                grids[step] = accuracy.coarsened(coarse)
            coarse = grids[step]
        return coarse

    # the refined part only in the pair's other run, the first one asked for (the third
    # run gives the observed order, which is the direct and linear runs')
    refined = [sim.refined is not None]

    def rerun(factor: float, every: int) -> tuple[ErrorCurves, ...] | None:
        traj = grid(factor)
        if traj is None:
            return None
        with_refined, refined[0] = refined[0], False

        def run(parts: tuple[str, ...]) -> Simulation:
            return simulate(sim.model, traj, sim.sources, method=method,
                            record_interval=every * traj.tau, parts=parts,
                            jit=jit, platform=sim.platform,
                            progress=accuracy.rerun_label(factor, trajectory.tau)
                            if progress else False)

        if with_refined:
            try:
                made = run(("real", "linear", "refined"))
                return made.direct_errors(), made.linear_errors(), made.refined_errors()
            except InsErrorsError:
                pass  # e.g. the refined run left its domain at this step: without it
        made = run(("real", "linear"))
        return made.direct_errors(), made.linear_errors()

    fine = (sim.direct_errors(), sim.linear_errors())
    if sim.refined is not None:
        fine = (*fine, sim.refined_errors())
    integration_errors_by_reruns(comparisons, fine,
                                 trajectory.n_steps, trajectory.tau, sim.stride, method,
                                 rerun, lambda: _rk4_step(sim, jit),
                                 breaks=accuracy.motion_breaks(trajectory))


Rerun = Callable[[float, int], "tuple[ErrorCurves, ...] | None"]
"""``rerun(factor, every)``: the (direct, linear) error curves of the same cases run again
— or (direct, linear, refined): the refined curves are estimated where both runs of the
pair have them —
at step ``factor`` τ (``factor`` 2 or 4: over the first ``⌊N/factor⌋`` of its steps, the
same motion on the coarser grid; ``factor`` 1/2 or 1/4: over ``2N`` or ``4N`` steps, only
asked for when ``breaks`` are given), recorded every ``every`` of its own steps; None when
the run at τ/2 (τ/4) cannot be made (a motion that cannot be generated again at τ/2). A run
that fails raises :class:`InsErrorsError`."""


def integration_errors_by_reruns(comparisons: Sequence[Comparison],
                                 fine: tuple[ErrorCurves, ...], n_steps: int,
                                 tau: float, stride: int, method: str, rerun: Rerun,
                                 rk4_step: Callable[[], float | None] | None = None,
                                 breaks: np.ndarray | None = None) -> None:
    """The integration-error estimate of :func:`add_integration_errors`, from any runs.

    A run at 2τ when the recording stride is even (every sample on its grid), else at
    τ/2 (every sample on its grid too), gives the Richardson estimate over every recorded
    sample; a third run (4τ, or 2τ beside τ/2) gives the observed order of the scheme
    (:attr:`Comparison.integration_order`), and the warnings of
    :func:`_integration_warning` follow (too large, or not reliable at this step, with a
    step the command line accepts). Where the run at τ/2 cannot be made, the run at 2τ
    is compared on the samples the two share (or nothing is estimated, and the cases say
    why).

    RK4 keeps its order over a step only where the motion is smooth: on a motion with
    dense ``breaks`` (a motion file's sample times, where its splines' third derivative
    jumps) a rerun whose steps straddle breaks that the run's steps end on is less
    accurate than the run by far more than the step ratio says, and the estimate would be
    orders of magnitude too large. When the coarse grids of the plan above straddle
    breaks of the run's grid in more than :data:`~ins_errors.numeric.accuracy.DENSE_BREAKS`
    of their steps, the reruns are at τ/2 (the estimate) and τ/4 (the observed order)
    instead, whose grids hold every point of the run's. When the run's own steps straddle
    breaks that densely, its error is not of the scheme's order and nothing is estimated:
    the cases say so and name a step that keeps the breaks. A few breaks (a manoeuvre's
    leg joins) leave the plan as it is.

    Parameters
    ----------
    comparisons : sequence of Comparison
        One per batch member of the curves; their metrics get the estimates.
    fine : tuple of ErrorCurves
        (direct, linear) error curves of the run, shape (Q, N / stride + 1, B), or
        (direct, linear, refined): ``refined_integration_error`` is then estimated where
        the pair's other run gives refined curves too (the observed order and the
        integration-error ratio are the direct and linear runs').
    n_steps, stride : int
        Steps of the run and steps between two recorded samples.
    tau : float
        Step of the run, s.
    method : {"rk4", "euler"}
        Scheme of every run.
    rerun : callable
        ``rerun(factor, every)``, see :data:`Rerun`.
    rk4_step : callable, optional
        RK4's own suggested step for these cases (or None), asked for when the rectangle
        method would need more steps than a run may take.
    breaks : numpy.ndarray, optional
        Times (s) where the motion is less smooth
        (:func:`~ins_errors.numeric.accuracy.motion_breaks`); None: smooth or unknown.

    Every comparison's :attr:`Comparison.integration_steps` gets the steps of the reruns
    that completed.
    """
    made: list[float] = []

    def recorded(factor: float, every: int) -> tuple[ErrorCurves, ...] | None:
        curves = rerun(factor, every)
        if curves is not None:
            made.append(factor * tau)
        return curves

    try:
        _by_reruns(comparisons, fine, n_steps, tau, stride, method, recorded, rk4_step,
                   breaks)
    finally:
        for comparison in comparisons:
            comparison.integration_steps = tuple(made)


def _by_reruns(comparisons: Sequence[Comparison], fine: tuple[ErrorCurves, ...],
               n_steps: int, tau: float, stride: int, method: str, rerun: Rerun,
               rk4_step: Callable[[], float | None] | None,
               breaks: np.ndarray | None = None) -> None:
    """The body of :func:`integration_errors_by_reruns` (same parameters)."""
    if n_steps < 2:
        return _not_estimated(comparisons, "the run has a single step")
    # a motion whose breaks are dense (a motion file's samples): RK4 keeps its order
    # only on grids that hold them (the rectangle method's order 1 is not affected)
    on_grid, straddled = accuracy.breaks_on_grid(
        breaks if accuracy.ORDERS[method] > 1 else None, tau, n_steps)
    if accuracy.dense(straddled.size, n_steps):
        return _not_estimated(comparisons, _straddling(breaks, straddled, tau, stride))
    spacing = (_kept(breaks, tau) if accuracy.dense(on_grid.size + straddled.size, n_steps)
               else None)  # suggested steps keep dense breaks
    if any(accuracy.dense(accuracy.straddled_by(on_grid, f, n_steps), n_steps // f)
           for f in ((2, 4) if stride % 2 == 0 else (2,))):
        return _finer_reruns(comparisons, fine, tau, stride, method, rerun, rk4_step,
                             spacing)
    try:
        if stride % 2 == 0:  # every sample on the grid of 2τ: runs at τ, 2τ, 4τ
            runs = [fine, rerun(2, stride // 2)]
            scale = 1.0 / (2 ** accuracy.ORDERS[method] - 1)
            factor = 4
        else:
            half = rerun(0.5, 2 * stride)
            if half is None:
                return _pairs_on_common_samples(comparisons, fine, n_steps, tau, stride,
                                                method, rerun)
            runs = [half, fine]  # at τ/2 and τ
            scale = 2 ** accuracy.ORDERS[method] / (2 ** accuracy.ORDERS[method] - 1)
            factor = 2
    except InsErrorsError as error:
        return _not_estimated(comparisons, f"the run at another step failed ({error})")
    # the third run, on the samples it shares with the others: the observed order
    every, fine_i, coarse_i = accuracy.sampling(stride, factor, n_steps)
    orders, failed = None, None
    if len(fine_i) > 1 and n_steps // factor >= 1:
        try:
            orders = (rerun(factor, every), fine_i, coarse_i)
        except InsErrorsError as error:  # e.g. leaves the domain: far from asymptotic
            failed = f"the run at τ = {factor * tau:g} s fails: {error}"
    _fill(comparisons, runs, scale, orders, False, tau, method, stride, rk4_step, failed,
          spacing)


def negligible_cause(order: float | None, scheme_order: int) -> str | None:
    """What a negligible integration-error estimate (below
    :data:`~ins_errors.numeric.accuracy.RELEVANT` of the error) is, from the order the
    runs at three steps show: ``"step error"`` when it is the scheme's (within
    :data:`~ins_errors.numeric.accuracy.ORDER_TOLERANCE`: the estimate falls as τ^p, so
    it is the scheme's error, however small), ``"rounding"`` when it is lower (the gap
    between the finer runs does not fall as it should: it is held up by rounding, which
    grows, not shrinks, with the number of steps), None when it is higher or not
    measured (not told)."""
    if order is None:
        return None
    if abs(order - scheme_order) <= accuracy.ORDER_TOLERANCE:
        return "step error"
    return "rounding" if order < scheme_order else None


REFINED_PART = 2
"""Index of the refined curves in a rerun's tuple (direct, linear, refined)."""

PART_ATTRIBUTES = ("direct_integration_error", "linear_integration_error",
                   "refined_integration_error")
"""The :class:`Metric` attribute each part of a run's curves (direct, linear, refined)
fills."""


def _estimated_parts(finer: tuple[ErrorCurves, ...], coarser: tuple[ErrorCurves, ...]
                     ) -> list[tuple[int, str]]:
    """(index, Metric attribute) of the parts both runs of a pair hold: direct and linear
    always, refined when both have it (a third curve, not None)."""
    parts = [(0, PART_ATTRIBUTES[0]), (1, PART_ATTRIBUTES[1])]
    if (len(finer) > REFINED_PART and len(coarser) > REFINED_PART
            and finer[REFINED_PART] is not None and coarser[REFINED_PART] is not None):
        parts.append((REFINED_PART, PART_ATTRIBUTES[REFINED_PART]))
    return parts


def _estimate(value: float, part: int) -> float | None:
    """A part's estimate as stored: the refined one is None where it is not finite (a
    refined run that left its range at one of the steps: nothing to estimate); the
    direct and linear ones as they are."""
    if part == REFINED_PART and not math.isfinite(value):
        return None
    return value


def _fill(comparisons: Sequence[Comparison], runs: list[tuple[ErrorCurves, ...]],
          scale: float, orders: tuple | None, finest: bool, tau: float, method: str,
          stride: int, rk4_step: Callable[[], float | None] | None,
          failed: str | None, spacing: float | None = None) -> None:
    """Set the estimates ``scale |y_finer − y_coarser|`` of the pair ``runs`` (finer
    first), the observed order from the third run of ``orders`` = (curves, indices of
    the pair's samples, indices of its own) — finer than the pair when ``finest``, else
    coarser — and warn (:func:`_integration_warning`, whose step divides ``spacing``)."""
    for b, comparison in enumerate(comparisons):
        observed = []
        for part, attribute in _estimated_parts(runs[0], runs[1]):
            finer, coarser = runs[0][part], runs[1][part]
            for k, metric in enumerate(comparison.metrics):
                gap = np.abs(residual(finer.values[k, :, b], coarser.values[k, :, b],
                                         metric.unit))
                setattr(metric, attribute, _estimate(float(np.max(gap)) * scale, part))
                if (part == REFINED_PART or orders is None or not metric.excited
                        or metric.max_direct <= 0):
                    continue  # the observed order is the direct and linear runs'
                third_curves, fi, ci = orders  # near: the finer pair; far: the coarser
                other = np.abs(residual(
                    (finer if finest else coarser).values[k, fi, b],
                    third_curves[part].values[k, ci, b], metric.unit))
                near, far = float(np.max(gap[fi])), float(np.max(other))
                q = accuracy.order_observed(*((far, near) if finest else (near, far)))
                if q is not None:
                    observed.append((getattr(metric, attribute) / metric.max_direct, q,
                                     metric))
        relevant = [o for o in observed if o[0] > accuracy.RELEVANT
                    and o[2].integration_error > NOISE_FLOOR.get(o[2].unit, 0.0)]
        comparison.integration_order = (max(relevant, key=lambda o: o[0])[1]
                                        if relevant else None)
        if observed and comparison.integration_negligible:  # not judged; but what is it?
            comparison.negligible_cause = negligible_cause(
                max(observed, key=lambda o: o[0])[1], accuracy.ORDERS[method])
        worst = comparison.worst_integration_ratio
        _integration_warning(comparison, tau, method, stride * tau, rk4_step,
                             failed if worst is not None and worst > accuracy.RELEVANT
                             else None, spacing)


def _finer_reruns(comparisons: Sequence[Comparison], fine: tuple[ErrorCurves, ...],
                  tau: float, stride: int, method: str, rerun: Rerun,
                  rk4_step: Callable[[], float | None] | None,
                  spacing: float | None = None) -> None:
    """The estimate from runs at τ/2 and τ/4, whose grids hold every point of the run's
    (a motion with breaks that coarser grids would straddle): Richardson's rule on τ/2
    and τ, the observed order from τ/4, τ/2 and τ."""
    try:
        half = rerun(0.5, 2 * stride)
        if half is None:
            return _not_estimated(comparisons, "the motion has breaks (e.g. the samples of "
                                  "a motion file) that runs at 2τ would straddle, and it "
                                  "cannot be generated again at τ/2")
    except InsErrorsError as error:
        return _not_estimated(comparisons, f"the run at τ/2 failed ({error})")
    p = accuracy.ORDERS[method]
    orders, failed = None, None
    try:
        quarter = rerun(0.25, 4 * stride)
        if quarter is not None:
            every = np.arange(half[0].values.shape[1])
            orders = (quarter, every, every)
    except InsErrorsError as error:
        failed = f"the run at τ = {tau / 4:g} s fails: {error}"
    _fill(comparisons, [half, fine], 2 ** p / (2 ** p - 1), orders, True, tau, method,
          stride, rk4_step, failed, spacing)


def _kept(breaks: np.ndarray, tau: float) -> float:
    """A length a suggested step must divide to keep the breaks that the run's steps
    keep: the breaks' spacing when they are evenly spaced, else the run's step."""
    d = accuracy.spacing(breaks)
    return tau if d is None else d


def _straddling(breaks: np.ndarray, straddled: np.ndarray, tau: float, stride: int) -> str:
    """Why nothing is estimated when the run's steps straddle the motion's breaks, with
    a step that keeps them when the breaks are evenly spaced."""
    d = accuracy.spacing(breaks)
    text = (f"the steps of τ = {tau:g} s straddle {straddled.size} of the motion's breaks "
            f"(the first at t = {straddled[0]:g} s; a motion file's sample times, where its "
            "splines' third derivative jumps): RK4 loses its order there, and step "
            "doubling would not measure the error")
    if d is None:  # e.g. a log's jittered sample times: no step lands on all of them
        return text + ("; the sample times are not on a regular grid, so no step keeps "
                       "them all: resample the log to a regular clock (t = 0, d, 2d, ...) "
                       "and run at a step that divides d")
    interval = stride * tau
    for k in range(max(1, math.ceil(d / tau - accuracy.BREAK_TOLERANCE)), 1025):
        step = float(np.format_float_positional(d / k, precision=12, trim="-"))
        if (whole_steps(d, step) is not None and whole_steps(interval, step) is not None):
            text_step = np.format_float_positional(step, unique=True, trim="-")
            return text + (f"; a step that divides the breaks' spacing of {d:g} s keeps "
                           f"them: τ = {text_step} s")
    return text + f"; choose a step that divides the breaks' spacing of {d:g} s"


NOTHING_SHARED = "the run at twice the step shares no recorded sample with this run but the start"
"""Why a step-doubling estimate is not made: a comparison at t = 0 alone would read 0."""


def _not_estimated(comparisons: Sequence[Comparison], why: str) -> None:
    """Say in every case of ``comparisons`` that its integration error is not estimated,
    and ``why``."""
    for c in comparisons:
        c.warnings.append(f"integration error not estimated: {why}")


def _pairs_on_common_samples(comparisons: Sequence[Comparison],
                             fine: tuple[ErrorCurves, ...], n_steps: int, tau: float,
                             stride: int, method: str, rerun: Rerun) -> None:
    """Step doubling on the samples a run at 2τ shares with the run (odd recording
    stride, a motion that cannot be generated at τ/2); says so when that leaves out the
    last sample, and gives no estimate when only the start is shared."""
    every, fine_i, _ = accuracy.sampling(stride, 2, n_steps)
    if len(fine_i) < 2:
        return _not_estimated(comparisons, f"{NOTHING_SHARED} (choose an even number of "
                              "steps between samples)")
    try:
        coarse = rerun(2, every)
    except InsErrorsError as error:
        return _not_estimated(comparisons, f"the run at twice the step failed ({error})")
    times = tau * stride * fine_i
    estimate_integration_errors(comparisons, fine, coarse, stride, every, n_steps, tau,
                                method)
    if fine_i[-1] * stride != n_steps:
        for c in comparisons:
            c.warnings.append(f"integration error estimated only up to t = {times[-1]:g} s "
                              f"({len(fine_i)} of {n_steps // stride + 1} samples)")


def estimate_integration_errors(comparisons: Sequence[Comparison],
                                fine: tuple[ErrorCurves, ...],
                                coarse: tuple[ErrorCurves, ...], stride: int,
                                coarse_stride: int, n_steps: int, tau: float,
                                method: str) -> None:
    """Fill the integration errors of ``comparisons`` from runs at τ and 2τ; warn.

    The plain step-doubling estimate on the samples two runs share, without the order
    check (:func:`integration_errors_by_reruns` makes that where it can). When the two
    runs share no recorded sample but the start, nothing is estimated (a warning says
    so): a comparison at t = 0 alone would report an error of 0.

    Parameters
    ----------
    comparisons : sequence of Comparison
        One per batch member of the curves.
    fine, coarse : tuple of ErrorCurves
        (direct, linear) error curves at step ``tau`` and at ``2 tau``, same quantities;
        with refined curves as a third in both, ``refined_integration_error`` too.
    stride, coarse_stride : int
        Recording strides (in their own steps) of the fine and of the coarse run.
    n_steps : int
        Steps of the fine run.
    tau : float
        Step of the fine run, s.
    method : {"rk4", "euler"}
        Scheme of both runs.
    """
    fine_i, coarse_i = accuracy.common_samples(stride, coarse_stride, n_steps)
    if len(fine_i) < 2:
        return _not_estimated(comparisons, NOTHING_SHARED)
    curves = [(fine[part], coarse[part], part, attribute)
              for part, attribute in _estimated_parts(fine, coarse)]
    for b, comparison in enumerate(comparisons):
        for fine_curves, rough, part, attribute in curves:
            for k, metric in enumerate(comparison.metrics):
                gap = residual(fine_curves.values[k, fine_i, b],
                                  rough.values[k, coarse_i, b], metric.unit)
                error = float(np.max(np.abs(gap))) / (2 ** accuracy.ORDERS[method] - 1)
                setattr(metric, attribute, _estimate(error, part))
        _integration_warning(comparison, tau, method, stride * tau)


def _rk4_step(sim: Simulation, jit: bool) -> float | None:
    """The step RK4 needs for the cases of ``sim`` (its own estimate, at the same step and
    recording), or None when that run fails."""
    try:
        run = simulate(sim.model, sim.trajectory, sim.sources, method="rk4",
                       record_interval=sim.stride * sim.trajectory.tau,
                       parts=("real", "linear"), jit=jit, platform=sim.platform)
        cases = comparisons_of(run)
        add_integration_errors(cases, run, jit=jit)
    except InsErrorsError:
        return None
    steps = [c.suggested_step for c in cases if c.suggested_step is not None]
    return min(steps) if steps else sim.trajectory.tau


def _integration_warning(comparison: Comparison, tau: float, method: str, interval: float,
                         rk4_step: Callable[[], float | None] | None = None,
                         failed: str | None = None, spacing: float | None = None) -> None:
    """Warn when the integration error is too large, or its estimate not asymptotic
    (:attr:`Comparison.integration_order` far from the scheme's order, or ``failed``: why
    the run that measures the order failed), naming a step the command line accepts
    (:func:`~ins_errors.numeric.accuracy.typable_step`); ``rk4_step`` gives RK4's own
    step when the rectangle method would need more than
    :data:`RECTANGLE_STEPS_ADVISED` steps; the step
    named divides ``spacing`` (s) too, when given (it keeps the motion's breaks)."""

    p, q = accuracy.ORDERS[method], comparison.integration_order
    unreliable = failed is not None or (q is not None
                                        and abs(q - p) > accuracy.ORDER_TOLERANCE)
    worst, worst_need = None, 1.0
    for m, error, difference in _judged_errors(comparison, "linear"):
        target, what = _limit(m, difference, "linear")
        if error > target and error / target > worst_need:
            worst, worst_need = (m, target, what), error / target
    note = _refined_note(comparison, tau, p)
    if worst is None and not unreliable:
        if note:
            comparison.warnings.append(note)
            comparison.brief[note] = _refined_brief(comparison, tau, p, method)
        return
    k = (1.25 * worst_need) ** (1.0 / p) if worst is not None else 1.0
    if unreliable:  # the estimate may be off by a factor 2^p: at least halve the step
        k = 2.0 * k
        if worst is not None and q is not None and 0 < q < p:
            k = max(k, (1.25 * worst_need) ** (1.0 / q))  # errors fall slower than p
    step, text = accuracy.typable_step(tau / k, interval, spacing)
    scheme = "rectangle method" if method == "euler" else method.upper()
    goal = "bring it under the limit" if worst is not None else "make the estimate reliable"
    duration = comparison.times[-1] if len(comparison.times) else interval
    brief = brief_warnings.Integration(tau, scheme, duration, step, tau / k, text, None, q, p,
                                       failed)
    if method == "euler" and duration / step > RECTANGLE_STEPS_ADVISED:
        alternative = rk4_step() if rk4_step is not None else None
        comparison.suggested_step = None
        if alternative is not None:
            step, text = accuracy.typable_step(alternative, interval, spacing)
            comparison.suggested_step, comparison.suggested_method = step, "rk4"
            brief.rk4_text = text
        advice = (f"the rectangle method would need τ ≤ {tau / k:.3g} s, more than "
                  f"{RECTANGLE_STEPS_ADVISED:.0e} steps for this run; use RK4 ({RK4_HOW})"
                  + (f", where τ = {text} s would {goal}" if alternative is not None else ""))
    else:
        comparison.suggested_step = step
        hint = f"; RK4 ({RK4_HOW}) needs far fewer steps" if method == "euler" else ""
        advice = f"τ = {text} s would {goal}{hint}"
    # the quantity named is the one furthest past its limit; the summary's
    # "integration error / error" is the largest share of the error, maybe another's
    shares = [(m.integration_error / m.max_direct, m) for m in comparison.excited
              if m.integration_error is not None and m.max_direct > 0]
    largest = max(shares, key=lambda s: s[0]) if shares else None
    also = ""
    if worst is not None and largest is not None and largest[1] is not worst[0]:
        other = largest[1]
        also = (f". The largest integration error relative to its quantity is "
                f"{other.quantity}'s: {_shown_size(other.integration_error, other.unit)} of "
                f"{_shown_size(other.max_direct, other.unit)}, {_percent(largest[0])} (the "
                "summary's integration error / error)")
    size = ""
    if worst is not None:
        m, target, what = worst
        size = (f"{m.quantity}'s integration error is {_shown_size(m.integration_error, m.unit)}"
                f", {_percent(m.integration_error / m.max_direct)} of its largest error "
                f"({_shown_size(m.max_direct, m.unit)}), over the limit of "
                f"{_shown_size(target, m.unit)} ({what})")
    if worst is not None:
        m, target, what = worst
        brief.worst = (m.quantity, _percent(m.integration_error / m.max_direct),
                       m.integration_error / target, what.startswith("a tenth"))
    brief.refined_too, brief.unreliable = note is not None, unreliable
    if unreliable:
        how = (f"observed order {q:.2g}, scheme order {p}" if failed is None
               else f"{failed}")
        size = (f"{size}, and the estimate is outside its asymptotic range" if size
                else "the estimate is outside its asymptotic range")
        full = (f"integration error not reliable at this step, τ = {tau:g} s, {scheme} "
                f"({how}): {size}; {advice}{also}" + (f". {note}" if note else ""))
    else:
        full = (f"integration error too large at τ = {tau:g} s, {scheme}: {size}; "
                f"{advice}{also}" + (f". {note}" if note else ""))
    comparison.warnings.append(full)
    comparison.brief[full] = brief.line()


def _judged_errors(comparison: Comparison, model: str) -> list[tuple[Metric, float, float]]:
    """(metric, integration error, difference) of each excited quantity whose integration
    error is judged against the ``model``'s residual: for ``"linear"`` the direct and
    linear runs' (:attr:`Metric.integration_error`) and the linear-vs-direct difference,
    for ``"refined"`` the direct and refined runs'
    (:attr:`Metric.refined_runs_integration_error`) and the refined-vs-direct difference
    (both finite). Estimates at rounding (at or below the unit's
    :data:`NOISE_FLOOR`, or below :data:`~ins_errors.numeric.accuracy.RELEVANT` of the
    error) are not judged."""
    out = []
    for m in comparison.excited:
        if model == "linear":
            error, difference = m.integration_error, m.linear_difference
        else:
            error, difference = m.refined_runs_integration_error, m.refined_difference
            if (error is None or difference is None or not math.isfinite(error)
                    or not math.isfinite(difference)):
                continue
        if (error is None or error <= NOISE_FLOOR.get(m.unit, 0.0)
                or error < accuracy.RELEVANT * m.max_direct):  # rounding: not judged
            continue
        out.append((m, error, difference))
    return out


def _limit(m: Metric, difference: float, model: str) -> tuple[float, str]:
    """The limit (SI) on the integration error of the runs whose difference is
    ``difference`` (``model`` − direct), and its words: 1 % of the largest error, or a
    tenth of the difference when that is above :data:`AGREEMENT_FLOOR` of the error,
    whichever is smaller."""
    limits = [(accuracy.ERROR_SHARE * m.max_direct,
               f"{accuracy.ERROR_SHARE:.0%} of its largest error")]
    if difference > AGREEMENT_FLOOR * m.max_direct:
        limits.append((accuracy.DIFFERENCE_SHARE * difference,
                       f"a tenth of its {model}-vs-direct difference, "
                       f"{_shown_size(difference, m.unit)}"))
    return min(limits)


def _refined_note(comparison: Comparison, tau: float, order: int) -> str | None:
    """The words on the refined run's integration error, when the direct and refined
    runs' estimate exceeds its limit (:func:`_limit`, as the linear pair's does) for some
    judged quantity: the one furthest past it, and about the step that would bring it
    under (the scheme's ``order``). It is said beside the linear pair's warning, or
    alone, and changes neither that warning's step nor ``suggested_step``."""
    worst = _refined_worst(comparison)
    if worst is None:
        return None
    m, error, target, what = worst
    step = tau / (1.25 * error / target) ** (1.0 / order)
    return (f"The refined run's integration error is over its limit too: {m.quantity}'s, "
            f"of the direct and refined runs, is {_shown_size(error, m.unit)} (refined "
            f"curve {_shown_size(m.refined_integration_error, m.unit)}), over the limit of "
            f"{_shown_size(target, m.unit)} ({what}): at τ = {tau:g} s the refined − direct "
            f"residual is not the second-order model's alone; about τ ≤ {step:.3g} s "
            "would bring it under")


def _refined_worst(comparison: Comparison) -> tuple[Metric, float, float, str] | None:
    """(metric, integration error, limit, the limit's words) of the judged quantity whose
    direct and refined runs' integration error is furthest past its limit
    (:func:`_limit`), or None when none is past it."""
    worst, worst_need = None, 1.0
    for m, error, difference in _judged_errors(comparison, "refined"):
        target, what = _limit(m, difference, "refined")
        if error > target and error / target > worst_need:
            worst, worst_need = (m, error, target, what), error / target
    return worst


def _refined_brief(comparison: Comparison, tau: float, order: int, method: str) -> str:
    """The terminal's short form of :func:`_refined_note` said alone
    (:mod:`~ins_errors.numeric.brief_warnings`)."""
    m, error, target, what = _refined_worst(comparison)
    return brief_warnings.refined_alone(
        tau, "rectangle method" if method == "euler" else method.upper(),
        comparison.times[-1] if len(comparison.times) else tau,
        tau / (1.25 * error / target) ** (1.0 / order), m.quantity,
        _percent(error / m.max_direct), error / target, what.startswith("a tenth"))


def _percent(share: float) -> str:
    """``"4.21%"``, ``"1234%"``, ``"2.83e-06%"``: a share in per cent to three significant
    digits (a fixed two decimals read 0.00 % for a share that was still over its limit)."""
    from ins_errors.units import percent_text

    return percent_text(share, 3)


def add_validity_warnings(comparisons: Sequence[Comparison], sim: Simulation,
                          threshold: float = VALIDITY_THRESHOLD, jit: bool = True) -> None:
    """Warn where the worst linear/direct ratio exceeds ``threshold``, with the factor on
    every source magnitude at which it would be 1 %.

    Those cases run again (direct and linear) at half their magnitudes; the ratio's
    measured slope ``s`` against magnitude gives a first factor ``(0.01/r)^(1/s)``. The
    slope far in the nonlinear range is not the slope near 1 % (a 25° azimuth error: 0.46
    at half size, about 1 near 1 %, so the first factor was 50 times too small), so the
    cases run again at the factor found, and the factor is corrected from the last two
    runs (a secant in log–log), up to :data:`VALIDITY_REFINEMENTS` times, until the ratio
    measured there is within a factor 1.25 of 1 %. The factor the warning names (and
    :attr:`Comparison.one_percent_scale`) is that secant's step from the last run to 1 %,
    along the ratio's slope measured between the last two runs, not the last run's own
    factor: an estimate ("about"), which the warning says it is from (the ratio measured
    at the last run's factor and the slope). strapdown_ned, an initial heading error over
    1 h at rest: from 5° and from 8°, 3.74 arcmin both, where a run measures 1.00 % (the
    last runs' own factors, 4.13 and 4.61 arcmin, measure 1.11 % and 1.23 %).
    """
    over = [b for b, c in enumerate(comparisons)
            if c.worst_linear is not None and c.worst_linear.linear_ratio > threshold]
    samples = len(comparisons[0].times) if comparisons else 0
    if over and samples < VALIDITY_SAMPLES:
        # the largest direct error over a handful of instants may be near a zero crossing
        for b in over:
            comparisons[b].warnings.append(
                f"validity not judged: linear − direct reaches "
                f"{comparisons[b].worst_linear.linear_ratio:.1%} of "
                f"{comparisons[b].worst_linear.quantity} over only {samples} recorded "
                f"samples, too few to judge (record at least {VALIDITY_SAMPLES})")
        return
    # by position in the batch (comparisons compare their arrays: no `in` or index())
    columns = [b for b in over if any(np.any(v) for v in comparisons[b].linear.values())]
    for comparison in (comparisons[b] for b in over if b not in columns):
        comparison.warnings.append(_unseen_text(comparison))
    if not columns:
        return
    flagged = [comparisons[b] for b in columns]
    # per case: points (factor, ratio) measured so far, the first at the full magnitudes
    points = [[(1.0, c.worst_linear.linear_ratio)] for c in flagged]
    last_slope: list[float] = [math.nan] * len(flagged)  # through the last two points
    factors = [0.5] * len(flagged)
    open_cases = list(range(len(flagged)))
    for round_ in range(1 + VALIDITY_REFINEMENTS):
        if not open_cases:
            break
        runs = _ratios_at(sim, [columns[k] for k in open_cases],
                          [factors[k] for k in open_cases],
                          [flagged[k].shown for k in open_cases], jit)
        still_open = []
        for k, ratio in zip(open_cases, runs, strict=True):
            if ratio is None or not ratio > 0:
                continue  # the run failed or nothing is excited there: keep what we have
            points[k].append((factors[k], ratio))
            (f0, r0), (f1, r1) = points[k][-2], points[k][-1]
            slope = math.log(r1 / r0) / math.log(f1 / f0) if f1 != f0 else math.nan
            last_slope[k] = slope
            # the next estimate, from the last point along the ratio's measured slope
            factors[k] = f1 * (0.01 / r1) ** (1.0 / _usable(slope))
            if round_ > 0 and 0.8 <= 100 * ratio <= 1.25:
                continue  # measured close enough to 1 %: the estimate is a short step
            still_open.append(k)
        open_cases = still_open
    for k, comparison in enumerate(flagged):
        worst = comparison.worst_linear
        ratio = worst.linear_ratio
        if _not_falling(points[k]):  # no magnitude brings it to 1 %: say so, not one
            comparison.warnings.append(_not_falling_text(sim.model, comparison, points[k],
                                                         threshold))
            continue
        if len(points[k]) == 1:  # the half-size run failed: nothing measured to scale by
            scale = 0.01 / ratio
            how = "assuming the ratio falls in proportion to the magnitude"
        else:
            scale = factors[k]
            there, measured = points[k][-1]
            slope = last_slope[k]
            how = f"from {measured:.2%} measured at {there:.3g}×, " + (
                f"the ratio ∝ magnitude^{slope:.2f} there" if _usable(slope) == slope else
                "assuming the ratio falls in proportion to the magnitude" + (
                    f" (its measured slope there, {slope:.2f}, is too small to go by)"
                    if math.isfinite(slope) else ""))
            if k in open_cases:
                how += "; the ratio does not scale steadily"
        comparison.one_percent_scale = scale
        at = ", ".join(f"{name} = {_shown(sim.model, name, value * scale)}"
                       for name, value in comparison.sources.items())
        comparison.warnings.append(
            f"linear model beyond its validity: linear − direct reaches {ratio:.1%} of "
            f"{worst.quantity} (threshold {threshold:.0%}); it would be 1 % at about "
            f"{scale:.3g}× the magnitudes ({at}; {how})")


def _usable(slope: float) -> float:
    """The log–log slope of the ratio to scale a magnitude by: the measured one when it
    is finite and above :data:`FALLING_SLOPE`, else 1 (first-order theory's)."""
    return slope if math.isfinite(slope) and slope > FALLING_SLOPE else 1.0


VALIDITY_REFINEMENTS = 3
"""Runs after the half-size one that correct the 1 % factor of a validity warning."""

FIRST_ORDER_SPAN = 0.1
"""Smallest factor on the magnitudes that must have been measured before a ratio that
does not fall with them is called so (:func:`_not_falling`): a decade at least."""

FALLING_SLOPE = 0.2
"""Least log–log slope of the linear/direct ratio against the magnitude, from the full
magnitudes to the smallest factor measured, for it to count as falling (first order:
1, the residual being of second order; a 25° azimuth error's, far in the nonlinear
range: 0.46 at half size). Below it no magnitude brings the ratio to 1 %."""


def _not_falling(points: Sequence[tuple[float, float]]) -> bool:
    """True when the ratios measured at (factor, ratio) ``points`` (the first at the full
    magnitudes) do not fall with the magnitude: at a factor of :data:`FIRST_ORDER_SPAN`
    or less the ratio is above ``ratio₀ · factor^FALLING_SLOPE`` (first-order theory
    has it near ``ratio₀ · factor``)."""
    (_, r0), (f, r) = points[0], min(points)
    return f <= FIRST_ORDER_SPAN and math.log(r / r0) / math.log(f) < FALLING_SLOPE


def _not_falling_text(model: Model, comparison: Comparison,
                      points: Sequence[tuple[float, float]], threshold: float) -> str:
    """The validity warning of a case whose ratio does not fall with the magnitude
    (:func:`_not_falling`): what was measured, what the first order would give there,
    and what to check; no magnitude is offered for 1 %."""
    worst = comparison.worst_linear
    (_, r0), (f, r) = points[0], min(points)
    at = ", ".join(f"{name} = {_shown(model, name, value * f)}"
                   for name, value in comparison.sources.items())
    return (f"linear model not valid at any magnitude measured: linear − direct reaches "
            f"{r0:.1%} of {worst.quantity} (threshold {threshold:.0%}), and the worst ratio "
            f"is still {r:.2%} at {f:.3g}× the magnitudes ({at}), where an error of first order "
            f"in the sources would have it fall with them to about {_percent(r0 * f)}: "
            "the direct error does not shrink with the sources as the linear one does, "
            "so part of it comes without a source or from a term the sources do not "
            "scale; check that the real-work equations (and initial state) reduce to the "
            "ideal-work ones when every error source is zero, and that the sources enter "
            "smoothly (no term that saturates far below the magnitudes run)")


def _unseen_text(comparison: Comparison) -> str:
    """The validity warning of a case whose linear errors are all zero while the direct
    run's are not: a source the linear model does not see, or, with every source at
    zero, an error without a source."""
    if comparison.sources:
        # zero columns of G and of the initial errors: no magnitude makes it valid
        return (f"the linear model does not see {', '.join(comparison.sources)}: its "
                "errors stay exactly zero while the direct run's do not, at any magnitude "
                "(the source has zero columns in G and in the initial errors: no "
                "equation uses it, or it enters only at second order); check how the "
                "model uses it")
    from ins_errors.units import display_scale

    worst = comparison.worst_linear
    scale, unit = display_scale(worst.unit)
    return (f"the run has no error input (every error source is zero), yet the direct "
            f"run's errors do not stay zero ({worst.quantity} reaches "
            f"{worst.max_direct * scale:.3g} {unit}): an error without a source, so the "
            "real work does not reduce to the ideal work with every source at zero; "
            "check the real-work equations and initial state for a term that no error "
            "source multiplies")

VALIDITY_SAMPLES = 10
"""Fewest recorded samples on which the validity of the linear model is judged."""


def _ratios_at(sim: Simulation, columns: list[int], factors: list[float],
               shown: list[tuple[str, ...] | None], jit: bool) -> list[float | None]:
    """Worst linear/direct ratio of each case ``columns`` of ``sim`` with its sources
    times ``factors`` (direct and linear runs in one batch); None where they fail."""
    sources = sim.sources[:, columns] * np.asarray(factors)
    try:
        run = simulate(sim.model, sim.trajectory, sources, method=sim.method,
                       record_interval=sim.stride * sim.trajectory.tau,
                       parts=("real", "linear"), jit=jit, platform=sim.platform)
        cases = comparisons_of(run)
    except InsErrorsError:
        return [None] * len(columns)
    out = []
    for case, chosen in zip(cases, shown, strict=True):
        case.shown = chosen
        worst = case.worst_linear
        out.append(None if worst is None else worst.linear_ratio)
    return out


def add_half_turn_warnings(comparisons: Sequence[Comparison], model: Model) -> None:
    """Warn of each initial angle error (an initial source in rad) given past half a turn.

    An angle error of 190° is one of −170°: the direct run starts from the same
    orientation (or position) either way, but the linear and refined runs take the value
    as given, and the linear errors are in proportion to it, so the two readings of one
    error get different predictions. Such a case gets one warning per source, naming the
    angle within ±180° that is the same error."""
    from ins_errors.units import format_readable

    for comparison in comparisons:
        for name, value in comparison.sources.items():
            info = model.sources[model.index("sources", name)]
            if info.unit != "rad" or info.kind != "initial" or not abs(value) > math.pi:
                continue
            shown = info.display_unit or info.unit
            given = format_readable(value, info.unit, shown, digits=3)
            same = format_readable(math.remainder(value, 2 * math.pi), info.unit, shown,
                                   digits=3)
            comparison.warnings.append(
                f"{name} = {given} is past half a turn: it is the same error as {same} "
                f"(the direct run starts the same for both), but the linear and refined "
                f"runs take {given} as given, and the linear errors are in proportion to "
                f"it; give {name} within ±180 deg ({same}) for the linear model's "
                "prediction of this error")


def _shown(model: Model, name: str, value: float) -> str:
    """A source's magnitude for a warning, readable; an angle past half a turn (π rad,
    a size no angle error has: 200° is −160°) says so."""
    from ins_errors.units import format_readable

    info = model.sources[model.index("sources", name)]
    text = format_readable(value, info.unit, info.display_unit or info.unit, digits=3)
    if info.unit == "rad" and abs(value) > math.pi:
        text += " (past half a turn: no angle error is that large)"
    return text


def _fmt(value: float | None) -> str:
    if value is None:
        return "–"
    if not math.isfinite(value):
        return "∞"
    return f"{value:.3e}"


def _times(value: float | None, factor: float) -> float | None:
    return None if value is None else value * factor


def _judged(metric: Metric) -> str:
    """The table's word on whether a quantity's ratios are judged, and why not."""
    if metric.excited:
        return "yes"
    return "no: 2nd order" if metric.second_order_only else "no: rounding"


def markdown_table(comparison: Comparison) -> str:
    """Markdown table of one case: one row per quantity, sizes in display units; the last
    column says whether its ratios are judged (``yes``), or why not: moved only at second
    order (``no: 2nd order``), or a direct error at the rounding floor of its unit
    (``no: rounding``)."""
    from ins_errors.markdown_cells import table_cell
    from ins_errors.units import display_scale

    lines = [f"**{table_cell(comparison.label)}**", "",
             "| quantity | unit | max abs direct | max abs (linear − direct) | ratio "
             "| max abs (refined − direct) | ratio | integration error direct | linear "
             "| refined | judged |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|:---:|"]
    for m in comparison.metrics:  # sizes in display units (arcmin, deg/h...), ratios bare
        k, unit = display_scale(m.unit)
        lines.append(f"| `{m.quantity}` | {unit} | {_fmt(_times(m.max_direct, k))} | "
                     f"{_fmt(_times(m.linear_difference, k))} | {_fmt(m.linear_ratio)} | "
                     f"{_fmt(_times(m.refined_difference, k))} | {_fmt(m.refined_ratio)} | "
                     f"{_fmt(_times(m.direct_integration_error, k))} | "
                     f"{_fmt(_times(m.linear_integration_error, k))} | "
                     f"{_fmt(_times(m.refined_integration_error, k))} | "
                     f"{_judged(m)} |")
    return "\n".join(lines) + "\n"


def _integration_cell(comparison: Comparison) -> str:
    """The summary's integration error / error: the estimate, or, where it is below
    :data:`~ins_errors.numeric.accuracy.RELEVANT` and not judged, ``< 1e-06`` with what
    the runs at three steps show it is (:attr:`Comparison.negligible_cause`):
    ``(negligible step error)`` when it falls as τ^p, ``(rounding)`` when it does not,
    ``(negligible)`` when that is not told."""
    if comparison.integration_negligible:
        cause = {"step error": "negligible step error", "rounding": "rounding"}.get(
            comparison.negligible_cause or "", "negligible")
        return f"< {accuracy.RELEVANT:.0e} ({cause})"
    return _fmt(comparison.worst_integration_ratio)


def markdown_summary(comparisons: Sequence[Comparison], title: str = "",
                     brief: bool = False, details: str | None = None) -> str:
    """Markdown summary: one row per case with the worst excited ratios (user text kept
    in its cell and on its line: :mod:`ins_errors.markdown_cells`).

    Parameters
    ----------
    comparisons : sequence of Comparison
    title : str
        Heading of the summary (none when empty).
    brief : bool
        Print the warnings' short forms (:attr:`Comparison.brief`), for a terminal; the
        default prints them in full (a report, a ``--markdown`` file).
    details : str, optional
        Where the full warnings are (e.g. ``"report.md"``): said in one line after the
        warnings when ``brief`` shortened any.
    """
    from ins_errors.markdown_cells import one_line, table_cell

    lines = [f"### {one_line(title)}", ""] if title else []
    lines += ["| case | worst linear ratio | quantity | worst refined ratio | quantity "
              "| integration error / error |",
              "|---|---:|---|---:|---|---:|"]
    for c in comparisons:
        wl, wr = c.worst_linear, c.worst_refined
        lines.append(f"| {table_cell(c.label)} | {_fmt(_value(wl, 'linear_ratio'))} | "
                     f"{'' if wl is None else '`' + wl.quantity + '`'} | "
                     f"{_fmt(_value(wr, 'refined_ratio'))} | "
                     f"{'' if wr is None else '`' + wr.quantity + '`'} | "
                     f"{_integration_cell(c)} |")
    warned = [(table_cell(c.label), c.brief.get(w, w) if brief else w)
              for c in comparisons for w in c.warnings]
    if warned:
        lines += [""] + [f"> **warning** ({label}): {w}" for label, w in warned]
        if brief and details and any(w in c.brief for c in comparisons for w in c.warnings):
            lines += ["", f"(the warnings in full: {details})"]
    noted = next((c.maxima_note for c in comparisons if c.maxima_note), None)
    if noted:  # the cases share the run's recording: one note
        lines += ["", f"> **note**: {noted}"]
    return "\n".join(lines) + "\n"
