# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive, step derive/transfer_functions.py)
# from ins_errors/models/north_pointing.py via ins_errors/symbolic/static_base.py.
# Edit those and run `make derive` again.

"""Closed-form static-base responses of the model 'north_pointing' (numpy, broadcasting).

responses_<variant>(t, x, u, p)[i, j, ...] is error state i at time t for a unit error source j
(SI), every other source zero. frequencies_<variant>(x, u, p) are the mode frequencies,
rad/s, in the order of MODES[<variant>]. BAKED: parameter values the closed forms
were derived for; every function refuses (ValueError) other values, times t < 0
and points outside the model's domain (a latitude at a pole, ...).

The checked way in, which builds the static-base x, u and p from a latitude:
ins_errors.numeric.closed_forms.closed_forms(model, latitude).responses(t)."""

import numpy as _np

_m = _np


def _as_vector(value, length, name, function):
    array = _np.asarray(value, dtype=float)
    if array.ndim == 0 or array.shape[0] != length:
        raise ValueError(f"{function}: argument {name} must have shape ({length}, ...), "
                         f"got {array.shape}")
    return array


def _domain_margins(x, u, p):
    """Margins of the model's domain and the static base's conditions (> 0: inside).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (6, ...)
        one margin per entry of _DOMAIN
    """
    x = _as_vector(x, 4, 'x', '_domain_margins')
    u = _as_vector(u, 3, 'u', '_domain_margins')
    p = _as_vector(p, 4, 'p', '_domain_margins')
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


def _check_arguments(function, x, u, p, t=None):
    """Refuse what the closed forms were not derived for: ValueError, one line."""
    if t is not None and not _np.all(_np.isfinite(t) & (t >= 0)):
        bad = float(t[~(_np.isfinite(t) & (t >= 0))].flat[0])
        raise ValueError(f"{function}: the closed forms hold for finite times t >= 0, "
                         f"got t = {bad!r}")
    for name, value in BAKED.items():
        given = p[_BAKED_INDEX[name]]
        wrong = ~(_np.abs(given - value) <= 1e-12 * abs(value))
        if _np.any(wrong):
            bad = float(_np.broadcast_to(given, wrong.shape)[wrong].flat[0])
            raise ValueError(f"{function}: derived for {name} = {value!r} only "
                             f"({_BAKED_MEANING[name]}), got {name} = {bad!r}")
    margins = _domain_margins(x, u, p)
    for k, message in enumerate(_DOMAIN):
        if not _np.all(margins[k] > 0):
            raise ValueError(f"{function}: {message}")


def _evaluate(function, variant, t, x, u, p):
    """The closed forms of ``variant`` at (t, x, u, p) (arguments already checked).

    The general forms, and each limit's own forms (LIMITS) at the points where the
    denominator that vanishes there is within the limit's width of zero; ValueError
    (one line) where the result is still not finite: a denominator of the forms
    vanishes (DENOMINATORS) with no limit derived for it.
    """
    general, margins, limits, denominators = _FORMS[variant]
    with _np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = general(t, x, u, p)
        if limits:
            near = _np.abs(margins(x, u, p))
            for k, (width, forms) in enumerate(limits):
                if _np.any(near[k] <= width):
                    out = _np.where(near[k] <= width, forms(t, x, u, p), out)
        if _np.all(_np.isfinite(out)):
            return out
        values = denominators(x, u, p)
    zero = [name for name, value in zip(DENOMINATORS[variant], values)
            if _np.any(value == 0) or not _np.all(_np.isfinite(value))]
    if zero:
        raise ValueError(f"{function}: the closed forms divide by {', '.join(zero)}, "
                         "zero at this point, where no limiting form is derived (e.g. a "
                         "Schuler frequency equal to the Earth rate)")
    raise ValueError(f"{function}: the closed forms overflow at this point")


def responses_full(t, x, u, p):
    """Closed-form responses of variant 'full': unit source -> error state.

    Raises ValueError (one line) for parameters other than BAKED and outside
    the model's domain (e.g. a latitude at a pole), for times t < 0, and where a
    denominator of the forms vanishes with no limiting form derived for it
    (DENOMINATORS, LIMITS).

    Parameters
    ----------
    t : array_like, shape (1, ...)
        time since the start, s (shape (1, ...)), finite, >= 0
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        error state i for unit source j
    """
    t = _as_vector(t, 1, 't', 'responses_full')
    x = _as_vector(x, 4, 'x', 'responses_full')
    u = _as_vector(u, 3, 'u', 'responses_full')
    p = _as_vector(p, 4, 'p', 'responses_full')
    _check_arguments('responses_full', x, u, p, t)
    return _evaluate('responses_full', 'full', t, x, u, p)


