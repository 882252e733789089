"""Independent oracles for faults the other tests would let through.

* Position and specific force of a flight, against an independent Earth-fixed (ECEF)
  computation: the geodetic position of the truth is turned into ECEF coordinates with
  the textbook ellipsoid formula, differentiated numerically, and the specific force a
  moving vehicle needs beyond a static one at the same point is
  ``r̈ + 2 Ω × ṙ`` (the gravity and centrifugal terms depend on position only).
* The meridian flight: ``φ̇ = v_N / (R_N + h)`` with the textbook meridian radius.
* Covariance propagation on a time-varying system: its convergence order against an
  adaptive ODE solution (scipy) of the same sensitivities.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import ins_errors
from ins_errors.analysis.covariance import Functionals, SourceStatistics, propagate
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.linear_system import LinearSystem

DEG = np.pi / 180
WGS84_A, WGS84_E2 = 6_378_137.0, 6.69437999014e-3
U = 7.292115e-5


def ecef(lat, lon, h, a, e2):
    """Textbook geodetic -> Earth-fixed coordinates, m (axes: Greenwich, 90° E, pole)."""
    n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    return np.array([(n + h) * np.cos(lat) * np.cos(lon), (n + h) * np.cos(lat) * np.sin(lon),
                     (n * (1 - e2) + h) * np.sin(lat)])


def local_axes(lat, lon):
    """East, north, up unit vectors in ECEF (geodetic normal)."""
    east = np.array([-np.sin(lon), np.cos(lon), 0 * lon])
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    up = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    return east, north, up


def motion_terms(lat, lon, h, tau, a, e2):
    """r̈ + 2Ω×ṙ (ECEF, m/s²) at the inner samples, by central differences."""
    r = ecef(lat, lon, h, a, e2)
    v = (r[:, 2:] - r[:, :-2]) / (2 * tau)
    acc = (r[:, 2:] - 2 * r[:, 1:-1] + r[:, :-2]) / tau**2
    coriolis = 2 * np.cross(np.array([0.0, 0.0, U]), v.T).T
    return acc + coriolis


# --------------------------------------------------------------------------------------
# orthodromic truth: east-west flight, meridian flight
# --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def wgs84_orthodromic():
    model = ins_errors.load_model("orthodromic")
    return model, model.parameter_vector(ellipsoid="wgs84")


def _flight(model, p, heading, minutes=20.0, tau=1.0, height=3000.0):
    profile = tr.great_circle_profile(50 * DEG, 30 * DEG, heading, 250.0, h=height)
    traj = tr.trajectory(model, profile, minutes * 60.0, tau, p=p)
    y = model.outputs_of(traj.truth, traj.inputs, p)
    names = [o.name for o in model.outputs]
    return traj, {n: y[k] for k, n in enumerate(names)}


def test_east_west_flight_specific_force_matches_ecef(wgs84_orthodromic):
    model, p = wgs84_orthodromic
    traj, y = _flight(model, p, 90 * DEG)
    tau = traj.tau
    lat, lon, chi = y["latitude"], y["longitude"], y["heading"]
    h = traj.inputs[[i.name for i in model.inputs].index("h")]
    expected = motion_terms(lat, lon, h, tau, WGS84_A, WGS84_E2)
    east, north, up = (axis[:, 1:-1] for axis in local_axes(lat, lon))
    c, s = np.cos(chi[1:-1]), np.sin(chi[1:-1])
    xi = c * north + s * east
    eta = np.cross(up.T, xi.T).T  # η = ζ × ξ, to the left of the track
    oracle = np.array([np.sum(axis * expected, axis=0) for axis in (xi, eta, up)])
    # the model's inputs minus those of a static base at each sampled point
    samples = np.arange(60, traj.n_steps - 60, 120)
    names = [i.name for i in model.inputs]
    got = []
    for k in samples:
        static = tr.trajectory(model, tr.static_profile(lat[k], lon[k], chi[k], h=h[k]),
                               tau, tau, p=p)
        got.append([traj.inputs[names.index(n), k] - static.inputs[names.index(n), 0]
                    for n in ("a_xi", "a_eta", "a_zeta")])
    got = np.array(got).T
    want = oracle[:, samples - 1]
    # the vertical terms are about 0.04 m/s² (v²/R ≈ 0.01, 2U cos φ v_E ≈ 0.023)
    assert np.abs(want[2]).min() > 0.03
    assert np.allclose(got, want, atol=2e-5 * 0.04 + 1e-6), (got - want)


def test_meridian_flight_latitude_rate(wgs84_orthodromic):
    model, p = wgs84_orthodromic
    traj, y = _flight(model, p, 0.0, minutes=30.0, tau=1.0)
    lat = y["latitude"]
    h = traj.inputs[[i.name for i in model.inputs].index("h")]
    rate = (lat[2:] - lat[:-2]) / (2 * traj.tau)
    s2 = np.sin(lat[1:-1]) ** 2
    meridian = WGS84_A * (1 - WGS84_E2) / (1 - WGS84_E2 * s2) ** 1.5
    expected = y["v_N"][1:-1] / (meridian + h[1:-1])
    assert np.allclose(y["v_N"], 250.0, rtol=1e-9)
    # the manual's radii are first order in e²: a few 1e-5 relative at most
    assert np.max(np.abs(rate / expected - 1)) < 1e-4


# --------------------------------------------------------------------------------------
# north-pointing model: vertical specific force, meridian radius
# --------------------------------------------------------------------------------------
def test_north_pointing_vertical_force_and_radii_match_ecef():
    model = ins_errors.load_model("north_pointing")
    p = model.parameter_vector(ellipsoid="wgs84")
    lat, lon, h, v_E, v_N = 50 * DEG, 30 * DEG, 3000.0, 230.0, -120.0
    x = np.array([v_E, v_N, lat, lon])
    u = model.input_vector(h=h)
    rates = model.numpy.ideal_rhs(x, u, p)
    # level flight through the point at these velocities, sampled around it
    tau = 0.5
    t = np.array([-tau, 0.0, tau])
    path_lat = lat + rates[2] * t
    path_lon = lon + rates[3] * t
    terms = motion_terms(path_lat, path_lon, h + 0 * t, tau, WGS84_A, WGS84_E2)[:, 0]
    east, north, up = local_axes(lat, lon)
    # the ground speed the model's position rates describe is the commanded one
    r = ecef(path_lat, path_lon, h + 0 * t, WGS84_A, WGS84_E2)
    velocity = (r[:, 2] - r[:, 0]) / (2 * tau)
    assert velocity @ north == pytest.approx(v_N, rel=1e-7)
    assert velocity @ east == pytest.approx(v_E, rel=1e-7)
    # vertical specific force: f_U(moving) − f_U(static) = up · (r̈ + 2Ω × ṙ), read from
    # the tilt coupling of the real-work equations (f_E = a_E − α_N f_U + ...)
    n = len(model.states)
    w = np.zeros(len(model.sources))

    def f_up(state):
        eps = 1e-7
        xr = np.concatenate([state, [0.0, eps, 0.0]])
        xr0 = np.concatenate([state, [0.0, -eps, 0.0]])
        fn = model.numpy.real_rhs_small_angle
        return -(fn(xr, state, u, w, p)[0] - fn(xr0, state, u, w, p)[0]) / (2 * eps)

    static = np.array([0.0, 0.0, lat, lon])
    assert f_up(x) - f_up(static) == pytest.approx(up @ terms, rel=1e-5)
    assert f_up(static) == pytest.approx(model.parameters[[q.name for q in
                                         model.parameters].index("g")].default, rel=1e-12)
    _ = n


# --------------------------------------------------------------------------------------
# covariance: convergence order on a time-varying system
# --------------------------------------------------------------------------------------
def _oscillator(step: float, duration: float) -> LinearSystem:
    """x'' = −ω(t)² x + b with ω(t) = ω₀ (1 + 0.5 sin(t/300 s)); b a constant source."""
    times = np.arange(0.0, duration + step / 2, step)
    w = 2 * np.pi / 600.0 * (1 + 0.5 * np.sin(times / 300.0))
    F = np.zeros((len(times), 2, 2))
    F[:, 0, 1] = 1.0
    F[:, 1, 0] = -w**2
    G = np.zeros((len(times), 2, 1))
    G[:, 1, 0] = 1e-3
    E = np.array([[1.0], [0.0]])
    return LinearSystem(times, F, G, E, np.eye(2), ("b",), ("constant",),
                        np.zeros((2, len(times))), np.zeros((1, len(times))), np.zeros(0))


def test_covariance_propagation_is_second_order_on_a_time_varying_system():
    duration = 1800.0

    def rhs(t, z):
        w = 2 * np.pi / 600.0 * (1 + 0.5 * np.sin(t / 300.0))
        return [z[1], -w**2 * z[0] + 1e-3]

    reference = solve_ivp(rhs, (0.0, duration), [1.0, 0.0], rtol=1e-12, atol=1e-14,
                          method="DOP853").y[:, -1]
    functionals = Functionals(("x", "v"), ("1", "1"), np.eye(2), np.zeros((2, 1)))
    errors = []
    for step in (20.0, 10.0, 5.0):
        cov = propagate(_oscillator(step, duration), [SourceStatistics("b", sigma=1.0)],
                        functionals)
        errors.append(np.abs(np.sqrt(cov.unit_variances[-1, :, 0]) - np.abs(reference)).max())
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.7), (errors, orders)
