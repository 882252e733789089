"""The checker's shortcuts give exactly what the plain SymPy operations give.

Each shortcut exists only to save time; the reports must not change by one character, so
each is compared here with the plain computation it replaces, structurally (``srepr``),
on the model's own variations.
"""

from __future__ import annotations

import sympy as sp

from ins_errors.checker.compare import _split_by_substitution
from ins_errors.checker.sides import model_side
from ins_errors.models import definition


def _plain_split(expr: sp.Expr, present: list[sp.Symbol]):
    zero = {b: sp.S.Zero for b in present}
    constant = expr.xreplace(zero)
    return {b: expr.xreplace({**zero, b: sp.S.One}) - constant for b in present}, constant


def test_split_by_substitution_is_plain_xreplace():
    side = model_side(definition("orthodromic"))
    basis = [*side.error_states.values(), *side.source_symbols.values()]
    expressions = [*side.state_rhs.values(), *side.delta_of.values()]
    assert len(expressions) > 20
    split = 0
    for expr in expressions:
        present = [b for b in basis if b in expr.free_symbols]
        coefficients, constant = _split_by_substitution(expr, present)
        plain, plain_constant = _plain_split(expr, present)
        assert sp.srepr(constant) == sp.srepr(plain_constant)
        assert list(coefficients) == list(plain)
        for b in present:
            assert sp.srepr(coefficients[b]) == sp.srepr(plain[b]), (expr, b)
        split += len(present)
    assert split > 50