def _forms_full(t, x, u, p):
    """The general closed forms of variant 'full' (unchecked: see responses_full).

    Parameters
    ----------
    t : array_like, shape (1, ...)
        time since the start, s (shape (1, ...)), finite, >= 0
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        error state i for unit source j
    """
    t = _as_vector(t, 1, 't', '_forms_full')
    x = _as_vector(x, 4, 'x', '_forms_full')
    u = _as_vector(u, 3, 'u', '_forms_full')
    p = _as_vector(p, 4, 'p', '_forms_full')
    _batch = _np.broadcast_shapes(t.shape[1:], x.shape[1:], u.shape[1:], p.shape[1:])
    t_ = t[0]
    phi_ = x[2]
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _t0 = 1/R_
    _t1 = _t0*g_
    _t2 = U_**2
    _t3 = _m.sin(phi_)
    _t4 = _t3**2
    _t5 = _t2*_t4
    _t6 = _t1 + _t5
    _t7 = _m.sqrt(_t6)
    _t8 = U_*_t3
    _t9 = _t7 + _t8
    _t10 = _t9*t_
    _t11 = _m.sin(_t10)
    _t12 = 1/_t7
    _t13 = ((1/2))*_t12
    _t14 = _t11*_t13
    _t15 = _t14*_t9
    _t16 = 2*_t8
    _t17 = _t16 + _t7
    _t18 = -_t7
    _t19 = _t18 + _t8
    _t20 = _t16*_t7
    _t21 = _m.cos(phi_)
    _t22 = _t21**2
    _t23 = -_t2*_t22
    _t24 = _t23 + _t6
    _t25 = 1/(-_t20 - _t24)
    _t26 = _t19*_t25
    _t27 = _t17*_t26
    _t28 = _t15*_t27
    _t29 = R_*_t3
    _t30 = U_*t_
    _t31 = _m.sin(_t30)
    _t32 = 1/(_t20 - _t24)
    _t33 = _t25*_t32
    _t34 = _t31*_t33
    _t35 = _t2*_t22
    _t36 = -_t1
    _t37 = 3*_t5
    _t38 = _t36 + _t37
    _t39 = 3*_t35 + _t38
    _t40 = _t19*_t9
    _t41 = _t39*_t40
    _t42 = _t34*_t41
    _t43 = _t19**2
    _t44 = -_t19
    _t45 = 1/_t44
    _t46 = _t44*t_
    _t47 = _m.sin(_t46)
    _t48 = _t13*_t45*_t47
    _t49 = _t43*_t48
    _t50 = _t16 + _t18
    _t51 = _t32*_t9
    _t52 = _t50*_t51
    _t53 = _t49*_t52
    _t54 = R_*_t53
    _t55 = _t35 + _t5
    _t56 = 1/_t55
    _t57 = R_*_t56
    _t58 = _t7*_t8
    _t59 = 3*_t58
    _t60 = _t1 + _t23 + _t37
    _t61 = -_t59 - _t60
    _t62 = _m.cos(_t10)
    _t63 = _t13*_t62
    _t64 = _t26*_t63
    _t65 = _t61*_t64
    _t66 = _t59 - _t60
    _t67 = _m.cos(_t46)
    _t68 = _t33*_m.cos(_t30)
    _t69 = _t41*_t68
    _t70 = _t5*_t69
    _t71 = _t2*_t56
    _t72 = _t21*_t71
    _t73 = _t29*_t72
    _t74 = U_*_t21
    _t75 = _t13*_t67
    _t76 = _t51*_t75
    _t77 = _t50*_t76
    _t78 = R_*_t77
    _t79 = _t17*_t64
    _t80 = _t74*_t79
    _t81 = _t19*_t48
    _t82 = _t14 - _t81
    _t83 = -_t63 + _t75
    _t84 = _t19*_t75
    _t85 = ((1/2))*_t12*_t62*_t9 - _t84
    _t86 = _t15 - _t49
    _t87 = 2*_t5
    _t88 = _t35 + _t87
    _t89 = -_t58 + _t88
    _t90 = _t51*_t84
    _t91 = R_*_t90
    _t92 = _t63*_t9
    _t93 = _t58 + _t88
    _t94 = R_*_t26
    _t95 = R_*_t69*_t8
    _t96 = _t9**2
    _t97 = _t61*_t94
    _t98 = _t51*_t66
    _t99 = R_*_t49
    _t100 = U_*_t4
    _t101 = R_*_t42
    _t102 = _t21*_t8
    _t103 = _t40*(_t35 + _t38)
    _t104 = _t103*_t68
    _t105 = R_*_t104
    _t106 = _t50*_t90
    _t107 = R_*_t106
    _t108 = _t27*_t92
    _t109 = _t14*_t26
    _t110 = _t109*_t61
    _t111 = _t103*_t34
    _t112 = _t81*_t98
    _t113 = _t111*_t21
    _t114 = _t52*_t81
    _t115 = _t114*_t74
    _t116 = _t51*_t89
    _t117 = 1/U_
    _t118 = _t117*_t34
    _t119 = _t103*_t118
    _t120 = R_*_t119*_t55
    _t121 = _t48*_t52
    _t122 = _t109*_t17
    _t123 = 2*_t35
    _t124 = _t56*_t8
    _t125 = 1/_t9
    _t126 = 1/_t19
    _t127 = _t125*_t126
    _t128 = _t66*_t76
    _t129 = _t125*_t65 - _t126*_t128
    _t130 = _t127*_t56
    _t131 = _t126*_t74*_t77
    _t132 = _t125*_t80
    _t133 = _t56*_t74
    _t134 = _t0*_t125
    _t135 = _t134*_t14
    _t136 = -_t0*_t48 + _t135
    _t137 = _t126*_t134
    _t138 = _t134*_t63
    _t139 = -(1/2)*_t0*_t12*_t126*_t67 + _t137 + _t138
    _t140 = -_t139
    _t141 = _t0*_t75
    _t142 = -(1/2)*_t0*_t12*_t62 + _t141
    _t143 = _t0*_t14
    _t144 = _t0*_t81
    _t145 = _t143 - _t144
    _t146 = _t76*_t89
    _t147 = _t64*_t93
    _t148 = _t122*_t74
    _t149 = 1/_t21
    _t150 = _t110*_t125
    _t151 = _t149*_t56
    _t152 = _t3*_t71
    _t153 = _t122*_t125
    _t154 = _t137*_t149
    _t155 = _t138*_t149
    _t156 = _t135*_t149
    _t157 = _t143*_t149
    _t158 = _t141*_t149
    _t159 = _t0*_t149*_t63
    _t160 = _t109*_t93
    _t161 = _t149*_t3
    _t162 = _t161*_t42
    _t163 = _t116*_t81
    _t164 = U_**4
    _t165 = _t21**4
    _t166 = 4*_t164*_t3**4
    _t167 = _t164*_t22*_t4
    _t168 = _t164*_t165 - _t166 - _t167 + _t2*_t4*_t6 - _t35*_t6
    _t169 = _t168*_t34
    _t170 = 2*U_**3*_t130
    _t171 = _t168*_t68
    _t172 = -_t136
    _t173 = _t1 + _t35 - _t37
    _t174 = _t173*_t68
    _t175 = _t173*_t34
    _t176 = _t175*_t3*_t55
    _t177 = _t117*_t149
    _t178 = -_t123*_t6 + _t164*_t165 + _t166 - _t167 - 5*_t5*_t6 + _t6**2
    _t179 = _t178*_t68
    _t180 = _t178*_t34
    _t181 = _t149*_t180*_t55/_t2
    _out = _np.zeros((7, 12) + _batch)
    _out[0, 0] = -R_*_t28 + _t29*_t42 + _t54
    _out[0, 1] = ((1/2))*R_*_t12*_t32*_t66*_t67*_t9 - R_*_t65 - _t35*_t57 - _t57*_t70
    _out[0, 2] = -R_*_t80 + _t69*_t73 - _t73 + _t74*_t78
    _out[0, 3] = _t82
    _out[0, 4] = _t83
    _out[0, 5] = _t85
    _out[0, 6] = _t86
    _out[0, 7] = _t89*_t91 - _t92*_t93*_t94 + _t95
    _out[0, 9] = -R_*_t79*_t96 + _t43*_t78 + _t95
    _out[0, 10] = _t100*_t101 + _t15*_t97 - _t98*_t99
    _out[0, 11] = ((1/2))*R_*U_*_t11*_t12*_t17*_t19*_t21*_t25*_t9 - _t101*_t102 - _t54*_t74
    _out[1, 0] = -R_*_t108 + _t105 + _t107
    _out[1, 1] = R_*_t110 - R_*_t112 + _t111*_t29
    _out[1, 2] = ((1/2))*R_*U_*_t11*_t12*_t17*_t19*_t21*_t25 - R_*_t113 - R_*_t115
    _out[1, 3] = -_t83
    _out[1, 4] = _t82
    _out[1, 5] = -_t86
    _out[1, 6] = _t85
    _out[1, 7] = ((1/2))*R_*_t11*_t12*_t19*_t25*_t9*_t93 - _t116*_t99 - _t120
    _out[1, 9] = ((1/2))*R_*_t11*_t12*_t17*_t19*_t25*_t96 - R_*_t121*_t19**3 - _t120
    _out[1, 10] = _t105*_t8 - _t66*_t91 + _t92*_t97
    _out[1, 11] = ((1/2))*R_*U_*_t12*_t17*_t19*_t21*_t25*_t62*_t9 - _t105*_t74 - _t107*_t74
    _out[2, 0] = _t114 + _t119 - _t122
    _out[2, 1] = -_t104*_t124 - _t124*_t127*(_t1 + _t123) - _t129
    _out[2, 2] = _t104*_t133 - _t130*_t74*(_t36 + _t87) + _t131 - _t132
    _out[2, 3] = _t136
    _out[2, 4] = _t140
    _out[2, 5] = -_t142
    _out[2, 6] = _t145
    _out[2, 7] = _t104 + _t146 - _t147
    _out[2, 9] = _t104 + _t106 - _t108
    _out[2, 10] = _t110 + _t111*_t3 - _t112
    _out[2, 11] = -_t113 - _t115 + _t148
    _out[3, 0] = U_*_t149*_t3*_t56 + ((1/2))*_t12*_t149*_t17*_t19*_t25*_t62 - _t124*_t149*_t69 - _t149*_t77
    _out[3, 1] = -_t100*_t151*_t42 + ((1/2))*_t12*_t149*_t32*_t45*_t47*_t66*_t9 - _t149*_t150 - _t72*t_
    _out[3, 2] = ((1/2))*U_*_t12*_t32*_t45*_t47*_t50*_t9 - U_*_t153 + U_*_t19*_t25*_t3*_t31*_t32*_t39*_t56*_t9 - _t152*t_
    _out[3, 3] = ((1/2))*_t0*_t12*_t126*_t149*_t67 - _t154 - _t155
    _out[3, 4] = ((1/2))*_t0*_t12*_t149*_t45*_t47 - _t156
    _out[3, 5] = -_t144*_t149 + _t157
    _out[3, 6] = _t158 - _t159
    _out[3, 7] = -_t149*_t160 + _t149*_t163 + _t162
    _out[3, 8] = 1
    _out[3, 9] = -_t149*_t28 + _t149*_t53 + _t162
    _out[3, 10] = ((1/2))*_t12*_t149*_t32*_t66*_t67*_t9 - _t149*_t65 - _t151*_t70 - _t72
    _out[3, 11] = U_*_t77 - U_*_t79 + _t152*_t69 - _t152
    _out[4, 0] = -_t114 + _t117*_t169 + _t122
    _out[4, 1] = -_t124*_t171 + _t129 + _t170*_t22*_t3
    _out[4, 2] = -_t131 + _t132 + _t133*_t171 + _t170*_t21*_t4
    _out[4, 3] = _t172
    _out[4, 4] = _t139
    _out[4, 5] = _t142
    _out[4, 6] = -_t145
    _out[4, 7] = -_t146 + _t147 + _t171
    _out[4, 9] = -_t106 + _t108 + _t171
    _out[4, 10] = -_t110 + _t112 + _t169*_t3
    _out[4, 11] = _t115 - _t148 - _t169*_t21
    _out[5, 0] = _t174*_t8 - _t77 + _t79
    _out[5, 1] = _t100*_t175 - _t150 + _t48*_t98
    _out[5, 2] = ((1/2))*U_*_t12*_t21*_t32*_t45*_t47*_t50*_t9 - _t102*_t175 - _t125*_t148
    _out[5, 3] = _t140
    _out[5, 4] = _t172
    _out[5, 5] = _t145
    _out[5, 6] = _t142
    _out[5, 7] = ((1/2))*_t12*_t19*_t32*_t45*_t47*_t89*_t9 - _t160 - _t176
    _out[5, 9] = ((1/2))*_t12*_t32*_t43*_t45*_t47*_t50*_t9 - _t176 - _t28
    _out[5, 10] = _t128 + _t174*_t5 - _t65
    _out[5, 11] = ((1/2))*U_*_t12*_t21*_t32*_t50*_t67*_t9 - _t174*_t2*_t21*_t3 - _t80
    _out[6, 0] = -_t161*_t77 + _t161*_t79 - _t177*_t179 + _t177
    _out[6, 1] = ((1/2))*_t12*_t149*_t3*_t32*_t45*_t47*_t66*_t9 - _t150*_t161 - _t177*_t180*_t3
    _out[6, 2] = _t118*_t178 + _t121*_t8 - _t153*_t8
    _out[6, 3] = ((1/2))*_t0*_t12*_t126*_t149*_t3*_t67 - _t154*_t3 - _t155*_t3
    _out[6, 4] = ((1/2))*_t0*_t12*_t149*_t3*_t45*_t47 - _t156*_t3
    _out[6, 5] = -_t144*_t161 + _t157*_t3
    _out[6, 6] = _t158*_t3 - _t159*_t3
    _out[6, 7] = -_t160*_t161 + _t161*_t163 + _t181
    _out[6, 9] = -_t161*_t28 + _t161*_t53 + _t181
    _out[6, 10] = ((1/2))*_t12*_t149*_t3*_t32*_t66*_t67*_t9 - _t161*_t179 - _t161*_t65
    _out[6, 11] = _t179 + _t77*_t8 - _t79*_t8
    return _out


