"""Engineering units at the edges (CLI, scenario and spec files, reports), via pint.

Inside the library everything is SI with radians. This module converts user text such
as ``"0.01 deg/h"``, ``"10 ug"``, ``"20 arcsec"``, ``"5 arcmin"``, ``"100 ppm"``,
``"0.1 m/s"`` or ``"1e-4 g"`` to SI numbers, checking that the dimension matches what
the quantity needs (an angle given in m/s is an error, not a silent number).

``g`` is standard gravity, 9.80665 m/s² (pint's ``g_0``); ``ug`` is a micro-g.
"""

from __future__ import annotations

import re
from functools import cache, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from ins_errors.errors import InsErrorsError
from ins_errors.models.earth import STANDARD_GRAVITY  # the g of the units g, mg, ug

if TYPE_CHECKING:
    import pint


class UnitError(InsErrorsError):
    """A quantity that cannot be parsed or has the wrong dimension."""


@cache
def registry() -> pint.UnitRegistry:
    """The shared pint registry, with the INS engineering units added.

    pint is imported here, when a unit is first converted: importing it (it imports
    dask where dask is installed) and building the registry cost about 0.5 s CPU, which
    e.g. ``make derive`` needs for nothing but numbers already in SI units.
    """
    import pint

    try:
        # pint keeps its parsed definition files in a cache folder (keyed by their
        # contents and pint's version): 0.33 -> 0.02 s CPU per process once it is there
        ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True,
                                 cache_folder=installation_folder(units_cache_directory()))
    except Exception:  # an unwritable or half-written cache folder: parse afresh
        ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    # 'g' means standard gravity in INS work (pint's 'g' is the gram).
    ureg.define(f"gee = {STANDARD_GRAVITY} * meter / second ** 2 = g_n")
    ureg.define("micro_gee = 1e-6 * gee = ug = µg")
    ureg.define("milli_gee = 1e-3 * gee = mg_n")
    ureg.define("parts_per_million_ins = 1e-6 = ppm_ins")
    return ureg


