"""Covariance propagation against textbook results and Monte Carlo runs."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from scipy.linalg import expm as scipy_expm
from threadpoolctl import threadpool_limits

from ins_errors.analysis import covariance as cv
from ins_errors.analysis import monte_carlo as mc
from ins_errors.errors import InsErrorsError
from ins_errors.numeric import trajectories as tr


def expm(matrices: np.ndarray) -> np.ndarray:
    """SciPy's matrix exponential (of a stack: one by one) with BLAS on one thread: the
    reference computations' matrices are at most 44 × 44, where BLAS threads only burn
    CPU waiting for each other (on a loaded 2-core machine about 10× the work itself)."""
    with threadpool_limits(limits=1, user_api="blas"):
        return scipy_expm(matrices)


PHI = np.radians(50.0)
DEG_H = np.radians(1.0) / 3600.0


@pytest.fixture(scope="module")
def static_3h(orthodromic):
    return cv.static_system(orthodromic, PHI, duration=3 * 3600.0, step=10.0, gravity=9.81)


def _tilt(orthodromic, system, source, sigma):
    fn = cv.state_and_output_functionals(orthodromic, system)
    c = cv.propagate(system, [cv.SourceStatistics(source, "constant", sigma)], fn)
    var = c.variance
    return c.times, np.sqrt(var[:, c.index("alpha_x")] + var[:, c.index("alpha_y")])


def schuler_period(latitude: float = PHI, g: float = 9.81) -> float:
    """2π sqrt(R/g) with R the mean radius of curvature of the Krasovsky ellipsoid, s."""
    a, f = 6378245.0, 1 / 298.3
    e2 = 2 * f - f * f
    s2 = np.sin(latitude) ** 2
    R = np.sqrt(a * (1 - e2) / (1 - e2 * s2) ** 1.5 * a / np.sqrt(1 - e2 * s2))
    return 2 * np.pi * np.sqrt(R / g)


# ------------------------------------------------------------------------------------
# Van Loan discretisation: closed forms
# ------------------------------------------------------------------------------------
def test_van_loan_random_walk_and_double_integrator():
    q, dt = 2.5, 7.0
    # x' = n: var = q t
    Phi, Qd = cv.van_loan(np.zeros((1, 1)), np.array([[q]]), dt)
    assert Phi[0, 0] == pytest.approx(1.0)
    assert Qd[0, 0] == pytest.approx(q * dt, rel=1e-12)
    # x'' = n: var x = q t³/3, cov = q t²/2, var v = q t
    A = np.array([[0.0, 1.0], [0.0, 0.0]])
    _, Qd = cv.van_loan(A, np.array([[0.0, 0.0], [0.0, q]]), dt)
    assert Qd == pytest.approx(np.array([[q * dt**3 / 3, q * dt**2 / 2],
                                         [q * dt**2 / 2, q * dt]]), rel=1e-12)


def test_markov_variance_is_stationary():
    sigma, tau = 3.0, 50.0
    _, Qd = cv.van_loan(np.array([[-1 / tau]]), np.array([[2 * sigma**2 / tau]]), 20.0)
    decay = np.exp(-20.0 / tau)
    assert decay**2 * sigma**2 + Qd[0, 0] == pytest.approx(sigma**2, rel=1e-12)



def test_square_sums_equal_the_closed_form_schuler_variances():
    """Blocked square sums (rank-reduced columns, cache-sized products) against the closed
    form of a Schuler oscillator ẍ = −ω²x + b with random x(0), v(0) and a bias b set by
    two independent sources (collinear columns: one is dropped by the rank reduction),
    plus a functional in tiny units beside one in large units."""
    omega = np.sqrt(9.81 / 6.371e6)
    sx, sv, s1, s2 = 300.0, 0.2, 1e-4, 3e-5
    A = np.array([[0.0, 1.0, 0.0], [-omega**2, 0.0, 1.0], [0.0, 0.0, 0.0]])
    Phi = expm(A)                                 # 1-s step, exact for constant A
    Z0 = np.array([[sx, 0.0, 0.0, 0.0], [0.0, sv, 0.0, 0.0], [0.0, 0.0, s1, s2]])
    C = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1e-9, 0.0, 0.0]])
    assert cv.column_factor(Z0).shape == (3, 3)
    steps = 20_000                                 # about 3.8 Schuler periods
    got = cv.power_sequence(Phi, Z0, C, steps, reduce="square-sum")
    wt = omega * np.arange(steps + 1)
    c, s = np.cos(wt), np.sin(wt)
    bias = s1**2 + s2**2
    var_x = sx**2 * c**2 + sv**2 * s**2 / omega**2 + bias * (1 - c)**2 / omega**4
    var_v = sx**2 * omega**2 * s**2 + sv**2 * c**2 + bias * s**2 / omega**2
    expected = np.stack([var_x, var_v, 1e-18 * var_x], axis=1)
    np.testing.assert_allclose(got / expected.max(0), expected / expected.max(0), rtol=0,
                               atol=1e-9)


def test_square_sums_equal_a_step_by_step_sum():
    """Against the plain definition Σ_m (C Φᵏ Z₀)², one step at a time, on a random
    system whose rows mix scales 1e-6..1e6 and whose columns repeat up to a factor."""
    rng = np.random.default_rng(5)
    N = 6
    Phi = expm(0.05 * rng.normal(size=(N, N)))
    rows = np.logspace(-6, 6, N)[:, None]
    base = rng.normal(size=(N, 3))
    Z0 = rows * np.hstack([base, 2.5 * base[:, :1], -base[:, 1:2]])   # rank 3 of 5
    C = rng.normal(size=(4, N)) / rows.T
    steps = 700
    got = cv.power_sequence(Phi, Z0, C, steps, reduce="square-sum")
    Z, expected = Z0.copy(), []
    for _ in range(steps + 1):
        expected.append(((C @ Z) ** 2).sum(1))
        Z = Phi @ Z
    expected = np.array(expected)
    assert cv.column_factor(Z0).shape == (N, 3)
    np.testing.assert_allclose(got / expected.max(0), expected / expected.max(0), rtol=0,
                               atol=1e-12)

# ------------------------------------------------------------------------------------
# Static base: textbook INS results
# ------------------------------------------------------------------------------------
def test_initial_tilt_vanishes_at_quarter_schuler_period(orthodromic, static_3h):
    times, tilt = _tilt(orthodromic, static_3h, "initial_tilt_x", 1e-4)
    first = times < 0.5 * schuler_period()
    k = np.argmin(tilt[first])
    assert times[k] == pytest.approx(schuler_period() / 4, abs=30.0)
    assert tilt[k] < 0.01 * 1e-4
    assert tilt[0] == pytest.approx(1e-4, rel=1e-12)


def test_bias_induced_tilt_is_twice_bias_over_g(orthodromic, static_3h):
    bias = 1e-4
    times, tilt = _tilt(orthodromic, static_3h, "accel_bias_x", bias)
    first = times < 0.75 * schuler_period()
    k = np.argmax(tilt[first])
    assert times[k] == pytest.approx(schuler_period() / 2, abs=30.0)
    # mean tilt bias/g, Schuler swing of the same size: peak 2 bias/g (Foucault: < 1 %)
    assert tilt[k] == pytest.approx(2 * bias / 9.81, rel=0.01)


def test_azimuth_gyro_drift_drives_azimuth(orthodromic, static_3h):
    fn = cv.state_and_output_functionals(orthodromic, static_3h)
    drift = 0.01 * DEG_H
    c = cv.propagate(static_3h, [cv.SourceStatistics("gyro_drift_z", "constant", drift)], fn)
    k = np.searchsorted(c.times, 3600.0)
    assert c.std[k, c.index("alpha_z")] == pytest.approx(drift * 3600.0, rel=0.01)


def test_white_noise_on_azimuth_gyro_is_an_angle_random_walk(orthodromic, static_3h):
    fn = cv.state_and_output_functionals(orthodromic, static_3h)
    arw = np.radians(0.01) / 60.0              # 0.01 deg/sqrt(h) in rad/sqrt(s)
    c = cv.propagate(static_3h, [cv.SourceStatistics("gyro_drift_z", "white", arw)], fn)
    k = np.searchsorted(c.times, 600.0)        # short time: azimuth nearly uncoupled
    assert c.std[k, c.index("alpha_z")] == pytest.approx(arw * np.sqrt(600.0), rel=0.01)


# ------------------------------------------------------------------------------------
# Fast paths against the general per-step path
# ------------------------------------------------------------------------------------
SOURCES = [
    cv.SourceStatistics("gyro_drift_x", "constant", 0.01 * DEG_H),
    cv.SourceStatistics("accel_bias_y", "constant", 1e-4),
    cv.SourceStatistics("initial_azimuth_error", "constant", np.radians(2 / 60)),
    cv.SourceStatistics("initial_latitude_error", "constant", np.radians(0.5 / 60)),
    cv.SourceStatistics("gyro_drift_z", "white", np.radians(0.01) / 60),
    cv.SourceStatistics("accel_bias_x", "markov", 5e-5, 900.0),
]


def test_blocked_powers_match_per_step_discretisation(orthodromic):
    s1 = cv.static_system(orthodromic, PHI, duration=7200.0, step=20.0)
    K = len(s1.times)
    s2 = dataclasses.replace(s1, F=np.repeat(s1.F[None], K, 0), G=np.repeat(s1.G[None], K, 0),
                             H=np.repeat(s1.H[None], K, 0))
    a = cv.propagate(s1, SOURCES, cv.state_and_output_functionals(orthodromic, s1))
    b = cv.propagate(s2, SOURCES, cv.state_and_output_functionals(orthodromic, s2))
    scale = b.std.max(0)
    meaningful = scale > 1e-15          # some direction cosines carry only round-off
    assert np.max(np.abs(a.std - b.std)[:, meaningful] / scale[meaningful]) < 1e-9
    # totals (reduced-state fast path) equal the sum of the per-source contributions
    total = cv.propagate(s1, SOURCES, cv.state_and_output_functionals(orthodromic, s1),
                         by_source=False)
    assert total.total_only
    assert np.allclose(total.variance, a.variance, rtol=1e-9, atol=1e-12 * a.variance.max())
    # reporting every 6th step = discretising at 6 steps
    c = cv.propagate(s1, SOURCES, cv.state_and_output_functionals(orthodromic, s1),
                     output_every=6)
    assert np.allclose(c.times, a.times[::6])
    assert np.allclose(c.variance, a.variance[::6], rtol=1e-9, atol=1e-12 * a.variance.max())


# ------------------------------------------------------------------------------------
# Monte Carlo: linear model (RK4, no matrix exponential) and direct model
# ------------------------------------------------------------------------------------
def _compare(predicted_std, sample_rms, runs, floor):
    """|RMS/σ − 1| within 4 sampling standard errors wherever σ is not negligible."""
    mask = predicted_std > floor
    ratio = sample_rms[mask] / predicted_std[mask]
    tolerance = 4 * mc.sampling_error(runs)
    assert np.max(np.abs(ratio - 1)) < tolerance, (np.max(np.abs(ratio - 1)), tolerance)


def test_covariance_equals_rms_of_linear_monte_carlo(orthodromic):
    system = cv.static_system(orthodromic, PHI, duration=5400.0, step=60.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    cov = cv.propagate(system, SOURCES, fn)
    runs = 3000
    sample = mc.linear_monte_carlo(system, SOURCES, fn, runs, seed=11, substeps=6)
    _compare(cov.std[1:], sample.rms[1:], runs, 1e-15)   # some cosines: round-off only


def test_covariance_equals_rms_of_direct_runs_at_small_magnitudes(orthodromic):
    constants = [s for s in SOURCES if s.kind == "constant"]
    motion = tr.trajectory(orthodromic, tr.static_profile(PHI), 3600.0, 1.0)
    system = cv.system_from_trajectory(orthodromic, motion, 60.0)
    cov = cv.propagate(system, constants, cv.state_and_output_functionals(orthodromic, system))
    runs = 400
    direct = mc.direct_monte_carlo(orthodromic, motion, constants, runs, seed=5,
                                   method="rk4", record_interval=60.0, workers=1,
                                   progress=False)
    for name in ("alpha_x", "alpha_y", "alpha_z", "delta_latitude", "delta_longitude",
                 "delta_v_N", "delta_v_E"):
        rms = np.sqrt(np.mean(direct[name] ** 2, axis=-1))
        _compare(cov.std[1:, cov.index(name)], rms[1:], runs, 0.0)


def test_moving_trajectory_covariance_matches_direct_runs(orthodromic):
    motion = tr.trajectory(orthodromic, tr.great_circle_profile(PHI, 0.5, np.radians(60),
                                                                250.0), 1800.0, 1.0)
    system = cv.system_from_trajectory(orthodromic, motion, 30.0)
    assert not system.time_invariant
    constants = [s for s in SOURCES if s.kind == "constant"]
    cov = cv.propagate(system, constants, cv.state_and_output_functionals(orthodromic, system))
    runs = 300
    direct = mc.direct_monte_carlo(orthodromic, motion, constants, runs, seed=8,
                                   method="rk4", record_interval=30.0, workers=1,
                                   progress=False)
    for name in ("alpha_x", "alpha_y", "delta_latitude", "delta_longitude", "delta_v_N"):
        rms = np.sqrt(np.mean(direct[name] ** 2, axis=-1))
        _compare(cov.std[1:, cov.index(name)], rms[1:], runs, 0.0)


# ------------------------------------------------------------------------------------
# Bad input
# ------------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, words", [
    ({"name": "gyro_drift_x", "kind": "pink"}, "kind must be one of"),
    ({"name": "gyro_drift_x", "sigma": -1.0}, "sigma"),
    ({"name": "gyro_drift_x", "sigma": float("nan")}, "sigma"),
    ({"name": "gyro_drift_x", "kind": "markov"}, "correlation time"),
])
def test_bad_statistics(kwargs, words):
    with pytest.raises(InsErrorsError, match=words) as info:
        cv.SourceStatistics(**kwargs)
    assert "\n" not in str(info.value)


def test_bad_sources_in_propagation(orthodromic, static_3h):
    fn = cv.state_and_output_functionals(orthodromic, static_3h)
    with pytest.raises(InsErrorsError, match="did you mean 'gyro_drift_x'"):
        cv.propagate(static_3h, [cv.SourceStatistics("gyro_drift_xx")], fn)
    with pytest.raises(InsErrorsError, match="initial error"):
        cv.propagate(static_3h, [cv.SourceStatistics("initial_tilt_x", "white", 1.0)], fn)
    with pytest.raises(InsErrorsError, match="no error sources"):
        cv.propagate(static_3h, [], fn)
    with pytest.raises(InsErrorsError, match="duration"):
        cv.uniform_grid(-1.0, 1.0)


def test_moving_trajectory_noise_matches_linear_monte_carlo(orthodromic):
    """Time-varying F, G with white and Markov noise: Van Loan per step vs RK4 runs."""
    motion = tr.trajectory(orthodromic, tr.great_circle_profile(PHI, 0.5, np.radians(30),
                                                                300.0), 2400.0, 5.0)
    system = cv.system_from_trajectory(orthodromic, motion, 30.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    cov = cv.propagate(system, SOURCES, fn)
    runs = 2000
    sample = mc.linear_monte_carlo(system, SOURCES, fn, runs, seed=21, substeps=6)
    _compare(cov.std[1:], sample.rms[1:], runs, 1e-15)


@pytest.mark.parametrize("kind", ["constant", "markov"])
def test_total_keeps_small_sources_next_to_large_ones(orthodromic, kind):
    """Totals must not drop a source whose SI variance is tiny beside another's (units mix:
    a 0.001 °/h drift next to a 10 m/s velocity error): compared quantity by quantity."""
    system = cv.static_system(orthodromic, PHI, duration=6 * 3600.0, step=60.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    extra = {"tau": 3600.0} if kind == "markov" else {}
    sources = [cv.SourceStatistics("initial_velocity_error_xi", "constant", 10.0),
               cv.SourceStatistics("gyro_drift_x", kind, 0.001 * DEG_H, **extra)]
    each = cv.propagate(system, sources, fn)
    total = cv.propagate(system, sources, fn, by_source=False)
    scale = each.variance.max(axis=0)
    used = scale > 0
    np.testing.assert_allclose(total.variance[:, used] / scale[used],
                               each.variance[:, used] / scale[used], atol=1e-9)
    # the azimuth error comes from the drift alone and must be there
    assert total.variance[-1, total.index("alpha_z")] > 1e-14


def test_single_threaded_blas_gives_the_previous_numbers(orthodromic):
    """propagate() limits BLAS to one thread. Threaded BLAS splits long dot products
    differently, so the last bits may differ: equal to rounding."""
    from ins_errors.analysis import covariance as cv

    system = cv.static_system(orthodromic, np.radians(50.0), duration=7200.0, step=10.0)
    sources = [cv.SourceStatistics(s.name, "constant", 1e-6) for s in orthodromic.sources]
    functionals = cv.state_and_output_functionals(orthodromic, system)
    for by_source in (True, False):
        limited = cv.propagate(system, sources, functionals, by_source=by_source)
        unlimited = cv._propagate(system, sources, functionals, 1, by_source)
        scale = np.abs(unlimited.unit_variances).max(axis=0, keepdims=True)
        np.testing.assert_allclose(limited.unit_variances / np.where(scale > 0, scale, 1),
                                   unlimited.unit_variances / np.where(scale > 0, scale, 1),
                                   rtol=0, atol=1e-13)


def test_moving_base_reduced_exponential_matches_the_augmented_one(orthodromic):
    """Constants only: the 2n-square exponential (Van Loan) gives the transition of the
    (n + m)-square augmented one; the exponentials round differently (their scaling and
    squaring depends on the norm), nothing else."""
    from ins_errors.analysis import covariance as cv
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.linear_system import system_from_trajectory

    profile = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(90), 250.0)
    # half an hour in 60 steps of 30 s: each step is one exponential of each kind (a few
    # ms apiece), compared step by step, so 5 s steps (360 of them) only repeated it
    traj = tr.trajectory(orthodromic, profile, 1800.0, 30.0)
    system = system_from_trajectory(orthodromic, traj)
    everything = cv.state_and_output_functionals(orthodromic, system)
    valued = np.arange(len(orthodromic.sources))
    F = cv._step_matrix(system.F)
    G = cv._step_matrix(system.G)
    Z0 = np.vstack([system.E, np.eye(len(valued))])
    keep = np.arange(len(system.times))
    reduced = cv._moving_sensitivities(system.F, system.G, list(valued),
                                       np.zeros(len(valued)), system.step, Z0,
                                       everything.C_x, everything.C_b, keep)
    # the previous path: exponential of the augmented matrix, state and sources carried
    Phis = expm(cv.augmented_dynamics(F, G, np.zeros(len(valued))) * system.step)
    Z, previous = Z0, []
    for k in keep:
        previous.append(np.hstack([everything.C_x[k], everything.C_b]) @ Z)
        if k < len(Phis):
            Z = Phis[k] @ Z
    previous = np.array(previous)
    # against each source's largest sensitivity: the augmented exponential leaves rounding
    # crumbs (growing to ~1e-7 of it over the run) where the reduced one has exact zeros
    per_source = np.abs(previous).max(axis=(0, 1), keepdims=True)
    np.testing.assert_allclose(reduced / per_source, previous / per_source, rtol=0, atol=1e-6)
    assert np.abs(previous).max() > 1e3  # the sensitivities really grew


def test_moving_base_constants_match_the_per_step_scipy_exponential(orthodromic, monkeypatch):
    """Constants along a great circle at 1 s: the batched series (pieces of 4096 steps,
    here also pieces of 7) against SciPy's expm of [[F, I], [0, 0]] dt step by step with
    the previous per-step loop. The two exponentials agree to ~1e-15 of their norm, so
    the variances agree to 1e-12 of each quantity's largest value; the total-only path
    sums the same squares in the same order as the per-source one, to the last bit."""
    profile = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(90), 250.0)
    traj = tr.trajectory(orthodromic, profile, 1200.0, 1.0)
    system = cv.system_from_trajectory(orthodromic, traj)
    sources = [cv.SourceStatistics(s.name, "constant", 1e-6) for s in orthodromic.sources]
    fn = cv.state_and_output_functionals(orthodromic, system)
    each = cv.propagate(system, sources, fn)
    total = cv.propagate(system, sources, fn, by_source=False)
    assert np.array_equal(total.variance, each.variance)
    # the previous computation
    n, F, G = system.E.shape[0], cv._step_matrix(system.F), cv._step_matrix(system.G)
    block = np.zeros((len(F), 2 * n, 2 * n))
    block[:, :n, :n] = F
    block[:, :n, n:] = np.eye(n)
    exp = expm(block * system.step)
    X, previous = system.E.copy(), []
    for k in range(len(system.times)):
        previous.append(fn.C_x[k] @ X + fn.C_b)
        if k < len(F):
            X = exp[k, :n, :n] @ X + exp[k, :n, n:] @ G[k]
    previous = np.array(previous) ** 2
    scale = previous.max(axis=0, keepdims=True)
    scale[scale == 0] = 1.0
    np.testing.assert_allclose(each.unit_variances / scale, previous / scale, rtol=0,
                               atol=1e-12)
    assert previous.max() > 1e3     # sensitivities really grew (m² per unit source)
    monkeypatch.setattr(cv, "_CHUNK", 7)
    pieces = cv.propagate(system, sources, fn)
    np.testing.assert_allclose(pieces.unit_variances / scale, previous / scale, rtol=0,
                               atol=1e-12)
    every_8 = cv.propagate(system, sources, fn, output_every=8)
    assert np.array_equal(every_8.times, system.times[::8])
    np.testing.assert_allclose(every_8.unit_variances, pieces.unit_variances[::8],
                               rtol=0, atol=0)
    # unevenly spaced outputs (indexed rather than sliced): the same numbers
    valued = list(range(len(sources)))
    Z0 = np.vstack([system.E, np.eye(len(valued))])
    uneven = np.array([0, 5, 6, 7, 600, 1200])
    Ys = cv._moving_sensitivities(system.F, system.G, valued, np.zeros(len(valued)),
                                  system.step, Z0, fn.C_x, fn.C_b, uneven)
    assert np.array_equal(Ys**2, pieces.unit_variances[uneven])


@pytest.mark.parametrize("chunk", [7, 4096])
def test_markov_sensitivities_in_pieces_equal_the_step_by_step_products(orthodromic,
                                                                       monkeypatch, chunk):
    """Augmented sensitivities with a Markov source, carried a piece of steps at a time
    and read at the kept steps in one product per piece, against one step and one read
    at a time with the same transitions: the same products, so the same bits. 70 steps
    in pieces of 7 end a piece exactly at the last step."""
    profile = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(90), 250.0)
    system = cv.system_from_trajectory(orthodromic, tr.trajectory(orthodromic, profile,
                                                                  70.0, 1.0))
    fn = cv.state_and_output_functionals(orthodromic, system)
    cols = [system.source_index(name) for name in ("gyro_drift_x", "accel_bias_x")]
    decay = np.array([0.0, -1.0 / 300.0])
    n = system.E.shape[0]
    Z0 = np.vstack([system.E[:, cols], np.eye(2)])
    C_b = fn.C_b[:, cols]
    monkeypatch.setattr(cv, "_CHUNK", chunk)
    Phis = cv.exponential(cv.augmented_dynamics(cv._step_matrix(system.F),
                                                cv._step_matrix(system.G)[..., cols],
                                                decay), system.step)
    Z, expected = Z0, []
    for k in range(len(system.times)):
        expected.append(np.hstack([fn.C_x[k], C_b]) @ Z)
        if k < len(Phis):
            Z = Phis[k] @ Z
    expected = np.array(expected)
    assert Z.shape == (n + 2, 2) and np.abs(expected).max() > 1.0
    for keep in (np.arange(len(system.times)), np.array([0, 6, 7, 8, 69, 70])):
        Ys = cv._moving_sensitivities(system.F, system.G, cols, decay, system.step, Z0,
                                      fn.C_x, C_b, keep)
        assert np.array_equal(Ys, expected[keep])


def test_moving_base_noise_matches_the_per_step_scipy_exponential(orthodromic, monkeypatch):
    """White gyro and accelerometer noises (one shared transition, carried side by side)
    and a Markov accelerometer noise along a great circle at 1 s: the batched series
    (each noise's column series, augmented Markov transitions) against
    SciPy's expm of the whole Van Loan blocks and augmented matrices one step at a time.
    Per step the two agree to ~1e-15 of the blocks' norm (the series are the closer to
    a 40-digit reference, see test_step_exponential); the variances are sums of large
    terms that cancel, so the per-step rounding shows at ~1e-10 of each quantity's
    largest value after 10 min: the stated tolerance is 1e-9 of it."""
    profile = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(90), 250.0)
    traj = tr.trajectory(orthodromic, profile, 600.0, 1.0)
    system = cv.system_from_trajectory(orthodromic, traj)
    fn = cv.state_and_output_functionals(orthodromic, system)
    sources = [cv.SourceStatistics("gyro_drift_x", "white", 1e-6),
               cv.SourceStatistics("accel_bias_x", "markov", 1e-4, 300.0),
               cv.SourceStatistics("gyro_drift_y", "constant", 1e-7),
               cv.SourceStatistics("accel_bias_y", "white", 1e-5)]
    batched = cv.propagate(system, sources, fn)
    total = cv.propagate(system, sources, fn, by_source=False)
    monkeypatch.setattr(cv, "exponential", lambda M, h: scipy_expm(M * h))  # one BLAS thread

    def scipy_van_loan(A, b, h):       # SciPy, one step and one noise column at a time
        columns = b if b.ndim == 3 else b[..., None]
        pairs = [cv.van_loan(A, c[..., :, None] * c[..., None, :], h)
                 for c in np.moveaxis(columns, -1, 0)]
        Qd = np.stack([Qd for _, Qd in pairs], axis=1)
        return pairs[0][0], (Qd if b.ndim == 3 else Qd[:, 0])

    monkeypatch.setattr(cv, "rank_one_noise_step", scipy_van_loan)
    previous = cv.propagate(system, sources, fn)
    scale = np.abs(previous.unit_variances).max(axis=0, keepdims=True)
    assert np.all(scale[0, :, [0, 1, 3]] > 0)      # every quantity sees the three noises
    scale[scale == 0] = 1.0
    np.testing.assert_allclose(batched.unit_variances / scale,
                               previous.unit_variances / scale, rtol=0, atol=1e-9)
    ref = previous.variance
    np.testing.assert_allclose(total.variance / ref.max(axis=0), ref / ref.max(axis=0),
                               rtol=0, atol=1e-9)


def test_linear_monte_carlo_on_one_blas_thread_gives_the_threaded_numbers(orthodromic,
                                                                          monkeypatch):
    """linear_monte_carlo() limits BLAS to one thread (as propagate does); its products
    are tens of rows deep, so the threaded pool computes the same numbers."""
    from threadpoolctl import threadpool_info

    system = cv.static_system(orthodromic, PHI, duration=1800.0, step=60.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    original = mc._linear_monte_carlo
    limited = mc.linear_monte_carlo(system, SOURCES, fn, 300, seed=3, substeps=2)
    threaded = original(system, SOURCES, fn, 300, 3, 2)
    assert np.array_equal(limited.samples, threaded.samples)
    assert np.abs(limited.samples).max() > 0
    seen = []

    def spy(*args):
        seen.append({p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"})
        return original(*args)

    monkeypatch.setattr(mc, "_linear_monte_carlo", spy)
    mc.linear_monte_carlo(system, SOURCES, fn, 2, seed=3)
    assert seen == [{1}]


def test_noise_columns_on_a_time_varying_system_match_closed_forms():
    """White and Markov columns along a time-varying F, against textbook closed forms
    (not against another run of the propagation):

    * v' = w (white, PSD q): Var v = q t; x' = a(t) v with a(t) = 1 + t/T, so
      x(t) = ∫ w(u) A(u, t) du, A(u, t) = ∫_u^t a = (t − u)(1 + (t + u)/2T) and
      Var x = q ∫_0^t A² du (q t³/3 for a ≡ 1), integrated here as a polynomial;
    * s' = −s/τ_s + w: Var s = q τ_s/2 (1 − e^{−2t/τ_s});
    * y' = m, m first-order Markov of steady 1σ σ_m and correlation time τ_m started
      stationary: Var y = 2 σ_m² τ_m² (t/τ_m − 1 + e^{−t/τ_m}), and Var m = σ_m².
    F is held at the mean of each step's ends (exact for the linear a(t) at the step's
    middle), so the discretisation error is second order in the step."""
    T, tau_s, tau_m, step, duration = 300.0, 200.0, 150.0, 1.0, 600.0
    times = np.arange(0.0, duration + step / 2, step)
    K = len(times)
    F = np.zeros((K, 4, 4))  # states x, v, s, y
    F[:, 0, 1] = 1 + times / T
    F[:, 2, 2] = -1 / tau_s
    G = np.zeros((K, 4, 2))  # sources w (white), m (Markov)
    G[:, 1, 0] = G[:, 2, 0] = 1.0
    G[:, 3, 1] = 1.0
    system = cv.LinearSystem(times, F, G, np.zeros((4, 2)), np.eye(4), ("w", "m"),
                             ("constant", "constant"), np.zeros((4, K)), np.zeros((1, K)),
                             np.zeros(0))
    assert not system.time_invariant
    C_b = np.zeros((5, 2))
    C_b[4, 1] = 1.0
    functionals = cv.Functionals(("x", "v", "s", "y", "m"), ("1",) * 5,
                                 np.vstack([np.eye(4), np.zeros((1, 4))]), C_b)
    q, sigma_m = 2e-3, 0.3
    cov = cv.propagate(system, [cv.SourceStatistics("w", "white", np.sqrt(q)),
                                cv.SourceStatistics("m", "markov", sigma_m, tau_m)],
                       functionals)
    var = cov.variance
    t = times
    P = np.polynomial.polynomial
    var_x = []
    for tk in t:
        # A(u) = (t − u)(1 + (t + u)/2T) = (t + t²/2T) − u − u²/2T
        A = np.array([tk + tk**2 / (2 * T), -1.0, -1.0 / (2 * T)])
        integral = P.polyint(P.polymul(A, A))
        var_x.append(q * P.polyval(tk, integral))
    expected = {
        "x": np.array(var_x),
        "v": q * t,
        "s": q * tau_s / 2 * (1 - np.exp(-2 * t / tau_s)),
        "y": 2 * sigma_m**2 * tau_m**2 * (t / tau_m - 1 + np.exp(-t / tau_m)),
        "m": np.full_like(t, sigma_m**2),
    }
    assert expected["x"][-1] > 2 * q * duration**3 / 3  # a(t) does matter
    # measured: x within 8.3e-4 at the first step (the held F: second order in the step,
    # relative to a variance that starts as t³) and 1.2e-5 after 60 s; the others at
    # rounding (≤ 3e-12)
    for k, name in enumerate(functionals.names):
        np.testing.assert_allclose(var[1:, k], expected[name][1:],
                                   rtol=2e-3 if name == "x" else 1e-9, err_msg=name)
    np.testing.assert_allclose(var[60:, 0], expected["x"][60:], rtol=5e-5)


def test_an_output_that_is_an_error_state_is_listed_once(orthodromic):
    """north_pointing's outputs (latitude, longitude, v_N, v_E) read its error states of
    the same names alone: each output error was listed a second time under the state's
    name (covariance.index found the first). Now once each; orthodromic's outputs, other
    quantities than its states, all stay."""
    from ins_errors.numeric.model import load_model

    model = load_model("north_pointing")
    system = cv.static_system(model, PHI, duration=3600.0, step=60.0)
    fn = cv.state_and_output_functionals(model, system)
    assert fn.names == tuple(s.name for s in model.error_states)
    assert np.array_equal(fn.C_x, np.eye(len(fn.names)))
    system = cv.static_system(orthodromic, PHI, duration=3600.0, step=60.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    assert fn.names == (*(s.name for s in orthodromic.error_states),
                        *(f"delta_{o.name}" for o in orthodromic.outputs))
    assert len(set(fn.names)) == len(fn.names)


# ------------------------------------------------------------------------------------
# Markov sources of a correlation time far shorter than the step
# ------------------------------------------------------------------------------------
def _integrator_system(step: float, duration: float, time_invariant: bool):
    """y' = m (one state) with m a source; functionals y and m."""
    times = np.arange(0.0, duration + step / 2, step)
    K = len(times)
    F, G = np.zeros((1, 1)), np.ones((1, 1))
    if not time_invariant:
        F, G = np.zeros((K, 1, 1)), np.ones((K, 1, 1))
    system = cv.LinearSystem(times, F, G, np.zeros((1, 1)), np.eye(1), ("m",), ("constant",),
                             np.zeros((1, K)), np.zeros((1, K)), np.zeros(0))
    functionals = cv.Functionals(("y", "m"), ("1", "1"), np.array([[1.0], [0.0]]),
                                 np.array([[0.0], [1.0]]))
    return system, functionals


