"""Moving flights of a model with a path-dependent state: the wander-azimuth INS of
tests/models/wander_azimuth.py, whose wander angle α starts at the parameter ``alpha0``
and then moves with the path (its frame has no vertical transport rate, ρ_z = 0, so
with its x axis turned from north towards east by α, α̇ = λ̇ sin φ). The flight carries
``alpha0`` as a moving parameter (ins_errors.numeric.model_flight.CarriedPath).

References, each independent of the code under test:

* the great circle and its wander angle integrated here by SciPy's DOP853 at a relative
  tolerance of 1e-13 from the textbook equations (φ̇ = V cos ψ/(R_N + h),
  λ̇ = V sin ψ/((R_E + h) cos φ), the geodesic's ψ̇ = λ̇ sin φ, α̇ = λ̇ sin φ), and the
  model's true C_b^w, v^w, C_w^e built from them;
* ``strapdown_ned`` (quaternion attitude in NED, latitude and longitude states) flown
  along the same flight: another exact mechanisation of the same Earth, so the same IMU
  errors give the same navigation errors, and its hand-written φ/ψ maps give the same F
  as the wander model carried into a convention through its own equations.
"""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from ins_errors import load_model
from ins_errors.cli import main
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr

ROOT = Path(__file__).resolve().parents[1]
WANDER = ROOT / "tests" / "models" / "wander_azimuth.py"
A, E2 = 6378137.0, 6.69437999014e-3  # WGS-84, the model's defaults
LAT, LON, COURSE, SPEED, HEIGHT = np.radians(50.0), 0.5, np.radians(60.0), 250.0, 1000.0


@pytest.fixture(scope="module")
def wander():
    return load_model(str(WANDER))


