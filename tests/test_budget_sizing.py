"""Sizing an IMU with ``ins-errors budget``: datasheet values (1σ biases, noise
densities) in a spec, checked against an independent 9-state NED error model at rest
(typed here: φ-angle, velocity and position errors with a damped vertical channel,
random constants as augmented states and white noise through Van Loan's exact
discretisation)."""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest
from scipy.linalg import expm

import ins_errors
from ins_errors.cli import main

DEG = np.pi / 180
G0 = 9.80665
LAT, HEIGHT, K1, K2 = 45 * DEG, 3000.0, 0.0293, 4.42e-4
ARW, VRW = 0.02 * DEG / 60, 0.02 / 60        # 0.02 deg/√h, 0.02 m/s/√h in SI
DRIFT, BIAS = 0.5 * DEG / 3600, 100e-6 * G0  # 0.5 deg/h, 100 ug


def ned_reference(lat: float, h: float, k1: float, k2: float):
    """The 9-state φ-angle error model at rest: states (φ_N, φ_E, φ_D, δv_N, δv_E, δv_D,
    δφ, δλ, δh up), WGS-84 radii and normal gravity at height h, the vertical channel
    damped by k1 (height) and k2 (vertical speed); the gyro and accelerometer biases'
    input columns with the body axes along north, east, down. Returns F, the inputs by
    source name, R_N and R_E cos φ (m)."""
    a, e2, omega = 6378137.0, 6.69437999014e-3, 7.292115e-5
    s, c = np.sin(lat), np.cos(lat)
    w = 1 - e2 * s * s
    r_n = a * (1 - e2) / w**1.5 + h
    r_e = a / np.sqrt(w) + h
    g0 = 9.7803253359 * (1 + 0.00193185265241 * s * s) / np.sqrt(w)
    f = 1 / 298.257223563
    m = omega**2 * a * a * (1 - f) / 3.986004418e14
    g = g0 * (1 - 2 * h / a * (1 + f + m - 2 * f * s * s) + 3 * h * h / (a * a))
    earth = np.array([omega * c, 0.0, -omega * s])

    def cross(v):
        return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    F = np.zeros((9, 9))
    F[:3, :3] = -cross(earth)
    F[0, 4], F[1, 3], F[2, 4] = 1 / r_e, -1 / r_n, -np.tan(lat) / r_e
    F[0, 6], F[2, 6] = -omega * s, -omega * c
    F[3:6, :3] = cross(np.array([0.0, 0.0, -g]))     # f × φ with f = (0, 0, −g)
    F[3:6, 3:6] = -2 * cross(earth)
    F[5, 8] = -2 * g / np.sqrt(r_n * r_e) + k2
    F[6, 3], F[7, 4], F[8, 5], F[8, 8] = 1 / r_n, 1 / (r_e * c), -1.0, -k1
    inputs = {}
    for i, axis in enumerate("xyz"):
        inputs[f"gyro_bias_{axis}"] = -np.eye(9)[i]
        inputs[f"accel_bias_{axis}"] = np.eye(9)[3 + i]
    return F, inputs, r_n, r_e * c


def reference_position(constants: dict, densities: dict, t: float, dt: float = 60.0) -> float:
    """1σ horizontal position error (m) at t (s) from random constants (1σ, SI) and white
    noises (densities, SI) on the reference model at the probe's site."""
    F, inputs, r_n, r_e_cos = ned_reference(LAT, HEIGHT, K1, K2)
    names = list(constants)
    n = 9
    N = n + len(names)
    A = np.zeros((N, N))
    A[:n, :n] = F
    for j, name in enumerate(names):
        A[:n, n + j] = inputs[name]
    P = np.zeros((N, N))
    P[n:, n:] = np.diag([constants[k] ** 2 for k in names])
    Q = np.zeros((N, N))
    for name, density in densities.items():
        b = np.zeros(N)
        b[:n] = inputs[name]
        Q += density**2 * np.outer(b, b)
    M = np.zeros((2 * N, 2 * N))
    M[:N, :N], M[:N, N:], M[N:, N:] = -A, Q, A.T
    X = expm(M * dt)
    Phi = X[N:, N:].T
    Qd = Phi @ X[:N, N:]
    for _ in range(round(t / dt)):
        P = Phi @ P @ Phi.T + Qd
    return float(np.sqrt(r_n**2 * P[6, 6] + r_e_cos**2 * P[7, 7]))


