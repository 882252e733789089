# GENERATED FILE: do not edit by hand.
# Written by `make derive` (python -m derive, step derive/transfer_functions.py)
# from ins_errors/models/north_pointing.py via ins_errors/symbolic/static_base.py.
# Edit those and run `make derive` again.

"""Closed-form static-base responses of the model 'north_pointing' (numpy, broadcasting).

responses_<variant>(t, x, u, p)[i, j, ...] is error state i at time t for a unit error source j
(SI), every other source zero. frequencies_<variant>(x, u, p) are the mode frequencies,
rad/s, in the order of MODES[<variant>]. BAKED: parameter values the closed forms
were derived for."""

import numpy as _np

_m = _np


def _as_vector(value, length, name, function):
    array = _np.asarray(value, dtype=float)
    if array.ndim == 0 or array.shape[0] != length:
        raise ValueError(f"{function}: argument {name} must have shape ({length}, ...), "
                         f"got {array.shape}")
    return array


def responses_full(t, x, u, p):
    """Closed-form responses of variant 'full': unit source -> error state.

    Parameters
    ----------
    t : array_like, shape (1, ...)
        time since the start, s (shape (1, ...))
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units (see BAKED)

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        error state i for unit source j
    """
    t = _as_vector(t, 1, 't', 'responses_full')
    x = _as_vector(x, 4, 'x', 'responses_full')
    u = _as_vector(u, 3, 'u', 'responses_full')
    p = _as_vector(p, 4, 'p', 'responses_full')
    _batch = _np.broadcast_shapes(t.shape[1:], x.shape[1:], u.shape[1:], p.shape[1:])
    t_ = t[0]
    phi_ = x[2]
    R_ = p[0]
    U_ = p[2]
    g_ = p[3]
    _t0 = U_**5
    _t1 = _m.sin(phi_)
    _t2 = _t1**3
    _t3 = _m.cos(phi_)
    _t4 = _t3**2
    _t5 = _t2*_t4
    _t6 = _t0*_t5
    _t7 = R_*_t6
    _t8 = U_**3
    _t9 = _t4*_t8
    _t10 = _t1*_t9
    _t11 = 1/R_
    _t12 = _t11*g_
    _t13 = U_**2
    _t14 = _t1**2
    _t15 = _t13*_t14
    _t16 = _t12 + _t15
    _t17 = R_*_t16
    _t18 = _t10*_t17
    _t19 = _t1**5
    _t20 = _t0*_t19
    _t21 = 4*_t20
    _t22 = R_*_t21
    _t23 = U_*_t1
    _t24 = _t16**2
    _t25 = R_*_t24
    _t26 = _t23*_t25
    _t27 = _t2*_t8
    _t28 = _t16*_t27
    _t29 = 5*_t28
    _t30 = -R_*_t29 + _t22 + _t26
    _t31 = -3*_t18 + _t30 + 3*_t7
    _t32 = _t15*_t16
    _t33 = 4*_t32
    _t34 = -_t33
    _t35 = U_**4
    _t36 = _t3**4
    _t37 = _t35*_t36
    _t38 = _t13*_t4
    _t39 = _t16*_t38
    _t40 = _t24 + _t37 - 2*_t39
    _t41 = 1/(_t34 + _t40)
    _t42 = 1/U_
    _t43 = U_*t_
    _t44 = _t42*_m.sin(_t43)
    _t45 = _t41*_t44
    _t46 = _t1**4
    _t47 = _t35*_t46
    _t48 = R_*_t47
    _t49 = _m.sqrt(_t16)
    _t50 = 6*_t49
    _t51 = _t48*_t50
    _t52 = _t16**((3/2))
    _t53 = 6*_t52
    _t54 = _t15*_t53
    _t55 = R_*_t54
    _t56 = 2*_t27
    _t57 = -4*R_*_t0*_t19 + _t17*_t56 + 2*_t26
    _t58 = -_t51 + _t55 + _t57
    _t59 = -_t58
    _t60 = 4*_t23
    _t61 = _t52*_t60
    _t62 = 8*_t32
    _t63 = 4*_t49
    _t64 = _t10*_t63
    _t65 = 1/(_t61 + _t62 - _t64)
    _t66 = _t23 + _t49
    _t67 = _t66*t_
    _t68 = _m.sin(_t67)/_t66
    _t69 = _t65*_t68
    _t70 = _t51 - _t55 + _t57
    _t71 = -_t70
    _t72 = 1/(-_t61 + _t62 + _t64)
    _t73 = -_t23 + _t49
    _t74 = 1/_t73
    _t75 = _t73*t_
    _t76 = _m.sin(_t75)
    _t77 = _t74*_t76
    _t78 = _t72*_t77
    _t79 = U_**6
    _t80 = _t1**6
    _t81 = _t79*_t80
    _t82 = _t4*_t46
    _t83 = _t79*_t82
    _t84 = 2*_t16
    _t85 = _t47*_t84
    _t86 = _t35*_t4
    _t87 = _t14*_t86
    _t88 = -_t84*_t87
    _t89 = _t15*_t24
    _t90 = _t24*_t38 + _t89
    _t91 = _t81 + _t83 - _t85 + _t88 + _t90
    _t92 = 1/_t91
    _t93 = _t25*_t38
    _t94 = R_*_t83
    _t95 = R_*_t87
    _t96 = 3*_t16
    _t97 = 4*_t81
    _t98 = R_*_t97
    _t99 = _t15*_t25
    _t100 = 5*_t16
    _t101 = -_t100*_t48 + _t98 + _t99
    _t102 = _t101 + 3*_t94 - _t95*_t96
    _t103 = 4*_t47
    _t104 = _t103*_t16
    _t105 = -_t104
    _t106 = _t14*_t36*_t79
    _t107 = _t3**6*_t79 - _t37*_t84 + _t90
    _t108 = 1/(-_t105 - _t106 - _t107 + 6*_t14*_t16*_t35*_t4)
    _t109 = _m.cos(_t43)
    _t110 = _t108*_t109
    _t111 = _t27*_t52
    _t112 = 8*R_*_t111
    _t113 = _t16**((5/2))
    _t114 = 2*_t23
    _t115 = R_*_t113*_t114
    _t116 = 10*_t49
    _t117 = R_*_t116*_t20
    _t118 = R_*_t104 + _t98 - 8*_t99
    _t119 = -_t112 - _t115 + _t117 + _t118
    _t120 = 2*_t49
    _t121 = _t120*_t7
    _t122 = 2*_t52
    _t123 = R_*_t10*_t122
    _t124 = _t84*_t95 - 2*_t94
    _t125 = -_t121 + _t123 + _t124
    _t126 = _t119 + _t125
    _t127 = _t113*_t60
    _t128 = 20*_t111
    _t129 = 4*_t52
    _t130 = _t10*_t129
    _t131 = _t6*_t63
    _t132 = _t16*_t47
    _t133 = 8*_t132 - 8*_t14*_t16*_t35*_t4 + 16*_t89
    _t134 = 1/(-_t127 - _t128 + _t130 + _t131 - _t133)
    _t135 = _m.cos(_t67)
    _t136 = _t134*_t135
    _t137 = _t112 + _t115 - _t117 + _t118
    _t138 = _t121 - _t123 + _t124
    _t139 = _t137 + _t138
    _t140 = 1/(_t127 + _t128 - _t130 - _t131 - _t133)
    _t141 = _m.cos(_t75)
    _t142 = _t140*_t141
    _t143 = _t19*_t79
    _t144 = R_*_t3
    _t145 = _t1*_t13
    _t146 = _t145*_t3
    _t147 = _t146*_t25
    _t148 = _t3**3
    _t149 = _t148*_t2*_t79
    _t150 = 4*_t143
    _t151 = _t144*_t150
    _t152 = 3*R_*_t1*_t148*_t16*_t35 - 3*R_*_t149 + 5*R_*_t16*_t2*_t3*_t35 - _t147 - _t151
    _t153 = _t0*_t46
    _t154 = _t153*_t50
    _t155 = _t144*_t154
    _t156 = _t14*_t8
    _t157 = _t156*_t53
    _t158 = _t144*_t157
    _t159 = 2*_t145
    _t160 = _t159*_t3
    _t161 = _t2*_t35
    _t162 = _t161*_t84
    _t163 = _t144*_t162 - _t151 + _t160*_t25
    _t164 = -_t155 + _t158 + _t163
    _t165 = _t155 - _t158 + _t163
    _t166 = 1/_t49
    _t167 = 1/_t1
    _t168 = 2*_t15
    _t169 = _t114*_t49
    _t170 = _t168 - _t169
    _t171 = -_t170
    _t172 = _t168 + _t169
    _t173 = -_t172
    _t174 = ((1/4))*_t166*_t167
    _t175 = _t174*_t42
    _t176 = _t173*_t175
    _t177 = _t176*_t68
    _t178 = ((1/4))*_t166*_t167*_t171*_t42*_t74*_t76 - _t177
    _t179 = ((1/2))*_t166
    _t180 = _t141*_t179
    _t181 = _t135*_t179
    _t182 = _t180 - _t181
    _t183 = -_t135*_t176 + ((1/4))*_t141*_t166*_t167*_t171*_t42
    _t184 = _t15*_t63
    _t185 = _t16*_t23
    _t186 = 2*_t185
    _t187 = _t186 + _t56
    _t188 = -_t184 + _t187
    _t189 = _t184 + _t187
    _t190 = _t175*_t68
    _t191 = _t120*_t48
    _t192 = _t168*_t52
    _t193 = R_*_t192
    _t194 = 4*_t28
    _t195 = _t10*_t84
    _t196 = -R_*_t195 + 2*_t7
    _t197 = -R_*_t194 + _t196 + _t22
    _t198 = _t141*_t72
    _t199 = _t135*_t65
    _t200 = _t109*_t41
    _t201 = _t200*_t31
    _t202 = _t49*_t56
    _t203 = R_*_t202
    _t204 = _t114*_t52
    _t205 = R_*_t204
    _t206 = R_*_t103
    _t207 = -R_*_t33 + _t206
    _t208 = 5*_t32
    _t209 = -_t18 + _t30 + _t7
    _t210 = -_t196 - _t58
    _t211 = -_t196 - _t70
    _t212 = U_*_t3
    _t213 = _t212*_t25
    _t214 = _t0*_t14
    _t215 = _t148*_t214
    _t216 = _t144*_t153
    _t217 = 4*_t216
    _t218 = 5*R_*_t14*_t16*_t3*_t8 + R_*_t148*_t16*_t8 - R_*_t215 - _t213 - _t217
    _t219 = _t144*_t159*_t52
    _t220 = _t144*_t161
    _t221 = _t120*_t220
    _t222 = -4*R_*_t14*_t16*_t3*_t8 + _t217
    _t223 = _t219 - _t221 - _t222
    _t224 = -_t219 + _t221 - _t222
    _t225 = _t45*(-R_*_t106 + 6*R_*_t14*_t16*_t35*_t4 + R_*_t16*_t35*_t36 - _t101 - _t93 - 5*_t94)
    _t226 = _t20*_t50
    _t227 = R_*_t226
    _t228 = 6*_t111
    _t229 = R_*_t228
    _t230 = _t168*_t25 + _t48*_t84 - _t98
    _t231 = -_t208
    _t232 = _t103 + _t87
    _t233 = _t231 + _t232 + _t24 - _t39
    _t234 = -_t204
    _t235 = _t103 + _t202
    _t236 = _t234 + _t235 + _t34
    _t237 = _t103 - _t202 + _t204 + _t34
    _t238 = _t23*_t24
    _t239 = _t16*_t56
    _t240 = 2*_t6
    _t241 = -_t240
    _t242 = _t10*_t16
    _t243 = _t21 + _t6
    _t244 = _t238 - _t29
    _t245 = -_t242 + _t243 + _t244
    _t246 = -_t195
    _t247 = _t240 + _t246
    _t248 = _t47*_t50
    _t249 = -_t21
    _t250 = 2*_t238 + _t239 + _t249
    _t251 = -_t248 + _t250 + _t54
    _t252 = _t247 + _t251
    _t253 = -_t252
    _t254 = _t248 + _t250 - _t54
    _t255 = _t247 + _t254
    _t256 = -_t255
    _t257 = _t153*_t3
    _t258 = _t212*_t24
    _t259 = 4*_t16
    _t260 = -_t156*_t259*_t3
    _t261 = _t258 + _t260
    _t262 = 4*_t257
    _t263 = _t215 + _t262
    _t264 = 5*_t14*_t16*_t3*_t8 + _t148*_t16*_t8 - _t258 - _t263
    _t265 = _t160*_t52
    _t266 = _t161*_t3
    _t267 = _t120*_t266
    _t268 = _t260 + _t262
    _t269 = -_t265 + _t267 + _t268
    _t270 = -_t269
    _t271 = _t265 - _t267 + _t268
    _t272 = -_t271
    _t273 = _t11*_t179
    _t274 = _t273*_t68
    _t275 = -_t273*_t77 + _t274
    _t276 = _t12/(-_t168*_t17 + _t25 + _t48)
    _t277 = 4*_t27
    _t278 = R_*_t277*_t49 + R_*_t61
    _t279 = _t141/(8*R_*_t13*_t14*_t16 - _t278)
    _t280 = _t135/(R_*_t62 + _t278)
    _t281 = _t171*_t279 + _t173*_t280 + _t276
    _t282 = _t11*_t180
    _t283 = -(1/2)*_t11*_t135*_t166 + _t282
    _t284 = ((1/4))*_t11*_t166*_t167*_t171*_t42*_t74*_t76 - _t11*_t177
    _t285 = _t16*_t168
    _t286 = _t235 - _t285
    _t287 = 2*_t87
    _t288 = _t10*_t120
    _t289 = _t287 + _t288
    _t290 = _t286 + _t289
    _t291 = -_t103
    _t292 = _t202 + _t291
    _t293 = _t285 + _t292
    _t294 = -_t287 + _t288
    _t295 = _t293 + _t294
    _t296 = _t200*_t233
    _t297 = U_**7
    _t298 = _t297*_t80
    _t299 = _t148*_t8
    _t300 = _t156*_t24
    _t301 = _t3*_t300
    _t302 = _t24*_t299 + _t301
    _t303 = 1/(_t148*_t297*_t46 - _t215*_t84 - _t257*_t84 + _t298*_t3 + _t302)
    _t304 = _t145*_t24
    _t305 = _t143 - _t162 + _t304
    _t306 = _t5*_t79
    _t307 = _t1*_t86
    _t308 = -_t100*_t161 + _t150 + _t304 + 3*_t306 - _t307*_t96
    _t309 = _t3**5
    _t310 = 1/(6*_t0*_t14*_t148*_t16 + 4*_t0*_t16*_t3*_t46 + 2*_t0*_t16*_t309 - _t14*_t297*_t309 - _t297*_t3**7 - _t302)
    _t311 = _t109*_t310
    _t312 = -_t150 + _t162 + 2*_t304
    _t313 = -_t154 + _t157 + _t312
    _t314 = -_t313
    _t315 = _t1*_t148*_t35
    _t316 = _t129*_t315
    _t317 = _t149*_t63
    _t318 = 4*_t113*_t146
    _t319 = _t161*_t52
    _t320 = 20*_t3*_t319
    _t321 = 8*_t16
    _t322 = -8*_t0*_t14*_t148*_t16 + _t257*_t321 + 16*_t301
    _t323 = 1/(_t316 + _t317 - _t318 - _t320 - _t322)
    _t324 = _t135*_t323
    _t325 = _t154 - _t157 + _t312
    _t326 = -_t325
    _t327 = 1/(-_t316 - _t317 + _t318 + _t320 - _t322)
    _t328 = _t141*_t327
    _t329 = _t297*_t82
    _t330 = _t303*(2*_t0*_t14*_t16*_t4 - _t24*_t9 - _t329)
    _t331 = 4*_t298
    _t332 = _t214*_t4
    _t333 = -_t100*_t153 + _t300 + 3*_t329 + _t331 - _t332*_t96
    _t334 = 8*_t319
    _t335 = _t113*_t159
    _t336 = _t116*_t143
    _t337 = _t120*_t306
    _t338 = _t122*_t307
    _t339 = _t153*_t259 - 8*_t300 - 2*_t329 + _t331 + _t332*_t84
    _t340 = -_t334 - _t335 + _t336 - _t337 + _t338 + _t339
    _t341 = _t334 + _t335 - _t336 + _t337 - _t338 + _t339
    _t342 = -_t305*_t92
    _t343 = -_t308
    _t344 = 2*_t156
    _t345 = 1/(-_t144*_t16*_t344 + _t213 + _t216)
    _t346 = _t159*_t49
    _t347 = -_t344 + _t346
    _t348 = _t129*_t144*_t145 + _t220*_t63
    _t349 = _t141/(8*R_*_t14*_t16*_t3*_t8 - _t348)
    _t350 = -_t344 - _t346
    _t351 = _t135/(_t144*_t156*_t321 + _t348)
    _t352 = 1/_t3
    _t353 = _t274*_t352
    _t354 = 1/_t13
    _t355 = _t11*_t174*_t352*_t354*_t68
    _t356 = _t282*_t352
    _t357 = _t11*_t181*_t352
    _t358 = _t0*_t309
    _t359 = _t16*_t299
    _t360 = 1/(_t261 + _t358 - 2*_t359)
    _t361 = _t360*_t44
    _t362 = _t308*_t361
    _t363 = _t344*_t52
    _t364 = _t120*_t153
    _t365 = _t150 - _t161*_t259 + 2*_t306 - _t307*_t84
    _t366 = _t315*_t63
    _t367 = _t129*_t146
    _t368 = _t16*_t3
    _t369 = _t156*_t368
    _t370 = 8*_t369
    _t371 = 1/(-_t366 + _t367 + _t370)
    _t372 = _t371*_t68
    _t373 = 1/(_t366 - _t367 + _t370)
    _t374 = _t373*_t77
    _t375 = _t13*_t14*_t16 - _t232 + _t35*_t36 - _t39
    _t376 = -_t236
    _t377 = -_t237
    _t378 = _t0*_t1*_t36
    _t379 = -_t242 - _t243 + _t28 + _t378
    _t380 = _t263 - _t358 + _t359 - _t369
    _t381 = -_t275
    _t382 = _t200*_t375
    _t383 = _t168*_t49
    _t384 = -_t277
    _t385 = _t291 + _t32 + _t87
    _t386 = -_t236 - _t294
    _t387 = _t234 + _t289 + _t292 + _t33
    _t388 = -4*_t2*_t3*_t35
    _t389 = -_t145*_t368 - _t315 - _t388
    _t390 = _t146*_t84
    _t391 = _t3*_t344*_t49
    _t392 = -_t388 - _t390 - _t391
    _t393 = 4*_t266 - _t390 + _t391
    _t394 = _t45*(3*_t0*_t2*_t4 - _t242 - _t249 - _t28 - _t378)
    _t395 = _t120*_t47
    _t396 = -_t192 + _t395
    _t397 = -_t194
    _t398 = _t21 + _t247 + _t397
    _t399 = _t107 - 5*_t132 - 7*_t16*_t87 + 3*_t83 + _t97
    _t400 = -4*_t79*_t80 + _t85 + 2*_t89
    _t401 = _t226 - _t228 - _t400
    _t402 = -_t226 + _t228 - _t400
    _t403 = _t360*(-_t21 - _t244 - _t246 - _t378 + _t6)
    _t404 = _t287*_t49 + _t396
    _t405 = _t371*(-_t21 - _t241 - _t397 - _t404)
    _t406 = _t373*(_t194 + _t240 + _t249 + _t404)
    _t407 = _t103 + _t231 + _t40 - _t87
    _t408 = -_t293
    _t409 = _t383 - _t56
    _t410 = -_t383 - _t56
    _t411 = _t361*_t399
    _t412 = _t52*_t56
    _t413 = _t120*_t20
    _t414 = _t105 + 2*_t83 + _t88 + _t97
    _out = _np.zeros((7, 12) + _batch)
    _out[0, 0] = _t31*_t45 + _t59*_t69 + _t71*_t78
    _out[0, 1] = _t102*_t110 + _t126*_t136 + _t139*_t142 + _t92*(2*R_*_t14*_t16*_t35*_t4 - _t93 - _t94)
    _out[0, 2] = _t110*_t152 + _t136*_t164 + _t142*_t165 + _t92*(2*R_*_t16*_t2*_t3*_t35 - _t143*_t144 - _t147)
    _out[0, 3] = _t178
    _out[0, 4] = _t182
    _out[0, 5] = _t183
    _out[0, 6] = -(1/4)*_t166*_t167*_t188*_t42*_t74*_t76 + _t189*_t190
    _out[0, 7] = _t198*(-_t191 + _t193 + _t197) + _t199*(_t191 - _t193 + _t197) + _t201
    _out[0, 9] = _t198*_t71 + _t199*_t59 + _t201
    _out[0, 10] = _t102*_t45 + _t126*_t69 + _t139*_t78
    _out[0, 11] = _t152*_t45 + _t164*_t69 + _t165*_t78
    _out[1, 0] = _t198*(-_t203 + _t205 + _t207) + _t199*(_t203 - _t205 + _t207) + _t200*(-R_*_t208 - R_*_t39 + _t206 + _t25 + _t95)
    _out[1, 1] = _t209*_t45 + _t210*_t69 + _t211*_t78
    _out[1, 2] = _t218*_t45 + _t223*_t69 + _t224*_t78
    _out[1, 3] = -_t182
    _out[1, 4] = _t178
    _out[1, 5] = ((1/4))*_t166*_t167*_t188*_t42*_t74*_t76 - _t189*_t190
    _out[1, 6] = _t183
    _out[1, 7] = _t225 + _t69*(_t125 - _t227 + _t229 + _t230) + _t78*(_t138 + _t227 - _t229 + _t230)
    _out[1, 9] = -_t119*_t69 - _t137*_t78 + _t225
    _out[1, 10] = _t198*_t211 + _t199*_t210 + _t200*_t209
    _out[1, 11] = _t198*_t224 + _t199*_t223 + _t200*_t218
    _out[2, 0] = _t233*_t45 + _t236*_t69 + _t237*_t78
    _out[2, 1] = _t110*_t245 + _t136*_t253 + _t142*_t256 + _t92*(_t195 + _t20 + _t238 - _t239 + _t241)
    _out[2, 2] = _t110*_t264 + _t136*_t270 + _t142*_t272 + _t92*(-3*_t257 - _t261)
    _out[2, 3] = _t275
    _out[2, 4] = _t281
    _out[2, 5] = -_t283
    _out[2, 6] = _t284
    _out[2, 7] = _t198*_t290 - _t199*_t295 + _t296
    _out[2, 9] = _t198*_t237 + _t199*_t236 + _t296
    _out[2, 10] = _t245*_t45 + _t253*_t69 + _t256*_t78
    _out[2, 11] = _t264*_t45 + _t270*_t69 + _t272*_t78
    _out[3, 0] = _t303*_t305 + _t308*_t311 + _t314*_t324 + _t326*_t328
    _out[3, 1] = _t310*_t333*_t44 + _t323*_t340*_t68 + _t327*_t341*_t77 + _t330*t_
    _out[3, 2] = _t108*_t343*_t44 + _t134*_t313*_t68 + _t140*_t325*_t77 + _t342*t_
    _out[3, 3] = _t345*(U_*_t16 - _t156) + _t347*_t349 + _t350*_t351
    _out[3, 4] = ((1/2))*_t11*_t166*_t352*_t74*_t76 - _t353
    _out[3, 5] = ((1/4))*_t11*_t166*_t167*_t347*_t352*_t354*_t74*_t76 - _t350*_t355
    _out[3, 6] = _t356 - _t357
    _out[3, 7] = _t362 + _t372*(-_t363 + _t364 + _t365) + _t374*(_t363 - _t364 + _t365)
    _out[3, 8] = 1
    _out[3, 9] = _t314*_t372 + _t326*_t374 + _t362
    _out[3, 10] = _t311*_t333 + _t324*_t340 + _t328*_t341 + _t330
    _out[3, 11] = _t110*_t343 + _t136*_t313 + _t142*_t325 + _t342
    _out[4, 0] = _t375*_t45 + _t376*_t69 + _t377*_t78
    _out[4, 1] = _t110*_t379 + _t136*_t252 + _t142*_t255 + _t247*_t92
    _out[4, 2] = _t110*_t380 + _t136*_t269 + _t142*_t271 + _t92*(2*_t257 - _t344*_t368)
    _out[4, 3] = _t381
    _out[4, 4] = _t170*_t279 + _t172*_t280 - _t276
    _out[4, 5] = _t283
    _out[4, 6] = ((1/4))*_t11*_t166*_t167*_t170*_t42*_t74*_t76 - _t11*_t172*_t190
    _out[4, 7] = -_t198*_t290 + _t199*_t295 + _t382
    _out[4, 9] = _t198*_t377 + _t199*_t376 + _t382
    _out[4, 10] = _t252*_t69 + _t255*_t78 + _t379*_t45
    _out[4, 11] = _t269*_t69 + _t271*_t78 + _t380*_t45
    _out[5, 0] = _t198*(_t186 - _t277 - _t383) + _t199*(_t186 + _t383 + _t384) + _t200*(_t10 + _t185 + _t384)
    _out[5, 1] = _t385*_t45 + _t386*_t69 + _t387*_t78
    _out[5, 2] = _t389*_t45 + _t392*_t69 + _t393*_t78
    _out[5, 3] = _t281
    _out[5, 4] = _t381
    _out[5, 5] = _t284
    _out[5, 6] = _t283
    _out[5, 7] = _t394 + _t69*(_t396 + _t398) + _t78*(_t192 - _t395 + _t398)
    _out[5, 9] = -_t251*_t69 - _t254*_t78 + _t394
    _out[5, 10] = _t198*_t387 + _t199*_t386 + _t200*_t385
    _out[5, 11] = _t198*_t393 + _t199*_t392 + _t200*_t389
    _out[6, 0] = _t303*_t91 + _t311*_t399 + _t324*_t401 + _t328*_t402
    _out[6, 1] = _t403*_t44 + _t405*_t68 + _t406*_t77
    _out[6, 2] = _t286*_t78 + _t407*_t45 + _t408*_t69
    _out[6, 3] = _t345*(U_*_t1*_t16 - _t27) + _t349*_t409 + _t351*_t410
    _out[6, 4] = ((1/2))*_t1*_t11*_t166*_t352*_t74*_t76 - _t1*_t353
    _out[6, 5] = ((1/4))*_t11*_t166*_t167*_t352*_t354*_t409*_t74*_t76 - _t355*_t410
    _out[6, 6] = _t1*_t356 - _t1*_t357
    _out[6, 7] = _t372*(-_t412 + _t413 + _t414) + _t374*(_t412 - _t413 + _t414) + _t411
    _out[6, 9] = _t372*_t401 + _t374*_t402 + _t411
    _out[6, 10] = _t109*_t403 + _t135*_t405 + _t141*_t406
    _out[6, 11] = _t198*_t286 + _t199*_t408 + _t200*_t407
    return _out