@pytest.mark.parametrize("time_invariant", [True, False])
@pytest.mark.parametrize("tau", [1.0, 1e-2, 1e-6, 1e-9])
def test_markov_source_far_shorter_than_the_step_matches_the_closed_form(time_invariant,
                                                                        tau):
    """The integral of stationary first-order Markov noise (steady 1σ σ, correlation time
    τ) has Var y = 2σ²τ (t − τ(1 − e^{−t/τ})) (textbook closed form) at a 60-s step,
    however short τ is: e^{Δt/τ} = e^{60} … e^{6·10¹⁰} must not enter. Far below the step
    it is white noise of PSD 2σ²τ (Var y = 2σ²τ t, to τ/t)."""
    sigma, step = 0.3, 60.0
    system, functionals = _integrator_system(step, 3600.0, time_invariant)
    assert system.time_invariant is time_invariant
    with warnings.catch_warnings():
        warnings.simplefilter("error")      # the old static path overflowed here
        cov = cv.propagate(system, [cv.SourceStatistics("m", "markov", sigma, tau)],
                           functionals)
    t = cov.times
    var_y = 2 * sigma**2 * tau * (t + tau * np.expm1(-t / tau))
    np.testing.assert_allclose(cov.variance[1:, 0], var_y[1:], rtol=1e-12)
    np.testing.assert_allclose(cov.variance[:, 1], sigma**2, rtol=1e-12)
    if tau <= 1e-6:
        np.testing.assert_allclose(cov.variance[1:, 0], 2 * sigma**2 * tau * t[1:],
                                   rtol=2 * tau / step)
    total = cv.propagate(system, [cv.SourceStatistics("m", "markov", sigma, tau)],
                         functionals, by_source=False)
    np.testing.assert_allclose(total.variance[1:, 0], var_y[1:], rtol=1e-12)


