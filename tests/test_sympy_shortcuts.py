"""The SymPy shortcuts of `make derive` answer as SymPy does (SymPy itself is the reference).

ins_errors/symbolic/term_order.py (the printers' order of a sum's terms; a sum's
``could_extract_minus_sign``), ins_errors/symbolic/quick_sympy.py
(``Mul.could_extract_minus_sign``, ``complex`` of a rational) and
ins_errors/symbolic/symbol_order.py (the canonical order of symbols).
"""

from __future__ import annotations

import sympy as sp
from sympy.printing.printer import Printer

from ins_errors.symbolic import codegen, documents, quick_sympy, term_order


def _expressions() -> list[sp.Expr]:
    x, y, z = sp.symbols("x y z", real=True)
    a, b = sp.symbols("a b", positive=True)
    A, B = sp.symbols("A B", commutative=False)
    big = sp.Integer(2**60 + 1)
    terms = [
        x + y, 2 * x - 3 * y + 1, sp.Rational(1, 3) * x - sp.Rational(2, 3) * y * z,
        big * x + (big + 2) * y, x / big - y / (big - 1), sp.Rational(10**400 + 1, 3) * x + y,
        sp.Float(0.1) * x + sp.Float(-2.5) * y**2, sp.sqrt(2) * x + sp.pi * y + sp.E,
        3 - 2 * x, -3 + 2 * x, 1 - sp.sqrt(2) * x, sp.pi - 3 * y, x**2 * y + x * y**2 + x**3,
        sp.sin(x) ** 2 * sp.cos(x) + sp.sin(x) ** 2 + 1, sp.I * x + 2 * sp.I * y + 3,
        (1 + sp.I) * x - y, sp.sqrt(a + b) * x - sp.sqrt(a) / 7 + b**sp.Rational(3, 2),
        A * B + B * A + 2 * x, x + sp.O(x**2), 1 / (x + y) - x / (y - z) ** 2,
        sp.exp(-x) * a - sp.log(b) / 3 + sp.atan2(y, x) ** 2, x * sp.sqrt(3) / 2 - y / 2,
        # one monomial, so ordered by the numeric factors' values
        sp.sqrt(2) * x + sp.pi * x + sp.Rational(17, 25) * sp.sqrt(3) * x - sp.E * x]
    nested = [t1 * t2 - t2 / 7 for t1, t2 in zip(terms[:10], terms[10:20], strict=True)]
    return terms + nested


def test_ordered_terms_are_sympys():
    for expr in _expressions():
        for e in sp.preorder_traversal(expr):
            if isinstance(e, sp.Expr) and e.is_Add:
                assert term_order.ordered_terms(e) == e.as_ordered_terms(), e


def test_printers_write_sympys_text():
    from sympy.printing.codeprinter import CodePrinter

    class Reference(codegen._BackendPrinter):  # the same printer as SymPy runs it
        _as_ordered_terms = Printer._as_ordered_terms
        _handle_UnevaluatedExpr = CodePrinter._handle_UnevaluatedExpr

    neutral = Reference({f: "_m." + codegen._MARK + f for f in codegen._FUNCTIONS})
    numpy = Reference(codegen._NUMPY_NAMES)
    names = {sp.Symbol("x", real=True): r"\xi"}
    for expr in _expressions():
        if expr.is_commutative and not expr.has(sp.Order):
            assert codegen._NEUTRAL_PRINTER.doprint(expr) == neutral.doprint(expr)
            assert codegen.NUMPY_PRINTER.doprint(expr) == numpy.doprint(expr)
        assert documents.to_latex(expr, names) == sp.latex(expr, symbol_names=names,
                                                           mul_symbol=None)
    # trees with re(...) still go through SymPy's rewrite (of re of a real argument)
    x, w = sp.Symbol("x", real=True), sp.Symbol("w")
    for expr in (sp.re(sp.UnevaluatedExpr(x)) * 3 + x, sp.re(w) + sp.sin(x), x**2 + 1):
        assert codegen._NEUTRAL_PRINTER._handle_UnevaluatedExpr(expr) == \
            CodePrinter._handle_UnevaluatedExpr(neutral, expr)


