"""Quantities a source moves only at second order, in the propagation summary.

At the equator the east gyro drift of the north-pointing INS moves the east velocity,
the longitude and the tilt about north in the direct run (0.02 m/s, 0.04′, 0.5″ after
6 h) while the linear model leaves them identically zero: `propagation` counted them
nowhere and printed "direct vs linear 2.00e-05" as if all were judged, where `compare`
marks such rows "no: 2nd order". The summary now names them by `compare`'s own rule.
The reference that they are second order is the physics of the direct run itself: they
grow as the square of the source (4× for 2× the drift), the judged ones in proportion.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from ins_errors.cli import main
from ins_errors.studies.propagation import QUANTITIES, Experiment, run

NAMES = [q[1] for q in QUANTITIES]


@pytest.fixture(scope="module")
def runs():
    base = Experiment(latitude=0.0, duration=7200.0)
    doubled = Experiment(latitude=0.0, duration=7200.0, gyro_drift=2 * base.gyro_drift,
                         accel_bias=2 * base.accel_bias, level_error=2 * base.level_error,
                         azimuth_error=2 * base.azimuth_error)
    return run(base), run(doubled)


@pytest.mark.parametrize("source", ["gyro_drift_east", "gyro_drift_up", "accel_bias_north",
                                    "initial_tilt_east", "initial_azimuth_error"])
def test_the_named_quantities_are_the_ones_that_grow_as_the_square_of_the_source(
        runs, source):
    once, twice = (r.curve(source) for r in runs)
    assert set(once.second_order) == {"dVx", "dN", "Qy"}
    for k, name in enumerate(NAMES):
        size = np.max(np.abs(once.direct[k]))
        if size == 0:
            continue
        growth = np.max(np.abs(twice.direct[k])) / size
        if name in once.second_order:
            assert not np.any(once.linear[k])  # the linear model has none of it
            assert growth == pytest.approx(4.0, rel=1e-2)
        elif np.any(once.linear[k]):
            assert growth == pytest.approx(2.0, rel=1e-2)


def test_direct_vs_linear_judges_only_the_first_order_quantities(runs):
    result = runs[0]
    for curve in result.curves:
        judged = [k for k, name in enumerate(NAMES) if name not in curve.second_order
                  and np.any(curve.linear[k])]
        gaps = [np.max(np.abs(curve.direct[k] - curve.linear[k]))
                / np.max(np.abs(curve.linear[k])) for k in judged]
        assert np.nanmax(curve.agreement("direct", "linear")) == pytest.approx(max(gaps))
    table = result.summary_markdown()
    assert "| moved only at 2nd order (not judged) |" in table
    rows = {line.split(" | ")[0]: line for line in reversed(table.splitlines())
            if line.startswith("| `")}  # the agreement table's row (before the end values)
    assert "| dVx, dN, Qy |" in rows["| `gyro_drift_east`"]
    assert re.search(r"\| (Qy|dVx|dN) \| – \|", rows["| `gyro_drift_north`"])


def test_json_lists_them(capsys):
    assert main(["propagation", "--latitude", "0deg", "--hours", "2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    sources = {s["source"]: s for s in data["sources"]}
    assert sources["gyro_drift_east"]["second_order_only"] == ["dVx", "dN", "Qy"]
    assert sources["gyro_drift_north"]["second_order_only"] == []


def test_the_orthodromic_day_names_its_second_order_states(monkeypatch):
    """The orthodromic day table judged only the states its closed form moves and
    skipped the others silently; at the equator the y gyro drift moves δV_η by 4e-4 m/s
    in an hour at second order. They are named now, by the same rule, and grow as the
    square of the factor."""
    from ins_errors.studies import propagation

    once = propagation.orthodromic_day(0.0, 1800.0)
    monkeypatch.setattr(propagation, "ORTHODROMIC_MAGNITUDES",
                        {k: 2 * v for k, v in propagation.ORTHODROMIC_MAGNITUDES.items()})
    twice = propagation.orthodromic_day(0.0, 1800.0)
    j = once.sources.index("gyro_drift_y")
    assert "delta_V_eta" in once.second_order[j]
    for state in once.second_order[j]:
        k = once.error_states.index(state)
        assert not np.any(once.linear[k, j]) and not np.any(once.analytic[k, j])
        growth = np.max(np.abs(twice.direct[k, j])) / np.max(np.abs(once.direct[k, j]))
        assert growth == pytest.approx(4.0, rel=2e-2)
    row = next(line for line in once.summary_markdown().splitlines()
               if line.startswith("| `gyro_drift_y` |"))
    assert row.endswith(f"| {', '.join(once.second_order[j])} |")
