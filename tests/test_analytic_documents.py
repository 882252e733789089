"""The forms transfer_functions.md prints equal the model's own F, (sI − F)⁻¹ and responses.

The document's F, Δ(s), adjugate entries and time responses (the SymPy objects
``derive.transfer_functions.shown_forms`` prints, after their rewriting with identities
such as ω₊ω₋ = ω_s²) are evaluated with the printed definitions of their symbols at a
latitude and compared with independent numerics of the generated model: its numeric F,
numpy's determinant and inverse of sI − F at complex s, and scipy's expm for the
responses (x(t) = e^{Ft} x₀ for initial errors, ∫₀ᵗ e^{Fτ} g dτ for constant sources).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.linalg import expm

from derive.transfer_functions import markdown, shown_forms
from ins_errors.numeric.closed_forms import closed_forms
from ins_errors.numeric.model import load_model
from ins_errors.symbolic.simplifications import simplification
from ins_errors.symbolic.static_base import static_analyses
from tests.helpers import one_blas_thread_for_references

LATITUDE = 0.7
S_POINTS = (4e-4 + 1.3e-3j, 5e-5 + 2e-4j, 2e-3 + 1e-5j)
TIMES = (1000.0, 30000.0)


def _numbers(model):
    """Numeric static base: x, u, p (consistent apparent accelerations), by symbol name."""
    cf = closed_forms(model, LATITUDE)
    x, u, p = cf.x, cf.u.copy(), cf.p
    if "a_xi" in [i.name for i in model.inputs]:
        f = model.ideal_rhs(x, u, p)
        u[0], u[1] = -f[6], -f[7]
    values = {q.name: float(v) for q, v in zip(model.parameters, p, strict=True)}
    values.update({i.name: float(v) for i, v in zip(model.inputs, u, strict=True)})
    values.update({s.name: float(v) for s, v in zip(model.states, x, strict=True)})
    values["phi"] = LATITUDE
    return x, u, p, values


def _evaluate(expr, forms, values, **more):
    for _ in range(len(forms.definitions) + 1):
        if not expr.free_symbols & forms.definitions.keys():
            break
        expr = expr.xreplace(forms.definitions)
    numbers = {**values, **more}
    rule = {q: numbers[q.name] for q in expr.free_symbols}
    return complex(sp.N(expr.xreplace(rule), 30))


@pytest.fixture(scope="module", params=["north_pointing", "orthodromic"])
def documented(request):
    name = request.param
    return name, [(r, shown_forms(name, r)) for r in static_analyses(name)]


def _numeric_F(model, result, x, u, p):
    F = model.state_matrix(x, u, p)
    if result.variant.simplification:
        names = [s.name for s in model.error_states]
        for term in simplification(result.variant.simplification).terms:
            F[names.index(term.equation), names.index(term.variable)] = 0.0
    return F


def test_printed_state_matrix_and_determinant_are_the_models(documented):
    name, variants = documented
    model = load_model(name)
    x, u, p, values = _numbers(model)
    for result, forms in variants:
        F = _numeric_F(model, result, x, u, p)
        shown = np.array([[_evaluate(e, forms, values).real for e in forms.state_matrix.row(i)]
                          for i in range(F.shape[0])])
        assert np.allclose(shown, F, rtol=1e-12, atol=1e-14 * np.max(np.abs(F)))
        for s in S_POINTS:
            det = np.linalg.det(s * np.eye(F.shape[0]) - F)
            got = _evaluate(forms.characteristic, forms, values, s=s)
            assert abs(got - det) <= 1e-9 * abs(det), (result.variant.name, s)


def test_printed_resolvent_is_numpys_inverse(documented):
    name, variants = documented
    model = load_model(name)
    x, u, p, values = _numbers(model)
    for result, forms in variants:
        if not forms.adjugate:
            assert name == "orthodromic"  # not printed (the document says why)
            continue
        F = _numeric_F(model, result, x, u, p)
        n = F.shape[0]
        assert len(forms.adjugate) + len(forms.zero_adjugate) == n * n
        for s in S_POINTS:
            inverse = np.linalg.inv(s * np.eye(n) - F)
            delta = _evaluate(forms.characteristic, forms, values, s=s)
            scale = np.max(np.abs(inverse))
            for (i, j), terms in forms.adjugate.items():
                numerator = _evaluate(sp.Add(*[c * sp.Symbol("s") ** k for k, c in terms]),
                                      forms, values, s=s)
                assert abs(numerator / delta - inverse[i, j]) <= 1e-8 * scale, (i, j, s)
            for i, j in forms.zero_adjugate:
                assert abs(inverse[i, j]) <= 1e-12 * scale, (i, j)


def test_printed_responses_are_scipys_expm(documented):
    name, variants = documented
    model = load_model(name)
    x, u, p, values = _numbers(model)
    G = model.source_matrix(x, u, p)
    E = model.initial_error_matrix(model.initial_condition_vector(latitude=LATITUDE), u, p)
    checked = 0
    for result, forms in variants:
        if forms.responses is None:
            assert name == "orthodromic"  # not printed (the document says why)
            continue
        F = _numeric_F(model, result, x, u, p)
        n = F.shape[0]
        references = {}
        with one_blas_thread_for_references():
            for j, source in enumerate(model.sources):
                for t in TIMES:
                    if source.kind == "constant":
                        augmented = np.zeros((n + 1, n + 1))
                        augmented[:n, :n], augmented[:n, n] = F, G[:, j]
                        references[j, t] = expm(augmented * t)[:n, n]
                    else:
                        references[j, t] = expm(F * t) @ E[:, j]
        for j, source in enumerate(model.sources):
            for t in TIMES:
                expected = references[j, t]
                scale = max(np.max(np.abs(expected)), 1e-300)
                shown = forms.responses[source.name]
                for i in range(n):
                    if i in shown:
                        got = _evaluate(shown[i], forms, values, t=t)
                        assert abs(got - expected[i]) <= 1e-7 * scale, (source.name, i, t)
                        checked += 1
                    else:  # left out: identically zero, as the document says
                        assert abs(expected[i]) <= 1e-9 * scale, (source.name, i, t)
    assert name == "orthodromic" or checked > 100


def test_documents_name_what_they_leave_out_and_keep_constants_symbolic(documented):
    name, variants = documented
    # north_pointing's printed forms are the fixture's (computing them again is most of
    # this test's cost); orthodromic's (cheap) are computed by markdown itself
    shown = None if name == "orthodromic" else [forms for _, forms in variants]
    text = markdown(name, [r for r, _ in variants], shown)
    assert "Laplace-domain forms above" not in text
    assert "derived for this value only" in text  # the constants table
    for number in ("1458423", "6378245 u", "2713302421307331921"):  # U, a as numbers
        assert number not in text.split("## ", 1)[1], number
    if name == "north_pointing":
        assert "Entries not listed are identically zero: $\\operatorname{adj}_{14}$" in text
        assert "Identically zero: " in text
        assert "(\\Omega_U - \\bar\\omega)" not in text.replace("\\left", "").replace(
            "\\right", "")
    else:
        assert "(sI − F)⁻¹ is not printed for this model" in text