def noise_densities() -> dict:
    return {**{f"gyro_bias_{a}": ARW for a in "xyz"},
            **{f"accel_bias_{a}": VRW for a in "xyz"}}


def bias_constants() -> dict:
    return {**{f"gyro_bias_{a}": DRIFT for a in "xyz"},
            **{f"accel_bias_{a}": BIAS for a in "xyz"}}


def spec_text(sources: str, sigma_level: float = 1, limit: str = "2 km") -> str:
    """A spec at the probe's site with one item, the horizontal position at 1 h, and
    every strapdown_ned source left out but those ``sources`` (TOML tables) give."""
    model = ins_errors.load_model("strapdown_ned")
    given = {line.split(".", 1)[1].split("]")[0].split(".")[0]
             for line in sources.splitlines() if line.startswith("[sources.")}
    left_out = "".join(f"[sources.{s.name}]\ninclude = false\n" for s in model.sources
                       if s.name not in given)
    return textwrap.dedent(f"""\
        sigma_level = {sigma_level}
        operating_time = "1 h"
        step = "60 s"
        [motion]
        kind = "static"
        latitude = "45 deg"
        longitude = "10 deg"
        height = "3000 m"
        [items.position_error_absolute]
        value = "{limit}"
        times = ["1 h"]
        [parameters]
        k_h1 = "0.0293 1/s"
        k_h2 = "4.42e-4 1/s**2"
        """) + textwrap.dedent(sources) + left_out


def run_budget(tmp_path, capsys, text: str, name: str = "spec.toml") -> tuple[int, dict]:
    path = tmp_path / name
    path.write_text(text)
    status = main(["budget", "strapdown_ned", "--spec", str(path), "--json"])
    return status, json.loads(capsys.readouterr().out)


NOISE = """\
[sources.gyro_bias_x]
kind = "white"
fixed = "0.02 deg/sqrt(h)"
[sources.gyro_bias_y]
kind = "white"
fixed = "0.02 deg/sqrt(h)"
[sources.gyro_bias_z]
kind = "white"
fixed = "0.02 deg/sqrt(h)"
[sources.accel_bias_x]
kind = "white"
fixed = "0.02 m/s/sqrt(h)"
[sources.accel_bias_y]
kind = "white"
fixed = "0.02 m/s/sqrt(h)"
[sources.accel_bias_z]
kind = "white"
fixed = "0.02 m/s/sqrt(h)"
"""


def test_a_noise_density_is_read_as_it_is_whatever_the_spec_level(tmp_path, capsys):
    """A white-noise density has no σ level: 0.02 deg/√h in a 3σ spec is 0.02 deg/√h
    (it was divided by 3, and the 3σ position error came out a third of the truth). The
    3σ spec's position error is 3 times the reference's 1σ one, and the 1σ spec's is
    the reference's."""
    expected = reference_position({}, noise_densities(), 3600.0)
    assert expected == pytest.approx(4400, rel=0.01)       # the probe's 1σ figure
    for level in (1, 3):
        status, data = run_budget(tmp_path, capsys, spec_text(NOISE, level),
                                  f"noise_{level}.toml")
        assert status == 1                                  # 2 km is exceeded either way
        row = data["rows"][0]
        assert row["sigma_level"] == level
        assert row["value"] == pytest.approx(level * expected, rel=2e-3)
        gyro = next(s for s in data["sources"] if s["name"] == "gyro_bias_x")
        assert gyro["magnitude"] == pytest.approx(ARW, rel=1e-12)
        assert gyro["magnitude_1sigma"] == pytest.approx(ARW, rel=1e-12)
        assert gyro["magnitude_sigma_level"] == 1
    main(["budget", "strapdown_ned", "--spec", str(tmp_path / "noise_3.toml")])
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("Fixed sources"))
    assert "3σ; white-noise densities as given, 1σ" in line


