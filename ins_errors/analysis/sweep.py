"""Sweeps: a scenario run over a grid of parameters, one task per grid point.

A scenario file (:mod:`ins_errors.scenario`) gains an optional ``[sweep]`` table::

    [sweep]
    latitude = ["30 deg", "50 deg", "70 deg"]          # motion parameters
    heading = { start = "0 deg", stop = "90 deg", count = 4 }
    duration = ["1 h", "2 h"]                          # run length (or step)
    gyro_drift_x = ["0.005 deg/h", "0.01 deg/h"]       # error-source magnitudes
    draws = 100                                        # Monte Carlo draws per point
    seed = 7                                           # of the draws
    scheduler = "tcp://10.0.0.5:8786"                  # optional Dask cluster
    [sweep.random]                                     # 1σ of the drawn sources
    accel_bias_x = "50 ug"

Sweepable names: the motion's ``latitude``, ``longitude``, ``heading``, ``speed``,
``height``; the run's ``duration`` and ``step``; any error source of the model (its
magnitude in the scenario's case). The grid is the product of every list (first name
slowest), of the scenario's cases (when there are several) and of the draws. A draw adds
to the case's sources a Gaussian value of the given 1σ per random source, drawn from the
draw's own generator (:func:`ins_errors.analysis.monte_carlo.draw_generator`): draw
``k`` has the same values at every grid point and on every engine.

Each grid point runs the direct, linear (and refined) runs of
:func:`ins_errors.numeric.compare.compare` (:func:`run_point`, a pure function of its
:class:`PointJob`); :func:`run_sweep` spreads the points over
:mod:`ins_errors.analysis.engine` and streams them into a
:class:`~ins_errors.analysis.store.SweepStore`, skipping points a previous, interrupted
run of the same sweep already stored. A point that fails on its own bad input
(:class:`PointError`) is stored with its reason and no data while the others run on; a
resumed sweep runs it again only when asked (``retry_failed``): its failure is as
deterministic as its numbers.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from ins_errors.analysis.store import failure_reasons
from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.figure_layout import text_width, wrap_to_width
from ins_errors.units import parse_quantity

MOTION_PARAMETERS: dict[str, str] = {"latitude": "rad", "longitude": "rad", "heading": "rad",
                                     "speed": "m/s", "height": "m"}
"""Sweepable motion settings and their SI units."""

RUN_PARAMETERS: dict[str, str] = {"duration": "s", "step": "s"}
"""Sweepable run settings and their SI units."""

CONTROL_KEYS = ("draws", "seed", "random", "scheduler")
"""Keys of ``[sweep]`` that are not grids."""

FIGURES = ("worst_linear_ratio", "worst_refined_ratio", "max_direct:QUANTITY",
           "linear_ratio:QUANTITY", "refined_ratio:QUANTITY")
"""Figures a sweep can plot against its parameters."""


class SweepError(InsErrorsError):
    """A ``[sweep]`` table or sweep request that cannot be run."""


class PointError(SweepError):
    """A grid point that failed on its own bad input (a motion that reaches a pole, a
    step that does not fit its duration...): its outcome, recorded in the store.

    Parameters
    ----------
    label : str
        The point's swept values as written.
    reason : str
        The one-line error the point raised.
    """

    def __init__(self, label: str, reason: str):
        super().__init__(f"at the point {label}: {reason}")
        self.label = label
        self.reason = reason

    def __reduce__(self):  # sent back from worker processes with both parts
        return (type(self), (self.label, self.reason))


@dataclass(frozen=True)
class Parameter:
    """One swept parameter.

    Attributes
    ----------
    name : str
        ``latitude``, ``duration``, ``gyro_drift_x``...
    kind : str
        ``"motion"``, ``"run"`` or ``"source"``.
    unit : str
        SI unit of ``values``.
    values : tuple of float
        Grid values, SI.
    display_unit : str
        Unit the file wrote them in (for tables and plots).
    """

    name: str
    kind: str
    unit: str
    values: tuple[float, ...]
    display_unit: str

    def shown(self, value: float) -> float:
        """``value`` (SI) in :attr:`display_unit`."""
        if self.display_unit == self.unit:
            return float(value)
        from ins_errors.units import format_quantity

        return float(format_quantity(value, self.unit, self.display_unit, 17).split()[0])


@dataclass(frozen=True)
class SweepSpec:
    """A parsed ``[sweep]`` table.

    Attributes
    ----------
    parameters : tuple of Parameter
        Grids, in file order.
    draws : int
        Monte Carlo draws per grid point (0: none).
    seed : int
        Seed of the draws.
    random : tuple of (str, float)
        Randomly drawn sources and their 1σ, SI.
    scheduler : str or None
        Dask scheduler address from the file.
    """

    parameters: tuple[Parameter, ...] = ()
    draws: int = 0
    seed: int = 0
    random: tuple[tuple[str, float], ...] = ()
    scheduler: str | None = None


def _display_unit(text: Any, unit: str) -> str:
    match = re.match(r"^\s*[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?\s*(.+?)\s*$", str(text))
    if isinstance(text, str) and match:
        try:
            parse_quantity(f"1 {match.group(1)}", unit)
        except InsErrorsError:
            return unit
        return match.group(1)
    return unit


def _value(text: Any, unit: str, what: str) -> float:
    """A grid value or 1σ of the user's file, in SI ``unit``: it must carry its unit
    (a bare number, text or TOML number, is refused as everywhere else; zero and plain
    ratios need none)."""
    if isinstance(text, str) and unit != "1":
        try:
            number = float(text)
        except ValueError:
            pass
        else:
            if not np.isfinite(number):
                raise SweepError(f"{what} value {text!r} is not a finite number")
            raise SweepError(f"{what} value {text!r} needs a unit, e.g. '{text} {unit}'")
    return parse_quantity(text, unit, what, numbers_are_si=False)


def _grid(name: str, raw: Any, unit: str, where: str) -> tuple[tuple[float, ...], str]:
    what = f"{where} [sweep] {name}"
    if isinstance(raw, dict):
        extra = set(raw) - {"start", "stop", "count"}
        if extra or len(raw) != 3:
            raise SweepError(f"{what}: a range is {{ start = ..., stop = ..., count = N }}"
                             f"{'; unknown ' + ', '.join(sorted(extra)) if extra else ''}")
        count = raw["count"]
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise SweepError(f"{what}: count must be a positive integer, got {count!r}")
        start = _value(raw["start"], unit, what)
        stop = _value(raw["stop"], unit, what)
        values = tuple(float(v) for v in np.linspace(start, stop, count))
        return values, _display_unit(raw["start"], unit)
    if not isinstance(raw, list) or not raw:
        raise SweepError(f"{what}: give a non-empty list of values or "
                         "{ start = ..., stop = ..., count = N }")
    values = tuple(_value(v, unit, what) for v in raw)
    if len(set(values)) != len(values):
        raise SweepError(f"{what}: a value is listed twice")
    return values, _display_unit(raw[0], unit)


def parse_sweep(raw: Any, model, where: str) -> SweepSpec:
    """Check and convert a ``[sweep]`` table (called by :func:`ins_errors.scenario.load_scenario`).

    Parameters
    ----------
    raw : dict
        The table as TOML read it.
    model : ins_errors.numeric.model.Model
        The scenario's model (source names and units).
    where : str
        File name for messages.

    Raises
    ------
    SweepError, UnknownNameError, UnitError
        One line naming the key and the problem.
    """
    if not isinstance(raw, dict):
        raise SweepError(f"{where}: 'sweep' must be a table, [sweep]")
    source_units = {s.name: s.unit for s in model.sources}
    known = [*MOTION_PARAMETERS, *RUN_PARAMETERS, *source_units, *CONTROL_KEYS]
    parameters = []
    for name, value in raw.items():
        if name in CONTROL_KEYS:
            continue
        if name in MOTION_PARAMETERS:
            kind, unit = "motion", MOTION_PARAMETERS[name]
        elif name in RUN_PARAMETERS:
            kind, unit = "run", RUN_PARAMETERS[name]
        elif name in source_units:
            kind, unit = "source", source_units[name]
        else:
            raise unknown_name(f"key in {where} [sweep]", name, known)
        values, shown = _grid(name, value, unit, where)
        if kind == "run" and min(values) <= 0:
            raise SweepError(f"{where} [sweep] {name}: values must be positive")
        parameters.append(Parameter(name, kind, unit, values, shown))
    draws = raw.get("draws", 0)
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 0:
        raise SweepError(f"{where} [sweep] draws must be a whole number >= 0, got {draws!r}")
    seed = raw.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise SweepError(f"{where} [sweep] seed must be a whole number >= 0, got {seed!r}")
    table = raw.get("random", {})
    if not isinstance(table, dict):
        raise SweepError(f"{where}: 'random' must be a table, [sweep.random]")
    random = []
    for name, value in table.items():
        if name not in source_units:
            raise unknown_name(f"error source in {where} [sweep.random]", name, source_units)
        sigma = _value(value, source_units[name], f"{where} [sweep.random] {name}")
        if not sigma > 0:
            raise SweepError(f"{where} [sweep.random] {name}: 1σ must be positive")
        if name in {p.name for p in parameters}:
            raise SweepError(f"{where} [sweep]: {name} is both swept and drawn at random")
        random.append((name, sigma))
    if bool(draws) != bool(random):
        raise SweepError(f"{where} [sweep]: draws = N and a [sweep.random] table of 1σ go "
                         "together (give both or neither)")
    scheduler = raw.get("scheduler")
    if scheduler is not None and not isinstance(scheduler, str):
        raise SweepError(f"{where} [sweep] scheduler must be an address like "
                         "'tcp://host:8786'")
    if not parameters and not draws:
        raise SweepError(f"{where} [sweep] names no parameter grid and no draws")
    return SweepSpec(tuple(parameters), draws, seed, tuple(random), scheduler)


# --------------------------------------------------------------------------------------
# Grid points and the task of one point
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PointJob:
    """Everything one grid point's runs depend on (pickled to a worker).

    Attributes
    ----------
    model : str
    motion : dict
        Motion description with the swept values in SI.
    base : str
        Folder of the scenario file (motion files).
    duration, step, record : float
        s.
    method : str
    refined : bool
    ellipsoid : str or None
    sources : tuple of (str, float)
        The case's sources with swept magnitudes, SI.
    random : tuple of (str, float)
        Random sources and their 1σ.
    seed : int
    draw : int or None
        Draw number (None: no random draw).
    platform : str
        ``"exact"`` or ``"small_angle"`` platform kinematics of the direct run.
    parameters : tuple of (str, float)
        Model parameters set by the scenario's ``[parameters]`` table, SI.
    label : str
        The point's swept values as written (for messages).
    truth : str
        How a moving truth is computed: ``"auto"``, ``"interpolated"`` or ``"fine"``.
    motion_si : tuple of (str, object)
        The same motion with every quantity as exact SI text
        (:func:`ins_errors.numeric.motion_spec.in_si`), which the worker reads without
        pint; empty: read ``motion``. Not part of the sweep's identity (it says nothing
        ``motion`` does not).
    """

    model: str
    motion: tuple[tuple[str, Any], ...]
    base: str
    duration: float
    step: float
    record: float
    method: str
    refined: bool
    ellipsoid: str | None
    sources: tuple[tuple[str, float], ...]
    random: tuple[tuple[str, float], ...] = ()
    seed: int = 0
    draw: int | None = None
    platform: str = "exact"
    label: str = ""
    parameters: tuple[tuple[str, float], ...] = ()
    truth: str = "auto"
    motion_si: tuple[tuple[str, Any], ...] = ()


@dataclass
class Grid:
    """The points of a sweep.

    Attributes
    ----------
    jobs : list of PointJob
    coordinates : dict of str to (numpy.ndarray, dict)
        Per-point labels (swept values SI, case, draw) with attributes.
    parameters : tuple of Parameter
    """

    jobs: list[PointJob]
    coordinates: dict[str, tuple[np.ndarray, dict]] = field(default_factory=dict)
    parameters: tuple[Parameter, ...] = ()


def grid(scenario) -> Grid:
    """Every grid point of a scenario with a ``[sweep]`` table, in a fixed order."""
    from ins_errors.numeric.motion_spec import in_si

    spec: SweepSpec = scenario.sweep
    if spec is None:
        raise SweepError(f"scenario {scenario.title!r} has no [sweep] table")
    axes = [p.values for p in spec.parameters]
    cases = list(range(len(scenario.cases)))
    draws: list[int | None] = list(range(spec.draws)) if spec.draws else [None]
    jobs, labels = [], {p.name: [] for p in spec.parameters}
    case_index, draw_index = [], []
    in_si_text: dict[str, tuple[tuple[str, Any], ...]] = {}  # by the motion as written
    for values in itertools.product(*axes):
        for case in cases:
            for draw in draws:
                motion = dict(scenario.motion)
                duration, step = scenario.duration, scenario.step
                sources = dict(scenario.cases[case].sources)
                for p, v in zip(spec.parameters, values, strict=True):
                    labels[p.name].append(v)
                    if p.kind == "motion":  # exact SI value, with its unit as text
                        motion[p.name] = f"{v!r} {p.unit}"
                    elif p.name == "duration":
                        duration = v
                    elif p.name == "step":
                        step = v
                    else:
                        sources[p.name] = v
                case_index.append(case)
                draw_index.append(-1 if draw is None else draw)
                label = [f"{p.name} = {p.shown(v):.6g} {p.display_unit}"
                         for p, v in zip(spec.parameters, values, strict=True)]
                label += [f"case {case + 1}"] if len(cases) > 1 else []
                label += [f"draw {draw}"] if draw is not None else []
                written = json.dumps(motion, sort_keys=True)
                if written not in in_si_text:
                    in_si_text[written] = tuple(sorted(in_si(motion).items()))
                jobs.append(PointJob(
                    scenario.model, tuple(sorted(motion.items())), str(scenario.base),
                    duration, step, scenario.record, scenario.method, scenario.refined,
                    scenario.ellipsoid, tuple(sorted(sources.items())), spec.random,
                    spec.seed, draw, scenario.platform, ", ".join(label),
                    tuple(sorted(scenario.parameters.items())), scenario.truth,
                    in_si_text[written]))
    _check_grids(scenario, jobs)
    coordinates = {p.name: (np.array(labels[p.name]), {"units": p.unit, "display_unit":
                                                       p.display_unit, "swept": 1})
                   for p in spec.parameters}
    if len(cases) > 1:
        coordinates["case"] = (np.array(case_index), {
            "long_name": "case number in the scenario file", "units": "1", "swept": 1,
            "labels": json.dumps([c.label for c in scenario.cases])})
    if spec.draws:
        coordinates["draw"] = (np.array(draw_index), {
            "long_name": "Monte Carlo draw", "units": "1", "swept": 1})
    return Grid(jobs, coordinates, spec.parameters)


def _check_grids(scenario, jobs: Sequence[PointJob]) -> None:
    """Every point's duration, step and recording interval fit together; motions are valid."""
    from ins_errors.numeric.integrators import record_stride, step_count
    from ins_errors.numeric.motion_spec import motion_profile

    for duration, step in sorted({(j.duration, j.step) for j in jobs}):
        steps = step_count(duration, step, "sweep duration")
        record_stride(scenario.record, step, steps)
    for motion in {json.dumps(dict(j.motion), sort_keys=True) for j in jobs}:
        motion_profile(json.loads(motion), base=scenario.base)


