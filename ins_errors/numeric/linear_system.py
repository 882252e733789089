"""The linear error equations of a model sampled along a motion (static or moving).

A :class:`LinearSystem` holds F, G, H (constant on a static base, per grid time along a
moving trajectory), the initial error matrix E, and the ideal state and inputs they were
evaluated at; covariance propagation (:mod:`ins_errors.analysis.covariance`) and the
linear Monte Carlo (:mod:`ins_errors.analysis.monte_carlo`) run on it.
"""

from __future__ import annotations

import math
from collections.abc import Collection
from dataclasses import dataclass, field

import numpy as np

from ins_errors.errors import InsErrorsError, ShapeError, unknown_name
from ins_errors.machine_memory import physical_memory, size_text


class LinearSystemError(InsErrorsError):
    """A motion or grid the linear error equations cannot be sampled on."""


@dataclass(frozen=True, eq=False)
class LinearSystem:
    """The linear error equations sampled on a uniform time grid.

    Compared by identity (``==`` is ``is``; hashable): it holds arrays, whose ``==``
    has no single truth value.

    Attributes
    ----------
    times : numpy.ndarray, shape (K+1,)
        Uniform grid, s, starting at 0.
    F : numpy.ndarray, shape (n, n) or (K+1, n, n)
        State matrix; 2-D means time-invariant.
    G : numpy.ndarray, shape (n, nw) or (K+1, n, nw)
        Source matrix over every model source.
    E : numpy.ndarray, shape (n, nw)
        Initial error matrix, ``x_e(0) = E w``.
    H : numpy.ndarray, shape (ny, n) or (K+1, ny, n)
        Output matrix.
    source_names : tuple of str
        The model's source names, in the column order of G and E.
    source_kinds : tuple of str
        The model's kind of each source (``"constant"`` or ``"initial"``).
    x, u : numpy.ndarray
        Ideal state (n_x, K+1) and inputs (n_u, K+1) the matrices were evaluated at
        (read-only views of one column on a static base).
    p : numpy.ndarray
        Parameters.
    labels : dict
        What the motion was (``"trajectory"``: its description), for reports.
    model_name : str
        How a command line names the model (``ins-errors modes NAME``), or ``""`` for
        equations not sampled from a model (a :class:`LinearSystem` built by hand).
    damping_remedy : str
        The clause naming the model's damping gains left at 0 in ``p``
        (:func:`undamped_remedy`: ``"; the damping gains k_h1, k_h2 are 0 ..."``), or
        ``""``; the growth warning of
        :func:`~ins_errors.analysis.covariance.propagate` ends with it.
    """

    times: np.ndarray
    F: np.ndarray
    G: np.ndarray
    E: np.ndarray
    H: np.ndarray
    source_names: tuple[str, ...]
    source_kinds: tuple[str, ...]
    x: np.ndarray
    u: np.ndarray
    p: np.ndarray
    labels: dict = field(default_factory=dict)
    model_name: str = ""
    damping_remedy: str = ""

    @property
    def time_invariant(self) -> bool:
        """True when F, G and H do not change along the grid."""
        return self.F.ndim == 2

    @property
    def step(self) -> float:
        """Grid step, s."""
        return float(self.times[1] - self.times[0])

    def source_index(self, name: str) -> int:
        """Column of the source ``name`` in G and E."""
        if name not in self.source_names:
            raise unknown_name("error source", name, self.source_names)
        return self.source_names.index(name)

    def at(self, matrix: np.ndarray, k: int) -> np.ndarray:
        """The matrix at grid index ``k`` (the same for a time-invariant system)."""
        return matrix if matrix.ndim == 2 else matrix[k]


WORKING_COPIES = 2
"""Peak memory of sampled equations over the arrays kept: building them takes working
copies of the same size (measured: a day at 1 s of orthodromic at rest, 344 MB kept, raised
the budget's peak by 632 MB, 1.84 times)."""
MEMORY_SHARE = 0.6
"""The largest share of the machine's physical memory that the equations sampled along a
moving base (F, G, H, state and inputs at every grid time) may take: beyond it the
covariance would swap or be killed by the system, so it is refused beforehand."""


