"""Direct, linear and refined error runs along one true motion (model-independent).

* **direct**: the ideal-work and the real-work equations integrated side by side with the
  same scheme, step and inputs; the errors are real − ideal (the source documents'
  "direct modelling"). The real work's platform is exact by default (``platform="exact"``:
  rotation of the platform relative to its trihedron, :mod:`ins_errors.models.platform`);
  ``platform="small_angle"`` uses the source documents' small-angle platform matrix.
  The sines and cosines of the exact platform's angles travel with the state and are
  rotated through each step's angle increment (:mod:`ins_errors.numeric.carried_trig`)
  rather than recomputed by the C library at every evaluation: the same scheme, up to
  rounding, in about two thirds of the time;
* **linear**: the generated first-order error equations ``ė = F e + G w`` along the
  *ideal run's* states, from ``e(0) = E w``;
* **refined**: the truncated quadratic error equations ``ė₂ = F e₂ + G w + S(x, u, e₂, w)``
  (``S`` the generated second-order terms) along the ideal run's states, from the exact
  initial difference ``x̃(0) − (x(0), 0)``, its outputs read through the exact output map,
  ``y(x + e₂) − y(x)``. This is an ODE of its own, not the second-order term of a series
  in the sources' magnitude: its quadratic terms feed back, and where they are beyond
  their range it can run away from the direct run (see :mod:`ins_errors.numeric.compare`,
  which warns).

All three are integrated in one compiled loop (state ``[x, x̃, e, e₂]``, then any carried
sines and cosines), so they share the ideal trajectory exactly; the rectangle scheme of
the linear run is then exactly the first-order variation of the direct rectangle scheme,
whatever the step.

Errors are reported per *quantity*: the platform angles (the error states beyond the
computed states) and the change of every navigation output (latitude, longitude,
heading, ..., v_N, v_E), angles wrapped to (−π, π].

A static base can also be run with the exact matrix-exponential discretisation of the
linear equations (:func:`linear_exact`).

Example
-------
>>> import numpy as np
>>> from ins_errors import load_model
>>> from ins_errors.numeric import trajectories as tr
>>> from ins_errors.numeric.simulate import simulate
>>> model = load_model("orthodromic")
>>> motion = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(40), 250.0)
>>> traj = tr.trajectory(model, motion, duration=7200.0, tau=1.0)
>>> sim = simulate(model, traj, [{"gyro_drift_x": 4.8e-8}, {"accel_bias_y": 1e-4}],
...                record_interval=60.0)
>>> sim.direct_errors()["delta_latitude"].shape  # (recorded times, cases)
(121, 2)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from functools import cache, lru_cache

import casadi as ca
import numpy as np

from ins_errors.errors import DomainError, InsErrorsError, ShapeError, name_list, unknown_name
from ins_errors.numeric.integrators import (
    CompiledLoop,
    InputRows,
    LoopResult,
    Method,
    PieceCheck,
    StepError,
    check_method,
    exact_discretisation,
    progress_bar,
    record_stride,
    worker_count,
)
from ins_errors.numeric.model import Model, as_model
from ins_errors.numeric.nonfinite import WHY, nonfinite_entries
from ins_errors.numeric.trajectories import Trajectory

PARTS: tuple[str, ...] = ("real", "linear", "refined")
"""Runs that can be integrated next to the ideal run."""

PLATFORMS: tuple[str, ...] = ("exact", "small_angle")
"""Platform kinematics of the direct run: exact rotation (default) or the source
documents' small-angle matrix."""

SMALL_ANGLE_LIMIT = 0.5
"""Largest platform misalignment (rad) accepted with the small-angle platform matrix
(``platform="small_angle"``); the exact platform has no such limit."""

EULER_LIMIT = np.radians(89.9)
"""Largest |alpha_y| (rad) of the exact platform: its z-y-x angles are singular at 90°."""

MAX_RECORDED_VALUES = 250_000_000
"""Largest number of recorded floats (2 GB) a run may produce."""

CURVE_VALUES = 4096
"""Values per row (recorded samples times cases) of one piece in which the error curves
are evaluated (:meth:`Simulation.direct_errors` ...): the generated output maps make a
few hundred temporaries of a piece's size, about 10 MB at this size whatever the record
(and the pieces stay in cache: 2.5 times faster than the whole record at once)."""


# --------------------------------------------------------------------------------------
# The combined system
# --------------------------------------------------------------------------------------
def real_rhs_name(model: Model, platform: str) -> str:
    """Name of the generated real-work function for a platform form.

    Raises
    ------
    UnknownNameError, ShapeError
        For an unknown form, or a model without a small-angle variant.
    """
    if platform not in PLATFORMS:
        raise unknown_name("platform", platform, PLATFORMS)
    if platform == "exact":
        return "real_rhs"
    if not model.has_small_angle_platform:
        raise ShapeError(f"model {model.name!r} has no small-angle platform variant")
    return "real_rhs_small_angle"