def _denominators_full(x, u, p):
    """The factors the closed forms of variant 'full' (and its limits') divide by.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (11, ...)
        one value per entry of DENOMINATORS[variant]
    """
    x = _as_vector(x, 4, 'x', '_denominators_full')
    u = _as_vector(u, 3, 'u', '_denominators_full')
    p = _as_vector(p, 4, 'p', '_denominators_full')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    phi_ = x[2]
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.cos(phi_)
    _t1 = U_**2
    _t2 = _m.sin(phi_)
    _t3 = _t1*_t2**2
    _t4 = _t3 + g_/R_
    _t5 = _m.sqrt(_t4)
    _t6 = U_*_t2
    _t7 = -_t5 + _t6
    _t8 = _t5 + _t6
    _t9 = _t0**2
    _t10 = 2*_t5*_t6
    _t11 = -_t1*_t9 + _t4
    _out = _np.zeros((11,) + _batch)
    _out[0] = U_*_t0
    _out[1] = R_
    _out[2] = U_
    _out[3] = _t5
    _out[4] = -_t7
    _out[5] = _t8
    _out[6] = _t1*_t9 + _t3
    _out[7] = _t7
    _out[8] = _t8
    _out[9] = -_t10 - _t11
    _out[10] = _t10 - _t11
    return _out


