"""SharedTrees returns exactly what SymPy's diff and xreplace return, only faster.

The reference is plain SymPy on the same expressions (structural equality, which is
what makes the printed generated code byte-identical); ``make derive``'s output as a
whole is compared with the committed tree by test_generated_fresh.
"""

from __future__ import annotations

import pytest
import sympy as sp
from sympy.core.expr import Expr

from ins_errors.models import definition
from ins_errors.symbolic.shared_trees import SharedTrees


@pytest.fixture(scope="module")
def model():
    d = definition("north_pointing")
    return d, d.real_rhs_expanded(), [*d.real_states, *d.w]


def test_jacobian_and_second_derivatives_equal_sympys(model):
    d, rhs, variables = model
    point = {**d.at_ideal(), **d.no_errors()}
    plain = rhs.jacobian(variables)
    held = {(i, j): plain[i, j].free_symbols  # (one walk an entry, not one a variable)
            for i in range(plain.rows) for j in range(plain.cols)}
    plain_second = {(i, j, k): sp.diff(plain[i, j], v).xreplace(point)
                    for i in range(plain.rows) for j in range(plain.cols)
                    for k, v in enumerate(variables) if v in held[i, j]}
    assert plain_second  # the model has curvature to compare
    with SharedTrees().differentiating() as trees:
        shared = rhs.jacobian(variables)
        shared_second = {(i, j, k): trees.xreplace(trees.derivative(shared[i, j], v), point)
                         for i in range(shared.rows) for j in range(shared.cols)
                         for k, v in enumerate(variables)
                         if v in trees.free_symbols(shared[i, j])}
    assert shared == plain  # structural equality, entry by entry
    assert shared_second == plain_second
    assert [trees.free_symbols(e) for e in rhs] == [e.free_symbols for e in rhs]


def test_xreplace_rebuilds_like_sympy():
    x, y = sp.symbols("x y", real=True)
    unevaluated = sp.Mul(2, sp.Add(x, y), evaluate=False)  # rebuilt (evaluated) if touched
    expr = sp.sin(unevaluated) + sp.cos(x) ** 2 * unevaluated
    trees = SharedTrees()
    for rule in ({x: 0}, {x: x}, {y: sp.pi * x}, {}):
        assert trees.xreplace(expr, rule) == expr.xreplace(rule)
    assert trees.xreplace_matrix(sp.Matrix([expr, x]), {x: 1}) == sp.Matrix(
        [expr.xreplace({x: 1}), 1])


def test_other_derivatives_are_sympys_and_diff_is_restored():
    x, y = sp.symbols("x y", real=True)
    f = sp.Function("f")
    expr = f(x * y) * sp.atan2(y, x) + sp.Abs(x) * x**3
    expected = [sp.diff(expr, x), sp.diff(expr, x, 2), sp.diff(expr, (x, 2), y),
                sp.diff(expr, f(x * y))]
    original = Expr.diff
    with pytest.raises(RuntimeError), SharedTrees().differentiating():
        assert [sp.diff(expr, x), sp.diff(expr, x, 2), sp.diff(expr, (x, 2), y),
                sp.diff(expr, f(x * y))] == expected
        raise RuntimeError("leave the block")
    assert Expr.diff is original


def test_subs_of_a_sum_gives_sympys_subs():
    a, b, c, t, w = sp.symbols("a b c t w", positive=True)
    old, new = a**2 + b**2, w**2
    shared = sp.sin(c * t) / (a**2 + b**2)
    cases = [
        shared * (a**2 + b**2 + c) + sp.cos(t * sp.sqrt(a**2 + b**2)) * shared,  # repeats
        2 * a**2 + 2 * b**2 + c,  # a multiple of the sum among other terms
        -a**2 - b**2 + c * t,  # its negative
        (a**2 + b**2) ** 3 * (a**2 - b**2) / (c + a**2 + b**2) ** 2,
        a**2 * c + b**2,  # the terms without the pattern's coefficients: no match
        sp.Integer(3), c, a**2, sp.Derivative(sp.Function("f")(a**2 + b**2), a),
    ]
    trees = SharedTrees()
    for expr in cases:
        expected = expr.subs(old, new)
        got = trees.subs(expr, old, new)
        assert got == expected and sp.srepr(got) == sp.srepr(expected), expr
    assert trees.subs(cases[0], old, new) != cases[0]  # the repeated subtree was replaced
    assert trees.subs(cases[4], old, new) is cases[4]  # no match: the same object back


def test_renames_share_a_memo_only_where_their_rules_agree(model):
    _d, rhs, _variables = model
    symbols = sorted(set().union(*(e.free_symbols for e in rhs)), key=str)
    first = {s: sp.Symbol(f"{s.name}_", real=True) for s in symbols}
    # the same renames for all but one symbol, which another rule sends elsewhere
    other = dict(first)
    other[symbols[0]] = sp.Symbol("elsewhere", real=True)
    part = rhs[:2, :]  # fewer symbols, agreeing with the first rule
    partial = {s: first[s] for s in list(symbols)[1:]}  # misses a symbol: plain xreplace
    trees = SharedTrees()
    for rule, matrix in ((first, rhs), (other, rhs), (first, part), (partial, rhs),
                         (other, part)):
        used = {s: rule[s] for s in set().union(*(e.free_symbols for e in matrix))
                if s in rule}
        assert trees.rename_matrix(matrix, used) == matrix.xreplace(used)
    assert len(trees._renames) == 2  # the first and the disagreeing rule, one memo each
