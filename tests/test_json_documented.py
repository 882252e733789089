"""Every key a command's ``--json`` prints is documented in docs/json.md, and every output
carries ``schema_version`` and is indented alike.

The commands run here (compare, check and its variants, budget, validity, modes,
transfer, matrices, sweep, cache, models, study list) and their output is compared with the page,
key by key: a key that the page does not list fails the test, naming it, so whoever adds
a key to a command's JSON documents it there (meaning and unit) in the same change.

How the page is read: a ``## `command``` section holds the keys of that command's object,
one table row each (every key in backticks in the row's first cell); a ``### `prefix```
heading inside a section puts its rows under that key (``cases[]``: each object of the
list ``cases``). ``<name>`` stands for any key of a table keyed by names; where such a
key sits beside fixed keys it matches only those fixed keys, or, for ``<swept>``, the
names the output lists under ``swept``. The rows of "Every command" belong to every
command.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "json.md"
COMMON = "Every command"
PLACEHOLDER = re.compile(r"<[^<>]+>")
RESOLVED = {"<swept>": lambda data: set(data.get("swept") or ())}
"""Placeholders beside fixed keys that stand for names the output itself lists."""

SWEEP = """title = "JSON keys"
model = "orthodromic"
[motion]
kind = "static"
[run]
duration = "10 min"
step = "10 s"
record = "60 s"
[[case]]
accel_bias_x = "100 ug"
[sweep]
latitude = ["20 deg", "40 deg"]
"""


def documented() -> dict[str, list[str]]:
    """Section title (backticks removed) -> the key patterns its tables list."""
    sections: dict[str, list[str]] = {}
    current, prefix = None, ""
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            current, prefix = line[3:].replace("`", "").strip(), ""
            sections[current] = []
        elif line.startswith("### "):
            found = re.search(r"`([^`]+)`", line)
            prefix = found.group(1) if found else ""
        elif current is not None and line.startswith("| `"):
            first = re.split(r"(?<!\\)\|", line)[1]
            sections[current] += [f"{prefix}.{key}" if prefix else key
                                  for key in re.findall(r"`([^`]+)`", first)]
    return sections


def key_paths(value, prefix: tuple[str, ...] = ()) -> set[tuple[str, ...]]:
    """Every key of a JSON value as a path of segments; ``name[]`` descends into the
    objects of the list ``name``. A top-level array: the keys of its objects."""
    out: set[tuple[str, ...]] = set()
    if isinstance(value, dict):
        for key, item in value.items():
            path = (*prefix, str(key))
            out.add(path)
            out |= key_paths(item, path)
    elif isinstance(value, list):
        for item in value:
            if prefix:
                out |= key_paths(item, (*prefix[:-1], prefix[-1] + "[]"))
            else:
                out |= key_paths(item, prefix)
    return out


def _segment_regex(segment: str) -> re.Pattern:
    parts = PLACEHOLDER.split(segment)
    return re.compile("(.+)".join(re.escape(p) for p in parts))


def matcher(patterns: list[str]):
    """A function: (path, output) -> whether a documented pattern covers the path."""
    split = [tuple(p.split(".")) for p in patterns]

    def allowed(pattern: tuple[str, ...], i: int, data) -> set[str] | None:
        """Names a whole-segment placeholder at ``pattern[i]`` may stand for, or None
        (any name: a table keyed by names alone)."""
        segment = pattern[i]
        bare = segment.removesuffix("[]")
        if PLACEHOLDER.fullmatch(bare) is None:
            return None
        if bare in RESOLVED:
            return RESOLVED[bare](data)
        fixed = {other[i].removesuffix("[]") for other in split
                 if len(other) > i and other[:i] == pattern[:i]
                 and PLACEHOLDER.search(other[i]) is None}
        return fixed or None

    def covers(path: tuple[str, ...], data) -> bool:
        for pattern in split:
            if len(pattern) != len(path):
                continue
            for i, (want, got) in enumerate(zip(pattern, path, strict=True)):
                if want == got:
                    continue
                if PLACEHOLDER.search(want) is None or not _segment_regex(want).fullmatch(got):
                    break
                names = allowed(pattern, i, data)
                if names is not None and got.removesuffix("[]") not in names:
                    break
            else:
                return True
        return False

    return covers


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    """A scratch folder for what the commands write, and the sweep scenario."""
    tmp = tmp_path_factory.mktemp("json_keys")
    sweep = tmp / "sweep.toml"
    sweep.write_text(SWEEP, encoding="utf-8")
    return tmp, sweep


def _run(argv, capsys, monkeypatch, tmp):
    if argv[0] == "cache":  # a scratch cache: clear must not empty the user's
        monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp / "cache"))
    status = main(argv)
    return status, capsys.readouterr().out


EXAMPLES = ROOT / "examples"
VARIANTS = {
    # variant: (sections of the page, argv with {tmp}, expected exit status)
    "compare": (["compare"], ["compare", "orthodromic", "--source", "gyro_drift_y=0.01deg/h",
                              "--hours", "1", "--json", "--no-progress"], 0),
    "check": (["check"], ["check", "orthodromic",
                          str(EXAMPLES / "manual_000/equations.txt"), "--json"], 1),
    "check several files": (["check"], [
        "check", "north_pointing", str(ROOT / "tests/data/hand_correct_north_pointing.txt"),
        "{tmp}/absent.txt", "--json", "-p", "R=6371km"], 2),
    "check @convention": (["check --matrix", "check of a file with @convention"], [
        "check", "strapdown_ned", str(EXAMPLES / "strapdown/phi_attitude.txt"), "--json"], 0),
    "check --matrix": (["check --matrix"], [
        "check", "strapdown_ned", "--matrix",
        f"{EXAMPLES / 'strapdown/psi_model.py'}:psi_model", "--convention", "psi",
        "--json"], 0),
    "check --list-conventions": (["check --list-conventions"], [
        "check", "strapdown_ned", "--list-conventions", "--json"], 0),
    "check --list-conventions without one": (["check --list-conventions"], [
        "check", "orthodromic", "--list-conventions", "--json"], 0),
    "check --write-samples": (["check --write-samples"], [
        "check", "strapdown_ned", "--write-samples", "{tmp}/samples.npz", "--json"], 0),
    "budget": (["budget"], ["budget", "orthodromic", "--json", "--at", "1 h",
                            "--monte-carlo", "2", "--mc-duration", "2 h", "--mc-step", "1 s",
                            "--engine", "serial"], 0),
    "budget exceeded": (["budget"], [
        "budget", "orthodromic", "--spec", str(EXAMPLES / "specs/gyro_drift_fixed.toml"),
        "--json", "--at", "1 h"], 1),
    "validity": (["validity"], ["validity", "orthodromic", "--source", "gyro_drift_x",
                                "--motion", "static", "--hours", "1", "--step", "10s",
                                "--latitude", "20deg", "--json", "--no-progress"], 0),
    "modes": (["modes"], ["modes", "strapdown_ned", "--json"], 0),
    # constant (the tilt), power (the drift's latitude), exponential (the vertical
    # channel) and none (a longitude error seen nowhere else) long runs
    "transfer": (["transfer"], [
        "transfer", str(EXAMPLES / "own_model/schuler_loop.py"), "--source", "accel_bias",
        "--source", "gyro_drift", "--output", "psi", "--output", "latitude", "--json"], 0),
    "transfer strapdown_ned": (["transfer"], [
        "transfer", "strapdown_ned", "--source", "accel_bias_z", "--source",
        "initial_position_error_E", "--output", "height", "--output", "latitude", "--json"],
        0),
    "matrices": (["matrices"], ["matrices", "strapdown_ned", "--hours", "1", "--out",
                                "{tmp}/F.npz", "--json"], 0),
    "matrices --discrete": (["matrices"], [
        "matrices", "strapdown_ned", "--motion", "static", "--hours", "1", "--step", "60 s",
        "--bias-states", "gyro_bias_z", "--markov", "gyro_bias_z=1h", "--discrete",
        "--noise", "gyro_bias_x=0.003deg/rt-hr,gyro_bias_z=0.01deg/h", "--out",
        "{tmp}/Phi.npz", "--json"], 0),
    "sweep": (["sweep"], ["sweep", "{sweep}", "--store", "{tmp}/sweep.zarr", "--engine",
                          "serial", "--json", "--no-progress"], 0),
    "cache info": (["cache info"], ["cache", "info", "--json"], 0),
    "cache clear": (["cache clear"], ["cache", "clear", "--json"], 0),
    "models": (["models"], ["models", "--json"], 0),
    "models MODEL": (["models MODEL"], ["models", "orthodromic", "--json"], 0),
    "study list": (["study list"], ["study", "list", "--json"], 0),
}


@pytest.mark.parametrize("variant", VARIANTS)
def test_every_json_key_is_documented(variant, scratch, capsys, monkeypatch):
    tmp, sweep = scratch
    sections, argv, expected = VARIANTS[variant]
    argv = [a.replace("{tmp}", str(tmp)).replace("{sweep}", str(sweep)) for a in argv]
    status, text = _run(argv, capsys, monkeypatch, tmp)
    assert status == expected, text
    # indented by two, schema_version first (in each object of an array)
    head = '{\n  "schema_version": 2,' if text.startswith("{") else \
        '[\n  {\n    "schema_version": 2,'
    assert text.startswith(head), text[:80]
    data = json.loads(text)
    page = documented()
    for section in [COMMON, *sections]:
        assert section in page, f"docs/json.md has no section '## {section}'"
    covers = matcher([p for s in [COMMON, *sections] for p in page[s]])
    objects = data if isinstance(data, list) else [data]
    missing = sorted({".".join(path) for item in objects for path in key_paths(item)
                      if not covers(path, item)})
    assert not missing, (f"keys of {variant} --json not in docs/json.md "
                         f"({', '.join(sections)}): {missing}")


def test_the_page_is_read_as_meant():
    """The reader of the page: prefixes, several keys in a cell, placeholders beside
    fixed keys (only those keys), placeholders alone (any name), swept names."""
    page = documented()
    compare = matcher(page[COMMON] + page["compare"])
    assert compare(("cases[]", "metrics[]", "linear_ratio"), {})
    assert compare(("cases[]", "sources", "gyro_drift_y"), {})  # a table of names
    assert compare(("parameters_used", "a", "value"), {})
    assert not compare(("cases[]", "metrics[]", "no_such_key"), {})
    modes = matcher(page[COMMON] + page["modes"])
    assert modes(("references", "g", "value"), {})
    assert not modes(("references", "h", "value"), {})  # g, R, Omega, latitude only
    sweep = matcher(page[COMMON] + page["sweep"])
    assert sweep(("summary[]", "latitude"), {"swept": {"latitude": "rad"}})
    assert not sweep(("summary[]", "latitude"), {"swept": {"heading": "rad"}})
    assert not sweep(("summary[]", "new_key"), {"swept": {"latitude": "rad"}})
    models = matcher(page[COMMON] + page["models MODEL"])
    assert models(("sources[]", "display_unit"), {})
    assert not models(("others[]", "display_unit"), {})
