"""Which state each error source reaches: a table written from the model documentation.

Every other check of the built-in models compares a model with itself (direct vs linear
runs, generated vs symbolic), so a source wired to the wrong axis (``initial_tilt_east``
setting α_N, ``initial_velocity_error_xi`` setting δV_η) passes them all. Here a direct
run of each source alone is read at t = 0:

* an ``initial_*`` source sets the state (or output error) it is named after, by its own
  value, and leaves the other members of that family (platform angles, velocities,
  position) at zero;
* a bias, drift or offset enters the derivative of the state it is named after at t = 0
  (finite difference of the direct run over one short step), and not that of the other
  members of the family.

The tables below are written from the model documentation (module docstrings, source
descriptions, the source documents' axes), not from the code's values. The static bases
are chosen so that the platform axes coincide with named directions (heading 0: ξ and
platform x north, η and y west for the orthodromic trihedron (η = ζ × ξ); NED body
axes x north, y east, z down for the strapdown model).

Two closed forms follow: the Schuler response of an initial velocity error in each
orthodromic channel and that of an initial east or north tilt of the north-pointing
platform (an east tilt α_E gives f_N = +g α_E by f^p = f − α × f, so a north velocity
error of amplitude g α / ω_s).
"""

from __future__ import annotations

import numpy as np
import pytest

import ins_errors
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate
from ins_errors.numeric.trajectories import Profile

DEG = np.pi / 180
U = 7.292115e-5
LAT = 45 * DEG
ANGLE, SPEED, RATE, ACCEL, RATIO, METRES = 1e-4, 0.1, 1e-6, 1e-4, 1e-4, 10.0
WGS84_A, WGS84_E2 = 6_378_137.0, 6.69437999014e-3


def _geographic_rest(lat, heading):
    def commands(t):
        return np.zeros((4, t.size)), np.zeros((4, t.size))

    return Profile("geographic", commands, lat, 0.0, heading, "rest", static=True)


# Families of error quantities: a source named after one member must leave the others.
FAMILIES = {
    "orthodromic": [("alpha_x", "alpha_y", "alpha_z"), ("delta_V_xi", "delta_V_eta"),
                    ("delta_latitude", "delta_longitude", "delta_heading")],
    "north_pointing": [("alpha_E", "alpha_N", "alpha_U"), ("delta_v_E", "delta_v_N"),
                       ("delta_latitude", "delta_longitude")],
    "free_azimuth": [("alpha_x", "alpha_y", "alpha_z"), ("delta_V_x", "delta_V_y"),
                     ("delta_Phi", "delta_Lam", "delta_A")],
    "geodetic_vertical": [("alpha_x", "alpha_y", "alpha_z"), ("delta_W_xi", "delta_W_eta"),
                          ("delta_Phi", "delta_Lam")],
    "strapdown_ned": [("delta_roll", "delta_pitch", "delta_heading"),
                      ("delta_v_N", "delta_v_E", "delta_v_D"),
                      ("delta_latitude", "delta_longitude", "delta_height")],
}

_COS, _SIN = np.cos(LAT), np.sin(LAT)
_RN = WGS84_A * (1 - WGS84_E2) / (1 - WGS84_E2 * _SIN**2) ** 1.5  # textbook radii, h = 0
_RE = WGS84_A / np.sqrt(1 - WGS84_E2 * _SIN**2)
G_NED = 9.8062  # normal gravity at 45°, h = 0 (≈ 9.80620 m/s²), to 1e-4

