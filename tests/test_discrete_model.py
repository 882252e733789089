"""The discrete-time model a Kalman filter runs (``ins-errors matrices --discrete``, and
:func:`ins_errors.analysis.discrete_model.discrete_matrices`): Φ_k and Q_k over each
sample step. References, none of them the code under test:

* Φ: SciPy's ``expm(F Δt)`` and a fine classical Runge–Kutta integration of Φ̇ = F Φ;
* Q: a Gauss–Legendre quadrature of ∫ e^{Fs} g q² gᵀ e^{Fᵀs} ds with SciPy's ``expm``; the
  textbook random walks (a gyro's white noise of density N gives an attitude variance
  N² t, an accelerometer's a velocity variance N² t, while t is short against the
  Schuler and Earth periods); the discrete Gauss–Markov variance σ²(1 − e^{−2Δt/τ});
* P_{k+1} = Φ P Φᵀ + Q over the samples against the project's covariance propagation
  (:func:`ins_errors.analysis.covariance.propagate`, a series of its own, not Van Loan's
  double-size block) for a white and a Gauss–Markov source on a static base;
* the units: a density typed as on a datasheet against its value in SI worked by hand.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.io import loadmat
from scipy.linalg import expm

from ins_errors.analysis import covariance as cv
from ins_errors.analysis.discrete_model import discrete_matrices, process_noise
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError

BIASES = "gyro_bias_x,gyro_bias_y,gyro_bias_z,accel_bias_x,accel_bias_y,accel_bias_z"
ARW = math.radians(0.003) / 60.0          # 0.003 deg/√h in rad/√s (√h = 60 √s)
VRW = 50e-6 * 9.80665                     # 50 µg/√Hz in m/s²·√s = m/s/√s
SIGMA_Z = math.radians(0.01) / 3600.0     # 0.01 deg/h in rad/s


def _matrices(tmp_path: Path, name: str, *args: str) -> dict[str, np.ndarray]:
    out = tmp_path / name
    assert main(["matrices", "strapdown_ned", "--convention", "phi", *args,
                 "--out", str(out)]) == 0
    if out.suffix == ".mat":
        return {k: v for k, v in loadmat(out).items() if not k.startswith("__")}
    with np.load(out) as data:
        return {k: data[k] for k in data.files}


@pytest.fixture(scope="module")
def static_15(tmp_path_factory):
    """A 15-state filter on the static base, 1 h every 60 s, with a Gauss–Markov z gyro
    bias far faster than the step (τ = 0.05 s: e^{Δt/τ} = e^{1200} overflows a float)."""
    return _matrices(tmp_path_factory.mktemp("static"), "fg.mat", "--motion", "static",
                     "--hours", "1", "--step", "60s", "--bias-states", BIASES,
                     "--markov", "gyro_bias_z=0.05s", "--markov", "accel_bias_x=20min",
                     "--discrete",
                     "--noise", "gyro_bias_x=0.003deg/rt-hr,gyro_bias_z=0.01deg/h",
                     "--noise", "accel_bias_x=2ug", "--noise", "accel_bias_y=50ug/rtHz")


def _rk4_transition(F: np.ndarray, dt: float, steps: int) -> np.ndarray:
    """Φ(dt) of Φ̇ = F Φ, Φ(0) = I, by the classical Runge–Kutta method."""
    h = dt / steps
    Phi = np.eye(len(F))
    for _ in range(steps):
        k1 = F @ Phi
        k2 = F @ (Phi + 0.5 * h * k1)
        k3 = F @ (Phi + 0.5 * h * k2)
        k4 = F @ (Phi + h * k3)
        Phi = Phi + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    return Phi


def test_phi_is_the_exponential_and_the_solution_of_the_transition_equation(static_15):
    F, Phi, t = static_15["F_static"], static_15["Phi_static"], static_15["t_static"].ravel()
    assert Phi.shape == (60, 15, 15) and static_15["Qd_static"].shape == (60, 15, 15)
    states = [str(s[0]) for s in static_15["states"].ravel()]
    z = states.index("gyro_bias_z")
    for k in (0, 37):
        dt = t[k + 1] - t[k]
        reference = expm(F[k] * dt)
        scale = np.abs(reference).max()
        assert np.abs(Phi[k] - reference).max() < 1e-12 * scale
        # the fast Markov state apart (RK4 needs h ≪ τ there), Runge–Kutta on 6000 steps
        keep = [i for i in range(15) if i != z]
        slow = _rk4_transition(F[k][np.ix_(keep, keep)], dt, 6000)
        assert np.abs(Phi[k][np.ix_(keep, keep)] - slow).max() < 1e-10 * scale
    assert Phi[0, z, z] == 0.0 and np.isfinite(Phi).all()   # e^{-1200}: underflows to 0


def test_q_of_one_noise_is_the_integral_of_the_propagated_noise(tmp_path):
    """One accelerometer's white noise over a 10-minute step, where the Schuler and Earth
    couplings shape Q: against a 48-point Gauss–Legendre quadrature."""
    data = _matrices(tmp_path, "fg.npz", "--motion", "static", "--hours", "1", "--step",
                     "10min", "--discrete", "--noise", "accel_bias_y=50ug/rtHz")
    sources = [str(s) for s in data["sources"]]
    F, g = data["F_static"][0], data["G_static"][0][:, sources.index("accel_bias_y")]
    assert [str(s) for s in data["noise_sources"]] == ["accel_bias_y"]
    assert data["noise_densities"][0] == pytest.approx(VRW, rel=1e-14)
    dt = 600.0
    nodes, weights = np.polynomial.legendre.leggauss(48)
    reference = np.zeros((9, 9))
    for s, w in zip(0.5 * dt * (nodes + 1.0), 0.5 * dt * weights, strict=True):
        y = expm(F * s) @ g * VRW
        reference += w * np.outer(y, y)
    Qd = data["Qd_static"]
    assert np.abs(Qd[3] - reference).max() < 1e-11 * np.abs(reference).max()
    # the couplings matter over this step: the position and the tilt are driven too
    assert reference[6, 6] > 0 and abs(reference[0, 4]) > 1e-6 * np.sqrt(
        reference[0, 0] * reference[4, 4])


def test_white_gyro_and_accelerometer_noises_are_random_walks_over_a_short_step(tmp_path):
    """Textbook: over t ≪ the Schuler period a gyro's white noise N integrates to an
    attitude variance N² t (the φ-angle's Earth-rate term is a rotation and keeps its
    length), an accelerometer's to a velocity variance N² t (+ O((g/R) t²) of it)."""
    data = _matrices(tmp_path, "fg.npz", "--motion", "static", "--hours", "0.1", "--step",
                     "10s", "--discrete", "--noise", "gyro_bias_y=0.003deg/rt-hr")
    Qd = data["Qd_static"]
    assert np.trace(Qd[0][:3, :3]) == pytest.approx(ARW**2 * 10.0, rel=1e-7)
    assert np.trace(Qd[-1][:3, :3]) == pytest.approx(ARW**2 * 10.0, rel=1e-7)
    data = _matrices(tmp_path, "fg2.npz", "--motion", "static", "--hours", "0.1", "--step",
                     "10s", "--discrete", "--noise", "accel_bias_z=50ug/rtHz")
    Qd = data["Qd_static"]
    # next order: the Schuler (and vertical-channel) coupling, of relative size (g/R) t²
    assert np.trace(Qd[0][3:6, 3:6]) == pytest.approx(VRW**2 * 10.0,
                                                      rel=9.8 / 6.371e6 * 10.0**2)
    # a force turns the platform only through the transport rate δv/R: ≪ N² t³/R²
    assert 0.0 <= np.trace(Qd[0][:3, :3]) < VRW**2 * 10.0**3 / 6.371e6**2


