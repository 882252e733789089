"""Methodological errors: the on-board computer uses a simplified formula (000, tasks 3, 5, 6).

Each study swaps the orthodromic INS's computer for a simplified one and nothing else
(:func:`ins_errors.models.orthodromic.build` with a ``simplify`` flag):

``nonsphericity`` (task 3)
    the Earth taken as a sphere on board: e² = 0 in the radii of curvature 1/R_ξ,
    1/R_η, 1/R_o and in R_E of the velocity integrators (the output formulas for
    v_N, v_E keep the exact radii: the study measures the navigation-state errors);
``coriolis`` (task 5)
    the transport and Coriolis corrections W_ξ, W_η dropped from the velocity integrators;
``gravity_projections`` (task 6)
    the horizontal projections g'_ξ, g'_η of the gravitation dropped.

The *equivalent error source* is derived mechanically as the difference of the two
right-hand sides along the true motion,
``d(t) = f̃_simplified(x(t), 0; u(t)) − (f(x(t); u(t)), 0)``: its velocity rows are
equivalent accelerometer errors, its direction-cosine rows equivalent rate offsets of the
second integrators, and its platform rows equivalent gyro drifts. The linear estimate
integrates ``ė = F̃ e + d(t)``, F̃ being the Jacobian of the simplified real work at the
ideal point (equal to the exact model's F when the simplification does not change the
error dynamics; dropping the Coriolis terms does, e.g. it removes the Foucault
coupling); the direct run integrates the real work with the simplified computer next to
the ideal work and subtracts. Both run in one loop (RK4, or the rectangle method) along
the same true motion (static base or a great-circle flight), so their difference is the
linearisation error alone.

A quantity is judged as ``compare`` judges it (:func:`ins_errors.numeric.compare.metrics_of`):
above the rounding floor of its unit and moved by the linear estimate at first order.
A study's linear estimate can move a quantity whose first-order response cancels,
though: ``d(t)`` holds every power of the neglected quantity (e² in ``nonsphericity``),
and F̃ and the true motion depend on it too, so the linear estimate of the azimuth on a
static base with the sphere on board is of order e⁴ (as is the direct error), not 0,
and their "mismatch" of about 100 % would stay at any e². A study with such a size
parameter (:attr:`Study.size_parameter`) therefore runs once more with it halved, true
motion and computer alike: an error that falls to a quarter, not to a half
(:data:`SECOND_ORDER_SCALING`), is moved only at second order, like one the linear
estimate leaves at 0, and is not judged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cache
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.numeric.compare import (
    SECOND_ORDER_FRACTION,
    Comparison,
    Metric,
    integration_errors_by_reruns,
    metrics_of,
)
from ins_errors.numeric.integrators import CompiledLoop, check_method, input_stream, record_stride
from ins_errors.numeric.model import Model, load_model
from ins_errors.numeric.simulate import ErrorCurves, chunk_size, error_curves
from ins_errors.numeric.trajectories import (
    Trajectory,
    great_circle_profile,
    static_profile,
    trajectory,
)
from ins_errors.output import save_figure


@dataclass(frozen=True)
class Study:
    """One simplified on-board formula.

    Attributes
    ----------
    name : str
        Study name (public).
    flag : str
        ``simplify`` flag of the orthodromic computer.
    task : int
        Number of the lab task in source 000.
    description : str
        One line.
    size_parameter : str or None
        The model parameter that sizes what the simplified formula neglects (``"e2"``:
        the sphere neglects the flattening), halved in the scaling run
        (:attr:`StudyResult.half_size_ratios`); None when no parameter sizes it alone (a
        dropped Coriolis or gravitation term is sized by the Earth rate, which sizes the
        whole motion too): then only the linear estimate's 0 marks a second-order
        quantity.
    """

    name: str
    flag: str
    task: int
    description: str
    size_parameter: str | None = None


STUDIES: dict[str, Study] = {
    s.name: s for s in (
        Study("nonsphericity", "sphere", 3,
              "Earth taken as a sphere on board (e² = 0 in the radii of curvature)",
              size_parameter="e2"),
        Study("coriolis", "no_coriolis", 5,
              "transport and Coriolis corrections W_ξ, W_η dropped"),
        Study("gravity_projections", "no_gravity", 6,
              "horizontal gravitation projections g'_ξ, g'_η dropped"),
    )
}
"""The methodological studies, by name."""

SCENARIOS = ("static", "flight")
"""Motions a study runs along."""

SECOND_ORDER_SCALING = 0.5 ** 1.5
"""A direct error whose largest value with the study's size parameter halved is at most
this share of the study's (0.35: the geometric middle of a half and a quarter, an
exponent of 1.5 or more) is moved only at second order by the simplification."""

FORCING_ROWS = ("delta_u11", "delta_u21", "delta_u31", "delta_u12", "delta_u22", "delta_u32",
                "delta_V_xi", "delta_V_eta", "alpha_x", "alpha_y", "alpha_z")


class StudyError(InsErrorsError):
    """A study that cannot be run as asked (bad scenario, duration or step)."""


def study(name: str) -> Study:
    """Look a study up by name (unknown names get close suggestions)."""
    if name not in STUDIES:
        raise unknown_name("methodological study", name, STUDIES)
    return STUDIES[name]


# --------------------------------------------------------------------------------------
# Symbolic part: the simplified real work and the equivalent forcing, as casadi functions
# --------------------------------------------------------------------------------------
@cache
def _symbolic_variant(flag: str):
    """SymPy pieces of the computer simplified by ``flag``.

    Returns
    -------
    simple : ModelDefinition
        The orthodromic model with the simplified computer.
    real : sympy.Matrix
        Simplified real work without instrument errors, in ``xr, x, u, p``.
    forcing : sympy.Matrix
        Simplified minus exact right-hand side at the ideal point, in ``x, u, p``.
    jacobian : sympy.Matrix
        Jacobian F~ of the simplified real work at the ideal point, in ``x, u, p``.
    """
    import sympy as sp

    from ins_errors.models import definition
    from ins_errors.models.orthodromic import build

    exact = definition("orthodromic")  # the registered model: build() with no flags
    simple = build(frozenset({flag}))
    real = simple.real_rhs_expanded().xreplace(simple.no_errors())
    at_ideal = real.xreplace(simple.at_ideal())
    forcing = at_ideal - sp.Matrix([*exact.ideal_rhs_expanded(), 0, 0, 0])
    jacobian = real.jacobian(simple.real_states).xreplace(simple.at_ideal())
    return simple, real, forcing, jacobian


def _casadi_function(name: str, arguments: list, result) -> ca.Function:
    """A casadi.Function of a SymPy matrix, through the project's code generator."""
    from ins_errors.symbolic.codegen import (
        Argument,
        FunctionSpec,
        casadi_namespace,
        emit_casadi_builder,
        prepare,
    )

    spec = FunctionSpec(name, [Argument(label, symbols, label) for label, symbols in arguments],
                        result, name, name, matrix=True)  # CasADi: always 2-D
    namespace = casadi_namespace()
    exec(emit_casadi_builder(prepare(spec)), namespace)  # generated from our own SymPy
    return namespace[f"_build_{name}"]()


