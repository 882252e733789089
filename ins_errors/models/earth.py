"""The Earth, in one place: ellipsoids, rotation rate, radii of curvature, gravity.

Values are those of the source documents' notes: Krasovsky (1940) a = 6 378 245 m,
f = 1/298.3 (the default of the source documents); WGS-84 a = 6 378 137 m,
f = 1/298.257223563; Earth rate U = 7.292115e-5 rad/s.

Conventions, for every model, trajectory generator and budget:

* latitude φ is geodetic (angle of the ellipsoid normal to the equator);
* height h is measured along the ellipsoid normal, so a point at height h has the radii
  of curvature ``R_N + h`` (meridian) and ``R_E + h`` (prime vertical);
* gravity means normal gravity γ(φ, h) of the ellipsoid (gravitation plus centrifugal),
  along the normal (:func:`normal_gravity`);
* a model names its Earth with the parameters ``a`` and ``e2`` (or ``R`` and ``ecc2``;
  ``R`` alone is a sphere) and ``U``; :func:`earth_shape` reads them and refuses a model
  that lacks one, instead of filling in a constant.
"""

from __future__ import annotations

from dataclasses import dataclass

from ins_errors.errors import unknown_name

EARTH_RATE = 7.292115e-5
"""Earth rotation rate U, rad/s."""

MEAN_RADIUS = 6_371_000.0
"""Mean Earth radius rounded to the kilometre, m (the IUGG mean radius is 6 371 008.8 m);
the default sphere of the spherical models."""

STANDARD_GRAVITY = 9.80665
"""Standard gravity g₀, m/s² (the g of '1e-4 g' and a constant-gravity model's default)."""


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


# --------------------------------------------------------------------------------------
# Radii of curvature and normal gravity (generic: numpy arrays or SymPy expressions)
# --------------------------------------------------------------------------------------
WGS84_EQUATORIAL_GRAVITY = 9.7803253359
"""Normal gravity on the equator of the WGS-84 ellipsoid γ_e, m/s² (NIMA TR8350.2, 4-1)."""

WGS84_SOMIGLIANA_K = 0.00193185265241
"""Somigliana constant k = (b γ_p)/(a γ_e) − 1 of WGS-84, dimensionless."""

WGS84_GRAVITY_M = 0.00344978650684
"""m = ω² a² b / GM of WGS-84, dimensionless (enters the height dependence of γ)."""


def radii_of_curvature(latitude, a, e2, xp=None):
    """Meridian and prime-vertical radii of curvature of an ellipsoid.

    ``R_N = a (1 − e²) / (1 − e² sin² φ)^{3/2}`` (north-south, meridian) and
    ``R_E = a / (1 − e² sin² φ)^{1/2}`` (east-west, prime vertical).

    Parameters
    ----------
    latitude : array_like or sympy.Expr
        Geodetic latitude φ, rad.
    a : float or sympy.Expr
        Semi-major axis, m.
    e2 : float or sympy.Expr
        First eccentricity squared.
    xp : module, optional
        ``numpy`` (default) or ``sympy``: where ``sin`` and ``sqrt`` come from.

    Returns
    -------
    R_N, R_E
        Radii, m, shaped like ``latitude``.
    """
    xp = _numpy() if xp is None else xp
    w2 = 1 - e2 * xp.sin(latitude) ** 2
    w = xp.sqrt(w2)
    return a * (1 - e2) / (w2 * w), a / w


def normal_gravity(latitude, height, a, e2, gamma_e=WGS84_EQUATORIAL_GRAVITY,
                   k=WGS84_SOMIGLIANA_K, m=WGS84_GRAVITY_M, xp=None):
    """Normal gravity of the ellipsoid at geodetic latitude and height.

    Somigliana's closed formula on the ellipsoid, ``γ0 = γ_e (1 + k sin² φ) /
    (1 − e² sin² φ)^{1/2}``, continued to height ``h`` with the second-order series
    ``γ = γ0 [1 − 2 h/a (1 + f + m − 2 f sin² φ) + 3 h²/a²]`` (NIMA TR8350.2, eq. 4-3),
    ``f = 1 − (1 − e²)^{1/2}``. Near the ground its vertical gradient is about
    −2γ/a = −3.1e-6 s⁻², the source of the vertical-channel instability.

    Parameters
    ----------
    latitude, height : array_like or sympy.Expr
        Geodetic latitude φ (rad) and height above the ellipsoid h (m).
    a, e2 : float or sympy.Expr
        Semi-major axis (m) and first eccentricity squared.
    gamma_e, k, m : float or sympy.Expr
        Equatorial normal gravity (m/s²), Somigliana constant and ω²a²b/GM (WGS-84
        values by default).
    xp : module, optional
        ``numpy`` (default) or ``sympy``.

    Returns
    -------
    Magnitude of normal gravity, m/s², along the ellipsoid normal (downwards).
    """
    xp = _numpy() if xp is None else xp
    s2 = xp.sin(latitude) ** 2
    f = 1 - xp.sqrt(1 - e2)
    gamma0 = gamma_e * (1 + k * s2) / xp.sqrt(1 - e2 * s2)
    return gamma0 * (1 - 2 * height / a * (1 + f + m - 2 * f * s2) + 3 * height**2 / a**2)


def earth_shape(names, values, model: str = "the model") -> tuple[float, float, float]:
    """The Earth a model's parameter vector describes: (a, e², U).

    Parameters
    ----------
    names : sequence of str
        The model's parameter names.
    values : sequence
        Their values (numbers, or CasADi/SymPy symbols), same order.
    model : str
        Model name for messages.

    Returns
    -------
    a, e2, U
        Semi-major axis (``a`` or ``R``), m; eccentricity squared (``e2`` or ``ecc2``; 0
        for a model whose Earth is a sphere of radius ``R`` with no eccentricity
        parameter); Earth rate ``U``, rad/s.

    Raises
    ------
    InsErrorsError
        When the model has no radius or no Earth rate parameter (no fallback constant).
    """
    from ins_errors.errors import InsErrorsError

    a, e2 = earth_ellipsoid(names, values, model)
    p = dict(zip(names, values, strict=True))
    if "U" not in p:
        raise InsErrorsError(f"{model} has no Earth rate parameter 'U'")
    return a, e2, p["U"]


def earth_ellipsoid(names, values, model: str = "the model") -> tuple[float, float]:
    """The Earth shape a model's parameter vector describes: (a, e²), as
    :func:`earth_shape` without the Earth rate.

    Raises
    ------
    InsErrorsError
        When the model has no radius parameter (``a`` with ``e2``, or ``R``).
    """
    from ins_errors.errors import InsErrorsError

    p = dict(zip(names, values, strict=True))
    if "a" in p:
        a = p["a"]
        if "e2" not in p:
            raise InsErrorsError(f"{model} has a semi-major axis 'a' but no eccentricity "
                                 "parameter 'e2'")
        e2 = p["e2"]
    elif "R" in p:
        a, e2 = p["R"], p.get("ecc2", 0.0)
    else:
        raise InsErrorsError(f"{model} has no Earth radius parameter ('a' with 'e2', or "
                             "'R'): cannot compute its Earth")
    return a, e2


def _numpy():
    import numpy

    return numpy
