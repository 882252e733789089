"""Numeric transfer functions (``ins_errors.analysis.transfer``) against references
independent of the code under test.

1. north_pointing's own SymPy error equations (the variation of its definition, not the
   generated numpy code), evaluated at 30 digits: h (iωI − F)⁻¹ g solved by mpmath at
   s = iω, against the factored form (after the reduction) at the same s.
2. The textbook Schuler loop (examples/own_model/schuler_loop.py): δV' = −g ψ + ∇ + ...,
   ψ' = δV/R + ε, δφ' = δV/R give, with ω_s² = g/R from the model's own g and R,
   ψ/∇ = δφ/∇ = (1/R)/(s² + ω_s²), δV/∇ = s/(s² + ω_s²), δφ/ε = −ω_s²/(s (s² + ω_s²)):
   the tilt from a bias oscillates about ∇/g with amplitude ∇/g, the velocity about 0 with
   amplitude ∇/ω_s, and a drift ε makes the latitude error grow as −ε t.
3. The time response rebuilt from the printed partial fractions (--json) against the
   matrix exponential of ẋ = F x + g b (scipy), for constant sources and initial errors.
4. Cancellation argued from the equations: in north_pointing the ψ-angle
   ψ = (α_E + δφ, α_N − δλ cos φ, α_U − δλ sin φ) obeys ψ' = −Ω × ψ + ε, which an
   accelerometer bias does not enter; ψ carries F's Earth pair and one integrator, so an
   accelerometer bias never excites them (checked here on the model's own F and G by
   the matrix exponential), and its transfer functions are of order 4 of 7. In the
   Schuler loop, δφ − ψ obeys (δφ − ψ)' = −ε: a bias does not reach that integrator.
"""

from __future__ import annotations

import math
from pathlib import Path

import mpmath
import numpy as np
import pytest
import scipy.linalg as sl
import sympy as sp

from ins_errors import load_model
from ins_errors.analysis.transfer import transfer_functions

ROOT = Path(__file__).resolve().parent.parent
SCHULER = str(ROOT / "examples" / "own_model" / "schuler_loop.py")


# --------------------------------------------------------------------------------------
# 1. against the model's SymPy equations at 30 digits
# --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def north_pointing_symbolic():
    from ins_errors.symbolic.variation import vary

    model = load_model("north_pointing")
    return model, vary(model.symbolic)


def _symbolic_w(model, varied, latitude: sp.Expr, source: str, output: str,
                omega: float) -> complex:
    """h (iωI − F)⁻¹ g from the SymPy F, G (or E) and H at rest, 30 digits."""
    d = model.symbolic
    longitude = sp.pi / 6
    values = {"V_E": 0, "V_N": 0, "phi": latitude, "lam": longitude, "a_E": 0, "a_N": 0,
              "h": 0, "latitude": latitude, "longitude": longitude, "v_N": 0, "v_E": 0}
    values.update({p.name: sp.Rational(repr(p.default)) for p in model.parameters})
    symbols = [*d.states, *d.inputs, *d.parameters, *d.initial_conditions]
    point = {v.symbol: values[v.name] for v in symbols}
    j = model.index("sources", source)
    kind = model.sources[j].kind
    column = (varied.initial_error_matrix if kind == "initial" else varied.source_matrix)[:, j]
    row = varied.output_matrix[model.index("outputs", output), :]
    mpmath.mp.dps = 30

    def numeric(matrix):
        return mpmath.matrix([[mpmath.mpf(str(sp.N(e.subs(point), 40))) for e in
                               matrix.row(i)] for i in range(matrix.rows)])

    F, g, h = numeric(varied.state_matrix), numeric(column), numeric(row)
    n = F.rows
    A = mpmath.matrix(n, n)
    for i in range(n):
        for k in range(n):
            A[i, k] = (1j * mpmath.mpf(omega) if i == k else 0) - F[i, k]
    x = mpmath.lu_solve(A, g)
    return complex(sum(h[0, k] * x[k] for k in range(n)))


