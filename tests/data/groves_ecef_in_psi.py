"""Groves' Earth-fixed error model (Principles of GNSS, Inertial and Multisensor
Integrated Navigation Systems, 2nd ed., ch. 14) with a Coriolis sign slip, carried by
hand into the NED ψ states of ``--convention psi`` (z = blockdiag(−C_e^n, C_e^n, C_e^n)
x_e, ż = (T F_e Tᵀ + Ṫ T⁻¹) z, Ṫ T⁻¹ = −I ⊗ [ω_en ×]), as a researcher checks it against
``tests/models/ecef_ins.py`` (point-mass gravity on a sphere) before the ``psi_ecef``
convention existed. In ψ states the slipped −2Ω_ie shares its entries with transport-rate
terms, so only at rest is the hand entry exactly minus the model's."""

import numpy as np

MU = 3.986004418e14
STATES = ["psi_N", "psi_E", "psi_D", "dvc_N", "dvc_E", "dvc_D", "dr_N", "dr_E", "dr_D"]
SOURCES = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
           "accel_bias_x", "accel_bias_y", "accel_bias_z"]


def _skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def coriolis_slip(nav, imu):
    """F and G with +2Ω_ie where Groves has −2Ω_ie (the velocity rows)."""
    lat, lon, h, radius = nav.latitude, nav.longitude, nav.height, nav.a
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    c_en = np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])
    r = (radius + h) * np.array([cl * co, cl * so, sl])
    u = r / np.linalg.norm(r)
    omega = _skew([0.0, 0.0, nav.earth_rate])
    gradient = MU / np.linalg.norm(r) ** 3 * (3 * np.outer(u, u) - np.eye(3)) - omega @ omega
    f_e = np.zeros((9, 9))
    f_e[0:3, 0:3] = -omega
    f_e[3:6, 0:3] = -_skew(c_en.T @ imu.f_n)
    f_e[3:6, 3:6] = +2 * omega                     # the slip: Groves has −2 Ω_ie
    f_e[3:6, 6:9] = gradient
    f_e[6:9, 3:6] = np.eye(3)
    g_e = np.zeros((9, 6))
    g_e[0:3, 0:3] = g_e[3:6, 3:6] = c_en.T @ nav.C_bn
    v_n, v_e, _ = nav.v_ned
    w_en = np.array([v_e, -v_n, -v_e * np.tan(lat)]) / (radius + h)
    t = np.zeros((9, 9))
    t[0:3, 0:3], t[3:6, 3:6], t[6:9, 6:9] = -c_en, c_en, c_en
    return t @ f_e @ t.T + np.kron(np.eye(3), -_skew(w_en)), t @ g_e