FUNCTION_NAMES = ("direct", "linear_terms", "forcing")
"""The casadi functions of one simplified computer, in :func:`_study_functions` order."""


def _derive_functions(flag: str) -> tuple[ca.Function, ca.Function, ca.Function]:
    """The casadi functions of the computer simplified by ``flag``, from SymPy (~1 s CPU)."""
    import sympy as sp

    simple, real, forcing, jacobian = _symbolic_variant(flag)
    args = [("x", simple.x), ("u", simple.u), ("p", simple.p)]
    direct = _casadi_function("simplified_real_rhs",
                              [("xr", simple.real_states), *args], real)
    linear_terms = _casadi_function(
        "simplified_linear", [*args, ("e", simple.xe)],
        jacobian * sp.Matrix(simple.xe) + forcing)
    return direct, linear_terms, _casadi_function("equivalent_forcing", args, forcing)


@cache
def _study_functions(flag: str) -> tuple[ca.Function, ca.Function, ca.Function]:
    """casadi.Functions of the computer simplified by ``flag``: once per process and flag
    (every step, duration and motion of a study shares them), and kept on disk
    (:mod:`ins_errors.studies.function_cache`) so that a new process skips the SymPy
    derivation.

    Returns
    -------
    direct : casadi.Function
        ``(xr, x, u, p) -> dxr/dt``, the simplified real work without instrument errors.
    linear_terms : casadi.Function
        ``(x, u, p, e) -> F~ e + d``, the right-hand side of the linear estimate.
    forcing : casadi.Function
        ``(x, u, p) -> d``: simplified minus exact right-hand side at the ideal point.
    """
    from ins_errors.studies import function_cache

    name = f"methodological-{flag}"
    kept = function_cache.read(name, FUNCTION_NAMES)
    if kept is not None:
        return kept  # type: ignore[return-value]
    functions = _derive_functions(flag)
    function_cache.write(name, dict(zip(FUNCTION_NAMES, functions, strict=True)))
    return functions


