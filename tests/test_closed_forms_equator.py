"""The closed forms where a denominator of their partial fractions vanishes.

The orthodromic closed forms split the Foucault pair ω± = ω̄ ± Ω_U by partial fractions
that divide by Ω_U = U sin φ; at the equator the pair is one double Schuler pair, and
the general forms gave NaN in 18 of the 26 sources (and `propagation --orthodromic
--latitude 0deg` a traceback). The responses are finite there (F has no Jordan block),
and the generated module now takes forms derived with φ = 0 substituted before the
partial fractions. References: scipy's expm of the model's own F, G and E (generated
numpy functions), never the closed forms.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp
from scipy.linalg import expm

from ins_errors.cli import main
from ins_errors.errors import DomainError
from ins_errors.models import definition
from ins_errors.numeric.closed_forms import closed_form_module, closed_forms
from ins_errors.numeric.model import load_model
from ins_errors.symbolic.static_base import static_analyses

TIMES = np.linspace(0.0, 86400.0, 13)


def _expm_responses(model_name: str, latitude: float, cf) -> np.ndarray:
    """Error states for each unit source, shape (ne, nw, T): expm of [[F, g], [0, 0]]
    for a constant source, expm(F t) e for an initial error."""
    model = load_model(model_name)
    F = model.state_matrix(cf.x, cf.u, cf.p)
    G = model.source_matrix(cf.x, cf.u, cf.p)
    E = model.initial_error_matrix(model.initial_condition_vector(latitude=latitude),
                                   cf.u, cf.p)
    n = F.shape[0]
    out = np.zeros((n, len(model.sources), len(TIMES)))
    for j, source in enumerate(model.sources):
        A = np.zeros((n + 1, n + 1))
        A[:n, :n] = F
        start = np.zeros(n + 1)
        if source.kind == "constant":
            A[:n, n], start[n] = G[:, j], 1.0
        else:
            start[:n] = E[:, j]
        out[:, j] = np.array([(expm(A * t) @ start)[:n] for t in TIMES]).T
    return out


def _assert_close(closed: np.ndarray, reference: np.ndarray, rel: float,
                  floor: float = 0.0) -> None:
    """Each error state to ``rel`` of its largest response over all sources (or of
    ``floor`` times the largest response of all, if that is more)."""
    scale = np.maximum(np.max(np.abs(reference), axis=(1, 2), keepdims=True),
                       floor * np.max(np.abs(reference)))
    assert np.all(np.isfinite(closed))
    assert np.all(np.abs(closed - reference) <= rel * scale)


@pytest.mark.parametrize("model_name", ["orthodromic", "north_pointing"])
@pytest.mark.parametrize("latitude", [0.0, -0.0, np.radians(1e-12), np.radians(-1e-5)])
def test_closed_forms_at_and_near_the_equator_are_scipys_expm(model_name, latitude):
    cf = closed_forms(model_name, latitude)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no divide-by-zero warnings either
        closed = cf.responses(TIMES)
    _assert_close(closed, _expm_responses(model_name, latitude, cf), 1e-9)


@pytest.mark.parametrize("latitude", [1e-160, -1e-300, 5e-324])
def test_the_equatorial_forms_take_over_where_the_general_ones_underflow(latitude):
    """Below |sin φ| = 1e-150 the general forms lose their sin² φ terms and, below
    1e-290, overflow (NaN at 1e-300 before); there the equatorial forms are used. They
    are the φ → 0 limit: every response as expm's, but for the ones that vanish at the
    equator, of size ∝ sin φ, which they give as 0 (below 1e-150 of the others)."""
    cf = closed_forms("orthodromic", latitude)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        closed = cf.responses(TIMES)
    _assert_close(closed, _expm_responses("orthodromic", latitude, cf), 1e-9, floor=1e-145)


def test_a_batch_across_the_equator_mixes_the_two_forms():
    """x batched over latitudes: each point gets the forms that hold there."""
    module = closed_form_module("orthodromic")
    latitudes = np.radians([-20.0, 0.0, 1e-5, 35.0])
    bases = [closed_forms("orthodromic", lat) for lat in latitudes]
    x = np.stack([cf.x for cf in bases], axis=-1)[:, :, None]  # batch (latitude, time)
    u = np.stack([cf.u for cf in bases], axis=-1)[:, :, None]
    batched = module.responses_full(TIMES[None, None, :], x, u, bases[0].p)
    for k, (latitude, cf) in enumerate(zip(latitudes, bases, strict=True)):
        _assert_close(batched[:, :, k, :], _expm_responses("orthodromic", latitude, cf),
                      1e-9)


def _factor_functions(model_name: str):
    """Every factor the general closed forms of every variant divide by, as a numpy
    function of the static base's x, u and p (the model's own symbols)."""
    d = definition(model_name)
    out = []
    for result in static_analyses(model_name):
        a = result.analysis
        for factor in a.denominators:
            expr = a.in_model_symbols(a.parametrisation.to_model(factor))
            out.append((result.variant.name, factor,
                        sp.lambdify([d.x, d.u, d.p], expr, "numpy")))
    return out


@pytest.mark.parametrize("model_name", ["orthodromic", "north_pointing"])
def test_only_the_orthodromic_equator_zeroes_a_denominator_and_it_has_its_limit(model_name):
    """The special latitudes are read off the forms' own denominators (not guessed):
    each factor is evaluated at the static base of a dense latitude grid, both signs,
    and where it vanishes or changes sign inside (−90°, 90°) a limit must be derived for
    it. Only the orthodromic Ω_U = U sin φ does, at 0°; north_pointing's Ω_N = U cos φ
    vanishes only at the poles, outside the domain."""
    grid = np.radians(np.unique(np.r_[np.linspace(-89.9, 89.9, 720), 0.0, 1e-9, -1e-9]))
    bases = [closed_forms(model_name, latitude) for latitude in grid]
    x, u, p = (np.stack([getattr(cf, k) for cf in bases], axis=-1) for k in "xup")
    vanishing = []
    for variant, factor, function in _factor_functions(model_name):
        values = np.broadcast_to(function(x, u, p), grid.shape)
        signs = np.sign(values)
        if np.any(values == 0) or np.any(signs[1:] != signs[:-1]):
            where = float(np.degrees(grid[np.argmin(np.abs(values))]))
            vanishing.append((variant, factor, where))
    if model_name == "orthodromic":
        omega_u = sp.Symbol("Omega_U", positive=True)
        assert vanishing == [("full", omega_u, 0.0)]
        [limit] = static_analyses(model_name)[0].variant.limits
        assert limit.factor == omega_u and limit.name == "equator"
    else:
        assert vanishing == []


def test_a_point_where_the_forms_overflow_is_refused_in_one_line():
    """A time at which the integrators' t⁴ terms overflow gave inf and NaN silently."""
    with pytest.raises(DomainError, match="overflow at this point") as caught:
        closed_forms("orthodromic", np.radians(40.0)).responses(np.array([1e300]))
    assert "\n" not in str(caught.value)