def test_quick_minus_sign_answers_as_sympy():
    x, y = sp.symbols("x y", real=True)
    unevaluated = [
        sp.Mul(2, 0, x, evaluate=False), sp.Mul(1, -1, x, evaluate=False),
        sp.Mul(-2, sp.zoo, x, evaluate=False), sp.Mul(-1, x + y, evaluate=False),
        sp.Mul(sp.nan, x, evaluate=False), sp.Mul(-3, sp.oo, x, evaluate=False),
        sp.Mul(-3, 2, x, evaluate=False), sp.Mul(x, -2, evaluate=False),
        sp.Mul(sp.Rational(-1, 2), x + y, evaluate=False)]
    evaluated = [sp.zoo * x, -x * y, sp.Float(-1.5) * x, sp.Float(2.0) * y, -sp.pi * x,
                 sp.sqrt(2) * x, -sp.sqrt(2) * x, -sp.I * x, 3 * sp.I * y, -x / y]
    products = unevaluated + evaluated + [
        e for expr in _expressions() for e in sp.preorder_traversal(expr)
        if isinstance(e, sp.Mul)]
    assert len(products) > 100
    sympys = [quick_sympy._SYMPYS_MINUS_SIGN(p) for p in products]
    assert [quick_sympy.could_extract_minus_sign(p) for p in products] == sympys
    assert any(sympys) and not all(sympys)
    with quick_sympy.quick_sympy():
        assert sp.Mul.could_extract_minus_sign is quick_sympy.could_extract_minus_sign
        assert [p.could_extract_minus_sign() for p in products] == sympys
        with quick_sympy.quick_sympy():  # nested: the outer block restores
            pass
        assert sp.Mul.could_extract_minus_sign is quick_sympy.could_extract_minus_sign
    assert sp.Mul.could_extract_minus_sign is quick_sympy._SYMPYS_MINUS_SIGN


def test_quick_minus_sign_of_a_sum_answers_as_sympy():
    from ins_errors.models import definition

    x, y, z = sp.symbols("x y z", real=True)
    ties = [x - y, y - x, 1 - x, x - 1, 2 - 3 * x, -2 + 3 * x, sp.sqrt(2) - 3, sp.pi - x,
            sp.sqrt(2) * x - x, x - sp.sqrt(2) * x, x * y - z + x**2 - y, -x**2 + x - 2 * y + 1,
            sp.Rational(1, 3) * x - sp.Float(0.5) * y, sp.I * x - y, x + sp.O(x**2) - 1,
            sp.sqrt(3) * x * y / 2 - x / 2 + z**2 - sp.sqrt(3) * z]
    sums = ties + [e for expr in _expressions() for e in sp.preorder_traversal(expr)
                   if isinstance(e, sp.Add)]
    for name in ("north_pointing", "strapdown_ned"):  # a model's closed equations
        sums += [e for expr in definition(name).real_rhs_expanded()
                 for e in sp.preorder_traversal(expr) if isinstance(e, sp.Add)]
    sums += [-e for e in sums]
    assert len(sums) > 500
    sympys = [quick_sympy._SYMPYS_SUM_MINUS_SIGN(e) for e in sums]
    assert [term_order.sum_could_extract_minus_sign(e) for e in sums] == sympys
    assert sum(sympys) > 100 and not all(sympys)
    with quick_sympy.quick_sympy():
        assert [e.could_extract_minus_sign() for e in sums] == sympys
    assert sp.Add.could_extract_minus_sign is quick_sympy._SYMPYS_SUM_MINUS_SIGN


