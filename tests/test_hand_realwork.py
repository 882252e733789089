"""Real-work lines of a hand file: accelerometer outputs and the velocity update.

The reference for the accelerometer rows is an independent one: the platform attitude
as a scipy rotation (z-y-x angles, platform → trihedron), its transpose applied to a
specific-force vector and differentiated numerically at α = 0.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.spatial.transform import Rotation

from ins_errors.checker.compare import check_hand
from ins_errors.checker.notation import default_notation
from ins_errors.checker.parse import parse_hand_text

PRINTED_AZ = "a_z = a_xi - a_eta*alpha_z + alpha_x*a_zeta"
CORRECT = """@realwork instrument model and computer
tilde(V_xi_k1) = tilde(V_xi_k) + tau*(a_x_k - (tilde(omega_eta_k)*tilde(V_zeta_k) \
- tilde(omega_zeta_k)*tilde(V_eta_k)) + tilde(g_xi_k) + Delta_a)
a_x = a_xi + a_eta*alpha_z - a_zeta*alpha_y
a_y = a_eta - a_xi*alpha_z + a_zeta*alpha_x
a_z = a_zeta + a_xi*alpha_y - a_eta*alpha_x
"""


def check(text: str):
    hand = parse_hand_text(text, default_notation("orthodromic"))
    return check_hand(hand, effects=False)


def _rotation_rows(row: int) -> tuple[float, np.ndarray]:
    """d(f^p_row)/dα by central differences of the exact rotation, for f = (1, 2, 3)."""
    f = np.array([1.0, 2.0, 3.0])

    def out(alpha):
        c = Rotation.from_euler("ZYX", [alpha[2], alpha[1], alpha[0]]).as_matrix()
        return (c.T @ f)[row]

    step = 1e-6
    grad = np.array([(out(np.eye(3)[i] * step) - out(-np.eye(3)[i] * step)) / (2 * step)
                     for i in range(3)])
    return out(np.zeros(3)), grad


def _printed_row(expr: str) -> tuple[float, np.ndarray]:
    """Value and α-gradient of a printed row at (a_xi, a_eta, a_zeta) = (1, 2, 3)."""
    rhs = sp.sympify(expr.split("=", 1)[1]).subs({"a_xi": 1.0, "a_eta": 2.0, "a_zeta": 3.0})
    value = sp.lambdify(sp.symbols("alpha_x alpha_y alpha_z"), rhs)
    return value(0, 0, 0), np.array([value(*np.eye(3)[i]) - value(0, 0, 0)
                                     for i in range(3)])


def test_printed_az_row_is_not_the_rotation_but_the_checker_reference_is():
    rows = CORRECT.splitlines()[2:5]
    for row, line in enumerate(rows):  # the correct rows are the rotation's expansion
        value, grad = _printed_row(line)
        ref_value, ref_grad = _rotation_rows(row)
        assert value == pytest.approx(ref_value) and grad == pytest.approx(ref_grad, abs=1e-6)
    value, grad = _printed_row(PRINTED_AZ)
    ref_value, ref_grad = _rotation_rows(2)
    assert value != pytest.approx(ref_value) and grad != pytest.approx(ref_grad, abs=1e-3)


def test_correct_real_work_agrees():
    report = check(CORRECT)
    assert [r.status for r in report.results] == ["agrees"] * 5
    assert {"real work: difference-scheme update of tilde(V_xi) (increment proportional to "
            "tau)", "error state delta_V_xi"} <= {r.target for r in report.results}
    assert report.exit_status == 0


def test_wrong_coriolis_sign_in_the_update_is_found_by_its_variation():
    report = check(CORRECT.replace("- tilde(omega_zeta_k)", "+ tilde(omega_zeta_k)"))
    (result,) = [r for r in report.results if r.target == "error state delta_V_xi"]
    found = {f.quantity: f for f in result.findings}
    # -omega_zeta where +omega_zeta belongs (beside the V_zeta terms of the same coefficient)
    assert found["delta_V_eta"].severity == "mistake"
    assert found["delta_V_eta"].kind in ("wrong sign", "wrong coefficient")


def test_printed_az_row_is_a_mistake():
    report = check(CORRECT.replace(CORRECT.splitlines()[4], PRINTED_AZ))
    (result,) = [r for r in report.results if r.equation.label == "a_z"]
    found = {f.quantity: f for f in result.findings}
    assert result.status == "mistake" and report.exit_status == 1
    assert (found["(value)"].kind, found["(value)"].severity) == (
        "wrong symbol or index", "mistake")
    assert found["(value)"].detail == "a_xi written where a_zeta belongs"
    assert found["alpha_x"].kind == "wrong symbol or index"
    assert found["alpha_z"].kind == "extra term" and found["alpha_y"].kind == "omitted term"


def test_injected_sign_error_in_ax_is_found():
    report = check(CORRECT.replace("a_xi + a_eta*alpha_z", "a_xi - a_eta*alpha_z"))
    (result,) = [r for r in report.results if r.equation.label == "a_x"]
    (finding,) = result.findings
    assert (finding.quantity, finding.kind) == ("alpha_z", "wrong sign")
    assert finding.is_mistake


def test_terms_outside_the_time_step_are_reported():
    printed = CORRECT.replace("+ tilde(g_xi_k) + Delta_a)", ") + tilde(g_xi_k) + Delta_a")
    report = check(printed)
    (result,) = [r for r in report.results if r.equation.step]
    (finding,) = result.findings
    assert (finding.kind, finding.severity) == ("outside the time step", "mistake")
    assert finding.hand == "Delta_a + tilde(g_xi)"


def test_real_work_line_errors_are_input_problems():
    hand = parse_hand_text("@realwork x\na_x + a_y = a_xi\na_x = a_xi = a_eta\n",
                           default_notation("orthodromic"))
    assert [p.line for p in hand.problems] == [2, 3] and not hand.real_work


def _theta_orthodromic(tmp_path):
    """The orthodromic model as a model file whose platform angles are named theta_x,
    theta_y, theta_z (LaTeX \\theta): nothing else changed."""
    from pathlib import Path

    from ins_errors.model_files import load_model_file

    source = Path(__file__).resolve().parent.parent / "ins_errors" / "models" / "orthodromic.py"
    text = source.read_text(encoding="utf-8")
    assert text.count("alpha_") >= 6 and "theta" not in text
    path = tmp_path / "orthodromic_theta.py"
    path.write_text(text.replace("alpha_", "theta_"), encoding="utf-8")
    d = load_model_file(path)
    assert [v.name for v in d.platform_angles] == ["theta_x", "theta_y", "theta_z"]
    return d


@pytest.mark.parametrize("attitude", ["1e-4 rad", "1e-3 rad"])
def test_platform_angles_are_the_models_whatever_their_names(tmp_path, attitude):
    """The real-work check took the platform angles by the prefix ``alpha``: with the
    angles named theta_*, correct accelerometer rows were "mistakes" (their θ terms read
    as part of the zero-order value), the velocity update's variation lost its tilt
    terms, and the typical platform angle stayed 1e-4 rad whatever the declared attitude.
    The same file in the model's names gives the same report, names aside."""
    from ins_errors.checker.report import to_json

    hand_text = CORRECT.replace(CORRECT.splitlines()[4], PRINTED_AZ)
    reports = []
    for model, text in (("orthodromic", hand_text),
                        (_theta_orthodromic(tmp_path), hand_text.replace("alpha_", "theta_"))):
        hand = parse_hand_text(text, default_notation(model))
        reports.append(check_hand(hand, model, magnitudes={"attitude": attitude},
                                  effects=False))
    alpha, theta = reports
    assert [r.status for r in theta.results] == ["agrees"] * 4 + ["mistake"]
    (a_z,) = [r for r in theta.results if r.equation.label == "a_z"]
    found = {f.quantity: f for f in a_z.findings}
    # the x-angle term: (a_zeta + a_eta) θ_x too much, g θ at rest against the row's g:
    # its size is the declared attitude θ (to the small terms of the row's largest part)
    assert found["theta_x"].size == pytest.approx(float(attitude.split()[0]), rel=1e-2)
    same = str(to_json(theta)).replace("theta_", "alpha_").replace(r"\\theta", r"\\alpha")
    assert same == str(to_json(alpha))


def test_accelerometer_rows_are_not_compared_for_a_model_without_platform_angles():
    """strapdown_ned has no platform: an ``a_x`` row "agreed" with a platform rotation in
    angles alpha_* the model does not have."""
    hand = parse_hand_text("@realwork x\na_x = a_xi + a_eta*alpha_z - a_zeta*alpha_y\n",
                           default_notation("strapdown_ned"))
    (result,) = check_hand(hand, "strapdown_ned", effects=False).results
    assert result.status == "not compared"
    assert "no three platform angles" in result.notes[0]
