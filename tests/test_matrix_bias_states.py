"""Bias states: a 15-state hand F (ψ, δv, δr, gyro and accelerometer biases) checked
against the derived model augmented with those sources as states.

References, independent of the augmentation:

* the same textbook ψ-angle model written as 9 states with a G (examples/strapdown/
  psi_model.py, checked in tests/test_matrix_check.py): its 15-state form
  ``[[F, G], [0, 0]]`` (examples/strapdown/psi_model_15.py) is the same linear system,
  so it must get the same verdicts entry by entry and the same propagated differences;
* injected mistakes whose place and factor are known by construction: −C_b^n written
  +C_b^n in the attitude rows' gyro-bias columns (hand/model = −1 there, nowhere else),
  an accelerometer column left out;
* a first-order Gauss–Markov bias ``ḃ = −b/τ``: its row is −1/τ, and the bias state
  alone decays as e^{−t/τ}.
"""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker import matrix as mc
from ins_errors.checker import transition
from ins_errors.checker.conventions import convention
from ins_errors.checker.matrix_report import to_json, to_markdown, to_terminal
from ins_errors.cli import main
from ins_errors.numeric.model import load_model

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "strapdown"
PSI_9 = f"{EXAMPLES / 'psi_model.py'}:psi_model"
PSI_15 = f"{EXAMPLES / 'psi_model_15.py'}:psi_model_15"
NINE = ["psi_N", "psi_E", "psi_D", "dvc_N", "dvc_E", "dvc_D", "dr_N", "dr_E", "dr_D"]
GYRO = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z"]
ACCEL = ["accel_bias_x", "accel_bias_y", "accel_bias_z"]


@pytest.fixture(scope="module")
def nine():
    return mc.check_matrices("strapdown_ned", PSI_9, "psi")


@pytest.fixture(scope="module")
def fifteen():
    return mc.check_matrices("strapdown_ned", PSI_15, "psi")


def _hand(tmp_path: Path, body: str, name: str = "hand") -> str:
    """A hand file next to a copy of the example files (it imports them)."""
    for example in ("psi_model.py", "psi_model_15.py"):
        (tmp_path / example).write_text((EXAMPLES / example).read_text(encoding="utf-8"),
                                        encoding="utf-8")
    path = tmp_path / f"{name}.py"
    path.write_text(textwrap.dedent(body), encoding="utf-8")
    return f"{path}:hand"


def _key(f) -> tuple:
    """A finding of the 9-state model in the 15-state's terms (G columns are F's)."""
    return ("F", f.row, f.column, f.kind, f.severity)


def test_the_15_state_model_gets_the_verdicts_of_the_9_state_model_with_g(nine, fifteen):
    assert fifteen.states == NINE + GYRO + ACCEL
    assert [b.name for b in fifteen.bias_states] == GYRO + ACCEL
    assert all(b.tau is None and b.rate == 0.0 for b in fifteen.bias_states)
    assert fifteen.sources == [] and not set(GYRO + ACCEL) & set(fifteen.out_of_scope)
    assert fifteen.compared == 15 * 15 and nine.compared == 9 * 15
    # nothing new found: the same entries, kinds, severities and sizes
    assert sorted(map(_key, fifteen.findings)) == sorted(map(_key, nine.findings))
    assert len(fifteen.findings) == 22 and fifteen.exit_status == nine.exit_status == 0
    for f in fifteen.findings:
        other = nine.finding(f.row, f.column)
        assert (f.motion, f.time, f.detail) == (other.motion, other.time, other.detail)
        assert (f.size, f.hand, f.model) == pytest.approx(
            (other.size, other.hand, other.model), rel=1e-12)
    # the bias states' typical sizes are the sources' (0.01 °/h, 1e-4 g)
    for name in GYRO + ACCEL:
        assert fifteen.magnitudes[name] == nine.magnitudes[name]


def test_bias_states_propagate_as_the_sources_do(nine, fifteen):
    # the augmented systems are the same: every case has the same difference, the
    # source's case of the 9-state model being the bias state's initial value
    by_case = {(e.motion, e.hours, e.case.replace("source ", "initial ")): e
               for e in nine.effects}
    assert len(fifteen.effects) == len(nine.effects) == 3 * 2 * (7 + 6)
    for e in fifteen.effects:
        other = by_case[(e.motion, e.hours, e.case)]
        assert e.magnitude == other.magnitude
        for a, b, floor in ((e.position_difference, other.position_difference,
                             e.position_floor),
                            (e.attitude_difference, other.attitude_difference,
                             e.attitude_floor),
                            (e.position_model, other.position_model, e.position_floor)):
            assert abs(a - b) <= floor
    # the worst 24-h difference on the weave, as tests/test_matrix_check.py has it
    worst = max((e for e in fifteen.effects if e.hours == 24.0 and e.motion == "manoeuvre"),
                key=lambda e: e.position_difference)
    assert worst.case == "initial gyro_bias_z" and 70 < worst.position_difference < 80
    for entry, alone in fifteen.finding_effects.items():
        assert alone.position == pytest.approx(nine.finding_effects[entry].position,
                                               rel=1e-6, abs=alone.position_floor)


