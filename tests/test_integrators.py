"""Integrators: the manual's difference scheme exactly, RK4 order, compiled = reference.

The lab manual's rectangle-method scheme (source 000, ideal and real work) is written out
below from the printed formulas, independently of the model definition and of the
generated code, and stepped alongside the library's compiled Euler loop.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from ins_errors.numeric import integrators as integ
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.integrators import StepError, exact_discretisation, integrate, step_count
from ins_errors.numeric.simulate import linear_exact, simulate

DEG = np.pi / 180.0


# --------------------------------------------------------------------------------------
# The manual's printed difference equations (ideal and real work), written independently
# --------------------------------------------------------------------------------------
def manual_rates(s, h, a, e2, U):
    """ω (absolute), ω' (relative) of the printed formulas for a state s = (u.., V..)."""
    u11, u21, u31, _u12, _u22, _u32, Vxi, Veta = s
    inv_Rxi = (1 - 0.5 * e2 * u31**2 + e2 * u11**2 - h / a) / a
    inv_Reta = (1 - 0.5 * e2 * u31**2 + e2 * u21**2 - h / a) / a
    inv_Ro = e2 * u11 * u21 / a
    w = (-(Veta * inv_Reta + Vxi * inv_Ro), Vxi * inv_Rxi + Veta * inv_Ro, U * u31)
    wr = (w[0] - U * u11, w[1] - U * u21, w[2] - U * u31)
    return w, wr


def manual_computer_step(s, f_xi, f_eta, Vz, h, tau, a, e2, U):
    """u_ij(k+1), V(k+1) of the printed scheme, fed accelerations (f_xi, f_eta)."""
    u11, u21, u31, u12, u22, u32, Vxi, Veta = s
    w, (wx, wy, wz) = manual_rates(s, h, a, e2, U)
    RE = (a + h) / math.sqrt(1 - e2 * u31**2)
    W_xi = w[1] * Vz - w[2] * Veta
    W_eta = w[2] * Vxi - w[0] * Vz
    g_xi = U**2 * RE * u31 * u11
    g_eta = U**2 * RE * u31 * u21
    return [u11 + tau * (wz * u21 - wy * u31),
            u21 + tau * (wx * u31 - wz * u11),
            u31 + tau * (wy * u11 - wx * u21),
            u12 + tau * (wz * u22 - wy * u32),
            u22 + tau * (wx * u32 - wz * u12),
            u32 + tau * (wy * u12 - wx * u22),
            Vxi + tau * (f_xi - W_xi + g_xi),
            Veta + tau * (f_eta - W_eta + g_eta)]


def manual_run(x0, xr0, inputs, tau, n, a, e2, U, drift, bias):
    """Step the ideal and real schemes n times; inputs (a_xi, a_eta, a_zeta, V_zeta, h)."""
    x, xr = list(x0), list(xr0)
    for k in range(n):
        a_xi, a_eta, a_zeta, Vz, h = inputs[:, k]
        ax, ay, az = xr[8:]
        # accelerometers on the misaligned platform (printed a_x, a_y) + constant error Δa
        a_x = a_xi + a_eta * az - a_zeta * ay + bias
        a_y = a_eta - a_xi * az + a_zeta * ax + bias
        w, _ = manual_rates(x, h, a, e2, U)
        wc, _ = manual_rates(xr[:8], h, a, e2, U)
        dw = [wc[i] - w[i] for i in range(3)]
        alpha = [ax + tau * (-w[1] * az + w[2] * ay + dw[0] + drift),
                 ay + tau * (w[0] * az - w[2] * ax + dw[1] + drift),
                 az + tau * (-w[0] * ay + w[1] * ax + dw[2] + drift)]
        xr = manual_computer_step(xr[:8], a_x, a_y, Vz, h, tau, a, e2, U) + alpha
        x = manual_computer_step(x, a_xi, a_eta, Vz, h, tau, a, e2, U)
    return np.array(x), np.array(xr)


