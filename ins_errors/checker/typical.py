"""Typical error sizes by SI unit (no SymPy needed).

The matrix check weighs its terms with fixed sizes (:func:`typical_magnitude`,
:mod:`~ins_errors.checker.matrix`); equation checks, and a matrix check given an attitude
error, tie them together by the Schuler loop instead (:func:`schuler_magnitudes`), from
the model's Earth radius and gravity: its parameters, read from the SymPy definition or
from the generated package's metadata alike.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache

from ins_errors.earth_constants import earth_constants
from ins_errors.errors import InsErrorsError
from ins_errors.models.earth import STANDARD_GRAVITY
from ins_errors.units import parse_quantity

MAGNITUDE_UNITS = {"rad": "rad", "1": "1", "m/s": "m/s", "rad/s": "rad/s",
                   "m/s**2": "m/s**2", "m": "m"}
"""SI units of error quantities that have a typical magnitude."""

TYPICAL_BY_UNIT = {
    "rad": ("1e-4 rad", "rad"),
    "1": ("1e-4", "1"),
    "m/s": ("0.1 m/s", "m/s"),
    "rad/s": ("0.01 deg/h", "rad/s"),
    "m/s**2": ("1e-4 g", "m/s**2"),
    "m": ("10 m", "m"),
}
"""Fixed typical sizes by SI unit (text, unit), kept for the matrix check
(:mod:`ins_errors.checker.matrix`); equation checks use :func:`schuler_magnitudes`."""

_CONVERTED = {"1e-4": 1e-4, "0.01 deg/h": 0.01 * math.pi / 180 / 3600,
              "1e-4 g": 1e-4 * STANDARD_GRAVITY}
"""The fixed sizes of :data:`TYPICAL_BY_UNIT` that :func:`~ins_errors.units.parse_quantity`
reads with pint (a plain ratio, units other than SI), in SI: the same bits as pint's
conversion, which a test checks. A matrix check reads no other text, and importing pint
for these (~0.3 s CPU) cost about as much as the check's own arithmetic."""


@cache
def typical_magnitude(unit: str) -> tuple[float, str]:
    """Fixed typical size (SI) and its spelling for an error quantity of ``unit``.

    Raises
    ------
    InsErrorsError
        If no typical size is known for that unit.
    """
    if unit not in TYPICAL_BY_UNIT:
        raise InsErrorsError(f"no typical error magnitude for unit {unit!r} "
                             f"(known: {', '.join(TYPICAL_BY_UNIT)})")
    text, si = TYPICAL_BY_UNIT[unit]
    if text in _CONVERTED:
        return _CONVERTED[text], text
    return parse_quantity(text, si, "typical magnitude"), text


def magnitude_override(unit: str, text: str) -> float:
    """A typical size given by the user for one SI unit, checked and in SI.

    Parameters
    ----------
    unit : str
        One of :data:`MAGNITUDE_UNITS` (``"rad"``, ``"m/s"``, ...).
    text : str
        The size with its unit (``"0.5 m/s"``).

    Returns
    -------
    float
        The size in ``unit``, positive.

    Raises
    ------
    InsErrorsError
        For an unknown unit or a size that is not positive.
    """
    if unit not in MAGNITUDE_UNITS:
        raise InsErrorsError(f"magnitude for unknown unit {unit!r} (known: "
                             f"{', '.join(MAGNITUDE_UNITS)}, or 'attitude')")
    value = parse_quantity(text, unit, f"magnitude of {unit}")
    if not value > 0:
        raise InsErrorsError(f"magnitude of {unit} must be positive, got {text!r}")
    return value


GRAVITY = 9.81
"""Apparent vertical acceleration a_ζ at the checker's reference points, and the gravity
of a model without a gravity parameter, m/s²."""

DEFAULT_ATTITUDE = "1e-4 rad"
"""Declared attitude error the Schuler-consistent magnitudes are built from."""


