"""Moving flights of a model fed body rates and specific forces (a strapdown model file):
its states from the flight's navigation quantities by its own initial-state map, its
inputs solved from its own ideal work (ins_errors.numeric.model_flight).

References, each independent of that solution:

* ``strapdown_ned``'s true IMU signals from the exact rigid-body kinematics of
  ins_errors.numeric.strapdown_truth (ω_ib = ω_nb + C ω_in, f = C (v̇ + (2Ω + ρ) × v − γ));
* the model's own equations integrated by a plain RK4 written here from the truth's
  inputs: the truth must be their solution;
* ``strapdown_ned`` itself put on the same sphere with the same constant gravity (another
  attitude representation, written separately): the same flight and biases give the same
  horizontal errors.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.cli import main
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.model_flight import FlightAdapter
from ins_errors.numeric.motion_spec import default_legs

SPHERE_FILE = Path(__file__).resolve().parents[1] / "examples" / "strapdown" / "strapdown_sphere.py"
MICRO_G = 9.80665e-6  # m/s²
LEGS = default_legs(250.0, 1000.0, hours=1)


@pytest.fixture(scope="module")
def sphere():
    return load_model(str(SPHERE_FILE))


def manoeuvre(h: float = 1000.0) -> tr.Profile:
    return tr.manoeuvre_profile(np.radians(50), np.radians(30), np.radians(60), 250.0,
                                LEGS, h=h)


def test_strapdown_neds_own_equations_give_its_truths_imu_signals():
    model = load_model("strapdown_ned")
    p = model.parameter_vector(k_h1=0.03, k_h2=4e-4)
    flight = st.flight_from_profile(manoeuvre())
    earth = st._earth(model, p)
    t = np.linspace(0.0, 3600.0, 3601)  # turns, a climb, a speed change, a descent
    y = st._position_solution(flight, earth, 3600.0, 1.0).sol(t)
    state, inputs, _, nav, rates = st.rigid_body_signals(flight, earth, t, y, navigation=True)
    adapter = FlightAdapter(model, p, (nav[:, 0], rates[:, 0]))
    x, u = adapter(nav, rates, t)
    np.testing.assert_allclose(x, state, rtol=0, atol=1e-15)
    for rows in (slice(0, 3), slice(3, 6), slice(6, 7)):  # rad/s, m/s², m
        scale = np.abs(inputs[rows]).max()
        assert np.abs(u[rows] - inputs[rows]).max() <= 1e-12 * scale


def _rk4_ideal(model, truth: tr.Trajectory) -> np.ndarray:
    """The ideal work integrated by RK4 from the truth's start and inputs, (n, N + 1)."""
    f, p, tau = model.numpy.ideal_rhs, truth.parameters, truth.tau
    x = truth.truth[:, 0].copy()
    out = [x.copy()]
    for k in range(truth.n_steps):
        u0, um, u1 = truth.inputs[:, k], truth.midpoints[:, k], truth.inputs[:, k + 1]
        k1 = np.ravel(f(x, u0, p))
        k2 = np.ravel(f(x + tau / 2 * k1, um, p))
        k3 = np.ravel(f(x + tau / 2 * k2, um, p))
        k4 = np.ravel(f(x + tau * k3, u1, p))
        x = x + tau / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(x.copy())
    return np.array(out).T


