"""Sweeps: a scenario run over a grid of parameters, one task per grid point.

A scenario file (:mod:`ins_errors.scenario`) gains an optional ``[sweep]`` table::

    [sweep]
    latitude = ["30 deg", "50 deg", "70 deg"]          # motion parameters
    heading = { start = "0 deg", stop = "90 deg", count = 4 }
    duration = ["1 h", "2 h"]                          # run length (or step)
    gyro_drift_x = ["0.005 deg/h", "0.01 deg/h"]       # error-source magnitudes
    k_h1 = ["0.002/s", "0.0047/s"]                     # model parameters (gains...)
    draws = 100                                        # Monte Carlo draws per point
    seed = 7                                           # of the draws
    scheduler = "tcp://10.0.0.5:8786"                  # optional Dask cluster
    [sweep.random]                                     # 1σ of the drawn sources
    accel_bias_x = "50 ug"

Sweepable names: the motion's ``latitude``, ``longitude``, ``heading``, ``speed``,
``height``; the run's ``duration`` and ``step``; any error source of the model (its
magnitude in the scenario's case); any parameter of the model (``ins-errors models
MODEL`` lists them: a damping gain, the Earth radius...), its values with units as
``--parameter NAME=VALUE`` takes them, in place of the scenario's ``[parameters]`` value.
A key of the scenario (a motion or run setting, or ``draws``, ``seed``, ``random``,
``scheduler``) keeps its meaning for every model: a model parameter of the same name is
set by ``[parameters]`` only, and the sweep says so in a note. The grid is the product of
every list (first name slowest), of the scenario's cases (when there are several) and of
the draws. A draw adds
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
deterministic as its numbers. Points whose simulation loops would have numbers of their
own compiled in (several static-base motions, model parameters: :func:`loop_combinations`)
run with loops that read those numbers at run time, compiled once for the whole sweep
(:func:`run_point_with_loops`), with the same results to the last bit.

A sweep may be split into *shards* (:class:`Shard`, ``--shard I/N``) run by separate
jobs, each into its own store: shard ``I`` of ``N`` runs the points ``I - 1, I - 1 + N,
I - 1 + 2N, ...`` of the fixed point order above (Monte Carlo draws included), whatever
engine runs them. :func:`merge_shards` checks that a set of shard stores holds every
point of one sweep exactly once and writes them into one store, bit-identical to the
store of the same sweep run whole. A sweep has at most :data:`MAX_POINTS` points
(:func:`point_count` counts them before any is built).

The worst ratios of a point (:func:`summary`, the tables and plots) judge the quantities
of the scenario's ``[outputs] quantities`` (all of them when it has none), as ``run``
does; the store records that list in its ``judged_quantities`` attribute.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from ins_errors.analysis.store import POINT_KEY, failure_reasons
from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.units import parse_quantity, typed_value

MOTION_PARAMETERS: dict[str, str] = {"latitude": "rad", "longitude": "rad", "heading": "rad",
                                     "speed": "m/s", "height": "m"}
"""Sweepable motion settings and their SI units."""

RUN_PARAMETERS: dict[str, str] = {"duration": "s", "step": "s"}
"""Sweepable run settings and their SI units."""

CONTROL_KEYS = ("draws", "seed", "random", "scheduler")
"""Keys of ``[sweep]`` that are not grids."""

MAX_POINTS = 100_000
"""Most points a sweep may have. Every process of a sweep (each shard's too) holds the
list of all its points and their identity (about 2 KB and 0.1 ms each: a process of a
100 000-point sweep takes some 300 MB and 10 s before the first point runs), and the
store has a few files per point and variable; a larger study is split into several
sweep files."""

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
        ``"motion"``, ``"run"``, ``"source"`` or ``"parameter"`` (of the model).
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

    def text(self, value: float) -> str:
        """``value`` (SI) as text in :attr:`display_unit`, ``"89.99999 deg"``: six
        significant digits, more where six would show another value
        (:func:`number_text`)."""
        return f"{number_text(self.shown(value))} {self.display_unit}"


def number_text(value: float, least: int = 6) -> str:
    """``value`` with ``least`` significant digits, or the fewest more that still read
    as ``value``: 89.99999 is ``"89.99999"``, not ``"90"`` (a pole), and 15 converted
    from radians and back (15.000000000000002) is ``"15"``.

    Parameters
    ----------
    value : float
        The number, in the unit it is shown in.
    least : int
        Significant digits at least.

    Returns
    -------
    str
        The text with the fewest digits, from ``least`` to :data:`MOST_DIGITS`, that
        reads back within 4 units in the last place of ``value`` (the noise a unit
        conversion leaves); a value that needs more (1/6 of a degree from an uneven
        range) is shown with :data:`MOST_DIGITS`, which tell it from its neighbours.
    """
    if not math.isfinite(value) or value == 0.0:
        return f"{value:g}"
    for digits in range(least, max(least, MOST_DIGITS) + 1):
        text = f"{value:.{digits}g}"
        if abs(float(text) - value) <= 4 * math.ulp(value):
            return text
    return text


MOST_DIGITS = 10
"""Significant digits :func:`number_text` shows at most (a sweep's values differ in far
fewer)."""


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


@dataclass(frozen=True)
class Shard:
    """Shard ``index`` of ``count`` of a sweep: the points ``index - 1``,
    ``index - 1 + count``, ``index - 1 + 2 count``, ... of its fixed point order.

    Attributes
    ----------
    index : int
        1 to ``count``.
    count : int
        Number of shards (jobs) the sweep is split into.
    """

    index: int
    count: int

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"

    def points(self, total: int) -> range:
        """Indices of this shard's points among ``total``."""
        return range(self.index - 1, total, self.count)


_SHARD = re.compile(r"^\s*(\d+)\s*/\s*(\d+)\s*$")


def parse_shard(text: str) -> Shard:
    """Read ``--shard I/N``.

    Raises
    ------
    SweepError
        Not two whole numbers ``I/N`` with ``1 <= I <= N`` (one line).
    """
    match = _SHARD.match(str(text))
    if not match:
        raise SweepError(f"--shard {text!r}: give I/N, shard I of N with whole numbers "
                         "1 <= I <= N (e.g. --shard 2/8; in a SLURM array job "
                         "--shard $SLURM_ARRAY_TASK_ID/8 with --array=1-8)")
    index, count = int(match.group(1)), int(match.group(2))
    if count < 1:
        raise SweepError(f"--shard {text}: N, the number of shards, must be at least 1")
    if not 1 <= index <= count:
        raise SweepError(f"--shard {text}: I must be 1 to {count} (shards are numbered "
                         f"from 1; a SLURM array for them is --array=1-{count})")
    return Shard(index, count)


def check_shard(shard: Shard, points: int) -> None:
    """Refuse a split into more shards than the sweep has points (a shard without any).

    Raises
    ------
    SweepError
    """
    if shard.count > points:
        raise SweepError(f"--shard {shard}: the sweep has {points} point"
                         f"{'s' if points != 1 else ''}, so it splits into at most {points} "
                         "shards")


def _display_unit(text: Any, unit: str) -> str:
    match = re.match(r"^\s*[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?\s*(.+?)\s*$", str(text))
    if isinstance(text, str) and match:
        written = match.group(1)
        if written.startswith("/"):  # '5e-4/s', as -p takes it: shown as '1/s'
            written = f"1{written}"
        try:
            parse_quantity(f"1 {written}", unit)
        except InsErrorsError:
            return unit
        return written
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
            raise SweepError(f"{what} value {text!r} needs a unit, e.g. "
                             f"'{typed_value(text, unit)}'")
    return parse_quantity(text, unit, what, numbers_are_si=False)


def _grid_size(name: str, raw: Any, where: str) -> int:
    """How many values a grid as written has (its ``count``, or its list's length),
    checked without converting or building any of them."""
    what = f"{where} [sweep] {name}"
    if isinstance(raw, dict):
        extra = set(raw) - {"start", "stop", "count"}
        if extra or len(raw) != 3:
            raise SweepError(f"{what}: a range is {{ start = ..., stop = ..., count = N }}"
                             f"{'; unknown ' + ', '.join(sorted(extra)) if extra else ''}")
        count = raw["count"]
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise SweepError(f"{what}: count must be a positive integer, got {count!r}")
        return count
    if not isinstance(raw, list) or not raw:
        raise SweepError(f"{what}: give a non-empty list of values or "
                         "{ start = ..., stop = ..., count = N }")
    return len(raw)


def _grid(name: str, raw: Any, unit: str, where: str) -> tuple[tuple[float, ...], str]:
    what = f"{where} [sweep] {name}"
    count = _grid_size(name, raw, where)
    if isinstance(raw, dict):
        start = _value(raw["start"], unit, what)
        stop = _value(raw["stop"], unit, what)
        values = tuple(float(v) for v in np.linspace(start, stop, count))
        if count > 1 and same_value(start, stop):
            raise SweepError(f"{what}: start {raw['start']!r} and stop {raw['stop']!r} are "
                             f"the same value, so its {count} values are one; give "
                             "count = 1 or another stop")
        if count == 1 and not same_value(start, stop):  # (was: the stop dropped, silently)
            raise SweepError(f"{what}: a range of one point (count = 1) has no stop: "
                             f"{raw['stop']!r} would never run; write the value alone "
                             f"({name} = [{raw['start']!r}]) or count = 2 or more")
        return values, _display_unit(raw["start"], unit)
    values = tuple(_value(v, unit, what) for v in raw)
    _refuse_equal(values, raw, what)
    return values, _display_unit(raw[0], unit)


SAME_VALUE = 1e-12
"""Relative difference within which two grid values are the same value (a rounding of
one unit's conversion: ``45 deg`` and ``2700 arcmin`` differ by one unit in the last
place in radians): a grid giving both is refused; a grid extending a store takes the
store's value for one within it."""


def same_value(a: float, b: float) -> bool:
    """Whether ``a`` and ``b`` are equal within :data:`SAME_VALUE`, relative."""
    return abs(a - b) <= SAME_VALUE * max(abs(a), abs(b))


def _refuse_equal(values: Sequence[float], written: Sequence[Any], what: str) -> None:
    """Refuse a grid with two values equal within :data:`SAME_VALUE` (naming both as
    written): their points would be the same runs, rows and plot cells twice."""
    order = sorted(range(len(values)), key=lambda k: values[k])
    for i, j in itertools.pairwise(order):
        if same_value(values[i], values[j]):
            a, b = (written[k] for k in sorted((i, j)))
            shown = (f"{a!r} is listed twice" if a == b else f"{a!r} and {b!r} are the "
                     f"same value (within {SAME_VALUE:g}, relative)")
            raise SweepError(f"{what}: {shown}; give each value once")


def parse_sweep(raw: Any, model, where: str, cases: int = 1) -> SweepSpec:
    """Check and convert a ``[sweep]`` table (called by :func:`ins_errors.scenario.load_scenario`).

    Parameters
    ----------
    raw : dict
        The table as TOML read it.
    model : ins_errors.numeric.model.Model
        The scenario's model (source names and units).
    where : str
        File name for messages.
    cases : int
        The scenario's ``[[case]]`` tables (a factor of the point count).

    Raises
    ------
    SweepError, UnknownNameError, UnitError
        One line naming the key and the problem; more than :data:`MAX_POINTS` points
        (:func:`refuse_too_many`), found from the grids' sizes as written, before any
        grid value is built or converted.
    """
    if not isinstance(raw, dict):
        raise SweepError(f"{where}: 'sweep' must be a table, [sweep]")
    source_units = {s.name: s.unit for s in model.sources}
    parameter_units = {p.name: p.unit for p in model.parameters}
    known = [*MOTION_PARAMETERS, *RUN_PARAMETERS, *source_units, *CONTROL_KEYS,
             *(name for name in parameter_units if name not in SCENARIO_KEYS)]
    kinds = {}
    for name in raw:
        if name in SCENARIO_KEYS and name in parameter_units:
            _note_shadowed(name, model, where)
        if name in CONTROL_KEYS:
            continue
        if name in MOTION_PARAMETERS:
            kinds[name] = "motion", MOTION_PARAMETERS[name]
        elif name in RUN_PARAMETERS:
            kinds[name] = "run", RUN_PARAMETERS[name]
        elif name in source_units:
            kinds[name] = "source", source_units[name]
        elif name in parameter_units:
            kinds[name] = "parameter", parameter_units[name]
        else:
            raise unknown_name(f"key in {where} [sweep]", name, known)
    draws = raw.get("draws", 0)
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 0:
        raise SweepError(f"{where} [sweep] draws must be a whole number >= 0, got {draws!r}")
    # the size of the sweep from the sizes as written: a count of 10**9 would take
    # gigabytes (and minutes) to build before the point count could refuse it
    factors = [(_grid_size(name, raw[name], where), name) for name in kinds]
    factors += [(cases, "cases")] if cases > 1 else []
    factors += [(draws, "draws")] if draws else []
    refuse_too_many(factors, f"{where} [sweep]: ")
    parameters = []
    for name, (kind, unit) in kinds.items():
        values, shown = _grid(name, raw[name], unit, where)
        if kind == "run" and min(values) <= 0:
            raise SweepError(f"{where} [sweep] {name}: values must be positive")
        parameter = Parameter(name, kind, unit, values, shown)
        if kind == "parameter":
            _check_parameter_values(model, parameter, where)
        parameters.append(parameter)
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


SCENARIO_KEYS = frozenset((*MOTION_PARAMETERS, *RUN_PARAMETERS, *CONTROL_KEYS))
"""``[sweep]`` keys that mean the same for every model: a model parameter of one of
these names is not swept by them (it is set by ``[parameters]`` only)."""


def _note_shadowed(name: str, model, where: str) -> None:
    """Say (a one-line note) that ``[sweep] name`` is the scenario's setting, not the
    model's parameter of the same name."""
    import warnings

    what = ("the motion's" if name in MOTION_PARAMETERS else
            "the run's" if name in RUN_PARAMETERS else "the sweep's own")
    warnings.warn(f"ins-errors: note: {where} [sweep] {name} is {what} {name}, not "
                  f"the parameter {name} of model {model.name!r} (a parameter named like "
                  "a scenario key is set by [parameters] only; rename it in the model "
                  "to sweep it)", stacklevel=3)


def _check_parameter_values(model, parameter: Parameter, where: str) -> None:
    """Refuse a grid value no run can take as the model parameter (a negative damping
    gain, an Earth radius below 100 km, ...: :func:`ins_errors.model_parameters
    .parameter_problem`), naming the value as the file's unit shows it.

    Raises
    ------
    SweepError
    """
    from ins_errors.model_parameters import parameter_info, parameter_problem

    info = parameter_info(model, parameter.name)
    for value in parameter.values:
        problem = parameter_problem(model, info, value)
        if problem is not None:
            raise SweepError(f"{where} [sweep] {parameter.name} = "
                             f"{parameter.text(value)}: {problem}")


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
        Model parameters set by the scenario's ``[parameters]`` table or swept, SI.
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
    point_count(scenario)  # refused beyond MAX_POINTS before any point is built
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
                parameters = dict(scenario.parameters)  # a grid replaces its value
                for p, v in zip(spec.parameters, values, strict=True):
                    labels[p.name].append(v)
                    if p.kind == "motion":  # exact SI value, with its unit as text
                        motion[p.name] = f"{v!r} {p.unit}"
                    elif p.kind == "parameter":
                        parameters[p.name] = v
                    elif p.name == "duration":
                        duration = v
                    elif p.name == "step":
                        step = v
                    else:
                        sources[p.name] = v
                case_index.append(case)
                draw_index.append(-1 if draw is None else draw)
                label = [f"{p.name} = {p.text(v)}"
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
                    tuple(sorted(parameters.items())), scenario.truth,
                    in_si_text[written]))
    _check_grids(scenario, jobs)
    _check_references(scenario, jobs)
    coordinates = {p.name: (np.array(labels[p.name]), {"units": p.unit, "display_unit":
                                                       p.display_unit, "swept": 1,
                                                       **_described(scenario, p)})
                   for p in spec.parameters}
    if len(cases) > 1:
        coordinates["case"] = (np.array(case_index), {
            "long_name": "case number in the scenario file", "units": "1", "swept": 1,
            "labels": json.dumps([c.label for c in scenario.cases])})
    if spec.draws:
        coordinates["draw"] = (np.array(draw_index), {
            "long_name": "Monte Carlo draw", "units": "1", "swept": 1})
    return Grid(jobs, coordinates, spec.parameters)


