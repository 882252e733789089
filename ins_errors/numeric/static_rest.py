"""A static base for any model: the constant ideal state and the inputs that hold it.

The kinematic motion generators (:mod:`ins_errors.numeric.trajectories`) set inputs by
name (apparent accelerations ``a_*``, ``a_zeta``, the height ``h``, ``V_zeta``). A model
with other inputs (a researcher's strapdown INS fed body rates and specific forces) has
a static base found from its own equations (its moving flights: the same idea along a
planned flight, :mod:`ins_errors.numeric.model_flight`):

1. the initial conditions ``c`` come from the static description by name: ``latitude``,
   ``longitude``, ``height`` (or ``h``), ``heading``, ``roll`` and ``pitch`` (zero: a
   level vehicle), and zero for every velocity (an initial condition in m/s);
2. the true state is the model's own initial-state map ``x0 = initial_state(c, u, p)``;
3. the constant inputs solve ``f(x0, u) = 0``, ``f`` the ideal-work right-hand side,
   in the least-squares sense (Gauss-Newton from a prior: the height for inputs named
   ``h``, ``height`` or ``h_ref``, zero for the others, so an input the equations do
   not determine keeps its prior); ``f`` is affine in ``u`` for an INS (the instruments'
   signals enter linearly), so one step solves it, and the steps repeat while ``x0``
   still changes with ``u``.

If no constant input holds the state still (a state that moves at rest whatever the
inputs, such as a free-azimuth angle following the Earth's rotation), the residual
``f(x0, u)`` is larger than :data:`REST_TOLERANCE` of the terms it sums (or than
:data:`~ins_errors.numeric.trajectories.STATIC_TOLERANCE`) and the static base is
refused in one line naming the state.

For ``strapdown_ned`` the solution is the strapdown truth's static signals: the body
rate is the Earth rate in body axes and the specific force minus gravity.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import casadi as ca
import numpy as np

from ins_errors.errors import DomainError
from ins_errors.numeric.model import Model

FILLED = ("latitude", "longitude", "height", "h", "heading", "roll", "pitch")
"""Initial conditions a static base fills by name (besides zero velocities)."""

HEIGHT_INPUTS = ("h", "height", "h_ref")
"""Inputs whose prior value is the static base's height (the height an external
reference, e.g. a barometer, reports); the others start from zero."""

REST_TOLERANCE = 1e-9
"""Largest |f_i(x0, u)| relative to the sum of the magnitudes of the terms of f_i
(:func:`rest_terms`) for which a state is at rest."""

MAX_ITERATIONS = 30
"""Gauss-Newton steps at most (an input-dependent initial state may need a few)."""


def _is_velocity(unit: str) -> bool:
    """True when ``unit`` (as a model states it) is a velocity (length per time)."""
    from ins_errors.units import same_dimension

    return same_dimension(unit, "m/s")


def static_conditions(model: Model, latitude: float, longitude: float, heading: float,
                      height: float) -> tuple[np.ndarray, frozenset[str]]:
    """The initial conditions ``c`` of a static base, by name.

    Parameters
    ----------
    model : Model
    latitude, longitude, heading : float
        rad.
    height : float
        m.

    Returns
    -------
    c : numpy.ndarray, shape (nc,)
    references : frozenset of str
        The reference values of the description the conditions use (``latitude``,
        ``longitude``, ``heading``, ``height``).

    Raises
    ------
    MotionError
        One line naming the initial conditions a static base cannot fill.
    """
    from ins_errors.numeric.trajectories import MotionError

    values = {"latitude": latitude, "longitude": longitude, "height": height, "h": height,
              "heading": heading, "roll": 0.0, "pitch": 0.0}
    c, missing, used = [], [], set()
    for condition in model.initial_conditions:
        if condition.name in values:
            c.append(values[condition.name])
            if condition.name not in ("roll", "pitch"):
                used.add("height" if condition.name == "h" else condition.name)
        elif _is_velocity(condition.unit):
            c.append(0.0)
        else:
            missing.append(condition.name)
    if missing:
        raise MotionError(f"a static base cannot set the initial condition(s) "
                          f"{', '.join(missing)} of model {model.name!r}: it fills "
                          "latitude, longitude, height (or h), heading, roll and pitch "
                          "(level) and zero velocities (m/s)")
    return np.array(c, dtype=float), frozenset(used)


@cache
def rest_functions(model_key: str) -> tuple[Callable, Callable]:
    """``rest(x, u, p) -> (f, df/du, |terms|)`` and ``start(c, u, p) -> x0``, compiled
    from the model's generated CasADi functions."""
    from ins_errors.numeric.model import load_model

    model = load_model(model_key)
    fn = model.casadi.function
    x = ca.SX.sym("x", len(model.states))
    u = ca.SX.sym("u", len(model.inputs))
    p = ca.SX.sym("p", len(model.parameters))
    f = fn("ideal_rhs")(x, u, p)
    jacobian = ca.jacobian(f, u)
    at_zero = ca.substitute(f, u, ca.DM.zeros(len(model.inputs)))
    rest = ca.Function("static_rest", [x, u, p], [f, jacobian, at_zero])
    return rest, fn("initial_state")


