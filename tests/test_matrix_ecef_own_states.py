"""A hand F in the own states of an ECEF strapdown INS (tests/models/ecef_ins.py): no state
is a north or east position, and none is the vertical channel; and ``nav.gravity`` of a
model file without a parameter g.

References, independent of the checker:

* the static base propagated with SciPy's matrix exponential: Groves' ECEF error model
  (tests/data/ecef_vr.py) turned into NED by C_e^n, its down velocity and position held
  (rows and columns zeroed, as the checker holds dv_D, dr_D), read as north and east
  metres; the attitude error of the computed frame, δθ = (δλ cos φ, −δφ, −δλ sin φ);
* the gravity of the model's equations written out: |−μ r/|r|³ − Ω × (Ω × r)|, and the
  fixture tests/models/enu_strapdown.py's γ(φ) (a/(a + h))².
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from ins_errors import load_model
from ins_errors.checker.check_motions import motions
from ins_errors.checker.matrix import check_matrices
from ins_errors.checker.matrix_report import to_json, to_terminal
from ins_errors.cli import main

HERE = Path(__file__).resolve().parent
MODEL = str(HERE / "models" / "ecef_ins.py")
HAND = HERE / "data" / "ecef_vr.py"
G0 = 9.80665
MU, R, U = 3.986004418e14, 6_371_000.0, 7.292115e-5
LAT, LON, HEADING = np.radians(50.0), np.radians(30.0), np.radians(30.0)


def _hand_module():
    spec = importlib.util.spec_from_file_location("ecef_vr_reference", HAND)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _static_sample():
    """The static base's navigation state and IMU (rest at φ 50°, λ 30°, heading 30°)."""
    from types import SimpleNamespace

    ch, sh = np.cos(HEADING), np.sin(HEADING)
    nav = SimpleNamespace(latitude=LAT, longitude=LON, height=0.0, a=R, earth_rate=U,
                          C_bn=np.array([[ch, -sh, 0.0], [sh, ch, 0.0], [0.0, 0.0, 1.0]]))
    return nav, None


def _static_reference(F_hand: np.ndarray, F_model: np.ndarray, G: np.ndarray, hours: float
                      ) -> list[tuple[float, float, float]]:
    """(position Δ m, derived position m, attitude Δ rad) of each case (initial δv_X..Z at
    0.1 m/s, δr_X..Z at 10 m, accel_bias_x..z at 1e-4 g) on the static base."""
    C = _hand_module().ecef_to_ned(LAT, LON)
    M = np.kron(np.eye(2), C)  # (δv, δr) ECEF -> NED (v = 0 at rest)
    vertical = [2, 5]
    out = []
    for case in range(9):
        responses = []
        for F in (F_hand, F_model):
            A = np.zeros((9, 9))
            A[:6, :6] = M @ F @ M.T
            A[:6, 6:] = M @ G
            A[vertical, :] = 0.0
            A[:, vertical] = 0.0
            start = np.zeros(9)
            start[case] = 0.1 if case < 3 else 10.0 if case < 6 else 1e-4 * G0
            start[:6] = M @ start[:6]
            start[vertical] = 0.0
            responses.append((expm(A * hours * 3600.0) @ start)[3:5])
        d = responses[0] - responses[1]
        # attitude of the computed NED frame: δθ from the north and east position errors
        theta = np.array([d[1] / R, -d[0] / R, -d[1] * np.tan(LAT) / R])
        out.append((float(np.linalg.norm(d)), float(np.linalg.norm(responses[1])),
                    float(np.linalg.norm(theta))))
    return out


@pytest.fixture(scope="module")
def slip():
    return check_matrices(MODEL, f"{HAND}:coriolis_slip", "model")


def test_an_ecef_hand_model_reads_its_position_through_the_states(slip):
    # the check finds the slip (both Coriolis entries of the equatorial plane)
    [f] = [f for f in slip.findings if {(f.row, f.column), f.pair}
           == {("delta_v_X", "delta_v_Y"), ("delta_v_Y", "delta_v_X")}]  # one finding
    assert f.kind == "wrong sign"
    module = _hand_module()
    nav, imu = _static_sample()
    F_exact, G = module.exact(nav, imu)
    F_slip, _ = module.coriolis_slip(nav, imu)
    for hours in (1.0, 24.0):
        reference = _static_reference(F_slip, F_exact, G, hours)
        effects = [e for e in slip.effects if e.motion == "static" and e.hours == hours]
        assert [e.case for e in effects] == (
            [f"initial delta_{q}_{a}" for q in "vr" for a in "XYZ"]
            + [f"source accel_bias_{a}" for a in "xyz"])
        for e, (position, own, attitude) in zip(effects, reference, strict=True):
            assert e.position_difference == pytest.approx(position, rel=1e-6)
            assert e.position_model == pytest.approx(own, rel=1e-6, abs=1e-9)
            assert e.attitude_difference == pytest.approx(attitude, rel=1e-6)
        worst = max(effects, key=lambda e: e.position_difference)
        assert worst.position_difference > 1e6 * worst.position_floor
    # 1.16 km: the slip's worst case after a day at rest (29.6 m after an hour)
    assert 1000.0 < worst.position_difference < 1300.0
    # the finding's effect is its mirror pair's, both entries (the whole slip here)
    F_one = F_exact.copy()
    F_one[0, 1], F_one[1, 0] = F_slip[0, 1], F_slip[1, 0]
    alone = slip.finding_effects[f.entry]
    assert alone.position == pytest.approx(
        max(p for p, _, _ in _static_reference(F_one, F_exact, G, 24.0)), rel=1e-6)
    assert 1000.0 < alone.position < 1300.0
    # one entry alone (its partner kept right) breaks the antisymmetry: 1.97e5 m
    F_one[1, 0] = F_exact[1, 0]
    assert max(p for p, _, _ in _static_reference(F_one, F_exact, G, 24.0)) > 100 * (
        alone.position)
    text = to_terminal(slip)
    assert f"the pair together after 24 h: {alone.position:.3g} m" in text
    assert ("vertical channel held: the down velocity and position of the states (dv_D, "
            "dr_D of the phi convention)") in text
    assert " 0 m " not in text and "(0 m, 0″)" not in text


