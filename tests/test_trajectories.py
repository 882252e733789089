"""True motion: the ideal equations fed the generated inputs follow the intended motion.

References are independent of the code under test: spherical great-circle geometry
(closed form), the commanded speeds and heights, finite differences of the true state.
"""

from __future__ import annotations

import numpy as np
import pytest

from ins_errors.errors import DomainError, InsErrorsError, ShapeError
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.integrators import StepError
from ins_errors.numeric.simulate import simulate

DEG = np.pi / 180.0


def great_circle(phi0, lam0, chi0, distance_angle):
    """Latitude and longitude along a great circle on a sphere (closed form)."""
    phi = np.arcsin(np.sin(phi0) * np.cos(distance_angle)
                    + np.cos(phi0) * np.sin(distance_angle) * np.cos(chi0))
    lam = lam0 + np.arctan2(np.sin(chi0) * np.sin(distance_angle) * np.cos(phi0),
                            np.cos(distance_angle) - np.sin(phi0) * np.sin(phi))
    return phi, lam


def wrap(angle):
    return (angle + np.pi) % (2 * np.pi) - np.pi


@pytest.fixture(scope="module")
def sphere(orthodromic):
    return orthodromic.parameter_vector(e2=0.0)


def test_static_base_stays_put_to_rounding(orthodromic):
    traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG, 150.0),
                         86400.0, 1.0)
    assert traj.constant
    # the ideal run (manual's rectangle scheme) fed the inputs keeps every state constant
    sim = simulate(orthodromic, traj, {}, parts=(), record_interval=3600.0, method="euler")
    drift = np.abs(sim.ideal[:, :, 0] - traj.truth[:, :1])
    assert drift[:6].max() < 1e-13  # direction cosines
    assert drift[6:].max() < 1e-9  # absolute velocities (~300 m/s), m/s
    y = orthodromic.outputs_of(traj.truth[:, 0], traj.inputs[:, 0])
    np.testing.assert_allclose(y[:3], [50 * DEG, 30 * DEG, 20 * DEG], atol=1e-14)
    np.testing.assert_allclose(y[5:], 0.0, atol=1e-9)
    # apparent vertical acceleration at rest: normal gravity at 50°, 150 m (~9.8107)
    assert traj.inputs[2, 0] == pytest.approx(9.81069 - 3.086e-6 * 150, abs=1e-4)


def test_great_circle_truth_matches_spherical_geometry(orthodromic, sphere):
    phi0, lam0, chi0, speed, h = 50 * DEG, 30 * DEG, 40 * DEG, 250.0, 1000.0
    traj = tr.trajectory(orthodromic, tr.great_circle_profile(phi0, lam0, chi0, speed, h),
                         4 * 3600.0, 1.0, p=sphere)
    y = orthodromic.numpy.outputs(traj.truth, traj.inputs, sphere)
    phi, lam = great_circle(phi0, lam0, chi0, speed * traj.times / (sphere[0] + h))
    assert np.abs(y[0] - phi).max() < 1e-11
    assert np.abs(wrap(y[1] - lam)).max() < 1e-11
    np.testing.assert_allclose(np.hypot(y[5], y[6]), speed, rtol=1e-12)


def test_ideal_runs_reproduce_the_great_circle(orthodromic, sphere):
    phi0, lam0, chi0, speed = -20 * DEG, 100 * DEG, 130 * DEG, 300.0
    traj = tr.trajectory(orthodromic, tr.great_circle_profile(phi0, lam0, chi0, speed),
                         2 * 3600.0, 2.0, p=sphere)
    phi, lam = great_circle(phi0, lam0, chi0, speed * traj.times / sphere[0])
    for method, tolerance in (("rk4", 1e-11), ("euler", 2e-5)):
        sim = simulate(orthodromic, traj, {}, method=method, parts=())
        y = orthodromic.numpy.outputs(sim.ideal[:, :, 0], traj.inputs, sphere)
        error = max(np.abs(y[0] - phi).max(), np.abs(wrap(y[1] - lam)).max())
        # rk4: rounding only; euler: the rectangle scheme's O(τ) drift over 3600 steps
        # (|u|² grows by (ωτ)² per step, ω = v/R ≈ 4.7e-5 rad/s)
        assert error < tolerance, (method, error)
    assert error > 1e-9  # the rectangle scheme really is first order, not exact


