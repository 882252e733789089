"""The NED strapdown model against textbook relations (not against its own output).

Oracles: the Schuler period 84.4 min, the Foucault split 2 U sin φ and the Earth period
(eigenvalues of F on a static base); an accelerometer bias tilts the computed frame by
b/g (pitch error oscillating between 0 and 2b/g over a Schuler period, at the equator
where there is no Foucault rotation); an east gyro drift ε is held in equilibrium by the
gyrocompassing heading error ε/(U cos φ); an undamped vertical channel grows as
cosh(t/τ) with τ = √(R/2g). The φ- and ψ-angle forms of Titterton & Weston / Benson are
recovered by the convention maps, and the modified velocity error of Scherzinger & Reid
removes the specific force from the velocity-error equation. The true IMU signals solve
the ideal-work equations; direct and linear runs agree at small errors.
"""

from __future__ import annotations

import numpy as np
import pytest

import ins_errors
from ins_errors.models import strapdown_conventions as sc
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric.compare import compare
from ins_errors.numeric.integrators import integrate
from ins_errors.numeric.simulate import simulate

U = 7.292115e-5
G0 = 9.80665
R0 = 6_371_000.0  # mean Earth radius of the textbook relations, m
DEG_H = np.radians(1.0) / 3600.0


@pytest.fixture(scope="module")
def model():
    return ins_errors.load_model("strapdown_ned")


def static_point(model, lat, heading=0.0):
    p = model.parameter_vector()
    trajectory = st.trajectory(model, st.static(lat, heading=heading), 1.0, 1.0)
    return trajectory.truth[:, 0], trajectory.inputs[:, 0], p


def test_static_base_periods_are_the_textbook_ones(model):
    lat = np.radians(45.0)
    x, u, p = static_point(model, lat)
    assert np.abs(model.ideal_rhs(x, u, p)).max() < 1e-12  # at rest
    eig = np.linalg.eigvals(model.state_matrix(x, u, p))
    oscillating = np.sort(eig.imag[eig.imag > 1e-9])
    earth, slow, fast = oscillating
    assert earth == pytest.approx(U, rel=1e-6)  # the Earth (24 h) mode
    schuler = (slow + fast) / 2
    assert 2 * np.pi / schuler / 60 == pytest.approx(84.4, rel=5e-3)
    assert fast - slow == pytest.approx(2 * U * np.sin(lat), rel=1e-2)  # Foucault split
    growing = eig.real.max()
    assert growing == pytest.approx(np.sqrt(2 * G0 / R0), rel=1e-2)  # vertical channel


def test_true_imu_signals_solve_the_ideal_equations(model):
    flight = st.manoeuvre(np.radians(50), np.radians(30), np.radians(90), 150.0, [
        st.Leg(40.0, 200.0, np.radians(60.0), 500.0), st.Leg(40.0, 180.0, np.radians(-90.0))])
    traj = st.trajectory(model, flight, 120.0, 0.05)
    p = traj.parameters
    inputs, mid = traj.full_inputs()
    z = integrate(lambda s, v: model.numpy.ideal_rhs(s, v, p), traj.truth[:, 0], inputs,
                  traj.tau, "rk4", mid, record_every=40)
    truth = traj.truth[:, ::40]
    assert np.abs(z[:4] - truth[:4]).max() < 1e-9  # quaternion
    assert np.abs(z[4:7] - truth[4:7]).max() < 1e-6  # m/s
    assert np.abs(z[9] - truth[9]).max() < 1e-5  # m
    # the manoeuvre really manoeuvres: bank, climb and turn rates in the body signals
    assert np.abs(traj.inputs[2]).max() > 0.02 and np.abs(traj.inputs[5] + G0).max() > 1.0


def damped_parameters(model, period=600.0, damping=0.7):
    """Parameters with the vertical loop of natural frequency 2π/period and the damping."""
    w0 = 2 * np.pi / period
    return model.parameter_vector(k_h1=2 * damping * w0, k_h2=w0**2 + 2 * G0 / R0)