def _turn(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _reference(t_end: float, alpha0: float):
    """Dense (φ, λ, ψ, α) of the great circle, integrated here."""
    def rhs(_t, y):
        lat, _lon, psi, _alpha = y
        s = np.sin(lat)
        w = np.sqrt(1.0 - E2 * s * s)
        r_n, r_e = A * (1.0 - E2) / w**3, A / w
        lon_rate = SPEED * np.sin(psi) / ((r_e + HEIGHT) * np.cos(lat))
        return [SPEED * np.cos(psi) / (r_n + HEIGHT), lon_rate, lon_rate * s, lon_rate * s]

    return solve_ivp(rhs, (0.0, t_end), [LAT, LON, COURSE, alpha0], method="DOP853",
                     rtol=1e-13, atol=1e-15, dense_output=True).sol


@pytest.mark.parametrize("truth", ["fine", "interpolated"])
def test_the_wander_angle_of_a_great_circle_is_the_integrated_one(wander, truth):
    alpha0 = 0.7
    p = wander.parameter_vector(alpha0=alpha0)
    profile = tr.great_circle_profile(LAT, LON, COURSE, SPEED, HEIGHT)
    run = tr.trajectory(wander, profile, 3600.0, 1.0, p=p, truth=truth, stream=False)
    times = run.times[::120]
    lat, lon, psi, alpha = _reference(3600.0, alpha0)(times)
    assert alpha[-1] - alpha0 > 0.15  # the wander angle turned by 9° in the hour
    gap = {"C": 0.0, "v": 0.0, "P": 0.0, "h": 0.0}
    for k, column in enumerate(run.truth[:, ::120].T):
        C_wn = _turn(alpha[k])
        sl, cl, so, co = np.sin(lat[k]), np.cos(lat[k]), np.sin(lon[k]), np.cos(lon[k])
        C_en = np.array([[-sl * co, -so, -cl * co], [-sl * so, co, -cl * so], [cl, 0, -sl]])
        v_n = SPEED * np.array([np.cos(psi[k]), np.sin(psi[k]), 0.0])
        gap["C"] = max(gap["C"], np.abs(column[:9] - (C_wn.T @ _turn(psi[k])).ravel()).max())
        gap["v"] = max(gap["v"], np.abs(column[9:12] - C_wn.T @ v_n).max())
        gap["P"] = max(gap["P"], np.abs(column[12:21] - (C_en @ C_wn).ravel()).max())
        gap["h"] = max(gap["h"], abs(column[21] - HEIGHT))
    # measured: 1.4e-15, 3.4e-13 m/s, 7.8e-13 (the position's own integration), 0 m
    assert gap["C"] < 1e-12 and gap["v"] < 1e-10 and gap["P"] < 1e-11, gap
    assert gap["h"] < 1e-9, gap


def test_the_wander_angle_of_the_manoeuvre_is_the_integrated_one(wander):
    # the check's weaving flight (turns, speed and height changes): α̇ = λ̇ sin φ
    # integrated here along the flight's own position
    from ins_errors.checker.check_motions import _strapdown_flights
    from ins_errors.numeric.model_flight import flight_earth

    flight = dict(_strapdown_flights())["manoeuvre"]
    p = wander.parameter_vector()
    run = st.trajectory(wander, flight, 7200.0, 10.0, p=p, stream=False)
    earth = flight_earth(wander, p)
    position = st._position_solution(flight, earth, 7200.0, 10.0).sol

    def rate(t, _alpha):
        *_, nav, rates = st.rigid_body_signals(flight, earth, np.array([t]),
                                               position(np.array([t])), navigation=True)
        return [rates[1, 0] * np.sin(nav[0, 0])]

    times = run.times[::30]
    alpha = solve_ivp(rate, (0.0, 7200.0), [p[3]], method="DOP853", rtol=1e-13, atol=1e-15,
                      t_eval=times).y[0]
    P = run.truth[12:21, ::30]
    # α from the position matrix: C_w^e = C_n^e C_w^n, so (C_n^e)ᵀ C_w^e = C_w^n
    lat, lon = position(times)[:2]
    measured = []
    for k in range(times.size):
        sl, cl, so, co = np.sin(lat[k]), np.cos(lat[k]), np.sin(lon[k]), np.cos(lon[k])
        C_en = np.array([[-sl * co, -so, -cl * co], [-sl * so, co, -cl * so], [cl, 0, -sl]])
        C_wn = C_en.T @ P[:, k].reshape(3, 3)
        measured.append(np.arctan2(C_wn[1, 0], C_wn[0, 0]))
    assert np.ptp(alpha) > 0.05
    assert np.abs(np.array(measured) - alpha).max() < 1e-11  # measured: 3.5e-14 rad


def _direct_errors(model, p, profile):
    from ins_errors.numeric.simulate import simulate

    run = tr.trajectory(model, profile, 3600.0, 0.5, p=p)
    cases = [{"gyro_bias_x": np.radians(0.01) / 3600.0, "gyro_bias_z": np.radians(0.01) / 3600,
              "accel_bias_y": 1e-4}]
    return simulate(model, run, cases, record_interval=60.0).direct_errors()


def test_the_wander_models_direct_run_is_strapdown_neds_on_a_great_circle(wander):
    # two exact mechanisations of the same Earth and gravity fed the same body rates and
    # specific forces: the real − ideal navigation errors agree to the rounding of the
    # states they are differences of (latitude 0.9 rad, height 1 km, speed 250 m/s)
    profile = tr.great_circle_profile(LAT, LON, COURSE, SPEED, HEIGHT)
    mine = _direct_errors(wander, wander.parameter_vector(k1=0.03, k2=4e-4), profile)
    ned = load_model("strapdown_ned")
    theirs = _direct_errors(ned, ned.parameter_vector(k_h1=0.03, k_h2=4e-4), profile)
    bounds = {"latitude": 1e-13, "longitude": 1e-13, "roll": 1e-13, "pitch": 1e-13,
              "heading": 1e-13, "height": 1e-8, "v_N": 1e-10, "v_E": 1e-10, "v_D": 1e-10}
    for name, bound in bounds.items():  # measured: 8e-15 rad, 1.7e-10 m, 6e-12 m/s
        a, b = mine[f"delta_{name}"], theirs[f"delta_{name}"]
        assert np.abs(b).max() > 1e3 * bound, name  # errors well above the comparison
        assert np.abs(a - b).max() < bound, (name, np.abs(a - b).max())


def test_a_cli_compare_of_the_wander_model_flies_a_great_circle(capsys):
    reports = []
    for model in (str(WANDER), "strapdown_ned"):
        status = main(["compare", model, "--source", "gyro_bias_x=0.01deg/h", "--hours", "0.2",
                       "--step", "2s", "--motion", "great-circle", "--json", "--no-refined"])
        assert status == 0
        reports.append(json.loads(capsys.readouterr().out))
    mine, ned = ({m["quantity"]: m for m in r["cases"][0]["metrics"]} for r in reports)
    assert 0 < reports[0]["cases"][0]["worst_linear_ratio"] < 1e-2
    for name in ("delta_latitude", "delta_longitude", "delta_heading", "delta_v_N"):
        assert mine[name]["max_direct"] == pytest.approx(ned[name]["max_direct"], rel=1e-9)


@pytest.mark.parametrize("label", ["cruise", "manoeuvre"])
@pytest.mark.parametrize("name", ["phi", "psi"])
def test_the_wander_model_in_a_convention_is_strapdown_ned_in_flight(wander, label, name):
    from ins_errors.checker.check_motions import _strapdown_flights
    from ins_errors.checker.conventions import conventions
    from ins_errors.models import strapdown_conventions as sc

    flight = dict(_strapdown_flights())[label]

    def flown(model, p):
        run = st.trajectory(model, flight, 5400.0, 60.0, p=p, stream=False)
        return run.truth, run.inputs_at(np.arange(run.n_steps + 1)), run.parameters

    x, u, p = flown(wander, wander.parameter_vector(alpha0=0.3))
    conv = conventions(wander)[name]
    T, T_dot = conv.matrices(wander, x, p, u)  # refused before: the wander angle moved
    L = np.moveaxis(conv.lift(x, p), -1, 0)
    F = np.moveaxis(wander.state_matrix(x, u, p), -1, 0)
    F_mine = (T_dot + T @ F) @ L
    ned = load_model("strapdown_ned")
    x_n, u_n, p_n = flown(ned, ned.parameter_vector())
    F_ned, _ = (np.moveaxis(m, -1, 0) for m in sc.convention_matrices(ned, name, x_n, u_n, p_n))
    scale = np.abs(F_ned).max(axis=2, keepdims=True)  # per row (rows of mixed units)
    assert (np.abs(F_mine - F_ned) / scale).max() < 1e-9


def test_a_streamed_wander_flight_survives_pickling(wander):
    # a Monte Carlo run sends the trajectory, with its carried wander angle, to workers
    profile = tr.great_circle_profile(LAT, LON, COURSE, SPEED, HEIGHT)
    run = tr.trajectory(wander, profile, 3000.0, 1.0, stream=True)
    again = pickle.loads(pickle.dumps(run))
    for a, b in zip(run.source.chunks(700), again.source.chunks(700), strict=True):
        np.testing.assert_array_equal(a.truth, b.truth)
        np.testing.assert_array_equal(a.midpoints, b.midpoints)


def test_a_meridian_keeps_the_wander_angle_at_its_parameter(wander):
    # along a meridian λ̇ = 0: the carried parameter stays at alpha0, bit for bit
    profile = tr.great_circle_profile(LAT, LON, 0.0, SPEED, HEIGHT)
    run = tr.trajectory(wander, profile, 1800.0, 1.0, stream=True)
    path = run.source.adapter.path
    assert np.all(path(np.linspace(0.0, 1800.0, 1001)) == wander.parameter_vector()[3])


def test_a_wander_angle_fixed_in_the_map_is_still_refused(tmp_path, capsys, monkeypatch):
    # a literal wander angle: no parameter carries it, and the flight is refused in one
    # line saying why
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = WANDER.read_text(encoding="utf-8")
    old = 'C_wn = turn_z(S["alpha0"])'
    assert text.count(old) == 1
    path = tmp_path / "fixed_wander.py"
    path.write_text(text.replace(old, "C_wn = turn_z(sp.Rational(1, 2))"), encoding="utf-8")
    status = main(["compare", str(path), "--motion", "great-circle", "--hours", "0.1",
                   "--source", "gyro_bias_x=0.01deg/h"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    assert "no navigation quantity sets (such as a wander angle)" in err[0]
    assert "at no parameter that the flight could carry" in err[0]


def test_the_check_decides_what_a_flight_carries_where_the_flight_does(tmp_path, monkeypatch):
    # a wander angle started at alpha0·sin φ: at the equator alpha0 starts nothing, at 50°
    # it starts the wander angle. The flight decides at its start; the check of its
    # samples must decide there too (it decided at 50° and then fitted alpha0 to
    # samples on the equator, along a direction ∂x0/∂alpha0 = 0: a singular solve)
    from ins_errors.checker.strapdown_description import carried_values
    from ins_errors.numeric.model_flight import FlightAdapter, condition_matrix

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = WANDER.read_text(encoding="utf-8")
    old = 'C_wn = turn_z(S["alpha0"])'
    assert text.count(old) == 1
    path = tmp_path / "latitude_wander.py"
    path.write_text(text.replace(old, 'C_wn = turn_z(S["alpha0"] * sp.sin(lat))'),
                    encoding="utf-8")
    model = load_model(str(path))
    p = model.parameter_vector(alpha0=0.4)
    initial = model.casadi.function("initial_state")
    for lat, carried in ((0.0, ()), (LAT, (3,))):
        nav = np.array([lat, LON, HEIGHT, 0.0, 0.0, 0.0, 0.0, 0.0, COURSE])
        adapter = FlightAdapter(model, p, (nav, np.zeros(9)))
        assert adapter.carried == carried
        x0 = np.asarray(initial(condition_matrix(model) @ nav, np.zeros(len(model.inputs)),
                                p), dtype=float)
        x = np.repeat(x0, 3, axis=1)
        np.testing.assert_array_equal(carried_values(model, x, p), p)  # at its value