def test_a_sign_error_in_the_gyro_bias_columns_is_a_wrong_sign_there(tmp_path, nine):
    spec = _hand(tmp_path, """
        import psi_model_15 as m15

        STATES = m15.STATES


        def hand(nav, imu):
            F = m15.psi_model_15(nav, imu)
            F[0:3, 9:12] = nav.C_bn        # −C_b^n written +C_b^n
            return F
        """)
    report = mc.check_matrices("strapdown_ned", spec, "psi")
    new = [f for f in report.findings if f.column in GYRO]
    assert {(f.row, f.column) for f in new} == {(r, c) for r in NINE[:3] for c in GYRO}
    for f in new:
        assert (f.matrix, f.kind, f.severity) == ("F", "wrong sign", "mistake")
        assert f.hand == pytest.approx(-f.model, rel=1e-12) and f.hand != 0
    # the others are the 9-state model's, unchanged
    assert sorted(map(_key, (f for f in report.findings if f not in new))) == sorted(
        map(_key, nine.findings))
    # C_b^n at heading 30°, level: F[psi_N, gyro_bias_x] = −cos 30° in the model
    f = report.finding("psi_N", "gyro_bias_x")
    assert f.model == pytest.approx(-np.cos(np.radians(30.0)), rel=1e-9)
    assert "F[psi_N, gyro_bias_x]: wrong sign" in to_terminal(report)


def test_an_accelerometer_column_left_out_is_an_omitted_term(tmp_path):
    spec = _hand(tmp_path, """
        import psi_model_15 as m15

        STATES = m15.STATES


        def hand(nav, imu):
            F = m15.psi_model_15(nav, imu)
            F[:, 14] = 0.0                 # accel_bias_z forgotten
            return F
        """)
    report = mc.check_matrices("strapdown_ned", spec, "psi", effects=False)
    found = [f for f in report.findings if f.column == "accel_bias_z"]
    # C_b^n δf: the down accelerometer feeds the velocity rows only (δv_D alone when
    # level, the horizontal ones too in the weave's banked turns)
    assert {f.row for f in found} <= {"dvc_N", "dvc_E", "dvc_D"}
    assert all(f.kind == "omitted term" and f.hand == 0.0 for f in found)
    down = report.finding("dvc_D", "accel_bias_z")
    assert (down.kind, down.severity, down.hand) == ("omitted term", "mistake", 0.0)
    assert down.model == pytest.approx(1.0, abs=0.05)


def test_a_gauss_markov_bias_row_is_minus_one_over_tau(tmp_path, fifteen):
    tau = 3600.0
    body = """
        import psi_model_15 as m15

        STATES = m15.STATES
        MARKOV = {{"accel_bias_z": "1 h"}}


        def hand(nav, imu):
            F = m15.psi_model_15(nav, imu)
            F[14, 14] = {rate}
            return F
        """
    agrees = mc.check_matrices("strapdown_ned",
                               _hand(tmp_path, body.format(rate=-1 / tau)), "psi")
    assert [b.tau for b in agrees.bias_states] == [None] * 5 + [tau]
    assert sorted(map(_key, agrees.findings)) == sorted(map(_key, fifteen.findings))
    # the row left at zero: the derived row is −1/τ, the only term of the row
    zero = mc.check_matrices("strapdown_ned", _hand(tmp_path, body.format(rate=0.0),
                                                    name="zero"), "psi", effects=False)
    [f] = [f for f in zero.findings if f.row == "accel_bias_z"]
    assert (f.column, f.kind, f.severity) == ("accel_bias_z", "omitted term", "mistake")
    assert f.model == -1 / tau and f.size == pytest.approx(1.0, rel=1e-12)
    assert "Gauss–Markov, τ = 3600 s" in f.detail
    # the derived bias state alone decays as e^(−t/τ) (static base: one exponential)
    model = load_model("strapdown_ned")
    conv = convention(model, "psi").with_biases(tuple(agrees.bias_states))
    static = mc.motions(model)[0]
    F, G = mc.derived_in_convention(model, conv, static)
    assert F.shape == (static.times.size, 15, 15)
    from scipy.linalg import expm

    phi = expm(F[0] * 7200.0)  # (the undamped vertical channel costs expm digits)
    assert phi[14, 14] == pytest.approx(np.exp(-2.0), rel=1e-7)
    assert F[0][14, 14] == -1 / tau and not np.any(np.delete(F[0][14], 14))
    assert np.all(G[:, :, [s.name for s in model.sources].index("accel_bias_z")] == 0.0)