def test_markov_source_of_one_second_at_a_minute_step_matches_a_small_step_reference(
        orthodromic):
    """orthodromic at rest, gyro_drift_x Markov of τ = 1 s on a 60-s grid (the case a
    budget spec reported as 'not limited' after overflowing) against the test's own Van
    Loan (SciPy's expm of the double-size block) at a 60/512-s step, iterated step by
    step: Δt/τ = 0.12 there, where the block's e^{Δt/τ} is harmless."""
    sigma, tau, step = 0.1 * DEG_H, 1.0, 60.0
    system = cv.static_system(orthodromic, PHI, duration=1800.0, step=step)
    fn = cv.state_and_output_functionals(orthodromic, system)
    cov = cv.propagate(system, [cv.SourceStatistics("gyro_drift_x", "markov", sigma, tau)],
                       fn)
    n = system.F.shape[0]
    A = np.zeros((n + 1, n + 1))
    A[:n, :n] = system.F
    A[:n, n] = system.G[:, system.source_index("gyro_drift_x")]
    A[n, n] = -1 / tau
    Q = np.zeros_like(A)
    Q[n, n] = 2 * sigma**2 / tau
    sub = 512
    h = step / sub
    M = np.block([[-A, Q], [np.zeros_like(A), A.T]]) * h
    X = expm(M)
    Phi = X[n + 1:, n + 1:].T
    Qd = Phi @ X[:n + 1, n + 1:]
    P = np.zeros_like(A)
    P[n, n] = sigma**2                      # started stationary, no initial error
    C = fn.C_x
    expected = [np.diag(C @ P[:n, :n] @ C.T)]
    for _ in range(len(system.times) - 1):
        for _ in range(sub):
            P = Phi @ P @ Phi.T + Qd
        expected.append(np.diag(C @ P[:n, :n] @ C.T))
    expected = np.array(expected)
    scale = expected.max(axis=0)
    used = scale > 0
    assert np.all(np.isfinite(cov.variance))
    np.testing.assert_allclose(cov.variance[:, used] / scale[used],
                               expected[:, used] / scale[used], rtol=0, atol=1e-8)
    assert expected[-1, cov.index("alpha_x")] > 0     # it does tilt the platform


