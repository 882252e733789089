"""True motion described in words and units (CLI options, scenario files) -> a Profile.

One place turns ``{"kind": "great-circle", "latitude": "50 deg", "speed": "250 m/s"}``
into a :class:`~ins_errors.numeric.trajectories.Profile`, so the command line and the
scenario files accept exactly the same motions with the same defaults.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.numeric import trajectories as tr
from ins_errors.units import parse_quantity

MOTION_KINDS = ("static", "great-circle", "manoeuvre", "file")
"""Kinds of motion a description may name."""

MOTION_ALIASES = {"great_circle": "great-circle"}
"""Other spellings of a motion kind, read as the kind everywhere one is named (scenario
and spec files, ``--motion``; spec files were first written with ``great_circle``). A
near miss (``maneuver``, the US spelling) is refused with the kind it is close to."""


def motion_kind(text: str, known: Sequence[str] = MOTION_KINDS,
                what: str = "motion kind") -> str:
    """The kind of motion ``text`` names: one of ``known``, or an alias of one
    (:data:`MOTION_ALIASES`).

    Parameters
    ----------
    text : str
        The kind as written.
    known : sequence of str
        The kinds the caller takes (default :data:`MOTION_KINDS`).
    what : str
        What the refusal calls it.

    Raises
    ------
    UnknownNameError
        One line with the closest kinds (``maneuver``: did you mean 'manoeuvre'?).
    """
    kind = MOTION_ALIASES.get(text, text)
    if kind not in known:
        raise unknown_name(what, text, known)
    return kind

DEFAULTS: dict[str, str] = {
    "kind": "static",
    "latitude": "50 deg",
    "longitude": "30 deg",
    "heading": "0 deg",
    "speed": "250 m/s",
    "height": "0 m",
}
"""Defaults of every motion description (the CLI shows the same)."""

MOVING_HEADING = "90 deg"
"""Default track angle of a moving base: due east. A great circle started due east from
latitude φ never goes beyond ±φ, so a day's flight stays clear of the poles (due north at
250 m/s from 50° reaches the pole after about 5 h)."""

_KEYS = {*DEFAULTS, "file", "legs"}

APPLIES_TO: dict[str, tuple[str, ...]] = {
    "speed": ("great-circle", "manoeuvre"),
    "legs": ("manoeuvre",),
    "file": ("file",),
}
"""The motion settings that only some kinds use: a description of another kind that
states one is refused (it was silently dropped). The heading stays meaningful for every
kind: it is the trihedron's track angle at the start, on which the errors of a model with
a heading output depend even at rest or along a motion file (a strapdown INS along a motion
file heads along the file's course: there a heading given is refused)."""

_WHY_NOT = {"static": "the base is static", "file": "the file gives the motion",
            "great-circle": "the kind is great-circle", "manoeuvre": "the kind is manoeuvre"}


STANDARD_MANOEUVRE = ("standard manoeuvre (every hour a 90° left turn, a 20 % speed-up with "
                      "a 2-km climb, then two 45° right turns back, the second slowing down "
                      "and descending)")
"""How the flight of :func:`default_legs` is described."""


def default_legs(speed: float, height: float, hours: int = 24) -> list[tr.Leg]:
    """The standard manoeuvre: a turn, a speed change with a climb, a turn back and a
    descent, repeated every hour.

    Parameters
    ----------
    speed, height : float
        Start speed (m/s) and height (m); every hour ends at them again, on the
        start's course.
    hours : int
        Hours of legs. :func:`motion_profile` builds 24 and flies them again and again
        (``manoeuvre_profile(..., repeat=True)``), so the manoeuvre lasts as long as
        any run; the legs of a longer list are the same numbers.

    Returns
    -------
    list of Leg
        Five legs an hour.
    """
    legs = []
    for _ in range(hours):
        legs += [tr.Leg(600.0, speed, np.radians(90.0), height),
                 tr.Leg(600.0, speed * 1.2, 0.0, height + 2000.0),
                 tr.Leg(1200.0, speed * 1.2, np.radians(-45.0), height + 2000.0),
                 tr.Leg(600.0, speed, np.radians(-45.0), height),
                 tr.Leg(600.0, speed, 0.0, height)]
    return legs


SAMPLES_NEEDED = 4
"""Rows of samples a motion file needs (a cubic spline through each column)."""

FILE_COLUMNS = ("t", "v_N", "v_E", "h")
"""The columns a motion file may have (``h`` is optional), in SI: s, m/s, m/s, m."""

GAP_FACTOR = 10.0
"""A motion file's sample spacing beyond this many times its median spacing is a gap in
the samples, which the cubic splines bridge with a motion the file does not record: it
is noted on stderr (``ins-errors: note: ...``)."""


def read_motion_file(path: str | Path, latitude: float, longitude: float, heading: float,
                     height: float, *, height_given: bool = False) -> tr.Profile:
    """A sampled motion from a CSV file with a header and columns t, v_N, v_E [, h] (SI).

    The file is UTF-8 (a byte-order mark, as spreadsheet programs write, is skipped);
    ``#`` starts a comment and blank lines are skipped. The columns may come in any
    order; a column of another name (``lat``, ``alt``, ``v_N [m/s]``) is refused, as
    are times that do not increase strictly or start after 0 (a run starts at t = 0).
    A gap in the samples (a spacing above :data:`GAP_FACTOR` times the median) is noted
    on stderr as a warning ``ins-errors: note: ...``.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    latitude, longitude, heading : float
        Start point and the trihedron's initial track angle, rad.
    height : float
        Height, m, of a file without an ``h`` column.
    height_given : bool
        True when the user stated ``height``: refused for a file with an ``h`` column,
        whose heights the flight follows.

    Raises
    ------
    InsErrorsError
        One line naming the file and, for a cell that is not a number or a time out of
        order, its column and line.
    """
    where = f"motion file {str(path)!r}"
    names, table, lines = _read_columns(Path(path))
    _check_names(where, names)
    if len(table["t"]) < SAMPLES_NEEDED:
        raise InsErrorsError(f"{where} has {len(table['t'])} row(s) of "
                             f"samples; a sampled motion needs at least {SAMPLES_NEEDED} (t, "
                             "v_N, v_E: cubic splines run through them)")
    if height_given and "h" in names:
        raise InsErrorsError(f"motion height: {where} has its own column h, which the "
                             "flight follows; leave the height out")
    _check_finite(where, names, table, lines)
    _check_times(where, table["t"], lines)
    if "h" in names:
        beyond = np.flatnonzero(np.abs(table["h"]) > tr.HEIGHT_LIMIT)
        if beyond.size:       # the first such sample, with its line (NaN: sampled_profile)
            k = int(beyond[0])
            tr.check_height(float(table["h"][k]), f"{where}, line {lines[k]}: h")
    h = table["h"] if "h" in names else height
    profile = tr.sampled_profile(table["t"], table["v_N"], table["v_E"], latitude,
                                 longitude, heading, h, source=str(path))
    _note_gaps(where, table["t"])
    return profile


def _check_names(where: str, names: list[str]) -> None:
    """Refuse a header that lacks a column the reader needs, has one it does not read,
    or has one twice (one line)."""
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InsErrorsError(f"{where}: column(s) {', '.join(twice)} appear more than once "
                             "in the header")
    missing = [c for c in ("t", "v_N", "v_E") if c not in names]
    unknown = [n for n in names if n not in FILE_COLUMNS]
    if not missing and not unknown:
        return
    text = (f"{where} lacks column(s) {', '.join(missing)} (has {', '.join(names) or 'none'})"
            if missing else where)
    if not unknown:
        raise InsErrorsError(text)
    for name in unknown:  # a known name with a unit written beside it
        match = re.match(r"(t|v_N|v_E|h)(?:\s*[\[(]|_|\s+)(.+)$", name)
        if match:
            raise InsErrorsError(f"{text}: headers are bare names with the values in SI (s, "
                                 f"m/s, m), {match.group(1)!r}, not {name!r}")
    raise InsErrorsError(
        f"{text}{';' if missing else ':'} column(s) {', '.join(unknown)} are not read: a "
        "motion file has the columns t (s), v_N, v_E (m/s) and optionally h (m), no others "
        "(the start latitude and longitude come from --latitude/--longitude or the "
        "scenario's [motion]; a height column must be named h)")


def _check_finite(where: str, names: list[str], table: Mapping[str, np.ndarray],
                  lines: list[int]) -> None:
    """Refuse a NaN or infinite value (``nan``, ``inf``, ``1e999``) in any column, naming
    the first one in the file: its column, sample and line (one line)."""
    bad = ~np.isfinite(np.column_stack([table[name] for name in names]))
    if bad.any():
        k, j = (int(i) for i in np.argwhere(bad)[0])  # the first row, then column
        raise InsErrorsError(f"{where}: {names[j]} is NaN or infinite in sample {k + 1} of "
                             f"{bad.shape[0]} (line {lines[k]})")


def _check_times(where: str, t: np.ndarray, lines: list[int]) -> None:
    """Refuse times that are not finite, do not increase strictly, or start after 0,
    naming the line of the file."""
    bad = ~np.isfinite(t)
    if bad.any():
        k = int(np.argmax(bad))
        raise InsErrorsError(f"{where}: t is NaN or infinite in sample {k + 1} of {t.size} "
                             f"(line {lines[k]})")
    step = np.diff(t)
    wrong = np.flatnonzero(step <= 0)
    if wrong.size:
        k = int(wrong[0])
        more = (f" (and at {wrong.size - 1} more line(s))" if wrong.size > 1 else "")
        what = (f"t = {t[k]:.10g} s repeats at line {lines[k + 1]} (line {lines[k]} has it)"
                if step[k] == 0 else
                f"t goes back from {t[k]:.10g} s (line {lines[k]}) to {t[k + 1]:.10g} s at "
                f"line {lines[k + 1]}")
        raise InsErrorsError(f"{where}: {what}{more}; the times must increase strictly "
                             "(one sample per time, in time order)")
    if abs(t[0]) > 1e-9:  # before 0 too: the run would start mid-file, in silence
        shift = (f"subtract {t[0]:.10g} s from every time" if t[0] > 0
                 else f"add {-t[0]:.10g} s to every time")
        raise InsErrorsError(f"{where}: its times start at {t[0]:.10g} s, and a run starts "
                             "at t = 0 from the file's first sample: shift the column t to "
                             f"start at 0 ({shift})")


def _note_gaps(where: str, t: np.ndarray) -> None:
    """Note the largest gap in the samples (spacing > :data:`GAP_FACTOR` × median)."""
    import warnings

    step = np.diff(t)
    usual = float(np.median(step))
    gaps = np.flatnonzero(step > GAP_FACTOR * usual)
    if not gaps.size:
        return
    k = int(gaps[np.argmax(step[gaps])])
    more = f"; {gaps.size - 1} more gap(s) above {GAP_FACTOR:g}× that" if gaps.size > 1 else ""
    warnings.warn(f"ins-errors: note: {where} has no samples for {step[k]:.4g} s, from "
                  f"t = {t[k]:.10g} s to {t[k + 1]:.10g} s (its samples are usually "
                  f"{usual:.4g} s apart{more}): the cubic splines bridge the gap with a "
                  "motion the file does not record", RuntimeWarning, stacklevel=3)


def file_duration(profile: tr.Profile, step: float) -> float:
    """The length of a motion file's run: from t = 0 to its last sample, rounded down to
    a whole number of steps, s.

    Parameters
    ----------
    profile : ins_errors.numeric.trajectories.Profile
        The profile of :func:`read_motion_file`.
    step : float
        Integration step, s (> 0).
    """
    from ins_errors.numeric.integrators import whole_steps

    end = float(profile.breaks[-1])
    if whole_steps(end, step) is not None:
        return end
    return float(np.floor(end / step)) * step


def _read_columns(path: Path) -> tuple[list[str], dict[str, np.ndarray], list[int]]:
    """Header names, numeric columns and the line number of each sample of a motion CSV
    file (one-line errors)."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as error:
        reason = (getattr(error, "strerror", None) or str(error).splitlines()[0]
                  if str(error).strip() else "unreadable")
        raise InsErrorsError(f"cannot read motion file {str(path)!r}: {reason}") from None
    rows = []  # (line number, cells)
    for number, line in enumerate(text.splitlines(), start=1):
        body = line.split("#", 1)[0].strip()
        if body:
            rows.append((number, [cell.strip() for cell in body.split(",")]))
    if not rows:
        raise InsErrorsError(f"cannot read motion file {str(path)!r}: it is empty (expected "
                             "a header row t,v_N,v_E and rows of samples)")
    (_, names), samples = rows[0], rows[1:]
    if len(names) == 1 and any(mark in names[0] for mark in (";", "\t", " ")):
        raise InsErrorsError(f"motion file {str(path)!r}: its header {names[0]!r} is one "
                             "column: columns are separated by commas (t,v_N,v_E,h)")
    if "" in names:
        raise InsErrorsError(f"motion file {str(path)!r}: its header has an empty column "
                             f"name (column {names.index('') + 1}; a comma too many?): "
                             f"{','.join(names)!r}")
    values = np.empty((len(samples), len(names)))
    for k, (number, cells) in enumerate(samples):
        if len(cells) != len(names):
            raise InsErrorsError(f"motion file {str(path)!r}: line {number} has {len(cells)} "
                                 f"values, the header {len(names)} columns")
        for j, cell in enumerate(cells):
            try:
                values[k, j] = float(cell)
            except ValueError:
                shown = repr(cell if len(cell) <= 20 else cell[:20] + "…")
                raise InsErrorsError(
                    f"motion file {str(path)!r}: column {names[j]}, sample {k + 1} (line "
                    f"{number}): {shown} is not a number" if cell else
                    f"motion file {str(path)!r}: column {names[j]}, sample {k + 1} (line "
                    f"{number}) is empty") from None
    return (names, {name: values[:, j] for j, name in enumerate(names)},
            [number for number, _ in samples])


def _angle(value: Any, what: str) -> float:
    """An angle; text must carry its unit (``"50"`` would silently mean 50 rad)."""
    if isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            pass
        else:
            if not np.isfinite(number):
                raise InsErrorsError(f"{what}: {value!r} is not a finite number")
            raise InsErrorsError(f"{what} {value!r} needs a unit, e.g. '{value} deg' or "
                                 f"'{value} rad'")
    return parse_quantity(value, "rad", what, numbers_are_si=False)


_LEG_KEYS = ("duration", "speed", "turn", "height")


def _quantity(table: Mapping[str, Any], key: str, default: Any, unit: str) -> float:
    """A value of a user's table (must carry its unit) or the SI default."""
    if key not in table:
        return parse_quantity(default, unit, f"leg {key}")
    return parse_quantity(table[key], unit, f"leg {key}", numbers_are_si=False)


_SI_UNITS = {"latitude": "rad", "longitude": "rad", "heading": "rad", "speed": "m/s",
             "height": "m"}
"""The SI unit of each quantity of a motion description."""


def _read(description: Mapping[str, Any]) -> tuple[str, dict[str, float], Any,
                                                   list[tr.Leg] | None]:
    """Check a motion description and read it: (kind, SI values by :data:`_SI_UNITS` key,
    the ``file`` setting or None, the legs of a manoeuvre that lists its own or None)."""
    for key in description:
        if key not in _KEYS:
            raise unknown_name("motion setting", key, sorted(_KEYS))
    spec = {**DEFAULTS, **{k: v for k, v in description.items() if v is not None}}
    kind = motion_kind(str(spec["kind"]))  # spec files spell it great_circle
    for key, kinds in APPLIES_TO.items():
        if description.get(key) is not None and kind not in kinds:
            verb = "apply" if key == "legs" else "applies"
            raise InsErrorsError(f"motion {key} {verb} to kind {' or '.join(kinds)}, and "
                                 f"{_WHY_NOT[kind]}: leave {key} out or choose kind "
                                 f"{' or '.join(repr(k) for k in kinds)}")
    if kind != "static" and description.get("heading") is None:
        spec["heading"] = MOVING_HEADING
    values = {key: _angle(spec[key], f"motion {key}")
              for key in ("latitude", "longitude", "heading")}
    values["speed"] = parse_quantity(spec["speed"], "m/s", "motion speed",
                                     numbers_are_si=False)
    values["height"] = parse_quantity(spec["height"], "m", "motion height",
                                      numbers_are_si=False)
    legs = None
    if kind == "manoeuvre" and "legs" in spec:
        if not isinstance(spec["legs"], list) or not all(isinstance(leg, dict)
                                                         for leg in spec["legs"]):
            raise InsErrorsError("motion legs: expected a list of tables, [[motion.legs]]")
        for leg in spec["legs"]:
            for key in leg:
                if key not in _LEG_KEYS:
                    raise unknown_name("key of a motion leg", key, _LEG_KEYS)
        legs = [tr.Leg(_quantity(leg, "duration", "600 s", "s"),
                       _quantity(leg, "speed", values["speed"], "m/s"),
                       _quantity(leg, "turn", 0.0, "rad"),
                       _quantity(leg, "height", values["height"], "m"))
                for leg in spec["legs"]]
    return kind, values, spec.get("file"), legs


def motion_profile(description: Mapping[str, Any], base: Path | None = None,
                   model=None) -> tr.Profile:
    """Build a Profile from a motion description.

    Parameters
    ----------
    description : mapping
        ``kind`` (one of :data:`MOTION_KINDS`), ``latitude``, ``longitude``, ``heading``
        (track angle; default 0 at rest, :data:`MOVING_HEADING` when moving), ``speed``,
        ``height`` as text with units or SI numbers; ``file`` (a CSV, for kind
        ``"file"``); ``legs`` (for ``"manoeuvre"``: a list of tables with
        ``duration``, ``speed``, ``turn``, ``height``; default: :func:`default_legs`).
    base : Path, optional
        Folder that a relative ``file`` is taken from.
    model : ins_errors.numeric.model.Model, optional
        The model to fly: a heading given beside a motion file for a strapdown INS (a
        model fed body rates and specific forces, whose heading is the file's course) is
        refused before the file is read.

    Raises
    ------
    InsErrorsError
        For unknown keys or kinds, a setting the kind does not use (see
        :data:`APPLIES_TO`), values with wrong units, headings beyond ±360°, unreadable
        files.
    """
    kind, values, file, legs = _read(description)
    lat, lon, heading = values["latitude"], values["longitude"], values["heading"]
    speed, height = values["speed"], values["height"]
    if kind == "static":
        return tr.static_profile(lat, lon, heading, height)
    if kind == "great-circle":
        return tr.great_circle_profile(lat, lon, heading, speed, height)
    if kind == "file":
        if file is None:
            raise InsErrorsError("motion kind 'file' needs file = 'path/to/motion.csv'")
        refuse_file_heading(model, kind, description.get("heading") is not None)
        from ins_errors.user_paths import user_path

        path = user_path(file)
        if base is not None and not path.is_absolute():
            path = base / path
        return read_motion_file(path, lat, lon, heading, height,
                                height_given=description.get("height") is not None)
    if legs is None:  # the standard manoeuvre: described by its pattern, not its count;
        # a day of legs flown again and again, so that it lasts as long as any run
        return tr.manoeuvre_profile(lat, lon, heading, speed, default_legs(speed, height),
                                    height, name=STANDARD_MANOEUVRE, repeat=True)
    return tr.manoeuvre_profile(lat, lon, heading, speed, legs, height)


def refuse_file_heading(model, kind: str, heading_given: bool,
                        where: str = "motion heading") -> None:
    """Refuse a heading given for a strapdown INS along a motion file: it heads along the
    file's course, whatever heading is given (``where`` names the setting).

    Raises
    ------
    InsErrorsError
        One line.
    """
    if kind == "file" and heading_given and model is not None and flies_strapdown(model):
        raise InsErrorsError(f"{where}: a strapdown INS along a motion file heads along the "
                             "file's course atan2(v_E, v_N); leave the heading out")


def flies_strapdown(model) -> bool:
    """True for a model the strapdown flights carry: ``strapdown_ned`` and models fed
    body rates and specific forces (:func:`~ins_errors.numeric.trajectories.unset_inputs`)."""
    return model.name == "strapdown_ned" or bool(tr.unset_inputs(model))


def refuse_unused_heading(model, profile: tr.Profile, option: str = "--heading") -> None:
    """Refuse a heading given for a static base of a model without a heading output.

    At rest such a model's errors do not depend on its trihedron's track angle, so a
    heading given there was meant for something else.

    Raises
    ------
    InsErrorsError
        One line naming ``option`` and the model.
    """
    if profile.static and not any(o.name == "heading" for o in model.outputs):
        raise InsErrorsError(f"{option}: model {model.name!r} has no heading output, and at "
                             f"rest its errors do not depend on the heading; leave {option} "
                             "out")


def in_si(description: Mapping[str, Any]) -> dict[str, Any]:
    """The same motion with its defaults filled in and every quantity written as its exact
    SI value in its SI unit (``"0.8726646259971648 rad"``).

    :func:`motion_profile` reads such text without pint (a plain number in the very unit
    it wants) and gives the same profile bit for bit (a float's ``repr`` reads back as the
    same float). Sweep and validity tasks carry their motion in this form, so the worker
    processes that run them never import pint or build its registry (about 0.15 s CPU
    each beside Dask, 0.5 s alone).

    Raises
    ------
    InsErrorsError
        As :func:`motion_profile` (a missing or unreadable motion file is not checked).
    """
    kind, values, file, legs = _read(description)
    out: dict[str, Any] = {"kind": kind}
    out.update({key: f"{value!r} {_SI_UNITS[key]}" for key, value in values.items()
                if kind in APPLIES_TO.get(key, (kind,))
                # a motion file's height only as given: beside an h column it is refused
                and not (kind == "file" and key == "height"
                         and description.get("height") is None)})
    if file is not None:
        out["file"] = file
    if legs is not None:
        out["legs"] = [{"duration": f"{leg.duration!r} s", "speed": f"{leg.speed!r} m/s",
                        "turn": f"{leg.turn!r} rad", "height": f"{leg.height!r} m"}
                       for leg in legs]
    return out
