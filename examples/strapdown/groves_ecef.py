r"""Groves' Earth-fixed (ECEF) error model of a strapdown INS, for strapdown_sphere.py.

P. D. Groves, *Principles of GNSS, Inertial, and Multisensor Integrated Navigation
Systems*, 2nd ed., Artech House, 2013, section 14.2.3 (ECEF-frame error equations):

    δψ̇^e = −Ω_ie^e δψ^e + C_b^e δω^b                            (attitude error)
    δv̇^e = −[(C_b^e f^b)×] δψ^e − 2 Ω_ie^e δv^e + Γ δr^e + C_b^e δf^b
    δṙ^e = δv^e

with Groves' sign of the attitude error, C̃_b^e = (I + [δψ^e×]) C_b^e, Ω_ie^e =
[(0, 0, U)×], and Γ = ∂g^e/∂r^e the gradient of the gravity the INS uses.
strapdown_sphere.py's gravity is a constant g along the local down, g^e = −g u
(u = r/|r|): it turns with the position but keeps its size, so

    Γ = −(g/|r|) (I − u uᵀ)

(Groves' point-mass gravity would add the radial 2g/|r| u uᵀ, the unstable vertical
channel; this INS has none). The navigation solution comes in NED (``nav``): C_e^n, r^e,
C_b^e and f^e are formed from it. States are those of the ``psi_ecef`` convention, checked by

    ins-errors check examples/strapdown/strapdown_sphere.py \
        --matrix examples/strapdown/groves_ecef.py:groves_ecef --convention psi_ecef
"""

import numpy as np

STATES = ["psi_X", "psi_Y", "psi_Z", "dv_X", "dv_Y", "dv_Z", "dr_X", "dr_Y", "dr_Z"]
SOURCES = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
           "accel_bias_x", "accel_bias_y", "accel_bias_z"]


def skew(w):
    """[w×], the matrix of the cross product w × (·)."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def groves_ecef(nav, imu):
    """F (9 × 9) and G (9 × 6) of the ECEF error model at one point of the motion."""
    lat, lon = nav.latitude, nav.longitude
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    C_en = np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])
    C_be = C_en.T @ nav.C_bn                       # body -> ECEF
    u = np.array([cl * co, cl * so, sl])           # r / |r| on the sphere
    r = nav.a + nav.height                         # |r|
    omega = skew([0.0, 0.0, nav.earth_rate])       # Ω_ie^e

    F = np.zeros((9, 9))
    F[0:3, 0:3] = -omega
    F[3:6, 0:3] = -skew(C_be @ imu.f_b)
    F[3:6, 3:6] = -2.0 * omega
    F[3:6, 6:9] = -nav.gravity / r * (np.eye(3) - np.outer(u, u))
    F[6:9, 3:6] = np.eye(3)

    G = np.zeros((9, 6))
    G[0:3, 0:3] = C_be                             # gyro biases (δω = ω̃ − ω)
    G[3:6, 3:6] = C_be                             # accelerometer biases
    return F, G
