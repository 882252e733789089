# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/geodetic_vertical.py.
# Edit the model definition and run `make derive` again.

"""numpy functions of the model 'geodetic_vertical' (broadcasting)."""

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
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        time derivative of the true state
    """
    x = _as_vector(x, 4, 'x', 'ideal_rhs')
    u = _as_vector(u, 4, 'u', 'ideal_rhs')
    p = _as_vector(p, 6, 'p', 'ideal_rhs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    a_xi_ = u[0]
    a_eta_ = u[1]
    V_zeta_ = u[3]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    _t0 = _m.cos(Phi_)
    _t1 = _m.sin(orth_latitude_)
    _t2 = _m.cos(Lam_)
    _t3 = _t1*_t2
    _t4 = _m.sin(Phi_)
    _t5 = _m.cos(orth_latitude_)
    _t6 = _t5*_m.cos(orth_angle_)
    _t7 = _m.sin(Lam_)
    _t8 = _m.sin(orth_angle_)
    _t9 = -_t0*_t3 + _t0*_t5*_t7*_t8 - _t4*_t6
    _t10 = 1/(a_*(-_t9**2*e2_/(2 - e2_) + 1))
    _t11 = W_eta_*_t10
    _t12 = _t5*_t8
    _t13 = 2*U_
    _t14 = V_zeta_*_t13
    _t15 = _m.tan(Phi_)
    _out = _np.zeros((4,) + _batch)
    _out[0] = -_t11
    _out[1] = W_xi_*_t10/_t0
    _out[2] = 2*U_*W_eta_*_t9 - W_xi_*_t11*_t15 - _t14*(_t0*_t6 + _t12*_t4*_t7 - _t3*_t4) + a_xi_
    _out[3] = W_xi_**2*_t10*_t15 - W_xi_*_t13*_t9 + _t14*(_t1*_t7 + _t12*_t2) + a_eta_
    return _out


def real_rhs(xr, x, u, w, p):
    """Real-work equations: dxr/dt (needs the true state x for the platform).

    Parameters
    ----------
    xr : array_like, shape (7, ...)
        real-work state: the 4 computed states in the order of x, then the platform angles alpha_x, alpha_y, alpha_z (rad)
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 7, 'xr', 'real_rhs')
    x = _as_vector(x, 4, 'x', 'real_rhs')
    u = _as_vector(u, 4, 'u', 'real_rhs')
    w = _as_vector(w, 12, 'w', 'real_rhs')
    p = _as_vector(p, 6, 'p', 'real_rhs')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    Phi_c_ = xr[0]
    Lam_c_ = xr[1]
    W_xi_c_ = xr[2]
    W_eta_c_ = xr[3]
    alpha_x_ = xr[4]
    alpha_y_ = xr[5]
    alpha_z_ = xr[6]
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    gyro_drift_x_ = w[7]
    gyro_drift_y_ = w[8]
    gyro_drift_z_ = w[9]
    accel_bias_x_ = w[10]
    accel_bias_y_ = w[11]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    _t0 = 1/a_
    _t1 = _m.cos(Phi_c_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_c_)
    _t4 = _t2*_t3
    _t5 = _m.sin(Phi_c_)
    _t6 = _m.cos(orth_latitude_)
    _t7 = _t6*_m.cos(orth_angle_)
    _t8 = _m.sin(Lam_c_)
    _t9 = _m.sin(orth_angle_)
    _t10 = -_t1*_t4 + _t1*_t6*_t8*_t9 - _t5*_t7
    _t11 = _t10**2
    _t12 = 2 - e2_
    _t13 = e2_/_t12
    _t14 = _t0/(-_t11*_t13 + 1)
    _t15 = W_eta_c_*_t14
    _t16 = -_t15
    _t17 = W_xi_c_*_t14
    _t18 = _m.sin(alpha_y_)
    _t19 = _m.sin(alpha_z_)
    _t20 = _m.cos(alpha_z_)
    _t21 = _t19*a_eta_ + _t20*a_xi_
    _t22 = _m.cos(alpha_y_)
    _t23 = _t6*_t9
    _t24 = _t1*_t7 + _t23*_t5*_t8 - _t4*_t5
    _t25 = U_*_t24
    _t26 = 2*V_zeta_
    _t27 = _m.tan(Phi_c_)
    _t28 = _m.cos(alpha_x_)
    _t29 = _m.sin(alpha_x_)
    _t30 = U_*_t10
    _t31 = _t2*_t8 + _t23*_t3
    _t32 = U_*_t31
    _t33 = _m.cos(Phi_)
    _t34 = _m.cos(Lam_)
    _t35 = _t2*_t34
    _t36 = _m.sin(Phi_)
    _t37 = _m.sin(Lam_)
    _t38 = -_t33*_t35 + _t33*_t37*_t6*_t9 - _t36*_t7
    _t39 = _t38**2
    _t40 = _t0/(-_t13*_t39 + 1)
    _t41 = W_xi_*_t40
    _t42 = _t41*_m.tan(Phi_)
    _t43 = W_eta_*_t40
    _t44 = _t2*_t37 + _t23*_t34
    _t45 = 2*_t13
    _t46 = 2*e2_**2/_t12**2
    _t47 = -_t38*_t45 + _t38*_t46*(1 - 2*_t39)
    _t48 = _t44*_t47
    _t49 = U_*_t38 - _t42 + _t43*_t48
    _t50 = U_*_t44 - _t42*_t48 - _t43
    _t51 = _t23*_t36*_t37 + _t33*_t7 - _t35*_t36
    _t52 = U_*_t51 + _t41 - _t42*_t47*_t51
    _t53 = _t19*_t52 + _t20*_t50
    _t54 = -_t10*_t45 + _t10*_t46*(1 - 2*_t11)
    _t55 = _t17*_t27
    _t56 = _t17 - _t24*_t54*_t55 + _t25 + gyro_drift_y_
    _t57 = _t31*_t54
    _t58 = _t15*_t57 + _t30 - _t55 + gyro_drift_z_
    _t59 = -_t18*_t53 - _t22*_t49 + _t28*_t58 + _t29*_t56
    _out = _np.zeros((7,) + _batch)
    _out[0] = _t16
    _out[1] = _t17/_t1
    _out[2] = 2*U_*W_eta_c_*_t10 - W_xi_c_*_t15*_t27 - _t18*a_zeta_ + _t21*_t22 - _t25*_t26 + accel_bias_x_
    _out[3] = W_xi_c_**2*_t14*_t27 - 2*W_xi_c_*_t30 + _t26*_t32 + _t28*(-_t19*a_xi_ + _t20*a_eta_) + _t29*(_t18*_t21 + _t22*a_zeta_) + accel_bias_y_
    _out[4] = _t16 + _t18*_t49 - _t22*_t53 + _t32 - _t55*_t57 + _t59*_m.tan(alpha_y_) + gyro_drift_x_
    _out[5] = _t19*_t50 - _t20*_t52 + _t28*_t56 - _t29*_t58
    _out[6] = _t59/_t22
    return _out


