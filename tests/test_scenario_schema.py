"""Scenario files have one declared shape: pydantic checks it, editors get its JSON Schema.

The published schema (docs/scenario.schema.json) must be what ``ins-errors run --schema``
prints today, accept every example scenario and reject what the loader rejects; the
loader's schema errors are one line with close names suggested.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.scenario import load_scenario
from ins_errors.scenario_schema import json_schema

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent.parent
PUBLISHED = ROOT / "docs" / "scenario.schema.json"
# every example TOML file is a scenario, except the accuracy specs of examples/specs/
EXAMPLES = sorted(p for p in (ROOT / "examples").glob("**/*.toml")
                  if "specs" not in p.relative_to(ROOT / "examples").parts)
BASE = 'model = "orthodromic"\n[run]\nduration = "1 h"\n[[case]]\ngyro_drift_x = "0.01 deg/h"\n'


def test_published_schema_is_fresh(capsys):
    assert main(["run", "--schema"]) == 0
    printed = capsys.readouterr().out
    assert printed == json_schema()
    assert PUBLISHED.read_text(encoding="utf-8") == printed, (
        "docs/scenario.schema.json is stale: ins-errors run --schema > "
        "docs/scenario.schema.json")


@pytest.fixture(scope="module")
def validator():
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(PUBLISHED.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_every_example_matches_the_published_schema(path, validator):
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    assert not list(validator.iter_errors(data)), path.name


BAD = {
    "unknown top key": ('titel = "x"\n' + BASE,
                        "unknown key in s.toml 'titel'; did you mean 'title'"),
    "unknown run key": (BASE.replace("[run]", '[run]\nduraton = "2 h"'),
                        "unknown key in s.toml [run] 'duraton'; did you mean 'duration'"),
    "unknown method": (BASE.replace("[run]", '[run]\nmethod = "rk5"'),
                       "s.toml: unknown run method 'rk5'; did you mean 'rk4'"),
    "refined not bool": (BASE.replace("[run]", '[run]\nrefined = "yes"'),
                         "[run] refined must be true or false, got 'yes'"),
    "no case": (BASE.split("[[case]]")[0], "no [[case]]"),
    "case not array": (BASE.replace("[[case]]", "[case]"), "write [[case]], not [case]"),
    "motion not table": ('motion = "static"\n' + BASE, "'motion' must be a table"),
    "no model": (BASE.replace('model = "orthodromic"\n', ""), "missing 'model'"),
    "bad motion kind": (BASE + '[motion]\nkind = "orbit"\n', "s.toml: unknown motion kind 'orbit'"),
    "threshold range": (BASE.replace("[run]", "[run]\nvalidity_threshold = -1"),
                        "validity_threshold"),
    # read as no quantity: the report said "not excited: no magnitude of gyro_drift_x
    # gives any error on this motion", exit 0
    "empty outputs": (BASE + "[outputs]\nquantities = []\n",
                      "s.toml: outputs.quantities = []: an empty list; give at least 1, or "
                      "leave quantities out for the default (every judged quantity)"),
    # an IndexError traceback in the trajectory generator
    "empty legs": (BASE + '[motion]\nkind = "manoeuvre"\nlegs = []\n',
                   "s.toml: motion.legs = []: an empty list; give at least 1, or leave legs "
                   "out for the default (the standard manoeuvre)"),
}


@pytest.mark.parametrize("text, message", BAD.values(), ids=BAD.keys())
def test_schema_errors_are_one_line_with_suggestions(text, message, tmp_path, validator,
                                                     monkeypatch):
    monkeypatch.chdir(tmp_path)  # the file named as given: "s.toml"
    (tmp_path / "s.toml").write_text(text, encoding="utf-8")
    with pytest.raises(InsErrorsError) as raised:
        load_scenario("s.toml")
    assert message in str(raised.value) and "\n" not in str(raised.value)
    # what the loader refuses for its shape, the published schema refuses too
    assert list(validator.iter_errors(tomllib.loads(text)))


@pytest.mark.parametrize("text, message", [
    ('[items.position_error]\nvalue = "3.7 km/h"\nevry = "1 h"\n',
     "unknown key in [items.position_error] 'evry'; did you mean 'every'"),
    ('[items.position_eror]\nvalue = "3.7 km/h"\n',
     "unknown key in [items] 'position_eror'; did you mean 'position_error'"),
    ('[items.position_error]\nvalue = "3.7 km/h"\n[sources.gyro_drift_x]\nweigth = 2\n',
     "unknown key in [sources.gyro_drift_x] 'weigth'; did you mean 'weight'"),
    ('[items.position_error]\nvalue = "3.7 km/h"\ncombine = "max"\n',
     "unknown position_error combine 'max'"),
    ('sigma_level = true\n[items.position_error]\nvalue = "3.7 km/h"\n', "sigma_level"),
    ('[motion]\nkind = "manoeuvre"\nspeed = "200 m/s"\nlegs = []\n[items.position_error]\n'
     'value = "3.7 km/h"\n', "motion.legs = []: an empty list; give at least 1, or leave "
     "legs out for the default (the standard manoeuvre)"),
])
def test_spec_files_have_a_declared_shape_too(text, message, tmp_path):
    from ins_errors.specs import load_spec

    path = tmp_path / "spec.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InsErrorsError) as raised:
        load_spec(path)
    assert message in str(raised.value) and "\n" not in str(raised.value)


@pytest.mark.parametrize("extra, words", [
    ("[outputs]\nquantities = []\n", "outputs.quantities = []: an empty list"),
    ('[motion]\nkind = "manoeuvre"\nlegs = []\n', "motion.legs = []: an empty list"),
])
def test_run_refuses_an_empty_list_in_one_line(extra, words, tmp_path, capsys,
                                               monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(BASE.replace('"1 h"', '"6 min"') + extra,
                                     encoding="utf-8")
    assert main(["run", "s.toml", "--no-progress", "--out", "o"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and words in err, err
    assert not (tmp_path / "o").exists()


def test_the_python_api_refuses_a_manoeuvre_without_legs():
    from ins_errors.numeric import strapdown_truth as st
    from ins_errors.numeric import trajectories as tr

    for call in (lambda: tr.manoeuvre_profile(0.8, 0.0, 0.0, 200.0, []),
                 lambda: st.manoeuvre(0.8, 0.0, 0.0, 200.0, [])):
        with pytest.raises(tr.MotionError, match="a manoeuvre needs at least 1 leg"):
            call()
