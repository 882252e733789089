"""Model north_pointing: against the report's F, finite differences, textbook physics and
direct (nonlinear) simulation."""

from __future__ import annotations

import numpy as np
import pytest

from ins_errors.errors import DomainError
from ins_errors.models.north_pointing import ellipsoid_parameters
from ins_errors.numeric.model import load_model
from ins_errors.numeric.simulate import simulate
from ins_errors.numeric.trajectories import Trajectory, sampled_profile, trajectory
from ins_errors.symbolic.simplifications import simplification

G0 = 9.80665
R0 = 6_371_000.0
U0 = 7.292115e-5


@pytest.fixture(scope="module")
def model():
    return load_model("north_pointing")


def _static(model, latitude, **overrides):
    x = np.array([0.0, 0.0, latitude, 0.0])
    u = np.zeros(len(model.inputs))
    p = model.parameter_vector(R=R0, g=G0)
    for name, value in overrides.items():  # set in place: a value outside the domain
        p[model.index("parameters", name)] = value  # reaches the evaluators' own check
    return x, u, p


def _static_trajectory(model, latitude, duration, tau, p=None):
    x, u, p0 = _static(model, latitude)
    p = p0 if p is None else p
    c = model.initial_condition_vector(latitude=latitude)
    return Trajectory(model.name, tau, round(duration / tau), x[:, None], u[:, None],
                      u[:, None], p, c, True, "static base")


def test_reduced_static_matrix_is_the_reports(model):
    """The report's printed F (section III), states (dVx, dVy, dL, Qx, Qy, Qz)."""
    L = np.radians(39.0)
    x, u, p = _static(model, L)
    F = model.state_matrix(x, u, p)
    names = [s.name for s in model.error_states]
    for term in simplification("report_reduced").terms:
        F[names.index(term.equation), names.index(term.variable)] = 0.0
    keep = [names.index(n) for n in ("delta_v_E", "delta_v_N", "delta_latitude",
                                     "alpha_E", "alpha_N", "alpha_U")]
    s, c = np.sin(L), np.cos(L)
    report = np.array([
        [0, 0, 0, 0, -G0, 0],
        [0, 0, 0, G0, 0, 0],
        [0, 1 / R0, 0, 0, 0, 0],
        [0, -1 / R0, 0, 0, U0 * s, -U0 * c],
        [1 / R0, 0, -U0 * s, -U0 * s, 0, 0],
        [np.tan(L) / R0, 0, U0 * c, U0 * c, 0, 0],
    ])
    assert np.allclose(F[np.ix_(keep, keep)], report, rtol=1e-12, atol=0)
    # the longitude feeds nothing back (the report keeps it as an output only)
    assert np.all(F[:, names.index("delta_longitude")] == 0)


def test_full_model_has_the_foucault_cross_couplings(model):
    L = np.radians(-33.0)
    x, u, p = _static(model, L)
    F = model.state_matrix(x, u, p)
    names = [s.name for s in model.error_states]
    dvE, dvN = names.index("delta_v_E"), names.index("delta_v_N")
    assert F[dvE, dvN] == pytest.approx(2 * U0 * np.sin(L), rel=1e-12)
    assert F[dvN, dvE] == pytest.approx(-2 * U0 * np.sin(L), rel=1e-12)


def test_matrices_match_finite_differences_on_a_moving_base(model):
    """F = ∂f̃/∂x̃ and G = ∂f̃/∂w at the ideal point, by central differences."""
    x = np.array([180.0, -95.0, np.radians(52.0), np.radians(20.0)])
    u = np.array([0.3, -0.2, 3000.0])
    p = model.parameter_vector(**ellipsoid_parameters("wgs84"))
    n, ne = len(model.states), len(model.error_states)
    xr = np.concatenate([x, np.zeros(ne - n)])
    w = np.zeros(len(model.sources))
    F, G = model.state_matrix(x, u, p), model.source_matrix(x, u, p)
    steps = np.array([1e-3, 1e-3, 1e-8, 1e-8, 1e-7, 1e-7, 1e-7])
    for k in range(ne):
        d = np.zeros(ne)
        d[k] = steps[k]
        column = (model.real_rhs(xr + d, x, u, w, p) - model.real_rhs(xr - d, x, u, w, p))
        assert np.allclose(column / (2 * steps[k]), F[:, k], rtol=1e-6, atol=1e-12), k
    for j in range(len(model.sources)):
        d = np.zeros(len(w))
        d[j] = 1e-6
        column = (model.real_rhs(xr, x, u, w + d, p) - model.real_rhs(xr, x, u, w - d, p))
        assert np.allclose(column / 2e-6, G[:, j], rtol=1e-6, atol=1e-12), j


def test_ellipsoid_radii_are_the_textbook_ones(model):
    """δφ̇ = δv_N/(R_N + h) and the R_E in δλ̇, with R_N, R_E of the WGS-84 ellipsoid."""
    a, f = 6_378_137.0, 1 / 298.257223563
    e2 = 2 * f - f * f
    L, h = np.radians(60.0), 1000.0
    x = np.array([0.0, 0.0, L, 0.0])
    u = np.array([0.0, 0.0, h])
    F = model.state_matrix(x, u, model.parameter_vector(**ellipsoid_parameters("wgs84")))
    RN = a * (1 - e2) / (1 - e2 * np.sin(L) ** 2) ** 1.5
    RE = a / np.sqrt(1 - e2 * np.sin(L) ** 2)
    assert F[2, 1] == pytest.approx(1 / (RN + h), rel=1e-12)
    assert F[3, 0] == pytest.approx(1 / ((RE + h) * np.cos(L)), rel=1e-12)


