"""``Mul.could_extract_minus_sign`` without building the negated product (same answers).

SymPy answers "could a minus sign be pulled out of this product?" by first building
``-self`` and comparing it with ``self`` (to rule out products such as ``zoo*x``, equal
to their negation), then looking at the numeric coefficient. The common subexpression
elimination asks it of every product it visits, and the printers of every product they
parenthesise, so ``make derive`` spends a few percent of its time building negated
products only to compare them. For a product whose first factor is a nonzero rational
and whose other factors are neither numbers nor ``zoo`` (the canonical form),
``-self`` has the opposite coefficient and so never equals ``self``, and the answer is
the coefficient's sign; a product whose first factor is not a number never answers yes. Every other
product (zero, infinite or float factors, unevaluated products with several numbers)
is left to SymPy.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

import sympy as sp

_SYMPYS = sp.Mul.could_extract_minus_sign


def could_extract_minus_sign(product: sp.Mul) -> bool:
    """``product.could_extract_minus_sign()`` as SymPy answers it."""
    args = product.args
    first = args[0]
    if not first.is_Number:
        return False
    if first.is_Rational and first.p != 0 and not any(
            a.is_Number or a is sp.S.ComplexInfinity for a in args[1:]):
        return first.p < 0
    return _SYMPYS(product)


@contextlib.contextmanager
def quick_minus_sign() -> Iterator[None]:
    """Products answer with :func:`could_extract_minus_sign` inside the block.

    Not thread-safe: the block swaps a method of ``sympy.Mul`` and restores it on exit.
    """
    if sp.Mul.could_extract_minus_sign is could_extract_minus_sign:  # nested
        yield
        return
    sp.Mul.could_extract_minus_sign = could_extract_minus_sign
    try:
        yield
    finally:
        sp.Mul.could_extract_minus_sign = _SYMPYS
