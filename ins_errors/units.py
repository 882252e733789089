"""Engineering units at the edges (CLI, scenario and spec files, reports), via pint.

Inside the library everything is SI with radians. This module converts user text such
as ``"0.01 deg/h"``, ``"10 ug"``, ``"20 arcsec"``, ``"5 arcmin"``, ``"100 ppm"``,
``"0.1 m/s"`` or ``"1e-4 g"`` to SI numbers, checking that the dimension matches what
the quantity needs (an angle given in m/s is an error, not a silent number) and that
the power of the angle matches (pint counts radians as dimensionless, so ``deg**2``
would otherwise convert to ``rad``). A quantity is one number followed by one unit
expression: ``"45 deg 30 arcmin"`` (which pint reads as a product) is refused with a
suggestion (``'45.5 deg'``), never added up silently.

``g`` is standard gravity, 9.80665 m/s² (pint's ``g_0``, also written ``g0``); ``ug`` is
a micro-g; ``gal`` (like ``Gal``) is the galileo, 1 cm/s², never pint's US gallon. An
angle may be written with the signs ``°``, ``′`` and ``″``, and a minute or second of arc
with the keyboard's ``'`` and ``"`` (or ``''``) right after its number: ``5'``, ``20"``.
A message names a unit as the user writes it (``mg``, not the registry's ``mg_n``).
"""

from __future__ import annotations

import contextlib
import math
import os
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

    ureg = _cached_registry()
    if ureg is None:   # no cache folder to be had: parsed afresh in every process
        ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    # 'g' means standard gravity in INS work (pint's 'g' is the gram).
    ureg.define(f"gee = {STANDARD_GRAVITY} * meter / second ** 2 = g_n")
    ureg.define("micro_gee = 1e-6 * gee = ug = µg")
    ureg.define("milli_gee = 1e-3 * gee = mg_n")
    ureg.define("parts_per_million_ins = 1e-6 = ppm_ins")
    return ureg


def _cached_registry() -> pint.UnitRegistry | None:
    """pint's registry with its parsed definition files kept in the cache (keyed by their
    contents and pint's version: 0.33 -> 0.02 s CPU per process once they are there);
    None where the cache cannot be used.

    A set is made whole in a scratch folder of the store and renamed into place
    (:func:`_made_set`), so a process reading finds a complete set or none: several
    processes started together on an empty cache each parse and write their own, the
    first renamed in place is kept. A set found damaged (a file cut short, which pint
    cannot read) is said in one line and deleted, and the files are parsed and kept
    again."""
    from ins_errors.numeric.cache import report_damaged

    try:
        store = units_cache_directory()
        folder = installation_folder(store)
    except OSError:
        return None
    if (folder / INSTALLATION_FILE).is_file():
        try:
            return _read_set(folder)
        except Exception:  # a file pint cannot read, or the set removed meanwhile
            if (folder / INSTALLATION_FILE).is_file():
                report_damaged(folder, "parsing pint's unit definitions again")
                _discard(folder)
    try:
        return _made_set(store, folder)
    except Exception:  # an unwritable store, a full disk: parsed without the cache
        return None


def _read_set(folder: Path) -> pint.UnitRegistry:
    """pint's registry read from the complete set ``folder`` (pint writes nothing to it:
    the set's name keys every version pint's file names hold)."""
    import pint

    return pint.UnitRegistry(autoconvert_offset_to_baseunit=True, cache_folder=folder)


def _made_set(store: Path, folder: Path) -> pint.UnitRegistry:
    """pint's registry parsed afresh, its parsed files kept as the set ``folder``.

    The files are written into a scratch folder of ``store`` (locked while in use, as a
    compile's: ``ins-errors cache clear`` and :func:`installation_folder` leave it alone
    meanwhile), the installation's note last, and the folder is then renamed to
    ``folder`` in one step. Where another process has placed its set first, that one is
    kept and this one dropped (the same files).

    Raises
    ------
    OSError
        If the store cannot be written.
    """
    import pint

    from ins_errors.numeric.cache import SCRATCH_LOCK, scratch_folder
    from ins_errors.output import open_modes

    store.mkdir(parents=True, exist_ok=True)
    with scratch_folder(store) as scratch:
        ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True, cache_folder=scratch)
        (scratch / INSTALLATION_FILE).write_text(_installation_note(), encoding="utf-8")
        (scratch / SCRATCH_LOCK).unlink()
        os.chmod(scratch, open_modes()[1])  # readable by the users of a shared cache
        with contextlib.suppress(OSError):  # placed meanwhile by another process: kept
            os.rename(scratch, folder)
    return ureg