def real_rhs_small_angle(xr, x, u, w, p):
    """Real-work equations with the source's small-angle platform: dxr/dt.

    Parameters
    ----------
    xr : array_like, shape (7, ...)
        real-work state: the 4 computed states in the order of x, then the platform angles alpha_x, alpha_y, alpha_z (rad)
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 7, 'xr', 'real_rhs_small_angle')
    x = _as_vector(x, 4, 'x', 'real_rhs_small_angle')
    u = _as_vector(u, 4, 'u', 'real_rhs_small_angle')
    w = _as_vector(w, 12, 'w', 'real_rhs_small_angle')
    p = _as_vector(p, 6, 'p', 'real_rhs_small_angle')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    Phi_c_ = xr[0]
    Lam_c_ = xr[1]
    W_xi_c_ = xr[2]
    W_eta_c_ = xr[3]
    alpha_x_ = xr[4]
    alpha_y_ = xr[5]
    alpha_z_ = xr[6]
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    gyro_drift_x_ = w[7]
    gyro_drift_y_ = w[8]
    gyro_drift_z_ = w[9]
    accel_bias_x_ = w[10]
    accel_bias_y_ = w[11]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    _t0 = 1/a_
    _t1 = _m.cos(Phi_c_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Lam_c_)
    _t4 = _t2*_t3
    _t5 = _m.sin(Phi_c_)
    _t6 = _m.cos(orth_latitude_)
    _t7 = _t6*_m.cos(orth_angle_)
    _t8 = _m.sin(Lam_c_)
    _t9 = _m.sin(orth_angle_)
    _t10 = -_t1*_t4 + _t1*_t6*_t8*_t9 - _t5*_t7
    _t11 = _t10**2
    _t12 = 2 - e2_
    _t13 = e2_/_t12
    _t14 = _t0/(-_t11*_t13 + 1)
    _t15 = W_eta_c_*_t14
    _t16 = -_t15
    _t17 = W_xi_c_*_t14
    _t18 = _t6*_t9
    _t19 = _t1*_t7 + _t18*_t5*_t8 - _t4*_t5
    _t20 = U_*_t19
    _t21 = 2*V_zeta_
    _t22 = U_*_t10
    _t23 = 2*_t22
    _t24 = _m.tan(Phi_c_)
    _t25 = _t18*_t3 + _t2*_t8
    _t26 = U_*_t25
    _t27 = _m.cos(Phi_)
    _t28 = _m.cos(Lam_)
    _t29 = _t2*_t28
    _t30 = _m.sin(Phi_)
    _t31 = _m.sin(Lam_)
    _t32 = -_t27*_t29 + _t27*_t31*_t6*_t9 - _t30*_t7
    _t33 = U_*_t32
    _t34 = _t32**2
    _t35 = _t0/(-_t13*_t34 + 1)
    _t36 = W_xi_*_t35
    _t37 = _t36*_m.tan(Phi_)
    _t38 = W_eta_*_t35
    _t39 = _t18*_t28 + _t2*_t31
    _t40 = 2*_t13
    _t41 = 2*e2_**2/_t12**2
    _t42 = -_t32*_t40 + _t32*_t41*(1 - 2*_t34)
    _t43 = _t39*_t42
    _t44 = _t38*_t43
    _t45 = _t33 - _t37 + _t44
    _t46 = _t18*_t30*_t31 + _t27*_t7 - _t29*_t30
    _t47 = U_*_t46
    _t48 = _t37*_t42*_t46
    _t49 = _t36 + _t47 - _t48
    _t50 = _t17*_t24
    _t51 = -_t10*_t40 + _t10*_t41*(1 - 2*_t11)
    _t52 = _t25*_t51
    _t53 = -U_*_t39 + _t37*_t43 + _t38
    _t54 = -_t53
    _out = _np.zeros((7,) + _batch)
    _out[0] = _t16
    _out[1] = _t17/_t1
    _out[2] = W_eta_c_*_t23 - W_xi_c_*_t15*_t24 - _t20*_t21 + a_eta_*alpha_z_ + a_xi_ - a_zeta_*alpha_y_ + accel_bias_x_
    _out[3] = W_xi_c_**2*_t14*_t24 - W_xi_c_*_t23 + _t21*_t26 + a_eta_ - a_xi_*alpha_z_ + a_zeta_*alpha_x_ + accel_bias_y_
    _out[4] = _t16 + _t26 + _t45*alpha_y_ - _t49*alpha_z_ - _t50*_t52 + _t53 + gyro_drift_x_
    _out[5] = _t17 - _t19*_t50*_t51 + _t20 - _t36 - _t45*alpha_x_ - _t47 + _t48 + _t54*alpha_z_ + gyro_drift_y_
    _out[6] = _t15*_t52 + _t22 - _t33 + _t37 - _t44 + _t49*alpha_x_ - _t50 - _t54*alpha_y_ + gyro_drift_z_
    return _out


def second_order_small_angle(x, u, p, xe, w):
    """Second-order term of the error equations of the small-angle platform.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
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
    u = _as_vector(u, 4, 'u', 'second_order_small_angle')
    p = _as_vector(p, 6, 'p', 'second_order_small_angle')
    xe = _as_vector(xe, 7, 'xe', 'second_order_small_angle')
    w = _as_vector(w, 12, 'w', 'second_order_small_angle')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    V_zeta_ = u[3]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    delta_Phi_ = xe[0]
    delta_Lam_ = xe[1]
    delta_W_xi_ = xe[2]
    delta_W_eta_ = xe[3]
    _t0 = 2 - e2_
    _t1 = 1/_t0
    _t2 = _t1*e2_
    _t3 = 1/a_
    _t4 = _m.cos(Phi_)
    _t5 = _m.cos(Lam_)
    _t6 = _m.sin(orth_latitude_)
    _t7 = _t4*_t5*_t6
    _t8 = _m.sin(Phi_)
    _t9 = _m.cos(orth_latitude_)
    _t10 = _t9*_m.cos(orth_angle_)
    _t11 = _t10*_t8
    _t12 = _m.sin(Lam_)
    _t13 = _t9*_m.sin(orth_angle_)
    _t14 = _t12*_t13
    _t15 = _t14*_t4
    _t16 = _t11 - _t15 + _t7
    _t17 = -_t16
    _t18 = _t17**2
    _t19 = -_t18*_t2 + 1
    _t20 = _t19**(-2)
    _t21 = _t20*_t3
    _t22 = _t2*_t21
    _t23 = W_eta_*_t22
    _t24 = _t12*_t6
    _t25 = _t24*_t4
    _t26 = _t13*_t5
    _t27 = _t26*_t4
    _t28 = _t25 + _t27
    _t29 = 2*_t25 + 2*_t27
    _t30 = _t28*_t29
    _t31 = _t23*_t30
    _t32 = 2*_t15
    _t33 = -_t32 + 2*_t4*_t5*_t6
    _t34 = _t17*_t23
    _t35 = _t33*_t34
    _t36 = _t29**2
    _t37 = e2_**2
    _t38 = _t0**(-2)
    _t39 = _t37*_t38
    _t40 = _t36*_t39
    _t41 = 2*_t18
    _t42 = _t19**(-3)
    _t43 = _t3*_t42
    _t44 = _t41*_t43
    _t45 = W_eta_*_t44
    _t46 = _t40*_t45
    _t47 = _t31 + _t35 + _t46
    _t48 = ((1/2))*delta_Lam_**2
    _t49 = _t10*_t4
    _t50 = _t14*_t8
    _t51 = -_t5*_t6*_t8 + _t50
    _t52 = _t49 + _t51
    _t53 = -_t52
    _t54 = -2*_t49 + 2*_t5*_t6*_t8 - 2*_t50
    _t55 = _t53*_t54
    _t56 = _t23*_t55
    _t57 = 2*_t11 - _t32 + 2*_t7
    _t58 = _t34*_t57
    _t59 = _t54**2
    _t60 = _t39*_t59
    _t61 = _t45*_t60
    _t62 = _t56 + _t58 + _t61
    _t63 = ((1/2))*delta_Phi_**2
    _t64 = 2*W_eta_
    _t65 = _t22*_t64
    _t66 = _t28*_t54
    _t67 = _t65*_t66
    _t68 = _t24*_t8
    _t69 = _t26*_t8
    _t70 = -2*_t68 - 2*_t69
    _t71 = _t17*_t70
    _t72 = _t65*_t71
    _t73 = 4*_t18*_t39
    _t74 = _t29*_t73
    _t75 = _t43*_t54*_t74
    _t76 = W_eta_*_t75
    _t77 = _t67 + _t72 + _t76
    _t78 = ((1/2))*delta_Phi_
    _t79 = _t78*delta_Lam_
    _t80 = _t29*delta_Lam_
    _t81 = _t17*_t22
    _t82 = _t81*delta_W_eta_
    _t83 = -_t54*_t82*delta_Phi_ - _t80*_t82
    _t84 = 1/_t4
    _t85 = W_xi_*_t22
    _t86 = _t30*_t85
    _t87 = _t17*_t85
    _t88 = _t33*_t87
    _t89 = W_xi_*_t44
    _t90 = _t40*_t89
    _t91 = _t3/_t19
    _t92 = W_xi_*_t91
    _t93 = _t55*_t85
    _t94 = _t57*_t87
    _t95 = _t60*_t89
    _t96 = _t8/_t4**2
    _t97 = 2*W_xi_
    _t98 = _t81*_t97
    _t99 = _t96*_t98
    _t100 = _t22*_t97
    _t101 = _t100*_t66
    _t102 = _t100*_t71
    _t103 = 2*_t91
    _t104 = 2*_t2
    _t105 = _t104*_t17
    _t106 = _t105*_t21
    _t107 = _t106*_t54
    _t108 = _t78*delta_W_xi_
    _t109 = _t80*delta_W_xi_
    _t110 = _t109*_t81
    _t111 = -_t15 + _t7
    _t112 = -_t51
    _t113 = 2*V_zeta_
    _t114 = _m.tan(Phi_)
    _t115 = W_xi_*_t114
    _t116 = U_*_t53
    _t117 = _t114**2
    _t118 = 2*_t117 + 2
    _t119 = _t114*_t92
    _t120 = _t118*_t119
    _t121 = _t117 + 1
    _t122 = _t64*_t87
    _t123 = _t121*_t122
    _t124 = _t68 + _t69
    _t125 = -_t124
    _t126 = 4*U_*_t28
    _t127 = _t114*_t29
    _t128 = _t127*_t98
    _t129 = ((1/2))*delta_Lam_
    _t130 = _t129*delta_W_eta_
    _t131 = -4*_t116
    _t132 = _t121*_t92
    _t133 = 2*_t132
    _t134 = _t114*_t54
    _t135 = _t134*_t98
    _t136 = _t78*delta_W_eta_
    _t137 = _t64*_t91
    _t138 = _t17*_t65
    _t139 = _t114*_t91
    _t140 = U_*_t111
    _t141 = _t24 + _t26
    _t142 = -_t141
    _t143 = W_xi_**2
    _t144 = _t114*_t143
    _t145 = _t144*_t22
    _t146 = _t144*_t81
    _t147 = _t144*_t44
    _t148 = U_*_t16
    _t149 = _t121*_t143
    _t150 = U_*_t125
    _t151 = _t106*_t29
    _t152 = _t104*_t28
    _t153 = _t129*delta_W_xi_
    _t154 = 4*_t17
    _t155 = 1 - _t41
    _t156 = _t154*_t39
    _t157 = _t156*_t29
    _t158 = -_t104*_t111 + 2*_t111*_t155*_t37*_t38 - _t154*_t40 - _t157*_t28 - _t33*_t73
    _t159 = _t141*_t158
    _t160 = -_t105 + 2*_t155*_t17*_t39
    _t161 = _t142*_t160
    _t162 = -_t152 + 2*_t155*_t28*_t37*_t38 - _t74
    _t163 = -_t14 + _t5*_t6
    _t164 = 2*_t119
    _t165 = _t163*_t164
    _t166 = _t114*_t86
    _t167 = _t141*_t160
    _t168 = _t114*_t88
    _t169 = _t160*_t163
    _t170 = _t141*_t162
    _t171 = _t114*_t90
    _t172 = -_t104*_t16 + 2*_t155*_t16*_t37*_t38 - _t156*_t55 - _t156*_t59 - _t57*_t73
    _t173 = _t141*_t172
    _t174 = -_t104*_t53 + 2*_t155*_t37*_t38*_t53 - _t54*_t73
    _t175 = _t133*_t141
    _t176 = _t120*_t160
    _t177 = _t114*_t93
    _t178 = _t114*_t94
    _t179 = _t121*_t98
    _t180 = _t179*_t54
    _t181 = _t141*_t174
    _t182 = _t114*_t95
    _t183 = -_t104*_t125 + 2*_t125*_t155*_t37*_t38 - _t157*_t53 - _t157*_t54 - _t70*_t73
    _t184 = _t141*_t183
    _t185 = _t179*_t29
    _t186 = _t101*_t114
    _t187 = _t102*_t114
    _t188 = _t115*_t75
    _t189 = 2*_t139
    _t190 = _t141*_t189
    _t191 = _t151*_t167
    _t192 = _t103*_t121
    _t193 = _t160*_t192
    _t194 = _t107*_t114
    _t195 = _t119*_t160
    _t196 = _t119*_t52
    _t197 = _t124*_t164
    _t198 = _t160*_t52
    _t199 = _t124*_t160
    _t200 = _t128*_t52
    _t201 = _t133*_t160
    _t202 = _t133*_t52
    _t203 = _t164*_t17
    _t204 = _t160*_t41*_t85
    _t205 = _t135*_t52
    _t206 = _t160*_t189
    _t207 = _t189*_t52
    _t208 = W_eta_*_t91
    _t209 = _t137*_t163
    _t210 = _t138*_t29
    _t211 = _t141*_t210
    _t212 = _t138*_t54
    _t213 = _t103*_t141
    _out = _np.zeros((7,) + _batch)
    _out[0] = -_t47*_t48 - _t62*_t63 - _t77*_t79 + _t83
    _out[1] = _t108*(_t103*_t96 + _t107*_t84) + _t110*_t84 + _t48*(_t84*_t86 + _t84*_t88 + _t84*_t90) + _t63*(_t54*_t99 + _t84*_t92 + _t84*_t93 + _t84*_t94 + _t84*_t95 + 2*_t8**2*_t92/_t4**3) + _t79*(W_xi_*_t75*_t84 + _t101*_t84 + _t102*_t84 + _t29*_t99)
    _out[2] = _t108*(-_t121*_t137 - _t134*_t138) - _t109*_t114*_t34 + _t130*(_t126 - _t128) + _t136*(-_t131 - _t133 - _t135) - _t139*delta_W_eta_*delta_W_xi_ + _t48*(2*U_*W_eta_*_t111 - U_*_t112*_t113 - _t115*_t31 - _t115*_t35 - _t115*_t46) + _t63*(2*U_*W_eta_*_t16 - W_eta_*_t120 - _t113*_t116 - _t115*_t56 - _t115*_t58 - _t115*_t61 - _t123*_t54) + _t79*(4*U_*W_eta_*_t125 - V_zeta_*_t126 - _t114*_t122*_t70 - _t114*_t64*_t66*_t85 - _t115*_t76 - _t123*_t29)
    _out[3] = _t108*(_t131 + 4*_t132 + _t134*_t154*_t85) + _t139*delta_W_xi_**2 + _t153*(4*W_xi_*_t1*_t114*_t17*_t20*_t29*_t3*e2_ - _t126) + _t48*(U_*_t113*_t142 - _t140*_t97 + _t145*_t30 + _t146*_t33 + _t147*_t40) + _t63*(_t107*_t149 + _t118*_t139*_t143 + _t145*_t55 + _t146*_t57 + _t147*_t60 - _t148*_t97) + _t79*(-4*W_xi_*_t150 + _t106*_t144*_t70 + _t144*_t152*_t21*_t54 + _t144*_t75 + _t149*_t151)
    _out[4] = _t108*(-_t141*_t193 - _t167*_t194 - _t174*_t190) + _t153*(-_t114*_t191 - _t162*_t190 - _t169*_t189) + _t48*(U_*_t142 - _t119*_t159 - _t119*_t161 - _t128*_t169 - _t128*_t170 - _t162*_t165 - _t166*_t167 - _t167*_t168 - _t167*_t171 - _t47) + _t63*(-_t119*_t173 - _t135*_t181 - _t141*_t176 - _t167*_t177 - _t167*_t178 - _t167*_t180 - _t167*_t182 - _t174*_t175 - _t62) + _t79*(-_t128*_t181 - _t133*_t169 - _t135*_t169 - _t135*_t170 - _t162*_t175 - _t164*_t184 - _t165*_t174 - _t167*_t185 - _t167*_t186 - _t167*_t187 - _t167*_t188 - _t77) + _t83
    _out[5] = _t108*(2*_t1*_t17*_t20*_t3*_t54*e2_ - _t17*_t206 - _t174*_t207 - _t193*_t52 - _t194*_t198) + _t153*(2*_t1*_t17*_t20*_t29*_t3*e2_ - _t114*_t151*_t198 - _t124*_t206 - _t162*_t207) + _t48*(U_*_t112 + W_xi_*_t1*_t17*_t20*_t3*_t33*e2_ + W_xi_*_t1*_t20*_t28*_t29*_t3*e2_ + 2*W_xi_*_t18*_t3*_t36*_t37*_t38*_t42 - _t112*_t195 - _t128*_t199 - _t158*_t196 - _t162*_t197 - _t162*_t200 - _t166*_t198 - _t168*_t198 - _t171*_t198) + _t63*(U_*_t53 + W_xi_*_t1*_t17*_t20*_t3*_t57*e2_ + W_xi_*_t1*_t20*_t3*_t53*_t54*e2_ + 2*W_xi_*_t18*_t3*_t37*_t38*_t42*_t59 - _t134*_t204 - _t17*_t201 - _t172*_t196 - _t174*_t202 - _t174*_t203 - _t174*_t205 - _t176*_t52 - _t177*_t198 - _t178*_t198 - _t180*_t198 - _t182*_t198 - _t195*_t53) + _t79*(2*U_*_t28 + 2*W_xi_*_t1*_t17*_t20*_t3*_t70*e2_ + 2*W_xi_*_t1*_t20*_t28*_t3*_t54*e2_ + 4*W_xi_*_t18*_t29*_t3*_t37*_t38*_t42*_t54 - _t124*_t201 - _t127*_t204 - _t135*_t199 - _t162*_t202 - _t162*_t203 - _t162*_t205 - _t174*_t197 - _t174*_t200 - 2*_t183*_t196 - _t185*_t198 - _t186*_t198 - _t187*_t198 - _t188*_t198 - 2*_t195*_t28)
    _out[6] = _t108*(-_t192 - _t194) - _t110*_t114 + _t130*(_t103*_t169 + _t162*_t213 + _t191) + _t136*(_t107*_t167 + _t174*_t213) + _t48*(_t140 + _t159*_t208 + _t161*_t208 + _t162*_t209 + _t162*_t211 - _t166 + _t167*_t31 + _t167*_t35 + _t167*_t46 - _t168 + _t169*_t210 - _t171) + _t63*(-_t120 + _t148 + _t167*_t56 + _t167*_t58 + _t167*_t61 + _t173*_t208 - _t177 - _t178 - _t180 + _t181*_t212 - _t182) + _t79*(_t137*_t184 + 2*_t150 + _t167*_t67 + _t167*_t72 + _t167*_t76 + _t169*_t212 + _t170*_t212 + _t174*_t209 + _t174*_t211 - _t185 - _t186 - _t187 - _t188)
    return _out