PAIRS = [("gyro_drift_east", "latitude"), ("gyro_drift_up", "longitude"),
         ("accel_bias_north", "v_E"), ("accel_bias_east", "longitude"),
         ("initial_azimuth_error", "latitude"), ("initial_tilt_north", "v_N"),
         ("initial_velocity_error_east", "longitude")]
OMEGAS = [3.1e-6, 5.3e-5, 9.7e-4, 1.27e-3, 2.2e-2]  # rad/s: below, between, above the modes


@pytest.mark.parametrize("degrees, exact", [(45.0, sp.pi / 4), (-30.0, -sp.pi / 6),
                                            (72.0, sp.pi * 2 / 5)])
def test_north_pointing_agrees_with_its_sympy_equations_at_30_digits(
        north_pointing_symbolic, degrees, exact):
    model, varied = north_pointing_symbolic
    result = transfer_functions(model, sorted({s for s, _ in PAIRS}),
                                sorted({o for _, o in PAIRS}), latitude=np.radians(degrees))
    for source, output in PAIRS:
        pair = result.pair(source, output)
        assert not pair.is_zero
        for omega in OMEGAS:
            expected = _symbolic_w(model, varied, exact, source, output, omega)
            got = complex(pair(1j * omega))
            assert abs(got - expected) <= 1e-9 * abs(expected), (source, output, omega)


# --------------------------------------------------------------------------------------
# 2. the textbook Schuler loop
# --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def schuler():
    model = load_model(SCHULER)
    defaults = {p.name: p.default for p in model.parameters}
    result = transfer_functions(model, ["accel_bias", "gyro_drift"],
                                ["psi", "latitude", "v_N"], latitude=np.radians(35.0))
    return result, defaults["R"], defaults["g"]


def test_schuler_loop_accelerometer_bias_to_tilt_and_latitude_is_one_over_r(schuler):
    result, R, g = schuler
    omega_s = math.sqrt(g / R)
    for output in ("psi", "latitude"):
        pair = result.pair("accel_bias", output)
        assert (pair.order, pair.full_order, pair.relative_degree) == (2, 3, 2)
        assert pair.zeros == ()
        (pole,) = pair.poles
        assert pole.name == "Schuler" and pole.multiplicity == 1
        assert pole.value.real == 0 and pole.value.imag == pytest.approx(omega_s, rel=1e-12)
        assert pair.gain == pytest.approx(1 / R, rel=1e-12)
        for omega in OMEGAS:
            assert complex(pair(1j * omega)) == pytest.approx(
                (1 / R) / (omega_s**2 - omega**2), rel=1e-10)
        # the tilt (and the latitude error with it) oscillates about bias/g, amplitude bias/g
        run = pair.long_run
        assert run.kind == "constant" and run.power == 0
        assert run.coefficient == pytest.approx(1 / g, rel=1e-12)
        (wave,) = run.oscillations
        assert wave.name == "Schuler"
        assert wave.period_s == pytest.approx(2 * math.pi * math.sqrt(R / g), rel=1e-12)
        assert wave.amplitude == pytest.approx(1 / g, rel=1e-10)
        assert [f.name for f in pair.cancelled] == ["integrator"]


def test_schuler_loop_accelerometer_bias_to_velocity_and_drift_to_latitude(schuler):
    result, R, g = schuler
    omega_s = math.sqrt(g / R)
    velocity = result.pair("accel_bias", "v_N")
    assert [(z.value, z.multiplicity) for z in velocity.zeros] == [(0, 1)]
    assert velocity.gain == pytest.approx(1.0, rel=1e-12)
    for omega in OMEGAS:
        assert complex(velocity(1j * omega)) == pytest.approx(
            1j * omega / (omega_s**2 - omega**2), rel=1e-10)
    assert velocity.long_run.kind == "zero"  # δV = (∇/ω_s) sin ω_s t: about zero
    assert velocity.long_run.oscillations[0].amplitude == pytest.approx(1 / omega_s, rel=1e-10)
    drift = result.pair("gyro_drift", "latitude")
    assert (drift.order, drift.cancelled) == (3, ())
    assert drift.gain == pytest.approx(-omega_s**2, rel=1e-12)
    assert sorted(f.name for f in drift.poles) == ["Schuler", "integrator"]
    for omega in OMEGAS:
        assert complex(drift(1j * omega)) == pytest.approx(
            -omega_s**2 / (1j * omega * (omega_s**2 - omega**2)), rel=1e-10)
    # a level gyro drift: the latitude error grows as −ε t
    assert (drift.long_run.kind, drift.long_run.power) == ("power", 1)
    assert drift.long_run.coefficient == pytest.approx(-1.0, rel=1e-10)


