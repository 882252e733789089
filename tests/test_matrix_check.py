"""`ins-errors check MODEL --matrix ...`: a hand-coded F and G checked entry by entry.

The reference hand model (tests/data/north_pointing_F.py) is written from the textbook
local-level equations, not from the package. Copies with one injected mistake must be
reported in exactly that entry; the ψ-angle convention must give Benson's decoupled
attitude equation ψ̇ = ψ × ω + ε; the propagated error must follow the Schuler period.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker import check_motions, derived_convention, matrix_effects, transition
from ins_errors.checker import matrix as mc
from ins_errors.checker.conventions import convention
from ins_errors.checker.matrix_input import HandMatrices, load_function, write_samples
from ins_errors.checker.matrix_report import to_terminal
from ins_errors.checker.navigation import samples
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.numeric.model import load_model

DATA = Path(__file__).resolve().parent / "data"
HAND = DATA / "north_pointing_F.py"
MODEL = "north_pointing"


@pytest.fixture(scope="module")
def model():
    return load_model(MODEL)


@pytest.fixture(scope="module")
def wgs84(model):
    """The three motions on the WGS-84 ellipsoid (so the radius derivatives matter)."""
    return mc.motions(model, hours=24.0, step=120.0, ellipsoid="wgs84")


def _copy(tmp_path: Path, old: str, new: str) -> str:
    text = HAND.read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / "hand_copy.py"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return f"{path}:error_model"


def test_correct_hand_model_agrees_in_full(wgs84):
    report = mc.check_matrices(MODEL, f"{HAND}:error_model", "model", motion_list=wgs84,
                              effects=False)
    assert report.findings == []
    assert report.compared == 7 * 7 + 7 * 5 and report.exit_status == 0


def test_a_function_object_is_checked_as_its_file_spec(wgs84, tmp_path):
    """A notebook user holds the function itself: passed as an object it was read as a
    file name ("matrix file '<function error_model at 0x...>' does not exist"). Its
    STATES/SOURCES are the globals beside it (here its module's), or its attributes."""
    import importlib.util

    def imported(name: str, path: Path):
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    module = imported("hand_in_memory", HAND)
    spec_text = _copy(tmp_path, "F[1, 4] = f_u", "F[1, 4] = -f_u")
    by_file = mc.check_matrices(MODEL, spec_text, "model", motion_list=wgs84, effects=False)
    wrong = imported("hand_wrong", Path(spec_text.rpartition(":")[0]))
    by_object = mc.check_matrices(MODEL, wrong.error_model, "model", motion_list=wgs84,
                                  effects=False)
    assert [(f.matrix, f.row, f.column, f.kind) for f in by_object.findings] == [
        (f.matrix, f.row, f.column, f.kind) for f in by_file.findings] != []
    assert mc.check_matrices(MODEL, module.error_model, "model", motion_list=wgs84,
                             effects=False).findings == []

    def bare(nav, imu):  # no STATES anywhere: one line saying how to give them
        return np.zeros((7, 7))

    with pytest.raises(InsErrorsError, match=r"bare\.states = \[\.\.\.\]"):
        mc.check_matrices(MODEL, bare, "model", motion_list=wgs84, effects=False)
    bare.states = list(module.STATES)
    report = mc.check_matrices(MODEL, bare, "model", motion_list=wgs84, effects=False)
    assert report.findings and all(f.kind == "omitted term" for f in report.findings)


@pytest.mark.parametrize("old, new, row, column, kind", [
    ("F[1, 4] = f_u", "F[1, 4] = -f_u", "delta_v_N", "alpha_E", "wrong sign"),
    ("F[2, 1] = 1 / r_n", "F[2, 1] = 2 / r_n", "delta_latitude", "delta_v_N",
     "wrong coefficient"),
    ("F[0, 1] = turn", "F[0, 1] = 0.0", "delta_v_E", "delta_v_N", "omitted term"),
    ("F[5, 4], F[5, 6] = -w_u, w_e", "F[5, 4], F[5, 6] = -w_u, w_e + U",
     "alpha_N", "alpha_U", "wrong coefficient"),
    ("G[0, 3] = G[1, 4] = 1.0", "G[0, 3] = G[1, 4] = 1.0\n    G[2, 3] = 1e-7",
     "delta_latitude", "accel_bias_east", "extra term"),
    # the model's U cos φ (7e-5/s) is no zero against a hand's 1000/s: a term the model
    # has, written with a wrong coefficient (it was called an extra term)
    ("F[5, 4], F[5, 6] = -w_u, w_e", "F[5, 4], F[5, 6] = -w_u, 1e3",
     "alpha_N", "alpha_U", "wrong coefficient"),
])
def test_injected_mistake_is_reported_in_its_entry(tmp_path, wgs84, old, new, row, column,
                                                   kind):
    report = mc.check_matrices(MODEL, _copy(tmp_path, old, new), "model", motion_list=wgs84,
                              effects=False)
    [finding] = report.findings
    matrix = "G" if column.startswith("accel") else "F"
    assert (finding.matrix, finding.row, finding.column) == (matrix, row, column)
    assert finding.kind == kind and finding in report.mistakes
    assert report.exit_status == 1
    if old.startswith("F[2, 1]"):
        assert "= 2 at every sample" in finding.detail


def test_height_left_out_of_the_radii_is_a_dropped_small_term(tmp_path, wgs84):
    """r_E, r_N without h: a 10 km height changes 1/r by h/R ≈ 1.6e-3 of the entry."""
    report = mc.check_matrices(
        MODEL, _copy(tmp_path, "    r_e = a / np.sqrt(w) + h\n    r_n = a * (1 - e2) / w**1.5 + h",
                     "    r_e = a / np.sqrt(w)\n    r_n = a * (1 - e2) / w**1.5"),
        "model", motion_list=wgs84, effects=False)
    f = report.finding("alpha_N", "delta_v_E")
    assert f.kind == "approximated" and f.severity == "dropped small term"
    assert f.per_motion["static"] == 0.0 and f.per_motion["cruise"] > 0
    # hand/model of 1/r is (R_E + h)/R_E at the cruise height
    lo, hi = (float(v) for v in re.findall(r"[\d.]+", f.detail)[:2])
    assert hi == pytest.approx(1 + 9000.0 / 6.39e6, rel=2e-4)  # highest manoeuvre point
    assert lo >= 1.0


def test_psi_convention_gives_bensons_decoupled_attitude_equation(model, wgs84):
    """ψ = α − δθ (platform vs computer frame) obeys ψ̇ = ψ × ω_in + ε, with no velocity
    or position coupling (Benson 1975), on the moving, climbing manoeuvre."""
    conv = convention(model, "psi")
    motion = wgs84[2]
    F, G = mc.derived_in_convention(model, conv, motion)
    w = motion.navigation["omega_ib_b"]  # platform rate = ω_in, NED
    w_e, w_n, w_u = w[1], w[0], -w[2]
    expected = np.zeros((len(motion.times), 3, 7))
    expected[:, 0, 5], expected[:, 0, 6] = w_u, -w_n
    expected[:, 1, 4], expected[:, 1, 6] = -w_u, w_e
    expected[:, 2, 4], expected[:, 2, 5] = w_n, -w_e
    scale = np.abs(w).max()
    assert np.abs(F[:, 4:, :] - expected).max() < 1e-9 * scale
    drifts = [s.name for s in model.sources].index("gyro_drift_east")
    assert np.allclose(G[:, 4:, drifts:drifts + 3], np.eye(3))


def test_schuler_oscillation_of_the_propagated_model(wgs84):
    """An initial 0.1 m/s east velocity error: |δr(t)| = v0 |sin ω_s t| / ω_s on a static
    base, ω_s = √(g/R) (the Foucault rotation does not change the length)."""
    report = mc.check_matrices(MODEL, f"{HAND}:error_model", "model", motion_list=wgs84)
    [effect] = [e for e in report.effects if (e.motion, e.hours, e.case)
                == ("static", 1.0, "initial delta_v_E")]
    omega = np.sqrt(9.80665 / 6.371e6)  # rough radius: the test is for 1 % agreement
    assert effect.position_model == pytest.approx(0.1 * abs(np.sin(omega * 3600)) / omega,
                                                  rel=0.01)
    assert max(e.position_difference for e in report.effects) < 1e-6


def test_effect_of_a_missing_coriolis_term(tmp_path, wgs84):
    """Dropping 2U sin φ δv_N from δv̇_E leaves the Foucault rotation out: after 24 h the
    error from an east velocity error differs by metres to kilometres, after 1 h by less."""
    report = mc.check_matrices(MODEL, _copy(tmp_path, "F[0, 1] = turn", "F[0, 1] = 0.0"),
                              "model", motion_list=wgs84)
    case = {(e.hours): e for e in report.effects
            if e.motion == "static" and e.case == "initial delta_v_E"}
    assert 0 < case[1.0].position_difference < case[24.0].position_difference
    assert case[24.0].position_difference > 10.0
    # the only difference: its effect alone is the whole difference
    alone = report.finding_effects["F[delta_v_E, delta_v_N]"]
    whole = max((e for e in report.effects if e.hours == 24.0),
                key=lambda e: e.position_difference)
    assert alone.position == pytest.approx(whole.position_difference, rel=1e-6)
    assert alone.motion == whole.motion and alone.position_above_rounding
    assert whole.position_above_rounding and whole.position_difference > 1e6 * whole.position_floor


def test_sampled_matrices_from_npz_and_mat(tmp_path, model):
    ms = mc.motions(model, hours=2.0, step=600.0)
    fn, states, sources = load_function(HAND, "error_model")
    arrays = {"states": np.array(states), "sources": np.array(sources)}
    for motion in ms:
        pairs = [fn(nav, imu) for nav, imu in samples(motion.navigation, motion.times,
                                                       motion.label)]
        arrays[f"F_{motion.label}"] = np.array([f for f, _ in pairs])
        arrays[f"G_{motion.label}"] = np.array([g for _, g in pairs])
    np.savez(tmp_path / "hand.npz", **arrays)
    assert mc.check_matrices(MODEL, tmp_path / "hand.npz", "model", motion_list=ms,
                            effects=False).findings == []
    from scipy.io import savemat

    arrays["F_cruise"][:, 2, 1] *= -1
    savemat(tmp_path / "hand.mat", arrays)
    report = mc.check_matrices(MODEL, tmp_path / "hand.mat", "model", motion_list=ms,
                              effects=False)
    [f] = report.findings
    assert (f.row, f.column, f.kind) == ("delta_latitude", "delta_v_N", "wrong coefficient")
    arrays["G_static"] = arrays["G_static"] + 0j
    np.savez(tmp_path / "complex.npz", **arrays)
    with pytest.raises(InsErrorsError, match=r"^complex.npz: G_static is complex"):
        mc.check_matrices(MODEL, tmp_path / "complex.npz", "model", motion_list=ms,
                          effects=False)
    assert f.per_motion["static"] == 0 and f.motion == "cruise"


@pytest.mark.parametrize("edit, message", [
    (("STATES = [", "STATE = ["), "define STATES"),
    (('"alpha_U"]', '"alpha_up"]'), "unknown state of convention 'model' 'alpha_up'"),
    (("return F, G", "return F[:, :6], G"), "F must have shape (7, 7)"),
    (("w = 1 - e2 * s**2", "w = 1 - e2 * s**2 + undefined_name"), "NameError"),
    (("import numpy as np", "import numpy as np\nraise RuntimeError('broken')"),
     "cannot import"),
    # numpy would drop the imaginary part with a warning only, and read digit strings
    (("return F, G", "return F + 1e-3j, G"), "F is complex (dtype complex128)"),
    (("return F, G", "return F.astype(object) + 1e-3j, G"), "F is complex (dtype object)"),
    (("return F, G", 'return np.full(F.shape, "x"), G'), "F must be a numeric array, got strings"),
    (("return F, G", "return F.astype(str), G"), "F must be a numeric array, got strings"),
    # sys.exit() in the researcher's code ended ins-errors with its status (3, or 0)
    (("return F, G", "import sys\n    sys.exit(3)"), "called sys.exit(3) (line"),
    (("import numpy as np", "import numpy as np\nimport sys\nsys.exit(0)"),
     "cannot import hand_copy.py: called sys.exit(0) (line"),
])
def test_bad_hand_model_is_a_one_line_error(tmp_path, capsys, edit, message):
    spec = _copy(tmp_path, *edit)
    assert main(["check", MODEL, "--matrix", spec]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and "Traceback" not in err
    if message == "NameError":
        assert "(line " in err and "on static at t = 0 s" in err


@pytest.mark.parametrize("argv, message", [
    (["--matrix", f"{HAND}:no_such_function"], "has no function 'no_such_function'"),
    (["--matrix", f"{HAND}:error_model", "--convention", "psy"], "did you mean 'psi'"),
    (["--matrix", "missing.npz"], "does not exist"),
    ([], "needs a hand FILE"),
])
def test_bad_command_line(capsys, argv, message):
    assert main(["check", MODEL, *argv]) == 2
    assert message in capsys.readouterr().err


def test_cli_lists_conventions_and_writes_samples(tmp_path, capsys):
    assert main(["check", MODEL, "--list-conventions"]) == 0
    out = capsys.readouterr().out
    assert "psi_U (rad)" in out and "delta_latitude (rad)" in out
    assert main(["check", MODEL, "--write-samples", str(tmp_path / "s.npz")]) == 0
    with np.load(tmp_path / "s.npz") as data:
        assert data["t_static"][-1] == 86400.0 and data["C_bn_cruise"].shape[1:] == (3, 3)
        # the cruise flies east at 250 m/s at 10 km
        assert np.allclose(data["v_ned_cruise"][:, 1], 250.0)
        assert np.allclose(data["height_cruise"], 10_000.0)


def test_written_samples_hold_every_documented_attribute(tmp_path):
    """--write-samples writes every attribute a hand function sees (docs/matrix_check.md),
    omega_in_n and f_n included, with the values the function is called with; on the
    static base f_n is the reaction to gravity and omega_in_n the Earth rate."""
    ms = mc.motions(load_model(MODEL), hours=1.0, step=600.0)
    path = tmp_path / "s.npz"
    write_samples(path, ms)
    doc = (DATA.parent.parent / "docs" / "matrix_check.md").read_text(encoding="utf-8")
    section = doc.split("## The researcher's function")[1].split("## Conventions")[0]
    table = [line.split("|")[1] for line in section.splitlines() if line.startswith("| `")]
    imu = section.split("* `imu` (an `Imu`):")[1].split("\n* ")[0]  # `f_n = C_bn @ f_b`
    documented = set(re.findall(r"`(\w+)(?:`| =)", " ".join([*table, imu]))) - {"motion"}
    assert {"omega_in_n", "f_n", "f_b", "gravity"} <= documented
    with np.load(path) as data:
        for motion in ms:
            keys = {k[: -len(motion.label) - 1] for k in data.files
                    if k.endswith("_" + motion.label)}
            assert documented <= keys, documented - keys
            for k, (nav, imu) in enumerate(samples(motion.navigation, motion.times,
                                                   motion.label)):
                assert np.array_equal(data[f"omega_in_n_{motion.label}"][k], nav.omega_in_n)
                assert np.array_equal(data[f"f_n_{motion.label}"][k], imu.f_n)
        g, f_n = data["gravity_static"], data["f_n_static"]
        assert np.allclose(f_n[:, :2], 0.0, atol=1e-9 * g[0])
        assert np.allclose(f_n[:, 2], -g, rtol=1e-12)
        rate = np.linalg.norm(data["omega_in_n_static"], axis=1)
        assert np.allclose(rate, 7.292115e-5, rtol=1e-6)


# --------------------------------------------------------------------------------------
# strapdown_ned and the textbook ψ-angle model (examples/strapdown/psi_model.py)
# --------------------------------------------------------------------------------------
PSI = DATA.parent.parent / "examples" / "strapdown" / "psi_model.py"


@pytest.fixture(scope="module")
def strapdown_motions():
    return mc.motions(load_model("strapdown_ned"), hours=2.0, step=60.0)


@pytest.fixture(scope="module")
def psi_report(strapdown_motions):
    return mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                             motion_list=strapdown_motions, effects=False)


def test_textbook_psi_model_has_no_mistake(psi_report):
    """Benson's ψ form is exact on a sphere: what differs is the Earth's shape only."""
    assert psi_report.exit_status == 0 and psi_report.compared == 9 * 9 + 9 * 6
    kinds = {f.kind for f in psi_report.findings}
    assert kinds <= {"approximated", "omitted term"}
    # the attitude equation's coupling, the Coriolis terms, the G columns: all agree
    assert not [f for f in psi_report.findings if f.matrix == "G"]
    assert psi_report.finding("dvc_N", "psi_E") is None  # f × ψ, exact
    assert psi_report.finding("dr_N", "dvc_N") is None   # δṙ = δv
    assert all(f.size < psi_report.threshold for f in psi_report.findings)


def test_psi_model_drops_the_latitude_dependence_of_gravity(psi_report):
    """The derived model has δg_D = (∂γ/∂φ) δφ: with the international gravity formula
    γ = γ_e (1 + β sin² φ), β = 0.0053024, ∂γ/∂φ = γ_e β sin 2φ ≈ 0.051 m/s² per rad,
    i.e. 8.0e-9 s⁻² per metre of north error; the textbook's spherical Γ has no such term."""
    f = psi_report.finding("dvc_D", "dr_N")
    assert f.kind == "omitted term" and f.severity == "dropped small term"
    phi = np.radians(50.0)
    r_n = 6_378_137.0 * (1 - 6.694e-3) / (1 - 6.694e-3 * np.sin(phi) ** 2) ** 1.5
    expected = 9.780327 * 0.0053024 * np.sin(2 * phi) / r_n
    assert abs(f.model) == pytest.approx(expected, rel=0.01)


def test_psi_model_spherical_radius_is_an_approximation_of_the_transport_rate(psi_report):
    """ω_en with R = a instead of R_N + h, R_E + h: hand/model of the transport terms is
    (R + h)/(a + h) within the ellipsoid's 0.7 %; on the static base they agree."""
    f = psi_report.finding("dr_N", "dr_E")
    assert f.kind == "approximated" and f.per_motion["static"] < 1e-12
    lo, hi = (float(v) for v in re.findall(r"[\d.]+", f.detail)[:2])
    assert 0.99 < lo <= hi < 1.01


def test_wrong_entry_in_a_copy_of_the_psi_model(tmp_path, strapdown_motions):
    """The Done-when item: one deliberately wrong entry is a mistake in that entry."""
    text = PSI.read_text(encoding="utf-8")
    old = "F[3:6, 3:6] = -skew(2 * w_ie + w_en)"
    assert old in text
    path = tmp_path / "psi_copy.py"
    path.write_text(text.replace(old, old + "\n    F[3, 4] = 0.0"), encoding="utf-8")
    report = mc.check_matrices("strapdown_ned", f"{path}:psi_model", "psi",
                               motion_list=strapdown_motions)
    [mistake] = report.mistakes
    assert (mistake.row, mistake.column, mistake.kind) == ("dvc_N", "dvc_E", "omitted term")
    assert report.held == ["dvc_D", "dr_D"]
    # leaving out the Coriolis coupling 2Ω sin φ changes the 1-h position error visibly
    worst = max(e.position_difference for e in report.effects if e.hours == 1.0)
    assert worst > 1.0


TRANSPOSED = "is the derived one transposed at every sample: C_n^b written where C_b^n"


@pytest.mark.parametrize("old, rows, columns", [
    ("G[0:3, 0:3] = -nav.C_bn", ("psi_N", "psi_E", "psi_D"), "gyro_bias_"),
    ("G[3:6, 3:6] = nav.C_bn", ("dvc_N", "dvc_E", "dvc_D"), "accel_bias_")])
def test_transposed_direction_cosines_are_one_finding(tmp_path, strapdown_motions, old,
                                                      rows, columns):
    """C_n^b written where C_b^n belongs: one finding for the block, not six entries."""
    # the motions turn the body away from NED, so C_b^n is not symmetric: the hand's
    # block really differs from the derived one in its off-diagonal entries
    C = strapdown_motions[-1].navigation["C_bn"]  # (3, 3, K)
    assert np.abs(C - np.swapaxes(C, 0, 1)).max() > 0.1
    text = PSI.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / "psi_transposed.py"
    path.write_text(text.replace(old, old + ".T"), encoding="utf-8")
    report = mc.check_matrices("strapdown_ned", f"{path}:psi_model", "psi",
                               motion_list=strapdown_motions, effects=False)
    [finding] = [f for f in report.findings if f.matrix == "G"]
    assert finding.row in rows and finding.column.startswith(columns)
    assert finding.kind == "wrong symbol or index" and finding.severity == "mistake"
    assert TRANSPOSED in finding.detail
    assert report.mistakes == [finding]


def test_no_transposition_in_the_textbook_or_a_skew_sign_slip(psi_report, tmp_path,
                                                              strapdown_motions):
    """The untouched model has no transposed block (its skew-symmetric blocks agree);
    f^n × ψ with the wrong sign is its own transpose, and stays six wrong signs."""
    assert not [f for f in psi_report.findings if TRANSPOSED in f.detail]
    text = PSI.read_text(encoding="utf-8")
    old = "F[3:6, 0:3] = skew(imu.f_n)"
    path = tmp_path / "psi_skew_sign.py"
    path.write_text(text.replace(old, "F[3:6, 0:3] = -skew(imu.f_n)"), encoding="utf-8")
    report = mc.check_matrices("strapdown_ned", f"{path}:psi_model", "psi",
                               motion_list=strapdown_motions, effects=False)
    assert report.compared == 9 * 9 + 9 * 6
    slips = [f for f in report.mistakes if f.row.startswith("dvc")]
    assert len(slips) == 6 and {f.kind for f in slips} == {"wrong sign"}


def test_a_transposed_block_s_effect_is_the_whole_block_s():
    """The effect of a transposed block is that of the researcher's whole block: a hand
    model equal to the derived one but for G[ψ, gyro] = −C_n^b (−C_b^n transposed),
    propagated against the derived model on the static base with SciPy's matrix
    exponential (dvc_D, dr_D held: rows and columns zeroed), read as the horizontal
    position error (dr_N, dr_E) and the attitude error ψ + δθ after 24 h, worst case over
    the initial errors and sources at their typical sizes."""
    from scipy.linalg import expm

    model = load_model("strapdown_ned")
    static = mc.motions(model, hours=24.0, step=60.0)[0]
    conv = convention(model, "psi")
    F_all, G_all = mc.derived_in_convention(model, conv, static)
    F, G_model = F_all[0], G_all[0]
    sources = [f"{kind}_bias_{a}" for kind in ("gyro", "accel") for a in "xyz"]
    G_model = G_model[:, [[s.name for s in model.sources].index(n) for n in sources]]
    G_hand = G_model.copy()
    G_hand[0:3, 0:3] = G_model[0:3, 0:3].T
    assert np.abs(G_hand - G_model).max() > 0.1  # heading 30°: C_b^n is no symmetric matrix

    def transposed(nav, imu):
        return F, G_hand

    transposed.states = list(conv.names)
    transposed.sources = sources
    report = mc.check_matrices("strapdown_ned", transposed, "psi", motion_list=[static])
    [finding] = report.findings
    assert TRANSPOSED in finding.detail and finding.matrix == "G"

    nav = static.navigation
    lat, h = nav["latitude"][0], nav["height"][0]
    R_N, R_E = nav["R_N"][0] + h, nav["R_E"][0] + h
    held = [5, 8]  # dvc_D, dr_D
    mags = np.array([1e-4] * 3 + [0.1] * 3 + [10.0] * 3
                    + [np.radians(0.01) / 3600.0] * 3 + [1e-4 * 9.80665] * 3)
    cases = [c for c in range(15) if c not in held]
    responses = []
    for G in (G_hand, G_model):
        A = np.zeros((15, 15))
        A[:9, :9], A[:9, 9:] = F, G
        A[held, :], A[:, held] = 0.0, 0.0
        responses.append(expm(A * 86400.0)[:9, cases] * mags[cases])
    d = responses[0] - responses[1]
    position = np.linalg.norm(d[6:8], axis=0).max()
    theta = np.array([d[7] / R_E, -d[6] / R_N, -d[7] * np.tan(lat) / R_E])
    attitude = np.linalg.norm(d[0:3] + theta, axis=0).max()
    alone = report.finding_effects[finding.entry]
    assert alone.motion == "static" and alone.position_above_rounding
    assert alone.position == pytest.approx(position, rel=1e-6)
    assert alone.attitude == pytest.approx(attitude, rel=1e-6)
    # the whole propagation compares the same two models
    worst = max(e.position_difference for e in report.effects if e.hours == 24.0)
    assert worst == pytest.approx(position, rel=1e-6)


def test_example_sign_error_file(strapdown_motions):
    path = PSI.parent / "psi_model_sign_error.py"
    report = mc.check_matrices("strapdown_ned", f"{path}:psi_model_sign_error", "psi",
                               motion_list=strapdown_motions, effects=False)
    [mistake] = report.mistakes
    assert (mistake.row, mistake.column, mistake.kind) == ("dvc_E", "dr_E", "wrong sign")


@pytest.mark.parametrize("model_name, reference, psi", [
    ("north_pointing", "model", "psi"), ("strapdown_ned", "phi", "psi"),
    ("strapdown_ned", "phi_geodetic", "psi_geodetic")])
def test_psi_attitude_readout_is_the_true_attitude_error(model_name, reference, psi,
                                                         wgs84, strapdown_motions):
    """ψ + δθ read out of a ψ-convention state equals the φ-angle (or platform angles)
    of the same model error state: T (the transform) and the readout agree."""
    model = load_model(model_name)
    motion = (wgs84 if model_name == "north_pointing" else strapdown_motions)[1]
    rng = np.random.default_rng(1)
    e = rng.normal(size=(len(model.error_states), motion.times.size)) * 1e-5
    readings = []
    for name in (reference, psi):
        conv = convention(model, name)
        T, _ = conv.matrices(model, motion.x, motion.p, motion.u)
        z = np.einsum("kij,jk->ik", T, e)
        readings.append(np.einsum("aik,ik->ak", conv.attitude(motion.navigation), z))
    assert np.abs(readings[0] - readings[1]).max() < 1e-12 * np.abs(readings[0]).max() + 1e-18


def test_magnitudes_scale_the_sizes(strapdown_motions, psi_report):
    """A position error 10× larger makes the dropped ∂γ/∂φ term 10× larger relative to the
    vertical channel's largest term (the 1e-4 g accelerometer bias); with Schuler-consistent
    sizes (θ = 1e-4 rad: R θ ≈ 640 m) the spherical gravity gradient becomes a mistake."""
    bigger = mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                               motion_list=strapdown_motions, effects=False,
                               magnitudes={"m": "100 m"})
    before = psi_report.finding("dvc_D", "dr_N").size
    assert bigger.finding("dvc_D", "dr_N").size == pytest.approx(10 * before, rel=1e-9)
    assert bigger.magnitudes["dr_N"][1] == "100 m"
    schuler = mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                                motion_list=strapdown_motions, effects=False,
                                magnitudes={"attitude": "1e-4 rad"})
    assert schuler.magnitudes["dr_N"][0] == pytest.approx(6.37e6 * 1e-4, rel=0.01)
    assert {(f.row, f.column) for f in schuler.mistakes} >= {("dvc_N", "dr_N"),
                                                              ("dvc_E", "dr_E")}


