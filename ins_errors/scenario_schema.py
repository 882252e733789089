"""The shape of a scenario file, declared once (pydantic), and its published JSON Schema.

:func:`validate` checks a TOML table against :class:`ScenarioFile` and turns the first
problem into one line with close-name suggestions (``unknown key in s.toml [run]
'duraton'; did you mean 'duration'?``). What the schema cannot know (which error sources
and quantities the chosen model has, what a quantity's unit must be, whether the grid
divides the run) is checked afterwards by :func:`ins_errors.scenario.load_scenario`.

``ins-errors run --schema`` prints :func:`json_schema`; the copy in
``docs/scenario.schema.json`` lets editors (e.g. VS Code's Even Better TOML, taplo)
check and complete scenario files as they are typed (a test keeps it fresh).
"""

from __future__ import annotations

import json
import re
from typing import Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
)

from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.units import VALIDITY_RATIO_CEILING, ratio_outside

Quantity = StrictStr | StrictFloat | StrictInt
"""A value with its unit as text (``"0.01 deg/h"``, ``"24 h"``); a bare number is
accepted by the schema only where zero or a plain ratio is meant."""

_QUANTITY = {"description": "a value with its unit, e.g. '0.01 deg/h', '24 h', '50 deg'"}


class _Table(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Leg(_Table):
    """One leg of a manoeuvre: it lasts ``duration`` at ``speed``, turning by ``turn``."""

    duration: Quantity = Field("600 s", json_schema_extra=_QUANTITY)
    speed: Quantity | None = Field(None, json_schema_extra=_QUANTITY)
    turn: Quantity = Field(0.0, json_schema_extra=_QUANTITY)
    height: Quantity | None = Field(None, json_schema_extra=_QUANTITY)


class Motion(_Table):
    """``[motion]``: the true motion (see :mod:`ins_errors.numeric.motion_spec`)."""

    kind: Literal["static", "great-circle", "great_circle", "manoeuvre", "file"] = "static"
    latitude: Quantity = Field("50 deg", json_schema_extra=_QUANTITY)
    longitude: Quantity = Field("30 deg", json_schema_extra=_QUANTITY)
    heading: Quantity | None = Field(
        None, description="track angle; default 0 deg at rest, 90 deg (east) when moving")
    speed: Quantity = Field("250 m/s", json_schema_extra=_QUANTITY)
    height: Quantity = Field("0 m", json_schema_extra=_QUANTITY)
    file: str | None = Field(None, description="kind 'file': CSV with t, v_N, v_E [, h] (SI)")
    legs: list[Leg] | None = Field(None, min_length=1,
                                   description="kind 'manoeuvre': the legs flown")


class Run(_Table):
    """``[run]``: duration, grid and scheme of the runs."""

    duration: Quantity = Field("24 h", json_schema_extra={
        "description": "a value with its unit, e.g. '24 h', '90 min'; default 24 h, along a "
                       "motion file the file's length"})
    step: Quantity = Field("1 s", json_schema_extra=_QUANTITY)
    record: Quantity = Field("60 s", json_schema_extra=_QUANTITY)
    method: Literal["euler", "rk4"] = Field(
        "rk4", description="'euler': the manual's rectangle method; 'rk4'")
    refined: StrictBool = Field(True, description="also run the second-order model")
    ellipsoid: str | None = Field(None, description="Earth model, e.g. 'wgs84', "
                                                    "'krasovsky' (default: the model's)")
    platform: Literal["exact", "small_angle"] = "exact"
    validity_threshold: float = Field(0.05, gt=0, lt=VALIDITY_RATIO_CEILING,
                                      description="linear/direct ratio that warns")
    truth: Literal["auto", "interpolated", "fine"] = Field(
        "auto", description="true motion of a moving run: 'fine' integrated at every step, "
                            "'interpolated' from coarse exact intervals, 'auto' the "
                            "library's choice (as 'ins-errors compare --truth')")


class Outputs(_Table):
    """``[outputs]``: the quantities the report shows and judges (its worst ratios and
    warnings); default: every judged one."""

    quantities: list[str] | None = Field(None, min_length=1)


class Case(BaseModel):
    """``[[case]]``: an optional label and error sources of the model with units."""

    model_config = ConfigDict(
        extra="allow",
        json_schema_extra={"additionalProperties": {"type": ["string", "number"],
                                                    **_QUANTITY}})

    label: str | None = None


_GRID = {
    "anyOf": [
        {"type": "array", "minItems": 1, "items": {"type": ["string", "number"]},
         "description": "the grid's values with their units, e.g. ['30 deg', '60 deg'], "
                        "['5e-4/s', '1e-3/s']"},
        {"type": "object", "required": ["start", "stop", "count"],
         "additionalProperties": False,
         "properties": {"start": {"type": ["string", "number"], **_QUANTITY},
                        "stop": {"type": ["string", "number"], **_QUANTITY},
                        "count": {"type": "integer", "minimum": 1}},
         "description": "count values evenly from start to stop"},
    ],
    "description": "a grid over a motion or run setting, an error source or a model "
                   "parameter (which names a model has: ins-errors models MODEL)",
}


def _sweep_schema(schema: dict[str, Any]) -> None:
    """The ``[sweep]`` table's shape for editors (the table itself is read by
    :func:`ins_errors.analysis.sweep.parse_sweep`, which knows the model's names): its
    own keys, and a grid under any other name."""
    table = {
        "type": "object",
        "properties": {
            "draws": {"type": "integer", "minimum": 0,
                      "description": "Monte Carlo draws per grid point"},
            "seed": {"type": "integer", "minimum": 0, "description": "seed of the draws"},
            "scheduler": {"type": "string",
                          "description": "Dask scheduler, e.g. 'tcp://host:8786'"},
            "random": {"type": "object",
                       "additionalProperties": {"type": ["string", "number"], **_QUANTITY},
                       "description": "[sweep.random]: 1σ of the error sources drawn"},
        },
        "additionalProperties": _GRID,
    }
    schema["anyOf"] = [table if option.get("type") == "object" else option
                       for option in schema["anyOf"]]


class ScenarioFile(_Table):
    """A whole scenario file (TOML)."""

    model_config = ConfigDict(extra="forbid", title="ins-errors scenario file")

    title: str | None = None
    description: str = ""
    model: str = Field(description="model name, e.g. 'orthodromic' (ins-errors models)")
    motion: Motion = Field(default_factory=Motion)
    run: Run = Field(default_factory=Run)
    case: list[Case] = Field(min_length=1, description="one [[case]] per set of sources")
    outputs: Outputs = Field(default_factory=Outputs)
    parameters: dict[str, Quantity] | None = Field(
        None, description="model parameters with units (ins-errors models MODEL lists "
                          "them), e.g. strapdown_ned's vertical damping gains "
                          "k_h1 = '0.0047 1/s', k_h2 = '1.4e-5 1/s**2' (default: the model's)")
    sweep: dict[str, Any] | None = Field(
        None, description="grids over settings (ins-errors sweep): the motion's latitude, "
                          "longitude, heading, speed, height; the run's duration, step; "
                          "any error source's magnitude or model parameter's value, e.g. "
                          "k_v = ['5e-4/s', '1e-3/s']; Monte Carlo draws",
        json_schema_extra=_sweep_schema)


_TABLES: dict[str, type[BaseModel]] = {"": ScenarioFile, "motion": Motion, "run": Run,
                                       "outputs": Outputs, "legs": Leg}


def _where(loc: tuple, name: str) -> str:
    tables = ".".join(str(p) for p in loc[:-1] if isinstance(p, str))
    if not name:
        return f"[{tables}]" if tables else "the file"
    return f"{name} [{tables}]" if tables else name


def one_line(error: ValidationError, name: str,
             tables: dict[str, type[BaseModel]]) -> InsErrorsError:
    """The first problem of a pydantic ``ValidationError`` as one line for people.

    Parameters
    ----------
    error : pydantic.ValidationError
        What ``model_validate`` raised.
    name : str
        File name to prefix (``""``: none).
    tables : dict
        Table name -> schema class, to suggest close names for an unknown key.
    """
    first = error.errors()[0]
    loc, kind = tuple(first["loc"]), first["type"]
    key = str(loc[-1]) if loc else ""
    prefix = f"{name}: " if name else ""
    parent = next((str(p) for p in reversed(loc[:-1]) if isinstance(p, str)), "")
    if kind == "extra_forbidden":
        fields = sorted(f.alias or n for n, f in tables.get(parent, tables[""])
                        .model_fields.items())
        return unknown_name(f"key in {_where(loc, name)}", key, fields)
    if kind == "literal_error":
        expected = [e.strip().strip("'") for e in
                    first["ctx"]["expected"].replace(" or ", ", ").split(",")]
        found = unknown_name(f"{parent} {key}".strip(), str(first["input"]), expected)
        return type(found)(f"{prefix}{found}")
    if kind == "bool_type":
        return InsErrorsError(f"{prefix}[{parent}] {key} must be true or false, got "
                              f"{first['input']!r}")
    if kind in ("model_type", "dict_type") and isinstance(loc[-1], str):
        return InsErrorsError(f"{prefix}'{key}' must be a table, [{key}]")
    members = [p for p in loc if isinstance(p, str) and UNION_MEMBER.match(p)]
    loc = tuple(p for p in loc if p not in members)  # pydantic's names, not the file's
    path = ".".join(str(p) for p in loc)
    value = repr(first.get("input"))[:60]
    if kind == "missing":
        return InsErrorsError(f"{prefix}missing {path!r}")
    if kind == "too_short" and first.get("input") == []:
        default = {"legs": " (the standard manoeuvre)",
                   "quantities": " (every judged quantity)"}.get(key, "")
        return InsErrorsError(f"{prefix}{path} = []: an empty list; give at least "
                              f"{first['ctx']['min_length']}, or leave {key} out for "
                              f"the default{default}")
    if members:  # a quantity (text with a unit, or a number) that is neither
        return InsErrorsError(f"{prefix}{path} must be one value with its unit (e.g. "
                              f"'50 deg', '24 h'), got {value}")
    return InsErrorsError(f"{prefix}{path} = {value}: {first['msg'].lower()}")


UNION_MEMBER = re.compile(r"^(constrained-)?(str|float|int|bool)$")
"""How pydantic names the member of a union type (a quantity: text or a number) in an
error's location."""


def _one_line(error: ValidationError, name: str) -> InsErrorsError:
    first = error.errors()[0]
    loc, kind = tuple(first["loc"]), first["type"]
    if loc == ("case",) and kind in ("missing", "too_short"):
        return InsErrorsError(f"{name}: no [[case]] with error sources")
    if loc == ("case",) and kind == "list_type":
        return InsErrorsError(f"{name}: cases are an array of tables: write [[case]], "
                              "not [case]")
    if loc == ("run", "truth") and kind == "literal_error":
        from ins_errors.numeric.trajectories import TRUTHS

        return InsErrorsError(f"{name}: unknown run truth {first['input']!r}; allowed: "
                              f"{', '.join(TRUTHS)}")
    if loc == ("run", "validity_threshold") and kind in ("greater_than", "less_than"):
        return InsErrorsError(f"{name}: [run] validity_threshold = {first['input']!r}: "
                              f"{ratio_outside(float(first['input']), '0.05')}")
    if loc == ("model",) and kind == "missing":
        return InsErrorsError(f"{name}: missing 'model' (e.g. model = \"orthodromic\")")
    return one_line(error, name, _TABLES)


def validate(data: Any, name: str) -> ScenarioFile:
    """Check a scenario table (as TOML read it) against the schema.

    Parameters
    ----------
    data : dict
        The parsed TOML.
    name : str
        File name for messages.

    Raises
    ------
    InsErrorsError
        One line: the file, the table and key, what is wrong (close names suggested).
    """
    try:
        return ScenarioFile.model_validate(data)
    except ValidationError as error:
        raise _one_line(error, name) from None


def json_schema() -> str:
    """The JSON Schema (draft 2020-12) of a scenario file, as stable, indented text."""
    schema = ScenarioFile.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return json.dumps(schema, indent=2, sort_keys=True, ensure_ascii=False) + "\n"
