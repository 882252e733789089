"""Reference motions and typical error magnitudes for the hand-derivation checker.

The checker compares coefficients of error equations numerically at a few points of
typical motions, and weighs each term by a typical size of the error quantity it
multiplies. Both come from the model's own SymPy definition (no generated code):

* **Points.** The model's ``initial_state`` turns a navigation fix (latitude,
  longitude, heading where the model has one, north and east velocity) into its state;
  the horizontal apparent accelerations (inputs ``a_*``) are solved from its
  ``ideal_rhs`` so that the velocity states stay constant (or change along the track
  at a stated rate: the ground velocity in the axes of the velocity states, i.e. the
  states less the Earth's rotation they carry, grows along itself, while that
  rotation part follows the position and height); the vertical apparent acceleration
  (``a_zeta``) is 9.81 m/s², ``h`` and ``V_zeta`` are set where the model has them.
  The motions are

  - static base at φ = 50°, λ = 30°, heading 30°, h = 0 (every model);
  - a great-circle cruise at 250 m/s, h = 10 km: three points 0, 2000 and 4000 km along
    the great circle that leaves (50°, 30°) at track 60° (every model);
  - a climbing, accelerating leg of the same circle: 150 m/s, h = 3 km, vertical
    velocity 10 m/s, ground speed growing by 1 m/s² along track (models with a
    ``V_zeta`` input only). For ``orthodromic`` the leg keeps to its orthodrome (the
    ground velocity turns with the great circle, 0.004 m/s² across); ``free_azimuth``'s
    velocity axes keep a fixed absolute azimuth, so its leg turns by the Earth rate's
    vertical part besides (0.012 m/s² across in all).

  A model that cannot fly a motion is checked on the others; :func:`reference_points`
  says which were left out and why. A ``@scope static base`` directive keeps only the
  static base. Each point's description names only what of the fix the model takes: a
  model without a latitude initial condition (a tangent-plane INS, say) sits at its own
  initial position, so its points are "static base, at rest" and cruises that differ
  only in velocity and track, said so; one without a height (initial condition or
  input) is said to have none.
* **Magnitudes.** Tied together by the Schuler loop, from one declared attitude error θ
  (default 1e-4 rad): with the model's Earth radius R and gravity g,
  ω_s = √(g/R), angles and direction-cosine errors θ, velocity errors √(gR)·θ (≈ 0.8 m/s
  for 1e-4 rad), position errors R·θ, rate errors (drifts) ω_s·θ, acceleration errors
  (biases) g·θ, dimensionless errors (scale factors) θ. Any of them can be overridden
  (``@magnitude`` in the hand file, ``--magnitude`` on the command line).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ins_errors.checker.typical import (  # noqa: F401 (also names of this module)
    DEFAULT_ATTITUDE,
    GRAVITY,
    MAGNITUDE_UNITS,
    TYPICAL_BY_UNIT,
    Magnitudes,
    _earth,
    magnitude_override,
    schuler_magnitudes,
    typical_magnitude,
)
from ins_errors.errors import DomainError, InsErrorsError
from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.variation import ideal_intermediate_values

STATIC_BASE = "static base"
"""Scope name of the static-base motion class (``@scope static base``)."""


@dataclass(frozen=True)
class ReferencePoint:
    """One point of a reference motion.

    Attributes
    ----------
    label : str
        Short name (``"static base"``, ``"cruise 2000 km"``).
    description : str
        Latitude, heading, speed, height... in words.
    values : dict
        Value of every ideal symbol of the model (states, inputs, parameters and ideal
        intermediates), SI units.
    motion : str
        Motion class (``"static base"``, ``"cruise"``, ``"climb"``).
    ground_velocity : tuple of float
        North and east ground velocity of the motion at the point, m/s (what the fix
        sets the model's velocity initial conditions to; (0, 0) on the static base).
    """

    label: str
    description: str
    values: dict[sp.Symbol, float]
    motion: str = ""
    ground_velocity: tuple[float, float] = (0.0, 0.0)


@dataclass
class ReferenceMotions:
    """The points a model is checked at, and the motions it could not fly."""

    points: list[ReferencePoint]
    skipped: list[str] = field(default_factory=list)


POINT_RADIUS = 6_371_000.0
"""Sphere (m) the cruise points' distances are laid out on (their angles are fixed)."""


def _great_circle(lat0: float, lon0: float, track0: float, distance: float,
                  radius: float = POINT_RADIUS) -> tuple[float, float, float]:
    """Latitude, longitude, track (rad) after ``distance`` m along a great circle."""
    r0 = np.array([np.cos(lat0) * np.cos(lon0), np.cos(lat0) * np.sin(lon0), np.sin(lat0)])
    east = np.array([-np.sin(lon0), np.cos(lon0), 0.0])
    north = np.cross(r0, east)
    t0 = np.cos(track0) * north + np.sin(track0) * east
    s = distance / radius
    r = np.cos(s) * r0 + np.sin(s) * t0
    t = -np.sin(s) * r0 + np.cos(s) * t0
    lat, lon = np.arcsin(r[2]), np.arctan2(r[1], r[0])
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    north = np.cross(r, east)
    return float(lat), float(lon), float(np.arctan2(t @ east, t @ north))


def _on_sphere(m: _Motion, radius: float) -> tuple[str, str]:
    """Label and description of a cruise point on a sphere of the model's ``radius`` (m).

    The points sit at fixed angles along the great circle (``m.distance`` on a sphere of
    :data:`POINT_RADIUS`); on the model's sphere that arc is ``angle × radius``, given to
    10 km. For the Earth's radii (6371-6378 km) this is the nominal distance.
    """
    angle = m.distance / POINT_RADIUS
    km = round(angle * radius / 1e4) * 10
    if km == round(m.distance / 1e3):
        return m.label, m.description
    return (f"cruise {km} km", f"same great circle, {km} km on along the model's sphere "
            f"of radius {radius / 1e3:.0f} km ({np.degrees(angle):.1f}° of arc)")


@dataclass(frozen=True)
class _Motion:
    label: str
    motion: str
    description: str
    latitude: float  # deg
    longitude: float  # deg
    heading: float  # deg
    distance: float | None  # m along the great circle, None: static
    speed: float  # m/s
    height: float  # m
    climb: float  # m/s
    acceleration: float  # m/s² along track


_MOTIONS = (
    _Motion("static base", STATIC_BASE, "static base, φ 50°, λ 30°, heading 30°, h 0",
            50.0, 30.0, 30.0, None, 0.0, 0.0, 0.0, 0.0),
    _Motion("cruise 0 km", "cruise", "great-circle cruise, 250 m/s, h 10 km, start "
            "(φ 50°, λ 30°, track 60°)", 50.0, 30.0, 60.0, 0.0, 250.0, 10_000.0, 0.0, 0.0),
    _Motion("cruise 2000 km", "cruise", "same great circle, 2000 km on", 50.0, 30.0, 60.0,
            2.0e6, 250.0, 10_000.0, 0.0, 0.0),
    _Motion("cruise 4000 km", "cruise", "same great circle, 4000 km on", 50.0, 30.0, 60.0,
            4.0e6, 250.0, 10_000.0, 0.0, 0.0),
    _Motion("climb", "climb", "same great circle at its start: 150 m/s, h 3 km, climbing "
            "10 m/s, accelerating 1 m/s² along track", 50.0, 30.0, 60.0, 0.0, 150.0,
            3_000.0, 10.0, 1.0),
)

MOTION_CLASSES = ("static base", "cruise", "climb")
"""Motion classes a ``@scope`` directive may name."""

_EVALUATORS: dict[int, tuple] = {}


def _evaluators(d: ModelDefinition):
    if id(d) in _EVALUATORS and _EVALUATORS[id(d)][0] is d:
        return _EVALUATORS[id(d)][1:]
    c, u, p, x = d.c, d.u, d.p, d.x
    initial = sp.lambdify([c, u, p], list(d.initial_state), "numpy",
                          docstring_limit=0)
    rhs_expr = d.ideal_rhs_expanded()
    rhs = sp.lambdify([x, u, p], list(rhs_expr), "numpy", docstring_limit=0)
    free = [v.symbol for v in d.inputs if _is_solved_input(v.name)]
    jacobian = sp.lambdify([x, u, p], rhs_expr.jacobian(free) if free else sp.zeros(
        len(x), 0), "numpy", docstring_limit=0)
    closed = ideal_intermediate_values(d)
    symbols = list(closed)
    intermediates = sp.lambdify([x, u, p], [closed[s] for s in symbols], "numpy",
                                docstring_limit=0)
    earth = _earth_part(d)
    _EVALUATORS[id(d)] = (d, initial, rhs, jacobian, intermediates, symbols, earth)
    return initial, rhs, jacobian, intermediates, symbols, earth


_GROUND_VELOCITY = ("v_N", "v_E", "v_N0", "v_E0", "v_D0", "v_U0", "v_D", "v_U")
"""Initial conditions that are the relative (ground) velocity."""


def _earth_part(d: ModelDefinition):
    """The Earth's rotation carried by the model's velocity states, as a function of x.

    The model's ``initial_state`` evaluated at the state's own position and heading (its
    outputs named like the initial conditions) with zero ground velocity: the consistent
    state of a vehicle at rest there (what :func:`ins_errors.numeric.trajectories.\
consistent_state` builds from the generated functions, here from the definition). For
    a model whose velocity states are absolute (``orthodromic``'s V_ξ, V_η,
    ``free_azimuth``'s V_x, V_y) this is U × r in the states' axes; for one whose
    velocity states are already relative it is identically zero.

    Returns
    -------
    tuple or None
        ``(rows, e, e_x, e_u)``: the velocity-state indices and three functions of
        ``(x, u, p, c)`` giving that part (shape (len(rows),)) and its Jacobians in the
        state (len(rows), n) and the inputs (len(rows), m); None when the part is zero.
    """
    rows = [k for k, v in enumerate(d.states) if v.unit == "m/s"]
    outputs = {v.name: expr for v, expr in zip(d.outputs, d.outputs_expanded(),
                                                strict=True)}
    at_rest = {}
    for v in d.initial_conditions:
        if v.name in _GROUND_VELOCITY:
            at_rest[v.symbol] = sp.S.Zero
        elif v.name in outputs:
            at_rest[v.symbol] = outputs[v.name]
    part = sp.Matrix([d.initial_state[k] for k in rows]).xreplace(at_rest)
    if not rows or all(_identically_zero(e) for e in part):
        return None
    args = [d.x, d.u, d.p, d.c]
    return (rows,
            *(sp.lambdify(args, expr, "numpy", docstring_limit=0)
              for expr in (part, part.jacobian(d.x), part.jacobian(d.u))))


def _identically_zero(expr: sp.Expr) -> bool:
    """Whether ``expr`` simplifies to zero (``sp.simplify(expr) == 0``).

    An expression that is far from zero at one generic point (every symbol a distinct
    rational between 0.3 and 1.6, evaluated to 50 digits, where an expression that is
    identically zero gives a few units of the 50th digit at most) is not zero, and is
    not simplified: SymPy's simplify took ~7 s on each of free_azimuth's velocity parts.
    Only an expression within 1e-20 of zero there (or not a finite number) is
    simplified, so the answer is ``sp.simplify(expr) == 0``'s.

    Parameters
    ----------
    expr : sympy.Expr
        A scalar expression of the model's symbols.

    Returns
    -------
    bool
        True when ``sp.simplify(expr) == 0``.
    """
    if expr == 0:
        return True
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    point = {s: sp.Rational(3 + k % 13, 10) + sp.Rational(1, 97 + k)
             for k, s in enumerate(symbols)}
    try:
        value = complex(expr.xreplace(point).evalf(50))
    except (TypeError, ValueError, ZeroDivisionError):
        value = 0j  # not a number there: SymPy decides
    if np.isfinite(value) and abs(value) > 1e-20:
        return False
    return sp.simplify(expr) == 0


_HEIGHTS = ("h", "h_ref", "height")
_VERTICAL = ("a_zeta", "a_U", "a_z", "a_up", "a_D")
_CLIMB = ("V_zeta",)


def _is_horizontal_acceleration(name: str) -> bool:
    return name.startswith("a_") and name not in _VERTICAL


def _is_solved_input(name: str) -> bool:
    """Inputs solved from the ideal equations (accelerations, body rates, forces)."""
    return name not in (*_HEIGHTS, *_VERTICAL, *_CLIMB)


def _unusable(d: ModelDefinition, motion: _Motion) -> str | None:
    """Why ``d`` cannot fly ``motion`` (None if it can)."""
    inputs = {v.name for v in d.inputs}
    conditions = {v.name for v in d.initial_conditions}
    vertical = {"v_D0", "v_U0", "v_D", "v_U"}  # a vertical velocity the fix sets
    if motion.climb and "V_zeta" not in inputs and not conditions & vertical:
        return "the model has no vertical-velocity input V_zeta"
    if motion.acceleration and not any(_is_solved_input(n) for n in inputs):
        return "the model has no horizontal acceleration input"
    return None


def check_parameter_domain(d: ModelDefinition, p: list[float]) -> None:
    """Refuse parameter values outside the model's own domain, as every run does.

    The model's ``initial_domain`` conditions are evaluated with the initial conditions
    and inputs at zero (equator, at rest: inside every domain), so a condition that
    fails there fails for the parameters themselves (e.g. a tangent-plane origin
    latitude at a pole), the check of :meth:`ins_errors.numeric.model.Model.\
parameter_vector` on the definition.

    Parameters
    ----------
    d : ModelDefinition
    p : list of float
        Parameter values, SI, in the order of ``d.parameters``.

    Raises
    ------
    DomainError
        ``parameters of MODEL: MESSAGE`` with the model's own message of the first
        condition that fails (not > 0, or not a real number).
    """
    if not d.initial_domain:
        return
    margins = sp.lambdify([d.c, d.u, d.p], [expr for expr, _ in d.initial_domain], "numpy",
                          docstring_limit=0)
    with np.errstate(all="ignore"):
        values = margins([0.0] * len(d.c), [0.0] * len(d.u), list(p))
    for value, (_, message) in zip(values, d.initial_domain, strict=True):
        try:
            holds = float(value) > 0
        except (TypeError, ValueError):  # complex or not a number
            holds = False
        if not holds:
            raise DomainError(f"parameters of {d.name}: {message}")


_VELOCITY_FIX = ("v_N", "v_E", "v_N0", "v_E0")
"""Initial conditions that carry the horizontal ground velocity of a fix."""


def _takes(d: ModelDefinition) -> frozenset[str]:
    """What of a reference fix the model takes: ``latitude``, ``longitude``, ``heading``,
    ``velocity`` (horizontal), ``height`` (an initial condition or an input)."""
    names_c = {v.name for v in d.initial_conditions}
    names_u = {v.name for v in d.inputs}
    takes = {name for name in ("latitude", "longitude") if name in names_c}
    if names_c & {"heading", "yaw"}:
        takes.add("heading")
    if names_c & set(_VELOCITY_FIX):
        takes.add("velocity")
    if "height" in names_c or names_u & set(_HEIGHTS):
        takes.add("height")
    return frozenset(takes)


def _height_text(height: float) -> str:
    return "h 0" if height == 0 else f"h {height / 1e3:g} km"


def _without_position(m: _Motion, track: float, takes: frozenset[str]) -> str:
    """Description of a point for a model that takes no latitude: only what it does take
    (velocity, heading, height), and what it does not."""
    parts = ["static base, at rest" if m.distance is None and m.motion == STATIC_BASE
             else m.motion]
    if m.speed and "velocity" in takes:
        parts.append(f"{m.speed:g} m/s, track {np.degrees(track):.4g}°")
    elif "heading" in takes:
        parts.append(f"heading {np.degrees(track):.4g}°")
    if "height" in takes:
        parts.append(_height_text(m.height))
    if m.climb:
        parts.append(f"climbing {m.climb:g} m/s")
    if m.acceleration:
        parts.append(f"accelerating {m.acceleration:g} m/s² along track")
    notes = []
    if m.distance and "velocity" in takes:
        notes.append(f"the track {m.distance / 1e3:g} km along the great circle of the "
                     "cruise points")
    absent = [name for name in ("latitude", "longitude", "heading", "velocity", "height")
              if name not in takes and not (name == "heading" and "velocity" in takes)]
    if absent:
        listed = (absent[0] if len(absent) == 1
                  else ", ".join(absent[:-1]) + " or " + absent[-1])
        notes.append(f"the model takes no {listed}")
    return ", ".join(parts) + (f" ({'; '.join(notes)})" if notes else "")


_FIX = ("latitude", "longitude", "heading", "v_N", "v_E", "v_N0", "v_E0", "v_D0", "v_U0",
        "v_D", "v_U", "height", "roll", "pitch", "yaw")
"""Initial conditions a navigation fix and a motion set."""


def reference_points(d: ModelDefinition, scope: str | None = None,
                     parameters: Mapping[str, float] | None = None) -> ReferenceMotions:
    """The reference-motion points of model ``d`` (see module docstring).

    Parameters
    ----------
    d : ModelDefinition
    scope : str, optional
        Keep only this motion class (``"static base"``, ``"cruise"``, ``"climb"``).
    parameters : mapping of str to float, optional
        Parameter values (SI) replacing the model's defaults at every point (``-p
        k_h1=0.0293/s``: a damping gain at 0 hides every term it multiplies).

    Raises
    ------
    InsErrorsError
        If the model's initial conditions or inputs are not ones a navigation fix and a
        motion can set; a :class:`~ins_errors.errors.DomainError` for parameters outside
        the model's domain (:func:`check_parameter_domain`).
    """
    if scope is not None and scope not in MOTION_CLASSES:
        raise InsErrorsError(f"unknown scope {scope!r} (known: {', '.join(MOTION_CLASSES)})")
    settable = set(_FIX)
    strange = [v.name for v in d.initial_conditions if v.name not in settable]
    if strange:
        raise InsErrorsError(f"model {d.name!r}: the checker's reference motions cannot set "
                             f"the initial condition {strange[0]!r} (they set "
                             f"{', '.join(sorted(settable))})")
    initial, rhs, jacobian, intermediates, symbols, earth = _evaluators(d)
    radius, _ = _earth(d, parameters)
    values_set = dict(parameters or {})
    p = [float(values_set.get(v.name, v.default)) for v in d.parameters]
    check_parameter_domain(d, p)
    takes = _takes(d)
    names_c = [v.name for v in d.initial_conditions]
    names_u = [v.name for v in d.inputs]
    accel = [k for k, n in enumerate(names_u) if _is_solved_input(n)]
    velocity = [k for k, v in enumerate(d.states) if v.unit == "m/s"]
    result = ReferenceMotions([])
    for m in _MOTIONS:
        if scope is not None and m.motion != scope:
            continue
        why = _unusable(d, m)
        if why is not None:
            if not any(s.startswith(m.motion) for s in result.skipped):
                result.skipped.append(f"{m.motion}: {why}")
            continue
        lat, lon, track = np.radians([m.latitude, m.longitude, m.heading])
        label, description = m.label, m.description
        if m.distance is not None:
            lat, lon, track = _great_circle(lat, lon, track, m.distance)
            label, description = _on_sphere(m, radius)
        v_n, v_e = m.speed * np.cos(track), m.speed * np.sin(track)
        fix = {"latitude": lat, "longitude": lon, "heading": track, "yaw": track,
               "v_N": v_n, "v_E": v_e, "v_N0": v_n, "v_E0": v_e, "v_D0": -m.climb,
               "v_U0": m.climb, "v_D": -m.climb, "v_U": m.climb, "height": m.height,
               "roll": 0.0, "pitch": 0.0}
        c = [fix[n] for n in names_c]
        u = []
        for n in names_u:
            u.append(m.height if n in _HEIGHTS else m.climb if n in _CLIMB
                     else GRAVITY if n in _VERTICAL else 0.0)
        x = [float(v) for v in initial(c, u, p)]
        if accel:
            rates = np.asarray(rhs(x, u, p), dtype=float).ravel()
            target = np.zeros_like(rates)
            b = np.asarray(jacobian(x, u, p), dtype=float).reshape(len(x), len(accel))
            # the ground velocity in the velocity states' axes: the states less the
            # Earth's rotation they carry (zero for relative-velocity states)
            relative = {k: x[k] for k in velocity}
            if earth is not None and m.acceleration:
                rows_e, e, e_x, e_u = earth
                e_now = np.asarray(e(x, u, p, c), dtype=float).ravel()
                j_x = np.asarray(e_x(x, u, p, c), dtype=float).reshape(len(rows_e), len(x))
                j_u = np.asarray(e_u(x, u, p, c), dtype=float).reshape(len(rows_e), len(u))
                u_rate = np.array([m.climb if n in _HEIGHTS else 0.0 for n in names_u])
                moved = j_x @ b
                for i, k in enumerate(rows_e):
                    relative[k] = x[k] - e_now[i]
                    # the Earth part follows the position: d/dt e(x(t), u(t)), with
                    # ẋ = rates + b a (the a-dependent part moves to the left side)
                    target[k] = j_x[i] @ rates + j_u[i] @ u_rate
                    b[k] = b[k] - moved[i]
            speed = np.linalg.norm([relative[k] for k in velocity]) if velocity else 0.0
            if speed > 0 and m.acceleration:
                for k in velocity:
                    target[k] += m.acceleration * relative[k] / speed
            # every state the solved inputs drive: velocities follow the motion's
            # along-track acceleration, the others (attitude) stay as they are
            rows = [i for i in range(len(x)) if np.any(b[i] != 0)]
            solution, *_ = np.linalg.lstsq(b[rows], (target - rates)[rows], rcond=None)
            for k, value in zip(accel, solution, strict=True):
                u[k] = float(value)
        values = dict(zip(d.x, x, strict=True))
        values.update(zip(d.u, u, strict=True))
        values.update(zip(d.p, p, strict=True))
        values.update({s: float(v) for s, v in zip(symbols, intermediates(x, u, p),
                                                     strict=True)})
        if "latitude" not in takes:
            description = _without_position(m, track, takes)
        elif "height" not in takes:
            description += " (the model has no height input)"
        result.points.append(ReferencePoint(label, description, values, m.motion,
                                            (float(v_n), float(v_e))))
    return result