def test_a_markov_row_without_its_declaration_is_an_extra_term_naming_tau(tmp_path):
    spec = _hand(tmp_path, """
        import psi_model_15 as m15

        STATES = m15.STATES


        def hand(nav, imu):
            F = m15.psi_model_15(nav, imu)
            F[9, 9] = -1 / 7200.0
            return F
        """)
    report = mc.check_matrices("strapdown_ned", spec, "psi", effects=False)
    f = report.finding("gyro_bias_x", "gyro_bias_x")
    assert (f.kind, f.severity, f.model) == ("extra term", "mistake", 0.0)
    assert "τ = 7200 s" in f.detail and "random constant" in f.detail


def test_reports_name_the_bias_states_alike(tmp_path, fifteen):
    text, markdown, data = to_terminal(fifteen), to_markdown(fifteen), to_json(fifteen)
    line = ("gyro_bias_x, gyro_bias_y, gyro_bias_z, accel_bias_x, accel_bias_y, "
            "accel_bias_z (random constants)")
    assert f"bias states (6, error sources as states: their columns hold G's): {line}" in text
    assert "no G: the other error sources' columns not compared" in text
    assert "`accel_bias_z` (random constants)" in markdown
    assert [b["name"] for b in data["bias_states"]] == GYRO + ACCEL
    assert {(b["statistics"], b["tau_s"], b["rate_per_s"]) for b in data["bias_states"]} == {
        ("constant", None, 0.0)}
    assert json.loads(json.dumps(data))["states"][-6:] == GYRO + ACCEL


