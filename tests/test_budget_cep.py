"""CEP items (``combine = "cep"``): the circular error probable of the horizontal position
error, from its 2×2 covariance with the north-east cross term, checked against a Monte
Carlo estimate, the textbook circular and linear cases, a quadrature of the polar form,
and, in a budget, against the independent 9-state NED error model of
tests/test_budget_sizing.py (Van Loan's exact discretisation)."""

from __future__ import annotations

import itertools
import json
import math
import textwrap

import numpy as np
import pytest
from scipy import integrate, optimize, stats
from scipy.linalg import expm

from ins_errors.analysis.budget_cep import cep, inside_probability
from ins_errors.cli import main
from ins_errors.numeric.model import load_model
from tests.test_budget_sizing import HEIGHT, K1, K2, LAT, ned_reference

DEG = math.pi / 180


def polar_probability(r: float, P: np.ndarray) -> float:
    """P(|x| < r) for x ~ N(0, P), by the polar form: the disc's mass over the angle,
    (1/2π√det) ∫ (1 − exp(−r² q/2))/q dθ with q = uᵀ P⁻¹ u (u the unit direction)."""
    inverse = np.linalg.inv(P)

    def mass(theta: float) -> float:
        u = np.array([math.cos(theta), math.sin(theta)])
        q = u @ inverse @ u
        return (1 - math.exp(-0.5 * r * r * q)) / q

    value, _ = integrate.quad(mass, 0.0, 2 * math.pi, limit=1000, epsabs=1e-13,
                              epsrel=1e-12)
    return value / (2 * math.pi * math.sqrt(np.linalg.det(P)))


def reference_cep(P: np.ndarray) -> float:
    """The radius of probability 1/2 by the polar form and a bracketing root finder (an
    error along a line, which has no polar density: the median of |z| σ)."""
    small, large = np.linalg.eigvalsh(P)
    if small <= 1e-12 * large:
        return float(stats.norm.ppf(0.75) * math.sqrt(large))
    top = math.sqrt(np.trace(P)) * 2
    return optimize.brentq(lambda r: polar_probability(r, P) - 0.5, 1e-9 * top, top,
                           xtol=1e-14 * top, rtol=1e-14)