def growth_rate(f: np.ndarray) -> float:
    """Largest real part of the eigenvalues of F (1/s); 0 when F is not finite.

    Parameters
    ----------
    f : ndarray, shape (n, n)
        A (frozen) system matrix, 1/s.
    """
    if not np.all(np.isfinite(f)) or not f.size:
        return 0.0
    return float(np.linalg.eigvals(f).real.max())


GROWTH_WARNED = 3.0
"""E-foldings over a run (growth rate times duration) of a growing mode of F at the start
from which the commands warn (a factor of 20)."""


GROWTH_SEEN = 0.5
"""On a moving base, a growing mode of F at the start is warned of only where the errors
along the motion grow at least at this share of its rate (F changes along the motion: a
mode of F frozen at one time need not be followed)."""


def transition_growth(system: LinearSystem) -> float:
    """Growth rate (1/s) of the sampled equations over their grid: the log of the largest
    modulus of the eigenvalues of the transition matrix Φ(T, 0) (the product of the
    steps' exponentials of F at the midpoints), over T. Eigenvalues do not depend on the
    units of the states; a stable or oscillating system gives about 0, a mode that
    grows as e^{rt} along the motion gives r (+inf where Φ overflows).

    Parameters
    ----------
    system : LinearSystem
        Sampled on a moving base (F of shape (K+1, n, n)); a time-invariant one gives the
        growth of its F (:func:`growth_rate`).
    """
    from ins_errors.numeric.blas_threads import import_limited

    if system.time_invariant:
        return growth_rate(system.F)
    expm = import_limited("scipy.linalg").expm
    step, n = system.step, system.F.shape[-1]
    phi = np.eye(n)
    middle = 0.5 * (system.F[1:] + system.F[:-1])
    with np.errstate(all="ignore"):
        for f in middle:
            phi = expm(f * step) @ phi
            if not np.all(np.isfinite(phi)):
                return math.inf
        largest = float(np.abs(np.linalg.eigvals(phi)).max())
    end = float(system.times[-1])
    return math.log(largest) / end if largest > 0 and end > 0 else -math.inf


def growth_warning(f: np.ndarray, duration: float, model_name: str, consequence: str,
                   span: str = "run", remedy: str = "", static: bool = True) -> str | None:
    """The one-line warning of errors that grow exponentially, or None.

    A growing mode of F (an undamped vertical channel, a sign slip that turns the Schuler
    loop into an exponential) makes every error grow by e^(rate t), whatever the sources.
    The sentence gives the e-folding time of F's fastest growing mode (:func:`growth_rate`)
    and the factor over the duration, says what that means for the command's numbers,
    and, on a static base, names the command that names the mode (``ins-errors modes``
    analyses the static base: on a moving one the sentence says the mode is of F at the
    motion's start state instead).

    Parameters
    ----------
    f : numpy.ndarray, shape (n, n)
        F at the start, 1/s (on a moving base F changes along the motion).
    duration : float
        Length of the run, s.
    model_name : str
        For ``ins-errors modes MODEL``.
    consequence : str
        What the growth does to the numbers, after "so every error grows with it and".
    span : str
        What ``duration`` is ("run": "over the 8 h run").
    remedy : str
        Added at the end (e.g. "; ..." naming damping gains).
    static : bool
        Whether ``f`` is F of a static base (the one ``ins-errors modes`` analyses); on a
        moving base it is F at the motion's start state.

    Returns
    -------
    str or None
        None when the mode grows by fewer than :data:`GROWTH_WARNED` e-foldings.
    """
    from ins_errors.time_text import duration_text

    rate = growth_rate(np.asarray(f, dtype=float))
    if duration <= 0 or rate * duration < GROWTH_WARNED:
        return None
    folds = rate * duration
    factor = f"{math.exp(folds):.3g}" if folds < 700.0 else f"e^{folds:.0f}"  # no overflow
    return (f"the error equations grow exponentially: {growing_mode_text(rate, static)} "
            f"(×{factor} over the "
            f"{duration_text(duration)} {span}), so every error grows with it and "
            f"{consequence}{modes_pointer(model_name, static)}{remedy}")