def _discard(folder: Path) -> None:
    """Delete the set ``folder``: renamed aside in one step first (a process reading it
    meanwhile finds it whole or gone), then removed."""
    import shutil
    import tempfile

    try:
        aside = Path(tempfile.mkdtemp(prefix="tmp", dir=folder.parent))
    except OSError:
        return
    with contextlib.suppress(OSError):  # discarded meanwhile by another process
        os.rename(folder, aside / folder.name)
    shutil.rmtree(aside, ignore_errors=True)


def units_cache_directory() -> Path:
    """The store of pint's parsed unit definitions (``$INS_ERRORS_CACHE/units`` or the
    user cache folder next to the compiled loops), one subfolder per pint installation
    (:func:`installation_folder`)."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("units")


INSTALLATION_FILE = "installation.txt"
"""The file of an installation's subfolder that names the pint folder it was made from
(first line) and the machine (second line); written last, so a set holding it is whole."""


def _pint_location() -> str:
    """The folder of the pint package this process imports (resolved)."""
    import pint

    return str(Path(pint.__file__).resolve().parent)


def _installation_note() -> str:
    """The text of :data:`INSTALLATION_FILE` for this process's pint."""
    import platform

    return f"{_pint_location()}\n{platform.node()}\n"


def installation_folder(store: Path) -> Path:
    """This pint installation's subfolder of the units store (may not exist yet).

    pint finds a parsed file in its cache by the file's contents, but the parsed file
    names the definition files it includes by the folder it was first read from. Every
    virtual environment has its own copy of pint, so a set parsed by another checkout's
    environment is found by the contents and then read from that environment's folder;
    once the environment is deleted, every registry fails to load (and is parsed
    afresh, twice the time of no cache at all). Each installation therefore keeps its
    own set, in a subfolder named by the hash of pint's folder and of the versions
    pint's file names hold (pint's, Python's, the system's: an upgrade in place is a new
    set, never files added to a set other processes read). When the set is missing,
    the sets whose installation no longer exists on this machine, those of this
    installation's earlier versions, the scratch folders of interrupted writes and the
    loose files of the earlier one-set layout are deleted (a set made on another machine
    sharing the cache folder is kept: its folder need not exist here).
    """
    import hashlib
    import platform
    import shutil

    import pint

    from ins_errors.numeric.cache import SCRATCH_PREFIX, scratch_in_use

    location = _pint_location()
    key = "\n".join([location, pint.__version__, platform.python_implementation(),
                     platform.python_version(), platform.system()])
    folder = store / hashlib.sha256(key.encode()).hexdigest()[:16]
    if (folder / INSTALLATION_FILE).is_file() or not store.is_dir():
        return folder
    host = platform.node()
    try:
        for entry in store.iterdir():
            if entry == folder:
                continue
            if entry.is_dir() and not entry.is_symlink():
                if entry.name.startswith(SCRATCH_PREFIX):
                    if not scratch_in_use(entry):
                        shutil.rmtree(entry, ignore_errors=True)
                    continue
                try:
                    made_at, _, made_on = (entry / INSTALLATION_FILE).read_text(
                        "utf-8").partition("\n")
                except (OSError, UnicodeDecodeError):
                    continue   # no note (an earlier version's set being made): kept
                if made_on.strip() == host and (made_at == location
                                                or not Path(made_at).is_dir()):
                    shutil.rmtree(entry, ignore_errors=True)
            else:
                entry.unlink(missing_ok=True)
    except OSError:
        pass  # a read-only store: what it holds is read as it is
    return folder


_ALIASES = {"deg/hr": "deg/h", "°/h": "deg/h"}

_ANGLE_MARKS = (("°", "deg"), ("″", "arcsec"), ("′", "arcmin"))
"""The degree, second and minute signs and the unit each stands for."""

_ASCII_MARKS = re.compile(r"(?<=[\d.])(?P<mark>''|'|\")")
"""An ASCII minute (``'``) or second (``"``, also ``''``) sign right after a number: the
keyboard's stand-ins for ′ and ″ (``5'``, ``20"``)."""

_ASCII_MARK_UNITS = {"'": "arcmin", "''": "arcsec", '"': "arcsec"}