@pytest.mark.parametrize("truth", ["interpolated", "fine"])
def test_the_flight_of_a_model_file_solves_its_own_equations(sphere, truth):
    # the first 20 min of the manoeuvre: a 90° turn, then a speed change with a climb
    traj = tr.trajectory(sphere, manoeuvre(), 1200.0, 0.5, truth=truth, stream=False)
    assert traj.truth.shape == (len(sphere.states), 2401)
    integrated = _rk4_ideal(sphere, traj)
    names = [s.name for s in sphere.states]
    attitude = [names.index(n) for n in names if n.startswith("T")]
    velocity = [names.index(n) for n in ("v_N", "v_E", "v_D")]
    position = [names.index(n) for n in ("lat", "lon")]
    gap = np.abs(integrated - traj.truth)
    assert gap[attitude].max() < 1e-9  # of entries of size 1
    assert gap[velocity].max() < 1e-7  # m/s, at 250-300 m/s
    assert gap[position].max() * 6.371e6 < 1e-4  # m, after 300 km
    assert gap[names.index("h")].max() < 1e-4  # m, after a 2-km climb
    # the flight: heading turned by 90°, a 2-km climb, level at the end
    v_N, v_E = traj.truth[velocity[0]], traj.truth[velocity[1]]
    assert np.hypot(v_N, v_E).max() == pytest.approx(300.0, rel=1e-6)
    assert traj.truth[names.index("h"), -1] == pytest.approx(3000.0, abs=1e-6)


def test_a_model_files_imu_signals_are_strapdown_neds_on_its_sphere(sphere):
    # strapdown_ned on the file's sphere: its normal gravity is g at h = 0 with these
    # parameters, so a level flight (turns and a speed change at h = 0) needs the same
    # body rates and specific forces from the two models: one of them from exact
    # rigid-body kinematics, the other solved from the file's own DCM equations
    model = load_model("strapdown_ned")
    p = model.parameter_vector(a=6_371_000.0, e2=0.0, gamma_e=9.81, gravity_k=0.0,
                               gravity_m=0.0)
    legs = [tr.Leg(600.0, 250.0, np.radians(90.0), 0.0), tr.Leg(600.0, 300.0, 0.0, 0.0),
            tr.Leg(600.0, 300.0, np.radians(-45.0), 0.0)]
    profile = tr.manoeuvre_profile(np.radians(40), np.radians(10), np.radians(30), 250.0,
                                   legs)
    mine = tr.trajectory(sphere, profile, 1800.0, 0.5, stream=False)
    ned = tr.trajectory(model, profile, 1800.0, 0.5, p=p, stream=False)
    for rows in (slice(0, 3), slice(3, 6)):  # rad/s, m/s²
        for a, b in ((mine.inputs, ned.inputs), (mine.midpoints, ned.midpoints)):
            assert np.abs(a[rows] - b[rows]).max() <= 1e-11 * np.abs(b[rows]).max()
    # the turn rate of the first leg: 90° in 10 min at most
    assert np.abs(mine.inputs[2]).max() > np.radians(90.0) / 600.0


def test_a_cli_compare_of_a_model_file_flies_a_great_circle(capsys):
    status = main(["compare", str(SPHERE_FILE), "--source", "gyro_bias_x=0.01deg/h",
                   "--hours", "0.2", "--step", "2s", "--motion", "great-circle", "--json",
                   "--no-refined"])
    out = capsys.readouterr().out
    assert status == 0
    import json

    report = json.loads(out)
    assert report["motion"].startswith("great circle") and report["truth_used"] == "fine"
    (case,) = report["cases"]
    metrics = {m["quantity"]: m for m in case["metrics"]}
    # the linear model follows the direct run: ratio well below 1 %
    assert 0 < case["worst_linear_ratio"] < 1e-2
    # a 0.01 deg/h gyro bias about body x, flying east (x along east): a tilt about east
    # whose north position error is the Schuler response R ε (t − sin(ω_s t)/ω_s),
    # ω_s = √(g/R) on the model's sphere: 28.5 m after 12 min, as latitude R·δφ
    R, g, eps, t = 6_371_000.0, 9.81, np.radians(0.01) / 3600.0, 720.0
    w_s = np.sqrt(g / R)
    north = R * eps * (t - np.sin(w_s * t) / w_s)
    assert metrics["delta_latitude"]["max_direct"] * R == pytest.approx(north, rel=0.03)
    # the east error stays an order smaller (Earth-rate coupling only)
    lon = metrics["delta_longitude"]["max_direct"] * R * np.cos(np.radians(50.0))
    assert 0 < lon < 0.1 * north


