"""The operation count in `make derive`'s summary is SymPy's ``count_ops``, to the unit.

``codegen._count_ops`` adds integers along SymPy's own walk instead of symbols; the
reference is ``sympy.count_ops`` itself on every branch of that walk and on every
printed expression of a model.
"""

from __future__ import annotations

import sympy as sp

from derive.model_files import function_specs
from ins_errors.models import definition
from ins_errors.symbolic.codegen import _count_ops, prepare
from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.variation import vary

x, y, z = sp.symbols("x y z", real=True)
f = sp.Function("f")

CASES = [
    x, sp.S.One, sp.S.Zero, sp.Rational(-1, 3), sp.Integer(-4), sp.Float(2.5), sp.pi,
    x + y, x - y, -x - y, -x + y, -x - 2 * y + z, 2 * x * y, -x * y, -2 * x * y,
    x / y, -x / y, 1 / x, -1 / (x + y), 3 / (x * y), sp.Rational(3, 4) * x / y,
    x**2, x**-2, x ** sp.Rational(-1, 2), sp.sqrt(x + y), 1 / sp.sqrt(x**2 + y**2),
    sp.exp(x), sp.exp(-x) * y, sp.E, sp.sin(x) * sp.cos(y) - sp.tan(x / y),
    sp.atan2(y, -x), sp.Abs(-x + y), sp.Max(x, y, z), sp.Min(x, -y), f(x, y) - 1,
    sp.Derivative(f(x), x), sp.Piecewise((x, x < 0), (-y, True)),
    -(x + y) / (2 * z - x) ** 3 + sp.sin(-x * y) ** 2,
    # products whose factors all stay in the numerator, and ones where one may not
    x**y * z, x ** (-y) * z, 2 * x ** (y * z), sp.exp(-x * y) / z, sp.sqrt(2) * x / 3,
    -sp.sqrt(3) * x * y**2, x ** sp.Symbol('n', positive=True) * y,
]


def test_every_branch_of_sympys_walk_counts_alike():
    for expr in CASES:
        assert _count_ops(expr) == sp.count_ops(expr), expr


def test_a_models_printed_expressions_count_alike():
    trees = SharedTrees()
    checked = 0
    for spec in function_specs(vary(definition("north_pointing"))):
        prepared = prepare(spec, trees)
        for expr in [e for _, e in prepared.assignments] + [e for *_, e in prepared.entries]:
            assert _count_ops(expr) == sp.count_ops(expr), (spec.name, expr)
            checked += 1
    assert checked > 300
