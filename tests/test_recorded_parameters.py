"""The model parameters a run set are recorded in its JSON, and budget specs can set them.

Every machine-readable output (``compare --json``, ``budget --json``, ``validity``'s
``results.json``/``--json``, ``run``'s ``results.json``) carries ``parameters``: the
values that differ from the model's defaults, name -> SI value and unit; an empty
mapping when none was set. A spec's ``[parameters]`` table means the same as
``--parameter`` (the same budget to the last bit), and ``--parameter`` overrides it.
"""

from __future__ import annotations

import json
import re

import pytest

from ins_errors.cli import main

COMPARE = ["compare", "strapdown_ned", "-s", "initial_position_error_D=-1m", "--duration",
           "2 min", "--step", "10s", "--no-refined", "--json"]
# 0.0047/s and 1.4e-5/s² in SI; 6400 km = 6.4e6 m (units converted by hand, not by the code)
SET = ["-p", "k_h1=0.0047/s", "-p", "k_h2=1.4e-5 1/s^2"]
RECORDED = {"k_h1": {"value": 0.0047, "unit": "1/s"},
            "k_h2": {"value": 1.4e-5, "unit": "1/s**2"}}


def json_out(capsys, argv) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


WGS84_A = 6378137.0  # m, the WGS-84 semi-major axis (strapdown_ned's default)


def test_compare_json_records_the_parameters(capsys):
    assert json_out(capsys, COMPARE)["parameters"] == {}
    printed = json_out(capsys, [*COMPARE, *SET])
    recorded = printed["parameters"]
    # and every value the run used, the defaults among them
    used = printed["parameters_used"]
    assert used["a"] == {"value": WGS84_A, "unit": "m"}
    assert used["k_h1"]["value"] == pytest.approx(0.0047, rel=1e-12)
    assert recorded.keys() == RECORDED.keys()
    for name, entry in RECORDED.items():
        assert recorded[name]["unit"] == entry["unit"]
        assert recorded[name]["value"] == pytest.approx(entry["value"], rel=1e-12)


def test_validity_json_and_results_record_the_parameters(capsys, tmp_path):
    argv = ["validity", "orthodromic", "-s", "accel_bias_x", "--motion", "static", "--hours",
            "0.1", "--step", "10s", "--engine", "serial", "--json", "--no-progress"]
    assert json_out(capsys, argv)["parameters"] == {}
    out = tmp_path / "validity"
    printed = json_out(capsys, [*argv, "-p", "a=6400 km", "--out", str(out)])
    written = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert printed["parameters"] == written["parameters"] == {
        "a": {"value": 6.4e6, "unit": "m"}}


SCENARIO = """model = "strapdown_ned"
[run]
duration = "2 min"
step = "10 s"
refined = false
{parameters}
[[case]]
initial_position_error_D = "-1 m"
"""


def test_run_results_record_the_parameters(capsys, tmp_path):
    """One run (each writes plots); the empty record is checked through compare,
    validity and budget, which share the helper."""
    path = tmp_path / "damped.toml"
    path.write_text(SCENARIO.format(parameters='[parameters]\nk_h1 = "0.0047 1/s"'),
                    encoding="utf-8")
    out = tmp_path / "damped"
    printed = json_out(capsys, ["run", str(path), "--out", str(out), "--json",
                                "--no-progress"])
    written = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert printed["parameters"] == written["parameters"] == {
        "k_h1": {"value": pytest.approx(0.0047, rel=1e-12), "unit": "1/s"}}
    # every value the run used: the defaults too (a model file's are shown nowhere else)
    used = written["parameters_used"]
    assert used["a"] == {"value": WGS84_A, "unit": "m"}
    assert used["k_h1"]["value"] == pytest.approx(0.0047, rel=1e-12)
    assert used["k_h2"] == {"value": 0.0, "unit": "1/s**2"}
    # and the reader of the report sees it (it changes every curve)
    for name in ("report.md", "report.html"):
        text = (out / name).read_text(encoding="utf-8")
        assert "k_h1</code> = 0.0047 1/s" in text or "`k_h1` = 0.0047 1/s" in text, name
        assert "a</code> = 6378137 m" in text or "`a` = 6378137 m" in text, name
    # a strapdown INS has no platform whose kinematics a run would choose
    assert "| platform |" not in (out / "report.md").read_text(encoding="utf-8")


# --------------------------------------------------------------------------------------
# budget: [parameters] in the spec file
# --------------------------------------------------------------------------------------
def write_spec(tmp_path, parameters: str = "") -> str:
    """A one-item spec on accel_bias_x (the vertical error at 30 min, Schuler-bounded)."""
    from ins_errors.numeric.model import load_model

    lines = ['sigma_level = 2', 'operating_time = "30 min"', 'step = "60 s"', '[motion]',
             'latitude = "50 deg"', '[items.vertical_error]', 'value = "0.1 deg"',
             'times = ["30 min"]']
    lines += [f"[sources.{s.name}]\ninclude = false"
              for s in load_model("orthodromic").sources if s.name != "accel_bias_x"]
    if parameters:
        lines += ["[parameters]", parameters]
    path = tmp_path / "spec.toml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def budget(capsys, spec, *options) -> dict:
    return json_out(capsys, ["budget", "orthodromic", "--spec", spec, "--json", *options])


def test_spec_parameters_give_the_budget_of_the_cli_option(tmp_path, capsys):
    plain = budget(capsys, write_spec(tmp_path))
    assert plain["parameters"] == {}
    cli = budget(capsys, write_spec(tmp_path), "-p", "e2=0", "-p", "a=25484 km")
    from_file = budget(capsys, write_spec(tmp_path, 'e2 = "0 1"\na = "25484 km"'))
    assert from_file == cli  # every number bit-identical, the record included
    assert cli["parameters"] == {"e2": {"value": 0.0, "unit": "1"},
                                 "a": {"value": 25_484_000.0, "unit": "m"}}
    # a Schuler period twice as long allows a larger bias (the physics is in
    # test_model_parameters); here only: the parameters did change the answer
    assert cli["sources"][0]["magnitude"] > 2 * plain["sources"][0]["magnitude"]
    # --parameter overrides the file's value of the same name
    overridden = budget(capsys, write_spec(tmp_path, 'e2 = "0 1"\na = "1000 km"'),
                        "-p", "a=25484km")
    assert overridden == cli


@pytest.mark.parametrize(("table", "message"), [
    ('k_h1 = "0.01 1/s"', r"spec\.toml \[parameters\]: unknown parameter of orthodromic "
                          "'k_h1'"),
    ("a = 6400000", r"spec\.toml \[parameters\]: .*has no unit"),
    ('a = "6400 km/h"', r"spec\.toml \[parameters\]: .*do not convert"),
    ('a = "nan km"', r"spec\.toml \[parameters\]: a: 'nan km' is not a finite number"),
    ("a = true", r"parameters\.a"),
])
def test_bad_spec_parameters_give_one_line(tmp_path, capsys, table, message):
    assert main(["budget", "orthodromic", "--spec", write_spec(tmp_path, table)]) == 2
    captured = capsys.readouterr()
    (line,) = captured.err.strip().splitlines()
    assert not captured.out
    assert re.search(message, line), line


def test_negative_gain_in_a_spec_is_refused(tmp_path, capsys):
    path = tmp_path / "spec.toml"
    path.write_text('[items.vertical_error]\nvalue = "0.1 deg"\n[parameters]\n'
                    'k_h1 = "-0.01 1/s"\n', encoding="utf-8")
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "spec.toml [parameters]: k_h1 = '-0.01 1/s': a vertical damping gain" in line