def test_quick_complex_of_a_rational_is_sympys():
    import random

    rng = random.Random(5)
    values = [sp.Integer(n) for n in (0, 1, -1, 2**53 + 1, -(2**64) - 3, 10**308)]
    values += [sp.S.Half, sp.Rational(-1, 3), sp.Rational(17, 25), sp.Rational(1, 10**320),
               sp.Rational(-(10**300) + 7, 3), sp.Rational(3, 2**1075)]
    for bits in (8, 40, 60, 200):
        values += [sp.Rational(rng.getrandbits(bits) - 2 ** (bits - 1), rng.getrandbits(bits) + 1)
                   for _ in range(50)]
    expected = [sp.Expr.__complex__(r) for r in values]
    assert expected[8] != complex(17 / 25)  # SymPy's own rounding (not p/q's) is kept
    for _ in range(2):  # converted, then remembered
        assert [quick_sympy.rational_complex(r) for r in values] == expected
    with quick_sympy.quick_sympy():
        assert [complex(r) for r in values] == expected
        assert complex(sp.Float(0.1)) == 0.1 and complex(sp.sqrt(2)) == 2**0.5
    assert "__complex__" not in sp.Rational.__dict__


def test_fast_ordered_set_keeps_sympys_orders():
    import random

    from sympy.core.containers import OrderedSet

    rng = random.Random(3)
    for _ in range(200):
        a_items = [rng.randrange(30) for _ in range(rng.randrange(12))]
        b_items = [rng.randrange(30) for _ in range(rng.randrange(12))]
        pairs = [(cls(a_items), cls(b_items)) for cls in (OrderedSet, quick_sympy.FastOrderedSet)]
        results = []
        for a, b in pairs:
            out = [list(a & b), list(a | b), list(a - b), list(a.intersection(b)),
                   list(a.difference(b)), list(a - b_items), list(a & b_items)]
            c = type(a)(a)
            c &= b
            d = type(a)(a)
            d.update(b_items)
            out += [list(c), list(d), len(a), 3 in a]
            if len(a) > 1:
                out += [a.pop(last=False), list(a), a.pop(), list(a)]
            a.add(99)
            a.discard(99)
            a.clear()
            out.append(list(a))
            results.append(out)
        assert results[0] == results[1]


def test_cse_inside_the_block_is_sympys():
    x, y, z = sp.symbols("x y z", real=True)
    exprs = [(x + y + z) ** 2 * sp.sin(x + y) - (x + y) * z / (x - z) ** 3,
             sp.sqrt(x * y + z) * (x * y + 2 * z) - 3 * x * y * z + (x + y + z) ** 2,
             -x * y * sp.cos(x * y * z) + sp.Rational(17, 25) * (x + z) - sp.sqrt(2) * x * y]
    for order in ("none", "canonical"):
        expected = sp.cse(exprs, symbols=sp.numbered_symbols("_t"), order=order)
        with quick_sympy.quick_sympy():
            assert sp.cse(exprs, symbols=sp.numbered_symbols("_t"), order=order) == expected


def test_factors_of_a_dict_are_sympys():
    from sympy.core.exprtools import Factors

    x, y = sp.symbols("x y", real=True)
    n = sp.Symbol("n", integer=True)
    dicts = [{}, {x: 2}, {x: 1, y: -3}, {sp.S.NegativeOne: 1, x: 2},
             {sp.S.NegativeOne: n, y: 1}, {sp.S.One: 5, x: sp.Rational(1, 2)},
             {sp.I: 3, x: 1}, {sp.I: 2, sp.S.NegativeOne: 1}, {sp.Integer(2): n, x + y: -1},
             {sp.S.NegativeOne: sp.Rational(1, 2), x: 1}]
    others = [None, 1, 0, sp.S.One, sp.Rational(-3, 4), x, 2 * x**2 / y, Factors({x: 2})]
    expected = [(f.factors, f.gens) for f in (Factors(dict(d)) for d in dicts)]
    expected_others = [(f.factors, f.gens) for f in map(Factors, others)]
    with quick_sympy.quick_sympy():
        assert Factors.__init__ is quick_sympy.factors_init
        built = [Factors(dict(d)) for d in dicts]
        assert [(f.factors, f.gens) for f in built] == expected
        assert all(type(f.factors) is dict for f in built)
        # the other forms of argument go to SymPy's code unchanged
        assert [(f.factors, f.gens) for f in map(Factors, others)] == expected_others
    assert Factors.__init__ is quick_sympy._SYMPYS_FACTORS_INIT