@lru_cache(maxsize=4)
def _trajectory(model_name: str, motion: str, base: str, duration: float, step: float,
                ellipsoid: str | None, parameters: tuple[tuple[str, float], ...] = (),
                truth: str = "auto"):
    """The true motion of a point (kept for the next point with the same motion)."""
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import motion_profile

    model = load_model(model_name)
    profile = motion_profile(json.loads(motion), base=Path(base))
    p = model.parameter_vector(ellipsoid=ellipsoid, **dict(parameters))
    return tr.trajectory(model, profile, duration, step, p=p, truth=truth)


def run_point(job: PointJob) -> dict[str, np.ndarray]:
    """Run one grid point: direct, linear (and refined) errors and their metrics.

    Returns
    -------
    dict
        ``direct``, ``linear`` (``refined``) of shape (nt, nq), ``max_direct``,
        ``linear_ratio`` (``refined_ratio``), ``excited`` of shape (nq,), and
        ``source_value`` (nw,), all SI, quantities in the order of
        :func:`ins_errors.numeric.simulate.error_quantities`.

    Raises
    ------
    PointError
        The point's bad input (any :class:`~ins_errors.errors.InsErrorsError`), with
        the point's label.
    """
    try:
        return _run_point(job)
    except InsErrorsError as error:
        raise PointError(job.label or "the point", str(error)) from None


