"""A strapdown model file describes itself by its outputs: its navigation description
and the φ/ψ conventions come from them (ins_errors.checker.strapdown_description), so a
hand-coded F is checked against one's own strapdown INS.

References, independent of that module:

* ``strapdown_ned`` on the file's sphere (another attitude representation, a quaternion,
  carried into the conventions by its own hand-written maps and T⁺): the same flight
  gives the same F in every convention, except the gravity gradient of the height that
  only ``strapdown_ned`` has (its normal gravity falls off as 2g/R per metre; the file's
  g is constant);
* the textbook ψ-angle model of examples/strapdown/psi_model.py (Benson 1975), which has
  that gradient (Γ = (g/R) diag(−1, −1, 2)) and the radius R where the file has R + h.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.checker.conventions import conventions
from ins_errors.cli import main
from ins_errors.models import strapdown_conventions as sc
from ins_errors.numeric import trajectories as tr

ROOT = Path(__file__).resolve().parents[1]
SPHERE_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"
PSI_MODEL = ROOT / "examples" / "strapdown" / "psi_model.py"


@pytest.fixture(scope="module")
def sphere():
    return load_model(str(SPHERE_FILE))


def _flight(model, p=None) -> tr.Trajectory:
    # level at h = 0 (where strapdown_ned's gravity is the file's g): turns and a speed
    # change, so that the attitude and the specific force move
    legs = [tr.Leg(600.0, 250.0, np.radians(90.0), 0.0), tr.Leg(600.0, 300.0, 0.0, 0.0)]
    profile = tr.manoeuvre_profile(np.radians(50), np.radians(30), np.radians(60), 250.0,
                                   legs)
    return tr.trajectory(model, profile, 1800.0, 60.0, p=p, stream=False)


@pytest.mark.parametrize("name", ["phi", "psi", "phi_modified", "psi_geodetic"])
def test_a_dcm_model_file_in_a_convention_is_strapdown_ned_on_its_sphere(sphere, name):
    ned = load_model("strapdown_ned")
    p_ned = ned.parameter_vector(a=6_371_000.0, e2=0.0, gamma_e=9.81, gravity_k=0.0,
                                 gravity_m=0.0)
    mine, theirs = _flight(sphere), _flight(ned, p_ned)
    conv = conventions(sphere)[name]
    T, T_dot = conv.matrices(sphere, mine.truth, mine.parameters, mine.inputs)
    L = np.moveaxis(conv.lift(mine.truth, mine.parameters), -1, 0)
    assert np.abs(T @ L - np.eye(9)).max() < 1e-9
    F = np.moveaxis(sphere.state_matrix(mine.truth, mine.inputs, mine.parameters), -1, 0)
    G = np.moveaxis(sphere.source_matrix(mine.truth, mine.inputs, mine.parameters), -1, 0)
    F_mine, G_mine = (T_dot + T @ F) @ L, T @ G
    F_ned, G_ned = sc.convention_matrices(ned, name.removesuffix("_geodetic"), theirs.truth,
                                          theirs.inputs, p_ned,
                                          "geodetic" if "geodetic" in name else "ned")
    F_ned, G_ned = np.moveaxis(F_ned, -1, 0), np.moveaxis(G_ned, -1, 0)
    names = sc.state_names(name.removesuffix("_geodetic"),
                           "geodetic" if "geodetic" in name else "ned")
    vertical_velocity = next(i for i, n in enumerate(names) if n.endswith("_D") and
                             not n.startswith(("phi", "psi", "dr")))
    height = len(names) - 1
    # the only difference: ∂(gravity)/∂h, 2g/R in strapdown_ned, none in the file
    gradient = F_ned[:, vertical_velocity, height] - F_mine[:, vertical_velocity, height]
    sign = 1.0 if names[height] == "dr_D" else -1.0  # dr_D = −δh; g falls off upwards
    np.testing.assert_allclose(gradient, sign * 2 * 9.81 / 6_371_000.0, rtol=1e-3)
    F_ned[:, vertical_velocity, height] = F_mine[:, vertical_velocity, height]
    # (the lift puts the convention's states on the orthonormal matrices; with the
    # φ-rows read as the skew part of −δC Cᵀ, T⁺ happens to land there too for a DCM,
    # but not for a map whose tangent is not orthogonal to T's null space)
    scale = np.abs(F_ned).max(axis=2, keepdims=True) + 1e-300  # per row
    assert (np.abs(F_mine - F_ned) / scale).max() < 1e-9  # (rows of mixed units)
    gyro_accel = [ned.index("sources", s.name) for s in sphere.sources]
    np.testing.assert_allclose(G_mine, G_ned[:, :, gyro_accel], rtol=0,
                               atol=1e-9 * np.abs(G_ned).max())


@pytest.mark.parametrize("name", ["phi", "psi", "phi_modified", "psi_geodetic"])
def test_the_lift_of_a_convention_is_exact_to_rounding_despite_mixed_units(sphere, name):
    # T K mixes radians of latitude per metre with dimensionless attitude entries
    # (condition number about the Earth's radius in metres): the lift L = K (T K)⁻¹ must
    # still invert T to rounding, or the span check that every φ/ψ check makes first
    # (a state's off-span part ≤ 1e-8 of its rate) passes with one BLAS and fails with
    # another (1.44e-8 for 'lat' with OpenBLAS 0.3.31 on an AMD EPYC)
    mine = _flight(sphere)
    conv = conventions(sphere)[name]
    T = np.moveaxis(conv.transform(mine.truth, mine.parameters), -1, 0)
    L = np.moveaxis(conv.lift(mine.truth, mine.parameters), -1, 0)
    assert np.abs(T @ L - np.eye(9)).max() < 1e-13


def test_the_textbook_psi_model_checked_against_a_dcm_model_file(sphere, capsys):
    import json

    status = main(["check", str(SPHERE_FILE), "--matrix", f"{PSI_MODEL}:psi_model",
                   "--convention", "psi", "--json"])
    report = json.loads(capsys.readouterr().out)
    assert status == 1
    entries = {(f["row"], f["column"]): f for f in report["findings"]}
    assert report["compared"] == 135
    # every entry agrees but three (findings list only the others)
    assert set(entries) == {("dvc_D", "dr_D"), ("dvc_N", "dr_N"), ("dvc_E", "dr_E")}
    # the textbook's vertical gravity gradient 2g/R, which the file's constant g lacks
    vertical = entries["dvc_D", "dr_D"]
    assert (vertical["kind"], vertical["severity"]) == ("extra term", "mistake")
    assert vertical["hand"] == pytest.approx(2 * 9.81 / 6_371_000, rel=1e-9)
    # R for R + h in the horizontal gravity terms: on the cruise at 10 km the hand's
    # coefficient is the model's times (R + h)/R
    for key in (("dvc_N", "dr_N"), ("dvc_E", "dr_E")):
        finding = entries[key]
        assert (finding["kind"], finding["severity"]) == ("approximated",
                                                         "dropped small term")
        assert (finding["motion"], finding["time_s"]) == ("cruise", 0.0)
        assert finding["hand"] / finding["model"] == pytest.approx(
            1 + 10_000 / 6_371_000, rel=1e-9)


def test_the_15_state_psi_model_checked_against_a_dcm_model_file(sphere, capsys):
    """The biases as states (examples/strapdown/psi_model_15.py, [[F, G], [0, 0]]): the
    same three entries as the 9-state form with G, the bias columns and rows agree."""
    import json

    status = main(["check", str(SPHERE_FILE), "--matrix",
                   f"{PSI_MODEL.parent / 'psi_model_15.py'}:psi_model_15",
                   "--convention", "psi", "--json"])
    report = json.loads(capsys.readouterr().out)
    assert status == 1
    assert report["compared"] == 15 * 15
    assert [b["name"] for b in report["bias_states"]] == [
        f"{kind}_bias_{axis}" for kind in ("gyro", "accel") for axis in "xyz"]
    entries = {(f["row"], f["column"]): f for f in report["findings"]}
    assert set(entries) == {("dvc_D", "dr_D"), ("dvc_N", "dr_N"), ("dvc_E", "dr_E")}
    vertical = entries["dvc_D", "dr_D"]
    assert (vertical["kind"], vertical["severity"]) == ("extra term", "mistake")
    assert vertical["hand"] == pytest.approx(2 * 9.81 / 6_371_000, rel=1e-9)
    assert [f for f in report["findings"] if f["severity"] == "mistake"] == [vertical]
    for key in (("dvc_N", "dr_N"), ("dvc_E", "dr_E")):
        assert entries[key]["hand"] / entries[key]["model"] == pytest.approx(
            1 + 10_000 / 6_371_000, rel=1e-9)


def test_a_model_file_without_the_navigation_outputs_is_refused_in_one_line(tmp_path,
                                                                           capsys,
                                                                           monkeypatch):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = SPHERE_FILE.read_text(encoding="utf-8")
    text = text.replace('ANGLES = (("roll", r"\\gamma"), ', 'ANGLES = (("bank", r"\\gamma"), ')
    text = text.replace('c["roll"]', 'c["bank"]')
    path = tmp_path / "no_roll.py"
    path.write_text(text, encoding="utf-8")
    status = main(["check", str(path), "--matrix", f"{PSI_MODEL}:psi_model", "--convention",
                   "psi"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    assert "lacks the outputs roll" in err[0]


@pytest.mark.parametrize("file, status, mistakes", [
    ("phi_attitude.txt", 0, []),
    ("phi_attitude_sign_error.txt", 1, [("phi_E", "phi_N", "wrong sign")]),
])
def test_textbook_phi_attitude_equations_checked_against_a_dcm_model_file(file, status,
                                                                          mistakes, capsys):
    # the φ-angle attitude equation φ̇ = −ω_in × φ + δω_in − C_b^n δω holds for any
    # strapdown mechanisation: written for strapdown_ned's conventions, it holds for the
    # file's direction-cosine matrix, and a flipped sign is found there too
    import json

    assert main(["check", str(SPHERE_FILE), str(PSI_MODEL.parent / file), "--json"]) == status
    report = json.loads(capsys.readouterr().out)
    found = [(f["row"], f["column"], f["kind"]) for f in report["findings"]
             if f["severity"] == "mistake"]
    assert found == mistakes
    assert report["compared"] == 36


ENU_FILE = ROOT / "tests" / "models" / "enu_strapdown.py"


@pytest.fixture
def psi_check(capsys):
    """The ψ-model check against a model: {(row, column): (kind, severity)}, compared."""
    import json

    def run(model: str) -> tuple[dict, int]:
        main(["check", model, "--matrix", f"{PSI_MODEL}:psi_model", "--convention", "psi",
              "--json"])
        report = json.loads(capsys.readouterr().out)
        return ({(f["row"], f["column"]): (f["kind"], f["severity"])
                 for f in report["findings"]}, report["compared"])

    return run


def test_strapdown_ned_as_a_model_file_is_checked_as_the_built_in(psi_check, tmp_path):
    # a quaternion model file: its initial-state map gives −q once the manoeuvre's heading
    # has wrapped past ±180° (4.7 h), where its flight keeps q (the lift absorbs it)
    source = (ROOT / "ins_errors" / "models" / "strapdown_ned.py").read_text(encoding="utf-8")
    assert source.count('name="strapdown_ned"') == 1
    path = tmp_path / "my_strapdown.py"
    path.write_text(source.replace('name="strapdown_ned"', 'name="my_strapdown"'),
                    encoding="utf-8")
    built_in = psi_check("strapdown_ned")
    assert psi_check(str(path)) == built_in
    assert built_in[1] == 135 and all(s != "mistake" for _, s in built_in[0].values())


def test_an_enu_model_with_right_forward_up_axes_is_checked_in_ned(psi_check):
    # ENU navigation, body axes right-forward-up, v_U output: its C_bn comes from its
    # own equations, so the textbook model (NED) finds what it finds on strapdown_ned
    # (the same WGS-84 Earth and normal gravity, up to the fall-off with height)
    mine, compared = psi_check(str(ENU_FILE))
    theirs, _ = psi_check("strapdown_ned")
    assert compared == 135
    assert all(severity != "mistake" for _, severity in mine.values())
    assert set(mine) == set(theirs)


def test_the_attitude_of_an_enu_model_is_read_from_its_equations():
    from ins_errors.checker.navigation import navigation_arrays
    from ins_errors.numeric.strapdown_truth import euler_matrix

    profile = tr.great_circle_profile(np.radians(40), 0.0, np.radians(120), 200.0)
    navs = []
    for model in (load_model(str(ENU_FILE)), load_model("strapdown_ned")):
        traj = tr.trajectory(model, profile, 600.0, 60.0, stream=False)
        navs.append(navigation_arrays(model, traj.truth, traj.inputs, traj.parameters))
    mine, ned = navs
    C = np.moveaxis(mine["C_bn"], -1, 0)
    np.testing.assert_allclose(C @ np.swapaxes(C, 1, 2), np.broadcast_to(np.eye(3), C.shape),
                               atol=1e-12)
    # the IMU signals in NED (f_n = C_bn f_b, ω_ib in NED) are the flight's, whatever the
    # body axes: those of strapdown_ned (the same WGS-84 Earth and gravity at h = 0)
    for field in ("f_b", "omega_ib_b"):
        a = np.einsum("ijk,jk->ik", mine["C_bn"], mine[field])
        b = np.einsum("ijk,jk->ik", ned["C_bn"], ned[field])
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * np.abs(b).max())
    # right-forward-up body axes: C_bn is the forward-right-down attitude of the flight
    # (heading 120°, level) with its columns permuted: body x = right, y = forward, z = up
    frd = euler_matrix(0.0, 0.0, np.radians(120.0))
    np.testing.assert_allclose(C[0], frd @ np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]]),
                               atol=1e-9)


@pytest.mark.parametrize("option, said", [
    ("a=-6378137m", "a = '-6378137m': the Earth's radius (semi-major axis) must be positive"),
    ("e2=1.5", "e2 = '1.5': the Earth's eccentricity squared must be at least 0"),
    ("a=50km", "a = '50km': an Earth radius of 50000 m is below 100 km"),
])
def test_an_impossible_earth_is_refused_for_a_flight(option, said, capsys):
    status = main(["compare", str(ENU_FILE), "--motion", "great-circle", "--hours", "0.1",
                   "--source", "gyro_bias_x=0.01deg/h", "-p", option])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and said in err[0], err


BARO_LOOP = [  # a third-order barometer loop: its integrator z no navigation quantity sets
    ('    Variable("h", "m", "height", "h"),\n)',
     '    Variable("h", "m", "height", "h"),\n'
     '    Variable("z", "m/s**2", "baro loop integrator", "z"),\n)'),
    ('    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),\n',
     '    Parameter("U", "rad/s", "Earth rate", "U", EARTH_RATE),\n'
     '    Parameter("k3", "1/s**3", "third gain", "k_3", 1e-6),\n'),
    ("    lat, h = state[12], state[14]\n",
     "    lat, h = state[12], state[14]\n    z = state[15]\n"),
    ("+ sp.Matrix([0, 0, g])\n", "+ sp.Matrix([0, 0, g - z])\n"),
    ("v[1] / (r * sp.cos(lat)), -v[2]]",
     "v[1] / (r * sp.cos(lat)), -v[2], -SYMBOL['k3'] * (h - SYMBOL['h_ref'])]"),
    ('f"specific force along {a}", f"f_{a}") for a in AXES),\n)',
     'f"specific force along {a}", f"f_{a}") for a in AXES),\n'
     '    Variable("h_ref", "m", "barometric height", "h_b"),\n)'),
    ("    v_n, v_e, v_d, lat, lon, h = state[9:]", "    v_n, v_e, v_d, lat, lon, h = state[9:15]"),
    ('                       c["height"]])', '                       c["height"], 0])'),
]


@pytest.mark.parametrize("edits, said", [
    (BARO_LOOP, "'z' changes with the navigation errors"),
    ([("sp.asin(-T[2, 0]), sp.atan2(T[1, 0], T[0, 0])",  # heading from east, anticlockwise
       "sp.asin(-T[2, 0]), sp.pi / 2 - sp.atan2(T[1, 0], T[0, 0])")],
     "its output 'heading' does not read back what its initial-state map was given"),
    ([('Variable(f"f_{a}", "m/s**2"', 'Variable(f"f_{a}", "1"'),  # specific force in g
      ("v_dot = T * sp.Matrix(force)", "v_dot = g * T * sp.Matrix(force)"),
      ('f + SYMBOL[f"accel_bias_{a}"]', 'f + SYMBOL[f"accel_bias_{a}"] / SYMBOL["g"]')],
     "is not a rotation"),
    # a velocity output at a lever arm (ω_z × r): no longer a function of the state alone
    ([("return sp.Matrix([lat, lon, h, v_n, v_e, v_d,",
       "return sp.Matrix([lat, lon, h, v_n - 2.0 * inputs[2], v_e, v_d,")],
     "lacks navigation outputs that are functions of the state alone"),
])
def test_a_model_the_conventions_cannot_carry_is_refused_in_one_line(edits, said, tmp_path,
                                                                     capsys, monkeypatch):
    # each was accepted before and gave a report with false findings (or, for the loop,
    # the same report whatever its gain: the integrator was dropped)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = SPHERE_FILE.read_text(encoding="utf-8")
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / "variant.py"
    path.write_text(text, encoding="utf-8")
    status = main(["check", str(path), "--matrix", f"{PSI_MODEL}:psi_model", "--convention",
                   "psi"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1 and said in err[0], err


BARO_FILE = ROOT / "tests" / "models" / "baro_point_mass.py"
BARO_GAINS = ["-p", "k1=0.0293/s", "-p", "k2=4.42e-4/s^2"]


@pytest.mark.parametrize("height", [0.0, 5_000.0, 10_000.0])
def test_the_gravity_of_a_baro_damped_model_file_is_its_own_at_any_height(height):
    # the file's gravity is μ/(R + h)²; its loop k₂ (h − h_ref) adds nothing with the
    # reference at the true height (it added k₂ h, 4.4 m/s² at 10 km, with h_ref = 0)
    from ins_errors.checker import strapdown_description as sd
    from ins_errors.numeric.static_rest import static_rest

    model = load_model(str(BARO_FILE))
    p = model.parameter_vector(k1=0.0293, k2=4.42e-4)
    x, u, _, _ = static_rest(model, np.radians(50), np.radians(30), np.radians(30), height, p)
    # a moving state at that position: the gravity is the same
    moving = x.copy()
    moving[[model.index("states", n) for n in ("v_N", "v_E", "v_D")]] = [200.0, -100.0, 5.0]
    gravity = sd.navigation(model, np.stack([x, moving], axis=1), np.stack([u, u], axis=1),
                            p)["gravity"]
    mu, R = model.parameter_vector()[[1, 0]]
    np.testing.assert_allclose(gravity, mu / (R + height) ** 2, rtol=1e-12)


def test_the_textbook_psi_model_on_a_baro_damped_model_file_at_altitude(capsys):
    # the horizontal gravity terms −g/R of the textbook against the file's −g/(R + h):
    # only R for R + h (a dropped small term), no wrong coefficient at the cruise (10 km)
    # or in the manoeuvre (5 km)
    import json

    status = main(["check", str(BARO_FILE), "--matrix", f"{PSI_MODEL}:psi_model",
                   "--convention", "psi", "--json", *BARO_GAINS])
    report = json.loads(capsys.readouterr().out)
    assert status == 1  # the textbook has no damping loop: its vertical rows differ
    entries = {(f["row"], f["column"]): f for f in report["findings"]}
    for key in (("dvc_N", "dr_N"), ("dvc_E", "dr_E")):
        finding = entries[key]
        assert (finding["kind"], finding["severity"]) == ("approximated",
                                                         "dropped small term")
        assert (finding["motion"], finding["time_s"]) == ("cruise", 0.0)
        assert finding["hand"] / finding["model"] == pytest.approx(
            1 + 10_000 / 6_371_000, rel=1e-9)
    assert {k for k, f in entries.items() if f["severity"] == "mistake"} == {
        ("dvc_D", "dr_D"), ("dr_D", "dr_D")}
