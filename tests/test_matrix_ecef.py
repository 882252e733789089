"""The Earth-fixed convention ``psi_ecef``: a hand-coded ECEF error model (Groves 2013,
ch. 14: ψ^e, δv^e, δr^e) is checked in its own states against any self-describing
strapdown model.

References, independent of the code under test:

* the ECEF attitude, velocity and position of a perturbed state, computed here with
  numpy from the model's own state (complex-step derivatives: exact to rounding);
  an ECEF-mechanised model file (tests/models/ecef_ins.py) whose own states *are*
  C_b^e, v^e and r^e;
* Groves' ECEF F and G coded from the textbook in tests/data/groves_ecef.py (with the
  gravity gradient of that model's point-mass gravity);
* the ψ-angle (NED) convention, through the change of states T_l = blockdiag(−C_e^n,
  C_e^n, C_e^n), Ṫ_l T_l⁻¹ = −I ⊗ [ω_en×] (what a researcher did by hand before);
* ½ b t² − (b/ω_s²)(1 − cos ω_s t), the position error an accelerometer bias gives
  without and with the Schuler loop.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.checker.check_motions import motions
from ins_errors.checker.conventions import conventions
from ins_errors.checker.matrix import check_matrices, derived_in_convention
from ins_errors.checker.matrix_report import to_json, to_terminal
from ins_errors.errors import InsErrorsError
from ins_errors.models import strapdown_conventions as sc

ROOT = Path(__file__).resolve().parent
ECEF_MODEL = str(ROOT / "models" / "ecef_ins.py")
GROVES = ROOT / "data" / "groves_ecef.py"
SPHERE = ROOT.parent / "examples" / "strapdown" / "strapdown_sphere.py"
SPHERE_GROVES = ROOT.parent / "examples" / "strapdown" / "groves_ecef.py"
MU = 3.986004418e14
G0 = 9.80665


def _hand(function: str) -> str:
    return f"{GROVES}:{function}"


def _c_en(lat, lon):
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def _skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


@pytest.fixture(scope="module")
def reports():
    """The Groves hand functions against the ECEF model file, with effects."""
    return {name: check_matrices(ECEF_MODEL, _hand(name), "psi_ecef")
            for name in ("groves_exact", "groves_coriolis_slip", "groves_no_gradient")}


def test_the_ecef_rows_are_the_errors_of_c_be_v_e_and_r_e(monkeypatch):
    """strapdown_ned (quaternion, NED, WGS-84): T e = (ψ^e, δv^e, δr^e) of the perturbed
    state, ψ^e with Groves' sign [ψ^e×] = δC_b^e C_b^eᵀ; the closed forms of the module
    docstring (−C_n^e ψ, C_n^e dvc, C_n^e dr) hold."""
    model = load_model("strapdown_ned")
    p = model.parameter_vector()
    a, e2 = p[0], p[1]
    rng = np.random.default_rng(7)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    x = np.concatenate([q, [120.0, -80.0, 3.0], [np.radians(50), np.radians(30), 4000.0]])

    def ecef(x):  # complex-safe: C_b^e, v^e, r^e of a strapdown_ned state
        q0, q1, q2, q3 = x[:4] / np.sqrt(np.sum(x[:4] ** 2))
        C = np.array([[q0*q0 + q1*q1 - q2*q2 - q3*q3, 2*(q1*q2 - q0*q3), 2*(q1*q3 + q0*q2)],
                      [2*(q1*q2 + q0*q3), q0*q0 - q1*q1 + q2*q2 - q3*q3, 2*(q2*q3 - q0*q1)],
                      [2*(q1*q3 - q0*q2), 2*(q2*q3 + q0*q1), q0*q0 - q1*q1 - q2*q2 + q3*q3]])
        lat, lon, h = x[7:10]
        N = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
        r = np.array([(N + h) * np.cos(lat) * np.cos(lon), (N + h) * np.cos(lat) * np.sin(lon),
                      (N * (1 - e2) + h) * np.sin(lat)])
        C_ne = _c_en(lat, lon).T
        return C_ne @ C, C_ne @ x[4:7], r

    T = sc.transform_matrix("psi_ecef", x, p)
    T_psi = sc.transform_matrix("psi", x, p)
    C_ne = _c_en(x[7], x[8]).T
    C_be = ecef(x)[0].real
    for _ in range(4):
        e = rng.normal(size=10) * np.array([1e-4] * 4 + [0.1] * 3 + [1e-6, 1e-6, 10.0])
        e[:4] -= q * (q @ e[:4])
        step = 1e-20
        dC, dv, dr = (part.imag / step for part in ecef(x + 1j * step * e))
        W = dC @ C_be.T
        expected = np.concatenate([[W[2, 1], W[0, 2], W[1, 0]], dv, dr])
        got = T @ e
        assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
        assert np.abs(W + W.T).max() <= 1e-12 * np.abs(W).max()  # a rotation
        z = T_psi @ e
        closed = np.concatenate([-C_ne @ z[:3], C_ne @ z[3:6], C_ne @ z[6:9]])
        assert np.abs(got - closed).max() <= 1e-12 * np.abs(got).max()
    with pytest.raises(InsErrorsError, match="position-error form"):
        sc.convention("psi_ecef", "geodetic")


def test_an_ecef_model_files_own_states_are_its_ecef_convention_states():
    """tests/models/ecef_ins.py keeps C_b^e, v^e, r^e: in psi_ecef its velocity and
    position error states are its own (identity rows), its attitude rows the axial vector
    of δC C_b^eᵀ."""
    model = load_model(ECEF_MODEL)
    motion = motions(model, hours=0.5, step=600.0)[2]  # the manoeuvre
    conv = conventions(model)["psi_ecef"]
    T, _ = conv.matrices(model, motion.x, motion.p, motion.u)
    for k in range(T.shape[0]):
        C = motion.x[:9, k].reshape(3, 3)
        expected = np.zeros((9, 15))
        for j in range(9):  # δC = unit matrix at entry j
            dC = np.zeros(9)
            dC[j] = 1.0
            W = dC.reshape(3, 3) @ C.T
            expected[0:3, j] = 0.5 * np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0],
                                               W[1, 0] - W[0, 1]])
        expected[3:9, 9:15] = np.eye(6)
        np.testing.assert_allclose(T[k], expected, rtol=0, atol=1e-12)


def test_ecef_readouts_are_those_of_the_psi_convention_carried_over():
    """Position (NED m) and attitude error (φ, NED rad) read from ECEF states equal the ψ
    convention's read-outs through T_l (δr^n = C_e^n δr^e, φ = −C_e^n ψ^e + δθ)."""
    model = load_model("strapdown_ned")
    motion = motions(model, hours=0.5, step=600.0)[2]
    nav = motion.navigation
    conv, psi = conventions(model)["psi_ecef"], conventions(model)["psi"]
    for k in range(len(motion.times)):
        C = _c_en(nav["latitude"][k], nav["longitude"][k])
        T_l = np.zeros((9, 9))
        T_l[0:3, 0:3], T_l[3:6, 3:6], T_l[6:9, 6:9] = -C, C, C
        for read in ("position", "attitude"):
            ecef = getattr(conv, read)(nav)[:, :, k]
            ned = getattr(psi, read)(nav)[:, :, k]
            np.testing.assert_allclose(ecef, ned @ T_l, rtol=0, atol=1e-15)