def growth_folds(system: LinearSystem, duration: float) -> tuple[float, float] | None:
    """The growing mode the commands warn of, or None: the growth rate of F at the start
    (1/s) and the e-foldings the error equations grow by over ``duration`` (s) along the
    motion.

    None when F at the start grows by fewer than :data:`GROWTH_WARNED` e-foldings, or, on
    a moving base, when the transition matrix over the grid grows at less than
    :data:`GROWTH_SEEN` of that rate (the equations do not follow that mode of F:
    orthodromic's delta_V_eta on an eastbound great circle). On a static base the
    e-foldings are rate × duration, on a moving one the transition matrix's growth rate
    (:func:`transition_growth`) times the duration.

    Parameters
    ----------
    system : LinearSystem
        The sampled equations.
    duration : float
        The span the errors grow over, s (a budget's operating time, a propagation's
        grid).
    """
    F = system.F if system.F.ndim == 2 else system.F[0]
    rate = growth_rate(F)
    if duration <= 0 or rate * duration < GROWTH_WARNED:
        return None
    if system.time_invariant:
        return rate, rate * duration
    along = transition_growth(system)
    if along < GROWTH_SEEN * rate:
        return None
    return rate, along * duration


def model_labels(model, p: np.ndarray) -> dict[str, str]:
    """The :class:`LinearSystem` fields that name ``model``: ``model_name`` (how a command
    line names it) and ``damping_remedy`` (:func:`undamped_remedy` at ``p``)."""
    from ins_errors.model_lookup import command_name

    return {"model_name": command_name(model), "damping_remedy": undamped_remedy(model, p)}


def start_state_matrix(model, trajectory) -> np.ndarray:
    """F at t = 0 of a trajectory, shape (ne, ne), 1/s.

    F is evaluated at the start state, the inputs at the start and the parameters:
    ``trajectory.start_inputs``, never ``inputs_at``, which stores a streamed motion
    whole. On a moving base F changes along the motion; this is its start.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        The model the trajectory was computed for.
    trajectory : ins_errors.numeric.trajectories.Trajectory
        The true motion.
    """
    x0, u0, p = trajectory.start_state, trajectory.start_inputs, trajectory.parameters
    return np.asarray(model.state_matrix(x0, u0, p), dtype=float)


def start_growth_rate(model, trajectory) -> float:
    """Growth rate of F at t = 0 of a trajectory (1/s; :func:`growth_rate` of
    :func:`start_state_matrix`)."""
    return growth_rate(start_state_matrix(model, trajectory))


def growing_mode_text(rate: float, static: bool = True) -> str:
    """``"F at the start has a mode that grows ×e every 9.498 min"`` (``rate`` in 1/s,
    positive): the clause :func:`growth_warning` and a run that left its domain share.

    On a moving base (``static`` False) F at the start is F of the motion's moving start
    state, not the static base's that ``ins-errors modes`` analyses, and the clause says
    so."""
    from ins_errors.time_text import duration_text

    where = ("F at the start" if static else
             "F at the motion's start (of its moving start state, not the static base's)")
    return f"{where} has a mode that grows ×e every {duration_text(1.0 / rate)}"


def modes_pointer(model_name: str, static: bool) -> str:
    """``"; `ins-errors modes M` names the mode"`` on a static base, else ``""``:
    ``ins-errors modes`` analyses F of the static base only, which need not have the mode
    F has at a moving motion's start."""
    return f"; `ins-errors modes {model_name}` names the mode" if static else ""


