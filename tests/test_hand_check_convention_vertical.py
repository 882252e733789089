"""Effects of vertical-channel findings (strapdown_ned, φ convention).

The horizontal effect propagation holds the vertical channel (it diverges in the model
itself); a vertical-channel term written wrongly is then given its effect on the height
error with the vertical channel free. Reference: the closed form of the undamped
vertical channel, δḧ = ω² δh, δh(t) = δh₀ cosh ωt, with ω² = 2γ/a (1 + f + m − 2f sin²φ)
(the normal-gravity gradient, WGS-84) against a hand g/a: a researcher's independent
figures for 10 m of initial height error are 2.76 km and 435 m after 1 h.
"""

from __future__ import annotations

import numpy as np
import pytest

from ins_errors.checker.convention_equations import check_convention_file
from ins_errors.checker.matrix_report import NOT_ASSESSED, to_json, vertical_text

A, F, M = 6378137.0, 0.0033528106647, 0.00344978600308
GAMMA_E, K, E2 = 9.7803253359, 0.00193185265241, 6.69437999014e-3
LAT = np.radians(50.0)

COUPLING = ("f_N*phi_E - f_E*phi_N - ((2*omega_ie_N + omega_en_N)*dv_E"
            " - (2*omega_ie_E + omega_en_E)*dv_N)")


def _gamma() -> float:
    s2 = np.sin(LAT) ** 2
    return GAMMA_E * (1 + K * s2) / np.sqrt(1 - E2 * s2)


def _file(tmp_path, *lines, tiny: bool = True):
    path = tmp_path / "vertical.txt"
    # tiny velocity and angle sizes: the 10 m initial height error is the worst case
    sizes = ["@magnitude m/s = 1e-9 m/s", "@magnitude rad = 1e-12 rad"] if tiny else []
    path.write_text("\n".join(["@convention phi", "@scope static base", *sizes,
                               *lines]) + "\n")
    return path


def test_half_the_vertical_gravity_gradient_changes_the_height_error_as_cosh(tmp_path):
    gamma = _gamma()
    w_model = np.sqrt(2 * gamma / A * (1 + F + M - 2 * F * np.sin(LAT) ** 2))
    w_hand = np.sqrt(gamma / A)
    t = 3600.0
    model, hand = 10 * np.cosh(w_model * t), 10 * np.cosh(w_hand * t)
    assert model == pytest.approx(2760, rel=0.01)  # the researcher's figures
    assert hand == pytest.approx(435, rel=0.01)
    path = _file(tmp_path, f"dot(dv_D) = {COUPLING} + g/a*dr_D")
    check = check_convention_file(path, hours=2.0, step=600.0)
    f = check.report.finding("dv_D", "dr_D")
    assert (f.kind, f.severity) == ("wrong coefficient", "mistake")
    e = check.report.vertical_effects[f.entry]
    assert e.hours == (1.0,)
    assert e.case == ("initial dr_D",) and e.motion == ("static",)
    assert e.height[0] == pytest.approx(model - hand, rel=0.01)
    text = vertical_text(check.report, f)
    assert text.startswith("height error, vertical channel not held: 1 h: 2.3")
    assert "no effect" not in text
    [shown] = [g for g in to_json(check.report)["findings"] if g["column"] == "dr_D"]
    assert shown["effect_vertical"]["height_m"] == [e.height[0]]


def test_the_models_own_vertical_mode_is_named_after_a_day(tmp_path):
    """After 24 h the undamped channel has grown by e^151: the model's own mode (×e every
    1/ω = 9.5 min), not a figure."""
    path = _file(tmp_path, f"dot(dv_D) = {COUPLING} + g/a*dr_D")
    check = check_convention_file(path, hours=24.0, step=600.0)
    f = check.report.finding("dv_D", "dr_D")
    e = check.report.vertical_effects[f.entry]
    assert e.exponential == (False, True)
    assert e.growing_mode == "model"
    w_model = np.sqrt(2 * _gamma() / A * (1 + F + M - 2 * F * np.sin(LAT) ** 2))
    assert e.e_folding == pytest.approx(1 / w_model, rel=0.01)
    assert "24 h: grows exponentially, ×e every 9.5" in vertical_text(check.report, f)
    assert "(the model's own mode)" in vertical_text(check.report, f)


def test_a_horizontal_row_in_a_vertical_column_says_not_assessed(tmp_path):
    """F[dv_E, dv_D] (the Coriolis term 2Ω cos φ) with the wrong sign: the vertical
    errors it feeds into the east channel are held, so its effect is not assessed (not
    'no effect')."""
    path = _file(tmp_path, "dot(dv_E) = f_D*phi_N - f_N*phi_D"
                 " - ((2*omega_ie_D + omega_en_D)*dv_N + (2*omega_ie_N + omega_en_N)*dv_D)",
                 tiny=False)
    check = check_convention_file(path, hours=2.0, step=600.0)
    f = check.report.finding("dv_E", "dv_D")
    assert f is not None and f.kind == "wrong sign"
    assert vertical_text(check.report, f) == NOT_ASSESSED