def test_a_bias_state_s_white_noise_enters_as_its_bias_does_and_a_markov_state_is_driven(
        static_15, tmp_path):
    """The 15-state file's Q: the Markov states' own variance added in a step is
    σ²(1 − e^{−2Δt/τ}), σ the steady-state 1σ; the x gyro's and y accelerometer's white
    noises, with no Markov noise beside them, give exactly the Q of the 9-state model,
    where these biases are columns of G, and nothing on the bias states."""
    nine = _matrices(tmp_path, "fg9.npz", "--motion", "static", "--hours", "1", "--step",
                     "60s", "--discrete",
                     "--noise", "gyro_bias_x=0.003deg/rt-hr,accel_bias_y=50ug/rtHz")
    Qd, Qd9 = static_15["Qd_static"], nine["Qd_static"]
    states = [str(s[0]) for s in static_15["states"].ravel()]
    z, ax = states.index("gyro_bias_z"), states.index("accel_bias_x")
    assert Qd[0, z, z] == pytest.approx(SIGMA_Z**2, rel=1e-14)   # 1 − e^{−2400}
    sigma_ax = 2e-6 * 9.80665                                     # 2 µg
    assert Qd[0, ax, ax] == pytest.approx(sigma_ax**2 * (1 - math.exp(-2 * 60 / 1200.0)),
                                          rel=1e-12)
    # Q of the white noises alone: the same noises, no Markov σ, in the 15-state file
    white = _matrices(tmp_path, "fg15w.npz", "--motion", "static", "--hours", "1",
                      "--step", "60s", "--bias-states", BIASES, "--discrete",
                      "--noise", "gyro_bias_x=0.003deg/rt-hr,accel_bias_y=50ug/rtHz")
    Qw = white["Qd_static"]
    scale = np.abs(Qd9).max()
    assert np.abs(Qw[:, :9, :9] - Qd9).max() < 1e-12 * scale
    assert not Qw[:, 9:, :].any() and not Qw[:, :, 9:].any()


