"""The shortcuts of the static-base analysis and the code printer give the same values.

References: SymPy's full Taylor shift, its dense inverse, each backend's own printer, and
a sum of residues checked against the rational function itself.
"""

from __future__ import annotations

import sympy as sp
from sympy.polys.matrices import DomainMatrix

from ins_errors.symbolic import analytic as an


def _field_and_symbols():
    g, R, W = sp.symbols("g R Omega", positive=True)
    return sp.QQ.frac_field(g, R, W), (g, R, W)


def test_taylor_head_is_the_start_of_sympys_taylor_shift():
    field, (g, R, W) = _field_and_symbols()
    z = an.Z
    poly = sp.Poly((z + g / R) ** 2 * (z + W**2) * (3 * z - g), z, domain=field)
    point = -g / R
    full = poly.shift(point).all_coeffs()[::-1]
    for count in (1, 2, 3, 7):
        assert an._taylor_head(poly, point, count) == full[:count]
    assert an._taylor_head(sp.Poly(0, z, domain=field), point, 2) == [0]
    # the pole table passes the point already converted to the field: same coefficients
    for count in (1, 2, 3, 7):
        assert an._taylor_head(poly, field.convert(point), count) == full[:count]


def test_partial_fractions_sum_back_to_the_fraction():
    field, (g, R, W) = _field_and_symbols()
    z = an.Z
    schuler = an.Mode("Schuler", sp.Symbol("w_s"), g / R, 2)
    earth = an.Mode("Earth", W, W**2, 1)
    den = sp.Poly((z + g / R) ** 2 * (z + W**2), z, domain=field)
    num = sp.Poly(z**2 - 5 * g * z + R, z, domain=field)
    table = an._PoleTable([schuler, earth], field)
    parts = table.partial_fractions(num, den)
    assert table.partial_fractions(num, den) == parts  # the memo answers the same
    total = sum(c / (z + m.squared) ** p for c, m, p in parts)
    assert sp.cancel(total - num.as_expr() / den.as_expr()) == 0


def _pole_table_cases():
    """Modes with polynomial ω² (as in the static analyses) and one with ω² = g/R."""
    field, (g, R, W) = _field_and_symbols()
    z = an.Z
    schuler = an.Mode("Schuler", sp.Symbol("w_s"), g * R, 2)
    earth = an.Mode("Earth", W, W**2, 1)
    integrator = an.Mode("integrator", None, sp.S.Zero, 1)
    rational = an.Mode("rational", sp.Symbol("w_r"), g / R, 1)
    dens = [sp.Poly(d, z, domain=field) for d in (
        (z + g * R) ** 2 * (z + W**2), 3 * R * (z + g * R) * (z + W**2) ** 2,
        sp.Rational(2, 5) * z * (z + W**2) * (z + g * R) ** 2)]
    nums = [sp.Poly(n, z, domain=field) for n in (
        z**2 - 5 * g * z + R, 3 * z - g * W, sp.Rational(-2, 7) * z**2 + W**2 * R,
        sp.Integer(4), (g - R * W**2) * (z + g * R) * W, g * (g - R * W**2) ** 2,
        z / R + g)]
    return field, (schuler, earth, integrator), rational, dens, nums


def test_pole_table_in_the_ring_gives_the_fields_coefficients():
    field, modes, rational, dens, nums = _pole_table_cases()
    z = an.Z
    cases = [(modes, den) for den in dens] + [  # ω² = g/R: the field throughout
        ((rational, *modes), sp.Poly((z + rational.squared) * (z + modes[1].squared), z,
                                     domain=field))]
    for poles, den in cases:
        ring_table, field_table = an._PoleTable(poles, field), an._PoleTable(poles, field)
        field_table.ring = None  # the reference: every operation in the field
        for num in nums:
            if num.degree() < den.degree():
                assert ring_table.partial_fractions(num, den) == \
                    field_table.partial_fractions(num, den)