def _square_roots(text: str) -> str:
    """``sqrt(X)`` and ``√X`` (X a name or a bracket) written as ``(X)**0.5``: pint has
    no square-root function, and a random walk is quoted per √h or √Hz."""
    while (start := text.find("sqrt(")) >= 0 or (start := text.find("√")) >= 0:
        opening = start + (4 if text.startswith("sqrt(", start) else 1)
        if text.startswith("(", opening):
            depth, end = 0, opening
            while end < len(text):
                depth += {"(": 1, ")": -1}.get(text[end], 0)
                end += 1
                if depth == 0:
                    break
            else:
                return text  # an unclosed bracket: pint words the error
            inner = text[opening + 1:end - 1]
        else:
            name = re.match(r"\s*([^\W\d]\w*)", text[opening:])
            if name is None:
                return text  # '√' before nothing to take the root of: pint's error
            inner, end = name.group(1), opening + name.end()
        text = f"{text[:start]}({inner})**0.5{text[end:]}"
    return text


_GALILEO = re.compile(r"(?<![A-Za-z_])(?P<prefix>[muµμ]?)gal(?![A-Za-z_0-9])")
"""``gal`` (also ``mgal``, ``ugal``, ``µgal``): the galileo, 1 cm/s², as gravimetry writes
it in lower case; pint's ``gal`` is the US gallon, a volume no value here is."""


_DATASHEET_ROOT = re.compile(r"(?<![A-Za-z_])rt-?(?=\s*[A-Za-z(])")
"""``rt`` (also ``rt-``) before a unit: a datasheet's square root (``deg/rt-hr``,
``ug/rtHz``); pint would read ``rt`` as the rontometric ton."""

_GRAVITY_CAPITAL = re.compile(r"(?<![A-Za-z_])(?P<prefix>[muµμ]?)G(?![A-Za-z_0-9])")
"""``G``, ``mG``, ``uG``, ``µG``: what accelerometer datasheets often write for g, mg, µg;
pint's ``G`` is the gauss, a magnetic flux density no value here is."""

_GRAVITY_PREFIXES = {"": "gee", "m": "milli_gee", "u": "micro_gee", "µ": "micro_gee",
                     "μ": "micro_gee"}


def _normalise(text: str) -> str:
    """The text pint is given for a user's (or a model's) unit text."""
    text = text.strip()
    text = _ASCII_MARKS.sub(lambda m: f" {_ASCII_MARK_UNITS[m['mark']]} ", text).strip()
    for old, new in _ALIASES.items():
        text = text.replace(old, new)
    for sign, name in _ANGLE_MARKS:   # '1°30′' is two parts, as '1 deg 30 arcmin' is
        text = re.sub(f"{sign}(?=[\\d.])", f" {name} ", text).replace(sign, f" {name}")
    text = _DATASHEET_ROOT.sub("√", text)
    text = _square_roots(text)
    text = _GRAVITY_CAPITAL.sub(lambda m: _GRAVITY_PREFIXES[m["prefix"]], text)
    # a bare 'g' (or 'mg') means gravity, not grams; 'ppm' a plain ratio; 'gal' the galileo
    text = re.sub(r"(?<![A-Za-z_])g(?![A-Za-z_0-9])", "gee", text)
    text = re.sub(r"(?<![A-Za-z_])mg(?![A-Za-z_0-9])", "milli_gee", text)
    text = re.sub(r"(?<![A-Za-z_])ppm(?![A-Za-z_0-9])", "ppm_ins", text)
    text = _GALILEO.sub(lambda m: f"{m['prefix']}Gal", text)
    return text.strip()


UNIT_FAMILIES: dict[str, str] = {
    "rad": "an angle, e.g. '{v} deg', '{v} arcmin', '{v} arcsec' or '{v} rad'",
    "rad/s": "an angular rate, e.g. '{v} deg/h' or '{v} rad/s'",
    "m/s**2": "an acceleration, e.g. '{v} ug', '{v} mg', '{v} g' or '{v} m/s^2'",
    "m/s": "a velocity, e.g. '{v} m/s' or '{v} km/h'",
    "m": "a length, e.g. '{v} m' or '{v} km'",
    "s": "a time, e.g. '{v} s', '{v} min' or '{v} h'",
    "1": "a plain number or ratio, e.g. '{v}', '{v} ppm' or '{v} %'",
    "(rad/s)*s**0.5": "an angle random walk or rate noise density, e.g. "
                      "'{v} deg/sqrt(h)' or '{v} (deg/h)/sqrt(Hz)'",
    "(m/s**2)*s**0.5": "a velocity random walk or acceleration noise density, e.g. "
                       "'{v} ug/sqrt(Hz)' or '{v} m/s/sqrt(h)'",
}
"""The family of units expected by SI unit, with examples (what a bare number lacks);
a noise density (a white source's magnitude) as a datasheet quotes it."""

