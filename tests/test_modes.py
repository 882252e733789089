"""``ins-errors modes``: the static-base modes of every model, against theory.

References (independent of the code under test): the Schuler period 2π√(R/g) (84.4 min
on the Earth), the sidereal day 2π/Ω = 23.93 h, the Foucault split of the symbolic
closed forms (``make derive``'s analysis of north_pointing and orthodromic), the
undamped vertical channel's rate √(2g/R) (e-folding time ≈ 570 s) with g the Somigliana
normal gravity and R the geometric mean of the radii of curvature, both typed here from
their textbook formulas, and the damped vertical loop ḣ = −v_D − k₁ δh,
v̇_D = ... + k₂ δh, whose roots solve s² + k₁ s + (k₂ − 2g/R) = 0.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from ins_errors.analysis.modes import static_modes
from ins_errors.cli import main
from ins_errors.numeric.closed_forms import SPLIT_MODES, closed_form_module, closed_forms
from tests.test_cli_json import strict_json

ROOT = Path(__file__).resolve().parent.parent
SIDEREAL_DAY = 2 * np.pi / 7.292115e-5  # s, 23.934 h
OWN_MODEL = str(ROOT / "examples/own_model/schuler_loop.py")

# WGS-84, typed from the textbook (NIMA TR8350.2)
WGS84_A, WGS84_E2 = 6_378_137.0, 6.69437999014e-3
GAMMA_E, SOMIGLIANA_K = 9.7803253359, 1.93185265241e-3


def _wgs84_schuler_constants(latitude: float) -> tuple[float, float]:
    """(normal gravity at the ellipsoid, √(R_M R_N)) at ``latitude``."""
    s2 = np.sin(latitude) ** 2
    gravity = GAMMA_E * (1 + SOMIGLIANA_K * s2) / np.sqrt(1 - WGS84_E2 * s2)
    prime_vertical = WGS84_A / np.sqrt(1 - WGS84_E2 * s2)
    meridian = WGS84_A * (1 - WGS84_E2) / (1 - WGS84_E2 * s2) ** 1.5
    return gravity, np.sqrt(meridian * prime_vertical)


def _periods(result, prefix: str = "Schuler") -> list[float]:
    return [m.period_s for m in result.modes if m.name.startswith(prefix)
            for _ in range(m.multiplicity)]


@pytest.mark.parametrize("model", ["orthodromic", "north_pointing", "free_azimuth",
                                   "geodetic_vertical", "strapdown_ned", OWN_MODEL])
def test_every_model_has_a_schuler_period_of_84_minutes(model):
    result = static_modes(model, np.radians(40.0))
    periods = _periods(result)
    assert len(periods) in (1, 2)
    # the geometric mean of a Foucault pair's frequencies is ω_s itself
    mean_minutes = np.exp(np.mean(np.log(periods))) / 60
    assert mean_minutes == pytest.approx(84.4, abs=0.5)


@pytest.mark.parametrize("model", [OWN_MODEL, "north_pointing"])
def test_schuler_period_is_2_pi_sqrt_r_over_g_exactly(model):
    """Both models default to R = 6371 km and g = 9.80665 m/s²; at the equator the
    north-pointing platform's two Schuler pairs coincide (no Foucault split)."""
    result = static_modes(model, 0.0)
    [schuler] = [m for m in result.modes if m.name == "Schuler"]
    assert schuler.multiplicity == (1 if model == OWN_MODEL else 2)
    assert schuler.period_s == pytest.approx(2 * np.pi * np.sqrt(6_371_000 / 9.80665),
                                             rel=1e-9)
    assert schuler.kind == "oscillation"


@pytest.mark.parametrize("model", ["orthodromic", "north_pointing", "free_azimuth",
                                   "strapdown_ned"])
def test_earth_mode_is_the_sidereal_day(model):
    earth = static_modes(model, np.radians(35.0)).mode("Earth")
    assert earth.period_s == pytest.approx(SIDEREAL_DAY, rel=1e-9)
    assert earth.period_s / 3600 == pytest.approx(23.93, abs=0.005)
    assert earth.reference.relative_difference == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("latitude_deg", [45.0, -45.0, 20.0, -70.0])
