"""The error-propagation experiment of source 001 (north-pointing INS, static base).

For each error source of the report (gyro drifts, accelerometer biases, initial velocity,
position and attitude errors) at the report's magnitudes, three curves over 24 h:

* **analytic**: the closed-form responses derived symbolically
  (``generated/north_pointing/closed_forms.py``), full model and the report's reduced
  model (Foucault cross-couplings dropped);
* **linear numeric**: the first-order error equations integrated (RK4);
* **direct numeric**: the nonlinear ideal- and real-work equations integrated side by
  side (RK4, same step) and subtracted.

The direct and linear runs estimate their own integration error by step doubling, with
the machinery of ``compare`` (:func:`ins_errors.numeric.compare.add_integration_errors`):
the estimate is printed beside the direct-vs-linear agreement, and a source whose
estimate exceeds 10 % of the direct-vs-linear difference or 1 % of the error gets a
warning naming a step that would do.

The agreement figures (largest difference over the run relative to the largest value
of the linear curve, per error quantity) go into a Markdown summary, with a key to the
report's symbols (dVx, dVy, dL, dN, Qx, Qy, Qz: dN is the longitude error), and every
source gets a PNG of its seven error quantities. The orthodromic day run (source 000,
task 4) writes its summary and one PNG of the error states per excited factor likewise
(:func:`write_day_report`).

The reduced model is judged against the full one quantity by quantity
(:meth:`SourceCurves.reduced_vs_full`): the difference relative to the quantity's size
in the full model, a difference at rounding level counting as zero, and the quantities
the reduced model does not have at all (it leaves them at zero) named apart instead of
counted as 100 % differences.

The Foucault-split Schuler periods are labelled by size in either hemisphere
(:meth:`~ins_errors.numeric.closed_forms.ClosedForms.periods`): "Schuler − Foucault" is
always the longer period 2π/(ω̄ − Ω|sin φ|), "Schuler + Foucault" the shorter
2π/(ω̄ + Ω|sin φ|).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ins_errors.errors import DomainError
from ins_errors.models.earth import (
    EARTH_RATE,
    MEAN_RADIUS,
    WGS84_EQUATORIAL_GRAVITY,
    WGS84_SOMIGLIANA_K,
)
from ins_errors.numeric.accuracy import ORDERS
from ins_errors.numeric.closed_forms import SPLIT_MODES, closed_forms
from ins_errors.numeric.compare import (
    Comparison,
    add_integration_errors,
    comparisons_of,
    metrics_of,
)
from ins_errors.numeric.envelope import column_envelopes
from ins_errors.numeric.integrators import step_count
from ins_errors.numeric.model import Model, load_model
from ins_errors.numeric.simulate import ErrorCurves, simulate
from ins_errors.numeric.trajectories import Trajectory
from ins_errors.output import OutputFolder
from ins_errors.units import STANDARD_GRAVITY, registry

MODEL = "north_pointing"

_SCHEMES = {"rk4": "RK4", "euler": "rectangle-method"}

QUANTITIES: tuple[tuple[str, str, str, str], ...] = (
    # (error state, report name, display unit, label)
    ("delta_v_E", "dVx", "m/s", "east velocity error"),
    ("delta_v_N", "dVy", "m/s", "north velocity error"),
    ("delta_latitude", "dL", "arcmin", "latitude error"),
    ("delta_longitude", "dN", "arcmin", "longitude error"),
    ("alpha_E", "Qx", "arcsec", "platform error angle about east"),
    ("alpha_N", "Qy", "arcsec", "platform error angle about north"),
    ("alpha_U", "Qz", "arcmin", "platform azimuth error (about up)"),
)
"""Error quantities in the report's order, with the units they are plotted in."""

ROUNDING_FLOOR = 1e-12
"""Rounding level of the closed forms, as a fraction of a source's largest error quantity
(velocities taken as the equivalent angle δv/√(gR), angles in rad): a value or a
difference below it is zero. Closed-form round-off is ~1e-17 of that size; the smallest
real quantity of the experiment ~1e-3 of it."""


@dataclass(frozen=True)
class ReducedComparison:
    """The report's reduced closed forms against the full ones, for one source.

    Attributes
    ----------
    relative : numpy.ndarray, shape (7,)
        Per quantity of :data:`QUANTITIES` that both models have: max over the run of
        |reduced − full| / max |full|, exactly 0 where the difference is at rounding
        level (:data:`ROUNDING_FLOOR`); NaN for a quantity one of them does not have.
    lacking : tuple of str
        Report names (dVx, …) of the quantities the full model has and the reduced model
        leaves at zero: the dropped Foucault terms are their only path from the source.
    extra : tuple of str
        Report names of quantities only the reduced model has (none for the report's
        reduced model; listed rather than divided by zero).
    """

    relative: np.ndarray
    lacking: tuple[str, ...]
    extra: tuple[str, ...]

    def worst(self) -> float:
        """Largest :attr:`relative` (NaN when the models share no quantity)."""
        return finite_max(self.relative)

    def worst_quantity(self) -> str | None:
        """Report name of the quantity of :meth:`worst` (None with no difference)."""
        if not np.any(self.relative > 0):
            return None
        return QUANTITIES[int(np.nanargmax(self.relative))][1]


def finite_max(values: np.ndarray) -> float:
    """Largest finite value, NaN when there is none (no all-NaN warning)."""
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    return float(finite.max()) if finite.size else float("nan")


MAGNITUDES = ("gyro_drift", "accel_bias", "velocity_error", "position_error", "level_error",
              "azimuth_error")
"""The magnitude fields of :class:`Experiment` (each must be non-zero)."""