def _undamped(model, p: np.ndarray, names: Collection[str] | None = None) -> list:
    """The parameter descriptions (:class:`~ins_errors.numeric.model.Info`) of the
    model's damping gains that are 0 in ``p`` (only those of ``names`` if given)."""
    return [info for info, value in zip(model.parameters, p, strict=True)
            if info.damping_gain and value == 0 and (names is None or info.name in names)]


def undamped_gains(model, p: np.ndarray) -> list[str]:
    """The model's damping gains that are 0 in the parameter vector ``p``.

    A damping gain is a parameter its model flags ``damping_gain=True``
    (:class:`ins_errors.modeling.Parameter`; strapdown_ned's ``k_h1``, ``k_h2``: 0 leaves
    its vertical channel undamped).
    """
    return [info.name for info in _undamped(model, p)]


def undamped_remedy(model, p: np.ndarray, names: Collection[str] | None = None) -> str:
    """``"; the damping gains k_h1, k_h2 are 0 (undamped): set them, e.g. `-p
    k_h1=0.0293/s -p k_h2=4.42e-4/s^2` (a 300-s loop, damping 0.7)"`` for the gains of
    :func:`undamped_gains`, or ``""`` (a ``remedy`` of :func:`growth_warning`).

    The values and the phrase in parentheses are the gains' own ``example`` and
    ``example_gives`` (:class:`ins_errors.modeling.Parameter`); where a gain has no
    example, every gain is shown as ``-p NAME=…``. ``names`` limits the gains to those
    named (e.g. the gains a checked equation holds).

    ``model`` is anything whose ``parameters`` have ``name``, ``damping_gain``,
    ``example`` and ``example_gives``: a loaded model or a
    :class:`~ins_errors.modeling.ModelDefinition`.
    """
    gains = _undamped(model, p, names)
    if not gains:
        return ""
    names = ", ".join(g.name for g in gains)
    several = len(gains) > 1
    known = all(g.example for g in gains)
    options = " ".join(f"-p {g.name}={g.example if known else '…'}" for g in gains)
    if known:
        gives = "; ".join(dict.fromkeys(g.example_gives for g in gains if g.example_gives))
        example = f", e.g. `{options}`" + (f" ({gives})" if gives else "")
    else:
        example = f" (`{options}`)"
    return (f"; the damping gain{'s' if several else ''} {names} "
            f"{'are' if several else 'is'} 0 (undamped): set {'them' if several else 'it'}"
            + example)


def check_grid_memory(model, times: int, step: float) -> None:
    """Refuse a moving-base grid whose sampled equations would not fit in memory.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        The model whose F (ne, ne), G (ne, nw), H (ny, ne), state and inputs are kept at
        every grid time (with :data:`WORKING_COPIES` for the peak while they are built).
    times : int
        Grid times (steps + 1).
    step : float
        Grid step, s (for the suggested step).

    Raises
    ------
    LinearSystemError
        If they need more than :data:`MEMORY_SHARE` of the physical memory; the message
        gives the size and the shortest step that fits.
    """
    memory = physical_memory()
    if not memory:
        return
    ne = len(model.error_states)
    per_time = WORKING_COPIES * 8 * (ne * (ne + len(model.sources) + len(model.outputs))
                                     + len(model.states) + len(model.inputs))
    limit = MEMORY_SHARE * memory
    if times * per_time <= limit:
        return
    longer = step * math.ceil(times * per_time / limit)
    raise LinearSystemError(
        f"the error equations at {times:,} grid times need about "
        f"{size_text(times * per_time)}, more than {MEMORY_SHARE:.0%} of this machine's "
        f"{size_text(memory)}; choose a step of at least {longer:g} s "
        f"(or a shorter duration)")


