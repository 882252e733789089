"""Compiled time-invariant loops with the state that never moves written in as numbers.

A static run's ideal work stays exactly at its start (its step returns the same bits);
the compiled loop then bakes those components into the C source as exact numbers and the
compiler folds every operation on them alone (``CompiledLoop._frozen``). The results must
be the general loop's to the last bit: checked against the CasADi virtual machine (which
never freezes anything) and against the compiled loop with freezing switched off.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from ins_errors.numeric import integrators as integ
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate

DEG = np.pi / 180.0


def _toy_loop(jit: bool, batch: int) -> integ.CompiledLoop:
    """a' = w; b' = u (b - 1) (at rest at b = 1); c' = a (still for one step, then
    driven by a); e' = (b - 1) e + (b - 1) / 3 (at rest while b = 1)."""
    z, u, w, p = ca.SX.sym("z", 4), ca.SX.sym("u", 1), ca.SX.sym("w", 1), ca.SX.sym("p", 0)
    a, b, e = z[0], z[1], z[3]
    rhs = ca.Function("toy", [z, u, w, p], [ca.vertcat(w[0], u[0] * (b - 1), a,
                                                       (b - 1) * e + (b - 1) / 3)])
    return integ.CompiledLoop(rhs, None, "rk4", 3, 0.1, np.zeros(0), np.array([0.3]),
                              chunk=4, batch=batch, jit=jit, workers=1)


@pytest.mark.parametrize("shared_e", [True, False])
def test_only_components_at_rest_that_depend_on_components_at_rest_are_frozen(shared_e):
    z0 = np.array([[0.0, 0.0], [1.0, 1.0], [0.25, 0.25], [0.7, 0.7 if shared_e else 0.8]])
    w = np.array([[0.5, -1.5]])
    loop = _toy_loop(True, 2)
    frozen = loop._frozen(loop.start(z0, w))
    # c is unchanged by the first step too (a starts at 0) but a moves: c is not frozen
    assert frozen == (((1, 1.0), (3, 0.7)) if shared_e else ((1, 1.0),))
    compiled = loop.run(z0, w, 60).states
    virtual = _toy_loop(False, 2).run(z0, w, 60).states
    assert np.array_equal(compiled.view(np.int64), virtual.view(np.int64))
    assert np.all(compiled[1] == 1.0) and np.all(compiled[3] == z0[3])
    assert np.all(np.abs(compiled[2, -1] - 0.25) > 0.1)   # c was driven by a


@pytest.mark.parametrize(("method", "platform"), [("euler", "exact"), ("rk4", "exact"),
                                                 ("euler", "small_angle")])
def test_static_runs_equal_the_unfrozen_loop_bit_for_bit(orthodromic, method, platform,
                                                         monkeypatch):
    traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG, 30 * DEG, 20 * DEG),
                         600.0, 0.01)
    cases = [{"gyro_drift_x": 1e-6, "accel_bias_y": 1e-4}, {"initial_tilt_x": 1e-3}]
    seen = []
    original = integ.CompiledLoop._frozen

    def spy(self, carry):
        seen.append(original(self, carry))
        return seen[-1]

    monkeypatch.setattr(integ.CompiledLoop, "_frozen", spy)
    frozen = simulate(orthodromic, traj, cases, method=method, record_interval=1.0,
                      platform=platform)
    n = len(orthodromic.states)
    # the ideal work stays at rest to the last bit: all of it is frozen, nothing else
    assert [i for i, _ in seen[-1]] == list(range(n))
    monkeypatch.setattr(integ.CompiledLoop, "_frozen", lambda self, carry: ())
    general = simulate(orthodromic, traj, cases, method=method, record_interval=1.0,
                       platform=platform)
    for part in ("ideal", "real", "linear", "refined"):
        assert np.array_equal(getattr(frozen, part).view(np.int64),
                              getattr(general, part).view(np.int64)), part
    assert np.abs(frozen.real[n:, -1]).min() > 0   # the error runs did move