@pytest.mark.parametrize("model_name", ["strapdown_ned", str(SPHERE)])
def test_derived_model_in_ecef_is_the_psi_model_carried_by_hand(model_name):
    """F_e = T_l⁻¹ (F_ψ − W) T_l and G_e = T_l⁻¹ G_ψ along a manoeuvre, W = −I ⊗ [ω_en×]:
    the change of states a researcher would otherwise write by hand."""
    model = load_model(model_name)
    motion = motions(model, hours=1.0, step=300.0)[2]
    convs = conventions(model)
    F_e, G_e = derived_in_convention(model, convs["psi_ecef"], motion)
    F_p, G_p = derived_in_convention(model, convs["psi"], motion)
    nav = motion.navigation
    for k in range(len(motion.times)):
        C = _c_en(nav["latitude"][k], nav["longitude"][k])
        T_l = np.zeros((9, 9))
        T_l[0:3, 0:3], T_l[3:6, 3:6], T_l[6:9, 6:9] = -C, C, C
        W = np.kron(np.eye(3), -_skew(nav["omega_en_n"][:, k]))
        scale = np.abs(F_p[k]).max()
        np.testing.assert_allclose(F_e[k], T_l.T @ (F_p[k] - W) @ T_l, rtol=0,
                                   atol=1e-9 * scale)
        np.testing.assert_allclose(G_e[k], T_l.T @ G_p[k], rtol=0,
                                   atol=1e-12 * np.abs(G_p[k]).max())


