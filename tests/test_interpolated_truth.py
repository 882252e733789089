"""The interpolated (coarse-grid) truth against the fine truth and closed forms.

References: the fine truth (RK4 at half the step, inputs evaluated at every half step:
the previous code path, kept as ``truth="fine"``), spherical great-circle geometry
(closed form), and the direct error runs that users read. The interpolated truth must
reproduce the fine one to far below the linear-vs-direct differences the toolchain
reports.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from ins_errors.errors import DomainError, InsErrorsError
from ins_errors.numeric import interpolated_truth as it
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.integrators import StepError
from ins_errors.numeric.simulate import simulate
from tests.helpers import assert_chunks_join_into, joined_chunks

DEG = np.pi / 180.0
# leg joins at 300 s, 423.456 s (off the step grid), 723.456 s; ramps of 1.875x mean rate
LEGS = [tr.Leg(300.0, 280.0, 75 * DEG, 2500.0), tr.Leg(123.456, 230.0, -40 * DEG, 1500.0),
        tr.Leg(300.0, 200.0, -90 * DEG, 500.0)]
SOURCES = {"gyro_drift_x": 0.01 * DEG / 3600, "accel_bias_y": 1e-4,
           "initial_azimuth_error": 2e-4}


def _both(model, profile, duration, tau):
    """The fine truth stored (the tests read it three times; streamed, it would be
    integrated again each time) and the interpolated truth streamed."""
    fine = tr.trajectory(model, profile, duration, tau, stream=False, truth="fine")
    fast = tr.trajectory(model, profile, duration, tau, stream=True, truth="interpolated")
    return fine, fast


@pytest.fixture(scope="module")
def manoeuvre(orthodromic):
    profile = tr.manoeuvre_profile(48 * DEG, 20 * DEG, 30 * DEG, 220.0, LEGS, h=1000.0)
    return _both(orthodromic, profile, 900.0, 0.01)


@pytest.fixture(scope="module")
def cruise(orthodromic):
    profile = tr.great_circle_profile(50 * DEG, 30 * DEG, 90 * DEG, 250.0, 5000.0)
    return _both(orthodromic, profile, 1200.0, 0.01)


def _unit_sizes(values, units):
    """Largest magnitude over the run of all quantities sharing each row's unit."""
    size = np.abs(values).max(axis=1)
    return np.array([max(size[[k for k, v in enumerate(units) if v == unit]].max(), 1e-30)
                     for unit in units])


@pytest.fixture(scope="module")
def sampled(orthodromic):
    """A weave given as samples every 5 s (geographic frame, cubic splines: breaks at the
    knots)."""
    t = np.arange(0.0, 905.0, 5.0)
    profile = tr.sampled_profile(t, 200.0 + 30.0 * np.sin(2 * np.pi * t / 300.0),
                                 100.0 * np.cos(2 * np.pi * t / 450.0), 35 * DEG, 10 * DEG,
                                 0.0, 1000.0 + 200.0 * np.sin(2 * np.pi * t / 600.0))
    return _both(orthodromic, profile, 900.0, 0.01)


MOTIONS = ["cruise", "manoeuvre", "sampled"]


@pytest.mark.parametrize("motion", MOTIONS)
def test_states_and_inputs_match_the_fine_truth(orthodromic, motion, request):
    """At every 100 Hz step and midpoint, across the leg joins (one off the grid)."""
    fine, fast = request.getfixturevalue(motion)
    assert isinstance(fast.source, it.InterpolatedTruth)
    x_f, u_f, m_f = joined_chunks(fine)
    x_i, u_i, m_i = joined_chunks(fast)
    # relative to the size of the quantities of the same unit over the run (inputs:
    # accelerations, V_zeta, h; states: direction cosines, velocities); measured: inputs
    # 1e-15 (cruise, sampled) and 2e-12 (manoeuvre), states 2e-14, 2e-13 and 4e-10 (the
    # RK4 error of the node-to-node steps, 2e-7 m/s of the velocities after 900 s of
    # manoeuvres)
    state_units = [s.unit for s in orthodromic.states]
    input_units = [i.unit for i in orthodromic.inputs]
    for fine_values, fast_values, units, tolerance in (
            (x_f, x_i, state_units, 5e-9), (u_f, u_i, input_units, 1e-10),
            (m_f, m_i, input_units, 1e-10)):
        size = _unit_sizes(fine_values, units)
        error = (np.abs(fast_values - fine_values).max(axis=1) / size).max()
        assert error < tolerance
    if motion == "manoeuvre":  # the joins really are rough: the accelerations jump in slope
        a_eta = u_f[1]
        assert np.abs(a_eta).max() > 0.5
    # the interpolation's own (cautious) estimate is small for these motions
    estimate = fast.source.error_estimate
    units = state_units + input_units
    sizes = np.concatenate([_unit_sizes(x_f, state_units), _unit_sizes(u_f, input_units)])
    assert (estimate / sizes).max() < 1e-8 and fast.source.worst < it.WARN_RELATIVE
    assert len(units) == len(estimate)


