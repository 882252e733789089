"""Accuracy specifications read from TOML files with units.

A spec lists the accuracy items a system must meet (all at one σ level, e.g. 2σ), the
motion over which they are checked, and options for allocating the error budget among
the error sources. Every quantity is text with a unit (``"3.7 km/h"``, ``"0.1 deg"``,
``"0.1 deg/h"``, ``"8 h"``), parsed by :func:`ins_errors.units.parse_quantity`, so a
value in the wrong dimension (an angle given in m/s) is an error, not a silent number.

Items (what each one measures is defined in :mod:`ins_errors.analysis.budget`):

``position_error``
    horizontal position error *per hour of operation* (a length per time, e.g.
    ``"3.7 km/h"``): at each check time t the error must not exceed value × t;
``position_error_absolute``
    horizontal position error itself, a length (``"2 km"``): at each check time the
    error must not exceed the value (a limit that does not grow with time);
``height_error``
    error of the computed height, a length (models with a ``height`` output);
``ground_speed_error``
    horizontal (north, east) velocity error, m/s;
``vertical_error``
    error of holding the vertical: platform tilt, an angle;
``heading_error``
    azimuth error of the platform (the gyroscopic heading), an angle, including the
    initial alignment error;
``heading_drift``
    drift rate of the gyroscopic heading (platform azimuth), angle per time.

The file format (see ``ins_errors/data/802m.toml``, the built-in default)::

    title = "..."
    sigma_level = 2                  # the values are 2σ
    operating_time = "8 h"
    step = "60 s"                    # analysis grid (a great circle keeps F, G, H at
                                     # every grid time: 4 kB each for orthodromic, so
                                     # 0.34 GB a day at 1 s; beyond 60 % of the machine's
                                     # memory it is refused with a step that fits)
    [motion]                         # kind = "static", "great_circle" ("great-circle") or
    latitude = "50 deg"              # "manoeuvre" (the standard manoeuvre of the
                                     # scenario files, or [[motion.legs]] of your own)
    [items.position_error]
    value = "3.7 km/h"
    times = ["1 h", "2 h"]           # optional, check times, or a regular grid:
    # every = "5 min"; from = "5 min" (default: 0; every for the rate items
    # position_error and heading_drift); until = "1 h" (default: the operating time)
    combine = "rss"                  # optional: "rss" of the components, "each", or
                                     # "cep" (position items: the CEP, no σ level)
    [allocation]
    fill = false                     # scale the free sources up until an item is met exactly
    [sources.gyro_drift_z]
    weight = 2                       # or fixed = "0.01 deg/h" (not both), kind = "markov",
                                     # tau = "1 h"; sigma_level = 1: the fixed value is
                                     # 1σ (default: the spec's level; a white density,
                                     # kind = "white", is always read as given)
    [parameters]                     # optional: model parameters with units, as in a
    k_h1 = "0.0047 1/s"              # scenario (--parameter overrides them)
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ins_errors.earth_constants import FIRST_COSMIC_VELOCITY
from ins_errors.errors import InsErrorsError, UnknownNameError, unknown_name
from ins_errors.units import UnitError, format_duration, parse_quantity

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

HOUR = 3600.0


class SpecError(InsErrorsError):
    """A spec file or spec value that cannot be used."""


@dataclass(frozen=True)
class ItemKind:
    """What a spec item measures and how its value is written.

    Attributes
    ----------
    unit : str
        SI unit of the value.
    example : str
        A valid value, quoted in error messages.
    description : str
        One line.
    default_times : str
        ``"hourly"`` (every hour up to the operating time), ``"quarter-hourly"`` (every
        15 min from 0), ``"quarter-hourly-to-end"`` (every 15 min from 0, and the last
        grid time of the operating time) or ``"first-hour"`` (1 h only); the hourly rules
        check an operating time shorter than an hour at its end.

    An item that limits an error itself, not its rate (every item but the keys of
    :data:`ABSOLUTE_OF`), holds from the start: its ``every`` grid starts at 0 unless
    ``from`` says otherwise (at 0 the error is the initial error, which a damped loop
    may have removed by the first check time after it).
    """

    unit: str
    example: str
    description: str
    default_times: str


ITEM_KINDS: dict[str, ItemKind] = {
    "position_error": ItemKind(
        "m/s", "3.7 km/h", "horizontal position error per hour of operation (φ, λ)",
        "hourly"),
    "position_error_absolute": ItemKind(
        "m", "2 km", "horizontal position error (φ, λ), a distance not divided by time",
        "quarter-hourly-to-end"),
    "height_error": ItemKind(
        "m", "30 m", "error of the computed height (a model with a height output)",
        "quarter-hourly-to-end"),
    "ground_speed_error": ItemKind(
        "m/s", "4 m/s", "horizontal velocity (ground-speed) error", "first-hour"),
    "vertical_error": ItemKind(
        "rad", "0.1 deg", "error of holding the vertical (platform tilt)", "quarter-hourly"),
    "heading_error": ItemKind(
        "rad", "0.5 deg", "azimuth error of the platform (gyroscopic heading), initial "
        "alignment error included", "quarter-hourly-to-end"),
    "heading_drift": ItemKind(
        "rad/s", "0.1 deg/h", "drift rate of the gyroscopic heading (platform azimuth)",
        "first-hour"),
}
"""Spec items the budget knows."""

ABSOLUTE_OF = {"position_error": "position_error_absolute", "heading_drift": "heading_error"}
"""The item that takes an absolute limit for each rate item (a value in the wrong
dimension names it)."""

SIGMA_LEVELS = (0.1, 10.0)
"""The σ levels a spec may state its values at: beyond 10σ a normal error's exceedance
probability (1.5e-23) is past any test or flight record, below 0.1σ the limit is exceeded
92 % of the time."""

COMBINE = ("rss", "each", "cep")
CEP_ITEMS = ("position_error", "position_error_absolute")
"""The items ``combine = "cep"`` applies to: the horizontal position errors."""
STATISTICS = ("constant", "white", "markov")
SOURCE_UNIT_SUFFIX = {"constant": "", "white": "*s**0.5", "markov": ""}
"""A white-noise magnitude is a density: the source's unit times √s."""


