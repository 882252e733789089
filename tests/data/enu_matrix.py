"""Test fixture: a textbook ENU φ-angle model as a --matrix function, in ENU state names
(phi_U, dv_U: up), for tests/models/enu_euler_sphere.py; and the same converted to NED
by hand (a permutation with the up rows negated), which the check reads as it is."""
import numpy as np

STATES = ["phi_E", "phi_N", "phi_U", "dv_E", "dv_N", "dv_U", "dlat", "dlon", "dh"]
SOURCES = ["gyro_bias_x", "gyro_bias_y", "gyro_bias_z",
           "accel_bias_x", "accel_bias_y", "accel_bias_z"]
P3 = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]])  # NED -> ENU


def sk(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def enu_model(nav, imu):
    L, h = nav.latitude, nav.height
    vN, vE, vD = nav.v_ned
    vU = -vD
    R = nav.parameters["R"]
    U = nav.earth_rate
    C = P3 @ nav.C_bn
    fn = C @ imu.f_b
    r = R + h
    tL, sL = np.tan(L), 1 / np.cos(L)
    wie = np.array([0, U * np.cos(L), U * np.sin(L)])
    wen = np.array([-vN / r, vE / r, vE * tL / r])
    v = np.array([vE, vN, vU])
    Mie = np.zeros((3, 6))
    Mie[1, 3] = -U * np.sin(L)
    Mie[2, 3] = U * np.cos(L)
    Men = np.zeros((3, 6))
    Men[0, 1] = -1 / r
    Men[0, 5] = vN / r**2
    Men[1, 0] = 1 / r
    Men[1, 5] = -vE / r**2
    Men[2, 0] = tL / r
    Men[2, 3] = vE * sL**2 / r
    Men[2, 5] = -vE * tL / r**2
    F = np.zeros((9, 9))
    F[0:3, 0:3] = -sk(wie + wen)
    F[0:3, 3:9] = Mie + Men
    F[3:6, 0:3] = sk(fn)
    F[3:6, 3:6] = -sk(2 * wie + wen)
    F[3:6, 3:9] += sk(v) @ (2 * Mie + Men)
    F[6, 4] = 1 / r
    F[6, 8] = -vN / r**2
    F[7, 3] = sL / r
    F[7, 6] = vE * sL * tL / r
    F[7, 8] = -vE * sL / r**2
    F[8, 5] = 1.0
    G = np.zeros((9, 6))
    G[0:3, 0:3] = -C
    G[3:6, 3:6] = C
    return F, G


def enu_model_up_slip(nav, imu):
    """The Earth-rate term of F[phi_U, dlat] written twice as large."""
    F, G = enu_model(nav, imu)
    F = F.copy()
    F[2, 6] += nav.earth_rate * np.cos(nav.latitude)
    return F, G


def enu_model_both(nav, imu):
    return enu_model(nav, imu)


enu_model_both.states = ["phi_E", "phi_N", "phi_U", "dv_E", "dv_N", "dv_U", "dlat", "dlon",
                         "phi_D"]  # phi_D is phi_U again: refused
enu_model_both.sources = SOURCES

P = np.zeros((9, 9))  # ENU state k -> NED state i, with the sign of an up component
for i_ned, (i_enu, s) in enumerate([(1, 1), (0, 1), (2, -1), (4, 1), (3, 1), (5, -1),
                                    (6, 1), (7, 1), (8, 1)]):
    P[i_ned, i_enu] = s


def as_ned(fun):
    def g(nav, imu):
        F, G = fun(nav, imu)
        return P @ F @ P.T, P @ G
    g.states = ["phi_N", "phi_E", "phi_D", "dv_N", "dv_E", "dv_D", "dlat", "dlon", "dh"]
    g.sources = SOURCES
    return g


enu_model_ned = as_ned(enu_model)
enu_model_up_slip_ned = as_ned(enu_model_up_slip)
