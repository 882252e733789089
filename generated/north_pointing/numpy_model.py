# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/north_pointing.py.
# Edit the model definition and run `make derive` again.

"""numpy functions of the model 'north_pointing' (broadcasting)."""

import numpy as _np

_m = _np


def _as_vector(value, length, name, function):
    array = _np.asarray(value, dtype=float)
    if array.ndim == 0 or array.shape[0] != length:
        raise ValueError(f"{function}: argument {name} must have shape ({length}, ...), "
                         f"got {array.shape}")
    return array


def ideal_rhs(x, u, p):
    """Ideal-work equations: dx/dt.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        time derivative of the true state
    """
    x = _as_vector(x, 4, 'x', 'ideal_rhs')
    u = _as_vector(u, 3, 'u', 'ideal_rhs')
    p = _as_vector(p, 4, 'p', 'ideal_rhs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    a_E_ = u[0]
    a_N_ = u[1]
    h_ = u[2]
    R_ = p[0]
    ecc2_ = p[1]
    U_ = p[2]
    _t0 = _m.sin(phi_)
    _t1 = -_t0**2*ecc2_ + 1
    _t2 = V_E_/(R_/_m.sqrt(_t1) + h_)
    _t3 = 2*U_*_t0 + _t2*_m.tan(phi_)
    _out = _np.zeros((4,) + _batch)
    _out[0] = V_N_*_t3 + a_E_
    _out[1] = -V_E_*_t3 + a_N_
    _out[2] = V_N_/(R_*(1 - ecc2_)/(_t1*_m.sqrt(_t1)) + h_)
    _out[3] = _t2/_m.cos(phi_)
    return _out


def real_rhs(xr, x, u, w, p):
    """Real-work equations: dxr/dt (needs the true state x for the platform).

    Parameters
    ----------
    xr : array_like, shape (7, ...)
        real-work state: the 4 computed states in the order of x, then the platform angles alpha_E, alpha_N, alpha_U (rad)
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 7, 'xr', 'real_rhs')
    x = _as_vector(x, 4, 'x', 'real_rhs')
    u = _as_vector(u, 3, 'u', 'real_rhs')
    w = _as_vector(w, 12, 'w', 'real_rhs')
    p = _as_vector(p, 4, 'p', 'real_rhs')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    V_E_c_ = xr[0]
    V_N_c_ = xr[1]
    phi_c_ = xr[2]
    alpha_E_ = xr[4]
    alpha_N_ = xr[5]
    alpha_U_ = xr[6]
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    a_E_ = u[0]
    a_N_ = u[1]
    h_ = u[2]
    gyro_drift_east_ = w[0]
    gyro_drift_north_ = w[1]
    gyro_drift_up_ = w[2]
    accel_bias_east_ = w[3]
    accel_bias_north_ = w[4]
    R_ = p[0]
    ecc2_ = p[1]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.sin(phi_c_)
    _t1 = U_*_t0
    _t2 = -_t0**2*ecc2_ + 1
    _t3 = V_E_c_/(R_/_m.sqrt(_t2) + h_)
    _t4 = _t3*_m.tan(phi_c_)
    _t5 = 2*_t1 + _t4
    _t6 = _m.cos(alpha_U_)
    _t7 = _m.sin(alpha_U_)
    _t8 = _t6*a_E_ + _t7*a_N_
    _t9 = _m.cos(alpha_N_)
    _t10 = _m.sin(phi_)
    _t11 = -_t10**2*ecc2_ + 1
    _t12 = 1/(R_/_m.sqrt(_t11) + h_)
    _t13 = R_*(1 - ecc2_)
    _t14 = 1/(h_ + _t13/(_t11*_m.sqrt(_t11)))
    _t15 = U_*_m.cos(phi_)
    _t16 = -V_E_**2*_t12 - 2*V_E_*_t15 - V_N_**2*_t14 + g_
    _t17 = _m.sin(alpha_N_)
    _t18 = _m.cos(alpha_E_)
    _t19 = _m.sin(alpha_E_)
    _t20 = V_N_c_/(_t13/(_t2*_m.sqrt(_t2)) + h_)
    _t21 = _m.cos(phi_c_)
    _t22 = V_E_*_t12
    _t23 = U_*_t10 + _t22*_m.tan(phi_)
    _t24 = _t15 + _t22
    _t25 = V_N_*_t14
    _t26 = _t24*_t7 - _t25*_t6
    _t27 = U_*_t21 + _t3 + gyro_drift_north_
    _t28 = _t1 + _t4 + gyro_drift_up_
    _t29 = -_t17*_t26 + _t18*_t28 + _t19*_t27 - _t23*_t9
    _out = _np.zeros((7,) + _batch)
    _out[0] = V_N_c_*_t5 - _t16*_t17 + _t8*_t9 + accel_bias_east_
    _out[1] = -V_E_c_*_t5 + _t18*(_t6*a_N_ - _t7*a_E_) + _t19*(_t16*_t9 + _t17*_t8) + accel_bias_north_
    _out[2] = _t20
    _out[3] = _t3/_t21
    _out[4] = _t17*_t23 - _t20 - _t26*_t9 + _t29*_m.tan(alpha_N_) + gyro_drift_east_
    _out[5] = _t18*_t27 - _t19*_t28 - _t24*_t6 - _t25*_t7
    _out[6] = _t29/_t9
    return _out


def real_rhs_small_angle(xr, x, u, w, p):
    """Real-work equations with the source's small-angle platform: dxr/dt.

    Parameters
    ----------
    xr : array_like, shape (7, ...)
        real-work state: the 4 computed states in the order of x, then the platform angles alpha_E, alpha_N, alpha_U (rad)
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 7, 'xr', 'real_rhs_small_angle')
    x = _as_vector(x, 4, 'x', 'real_rhs_small_angle')
    u = _as_vector(u, 3, 'u', 'real_rhs_small_angle')
    w = _as_vector(w, 12, 'w', 'real_rhs_small_angle')
    p = _as_vector(p, 4, 'p', 'real_rhs_small_angle')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    V_E_c_ = xr[0]
    V_N_c_ = xr[1]
    phi_c_ = xr[2]
    alpha_E_ = xr[4]
    alpha_N_ = xr[5]
    alpha_U_ = xr[6]
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    a_E_ = u[0]
    a_N_ = u[1]
    h_ = u[2]
    gyro_drift_east_ = w[0]
    gyro_drift_north_ = w[1]
    gyro_drift_up_ = w[2]
    accel_bias_east_ = w[3]
    accel_bias_north_ = w[4]
    R_ = p[0]
    ecc2_ = p[1]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.sin(phi_c_)
    _t1 = U_*_t0
    _t2 = -_t0**2*ecc2_ + 1
    _t3 = 1/(R_/_m.sqrt(_t2) + h_)
    _t4 = V_E_c_*_t3
    _t5 = _t4*_m.tan(phi_c_)
    _t6 = 2*_t1 + _t5
    _t7 = _m.sin(phi_)
    _t8 = -_t7**2*ecc2_ + 1
    _t9 = 1/(R_/_m.sqrt(_t8) + h_)
    _t10 = R_*(1 - ecc2_)
    _t11 = 1/(_t10/(_t8*_m.sqrt(_t8)) + h_)
    _t12 = U_*_m.cos(phi_)
    _t13 = -V_E_**2*_t9 - 2*V_E_*_t12 - V_N_**2*_t11 + g_
    _t14 = V_N_c_/(_t10/(_t2*_m.sqrt(_t2)) + h_)
    _t15 = _m.cos(phi_c_)
    _t16 = V_N_*_t11
    _t17 = U_*_t7
    _t18 = V_E_*_t9
    _t19 = _t18*_m.tan(phi_)
    _t20 = _t17 + _t19
    _t21 = _t12 + _t18
    _out = _np.zeros((7,) + _batch)
    _out[0] = V_N_c_*_t6 - _t13*alpha_N_ + a_E_ + a_N_*alpha_U_ + accel_bias_east_
    _out[1] = -V_E_c_*_t6 + _t13*alpha_E_ - a_E_*alpha_U_ + a_N_ + accel_bias_north_
    _out[2] = _t14
    _out[3] = _t4/_t15
    _out[4] = -_t14 + _t16 + _t20*alpha_N_ - _t21*alpha_U_ + gyro_drift_east_
    _out[5] = U_*_t15 + V_E_c_*_t3 - _t16*alpha_U_ - _t20*alpha_E_ - _t21 + gyro_drift_north_
    _out[6] = _t1 + _t16*alpha_N_ - _t17 - _t19 + _t21*alpha_E_ + _t5 + gyro_drift_up_
    return _out