def test_a_bias_with_its_own_sigma_level(tmp_path, capsys):
    """``sigma_level = 1`` on a fixed bias reads a datasheet's 1σ value in a 3σ spec:
    the 3σ position error is 3 times the reference's 1σ one; without it the value is
    read at the spec's level (a third of the bias)."""
    biases = "".join(f'[sources.{name}]\nfixed = "{text}"\nsigma_level = 1\n'
                     for name, text in [*((f"gyro_bias_{a}", "0.5 deg/h") for a in "xyz"),
                                        *((f"accel_bias_{a}", "100 ug") for a in "xyz")])
    expected = reference_position(bias_constants(), {}, 3600.0)
    _, data = run_budget(tmp_path, capsys, spec_text(biases, 3, "1000 km"))
    assert data["rows"][0]["value"] == pytest.approx(3 * expected, rel=2e-3)
    gyro = next(s for s in data["sources"] if s["name"] == "gyro_bias_x")
    assert gyro["magnitude"] == pytest.approx(DRIFT, rel=1e-12)
    assert gyro["magnitude_sigma_level"] == 1
    _, data = run_budget(tmp_path, capsys, spec_text(biases.replace(
        "sigma_level = 1\n", ""), 3, "1000 km"), "spec_level.toml")
    assert data["rows"][0]["value"] == pytest.approx(expected, rel=2e-3)


def test_a_sigma_level_on_a_noise_density_is_refused(tmp_path, capsys):
    text = spec_text('[sources.gyro_bias_x]\nkind = "white"\nfixed = "0.02 deg/sqrt(h)"\n'
                     'sigma_level = 3\n', 3)
    path = tmp_path / "spec.toml"
    path.write_text(text)
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    err = capsys.readouterr().err
    assert "a white-noise density has no σ level" in err and len(err.splitlines()) == 1


BOTH = "".join(f'[sources.{name}]\nfixed = "{bias}"\n[sources.{name}.noise]\nfixed = "{noise}"\n'
               for name, bias, noise in [
                   *((f"gyro_bias_{a}", "0.5 deg/h", "0.02 deg/sqrt(h)") for a in "xyz"),
                   *((f"accel_bias_{a}", "100 ug", "0.02 m/s/sqrt(h)") for a in "xyz")])
"""A FOG-grade IMU: each gyro and accelerometer with its bias and its white noise."""


def test_a_source_with_a_bias_and_a_noise(tmp_path, capsys):
    """``[sources.NAME.noise]`` gives a source a white noise beside its constant bias
    (once refused: a source had one kind): the run with both equals the reference
    model's 1σ position error from the biases and the noises together (95.67 km at 1 h,
    the probe's figure), and the root sum of squares of the runs with the biases alone
    and the noises alone; the rows name each part."""
    expected = reference_position(bias_constants(), noise_densities(), 3600.0)
    assert expected == pytest.approx(95670, rel=1e-3)
    _, both = run_budget(tmp_path, capsys, spec_text(BOTH, 1, "200 km"), "both.toml")
    value = both["rows"][0]["value"]
    assert value == pytest.approx(expected, rel=2e-3)
    biases = "".join(f'[sources.{name}]\nfixed = "{text}"\n' for name, text in [
        *((f"gyro_bias_{a}", "0.5 deg/h") for a in "xyz"),
        *((f"accel_bias_{a}", "100 ug") for a in "xyz")])
    _, alone = run_budget(tmp_path, capsys, spec_text(biases, 1, "200 km"), "biases.toml")
    _, noise = run_budget(tmp_path, capsys, spec_text(NOISE, 1, "200 km"), "noise.toml")
    assert value == pytest.approx(np.hypot(alone["rows"][0]["value"],
                                           noise["rows"][0]["value"]), rel=1e-9)
    labels = [s["label"] for s in both["sources"]]
    assert labels[:2] == ["gyro_bias_x (constant)", "gyro_bias_x (white)"]
    assert [s["name"] for s in both["sources"]][:2] == ["gyro_bias_x", "gyro_bias_x"]
    assert main(["budget", "strapdown_ned", "--spec", str(tmp_path / "both.toml")]) == 0
    out = capsys.readouterr().out
    assert any(line.startswith("gyro_bias_x (white)") and "0.02 deg/√h" in line
               for line in out.splitlines())