def _run_point(job: PointJob) -> dict[str, np.ndarray]:
    from ins_errors.analysis.monte_carlo import draw_generator
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import error_quantities

    model = load_model(job.model)
    motion = json.dumps(dict(job.motion_si or job.motion), sort_keys=True)
    trajectory = _trajectory(job.model, motion, job.base, job.duration, job.step,
                             job.ellipsoid, job.parameters, job.truth)
    sources = dict(job.sources)
    if job.draw is not None:
        rng = draw_generator(job.seed, job.draw)
        for name, sigma in job.random:
            sources[name] = sources.get(name, 0.0) + rng.normal(0.0, sigma)
    # (no validity warning: the store keeps the ratios, not the warnings, so its runs at
    # other magnitudes would be wasted)
    [comparison] = compare(model, trajectory, [sources], method=job.method,
                           record_interval=job.record, refined=job.refined,
                           platform=job.platform, labels=[job.label or "the point"],
                           validity_threshold=None)
    names = error_quantities(model)[0]
    metrics = {m.quantity: m for m in comparison.metrics}
    out = {curve: np.stack([getattr(comparison, curve)[q] for q in names], axis=1)
           for curve in (("direct", "linear", "refined") if job.refined
                         else ("direct", "linear"))}
    out["max_direct"] = np.array([metrics[q].max_direct for q in names])
    out["linear_ratio"] = np.array([metrics[q].linear_ratio for q in names])
    if job.refined:
        out["refined_ratio"] = np.array([metrics[q].refined_ratio for q in names])
    out["excited"] = np.array([metrics[q].excited for q in names], dtype=np.int8)
    out["integration_error"] = np.array(
        [np.nan if metrics[q].integration_error is None else metrics[q].integration_error
         for q in names])
    out["source_value"] = model.source_vector(**sources)
    return out


