"""The textbook references a static-base mode is named against: g, R and Ω of a model.

The classical INS error modes at rest are the Schuler oscillation (ω_s = √(g/R), period
2π√(R/g) ≈ 84.4 min), split by the Foucault coupling into ω̄ ± Ω|sin φ| with
ω̄ = √(ω_s² + Ω² sin² φ), the Earth-rate oscillation (Ω, 23.93 h) and, for a model with a
vertical channel, the divergence at √(2g/R) (e-folding time √(R/2g) ≈ 570 s).

The three constants are read from the model itself, where it has them, and each says
where it came from:

* g: a parameter ``g``; else the vertical specific force at rest, an input ``a_zeta``;
  else the magnitude of the specific-force inputs ``f_x, f_y, f_z`` (a strapdown IMU at
  rest measures normal gravity);
* R: a parameter ``R`` (a sphere), or ``a`` with ``e2`` / ``ecc2`` (an ellipsoid: the
  geometric mean √(R_M R_N) of the meridian and prime-vertical radii at the latitude, the
  radius whose Schuler frequency is the geometric mean of the two channels'), plus the
  height;
* Ω: a parameter ``U``, ``Omega``, ``omega_ie`` or ``earth_rate``.

A model lacking one of them gets None for it, and its modes are named by kind only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ins_errors.models.earth import radii_of_curvature
from ins_errors.numeric.model import Model

EARTH_RATE_NAMES = ("U", "Omega", "omega_ie", "earth_rate")
"""Parameter names read as the Earth's rotation rate Ω, rad/s, in this order."""


@dataclass(frozen=True)
class Constant:
    """One reference constant and where it was read.

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
class References:
    """g, R and Ω of a model at one static base (None where the model lacks one).

    Attributes
    ----------
    g : Constant or None
        Gravity (vertical specific force at rest), m/s².
    R : Constant or None
        Earth radius of the Schuler loop at the base, m.
    Omega : Constant or None
        Earth rotation rate, rad/s.
    latitude : float
        Latitude of the base, rad (for the Foucault split Ω|sin φ|).
    """

    g: Constant | None
    R: Constant | None
    Omega: Constant | None
    latitude: float

    @property
    def schuler(self) -> float | None:
        """ω_s = √(g/R), rad/s (None without g or R)."""
        if self.g is None or self.R is None:
            return None
        return float(np.sqrt(self.g.value / self.R.value))

    @property
    def vertical(self) -> float | None:
        """√(2g/R), rad/s: the rate of the undamped vertical channel (None without g, R)."""
        return None if self.schuler is None else float(np.sqrt(2.0) * self.schuler)

    @property
    def foucault(self) -> float | None:
        """Ω|sin φ|, rad/s (None without Ω)."""
        if self.Omega is None:
            return None
        return float(self.Omega.value * abs(np.sin(self.latitude)))

    def split(self) -> tuple[float, float] | None:
        """(ω̄ − Ω|sin φ|, ω̄ + Ω|sin φ|), rad/s, ω̄ = √(ω_s² + Ω² sin² φ): the
        Foucault-split Schuler frequencies on a sphere (None without g, R or Ω)."""
        if self.schuler is None or self.foucault is None:
            return None
        mean = float(np.hypot(self.schuler, self.foucault))
        return mean - self.foucault, mean + self.foucault

    def to_dict(self) -> dict:
        return {name: None if c is None else c.to_dict()
                for name, c in (("g", self.g), ("R", self.R), ("Omega", self.Omega))}


def _named(model: Model, kind: str, values: np.ndarray) -> dict[str, float]:
    return {info.name: float(v) for info, v in zip(getattr(model, kind), values, strict=True)}


def _gravity(model: Model, u: dict[str, float], p: dict[str, float]) -> Constant | None:
    if "g" in p:
        return Constant(p["g"], "m/s**2", "parameter g")
    if "a_zeta" in u:
        return Constant(abs(u["a_zeta"]), "m/s**2", "input a_zeta at rest")
    if all(f"f_{axis}" in u for axis in "xyz"):
        value = float(np.sqrt(sum(u[f"f_{axis}"] ** 2 for axis in "xyz")))
        return Constant(value, "m/s**2", "|f| of the inputs f_x, f_y, f_z at rest")
    return None


def _radius(p: dict[str, float], latitude: float, height: float) -> Constant | None:
    at = f" at φ = {np.degrees(latitude):.4g}°" + (f", + h = {height:g} m" if height else "")
    semi_major = next((name for name in ("a", "R") if name in p), None)
    eccentricity = next((name for name in ("e2", "ecc2") if name in p), None)
    if semi_major is None:
        return None
    e2 = p[eccentricity] if eccentricity else 0.0
    if e2 == 0.0:
        where = f"parameter {semi_major}" + (f" ({eccentricity} = 0)" if eccentricity else "")
        return Constant(p[semi_major] + height, "m", where + (f", + h = {height:g} m"
                                                             if height else ""))
    meridian, prime_vertical = radii_of_curvature(latitude, p[semi_major], e2)
    value = float(np.sqrt((meridian + height) * (prime_vertical + height)))
    return Constant(value, "m", f"√(R_M R_N) of parameters {semi_major}, {eccentricity}{at}")


def references(model: Model, u: np.ndarray, p: np.ndarray, latitude: float,
               height: float) -> References:
    """The reference constants of ``model`` at a static base.

    Parameters
    ----------
    model : Model
        The loaded model.
    u : numpy.ndarray, shape (nu,)
        Inputs at rest.
    p : numpy.ndarray, shape (np,)
        Parameters, SI.
    latitude : float
        Latitude of the base, rad.
    height : float
        Height of the base, m.

    Returns
    -------
    References
    """
    inputs, parameters = _named(model, "inputs", u), _named(model, "parameters", p)
    omega = next((Constant(parameters[name], "rad/s", f"parameter {name}")
                  for name in EARTH_RATE_NAMES if name in parameters), None)
    return References(_gravity(model, inputs, parameters),
                      _radius(parameters, latitude, height), omega, float(latitude))
