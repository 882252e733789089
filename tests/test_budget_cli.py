"""The budget command's edge cases: undefined ratios, option checks, messages."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import main

NO_TILT = """
    sigma_level = 1
    operating_time = "1 h"
    [motion]
    kind = "static"
    latitude = "45 deg"
    [items.vertical_error]
    value = "30 arcsec"
    every = "10 min"
    from = "0 h"
    [sources.initial_tilt_x]
    include = false
    [sources.initial_tilt_y]
    include = false
"""


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_monte_carlo_row_with_zero_covariance(tmp_path, capsys):
    """Without initial tilts nothing tilts the platform at t = 0: the covariance and the
    runs both give 0 there, the ratio is undefined and said to be, not a crash."""
    spec = str(write(tmp_path, NO_TILT))
    argv = ["budget", "orthodromic", "--spec", spec, "--monte-carlo", "2", "--mc-step",
            "1 s", "--mc-duration", "10 min", "--engine", "serial"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("vertical_error at 0 h"))
    assert row.split()[-1] == "–"
    assert "Monte Carlo / covariance is undefined" in out
    later = next(line for line in out.splitlines()
                 if line.startswith("vertical_error at 10 min"))
    assert 0.2 < float(later.split()[-1]) < 5    # 2 runs: a sampling error of 50 %
    assert main([*argv, "--json"]) == 0
    text = capsys.readouterr().out
    rows = json.loads(text)["monte_carlo"]["rows"]
    # the same seeded runs give the same JSON, byte for byte: no wall-clock time in it
    assert "seconds" not in json.loads(text)["monte_carlo"]
    assert main([*argv, "--json"]) == 0
    assert capsys.readouterr().out == text
    assert rows[0]["covariance"] == 0.0 and rows[0]["monte_carlo"] == 0.0
    assert rows[0]["ratio"] is None and "undefined" in rows[0]["note"]
    assert rows[1]["ratio"] > 0 and "note" not in rows[1]


def test_monte_carlo_runs_default_to_a_spec_shorter_than_an_hour(tmp_path, capsys):
    """The runs' default length (1 h) was refused for a 20-min spec ('at most the
    operating time (0.333333 h)'): they now last the operating time, and say so."""
    spec = str(write(tmp_path, NO_TILT.replace('"1 h"', '"20 min"')))
    assert main(["budget", "orthodromic", "--spec", spec, "--monte-carlo", "2", "--mc-step",
                 "1 s", "--engine", "serial"]) == 0
    out = capsys.readouterr().out
    assert "Direct Monte Carlo: 2 runs of 20 min at 1 s" in out
    assert any(line.startswith("vertical_error at 20 min") for line in out.splitlines())
    assert main(["budget", "orthodromic", "--spec", spec, "--monte-carlo", "2",
                 "--mc-duration", "1 h"]) == 2  # asked for explicitly: still refused
    assert "at most the operating time (20 min)" in capsys.readouterr().err