def test_rectangle_method_is_the_manuals_difference_scheme(orthodromic):
    legs = [tr.Leg(200.0, 280.0, 60 * DEG, 2500.0), tr.Leg(200.0, 200.0, -90 * DEG, 500.0)]
    profile = tr.manoeuvre_profile(55 * DEG, 37 * DEG, 30 * DEG, 200.0, legs, h=500.0)
    tau, n = 0.5, 800
    traj = tr.trajectory(orthodromic, profile, n * tau, tau)
    drift, bias = 0.5 * DEG / 3600, 2e-3  # large on purpose: exercise every term
    sources = dict(gyro_drift_x=drift, gyro_drift_y=drift, gyro_drift_z=drift,
                   accel_bias_x=bias, accel_bias_y=bias, initial_tilt_x=2e-3,
                   initial_tilt_y=-1e-3, initial_azimuth_error=3e-3)
    # the manual's scheme has the manual's small-angle platform matrix
    sim = simulate(orthodromic, traj, sources, method="euler", parts=("real",),
                   platform="small_angle")
    a, e2, U = traj.parameters
    xr0 = np.concatenate([traj.truth[:, 0], [2e-3, -1e-3, 3e-3]])
    x_manual, xr_manual = manual_run(traj.truth[:, 0], xr0, traj.inputs, tau, n, a, e2, U,
                                     drift, bias)
    x_lib, xr_lib = sim.ideal[:, -1, 0], sim.real[:, -1, 0]
    # same scheme, same order of steps: only rounding differs
    np.testing.assert_allclose(x_lib[:6], x_manual[:6], rtol=0, atol=1e-13)
    np.testing.assert_allclose(x_lib[6:], x_manual[6:], rtol=1e-13)
    np.testing.assert_allclose(xr_lib[:6], xr_manual[:6], rtol=0, atol=1e-13)
    np.testing.assert_allclose(xr_lib[6:8], xr_manual[6:8], rtol=1e-12)
    np.testing.assert_allclose(xr_lib[8:], xr_manual[8:], rtol=1e-10)
    assert np.abs(xr_lib[8:] - xr0[8:]).max() > 1e-4  # the platform really moved
    # the numpy reference loop gives the same ideal run
    f = lambda z, u: orthodromic.numpy.ideal_rhs(z, u, traj.parameters)  # noqa: E731
    ref = integrate(f, traj.truth[:, 0], traj.inputs, tau, "euler")
    np.testing.assert_allclose(ref[:, -1], x_manual, rtol=1e-13, atol=1e-13)


# --------------------------------------------------------------------------------------
# RK4 order, compiled = reference
# --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def free_motion(orthodromic):
    """Ideal equations with constant inputs and a moving start: smooth, time-invariant."""
    p = orthodromic.parameter_vector()
    c = orthodromic.initial_condition_vector(latitude=40 * DEG, longitude=10 * DEG,
                                             heading=30 * DEG, v_N=150.0, v_E=-80.0)
    u = orthodromic.input_vector(a_zeta=9.8, h=2000.0)
    x0 = orthodromic.initial_state(c, u, p)
    return (lambda z, uu: orthodromic.numpy.ideal_rhs(z, uu, p)), x0, u


def test_rk4_converges_at_fourth_order(free_motion):
    f, x0, u = free_motion
    T = 7200.0

    def final(tau):
        n = round(T / tau)
        inputs = np.repeat(u[:, None], n + 1, axis=1)
        return integrate(f, x0, inputs, tau, "rk4", midpoints=inputs[:, :-1])[:, -1]

    reference = final(5.0)
    errors = [np.abs(final(tau) - reference)[6:].max() for tau in (300.0, 150.0, 75.0)]
    orders = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert all(3.7 < order < 4.3 for order in orders), (errors, orders)