def _forcing_function(flag: str):
    """``(x, u, p) -> d``, numpy: the equivalent source of the computer simplified by
    ``flag``, shape (11,) for one point or (11, N) for N columns of ``x`` and ``u``
    (``p`` is one parameter vector)."""
    forcing = _study_functions(flag)[2]

    def call(x, u, p):
        x, u, p = (np.asarray(v, dtype=float) for v in (x, u, p))
        if x.ndim == 1:
            return np.asarray(forcing(x, u, p)).reshape(-1)
        columns = x.shape[1]
        return np.asarray(forcing.map(columns)(x, u, np.repeat(p[:, None], columns, axis=1)))

    return call


@cache
def _study_loop(flag: str, tau: float, stride: int, p: tuple[float, ...],
                constant_inputs: tuple[float, ...] | None, chunk: int,
                method: str = "rk4") -> CompiledLoop:
    """Compiled loop (RK4, or the rectangle method) of ``z = [x, x~, e]``: ideal work,
    simplified real work, and the linear estimate ``ė = F~ e + d``."""
    direct, linear_terms, _forcing = _study_functions(flag)
    model = load_model("orthodromic")
    ideal = model.casadi.function("ideal_rhs")
    # direct(xr, x, u, p): the sizes of the real and ideal states, inputs and parameters
    ne, n, nu, npar = (direct.size1_in(k) for k in range(4))
    z, u = ca.SX.sym("z", n + 2 * ne), ca.SX.sym("u", nu)
    par, none = ca.SX.sym("p", npar), ca.SX.sym("none", 0)
    x, xr, e = z[:n], z[n:n + ne], z[n + ne:]
    rhs = ca.Function("study_rhs", [z, u, none, par],
                      [ca.vertcat(ideal(x, u, par), direct(xr, x, u, par),
                                  linear_terms(x, u, par, e))])
    return CompiledLoop(rhs, None, method, stride, tau, np.array(p),
                        None if constant_inputs is None else np.array(constant_inputs),
                        chunk=chunk)


