"""The second-order term sums its terms in one Add: the same expression as adding them
one by one (what the derivation did before), so generated code is unchanged."""

from __future__ import annotations

import sympy as sp

from ins_errors.models import definition
from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.variation import _second_order_term


def _one_by_one(jacobian, variables, directions, point):
    """The term as first written: a running sum, every term added to it in turn."""
    rows = []
    for i in range(jacobian.rows):
        total = sp.S.Zero
        for j, d_j in enumerate(directions):
            entry = jacobian[i, j]
            free = entry.free_symbols
            for k, v_k in enumerate(variables):
                if k < j or entry == 0 or v_k not in free:  # (a derivative of zero)
                    continue
                curvature = sp.diff(entry, v_k).xreplace(point)
                if curvature != 0:
                    total += (1 if k == j else 2) * curvature * d_j * directions[k]
        rows.append(total / 2)
    return sp.Matrix(rows)


def test_second_order_term_equals_the_running_sum_node_for_node():
    d = definition("north_pointing")
    variables = [*d.real_states, *d.w]
    point = {**d.at_ideal(), **d.no_errors()}
    directions = [*d.xe, *d.w]
    with SharedTrees().differentiating() as trees:  # SymPy's Jacobian (test_shared_trees)
        jacobian = d.real_rhs_expanded().jacobian(variables)
        summed = _second_order_term(jacobian, variables, directions, point, trees)
    expected = _one_by_one(jacobian, variables, directions, point)
    assert max(len(e.args) for e in expected) >= 8  # sums of several terms
    assert sp.srepr(summed) == sp.srepr(expected)