def second_order_small_angle(x, u, p, xe, w):
    """Second-order term of the error equations of the small-angle platform.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units
    xe : array_like, shape (7, ...)
        error state xr - (x, 0)
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 4, 'x', 'second_order_small_angle')
    u = _as_vector(u, 3, 'u', 'second_order_small_angle')
    p = _as_vector(p, 4, 'p', 'second_order_small_angle')
    xe = _as_vector(xe, 7, 'xe', 'second_order_small_angle')
    w = _as_vector(w, 12, 'w', 'second_order_small_angle')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    h_ = u[2]
    R_ = p[0]
    ecc2_ = p[1]
    U_ = p[2]
    delta_v_E_ = xe[0]
    delta_v_N_ = xe[1]
    delta_latitude_ = xe[2]
    _t0 = _m.sin(phi_)
    _t1 = U_*_t0
    _t2 = _t0**2
    _t3 = _t2*ecc2_
    _t4 = 1 - _t3
    _t5 = R_/_m.sqrt(_t4) + h_
    _t6 = 1/_t5
    _t7 = _m.tan(phi_)
    _t8 = _t7**2
    _t9 = _t5**(-2)
    _t10 = (1/(_t4*_m.sqrt(_t4)))
    _t11 = R_*_t10
    _t12 = _t11*_t9*ecc2_
    _t13 = _m.cos(phi_)
    _t14 = _t13**2
    _t15 = V_E_*_t12*_t14
    _t16 = R_**2
    _t17 = ecc2_**2
    _t18 = _t4**(-3)
    _t19 = _t5**(-3)
    _t20 = _t8 + 1
    _t21 = 2*_t20
    _t22 = V_E_*_t13
    _t23 = _t12*_t22
    _t24 = V_E_*_t9
    _t25 = 3*R_/(_t4**2*_m.sqrt(_t4))
    _t26 = _t2*_t25
    _t27 = _t14*_t17*_t24*_t26
    _t28 = -R_*V_E_*_t10*_t2*_t7*_t9*ecc2_ - 2*V_E_*_t14*_t16*_t17*_t18*_t19*_t2*_t7 - V_E_*_t6*_t7*(2*_t8 + 2) + _t0*_t21*_t23 + _t15*_t7 + _t27*_t7
    _t29 = delta_latitude_**2
    _t30 = ((1/2))*_t29
    _t31 = _t30*(-2*_t1 - _t28)
    _t32 = 2*_t0
    _t33 = _t12*_t32
    _t34 = _t13*_t33*_t7
    _t35 = ((1/2))*delta_latitude_
    _t36 = _t35*delta_v_E_
    _t37 = U_*_t13
    _t38 = 4*_t37
    _t39 = V_E_*_t6
    _t40 = _t6*_t7
    _t41 = 1 - ecc2_
    _t42 = _t11*_t41 + h_
    _t43 = _t42**(-2)
    _t44 = V_N_*_t14
    _t45 = _t41*_t43*_t44
    _t46 = _t25*ecc2_
    _t47 = _t41*_t43
    _t48 = _t17*_t2
    _t49 = -15*R_*_t45*_t48/(_t4**3*_m.sqrt(_t4)) + V_N_*_t25*_t3*_t47 + 18*_t16*_t41**2*_t44*_t48/(_t4**5*_t42**3) - _t45*_t46
    _t50 = _t0*_t13*delta_latitude_
    _t51 = _t46*_t47*_t50*delta_v_N_
    _t52 = 1/_t13
    _t53 = 2*_t2
    _t54 = _t17*_t22
    _out = _np.zeros((7,) + _batch)
    _out[0] = V_N_*_t31 + _t35*delta_v_N_*(_t21*_t39 - _t23*_t32*_t7 + _t38) + _t36*(2*V_N_*_t20*_t6 - V_N_*_t34) + _t40*delta_v_E_*delta_v_N_
    _out[1] = -V_E_*_t31 - _t40*delta_v_E_**2 + ((1/2))*delta_latitude_*delta_v_E_*(4*R_*V_E_*_t0*_t10*_t13*_t7*_t9*ecc2_ - 4*_t20*_t39 - _t38)
    _out[2] = ((1/2))*_t29*_t49 - _t51
    _out[3] = _t30*(-_t11*_t24*_t3*_t52 + _t16*_t18*_t19*_t53*_t54 - _t23 - _t26*_t54*_t9 + _t39*_t52 + _t39*_t53/_t13**3) + _t36*(2*_t0*_t6/_t14 - _t33)
    _out[4] = -_t30*_t49 + _t51
    _out[5] = -_t12*_t50*delta_v_E_ + ((1/2))*_t29*(R_*V_E_*_t10*_t2*_t9*ecc2_ + 2*V_E_*_t14*_t16*_t17*_t18*_t19*_t2 - _t15 - _t27 - _t37)
    _out[6] = _t30*(-_t1 - _t28) + _t36*(2*_t20*_t6 - _t34)
    return _out


def outputs(x, u, p):
    """Navigation outputs of a state (true or computed part of xr).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        outputs in SI units
    """
    x = _as_vector(x, 4, 'x', 'outputs')
    u = _as_vector(u, 3, 'u', 'outputs')
    p = _as_vector(p, 4, 'p', 'outputs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    lam_ = x[3]
    _out = _np.zeros((4,) + _batch)
    _out[0] = phi_
    _out[1] = lam_
    _out[2] = V_N_
    _out[3] = V_E_
    return _out


def state_matrix(x, u, p):
    """State matrix F of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 7, ...)
        F
    """
    x = _as_vector(x, 4, 'x', 'state_matrix')
    u = _as_vector(u, 3, 'u', 'state_matrix')
    p = _as_vector(p, 4, 'p', 'state_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    a_E_ = u[0]
    a_N_ = u[1]
    h_ = u[2]
    R_ = p[0]
    ecc2_ = p[1]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.sin(phi_)
    _t1 = -_t0**2*ecc2_ + 1
    _t2 = R_/_m.sqrt(_t1) + h_
    _t3 = 1/_t2
    _t4 = _m.tan(phi_)
    _t5 = _t3*_t4
    _t6 = U_*_t0
    _t7 = 2*_t6
    _t8 = V_E_*_t3
    _t9 = _t4*_t8
    _t10 = _m.cos(phi_)
    _t11 = U_*_t10
    _t12 = 2*_t11
    _t13 = R_/(_t1*_m.sqrt(_t1))
    _t14 = _t0*ecc2_
    _t15 = V_E_*_t13*_t14/_t2**2
    _t16 = _t10*_t15
    _t17 = -_t16*_t4 + _t8*(_t4**2 + 1)
    _t18 = _t12 + _t17
    _t19 = 1 - ecc2_
    _t20 = _t13*_t19 + h_
    _t21 = 1/_t20
    _t22 = V_E_**2*_t3 + V_E_*_t12 + V_N_**2*_t21 - g_
    _t23 = 3*R_*V_N_*_t10*_t14*_t19/((_t1**2*_m.sqrt(_t1))*_t20**2)
    _t24 = _t6 + _t9
    _t25 = _t11 + _t8
    _t26 = V_N_*_t21
    _out = _np.zeros((7, 7) + _batch)
    _out[0, 0] = V_N_*_t5
    _out[0, 1] = _t7 + _t9
    _out[0, 2] = V_N_*_t18
    _out[0, 5] = _t22
    _out[0, 6] = a_N_
    _out[1, 0] = -_t7 - 2*_t9
    _out[1, 2] = -V_E_*_t18
    _out[1, 4] = -_t22
    _out[1, 6] = -a_E_
    _out[2, 1] = _t21
    _out[2, 2] = -_t23
    _out[3, 0] = _t3/_t10
    _out[3, 2] = V_E_*_t0*_t3/_t10**2 - _t15
    _out[4, 1] = -_t21
    _out[4, 2] = _t23
    _out[4, 5] = _t24
    _out[4, 6] = -_t25
    _out[5, 0] = _t3
    _out[5, 2] = -_t16 - _t6
    _out[5, 4] = -_t24
    _out[5, 6] = -_t26
    _out[6, 0] = _t5
    _out[6, 2] = _t11 + _t17
    _out[6, 4] = _t25
    _out[6, 5] = _t26
    return _out


def source_matrix(x, u, p):
    """Error-source matrix G of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        G
    """
    x = _as_vector(x, 4, 'x', 'source_matrix')
    u = _as_vector(u, 3, 'u', 'source_matrix')
    p = _as_vector(p, 4, 'p', 'source_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    _out = _np.zeros((7, 12) + _batch)
    _out[0, 3] = 1
    _out[1, 4] = 1
    _out[4, 0] = 1
    _out[5, 1] = 1
    _out[6, 2] = 1
    return _out


def output_matrix(x, u, p):
    """Output matrix H: output errors = H xe to first order.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, 7, ...)
        H
    """
    x = _as_vector(x, 4, 'x', 'output_matrix')
    u = _as_vector(u, 3, 'u', 'output_matrix')
    p = _as_vector(p, 4, 'p', 'output_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    _out = _np.zeros((4, 7) + _batch)
    _out[0, 2] = 1
    _out[1, 3] = 1
    _out[2, 1] = 1
    _out[3, 0] = 1
    return _out


def second_order(x, u, p, xe, w):
    """Second-order term of the error equations (refined model).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units
    xe : array_like, shape (7, ...)
        error state xr - (x, 0)
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 4, 'x', 'second_order')
    u = _as_vector(u, 3, 'u', 'second_order')
    p = _as_vector(p, 4, 'p', 'second_order')
    xe = _as_vector(xe, 7, 'xe', 'second_order')
    w = _as_vector(w, 12, 'w', 'second_order')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    V_E_ = x[0]
    V_N_ = x[1]
    phi_ = x[2]
    a_E_ = u[0]
    a_N_ = u[1]
    h_ = u[2]
    R_ = p[0]
    ecc2_ = p[1]
    U_ = p[2]
    delta_v_E_ = xe[0]
    delta_v_N_ = xe[1]
    delta_latitude_ = xe[2]
    alpha_E_ = xe[4]
    alpha_N_ = xe[5]
    alpha_U_ = xe[6]
    gyro_drift_north_ = w[1]
    gyro_drift_up_ = w[2]
    _t0 = alpha_N_**2
    _t1 = ((1/2))*a_E_
    _t2 = alpha_U_**2
    _t3 = _m.sin(phi_)
    _t4 = U_*_t3
    _t5 = 2*_t4
    _t6 = _t3**2
    _t7 = _t6*ecc2_
    _t8 = 1 - _t7
    _t9 = R_/_m.sqrt(_t8) + h_
    _t10 = 1/_t9
    _t11 = _m.tan(phi_)
    _t12 = _t11**2
    _t13 = _t9**(-2)
    _t14 = (1/(_t8*_m.sqrt(_t8)))
    _t15 = R_*_t14
    _t16 = _t13*_t15*ecc2_
    _t17 = _m.cos(phi_)
    _t18 = _t17**2
    _t19 = V_E_*_t16*_t18
    _t20 = R_**2
    _t21 = ecc2_**2
    _t22 = _t8**(-3)
    _t23 = _t9**(-3)
    _t24 = _t12 + 1
    _t25 = V_E_*_t17
    _t26 = _t16*_t25
    _t27 = 2*_t26*_t3
    _t28 = V_E_*_t13
    _t29 = 3*R_/(_t8**2*_m.sqrt(_t8))
    _t30 = _t21*_t6
    _t31 = _t18*_t28*_t29*_t30
    _t32 = -R_*V_E_*_t11*_t13*_t14*_t6*ecc2_ - V_E_*_t10*_t11*(2*_t12 + 2) - 2*V_E_*_t11*_t18*_t20*_t21*_t22*_t23*_t6 + _t11*_t19 + _t11*_t31 + _t24*_t27
    _t33 = delta_latitude_**2
    _t34 = ((1/2))*_t33
    _t35 = _t34*(-_t32 - _t5)
    _t36 = _t16*_t3
    _t37 = 2*_t36
    _t38 = _t11*_t17*_t37
    _t39 = ((1/2))*delta_latitude_
    _t40 = _t39*delta_v_E_
    _t41 = U_*_t17
    _t42 = 4*_t41
    _t43 = V_E_*_t10
    _t44 = 2*_t43
    _t45 = -_t11*_t27 + _t24*_t44
    _t46 = _t10*_t11
    _t47 = _t46*delta_v_E_
    _t48 = alpha_E_**2
    _t49 = ((1/2))*a_N_
    _t50 = 1 - ecc2_
    _t51 = _t15*_t50 + h_
    _t52 = _t51**(-2)
    _t53 = V_N_*_t18
    _t54 = _t50*_t52*_t53
    _t55 = _t29*ecc2_
    _t56 = _t50*_t52
    _t57 = -15*R_*_t30*_t54/(_t8**3*_m.sqrt(_t8)) + V_N_*_t29*_t56*_t7 + 18*_t20*_t30*_t50**2*_t53/(_t51**3*_t8**5) - _t54*_t55
    _t58 = _t17*delta_latitude_
    _t59 = _t3*_t55*_t56*_t58*delta_v_N_
    _t60 = 1/_t17
    _t61 = _t25*_t30
    _t62 = ((1/2))*_t0
    _t63 = V_N_/_t51
    _t64 = 2*_t41
    _t65 = _t44 + _t64
    _t66 = _t45 + _t64
    _t67 = ((1/2))*_t2
    _t68 = _t41 + _t43
    _t69 = ((1/2))*_t48
    _t70 = _t39*alpha_E_
    _t71 = alpha_E_*delta_v_E_
    _t72 = _t11*_t43 + _t4
    _out = _np.zeros((7,) + _batch)
    _out[0] = V_N_*_t35 - _t0*_t1 - _t1*_t2 + _t39*delta_v_N_*(_t42 + _t45) + _t40*(2*V_N_*_t10*_t24 - V_N_*_t38) + _t47*delta_v_N_
    _out[1] = -V_E_*_t35 - _t2*_t49 - _t46*delta_v_E_**2 - _t48*_t49 + a_E_*alpha_E_*alpha_N_ + ((1/2))*delta_latitude_*delta_v_E_*(4*R_*V_E_*_t11*_t13*_t14*_t17*_t3*ecc2_ - 4*_t24*_t43 - _t42)
    _out[2] = ((1/2))*_t33*_t57 - _t59
    _out[3] = _t34*(-_t13*_t29*_t61 - _t15*_t28*_t60*_t7 + 2*_t20*_t22*_t23*_t61 - _t26 + _t43*_t60 + _t44*_t6/_t17**3) + _t40*(2*_t10*_t3/_t18 - _t37)
    _out[4] = -_t34*_t57 + _t39*_t66*alpha_N_ + _t47*alpha_N_ + _t59 + _t62*_t63 - _t63*_t67 + ((1/2))*_t65*alpha_E_*alpha_N_ + alpha_N_*gyro_drift_up_
    _out[5] = _t34*(R_*V_E_*_t13*_t14*_t6*ecc2_ + 2*V_E_*_t18*_t20*_t21*_t22*_t23*_t6 - _t19 - _t31 - _t41) - _t36*_t58*delta_v_E_ - _t46*_t71 - _t66*_t70 + _t67*_t68 - _t68*_t69 - alpha_E_*gyro_drift_up_
    _out[6] = _t10*_t71 + _t34*(-_t32 - _t4) + _t40*(2*_t10*_t24 - _t38) + _t62*_t72 - (1/2)*_t65*alpha_N_*alpha_U_ - _t69*_t72 + _t70*(-_t27 - _t5) + alpha_E_*gyro_drift_north_
    return _out