# --------------------------------------------------------------------------------------
# Runs
# --------------------------------------------------------------------------------------
@dataclass
class StudyResult:
    """Direct and linear errors of one methodological study along one motion.

    Attributes
    ----------
    study : Study
    scenario : str
        ``"static"`` or ``"flight"``.
    motion : str
        One-line description of the true motion.
    direct, linear : ErrorCurves
        Platform angles and output errors (one case: ``values[..., 0]``).
    forcing_names : tuple of str
        Rows of the equivalent source ``d(t)``.
    forcing : numpy.ndarray, shape (11, R + 1)
        Equivalent source along the motion (SI: 1/s for direction cosines, m/s² for
        velocities, rad/s for the platform).
    comparison : Comparison or None
        Direct vs linear metrics with the estimated integration error of each quantity
        (step doubling, as ``compare``) and its warnings; None when not estimated.
    half_size_ratios : dict of str to float
        Per quantity, max |direct error| with the study's size parameter halved (e.g. e²:
        the same study on an Earth half as flat) over max |direct error|: 0.5 for an
        error moved at first order, 0.25 for one moved only at second order (NaN where
        the study's error is 0); empty when the study has no size parameter or the
        scaling run was not made.
    latitude : numpy.ndarray or None, shape (R + 1,)
        True latitude φ at the recorded times, rad (for the east error R cos φ Δλ);
        None: not recorded (taken as 0).
    """

    study: Study
    scenario: str
    motion: str
    direct: ErrorCurves
    linear: ErrorCurves
    forcing_names: tuple[str, ...]
    forcing: np.ndarray
    comparison: Comparison | None = None
    half_size_ratios: dict[str, float] = field(default_factory=dict)
    latitude: np.ndarray | None = None

    @property
    def warnings(self) -> list[str]:
        """One line each (e.g. an integration error too large, with a step that would do)."""
        return [] if self.comparison is None else list(self.comparison.warnings)

    def integration_error(self, name: str) -> float | None:
        """Estimated integration error of one quantity (larger of direct and linear), SI."""
        return None if self.comparison is None else self.comparison.metric(name).integration_error

    @property
    def times(self) -> np.ndarray:
        """Recorded times, s."""
        return self.direct.times

    def east_error(self, radius: float = 6_371_000.0) -> tuple[np.ndarray, np.ndarray]:
        """The east position error R cos φ Δλ of the direct and the linear run, m, shape
        (R + 1,) each (:func:`east_error`)."""
        return east_error(self.direct, self.linear, self.latitude, radius)

    def agreement(self, name: str) -> float:
        """max |direct − linear| / max |direct| of one error quantity."""
        d, lin = self.direct[name][:, 0], self.linear[name][:, 0]
        scale = np.abs(d).max()
        return float(np.abs(d - lin).max() / scale) if scale > 0 else float(np.abs(lin).max())

    def metrics(self) -> list[Metric]:
        """Direct vs linear metrics of each quantity, judged as ``compare`` judges them
        (:func:`~ins_errors.numeric.compare.metrics_of`), and a quantity whose direct
        error falls to a quarter with the study's size parameter halved (to at most
        :data:`SECOND_ORDER_SCALING` of itself) marked as moved only at second order (not
        excited), whatever the linear estimate gives (see the module's notes)."""
        return [self._scaled(m) for m in metrics_of(self.direct, self.linear, None)]

    def _scaled(self, metric: Metric) -> Metric:
        """``metric`` marked second order when the scaling run shows it (see :meth:`metrics`)."""
        ratio = self.half_size_ratios.get(metric.quantity, math.nan)
        if metric.excited and ratio <= SECOND_ORDER_SCALING:
            return replace(metric, excited=False, second_order_only=True)
        return metric

    def quantities(self) -> dict[str, dict[str, Any]]:
        """Each error quantity's direct and linear maxima, SI, for JSON.

        Returns
        -------
        dict
            Quantity name -> ``unit`` (SI), ``direct_max_<unit>``, ``linear_max_<unit>``
            and ``difference_max_<unit>`` (max |direct|, max |linear|, max |direct −
            linear| over the run), ``mismatch_ratio`` (difference over direct maximum,
            :meth:`agreement`), ``excited`` (compare's rule: above the rounding floor of
            its unit and moved by the linear estimate at first order; a ratio of an error
            not excited means nothing), ``second_order_only`` (the direct run moves it
            while the linear estimate gives 0, or it falls to a quarter with the study's
            size parameter halved: a second-order effect, :meth:`metrics`),
            ``half_size_ratio`` (:attr:`half_size_ratios`, or None),
            ``at_rounding_level`` (direct maximum at or below :data:`MISMATCH_FLOOR`) and
            ``integration_error_<unit>`` (or None).
            ``<unit>`` is the unit in words: ``rad``, ``rad_per_s``, ``m_per_s``.
        """
        metrics = {m.quantity: m for m in self.metrics()}
        out = {}
        for name, unit in zip(self.direct.names, self.direct.units, strict=True):
            d, lin = self.direct[name][:, 0], self.linear[name][:, 0]
            largest = float(np.abs(d).max())
            suffix = unit_suffix(unit)
            out[name] = {
                "unit": unit,
                f"direct_max_{suffix}": largest,
                f"linear_max_{suffix}": float(np.abs(lin).max()),
                f"difference_max_{suffix}": float(np.abs(d - lin).max()),
                "mismatch_ratio": self.agreement(name),
                "excited": bool(metrics[name].excited),
                "second_order_only": bool(metrics[name].second_order_only),
                "half_size_ratio": _number_or_none(self.half_size_ratios.get(name)),
                "at_rounding_level": largest <= MISMATCH_FLOOR.get(
                    "m/s" if unit == "m/s" else "rad", 0.0),
                f"integration_error_{suffix}": self.integration_error(name),
            }
        return out

    def _second_order_evidence(self, quantity: dict[str, Any]) -> str:
        """Why a quantity of :meth:`quantities` counts as moved only at second order: the
        linear estimate's 0, and the quarter of the scaling run when it was made."""
        suffix = unit_suffix(quantity["unit"])
        reasons = []
        if (quantity[f"linear_max_{suffix}"]
                <= SECOND_ORDER_FRACTION * quantity[f"direct_max_{suffix}"]):
            reasons.append("the linear estimate gives 0")
        ratio = quantity["half_size_ratio"]
        if ratio is not None:
            reasons.append(f"its direct error ×{ratio:.2g} with {self.study.size_parameter} halved")
        return "; ".join(reasons)

    def equivalent_sources(self) -> dict[str, float]:
        """Largest equivalent sources along the motion, SI: accelerometer (m/s², the
        velocity rows), gyro drift (rad/s, the platform rows), direction-cosine rate (1/s,
        the direction-cosine rows; 0 when none)."""
        f = np.abs(self.forcing).max(axis=1)
        return {"accelerometer_max_m_per_s2": float(max(f[6], f[7])),
                "gyro_drift_max_rad_per_s": float(max(f[8], f[9], f[10])),
                "direction_cosine_rate_max_per_s": float(max(f[:6].max(), 0.0))}

    def summary(self, radius: float = 6_371_000.0) -> list[str]:
        """Report lines: equivalent sources and the largest errors, engineering units."""
        deg_h, ug = np.pi / 180 / 3600, 9.80665e-6
        hours = self.times[-1] / 3600
        lines = [f"{self.study.name} (source 000, task {self.study.task}: "
                 f"{self.study.description}); {self.motion}; {hours:g} h, direct vs linear"]
        sources = self.equivalent_sources()
        lines.append(f"  equivalent sources (max along the motion): accelerometer "
                     f"{sources['accelerometer_max_m_per_s2'] / ug:.4g} µg, "
                     f"gyro drift {sources['gyro_drift_max_rad_per_s'] / deg_h:.4g} °/h, "
                     f"direction-cosine rate "
                     f"{sources['direction_cosine_rate_max_per_s'] / deg_h:.4g} °/h")
        units = {"alpha_x": ("arcsec", 180 / np.pi * 3600),
                 "alpha_y": ("arcsec", 180 / np.pi * 3600),
                 "alpha_z": ("arcmin", 180 / np.pi * 60),
                 "delta_latitude": ("km north (R Δφ)", radius / 1000),
                 "delta_longitude": (EAST_UNIT, radius / 1000),
                 "delta_heading": ("arcmin", 180 / np.pi * 60),
                 "delta_v_N": ("m/s", 1.0), "delta_v_E": ("m/s", 1.0)}
        numbers = self.quantities()
        for name, (unit, scale) in units.items():
            if name not in numbers:
                continue
            q = numbers[name]
            suffix = unit_suffix(q["unit"])
            d, lin = q[f"direct_max_{suffix}"] * scale, q[f"linear_max_{suffix}"] * scale
            if name == "delta_longitude":  # the east distance at each time's latitude
                direct, linear = self.east_error(radius)
                peak = float(np.abs(direct).max())
                d, lin = peak / 1000, float(np.abs(linear).max()) / 1000
                if peak > 0:
                    q = {**q, "mismatch_ratio": float(np.abs(direct - linear).max()) / peak}
                if self.latitude is not None:  # Δλ's estimate times the largest R cos φ
                    scale *= float(np.abs(np.cos(self.latitude)).max())
            if q["at_rounding_level"]:
                mismatch = "– (error at rounding level)"
            elif not q["excited"]:  # compare's rule: a ratio here would only alarm
                mismatch = ("– (not excited at first order: moved only at second order, "
                            f"{self._second_order_evidence(q)})" if q["second_order_only"]
                            else "– (not excited: at the rounding floor of its unit)")
            else:
                mismatch = f"{100 * q['mismatch_ratio']:.3g} %"
            error = q[f"integration_error_{suffix}"]
            integration = ("" if error is None else  # in the line's unit, not relative
                           f"  integration error {error * scale:.2g} {unit.split()[0]}")
            lines.append(f"  {name:<16} direct {d:11.4g}  linear {lin:11.4g} {unit:<20}"
                         f" mismatch {mismatch}{integration}")
        lines += [f"  warning: {w}" for w in self.warnings]
        return lines


