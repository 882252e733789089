"""Hand-coded velocity and position rows of the ECEF strapdown INS of
tests/models/ecef_ins.py, in its own states (test data), written from Groves (2013,
ch. 14) for point-mass gravitation and the centrifugal acceleration:

    δv̇ = −2 [Ω ×] δv + Γ δr + C_b^e δf,   δṙ = δv,
    Γ = μ/|r|³ (3 u uᵀ − I) − [Ω ×]²,   u = r/|r|,

r at the sample's geocentric latitude and longitude on the sphere of radius ``nav.a``.
``coriolis_slip`` writes +2 [Ω ×] for −2 [Ω ×]; ``velocity_only`` keeps the velocity
rows alone (no position state, no attitude state).
"""

import numpy as np

MU = 3.986004418e14
STATES = ["delta_v_X", "delta_v_Y", "delta_v_Z", "delta_r_X", "delta_r_Y", "delta_r_Z"]
SOURCES = ["accel_bias_x", "accel_bias_y", "accel_bias_z"]


def ecef_to_ned(lat, lon):
    """C_e^n: ECEF → NED at geocentric latitude ``lat`` and longitude ``lon`` (rad)."""
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def rows(nav, imu, coriolis=-2.0):
    """F (6 × 6) and G (6 × 3) of the velocity and position rows."""
    lat, lon = nav.latitude, nav.longitude
    r = (nav.a + nav.height) * np.array([np.cos(lat) * np.cos(lon),
                                         np.cos(lat) * np.sin(lon), np.sin(lat)])
    norm = np.linalg.norm(r)
    u = r / norm
    earth = np.array([[0.0, -nav.earth_rate, 0.0], [nav.earth_rate, 0.0, 0.0],
                      [0.0, 0.0, 0.0]])
    F = np.zeros((6, 6))
    F[0:3, 0:3] = coriolis * earth
    F[0:3, 3:6] = MU / norm**3 * (3 * np.outer(u, u) - np.eye(3)) - earth @ earth
    F[3:6, 0:3] = np.eye(3)
    G = np.zeros((6, 3))
    G[0:3, :] = ecef_to_ned(lat, lon).T @ nav.C_bn
    return F, G


def exact(nav, imu):
    return rows(nav, imu)


def coriolis_slip(nav, imu):
    return rows(nav, imu, coriolis=+2.0)


def velocity_only(nav, imu):
    F, G = rows(nav, imu)
    return F[0:3, 0:3], G[0:3]


velocity_only.states = STATES[0:3]
