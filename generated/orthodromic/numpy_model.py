# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/orthodromic.py.
# Edit the model definition and run `make derive` again.

"""numpy functions of the model 'orthodromic' (broadcasting)."""

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
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        time derivative of the true state
    """
    x = _as_vector(x, 8, 'x', 'ideal_rhs')
    u = _as_vector(u, 5, 'u', 'ideal_rhs')
    p = _as_vector(p, 3, 'p', 'ideal_rhs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    V_zeta_ = u[3]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = 1/a_
    _t1 = e2_*u31_**2
    _t2 = -_t0*h_ - (1/2)*_t1 + 1
    _t3 = V_xi_*_t0
    _t4 = V_eta_*_t0
    _t5 = e2_*u11_*u21_
    _t6 = _t3*(_t2 + e2_*u11_**2) + _t4*_t5
    _t7 = -U_*u21_ + _t6
    _t8 = _t3*_t5 + _t4*(_t2 + e2_*u21_**2)
    _t9 = -U_*u11_ - _t8
    _t10 = U_*u31_
    _t11 = U_**2*u31_*(a_ + h_)/_m.sqrt(1 - _t1)
    _out = _np.zeros((8,) + _batch)
    _out[0] = -_t7*u31_
    _out[1] = _t9*u31_
    _out[2] = _t7*u11_ - _t9*u21_
    _out[3] = -_t7*u32_
    _out[4] = _t9*u32_
    _out[5] = _t7*u12_ - _t9*u22_
    _out[6] = V_eta_*_t10 - V_zeta_*_t6 + _t11*u11_ + a_xi_
    _out[7] = -V_xi_*_t10 - V_zeta_*_t8 + _t11*u21_ + a_eta_
    return _out


def real_rhs(xr, x, u, w, p):
    """Real-work equations: dxr/dt (needs the true state x for the platform).

    Parameters
    ----------
    xr : array_like, shape (11, ...)
        real-work state: the 8 computed states in the order of x, then the platform angles alpha_x, alpha_y, alpha_z (rad)
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    w : array_like, shape (26, ...)
        error-source magnitudes, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (11, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 11, 'xr', 'real_rhs')
    x = _as_vector(x, 8, 'x', 'real_rhs')
    u = _as_vector(u, 5, 'u', 'real_rhs')
    w = _as_vector(w, 26, 'w', 'real_rhs')
    p = _as_vector(p, 3, 'p', 'real_rhs')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    u11_c_ = xr[0]
    u21_c_ = xr[1]
    u31_c_ = xr[2]
    u12_c_ = xr[3]
    u22_c_ = xr[4]
    u32_c_ = xr[5]
    V_xi_c_ = xr[6]
    V_eta_c_ = xr[7]
    alpha_x_ = xr[8]
    alpha_y_ = xr[9]
    alpha_z_ = xr[10]
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    h_ = u[4]
    gyro_drift_x_ = w[8]
    gyro_drift_y_ = w[9]
    gyro_drift_z_ = w[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_xi_ = w[13]
    velocity_integrator_offset_eta_ = w[14]
    position_integrator_offset_xi_ = w[15]
    position_integrator_offset_eta_ = w[16]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_xi_ = w[19]
    velocity_integrator_gain_error_eta_ = w[20]
    position_integrator_gain_error_xi_ = w[21]
    position_integrator_gain_error_eta_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    correction_gain_error_z_ = w[25]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = e2_*u31_c_**2
    _t1 = 1/a_
    _t2 = -_t1*h_ + 1
    _t3 = -(1/2)*_t0 + _t2
    _t4 = V_xi_c_*_t1
    _t5 = V_eta_c_*_t1
    _t6 = e2_*u11_c_*u21_c_
    _t7 = _t4*(_t3 + e2_*u11_c_**2) + _t5*_t6
    _t8 = position_integrator_offset_eta_ + (position_integrator_gain_error_eta_ + 1)*(-U_*u21_c_ + _t7)
    _t9 = _t4*_t6 + _t5*(_t3 + e2_*u21_c_**2)
    _t10 = position_integrator_offset_xi_ + (position_integrator_gain_error_xi_ + 1)*(-U_*u11_c_ - _t9)
    _t11 = _m.sin(alpha_y_)
    _t12 = _m.sin(alpha_z_)
    _t13 = _m.cos(alpha_z_)
    _t14 = _t12*a_eta_ + _t13*a_xi_
    _t15 = _m.cos(alpha_y_)
    _t16 = U_*u31_c_
    _t17 = U_**2*u31_c_*(a_ + h_)/_m.sqrt(1 - _t0)
    _t18 = -_t9
    _t19 = _m.cos(alpha_x_)
    _t20 = _m.sin(alpha_x_)
    _t21 = _t2 - (1/2)*e2_*u31_**2
    _t22 = V_xi_*_t1
    _t23 = V_eta_*_t1
    _t24 = e2_*u11_*u21_
    _t25 = _t22*(_t21 + e2_*u11_**2) + _t23*_t24
    _t26 = -_t22*_t24 - _t23*(_t21 + e2_*u21_**2)
    _t27 = _t12*_t25 + _t13*_t26
    _t28 = _t7*(correction_gain_error_y_ + 1) + gyro_drift_y_
    _t29 = _t16*(correction_gain_error_z_ + 1) + gyro_drift_z_
    _t30 = U_*u31_
    _t31 = -_t11*_t27 - _t15*_t30 + _t19*_t29 + _t20*_t28
    _out = _np.zeros((11,) + _batch)
    _out[0] = -_t8*u31_c_
    _out[1] = _t10*u31_c_
    _out[2] = -_t10*u21_c_ + _t8*u11_c_
    _out[3] = -_t8*u32_c_
    _out[4] = _t10*u32_c_
    _out[5] = -_t10*u22_c_ + _t8*u12_c_
    _out[6] = (velocity_integrator_gain_error_xi_ + 1)*(V_eta_c_*_t16 - V_zeta_*_t7 + _t17*u11_c_ + accel_bias_x_ + velocity_integrator_offset_xi_ + (accel_scale_error_x_ + 1)*(-_t11*a_zeta_ + _t14*_t15))
    _out[7] = (velocity_integrator_gain_error_eta_ + 1)*(-V_xi_c_*_t16 + V_zeta_*_t18 + _t17*u21_c_ + accel_bias_y_ + velocity_integrator_offset_eta_ + (accel_scale_error_y_ + 1)*(_t19*(-_t12*a_xi_ + _t13*a_eta_) + _t20*(_t11*_t14 + _t15*a_zeta_)))
    _out[8] = _t11*_t30 - _t15*_t27 + _t18*(correction_gain_error_x_ + 1) + _t31*_m.tan(alpha_y_) + gyro_drift_x_
    _out[9] = _t12*_t26 - _t13*_t25 + _t19*_t28 - _t20*_t29
    _out[10] = _t31/_t15
    return _out


def real_rhs_small_angle(xr, x, u, w, p):
    """Real-work equations with the source's small-angle platform: dxr/dt.

    Parameters
    ----------
    xr : array_like, shape (11, ...)
        real-work state: the 8 computed states in the order of x, then the platform angles alpha_x, alpha_y, alpha_z (rad)
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    w : array_like, shape (26, ...)
        error-source magnitudes, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (11, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 11, 'xr', 'real_rhs_small_angle')
    x = _as_vector(x, 8, 'x', 'real_rhs_small_angle')
    u = _as_vector(u, 5, 'u', 'real_rhs_small_angle')
    w = _as_vector(w, 26, 'w', 'real_rhs_small_angle')
    p = _as_vector(p, 3, 'p', 'real_rhs_small_angle')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    u11_c_ = xr[0]
    u21_c_ = xr[1]
    u31_c_ = xr[2]
    u12_c_ = xr[3]
    u22_c_ = xr[4]
    u32_c_ = xr[5]
    V_xi_c_ = xr[6]
    V_eta_c_ = xr[7]
    alpha_x_ = xr[8]
    alpha_y_ = xr[9]
    alpha_z_ = xr[10]
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    h_ = u[4]
    gyro_drift_x_ = w[8]
    gyro_drift_y_ = w[9]
    gyro_drift_z_ = w[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_xi_ = w[13]
    velocity_integrator_offset_eta_ = w[14]
    position_integrator_offset_xi_ = w[15]
    position_integrator_offset_eta_ = w[16]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_xi_ = w[19]
    velocity_integrator_gain_error_eta_ = w[20]
    position_integrator_gain_error_xi_ = w[21]
    position_integrator_gain_error_eta_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    correction_gain_error_z_ = w[25]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = e2_*u31_c_**2
    _t1 = 1/a_
    _t2 = -_t1*h_ + 1
    _t3 = -(1/2)*_t0 + _t2
    _t4 = V_xi_c_*_t1
    _t5 = V_eta_c_*_t1
    _t6 = e2_*u11_c_*u21_c_
    _t7 = _t4*(_t3 + e2_*u11_c_**2) + _t5*_t6
    _t8 = position_integrator_offset_eta_ + (position_integrator_gain_error_eta_ + 1)*(-U_*u21_c_ + _t7)
    _t9 = _t4*_t6 + _t5*(_t3 + e2_*u21_c_**2)
    _t10 = position_integrator_offset_xi_ + (position_integrator_gain_error_xi_ + 1)*(-U_*u11_c_ - _t9)
    _t11 = U_*u31_c_
    _t12 = U_**2*u31_c_*(a_ + h_)/_m.sqrt(1 - _t0)
    _t13 = -_t9
    _t14 = _t2 - (1/2)*e2_*u31_**2
    _t15 = V_xi_*_t1
    _t16 = V_eta_*_t1
    _t17 = e2_*u11_*u21_
    _t18 = _t15*(_t14 + e2_*u11_**2) + _t16*_t17
    _t19 = U_*u31_
    _t20 = _t15*_t17 + _t16*(_t14 + e2_*u21_**2)
    _t21 = -_t20
    _out = _np.zeros((11,) + _batch)
    _out[0] = -_t8*u31_c_
    _out[1] = _t10*u31_c_
    _out[2] = -_t10*u21_c_ + _t8*u11_c_
    _out[3] = -_t8*u32_c_
    _out[4] = _t10*u32_c_
    _out[5] = -_t10*u22_c_ + _t8*u12_c_
    _out[6] = (velocity_integrator_gain_error_xi_ + 1)*(V_eta_c_*_t11 - V_zeta_*_t7 + _t12*u11_c_ + accel_bias_x_ + velocity_integrator_offset_xi_ + (accel_scale_error_x_ + 1)*(a_eta_*alpha_z_ + a_xi_ - a_zeta_*alpha_y_))
    _out[7] = (velocity_integrator_gain_error_eta_ + 1)*(-V_xi_c_*_t11 + V_zeta_*_t13 + _t12*u21_c_ + accel_bias_y_ + velocity_integrator_offset_eta_ + (accel_scale_error_y_ + 1)*(a_eta_ - a_xi_*alpha_z_ + a_zeta_*alpha_x_))
    _out[8] = _t13*(correction_gain_error_x_ + 1) - _t18*alpha_z_ + _t19*alpha_y_ + _t20 + gyro_drift_x_
    _out[9] = -_t18 - _t19*alpha_x_ + _t21*alpha_z_ + _t7*(correction_gain_error_y_ + 1) + gyro_drift_y_
    _out[10] = _t11*(correction_gain_error_z_ + 1) + _t18*alpha_x_ - _t19 - _t21*alpha_y_ + gyro_drift_z_
    return _out


def second_order_small_angle(x, u, p, xe, w):
    """Second-order term of the error equations of the small-angle platform.

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units
    xe : array_like, shape (11, ...)
        error state xr - (x, 0)
    w : array_like, shape (26, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (11, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 8, 'x', 'second_order_small_angle')
    u = _as_vector(u, 5, 'u', 'second_order_small_angle')
    p = _as_vector(p, 3, 'p', 'second_order_small_angle')
    xe = _as_vector(xe, 11, 'xe', 'second_order_small_angle')
    w = _as_vector(w, 26, 'w', 'second_order_small_angle')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    delta_u11_ = xe[0]
    delta_u21_ = xe[1]
    delta_u31_ = xe[2]
    delta_u12_ = xe[3]
    delta_u22_ = xe[4]
    delta_u32_ = xe[5]
    delta_V_xi_ = xe[6]
    delta_V_eta_ = xe[7]
    alpha_x_ = xe[8]
    alpha_y_ = xe[9]
    alpha_z_ = xe[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_xi_ = w[13]
    velocity_integrator_offset_eta_ = w[14]
    position_integrator_offset_xi_ = w[15]
    position_integrator_offset_eta_ = w[16]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_xi_ = w[19]
    velocity_integrator_gain_error_eta_ = w[20]
    position_integrator_gain_error_xi_ = w[21]
    position_integrator_gain_error_eta_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    correction_gain_error_z_ = w[25]
    _t0 = e2_*u11_**2
    _t1 = 1/a_
    _t2 = u31_**2
    _t3 = _t2*e2_
    _t4 = -_t1*h_ - (1/2)*_t3 + 1
    _t5 = _t0 + _t4
    _t6 = 2*_t1
    _t7 = _t5*_t6
    _t8 = _t3*_t6
    _t9 = _t6*e2_
    _t10 = V_eta_*_t9
    _t11 = _t10*u21_
    _t12 = _t1*e2_
    _t13 = V_xi_*_t12
    _t14 = _t13*u11_
    _t15 = _t11 + 4*_t14
    _t16 = -_t15
    _t17 = 2*U_
    _t18 = -_t10*u11_ + _t17
    _t19 = _t17*u21_
    _t20 = V_xi_*_t7
    _t21 = _t11*u11_
    _t22 = position_integrator_gain_error_eta_*u31_
    _t23 = V_eta_*_t12
    _t24 = _t23*u21_
    _t25 = V_xi_*_t9
    _t26 = _t25*u11_
    _t27 = _t24 + _t26
    _t28 = _t27*delta_u11_
    _t29 = delta_u21_*(-U_ + V_eta_*_t1*e2_*u11_)
    _t30 = delta_u11_**2
    _t31 = _t13*_t30
    _t32 = _t5*delta_V_xi_
    _t33 = _t1*_t32
    _t34 = delta_u31_**2
    _t35 = delta_u11_*delta_u21_
    _t36 = _t23*_t35
    _t37 = _t12*delta_V_eta_
    _t38 = delta_u11_*u21_
    _t39 = _t37*_t38
    _t40 = delta_u21_*u11_
    _t41 = _t37*_t40
    _t42 = u11_*u21_
    _t43 = _t42*delta_u31_
    _t44 = delta_V_xi_*u11_
    _t45 = _t44*delta_u11_
    _t46 = _t45*_t9
    _t47 = _t37*_t42
    _t48 = e2_*u21_**2
    _t49 = _t4 + _t48
    _t50 = _t49*_t6
    _t51 = _t17 + _t25*u21_
    _t52 = -_t51
    _t53 = 4*_t24 + _t26
    _t54 = -_t53
    _t55 = V_eta_*_t50 + _t17*u11_ + _t26*u21_
    _t56 = _t13*u21_
    _t57 = -U_ - _t56
    _t58 = -_t11 - _t14
    _t59 = delta_u21_**2
    _t60 = _t23*_t59
    _t61 = position_integrator_gain_error_xi_*u31_
    _t62 = _t49*delta_V_eta_
    _t63 = _t1*_t62
    _t64 = _t13*_t35
    _t65 = _t12*delta_V_xi_
    _t66 = _t38*_t65
    _t67 = _t40*_t65
    _t68 = delta_V_eta_*u21_
    _t69 = _t68*delta_u21_
    _t70 = _t69*_t9
    _t71 = _t42*_t65
    _t72 = ((1/2))*_t34
    _t73 = 4*_t1
    _t74 = ((1/2))*delta_u21_
    _t75 = _t74*delta_V_eta_
    _t76 = ((1/2))*delta_u11_
    _t77 = _t76*delta_V_xi_
    _t78 = _t23*u11_
    _t79 = _t74*delta_u11_
    _t80 = 2*_t27
    _t81 = -_t19 + _t20 + _t21
    _t82 = 2*_t58
    _t83 = _t29*position_integrator_gain_error_eta_
    _t84 = _t57*delta_u11_*position_integrator_gain_error_xi_
    _t85 = _t63*position_integrator_gain_error_xi_
    _t86 = _t33*position_integrator_gain_error_eta_
    _t87 = delta_u31_*u31_
    _t88 = _t23*_t87
    _t89 = _t13*_t87
    _t90 = _t37*_t87
    _t91 = _t65*_t87
    _t92 = _t61*delta_u31_
    _t93 = _t22*delta_u31_
    _t94 = _t1*delta_u32_
    _t95 = _t28*position_integrator_gain_error_eta_
    _t96 = _t42*delta_u32_
    _t97 = _t58*delta_u21_*position_integrator_gain_error_xi_
    _t98 = _t23*u22_
    _t99 = _t13*u12_
    _t100 = u11_*u12_
    _t101 = u21_*u22_
    _t102 = 4*_t12
    _t103 = _t15*_t76
    _t104 = V_zeta_*_t13
    _t105 = U_**2*(a_ + h_)
    _t106 = 3*_t105
    _t107 = _t106*u11_
    _t108 = 1 - _t3
    _t109 = (1/(_t108*_m.sqrt(_t108)))
    _t110 = _t109*e2_*u31_
    _t111 = e2_**2*u31_**3/(_t108**2*_m.sqrt(_t108))
    _t112 = U_*delta_u31_
    _t113 = a_eta_*alpha_z_
    _t114 = _t17*u31_
    _t115 = V_zeta_*_t9
    _t116 = _t115*_t42
    _t117 = 2*_t105
    _t118 = _t117/_m.sqrt(_t108)
    _t119 = _t109*_t117*_t3
    _t120 = _t118 + _t119
    _t121 = ((1/2))*delta_u31_
    _t122 = _t118*u31_
    _t123 = V_zeta_*u31_
    _t124 = a_zeta_*alpha_y_
    _t125 = V_zeta_*velocity_integrator_gain_error_xi_
    _t126 = V_zeta_*_t23
    _t127 = _t78*delta_u21_
    _t128 = _t106*u21_
    _t129 = a_zeta_*alpha_x_
    _t130 = a_xi_*alpha_z_
    _t131 = V_zeta_*velocity_integrator_gain_error_eta_
    _t132 = _t56*delta_u11_
    _out = _np.zeros((11,) + _batch)
    _out[0] = ((3/2))*V_xi_*_t1*_t34*e2_*u31_ + ((1/2))*_t16*delta_u11_*delta_u31_ + ((1/2))*_t18*delta_u21_*delta_u31_ - _t22*_t28 - _t22*_t29 - _t22*_t33 - _t22*_t47 - _t31*u31_ - _t36*u31_ - _t37*_t43 - _t39*u31_ - _t41*u31_ - _t46*u31_ + ((1/2))*delta_V_xi_*delta_u31_*(-_t7 + _t8) + ((1/2))*delta_u31_*position_integrator_gain_error_eta_*(V_xi_*_t8 + _t19 - _t20 - _t21) - delta_u31_*position_integrator_offset_eta_
    _out[1] = ((3/2))*V_eta_*_t1*_t34*e2_*u31_ - _t43*_t65 + ((1/2))*_t52*delta_u11_*delta_u31_ + ((1/2))*_t54*delta_u21_*delta_u31_ + _t57*delta_u11_*position_integrator_gain_error_xi_*u31_ + _t58*delta_u21_*position_integrator_gain_error_xi_*u31_ - _t60*u31_ - _t61*_t63 - _t61*_t71 - _t64*u31_ - _t66*u31_ - _t67*u31_ - _t70*u31_ + ((1/2))*delta_V_eta_*delta_u31_*(-_t50 + _t8) + ((1/2))*delta_u31_*position_integrator_gain_error_xi_*(2*V_eta_*_t1*_t2*e2_ - _t55) + delta_u31_*position_integrator_offset_xi_
    _out[2] = _t0*_t1*_t68*position_integrator_gain_error_eta_ + _t1*_t44*_t48*position_integrator_gain_error_xi_ - _t14*_t93 - _t24*_t92 + ((1/2))*_t30*(_t11 + 6*_t14) + _t38*_t9*delta_V_eta_*u11_ + _t40*_t9*delta_V_xi_*u21_ + ((1/2))*_t59*(6*_t24 + _t26) + _t72*(-_t14 - _t24) + _t74*position_integrator_gain_error_xi_*(_t55 - _t82*u21_) + _t75*(_t0*_t6 + _t48*_t73 + _t50) + _t76*position_integrator_gain_error_eta_*(_t80*u11_ + _t81) + _t77*(_t0*_t73 + _t48*_t6 + _t7) + _t79*(4*_t56 + 4*_t78) + _t83*u11_ - _t84*u21_ + _t85*u21_ + _t86*u11_ - _t88*delta_u21_ - _t89*delta_u11_ - _t90*u21_ - _t91*u11_ + delta_u11_*position_integrator_offset_eta_ - delta_u21_*position_integrator_offset_xi_
    _out[3] = ((1/2))*V_xi_*_t1*_t34*e2_*u32_ + V_xi_*_t1*delta_u31_*delta_u32_*e2_*u31_ + V_xi_*_t1*delta_u31_*e2_*position_integrator_gain_error_eta_*u31_*u32_ + _t1*delta_V_xi_*delta_u31_*e2_*u31_*u32_ + ((1/2))*_t16*delta_u11_*delta_u32_ + ((1/2))*_t18*delta_u21_*delta_u32_ - _t31*u32_ - _t32*_t94 - _t36*u32_ - _t37*_t96 - _t39*u32_ - _t41*u32_ - _t46*u32_ - _t47*position_integrator_gain_error_eta_*u32_ - (1/2)*_t81*delta_u32_*position_integrator_gain_error_eta_ - _t83*u32_ - _t86*u32_ - _t95*u32_ - delta_u32_*position_integrator_offset_eta_
    _out[4] = _t23*_t72*u32_ + _t23*_t92*u32_ + _t52*_t76*delta_u32_ + _t54*_t74*delta_u32_ - (1/2)*_t55*delta_u32_*position_integrator_gain_error_xi_ - _t60*u32_ - _t62*_t94 - _t64*u32_ - _t65*_t96 - _t66*u32_ - _t67*u32_ - _t70*u32_ - _t71*position_integrator_gain_error_xi_*u32_ + _t84*u32_ - _t85*u32_ + _t88*delta_u32_ + _t90*u32_ + _t97*u32_ + delta_u32_*position_integrator_offset_xi_
    _out[5] = _t100*_t37*position_integrator_gain_error_eta_*u21_ + _t101*_t65*position_integrator_gain_error_xi_*u11_ + _t103*delta_u12_ - _t18*_t74*delta_u12_ + _t30*_t99 + _t33*delta_u12_ + _t39*u12_ + _t47*delta_u12_ + _t51*_t76*delta_u22_ + _t53*_t74*delta_u22_ + ((1/2))*_t55*delta_u22_*position_integrator_gain_error_xi_ + _t59*_t98 + _t63*delta_u22_ + _t67*u22_ + _t71*delta_u22_ + _t72*(-_t98 - _t99) + _t75*(_t100*_t9 + _t101*_t102) + _t77*(_t100*_t102 + _t101*_t9) + _t79*(_t10*u12_ + _t25*u22_) + ((1/2))*_t81*delta_u12_*position_integrator_gain_error_eta_ + _t83*u12_ - _t84*u22_ + _t85*u22_ + _t86*u12_ - _t88*delta_u22_ - _t89*delta_u12_ - _t90*u22_ - _t91*u12_ - _t92*_t98 - _t93*_t99 + _t95*u12_ - _t97*u22_ + delta_u12_*position_integrator_offset_eta_ - delta_u22_*position_integrator_offset_xi_
    _out[6] = -V_zeta_*_t39 - V_zeta_*_t41 + V_zeta_*_t91 - _t104*_t30 + _t112*delta_V_eta_ + _t113*accel_scale_error_x_ + _t113*velocity_integrator_gain_error_xi_ - _t115*_t45 + _t120*_t121*delta_u11_ + _t121*velocity_integrator_gain_error_xi_*(V_eta_*_t17 + _t118*u11_ + _t119*u11_ + _t123*_t25) - _t124*accel_scale_error_x_ - _t124*velocity_integrator_gain_error_xi_ - _t125*_t127 - _t125*_t33 - _t126*_t35 + _t72*(_t104 + _t107*_t110 + _t107*_t111) + _t76*velocity_integrator_gain_error_xi_*(-V_zeta_*_t80 + _t122) + a_xi_*accel_scale_error_x_*velocity_integrator_gain_error_xi_ + accel_bias_x_*velocity_integrator_gain_error_xi_ + ((1/2))*delta_V_eta_*velocity_integrator_gain_error_xi_*(_t114 - _t116) + velocity_integrator_gain_error_xi_*velocity_integrator_offset_xi_
    _out[7] = -V_zeta_*_t66 - V_zeta_*_t67 + V_zeta_*_t90 - _t104*_t35 - _t112*delta_V_xi_ - _t115*_t69 + _t120*_t121*delta_u21_ + _t121*velocity_integrator_gain_error_eta_*(-V_xi_*_t17 + _t10*_t123 + _t118*u21_ + _t119*u21_) - _t126*_t59 + _t129*accel_scale_error_y_ + _t129*velocity_integrator_gain_error_eta_ - _t130*accel_scale_error_y_ - _t130*velocity_integrator_gain_error_eta_ - _t131*_t132 - _t131*_t63 + _t72*(_t110*_t128 + _t111*_t128 + _t126) + _t74*velocity_integrator_gain_error_eta_*(V_zeta_*_t82 + _t122) + a_eta_*accel_scale_error_y_*velocity_integrator_gain_error_eta_ + accel_bias_y_*velocity_integrator_gain_error_eta_ + ((1/2))*delta_V_xi_*velocity_integrator_gain_error_eta_*(-_t114 - _t116) + velocity_integrator_gain_error_eta_*velocity_integrator_offset_eta_
    _out[8] = ((1/2))*V_eta_*_t1*_t34*e2_ + V_eta_*_t1*correction_gain_error_x_*delta_u31_*e2_*u31_ + _t1*delta_V_eta_*delta_u31_*e2_*u31_ - _t132*correction_gain_error_x_ + ((1/2))*_t54*correction_gain_error_x_*delta_u21_ - _t60 - _t63*correction_gain_error_x_ - _t64 - _t66 - _t67 - _t70 - _t71*correction_gain_error_x_
    _out[9] = _t103*correction_gain_error_y_ + _t127*correction_gain_error_y_ - _t13*_t72 + _t31 + _t33*correction_gain_error_y_ + _t36 + _t39 + _t41 + _t46 + _t47*correction_gain_error_y_ - _t89*correction_gain_error_y_ - _t91
    _out[10] = _t112*correction_gain_error_z_
    return _out


def outputs(x, u, p):
    """Navigation outputs of a state (true or computed part of xr).

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        outputs in SI units
    """
    x = _as_vector(x, 8, 'x', 'outputs')
    u = _as_vector(u, 5, 'u', 'outputs')
    p = _as_vector(p, 3, 'p', 'outputs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = u31_**2
    _t1 = u11_**2
    _t2 = u21_**2
    _t3 = 1/_m.sqrt(_t1 + _t2)
    _t4 = 1/a_
    _t5 = _t0*e2_
    _t6 = -_t4*h_ - (1/2)*_t5 + 1
    _t7 = V_eta_*_t4
    _t8 = V_xi_*_t4
    _t9 = e2_*u11_*u21_
    _t10 = -U_*u11_ - _t7*(_t2*e2_ + _t6) - _t8*_t9
    _t11 = _t3*(-U_*u21_ + _t7*_t9 + _t8*(_t1*e2_ + _t6))
    _t12 = _t10*_t3*u11_ + _t11*u21_
    _t13 = _t10*_t3*u21_ - _t11*u11_
    _t14 = 1 - _t5
    _t15 = a_ + h_
    _out = _np.zeros((7,) + _batch)
    _out[0] = _m.arctan2(u31_, _m.sqrt(1 - _t0))
    _out[1] = _m.arctan2(-u32_, u11_*u22_ - u12_*u21_)
    _out[2] = _m.arctan2(u21_, u11_)
    _out[3] = _t12
    _out[4] = _t13
    _out[5] = -_t13*_t15*(1 - e2_)/(_t14*_m.sqrt(_t14))
    _out[6] = _t12*_t15/_m.sqrt(_t14)
    return _out


def state_matrix(x, u, p):
    """State matrix F of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (11, 11, ...)
        F
    """
    x = _as_vector(x, 8, 'x', 'state_matrix')
    u = _as_vector(u, 5, 'u', 'state_matrix')
    p = _as_vector(p, 3, 'p', 'state_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = 1/a_
    _t1 = _t0*e2_
    _t2 = V_eta_*_t1
    _t3 = _t2*u21_
    _t4 = V_xi_*_t1
    _t5 = _t4*u11_
    _t6 = _t3 + 2*_t5
    _t7 = -U_ + V_eta_*_t0*e2_*u11_
    _t8 = U_*u21_
    _t9 = e2_*u11_**2
    _t10 = u31_**2
    _t11 = _t10*e2_
    _t12 = -_t0*h_ - (1/2)*_t11 + 1
    _t13 = _t0*(_t12 + _t9)
    _t14 = V_xi_*_t13
    _t15 = _t3*u11_
    _t16 = _t1*u11_*u21_
    _t17 = -_t16*u31_
    _t18 = _t4*u21_
    _t19 = -U_ - _t18
    _t20 = -2*_t3 - _t5
    _t21 = e2_*u21_**2
    _t22 = _t0*(_t12 + _t21)
    _t23 = V_eta_*_t22 + _t18*u11_
    _t24 = U_*u11_ + _t23
    _t25 = _t14 + _t15
    _t26 = _t25 - _t8
    _t27 = _t4*u31_
    _t28 = -_t16*u32_
    _t29 = _t2*u31_
    _t30 = 1 - _t11
    _t31 = U_**2*(a_ + h_)
    _t32 = _t31/_m.sqrt(_t30)
    _t33 = _t32*u31_
    _t34 = _t2*u11_
    _t35 = _t11*_t31/(_t30*_m.sqrt(_t30))
    _t36 = U_*u31_
    _t37 = V_zeta_*_t16
    _out = _np.zeros((11, 11) + _batch)
    _out[0, 0] = -_t6*u31_
    _out[0, 1] = -_t7*u31_
    _out[0, 2] = V_xi_*_t0*_t11 - _t14 - _t15 + _t8
    _out[0, 6] = -_t13*u31_
    _out[0, 7] = _t17
    _out[1, 0] = _t19*u31_
    _out[1, 1] = _t20*u31_
    _out[1, 2] = V_eta_*_t0*_t10*e2_ - _t24
    _out[1, 6] = _t17
    _out[1, 7] = -_t22*u31_
    _out[2, 0] = -_t19*u21_ + _t26 + _t6*u11_
    _out[2, 1] = -_t20*u21_ + _t24 + _t7*u11_
    _out[2, 2] = -_t3*u31_ - _t5*u31_
    _out[2, 6] = _t0*_t21*u11_ + _t13*u11_
    _out[2, 7] = _t0*_t9*u21_ + _t22*u21_
    _out[3, 0] = -_t6*u32_
    _out[3, 1] = -_t7*u32_
    _out[3, 2] = _t27*u32_
    _out[3, 5] = -_t26
    _out[3, 6] = -_t13*u32_
    _out[3, 7] = _t28
    _out[4, 0] = _t19*u32_
    _out[4, 1] = _t20*u32_
    _out[4, 2] = _t29*u32_
    _out[4, 5] = -_t24
    _out[4, 6] = _t28
    _out[4, 7] = -_t22*u32_
    _out[5, 0] = -_t19*u22_ + _t6*u12_
    _out[5, 1] = -_t20*u22_ + _t7*u12_
    _out[5, 2] = -_t27*u12_ - _t29*u22_
    _out[5, 3] = _t26
    _out[5, 4] = _t24
    _out[5, 6] = _t13*u12_ + _t16*u22_
    _out[5, 7] = _t16*u12_ + _t22*u22_
    _out[6, 0] = -V_zeta_*_t6 + _t33
    _out[6, 1] = -V_zeta_*_t34
    _out[6, 2] = U_*V_eta_ + V_zeta_*_t27 + _t32*u11_ + _t35*u11_
    _out[6, 6] = -V_zeta_*_t13
    _out[6, 7] = _t36 - _t37
    _out[6, 9] = -a_zeta_
    _out[6, 10] = a_eta_
    _out[7, 0] = -V_zeta_*_t18
    _out[7, 1] = V_zeta_*_t20 + _t33
    _out[7, 2] = -U_*V_xi_ + V_zeta_*_t29 + _t32*u21_ + _t35*u21_
    _out[7, 6] = -_t36 - _t37
    _out[7, 7] = -V_zeta_*_t22
    _out[7, 8] = a_zeta_
    _out[7, 10] = -a_xi_
    _out[8, 0] = -_t18
    _out[8, 1] = _t20
    _out[8, 2] = _t29
    _out[8, 6] = -_t16
    _out[8, 7] = -_t22
    _out[8, 9] = _t36
    _out[8, 10] = -_t25
    _out[9, 0] = _t6
    _out[9, 1] = _t34
    _out[9, 2] = -_t27
    _out[9, 6] = _t13
    _out[9, 7] = _t16
    _out[9, 8] = -_t36
    _out[9, 10] = -_t23
    _out[10, 2] = U_
    _out[10, 8] = _t25
    _out[10, 9] = _t23
    return _out


def source_matrix(x, u, p):
    """Error-source matrix G of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (11, 26, ...)
        G
    """
    x = _as_vector(x, 8, 'x', 'source_matrix')
    u = _as_vector(u, 5, 'u', 'source_matrix')
    p = _as_vector(p, 3, 'p', 'source_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    V_zeta_ = u[3]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = 1/a_
    _t1 = e2_*u31_**2
    _t2 = -_t0*h_ - (1/2)*_t1 + 1
    _t3 = V_xi_*_t0
    _t4 = V_eta_*_t0
    _t5 = e2_*u11_*u21_
    _t6 = _t3*(_t2 + e2_*u11_**2) + _t4*_t5
    _t7 = -U_*u21_ + _t6
    _t8 = _t3*_t5 + _t4*(_t2 + e2_*u21_**2)
    _t9 = -U_*u11_ - _t8
    _t10 = U_*u31_
    _t11 = U_**2*u31_*(a_ + h_)/_m.sqrt(1 - _t1)
    _t12 = -_t8
    _out = _np.zeros((11, 26) + _batch)
    _out[0, 16] = -u31_
    _out[0, 22] = -_t7*u31_
    _out[1, 15] = u31_
    _out[1, 21] = _t9*u31_
    _out[2, 15] = -u21_
    _out[2, 16] = u11_
    _out[2, 21] = -_t9*u21_
    _out[2, 22] = _t7*u11_
    _out[3, 16] = -u32_
    _out[3, 22] = -_t7*u32_
    _out[4, 15] = u32_
    _out[4, 21] = _t9*u32_
    _out[5, 15] = -u22_
    _out[5, 16] = u12_
    _out[5, 21] = -_t9*u22_
    _out[5, 22] = _t7*u12_
    _out[6, 11] = 1
    _out[6, 13] = 1
    _out[6, 17] = a_xi_
    _out[6, 19] = V_eta_*_t10 - V_zeta_*_t6 + _t11*u11_ + a_xi_
    _out[7, 12] = 1
    _out[7, 14] = 1
    _out[7, 18] = a_eta_
    _out[7, 20] = -V_xi_*_t10 + V_zeta_*_t12 + _t11*u21_ + a_eta_
    _out[8, 8] = 1
    _out[8, 23] = _t12
    _out[9, 9] = 1
    _out[9, 24] = _t6
    _out[10, 10] = 1
    _out[10, 25] = _t10
    return _out


def output_matrix(x, u, p):
    """Output matrix H: output errors = H xe to first order.

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 11, ...)
        H
    """
    x = _as_vector(x, 8, 'x', 'output_matrix')
    u = _as_vector(u, 5, 'u', 'output_matrix')
    p = _as_vector(p, 3, 'p', 'output_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = u31_**2
    _t1 = _m.sqrt(1 - _t0)
    _t2 = u11_*u22_ - u12_*u21_
    _t3 = 1/(_t2**2 + u32_**2)
    _t4 = _t3*u32_
    _t5 = u11_**2
    _t6 = u21_**2
    _t7 = _t5 + _t6
    _t8 = 1/_t7
    _t9 = 1/_m.sqrt(_t7)
    _t10 = _t6*e2_
    _t11 = 1/a_
    _t12 = _t0*e2_
    _t13 = -_t11*h_ - (1/2)*_t12 + 1
    _t14 = _t10 + _t13
    _t15 = V_eta_*_t11
    _t16 = V_xi_*_t11
    _t17 = e2_*u21_
    _t18 = _t16*_t17
    _t19 = -U_*u11_ - _t14*_t15 - _t18*u11_
    _t20 = _t19*_t9
    _t21 = -U_ - _t18
    _t22 = _t9*u11_
    _t23 = _t15*_t17
    _t24 = _t16*e2_*u11_
    _t25 = _t23 + 2*_t24
    _t26 = _t9*u21_
    _t27 = (1/(_t7*_m.sqrt(_t7)))
    _t28 = _t5*e2_
    _t29 = _t13 + _t28
    _t30 = -U_*u21_ + _t16*_t29 + _t23*u11_
    _t31 = _t27*u11_*u21_
    _t32 = _t30*_t31
    _t33 = -_t19*_t27*_t5 + _t20 + _t21*_t22 + _t25*_t26 - _t32
    _t34 = _t30*_t9
    _t35 = -2*_t23 - _t24
    _t36 = -U_ + V_eta_*_t11*e2_*u11_
    _t37 = _t27*_t6
    _t38 = _t19*_t31
    _t39 = _t22*_t35 + _t26*_t36 - _t30*_t37 + _t34 - _t38
    _t40 = e2_*u31_
    _t41 = _t15*_t40
    _t42 = _t16*_t40
    _t43 = _t22*_t41 - _t26*_t42
    _t44 = _t11*_t26*_t28
    _t45 = _t11*_t29*_t9*u21_ - _t44
    _t46 = _t11*_t14
    _t47 = _t10*_t11*_t22
    _t48 = -_t22*_t46 + _t47
    _t49 = _t21*_t9*u21_ - _t22*_t25 + _t27*_t30*_t5 - _t34 - _t38
    _t50 = -_t19*_t37 + _t20 - _t22*_t36 + _t26*_t35 + _t32
    _t51 = _t22*_t42 + _t26*_t41
    _t52 = -_t11*_t22*_t29 - _t47
    _t53 = -_t26*_t46 - _t44
    _t54 = 1 - e2_
    _t55 = a_ + h_
    _t56 = 1 - _t12
    _t57 = _t55/(_t56*_m.sqrt(_t56))
    _t58 = _t54*_t57
    _t59 = _t55/_m.sqrt(_t56)
    _out = _np.zeros((7, 11) + _batch)
    _out[0, 2] = _t0/_t1 + _t1
    _out[1, 0] = _t4*u22_
    _out[1, 1] = -_t4*u12_
    _out[1, 3] = -_t4*u21_
    _out[1, 4] = _t4*u11_
    _out[1, 5] = -_t2*_t3
    _out[2, 0] = -_t8*u21_
    _out[2, 1] = _t8*u11_
    _out[3, 0] = _t33
    _out[3, 1] = _t39
    _out[3, 2] = _t43
    _out[3, 6] = _t45
    _out[3, 7] = _t48
    _out[4, 0] = _t49
    _out[4, 1] = _t50
    _out[4, 2] = _t51
    _out[4, 6] = _t52
    _out[4, 7] = _t53
    _out[5, 0] = -_t49*_t58
    _out[5, 1] = -_t50*_t58
    _out[5, 2] = -3*_t40*_t54*_t55*(_t19*_t9*u21_ - _t34*u11_)/(_t56**2*_m.sqrt(_t56)) - _t51*_t58
    _out[5, 6] = -_t52*_t58
    _out[5, 7] = -_t53*_t58
    _out[6, 0] = _t33*_t59
    _out[6, 1] = _t39*_t59
    _out[6, 2] = _t40*_t57*(_t20*u11_ + _t34*u21_) + _t43*_t59
    _out[6, 6] = _t45*_t59
    _out[6, 7] = _t48*_t59
    return _out


def second_order(x, u, p, xe, w):
    """Second-order term of the error equations (refined model).

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units
    xe : array_like, shape (11, ...)
        error state xr - (x, 0)
    w : array_like, shape (26, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (11, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 8, 'x', 'second_order')
    u = _as_vector(u, 5, 'u', 'second_order')
    p = _as_vector(p, 3, 'p', 'second_order')
    xe = _as_vector(xe, 11, 'xe', 'second_order')
    w = _as_vector(w, 26, 'w', 'second_order')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    u11_ = x[0]
    u21_ = x[1]
    u31_ = x[2]
    u12_ = x[3]
    u22_ = x[4]
    u32_ = x[5]
    V_xi_ = x[6]
    V_eta_ = x[7]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    delta_u11_ = xe[0]
    delta_u21_ = xe[1]
    delta_u31_ = xe[2]
    delta_u12_ = xe[3]
    delta_u22_ = xe[4]
    delta_u32_ = xe[5]
    delta_V_xi_ = xe[6]
    delta_V_eta_ = xe[7]
    alpha_x_ = xe[8]
    alpha_y_ = xe[9]
    alpha_z_ = xe[10]
    gyro_drift_y_ = w[9]
    gyro_drift_z_ = w[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_xi_ = w[13]
    velocity_integrator_offset_eta_ = w[14]
    position_integrator_offset_xi_ = w[15]
    position_integrator_offset_eta_ = w[16]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_xi_ = w[19]
    velocity_integrator_gain_error_eta_ = w[20]
    position_integrator_gain_error_xi_ = w[21]
    position_integrator_gain_error_eta_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    correction_gain_error_z_ = w[25]
    _t0 = e2_*u11_**2
    _t1 = 1/a_
    _t2 = u31_**2
    _t3 = _t2*e2_
    _t4 = -_t1*h_ - (1/2)*_t3 + 1
    _t5 = _t0 + _t4
    _t6 = 2*_t1
    _t7 = _t5*_t6
    _t8 = _t3*_t6
    _t9 = _t6*e2_
    _t10 = V_eta_*_t9
    _t11 = _t10*u21_
    _t12 = V_xi_*_t1
    _t13 = _t12*e2_
    _t14 = _t13*u11_
    _t15 = _t11 + 4*_t14
    _t16 = -_t15
    _t17 = 2*U_
    _t18 = -_t10*u11_ + _t17
    _t19 = _t17*u21_
    _t20 = V_xi_*_t7
    _t21 = _t11*u11_
    _t22 = position_integrator_gain_error_eta_*u31_
    _t23 = V_eta_*_t1
    _t24 = _t23*e2_
    _t25 = _t24*u21_
    _t26 = V_xi_*_t9
    _t27 = _t26*u11_
    _t28 = _t25 + _t27
    _t29 = _t28*delta_u11_
    _t30 = delta_u21_*(-U_ + V_eta_*_t1*e2_*u11_)
    _t31 = delta_u11_**2
    _t32 = _t13*_t31
    _t33 = _t5*delta_V_xi_
    _t34 = _t1*_t33
    _t35 = delta_u31_**2
    _t36 = delta_u11_*delta_u21_
    _t37 = _t24*_t36
    _t38 = _t1*e2_
    _t39 = _t38*delta_V_eta_
    _t40 = delta_u11_*u21_
    _t41 = _t39*_t40
    _t42 = delta_u21_*u11_
    _t43 = _t39*_t42
    _t44 = u11_*u21_
    _t45 = _t44*delta_u31_
    _t46 = delta_V_xi_*u11_
    _t47 = _t46*delta_u11_
    _t48 = _t47*_t9
    _t49 = _t39*_t44
    _t50 = e2_*u21_**2
    _t51 = _t4 + _t50
    _t52 = _t51*_t6
    _t53 = _t17 + _t26*u21_
    _t54 = -_t53
    _t55 = 4*_t25 + _t27
    _t56 = -_t55
    _t57 = V_eta_*_t52 + _t17*u11_ + _t27*u21_
    _t58 = _t13*u21_
    _t59 = -U_ - _t58
    _t60 = -_t11 - _t14
    _t61 = delta_u21_**2
    _t62 = _t24*_t61
    _t63 = position_integrator_gain_error_xi_*u31_
    _t64 = _t51*delta_V_eta_
    _t65 = _t1*_t64
    _t66 = _t13*_t36
    _t67 = _t38*delta_V_xi_
    _t68 = _t40*_t67
    _t69 = _t42*_t67
    _t70 = delta_V_eta_*u21_
    _t71 = _t70*delta_u21_
    _t72 = _t71*_t9
    _t73 = _t44*_t67
    _t74 = ((1/2))*_t35
    _t75 = 4*_t1
    _t76 = ((1/2))*delta_u21_
    _t77 = _t76*delta_V_eta_
    _t78 = ((1/2))*delta_u11_
    _t79 = _t78*delta_V_xi_
    _t80 = _t24*u11_
    _t81 = _t76*delta_u11_
    _t82 = 2*_t28
    _t83 = _t20 + _t21
    _t84 = -_t19 + _t83
    _t85 = 2*_t60
    _t86 = _t30*position_integrator_gain_error_eta_
    _t87 = _t59*delta_u11_*position_integrator_gain_error_xi_
    _t88 = _t65*position_integrator_gain_error_xi_
    _t89 = _t34*position_integrator_gain_error_eta_
    _t90 = delta_u31_*u31_
    _t91 = _t24*_t90
    _t92 = _t13*_t90
    _t93 = _t39*_t90
    _t94 = _t67*_t90
    _t95 = _t63*delta_u31_
    _t96 = _t22*delta_u31_
    _t97 = _t1*delta_u32_
    _t98 = _t29*position_integrator_gain_error_eta_
    _t99 = _t44*_t97*e2_
    _t100 = _t60*delta_u21_*position_integrator_gain_error_xi_
    _t101 = _t24*_t74
    _t102 = _t24*u22_
    _t103 = _t13*u12_
    _t104 = u11_*u12_
    _t105 = u21_*u22_
    _t106 = _t75*e2_
    _t107 = _t15*_t78
    _t108 = V_zeta_*_t13
    _t109 = U_**2*(a_ + h_)
    _t110 = 3*_t109
    _t111 = _t110*u11_
    _t112 = 1 - _t3
    _t113 = (1/(_t112*_m.sqrt(_t112)))
    _t114 = _t113*e2_*u31_
    _t115 = e2_**2*u31_**3/(_t112**2*_m.sqrt(_t112))
    _t116 = alpha_y_**2
    _t117 = ((1/2))*a_xi_
    _t118 = alpha_z_**2
    _t119 = U_*delta_u31_
    _t120 = a_eta_*alpha_z_
    _t121 = _t17*u31_
    _t122 = V_zeta_*_t9
    _t123 = _t122*_t44
    _t124 = 2*_t109
    _t125 = _t124/_m.sqrt(_t112)
    _t126 = _t113*_t124*_t3
    _t127 = _t125 + _t126
    _t128 = ((1/2))*delta_u31_
    _t129 = _t125*u31_
    _t130 = V_zeta_*u31_
    _t131 = a_zeta_*alpha_y_
    _t132 = V_zeta_*velocity_integrator_gain_error_xi_
    _t133 = V_zeta_*_t24
    _t134 = _t80*delta_u21_
    _t135 = alpha_x_**2
    _t136 = ((1/2))*a_eta_
    _t137 = _t110*u21_
    _t138 = a_xi_*alpha_z_
    _t139 = V_zeta_*velocity_integrator_gain_error_eta_
    _t140 = _t58*delta_u11_
    _t141 = _t23*_t51 + _t58*u11_
    _t142 = ((1/2))*_t116
    _t143 = ((1/2))*_t118
    _t144 = ((1/2))*_t83
    _t145 = U_*u31_
    _t146 = _t145*correction_gain_error_z_
    _t147 = _t12*_t5 + _t25*u11_
    _t148 = ((1/2))*_t135
    _out = _np.zeros((11,) + _batch)
    _out[0] = ((3/2))*V_xi_*_t1*_t35*e2_*u31_ + ((1/2))*_t16*delta_u11_*delta_u31_ + ((1/2))*_t18*delta_u21_*delta_u31_ - _t22*_t29 - _t22*_t30 - _t22*_t34 - _t22*_t49 - _t32*u31_ - _t37*u31_ - _t39*_t45 - _t41*u31_ - _t43*u31_ - _t48*u31_ + ((1/2))*delta_V_xi_*delta_u31_*(-_t7 + _t8) + ((1/2))*delta_u31_*position_integrator_gain_error_eta_*(V_xi_*_t8 + _t19 - _t20 - _t21) - delta_u31_*position_integrator_offset_eta_
    _out[1] = ((3/2))*V_eta_*_t1*_t35*e2_*u31_ - _t45*_t67 + ((1/2))*_t54*delta_u11_*delta_u31_ + ((1/2))*_t56*delta_u21_*delta_u31_ + _t59*delta_u11_*position_integrator_gain_error_xi_*u31_ + _t60*delta_u21_*position_integrator_gain_error_xi_*u31_ - _t62*u31_ - _t63*_t65 - _t63*_t73 - _t66*u31_ - _t68*u31_ - _t69*u31_ - _t72*u31_ + ((1/2))*delta_V_eta_*delta_u31_*(-_t52 + _t8) + ((1/2))*delta_u31_*position_integrator_gain_error_xi_*(2*V_eta_*_t1*_t2*e2_ - _t57) + delta_u31_*position_integrator_offset_xi_
    _out[2] = _t0*_t1*_t70*position_integrator_gain_error_eta_ + _t1*_t46*_t50*position_integrator_gain_error_xi_ - _t14*_t96 - _t25*_t95 + ((1/2))*_t31*(_t11 + 6*_t14) + _t40*_t9*delta_V_eta_*u11_ + _t42*_t9*delta_V_xi_*u21_ + ((1/2))*_t61*(6*_t25 + _t27) + _t74*(-_t14 - _t25) + _t76*position_integrator_gain_error_xi_*(_t57 - _t85*u21_) + _t77*(_t0*_t6 + _t50*_t75 + _t52) + _t78*position_integrator_gain_error_eta_*(_t82*u11_ + _t84) + _t79*(_t0*_t75 + _t50*_t6 + _t7) + _t81*(4*_t58 + 4*_t80) + _t86*u11_ - _t87*u21_ + _t88*u21_ + _t89*u11_ - _t91*delta_u21_ - _t92*delta_u11_ - _t93*u21_ - _t94*u11_ + delta_u11_*position_integrator_offset_eta_ - delta_u21_*position_integrator_offset_xi_
    _out[3] = ((1/2))*V_xi_*_t1*_t35*e2_*u32_ + V_xi_*_t1*delta_u31_*delta_u32_*e2_*u31_ + V_xi_*_t1*delta_u31_*e2_*position_integrator_gain_error_eta_*u31_*u32_ + _t1*delta_V_xi_*delta_u31_*e2_*u31_*u32_ + ((1/2))*_t16*delta_u11_*delta_u32_ + ((1/2))*_t18*delta_u21_*delta_u32_ - _t32*u32_ - _t33*_t97 - _t37*u32_ - _t41*u32_ - _t43*u32_ - _t48*u32_ - _t49*position_integrator_gain_error_eta_*u32_ - (1/2)*_t84*delta_u32_*position_integrator_gain_error_eta_ - _t86*u32_ - _t89*u32_ - _t98*u32_ - _t99*delta_V_eta_ - delta_u32_*position_integrator_offset_eta_
    _out[4] = _t100*u32_ + _t101*u32_ + _t24*_t95*u32_ + _t54*_t78*delta_u32_ + _t56*_t76*delta_u32_ - (1/2)*_t57*delta_u32_*position_integrator_gain_error_xi_ - _t62*u32_ - _t64*_t97 - _t66*u32_ - _t68*u32_ - _t69*u32_ - _t72*u32_ - _t73*position_integrator_gain_error_xi_*u32_ + _t87*u32_ - _t88*u32_ + _t91*delta_u32_ + _t93*u32_ - _t99*delta_V_xi_ + delta_u32_*position_integrator_offset_xi_
    _out[5] = -_t100*u22_ + _t102*_t61 - _t102*_t95 + _t103*_t31 - _t103*_t96 + _t104*_t39*position_integrator_gain_error_eta_*u21_ + _t105*_t67*position_integrator_gain_error_xi_*u11_ + _t107*delta_u12_ - _t18*_t76*delta_u12_ + _t34*delta_u12_ + _t41*u12_ + _t49*delta_u12_ + _t53*_t78*delta_u22_ + _t55*_t76*delta_u22_ + ((1/2))*_t57*delta_u22_*position_integrator_gain_error_xi_ + _t65*delta_u22_ + _t69*u22_ + _t73*delta_u22_ + _t74*(-_t102 - _t103) + _t77*(_t104*_t9 + _t105*_t106) + _t79*(_t104*_t106 + _t105*_t9) + _t81*(_t10*u12_ + _t26*u22_) + ((1/2))*_t84*delta_u12_*position_integrator_gain_error_eta_ + _t86*u12_ - _t87*u22_ + _t88*u22_ + _t89*u12_ - _t91*delta_u22_ - _t92*delta_u12_ - _t93*u22_ - _t94*u12_ + _t98*u12_ + delta_u12_*position_integrator_offset_eta_ - delta_u22_*position_integrator_offset_xi_
    _out[6] = -V_zeta_*_t41 - V_zeta_*_t43 + V_zeta_*_t94 - _t108*_t31 - _t116*_t117 - _t117*_t118 + _t119*delta_V_eta_ + _t120*accel_scale_error_x_ + _t120*velocity_integrator_gain_error_xi_ - _t122*_t47 + _t127*_t128*delta_u11_ + _t128*velocity_integrator_gain_error_xi_*(V_eta_*_t17 + _t125*u11_ + _t126*u11_ + _t130*_t26) - _t131*accel_scale_error_x_ - _t131*velocity_integrator_gain_error_xi_ - _t132*_t134 - _t132*_t34 - _t133*_t36 + _t74*(_t108 + _t111*_t114 + _t111*_t115) + _t78*velocity_integrator_gain_error_xi_*(-V_zeta_*_t82 + _t129) + a_xi_*accel_scale_error_x_*velocity_integrator_gain_error_xi_ + accel_bias_x_*velocity_integrator_gain_error_xi_ + ((1/2))*delta_V_eta_*velocity_integrator_gain_error_xi_*(_t121 - _t123) + velocity_integrator_gain_error_xi_*velocity_integrator_offset_xi_
    _out[7] = V_zeta_*_t1*delta_V_eta_*delta_u31_*e2_*u31_ - V_zeta_*_t68 - V_zeta_*_t69 - _t108*_t36 - _t118*_t136 - _t119*delta_V_xi_ - _t122*_t71 + ((1/2))*_t127*delta_u21_*delta_u31_ - _t133*_t61 - _t135*_t136 - _t138*accel_scale_error_y_ - _t138*velocity_integrator_gain_error_eta_ - _t139*_t140 - _t139*_t65 + ((1/2))*_t35*(_t114*_t137 + _t115*_t137 + _t133) + a_eta_*accel_scale_error_y_*velocity_integrator_gain_error_eta_ + a_xi_*alpha_x_*alpha_y_ + a_zeta_*accel_scale_error_y_*alpha_x_ + a_zeta_*alpha_x_*velocity_integrator_gain_error_eta_ + accel_bias_y_*velocity_integrator_gain_error_eta_ + ((1/2))*delta_V_xi_*velocity_integrator_gain_error_eta_*(-_t121 - _t123) + ((1/2))*delta_u21_*velocity_integrator_gain_error_eta_*(V_zeta_*_t85 + _t129) + ((1/2))*delta_u31_*velocity_integrator_gain_error_eta_*(-V_xi_*_t17 + _t10*_t130 + _t125*u21_ + _t126*u21_) + velocity_integrator_gain_error_eta_*velocity_integrator_offset_eta_
    _out[8] = _t101 + _t119*alpha_y_ - _t140*correction_gain_error_x_ + _t141*_t142 - _t141*_t143 + _t144*alpha_x_*alpha_y_ + _t146*alpha_y_ + _t56*_t76*correction_gain_error_x_ - _t62 - _t65*correction_gain_error_x_ - _t66 - _t68 - _t69 - _t72 - _t73*correction_gain_error_x_ + _t91*correction_gain_error_x_ + _t93 + alpha_y_*gyro_drift_z_
    _out[9] = _t107*correction_gain_error_y_ - _t119*alpha_x_ - _t13*_t74 + _t134*correction_gain_error_y_ + _t143*_t147 - _t146*alpha_x_ - _t147*_t148 + _t32 + _t34*correction_gain_error_y_ + _t37 + _t41 + _t43 + _t48 + _t49*correction_gain_error_y_ - _t92*correction_gain_error_y_ - _t94 - alpha_x_*gyro_drift_z_
    _out[10] = _t107*alpha_x_ + _t119*correction_gain_error_z_ + _t134*alpha_x_ + _t142*_t145 + _t144*alpha_x_*correction_gain_error_y_ - _t145*_t148 + _t34*alpha_x_ + _t49*alpha_x_ - (1/2)*_t83*alpha_y_*alpha_z_ - _t92*alpha_x_ + alpha_x_*gyro_drift_y_
    return _out


def initial_state(c, u, p):
    """True initial state from navigation initial conditions.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        x(0)
    """
    c = _as_vector(c, 5, 'c', 'initial_state')
    u = _as_vector(u, 5, 'u', 'initial_state')
    p = _as_vector(p, 3, 'p', 'initial_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    heading_ = c[2]
    v_N_ = c[3]
    v_E_ = c[4]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = _m.cos(heading_)
    _t1 = _m.cos(latitude_)
    _t2 = _t0*_t1
    _t3 = _m.sin(heading_)
    _t4 = _t1*_t3
    _t5 = _m.sin(latitude_)
    _t6 = _m.cos(longitude_)
    _t7 = _m.sin(longitude_)
    _t8 = 1/a_
    _t9 = _t8*h_
    _t10 = _t5**2
    _t11 = _t10*e2_
    _t12 = ((1/2))*_t11
    _t13 = _t3**2
    _t14 = _t1**2
    _t15 = _t14*e2_
    _t16 = _t13*_t15
    _t17 = 1/(a_ + h_)
    _t18 = _t17*_t3
    _t19 = 1 - _t11
    _t20 = _m.sqrt(_t19)*v_E_
    _t21 = _t0*_t17
    _t22 = (_t19*_m.sqrt(_t19))*v_N_/(1 - e2_)
    _t23 = _t8*(U_*_t4 + _t18*_t20 + _t21*_t22)
    _t24 = _t8*(U_*_t2 - _t18*_t22 + _t20*_t21)
    _t25 = _t0*_t15*_t3
    _t26 = a_**2
    _t27 = a_*h_
    _t28 = e2_**2
    _t29 = _t0**2
    _t30 = 2*_t10*_t14*_t26*_t28
    _t31 = 4*_t27
    _t32 = 4*a_**4/(4*_t10*a_*e2_*h_ - 4*_t11*_t26 + 4*_t13*_t14*_t26*e2_ - _t13*_t30 + 4*_t14*_t26*_t29*e2_ - _t15*_t29*_t31 - _t16*_t31 + _t26*_t28*_t5**4 + 4*_t26 - 8*_t27 - _t29*_t30 + 4*h_**2)
    _out = _np.zeros((8,) + _batch)
    _out[0] = _t2
    _out[1] = _t4
    _out[2] = _t5
    _out[3] = _t0*_t5*_t7 - _t3*_t6
    _out[4] = _t0*_t6 + _t3*_t5*_t7
    _out[5] = -_t1*_t7
    _out[6] = _t32*(_t23*(-_t12 + _t16 - _t9 + 1) + _t24*_t25)
    _out[7] = _t32*(-_t23*_t25 - _t24*(-_t12 + _t14*_t29*e2_ - _t9 + 1))
    return _out


def initial_real_state(c, u, w, p):
    """Real-work initial state, initial-error sources applied.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    w : array_like, shape (26, ...)
        error-source magnitudes, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (11, ...)
        xr(0)
    """
    c = _as_vector(c, 5, 'c', 'initial_real_state')
    u = _as_vector(u, 5, 'u', 'initial_real_state')
    w = _as_vector(w, 26, 'w', 'initial_real_state')
    p = _as_vector(p, 3, 'p', 'initial_real_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    heading_ = c[2]
    v_N_ = c[3]
    v_E_ = c[4]
    h_ = u[4]
    initial_tilt_x_ = w[0]
    initial_tilt_y_ = w[1]
    initial_azimuth_error_ = w[2]
    initial_velocity_error_xi_ = w[3]
    initial_velocity_error_eta_ = w[4]
    initial_latitude_error_ = w[5]
    initial_longitude_error_ = w[6]
    initial_heading_error_ = w[7]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = heading_ + initial_heading_error_
    _t1 = _m.cos(_t0)
    _t2 = initial_latitude_error_ + latitude_
    _t3 = _m.cos(_t2)
    _t4 = _t1*_t3
    _t5 = _m.sin(_t0)
    _t6 = _t3*_t5
    _t7 = _m.sin(_t2)
    _t8 = initial_longitude_error_ + longitude_
    _t9 = _m.cos(_t8)
    _t10 = _m.sin(_t8)
    _t11 = 1/a_
    _t12 = _t11*h_
    _t13 = _t7**2
    _t14 = _t13*e2_
    _t15 = ((1/2))*_t14
    _t16 = _t5**2
    _t17 = _t3**2
    _t18 = _t17*e2_
    _t19 = _t16*_t18
    _t20 = 1/(a_ + h_)
    _t21 = _t20*_t5
    _t22 = 1 - _t14
    _t23 = _m.sqrt(_t22)*v_E_
    _t24 = _t1*_t20
    _t25 = (_t22*_m.sqrt(_t22))*v_N_/(1 - e2_)
    _t26 = _t11*(U_*_t6 + _t21*_t23 + _t24*_t25)
    _t27 = _t11*(U_*_t4 - _t21*_t25 + _t23*_t24)
    _t28 = _t1*_t18*_t5
    _t29 = a_**2
    _t30 = a_*h_
    _t31 = e2_**2
    _t32 = _t1**2
    _t33 = 2*_t13*_t17*_t29*_t31
    _t34 = 4*_t30
    _t35 = 4*a_**4/(4*_t13*a_*e2_*h_ - 4*_t14*_t29 + 4*_t16*_t17*_t29*e2_ - _t16*_t33 + 4*_t17*_t29*_t32*e2_ - _t18*_t32*_t34 - _t19*_t34 + _t29*_t31*_t7**4 + 4*_t29 - 8*_t30 - _t32*_t33 + 4*h_**2)
    _out = _np.zeros((11,) + _batch)
    _out[0] = _t4
    _out[1] = _t6
    _out[2] = _t7
    _out[3] = _t1*_t10*_t7 - _t5*_t9
    _out[4] = _t1*_t9 + _t10*_t5*_t7
    _out[5] = -_t10*_t3
    _out[6] = _t35*(_t26*(-_t12 - _t15 + _t19 + 1) + _t27*_t28) + initial_velocity_error_xi_
    _out[7] = _t35*(-_t26*_t28 - _t27*(-_t12 - _t15 + _t17*_t32*e2_ + 1)) + initial_velocity_error_eta_
    _out[8] = initial_tilt_x_
    _out[9] = initial_tilt_y_
    _out[10] = initial_azimuth_error_
    return _out


def initial_error_matrix(c, u, p):
    """First-order map from error sources to the initial error state.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (11, 26, ...)
        E: xe(0) = E w
    """
    c = _as_vector(c, 5, 'c', 'initial_error_matrix')
    u = _as_vector(u, 5, 'u', 'initial_error_matrix')
    p = _as_vector(p, 3, 'p', 'initial_error_matrix')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    heading_ = c[2]
    v_N_ = c[3]
    v_E_ = c[4]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    _t0 = _m.cos(heading_)
    _t1 = _m.sin(latitude_)
    _t2 = _t0*_t1
    _t3 = _m.cos(latitude_)
    _t4 = _m.sin(heading_)
    _t5 = _t3*_t4
    _t6 = _t1*_t4
    _t7 = _t0*_t3
    _t8 = _m.sin(longitude_)
    _t9 = _m.cos(longitude_)
    _t10 = _t1*e2_
    _t11 = _t10*_t3
    _t12 = _t4**2
    _t13 = 2*_t11
    _t14 = 1/a_
    _t15 = 1/(a_ + h_)
    _t16 = _t15*_t4
    _t17 = _t1**2
    _t18 = _t17*e2_
    _t19 = 1 - _t18
    _t20 = _m.sqrt(_t19)
    _t21 = _t20*v_E_
    _t22 = _t0*_t15
    _t23 = 1/(1 - e2_)
    _t24 = _t23*v_N_
    _t25 = (_t19*_m.sqrt(_t19))*_t24
    _t26 = U_*_t5 + _t16*_t21 + _t22*_t25
    _t27 = _t14*_t26
    _t28 = _t15*v_E_/_t20
    _t29 = _t2*e2_
    _t30 = _t29*_t3
    _t31 = -U_*_t6 - _t10*_t28*_t5 - 3*_t15*_t20*_t24*_t30
    _t32 = _t14*h_
    _t33 = ((1/2))*_t18
    _t34 = _t3**2
    _t35 = _t34*e2_
    _t36 = _t12*_t35
    _t37 = -_t32 - _t33 + _t36 + 1
    _t38 = _t14*_t37
    _t39 = -U_*_t2 + 3*_t1*_t15*_t20*_t23*_t3*_t4*e2_*v_N_ - _t28*_t30
    _t40 = _t0*_t35*_t4
    _t41 = _t14*_t40
    _t42 = U_*_t7 - _t16*_t25 + _t21*_t22
    _t43 = _t14*_t42
    _t44 = a_**2
    _t45 = a_*h_
    _t46 = 8*_t45
    _t47 = e2_**2
    _t48 = 4*_t44
    _t49 = _t0**2
    _t50 = 2*_t17*_t34*_t44*_t47
    _t51 = _t35*_t49
    _t52 = 4*_t45
    _t53 = _t1**4*_t44*_t47 + 4*_t12*_t34*_t44*e2_ - _t12*_t50 + 4*_t17*a_*e2_*h_ - _t18*_t48 + 4*_t34*_t44*_t49*e2_ - _t36*_t52 + 4*_t44 - _t46 - _t49*_t50 - _t51*_t52 + 4*h_**2
    _t54 = 4*a_**4
    _t55 = _t54/_t53
    _t56 = _t40*_t43
    _t57 = _t1**3*_t3*_t47*_t48
    _t58 = _t3**3
    _t59 = _t11*_t46
    _t60 = _t54*(8*_t1*_t12*_t3*_t44*e2_ + 4*_t1*_t12*_t44*_t47*_t58 + 8*_t1*_t3*_t44*_t49*e2_ + 8*_t1*_t3*_t44*e2_ + 4*_t1*_t44*_t47*_t49*_t58 - _t12*_t57 - _t12*_t59 - _t49*_t57 - _t49*_t59 - _t57 - _t59)/_t53**2
    _t61 = -_t26
    _t62 = _t27*_t40
    _t63 = -_t32 - _t33 + _t34*_t49*e2_ + 1
    _t64 = _t14*_t63
    _out = _np.zeros((11, 26) + _batch)
    _out[0, 5] = -_t2
    _out[0, 7] = -_t5
    _out[1, 5] = -_t6
    _out[1, 7] = _t7
    _out[2, 5] = _t3
    _out[3, 5] = _t7*_t8
    _out[3, 6] = _t2*_t9 + _t4*_t8
    _out[3, 7] = -_t0*_t9 - _t6*_t8
    _out[4, 5] = _t5*_t8
    _out[4, 6] = -_t0*_t8 + _t6*_t9
    _out[4, 7] = _t0*_t1*_t8 - _t4*_t9
    _out[5, 5] = _t1*_t8
    _out[5, 6] = -_t3*_t9
    _out[6, 3] = 1
    _out[6, 5] = _t55*(_t27*(-_t11 - _t12*_t13) - 2*_t29*_t43*_t5 + _t31*_t38 + _t39*_t41) + _t60*(_t27*_t37 + _t56)
    _out[6, 7] = _t55*(-_t36*_t43 + _t38*_t42 + _t41*_t61 + _t43*_t51 + 2*_t62)
    _out[7, 4] = 1
    _out[7, 5] = _t55*(2*_t0*_t1*_t14*_t26*_t3*_t4*e2_ - _t31*_t41 - _t39*_t64 - _t43*(-_t11 - _t13*_t49)) + _t60*(-_t43*_t63 - _t62)
    _out[7, 7] = _t55*(_t27*_t36 - _t27*_t51 + _t56 - _t61*_t64)
    _out[8, 0] = 1
    _out[9, 1] = 1
    _out[10, 2] = 1
    return _out


def domain_margins(x, u, p):
    """Margins that must be positive for the formulas to hold (see DOMAIN).

    Parameters
    ----------
    x : array_like, shape (8, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        one margin per condition of DOMAIN
    """
    x = _as_vector(x, 8, 'x', 'domain_margins')
    u = _as_vector(u, 5, 'u', 'domain_margins')
    p = _as_vector(p, 3, 'p', 'domain_margins')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    u31_ = x[2]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    _out = _np.zeros((4,) + _batch)
    _out[0] = 0.999999999999 - u31_**2
    _out[1] = a_
    _out[2] = a_ + h_
    _out[3] = 1 - e2_
    return _out


def initial_domain_margins(c, u, p):
    """Margins that must be positive for the initial conditions.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (5, ...)
        true-motion inputs, SI units
    p : array_like, shape (3, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        one margin per condition of INITIAL_DOMAIN
    """
    c = _as_vector(c, 5, 'c', 'initial_domain_margins')
    u = _as_vector(u, 5, 'u', 'initial_domain_margins')
    p = _as_vector(p, 3, 'p', 'initial_domain_margins')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    h_ = u[4]
    a_ = p[0]
    e2_ = p[1]
    _out = _np.zeros((4,) + _batch)
    _out[0] = _m.cos(latitude_)**2 - 1e-12
    _out[1] = a_
    _out[2] = a_ + h_
    _out[3] = 1 - e2_
    return _out


FUNCTIONS = ('ideal_rhs', 'real_rhs', 'real_rhs_small_angle', 'second_order_small_angle', 'outputs', 'state_matrix', 'source_matrix', 'output_matrix', 'second_order', 'initial_state', 'initial_real_state', 'initial_error_matrix', 'domain_margins', 'initial_domain_margins')