def frequencies_full(x, u, p):
    """Mode frequencies of variant 'full', rad/s.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units (see BAKED)

    Returns
    -------
    numpy.ndarray, shape (3, ...)
        one frequency per entry of MODES
    """
    x = _as_vector(x, 4, 'x', 'frequencies_full')
    u = _as_vector(u, 3, 'u', 'frequencies_full')
    p = _as_vector(p, 4, 'p', 'frequencies_full')
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

    Parameters
    ----------
    t : array_like, shape (1, ...)
        time since the start, s (shape (1, ...))
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units (see BAKED)

    Returns
    -------
    numpy.ndarray, shape (7, 12, ...)
        error state i for unit source j
    """
    t = _as_vector(t, 1, 't', 'responses_report_reduced')
    x = _as_vector(x, 4, 'x', 'responses_report_reduced')
    u = _as_vector(u, 3, 'u', 'responses_report_reduced')
    p = _as_vector(p, 4, 'p', 'responses_report_reduced')
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
    _out[1, 9] = -R_*_t18*_t4**((3/2)) - _t41
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


def frequencies_report_reduced(x, u, p):
    """Mode frequencies of variant 'report_reduced', rad/s.

    Parameters
    ----------
    x : array_like, shape (4, ...)
        static-base state (only the position matters), SI units
    u : array_like, shape (3, ...)
        static-base inputs (only the vertical specific force matters, where it is an input), SI units
    p : array_like, shape (4, ...)
        model parameters, SI units (see BAKED)

    Returns
    -------
    numpy.ndarray, shape (2, ...)
        one frequency per entry of MODES
    """
    x = _as_vector(x, 4, 'x', 'frequencies_report_reduced')
    u = _as_vector(u, 3, 'u', 'frequencies_report_reduced')
    p = _as_vector(p, 4, 'p', 'frequencies_report_reduced')
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
