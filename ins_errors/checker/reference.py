"""Reference motions and typical error magnitudes for the hand-derivation checker.

The checker compares coefficients of error equations numerically at a few points of
typical motions, and weighs each term by a typical size of the error quantity it
multiplies. Points are computed from the model's own SymPy definition (no generated code),
so the symbolic layer stays independent of ``generated/``.

Reference motions of the orthodromic model:

* static base at φ = 50°, λ = 30°, trihedron heading χ = 30°, h = 0;
* a great-circle cruise at 250 m/s, h = 10 km, three points 0, 2000 and 4000 km along
  the great circle that leaves (50°, 30°) at track 60° (spherical-Earth geometry);
* a climbing, accelerating leg of the same great circle: 150 m/s, h = 3 km, vertical
  velocity 10 m/s, along-track acceleration 1 m/s².

Inputs are the consistent ones (apparent accelerations that keep the ideal velocities
constant, plus the along-track acceleration where stated; a_ζ = 9.81 m/s²).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np
import sympy as sp

from ins_errors.errors import InsErrorsError
from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.variation import ideal_intermediate_values
from ins_errors.units import parse_quantity

GRAVITY = 9.81
"""Apparent vertical acceleration a_ζ used at the reference points, m/s²."""

TYPICAL_BY_UNIT = {
    "rad": ("1e-4 rad", "rad"),
    "1": ("1e-4", "1"),
    "m/s": ("0.1 m/s", "m/s"),
    "rad/s": ("0.01 deg/h", "rad/s"),
    "m/s**2": ("1e-4 g", "m/s**2"),
    "m": ("10 m", "m"),
}
"""Typical size of an error quantity, by its SI unit: (text, unit) parsed with pint."""


@cache
def typical_magnitude(unit: str) -> tuple[float, str]:
    """Typical size (SI) and its human spelling for an error quantity of ``unit``.

    Raises
    ------
    InsErrorsError
        If no typical size is known for that unit.
    """
    if unit not in TYPICAL_BY_UNIT:
        raise InsErrorsError(f"no typical error magnitude for unit {unit!r} "
                             f"(known: {', '.join(TYPICAL_BY_UNIT)})")
    text, si = TYPICAL_BY_UNIT[unit]
    return parse_quantity(text, si, "typical magnitude"), text


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
    """

    label: str
    description: str
    values: dict[sp.Symbol, float]


def _great_circle(lat0: float, lon0: float, track0: float, distance: float,
                  radius: float = 6_371_000.0) -> tuple[float, float, float]:
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


_MOTIONS = (
    # label, description, latitude, longitude, heading (deg), distance (m), speed (m/s),
    # height (m), vertical velocity (m/s), along-track acceleration (m/s²)
    ("static base", "static base, φ 50°, λ 30°, χ 30°, h 0", 50.0, 30.0, 30.0, None,
     0.0, 0.0, 0.0, 0.0),
    ("cruise 0 km", "great-circle cruise, 250 m/s, h 10 km, start (φ 50°, λ 30°, χ 60°)",
     50.0, 30.0, 60.0, 0.0, 250.0, 10_000.0, 0.0, 0.0),
    ("cruise 2000 km", "same great circle, 2000 km on", 50.0, 30.0, 60.0, 2.0e6, 250.0,
     10_000.0, 0.0, 0.0),
    ("cruise 4000 km", "same great circle, 4000 km on", 50.0, 30.0, 60.0, 4.0e6, 250.0,
     10_000.0, 0.0, 0.0),
    ("climb", "same great circle at its start: 150 m/s, h 3 km, climbing 10 m/s, "
     "accelerating 1 m/s² along track", 50.0, 30.0, 60.0, 0.0, 150.0, 3_000.0, 10.0, 1.0),
)


_EVALUATORS: dict[int, tuple] = {}


def _evaluators(d: ModelDefinition):
    if id(d) in _EVALUATORS and _EVALUATORS[id(d)][0] is d:
        return _EVALUATORS[id(d)][1:]
    c, u, p, x = d.c, d.u, d.p, d.x
    initial = sp.lambdify([c, u, p], list(d.initial_state), "numpy")
    rhs = sp.lambdify([x, u, p], list(d.ideal_rhs_expanded()), "numpy")
    closed = ideal_intermediate_values(d)
    symbols = list(closed)
    intermediates = sp.lambdify([x, u, p], [closed[s] for s in symbols], "numpy")
    _EVALUATORS[id(d)] = (d, initial, rhs, intermediates, symbols)
    return initial, rhs, intermediates, symbols


def reference_points(d: ModelDefinition) -> list[ReferencePoint]:
    """The reference-motion points of model ``d`` (see module docstring).

    Raises
    ------
    InsErrorsError
        If the model lacks the names the reference motions are built from.
    """
    needed_c = ["latitude", "longitude", "heading", "v_N", "v_E"]
    needed_u = ["a_xi", "a_eta", "a_zeta", "V_zeta", "h"]
    names_c = [v.name for v in d.initial_conditions]
    names_u = [v.name for v in d.inputs]
    names_x = [v.name for v in d.states]
    if names_c != needed_c or names_u != needed_u or "V_xi" not in names_x:
        raise InsErrorsError(f"no reference motions are defined for model {d.name!r} "
                             "(the hand checker supports orthodromic-type models)")
    initial, rhs, intermediates, symbols = _evaluators(d)
    p = [float(v.default) for v in d.parameters]
    i_xi, i_eta = names_x.index("V_xi"), names_x.index("V_eta")
    points = []
    for label, text, lat, lon, track, distance, speed, h, vz, accel in _MOTIONS:
        lat, lon, track = np.radians([lat, lon, track])
        if distance is not None:
            lat, lon, track = _great_circle(lat, lon, track, distance)
        c = [lat, lon, track, speed * np.cos(track), speed * np.sin(track)]
        u = [0.0, 0.0, GRAVITY, vz, h]
        x = [float(v) for v in initial(c, u, p)]
        rates = rhs(x, u, p)
        u[0], u[1] = -float(rates[i_xi]) + accel, -float(rates[i_eta])
        values = dict(zip(d.x, x, strict=True))
        values.update(zip(d.u, u, strict=True))
        values.update(zip(d.p, p, strict=True))
        values.update({s: float(v) for s, v in zip(symbols, intermediates(x, u, p),
                                                     strict=True)})
        points.append(ReferencePoint(label, text, values))
    return points