# source -> (magnitude, {quantity: value at t = 0 per unit of the source}); None: not
# checked (e.g. the absolute velocity at rest depends on the set latitude)
INITIAL = {
    "orthodromic": {
        "initial_tilt_x": (ANGLE, {"alpha_x": 1}),
        "initial_tilt_y": (ANGLE, {"alpha_y": 1}),
        "initial_azimuth_error": (ANGLE, {"alpha_z": 1}),
        "initial_velocity_error_xi": (SPEED, {"delta_V_xi": 1}),
        "initial_velocity_error_eta": (SPEED, {"delta_V_eta": 1}),
        "initial_latitude_error": (ANGLE, {"delta_latitude": 1}),
        "initial_longitude_error": (ANGLE, {"delta_longitude": 1}),
        "initial_heading_error": (ANGLE, {"delta_heading": 1}),
    },
    "north_pointing": {
        "initial_tilt_east": (ANGLE, {"alpha_E": 1}),
        "initial_tilt_north": (ANGLE, {"alpha_N": 1}),
        "initial_azimuth_error": (ANGLE, {"alpha_U": 1}),
        "initial_velocity_error_east": (SPEED, {"delta_v_E": 1}),
        "initial_velocity_error_north": (SPEED, {"delta_v_N": 1}),
        "initial_latitude_error": (ANGLE, {"delta_latitude": 1}),
        "initial_longitude_error": (ANGLE, {"delta_longitude": 1}),
    },
    "free_azimuth": {
        "initial_tilt_x": (ANGLE, {"alpha_x": 1}),
        "initial_tilt_y": (ANGLE, {"alpha_y": 1}),
        "initial_azimuth_error": (ANGLE, {"alpha_z": 1}),
        "initial_A_error": (ANGLE, {"delta_A": 1}),
        "initial_velocity_error_x": (SPEED, {"delta_V_x": 1}),
        "initial_velocity_error_y": (SPEED, {"delta_V_y": 1}),
        "initial_Phi_error": (ANGLE, {"delta_Phi": 1}),
        "initial_Lam_error": (ANGLE, {"delta_Lam": 1}),
    },
    "geodetic_vertical": {
        "initial_tilt_x": (ANGLE, {"alpha_x": 1}),
        "initial_tilt_y": (ANGLE, {"alpha_y": 1}),
        "initial_azimuth_error": (ANGLE, {"alpha_z": 1}),
        "initial_velocity_error_xi": (SPEED, {"delta_W_xi": 1}),
        "initial_velocity_error_eta": (SPEED, {"delta_W_eta": 1}),
        "initial_Phi_error": (ANGLE, {"delta_Phi": 1}),
        "initial_Lam_error": (ANGLE, {"delta_Lam": 1}),
    },
    "strapdown_ned": {
        # level, heading 0: roll, pitch, heading errors are the Euler-angle errors
        "initial_roll_error": (ANGLE, {"delta_roll": 1}),
        "initial_pitch_error": (ANGLE, {"delta_pitch": 1}),
        "initial_heading_error": (ANGLE, {"delta_heading": 1}),
        "initial_velocity_error_N": (SPEED, {"delta_v_N": 1}),
        "initial_velocity_error_E": (SPEED, {"delta_v_E": 1}),
        "initial_velocity_error_D": (SPEED, {"delta_v_D": 1}),
        # position errors in NED metres: δφ = δN / R_N, δλ = δE / (R_E cos φ), δh = −δD
        "initial_position_error_N": (METRES, {"delta_latitude": 1 / _RN}),
        "initial_position_error_E": (METRES, {"delta_longitude": 1 / (_RE * _COS)}),
        "initial_position_error_D": (METRES, {"delta_height": -1}),
    },
}