def _number_or_none(value: float | None) -> float | None:
    """A float for JSON: None for a missing or NaN value."""
    return None if value is None or math.isnan(value) else float(value)


def east_error(direct: ErrorCurves, linear: ErrorCurves, latitude: np.ndarray | None,
               radius: float = 6_371_000.0) -> tuple[np.ndarray, np.ndarray]:
    """The east position error R cos φ Δλ of a direct and a linear run: the longitude
    error as a distance on a sphere of ``radius`` (m) at the true latitude φ (rad, shape
    (R + 1,); None: taken as 0) of each recorded time; m, shape (R + 1,) each."""
    cos = np.cos(latitude) if latitude is not None else 1.0
    return (radius * cos * direct["delta_longitude"][:, 0],
            radius * cos * linear["delta_longitude"][:, 0])


EAST_UNIT = "km east (R cos φ Δλ)"
"""How a study's summary shows the longitude error: as the east distance R cos φ Δλ at
the true latitude φ (Δλ·R alone overstates it by 1/cos φ: 1.56 times at 50°)."""


def unit_suffix(unit: str) -> str:
    """A SI unit as a JSON key suffix: ``"m/s"`` -> ``"m_per_s"``, ``"m/s**2"`` ->
    ``"m_per_s2"``, ``"rad"`` -> ``"rad"``, ``"1"`` -> ``"ratio"``."""
    if unit == "1":
        return "ratio"
    return unit.replace("**", "").replace("/", "_per_").replace(" ", "_")


