"""The printers' order of the terms of a sum, as SymPy orders them, computed faster.

SymPy's printers write a sum's terms in the order of ``Expr.as_ordered_terms()``, whose
sort key holds each term's numeric coefficient as a Python complex number, obtained with
``complex(coefficient)``: for a rational coefficient that is a full ``evalf`` each time
(about a third of the time ``make derive`` spent printing). :func:`ordered_terms` is
the same function with the complex value of each distinct rational computed once by
SymPy and remembered (:func:`~ins_errors.symbolic.quick_sympy.rational_complex`), and
:class:`FastTermOrder` gives a printer that method.
"""

from __future__ import annotations

import sympy as sp
from sympy.core.exprtools import decompose_power
from sympy.core.numbers import Number, NumberSymbol
from sympy.core.sorting import default_sort_key

from ins_errors.symbolic.quick_sympy import rational_complex


def _complex(number: sp.Expr) -> complex:
    """``complex(number)``: the same value, remembered for a rational."""
    return rational_complex(number) if number.is_Rational else complex(number)


def _as_terms(expr: sp.Expr) -> list[tuple[sp.Expr, tuple]]:
    """``expr.as_terms()[0]`` with :func:`_complex` for ``complex``: same operations."""
    gens, terms = set(), []
    for term in sp.Add.make_args(expr):
        coeff, rest = term.as_coeff_Mul()
        coeff = _complex(coeff)
        cpart, ncpart = {}, []
        if rest is not sp.S.One:
            for factor in sp.Mul.make_args(rest):
                if factor.is_number:
                    try:
                        coeff *= _complex(factor)
                    except (TypeError, ValueError):
                        pass
                    else:
                        continue
                if factor.is_commutative:
                    base, exp = decompose_power(factor)
                    cpart[base] = exp
                    gens.add(base)
                else:
                    ncpart.append(factor)
        terms.append((term, ((coeff.real, coeff.imag), cpart, tuple(ncpart))))
    indices = {g: i for i, g in enumerate(sorted(gens, key=default_sort_key))}
    result = []
    for term, (coeff, cpart, ncpart) in terms:
        monom = [0] * len(indices)
        for base, exp in cpart.items():
            monom[indices[base]] = exp
        result.append((term, (coeff, tuple(monom), ncpart)))
    return result


def ordered_terms(expr: sp.Expr) -> list[sp.Expr]:
    """``expr.as_ordered_terms()`` (order None): the same list of terms."""
    if not expr.is_Add:
        return expr.as_ordered_terms()
    # SymPy's special case: Add(Number, Mul(Number, expr)), the first number positive
    # and the second negative, is kept as written
    def key(x):
        return not isinstance(x, (Number, NumberSymbol))

    add_args = sorted(sp.Add.make_args(expr), key=key)
    if (len(add_args) == 2 and isinstance(add_args[0], (Number, NumberSymbol))
            and isinstance(add_args[1], sp.Mul)):
        mul_args = sorted(sp.Mul.make_args(add_args[1]), key=key)
        if (len(mul_args) == 2 and isinstance(mul_args[0], Number)
                and add_args[0].is_positive and mul_args[0].is_negative):
            return add_args
    terms = _as_terms(expr)
    if any(term.is_Order for term, _ in terms):
        return expr.as_ordered_terms()
    sort_key, reverse = expr._parse_order(None)
    return [term for term, _ in sorted(terms, key=sort_key, reverse=reverse)]


class FastTermOrder:
    """Printer mix-in: sums ordered by :func:`ordered_terms` (the default order only)."""

    def _as_ordered_terms(self, expr, order=None):
        if (order or self.order) is None:
            return ordered_terms(expr)
        return super()._as_ordered_terms(expr, order=order)