# source -> (magnitude, {quantity: derivative at t = 0 per unit of the source})
RATES = {
    "orthodromic": {
        # α̇ = α × ω + (ω_cmd − ω) + drift; the correction loop scales ω_cmd, the absolute
        # rate of the trihedron (U cos φ about ξ = north, 0 about η = west, U sin φ up)
        "gyro_drift_x": (RATE, {"alpha_x": 1}),
        "gyro_drift_y": (RATE, {"alpha_y": 1}),
        "gyro_drift_z": (RATE, {"alpha_z": 1}),
        "correction_gain_error_x": (RATIO, {"alpha_x": U * _COS}),
        "correction_gain_error_z": (RATIO, {"alpha_z": U * _SIN}),
        "accel_bias_x": (ACCEL, {"delta_V_xi": 1}),
        "accel_bias_y": (ACCEL, {"delta_V_eta": 1}),
        "velocity_integrator_offset_xi": (ACCEL, {"delta_V_xi": 1}),
        "velocity_integrator_offset_eta": (ACCEL, {"delta_V_eta": 1}),
        # a relative rate o of the trihedron about ξ (north) moves the place east at
        # o·R (north × up = east) along a great circle: λ̇ cos φ = o and the track angle
        # turns as χ̇ = λ̇ sin φ; about η (west): north along the meridian, φ̇ = o
        "position_integrator_offset_xi": (RATE, {"delta_longitude": 1 / _COS,
                                                 "delta_heading": _SIN / _COS,
                                                 "delta_latitude": 0}),
        "position_integrator_offset_eta": (RATE, {"delta_latitude": 1}),
    },
    "north_pointing": {
        "gyro_drift_east": (RATE, {"alpha_E": 1}),
        "gyro_drift_north": (RATE, {"alpha_N": 1}),
        "gyro_drift_up": (RATE, {"alpha_U": 1}),
        "accel_bias_east": (ACCEL, {"delta_v_E": 1}),
        "accel_bias_north": (ACCEL, {"delta_v_N": 1}),
    },
    "free_azimuth": {
        "gyro_drift_x": (RATE, {"alpha_x": 1}),
        "gyro_drift_y": (RATE, {"alpha_y": 1}),
        "gyro_drift_z": (RATE, {"alpha_z": 1}),
        "accel_bias_x": (ACCEL, {"delta_V_x": 1}),
        "accel_bias_y": (ACCEL, {"delta_V_y": 1}),
        "velocity_integrator_offset_x": (ACCEL, {"delta_V_x": 1}),
        "velocity_integrator_offset_y": (ACCEL, {"delta_V_y": 1}),
        "position_integrator_offset_Phi": (RATE, {"delta_Phi": 1}),
        "position_integrator_offset_Lam": (RATE, {"delta_Lam": 1}),
    },
    "geodetic_vertical": {
        "gyro_drift_x": (RATE, {"alpha_x": 1}),
        "gyro_drift_y": (RATE, {"alpha_y": 1}),
        "gyro_drift_z": (RATE, {"alpha_z": 1}),
        "accel_bias_x": (ACCEL, {"delta_W_xi": 1}),
        "accel_bias_y": (ACCEL, {"delta_W_eta": 1}),
    },
    "strapdown_ned": {
        # level at heading 0: body x north, y east, z down; at rest ω^b = (U cos φ, 0,
        # −U sin φ), f^b = (0, 0, −g); ω̃_i = (1 + s_i) ω_i + m_ij ω_j + b_i
        "gyro_bias_x": (RATE, {"delta_roll": 1}),
        "gyro_bias_y": (RATE, {"delta_pitch": 1}),
        "gyro_bias_z": (RATE, {"delta_heading": 1}),
        "gyro_scale_error_x": (RATIO, {"delta_roll": U * _COS}),
        "gyro_scale_error_z": (RATIO, {"delta_heading": -U * _SIN}),
        "gyro_misalignment_xz": (RATIO, {"delta_roll": -U * _SIN}),
        "gyro_misalignment_yx": (RATIO, {"delta_pitch": U * _COS}),
        "gyro_misalignment_zx": (RATIO, {"delta_heading": U * _COS}),
        "accel_bias_x": (ACCEL, {"delta_v_N": 1}),
        "accel_bias_y": (ACCEL, {"delta_v_E": 1}),
        "accel_bias_z": (ACCEL, {"delta_v_D": 1}),
        "accel_scale_error_z": (RATIO, {"delta_v_D": -G_NED}),
        "accel_misalignment_xz": (RATIO, {"delta_v_N": -G_NED}),
        "accel_misalignment_yz": (RATIO, {"delta_v_E": -G_NED}),
    },
}