@pytest.mark.parametrize("name", ["orthodromic", "north_pointing", "strapdown_ned",
                                  "examples/own_model/schuler_loop.py"])
def test_schuler_magnitudes_from_the_metadata_are_the_definitions(name):
    """The matrix check reads R and g from the generated package's metadata (no SymPy);
    equation checks from the SymPy definition: the same sizes to the bit, and the
    textbook Schuler period (84.4 min on the spherical 6371 km Earth)."""
    from ins_errors.checker.typical import schuler_magnitudes

    model = load_model(str(Path(__file__).resolve().parent.parent / name)
                       if name.endswith(".py") else name)
    numeric = schuler_magnitudes(model, "20 arcsec", {"m/s": "0.1 m/s"})
    symbolic = schuler_magnitudes(model.symbolic, "20 arcsec", {"m/s": "0.1 m/s"})
    assert numeric == symbolic
    if name == "north_pointing":
        assert "Schuler period 84.4 min" in numeric.origin


def test_fixed_typical_sizes_are_pints_conversions():
    """The matrix check's fixed sizes, converted without pint, are pint's conversions of
    their texts to the bit (0.01 deg/h = 4.848e-8 rad/s, 1e-4 g = 9.807e-4 m/s²)."""
    from ins_errors import units
    from ins_errors.checker.typical import TYPICAL_BY_UNIT, typical_magnitude

    for unit, (text, si) in TYPICAL_BY_UNIT.items():
        value, shown = typical_magnitude(unit)
        assert shown == text
        assert value == units._text_value(units.registry(), text, si), unit
    assert typical_magnitude("rad/s")[0] == pytest.approx(4.8481368e-8, rel=1e-7)
    assert typical_magnitude("m/s**2")[0] == pytest.approx(9.80665e-4, rel=1e-12)