# --------------------------------------------------------------------------------------
# 3. the partial fractions against the matrix exponential
# --------------------------------------------------------------------------------------
def _expm_response(model, result, source: str, output: str, times, b: float):
    """y(t) of ẋ = F x + g b (a constant source) or of x(0) = e b (an initial error)."""
    point, F = result.modes.point, result.modes.state_matrix
    j = model.index("sources", source)
    names = [o.name for o in model.outputs]
    h = (model.output_matrix(point.x, point.u, point.p)[names.index(output)]
         if output in names else np.eye(len(F))[model.index("error_states", output)])
    n = len(F)
    out = []
    for t in times:
        if model.sources[j].kind == "initial":
            e = model.initial_error_matrix(point.c, point.u, point.p)[:, j]
            x = sl.expm(F * t) @ e
        else:
            M = np.zeros((n + 1, n + 1))
            M[:n, :n] = F
            M[:n, n] = model.source_matrix(point.x, point.u, point.p)[:, j]
            x = sl.expm(M * t)[:n, n]
        out.append(b * (h @ x))
    return np.array(out)


def _from_partial_fractions(data: dict, times: np.ndarray, b: float) -> np.ndarray:
    """y(t) = b Σ_p Σ_j r_pj t^(j−1)/(j−1)! e^(pt), from the JSON's partial fractions."""
    total = np.zeros(len(times), dtype=complex)
    for term in data["partial_fractions"]:
        pole = complex(term["pole"]["real"], term["pole"]["imag"])
        for j, r in enumerate(term["coefficients"]):
            total += (complex(r["real"], r["imag"]) * times**j / math.factorial(j)
                      * np.exp(pole * times))
    return b * total.real


@pytest.mark.parametrize("model_name, latitude, pairs, hours", [
    ("north_pointing", 40.0, [("gyro_drift_east", "latitude"), ("gyro_drift_up", "longitude"),
                              ("accel_bias_north", "v_N"), ("initial_azimuth_error", "v_E"),
                              ("initial_latitude_error", "longitude")], (0.2, 1, 6, 30)),
    (SCHULER, 50.0, [("gyro_drift", "latitude"), ("accel_bias", "psi"),
                     ("initial_tilt", "latitude")], (0.2, 1, 6, 30)),
    # the undamped vertical channel grows: times it leaves within reach of double precision
    ("strapdown_ned", -35.0, [("accel_bias_z", "height"), ("gyro_bias_y", "latitude"),
                              ("initial_heading_error", "v_E")], (0.05, 0.25, 0.5, 1.0)),
])
def test_partial_fractions_give_the_matrix_exponential_response(model_name, latitude, pairs,
                                                                 hours):
    model = load_model(model_name)
    result = transfer_functions(model, sorted({s for s, _ in pairs}),
                                sorted({o for _, o in pairs}), latitude=np.radians(latitude))
    times = np.array(hours) * 3600.0
    for source, output in pairs:
        pair = result.pair(source, output)
        b = 3.0 * pair.magnitude
        expected = _expm_response(model, result, source, output, times, b)
        got = _from_partial_fractions(pair.to_dict(), times, b)
        assert np.abs(got - expected).max() <= 1e-8 * np.abs(expected).max(), (source, output)
        np.testing.assert_allclose(pair.response(times, b), got, rtol=1e-12,
                                   atol=1e-12 * np.abs(got).max())