def _trajectory(model, duration, tau):
    if model.name == "strapdown_ned":
        return st.trajectory(model, st.static(LAT), duration, tau)
    if model.name in ("free_azimuth", "geodetic_vertical"):
        return tr.trajectory(model, _geographic_rest(LAT, 0.0), duration, tau)
    return tr.trajectory(model, tr.static_profile(LAT, 0.0, 0.0), duration, tau)


def _quantities(model, sim) -> dict[str, np.ndarray]:
    """Error states (computed − true, platform angles) and output errors, (R + 1, B)."""
    n = len(model.states)
    e = sim.real.copy()
    e[:n] -= sim.ideal
    out = {s.name: e[k] for k, s in enumerate(model.error_states)}
    direct = sim.direct_errors()
    out.update({name: direct[name] for name in direct.names})
    return out


@pytest.fixture(scope="module", params=list(FAMILIES))
def runs(request):
    """One batch of single-source direct runs over one 0.05-s step, per model."""
    model = ins_errors.load_model(request.param)
    cases = {**INITIAL[model.name], **RATES[model.name]}
    tau = 0.05
    traj = _trajectory(model, tau, tau)
    sim = simulate(model, traj, [{s: m} for s, (m, _) in cases.items()], parts=("real",))
    return model, list(cases), _quantities(model, sim), tau


def _family(model_name, quantity):
    return next(f for f in FAMILIES[model_name] if quantity in f)


def _check(model_name, source, magnitude, expected, got):
    """Expected quantities have their value; the rest of their family stays at zero."""
    scale = max(abs(v) for v in expected.values()) * magnitude
    for quantity, factor in expected.items():
        value = got(quantity)
        assert value == pytest.approx(factor * magnitude, rel=2e-3, abs=1e-3 * scale), (
            source, quantity, value)
        for other in _family(model_name, quantity):
            if other not in expected:
                assert abs(got(other)) < 1e-3 * scale, (source, other, got(other))


def test_every_source_has_an_entry():
    for name in FAMILIES:
        model = ins_errors.load_model(name)
        checked = set(INITIAL[name]) | set(RATES[name])
        initial = {s.name for s in model.sources if s.kind == "initial"}
        assert initial <= checked, initial - checked


def test_initial_sources_set_their_own_state(runs):
    model, names, q, _ = runs
    for source, (magnitude, expected) in INITIAL[model.name].items():
        case = names.index(source)
        _check(model.name, source, magnitude, expected, lambda k, c=case: q[k][0, c])


def test_biases_and_drifts_enter_their_own_state(runs):
    model, names, q, tau = runs
    for source, (magnitude, expected) in RATES[model.name].items():
        case = names.index(source)
        _check(model.name, source, magnitude, expected,
               lambda k, c=case: (q[k][1, c] - q[k][0, c]) / tau)