def test_gcd_terms_and_assumptions_answer_as_sympy():
    """factor_terms/together (Factors of dicts) and assumption queries (facts tried in the
    order found instead of a shuffled one) give SymPy's results, on fresh expressions."""
    from sympy.core.cache import clear_cache

    def answers(tag: str) -> list:
        clear_cache()
        x, y = sp.symbols(f"x{tag} y{tag}", real=True)
        a, b = sp.symbols(f"a{tag} b{tag}", positive=True)
        k = sp.Symbol(f"k{tag}", integer=True)
        exprs = [x / (1 + y**2) + sp.sqrt(a) * x / 3, sp.sqrt(a + b) / (a * x) - y / (2 * b),
                 (x - y) ** 2 / (a * b) + sp.sin(x) / a, 1 / (sp.sqrt(a) * b) - 1 / a**2,
                 a**k * x + a ** (k + 1) * y, sp.cos(x) ** 2 / (b - a) + k / 2]
        out = [sp.srepr(sp.factor_terms(sp.together(e))).replace(tag, "") for e in exprs]
        facts = ("zero", "positive", "negative", "nonnegative", "integer", "rational",
                 "finite", "extended_real", "even", "odd", "prime", "composite")
        probes = [*exprs, a - b, a * b + 1, x**2 + a, k**2 - k, 2 * k + 1, a / b - 1, -a - b,
                  sp.sqrt(a) * k, x * y * a, sp.Abs(x) + b]
        out += [[getattr(e, f"is_{f}") for f in facts] for e in probes]
        return out

    reference = answers("_0")
    with quick_sympy.quick_sympy():
        assert answers("_1") == reference
    assert answers("_2") == reference


def test_symbol_order_is_sympys():
    """sorted_symbols gives sorted(..., key=default_sort_key), element for element, on
    the free symbols of the orthodromic model's structured variation and on sets where the two
    keys could part: equal names with different assumptions (ties keep their input
    order under both), names that sort differently as text and as SymPy would if it
    compared anything else, and non-Symbol elements (Dummy, Wild, indexed)."""
    from ins_errors.models import definition
    from ins_errors.symbolic.symbol_order import sorted_symbols
    from ins_errors.symbolic.variation import structured_variation

    def same(items):
        got, expected = sorted_symbols(items), sorted(items, key=sp.default_sort_key)
        assert len(got) == len(expected)
        assert all(a is b for a, b in zip(got, expected, strict=True)), (got, expected)

    checked = 0
    for line in structured_variation(definition("orthodromic")):
        same(list(line.rhs.free_symbols))
        checked += 1
    assert checked > 30
    x_real, x_plain, x_positive = (sp.Symbol("x", real=True), sp.Symbol("x"),
                                   sp.Symbol("x", positive=True))
    names = [sp.Symbol(n) for n in ("b", "B", "a10", "a2", "_a", "Delta_x", "delta_x",
                                    "alpha_z", "\u03b1", "x_c")]
    for order in ([x_real, x_plain, x_positive], [x_positive, x_real, x_plain]):
        same(order + names)
        same(names[::-1] + order)
    i = sp.Idx("i")
    for odd in (sp.Dummy("a"), sp.Wild("a"), sp.Indexed("y", i), sp.Dummy("x")):
        same([odd, *names, x_real])
        same([x_real, *names, odd])
    same([])