@cache
def _system(model_name: str, parts: tuple[str, ...], platform: str = "exact"
            ) -> tuple[ca.Function, ca.Function, tuple[int, ...]]:
    """``rhs(z, u, w, p)`` and ``margin(z, u, w, p)`` of ``z = [x, x̃?, e?, e₂?, s?, c?]``.

    The third value lists the real-work states (indices into ``x̃``, platform angles)
    whose sines ``s`` and cosines ``c`` are carried at the end of ``z`` instead of being
    computed at every evaluation (:mod:`ins_errors.numeric.carried_trig`); empty when the
    real run is off or its equations take no sine or cosine of a bare platform angle.
    """
    from ins_errors.numeric.carried_trig import with_trig_inputs
    from ins_errors.numeric.model import load_model

    model = load_model(model_name)
    fn = model.casadi.function
    n, ne = len(model.states), len(model.error_states)
    nu, nw, npar = len(model.inputs), len(model.sources), len(model.parameters)
    sizes = {"ideal": n, "real": ne, "linear": ne, "refined": ne}
    layout = ["ideal", *parts]
    nz = sum(sizes[k] for k in layout)
    carried: list[int] = []
    if "real" in parts:
        real_fn = fn(real_rhs_name(model, platform))
        carried = with_trig_inputs(real_fn, 0, range(n, ne))[1]   # the platform angles
        if carried:
            real_fn = with_trig_inputs(real_fn, 0, carried)[0]
        nz += 2 * len(carried)
    z, u = ca.SX.sym("z", nz), ca.SX.sym("u", nu)
    w, p = ca.SX.sym("w", nw), ca.SX.sym("p", npar)
    pieces, offset = {}, 0
    for name in layout:
        pieces[name] = z[offset:offset + sizes[name]]
        offset += sizes[name]
    x = pieces["ideal"]
    rates = [fn("ideal_rhs")(x, u, p)]
    margins = [fn("domain_margins")(x, u, p)]
    if "linear" in parts or "refined" in parts:
        F, G = fn("state_matrix")(x, u, p), fn("source_matrix")(x, u, p)
    if "real" in parts:
        xr = pieces["real"]
        trig = [z[offset:offset + len(carried)], z[offset + len(carried):]] if carried else []
        rates.append(real_fn(xr, x, u, w, p, *trig))
        margins.append(fn("domain_margins")(xr[:n], u, p))
    if "linear" in parts:
        rates.append(F @ pieces["linear"] + G @ w)
    if "refined" in parts:
        e2 = pieces["refined"]
        second = "second_order" if platform == "exact" else "second_order_small_angle"
        rates.append(F @ e2 + G @ w + fn(second)(x, u, p, e2, w))
    rates.append(ca.SX.zeros(2 * len(carried)))  # not used: the step rotates them
    rhs = ca.Function("system_rhs", [z, u, w, p], [ca.vertcat(*rates)])
    margin = ca.Function("system_margin", [z, u, w, p], [ca.mmin(ca.vertcat(*margins))])
    return rhs, margin, tuple(carried)


def _rotations(model: Model, parts: tuple[str, ...],
               carried: tuple[int, ...]) -> tuple[tuple[int, int, int], ...]:
    """``(angle, sine, cosine)`` indices into ``z`` of the carried platform angles."""
    if not carried:
        return ()
    n, ne = len(model.states), len(model.error_states)
    end = n + ne * len(parts)
    return tuple((n + a, end + j, end + len(carried) + j) for j, a in enumerate(carried))


_RUNTIME_CONSTANTS: ContextVar[bool] = ContextVar("runtime_constants", default=False)


@contextmanager
def runtime_constant_loops(on: bool = True) -> Iterator[None]:
    """Inside (in this thread), :func:`simulate` compiles loops that read the numbers
    made from the model parameters and a static base's inputs at run time
    (:class:`~ins_errors.numeric.integrators.CompiledLoop` with ``runtime_constants``)
    instead of writing them into the C code: one compiled library then serves every
    latitude, heading and parameter value, with the same results to the last bit and
    the same speed per step within a few per cent
    (:class:`~ins_errors.numeric.integrators.CompiledLoop`). For work over many such
    values: a sweep's points (:func:`ins_errors.analysis.sweep.run_sweep`).

    Parameters
    ----------
    on : bool
        False: loops with their numbers compiled in (the default outside the block).
    """
    token = _RUNTIME_CONSTANTS.set(bool(on))
    try:
        yield
    finally:
        _RUNTIME_CONSTANTS.reset(token)


@lru_cache(maxsize=32)
def _loop(model_name: str, parts: tuple[str, ...], method: str, stride: int, tau: float,
          p: tuple[float, ...], u: tuple[float, ...] | None, active: tuple[bool, ...],
          batch: int, jit: bool, chunk: int, platform: str = "exact",
          workers: int = 1, runtime_constants: bool = False) -> CompiledLoop:
    """The compiled loop, specialised to the error sources that are non-zero in some case.

    Sources that are zero in every case of the batch are baked in as zeros, so the C
    compiler drops every term they multiply. ``runtime_constants``: the loop's numbers
    are read at run time (:func:`runtime_constant_loops`).
    """
    from ins_errors.numeric.model import load_model

    full_rhs, full_margin, carried = _system(model_name, parts, platform)
    nz, nu, npar = full_rhs.size1_in(0), full_rhs.size1_in(1), full_rhs.size1_in(3)
    z, uu, par = ca.SX.sym("z", nz), ca.SX.sym("u", nu), ca.SX.sym("p", npar)
    w_active = ca.SX.sym("w", sum(active))
    entries, k = [], 0
    for on in active:
        entries.append(w_active[k] if on else ca.SX(0))
        k += on
    w = ca.vertcat(*entries)
    rhs = ca.Function("active_rhs", [z, uu, w_active, par], [full_rhs(z, uu, w, par)])
    margin = ca.Function("active_margin", [z, uu, w_active, par], [full_margin(z, uu, w, par)])
    return CompiledLoop(rhs, margin, method, stride, tau, np.array(p),
                        None if u is None else np.array(u), chunk=chunk, batch=batch, jit=jit,
                        workers=workers,
                        rotations=_rotations(load_model(model_name), parts, carried),
                        runtime_constants=runtime_constants)


# --------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------
@dataclass(eq=False)
class ErrorCurves:
    """Error quantities over time, read like a mapping from quantity name to its curves
    (``curves["delta_latitude"]``, ``"alpha_y" in curves``, ``list(curves)``,
    ``curves.items()``).

    Compared by identity (``==`` is ``is``; hashable), as numpy's ``==`` on the curves
    has no single truth value: compare numbers with
    ``numpy.array_equal(a.values, b.values)``.

    Attributes
    ----------
    names : list of str
        Quantity names: platform angles (``alpha_x``...) then ``delta_<output>``.
    units : list of str
        SI units.
    times : numpy.ndarray, shape (R + 1,)
        s.
    values : numpy.ndarray, shape (nq, R + 1, B)
        Errors for each of the B cases.
    """

    names: list[str]
    units: list[str]
    times: np.ndarray
    values: np.ndarray

    def __getitem__(self, name: str) -> np.ndarray:
        """Curves of one quantity, shape (R + 1, B).

        Raises
        ------
        UnknownNameError
            For a name that is not a quantity (close names suggested); also for an
            integer or any other key, which names the quantities (rows of
            :attr:`values` are ``values[k]``).
        """
        if not isinstance(name, str) or name not in self.names:
            raise unknown_name("error quantity", str(name), self.names)
        return self.values[self.names.index(name)]

    def __contains__(self, name: object) -> bool:
        return name in self.names

    def __iter__(self) -> Iterator[str]:
        """The quantity names, in the order of :attr:`values`."""
        return iter(self.names)

    def __len__(self) -> int:
        return len(self.names)

    def keys(self) -> list[str]:
        """The quantity names."""
        return list(self.names)

    def items(self) -> list[tuple[str, np.ndarray]]:
        """(name, curves of shape (R + 1, B)) of every quantity."""
        return [(name, self.values[k]) for k, name in enumerate(self.names)]