def test_factored_partial_fractions_are_sympys_factorisations():
    field, modes, rational, dens, nums = _pole_table_cases()
    table = an._PoleTable(modes, field)
    checked = 0
    for den in dens:
        for num in nums:
            if num.degree() >= den.degree():
                continue
            factored = table.factored_fractions(num, den)
            if num == nums[-1]:  # a coefficient that is no polynomial: not in the ring
                assert factored is None
                continue
            expected = [(sp.factor(field.to_sympy(c)), m, p)  # (a zero value is left out)
                        for c, m, p in table.partial_fractions(num, den)]
            assert factored == [e for e in expected if e[0] != 0]
            checked += len(expected)
    assert checked > 30
    den = sp.Poly(an.Z + rational.squared, an.Z, domain=field)
    assert an._PoleTable((rational,), field).factored_fractions(nums[3], den) is None


def test_fraction_free_inverse_gives_the_fields_own_elements():
    s = an.S
    g, R, W = sp.symbols("g R Omega", positive=True)
    F = sp.Matrix([[0, 1, 0, 0], [-g / R, 0, 2 * W, 0], [0, -2 * W, 0, 1], [0, 0, -g / R, 0]])
    outer = sp.QQ.frac_field(s, g, R, W)
    matrix = DomainMatrix.from_list_sympy(4, 4, (s * sp.eye(4) - F).tolist()).convert_to(outer)
    B = DomainMatrix.from_list_sympy(4, 3, [[1, 0, g / 3], [0, W / R, 0], [0, 0, 1],
                                            [R, 0, -W**2]]).convert_to(outer)
    dense = matrix.inv()  # the reference: Gauss-Jordan over the field
    expected = (dense * B).to_Matrix()
    inverse = an._FractionFreeInverse(matrix)
    product = inverse.times(B)
    assert sp.Matrix(4, 3, [outer.to_sympy(e) for row in product for e in row]) == expected
    for row, reference in zip(product, (dense * B).rep.to_ddm(), strict=True):
        for e, r in zip(row, reference, strict=True):  # the same cancelled representation
            assert (e.numer, e.denom) == (r.numer, r.denom)
    assert inverse.inverse().to_Matrix() == dense.to_Matrix()
    determinant = matrix.det()  # the adjugate: A⁻¹ det A, and any other factor
    for factor in (determinant, outer.from_sympy(g / (3 * R) + s), outer.one):
        scaled = inverse.scaled_inverse(factor)
        for row, reference in zip(scaled.rep.to_ddm(), (dense * factor).rep.to_ddm(),
                                  strict=True):
            for e, r in zip(row, reference, strict=True):
                assert (e.numer, e.denom) == (r.numer, r.denom)


def test_division_by_s_gives_the_fields_quotient():
    s = an.S
    g, R, W = sp.symbols("g R Omega", positive=True)
    outer = sp.QQ.frac_field(s, g, R, W)
    s_elem = outer.from_sympy(s)
    values = [(s**2 + g) / (3 * R * s + W), s * (g - R) / (s**2 + W**2), sp.Integer(0),
              sp.Rational(-2, 7) * s**3 / (R * (s + 1)), (g * s + R) / s**2, 5 / s,
              (s * g / 3 + W**2 * s**2) / (s**2 - g / R) ** 2, -g / (2 * W), s / 4]
    for v in values:
        element = outer.from_sympy(v)
        quotient, reference = an._over_first_generator(element), element / s_elem
        assert (quotient.numer, quotient.denom) == (reference.numer, reference.denom), v


def test_one_printing_serves_both_backends():
    from ins_errors.symbolic import codegen

    x, y = sp.symbols("x y", real=True)
    expr = (sp.asin(x) + sp.acos(y) * sp.atan(x / y) - sp.atan2(y, x) + sp.Abs(x) ** 3
            + 1 / sp.sqrt(x**2 + y**2) + sp.exp(-sp.tanh(x)) * sp.log(sp.cosh(y))
            + sp.pi * sp.sinh(x) / sp.tan(y) - sp.Rational(3, 7) * sp.sqrt(sp.sin(x)))
    neutral = codegen._NEUTRAL_PRINTER.doprint(expr)
    assert codegen._in_backend(neutral, codegen._NUMPY_NAMES) == \
        codegen.NUMPY_PRINTER.doprint(expr)
    assert codegen._in_backend(neutral, codegen._CASADI_NAMES) == \
        codegen.CASADI_PRINTER.doprint(expr)