WRONG_EARTH = "r = eq.let(\"r\", R + h, \"r\")"


@pytest.mark.parametrize("edit, said", [
    # position equations on a sphere without the height: cannot follow a flight at 1 km
    ((WRONG_EARTH, "r = eq.let(\"r\", R + 0 * h, \"r\")"), ["'lon'", "cannot follow", "radius"]),
    # an initial condition a flight cannot set
    (('("heading", r"\\psi")', '("yaw", r"\\psi")'), ["yaw", "cannot set"]),
    # no Earth radius among the parameters
    (('Parameter("R", "m"', 'Parameter("R_sphere", "m"'), ["Earth radius"]),
])
def test_a_flight_the_model_cannot_follow_is_one_line(edit, said, tmp_path, capsys,
                                                     monkeypatch):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = SPHERE_FILE.read_text(encoding="utf-8")
    old, new = edit
    assert old in text
    text = text.replace(old, new)
    if "R_sphere" in new:
        text = text.replace('SYMBOL["R"]', 'SYMBOL["R_sphere"]')
    if "yaw" in new:
        text = text.replace('c["heading"]', 'c["yaw"]')
    path = tmp_path / "my_strapdown.py"
    path.write_text(text, encoding="utf-8")
    status = main(["compare", str(path), "--source", "gyro_bias_x=0.01deg/h", "--hours", "1",
                   "--step", "10s", "--motion", "great-circle", "--height", "1000m"])
    err = capsys.readouterr().err.strip().splitlines()
    err = [line for line in err if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    for word in said:
        assert word in err[0], (word, err[0])


def test_a_static_flight_of_a_model_file_is_its_static_rest(sphere):
    from ins_errors.numeric.static_rest import static_rest

    p = sphere.parameter_vector()
    flight = st.static(np.radians(35), np.radians(20), 500.0, heading=np.radians(75))
    traj = st.trajectory(sphere, flight, 60.0, 1.0, p)
    x, u, c, _ = static_rest(sphere, np.radians(35), np.radians(20), np.radians(75), 500.0,
                             p)
    np.testing.assert_allclose(traj.truth[:, 0], x, rtol=0, atol=1e-15)
    np.testing.assert_allclose(traj.inputs[:, 0], u, rtol=1e-12, atol=1e-18)
    np.testing.assert_array_equal(traj.initial_conditions, c)


def test_a_streamed_flight_of_a_model_file_survives_pickling(sphere):
    # a Monte Carlo run sends the trajectory to worker processes
    import pickle

    traj = tr.trajectory(sphere, manoeuvre(), 600.0, 0.5, stream=True)
    again = pickle.loads(pickle.dumps(traj))
    for a, b in zip(traj.source.chunks(500), again.source.chunks(500), strict=True):
        np.testing.assert_array_equal(a.truth, b.truth)
        np.testing.assert_array_equal(a.midpoints, b.midpoints)


def test_a_state_the_initial_state_map_sets_to_a_constant_flies(tmp_path, monkeypatch):
    # a literal 0 in the initial-state map (a state that starts at rest, e.g. an
    # integrator of a loop) is a structural zero of the compiled solution
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = SPHERE_FILE.read_text(encoding="utf-8")
    assert text.count('c["v_D0"]') == 1
    path = tmp_path / "level_start.py"
    path.write_text(text.replace('c["v_D0"]', "0"), encoding="utf-8")
    model = load_model(str(path))
    traj = tr.trajectory(model, tr.great_circle_profile(np.radians(50), 0.0, 0.5, 250.0),
                         600.0, 60.0, stream=False)
    assert np.all(np.isfinite(traj.truth)) and np.abs(traj.truth[[11]]).max() < 1e-12


def test_a_model_without_a_heading_condition_is_refused_a_flight(tmp_path, monkeypatch,
                                                                 capsys):
    # its body would keep heading 0 while the flight follows its course (sideways)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = SPHERE_FILE.read_text(encoding="utf-8")
    old = 'f"initial {name}", f"{latex}_0") for name, latex in ANGLES)'
    assert text.count(old) == 1 and text.count('c["heading"]') == 1
    text = text.replace(old, old.replace("in ANGLES", "in ANGLES[:2]"))
    path = tmp_path / "no_heading.py"
    path.write_text(text.replace('c["heading"]', "0"), encoding="utf-8")
    status = main(["compare", str(path), "--motion", "great-circle", "--hours", "0.1",
                   "--source", "gyro_bias_x=0.01deg/h"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1 and "no initial condition 'heading'" in err[0]


@pytest.mark.parametrize("radius", ["1m", "10m", "50km"])
def test_a_flight_on_an_earth_of_metres_is_refused_in_one_line(radius, capsys):
    # on a sphere of 1 m a 250 m/s flight turns 250 rad/s: its integration never ended
    status = main(["compare", str(SPHERE_FILE), "--motion", "great-circle", "--hours", "0.1",
                   "--source", "gyro_bias_x=0.01deg/h", "-p", f"R={radius}"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    assert f"R = '{radius}'" in err[0] and "planet-sized" in err[0], err


def test_a_position_integration_whose_steps_explode_is_refused(sphere):
    # a path past the radius check (strapdown_ned's own Earth, or a flight near a pole)
    # must stop when DOP853's steps shrink without end, not run for hours
    import dataclasses
    import time

    from ins_errors.errors import DomainError

    flight = st.flight_from_profile(tr.great_circle_profile(np.radians(50), 0.0, 0.5, 250.0))
    earth = dataclasses.replace(st._earth(load_model("strapdown_ned"),
                                          load_model("strapdown_ned").parameter_vector()),
                                a=1.0)
    start = time.perf_counter()
    with pytest.raises(DomainError, match="shrink without end"):
        st._position_solution(flight, earth, 360.0, 0.01)
    assert time.perf_counter() - start < 30.0
    # a planet-sized Earth of 100 km flies 24 h well inside the bound
    earth = dataclasses.replace(earth, a=100e3)
    solution = st._position_solution(flight, earth, 86400.0, 0.01)
    assert solution.success and solution.t[-1] == 86400.0


def test_a_model_whose_inputs_enter_non_linearly_flies(sphere, tmp_path, monkeypatch):
    # an accelerometer compensation f + k f²: two Gauss–Newton steps left a residual of
    # 1e-5 m/s² (refused as "cannot follow"); iterated, its specific force is the root
    # of k f² + f = f_sphere, the sphere model's own along the same flight
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    k = 1e-3  # s²/m
    text = SPHERE_FILE.read_text(encoding="utf-8")
    old = "T * sp.Matrix(force)"
    assert text.count(old) == 1
    text = text.replace(old, f"T * sp.Matrix([fi + {k!r} * fi**2 for fi in force])")
    path = tmp_path / "compensated.py"
    path.write_text(text.replace('name="strapdown_sphere"', 'name="compensated"'),
                    encoding="utf-8")
    model = load_model(str(path))
    profile = manoeuvre()
    mine = tr.trajectory(model, profile, 600.0, 1.0, stream=False)
    plain = tr.trajectory(sphere, profile, 600.0, 1.0, stream=False)
    np.testing.assert_allclose(mine.truth, plain.truth, rtol=0, atol=1e-9)
    f_sphere = plain.inputs[3:6]
    expected = (np.sqrt(1 + 4 * k * f_sphere) - 1) / (2 * k)
    assert np.abs(mine.inputs[3:6] - expected).max() <= 1e-10 * np.abs(expected).max()
    assert np.abs(mine.inputs[3:6] - f_sphere).max() > 0.05  # k f² of g: about 0.1 m/s²
    np.testing.assert_allclose(mine.inputs[:3], plain.inputs[:3], rtol=0, atol=1e-15)