@dataclass(frozen=True)
class SpecItem:
    """One accuracy requirement.

    Attributes
    ----------
    name : str
        Key of :data:`ITEM_KINDS`.
    value : float
        Limit at the spec's σ level, SI unit of the kind.
    text : str
        The value as written.
    times : tuple of float
        Check times, s.
    combine : {"rss", "each", "cep"}
        ``"rss"``: the item's components (e.g. north and east) are combined as the root
        sum of squares (2DRMS at 2σ); ``"each"``: every component must meet the limit;
        ``"cep"`` (the position items): the value is the circular error probable of the
        north and east errors, a radius holding them with probability 1/2, whatever the
        spec's σ level (:mod:`ins_errors.analysis.budget_cep`).
    """

    name: str
    value: float
    text: str
    times: tuple[float, ...]
    combine: str = "rss"

    @property
    def kind(self) -> ItemKind:
        return ITEM_KINDS[self.name]


@dataclass(frozen=True)
class SourceOption:
    """Allocation options and statistics of one error source.

    Attributes
    ----------
    name : str
        Model source name.
    weight : float
        Relative share of each item's variance (default 1).
    fixed : float or None
        Fixed magnitude at the spec's σ level (SI), not allocated.
    kind : {"constant", "white", "markov"}
        Statistics of the source.
    tau : float or None
        Correlation time of a Markov source, s.
    include : bool
        False leaves the source out of the budget (taken as zero).
    sigma_level : float or None
        σ level of the source's magnitude as written (``fixed``) and reported, for a
        constant or Markov source (``sigma_level = 1``: a datasheet's 1σ bias in a 3σ
        spec); None: the spec's level. A white-noise density has none: it is read and
        reported as the density it is (1σ), whatever the spec's level.
    noise : SourceOption or None
        A second part of the source, of another kind (``[sources.NAME.noise]``: white
        noise or Gauss-Markov noise beside a constant bias), propagated together with
        it and allocated or fixed as a source of its own; None: the source has one part.
    """

    name: str
    weight: float = 1.0
    fixed: float | None = None
    kind: str = "constant"
    tau: float | None = None
    include: bool = True
    sigma_level: float | None = None
    noise: SourceOption | None = None