def frequencies_full(x, u, p):
    """Mode frequencies of variant 'full', rad/s.

    Raises ValueError (one line) for parameters other than BAKED and outside
    the model's domain (e.g. a latitude at a pole).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (3, ...)
        one frequency per entry of MODES
    """
    x = _as_vector(x, 4, 'x', 'frequencies_full')
    u = _as_vector(u, 3, 'u', 'frequencies_full')
    p = _as_vector(p, 4, 'p', 'frequencies_full')
    _check_arguments('frequencies_full', x, u, p, None)
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    phi_ = x[2]
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.sin(phi_)
    _t1 = _m.sqrt(U_**2*_t0**2 + g_/R_)
    _t2 = U_*_t0
    _out = _np.zeros((3,) + _batch)
    _out[0] = U_
    _out[1] = _t1 - _t2
    _out[2] = _t1 + _t2
    return _out


def responses_report_reduced(t, x, u, p):
    """Closed-form responses of variant 'report_reduced': unit source -> error state.

    Raises ValueError (one line) for parameters other than BAKED and outside
    the model's domain (e.g. a latitude at a pole), for times t < 0, and where a
    denominator of the forms vanishes with no limiting form derived for it
    (DENOMINATORS, LIMITS).

    Parameters
    ----------
    t : array_like, shape (1, ...)
        time since the start, s (shape (1, ...)), finite, >= 0
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        error state i for unit source j
    """
    t = _as_vector(t, 1, 't', 'responses_report_reduced')
    x = _as_vector(x, 4, 'x', 'responses_report_reduced')
    u = _as_vector(u, 3, 'u', 'responses_report_reduced')
    p = _as_vector(p, 4, 'p', 'responses_report_reduced')
    _check_arguments('responses_report_reduced', x, u, p, t)
    return _evaluate('responses_report_reduced', 'report_reduced', t, x, u, p)


