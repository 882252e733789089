"""Accuracy-spec files have a published JSON Schema, like scenario files.

The published schema (docs/spec.schema.json) must be what ``ins-errors budget --schema``
prints today, accept the built-in 802m spec and reject what the spec loader rejects for
its shape.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.spec_schema import json_schema
from ins_errors.specs import default_spec_path, load_spec

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent.parent
PUBLISHED = ROOT / "docs" / "spec.schema.json"


def test_published_spec_schema_is_fresh(capsys):
    assert main(["budget", "--schema"]) == 0
    printed = capsys.readouterr().out
    assert printed == json_schema()
    assert PUBLISHED.read_text(encoding="utf-8") == printed, (
        "docs/spec.schema.json is stale: ins-errors budget --schema > docs/spec.schema.json")


def test_budget_without_model_or_schema_is_one_line(capsys):
    assert main(["budget"]) == 2
    err = capsys.readouterr().err
    assert "budget needs a MODEL (or --schema)" in err and "Traceback" not in err


@pytest.fixture(scope="module")
def validator():
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(PUBLISHED.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_built_in_spec_matches_the_published_schema(validator):
    data = tomllib.loads(default_spec_path().read_text(encoding="utf-8"))
    assert not list(validator.iter_errors(data))


GOOD_ITEM = '[items.position_error]\nvalue = "3.7 km/h"\n'
BAD = {
    "misspelt item key": (GOOD_ITEM + 'evry = "1 h"\n', "'evry'"),
    "unknown item": ('[items.position_eror]\nvalue = "3.7 km/h"\n', "'position_eror'"),
    "misspelt source key": (GOOD_ITEM + "[sources.gyro_drift_x]\nweigth = 2\n", "'weigth'"),
    "unknown combine": (GOOD_ITEM + 'combine = "sum"\n', "combine"),
    "negative weight": (GOOD_ITEM + "[sources.gyro_drift_x]\nweight = -1\n", "weight"),
    "unknown motion kind": (GOOD_ITEM + '[motion]\nkind = "orbit"\n', "kind"),
    "zero sigma level": ("sigma_level = 0\n" + GOOD_ITEM, "sigma_level"),
}


@pytest.mark.parametrize("text, message", BAD.values(), ids=BAD.keys())
def test_what_the_loader_refuses_the_schema_refuses(text, message, tmp_path, validator):
    path = tmp_path / "s.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InsErrorsError) as raised:
        load_spec(path)
    assert message in str(raised.value) and "\n" not in str(raised.value)
    assert list(validator.iter_errors(tomllib.loads(text)))


def test_a_limit_without_its_unit_is_refused_with_one_set_of_examples(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[items.position_error]\nvalue = "3.7"\n', encoding="utf-8")
    with pytest.raises(InsErrorsError) as raised:
        load_spec(path)
    message = str(raised.value)
    assert "position_error" in message and "\n" not in message
    assert message.count("e.g.") == 1, message


def test_a_motion_file_in_a_spec_is_refused_as_not_taken_by_budgets(tmp_path, capsys):
    # the docs say what takes a motion file (compare, run, sweep) and what does not:
    # a budget spec said only "unknown motion kind 'file'"
    csv = tmp_path / "flight.csv"
    csv.write_text("t,v_N,v_E\n0,0,100\n600,0,100\n1200,0,100\n1800,0,100\n")
    path = tmp_path / "s.toml"
    path.write_text(GOOD_ITEM + f'[motion]\nkind = "file"\nfile = "{csv.as_posix()}"\n',
                    encoding="utf-8")
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1
    assert "a budget spec takes no motion file" in err and "compare --motion-file" in err
    # and validity takes none either, as the docs say
    with pytest.raises(SystemExit) as stop:  # an argparse usage error
        main(["validity", "strapdown_ned", "--motion-file", str(csv)])
    assert stop.value.code == 2
    assert "unrecognized arguments: --motion-file" in capsys.readouterr().err