def test_north_pointing_foucault_split_equals_the_closed_forms(latitude_deg):
    latitude = np.radians(latitude_deg)
    result = static_modes("north_pointing", latitude)
    expected = closed_forms("north_pointing", latitude).periods()
    for name in (*SPLIT_MODES, "Earth"):
        assert result.mode(name).period_s == pytest.approx(expected[name], rel=1e-9)
    # the longer period is "Schuler − Foucault" in either hemisphere
    assert result.mode(SPLIT_MODES[0]).period_s > result.mode(SPLIT_MODES[1]).period_s


def test_hemispheres_give_the_same_named_periods():
    north = static_modes("north_pointing", np.radians(50.0))
    south = static_modes("north_pointing", np.radians(-50.0))
    for name in (*SPLIT_MODES, "Earth"):
        assert south.mode(name).period_s == pytest.approx(north.mode(name).period_s,
                                                          rel=1e-9)


@pytest.mark.parametrize("latitude_deg", [50.0, -30.0])
def test_orthodromic_at_its_baked_parameters_equals_the_closed_forms(latitude_deg):
    latitude = np.radians(latitude_deg)
    baked = closed_form_module("orthodromic").BAKED
    result = static_modes("orthodromic", latitude, parameters=baked)
    # at rest a_zeta is the normal gravity of the (spherical) baked Earth at φ
    gravity = GAMMA_E * (1 + SOMIGLIANA_K * np.sin(latitude) ** 2)
    assert result.references.g.value == pytest.approx(gravity, rel=1e-12)
    expected = closed_forms("orthodromic", latitude, gravity=gravity).periods()
    for name in (*SPLIT_MODES, "Earth"):
        assert result.mode(name).period_s == pytest.approx(expected[name], rel=1e-9)


def test_strapdown_undamped_vertical_channel_grows_at_sqrt_2g_over_r():
    latitude = np.radians(50.0)
    result = static_modes("strapdown_ned", latitude)
    gravity, radius = _wgs84_schuler_constants(latitude)
    growing = result.mode("vertical channel (growing)")
    assert growing.kind == "growing"
    assert growing.eigenvalue.real == pytest.approx(np.sqrt(2 * gravity / radius), rel=2e-3)
    assert growing.time_constant_s == pytest.approx(570.0, abs=2.0)
    assert growing.doubling_time_s == pytest.approx(np.log(2) * growing.time_constant_s)
    assert result.mode("vertical channel (decaying)").eigenvalue.real == pytest.approx(
        -growing.eigenvalue.real, rel=1e-9)
    # the vertical channel is height and vertical velocity (Coriolis adds a little v_E)
    assert {name for name, _ in growing.states(0.1)} == {"delta_h", "delta_v_D"}


def _vertical_roots(k1: float, k2: float, latitude: float) -> np.ndarray:
    gravity, radius = _wgs84_schuler_constants(latitude)
    return np.roots([1.0, k1, k2 - 2 * gravity / radius])


def test_strapdown_damped_vertical_loop_of_300_s_and_zeta_0_7():
    """The README's loop: k₁ = 2ζω₀, k₂ = ω₀² + 2g/R for ω₀ = 2π/300 s, ζ = 0.7."""
    latitude = np.radians(50.0)
    gravity, radius = _wgs84_schuler_constants(latitude)
    omega0 = 2 * np.pi / 300.0
    k1, k2 = 2 * 0.7 * omega0, omega0**2 + 2 * gravity / radius
    result = static_modes("strapdown_ned", latitude, parameters={"k_h1": k1, "k_h2": k2})
    [loop] = [m for m in result.modes if m.kind == "damped oscillation"
              and m.damping_ratio > 0.1]
    root = max(_vertical_roots(k1, k2, latitude), key=lambda r: r.imag)
    assert loop.eigenvalue == pytest.approx(root, rel=1e-4)
    assert loop.damping_ratio == pytest.approx(0.7, rel=1e-3)
    assert abs(loop.eigenvalue) == pytest.approx(omega0, rel=1e-3)
    # the loop's natural period, 2π/ω₀ = 300 s, beside its damped one 300 s/√(1 − ζ²)
    assert loop.natural_period_s == pytest.approx(300.0, rel=1e-3)
    assert loop.period_s == pytest.approx(300.0 / np.sqrt(1 - 0.7**2), rel=1e-3)
    assert result.mode("Earth").natural_period_s is None or abs(
        result.mode("Earth").natural_period_s - result.mode("Earth").period_s) < 1.0
    # the horizontal modes keep their names though the loop damps them slightly
    for name in (*SPLIT_MODES, "Earth"):
        assert abs(result.mode(name).damping_ratio) < 1e-3
    assert not any(m.name.startswith("vertical channel") for m in result.modes)


