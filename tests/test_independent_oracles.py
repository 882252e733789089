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


def _motion_inputs_and_ecef(model, p, traj, lat, lon, chi, h):
    """Sample times, the model's motion inputs (a_ξ, a_η, a_ζ less those of a static
    base at the same place) and the ECEF computation's, in the track axes, shape (3, n).

    The ECEF terms come from the truth's latitude, longitude and height by central
    differences (one step lost at each end, hence ``samples - 1``)."""
    tau = traj.tau
    expected = motion_terms(lat, lon, h, tau, WGS84_A, WGS84_E2)
    east, north, up = (axis[:, 1:-1] for axis in local_axes(lat, lon))
    c, s = np.cos(chi[1:-1]), np.sin(chi[1:-1])
    xi = c * north + s * east
    eta = np.cross(up.T, xi.T).T  # η = ζ × ξ, to the left of the track
    oracle = np.array([np.sum(axis * expected, axis=0) for axis in (xi, eta, up)])
    samples = np.arange(60, traj.n_steps - 60, 120)
    names = [i.name for i in model.inputs]
    got = []
    for k in samples:
        static = tr.trajectory(model, tr.static_profile(lat[k], lon[k], chi[k], h=h[k]),
                               tau, tau, p=p)
        got.append([traj.inputs[names.index(n), k] - static.inputs[names.index(n), 0]
                    for n in ("a_xi", "a_eta", "a_zeta")])
    return samples, np.array(got).T, oracle[:, samples - 1]


def test_east_west_flight_specific_force_matches_ecef(wgs84_orthodromic):
    model, p = wgs84_orthodromic
    traj, y = _flight(model, p, 90 * DEG)
    lat, lon, chi = y["latitude"], y["longitude"], y["heading"]
    h = traj.inputs[[i.name for i in model.inputs].index("h")]
    _, got, want = _motion_inputs_and_ecef(model, p, traj, lat, lon, chi, h)
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


def test_climbing_flight_specific_force_matches_ecef(wgs84_orthodromic):
    """A manoeuvring flight with 15 m/s climbs and descents: the vertical velocity's
    Coriolis and transport terms (ω_η V_ζ, ω_ξ V_ζ in W_ξ, W_η: ~2e-3 m/s² here) and the
    vertical acceleration must be in the inputs, as the ECEF computation has them."""
    model, p = wgs84_orthodromic
    tau = 0.5
    legs = [tr.Leg(300.0, 250.0, 0.0, 7500.0), tr.Leg(300.0, 250.0, 30 * DEG, 7500.0),
            tr.Leg(300.0, 250.0, 0.0, 3000.0)]
    profile = tr.manoeuvre_profile(50 * DEG, 30 * DEG, 40 * DEG, 250.0, legs, h=3000.0)
    traj = tr.trajectory(model, profile, 900.0, tau, p=p)
    y = model.outputs_of(traj.truth, traj.inputs, p)
    names = [o.name for o in model.outputs]
    y = {n: y[k] for k, n in enumerate(names)}
    inputs = [i.name for i in model.inputs]
    lat, lon, chi = y["latitude"], y["longitude"], y["heading"]
    h, v_zeta = traj.inputs[inputs.index("h")], traj.inputs[inputs.index("V_zeta")]
    assert np.abs(v_zeta).max() > 14.0  # it does climb
    samples, got, want = _motion_inputs_and_ecef(model, p, traj, lat, lon, chi, h)
    climbing = np.abs(v_zeta[samples]) > 5.0
    assert climbing.sum() >= 5
    # central differences of a C² ramp at τ = 1 s: ~1e-6 m/s²
    # measured: up to 8e-6 m/s² in the 0.8 m/s² turn (the manual's first-order radii,
    # central differences) and 7e-6 in a_ξ at the 28 m/s climb (2.6e-3 of the
    # ω_η V_ζ term there); dropping the V_ζ terms of W changes a_ξ, a_η by ~3e-3 m/s²
    assert np.allclose(got, want, atol=2.5e-5), np.abs(got - want).max(axis=1)


# --------------------------------------------------------------------------------------
# free-azimuth model: a climbing flight over its sphere
# --------------------------------------------------------------------------------------
def test_free_azimuth_climb_horizontal_specific_force_matches_inertial_kinematics():
    """The free-azimuth INS climbing at 20 m/s over its navigation sphere (radius R; the
    source: height not modelled, "as V_z we use V_h", vertical acceleration neglected).
    Its design equation V̇ = f − ω × V_h (V the absolute horizontal velocity R u̇, u the
    inertial unit vector of the place) says the horizontal specific force is
    f_h = R ü_h + V_h u̇: here computed from the truth's latitude and longitude alone,
    turned by U t into inertial axes and differentiated numerically. The V_h u̇ part is
    1.6e-3 m/s² (20 m/s · 520 m/s / R, the absolute speed with the Earth's turn); it
    changes |f_h| by 1.8e-4 m/s² in this geometry."""
    model = ins_errors.load_model("free_azimuth")
    p = model.parameter_vector(orth_latitude=50 * DEG, orth_longitude=30 * DEG,
                               orth_azimuth=70 * DEG)
    R = p[[q.name for q in model.parameters].index("R")]
    v_n, v_e, climb = 150.0, 200.0, 20.0

    def commands(t):
        values = np.zeros((4, t.size))
        values[0], values[1], values[2], values[3] = v_n, v_e, climb * t, climb
        rates = np.zeros((4, t.size))
        rates[2] = climb
        return values, rates

    profile = tr.Profile("geographic", commands, 50 * DEG, 30 * DEG, 0.3, "climb")
    tau = 0.5
    traj = tr.trajectory(model, profile, 600.0, tau, p=p)
    y = model.outputs_of(traj.truth, traj.inputs, p)
    names = [o.name for o in model.outputs]
    lat, lon = y[names.index("latitude")], y[names.index("longitude")]
    t = np.arange(lat.size) * tau
    inputs = [i.name for i in model.inputs]
    assert np.allclose(traj.inputs[inputs.index("V_zeta")], climb)
    got, want, transport = [], [], []
    for k in range(100, lat.size - 100, 100):
        j = np.array([k - 1, k, k + 1])
        spin = lon[j] + U * t[j]  # inertial axes: the Earth-fixed ones turned by U t
        unit = np.array([np.cos(lat[j]) * np.cos(spin), np.cos(lat[j]) * np.sin(spin),
                         np.sin(lat[j])])
        rate = (unit[:, 2] - unit[:, 0]) / (2 * tau)
        acc = (unit[:, 2] - 2 * unit[:, 1] + unit[:, 0]) / tau**2
        acc = acc - (acc @ unit[:, 1]) * unit[:, 1]
        want.append(np.linalg.norm(R * acc + climb * rate))
        transport.append(np.linalg.norm(R * acc + climb * rate) - np.linalg.norm(R * acc))
        got.append(np.hypot(traj.inputs[inputs.index("a_x"), k],
                            traj.inputs[inputs.index("a_y"), k]))
    got, want = np.array(got), np.array(want)
    assert np.abs(transport).min() > 1e-4  # what the V_h coupling does to |f_h|
    # measured: 5e-9 m/s² (central differences at τ = 0.5 s)
    assert np.allclose(got, want, rtol=0, atol=1e-6), np.abs(got - want).max()