def test_ellipsoidal_truth_is_consistent_with_the_ideal_equations(orthodromic):
    """Finite differences of the true state equal the ideal right-hand side (O(τ²))."""
    traj = tr.trajectory(orthodromic, tr.great_circle_profile(60 * DEG, 0.0, 80 * DEG, 250.0,
                                                              9000.0), 1800.0, 1.0)
    x, u, p = traj.truth, traj.inputs, traj.parameters
    central = (x[:, 2:] - x[:, :-2]) / 2.0
    rates = orthodromic.numpy.ideal_rhs(x[:, 1:-1], u[:, 1:-1], p)
    scale = np.abs(rates).max(axis=1, keepdims=True)
    assert (np.abs(central - rates) / scale).max() < 1e-6
    y = orthodromic.numpy.outputs(x, u, p)
    np.testing.assert_allclose(np.hypot(y[5], y[6]), 250.0, rtol=1e-10)


def test_manoeuvre_follows_the_commanded_speed_course_and_height(orthodromic):
    legs = [tr.Leg(300.0, 300.0, 90 * DEG, 3000.0), tr.Leg(300.0, 200.0, -30 * DEG, 1000.0)]
    profile = tr.manoeuvre_profile(45 * DEG, 10 * DEG, 0.0, 200.0, legs, h=1000.0)
    traj = tr.trajectory(orthodromic, profile, 900.0, 0.5)
    y = orthodromic.numpy.outputs(traj.truth, traj.inputs, traj.parameters)
    values, rates = profile.commands(traj.times)
    speed = np.hypot(values[0], values[1])
    np.testing.assert_allclose(np.hypot(y[5], y[6]), speed, rtol=1e-9)
    np.testing.assert_allclose(traj.inputs[4], values[2])  # height input
    np.testing.assert_allclose(traj.inputs[3], values[3])  # V_zeta = dh/dt
    assert speed[600] == pytest.approx(300.0) and speed[-1] == pytest.approx(200.0)
    assert np.abs(values[3]).max() > 5.0  # it really climbs
    # the course relative to the trihedron turned by 90° during the first leg
    course = np.arctan2(values[1], values[0])
    assert course[600] == pytest.approx(90 * DEG)
    # apparent accelerations are the physical ones: speed change of 100 m/s over 300 s
    # with the C² ramp peaks at 1.875 · 100 / 300 m/s²
    assert np.abs(rates[:2]).max() > 0.6


def test_sampled_motion_reproduces_a_generated_one(orthodromic, sphere):
    phi0, lam0, chi0, speed = 10 * DEG, 20 * DEG, 60 * DEG, 220.0
    reference = tr.trajectory(orthodromic, tr.great_circle_profile(phi0, lam0, chi0, speed),
                              1800.0, 1.0, p=sphere)
    y = orthodromic.numpy.outputs(reference.truth, reference.inputs, sphere)
    t = reference.times[::10]
    profile = tr.sampled_profile(t, y[5, ::10], y[6, ::10], phi0, lam0, chi0, 0.0)
    sampled = tr.trajectory(orthodromic, profile, 1800.0, 1.0, p=sphere)
    ys = orthodromic.numpy.outputs(sampled.truth, sampled.inputs, sphere)
    assert np.abs(ys[0] - y[0]).max() < 1e-9
    assert np.abs(wrap(ys[1] - y[1])).max() < 1e-9