# --------------------------------------------------------------------------------------
# Running a sweep
# --------------------------------------------------------------------------------------
@dataclass
class SweepResult:
    """A finished sweep.

    Attributes
    ----------
    dataset : xarray.Dataset
        Everything the store holds (see :mod:`ins_errors.analysis.store`).
    store : Path
    points, computed, reused : int
        Grid points, points run by this call (including those that failed), points read
        back from the store.
    engine : EngineStats or None
        None when every point was already stored.
    failed : list of int
        Points that failed (run by this call or read back), in order; their reasons
        are in :func:`failures`.
    """

    dataset: Any
    store: Path
    points: int
    computed: int
    reused: int
    engine: Any = None
    failed: list[int] = field(default_factory=list)


def fingerprint(jobs: Sequence[PointJob], extra: Mapping[str, Any]) -> str:
    """Identity of a sweep: a hash of every point's job and the store layout."""
    rows = []
    for job in jobs:
        row = asdict(job)
        del row["motion_si"]  # the same motion as job.motion
        if "file" not in dict(job.motion):
            del row["base"]  # the folder matters to motion files only
        if not job.parameters:
            del row["parameters"]  # a sweep stored before [parameters] existed is the same
        if job.truth == "auto":
            del row["truth"]  # likewise before truth could be chosen
        rows.append(row)
    text = json.dumps({"jobs": rows, **extra}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def layout(scenario, points: Grid):
    """The store layout of a sweep."""
    from ins_errors.analysis.store import Layout
    from ins_errors.model_parameters import parameters_record
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import error_quantities

    model = load_model(scenario.model)
    longest = max(j.duration for j in points.jobs)
    record = scenario.record
    count = round(longest / record)
    times = np.arange(count + 1) * record
    names, units = error_quantities(model)
    curves = ("direct", "linear", "refined") if scenario.refined else ("direct", "linear")
    settings = {"model": scenario.model, "curves": curves, "quantities": names,
                "times": times.tolist(), "store": 2}
    spec = scenario.sweep
    attributes = {
        "title": scenario.title, "model": scenario.model, "method": scenario.method,
        "platform": scenario.platform, "truth": scenario.truth,
        "record_s": record, "draws": spec.draws, "seed": spec.seed,
        "random": {name: sigma for name, sigma in spec.random},
        "swept": [name for name, (_, attrs) in points.coordinates.items()
                  if attrs.get("swept")],
        "motion": {k: str(v) for k, v in scenario.motion.items()},
        "parameters": parameters_record(model, scenario.parameters),
        "Conventions": "ins-errors sweep store 2",
    }
    return Layout(len(points.jobs), times, tuple(names), tuple(units),
                  tuple(s.name for s in model.sources), tuple(s.unit for s in model.sources),
                  points.coordinates, curves, attributes,
                  fingerprint(points.jobs, settings))


def default_store(scenario_path: str | Path) -> Path:
    """``<scenario name>.zarr`` in the current folder."""
    return Path(f"{Path(scenario_path).stem}.zarr")


def run_sweep(scenario, store: str | Path, *, engine: str = "auto",
              scheduler: str | None = None, workers: int | None = None,
              progress: bool = False,
              on_result: Callable[[int], None] | None = None,
              retry_failed: bool = False) -> SweepResult:
    """Run (or finish) a sweep into a store.

    Parameters
    ----------
    scenario : ins_errors.scenario.Scenario
        With a ``[sweep]`` table.
    store : str or Path
        ``*.zarr`` (filled as points finish) or ``*.nc`` (NetCDF once complete).
    engine, scheduler, workers
        See :func:`ins_errors.analysis.engine.run_tasks`; ``scheduler`` defaults to
        the file's ``[sweep] scheduler``.
    progress : bool
        Progress bar over points.
    on_result : callable, optional
        Called with the point index after each point is stored (results or failure).
    retry_failed : bool
        Run again the points the store records as failed (by default they are kept:
        the same input fails the same way).

    Returns
    -------
    SweepResult
        Points that failed (:class:`PointError`) are in ``failed``; the others ran.
    """
    from ins_errors.analysis.engine import choose_engine, run_tasks
    from ins_errors.analysis.store import SweepStore, store_path

    store = store_path(store)  # a name of no known format, before anything is made
    scheduler = scheduler or scenario.sweep.scheduler
    engine = choose_engine(engine, scheduler)  # before any store is made
    points = grid(scenario)
    shape = layout(scenario, points)
    box = SweepStore.open(store, shape)
    todo = [k for k in range(len(points.jobs))
            if not box.done[k] or (retry_failed and box.failure[k])]
    reused = len(points.jobs) - len(todo)
    stats = None
    if todo:
        def keep(k: int, result: dict) -> None:
            box.write(todo[k], result)
            if on_result is not None:
                on_result(todo[k])

        def failed(k: int, error: InsErrorsError) -> None:
            if not isinstance(error, PointError):  # not a point's own outcome
                raise error
            box.fail(todo[k], error.reason)
            if on_result is not None:
                on_result(todo[k])

        stats = run_tasks(run_point, [(points.jobs[k],) for k in todo], engine=engine,
                          scheduler=scheduler, workers=workers, on_result=keep,
                          on_failure=failed, progress=progress, label="sweep")
    box.finish()
    return SweepResult(box.dataset(), Path(store), len(points.jobs),
                       len(todo), reused, stats, box.failed)


# --------------------------------------------------------------------------------------
# Summaries and plots
# --------------------------------------------------------------------------------------
def swept_names(dataset) -> list[str]:
    """Per-point coordinates that label the grid: the parameters in file order, then
    ``case`` and ``draw``."""
    return list(json.loads(dataset.attrs.get("swept", "[]")))


def model_parameters(dataset) -> dict[str, dict[str, object]]:
    """The model parameters the sweep set (its scenario's ``[parameters]``), as stored.

    Returns
    -------
    dict of str to dict
        Name -> ``{"value": SI value, "unit": SI unit}``, as
        :func:`ins_errors.model_parameters.parameters_record` gives it; empty when none
        was set (also for a store written before the record existed, whose fingerprint
        then says none was set).
    """
    return json.loads(dataset.attrs.get("parameters", "{}"))


def point_label(dataset, k: int) -> str:
    """Point ``k``'s swept values as the scenario wrote them, e.g.
    ``latitude = 70 deg, case 2, draw 5``."""
    parts = []
    for name in swept_names(dataset):
        value = dataset[name].values[k]
        if name == "case":
            parts.append(f"case {int(value) + 1}")
        elif name == "draw":
            parts.append(f"draw {int(value)}")
        else:
            attrs = dataset[name].attrs
            parameter = Parameter(name, "", attrs.get("units", "1"), (),
                                  attrs.get("display_unit", attrs.get("units", "1")))
            parts.append(f"{name} = {parameter.shown(float(value)):.6g} "
                         f"{parameter.display_unit}")
    return ", ".join(parts)


def failures(dataset) -> list[dict]:
    """The points that failed: index, swept values (SI, as :func:`summary`), their label
    as written (``"label"``) and the one-line reason (``"reason"``), in point order."""
    rows = []
    for k, reason in enumerate(failure_reasons(dataset)):
        if not reason:
            continue
        row: dict[str, Any] = {"point": k}
        for name in swept_names(dataset):
            value = dataset[name].values[k]
            row[name] = int(value) if name in ("case", "draw") else float(value)
        row["label"] = point_label(dataset, k)
        row["reason"] = reason
        rows.append(row)
    return rows


def failures_text(dataset, limit: int = 10) -> str:
    """One line per failed point (the first ``limit``, then how many more), or empty
    text when none failed."""
    rows = failures(dataset)
    if not rows:
        return ""
    from ins_errors.output import failure_list

    points = dataset.sizes["point"]
    return failure_list(f"{len(rows)} of {points} point{'s' if points != 1 else ''} failed "
                        "(stored without results; --retry-failed runs them again):",
                        [f"point {r['point']} ({r['label'] or 'the point'}): {r['reason']}"
                         for r in rows], limit)


def _worst(dataset, curve: str) -> tuple[np.ndarray, list[str | None]]:
    ratio = np.where(dataset["excited"].values == 1, dataset[f"{curve}_ratio"].values, -np.inf)
    k = np.argmax(ratio, axis=1)
    best = ratio[np.arange(len(k)), k]
    names = [str(dataset["quantity"].values[j]) if np.isfinite(b) else None
             for j, b in zip(k, best, strict=True)]
    return np.where(np.isfinite(best), best, np.nan), names


def worst_integration_ratio(dataset) -> np.ndarray:
    """Per point: worst over excited quantities of integration error / max |direct|
    (NaN where nothing is excited), shape (P,)."""
    excited = dataset["excited"].values == 1
    peak = dataset["max_direct"].values
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(excited & (peak > 0), dataset["integration_error"].values / peak,
                         -np.inf)
    best = np.max(ratio, axis=1) if ratio.size else np.full(len(ratio), -np.inf)
    return np.where(np.isfinite(best), best, np.nan)


def summary(dataset) -> list[dict]:
    """Per grid point: its labels, its failure reason (``None`` unless it failed; its
    numbers are then ``None``), worst linear (refined) ratio and max errors, SI."""
    rows = []
    labels = swept_names(dataset)
    quantities = [str(q) for q in dataset["quantity"].values]
    worst_linear, linear_names = _worst(dataset, "linear")
    integration = worst_integration_ratio(dataset)
    refined = "refined_ratio" in dataset
    if refined:
        worst_refined, refined_names = _worst(dataset, "refined")
    reasons = failure_reasons(dataset)
    for k in range(dataset.sizes["point"]):
        row: dict[str, Any] = {"point": k}
        for name in labels:
            value = dataset[name].values[k]
            row[name] = int(value) if name in ("case", "draw") else float(value)
        row["failure"] = reasons[k] or None
        row["worst_linear_ratio"] = _number(worst_linear[k])
        row["worst_linear_quantity"] = linear_names[k]
        if refined:
            row["worst_refined_ratio"] = _number(worst_refined[k])
            row["worst_refined_quantity"] = refined_names[k]
        row["max_direct"] = {q: _number(v) for q, v in
                             zip(quantities, dataset["max_direct"].values[k], strict=True)}
        row["linear_ratio"] = {q: _number(v) for q, v in
                               zip(quantities, dataset["linear_ratio"].values[k], strict=True)}
        row["integration_error"] = {q: _number(v) for q, v in zip(
            quantities, dataset["integration_error"].values[k], strict=True)}
        row["worst_integration_error_ratio"] = _number(integration[k])
        rows.append(row)
    return rows


def over_draws(dataset) -> list[dict]:
    """Monte Carlo statistics per grid point: over its draws, the RMS and the largest of
    each quantity's max |direct error| (SI) and the largest worst linear/direct ratio.

    Empty when the sweep has no draws. A draw that failed is not left out: the statistics
    of its grid point are ``None`` (unknown) and ``failed_draws`` counts and names it.
    """
    labels = [n for n in swept_names(dataset) if n != "draw"]
    if "draw" not in swept_names(dataset):
        return []
    quantities = [str(q) for q in dataset["quantity"].values]
    peaks = dataset["max_direct"].values
    worst = _worst(dataset, "linear")[0]
    reasons = failure_reasons(dataset)
    draw = dataset["draw"].values
    groups: dict[tuple, list[int]] = {}
    for k in range(dataset.sizes["point"]):
        key = tuple(float(dataset[n].values[k]) for n in labels)
        groups.setdefault(key, []).append(k)
    rows = []
    for key, members in groups.items():
        block = peaks[members]
        row: dict[str, Any] = dict(zip(labels, key, strict=True))
        row["draws"] = len(members)
        row["failed_draws"] = [int(draw[k]) for k in members if reasons[k]]
        row["rms_max_direct"] = {q: _number(v) for q, v in
                                 zip(quantities, np.sqrt(np.mean(block**2, axis=0)),
                                     strict=True)}
        row["largest_max_direct"] = {q: _number(v) for q, v in
                                     zip(quantities, np.max(block, axis=0), strict=True)}
        row["largest_worst_linear_ratio"] = (
            None if row["failed_draws"] else _number(np.nanmax(worst[members])))
        rows.append(row)
    return rows


def _number(value: float) -> float | None:
    value = float(value)
    return value if np.isfinite(value) else None


def table(dataset, quantities: Sequence[str] | None = None, limit: int = 40) -> str:
    """Plain-text table: one row per grid point (at most ``limit``)."""
    labels = swept_names(dataset)
    all_quantities = [str(q) for q in dataset["quantity"].values]
    if quantities is None:
        excited = dataset["excited"].values.any(axis=0)
        quantities = [q for q, e in zip(all_quantities, excited, strict=True)
                      if e and q.startswith("delta_")][:3]
    from ins_errors.units import display_scale

    scales = {q: display_scale(str(u)) for q, u in
              zip(all_quantities, dataset["quantity_unit"].values, strict=True)}
    shown = {}
    for name in labels:
        unit = dataset[name].attrs.get("display_unit", "")
        shown[name] = f"{name} [{unit}]" if unit and unit != "1" else name
    head = [*shown.values(), "worst lin/dir", "quantity", "integ. err/err",
            *(f"max {q} [{scales[q][1]}]" for q in quantities)]
    rows = []
    worst, names = _worst(dataset, "linear")
    integration = worst_integration_ratio(dataset)
    reasons = failure_reasons(dataset)
    for k in range(min(dataset.sizes["point"], limit)):
        cells = []
        for name in labels:
            value = float(dataset[name].values[k])
            attrs = dataset[name].attrs
            unit, display = attrs.get("units", "1"), attrs.get("display_unit", "1")
            cells.append(f"{Parameter(name, '', unit, (), display).shown(value):.6g}")
        if reasons[k]:
            rows.append([*cells, "failed", *(["–"] * (len(head) - len(cells) - 1))])
            continue
        cells += [f"{worst[k]:.3e}" if np.isfinite(worst[k]) else "–", names[k] or "–",
                  f"{integration[k]:.1e}" if np.isfinite(integration[k]) else "–"]
        for q in quantities:
            value = dataset["max_direct"].values[k, all_quantities.index(q)]
            cells.append(f"{value * scales[q][0]:.4g}")
        rows.append(cells)
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h)
              for i, h in enumerate(head)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    if dataset.sizes["point"] > limit:
        lines.append(f"... {dataset.sizes['point'] - limit} more points (--json for all)")
    return "\n".join(lines)