def _described(scenario, parameter: Parameter) -> dict[str, str]:
    """A swept model parameter's ``long_name`` for its store coordinate (``"model
    parameter k_v: velocity damping gain"``): its name alone says little. Empty for the
    other kinds, whose names say what they are."""
    if parameter.kind != "parameter":
        return {}
    from ins_errors.model_parameters import parameter_info
    from ins_errors.numeric.model import load_model

    info = parameter_info(load_model(scenario.model), parameter.name)
    return {"long_name": f"model parameter {info.name}: {info.description}"}


def point_count(scenario) -> int:
    """The number of points of a scenario's sweep (grid values × cases × draws), counted
    without building them.

    Raises
    ------
    SweepError
        More than :data:`MAX_POINTS` points (one line with the factors).
    """
    spec: SweepSpec = scenario.sweep
    factors = [(len(p.values), p.name) for p in spec.parameters]
    if len(scenario.cases) > 1:
        factors.append((len(scenario.cases), "cases"))
    if spec.draws:
        factors.append((spec.draws, "draws"))
    return refuse_too_many(factors)


def refuse_too_many(factors: Sequence[tuple[int, str]], where: str = "") -> int:
    """The number of points of a sweep of these factors (size, name), refused beyond
    :data:`MAX_POINTS`.

    Raises
    ------
    SweepError
        More than :data:`MAX_POINTS` points (one line giving the factors).
    """
    count = math.prod(size for size, _ in factors)
    if count > MAX_POINTS:
        product = " × ".join(f"{size:,} {name}" for size, name in factors)
        raise SweepError(f"{where}the sweep has {count:,} points ({product}), more than the "
                         f"{MAX_POINTS:,} a sweep may have (every process holds the list "
                         "of its points); split it into several sweep files")
    return count


