"""The orthodromic model's alpha_z is the platform's azimuth misalignment from its computed
great-circle trihedron, not from north (its description says so): the textbook azimuth
error from north, a horizontal gyro drift ε giving ε/(U cos φ)(1 − cos Ut) with its
largest value 2ε/(U cos φ) at half an Earth period, is alpha_z + delta_heading."""

from __future__ import annotations

import numpy as np

from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate

PHI = np.radians(50.0)
EARTH_RATE = 7.292115e-5   # rad/s (U of the model)


def test_the_azimuth_error_from_north_is_alpha_z_plus_the_heading_error(orthodromic):
    drift = np.radians(0.01) / 3600.0
    p = orthodromic.parameter_vector(e2=0.0)
    rest = tr.trajectory(orthodromic, tr.static_profile(PHI), 86400.0, 60.0, p=p)
    run = simulate(orthodromic, rest, {"gyro_drift_y": drift}, parts=("linear",),
                   record_interval=600.0)
    errors = run.linear_errors()
    azimuth = errors["alpha_z"][:, 0] + errors["delta_heading"][:, 0]
    textbook = drift / (EARTH_RATE * np.cos(PHI)) * (1 - np.cos(EARTH_RATE * run.times))
    largest = 2 * drift / (EARTH_RATE * np.cos(PHI))
    # the Schuler oscillation rides on the Earth-rate swing: a few per cent of it
    assert np.max(np.abs(np.abs(azimuth) - textbook)) < 0.03 * largest
    assert abs(np.max(np.abs(azimuth)) - largest) < 0.02 * largest
    # alpha_z alone is not it (it stays well under half the textbook's swing), nor is
    # the heading error taken with the other sign
    assert np.max(np.abs(errors["alpha_z"][:, 0])) < 0.5 * largest
    other = errors["alpha_z"][:, 0] - errors["delta_heading"][:, 0]
    assert np.max(np.abs(np.abs(other) - textbook)) > 0.3 * largest
    assert "from north: alpha_z + delta_heading" in orthodromic.error_states[
        [s.name for s in orthodromic.error_states].index("alpha_z")].description
