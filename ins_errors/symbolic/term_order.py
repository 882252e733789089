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

from ins_errors.symbolic.quick_sympy import _SYMPYS_SUM_MINUS_SIGN, rational_complex


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


def sum_could_extract_minus_sign(total: sp.Add) -> bool:
    """``total.could_extract_minus_sign()`` as SymPy answers it, for a sum.

    SymPy counts the terms that could give up a minus sign; on a tie it compares the
    sort keys of ``total`` and ``-total``, which builds the negated sum and orders the
    terms of both (common subexpression elimination asks this of every sum it visits).
    The sort key of a sum lists its terms' keys in :func:`ordered_terms` order, and a
    term's key ends with its numeric coefficient. When no two terms share a monomial
    (and SymPy's special two-term order does not apply), ``-total`` orders its terms
    as ``total`` does, so the two keys first differ at the first term's coefficient
    c, against -c: the answer is c < -c. Any other sum is left to SymPy.
    """
    args = total.args
    negative = sum(1 for term in args if term.could_extract_minus_sign())
    if 2 * negative != len(args):
        return 2 * negative > len(args)
    if len(args) == 2 and any(isinstance(a, (Number, NumberSymbol)) for a in args):
        return _SYMPYS_SUM_MINUS_SIGN(total)  # (as_ordered_terms' special case)
    terms = _as_terms(total)
    monomials = {(monom, ncpart) for _, (_, monom, ncpart) in terms}
    if len(monomials) != len(terms) or any(term.is_Order for term, _ in terms):
        return _SYMPYS_SUM_MINUS_SIGN(total)
    sort_key, reverse = total._parse_order(None)
    first = (max if reverse else min)(terms, key=sort_key)[0]
    coefficient = first.as_coeff_Mul()[0]
    return bool(coefficient < -coefficient)


class FastTermOrder:
    """Printer mix-in: sums ordered by :func:`ordered_terms` (the default order only)."""

    def _as_ordered_terms(self, expr, order=None):
        if (order or self.order) is None:
            return ordered_terms(expr)
        return super()._as_ordered_terms(expr, order=order)