def uniform_grid(duration: float, step: float) -> np.ndarray:
    """Times 0, step, ..., duration, s.

    Raises
    ------
    LinearSystemError
        A duration or step that is not a positive number of seconds, a step longer than
        the duration, or a duration that is not a whole number of steps (to
        :data:`~ins_errors.numeric.integrators.STEP_TOLERANCE` of a step, as
        :func:`~ins_errors.numeric.trajectories.trajectory` takes it): the message names
        the nearest durations that are, instead of running to one of them unsaid.
    """
    from ins_errors.numeric.integrators import StepError, step_count

    if not (np.isfinite(duration) and duration > 0):
        raise LinearSystemError(f"duration must be > 0 s, got {duration!r}")
    if not (np.isfinite(step) and 0 < step <= duration):
        raise LinearSystemError(f"step must be in (0, duration], got {step!r}")
    try:
        count = step_count(duration, step)
    except StepError as error:
        raise LinearSystemError(str(error)) from None
    return np.arange(count + 1) * step


def static_system(model, latitude: float, longitude: float = 0.0, heading: float = 0.0,
                  height: float = 0.0, gravity: float | None = None,
                  duration: float = 3600.0, step: float = 1.0,
                  p: np.ndarray | None = None) -> LinearSystem:
    """The error equations of a model at rest on the Earth (time-invariant).

    For a model fed apparent accelerations whose state stays constant at rest
    (``orthodromic``, ``north_pointing``, ``geodetic_vertical``, a model file such as
    ``examples/own_model/schuler_loop.py``): the initial conditions it has (latitude,
    longitude, heading; velocities zero) give the state, ``a_zeta`` (if the model has
    it) is ``gravity``, ``h`` is ``height``, and the other apparent-acceleration inputs
    (``a_*``) are solved for so that the ideal state stays at rest (least squares on the
    ideal equations, which are linear in them).

    Other models are refused with :class:`LinearSystemError`: a strapdown INS fed body
    rates and specific forces (``strapdown_ned``, a strapdown model file) and a model
    whose state moves at rest (``free_azimuth``: its wander angle turns with the Earth).
    Their static base is the motion generators' one, sampled by
    :func:`system_from_trajectory`::

        system_from_trajectory(model, trajectories.trajectory(
            model, trajectories.static_profile(latitude), duration, step))

    which takes every model (the commands build their static bases so).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        A loaded model.
    latitude, longitude, heading : float
        Site and the trihedron's track angle, rad (where the model has them).
    height : float
        Height above the ellipsoid, m.
    gravity : float, optional
        Apparent acceleration along the vertical, m/s² (a_ζ, where the model has it).
        Default: the one the motion generators give a static base of the model
        (:func:`static_base_gravity`: Somigliana's formula on the model's own a and e²,
        as ``compare``, ``run`` and :func:`~ins_errors.analysis.modes.static_modes`
        use), or 9.81 m/s² for a model they do not fly.
    duration, step : float
        Length and step of the time grid, s.
    p : numpy.ndarray, optional
        Parameter vector (default: the model's defaults).
    """
    from ins_errors.numeric.trajectories import check_height

    check_height(float(height), "static base height")
    p = model.parameter_vector() if p is None else np.asarray(p, dtype=float)
    given = {"latitude": latitude, "longitude": longitude, "heading": heading}
    known = {i.name for i in model.initial_conditions}
    c = model.initial_condition_vector(**{k: v for k, v in given.items() if k in known})
    inputs = [i.name for i in model.inputs]
    if gravity is None and "a_zeta" in inputs:
        gravity = static_base_gravity(model, latitude, longitude, heading, height, p)
    u = model.input_vector(**{k: v for k, v in (("a_zeta", gravity), ("h", height))
                              if k in inputs})
    x = model.initial_state(c, u, p)
    free = [k for k, name in enumerate(inputs) if name.startswith("a_") and name != "a_zeta"]
    r0 = model.numpy.ideal_rhs(x, u, p)
    if free:
        J = np.empty((len(r0), len(free)))
        for column, k in enumerate(free):
            probe = u.copy()
            probe[k] += 1.0
            J[:, column] = model.numpy.ideal_rhs(x, probe, p) - r0
        u[free] = np.linalg.lstsq(J, -r0, rcond=None)[0]
    rates = model.numpy.ideal_rhs(x, u, p)
    if np.max(np.abs(rates)) > 1e-12 * max(1.0, np.max(np.abs(r0))):
        why = ("its state moves at rest" if free else
               "its inputs are not apparent accelerations a_*")
        raise LinearSystemError(f"static_system: no apparent accelerations a_* keep the "
                                f"ideal state of {model.name} at rest ({why}); build its "
                                "static base as the commands do: "
                                "system_from_trajectory(model, trajectories.trajectory("
                                "model, trajectories.static_profile(latitude), duration, "
                                "step))")
    times = uniform_grid(duration, step)
    return LinearSystem(
        times=times,
        F=model.state_matrix(x, u, p), G=model.source_matrix(x, u, p),
        E=model.initial_error_matrix(c, u, p), H=model.output_matrix(x, u, p),
        source_names=tuple(i.name for i in model.sources),
        source_kinds=tuple(i.kind for i in model.sources),
        # the same state and inputs at every time: read-only views, not copies
        x=np.broadcast_to(x[:, None], (len(x), len(times))),
        u=np.broadcast_to(u[:, None], (len(u), len(times))),
        p=p, labels={"trajectory": f"static base at φ={np.degrees(latitude):.4g}°",
                     "latitude": latitude, "height": height},
        **model_labels(model, p),
    )


