"""Earth models: reference ellipsoids and the Earth rotation rate.

Values are those of ``shared/spec/NOTES.md``: Krasovsky (1940) a = 6 378 245 m,
f = 1/298.3 (the default of the source documents); WGS-84 a = 6 378 137 m,
f = 1/298.257223563; Earth rate U = 7.292115e-5 rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass

from ins_errors.errors import unknown_name

EARTH_RATE = 7.292115e-5
"""Earth rotation rate U, rad/s."""


@dataclass(frozen=True)
class Ellipsoid:
    """A reference ellipsoid.

    Attributes
    ----------
    name : str
        Registry name.
    semi_major_axis : float
        a, m.
    flattening : float
        f, dimensionless.
    """

    name: str
    semi_major_axis: float
    flattening: float

    @property
    def eccentricity_squared(self) -> float:
        """First eccentricity squared e^2 = 2f - f^2."""
        return 2.0 * self.flattening - self.flattening**2


ELLIPSOIDS: dict[str, Ellipsoid] = {
    "krasovsky": Ellipsoid("krasovsky", 6_378_245.0, 1.0 / 298.3),
    "wgs84": Ellipsoid("wgs84", 6_378_137.0, 1.0 / 298.257223563),
}


def ellipsoid(name: str) -> Ellipsoid:
    """Look up a reference ellipsoid by name (``"krasovsky"`` or ``"wgs84"``)."""
    try:
        return ELLIPSOIDS[name.lower()]
    except KeyError:
        raise unknown_name("ellipsoid", name, ELLIPSOIDS) from None