def initial_state(c, u, p):
    """True initial state from navigation initial conditions.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        x(0)
    """
    c = _as_vector(c, 4, 'c', 'initial_state')
    u = _as_vector(u, 3, 'u', 'initial_state')
    p = _as_vector(p, 4, 'p', 'initial_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    v_N_ = c[2]
    v_E_ = c[3]
    _out = _np.zeros((4,) + _batch)
    _out[0] = v_E_
    _out[1] = v_N_
    _out[2] = latitude_
    _out[3] = longitude_
    return _out


def initial_real_state(c, u, w, p):
    """Real-work initial state, initial-error sources applied.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        xr(0)
    """
    c = _as_vector(c, 4, 'c', 'initial_real_state')
    u = _as_vector(u, 3, 'u', 'initial_real_state')
    w = _as_vector(w, 12, 'w', 'initial_real_state')
    p = _as_vector(p, 4, 'p', 'initial_real_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    v_N_ = c[2]
    v_E_ = c[3]
    initial_velocity_error_east_ = w[5]
    initial_velocity_error_north_ = w[6]
    initial_latitude_error_ = w[7]
    initial_longitude_error_ = w[8]
    initial_tilt_east_ = w[9]
    initial_tilt_north_ = w[10]
    initial_azimuth_error_ = w[11]
    _out = _np.zeros((7,) + _batch)
    _out[0] = initial_velocity_error_east_ + v_E_
    _out[1] = initial_velocity_error_north_ + v_N_
    _out[2] = initial_latitude_error_ + latitude_
    _out[3] = initial_longitude_error_ + longitude_
    _out[4] = initial_tilt_east_
    _out[5] = initial_tilt_north_
    _out[6] = initial_azimuth_error_
    return _out


def initial_error_matrix(c, u, p):
    """First-order map from error sources to the initial error state.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        E: xe(0) = E w
    """
    c = _as_vector(c, 4, 'c', 'initial_error_matrix')
    u = _as_vector(u, 3, 'u', 'initial_error_matrix')
    p = _as_vector(p, 4, 'p', 'initial_error_matrix')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    _out = _np.zeros((7, 12) + _batch)
    _out[0, 5] = 1
    _out[1, 6] = 1
    _out[2, 7] = 1
    _out[3, 8] = 1
    _out[4, 9] = 1
    _out[5, 10] = 1
    _out[6, 11] = 1
    return _out


def domain_margins(x, u, p):
    """Margins that must be positive for the formulas to hold (see DOMAIN).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (6, ...)
        one margin per condition of DOMAIN
    """
    x = _as_vector(x, 4, 'x', 'domain_margins')
    u = _as_vector(u, 3, 'u', 'domain_margins')
    p = _as_vector(p, 4, 'p', 'domain_margins')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    phi_ = x[2]
    h_ = u[2]
    R_ = p[0]
    ecc2_ = p[1]
    g_ = p[3]
    _out = _np.zeros((6,) + _batch)
    _out[0] = _m.cos(phi_)**2 - 1e-12
    _out[1] = R_
    _out[2] = g_
    _out[3] = 1 - ecc2_
    _out[4] = ecc2_ + 1e-300
    _out[5] = R_ + h_
    return _out


def initial_domain_margins(c, u, p):
    """Margins that must be positive for the initial conditions.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (3, ...)
        true-motion inputs, SI units
    p : array_like, shape (4, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (6, ...)
        one margin per condition of INITIAL_DOMAIN
    """
    c = _as_vector(c, 4, 'c', 'initial_domain_margins')
    u = _as_vector(u, 3, 'u', 'initial_domain_margins')
    p = _as_vector(p, 4, 'p', 'initial_domain_margins')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    h_ = u[2]
    R_ = p[0]
    ecc2_ = p[1]
    g_ = p[3]
    _out = _np.zeros((6,) + _batch)
    _out[0] = _m.cos(latitude_)**2 - 1e-12
    _out[1] = R_
    _out[2] = g_
    _out[3] = 1 - ecc2_
    _out[4] = ecc2_ + 1e-300
    _out[5] = R_ + h_
    return _out


FUNCTIONS = ('ideal_rhs', 'real_rhs', 'real_rhs_small_angle', 'second_order_small_angle', 'outputs', 'state_matrix', 'source_matrix', 'output_matrix', 'second_order', 'initial_state', 'initial_real_state', 'initial_error_matrix', 'domain_margins', 'initial_domain_margins')