def test_accelerometer_bias_tilts_by_b_over_g(model):
    b = 100e-6 * G0
    traj = st.trajectory(model, st.static(0.0), 5100.0, 1.0)
    sim = simulate(model, traj, {"accel_bias_x": b}, method="rk4", parts=("real",),
                   record_interval=10.0)
    pitch = sim.direct_errors()["delta_pitch"][:, 0]
    # the computed frame levels on the apparent gravity: pitch error (b/g)(1 − cos ω_s t)
    assert np.abs(pitch).max() == pytest.approx(2 * b / G0, rel=1e-2)
    assert np.abs(pitch[: 5064 // 10]).mean() == pytest.approx(b / G0, rel=2e-2)


def test_gyrocompass_heading_error_balances_an_east_drift(model):
    lat, eps = np.radians(45.0), 0.01 * DEG_H
    # damped vertical channel: the undamped one amplifies second-order terms by e^12.6
    traj = st.trajectory(model, st.static(lat), 7200.0, 2.0, p=damped_parameters(model))
    heading_error = eps / (U * np.cos(lat))
    cases = [{"gyro_bias_y": eps, "initial_heading_error": -heading_error},
             {"gyro_bias_y": eps}, {"gyro_bias_y": eps, "initial_heading_error": heading_error}]
    errors = simulate(model, traj, cases, method="rk4", parts=("real",),
                      record_interval=60.0).direct_errors()
    speed = np.hypot(errors["delta_v_N"], errors["delta_v_E"]).max(axis=0)
    assert speed[0] < 1e-3 * speed[1]  # equilibrium: no velocity error grows
    assert speed[2] > speed[1]  # the other sign doubles the effective drift


def test_vertical_channel_diverges_with_time_constant(model):
    lat = np.radians(45.0)
    traj = st.trajectory(model, st.static(lat), 1200.0, 1.0)
    height = simulate(model, traj, {"initial_position_error_D": -1.0}, method="rk4",
                      parts=("real",), record_interval=100.0).direct_errors()["delta_height"][:, 0]
    t = np.arange(height.size) * 100.0
    tau_v = np.sqrt(R0 / (2 * G0))
    np.testing.assert_allclose(height, np.cosh(t / tau_v), rtol=2e-2)
    # a damping loop of natural frequency w0 and damping 0.7 holds it
    damped = st.trajectory(model, st.static(lat), 1200.0, 1.0,
                           p=damped_parameters(model, period=300.0))
    held = simulate(model, damped, {"initial_position_error_D": -1.0}, method="rk4",
                    parts=("real",), record_interval=100.0).direct_errors()["delta_height"]
    assert np.abs(held[-1]).max() < 0.05


def test_phi_and_psi_conventions_are_the_textbook_forms(model):
    lat = np.radians(45.0)
    x, u, p = static_point(model, lat)
    F, G = sc.convention_matrices(model, "phi", x, u, p)
    names = sc.state_names("phi")
    i = {n: k for k, n in enumerate(names)}
    att = [i["phi_N"], i["phi_E"], i["phi_D"]]
    Om = np.array([U * np.cos(lat), 0.0, -U * np.sin(lat)])
    skew = np.array([[0, -Om[2], Om[1]], [Om[2], 0, -Om[0]], [-Om[1], Om[0], 0]])
    np.testing.assert_allclose(F[np.ix_(att, att)], -skew, atol=1e-12)  # φ̇ = −Ω × φ ...
    gyro = [model.index("sources", f"gyro_bias_{a}") for a in "xyz"]
    np.testing.assert_allclose(G[np.ix_(att, gyro)], -np.eye(3), atol=1e-12)  # ... − C ε
    g = -u[5]
    assert F[i["dv_N"], i["phi_E"]] == pytest.approx(g) and F[i["dv_E"], i["phi_N"]] == \
        pytest.approx(-g)  # δv̇ = f × φ with f = (0, 0, −g)
    assert F[i["dv_D"], i["dr_D"]] == pytest.approx(2 * G0 / R0, rel=1e-2)
    # ψ-angle: the attitude error equation is free of velocity and position errors, on a
    # moving and turning vehicle too (Benson 1975)
    flight = st.manoeuvre(np.radians(50), 0.0, 0.3, 200.0, [st.Leg(60.0, 220.0, 1.0, 300.0)])
    traj = st.trajectory(model, flight, 60.0, 1.0)
    xm, um = traj.truth[:, 30], traj.inputs[:, 30]
    Fp, _ = sc.convention_matrices(model, "psi", xm, um, traj.parameters)
    Ff, _ = sc.convention_matrices(model, "phi", xm, um, traj.parameters)
    assert np.abs(Fp[:3, 3:]).max() < 1e-15
    assert np.abs(Ff[:3, 3:]).max() > 1e-8  # the φ form is coupled
    assert np.abs(Fp[:3, :3]).max() < 1e-3


def test_modified_velocity_error_removes_the_specific_force(model):
    flight = st.great_circle(np.radians(40), 0.0, 0.5, 250.0, 1000.0)
    traj = st.trajectory(model, flight, 10.0, 1.0)
    x, u, p = traj.truth[:, 5], traj.inputs[:, 5].copy(), traj.parameters
    pushed = u.copy()
    pushed[3:6] += [3.0, -2.0, 4.0]  # a different specific force at the same state
    blocks = {}
    for name, vel in (("phi", "dv"), ("phi_modified", "du")):
        rows = [sc.state_names(name).index(f"{vel}_{c}") for c in "NED"]
        A = [sc.convention_matrices(model, name, x, v, p)[0][np.ix_(rows, range(3))]
             for v in (u, pushed)]
        blocks[name] = A[1] - A[0]
    C = st.euler_matrix(*_euler(x))
    df = C @ np.array([3.0, -2.0, 4.0])
    f_cross = np.array([[0, -df[2], df[1]], [df[2], 0, -df[0]], [-df[1], df[0], 0]])
    np.testing.assert_allclose(blocks["phi"], f_cross, atol=1e-9)  # δv̇ ∋ f × φ
    assert np.abs(blocks["phi_modified"]).max() < 1e-9  # δu̇ has no f (rounding: 1e-11)


def _euler(x):
    q0, q1, q2, q3 = x[:4]
    roll = np.arctan2(2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2)
    pitch = np.arcsin(-2 * (q1 * q3 - q0 * q2))
    heading = np.arctan2(2 * (q1 * q2 + q0 * q3), q0**2 + q1**2 - q2**2 - q3**2)
    return roll, pitch, heading


@pytest.mark.parametrize("motion", ["static", "great circle", "manoeuvre"])
def test_direct_and_linear_agree_over_a_day_at_small_errors(model, motion):
    """Issue 11's figures with every source at once (SMALL_ERRORS), 24 h, coarse steps
    (the 100 Hz runs are in benchmarks/bench_strapdown.py)."""
    from ins_errors.models.strapdown_ned import SMALL_ERRORS

    flight = {"static": st.static(np.radians(45.0), heading=np.radians(30.0)),
              "great circle": st.great_circle(np.radians(50.0), np.radians(30.0),
                                              np.radians(60.0), 250.0, 10_000.0),
              "manoeuvre": st.standard_manoeuvre()}[motion]
    traj = st.trajectory(model, flight, 86400.0, 2.0, p=damped_parameters(model))
    # the asserted ratios come from the main run: no step-doubling or half-magnitude
    # runs for the warnings (tested in test_integration_error.py and test_validity.py)
    [c] = compare(model, traj, [SMALL_ERRORS], method="rk4", record_interval=600.0,
                  integration_error=False, validity_threshold=None)
    assert c.worst_linear.linear_ratio < 1e-3
    assert c.worst_refined.refined_ratio < 1e-5
    assert len(c.excited) == 9


def test_bad_flights_are_one_line_errors(model):
    with pytest.raises(ins_errors.InsErrorsError, match="pole"):
        st.static(np.radians(90.0))
    with pytest.raises(ins_errors.InsErrorsError, match="speed"):
        st.great_circle(0.5, 0.0, 0.0, -5.0)
    with pytest.raises(ins_errors.InsErrorsError, match="whole number of steps"):
        st.trajectory(model, st.static(0.5), 10.0, 0.3)
    with pytest.raises(ins_errors.InsErrorsError, match="convention"):
        sc.convention("phy")


def test_compare_command_flies_strapdown_motions(capsys):
    """The CLI's manoeuvre (a track-frame profile) becomes a strapdown flight."""
    import json

    from ins_errors.cli import main

    status = main(["compare", "strapdown_ned", "--source", "gyro_bias_x=0.01deg/h",
                   "--source", "accel_bias_y=20ug", "--motion", "manoeuvre", "--hours", "0.25",
                   "--step", "0.5s", "--method", "rk4", "--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    (case,) = json.loads(out)["cases"]
    assert case["worst_linear_ratio"] < 1e-3 and case["worst_refined_ratio"] < 1e-5
    heading = next(m for m in case["metrics"] if m["quantity"] == "delta_heading")
    assert heading["excited"]


def _mapped_and_convention_runs(model, tau, names):
    """Relative differences (attitude, velocity, position) at the end of a 40-s turning
    climb between T(x) e of the model's linear run and the convention runs, both with
    Heun's scheme of step tau."""
    flight = st.manoeuvre(np.radians(50), 0.0, 0.3, 200.0,
                          [st.Leg(40.0, 240.0, np.radians(70.0), 800.0)])
    traj = st.trajectory(model, flight, 40.0, tau)
    p, x, u = traj.parameters, traj.truth, traj.inputs
    w = model.source_vector(gyro_bias_x=1 * DEG_H, accel_bias_y=1e-3, gyro_scale_error_z=1e-4,
                            initial_heading_error=1e-3, initial_position_error_N=10.0)
    e0 = model.initial_error_matrix(traj.initial_conditions, u[:, 0], p) @ w
    F = np.moveaxis(model.state_matrix(x, u, p), -1, 0)
    Gw = np.einsum("ijk,j->ki", model.source_matrix(x, u, p), w)

    def heun(e, A, b):
        for k in range(traj.n_steps):
            de = A[k] @ e + b[k]
            e = e + tau / 2 * (de + A[k + 1] @ (e + tau * de) + b[k + 1])
        return e

    e = heun(e0, F, Gw)
    out = {}
    for name in names:
        F_c, G_c = sc.convention_matrices(model, name, x, u, p)  # all samples at once
        ec = heun(sc.transform_matrix(name, x[:, 0], p) @ e0, np.moveaxis(F_c, -1, 0),
                  np.einsum("ijk,j->ki", G_c, w))
        mapped = sc.transform_matrix(name, x[:, -1], p) @ e
        out[name] = np.array([np.abs(ec[b] - mapped[b]).max() / np.abs(mapped[b]).max()
                              for b in (slice(0, 3), slice(3, 6), slice(6, 9))])
    return out


def test_convention_matrices_of_many_samples_are_those_of_each(model):
    """The batched call (states (10, K)) gives each sample's F_c and G_c of a call per
    sample, to rounding, in every convention and position form."""
    flight = st.manoeuvre(np.radians(50), 0.0, 0.3, 200.0,
                          [st.Leg(20.0, 240.0, np.radians(70.0), 800.0)])
    traj = st.trajectory(model, flight, 20.0, 2.0)
    p, x, u = traj.parameters, traj.truth, traj.inputs
    for name in sc.CONVENTIONS:
        for position in ("ned", "geodetic"):
            F_c, G_c = sc.convention_matrices(model, name, x, u, p, position)
            assert F_c.shape == (9, 9, x.shape[1]) and G_c.shape[::2] == (9, x.shape[1])
            for k in range(x.shape[1]):
                F, G = sc.convention_matrices(model, name, x[:, k], u[:, k], p, position)
                scale = np.abs(F).max() + np.abs(G).max()
                np.testing.assert_allclose(F_c[..., k], F, rtol=0, atol=1e-14 * scale)
                np.testing.assert_allclose(G_c[..., k], G, rtol=0, atol=1e-14 * scale)


def test_convention_models_propagate_the_mapped_errors(model):
    """ė_c = F_c e_c + G_c w along a turning climb gives T(x(t)) e(t) of the model's own
    linear run: the difference is the scheme's O(τ²) error only (it drops fourfold when
    the step halves), so the maps and their rates Ṫ are exact."""
    names = ["phi", "psi", "psi_modified"]
    coarse = _mapped_and_convention_runs(model, 0.2, names)
    fine = _mapped_and_convention_runs(model, 0.1, names)
    for name in names:
        assert np.all(fine[name] < 3e-5), name
        np.testing.assert_allclose(coarse[name] / fine[name], 4.0, rtol=0.1, err_msg=name)