def test_bad_motions_raise_one_line_errors(orthodromic):
    with pytest.raises(InsErrorsError, match="pole"):
        tr.static_profile(90 * DEG)
    with pytest.raises(StepError, match="whole number of steps"):
        tr.trajectory(orthodromic, tr.static_profile(0.3), 10.5, 1.0)
    with pytest.raises(StepError, match="positive"):
        tr.trajectory(orthodromic, tr.static_profile(0.3), 10.0, 0.0)
    t = np.arange(10.0)
    with pytest.raises(InsErrorsError, match="increasing"):
        tr.sampled_profile(t[::-1], t, t, 0.1, 0.0, 0.0)
    with pytest.raises(DomainError, match="NaN"):
        tr.sampled_profile(t, np.full(10, np.nan), t, 0.1, 0.0, 0.0)
    with pytest.raises(ShapeError):
        tr.sampled_profile(t, t[:5], t, 0.1, 0.0, 0.0)
    profile = tr.sampled_profile(t, t, t, 0.1, 0.0, 0.0)
    with pytest.raises(InsErrorsError, match="leaves the sampled motion"):
        tr.trajectory(orthodromic, profile, 20.0, 1.0)
    with pytest.raises(InsErrorsError, match="leg duration"):
        tr.manoeuvre_profile(0.1, 0.0, 0.0, 100.0, [tr.Leg(0.0, 100.0)])
    # a 7-day flight at 100 Hz is streamed; keeping it whole would need gigabytes: refused
    week = tr.trajectory(orthodromic, tr.great_circle_profile(0.5, 0.0, 0.0, 250.0),
                         7 * 86400.0, 0.01)
    assert week.is_streamed
    with pytest.raises(StepError, match="GB"):
        week.truth  # noqa: B018
    # a flight over the pole leaves the model's domain: named, with its time
    polar = tr.great_circle_profile(89.9 * DEG, 0.0, 0.0, 300.0)
    with pytest.raises(DomainError, match=r"t = \d"):
        tr.trajectory(orthodromic, polar, 600.0, 1.0)
    # ... and a streamed one says the same when it is run
    streamed = tr.trajectory(orthodromic, polar, 600.0, 1.0, stream=True)
    with pytest.raises(DomainError, match=r"true motion leaves the model's domain at t = \d"):
        simulate(orthodromic, streamed, {"gyro_drift_x": 1e-7}, method="euler")


def test_rest_with_a_moving_state_is_integrated():
    """A free-azimuth platform at rest keeps turning in azimuth: the truth must follow it,
    and the ideal equations fed the trajectory's inputs must reproduce that truth."""
    import ins_errors

    model = ins_errors.load_model("free_azimuth")
    tau = 10.0
    traj = tr.trajectory(model, tr.static_profile(np.radians(50), 0.3), 7200.0, tau)
    assert not traj.constant
    x, p = traj.truth[:, 0].copy(), traj.parameters
    f = model.numpy.ideal_rhs
    for k in range(traj.n_steps):  # independent RK4 over the sampled inputs
        u0, um, u1 = traj.inputs[:, k], traj.midpoints[:, k], traj.inputs[:, k + 1]
        k1 = f(x, u0, p)
        k2 = f(x + tau / 2 * k1, um, p)
        k3 = f(x + tau / 2 * k2, um, p)
        k4 = f(x + tau * k3, u1, p)
        x = x + tau / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    np.testing.assert_allclose(x, traj.truth[:, -1], rtol=1e-6, atol=1e-6)
    names = [o.name for o in model.outputs]
    y = model.numpy.outputs(x, traj.inputs[:, -1], p)
    assert y[names.index("latitude")] == pytest.approx(np.radians(50), abs=1e-9)
    assert y[names.index("longitude")] == pytest.approx(0.3, abs=1e-9)


def test_every_motion_survives_pickling_with_the_same_commands():
    """The process pool of a Monte Carlo run pickles the trajectory, and with it the
    profile (and a strapdown flight) whose commands were closures, which pickle refuses.
    Every profile and flight now goes through pickle and commands the same bits."""
    import pickle

    from ins_errors.numeric import strapdown_truth as sd

    legs = [tr.Leg(120.0, 200.0, 0.0, 3000.0), tr.Leg(90.0, 220.0, np.radians(90.0), 2000.0)]
    samples = np.arange(0.0, 1000.0, 10.0)
    profiles = [tr.static_profile(0.8, 0.1, 0.2, 10.0),
                tr.great_circle_profile(0.8, 0.5, 0.1, 250.0, 100.0),
                tr.manoeuvre_profile(0.8, 0.5, 0.1, 150.0, legs),
                tr.sampled_profile(samples, np.sin(samples / 99), np.cos(samples / 77), 0.8,
                                   0.5, 0.1, h=samples)]
    flights = [sd.static(0.8, 0.1, 5.0), sd.great_circle(0.8, 0.1, 0.3, 200.0),
               sd.manoeuvre(0.8, 0.5, 0.1, 150.0, legs), sd.standard_manoeuvre(),
               sd.flight_from_profile(profiles[2])]
    t = np.linspace(0.0, 900.0, 901)
    for motion in profiles + flights:
        copy = pickle.loads(pickle.dumps(motion))
        for mine, theirs in zip(motion.commands(t), copy.commands(t), strict=True):
            assert mine.tobytes() == theirs.tobytes()