@pytest.mark.parametrize("method", ["euler", "rk4"])
@pytest.mark.parametrize("motion", MOTIONS)
def test_direct_errors_match_the_fine_truth_far_below_linear_differences(
        orthodromic, motion, method, request):
    fine, fast = request.getfixturevalue(motion)
    runs = [simulate(orthodromic, t, SOURCES, method=method, record_interval=1.0,
                     parts=("real", "linear")) for t in (fine, fast)]
    direct_fine, direct_fast = (r.direct_errors() for r in runs)
    linear = runs[0].linear_errors()
    size = np.abs(direct_fine.values).max(axis=(1, 2))
    excited = size > 0
    fast_vs_fine = np.abs(direct_fast.values - direct_fine.values).max(axis=(1, 2))[excited]
    linear_vs_direct = np.abs(linear.values - direct_fine.values).max(axis=(1, 2))[excited]
    # measured (largest over the quantities, of each curve's size): 1.2e-10 (cruise),
    # 1.8e-9 (manoeuvre), 3.4e-10 (sampled); the linear-vs-direct differences are 7e-8 to
    # 1e-4 of them, the fast-vs-fine ones at most 1.4e-4 of those
    assert (fast_vs_fine / size[excited]).max() < 1e-7
    assert (fast_vs_fine / linear_vs_direct).max() < 1e-2


def test_great_circle_follows_spherical_geometry(orthodromic):
    sphere = orthodromic.parameter_vector(e2=0.0)
    phi0, lam0, chi0, speed, h = -30 * DEG, 100 * DEG, 140 * DEG, 300.0, 2000.0
    traj = tr.trajectory(orthodromic, tr.great_circle_profile(phi0, lam0, chi0, speed, h),
                         3600.0, 0.05, p=sphere)
    assert isinstance(traj.source, it.InterpolatedTruth)  # "auto" chose it
    y = orthodromic.numpy.outputs(traj.truth, traj.inputs, sphere)
    angle = speed * traj.times / (sphere[0] + h)
    phi = np.arcsin(np.sin(phi0) * np.cos(angle) + np.cos(phi0) * np.sin(angle) * np.cos(chi0))
    lam = lam0 + np.arctan2(np.sin(chi0) * np.sin(angle) * np.cos(phi0),
                            np.cos(angle) - np.sin(phi0) * np.sin(phi))
    assert np.abs(y[0] - phi).max() < 1e-11
    assert np.abs((y[1] - lam + np.pi) % (2 * np.pi) - np.pi).max() < 1e-11
    np.testing.assert_allclose(np.hypot(y[5], y[6]), speed, rtol=1e-11)


def test_chunks_do_not_change_the_numbers(orthodromic):
    """Stored, streamed in any chunk size, runs fed either way: identical to the bit."""
    profile = tr.manoeuvre_profile(48 * DEG, 20 * DEG, 30 * DEG, 220.0, LEGS, h=1000.0)
    stored = tr.trajectory(orthodromic, profile, 1500.0, 0.1, stream=False)
    streamed = tr.trajectory(orthodromic, profile, 1500.0, 0.1, stream=True)
    assert isinstance(streamed.source, it.InterpolatedTruth)
    # blocks of 12800 steps: every boundary crossed
    assert_chunks_join_into(streamed, stored, (7, 250, 5000, 15000))
    a = simulate(orthodromic, stored, SOURCES, method="rk4", record_interval=10.0)
    b = simulate(orthodromic, streamed, SOURCES, method="rk4", record_interval=10.0)
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(getattr(a, part), getattr(b, part)), part