def draws_table(dataset, quantities: Sequence[str] | None = None) -> str:
    """Plain-text table of :func:`over_draws` (empty text without draws)."""
    from ins_errors.units import display_scale

    rows = over_draws(dataset)
    if not rows:
        return ""
    names = [str(q) for q in dataset["quantity"].values]
    units = dict(zip(names, (str(u) for u in dataset["quantity_unit"].values), strict=True))
    if quantities is None:
        quantities = [q for q in names if q.startswith("delta_")
                      and any(r["largest_max_direct"][q] for r in rows)][:3]
    labels = [n for n in swept_names(dataset) if n != "draw"]
    shown = []
    for name in labels:
        unit = dataset[name].attrs.get("display_unit", "1")
        shown.append(f"{name} [{unit}]" if unit != "1" else name)
    any_failed = any(row["failed_draws"] for row in rows)
    head = [*shown, "draws", *(["failed"] if any_failed else []), "largest lin/dir",
            *(f"RMS max {q} [{display_scale(units[q])[1]}]" for q in quantities)]
    body = []
    for row in rows:
        cells = []
        for name in labels:
            attrs = dataset[name].attrs
            parameter = Parameter(name, "", attrs.get("units", "1"), (),
                                  attrs.get("display_unit", "1"))
            cells.append(f"{parameter.shown(row[name]):.6g}")
        ratio = row["largest_worst_linear_ratio"]
        cells += [str(row["draws"]), *([str(len(row["failed_draws"]))] if any_failed else []),
                  "–" if ratio is None else f"{ratio:.3e}"]
        for q in quantities:
            value = row["rms_max_direct"][q]
            cells.append("–" if value is None else f"{value * display_scale(units[q])[0]:.4g}")
        body.append(cells)
    widths = [max(len(h), *(len(r[i]) for r in body)) for i, h in enumerate(head)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in body]
    return "\n".join(lines)