def _recursion(Phi: np.ndarray, Qd: np.ndarray, P0: np.ndarray) -> np.ndarray:
    P = [P0]
    for A, Q in zip(Phi, Qd, strict=True):
        P.append(A @ P[-1] @ A.T + Q)
    return np.array(P)


@pytest.mark.parametrize("source, sigma", [("gyro_drift_y", 2e-8), ("accel_bias_x", 3e-4)])
def test_the_filter_recursion_is_the_covariance_propagation(orthodromic, source, sigma):
    """P_{k+1} = Φ P Φᵀ + Q with Φ, Q of discrete_matrices gives, sample by sample, the
    variances the project's propagation gives for the same white source (3 h every
    10 s on the static base, past a Schuler period)."""
    system = cv.static_system(orthodromic, math.radians(50.0), duration=3 * 3600.0,
                              step=10.0)
    K, n = len(system.times), system.F.shape[0]
    g = system.G[:, system.source_index(source)]
    dm = discrete_matrices(np.broadcast_to(system.F, (K, n, n)),
                           np.broadcast_to(g[:, None], (K, n, 1)), system.times, [sigma])
    P = _recursion(dm.Phi, dm.Qd, np.zeros((n, n)))
    functionals = cv.state_and_output_functionals(orthodromic, system)
    reference = cv.propagate(system, [cv.SourceStatistics(source, "white", sigma)],
                             functionals).variance[:, :n]
    ours = np.einsum("kii->ki", P)
    assert reference[-1].max() > 0
    _agree(ours, reference, [i.unit for i in orthodromic.error_states],
           [i.name for i in orthodromic.error_states])


