"""A hand-coded linear error model of the north-pointing platform INS (test data).

Written by hand from the textbook local-level equations in the model's own states
(east/north velocity errors, latitude and longitude errors, platform angles about east,
north and up), with the radii of curvature of the ellipsoid and the height:

    δv̇_E = (2U sin φ + v_E tan φ/r_E) δv_N + v_N δ(turn) − f_U α_N + a_N α_U + ∇_E
    δv̇_N = −(2U sin φ + v_E tan φ/r_E) δv_E − v_E δ(turn) + f_U α_E − a_E α_U + ∇_N
    δφ̇ = δv_N/r_N − v_N r_N' δφ/r_N²
    δλ̇ = δv_E/(r_E cos φ) + v_E (sin φ/(r_E cos² φ) − r_E'/(r_E² cos φ)) δφ
    α̇ = α × ω + δω + ε,   δω = (−δ(v_N/r_N), δ(U cos φ + v_E/r_E), δ(U sin φ + v_E tan φ/r_E))

with r_E = R_E + h, r_N = R_N + h, and ' the derivative with respect to φ.
"""

import numpy as np

STATES = ["delta_v_E", "delta_v_N", "delta_latitude", "delta_longitude",
          "alpha_E", "alpha_N", "alpha_U"]
SOURCES = ["gyro_drift_east", "gyro_drift_north", "gyro_drift_up",
           "accel_bias_east", "accel_bias_north"]


def error_model(nav, imu):
    phi, h = nav.latitude, nav.height
    U, a, e2 = nav.earth_rate, nav.a, nav.e2
    v_n, v_e = nav.v_ned[0], nav.v_ned[1]
    a_n, a_e, f_u = imu.f_n[0], imu.f_n[1], -imu.f_n[2]
    s, c = np.sin(phi), np.cos(phi)
    w = 1 - e2 * s**2
    r_e = a / np.sqrt(w) + h
    r_n = a * (1 - e2) / w**1.5 + h
    dr_e = a * e2 * s * c / w**1.5
    dr_n = 3 * a * e2 * (1 - e2) * s * c / w**2.5
    w_e, w_n, w_u = -v_n / r_n, U * c + v_e / r_e, U * s + v_e * np.tan(phi) / r_e
    turn = 2 * U * s + v_e * np.tan(phi) / r_e
    dturn_dve = np.tan(phi) / r_e
    dturn_dphi = 2 * U * c + v_e / (r_e * c**2) - v_e * np.tan(phi) * dr_e / r_e**2
    dwu_dphi = U * c + v_e / (r_e * c**2) - v_e * np.tan(phi) * dr_e / r_e**2

    F = np.zeros((7, 7))
    # velocity errors
    F[0, 0] = v_n * dturn_dve
    F[0, 1] = turn
    F[0, 2] = v_n * dturn_dphi
    F[0, 5] = -f_u
    F[0, 6] = a_n
    F[1, 0] = -turn - v_e * dturn_dve
    F[1, 2] = -v_e * dturn_dphi
    F[1, 4] = f_u
    F[1, 6] = -a_e
    # position errors
    F[2, 1] = 1 / r_n
    F[2, 2] = -v_n * dr_n / r_n**2
    F[3, 0] = 1 / (r_e * c)
    F[3, 2] = v_e * s / (r_e * c**2) - v_e * dr_e / (r_e**2 * c)
    # platform angles: α × ω + δω
    F[4, 1] = -1 / r_n
    F[4, 2] = v_n * dr_n / r_n**2
    F[4, 5], F[4, 6] = w_u, -w_n
    F[5, 0] = 1 / r_e
    F[5, 2] = -U * s - v_e * dr_e / r_e**2
    F[5, 4], F[5, 6] = -w_u, w_e
    F[6, 0] = np.tan(phi) / r_e
    F[6, 2] = dwu_dphi
    F[6, 4], F[6, 5] = w_n, -w_e

    G = np.zeros((7, 5))
    G[4, 0] = G[5, 1] = G[6, 2] = 1.0
    G[0, 3] = G[1, 4] = 1.0
    return F, G
