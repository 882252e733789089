"""A model without latitude, longitude or height: a researcher's tangent-plane INS.

``tests/models/tangent_plane_ins.py`` (a probe's own file) is a platform INS on a
rotating flat Earth: x/y position in metres, the origin latitude ``phi0`` a parameter,
velocity damping gains ``c_v``, ``c_i`` (0 by default) and inputs ``a_E``, ``a_N``.

References (independent of the code under test): the model file's own ideal work,
typed here from its docstring (dV_E/dt = a_E + 2 U sin φ0 V_N + U² x_E, dV_N/dt = a_N −
2 U sin φ0 V_E + U² sin² φ0 x_N, dx/dt = V), a motion file's velocities as the cubic
splines through its samples (scipy), degrees and half a turn.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from ins_errors.cli import main
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.model import load_model
from ins_errors.numeric.motion_spec import motion_profile
from tests.test_cli_json import strict_json

ROOT = Path(__file__).resolve().parent.parent
MODEL = str(ROOT / "tests/models/tangent_plane_ins.py")
PHI0 = np.radians(50.0)  # the file's default origin latitude
U = 7.292115e-5
SCHULER_LOOP = str(ROOT / "examples/own_model/schuler_loop.py")


@pytest.fixture(scope="module", autouse=True)
def model():
    """The model, derived (first use: one line on stderr) before any output is read."""
    return load_model(MODEL)


def _one_line_error(capsys, argv) -> str:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and err.startswith("ins-errors: error: ")
    return err


# -- 1. a latitude, longitude or height the model does not have is refused -------------
@pytest.mark.parametrize("command", [["modes", MODEL], ["compare", MODEL, "-s",
                                                        "gyro_drift_E=0.01deg/h",
                                                        "--hours", "1", "--step", "10s"]])
def test_a_latitude_for_a_model_without_one_is_refused_naming_its_parameter(capsys,
                                                                             command):
    err = _one_line_error(capsys, [*command, "--latitude", "10deg"])
    assert "no latitude" in err and "-p phi0=10deg" in err
    err = _one_line_error(capsys, [*command, "--height", "100m"])
    assert "no height" in err and "leave --height out" in err


def test_a_scenarios_latitude_for_a_model_without_one_is_refused(capsys, tmp_path):
    """A scenario file's [motion] latitude is refused as --latitude is, the way out
    written as the file sets a parameter; without it the same file runs."""
    text = (f'title = "tangent plane"\nmodel = "{MODEL}"\n[motion]\nkind = "static"\n'
            'latitude = "10 deg"\n[run]\nduration = "10 min"\nstep = "10 s"\n'
            '[[case]]\ngyro_drift_E = "0.01 deg/h"\n')
    path = tmp_path / "tangent.toml"
    path.write_text(text)
    err = _one_line_error(capsys, ["run", str(path), "--out", str(tmp_path / "out")])
    assert "[motion] latitude" in err and 'phi0 = "10 deg"' in err
    path.write_text(text.replace('latitude = "10 deg"\n', ""))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0


@pytest.mark.parametrize("sweep, motion, message", [
    ('latitude = ["10 deg", "20 deg"]', "", ('[sweep] latitude: model \'tangent_plane_ins\' '
                                             'has no latitude',
                                             '[sweep] phi0 = ["10 deg", "20 deg"]')),
    ('height = ["10 m", "20 m"]', "", ("[sweep] height: model", "leave height out of [sweep]")),
    ('gyro_drift_E = ["0.01 deg/h", "0.02 deg/h"]', 'latitude = "10 deg"\n',
     ("[motion] latitude: model", '[parameters] phi0 = "10 deg"')),
])
def test_a_sweeps_latitude_for_a_model_without_one_is_refused(capsys, tmp_path, monkeypatch,
                                                              sweep, motion, message):
    """A sweep over the latitude of a model without one ran every point alike (the
    latitude is its parameter phi0); it is refused before any point runs, as run refuses
    a [motion] latitude, naming the file and the model's own setting."""
    monkeypatch.chdir(tmp_path)
    text = (f'title = "tangent plane"\nmodel = "{MODEL}"\n[motion]\nkind = "static"\n'
            f'{motion}[run]\nduration = "10 min"\nstep = "10 s"\n'
            f'[[case]]\ngyro_drift_E = "0.01 deg/h"\n[sweep]\n{sweep}\n')
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "tangent.toml").write_text(text)
    argv = ["sweep", "sub/tangent.toml", "--store", "t.zarr", "--engine", "serial",
            "--no-progress"]
    err = _one_line_error(capsys, argv)
    assert err.startswith("ins-errors: error: sub/tangent.toml [")
    assert all(part in err for part in message), err
    assert not (tmp_path / "t.zarr").exists()
    if motion:  # run refuses the same [motion] latitude (of the file without its
        # [sweep] table, which run refuses first), naming the file too
        (tmp_path / "sub" / "one.toml").write_text(text.split("[sweep]")[0])
        err = _one_line_error(capsys, ["run", "sub/one.toml", "--out", "out"])
        assert err.startswith("ins-errors: error: sub/one.toml [motion] latitude:")
    if "[sweep] phi0" in message[1]:  # the way out it names sweeps the model's latitude
        (tmp_path / "sub" / "tangent.toml").write_text(text.replace(sweep, message[1][8:]))
        assert main([*argv, "--json"]) == 0
        rows = json.loads(capsys.readouterr().out)["summary"]
        assert [row["phi0"] for row in rows] == pytest.approx(np.radians([10.0, 20.0]))
        # a drift about east at rest on the tangent plane: its tilt and velocity errors
        # follow the origin latitude through the Earth rate's components (they differ)
        assert rows[0]["max_direct"] != rows[1]["max_direct"]


