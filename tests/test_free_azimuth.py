"""Model free_azimuth (source 002, IS-1-72A): rebuilt equations checked by physics.

* the rebuilt ideal-work equations, fed the specific force of an independent 3-D
  simulation (rotating sphere, inertially non-rotating azimuth), reproduce the true
  coordinates, velocity and platform azimuth of a great-circle flight and of a rest;
* F, G, H, E equal central finite differences (relative 1e-6); numpy, CasADi and the
  in-memory SymPy variation agree;
* the error dynamics: Schuler period 2π√(R/g) of the tuning radius R (not of the Earth),
  uncompensated azimuth drift grows as ω_dz t, bias-induced tilt b/g;
* direct vs linear runs agree at small magnitudes; bad input gets one-line errors.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import ins_errors
from ins_errors.errors import DomainError
from ins_errors.models.free_azimuth import TUNING_RADIUS, levelling_offsets
from ins_errors.numeric.simulate import simulate
from ins_errors.numeric.trajectories import Profile, trajectory
from tests.helpers import (
    central_difference,
    complex_step_matrices,
    row_relative_error,
    source_steps,
)

U = 7.292115e-5
DEG_H = np.pi / 180 / 3600


@pytest.fixture(scope="module")
def model() -> ins_errors.Model:
    return ins_errors.load_model("free_azimuth")


def _orthodrome(model, lat0, lon0, azimuth):
    return model.parameter_vector(orth_latitude=lat0, orth_longitude=lon0, orth_azimuth=azimuth)


# --------------------------------------------------------------------------------------
# Independent truth: 3-D kinematics on the rotating sphere of radius R
# --------------------------------------------------------------------------------------
def _rz(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _cross(a, b):
    """a × b of two 3-vectors (np.cross's formula, without its axis handling, which
    costs more than the product here)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _enu(lat, lon):
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    up = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    return east, north, up


@pytest.mark.parametrize("speed, track, psi0, orthodrome", [
    (250.0, 60.0, 20.0, "along"),      # on the orthodromic equator
    (300.0, -35.0, 140.0, "crossing"),  # orthodrome of another azimuth: Φ ≠ 0
    (0.0, 0.0, -70.0, "along"),        # at rest: only the Earth turns under the platform
])
def test_perfect_system_reproduces_great_circle_flight(model, speed, track, psi0, orthodrome):
    R = TUNING_RADIUS
    lat0, lon0, chi0, psi0 = np.radians([50.0, 30.0, track, psi0])
    east, north, up = _enu(lat0, lon0)
    along = np.sin(chi0) * east + np.cos(chi0) * north
    rate = speed / R
    omega = np.array([0.0, 0.0, U])

    @functools.lru_cache(maxsize=4)  # RK4 asks twice at the midpoint, and the step's end again
    def truth(t):
        r = R * (np.cos(rate * t) * up + np.sin(rate * t) * along)
        v = R * rate * (-np.sin(rate * t) * up + np.cos(rate * t) * along)
        a = -rate**2 * r
        q = _rz(U * t)
        return (r, v, q @ r, q @ (v + _cross(omega, r)),
                q @ (a + 2 * _cross(omega, v) + _cross(omega, _cross(omega, r))))

    azimuth = chi0 if orthodrome == "along" else chi0 + 0.7
    p = _orthodrome(model, lat0 - 0.1 * (orthodrome != "along"), lon0, azimuth)
    c = model.initial_condition_vector(latitude=lat0, longitude=lon0, heading=psi0,
                                       v_N=speed * np.cos(chi0), v_E=speed * np.sin(chi0))
    x0 = model.initial_state(c, model.input_vector(a_zeta=9.8), p)

    def rhs(t, y):
        x, xi = y[:5], y[5:]
        _r, _v, r_i, v_i, a_i = truth(t)
        zeta = r_i / R
        frame_rate = _cross(zeta, v_i / R)  # horizontal only: free in azimuth
        eta = _cross(zeta, xi)
        u = np.array([a_i @ xi, a_i @ eta, 9.8, 0.0])
        return np.r_[model.numpy.ideal_rhs(x, u, p), _cross(frame_rate, xi)]

    y = np.r_[x0, np.sin(psi0) * east + np.cos(psi0) * north]
    dt, T = 30.0, 3 * 3600.0  # RK4's own error: 4e-13 rad, 3e-10 m/s (1e-14 at 10 s)
    for k in range(int(T / dt)):
        t = k * dt
        k1 = rhs(t, y)
        k2 = rhs(t + dt / 2, y + dt / 2 * k1)
        k3 = rhs(t + dt / 2, y + dt / 2 * k2)
        k4 = rhs(t + dt, y + dt * k3)
        y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    r_e, v_e, *_ = truth(T)
    lat, lon = np.arcsin(r_e[2] / R), np.arctan2(r_e[1], r_e[0])
    east, north, up = _enu(lat, lon)
    xi_e = _rz(-U * T) @ y[5:]
    expected = [lat, lon, np.arctan2(xi_e @ east, xi_e @ north), v_e @ north, v_e @ east]
    got = model.outputs_of(y[:5], model.input_vector(a_zeta=9.8), p)
    np.testing.assert_allclose(got[:3], expected[:3], atol=1e-9)  # 6 mm on the ground
    np.testing.assert_allclose(got[3:], expected[3:], atol=1e-6)  # m/s
    if orthodrome == "along":
        assert abs(y[0]) < 1e-9  # stays on the orthodromic equator (Φ = 0)