def test_euler_converges_at_first_order(free_motion):
    f, x0, u = free_motion

    def final(tau):
        n = round(1800.0 / tau)
        inputs = np.repeat(u[:, None], n + 1, axis=1)
        return integrate(f, x0, inputs, tau, "euler")[:, -1]

    reference = integrate(f, x0, np.repeat(u[:, None], 1801, axis=1), 1.0, "rk4",
                          midpoints=np.repeat(u[:, None], 1800, axis=1))[:, -1]
    errors = [np.abs(final(tau) - reference)[6:].max() for tau in (20.0, 10.0)]
    assert 0.85 < math.log2(errors[0] / errors[1]) < 1.15


def test_compiled_loops_match_the_reference_loop(orthodromic):
    legs = [tr.Leg(120.0, 260.0, 45 * DEG, 1500.0)]
    traj = tr.trajectory(orthodromic, tr.manoeuvre_profile(30 * DEG, 0.0, 0.0, 200.0, legs),
                         240.0, 1.0)
    f = lambda z, u: orthodromic.numpy.ideal_rhs(z, u, traj.parameters)  # noqa: E731
    for method in ("euler", "rk4"):
        ref = integrate(f, traj.truth[:, 0], traj.inputs, 1.0, method,
                        midpoints=traj.midpoints, record_every=10)
        for jit in (True, False):
            sim = simulate(orthodromic, traj, {}, method=method, parts=(),
                           record_interval=10.0, jit=jit)
            np.testing.assert_allclose(sim.ideal[:, :, 0], ref, rtol=1e-13, atol=1e-13)


def test_vm_fallback_says_so_once(monkeypatch):
    monkeypatch.setattr(integ, "_compiler", lambda: None)
    monkeypatch.setattr(integ, "_NOTICE_GIVEN", False)
    rhs = lambda z, u, w, p: -z  # noqa: E731
    import casadi as ca

    z, u, w, p = ca.SX.sym("z", 2), ca.SX.sym("u", 1), ca.SX.sym("w", 0), ca.SX.sym("p", 0)
    fn = ca.Function("decay", [z, u, w, p], [rhs(z, u, w, p)])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(2):
            loop = integ.CompiledLoop(fn, None, "rk4", 5, 0.1, np.zeros(0),
                                      constant_inputs=np.zeros(1))
            result = loop.run(np.array([1.0, 2.0]), np.zeros(0), 50)
    notices = [c for c in caught if "virtual machine" in str(c.message)]
    assert len(notices) == 1
    # RK4 on ż = −z multiplies by R(h) = 1 − h + h²/2 − h³/6 + h⁴/24 per step
    h = 0.1
    growth = 1 - h + h**2 / 2 - h**3 / 6 + h**4 / 24
    np.testing.assert_allclose(result.states[:, -1, 0], np.array([1.0, 2.0]) * growth**50,
                               rtol=1e-14)
    np.testing.assert_allclose(result.states[0, 1, 0], growth**5, rtol=1e-14)


