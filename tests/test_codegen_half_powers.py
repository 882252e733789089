"""Half-integer powers are printed as a square root and products (no ``pow`` call).

``x**(p/2)`` for odd ``|p| >= 3`` is emitted as ``x**n * sqrt(x)`` (inverted for
``p < 0``) in both backends. Reference: mpmath at 40 digits, independent of the printer
and of the C library. Tolerance: the rounding count of the printed form times the unit
roundoff 2^-53 (every +, ×, /, sqrt is correctly rounded; ``x**3`` is numpy's ``pow``,
below one unit roundoff in glibc, or CasADi's ``x*sq(x)``, two roundings), so a form with
one more rounding than stated, or a wrong power, fails.
"""

from __future__ import annotations

import re
from pathlib import Path

import casadi as ca
import mpmath
import numpy as np
import pytest
import sympy as sp

from ins_errors.symbolic.codegen import CASADI_PRINTER, NUMPY_PRINTER

U = 2.0**-53
ROUNDINGS = {3: 2, -3: 3, 5: 3, -5: 4, 7: 4, -7: 5}
"""Roundings of the printed ``x**(p/2)``: sqrt and one product for 3/2, plus the square
(5/2) or the cube (7/2, two), plus the division of a negative power."""

ROOT = Path(__file__).resolve().parent.parent


def _points() -> np.ndarray:
    rng = np.random.default_rng(2024)
    wide = 10.0 ** rng.uniform(-6, 6, 1500)
    # the ellipsoid's 1 - e² sin²φ, the base these powers have in the models
    ellipsoid = 1 - 0.00669438 * np.sin(rng.uniform(-np.pi / 2, np.pi / 2, 1500)) ** 2
    return np.concatenate([wide, ellipsoid])


@pytest.mark.parametrize("p", sorted(ROUNDINGS))
def test_half_powers_are_within_their_rounding_count(p):
    symbol = sp.Symbol("x", positive=True)
    expr = sp.Pow(symbol, sp.Rational(p, 2))
    numpy_text, casadi_text = NUMPY_PRINTER.doprint(expr), CASADI_PRINTER.doprint(expr)
    assert "**((" not in numpy_text and "sqrt" in numpy_text   # no pow of a fraction
    x = _points()
    with mpmath.workdps(40):
        exact = [mpmath.power(mpmath.mpf(float(v)), mpmath.mpf(p) / 2) for v in x]
    got_np = eval(numpy_text, {"_m": np, "x": x})
    xs = ca.SX.sym("x", x.size)
    got_ca = np.asarray(ca.Function("f", [xs], [eval(casadi_text, {"_m": ca, "x": xs})])(
        x)).ravel()
    bound = ROUNDINGS[p] * U * (1 + 1e-9)
    for got in (got_np, got_ca):
        with mpmath.workdps(40):
            worst = max(abs((mpmath.mpf(float(g)) - e) / e) for g, e in zip(got, exact,
                                                                            strict=True))
        assert worst <= bound, (p, float(worst) / U)
    # the two backends print the same operations: CasADi's x*sq(x) may differ from
    # numpy's pow(x, 3) for |p| = 7, every other form gives the same bits
    if abs(p) < 7:
        assert np.array_equal(got_np, got_ca)


def test_half_power_bases_are_parenthesised():
    x, y = sp.symbols("x y", positive=True)
    text = NUMPY_PRINTER.doprint(y / (x + y) ** sp.Rational(3, 2))
    value = eval(text, {"_m": np, "x": 2.0, "y": 3.0})
    assert value == pytest.approx(3.0 / 5.0**1.5, rel=4 * U)


def test_generated_models_have_no_fractional_pow():
    """What the loops compile: every model's generated code takes no power of a fraction
    (a half-integer power would be a call to the C library's ``pow``)."""
    files = sorted((ROOT / "generated").glob("*/*_model.py"))
    assert len(files) >= 10
    for path in files:
        assert not re.search(r"\*\*\(\(-?\d+/\d+\)\)", path.read_text()), path