@dataclass(frozen=True)
class Experiment:
    """The report's experiment (001, part II); SI units, radians.

    Attributes
    ----------
    latitude : float
        Local latitude (the scrape shows only "…9°"; 39° per NOTES.md).
    gyro_drift, accel_bias, velocity_error, position_error, level_error, azimuth_error
        Magnitudes of the report: 0.1 °/h, 1e-4 g, 0.1 m/s, 0.0005°, 20″, 5′.
    duration : float
        24 h.
    step, record_interval : float
        Integration step and sampling of the numeric runs, s.
    method : {"rk4", "euler"}
        Integration scheme (``"euler"``: the manual's rectangle method).
    """

    latitude: float = float(np.radians(39.0))
    gyro_drift: float = float(np.radians(0.1) / 3600)
    accel_bias: float = 1e-4 * STANDARD_GRAVITY
    velocity_error: float = 0.1
    position_error: float = float(np.radians(0.0005))
    level_error: float = float(np.radians(20 / 3600))
    azimuth_error: float = float(np.radians(5 / 60))
    duration: float = 24 * 3600.0
    step: float = 10.0
    record_interval: float = 300.0
    method: str = "rk4"

    def sources(self) -> dict[str, float]:
        """Source name -> magnitude (SI), one run per source, in the report's order."""
        return {
            "gyro_drift_east": self.gyro_drift,
            "gyro_drift_north": self.gyro_drift,
            "gyro_drift_up": self.gyro_drift,
            "accel_bias_east": self.accel_bias,
            "accel_bias_north": self.accel_bias,
            "initial_velocity_error_east": self.velocity_error,
            "initial_velocity_error_north": self.velocity_error,
            "initial_latitude_error": self.position_error,
            "initial_longitude_error": self.position_error,
            "initial_tilt_east": self.level_error,
            "initial_tilt_north": self.level_error,
            "initial_azimuth_error": self.azimuth_error,
        }

    def check(self) -> None:
        """Raise a one-line :class:`DomainError` for an experiment that cannot run."""
        for name in ("latitude", "gyro_drift", "accel_bias", "velocity_error",
                     "position_error", "level_error", "azimuth_error", "duration", "step",
                     "record_interval"):
            if not np.isfinite(getattr(self, name)):
                raise DomainError(f"experiment: {name} must be finite")
        if abs(self.latitude) >= np.pi / 2:
            raise DomainError("experiment: latitude at or beyond ±90°: the north-pointing "
                              "formulas divide by cos φ")
        for name in ("duration", "step", "record_interval"):
            if getattr(self, name) <= 0:
                raise DomainError(f"experiment: {name} must be positive")
        for name in MAGNITUDES:
            if getattr(self, name) == 0:
                raise DomainError(f"experiment: {name} is zero: every source runs alone at "
                                  "its magnitude and is compared by ratios, which a zero "
                                  "source leaves 0/0")
        if self.method not in ORDERS:
            from ins_errors.errors import unknown_name

            raise unknown_name("integration method", self.method, list(ORDERS))


