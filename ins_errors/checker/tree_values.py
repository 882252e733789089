"""Values of many SymPy expressions at the reference points, each shared subtree once.

The checker evaluates thousands of coefficients (the hand's and the model's, their
differences, candidate corrections) that share most of their subtrees: the model's
variation is one large expression graph, and a coefficient difference ``h - m`` is built
from two coefficients already evaluated. :class:`TreeValues` walks the trees once and
keeps the value of every node it met, so a later expression costs only its new nodes; a
compiled function per batch (:func:`sympy.lambdify` with common subexpressions) costs
its whole tree again, plus the elimination, the printing and the compilation.

The arithmetic is NumPy's on float64 arrays (complex only where the expression holds
``I``), as in the code :func:`sympy.lambdify` writes: a square root or non-integer power
of a negative value, a division by zero give NaN or ±inf (never an exception), which the
caller reports. Terms of a sum are added, and factors of a product multiplied, in the
order of the expression's arguments (the compiled code follows the printed order), so
values may differ from the compiled ones in the last bits: every decision of the
checker has a margin far above that (:data:`~ins_errors.checker.compare.AGREEMENT`).
An expression with a node outside :data:`FUNCTIONS` (Piecewise, ...) raises
:class:`UnsupportedError`, and the caller compiles it instead.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

FUNCTIONS = {
    sp.sin: np.sin, sp.cos: np.cos, sp.tan: np.tan, sp.asin: np.arcsin, sp.acos: np.arccos,
    sp.atan: np.arctan, sp.sinh: np.sinh, sp.cosh: np.cosh, sp.tanh: np.tanh,
    sp.exp: np.exp, sp.log: np.log, sp.Abs: np.abs, sp.sign: np.sign,
    sp.atan2: np.arctan2, sp.re: np.real, sp.im: np.imag, sp.conjugate: np.conjugate,
    sp.sec: lambda x: 1 / np.cos(x), sp.csc: lambda x: 1 / np.sin(x),
    sp.cot: lambda x: 1 / np.tan(x),
}
"""SymPy functions evaluated here, with their NumPy counterparts."""


class UnsupportedError(Exception):
    """An expression holds a node :class:`TreeValues` does not evaluate."""


def _number(node: sp.Basic):
    """A NumPy scalar (float64, or complex128 for a complex number)."""
    if node.is_Rational or node.is_Float or node.is_NumberSymbol:
        return np.float64(float(node))
    if node is sp.I:
        return np.complex128(1j)
    try:
        value = complex(node)
    except TypeError:  # zoo and the like: left to the compiled code
        raise UnsupportedError(type(node).__name__) from None
    return np.float64(value.real) if value.imag == 0 else np.complex128(value)


class TreeValues:
    """Node values of SymPy expressions at fixed sample values of their symbols.

    Parameters
    ----------
    symbols : list of sympy.Symbol
        The symbols that may appear.
    arrays : list of numpy.ndarray
        Their values, each of shape (K,).
    """

    def __init__(self, symbols: list[sp.Symbol], arrays: list[np.ndarray]):
        self._memo: dict[sp.Basic, object] = dict(zip(symbols, arrays, strict=True))

    def value(self, expr: sp.Basic):
        """The value of ``expr``: an array of shape (K,), or a NumPy scalar if constant.

        Raises
        ------
        UnsupportedError
            If ``expr`` holds a node other than numbers, known symbols, sums, products,
            powers and :data:`FUNCTIONS`.
        """
        memo = self._memo
        found = memo.get(expr)
        if found is not None:
            return found
        stack = [(expr, False)]
        while stack:
            node, ready = stack.pop()
            if node in memo:
                continue
            if not node.args:
                if node.is_Symbol:
                    raise UnsupportedError(f"symbol {node} has no value")
                memo[node] = _number(node)
                continue
            if not ready:
                stack.append((node, True))
                stack.extend((a, False) for a in node.args if a not in memo)
                continue
            memo[node] = self._combine(node)
        return memo[expr]

    def _combine(self, node: sp.Basic):
        """The value of ``node`` from its arguments' (all known)."""
        memo = self._memo
        if node.is_Add:
            terms = iter(node.args)
            total = memo[next(terms)]
            for a in terms:
                total = total + memo[a]
            return total
        if node.is_Mul:
            # as the printed code: a*b/(c*d) for the factors with negative exponents
            top = bottom = None
            for a in node.args:
                if a.is_Pow and a.exp.is_Rational and a.exp.is_negative:
                    part = _power(-a.exp, memo[a.base])
                    bottom = part if bottom is None else bottom * part
                else:
                    top = memo[a] if top is None else top * memo[a]
            if top is None:
                top = np.float64(1.0)
            return top if bottom is None else top / bottom
        if node.is_Pow:
            return _power(node.exp, memo[node.base], memo[node.exp])
        function = FUNCTIONS.get(node.func)
        if function is None:
            raise UnsupportedError(type(node).__name__)
        return function(*(memo[a] for a in node.args))


def _power(exponent: sp.Expr, base_value, exponent_value=None):
    """``base ** exponent`` from the value of the base, as the printed code computes it."""
    if exponent == sp.S.Half:
        return np.sqrt(base_value)
    if exponent == -sp.S.Half:
        return 1 / np.sqrt(base_value)
    if exponent.is_Integer:
        e = int(exponent)
        return base_value ** e if e >= 0 else 1 / base_value ** (-e)
    if exponent_value is None:
        exponent_value = _number(exponent)
    return base_value ** exponent_value
