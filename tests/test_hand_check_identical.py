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


def test_kept_parses_follow_the_notation():
    """A parse kept for one notation is never handed to another."""
    from ins_errors.checker.notation import Notation
    from ins_errors.checker.parse import parse_latex_expression, parse_text_expression

    plain, spelled = Notation(), Notation(spellings={"w_xi": "omega_xi"})
    for _ in range(2):  # the second round reads the kept results
        assert parse_text_expression("2*w_xi", plain)[0] == 2 * sp.Symbol("w_xi")
        assert parse_text_expression("2*w_xi", spelled)[0] == 2 * sp.Symbol("omega_xi")
        assert parse_text_expression("2*w_xi", plain, column=5)[1] == {"w_xi": 7}
    primed = Notation(latex_primes={"omega": "omega_rel"})
    assert parse_latex_expression(r"\omega'_\xi", Notation())[0] == sp.Symbol("omegap_xi")
    assert parse_latex_expression(r"\omega'_\xi", primed)[0] == sp.Symbol("omega_rel_xi")
    # the caller may change the columns it gets without changing the kept ones
    parse_text_expression("2*w_xi", plain)[1].clear()
    assert parse_text_expression("2*w_xi", plain)[1] == {"w_xi": 3}


def test_a_check_after_other_checks_equals_one_with_nothing_kept():
    """The kept splits, comparisons, tautologies and parses change no report."""
    from ins_errors.checker import compare, parse, sides
    from ins_errors.checker.compare import check_hand
    from ins_errors.checker.notation import default_notation
    from ins_errors.checker.parse import parse_hand_text
    from ins_errors.checker.report import to_json
    from tests.test_hand_check import CORRECT

    def report(text):
        hand = parse_hand_text(text, default_notation("orthodromic"))
        return to_json(check_hand(hand, threshold=1e-3, effects=False))

    wrong = CORRECT.replace("- a_zeta*alpha_y", "+ a_zeta*alpha_y")
    report(CORRECT)
    warm = report(wrong)
    for kept in (compare._shared_linear_parts, compare._identical, compare._display,
                 sides._tautology, parse._parsed_text, parse._parsed_latex):
        kept.cache_clear()
    for side in sides._SHARED.values():
        side[1]._varied.clear()
    cold = report(wrong)
    assert warm == cold
    assert warm["summary"]["mistakes"] >= 1


def test_checks_run_with_one_blas_thread_and_restore_the_pools():
    from threadpoolctl import threadpool_info

    from ins_errors.checker.blas import one_blas_thread

    def blas_threads():
        return [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]

    before = blas_threads()
    inside = one_blas_thread(blas_threads)()
    assert inside and set(inside) == {1}
    assert blas_threads() == before