@dataclass(frozen=True)
class Motion:
    """The motion over which the spec is checked.

    Attributes
    ----------
    kind : {"static", "great_circle", "manoeuvre"}
    latitude, longitude, heading : float
        Start, rad (heading: track angle from north).
    height : float
        m.
    speed : float
        Ground speed of a great-circle flight, or the start speed of a manoeuvre, m/s.
    given : tuple of (str, str)
        ``(name, text as written)`` of the start values the spec set among latitude,
        longitude, height and heading (a model without such a value refuses it:
        :func:`ins_errors.analysis.budget.spec_system`).
    legs : tuple of dict or None
        The legs of a manoeuvre that lists its own, each as
        :func:`~ins_errors.numeric.motion_spec.in_si` writes it (``duration``, ``speed``,
        ``turn``, ``height`` as SI text); None: the standard manoeuvre
        (:func:`~ins_errors.numeric.motion_spec.default_legs`).
    """

    kind: str = "static"
    latitude: float = 0.0
    longitude: float = 0.0
    heading: float = 0.0
    height: float = 0.0
    speed: float = 0.0
    given: tuple[tuple[str, str], ...] = ()
    legs: tuple[dict, ...] | None = None

    @property
    def heading_given(self) -> bool:
        """Whether the spec set ``heading`` (refused at rest for a model without a
        heading output, :func:`ins_errors.analysis.budget.spec_profile`)."""
        return any(name == "heading" for name, _ in self.given)

    def description(self) -> dict[str, Any]:
        """The motion as :func:`~ins_errors.numeric.motion_spec.motion_profile` reads it
        (every value as exact SI text)."""
        out: dict[str, Any] = {"kind": self.kind.replace("_", "-"),
                               "latitude": f"{self.latitude!r} rad",
                               "longitude": f"{self.longitude!r} rad",
                               "heading": f"{self.heading!r} rad",
                               "height": f"{self.height!r} m"}
        if self.kind != "static":
            out["speed"] = f"{self.speed!r} m/s"
        if self.legs is not None:
            out["legs"] = [dict(leg) for leg in self.legs]
        return out


@dataclass(frozen=True)
class Spec:
    """An accuracy specification.

    Attributes
    ----------
    title : str
    sigma_level : float
        The values are this many σ (2 for the 802m table).
    operating_time : float
        s.
    step : float
        Analysis grid step, s.
    motion : Motion
    items : tuple of SpecItem
    sources : dict of str to SourceOption
        Options of the sources that have any (others: weight 1, random constants).
    fill : bool
        After the equal-share allocation, scale every free source by one common factor
        until the tightest item is met exactly.
    path : str
        Where the spec was read from.
    parameters : dict of str to str
        The ``[parameters]`` table: model parameter name -> value with unit, as text until
        the spec is bound to a model (:func:`spec_parameters`).
    """

    title: str
    sigma_level: float
    operating_time: float
    step: float
    motion: Motion
    items: tuple[SpecItem, ...]
    sources: dict[str, SourceOption] = field(default_factory=dict)
    fill: bool = False
    path: str = ""
    parameters: dict[str, Any] = field(default_factory=dict)

    def item(self, name: str) -> SpecItem:
        """The item ``name``."""
        for item in self.items:
            if item.name == name:
                return item
        raise unknown_name("spec item", name, [i.name for i in self.items])

    def option(self, source: str) -> SourceOption:
        """Options of ``source`` (defaults if the spec names none)."""
        return self.sources.get(source, SourceOption(source))


# --------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------
def _positive(text: Any, unit: str, what: str, example: str = "",
              allow_zero: bool = False) -> float:
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise SpecError(f"{what}: expected a quantity such as {example or unit!r}, "
                        f"got {text!r:.60}")
    try:
        value = parse_quantity(text, unit, what, numbers_are_si=False)
    except UnitError as error:
        # the unit parser's line may already end in its own examples
        hint = f" (e.g. {example!r})" if example and "e.g." not in str(error) else ""
        raise SpecError(f"{error}{hint}") from None
    if value < 0 or (value == 0 and not allow_zero):
        raise SpecError(f"{what}: must be {'>= 0' if allow_zero else '> 0'}, got {text!r}")
    return value


