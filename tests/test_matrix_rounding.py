"""The matrix check's effects against their rounding floor.

A difference of two day-long propagations at rounding level names no initial error,
source or motion (which one reaches the largest rounding difference changes with the last
bits of the arithmetic); a real difference is reported as before, with its case.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker import matrix as mc
from ins_errors.checker import matrix_effects
from ins_errors.checker.conventions import convention
from ins_errors.checker.matrix_input import HandMatrices
from ins_errors.checker.matrix_report import NO_EFFECT, to_json, to_markdown, to_terminal
from ins_errors.numeric.model import load_model

HAND = Path(__file__).resolve().parent / "data" / "north_pointing_F.py"
MODEL = "north_pointing"


@pytest.fixture(scope="module")
def motions():
    """Three day-long motions (the same request as test_matrix_check: kept per process)."""
    return mc.motions(load_model(MODEL), hours=24.0, step=120.0, ellipsoid="wgs84")


def _derived_as_hand(motions, nudge=lambda a: a) -> HandMatrices:
    """The derived model itself as the hand's matrices (every state, every source),
    each matrix passed through ``nudge``."""
    model = load_model(MODEL)
    conv = convention(model, "model")
    F, G = {}, {}
    for m in motions:
        Fz, Gz = mc.derived_in_convention(model, conv, m)
        F[m.label], G[m.label] = nudge(np.array(Fz)), nudge(np.array(Gz))
    return HandMatrices("derived", list(conv.names), [s.name for s in model.sources], F, G)


def _one_ulp(a: np.ndarray) -> np.ndarray:
    """Every nonzero entry moved by one unit in the last place (away from zero)."""
    return np.where(a != 0, np.nextafter(a, np.copysign(np.inf, a)), a)


def test_rounding_differences_name_no_case_and_do_not_change_the_report(motions):
    """The derived model checked against itself, exactly and with every entry one ulp
    off: the propagated differences (exactly 0, resp. rounding) are below their floors
    on every motion, no case is named, and the two reports read the same."""
    exact = mc.check_matrices(MODEL, _derived_as_hand(motions), "model", motion_list=motions)
    nudged = mc.check_matrices(MODEL, _derived_as_hand(motions, _one_ulp), "model",
                               motion_list=motions)
    assert exact.findings == [] and nudged.findings == []
    assert all(e.position_difference == 0 and e.attitude_difference == 0
               for e in exact.effects)
    assert any(e.position_difference > 0 for e in nudged.effects)  # rounding shows
    for e in nudged.effects:
        assert not e.position_above_rounding and not e.attitude_above_rounding
        # the floor is far below any effect worth naming: 1e-10 of the error itself
        largest = max(x.position_model for x in nudged.effects
                      if (x.motion, x.hours) == (e.motion, e.hours))
        assert 0 < e.position_floor < 1e-10 * largest
    text = to_terminal(nudged)
    assert text == to_terminal(exact)
    table = text[text.index("Effect of the differences"):].splitlines()[2:]
    assert len(table) == 6
    for row in table:
        assert row.count(NO_EFFECT) == 2 and "initial" not in row and "source" not in row
        assert " < " in row and "″" in row
    assert to_markdown(nudged) == to_markdown(exact)
    for case in to_json(nudged)["effects"]:
        assert case["position_below_rounding"] and case["attitude_below_rounding"]
        assert case["position_difference_m"] <= case["position_floor_m"]


def test_a_finding_whose_change_is_rounding_names_no_motion(motions):
    """finding_effects of an entry the hand gives one ulp off: the change is below the
    rounding floor on every motion, so no motion is named and the line says so."""
    model = load_model(MODEL)
    conv = convention(model, "model")
    hand = _derived_as_hand(motions)
    report = mc.check_matrices(MODEL, hand, "model", motion_list=motions, effects=False)
    sampled = mc._Sampled(hand.F, hand.G, {}, {})
    for m in motions:
        sampled.Fz[m.label], sampled.Gz[m.label] = mc.derived_in_convention(model, conv, m)
        hand.F[m.label][:, 0, 1] = _one_ulp(hand.F[m.label][:, 0, 1])  # δv̇_E from δv_N
    finding = mc.EntryFinding("F", "delta_v_E", "delta_v_N", "wrong coefficient", "mistake",
                              1.0, "major", "static", 0.0, 1.0, 1.0, 0.0, "m/s**2",
                              {m.label: 1.0 for m in motions})
    report.findings = [finding]
    report.finding_effects = mc.finding_effects(report, sampled, conv, model, motions)
    alone = report.finding_effects[finding.entry]
    assert alone.position > 0  # the ulp propagates ...
    assert alone.motion is None and not alone.position_above_rounding  # ... as rounding
    assert alone.position < alone.position_floor
    assert not alone.attitude_above_rounding
    text = to_terminal(report)
    assert f"alone after 24 h: {NO_EFFECT} (< " in text
    assert "largest on static)" not in text.split("alone after 24 h")[1]
    effect = to_json(report)["findings"][0]["effect_alone_24h"]
    assert effect["motion"] is None and effect["position_below_rounding"]
    assert effect["position_floor_m"] == alone.position_floor > alone.position


def test_a_real_effect_names_its_case_and_value(tmp_path, motions):
    """Dropping the Coriolis term 2U sin φ δv_N from δv̇_E (the Foucault rotation) changes
    the 24-h error by more than 10 m: far above the floor, the table names the worst case
    and its value, and the finding's effect alone is that difference, with its motion."""
    text = HAND.read_text(encoding="utf-8")
    path = tmp_path / "hand_copy.py"
    path.write_text(text.replace("F[0, 1] = turn", "F[0, 1] = 0.0"), encoding="utf-8")
    report = mc.check_matrices(MODEL, f"{path}:error_model", "model", motion_list=motions)
    worst = max((e for e in report.effects if (e.motion, e.hours) == ("static", 24.0)),
                key=lambda e: e.position_difference)
    assert worst.position_difference > 10.0
    assert worst.position_difference > 1e6 * worst.position_floor
    out = to_terminal(report)
    [row] = [line for line in out.splitlines() if line.split()[:3] == ["static", "24", "h"]]
    assert f"{worst.position_difference:.3g} m" in row
    assert f"{worst.case} ({worst.magnitude})" in row and NO_EFFECT not in row
    alone = report.finding_effects["F[delta_v_E, delta_v_N]"]
    assert alone.position_above_rounding and alone.motion is not None
    assert f"alone after 24 h: {alone.position:.3g} m" in out
    effect = to_json(report)["findings"][0]["effect_alone_24h"]
    assert effect["motion"] == alone.motion and not effect["position_below_rounding"]


def test_rounding_floor_is_the_product_error_bound():
    """γ = size·steps·ε times the largest scaled response and the readout's unit."""
    eps = np.finfo(float).eps
    floor = matrix_effects.rounding_floor
    assert floor(2.0, 15, 1440, 10.0) == pytest.approx(15 * 1440 * eps * 20.0)
    assert floor(1.0, 3, 0, 1.0) == pytest.approx(3 * eps)  # at least one step


def test_phi_attitude_example_has_no_effect_above_rounding():
    """examples/strapdown/phi_attitude.txt agrees with the derived φ-angle attitude rows:
    its effect table (24 h, the README's command) names no case on any motion."""
    from ins_errors.checker.convention_equations import check_convention_file
    from ins_errors.checker.convention_equations import to_terminal as convention_text

    path = HAND.parent.parent.parent / "examples" / "strapdown" / "phi_attitude.txt"
    report = check_convention_file(path).report
    assert report.findings == [] and len(report.effects) > 0
    assert max(e.position_difference for e in report.effects) < 1e-9
    assert not any(e.position_above_rounding or e.attitude_above_rounding
                   for e in report.effects)
    assert convention_text(check_convention_file(path)).count(NO_EFFECT) == 12