def test_a_left_out_state_that_nothing_excites_is_not_assessed(slip):
    # the attitude coupling F[δv, δC] is left out, but from a velocity, position or
    # accelerometer error the attitude error of the ECEF model stays 0: its effect is not
    # measured here, which the report says instead of "no effect"
    f = slip.finding("delta_v_X", "delta_CXz")
    assert f.kind == "state left out" and f.size_class == "major"
    said = ("effect not assessed: delta_CXz, a state the hand leaves out, stays 0 from "
            "every initial error and source of the hand")
    assert slip.finding_effects[f.entry].not_assessed == said
    assert said in to_terminal(slip)
    finding = next(x for x in to_json(slip)["findings"] if x["column"] == "delta_CXz")
    assert finding["effect_not_assessed"] == said


def test_the_vertical_channel_of_ecef_states_is_held_as_in_the_phi_convention():
    # the derived model's own error from each accelerometer bias: in the ECEF states with
    # the vertical held through the φ-angle frame, and in the φ-angle convention with
    # dv_D, dr_D held, on every motion (the same propagation in two sets of states, up to
    # the second-order steps of a moving motion)
    own = check_matrices(MODEL, f"{HAND}:exact", "model")
    assert {(f.kind, f.column[:7]) for f in own.findings} == {("state left out", "delta_C")}

    def phi_hand(nav, imu):
        return np.zeros((6, 6)), np.zeros((6, 3))

    phi_hand.states = ["dv_N", "dv_E", "dv_D", "dr_N", "dr_E", "dr_D"]
    phi_hand.sources = ["accel_bias_x", "accel_bias_y", "accel_bias_z"]
    phi = check_matrices(MODEL, phi_hand, "phi", effects=True)
    compared = 0
    for e in own.effects:
        if e.case.startswith("source"):
            [other] = [x for x in phi.effects if (x.motion, x.hours, x.case)
                       == (e.motion, e.hours, e.case)]
            assert e.position_model == pytest.approx(other.position_model, rel=1e-2,
                                                     abs=1e-6)
            compared += e.position_model > 10.0  # (a level z accelerometer: ~0 m)
    assert compared >= 12
    # the exact hand model agrees in its own states: no difference above rounding
    assert all(not e.position_above_rounding for e in own.effects)


def test_a_hand_model_without_position_states_reports_no_position(capsys):
    status = main(["check", MODEL, "--matrix", f"{HAND}:velocity_only", "--json"])
    report = json.loads(capsys.readouterr().out)
    assert status == 1  # the gravity coupling into δr is a state left out
    assert report["effects"]
    for e in report["effects"]:
        assert e["position_difference_m"] is None and e["position_model_m"] is None
        assert e["position_floor_m"] is None and e["position_below_rounding"] is None
        assert e["attitude_difference_rad"] is None
    for f in report["findings"]:
        if f["effect_alone_24h"] is not None and f["effect_not_assessed"] is None:
            assert f["effect_alone_24h"]["position_m"] is None
    main(["check", MODEL, "--matrix", f"{HAND}:velocity_only"])
    text = capsys.readouterr().out
    assert "position n/a" in text and "attitude n/a" in text
    assert " 0 m " not in text and "no effect above rounding" not in text.split(
        "Effect of the differences")[1]


def test_nav_gravity_is_the_gravity_of_the_models_own_equations():
    from ins_errors.checker.navigation import navigation_arrays

    model = load_model(MODEL)
    earth = np.array([0.0, 0.0, U])
    for motion in motions(model)[:2]:  # at rest at h = 0, and the cruise at 10 km
        nav = motion.navigation
        lat, lon, h = nav["latitude"], nav["longitude"], nav["height"]
        r = (R + h) * np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon),
                                np.sin(lat)])
        g = -MU * r / np.linalg.norm(r, axis=0)**3 - np.cross(earth, np.cross(earth, r.T)).T
        np.testing.assert_allclose(nav["gravity"], np.linalg.norm(g, axis=0), rtol=1e-12)
    # at rest the accelerometers read it (what `ins-errors modes` takes as g): 9.806267,
    # not the WGS-84 normal-gravity formula with e² = 0 (9.791413)
    static = motions(model)[0].navigation
    np.testing.assert_allclose(static["gravity"], np.linalg.norm(static["f_b"], axis=0),
                               rtol=1e-12)
    assert static["gravity"][0] == pytest.approx(9.806267, abs=1e-6)
    # a model file with normal gravity falling off as (a/(a + h))²
    enu = load_model(str(HERE / "models" / "enu_strapdown.py"))
    cruise = motions(enu)[1]
    p = dict(zip((q.name for q in enu.parameters), cruise.p, strict=True))
    nav = navigation_arrays(enu, cruise.x, cruise.u, cruise.p)
    s2 = np.sin(nav["latitude"])**2
    a, e2 = p["a"], p["e2"]
    gamma = p["gamma_e"] * (1 + p["gk"] * s2) / np.sqrt(1 - e2 * s2)
    np.testing.assert_allclose(nav["gravity"], gamma * (a / (a + nav["height"]))**2,
                               rtol=1e-12)
