r"""The classic ψ-angle error model of a strapdown INS, coded the way a textbook prints it.

Source of the equations: D. O. Benson, "A comparison of two approaches to pure-inertial
and Doppler-inertial error analysis", IEEE Transactions on Aerospace and Electronic
Systems, AES-11(4), 1975, pp. 447-455 (the ψ-angle or "computer frame" approach); the
same form appears in D. H. Titterton and J. L. Weston, *Strapdown Inertial Navigation
Technology*, 2nd ed., IEE, 2004, chapter 12. Coded here from the equations, in NED:

    ψ̇  = −ω_in × ψ − C_b^n δω                       (attitude: ψ-angle)
    δv̇ = f^n × ψ − (2 ω_ie + ω_en) × δv + Γ δr + C_b^n δf   (velocity, computer frame)
    δṙ = −ω_en × δr + δv                              (position, NED metres)

with the textbook's simplifications:

* a spherical Earth of radius R = a (the semi-major axis), so
  ω_en = (v_E, −v_N, −v_E tan φ) / (R + h);
* the gravity error of a spherical Earth, Γ = (g/R) diag(−1, −1, 2): a horizontal
  position error tilts gravity (the Schuler restoring term), a height error changes its
  magnitude (the unstable vertical channel); g is the local gravity magnitude;
* IMU errors: gyro bias δω and accelerometer bias δf only.

States (the vocabulary of the ``psi`` convention, ``ins-errors check strapdown_ned
--list-conventions``): ψ-angle, velocity error in the computed frame, position error in
NED metres. This file is checked by

    ins-errors check strapdown_ned --matrix examples/strapdown/psi_model.py:psi_model \
        --convention psi
"""

import numpy as np

STATES = ["psi_N", "psi_E", "psi_D", "dvc_N", "dvc_E", "dvc_D", "dr_N", "dr_E", "dr_D"]
SOURCES = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
           "accel_bias_x", "accel_bias_y", "accel_bias_z"]


def skew(w):
    """[w×], the matrix of the cross product w × (·)."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def psi_model(nav, imu):
    """F (9 × 9) and G (9 × 6) of the ψ-angle model at one point of the motion."""
    lat, h = nav.latitude, nav.height
    v_n, v_e, _ = nav.v_ned
    R = nav.a                                   # spherical Earth
    U = nav.earth_rate
    w_ie = np.array([U * np.cos(lat), 0.0, -U * np.sin(lat)])
    w_en = np.array([v_e, -v_n, -v_e * np.tan(lat)]) / (R + h)
    g = nav.gravity

    F = np.zeros((9, 9))
    F[0:3, 0:3] = -skew(w_ie + w_en)
    F[3:6, 0:3] = skew(imu.f_n)
    F[3:6, 3:6] = -skew(2 * w_ie + w_en)
    F[3:6, 6:9] = g / R * np.diag([-1.0, -1.0, 2.0])
    F[6:9, 3:6] = np.eye(3)
    F[6:9, 6:9] = -skew(w_en)

    G = np.zeros((9, 6))
    G[0:3, 0:3] = -nav.C_bn
    G[3:6, 3:6] = nav.C_bn
    return F, G