# --------------------------------------------------------------------------------------
# Derived matrices
# --------------------------------------------------------------------------------------
STATE_STEPS = np.r_[1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6]


def _points(model, count, seed, moving=True):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        p = _orthodrome(model, rng.uniform(-1.2, 1.2), rng.uniform(-3, 3), rng.uniform(-3, 3))
        c = model.initial_condition_vector(
            latitude=rng.uniform(-1.3, 1.3), longitude=rng.uniform(-3, 3),
            heading=rng.uniform(-3, 3), v_N=rng.uniform(-300, 300) * moving,
            v_E=rng.uniform(-300, 300) * moving)
        x = model.initial_state(c, model.input_vector(), p)
        if abs(np.cos(x[0])) < 0.2:
            continue
        u = model.input_vector(a_x=rng.uniform(-3, 3), a_y=rng.uniform(-3, 3),
                               a_zeta=rng.uniform(8, 12), V_zeta=rng.uniform(-20, 20) * moving)
        out.append((x, u, p, c))
    return out





@pytest.mark.parametrize("moving", [False, True], ids=["static", "moving"])
def test_state_and_source_matrices_equal_finite_differences(model, moving):
    nw = len(model.sources)
    for x, u, p, _c in _points(model, 12, 3 + moving, moving):
        xr0, w0 = np.r_[x, 0.0, 0.0, 0.0], np.zeros(nw)
        F_fd = central_difference(lambda xr: model.numpy.real_rhs(xr, x, u, w0, p), xr0,  # noqa: B023
                        STATE_STEPS)
        G_fd = central_difference(lambda w: model.numpy.real_rhs(xr0, x, u, w, p), w0,  # noqa: B023
                        source_steps(model))
        assert row_relative_error(F_fd, model.state_matrix(x, u, p)) < 1e-6
        assert row_relative_error(G_fd, model.source_matrix(x, u, p)) < 1e-6


def test_output_and_initial_error_matrices_equal_finite_differences(model):
    for x, u, p, c in _points(model, 10, 11):
        H = model.output_matrix(x, u, p)
        H_fd = central_difference(lambda xx: model.numpy.outputs(xx, u, p), x, STATE_STEPS[:5])  # noqa: B023
        assert np.all(H[:, 5:] == 0)
        assert row_relative_error(H_fd, H[:, :5]) < 1e-6
        E_fd = central_difference(lambda w: model.numpy.initial_real_state(c, u, w, p),  # noqa: B023
                        np.zeros(len(model.sources)), source_steps(model))
        assert row_relative_error(E_fd, model.initial_error_matrix(c, u, p)) < 1e-6