def _agree(ours: np.ndarray, reference: np.ndarray, units: list[str], names: list[str]
           ) -> None:
    """Each state's variances within 1e-9 of its largest, or within 1e-12 of the largest
    of the states of its unit (a state the source barely reaches: rounding)."""
    for i, (unit, name) in enumerate(zip(units, names, strict=True)):
        same = [j for j, u in enumerate(units) if u == unit]
        floor = 1e-12 * reference[:, same].max()
        assert np.abs(ours[:, i] - reference[:, i]).max() <= max(
            1e-9 * reference[:, i].max(), floor), name


def test_a_gauss_markov_bias_state_is_the_propagation_s_markov_source(orthodromic):
    """The bias carried as a state ḃ = −b/τ + n, driven by process_noise's σ√(2/τ) and
    started stationary (P₀ = σ²), against propagate's Markov source of σ and τ."""
    system = cv.static_system(orthodromic, math.radians(50.0), duration=3 * 3600.0,
                              step=30.0)
    K, n = len(system.times), system.F.shape[0]
    source, sigma, tau = "gyro_drift_x", 1e-8, 1800.0
    sources = list(system.source_names)
    j = sources.index(source)
    F = np.zeros((n + 1, n + 1))
    F[:n, :n], F[:n, n], F[n, n] = system.F, system.G[:, j], -1.0 / tau
    G = np.zeros((n + 1, len(sources)))
    G[:n] = system.G
    G[:n, j] = 0.0                   # its column moved into F
    states = [*(i.name for i in orthodromic.error_states), source]
    F, G = np.broadcast_to(F, (K, n + 1, n + 1)), np.broadcast_to(G, (K, n + 1, len(sources)))
    Gw, q, names = process_noise(F, G, states, sources, markov_sigma={source: sigma},
                                 markov={source: tau})
    assert names == (f"{source}:markov",) and q[0] == pytest.approx(sigma * math.sqrt(2 / tau))
    dm = discrete_matrices(F, Gw, system.times, q)
    P0 = np.zeros((n + 1, n + 1))
    P0[n, n] = sigma**2
    ours = np.einsum("kii->ki", _recursion(dm.Phi, dm.Qd, P0))
    reference = cv.propagate(system, [cv.SourceStatistics(source, "markov", sigma, tau)],
                             cv.state_and_output_functionals(orthodromic, system)).variance
    _agree(ours[:, :n], reference[:, :n], [i.unit for i in orthodromic.error_states],
           states[:n])
    assert np.abs(ours[:, n] - sigma**2).max() < 1e-12 * sigma**2   # stays stationary


def test_a_moving_base_holds_f_at_the_step_s_start(tmp_path):
    data = _matrices(tmp_path, "fg.npz", "--motion", "manoeuvre", "--hours", "0.2",
                     "--step", "10s", "--discrete", "--noise", "gyro_bias_x=0.003deg/rt-hr")
    F, Phi = data["F_manoeuvre"], data["Phi_manoeuvre"]
    changed = [k for k in range(len(Phi)) if np.abs(F[k + 1] - F[k]).max() > 1e-3]
    assert changed, "the manoeuvre turns"
    for k in changed[:3]:
        start = expm(F[k] * 10.0)
        assert np.abs(Phi[k] - start).max() < 1e-12 * np.abs(start).max()
        assert np.abs(Phi[k] - expm(F[k + 1] * 10.0)).max() > 1e-6


def test_the_mat_and_npz_files_hold_the_same_discrete_model(static_15, tmp_path):
    data = _matrices(tmp_path, "fg.npz", "--motion", "static", "--hours", "1", "--step",
                     "60s", "--bias-states", BIASES, "--markov", "gyro_bias_z=0.05s",
                     "--markov", "accel_bias_x=20min", "--discrete",
                     "--noise", "gyro_bias_x=0.003deg/rt-hr,gyro_bias_z=0.01deg/h",
                     "--noise", "accel_bias_x=2ug", "--noise", "accel_bias_y=50ug/rtHz")
    np.testing.assert_array_equal(data["Phi_static"], static_15["Phi_static"])
    np.testing.assert_array_equal(data["Qd_static"], static_15["Qd_static"])
    np.testing.assert_array_equal(data["noise_densities"],
                                  static_15["noise_densities"].ravel())
    assert [str(s) for s in data["noise_sources"]] == [
        "gyro_bias_x", "accel_bias_y", "gyro_bias_z:markov", "accel_bias_x:markov"]


