"""A strapdown INS flies a motion file (columns t, v_N, v_E, h).

References, each independent of the flight generator (ins_errors.numeric.strapdown_truth,
strapdown_stream):

* the model's ideal-work equations integrated by RK4 from the truth's IMU signals: the
  true motion must be their solution (attitude, velocity, position);
* the file's samples themselves, SciPy cubic splines built here, and the position
  equations φ̇ = v_N/(R_N + h), λ̇ = v_E/((R_E + h) cos φ) integrated here by DOP853
  one sample interval at a time (so no step straddles a sample, where the velocity's
  third derivative jumps);
* the coordinated bank atan(V r / g₀) with r = ψ̇ − v_E tan φ/(R_E + h), ψ̇ computed
  here from the splines' derivatives, and the flight-path pitch and course;
* the linearised error equations against the direct run (as the great-circle tests);
* the strapdown model file of examples/strapdown flown along the same file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

import ins_errors
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import compare
from ins_errors.numeric.integrators import integrate
from ins_errors.numeric.motion_spec import read_motion_file

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "strapdown" / "turn_and_climb.csv"
SPHERE_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"
G0 = 9.80665
LAT, LON = np.radians(50.0), np.radians(30.0)


@pytest.fixture(scope="module")
def model():
    return ins_errors.load_model("strapdown_ned")


def circling(duration: float = 660.0, every: float = 2.0):
    """Samples of a climbing, circling flight with a speed change: t, v_N, v_E, h."""
    t = np.arange(0.0, duration + every / 2, every)
    course = np.radians(30.0) + t / 300.0  # a turn to the right at 0.19°/s
    speed = 180.0 + 30.0 * np.sin(t / 200.0)
    return t, speed * np.cos(course), speed * np.sin(course), 800.0 + 400.0 * np.sin(t / 250.0)


def profile(samples) -> tr.Profile:
    t, vN, vE, h = samples
    return tr.sampled_profile(t, vN, vE, LAT, LON, 0.0, h)


def splines(samples):
    t, vN, vE, h = samples
    return CubicSpline(t, vN), CubicSpline(t, vE), CubicSpline(t, h)


def euler(q):
    q0, q1, q2, q3 = q
    roll = np.arctan2(2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2)
    pitch = np.arcsin(-2 * (q1 * q3 - q0 * q2))
    heading = np.arctan2(2 * (q1 * q2 + q0 * q3), q0**2 + q1**2 - q2**2 - q3**2)
    return roll, pitch, heading


def earth(model):
    p = dict(zip((q.name for q in model.parameters), model.parameter_vector(), strict=True))
    return p["a"], p["e2"]


@pytest.mark.parametrize("truth", ["fine", "interpolated"])
def test_the_true_imu_signals_fly_the_file_in_the_ideal_equations(model, truth):
    traj = st.trajectory(model, st.flight_from_profile(profile(circling())), 600.0, 0.1,
                         truth=truth)
    assert traj.truth_kind == truth
    p = traj.parameters
    inputs, mid = traj.full_inputs()
    z = integrate(lambda s, v: model.numpy.ideal_rhs(s, v, p), traj.truth[:, 0], inputs,
                  traj.tau, "rk4", mid, record_every=20)
    x = traj.truth[:, ::20]
    assert np.abs(z[:4] - x[:4]).max() < 1e-11  # quaternion
    assert np.abs(z[4:7] - x[4:7]).max() < 1e-8  # m/s
    assert np.abs(z[7:9] - x[7:9]).max() * 6.4e6 < 1e-6  # m
    assert np.abs(z[9] - x[9]).max() < 1e-6  # m (the unstable vertical channel)
    # the flight turns, banks and climbs: the body signals show it
    assert np.abs(traj.inputs[2]).max() > 3e-3 and np.abs(traj.inputs[3]).max() > 0.1


@pytest.mark.parametrize("truth", ["fine", "interpolated"])
def test_the_truth_is_the_files_velocity_and_its_integral(model, truth):
    samples = circling(330.0, 3.0)
    t, vN, vE, h = samples
    traj = st.trajectory(model, st.flight_from_profile(profile(samples)), 300.0, 0.5,
                         truth=truth)
    at = slice(0, None, 6)  # the sample times, every 3 s
    n = traj.truth[:, at].shape[1]
    assert np.abs(traj.truth[4, at] - vN[:n]).max() < 1e-9
    assert np.abs(traj.truth[5, at] - vE[:n]).max() < 1e-9
    assert np.abs(traj.truth[9, at] - h[:n]).max() < 1e-9
    sN, sE, sh = splines(samples)
    times = traj.times
    assert np.abs(traj.truth[6] + sh(times, 1)).max() < 1e-9  # v_D = −ḣ between samples too
    assert np.abs(traj.truth[4] - sN(times)).max() < 1e-9
    # latitude and longitude: the position equations on the model's ellipsoid
    a, e2 = earth(model)

    def rhs(s, y):
        w = np.sqrt(1 - e2 * np.sin(y[0]) ** 2)
        return [sN(s) / (a * (1 - e2) / w**3 + sh(s)),
                sE(s) / ((a / w + sh(s)) * np.cos(y[0]))]

    y, reference = np.array([LAT, LON]), [np.array([LAT, LON])]
    for k in range(n - 1):
        y = solve_ivp(rhs, (t[k], t[k + 1]), y, method="DOP853", rtol=1e-13,
                      atol=1e-16).y[:, -1]
        reference.append(y)
    gap = np.abs(traj.truth[7:9, at] - np.array(reference).T)
    assert gap.max() * a < 1e-7  # m, after 17 km
    assert np.abs(np.array(reference)[-1] - [LAT, LON]).max() * a > 1e4


def test_a_turn_banks_by_the_coordinated_rule_on_top_of_the_geodesic(model):
    samples = circling()
    traj = st.trajectory(model, st.flight_from_profile(profile(samples)), 600.0, 1.0)
    sN, sE, sh = splines(samples)
    t = traj.times
    vN, vE, vD = sN(t), sE(t), -sh(t, 1)
    V = np.hypot(vN, vE)
    course_rate = (vN * sE(t, 1) - vE * sN(t, 1)) / V**2
    lat, h = traj.truth[7], traj.truth[9]
    a, e2 = earth(model)
    R_E = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    r = course_rate - vE * np.tan(lat) / (R_E + h)
    roll, pitch, heading = euler(traj.truth[:4])
    assert np.abs(roll - np.arctan(V * r / G0)).max() < 1e-12
    assert np.abs(pitch - np.arctan(-vD / V)).max() < 1e-12
    assert np.abs(np.angle(np.exp(1j * (heading - np.arctan2(vE, vN))))).max() < 1e-12
    # a real bank (3.5°), which the absolute course rate would have set about 1 % higher
    assert np.degrees(np.abs(roll)).min() > 3.0
    absolute = np.arctan(V * course_rate / G0)
    assert np.abs(absolute - roll).max() > 1e-4


def test_linear_and_direct_errors_agree_along_the_file(model):
    w0 = 2 * np.pi / 600.0  # a damped vertical loop
    p = model.parameter_vector(k_h1=2 * 0.7 * w0, k_h2=w0**2 + 2 * G0 / 6.371e6)
    traj = st.trajectory(model, st.flight_from_profile(profile(circling(1260.0, 5.0))),
                         1200.0, 0.5, p=p)
    [c] = compare(model, traj, [{"gyro_bias_x": np.radians(0.01) / 3600.0}],
                  method="rk4", record_interval=60.0, integration_error=False,
                  validity_threshold=None)
    assert c.worst_linear.linear_ratio < 1e-3
    assert c.worst_refined.refined_ratio < 1e-6
    assert len(c.excited) == 9


def test_the_strapdown_model_file_flies_the_file_as_strapdown_ned(model):
    # strapdown_ned put on the model file's sphere with its constant gravity: the same
    # level file (turns and a speed change at h = 0) needs the same body rates and
    # specific forces, one from the exact kinematics, the other solved from the model
    # file's own equations
    sphere = ins_errors.load_model(str(SPHERE_FILE))
    p = model.parameter_vector(a=6_371_000.0, e2=0.0, gamma_e=9.81, gravity_k=0.0,
                               gravity_m=0.0)
    t, vN, vE, _ = circling(660.0, 2.0)
    level = tr.sampled_profile(t, vN, vE, LAT, LON, 0.0, 0.0)
    mine = tr.trajectory(sphere, level, 600.0, 0.5, stream=False)
    ned = tr.trajectory(model, level, 600.0, 0.5, p=p, stream=False)
    for rows in (slice(0, 3), slice(3, 6)):  # rad/s, m/s²
        for a, b in ((mine.inputs, ned.inputs), (mine.midpoints, ned.midpoints)):
            assert np.abs(a[rows] - b[rows]).max() <= 1e-11 * np.abs(b[rows]).max()
    names = [s.name for s in sphere.states]
    for mine_name, ned_row in (("lat", 7), ("lon", 8), ("v_N", 4), ("v_E", 5)):
        assert np.abs(mine.truth[names.index(mine_name)] - ned.truth[ned_row]).max() < 1e-9


def _cli(capsys, *argv):
    from ins_errors.cli import main

    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_the_cli_and_a_scenario_fly_the_example_file(capsys, tmp_path):
    import json

    status, out, err = _cli(capsys, "compare", "strapdown_ned", "--motion-file", str(EXAMPLE),
                            "--hours", "0.1", "--step", "1s", "-s", "gyro_bias_x=0.01deg/h",
                            "--json")
    assert status == 0, err
    (case,) = json.loads(out)["cases"]
    # the file and its start; no track angle (the file's own course is flown)
    assert json.loads(out)["motion"] == (f"motion file {EXAMPLE} (601 samples, geographic "
                                         "frame) from φ=50°, λ=30°")
    assert case["worst_linear_ratio"] < 1e-3
    scenario = tmp_path / "file.toml"
    scenario.write_text(f'model = "strapdown_ned"\n[motion]\nkind = "file"\nfile = '
                        f'"{EXAMPLE.as_posix()}"\nlatitude = "40 deg"\n[run]\nduration = '
                        f'"5 min"\nstep = "1 s"\nrecord = "30 s"\nmethod = "rk4"\n[[case]]\n'
                        f'accel_bias_y = "50 ug"\n')
    status, out, err = _cli(capsys, "run", str(scenario), "--out", str(tmp_path / "out"))
    assert status == 0, err
    assert (tmp_path / "out" / "results.json").exists()


def stops(tmp_path) -> Path:
    path = tmp_path / "stops.csv"
    path.write_text("t,v_N,v_E\n0,0,100\n600,0,100\n1200,0,0\n1800,0,100\n3600,0,100\n")
    return path


@pytest.mark.parametrize("argv, said", [
    (["--hours", "1"], "ground speed is 0 m/s at t = 1200 s: a strapdown INS heads along "
                       "the course atan2(v_E, v_N)"),
    (["--hours", "2"], "the run (0–7200 s) leaves the sampled motion (0–3600 s)"),
    (["--hours", "0.25", "--heading", "10deg"], "a strapdown INS along a motion file heads "
                                               "along the file's course")])
def test_a_file_a_strapdown_ins_cannot_fly_is_one_line(argv, said, tmp_path, capsys):
    status, out, err = _cli(capsys, "compare", "strapdown_ned", "-s", "gyro_bias_x=0.01deg/h",
                            "--motion-file", str(stops(tmp_path)), *argv)
    assert status == 2 and out == ""
    assert said in err and len(err.strip().splitlines()) == 1


def test_the_file_is_checked_before_any_work_also_through_the_api(model, tmp_path):
    flight = st.flight_from_profile(read_motion_file(stops(tmp_path), LAT, LON, 0.0, 0.0))
    # the run before the stop flies; the one that reaches it is refused before any step
    assert st.trajectory(model, flight, 900.0, 10.0).n_steps == 90
    with pytest.raises(ins_errors.InsErrorsError, match="at t = 1200 s"):
        st.trajectory(model, flight, 1500.0, 10.0)


@pytest.mark.parametrize("truth", ["fine", "interpolated"])
def test_a_streamed_file_flight_reruns_and_pickles_to_the_same_bits(model, truth, monkeypatch):
    # a Monte Carlo run reruns the streamed truth and sends it to worker processes; the
    # fine truth's position is held two blocks at a time (16 intervals each here)
    import pickle

    from ins_errors.numeric import strapdown_stream as ss

    monkeypatch.setattr(ss.FilePosition, "BLOCK", 16)
    flight = st.flight_from_profile(profile(circling(330.0, 3.0)))
    traj = st.trajectory(model, flight, 300.0, 0.5, truth=truth, stream=True)
    whole = st.trajectory(model, flight, 300.0, 0.5, truth=truth, stream=False)
    again = pickle.loads(pickle.dumps(traj))
    for run in (traj, traj, again):
        chunks = list(run.source.chunks(100))
        truths = np.hstack([c.truth[:, :-1] for c in chunks] + [chunks[-1].truth[:, -1:]])
        np.testing.assert_array_equal(truths, whole.truth)
        np.testing.assert_array_equal(np.hstack([c.midpoints for c in chunks]),
                                      whole.midpoints)


@pytest.mark.parametrize("table", ["[sweep]", "[motion]"])
def test_a_sweep_refuses_a_heading_a_file_flight_ignores(capsys, tmp_path, table):
    """A strapdown INS flies a file's own course: a swept heading gave the same numbers
    at every point (the points dropped it), where run refuses a [motion] heading."""
    heading = ('[sweep]\nheading = ["0 deg", "90 deg"]\n' if table == "[sweep]" else
               '[sweep]\nlatitude = ["40 deg", "50 deg"]\n')
    motion_heading = 'heading = "90 deg"\n' if table == "[motion]" else ""
    scenario = tmp_path / "s.toml"
    scenario.write_text(f'model = "strapdown_ned"\n[motion]\nkind = "file"\nfile = '
                        f'"{EXAMPLE.as_posix()}"\n{motion_heading}[run]\nduration = "60 s"\n'
                        f'step = "1 s"\nrecord = "10 s"\n[[case]]\ngyro_bias_x = "1 deg/h"\n'
                        + heading, encoding="utf-8")
    status, _out, err = _cli(capsys, "sweep", str(scenario), "--store",
                            str(tmp_path / "s.zarr"), "--no-progress")
    assert status == 2 and err.count("\n") == 1, err
    assert f"{table}" in err and "heading: a strapdown INS along a motion file" in err
    assert not (tmp_path / "s.zarr").exists()