def test_a_denominator_zero_with_no_limit_is_refused_naming_it():
    """Gravity that puts the Schuler frequency exactly on the Earth rate at the equator
    (ω_s = U: a resonance, t sin t terms the forms do not have) is refused naming the
    factor of the equatorial forms that vanishes, not NaN."""
    module = closed_form_module("orthodromic")
    base = closed_forms("orthodromic", 0.0)
    model = load_model("orthodromic")
    a = base.p[[q.name for q in model.parameters].index("a")]
    k = [i.name for i in model.inputs].index("a_zeta")
    index = module.DENOMINATORS["full"].index(
        "20000000000*omega_s - 1458423 = 20000000000*sqrt(a_zeta/a) - 1458423")
    gravity = (1458423 / 20000000000) ** 2 * a
    u = base.u.copy()
    for _ in range(64):  # the nearest double at which the factor is exactly 0
        u[k] = gravity
        value = module._denominators_full(base.x, u, base.p)[index]
        if value == 0:
            break
        gravity = np.nextafter(gravity, np.inf if value < 0 else -np.inf)
    assert value == 0
    with pytest.raises(DomainError, match=r"divide by .*20000000000\*omega_s - 1458423"):
        closed_forms("orthodromic", 0.0, gravity=gravity).responses(TIMES)


def test_propagation_orthodromic_at_the_equator_runs(tmp_path, capsys):
    """The probe's command (a traceback and ~80 RuntimeWarnings before), shortened."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert main(["propagation", "--orthodromic", "--latitude", "0deg", "--hours",
                     "0.25", "--step", "30s", "--out", str(tmp_path / "eq")]) == 0
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err and "nan" not in captured.out.lower()
    assert (tmp_path / "eq" / "orthodromic_day.md").is_file()
