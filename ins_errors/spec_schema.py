"""The shape of an accuracy-spec file (``ins-errors budget --spec``), declared once.

:func:`validate` checks the TOML table against :class:`SpecFile` (tables, keys, types,
names of choices, signs of plain numbers) with one-line errors and close names
suggested; :func:`ins_errors.specs.parse_spec` then reads the quantities with their
units and checks what depends on them (check times on the analysis grid, a Markov
source's correlation time...).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    ValidationError,
    create_model,
)

from ins_errors.errors import InsErrorsError
from ins_errors.scenario_schema import UNION_MEMBER, Leg, Quantity, one_line

Number = StrictFloat | StrictInt
Positive = (Annotated[StrictFloat, Field(gt=0, allow_inf_nan=False)]
            | Annotated[StrictInt, Field(gt=0)])
"""A plain finite number above zero (the bound on each member, so the JSON Schema carries
it; TOML's inf and nan are refused)."""
_UNIT = {"description": "a value with its unit, e.g. '8 h', '3.7 km/h', '0.01 deg/h'"}


class _Table(BaseModel):
    model_config = ConfigDict(extra="forbid", populate_by_name=True)


class SpecMotion(_Table):
    """``[motion]``: the motion the spec is checked along."""

    kind: Literal["static", "great_circle", "great-circle", "manoeuvre"] = Field(
        "static", description="'manoeuvre': the scenario files' standard manoeuvre (every "
        "hour a 90° left turn, a 20 % speed-up with a 2-km climb, two 45° right turns "
        "back), or the "
        "[[motion.legs]] given")  # spelled as in scenario files
    latitude: Quantity = Field("0 deg", json_schema_extra=_UNIT)
    longitude: Quantity = Field("0 deg", json_schema_extra=_UNIT)
    heading: Quantity = Field("0 deg", json_schema_extra=_UNIT)
    height: Quantity = Field(0, json_schema_extra=_UNIT)
    speed: Quantity = Field(0, description="ground speed of a great circle, start speed "
                            "of a manoeuvre (required > 0 for both), e.g. '250 m/s'")
    legs: list[Leg] | None = Field(None, min_length=1, description="kind 'manoeuvre': "
                                   "the legs flown instead of the standard manoeuvre")


class SpecItem(_Table):
    """``[items.NAME]``: a limit and when it is checked."""

    value: Quantity = Field(json_schema_extra=_UNIT)
    times: list[Quantity] | None = Field(None, min_length=1)
    every: Quantity | None = None
    start: Quantity | None = Field(None, alias="from")
    until: Quantity | None = None
    combine: Literal["rss", "each", "cep"] = Field(
        "rss", description="how the components combine: 'rss' (root sum of squares: "
        "2DRMS at 2σ), 'each' (every component on its own) or, for position_error and "
        "position_error_absolute, 'cep' (the circular error probable of the north and "
        "east errors, whatever the σ level)")


class NoiseTable(_Table):
    """``[sources.NAME.noise]``: a second part of the source, noise beside its bias."""

    weight: Positive = 1.0
    fixed: Quantity | None = Field(None, json_schema_extra=_UNIT)
    kind: Literal["white", "markov"] = Field(
        "white", description="'white' (a density, e.g. '0.02 deg/sqrt(h)') or 'markov' "
        "(with tau); a kind other than the source's own")
    tau: Quantity | None = Field(None, json_schema_extra=_UNIT)
    sigma_level: Positive | None = Field(
        None, description="σ level of a Markov part's magnitude (default: the spec's); a "
        "white density has none")


class SourceTable(_Table):
    """``[sources.NAME]``: how the budget treats one error source."""

    weight: Positive = 1.0
    fixed: Quantity | None = Field(None, json_schema_extra=_UNIT)
    kind: Literal["constant", "white", "markov"] = "constant"
    tau: Quantity | None = Field(None, json_schema_extra=_UNIT)
    include: StrictBool = True
    sigma_level: Positive | None = Field(
        None, description="σ level of this source's magnitude (fixed, and as reported), "
        "e.g. 1 for a datasheet's 1σ bias in a 3σ spec (default: the spec's "
        "sigma_level); a white-noise density (kind 'white') has none: it is read as "
        "given")
    noise: NoiseTable | None = Field(
        None, description="a second part of the source, propagated beside it: its noise "
        "(e.g. [sources.gyro_bias_x] fixed = '0.5 deg/h' with [sources.gyro_bias_x.noise] "
        "fixed = '0.02 deg/sqrt(h)')")


class Allocation(_Table):
    """``[allocation]``."""

    fill: StrictBool = False


def _items_table() -> type[BaseModel]:
    from ins_errors.specs import ITEM_KINDS

    fields = {name: (SpecItem | None, Field(None, description=kind.description))
              for name, kind in ITEM_KINDS.items()}
    return create_model("Items", __base__=_Table, **fields)


Items = _items_table()


class SpecFile(_Table):
    """A whole accuracy-spec file (TOML)."""

    title: str | None = None
    sigma_level: Positive = Field(1, description="the spec's values are this many σ, from "
                                  "0.1 to 10")
    operating_time: Quantity = Field("1 h", json_schema_extra=_UNIT)
    step: Quantity = Field("60 s", json_schema_extra=_UNIT)
    motion: SpecMotion = Field(default_factory=SpecMotion)
    items: Items  # type: ignore[valid-type]
    allocation: Allocation = Field(default_factory=Allocation)
    sources: dict[str, SourceTable] = Field(default_factory=dict)
    parameters: dict[str, Quantity] | None = Field(
        None, description="model parameters with units, as in a scenario's [parameters] "
                          "(ins-errors models MODEL lists them), e.g. strapdown_ned's "
                          "k_h1 = '0.0047 1/s'; 'ins-errors budget --parameter' overrides "
                          "them (default: the model's)")


_TABLES: dict[str, type[BaseModel]] = {"": SpecFile, "motion": SpecMotion, "items": Items,
                                       "allocation": Allocation, "legs": Leg}


def validate(data: dict) -> SpecFile:
    """Check a spec table (as TOML read it) against the schema.

    Raises
    ------
    InsErrorsError
        One line naming the table, the key and the problem.
    """
    from ins_errors.specs import ITEM_KINDS

    if not data.get("items"):
        raise InsErrorsError(f"the spec has no [items.*]; known items: "
                             f"{', '.join(ITEM_KINDS)}")
    items = data.get("items")
    if isinstance(items, dict):
        for name in items:
            if name in ITEM_SYNONYMS and name not in ITEM_KINDS:
                known = ITEM_SYNONYMS[name]
                raise InsErrorsError(
                    f"unknown item [items.{name}]: {ITEM_KINDS[known].description} is "
                    f"[items.{known}] (items: {', '.join(ITEM_KINDS)})")
    try:
        return SpecFile.model_validate(data)
    except ValidationError as error:
        first = error.errors()[0]
        loc = tuple(first["loc"])
        if loc == ("motion", "kind") and first.get("input") == "file":
            raise InsErrorsError(
                "[motion] kind = 'file': a budget spec takes no motion file; its motion is "
                "'static', 'great_circle' or 'manoeuvre' (planned motions that last any "
                "operating time); fly a motion file with compare --motion-file, or with "
                "kind = 'file' in a run or sweep scenario") from None
        tables = dict(_TABLES)
        if len(loc) >= 3 and loc[0] == "items":
            tables[str(loc[1])] = SpecItem
        if len(loc) >= 3 and loc[0] == "sources":
            tables[str(loc[1])] = SourceTable
            tables["noise"] = NoiseTable
        plain = _union_message(first)
        if plain:
            raise InsErrorsError(plain) from None
        raise one_line(error, "", tables) from None


ITEM_SYNONYMS = {
    "velocity_error": "ground_speed_error", "speed_error": "ground_speed_error",
    "horizontal_velocity_error": "ground_speed_error",
    "altitude_error": "height_error", "vertical_position_error": "height_error",
    "azimuth_error": "heading_error", "yaw_error": "heading_error",
    "tilt_error": "vertical_error", "level_error": "vertical_error",
    "attitude_error": "vertical_error", "azimuth_drift": "heading_drift",
    "drift_rate": "heading_drift", "position_drift": "position_error",
    "horizontal_position_error": "position_error_absolute",
}
"""Names one might give a spec item, and the item that measures it (spelling slips are
caught by the close-name suggestion; these are other words for the same error)."""


def _union_message(first: dict) -> str | None:
    """One line for a value of a union type (a positive number, a quantity) that none of
    the members takes, in the file's own key names (no pydantic member names)."""
    loc = tuple(first["loc"])
    members = [p for p in loc if isinstance(p, str) and UNION_MEMBER.match(p)]
    if not members:
        return None
    keys = [p for p in loc if p not in members]
    path = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in keys).lstrip(".")
    value = repr(first.get("input"))[:60]
    if members[0].startswith("constrained-"):      # a Positive
        hint = " (include = false leaves a source out)" if keys[-1] == "weight" else ""
        return f"{path} must be a number > 0, got {value}{hint}"
    return f"{path} must be a value with its unit (e.g. '8 h', '0.1 deg'), got {value}"


def json_schema() -> str:
    """The JSON Schema (draft 2020-12) of an accuracy-spec file, as stable, indented text."""
    import json

    schema = SpecFile.model_json_schema()
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return json.dumps(schema, indent=2, sort_keys=True, ensure_ascii=False) + "\n"