@pytest.mark.parametrize("time_invariant", [True, False])
def test_markov_source_white_within_rounding_is_refused_naming_the_white_density(
        time_invariant):
    system, functionals = _integrator_system(60.0, 600.0, time_invariant)
    with pytest.raises(InsErrorsError, match=r"below 2⁻⁵³ of the 60 s step.*kind = 'white' "
                                             r"with density σ·√\(2τ\)") as info:
        cv.propagate(system, [cv.SourceStatistics("m", "markov", 1.0, 1e-300)], functionals)
    assert "\n" not in str(info.value) and "'m'" in str(info.value)


@pytest.mark.parametrize("kinds", [("constant", "white"), ("constant", "markov"),
                                   ("markov", "white")])
def test_linear_monte_carlo_keeps_every_part_of_a_source(orthodromic, kinds):
    """A source listed once per kind (a drift with a constant and a noise part): the linear
    Monte Carlo runs draw every part on the source's column. They had kept one part only
    (a white part zeroed the constant's drive, a Markov start overwrote the constant), so
    their rms came out at a quarter of the covariance's."""
    system = cv.static_system(orthodromic, PHI, duration=4 * 3600.0, step=60.0)
    fn = cv.state_and_output_functionals(orthodromic, system)
    parts = {"constant": cv.SourceStatistics("gyro_drift_z", "constant", 0.01 * DEG_H),
             "white": cv.SourceStatistics("gyro_drift_z", "white", 0.01 * DEG_H * 60),
             "markov": cv.SourceStatistics("gyro_drift_z", "markov", 0.01 * DEG_H,
                                           tau=3600.0)}
    sources = [parts[kind] for kind in kinds]
    cov = cv.propagate(system, sources, fn)
    runs = 1000
    sample = mc.linear_monte_carlo(system, sources, fn, runs, seed=3, substeps=6)
    for part in kinds:  # each part alone reaches a sizeable share of the total
        alone = cv.propagate(system, [parts[part]], fn).variance[-1, cov.index("alpha_z")]
        assert alone > 0.15 * cov.variance[-1, cov.index("alpha_z")], part
    _compare(cov.std[1:], sample.rms[1:], runs, 1e-15)
