"""Validity ratios are judged on every step of the runs, not on a 5-min record.

A probe's externally damped INS (a velocity reference error, damping ratio 0.5 at
k_v = 1.24e-3/s): the map judged its ratio on samples every 300 s, missing the peaks of
the oscillating residual between them, so its 1 % magnitude came out 1.6 % too large.
Reference: the model's real-work equations and its linear error equations (F and G by
central differences of the real work, not the generated matrices) integrated here by
scipy at tight tolerances and read every second.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from ins_errors.analysis import validity
from ins_errors.analysis.validity import run_validity_task, validity_tasks
from ins_errors.cli import main
from ins_errors.numeric.model import load_model

MODEL = Path(__file__).resolve().parent / "models" / "damped_ins.py"
SOURCE = "ref_velocity_error_north"
HOURS, STEP, K_V = 6.0, 10.0, 1.24e-3
QUANTITY_ROW = {"delta_v_E": 0, "delta_v_N": 1, "delta_latitude": 2, "delta_longitude": 3,
                "alpha_E": 4, "alpha_N": 5, "alpha_U": 6}
"""Error state of each error quantity (the model's outputs are its states)."""


@pytest.fixture(scope="module")
def damped():
    model = load_model(str(MODEL))
    p = model.parameter_vector(k_v=K_V)
    c = model.initial_condition_vector(latitude=np.radians(50.0), longitude=np.radians(30.0))
    u = model.input_vector()  # at rest: no horizontal specific force
    x = np.asarray(model.initial_state(c, u, p), dtype=float)
    return model, p, x, u


def _own_ratios(damped, magnitude: float) -> dict[str, float]:
    """max |linear − direct| / max |direct| of every error quantity, read every 1 s of
    scipy's own integration of the real work and of ẋe = F xe + G w on the static base."""
    model, p, x, u = damped
    w = model.source_vector(**{SOURCE: magnitude})
    n, ne = len(model.states), len(model.error_states)
    xr0 = np.concatenate([x, np.zeros(ne - n)])
    h = np.array([1e-4, 1e-4, 1e-9, 1e-9, 1e-8, 1e-8, 1e-8])
    F = np.column_stack([(model.real_rhs(xr0 + hj * e, x, u, model.source_vector(), p)
                          - model.real_rhs(xr0 - hj * e, x, u, model.source_vector(), p))
                         / (2 * hj) for hj, e in zip(h, np.eye(ne), strict=True)])
    Gw = (model.real_rhs(xr0, x, u, w * 1e-3, p) - model.real_rhs(xr0, x, u, -w * 1e-3, p)
          ) / 2e-3
    assert not np.any(model.ideal_rhs(x, u, p))  # at rest the truth stays x

    def rates(_, z):
        xr, xe = z[:ne], z[ne:]
        return np.concatenate([model.real_rhs(xr, x, u, w, p), F @ xe + Gw])

    t = np.arange(0.0, HOURS * 3600.0 + 0.5, 1.0)
    run = solve_ivp(rates, (0.0, t[-1]), np.concatenate([xr0, np.zeros(ne)]),
                    method="DOP853", t_eval=t, rtol=1e-12, atol=1e-16)
    assert run.success
    direct = run.y[:ne] - xr0[:, None]
    linear = run.y[ne:]
    return {name: float(np.abs(linear[k] - direct[k]).max() / np.abs(direct[k]).max())
            for name, k in QUANTITY_ROW.items()}


@pytest.fixture(scope="module")
def sweep(damped):
    model = damped[0]
    (task,) = validity_tasks(model, ["static"], [SOURCE], hours=HOURS, step=STEP,
                             factors=(1.0, 30.0, 100.0, 300.0), parameters={"k_v": K_V})
    return task, run_validity_task(task)


def test_the_ratios_are_the_largest_differences_over_the_whole_run(damped, sweep):
    _, result = sweep
    assert result.status == "ok"
    for magnitude, ratio in zip(result.magnitudes, result.linear_ratio, strict=True):
        own = _own_ratios(damped, magnitude)[result.quantity]
        # a 5-min record put them 1.6 % low (7.348e-5 against 7.4655e-5 at 0.5 m/s)
        assert ratio == pytest.approx(own, rel=2e-3), (magnitude, ratio, own)
    assert result.judged_every_s == STEP


def test_the_one_percent_magnitude_gives_one_percent_in_an_own_integration(damped, sweep):
    _, result = sweep
    own = _own_ratios(damped, result.magnitude_1pct)[result.quantity]
    # the 5-min record's magnitude, 68.1 m/s, gives 1.015 % here
    assert own == pytest.approx(0.01, rel=4e-3), (result.magnitude_1pct, own)


def test_a_run_too_long_to_keep_whole_is_judged_on_a_stride_and_says_so(monkeypatch, tmp_path,
                                                                         capsys):
    """Beyond the memory a sweep may keep, the ratios come from every k-th step, k the
    smallest that fits and divides the run, and the map says so under its title and in
    the JSON."""
    monkeypatch.setattr(validity, "MAX_JUDGED_VALUES", 20_000)
    args = ["validity", str(MODEL), "--source", SOURCE, "--motion", "static", "--hours", "1",
            "--step", "10s", "-p", "k_v=1.24e-3/s", "--engine", "serial", "--no-progress"]
    assert main(args) == 0
    said = capsys.readouterr().out
    # 361 samples × 8 magnitudes × (4 + 3·7 + 3·7) values: 6.65 times the limit; 8 steps
    # is the first stride from 7 that divides the 360 steps
    assert "Ratios judged on samples every 80 s, not at every step of 10 s" in said, said
    assert main([*args, "--json"]) == 0
    (source,) = json.loads(capsys.readouterr().out)["sources"]
    assert source["judged_every_s"] == 80.0
    monkeypatch.undo()
    assert main([*args, "--json"]) == 0
    (whole,) = json.loads(capsys.readouterr().out)["sources"]
    assert whole["judged_every_s"] == 10.0



@pytest.mark.parametrize("n_steps", [7919, 2 * 7919])
def test_a_run_of_awkward_length_is_not_kept_whole_beyond_the_allowance(monkeypatch, n_steps):
    """A run whose step count has no divisor near the least stride that fits (7919 is
    prime): the fallback went down to the largest divisor below, 1 or 2 here, and kept
    (nearly) every step, 300 times the allowance; a record must divide the run, so the
    stride is now the next divisor up, however coarse (the map says how coarse)."""
    monkeypatch.setattr(validity, "MAX_JUDGED_VALUES", 20_000)  # 360 steps need 8 (above)
    stride = validity.judged_stride(load_model(MODEL), n_steps, 8)
    assert n_steps % stride == 0 and stride > 2