@pytest.mark.parametrize("args, said", [
    (["--noise", "gyro_bias_x=0.003deg/rt-hr"], "add --discrete"),
    (["--discrete", "--noise", "gyro_bias_q=0.003deg/rt-hr"], "did you mean 'gyro_bias_"),
    (["--discrete", "--noise", "gyro_bias_x=0.003"], "'0.003' has no unit; give a density "
                                                     "in deg/√h"),
    (["--discrete", "--noise", "accel_bias_x=50ug"], "a white-noise density has units of "
                                                     "ug/√Hz, not ug"),
    (["--discrete", "--noise", "accel_bias_x=5m"], "give a density in ug/√Hz"),
    (["--discrete", "--noise", "gyro_bias_x=-0.003deg/rt-hr"], "must be >= 0"),
    (["--discrete", "--noise", "gyro_bias_x=nan deg/rt-hr"], "not a finite number"),
    (["--discrete", "--noise", "gyro_bias_x"], "expected NAME=VALUE"),
    (["--discrete", "--noise", "gyro_bias_x=1deg/rt-hr,gyro_bias_x=2deg/rt-hr"],
     "--noise gyro_bias_x given twice"),
    (["--discrete", "--noise", "initial_roll_error=1arcsec/rtHz"], "is an initial error"),
    (["--discrete", "--bias-states", "gyro_bias_x", "--noise", "gyro_bias_x=0.01deg/h"],
     "'gyro_bias_x' is a random-constant bias state, which no noise drives"),
    (["--discrete", "--bias-states", "gyro_bias_x", "--markov", "gyro_bias_x=300s",
      "--noise", "gyro_bias_x=0.01deg/h,gyro_bias_x=0.02deg/h"],
     "given twice as a steady-state σ"),
    (["--discrete", "--bias-states", "gyro_bias_x", "--markov", "gyro_bias_x=300s",
      "--noise", "gyro_bias_x=2m"], "or, for the Gauss–Markov bias state, its steady-state"),
])
def test_bad_noise_is_one_line_and_exit_2(args, said, tmp_path, capsys):
    out = tmp_path / "x.npz"
    status = main(["matrices", "strapdown_ned", "--motion", "static", "--hours", "0.1",
                   "--step", "10s", *args, "--out", str(out)])
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert status == 2 and len(err) == 1 and said in err[0] and not captured.out, err
    assert not out.exists()


def test_the_api_refuses_bad_arrays_in_one_line():
    F, G, t = np.zeros((3, 2, 2)), np.zeros((3, 2, 1)), np.array([0.0, 1.0, 2.0])
    for args, said in [((F, G, t, [-1.0]), "densities must be >= 0"),
                       ((F, G, t[::-1], [1.0]), "times must increase strictly"),
                       ((F, G[:2], t, [1.0]), "G must have shape (K, n, m) = (3, 2, m)"),
                       ((F, G, t, [1.0, 2.0]), "densities must have shape (m,) = (1,)"),
                       ((F[:1], G[:1], t[:1], [1.0]), "at least 2 samples"),
                       ((F * np.nan, G, t, [1.0]), "F contains NaN")]:
        with pytest.raises(InsErrorsError, match=None) as error:
            discrete_matrices(*args)
        assert said in str(error.value) and "\n" not in str(error.value)
    with pytest.raises(InsErrorsError, match="no Gauss–Markov bias state"):
        process_noise(F, G, ["a", "b"], ["w"], markov_sigma={"w": 1.0})
    with pytest.raises(InsErrorsError, match="unknown error source 'v'"):
        process_noise(F, G, ["a", "b"], ["w"], white={"v": 1.0})