def _check_height(value: float, what: str) -> None:
    """:func:`~ins_errors.numeric.trajectories.check_height` as a :class:`SpecError`."""
    from ins_errors.numeric.trajectories import check_height

    try:
        check_height(value, what)
    except InsErrorsError as error:
        raise SpecError(str(error)) from None


def _angle(text: Any, what: str) -> float:
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise SpecError(f"{what}: expected an angle such as '50 deg', got {text!r:.60}")
    try:
        return parse_quantity(text, "rad", what, numbers_are_si=False)
    except UnitError as error:
        raise SpecError(str(error)) from None


def _default_times(rule: str, operating_time: float, step: float) -> tuple[float, ...]:
    """An item's check times by its :attr:`ItemKind.default_times` rule; an operating
    time shorter than an hour is checked at its end by the hourly rules."""
    end = step * int(operating_time / step + 1e-9)  # the last grid time
    if rule == "first-hour":
        return (min(HOUR, end),)
    if rule == "hourly":
        count = int(operating_time // HOUR + 1e-9)
        return tuple(HOUR * k for k in range(1, count + 1)) or (end,)
    quarter = 900.0
    count = int(operating_time // quarter + 1e-9)
    if rule == "quarter-hourly":
        return tuple(quarter * k for k in range(count + 1))
    # from the start every 15 min that is on the grid, and the operating time's last
    # grid time
    from ins_errors.numeric.integrators import whole_steps

    times = [quarter * k for k in range(count + 1)
             if quarter * k < end * (1 - 1e-12)
             and whole_steps(quarter * k, step) is not None]   # 0 steps is on the grid
    return (*times, end)


def _item_value(name: str, text: Any) -> float:
    """An item's limit in the item's unit; a value in the dimension of the item's
    absolute or rate counterpart (``position_error = "3.7 km"``) names that item."""
    kind = ITEM_KINDS[name]
    try:
        value = _positive(text, kind.unit, f"items.{name}", kind.example)
    except SpecError as error:
        other = ABSOLUTE_OF.get(name) or next(
            (rate for rate, absolute in ABSOLUTE_OF.items() if absolute == name), None)
        if other is None or not isinstance(text, str):
            raise
        try:
            parse_quantity(text, ITEM_KINDS[other].unit, name, numbers_are_si=False)
        except UnitError:
            raise error from None
        what = ("a rate per hour of operation" if name in ABSOLUTE_OF else
                "an absolute limit, not a rate")
        raise SpecError(f"items.{name} is {what} (e.g. {kind.example!r}); {text!r} is a "
                        f"limit for [items.{other}] (e.g. {ITEM_KINDS[other].example!r}): "
                        f"rename the table or change the value") from None
    from ins_errors.model_parameters import source_problem

    problem = source_problem(kind, value)  # an error no run can have limits nothing
    if problem is not None:
        raise SpecError(f"items.{name} = {text!r} {problem}")
    return value


def _sparse_every(name: str, table, start: float, stop: float, operating: str) -> str:
    """Why an ``every`` longer than the span it checks is refused: its grid would hold
    t = 0 alone (``every = "2 h"`` over a 1-h operating time checks a speed item at its
    initial error only), or, for a rate item whose grid starts at ``every``, no time."""
    span = (f"from {format_duration(start)} to {format_duration(stop)}"
            if table.start is not None or table.until is not None
            else f"the {operating} operating time" if start == 0
            else f"its grid starts at every ({format_duration(start)}) and the operating "
                 f"time is {operating}")
    if start > stop * (1 + 1e-12):
        what = "no check time at all"
    else:
        what = f"one check time only, at {format_duration(start)}"
    return (f"items.{name}.every = {table.every!r} is longer than the span it checks "
            f"({span}), so the item would have {what}; give an every no longer than the "
            f"span, or list the check times (times = [\"{format_duration(stop)}\"])")


def _manoeuvre(motion: Motion, legs: list | None) -> Motion:
    """A manoeuvre motion with its legs checked and written in SI (one-line errors)."""
    from dataclasses import replace

    from ins_errors.numeric.motion_spec import in_si, motion_profile

    description = motion.description()
    if legs is None:
        return motion
    description["legs"] = [leg.model_dump(exclude_unset=True) for leg in legs]
    try:
        si = in_si(description)
    except InsErrorsError as error:
        raise SpecError(f"motion.legs: {error}") from None
    for number, (leg, given) in enumerate(zip(si["legs"], legs, strict=True), start=1):
        if not float(leg["duration"].split()[0]) > 0:
            raise SpecError(f"motion.legs: leg {number}'s duration must be > 0, got "
                            f"{given.duration!r}")
        if "height" in leg:
            _check_height(float(leg["height"].split()[0]), f"motion.legs: leg {number}'s height")
    try:
        motion_profile(si)  # a leg no vehicle flies (100 g, 1000°/s) is refused here
    except InsErrorsError as error:
        raise SpecError(f"motion.legs: {error}") from None
    return replace(motion, legs=tuple(si["legs"]))


def parse_spec(data: dict, path: str = "<spec>") -> Spec:
    """Build a :class:`Spec` from the parsed TOML table.

    The shape (tables, keys, types, choices) is checked by
    :func:`ins_errors.spec_schema.validate`; this reads the quantities with their units
    and checks what depends on their values.

    Raises
    ------
    SpecError, UnknownNameError
        Unknown keys or items, values that are not positive, wrong units.
    """
    from ins_errors.numeric.integrators import whole_steps
    from ins_errors.numeric.motion_spec import motion_kind
    from ins_errors.spec_schema import validate

    try:
        checked = validate(data)
    except UnknownNameError:
        raise
    except InsErrorsError as error:
        raise SpecError(str(error)) from None
    title = checked.title if checked.title is not None else Path(path).stem
    if not SIGMA_LEVELS[0] <= checked.sigma_level <= SIGMA_LEVELS[1]:
        raise SpecError(f"sigma_level = {checked.sigma_level:g} is outside "
                        f"[{SIGMA_LEVELS[0]:g}, {SIGMA_LEVELS[1]:g}]: a normal error exceeds "
                        f"10σ with probability 1.5e-23, which no test or flight can tell from "
                        f"20σ, and stays within 0.1σ only 8 % of the time (1σ or 2σ are usual)")
    operating_time = _positive(checked.operating_time, "s", "operating_time", "8 h")
    step = _positive(checked.step, "s", "step", "60 s")
    if step > operating_time:
        raise SpecError(f"step ({step:g} s) is longer than the operating time")

    m = checked.motion
    motion = Motion(
        kind=motion_kind(m.kind).replace("-", "_"),  # the budget's own spelling
        latitude=_angle(m.latitude, "motion.latitude"),
        longitude=_angle(m.longitude, "motion.longitude"),
        heading=_angle(m.heading, "motion.heading"),
        height=_positive(m.height, "m", "motion.height", "0 m", allow_zero=True),
        speed=_positive(m.speed, "m/s", "motion.speed", "250 m/s", allow_zero=True),
        given=tuple((name, str(getattr(m, name))) for name in ("latitude", "longitude",
                                                               "height", "heading")
                    if name in m.model_fields_set),
    )
    _check_height(motion.height, "motion.height")
    if abs(motion.latitude) >= np.pi / 2:
        raise SpecError(f"motion.latitude {m.latitude!r} is at or beyond a pole (|φ| >= "
                        f"90 deg): the models divide by cos φ")
    if motion.speed > FIRST_COSMIC_VELOCITY:
        from ins_errors.numeric.trajectories import speed_beyond

        raise SpecError(speed_beyond(motion.speed, "motion.speed"))
    if motion.kind != "static" and motion.speed <= 0:
        raise SpecError(f"motion.speed must be > 0 for a {motion.kind} motion (e.g. "
                        f"'250 m/s')")
    if m.legs is not None and motion.kind != "manoeuvre":
        raise SpecError(f"motion.legs apply to kind = 'manoeuvre', and the kind is "
                        f"{motion.kind!r}: leave [[motion.legs]] out or choose kind = "
                        f"'manoeuvre'")
    if motion.kind == "manoeuvre":
        motion = _manoeuvre(motion, m.legs)

    items = []
    for name, table in checked.items:
        if table is None:
            continue
        kind_info = ITEM_KINDS[name]
        value = _item_value(name, table.value)
        timed = {"every", "start", "until"} & table.model_fields_set
        if table.times is not None and timed:
            raise SpecError(f"items.{name}: give either times or every/from/until")
        if table.every is not None:
            every = _positive(table.every, "s", f"items.{name}.every", "15 min")
            start = ((every if name in ABSOLUTE_OF else 0.0) if table.start is None else
                     _positive(table.start, "s", f"items.{name}.from", "0 h", allow_zero=True))
            stop = (operating_time if table.until is None else
                    _positive(table.until, "s", f"items.{name}.until", "1 h"))
            if stop > operating_time * (1 + 1e-12):
                raise SpecError(f"items.{name}.until = {table.until!r} is after the "
                                f"operating time {checked.operating_time!r}")
            if start > stop * (1 + 1e-12) and table.start is not None:
                raise SpecError(f"items.{name}: from is after until")
            if start > stop * (1 + 1e-12) or (start == 0 and every > stop * (1 + 1e-9)):
                # no time at all (a rate item's grid from every), or t = 0 alone
                raise SpecError(_sparse_every(name, table, start, stop,
                                              checked.operating_time))
            count = int(np.floor((stop - start) / every + 1e-9))
            times = tuple(start + every * k for k in range(count + 1))
        elif timed:
            raise SpecError(f"items.{name}: from/until need every (e.g. every = '15 min')")
        elif table.times is not None:
            times = tuple(_positive(t, "s", f"items.{name}.times", "1 h", allow_zero=True)
                          for t in table.times)
        else:
            times = _default_times(kind_info.default_times, operating_time, step)
        for t in times:
            if t > operating_time * (1 + 1e-12):
                raise SpecError(f"items.{name}: check time {format_duration(t)} is after "
                                f"the operating time {format_duration(operating_time)}")
            if whole_steps(t, step) is None:
                raise SpecError(f"items.{name}: check time {t:g} s is not on the "
                                f"{step:g} s analysis grid")
        if name in ("position_error", "heading_drift") and any(t <= 0 for t in times):
            raise SpecError(f"items.{name}: a rate over the operating time needs check "
                            f"times > 0")
        if table.combine == "cep" and name not in CEP_ITEMS:
            raise SpecError(f"items.{name}: combine = 'cep' (the circular error probable) "
                            f"applies to the horizontal position items "
                            f"({', '.join(CEP_ITEMS)}); give 'rss' or 'each'")
        items.append(SpecItem(name, value, str(table.value), times, table.combine))
    if not items:
        raise SpecError(f"the spec has no [items.*]; known items: {', '.join(ITEM_KINDS)}")

    sources = {}
    for name, table in checked.sources.items():
        noise = None
        if table.noise is not None:
            where = f"sources.{name}.noise"
            if table.noise.kind == table.kind:
                raise SpecError(f"{where}: the noise part's kind is {table.kind!r}, as the "
                                f"source's own: a source takes at most one part of each "
                                f"kind (give the noise kind = 'white' or 'markov', the "
                                f"source another)")
            if not table.include:
                raise SpecError(f"{where}: include = false leaves the whole source out, its "
                                f"noise too: drop the noise table or the include")
            noise = _source_option(name, table.noise, where, step, include=True)
        sources[name] = _source_option(name, table, f"sources.{name}", step, table.include,
                                       noise)
    return Spec(title, float(checked.sigma_level), operating_time, step, motion, tuple(items),
                sources, checked.allocation.fill, path, dict(checked.parameters or {}))


def _source_option(name: str, table, where: str, step: float, include: bool,
                   noise: SourceOption | None = None) -> SourceOption:
    """One part of a source (``[sources.NAME]`` or its ``.noise``) with its values
    checked: a Markov part's tau, fixed or weight, a σ level only where there is one."""
    tau = None
    if table.kind == "markov":
        if table.tau is None:
            raise SpecError(f"{where}: a markov source needs tau (e.g. '1 h')")
        tau = _positive(table.tau, "s", f"{where}.tau", "1 h")
        from ins_errors.analysis.covariance import SHORTEST_TAU_PER_STEP, short_tau_message

        if tau < step * SHORTEST_TAU_PER_STEP:
            raise SpecError(short_tau_message(f"{where}.tau", tau, step))
    elif table.tau is not None:
        raise SpecError(f"{where}: tau applies only to kind = 'markov'")
    if table.fixed is not None and "weight" in table.model_fields_set:
        raise SpecError(f"{where}: a fixed source takes no share, so its weight would be "
                        f"ignored: give either fixed or weight")
    level = None if table.sigma_level is None else float(table.sigma_level)
    if table.kind == "white" and level not in (None, 1.0):
        raise SpecError(f"{where}: a white-noise density has no σ level (it is read as the "
                        f"density it is, 1σ, whatever the spec's sigma_level): leave "
                        f"sigma_level out")
    return SourceOption(name, float(table.weight), table.fixed, table.kind, tau, include,
                        level, noise)


def spec_parameters(spec: Spec, model, options: Iterable[str] = ()) -> dict[str, float]:
    """The model parameters of a budget: the spec's ``[parameters]``, then ``--parameter``.

    Parameters
    ----------
    spec : Spec
        The spec; its ``[parameters]`` values need units (as a scenario's do).
    model : ins_errors.numeric.model.Model
        The model the spec is bound to.
    options : iterable of str
        ``--parameter NAME=VALUE`` items; each replaces the spec's value of that name.

    Returns
    -------
    dict of str to float
        Parameter name -> SI value (spec order, then new names of the options).

    Raises
    ------
    InsErrorsError
        One line: an unknown name, a value without or in the wrong unit, a negative gain.
    """
    from ins_errors.model_parameters import parse_parameter_options, parse_parameters

    where = f"{spec.path} [parameters]" if spec.path else "[parameters]"
    values = parse_parameters(model, spec.parameters, where, numbers_are_si=False)
    values.update(parse_parameter_options(model, options))
    return values


def load_spec(path: str | Path) -> Spec:
    """Read a spec file (TOML).

    Fixed source magnitudes (``fixed = "0.01 deg/h"``) stay text until the spec is bound
    to a model (:func:`ins_errors.analysis.budget.resolve_sources`), which knows each
    source's unit.

    Raises
    ------
    SpecError
        Missing or unreadable file, bad TOML, or any bad entry (see :func:`parse_spec`).
    """
    where = os.fspath(path)  # as the user typed it, for messages
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")  # -sig: a leading BOM is no TOML
    except OSError as error:
        raise SpecError(f"cannot read spec file {where!r}: {error.strerror}") from None
    except UnicodeDecodeError:
        raise SpecError(f"{where}: not a text file (not UTF-8): expected a TOML spec") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SpecError(f"{where}: not valid TOML ({error})") from None
    try:
        return parse_spec(data, where)
    except InsErrorsError as error:  # named with the file the reader is to fix
        raise type(error)(f"{where}: {error}") from None


def default_spec_path() -> Path:
    """The built-in spec of product 802m (source 000's appendix, 2σ), shipped in the package."""
    return Path(__file__).resolve().parent / "data" / "802m.toml"


def spec_label(spec: Spec) -> str:
    """The spec file as its refusals name it: the path as the user gave it
    (``sub/hs.toml``, not ``hs.toml``), ``the built-in 802m spec`` for the built-in one
    (not to be taken for a copy of it named ``802m.toml``), ``the spec`` without a file."""
    if not spec.path:
        return "the spec"
    if Path(spec.path).resolve() == default_spec_path():
        return "the built-in 802m spec"
    return spec.path