def figure_values(dataset, figure: str) -> tuple[np.ndarray, str]:
    """Per-point values of a figure (see :data:`FIGURES`) and its axis label (errors in
    the display units of :data:`ins_errors.units.DISPLAY_UNITS`)."""
    if figure in ("worst_linear_ratio", "worst_refined_ratio"):
        curve = figure.split("_")[1]
        if f"{curve}_ratio" not in dataset:
            raise SweepError(f"figure {figure!r}: the sweep ran without the {curve} model")
        return _worst(dataset, curve)[0], f"worst {curve}/direct ratio"
    kind, _, quantity = figure.partition(":")
    if kind not in ("max_direct", "linear_ratio", "refined_ratio") or not quantity:
        raise unknown_name("figure", figure, FIGURES)
    if kind not in dataset:
        raise SweepError(f"figure {figure!r}: the sweep ran without the refined model")
    names = [str(q) for q in dataset["quantity"].values]
    if quantity not in names:
        raise unknown_name("error quantity", quantity, names)
    from ins_errors.units import display_scale

    j = names.index(quantity)
    scale, unit = (display_scale(str(dataset["quantity_unit"].values[j]))
                   if kind == "max_direct" else (1.0, "1"))
    title = {"max_direct": f"max |{quantity}|", "linear_ratio": f"{quantity} linear/direct",
             "refined_ratio": f"{quantity} refined/direct"}[kind]
    return dataset[kind].values[:, j] * scale, f"{title} [{unit}]"