def test_library_functions_of_frozen_components_stay_calls(monkeypatch):
    """A frozen component inside sin/cos: the compiler must not evaluate them itself (its
    correctly rounded values may differ in the last bit from the C library's, which the
    general loop and the virtual machine call), so the frozen build keeps the calls."""
    z, u, w, p = ca.SX.sym("z", 3), ca.SX.sym("u", 1), ca.SX.sym("w", 1), ca.SX.sym("p", 0)
    rest = 0.7
    rhs = ca.Function("toy", [z, u, w, p], [ca.vertcat(
        u[0] * (z[0] - rest),                                  # at rest at 0.7
        (ca.sin(z[0]) - np.sin(rest)) * z[1] + w[0] * ca.cos(z[0]) * z[2],
        -ca.tan(z[0]) * z[1])])
    flags = []
    original = integ.compile_source

    def spy(source, options=integ.DEFAULT_FLAGS, **keywords):
        flags.append(tuple(options))
        return original(source, options, **keywords)

    monkeypatch.setattr(integ, "compile_source", spy)
    z0, w0 = np.array([rest, 0.3, -0.2]), np.array([0.05])
    runs = [integ.CompiledLoop(rhs, None, "euler", 2, 0.1, np.zeros(0), np.array([-0.4]),
                               jit=jit).run(z0, w0, 40).states for jit in (True, False)]
    assert "-fno-builtin-sin" in flags[-1] and "-fno-builtin-tan" in flags[-1]
    assert np.array_equal(runs[0].view(np.int64), runs[1].view(np.int64))
    assert np.all(runs[0][0] == rest) and np.ptp(runs[0][1]) > 0.01


def test_a_frozen_zero_keeps_its_sign():
    """Frozen -0.0 and +0.0 are different numbers for the compiled loop (x * -0.0 and
    x * +0.0 differ in sign): one loop object run from each gives each its own bits."""
    z, u, w, p = ca.SX.sym("z", 2), ca.SX.sym("u", 1), ca.SX.sym("w", 1), ca.SX.sym("p", 0)
    rhs = ca.Function("toy", [z, u, w, p], [ca.vertcat(u[0] * z[0], 1.0 / (w[0] * z[0]))])
    loops = [integ.CompiledLoop(rhs, None, "euler", 1, 0.5, np.zeros(0), np.array([2.0]),
                                jit=jit) for jit in (True, False)]
    for zero in (-0.0, 0.0, -0.0):
        runs = [loop.run(np.array([zero, 1.0]), np.array([3.0]), 3).states
                for loop in loops]
        assert np.array_equal(runs[0].view(np.int64), runs[1].view(np.int64))
        assert runs[0][1, -1] == np.copysign(np.inf, zero)   # 1 + 0.5 / (3 * ±0)
        assert np.signbit(runs[0][0, -1]) == np.signbit(zero)


def test_what_a_loop_freezes_is_kept_with_its_library(tmp_path, monkeypatch):
    """The frozen set is found once (it needs the step's graph) and kept as a note in the
    cache folder: a new loop of the same description run from the same states reads it
    back and runs its cached library without building any graph, to the same bits;
    other per-case constants read the same note (they never decide it), other start
    states get their own, and with the notes gone everything is found again."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    z0 = np.array([[0.0, 0.0], [1.0, 1.0], [0.25, 0.25], [0.7, 0.7]])
    w = np.array([[0.5, -1.5]])
    first = _toy_loop(True, 2).run(z0, w, 60).states
    notes = tmp_path / "notes"
    assert len(list(notes.glob("frozen_*"))) == 1

    def no_graph():
        raise AssertionError("the step's graph was built")

    again = _toy_loop(True, 2)
    again._graph = no_graph
    assert again._frozen(again.start(z0, w)) == ((1, 1.0), (3, 0.7))
    assert np.array_equal(again.run(z0, w, 60).states.view(np.int64), first.view(np.int64))
    other_w = again.run(z0, np.array([[0.0, 2.5]]), 60).states
    virtual = _toy_loop(False, 2)
    assert np.array_equal(other_w.view(np.int64),
                          virtual.run(z0, np.array([[0.0, 2.5]]), 60).states.view(np.int64))
    assert len(list(notes.glob("frozen_*"))) == 1
    z1 = z0.copy()
    z1[3, 1] = 0.8   # e differs between the cases: e is no longer frozen
    moved = _toy_loop(True, 2)
    assert moved._frozen(moved.start(z1, w)) == ((1, 1.0),)
    assert len(list(notes.glob("frozen_*"))) == 2
    assert np.array_equal(moved.run(z1, w, 60).states.view(np.int64),
                          virtual.run(z1, w, 60).states.view(np.int64))
    from ins_errors.numeric import cache

    cache.clear(tmp_path)
    assert not notes.exists()
    fresh = _toy_loop(True, 2)
    assert np.array_equal(fresh.run(z0, w, 60).states.view(np.int64), first.view(np.int64))