_DENSITY = re.compile(r"^\((?P<unit>.+)\)\*s\*\*0\.5$")
"""A noise density's SI unit, ``(unit)*s**0.5``: suggested per √Hz where
:data:`UNIT_FAMILIES` has no datasheet form of it."""


_PLAIN_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def _needs_unit(text: object, unit: str, what: str, value: float) -> UnitError:
    """The one line for a number without the unit ``unit`` needs; the examples show the
    number as it was written when it is a plain number, else its value."""
    shown = str(text).strip()
    number = shown if _PLAIN_NUMBER.fullmatch(shown) else f"{value:g}"
    return UnitError(f"{what}: {text!r} has no unit; give {_example(unit, number)}")


_INTERNAL_NAMES = ((re.compile(r"(?<!\w)([A-Za-zµμ]?)g_n(?!\w)"), r"\1g"),
                   (re.compile(r"(?<!\w)g_0(?!\w)"), "g0"),
                   (re.compile(r"(?<!\w)milli_gee(?!\w)"), "mg"),
                   (re.compile(r"(?<!\w)gee(?!\w)"), "g"),
                   (re.compile(r"(?<!\w)ppm_ins(?!\w)"), "ppm"),
                   (re.compile(r"(?<!\w)gal(?!\w)"), "gallon"))
"""The names this module gives pint (``gee``, ``ppm_ins``, ...) and pint's symbols of them
(``mg_n``, ``µg_n``), each with the name a user writes; pint's symbol of the gallon,
``gal``, written out (``gal`` is read as the galileo here)."""

_GLOSSES = {"g": "standard gravity", "g0": "standard gravity", "mg": "milli-g",
            "ug": "micro-g", "µg": "micro-g", "μg": "micro-g", "Gal": "galileo = 1 cm/s²",
            "mGal": "milli-galileo", "µGal": "micro-galileo"}
"""What the units a reader may take for another (mg, a milligram?) stand for here."""

_MASS_GLOSSES = {"g": "gram", "mg": "milligram", "µg": "microgram", "μg": "microgram"}
"""The same symbols where pint has read a mass (``100mug``: ``mu`` + ``g``, a microgram):
there they are grams, not the g of an acceleration."""


def _user_words(text: str) -> str:
    """``text`` (pint's words) with this module's internal unit names as a user writes
    them (``mg_n`` -> ``mg``, ``ppm_ins`` -> ``ppm``)."""
    for pattern, name in _INTERNAL_NAMES:
        text = pattern.sub(name, text)
    return text


def _shown_units(quantity: pint.Quantity, *notes: str) -> str:
    """A quantity's units in the names a user writes, the easily misread ones explained,
    and ``notes`` after them: ``mg (milli-g)``, ``deg ** 2``, ``mg / h (mg: milli-g)``,
    ``mg (milli-g, an acceleration)``."""
    shown = _user_words(f"{quantity.units:~}")
    glosses, hint = _GLOSSES, []
    if quantity.dimensionality.get("[mass]"):
        glosses = _MASS_GLOSSES
        if any(word in glosses for word in re.findall(r"[\wµμ]+", shown)):
            hint = ["the g of an acceleration is written g, mg or ug"]
    if shown in glosses:
        return f"{shown} ({'; '.join([', '.join([glosses[shown], *notes]), *hint])})"
    named = [f"{word}: {glosses[word]}"
             for word in dict.fromkeys(re.findall(r"[\wµμ]+", shown)) if word in glosses]
    parts = [*named, *notes, *hint]
    return f"{shown} ({'; '.join(parts)})" if parts else shown


_KINDS: dict[tuple[frozenset, float], str] = {
    (frozenset(), 1): "an angle",
    (frozenset(), 0): "a plain number or ratio",
    (frozenset(), 2): "an angle squared",
    (frozenset({("[time]", -1)}), 1): "an angular rate",
    (frozenset({("[time]", -1)}), 0): "a frequency",
    (frozenset({("[time]", -2)}), 1): "an angular acceleration",
    (frozenset({("[time]", -0.5)}), 1): "an angle per √time",
    (frozenset({("[length]", 1), ("[time]", -2)}), 0): "an acceleration",
    (frozenset({("[length]", 1), ("[time]", -1.5)}), 0): "an acceleration per √Hz",
    (frozenset({("[length]", 1), ("[time]", -1)}), 0): "a velocity",
    (frozenset({("[length]", 1)}), 0): "a length",
    (frozenset({("[time]", 1)}), 0): "a time",
    (frozenset({("[length]", 2)}), 0): "an area",
    (frozenset({("[length]", 3)}), 0): "a volume",
    (frozenset({("[mass]", 1)}), 0): "a mass",
    (frozenset({("[temperature]", 1)}), 0): "a temperature",
}
"""What a quantity is, by its dimension and the power of the angle in it."""