BAR_WIDTH, BAR_PAD = 0.18, 0.25
"""Width of the colour bar of :func:`plot` and its gap from the panel, inches."""


def _tick_labels(axis) -> tuple[list[str], str]:
    """The tick labels an axis will draw at its current limits, and its offset text
    (from its locator and formatter, without drawing)."""
    low, high = sorted(axis.get_view_interval())
    span = (high - low) * 1e-9
    locs = [v for v in axis.get_majorticklocs() if low - span <= v <= high + span]
    formatter = axis.get_major_formatter()
    return formatter.format_ticks(locs), formatter.get_offset()


def _fixed_margins(figure_, ax, bar, heading: str) -> None:
    """Place the panel (and colour bar) with margins that fit its labels and title.

    Sizes in inches: tick labels measured at their formatted values, a line of text
    1.2 × its size high. Replaces ``tight_layout``, which draws the figure once more
    only to measure it.
    """
    width, height = figure_.get_size_inches()
    size = 10 / 72  # the default font size, inches
    ticks = 7 / 72  # tick length + pad
    for _ in range(2):  # the tick labels chosen for the panel's first size, then its own
        ylabels, yoffset = _tick_labels(ax.yaxis)
        xlabels, xoffset = _tick_labels(ax.xaxis)
        blabels, boffset = _tick_labels(bar.ax.yaxis) if bar is not None else ([], "")
        left = 0.12 + 1.2 * size + 4 / 72 + text_width(ylabels, 10) + ticks
        bottom = 0.12 + 1.2 * size * 2 + 4 / 72 + ticks + (1.2 * size if xoffset else 0.0)
        right = 0.15 + text_width(xlabels[-1:], 10) / 2
        if bar is not None:  # the bar, its tick labels and its label right of the panel
            labels = 0.12 + 1.2 * size + 4 / 72 + text_width(blabels, 10) + ticks
            right = max(right, labels + BAR_WIDTH + BAR_PAD)
        title = wrap_to_width(heading, 10, width - left - right)  # (over the panel only)
        ax.set_title(title, fontsize=10)
        top = 0.12 + 1.2 * size * (title.count("\n") + 1) + 6 / 72 + (
            1.2 * size + 0.05 if yoffset or boffset else 0.0)
        if bar is not None:
            bar.ax.set_position(((width - right + BAR_PAD) / width, bottom / height,
                                 BAR_WIDTH / width, (height - top - bottom) / height))
        ax.set_position((left / width, bottom / height, (width - left - right) / width,
                         (height - top - bottom) / height))


