"""Model parameters set by the user: ``--parameter NAME=VALUE`` and a scenario's ``[parameters]``.

A model's parameters (Earth shape, gravity constants, loop gains; ``ins-errors models
MODEL`` lists them) have defaults; a run may set any of them, each with its unit
(``k_h1 = "0.0047 1/s"``), read at the edge by :mod:`ins_errors.units` and kept SI. The
vertical damping gains of ``strapdown_ned`` are the reason this exists: ``k_h1`` (1/s) on
the height difference in ``ḣ`` and ``k_h2`` (1/s²) in ``v̇_D``; ``k_h1 = 2ζω₀``,
``k_h2 = ω₀² + 2γ/R`` give a loop of natural frequency ω₀ and damping ζ (0: undamped).

Gains (:data:`NON_NEGATIVE`, and any parameter a model flags as a damping gain) must not
be negative: a negative gain turns the damping loop into a second source of divergence,
which no one means to ask for.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Literal, overload

import numpy as np

from ins_errors.errors import InsErrorsError, unknown_name

MIN_EARTH_RADIUS = 100e3
"""m: the smallest Earth radius (semi-major axis) a run takes. Below it the ±100 km heights
of a motion reach the centre (R + h ≤ 0), the course of a flight turns hundreds of radians
a second, and the Schuler period 2π√(R/g) shrinks from the Earth's 84 min to seconds (2 s
at R = 1 m), below any integration step."""

MAX_EARTH_RADIUS = 1e12
"""m: the largest Earth radius a run takes. The models hold the relative velocity as the
angular rate v/R beside the Earth rate U; float64 rounds their sum to about 1.4e-20 rad/s,
which is 1.4e-8 m/s of velocity at 1e12 m. It grows with R: at 1e16 m a static run's
velocity errors are 0.2 % off, at 1e30 m a 0.01 deg/h drift gives 3e8 m/s. A flat Earth is
approached well within the limit (1e12 m is flat to 1e-7 rad over 100 km)."""

NON_NEGATIVE = {"k_h1": "vertical damping gain", "k_h2": "vertical damping gain"}
"""Parameters (of any model that has them) that must be zero or positive, with what they are."""


def parse_parameters(model, values: Mapping[str, object], where: str = "",
                     numbers_are_si: bool = True) -> dict[str, float]:
    """Read parameter values with their units, checked against the model.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model or ins_errors.modeling.ModelDefinition
        The model whose parameters are set (a definition for the equation checker,
        which needs no generated code).
    values : mapping of str to str or float
        Parameter name -> value with unit (``"0.0047 1/s"``); a bare number is SI when
        ``numbers_are_si``, refused otherwise (scenario files).
    where : str
        Prefix of messages (``"s.toml [parameters]"``).
    numbers_are_si : bool
        Accept a bare number as SI.

    Returns
    -------
    dict of str to float
        The values in SI units.

    Raises
    ------
    InsErrorsError
        One line: an unknown name (close names suggested), a value without unit or in
        the wrong unit, NaN or infinity, a negative gain, an Earth radius that is not
        positive or an eccentricity squared outside [0, 1).
    """
    from ins_errors.units import parse_quantity

    out: dict[str, float] = {}
    prefix = f"{where}: " if where else ""
    for name, text in values.items():
        try:
            info = parameter_info(model, name)
        except InsErrorsError as error:
            raise type(error)(f"{prefix}{error}") from None
        try:
            value = parse_quantity(text, info.unit, name, numbers_are_si=numbers_are_si)
        except InsErrorsError as error:
            raise type(error)(f"{prefix}{error}") from None
        problem = parameter_problem(model, info, value)
        if problem is not None:
            raise InsErrorsError(f"{prefix}{name} = {text!r}: {problem}")
        out[name] = value
    return out


def parameter_problem(model, info, value: float) -> str | None:
    """Why ``value`` (SI) cannot be parameter ``info`` of ``model``, or None: a negative
    gain (:data:`NON_NEGATIVE`, or a parameter the model flags as a damping gain), an
    Earth radius that is not positive, an eccentricity squared outside [0, 1).

    The one rule for values read from text (:func:`parse_parameters`) and for values
    given in SI (:meth:`~ins_errors.numeric.model.Model.parameter_vector`).
    """
    gain = NON_NEGATIVE.get(info.name) or (
        "damping gain" if getattr(info, "damping_gain", False) else None)
    if gain is not None and value < 0:
        return f"a {gain} must be zero (undamped) or positive, in {info.unit}"
    return _earth_problem(model, info.name, value, getattr(info, "description", "") or "")


def _radius_words(description: str) -> str:
    """The radius parameter as a refusal names it: the Earth's radius, or the model's own
    radius by its description where it is another (free_azimuth's tuning radius)."""
    words = description.lower()
    if "radius" in words and "earth" not in words:
        return f"the {description} (the model's Earth radius)"
    return "the Earth's radius (semi-major axis)"


def _earth_problem(model, name: str, value: float, description: str = "") -> str | None:
    """Why ``value`` (SI) cannot be the Earth radius or eccentricity² that parameter
    ``name`` of ``model`` is read as (:mod:`ins_errors.earth_constants`: the first
    radius name in m, the first eccentricity name of unit 1), else None."""
    from ins_errors.earth_constants import earth_parameter_names

    earth = earth_parameter_names(model.parameters)
    if name == earth.radius and not value > 0:
        return f"{_radius_words(description)} must be positive, in m"
    if name == earth.radius and value < MIN_EARTH_RADIUS:
        return (f"an Earth radius of {value:g} m is below {MIN_EARTH_RADIUS / 1e3:g} km, "
                f"the smallest planet-sized body the models hold: at ±100 km heights R + h "
                f"reaches the centre, a flight's course turns hundreds of radians a "
                f"second, and the Schuler period 2π√(R/g) falls to "
                f"{2 * np.pi * np.sqrt(value / 9.80665):.3g} s (84 min for the Earth)")
    if name == earth.radius and value > MAX_EARTH_RADIUS:
        return (f"an Earth radius of {value:g} m is beyond {MAX_EARTH_RADIUS:g} m: the models "
                f"hold the velocity as the angular rate v/R beside the Earth rate, whose "
                f"rounding (1.4e-20 rad/s) is then {1.4e-20 * value:.2g} m/s of velocity "
                f"(for a flat Earth, {MAX_EARTH_RADIUS:g} m is flat to 1e-7 rad over 100 km)")
    if name == earth.eccentricity and not 0 <= value < 1:
        return ("the Earth's eccentricity squared must be at least 0 (a sphere) and below "
                "1 (0.00669 for WGS-84)")
    return None


SOURCE_LIMITS: dict[str, tuple[float, str, str]] = {
    "rad": (2.0 * np.pi, "360° (one turn)",
            "an angle error beyond one turn is the same attitude as one within it, and the "
            "linear error model holds only below about 0.1 rad (5.7°)"),
    "rad/s": (1.0, "1 rad/s (57°/s, 206 265 deg/h)",
              "such a drift turns the platform a full turn in 6 s; even a consumer MEMS "
              "gyro's bias is about 1°/s"),
    "m/s**2": (10.0 * 9.80665, "10 g",
               "beyond the accelerations the instrument measures; even a consumer MEMS "
               "accelerometer's bias is about 0.1 g"),
    "1": (1.0, "1 (100 %)",
          "a scale-factor or gain error of 100 % or more leaves the instrument reading zero "
          "or twice the truth, no longer an error of it"),
    "m/s": (7909.0, "7.91 km/s",  # earth_constants.FIRST_COSMIC_VELOCITY, rounded
            "the first cosmic velocity √(g a): nothing faster holds a height above the "
            "Earth"),
    "m": (2.0e7, "20 000 km",
          "no two points on the Earth are farther apart than half its circumference"),
}
"""Largest magnitude of an error source by its SI unit (SI value, the same in words, why);
:func:`source_problem` refuses a larger one (for unit 1, that one too). Sources in other
units (noise densities) are not limited. The limits lie far beyond any instrument or
alignment: a larger value is a unit or exponent slip (``1e30 deg/h``), whose runs
otherwise leave the model's domain with no word of the source, or run on with the sines
of rounding noise."""


def source_problem(info, value: float) -> str | None:
    """Why ``value`` (SI) cannot be the magnitude of error source ``info``, or None: a
    magnitude beyond :data:`SOURCE_LIMITS` for its unit. The reason reads on from the
    value (``"is beyond 360° (one turn), ..."``).

    Parameters
    ----------
    info : ins_errors.numeric.model.Info
        The source's description (its ``unit`` is SI).
    value : float
        The magnitude, SI.
    """
    limit = SOURCE_LIMITS.get(info.unit)
    if limit is None:
        return None
    largest, bound, why = limit
    if (abs(value) >= largest) if info.unit == "1" else not abs(value) <= largest:
        verb = "reaches" if info.unit == "1" else "is beyond"
        return (f"{verb} {bound}, the largest magnitude a run can mean ({why}); a unit or "
                f"exponent slip?")
    return None


def check_source(info, value: float, text: object) -> float:
    """``value`` (SI) if :func:`source_problem` finds nothing in it.

    Parameters
    ----------
    info : ins_errors.numeric.model.Info
        The source.
    value : float
        Its magnitude, SI.
    text : object
        The value as the user gave it, for the message.

    Raises
    ------
    InsErrorsError
        One line naming the source, the value as given and why it is refused.
    """
    problem = source_problem(info, value)
    if problem is not None:
        raise InsErrorsError(f"{info.name} = {text!r} {problem}")
    return value


def parameter_info(model, name: str):
    """The description of parameter ``name`` of ``model`` (a loaded model or a
    definition: anything with ``name`` and ``parameters`` that have ``name`` and ``unit``).

    Raises
    ------
    UnknownNameError
        For a name the model does not have (close names suggested).
    """
    names = [info.name for info in model.parameters]
    if name not in names:
        raise unknown_name(f"parameter of {model.name}", name, names)
    return model.parameters[names.index(name)]


def parameters_record(model, parameters: Mapping[str, float]) -> dict[str, dict[str, object]]:
    """The parameters a run set, for its machine-readable output (JSON).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model or ins_errors.modeling.ModelDefinition
        The model whose parameters were set.
    parameters : mapping of str to float
        Parameter name -> SI value, as :func:`parse_parameters` returned (the others kept
        the model's defaults).

    Returns
    -------
    dict of str to dict
        Name -> ``{"value": SI value, "unit": SI unit}``, in the order given; empty when
        every parameter kept its default.
    """
    return {name: {"value": float(value), "unit": parameter_info(model, name).unit}
            for name, value in parameters.items()}


def parameters_used(model, p) -> dict[str, dict[str, object]]:
    """Every parameter's value in a run, for its record (report, JSON).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    p : array_like, shape (np,)
        The parameter vector the run used (defaults, Earth model and the values set).

    Returns
    -------
    dict of str to dict
        Name -> ``{"value": SI value, "unit": SI unit}`` for every parameter, in the
        model's order.
    """
    return {info.name: {"value": float(value), "unit": info.unit}
            for info, value in zip(model.parameters, p, strict=True)}


@overload
def name_value_pairs(items: Iterable[str], option: str, example: str,
                     optional: Literal[False] = False) -> dict[str, str]: ...


@overload
def name_value_pairs(items: Iterable[str], option: str, example: str,
                     optional: Literal[True]) -> dict[str, str | None]: ...


def name_value_pairs(items: Iterable[str], option: str, example: str,
                     optional: bool = False) -> dict[str, str] | dict[str, str | None]:
    """Split repeated ``OPTION NAME=VALUE`` items into names and value texts, in order.

    Parameters
    ----------
    items : iterable of str
        The items as given (``"k_h1=0.0047/s"``).
    option : str
        The option, for the messages (``"--parameter"``).
    example : str
        An item that is right, for the messages.
    optional : bool
        The value may be left out: a bare ``NAME`` gives None.

    Returns
    -------
    dict of str to str (or None)
        Name to value text, in the order given.

    Raises
    ------
    InsErrorsError
        For an item without a name, with ``=`` and no value, without ``=`` where the value
        is not ``optional`` (the message shows ``example``), or a name given twice.
    """
    values: dict[str, str | None] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        missing = not text.strip() and (bool(sep) or not optional)
        if not name or missing:
            expected = "NAME or NAME=VALUE" if optional else "NAME=VALUE"
            raise InsErrorsError(f"{option} {item!r}: expected {expected}, e.g. {example}")
        if name in values:
            raise InsErrorsError(f"{option} {name} given twice")
        values[name] = text if sep else None
    return values


def parse_parameter_options(model, items: Iterable[str]) -> dict[str, float]:
    """Read repeated ``--parameter NAME=VALUE`` options (see :func:`parse_parameters`).

    Raises
    ------
    InsErrorsError
        For an item without ``=``, a name given twice, or a bad value.
    """
    values = name_value_pairs(items, "--parameter", "k_h1=0.0047/s")
    return parse_parameters(model, values, "--parameter")