def units_cache_directory() -> Path:
    """The store of pint's parsed unit definitions (``$INS_ERRORS_CACHE/units`` or the
    user cache folder next to the compiled loops), one subfolder per pint installation
    (:func:`installation_folder`)."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("units")


INSTALLATION_FILE = "installation.txt"
"""The file of an installation's subfolder that names the pint folder it was made from
(first line) and the machine (second line)."""


def installation_folder(store: Path) -> Path:
    """This pint installation's subfolder of the units store, made if missing.

    pint finds a parsed file in its cache by the file's contents, but the parsed file
    names the definition files it includes by the folder it was first read from. Every
    virtual environment has its own copy of pint, so a set parsed by another checkout's
    environment is found by the contents and then read from that environment's folder;
    once the environment is deleted, every registry fails to load (and is parsed
    afresh, twice the time of no cache at all). Each installation therefore keeps its
    own set, in a subfolder named by the hash of pint's folder. Sets whose installation
    no longer exists on this machine, and the loose files of the earlier one-set layout,
    are deleted here (a set made on another machine sharing the cache folder is kept:
    its folder need not exist here).

    Raises
    ------
    OSError
        If the folder cannot be made or written.
    """
    import hashlib
    import platform
    import shutil

    import pint

    location = str(Path(pint.__file__).resolve().parent)
    host = platform.node()
    folder = store / hashlib.sha256(location.encode()).hexdigest()[:16]
    if (folder / INSTALLATION_FILE).is_file():
        return folder
    for entry in store.iterdir() if store.is_dir() else ():
        if entry.is_dir() and not entry.is_symlink():
            try:
                made_at, _, made_on = (entry / INSTALLATION_FILE).read_text(
                    "utf-8").partition("\n")
            except (OSError, UnicodeDecodeError):
                continue   # no note yet (being made by another process): kept
            if made_on.strip() == host and not Path(made_at).is_dir():
                shutil.rmtree(entry, ignore_errors=True)
        else:
            entry.unlink(missing_ok=True)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / INSTALLATION_FILE).write_text(f"{location}\n{host}\n", encoding="utf-8")
    return folder


_ALIASES = {"deg/hr": "deg/h", "°/h": "deg/h", "″": "arcsec", "′": "arcmin", "°": "deg"}


def _normalise(text: str) -> str:
    text = text.strip()
    for old, new in _ALIASES.items():
        text = text.replace(old, new)
    # a bare 'g' (or 'mg') means gravity, not grams; 'ppm' a plain ratio
    text = re.sub(r"(?<![A-Za-z_])g(?![A-Za-z_])", "gee", text)
    text = re.sub(r"(?<![A-Za-z_])mg(?![A-Za-z_])", "milli_gee", text)
    text = re.sub(r"(?<![A-Za-z_])ppm(?![A-Za-z_])", "ppm_ins", text)
    return text


UNIT_FAMILIES: dict[str, str] = {
    "rad": "an angle, e.g. '{v} deg', '{v} arcmin', '{v} arcsec' or '{v} rad'",
    "rad/s": "an angular rate, e.g. '{v} deg/h' or '{v} rad/s'",
    "m/s**2": "an acceleration, e.g. '{v} ug', '{v} mg', '{v} g' or '{v} m/s**2'",
    "m/s": "a velocity, e.g. '{v} m/s' or '{v} km/h'",
    "m": "a length, e.g. '{v} m' or '{v} km'",
    "s": "a time, e.g. '{v} s', '{v} min' or '{v} h'",
}
"""What a bare number lacks, by SI unit: the family of units expected, with examples."""


def _needs_unit(text: object, unit: str, what: str) -> UnitError:
    family = UNIT_FAMILIES.get(unit, f"a quantity in units of {unit}, e.g. '{{v}} {unit}'")
    return UnitError(f"{what}: {text!r} has no unit; give {family.format(v=text)}")


_IN_TARGET_UNIT = re.compile(
    r"\s*(?P<number>[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s+(?P<unit>[A-Za-z/*0-9]+)\s*")
"""A plain decimal number and a unit, e.g. ``"1e-4 rad"`` or ``"0.1 m/s"``."""

_PLAIN_SI = frozenset({"rad", "m", "m/s", "rad/s", "s"})
"""SI units that :func:`parse_quantity` reads without pint when the text is a plain
number in that very unit (pint's conversion factor is then exactly 1)."""


def parse_quantity(text: str | float | int, unit: str, what: str = "value", *,
                   numbers_are_si: bool = True) -> float:
    """Convert ``text`` to a float in the SI ``unit``.

    Parameters
    ----------
    text : str or float
        ``"0.01 deg/h"``, ``"10ug"``, ``"5 arcmin"``. Text must carry its unit when
        ``unit`` has one: ``"0.01"`` for a gyro drift is refused (it would silently mean
        0.01 rad/s); zero and plain ratios (``unit == "1"``) need none.
    unit : str
        Target SI unit as the model states it (``"rad/s"``, ``"m/s**2"``, ``"rad"``,
        ``"m/s"``, ``"1"``).
    what : str
        Name used in error messages (e.g. the error-source name).
    numbers_are_si : bool
        Whether a Python ``int``/``float`` is already in ``unit`` (library calls, the
        default) or, like bare text, needs a unit (numbers read from a user's file).

    Returns
    -------
    float
        The magnitude in ``unit``.

    Raises
    ------
    UnitError
        If the text does not parse, is not finite, lacks a unit, or has another
        dimension.
    """
    if isinstance(text, str):
        plain = _IN_TARGET_UNIT.fullmatch(text)
        if plain is not None and plain["unit"] == unit and unit in _PLAIN_SI:
            value = float(plain["number"])  # what pint gives: the same unit, factor 1
            if value - value == 0:  # finite (else pint's path words the error)
                return value
    if isinstance(text, bool):  # True is an int in Python: never a magnitude
        raise UnitError(f"{what}: expected a number or a quantity with a unit, got {text!r}")
    if isinstance(text, (int, float)):
        value = float(text)
        if not numbers_are_si and unit != "1" and value != 0 and value == value:
            raise _needs_unit(text, unit, what)
    else:
        try:
            value = _text_value(registry(), str(text), unit)
        except _UnreadableError as problem:
            raise UnitError(f"{what}: cannot read {text!r} as a quantity ({problem})") from None
        except _NoUnitError:
            raise _needs_unit(str(text).strip(), unit, what) from None
        except _OtherDimensionError as problem:
            raise UnitError(f"{what}: {text!r} has units of {problem}, which do not convert "
                            f"to {unit}") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise UnitError(f"{what}: {text!r} is not a finite number")
    return value


class _UnreadableError(Exception):
    """pint cannot parse the text (the message is pint's)."""


class _NoUnitError(Exception):
    """A plain number where the target unit needs one."""


class _OtherDimensionError(Exception):
    """A quantity whose units (the message) do not convert to the target unit."""


@lru_cache(maxsize=4096)
def _text_value(ureg: pint.UnitRegistry, text: str, unit: str) -> float:
    """``text`` in the SI ``unit`` through ``ureg`` (raises the problems above).

    Kept per process (and registry): scenario, spec and command-line values repeat the
    same few texts, and pint's parser costs ~0.3 ms CPU per call. A conversion depends
    on nothing but the registry, the text and the unit, which form the key; failures
    are not kept (they raise) and are worded by the caller.
    """
    try:
        quantity = ureg.parse_expression(_normalise(text))
    except Exception as error:  # pint raises several unrelated types
        raise _UnreadableError(str(error)) from None
    if not isinstance(quantity, ureg.Quantity) or quantity.units == ureg.dimensionless:
        value = float(getattr(quantity, "magnitude", quantity))
        if unit != "1" and value != 0 and value == value:
            raise _NoUnitError
        return value
    import pint  # imported by registry()

    try:
        return float(quantity.to(_units(ureg, unit)).magnitude)
    except pint.DimensionalityError:
        raise _OtherDimensionError(f"{quantity.units:~}") from None


@lru_cache(maxsize=256)
def _units(ureg: pint.UnitRegistry, unit: str) -> pint.Unit:
    """The pint unit of a unit text as the model or a table states it (``"1"``: none)."""
    return ureg.parse_units(_normalise(unit) if unit != "1" else "dimensionless")


DISPLAY_UNITS: dict[str, str] = {"rad": "arcmin", "rad/s": "deg/h", "m/s**2": "ug",
                                 "m/s": "m/s", "m": "m", "1": "1"}
"""Unit each SI unit is shown in by tables and plots meant for people (JSON stays SI)."""


def display_scale(unit: str) -> tuple[float, str]:
    """(factor, display unit) turning a value in the SI ``unit`` into its display unit.

    ``value_si * factor`` is the value in the display unit of :data:`DISPLAY_UNITS`;
    units not listed are shown as they are (factor 1).
    """
    shown = DISPLAY_UNITS.get(unit, unit)
    if shown == unit:
        return 1.0, unit
    return 1.0 / parse_quantity(f"1 {shown}", unit), shown


def format_quantity(value_si: float, unit: str, display_unit: str, digits: int = 4) -> str:
    """Format an SI value in an engineering unit, e.g. ``4.848e-8 rad/s -> '0.01 deg/h'``."""
    ureg = registry()
    value = ureg.Quantity(value_si, _units(ureg, unit)).to(_units(ureg, display_unit)).magnitude
    return f"{value:.{digits}g} {display_unit}"
