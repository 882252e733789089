r"""Sines and cosines of angle states carried through a step instead of recomputed.

The exact platform's real-work equations evaluate ``sin``, ``cos`` (and ``tan``) of the
three platform angles at every right-hand-side evaluation: in a compiled loop these
library calls cost more than all the rest of the step. Here the sine and cosine of each
such angle travel with the state as two extra components, and a step moves them on by
the *exact* rotation through the angle's increment ``d``:

.. math::

   \sin(α + d) = \sin α \cos d + \cos α \sin d, \qquad
   \cos(α + d) = \cos α \cos d − \sin α \sin d,

with ``sin d`` and ``cos d`` of the small increment (``d = τ α̇`` for the rectangle
method) from their Taylor polynomials to ``d⁵`` and ``d⁶``. In real numbers the carried
values therefore equal the sine and cosine of the angle the scheme computes, at every
stage of every step, whatever the step size: the difference equations of the angles are
the same as with the library calls. The polynomials are exact to the rounding of double
precision (relative error below ``d⁶/5040``, under 2e-16) while ``|d| <= 0.01`` rad per
step, and stay far below the rectangle method's own local error (of order ``d²``) for any
increment a usable step produces. What differs from calling ``sin``/``cos`` each step is
only rounding: the carried values may wander from the library's by a few units in the
last place per thousand steps (about 1e-11 after a day at 100 Hz).

:func:`with_trig_inputs` rewrites a CasADi function so that ``sin``/``cos``/``tan`` of
chosen input elements become extra inputs (every other operation kept as it was, in
the same order); :func:`rotate` is the update above.
"""

from __future__ import annotations

from collections.abc import Sequence

import casadi as ca

_TRIG = (ca.OP_SIN, ca.OP_COS, ca.OP_TAN)


def with_trig_inputs(function: ca.Function, argument: int,
                     elements: Sequence[int]) -> tuple[ca.Function, list[int]]:
    """``function`` with the sines and cosines of some input elements as extra inputs.

    Every ``sin(v)``, ``cos(v)`` and ``tan(v)`` whose argument is one of the given
    elements ``v`` of input ``argument`` itself (not an expression of it) is replaced
    by ``s``, ``c`` and ``s / c``; every other operation is rebuilt unchanged and in the
    same order, so the arithmetic is the same.

    Parameters
    ----------
    function : casadi.Function
        An SX function with dense inputs.
    argument : int
        Index of the input that holds the angles.
    elements : sequence of int
        Elements of that input (angles, rad) whose trigonometric functions are replaced.

    Returns
    -------
    casadi.Function
        The inputs of ``function``, then the sines and the cosines (one column each of
        ``len(used)`` entries, in the order of ``used``), same outputs.
    list of int
        The elements that occur in a replaced operation (possibly empty: then the
        function does not use the extra inputs).
    """
    inputs = [ca.SX.sym(f"i{k}", function.sparsity_in(k)) for k in range(function.n_in())]
    outputs = [ca.SX.zeros(function.sparsity_out(k)) for k in range(function.n_out())]
    targets = {int(e): j for j, e in enumerate(elements)}
    sines = ca.SX.sym("sin", len(targets))
    cosines = ca.SX.sym("cos", len(targets))
    work: dict[int, ca.SX] = {}
    holds: dict[int, int] = {}    # work slot -> target element it holds unchanged
    used: set[int] = set()
    for k in range(function.n_instructions()):
        op = function.instruction_id(k)
        into = function.instruction_input(k)
        out = function.instruction_output(k)
        if op == ca.OP_OUTPUT:
            outputs[out[0]][out[1]] = work[into[0]]
            continue
        slot = out[0]
        angle = holds.get(into[0]) if op in _TRIG else None
        holds.pop(slot, None)   # the slot is overwritten (possibly in place)
        if op == ca.OP_INPUT:
            work[slot] = inputs[into[0]][into[1]]
            if into[0] == argument and into[1] in targets:
                holds[slot] = into[1]
        elif op == ca.OP_CONST:
            work[slot] = ca.SX(function.instruction_constant(k))
        elif angle is not None:
            used.add(angle)
            s, c = sines[targets[angle]], cosines[targets[angle]]
            work[slot] = s if op == ca.OP_SIN else c if op == ca.OP_COS else s / c
        elif len(into) == 1:
            work[slot] = ca.SX.unary(op, work[into[0]])
        elif len(into) == 2:
            work[slot] = ca.SX.binary(op, work[into[0]], work[into[1]])
        else:
            raise NotImplementedError(f"{function.name()}: operation {op} with "
                                      f"{len(into)} operands cannot be rebuilt")
    rebuilt = ca.Function(f"{function.name()}_trig", [*inputs, sines, cosines], outputs)
    return rebuilt, sorted(used)


# Taylor coefficients of sin d and cos d (the same numbers in the graph and in C)
_S3, _S5 = -1.0 / 6.0, 1.0 / 120.0
_C2, _C4, _C6 = -0.5, 1.0 / 24.0, -1.0 / 720.0

TINY = 2.0 ** -27
"""Below this ``|d|`` (rad; then ``d² < 2⁻⁵⁴``) the polynomials round to exactly
``cos d = 1`` and ``sin d = d`` for ``d ≠ 0``: see :data:`ROTATE_C`."""


def sin_small(d: ca.SX) -> ca.SX:
    """``sin d`` for a small increment: ``d − d³/6 + d⁵/120``."""
    d2 = d * d
    return d + d * d2 * (_S3 + d2 * _S5)


def cos_small(d: ca.SX) -> ca.SX:
    """``cos d`` for a small increment: ``1 − d²/2 + d⁴/24 − d⁶/720``."""
    d2 = d * d
    return 1.0 + d2 * (_C2 + d2 * (_C4 + d2 * _C6))


def rotate(s: ca.SX, c: ca.SX, d: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Sine and cosine of ``α + d`` from those of ``α`` (``d`` a small increment, rad)."""
    sd, cd = sin_small(d), cos_small(d)
    return s * cd + c * sd, c * cd - s * sd


ROTATE_C = f"""
/* Sine and cosine of an angle moved on by a small increment d (rad): the operations of
   carried_trig.rotate in the same order, so the same bits. When 0 < |d| < 2^-27
   (d*d < 2^-54) the polynomials round to cos d = 1 and sin d = d exactly (their higher
   terms are below a quarter unit in the last place of the leading ones), and s*1 = s:
   the short branch skips operations, not bits. (d = -0 takes the long way: there
   d + d*d*d*(-1/6) is +0.) */
static inline void ins_rotate(casadi_real d, casadi_real s, casadi_real c,
                              casadi_real* s_out, casadi_real* c_out) {{
  casadi_real d2, cd, sd;
  if (fabs(d) < {TINY.hex()} && d != 0.0) {{
    *s_out = s + c * d;
    *c_out = c - s * d;
    return;
  }}
  d2 = d * d;
  cd = 1.0 + d2 * ({_C2.hex()} + d2 * ({_C4.hex()} + d2 * {_C6.hex()}));
  sd = d + d * d2 * ({_S3.hex()} + d2 * {_S5.hex()});
  *s_out = s * cd + c * sd;
  *c_out = c * cd - s * sd;
}}
"""
"""C function ``ins_rotate(d, s, c, &s_out, &c_out)``: :func:`rotate` for the compiled
loops, with the same bits (compiled without fused multiply-add contraction)."""