def test_remembered_factor_lists_give_sympys_factorisations():
    g, R, W = sp.symbols("g R Omega", positive=True)
    shared = (g + R * W**2) * (g - R * W**2)
    coefficients = [shared / (R * (W**2 + 1)), 3 * shared**2 / (g * R - R**2 * W),
                    -shared / (2 * (W**2 + 1) ** 2)]
    expected = [sp.factor(c) for c in coefficients]
    original = sp.Poly.factor_list
    with an.factor_lists_remembered():
        assert [sp.factor(c) for c in coefficients + coefficients] == expected + expected
    assert sp.Poly.factor_list is original


def test_factor_product_equals_sympys_factor():
    field, (g, R, W) = _field_and_symbols()
    z = an.Z
    schuler = an.Mode("Schuler", sp.Symbol("w_s"), g / R, 2)
    earth = an.Mode("Earth", W, W**2, 1)
    table = an._PoleTable([schuler, earth], field)
    den = sp.Poly((z + g / R) ** 2 * (z + W**2), z, domain=field)
    coefficients = []
    for num in (z**2 - 5 * g * z + R, 3 * z - g * W, sp.Rational(-2, 7) * z**2 + W**2 * R):
        coefficients += [c for c, _, _ in table.partial_fractions(
            sp.Poly(num, z, domain=field), den)]
    a, b = sp.symbols("a b", real=True)
    coefficients += [  # the shapes of partial-fraction coefficients, and what falls back
        (a - b) * (b - a) ** 3 / (2 * (a**2 - b**2)), -6 * (a + 2 * b) ** 2 / (4 * a - 8 * b),
        (b - a) / (a**2 + 2 * a * b + b**2) ** 2, -a / b, sp.Integer(3), sp.Rational(-1, 2),
        a / (b + 1) + b / (a - 1), sp.sin(a) * (a**2 - 1) / (a + 1), sp.sqrt(a) * (a - b)]
    assert len(coefficients) > 12
    for c in coefficients:
        assert an.factor_product(c) == sp.factor(c), c


def test_operation_count_is_sympys_count_of_the_cse_result():
    from ins_errors.symbolic import codegen

    x, y = sp.symbols("x y", real=True)
    matrix = sp.Matrix([sp.sin(x) * y + sp.sin(x) ** 2 - x / y, (x - y) ** 3 / sp.sqrt(x)])
    spec = codegen.FunctionSpec("f", [codegen.Argument("v", [x, y], "")], matrix, "", "")
    prepared = codegen.prepare(spec)
    expected = sum(sp.count_ops(e) for _, e in prepared.assignments) + sum(
        sp.count_ops(e) for _, _, e in prepared.entries)
    assert prepared.operations == expected > 0


def test_static_matrices_from_the_varied_model_equal_the_direct_jacobians():
    from ins_errors.models import definition
    from ins_errors.symbolic import variation
    from ins_errors.symbolic.static_base import setup, static_matrices

    name = "north_pointing"
    point = setup(name).point
    initial = {sp.Symbol("latitude", real=True): sp.Rational(1, 3)}
    variation._LAST_VARIED = None
    direct = static_matrices(name, point, initial)  # differentiates the equations itself
    variation.vary(definition(name))
    assert variation.last_varied(definition(name)) is not None
    assert variation.last_varied(definition("free_azimuth")) is None
    reused = static_matrices(name, point, initial)  # substitutes into vary's F, G, E
    for a, b in zip(direct, reused, strict=True):
        assert a == b
        assert [sp.srepr(e) for e in a] == [sp.srepr(e) for e in b]