def test_a_budget_specs_latitude_for_a_model_without_one_is_refused(capsys, tmp_path):
    """A spec's [motion] latitude was silently ignored by the budget of a model without
    one (it sat at phi0 = 50° whatever the spec said); without it the spec is budgeted."""
    text = ('sigma_level = 1\noperating_time = "1 h"\nstep = "60 s"\n[motion]\n'
            'kind = "static"\nlatitude = "10 deg"\n[items.ground_speed_error]\n'
            'value = "1 m/s"\n')
    spec = tmp_path / "own.toml"
    spec.write_text(text)
    err = _one_line_error(capsys, ["budget", MODEL, "--spec", str(spec)])
    assert "own.toml [motion] latitude: model 'tangent_plane_ins' has no latitude" in err
    assert "-p phi0=10deg" in err
    spec.write_text(text.replace('latitude = "10 deg"\n', ""))
    assert main(["budget", MODEL, "--spec", str(spec)]) == 0


def test_the_parameter_the_refusal_names_is_the_models_latitude(capsys):
    """-p phi0=10deg, the way the refusal names, moves the model's latitude: the
    Foucault split Ω sin φ0 of its Coriolis terms 2 U sin φ0 changes with it."""
    split = {}
    for phi in ("10deg", "50deg"):
        assert main(["modes", MODEL, "-p", f"phi0={phi}", "--json"]) == 0
        data = strict_json(capsys.readouterr().out)
        assert data["latitude_rad"] is None and data["height_m"] is None
        latitude = data["references"]["latitude"]
        assert latitude["source"] == "parameter phi0"
        assert latitude["value"] == pytest.approx(np.radians(float(phi[:2])))
        rates = sorted(m["eigenvalue"]["imag"] for m in data["modes"]
                       if m["eigenvalue"]["imag"] > 1e-4)
        split[phi] = rates[-1] - rates[0]
    assert split["10deg"] < split["50deg"]


