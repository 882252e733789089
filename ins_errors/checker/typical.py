"""Fixed typical error sizes by SI unit (no SymPy needed).

The matrix check weighs its terms with these (:mod:`~ins_errors.checker.matrix`);
equation checks tie their sizes together by the Schuler loop instead
(:func:`ins_errors.checker.reference.schuler_magnitudes`).
"""

from __future__ import annotations

from functools import cache

from ins_errors.errors import InsErrorsError
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