def test_real_work_without_errors_is_ideal_work(model):
    for x, u, p, c in _points(model, 8, 5):
        w0 = np.zeros(len(model.sources))
        real = model.real_rhs(np.r_[x, 0, 0, 0], x, u, w0, p)
        np.testing.assert_allclose(real[:5], model.ideal_rhs(x, u, p), rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(real[5:], 0.0, atol=1e-18)
        np.testing.assert_allclose(model.initial_real_state(c, u, w0, p),
                                   np.r_[model.initial_state(c, u, p), 0, 0, 0], atol=1e-9)


def test_backends_agree_with_sympy(model):
    # in-memory SymPy: the real-work equations differentiated by complex steps (exact to
    # rounding; a symbolic Jacobian of the expanded equations gave the same to 1e-16
    # relative at several times the cost)
    matrices = complex_step_matrices(model)
    F_ca, G_ca = model.casadi.function("state_matrix"), model.casadi.function("source_matrix")
    H_ca = model.casadi.function("output_matrix")
    for x, u, p, _c in _points(model, 6, 17):
        F_sym, G_sym = matrices(x, u, p)
        F = model.state_matrix(x, u, p)
        np.testing.assert_allclose(np.asarray(F_ca(x, u, p)), F, rtol=1e-12, atol=1e-20)
        np.testing.assert_allclose(F_sym, F, rtol=1e-10, atol=1e-20)
        G = model.source_matrix(x, u, p)
        np.testing.assert_allclose(np.asarray(G_ca(x, u, p)), G, rtol=1e-12, atol=1e-20)
        np.testing.assert_allclose(G_sym, G, rtol=1e-10, atol=1e-20)
        np.testing.assert_allclose(np.asarray(H_ca(x, u, p)), model.output_matrix(x, u, p),
                                   rtol=1e-12, atol=1e-20)


# --------------------------------------------------------------------------------------
# Error dynamics against textbook values
# --------------------------------------------------------------------------------------
def _rest_point(model, lat=np.pi / 4, psi=0.3):
    p = _orthodrome(model, lat, 0.0, np.radians(80.0))
    c = model.initial_condition_vector(latitude=lat, longitude=0.0, heading=psi)
    x = model.initial_state(c, model.input_vector(), p)
    return x, p, c


def test_schuler_period_is_that_of_the_tuning_radius(model):
    x, p, _c = _rest_point(model)
    g = 9.81
    u = model.input_vector(a_zeta=g)
    eigenvalues = np.linalg.eigvals(model.state_matrix(x, u, p))
    fastest = np.abs(eigenvalues.imag).max()
    period = 2 * np.pi / fastest
    schuler = 2 * np.pi * np.sqrt(TUNING_RADIUS / g)  # 84.67 min for R = 6 411 km
    assert period == pytest.approx(schuler, rel=2e-3)
    assert abs(period - 2 * np.pi * np.sqrt(6.371e6 / g)) > 10.0  # not the Earth's


def _rest_profile(lat, lon, psi):
    def commands(t):
        return np.zeros((4, t.size)), np.zeros((4, t.size))

    # not "static": the free-azimuth state turns with the Earth under the platform
    return Profile("geographic", commands, lat, lon, psi, "rest (free azimuth)")


def _cruise_profile(lat, lon, psi, v_N, v_E):
    def commands(t):
        values = np.zeros((4, t.size))
        values[0], values[1] = v_N, v_E
        return values, np.zeros((4, t.size))

    return Profile("geographic", commands, lat, lon, psi, "constant v_N, v_E")


@pytest.fixture(scope="module")
def rest_run(model):
    lat = np.radians(45.0)
    p = _orthodrome(model, lat, 0.0, np.radians(80.0))
    traj = trajectory(model, _rest_profile(lat, 0.0, 0.3), 3 * 3600.0, 10.0, p)
    cases = [{"gyro_drift_z": 0.05 * DEG_H}, {"accel_bias_x": 5e-5 * 9.80665},
             {"gyro_drift_x": 0.005 * DEG_H, "initial_tilt_y": 5e-6,
              "initial_A_error": 1e-4, "initial_velocity_error_y": 0.05}]
    return traj, simulate(model, traj, cases, method="rk4", record_interval=60.0)


def test_azimuth_drift_is_not_compensated(rest_run):
    _traj, sim = rest_run
    direct = sim.direct_errors()
    t = direct.times
    # δ = ω_dz t: nothing torques the platform in azimuth; the 0.2 % left over in 3 h is
    # the gyrocompass coupling (horizontal Earth rate × δ tilts the platform, the tilt
    # feeds back into δ̇ through α × Ω)
    np.testing.assert_allclose(direct["alpha_z"][:, 0], 0.05 * DEG_H * t, rtol=5e-3,
                               atol=1e-12)


def test_bias_tilt_is_bias_over_g(rest_run):
    traj, sim = rest_run
    g = traj.inputs[2, 0]
    b = 5e-5 * 9.80665
    tilt = sim.direct_errors()["alpha_y"][:, 1]
    # the tilt is (b/g)(1 − cos ω_s t) with the tuning radius's Schuler frequency: between
    # 0 and 2b/g (measured 1.2e-3 below 2b/g), mean b/g over whole periods (measured 5e-3
    # off, the 60-s samples), within 8e-3 b/g of that curve over 3 h
    t = sim.times
    omega_s = np.sqrt(g / TUNING_RADIUS)
    assert tilt.max() == pytest.approx(2 * b / g, rel=5e-3)
    assert abs(tilt.min()) < 0.005 * b / g
    whole = t < 2 * (2 * np.pi / omega_s)
    assert tilt[whole].mean() == pytest.approx(b / g, rel=0.01)
    assert np.abs(tilt - b / g * (1 - np.cos(omega_s * t))).max() < 0.02 * b / g


@pytest.mark.parametrize("motion", ["rest", "cruise"])
def test_direct_and_linear_agree_at_small_magnitudes(model, rest_run, motion):
    if motion == "rest":
        _traj, sim = rest_run
    else:
        lat = np.radians(40.0)
        p = _orthodrome(model, lat, 0.2, np.radians(30.0))
        traj = trajectory(model, _cruise_profile(lat, 0.2, 1.0, 150.0, 200.0), 2 * 3600.0,
                          10.0, p)
        sim = simulate(model, traj, [{"gyro_drift_y": 0.01 * DEG_H, "accel_bias_y": 2e-5 * 9.8,
                                      "initial_azimuth_error": 2e-4,
                                      "correction_gain_error_x": 1e-4}],
                       method="rk4", record_interval=120.0)
    direct, linear = sim.direct_errors(), sim.linear_errors()
    for name in ("alpha_x", "alpha_y", "alpha_z", "delta_latitude", "delta_longitude",
                 "delta_heading", "delta_v_N", "delta_v_E"):
        d, lin = direct[name], linear[name]
        scale = np.abs(d).max(axis=0)
        assert np.all(scale > 0)
        # second-order residual of the exact platform: about the largest angle (the
        # 0.05 °/h azimuth drift turns the platform 2.6e-3 rad in 3 h)
        assert np.all(np.abs(d - lin).max(axis=0) < 5e-3 * scale + 1e-12), name


# --------------------------------------------------------------------------------------
# Levelling offsets and bad input
# --------------------------------------------------------------------------------------
def test_levelling_offsets_are_the_geodetic_minus_geocentric_deflection():
    f = 1 / 298.3
    lat, psi = np.radians(45.0), np.radians(30.0)
    alpha0, beta0 = levelling_offsets(lat, psi)
    assert np.hypot(alpha0, beta0) == pytest.approx(f * np.sin(2 * lat), rel=1e-12)
    # the platform vertical (β0, −α0) tilts toward geographic north (cos ψ, sin ψ) on x, y
    tilt = np.array([beta0, -alpha0])
    assert tilt @ np.array([np.cos(psi), np.sin(psi)]) == pytest.approx(np.hypot(*tilt))
    assert 11.0 < np.degrees(np.hypot(alpha0, beta0)) * 60 < 12.0  # ≈ 11.5′ at 45°


def test_bad_input(model):
    x, p, c = _rest_point(model)
    u = model.input_vector(a_zeta=9.8)
    with pytest.raises(DomainError, match=r"latitude 90° is refused.* heading is undefined"):
        model.initial_state(model.initial_condition_vector(latitude=np.pi / 2), u, p)
    with pytest.raises(DomainError, match="R <= 0"):
        model.state_matrix(x, u, model.parameter_vector(R=0.0))
    with pytest.raises(DomainError, match="R <= 0"):
        model.initial_state(c, u, model.parameter_vector(R=-6.4e6))
    polar = x.copy()
    polar[0] = np.pi / 2
    with pytest.raises(DomainError, match="orthodromic latitude"):
        model.source_matrix(polar, u, p)
    with pytest.raises(DomainError, match="NaN"):
        model.state_matrix(np.r_[np.nan, x[1:]], u, p)


def test_integrator_offsets_act_like_their_instrument_counterparts(model):
    """First-integrator offsets enter exactly as accelerometer biases (factor 8 vs 7)."""
    names = [s.name for s in model.sources]
    for x, u, p, _c in _points(model, 4, 23):
        G = model.source_matrix(x, u, p)
        for axis in "xy":
            np.testing.assert_array_equal(G[:, names.index(f"velocity_integrator_offset_{axis}")],
                                          G[:, names.index(f"accel_bias_{axis}")])
        # second-integrator offsets drive only their own coordinate rate
        for coordinate, row in (("Phi", 0), ("Lam", 1)):
            column = G[:, names.index(f"position_integrator_offset_{coordinate}")]
            expected = np.zeros(len(column))
            expected[row] = 1.0
            np.testing.assert_array_equal(column, expected)