@dataclass
class SourceCurves:
    """The curves of one error source.

    Attributes
    ----------
    source : str
    magnitude : float
        SI.
    analytic, reduced, linear, direct : numpy.ndarray, shape (7, T)
        Quantities in the order of :data:`QUANTITIES`, SI.
    integration_error : numpy.ndarray, shape (7,), optional
        Estimated integration error (step doubling) of each quantity, SI: the larger of
        the direct and the linear run's estimates; None when not estimated.
    warnings : list of str
        One line each, e.g. an integration error too large, with a step that would do.
    schuler_speed : float
        √(gR) of the model, m/s: a velocity error δv weighs as the angle δv/√(gR) when
        the quantities of a source are put on one scale (the Schuler loop turns a tilt
        α into a velocity-error swing α√(gR)).
    second_order : tuple of str
        Report names (dVx, …) of the quantities the source moves only at second order
        on this base, by ``compare``'s rule (:attr:`~ins_errors.numeric.compare.Metric.
        second_order_only`: above the rounding floor in the direct run, while the linear
        run leaves them at 0 to 1e-6 of that): the linear model has nothing of them to
        judge (``compare``'s "no: 2nd order").
    """

    source: str
    magnitude: float
    analytic: np.ndarray
    reduced: np.ndarray
    linear: np.ndarray
    direct: np.ndarray
    integration_error: np.ndarray | None = None
    warnings: list[str] = field(default_factory=list)
    schuler_speed: float = float(np.sqrt(STANDARD_GRAVITY * MEAN_RADIUS))
    second_order: tuple[str, ...] = ()

    def integration_share(self) -> float:
        """Worst over quantities of integration error / max |linear numeric|: on the same
        scale as :meth:`agreement`, to be read beside ``agreement("direct", "linear")``
        (NaN when not estimated or nothing is excited)."""
        if self.integration_error is None:
            return float("nan")
        scale = np.max(np.abs(self.linear), axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(scale > 0, self.integration_error / scale, np.nan)
        return float(np.nanmax(share)) if np.any(np.isfinite(share)) else float("nan")

    def agreement(self, a: str, b: str) -> np.ndarray:
        """max|a − b| / max|b| per quantity (NaN where b is identically zero, and for
        the quantities moved only at second order, :attr:`second_order`: not judged)."""
        x, y = getattr(self, a), getattr(self, b)
        scale = np.max(np.abs(y), axis=1)
        gap = np.max(np.abs(x - y), axis=1)
        judged = np.array([q[1] not in self.second_order for q in QUANTITIES])
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(judged & (scale > 0), gap / scale, np.nan)

    def reduced_vs_full(self) -> ReducedComparison:
        """The report's reduced closed forms against the full ones, quantity by quantity.

        Each quantity's difference is judged against its size in the full model. The
        rounding floor is :data:`ROUNDING_FLOOR` times the source's largest quantity on
        one scale (velocities as δv/√(gR), angles in rad): a difference below it is 0
        (at the equator the two models are the same one), and a quantity below it in one
        model is one that model does not have (named in ``lacking`` or ``extra``, not
        counted as a 100 % difference).
        """
        weight = np.array([1 / self.schuler_speed if q[2] == "m/s" else 1.0
                           for q in QUANTITIES])
        full = np.max(np.abs(self.analytic), axis=1)
        reduced = np.max(np.abs(self.reduced), axis=1)
        gap = np.max(np.abs(self.reduced - self.analytic), axis=1)
        size = max(float(np.max(full * weight)), float(np.max(reduced * weight)))
        floor = ROUNDING_FLOOR * size / weight
        has_full, has_reduced = full > floor, reduced > floor
        relative = np.full(len(QUANTITIES), np.nan)
        for k in np.nonzero(has_full & has_reduced)[0]:
            relative[k] = gap[k] / full[k] if gap[k] > floor[k] else 0.0
        names = [q[1] for q in QUANTITIES]
        return ReducedComparison(
            relative,
            tuple(n for n, f, r in zip(names, has_full, has_reduced, strict=True) if f and not r),
            tuple(n for n, f, r in zip(names, has_full, has_reduced, strict=True) if r and not f))


@dataclass
class PropagationResult:
    """Everything the experiment produced.

    ``periods`` maps variant -> mode -> period (s), the Foucault-split pair named by size
    (:meth:`~ins_errors.numeric.closed_forms.ClosedForms.periods`); ``gravity`` (m/s²),
    ``radius`` (m) and ``earth_rate`` (rad/s) are the model's g, R and Ω those periods
    come from.
    """

    experiment: Experiment
    times: np.ndarray
    curves: list[SourceCurves] = field(default_factory=list)
    periods: dict[str, dict[str, float]] = field(default_factory=dict)
    gravity: float = STANDARD_GRAVITY
    radius: float = MEAN_RADIUS
    earth_rate: float = EARTH_RATE

    def curve(self, source: str) -> SourceCurves:
        """Curves of one source."""
        for c in self.curves:
            if c.source == source:
                return c
        from ins_errors.errors import unknown_name

        raise unknown_name("error source of the experiment", source,
                           [c.source for c in self.curves])

    def summary_markdown(self) -> str:
        """Agreement table and periods as Markdown."""
        e = self.experiment
        ureg = registry()
        lines = [
            "# Error propagation of the north-pointing INS (source 001 experiment)", "",
            f"Static base at latitude {np.degrees(e.latitude):.4g}°, "
            f"{e.duration / 3600:.4g} h; {_SCHEMES[e.method]} step {e.step:g} s, sampled every "
            f"{e.record_interval:g} s. Sources one at a time: gyro drift "
            f"{ureg.Quantity(e.gyro_drift, 'rad/s').to('deg/h').magnitude:.4g} °/h, "
            f"accelerometer bias {e.accel_bias / STANDARD_GRAVITY:.4g} g, velocity error "
            f"{e.velocity_error:g} m/s, position error {np.degrees(e.position_error):.4g}°, "
            f"level error {np.degrees(e.level_error) * 3600:.4g}″, azimuth error "
            f"{np.degrees(e.azimuth_error) * 60:.4g}′.", "",
            "Agreement = max over the run of |difference| / max |linear numeric|, the worst "
            "error quantity of each source (quantities that stay exactly zero skipped). "
            "A quantity the direct run moves while the linear run leaves it at zero (to "
            "1e-6 of the direct error: moved only at second order on this base, the rule "
            "of `compare`'s 'no: 2nd order') is not judged: the linear model has nothing "
            "of it to compare, so it is named in the column 'moved only at 2nd order' "
            "instead of counted in 'direct vs linear'. "
            "Integration error = the larger estimated integration error (step doubling) "
            "of the direct and linear runs, a relative figure as the agreement is: divided "
            "by the same max |linear numeric|, worst quantity; to be read beside 'direct "
            "vs linear'. Reduced vs full = max over the run of "
            "|reduced − full| / max |full|, per quantity both closed forms have, the worst "
            "one named; a difference below "
            f"{ROUNDING_FLOOR:.0e} of the source's largest quantity (velocities as the angle "
            "δv/√(gR)) is rounding and counts as 0. Quantities the full model has and the "
            "reduced model leaves at zero (the dropped Foucault terms are their only path "
            "from that source) are named in the last column instead.", "",
            *symbol_key(), "",
            "| source | analytic (full) vs linear numeric | direct vs linear numeric | "
            "integration error (relative) | worst quantity (direct) | "
            "moved only at 2nd order (not judged) | reduced vs full analytic | "
            "not in the reduced model |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for c in self.curves:
            a = c.agreement("analytic", "linear")
            d = c.agreement("direct", "linear")
            r = c.reduced_vs_full()
            worst = QUANTITIES[int(np.nanargmax(d))][1] if np.any(np.isfinite(d)) else "–"
            lines.append(f"| `{c.source}` | {_figure(finite_max(a))} | {_figure(finite_max(d))} | "
                         f"{_figure(c.integration_share())} | {worst} | "
                         f"{', '.join(c.second_order) or '–'} | "
                         f"{_reduced_cell(r)} | {_lacking_cell(r)} |")
        warned = [(c.source, w) for c in self.curves for w in c.warnings]
        if warned:
            lines += ["", "Warnings:", ""] + [f"- `{name}`: {w}" for name, w in warned]
        lines += ["", "Periods from the closed forms (min):", "",
                  "| variant | mode | period, min |", "|---|---|---|"]
        for variant, periods in self.periods.items():
            for mode, value in periods.items():
                lines.append(f"| {variant} | {mode} | {value / 60:.2f} |")
        lines += ["", _period_note(e.latitude, self.gravity, self.radius, self.earth_rate,
                                   "g", "the model's parameter g" + (
                                       ", standard gravity"
                                       if self.gravity == STANDARD_GRAVITY else ""),
                                   "the model's parameter R" + (
                                       ", the mean Earth radius"
                                       if self.radius == MEAN_RADIUS else "")),
                  "", foucault_note(e.latitude, e.duration, self.earth_rate)]
        lines += ["", f"Values at the end of the run, {_hours(e.duration)} (direct numeric):",
                  "",
                  "| source | " + " | ".join(f"{q[1]}, {q[2]}" for q in QUANTITIES) + " |",
                  "|---|" + "---|" * len(QUANTITIES)]
        for c in self.curves:
            row = [f"{_display(c.direct[k, -1], q[2]):.4g}" for k, q in enumerate(QUANTITIES)]
            lines.append(f"| `{c.source}` | " + " | ".join(row) + " |")
        return "\n".join(lines) + "\n"


def symbol_key() -> list[str]:
    """Markdown lines of the key to the report's symbols (dVx, …, Qz): what each is, the
    error state it is and its unit in the tables and plots. The symbols are the source
    document's; dN is the longitude error (not a north error: north is dVy's y)."""
    lines = ["Symbols (the source report's): dN is the longitude error and dL the latitude "
             "error; x is east, y north, z up.", "",
             "| symbol | quantity | error state | unit |", "|---|---|---|---|"]
    lines += [f"| {short} | {label} | `{state}` | {unit} |"
              for state, short, unit, label in QUANTITIES]
    return lines


def foucault_period(latitude: float, earth_rate: float = EARTH_RATE) -> float:
    """The Foucault period 2π / (U sin φ), s (infinite at the equator)."""
    rate = earth_rate * abs(np.sin(latitude))
    return 2 * np.pi / rate if rate > 0 else float("inf")


def foucault_note(latitude: float, duration: float, earth_rate: float = EARTH_RATE) -> str:
    """What the Foucault rotation does to 'reduced vs full' on this run, one paragraph.

    Three cases: the equator (no Foucault rotation: the reduced model is the full one),
    a run shorter than half a Foucault period (the Schuler plane has turned by
    Ω|sin φ|·t only) and a longer run (the two models oscillate in opposite phase).
    """
    at = f"at {np.degrees(latitude):.4g}°"
    period = foucault_period(latitude, earth_rate)
    if not np.isfinite(period):
        return (f"No Foucault rotation {at}: Ω sin φ = 0, so the Foucault period "
                "2π/(Ω sin φ) is infinite, the Schuler split vanishes (both split periods "
                "are the Schuler period) and the report's reduced model, which drops only "
                "the ±2Ω sin φ Foucault terms, is the full model: 'reduced vs full' is 0.")
    head = (f"Foucault period 2π/(Ω |sin φ|) {at}: {period / 3600:.1f} h. The report's "
            "reduced model leaves out the Foucault coupling, so its Schuler oscillation "
            "keeps its plane while the full one turns it round at Ω |sin φ|; ")
    if duration < period / 2:
        turned = 2 * np.pi * duration / period
        return head + (f"this run ({_hours(duration)}) is shorter than half a Foucault "
                       f"period ({period / 7200:.1f} h): by its end the plane has turned by "
                       f"θ = {np.degrees(turned):.3g}°. A quantity along the swing differs "
                       f"by up to about 1 − cos θ = {1 - np.cos(turned):.2g} of its size; "
                       "one across the swing comes from the turning in the full model only "
                       f"(up to sin θ = {np.sin(turned):.2g} of the swing): it is not in the "
                       "reduced model at all, or, where the reduced model reaches it by "
                       "another path (e.g. gyro drifts, tilts), differs by about its own size. "
                       "The opposite phase of half a Foucault period is not reached.")
    return head + (f"after half a Foucault period ({period / 7200:.1f} h) the two oscillate "
                   "in opposite phase, and 'reduced vs full' reaches about 2 on this run: "
                   "the size of the Foucault modulation, not an error of either.")


def _period_note(latitude: float, gravity: float, radius: float, earth_rate: float,
                 gravity_name: str, gravity_source: str, radius_source: str) -> str:
    """How the Foucault-split periods are named and what they were computed from."""
    w_u = earth_rate * abs(np.sin(latitude))
    w_bar = np.sqrt(gravity / radius + w_u**2)
    return (f"{SPLIT_MODES[0]} = 2π/(ω̄ − Ω|sin φ|), the longer period, and {SPLIT_MODES[1]} "
            "= 2π/(ω̄ + Ω|sin φ|), the shorter, in either hemisphere; ω̄ = "
            f"√({gravity_name}/R + Ω² sin² φ) = {w_bar:.6e} rad/s from {gravity_name} = "
            f"{gravity:.6g} m/s², R = {radius:.7g} m and Ω = {earth_rate:.7g} rad/s. "
            f"{gravity_name} is {gravity_source}; R is {radius_source}.")


def _hours(duration: float) -> str:
    return f"{duration / 3600:.4g} h"


def _figure(value: float) -> str:
    return f"{value:.2e}" if np.isfinite(value) else "–"


def _reduced_cell(r: ReducedComparison) -> str:
    """'reduced vs full' of one source: worst relative difference and its quantity."""
    worst = r.worst()
    if not np.isfinite(worst):
        return "–"
    if worst == 0:
        return "0 (same to rounding)"
    return f"{worst:.2e} ({r.worst_quantity()})"


def _lacking_cell(r: ReducedComparison) -> str:
    cell = ", ".join(r.lacking) or "–"
    if r.extra:
        cell += "; only in the reduced model: " + ", ".join(r.extra)
    return cell


def _display(value_si, unit: str):
    if unit == "m/s":
        return value_si
    return registry().Quantity(value_si, "rad").to(unit).magnitude


def _static_trajectory(model: Model, e: Experiment, p: np.ndarray) -> Trajectory:
    x = np.zeros(len(model.states))
    x[[s.name for s in model.states].index("phi")] = e.latitude
    u = np.zeros(len(model.inputs))
    c = model.initial_condition_vector(latitude=e.latitude)
    n_steps = step_count(e.duration, e.step)
    return Trajectory(model.name, e.step, n_steps, x[:, None], u[:, None], u[:, None], p,
                      c, True, f"static base at φ={np.degrees(e.latitude):.4g}°")


def run(experiment: Experiment | None = None, progress: bool = False) -> PropagationResult:
    """Run the experiment: closed forms, linear and direct numeric runs for every source.

    Raises
    ------
    DomainError
        Latitude at a pole, non-positive duration or step, non-finite values.
    """
    e = experiment or Experiment()
    e.check()
    model = load_model(MODEL)
    p = model.parameter_vector()
    trajectory = _static_trajectory(model, e, p)
    sources = e.sources()
    cases = [{name: value} for name, value in sources.items()]
    sim = simulate(model, trajectory, cases, method=e.method,
                   record_interval=e.record_interval, parts=("real", "linear"),
                   progress=progress)
    comparisons = comparisons_of(sim, labels=list(sources))
    add_integration_errors(comparisons, sim)
    times = sim.times
    direct, linear = sim.direct_errors(), sim.linear_errors()
    cf = closed_forms(model, e.latitude, p)
    unit = {name: cf.responses(times, variant) for name, variant in
            (("full", "full"), ("reduced", "report_reduced"))}
    states = [s.name for s in model.error_states]
    rows = [states.index(q[0]) for q in QUANTITIES]
    names = [q.name for q in model.parameters]
    gravity, radius = float(p[names.index("g")]), float(p[names.index("R")])
    result = PropagationResult(e, times, gravity=gravity, radius=radius,
                               earth_rate=float(p[names.index("U")]))
    for b, (name, magnitude) in enumerate(sources.items()):
        j = [s.name for s in model.sources].index(name)
        result.curves.append(SourceCurves(
            name, magnitude,
            analytic=unit["full"][rows, j] * magnitude,
            reduced=unit["reduced"][rows, j] * magnitude,
            linear=np.stack([linear[q[0]][:, b] for q in QUANTITIES]),
            direct=np.stack([direct[q[0]][:, b] for q in QUANTITIES]),
            integration_error=_integration_errors(comparisons[b]),
            warnings=list(comparisons[b].warnings),
            schuler_speed=float(np.sqrt(gravity * radius)),
            second_order=tuple(q[1] for q in QUANTITIES
                               if comparisons[b].metric(q[0]).second_order_only),
        ))
    result.periods = {variant: cf.periods(variant)
                      for variant in ("full", "report_reduced")}
    return result


def _integration_errors(comparison: Comparison) -> np.ndarray | None:
    """Per quantity of :data:`QUANTITIES`: the larger integration-error estimate, SI."""
    errors = [comparison.metric(q[0]).integration_error for q in QUANTITIES]
    if any(e is None for e in errors):
        return None
    return np.array(errors, dtype=float)


PLOT_DPI = 90
"""Resolution of the per-source figures of :func:`plot`, dots per inch."""


def plot(result: PropagationResult, folder: OutputFolder,
         sources: list[str] | None = None) -> list[Path]:
    """One PNG per source (default every source): its seven error quantities, four curves.

    The sources share one figure whose curves, ranges and title are replaced source by
    source (the same files as a fresh figure each, without building every panel and
    tick again). The solid curves of long records are drawn through their column
    envelope (:func:`~ins_errors.numeric.envelope.column_envelopes`): per half pixel
    column each curve's first, last, smallest and largest sample, the same picture as
    every sample.

    Returns
    -------
    list of pathlib.Path
        ``folder/<source>.png``.
    """
    from ins_errors.units import format_quantity

    model = load_model("north_pointing")
    hours = result.times / 3600
    chosen = [result.curve(name) for name in sources] if sources else result.curves
    if not chosen:
        return []
    runs = ("direct", "linear", "analytic", "reduced")
    styles = ({"color": "C0", "lw": 2.2, "alpha": 0.6, "label": "direct numeric"},
              {"color": "C1", "lw": 1.2, "label": "linear numeric"},
              {"color": "k", "lw": 0.8, "ls": "--", "label": "analytic (full)"},
              {"color": "C3", "lw": 0.8, "ls": ":", "label": "analytic (report's reduced)"})

    def pages():
        for c in chosen:
            info = model.source(c.source)
            magnitude = format_quantity(c.magnitude, info.unit, info.display_unit or info.unit)
            yield (f"{c.source}.png",
                   f"north_pointing, {c.source} = {magnitude}, φ = "
                   f"{np.degrees(result.experiment.latitude):.4g}°",
                   [[_display(getattr(c, run)[k], unit) for run in runs]
                    for k, (_, _, unit, _) in enumerate(QUANTITIES)])

    return _panel_pages(folder, hours, [(f"{short}, {unit}", label)
                                        for _, short, unit, label in QUANTITIES],
                        styles, height=13, top=0.62, hspace=0.38, size=8, pages=pages())


def _panel_pages(folder: OutputFolder, hours: np.ndarray, panels: list[tuple[str, str]],
                 styles: tuple[dict, ...], height: float, top: float, hspace: float,
                 size: int, pages) -> list[Path]:
    """Save one PNG per page of one figure of stacked panels against time, refilled
    page by page (the same files as a fresh figure each, without building every panel
    and tick again).

    Parameters
    ----------
    folder : OutputFolder
    hours : numpy.ndarray, shape (T,)
        Times, h.
    panels : list of (str, str)
        Each panel's y label and title (left, above it).
    styles : tuple of dict
        The curves' line styles (the first two solid, drawn through their column
        envelope, :func:`~ins_errors.numeric.envelope.column_envelopes`: per half pixel
        column each curve's first, last, smallest and largest sample, the same picture;
        the others whole, their dash pattern running along the drawn length).
    height : float
        Height of the panels, in (the legend's row is added).
    top, hspace : float
        Margin above the panels, in, and the space between them (fraction of a panel).
    size : int
        Font size of the labels and titles, pt.
    pages : iterable of (str, str, list of list of numpy.ndarray)
        File name, figure title and, per panel, one curve per style.

    Returns
    -------
    list of pathlib.Path
        The files, in the order of ``pages``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ins_errors import figure_layout as layout

    # no sharex and no tight_layout: both redo every panel's ticks several times a
    # draw (see figure_layout); the same times give the same range, fixed margins fit
    # the labels
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, height + layout.LEGEND_ROW))
    layout.share_time_axis(axes)
    layout.fixed_margins(fig, left=1.0, right=0.2, bottom=0.6 + layout.LEGEND_ROW,
                         top=top, hspace=hspace)
    columns = 2 * math.ceil(axes[0].get_position().width * fig.get_figwidth() * PLOT_DPI)
    paths: list[Path] = []
    try:
        lines = []
        for ax, (ylabel, label) in zip(axes, panels, strict=True):
            lines.append([ax.plot([], [], **style)[0] for style in styles])
            ax.set_ylabel(ylabel, fontsize=size)
            # the title keeps its place above the left end (matplotlib's search for an
            # offset text to clear lays out the panel's tick labels once more every
            # draw); a power-of-ten multiplier of tiny values goes to the right end
            layout.fixed_title(ax, label, fontsize=size, loc="left")
            ax.yaxis.set_offset_position("right")
            ax.ticklabel_format(axis="y", useOffset=False)
            ax.grid(True, alpha=0.3)
        # under the panels: over the top one it hid the dense Schuler curves
        layout.legend_below(axes[-1], 7, handles=lines[0])
        axes[-1].set_xlabel("time, h")
        title = fig.suptitle("", fontsize=9)
        for name, text, curves in pages:
            for ax, row, shown in zip(axes, lines, curves, strict=True):
                drawn = column_envelopes(hours, shown[:2], columns) + [
                    (hours, values) for values in shown[2:]]
                for line, (times, values) in zip(row, drawn, strict=True):
                    line.set_data(times, values)
                ax.set_autoscaley_on(True)  # the previous page may have fixed it
                ax.relim()
                ax.autoscale_view()
                _honest_range(ax, shown)
            layout.common_time_range(axes)
            title.set_text(text)
            paths.append(folder.save_figure(fig, name, dpi=PLOT_DPI, close=False))
    finally:
        plt.close(fig)
    return paths


def _honest_range(ax, curves: list[np.ndarray]) -> None:
    """Keep zero in view when the curves are flat to rounding: a 5e-13 difference
    between two constant curves must not fill the panel like a real gap."""
    values = np.concatenate([np.ravel(v) for v in curves])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return
    lo, hi = float(values.min()), float(values.max())
    size = max(abs(lo), abs(hi))
    if hi - lo <= 1e-6 * size:
        ax.set_ylim(min(0.0, lo) * 1.1 - (size == 0), max(0.0, hi) * 1.1 + (size == 0))


def write_report(result: PropagationResult, folder: str | Path,
                 sources: list[str] | None = None, force: bool = False) -> Path:
    """Write ``summary.md`` and the plots (of ``sources``, default all) into ``folder``.

    The folder is an :class:`~ins_errors.output.OutputFolder`: a folder of someone
    else's files is refused unless ``force``; an earlier report there is replaced.
    """
    with OutputFolder(folder, force=force) as out:   # taken back if it stops
        paths = plot(result, out, sources)
        text = result.summary_markdown() + "\nPlots:\n\n" + "".join(
            f"- ![{p.stem}]({p.name})\n" for p in paths)
        summary = out.write_text("summary.md", text)
    return summary


# --------------------------------------------------------------------------------------
# Source 000, task 4: the orthodromic INS over a day (or --hours), numeric vs analytic
# --------------------------------------------------------------------------------------
ORTHODROMIC_MAGNITUDES: dict[str, float] = {
    "initial_tilt_x": float(np.radians(20 / 3600)),
    "initial_tilt_y": float(np.radians(20 / 3600)),
    "initial_azimuth_error": float(np.radians(5 / 60)),
    "initial_velocity_error_xi": 0.1,
    "initial_velocity_error_eta": 0.1,
    "initial_latitude_error": float(np.radians(0.0005)),
    "initial_longitude_error": float(np.radians(0.0005)),
    "initial_heading_error": float(np.radians(5 / 60)),
    "gyro_drift_x": float(np.radians(0.1) / 3600),
    "gyro_drift_y": float(np.radians(0.1) / 3600),
    "gyro_drift_z": float(np.radians(0.1) / 3600),
    "accel_bias_x": 1e-4 * STANDARD_GRAVITY,
    "accel_bias_y": 1e-4 * STANDARD_GRAVITY,
    "velocity_integrator_offset_xi": 1e-4 * STANDARD_GRAVITY,
    "velocity_integrator_offset_eta": 1e-4 * STANDARD_GRAVITY,
    "position_integrator_offset_xi": float(np.radians(0.1) / 3600),
    "position_integrator_offset_eta": float(np.radians(0.1) / 3600),
    "accel_scale_error_x": 1e-4,
    "accel_scale_error_y": 1e-4,
    "velocity_integrator_gain_error_xi": 1e-4,
    "velocity_integrator_gain_error_eta": 1e-4,
    "position_integrator_gain_error_xi": 1e-4,
    "position_integrator_gain_error_eta": 1e-4,
    "correction_gain_error_x": 1e-4,
    "correction_gain_error_y": 1e-4,
    "correction_gain_error_z": 1e-4,
}
"""Magnitudes of the day run of ``orthodromic``: the 001 experiment's where the factor is
the same kind (0.1 °/h, 1e-4 g, 20″, 5′, 0.1 m/s, 0.0005°), 100 ppm for gains and scale
factors, 0.1 °/h for the second-integrator offsets."""


@dataclass
class DayResult:
    """Agreement of the orthodromic day run, per source, over the error states.

    Attributes
    ----------
    latitude, duration : float
    times : numpy.ndarray, shape (T,)
    analytic, linear, direct : numpy.ndarray, shape (ne, nw, T)
        Error states for each source alone (SI).
    sources : list of str
    error_states : list of str
    periods : dict
        Mode name -> period, s (closed forms).
    integration : numpy.ndarray, shape (nw,), optional
        Per source: worst over excited quantities of the estimated integration error
        (step doubling, as ``compare``) / max |direct error|; NaN where not excited.
    warnings : list of list of str
        Per source: integration-error warnings, one line each.
    gravity : float
        a_ζ of the static base, m/s²: the vertical specific force the closed forms and
        the runs use, normal gravity by the WGS-84 Somigliana formula on the model's
        sphere (e² = 0), γ_e (1 + k sin² φ).
    radius : float
        Sphere radius a of the closed forms, m (the Krasovsky semi-major axis).
    earth_rate : float
        U of the closed forms, rad/s.
    second_order : list of tuple of str
        Per source: the error states it moves only at second order on this base, by
        ``compare``'s rule (:func:`~ins_errors.numeric.compare.metrics_of` on the error
        states: above the rounding floor of their unit in the direct run while the
        linear run leaves them at 0 to 1e-6 of that); not judged.
    navigation : list of str
        The navigation errors plotted beside the error states (:data:`DAY_NAVIGATION`).
    navigation_analytic, navigation_linear, navigation_direct : numpy.ndarray, shape (4, nw, T)
        Those errors (SI): the closed forms through the output matrix H of the static
        base (constant there, so exact), and the runs' own output errors.
    """

    latitude: float
    duration: float
    times: np.ndarray
    analytic: np.ndarray
    linear: np.ndarray
    direct: np.ndarray
    sources: list[str]
    error_states: list[str]
    periods: dict[str, float]
    integration: np.ndarray | None = None
    warnings: list[list[str]] = field(default_factory=list)
    gravity: float = float("nan")
    radius: float = float("nan")
    earth_rate: float = EARTH_RATE
    second_order: list[tuple[str, ...]] = field(default_factory=list)
    navigation: list[str] = field(default_factory=list)
    navigation_analytic: np.ndarray | None = None
    navigation_linear: np.ndarray | None = None
    navigation_direct: np.ndarray | None = None

    def excited(self) -> np.ndarray:
        """Per source: True unless the closed form is identically zero (a factor whose
        input vanishes on a static base, e.g. a gain on a zero relative rate)."""
        return np.any(self.analytic != 0, axis=(0, 2))

    def agreement(self, a: str, b: str) -> np.ndarray:
        """Per source: worst over error states of max|a − b| / max|b|; shape (nw,).

        NaN for sources that are not excited (their numeric curves are round-off).
        """
        x, y = getattr(self, a), getattr(self, b)
        scale = np.max(np.abs(y), axis=2)
        gap = np.max(np.abs(x - y), axis=2)
        out = np.full(len(self.sources), np.nan)
        for j in np.nonzero(self.excited())[0]:
            used = np.max(np.abs(self.analytic[:, j]), axis=1) > 0
            out[j] = np.max(gap[used, j] / scale[used, j])
        return out

    def summary_markdown(self) -> str:
        """Agreement table (source 000, task 4) as Markdown."""
        lines = [
            f"# Orthodromic INS over {_hours(self.duration)} (source 000, task 4): numeric "
            "vs analytic", "",
            f"Static base at latitude {np.degrees(self.latitude):.4g}°, ξ north, sphere of "
            f"the Krasovsky radius, {_hours(self.duration)}. Periods from the closed "
            "forms: " + ", ".join(f"{k} {v / 60:.2f} min" for k, v in self.periods.items())
            + ".", "",
            _period_note(self.latitude, self.gravity, self.radius, self.earth_rate, "a_ζ",
                         "the vertical specific force at rest: normal gravity by the WGS-84 "
                         "Somigliana formula γ_e·(1 + k sin² φ)/√(1 − e² sin² φ) with γ_e = "
                         f"{WGS84_EQUATORIAL_GRAVITY} m/s² and k = {WGS84_SOMIGLIANA_K} on "
                         "the model's sphere, e² = 0: γ_e·(1 + k sin² φ), not the standard "
                         "9.80665 m/s²",
                         "the sphere's radius a, the Krasovsky semi-major axis"), "",
            "Agreement = worst error state of max |difference| / max |linear numeric|, "
            "over the error states the closed form moves. A state the direct run moves "
            "while the linear run leaves it at zero (to 1e-6 of the direct error: moved "
            "only at second order on this base, the rule of `compare`'s 'no: 2nd order') "
            "is not judged and is named in the last column.", "",
            "Integration error = estimated integration error (step doubling) / max |direct|,"
            " worst excited quantity: a relative figure, like the agreement.", "",
            "| source | magnitude | analytic vs linear numeric | direct vs linear | "
            "integration error (relative) | moved only at 2nd order (not judged) |",
            "|---|---|---|---|---|---|"]
        from ins_errors.units import format_quantity

        model = load_model("orthodromic")
        a, d = self.agreement("analytic", "linear"), self.agreement("direct", "linear")
        for j, source in enumerate(self.sources):
            info = model.source(source)
            shown = format_quantity(ORTHODROMIC_MAGNITUDES[source], info.unit,
                                    info.display_unit or info.unit)
            if not self.excited()[j]:
                lines.append(f"| `{source}` | {shown} | not "
                             "excited on a static base (its input is zero there) | – | – "
                             "| – |")
                continue
            share = np.nan if self.integration is None else self.integration[j]
            second = self.second_order[j] if j < len(self.second_order) else ()
            lines.append(f"| `{source}` | {shown} | {a[j]:.2e} | {d[j]:.2e} | "
                         + (f"{share:.2e} |" if np.isfinite(share) else "– |")
                         + f" {', '.join(second) or '–'} |")
        warned = [(s, w) for s, ws in zip(self.sources, self.warnings, strict=False)
                  for w in ws]
        if warned:
            lines += ["", "Warnings:", ""] + [f"- `{s}`: {w}" for s, w in warned]
        return "\n".join(lines) + "\n"


DAY_DISPLAY = {"1": ("ppm", 1e6), "m/s": ("m/s", 1.0)}
"""Display units of the orthodromic error states by SI unit (the platform angles by
:data:`DAY_ANGLES`)."""

DAY_NAVIGATION = ("delta_latitude", "delta_longitude", "delta_v_N", "delta_v_E")
"""The navigation errors of the day run's plots (what a lab report of task 4 reads off):
latitude and longitude in arcmin, velocities in m/s, as ``compare`` shows them."""

DAY_ANGLES = {"alpha_z": ("arcmin", 180 * 60 / np.pi),
              "delta_latitude": ("arcmin", 180 * 60 / np.pi),
              "delta_longitude": ("arcmin", 180 * 60 / np.pi)}
"""Display unit of a platform angle of the day run: the azimuth in arcmin, the tilts in
arcsec (:func:`_day_unit`)."""


def _day_unit(name: str, unit: str) -> tuple[str, float]:
    """(display unit, factor from SI) of one error state of the day run."""
    if unit == "rad":
        return DAY_ANGLES.get(name, ("arcsec", 180 * 3600 / np.pi))
    return DAY_DISPLAY.get(unit, (unit, 1.0))


def plot_day(day: DayResult, folder: OutputFolder) -> list[Path]:
    """One PNG per excited source of the orthodromic day run: each error state (the six
    direction-cosine errors, the two velocity errors, the three platform angles) as the
    direct and linear numeric runs and the closed form. A source whose closed form is
    identically zero (no input on a static base) gets none: its runs are round-off.

    Returns
    -------
    list of pathlib.Path
        ``folder/<source>.png``, in the order of ``day.sources``.
    """
    from ins_errors.units import format_quantity

    model = load_model("orthodromic")
    outputs = {f"delta_{o.name}": o for o in model.outputs}
    states = [*model.error_states,
              *(replace(outputs[name], name=name,
                        description=f"error of the {outputs[name].description}")
                for name in day.navigation)]
    excited = day.excited()
    if not np.any(excited):
        return []
    runs = ("direct", "linear", "analytic")
    styles = ({"color": "C0", "lw": 2.2, "alpha": 0.6, "label": "direct numeric"},
              {"color": "C1", "lw": 1.2, "label": "linear numeric"},
              {"color": "k", "lw": 0.8, "ls": "--", "label": "analytic (closed form)"})
    factors = [_day_unit(state.name, state.unit) for state in states]

    def pages():
        for j, source in enumerate(day.sources):
            if not excited[j]:
                continue
            info = model.source(source)
            magnitude = format_quantity(ORTHODROMIC_MAGNITUDES[source], info.unit,
                                        info.display_unit or info.unit)
            curves = [np.concatenate([getattr(day, run)] + ([getattr(day, f"navigation_{run}")]
                                                            if day.navigation else []))
                      for run in runs]
            yield (f"{source}.png",
                   f"orthodromic, {source} = {magnitude}, static base, φ = "
                   f"{np.degrees(day.latitude):.4g}°",
                   [[curve[k, j] * factor for curve in curves]
                    for k, (_, factor) in enumerate(factors)])

    return _panel_pages(folder, day.times / 3600,
                        [(f"{state.name}, {unit}", state.description)
                         for state, (unit, _) in zip(states, factors, strict=True)],
                        styles, height=18 * len(states) / 11, top=0.85, hspace=0.45,
                        size=7, pages=pages())

def write_day_report(day: DayResult, folder: str | Path, force: bool = False) -> Path:
    """Write ``orthodromic_day.md`` and the plots of :func:`plot_day` into ``folder`` (an
    :class:`~ins_errors.output.OutputFolder`, as :func:`write_report`)."""
    with OutputFolder(folder, force=force) as out:   # taken back if it stops
        paths = plot_day(day, out)
        skipped = [s for s, e in zip(day.sources, day.excited(), strict=True) if not e]
        text = day.summary_markdown() + "\nPlots (each error state: direct and linear numeric, "
        text += "closed form):\n\n" + "".join(f"- ![{p.stem}]({p.name})\n" for p in paths)
        if skipped:
            text += ("\nNo plot for " + ", ".join(f"`{s}`" for s in skipped) + ": not excited "
                     "on a static base (the closed form is zero; the runs are round-off).\n")
        summary = out.write_text("orthodromic_day.md", text)
    return summary


def orthodromic_day(latitude: float = float(np.radians(50.0)), duration: float = 86400.0,
                    step: float = 10.0, record_interval: float = 600.0,
                    progress: bool = False) -> DayResult:
    """Source 000, task 4: every error factor alone over a day, closed forms vs runs.

    The static base holds the ξ axis north on the sphere the closed forms were derived
    for (see ``generated/orthodromic/transfer_functions.md``). The direct run uses the
    manual's small-angle platform, as the task does: with the exact platform, a day of
    0.1 °/h second-integrator offset or azimuth drift turns the platform by degrees, and
    the second-order difference between its z-y-x angles and the linear model's small
    rotation dominates the states that are small at first order.

    Raises
    ------
    DomainError
        Latitude at a pole, bad step or duration.
    """
    from ins_errors.numeric.trajectories import static_profile, trajectory

    if not (np.isfinite(latitude) and abs(latitude) < np.pi / 2):
        raise DomainError("latitude must be finite and strictly between −90° and 90°")
    model = load_model("orthodromic")
    cf0 = closed_forms(model, latitude)
    traj = trajectory(model, static_profile(latitude), duration, step, p=cf0.p)
    gravity = float(traj.inputs[[i.name for i in model.inputs].index("a_zeta"), 0])
    cf = closed_forms(model, latitude, p=cf0.p, gravity=gravity)
    sources = list(ORTHODROMIC_MAGNITUDES)
    cases = [{s: ORTHODROMIC_MAGNITUDES[s]} for s in sources]
    sim = simulate(model, traj, cases, method="rk4", record_interval=record_interval,
                   parts=("real", "linear"), progress=progress,
                   platform="small_angle")
    comparisons = comparisons_of(sim, labels=sources)
    add_integration_errors(comparisons, sim)
    n = len(model.states)
    ideal = sim.ideal
    platform = np.zeros((sim.real.shape[0] - n, *ideal.shape[1:]))
    direct = sim.real - np.concatenate([ideal, platform])
    order = [[s.name for s in model.sources].index(s) for s in sources]
    magnitudes = np.array([ORTHODROMIC_MAGNITUDES[s] for s in sources])
    analytic = cf.responses(sim.times)[:, order] * magnitudes[None, :, None]
    shares = np.array([max((m.integration_error / m.max_direct for m in c.excited
                            if m.integration_error is not None), default=np.nan)
                       for c in comparisons])
    names = [q.name for q in model.parameters]
    states = [s.name for s in model.error_states]
    units = [s.unit for s in model.error_states]
    curves = [ErrorCurves(states, units, sim.times, values) for values in (direct, sim.linear)]
    second = [tuple(m.quantity for m in metrics_of(*curves, None, j) if m.second_order_only)
              for j in range(len(sources))]
    # the navigation errors: the closed forms through H of the static base (constant at
    # rest, so the map of the states is exact), the runs' own output errors
    H = model.output_matrix(traj.start_state, traj.start_inputs, traj.parameters)
    rows = [[f"delta_{o.name}" for o in model.outputs].index(name) for name in DAY_NAVIGATION]
    errors = {"direct": sim.direct_errors(), "linear": sim.linear_errors()}
    navigation = {run: np.stack([np.transpose(e[name], (1, 0)) for name in DAY_NAVIGATION])
                  for run, e in errors.items()}
    return DayResult(latitude, duration, sim.times, analytic,
                     np.transpose(sim.linear, (0, 2, 1)), np.transpose(direct, (0, 2, 1)),
                     sources, states, cf.periods(), shares,
                     [list(c.warnings) for c in comparisons], gravity,
                     float(cf.p[names.index("a")]), float(cf.p[names.index("U")]), second,
                     list(DAY_NAVIGATION), np.einsum("ok,kjt->ojt", H[rows], analytic),
                     navigation["linear"], navigation["direct"])