@dataclass(eq=False)
class Simulation:
    """States of one batch of runs along one trajectory.

    Compared by identity (``==`` is ``is``; hashable): a copy of a run is another run
    (its records are arrays, compare them with ``numpy.array_equal``).

    Attributes
    ----------
    model : Model
    trajectory : Trajectory
    method : str
        ``"euler"`` or ``"rk4"``.
    stride : int
        Steps between recorded samples.
    sources : numpy.ndarray, shape (nw, B)
        Error-source vectors of the B cases, SI.
    ideal : numpy.ndarray, shape (n, R + 1, B)
    real, linear, refined : numpy.ndarray, shape (ne, R + 1, B), or None if not run
    platform : str
        Platform kinematics of the real run (``"exact"`` or ``"small_angle"``).

    The error curves (:meth:`direct_errors` ...) are computed once and kept: later calls
    return the same, read-only, curves.
    """

    model: Model
    trajectory: Trajectory
    method: str
    stride: int
    sources: np.ndarray
    ideal: np.ndarray
    real: np.ndarray | None = None
    linear: np.ndarray | None = None
    refined: np.ndarray | None = None
    platform: str = "exact"
    recorded_inputs: np.ndarray | None = None
    _kept: dict[str, ErrorCurves] = field(default_factory=dict, init=False, repr=False,
                                          compare=False)

    @property
    def times(self) -> np.ndarray:
        """Recorded times, s, shape (R + 1,)."""
        return np.arange(self.ideal.shape[1]) * self.stride * self.trajectory.tau

    def _recorded_inputs(self, rows: slice = slice(None)) -> np.ndarray:
        """Inputs at the recorded samples ``rows``, shape (nu, len(rows), 1)."""
        if self.recorded_inputs is not None:
            return self.recorded_inputs[:, rows, None]
        steps = np.arange(*rows.indices(self.ideal.shape[1])) * self.stride
        return self.trajectory.inputs_at(steps)[:, :, None]

    def _pieces(self) -> Iterator[slice]:
        """Recorded samples in pieces of about :data:`CURVE_VALUES` values per row."""
        samples, batch = self.ideal.shape[1], self.ideal.shape[2]
        size = _power_of_two_below(max(1, CURVE_VALUES // batch))
        for start in range(0, samples, size):
            yield slice(start, min(start + size, samples))

    def _collect(self, platform: np.ndarray,
                 outputs: Callable[[slice, np.ndarray], np.ndarray]) -> ErrorCurves:
        """Error curves from the platform angles and ``outputs(rows, u)``: the output
        differences at the recorded samples ``rows`` (inputs ``u``, shape
        (nu, len(rows), 1)), evaluated piece by piece into the curves' own array, so the
        generated output maps' temporaries (dozens of arrays the size of their argument,
        and H of shape (ny, ne, ...)) cover one piece, not the whole record."""
        names, units = error_quantities(self.model)
        angles = _wrapped_outputs(self.model)
        first = platform.shape[0]
        values = np.empty((len(names), *platform.shape[1:]))
        values[:first] = platform
        for rows in self._pieces():
            dy = outputs(rows, self._recorded_inputs(rows))
            dy[angles] = (dy[angles] + np.pi) % (2 * np.pi) - np.pi
            values[first:, rows] = dy
        values.flags.writeable = False  # kept and shared by every caller
        kept = next(iter(self._kept.values()), None)  # one array of times for all
        return ErrorCurves(names, units, self.times if kept is None else kept.times, values)

    def direct_errors(self) -> ErrorCurves:
        """Errors of the direct run: real − ideal."""
        if self.real is None:
            raise ShapeError("this simulation did not run the real-work equations")
        if "direct" in self._kept:
            return self._kept["direct"]
        n, p = len(self.model.states), self.trajectory.parameters
        outputs = self.model.numpy.outputs

        def difference(rows: slice, u: np.ndarray) -> np.ndarray:
            return outputs(self.real[:n, rows], u, p) - outputs(self.ideal[:, rows], u, p)

        self._kept["direct"] = self._collect(self.real[n:], difference)
        return self._kept["direct"]

    def _error_curves(self, e: np.ndarray | None, exact_outputs: bool,
                      label: str) -> ErrorCurves:
        if e is None:
            raise ShapeError(f"this simulation did not run the {label} error equations")
        if label in self._kept:
            return self._kept[label]
        n, p = len(self.model.states), self.trajectory.parameters
        numpy = self.model.numpy

        def difference(rows: slice, u: np.ndarray) -> np.ndarray:
            x, de = self.ideal[:, rows], e[:, rows]
            if exact_outputs:  # as the direct run's: y(x + e₂) − y(x)
                with np.errstate(invalid="ignore"):  # NaN: beyond the map's domain
                    return numpy.outputs(x + de[:n], u, p) - numpy.outputs(x, u, p)
            return np.einsum("ij...,j...->i...", numpy.output_matrix(x, u, p), de)

        self._kept[label] = self._collect(e[n:], difference)
        return self._kept[label]

    def linear_errors(self) -> ErrorCurves:
        """Errors of the first-order error equations (outputs to first order, ``H e``)."""
        return self._error_curves(self.linear, False, "linear")

    def refined_errors(self) -> ErrorCurves:
        """Errors of the refined run (the truncated quadratic error equations), outputs
        read through the exact output map, ``y(x + e₂) − y(x)`` with ``x`` the ideal
        run's state: at t = 0, where ``e₂`` is the exact initial difference, they are
        the direct run's. NaN where ``x + e₂`` is beyond the output map's domain (a run
        that diverged)."""
        return self._error_curves(self.refined, True, "refined")


# --------------------------------------------------------------------------------------
# Running
# --------------------------------------------------------------------------------------
def error_quantities(model: Model) -> tuple[list[str], list[str]]:
    """Names and SI units of the error quantities a run reports.

    The platform angles (error states beyond the computed states), then
    ``delta_<output>`` for every navigation output.
    """
    n = len(model.states)
    names = [s.name for s in model.error_states[n:]] + [f"delta_{o.name}" for o in model.outputs]
    units = [s.unit for s in model.error_states[n:]] + [o.unit for o in model.outputs]
    return names, units


def _wrapped_outputs(model: Model) -> list[int]:
    """Indices of the outputs that are angles (their differences are wrapped)."""
    return [k for k, o in enumerate(model.outputs) if o.unit == "rad"]


def error_curves(model: Model, times: np.ndarray, platform: np.ndarray,
                 outputs: np.ndarray) -> ErrorCurves:
    """Error quantities over time from platform angles and output differences.

    Parameters
    ----------
    model : Model
    times : numpy.ndarray, shape (R + 1,)
        s.
    platform : numpy.ndarray, shape (ne - n, R + 1, B)
        Platform angles, rad.
    outputs : numpy.ndarray, shape (ny, R + 1, B)
        Output differences (SI); angles are wrapped to (−π, π].
    """
    names, units = error_quantities(model)
    angles = _wrapped_outputs(model)
    outputs = outputs.copy()
    outputs[angles] = (outputs[angles] + np.pi) % (2 * np.pi) - np.pi
    return ErrorCurves(names, units, times, np.concatenate([platform, outputs]))


def source_cases(model: Model, sources: dict[str, float] | np.ndarray
                  | Sequence[dict[str, float]]) -> np.ndarray:
    """Error-source vectors as an array of shape (nw, B).

    Accepts one ``{name: SI value}`` mapping, a list of them (one per case), or an array
    of shape (nw,) or (nw, B).

    Raises
    ------
    ShapeError
        For no case at all, an array of another shape, or something else.
    """
    nw = len(model.sources)
    if isinstance(sources, Mapping):
        return model.source_vector(**sources)[:, None]
    cases = sources if isinstance(sources, np.ndarray) else (
        list(sources) if isinstance(sources, Iterable) and not isinstance(sources, str | bytes)
        else None)
    if cases is None:
        raise ShapeError("error sources must be a {name: SI value} mapping, a list of them "
                         f"or an array of shape ({nw}, B), got {type(sources).__name__}")
    if (cases.size if isinstance(cases, np.ndarray) else len(cases)) == 0:
        raise ShapeError("give at least one case of error sources")
    if not isinstance(cases, np.ndarray) and all(isinstance(c, Mapping) for c in cases):
        return np.stack([model.source_vector(**case) for case in cases], axis=1)
    try:
        array = np.array(cases, dtype=float)
    except (TypeError, ValueError):
        raise ShapeError(f"error sources must be {{name: SI value}} mappings or numbers "
                         f"(an array of shape ({nw}, B)), got {sources!r:.60}") from None
    w = array[:, None] if array.ndim == 1 and array.shape[0] == nw else array
    if w.ndim != 2 or w.shape[0] != nw or w.shape[1] == 0:
        columns = " (one case per column: transpose it)" if (
            w.ndim == 2 and w.shape[1] == nw) else ""
        raise ShapeError(f"error sources must have shape ({nw}, B) or ({nw},), "
                         f"got {array.shape}{columns}")
    if not np.all(np.isfinite(w)):
        raise DomainError("error sources contain NaN or infinite values")
    return w


def simulate(model: Model, trajectory: Trajectory, sources, method: Method = "rk4",
             record_interval: float | None = None,
             parts: Sequence[str] = PARTS, jit: bool = True,
             progress: bool | str = False, platform: str = "exact") -> Simulation:
    """Run the ideal work and the chosen error runs along ``trajectory``.

    Parameters
    ----------
    model : Model
        Loaded model (the trajectory must have been computed for it).
    trajectory : Trajectory
        True motion and inputs on the step grid.
    sources : dict, list of dict or numpy.ndarray
        Error sources, SI (see :func:`source_cases`); several cases run as one batch.
    method : {"rk4", "euler"}
        Scheme: RK4 (default, as ``compare`` and the command line) or ``"euler"``, the
        manual's rectangle method.
    record_interval : float, optional
        Seconds between recorded samples (a multiple of the step that divides the run);
        default: every step.
    parts : sequence of {"real", "linear", "refined"}, or one of them
        Runs to integrate next to the ideal run (one string is one run).
    jit : bool
        Compile the loop to C (falls back to the CasADi VM where no compiler works).
    progress : bool or str
        Show a progress bar over the run's steps, labelled with the runs it makes
        (``"direct and linear runs"``) or with the text given.
    platform : {"exact", "small_angle"}
        Platform kinematics of the real-work run: the exact rotation (default), or the
        source documents' small-angle matrix (platform angles above
        :data:`SMALL_ANGLE_LIMIT` are then refused).

    Raises
    ------
    DomainError
        If the real system leaves its domain (|u31| ≥ 1, NaN or infinite values): the
        message names the time and the quantity. The records are checked piece by piece
        as the run goes (:data:`~ins_errors.numeric.integrators.RUN_PIECES` pieces on a
        static base, :data:`STREAM_STEPS` steps along a moving one), so a long run that
        leaves its domain early is refused soon after, not at its end.
    StepError, ShapeError, UnknownNameError
        Bad grid, bad arrays or unknown names.
    """
    check_method(method)
    model = as_model(model, "simulate")
    if not isinstance(trajectory, Trajectory):
        raise InsErrorsError("simulate: trajectory must be a Trajectory (ins_errors.numeric."
                             f"trajectories.trajectory(...)), got {type(trajectory).__name__}")
    real_rhs_name(model, platform)
    if trajectory.model != model.key:
        raise ShapeError(f"trajectory was computed for model {trajectory.model!r}, "
                         f"not {model.key!r}")
    if not error_quantities(model)[0]:
        raise ShapeError(f"model {model.name!r} has no outputs and no platform angles (error "
                         "states after the computed states): a run has no error to report; "
                         "add an output")
    parts = name_list(parts, "simulate: parts")  # "linear" is one part, not letters
    for part in parts:
        if part not in PARTS:
            raise unknown_name("simulation part", part, PARTS)
    parts = tuple(k for k in PARTS if k in parts)
    w = source_cases(model, sources)
    B = w.shape[1]
    tau, N, p = trajectory.tau, trajectory.n_steps, trajectory.parameters
    stride = record_stride(record_interval, tau, N)
    n_values = (N // stride + 1) * B * (len(model.states) + len(parts) * len(model.error_states))
    if n_values > MAX_RECORDED_VALUES:
        raise StepError(f"recording {N // stride + 1:,} samples of {B} case(s) needs "
                        f"{8 * n_values / 1e9:.1f} GB; choose a longer recording interval")
    c, u0 = trajectory.initial_conditions, trajectory.start_inputs
    n = len(model.states)
    x0 = np.repeat(trajectory.start_state[:, None], B, axis=1)
    blocks = [x0]
    if {"real", "refined"} & set(parts):
        try:
            xr0 = model.initial_real_state(c[:, None], u0[:, None], w, p)
        except DomainError as error:  # the truth's initial conditions: the motion's start
            said = str(error).removeprefix("initial_real_state: ")
            raise DomainError(f"the motion starts outside the {model.name} model's domain "
                              f"(its initial conditions at t = 0): {said}") from None
        _check_initial(model, xr0)
        if "real" in parts:
            _check_initial_platform(model, xr0, platform)
        exact0 = xr0 - np.vstack([x0, np.zeros((xr0.shape[0] - n, B))])
    if {"linear", "refined"} & set(parts):
        _check_start_matrices(model, trajectory, np.any(w != 0, axis=1))
    if "real" in parts:
        blocks.append(xr0)
    if "linear" in parts:
        E = model.initial_error_matrix(c, u0, p)
        blocks.append(E @ w)
    if "refined" in parts:
        blocks.append(exact0)
    carried = _system(model.key, parts, platform)[2]
    if carried:   # sines, then cosines of the platform angles (the C library's, as before)
        angles = xr0[list(carried)]
        blocks += [np.vectorize(math.sin)(angles), np.vectorize(math.cos)(angles)]
    z0 = np.vstack(blocks)
    u_const = tuple(u0) if trajectory.constant else None
    active = np.any(w != 0, axis=1)
    records = N // stride
    # a moving run is fed in pieces of about STREAM_STEPS steps (whole compiled chunks)
    chunk = chunk_size(records) if trajectory.constant else min(
        chunk_size(records), _power_of_two_below(max(1, STREAM_STEPS // stride)))
    loop = _loop(model.key, parts, method, stride, float(tau), tuple(p), u_const,
                 tuple(bool(a) for a in active), B, jit, chunk, platform, worker_count(),
                 _RUNTIME_CONSTANTS.get())
    label = ((progress if isinstance(progress, str) else bar_label(parts)) if progress
             else "")
    check = _domain_check(model, parts, platform)
    if trajectory.constant:
        result = loop.run(z0, w[active], N, None, progress=label, check=check)
        recorded = None
    else:
        result, recorded = _run_streamed(loop, trajectory, z0, w[active], stride, method,
                                         chunk * stride, label, check)
    states = result.states
    sim = Simulation(model, trajectory, method, stride, w, states[:n], platform=platform,
                     recorded_inputs=recorded)
    offset = n
    ne = len(model.error_states)
    for part in parts:
        setattr(sim, part, states[offset:offset + ne])
        offset += ne
    if result.stopped or not records:  # else every record passed the pieces' checks
        _check_domain(sim, result.margins)
    if result.stopped:
        raise InsErrorsError("simulate: a piece's domain check stopped the run but the "
                             "records show no departure (an internal inconsistency)")
    return sim


STREAM_STEPS = 32768
"""Steps of a moving trajectory fed to a compiled loop at a time (about 1–4 MB of inputs)."""

TRUTH_AHEAD = STREAM_STEPS
"""Steps of a streamed true motion made beyond the piece where the runs left their
domain (:func:`_run_streamed`), so that a motion leaving its own domain just after
(a flight through a pole) is refused as such."""


def _power_of_two_below(n: int) -> int:
    return 1 << (max(1, n).bit_length() - 1)


def _run_streamed(loop: CompiledLoop, trajectory: Trajectory, z0: np.ndarray, w: np.ndarray,
                  stride: int, method: str, piece: int, progress: str,
                  check: PieceCheck | None = None) -> tuple[LoopResult, np.ndarray]:
    """Run ``loop`` along a moving trajectory fed chunk by chunk (never stored whole).

    ``progress`` labels a bar over the steps (empty: none), shown from the end of the
    first piece, which compiles the loop, so the rate and the ETA leave the compile out.
    ``check`` looks at each piece's records (the sample before the piece first) as
    :meth:`CompiledLoop.run` does; once it returns True the run ends there (the result
    is ``stopped``, its records cut at that piece's end). The true motion is then made
    :data:`TRUTH_AHEAD` steps further, without the runs, and no more: a motion that
    leaves its own domain there raises its own error, which names the cause (a flight
    through a pole, which the runs following it leave a few steps before it does, as
    a stored trajectory names it before anything runs). Returns the loop's result and
    the inputs at the recorded steps, shape (nu, R + 1).
    """
    N = trajectory.n_steps
    records = N // stride
    carry = loop.start(z0, w)
    B = loop.batch
    states = np.empty((loop.nz, records + 1, B))
    margins = np.empty((records, B))
    states[:, 0] = carry[:B, :loop.nz].T
    recorded = np.empty((len(trajectory.start_inputs), records + 1))
    recorded[:, 0] = trajectory.start_inputs
    bar = None
    chunks = trajectory.chunks(piece)
    try:
        for part in chunks:
            k, m = part.start, part.size
            stream = _piece_rows(part, method)
            r0, r1 = k // stride, (k + m) // stride
            loop.advance(carry, m, stream, states[:, r0 + 1:r1 + 1], margins[r0:r1])
            recorded[:, r0 + 1:r1 + 1] = part.inputs[:, stride::stride]
            if check is not None and check(states[:, r0:r1 + 1], margins[r0:r1]):
                for ahead in chunks:   # the true motion alone, a little further
                    if ahead.start + ahead.size >= k + m + TRUTH_AHEAD:
                        break
                return (LoopResult(states[:, :r1 + 1], margins[:r1], stopped=True),
                        recorded[:, :r1 + 1])
            if bar is not None:
                bar.update(m)
            elif progress:  # timed from the end of the first piece, which compiles the loop
                bar = progress_bar(N, progress, initial=k + m)
    finally:
        if bar is not None:
            bar.close()
    return LoopResult(states, margins), recorded


def bar_label(parts: Sequence[str]) -> str:
    """``"direct, linear and refined runs"``: the runs of a progress bar."""
    names = ["direct" if part == "real" else part for part in parts] or ["ideal"]
    return (", ".join(names[:-1]) + " and " if len(names) > 1 else "") + names[-1] + " runs"


def _piece_rows(part, method: str) -> InputRows:
    """A piece's inputs as the rows the compiled loop reads in place (a chunk of the
    interpolated truth already holds them so: no copy)."""
    midpoints = None if method == "euler" else np.ascontiguousarray(part.midpoints.T)
    return InputRows(np.ascontiguousarray(part.inputs.T), midpoints)


def chunk_size(records: int) -> int:
    """Recorded samples per compiled call: a power of two from 32 to 1024, about 1/64 of
    the run (few Python round trips on long runs, few compiled variants overall)."""
    size = 32
    while size < 1024 and size * 128 <= records:
        size *= 2
    return size


def _check_initial(model: Model, xr0: np.ndarray) -> None:
    bad = ~np.isfinite(xr0)
    if bad.any():
        k = int(np.argmax(bad.any(axis=1)))
        raise DomainError(f"the real system's initial {model.error_states[k].name} is NaN or "
                          "infinite: initial errors too large")


def _check_start_matrices(model: Model, trajectory: Trajectory, active: np.ndarray) -> None:
    """Refuse a linear or refined run whose F, or whose G in a column of a source in use
    (``active``, shape (ns,)), is not finite at t = 0, naming the entries.

    Such a matrix (a derivative 0/0, as of a drag term |V|·V at V = 0) makes every
    linear error NaN from the first step; the run would report that as leaving the
    domain a step later, with numpy's warnings about the generated code before it.

    Raises
    ------
    DomainError
        One line: the matrix, the time, the trajectory and the entries (row, column).
    """
    found = _nonfinite_matrix(model, trajectory.start_state, trajectory.start_inputs,
                              trajectory.parameters, active)
    if found is not None:
        symbol, listed = found
        raise DomainError(f"{symbol} of {model.name} is not finite at t = 0 s "
                          f"({trajectory.description}) in {listed}; {WHY}, so the "
                          "linear and refined runs cannot start from it: write the "
                          "term smoothly there, or start the motion elsewhere")


def _nonfinite_matrix(model: Model, x: np.ndarray, u: np.ndarray, p: np.ndarray,
                      active: np.ndarray) -> tuple[str, str] | None:
    """``("F", "F[a, b] and F[c, d]")`` when F at the point ``(x, u, p)`` (shapes (n,),
    (nu,), (np,)), or else G in a column of a source in use (``active``, shape (nw,)),
    is not finite there (evaluated without numpy's warnings); None when both are finite
    or the point is outside the model's domain (the run's own checks say where)."""
    states = [e.name for e in model.error_states]
    try:
        with np.errstate(all="ignore"):
            F = np.asarray(model.state_matrix(x, u, p), dtype=float)
            G = np.asarray(model.source_matrix(x, u, p), dtype=float)
    except DomainError:
        return None
    sources = [s.name for s in model.sources]
    for symbol, matrix, columns, used in (("F", F, states, None), ("G", G, sources, active)):
        listed = nonfinite_entries(symbol, matrix, states, columns, used)
        if listed is not None:
            return symbol, listed
    return None


def _matrix_detail(sim: Simulation, first: int, run: str) -> str | None:
    """The line that refuses a linear or refined run (``run``) whose states became NaN
    or infinite between the records ``first - 1`` and ``first`` because F (or G in a
    column of a source in use) is not finite at the ideal run's state there (a
    derivative 0/0 the motion reaches later, as a drag |V|·V when the speed passes
    through 0), naming the entries and the recorded time; None when F and G are finite
    at both records (a growing error, or a point between them)."""
    model, dt = sim.model, sim.stride * sim.trajectory.tau
    active = np.any(sim.sources != 0, axis=1)
    inputs = sim._recorded_inputs(slice(max(first - 1, 0), first + 1))[:, :, 0]
    for k, record in enumerate(range(max(first - 1, 0), first + 1)):
        x = sim.ideal[:, record, 0]
        if not np.all(np.isfinite(x)):
            return None
        found = _nonfinite_matrix(model, x, inputs[:, k], sim.trajectory.parameters, active)
        if found is not None:
            symbol, listed = found
            t = record * dt
            return (f"{symbol} of {model.name} is not finite at t = {t:.6g} s "
                    f"({t / 3600:.4g} h) along the motion ({sim.trajectory.description}) "
                    f"in {listed}; {WHY}, so the {run} run became NaN there: write the "
                    "term smoothly there, or choose a motion that does not pass that point")
    return None


def _domain_check(model: Model, parts: Sequence[str], platform: str) -> PieceCheck:
    """``check(states, margins)``: True when a piece of a run's records (the loop's
    states ``[x, x̃?, e?, e₂?, ...]``, shape (nz, r + 1, b), and margins, shape (r, b))
    holds something :func:`_check_domain` refuses: a margin not above 0 (NaN included),
    a NaN or infinite state of the runs (the carried sines and cosines are not looked
    at) or, with the real run, a platform angle beyond its limit."""
    n, ne = len(model.states), len(model.error_states)
    runs = n + len(parts) * ne
    angles, limit, _ = _platform_limit(model, platform)
    angles = [n + k for k in angles] if "real" in parts else []

    def check(states: np.ndarray, margins: np.ndarray) -> bool:
        return bool(not np.all(margins > 0) or not np.all(np.isfinite(states[:runs]))
                    or (angles and np.any(np.abs(states[angles]) > limit)))

    return check


def _check_domain(sim: Simulation, margins: np.ndarray) -> None:
    """Raise if any recorded run left the domain or became NaN (first time, quantity).

    :func:`_domain_check` tells whether a piece of records holds anything refused here;
    the two must agree."""
    model = sim.model
    dt = sim.stride * sim.trajectory.tau
    first, detail, flight, matrix = None, "", "", None
    bad_margin = ~(margins > 0)  # NaN counts as bad
    if bad_margin.any():
        r = int(np.argmax(bad_margin.any(axis=1)))
        first = r + 1
        detail, flight = _margin_detail(sim, r + 1, int(np.argmax(bad_margin[r])))
    labels = {"ideal": "ideal-work state", "real": "real-work state",
              "linear": "linear error state", "refined": "refined error state"}
    for name, label in labels.items():
        states = getattr(sim, name)
        if states is None:
            continue
        finite = np.all(np.isfinite(states), axis=(0, 2))
        if not finite.all():
            r = int(np.argmin(finite))
            if first is None or r < first:
                n = len(model.states)
                names = {"ideal": [s.name for s in model.states],
                         "real": [f"computed {s.name}" for s in model.states]
                         + [s.name for s in model.error_states[n:]]}.get(
                             name, [s.name for s in model.error_states])
                k = int(np.argmax((~np.isfinite(states[:, r])).any(axis=1)))
                first, detail, flight = r, f"{label} {names[k]} became NaN or infinite", ""
                matrix = (_matrix_detail(sim, r, name) if name in ("linear", "refined")
                          and r > 0 else None)
    if sim.real is not None:  # platform angles beyond where the platform form holds
        angles, limit, why = _platform_limit(model, sim.platform)
        if angles:
            large = np.abs(sim.real[angles]) > limit
            if large.any():
                r = int(np.argmax(large.any(axis=(0, 2))))
                if first is None or r < first:
                    first, flight, matrix = r, "", None
                    detail = _platform_detail(model, sim.real[:, r], angles, limit, why)
    if first is not None:
        t0, t1 = (first - 1) * dt, first * dt
        if first == 0:  # the recorded start: the initial errors themselves
            raise DomainError(f"the system starts outside its domain (t = 0 s, the initial "
                              f"errors): {detail}")
        when = f"at t = {t1:.6g} s" if sim.stride == 1 else (
            f"between t = {t0:.6g} s and {t1:.6g} s")
        if matrix is not None:  # F not finite where the motion took it: no domain left
            raise DomainError(matrix)
        if flight:  # the true motion's own doing: no step or mode to blame
            raise DomainError(f"the flight takes the {model.name} model {flight} {when} "
                              f"({t1 / 3600:.4g} h): {detail}")
        hint = _step_hint(sim) or _growth_hint(sim, t1)
        raise DomainError(f"the system left its domain {when} ({t1 / 3600:.4g} h): "
                          f"{detail}{hint}")


STEP_STABILITY = {"rk4": 2.785, "euler": 2.0}
"""How far (|λ|·step) each scheme's stability region reaches along the negative real
axis: classical RK4 is stable for a decaying mode e^{λt} only while |λ|·step is below
about 2.785, Euler's method below 2."""


def _amplification(method: str, z: np.ndarray) -> np.ndarray:
    """Modulus of the growth factor of one step of ``method`` on x' = λx, z = λ·step."""
    if method == "euler":
        return np.abs(1 + z)
    return np.abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24)


def _step_hint(sim: Simulation) -> str:
    """``"; the step of 600 s is beyond RK4's stability for F's fastest mode (…): choose a
    step of at most … s"`` when a mode of F at t = 0 that the equations damp (or hold)
    grows in the scheme's steps (its amplification per step exceeds 1 and exceeds the
    true e^{Re λ·step} by far), so the run's blow-up is the step's, not the physics'; else
    ``""``."""
    from ins_errors.numeric.linear_system import start_state_matrix
    from ins_errors.units import nice_below

    method, step = sim.method, float(sim.trajectory.tau)
    try:
        f = start_state_matrix(sim.model, sim.trajectory)
    except (InsErrorsError, ArithmeticError, ValueError):  # no F to read: no hint
        return ""
    if not f.size or not np.all(np.isfinite(f)) or step <= 0:
        return ""
    lam = np.linalg.eigvals(f)
    z = lam * step
    with np.errstate(over="ignore"):
        true_growth = np.exp(np.minimum(z.real, 700.0))
    false = (_amplification(method, z) > np.maximum(1.0, 2.0 * true_growth))
    if not false.any():
        return ""
    fastest = float(np.abs(lam[false]).max())
    limit = STEP_STABILITY.get(method, STEP_STABILITY["rk4"])
    bound = limit / float(np.abs(lam).max())
    suggested = nice_below(bound / 2)
    name = "RK4" if method == "rk4" else "Euler's method"
    return (f"; the step of {step:g} s is beyond {name}'s stability for F's fastest mode "
            f"(|λ| = {fastest:.3g}/s: |λ|·step = {fastest * step:.3g}, stable only below "
            f"about {limit:g} on the real axis), so the steps themselves blew up; choose a "
            f"step below {bound:.3g} s, e.g. {suggested:g} s")


def _growth_hint(sim: Simulation, t_left: float) -> str:
    """``"; F at the start has a mode that grows ×e every …, the likely cause; `ins-errors
    modes M` names the mode; …"`` (on a moving base: the mode of F at the motion's moving
    start state, without the pointer to ``modes``, which analyses the static base) when
    F at t = 0 has a mode that grew by
    :data:`~ins_errors.numeric.linear_system.GROWTH_WARNED` e-foldings or more before
    the run left its domain at ``t_left`` (s), naming any damping gain left at 0; else
    ``""``."""
    from ins_errors.numeric.linear_system import (
        GROWTH_WARNED,
        growing_mode_text,
        modes_pointer,
        start_growth_rate,
        undamped_remedy,
    )

    try:
        rate = start_growth_rate(sim.model, sim.trajectory)
    except (InsErrorsError, ArithmeticError, ValueError):  # no F to read: no hint
        return ""
    if not rate * t_left >= GROWTH_WARNED:
        return ""
    from ins_errors.model_lookup import command_name

    p, static = sim.trajectory.parameters, sim.trajectory.constant
    return (f"; {growing_mode_text(rate, static)}, the likely cause"
            f"{modes_pointer(command_name(sim.model), static)}{undamped_remedy(sim.model, p)}")


def _platform_limit(model: Model, platform: str) -> tuple[list[int], float, str]:
    """The platform angles (indices into the error states) that have a limit on this
    platform, the limit (rad) and why it holds."""
    n = len(model.states)
    angles = [k for k in range(n, len(model.error_states))
              if model.error_states[k].unit == "rad"]
    if platform == "small_angle":
        return angles, SMALL_ANGLE_LIMIT, ("beyond the small-angle platform matrix (the "
                                           "exact platform, the default, has no such limit)")
    # z-y-x angles: only alpha_y has a singular value
    if not model.has_small_angle_platform:  # a model file writes its own kinematics
        return angles[1:2], EULER_LIMIT, (
            "a quarter turn, where a platform's z-y-x angles are singular and no error "
            "analysis holds (the limit of the built-in platforms, applied to the model's "
            "second platform angle)")
    return angles[1:2], EULER_LIMIT, "near the singular ±90° of the exact platform's z-y-x angles"


def _platform_detail(model: Model, real: np.ndarray, angles: list[int], limit: float,
                     why: str) -> str:
    """The first platform angle of ``real`` (shape (ne, B), one record) beyond ``limit``,
    with its largest size over the cases."""
    large = np.abs(real[angles]) > limit
    row = int(np.argmax(large.any(axis=1)))
    k = angles[row]
    size = float(np.max(np.abs(real[k])))
    return (f"platform angle {model.error_states[k].name} = {np.degrees(size):.4g}° exceeds "
            f"{limit:.4g} rad ({np.degrees(limit):.4g}°), {why}")


def _check_initial_platform(model: Model, xr0: np.ndarray, platform: str) -> None:
    """Refuse initial platform angles (``xr0`` shape (ne, B)) beyond the platform's limit
    before anything runs."""
    angles, limit, why = _platform_limit(model, platform)
    if angles and np.any(np.abs(xr0[angles]) > limit):
        raise DomainError("the system starts outside its domain (t = 0 s, the initial "
                          f"errors): {_platform_detail(model, xr0, angles, limit, why)}")


def _margin_detail(sim: Simulation, record: int, case: int) -> tuple[str, str]:
    """What left the domain at ``record`` (case ``case``), and ``""`` or, when the true
    motion itself is the cause, what the flight does to the model: "out of its domain"
    when the ideal (error-free) system leaves too; "to the edge of its domain" when the
    real system leaves and the motion has moved the failing condition's margin (the
    model's domain expression) from its value at the start further towards 0 than the
    errors moved it on from there."""
    model, n = sim.model, len(sim.model.states)
    u = sim._recorded_inputs()[:, record, 0]
    p = sim.trajectory.parameters
    messages = model.meta.DOMAIN

    def extra(message: str, values: np.ndarray) -> str:
        return f" (|u31| = {abs(values[2]):.6g})" if "u31" in message and n > 2 else ""

    ideal = sim.ideal[:, record, case]
    if np.all(np.isfinite(ideal)):
        margins = np.asarray(model.numpy.domain_margins(ideal, u, p))
        for k, message in enumerate(messages):
            if not margins[k] > 0:
                return (f"the ideal (error-free) system, i.e. the true motion, reaches "
                        f"{message}{extra(message, ideal)}; no error analysis holds there, "
                        "whatever the error sources", "out of its domain")
    for label, state in (("real system", None if sim.real is None else sim.real[:n]),
                         ("ideal system", sim.ideal)):
        if state is None:
            continue
        values = state[:, record, case]
        if not np.all(np.isfinite(values)):
            bad = [model.states[k].name for k in range(n) if not np.isfinite(values[k])]
            return f"{label} state {bad[0]} became NaN or infinite", ""
        margins = np.asarray(model.numpy.domain_margins(values, u, p))
        for k, message in enumerate(messages):
            if not margins[k] > 0:
                line = f"{label}: {message}{extra(message, values)}"
                if label == "real system" and np.all(np.isfinite(ideal)):
                    start = float(np.asarray(model.numpy.domain_margins(
                        sim.ideal[:, 0, case], sim._recorded_inputs()[:, 0, 0], p))[k])
                    there = float(np.asarray(model.numpy.domain_margins(ideal, u, p))[k])
                    # the motion's part of the way to the boundary against the errors'
                    if start - there > there - float(margins[k]):
                        return (f"{line}; the true motion (the ideal, error-free system) "
                                f"took that condition's margin, the model's domain "
                                f"expression, from {start:.3g} at the start to {there:.3g} "
                                f"there, the errors only the rest of the way, so the "
                                "flight, not a growing error, is the cause",
                                "to the edge of its domain")
                return line, ""
    return "a state crossed the domain boundary between two recorded samples", ""


def linear_exact(model: Model, trajectory: Trajectory, sources,
                 record_interval: float | None = None) -> ErrorCurves:
    """Linear error run on a static base, stepped exactly with the matrix exponential.

    ``e[j+1] = Φ e[j] + Γ w`` with ``Φ = exp(F Δt)``, ``Γ = ∫ exp(F s) ds G`` over the
    recording interval Δt: no discretisation error at all (the continuous-time solution).

    Raises
    ------
    StepError
        If the trajectory is not time-invariant.
    """
    if not trajectory.constant:
        raise StepError("exact discretisation needs a time-invariant (static-base) trajectory")
    w = source_cases(model, sources)
    stride = record_stride(record_interval, trajectory.tau, trajectory.n_steps)
    dt = stride * trajectory.tau
    x, u, p = trajectory.start_state, trajectory.start_inputs, trajectory.parameters
    F, G = model.state_matrix(x, u, p), model.source_matrix(x, u, p)
    Phi, Gamma = exact_discretisation(F, G, dt)
    E = model.initial_error_matrix(trajectory.initial_conditions, u, p)
    R = trajectory.n_steps // stride
    e = np.empty((F.shape[0], R + 1, w.shape[1]))
    e[:, 0] = E @ w
    drive = Gamma @ w
    for j in range(R):
        e[:, j + 1] = Phi @ e[:, j] + drive
    sim = Simulation(model, trajectory, "exact", stride, w,
                     np.repeat(np.repeat(x[:, None, None], R + 1, axis=1), w.shape[1], axis=2),
                     linear=e)
    return sim.linear_errors()