def _kind(quantity: pint.Quantity) -> str:
    """What a quantity is in words (``an acceleration``), from its dimension and angle
    power; else its dimension as pint writes it."""
    dimension = frozenset((name, float(power))
                          for name, power in quantity.dimensionality.items() if power)
    kind = _KINDS.get((dimension, _angle_power(quantity)))
    return kind if kind is not None else f"a quantity of dimension {quantity.dimensionality}"


def _other_dimension(text: str, unit: str, what: str, shown: str) -> UnitError:
    """The one line for a quantity (its units ``shown``, what it is said) that does not
    convert to ``unit``."""
    ureg = registry()
    family = UNIT_FAMILIES.get(unit)
    wanted = family.split(", e.g.")[0] if family else _kind(1 * _units(ureg, unit))
    lead = _TOKEN.match(_normalise(text).lstrip("+-"))
    magnitude = lead.group().strip() if lead and lead.lastgroup == "number" else "1"
    target = f"{unit} ({wanted})" if unit != "1" else wanted
    return UnitError(f"{what}: {text!r} has units of {shown}, which do not convert to "
                     f"{target}; give {_example(unit, magnitude)}")


_TOKEN = re.compile(r"""\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
                       |(?P<name>[^\W\d]\w*)|(?P<op>\*\*|[-+*/^()])|(?P<other>\S))""",
                    re.VERBOSE)
"""One token of a quantity's text: a number, a name (a unit), an operator or else."""

_NOT_FINITE = frozenset({"nan", "inf", "infinity"})
"""Names pint reads as a number (refused later as not finite)."""


def _second_number(text: str) -> tuple[int, str] | None:
    """Where ``text`` (normalised) breaks the rule *one number, then one unit
    expression*: (position, number) of a number after the leading one, else None.

    pint multiplies things written side by side, so ``"45 deg 30 arcmin"`` would be
    45·30 deg·arcmin, which converts to radians (an angle is dimensionless to pint). A
    number is allowed after the leading one only as an exponent (``h**0.5``,
    ``s^-1``, ``Hz**(1/2)``), as the unit one (``1/s``; ``"0 1"`` for a plain ratio),
    which multiplies by nothing, or as the denominator of a leading fraction
    (``1/3600 Hz``). A text with no number at all
    (``"deg"``, ``""``) or a unit before its number is refused too (position -1, '').
    """
    tokens = [(m.lastgroup, m.group(m.lastgroup), m.start(m.lastgroup))
              for m in _TOKEN.finditer(text)]
    i = 1 if tokens and tokens[0][1] in ("+", "-") else 0
    if i < len(tokens) and (tokens[i][0] == "number"
                            or tokens[i][1].lower() in _NOT_FINITE):
        i += 1
        if [kind for kind, *_ in tokens[i:i + 2]] == ["op", "number"] and tokens[i][1] == "/":
            i += 2   # a leading fraction, 1/3600
    else:
        return -1, ""   # a unit before the number, no number at all, or nothing
    exponent_brackets: list[bool] = []   # per open bracket: whether it is an exponent's
    after_power = False
    for k in range(i, len(tokens)):
        kind, value, start = tokens[k]
        in_exponent = after_power or any(exponent_brackets)
        if kind == "op" and value in ("**", "^"):
            after_power = True
            continue
        if kind == "op" and value in ("+", "-") and after_power:
            continue   # the sign of an exponent
        if kind == "op" and value == "(":
            exponent_brackets.append(after_power)
        elif kind == "op" and value == ")" and exponent_brackets:
            exponent_brackets.pop()
        elif kind == "number" and not in_exponent:
            following = tokens[k + 1][1] if k + 1 < len(tokens) else ""
            if float(value) != 1 or following not in ("", "/", "*", ")"):
                return start, value   # not the unit one (as '45 deg 1 arcmin')
        after_power = False
    return None