def test_strapdown_overdamped_vertical_loop_gives_two_time_constants():
    latitude = np.radians(50.0)
    k1, k2 = 0.05, 2e-4
    result = static_modes("strapdown_ned", latitude, parameters={"k_h1": k1, "k_h2": k2})
    damped = sorted(m.time_constant_s for m in result.modes if m.kind == "damped")
    expected = sorted(-1 / _vertical_roots(k1, k2, latitude).real)
    # the Coriolis coupling to the horizontal channels moves 2e-6 1/s of damping from
    # the loop to the Schuler pairs (F's trace is kept): 5e-4 of the slow root
    np.testing.assert_allclose(damped, expected, rtol=1e-3)


def test_participation_schuler_in_tilt_and_velocity_earth_in_azimuth_and_latitude():
    result = static_modes("north_pointing", np.radians(50.0))
    for name in SPLIT_MODES:
        share = result.mode(name).participation
        for state in ("delta_v_E", "delta_v_N", "alpha_E", "alpha_N"):
            assert share[state] > 0.3, (name, state)
    earth = result.mode("Earth").participation
    # as a distance the Earth mode's east error is sin φ times its north one (its
    # eigenvector), and the share measures δλ as that distance, cos φ δλ
    assert {name for name, _ in result.mode("Earth").states(0.3)} == {
        "delta_latitude", "alpha_U", "delta_longitude"}
    # at the Earth rate the velocity errors are (Ω/ω_s)² smaller than the angles
    assert max(earth["delta_v_E"], earth["delta_v_N"]) < 0.1


def test_model_file_without_earth_rate_names_its_modes_by_kind():
    result = static_modes(OWN_MODEL, np.radians(50.0))
    assert result.references.Omega is None
    assert [m.name for m in result.modes] == ["integrator", "Schuler"]
    assert result.mode("Schuler").reference.formula == "2π√(R/g)"
    assert set(result.mode("Schuler").participation) == {"delta_V", "delta_phi", "psi"}


def test_cli_on_a_model_file(capsys):
    assert main(["modes", OWN_MODEL, "--latitude", "10deg"]) == 0
    out = capsys.readouterr().out
    assert "| Schuler |" in out and "84.41 min" in out
    assert "the model has no Ω" in out