def _forms_report_reduced(t, x, u, p):
    """The general closed forms of variant 'report_reduced' (unchecked: see responses_report_reduced).

    Parameters
    ----------
    t : array_like, shape (1, ...)
        time since the start, s (shape (1, ...)), finite, >= 0
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        error state i for unit source j
    """
    t = _as_vector(t, 1, 't', '_forms_report_reduced')
    x = _as_vector(x, 4, 'x', '_forms_report_reduced')
    u = _as_vector(u, 3, 'u', '_forms_report_reduced')
    p = _as_vector(p, 4, 'p', '_forms_report_reduced')
    _batch = _np.broadcast_shapes(t.shape[1:], x.shape[1:], u.shape[1:], p.shape[1:])
    t_ = t[0]
    phi_ = x[2]
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.sin(phi_)
    _t1 = U_*t_
    _t2 = _m.sin(_t1)
    _t3 = 1/R_
    _t4 = _t3*g_
    _t5 = U_**2
    _t6 = _m.cos(phi_)
    _t7 = _t5*_t6**2
    _t8 = _t0**2
    _t9 = _t5*_t8
    _t10 = _t7 + _t9
    _t11 = 1/(_t10 - _t4)
    _t12 = _t11*g_
    _t13 = _t12*_t2
    _t14 = U_*_t0
    _t15 = _m.sqrt(_t4)
    _t16 = _t15*t_
    _t17 = _m.sin(_t16)
    _t18 = _t11*_t17
    _t19 = _t15*_t18
    _t20 = R_*_t19
    _t21 = -_t0*_t13 + _t14*_t20
    _t22 = 1/_t10
    _t23 = _m.cos(_t16)
    _t24 = _t11*_t23
    _t25 = U_*_t6
    _t26 = _t15 + _t25
    _t27 = -_t15 + _t25
    _t28 = _t26*_t27
    _t29 = _t24*_t28
    _t30 = _m.cos(_t1)
    _t31 = _t12*_t30
    _t32 = _t22*_t9
    _t33 = _t0*_t22
    _t34 = _t5*_t6
    _t35 = R_*_t34
    _t36 = 1/_t15
    _t37 = _t17*_t36
    _t38 = U_*_t0*_t11*_t23*g_ - _t14*_t31
    _t39 = U_*_t8
    _t40 = 1/U_
    _t41 = -_t10*_t11*_t2*_t40*g_
    _t42 = _t11*_t2
    _t43 = _t4*_t42
    _t44 = U_*_t33
    _t45 = _t14*_t24
    _t46 = -_t45
    _t47 = _t11*_t30
    _t48 = _t4*_t47
    _t49 = _t22*_t25
    _t50 = -_t24*_t25
    _t51 = 1/g_
    _t52 = _t23*_t51
    _t53 = -_t51 + _t52
    _t54 = -_t53
    _t55 = _t3*_t37
    _t56 = _t10*_t11
    _t57 = _t23*_t56
    _t58 = -_t24*_t4
    _t59 = _t14*_t19
    _t60 = _t0*_t43
    _t61 = _t19*_t25
    _t62 = 1/_t6
    _t63 = _t44*_t62
    _t64 = _t22*_t34
    _t65 = _t11*_t37
    _t66 = _t28*_t65
    _t67 = _t62*_t66
    _t68 = _t39*_t42
    _t69 = _t33*_t5
    _t70 = _t52*_t62
    _t71 = _t55*_t62
    _t72 = _t59*_t62 - _t60*_t62
    _t73 = _t14*_t47 + _t46
    _t74 = _t30*_t56
    _t75 = -_t0*_t10*_t11*_t2 + _t59
    _t76 = _t2*_t56
    _t77 = _t0*_t42
    _t78 = _t0*_t34
    _t79 = _t39*_t62
    _t80 = _t40*_t62
    _t81 = _t28*_t47
    _t82 = _t19*_t79 + _t28*_t62*_t76/_t5
    _out = _np.zeros((7, 12) + _batch)
    _out[0, 0] = _t21
    _out[0, 1] = -R_*_t22*_t7 + R_*_t29 + _t31*_t32
    _out[0, 2] = R_*_t0*_t11*_t23*_t5*_t6 - _t31*_t33*_t34 - _t33*_t35
    _out[0, 3] = _t37
    _out[0, 5] = _t23
    _out[0, 7] = _t38
    _out[0, 9] = _t38
    _out[0, 10] = -_t13*_t39 - _t20*_t28
    _out[0, 11] = U_*_t0*_t11*_t2*_t6*g_ - _t0*_t19*_t35
    _out[1, 0] = _t11*_t23*g_ - _t31
    _out[1, 1] = _t21
    _out[1, 2] = _t11*_t2*_t6*g_ - _t20*_t25
    _out[1, 4] = _t37
    _out[1, 6] = _t23
    _out[1, 7] = -_t10*_t20 - _t41
    _out[1, 9] = -R_*_t18*(_t4*_m.sqrt(_t4)) - _t41
    _out[1, 10] = _t38
    _out[1, 11] = -_t12*_t23*_t25 + _t25*_t31
    _out[2, 0] = _t19 - _t40*_t43
    _out[2, 1] = _t44*_t48 + _t44 + _t46
    _out[2, 2] = -_t48*_t49 - _t49 - _t50
    _out[2, 4] = _t54
    _out[2, 6] = _t55
    _out[2, 7] = -_t48 + _t57
    _out[2, 9] = -_t48 - _t58
    _out[2, 10] = _t59 - _t60
    _out[2, 11] = _t11*_t2*_t3*_t6*g_ - _t61
    _out[3, 0] = -_t45*_t62 + _t48*_t63 + _t63
    _out[3, 1] = _t22*_t4*_t62*_t68 - _t64*t_ + _t67
    _out[3, 2] = _t0*_t11*_t17*_t36*_t5 - _t43*_t44 - _t69*t_
    _out[3, 3] = _t51*_t62 - _t70
    _out[3, 5] = _t71
    _out[3, 7] = _t72
    _out[3, 8] = 1
    _out[3, 9] = _t72
    _out[3, 10] = _t29*_t62 + _t32*_t48*_t62 - _t64
    _out[3, 11] = _t0*_t11*_t23*_t5 - _t48*_t69 - _t69
    _out[4, 0] = _t10*_t11*_t2*_t40 - _t19
    _out[4, 1] = -_t73
    _out[4, 2] = _t25*_t47 + _t50
    _out[4, 4] = _t53
    _out[4, 6] = -_t55
    _out[4, 7] = -_t57 + _t74
    _out[4, 9] = _t58 + _t74
    _out[4, 10] = -_t75
    _out[4, 11] = -_t6*_t76 + _t61
    _out[5, 0] = _t73
    _out[5, 1] = _t66 + _t68
    _out[5, 2] = -_t25*_t77 + _t65*_t78
    _out[5, 3] = _t54
    _out[5, 5] = _t55
    _out[5, 7] = _t75
    _out[5, 9] = _t75
    _out[5, 10] = _t29 + _t47*_t9
    _out[5, 11] = _t0*_t11*_t23*_t5*_t6 - _t47*_t78
    _out[6, 0] = -_t24*_t79 + _t40*_t62 - _t80*_t81
    _out[6, 1] = _t0*_t67 - _t28*_t77*_t80
    _out[6, 2] = _t28*_t40*_t42 + _t65*_t9
    _out[6, 3] = _t0*_t51*_t62 - _t0*_t70
    _out[6, 5] = _t0*_t71
    _out[6, 7] = _t82
    _out[6, 9] = _t82
    _out[6, 10] = _t0*_t11*_t23*_t26*_t27*_t62 - _t0*_t62*_t81
    _out[6, 11] = _t24*_t9 + _t81
    return _out