def _angle_power(quantity: pint.Quantity) -> float:
    """The power of radian in a quantity's units reduced to base units (``deg/h`` -> 1,
    ``deg*arcmin`` -> 2, ``Hz`` -> 0): pint counts an angle as dimensionless, so the
    dimension check alone cannot tell an angle from an angle squared or a plain ratio."""
    return float(dict(quantity.to_root_units().unit_items()).get("radian", 0))


def _power_words(power: float) -> str:
    return {0: "no angle", 1: "an angle", 2: "an angle squared"}.get(
        power, f"an angle to the power {power:g}")


def typed_value(number: str, unit: str) -> str:
    """``number`` in the SI ``unit`` (SymPy's spelling, ``1/s**2``) as a person types it
    after ``-p NAME=`` or in a TOML file: ``'2e-3/s^2'``, ``'9.8 m/s^2'``, ``'0.5'`` for
    ``"1"``, ``'0.5 rad'`` (the number keeps its meaning: not turned into degrees)."""
    if unit == "1":
        return number
    shown = unit.replace("**", "^")
    return f"{number}{shown[1:]}" if shown.startswith("1/") else f"{number} {shown}"


def _example(unit: str, number: str) -> str:
    """How :data:`UNIT_FAMILIES` suggests giving a value in ``unit`` (``number``: the
    magnitude to show)."""
    density = _DENSITY.match(unit)
    if unit in UNIT_FAMILIES:
        family = UNIT_FAMILIES[unit]
    elif density:  # a ratio (a scale factor's noise) in ppm, as its bias is quoted
        per = "ppm" if density["unit"] == "1" else f"({density['unit']})"
        family = f"a noise density, e.g. '{{v}} {per}/sqrt(Hz)'"
    else:
        return (f"a quantity in units of {unit.replace('**', '^')}, e.g. "
                f"'{typed_value(number, unit)}'")
    return family.format(v=number)


def _sum_of_parts(text: str, unit: str) -> str | None:
    """``"45.5 deg"`` for ``"45 deg 30 arcmin"``: the parts written side by side added up,
    in the first part's unit, as a suggestion only (None when a part is not a magnitude
    with a unit of the same kind; a leading sign applies to the whole, as in -45° 30′)."""
    ureg = registry()
    normal = _normalise(text)
    sign = -1.0 if normal.startswith("-") else 1.0
    normal = normal.lstrip("+-")
    cuts = [0]
    while (found := _second_number(normal[cuts[-1]:])) is not None and found[0] > 0:
        cuts.append(cuts[-1] + found[0])
    parts = [normal[a:b].strip() for a, b in
             zip(cuts, [*cuts[1:], len(normal)], strict=True)]
    first = _TOKEN.match(parts[0])
    if len(parts) < 2 or first is None or first.lastgroup != "number":
        return None
    shown = parts[0][first.end():].strip()
    try:
        target = _units(ureg, unit)
        total = 0.0
        for part in parts:
            quantity = ureg.parse_expression(part)
            if (not isinstance(quantity, ureg.Quantity) or quantity.magnitude <= 0
                    or _angle_power(quantity) != _angle_power(1 * target)):
                return None
            total += float(quantity.to(ureg.parse_units(shown)).magnitude)
    except Exception:  # pint raises several unrelated types
        return None
    return f"{sign * total:.10g} {shown}"


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
        ``"0.01 deg/h"``, ``"10ug"``, ``"5 arcmin"``, ``"0.05 deg/sqrt(h)"``: one number
        followed by one unit expression (numbers after the first only in exponents,
        ``h**0.5``, or as the unit one, ``1/s``; ``"1/3600 Hz"`` is one number). Text must
        carry its unit when ``unit`` has one: ``"0.01"`` for a gyro drift is refused (it
        would silently mean 0.01 rad/s); zero and plain ratios (``unit == "1"``) need
        none. Two quantities side by side (``"45 deg 30 arcmin"``, which pint would
        multiply) and a unit with another power of the angle than ``unit`` has
        (``"45 deg**2"`` for ``rad``, ``"10 Hz"`` for ``rad/s``: pint counts radians as
        dimensionless, so these would convert) are refused.
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
        If the text does not parse, is not one number and one unit, is not finite,
        lacks a unit, or has another dimension or power of the angle.
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
            raise _needs_unit(text, unit, what, value)
    else:
        try:
            value = _text_value(registry(), str(text), unit)
        except _UnreadableError as problem:
            raise UnitError(f"{what}: cannot read {text!r} as a quantity "
                            f"({_user_words(str(problem))})") from None
        except _NoUnitError as problem:
            raise _needs_unit(str(text).strip(), unit, what, *problem.args) from None
        except _OtherDimensionError as problem:
            raise _other_dimension(str(text), unit, what, *problem.args) from None
        except _SecondNumberError as problem:
            raise _second_number_error(str(text), unit, what, *problem.args) from None
        except _AnglePowerError as problem:
            shown, got, wanted = problem.args
            number = _TOKEN.match(_normalise(str(text)))
            raise UnitError(
                f"{what}: {text!r} has units of {shown}, {_power_words(got)}, where {unit} "
                f"needs {_power_words(wanted)}; give "
                f"{_example(unit, number.group().strip() if number else '1')}") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise UnitError(f"{what}: {text!r} is not a finite number")
    return value