@pytest.mark.parametrize("edit, message", [
    ('STATES = [*m15.STATES, "initial_roll_error"]',
     "'initial_roll_error' is an initial error of strapdown_ned (kind 'initial'): it only "
     "sets the initial state, so it cannot be a bias state"),
    ('STATES = m15.STATES\nSOURCES = ["gyro_bias_x"]',
     "'gyro_bias_x' is both a state (STATES) and a column of G (SOURCES)"),
    ('STATES = m15.STATES\nMARKOV = {"gyro_bias_x": 0}',
     "a correlation time of 0 is white noise, which cannot be a state"),
    ('STATES = m15.STATES\nMARKOV = {"gyro_bias_x": -5.0}',
     "MARKOV['gyro_bias_x']: the correlation time must be positive and finite"),
    ('STATES = m15.STATES\nMARKOV = {"gyro_bias_x": "1 m"}', "MARKOV['gyro_bias_x']"),
    ('STATES = m15.STATES\nMARKOV = {"psi_N": 60.0}',
     "MARKOV gives a correlation time for 'psi_N', which is not a bias state"),
    ('STATES = m15.STATES\nMARKOV = ["gyro_bias_x"]', "MARKOV must be a dictionary"),
    ('STATES = [*m15.STATES[:9], "gyro_bais_x"]',
     "unknown state of convention 'psi' 'gyro_bais_x'; did you mean 'gyro_bias_x'"),
])
def test_bad_bias_states_are_one_line_errors(tmp_path, capsys, edit, message):
    spec = _hand(tmp_path, f"""
        import numpy as np
        import psi_model_15 as m15

        {edit.replace(chr(10), chr(10) + ' ' * 8)}


        def hand(nav, imu):
            return np.zeros((len(STATES), len(STATES)))
        """)
    assert main(["check", "strapdown_ned", "--matrix", spec, "--convention", "psi"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert message in err and "\n" not in err and "Traceback" not in err, err
    assert captured.out == ""


def test_sampled_matrices_carry_bias_states_and_their_correlation_times(tmp_path, fifteen):
    from ins_errors.checker.matrix_input import evaluate_function, load_hand

    model = load_model("strapdown_ned")
    motion_list = mc.motions(model)
    path, function = PSI_15.rsplit(":", 1)
    fn, states, sources, markov = load_hand(Path(path), function)
    assert (sources, markov) == ([], {})
    hand = evaluate_function(fn, "x", Path(path), states, sources, motion_list)
    for m in motion_list:
        hand.F[m.label][:, 12, 12] = -1 / 1800.0
    arrays = {f"F_{k}": v for k, v in hand.F.items()}
    np.savez(tmp_path / "F15.npz", states=np.array(states), markov_states=np.array(
        ["accel_bias_x"]), markov_tau=np.array([1800.0]), **arrays)
    report = mc.check_matrices("strapdown_ned", str(tmp_path / "F15.npz"), "psi",
                               motion_list=motion_list, effects=False)
    assert [b.tau for b in report.bias_states] == [None, None, None, 1800.0, None, None]
    assert sorted(map(_key, report.findings)) == sorted(map(_key, fifteen.findings))


def test_declared_sizes_weigh_bias_states_and_g_columns_alike():
    # under --magnitude attitude=... the gyro bias is ω_s·θ (0.0256 °/h for 1e-4 rad),
    # listed in the report: a G column and a bias state's column are weighed by it alike,
    # so the ψ rows' largest term, and every size, is the same in both forms
    sizes = {"attitude": "1e-4rad"}
    nine = mc.check_matrices("strapdown_ned", PSI_9, "psi", effects=False, magnitudes=sizes)
    fifteen = mc.check_matrices("strapdown_ned", PSI_15, "psi", effects=False,
                                magnitudes=sizes)
    assert nine.magnitudes["gyro_bias_x"][1] == fifteen.magnitudes["gyro_bias_x"][1]
    assert "0.0256 deg/h" in nine.magnitudes["gyro_bias_x"][1]
    assert sorted(map(_key, fifteen.findings)) == sorted(map(_key, nine.findings))
    assert len(nine.mistakes) == 4
    for f in fifteen.findings:
        assert f.size == pytest.approx(nine.finding(f.row, f.column).size, rel=1e-12)
    # a ψ row's largest term is its gyro term, |C_b^n entry| × ω_s θ: the largest entry of
    # a row of a rotation matrix is between 1/√3 and 1, so the row's largest term is
    # 7.2e-8 to 1.24e-7 rad/s (the fixed 0.01 °/h would make it at most 4.85e-8)
    f = nine.finding("psi_N", "psi_D")
    largest = abs(f.hand - f.model) * 1e-4 / f.size
    omega_s_theta = np.sqrt(9.80665 / 6.378e6) * 1e-4
    assert omega_s_theta / np.sqrt(3) * 0.99 < largest < omega_s_theta * 1.01


@pytest.mark.parametrize("tau", ["1e-100", "0.5"])
def test_a_correlation_time_the_check_cannot_represent_is_refused(tmp_path, capsys, tau):
    # τ = 1e-100 s overflowed the propagation into "no effect above rounding"
    spec = _hand(tmp_path, f"""
        import psi_model_15 as m15

        STATES = m15.STATES
        MARKOV = {{"accel_bias_z": {tau}}}


        def hand(nav, imu):
            F = m15.psi_model_15(nav, imu)
            F[14, 14] = -1 / {tau}
            return F
        """)
    assert main(["check", "strapdown_ned", "--matrix", spec, "--convention", "psi"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and f"MARKOV['accel_bias_z']: a correlation time of {float(tau):g} s" \
        in err and "too short" in err and "(SOURCES)" in err, err


def test_a_short_valid_correlation_time_propagates_finite_and_exact(tmp_path, fifteen):
    # τ = 10 s, six e-foldings a sampling step: the derived bias state alone decays as
    # e^(−t/τ) through the check's stepped propagation, and a hand row of 2τ is a finding
    # whose effects are finite numbers
    tau = 10.0
    body = """
        import psi_model_15 as m15

        STATES = m15.STATES
        MARKOV = {{"accel_bias_z": 10.0}}


        def hand(nav, imu):
            F = m15.psi_model_15(nav, imu)
            F[14, 14] = {rate}
            return F
        """
    agrees = mc.check_matrices("strapdown_ned", _hand(tmp_path, body.format(rate=-1 / tau)),
                               "psi")
    assert sorted(map(_key, agrees.findings)) == sorted(map(_key, fifteen.findings))
    model = load_model("strapdown_ned")
    conv = convention(model, "psi").with_biases(tuple(agrees.bias_states))
    cruise = mc.motions(model)[1]
    F, _ = mc.derived_in_convention(model, conv, cruise)
    [phi] = transition._stepped(F, cruise.times, [120.0])
    assert phi[14, 14] == pytest.approx(np.exp(-120.0 / tau), rel=1e-9)
    slow = mc.check_matrices("strapdown_ned",
                             _hand(tmp_path, body.format(rate=-1 / (2 * tau)), name="slow"),
                             "psi")
    f = slow.finding("accel_bias_z", "accel_bias_z")
    assert f.kind == "wrong coefficient" and f.hand / f.model == pytest.approx(0.5)
    rows = to_json(slow)["effects"]
    assert rows and all(np.isfinite(v) for row in rows for v in row.values()
                        if isinstance(v, float))