def _denominators_report_reduced(x, u, p):
    """The factors the closed forms of variant 'report_reduced' (and its limits') divide by.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (6, ...)
        one value per entry of DENOMINATORS[variant]
    """
    x = _as_vector(x, 4, 'x', '_denominators_report_reduced')
    u = _as_vector(u, 3, 'u', '_denominators_report_reduced')
    p = _as_vector(p, 4, 'p', '_denominators_report_reduced')
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    phi_ = x[2]
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _t0 = _m.cos(phi_)
    _t1 = g_/R_
    _t2 = U_**2
    _t3 = _t0**2*_t2 + _t2*_m.sin(phi_)**2
    _out = _np.zeros((6,) + _batch)
    _out[0] = U_*_t0
    _out[1] = R_
    _out[2] = U_
    _out[3] = _m.sqrt(_t1)
    _out[4] = _t3
    _out[5] = -_t1 + _t3
    return _out


def frequencies_report_reduced(x, u, p):
    """Mode frequencies of variant 'report_reduced', rad/s.

    Raises ValueError (one line) for parameters other than BAKED and outside
    the model's domain (e.g. a latitude at a pole).

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units; those in BAKED must have their BAKED values

    Returns
    -------
    numpy.ndarray, shape (2, ...)
        one frequency per entry of MODES
    """
    x = _as_vector(x, 4, 'x', 'frequencies_report_reduced')
    u = _as_vector(u, 3, 'u', 'frequencies_report_reduced')
    p = _as_vector(p, 4, 'p', 'frequencies_report_reduced')
    _check_arguments('frequencies_report_reduced', x, u, p, None)
    _batch = _np.broadcast_shapes(x.shape[1:], u.shape[1:], p.shape[1:])
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _out = _np.zeros((2,) + _batch)
    _out[0] = U_
    _out[1] = _m.sqrt(g_/R_)
    return _out