def test_a_noise_part_is_allocated_beside_a_fixed_bias(tmp_path, capsys):
    """A noise part without ``fixed`` takes a share as any free source: the fixed parts
    first, and the one free noise (gyro_bias_x's) all they leave, so that at its
    allowance the reference model's position error is the 200-km limit."""
    text = BOTH.replace('[sources.gyro_bias_x.noise]\nfixed = "0.02 deg/sqrt(h)"',
                        '[sources.gyro_bias_x.noise]\nweight = 1')
    status, data = run_budget(tmp_path, capsys, spec_text(text, 1, "200 km"))
    assert status == 0
    noise = next(s for s in data["sources"] if s["label"] == "gyro_bias_x (white)")
    assert not noise["fixed"] and noise["binding_item"] == "position_error_absolute"
    # the reference at the allowed density: the rest of the allowed variance
    allowed = reference_position(bias_constants(), {
        **noise_densities(), "gyro_bias_x": noise["magnitude_1sigma"]}, 3600.0)
    assert allowed == pytest.approx(200e3, rel=2e-3)


@pytest.mark.parametrize("table, message", [
    ('[sources.gyro_bias_x]\nkind = "white"\n[sources.gyro_bias_x.noise]\nkind = "white"\n',
     "a source takes at most one part of each kind"),
    ('[sources.initial_roll_error.noise]\nfixed = "1 arcsec*h**0.5"\n',
     "an initial error can only be a random constant"),
    ('[sources.gyro_bias_x]\ninclude = false\n[sources.gyro_bias_x.noise]\n'
     'fixed = "0.02 deg/sqrt(h)"\n', "include = false leaves the whole source out"),
    ('[sources.gyro_bias_x.noise]\nkind = "markov"\n', "a markov source needs tau"),
    ('[sources.gyro_bias_x.noise]\nfixed = "0.02 deg/sqrt(h)"\nwieght = 1\n', "weight"),
])
def test_bad_noise_parts_are_refused_in_one_line(tmp_path, capsys, table, message):
    path = tmp_path / "spec.toml"
    path.write_text(spec_text(table))
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.splitlines()) == 1


def test_covariance_of_a_source_with_two_parts():
    """In the covariance API a source may be listed as a constant and a white noise
    (once "an error source is listed twice"): each part's variance is what it gives
    alone, and the reference model's total is their sum; one kind twice is refused."""
    from ins_errors.analysis import covariance as cv
    from ins_errors.numeric import trajectories as tr

    model = ins_errors.load_model("strapdown_ned")
    p = model.parameter_vector(k_h1=K1, k_h2=K2)
    trajectory = tr.trajectory(model, tr.static_profile(LAT, 10 * DEG, 0.0, HEIGHT), 3600.0,
                               60.0, p=p)
    system = cv.system_from_trajectory(model, trajectory)
    functionals = cv.state_and_output_functionals(model, system)
    parts = [cv.SourceStatistics("gyro_bias_x", "constant", DRIFT),
             cv.SourceStatistics("gyro_bias_x", "white", ARW)]
    both = cv.propagate(system, parts, functionals)
    assert both.source_names == ("gyro_bias_x", "gyro_bias_x")
    for j, part in enumerate(parts):
        alone = cv.propagate(system, [part], functionals)
        np.testing.assert_allclose(both.contributions[..., j], alone.contributions[..., 0],
                                   rtol=1e-12, atol=0)
    names = list(functionals.names)
    lat, lon = names.index("delta_lat"), names.index("delta_lon")
    _, _, r_n, r_e_cos = ned_reference(LAT, HEIGHT, K1, K2)
    total = both.variance[-1]
    position = np.sqrt(r_n**2 * total[lat] + r_e_cos**2 * total[lon])
    expected = reference_position({"gyro_bias_x": DRIFT}, {"gyro_bias_x": ARW}, 3600.0)
    assert position == pytest.approx(expected, rel=2e-3)
    with pytest.raises(ins_errors.InsErrorsError, match="listed twice as a 'white' part"):
        cv.propagate(system, [parts[1], parts[1]], functionals)


