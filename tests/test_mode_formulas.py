"""The formulas the models' mode notes state, against the models' eigenvalues.

* free_azimuth showed two rows named "Schuler" (84.76 and 84.65 min at −30°) with no
  note, and a Foucault footer about a split its modes do not have. Its note now gives
  ω² = g/R + Ω² cos² φ for the channel the horizontal Earth rate couples to the azimuth
  (the gyrocompass coupling, α̇ = α × ω); g is typed here from the Somigliana formula on
  the model's sphere, R and Ω are the model's constants.
* strapdown_ned's note claimed its Schuler formula "to 1e-5"; at 5° the gap was 2.5e-5.
  The figure the note states is now checked over a latitude grid.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from ins_errors.analysis.modes import static_modes
from ins_errors.cli import main

EARTH_RATE = 7.292115e-5
GAMMA_E, SOMIGLIANA_K = 9.7803253359, 0.00193185265241  # WGS-84 normal gravity
WGS84_A, WGS84_E2 = 6_378_137.0, 6.69437999014e-3
FLATTENING, M_RATIO = 1 / 298.257223563, 0.00344978650684
FREE_AZIMUTH_R = 6_411_000.0  # the source's tuning radius (002)


def _schuler_rates(result) -> list[float]:
    return sorted(m.eigenvalue.imag for m in result.modes if m.name.startswith("Schuler")
                  for _ in range(m.multiplicity))


@pytest.mark.parametrize("heading_deg", [0.0, 40.0, 135.0])
@pytest.mark.parametrize("latitude_deg", [-60.0, -30.0, 0.0, 17.0, 45.0, 80.0])
def test_free_azimuth_channels_are_the_textbook_one_and_the_gyrocompass_stiffened_one(
        latitude_deg, heading_deg):
    latitude = np.radians(latitude_deg)
    gravity = GAMMA_E * (1 + SOMIGLIANA_K * np.sin(latitude) ** 2)  # on the sphere, e² = 0
    schuler2 = gravity / FREE_AZIMUTH_R
    expected = [np.sqrt(schuler2), np.sqrt(schuler2 + (EARTH_RATE * np.cos(latitude)) ** 2)]
    result = static_modes("free_azimuth", latitude, heading=np.radians(heading_deg))
    assert _schuler_rates(result) == pytest.approx(expected, rel=1e-11)
    # no Foucault pair is named, and the note is on the stiffened row where it is off
    assert not any("Foucault" in m.name for m in result.modes)
    [stiff] = [m for m in result.modes if m.name == "Schuler"
               and m.eigenvalue.imag == pytest.approx(expected[1], rel=1e-11)]
    assert (stiff.note is not None) == (abs(stiff.reference.relative_difference) > 1e-4)
    if stiff.note is not None:
        assert "ω² = g/R + Ω² cos² φ" in stiff.note
    [plain] = [m for m in result.modes if m.name == "Schuler" and m is not stiff]
    assert plain.note is None


def test_free_azimuth_footer_says_its_modes_show_no_foucault_split(capsys):
    assert main(["modes", "free_azimuth", "--latitude", "-30deg"]) == 0
    out = capsys.readouterr().out
    footer = next(line for line in out.splitlines() if line.startswith("Foucault period"))
    assert "47.87 h" in footer  # 2π/(Ω sin 30°), the meridian's turning
    assert "turns once in it" not in footer
    assert "no two Schuler rows here differ by Ω|sin φ|" in footer
    assert "note on Schuler (from the model): " in out
    # near the equator strapdown_ned's two channels are split by their radii more than by
    # Ω|sin φ|: the coupling is there (its note), only not resolved as a pair; the note
    # names each mode once
    assert main(["modes", "strapdown_ned", "--latitude", "0.5deg"]) == 0
    out = capsys.readouterr().out
    assert "not resolved as a pair" in out and "note on Schuler, Schuler" not in out
    # a model with the split keeps the turning plane and its period from the pair
    assert main(["modes", "north_pointing", "--latitude", "-30deg"]) == 0
    footer = next(line for line in capsys.readouterr().out.splitlines()
                  if line.startswith("Foucault period"))
    assert "the plane of the Schuler oscillation turns once in it; from the split pair" \
        in footer


def _strapdown_reference(latitude: float) -> tuple[list[float], list[float]]:
    """The coupled-channel frequencies and the mean-frequency pair of the note, from
    WGS-84 typed here: normal gravity at the ellipsoid, its vertical gradient
    (NIMA TR8350.2 (4-3)), the meridian and prime-vertical radii."""
    s2 = np.sin(latitude) ** 2
    gravity = GAMMA_E * (1 + SOMIGLIANA_K * s2) / np.sqrt(1 - WGS84_E2 * s2)
    gradient = 2 * gravity / WGS84_A * (1 + FLATTENING + M_RATIO - 2 * FLATTENING * s2)
    meridian = WGS84_A * (1 - WGS84_E2) / (1 - WGS84_E2 * s2) ** 1.5
    prime = WGS84_A / np.sqrt(1 - WGS84_E2 * s2)
    schuler2 = gravity / np.sqrt(meridian * prime)
    coriolis2 = 4 * EARTH_RATE**2 * (1 - s2)
    foucault = EARTH_RATE * np.sin(latitude)
    north2 = gravity / meridian
    east2 = gravity / prime + coriolis2 * schuler2 / (schuler2 + gradient)
    b = north2 + east2 + 4 * foucault**2  # (ω² − ω_N²)(ω² − ω_E²) = 4Ω² sin² φ ω²
    root = np.sqrt(b * b - 4 * north2 * east2)
    coupled = sorted(np.sqrt([(b - root) / 2, (b + root) / 2]))
    mean = np.sqrt(schuler2 + foucault**2 + coriolis2 / 6)
    return coupled, [mean - abs(foucault), mean + abs(foucault)]


def test_strapdown_ned_schuler_note_states_its_accuracy_truly():
    note = static_modes("strapdown_ned", np.radians(50.0)).mode("Schuler − Foucault").note
    stated = float(re.search(r"to (\d(?:\.\d)?e-\d+) at every latitude", note).group(1))
    away = re.search(r"\(\|φ\| ≥ (\d+)°\).*?again to (\d(?:\.\d)?e-\d+) \((\d\.\de-\d+) at 5°\)",
                     note)
    bound, stated_away, at_five = (float(g) for g in away.groups())
    worst = worst_away = 0.0
    for latitude_deg in np.r_[np.arange(-89.0, 90.0, 2.0), 0.0, 0.5, 5.0, 33.0, -33.0]:
        latitude = np.radians(latitude_deg)
        rates = _schuler_rates(static_modes("strapdown_ned", latitude))
        coupled, mean = _strapdown_reference(latitude)
        worst = max(worst, *(abs(r / c - 1) for r, c in zip(rates, coupled, strict=True)))
        gap = max(abs(r / m - 1) for r, m in zip(rates, mean, strict=True))
        if abs(latitude_deg) >= bound:
            worst_away = max(worst_away, gap)
        if latitude_deg == 5.0:
            assert gap == pytest.approx(at_five, rel=0.05)
    assert worst <= stated and worst > stated / 3  # true, and not a loose bound
    assert worst_away <= stated_away


KRASOVSKY_A, KRASOVSKY_E2 = 6_378_245.0, 0.006693421622965943


def _orthodromic_reference(latitude: float) -> list[float]:
    """The note's two channels coupled by the Foucault terms, from the Krasovsky
    ellipsoid and g by Somigliana's formula with WGS-84's γ_e and k on it, typed here."""
    s2 = np.sin(latitude) ** 2
    gravity = GAMMA_E * (1 + SOMIGLIANA_K * s2) / np.sqrt(1 - KRASOVSKY_E2 * s2)
    meridian = KRASOVSKY_A * (1 - KRASOVSKY_E2) / (1 - KRASOVSKY_E2 * s2) ** 1.5
    prime = KRASOVSKY_A / np.sqrt(1 - KRASOVSKY_E2 * s2)
    north2, east2 = gravity / meridian, gravity / prime
    b = north2 + east2 + 4 * EARTH_RATE**2 * s2
    root = np.sqrt(b * b - 4 * north2 * east2)
    return sorted(np.sqrt([(b - root) / 2, (b + root) / 2]))


def test_orthodromic_schuler_note_explains_its_two_radii(capsys):
    # the probe: two Schuler rows at the equator, +0.168 % and −0.166 % off, no note
    assert main(["modes", "orthodromic", "--latitude", "0deg"]) == 0
    out = capsys.readouterr().out
    assert "note on Schuler (from the model): two channels, each on its own radius" in out
    note = static_modes("orthodromic", 0.0).mode("Schuler").note
    stated = float(re.search(r"to (\d(?:\.\d)?e-\d+) at every latitude", note).group(1))
    worst = 0.0
    for latitude_deg in np.r_[np.arange(-88.0, 89.0, 4.0), 0.0, 0.5, 1.0, 5.0, 14.0]:
        latitude = np.radians(latitude_deg)
        for heading_deg in (0.0, 70.0):
            rates = _schuler_rates(static_modes("orthodromic", latitude,
                                                heading=np.radians(heading_deg)))
            reference = _orthodromic_reference(latitude)
            worst = max(worst, *(abs(r / c - 1) for r, c in zip(rates, reference,
                                                               strict=True)))
    assert worst <= stated and worst > stated / 3
    # the equator's periods the note quotes, and the channel each belongs to
    gravity = GAMMA_E
    north = 2 * np.pi * np.sqrt(KRASOVSKY_A * (1 - KRASOVSKY_E2) / gravity) / 60
    east = 2 * np.pi * np.sqrt(KRASOVSKY_A / gravity) / 60
    assert (f"north about 2π√(R_M/g) = {north:.2f} min, east about 2π√(R_N/g) = "
            f"{east:.2f} min") in note
    result = static_modes("orthodromic", 0.0)
    by_state = {max(m.participation, key=lambda k: m.participation[k]
                    if k.startswith("delta_V") else -1): m.period_s / 60
                for m in result.modes if m.name == "Schuler"}
    assert by_state["delta_V_xi"] == pytest.approx(north, rel=stated)  # ξ north at χ = 0
    assert by_state["delta_V_eta"] == pytest.approx(east, rel=stated)
    # "within 0.01 % beyond about 14°": no note there, and on a sphere one textbook row
    for latitude_deg in (14.0, -14.0, 45.0, -60.0):
        assert all(m.note is None for m in static_modes(
            "orthodromic", np.radians(latitude_deg)).modes), latitude_deg
    sphere = static_modes("orthodromic", 0.0, parameters={"e2": 0.0})
    [row] = [m for m in sphere.modes if m.name == "Schuler"]
    assert row.multiplicity == 2 and row.note is None


def test_orthodromic_listing_says_where_eta_points(capsys):
    assert main(["models", "orthodromic"]) == 0
    out = capsys.readouterr().out
    line = next(k for k in out.splitlines() if k.strip().startswith("delta_V_eta "))
    assert "to the left of ξ: west at χ = 0" in line