def test_a_model_with_a_latitude_reports_it_and_takes_the_option(capsys):
    assert main(["modes", "north_pointing", "--latitude", "10deg", "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    assert data["latitude_rad"] == pytest.approx(np.radians(10.0))
    assert data["references"]["latitude"]["source"] == "base"


def test_a_longitude_or_height_the_schuler_loop_has_not_is_refused(capsys):
    """The tutorial's single-axis loop depends on its latitude only."""
    args = ["compare", SCHULER_LOOP, "-s", "accel_bias=100ug", "--hours", "1", "--step",
            "10s"]
    # (first: a first use derives the file, one line on stderr that is not the error's)
    assert main([*args, "--latitude", "40deg", "--json"]) == 0
    assert "φ=40°" in json.loads(capsys.readouterr().out)["motion"]
    assert "no longitude" in _one_line_error(capsys, [*args, "--longitude", "-70deg"])
    assert "no height" in _one_line_error(capsys, [*args, "--height", "3000m"])


# -- 2. moving motions of a model without latitude -------------------------------------
def test_a_motion_file_is_flown_on_the_models_own_flat_earth(model, tmp_path):
    """The true state and inputs of a motion file: velocities the splines of the file,
    positions their integrals, and a_* what the file's ideal work needs to follow them."""
    t = np.array([0.0, 1200.0, 2400.0, 3600.0, 4800.0])
    v_n = np.array([0.0, 50.0, 50.0, 0.0, -20.0])
    v_e = np.array([100.0, 100.0, 120.0, 120.0, 90.0])
    path = tmp_path / "motion.csv"
    path.write_text("t,v_N,v_E\n" + "".join(f"{a:g},{b:g},{c:g}\n"
                                            for a, b, c in zip(t, v_n, v_e, strict=True)))
    profile = motion_profile({"kind": "file", "file": str(path)}, model=model)
    motion = tr.trajectory(model, profile, 3600.0, 10.0, truth="fine")
    assert "latitude" not in motion.references
    times = motion.times
    spline_n, spline_e = CubicSpline(t, v_n), CubicSpline(t, v_e)
    names = [s.name for s in model.states]
    x = dict(zip(names, motion.truth, strict=True))
    np.testing.assert_allclose(x["V_N"], spline_n(times), atol=1e-9)
    np.testing.assert_allclose(x["V_E"], spline_e(times), atol=1e-9)
    # the file's dx/dt = V, integrated exactly from the splines (RK4 at 5 s: 1e-6 m)
    np.testing.assert_allclose(x["x_N"], spline_n.antiderivative()(times), atol=1e-4)
    np.testing.assert_allclose(x["x_E"], spline_e.antiderivative()(times), atol=1e-4)
    u = dict(zip([i.name for i in model.inputs], motion.inputs, strict=True))
    s = np.sin(PHI0)
    a_e = spline_e(times, 1) - 2 * U * s * x["V_N"] - U**2 * x["x_E"]
    a_n = spline_n(times, 1) + 2 * U * s * x["V_E"] - U**2 * s**2 * x["x_N"]
    np.testing.assert_allclose(u["a_E"], a_e, atol=1e-12)
    np.testing.assert_allclose(u["a_N"], a_n, atol=1e-12)


def test_compare_flies_a_motion_file_and_refuses_a_great_circle_for_its_heading(
        capsys, tmp_path):
    path = tmp_path / "motion.csv"
    path.write_text("t,v_N,v_E\n0,0,100\n1200,50,100\n2400,50,120\n3600,0,120\n")
    assert main(["compare", MODEL, "--motion-file", str(path), "--hours", "1", "--step",
                 "10s", "-s", "accel_bias_N=50ug", "--json"]) == 0
    cases = json.loads(capsys.readouterr().out)["cases"]
    assert cases[0]["worst_linear_ratio"] < 1e-5
    for motion in ("great-circle", "manoeuvre"):
        err = _one_line_error(capsys, ["compare", MODEL, "--motion", motion, "--hours",
                                       "1", "-s", "accel_bias_N=50ug"])
        assert "steered by the heading" in err and "motion file" in err
        assert "latitude" not in err


# -- 3. a source a damping gain at 0 switches off --------------------------------------
@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("validity") / "out"
    argv = ["validity", MODEL, "--source", "vref_bias_E", "--source", "accel_scale_E",
            "--source", "initial_azimuth_error", "--motion", "static", "--hours", "6",
            "--step", "10s", "--plot", "--out", str(folder), "--engine", "serial",
            "--no-progress"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a matplotlib warning fails the sweep
        status = main(argv)
    return status, folder


def test_a_source_behind_a_damping_gain_at_0_is_said_to_be(sweep, capsys):
    status, folder = sweep
    assert status == 0
    rows = {r["source"]: r for r in
            json.loads((folder / "results.json").read_text())["sources"]}
    assert rows["vref_bias_E"]["status"] == "not excited"
    note = rows["vref_bias_E"]["note"]
    assert "damping gain" in note and "c_v" in note and "-p c_v=2e-3/s" in note
    # a scale factor at rest: no specific force along its axis, no gain to blame
    assert rows["accel_scale_E"]["status"] == "not excited"
    assert "damping" not in rows["accel_scale_E"]["note"]
    assert (folder / "vref_bias_E.png").stat().st_size > 0


def test_compare_says_why_a_case_gives_no_error(capsys):
    """A case whose sources excite nothing gets a warning with each source's reason (a
    damping gain at 0; a scale factor at rest) instead of a bare table of 'no'; a case
    that excites something gets none."""
    assert main(["compare", MODEL, "-s", "vref_bias_E=1m/s", "--hours", "0.1",
                 "--json"]) == 0
    [case] = strict_json(capsys.readouterr().out)["cases"]
    assert not any(m["excited"] for m in case["metrics"])
    assert any("enters only through damping gains" in w and "c_v" in w
               for w in case["warnings"])
    assert main(["compare", "orthodromic", "-s", "accel_scale_error_x=100ppm", "-s",
                 "gyro_drift_x=0.01deg/h", "--separately", "--hours", "0.1", "--json"]) == 0
    scale, drift = strict_json(capsys.readouterr().out)["cases"]
    assert any("accel_scale_error_x gives any error" in w for w in scale["warnings"])
    assert not any("not excited" in w for w in drift["warnings"])


def test_the_plot_of_a_source_not_excited_draws_without_a_warning(tmp_path):
    from ins_errors.analysis.validity import SourceValidity
    from ins_errors.analysis.validity_plot import plot_validity

    result = SourceValidity("vref_bias_E", "static", "m/s", "m/s", [0.05, 0.5, 5.0], None,
                            status="not excited", note="not excited: a damping gain at 0")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plot_validity([result], tmp_path / "flat.png", "title")
    assert (tmp_path / "flat.png").stat().st_size > 0


# -- 4. magnitudes of an angle past half a turn ----------------------------------------
def test_an_angle_magnitude_past_half_a_turn_is_marked(sweep, capsys):
    _, folder = sweep
    rows = {r["source"]: r for r in
            json.loads((folder / "results.json").read_text())["sources"]}
    azimuth = rows["initial_azimuth_error"]
    largest = max(azimuth["magnitudes"])
    for key in ("magnitude_1pct", "magnitude_10pct"):
        value = azimuth[key]
        expected = ("past half a turn" if value > np.pi else
                    "extrapolated" if value > largest else None)
        assert azimuth["extrapolated"].get(key) == expected
    assert azimuth["magnitude_10pct"] > np.pi  # this model: the fit passes 180°
    from ins_errors.analysis.validity import SourceValidity
    from ins_errors.commands.validity import table

    result = SourceValidity(**{k: v for k, v in azimuth.items()})
    text = table([result], None)
    row = next(line for line in text.splitlines() if "initial_azimuth_error" in line)
    one = np.degrees(azimuth["magnitude_1pct"])
    assert f"{one:.3g} deg" in row and "past 180 deg" in row and "arcmin" not in row
    assert "past half a turn" in text


def test_compares_one_percent_magnitude_past_half_a_turn_says_so():
    from ins_errors.numeric.compare import _shown

    model = load_model("orthodromic")
    assert _shown(model, "initial_azimuth_error", np.radians(30.0)) == "30 deg"
    assert "past half a turn" in _shown(model, "initial_azimuth_error", np.radians(462.0))


# -- 5. angle parameters in degrees ----------------------------------------------------
def test_models_and_report_show_an_angle_parameter_in_degrees(capsys, tmp_path):
    assert main(["models", MODEL]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.strip().startswith("phi0"))
    assert line.endswith("(default 50 deg)")
    assert main(["models", MODEL, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    phi0 = next(p for p in data["parameters"] if p["name"] == "phi0")
    assert phi0["default"] == PHI0 and phi0["unit"] == "rad"  # JSON stays SI
    scenario = tmp_path / "s.toml"
    scenario.write_text(f'title = "tangent"\nmodel = {json.dumps(MODEL)}\n'
                        '[motion]\nkind = "static"\n[parameters]\nphi0 = "45.5 deg"\n'
                        '[run]\nduration = "1 h"\nstep = "10 s"\n'
                        '[[case]]\naccel_bias_N = "50 ug"\n', encoding="utf-8")
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()
    report = (tmp_path / "out" / "report.md").read_text()
    assert "`phi0` = 45.5 deg (set)" in report and "0.79" not in report
    results = json.loads((tmp_path / "out" / "results.json").read_text())
    assert results["parameters_used"]["phi0"]["value"] == pytest.approx(np.radians(45.5))


def test_a_platform_angle_past_a_quarter_turn_is_refused_without_claiming_the_exact_platform(
        capsys):
    """A model file writes its platform's kinematics itself; the quarter-turn limit of
    the built-in platforms still holds its second platform angle, but the line said
    "the exact platform's z-y-x angles", which the researcher's model does not have."""
    assert main(["compare", MODEL, "--source", "initial_tilt_N=100deg", "--hours", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "alpha_N = 100° exceeds" in err and "quarter turn" in err
    assert "exact platform" not in err
