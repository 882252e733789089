"""A comparison warns when the linear error equations grow exponentially over the run.

A probe's model file with a sign slip in the transport rate ran to 1.7e4 m/s of velocity
error with only a validity warning ("the ratio does not scale steadily"); the growing
mode was named by ``check`` but not by ``compare``. The reference here is the textbook
e-folding time of an undamped vertical channel, √(R/2g), not the code's own figure.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import compare

GROWS = "grow exponentially"


def _strapdown(hours: float, damped: bool):
    model = load_model("strapdown_ned")
    w0 = 2 * np.pi / 300.0
    gains = {"k_h1": 2 * 0.7 * w0, "k_h2": w0**2 + 2 * 9.80665 / 6_371_000.0} if damped else {}
    p = model.parameter_vector(**gains)
    motion = st.trajectory(model, st.static(np.radians(50.0)), hours * 3600.0, 10.0, p=p)
    return compare(model, motion, [{"accel_bias_y": 1e-4}], record_interval=60.0,
                   refined=False, validity_threshold=None, integration_error=False)[0]


def _vertical_e_folding_minutes(latitude_deg: float) -> float:
    """√(R/2g): WGS-84 normal gravity (Somigliana) and the Gaussian mean radius."""
    a, e2, s2 = 6_378_137.0, 0.00669437999014, math.sin(math.radians(latitude_deg)) ** 2
    g = 9.7803253359 * (1 + 0.00193185265241 * s2) / math.sqrt(1 - e2 * s2)
    radius = math.sqrt(a * (1 - e2) / (1 - e2 * s2) ** 1.5 * a / math.sqrt(1 - e2 * s2))
    return math.sqrt(radius / (2 * g)) / 60.0


def test_an_undamped_vertical_channel_is_named_with_its_textbook_e_folding_time():
    [warning] = [w for w in _strapdown(2.0, damped=False).warnings if GROWS in w]
    minutes = float(re.search(r"×e every ([\d.]+) min", warning).group(1))
    assert minutes == pytest.approx(_vertical_e_folding_minutes(50.0), rel=2e-3)
    assert "ins-errors modes strapdown_ned" in warning
    assert "k_h1, k_h2 are 0" in warning


def test_a_run_that_leaves_its_domain_names_the_growing_mode_and_the_zero_gains():
    """strapdown_ned's default (undamped) vertical channel runs to NaN after some hours;
    the one-line error said only "became NaN"."""
    from ins_errors.errors import DomainError
    from ins_errors.numeric.simulate import simulate

    model = load_model("strapdown_ned")
    motion = st.trajectory(model, st.static(np.radians(50.0)), 8 * 3600.0, 10.0)
    with pytest.raises(DomainError) as caught:
        simulate(model, motion, [{"accel_bias_x": 50 * 9.80665e-6}], record_interval=60.0,
                 parts=("real", "linear"))
    message = str(caught.value)
    assert "left its domain" in message and "\n" not in message
    minutes = float(re.search(r"×e every ([\d.]+) min", message).group(1))
    assert minutes == pytest.approx(_vertical_e_folding_minutes(50.0), rel=2e-3)
    assert "ins-errors modes strapdown_ned" in message
    assert "k_h1, k_h2 are 0" in message and "-p k_h1=" in message
    # one gain set: only the other one is named
    from ins_errors.numeric.linear_system import undamped_remedy

    assert "gain k_h1 is 0" in undamped_remedy(model, model.parameter_vector(k_h2=1e-3))
    assert undamped_remedy(model, model.parameter_vector(k_h1=0.03, k_h2=1e-3)) == ""


def test_a_domain_error_without_a_growing_mode_has_no_hint():
    from ins_errors.errors import DomainError
    from ins_errors.numeric.simulate import simulate

    model = load_model("orthodromic")
    motion = tr.trajectory(model, tr.static_profile(np.radians(50.0)), 6 * 3600.0, 10.0)
    with pytest.raises(DomainError) as caught:  # a platform tilted past 90° in minutes
        simulate(model, motion, [{"gyro_drift_y": 1e-3}], record_interval=60.0,
                 parts=("real", "linear"), platform="small_angle")
    assert "left its domain" in str(caught.value) and "grows" not in str(caught.value)


@pytest.mark.parametrize("hours, damped", [(2.0, True), (0.25, False)])
def test_no_warning_for_a_damped_channel_or_a_run_shorter_than_three_e_foldings(hours, damped):
    assert not [w for w in _strapdown(hours, damped).warnings if GROWS in w]


def test_the_schuler_loop_of_a_platform_model_does_not_warn():
    model = load_model("orthodromic")
    motion = tr.trajectory(model, tr.static_profile(np.radians(50.0)), 24 * 3600.0, 60.0)
    [result] = compare(model, motion, [{"accel_bias_y": 1e-4}], record_interval=600.0,
                       refined=False, validity_threshold=None, integration_error=False)
    assert not [w for w in result.warnings if GROWS in w]


def test_the_growth_check_leaves_a_streamed_motion_streamed():
    """It read F's inputs at t = 0 through inputs_at, which stores a streamed motion whole:
    a moving week at 100 Hz then ran to its end and was refused (8.7 GB), and a moving
    day's memory no longer followed the recording interval."""
    model = load_model("orthodromic")
    profile = tr.great_circle_profile(np.radians(50.0), 0.5, np.radians(90.0), 250.0)
    motion = tr.trajectory(model, profile, 600.0, 0.01, stream=True)
    assert motion.is_streamed
    compare(model, motion, [{"accel_bias_y": 1e-4}], record_interval=60.0, refined=False,
            validity_threshold=None, integration_error=False)
    assert motion.is_streamed