STATIC_GRAVITY_FALLBACK = 9.81
"""a_ζ (m/s²) of :func:`static_system` for a model the motion generators do not fly."""


def static_base_gravity(model, latitude: float, longitude: float = 0.0,
                        heading: float = 0.0, height: float = 0.0,
                        p: np.ndarray | None = None) -> float:
    """a_ζ of the motion generators' static base of ``model``, m/s².

    Somigliana's formula γ_e (1 + k sin² φ)/√(1 − e² sin² φ) with WGS-84's γ_e and k
    on the model's own a and e² (:func:`~ins_errors.models.earth.normal_gravity`, with
    its height series) at the site, as ``compare``, ``run``, ``modes``,
    :func:`static_system` and the closed forms take it by default, or
    :data:`STATIC_GRAVITY_FALLBACK` for a model the generators do not fly. On an
    ellipsoid near WGS-84's that is about its normal gravity; on a sphere (e² = 0) it is
    γ_e (1 + k sin² φ), not WGS-84 normal gravity (9.78977 against 9.80620 m/s² at
    45°) nor the gravity of any Earth of the model's own.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        A loaded model with an input ``a_zeta``.
    latitude, longitude, heading : float
        Site and track angle, rad.
    height : float
        Height above the ellipsoid, m.
    p : numpy.ndarray, optional
        Parameter vector (default: the model's defaults).
    """
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric import trajectories as tr

    try:
        start = tr.trajectory(model, tr.static_profile(latitude, longitude, heading, height),
                              1.0, 1.0, p=p).start_inputs
    except InsErrorsError:
        return STATIC_GRAVITY_FALLBACK
    return float(start[model.index("inputs", "a_zeta")])


