"""SymPy answers computed without SymPy's detours (the same answers), for a block.

``make derive`` asks SymPy two small questions very often:

* ``Mul.could_extract_minus_sign``: could a minus sign be pulled out of this product?
  (common subexpression elimination asks it of every product it visits, the printers
  of every product they parenthesise). SymPy first builds ``-self`` and compares it
  with ``self`` (to rule out products such as ``zoo*x``, equal to their negation),
  then looks at the numeric coefficient. For a product whose first factor is a nonzero
  rational and whose other factors are neither numbers nor ``zoo`` (the canonical
  form), ``-self`` has the opposite coefficient and never equals ``self``, so the
  answer is the coefficient's sign; a product whose first factor is not a number never
  answers yes. Every other product (zero, infinite or float factors, unevaluated
  products with several numbers) is left to SymPy. The same question of a sum
  (:func:`~ins_errors.symbolic.term_order.sum_could_extract_minus_sign`): on a tie of
  negative and positive terms SymPy builds the negated sum and sorts the terms of both;
  where no two terms share a monomial the answer is the sign of the first term's
  coefficient in that order.
* ``complex(rational)``: the sort keys of sums (printing order, canonical signs) hold
  their coefficients as Python complex numbers, and SymPy converts a rational through
  a full ``evalf`` each time (to 57 bits rounded down, then to 53 bits to nearest: not
  always p/q correctly rounded, e.g. 17/25). The same few rationals recur, so each
  distinct one is converted once, by SymPy, and remembered.
* the ordered sets of SymPy's common subexpression elimination (``cse_main``'s
  ``OrderedSet``, on an ``OrderedDict``; its set operations go through the generic
  ``collections.abc`` mix-ins, element by element): :class:`FastOrderedSet` keeps the
  same elements in the same order on a plain dict (insertion-ordered too), with the
  operations CSE uses written directly. About a third of CSE's time was spent there.

* ``Factors(d)`` of a plain dict ``d`` (``factor_terms`` and ``gcd_terms`` build them
  for every term they visit): SymPy first asks whether ``d`` is ``None`` or ``S.One``,
  and ``S.One == d`` sympifies the whole dict into a ``Dict`` (sorting its items) only
  to answer False. :func:`factors_init` hands SymPy the same items in a dict that
  refuses to be sympified (:class:`_PlainFactors`), so the comparisons answer False at
  once and SymPy's own code builds the same ``Factors``.
* the order in which SymPy's assumption system tries the facts that may decide an
  unknown one: ``sympy.core.assumptions`` shuffles them with an unseeded generator
  (to expose handlers that disagree with its inference rules, which would give
  answers depending on the order); the answers are the same in every order, so the
  block keeps the order as found instead of drawing a random permutation each time.

:func:`quick_sympy` installs them for the duration of a block.
"""

from __future__ import annotations

import contextlib
import importlib
from collections.abc import Iterable, Iterator, Set

import sympy as sp
from sympy.core.containers import OrderedSet
from sympy.core.exprtools import Factors

_CSE = importlib.import_module("sympy.simplify.cse_main")
_ASSUMPTIONS = importlib.import_module("sympy.core.assumptions")
_SYMPYS_SHUFFLE = _ASSUMPTIONS.shuffle
_SYMPYS_FACTORS_INIT = Factors.__init__

_SYMPYS_MINUS_SIGN = sp.Mul.could_extract_minus_sign
_SYMPYS_SUM_MINUS_SIGN = sp.Add.could_extract_minus_sign
_SYMPYS_COMPLEX = sp.Rational.__complex__  # (Expr's: through evalf)


def could_extract_minus_sign(product: sp.Mul) -> bool:
    """``product.could_extract_minus_sign()`` as SymPy answers it."""
    args = product.args
    first = args[0]
    if not first.is_Number:
        return False
    if first.is_Rational and first.p != 0 and not any(
            a.is_Number or a is sp.S.ComplexInfinity for a in args[1:]):
        return first.p < 0
    return _SYMPYS_MINUS_SIGN(product)


def rational_complex(rational: sp.Rational) -> complex:
    """``complex(rational)`` as SymPy converts it (each distinct value converted once)."""
    key = rational.p, rational.q
    try:
        return _COMPLEX[key]
    except KeyError:
        value = _COMPLEX[key] = _SYMPYS_COMPLEX(rational)
        return value


