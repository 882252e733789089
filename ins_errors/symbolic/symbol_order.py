"""SymPy's canonical order of a set of symbols, without building a sort key per symbol.

The checker and the structured variation walk the free symbols of an expression in
SymPy's canonical order (``sorted(symbols, key=sympy.default_sort_key)``) so that what
they do first (the unknown symbol reported first, the order of a sum's terms) does not
depend on set iteration. ``default_sort_key`` of a plain :class:`sympy.Symbol` is
``(class_key, (1, (name,)), S.One.sort_key(), S.One)``: for symbols that are all of the
class ``Symbol`` itself, only the name differs, so sorting by name gives the same order
(symbols of equal name, e.g. with different assumptions, tie under both keys and keep
their input order: ``sorted`` is stable). Building SymPy's key costs about 10 µs a
symbol, sorting by name about 0.2 µs. Any other element (a ``Dummy``, a ``Wild``, an
indexed object) leaves the whole set to SymPy's key.
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

__all__ = ["sorted_symbols"]


def _name(symbol: sp.Symbol) -> str:
    return symbol.name


def sorted_symbols(symbols: Iterable[sp.Basic]) -> list[sp.Basic]:
    """``sorted(symbols, key=sympy.default_sort_key)``, the same list (see module doc).

    Parameters
    ----------
    symbols : iterable of sympy.Basic
        Usually an expression's ``free_symbols``.

    Returns
    -------
    list
        The elements in SymPy's canonical order.
    """
    items = list(symbols)
    if all(type(s) is sp.Symbol for s in items):
        return sorted(items, key=_name)
    return sorted(items, key=sp.default_sort_key)