def _check_grids(scenario, jobs: Sequence[PointJob]) -> None:
    """Every point's duration, step and recording interval fit together; motions are
    valid; every point's model parameters are within the model's own parameter domain.

    Raises
    ------
    InsErrorsError
        One line naming the scenario file as given, ``[sweep]`` and the first point that
        cannot run.
    """
    from ins_errors.numeric.integrators import record_stride, step_count
    from ins_errors.numeric.motion_spec import motion_profile

    where = f"{scenario.file or 'scenario'} [sweep]"
    seen: set = set()
    for job in jobs:
        if (job.duration, job.step) in seen:
            continue
        seen.add((job.duration, job.step))
        try:
            steps = step_count(job.duration, job.step, "duration")
            record_stride(scenario.record, job.step, steps)
        except InsErrorsError as error:
            raise type(error)(f"{where} at the point {job.label}: {error}") from None
    seen = set()
    for job in jobs:
        motion = json.dumps(dict(job.motion), sort_keys=True)
        if motion in seen:
            continue
        seen.add(motion)
        try:
            motion_profile(json.loads(motion), base=scenario.base)
        except InsErrorsError as error:
            raise type(error)(f"{where} at the point {job.label}: {error}") from None
    if not any(p.kind == "parameter" for p in scenario.sweep.parameters):
        return  # (the scenario's own parameters were checked when it was read)
    from ins_errors.numeric.model import load_model

    model = load_model(scenario.model)
    seen = set()
    for job in jobs:
        if job.parameters in seen:
            continue
        seen.add(job.parameters)
        try:
            model.parameter_vector(ellipsoid=scenario.ellipsoid, **dict(job.parameters))
        except InsErrorsError as error:
            raise type(error)(f"{where} at the point {job.label}: {error}") from None


def _check_references(scenario, jobs: Sequence[PointJob]) -> None:
    """Refuse a reference value of the motion's start (latitude, longitude, heading,
    height) that the sweep sets, in ``[motion]`` or as a grid, for a model whose runs do
    not depend on it (a tangent-plane INS whose origin latitude is its parameter
    ``phi0``): every point would run the same, whatever the file says.

    Decided, as ``run`` and ``compare`` decide it, from the true motion of the first
    point (one step of it, streamed: no run is made); a first point that cannot start
    is left to fail as a point.

    Raises
    ------
    MotionError
        One line naming the file, the table and key, and the model's own setting of the
        value (its parameter) or that the key is to be left out.
    """
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import motion_profile

    where = scenario.file or "scenario"
    swept = {p.name: p for p in scenario.sweep.parameters if p.name in tr.REFERENCES}
    given = {name: (f"{where} [motion] {name}", str(scenario.motion[name]))
             for name in tr.REFERENCES
             if name not in swept and scenario.motion.get(name) is not None}
    if not swept and not given:
        return
    first = jobs[0]
    model = load_model(scenario.model)
    from ins_errors.numeric.motion_spec import refuse_file_heading

    # every point would fly the file's own course (the points do not pass the model)
    refuse_file_heading(model, dict(first.motion).get("kind"),
                        "heading" in swept or "heading" in given,
                        f"{where} {'[sweep]' if 'heading' in swept else '[motion]'} heading")
    try:
        profile = motion_profile(dict(first.motion), base=scenario.base, model=model)
        p = model.parameter_vector(ellipsoid=scenario.ellipsoid, **dict(first.parameters))
        start = tr.trajectory(model, profile, first.step, first.step, p=p, stream=True,
                              truth=scenario.truth)
    except InsErrorsError:
        return  # the point fails with its own reason
    tr.refuse_unused_references(model, start, given,
                                setting='[parameters] {name} = "{value}"')
    used = start.references
    for name, parameter in swept.items():
        if used is None or name in used:
            continue
        own = tr.reference_parameter(model, name)
        shown = ", ".join(parameter.text(v) for v in parameter.values)
        values = ", ".join(f'"{parameter.text(v)}"' for v in parameter.values)
        way = (f"its parameter {own.name} ({own.description}) sets it: sweep that, "
               f"[sweep] {own.name} = [{values}]"
               if own is not None and own.name not in SCENARIO_KEYS else
               f"its parameter {own.name} ({own.description}) sets it, one value per "
               f'scenario file: [parameters] {own.name} = "'
               f'{parameter.text(parameter.values[0])}"'
               if own is not None else f"leave {name} out of [sweep]")
        raise tr.MotionError(f"{where} [sweep] {name}: model {model.name!r} has no {name} "
                             f"(its runs do not depend on one), so its values {shown} would "
                             f"all run alike; {way}")


def _stamp(path: Path) -> tuple[int, int]:
    """(modification time in ns, size) of a file, (0, 0) when it cannot be read: what
    tells an edited file in the cache key of :func:`_trajectory`."""
    try:
        status = path.stat()
    except OSError:
        return 0, 0
    return status.st_mtime_ns, status.st_size