_COMPLEX: dict[tuple[int, int], complex] = {}
"""(numerator, denominator) -> SymPy's complex value of the rational."""


class FastOrderedSet(OrderedSet):
    """SymPy's ``OrderedSet``: the same elements in the same order, on a plain dict.

    Every result keeps the order SymPy's gives: ``a & b`` the order of ``b`` (as the
    ``collections.abc`` mix-in iterates), ``a | b`` that of ``a`` then the new elements
    of ``b``, ``a - b``, ``a &= b``, ``intersection`` and ``difference`` that of ``a``.
    """

    def __init__(self, iterable=None):
        self.map = dict.fromkeys(iterable) if iterable else {}

    @classmethod
    def _of(cls, iterable) -> FastOrderedSet:
        out = cls.__new__(cls)
        out.map = dict.fromkeys(iterable)
        return out

    _from_iterable = _of

    def __iter__(self):
        return iter(self.map)

    def pop(self, last=True):
        if not self.map:
            raise KeyError("dictionary is empty")
        if last:
            return self.map.popitem()[0]
        key = next(iter(self.map))
        del self.map[key]
        return key

    def clear(self):
        self.map.clear()

    def update(self, iterable):
        self.map.update(dict.fromkeys(iterable))

    def intersection(self, other):
        return self._of(k for k in self.map if k in other)

    def difference(self, other):
        return self._of(k for k in self.map if k not in other)

    def __sub__(self, other):
        if not isinstance(other, Set):
            return super().__sub__(other)
        return self._of(k for k in self.map if k not in other)

    def __and__(self, other):
        if not isinstance(other, Iterable):
            return NotImplemented
        return self._of(k for k in other if k in self.map)

    def __iand__(self, other):
        if not isinstance(other, Set):
            return super().__iand__(other)
        m = self.map
        for key in [k for k in m if k not in other]:
            del m[key]
        return self

    def __or__(self, other):
        if not isinstance(other, Iterable):
            return NotImplemented
        out = self._of(self.map)
        out.map.update(dict.fromkeys(other))
        return out


class _PlainFactors(dict):
    """A dict SymPy will not sympify (comparisons with SymPy numbers are False at once)."""

    __sympy__ = False  # strict sympify refuses it


def factors_init(self: Factors, factors=None) -> None:
    """``Factors.__init__`` as SymPy runs it; a plain dict's items arrive in a
    :class:`_PlainFactors` (SymPy copies them into a plain dict, as it does the
    caller's dict)."""
    if type(factors) is dict:
        factors = _PlainFactors(factors)
    _SYMPYS_FACTORS_INIT(self, factors)


def _keep_order(facts: list) -> None:
    """In place of SymPy's shuffle of the facts to try next: the order as found."""


@contextlib.contextmanager
def quick_sympy() -> Iterator[None]:
    """SymPy products and rationals answer with the functions above inside the block.

    Not thread-safe: the block sets ``could_extract_minus_sign`` of ``sympy.Mul`` and
    ``sympy.Add``,
    ``sympy.Rational.__complex__``, ``OrderedSet`` of ``sympy.simplify.cse_main``,
    ``Factors.__init__`` and the shuffle of ``sympy.core.assumptions`` and restores
    SymPy's on exit.
    """
    if sp.Mul.could_extract_minus_sign is could_extract_minus_sign:  # nested
        yield
        return
    from ins_errors.symbolic.term_order import sum_could_extract_minus_sign

    own_complex = sp.Rational.__dict__.get("__complex__")  # (None: Expr's)
    sp.Mul.could_extract_minus_sign = could_extract_minus_sign
    sp.Add.could_extract_minus_sign = sum_could_extract_minus_sign
    sp.Rational.__complex__ = rational_complex
    _CSE.OrderedSet = FastOrderedSet
    Factors.__init__ = factors_init
    _ASSUMPTIONS.shuffle = _keep_order
    try:
        yield
    finally:
        _ASSUMPTIONS.shuffle = _SYMPYS_SHUFFLE
        Factors.__init__ = _SYMPYS_FACTORS_INIT
        _CSE.OrderedSet = OrderedSet
        sp.Mul.could_extract_minus_sign = _SYMPYS_MINUS_SIGN
        sp.Add.could_extract_minus_sign = _SYMPYS_SUM_MINUS_SIGN
        if own_complex is None:
            del sp.Rational.__complex__
        else:
            sp.Rational.__complex__ = own_complex