MISMATCH_FLOOR = {"rad": 1e-10, "m/s": 1e-6}
"""SI size below which a direct error is rounding noise (as
:data:`ins_errors.numeric.compare.NOISE_FLOOR`): its relative mismatch is printed as "–",
since a ratio of two noises looks like an alarm and means nothing."""


def motion(scenario: str, latitude: float, duration: float, tau: float,
           speed: float = 250.0, track: float = np.radians(60.0),
           model: Model | None = None, p: np.ndarray | None = None) -> Trajectory:
    """True motion of a study: a static base or a great-circle flight (orthodromic model),
    on the Earth of the parameters ``p`` (default: the model's)."""
    model = model or load_model("orthodromic")
    if scenario == "static":
        profile = static_profile(latitude, 0.0, 0.0)
    elif scenario == "flight":
        profile = great_circle_profile(latitude, 0.0, track, speed)
    else:
        raise unknown_name("scenario", scenario, SCENARIOS)
    return trajectory(model, profile, duration, tau, p)


def run(name: str, scenario: str = "static", latitude: float = np.radians(50.0),
        duration: float = 24 * 3600.0, tau: float = 20.0, record_interval: float = 600.0,
        speed: float = 250.0, track: float = np.radians(60.0),
        integration_error: bool = True, method: str = "rk4",
        scaling: bool = True) -> StudyResult:
    """Run one methodological study: direct and linear, RK4 (or the rectangle method)
    with step ``tau``.

    Parameters
    ----------
    name : str
        Study name (see :data:`STUDIES`).
    scenario : {"static", "flight"}
        Static base at ``latitude`` or a great-circle flight from it at ``speed`` (m/s) on
        initial track ``track`` (rad).
    latitude : float
        Start latitude, rad.
    duration, tau, record_interval : float
        Run length, integration step and recording interval, s.
    integration_error : bool
        Estimate the integration error as ``compare`` does (runs at another step and at a
        third one for the observed order, :func:`_integration_errors`) and warn when it
        is too large or not reliable at this step.
    method : {"rk4", "euler"}
        Scheme: RK4, or the manual's rectangle method.
    scaling : bool
        For a study with a size parameter (:attr:`Study.size_parameter`), run it once more
        with that parameter halved and judge the quantities that it moves only at second
        order (:attr:`StudyResult.half_size_ratios`).
    """
    st = study(name)
    method = check_method(method)
    if not (np.isfinite(tau) and tau > 0 and np.isfinite(duration) and duration > 0):
        raise StudyError(f"duration and step must be positive, got {duration} s and {tau} s")
    model = load_model("orthodromic")
    traj = motion(scenario, latitude, duration, tau, speed, track, model)
    stride = record_stride(record_interval, tau, traj.n_steps)
    direct, linear, x, u = _direct_and_linear(st, scenario, traj, tau, stride, method)
    forcing = _forcing_function(st.flag)(x, u, traj.parameters)
    records = len(direct.times)
    true_latitude = model.numpy.outputs(x, u, traj.parameters)[
        [o.name for o in model.outputs].index("latitude")]
    result = StudyResult(st, scenario, traj.description, direct, linear, FORCING_ROWS,
                         np.broadcast_to(forcing, (len(FORCING_ROWS), records)).copy(),
                         latitude=np.array(true_latitude, dtype=float))
    if scaling and st.size_parameter is not None:
        p = traj.parameters.copy()
        p[model.index("parameters", st.size_parameter)] /= 2
        half, _, _, _ = _direct_and_linear(
            st, scenario, motion(scenario, latitude, duration, tau, speed, track, model, p),
            tau, stride, method)
        result.half_size_ratios = {
            n: _ratio_of_peaks(half[n][:, 0], direct[n][:, 0]) for n in direct.names}
    if integration_error:
        result.comparison = _integration_errors(result, traj.n_steps, stride, tau, latitude,
                                                speed, track, method)
    return result


