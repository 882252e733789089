"""Static base: the eigenvalues of F are the classical INS error modes.

Theory (independent of the code): an undamped platform INS at rest has Earth-rate modes
±iU and two Schuler oscillations coupled by the Coriolis term 2U sin φ. With north and
east Schuler frequencies ω_M² = g/R_M, ω_N² = g/R_N (meridian, prime-vertical radii),
the frequencies ω solve (ω_M² − ω²)(ω_N² − ω²) = 4 U² sin²φ ω²; on a sphere they are
√(ω_s² + U² sin²φ) ± U sin φ (the Foucault split of the Schuler period, 84.4 min).
"""

from __future__ import annotations

import numpy as np
import pytest

from tests.helpers import static_inputs

G = 9.81
U = 7.292115e-5
A, F_FLAT = 6_378_245.0, 1 / 298.3


def _static_frequencies(model, latitude, p):
    c = model.initial_condition_vector(latitude=latitude, longitude=0.4, heading=0.7)
    x = model.initial_state(c, model.input_vector(), p)
    u = static_inputs(model, x, p, g=G)
    frequencies = np.abs(np.linalg.eigvals(model.state_matrix(x, u, p)).imag)
    return np.unique(np.round(frequencies[frequencies > 1e-6], 12))


def _theory(latitude, e2):
    s2 = np.sin(latitude) ** 2
    prime_vertical = A / np.sqrt(1 - e2 * s2)
    meridian = A * (1 - e2) / (1 - e2 * s2) ** 1.5
    wm2, wn2, coriolis = G / meridian, G / prime_vertical, U * np.sin(latitude)
    squares = np.roots([1.0, -(wm2 + wn2 + 4 * coriolis**2), wm2 * wn2])
    return np.sort(np.sqrt(squares.real))


@pytest.mark.parametrize("latitude_deg", [0.0, 10.0, 45.0, 60.0, 80.0])
def test_schuler_foucault_and_earth_rate_modes(orthodromic, latitude_deg):
    latitude = np.radians(latitude_deg)
    earth, low, high = _static_frequencies(orthodromic, latitude, orthodromic.parameter_vector())
    assert earth == pytest.approx(U, rel=1e-6)
    np.testing.assert_allclose([low, high], _theory(latitude, 2 * F_FLAT - F_FLAT**2),
                               rtol=1e-4)
    period_minutes = 2 * np.pi / np.sqrt(low * high) / 60
    assert period_minutes == pytest.approx(84.4, abs=0.5)


@pytest.mark.parametrize("latitude_deg", [30.0, 45.0])
def test_foucault_split_on_a_sphere(orthodromic, latitude_deg):
    latitude = np.radians(latitude_deg)
    p = orthodromic.parameter_vector(e2=0.0)
    _, low, high = _static_frequencies(orthodromic, latitude, p)
    assert (high - low) / 2 == pytest.approx(U * np.sin(latitude), rel=1e-6)
    schuler = np.sqrt(G / A)
    assert np.sqrt(low * high + (U * np.sin(latitude)) ** 2) == pytest.approx(
        np.sqrt(schuler**2 + (U * np.sin(latitude)) ** 2), rel=1e-6)
    # the Foucault modulation period 2π/(U sin φ): 33.8 h at 45°
    if latitude_deg == 45.0:
        assert 2 * np.pi / ((high - low) / 2) / 3600 == pytest.approx(33.8, abs=0.05)
