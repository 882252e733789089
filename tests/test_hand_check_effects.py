"""The hand check's "effect after 1 h / 24 h" of a mistake, against an independent
propagation: the tutorial's Schuler loop (δV' = −g ψ + ∇, δφ' = δV/R, ψ' = δV/R + ε)
and a hand version with one mistake, each initial error and source taken alone at its
typical (Schuler-consistent) size, propagated by mpmath's matrix exponential at 40
digits. The effect is the worst single case; a difference that is rounding is given as
below its floor; a mistake that makes the loop unstable is said to grow exponentially.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import mpmath
import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
R, G, THETA = 6_371_000.0, 9.80665, 1e-4
OMEGA_S = math.sqrt(G / R)
# typical sizes from the Schuler relations (the tutorial's declared θ): δV, δφ, ψ; ε, ∇
MAGNITUDES = [math.sqrt(G * R) * THETA, THETA, THETA, OMEGA_S * THETA, G * THETA]
CORRECT = ("dot(delta_V) = -g*psi + accel_bias\ndot(delta_phi) = delta_V/R\n"
           "dot(psi) = delta_V/R + gyro_drift\n")


def _matrix(signs: dict) -> list[list[float]]:
    """Augmented 5 × 5 matrix of (δV, δφ, ψ, ε, ∇) with the given coefficients."""
    a = [[0.0] * 5 for _ in range(5)]
    a[0][2], a[0][4] = signs.get("V_psi", -G), signs.get("V_bias", 1.0)
    a[1][0] = signs.get("phi_V", 1 / R)
    a[2][0], a[2][3] = signs.get("psi_V", 1 / R), 1.0
    return a


def _worst(hand: dict, hours: float) -> tuple[float, float]:
    """Largest |R Δδφ| (m) and |Δψ| (rad), hand minus model, over the five cases."""
    mpmath.mp.dps = 40
    t = hours * 3600.0
    phis = [mpmath.expm(mpmath.matrix(_matrix(s)) * t) for s in (hand, {})]
    position = attitude = mpmath.mpf(0)
    for j, size in enumerate(MAGNITUDES):
        d_phi = (phis[0][1, j] - phis[1][1, j]) * size
        d_psi = (phis[0][2, j] - phis[1][2, j]) * size
        position, attitude = max(position, abs(R * d_phi)), max(attitude, abs(d_psi))
    return float(position), float(attitude)


def _effect(tmp_path, capsys, text: str) -> tuple[dict, str]:
    hand = tmp_path / "hand.txt"
    hand.write_text(text, encoding="utf-8")
    assert main(["check", str(SCHULER), str(hand), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    (effect,) = [f["effect"] for e in data["equations"] for f in e["findings"]
                 if f.get("effect")]
    assert main(["check", str(SCHULER), str(hand)]) == 1
    return effect, capsys.readouterr().out


def test_worst_single_error_and_exponential_growth(tmp_path, capsys):
    """ψ' = −δV/R (the tutorial's wrong file): the loop turns unstable with rate ω_s. All
    errors started together cancel the growing mode (Schuler-consistent sizes), so the
    old combined case said 6.93 km after 1 h; each alone gives 28.3 km and 918″."""
    effect, out = _effect(tmp_path, capsys, CORRECT.replace("= delta_V/R + gyro",
                                                            "= -delta_V/R + gyro"))
    position, attitude = _worst({"psi_V": -1 / R}, 1.0)
    assert position == pytest.approx(28.3e3, rel=2e-3)  # the probe's figures
    assert effect["position_1h"] == pytest.approx(position, rel=1e-5)
    assert effect["attitude_1h"] == pytest.approx(attitude, rel=1e-5)
    assert effect["position_case_1h"] == "initial delta_V"
    # the hand's loop grows as e^{ω_s t}: 107 e-foldings in a day
    assert effect["e_folding_s"] == pytest.approx(1 / OMEGA_S, rel=1e-6)
    position_24, _ = _worst({"psi_V": -1 / R}, 24.0)
    assert effect["position_24h"] == pytest.approx(position_24, rel=1e-5)
    line = next(s for s in out.splitlines() if "effect:" in s)
    assert "1 h: 28.3 km, 918″" in line
    assert f"24 h: grows exponentially, ×e every {1 / OMEGA_S / 60:.3g} min" in line


def test_a_huge_coefficient_of_a_model_term_is_a_wrong_coefficient(tmp_path, capsys):
    """∇ written 1e15 ∇: the model has the term (coefficient 1), so this is a wrong
    coefficient with its ratio, not an "extra term" (the model's 1 was taken for zero
    against the hand's 1e15); its effect is the propagated one, 1e15 times the bias's."""
    effect, out = _effect(tmp_path, capsys, CORRECT.replace("+ accel_bias",
                                                            "+ 1e15*accel_bias"))
    row = next(s for s in out.splitlines() if "accel_bias" in s and "mistake" in s)
    assert "wrong coefficient" in row and "extra term" not in row
    assert "hand/model = 1e+15 at every point" in out
    position, _ = _worst({"V_bias": 1e15}, 1.0)
    assert effect["position_1h"] == pytest.approx(position, rel=1e-5)
    assert effect["position_case_1h"] == "source accel_bias"


def test_a_propagation_that_overflows_is_no_figure_below_the_floor(tmp_path, capsys):
    """∇ written 1e300 ∇: the mistake's propagation passes the largest double (its
    exponential is inf and NaN); that was shown as "< 5e-11 m", a 1e300-fold error
    called negligible. It is said to overflow (JSON: the figure null, overflow true)."""
    effect, out = _effect(tmp_path, capsys, CORRECT.replace("+ accel_bias",
                                                            "+ 1e300*accel_bias"))
    assert "hand/model = 1e+300 at every point" in out
    for tag in ("1h", "24h"):
        assert effect[f"overflow_{tag}"] is True
        assert effect[f"position_{tag}"] is None and effect[f"attitude_{tag}"] is None
    line = next(s for s in out.splitlines() if "effect:" in s)
    assert "1 h: overflows" in line and "24 h: overflows" in line and "<" not in line


def test_rounding_floor_instead_of_noise(tmp_path, capsys):
    """δφ' = δV (R dropped) changes the position only: the tilt is exactly the model's,
    so the attitude effect is below its rounding floor, not a figure like 7e-13″."""
    effect, out = _effect(tmp_path, capsys, CORRECT.replace("dot(delta_phi) = delta_V/R",
                                                            "dot(delta_phi) = delta_V"))
    position, attitude = _worst({"phi_V": 1.0}, 1.0)
    assert attitude == 0.0
    assert effect["position_1h"] == pytest.approx(position, rel=1e-6)
    assert "e_folding_s" not in effect
    for tag in ("1h", "24h"):
        assert 0 <= effect[f"attitude_{tag}"] <= effect[f"attitude_floor_{tag}"]
        assert effect[f"attitude_case_{tag}"] is None
        # the floor is far below any position figure that matters
        assert effect[f"position_floor_{tag}"] < 1e-9 * effect[f"position_{tag}"]
    line = next(s for s in out.splitlines() if "effect:" in s)
    assert "1 h: 2.21e+07 km, < " in line and "(source gyro_drift)" in line


def test_the_models_own_growing_mode_is_named():
    """strapdown_ned's undamped vertical channel grows as e^{t/τ}, τ = √(R/2g) ≈ 9.5 min
    (textbook). A wrong sign in δh' = −δv_D changes a difference that grows with it:
    after 24 h that is said, not printed as a figure of 1e65 km; after 1 h (6 e-foldings)
    the figure stays."""
    from ins_errors.checker.compare import check_hand
    from ins_errors.checker.notation import default_notation
    from ins_errors.checker.parse import parse_hand_text
    from ins_errors.checker.report import to_terminal

    text = "dot(Delta_h) = Delta_v_D\n"
    report = check_hand(parse_hand_text(text, default_notation("strapdown_ned")),
                        model="strapdown_ned")
    ((_, finding),) = report.mistakes
    effect = finding.effect
    tau = math.sqrt(6_378_137.0 / (2 * 9.81))
    assert effect["growing_mode"] == "model"
    assert effect["e_folding_s"] == pytest.approx(tau, rel=3e-3)
    assert (effect["exponential_1h"], effect["exponential_24h"]) == (False, True)
    assert 0 < effect["position_1h"] < 1e5
    assert f"24 h: grows exponentially, ×e every {effect['e_folding_s'] / 60:.3g} min " \
           "(the model's own mode)" in to_terminal(report)


def test_a_difference_the_models_own_mode_does_not_reach_keeps_its_figure():
    """The rule behind the model's own mode: strapdown_ned's frozen F at rest grows as
    e^{t/τ}, τ = √(R/2g) ≈ 9.5 min (textbook), 145 e-foldings in 23 h. A difference that
    did not grow with it (a horizontal, Schuler-bounded one: 1.35 km after 1 h, 2.7 km
    after 24 h) keeps its 24-h figure; one that did grow by more than e^10 since 1 h is
    said to grow exponentially. (Through the Coriolis term 2U cos φ δv_D every state of
    the undamped model is reached by its vertical mode, so no single hand line gives the
    first case: the rule is driven directly with the model's own rate.)"""
    import ins_errors
    from ins_errors.checker.growth import growth_rate, mark_growth
    from ins_errors.numeric import strapdown_truth as st

    model = ins_errors.load_model("strapdown_ned")
    p = model.parameter_vector()
    traj = st.trajectory(model, st.static(math.radians(45.0)), 1.0, 1.0)
    F = model.numpy.state_matrix(traj.truth[:, 0], traj.inputs[:, 0], p)
    rate = growth_rate(F)
    tau = math.sqrt(6_378_137.0 / (2 * 9.81))
    assert 1 / rate == pytest.approx(tau, rel=3e-3)
    floors = {"position_floor_1h": 4e-8, "position_floor_24h": 1e-6}
    bounded = {"position_1h": 1354.0, "position_24h": 2708.0, **floors}
    mark_growth(bounded, rate, rate)
    assert bounded["growing_mode"] == "model"
    assert (bounded["exponential_1h"], bounded["exponential_24h"]) == (False, False)
    assert bounded["position_24h"] == 2708.0  # the figure stays
    # grown with the mode since 1 h (e^{23 h/τ} ≈ e^145): said to grow
    grown = {"position_1h": 1354.0, "position_24h": 1354.0 * math.exp(23 * 3600 / tau),
             **floors}
    mark_growth(grown, rate, rate)
    assert (grown["exponential_1h"], grown["exponential_24h"]) == (False, True)
    # nothing at all (below the floor both times) is not growth either
    nothing = {"position_1h": 1e-9, "position_24h": 5e-7, **floors}
    mark_growth(nothing, rate, rate)
    assert nothing["exponential_24h"] is False


STRAPDOWN_LOOP = '''"""The Schuler loop of a strapdown computer: the tilt is the
computer's pitch θ, a state of its own (no platform angle), read out as ``pitch``."""
import sympy as sp

from ins_errors.modeling import (Mechanisation, ModelDefinition, Parameter, Variable,
                                 computed_symbols, error_source, error_states_of)

STATES = (Variable("V", "m/s", "north velocity", "V"),
          Variable("phi", "rad", "latitude", r"\\\\varphi"),
          Variable("theta", "rad", "computed pitch of the body", r"\\\\theta"))
INPUTS = (Variable("a_N", "m/s**2", "true north specific force", "a_N"),)
PARAMETERS = (Parameter("R", "m", "Earth radius", "R", 6_371_000.0),
              Parameter("g", "m/s**2", "gravity", "g", 9.80665))
SOURCES = (error_source("gyro_drift", "rad/s", "deg/h", "constant", None, r"\\\\varepsilon",
                        "pitch gyro drift"),
           error_source("accel_bias", "m/s**2", "ug", "constant", None, r"\\\\nabla",
                        "accelerometer bias"),
           error_source("initial_tilt", "rad", "arcsec", "initial", None, r"\\\\theta_0",
                        "initial pitch error"))
OUTPUTS = (Variable("latitude", "rad", "latitude", r"\\\\varphi"),
           Variable("v_N", "m/s", "north velocity", "v_N"),
           Variable("pitch", "rad", "pitch", r"\\\\theta"))
INITIAL_CONDITIONS = (Variable("latitude", "rad", "initial latitude", r"\\\\varphi_0"),
                      Variable("v_N", "m/s", "initial north velocity", "v_{N0}"))
V, phi, theta = (v.symbol for v in STATES)
V_c, phi_c, theta_c = computed_symbols(STATES)
(a_N,) = (v.symbol for v in INPUTS)
R, g = (v.symbol for v in PARAMETERS)
drift, bias, tilt0 = (v.symbol for v in SOURCES)


def outputs(eq, state, inputs):
    velocity, latitude, pitch = state
    return sp.Matrix([latitude, velocity, pitch])


def build():
    ideal = Mechanisation()
    ideal_rhs = sp.Matrix([a_N * sp.cos(theta) + g * sp.sin(theta), V / R, V / R - V / R])
    real = Mechanisation(computed=True)
    real_rhs = sp.Matrix([(a_N + bias) * sp.cos(theta_c) + g * sp.sin(theta_c), V_c / R,
                          V / R + drift - V_c / R])
    lat0, v0 = (v.symbol for v in INITIAL_CONDITIONS)
    return ModelDefinition(
        name="strapdown_loop", title="Strapdown Schuler loop", source="a test",
        states=STATES, error_states=error_states_of(STATES, []),
        real_states=[V_c, phi_c, theta_c], inputs=INPUTS, parameters=PARAMETERS,
        sources=SOURCES, outputs=OUTPUTS, initial_conditions=INITIAL_CONDITIONS,
        ideal=ideal, real=real, ideal_rhs=ideal_rhs, real_rhs=real_rhs,
        output_map=outputs, initial_state=sp.Matrix([v0, lat0, 0]),
        initial_real_state=sp.Matrix([v0, lat0, tilt0]))
'''


def test_a_model_without_platform_angles_reads_its_attitude_outputs(tmp_path, capsys,
                                                                     monkeypatch):
    """A strapdown computer's tilt is a state of its own, not a platform angle: the
    attitude effect was printed as 0″ for every mistake. It is read from the pitch output
    now; with ψ = −θ the loop is the tutorial's, so the figures are _worst's."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    model = tmp_path / "strapdown_loop.py"
    model.write_text(STRAPDOWN_LOOP, encoding="utf-8")
    hand = tmp_path / "hand.txt"
    hand.write_text("dot(delta_V) = g*delta_theta + accel_bias\ndot(delta_phi) = delta_V/R\n"
                    "dot(delta_theta) = delta_V/R + gyro_drift\n", encoding="utf-8")
    assert main(["check", str(model), str(hand), "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    (effect,) = [f["effect"] for e in data["equations"] for f in e["findings"]
                 if f.get("effect")]
    position, attitude = _worst({"psi_V": -1 / R}, 1.0)
    assert effect["attitude_1h"] == pytest.approx(attitude, rel=1e-5)
    assert effect["position_1h"] == pytest.approx(position, rel=1e-5)


def test_an_effect_without_any_attitude_reading_says_so():
    from ins_errors.checker.classify import Finding
    from ins_errors.checker.report import _effect as effect_text

    effect = {"point": "static", "position_1h": 12.0, "position_24h": 340.0,
              "attitude_1h": None, "attitude_24h": None}
    finding = Finding.__new__(Finding)
    object.__setattr__(finding, "effect", effect)
    text = effect_text(finding)
    assert "attitude n/a" in text and "0″" not in text


NORTH_POINTING_HAND = ROOT / "tests" / "data" / "hand_correct_north_pointing.txt"


def test_a_larger_effect_at_another_point_is_named(tmp_path, capsys):
    """The Coriolis part 2U sin φ left out of δv_N's coefficient in δv_E' differs most,
    relative to the coefficient, at the 2000-km cruise (where V_E tan φ/R adds to it),
    but its error grows most at rest: 1.39 km after a day at the cruise, 3.46 km at the
    static base (the referee probe's finding). The static-base figure is named beside
    the cruise's and equals the effect of the same slip checked at the static base alone."""
    slip = NORTH_POINTING_HAND.read_text(encoding="utf-8").replace(
        "accel_bias_east + turn_rate*Delta_v_N", "accel_bias_east + V_E*tan(phi)/r_E*Delta_v_N")
    assert slip != NORTH_POINTING_HAND.read_text(encoding="utf-8")

    def effect(text: str) -> tuple[dict, str]:
        hand = tmp_path / "hand.txt"
        hand.write_text(text, encoding="utf-8")
        assert main(["check", "north_pointing", str(hand), "--json"]) == 1
        data = json.loads(capsys.readouterr().out)
        (found,) = [f["effect"] for e in data["equations"] for f in e["findings"]
                    if f.get("effect")]
        assert main(["check", "north_pointing", str(hand)]) == 1
        return found, capsys.readouterr().out

    moving, out = effect(slip)
    at_rest, _ = effect("@scope static base\n" + slip)
    assert at_rest["point"] == "static base" and "largest_point" not in at_rest
    assert moving["point"] != "static base"
    assert moving["largest_point"] == "static base"
    assert moving["largest_24h"] == pytest.approx(at_rest["position_24h"], rel=1e-9)
    assert moving["largest_24h"] > 1.5 * moving["position_24h"]
    line = next(s for s in out.splitlines() if "effect:" in s)
    assert line.endswith("larger at static base: 24 h: 3.46 km")