def test_spec_latitude_at_or_beyond_a_pole_is_refused(tmp_path, capsys):
    """As the motions of scenarios and compare refuse them: |φ| >= 90 deg, one line."""
    for latitude in ("100 deg", "-95 deg", "90 deg", "1.6 rad"):
        spec = write(tmp_path, NO_TILT.replace('"45 deg"', f'"{latitude}"'))
        assert main(["budget", "orthodromic", "--spec", str(spec)]) == 2
        captured = capsys.readouterr()
        assert not captured.out
        assert captured.err.count("\n") == 1
        assert f"motion.latitude '{latitude}' is at or beyond a pole" in captured.err
    spec = write(tmp_path, NO_TILT.replace('"45 deg"', '"89.9 deg"'))
    assert main(["budget", "orthodromic", "--spec", str(spec), "--json"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize("options, words", [
    (["--monte-carlo", "0"], "--monte-carlo needs at least 2 runs, got 0"),
    (["--monte-carlo", "-3"], "--monte-carlo needs at least 2 runs, got -3"),
    (["--at", ","], "--at needs times with units"),
    (["--at", " "], "--at needs times with units"),
    (["--mc-step", "1s"], "--mc-step applies to the Monte Carlo runs: add --monte-carlo N"),
    (["--mc-duration", "10 min"], "--mc-duration applies to the Monte Carlo runs"),
    (["--seed", "3"], "--seed applies to the Monte Carlo runs"),
    (["--engine", "serial"], "--engine applies to the Monte Carlo runs"),
    (["--workers", "2"], "--workers applies to the Monte Carlo runs"),
    (["--monte-carlo", "2", "--workers", "0"], "--workers must be at least 1, got 0"),
])
def test_options_that_do_nothing_are_refused(options, words, capsys, monkeypatch):
    """One line, exit 2, before any propagation."""
    from ins_errors.analysis import budget as bd

    monkeypatch.setattr(bd, "unit_budget", lambda *a, **k: pytest.fail("computed"))
    assert main(["budget", "orthodromic", *options]) == 2
    captured = capsys.readouterr()
    assert not captured.out and captured.err.count("\n") == 1
    assert words in captured.err


def test_at_ignores_a_trailing_comma(capsys):
    assert main(["budget", "orthodromic", "--at", "1 h,", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["contributions"]["times_h"] == [1.0]


STRAPDOWN = """
    sigma_level = 1
    operating_time = "1 h"
    [motion]
    kind = "static"
    latitude = "45 deg"
    [items.position_error]
    value = "1 nmi/h"
    [items.ground_speed_error]
    value = "0.8 m/s"
    every = "10 min"
    [parameters]
    k_h1 = "0.0047 1/s"
    k_h2 = "5.5e-6 1/s**2"
"""


def test_sources_no_row_depends_on_take_no_share(tmp_path, capsys):
    """On a level static base a gyro misalignment x→y sees no rate about y: nothing in
    the spec depends on it, so it is "not limited" like the sources the motion barely
    excites, and takes no share: every limited source uses exactly its 1/n of its
    binding row (n = the limited sources), recomputed by a fresh propagation."""
    from ins_errors.analysis import budget as bd
    from ins_errors.numeric.model import load_model
    from ins_errors.specs import load_spec, spec_parameters

    path = write(tmp_path, STRAPDOWN)
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines()
                if x.startswith("gyro_misalignment_xy "))
    assert line.split()[1:] == ["unconstrained", "not", "limited", "on", "this", "motion"]
    model, spec = load_model("strapdown_ned"), load_spec(path)
    p = model.parameter_vector(**spec_parameters(spec, model))
    allocation = bd.allocate(bd.unit_budget(model, spec, p=p))
    names = [s.name for s in allocation.budget.sources]
    j = names.index("gyro_misalignment_xy")
    assert not np.any(allocation.budget.unit_variances[:, j])
    assert allocation.binding_row(j) is None
    limited = np.flatnonzero(np.isfinite(allocation.sigma))
    sigma = {names[i]: float(allocation.sigma[i]) for i in limited}
    evaluation = bd.evaluate(model, spec, sigma, p=p)
    allowed = allocation.budget.allowed_variances
    for i in limited:
        r = allocation.binding[i]
        assert evaluation.contributions[r, i] == pytest.approx(allowed[r] / limited.size,
                                                               rel=1e-9)


@pytest.mark.parametrize("change, words", [
    (("sigma_level = 1", "sigma_level = 0"), "sigma_level must be a number > 0, got 0"),
    (("sigma_level = 1", 'sigma_level = "2"'), "sigma_level must be a number > 0, got '2'"),
    (("include = false\n", "include = false\n    weight = 0\n", 1),
     "sources.initial_tilt_x.weight must be a number > 0, got 0 (include = false"),
    # inf was taken: NaN shares, two numpy warnings, and the source called unconstrained
    (("include = false\n", "include = false\n    weight = inf\n", 1),
     "sources.initial_tilt_x.weight must be a number > 0, got inf (include = false"),
    (("sigma_level = 1", "sigma_level = inf"), "sigma_level must be a number > 0, got inf"),
    (('latitude = "45 deg"', "latitude = [45]"),
     "motion.latitude must be a value with its unit (e.g. '8 h', '0.1 deg'), got [45]"),
    (('every = "10 min"', 'every = "10 min"\n    until = "65 min"'),
     "items.vertical_error.until = '65 min' is after the operating time '1 h'"),
])
def test_spec_messages_use_the_files_words(tmp_path, capsys, change, words):
    """One line in the spec's own key names: no pydantic member names, and the key
    that is wrong (until), not a check time derived from it."""
    spec = write(tmp_path, NO_TILT.replace(*change))
    assert main(["budget", "orthodromic", "--spec", str(spec)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err
    assert "constrained" not in err and ".str" not in err and "check time" not in err


ROOT = Path(__file__).resolve().parent.parent
FIXED_GYRO = ROOT / "examples" / "specs" / "gyro_drift_fixed.toml"


def test_spec_exceeded_by_fixed_sources_exits_1_with_the_rows(tmp_path, capsys):
    """A fixed gyro drift that alone breaks the spec is an answer ("exceeded", exit 1,
    the rows with their ratios), not bad input (exit 2, nothing on standard output)."""
    assert main(["budget", "orthodromic", "--spec", str(FIXED_GYRO), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["exceeded"] is True
    assert [s["name"] for s in data["sources"]] == ["gyro_drift_x"]
    assert "gyro_drift_y" in data["free_sources"]
    for row in data["rows"]:
        assert row["ratio"] == pytest.approx(row["value"] / row["limit"])
        assert row["exceeded"] == (row["ratio"] >= 1)
    position = [r for r in data["rows"] if r["item"] == "position_error"]
    assert all(r["exceeded"] for r in position)
    # the covariance of one constant source is linear in its σ: twice the drift, twice
    # every row's value
    doubled = write(tmp_path, FIXED_GYRO.read_text().replace('"0.5 deg/h"', '"1.0 deg/h"'))
    assert main(["budget", "orthodromic", "--spec", str(doubled), "--json"]) == 1
    again = json.loads(capsys.readouterr().out)
    for one, two in zip(data["rows"], again["rows"], strict=True):
        assert two["value"] == pytest.approx(2 * one["value"], rel=1e-9)
    # the text says which items are exceeded and by how much (the worst ratio)
    assert main(["budget", "orthodromic", "--spec", str(FIXED_GYRO)]) == 1
    text = capsys.readouterr().out
    assert "SPEC EXCEEDED" in text
    for item in ("position_error", "ground_speed_error"):
        worst = max(r["ratio"] for r in data["rows"] if r["item"] == item)
        [line] = [t for t in text.splitlines() if t.startswith(item)]
        assert f"{worst:.3f}" in line and " of " in line


def test_allocated_budget_reports_not_exceeded(capsys):
    assert main(["budget", "orthodromic", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["exceeded"] is False
    assert not any(r["exceeded"] for r in data["rows"])
    assert max(r["ratio"] for r in data["rows"]) <= 1 + 1e-9


def test_malformed_spec_still_exits_2_without_output(capsys):
    spec = ROOT / "examples" / "specs" / "malformed.toml"
    assert main(["budget", "orthodromic", "--spec", str(spec), "--json"]) == 2
    captured = capsys.readouterr()
    assert not captured.out and captured.err.count("\n") == 1


GREAT_CIRCLE = """
    sigma_level = 2
    operating_time = "1 h"
    step = "60 s"
    [motion]
    kind = "great_circle"
    speed = "250 m/s"
    latitude = "50 deg"
    longitude = "30 deg"
    heading = "60 deg"
    [items.ground_speed_error]
    value = "4.0 m/s"
    every = "5 min"
    until = "1 h"
    [items.vertical_error]
    value = "0.1 deg"
    every = "5 min"
    from = "0 h"
"""


def test_moving_base_monte_carlo_in_a_process_pool_equals_one_process(tmp_path, capsys):
    """A great-circle trajectory carried its profile's commands as a closure, which the
    process pool (the engine without Dask) cannot send to a worker: more runs than one
    task (50) gave a 44-line traceback and exit 1, the "spec exceeded" status. The
    pool's runs now give the JSON of the same runs in this process, byte for byte."""
    spec = str(write(tmp_path, GREAT_CIRCLE))
    argv = ["budget", "orthodromic", "--spec", spec, "--monte-carlo", "60", "--mc-duration",
            "10 min", "--mc-step", "1 s", "--json", "--workers", "2"]
    assert main([*argv, "--engine", "serial"]) == 0
    serial = capsys.readouterr().out
    assert main([*argv, "--engine", "pool"]) == 0
    pool = capsys.readouterr().out
    assert pool == serial
    rows = json.loads(pool)["monte_carlo"]["rows"]
    # the rows within 10 min: ground speed and vertical at 0, 5 and 10 min (0 h, where
    # the errors are the initial errors, is checked too)
    assert json.loads(pool)["monte_carlo"]["runs"] == 60 and len(rows) == 6


def test_an_undamped_vertical_channel_is_warned_of_with_its_textbook_e_folding_time(
        tmp_path, capsys):
    """strapdown_ned's default (k_h1 = k_h2 = 0) leaves the vertical channel undamped: it
    grows as e^(t/√(R/2g)), e^50 over 8 h, and the allocation silently allowed gyro
    biases of 1e-19 deg/h. The budget now says so in one line (stderr, and in --json),
    with the textbook e-folding time √(R/2g), the command that names the mode and the
    damping gains; with those gains, and on a platform model, it says nothing."""
    import math
    import re

    # 2 h: 12.6 e-foldings, warned of; over 8 h (50) the budget is refused instead
    # (test_budget_growth.py)
    spec = str(write(tmp_path, STRAPDOWN.replace('"1 h"', '"2 h"').split("[parameters]")[0]))
    assert main(["budget", "strapdown_ned", "--spec", spec, "--json"]) == 0
    captured = capsys.readouterr()
    [line] = [x for x in captured.err.splitlines() if "grow exponentially" in x]
    assert line.startswith("ins-errors: warning: ") and captured.err.count("\n") == 1
    assert json.loads(captured.out)["warnings"] == [line.removeprefix("ins-errors: warning: ")]
    minutes = float(re.search(r"×e every ([\d.]+) min", line).group(1))
    # √(R/2g) at 45°: WGS-84 normal gravity (Somigliana) and the Gaussian mean radius
    a, e2, s2 = 6_378_137.0, 0.00669437999014, math.sin(math.radians(45.0)) ** 2
    g = 9.7803253359 * (1 + 0.00193185265241 * s2) / math.sqrt(1 - e2 * s2)
    radius = math.sqrt(a * (1 - e2) / (1 - e2 * s2) ** 1.5 * a / math.sqrt(1 - e2 * s2))
    assert minutes == pytest.approx(math.sqrt(radius / (2 * g)) / 60.0, rel=2e-3)
    assert "over the 2 h operating time" in line
    assert "`ins-errors modes strapdown_ned`" in line
    gains = re.search(r"`(-p k_h1=\S+ -p k_h2=\S+)`", line).group(1).split()
    assert main(["budget", "strapdown_ned", "--spec", spec, *gains, "--json"]) == 0
    captured = capsys.readouterr()
    assert "grow" not in captured.err   # (the damped channel's initial height error is
    # still bound only through the horizontal items: vertical_channel_note's line)
    assert not any("grow" in w for w in json.loads(captured.out)["warnings"])
    assert main(["budget", "orthodromic"]) == 0
    assert "grow" not in capsys.readouterr().err


SCHULER = """
    sigma_level = 1
    operating_time = "2 h"
    step = "60 s"
    [motion]
    kind = "static"
    latitude = "50 deg"
    [items.vertical_error]
    value = "30 arcsec"
    every = "30 min"
    [items.ground_speed_error]
    value = "1 m/s"
    every = "30 min"
"""


def _monte_carlo(spec: str, runs: int, step: str, capsys) -> tuple[dict, str]:
    assert main(["budget", "orthodromic", "--spec", spec, "--monte-carlo", str(runs),
                 "--mc-duration", "2 h", "--mc-step", step, "--engine", "serial",
                 "--json"]) == 0
    captured = capsys.readouterr()
    return json.loads(captured.out), captured.err


def test_monte_carlo_states_its_integration_error_by_step_doubling(tmp_path, capsys):
    """The rectangle method lets the Schuler oscillation grow by e^(ω²τt/2), 5 % in 2 h
    at τ = 10 s; only the sampling error was stated. The estimate (the first 16 runs
    again at 2τ) predicts what a ten times finer run of the same draws changes, within
    a factor 2 on every row it moves by more than 1 %."""
    spec = str(write(tmp_path, SCHULER))
    coarse, _ = _monte_carlo(spec, 16, "10 s", capsys)
    fine, _ = _monte_carlo(spec, 16, "1 s", capsys)
    estimate = coarse["monte_carlo"]["integration_error"]
    assert estimate["runs"] == 16 and estimate["step_s"] == 20.0
    checked = 0
    for mine, finer in zip(coarse["monte_carlo"]["rows"], fine["monte_carlo"]["rows"],
                           strict=True):
        change = mine["monte_carlo"] / finer["monte_carlo"] - 1   # same draws, same seed
        predicted = mine["integration_error"] - finer["integration_error"]
        if abs(change) > 0.01:
            assert 0.5 < predicted / change < 2, mine["row"]
            checked += 1
    assert checked >= 4
    assert estimate["largest"] == max(abs(r["integration_error"])
                                      for r in coarse["monte_carlo"]["rows"])


def test_an_integration_error_above_the_sampling_error_names_a_smaller_step(tmp_path,
                                                                           capsys):
    """400 runs sample to ±3.5 %; at τ = 10 s the scheme's bias is larger, which is
    said in one line naming a step that divides the analysis step, and at that step the
    estimate is below the sampling error and nothing is said."""
    import re

    spec = str(write(tmp_path, SCHULER))
    data, err = _monte_carlo(spec, 400, "10 s", capsys)
    mc = data["monte_carlo"]
    assert mc["integration_error"]["largest"] > mc["relative_sampling_error"]
    assert mc["integration_error"]["extra_steps"] == pytest.approx(16 / 400 / 2)
    [line] = [x for x in err.splitlines() if "integration error" in x]
    assert line.startswith("ins-errors: warning: ") and line[21:] in data["warnings"]
    step = re.search(r'--mc-step "(\S+) s"', line).group(1)
    assert float(step) < 10 and 60 / float(step) == round(60 / float(step))
    data, err = _monte_carlo(spec, 400, f"{step} s", capsys)
    mc = data["monte_carlo"]
    assert mc["integration_error"]["largest"] < mc["relative_sampling_error"]
    assert "integration error" not in err and data["warnings"] == []


def test_densities_are_shown_as_they_are_written(tmp_path, capsys):
    """Noise densities read "0.002 deg/h**0.5" and "2 ug*s**0.5"; they are now quoted per
    √h and per √Hz, values unchanged (0.002 deg/√h = 0.002° per 60 √s, 2 µg/√Hz = 2 µg·√s)."""
    text = NO_TILT + """
    [sources.gyro_drift_x]
    kind = "white"
    fixed = "0.002 deg/sqrt(h)"
    [sources.accel_bias_x]
    kind = "white"
    fixed = "2 ug*s**0.5"
    """
    assert main(["budget", "orthodromic", "--spec", str(write(tmp_path, text)), "--json"]) == 0
    sources = {s["name"]: s for s in json.loads(capsys.readouterr().out)["sources"]}
    assert sources["gyro_drift_x"]["display"] == "0.002 deg/√h"
    assert sources["accel_bias_x"]["display"] == "2 ug/√Hz"
    assert sources["gyro_drift_x"]["magnitude"] == pytest.approx(0.002 * np.pi / 180 / 60,
                                                                 rel=1e-12)
    assert sources["accel_bias_x"]["magnitude"] == pytest.approx(2e-6 * 9.80665, rel=1e-12)


def test_monte_carlo_of_noise_sources_is_refused_before_the_covariance(tmp_path, capsys,
                                                                        monkeypatch):
    """Direct runs take random constants only: a spec with a white or Gauss-Markov
    source was refused only after the whole covariance had been computed. Now before,
    in one line naming the sources, and --help says so."""
    from ins_errors.analysis import budget as bd

    text = NO_TILT + """
    [sources.gyro_drift_z]
    kind = "white"
    [sources.accel_bias_x]
    kind = "markov"
    tau = "30 min"
    """
    monkeypatch.setattr(bd, "unit_budget", lambda *a, **k: pytest.fail("computed"))
    assert main(["budget", "orthodromic", "--spec", str(write(tmp_path, text)),
                 "--monte-carlo", "10"]) == 2
    captured = capsys.readouterr()
    assert not captured.out and captured.err.count("\n") == 1
    assert "random constants only" in captured.err
    assert "gyro_drift_z, accel_bias_x" in captured.err
    with pytest.raises(SystemExit):
        main(["budget", "--help"])
    assert "random constants only" in " ".join(capsys.readouterr().out.split())


def test_times_of_the_contribution_tables_read_as_times(capsys):
    """'at 0.0166667 h' and 'time 0.00833333 h' were hours with six digits."""
    assert main(["budget", "orthodromic", "--at", "1 min, 90 min"]) == 0
    out = capsys.readouterr().out
    assert "Contributions to the navigation errors at 1 min (" in out
    assert "Contributions to the navigation errors at 1 h 30 min (" in out
    assert main(["budget", "orthodromic", "--at", "30 s"]) == 2
    assert "time 30 s is not on the spec's 60 s analysis grid" in capsys.readouterr().err


def test_heading_at_rest_is_refused_by_a_spec_as_by_a_scenario(tmp_path, capsys,
                                                               monkeypatch):
    """A spec's motion.heading at rest for a model without a heading output was taken
    silently where a scenario file refuses it: now the same line, exit 2, before any
    covariance; a heading in motion, or none at rest, is still taken."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.scenario import load_scenario

    at_rest = NO_TILT.split("    [sources")[0]  # no source options: any model
    heading = at_rest.replace('kind = "static"', 'kind = "static"\n    heading = "30 deg"')
    spec = write(tmp_path, heading, "s.toml")
    scenario = tmp_path / "scenario" / "s.toml"
    scenario.parent.mkdir()
    scenario.write_text('model = "north_pointing"\n[motion]\nkind = "static"\n'
                        'heading = "30 deg"\n[run]\nduration = "10 min"\nstep = "10 s"\n'
                        '[[case]]\ngyro_drift_east = "0.01 deg/h"\n')
    monkeypatch.chdir(scenario.parent)  # each file named as typed: s.toml
    with pytest.raises(InsErrorsError) as info:
        load_scenario("s.toml")
    monkeypatch.chdir(tmp_path)
    assert main(["budget", "north_pointing", "--spec", spec.name]) == 2
    captured = capsys.readouterr()
    assert not captured.out
    (line,) = captured.err.strip().splitlines()
    assert line.split("error: ", 1)[1] == str(info.value)
    from ins_errors.analysis import budget as bd
    from ins_errors.numeric.model import load_model
    from ins_errors.specs import load_spec

    model = load_model("north_pointing")
    bd.spec_profile(model, load_spec(write(tmp_path, at_rest, "none.toml")))
    moving = heading.replace('kind = "static"', 'kind = "great_circle"\n    speed = "200 m/s"')
    bd.spec_profile(model, load_spec(write(tmp_path, moving, "moving.toml")))


AT_REST = NO_TILT.split("    [sources")[0]   # no source options: any model
MOVING = (AT_REST.replace('kind = "static"\n    latitude = "45 deg"',
                          'kind = "great_circle"\n    speed = "100 m/s"')
          + '    [items.ground_speed_error]\n    value = "1 m/s"\n')


@pytest.mark.parametrize("text, model, words", [
    # a heading at rest for a model without a heading output
    (AT_REST.replace('kind = "static"', 'kind = "static"\n    heading = "30 deg"'),
     "north_pointing", "{path} [motion] heading: model 'north_pointing' has no heading"),
    # a source the model does not have
    (NO_TILT + "    [sources.no_such_gyro]\n    weight = 2\n", "orthodromic",
     "unknown error source of orthodromic in {path} 'no_such_gyro'"),
    # a fixed magnitude in the wrong unit
    (NO_TILT.replace("include = false\n", 'fixed = "3 m"\n', 1), "orthodromic",
     "{path}: sources.initial_tilt_x.fixed"),
    # a moving base for a model that is steered by a heading it has no output for
    (MOVING, "tests/models/tangent_plane_ins.py", "set kind = \"static\" in {path}'s [motion]"),
])
def test_a_specs_later_refusals_name_the_file_as_typed(tmp_path, capsys, monkeypatch,
                                                      text, model, words):
    """Refusals of a spec that come after it is read (bound to the model, its motion
    flown) named it by its bare file name (802m.toml for sub/802m.toml, the built-in
    spec's name too), unlike the refusals of its reading: now by the path the user typed,
    as a scenario's are."""
    if model.endswith(".py"):
        model = str(Path(__file__).resolve().parent.parent / model)
        # a model file's first use in a cache says so on stderr ("deriving model file
        # ..."): derived here first, so that the one line read below is the refusal
        from ins_errors.numeric.model import load_model

        load_model(model)
        capsys.readouterr()
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    write(tmp_path / "sub", text, "802m.toml")
    assert main(["budget", model, "--spec", "sub/802m.toml"]) == 2
    captured = capsys.readouterr()
    assert not captured.out
    (line,) = captured.err.strip().splitlines()
    message = line.split("error: ", 1)[1]
    assert words.format(path="sub/802m.toml") in message, message
    assert "802m.toml" not in message.replace("sub/802m.toml", "")


def test_the_built_in_spec_is_named_apart_from_a_file_of_its_name(tmp_path, monkeypatch):
    """The built-in spec reads 'the built-in 802m spec' in a refusal, a user's copy of it
    its own path as typed (both were '802m.toml')."""
    from ins_errors.specs import default_spec_path, load_spec, spec_label

    assert spec_label(load_spec(default_spec_path())) == "the built-in 802m spec"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "802m.toml").write_text(default_spec_path().read_text())
    assert spec_label(load_spec("802m.toml")) == "802m.toml"
    assert spec_label(load_spec("./802m.toml")) == "./802m.toml"


MARKOV_SPEC = """
    sigma_level = 2
    operating_time = "1 h"
    step = "{step}"
    [motion]
    kind = "static"
    latitude = "50 deg"
    [items.position_error]
    value = "3.7 km/h"
    times = ["1 h"]
    [sources.gyro_drift_x]
    kind = "{kind}"
    {tau}
"""


def _gyro_x_allowance(tmp_path, capsys, step: str, kind: str, tau: str = "") -> float:
    """gyro_drift_x's allowance (SI, 1σ: a Markov process's steady-state σ, or a white
    density, which is read and reported as it is whatever the spec's level) of the spec
    above, run with warnings as errors."""
    spec = write(tmp_path, MARKOV_SPEC.format(step=step, kind=kind, tau=tau),
                 f"{kind}_{step}_{len(tau)}.toml".replace(" ", ""))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")        # the overflow of a short τ must not come back
        assert main(["budget", "orthodromic", "--spec", str(spec), "--json"]) == 0
    sources = json.loads(capsys.readouterr().out)["sources"]
    return next(s for s in sources if s["name"] == "gyro_drift_x")["magnitude_1sigma"]


def test_markov_source_far_shorter_than_the_step_is_allocated_as_its_white_equivalent(
        tmp_path, capsys):
    """A Gauss–Markov gyro drift of τ = 1 s on the 60-s grid gets the allowance a 1-s grid
    gives it (60 s at τ = 1 s was once 'not limited on this motion' after an overflow),
    and one of τ = 1e-9 s acts as white noise of density σ·√(2τ): its allowance times
    √(2τ) is the allowance of a white gyro_drift_x (exit 1 and a traceback once)."""
    tau_1s = 'tau = "1 s"'
    at_60 = _gyro_x_allowance(tmp_path, capsys, "60 s", "markov", tau_1s)
    at_1 = _gyro_x_allowance(tmp_path, capsys, "1 s", "markov", tau_1s)
    assert np.isfinite(at_60) and at_60 == pytest.approx(at_1, rel=1e-9)
    tau = 1e-9
    markov = _gyro_x_allowance(tmp_path, capsys, "60 s", "markov", f'tau = "{tau} s"')
    white = _gyro_x_allowance(tmp_path, capsys, "60 s", "white")
    assert markov * np.sqrt(2 * tau) == pytest.approx(white, rel=1e-6)


def test_markov_source_white_within_rounding_is_refused_in_one_line(tmp_path, capsys):
    spec = write(tmp_path, MARKOV_SPEC.format(step="60 s", kind="markov",
                                              tau='tau = "1e-300 s"'))
    assert main(["budget", "orthodromic", "--spec", str(spec)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip()
    assert "\n" not in err and "sources.gyro_drift_x.tau" in err
    assert "kind = 'white' with density σ·√(2τ)" in err


def test_monte_carlo_that_ends_before_the_first_row_is_refused(tmp_path, capsys):
    """Runs of 60 s against a spec whose only row is at 1 h checked nothing: they printed
    an empty 'row covariance Monte Carlo ratio' table and a stray '(0.1 s)', exit 0."""
    spec = write(tmp_path, MARKOV_SPEC.format(step="60 s", kind="constant", tau=""))
    argv = ["budget", "orthodromic", "--spec", str(spec), "--monte-carlo", "2",
            "--mc-step", "1 s", "--mc-duration", "60 s"]
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip()
    assert "\n" not in err
    assert "--mc-duration '60 s' ends before the spec's first row (position_error at 1 h)" \
        in err and "give at least 1 h" in err


@pytest.mark.parametrize("option, value", [("--mc-step", "0 s"), ("--mc-duration", "-1 min")])
def test_a_monte_carlo_option_of_zero_or_less_is_named_alone(capsys, option, value):
    """Both options were named whichever was wrong ("--mc-duration and --mc-step must
    be > 0"); the one given is named, with its value."""
    assert main(["budget", "orthodromic", "--monte-carlo", "2", option, value]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"ins-errors: error: {option} must be positive, got {value!r}"