def outputs(x, u, p):
    """Navigation outputs of a state (true or computed part of xr).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, ...)
        outputs in SI units
    """
    x = _as_vector(x, 4, 'x', 'outputs')
    u = _as_vector(u, 4, 'u', 'outputs')
    p = _as_vector(p, 6, 'p', 'outputs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    orth_latitude_ = p[3]
    orth_longitude_ = p[4]
    orth_angle_ = p[5]
    _t0 = _m.cos(Phi_)
    _t1 = _m.sin(orth_latitude_)
    _t2 = _m.cos(Lam_)
    _t3 = _t1*_t2
    _t4 = _m.sin(Phi_)
    _t5 = _m.cos(orth_angle_)
    _t6 = _m.cos(orth_latitude_)
    _t7 = _t5*_t6
    _t8 = _m.sin(orth_angle_)
    _t9 = _t6*_t8
    _t10 = _m.sin(Lam_)
    _t11 = _t0*_t10
    _t12 = _t1*_t10 + _t2*_t9
    _t13 = _t0*_t7 + _t10*_t4*_t9 - _t3*_t4
    _t14 = _m.sqrt(_t12**2 + _t13**2)
    _t15 = _m.cos(orth_longitude_)
    _t16 = _t15*_t8
    _t17 = _m.sin(orth_longitude_)
    _t18 = _t15*_t5
    _t19 = _t17*_t8
    _t20 = _t0*_t2*_t6
    _t21 = 1/_t14
    _out = _np.zeros((5,) + _batch)
    _out[0] = _m.arctan2(_t0*_t3 - _t11*_t9 + _t4*_t7, _t14)
    _out[1] = _m.arctan2(_t11*(_t1*_t19 + _t18) + _t17*_t20 - _t4*(_t1*_t17*_t5 - _t16), _t11*(_t1*_t16 - _t17*_t5) + _t15*_t20 - _t4*(_t1*_t18 + _t19))
    _out[2] = _m.arctan2(_t12, _t13)
    _out[3] = _t21*(-W_eta_*_t13 - W_xi_*_t12)
    _out[4] = _t21*(W_eta_*_t12 - W_xi_*_t13)
    return _out


def state_matrix(x, u, p):
    """State matrix F of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 7, ...)
        F
    """
    x = _as_vector(x, 4, 'x', 'state_matrix')
    u = _as_vector(u, 4, 'u', 'state_matrix')
    p = _as_vector(p, 6, 'p', 'state_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    a_xi_ = u[0]
    a_eta_ = u[1]
    a_zeta_ = u[2]
    V_zeta_ = u[3]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    _t0 = _m.cos(Lam_)
    _t1 = _m.sin(Phi_)
    _t2 = _m.sin(orth_latitude_)
    _t3 = _m.cos(Phi_)
    _t4 = _m.cos(orth_latitude_)
    _t5 = _t4*_m.cos(orth_angle_)
    _t6 = _t3*_t5
    _t7 = _m.sin(Lam_)
    _t8 = _m.sin(orth_angle_)
    _t9 = _t4*_t8
    _t10 = _t7*_t9
    _t11 = _t1*_t10
    _t12 = 2*_t0*_t1*_t2 - 2*_t11 - 2*_t6
    _t13 = 1/a_
    _t14 = -_t0*_t2*_t3 - _t1*_t5 + _t3*_t4*_t7*_t8
    _t15 = _t14**2
    _t16 = 2 - e2_
    _t17 = 1/_t16
    _t18 = _t17*e2_
    _t19 = -_t15*_t18 + 1
    _t20 = _t19**(-2)
    _t21 = _t13*_t14*_t18*_t20
    _t22 = W_eta_*_t21
    _t23 = _t12*_t22
    _t24 = _t2*_t7
    _t25 = _t24*_t3
    _t26 = _t0*_t9
    _t27 = _t26*_t3
    _t28 = 2*_t25 + 2*_t27
    _t29 = _t22*_t28
    _t30 = 1/_t19
    _t31 = _t13*_t30
    _t32 = -_t31
    _t33 = W_xi_*_t31
    _t34 = 1/_t3
    _t35 = W_xi_*_t21
    _t36 = _t12*_t35
    _t37 = _t28*_t35
    _t38 = -_t0*_t1*_t2 + _t11 + _t6
    _t39 = -_t38
    _t40 = U_*_t14
    _t41 = 2*_t40
    _t42 = _m.tan(Phi_)
    _t43 = _t42**2 + 1
    _t44 = _t33*_t43
    _t45 = W_xi_*_t42
    _t46 = _t25 + _t27
    _t47 = _t1*_t24 + _t1*_t26
    _t48 = 2*V_zeta_
    _t49 = W_eta_*_t31
    _t50 = _t33*_t42
    _t51 = -_t50
    _t52 = U_*_t39
    _t53 = 2*W_xi_
    _t54 = W_xi_**2
    _t55 = _t21*_t42*_t54
    _t56 = U_*_t46
    _t57 = _t0*_t2 - _t10
    _t58 = _t24 + _t26
    _t59 = 2*_t18
    _t60 = 1 - 2*_t15
    _t61 = e2_**2
    _t62 = _t16**(-2)
    _t63 = _t61*_t62
    _t64 = -_t14*_t59 + 2*_t14*_t60*_t63
    _t65 = _t58*_t64
    _t66 = 4*_t15*_t63
    _t67 = -_t12*_t66 - _t39*_t59 + 2*_t39*_t60*_t61*_t62
    _t68 = _t50*_t58
    _t69 = _t36*_t42
    _t70 = _t57*_t64
    _t71 = -_t28*_t66 - _t46*_t59 + 2*_t46*_t60*_t61*_t62
    _t72 = _t37*_t42
    _t73 = _t31*_t42
    _t74 = _t40 + _t49*_t65 + _t51
    _t75 = U_*_t38 - W_xi_*_t13*_t30*_t38*_t42*_t64 + _t33
    _t76 = _t38*_t64
    _t77 = _t50*_t64
    _t78 = _t38*_t50
    _t79 = -U_*_t58 + _t49 + _t50*_t65
    _t80 = _t49*_t58
    _out = _np.zeros((7, 7) + _batch)
    _out[0, 0] = -_t23
    _out[0, 1] = -_t29
    _out[0, 3] = _t32
    _out[1, 0] = _t1*_t33/_t3**2 + _t34*_t36
    _out[1, 1] = _t34*_t37
    _out[1, 2] = _t31*_t34
    _out[2, 0] = 2*U_*W_eta_*_t39 - V_zeta_*_t41 - W_eta_*_t44 - _t23*_t45
    _out[2, 1] = 2*U_*W_eta_*_t46 - U_*_t47*_t48 - _t29*_t45
    _out[2, 2] = -_t42*_t49
    _out[2, 3] = _t41 + _t51
    _out[2, 5] = -a_zeta_
    _out[2, 6] = a_eta_
    _out[3, 0] = _t12*_t55 + _t31*_t43*_t54 - _t52*_t53
    _out[3, 1] = U_*_t48*_t57 + _t28*_t55 - _t53*_t56
    _out[3, 2] = 2*W_xi_*_t13*_t30*_t42 - _t41
    _out[3, 4] = a_zeta_
    _out[3, 6] = -a_xi_
    _out[4, 0] = -_t23 - _t44*_t65 - _t65*_t69 - _t67*_t68
    _out[4, 1] = U_*_t57 - _t29 - _t50*_t70 - _t65*_t72 - _t68*_t71
    _out[4, 2] = -_t65*_t73
    _out[4, 3] = _t32
    _out[4, 5] = _t74
    _out[4, 6] = -_t75
    _out[5, 0] = W_xi_*_t12*_t13*_t14*_t17*_t20*e2_ - _t14*_t77 + _t40 - _t44*_t76 - _t67*_t78 - _t69*_t76
    _out[5, 1] = U_*_t47 + W_xi_*_t13*_t14*_t17*_t20*_t28*e2_ - _t47*_t77 - _t71*_t78 - _t72*_t76
    _out[5, 2] = -_t32 - _t73*_t76
    _out[5, 4] = -_t74
    _out[5, 6] = -_t79
    _out[6, 0] = _t23*_t65 - _t44 + _t52 + _t67*_t80 - _t69
    _out[6, 1] = _t29*_t65 + _t49*_t70 + _t56 + _t71*_t80 - _t72
    _out[6, 2] = -_t73
    _out[6, 3] = _t31*_t65
    _out[6, 4] = _t75
    _out[6, 5] = _t79
    return _out


def source_matrix(x, u, p):
    """Error-source matrix G of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        G
    """
    x = _as_vector(x, 4, 'x', 'source_matrix')
    u = _as_vector(u, 4, 'u', 'source_matrix')
    p = _as_vector(p, 6, 'p', 'source_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    _out = _np.zeros((7, 12) + _batch)
    _out[2, 10] = 1
    _out[3, 11] = 1
    _out[4, 7] = 1
    _out[5, 8] = 1
    _out[6, 9] = 1
    return _out


def output_matrix(x, u, p):
    """Output matrix H: output errors = H xe to first order.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, 7, ...)
        H
    """
    x = _as_vector(x, 4, 'x', 'output_matrix')
    u = _as_vector(u, 4, 'u', 'output_matrix')
    p = _as_vector(p, 6, 'p', 'output_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    orth_latitude_ = p[3]
    orth_longitude_ = p[4]
    orth_angle_ = p[5]
    _t0 = _m.cos(Phi_)
    _t1 = _m.cos(orth_angle_)
    _t2 = _m.cos(orth_latitude_)
    _t3 = _t1*_t2
    _t4 = _m.sin(Phi_)
    _t5 = _m.cos(Lam_)
    _t6 = _m.sin(orth_latitude_)
    _t7 = _t5*_t6
    _t8 = _m.sin(orth_angle_)
    _t9 = _t2*_t8
    _t10 = _m.sin(Lam_)
    _t11 = _t10*_t4
    _t12 = _t0*_t3 + _t11*_t9 - _t4*_t7
    _t13 = _t10*_t6
    _t14 = _t5*_t9
    _t15 = _t13 + _t14
    _t16 = _t12**2 + _t15**2
    _t17 = _m.sqrt(_t16)
    _t18 = _t0*_t7
    _t19 = _t3*_t4
    _t20 = _t0*_t10
    _t21 = _t18 + _t19 - _t20*_t9
    _t22 = 1/(_t16 + _t21**2)
    _t23 = _t17*_t22
    _t24 = 1/_t17
    _t25 = -_t21
    _t26 = _t24*_t25
    _t27 = _t22*_t26
    _t28 = ((1/2))*_t12
    _t29 = _t28*(2*_t0*_t10*_t2*_t8 - 2*_t18 - 2*_t19)
    _t30 = _t10*_t9
    _t31 = _t13*_t4
    _t32 = _t14*_t4
    _t33 = ((1/2))*_t15*(-2*_t30 + 2*_t5*_t6) + _t28*(2*_t31 + 2*_t32)
    _t34 = _m.sin(orth_longitude_)
    _t35 = _t34*_t8
    _t36 = _m.cos(orth_longitude_)
    _t37 = _t1*_t36
    _t38 = _t35 + _t37*_t6
    _t39 = _t36*_t8
    _t40 = -_t1*_t34 + _t39*_t6
    _t41 = _t2*_t36
    _t42 = _t4*_t5
    _t43 = _t0*_t5
    _t44 = _t2*_t43
    _t45 = _t20*_t40 + _t36*_t44 - _t38*_t4
    _t46 = _t1*_t34*_t6 - _t39
    _t47 = _t35*_t6 + _t37
    _t48 = _t20*_t47 + _t34*_t44 - _t4*_t46
    _t49 = 1/(_t45**2 + _t48**2)
    _t50 = -_t48*_t49
    _t51 = _t2*_t34
    _t52 = _t45*_t49
    _t53 = -_t15
    _t54 = 1/_t16
    _t55 = _t53*_t54
    _t56 = -_t30 + _t5*_t6
    _t57 = _t31 + _t32
    _t58 = -W_eta_*_t12 - W_xi_*_t15
    _t59 = (1/(_t16*_m.sqrt(_t16)))
    _t60 = _t29*_t59
    _t61 = -_t33*_t59
    _t62 = -_t12*_t24
    _t63 = W_eta_*_t15 - W_xi_*_t12
    _out = _np.zeros((5, 7) + _batch)
    _out[0, 0] = _t12*_t23 + _t27*_t29
    _out[0, 1] = _t23*(-_t0*_t13 - _t0*_t14) + _t27*_t33
    _out[1, 0] = _t50*(-_t0*_t38 - _t11*_t40 - _t41*_t42) + _t52*(-_t0*_t46 - _t11*_t47 - _t42*_t51)
    _out[1, 1] = _t50*(-_t20*_t41 + _t40*_t43) + _t52*(-_t20*_t51 + _t43*_t47)
    _out[2, 0] = _t25*_t55
    _out[2, 1] = _t12*_t54*_t56 + _t55*_t57
    _out[3, 0] = -W_eta_*_t26 - _t58*_t60
    _out[3, 1] = _t24*(-W_eta_*_t57 - W_xi_*_t56) + _t58*_t61
    _out[3, 2] = _t24*_t53
    _out[3, 3] = _t62
    _out[4, 0] = -W_xi_*_t26 - _t60*_t63
    _out[4, 1] = _t24*(W_eta_*_t56 - W_xi_*_t57) + _t61*_t63
    _out[4, 2] = _t62
    _out[4, 3] = _t15*_t24
    return _out


def second_order(x, u, p, xe, w):
    """Second-order term of the error equations (refined model).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
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
    u = _as_vector(u, 4, 'u', 'second_order')
    p = _as_vector(p, 6, 'p', 'second_order')
    xe = _as_vector(xe, 7, 'xe', 'second_order')
    w = _as_vector(w, 12, 'w', 'second_order')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    W_xi_ = x[2]
    W_eta_ = x[3]
    a_xi_ = u[0]
    a_eta_ = u[1]
    V_zeta_ = u[3]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    delta_Phi_ = xe[0]
    delta_Lam_ = xe[1]
    delta_W_xi_ = xe[2]
    delta_W_eta_ = xe[3]
    alpha_x_ = xe[4]
    alpha_y_ = xe[5]
    alpha_z_ = xe[6]
    gyro_drift_y_ = w[8]
    gyro_drift_z_ = w[9]
    _t0 = 2 - e2_
    _t1 = 1/_t0
    _t2 = _t1*e2_
    _t3 = 1/a_
    _t4 = _m.cos(Phi_)
    _t5 = _m.cos(Lam_)
    _t6 = _m.sin(orth_latitude_)
    _t7 = _t4*_t5*_t6
    _t8 = _m.sin(Phi_)
    _t9 = _m.cos(orth_latitude_)
    _t10 = _t9*_m.cos(orth_angle_)
    _t11 = _t10*_t8
    _t12 = _m.sin(Lam_)
    _t13 = _t9*_m.sin(orth_angle_)
    _t14 = _t12*_t13
    _t15 = _t14*_t4
    _t16 = _t11 - _t15 + _t7
    _t17 = -_t16
    _t18 = _t17**2
    _t19 = -_t18*_t2 + 1
    _t20 = _t19**(-2)
    _t21 = _t20*_t3
    _t22 = _t2*_t21
    _t23 = W_eta_*_t22
    _t24 = _t12*_t6
    _t25 = _t24*_t4
    _t26 = _t13*_t5
    _t27 = _t26*_t4
    _t28 = _t25 + _t27
    _t29 = 2*_t25 + 2*_t27
    _t30 = _t28*_t29
    _t31 = _t23*_t30
    _t32 = 2*_t15
    _t33 = -_t32 + 2*_t4*_t5*_t6
    _t34 = _t17*_t23
    _t35 = _t33*_t34
    _t36 = _t29**2
    _t37 = 2*_t18
    _t38 = e2_**2
    _t39 = _t0**(-2)
    _t40 = _t38*_t39
    _t41 = _t19**(-3)
    _t42 = _t3*_t41
    _t43 = _t37*_t40*_t42
    _t44 = W_eta_*_t43
    _t45 = _t36*_t44
    _t46 = _t31 + _t35 + _t45
    _t47 = ((1/2))*delta_Lam_**2
    _t48 = _t10*_t4
    _t49 = _t14*_t8
    _t50 = _t49 - _t5*_t6*_t8
    _t51 = _t48 + _t50
    _t52 = -_t51
    _t53 = -2*_t48 - 2*_t49 + 2*_t5*_t6*_t8
    _t54 = _t52*_t53
    _t55 = _t23*_t54
    _t56 = 2*_t11 - _t32 + 2*_t7
    _t57 = _t34*_t56
    _t58 = _t53**2
    _t59 = _t44*_t58
    _t60 = _t55 + _t57 + _t59
    _t61 = ((1/2))*delta_Phi_**2
    _t62 = 2*W_eta_
    _t63 = _t22*_t62
    _t64 = _t28*_t53
    _t65 = _t63*_t64
    _t66 = _t24*_t8
    _t67 = _t26*_t8
    _t68 = -2*_t66 - 2*_t67
    _t69 = _t17*_t68
    _t70 = _t63*_t69
    _t71 = _t18*_t40
    _t72 = _t42*_t53
    _t73 = _t29*_t71*_t72
    _t74 = 4*W_eta_*_t73
    _t75 = _t65 + _t70 + _t74
    _t76 = ((1/2))*delta_Phi_
    _t77 = _t76*delta_Lam_
    _t78 = _t29*delta_Lam_
    _t79 = _t17*_t22
    _t80 = _t79*delta_W_eta_
    _t81 = -_t53*_t80*delta_Phi_ - _t78*_t80
    _t82 = 1/_t4
    _t83 = W_xi_*_t22
    _t84 = _t17*_t83
    _t85 = W_xi_*_t43
    _t86 = 1/_t19
    _t87 = _t3*_t86
    _t88 = W_xi_*_t87
    _t89 = 2*_t88
    _t90 = _t8/_t4**2
    _t91 = 2*W_xi_
    _t92 = _t79*_t91
    _t93 = _t53*_t92
    _t94 = _t22*_t91
    _t95 = _t64*_t94
    _t96 = _t69*_t94
    _t97 = _t29*_t92
    _t98 = 4*W_xi_
    _t99 = _t73*_t98
    _t100 = 2*_t87
    _t101 = 2*_t2
    _t102 = _t101*_t17
    _t103 = _t102*_t21
    _t104 = _t103*_t53
    _t105 = _t76*delta_W_xi_
    _t106 = _t78*delta_W_xi_
    _t107 = _t106*_t79
    _t108 = -_t15 + _t7
    _t109 = -_t50
    _t110 = 2*V_zeta_
    _t111 = _m.tan(Phi_)
    _t112 = W_xi_*_t111
    _t113 = U_*_t52
    _t114 = 2*_t113
    _t115 = _t111**2
    _t116 = 2*_t115 + 2
    _t117 = W_eta_*_t87
    _t118 = _t115 + 1
    _t119 = _t118*_t62*_t84
    _t120 = alpha_y_**2
    _t121 = ((1/2))*a_xi_
    _t122 = alpha_z_**2
    _t123 = _t66 + _t67
    _t124 = -_t123
    _t125 = U_*_t28
    _t126 = 4*_t125
    _t127 = _t111*_t97
    _t128 = -_t127
    _t129 = ((1/2))*delta_Lam_
    _t130 = _t129*delta_W_eta_
    _t131 = -4*_t113
    _t132 = _t118*_t89
    _t133 = _t111*_t93
    _t134 = _t76*delta_W_eta_
    _t135 = 2*_t117
    _t136 = _t111*_t53
    _t137 = _t17*_t63
    _t138 = _t111*_t87
    _t139 = _t138*delta_W_xi_
    _t140 = U_*_t108
    _t141 = _t24 + _t26
    _t142 = -_t141
    _t143 = W_xi_**2
    _t144 = _t111*_t143
    _t145 = _t22*_t30
    _t146 = _t144*_t79
    _t147 = _t144*_t43
    _t148 = U_*_t16
    _t149 = _t22*_t54
    _t150 = _t118*_t143
    _t151 = alpha_x_**2
    _t152 = ((1/2))*a_eta_
    _t153 = alpha_x_*alpha_y_
    _t154 = _t103*_t29
    _t155 = _t101*_t28
    _t156 = 4*_t71
    _t157 = _t156*_t29
    _t158 = _t129*delta_W_xi_
    _t159 = _t17*_t40
    _t160 = 1 - _t37
    _t161 = -_t102 + 2*_t159*_t160
    _t162 = _t111*_t88
    _t163 = _t141*_t162
    _t164 = -U_*_t141 + _t117 + _t161*_t163
    _t165 = ((1/2))*_t120
    _t166 = ((1/2))*_t122
    _t167 = 4*_t159
    _t168 = _t167*_t29
    _t169 = -_t101*_t108 + 2*_t108*_t160*_t38*_t39 - _t156*_t33 - _t167*_t36 - _t168*_t28
    _t170 = _t142*_t161
    _t171 = -_t155 - _t157 + 2*_t160*_t28*_t38*_t39
    _t172 = -_t14 + _t5*_t6
    _t173 = _t111*_t89
    _t174 = _t172*_t173
    _t175 = _t141*_t161
    _t176 = _t112*_t145
    _t177 = _t112*_t79
    _t178 = _t177*_t33
    _t179 = _t161*_t172
    _t180 = _t141*_t171
    _t181 = _t112*_t43
    _t182 = _t181*_t36
    _t183 = -_t101*_t16 - _t156*_t56 + 2*_t16*_t160*_t38*_t39 - _t167*_t54 - _t167*_t58
    _t184 = -_t101*_t52 - _t156*_t53 + 2*_t160*_t38*_t39*_t52
    _t185 = _t132*_t141
    _t186 = _t116*_t162
    _t187 = _t112*_t149
    _t188 = _t177*_t56
    _t189 = _t118*_t93
    _t190 = _t141*_t184
    _t191 = _t181*_t58
    _t192 = U_*_t51
    _t193 = _t161*_t51
    _t194 = -_t173*_t193 + 2*_t192 + _t89
    _t195 = 2*_t125
    _t196 = _t135*_t141
    _t197 = _t137*_t175
    _t198 = _t128 + _t135*_t179 + _t171*_t196 + _t195 + _t197*_t29
    _t199 = _t114 - _t132 - _t133 + _t184*_t196 + _t197*_t53
    _t200 = -_t101*_t124 + 2*_t124*_t160*_t38*_t39 - _t156*_t68 - _t168*_t52 - _t168*_t53
    _t201 = _t173*_t200
    _t202 = _t118*_t97
    _t203 = _t111*_t95
    _t204 = _t111*_t96
    _t205 = _t111*_t99
    _t206 = _t100*_t179
    _t207 = _t100*_t141
    _t208 = _t171*_t207
    _t209 = _t154*_t175
    _t210 = _t100*_t118
    _t211 = _t184*_t207
    _t212 = _t104*_t111
    _t213 = _t175*_t87*delta_W_eta_
    _t214 = -W_xi_*_t111*_t161*_t3*_t51*_t86 + _t192 + _t88
    _t215 = ((1/2))*_t151
    _t216 = _t161*_t162
    _t217 = _t162*_t51
    _t218 = _t123*_t173
    _t219 = _t123*_t161
    _t220 = _t127*_t51
    _t221 = _t161*_t17
    _t222 = _t132*_t51
    _t223 = _t17*_t173
    _t224 = _t112*_t161*_t22*_t37
    _t225 = _t133*_t51
    _t226 = _t129*alpha_x_
    _t227 = _t76*alpha_x_
    _t228 = _t111*_t193
    _t229 = _t100*_t111
    _t230 = _t229*_t51
    _t231 = alpha_x_*delta_W_xi_
    _t232 = _t117*_t141
    _t233 = U_*_t17 - W_xi_*_t111*_t3*_t86 + _t161*_t232
    _t234 = _t135*_t172
    _t235 = _t137*_t29
    _t236 = _t141*_t235
    _t237 = _t137*_t53
    _t238 = _t173*_t51
    _out = _np.zeros((7,) + _batch)
    _out[0] = -_t46*_t47 - _t60*_t61 - _t75*_t77 + _t81
    _out[1] = _t105*(_t100*_t90 + _t104*_t82) + _t107*_t82 + _t47*(_t30*_t82*_t83 + _t33*_t82*_t84 + _t36*_t82*_t85) + _t61*(_t54*_t82*_t83 + _t56*_t82*_t84 + _t58*_t82*_t85 + _t82*_t88 + _t90*_t93 + _t8**2*_t89/_t4**3) + _t77*(_t82*_t95 + _t82*_t96 + _t82*_t99 + _t90*_t97)
    _out[2] = _t105*(-_t118*_t135 - _t136*_t137) - _t106*_t111*_t34 - _t120*_t121 - _t121*_t122 + _t130*(_t126 + _t128) + _t134*(-_t131 - _t132 - _t133) - _t139*delta_W_eta_ + _t47*(2*U_*W_eta_*_t108 - U_*_t109*_t110 - _t112*_t31 - _t112*_t35 - _t112*_t45) + _t61*(2*U_*W_eta_*_t16 - V_zeta_*_t114 - _t112*_t116*_t117 - _t112*_t55 - _t112*_t57 - _t112*_t59 - _t119*_t53) + _t77*(4*U_*W_eta_*_t124 - V_zeta_*_t126 - _t112*_t65 - _t112*_t70 - _t112*_t74 - _t119*_t29)
    _out[3] = _t105*(4*_t118*_t88 + _t131 + _t136*_t79*_t98) - _t122*_t152 + _t138*delta_W_xi_**2 - _t151*_t152 + _t153*a_xi_ + _t158*(4*W_xi_*_t1*_t111*_t17*_t20*_t29*_t3*e2_ - _t126) + _t47*(U_*_t110*_t142 - _t140*_t91 + _t144*_t145 + _t146*_t33 + _t147*_t36) + _t61*(_t104*_t150 + _t116*_t138*_t143 + _t144*_t149 + _t146*_t56 + _t147*_t58 - _t148*_t91) + _t77*(-U_*_t124*_t98 + _t103*_t144*_t68 + _t144*_t155*_t21*_t53 + _t144*_t157*_t72 + _t150*_t154)
    _out[4] = _t105*(-_t111*_t211 - _t175*_t210 - _t175*_t212) + _t129*_t198*alpha_y_ - _t139*alpha_y_ + ((1/2))*_t153*_t194 + _t158*(-_t111*_t206 - _t111*_t208 - _t111*_t209) + _t164*_t165 - _t164*_t166 + _t199*_t76*alpha_y_ + _t213*alpha_y_ + _t47*(U_*_t142 - _t127*_t179 - _t127*_t180 - _t162*_t170 - _t163*_t169 - _t171*_t174 - _t175*_t176 - _t175*_t178 - _t175*_t182 - _t46) + _t61*(-_t133*_t190 - _t163*_t183 - _t175*_t186 - _t175*_t187 - _t175*_t188 - _t175*_t189 - _t175*_t191 - _t184*_t185 - _t60) + _t77*(-_t127*_t190 - _t132*_t179 - _t133*_t179 - _t133*_t180 - _t141*_t201 - _t171*_t185 - _t174*_t184 - _t175*_t202 - _t175*_t203 - _t175*_t204 - _t175*_t205 - _t75) + _t81 + alpha_y_*gyro_drift_z_
    _out[5] = _t105*(2*_t1*_t17*_t20*_t3*_t53*e2_ - _t184*_t230 - _t193*_t210 - _t193*_t212 - _t221*_t229) + _t138*_t231 + _t158*(2*_t1*_t17*_t20*_t29*_t3*e2_ - _t154*_t228 - _t171*_t230 - _t219*_t229) + _t166*_t214 - _t198*_t226 - _t199*_t227 - _t213*alpha_x_ - _t214*_t215 + _t47*(U_*_t109 + W_xi_*_t1*_t17*_t20*_t3*_t33*e2_ + W_xi_*_t1*_t20*_t28*_t29*_t3*e2_ + 2*W_xi_*_t18*_t3*_t36*_t38*_t39*_t41 - _t109*_t216 - _t127*_t219 - _t169*_t217 - _t171*_t218 - _t171*_t220 - _t176*_t193 - _t178*_t193 - _t182*_t193) + _t61*(U_*_t52 + W_xi_*_t1*_t17*_t20*_t3*_t56*e2_ + W_xi_*_t1*_t20*_t3*_t52*_t53*e2_ + 2*W_xi_*_t18*_t3*_t38*_t39*_t41*_t58 - _t132*_t221 - _t183*_t217 - _t184*_t222 - _t184*_t223 - _t184*_t225 - _t186*_t193 - _t187*_t193 - _t188*_t193 - _t189*_t193 - _t191*_t193 - _t216*_t52 - _t224*_t53) + _t77*(2*W_xi_*_t1*_t17*_t20*_t3*_t68*e2_ + 2*W_xi_*_t1*_t20*_t28*_t3*_t53*e2_ + 4*W_xi_*_t18*_t29*_t3*_t38*_t39*_t41*_t53 - _t132*_t219 - _t133*_t219 - _t161*_t173*_t28 - _t171*_t222 - _t171*_t223 - _t171*_t225 - _t184*_t218 - _t184*_t220 - _t193*_t202 - _t193*_t203 - _t193*_t204 + _t195 - _t201*_t51 - _t224*_t29 - _t228*_t99) - alpha_x_*gyro_drift_z_
    _out[6] = _t105*(-_t210 - _t212) - _t107*_t111 + _t130*(_t206 + _t208 + _t209) + _t134*(_t104*_t175 + _t211) + _t165*_t233 - (1/2)*_t194*alpha_y_*alpha_z_ - _t215*_t233 + _t226*(2*U_*_t123 + 2*W_xi_*_t1*_t17*_t20*_t29*_t3*e2_ - _t127*_t193 - _t171*_t238 - _t173*_t219) + _t227*(2*U_*_t17 + 2*W_xi_*_t1*_t17*_t20*_t3*_t53*e2_ - _t132*_t193 - _t133*_t193 - _t173*_t221 - _t184*_t238) + ((1/2))*_t231*(-_t161*_t230 + 2*_t3*_t86) + _t47*(_t117*_t170 + _t140 + _t169*_t232 + _t171*_t234 + _t171*_t236 + _t175*_t31 + _t175*_t35 + _t175*_t45 - _t176 - _t178 + _t179*_t235 - _t182) + _t61*(_t148 + _t175*_t55 + _t175*_t57 + _t175*_t59 + _t183*_t232 - _t186 - _t187 - _t188 - _t189 + _t190*_t237 - _t191) + _t77*(2*U_*_t124 + _t175*_t65 + _t175*_t70 + _t175*_t74 + _t179*_t237 + _t180*_t237 + _t184*_t234 + _t184*_t236 + _t196*_t200 - _t202 - _t203 - _t204 - _t205) + alpha_x_*gyro_drift_y_
    return _out


def initial_state(c, u, p):
    """True initial state from navigation initial conditions.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        x(0)
    """
    c = _as_vector(c, 4, 'c', 'initial_state')
    u = _as_vector(u, 4, 'u', 'initial_state')
    p = _as_vector(p, 6, 'p', 'initial_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    v_N_ = c[2]
    v_E_ = c[3]
    orth_latitude_ = p[3]
    orth_longitude_ = p[4]
    orth_angle_ = p[5]
    _t0 = _m.sin(orth_angle_)
    _t1 = _m.sin(orth_longitude_)
    _t2 = _t0*_t1
    _t3 = _m.sin(orth_latitude_)
    _t4 = _m.cos(orth_angle_)
    _t5 = _m.cos(orth_longitude_)
    _t6 = _t4*_t5
    _t7 = _m.cos(latitude_)
    _t8 = _t7*_m.cos(longitude_)
    _t9 = _t0*_t5
    _t10 = _t7*_m.sin(longitude_)
    _t11 = _m.cos(orth_latitude_)
    _t12 = _m.sin(latitude_)
    _t13 = -_t10*(_t1*_t3*_t4 - _t9) + _t11*_t12*_t4 - _t8*(_t2 + _t3*_t6)
    _t14 = _t1*_t10*_t11 + _t11*_t5*_t8 + _t12*_t3
    _t15 = -_t0*_t11*_t12 + _t10*(_t2*_t3 + _t6) + _t8*(-_t1*_t4 + _t3*_t9)
    _t16 = _t14**2 + _t15**2
    _t17 = _m.sqrt(_t16)
    _t18 = 1/_m.sqrt(_t13**2 + _t16)
    _t19 = _t11*_t18
    _t20 = 1/_t17
    _t21 = _t20*_t3
    _t22 = _t0*_t20
    _t23 = -_t13*_t14*_t18*_t21 + _t13*_t15*_t19*_t22 + _t17*_t19*_t4
    _t24 = 1/_t7
    _t25 = _t24*v_E_
    _t26 = _t11*_t14*_t22 + _t15*_t21
    _t27 = _t24*v_N_
    _out = _np.zeros((4,) + _batch)
    _out[0] = _m.arctan2(_t13, _t17)
    _out[1] = _m.arctan2(_t15, _t14)
    _out[2] = -_t23*_t25 - _t26*_t27
    _out[3] = -_t23*_t27 + _t25*_t26
    return _out


def initial_real_state(c, u, w, p):
    """Real-work initial state, initial-error sources applied.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    w : array_like, shape (12, ...)
        error-source magnitudes, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, ...)
        xr(0)
    """
    c = _as_vector(c, 4, 'c', 'initial_real_state')
    u = _as_vector(u, 4, 'u', 'initial_real_state')
    w = _as_vector(w, 12, 'w', 'initial_real_state')
    p = _as_vector(p, 6, 'p', 'initial_real_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    v_N_ = c[2]
    v_E_ = c[3]
    initial_tilt_x_ = w[0]
    initial_tilt_y_ = w[1]
    initial_azimuth_error_ = w[2]
    initial_velocity_error_xi_ = w[3]
    initial_velocity_error_eta_ = w[4]
    initial_Phi_error_ = w[5]
    initial_Lam_error_ = w[6]
    orth_latitude_ = p[3]
    orth_longitude_ = p[4]
    orth_angle_ = p[5]
    _t0 = _m.sin(orth_angle_)
    _t1 = _m.sin(orth_longitude_)
    _t2 = _t0*_t1
    _t3 = _m.sin(orth_latitude_)
    _t4 = _m.cos(orth_angle_)
    _t5 = _m.cos(orth_longitude_)
    _t6 = _t4*_t5
    _t7 = _m.cos(latitude_)
    _t8 = _t7*_m.cos(longitude_)
    _t9 = _t0*_t5
    _t10 = _t7*_m.sin(longitude_)
    _t11 = _m.cos(orth_latitude_)
    _t12 = _m.sin(latitude_)
    _t13 = -_t10*(_t1*_t3*_t4 - _t9) + _t11*_t12*_t4 - _t8*(_t2 + _t3*_t6)
    _t14 = _t1*_t10*_t11 + _t11*_t5*_t8 + _t12*_t3
    _t15 = -_t0*_t11*_t12 + _t10*(_t2*_t3 + _t6) + _t8*(-_t1*_t4 + _t3*_t9)
    _t16 = _t14**2 + _t15**2
    _t17 = _m.sqrt(_t16)
    _t18 = 1/_m.sqrt(_t13**2 + _t16)
    _t19 = _t11*_t18
    _t20 = 1/_t17
    _t21 = _t20*_t3
    _t22 = _t0*_t20
    _t23 = -_t13*_t14*_t18*_t21 + _t13*_t15*_t19*_t22 + _t17*_t19*_t4
    _t24 = 1/_t7
    _t25 = _t24*v_E_
    _t26 = _t11*_t14*_t22 + _t15*_t21
    _t27 = _t24*v_N_
    _out = _np.zeros((7,) + _batch)
    _out[0] = initial_Phi_error_ + _m.arctan2(_t13, _t17)
    _out[1] = initial_Lam_error_ + _m.arctan2(_t15, _t14)
    _out[2] = -_t23*_t25 - _t26*_t27 + initial_velocity_error_xi_
    _out[3] = -_t23*_t27 + _t25*_t26 + initial_velocity_error_eta_
    _out[4] = initial_tilt_x_
    _out[5] = initial_tilt_y_
    _out[6] = initial_azimuth_error_
    return _out


def initial_error_matrix(c, u, p):
    """First-order map from error sources to the initial error state.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        E: xe(0) = E w
    """
    c = _as_vector(c, 4, 'c', 'initial_error_matrix')
    u = _as_vector(u, 4, 'u', 'initial_error_matrix')
    p = _as_vector(p, 6, 'p', 'initial_error_matrix')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    _out = _np.zeros((7, 12) + _batch)
    _out[0, 5] = 1
    _out[1, 6] = 1
    _out[2, 3] = 1
    _out[3, 4] = 1
    _out[4, 0] = 1
    _out[5, 1] = 1
    _out[6, 2] = 1
    return _out


def domain_margins(x, u, p):
    """Margins that must be positive for the formulas to hold (see DOMAIN).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        one margin per condition of DOMAIN
    """
    x = _as_vector(x, 4, 'x', 'domain_margins')
    u = _as_vector(u, 4, 'u', 'domain_margins')
    p = _as_vector(p, 6, 'p', 'domain_margins')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    Phi_ = x[0]
    Lam_ = x[1]
    a_ = p[0]
    e2_ = p[1]
    orth_latitude_ = p[3]
    orth_angle_ = p[5]
    _t0 = _m.cos(Phi_)
    _t1 = _m.cos(orth_latitude_)
    _out = _np.zeros((4,) + _batch)
    _out[0] = _t0**2 - 1e-12
    _out[1] = 0.999999999999 - (_t0*_t1*_m.sin(Lam_)*_m.sin(orth_angle_) - _t0*_m.sin(orth_latitude_)*_m.cos(Lam_) - _t1*_m.sin(Phi_)*_m.cos(orth_angle_))**2
    _out[2] = a_
    _out[3] = 1 - e2_
    return _out


def initial_domain_margins(c, u, p):
    """Margins that must be positive for the initial conditions.

    Parameters
    ----------
    c : array_like, shape (4, ...)
        initial navigation conditions, SI units
    u : array_like, shape (4, ...)
        true-motion inputs, SI units
    p : array_like, shape (6, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (3, ...)
        one margin per condition of INITIAL_DOMAIN
    """
    c = _as_vector(c, 4, 'c', 'initial_domain_margins')
    u = _as_vector(u, 4, 'u', 'initial_domain_margins')
    p = _as_vector(p, 6, 'p', 'initial_domain_margins')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    a_ = p[0]
    e2_ = p[1]
    _out = _np.zeros((3,) + _batch)
    _out[0] = _m.cos(latitude_)**2 - 1e-12
    _out[1] = a_
    _out[2] = 1 - e2_
    return _out


FUNCTIONS = ('ideal_rhs', 'real_rhs', 'real_rhs_small_angle', 'second_order_small_angle', 'outputs', 'state_matrix', 'source_matrix', 'output_matrix', 'second_order', 'initial_state', 'initial_real_state', 'initial_error_matrix', 'domain_margins', 'initial_domain_margins')
