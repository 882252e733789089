"""What :func:`ins_errors.symbolic.analytic.analyse` refuses: a state matrix or a source
column that is not rational in the parametrisation's symbols is named in one line
(AnalysisError), not left to a SymPy conversion error deep in the field arithmetic."""

from __future__ import annotations

import pytest
import sympy as sp

from ins_errors.symbolic.analytic import (
    AnalysisError,
    Frequency,
    Parametrisation,
    T,
    analyse,
)

g, R, W_N, W_U, w_s = sp.symbols("g R Omega_N Omega_U omega_s", positive=True)
SCHULER = Parametrisation(lambda e: e.subs(g, R * w_s**2), {w_s: sp.sqrt(g / R)},
                          (Frequency(w_s, w_s**2, "Schuler"),))


def _loop(extra: sp.Expr) -> sp.Matrix:
    """A Schuler loop (δv, tilt) driven by a third state through ``extra``."""
    return sp.Matrix([[0, -g, 0], [1 / R, 0, extra], [0, 0, 0]])


@pytest.mark.parametrize("entry", [sp.sqrt(W_N**2 + W_U**2) / (W_N * R), sp.sin(W_N),
                                   sp.pi * W_N / R])
def test_an_entry_of_F_outside_the_rational_functions_is_named(entry):
    with pytest.raises(AnalysisError) as caught:
        analyse(_loop(entry), {"tilt": (sp.Matrix([0, 1, 0]), False)}, SCHULER)
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith("F: entry (2, 3) = ")
    assert "not a rational function of the parametrisation's symbols" in message


def test_a_source_column_outside_the_rational_functions_is_named():
    with pytest.raises(AnalysisError, match=r"source 'bias': entry 1 = sqrt\(R\)"):
        analyse(_loop(0), {"bias": (sp.Matrix([sp.sqrt(R), 0, 0]), True)}, SCHULER)


def test_the_same_entry_rewritten_into_a_symbol_is_analysed():
    """The remedy the message names: a Parametrisation that rewrites the root into a
    symbol (here Ω = √(Ω_N² + Ω_U²)) makes the same model analysable."""
    W = sp.Symbol("Omega", positive=True)
    par = Parametrisation(
        lambda e: e.subs(sp.sqrt(W_N**2 + W_U**2), W).subs(g, R * w_s**2),
        {w_s: sp.sqrt(g / R), W: sp.sqrt(W_N**2 + W_U**2)},
        (Frequency(w_s, w_s**2, "Schuler"),))
    result = analyse(_loop(sp.sqrt(W_N**2 + W_U**2) / (W_N * R)),
                     {"tilt": (sp.Matrix([0, 1, 0]), False)}, par)
    assert [m.name for m in result.modes] == ["integrator", "Schuler"]
    # a unit initial tilt swings as cos(ω_s t) (the undisturbed Schuler loop)
    assert sp.simplify(result.responses["tilt"][1] - sp.cos(w_s * T)) == 0