def test_direct_simulation_shows_schuler_and_bias_tilt(model):
    """Nonlinear real − ideal run: bias tilt peaks at −2∇/g at half a Schuler period; a
    velocity error returns after one Schuler period 2π√(R/g), turned by the Foucault
    angle Ω sin φ·t (so it comes back as 0.1·cos(Ω sin φ T_s))."""
    L = np.radians(39.0)
    schuler = 2 * np.pi * np.sqrt(R0 / G0)
    tau = schuler / 2000
    traj = _static_trajectory(model, L, schuler, tau)
    bias = 1e-4 * G0
    sim = simulate(model, traj, [{"accel_bias_north": bias},
                                 {"initial_velocity_error_north": 0.1}],
                   method="rk4", record_interval=tau * 1000, parts=("real",), jit=False)
    direct = sim.direct_errors()
    tilt = direct["alpha_E"][:, 0]
    # Earth-rate coupling over 42 min perturbs the pure Schuler value at the 1e-2 level
    assert tilt[1] == pytest.approx(-2 * bias / G0, rel=2e-2)
    dvN = direct["delta_v_N"][:, 1]
    foucault = U0 * np.sin(L)
    assert dvN[0] == pytest.approx(0.1, rel=1e-12)
    assert dvN[1] == pytest.approx(-0.1 * np.cos(foucault * schuler / 2), rel=3e-3)
    assert dvN[2] == pytest.approx(0.1 * np.cos(foucault * schuler), rel=3e-3)


@pytest.mark.parametrize("case", ["static", "moving"])
def test_direct_and_linear_runs_agree(model, case):
    """Experiment-size errors: the first-order equations follow the nonlinear difference."""
    sources = {"gyro_drift_north": np.radians(0.1) / 3600, "accel_bias_east": 1e-4 * G0,
               "initial_azimuth_error": np.radians(5 / 60),
               "initial_tilt_east": np.radians(20 / 3600),
               "initial_velocity_error_north": 0.1,
               "initial_latitude_error": np.radians(0.0005)}
    if case == "static":
        traj = _static_trajectory(model, np.radians(39.0), 6 * 3600.0, 5.0)
    else:
        t = np.linspace(0.0, 3 * 3600.0, 40)
        v_N = 150.0 * np.cos(t / 2000.0)
        v_E = 200.0 + 30.0 * np.sin(t / 1500.0)
        profile = sampled_profile(t, v_N, v_E, np.radians(45.0), np.radians(10.0), 0.0,
                                  h=2000.0, frame="geographic")
        traj = trajectory(model, profile, 3 * 3600.0, 5.0)
    scaled = {k: 0.1 * v for k, v in sources.items()}
    sim = simulate(model, traj, [sources, scaled], method="rk4", record_interval=300.0,
                   parts=("real", "linear"), jit=False)
    direct, linear = sim.direct_errors(), sim.linear_errors()
    for name in direct.names:
        gaps = []
        for b in (0, 1):
            d, lin = direct[name][:, b], linear[name][:, b]
            scale = np.max(np.abs(d))
            assert scale > 0, name
            gaps.append(np.max(np.abs(d - lin)) / scale)
        # second order: the largest angle is the azimuth error the north drift builds up,
        # about ε/Ω ≈ 7e-3 rad, so the relative gap is of that size ...
        assert gaps[0] < 2e-2, (case, name, gaps)
        # ... and it shrinks in proportion to the sources (first order is exact)
        assert 0.07 < gaps[1] / gaps[0] < 0.13, (case, name, gaps)


def test_bad_input_gives_one_line_errors(model):
    for latitude in (np.pi / 2, -np.pi / 2):
        x, u, p = _static(model, latitude)
        with pytest.raises(DomainError, match="±90"):
            model.state_matrix(x, u, p)
        with pytest.raises(DomainError, match=r"latitude -?90° is refused.* singular within"):
            model.initial_state(model.initial_condition_vector(latitude=latitude), u, p)
    x, u, p = _static(model, 0.5, R=-R0)
    with pytest.raises(DomainError, match="R must be positive"):
        model.state_matrix(x, u, p)
    x, u, p = _static(model, 0.5, R=0.0)
    with pytest.raises(DomainError, match="R must be positive"):
        model.ideal_rhs(x, u, p)
    for g in (0.0, -9.8):
        x, u, p = _static(model, 0.5, g=g)
        with pytest.raises(DomainError, match="g must be positive"):
            model.source_matrix(x, u, p)
    x, u, p = _static(model, 0.5, ecc2=1.2)
    with pytest.raises(DomainError, match="ecc2"):
        model.state_matrix(x, u, p)
    x, u, p = _static(model, 0.5)
    with pytest.raises(DomainError, match="NaN"):
        model.state_matrix(np.array([0.0, np.nan, 0.5, 0.0]), u, p)