def test_groves_exact_ecef_model_agrees_to_rounding_on_every_motion(reports):
    report = reports["groves_exact"]
    assert report.compared == 135 and report.findings == [] and not report.mistakes
    assert [m for m, _ in report.motions] == ["static", "cruise", "manoeuvre"]
    assert report.effects and all(not e.position_above_rounding
                                  and not e.attitude_above_rounding for e in report.effects)
    # floors of a held vertical channel (the NED conventions': 5e-8 to 9e-8 m after 24 h)
    assert max(e.position_floor for e in report.effects) < 1e-6
    assert report.held == ["the vertical (down) components of δv^e and δr^e"]
    assert "vertical channel held: the vertical (down) components" in to_terminal(report)


def test_the_15_state_ecef_filter_agrees_with_its_bias_states():
    report = check_matrices(ECEF_MODEL, _hand("groves_15"), "psi_ecef", effects=False)
    assert report.compared == 225 and report.findings == []
    assert [b.name for b in report.bias_states][:3] == ["gyro_bias_x", "gyro_bias_y",
                                                        "gyro_bias_z"]


def test_a_coriolis_sign_slip_is_the_two_entries_wrong_sign(reports):
    """Both Coriolis entries of the equatorial plane, opposite differences: one finding
    of the mirror pair, whose effect is the pair's (here the whole hand's)."""
    report = reports["groves_coriolis_slip"]
    [f] = report.findings
    assert {(f.row, f.column), f.pair} == {("dv_X", "dv_Y"), ("dv_Y", "dv_X")}
    U = 7.292115e-5
    assert f.kind == "wrong sign" and f.severity == "mistake"
    assert abs(f.hand) == pytest.approx(2 * U, rel=1e-9)
    assert f.hand == pytest.approx(-f.model, rel=1e-9)
    alone = report.finding_effects[f.entry]  # finite, above rounding
    assert alone.position_above_rounding and 1e3 < alone.position < 1e7
    assert not alone.exponential
    whole = max(e.position_difference for e in report.effects if e.hours == 24)
    assert alone.position == pytest.approx(whole, rel=1e-9)


def test_held_ecef_effects_are_those_of_the_psi_convention(tmp_path):
    """The slipped Groves model carried into ψ states by hand and checked in ``psi``
    (dvc_D, dr_D held) gives the effect of every error source of the ECEF check (its
    vertical channel held through ``hold``): on the static base to rounding; along the
    moving motions to the propagation's own discretisation (the exponential of the mean
    F of each step, taken in the other frame): it falls fourfold when the step halves."""
    hand = tmp_path / "groves_in_psi.py"
    hand.write_text(
        "import numpy as np\n"
        f"import sys; sys.path.insert(0, {str(GROVES.parent)!r})\n"
        "from groves_ecef import groves, ecef_to_ned, skew, SOURCES\n"
        "STATES = ['psi_N', 'psi_E', 'psi_D', 'dvc_N', 'dvc_E', 'dvc_D', 'dr_N', 'dr_E',"
        " 'dr_D']\n"
        "def slip(nav, imu):\n"
        "    F, G = groves(nav, imu, coriolis=+2.0)\n"
        "    C = ecef_to_ned(nav.latitude, nav.longitude)\n"
        "    T = np.zeros((9, 9))\n"
        "    T[0:3, 0:3], T[3:6, 3:6], T[6:9, 6:9] = -C, C, C\n"
        "    W = np.kron(np.eye(3), -skew(nav.omega_en_n))\n"
        "    return T @ F @ T.T + W, T @ G\n", encoding="utf-8")
    worst = {}
    for step in (60.0, 30.0):
        ned = check_matrices(ECEF_MODEL, f"{hand}:slip", "psi", hours=1.0, step=step)
        ecef = check_matrices(ECEF_MODEL, _hand("groves_coriolis_slip"), "psi_ecef",
                              hours=1.0, step=step)
        by_case = {(e.motion, e.case): e for e in ned.effects}
        moving = []
        for e in ecef.effects:
            if not e.case.startswith("source") or not e.position_above_rounding:
                continue
            other = by_case[(e.motion, e.case)]
            for mine, theirs in ((e.position_difference, other.position_difference),
                                 (e.attitude_difference, other.attitude_difference),
                                 (e.position_model, other.position_model)):
                if e.motion == "static":
                    assert mine == pytest.approx(theirs, rel=1e-12)
                else:
                    moving.append(abs(mine / theirs - 1))
        assert len(moving) == 3 * (5 + 6)  # (accel_bias_z on the cruise: below rounding)
        worst[step] = max(moving)
    assert worst[60.0] < 1e-3 and 3.0 < worst[60.0] / worst[30.0] < 5.0