VARIANTS = ('full', 'report_reduced')
MODES = {'full': ('Earth', 'Schuler − Foucault', 'Schuler + Foucault'), 'report_reduced': ('Earth', 'Schuler')}
SOURCES = ('gyro_drift_east', 'gyro_drift_north', 'gyro_drift_up', 'accel_bias_east', 'accel_bias_north', 'initial_velocity_error_east', 'initial_velocity_error_north', 'initial_latitude_error', 'initial_longitude_error', 'initial_tilt_east', 'initial_tilt_north', 'initial_azimuth_error')
BAKED = {'ecc2': 0.0}
ERROR_STATES = ('delta_v_E', 'delta_v_N', 'delta_latitude', 'delta_longitude', 'alpha_E', 'alpha_N', 'alpha_U')
_BAKED_INDEX = {'ecc2': 1}
_BAKED_MEANING = {'ecc2': 'a spherical Earth'}
_DOMAIN = ('latitude at or beyond ±90°: the formulas divide by cos φ (tan φ, sec φ)', 'Earth radius R must be positive', 'gravity g must be positive', 'eccentricity squared ecc2 must be below 1', 'eccentricity squared ecc2 must not be negative', "R + h must be positive: height below the Earth's centre")
DENOMINATORS = {'full': ('Omega_N = U*cos(phi)', 'R', 'U', 'omega_bar = sqrt(U**2*sin(phi)**2 + g/R)', 'omega_minus = -U*sin(phi) + sqrt(U**2*sin(phi)**2 + g/R)', 'omega_plus = U*sin(phi) + sqrt(U**2*sin(phi)**2 + g/R)', 'Omega_N**2 + Omega_U**2 = U**2*sin(phi)**2 + U**2*cos(phi)**2', 'Omega_U - omega_bar = U*sin(phi) - sqrt(U**2*sin(phi)**2 + g/R)', 'Omega_U + omega_bar = U*sin(phi) + sqrt(U**2*sin(phi)**2 + g/R)', 'Omega_N**2 - 2*Omega_U*omega_bar - omega_bar**2 = -U**2*sin(phi)**2 + U**2*cos(phi)**2 - 2*U*sqrt(U**2*sin(phi)**2 + g/R)*sin(phi) - g/R', 'Omega_N**2 + 2*Omega_U*omega_bar - omega_bar**2 = -U**2*sin(phi)**2 + U**2*cos(phi)**2 + 2*U*sqrt(U**2*sin(phi)**2 + g/R)*sin(phi) - g/R'), 'report_reduced': ('Omega_N = U*cos(phi)', 'R', 'U', 'omega_s = sqrt(g/R)', 'Omega_N**2 + Omega_U**2 = U**2*sin(phi)**2 + U**2*cos(phi)**2', 'Omega_N**2 + Omega_U**2 - omega_s**2 = U**2*sin(phi)**2 + U**2*cos(phi)**2 - g/R')}
LIMITS = {'full': {}, 'report_reduced': {}}
_FORMS = {
    'full': (_forms_full, None, (), _denominators_full),
    'report_reduced': (_forms_report_reduced, None, (), _denominators_report_reduced),
}