def ellipse(major: float, minor: float, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    R = np.array([[c, -s], [s, c]])
    return R @ np.diag([major**2, minor**2]) @ R.T


# ------------------------------------------------------------------------------------
# The CEP of a normal horizontal error
# ------------------------------------------------------------------------------------
def test_a_circular_error_has_the_rayleigh_median():
    """Circular, σ on each axis: the radius is Rayleigh, P(R < r) = 1 − exp(−r²/2σ²),
    whose median is σ √(2 ln 2) = 1.1774 σ (0.8326 DRMS); along a line the median of
    |z| σ, 0.6745 σ."""
    for sigma in (1e-3, 1.0, 370.0, 4.2e5):
        assert cep(sigma**2, sigma**2, 0.0) == pytest.approx(
            sigma * math.sqrt(-2 * math.log(0.5)), rel=1e-13)
        assert cep(sigma**2, 0.0, 0.0) == pytest.approx(sigma * stats.norm.ppf(0.75),
                                                        rel=1e-13)
        assert cep(0.0, sigma**2, 0.0) == pytest.approx(sigma * stats.norm.ppf(0.75),
                                                        rel=1e-13)
    assert cep(0.0, 0.0, 0.0) == 0.0


def test_cep_per_drms_rises_from_a_line_to_a_circle():
    """CEP / DRMS over the ellipses, by the polar form: from 0.6745 (a line) up to
    0.8326 = √(ln 2) (a circle), rising with the axes' ratio; the sharing of a CEP item
    rests on the circle being the largest."""
    ratios = [0.0, 1e-3, 0.05, 0.2, 0.5, 0.8, 0.95, 1.0]
    kappa = [reference_cep(np.diag([1.0, m * m])) / math.sqrt(1 + m * m) for m in ratios]
    assert kappa[0] == pytest.approx(stats.norm.ppf(0.75), rel=1e-12)
    assert kappa[-1] == pytest.approx(math.sqrt(math.log(2)), rel=1e-10)
    assert all(b > a for a, b in itertools.pairwise(kappa))
    for m, k in zip(ratios, kappa, strict=True):
        assert float(cep(1.0, m * m, 0.0)) / math.sqrt(1 + m * m) == pytest.approx(
            k, rel=1e-10)


@pytest.mark.parametrize("minor", [1.0, 0.7, 0.3, 0.1, 0.01, 1e-4])
@pytest.mark.parametrize("angle", [0.0, 0.4, -1.1])
def test_the_cep_is_the_polar_forms_root(minor, angle):
    """Any ellipse, turned by any angle (the cross term): the root of the polar form's
    probability, to 1e-10; the probability itself likewise at two radii (to 1e-10: the
    polar form inverts a turned ellipse of axes 1e-4 apart, which costs it digits)."""
    P = ellipse(2.0, 2.0 * minor, angle)
    value = float(cep(P[0, 0], P[1, 1], P[0, 1]))
    assert value == pytest.approx(reference_cep(P), rel=1e-10)
    for r in (0.5 * value, 1.7 * value):
        assert float(inside_probability(r, P[0, 0], P[1, 1], P[0, 1])) == pytest.approx(
            polar_probability(r, P), abs=1e-10)


def test_the_cep_is_a_monte_carlo_median():
    """A turned ellipse (correlation 0.77): the median of 10⁶ drawn radii, and the share
    of draws within three radii, agree with the CEP and the probability within five
    sampling errors (the median's: √(1/4n) over the radius's density there)."""
    P = ellipse(300.0, 80.0, 0.6)
    rho = P[0, 1] / math.sqrt(P[0, 0] * P[1, 1])
    assert abs(rho) > 0.7
    rng = np.random.default_rng(20240611)
    n = 1_000_000
    draws = rng.multivariate_normal([0.0, 0.0], P, size=n)
    radii = np.hypot(draws[:, 0], draws[:, 1])
    value = float(cep(P[0, 0], P[1, 1], P[0, 1]))
    h = 1e-4 * value
    density = (polar_probability(value + h, P) - polar_probability(value - h, P)) / (2 * h)
    assert abs(np.median(radii) - value) < 5 * math.sqrt(0.25 / n) / density
    for r in (0.5 * value, value, 2.0 * value):
        p = float(inside_probability(r, P[0, 0], P[1, 1], P[0, 1]))
        assert abs(np.mean(radii < r) - p) < 5 * math.sqrt(p * (1 - p) / n)
    # and not the circular rule: 0.8326 DRMS is 11 % off for this ellipse
    assert abs(0.8326 * math.sqrt(np.trace(P)) / value - 1) > 0.05


def test_the_cep_scales_with_the_error_and_grows_with_its_covariance():
    """Every magnitude × s: the CEP × s (the budget's common factor); a covariance made
    larger in any direction (adding a positive semi-definite part) never lowers it."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        A = rng.normal(size=(2, 2))
        P = A @ A.T
        s = float(np.exp(rng.uniform(-5, 5)))
        value = float(cep(P[0, 0], P[1, 1], P[0, 1]))
        assert float(cep(s * s * P[0, 0], s * s * P[1, 1], s * s * P[0, 1])) == \
            pytest.approx(s * value, rel=1e-12)
        B = rng.normal(size=(2, 1)) * rng.uniform(0, 1)
        Q = P + B @ B.T
        assert float(cep(Q[0, 0], Q[1, 1], Q[0, 1])) >= value * (1 - 1e-13)


# ------------------------------------------------------------------------------------
# In a budget
# ------------------------------------------------------------------------------------
def reference_horizontal(constants: dict, t: float, dt: float = 60.0) -> np.ndarray:
    """The 2×2 covariance of the north and east position errors (m²) at t from random
    constants (1σ, SI) on the reference model at rest."""
    F, inputs, r_n, r_e_cos = ned_reference(LAT, HEIGHT, K1, K2)
    names = list(constants)
    n, N = 9, 9 + len(names)
    A = np.zeros((N, N))
    A[:n, :n] = F
    for j, name in enumerate(names):
        A[:n, n + j] = inputs[name]
    P = np.zeros((N, N))
    P[n:, n:] = np.diag([constants[k] ** 2 for k in names])
    Phi = expm(A * t)
    P = Phi @ P @ Phi.T
    T = np.zeros((2, N))
    T[0, 6], T[1, 7] = r_n, r_e_cos
    return T @ P @ T.T


SOURCES = ("gyro_bias_x", "gyro_bias_y", "gyro_bias_z", "accel_bias_x", "accel_bias_y")


def cep_spec(sources: str, limit: str = "2 km", sigma_level: float = 1,
             item: str = "position_error_absolute") -> str:
    """The sizing tests' site (45°, 3000 m, damped), one CEP item at 1 h, every source
    of strapdown_ned but ``SOURCES`` left out."""
    model = load_model("strapdown_ned")
    left_out = "".join(f"[sources.{s.name}]\ninclude = false\n" for s in model.sources
                       if s.name not in SOURCES)
    return textwrap.dedent(f"""\
        sigma_level = {sigma_level}
        operating_time = "1 h"
        step = "60 s"
        [motion]
        kind = "static"
        latitude = "45 deg"
        longitude = "10 deg"
        height = "3000 m"
        [items.{item}]
        value = "{limit}"
        times = ["1 h"]
        combine = "cep"
        [parameters]
        k_h1 = "0.0293 1/s"
        k_h2 = "4.42e-4 1/s**2"
        """) + textwrap.dedent(sources) + left_out


def run(tmp_path, capsys, text: str, *extra: str, name: str = "spec.toml"):
    path = tmp_path / name
    path.write_text(text)
    status = main(["budget", "strapdown_ned", "--spec", str(path), "--json",
                   "--no-progress", *extra])
    return status, json.loads(capsys.readouterr().out)


FIXED = {"gyro_bias_x": (0.002, "deg/h"), "gyro_bias_y": (0.02, "deg/h"),
         "gyro_bias_z": (0.1, "deg/h"), "accel_bias_x": (10.0, "ug"),
         "accel_bias_y": (100.0, "ug")}
UNIT = {"deg/h": DEG / 3600, "ug": 9.80665e-6}


def test_a_cep_row_is_the_cep_of_the_reference_covariance(tmp_path, capsys):
    """Fixed biases whose position error at 1 h is a turned ellipse: the row is the CEP
    of the reference model's 2×2 covariance (its cross term and its shape, not 0.8326
    DRMS, which is 4 % off here), whatever the spec's σ level (a CEP has none)."""
    tables = "".join(f'[sources.{name}]\nfixed = "{v} {u}"\nsigma_level = 1\n'
                     for name, (v, u) in FIXED.items())
    P = reference_horizontal({name: v * UNIT[u] for name, (v, u) in FIXED.items()},
                             3600.0)
    rho = P[0, 1] / math.sqrt(P[0, 0] * P[1, 1])
    assert abs(rho) > 0.3 and not 0.5 < P[0, 0] / P[1, 1] < 2
    expected = reference_cep(P)
    assert abs(0.8326 * math.sqrt(np.trace(P)) / expected - 1) > 0.02
    for level in (1, 3):
        status, data = run(tmp_path, capsys, cep_spec(tables, "5 km", level),
                           name=f"spec_{level}.toml")
        assert status == 0
        [row] = data["rows"]
        assert row["value"] == pytest.approx(expected, rel=2e-3)
        assert row["display"].endswith(" CEP")
        assert data["items"][0]["combine"] == "cep"


