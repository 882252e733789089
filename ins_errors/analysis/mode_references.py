"""The textbook references a static-base mode is named against: g, R and Ω of a model.

The classical INS error modes at rest are the Schuler oscillation (ω_s = √(g/R), period
2π√(R/g) ≈ 84.4 min), split by the Foucault coupling into ω̄ ± Ω|sin φ| with
ω̄ = √(ω_s² + Ω² sin² φ), the Earth-rate oscillation (Ω, 23.93 h) and, for a model with a
vertical channel, the divergence at √(2g/R) (e-folding time √(R/2g) ≈ 570 s).

The three constants are read from the model itself, where it has them, by
:func:`ins_errors.earth_constants.earth_constants` (the names it knows: R from ``a``,
``R``, ``R_earth`` or ``semi_major_axis`` (with ``e2`` / ``ecc2``: the geometric mean
√(R_M R_N) at the latitude) plus the height; g from ``g``, ``gravity`` or ``g0``, else the
inputs at rest ``a_zeta`` or |``f_x, f_y, f_z``|; Ω from ``U``, ``Omega``, ``omega_ie``
or ``earth_rate``), and each says where it came from.

A model lacking one of them gets None for it, and its modes are named by kind only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ins_errors.earth_constants import Constant, earth_constants
from ins_errors.numeric.model import Model

__all__ = ["Constant", "References", "references"]


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
    latitude : float or None
        Latitude of the base, rad (for the Foucault split Ω|sin φ|); None for a model
        without one (no Foucault split is named).
    """

    g: Constant | None
    R: Constant | None
    Omega: Constant | None
    latitude: float | None

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
        """Ω|sin φ|, rad/s (None without Ω or φ)."""
        if self.Omega is None or self.latitude is None:
            return None
        return float(self.Omega.value * abs(np.sin(self.latitude)))

    def split(self, damping_ratio: float = 0.0) -> tuple[float, float] | None:
        """The natural frequencies |λ| of the Foucault-split Schuler pair on a sphere, rad/s
        (None without g, R or Ω).

        Undamped, (ω̄ − Ω|sin φ|, ω̄ + Ω|sin φ|) with ω̄ = √(ω_s² + Ω² sin² φ). Damped by a
        loop gain k in both horizontal channels, the pair is the roots of
        s² + (k + 2iΩ sin φ) s + ω_s² = 0 (the two channels as one complex error), whose
        sum −k − 2iΩ sin φ and product ω_s² give: both roots have the same damping ratio
        ζ, half the difference of their imaginary parts is Ω|sin φ| and the product of
        their sizes is ω_s², so with Ω_ζ = Ω|sin φ|/√(1 − ζ²) the sizes are
        ω̄_ζ ∓ Ω_ζ, ω̄_ζ = √(ω_s² + Ω_ζ²).

        Parameters
        ----------
        damping_ratio : float
            ζ of the pair (|ζ| < 1; negative for a growing pair; 0: undamped).
        """
        if self.schuler is None or self.foucault is None:
            return None
        turn = self.foucault / float(np.sqrt(1.0 - damping_ratio**2))
        mean = float(np.hypot(self.schuler, turn))
        return mean - turn, mean + turn

    def to_dict(self) -> dict:
        return {name: None if c is None else c.to_dict()
                for name, c in (("g", self.g), ("R", self.R), ("Omega", self.Omega))}


def _named(model: Model, kind: str, values: np.ndarray) -> dict[str, float]:
    return {info.name: float(v) for info, v in zip(getattr(model, kind), values, strict=True)}


def references(model: Model, u: np.ndarray, p: np.ndarray, latitude: float | None,
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
    latitude : float or None
        Latitude of the base, rad (None: the model has none).
    height : float
        Height of the base, m.

    Returns
    -------
    References
    """
    earth = earth_constants(_named(model, "parameters", p),
                            {info.name: info.unit for info in model.parameters},
                            _named(model, "inputs", u),
                            None if latitude is None else float(latitude), height)
    return References(earth.gravity, earth.radius, earth.earth_rate,
                      None if latitude is None else float(latitude))