class _UnreadableError(Exception):
    """pint cannot parse the text (the message is pint's)."""


class _NoUnitError(Exception):
    """A plain number where the target unit needs one (args: its value)."""


class _OtherDimensionError(Exception):
    """A quantity whose units do not convert to the target unit (args: its units as a
    user writes them and what it is; see :func:`_shown_units`, :func:`_kind`)."""


class _SecondNumberError(Exception):
    """Text that is not one number and one unit (args: position, number; see
    :func:`_second_number`)."""


class _AnglePowerError(Exception):
    """A quantity whose angle power differs from the target unit's (args: its units,
    its power, the target's power)."""


def _second_number_error(text: str, unit: str, what: str, position: int,
                         number: str) -> UnitError:
    """The one line for a text that is not one number followed by one unit."""
    lead = _TOKEN.match(_normalise(text).lstrip("+-"))
    magnitude = lead.group().strip() if lead and lead.lastgroup == "number" else "1"
    examples = _example(unit, magnitude).split("e.g. ", 1)[-1]
    if position < 0:
        return UnitError(f"{what}: {text!r} does not start with a number; give one number "
                         f"followed by one unit, e.g. {examples}")
    total = _sum_of_parts(text, unit)
    return UnitError(f"{what}: {text!r} has a second number ({number}) after the first, "
                     "and numbers side by side would be multiplied; give one number "
                     f"followed by one unit, e.g. {f'{total!r}' if total else examples}")


@lru_cache(maxsize=4096)
def _text_value(ureg: pint.UnitRegistry, text: str, unit: str) -> float:
    """``text`` in the SI ``unit`` through ``ureg`` (raises the problems above).

    Kept per process (and registry): scenario, spec and command-line values repeat the
    same few texts, and pint's parser costs ~0.3 ms CPU per call. A conversion depends
    on nothing but the registry, the text and the unit, which form the key; failures
    are not kept (they raise) and are worded by the caller.
    """
    normal = _normalise(text)
    second = _second_number(normal)
    if second is not None and second[0] >= 0:
        raise _SecondNumberError(*second)
    try:
        quantity = ureg.parse_expression(normal)
    except Exception as error:  # pint raises several unrelated types
        raise _UnreadableError(str(error)) from None   # e.g. 'four': pint names it
    if second is not None:   # no leading number, e.g. 'deg'
        raise _SecondNumberError(*second)
    if not isinstance(quantity, ureg.Quantity) or quantity.units == ureg.dimensionless:
        value = float(getattr(quantity, "magnitude", quantity))
        if unit != "1" and value != 0 and value == value:
            raise _NoUnitError(value)
        return value
    import pint  # imported by registry()

    target = _units(ureg, unit)
    try:
        value = float(quantity.to(target).magnitude)
    except pint.DimensionalityError:
        raise _OtherDimensionError(_shown_units(quantity, _kind(quantity))) from None
    if (power := _angle_power(quantity)) != (wanted := _angle_power(1 * target)):
        raise _AnglePowerError(_shown_units(quantity), power, wanted)
    return value


@lru_cache(maxsize=256)
def _units(ureg: pint.UnitRegistry, unit: str) -> pint.Unit:
    """The pint unit of a unit text as the model or a table states it (``"1"``: none)."""
    return ureg.parse_units(_normalise(unit) if unit != "1" else "dimensionless")


def same_dimension(unit: str, other: str) -> bool:
    """True when two unit texts (as a model states them) have the same dimension; False
    also when either is not a unit pint reads."""
    ureg = registry()
    try:
        return _units(ureg, unit).dimensionality == _units(ureg, other).dimensionality
    except Exception:  # pint raises several types for text it cannot read
        return False


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