def _orthodromic_east(hours: float):
    model = load_model("orthodromic")
    profile = tr.great_circle_profile(np.radians(50.0), np.radians(30.0), np.radians(90.0),
                                      250.0, 5000.0)
    motion = tr.trajectory(model, profile, hours * 3600.0, 10.0)
    return model, motion, compare(model, motion, [{"initial_velocity_error_eta": 0.1}],
                                  record_interval=60.0, refined=False,
                                  validity_threshold=None, integration_error=False)[0]


def test_a_mode_of_f_frozen_at_the_start_of_a_moving_base_is_checked_against_the_run():
    """orthodromic's F at the start of an eastbound great circle has a real eigenvalue
    of about +3e-5 /s along delta_V_eta (×e every 9 h), so every run of more than 27 h
    said its errors grow exponentially (×8.7e7 over a week, the long-flight probe),
    while an initial velocity error that starts exactly in that direction stays at
    0.1 m/s all along. F changes along the motion; the warning now needs the run's own
    errors to grow. The independent evidence: the direct (nonlinear) run's largest
    velocity error over the second half of the run is about that over the first."""
    from ins_errors.numeric.linear_system import growth_rate, start_state_matrix

    model, motion, case = _orthodromic_east(30.0)
    rate = growth_rate(start_state_matrix(model, motion))
    assert rate * 30 * 3600 > 3          # the frozen mode alone would warn
    times = case.times
    early, late = times <= times[-1] / 2, times >= times[-1] / 2
    velocity = np.abs(case.direct["delta_V_eta"]) if "delta_V_eta" in case.direct else None
    if velocity is None:  # the velocity outputs of the model, whichever names them
        velocity = np.max([np.abs(v) for k, v in case.direct.items() if k.startswith("delta_v")],
                          axis=0)
    # the frozen mode would multiply it by e^(rate × 15 h) ≈ 5 between the halves
    assert velocity[late].max() < 1.25 * velocity[early].max()
    assert not any(GROWS in w for w in case.warnings), case.warnings