def test_an_allocation_meets_its_cep_and_fill_meets_it_exactly(tmp_path, capsys):
    """Free biases against a 2-km CEP: the reference CEP at the allocated magnitudes is
    the row's and within the limit; filled, it is the limit (the common factor scales
    the CEP linearly). Each source's share of the row sums to (CEP / limit)²."""
    for extra in ((), ("--fill",)):
        status, data = run(tmp_path, capsys, cep_spec(""), *extra)
        assert status == 0
        sigma = {s["name"]: s["magnitude_1sigma"] for s in data["sources"]}
        assert all(sigma[name] > 0 for name in SOURCES)
        P = reference_horizontal(sigma, 3600.0)
        value = reference_cep(P)
        [row] = data["rows"]
        assert row["value"] == pytest.approx(value, rel=2e-3)
        assert value <= 2000.0 * (1 + 2e-3)
        if extra:
            assert value == pytest.approx(2000.0, rel=2e-3)
            assert row["ratio"] == pytest.approx(1.0, abs=1e-9)
        shares = sum(s["share_at_worst_time"]["position_error_absolute"]
                     for s in data["sources"])
        assert shares == pytest.approx(row["ratio"] ** 2, rel=1e-9)


def test_a_fixed_source_leaves_the_cep_its_remainder(tmp_path, capsys):
    """One bias fixed, the others free, filled: the reference CEP with the fixed one at
    its value is the limit; fixed beyond the limit alone, the spec is exceeded (exit 1)
    with the fixed source's reference CEP as the row."""
    fixed = '[sources.gyro_bias_z]\nfixed = "0.2 deg/h"\n'
    status, data = run(tmp_path, capsys, cep_spec(fixed), "--fill")
    assert status == 0
    sigma = {s["name"]: s["magnitude_1sigma"] for s in data["sources"]}
    assert sigma["gyro_bias_z"] == pytest.approx(0.2 * UNIT["deg/h"], rel=1e-12)
    assert reference_cep(reference_horizontal(sigma, 3600.0)) == pytest.approx(2000.0,
                                                                               rel=2e-3)
    fixed = '[sources.accel_bias_y]\nfixed = "3 mg"\n'
    status, data = run(tmp_path, capsys, cep_spec(fixed), name="over.toml")
    assert status == 1 and data["exceeded"]
    alone = reference_cep(reference_horizontal({"accel_bias_y": 3e-3 * 9.80665}, 3600.0))
    assert alone > 2000.0
    assert data["rows"][0]["value"] == pytest.approx(alone, rel=2e-3)