def test_a_dropped_gravity_gradient_is_the_f_vr_entries(reports):
    """Γ δr^e left out: the nine F[dv_i, dr_j] entries are omitted terms; without the
    Schuler loop an accelerometer bias b gives ½ b t² where the model gives
    (b/ω_s²)(1 − cos ω_s t): their difference after 1 h on the static base."""
    report = reports["groves_no_gradient"]
    found = {(f.row, f.column) for f in report.findings}
    assert found == {(f"dv_{i}", f"dr_{j}") for i in "XYZ" for j in "XYZ"}
    assert {f.kind for f in report.findings} == {"omitted term"}
    assert all(f.severity == "mistake" for f in report.findings)
    (effect,) = [e for e in report.effects if (e.motion, e.hours, e.case)
                 == ("static", 1.0, "source accel_bias_x")]
    b, t, R = 1e-4 * G0, 3600.0, 6_371_000.0
    w_s = np.sqrt(MU / R**3)
    expected = 0.5 * b * t**2 - b / w_s**2 * (1 - np.cos(w_s * t))
    assert effect.position_difference == pytest.approx(expected, rel=0.03)


def test_ecef_check_of_the_example_sphere_and_its_json(capsys):
    """examples/strapdown/groves_ecef.py (Groves' equations with strapdown_sphere.py's
    constant-g gradient) agrees; the JSON names what is held."""
    import json

    from ins_errors.cli import main

    status = main(["check", str(SPHERE), "--matrix", f"{SPHERE_GROVES}:groves_ecef",
                   "--convention", "psi_ecef", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert status == 0 and out["findings"] == [] and out["compared"] == 135
    assert out["held"] == ["the vertical (down) components of δv^e and δr^e"]


def test_part_of_an_ecef_triple_gets_no_held_effects(tmp_path):
    """dv_X, dv_Y without dv_Z cannot be held: the check compares, and says why no
    effects are given (instead of figures swamped by the vertical channel)."""
    hand = tmp_path / "part.py"
    hand.write_text("import numpy as np\nSTATES = ['dv_X', 'dv_Y']\n"
                    "def part(nav, imu):\n    return np.zeros((2, 2))\n", encoding="utf-8")
    report = check_matrices(ECEF_MODEL, f"{hand}:part", "psi_ecef")
    assert report.effects == [] and "part of a triple" in report.held[0]
    assert to_json(report)["held"] == report.held


def test_a_sign_slip_hidden_in_a_sum_of_psi_entries_is_named_where_it_is_whole():
    """The same Coriolis slip carried by hand into the NED ψ states (the probe's route
    before psi_ecef): there −2Ω_ie shares its entries with transport-rate terms, so the
    entries were "wrong coefficient" and nothing said sign. At rest the hand entry is
    exactly minus the model's (the entry is the Earth-rate part alone there); that is now
    said."""
    report = check_matrices(ECEF_MODEL, f"{ROOT / 'data' / 'groves_ecef_in_psi.py'}:"
                            "coriolis_slip", "psi", effects=False)
    coriolis = {("dvc_N", "dvc_E"), ("dvc_E", "dvc_N"), ("dvc_E", "dvc_D"),
                ("dvc_D", "dvc_E")}
    found = {(f.row, f.column): f for f in report.findings if f.matrix == "F"}
    found.update({f.pair: f for f in report.findings if f.pair is not None})
    assert coriolis <= set(found)
    for key in coriolis:
        f = found[key]
        assert f.kind in ("wrong coefficient", "wrong sign"), f
        if f.kind == "wrong coefficient":
            assert "hand = −model on motion 'static'" in f.detail, f.detail
    assert any(found[key].kind == "wrong coefficient" for key in coriolis)


def _groves_module():
    import importlib.util

    spec = importlib.util.spec_from_file_location("groves_ecef_reference", GROVES)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _static_sample():
    """The static base of tests/models/ecef_ins.py: rest at φ 50°, λ 30°, h 0, heading
    30°, on its sphere of 6371 km (the accelerometers read the plumb line)."""
    from types import SimpleNamespace

    h = np.radians(30.0)
    nav = SimpleNamespace(latitude=np.radians(50.0), longitude=np.radians(30.0), height=0.0,
                          a=6_371_000.0, earth_rate=7.292115e-5,
                          C_bn=np.array([[np.cos(h), -np.sin(h), 0.0],
                                         [np.sin(h), np.cos(h), 0.0], [0.0, 0.0, 1.0]]))
    return nav, SimpleNamespace(f_b=np.array([0.0, 0.0, -9.806267]))


@pytest.fixture(scope="module")
def static_base():
    return [motions(load_model(ECEF_MODEL))[0]]


def test_a_left_out_ecef_attitude_that_nothing_excites_is_not_assessed(static_base):
    """A velocity and position model leaves out the couplings −[f^e×] δψ^e: but in
    Groves' equations no velocity, position or accelerometer error reaches δψ^e, so
    from the hand's own initial errors and sources the left-out attitude stays 0 and
    those entries act on nothing. Their effect is not assessed (not "no effect")."""
    F, G = _groves_module().groves(*_static_sample())
    assert not F[0:3, 3:9].any() and not G[0:3, 3:6].any()
    report = check_matrices(ECEF_MODEL, _hand("groves_velocity_position"), "psi_ecef",
                            motion_list=static_base)
    left = [f for f in report.findings if f.kind == "state left out"]
    assert {f.column for f in left} == {"psi_X", "psi_Y", "psi_Z"} and len(left) == 6
    text, findings = to_terminal(report), to_json(report)["findings"]
    for f in left:
        said = (f"effect not assessed: {f.column}, a state the hand leaves out, stays 0 "
                "from every initial error and source of the hand")
        assert report.finding_effects[f.entry].not_assessed == said
        assert f"{f.entry}: state left out" in text and said in text
        [entry] = [x for x in findings if (x["row"], x["column"]) == (f.row, f.column)]
        assert entry["effect_not_assessed"] == said
    # the Coriolis slip, in the hand's own states, keeps its figure
    slip = report.finding_effects["F[dv_X, dv_Y]"]
    assert slip.not_assessed is None and slip.position_above_rounding


def test_an_ecef_model_without_position_states_reads_no_position(static_base):
    """An attitude and velocity model (no δr^e) has no position to read: the effect of
    each finding alone says `position n/a`, and the attitude change is the one measured
    and named with its motion. The Earth rate's sign slipped in F[psi_X, psi_Y] and
    F[psi_Y, psi_X] (one finding of the mirror pair, its effect both entries') against a
    SciPy propagation of Groves' attitude rows on the static base: ψ̇^e =
    −Ω_ie^e ψ^e + C_b^e δω^b, with both slipped entries, from each initial ψ^e (1e-4 rad)
    and gyro bias (0.01 °/h); the attitude error read is |C_e^n Δψ^e| = |Δψ^e| (no δθ
    without position states)."""
    from scipy.linalg import expm

    report = check_matrices(ECEF_MODEL, _hand("groves_attitude_velocity"), "psi_ecef",
                            motion_list=static_base)
    assert report.effects and all(e.position_difference is None for e in report.effects)
    # the Earth rate's sign slipped in both entries of Ω_ie^e: one finding of the pair
    [f] = [f for f in report.findings if {(f.row, f.column), f.pair}
           == {("psi_X", "psi_Y"), ("psi_Y", "psi_X")}]
    assert f.kind == "wrong sign"
    assert report.finding_effects and all(e.position is None and e.position_floor is None
                                          for e in report.finding_effects.values())
    module = _groves_module()
    F, G = module.groves_exact(*_static_sample())
    F_one = F.copy()  # both entries of the pair as the hand writes them
    F_one[0, 1] = module.groves_attitude_velocity(*_static_sample())[0][0, 1]
    F_one[1, 0] = module.groves_attitude_velocity(*_static_sample())[0][1, 0]
    mags = np.array([1e-4] * 3 + [np.radians(0.01) / 3600.0] * 3)
    responses = []
    for rows in (F_one, F):
        A = np.zeros((6, 6))
        A[:3, :3], A[:3, 3:] = rows[0:3, 0:3], G[0:3, 0:3]
        responses.append(expm(A * 86400.0)[:3] * mags)
    attitude = np.linalg.norm(responses[0] - responses[1], axis=0).max()
    alone = report.finding_effects[f.entry]
    assert alone.motion == "static" and alone.attitude_above_rounding
    assert alone.attitude == pytest.approx(attitude, rel=1e-6)
    arcsec = np.radians(1.0 / 3600.0)
    assert (f"the pair together after 24 h: position n/a, {alone.attitude / arcsec:.3g}″ "
            "(largest on static)") in to_terminal(report)
    [entry] = [x for x in to_json(report)["findings"]
               if (x["row"], x["column"]) == (f.row, f.column)]
    assert entry["pair"] == f"F[{f.pair[0]}, {f.pair[1]}]"
    assert entry["effect_alone_24h"]["position_m"] is None
    assert entry["effect_alone_24h"]["motion"] == "static"