def test_horizontal_psi_model_leaves_the_vertical_channel_out(tmp_path, strapdown_motions):
    """A 7-state textbook model without δv_D and δr_D: the coupling of the omitted states
    into its rows is reported as 'state left out'. The Coriolis term 2Ω cos φ δv_D of δv̇_E
    at rest is 9.4e-6 m/s² per 0.1 m/s, ~1 % of the row's largest term g·1e-4, above the
    default threshold; but the hand has no vertical channel at all, which the effect
    comparison holds anyway: 'vertical channel left out', no mistake (exit status 0)."""
    text = PSI.read_text(encoding="utf-8").replace(
        "    return F, G",
        "    keep = [0, 1, 2, 3, 4, 6, 7]\n    return F[np.ix_(keep, keep)], G[keep]")
    text = text.replace('"dvc_E", "dvc_D", "dr_N", "dr_E", "dr_D"]', '"dvc_E", "dr_N", "dr_E"]')
    path = tmp_path / "psi_horizontal.py"
    path.write_text(text, encoding="utf-8")
    report = mc.check_matrices("strapdown_ned", f"{path}:psi_model", "psi",
                               motion_list=strapdown_motions, effects=False)
    assert report.left_out == ["dvc_D", "dr_D"]
    f = report.finding("dvc_E", "dvc_D")
    assert f.kind == "state left out" and f.severity == "vertical channel left out"
    assert f.size > mc.DEFAULT_THRESHOLD
    U, phi, g = 7.292115e-5, np.radians(50.0), 9.81
    assert f.per_motion["static"] == pytest.approx(2 * U * np.cos(phi) * 0.1 / (g * 1e-4),
                                                   rel=1e-3)
    assert {m.column for m in report.without_vertical} == {"dvc_D", "dr_D"}
    assert report.mistakes == [] and report.exit_status == 0