@lru_cache(maxsize=4)
def _trajectory(model_name: str, motion: str, base: str, duration: float, step: float,
                ellipsoid: str | None, parameters: tuple[tuple[str, float], ...] = (),
                truth: str = "auto", files: tuple = ()):
    """The true motion of a point (kept for the next point with the same motion; ``files``:
    the :func:`_stamp` of its model and motion files, so an edited one is flown again)."""
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


def loop_combinations(jobs: Sequence[PointJob]) -> int:
    """How many sets of numbers the points' baked simulation loops would compile in: one
    per distinct model, ellipsoid and model-parameter values, and static-base motion
    (whose constant inputs are baked in; a moving base's are read as the run goes).

    Each set costs a compile of a few seconds (about 3.5 s of CPU for the strapdown
    model's three loops) against a few hundredths of a second to run a 90-min point at
    1 s, so more than one set makes the sweep take loops with run-time constants
    (:func:`run_point_with_loops`): one compile for all of them (per structure), with the
    same results and speed (:class:`~ins_errors.numeric.integrators.CompiledLoop`).
    """
    from ins_errors.numeric.motion_spec import in_si

    seen = set()
    for job in jobs:
        motion = dict(job.motion_si) if job.motion_si else in_si(dict(job.motion))
        static = motion.get("kind") == "static"
        seen.add((job.model, job.base if job.model.endswith(".py") else "", job.ellipsoid,
                  job.parameters, json.dumps(motion, sort_keys=True) if static else None))
    return len(seen)


def run_point_with_loops(runtime_constants: bool, job: PointJob) -> dict[str, np.ndarray]:
    """:func:`run_point` with the simulation loops that take the model parameters and
    a static base's inputs at run time (``runtime_constants``,
    :func:`ins_errors.numeric.simulate.runtime_constant_loops`) or the baked ones: the
    same numbers either way, compiled once per sweep or once per
    :func:`loop_combinations` set."""
    from ins_errors.numeric.simulate import runtime_constant_loops

    with runtime_constant_loops(runtime_constants):
        return run_point(job)