def test_a_figure_beyond_the_linear_model_is_warned_of(tmp_path, capsys):
    """Fixed biases whose 1σ position error after 1 h is, by the reference model, just
    above the linear model's 637 km (0.1 R) get a one-line warning naming the item and
    the figure (a MEMS-grade IMU, 955 km, once had none); just below, none."""
    unit = reference_position({"gyro_bias_x": DRIFT}, {}, 3600.0) / DRIFT   # m per rad/s
    limit = 0.1 * 6_371_000.0
    for factor, warned in ((1.03, True), (0.97, False)):
        drift = factor * limit / unit / (DEG / 3600)                          # deg/h
        text = spec_text(f'[sources.gyro_bias_x]\nfixed = "{drift!r} deg/h"\n', 1, "5000 km")
        path = tmp_path / f"spec_{factor}.toml"
        path.write_text(text)
        assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 0
        err = capsys.readouterr().err
        assert ("warning: beyond the linear error model's range" in err) == warned
        if warned:
            assert len(err.splitlines()) == 1
            assert "position_error_absolute at 1 h" in err and "637.1 km = 0.1 R" in err
            figure = float(err.split("at 1 h (")[1].split(" km")[0])
            assert figure == pytest.approx(factor * limit / 1e3, rel=2e-3)
        assert main(["budget", "strapdown_ned", "--spec", str(path), "--json"]) == 0
        warnings = json.loads(capsys.readouterr().out)["warnings"]
        assert any("linear error model" in w for w in warnings) == warned


@pytest.mark.parametrize("value", ['"500"', "500", "5e2", '" 500 "'])
def test_a_bare_number_on_a_scale_factor_is_refused(tmp_path, capsys, value):
    """``fixed = "500"`` on a scale factor was read as the fraction 500 (5e8 ppm, and a
    position error of 1e6 km): a bare number is refused, as everywhere a unit is needed,
    with the value in ppm and in % to write instead; '500 ppm' is 5e-4."""
    path = tmp_path / "spec.toml"
    path.write_text(spec_text(f"[sources.gyro_scale_error_x]\nfixed = {value}\n"))
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    err = capsys.readouterr().err
    assert "is a bare number" in err and "write '500 ppm' or '0.05 %'" in err
    assert len(err.splitlines()) == 1
    path.write_text(spec_text('[sources.gyro_scale_error_x]\nfixed = "500 ppm"\n'))
    assert main(["budget", "strapdown_ned", "--spec", str(path), "--json"]) in (0, 1)
    source = json.loads(capsys.readouterr().out)["sources"][0]
    assert source["name"] == "gyro_scale_error_x"
    assert source["magnitude"] == pytest.approx(500e-6, rel=1e-12)


@pytest.mark.parametrize("value", ["0", '"0"', "0.0"])
def test_a_bare_zero_on_a_scale_factor_is_taken(tmp_path, capsys, value):
    """Zero needs no unit (a part taken as perfect): only a non-zero bare number is
    ambiguous (a reviewer: 'fixed = 0' was refused as a bare number)."""
    path = tmp_path / "spec.toml"
    path.write_text(spec_text(f"[sources.gyro_scale_error_x]\nfixed = {value}\n"))
    assert main(["budget", "strapdown_ned", "--spec", str(path), "--json"]) in (0, 1)
    source = json.loads(capsys.readouterr().out)["sources"][0]
    assert source["name"] == "gyro_scale_error_x" and source["magnitude"] == 0.0


def test_a_fixed_value_is_echoed_in_the_unit_it_was_written_in(tmp_path, capsys):
    """A white accelerometer noise written in m/s/√h is shown so (it was echoed as
    '33.99 ug/√Hz'), a bias of '1 mg' as '1 mg', and the noise part is named as such."""
    path = tmp_path / "spec.toml"
    path.write_text(spec_text('[sources.accel_bias_x]\nfixed = "1 mg"\n'
                              '[sources.accel_bias_x.noise]\nfixed = "0.02 m/s/sqrt(h)"\n',
                              1, "5000 km"))
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert any(x.split() == ["accel_bias_x", "(white)", "0.02", "m/s/√h", "fixed"]
               for x in lines)
    assert any(x.split() == ["accel_bias_x", "(constant)", "1", "mg", "fixed"] for x in lines)


@pytest.mark.parametrize("name, item", [("velocity_error", "ground_speed_error"),
                                        ("altitude_error", "height_error"),
                                        ("azimuth_error", "heading_error")])
def test_another_word_for_an_item_names_the_item(tmp_path, capsys, name, item):
    path = tmp_path / "spec.toml"
    path.write_text(f'[items.{name}]\nvalue = "3 m"\n')
    assert main(["budget", "strapdown_ned", "--spec", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"unknown item [items.{name}]" in err and f"is [items.{item}]" in err
    assert len(err.splitlines()) == 1