def test_stepped_transition_matches_the_matrix_exponential(wgs84):
    """The moving-motion propagator (exp of the step-mean A, scaled Taylor series) against
    scipy's expm on a time-invariant system: the static base's scaled [[F, G], [0, 0]]."""
    from scipy.linalg import expm

    model = load_model(MODEL)
    F, G = mc.derived_in_convention(model, convention(model, "model"), wgs84[0])
    scale = np.array([0.1, 0.1, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4] + [1e-7] * G.shape[2])
    A = matrix_effects._augmented(F, G, scale, [])
    steps = transition.step_exponentials(0.5 * (A[1:] + A[:-1]), 120.0)
    phi = np.eye(A.shape[1])
    for step in steps[:30]:  # one hour
        phi = step @ phi
    assert np.abs(phi - expm(A[0] * 3600.0)).max() < 1e-10


def test_derived_model_kept_on_a_motion_is_per_model_and_convention(strapdown_motions, wgs84):
    """What a motion keeps for the next check equals a fresh computation, for each model
    and convention in turn, and cannot be changed by a caller."""
    strapdown, north = load_model("strapdown_ned"), load_model(MODEL)
    for _ in range(2):  # the second round reads what the first kept
        for model, motion, name in ((strapdown, strapdown_motions[2], "psi"),
                                    (strapdown, strapdown_motions[2], "model"),
                                    (north, wgs84[2], "model")):
            conv = convention(model, name)
            F, G = mc.derived_in_convention(model, conv, motion)
            fresh_F, fresh_G = derived_convention._derived_in_convention(model, conv, motion)
            assert np.array_equal(F, fresh_F) and np.array_equal(G, fresh_G)
            assert F.shape[1] == len(conv.names) and not F.flags.writeable
    psi, own = (mc.derived_in_convention(strapdown, convention(strapdown, n),
                                         strapdown_motions[2])[0] for n in ("psi", "model"))
    assert psi.shape != own.shape or not np.array_equal(psi, own)


def test_in_place_propagation_is_the_plain_formula_to_the_bit(wgs84):
    """The step exponentials and the stepped transition, evaluated in place, give exactly
    the numbers of their formulas written out plainly (degree-10 Taylor sum of A dt/2^s,
    s squarings; Φ_{k+1} = e^{Ā_k dt} Φ_k with Ā_k the step's mean)."""
    model = load_model(MODEL)
    motion = wgs84[2]  # the manoeuvre: A varies
    F, G = mc.derived_in_convention(model, convention(model, "model"), motion)
    scale = np.array([0.1, 0.1, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4] + [1e-7] * G.shape[2])
    A = matrix_effects._augmented(F, G, scale, [2])
    plain = np.zeros_like(A)
    plain[:, :7, :7], plain[:, :7, 7:] = F, G
    plain[:, 2, :], plain[:, :, 2] = 0.0, 0.0
    assert np.array_equal(A, plain * (1 / scale)[:, None] * scale[None, :])
    dt = float(motion.times[1] - motion.times[0])
    mean = 0.5 * (A[1:] + A[:-1])
    M = mean * dt
    norm = np.max(np.sum(np.abs(M), axis=-1))
    squarings = max(0, int(np.ceil(np.log2(norm / 0.25)))) if norm > 0.25 else 0
    assert squarings > 0  # the squaring branch is exercised
    M = M / 2**squarings
    eye = np.broadcast_to(np.eye(A.shape[-1]), mean.shape)
    result, term = eye.copy(), eye.copy()
    for k in range(1, 11):
        term = term @ M / k
        result = result + term
    for _ in range(squarings):
        result = result @ result
    steps = transition.step_exponentials(mean, dt)
    assert np.array_equal(steps, result)
    phi = np.eye(A.shape[-1])
    wanted = {}
    for k in range(steps.shape[0]):
        phi = steps[k] @ phi
        if k + 1 in (30, steps.shape[0]):
            wanted[k + 1] = phi
    at = [30 * dt, steps.shape[0] * dt]
    got = transition.transitions(A, motion.times, at)
    assert np.array_equal(got[0], wanted[30]) and np.array_equal(got[1], wanted[len(steps)])