def test_coarse_steps_keep_the_fine_truth_bit_for_bit(orthodromic):
    """Where an interval would hold few steps, "auto" is the fine truth."""
    profile = tr.manoeuvre_profile(48 * DEG, 20 * DEG, 30 * DEG, 220.0, LEGS, h=1000.0)
    auto = tr.trajectory(orthodromic, profile, 600.0, 0.5)
    fine = tr.trajectory(orthodromic, profile, 600.0, 0.5, truth="fine")
    assert np.array_equal(auto.truth, fine.truth) and np.array_equal(auto.inputs, fine.inputs)
    # so do samples denser than the intervals (breaks at every knot)
    t = np.arange(0.0, 20.05, 0.1)
    dense = tr.sampled_profile(t, 200.0 + 0 * t, 10.0 * np.sin(t), 0.6, 0.1, 0.0)
    traj = tr.trajectory(orthodromic, dense, 20.0, 0.01, stream=True)
    assert isinstance(traj.source, tr.ProfileTruth)


def test_plan_ends_intervals_at_every_break():
    plan = it.plan(90000, 0.01, (300.0, 423.456, 723.456, 5000.0))
    ends = plan.start + plan.length
    for b in (300.0, 423.456, 723.456):
        assert np.min(np.abs(ends - b)) < 1e-9  # an interval ends there
    assert plan.length.max() <= it.INTERVAL + 0.01 and plan.start[0] == 0.0
    assert ends[-1] == pytest.approx(900.0)
    np.testing.assert_allclose(plan.start[1:], ends[:-1])
    # every half step belongs to exactly one interval, in order
    assert plan.first_half[0] == 0 and plan.first_half[-1] == 2 * 90000 + 1
    assert np.all(np.diff(plan.first_half) > 0)


def _declared_smooth(commands_of_t):
    """A track-frame profile at 250 m/s whose sideways speed is ``commands_of_t(t)`` ->
    (v_eta, rate), declared smooth throughout (no breaks)."""
    smooth = tr.great_circle_profile(50 * DEG, 30 * DEG, 0.0, 250.0)

    def commands(t):
        values, rates = smooth.commands(t)
        values[1], rates[1] = commands_of_t(t)
        return values, rates

    return tr.Profile("track", commands, 50 * DEG, 30 * DEG, 0.0, "own", breaks=())


