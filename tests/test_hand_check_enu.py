"""An ENU strapdown model file checked in its own error states (``delta_v_U``, ...).

A model whose vertical velocity state is ``v_U`` (up) has the initial condition ``v_U0``
(the flight generator and the naming rules ask for it). The checker's reference motions
set it as they set ``v_D0``, with the sign of the axis: a vehicle climbing at 10 m/s has
``v_U = +10 m/s`` (``v_D = −10 m/s``), so its height grows at 10 m/s.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker.reference import reference_points
from ins_errors.cli import main
from ins_errors.model_lookup import definition_of, resolve

MODEL = Path(__file__).resolve().parent / "models" / "enu_strapdown.py"


@pytest.fixture(scope="module")
def definition():
    return definition_of(resolve(str(MODEL)))


def test_reference_motions_set_the_up_velocity(definition):
    motions = reference_points(definition)
    assert [p.label for p in motions.points] == [
        "static base", "cruise 0 km", "cruise 2000 km", "cruise 4000 km", "climb"]
    assert motions.skipped == []
    state = {v.name: v.symbol for v in definition.states}
    rates = definition.ideal_rhs_expanded()
    row_h = [v.name for v in definition.states].index("h")
    for point in motions.points:
        up = 10.0 if point.label == "climb" else 0.0
        assert point.values[state["v_U"]] == up
        # the ideal height rate is the up velocity: climbing means h grows
        assert float(rates[row_h].xreplace(point.values)) == pytest.approx(up, abs=1e-12)
    climb = motions.points[-1].values
    assert climb[state["h"]] == 3000.0
    # ground speed 150 m/s along track 60° (east of north), as the climb says
    assert np.hypot(climb[state["v_N"]], climb[state["v_E"]]) == pytest.approx(150.0)
    assert np.degrees(np.arctan2(climb[state["v_E"]], climb[state["v_N"]])) == \
        pytest.approx(60.0)


def _check(tmp_path, capsys, text: str, *options: str) -> tuple[int, dict]:
    hand = tmp_path / "vertical.txt"
    hand.write_text(text, encoding="utf-8")
    status = main(["check", str(MODEL), str(hand), "--json", *options])
    return status, json.loads(capsys.readouterr().out)


def test_an_enu_file_is_checked_in_its_own_states(tmp_path, capsys):
    status, report = _check(tmp_path, capsys,
                            "dot(delta_h) = delta_v_U - c_1*delta_h + c_1*baro_bias\n")
    assert status == 0, report
    assert [p["label"] for p in report["points"]][-1] == "climb"
    assert report["equations"][0]["status"] == "agrees"
    # the up velocity written with the down velocity's sign is a wrong sign
    status, report = _check(tmp_path, capsys, "dot(delta_h) = -delta_v_U\n")
    assert status == 1
    (finding,) = report["equations"][0]["findings"]
    assert (finding["quantity"], finding["kind"], finding["class"]) == (
        "delta_v_U", "wrong sign", "mistake")