def test_a_hand_function_that_changes_its_arguments_is_refused(tmp_path):
    """The samples are kept for the next check, so they are read-only: changing one in
    place is a one-line error naming the function, the motion and the line; the samples
    stay as they were."""
    from ins_errors.errors import InsErrorsError

    ms = mc.motions(load_model(MODEL), hours=2.0, step=600.0)
    before = [(nav.v_ned.copy(), imu.f_n.copy()) for nav, imu in samples(
        ms[1].navigation, ms[1].times, ms[1].label)]
    text = HAND.read_text(encoding="utf-8").replace(
        "    phi, h = nav.latitude, nav.height\n",
        "    phi, h = nav.latitude, nav.height\n    imu.f_n[2] += 0.0\n")
    path = tmp_path / "changes_inputs.py"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InsErrorsError, match=r"changes_inputs.py:error_model on static at "
                                             r"t = 0 s: ValueError: .*read-only \(line \d+\)"):
        mc.check_matrices(MODEL, f"{path}:error_model", "model", motion_list=ms)
    report = mc.check_matrices(MODEL, f"{HAND}:error_model", "model", motion_list=ms,
                               effects=False)
    assert report.findings == []
    kept = ms[1].kept["samples"]
    assert all(np.array_equal(nav.v_ned, v) and np.array_equal(imu.f_n, f)
               for (nav, imu), (v, f) in zip(kept, before, strict=True))