def test_a_cep_rate_item_is_the_cep_over_t(tmp_path, capsys):
    """``position_error`` with ``combine = "cep"``: the CEP at t divided by t."""
    tables = "".join(f'[sources.{name}]\nfixed = "{v} {u}"\n' for name, (v, u) in FIXED.items())
    status, data = run(tmp_path, capsys, cep_spec(tables, "5 km/h", item="position_error"))
    assert status == 0
    P = reference_horizontal({name: v * UNIT[u] for name, (v, u) in FIXED.items()}, 3600.0)
    assert data["rows"][0]["value"] == pytest.approx(reference_cep(P) / 3600.0, rel=2e-3)


@pytest.mark.parametrize("item, value", [("height_error", "30 m"),
                                         ("ground_speed_error", "1 m/s"),
                                         ("heading_error", "1 deg")])
def test_a_cep_of_another_item_is_refused_in_one_line(tmp_path, capsys, item, value):
    path = tmp_path / "spec.toml"
    path.write_text(textwrap.dedent(f"""\
        operating_time = "1 h"
        [motion]
        latitude = "45 deg"
        [items.{item}]
        value = "{value}"
        combine = "cep"
        """))
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    captured = capsys.readouterr()
    assert not captured.out
    [line] = captured.err.strip().splitlines()
    assert f"items.{item}: combine = 'cep'" in line
    assert "position_error, position_error_absolute" in line


def test_direct_runs_read_a_cep_row_as_the_covariance(tmp_path, capsys):
    """400 direct (nonlinear) runs of north_pointing at the allocated magnitudes: the CEP
    of their north and east errors' second moments is the covariance's within three
    sampling errors at both check times."""
    path = tmp_path / "spec.toml"
    path.write_text(textwrap.dedent("""\
        sigma_level = 1
        operating_time = "20 min"
        step = "60 s"
        [motion]
        kind = "static"
        latitude = "45 deg"
        [items.position_error_absolute]
        value = "1 km"
        times = ["10 min", "20 min"]
        combine = "cep"
        """))
    assert main(["budget", "north_pointing", "--spec", str(path), "--monte-carlo", "400",
                 "--mc-step", "0.5 s", "--engine", "serial", "--json",
                 "--no-progress"]) == 0
    mc = json.loads(capsys.readouterr().out)["monte_carlo"]
    assert [r["row"] for r in mc["rows"]] == ["position_error_absolute at 10 min",
                                              "position_error_absolute at 20 min"]
    for row in mc["rows"]:
        assert abs(row["ratio"] - 1) < 3 * mc["relative_sampling_error"]
        assert row["covariance"] <= 1000.0 * (1 + 1e-9)