def trajectory_system(model, times: np.ndarray, x: np.ndarray, u: np.ndarray,
                      c: np.ndarray, p: np.ndarray | None = None) -> LinearSystem:
    """The error equations along a sampled ideal trajectory (time-varying).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        A loaded model.
    times : numpy.ndarray, shape (K+1,)
        Uniform grid, s, starting at 0.
    x : numpy.ndarray, shape (n_x, K+1)
        Ideal state along the grid.
    u : numpy.ndarray, shape (n_u, K+1)
        True inputs along the grid.
    c : numpy.ndarray, shape (n_c,)
        Initial conditions of the run (for E).
    p : numpy.ndarray, optional
        Parameters.
    """
    p = model.parameter_vector() if p is None else np.asarray(p, dtype=float)
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or len(times) < 2 or times[0] != 0:
        raise ShapeError("trajectory_system: times must be a 1-D grid starting at 0")
    steps = np.diff(times)
    if np.any(steps <= 0) or np.ptp(steps) > 1e-9 * steps[0]:
        raise ShapeError("trajectory_system: times must be a uniform increasing grid")
    x, u = np.asarray(x, dtype=float), np.asarray(u, dtype=float)
    if x.shape != (len(model.states), len(times)) or u.shape != (len(model.inputs),
                                                                 len(times)):
        raise ShapeError(f"trajectory_system: x must be ({len(model.states)}, {len(times)}) "
                         f"and u ({len(model.inputs)}, {len(times)}), got {x.shape}, {u.shape}")
    F = np.moveaxis(model.state_matrix(x, u, p), -1, 0)
    G = np.moveaxis(model.source_matrix(x, u, p), -1, 0)
    H = np.moveaxis(model.output_matrix(x, u, p), -1, 0)
    E = model.initial_error_matrix(c, u[:, 0], p)
    return LinearSystem(times=times, F=F, G=G, E=E, H=H,
                        source_names=tuple(i.name for i in model.sources),
                        source_kinds=tuple(i.kind for i in model.sources),
                        x=x, u=u, p=p, labels={"trajectory": "moving"},
                        **model_labels(model, p))


def system_from_trajectory(model, trajectory, step: float | None = None) -> LinearSystem:
    """The error equations along a :class:`~ins_errors.numeric.trajectories.Trajectory`.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        The model the trajectory was computed for.
    trajectory : Trajectory
        True motion (static base: constant inputs and state).
    step : float, optional
        Covariance grid step, s: a whole multiple of the trajectory's step that divides
        its duration (default: the trajectory's step).
    """
    if trajectory.model != model.key:
        raise ShapeError(f"trajectory was computed for model {trajectory.model!r}, "
                         f"not {model.key!r}")
    tau, count = trajectory.tau, trajectory.n_steps
    stride = 1 if step is None else round(step / tau)
    if stride < 1 or abs(stride * tau - (step or tau)) > 1e-9 * tau or count % stride:
        raise LinearSystemError(f"covariance step {step!r} s must be a whole multiple of the "
                              f"trajectory step {tau} s that divides its duration")
    times = np.arange(count // stride + 1) * stride * tau
    if not trajectory.constant:
        check_grid_memory(model, len(times), stride * tau)
    p, c = trajectory.parameters, trajectory.initial_conditions
    names = (tuple(i.name for i in model.sources), tuple(i.kind for i in model.sources))
    if trajectory.constant:
        x, u = trajectory.truth[:, 0], trajectory.inputs[:, 0]
        return LinearSystem(
            times=times, F=model.state_matrix(x, u, p), G=model.source_matrix(x, u, p),
            E=model.initial_error_matrix(c, u, p), H=model.output_matrix(x, u, p),
            source_names=names[0], source_kinds=names[1],
            x=np.repeat(x[:, None], len(times), 1), u=np.repeat(u[:, None], len(times), 1),
            p=p, labels={"trajectory": trajectory.description}, **model_labels(model, p))
    steps = np.arange(0, count + 1, stride)
    if trajectory.is_streamed:  # pick the grid's samples while the motion streams by
        x = np.empty((len(model.states), len(steps)))
        u = np.empty((len(model.inputs), len(steps)))
        x[:, 0], u[:, 0] = trajectory.start_state, trajectory.start_inputs
        piece = stride * max(1, 65536 // stride)
        for chunk in trajectory.chunks(piece):
            first, last = chunk.start // stride + 1, (chunk.start + chunk.size) // stride
            x[:, first:last + 1] = chunk.truth[:, stride::stride]
            u[:, first:last + 1] = chunk.inputs[:, stride::stride]
    else:
        x, u = trajectory.truth[:, steps], trajectory.inputs_at(steps)
    system = trajectory_system(model, times, x, u, c, p)
    system.labels["trajectory"] = trajectory.description
    return system