# --------------------------------------------------------------------------------------
# 4. cancellation
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("degrees", [45.0, -30.0, 70.0])
def test_accelerometer_bias_does_not_excite_the_earth_mode_of_north_pointing(degrees):
    model = load_model("north_pointing")
    latitude = np.radians(degrees)
    result = transfer_functions(model, ["accel_bias_north", "accel_bias_east",
                                        "gyro_drift_east"], None, latitude=latitude)
    # the premise, on the model's own F and G: ψ stays zero under an accelerometer bias
    point, F = result.modes.point, result.modes.state_matrix
    G = model.source_matrix(point.x, point.u, point.p)
    n = len(F)
    for source in ("accel_bias_north", "accel_bias_east"):
        M = np.zeros((n + 1, n + 1))
        M[:n, :n] = F
        M[:n, n] = G[:, model.index("sources", source)]
        for t in (3600.0, 5e4, 86400.0):
            x = dict(zip([e.name for e in model.error_states], sl.expm(M * t)[:n, n],
                         strict=True))
            phi, lam, a_E = x["delta_latitude"], x["delta_longitude"], x["alpha_E"]
            psi = (a_E + phi, x["alpha_N"] - lam * np.cos(latitude),
                   x["alpha_U"] - lam * np.sin(latitude))
            assert np.abs(psi).max() <= 1e-12 * max(abs(phi), abs(lam), abs(a_E))
        for output in ("latitude", "longitude", "v_N", "v_E"):
            pair = result.pair(source, output)
            assert (pair.order, pair.full_order) == (4, 7), (source, output)
            assert sorted(f.name for f in pair.cancelled) == ["Earth", "integrator"]
            assert {f.name for f in pair.poles} == {"Schuler − Foucault", "Schuler + Foucault"}
    # a gyro drift enters ψ' and excites the Earth mode
    drift = result.pair("gyro_drift_east", "latitude")
    assert "Earth" in {f.name for f in drift.poles}
    assert "Earth" not in {f.name for f in drift.cancelled}


def test_schuler_loop_bias_does_not_reach_the_integrator_of_latitude_minus_tilt(schuler):
    result, _, _ = schuler
    model = load_model(SCHULER)
    point, F = result.modes.point, result.modes.state_matrix
    G = model.source_matrix(point.x, point.u, point.p)
    names = [s.name for s in model.error_states]
    phi, psi = names.index("delta_phi"), names.index("psi")
    bias, drift = model.index("sources", "accel_bias"), model.index("sources", "gyro_drift")
    # (δφ − ψ)' = (row δφ − row ψ) x + (G δφ − G ψ) w: no state, no bias, only −ε
    assert np.all(F[phi] == F[psi])
    assert G[phi, bias] - G[psi, bias] == 0 and G[phi, drift] - G[psi, drift] == -1
    for output in ("psi", "latitude", "v_N"):
        assert [f.name for f in result.pair("accel_bias", output).cancelled] == ["integrator"]
    assert result.pair("gyro_drift", "latitude").cancelled == ()


def test_a_source_that_reaches_nothing_is_zero():
    """north_pointing's longitude error feeds nothing back (F's column of δλ is zero): an
    initial longitude error reaches the longitude alone."""
    model = load_model("north_pointing")
    result = transfer_functions(model, ["initial_longitude_error"], None)
    F = result.modes.state_matrix
    assert np.all(F[:, model.index("error_states", "delta_longitude")] == 0)
    for output in ("latitude", "v_N", "v_E"):
        pair = result.pair("initial_longitude_error", output)
        assert pair.is_zero and pair.order == 0 and pair.long_run.kind == "none"
        assert sum(f.multiplicity * (2 if f.value.imag else 1) for f in pair.cancelled) == 7
    longitude = result.pair("initial_longitude_error", "longitude")
    assert longitude.order == 1 and longitude.poles[0].name == "integrator"
    assert longitude.long_run.kind == "constant"  # stays at the initial error
    assert longitude.long_run.coefficient == pytest.approx(1.0, rel=1e-12)