# --------------------------------------------------------------------------------------
# closed forms: Schuler response of one channel
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("channel", ["xi", "eta"])
def test_orthodromic_initial_velocity_error_is_a_schuler_oscillation_in_its_channel(channel):
    """At the equator, heading 0 (ξ north, η west), δV(0) = v0 in one channel gives
    δV(t) = v0 cos ω_s t there and a position error (v0/ω_s) sin ω_s t along that axis,
    ω_s = √(g/R), 84.4 min; the other channel stays quiet (no Foucault coupling at the
    equator, Earth-rate coupling second order over a quarter period)."""
    model = ins_errors.load_model("orthodromic")
    v0 = 0.1
    tau, period_guess = 2.0, 84.4 * 60
    traj = tr.trajectory(model, tr.static_profile(0.0, 0.0, 0.0), 2400 * tau, tau)
    sim = simulate(model, traj, {f"initial_velocity_error_{channel}": v0}, parts=("real",))
    q = _quantities(model, sim)
    t = sim.times
    a, e2 = model.parameter_vector()[:2]
    g = traj.inputs[2, 0]
    # ξ north: meridian radius a(1 − e²); η west: prime-vertical radius a, at φ = 0
    R = a * (1 - e2) if channel == "xi" else a
    w = np.sqrt(g / R)
    assert 2 * np.pi / w == pytest.approx(period_guess, rel=0.01)
    own, other = (("delta_V_xi", "delta_V_eta") if channel == "xi"
                  else ("delta_V_eta", "delta_V_xi"))
    assert q[own][0, 0] == pytest.approx(v0, rel=1e-12)
    assert q[other][0, 0] == 0.0
    quarter = t <= np.pi / (2 * w)
    np.testing.assert_allclose(q[own][quarter, 0], v0 * np.cos(w * t[quarter]), atol=5e-4 * v0)
    assert np.abs(q[other][quarter, 0]).max() < 1e-3 * v0
    if channel == "xi":  # north, on the meridian radius
        position = q["delta_latitude"][:, 0] * R
        cross = q["delta_longitude"][:, 0] * a
    else:  # west: a negative longitude error
        position = -q["delta_longitude"][:, 0] * R
        cross = q["delta_latitude"][:, 0] * a * (1 - e2)
    amplitude = v0 / w
    assert amplitude == pytest.approx(80.0, rel=0.01)  # 0.1 m/s · 806 s
    np.testing.assert_allclose(position[quarter], amplitude * np.sin(w * t[quarter]),
                               atol=5e-4 * amplitude)  # measured 3e-5
    assert np.abs(cross[quarter]).max() < 1e-3 * amplitude
    # the zero crossing of δV after a quarter Schuler period (84.4 min / 4)
    crossing = t[np.nonzero(np.diff(np.sign(q[own][:, 0])))[0][0]]
    assert crossing == pytest.approx(np.pi / (2 * w), abs=2 * tau)


@pytest.mark.parametrize("axis", ["east", "north"])
def test_north_pointing_initial_tilt_drives_the_crossed_velocity_channel(axis):
    """f^p = f − α × f with f = (0, 0, g): an east tilt α_E gives f_N = +g α_E, a north
    tilt α_N gives f_E = −g α_N. At the equator the tilt then oscillates with the
    Schuler frequency, so the velocity error is ±(g α0/ω_s) sin ω_s t in that channel
    and the other stays near zero over the first quarter period (the Earth rate U
    shifts the frequency by ~U²/(2ω_s²) and couples the channels through α_U = α_E U t,
    a few 1e-3 of the amplitude there)."""
    model = ins_errors.load_model("north_pointing")
    alpha0 = 1e-4
    tau = 2.0
    traj = tr.trajectory(model, tr.static_profile(0.0, 0.0, 0.0), 650 * tau, tau)
    sim = simulate(model, traj, {f"initial_tilt_{axis}": alpha0}, parts=("real",))
    q = _quantities(model, sim)
    t = sim.times
    names = [par.name for par in model.parameters]
    p = model.parameter_vector()
    g, R = p[names.index("g")], p[names.index("R")]
    w = np.sqrt(g / R)
    own, other = ("alpha_E", "alpha_N") if axis == "east" else ("alpha_N", "alpha_E")
    assert q[own][0, 0] == pytest.approx(alpha0, rel=1e-12)
    assert q[other][0, 0] == 0.0
    channel, quiet, sign = (("delta_v_N", "delta_v_E", 1.0) if axis == "east"
                            else ("delta_v_E", "delta_v_N", -1.0))
    amplitude = g * alpha0 / w
    assert amplitude == pytest.approx(alpha0 * 7.9e3, rel=0.01)  # α √(gR): 0.79 m/s
    quarter = t <= np.pi / (2 * w)
    np.testing.assert_allclose(q[channel][quarter, 0],
                               sign * amplitude * np.sin(w * t[quarter]), atol=5e-3 * amplitude)
    np.testing.assert_allclose(q[own][quarter, 0], alpha0 * np.cos(w * t[quarter]),
                               atol=1e-2 * alpha0)  # east: 3.5e-3 (α_U coupling), north: 1e-9
    assert np.abs(q[quiet][quarter, 0]).max() < 1e-3 * amplitude
