"""Exact platform kinematics against an independent rotation computation (scipy).

The generated real-work equations of every platform model resolve the specific force
through the platform's exact rotation and advance its z-y-x angles exactly. Checked
here without the model's formulas: scipy's ``Rotation`` builds the platform attitude
from the angles, the rotation-matrix equation Ċ = C[ω×] − [ω×]C (platform and trihedron
both turning at ω when the computer knows the true state) gives its rate, and scipy turns
the advanced matrix back into angles.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import ins_errors
from ins_errors.errors import DomainError
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate
from tests.helpers import central_difference, random_points

DEG = np.pi / 180
# model -> (specific-force inputs on the trihedron axes x, y, z)
FORCE_INPUTS = {"orthodromic": ("a_xi", "a_eta", "a_zeta"),
                "free_azimuth": ("a_x", "a_y", "a_zeta"),
                "geodetic_vertical": ("a_xi", "a_eta", "a_zeta")}


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _point(model):
    rng = np.random.default_rng(3)
    p = model.parameter_vector()
    c = model.initial_condition_vector(latitude=0.7)
    u = np.zeros(len(model.inputs))
    for k, info in enumerate(model.inputs):
        u[k] = {"m/s**2": rng.uniform(-3, 3), "m": 100.0}.get(info.unit, 0.0)
    names = [i.name for i in model.inputs]
    if model.name in FORCE_INPUTS:
        u[names.index(FORCE_INPUTS[model.name][2])] = 9.8
    x = model.initial_state(c, u, p)
    return x, u, p


@pytest.mark.parametrize("name", ["orthodromic", "north_pointing", "free_azimuth",
                                  "geodetic_vertical"])
def test_platform_angle_rates_follow_the_exact_rotation(name):
    model = ins_errors.load_model(name)
    x, u, p = _point(model)
    n = len(model.states)
    w = np.zeros(len(model.sources))
    small = model.numpy.real_rhs_small_angle

    def rates(alpha, fn):
        return fn(np.concatenate([x, alpha]), x, u, w, p)[n:]

    # the trihedron rate ω, read off the small-angle form α̇ = α × ω (computer = truth)
    e = np.eye(3)
    omega = np.array([rates(e[2], small)[1], rates(e[0], small)[2], rates(e[1], small)[0]])
    for alpha in (np.array([0.3, -0.5, 2.0]), np.array([-1.2, 1.1, -2.9])):
        C = Rotation.from_euler("ZYX", alpha[::-1]).as_matrix()  # R_z R_y R_x
        C_dot = C @ _skew(omega) - _skew(omega) @ C
        dt = 1e-4
        after = Rotation.from_matrix(C + dt * C_dot).as_euler("ZYX")[::-1]
        before = Rotation.from_matrix(C - dt * C_dot).as_euler("ZYX")[::-1]
        expected = (after - before) / (2 * dt)
        got = rates(alpha, model.numpy.real_rhs)
        assert np.allclose(got, expected, rtol=1e-5, atol=1e-12 * np.abs(omega).max())


@pytest.mark.parametrize("name", sorted(FORCE_INPUTS))
def test_accelerometers_see_the_exactly_rotated_specific_force(name):
    """The velocity rates differ between the two forms by exactly Cᵀf − (f − α × f)."""
    model = ins_errors.load_model(name)
    x, u, p = _point(model)
    n = len(model.states)
    w = np.zeros(len(model.sources))
    names = [i.name for i in model.inputs]
    f = np.array([u[names.index(k)] for k in FORCE_INPUTS[name]])
    alpha = np.array([0.4, -0.7, 1.9])
    xr = np.concatenate([x, alpha])
    diff = model.numpy.real_rhs(xr, x, u, w, p)[:n] - model.numpy.real_rhs_small_angle(
        xr, x, u, w, p)[:n]
    C = Rotation.from_euler("ZYX", alpha[::-1]).as_matrix()
    expected = (C.T @ f - (f - np.cross(alpha, f)))[:2]
    velocity = [k for k, s in enumerate(model.states) if s.unit == "m/s"][:2]
    assert np.allclose(diff[velocity], expected, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("name", ["orthodromic", "north_pointing", "free_azimuth",
                                  "geodetic_vertical"])
def test_both_platform_forms_have_the_same_first_order(name):
    """Finite-difference Jacobians of the two forms agree at α = 0, errors off."""
    model = ins_errors.load_model(name)
    n, ne = len(model.states), len(model.error_states)
    for x, u, p in random_points(model, 2, seed=11, moving=True) if name == "orthodromic" else [
            _point(model)]:
        at = np.concatenate([x, np.zeros(ne - n)])
        w = np.zeros(len(model.sources))
        steps = np.full(ne, 1e-6)
        jac = [central_difference(lambda z, fn=fn, x=x, u=u, w=w, p=p: fn(z, x, u, w, p),
                                  at, steps)
               for fn in (model.numpy.real_rhs, model.numpy.real_rhs_small_angle)]
        scale = np.abs(jac[1]).max(axis=1, keepdims=True) + 1e-300
        assert np.max(np.abs(jac[0] - jac[1]) / scale) < 1e-6


def test_large_tilt_runs_on_the_exact_platform_and_is_refused_in_small_angles(orthodromic):
    traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG), 600.0, 1.0)
    with pytest.raises(DomainError, match=r"platform angle alpha_x = 80° exceeds 0\.5 rad"):
        simulate(orthodromic, traj, {"initial_tilt_x": 80 * DEG}, record_interval=60.0,
                 platform="small_angle", method="euler")
    sim = simulate(orthodromic, traj, {"initial_tilt_x": 80 * DEG}, record_interval=60.0,
                   parts=("real",), method="euler")
    # a level accelerometer tilted by 80° about x reads g sin 80° along y: after 60 s
    # the η velocity error is close to g sin 80° · 60 s (the Schuler loop has barely
    # turned in 60 s)
    dv = sim.real[7, 1, 0] - sim.ideal[7, 1, 0]
    g = 9.81
    assert abs(dv) == pytest.approx(g * np.sin(80 * DEG) * 60, rel=0.02)