def test_a_growing_mode_the_run_follows_is_still_named_on_a_moving_base():
    """strapdown_ned's undamped vertical channel on a great circle: F changes along the
    motion, but the run's own height error grows (its ratio over the two halves of the
    run is far above 1), so the warning stands, with the textbook e-folding time."""
    model = load_model("strapdown_ned")
    motion = st.trajectory(model, st.great_circle(np.radians(50.0), 0.0, np.radians(60.0),
                                                  250.0, 5000.0), 2 * 3600.0, 1.0)
    [case] = compare(model, motion, [{"accel_bias_y": 1e-4}], record_interval=60.0,
                     refined=False, validity_threshold=None, integration_error=False)
    height = np.abs(case.direct["delta_height"])
    half = case.times <= case.times[-1] / 2
    assert height[~half].max() > 20 * height[half].max()
    [warning] = [w for w in case.warnings if GROWS in w]
    minutes = float(re.search(r"×e every ([\d.]+) min", warning).group(1))
    assert minutes == pytest.approx(_vertical_e_folding_minutes(50.0), rel=5e-3)


def test_the_command_that_names_the_mode_names_a_model_file_as_typed(tmp_path, capsys,
                                                                     monkeypatch):
    """A filter designer's model file my_ins.py was told "`ins-errors modes my_ins` names
    the mode", a command that finds no model; the warning now gives the file as the
    command takes it, and that command runs."""
    import shutil
    from pathlib import Path

    from ins_errors.cli import main

    folder = tmp_path / "work"
    folder.mkdir()
    shutil.copy(Path(__file__).parent / "models" / "enu_strapdown.py", folder / "my_ins.py")
    monkeypatch.chdir(folder)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    assert main(["compare", "my_ins.py", "--hours", "2", "--step", "10s", "--no-refined",
                 "-s", "gyro_bias_x=0.01deg/h"]) == 0
    said = re.search(r"`ins-errors modes ([^`]+)` names the mode", capsys.readouterr().out)
    assert said and said[1] == "my_ins.py", said
    assert main(["modes", said[1]]) == 0


def test_a_step_beyond_rk4_stability_is_named_with_a_step_that_runs():
    """A damped 300-s vertical loop sampled every 300 s: RK4 amplifies its decaying mode
    e^{λt} (|λ| = 2π/300 s, |λ|·step = 6.3, beyond the real-axis bound ≈ 2.785) and
    the run ran to NaN; the error said only "became NaN", as if the physics left its
    domain. The reference is the loop's own |λ| = ω0 and RK4's growth factor
    1 + z + z²/2 + z³/6 + z⁴/24 at the suggested step."""
    from ins_errors.errors import DomainError
    from ins_errors.numeric.simulate import simulate

    model = load_model("strapdown_ned")
    w0 = 2 * np.pi / 300.0
    p = model.parameter_vector(k_h1=2 * 0.7 * w0, k_h2=w0**2 + 2 * 9.80665 / 6_371_000.0)
    source = [{"accel_bias_y": 1e-4}]
    motion = st.trajectory(model, st.static(np.radians(50.0)), 12 * 3600.0, 300.0, p=p)
    with pytest.raises(DomainError) as caught:
        simulate(model, motion, source, parts=("real", "linear"))
    message = str(caught.value)
    assert "left its domain" in message and "\n" not in message
    assert "beyond RK4's stability" in message and "grow exponentially" not in message
    speed = float(re.search(r"\|λ\| = ([\d.e-]+)/s", message).group(1))
    assert speed == pytest.approx(w0, rel=5e-3)  # (three digits)
    bound = float(re.search(r"choose a step below ([\d.e+]+) s", message).group(1))
    assert bound == pytest.approx(2.785 / w0, rel=5e-3)
    suggested = float(re.search(r"e\.g\. ([\d.e+]+) s", message).group(1))
    z = w0 * (-0.7 + 1j * math.sqrt(1 - 0.7**2)) * suggested  # the loop's pole × step
    assert abs(1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24) < 1
    motion = st.trajectory(model, st.static(np.radians(50.0)), 12 * 3600.0, suggested, p=p)
    sim = simulate(model, motion, source, parts=("real", "linear"), record_interval=600.0)
    assert np.all(np.isfinite(sim.real))
