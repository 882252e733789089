"""A model's Earth radius, gravity and Earth rate, read from its parameters by name.

One list of names for every reader (the static-base modes of
:mod:`ins_errors.analysis.mode_references`, the checker's typical magnitudes of
:mod:`ins_errors.checker.typical`):

* radius R, m: a parameter named in :data:`RADIUS_NAMES` (a sphere's radius, or an
  ellipsoid's semi-major axis when one named in :data:`ECCENTRICITY_NAMES` is non-zero);
* gravity g, m/s²: a parameter named in :data:`GRAVITY_NAMES`; else, given the inputs at
  rest, the vertical specific force ``a_zeta``, else the magnitude of the specific-force
  inputs ``f_x, f_y, f_z`` (a strapdown IMU at rest measures normal gravity);
* Earth rate Ω, rad/s: a parameter named in :data:`EARTH_RATE_NAMES`.

A parameter counts only with the SI unit of what it is read as. Nothing here imports
more than numpy.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ins_errors.models.earth import radii_of_curvature

FIRST_COSMIC_VELOCITY = float(np.sqrt(9.80665 * 6_378_137.0))
"""m/s: √(g a), standard gravity and WGS-84 a, about 7.91 km/s: the speed along the
surface at which the centripetal acceleration v²/R equals gravity (an orbit). The largest
ground speed of a motion and the largest initial velocity error a run takes."""

RADIUS_NAMES = ("a", "R", "R_earth", "semi_major_axis")
"""Parameter names read as the Earth radius (or semi-major axis), m, in this order."""

ECCENTRICITY_NAMES = ("e2", "ecc2")
"""Parameter names read as the first eccentricity squared, 1, in this order."""

GRAVITY_NAMES = ("g", "gravity", "g0")
"""Parameter names read as gravity, m/s², in this order."""

EARTH_RATE_NAMES = ("U", "Omega", "omega_ie", "earth_rate")
"""Parameter names read as the Earth's rotation rate Ω, rad/s, in this order."""


@dataclass(frozen=True)
class Constant:
    """One constant and where it was read.

    Attributes
    ----------
    value : float
        SI value.
    unit : str
        SI unit.
    source : str
        Where it came from, e.g. ``"parameter U"``, ``"input a_zeta at rest"``.
    """

    value: float
    unit: str
    source: str

    def to_dict(self) -> dict:
        return {"value": self.value, "unit": self.unit, "source": self.source}


@dataclass(frozen=True)
class EarthConstants:
    """Radius, gravity and Earth rate of a model (None where it has none).

    Attributes
    ----------
    radius : Constant or None
        Earth radius, m.
    gravity : Constant or None
        Gravity (vertical specific force at rest), m/s².
    earth_rate : Constant or None
        Earth rotation rate, rad/s.
    """

    radius: Constant | None
    gravity: Constant | None
    earth_rate: Constant | None


def _first(names: tuple[str, ...], values: Mapping[str, float], units: Mapping[str, str],
           unit: str) -> str | None:
    return next((n for n in names if n in values and units.get(n) == unit), None)


class EarthParameterNames(NamedTuple):
    """Names of the parameters a model's Earth is read from (None where it has none)."""

    radius: str | None
    eccentricity: str | None
    earth_rate: str | None
    gravity: str | None


def earth_parameter_names(parameters: Iterable) -> EarthParameterNames:
    """The parameters read as the Earth radius (m), eccentricity² (1), Earth rate (rad/s)
    and gravity (m/s²): the first of :data:`RADIUS_NAMES`, :data:`ECCENTRICITY_NAMES`,
    :data:`EARTH_RATE_NAMES`, :data:`GRAVITY_NAMES` with that SI unit.

    Parameters
    ----------
    parameters : iterable
        A model's parameters (anything with ``name`` and ``unit``).
    """
    units = {q.name: q.unit for q in parameters}
    return EarthParameterNames(_first(RADIUS_NAMES, units, units, "m"),
                               _first(ECCENTRICITY_NAMES, units, units, "1"),
                               _first(EARTH_RATE_NAMES, units, units, "rad/s"),
                               _first(GRAVITY_NAMES, units, units, "m/s**2"))


def _radius(p: Mapping[str, float], units: Mapping[str, str], latitude: float | None,
            height: float) -> Constant | None:
    semi_major = _first(RADIUS_NAMES, p, units, "m")
    if semi_major is None:
        return None
    eccentricity = _first(ECCENTRICITY_NAMES, p, units, "1")
    e2 = float(p[eccentricity]) if eccentricity else 0.0
    if e2 == 0.0 or latitude is None:
        where = f"parameter {semi_major}" + (f" ({eccentricity} = 0)" if eccentricity and
                                              e2 == 0.0 else "")
        return Constant(float(p[semi_major]) + height, "m",
                        where + (f", + h = {height:g} m" if height else ""))
    at = f" at φ = {np.degrees(latitude):.4g}°" + (f", + h = {height:g} m" if height else "")
    meridian, prime_vertical = radii_of_curvature(latitude, float(p[semi_major]), e2)
    value = float(np.sqrt((meridian + height) * (prime_vertical + height)))
    return Constant(value, "m", f"√(R_M R_N) of parameters {semi_major}, {eccentricity}{at}")


def _gravity(p: Mapping[str, float], units: Mapping[str, str],
             u: Mapping[str, float] | None) -> Constant | None:
    name = _first(GRAVITY_NAMES, p, units, "m/s**2")
    if name is not None:
        return Constant(float(p[name]), "m/s**2", f"parameter {name}")
    u = u or {}
    if "a_zeta" in u:
        return Constant(abs(float(u["a_zeta"])), "m/s**2", "input a_zeta at rest")
    if all(f"f_{axis}" in u for axis in "xyz"):
        value = float(np.sqrt(sum(float(u[f"f_{axis}"]) ** 2 for axis in "xyz")))
        return Constant(value, "m/s**2", "|f| of the inputs f_x, f_y, f_z at rest")
    return None


def earth_constants(parameters: Mapping[str, float], units: Mapping[str, str],
                    inputs: Mapping[str, float] | None = None, latitude: float | None = None,
                    height: float = 0.0) -> EarthConstants:
    """The radius, gravity and Earth rate a model's parameters (and inputs at rest) hold.

    Parameters
    ----------
    parameters : mapping of str to float
        Parameter values by name, SI.
    units : mapping of str to str
        SI unit of each parameter (a name counts only with the unit it is read in).
    inputs : mapping of str to float, optional
        Inputs at rest by name, SI (gravity from ``a_zeta`` or ``f_x, f_y, f_z`` where no
        parameter holds it). None: from the parameters only.
    latitude : float, optional
        Latitude, rad: with a non-zero eccentricity, the radius is the geometric mean
        √(R_M R_N) of the meridian and prime-vertical radii there (the radius whose
        Schuler frequency is the geometric mean of the two channels'). None: the radius
        (or semi-major axis) parameter itself.
    height : float
        Height added to the radius, m.

    Returns
    -------
    EarthConstants
    """
    rate = _first(EARTH_RATE_NAMES, parameters, units, "rad/s")
    return EarthConstants(
        _radius(parameters, units, latitude, height), _gravity(parameters, units, inputs),
        None if rate is None else Constant(float(parameters[rate]), "rad/s",
                                           f"parameter {rate}"))
