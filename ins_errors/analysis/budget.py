r"""Error budget against an accuracy spec: per-source contributions and allocation.

What each spec item measures (error quantities of the linear error model, in SI):

``position_error``
    north error :math:`R_N \Delta\varphi` and east error :math:`R_E\cos\varphi\,
    \Delta\lambda`, with :math:`R_N = a(1-e^2)/(1-e^2\sin^2\varphi)^{3/2} + h` and
    :math:`R_E = a/\sqrt{1-e^2\sin^2\varphi} + h` the meridian and prime-vertical radii of
    the model's ellipsoid at the current latitude (Krasovsky by default); the item is a
    rate over the operating time: at a check time t the quantity is error / t, compared
    with the value (e.g. 3.7 km/h: 3.7 km after 1 h, 7.4 km after 2 h, ...);
``position_error_absolute``
    the same north and east errors in metres, not divided by time;
``height_error``
    the error of the model's ``height`` output (through H; strapdown_ned's
    :math:`\delta h`);
``ground_speed_error``
    north and east velocity errors :math:`\Delta v_N, \Delta v_E` (outputs through H);
``vertical_error``
    platform tilts :math:`\alpha_x, \alpha_y`; for a strapdown INS (``strapdown_ned``,
    or a strapdown model file that describes itself by its outputs:
    :mod:`ins_errors.checker.strapdown_description`) the level components
    :math:`\phi_N, \phi_E` of the φ-angle (the attitude error in the true NED frame);
``heading_error``
    :math:`\alpha_z(t)`, the azimuth error of the platform (the gyroscopic heading)
    itself, its initial alignment error included (a strapdown INS: :math:`\phi_D`);
``heading_drift``
    :math:`(\alpha_z(t) - \alpha_z(0))/t`, the mean drift rate of the platform azimuth
    (the gyroscopic heading) since the start; :math:`\alpha_z(0)` is the initial
    azimuth error, a linear function of the sources (``E``), so it is excluded exactly;
    for a strapdown INS the same with the azimuth component :math:`\phi_D`.

The direct runs of a Monte Carlo check read the same quantities: a strapdown INS's
φ-angle is the covariance's rows ``T_φ(x)`` along each run's own ideal states at its
record times, applied to the run's real − ideal states
(:mod:`~ins_errors.analysis.budget_attitude`).

With ``combine = "rss"`` (default) an item's components are combined as the root sum of
squares, so a 2σ limit on the position is a limit on 2DRMS = 2·sqrt(σ_N² + σ_E²); with
``"each"`` every component must meet the limit on its own; with ``"cep"`` (the position
items) the limit is a circular error probable, the CEP of the north and east errors' 2×2
covariance, cross term included (:mod:`~ins_errors.analysis.budget_cep`), whatever the
σ level.

Allocation rule (documented in the report): the spec's σ level k turns each limit L into
an allowed variance (L/k)². Fixed sources take their contribution first; of what
remains, every free source j gets the share w_j / Σw (equal shares by default) of every
item's variance at every check time, and its allowed 1σ magnitude is the largest that
keeps its own contribution within its share everywhere. The item (and time) where that
happens *binds* the source. Since no source exceeds its share, every item is met; with
``fill = true`` all free sources are then scaled by one common factor until the tightest
item is met exactly. A CEP row shares the north + east variance of a circular error
with the limit as its CEP, (limit / 0.8326)², the largest that meets the CEP whatever the
shape of the error ellipse (:func:`allocate`); ``fill`` brings its CEP to the limit.

A row whose limit itself lies beyond the linear model's range (:data:`LINEAR_LIMITS`)
cannot be sized (:func:`limits_beyond_linear`), and an allocation a growing mode has made
absurd is refused (:func:`growth_refusal`).

Sources that no spec row depends on take no share and are reported as not limited on
this motion. "Depends on" is judged against the rounding floor of the propagation
(:func:`rounding_floors`), not against an exact zero: a row whose computed dependence on
a source is at or below its floor depends on it only through round-off (e.g. the tilts
on the initial longitude error, through entries of F that are zero but for the last
bits), and such a dependence would otherwise allow an absurd magnitude (1e47 arcmin) and
still take a share from every other source. It is judged against the row's own scale
too (:data:`SEEN_FRACTION`): a source that, even at the largest size the linear model
covers for it (its linear limit, below), moves a row by less than a hundred-thousandth
of the row's limit is not seen by that row. The floor of the propagation is relative to
the source's own response, so it cannot tell a source whose whole drive on this motion
is a remainder: at rest the orthodromic model's x accelerometer sees a specific force of
−3.2e-8 m/s² along ξ (the e⁴ remainder of the manual's truncated 1/R_η in the absolute
velocity against the exact R_E of the gravitation g′; along η it is exactly 0), and its
second integrators' gains see relative rates of 1e-21 rad/s (rounding of a rate that is
0 at rest); these scale and gain errors are not limited on this motion, as their
partners on the other axis are, not "limited by the linear model" alone.

A source the spec sees only faintly gets a share whose size lies beyond the linear
error model (a velocity-reference bias behind a 1e-9/s damping gain: 3.6e5 m/s). Such
a source is judged by what it does at that size, not by its unit: if, alone at its
share, it drives an error quantity of the linear model beyond :data:`LINEAR_LIMITS`
(an error state at any time of the operating time, or the source's own value, which is
an error state of the augmented model too), the spec does not limit it within the
model's range: it takes no share, the shares are divided again among the other sources,
and it is reported as not limited by this spec with its linear limit
(:attr:`UnitBudget.linear_limits`), the largest size at which it keeps every error
quantity within those limits. A gyro drift or an accelerometer bias has no size limit of
its own (no error state is a rate or a specific force): a 40 °/h azimuth drift for 5
minutes turns the azimuth by 3.3°, well within the model, and is allocated. Tables and
plots of a budget are in :mod:`ins_errors.analysis.budget_report`.

A spec without a ``height_error`` item on a model with a height output still allocates
the sources that act mainly on the height (a vertical accelerometer's bias, the initial
vertical errors) through the weak coupling of the height into the other items: true
allowances, but they bound nothing about the height, and :func:`vertical_channel_note`
says so in one line.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ins_errors.analysis.budget_attitude import (
    PLATFORM_ANGLE_NAMES,
    attitude_label,
    attitude_quantities,
    attitude_rows,
    has_attitude,
)
from ins_errors.analysis.budget_cep import CEP_PER_DRMS_CIRCLE, CEP_PER_SIGMA_CIRCLE, cep
from ins_errors.analysis.covariance import (
    Covariance,
    Functionals,
    LinearSystem,
    SourceStatistics,
    propagate,
    static_system,
    system_from_trajectory,
)
from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.numeric.linear_system import check_grid_memory, growth_folds
from ins_errors.numeric.model import load_model
from ins_errors.specs import ITEM_KINDS, SOURCE_UNIT_SUFFIX, Spec, SpecError, spec_label
from ins_errors.units import (
    UnitError,
    format_duration,
    format_quantity,
    parse_quantity,
)

EPS = float(np.finfo(float).eps)


def format_time(seconds: float) -> str:
    """A time of the budget's tables and lines: ``"1 h"``, ``"40 min"``, ``"2 h 35 min"``
    as :func:`~ins_errors.units.format_duration` writes whole minutes, and a time off
    the minute from 2 min on in hours, minutes and seconds too (``"42 min 10 s"``,
    ``"1 h 0 min 5 s"``; below it ``"50 s"``, ``"90 s"``), not in seconds alone (a worst
    time of 2530 s read "2530 s").
    """
    seconds = round(float(seconds), 6)
    if seconds < 0:
        return "-" + format_time(-seconds)
    whole = 60.0 * (seconds // 60.0)
    if seconds < 120.0 or whole == seconds:
        return format_duration(seconds)
    rest = round(seconds - whole, 6)
    hours, minutes = divmod(round(whole / 60.0), 60)
    head = f"{hours} h {minutes} min" if hours else f"{minutes} min"
    return f"{head} {rest:g} s"

RATE_ITEMS = ("position_error", "heading_drift")
"""Items whose quantity is an error divided by the operating time."""


LINEAR_ANGLE = 0.1
"""rad: the largest angle error of the small-error model (sin x = x within 0.17 %, the
products of angles a tenth of the angles)."""

EARTH_RADIUS, GRAVITY = 6_371_000.0, 9.80665
"""m, m/s²: the scales of :data:`LINEAR_LIMITS` (orders of magnitude, the same for every
model)."""

SEEN_FRACTION = 1e-5
"""A source moves a spec row (the row depends on it) only when, at the largest size the
linear model covers for it (:attr:`UnitBudget.linear_limits`), it moves the row by at
least this fraction of the row's limit (1e-10 of its allowed variance; no digit the
budget prints). Measured: remainders of a static base 7e-7 (orthodromic's x scale-factor
error at 50°, at most 1.1e-6 at any latitude) and 1e-12 or less (integrator gains through
rounding); the faintest source a spec truly sees in the tests, a velocity-reference bias
behind a 1e-9/s damping gain, 6e-4."""

LINEAR_LIMITS = {
    "rad": LINEAR_ANGLE,
    "1": LINEAR_ANGLE,
    "m": LINEAR_ANGLE * EARTH_RADIUS,
    "m/s": LINEAR_ANGLE * float(np.sqrt(GRAVITY * EARTH_RADIUS)),
}
"""The range of the linear error model, by SI unit, at the spec's σ level: an error
quantity (an error state, or a source's own value) beyond its limit lies outside the
small-error model, and a linear budget cannot say what the spec allows there.

``rad``
    0.1 rad: attitude and azimuth errors, latitude and longitude errors, initial
    alignment errors, misalignments.
``1``
    0.1: a scale-factor or gain error over 10 %, a direction-cosine or quaternion error
    (a rotation of about 0.1 to 0.2 rad).
``m``
    0.1 R = 637 km: the position error whose arc on the Earth is 0.1 rad (the radii,
    gravity and Earth-rate components then change at second order as with a 0.1-rad
    angle); a height error of 637 km changes gravity by a fifth.
``m/s``
    0.1 √(gR) = 790 m/s: the velocity error the Schuler loop trades for a 0.1-rad tilt
    (δV = α √(gR)); its transport-rate error δV/R turns the navigation frame by 0.1 rad
    within the loop's time constant 1/ω_s = √(R/g).

Other units (a drift in rad/s, a specific force in m/s², a damping integrator) have no
limit of their own: such errors are large or small only through what they do to the
quantities above, and that is what is judged (an azimuth drift of 40 °/h is what a
5-minute spec of 40 °/h heading drift allows). White-noise densities are judged by
their effect only."""


class BudgetError(InsErrorsError):
    """A budget that cannot be formed (e.g. fixed sources alone break the spec)."""


class SpecExceededError(BudgetError):
    """The fixed sources alone use up (or exceed) at least one spec row: no magnitude is
    left for the free sources. Not a bad input: the spec is well formed and the answer is
    "exceeded" (the command line exits 1 with the rows, not 2).

    Attributes
    ----------
    budget : UnitBudget
    values : numpy.ndarray, shape (nr,)
        Each row's error from the fixed sources alone at the spec's σ level, SI.
    used_up : numpy.ndarray of bool, shape (nr,)
        Rows whose allowed variance the fixed sources use up.
    """

    def __init__(self, message: str, budget: UnitBudget, values: np.ndarray,
                 used_up: np.ndarray) -> None:
        super().__init__(message)
        self.budget, self.values, self.used_up = budget, values, used_up


@dataclass(frozen=True)
class BudgetSource:
    """One source in a budget.

    Attributes
    ----------
    name, unit, display_unit : str
        Model name, SI unit of the magnitude and the unit it is reported in (white noise:
        unit × √s, reported per √h).
    statistics : str
        ``"constant"``, ``"white"`` or ``"markov"``.
    tau : float or None
        Markov correlation time, s.
    weight : float
        Share weight.
    fixed : float or None
        Fixed 1σ magnitude (SI), or None when allocated.
    paired : bool
        The source has two parts in the budget (a bias and its noise,
        ``[sources.NAME.noise]``), this one of them.
    sigma_level : float
        σ level of the magnitude as the spec writes it and the reports show it: the
        source's own ``sigma_level`` or the spec's for a constant or Markov source, 1 for
        a white-noise density (a density has no σ level: it is read as given).
    """

    name: str
    unit: str
    display_unit: str
    statistics: str
    tau: float | None
    weight: float
    fixed: float | None
    sigma_level: float = 1.0
    paired: bool = False

    @property
    def label(self) -> str:
        """The source as the tables name it: its model name, with the part's kind after
        it for a noise (``gyro_bias_x (white)``) and for each part of a source that has
        two (``gyro_bias_x (constant)``)."""
        if self.paired or self.statistics != "constant":
            return f"{self.name} ({self.statistics})"
        return self.name


@dataclass(frozen=True)
class Row:
    """One checked constraint: an item at a time (and a component with ``"each"``).

    Attributes
    ----------
    item : str
    time : float
        s.
    component : str
        ``""`` for an rss row, else the component name.
    limit : float
        The item's value at the spec's σ level, SI (a CEP row's: the CEP itself, which
        has no σ level).
    cep : bool
        The row is the CEP of the north and east errors (``combine = "cep"``,
        :mod:`~ins_errors.analysis.budget_cep`), not k times their rss.
    """

    item: str
    time: float
    component: str
    limit: float
    cep: bool = False

    @property
    def label(self) -> str:
        extra = f" [{self.component}]" if self.component else ""
        return f"{self.item} at {format_time(self.time)}{extra}"


@dataclass(frozen=True)
class UnitBudget:
    """Variance of every spec row per unit variance of every source.

    Attributes
    ----------
    spec : Spec
    sources : tuple of BudgetSource
    rows : tuple of Row
    unit_variances : numpy.ndarray, shape (nr, ns)
        SI units² of the row per (source unit)².
    system : LinearSystem
    floors : numpy.ndarray, shape (nr, ns), optional
        Rounding floor of each unit variance (:func:`rounding_floors`), same units: a
        unit variance at or below it is round-off, no dependence. None: only exact
        zeros are taken as no dependence.
    state_peaks : numpy.ndarray, shape (n, ns), optional
        Largest variance of every error state over the operating time per unit variance
        of every source (round-off taken as 0), SI units² per (source unit)². None: the
        error states are not judged (only the sources' own values).
    state_units : tuple of str
        SI unit of every error state (the rows of ``state_peaks``).
    state_names : tuple of str
        Name of every error state (the rows of ``state_peaks``).
    item_variances : numpy.ndarray, shape (nt, q, ns), optional
        The propagation the rows are read from: variance of every item's functional
        (``item_names``, one per component, SI: m, m/s, rad; a rate item not yet
        divided by t) at every grid time ``system.times`` per unit variance of every
        source; :func:`item_lines` turns it into an item's values. None: not kept.
    item_names : tuple of str
        ``"item:component"`` of every functional of ``item_variances``.
    north, cross : numpy.ndarray, shape (nr, ns), optional
        Of a CEP row (:attr:`Row.cep`), the variance of the north error and the
        covariance of the north and east errors per unit variance of every source (the
        row's ``unit_variances`` are north + east); 0 on the other rows. None: the spec
        has no CEP item.
    model : ins_errors.numeric.model.Model, optional
        The model the budget is of (:func:`unit_budget` keeps it: the refusals name its
        damping gains).
    """

    spec: Spec
    sources: tuple[BudgetSource, ...]
    rows: tuple[Row, ...]
    unit_variances: np.ndarray
    system: LinearSystem
    floors: np.ndarray | None = None
    state_peaks: np.ndarray | None = None
    state_units: tuple[str, ...] = ()
    state_names: tuple[str, ...] = ()
    item_variances: np.ndarray | None = None
    item_names: tuple[str, ...] = ()
    north: np.ndarray | None = None
    cross: np.ndarray | None = None
    model: object = None

    @property
    def cep_rows(self) -> np.ndarray:
        """Which rows are CEP rows (:attr:`Row.cep`), shape (nr,) of bool."""
        return np.array([r.cep for r in self.rows], dtype=bool)

    def row_values(self, sigma: np.ndarray) -> np.ndarray:
        """Every row's value at the given 1σ magnitudes, SI, shape (nr,): k times the
        rss of its components, or a CEP row's CEP (:func:`row_values`).

        Parameters
        ----------
        sigma : numpy.ndarray, shape (ns,)
            1σ of every source, SI; inf or NaN (not limited) counts as 0.
        """
        sigma = np.where(np.isfinite(sigma), sigma, 0.0)
        return row_values(self.rows, self.spec.sigma_level, self.unit_variances * sigma**2,
                          *self._cep_parts(sigma))

    def _cep_parts(self, sigma: np.ndarray) -> tuple[np.ndarray | None, np.ndarray | None]:
        """The north variances and north-east covariances of every row from every source
        at ``sigma`` (finite), (nr, ns) each, or None without CEP rows."""
        if self.north is None:
            return None, None
        return self.north * sigma**2, self.cross * sigma**2

    @property
    def depends(self) -> np.ndarray:
        """Whether each row depends on each source, (nr, ns) of bool: above round-off, and
        by at least :data:`SEEN_FRACTION` of the row's limit at the source's linear limit
        (:attr:`linear_limits`; a source without one is judged by round-off only)."""
        floors = np.zeros_like(self.unit_variances) if self.floors is None else self.floors
        limits = self.linear_limits
        bounded = np.isfinite(limits)
        largest = self.unit_variances * np.where(bounded, limits, 0.0)[None, :] ** 2
        measurable = ~bounded[None, :] | (
            largest >= SEEN_FRACTION**2 * self.allowed_variances[:, None])
        return (self.unit_variances > floors) & measurable

    @property
    def allowed_variances(self) -> np.ndarray:
        """(limit / k)² of every row, shape (nr,); of a CEP row, the variance (σ_N² +
        σ_E², DRMS²) at which a circular error has the limit as its CEP, (limit /
        0.8326)²: the largest DRMS² that meets the CEP whatever the shape of the error
        ellipse (:data:`~ins_errors.analysis.budget_cep.CEP_PER_DRMS_CIRCLE`)."""
        return np.array([(r.limit / (CEP_PER_DRMS_CIRCLE if r.cep else self.spec.sigma_level))
                         ** 2 for r in self.rows])

    @property
    def linear_limits(self) -> np.ndarray:
        """Largest 1σ of every source within the linear model, SI, shape (ns,).

        The largest magnitude at which the source, alone, keeps its own value (constant
        and Markov sources) and every error state at every time of the operating time
        within :data:`LINEAR_LIMITS` at the spec's σ level; inf where nothing limits it.
        """
        own, reach = self._linear_reach()
        if reach is None:
            return own
        return np.minimum(own, reach.min(axis=0, initial=np.inf))

    def _linear_reach(self) -> tuple[np.ndarray, np.ndarray | None]:
        """At the spec's σ level, the largest 1σ of every source that keeps its own value
        within :data:`LINEAR_LIMITS` (ns,) and, per error state, that keeps the state
        within them (n, ns); None for the latter where the states are not judged."""
        k = self.spec.sigma_level
        own = np.array([np.inf if s.statistics == "white"
                        else LINEAR_LIMITS.get(s.unit, np.inf) for s in self.sources]) / k
        if self.state_peaks is None:
            return own, None
        limits = np.array([LINEAR_LIMITS.get(u, np.inf) for u in self.state_units]) / k
        with np.errstate(divide="ignore"):
            return own, limits[:, None] / np.sqrt(self.state_peaks)

    def linear_limit_cause(self, j: int) -> tuple[str, str]:
        """What sets source ``j``'s linear limit (:attr:`linear_limits`): the name and SI
        unit of the error state that leaves :data:`LINEAR_LIMITS` first, or ``("its own
        value", unit)``."""
        own, reach = self._linear_reach()
        if reach is not None and self.state_names:
            i = int(np.argmin(reach[:, j]))
            if reach[i, j] < own[j]:
                return self.state_names[i], self.state_units[i]
        return "its own value", self.sources[j].unit

    def statistics(self, sigma: np.ndarray) -> list[SourceStatistics]:
        """Source statistics with the given 1σ magnitudes (SI)."""
        return [SourceStatistics(s.name, s.statistics, float(v), s.tau)
                for s, v in zip(self.sources, sigma, strict=True)]


# --------------------------------------------------------------------------------------
# Binding a spec to a model
# --------------------------------------------------------------------------------------
def resolve_sources(model, spec: Spec) -> tuple[BudgetSource, ...]:
    """The model's sources with the spec's options (units checked against the model)."""
    names = [s.name for s in model.sources]
    where = spec_label(spec)   # the file as the user gave it
    for name in spec.sources:
        if name not in names:
            raise unknown_name(f"error source of {model.name} in {where}", name, names)
    result = []
    for info in model.sources:
        option = spec.option(info.name)
        if not option.include:
            continue
        parts = [option] if option.noise is None else [option, option.noise]
        for part, key in zip(parts, (f"sources.{info.name}", f"sources.{info.name}.noise"),
                             strict=False):
            result.append(_budget_part(info, part, spec, where, key, len(parts) > 1))
    if not result:
        raise SpecError(f"{where}: every error source is excluded from the budget")
    return tuple(result)


def _budget_part(info, option, spec: Spec, where: str, key: str,
                 paired: bool) -> BudgetSource:
    """One part of a model source (its bias, or its noise) as the budget carries it."""
    if info.kind == "initial" and option.kind != "constant":
        raise SpecError(f"{where}: {key}: an initial error can only be a random constant, "
                        f"not {option.kind!r}")
    suffix = SOURCE_UNIT_SUFFIX[option.kind]
    unit = f"({info.unit})*s**0.5" if suffix else info.unit
    display = info.display_unit or info.unit
    if suffix:
        display = density_display(display, unit)
    level = source_level(spec, option)
    fixed = None
    if option.fixed is not None:
        refuse_bare_ratio(option.fixed, info.unit, display, f"{where}: {key}.fixed")
        try:
            value = parse_quantity(option.fixed, unit, f"{key}.fixed", numbers_are_si=False)
        except UnitError as error:
            example = "" if "e.g." in str(error) else f" (e.g. '1 {display}')"
            raise SpecError(f"{where}: {error}{example}") from None
        if value < 0:
            raise SpecError(f"{where}: {key}.fixed must be >= 0, got {option.fixed!r}")
        fixed = value / level
        display = _written_unit(option.fixed, value, unit) or display
    return BudgetSource(info.name, unit, display, option.kind, option.tau, option.weight,
                        fixed, level, paired)


def _written_unit(text, value: float, unit: str) -> str | None:
    """The unit a fixed value was written in (``"0.02 m/s/sqrt(h)"`` -> ``m/s/√h``, a
    square root written √), so that the tables echo it as the spec gives it; None where
    there is none that converts back, or for a density written times √s (``ug*s**0.5``),
    which reads best per √Hz (:func:`density_display`)."""
    import re

    match = re.match(r"\s*[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?\s*", str(text))
    written = str(text)[match.end():].strip() if match else ""
    if not written or re.search(r"\*\s*(s\*\*0\.5|sqrt\(s\)|√s)", written):
        return None       # "ug*s**0.5" reads best per √Hz (density_display)
    written = re.sub(r"sqrt\((\w+)\)|(?<![\w)])(\w+)\s*(?:\*\*|\^)\s*0\.5\b",
                     lambda m: "√" + (m.group(1) or m.group(2)), written)
    try:
        format_quantity(value, unit, written)
    except Exception:  # any text the unit library cannot take back
        return None
    return written


def refuse_bare_ratio(value, unit: str, display: str, what: str) -> None:
    """Refuse a bare number for a dimensionless source (a scale factor or misalignment,
    shown in ppm): ``"500"`` would be read as the fraction 500, 5e8 ppm, where the
    writer meant 500 ppm. Such a value, too, needs its unit (docs/scenarios.md: a bare
    number where a unit is needed is refused).

    Raises
    ------
    SpecError
        One line, with the value written in ppm and in %.
    """
    if unit != "1":
        return
    text = str(value).strip() if isinstance(value, (str, int, float)) else ""
    try:
        number = float(text)
    except ValueError:
        return   # with a unit: parse_quantity reads it
    if number == 0:
        return   # zero is zero in any unit (a part bought perfect, a reference case)
    shown = display if display not in ("", "1") else "ppm"
    raise SpecError(f"{what} = {value!r} is a bare number; a ratio needs its unit, as the "
                    f"source is shown in {shown}: write '{number:g} ppm' or "
                    f"'{number / 1e4:g} %'")


def source_level(spec: Spec, option) -> float:
    """The σ level of a source's magnitude (:attr:`BudgetSource.sigma_level`): 1 for a
    white-noise density, else the source's ``sigma_level`` or the spec's."""
    if option.kind == "white":
        return 1.0
    return spec.sigma_level if option.sigma_level is None else option.sigma_level


def density_display(display: str, unit: str) -> str:
    """The unit a noise density is quoted in, as one writes it: a rate per hour per √h
    (``deg/h`` -> ``deg/√h``, an angle random walk), anything else per √Hz (``ug`` ->
    ``ug/√Hz``). Where the unit parser would not read that back, the plain product
    (``X*s**0.5``) is kept.

    Parameters
    ----------
    display : str
        The source's own display unit (of its bias).
    unit : str
        SI unit of the density (``(unit)*s**0.5``).
    """
    if display.endswith("/h") and "/" not in display[:-2]:
        shown = display[:-2] + "/√h"
    elif "/" in display or "*" in display:
        shown = f"({display})/√Hz"
    else:
        shown = f"{display}/√Hz"
    try:
        format_quantity(1.0, unit, shown)
    except Exception:  # any unit the parser cannot take back: the plain product
        return f"({display})*s**0.5"
    return shown


def spec_profile(model, spec: Spec):
    """The spec's motion as a :class:`~ins_errors.numeric.trajectories.Profile`.

    A manoeuvre is built as a scenario file's (:func:`~ins_errors.numeric.motion_spec.
    motion_profile`: the standard manoeuvre, :func:`~ins_errors.numeric.motion_spec.
    default_legs`, unless the spec lists its legs).

    Raises
    ------
    InsErrorsError
        For a heading set at rest for a model without a heading output, as a scenario
        file (:func:`~ins_errors.numeric.motion_spec.refuse_unused_heading`).
    """
    from ins_errors.numeric import trajectories
    from ins_errors.numeric.motion_spec import refuse_unused_heading

    m = spec.motion
    if m.kind == "static":
        profile = trajectories.static_profile(m.latitude, m.longitude, m.heading, m.height)
    elif m.kind == "great_circle":
        profile = trajectories.great_circle_profile(m.latitude, m.longitude, m.heading,
                                                    m.speed, m.height)
    else:  # a manoeuvre: the scenario files' standard one, or the spec's legs
        from ins_errors.numeric.motion_spec import motion_profile

        profile = motion_profile(m.description(), model=model)
    if m.heading_given:
        where = spec_label(spec)
        refuse_unused_heading(model, profile, f"{where} [motion] heading")
    return profile


def spec_trajectory(model, spec: Spec, tau: float | None = None,
                    duration: float | None = None, p: np.ndarray | None = None):
    """The true motion of the spec (trajectories module).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    spec : Spec
    tau : float, optional
        Step, s (default: the spec's analysis step).
    duration : float, optional
        Length, s, rounded to whole steps (default: the operating time).
    p : numpy.ndarray, optional
        Model parameters, SI (``Model.parameter_vector``; default: the model's defaults).
    """
    from ins_errors.numeric import trajectories

    profile = spec_profile(model, spec)
    step = spec.step if tau is None else tau
    length = spec.operating_time if duration is None else duration
    return trajectories.trajectory(model, profile, step * max(1, round(length / step)), step,
                                   p=p)


def spec_system(model, spec: Spec, trajectory=None,
                p: np.ndarray | None = None) -> LinearSystem:
    """The linear error equations along the spec's motion, on the spec's grid.

    The true motion comes from :mod:`ins_errors.numeric.trajectories`; for a static
    motion of a model those generators do not cover, the model's own rest state is used
    (:func:`~ins_errors.analysis.covariance.static_system`, a_ζ = 9.81 m/s² where the
    model has it). ``p``: model parameters, SI (default: the model's defaults; a given
    ``trajectory`` carries its own).
    """
    if trajectory is not None:
        return system_from_trajectory(model, trajectory, spec.step)
    spec_profile(model, spec)  # a refused heading is not the static fallback's case
    # before the motion is flown, at rest too: a static base keeps its true state, its
    # radii and the covariance of every row at every grid time as well (a month at
    # 0.01 s died in numpy after 33 s and 8 GB)
    check_grid_memory(model, round(spec.operating_time / spec.step) + 1, spec.step)
    try:
        trajectory = spec_trajectory(model, spec, p=p)
    except InsErrorsError as error:
        if spec.motion.kind != "static":
            if "heading" not in {o.name for o in model.outputs}:
                raise BudgetError(_unsteered(model, spec)) from None
            raise
        m = spec.motion
        try:
            return static_system(model, m.latitude, m.longitude, m.heading, m.height,
                                 duration=spec.step * max(1, round(spec.operating_time
                                                                   / spec.step)),
                                 step=spec.step, p=p)
        except InsErrorsError:
            raise error from None
    from ins_errors.numeric.trajectories import refuse_unused_references

    where = spec_label(spec)
    refuse_unused_references(model, trajectory, {   # a latitude the model has not
        name: (f"{where} [motion] {name}", text) for name, text in spec.motion.given})
    return system_from_trajectory(model, trajectory, spec.step)


def _unsteered(model, spec: Spec) -> str:
    """Why a model without a heading output cannot be budgeted on the spec's moving
    base, and the way out a spec has (a spec has no motion file, unlike a scenario)."""
    where = spec_label(spec)
    kind = spec.motion.kind.replace("_", " ")
    unused = [name for name, given in (("heading", spec.motion.heading_given),
                                       ("speed", spec.motion.speed > 0)) if given]
    out = f" and leave out its {' and '.join(unused)}" if unused else ""
    return (f"model {model.name!r} cannot fly the spec's {kind} motion (a moving base is "
            f"steered by the heading, which is not among its outputs); a budget spec has no "
            f"motion file, so budget this model on a static base: set kind = \"static\" "
            f"in {where}'s [motion]{out}")


def _radii(model, system: LinearSystem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Latitude (rad), R_N and R_E cos φ (m) along the grid, shape (K+1,) each."""
    from ins_errors.models.earth import earth_ellipsoid, radii_of_curvature

    names = [i.name for i in model.parameters]
    try:
        a, e2 = earth_ellipsoid(names, system.p, f"model {model.name}")
    except InsErrorsError as error:
        raise BudgetError(str(error)) from None
    outputs = [o.name for o in model.outputs]
    if "latitude" not in outputs:
        raise BudgetError(f"model {model.name} has no 'latitude' output")
    values = model.numpy.outputs(system.x, system.u, system.p)
    phi = values[outputs.index("latitude")]
    # the height of the flight: a strapdown INS's height output (a state), a platform
    # model's height input (was the input alone: every strapdown position error came out
    # R/(R + h) of its value, 0.16 % low at 10 km)
    inputs = [i.name for i in model.inputs]
    h = (values[outputs.index("height")] if "height" in outputs
         else system.u[inputs.index("h")] if "h" in inputs else 0.0)
    R_N, R_E = radii_of_curvature(phi, a, e2)
    return phi, R_N + h, (R_E + h) * np.cos(phi)


ITEM_NEEDS = {"position_error": ("outputs", ("latitude", "longitude")),
              "position_error_absolute": ("outputs", ("latitude", "longitude")),
              "height_error": ("outputs", ("height",)),
              "ground_speed_error": ("outputs", ("v_N", "v_E"))}
"""Outputs each item is read from; ``vertical_error``, ``heading_error`` and
``heading_drift`` need the attitude error (:func:`has_attitude`)."""

POSITION_ITEMS = ("position_error", "position_error_absolute")
"""Items read in metres from the latitude and longitude errors (need the Earth's radii)."""


def _unmet_items(model, names) -> dict[str, str]:
    """Item name -> what the model lacks to check it, for those of ``names`` it cannot
    check (the others are left out)."""
    outputs = {o.name for o in model.outputs}
    angles = has_attitude(model)
    parameters = {p.name for p in model.parameters}
    radius = {"a", "e2"} <= parameters or "R" in parameters
    missing: dict[str, str] = {}
    for name in names:
        if name in ITEM_NEEDS:
            lacking = [n for n in ITEM_NEEDS[name][1] if n not in outputs]
            if lacking:
                missing[name] = f"it has no output {', '.join(lacking)}"
            if name in POSITION_ITEMS and not radius:  # R_N, R_E of the metres
                missing[name] = (f"{missing[name]} and" if lacking else "it has"
                                 ) + " no Earth radius parameter ('a' with 'e2', or 'R')"
        elif not angles:
            missing[name] = ("it has no platform error angles (" + " or ".join(
                ", ".join(names) for names in PLATFORM_ANGLE_NAMES) + ") and is not a "
                "strapdown INS with navigation outputs (docs/matrix_check.md)")
    return missing


def check_items(model, spec: Spec) -> None:
    """Refuse, in one line, a spec with items the model has nothing to check them by.

    Raises
    ------
    BudgetError
        Naming every such item, what the model lacks, and how to leave the items out;
        when the model can check none of the spec's items, what a spec for it needs
        instead (the items it can check, or that no item of the budget fits it).
    """
    missing = _unmet_items(model, [item.name for item in spec.items])
    if not missing:
        return
    by_reason: dict[str, list[str]] = {}
    for name, why in missing.items():
        by_reason.setdefault(why, []).append(name)
    reasons = "; ".join(why if len(by_reason) == 1 else f"{', '.join(names)}: {why}"
                        for why, names in by_reason.items())
    source = f"{spec.path}" if spec.path else "the spec"   # a file to copy
    plural = "s" if len(missing) > 1 else ""
    if len(missing) == len(spec.items):   # leaving them out would leave no item
        source = spec_label(spec)
        checkable = [name for name in ITEM_KINDS if name not in _unmet_items(model,
                                                                             ITEM_KINDS)]
        if checkable:
            need = (f"a spec for it needs items it can check: write one with "
                    f"{', '.join(f'[items.{name}]' for name in checkable)} (docs/"
                    f"scenarios.md; 'ins-errors budget --schema' lists every key)")
        else:
            need = (f"a spec needs at least one item its model can check, and none of the "
                    f"budget's items ({', '.join(ITEM_KINDS)}) fits this model, so it "
                    f"cannot be budgeted as it is")
        every = "all the items" if plural else "the only item"
        raise BudgetError(f"model {model.name} cannot check the spec item{plural} "
                          f"{', '.join(missing)} ({reasons}), {every} of {source}; {need}")
    tables = ", ".join(f"[items.{name}]" for name in missing)
    raise BudgetError(f"model {model.name} cannot check the spec item{plural} "
                      f"{', '.join(missing)} ({reasons}); leave {'them' if plural else 'it'} "
                      f"out: copy {source} without its {tables} table{plural} and pass the "
                      f"copy with --spec")


def item_functionals(model, system: LinearSystem, spec: Spec) -> tuple[Functionals,
                                                                         dict[str, list[int]]]:
    """The error quantities every spec item needs, and which ones belong to each item."""
    nw = system.E.shape[1]
    K1 = len(system.times)
    outs = [o.name for o in model.outputs]

    def output_row(name: str) -> np.ndarray:
        if name not in outs:
            raise BudgetError(f"model {model.name} has no output {name!r}")
        H = system.H if system.H.ndim == 3 else np.broadcast_to(system.H, (K1, *system.H.shape))
        return H[:, outs.index(name), :]

    kept: list = []

    def attitude(model, system) -> list[tuple[str, np.ndarray]]:
        if not kept:  # the φ-angle rows of a strapdown INS once for both items
            kept.append(attitude_rows(model, system))
        return kept[0]

    rows: list[tuple[str, str, np.ndarray, np.ndarray]] = []
    groups: dict[str, list[int]] = {}
    zero_b = np.zeros(nw)
    for item in spec.items:
        if item.name in POSITION_ITEMS:   # the rate item is divided by t in _rows
            _, R_N, R_E_cos = _radii(model, system)
            north = output_row("latitude") * R_N[:, None]
            east = output_row("longitude") * R_E_cos[:, None]
            parts = [("north", north, zero_b), ("east", east, zero_b)]
            if item.combine == "cep":   # its variance gives the north-east covariance
                parts.append((DIAGONAL, (north + east) / np.sqrt(2.0), zero_b))
        elif item.name == "height_error":
            parts = [("height", output_row("height"), zero_b)]
        elif item.name == "ground_speed_error":
            parts = [("north", output_row("v_N"), zero_b), ("east", output_row("v_E"), zero_b)]
        elif item.name == "vertical_error":
            parts = [(label, row, zero_b) for label, row in attitude(model, system)[:2]]
        elif item.name == "heading_error":  # the azimuth itself, its start included
            parts = [("azimuth", attitude(model, system)[2][1], zero_b)]
        else:  # heading_drift: azimuth(t) - azimuth(0), azimuth(0) = row(0) E w
            _, row = attitude(model, system)[2]
            parts = [("azimuth", row, -(row[0] @ system.E))]
        groups[item.name] = []
        for label, C_x, C_b in parts:
            groups[item.name].append(len(rows))
            rows.append((f"{item.name}:{label}", item.name, C_x, C_b))
    C_x = np.stack([r[2] for r in rows], axis=1)                   # (K+1, q, n)
    if system.time_invariant:
        C_x = C_x[0]
    C_b = np.stack([r[3] for r in rows])
    units = tuple("" for _ in rows)
    return Functionals(tuple(r[0] for r in rows), units, C_x, C_b), groups


def unit_budget(model, spec: Spec, trajectory=None,
                p: np.ndarray | None = None) -> UnitBudget:
    """Variance of every spec row per unit variance of every source.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model or str
        The model, or a name :func:`~ins_errors.load_model` takes.
    spec : Spec
    trajectory : Trajectory, optional
        True motion (default: the spec's motion over its operating time, on its step).
    p : numpy.ndarray, optional
        Model parameters, SI (``Model.parameter_vector``; default: the model's defaults).
    """
    model = load_model(model)
    check_items(model, spec)
    sources = resolve_sources(model, spec)
    system = spec_system(model, spec, trajectory, p)
    statistics = [SourceStatistics(s.name, s.statistics, 1.0, s.tau) for s in sources]
    functionals, _ = item_functionals(model, system, spec)
    covariance = propagate(system, statistics, functionals, warn=False)
    rows, unit, parts = _cep_rows(spec, system, covariance, covariance.unit_variances)
    north, cross = (None, None) if parts is None else parts
    # the error states on their own (a separate propagation, so that the rows' numbers
    # are those of the items alone, to the bit): the scale of the rows' rounding floors
    states = propagate(system, statistics, _state_functionals(model, system), warn=False)
    floors = rounding_floors(states.unit_variances, functionals.C_x,
                             typical_state_sizes(model), len(model.error_states)
                             + len(sources))
    _, floor = _rows(spec, system, covariance, floors)
    # the states' own round-off is no reach: a state that depends on a source only
    # through it must not call a faintly seen source nonlinear
    n = len(model.error_states)
    own_floors = rounding_floors(states.unit_variances, np.eye(n), typical_state_sizes(model),
                                 n + len(sources))
    reached = np.where(states.unit_variances > own_floors, states.unit_variances, 0.0)
    return UnitBudget(spec, sources, tuple(rows), unit, system, floor,
                      reached.max(axis=0), tuple(st.unit for st in model.error_states),
                      tuple(st.name for st in model.error_states),
                      covariance.unit_variances, covariance.names, north, cross, model)


def growth_warning(model, budget: UnitBudget) -> str | None:
    """One line when the error equations at the start grow by e-foldings over the
    operating time (:func:`ins_errors.numeric.linear_system.growth_warning`), or None.

    The allocation then only divides what the growth leaves: an undamped vertical
    channel (strapdown_ned's default) grows as e^(t/570 s), e^50 in 8 h, and the
    allowances come out absurdly small (1e-19 deg/h). Damping gains left at zero are
    named (:func:`~ins_errors.numeric.linear_system.undamped_remedy`).
    """
    from ins_errors.model_lookup import command_name
    from ins_errors.numeric.linear_system import growth_warning as warning
    from ins_errors.numeric.linear_system import undamped_remedy

    system = budget.system
    # on a moving base F changes along the motion: the mode of F at the start must be
    # followed by the equations over the operating time (orthodromic's delta_V_eta on an
    # eastbound great circle, ×e every 9.2 h at the start, is not): growth_folds
    if growth_folds(system, budget.spec.operating_time) is None:
        return None
    F = system.F if system.F.ndim == 2 else system.F[0]
    remedy = undamped_remedy(model, system.p)
    return warning(F, budget.spec.operating_time, command_name(model),
                   "the allowed magnitudes are only what that growth leaves, far below what "
                   "the sources do on a stable system", "operating time", remedy,
                   static=system.time_invariant)


LIMIT_NAMES = {"rad": "0.1 rad", "1": "0.1", "m": "0.1 R", "m/s": "0.1 √(gR)"}
"""How :func:`linear_range_warning` names each of :data:`LINEAR_LIMITS`."""


def linear_range_warning(budget: UnitBudget, values: np.ndarray) -> str | None:
    """One line when a reported figure lies beyond the linear error model's range, or None.

    The budget's numbers are those of the linear error equations; a spec row whose
    error (at the spec's σ level) is beyond :data:`LINEAR_LIMITS` (a position error over
    637 km, an angle over 0.1 rad, a velocity error over 790 m/s) is outside the
    small-error model, where the direct equations differ (a MEMS-grade IMU at rest: 955 km
    after 1 h). A rate item is judged by the error it is the rate of (``position_error``
    × t, ``heading_drift`` × t). The line names each such item at its worst row, its
    value against the limit.

    Parameters
    ----------
    budget : UnitBudget
    values : numpy.ndarray, shape (nr,)
        Every row's value at the spec's σ level, SI (an allocation's, or the fixed
        sources' of a spec they exceed).
    """
    worst: dict[str, tuple[float, str]] = {}
    k = budget.spec.sigma_level
    for row, value in zip(budget.rows, values, strict=True):
        unit = ITEM_SI[row.item]
        size = value * row.time if row.item in RATE_ITEMS else value
        unit = {"m/s": "m", "rad/s": "rad"}[unit] if row.item in RATE_ITEMS else unit
        limit = LINEAR_LIMITS.get(unit)
        if limit is None or not size > limit:
            continue
        ratio = size / limit
        if row.item in worst and worst[row.item][0] >= ratio:
            continue
        shown = ("deg", "deg") if unit == "rad" else ("km", "km") if unit == "m" else (
            "m/s", "m/s")
        error = ("its error " if row.item in RATE_ITEMS else "")
        level = "CEP" if row.cep else f"at {k:g}σ"
        worst[row.item] = (ratio, f"{row.label} ({error}{format_quantity(size, unit, shown[0])}"
                                  f" {level}, beyond {format_quantity(limit, unit, shown[1])}"
                                  f" = {LIMIT_NAMES[unit]})")
    if not worst:
        return None
    listed = "; ".join(text for _, text in worst.values())
    return (f"beyond the linear error model's range: {listed}; the budget's figures come "
            f"from the linear error equations, which hold for small errors only: the real "
            f"errors differ there (check with direct runs: 'ins-errors compare')")


VERTICAL_DOMINANCE = 10.0
"""A source whose largest height error over the operating time is at least this many
times its largest horizontal position error acts mainly on the vertical channel."""

VERTICAL_GAP = 100.0
"""A source also acts mainly on the vertical channel when its ratio of largest height
error to largest horizontal position error is at least :data:`VERTICAL_SHARE` and this
many times the ratio of every source below it (:func:`vertical_sources`): two decades
between the sources the spec sees through the height and those it sees directly.
Measured on strapdown_ned: with its vertical channel damped (a 300-s loop) the
vertical accelerometer's bias and scale error give 0.26 of their horizontal error as
height, the initial vertical velocity and height errors 3.6 to 18 times it, and the
horizontal sources 0.0024 at most, at rest, on a great circle and on the manoeuvre;
undamped over 10 to 20 minutes the vertical ones 14 or more, the horizontal ones 0.12
at most."""

VERTICAL_SHARE = 0.1
"""The least ratio of largest height error to largest horizontal position error of a
source that acts mainly on the vertical channel by :data:`VERTICAL_GAP` (a height error
of a tenth of the horizontal one at least)."""


def vertical_sources(height: np.ndarray, horizontal: np.ndarray) -> np.ndarray:
    """Which sources act mainly on the height, shape (ns,) of bool.

    A source does when its largest height error is at least :data:`VERTICAL_DOMINANCE`
    times its largest horizontal position error, or when that ratio is at least
    :data:`VERTICAL_SHARE` and stands :data:`VERTICAL_GAP` or more above the ratio of
    every source below it (at the largest gap between the sources' ratios above
    :data:`VERTICAL_SHARE`; a damped
    vertical channel holds a vertical accelerometer's height error to b/k_h2, a quarter
    of the horizontal error it gives, but hundreds of times what the horizontal sources
    give as height).

    Parameters
    ----------
    height, horizontal : numpy.ndarray, shape (ns,)
        Each source's largest height error and largest horizontal position error over
        the operating time, at any common magnitude (the ratio is what counts), m.
    """
    height = np.asarray(height, dtype=float)
    horizontal = np.asarray(horizontal, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(height > 0, height / horizontal, 0.0)
    chosen = (height > 0) & (ratio >= VERTICAL_DOMINANCE)
    ranked = np.sort(ratio[(ratio > 0) & np.isfinite(ratio)])
    gaps = ranked[1:] / ranked[:-1]
    gaps[ranked[1:] < VERTICAL_SHARE] = 0.0     # a split above a tenth only
    if gaps.size and gaps.max() >= VERTICAL_GAP:
        chosen |= ratio >= ranked[int(np.argmax(gaps)) + 1]
    return chosen


def vertical_channel_note(model, allocation: Allocation) -> str | None:
    """One line naming the vertical-channel sources a spec without a ``height_error``
    item allocates only through its other items, or None.

    For a model with a height output, a source that acts mainly on the height
    (:func:`vertical_sources`: its largest 1σ height error over the operating time is
    at least :data:`VERTICAL_DOMINANCE` times its largest horizontal position error, or
    a tenth of it and two decades above the other sources' ratios: a vertical
    accelerometer's bias or scale factor, an initial vertical velocity or height error)
    is bound, when no item reads the height, only by the weak coupling of the height into
    the horizontal channels (the radii and gravity in the transport rates, Coriolis). Its
    allowance is then what those items allow, and true: it is left in the allocation (it
    does disturb them), but it says nothing about the height, which can grow to
    kilometres. The line names those sources, the height error their allowances give
    (at the spec's σ level, its largest over the operating time) and the item that bounds
    it.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    allocation : Allocation

    Returns
    -------
    str or None
        None when the spec has a ``height_error`` item, the model has no height output
        (or no latitude/longitude output and Earth radius to read the horizontal
        position by), no allocated source acts mainly on the height, or the error
        equations grow exponentially over the operating time (:func:`growth_warning`
        says so: the growing mode swamps every source's height error, so the line
        would name nearly all of them, and the damping gains it names are the remedy).
    """
    from dataclasses import replace

    from ins_errors.specs import SpecItem

    budget = allocation.budget
    spec, system = budget.spec, budget.system
    if any(item.name == "height_error" for item in spec.items):
        return None
    outputs = {o.name for o in model.outputs}
    if not {"height", "latitude", "longitude"} <= outputs:
        return None
    if growth_warning(model, budget) is not None:
        return None
    free = [j for j, s in enumerate(budget.sources)
            if s.fixed is None and np.isfinite(allocation.sigma[j])]
    if not free:
        return None
    probe = replace(spec, items=(SpecItem("height_error", 1.0, "", ()),
                                 SpecItem("position_error_absolute", 1.0, "", ())))
    try:
        functionals, groups = item_functionals(model, system, probe)
    except BudgetError:   # no Earth radius to read the position in metres by
        return None
    statistics = [SourceStatistics(budget.sources[j].name, budget.sources[j].statistics,
                                   1.0, budget.sources[j].tau) for j in free]
    unit = propagate(system, statistics, functionals, warn=False).unit_variances    # (nt, 3, nf)
    height = np.sqrt(unit[:, groups["height_error"]].sum(1))            # (nt, nf)
    horizontal = np.sqrt(unit[:, groups["position_error_absolute"]].sum(1))
    vertical = vertical_sources(height.max(0), horizontal.max(0))
    if not vertical.any():
        return None
    chosen = [j for j, v in zip(free, vertical, strict=True) if v]
    # their height error together at their allowances, at its largest
    total = spec.sigma_level * np.sqrt((height[:, vertical] ** 2
                                        * allocation.sigma[chosen] ** 2).sum(1))
    k = int(np.argmax(total))
    names = [budget.sources[j].label for j in chosen]
    one = len(names) == 1
    listed = names[0] if one else f"{', '.join(names[:-1])} and {names[-1]}"
    size = format_quantity(float(total[k]), "m", "km" if total[k] >= 1e3 else "m")
    give = "its allowance gives" if one else "together their allowances give"
    return (f"the spec has no height_error item: {listed} act{'s' if one else ''} mainly "
            f"on the height and {'is' if one else 'are'} allocated only through the other "
            f"items' weak coupling to it ({give} a {spec.sigma_level:g}σ height error of "
            f"{size} at {format_time(float(system.times[k]))}); add [items.height_error] "
            f"to bound {'it' if one else 'them'}")


def _propagate(model, system, spec, statistics) -> Covariance:
    functionals, _ = item_functionals(model, system, spec)
    return propagate(system, statistics, functionals, warn=False)


def _state_functionals(model, system: LinearSystem) -> Functionals:
    """Every error state, in SI units."""
    n, nw = system.E.shape
    return Functionals(tuple(s.name for s in model.error_states),
                       tuple(s.unit for s in model.error_states), np.eye(n),
                       np.zeros((n, nw)))


def typical_state_sizes(model) -> np.ndarray:
    """Typical size of every error state (SI), shape (n,): the matrix check's fixed sizes
    by unit (:func:`ins_errors.checker.typical.typical_magnitude`: 1e-4 rad, 0.1 m/s,
    10 m, ...), 1 for a unit it has none for. They only scale the states for
    :func:`rounding_floors`."""
    from ins_errors.checker.typical import typical_magnitude

    sizes = []
    for state in model.error_states:
        try:
            sizes.append(typical_magnitude(state.unit)[0])
        except InsErrorsError:
            sizes.append(1.0)
    return np.array(sizes)


def rounding_floors(state_variances: np.ndarray, readout: np.ndarray, typical: np.ndarray,
                    size: int, steps: np.ndarray | None = None) -> np.ndarray:
    r"""Rounding floor of the variances of linear functionals of the error state, per source.

    The propagation is a product of k step transitions of the ``size``-square augmented
    system (or, on a static base, powers of one), so the forward error of a propagated
    response is bounded by :math:`\gamma_k = \mathrm{size}\cdot k\cdot\varepsilon` times
    the largest response of the same source in scaled variables (each state over its
    typical size :math:`m_i`), whatever path it takes: entries of F that are zero but
    for their last bits, the exponential's own rounding, the products. A functional
    :math:`y = C x` reads that error as at most :math:`\gamma_k \max_i(\sigma_{ij}/m_i)
    \sum_l |C_l| m_l`, with :math:`\sigma_{ij}` the 1σ of state i from source j. This
    is the matrix check's floor (:func:`ins_errors.checker.matrix.rounding_floor`) with
    the source's own response as the largest one; the typical sizes only set the scale
    of the states against each other (a dependence through round-off lies tens of
    decades below it, a real one many decades above). A variance at or below the
    square of this floor is round-off: the functional does not depend on the source.

    Parameters
    ----------
    state_variances : numpy.ndarray, shape (nt, n, ns)
        Variance of every error state from every source at nt times (unit or actual
        statistics; the floors follow the same ones).
    readout : numpy.ndarray, shape (q, n) or (nt, q, n)
        The functionals' weights on the error state (``C_x``; the weights ``C_b`` on the
        sources' own values are exact and add no propagated rounding).
    typical : numpy.ndarray, shape (n,)
        Typical size of every state, in its SI unit.
    size : int
        Dimension of the propagated system (error states plus sources).
    steps : numpy.ndarray of int, shape (nt,), optional
        Grid steps propagated to each time (default: 0, 1, ..., nt-1, every grid time);
        at least 1 is counted.

    Returns
    -------
    numpy.ndarray, shape (nt, q, ns)
        Floor of each functional's variance from each source, same units as the
        variances of the functionals.
    """
    if steps is None:
        steps = np.arange(state_variances.shape[0])
    steps = np.maximum(np.asarray(steps), 1)
    gamma = size * steps * EPS                                            # (K+1,)
    scaled = np.maximum(state_variances, 0.0) / typical[None, :, None] ** 2
    response = np.sqrt(scaled.max(axis=1))                                # (K+1, ns)
    unit = np.abs(readout) @ typical                                      # (.., q)
    if unit.ndim == 1:
        unit = np.broadcast_to(unit, (len(steps), unit.size))
    return (gamma[:, None, None] * response[:, None, :] * unit[:, :, None]) ** 2


DIAGONAL = "diagonal"
"""The component of a CEP item that is no error of its own: (north + east)/√2, whose
variance gives the covariance of the north and east errors (:func:`item_cep_parts`)."""


def item_cep_parts(item, names: tuple[str, ...], per_source: np.ndarray, index,
                   times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A CEP item's 2×2 covariance at chosen grid times, per source: the variances of the
    north and east errors and their covariance (from the variance d of (north + east)/√2:
    c = d − (north + east)/2), each of shape (len(index), ns), SI² (a rate item's per s²).
    Arguments as :func:`item_lines`."""
    times = np.asarray(times, dtype=float)
    scale = 1.0 / times**2 if item.name in RATE_ITEMS else np.ones_like(times)
    block = per_source[np.asarray(index, dtype=int)] * scale[:, None, None]
    column = {nm.split(":", 1)[1]: k for k, nm in enumerate(names)
              if nm.startswith(f"{item.name}:")}
    north, east = block[:, column["north"]], block[:, column["east"]]
    cross = block[:, column[DIAGONAL]] - 0.5 * (north + east)
    # |c| <= sqrt(north east): rounding of the difference kept within the ellipse
    bound = np.sqrt(np.maximum(north, 0.0) * np.maximum(east, 0.0))
    return north, east, np.clip(cross, -bound, bound)


def row_values(rows, sigma_level: float, contributions: np.ndarray,
               north: np.ndarray | None = None,
               cross: np.ndarray | None = None) -> np.ndarray:
    """Every row's value from its sources' contributions, SI, shape (nr,).

    An rss row (or a component's) is k · √(Σ contributions); a CEP row (:attr:`Row.cep`)
    is the CEP of the sum of the sources' 2×2 covariances
    (:func:`~ins_errors.analysis.budget_cep.cep`), whatever k.

    Parameters
    ----------
    rows : sequence of Row
    sigma_level : float
        k.
    contributions : numpy.ndarray, shape (nr, ns)
        Variance of every row from every source (a CEP row's: north + east), SI².
    north, cross : numpy.ndarray, shape (nr, ns), optional
        Of the CEP rows, the north variance and the north-east covariance from every
        source (needed where a row is a CEP row).
    """
    total = contributions.sum(1)
    values = sigma_level * np.sqrt(total)
    chosen = np.array([r.cep for r in rows], dtype=bool)
    if chosen.any():
        n = north[chosen].sum(1)
        values[chosen] = cep(n, total[chosen] - n, cross[chosen].sum(1))
    return values


def item_lines(item, names: tuple[str, ...], per_source: np.ndarray, index,
               times: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """One spec item's variances at chosen grid times, per source: what its rows read.

    A rate item (:data:`RATE_ITEMS`) is divided by t; the components are summed
    (``combine = "rss"``, one line with component ``""``; ``"cep"`` too, the north +
    east variance that :func:`item_cep_parts` splits) or kept apart (``"each"``).

    Parameters
    ----------
    item : ins_errors.specs.SpecItem
    names : tuple of str
        ``"item:component"`` of every functional of ``per_source``.
    per_source : numpy.ndarray, shape (nt, q, ns)
        Variance of every functional at every grid time from every source, SI².
    index : sequence of int
        Grid times to read (indices into the first axis), each with its time in
        ``times``, s (> 0 for a rate item).
    times : numpy.ndarray, shape (len(index),)

    Returns
    -------
    list of (str, numpy.ndarray of shape (len(index), ns))
        Component (``""`` for rss) and the variances, SI² (a rate item's per s²).
    """
    columns = [k for k, nm in enumerate(names) if nm.startswith(f"{item.name}:")
               and nm != f"{item.name}:{DIAGONAL}"]
    times = np.asarray(times, dtype=float)
    scale = 1.0 / times**2 if item.name in RATE_ITEMS else np.ones_like(times)
    block = per_source[np.asarray(index, dtype=int)][:, columns] * scale[:, None, None]
    if item.combine in ("rss", "cep"):
        return [("", block.sum(1))]
    return [(names[col].split(":", 1)[1], block[:, c]) for c, col in enumerate(columns)]


def _rows(spec: Spec, system: LinearSystem, covariance: Covariance,
          per_source: np.ndarray) -> tuple[list[Row], np.ndarray]:
    """Rows of the spec and their variances from the functionals' variances.

    ``per_source`` has shape (nt, q, ns); returns rows and an array (nr, ns).
    """
    rows, values, _ = _cep_rows(spec, system, covariance, per_source)
    return rows, values


def _cep_rows(spec: Spec, system: LinearSystem, covariance: Covariance,
              per_source: np.ndarray) -> tuple[list[Row], np.ndarray,
                                               tuple[np.ndarray, np.ndarray] | None]:
    """:func:`_rows`, and of the CEP rows the north variances and north-east covariances
    ((nr, ns) each, 0 on the other rows; None without a CEP item)."""
    rows, values, norths, crosses = [], [], [], []
    for item in spec.items:
        index = []
        for t in item.times:
            k = round(t / system.step)
            if k >= len(covariance.times) or abs(covariance.times[k] - t) > 1e-6 * system.step:
                raise SpecError(f"{spec_label(spec)}: items.{item.name}: check time "
                                f"{t:g} s is outside the analysed run")
            index.append(k)
        lines = item_lines(item, covariance.names, per_source, index, np.array(item.times))
        ns = per_source.shape[-1]
        north = cross = np.zeros((len(index), ns))
        if item.combine == "cep":
            north, _, cross = item_cep_parts(item, covariance.names, per_source, index,
                                             np.array(item.times))
        for i, t in enumerate(item.times):
            for component, variances in lines:
                rows.append(Row(item.name, t, component, item.value,
                                item.combine == "cep"))
                values.append(variances[i])
                norths.append(north[i])
                crosses.append(cross[i])
    parts = ((np.array(norths), np.array(crosses))
             if any(item.combine == "cep" for item in spec.items) else None)
    return rows, np.array(values), parts


# --------------------------------------------------------------------------------------
# Allocation
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Allocation:
    """Allowed magnitudes of the sources.

    Attributes
    ----------
    budget : UnitBudget
    sigma : numpy.ndarray, shape (ns,)
        Allowed 1σ of every source, SI (inf: no spec row depends on the source).
    binding : numpy.ndarray of int, shape (ns,)
        Row that binds each free source (-1 for fixed or unconstrained sources).
    fill_factor : float
        Common variance factor applied by ``fill`` (1 without it).
    beyond_linear : numpy.ndarray of bool, shape (ns,), optional
        Sources left unconstrained because their share lies beyond the linear model
        (:data:`LINEAR_LIMITS`): not limited by this spec. None: none.
    """

    budget: UnitBudget
    sigma: np.ndarray
    binding: np.ndarray
    fill_factor: float
    beyond_linear: np.ndarray | None = None

    @property
    def levels(self) -> np.ndarray:
        """σ level of every source's magnitude (:attr:`BudgetSource.sigma_level`: the
        spec's, a source's own, 1 for a white-noise density), shape (ns,)."""
        return np.array([s.sigma_level for s in self.budget.sources])

    @property
    def magnitudes(self) -> np.ndarray:
        """Allowed magnitudes at each source's σ level (:attr:`levels`; the spec's k σ
        unless the source says otherwise, a white-noise density as it is), SI."""
        return self.sigma * self.levels

    def contributions(self) -> np.ndarray:
        """Variance of every row from every source at the allocated σ, (nr, ns)."""
        sigma = np.where(np.isfinite(self.sigma), self.sigma, 0.0)
        return self.budget.unit_variances * sigma**2

    @property
    def values(self) -> np.ndarray:
        """Every row's value at the allocated magnitudes, SI, shape (nr,): k times the
        rss, or a CEP row's CEP (:meth:`UnitBudget.row_values`)."""
        return self.budget.row_values(self.sigma)

    def shares(self) -> np.ndarray:
        """Share of every row's allowed variance each source takes, (nr, ns): its
        contribution over (limit / k)², so that a row's shares sum to (value / limit)².

        A CEP row's allowed variance is that of its error ellipse's shape at these
        magnitudes, (limit / κ)² with κ = CEP / DRMS of the row's total (0.8326 for a
        circular error, down to 0.6745 for one along a line): each source's share of
        north + east variance, and the shares again sum to (CEP / limit)².
        """
        contributions = self.contributions()
        allowed = self.budget.allowed_variances
        chosen = self.budget.cep_rows
        if chosen.any():
            total = contributions.sum(1)[chosen]
            values = self.values[chosen]
            with np.errstate(divide="ignore", invalid="ignore"):
                kappa = np.where(total > 0, values / np.sqrt(total), CEP_PER_DRMS_CIRCLE)
            allowed = allowed.copy()
            allowed[chosen] = (np.array([r.limit for r in self.budget.rows])[chosen]
                               / kappa) ** 2
        return contributions / allowed[:, None]

    def binding_row(self, j: int) -> Row | None:
        """The row binding source j, or None."""
        return None if self.binding[j] < 0 else self.budget.rows[self.binding[j]]


def allocate(budget: UnitBudget) -> Allocation:
    """Apply the allocation rule of the module docstring.

    A CEP row (:attr:`Row.cep`) is shared as a variance too: its sources share the
    north + east variance (DRMS²) whose circular error has the limit as its CEP,
    :attr:`UnitBudget.allowed_variances`, which meets the CEP whatever the shape of the
    error ellipse (the CEP is at most 0.8326 DRMS); with fixed sources, what they leave
    is the larger of that variance less theirs and the variance T of a circular error
    with CEP(P_fixed + T I) at the limit (P_free ≤ trace(P_free) I, and the CEP grows
    with the covariance). ``fill`` scales the free sources until the tightest row is met
    exactly, a CEP row by its CEP.

    Raises
    ------
    BudgetError
        If a row's limit itself lies beyond the linear error model's range
        (:func:`limits_beyond_linear`), or every source the spec sees would meet it only
        beyond that range.
    SpecExceededError
        If the fixed sources alone use up a spec row.
    """
    beyond_range = limits_beyond_linear(budget)
    if beyond_range is not None:
        raise BudgetError(beyond_range)
    V, allowed = budget.unit_variances, budget.allowed_variances
    depends = budget.depends
    fixed = np.array([s.fixed is not None for s in budget.sources])
    sigma = np.array([s.fixed if s.fixed is not None else np.nan for s in budget.sources])
    used = (V[:, fixed] * sigma[fixed] ** 2).sum(1) if fixed.any() else np.zeros(len(allowed))
    remaining = allowed - used
    cep_rows = budget.cep_rows
    fixed_sigma = np.where(fixed, sigma, 0.0)
    if cep_rows.any():
        remaining[cep_rows] = _cep_remaining(budget, fixed_sigma)[cep_rows]
    bad = np.flatnonzero(remaining <= 0)
    if bad.size:
        values = np.sqrt(used) * budget.spec.sigma_level
        if cep_rows.any():
            values[cep_rows] = budget.row_values(fixed_sigma)[cep_rows]
        row = budget.rows[bad[0]]
        si, shown = ITEM_SI[row.item], ITEM_DISPLAY[row.item]
        raise SpecExceededError(f"the fixed sources alone use up {row.label} "
                           f"({display(values[bad[0]], si, shown)} against the limit "
                           f"{display(row.limit, si, shown)})", budget,
                           values, remaining <= 0)
    binding = np.full(len(budget.sources), -1)
    fill_factor = 1.0
    excluded = np.zeros(len(budget.sources), dtype=bool)
    beyond = np.zeros(len(budget.sources), dtype=bool)
    linear = budget.linear_limits
    while True:
        free = np.flatnonzero(~fixed & ~excluded)
        if not free.size:
            break
        weights = np.array([budget.sources[j].weight for j in free])
        share = weights / weights.sum()
        with np.errstate(divide="ignore"):
            ratio = share[None, :] * remaining[:, None] / V[:, free]          # (nr, nf)
        ratio[~depends[:, free]] = np.inf   # no dependence, or only through round-off
        best = np.argmin(ratio, axis=0)
        sigma[free] = np.sqrt(ratio[best, np.arange(free.size)])
        binding[free] = best
        unseen = ~np.isfinite(sigma[free])
        nonlinear = ~unseen & (sigma[free] > linear[free])
        if not (unseen.any() or nonlinear.any()):
            break
        # not limited by this spec (on this motion, or within the linear model): no
        # share, the others' shares are divided again
        loose = free[unseen | nonlinear]
        beyond[free[nonlinear]] = True
        excluded[loose] = True
        sigma[loose], binding[loose] = np.inf, -1
    if beyond.any() and not (binding >= 0).any():
        raise _beyond_at_every_size(budget, beyond)
    if budget.spec.fill and free.size:
        totals = (V[:, free] * sigma[free] ** 2).sum(1)
        with np.errstate(divide="ignore"):
            factors = np.where(totals > 0, remaining / totals, np.inf)
        if cep_rows.any():
            factors[cep_rows] = _cep_fill(budget, fixed_sigma, np.where(
                fixed, 0.0, np.where(np.isfinite(sigma), sigma, 0.0)))[cep_rows]
        fill_factor = float(np.min(factors))
        sigma[free] *= np.sqrt(fill_factor)
    return Allocation(budget, sigma, binding, fill_factor, beyond)


_CEP_HALVINGS = 60
"""Bisection steps of the CEP rows' remaining variance and fill factor (to the last
bit of a bracket that starts within a factor of a few)."""


def _largest_within(limits: np.ndarray, value, high: np.ndarray) -> np.ndarray:
    """For every row, the largest x in [0, high] with value(x) <= limit (value increasing
    in x, elementwise over the rows), from below: the bisection's lower end."""
    low = np.zeros_like(high)
    for _ in range(_CEP_HALVINGS):
        middle = 0.5 * (low + high)
        inside = value(middle) <= limits
        low, high = np.where(inside, middle, low), np.where(inside, high, middle)
    return low


def _cep_remaining(budget: UnitBudget, fixed_sigma: np.ndarray) -> np.ndarray:
    """The north + east variance the free sources may share at every CEP row (others:
    0), given the fixed sources' 1σ (0 for the free ones): the larger of the circular
    bound less the fixed variance and the variance T with CEP(P_fixed + T I) at the
    limit (:func:`allocate`); 0 where the fixed sources' CEP reaches the limit."""
    chosen = budget.cep_rows
    out = np.zeros(len(budget.rows))
    limits = np.array([r.limit for r in budget.rows])[chosen]
    total = (budget.unit_variances * fixed_sigma**2).sum(1)[chosen]
    north = (budget.north * fixed_sigma**2).sum(1)[chosen]
    cross = (budget.cross * fixed_sigma**2).sum(1)[chosen]
    east = total - north
    circular = budget.allowed_variances[chosen] - total
    top = (limits / CEP_PER_SIGMA_CIRCLE) ** 2       # CEP(P + top I) >= CEP(top I) = limit
    around = _largest_within(limits, lambda t: cep(north + t, east + t, cross), top)
    fixed_cep = cep(north, east, cross)
    out[chosen] = np.where(fixed_cep >= limits, 0.0, np.maximum(circular, around))
    return out


def _cep_fill(budget: UnitBudget, fixed_sigma: np.ndarray,
              free_sigma: np.ndarray) -> np.ndarray:
    """The factor f on the free sources' variances that brings every CEP row's CEP to
    its limit, CEP(P_fixed + f P_free) = limit (others: inf; inf where the free sources
    do not reach the row)."""
    chosen = budget.cep_rows
    out = np.full(len(budget.rows), np.inf)
    limits = np.array([r.limit for r in budget.rows])[chosen]

    def parts(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        total = (budget.unit_variances * s**2).sum(1)[chosen]
        north = (budget.north * s**2).sum(1)[chosen]
        return north, total - north, (budget.cross * s**2).sum(1)[chosen]

    fn, fe, fc = parts(fixed_sigma)
    vn, ve, vc = parts(free_sigma)
    free_cep = cep(vn, ve, vc)
    reached = free_cep > 0
    with np.errstate(divide="ignore"):
        top = np.where(reached, (limits / np.where(reached, free_cep, 1.0)) ** 2, 0.0)
    found = _largest_within(limits, lambda f: cep(fn + f * vn, fe + f * ve, fc + f * vc),
                            top)
    out[chosen] = np.where(reached, found, np.inf)
    return out


def limits_beyond_linear(budget: UnitBudget) -> str | None:
    """Why a spec whose limit itself lies beyond the linear error model's range cannot
    be sized, one line, or None.

    A row whose limit, at the spec's σ level, is beyond :data:`LINEAR_LIMITS` (a rate
    item's by the error it is the rate of, limit × t; a CEP row's by the DRMS its
    sharing allows, k · limit / 0.8326) allows errors the linear equations do not
    describe: whatever they allocate, they cannot say whether the spec is met there
    (1000 nmi at 1 h: every source at its share drove the longitude past 0.1 rad, and
    400 nmi was "met" at 741 km, beyond 637 km). Only rows that size a free source (it
    depends on them, :attr:`UnitBudget.depends`) count: the fixed sources alone against
    a loose limit are a verdict the linear equations give (with a warning where their
    figure leaves the range, :func:`linear_range_warning`). The line names the row with the
    largest such limit against the range, and the largest limit the linear model can
    size there, in the unit the spec wrote the limit in.
    """
    from ins_errors.analysis.budget_report import written_unit

    k = budget.spec.sigma_level
    free = np.array([s.fixed is None for s in budget.sources], dtype=bool)
    sizing = (budget.depends[:, free].any(1) if free.any()
              else np.zeros(len(budget.rows), dtype=bool))
    worst = None
    for row, sizes in zip(budget.rows, sizing, strict=True):
        if not sizes:   # no free source to size by it: the fixed ones' verdict stands
            continue
        unit = ITEM_SI[row.item]
        per = row.time if row.item in RATE_ITEMS else 1.0
        unit = {"m/s": "m", "rad/s": "rad"}[unit] if row.item in RATE_ITEMS else unit
        limit = LINEAR_LIMITS.get(unit)
        if limit is None:
            continue
        size = row.limit * per * (k / CEP_PER_DRMS_CIRCLE if row.cep else 1.0)
        if size > limit * (1 + 1e-12) and (worst is None or size / limit > worst[0]):
            worst = (size / limit, row, size, unit, limit, per)
    if worst is None:
        return None
    _, row, size, unit, limit, per = worst
    item = budget.spec.item(row.item)
    shown = written_unit(item)
    largest = row.limit * limit / size
    kind = "CEP " if row.cep else ""
    reading = (f"a {k:g}σ DRMS of {_size_text(size, unit)} shared, the CEP / 0.8326"
               if row.cep else f"its error {_size_text(size, unit)} at {k:g}σ"
               if row.item in RATE_ITEMS else f"{_size_text(size, unit)} at {k:g}σ")
    return (f"{spec_label(budget.spec)}: items.{row.item} = {item.text!r} at "
            f"{format_time(row.time)} ({reading}) is beyond the linear error model's range "
            f"({_size_text(limit, unit)} = {LIMIT_NAMES[unit]}"
            f"): the budget's linear error equations cannot say what meets it; the largest "
            f"{kind}limit they can size there is {display(largest, item.kind.unit, shown)}"
            f"{'' if per == 1.0 else ' (a rate over ' + format_time(row.time) + ')'}")


def _size_text(value: float, unit: str) -> str:
    """An error's size against the linear range, as the budget's lines write it: a
    length in km, an angle in deg, a speed in m/s."""
    return format_quantity(value, unit, {"m": "km", "rad": "deg"}.get(unit, unit))


GROWTH_REFUSED = 0.5 * float(np.log(1.0 / EPS))
"""E-foldings (18.0: a factor 1/√ε = 6.7e7) of a growing mode over the operating time
beyond which a budget is refused (:func:`growth_refusal`): the variances the allocation
divides then grow by more than 1/ε = 4.5e15, the whole precision of a double, so what a
source does on the stable part of the equations is below the rounding of its own
variance and the allowances are set by the growing mode alone (strapdown_ned undamped
over 8 h, 50 e-foldings: a gyro bias of 1e-19 deg/h)."""


def _growth_factor(folds: float) -> str:
    """The factor e^folds as text (``"8.82e+21"``; ``"e^900"`` beyond a double)."""
    return f"{np.exp(folds):.3g}" if folds < 700.0 else f"e^{folds:.0f}"


def growth_refusal(allocation: Allocation) -> str | None:
    """Why an allocation made absurdly small by a growing mode is no budget, one line,
    or None.

    When the error equations grow over the operating time by more than
    :data:`GROWTH_REFUSED` e-foldings (:func:`growth_folds`) and the allocation gives
    some source a magnitude, that magnitude is what the growth leaves, no instrument's:
    the line names the growth, an allowance as example, the damping gains left at zero
    (:func:`~ins_errors.numeric.linear_system.undamped_remedy`) and the longest
    operating time the budget takes with that growth. A spec the fixed sources alone
    decide (nothing allocated) is not refused: its verdict is the propagation's.
    """
    from ins_errors.numeric.linear_system import undamped_remedy
    from ins_errors.time_text import duration_text

    budget = allocation.budget
    allocated = [j for j, s in enumerate(budget.sources)
                 if s.fixed is None and np.isfinite(allocation.sigma[j])]
    found = growth_folds(budget.system, budget.spec.operating_time)
    if not allocated or found is None or found[1] <= GROWTH_REFUSED:
        return None
    rate, folds = found
    if not budget.system.time_invariant:  # the rate the e-foldings were counted at
        rate = folds / budget.spec.operating_time
    j = allocated[0]
    source = budget.sources[j]
    factor = _growth_factor(folds)
    remedy = ("" if budget.model is None
              else undamped_remedy(budget.model, budget.system.p).lstrip("; "))
    longest = budget.spec.operating_time * GROWTH_REFUSED / folds
    cure = (f"{remedy}, or shorten the operating time" if remedy
            else "damp the growing mode, or shorten the operating time")
    return (f"the linear error model cannot size this spec: its error equations grow "
            f"×e every {duration_text(1.0 / rate)}, ×{factor} over the "
            f"{format_time(budget.spec.operating_time)} operating time, beyond "
            f"{np.exp(GROWTH_REFUSED):.2g} (1/√ε: the variances the budget divides grow "
            f"past the precision of the arithmetic), so the allowances are only what "
            f"that growth leaves, no instrument's (e.g. {source.label} "
            f"{display(allocation.magnitudes[j], source.unit, source.display_unit)}); "
            f"{cure} to at most {format_time(_whole_minutes(longest))} "
            f"({GROWTH_REFUSED:.0f} e-foldings of {duration_text(1.0 / rate)})")


def _whole_minutes(seconds: float) -> float:
    """``seconds`` rounded down to a whole minute; under a minute, to a whole second
    (never rounded up past ``seconds``)."""
    if seconds < 60.0:
        return max(1.0, float(np.floor(seconds)))
    return 60.0 * np.floor(seconds / 60.0)


def _beyond_at_every_size(budget: UnitBudget, beyond: np.ndarray) -> BudgetError:
    """The refusal of a spec every source it sees would meet only beyond the linear error
    model: "not limited by this spec" for all of them would read as a spec met by
    anything. With a growing mode over the operating time (:func:`growth_folds`: an
    undamped vertical channel over hours, where any source drives the height past 0.1 R
    long before the spec's items see it) the line names it and the damping gains; without
    one, the sources' errors of another quantity than the items' (a longitude at a high
    latitude, of a position item within 0.1 R) outrun the linear range at their shares,
    and the line says to tighten the items."""
    from ins_errors.numeric.linear_system import undamped_remedy
    from ins_errors.time_text import duration_text

    causes: dict[tuple[str, str], list[int]] = {}
    for j in np.flatnonzero(beyond):
        causes.setdefault(budget.linear_limit_cause(int(j)), []).append(int(j))
    (state, unit), sources = max(causes.items(), key=lambda item: len(item[1]))
    example = budget.sources[sources[0]]
    limit = budget.linear_limits[sources[0]] * budget.spec.sigma_level
    where = (f"{len(sources)} of them drive {state} beyond "
             f"{LIMIT_NAMES.get(unit, 'its linear limit')} first"
             if state != "its own value" else f"{len(sources)} of them are themselves "
             "beyond the linear range")
    growth = growth_folds(budget.system, budget.spec.operating_time)
    if growth is not None:
        rate, folds = growth
        factor = _growth_factor(folds)
        remedy = ("" if budget.model is None
                  else undamped_remedy(budget.model, budget.system.p))
        cause = (f"its error equations grow ×e every {duration_text(1.0 / rate)} (×{factor} "
                 f"over the operating time), which does this: damp the growing mode or "
                 f"shorten the operating time{remedy}")
    else:
        cause = ("nothing in its error equations grows: the spec's limits are loose enough "
                 f"that its sources' shares leave the linear range in {state} before its "
                 f"items reach their limits: tighten them")
    return BudgetError(
        f"the linear error model cannot size this spec: every source it sees would meet it "
        f"only at sizes beyond the model's range ({where}, e.g. {example.name} within it "
        f"only up to {display(limit, example.unit, example.display_unit)} over the "
        f"operating time); {cause}")


# --------------------------------------------------------------------------------------
# Evaluation at given magnitudes (recomputed from scratch)
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Evaluation:
    """Spec rows evaluated at given source magnitudes.

    Attributes
    ----------
    rows : tuple of Row
    sources : tuple of str
    contributions : numpy.ndarray, shape (nr, ns)
        Variance of each row from each source (SI²; a CEP row's: north + east).
    sigma_level : float
    north, cross : numpy.ndarray, shape (nr, ns), optional
        Of the CEP rows, the north variance and the north-east covariance from each
        source; None without a CEP item.
    """

    rows: tuple[Row, ...]
    sources: tuple[str, ...]
    contributions: np.ndarray
    sigma_level: float
    north: np.ndarray | None = None
    cross: np.ndarray | None = None

    @property
    def values(self) -> np.ndarray:
        """Each row's error at the spec's σ level (k·sqrt(total variance); a CEP row's
        CEP, :func:`row_values`), SI."""
        return row_values(self.rows, self.sigma_level, self.contributions, self.north,
                          self.cross)

    @property
    def ratios(self) -> np.ndarray:
        """Value / limit of each row (≤ 1: met)."""
        return self.values / np.array([r.limit for r in self.rows])


def evaluate(model, spec: Spec, sigma: dict[str, float], trajectory=None,
             p: np.ndarray | None = None) -> Evaluation:
    """Propagate the given 1σ magnitudes (SI) and evaluate every spec row.

    The covariance is propagated again at the actual magnitudes, so this checks the
    allocation arithmetic (shares, binding items, fill). It uses the same propagation as
    the allocation: for an independent check of the covariance itself compare with the
    Monte Carlo runs (:mod:`ins_errors.analysis.monte_carlo`). ``model`` and ``p``
    (model parameters, SI) as in :func:`unit_budget`; ``sigma`` numbers in each source's
    SI unit (text such as ``"0.01 deg/h"`` is refused: convert it with
    :func:`ins_errors.units.parse_quantity`), keyed by source name, or by
    :attr:`BudgetSource.label` (``"gyro_bias_x (white)"``) for each part of a source
    with two.
    """
    model = load_model(model)
    check_items(model, spec)
    sources = resolve_sources(model, spec)
    known = {s.label for s in sources} | {s.name for s in sources if not s.paired}
    for name in sigma:
        if name not in known:
            raise unknown_name("budget source", name, sorted(known))
    system = spec_system(model, spec, trajectory, p)
    stats = [SourceStatistics(s.name, s.statistics,
                              sigma.get(s.label, 0.0 if s.paired else sigma.get(s.name, 0.0)),
                              s.tau) for s in sources]
    covariance = _propagate(model, system, spec, stats)
    rows, contributions, parts = _cep_rows(spec, system, covariance,
                                           covariance.contributions)
    return Evaluation(tuple(rows), tuple(s.label for s in sources), contributions,
                      spec.sigma_level, *(parts or (None, None)))


# --------------------------------------------------------------------------------------
# Units of the items in reports
# --------------------------------------------------------------------------------------
ITEM_DISPLAY = {"position_error": "km/h", "position_error_absolute": "m",
                "height_error": "m", "ground_speed_error": "m/s", "vertical_error": "deg",
                "heading_error": "deg", "heading_drift": "deg/h"}
ITEM_SI = {name: kind.unit for name, kind in ITEM_KINDS.items()}
"""SI unit of each item's value (the spec's own table, :data:`ins_errors.specs.ITEM_KINDS`)."""


def display(value: float, unit: str, display_unit: str) -> str:
    """An SI value in an engineering unit (``inf`` for unconstrained)."""
    if not np.isfinite(value):
        return "unconstrained"
    return format_quantity(value, unit, display_unit)


# --------------------------------------------------------------------------------------
# Spec rows from direct runs
# --------------------------------------------------------------------------------------
def direct_rows(model, budget: UnitBudget, errors) -> tuple[list[Row], np.ndarray]:
    """Sample values (k · RMS) of the spec rows from direct runs.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    budget : UnitBudget
        Gives the rows and the radii along the motion.
    errors : ins_errors.analysis.monte_carlo.DirectErrors
        Direct errors recorded on a grid that contains the check times.

    Returns
    -------
    rows : list of Row
        The rows whose time lies within the runs.
    values : numpy.ndarray, shape (len(rows),)
        k · sample RMS (rss rows: k · sqrt of the mean sum of squares), SI; a CEP row's
        CEP of the runs' mean north², east² and north·east (the normal CEP of their
        second moments, as the covariance's, whose sampling error is a standard
        deviation's, not a sample median's).
    """
    spec, system = budget.spec, budget.system
    _, R_N, R_E_cos = _radii(model, system)
    rows, values = [], []
    for row in budget.rows:
        if row.time > errors.times[-1] * (1 + 1e-12):
            continue
        k = int(np.argmin(np.abs(errors.times - row.time)))
        if abs(errors.times[k] - row.time) > 1e-6:
            raise BudgetError(f"direct runs were not recorded at {row.label}")
        ks = round(row.time / system.step)
        if row.item in POSITION_ITEMS:
            per = row.time if row.item in RATE_ITEMS else 1.0
            parts = {"north": R_N[ks] * errors["delta_latitude"][k] / per,
                     "east": R_E_cos[ks] * errors["delta_longitude"][k] / per}
        elif row.item == "height_error":
            parts = {"height": errors["delta_height"][k]}
        elif row.item == "ground_speed_error":
            parts = {"north": errors["delta_v_N"][k], "east": errors["delta_v_E"][k]}
        elif row.item == "vertical_error":
            first, second, _ = attitude_quantities(model)
            parts = {attitude_label(model, first): errors[first][k],
                     attitude_label(model, second): errors[second][k]}
        elif row.item == "heading_error":
            parts = {"azimuth": errors[attitude_quantities(model)[2]][k]}
        else:
            azimuth = attitude_quantities(model)[2]
            parts = {"azimuth": (errors[azimuth][k] - errors[azimuth][0]) / row.time}
        rows.append(row)
        if row.cep:   # the CEP of the runs' second moments, as the covariance's
            north, east = parts["north"], parts["east"]
            values.append(float(cep(np.mean(north**2), np.mean(east**2),
                                    np.mean(north * east))))
            continue
        chosen = [parts[row.component]] if row.component else list(parts.values())
        mean_square = np.mean(sum(c**2 for c in chosen))
        values.append(spec.sigma_level * np.sqrt(mean_square))
    return rows, np.array(values)


def integration_errors(model, budget: UnitBudget, runs, other, factor: float,
                       method: str = "euler") -> tuple[list[Row], np.ndarray]:
    """Relative integration error of the sample values of the spec rows (Richardson).

    The same draws run at the step τ of the Monte Carlo and at ``factor`` τ (2, or ½
    when 2τ does not divide the recording interval) give, per draw and recorded sample,
    the extrapolated error ``y* = y_h + (y_h − y_2h) / (2^p − 1)`` (h the finer step, p
    the scheme's order: 1 for the rectangle method), as compare's estimate by step
    doubling does. Each row's sample value (:func:`direct_rows`) from the runs at τ is
    compared with the same value from ``y*``: their relative difference is the bias the
    scheme adds to that row, with the sampling noise of the draws cancelling (the same
    draws on both sides).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    budget : UnitBudget
    runs : ins_errors.analysis.monte_carlo.DirectErrors
        The draws at the Monte Carlo's step τ.
    other : ins_errors.analysis.monte_carlo.DirectErrors
        The same draws at ``factor`` τ, recorded at the same times.
    factor : {2, 0.5}
    method : {"euler", "rk4"}

    Returns
    -------
    rows : list of Row
        The rows within the runs.
    relative : numpy.ndarray, shape (len(rows),)
        (value at τ − extrapolated value) / extrapolated value; NaN where the
        extrapolated value is 0 (a row nothing reaches, e.g. the tilts at t = 0 without
        initial tilts).
    """
    from dataclasses import replace as copy

    from ins_errors.numeric.accuracy import richardson

    if factor not in (2, 0.5):
        raise BudgetError(f"the second runs must be at 2 or 0.5 times the step, got {factor}")
    if runs.values.shape != other.values.shape or not np.allclose(runs.times, other.times):
        raise BudgetError("the runs at the two steps must record the same draws at the "
                          "same times")
    finer, coarser = (runs, other) if factor == 2 else (other, runs)
    extrapolated = copy(runs, values=finer.values + richardson(finer.values, coarser.values,
                                                               method))
    rows, values = direct_rows(model, budget, runs)
    _, best = direct_rows(model, budget, extrapolated)
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(best > 0, (values - best) / best, np.nan)
    return rows, relative