def _ratio_of_peaks(part: np.ndarray, whole: np.ndarray) -> float:
    """max |part| / max |whole| (NaN where the whole is 0)."""
    peak = float(np.abs(whole).max())
    return float(np.abs(part).max()) / peak if peak > 0 else math.nan


def _direct_and_linear(st: Study, scenario: str, traj: Trajectory, tau: float, stride: int,
                       method: str
                       ) -> tuple[ErrorCurves, ErrorCurves, np.ndarray, np.ndarray]:
    """The direct errors and the linear estimate of one study along ``traj``.

    Returns
    -------
    direct, linear : ErrorCurves
        Recorded every ``stride`` steps.
    x, u : numpy.ndarray
        The true state and inputs at the recorded times.
    """
    model = load_model("orthodromic")
    np_ = model.numpy
    p = traj.parameters
    u_steps, _ = traj.full_inputs()
    n, ne = len(model.states), len(model.error_states)
    x0 = traj.truth[:, 0]
    z0 = np.concatenate([x0, x0, np.zeros(ne - n), np.zeros(ne)])
    records = traj.n_steps // stride + 1
    constant = tuple(traj.inputs[:, 0]) if traj.constant else None
    loop = _study_loop(st.flag, float(tau), stride, tuple(p), constant,
                       chunk_size(records - 1), method)
    stream = None if traj.constant else input_stream(traj.inputs, traj.midpoints, method)
    history = loop.run(z0, np.zeros(0), traj.n_steps, stream).states[:, :, 0]
    if not np.all(np.isfinite(history)):
        raise StudyError(f"study {st.name!r} ({scenario}) diverged: NaN or infinite errors")
    steps = np.arange(records) * stride
    x, xr, e = history[:n], history[n:n + ne], history[n + ne:]
    u = u_steps[:, steps]
    times = steps * tau
    with np.errstate(invalid="ignore"):  # beyond the domain (|u31| > 1): checked below
        outputs = np_.outputs(xr[:n], u, p) - np_.outputs(x, u, p)
    if not np.all(np.isfinite(outputs)):
        raise StudyError(f"study {st.name!r} ({scenario}) diverged: NaN or infinite errors "
                         "(the real work left the model's domain)")
    direct = error_curves(model, times, xr[n:, :, None], outputs[:, :, None])
    H = np_.output_matrix(x, u, p)
    linear = error_curves(model, times, e[n:, :, None],
                          np.einsum("ijt,jt->it", H, e)[:, :, None])
    return direct, linear, x, u