# --------------------------------------------------------------------------------------
# Exact discretisation (matrix exponential)
# --------------------------------------------------------------------------------------
def test_exact_discretisation_of_a_harmonic_oscillator():
    omega = 2 * np.pi / 5067.0  # Schuler-like
    F = np.array([[0.0, 1.0], [-omega**2, 0.0]])
    G = np.array([[0.0], [1.0]])
    Phi, Gamma = exact_discretisation(F, G, 300.0)
    c, s = np.cos(omega * 300.0), np.sin(omega * 300.0)
    np.testing.assert_allclose(Phi, [[c, s / omega], [-omega * s, c]], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(Gamma[:, 0], [(1 - c) / omega**2, s / omega], rtol=1e-12)


def test_exact_static_linear_run_matches_fine_rk4(orthodromic):
    traj = tr.trajectory(orthodromic, tr.static_profile(45 * DEG, 0.0, 10 * DEG), 6 * 3600.0, 2.0)
    sources = {"gyro_drift_y": 0.01 * DEG / 3600, "accel_bias_x": 1e-4}
    exact = linear_exact(orthodromic, traj, sources, record_interval=600.0)
    rk4 = simulate(orthodromic, traj, sources, method="rk4", record_interval=600.0,
                   parts=("linear",)).linear_errors()
    for k in range(len(exact.names)):
        scale = np.abs(exact.values[k]).max()
        assert np.abs(exact.values[k] - rk4.values[k]).max() <= 1e-8 * scale + 1e-18


# --------------------------------------------------------------------------------------
# Grid checks
# --------------------------------------------------------------------------------------
def test_grid_errors():
    assert step_count(86400.0, 0.01) == 8_640_000
    assert step_count(0.3, 0.1) == 3
    for tau in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(StepError, match="positive"):
            step_count(10.0, tau)
    with pytest.raises(StepError, match="non-negative"):
        step_count(-10.0, 1.0)
    with pytest.raises(StepError, match=r"10\.5 s is not a whole number of steps of 1 s"):
        step_count(10.5, 1.0)
    with pytest.raises(StepError, match="recording"):
        integ.record_stride(7.0, 1.0, 100)
    # a fortnight at 100 Hz runs (was refused at 1e8 steps though memory is streamed);
    # a mistyped step (a day in microseconds: 8.6e10 steps, hours of CPU) is refused
    assert step_count(14 * 86400.0, 0.01) == 120_960_000
    with pytest.raises(StepError, match=r"8\.64e\+10 steps, more than the 1e\+09"):
        step_count(86400.0, 1e-6)
    with pytest.raises(Exception, match="did you mean 'rk4'"):
        integ.check_method("rk5")


@pytest.mark.parametrize(("duration", "step", "count"), [
    ("86400 s", "0.01 s", 8_640_000), ("7 day", "0.01 s", 60_480_000),
    ("3 h", "0.1 s", 108_000), ("0.1 h", "0.1 s", 3_600), ("1e6 s", "0.01 s", 10**8),
    ("24 h", "0.003 s", 28_800_000), ("1 day", "1/3 s", 259_200),
    ("14 day", "0.01 s", 120_960_000), ("7 day", "0.005 s", 120_960_000),
    ("100 day", "0.01 s", 864_000_000), ("10 day", "0.001 s", 864_000_000),
    ("3 day", "0.0003 s", 864_000_000)])
def test_decimal_durations_are_whole_numbers_of_steps(duration, step, count):
    """Durations and steps typed in decimal are whole numbers of steps, whatever the
    rounding of their quotient in binary."""
    from ins_errors.units import parse_quantity

    d = parse_quantity(duration, "s", "d", numbers_are_si=False)
    tau = parse_quantity(step, "s", "s", numbers_are_si=False) if "/" not in step else 1 / 3
    assert step_count(d, tau) == count
    assert integ.record_stride(d, tau, count) == count


def test_a_fraction_of_a_step_is_refused_at_tens_of_millions_of_steps():
    """Seven days at 100 Hz with a duration 0.05 step too long: a relative 1e-9 of the
    count (0.06 step) accepted it and rounded it away; the tolerance is in steps."""
    week = 7 * 86400.0
    for off in (0.0005, -0.0005, 0.00002):  # 0.05, -0.05 and 0.002 of a step of 0.01 s
        with pytest.raises(StepError, match="not a whole number of steps"):
            step_count(week + off, 0.01)
    with pytest.raises(StepError, match="recording interval"):
        integ.record_stride(week + 0.0005, 0.01, 60_480_000)


def test_refused_duration_names_the_nearest_valid_ones(capsys):
    """86400.005 s at 0.01 s is half a step off: one line naming 86400 s and 86400.01 s,
    each of which the command line then accepts."""
    from ins_errors.cli import main

    with pytest.raises(StepError) as refused:
        step_count(86400.005, 0.01)
    message = str(refused.value)
    assert "86400.005 s is not a whole number of steps of 0.01 s" in message
    assert "86400 s or 86400.01 s" in message and "\n" not in message
    for text in ("86400", "86400.01"):
        assert step_count(float(text), 0.01) in (8_640_000, 8_640_001)
    status = main(["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h",
                   "--duration", "86400.005s", "--step", "0.01s"])
    assert status == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "86400 s or 86400.01 s" in lines[0]
