"""Carried sines and cosines of the platform angles against the C library's.

The exact platform's direct run carries sin α and cos α with the state and rotates them
through each step's angle increment instead of calling ``sin``/``cos``/``tan`` at every
evaluation (``ins_errors.numeric.carried_trig``). Checked here against independent
references: Python's ``math`` (the C library), a plain numpy re-integration of the
scheme, the run with the library calls in the step (the former formulation), and the
textbook platform tilt b/g with the Schuler period 2π√(R/g).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from ins_errors.numeric import carried_trig
from ins_errors.numeric import integrators as integ
from ins_errors.numeric import simulate as simulate_module
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.model import load_model
from ins_errors.numeric.simulate import simulate

DEG = np.pi / 180
PLATFORM_MODELS = ["orthodromic", "north_pointing", "free_azimuth", "geodetic_vertical"]


def _points(model, rng, count=4):
    """Admissible (x, u, p) of any platform model: random latitude and accelerations."""
    p = model.parameter_vector()
    for _ in range(count):
        c = model.initial_condition_vector(latitude=rng.uniform(-1.3, 1.3))
        u = np.array([{"m/s**2": rng.uniform(-3, 3), "m": 100.0}.get(i.unit, 0.0) + 9.8 *
                      (i.name == "a_zeta") for i in model.inputs])
        yield model.initial_state(c, u, p), u, p


def _call(function: ca.Function, *args) -> np.ndarray:
    return np.asarray(function(*args)).ravel()


@pytest.mark.parametrize("name", PLATFORM_MODELS)
def test_rebuilt_real_work_equations_differ_only_in_the_trig_of_the_angles(name):
    model = load_model(name)
    n, ne = len(model.states), len(model.error_states)
    exact = model.casadi.function("real_rhs")
    untouched, none = carried_trig.with_trig_inputs(exact, 0, [])
    rebuilt, used = carried_trig.with_trig_inputs(exact, 0, range(n, ne))
    assert none == []
    assert used == list(range(n, ne))   # all three platform angles enter through trig
    small = model.casadi.function("real_rhs_small_angle")
    assert carried_trig.with_trig_inputs(small, 0, range(n, ne))[1] == []
    rng = np.random.default_rng(7)
    w = rng.normal(0, 1e-4, len(model.sources))
    for x, u, p in _points(model, rng):
        alpha = rng.uniform(-1.2, 1.2, ne - n)
        xr = np.concatenate([x * (1 + 1e-6), alpha])
        reference = _call(exact, xr, x, u, w, p)
        # every other operation rebuilt in the same order: the same bits
        assert np.array_equal(_call(untouched, xr, x, u, w, p, np.zeros(0), np.zeros(0)),
                              reference)
        sines = np.array([math.sin(a) for a in alpha])
        cosines = np.array([math.cos(a) for a in alpha])
        got = _call(rebuilt, xr, x, u, w, p, sines, cosines)
        # tan α is now sin α / cos α: a few units in the last place
        assert np.allclose(got, reference, rtol=1e-14, atol=1e-14 * np.abs(reference).max())
        # the angles' trig is really read from the extra inputs
        assert not np.allclose(_call(rebuilt, xr, x, u, w, p, sines, cosines * 0.9), reference)


@pytest.mark.parametrize("increment", [0.0, 3e-13, -2e-9, 7e-6, -4e-4, 1e-2])
def test_rotation_through_an_increment_gives_the_library_sine_and_cosine(increment):
    s, c, d = ca.SX.sym("s"), ca.SX.sym("c"), ca.SX.sym("d")
    rotated = ca.Function("r", [s, c, d], [ca.vertcat(*carried_trig.rotate(s, c, d))])
    for angle in np.linspace(-3.1, 3.1, 23):
        got = _call(rotated, math.sin(angle), math.cos(angle), increment)
        # the C library's values at the rounded angle + increment, to its rounding
        assert got == pytest.approx([math.sin(angle + increment), math.cos(angle + increment)],
                                    abs=1e-15)


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_compiled_step_with_carried_trig_follows_the_library_trig_scheme(method):
    # a pendulum-like angle α̇ = 0.7 + 0.5 cos α + 0.2 sin α carried with (sin α, cos α)
    z, u, w, p = ca.SX.sym("z", 3), ca.SX.sym("u", 0), ca.SX.sym("w", 0), ca.SX.sym("p", 0)
    rate = 0.7 + 0.5 * z[2] + 0.2 * z[1]
    rhs = ca.Function("rhs", [z, u, w, p], [ca.vertcat(rate, 0, 0)])
    tau, steps = 0.01, 2000   # increments up to 0.012 rad per step
    loop = integ.CompiledLoop(rhs, None, method, 4, tau, np.zeros(0), np.zeros(0),
                              rotations=[(0, 1, 2)])
    result = loop.run(np.array([0.3, math.sin(0.3), math.cos(0.3)]), np.zeros(0), steps)

    def f(a, _u):   # the same scheme with the library's sine and cosine
        return 0.7 + 0.5 * np.cos(a) + 0.2 * np.sin(a)

    reference = integ.integrate(f, np.array([0.3]), np.zeros((0, steps + 1)), tau, method,
                                np.zeros((0, steps)), record_every=4)[0]
    angle, sine, cosine = result.states[:, :, 0]
    assert np.max(np.abs(angle - reference)) < 1e-12   # α̇ ≈ 1 rad/s: 3 turns
    assert np.max(np.abs(sine - np.sin(angle))) < 1e-12
    assert np.max(np.abs(cosine - np.cos(angle))) < 1e-12


def test_compiled_rotation_gives_the_bits_of_the_graph_rotation():
    """The C driver's rotation (carried_trig.ROTATE_C, with its short branch for
    0 < |d| < 2⁻²⁷) against carried_trig.rotate evaluated by CasADi's virtual machine, bit
    for bit, for increments on both sides of the branch and at it, signed zeros,
    subnormals and a sine of -0 (Euler at τ = 1 s with α̇ = u: the increment is u)."""
    edge = 2.0 ** -27
    increments = [-0.0, 0.0, 5e-324, -5e-324, 1e-300, edge, -edge, np.nextafter(edge, 0),
                  -np.nextafter(edge, 0), np.nextafter(edge, 1), 1e-12, -3e-10, 7e-9,
                  8e-9, 2e-8, -1e-7, 1e-6, -2e-4, 0.01, -0.01, 0.0, -0.0]
    z, u, w, p = ca.SX.sym("z", 3), ca.SX.sym("u", 1), ca.SX.sym("w", 0), ca.SX.sym("p", 0)
    rhs = ca.Function("rate", [z, u, w, p], [ca.vertcat(u, 0, 0)])
    angles = np.array([0.0, 0.4, -2.5, 3.0])
    z0 = np.vstack([angles, np.sin(angles), np.cos(angles)])
    z0[1, 0] = -0.0
    stream = np.array([increments * 2])
    runs = [integ.CompiledLoop(rhs, None, "euler", 1, 1.0, np.zeros(0), batch=4, jit=jit,
                               workers=1, rotations=[(0, 1, 2)]).run(z0, np.zeros(0),
                                                                     stream.size, stream)
            for jit in (True, False)]
    compiled, graph = runs[0].states, runs[1].states
    assert np.array_equal(compiled.view(np.int64), graph.view(np.int64))  # zeros' signs too
    # and both follow the library's sine and cosine of the summed angle (to the rounding
    # of 40 steps near |α| = 3; a wrong polynomial term would be off by d² ~ 1e-4)
    assert np.allclose(compiled[1], np.sin(compiled[0]), rtol=0, atol=4e-15)
    assert np.allclose(compiled[2], np.cos(compiled[0]), rtol=0, atol=4e-15)


@pytest.fixture
def library_trig(monkeypatch):
    """Run the direct run's real work with the C library's sin/cos/tan in every step."""
    def clear():
        simulate_module._system.cache_clear()
        simulate_module._loop.cache_clear()

    clear()
    monkeypatch.setattr(carried_trig, "with_trig_inputs", lambda function, *_: (function, []))
    yield
    monkeypatch.undo()
    clear()


def _large_misalignment_run(model, method):
    motion = tr.great_circle_profile(50 * DEG, 30 * DEG, 40 * DEG, 250.0)
    traj = tr.trajectory(model, motion, 3 * 3600.0, 1.0)
    sources = [{"initial_azimuth_error": 170 * DEG, "initial_tilt_x": 20 * DEG,
                "gyro_drift_y": 1 * DEG / 3600},
               {"initial_tilt_y": -40 * DEG, "accel_bias_x": 1e-3}]
    return simulate(model, traj, sources, method, record_interval=60.0, parts=("real",))


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_direct_run_equals_the_library_trig_formulation(orthodromic, method, request):
    carried = _large_misalignment_run(orthodromic, method)
    request.getfixturevalue("library_trig")
    library = _large_misalignment_run(orthodromic, method)
    n = len(orthodromic.states)
    assert not np.array_equal(carried.real, library.real)   # two different computations
    # platform angles (rad) and direction cosines agree to rounding (about 1e-14 after
    # 3 h at 1 s), velocities (m/s, about 1e-10)
    assert np.max(np.abs(carried.real[n:] - library.real[n:])) < 1e-12
    assert np.max(np.abs(carried.real[:6] - library.real[:6])) < 1e-12
    assert np.max(np.abs(carried.real[6:n] - library.real[6:n])) < 1e-8
    # and the run is not trivial: the platform has moved by degrees
    assert np.max(np.abs(carried.real[n:, -1] - carried.real[n:, 0])) > 1 * DEG


def test_exact_platform_tilt_settles_at_bias_over_g_with_the_schuler_period(orthodromic):
    g, radius = 9.81, 6371e3
    period = 2 * np.pi * np.sqrt(radius / g)     # 84.4 min
    traj = tr.trajectory(orthodromic, tr.static_profile(45 * DEG), 2 * 5064.0, 1.0)
    bias = 2e-4 * g
    sim = simulate(orthodromic, traj, {"accel_bias_y": bias}, record_interval=4.0,
                   parts=("real",), method="euler")
    tilt = sim.direct_errors()["alpha_x"][:, 0]
    times = sim.direct_errors().times
    # the tilt swings between 0 and twice its mean: the mean over the run is b/g
    assert abs(np.mean(tilt)) == pytest.approx(bias / g, rel=0.03)
    # the swing returns to its start after one Schuler period
    swing = np.abs(tilt) - np.abs(np.mean(tilt))
    crossings = times[1:][np.diff(np.sign(swing)) != 0]
    assert np.mean(np.diff(crossings)) * 2 == pytest.approx(period, rel=0.02)


def test_carrying_the_trig_leaves_the_other_runs_bit_for_bit(orthodromic):
    motion = tr.great_circle_profile(50 * DEG, 30 * DEG, 40 * DEG, 250.0)
    traj = tr.trajectory(orthodromic, motion, 1800.0, 1.0)
    sources = {"initial_azimuth_error": 1 * DEG, "gyro_drift_x": 0.01 * DEG / 3600}
    together = simulate(orthodromic, traj, sources, record_interval=60.0, method="euler")
    alone = simulate(orthodromic, traj, sources, record_interval=60.0,
                     parts=("linear", "refined"), method="euler")
    for part in ("ideal", "linear", "refined"):
        assert np.array_equal(getattr(together, part), getattr(alone, part)), part