def _integration_errors(result: StudyResult, n_steps: int, stride: int, tau: float,
                        latitude: float, speed: float, track: float,
                        method: str) -> Comparison:
    """The study's direct-vs-linear comparison with the integration-error estimate of
    ``compare`` (:func:`ins_errors.numeric.compare.integration_errors_by_reruns`): the
    study runs again at τ/2 or 2τ, and at a third step for the observed order."""
    comparison = Comparison(result.study.name, {}, result.metrics(), result.times, {}, {}, {})

    def rerun(factor: float, every: int) -> tuple[ErrorCurves, ErrorCurves]:
        steps = 2 * n_steps if factor < 1 else n_steps // factor
        again = run(result.study.name, result.scenario, latitude, steps * factor * tau,
                    factor * tau, every * factor * tau, speed, track,
                    integration_error=False, method=method, scaling=False)
        return again.direct, again.linear

    def rk4_step() -> float | None:
        try:
            again = run(result.study.name, result.scenario, latitude, n_steps * tau, tau,
                        stride * tau, speed, track, method="rk4")
        except InsErrorsError:
            return None
        step = again.comparison.suggested_step
        return tau if step is None else step

    integration_errors_by_reruns([comparison], (result.direct, result.linear), n_steps, tau,
                                 stride, method, rerun, rk4_step)
    return comparison


# --------------------------------------------------------------------------------------
# Plots
# --------------------------------------------------------------------------------------
def plot(result: StudyResult, path: str | Path, radius: float = 6_371_000.0) -> Path:
    """Save the direct (solid) and linear (dashed) error curves of a study as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ins_errors.figure_layout import common_time_range, fixed_margins, share_time_axis

    hours = result.times / 3600
    panels = [
        ("position error, km", [("delta_latitude", "north R Δφ", radius / 1000),
                                ("delta_longitude", "east R cos φ Δλ", radius / 1000)]),
        ("velocity error, m/s", [("delta_v_N", "Δv_N", 1.0), ("delta_v_E", "Δv_E", 1.0)]),
        ("platform tilt, arcsec", [("alpha_x", "α_x", 180 / np.pi * 3600),
                                   ("alpha_y", "α_y", 180 / np.pi * 3600)]),
        ("azimuth / heading error, arcmin", [("alpha_z", "α_z", 180 / np.pi * 60),
                                             ("delta_heading", "Δχ", 180 / np.pi * 60)]),
    ]
    # no sharex and no tight_layout (each lays out every panel's tick labels again,
    # see ins_errors.figure_layout): the panels share the times, fixed margins fit
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 10))
    share_time_axis(axes)
    fixed_margins(fig, left=1.05, right=0.15, bottom=0.6, top=0.66, hspace=0.25)
    for ax, (title, curves) in zip(axes, panels, strict=True):
        for k, (name, label, scale) in enumerate(curves):
            color = f"C{k}"
            direct, linear = result.direct[name][:, 0], result.linear[name][:, 0]
            if name == "delta_longitude":  # the east distance, at each time's latitude
                direct, linear = (c / radius for c in east_error(
                    result.direct, result.linear, result.latitude, radius))
            ax.plot(hours, direct * scale, color=color, label=f"{label} direct")
            ax.plot(hours, linear * scale, color=color, ls="--", label=f"{label} linear")
        ax.set_ylabel(title)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    axes[-1].set_xlabel("time, h")
    fig.suptitle(f"{result.study.name} (source 000, task {result.study.task}): "
                 f"{result.study.description}\n{result.motion}", fontsize=9)
    common_time_range(axes)
    return save_figure(fig, path, dpi=110)