def _run_point(job: PointJob) -> dict[str, np.ndarray]:
    from ins_errors.analysis.monte_carlo import draw_generator
    from ins_errors.numeric.compare import compare
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.simulate import error_quantities

    model = load_model(job.model)
    motion = json.dumps(dict(job.motion_si or job.motion), sort_keys=True)
    file = dict(job.motion).get("file")
    files = (_stamp(Path(job.base) / job.model) if job.model.endswith(".py") else (),
             _stamp(Path(job.base) / str(file)) if file is not None else ())
    trajectory = _trajectory(job.model, motion, job.base, job.duration, job.step,
                             job.ellipsoid, job.parameters, job.truth, files)
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
                           validity_threshold=None, warn=False)
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
        Everything the store holds (see :mod:`ins_errors.analysis.store`); of a shard,
        its points only (their ``point`` coordinate numbers them in the whole sweep).
    store : Path
    points, computed, reused : int
        Points of this run (of a shard: its share), points run by this call (including
        those that failed), points read back from the store.
    engine : EngineStats or None
        None when every point was already stored.
    failed : list of int
        Points that failed (run by this call or read back), in order; their reasons
        are in :func:`failures`.
    total : int
        Points of the whole sweep.
    shard : Shard or None
        The share this run computed (None: every point).
    merged : int
        Points copied from shard stores (:func:`merge_shards`).
    others : int
        Points the store holds outside this sweep (a store extended by other grids).
    """

    dataset: Any
    store: Path
    points: int
    computed: int
    reused: int
    engine: Any = None
    failed: list[int] = field(default_factory=list)
    total: int = 0
    shard: Shard | None = None
    merged: int = 0
    others: int = 0


def fingerprint(jobs: Sequence[PointJob], extra: Mapping[str, Any], versions=None) -> str:
    """Identity of a sweep: a hash of every point's job and the store layout
    (``versions``: :func:`_file_versions` of ``jobs`` if already made)."""
    rows = []
    names = [f.name for f in fields(PointJob)]
    versions = versions or _file_versions(jobs)
    for job in jobs:
        # (a shallow copy: the JSON text is that of dataclasses.asdict, at a tenth of
        # its time)
        row = {name: getattr(job, name) for name in names}
        del row["motion_si"]  # the same motion as job.motion
        model, motion_file = versions(job)
        if "@sha256:" in model:  # a model file: its contents (an edited one is another)
            row["model"] = model
        if motion_file is None:
            del row["base"]  # the folder matters to motion files only
        else:
            row["motion_file"] = motion_file  # its contents, not only its name
        if not job.parameters:
            del row["parameters"]  # a sweep stored before [parameters] existed is the same
        if job.truth == "auto":
            del row["truth"]  # likewise before truth could be chosen
        rows.append(row)
    text = json.dumps({"jobs": rows, **extra}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def point_keys(jobs: Sequence[PointJob], common: Mapping[str, Any],
               versions=None) -> list[str]:
    """Each point's identity: a hash of its full definition, what its numbers depend on.

    The point's job without its label (text for messages), its motion as exact SI values
    with the defaults filled in (``motion_si``: ``[motion] latitude = "50 deg"`` and a
    latitude grid's 50° are the same motion), the folder of its motion file (if it flies
    one), and ``common``, what every point of the sweep shares (model, curves, error
    quantities, the judging rule, the store's version), a model file's and a motion
    file's contents by their hashes. Two points of any two sweeps with the same key have
    the same numbers; a sweep that extends a store reuses them.
    """
    from ins_errors.numeric.motion_spec import in_si

    names = [f.name for f in fields(PointJob) if f.name not in ("label", "motion",
                                                                "motion_si")]
    keys = []
    versions = versions or _file_versions(jobs)
    for job in jobs:
        row = {name: getattr(job, name) for name in names}
        row["motion"] = job.motion_si or tuple(sorted(in_si(dict(job.motion)).items()))
        if job.parameters:  # a parameter set to its default is the default
            defaults = _defaults(job.model, job.ellipsoid)
            row["parameters"] = tuple((name, value) for name, value in job.parameters
                                      if defaults.get(name) != value)
        row["model"], motion_file = versions(job)
        if motion_file is None:
            del row["base"]
        else:  # the file's contents, not only its name: an edited flight log is another
            row["motion_file"] = motion_file
        text = json.dumps({"point": row, **common}, sort_keys=True, default=str)
        keys.append(hashlib.sha256(text.encode()).hexdigest()[:32])
    return keys


def _file_versions(jobs: Sequence[PointJob]):
    """``versions(job) -> (model, motion file)``: the job's model as
    :func:`_model_version` gives it and its motion file's SHA-256 (None without one), each
    file read once for all the jobs."""
    models: dict[tuple[str, str], str] = {}
    files: dict[str, str] = {}

    def versions(job: PointJob) -> tuple[str, str | None]:
        if (job.model, job.base) not in models:
            models[job.model, job.base] = _model_version(job.model, job.base)
        file = dict(job.motion).get("file")
        if file is None:
            return models[job.model, job.base], None
        path = str(Path(job.base) / str(file))
        if path not in files:
            files[path] = _file_version(path)
        return models[job.model, job.base], files[path]

    return versions


def _model_version(model: str, base: str) -> str:
    """A model as a point's identity holds it: a built-in's name, a model file's path with
    the hash of its contents (an edited model file is another model, whose stored points
    are not reused)."""
    from ins_errors.model_lookup import resolve

    try:
        return resolve(model, relative_to=base).key
    except InsErrorsError:
        return model


def _file_version(path: str) -> str:
    """SHA-256 of a motion file's contents ('' when it cannot be read: the run says why)."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return ""


@lru_cache(maxsize=8)
def _defaults(model: str, ellipsoid: str | None) -> dict[str, float]:
    """A model's parameter values when the scenario sets none (with its ellipsoid)."""
    from ins_errors.numeric.model import load_model

    loaded = load_model(model)
    vector = loaded.parameter_vector(ellipsoid=ellipsoid)
    return {info.name: float(v) for info, v in zip(loaded.parameters, vector, strict=True)}


def fixed_parameters(scenario) -> dict[str, float]:
    """The model parameters a sweep's ``[parameters]`` table sets for every point (SI):
    those its grids do not replace."""
    swept = {p.name for p in scenario.sweep.parameters if p.kind == "parameter"}
    return {name: value for name, value in scenario.parameters.items()
            if name not in swept}


def settings(scenario, quantities: Sequence[str]) -> dict[str, str]:
    """Everything a sweep's numbers depend on, readable name -> value as text (floats
    exactly, ``repr``; SI with their units), in the order of the scenario file.

    Stored with the sweep (attribute ``settings``) to say which setting differs when a
    store of another sweep is refused (:func:`ins_errors.analysis.store.mismatch`). A
    ``[parameters]`` value that a grid replaces at every point is left out, as in the
    store's ``parameters`` attribute (:func:`fixed_parameters`).
    """
    from ins_errors.numeric.model import load_model

    model = load_model(scenario.model)
    units = {s.name: s.unit for s in model.sources}
    spec: SweepSpec = scenario.sweep
    out = {"model": str(scenario.model), "error quantities": ", ".join(quantities)}
    version = _model_version(str(scenario.model), str(scenario.base))
    if "@sha256:" in version:  # a model file: an edited one is another model
        out["model file contents"] = f"sha256 {version.rsplit(':', 1)[1]}"
    for name, value in scenario.motion.items():
        out[f"[motion] {name}"] = json.dumps(value) if not isinstance(value, str) else value
    if "file" in scenario.motion:
        out["motion file folder"] = str(scenario.base)
        contents = _file_version(str(Path(scenario.base) / str(scenario.motion["file"])))
        out["motion file contents"] = f"sha256 {contents[:16]}"
    out.update({"[run] duration": f"{scenario.duration!r} s",
                "[run] step": f"{scenario.step!r} s", "[run] record": f"{scenario.record!r} s",
                "[run] method": str(scenario.method), "[run] refined": str(scenario.refined),
                "[run] platform": str(scenario.platform), "[run] truth": str(scenario.truth),
                "[run] ellipsoid": str(scenario.ellipsoid or "the model's own")})
    for name, value in fixed_parameters(scenario).items():  # (a grid replaces the others)
        out[f"[parameters] {name}"] = repr(value)
    for k, case in enumerate(scenario.cases):
        for name, value in case.sources.items():
            out[f"[[case]] {k + 1} {name}"] = f"{value!r} {units.get(name, '')}".strip()
    for parameter in spec.parameters:  # as written (12 digits: finer changes are
        values = parameter.values         # named only by the fingerprint)
        out[f"[sweep] {parameter.name}"] = (
            f"{len(values)} value{'s' if len(values) != 1 else ''} "
            + ", ".join(f"{parameter.shown(v):.12g}" for v in values)
            + f" {parameter.display_unit}")
    out["[sweep] draws"] = str(spec.draws)
    out["[sweep] seed"] = str(spec.seed)
    for name, sigma in spec.random:
        out[f"[sweep.random] {name}"] = f"{sigma!r} {units.get(name, '')}".strip()
    out["quantities judged"] = JUDGING
    return out


JUDGING = "each on its own (its unit's rounding floor, first order)"
"""Which quantities a point's worst ratios judge (part of a sweep's identity: a store of
the earlier rule, a share of the largest error of the same unit, is another sweep)."""


def layout(scenario, points: Grid, shard: Shard | None = None):
    """The store layout of a sweep (of one of its shards: ``shard``)."""
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
    common = {"model": scenario.model, "curves": curves, "quantities": names, "store": 2,
              "judging": JUDGING}
    identity = {**common, "times": times.tolist()}
    spec = scenario.sweep
    attributes = {
        "title": scenario.title, "model": scenario.model, "method": scenario.method,
        "platform": scenario.platform, "truth": scenario.truth,
        "record_s": record, "draws": spec.draws, "seed": spec.seed,
        "random": {name: sigma for name, sigma in spec.random},
        "swept": [name for name, (_, attrs) in points.coordinates.items()
                  if attrs.get("swept")],
        "motion": {k: str(v) for k, v in scenario.motion.items()},
        "parameters": parameters_record(model, fixed_parameters(scenario)),
        "judged_quantities": scenario.quantities,
        "settings": settings(scenario, names),
        "Conventions": "ins-errors sweep store 2",
    }
    versions = _file_versions(points.jobs)  # each model and motion file read once
    keys = point_keys(points.jobs, common, versions)
    coordinates = {**points.coordinates, POINT_KEY: (np.array(keys, dtype=str), {
        "long_name": "identity of the point's full definition (a sweep that extends the "
                     "store reuses the point whose identity is its own)"})}
    return Layout(len(points.jobs), times, tuple(names), tuple(units),
                  tuple(s.name for s in model.sources), tuple(s.unit for s in model.sources),
                  coordinates, curves, attributes,
                  fingerprint(points.jobs, identity, versions),
                  None if shard is None else (shard.index, shard.count))


def default_store(scenario_path: str | Path, shard: Shard | None = None) -> Path:
    """``<scenario name>.zarr`` in the current folder (of a shard:
    ``<scenario name>.shard-I-of-N.zarr``)."""
    stem = Path(scenario_path).stem
    if shard is not None:
        return Path(f"{stem}.shard-{shard.index}-of-{shard.count}.zarr")
    return Path(f"{stem}.zarr")


def run_sweep(scenario, store: str | Path, *, engine: str = "auto",
              scheduler: str | None = None, workers: int | None = None,
              progress: bool = False,
              on_result: Callable[[int], None] | None = None,
              retry_failed: bool = False, shard: Shard | None = None,
              on_start: Callable[[int, int, int], None] | None = None,
              on_extend: Callable[[int], None] | None = None,
              on_size: Callable[[Any], None] | None = None,
              allow_large_store: bool = False) -> SweepResult:
    """Run (or finish) a sweep, or one shard of it, into a store.

    A store of a sweep with other grid values and every other setting the same is
    extended (:func:`extend_store`): the points it holds that are points of this sweep
    (the same full definition) are reused, the others computed; it keeps its points
    outside this sweep, and the result covers this sweep's points only.

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
    shard : Shard, optional
        Run only this share of the points, into a store of its own (one made for the
        same shard, or a new one).
    on_start : callable, optional
        Called as ``on_start(points, to_compute, total)`` once the store is open, before
        any point runs (``points``: of this run, ``total``: of the whole sweep).
    on_extend : callable, optional
        Called as ``on_extend(others)`` before ``on_start`` when the store is one of
        other grid values, extended: ``others`` is the number of points it keeps outside
        this sweep.
    on_size : callable, optional
        Called with the estimated size of the store once the sweep is done
        (:class:`~ins_errors.analysis.store.StoreSize`) before anything is written into
        it (before ``on_extend`` and ``on_start``).
    allow_large_store : bool
        Write the store even when it is estimated beyond
        :data:`~ins_errors.analysis.store.MAX_STORE_BYTES` or
        :data:`~ins_errors.analysis.store.MAX_STORE_FILES`, or beyond the room left on
        its file system (:func:`~ins_errors.analysis.store.check_room`).

    Returns
    -------
    SweepResult
        Points that failed (:class:`PointError`) are in ``failed``; the others ran.

    Raises
    ------
    StoreBusyError
        Another process is writing the store (:func:`~ins_errors.analysis.store.store_lock`).
    """
    from ins_errors.analysis.engine import choose_engine, run_tasks
    from ins_errors.analysis.store import disk_full, full_disk_error, store_lock, store_path

    store = store_path(store)  # a name of no known format, before anything is made
    scheduler = scheduler or scenario.sweep.scheduler
    choose_engine(engine, scheduler)  # refused before any store is made
    if shard is None:
        scenario = _as_stored(scenario, store)
    points = grid(scenario)
    if shard is not None:
        check_shard(shard, len(points.jobs))
    shape = layout(scenario, points, shard)
    share = [int(k) for k in shape.share]
    sizing = _sizing(store, allow_large_store, on_size)
    with store_lock(store):
        box, where, others = _open_store(scenario, store, shape, shard, sizing)
        box.record_attributes(_judging(scenario))  # also when every point is reused
        todo = [k for k in share
                if not box.done[where[k]] or (retry_failed and box.failure[where[k]])]
        reused = len(share) - len(todo)
        if on_extend is not None and others is not None:
            on_extend(others)
        if on_start is not None:
            on_start(len(share), len(todo), len(points.jobs))
        stats = None
        try:
            if todo:
                def keep(k: int, result: dict) -> None:
                    box.write(where[todo[k]], result)
                    if on_result is not None:
                        on_result(todo[k])

                def failed(k: int, error: InsErrorsError) -> None:
                    if not isinstance(error, PointError):  # not a point's own outcome
                        raise error
                    box.fail(where[todo[k]], error.reason)
                    if on_result is not None:
                        on_result(todo[k])

                # one compile for every point when baked loops would need several
                shared = loop_combinations([points.jobs[k] for k in todo]) > 1
                stats = run_tasks(run_point_with_loops, [(points.jobs[k],) for k in todo],
                                  shared=(shared,), engine=engine, scheduler=scheduler,
                                  workers=workers,
                                  on_result=keep, on_failure=failed, progress=progress,
                                  label="sweep")
            box.finish()
        except OSError as error:  # a point is written whole or not at all: resumable
            if not disk_full(error):
                raise
            kept = sum(bool(box.done[where[k]]) for k in share)
            raise full_disk_error(store, kept, len(share), error) from None
        data = _judged_by(_view(box.dataset(), shape, where), scenario)
    if shard is not None:
        data = data.isel(point=share)
    failed = [k for k in share if box.failure[where[k]]]
    return SweepResult(data, Path(store), len(share), len(todo), reused, stats,
                       failed, len(points.jobs), shard, others=others or 0)


def _as_stored(scenario, store: Path):
    """``scenario`` whose grid values within :data:`SAME_VALUE` of a value the store at
    ``store`` holds for the same parameter take the stored value (``2700 arcmin`` for a
    stored ``45 deg``, one unit in the last place apart in radians): the sweep reuses
    those points and reports the values as stored, instead of computing them again as
    points of their own beside the stored ones."""
    from ins_errors.analysis.store import read_store

    work = store.with_name(store.name + ".partial.zarr") if store.suffix == ".nc" else store
    source = next((path for path in (work, store) if path.exists()), None)
    if source is None or not scenario.sweep.parameters:
        return scenario
    try:
        data = read_store(source)
    except InsErrorsError:
        return scenario  # not a store: said when it is opened
    try:
        stored = {p.name: np.asarray(data[p.name].values, dtype=float)
                  for p in scenario.sweep.parameters
                  if p.name in data.variables and data[p.name].dims == ("point",)}
    finally:
        data.close()
    parameters, changed = [], False
    for parameter in scenario.sweep.parameters:
        known = np.unique(stored.get(parameter.name, np.empty(0)))
        known = known[np.isfinite(known)]
        values = []
        for value in parameter.values:
            near = [float(s) for s in known if same_value(float(s), value)]
            values.append(near[0] if near else value)
        if values != list(parameter.values) and len(set(values)) == len(values):
            parameter = dataclasses.replace(parameter, values=tuple(values))
            changed = True
        parameters.append(parameter)
    if not changed:
        return scenario
    return dataclasses.replace(scenario, sweep=dataclasses.replace(
        scenario.sweep, parameters=tuple(parameters)))


def _sizing(store: Path, allow: bool, on_size: Callable[[Any], None] | None
            ) -> Callable[[Any, int, int | None], None]:
    """The check of a store's size before a sweep writes into it: a function of the
    store's layout once done, the points it then holds and the points it holds now
    (None: it is written whole, new or rewritten) that refuses a store beyond its limits
    or its file system's room (:func:`~ins_errors.analysis.store.check_room`) unless
    ``allow``, and then says the estimate (``on_size``)."""
    from ins_errors.analysis.store import block_size, check_room, store_size

    block = block_size(store)
    netcdf = store.suffix == ".nc"

    def sizing(shape, filled: int, present: int | None) -> None:
        final = store_size(shape, filled, netcdf=netcdf, block=block)
        needed = final if present is None else final - store_size(shape, present,
                                                                    block=block)
        check_room(store, final, needed, allow)  # (its one line says the estimate)
        if on_size is not None:
            on_size(final)

    return sizing


def _open_store(scenario, store: Path, shape, shard: Shard | None,
                sizing: Callable[[Any, int, int | None], None]):
    """The store opened for a sweep, where each of the sweep's points is in it, and how
    many points of other grids it keeps (None: the store is the sweep's own).

    A store of this very sweep (its fingerprint) is opened as it is. A whole sweep of
    other grid values and the same settings otherwise (:func:`extend_store`) reuses the
    points whose full definition is one of this sweep's, and gets the others added.

    Returns
    -------
    tuple of (SweepStore, numpy.ndarray, int or None)
        The store, the store index of each of the sweep's points (shape (P,)) and the
        number of points the store holds outside this sweep.

    ``sizing`` (:func:`_sizing`) is called before anything is written into the store.

    Raises
    ------
    StoreError
        A store of another sweep that cannot be extended (one line naming the settings
        that differ), or one too large (``sizing``).
    """
    from ins_errors.analysis.store import SweepStore, read_store, stored_source

    source = stored_source(store)
    if shard is None and source is not None:
        data = read_store(source)
        try:
            found = data.attrs.get("fingerprint")
            if found and found != shape.fingerprint and not data.attrs.get("shard"):
                return extend_store(scenario, store, shape, data, sizing)
        finally:
            data.close()
    share = len(shape.share)
    if source is None:
        sizing(shape, share, None)
    box = SweepStore.open(store, shape)
    if source is not None:  # (opening it wrote nothing)
        sizing(shape, share, int(np.count_nonzero(box.done[shape.share])))
    return box, np.arange(shape.points), None


def extend_store(scenario, store: Path, shape, data,
                 sizing: Callable[[Any, int, int | None], None] | None = None):
    """Open a store made by a sweep of other grid values for this one (``shape``).

    Every setting but the grids must be the same (otherwise the store is refused,
    naming the settings that differ): the store's points whose full definition
    (:data:`~ins_errors.analysis.store.POINT_KEY`) is one of this sweep's are reused.
    When this sweep has points the store lacks, the store is rewritten
    (:func:`~ins_errors.analysis.store.grow`) with every finished point it held
    followed by those, not yet run; its time axis is the longer of the two. A store made
    before points recorded their identity is matched by rebuilding its grid
    (:func:`_rebuilt_keys`). ``sizing`` (:func:`_sizing`) is called before anything is
    written into the store.

    Returns
    -------
    As :func:`_open_store`.
    """
    from ins_errors.analysis.store import (
        StoreError,
        extension_differences,
        grow,
        mismatch,
        reopen,
        stored_layout,
    )

    differences = extension_differences(data.attrs, shape)
    where_ = str(store)
    if differences is None:
        raise StoreError(f"{where_!r} holds {mismatch(data.attrs, shape)}; remove it or "
                         "choose another store")
    if differences:
        shown = ", ".join(differences[:3]) + (f" and {len(differences) - 3} more"
                                              if len(differences) > 3 else "")
        raise StoreError(f"{where_!r} holds another sweep: {shown}; a store takes other "
                         "[sweep] grid values only (every other setting the same): remove "
                         "it or choose another store")
    stored = (data[POINT_KEY].values.astype(str).tolist() if POINT_KEY in data.variables
              else _rebuilt_keys(scenario, data))
    if stored is None:
        raise StoreError(f"{where_!r} holds {mismatch(data.attrs, shape)}, made before "
                         "stores recorded each point's identity, so it cannot be extended: "
                         "remove it or choose another store")
    wanted = shape.coordinates[POINT_KEY][0].tolist()
    index: dict[str, int] = {}
    for j, key in enumerate(stored):
        index.setdefault(key, j)
    if all(key in index for key in wanted):  # every point has its place: as it is
        where = np.array([index[key] for key in wanted])
        box = reopen(store, data)
        if sizing is not None:
            done = set(np.flatnonzero(box.done).tolist())
            sizing(box.layout, len(done | set(where.tolist())), len(done))
        return box, where, len(stored) - len(set(where.tolist()))
    old = stored_layout(data)
    old = dataclasses.replace(old, coordinates={  # (rebuilt, for a store without them)
        **old.coordinates, POINT_KEY: (np.array(stored, dtype=str),
                                       shape.coordinates[POINT_KEY][1])})
    done = np.asarray(data["done"].values, dtype=bool)
    reasons = failure_reasons(data)
    keep = [j for j in range(len(stored)) if done[j] and index[stored[j]] == j]
    slot = {stored[j]: n for n, j in enumerate(keep)}
    added: list[int] = []
    for k, key in enumerate(wanted):
        if key not in slot:
            slot[key] = len(keep) + len(added)
            added.append(k)
    union = _union_layout(old, shape, keep, added)
    if sizing is not None:  # rewritten whole, beside the old store until it is done
        sizing(union, union.points, None)
    reader = _StoredPoints(data, union.point_variables)
    box = grow(store, union, [(n, reasons[j], lambda j=j: reader.values(j))
                              for n, j in enumerate(keep)])
    where = np.array([slot[key] for key in wanted])
    return box, where, union.points - len(set(where.tolist()))


def _union_layout(old, shape, keep: Sequence[int], added: Sequence[int]):
    """The layout of a store extended by a sweep: its kept points (``keep``, indices in
    the store of layout ``old``) then the sweep's points ``added`` (indices in the
    sweep of layout ``shape``).

    Attributes, labels and curves are the sweep's (the settings are the same but for
    the grids); the time axis is the longer; each per-point coordinate is the union of
    both (NaN, -1 or empty text where a point's sweep did not have it); ``swept`` names
    the grids of both, this sweep's first; the fingerprint is a hash of the points'
    keys (no sweep has it: every sweep finds its points by their keys).
    """
    from ins_errors.analysis.store import Layout

    times = shape.times if len(shape.times) >= len(old.times) else old.times
    names = [*shape.coordinates, *(n for n in old.coordinates if n not in shape.coordinates)]
    coordinates = {}
    for name in names:
        parts = []
        for layout, chosen in ((old, keep), (shape, added)):
            if name in layout.coordinates:
                parts.append(np.asarray(layout.coordinates[name][0])[list(chosen)])
            else:
                parts.append(None)
        attrs = dict((shape.coordinates.get(name) or old.coordinates[name])[1])
        kind = next(p.dtype.kind for p in parts if p is not None)
        fill = {"i": -1, "U": ""}.get(kind, np.nan)  # (case and draw are on both sides)
        coordinates[name] = (np.concatenate(
            [np.full(len(chosen), fill) if p is None else p
             for p, chosen in zip(parts, (keep, added), strict=True)]), attrs)
    attributes = dict(shape.attributes)
    before = old.attributes.get("swept", "[]")
    before = json.loads(before) if isinstance(before, str) else list(before)
    attributes["swept"] = [*shape.attributes.get("swept", []),
                           *(n for n in before if n not in shape.attributes.get("swept", []))]
    keys = coordinates[POINT_KEY][0].tolist()
    mark = hashlib.sha256(json.dumps({"extended": keys}).encode()).hexdigest()[:32]
    return Layout(len(keep) + len(added), np.asarray(times), shape.quantities,
                  shape.quantity_units, shape.sources, shape.source_units, coordinates,
                  shape.curves, attributes, mark)


class _StoredPoints:
    """One point at a time of an open store (:func:`~ins_errors.analysis.store.read_store`):
    its data variables as stored (curves over the store's time axis)."""

    def __init__(self, dataset, names: Sequence[str]) -> None:
        self.dataset, self.names = dataset, list(names)

    def values(self, k: int) -> dict[str, np.ndarray]:
        """Point ``k``'s data variables."""
        return {name: np.asarray(self.dataset[name].isel(point=k).values)
                for name in self.names}


def _rebuilt_keys(scenario, data) -> list[str] | None:
    """The point keys of a store made before points recorded them, or None.

    The store's grid is rebuilt from its per-point coordinates (each parameter's values
    in the order they first appear: the grid is their product, the first name slowest)
    in this scenario, whose settings but the grids are the store's; the keys stand only
    when the rebuilt sweep has the store's fingerprint, i.e. is the sweep that made it.
    """
    from ins_errors.analysis.store import stored_layout

    old = stored_layout(data)
    before = old.attributes.get("swept", "[]")
    swept = json.loads(before) if isinstance(before, str) else list(before)
    try:
        from ins_errors.numeric.model import load_model

        loaded = load_model(scenario.model)
    except InsErrorsError:
        return None
    units = {source.name: source.unit for source in loaded.sources}
    parameters_of = {parameter.name for parameter in loaded.parameters}
    parameters = []
    for name in swept:
        if name in ("case", "draw"):
            continue
        if name not in old.coordinates:
            return None
        values, attrs = old.coordinates[name]
        kind = ("motion" if name in MOTION_PARAMETERS else "run" if name in RUN_PARAMETERS
                else "source" if name in units else
                "parameter" if name in parameters_of else None)
        if kind is None:
            return None
        unit = str(attrs.get("units", ""))
        unique = tuple(dict.fromkeys(float(v) for v in values))
        parameters.append(Parameter(name, kind, unit, unique,
                                    str(attrs.get("display_unit", unit))))
    rebuilt = dataclasses.replace(scenario, sweep=dataclasses.replace(
        scenario.sweep, parameters=tuple(parameters)))
    try:
        points = grid(rebuilt)
        shape = layout(rebuilt, points)
    except InsErrorsError:
        return None
    if shape.fingerprint != old.fingerprint:
        return None
    return shape.coordinates[POINT_KEY][0].tolist()


def _view(dataset, shape, where: np.ndarray):
    """The sweep of layout ``shape`` in a store's dataset: its points (store indices
    ``where``) and times, labelled as a store of this sweep alone would label them (its
    coordinates, attributes and point numbers): the dataset a fresh sweep returns.
    ``dataset`` itself when the store is the sweep's own."""
    from ins_errors.analysis.store import stored_attributes

    if dataset.attrs.get("fingerprint") == shape.fingerprint:
        return dataset
    view = dataset.isel(point=where, time=slice(0, len(shape.times)))
    extra = [name for name in view.coords
             if name != "point" and view[name].dims == ("point",)
             and name not in shape.coordinates]
    view = view.drop_vars(extra).assign_coords(
        point=np.arange(len(where)).astype(view["point"].dtype),
        **{name: ("point", np.asarray(values).astype(  # typed as the store reads them
            view[name].dtype if name in view.coords else np.asarray(values).dtype),
            dict(attrs)) for name, (values, attrs) in shape.coordinates.items()})
    view.attrs = stored_attributes(shape)
    return view


def _judging(scenario) -> dict[str, str]:
    """The store attribute naming the quantities a sweep's worst ratios judge (its
    ``[outputs] quantities``, JSON; ``null``: all)."""
    return {"judged_quantities": json.dumps(scenario.quantities)}


def _judged_by(dataset, scenario):
    """``dataset`` whose worst ratios judge the scenario's ``[outputs] quantities`` as it
    is now (a store made before the list was recorded, or with another list, too)."""
    dataset.attrs.update(_judging(scenario))
    return dataset


def merge_shards(scenario, parts: Sequence[str | Path], store: str | Path,
                 on_start: Callable[[int, int, int], None] | None = None,
                 on_size: Callable[[Any], None] | None = None,
                 allow_large_store: bool = False) -> SweepResult:
    """Join the shard stores of a sweep into one store, computing nothing.

    Every part must be a store made by ``ins-errors sweep --shard I/N`` of this very
    sweep (the same settings, grid and seed), all with the same N and each I once, and
    finished. Each point is copied (its data, or its failure reason) from the shard that
    ran it; the result is bit for bit the store the sweep run whole would have written.
    A store of the sweep already at ``store`` keeps the points it holds (an interrupted
    merge resumes).

    Parameters
    ----------
    scenario : ins_errors.scenario.Scenario
        With a ``[sweep]`` table.
    parts : sequence of str or Path
        The shard stores (``*.zarr`` or ``*.nc``), in any order.
    store : str or Path
        The merged store.
    on_start : callable, optional
        As for :func:`run_sweep`, before any point is copied.
    on_size, allow_large_store
        As for :func:`run_sweep`: the merged store's size is said before anything is
        written, and a store too large refused.

    Raises
    ------
    SweepError, StoreError
        One line: a part of another sweep (naming the settings that differ), of another
        shard count, a shard given twice, shards missing or unfinished (naming them and
        their points), a part still being written.
    """
    from contextlib import ExitStack

    from ins_errors.analysis.store import (
        SweepStore,
        mismatch,
        read_store,
        store_lock,
        store_path,
        stored_source,
    )

    store = store_path(store)
    paths = [store_path(part) for part in parts]
    if not paths:
        raise SweepError("--merge needs the shard stores to join")
    seen: dict[Path, Path] = {}
    for path in paths:
        key = path.resolve()
        if key == store.resolve():
            raise SweepError(f"--merge {str(path)!r}: the merged store cannot be one of the "
                             "shard stores; give --store another name")
        if key in seen:
            raise SweepError(f"--merge names {str(path)!r} twice")
        seen[key] = path
    points = grid(scenario)
    shape = layout(scenario, points)
    total = len(points.jobs)
    with ExitStack() as stack:
        owners: dict[int, tuple[Path, Path, Any]] = {}  # shard -> (path, read, dataset)
        count = None
        problems: list[str] = []
        for path in paths:
            source = path
            partial = path.with_name(path.name + ".partial.zarr")
            if path.suffix == ".nc" and not path.exists() and partial.exists():
                source = partial  # a NetCDF shard that has not finished
            if not source.exists():
                raise SweepError(f"--merge {str(path)!r}: no such shard store")
            stack.enter_context(store_lock(path, reading=True))
            data = read_store(source)
            stack.callback(data.close)
            text = str(data.attrs.get("shard", ""))
            match = _SHARD.match(text)
            if not match:
                why = mismatch(data.attrs, shape)  # empty: the whole of this sweep
                raise SweepError(f"--merge {str(path)!r} holds "
                                 + (why if why else "a whole sweep, not a shard of it (a "
                                    "store of 'ins-errors sweep --shard I/N')"))
            part = Shard(int(match.group(1)), int(match.group(2)))
            why = mismatch(data.attrs, dataclasses.replace(shape, shard=(part.index,
                                                                         part.count)))
            if why:
                raise SweepError(f"--merge {str(path)!r} (shard {part}) holds {why}")
            if count is None:
                count = part.count
            elif part.count != count:
                first = next(iter(owners.values()))[0]
                raise SweepError(f"--merge {str(path)!r} is shard {part} but "
                                 f"{str(first)!r} is shard "
                                 f"{next(iter(owners))}/{count}: the parts of a merge are "
                                 "the shards of one split (the same N)")
            if part.index in owners:
                raise SweepError(f"--merge: shard {part} is given twice: "
                                 f"{str(owners[part.index][0])!r} and {str(path)!r}")
            owners[part.index] = (path, source, data)
            done = np.asarray(data["done"].values, dtype=bool)
            lacking = [k for k in part.points(total) if not done[k]]
            if lacking:
                problems.append(f"{str(path)!r} (shard {part}) lacks {len(lacking)} of its "
                                f"{len(part.points(total))} points "
                                f"({_some(lacking)}): run its sweep command again to "
                                "finish it")
        missing = [index for index in range(1, count + 1) if index not in owners]
        if missing:
            lost = sorted(k for index in missing for k in Shard(index, count).points(total))
            shards = ", ".join(f"{index}/{count}" for index in missing)
            problems.insert(0, f"shard{'s' if len(missing) > 1 else ''} {shards} "
                               f"{'are' if len(missing) > 1 else 'is'} missing ("
                               f"{len(lost)} of the {total} points: {_some(lost)}); give "
                               f"{'their stores' if len(missing) > 1 else 'its store'}")
        if problems:
            raise SweepError("cannot merge: " + "; ".join(problems))
        readers = {index: _PartReader(path, source, data, shape)
                   for index, (path, source, data) in owners.items()}
        sizing = _sizing(store, allow_large_store, on_size)
        with store_lock(store):
            new = stored_source(store) is None
            if new:
                sizing(shape, total, None)
            box = SweepStore.open(store, shape)
            if not new:
                sizing(shape, total, int(np.count_nonzero(box.done)))
            box.record_attributes(_judging(scenario))
            plan = []
            for k in range(total):
                reader = readers[k % count + 1]
                reason = reader.failure[k]
                if box.done[k] and box.failure[k] == reason:
                    continue  # already merged
                if box.done[k] and reason and not box.failure[k]:
                    raise SweepError(f"{str(store)!r} holds results at point {k} that its "
                                     f"shard store {str(reader.path)!r} records as failed; "
                                     "remove it to merge again")
                plan.append(k)
            if on_start is not None:
                on_start(total, len(plan), total)
            for k in plan:
                reader = readers[k % count + 1]
                if reader.failure[k]:
                    box.fail(k, reader.failure[k])
                else:
                    box.write(k, reader.values(k))
            box.finish()
            data = _judged_by(box.dataset(), scenario)
    return SweepResult(data, Path(store), total, 0, total - len(plan), None, box.failed,
                       total, None, len(plan))


def _some(indices: Sequence[int], limit: int = 8) -> str:
    """``"1, 4, 7"``, or the first ``limit`` then ``"…"``."""
    shown = ", ".join(str(k) for k in indices[:limit])
    return shown + (", …" if len(indices) > limit else "")


class _PartReader:
    """One point at a time from a shard store: its data variables, as stored (a Zarr
    folder's chunk of the point, a NetCDF file's row), and its failure reason.

    Parameters
    ----------
    path : Path
        The shard store as named.
    source : Path
        What is read: ``path``, or the Zarr folder of an unfinished ``*.nc`` store.
    dataset : xarray.Dataset
        ``source`` opened by :func:`ins_errors.analysis.store.read_store`.
    shape : Layout
        The sweep's store layout (which variables a point has).
    """

    def __init__(self, path: Path, source: Path, dataset, shape) -> None:
        self.path = path
        self.failure = failure_reasons(dataset)
        names = shape.point_variables
        if source.is_dir():  # Zarr: the point's chunks only
            import zarr

            group = zarr.open_group(str(source), mode="r", zarr_format=2)
            self._arrays = {name: group[name] for name in names}
        else:  # NetCDF, loaded whole
            self._arrays = {name: dataset[name].values for name in names}

    def values(self, k: int) -> dict[str, np.ndarray]:
        """Point ``k``'s data variables (curves over the whole time axis)."""
        return {name: np.asarray(array[k]) for name, array in self._arrays.items()}
