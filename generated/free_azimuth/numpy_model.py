# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/free_azimuth.py.
# Edit the model definition and run `make derive` again.

"""numpy functions of the model 'free_azimuth' (broadcasting)."""

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
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, ...)
        time derivative of the true state
    """
    x = _as_vector(x, 5, 'x', 'ideal_rhs')
    u = _as_vector(u, 4, 'u', 'ideal_rhs')
    p = _as_vector(p, 5, 'p', 'ideal_rhs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    V_zeta_ = u[3]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = 1/R_
    _t1 = _m.sin(Lam_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_)
    _t4 = _m.cos(orth_azimuth_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = -_t1*_t2 + _t3*_t4*_t5
    _t7 = _m.sin(A_)
    _t8 = _m.sin(Phi_)
    _t9 = _t2*_t3
    _t10 = _m.cos(Phi_)
    _t11 = _m.sin(orth_azimuth_)
    _t12 = _t1*_t4*_t5
    _t13 = _t10*_t11*_t5 - _t12*_t8 - _t8*_t9
    _t14 = _m.cos(A_)
    _t15 = R_*U_
    _t16 = V_x_ - _t15*(_t13*_t14 - _t6*_t7)
    _t17 = V_y_ + _t15*(_t13*_t7 + _t14*_t6)
    _t18 = _t0*(_t14*_t16 - _t17*_t7)
    _t19 = V_zeta_*_t0
    _out = _np.zeros((5,) + _batch)
    _out[0] = _t0*(_t14*_t17 + _t16*_t7)
    _out[1] = _t18/_t10
    _out[2] = -U_*(_t10*_t12 + _t10*_t9 + _t11*_t5*_t8) - _t18*_m.tan(Phi_)
    _out[3] = -V_x_*_t19 + a_x_
    _out[4] = -V_y_*_t19 + a_y_
    return _out


def real_rhs(xr, x, u, w, p):
    """Real-work equations: dxr/dt (needs the true state x for the platform).

    Parameters
    ----------
    xr : array_like, shape (8, ...)
        real-work state: the 5 computed states in the order of x, then the platform angles alpha_x, alpha_y, alpha_z (rad)
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    w : array_like, shape (25, ...)
        error-source magnitudes, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 8, 'xr', 'real_rhs')
    x = _as_vector(x, 5, 'x', 'real_rhs')
    u = _as_vector(u, 4, 'u', 'real_rhs')
    w = _as_vector(w, 25, 'w', 'real_rhs')
    p = _as_vector(p, 5, 'p', 'real_rhs')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    Phi_c_ = xr[0]
    Lam_c_ = xr[1]
    A_c_ = xr[2]
    V_x_c_ = xr[3]
    V_y_c_ = xr[4]
    alpha_x_ = xr[5]
    alpha_y_ = xr[6]
    alpha_z_ = xr[7]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    gyro_drift_x_ = w[8]
    gyro_drift_y_ = w[9]
    gyro_drift_z_ = w[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_x_ = w[13]
    velocity_integrator_offset_y_ = w[14]
    position_integrator_offset_Phi_ = w[15]
    position_integrator_offset_Lam_ = w[16]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_x_ = w[19]
    velocity_integrator_gain_error_y_ = w[20]
    position_integrator_gain_error_Phi_ = w[21]
    position_integrator_gain_error_Lam_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = 1/R_
    _t1 = _m.sin(Lam_c_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_c_)
    _t4 = _m.cos(orth_azimuth_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = -_t1*_t2 + _t3*_t4*_t5
    _t7 = _m.sin(A_c_)
    _t8 = _m.sin(Phi_c_)
    _t9 = _t2*_t3
    _t10 = _m.cos(Phi_c_)
    _t11 = _m.sin(orth_azimuth_)
    _t12 = _t1*_t4*_t5
    _t13 = _t10*_t11*_t5 - _t12*_t8 - _t8*_t9
    _t14 = _m.cos(A_c_)
    _t15 = R_*U_
    _t16 = V_x_c_ - _t15*(_t13*_t14 - _t6*_t7)
    _t17 = V_y_c_ + _t15*(_t13*_t7 + _t14*_t6)
    _t18 = _t0*(_t14*_t16 - _t17*_t7)
    _t19 = _m.sin(alpha_y_)
    _t20 = _m.cos(alpha_z_)
    _t21 = _m.sin(alpha_z_)
    _t22 = _t20*a_x_ + _t21*a_y_
    _t23 = _m.cos(alpha_y_)
    _t24 = V_zeta_*_t0
    _t25 = _m.cos(alpha_x_)
    _t26 = _m.sin(alpha_x_)
    _t27 = V_x_c_*_t0*(correction_gain_error_y_ + 1) + gyro_drift_y_
    _t28 = V_x_*_t0
    _t29 = V_y_*_t0
    _t30 = -_t20*_t29 + _t21*_t28
    _t31 = -_t19*_t30 + _t25*gyro_drift_z_ + _t26*_t27
    _out = _np.zeros((8,) + _batch)
    _out[0] = _t0*(position_integrator_gain_error_Phi_ + 1)*(_t14*_t17 + _t16*_t7) + position_integrator_offset_Phi_
    _out[1] = position_integrator_offset_Lam_ + _t18*(position_integrator_gain_error_Lam_ + 1)/_t10
    _out[2] = -U_*(_t10*_t12 + _t10*_t9 + _t11*_t5*_t8) - _t18*_m.tan(Phi_c_)
    _out[3] = (velocity_integrator_gain_error_x_ + 1)*(-V_x_c_*_t24 + accel_bias_x_ + velocity_integrator_offset_x_ + (accel_scale_error_x_ + 1)*(-_t19*a_zeta_ + _t22*_t23))
    _out[4] = (velocity_integrator_gain_error_y_ + 1)*(-V_y_c_*_t24 + accel_bias_y_ + velocity_integrator_offset_y_ + (accel_scale_error_y_ + 1)*(_t25*(_t20*a_y_ - _t21*a_x_) + _t26*(_t19*_t22 + _t23*a_zeta_)))
    _out[5] = -V_y_c_*_t0*(correction_gain_error_x_ + 1) - _t23*_t30 + _t31*_m.tan(alpha_y_) + gyro_drift_x_
    _out[6] = -_t20*_t28 - _t21*_t29 + _t25*_t27 - _t26*gyro_drift_z_
    _out[7] = _t31/_t23
    return _out


def real_rhs_small_angle(xr, x, u, w, p):
    """Real-work equations with the source's small-angle platform: dxr/dt.

    Parameters
    ----------
    xr : array_like, shape (8, ...)
        real-work state: the 5 computed states in the order of x, then the platform angles alpha_x, alpha_y, alpha_z (rad)
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    w : array_like, shape (25, ...)
        error-source magnitudes, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 8, 'xr', 'real_rhs_small_angle')
    x = _as_vector(x, 5, 'x', 'real_rhs_small_angle')
    u = _as_vector(u, 4, 'u', 'real_rhs_small_angle')
    w = _as_vector(w, 25, 'w', 'real_rhs_small_angle')
    p = _as_vector(p, 5, 'p', 'real_rhs_small_angle')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    Phi_c_ = xr[0]
    Lam_c_ = xr[1]
    A_c_ = xr[2]
    V_x_c_ = xr[3]
    V_y_c_ = xr[4]
    alpha_x_ = xr[5]
    alpha_y_ = xr[6]
    alpha_z_ = xr[7]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    gyro_drift_x_ = w[8]
    gyro_drift_y_ = w[9]
    gyro_drift_z_ = w[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_x_ = w[13]
    velocity_integrator_offset_y_ = w[14]
    position_integrator_offset_Phi_ = w[15]
    position_integrator_offset_Lam_ = w[16]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_x_ = w[19]
    velocity_integrator_gain_error_y_ = w[20]
    position_integrator_gain_error_Phi_ = w[21]
    position_integrator_gain_error_Lam_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = 1/R_
    _t1 = _m.sin(Lam_c_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_c_)
    _t4 = _m.cos(orth_azimuth_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = -_t1*_t2 + _t3*_t4*_t5
    _t7 = _m.sin(A_c_)
    _t8 = _m.sin(Phi_c_)
    _t9 = _t2*_t3
    _t10 = _m.cos(Phi_c_)
    _t11 = _m.sin(orth_azimuth_)
    _t12 = _t1*_t4*_t5
    _t13 = _t10*_t11*_t5 - _t12*_t8 - _t8*_t9
    _t14 = _m.cos(A_c_)
    _t15 = R_*U_
    _t16 = V_x_c_ - _t15*(_t13*_t14 - _t6*_t7)
    _t17 = V_y_c_ + _t15*(_t13*_t7 + _t14*_t6)
    _t18 = _t0*(_t14*_t16 - _t17*_t7)
    _t19 = V_zeta_*_t0
    _t20 = V_y_*_t0
    _t21 = V_x_*_t0
    _out = _np.zeros((8,) + _batch)
    _out[0] = _t0*(position_integrator_gain_error_Phi_ + 1)*(_t14*_t17 + _t16*_t7) + position_integrator_offset_Phi_
    _out[1] = position_integrator_offset_Lam_ + _t18*(position_integrator_gain_error_Lam_ + 1)/_t10
    _out[2] = -U_*(_t10*_t12 + _t10*_t9 + _t11*_t5*_t8) - _t18*_m.tan(Phi_c_)
    _out[3] = (velocity_integrator_gain_error_x_ + 1)*(-V_x_c_*_t19 + accel_bias_x_ + velocity_integrator_offset_x_ + (accel_scale_error_x_ + 1)*(a_x_ + a_y_*alpha_z_ - a_zeta_*alpha_y_))
    _out[4] = (velocity_integrator_gain_error_y_ + 1)*(-V_y_c_*_t19 + accel_bias_y_ + velocity_integrator_offset_y_ + (accel_scale_error_y_ + 1)*(-a_x_*alpha_z_ + a_y_ + a_zeta_*alpha_x_))
    _out[5] = -V_y_c_*_t0*(correction_gain_error_x_ + 1) + _t20 - _t21*alpha_z_ + gyro_drift_x_
    _out[6] = V_x_c_*_t0*(correction_gain_error_y_ + 1) - _t20*alpha_z_ - _t21 + gyro_drift_y_
    _out[7] = _t20*alpha_y_ + _t21*alpha_x_ + gyro_drift_z_
    return _out


def second_order_small_angle(x, u, p, xe, w):
    """Second-order term of the error equations of the small-angle platform.

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units
    xe : array_like, shape (8, ...)
        error state xr - (x, 0)
    w : array_like, shape (25, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 5, 'x', 'second_order_small_angle')
    u = _as_vector(u, 4, 'u', 'second_order_small_angle')
    p = _as_vector(p, 5, 'p', 'second_order_small_angle')
    xe = _as_vector(xe, 8, 'xe', 'second_order_small_angle')
    w = _as_vector(w, 25, 'w', 'second_order_small_angle')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    delta_Phi_ = xe[0]
    delta_Lam_ = xe[1]
    delta_A_ = xe[2]
    delta_V_x_ = xe[3]
    delta_V_y_ = xe[4]
    alpha_x_ = xe[5]
    alpha_y_ = xe[6]
    alpha_z_ = xe[7]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_x_ = w[13]
    velocity_integrator_offset_y_ = w[14]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_x_ = w[19]
    velocity_integrator_gain_error_y_ = w[20]
    position_integrator_gain_error_Phi_ = w[21]
    position_integrator_gain_error_Lam_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    _t0 = 1/R_
    _t1 = _m.sin(Lam_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _t1*_t2
    _t4 = _m.cos(Lam_)
    _t5 = _m.cos(orth_azimuth_)
    _t6 = _m.cos(orth_latitude_)
    _t7 = _t3 - _t4*_t5*_t6
    _t8 = -_t7
    _t9 = _m.sin(A_)
    _t10 = _m.cos(Phi_)
    _t11 = _m.sin(orth_azimuth_)
    _t12 = _m.sin(Phi_)
    _t13 = _t2*_t4
    _t14 = _t5*_t6
    _t15 = _t1*_t14
    _t16 = _t12*_t13 + _t12*_t15
    _t17 = -_t10*_t11*_t6 + _t16
    _t18 = -_t17
    _t19 = _m.cos(A_)
    _t20 = -_t18*_t19 + _t8*_t9
    _t21 = R_*U_
    _t22 = _t21*_t9
    _t23 = -_t20*_t21
    _t24 = _t23*_t9
    _t25 = V_x_ - _t23
    _t26 = _t18*_t9 + _t19*_t8
    _t27 = V_y_ + _t21*_t26
    _t28 = -_t26
    _t29 = _t19*_t21
    _t30 = _t19*_t27 + _t25*_t9 + _t28*_t29
    _t31 = ((1/2))*delta_A_**2
    _t32 = _t16*_t19 - _t7*_t9
    _t33 = _t16*_t9 + _t19*_t7
    _t34 = ((1/2))*delta_Lam_**2
    _t35 = -_t13 - _t15
    _t36 = _t14*_t4
    _t37 = _t12*_t3 - _t12*_t36
    _t38 = _t19*_t35 + _t37*_t9
    _t39 = _t22*_t38
    _t40 = -_t38
    _t41 = _t0*delta_A_
    _t42 = _t0*delta_V_x_
    _t43 = _t19*delta_A_
    _t44 = _t19*_t23
    _t45 = _t19*_t25 - _t27*_t9
    _t46 = -_t22*_t28 + _t45
    _t47 = _t29*_t38
    _t48 = _t19*_t37 - _t35*_t9
    _t49 = _t0*delta_V_y_
    _t50 = _t9*delta_A_
    _t51 = _t0/_t10
    _t52 = _t19**2
    _t53 = _t17*_t21
    _t54 = _t9**2
    _t55 = -_t52*_t53 - _t53*_t54
    _t56 = 2*_t0
    _t57 = _t45*_t56
    _t58 = _t10*_t13 + _t10*_t15
    _t59 = U_*(-_t11*_t12*_t6 - _t58)
    _t60 = R_*_t59
    _t61 = -_t52*_t60 - _t54*_t60
    _t62 = _t12/_t10**2
    _t63 = _t56*_t62
    _t64 = ((1/2))*delta_Phi_**2
    _t65 = _t21*(_t10*_t3 - _t10*_t36)
    _t66 = -_t52*_t65 - _t54*_t65
    _t67 = 2*_t51
    _t68 = -_t29*_t48 - _t39
    _t69 = ((1/2))*delta_Phi_
    _t70 = _t69*delta_Lam_
    _t71 = _t31*(-_t20*_t29 - 2*_t44 - _t46)
    _t72 = -_t22*_t33 - _t29*_t32
    _t73 = _t51*delta_A_
    _t74 = delta_Lam_*(-_t29*_t40 - _t47)
    _t75 = -_t24 - _t30
    _t76 = _t51*position_integrator_gain_error_Lam_
    _t77 = _t50*delta_V_x_
    _t78 = _t43*delta_V_y_
    _t79 = _t41*_t75
    _t80 = _t62*delta_Phi_
    _t81 = _t19*_t42
    _t82 = _t49*_t9
    _t83 = _m.tan(Phi_)
    _t84 = _t0*_t83
    _t85 = _t83**2
    _t86 = _t85 + 1
    _t87 = _t56*_t86
    _t88 = _t86*delta_Phi_
    _t89 = a_y_*alpha_z_
    _t90 = a_zeta_*alpha_y_
    _t91 = a_zeta_*alpha_x_
    _t92 = a_x_*alpha_z_
    _out = _np.zeros((8,) + _batch)
    _out[0] = _t0*_t31*(-_t20*_t22 - 2*_t24 - _t30) + _t0*_t34*(R_*U_*_t19*_t33 - _t22*_t32) + _t0*delta_Lam_*position_integrator_gain_error_Phi_*(-_t22*_t48 + _t47) + _t19*_t49*position_integrator_gain_error_Phi_ + _t41*delta_Lam_*(-_t22*_t40 - _t39) + _t41*position_integrator_gain_error_Phi_*(_t44 + _t46) + _t42*_t43 + _t42*_t9*position_integrator_gain_error_Phi_ - _t49*_t50
    _out[1] = _t19*_t76*delta_V_x_ + _t34*_t51*_t72 + _t51*_t71 - _t51*_t77 - _t51*_t78 + _t64*(_t45*_t51 + _t51*_t55 + _t61*_t63 + _t12**2*_t57/_t10**3) + _t68*_t76*delta_Lam_ + _t69*position_integrator_gain_error_Lam_*(_t57*_t62 + _t61*_t67) + _t70*(_t63*_t68 + _t66*_t67) + _t73*_t74 + _t73*_t75*position_integrator_gain_error_Lam_ - _t76*_t9*delta_V_y_ + _t79*_t80 + _t80*_t81 - _t80*_t82
    _out[2] = _t34*(U_*_t58 - _t72*_t84) + _t64*(-_t45*_t84*(2*_t85 + 2) - _t55*_t84 - _t59 - _t61*_t87) + _t70*(-2*U_*_t37 - 2*_t66*_t84 - _t68*_t87) - _t71*_t84 - _t74*_t84*delta_A_ + _t77*_t84 + _t78*_t84 - _t79*_t88 - _t81*_t88 + _t82*_t88
    _out[3] = -V_zeta_*_t42*velocity_integrator_gain_error_x_ + _t89*accel_scale_error_x_ + _t89*velocity_integrator_gain_error_x_ - _t90*accel_scale_error_x_ - _t90*velocity_integrator_gain_error_x_ + a_x_*accel_scale_error_x_*velocity_integrator_gain_error_x_ + accel_bias_x_*velocity_integrator_gain_error_x_ + velocity_integrator_gain_error_x_*velocity_integrator_offset_x_
    _out[4] = -V_zeta_*_t49*velocity_integrator_gain_error_y_ + _t91*accel_scale_error_y_ + _t91*velocity_integrator_gain_error_y_ - _t92*accel_scale_error_y_ - _t92*velocity_integrator_gain_error_y_ + a_y_*accel_scale_error_y_*velocity_integrator_gain_error_y_ + accel_bias_y_*velocity_integrator_gain_error_y_ + velocity_integrator_gain_error_y_*velocity_integrator_offset_y_
    _out[5] = -_t49*correction_gain_error_x_
    _out[6] = _t42*correction_gain_error_y_
    return _out


def outputs(x, u, p):
    """Navigation outputs of a state (true or computed part of xr).

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, ...)
        outputs in SI units
    """
    x = _as_vector(x, 5, 'x', 'outputs')
    u = _as_vector(u, 4, 'u', 'outputs')
    p = _as_vector(p, 5, 'p', 'outputs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_longitude_ = p[3]
    orth_azimuth_ = p[4]
    _t0 = _m.cos(Phi_)
    _t1 = _m.sin(orth_latitude_)
    _t2 = _m.cos(Lam_)
    _t3 = _t1*_t2
    _t4 = _m.cos(orth_latitude_)
    _t5 = _m.sin(Phi_)
    _t6 = _m.sin(orth_azimuth_)
    _t7 = _t5*_t6
    _t8 = _m.cos(orth_azimuth_)
    _t9 = _m.sin(Lam_)
    _t10 = _t0*_t8*_t9
    _t11 = -_t1*_t9 + _t2*_t4*_t8
    _t12 = _t5*_t8
    _t13 = _t0*_t4*_t6 - _t12*_t4*_t9 - _t3*_t5
    _t14 = _m.sqrt(_t11**2 + _t13**2)
    _t15 = _m.sin(A_)
    _t16 = _m.cos(A_)
    _t17 = -_t11*_t15 + _t13*_t16
    _t18 = _t11*_t16 + _t13*_t15
    _t19 = 1/_t14
    _t20 = R_*U_
    _t21 = V_x_ - _t17*_t20
    _t22 = V_y_ + _t18*_t20
    _out = _np.zeros((5,) + _batch)
    _out[0] = _m.arctan2(_t0*_t3 + _t10*_t4 + _t4*_t7, _t14)
    _out[1] = orth_longitude_ + _m.arctan2(_t0*_t6*_t9 - _t12, _t0*_t2*_t4 - _t1*(_t10 + _t7))
    _out[2] = _m.arctan2(_t17, _t18)
    _out[3] = _t19*(_t17*_t22 + _t18*_t21)
    _out[4] = _t19*(_t17*_t21 - _t18*_t22)
    return _out


def state_matrix(x, u, p):
    """State matrix F of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, 8, ...)
        F
    """
    x = _as_vector(x, 5, 'x', 'state_matrix')
    u = _as_vector(u, 4, 'u', 'state_matrix')
    p = _as_vector(p, 5, 'p', 'state_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = 1/R_
    _t1 = _m.cos(A_)
    _t2 = _m.cos(Lam_)
    _t3 = _m.sin(orth_latitude_)
    _t4 = _t2*_t3
    _t5 = _m.sin(Lam_)
    _t6 = _m.cos(orth_azimuth_)
    _t7 = _m.cos(orth_latitude_)
    _t8 = _t6*_t7
    _t9 = _t5*_t8
    _t10 = -_t4 - _t9
    _t11 = _m.sin(Phi_)
    _t12 = _t3*_t5
    _t13 = _t11*_t12 - _t11*_t2*_t8
    _t14 = _m.sin(A_)
    _t15 = R_*U_
    _t16 = _t15*(_t1*_t10 + _t13*_t14)
    _t17 = _t1*_t13 - _t10*_t14
    _t18 = _t14*_t15
    _t19 = -_t12 + _t2*_t6*_t7
    _t20 = _m.cos(Phi_)
    _t21 = _m.sin(orth_azimuth_)
    _t22 = -_t11*_t4 - _t11*_t9 + _t20*_t21*_t7
    _t23 = _t15*(_t1*_t22 - _t14*_t19)
    _t24 = _t1*_t19 + _t14*_t22
    _t25 = -_t24
    _t26 = V_x_ - _t23
    _t27 = V_y_ + _t15*_t24
    _t28 = _t1*_t26 - _t14*_t27
    _t29 = _t0*_t14
    _t30 = _t0*_t1
    _t31 = _t15*(-_t11*_t21*_t7 - _t20*_t4 - _t20*_t9)
    _t32 = -_t1**2*_t31 - _t14**2*_t31
    _t33 = 1/_t20
    _t34 = _t0*_t33
    _t35 = _t0*_t28
    _t36 = _t1*_t15
    _t37 = -_t14*_t16 - _t17*_t36
    _t38 = -_t1*_t27 - _t14*_t23 - _t14*_t26 - _t25*_t36
    _t39 = _m.tan(Phi_)
    _t40 = _t0*_t39
    _t41 = -V_zeta_*_t0
    _t42 = V_x_*_t0
    _t43 = V_y_*_t0
    _out = _np.zeros((8, 8) + _batch)
    _out[0, 1] = _t0*(_t1*_t16 - _t17*_t18)
    _out[0, 2] = _t0*(_t1*_t23 - _t18*_t25 + _t28)
    _out[0, 3] = _t29
    _out[0, 4] = _t30
    _out[1, 0] = _t11*_t35/_t20**2 + _t32*_t34
    _out[1, 1] = _t34*_t37
    _out[1, 2] = _t34*_t38
    _out[1, 3] = _t30*_t33
    _out[1, 4] = -_t29*_t33
    _out[2, 0] = -U_*_t22 - _t32*_t40 - _t35*(_t39**2 + 1)
    _out[2, 1] = -U_*(-_t12*_t20 + _t2*_t20*_t6*_t7) - _t37*_t40
    _out[2, 2] = -_t38*_t40
    _out[2, 3] = -_t30*_t39
    _out[2, 4] = _t29*_t39
    _out[3, 3] = _t41
    _out[3, 6] = -a_zeta_
    _out[3, 7] = a_y_
    _out[4, 4] = _t41
    _out[4, 5] = a_zeta_
    _out[4, 7] = -a_x_
    _out[5, 4] = -_t0
    _out[5, 7] = -_t42
    _out[6, 3] = _t0
    _out[6, 7] = -_t43
    _out[7, 5] = _t42
    _out[7, 6] = _t43
    return _out


def source_matrix(x, u, p):
    """Error-source matrix G of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, 25, ...)
        G
    """
    x = _as_vector(x, 5, 'x', 'source_matrix')
    u = _as_vector(u, 4, 'u', 'source_matrix')
    p = _as_vector(p, 5, 'p', 'source_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    V_zeta_ = u[3]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = 1/R_
    _t1 = _m.sin(Lam_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_)
    _t4 = _m.cos(orth_azimuth_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = -_t1*_t2 + _t3*_t4*_t5
    _t7 = _m.sin(A_)
    _t8 = _m.sin(Phi_)
    _t9 = _m.cos(Phi_)
    _t10 = -_t1*_t4*_t5*_t8 - _t2*_t3*_t8 + _t5*_t9*_m.sin(orth_azimuth_)
    _t11 = _m.cos(A_)
    _t12 = R_*U_
    _t13 = V_x_ - _t12*(_t10*_t11 - _t6*_t7)
    _t14 = V_y_ + _t12*(_t10*_t7 + _t11*_t6)
    _t15 = V_x_*_t0
    _t16 = V_y_*_t0
    _out = _np.zeros((8, 25) + _batch)
    _out[0, 15] = 1
    _out[0, 21] = _t0*(_t11*_t14 + _t13*_t7)
    _out[1, 16] = 1
    _out[1, 22] = _t0*(_t11*_t13 - _t14*_t7)/_t9
    _out[3, 11] = 1
    _out[3, 13] = 1
    _out[3, 17] = a_x_
    _out[3, 19] = -V_zeta_*_t15 + a_x_
    _out[4, 12] = 1
    _out[4, 14] = 1
    _out[4, 18] = a_y_
    _out[4, 20] = -V_zeta_*_t16 + a_y_
    _out[5, 8] = 1
    _out[5, 23] = -_t16
    _out[6, 9] = 1
    _out[6, 24] = _t15
    _out[7, 10] = 1
    return _out


def output_matrix(x, u, p):
    """Output matrix H: output errors = H xe to first order.

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, 8, ...)
        H
    """
    x = _as_vector(x, 5, 'x', 'output_matrix')
    u = _as_vector(u, 4, 'u', 'output_matrix')
    p = _as_vector(p, 5, 'p', 'output_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = _m.sin(Phi_)
    _t1 = _m.cos(Lam_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _t1*_t2
    _t4 = _m.cos(Phi_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = _m.sin(orth_azimuth_)
    _t7 = _m.sin(Lam_)
    _t8 = _m.cos(orth_azimuth_)
    _t9 = _t0*_t8
    _t10 = _t7*_t9
    _t11 = -_t0*_t3 - _t10*_t5 + _t4*_t5*_t6
    _t12 = _t2*_t7
    _t13 = _t1*_t5*_t8 - _t12
    _t14 = _t11**2 + _t13**2
    _t15 = _m.sqrt(_t14)
    _t16 = _t3*_t4
    _t17 = _t0*_t6
    _t18 = _t17*_t5
    _t19 = _t4*_t8
    _t20 = _t19*_t7
    _t21 = _t20*_t5
    _t22 = _t16 + _t18 + _t21
    _t23 = 1/(_t14 + _t22**2)
    _t24 = _t15*_t23
    _t25 = 1/_t15
    _t26 = -_t22
    _t27 = _t23*_t25*_t26
    _t28 = ((1/2))*_t11
    _t29 = _t28*(-2*_t16 - 2*_t18 - 2*_t21)
    _t30 = _t5*_t7
    _t31 = _t30*_t8
    _t32 = _t0*_t12
    _t33 = _t1*_t5
    _t34 = _t33*_t9
    _t35 = ((1/2))*_t13*(-2*_t3 - 2*_t31) + _t28*(2*_t32 - 2*_t34)
    _t36 = _t1*_t4*_t5 - _t2*(_t17 + _t20)
    _t37 = _t4*_t6
    _t38 = _t37*_t7 - _t9
    _t39 = 1/(_t36**2 + _t38**2)
    _t40 = -_t38*_t39
    _t41 = _t36*_t39
    _t42 = _m.cos(A_)
    _t43 = _m.sin(A_)
    _t44 = _t11*_t43 + _t13*_t42
    _t45 = -_t11*_t42 + _t13*_t43
    _t46 = -_t45
    _t47 = _t46**2
    _t48 = 1/(_t44**2 + _t47)
    _t49 = _t44*_t48
    _t50 = _t26*_t42
    _t51 = _t45*_t48
    _t52 = _t26*_t43
    _t53 = -_t3 - _t31
    _t54 = _t32 - _t34
    _t55 = _t42*_t53 + _t43*_t54
    _t56 = _t42*_t54 - _t43*_t53
    _t57 = -_t44
    _t58 = R_*U_
    _t59 = _t46*_t58
    _t60 = V_x_ - _t59
    _t61 = _t44*_t58
    _t62 = V_y_ + _t61
    _t63 = _t26*_t62
    _t64 = _t46*_t62
    _t65 = _t44*_t60 + _t64
    _t66 = (1/(_t14*_m.sqrt(_t14)))
    _t67 = _t29*_t66
    _t68 = -_t35*_t66
    _t69 = _t46*_t60
    _t70 = _t25*_t46
    _t71 = -_t44*_t62 + _t69
    _out = _np.zeros((5, 8) + _batch)
    _out[0, 0] = _t11*_t24 + _t27*_t29
    _out[0, 1] = _t24*(_t1*_t4*_t5*_t8 - _t12*_t4) + _t27*_t35
    _out[1, 0] = _t40*(-_t0*_t33 - _t2*(-_t10 + _t4*_t6)) + _t41*(-_t17*_t7 - _t19)
    _out[1, 1] = _t1*_t37*_t41 + _t40*(-_t19*_t3 - _t30*_t4)
    _out[2, 0] = _t49*_t50 + _t51*_t52
    _out[2, 1] = _t49*_t56 + _t51*_t55
    _out[2, 2] = _t46*_t51 + _t49*_t57
    _out[3, 0] = _t25*(_t26*_t43*_t60 + _t42*_t63 - _t50*_t61 + _t52*_t59) - _t65*_t67
    _out[3, 1] = _t25*(_t55*_t59 + _t55*_t60 - _t56*_t61 + _t56*_t62) + _t65*_t68
    _out[3, 2] = _t25*(_t47*_t58 - _t57*_t61 + _t57*_t62 + _t69)
    _out[3, 3] = _t25*_t44
    _out[3, 4] = _t70
    _out[4, 0] = _t25*(_t26*_t42*_t60 - _t43*_t63 - _t50*_t59 - _t52*_t61) - _t67*_t71
    _out[4, 1] = _t25*(-_t55*_t61 - _t55*_t62 - _t56*_t59 + _t56*_t60) + _t68*_t71
    _out[4, 2] = _t25*(-_t44*_t59 - _t57*_t59 + _t57*_t60 - _t64)
    _out[4, 3] = _t70
    _out[4, 4] = _t25*_t57
    return _out


def second_order(x, u, p, xe, w):
    """Second-order term of the error equations (refined model).

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units
    xe : array_like, shape (8, ...)
        error state xr - (x, 0)
    w : array_like, shape (25, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 5, 'x', 'second_order')
    u = _as_vector(u, 4, 'u', 'second_order')
    p = _as_vector(p, 5, 'p', 'second_order')
    xe = _as_vector(xe, 8, 'xe', 'second_order')
    w = _as_vector(w, 25, 'w', 'second_order')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    A_ = x[2]
    V_x_ = x[3]
    V_y_ = x[4]
    a_x_ = u[0]
    a_y_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    delta_Phi_ = xe[0]
    delta_Lam_ = xe[1]
    delta_A_ = xe[2]
    delta_V_x_ = xe[3]
    delta_V_y_ = xe[4]
    alpha_x_ = xe[5]
    alpha_y_ = xe[6]
    alpha_z_ = xe[7]
    gyro_drift_y_ = w[9]
    gyro_drift_z_ = w[10]
    accel_bias_x_ = w[11]
    accel_bias_y_ = w[12]
    velocity_integrator_offset_x_ = w[13]
    velocity_integrator_offset_y_ = w[14]
    accel_scale_error_x_ = w[17]
    accel_scale_error_y_ = w[18]
    velocity_integrator_gain_error_x_ = w[19]
    velocity_integrator_gain_error_y_ = w[20]
    position_integrator_gain_error_Phi_ = w[21]
    position_integrator_gain_error_Lam_ = w[22]
    correction_gain_error_x_ = w[23]
    correction_gain_error_y_ = w[24]
    _t0 = delta_A_**2
    _t1 = _m.sin(Lam_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _t1*_t2
    _t4 = _m.cos(Lam_)
    _t5 = _m.cos(orth_azimuth_)
    _t6 = _m.cos(orth_latitude_)
    _t7 = _t3 - _t4*_t5*_t6
    _t8 = -_t7
    _t9 = _m.sin(A_)
    _t10 = _m.cos(Phi_)
    _t11 = _m.sin(orth_azimuth_)
    _t12 = _m.sin(Phi_)
    _t13 = _t2*_t4
    _t14 = _t5*_t6
    _t15 = _t1*_t14
    _t16 = _t12*_t13 + _t12*_t15
    _t17 = -_t10*_t11*_t6 + _t16
    _t18 = -_t17
    _t19 = _m.cos(A_)
    _t20 = -_t18*_t19 + _t8*_t9
    _t21 = R_*U_
    _t22 = _t21*_t9
    _t23 = -_t20*_t21
    _t24 = _t23*_t9
    _t25 = V_x_ - _t23
    _t26 = _t18*_t9 + _t19*_t8
    _t27 = V_y_ + _t21*_t26
    _t28 = -_t26
    _t29 = _t19*_t21
    _t30 = _t19*_t27 + _t25*_t9 + _t28*_t29
    _t31 = 1/R_
    _t32 = ((1/2))*_t31
    _t33 = _t16*_t19 - _t7*_t9
    _t34 = _t16*_t9 + _t19*_t7
    _t35 = ((1/2))*delta_Lam_**2
    _t36 = -_t13 - _t15
    _t37 = _t14*_t4
    _t38 = _t12*_t3 - _t12*_t37
    _t39 = _t19*_t36 + _t38*_t9
    _t40 = _t22*_t39
    _t41 = -_t39
    _t42 = _t31*delta_A_
    _t43 = _t31*delta_V_x_
    _t44 = _t19*delta_A_
    _t45 = _t19*_t23
    _t46 = _t19*_t25 - _t27*_t9
    _t47 = -_t22*_t28 + _t46
    _t48 = _t29*_t39
    _t49 = _t19*_t38 - _t36*_t9
    _t50 = _t31*delta_V_y_
    _t51 = _t9*delta_A_
    _t52 = _t31/_t10
    _t53 = _t19**2
    _t54 = _t17*_t21
    _t55 = _t9**2
    _t56 = -_t53*_t54 - _t54*_t55
    _t57 = 2*_t31
    _t58 = _t46*_t57
    _t59 = _t10*_t13 + _t10*_t15
    _t60 = U_*(-_t11*_t12*_t6 - _t59)
    _t61 = R_*_t60
    _t62 = -_t53*_t61 - _t55*_t61
    _t63 = _t12/_t10**2
    _t64 = _t57*_t63
    _t65 = ((1/2))*delta_Phi_**2
    _t66 = _t21*(_t10*_t3 - _t10*_t37)
    _t67 = -_t53*_t66 - _t55*_t66
    _t68 = 2*_t52
    _t69 = -_t29*_t49 - _t40
    _t70 = ((1/2))*delta_Phi_
    _t71 = _t70*delta_Lam_
    _t72 = ((1/2))*_t0*(-_t20*_t29 - 2*_t45 - _t47)
    _t73 = -_t22*_t34 - _t29*_t33
    _t74 = _t52*delta_A_
    _t75 = delta_Lam_*(-_t29*_t41 - _t48)
    _t76 = -_t24 - _t30
    _t77 = _t52*position_integrator_gain_error_Lam_
    _t78 = _t51*delta_V_x_
    _t79 = _t44*delta_V_y_
    _t80 = _t42*_t76
    _t81 = _t63*delta_Phi_
    _t82 = _t19*_t43
    _t83 = _t50*_t9
    _t84 = _m.tan(Phi_)
    _t85 = _t31*_t84
    _t86 = _t84**2
    _t87 = _t86 + 1
    _t88 = _t57*_t87
    _t89 = _t87*delta_Phi_
    _t90 = alpha_y_**2
    _t91 = ((1/2))*a_x_
    _t92 = alpha_z_**2
    _t93 = a_y_*alpha_z_
    _t94 = a_zeta_*alpha_y_
    _t95 = alpha_x_**2
    _t96 = ((1/2))*a_y_
    _t97 = alpha_x_*alpha_y_
    _t98 = a_zeta_*alpha_x_
    _t99 = a_x_*alpha_z_
    _t100 = V_y_*_t32
    _t101 = V_x_*_t31
    _out = _np.zeros((8,) + _batch)
    _out[0] = _t0*_t32*(-_t20*_t22 - 2*_t24 - _t30) + _t19*_t50*position_integrator_gain_error_Phi_ + _t31*_t35*(R_*U_*_t19*_t34 - _t22*_t33) + _t31*delta_Lam_*position_integrator_gain_error_Phi_*(-_t22*_t49 + _t48) + _t42*delta_Lam_*(-_t22*_t41 - _t40) + _t42*position_integrator_gain_error_Phi_*(_t45 + _t47) + _t43*_t44 + _t43*_t9*position_integrator_gain_error_Phi_ - _t50*_t51
    _out[1] = _t19*_t77*delta_V_x_ + _t35*_t52*_t73 + _t52*_t72 - _t52*_t78 - _t52*_t79 + _t65*(_t46*_t52 + _t52*_t56 + _t62*_t64 + _t12**2*_t58/_t10**3) + _t69*_t77*delta_Lam_ + _t70*position_integrator_gain_error_Lam_*(_t58*_t63 + _t62*_t68) + _t71*(_t64*_t69 + _t67*_t68) + _t74*_t75 + _t74*_t76*position_integrator_gain_error_Lam_ - _t77*_t9*delta_V_y_ + _t80*_t81 + _t81*_t82 - _t81*_t83
    _out[2] = _t35*(U_*_t59 - _t73*_t85) + _t65*(-_t46*_t85*(2*_t86 + 2) - _t56*_t85 - _t60 - _t62*_t88) + _t71*(-2*U_*_t38 - 2*_t67*_t85 - _t69*_t88) - _t72*_t85 - _t75*_t85*delta_A_ + _t78*_t85 + _t79*_t85 - _t80*_t89 - _t82*_t89 + _t83*_t89
    _out[3] = -V_zeta_*_t43*velocity_integrator_gain_error_x_ - _t90*_t91 - _t91*_t92 + _t93*accel_scale_error_x_ + _t93*velocity_integrator_gain_error_x_ - _t94*accel_scale_error_x_ - _t94*velocity_integrator_gain_error_x_ + a_x_*accel_scale_error_x_*velocity_integrator_gain_error_x_ + accel_bias_x_*velocity_integrator_gain_error_x_ + velocity_integrator_gain_error_x_*velocity_integrator_offset_x_
    _out[4] = -V_zeta_*_t50*velocity_integrator_gain_error_y_ - _t92*_t96 - _t95*_t96 + _t97*a_x_ + _t98*accel_scale_error_y_ + _t98*velocity_integrator_gain_error_y_ - _t99*accel_scale_error_y_ - _t99*velocity_integrator_gain_error_y_ + a_y_*accel_scale_error_y_*velocity_integrator_gain_error_y_ + accel_bias_y_*velocity_integrator_gain_error_y_ + velocity_integrator_gain_error_y_*velocity_integrator_offset_y_
    _out[5] = _t100*_t90 - _t100*_t92 + _t101*_t97 - _t50*correction_gain_error_x_ + alpha_y_*gyro_drift_z_
    _out[6] = ((1/2))*V_x_*_t31*_t92 - V_x_*_t32*_t95 + _t31*correction_gain_error_y_*delta_V_x_ - alpha_x_*gyro_drift_z_
    _out[7] = _t101*alpha_x_*correction_gain_error_y_ - _t101*alpha_y_*alpha_z_ + _t43*alpha_x_ + alpha_x_*gyro_drift_y_
    return _out


def initial_state(c, u, p):
    """True initial state from navigation initial conditions.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, ...)
        x(0)
    """
    c = _as_vector(c, 5, 'c', 'initial_state')
    u = _as_vector(u, 4, 'u', 'initial_state')
    p = _as_vector(p, 5, 'p', 'initial_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    heading_ = c[2]
    v_N_ = c[3]
    v_E_ = c[4]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_longitude_ = p[3]
    orth_azimuth_ = p[4]
    _t0 = _m.cos(orth_latitude_)
    _t1 = _m.sin(latitude_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(latitude_)
    _t4 = longitude_ - orth_longitude_
    _t5 = _t3*_m.cos(_t4)
    _t6 = _t0*_t1 - _t2*_t5
    _t7 = _m.sin(orth_azimuth_)
    _t8 = _m.cos(orth_azimuth_)
    _t9 = _t3*_m.sin(_t4)
    _t10 = _t6*_t7 - _t8*_t9
    _t11 = _t6*_t8 + _t7*_t9
    _t12 = _t0*_t5 + _t1*_t2
    _t13 = _t11**2 + _t12**2
    _t14 = _m.sqrt(_t13)
    _t15 = 1/_m.sqrt(_t10**2 + _t13)
    _t16 = 1/_t14
    _t17 = _t16*_t2
    _t18 = _m.sin(heading_)
    _t19 = _m.cos(heading_)
    _t20 = R_*U_*_t3
    _out = _np.zeros((5,) + _batch)
    _out[0] = _m.arctan2(_t10, _t14)
    _out[1] = _m.arctan2(_t11, _t12)
    _out[2] = -heading_ + _m.arctan2(-_t0*_t10*_t11*_t15*_t16*_t8 + _t0*_t14*_t15*_t7 - _t10*_t12*_t15*_t17, _t0*_t12*_t16*_t8 - _t11*_t17)
    _out[3] = _t18*_t20 + _t18*v_E_ + _t19*v_N_
    _out[4] = _t18*v_N_ - _t19*_t20 - _t19*v_E_
    return _out


def initial_real_state(c, u, w, p):
    """Real-work initial state, initial-error sources applied.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    w : array_like, shape (25, ...)
        error-source magnitudes, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, ...)
        xr(0)
    """
    c = _as_vector(c, 5, 'c', 'initial_real_state')
    u = _as_vector(u, 4, 'u', 'initial_real_state')
    w = _as_vector(w, 25, 'w', 'initial_real_state')
    p = _as_vector(p, 5, 'p', 'initial_real_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    heading_ = c[2]
    v_N_ = c[3]
    v_E_ = c[4]
    initial_tilt_x_ = w[0]
    initial_tilt_y_ = w[1]
    initial_azimuth_error_ = w[2]
    initial_A_error_ = w[3]
    initial_velocity_error_x_ = w[4]
    initial_velocity_error_y_ = w[5]
    initial_Phi_error_ = w[6]
    initial_Lam_error_ = w[7]
    R_ = p[0]
    U_ = p[1]
    orth_latitude_ = p[2]
    orth_longitude_ = p[3]
    orth_azimuth_ = p[4]
    _t0 = _m.cos(orth_latitude_)
    _t1 = _m.sin(latitude_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(latitude_)
    _t4 = longitude_ - orth_longitude_
    _t5 = _t3*_m.cos(_t4)
    _t6 = _t0*_t1 - _t2*_t5
    _t7 = _m.sin(orth_azimuth_)
    _t8 = _m.cos(orth_azimuth_)
    _t9 = _t3*_m.sin(_t4)
    _t10 = _t6*_t7 - _t8*_t9
    _t11 = _t6*_t8 + _t7*_t9
    _t12 = _t0*_t5 + _t1*_t2
    _t13 = _t11**2 + _t12**2
    _t14 = _m.sqrt(_t13)
    _t15 = 1/_m.sqrt(_t10**2 + _t13)
    _t16 = 1/_t14
    _t17 = _t16*_t2
    _t18 = _m.sin(heading_)
    _t19 = _m.cos(heading_)
    _t20 = R_*U_*_t3
    _out = _np.zeros((8,) + _batch)
    _out[0] = initial_Phi_error_ + _m.arctan2(_t10, _t14)
    _out[1] = initial_Lam_error_ + _m.arctan2(_t11, _t12)
    _out[2] = -heading_ + initial_A_error_ + _m.arctan2(-_t0*_t10*_t11*_t15*_t16*_t8 + _t0*_t14*_t15*_t7 - _t10*_t12*_t15*_t17, _t0*_t12*_t16*_t8 - _t11*_t17)
    _out[3] = _t18*_t20 + _t18*v_E_ + _t19*v_N_ + initial_velocity_error_x_
    _out[4] = _t18*v_N_ - _t19*_t20 - _t19*v_E_ + initial_velocity_error_y_
    _out[5] = initial_tilt_x_
    _out[6] = initial_tilt_y_
    _out[7] = initial_azimuth_error_
    return _out


def initial_error_matrix(c, u, p):
    """First-order map from error sources to the initial error state.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (8, 25, ...)
        E: xe(0) = E w
    """
    c = _as_vector(c, 5, 'c', 'initial_error_matrix')
    u = _as_vector(u, 4, 'u', 'initial_error_matrix')
    p = _as_vector(p, 5, 'p', 'initial_error_matrix')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    _out = _np.zeros((8, 25) + _batch)
    _out[0, 6] = 1
    _out[1, 7] = 1
    _out[2, 3] = 1
    _out[3, 4] = 1
    _out[4, 5] = 1
    _out[5, 0] = 1
    _out[6, 1] = 1
    _out[7, 2] = 1
    return _out


def domain_margins(x, u, p):
    """Margins that must be positive for the formulas to hold (see DOMAIN).

    Parameters
    ----------
    x : array_like, shape (5, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (3, ...)
        one margin per condition of DOMAIN
    """
    x = _as_vector(x, 5, 'x', 'domain_margins')
    u = _as_vector(u, 4, 'u', 'domain_margins')
    p = _as_vector(p, 5, 'p', 'domain_margins')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    R_ = p[0]
    orth_latitude_ = p[2]
    orth_azimuth_ = p[4]
    _t0 = _m.cos(Phi_)
    _t1 = _m.sin(Lam_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_)
    _t4 = _m.cos(orth_azimuth_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = _m.sin(Phi_)
    _out = _np.zeros((3,) + _batch)
    _out[0] = _t0**2 - 1e-12
    _out[1] = (-_t1*_t2 + _t3*_t4*_t5)**2 + (_t0*_t5*_m.sin(orth_azimuth_) - _t1*_t4*_t5*_t6 - _t2*_t3*_t6)**2 - 1e-12
    _out[2] = R_
    return _out


def initial_domain_margins(c, u, p):
    """Margins that must be positive for the initial conditions.

    Parameters
    ----------
    c : array_like, shape (5, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (5, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (2, ...)
        one margin per condition of INITIAL_DOMAIN
    """
    c = _as_vector(c, 5, 'c', 'initial_domain_margins')
    u = _as_vector(u, 4, 'u', 'initial_domain_margins')
    p = _as_vector(p, 5, 'p', 'initial_domain_margins')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    R_ = p[0]
    _out = _np.zeros((2,) + _batch)
    _out[0] = _m.cos(latitude_)**2 - 1e-12
    _out[1] = R_
    return _out


FUNCTIONS = ('ideal_rhs', 'real_rhs', 'real_rhs_small_angle', 'second_order_small_angle', 'outputs', 'state_matrix', 'source_matrix', 'output_matrix', 'second_order', 'initial_state', 'initial_real_state', 'initial_error_matrix', 'domain_margins', 'initial_domain_margins')
