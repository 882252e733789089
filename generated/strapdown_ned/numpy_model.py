# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive) from ins_errors/models/strapdown_ned.py.
# Edit the model definition and run `make derive` again.

"""numpy functions of the model 'strapdown_ned' (broadcasting)."""

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
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, ...)
        time derivative of the true state
    """
    x = _as_vector(x, 10, 'x', 'ideal_rhs')
    u = _as_vector(u, 7, 'u', 'ideal_rhs')
    p = _as_vector(p, 8, 'p', 'ideal_rhs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    v_N_ = x[4]
    v_E_ = x[5]
    v_D_ = x[6]
    lat_ = x[7]
    h_ = x[9]
    omega_x_ = u[0]
    omega_y_ = u[1]
    omega_z_ = u[2]
    f_x_ = u[3]
    f_y_ = u[4]
    f_z_ = u[5]
    h_ref_ = u[6]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    gamma_e_ = p[3]
    gravity_k_ = p[4]
    gravity_m_ = p[5]
    k_h1_ = p[6]
    k_h2_ = p[7]
    _t0 = ((1/2))*q1_
    _t1 = ((1/2))*q2_
    _t2 = ((1/2))*q3_
    _t3 = _m.cos(lat_)
    _t4 = U_*_t3
    _t5 = _m.sin(lat_)
    _t6 = _t5**2
    _t7 = -_t6*e2_ + 1
    _t8 = 1/_m.sqrt(_t7)
    _t9 = v_E_/(_t8*a_ + h_)
    _t10 = _t4 + _t9
    _t11 = U_*_t5
    _t12 = _t9*_m.tan(lat_)
    _t13 = -_t11 - _t12
    _t14 = 1 - e2_
    _t15 = 1/(_t14*a_/(_t7*_m.sqrt(_t7)) + h_)
    _t16 = _t15*v_N_
    _t17 = ((1/2))*q0_
    _t18 = -2*_t11 - _t12
    _t19 = q2_**2
    _t20 = q3_**2
    _t21 = q0_**2
    _t22 = q1_**2
    _t23 = _t21 + _t22
    _t24 = 1/(_t19 + _t20 + _t23)
    _t25 = -_t19
    _t26 = -_t20
    _t27 = 2*q0_
    _t28 = _t27*q3_
    _t29 = _t27*q2_
    _t30 = 2*q1_
    _t31 = 2*_t4 + _t9
    _t32 = _t21 - _t22
    _t33 = _t27*q1_
    _t34 = h_ - h_ref_
    _t35 = _m.sqrt(_t14)
    _out = _np.zeros((10,) + _batch)
    _out[0] = -_t0*omega_x_ - _t1*_t16 - _t1*omega_y_ + ((1/2))*_t10*q1_ + ((1/2))*_t13*q3_ - _t2*omega_z_
    _out[1] = _t1*_t13 + _t1*omega_z_ - _t10*_t17 + _t16*_t2 + _t17*omega_x_ - _t2*omega_y_
    _out[2] = -_t0*_t13 - _t0*omega_z_ + _t10*_t2 + _t16*_t17 + _t17*omega_y_ + _t2*omega_x_
    _out[3] = -_t0*_t16 - _t1*_t10 - _t1*omega_x_ - _t13*_t17 + ((1/2))*omega_y_*q1_ + ((1/2))*omega_z_*q0_
    _out[4] = _t16*v_D_ + _t18*v_E_ + _t24*(f_x_*(_t23 + _t25 + _t26) + f_y_*(-_t28 + 2*q1_*q2_) + f_z_*(_t29 + _t30*q3_))
    _out[5] = -_t18*v_N_ + _t24*(f_x_*(_t28 + _t30*q2_) + f_y_*(_t19 + _t26 + _t32) + f_z_*(-_t33 + 2*q2_*q3_)) + _t31*v_D_
    _out[6] = -_t15*v_N_**2 + _t24*(f_x_*(-_t29 + 2*q1_*q3_) + f_y_*(_t33 + 2*q2_*q3_) + f_z_*(_t20 + _t25 + _t32)) - _t31*v_E_ + _t34*k_h2_ + _t8*gamma_e_*(_t6*gravity_k_ + 1)*(1 - 2*h_*(-_t35 - _t6*(2 - 2*_t35) + gravity_m_ + 2)/a_ + 3*h_**2/a_**2)
    _out[7] = _t16
    _out[8] = _t9/_t3
    _out[9] = -_t34*k_h1_ - v_D_
    return _out


def real_rhs(xr, x, u, w, p):
    """Real-work equations: dxr/dt (x is not used: the signature all models share).

    Parameters
    ----------
    xr : array_like, shape (10, ...)
        real-work state: the 10 computed states in the order of x, no further state
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    w : array_like, shape (33, ...)
        error-source magnitudes, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, ...)
        time derivative of the real-work state
    """
    xr = _as_vector(xr, 10, 'xr', 'real_rhs')
    x = _as_vector(x, 10, 'x', 'real_rhs')
    u = _as_vector(u, 7, 'u', 'real_rhs')
    w = _as_vector(w, 33, 'w', 'real_rhs')
    p = _as_vector(p, 8, 'p', 'real_rhs')
    _batch = _np.broadcast_shapes(xr.shape[1:], x.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    q0_c_ = xr[0]
    q1_c_ = xr[1]
    q2_c_ = xr[2]
    q3_c_ = xr[3]
    v_N_c_ = xr[4]
    v_E_c_ = xr[5]
    v_D_c_ = xr[6]
    lat_c_ = xr[7]
    h_c_ = xr[9]
    omega_x_ = u[0]
    omega_y_ = u[1]
    omega_z_ = u[2]
    f_x_ = u[3]
    f_y_ = u[4]
    f_z_ = u[5]
    h_ref_ = u[6]
    gyro_bias_x_ = w[0]
    gyro_bias_y_ = w[1]
    gyro_bias_z_ = w[2]
    gyro_scale_error_x_ = w[3]
    gyro_scale_error_y_ = w[4]
    gyro_scale_error_z_ = w[5]
    gyro_misalignment_xy_ = w[6]
    gyro_misalignment_xz_ = w[7]
    gyro_misalignment_yx_ = w[8]
    gyro_misalignment_yz_ = w[9]
    gyro_misalignment_zx_ = w[10]
    gyro_misalignment_zy_ = w[11]
    accel_bias_x_ = w[12]
    accel_bias_y_ = w[13]
    accel_bias_z_ = w[14]
    accel_scale_error_x_ = w[15]
    accel_scale_error_y_ = w[16]
    accel_scale_error_z_ = w[17]
    accel_misalignment_xy_ = w[18]
    accel_misalignment_xz_ = w[19]
    accel_misalignment_yx_ = w[20]
    accel_misalignment_yz_ = w[21]
    accel_misalignment_zx_ = w[22]
    accel_misalignment_zy_ = w[23]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    gamma_e_ = p[3]
    gravity_k_ = p[4]
    gravity_m_ = p[5]
    k_h1_ = p[6]
    k_h2_ = p[7]
    _t0 = gyro_bias_x_ + gyro_misalignment_xy_*omega_y_ + gyro_misalignment_xz_*omega_z_ + omega_x_*(gyro_scale_error_x_ + 1)
    _t1 = ((1/2))*q1_c_
    _t2 = gyro_bias_y_ + gyro_misalignment_yx_*omega_x_ + gyro_misalignment_yz_*omega_z_ + omega_y_*(gyro_scale_error_y_ + 1)
    _t3 = ((1/2))*q2_c_
    _t4 = gyro_bias_z_ + gyro_misalignment_zx_*omega_x_ + gyro_misalignment_zy_*omega_y_ + omega_z_*(gyro_scale_error_z_ + 1)
    _t5 = ((1/2))*q3_c_
    _t6 = _m.cos(lat_c_)
    _t7 = U_*_t6
    _t8 = _m.sin(lat_c_)
    _t9 = _t8**2
    _t10 = -_t9*e2_ + 1
    _t11 = 1/_m.sqrt(_t10)
    _t12 = v_E_c_/(_t11*a_ + h_c_)
    _t13 = _t12 + _t7
    _t14 = U_*_t8
    _t15 = _t12*_m.tan(lat_c_)
    _t16 = -_t14 - _t15
    _t17 = 1 - e2_
    _t18 = 1/(h_c_ + _t17*a_/(_t10*_m.sqrt(_t10)))
    _t19 = _t18*v_N_c_
    _t20 = ((1/2))*q0_c_
    _t21 = -2*_t14 - _t15
    _t22 = q2_c_**2
    _t23 = q3_c_**2
    _t24 = q0_c_**2
    _t25 = q1_c_**2
    _t26 = _t24 + _t25
    _t27 = 1/(_t22 + _t23 + _t26)
    _t28 = 2*q0_c_
    _t29 = _t28*q3_c_
    _t30 = accel_bias_y_ + accel_misalignment_yx_*f_x_ + accel_misalignment_yz_*f_z_ + f_y_*(accel_scale_error_y_ + 1)
    _t31 = _t28*q2_c_
    _t32 = 2*q1_c_
    _t33 = accel_bias_z_ + accel_misalignment_zx_*f_x_ + accel_misalignment_zy_*f_y_ + f_z_*(accel_scale_error_z_ + 1)
    _t34 = accel_bias_x_ + accel_misalignment_xy_*f_y_ + accel_misalignment_xz_*f_z_ + f_x_*(accel_scale_error_x_ + 1)
    _t35 = -_t22
    _t36 = -_t23
    _t37 = _t12 + 2*_t7
    _t38 = _t28*q1_c_
    _t39 = _t24 - _t25
    _t40 = h_c_ - h_ref_
    _t41 = _m.sqrt(_t17)
    _out = _np.zeros((10,) + _batch)
    _out[0] = -_t0*_t1 + ((1/2))*_t13*q1_c_ + ((1/2))*_t16*q3_c_ - _t19*_t3 - _t2*_t3 - _t4*_t5
    _out[1] = _t0*_t20 - _t13*_t20 + _t16*_t3 + _t19*_t5 - _t2*_t5 + _t3*_t4
    _out[2] = _t0*_t5 - _t1*_t16 - _t1*_t4 + _t13*_t5 + _t19*_t20 + _t2*_t20
    _out[3] = -_t0*_t3 - _t1*_t19 - _t13*_t3 - _t16*_t20 + ((1/2))*_t2*q1_c_ + ((1/2))*_t4*q0_c_
    _out[4] = _t19*v_D_c_ + _t21*v_E_c_ + _t27*(_t30*(-_t29 + 2*q1_c_*q2_c_) + _t33*(_t31 + _t32*q3_c_) + _t34*(_t26 + _t35 + _t36))
    _out[5] = -_t21*v_N_c_ + _t27*(_t30*(_t22 + _t36 + _t39) + _t33*(-_t38 + 2*q2_c_*q3_c_) + _t34*(_t29 + _t32*q2_c_)) + _t37*v_D_c_
    _out[6] = _t11*gamma_e_*(_t9*gravity_k_ + 1)*(1 - 2*h_c_*(-_t41 - _t9*(2 - 2*_t41) + gravity_m_ + 2)/a_ + 3*h_c_**2/a_**2) - _t18*v_N_c_**2 + _t27*(_t30*(_t38 + 2*q2_c_*q3_c_) + _t33*(_t23 + _t35 + _t39) + _t34*(-_t31 + 2*q1_c_*q3_c_)) - _t37*v_E_c_ + _t40*k_h2_
    _out[7] = _t19
    _out[8] = _t12/_t6
    _out[9] = -_t40*k_h1_ - v_D_c_
    return _out


def outputs(x, u, p):
    """Navigation outputs of a state (true or computed part of xr).

    Parameters
    ----------
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (9, ...)
        outputs in SI units
    """
    x = _as_vector(x, 10, 'x', 'outputs')
    u = _as_vector(u, 7, 'u', 'outputs')
    p = _as_vector(p, 8, 'p', 'outputs')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    v_N_ = x[4]
    v_E_ = x[5]
    v_D_ = x[6]
    lat_ = x[7]
    lon_ = x[8]
    h_ = x[9]
    _t0 = 2*q1_
    _t1 = 2*q2_
    _t2 = _t0*q0_ + _t1*q3_
    _t3 = q3_**2
    _t4 = q1_**2
    _t5 = q0_**2 - q2_**2
    _t6 = _t3 - _t4 + _t5
    _out = _np.zeros((9,) + _batch)
    _out[0] = lat_
    _out[1] = lon_
    _out[2] = h_
    _out[3] = v_N_
    _out[4] = v_E_
    _out[5] = v_D_
    _out[6] = _m.arctan2(_t2, _t6)
    _out[7] = _m.arctan2(-_t0*q3_ + _t1*q0_, _m.sqrt(_t2**2 + _t6**2))
    _out[8] = _m.arctan2(_t0*q2_ + 2*q0_*q3_, -_t3 + _t4 + _t5)
    return _out


def state_matrix(x, u, p):
    """State matrix F of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, 10, ...)
        F
    """
    x = _as_vector(x, 10, 'x', 'state_matrix')
    u = _as_vector(u, 7, 'u', 'state_matrix')
    p = _as_vector(p, 8, 'p', 'state_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    v_N_ = x[4]
    v_E_ = x[5]
    v_D_ = x[6]
    lat_ = x[7]
    h_ = x[9]
    omega_x_ = u[0]
    omega_y_ = u[1]
    omega_z_ = u[2]
    f_x_ = u[3]
    f_y_ = u[4]
    f_z_ = u[5]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    gamma_e_ = p[3]
    gravity_k_ = p[4]
    gravity_m_ = p[5]
    k_h1_ = p[6]
    k_h2_ = p[7]
    _t0 = ((1/2))*omega_x_
    _t1 = _m.cos(lat_)
    _t2 = U_*_t1
    _t3 = _m.sin(lat_)
    _t4 = _t3**2
    _t5 = -_t4*e2_ + 1
    _t6 = 1/_m.sqrt(_t5)
    _t7 = _t6*a_ + h_
    _t8 = 1/_t7
    _t9 = _t8*v_E_
    _t10 = ((1/2))*_t9
    _t11 = _t10 + ((1/2))*_t2
    _t12 = -_t0 + _t11
    _t13 = ((1/2))*omega_y_
    _t14 = 1 - e2_
    _t15 = (1/(_t5*_m.sqrt(_t5)))
    _t16 = _t15*a_
    _t17 = _t14*_t16 + h_
    _t18 = 1/_t17
    _t19 = _t18*v_N_
    _t20 = ((1/2))*_t19
    _t21 = _t13 + _t20
    _t22 = ((1/2))*omega_z_
    _t23 = U_*_t3
    _t24 = _m.tan(lat_)
    _t25 = _t10*_t24 + ((1/2))*_t23
    _t26 = _t22 + _t25
    _t27 = ((1/2))*_t18
    _t28 = ((1/2))*q1_
    _t29 = _t28*_t8
    _t30 = ((1/2))*q3_
    _t31 = _t30*_t8
    _t32 = _t7**(-2)
    _t33 = _t32*v_E_
    _t34 = _t3*e2_
    _t35 = _t16*_t33*_t34
    _t36 = _t1*_t35
    _t37 = -_t23 - _t36
    _t38 = -_t1*_t15*_t24*_t3*_t32*a_*e2_*v_E_ + _t9*(_t24**2 + 1)
    _t39 = -_t2 - _t38
    _t40 = ((1/2))*_t39
    _t41 = _t17**(-2)
    _t42 = _t41*v_N_
    _t43 = (1/(_t5**2*_m.sqrt(_t5)))
    _t44 = _t1*_t14*_t34*_t43*a_
    _t45 = ((3/2))*_t42*_t44
    _t46 = ((1/2))*q2_
    _t47 = _t28*_t33
    _t48 = _t30*_t33
    _t49 = -_t22 + _t25
    _t50 = _t13 - _t20
    _t51 = ((1/2))*q0_
    _t52 = _t51*_t8
    _t53 = _t46*_t8
    _t54 = _t33*_t51
    _t55 = _t33*_t46
    _t56 = _t0 + _t11
    _t57 = q2_**2
    _t58 = q3_**2
    _t59 = q0_**2
    _t60 = q1_**2
    _t61 = _t59 + _t60
    _t62 = _t57 + _t58 + _t61
    _t63 = 1/_t62
    _t64 = 2*q3_
    _t65 = 2*q0_
    _t66 = 2*q2_
    _t67 = -_t64*f_y_ + _t65*f_x_ + _t66*f_z_
    _t68 = -_t63*_t67
    _t69 = _t62**(-2)
    _t70 = -_t57
    _t71 = -_t58
    _t72 = _t64*q0_
    _t73 = _t65*q2_
    _t74 = _t69*(f_x_*(_t61 + _t70 + _t71) + f_y_*(-_t72 + 2*q1_*q2_) + f_z_*(_t64*q1_ + _t73))
    _t75 = 2*q1_
    _t76 = -_t63*(_t64*f_z_ + _t66*f_y_ + _t75*f_x_)
    _t77 = _t65*f_z_ - _t66*f_x_ + _t75*f_y_
    _t78 = -_t63*_t77
    _t79 = _t64*f_x_ + _t65*f_y_ - 2*f_z_*q1_
    _t80 = 2*_t23
    _t81 = _t24*_t9
    _t82 = 2*_t2
    _t83 = -_t38 - _t82
    _t84 = _t42*v_D_
    _t85 = 3*_t44
    _t86 = v_E_**2
    _t87 = -_t63*_t79
    _t88 = _t59 - _t60
    _t89 = _t65*q1_
    _t90 = _t69*(f_x_*(_t66*q1_ + _t72) + f_y_*(_t57 + _t71 + _t88) + f_z_*(-_t89 + 2*q2_*q3_))
    _t91 = _t24*v_N_
    _t92 = -_t36 - _t80
    _t93 = _t69*(f_x_*(-_t73 + 2*q1_*q3_) + f_y_*(_t64*q2_ + _t89) + f_z_*(_t58 + _t70 + _t88))
    _t94 = _t6*gamma_e_
    _t95 = a_**(-2)
    _t96 = 1/a_
    _t97 = _m.sqrt(_t14)
    _t98 = 2 - 2*_t97
    _t99 = 2*_t96*(-_t4*_t98 - _t97 + gravity_m_ + 2)
    _t100 = _t1*(3*_t95*h_**2 - _t99*h_ + 1)
    _t101 = _t4*gravity_k_ + 1
    _t102 = _t41*v_N_**2
    _t103 = _t101*_t94
    _t104 = 1/_t1
    _out = _np.zeros((10, 10) + _batch)
    _out[0, 1] = _t12
    _out[0, 2] = -_t21
    _out[0, 3] = -_t26
    _out[0, 4] = -_t27*q2_
    _out[0, 5] = -_t24*_t31 + _t29
    _out[0, 7] = _t28*_t37 + _t40*q3_ + _t45*q2_
    _out[0, 9] = _t24*_t48 + _t42*_t46 - _t47
    _out[1, 0] = -_t12
    _out[1, 2] = -_t49
    _out[1, 3] = -_t50
    _out[1, 4] = _t27*q3_
    _out[1, 5] = -_t24*_t53 - _t52
    _out[1, 7] = -_t37*_t51 + ((1/2))*_t39*q2_ - _t45*q3_
    _out[1, 9] = _t24*_t55 - _t30*_t42 + _t54
    _out[2, 0] = _t21
    _out[2, 1] = _t49
    _out[2, 3] = _t56
    _out[2, 4] = _t27*q0_
    _out[2, 5] = _t24*_t29 + _t31
    _out[2, 7] = -_t28*_t39 + ((1/2))*_t37*q3_ - _t45*q0_
    _out[2, 9] = -_t24*_t47 - _t42*_t51 - _t48
    _out[3, 0] = _t26
    _out[3, 1] = _t50
    _out[3, 2] = -_t56
    _out[3, 4] = -_t27*q1_
    _out[3, 5] = _t24*_t52 - _t53
    _out[3, 7] = ((3/2))*_t1*_t14*_t3*_t41*_t43*a_*e2_*q1_*v_N_ - _t37*_t46 - _t40*q0_
    _out[3, 9] = -_t24*_t54 + _t28*_t42 + _t55
    _out[4, 0] = -_t65*_t74 - _t68
    _out[4, 1] = -_t74*_t75 - _t76
    _out[4, 2] = -_t66*_t74 - _t78
    _out[4, 3] = -_t63*_t79 - _t64*_t74
    _out[4, 4] = _t18*v_D_
    _out[4, 5] = -_t80 - 2*_t81
    _out[4, 6] = _t19
    _out[4, 7] = _t83*v_E_ - _t84*_t85
    _out[4, 9] = _t24*_t32*_t86 - _t84
    _out[5, 0] = -_t65*_t90 - _t87
    _out[5, 1] = -_t63*_t77 - _t75*_t90
    _out[5, 2] = -_t66*_t90 - _t76
    _out[5, 3] = -_t64*_t90 - _t68
    _out[5, 4] = _t80 + _t81
    _out[5, 5] = _t8*_t91 + _t8*v_D_
    _out[5, 6] = _t82 + _t9
    _out[5, 7] = -_t83*v_N_ + _t92*v_D_
    _out[5, 9] = -_t33*_t91 - _t33*v_D_
    _out[6, 0] = -_t65*_t93 - _t78
    _out[6, 1] = -_t75*_t93 - _t87
    _out[6, 2] = -_t63*_t67 - _t66*_t93
    _out[6, 3] = -_t64*_t93 - _t76
    _out[6, 4] = -2*_t19
    _out[6, 5] = -_t82 - 2*_t9
    _out[6, 7] = 4*_t1*_t103*_t3*_t96*_t98*h_ + _t100*_t101*_t15*_t34*gamma_e_ + 2*_t100*_t3*_t94*gravity_k_ + _t102*_t85 - _t92*v_E_
    _out[6, 9] = _t102 + _t103*(6*_t95*h_ - _t99) + _t32*_t86 + k_h2_
    _out[7, 4] = _t18
    _out[7, 7] = -_t42*_t85
    _out[7, 9] = -_t42
    _out[8, 5] = _t104*_t8
    _out[8, 7] = -_t35 + _t3*_t8*v_E_/_t1**2
    _out[8, 9] = -_t104*_t33
    _out[9, 6] = -1
    _out[9, 9] = -k_h1_
    return _out


def source_matrix(x, u, p):
    """Error-source matrix G of the linear error equations.

    Parameters
    ----------
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, 33, ...)
        G
    """
    x = _as_vector(x, 10, 'x', 'source_matrix')
    u = _as_vector(u, 7, 'u', 'source_matrix')
    p = _as_vector(p, 8, 'p', 'source_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    omega_x_ = u[0]
    omega_y_ = u[1]
    omega_z_ = u[2]
    f_x_ = u[3]
    f_y_ = u[4]
    f_z_ = u[5]
    _t0 = ((1/2))*q1_
    _t1 = -_t0
    _t2 = ((1/2))*q2_
    _t3 = -_t2
    _t4 = ((1/2))*q3_
    _t5 = -_t4
    _t6 = _t0*omega_x_
    _t7 = -_t6
    _t8 = _t2*omega_y_
    _t9 = -_t8
    _t10 = _t4*omega_z_
    _t11 = -_t10
    _t12 = _t0*omega_y_
    _t13 = -_t12
    _t14 = _t0*omega_z_
    _t15 = -_t14
    _t16 = _t2*omega_x_
    _t17 = -_t16
    _t18 = _t2*omega_z_
    _t19 = -_t18
    _t20 = _t4*omega_x_
    _t21 = -_t20
    _t22 = _t4*omega_y_
    _t23 = -_t22
    _t24 = ((1/2))*q0_
    _t25 = _t24*omega_x_
    _t26 = _t24*omega_y_
    _t27 = _t24*omega_z_
    _t28 = q2_**2
    _t29 = q3_**2
    _t30 = q0_**2
    _t31 = q1_**2
    _t32 = _t30 + _t31
    _t33 = 1/(_t28 + _t29 + _t32)
    _t34 = -_t28
    _t35 = -_t29
    _t36 = _t33*(_t32 + _t34 + _t35)
    _t37 = 2*q0_
    _t38 = _t37*q3_
    _t39 = _t33*(-_t38 + 2*q1_*q2_)
    _t40 = _t37*q2_
    _t41 = 2*q1_
    _t42 = _t33*(_t40 + _t41*q3_)
    _t43 = _t33*(_t38 + _t41*q2_)
    _t44 = _t30 - _t31
    _t45 = _t33*(_t28 + _t35 + _t44)
    _t46 = _t37*q1_
    _t47 = _t33*(-_t46 + 2*q2_*q3_)
    _t48 = _t33*(-_t40 + 2*q1_*q3_)
    _t49 = _t33*(_t46 + 2*q2_*q3_)
    _t50 = _t33*(_t29 + _t34 + _t44)
    _out = _np.zeros((10, 33) + _batch)
    _out[0, 0] = _t1
    _out[0, 1] = _t3
    _out[0, 2] = _t5
    _out[0, 3] = _t7
    _out[0, 4] = _t9
    _out[0, 5] = _t11
    _out[0, 6] = _t13
    _out[0, 7] = _t15
    _out[0, 8] = _t17
    _out[0, 9] = _t19
    _out[0, 10] = _t21
    _out[0, 11] = _t23
    _out[1, 0] = _t24
    _out[1, 1] = _t5
    _out[1, 2] = _t2
    _out[1, 3] = _t25
    _out[1, 4] = _t23
    _out[1, 5] = _t18
    _out[1, 6] = _t26
    _out[1, 7] = _t27
    _out[1, 8] = _t21
    _out[1, 9] = _t11
    _out[1, 10] = _t16
    _out[1, 11] = _t8
    _out[2, 0] = _t4
    _out[2, 1] = _t24
    _out[2, 2] = _t1
    _out[2, 3] = _t20
    _out[2, 4] = _t26
    _out[2, 5] = _t15
    _out[2, 6] = _t22
    _out[2, 7] = _t10
    _out[2, 8] = _t25
    _out[2, 9] = _t27
    _out[2, 10] = _t7
    _out[2, 11] = _t13
    _out[3, 0] = _t3
    _out[3, 1] = _t0
    _out[3, 2] = _t24
    _out[3, 3] = _t17
    _out[3, 4] = _t12
    _out[3, 5] = _t27
    _out[3, 6] = _t9
    _out[3, 7] = _t19
    _out[3, 8] = _t6
    _out[3, 9] = _t14
    _out[3, 10] = _t25
    _out[3, 11] = _t26
    _out[4, 12] = _t36
    _out[4, 13] = _t39
    _out[4, 14] = _t42
    _out[4, 15] = _t36*f_x_
    _out[4, 16] = _t39*f_y_
    _out[4, 17] = _t42*f_z_
    _out[4, 18] = _t36*f_y_
    _out[4, 19] = _t36*f_z_
    _out[4, 20] = _t39*f_x_
    _out[4, 21] = _t39*f_z_
    _out[4, 22] = _t42*f_x_
    _out[4, 23] = _t42*f_y_
    _out[5, 12] = _t43
    _out[5, 13] = _t45
    _out[5, 14] = _t47
    _out[5, 15] = _t43*f_x_
    _out[5, 16] = _t45*f_y_
    _out[5, 17] = _t47*f_z_
    _out[5, 18] = _t43*f_y_
    _out[5, 19] = _t43*f_z_
    _out[5, 20] = _t45*f_x_
    _out[5, 21] = _t45*f_z_
    _out[5, 22] = _t47*f_x_
    _out[5, 23] = _t47*f_y_
    _out[6, 12] = _t48
    _out[6, 13] = _t49
    _out[6, 14] = _t50
    _out[6, 15] = _t48*f_x_
    _out[6, 16] = _t49*f_y_
    _out[6, 17] = _t50*f_z_
    _out[6, 18] = _t48*f_y_
    _out[6, 19] = _t48*f_z_
    _out[6, 20] = _t49*f_x_
    _out[6, 21] = _t49*f_z_
    _out[6, 22] = _t50*f_x_
    _out[6, 23] = _t50*f_y_
    return _out


def output_matrix(x, u, p):
    """Output matrix H: output errors = H xe to first order.

    Parameters
    ----------
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (9, 10, ...)
        H
    """
    x = _as_vector(x, 10, 'x', 'output_matrix')
    u = _as_vector(u, 7, 'u', 'output_matrix')
    p = _as_vector(p, 8, 'p', 'output_matrix')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    _t0 = 2*q0_
    _t1 = 2*q1_
    _t2 = 2*q2_
    _t3 = _t1*q0_ + _t2*q3_
    _t4 = q3_**2
    _t5 = q1_**2
    _t6 = q0_**2 - q2_**2
    _t7 = _t4 - _t5 + _t6
    _t8 = _t3**2 + _t7**2
    _t9 = 1/_t8
    _t10 = -_t3*_t9
    _t11 = _t1*_t7
    _t12 = _t0*_t7
    _t13 = _t2*_t7
    _t14 = 2*q3_
    _t15 = _m.sqrt(_t8)
    _t16 = -_t1*q3_ + _t2*q0_
    _t17 = 1/(_t16**2 + _t8)
    _t18 = _t15*_t17
    _t19 = 1/_t15
    _t20 = -_t16
    _t21 = _t17*_t19*_t20
    _t22 = _t0*q3_ + _t1*q2_
    _t23 = -_t4 + _t5 + _t6
    _t24 = 1/(_t22**2 + _t23**2)
    _t25 = -_t22*_t24
    _t26 = _t23*_t24
    _out = _np.zeros((9, 10) + _batch)
    _out[0, 7] = 1
    _out[1, 8] = 1
    _out[2, 9] = 1
    _out[3, 4] = 1
    _out[4, 5] = 1
    _out[5, 6] = 1
    _out[6, 0] = _t0*_t10 + _t11*_t9
    _out[6, 1] = -_t1*_t10 + _t12*_t9
    _out[6, 2] = -_t10*_t2 + 2*_t7*_t9*q3_
    _out[6, 3] = _t10*_t14 + _t13*_t9
    _out[7, 0] = _t18*_t2 + _t21*(_t1*_t3 + _t12)
    _out[7, 1] = -_t14*_t18 + _t17*_t19*_t20*(_t0*_t3 - _t11)
    _out[7, 2] = _t0*_t18 + _t21*(-_t13 + 2*_t3*q3_)
    _out[7, 3] = -_t1*_t18 + _t17*_t19*_t20*(_t14*_t7 + _t2*_t3)
    _out[8, 0] = _t0*_t25 + _t14*_t26
    _out[8, 1] = _t1*_t25 + _t2*_t26
    _out[8, 2] = _t1*_t26 - _t2*_t25
    _out[8, 3] = _t0*_t26 - _t14*_t25
    return _out


def second_order(x, u, p, xe, w):
    """Second-order term of the error equations (refined model).

    Parameters
    ----------
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units
    xe : array_like, shape (10, ...)
        error state xr - (x, 0)
    w : array_like, shape (33, ...)
        error-source magnitudes, SI units

    Returns
    -------
    numpy.ndarray, shape (10, ...)
        1/2 (xe, w)' Hessian (xe, w) per equation
    """
    x = _as_vector(x, 10, 'x', 'second_order')
    u = _as_vector(u, 7, 'u', 'second_order')
    p = _as_vector(p, 8, 'p', 'second_order')
    xe = _as_vector(xe, 10, 'xe', 'second_order')
    w = _as_vector(w, 33, 'w', 'second_order')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:], xe.shape[1:], w.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    v_N_ = x[4]
    v_E_ = x[5]
    v_D_ = x[6]
    lat_ = x[7]
    h_ = x[9]
    omega_x_ = u[0]
    omega_y_ = u[1]
    omega_z_ = u[2]
    f_x_ = u[3]
    f_y_ = u[4]
    f_z_ = u[5]
    a_ = p[0]
    e2_ = p[1]
    U_ = p[2]
    gamma_e_ = p[3]
    gravity_k_ = p[4]
    gravity_m_ = p[5]
    delta_q0_ = xe[0]
    delta_q1_ = xe[1]
    delta_q2_ = xe[2]
    delta_q3_ = xe[3]
    delta_v_N_ = xe[4]
    delta_v_E_ = xe[5]
    delta_v_D_ = xe[6]
    delta_lat_ = xe[7]
    delta_h_ = xe[9]
    gyro_bias_x_ = w[0]
    gyro_bias_y_ = w[1]
    gyro_bias_z_ = w[2]
    gyro_scale_error_x_ = w[3]
    gyro_scale_error_y_ = w[4]
    gyro_scale_error_z_ = w[5]
    gyro_misalignment_xy_ = w[6]
    gyro_misalignment_xz_ = w[7]
    gyro_misalignment_yx_ = w[8]
    gyro_misalignment_yz_ = w[9]
    gyro_misalignment_zx_ = w[10]
    gyro_misalignment_zy_ = w[11]
    accel_bias_x_ = w[12]
    accel_bias_y_ = w[13]
    accel_bias_z_ = w[14]
    accel_scale_error_x_ = w[15]
    accel_scale_error_y_ = w[16]
    accel_scale_error_z_ = w[17]
    accel_misalignment_xy_ = w[18]
    accel_misalignment_xz_ = w[19]
    accel_misalignment_yx_ = w[20]
    accel_misalignment_yz_ = w[21]
    accel_misalignment_zx_ = w[22]
    accel_misalignment_zy_ = w[23]
    _t0 = ((1/2))*gyro_bias_x_
    _t1 = ((1/2))*delta_q2_
    _t2 = ((1/2))*delta_q3_
    _t3 = delta_h_**2
    _t4 = 1 - e2_
    _t5 = _m.sin(lat_)
    _t6 = _t5**2
    _t7 = _t6*e2_
    _t8 = 1 - _t7
    _t9 = (1/(_t8*_m.sqrt(_t8)))
    _t10 = _t9*a_
    _t11 = _t10*_t4 + h_
    _t12 = _t11**(-3)
    _t13 = _t12*v_N_
    _t14 = _t13*q2_
    _t15 = 1/_m.sqrt(_t8)
    _t16 = _t15*a_ + h_
    _t17 = _t16**(-3)
    _t18 = _m.tan(lat_)
    _t19 = _t17*v_E_
    _t20 = _t19*q3_
    _t21 = delta_lat_**2
    _t22 = _m.cos(lat_)
    _t23 = U_*_t22
    _t24 = _t16**(-2)
    _t25 = _t24*v_E_
    _t26 = _t10*_t25
    _t27 = _t22**2
    _t28 = _t27*e2_
    _t29 = a_**2
    _t30 = e2_**2
    _t31 = _t8**(-3)
    _t32 = _t27*_t30
    _t33 = _t32*_t6
    _t34 = (1/(_t8**2*_m.sqrt(_t8)))
    _t35 = _t34*a_
    _t36 = 3*_t35
    _t37 = _t25*_t36
    _t38 = -2*_t17*_t27*_t29*_t30*_t31*_t6*v_E_ - _t24*_t6*_t9*a_*e2_*v_E_ + _t26*_t28 + _t33*_t37
    _t39 = -(1/2)*_t23 - (1/2)*_t38
    _t40 = U_*_t5
    _t41 = _t18**2
    _t42 = 1/_t16
    _t43 = _t42*v_E_
    _t44 = _t18*_t24
    _t45 = _t44*v_E_
    _t46 = _t10*_t45
    _t47 = _t18*_t19
    _t48 = 2*_t6
    _t49 = _t41 + 1
    _t50 = _t49*v_E_
    _t51 = 2*_t5
    _t52 = _t22*e2_
    _t53 = _t51*_t52
    _t54 = _t10*_t53
    _t55 = -_t18*_t43*(2*_t41 + 2) + _t24*_t50*_t54 + _t28*_t46 - _t29*_t31*_t32*_t47*_t48 + _t33*_t36*_t45 - _t46*_t7
    _t56 = ((1/2))*_t40 + ((1/2))*_t55
    _t57 = _t11**(-2)
    _t58 = _t4*_t57
    _t59 = _t58*v_N_
    _t60 = _t59*q2_
    _t61 = ((3/2))*_t35
    _t62 = _t60*_t61
    _t63 = _t29*_t33*_t4**2/_t8**5
    _t64 = 9*_t63
    _t65 = (1/(_t8**3*_m.sqrt(_t8)))
    _t66 = _t33*_t65*a_
    _t67 = ((15/2))*_t66
    _t68 = ((1/2))*delta_q1_
    _t69 = gyro_misalignment_xy_*omega_y_
    _t70 = gyro_misalignment_xz_*omega_z_
    _t71 = gyro_scale_error_x_*omega_x_
    _t72 = 1/_t11
    _t73 = _t72*delta_v_N_
    _t74 = _t1*omega_x_
    _t75 = _t1*omega_z_
    _t76 = _t1*omega_y_
    _t77 = _t2*omega_x_
    _t78 = _t2*omega_y_
    _t79 = _t2*omega_z_
    _t80 = _t24*_t49*v_E_ - _t47*_t54
    _t81 = _t19*q1_
    _t82 = _t5*_t52
    _t83 = _t35*_t82
    _t84 = _t4*_t83
    _t85 = 6*_t84
    _t86 = _t24*q1_
    _t87 = _t26*_t52
    _t88 = _t5*_t87
    _t89 = _t40 + _t88
    _t90 = -_t89
    _t91 = _t42*_t50
    _t92 = -_t18*_t22*_t24*_t5*_t9*a_*e2_*v_E_ + _t23 + _t91
    _t93 = -_t92
    _t94 = _t42*_t49
    _t95 = _t10*_t82
    _t96 = _t24*delta_h_
    _t97 = _t96*v_E_
    _t98 = _t42*delta_v_E_
    _t99 = _t2*_t98
    _t100 = _t19*q0_
    _t101 = _t19*q2_
    _t102 = ((1/2))*_t3
    _t103 = _t59*_t61
    _t104 = _t103*q3_
    _t105 = _t13*q3_
    _t106 = _t59*_t67
    _t107 = ((1/2))*_t21
    _t108 = ((1/2))*delta_h_
    _t109 = _t108*delta_lat_
    _t110 = _t24*q0_
    _t111 = _t24*q2_
    _t112 = _t111*_t18
    _t113 = _t108*delta_v_E_
    _t114 = ((1/2))*delta_q0_
    _t115 = _t114*delta_lat_
    _t116 = ((1/2))*delta_lat_
    _t117 = _t116*delta_v_E_
    _t118 = _t114*_t98
    _t119 = _t57*delta_h_
    _t120 = _t119*v_N_
    _t121 = _t119*delta_v_N_
    _t122 = ((1/2))*_t121
    _t123 = _t1*_t98
    _t124 = _t45*delta_h_
    _t125 = _t82*delta_lat_
    _t126 = _t103*_t125
    _t127 = _t125*delta_v_N_
    _t128 = _t127*_t58*_t61
    _t129 = _t13*q0_
    _t130 = _t103*q0_
    _t131 = _t24*q3_
    _t132 = _t18*_t86
    _t133 = _t114*omega_x_
    _t134 = _t114*omega_z_
    _t135 = _t114*omega_y_
    _t136 = _t68*omega_x_
    _t137 = _t68*omega_y_
    _t138 = _t68*omega_z_
    _t139 = _t13*q1_
    _t140 = _t110*_t18
    _t141 = _t17*v_E_**2
    _t142 = 2*_t141
    _t143 = 2*v_D_
    _t144 = 2*_t40 + _t55
    _t145 = _t36*_t58
    _t146 = _t145*v_N_
    _t147 = _t146*_t28
    _t148 = _t146*_t7
    _t149 = 15*_t66
    _t150 = _t149*_t59
    _t151 = 18*_t63
    _t152 = _t13*_t151
    _t153 = 2*f_y_
    _t154 = 2*q0_
    _t155 = 2*f_z_
    _t156 = -_t153*q3_ + _t154*f_x_ + _t155*q2_
    _t157 = q2_**2
    _t158 = q3_**2
    _t159 = q0_**2
    _t160 = q1_**2
    _t161 = _t159 + _t160
    _t162 = _t157 + _t158 + _t161
    _t163 = _t162**(-2)
    _t164 = 4*_t163
    _t165 = _t164*q0_
    _t166 = -_t156*_t165
    _t167 = -_t157
    _t168 = -_t158
    _t169 = _t161 + _t167 + _t168
    _t170 = _t169*f_x_
    _t171 = _t154*q3_
    _t172 = -_t171 + 2*q1_*q2_
    _t173 = _t172*f_y_
    _t174 = _t154*q2_
    _t175 = 2*q1_
    _t176 = _t174 + _t175*q3_
    _t177 = _t176*f_z_
    _t178 = _t170 + _t173 + _t177
    _t179 = _t162**(-3)
    _t180 = 8*_t179
    _t181 = _t178*_t180
    _t182 = 2*_t163
    _t183 = _t178*_t182
    _t184 = 1/_t162
    _t185 = 2*f_x_
    _t186 = _t184*_t185
    _t187 = -_t183 + _t186
    _t188 = ((1/2))*delta_q0_**2
    _t189 = _t153*q2_ + _t155*q3_ + _t175*f_x_
    _t190 = _t164*q1_
    _t191 = -_t189*_t190
    _t192 = ((1/2))*delta_q1_**2
    _t193 = _t154*f_z_ + _t175*f_y_ - _t185*q2_
    _t194 = _t164*q2_
    _t195 = _t193*_t194
    _t196 = _t183 + _t186
    _t197 = ((1/2))*delta_q2_**2
    _t198 = _t154*f_y_ + _t185*q3_ - 2*f_z_*q1_
    _t199 = -_t198
    _t200 = _t164*q3_
    _t201 = ((1/2))*delta_q3_**2
    _t202 = 4*_t184
    _t203 = _t202*q0_
    _t204 = -_t203
    _t205 = _t165*_t169
    _t206 = _t114*accel_bias_x_
    _t207 = _t202*q1_
    _t208 = -_t207
    _t209 = _t169*_t190
    _t210 = _t68*accel_bias_x_
    _t211 = _t202*q2_
    _t212 = _t169*_t194
    _t213 = _t1*accel_bias_x_
    _t214 = _t202*q3_
    _t215 = _t169*_t200
    _t216 = _t2*accel_bias_x_
    _t217 = _t165*_t172
    _t218 = _t114*accel_bias_y_
    _t219 = -_t211
    _t220 = _t172*_t190
    _t221 = _t68*accel_bias_y_
    _t222 = _t172*_t194
    _t223 = _t1*accel_bias_y_
    _t224 = _t172*_t200
    _t225 = _t2*accel_bias_y_
    _t226 = _t165*_t176
    _t227 = _t114*accel_bias_z_
    _t228 = -_t214
    _t229 = _t176*_t190
    _t230 = _t68*accel_bias_z_
    _t231 = _t176*_t194
    _t232 = _t1*accel_bias_z_
    _t233 = _t176*_t200
    _t234 = _t2*accel_bias_z_
    _t235 = _t203*f_y_
    _t236 = -_t235
    _t237 = _t114*accel_misalignment_xy_
    _t238 = _t207*f_y_
    _t239 = -_t238
    _t240 = _t68*accel_misalignment_xy_
    _t241 = _t211*f_y_
    _t242 = _t1*accel_misalignment_xy_
    _t243 = _t214*f_y_
    _t244 = _t2*accel_misalignment_xy_
    _t245 = _t203*f_z_
    _t246 = -_t245
    _t247 = _t114*accel_misalignment_xz_
    _t248 = _t207*f_z_
    _t249 = -_t248
    _t250 = _t68*accel_misalignment_xz_
    _t251 = _t211*f_z_
    _t252 = _t1*accel_misalignment_xz_
    _t253 = _t214*f_z_
    _t254 = _t2*accel_misalignment_xz_
    _t255 = _t214*f_x_
    _t256 = _t114*accel_misalignment_yx_
    _t257 = _t211*f_x_
    _t258 = -_t257
    _t259 = _t68*accel_misalignment_yx_
    _t260 = _t207*f_x_
    _t261 = _t1*accel_misalignment_yx_
    _t262 = _t203*f_x_
    _t263 = _t2*accel_misalignment_yx_
    _t264 = _t114*accel_misalignment_yz_
    _t265 = -_t251
    _t266 = _t68*accel_misalignment_yz_
    _t267 = _t1*accel_misalignment_yz_
    _t268 = _t2*accel_misalignment_yz_
    _t269 = _t114*accel_misalignment_zx_
    _t270 = -_t255
    _t271 = _t68*accel_misalignment_zx_
    _t272 = _t1*accel_misalignment_zx_
    _t273 = _t2*accel_misalignment_zx_
    _t274 = -_t241
    _t275 = _t114*accel_misalignment_zy_
    _t276 = -_t243
    _t277 = _t68*accel_misalignment_zy_
    _t278 = _t1*accel_misalignment_zy_
    _t279 = _t2*accel_misalignment_zy_
    _t280 = -_t262
    _t281 = _t114*accel_scale_error_x_
    _t282 = -_t260
    _t283 = _t68*accel_scale_error_x_
    _t284 = _t1*accel_scale_error_x_
    _t285 = _t2*accel_scale_error_x_
    _t286 = _t114*accel_scale_error_y_
    _t287 = _t68*accel_scale_error_y_
    _t288 = _t1*accel_scale_error_y_
    _t289 = _t2*accel_scale_error_y_
    _t290 = _t114*accel_scale_error_z_
    _t291 = -_t253
    _t292 = _t68*accel_scale_error_z_
    _t293 = _t1*accel_scale_error_z_
    _t294 = _t2*accel_scale_error_z_
    _t295 = 2*_t80
    _t296 = 12*_t84
    _t297 = 4*_t23
    _t298 = _t165*_t189
    _t299 = _t156*_t190
    _t300 = _t114*delta_q1_
    _t301 = -_t165*_t193
    _t302 = 16*_t179
    _t303 = _t178*_t302
    _t304 = _t202*f_z_
    _t305 = -_t156*_t194 + _t304
    _t306 = _t1*delta_q0_
    _t307 = _t202*f_y_
    _t308 = _t156*_t200
    _t309 = _t2*delta_q0_
    _t310 = -_t189*_t194
    _t311 = _t303*q1_
    _t312 = -_t190*_t193 + _t307
    _t313 = _t1*delta_q1_
    _t314 = -_t189*_t200
    _t315 = _t2*delta_q1_
    _t316 = _t193*_t200
    _t317 = _t1*delta_q3_
    _t318 = _t42*delta_v_E_**2
    _t319 = 2*delta_v_E_
    _t320 = _t127*_t145
    _t321 = 2*v_N_
    _t322 = -2*_t23 - _t38
    _t323 = -_t165*_t198
    _t324 = _t171 + _t175*q2_
    _t325 = _t324*f_x_
    _t326 = _t159 - _t160
    _t327 = _t157 + _t168 + _t326
    _t328 = _t327*f_y_
    _t329 = _t154*q1_
    _t330 = -_t329 + 2*q2_*q3_
    _t331 = _t330*f_z_
    _t332 = _t325 + _t328 + _t331
    _t333 = _t180*_t332
    _t334 = _t182*_t332
    _t335 = _t153*_t184
    _t336 = -_t334 + _t335
    _t337 = -_t193
    _t338 = _t334 + _t335
    _t339 = _t165*_t324
    _t340 = _t190*_t324
    _t341 = _t194*_t324
    _t342 = _t200*_t324
    _t343 = _t165*_t327
    _t344 = _t190*_t327
    _t345 = _t194*_t327
    _t346 = _t200*_t327
    _t347 = _t165*_t330
    _t348 = _t190*_t330
    _t349 = _t194*_t330
    _t350 = _t200*_t330
    _t351 = 4*_t95
    _t352 = _t143*_t24
    _t353 = _t321*_t44
    _t354 = 4*_t40
    _t355 = _t190*_t198
    _t356 = _t194*_t198
    _t357 = _t302*_t332
    _t358 = _t202*f_x_
    _t359 = -_t198*_t200 + _t358
    _t360 = q2_*q3_
    _t361 = v_N_**2
    _t362 = _t12*_t361
    _t363 = 1/_t29
    _t364 = _t6*gravity_k_
    _t365 = _t364 + 1
    _t366 = _t15*gamma_e_
    _t367 = _t364*_t366
    _t368 = 1/a_
    _t369 = _m.sqrt(_t4)
    _t370 = 2 - 2*_t369
    _t371 = _t370*_t6
    _t372 = 2*_t368*(-_t369 - _t371 + gravity_m_ + 2)
    _t373 = 3*_t363*h_**2 - _t372*h_ + 1
    _t374 = 2*_t373
    _t375 = _t366*gravity_k_
    _t376 = _t365*_t373*gamma_e_
    _t377 = _t376*_t9
    _t378 = _t365*_t366*_t368
    _t379 = 4*_t378*h_
    _t380 = _t145*_t361
    _t381 = _t9*gamma_e_
    _t382 = _t27*_t381*_t7
    _t383 = _t27*_t370
    _t384 = _t368*h_
    _t385 = 8*_t370
    _t386 = -_t174 + 2*q1_*q3_
    _t387 = _t386*f_x_
    _t388 = _t329 + 2*_t360
    _t389 = _t388*f_y_
    _t390 = _t158 + _t167 + _t326
    _t391 = _t390*f_z_
    _t392 = _t387 + _t389 + _t391
    _t393 = _t180*_t392
    _t394 = _t182*_t392
    _t395 = _t155*_t184
    _t396 = -_t394 + _t395
    _t397 = _t394 + _t395
    _t398 = -_t156
    _t399 = _t165*_t386
    _t400 = _t190*_t386
    _t401 = _t194*_t386
    _t402 = _t200*_t386
    _t403 = _t165*_t388
    _t404 = _t190*_t388
    _t405 = _t194*_t388
    _t406 = _t200*_t388
    _t407 = _t165*_t390
    _t408 = _t190*_t390
    _t409 = _t194*_t390
    _t410 = _t200*_t390
    _t411 = 6*_t363*h_ - _t372
    _t412 = 4*_t5
    _t413 = _t302*_t392
    _t414 = 1/_t22
    _t415 = _t22*_t30
    _t416 = 1/_t27
    _t417 = _t10*e2_
    _out = _np.zeros((10,) + _batch)
    _out[0] = -_t0*delta_q1_ - _t1*_t73 - _t1*gyro_bias_y_ + ((1/2))*_t18*_t24*delta_h_*delta_q3_*v_E_ - _t18*_t99 - _t2*gyro_bias_z_ + ((1/2))*_t21*(-_t14*_t64 + _t28*_t62 + _t39*q1_ + _t56*q3_ + _t60*_t67 - _t62*_t7) + ((3/2))*_t22*_t34*_t4*_t5*_t57*a_*delta_lat_*delta_q2_*e2_*v_N_ + ((3/2))*_t22*_t34*_t4*_t5*_t57*a_*delta_lat_*delta_v_N_*e2_*q2_ + ((1/2))*_t3*(-_t14 + _t17*q1_*v_E_ - _t18*_t20) + ((1/2))*_t42*delta_q1_*delta_v_E_ + ((1/2))*_t57*delta_h_*delta_q2_*v_N_ + ((1/2))*_t57*delta_h_*delta_v_N_*q2_ - _t68*_t69 - _t68*_t70 - _t68*_t71 - _t68*_t97 - _t74*gyro_misalignment_yx_ - _t75*gyro_misalignment_yz_ - _t76*gyro_scale_error_y_ - _t77*gyro_misalignment_zx_ - _t78*gyro_misalignment_zy_ - _t79*gyro_scale_error_z_ + ((1/2))*_t90*delta_lat_*delta_q1_ + ((1/2))*_t93*delta_lat_*delta_q3_ + ((1/2))*delta_h_*delta_lat_*(-_t14*_t85 + _t54*_t81 + _t80*q3_) + ((1/2))*delta_h_*delta_v_E_*(_t18*_t24*q3_ - _t86) + ((1/2))*delta_lat_*delta_v_E_*(_t18*_t22*_t24*_t5*_t9*a_*e2_*q3_ - _t86*_t95 - _t94*q3_)
    _out[1] = _t0*delta_q0_ + _t1*_t124 + _t1*_t93*delta_lat_ + _t1*gyro_bias_z_ + _t102*(-_t100 - _t101*_t18 + _t12*q3_*v_N_) + _t107*(-_t104*_t28 + _t104*_t7 + _t105*_t64 - _t106*q3_ - _t39*q0_ + _t56*q2_) + _t109*(-_t100*_t54 + _t105*_t85 + _t80*q2_) + _t113*(_t110 + _t112) + _t114*_t69 + _t114*_t70 + _t114*_t71 + _t114*_t97 + _t115*_t89 + _t117*(_t110*_t95 + _t112*_t95 - _t94*q2_) - _t118 - _t120*_t2 - _t122*q3_ - _t123*_t18 - _t126*delta_q3_ - _t128*q3_ + _t2*_t73 - _t2*gyro_bias_y_ + _t74*gyro_misalignment_zx_ + _t75*gyro_scale_error_z_ + _t76*gyro_misalignment_zy_ - _t77*gyro_misalignment_yx_ - _t78*gyro_scale_error_y_ - _t79*gyro_misalignment_yz_
    _out[2] = _t0*delta_q3_ + _t102*(_t129 + _t18*_t81 + _t20) + _t107*(-_t106*q0_ + _t129*_t64 - _t130*_t28 + _t130*_t7 + _t39*q3_ - _t56*q1_) + _t109*(_t129*_t85 + _t20*_t54 - _t80*q1_) + _t113*(-_t131 - _t132) - _t114*_t120 + _t114*_t73 + _t114*gyro_bias_y_ + _t117*(-_t131*_t95 - _t132*_t95 + _t42*_t49*q1_) - _t122*q0_ - _t124*_t68 - _t126*delta_q0_ - _t128*q0_ + _t133*gyro_misalignment_yx_ + _t134*gyro_misalignment_yz_ + _t135*gyro_scale_error_y_ - _t136*gyro_misalignment_zx_ - _t137*gyro_misalignment_zy_ - _t138*gyro_scale_error_z_ + _t18*_t68*_t98 + _t2*_t69 + _t2*_t70 + _t2*_t71 + _t2*_t90*delta_lat_ - _t2*_t97 + _t68*_t92*delta_lat_ - _t68*gyro_bias_z_ + _t99
    _out[3] = -_t0*delta_q2_ - _t1*_t69 - _t1*_t70 - _t1*_t71 + _t1*_t89*delta_lat_ + _t1*_t97 + _t102*(-_t101 - _t139 + _t17*_t18*q0_*v_E_) + _t107*(-_t103*_t7*q1_ - _t139*_t64 + ((15/2))*_t27*_t30*_t4*_t57*_t6*_t65*a_*q1_*v_N_ + ((3/2))*_t27*_t34*_t4*_t57*a_*e2_*q1_*v_N_ - _t39*q2_ - _t56*q0_) + _t109*(-_t101*_t54 - _t139*_t85 - _t80*q0_) + _t113*(-_t140 + _t24*q2_) - _t114*_t124 + _t114*gyro_bias_z_ + _t115*_t92 + _t117*(_t111*_t95 - _t140*_t95 + _t94*q0_) + _t118*_t18 + _t120*_t68 + _t122*q1_ - _t123 + _t126*delta_q1_ + _t128*q1_ + _t133*gyro_misalignment_zx_ + _t134*gyro_scale_error_z_ + _t135*gyro_misalignment_zy_ + _t136*gyro_misalignment_yx_ + _t137*gyro_scale_error_y_ + _t138*gyro_misalignment_yz_ - _t68*_t73 + _t68*gyro_bias_y_
    _out[4] = _t102*(_t13*_t143 - _t142*_t18) + _t107*(_t144*v_E_ - _t147*v_D_ + _t148*v_D_ - _t150*v_D_ + _t152*v_D_) + _t109*(_t13*_t296*v_D_ + _t295*v_E_) + _t117*(4*_t18*_t22*_t24*_t5*_t9*a_*e2_*v_E_ - _t297 - 4*_t91) - _t120*delta_v_D_ - _t121*v_D_ + _t124*_t319 - _t125*_t146*delta_v_D_ - _t18*_t318 + _t188*(_t159*_t181 + _t166 + _t187) + _t192*(_t160*_t181 + _t187 + _t191) + _t197*(8*_t157*_t178*_t179 - _t195 - _t196) + _t201*(8*_t158*_t178*_t179 - _t196 - _t199*_t200) + _t206*(-_t204 - _t205) + _t210*(-_t208 - _t209) + _t213*(-_t211 - _t212) + _t216*(-_t214 - _t215) + _t218*(-_t214 - _t217) + _t221*(-_t219 - _t220) + _t223*(_t207 - _t222) + _t225*(-_t203 - _t224) + _t227*(-_t219 - _t226) + _t230*(-_t228 - _t229) + _t232*(_t203 - _t231) + _t234*(_t207 - _t233) + _t237*(-_t205*f_y_ - _t236) + _t240*(-_t209*f_y_ - _t239) + _t242*(-_t212*f_y_ - _t241) + _t244*(-_t215*f_y_ - _t243) + _t247*(-_t205*f_z_ - _t246) + _t250*(-_t209*f_z_ - _t249) + _t252*(-_t212*f_z_ - _t251) + _t254*(-_t215*f_z_ - _t253) + _t256*(-_t217*f_x_ - _t255) + _t259*(-_t220*f_x_ - _t258) + _t261*(-_t222*f_x_ + _t260) + _t263*(-_t224*f_x_ - _t262) + _t264*(-_t217*f_z_ - _t253) + _t266*(-_t220*f_z_ - _t265) + _t267*(-_t222*f_z_ + _t248) + _t268*(-_t224*f_z_ - _t245) + _t269*(-_t226*f_x_ - _t258) + _t271*(-_t229*f_x_ - _t270) + _t272*(-_t231*f_x_ + _t262) + _t273*(-_t233*f_x_ + _t260) + _t275*(-_t226*f_y_ - _t274) + _t277*(-_t229*f_y_ - _t276) + _t278*(-_t231*f_y_ + _t235) + _t279*(-_t233*f_y_ + _t238) + _t281*(-_t165*_t170 - _t280) + _t283*(-_t170*_t190 - _t282) + _t284*(-_t170*_t194 - _t257) + _t285*(-_t170*_t200 - _t255) + _t286*(-_t165*_t173 - _t243) + _t287*(-_t173*_t190 - _t274) + _t288*(-_t173*_t194 + _t238) + _t289*(-_t173*_t200 - _t235) + _t290*(-_t165*_t177 - _t265) + _t292*(-_t177*_t190 - _t291) + _t293*(-_t177*_t194 + _t245) + _t294*(-_t177*_t200 + _t248) + _t300*(16*_t178*_t179*q0_*q1_ - _t298 - _t299) + _t306*(_t301 + _t303*q0_*q2_ + _t305) + _t309*(-_t165*_t199 + 16*_t178*_t179*q0_*q3_ - _t307 - _t308) + _t313*(_t310 + _t311*q2_ + _t312) + _t315*(-_t190*_t199 + _t304 + _t311*q3_ + _t314) + _t317*(16*_t178*_t179*q2_*q3_ - _t194*_t199 - _t316) - _t320*v_D_ + _t73*delta_v_D_
    _out[5] = _t102*(_t143*_t19 + _t321*_t47) + _t107*(-_t144*v_N_ + _t322*v_D_) + _t109*(_t19*_t351*v_D_ - _t295*v_N_) + _t113*(-_t352 - _t353) + _t116*delta_v_D_*(-_t354 - _t51*_t87) + _t116*delta_v_N_*(_t297 - _t46*_t53 + 2*_t91) + _t117*(-_t352*_t95 - _t353*_t95 + 2*_t42*_t49*v_N_) - _t124*delta_v_N_ + _t18*_t98*delta_v_N_ + _t188*(_t159*_t333 + _t323 + _t336) + _t192*(8*_t160*_t179*_t332 - _t190*_t337 - _t338) + _t197*(_t157*_t333 + _t310 + _t336) + _t201*(8*_t158*_t179*_t332 - _t308 - _t338) + _t206*(-_t228 - _t339) + _t210*(-_t219 - _t340) + _t213*(_t207 - _t341) + _t216*(_t203 - _t342) + _t218*(-_t204 - _t343) + _t221*(-_t207 - _t344) + _t223*(-_t219 - _t345) + _t225*(-_t214 - _t346) + _t227*(-_t207 - _t347) + _t230*(-_t203 - _t348) + _t232*(-_t228 - _t349) + _t234*(_t211 - _t350) + _t237*(-_t276 - _t339*f_y_) + _t240*(-_t274 - _t340*f_y_) + _t242*(_t238 - _t341*f_y_) + _t244*(_t235 - _t342*f_y_) + _t247*(-_t291 - _t339*f_z_) + _t250*(-_t265 - _t340*f_z_) + _t252*(_t248 - _t341*f_z_) + _t254*(_t245 - _t342*f_z_) + _t256*(-_t280 - _t343*f_x_) + _t259*(-_t260 - _t344*f_x_) + _t261*(-_t258 - _t345*f_x_) + _t263*(-_t255 - _t346*f_x_) + _t264*(-_t246 - _t343*f_z_) + _t266*(-_t248 - _t344*f_z_) + _t267*(-_t265 - _t345*f_z_) + _t268*(-_t253 - _t346*f_z_) + _t269*(-_t260 - _t347*f_x_) + _t271*(-_t262 - _t348*f_x_) + _t272*(-_t270 - _t349*f_x_) + _t273*(_t257 - _t350*f_x_) + _t275*(-_t238 - _t347*f_y_) + _t277*(-_t235 - _t348*f_y_) + _t278*(-_t276 - _t349*f_y_) + _t279*(_t241 - _t350*f_y_) + _t281*(-_t165*_t325 - _t270) + _t283*(-_t190*_t325 - _t258) + _t284*(-_t194*_t325 + _t260) + _t285*(-_t200*_t325 + _t262) + _t286*(-_t165*_t328 - _t236) + _t287*(-_t190*_t328 - _t238) + _t288*(-_t194*_t328 - _t274) + _t289*(-_t200*_t328 - _t243) + _t290*(-_t165*_t331 - _t248) + _t292*(-_t190*_t331 - _t245) + _t293*(-_t194*_t331 - _t291) + _t294*(-_t200*_t331 + _t251) + _t300*(-_t165*_t337 + 16*_t179*_t332*q0_*q1_ - _t304 - _t355) + _t306*(16*_t179*_t332*q0_*q2_ - _t298 - _t356) + _t309*(_t166 + _t357*q0_*q3_ + _t359) + _t313*(_t191 - _t194*_t337 + _t357*q1_*q2_ + _t358) + _t315*(16*_t179*_t332*q1_*q3_ - _t200*_t337 - _t299) + _t317*(_t305 + _t314 + _t357*_t360) - _t97*delta_v_D_ + _t98*delta_v_D_
    _out[6] = _t102*(-_t142 + 6*_t15*_t363*_t365*gamma_e_ - 2*_t362) + _t107*(_t149*_t361*_t58 - _t151*_t362 + _t27*_t374*_t375 + _t28*_t377 + _t28*_t380 - _t322*v_E_ + 3*_t33*_t34*_t376 + _t365*_t382*_t384*_t385 - _t367*_t374 + 16*_t367*_t383*_t384 - _t371*_t379 + 4*_t373*_t382*gravity_k_ - _t377*_t7 + _t379*_t383 - _t380*_t7) + _t109*(-_t141*_t351 + _t22*_t375*_t411*_t412 + _t22*_t378*_t385*_t5 - _t296*_t362 + _t365*_t381*_t411*_t53) + _t117*(_t354 + 4*_t88) + _t121*_t321 + _t188*(_t159*_t393 + _t301 + _t396) + _t192*(8*_t160*_t179*_t392 - _t355 - _t397) + _t197*(8*_t157*_t179*_t392 - _t194*_t398 - _t397) + _t201*(_t158*_t393 + _t314 + _t396) + _t206*(-_t211 - _t399) + _t210*(-_t228 - _t400) + _t213*(-_t203 - _t401) + _t216*(_t207 - _t402) + _t218*(-_t208 - _t403) + _t221*(_t203 - _t404) + _t223*(-_t228 - _t405) + _t225*(_t211 - _t406) + _t227*(-_t204 - _t407) + _t230*(-_t207 - _t408) + _t232*(-_t211 - _t409) + _t234*(-_t228 - _t410) + _t237*(-_t241 - _t399*f_y_) + _t240*(-_t276 - _t400*f_y_) + _t242*(-_t235 - _t401*f_y_) + _t244*(_t238 - _t402*f_y_) + _t247*(-_t251 - _t399*f_z_) + _t250*(-_t291 - _t400*f_z_) + _t252*(-_t245 - _t401*f_z_) + _t254*(_t248 - _t402*f_z_) + _t256*(-_t282 - _t403*f_x_) + _t259*(_t262 - _t404*f_x_) + _t261*(-_t270 - _t405*f_x_) + _t263*(_t257 - _t406*f_x_) + _t264*(-_t249 - _t403*f_z_) + _t266*(_t245 - _t404*f_z_) + _t267*(-_t291 - _t405*f_z_) + _t268*(_t251 - _t406*f_z_) + _t269*(-_t280 - _t407*f_x_) + _t271*(-_t260 - _t408*f_x_) + _t272*(-_t257 - _t409*f_x_) + _t273*(-_t270 - _t410*f_x_) + _t275*(-_t236 - _t407*f_y_) + _t277*(-_t238 - _t408*f_y_) + _t278*(-_t241 - _t409*f_y_) + _t279*(-_t276 - _t410*f_y_) + _t281*(-_t165*_t387 - _t257) + _t283*(-_t190*_t387 - _t270) + _t284*(-_t194*_t387 - _t262) + _t285*(-_t200*_t387 + _t260) + _t286*(-_t165*_t389 - _t239) + _t287*(-_t190*_t389 + _t235) + _t288*(-_t194*_t389 - _t276) + _t289*(-_t200*_t389 + _t241) + _t290*(-_t165*_t391 - _t246) + _t292*(-_t190*_t391 - _t248) + _t293*(-_t194*_t391 - _t251) + _t294*(-_t200*_t391 - _t291) + _t300*(_t312 + _t323 + _t413*q0_*q1_) + _t306*(-_t165*_t398 + 16*_t179*_t392*q0_*q2_ - _t195 - _t358) + _t309*(16*_t179*_t392*q0_*q3_ - _t298 - _t316) + _t313*(16*_t179*_t392*q1_*q2_ - _t190*_t398 - _t356) + _t315*(_t191 + _t359 + _t413*q1_*q3_) + _t317*(-_t200*_t398 + _t307 + _t310 + _t360*_t413) - _t318 + _t319*_t97 + 6*_t59*_t83*delta_lat_*delta_v_N_ - _t72*delta_v_N_**2
    _out[7] = _t107*(-_t147 + _t148 - _t150 + _t152) - _t121 + _t13*_t3 + _t13*_t85*delta_h_*delta_lat_ - _t320
    _out[8] = _t107*(_t19*_t29*_t31*_t415*_t48 - _t26*_t414*_t7 - _t37*_t415*_t6 + _t414*_t43 - _t87 + _t43*_t48/_t22**3) + _t109*(_t19*_t412*_t417 - _t25*_t416*_t51) + _t117*(-_t24*_t417*_t51 + 2*_t416*_t42*_t5) + _t19*_t3*_t414 - _t414*_t96*delta_v_E_
    return _out


def initial_state(c, u, p):
    """True initial state from navigation initial conditions.

    Parameters
    ----------
    c : array_like, shape (9, ...)
        initial navigation conditions, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, ...)
        x(0)
    """
    c = _as_vector(c, 9, 'c', 'initial_state')
    u = _as_vector(u, 7, 'u', 'initial_state')
    p = _as_vector(p, 8, 'p', 'initial_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    height_ = c[2]
    v_N0_ = c[3]
    v_E0_ = c[4]
    v_D0_ = c[5]
    roll_ = c[6]
    pitch_ = c[7]
    heading_ = c[8]
    _t0 = ((1/2))*roll_
    _t1 = _m.cos(_t0)
    _t2 = ((1/2))*heading_
    _t3 = _m.cos(_t2)
    _t4 = ((1/2))*pitch_
    _t5 = _m.cos(_t4)
    _t6 = _m.sin(_t0)
    _t7 = _m.sin(_t2)
    _t8 = _m.sin(_t4)
    _t9 = _t7*_t8
    _t10 = _t3*_t8
    _t11 = _t5*_t7
    _out = _np.zeros((10,) + _batch)
    _out[0] = _t1*_t3*_t5 + _t6*_t9
    _out[1] = -_t1*_t9 + _t3*_t5*_t6
    _out[2] = _t1*_t10 + _t11*_t6
    _out[3] = _t1*_t11 - _t10*_t6
    _out[4] = v_N0_
    _out[5] = v_E0_
    _out[6] = v_D0_
    _out[7] = latitude_
    _out[8] = longitude_
    _out[9] = height_
    return _out


def initial_real_state(c, u, w, p):
    """Real-work initial state, initial-error sources applied.

    Parameters
    ----------
    c : array_like, shape (9, ...)
        initial navigation conditions, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    w : array_like, shape (33, ...)
        error-source magnitudes, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, ...)
        xr(0)
    """
    c = _as_vector(c, 9, 'c', 'initial_real_state')
    u = _as_vector(u, 7, 'u', 'initial_real_state')
    w = _as_vector(w, 33, 'w', 'initial_real_state')
    p = _as_vector(p, 8, 'p', 'initial_real_state')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], w.shape[1:], p.shape[1:])
    latitude_ = c[0]
    longitude_ = c[1]
    height_ = c[2]
    v_N0_ = c[3]
    v_E0_ = c[4]
    v_D0_ = c[5]
    roll_ = c[6]
    pitch_ = c[7]
    heading_ = c[8]
    initial_roll_error_ = w[24]
    initial_pitch_error_ = w[25]
    initial_heading_error_ = w[26]
    initial_velocity_error_N_ = w[27]
    initial_velocity_error_E_ = w[28]
    initial_velocity_error_D_ = w[29]
    initial_position_error_N_ = w[30]
    initial_position_error_E_ = w[31]
    initial_position_error_D_ = w[32]
    a_ = p[0]
    e2_ = p[1]
    _t0 = ((1/2))*initial_roll_error_ + ((1/2))*roll_
    _t1 = _m.cos(_t0)
    _t2 = ((1/2))*heading_ + ((1/2))*initial_heading_error_
    _t3 = _m.cos(_t2)
    _t4 = ((1/2))*initial_pitch_error_ + ((1/2))*pitch_
    _t5 = _m.cos(_t4)
    _t6 = _m.sin(_t0)
    _t7 = _m.sin(_t2)
    _t8 = _m.sin(_t4)
    _t9 = _t7*_t8
    _t10 = _t3*_t8
    _t11 = _t5*_t7
    _t12 = -e2_*_m.sin(latitude_)**2 + 1
    _out = _np.zeros((10,) + _batch)
    _out[0] = _t1*_t3*_t5 + _t6*_t9
    _out[1] = -_t1*_t9 + _t3*_t5*_t6
    _out[2] = _t1*_t10 + _t11*_t6
    _out[3] = _t1*_t11 - _t10*_t6
    _out[4] = initial_velocity_error_N_ + v_N0_
    _out[5] = initial_velocity_error_E_ + v_E0_
    _out[6] = initial_velocity_error_D_ + v_D0_
    _out[7] = initial_position_error_N_/(height_ + a_*(1 - e2_)/(_t12*_m.sqrt(_t12))) + latitude_
    _out[8] = initial_position_error_E_/((height_ + a_/_m.sqrt(_t12))*_m.cos(latitude_)) + longitude_
    _out[9] = height_ - initial_position_error_D_
    return _out


def initial_error_matrix(c, u, p):
    """First-order map from error sources to the initial error state.

    Parameters
    ----------
    c : array_like, shape (9, ...)
        initial navigation conditions, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (10, 33, ...)
        E: xe(0) = E w
    """
    c = _as_vector(c, 9, 'c', 'initial_error_matrix')
    u = _as_vector(u, 7, 'u', 'initial_error_matrix')
    p = _as_vector(p, 8, 'p', 'initial_error_matrix')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    height_ = c[2]
    roll_ = c[6]
    pitch_ = c[7]
    heading_ = c[8]
    a_ = p[0]
    e2_ = p[1]
    _t0 = ((1/2))*heading_
    _t1 = ((1/2))*_m.sin(_t0)
    _t2 = ((1/2))*roll_
    _t3 = _m.cos(_t2)
    _t4 = ((1/2))*pitch_
    _t5 = _m.sin(_t4)
    _t6 = _t3*_t5
    _t7 = _t1*_t6
    _t8 = _m.cos(_t4)
    _t9 = _m.sin(_t2)
    _t10 = _t8*_t9
    _t11 = _m.cos(_t0)
    _t12 = ((1/2))*_t11
    _t13 = _t10*_t12
    _t14 = -_t13 + _t7
    _t15 = _t1*_t10
    _t16 = _t12*_t6
    _t17 = _t3*_t8
    _t18 = _t1*_t17
    _t19 = _t5*_t9
    _t20 = _t12*_t19
    _t21 = _t18 - _t20
    _t22 = _t1*_t19
    _t23 = _t12*_t17 + _t22
    _t24 = -_t15 - _t16
    _t25 = -e2_*_m.sin(latitude_)**2 + 1
    _out = _np.zeros((10, 33) + _batch)
    _out[0, 24] = _t14
    _out[0, 25] = _t15 - _t16
    _out[0, 26] = -_t21
    _out[1, 24] = _t23
    _out[1, 25] = -_t18 - _t20
    _out[1, 26] = _t24
    _out[2, 24] = _t21
    _out[2, 25] = ((1/2))*_t11*_t3*_t8 - _t22
    _out[2, 26] = -_t14
    _out[3, 24] = _t24
    _out[3, 25] = -_t13 - _t7
    _out[3, 26] = _t23
    _out[4, 27] = 1
    _out[5, 28] = 1
    _out[6, 29] = 1
    _out[7, 30] = 1/(height_ + a_*(1 - e2_)/(_t25*_m.sqrt(_t25)))
    _out[8, 31] = 1/((height_ + a_/_m.sqrt(_t25))*_m.cos(latitude_))
    _out[9, 32] = -1
    return _out


def domain_margins(x, u, p):
    """Margins that must be positive for the formulas to hold (see DOMAIN).

    Parameters
    ----------
    x : array_like, shape (10, ...)
        ideal-work (true) state, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (6, ...)
        one margin per condition of DOMAIN
    """
    x = _as_vector(x, 10, 'x', 'domain_margins')
    u = _as_vector(u, 7, 'u', 'domain_margins')
    p = _as_vector(p, 8, 'p', 'domain_margins')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    q0_ = x[0]
    q1_ = x[1]
    q2_ = x[2]
    q3_ = x[3]
    lat_ = x[7]
    a_ = p[0]
    e2_ = p[1]
    gamma_e_ = p[3]
    _t0 = q1_**2
    _t1 = q2_**2
    _t2 = q0_**2 + q3_**2
    _t3 = _t0 + _t1 + _t2
    _out = _np.zeros((6,) + _batch)
    _out[0] = _m.cos(lat_)**2 - 1e-12
    _out[1] = -1e-12*_t3**2 + (2*q0_*q1_ + 2*q2_*q3_)**2 + (-_t0 - _t1 + _t2)**2
    _out[2] = _t3 - 1e-06
    _out[3] = a_
    _out[4] = 1 - e2_
    _out[5] = gamma_e_
    return _out


def initial_domain_margins(c, u, p):
    """Margins that must be positive for the initial conditions.

    Parameters
    ----------
    c : array_like, shape (9, ...)
        initial navigation conditions, SI units
    u : array_like, shape (7, ...)
        true-motion inputs, SI units
    p : array_like, shape (8, ...)
        model parameters, SI units

    Returns
    -------
    numpy.ndarray, shape (5, ...)
        one margin per condition of INITIAL_DOMAIN
    """
    c = _as_vector(c, 9, 'c', 'initial_domain_margins')
    u = _as_vector(u, 7, 'u', 'initial_domain_margins')
    p = _as_vector(p, 8, 'p', 'initial_domain_margins')
    _batch = _np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
    latitude_ = c[0]
    pitch_ = c[7]
    a_ = p[0]
    e2_ = p[1]
    gamma_e_ = p[3]
    _out = _np.zeros((5,) + _batch)
    _out[0] = _m.cos(latitude_)**2 - 1e-12
    _out[1] = _m.cos(pitch_)**2 - 1e-12
    _out[2] = a_
    _out[3] = 1 - e2_
    _out[4] = gamma_e_
    return _out


FUNCTIONS = ('ideal_rhs', 'real_rhs', 'outputs', 'state_matrix', 'source_matrix', 'output_matrix', 'second_order', 'initial_state', 'initial_real_state', 'initial_error_matrix', 'domain_margins', 'initial_domain_margins')
