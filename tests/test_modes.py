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
    assert {name for name, _ in result.mode("Earth").states(0.5)} == {
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


# Krasovsky semi-major axis (the closed forms' sphere), typed from source 004
KRASOVSKY_A = 6_378_245.0
EARTH_RATE = 7.292115e-5

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