def rest_terms(jacobian: np.ndarray, at_zero: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The magnitude of the terms each row of ``f(x0, u) = f(x0, 0) + J u`` sums (for an
    affine ``f``): ``|f(x0, 0)| + Σ_j |J_ij u_j|``, shape (n,)."""
    return np.abs(at_zero) + np.abs(jacobian) @ np.abs(u)


def static_rest(model: Model, latitude: float, longitude: float, heading: float,
                height: float, p: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, frozenset[str]]:
    """The constant true state and inputs of a static base, from the model's equations.

    Parameters
    ----------
    model : Model
    latitude, longitude, heading : float
        rad.
    height : float
        m.
    p : numpy.ndarray, shape (np,)
        Parameters, SI (checked).

    Returns
    -------
    x0 : numpy.ndarray, shape (n,)
        True state at rest.
    u0 : numpy.ndarray, shape (nu,)
        Constant inputs with ``f(x0, u0) = 0``.
    c0 : numpy.ndarray, shape (nc,)
        Initial conditions.
    references : frozenset of str
        The reference values of the description the run depends on.

    Raises
    ------
    MotionError
        An initial condition a static base cannot fill, or no constant input holds the
        state at rest (naming the state with the largest residual).
    DomainError
        The state or inputs are NaN or infinite.
    """
    from ins_errors.numeric.trajectories import MotionError

    c, references = static_conditions(model, latitude, longitude, heading, height)
    rest, start = rest_functions(model.key)
    names = [i.name for i in model.inputs]
    u = np.array([height if name in HEIGHT_INPUTS else 0.0 for name in names])
    if any(name in HEIGHT_INPUTS for name in names):
        references |= {"height"}
    x = np.asarray(start(c, u, p), dtype=float).ravel()
    for iteration in range(MAX_ITERATIONS):
        f, jacobian, _ = (np.asarray(v, dtype=float) for v in rest(x, u, p))
        if not (np.all(np.isfinite(f)) and np.all(np.isfinite(jacobian))):
            raise DomainError(f"model {model.name!r}: the ideal work is NaN or infinite at "
                              "the static base")
        step = np.linalg.lstsq(jacobian, -f.ravel(), rcond=None)[0]
        u = u + step
        moved = np.asarray(start(c, u, p), dtype=float).ravel()
        # one more step after x0 stops moving refines the least-squares solution
        scale = np.maximum(np.abs(x), np.abs(x).max(initial=0.0))
        settled = iteration >= 1 and np.all(np.abs(moved - x) <= 1e-15 * scale)
        x = moved
        if settled:
            break
    f, jacobian, at_zero = (np.asarray(v, dtype=float).ravel() if k != 1 else
                            np.asarray(v, dtype=float) for k, v in enumerate(rest(x, u, p)))
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(u)) and np.all(np.isfinite(f))):
        raise DomainError(f"model {model.name!r}: the static-base state or inputs are NaN "
                          "or infinite")
    from ins_errors.numeric.trajectories import STATIC_TOLERANCE

    allowed = np.maximum(REST_TOLERANCE * rest_terms(jacobian, at_zero, u), STATIC_TOLERANCE)
    excess = np.abs(f) / allowed
    if excess.max() > 1.0:
        k = int(np.argmax(excess))
        state = model.states[k]
        raise MotionError(f"model {model.name!r} has no rest at the static base: no constant "
                          f"input holds {state.name!r} still (d{state.name}/dt = {f[k]:.3g} "
                          f"{state.unit}/s left by the best inputs)")
    return x, u, c, references
