"""Names for a constant hand/model ratio that is a slip, not a number (no SymPy).

A wrong coefficient whose ratio to the model's is constant is reported with the ratio.
Some ratios say what happened: a factor of the Earth radius or of gravity too many or
too few (``-g/R*psi`` for ``-g*psi``: hand/model = 1/R = 1.56961e-07), a factor 2 (a
Coriolis 2Ω written Ω), a unit slip (a value in deg/h where the model has rad/s:
206265; deg for rad: 57.3; per hour for per second: 3600), and, at a single latitude
(``@scope static base``), a ratio that is tan φ or cot φ there: sin φ and cos φ
swapped (the multi-point check names this from the expressions; at one latitude only
the number is seen, so it is a question). The hand-derivation check, which sees both
coefficients, names a constant ratio that is a trigonometric function of an angle they
hold (tan, cot, sin, csc, cos, sec) as a factor too many or missing
(:func:`trig_factor`), after a slip of a function the hand writes.
Both checkers (:mod:`~ins_errors.checker.classify`, :mod:`~ins_errors.checker.matrix`)
name these ratios in their details.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

EXACT = 1e-9
"""Relative agreement of a ratio with a named value ("within rounding")."""


def factors(radius: float | None, gravity: float | None, radius_name: str = "R",
            gravity_name: str = "g") -> list[tuple[str, float]]:
    """The named factors a ratio is compared with: 2, 1/2, and the model's Earth radius
    and gravity, each also inverted and the radius squared, as (name, value).

    Parameters
    ----------
    radius, gravity : float or None
        The model's Earth radius (m) and gravity (m/s²); None leaves them out.
    radius_name, gravity_name : str
        How the model names them (``R``, ``a``; ``g``).
    """
    out = [("2", 2.0), ("1/2", 0.5)]
    if radius:
        said = f" ({radius_name} = {radius:.4g} m)"
        out += [(f"1/{radius_name}{said}", 1.0 / radius), (f"{radius_name}{said}", radius),
                (f"{radius_name}²{said}", radius ** 2),
                (f"1/{radius_name}²{said}", 1.0 / radius ** 2)]
    if gravity:
        said = f" ({gravity_name} = {gravity:.6g} m/s²)"
        out += [(f"{gravity_name}{said}", gravity), (f"1/{gravity_name}{said}", 1.0 / gravity)]
    return out


UNIT_ROUNDED = 1e-3
"""Relative agreement of a ratio with a unit factor (:data:`UNIT_FACTORS`): a constant
converted by hand is typed to a few digits (57.3 for 180/π is 7e-4 off; 15.041 deg/h
for the Earth rate 2e-5)."""

_ARCSEC = 180 * 3600 / np.pi
UNIT_FACTORS = (
    ("206265", _ARCSEC, "rad → arcsec, or rad/s → deg/h (15.041 deg/h is the Earth rate "
     "7.292e-5 rad/s)"),
    ("1/206265", 1 / _ARCSEC, "arcsec → rad, or deg/h → rad/s"),
    ("57.2958", 180 / np.pi, "rad → deg, or rad/s → deg/s"),
    ("1/57.2958", np.pi / 180, "deg → rad, or deg/s → rad/s"),
    ("3600", 3600.0, "s/h: a rate per second written per hour, or the other way"),
    ("1/3600", 1 / 3600.0, "h/s: a rate per hour written per second, or the other way"),
)
"""Ratios a value in the wrong unit gives (name, value, which conversion), named within
:data:`UNIT_ROUNDED` as a unit slip."""


def factor_name(ratio: float, named: list[tuple[str, float]], units: bool = True
                ) -> tuple[str, str] | None:
    """(name, suggestion) when ``ratio`` is one of the ``named`` factors (:func:`factors`)
    or minus one, to :data:`EXACT`: ``("1/R (R = 6.371e+06 m)", "a factor 1/R too
    many?")``, ``("−2", "a factor 2 too many and the wrong sign?")``; or one of the
    :data:`UNIT_FACTORS`, to :data:`UNIT_ROUNDED`: ``("206265", "a unit slip? 206265 =
    rad → arcsec, ...")`` (not with ``units`` False); None otherwise."""
    for name, value in named:
        for sign, text in ((1.0, ""), (-1.0, "−")):
            if abs(ratio - sign * value) <= EXACT * value:
                bare = name.split(" (")[0]
                return (f"{text}{name}", f"a factor {bare} too many"
                        + (" and the wrong sign?" if sign < 0 else "?"))
    for name, value, conversion in UNIT_FACTORS if units else ():
        for sign, text in ((1.0, ""), (-1.0, "−")):
            if abs(ratio - sign * value) <= UNIT_ROUNDED * value:
                return (f"{text}{name}", f"a unit slip? {name} = {conversion}"
                        + (" (and the wrong sign)" if sign < 0 else ""))
    return None


def ratio_text(ratio: float, named: list[tuple[str, float]], where: str) -> str:
    """``"hand/model = 1.56961e-07 = 1/R (R = 6.371e+06 m) WHERE: a factor 1/R too
    many?"``, ``"hand/model = 2 WHERE: a factor 2 too many?"``, or without a name
    ``"hand/model = 0.8391 WHERE"`` (``where``: ``at every point``, ``at every
    sample``)."""
    found = factor_name(ratio, named)
    text = f"hand/model = {ratio:.6g}"
    if found is None:
        return f"{text} {where}"
    name, says = found
    shown = "" if name.lstrip("−") in ("2", "1/2") or says.startswith("a unit slip") \
        else f" = {name}"
    return f"{text}{shown} {where}: {says}"


TRIG = (
    ("cot φ", lambda s, c: c / s, "cos φ written where sin φ belongs?"),
    ("tan φ", lambda s, c: s / c, "sin φ written where cos φ belongs?"),
    ("sin φ", lambda s, c: s, "a factor sin φ too many?"),
    ("cos φ", lambda s, c: c, "a factor cos φ too many?"),
    ("1/sin φ", lambda s, c: 1.0 / s, "a factor sin φ left out?"),
    ("1/cos φ", lambda s, c: 1.0 / c, "a factor cos φ left out?"),
)
"""Ratios of the latitude a constant hand/model at one latitude is compared with, each
with what it suggests."""


def trig_name(ratio: np.ndarray, latitude: np.ndarray) -> str:
    """``"cot φ: cos φ written where sin φ belongs?"`` when hand/model equals one of
    :data:`TRIG` of the latitude at every sample (to :data:`EXACT`, either sign: a minus
    adds "and the sign"), ``""`` otherwise.

    Parameters
    ----------
    ratio, latitude : ndarray, shape (S,)
        hand/model and the latitude (rad) at the same samples.
    """
    if not ratio.size or ratio.shape != latitude.shape:
        return ""
    s, c = np.sin(latitude), np.cos(latitude)
    with np.errstate(all="ignore"):
        for name, value, says in TRIG:
            v = value(s, c)
            if not np.all(np.isfinite(v)) or np.any(np.abs(np.abs(v) - 1.0) <= 1e-6):
                continue  # (at φ = 45° tan = cot = 1: no name says which)
            for sign, text in ((1.0, ""), (-1.0, "−")):
                if np.all(np.abs(ratio - sign * v) <= EXACT * np.abs(v)):
                    return (f"{text}{name}: {says}"
                            + (" (and the sign)" if sign < 0 else ""))
    return ""


TRIG_FACTORS = (("tan", "cot", lambda s, c: s / c), ("sin", "csc", lambda s, c: s),
                ("cos", "sec", lambda s, c: c))
"""The functions of an angle a constant hand/model is compared with by
:func:`trig_factor` (name, the name of its inverse, value from sin and cos), in the
order they are tried."""


def trig_factor(ratio: float, sine: float, cosine: float, angle: str = "phi"
                ) -> tuple[str, str] | None:
    """(name, suggestion) when ``ratio`` is a trigonometric function of an angle or its
    inverse, to :data:`EXACT` (either sign): ``("cot(phi)", "a factor tan(phi)
    missing?")``, ``("−sin(phi)", "a factor sin(phi) too many and the wrong sign?")``;
    None otherwise, and for a value within 1e-6 of ±1 or 0 (at 45° tan = cot = 1: no name
    says which), which a factor of :func:`factors` (2, 1/2) names first.

    Parameters
    ----------
    ratio : float
        hand/model, constant.
    sine, cosine : float
        sin and cos of the angle where it was measured.
    angle : str
        How the angle is written (``phi``).
    """
    if not (np.isfinite(ratio) and np.isfinite(sine) and np.isfinite(cosine)):
        return None
    for name, inverse, value in TRIG_FACTORS:
        with np.errstate(all="ignore"):
            v = float(value(sine, cosine))
        if not np.isfinite(v) or abs(v) <= 1e-6 or abs(abs(v) - 1.0) <= 1e-6:
            continue
        for shown, target, says in ((name, v, "too many"), (inverse, 1.0 / v, "missing")):
            for sign, text in ((1.0, ""), (-1.0, "−")):
                if abs(ratio - sign * target) <= EXACT * abs(target):
                    return (f"{text}{shown}({angle})", f"a factor {name}({angle}) {says}"
                            + (" and the wrong sign?" if sign < 0 else "?"))
    return None


def earth_factors(model, parameters: Mapping[str, float] | None = None
                  ) -> list[tuple[str, float]]:
    """:func:`factors` of a model (a definition or a loaded model: anything with
    ``parameters`` that have ``name``, ``unit`` and ``default``), with its own names of
    the radius and gravity parameters and the values set (SI)."""
    from ins_errors.checker.typical import _earth
    from ins_errors.earth_constants import earth_parameter_names

    radius, gravity = _earth(model, parameters)
    names = earth_parameter_names(model.parameters)
    return factors(radius, gravity, names.radius or "R", names.gravity or "g")


__all__ = ["UNIT_FACTORS", "earth_factors", "factor_name", "factors", "ratio_text",
           "trig_factor", "trig_name"]