MAX_GRID_TICKS = 12
"""A colour map's axis with at most this many grid values has a tick at each of them."""


def cell_edges(values: Sequence[float]) -> np.ndarray:
    """Cell edges of a colour map over sorted grid values.

    Inner edges lie halfway between neighbouring values; the outer edges are the first
    and last values themselves (the outer cells are half as wide), so the axis spans
    exactly the swept range. A single value gets a cell of ±5 % of its size (±0.5 at 0).

    Parameters
    ----------
    values : sequence of float, shape (n,)
        Increasing grid values, in the axis's unit.

    Returns
    -------
    numpy.ndarray, shape (n + 1,)
    """
    v = np.asarray(values, dtype=float)
    if v.size == 1:
        half = 0.05 * abs(v[0]) or 0.5
        return np.array([v[0] - half, v[0] + half])
    return np.concatenate([v[:1], (v[1:] + v[:-1]) / 2, v[-1:]])


def plot(dataset, figure: str, against: Sequence[str], path: str | Path) -> Path:
    """Plot a figure against one (line) or two (colour map) swept parameters.

    Points that differ in the other swept labels are reduced to their maximum (the worst
    case over them), which the title says. A colour map's cells end at the first and
    last grid values (:func:`cell_edges`); dots mark the grid points.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = swept_names(dataset)
    if not 1 <= len(against) <= 2:
        raise SweepError("--against takes one or two swept parameters, e.g. latitude,heading")
    for name in against:
        if name not in labels:
            raise unknown_name("swept parameter", name, labels)
    values, title = figure_values(dataset, figure)
    axes = []
    for name in against:
        attrs = dataset[name].attrs
        parameter = Parameter(name, "", attrs.get("units", "1"), (),
                              attrs.get("display_unit", attrs.get("units", "1")))
        shown = np.array([parameter.shown(v) for v in dataset[name].values])
        axes.append((name, parameter.display_unit, shown))
    others = [n for n in labels if n not in against]
    keys = [tuple(a[2][k] for a in axes) for k in range(len(values))]
    reduced: dict[tuple, float] = {}
    for key, value in zip(keys, values, strict=True):
        if np.isfinite(value):
            reduced[key] = max(reduced.get(key, -np.inf), float(value))
    figure_, ax = plt.subplots(figsize=(7.0, 4.5))
    bar = None
    if len(axes) == 1:
        xs = sorted(reduced)
        ax.plot([x[0] for x in xs], [reduced[x] for x in xs], "o-")
        ax.set_xlabel(f"{axes[0][0]} [{axes[0][1]}]")
        ax.set_ylabel(title)
    else:
        xs = sorted({k[0] for k in reduced})
        ys = sorted({k[1] for k in reduced})
        grid_ = np.full((len(ys), len(xs)), np.nan)
        for (x, y), v in reduced.items():
            grid_[ys.index(y), xs.index(x)] = v
        # cells end at the grid's first and last values: the axes span the swept range
        # and no more; ticks (when few) and dots mark the values that were run
        mesh = ax.pcolormesh(cell_edges(xs), cell_edges(ys), grid_, shading="flat")
        ax.plot([x for x, _ in reduced], [y for _, y in reduced], "k.", markersize=4,
                clip_on=False, zorder=3)  # the edge points drawn whole
        for values_, axis in ((xs, ax.xaxis), (ys, ax.yaxis)):
            if len(values_) <= MAX_GRID_TICKS:
                axis.set_ticks(values_)
        # on an axes of its own, placed by _fixed_margins
        bar = figure_.colorbar(mesh, cax=figure_.add_axes((0.9, 0.1, 0.02, 0.8)),
                               label=title)
        ax.set_xlabel(f"{axes[0][0]} [{axes[0][1]}]")
        ax.set_ylabel(f"{axes[1][0]} [{axes[1][1]}]")
    heading = dataset.attrs.get("title", "sweep")
    if others:
        heading += f"\n(max over {', '.join(others)})"
    ax.grid(True, alpha=0.3)
    _fixed_margins(figure_, ax, bar, heading)
    from ins_errors.output import save_figure

    return save_figure(figure_, path, dpi=120)  # atomic, parent folders created
