"""Model parameters from the CLI (``--parameter``) and scenario files (``[parameters]``).

The physics reference is the vertical channel of ``strapdown_ned``: undamped, an initial
height error grows as cosh(t/τ) with τ = √(R/2g) ≈ 9.5 min (a textbook relation, not the
code); with the damping gains of a 300-s loop of damping 0.7 it stays within its start
value and is nearly gone after 20 min.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

from ins_errors.cli import main

G0 = 9.80665
R0 = 6_371_000.0  # mean Earth radius of the textbook relation, m
W0 = 2 * np.pi / 300.0  # natural frequency of the damping loop, rad/s
K1, K2 = 2 * 0.7 * W0, W0**2 + 2 * G0 / R0  # 1/s, 1/s²
RUN = ["compare", "strapdown_ned", "-s", "initial_position_error_D=-1m", "--latitude",
       "45deg", "--duration", "20 min", "--step", "10s", "--no-refined"]


def height_curve(folder) -> tuple[np.ndarray, np.ndarray]:
    with open(folder / "curves.csv", encoding="utf-8", newline="") as handle:
        rows = list(csv.reader(handle))
    body = np.array(rows[1:], dtype=float)
    return body[:, 1], body[:, rows[0].index("delta_height.direct [m]")]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("damping")
    assert main([*RUN, "--out", str(folder / "undamped")]) == 0
    assert main([*RUN, "--out", str(folder / "damped"), "--parameter", f"k_h1={K1!r}/s",
                 "-p", f"k_h2={K2!r} 1/s**2"]) == 0
    return folder


def test_damping_gains_from_the_cli_hold_the_vertical_channel(runs, capsys):
    t, free = height_curve(runs / "undamped")
    t_damped, held = height_curve(runs / "damped")
    np.testing.assert_array_equal(t, t_damped)
    assert t[-1] == 1200.0
    np.testing.assert_allclose(free, np.cosh(t / np.sqrt(R0 / (2 * G0))), rtol=2e-2)
    assert free[-1] > 4.0  # cosh(1200 s / 570 s) ≈ 4.2: it grows
    assert np.all(np.abs(held) <= 1.0 + 1e-9)  # bounded by the start error
    assert abs(held[-1]) < 0.05
    capsys.readouterr()


def test_scenario_parameters_reach_the_run(runs, tmp_path):
    from ins_errors.scenario import load_scenario, run_scenario

    path = tmp_path / "damped.toml"
    path.write_text(f"""model = "strapdown_ned"
[motion]
latitude = "45 deg"
[run]
duration = "20 min"
step = "10 s"
refined = false
[parameters]
k_h1 = "{K1!r} 1/s"
k_h2 = "{K2!r} 1/s**2"
[[case]]
initial_position_error_D = "-1 m"
""", encoding="utf-8")
    scenario = load_scenario(path)
    assert scenario.parameters == {"k_h1": K1, "k_h2": K2}
    [comparison] = run_scenario(scenario).comparisons
    _, held = height_curve(runs / "damped")  # the same run through the CLI
    np.testing.assert_array_equal(comparison.direct["delta_height"], held)


@pytest.mark.parametrize(("table", "message"), [
    ('k_h1 = "-0.01 1/s"', r"\[parameters\]: k_h1 = '-0.01 1/s': a vertical damping gain "
                           "must be zero"),
    ('k_h2 = "nan 1/s**2"', r"\[parameters\]: k_h2: 'nan 1/s\*\*2' is not a finite number"),
    ("k_h1 = 0.01", "has no unit"),
    ('k_h1 = "0.01 m/s"', "do not convert"),
    ('k_h3 = "0.01 1/s"', r"unknown parameter of strapdown_ned 'k_h3'; did you mean"),
    ("k_h1 = true", r"parameters\.k_h1"),
])
def test_bad_scenario_parameters_give_one_line(tmp_path, capsys, table, message):
    path = tmp_path / "bad.toml"
    path.write_text(f'model = "strapdown_ned"\n[parameters]\n{table}\n[[case]]\n'
                    'initial_position_error_D = "-1 m"\n', encoding="utf-8")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("ins-errors: error: bad.toml")
    assert __import__("re").search(message, line), line


@pytest.mark.parametrize(("option", "message"), [
    ("k_h1=-1/s", "--parameter: k_h1 = '-1/s': a vertical damping gain must be zero"),
    ("k_h2=nan/s^2", "--parameter: k_h2: 'nan/s^2' is not a finite number"),
    ("k_h1", "expected NAME=VALUE"),
    ("k_h1=0.01", "has no unit"),
])
def test_bad_parameter_options_give_one_line(capsys, option, message):
    assert main([*RUN, "--parameter", option]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert message in line, line


def test_sweep_points_carry_the_parameters(tmp_path):
    from ins_errors.analysis.sweep import fingerprint, grid
    from ins_errors.scenario import load_scenario

    text = ('model = "strapdown_ned"\n[run]\nduration = "20 min"\nstep = "10 s"\n'
            '[[case]]\ninitial_position_error_D = "-1 m"\n'
            '[sweep]\nlatitude = ["20 deg", "40 deg"]\n')
    plain, damped = tmp_path / "plain.toml", tmp_path / "damped.toml"
    plain.write_text(text, encoding="utf-8")
    damped.write_text(text + '[parameters]\nk_h1 = "0.03 1/s"\n', encoding="utf-8")
    jobs = grid(load_scenario(damped)).jobs
    assert [j.parameters for j in jobs] == [(("k_h1", 0.03),)] * 2
    plain_jobs = grid(load_scenario(plain)).jobs
    assert fingerprint(plain_jobs, {}) != fingerprint(jobs, {})