def test_kept_propagations_equal_fresh_ones_and_change_no_report(strapdown_motions, tmp_path,
                                                                  monkeypatch):
    """A propagation kept from an earlier check (same content of A, times and instants)
    is what a fresh computation gives, to the bit, and read-only; a check after others
    (the kept derived model and single-entry changes) reports exactly what it reports
    with nothing kept (in the process or on disk)."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))  # an empty store on disk
    spec = f"{PSI.parent / 'psi_model_sign_error.py'}:psi_model_sign_error"

    def report():
        r = mc.check_matrices("strapdown_ned", spec, "psi", motion_list=strapdown_motions)
        return r.findings, r.effects, r.finding_effects

    transition._KEPT.clear()
    cold = report()
    assert len(transition._KEPT) > 3
    mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                      motion_list=strapdown_motions)
    assert report() == cold
    assert all(not phi.flags.writeable for kept in transition._KEPT.values()
               for phi in kept)
    motion = strapdown_motions[2]
    model = load_model("strapdown_ned")
    F, G = mc.derived_in_convention(model, convention(model, "psi"), motion)
    A = matrix_effects._augmented(F, G, np.ones(F.shape[1] + G.shape[2]), [])
    at = [3600.0, 7200.0]
    first = transition.transitions(A, motion.times, at)
    again = transition.transitions(A.copy(), motion.times.copy(), at)  # equal content, new arrays
    fresh = transition._computed(A, motion.times, at)
    assert all(a is b for a, b in zip(first, again, strict=True))
    assert all(np.array_equal(a, b) for a, b in zip(first, fresh, strict=True))
    changed = A.copy()
    changed[5, 0, 1] += 1e-9
    assert not np.array_equal(transition.transitions(changed, motion.times, at)[1], first[1])


def test_stored_motions_are_the_flown_ones_to_the_bit(tmp_path, monkeypatch):
    """The motions read back from the on-disk store (the next `ins-errors check` process)
    are the flown ones bit for bit (samples and navigation arrays), so they give the same
    reports; another request is another file, an unreadable file is flown again, and the
    store keeps at most KEEP files."""
    from ins_errors.checker import motion_store

    # an empty motion store; the compiled loops that fly them stay where they are
    monkeypatch.setattr(motion_store, "folder", lambda: tmp_path / "motions")
    fly = check_motions._motions.__wrapped__  # past the per-process cache
    flown, none = fly(MODEL, 2.0, 600.0, None)
    (stored,) = (tmp_path / "motions").glob("*.npz")
    read, none_read = fly(MODEL, 2.0, 600.0, None)
    assert [m.label for m in read] == ["static", "cruise", "manoeuvre"]
    assert none == none_read == ()
    for a, b in zip(flown, read, strict=True):
        assert (a.label, a.description) == (b.label, b.description)
        for name in ("times", "x", "u", "p"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert a.navigation.keys() == b.navigation.keys()
        assert all(np.array_equal(a.navigation[k], b.navigation[k]) for k in a.navigation)
    model = load_model(MODEL)
    p = model.parameter_vector()
    keys = {motion_store.key(model, 2.0, 600.0, None, p),
            motion_store.key(model, 2.0, 300.0, None, p),
            motion_store.key(model, 3.0, 600.0, None, p),
            motion_store.key(model, 2.0, 600.0, "wgs84", model.parameter_vector(
                ellipsoid="wgs84")),
            motion_store.key(model, 2.0, 600.0, None, p * (1 + 1e-15))}
    assert len(keys) == 5 and stored.stem in keys
    stored.write_bytes(b"not a store")
    with pytest.warns(RuntimeWarning, match="is damaged .* flying the motions again"):
        again, _ = fly(MODEL, 2.0, 600.0, None)
    assert np.array_equal(again[2].x, flown[2].x)
    assert motion_store.load(stored.stem) is not None  # written anew
    for i in range(motion_store.KEEP + 3):
        motion_store.store(f"extra_{i}", [("static", "", {f: np.zeros(2) for f in
                                                           motion_store.FIELDS})])
    assert len(list((tmp_path / "motions").glob("*.npz"))) == motion_store.KEEP
    assert not list((tmp_path / "motions").glob("*.tmp"))


def test_stored_propagations_are_the_computed_ones_to_the_bit(tmp_path, monkeypatch):
    """A propagation read back from the on-disk store (the next process) is the computed
    one bit for bit; a damaged file is computed again; other instants are another
    entry; pruning keeps the most recently used files."""
    from collections import OrderedDict

    from ins_errors.checker import propagation_store

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    rng = np.random.default_rng(5)
    times = np.arange(0.0, 3601.0, 60.0)
    A = 1e-3 * rng.standard_normal((times.size, 6, 6))
    expected = transition._computed(A, times, [1800.0, 3600.0])

    def fresh(at):
        monkeypatch.setattr(transition, "_KEPT", OrderedDict())  # a new process
        return transition.transitions(A, times, at)

    first = fresh([1800.0, 3600.0])
    (stored,) = (tmp_path / "transitions").glob("*.npy")
    second = fresh([1800.0, 3600.0])
    for got in (first, second):
        assert all(np.array_equal(g, e) for g, e in zip(got, expected, strict=True))
    stored.write_bytes(b"damaged")
    with pytest.warns(RuntimeWarning, match="is damaged .* propagating again"):
        again = fresh([1800.0, 3600.0])
    assert all(np.array_equal(g, e) for g, e in zip(again, expected, strict=True))
    assert propagation_store.load(stored.stem) is not None  # written anew
    fresh([3600.0])
    assert len(list((tmp_path / "transitions").glob("*.npy"))) == 2
    propagation_store.prune(tmp_path / "transitions", 1)
    assert len(list((tmp_path / "transitions").glob("*.npy"))) == 1


def test_a_model_file_shaped_like_north_pointing_gives_the_same_findings(tmp_path,
                                                                          monkeypatch):
    # a researcher's modified copy of the built-in model, under its own name: the same
    # states, inputs and parameters, so the same navigation description and findings
    from ins_errors.numeric.model import _file_model

    monkeypatch.setattr("ins_errors.model_lookup.models_cache_directory",
                        lambda: tmp_path / "cache")
    _file_model.cache_clear()
    source = Path(mc.__file__).resolve().parent.parent / "models" / "north_pointing.py"
    text = source.read_text(encoding="utf-8")
    assert text.count('name="north_pointing",') == 1
    copy = tmp_path / "my_platform.py"
    copy.write_text(text.replace('name="north_pointing",', 'name="my_platform",'),
                    encoding="utf-8")
    hand = _copy(tmp_path, "F[1, 4] = f_u", "F[1, 4] = -f_u")
    reports = [mc.check_matrices(name, hand, "model", hours=1.0, step=600.0, effects=False)
               for name in (str(copy), MODEL)]
    by_file, by_name = ([(f.matrix, f.row, f.column, f.kind, f.severity, f.size)
                         for f in r.findings] for r in reports)
    assert by_file == by_name and [f[:4] for f in by_file] == [
        ("F", "delta_v_N", "alpha_E", "wrong sign")]
    assert reports[0].exit_status == reports[1].exit_status == 1
    assert reports[0].compared == reports[1].compared == 7 * 7 + 7 * 5


# --------------------------------------------------------------------------------------
# Ellipsoid terms left out: judged by the difference; sizes alike in every convention
# --------------------------------------------------------------------------------------
def _derived_hand(model, conv_name: str, motion_list, edit) -> HandMatrices:
    """The derived F in ``conv_name`` with ``edit(F, nav)`` applied on each motion."""
    conv = convention(model, conv_name)
    F = {}
    for motion in motion_list:
        f = np.array(mc.derived_in_convention(model, conv, motion)[0])
        edit(f, conv.names, motion.navigation)
        F[motion.label] = f
    return HandMatrices("edited", list(conv.names), [], F, {})


def _dre_dlat(nav):
    """∂R_E/∂φ of the prime-vertical radius R_E = a / √(1 − e² sin² φ), m/rad."""
    s, c = np.sin(nav["latitude"]), np.cos(nav["latitude"])
    return nav["a"] * nav["e2"] * s * c / (1 - nav["e2"] * s**2) ** 1.5


@pytest.fixture(scope="module")
def strapdown_day():
    """The documented day-long motions (every 60 s): on the weave some samples fall
    close to the zero crossings of the transport-rate entries."""
    return mc.motions(load_model("strapdown_ned"))


def test_transport_rate_without_the_radius_derivative_is_an_approximation(strapdown_day):
    """A φ-angle model that leaves ∂R_E/∂φ out of ω_en's latitude partials misses the
    same ellipsoid term in F[phi_N, dlat] (−v_E ∂R_E/∂φ / (R_E+h)²) and F[phi_D, dlat]
    (+v_E tan φ ∂R_E/∂φ / (R_E+h)²). On the weave v_E changes sign, so F[phi_D, dlat] =
    −U cos φ − v_E / ((R_E+h) cos² φ) + … crosses zero and hand/model is far from 1 there;
    the difference is still the small omitted term: an approximation, not a mistake."""
    model = load_model("strapdown_ned")
    down, crosses = {}, {}

    def drop(F, names, nav):
        r_e = nav["R_E"] + nav["height"]
        v_e = nav["v_ned"][1]
        i, d = names.index("dlat"), names.index("phi_D")
        F[:, names.index("phi_N"), i] += v_e * _dre_dlat(nav) / r_e**2
        label = "manoeuvre" if v_e.min() < 0 < v_e.max() else "cruise/static"
        crosses[label] = bool(F[:, d, i].min() < 0 < F[:, d, i].max())
        down[len(down)] = v_e * np.tan(nav["latitude"]) * _dre_dlat(nav) / r_e**2
        F[:, d, i] -= down[len(down) - 1]

    hand = _derived_hand(model, "phi_geodetic", strapdown_day, drop)
    assert crosses["manoeuvre"]  # the entry crosses zero on the weave
    report = mc.check_matrices("strapdown_ned", hand, "phi_geodetic",
                               motion_list=strapdown_day, effects=False)
    assert report.exit_status == 0
    assert sorted(f.entry for f in report.findings) == ["F[phi_D, dlat]", "F[phi_N, dlat]"]
    for f in report.findings:
        assert (f.kind, f.severity) == ("approximated", "dropped small term")
    # the difference reported is the omitted term computed here, at its sample
    f = report.finding("phi_D", "dlat")
    k = [m.label for m in strapdown_day].index(f.motion)
    sample = round(f.time / mc.STEP)
    assert f.model - f.hand == pytest.approx(down[k][sample], rel=1e-6)
    # a coefficient that is wrong where it crosses zero is still a wrong coefficient:
    # an offset of a fifth of the entry's largest value, or the entry's opposite
    def offset(F, names, nav):
        entry = F[:, names.index("phi_D"), names.index("dlat")]
        entry -= 0.2 * np.abs(entry).max()

    def flipped(F, names, nav):
        entry = F[:, names.index("phi_D"), names.index("dlat")]
        entry *= -1.0
        drop(F, names, nav)

    for edit, kind in ((offset, "wrong coefficient"), (flipped, "wrong sign")):
        report = mc.check_matrices("strapdown_ned",
                                   _derived_hand(model, "phi_geodetic", strapdown_day, edit),
                                   "phi_geodetic", motion_list=strapdown_day, effects=False)
        [mistake] = report.mistakes
        assert (mistake.entry, mistake.kind) == ("F[phi_D, dlat]", kind)


def _gravity_gradient(nav):
    """∂γ/∂φ of the international gravity formula γ = γ_e (1 + β sin² φ), m/s² per rad."""
    return 9.780327 * 0.0053024 * np.sin(2 * nav["latitude"])


def test_a_position_error_has_the_same_size_as_latitude_or_as_metres(strapdown_motions):
    """Leaving out the change of gravity with latitude is one physical omission whether
    position is written as dr_N (m) or dlat (rad): its size must not depend on that. The
    typical latitude error is the typical position error over the Earth radius (10 m / a),
    and the terminal report lists the sizes used."""
    model = load_model("strapdown_ned")

    def psi_edit(F, names, nav):
        F[:, names.index("dvc_D"), names.index("dr_N")] -= (
            _gravity_gradient(nav) / (nav["R_N"] + nav["height"]))

    def phi_edit(F, names, nav):
        F[:, names.index("dv_D"), names.index("dlat")] -= _gravity_gradient(nav)

    sizes = {}
    for name, edit, entry in (("psi", psi_edit, ("dvc_D", "dr_N")),
                              ("phi_geodetic", phi_edit, ("dv_D", "dlat"))):
        report = mc.check_matrices("strapdown_ned",
                                   _derived_hand(model, name, strapdown_motions, edit), name,
                                   motion_list=strapdown_motions, effects=False)
        f = report.finding(*entry)
        assert f.size_class == "small"
        sizes[name] = f.size
    assert sizes["phi_geodetic"] == pytest.approx(sizes["psi"], rel=0.01)
    assert report.magnitudes["dlat"][0] == pytest.approx(10.0 / 6_378_137.0, rel=1e-12)
    assert report.magnitudes["dh"][0] == 10.0 and report.magnitudes["phi_N"][0] == 1e-4
    text = to_terminal(report)
    assert "typical sizes: " in text and "dlat, dlon 1.57e-06 rad" in text
    # tied by the Schuler relations, a latitude error is the declared angle (R θ / R)
    schuler = mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                                motion_list=strapdown_motions, effects=False,
                                magnitudes={"attitude": "1e-4 rad"})
    geodetic = mc.check_matrices("strapdown_ned", _agreeing_hand(model, strapdown_motions),
                                 "phi_geodetic", motion_list=strapdown_motions,
                                 effects=False, magnitudes={"attitude": "1e-4 rad"})
    assert geodetic.magnitudes["dlat"][0] == pytest.approx(1e-4, rel=1e-12)
    assert schuler.magnitudes["dr_N"][0] == pytest.approx(637.8137, rel=1e-9)


def _agreeing_hand(model, motion_list) -> HandMatrices:
    """The derived model itself in phi_geodetic (agrees everywhere)."""
    return _derived_hand(model, "phi_geodetic", motion_list, lambda F, names, nav: None)


# --------------------------------------------------------------------------------------
# Runaway growth is said, not printed as 1e48 m
# --------------------------------------------------------------------------------------
def test_a_sign_flipped_schuler_loop_is_reported_as_exponential_growth(strapdown_day):
    """+g/R for −g/R in the east channel (examples/strapdown/psi_model_sign_error.py)
    turns δr̈_E = −(g/R) δr_E into δr̈_E = +(g/R) δr_E: a mode growing as e^{λt},
    λ = √(g/R) (the 2-state closed form). After 24 h (~100 e-foldings) the difference is
    said to grow exponentially with that e-folding time, as the equation checker says it;
    after 1 h (4.5 e-foldings) the figure stays. The rate is also what the day-long
    propagation itself shows between 1 h and 24 h."""
    import json

    from ins_errors.checker.matrix_report import to_json

    spec = f"{PSI.parent / 'psi_model_sign_error.py'}:psi_model_sign_error"
    report = mc.check_matrices("strapdown_ned", spec, "psi", motion_list=strapdown_day)
    [mistake] = report.mistakes
    # the closed form from the hand's own entry +g/R on the static base
    fn, states, _ = load_function(PSI.parent / "psi_model_sign_error.py",
                                  "psi_model_sign_error")
    static = strapdown_day[0]
    nav, imu = next(iter(samples(static.navigation, static.times, static.label)))
    F, _ = fn(nav, imu)
    g_over_r = F[states.index("dvc_E"), states.index("dr_E")]
    assert g_over_r == pytest.approx(nav.gravity / nav.R_E, rel=0.01)
    rate = np.sqrt(g_over_r)  # 1/s
    # numpy's eigenvalues of the hand F with the held vertical channel taken out
    keep = [i for i, s in enumerate(states) if s not in ("dvc_D", "dr_D")]
    eig = np.linalg.eigvals(F[np.ix_(keep, keep)]).real.max()
    effects = {(e.motion, e.hours): e for e in report.effects
               if e.case == "initial psi_N"}
    day, hour = effects[("static", 24.0)], effects[("static", 1.0)]
    assert day.exponential and not hour.exponential and day.growing_mode == "hand"
    assert 1 / day.e_folding == pytest.approx(eig, rel=1e-9)
    assert 1 / day.e_folding == pytest.approx(rate, rel=0.01)
    # the propagation's own growth from 1 h to 24 h (the worst case grows with the mode)
    seen = np.log(day.position_difference / hour.position_difference) / (23 * 3600.0)
    assert 1 / day.e_folding == pytest.approx(seen, rel=0.01)
    for motion in ("cruise", "manoeuvre"):
        assert 1 / effects[(motion, 24.0)].e_folding == pytest.approx(rate, rel=0.02)
        assert not effects[(motion, 1.0)].exponential
    # the entry alone gives the same mode
    alone = report.finding_effects[mistake.entry]
    assert alone.exponential and 1 / alone.e_folding == pytest.approx(rate, rel=0.02)
    text = to_terminal(report)
    assert (f"alone after 24 h: grows exponentially, ×e every {alone.e_folding / 60:.3g} "
            "min (fastest on static)") in text
    rows = [line.split() for line in text.splitlines() if line.startswith("  static ")]
    assert rows[1][:6] == ["static", "24", "h", "grows", "exponentially,", "×e"]
    assert rows[1][7:9] == [f"{day.e_folding / 60:.3g}", "min"]
    assert float(rows[0][3]) > 1e4 and rows[0][4] == "m"  # the 1-h figure (26 km) stays
    assert not re.search(r"e\+[1-9]\d", text)  # no figure like 8.84e+48 m anywhere
    data = json.loads(json.dumps(to_json(report)))
    [row] = [e for e in data["effects"] if (e["motion"], e["hours"], e["case"])
             == ("static", 24.0, "initial psi_N")]
    assert row["exponential"] and row["growth_rate_per_s"] == pytest.approx(eig, rel=1e-9)
    assert row["e_folding_s"] == pytest.approx(1 / eig, rel=1e-9)
    [finding] = [f for f in data["findings"] if f["severity"] == "mistake"]
    assert finding["effect_alone_24h"]["exponential"]
    assert finding["effect_alone_24h"]["growth_rate_per_s"] == pytest.approx(rate, rel=0.02)
    # what docs/matrix_check.md shows is the report's
    lines = [line.strip() for line in text.splitlines()]
    assert all(line in lines for line in _doc_block("**Exponential growth.**").splitlines())
    # a mistake without a growing mode keeps its figures
    assert not any(e.exponential for f, e in report.finding_effects.items()
                   if f != mistake.entry)


# --------------------------------------------------------------------------------------
# A term left out of an entry that holds several
# --------------------------------------------------------------------------------------
def _gravity_term(model):
    """∂γ/∂φ of the model's own gravity formula (SymPy, differentiated here), as a
    function of the samples of a motion: (K,) m/s² per rad."""
    import sympy as sp

    from ins_errors.symbolic.variation import ideal_intermediate_values

    d = model.symbolic
    closed = ideal_intermediate_values(d)
    [gamma] = [s for s in closed if s.name == "gamma"]
    [lat] = [s for s in d.x if s.name == "lat"]
    function = sp.lambdify([*d.x, *d.u, *d.p], sp.diff(closed[gamma], lat), "numpy")
    return lambda motion: np.broadcast_to(function(*motion.x, *motion.u, *motion.p),
                                          motion.times.shape)


def test_gravity_gradient_left_out_of_a_sum_is_an_omitted_term(strapdown_motions):
    """F[dv_D, dlat] of the φ-geodetic model holds ∂γ/∂φ and Coriolis and transport-rate
    terms. A hand F without ∂γ/∂φ (the model's own F less that term, differentiated here
    from the model's gravity formula) is the same omission as the ψ model's F[dvc_D,
    dr_N] = 0: an omitted term and a dropped small term, named, not a wrong coefficient.
    With a threshold below its size it is a mistake, still an omitted term (the equation
    checker's classes); half of the term left out, or the term twice, is a wrong
    coefficient."""
    model = load_model("strapdown_ned")
    gradient = _gravity_term(model)
    conv = convention(model, "phi_geodetic")
    row, column = conv.names.index("dv_D"), conv.names.index("dlat")

    def hand(factor, two=False):
        """The derived F less factor × ∂γ/∂φ in F[dv_D, dlat]; with ``two`` also less
        the Coriolis and one transport term of F[dv_D, dv_E] = −2U cos φ − 2 v_E/(R_E + h),
        which keeps the other transport term."""
        F = {}
        for motion in strapdown_motions:
            nav = motion.navigation
            F[motion.label] = np.array(mc.derived_in_convention(model, conv, motion)[0])
            F[motion.label][:, row, column] -= factor * gradient(motion)
            if two:
                F[motion.label][:, row, conv.names.index("dv_E")] += (
                    2 * nav["earth_rate"] * np.cos(nav["latitude"])
                    + nav["v_ned"][1] / (nav["R_E"] + nav["height"]))
        return HandMatrices("edited", list(conv.names), [], F, {})

    def check(hand_matrices, threshold=mc.DEFAULT_THRESHOLD):
        return mc.check_matrices("strapdown_ned", hand_matrices, "phi_geodetic",
                                 motion_list=strapdown_motions, effects=False,
                                 threshold=threshold)

    report = check(hand(1.0))
    [f] = report.findings
    assert (f.entry, f.kind, f.severity) == ("F[dv_D, dlat]", "omitted term",
                                             "dropped small term")
    assert report.exit_status == 0
    assert f.detail.startswith("term left out: ") and "Delta_gamma" in f.detail
    # its size against the entry: on the static base ∂γ/∂φ is the whole entry
    share = float(re.search(r"up to ([\d.e+-]+) of the entry", f.detail).group(1))
    entry = np.concatenate([np.abs(mc.derived_in_convention(model, conv, m)[0][:, row, column])
                            for m in strapdown_motions])
    gradients = np.concatenate([gradient(m) for m in strapdown_motions])
    assert share == pytest.approx(np.abs(gradients).max() / entry.max(), rel=0.01)
    assert np.abs(gradients).max() == pytest.approx(9.780327 * 0.0053024, rel=0.01)
    # the ψ convention's spelling of the same omission has the same class
    psi = mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi",
                            motion_list=strapdown_motions, effects=False)
    same = psi.finding("dvc_D", "dr_N")
    assert (same.kind, same.severity) == (f.kind, f.severity)
    # by its size: a mistake below its size, still an omitted term
    strict = check(hand(1.0), threshold=f.size / 2)
    assert [(g.entry, g.kind, g.severity) for g in strict.findings] == [
        ("F[dv_D, dlat]", "omitted term", "mistake")] and strict.exit_status == 1
    # two terms left out together: both named
    both = check(hand(0.0, two=True)).finding("dv_D", "dv_E")
    assert (both.kind, both.severity) == ("omitted term", "mistake")  # 1 % of its row
    assert both.detail.startswith("terms left out: -2*Omega_N (")
    # ρ_N and −v_E/(R_E + h) (of Δρ_N v_E) are equal: either is the other term left out
    assert ("and one of 2 terms of the entry equal in value at every sample: " in both.detail
            and "rho_N" in both.detail and "v_E/(R_E + h)" in both.detail)
    # a genuinely wrong coefficient stays one
    for factor in (0.5, -1.0):
        report = check(hand(factor))
        [wrong] = report.mistakes
        assert (wrong.entry, wrong.kind) == ("F[dv_D, dlat]", "wrong coefficient")
        assert "term left out" not in wrong.detail


def test_coriolis_part_of_the_turn_rate_left_out(tmp_path, wgs84):
    """north_pointing writes F[δv_E, δv_N] as one quantity, turn_rate = 2U sin φ +
    v_E tan φ / r_E. The textbook hand model without its Coriolis part 2U sin φ leaves out
    a term of that sum: named as such (as the equation checker names a missing part of a
    coefficient), and a mistake by its size (~1 % of the row)."""
    report = mc.check_matrices(MODEL, _copy(tmp_path, "    F[0, 1] = turn",
                                            "    F[0, 1] = turn - 2 * U * s"),
                               "model", motion_list=wgs84, effects=False)
    [f] = report.findings
    assert (f.entry, f.kind, f.severity) == ("F[delta_v_E, delta_v_N]", "omitted term",
                                             "mistake")
    assert f.detail.startswith("term left out: 2*U*sin(phi) (from turn_rate = ")
    motion = next(m for m in wgs84 if m.label == f.motion)
    k = round(f.time / (motion.times[1] - motion.times[0]))
    coriolis = 2 * 7.292115e-5 * np.sin(motion.navigation["latitude"][k])
    assert f.model - f.hand == pytest.approx(coriolis, rel=1e-6)
    # the line docs/matrix_check.md shows is the report's (its elisions aside)
    shown = _doc_block("**A term left out of a sum.**")
    text = to_terminal(report)
    assert all(piece.strip(" ;") in text for piece in shown.split("…"))


def _doc_block(after: str) -> str:
    """The first code block of docs/matrix_check.md after the text ``after``."""
    doc = (DATA.parent.parent / "docs" / "matrix_check.md").read_text(encoding="utf-8")
    block = doc.split(after, 1)[1].split("```\n", 1)[1].split("```", 1)[0]
    return "\n".join(line.strip() for line in block.strip("\n").splitlines())


def test_a_vertical_channel_that_overflows_is_reported_without_a_numpy_warning(capsys):
    # on a sphere of 100 km the hand's ψ model's 2g/R vertical term grows e-fold every
    # sqrt(R / 2g) = 71.4 s: its 24-h height effect overflows; numpy's "invalid value in
    # matmul" (a machine path) was printed before the report
    import json
    import warnings

    sphere = PSI.parent / "strapdown_sphere.py"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        status = main(["check", str(sphere), "--matrix", f"{PSI}:psi_model", "--convention",
                       "psi", "-p", "R=100km", "--json"])
    captured = capsys.readouterr()
    assert status == 1 and "Warning" not in captured.err, captured.err
    report = json.loads(captured.out)
    (vertical,) = [f["effect_vertical"] for f in report["findings"]
                   if (f["row"], f["column"]) == ("dvc_D", "dr_D")]
    assert vertical["exponential"] == [True, True] and vertical["growing_mode"] == "hand"
    assert vertical["e_folding_s"] == pytest.approx(np.sqrt(100e3 / (2 * 9.81)), rel=1e-3)
    for finding in report["findings"]:  # the horizontal effects stay finite numbers
        effect = finding["effect_alone_24h"]
        assert effect is None or all(np.isfinite(v) for v in effect.values()
                                     if isinstance(v, float))


def test_a_damped_vertical_channel_is_not_held():
    """The vertical channel was held in every effect propagation, damped or not, so the
    effect of every height term read "not assessed: the vertical channel is held" even
    with the damping gains set (the PhD probe's baro-damped INS). With the gains set
    strapdown_ned's F at rest has no growing mode, and nothing is held: a finding in the
    vertical rows gets its figures like any other. Undamped, the channel is held as
    before (it grows ×e every 9.5 min)."""
    from ins_errors.numeric.linear_system import growth_rate

    w0 = 2 * np.pi / 300.0
    gains = {"k_h1": 2 * 0.7 * w0, "k_h2": w0**2 + 2 * 9.80665 / 6_371_000.0}
    damped = mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi", parameters=gains)
    undamped = mc.check_matrices("strapdown_ned", f"{PSI}:psi_model", "psi", effects=False)
    assert undamped.vertical == ["dvc_D", "dr_D"]
    assert damped.held == [] and damped.vertical == []
    from ins_errors.numeric import strapdown_truth as st

    # the independent part: the damped F at rest has no growing mode
    model = load_model("strapdown_ned")
    p = model.parameter_vector(**gains)
    motion = st.trajectory(model, st.static(np.radians(50.0)), 1.0, 1.0, p=p)
    x0, u0 = motion.start_state, motion.start_inputs
    assert growth_rate(np.asarray(model.state_matrix(x0, u0, p))) <= 1e-7
    # the hand leaves out the k_h1 damping of dr_D: its effect is now given
    alone = damped.finding_effects["F[dr_D, dr_D]"]
    assert alone.position is not None and alone.position_above_rounding


def test_one_radius_of_curvature_written_for_the_other(strapdown_motions):
    """The latitude rate is δv_N/(R_N + h) (meridian radius), the longitude rate
    δv_E/((R_E + h) cos φ) (prime vertical). A hand F with the other radius in either is
    within 0.7 % of the derived entry, yet hand/model is exactly a ratio of the radii at
    every sample: a wrong symbol, a mistake at any threshold. The radius a of a sphere
    in the same place, and the change of R_E with latitude left out of the longitude
    rate's latitude column (whose ratio is also (R_E + h)/(R_N + h), as
    ∂((R_E + h) cos φ)/∂φ = −(R_N + h) sin φ), stay approximations."""
    model = load_model("strapdown_ned")

    def entry(F, names, row, column):
        return slice(None), names.index(row), names.index(column)

    def meridian_slip(F, names, nav):
        F[entry(F, names, "dlat", "dv_N")] = 1.0 / (nav["R_E"] + nav["height"])

    def prime_vertical_slip(F, names, nav):
        F[entry(F, names, "dlon", "dv_E")] = 1.0 / (
            (nav["R_N"] + nav["height"]) * np.cos(nav["latitude"]))

    def sphere(F, names, nav):
        F[entry(F, names, "dlat", "dv_N")] = 1.0 / (nav["a"] + nav["height"])

    def radius_derivative_left_out(F, names, nav):
        lat = nav["latitude"]
        F[entry(F, names, "dlon", "dlat")] = (
            nav["v_ned"][1] * np.tan(lat) / ((nav["R_E"] + nav["height"]) * np.cos(lat)))

    expected = {
        meridian_slip: ("dlat", "dv_N", "wrong symbol or index", "(R_N + h)/(R_E + h)"),
        prime_vertical_slip: ("dlon", "dv_E", "wrong symbol or index",
                              "(R_E + h)/(R_N + h)"),
        sphere: ("dlat", "dv_N", "approximated", "hand/model between"),
        radius_derivative_left_out: ("dlon", "dlat", "approximated", "hand/model between"),
    }
    for edit, (row, column, kind, said) in expected.items():
        hand = _derived_hand(model, "phi_geodetic", strapdown_motions, edit)
        for threshold in (1e-3, 1e-2):
            report = mc.check_matrices("strapdown_ned", hand, "phi_geodetic",
                                       threshold=threshold, motion_list=strapdown_motions,
                                       effects=False)
            [f] = report.findings
            assert (f.row, f.column, f.kind) == (row, column, kind), edit.__name__
            assert said in f.detail
            if kind == "approximated":
                assert f.severity == "dropped small term" and report.exit_status == 0
            else:
                assert f in report.mistakes and report.exit_status == 1


def test_a_huge_hand_entry_prints_no_numpy_warning(tmp_path):
    """F[psi_N, psi_E] = 1000 /s in a ψ model (the adversary probe): its effects overflow,
    and numpy's "invalid value encountered in matmul" (with a machine path) was printed
    on stderr before the report. The report comes without it."""
    import warnings

    text = PSI.read_text(encoding="utf-8").replace(
        "    G = np.zeros((9, 6))", "    F[0, 1] = 1e3\n    G = np.zeros((9, 6))", 1)
    assert "F[0, 1] = 1e3" in text
    hand = tmp_path / "huge.py"
    hand.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        report = mc.check_matrices("strapdown_ned", f"{hand}:psi_model", "psi")
    (found,) = [f for f in report.findings if (f.row, f.column) == ("psi_N", "psi_E")]
    assert found.kind == "wrong coefficient" and found.hand == pytest.approx(1e3)
