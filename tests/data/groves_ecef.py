r"""Groves' Earth-fixed (ECEF) error model of a strapdown INS, coded from the textbook.

P. D. Groves, *Principles of GNSS, Inertial, and Multisensor Integrated Navigation
Systems*, 2nd ed., Artech House, 2013, section 14.2.3 (ECEF-frame error equations):

    δψ̇^e = −Ω_ie^e δψ^e + C_b^e δω^b                            (attitude error)
    δv̇^e = −[(C_b^e f^b)×] δψ^e − 2 Ω_ie^e δv^e + Γ δr^e + C_b^e δf^b
    δṙ^e = δv^e

with Groves' attitude error C̃_b^e = (I + [δψ^e×]) C_b^e, Ω_ie^e = [(0, 0, U)×], and the
gravity gradient Γ = ∂g^e/∂r^e of the gravity the INS under test uses
(tests/models/ecef_ins.py: a point mass plus the centrifugal term,
g^e = −μ r/|r|³ − Ω_ie^e Ω_ie^e r):

    Γ = μ/|r|³ (3 u uᵀ − I) − Ω_ie^e Ω_ie^e,    u = r/|r|

(Groves' (14.49) keeps only its radial part, 2 g/|r| u uᵀ.) The navigation solution
comes in NED (``nav``): C_e^n, r^e, C_b^e and f^e are formed here from it. States are the
``psi_ecef`` convention's (``ins-errors check MODEL --list-conventions``), sources the
model's gyro and accelerometer biases. The slipped variants change one thing each.
"""

import numpy as np

MU = 3.986004418e14  # the model's default μ, m³/s²

STATES = ["psi_X", "psi_Y", "psi_Z", "dv_X", "dv_Y", "dv_Z", "dr_X", "dr_Y", "dr_Z"]
SOURCES = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
           "accel_bias_x", "accel_bias_y", "accel_bias_z"]


def skew(w):
    """[w×]."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def ecef_to_ned(lat, lon):
    """C_e^n."""
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def groves(nav, imu, coriolis=-2.0, gradient=True):
    """F (9 × 9) and G (9 × 6) at one point; ``coriolis`` the factor of Ω_ie^e in the
    velocity rows, ``gradient`` False to leave Γ out."""
    lat, lon = nav.latitude, nav.longitude
    C_ne = ecef_to_ned(lat, lon).T
    r = (nav.a + nav.height) * np.array([np.cos(lat) * np.cos(lon),
                                        np.cos(lat) * np.sin(lon), np.sin(lat)])
    rho = np.linalg.norm(r)
    u = r / rho
    omega = skew([0.0, 0.0, nav.earth_rate])
    C_be = C_ne @ nav.C_bn
    f_e = C_be @ imu.f_b
    gamma = MU / rho**3 * (3.0 * np.outer(u, u) - np.eye(3)) - omega @ omega

    F = np.zeros((9, 9))
    F[0:3, 0:3] = -omega
    F[3:6, 0:3] = -skew(f_e)
    F[3:6, 3:6] = coriolis * omega
    F[3:6, 6:9] = gamma if gradient else 0.0
    F[6:9, 3:6] = np.eye(3)
    G = np.zeros((9, 6))
    G[0:3, 0:3] = C_be
    G[3:6, 3:6] = C_be
    return F, G


def groves_exact(nav, imu):
    """The model as printed (with the model's own gravity gradient)."""
    return groves(nav, imu)


def groves_coriolis_slip(nav, imu):
    """+2 Ω_ie^e δv where the Coriolis error term is −2 Ω_ie^e δv."""
    return groves(nav, imu, coriolis=+2.0)


def groves_no_gradient(nav, imu):
    """The gravity gradient Γ δr^e left out."""
    return groves(nav, imu, gradient=False)


def groves_15(nav, imu):
    """The 15-state filter form [[F, G], [0, 0]]: the biases as random-constant states."""
    F, G = groves(nav, imu)
    out = np.zeros((15, 15))
    out[:9, :9], out[:9, 9:] = F, G
    return out


groves_15.states = [*STATES, *SOURCES]
groves_15.sources = None  # no G: the biases are states


def groves_velocity_position(nav, imu):
    """Only the velocity and position rows (no attitude states: the couplings
    −[f^e×] δψ^e are left out), with the Coriolis slip of :func:`groves_coriolis_slip`."""
    F, G = groves(nav, imu, coriolis=+2.0)
    return F[3:9, 3:9], G[3:9, 3:6]


groves_velocity_position.states = STATES[3:9]
groves_velocity_position.sources = SOURCES[3:6]


def groves_attitude_velocity(nav, imu):
    """Only the attitude and velocity rows (no position states: Γ δr^e is left out),
    with the Earth rate's sign slipped in the attitude rows: +Ω_ie^e δψ^e where the
    model has −Ω_ie^e δψ^e."""
    F, G = groves(nav, imu)
    F[0:3, 0:3] *= -1.0
    return F[0:6, 0:6], G[0:6, :]


groves_attitude_velocity.states = STATES[0:6]
groves_attitude_velocity.sources = SOURCES