def test_cli_json_is_strict_and_records_the_parameters(capsys):
    assert main(["modes", "strapdown_ned", "-p", "k_h1=0.0293/s", "-p",
                 "k_h2=4.42e-4/s^2", "--latitude", "-45deg", "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    assert data["parameters"]["k_h1"] == {"value": 0.0293, "unit": "1/s"}
    assert data["latitude_rad"] == pytest.approx(np.radians(-45.0))
    names = [m["name"] for m in data["modes"]]
    assert names.count("Earth") == 1 and set(SPLIT_MODES) <= set(names)
    assert len(data["eigenvalues"]) == 10


def test_cli_heading_is_used_where_the_model_has_one(capsys):
    assert main(["modes", "strapdown_ned", "--heading", "30deg"]) == 0
    assert "heading = 0°/0°/30°" in capsys.readouterr().out


BAD = {
    "unknown-model": (["modes", "orthodromik"], "did you mean 'orthodromic'"),
    "pole": (["modes", "orthodromic", "--latitude", "90deg"], "pole"),
    "near-pole": (["modes", "north_pointing", "--latitude", "89.99999999deg"], "0.206″"),
    "nan": (["modes", "orthodromic", "--latitude", "nan deg"], "not a finite number"),
    "bare-latitude": (["modes", "orthodromic", "--latitude", "50"], "needs a unit"),
    "unknown-parameter": (["modes", "strapdown_ned", "-p", "k_h3=1/s"], "k_h3"),
    "negative-gain": (["modes", "strapdown_ned", "-p", "k_h1=-1/s"], "zero (undamped)"),
    "heading-unused": (["modes", "north_pointing", "--heading", "10deg"],
                       "no heading output"),
}


@pytest.mark.parametrize("case", BAD.values(), ids=BAD.keys())
def test_bad_input_is_one_line_and_exit_2(case, capsys):
    argv, words = case
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("ins-errors: error: ")
    assert words in err


def test_the_example_table_of_docs_modes_is_the_commands_output(capsys):
    """docs/modes.md's strapdown_ned table is what the command prints today (its commands
    themselves run in tests/test_docs_commands.py, with every docs page's)."""
    text = (ROOT / "docs/modes.md").read_text(encoding="utf-8")
    shown = re.search(r"^```text\n(.*?)^```", text, re.M | re.S).group(1)
    assert main(["modes", "strapdown_ned"]) == 0
    printed = capsys.readouterr().out.splitlines()
    rows = [line for line in shown.splitlines() if line.startswith("|")]
    assert len(rows) >= 6
    for row in rows:
        assert row in printed, row


def test_model_file_with_a_radius_named_r_earth_gets_its_schuler_period(tmp_path):
    """``check`` read a radius parameter named R_earth, ``modes`` did not (two lists of
    names): such a model had no Schuler reference. The loop of the tutorial with its
    radius renamed R_earth and set to 6000 km oscillates at 2π√(R/g) of those values."""
    from ins_errors.checker.typical import schuler_magnitudes
    from ins_errors.numeric.model import load_model

    text = Path(OWN_MODEL).read_text(encoding="utf-8")
    text = text.replace('Parameter("R", "m", "Earth radius (sphere)", "R", 6_371_000.0)',
                        'Parameter("R_earth", "m", "Earth radius (sphere)", "R", 6.0e6)')
    text = text.replace('name="schuler_loop"', 'name="schuler_r_earth"')
    assert "R_earth" in text and "schuler_r_earth" in text
    path = tmp_path / "schuler_r_earth.py"
    path.write_text(text, encoding="utf-8")
    period = 2 * np.pi * np.sqrt(6.0e6 / 9.80665)
    result = static_modes(str(path), np.radians(30.0))
    assert result.references.R.value == 6.0e6
    assert result.references.R.source == "parameter R_earth"
    schuler = result.mode("Schuler")
    assert schuler.period_s == pytest.approx(period, rel=1e-9)
    assert schuler.reference.relative_difference == pytest.approx(0.0, abs=1e-9)
    # the checker's typical magnitudes read the same radius
    assert "R = 6000000 m" in schuler_magnitudes(load_model(str(path))).origin


# --------------------------------------------------------------------------------------
# geodetic_vertical on the ellipsoid: why its Earth and Schuler periods are off
# --------------------------------------------------------------------------------------
# Krasovsky, typed from the source (004) and its translator's notes: a, flattening 1/298.3
KRASOVSKY_A, KRASOVSKY_F = 6_378_245.0, 1 / 298.3
KRASOVSKY_E2 = 2 * KRASOVSKY_F - KRASOVSKY_F**2
EARTH_RATE = 7.292115e-5


def _geodetic_vertical_base(latitude: float, longitude: float, orthodrome=(0.0, 0.0, 0.0)):
    """(Φ, N, μ, ν1, ν2, Earth rate on ξηζ) at a point of geodetic (B, L) at rest, from
    source 004's tables written out here with numpy: the start frame n of (1) (with the
    translator's orthonormal n11, n22), Table 2, sin B = −m32, (3) and (4)."""
    lam0, phi0, n0 = orthodrome
    s, c = np.sin, np.cos
    n = np.array([
        [c(lam0) * c(n0) + s(lam0) * s(phi0) * s(n0), c(phi0) * s(n0),
         s(phi0) * c(lam0) * s(n0) - s(lam0) * c(n0)],
        [s(lam0) * s(phi0) * c(n0) - c(lam0) * s(n0), c(phi0) * c(n0),
         c(lam0) * s(phi0) * c(n0) + s(lam0) * s(n0)],
        [s(lam0) * c(phi0), -s(phi0), c(lam0) * c(phi0)]])
    up = n @ np.array([s(longitude) * c(latitude), -s(latitude), c(longitude) * c(latitude)])
    big_phi, big_lam = np.arctan2(-up[1], np.hypot(up[0], up[2])), np.arctan2(up[0], up[2])
    table2 = np.array([
        [c(big_lam), 0.0, -s(big_lam)],
        [s(big_lam) * s(big_phi), c(big_phi), c(big_lam) * s(big_phi)],
        [s(big_lam) * c(big_phi), -s(big_phi), c(big_lam) * c(big_phi)]])
    earth_axis = (table2 @ n)[:, 1]  # the Earth's rotation axis η0 on ξ, η, ζ
    angle = np.arctan2(earth_axis[0], earth_axis[1])
    flattening = KRASOVSKY_E2 / (2 - KRASOVSKY_E2)
    mu = flattening * s(2 * latitude) - 0.5 * flattening**2 * s(4 * latitude)
    return big_phi, angle, mu, mu * c(angle), -mu * s(angle), EARTH_RATE * earth_axis


def _earth_rate_of_the_psi_equation(latitude: float, longitude: float, orthodrome) -> float:
    """The Earth-mode frequency the correction rates (9) imply, rad/s.

    The angle ψ of the platform against the trihedron of the reckoned (Φ, Λ) obeys
    ψ̇ = −Ω × ψ + ΔΩ, where ΔΩ is what (9) torques the platform with beyond the rate at
    which the dead reckoning Φ̇ = −W_η/R, Λ̇ = W_ξ/(R cos Φ) turns that trihedron: its
    deflection terms ((W_ξ/R) tg Φ ν2, −(W_ξ/R) tg Φ ν1, −(W_η/R) ν2) of the velocity
    error. At the Earth rate, far below Schuler's, the level loop keeps the platform on
    the vertical: the trihedron's error then follows −ψ, so δW_ξ/R = −ψ̇_η and
    δW_η/R = ψ̇_ξ, and (I + K) ψ̇ = −Ω × ψ with the K below. Its oscillation is the
    Earth mode; the approximation leaves out (Ω/ω_s)² ≈ 0.35 % of the shift from Ω.
    """
    big_phi, _, _, nu1, nu2, rate = _geodetic_vertical_base(latitude, longitude, orthodrome)
    t = np.tan(big_phi)
    inertia = np.array([[1.0, t * nu2, 0.0], [0.0, 1.0 - t * nu1, 0.0], [nu2, 0.0, 1.0]])
    cross = np.array([[0.0, -rate[2], rate[1]], [rate[2], 0.0, -rate[0]],
                      [-rate[1], rate[0], 0.0]])
    return float(np.max(np.abs(np.linalg.eigvals(np.linalg.solve(inertia, cross)).imag)))


@pytest.mark.parametrize("latitude_deg, orthodrome", [
    (45.0, (0.0, 0.0, 0.0)), (80.0, (0.0, 0.0, 0.0)), (-60.0, (0.0, 0.0, 0.0)),
    (50.0, (0.3, 0.6, 0.7)), (70.0, (0.2, 0.4, 1.2))])
def test_geodetic_vertical_earth_mode_is_off_omega_by_the_deflection_terms_of_9(
        latitude_deg, orthodrome):
    """The probe's −0.316 % at 80°: the model transcribes (9) faithfully, and (9) torques
    the platform with deflection terms its dead reckoning does not turn the reckoned
    trihedron with. The ψ-equation above (typed from the source's tables, not from the
    model) predicts the shift on any orthodrome; with e² = 0 (ν = 0) it is exactly Ω;
    ``modes`` says so on the row."""
    latitude, longitude = np.radians(latitude_deg), np.radians(30.0)
    parameters = dict(zip(("orth_longitude", "orth_latitude", "orth_angle"), orthodrome,
                          strict=True))
    earth = static_modes("geodetic_vertical", latitude, longitude,
                         parameters=parameters).mode("Earth")
    predicted = _earth_rate_of_the_psi_equation(latitude, longitude, orthodrome)
    assert abs(predicted / EARTH_RATE - 1) > 5e-5  # a shift worth explaining
    assert (earth.eigenvalue.imag - EARTH_RATE) / (predicted - EARTH_RATE) == pytest.approx(
        1.0, abs=0.01)
    sphere = static_modes("geodetic_vertical", latitude, longitude,
                          parameters={**parameters, "e2": 0.0}).mode("Earth")
    assert sphere.period_s == pytest.approx(SIDEREAL_DAY, rel=1e-9)
    assert sphere.reference.relative_difference == pytest.approx(0.0, abs=1e-9)
    assert "(9)" in earth.note and "dead reckoning" in earth.note
    if orthodrome == (0.0, 0.0, 0.0):  # the note's figure on the meridian: −c sin⁴ B
        flattening = KRASOVSKY_E2 / (2 - KRASOVSKY_E2)
        assert earth.reference.relative_difference == pytest.approx(
            -flattening * np.sin(latitude) ** 4, rel=0.01)
        assert "c sin⁴ B" in earth.note


@pytest.mark.parametrize("latitude_deg", [60.0, 80.0])  # at 45° √(R_M R_N) ≈ a anyway
def test_geodetic_vertical_schuler_pair_runs_on_its_own_radii(latitude_deg):
    """On the meridian orthodrome the north channel of (9) has R = a(1 − c sin² B) and the
    east channel, with −(W_ξ/R) tg Φ ν1 in Ω_η, R/(1 − ν1 tg Φ): the Foucault pair of a
    sphere of their geometric mean, not of √(R_M R_N) (the textbook column)."""
    latitude = np.radians(latitude_deg)
    result = static_modes("geodetic_vertical", latitude)
    big_phi, _, _, nu1, _, _ = _geodetic_vertical_base(latitude, np.radians(30.0))
    flattening = KRASOVSKY_E2 / (2 - KRASOVSKY_E2)
    north = KRASOVSKY_A * (1 - flattening * np.sin(latitude) ** 2)
    radius = north / np.sqrt(1 - nu1 * np.tan(big_phi))
    gravity = result.references.g.value  # a_ζ at rest: the loop's own g
    foucault = EARTH_RATE * np.sin(latitude)
    mean = np.sqrt(gravity / radius + foucault**2)
    for name, sign in zip(SPLIT_MODES, (-1, 1), strict=True):
        mode = result.mode(name)
        assert mode.period_s == pytest.approx(2 * np.pi / (mean + sign * foucault), rel=2e-4)
        assert abs(mode.reference.relative_difference) > 4e-4
        assert "R/(1 − ν1 tg Φ)" in mode.note


@pytest.mark.parametrize("latitude_deg", [0.0, 30.0, 50.0, 70.0, -40.0])
def test_strapdown_ned_modes_are_the_textbook_ones_coupled_to_the_vertical_channel(
        latitude_deg):
    """The lab probe's unexplained −0.05 % on strapdown_ned's Schuler rows. The textbook
    pair leaves the vertical channel out; a 9-state NED φ-model typed from the textbook
    (checked separately: dropping its δv_E ↔ δv_D Coriolis terms gives the textbook pair
    to 1e-5) says the unstable vertical channel, λ_v² = ∂γ/∂h, stiffens the east channel
    by (2Ω cos φ)² ω_s²/(ω_s² + λ_v²). With ∂γ/∂h the closed form of WGS-84 normal gravity
    (NIMA TR8350.2 (4-3)), that predicts every Schuler and vertical-channel rate of the
    model; the rows carry the model's note saying so."""
    latitude = np.radians(latitude_deg)
    s2, c2 = np.sin(latitude) ** 2, np.cos(latitude) ** 2
    gravity, radius = _wgs84_schuler_constants(latitude)
    flattening, m = 1 / 298.257223563, 0.00344978650684
    gradient = 2 * gravity / WGS84_A * (1 + flattening + m - 2 * flattening * s2)
    schuler2 = gravity / radius
    coriolis2 = 4 * EARTH_RATE**2 * c2
    result = static_modes("strapdown_ned", latitude)
    growing = result.mode("vertical channel (growing)")
    assert growing.eigenvalue.real == pytest.approx(
        np.sqrt(gradient - coriolis2 * gradient / (gradient + schuler2)), rel=2e-6)
    if latitude_deg == 50.0:  # the probe's case: the textbook rate is well off
        assert abs(growing.eigenvalue.real / np.sqrt(2 * schuler2) - 1) > 5e-4
    # the note is on every row off its textbook value by more than 0.01 %
    assert (growing.note is not None and "∂γ/∂h" in growing.note) == (
        abs(growing.reference.relative_difference) > 1e-4)
    schuler = sorted((mode for mode in result.modes if mode.name.startswith("Schuler")),
                     key=lambda mode: mode.period_s, reverse=True)
    if latitude_deg == 0.0:  # no Foucault split: the channels part on their own radii
        meridian = WGS84_A * (1 - WGS84_E2)
        expected = [np.sqrt(gravity / meridian),
                    np.sqrt(gravity / WGS84_A + coriolis2 * schuler2 / (schuler2 + gradient))]
        expected.sort()
    else:
        foucault = EARTH_RATE * np.sqrt(s2)
        mean = np.sqrt(schuler2 + foucault**2 + coriolis2 / 6)
        expected = [mean - foucault, mean + foucault]
    for mode, rate in zip(schuler, expected, strict=True):
        assert 2 * np.pi / mode.period_s == pytest.approx(rate, rel=1e-5)
        assert abs(mode.reference.relative_difference) > 1e-4
        assert "(2Ω cos φ)²" in mode.note


def test_cli_shows_the_models_note_on_the_rows_it_explains(capsys):
    assert main(["modes", "geodetic_vertical", "--latitude", "80deg"]) == 0
    out = capsys.readouterr().out
    [earth] = [line for line in out.splitlines() if line.startswith("| Earth |")]
    assert "-0.316 % (see note)" in earth
    assert "\nnote on Earth (from the model): " in out
    assert "\nnote on Schuler − Foucault, Schuler + Foucault (from the model): " in out
    assert main(["modes", "geodetic_vertical", "--latitude", "80deg", "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    notes = {m["name"]: m["note"] for m in data["modes"]}
    assert "dead reckoning" in notes["Earth"] and notes["integrator"] is None
    # a model without notes: no note anywhere
    assert main(["modes", "north_pointing"]) == 0
    assert "see note" not in capsys.readouterr().out
    # a note on a row at its textbook value is not shown: strapdown_ned's Schuler note
    # (the undamped vertical channel's coupling) once the damping loop is set
    assert main(["modes", "strapdown_ned", "-p", "k_h1=0.0293/s", "-p",
                 "k_h2=4.42e-4/s^2"]) == 0
    out = capsys.readouterr().out
    assert "see note" not in out and "note on" not in out
    assert main(["modes", "geodetic_vertical", "--latitude", "80deg", "-p", "e2=0"]) == 0
    assert "see note" not in capsys.readouterr().out


def test_a_mode_note_must_name_a_mode():
    from ins_errors.errors import ModelDefinitionError
    from ins_errors.models import geodetic_vertical

    definition = geodetic_vertical.build()
    fields = {name: getattr(definition, name) for name in definition.__dataclass_fields__}
    with pytest.raises(ModelDefinitionError, match="no mode 'Schuler period'"):
        type(definition)(**{**fields, "mode_notes": {"Schuler period": "x"}})


# --------------------------------------------------------------------------------------
# Foucault period, longitude shares, negative zero
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("latitude_deg", [50.0, -30.0])
def test_foucault_period_is_printed_and_equals_2_pi_over_omega_sin_phi(latitude_deg, capsys):
    latitude = np.radians(latitude_deg)
    expected = 2 * np.pi / (EARTH_RATE * abs(np.sin(latitude)))  # 31.24 h at 50°
    result = static_modes("north_pointing", latitude)
    assert result.foucault_period_s == pytest.approx(expected, rel=1e-12)
    # the Schuler pair's half split is Ω|sin φ| exactly on north_pointing's sphere
    assert result.foucault_period_from_modes_s == pytest.approx(expected, rel=1e-9)
    assert main(["modes", "north_pointing", "--latitude", f"{latitude_deg}deg"]) == 0
    out = capsys.readouterr().out
    hours = re.search(r"^Foucault period 2π/\(Ω\|sin φ\|\) = ([\d.]+) h at φ = ", out, re.M)
    assert float(hours.group(1)) == pytest.approx(expected / 3600, abs=0.01)
    assert main(["modes", "north_pointing", "--latitude", f"{latitude_deg}deg", "--json"]) == 0
    foucault = strict_json(capsys.readouterr().out)["foucault"]
    assert foucault["period_s"] == pytest.approx(expected, rel=1e-12)


def test_no_foucault_period_at_the_equator(capsys):
    assert static_modes("north_pointing", 0.0).foucault_period_s is None
    assert main(["modes", "north_pointing", "--latitude", "0deg"]) == 0
    assert "Foucault period" not in capsys.readouterr().out


@pytest.mark.parametrize("model, latitude_name, longitude_name", [
    ("north_pointing", "delta_latitude", "delta_longitude"),
    ("strapdown_ned", "delta_lat", "delta_lon")])
def test_a_longitude_error_takes_part_as_a_distance(model, latitude_name, longitude_name):
    """The shares measure lengths over R; a longitude error δλ is the ground distance
    R cos φ δλ, so it counts as cos φ δλ. The Foucault-split Schuler modes move the
    position error round a circle (numpy's eigenvectors: |cos φ δλ| = |δφ|), and
    δλ measured in rad (inflated by 1/cos φ = 2.9 at 70°) topped both modes. The
    shares are the row norms of the projector on the mode's plane (span of the real
    and imaginary parts of numpy's eigenvector) with δλ scaled by cos φ."""
    latitude = np.radians(-70.0)
    result = static_modes(model, latitude)
    names = list(result.scales)
    lat, lon = names.index(latitude_name), names.index(longitude_name)
    eigenvalues, vectors = np.linalg.eig(result.state_matrix)
    gravity, radius = result.references.g.value, result.references.R.value
    units = {"rad": 1.0, "1": 1.0, "m": 1 / radius, "m/s": 1 / np.sqrt(gravity * radius)}
    scale = np.array([units[result.scales[n].split(" ")[0].replace("(m/s)", "m/s")]
                      if not n.startswith(longitude_name) else np.cos(latitude)
                      for n in names])
    for name in SPLIT_MODES:
        mode = result.mode(name)
        vector = vectors[:, np.argmin(np.abs(eigenvalues - mode.eigenvalue))]
        assert abs(np.cos(latitude) * vector[lon]) == pytest.approx(abs(vector[lat]),
                                                                    rel=0.02)
        plane = scale[:, None] * np.column_stack([vector.real, vector.imag])
        projector = plane @ np.linalg.pinv(plane)
        share = np.sqrt(np.clip(np.diag(projector), 0, None))
        share /= share.max()
        np.testing.assert_allclose([mode.participation[n] for n in names], share,
                                   atol=1e-6)
        assert mode.states()[0][0] != longitude_name
    assert "cos" in result.scales[longitude_name]


def test_no_negative_zero_in_the_json(capsys):
    """An undamped mode's ζ = −0/|λ| was written "damping_ratio": -0.0."""
    from ins_errors.json_output import dumps

    assert main(["modes", "north_pointing", "--json"]) == 0
    text = capsys.readouterr().out
    assert not re.search(r"-0\.0\b(?!\d)", text)
    ratios = [m["damping_ratio"] for m in strict_json(text)["modes"]
              if m["kind"] == "oscillation"]
    assert ratios and all(r == 0.0 and np.copysign(1.0, r) == 1.0 for r in ratios)
    assert np.copysign(1.0, static_modes("north_pointing").mode("Earth").damping_ratio) == 1.0
    assert dumps({"x": -0.0, "y": [np.float64(-0.0)]}, indent=None) == '{"x": 0.0, "y": [0.0]}'


def test_closed_forms_default_gravity_is_the_static_base_of_the_other_commands():
    """closed_forms('orthodromic', 39°) took a_ζ = 9.80665 m/s² where ``modes`` and
    ``propagation --orthodromic`` take the generators' normal gravity of the model's
    Earth at the site (Somigliana, typed here, on the closed forms' sphere: 9.78781):
    their periods differed by 0.1 %. An explicit gravity is still taken."""
    latitude = np.radians(39.0)
    gravity = GAMMA_E * (1 + SOMIGLIANA_K * np.sin(latitude) ** 2)
    assert gravity == pytest.approx(9.78781, abs=1e-5)
    forms = closed_forms("orthodromic", latitude)
    a_zeta = forms.u[[i.name for i in forms.model.inputs].index("a_zeta")]
    assert a_zeta == pytest.approx(gravity, rel=1e-12)
    periods = forms.periods()
    modes = static_modes("orthodromic", latitude, parameters={"e2": 0.0})
    foucault = EARTH_RATE * np.sin(latitude)
    mean = np.sqrt(gravity / KRASOVSKY_A + foucault**2)  # the closed forms' sphere: R = a
    for name, sign in zip(SPLIT_MODES, (-1, 1), strict=True):
        assert periods[name] == pytest.approx(2 * np.pi / (mean + sign * foucault), rel=1e-9)
        assert periods[name] == pytest.approx(modes.mode(name).period_s, rel=1e-9)
    assert periods["Earth"] == pytest.approx(modes.mode("Earth").period_s, rel=1e-9)
    explicit = closed_forms("orthodromic", latitude, gravity=9.80665)
    assert explicit.u[[i.name for i in explicit.model.inputs].index("a_zeta")] == 9.80665