_ANGLE_STEPS = ("arcsec", "arcmin", "deg")
"""Angle units from small to large, each 60 of the one before."""


def readable_angle_unit(value_si: float, display_unit: str, down: bool = False) -> str:
    """The angle unit a value in rad reads best in, starting from ``display_unit``.

    Up to arcmin or deg while the value is at least 60 of the unit; with ``down``, also
    down to arcmin or arcsec while it is below 0.1 of the unit (a limit of 1 arcmin reads
    ``1 arcmin``, not ``0.01667 deg``; one of 0.1 deg stays ``0.1 deg``).
    A unit that is not arcsec, arcmin or deg is returned as it is.
    """
    if display_unit not in _ANGLE_STEPS or not math.isfinite(value_si) or value_si == 0:
        return display_unit
    step = _ANGLE_STEPS.index(display_unit)
    size = abs(value_si) * 180 / math.pi * 3600 / 60**step  # in the display unit
    while step < len(_ANGLE_STEPS) - 1 and size >= 60:
        step, size = step + 1, size / 60
    while down and step > 0 and size < 0.1:
        step, size = step - 1, size * 60
    return _ANGLE_STEPS[step]


def format_readable(value_si: float, unit: str, display_unit: str, digits: int = 4) -> str:
    """:func:`format_quantity` of one value for a label: an angle shown in arcsec or arcmin
    moves up to arcmin or deg when it is at least 60 of its display unit (an initial
    heading error of 30° reads ``30 deg``, not ``1800 arcmin``); anything else as
    :func:`format_quantity` gives it.
    """
    return format_quantity(value_si, unit, readable_angle_unit(value_si, display_unit),
                           digits)


def nice_below(value: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above ``value`` (> 0): a round
    figure to suggest (a step of 50 s for a stability bound of 133 s)."""
    power = 10.0 ** math.floor(math.log10(value))
    return max(m for m in (1.0, 2.0, 5.0) if m * power <= value * (1 + 1e-12)) * power


def percent_text(ratio: float, digits: int = 2) -> str:
    """A ratio as a percentage for a message: ``digits`` significant digits below 100 %
    and whole per cent from there (1.44: ``"144%"``, 0.9996: ``"100%"``, 12: ``"1200%"``,
    0.072: ``"7.2%"``, 0.0012: ``"0.12%"``), never in exponent notation down to 1e-4 %
    (below that, ``"2.8e-06%"``).

    Parameters
    ----------
    ratio : float
        The ratio (1 is 100 %).
    digits : int
        Significant digits below 100 %.
    """
    value = 100.0 * float(ratio)
    if not math.isfinite(value):
        return f"{value}%"
    if value == 0.0:
        return "0%"
    if abs(float(f"{value:.{digits}g}")) >= 100.0:
        return f"{value:.0f}%"
    if abs(value) < 1e-4:
        return f"{value:.{digits}g}%"
    text = repr(float(f"{value:.{digits}g}"))
    return f"{text.removesuffix('.0')}%"


def format_duration(seconds: float) -> str:
    """``"1 h"``, ``"40 min"``, ``"2 h 35 min"``, ``"90 s"``, ``"-1 min"``.

    Rounded to the microsecond first, so a time that went through hours and back
    (7800.000000000001 s) still reads ``"2 h 10 min"``.
    """
    seconds = round(float(seconds), 6)
    if seconds < 0:
        return "-" + format_duration(-seconds)
    if seconds % 60:
        return f"{seconds:g} s"
    hours, minutes = divmod(round(seconds / 60), 60)
    if not minutes:
        return f"{hours} h"
    return f"{hours} h {minutes} min" if hours else f"{minutes} min"


VALIDITY_RATIO_CEILING: float = 10  # an int: the published schema writes 10
"""A validity threshold (the linear/direct ratio that warns) must be below this ratio,
1000 % of the error: a linear run off by ten times the error it estimates tells
nothing, so a larger threshold could only hide that."""


def ratio_outside(value: float, example: str = "0.05 or 5%") -> str:
    """Why a validity threshold ``value`` is refused, naming the accepted range and
    ``example`` (how the threshold is written where it was given)."""
    shown = f"{value:g} ({100 * value:g} %)" if math.isfinite(value) else f"{value:g}"
    return (f"the ratio {shown} is outside the accepted range, above 0 and below "
            f"{VALIDITY_RATIO_CEILING:g} ({100 * VALIDITY_RATIO_CEILING:g} % of the error; "
            f"a bare number is a ratio, e.g. {example})")