@dataclass(frozen=True)
class Magnitudes:
    """Typical error sizes by SI unit, and how they were obtained.

    Attributes
    ----------
    by_unit : dict
        SI unit -> (value in SI, text as people write it).
    origin : str
        One line: the relations and the declared attitude error they come from.
    """

    by_unit: dict[str, tuple[float, str]]
    origin: str

    def of(self, unit: str) -> tuple[float, str]:
        """Typical size (SI) and its spelling for an error quantity of ``unit``."""
        if unit not in self.by_unit:
            raise InsErrorsError(f"no typical error magnitude for unit {unit!r} "
                                 f"(known: {', '.join(self.by_unit)})")
        return self.by_unit[unit]


def _earth(d, parameters: Mapping[str, float] | None = None) -> tuple[float, float]:
    """(Earth radius R in m, gravity g in m/s²) of a model, from its parameters' defaults
    and the values set (:func:`ins_errors.earth_constants.earth_constants`: the radius or
    semi-major axis itself, no curvature at a latitude); 6 371 km and :data:`GRAVITY`
    where it has none.

    ``d``: anything with ``parameters`` that have ``name``, ``unit`` and ``default``: a
    :class:`~ins_errors.modeling.ModelDefinition` or a loaded
    :class:`~ins_errors.numeric.model.Model` (whose metadata records the same defaults).
    ``parameters``: name -> SI value of those set (``-p NAME=VALUE``), replacing defaults.
    """
    values = {p.name: float(p.default) for p in d.parameters}
    values.update(parameters or {})
    earth = earth_constants(values, {p.name: p.unit for p in d.parameters})
    return (6_371_000.0 if earth.radius is None else earth.radius.value,
            GRAVITY if earth.gravity is None else earth.gravity.value)


def _text(value: float, unit: str) -> str:
    shown = {"m/s**2": "m/s²", "1": ""}.get(unit, unit)
    return f"{value:.3g} {shown}".strip()


def schuler_magnitudes(d, attitude: str | float = DEFAULT_ATTITUDE,
                       overrides: dict[str, str] | None = None,
                       parameters: Mapping[str, float] | None = None) -> Magnitudes:
    """Typical error sizes tied together by the Schuler loop of model ``d``.

    Parameters
    ----------
    d : ModelDefinition or Model
        Supplies the Earth radius and gravity (the parameters
        :func:`ins_errors.earth_constants.earth_constants` knows; else 6371 km and
        9.81 m/s²).
    attitude : str or float
        Declared attitude error θ (``"20 arcsec"``, or radians).
    overrides : dict, optional
        SI unit (``"m/s"``, ``"rad/s"``...) -> quantity text (``"0.1 m/s"``) replacing
        the Schuler value.
    parameters : mapping of str to float, optional
        Parameter values set (SI), replacing the defaults the radius and gravity are
        read from.

    Returns
    -------
    Magnitudes
    """
    theta = (float(attitude) if isinstance(attitude, (int, float))
             else parse_quantity(attitude, "rad", "attitude error"))
    if not theta > 0:
        raise InsErrorsError(f"the attitude error must be positive, got {attitude!r}")
    radius, gravity = _earth(d, parameters)
    omega_s = math.sqrt(gravity / radius)
    values = {"rad": theta, "1": theta, "m/s": math.sqrt(gravity * radius) * theta,
              "m": radius * theta, "rad/s": omega_s * theta, "m/s**2": gravity * theta}
    by_unit = {unit: (value, _text(value, unit)) for unit, value in values.items()}
    by_unit["rad/s"] = (values["rad/s"], f"{values['rad/s'] * 180 / math.pi * 3600:.3g} deg/h")
    shown_theta = attitude if isinstance(attitude, str) else f"{theta:g} rad"
    origin = (f"Schuler relations from a declared attitude error θ = {shown_theta} "
              f"(R = {radius:.0f} m, g = {gravity:g} m/s², ω_s = √(g/R) = "
              f"{omega_s:.4g} rad/s, Schuler period {2 * math.pi / omega_s / 60:.1f} min): "
              "angles θ, velocities √(gR)·θ, positions R·θ, rates ω_s·θ, accelerations g·θ")
    changed = []
    for unit, text in (overrides or {}).items():
        by_unit[unit] = (magnitude_override(unit, text), text)
        changed.append(f"{unit}: {text}")
    if changed:
        origin += "; overridden: " + ", ".join(changed)
    return Magnitudes(by_unit, origin)