@pytest.mark.parametrize("motion", ["hard turns", "weave"])
def test_fast_motions_get_shorter_intervals(orthodromic, motion):
    """Turns of 137° in 20 s (about 6 g) and a weave of 4 s period: the commands are not
    resolved by 10-s intervals, which are halved until they are."""
    if motion == "hard turns":
        legs = [tr.Leg(20.0, 250.0, 2.4), tr.Leg(20.0, 250.0, -2.4)] * 2
        profile = tr.manoeuvre_profile(48 * DEG, 20 * DEG, 30 * DEG, 250.0, legs, h=1000.0)
    else:
        w = 2 * np.pi / 4.0
        profile = _declared_smooth(lambda t: (20.0 * np.sin(w * t), 20.0 * w * np.cos(w * t)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning: the intervals resolve the motion
        fine, fast = _both(orthodromic, profile, 80.0, 0.01)
        _, u_f, m_f = joined_chunks(fine)
        _, u_i, m_i = joined_chunks(fast)
    blocks = list(fast.source._blocks())
    assert sum(len(b.nodes) for b in blocks) > 2 * len(fast.source.plan.start)  # refined
    units = [i.unit for i in orthodromic.inputs]
    for a, b in ((u_f, u_i), (m_f, m_i)):
        # measured 9e-13 (hard turns) and 6e-12 (weave); 4e-4 and 0.45 without halving
        assert (np.abs(b - a).max(axis=1) / _unit_sizes(a, units)).max() < 1e-10


def test_a_hidden_kink_is_flagged(orthodromic):
    """A sideways speed that starts to grow at 3.3 s (its rate jumps) declared smooth:
    no interval resolves it; the estimate sees it and warns."""
    kink = _declared_smooth(lambda t: (5.0 * np.maximum(t - 3.3, 0.0), 5.0 * (t > 3.3)))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        traj = tr.trajectory(orthodromic, kink, 60.0, 0.01, stream=True)
        list(traj.chunks(1000))
    assert any("--truth fine" in str(w.message) for w in caught)
    assert traj.source.worst > it.WARN_RELATIVE


def test_bad_truth_choices_raise_one_line_errors(orthodromic):
    great = tr.great_circle_profile(50 * DEG, 30 * DEG, 0.0, 250.0)
    with pytest.raises(InsErrorsError, match="truth"):
        tr.trajectory(orthodromic, great, 10.0, 0.01, truth="coarse")
    unknown = tr.Profile("track", great.commands, 50 * DEG, 30 * DEG, 0.0, "own")
    with pytest.raises(InsErrorsError, match="breaks"):
        tr.trajectory(orthodromic, unknown, 10.0, 0.01, truth="interpolated")
    # a flight over the pole (after about 37 s) leaves the domain: named with its time,
    # when it is run
    polar = tr.great_circle_profile(89.9 * DEG, 0.0, 0.0, 300.0)
    streamed = tr.trajectory(orthodromic, polar, 600.0, 0.01, stream=True)
    with pytest.raises(DomainError, match=r"true motion leaves the model's domain at t = 3\d"):
        simulate(orthodromic, streamed, {"gyro_drift_x": 1e-7}, method="euler")


@pytest.mark.parametrize("stream", [False, True])
def test_a_run_of_no_steps_is_refused(orthodromic, stream):
    """A run of zero duration is refused as the scenario files refuse it (compare() gave
    worst_linear None for it), stored or streamed alike."""
    great = tr.great_circle_profile(50 * DEG, 30 * DEG, 10 * DEG, 250.0)
    with pytest.raises(StepError, match="run duration must be positive, got 0 s"):
        tr.trajectory(orthodromic, great, 0.0, 0.01, stream=stream)


def test_manoeuvre_commands_follow_the_legs():
    """Commands against the C² ramp written out: before, inside and after the legs."""
    profile = tr.manoeuvre_profile(0.5, 0.1, 0.0, 220.0, LEGS, h=1000.0)
    t = np.array([-3.0, 0.0, 150.0, 300.0, 361.728, 1000.0])
    values, rates = profile.commands(t)
    # before and at the start of the first leg: the initial speed along ξ, at rest in h
    np.testing.assert_array_equal(values[:, :2], [[220.0, 220.0], [0.0, 0.0],
                                                  [1000.0, 1000.0], [0.0, 0.0]])
    np.testing.assert_array_equal(rates[:, :2], 0.0)
    # mid first leg: s = 1/2, ds/dθ = 30/16, course 75°/2, height halfway to 2500 m
    speed, course = 220.0 + 60.0 / 2, 75 * DEG / 2
    np.testing.assert_allclose(values[:, 2], [speed * np.cos(course), speed * np.sin(course),
                                              1750.0, 1500.0 * 30 / 16 / 300.0], rtol=1e-14)
    dv, dpsi = 60.0 * 30 / 16 / 300.0, 75 * DEG * 30 / 16 / 300.0
    np.testing.assert_allclose(rates[:2, 2], [dv * np.cos(course) - speed * np.sin(course) * dpsi,
                                              dv * np.sin(course) + speed * np.cos(course) * dpsi],
                               rtol=1e-13)
    # at the join and after the last leg: the legs' end values, steady
    np.testing.assert_allclose(np.hypot(values[0, 3], values[1, 3]), 280.0, rtol=1e-15)
    course_end = (75 - 40 - 90) * DEG
    np.testing.assert_allclose(values[:, 5], [200.0 * np.cos(course_end),
                                              200.0 * np.sin(course_end), 500.0, 0.0],
                               rtol=1e-14, atol=1e-12)
    np.testing.assert_allclose(rates[:, 5], 0.0, atol=1e-15)


def test_what_the_warning_says_of_the_error_curves_holds(orthodromic):
    """The warning says the error curves (real minus ideal work along the same motion)
    are affected far less than the motion: on the hidden kink (the motion off by up to
    0.036 of its size), the direct and linear error curves on the interpolated truth
    against those on the fine truth (measured: at most 1.5e-3 of their size)."""
    from ins_errors.numeric.simulate import simulate

    kink = _declared_smooth(lambda t: (5.0 * np.maximum(t - 3.3, 0.0), 5.0 * (t > 3.3)))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fine, fast = _both(orthodromic, kink, 120.0, 0.01)
        sources = {"gyro_drift_x": 0.01 * DEG / 3600, "accel_bias_y": 1e-4}
        runs = [simulate(orthodromic, traj, sources, record_interval=1.0,
                         parts=("real", "linear")) for traj in (fine, fast)]
    said = [str(w.message) for w in caught if "interpolated true motion" in str(w.message)]
    assert len(said) == 1
    assert said[0].endswith("""rerun with a truth integrated at every step: --truth fine """
                            """(truth = "fine" in a scenario's [run])""")
    worst = fast.source.worst
    assert worst > 1e-2
    for kind in ("direct_errors", "linear_errors"):
        a, b = (getattr(run, kind)() for run in runs)
        for k in range(len(a.names)):
            scale = np.abs(a.values[k]).max()
            assert np.abs(b.values[k] - a.values[k]).max() <= 0.1 * worst * scale
