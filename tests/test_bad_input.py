"""Bad input gives one clear line naming the problem, never a traceback or a silent NaN."""

from __future__ import annotations

import re

import numpy as np
import pytest

import ins_errors
from ins_errors.cli import main
from tests.helpers import random_points


@pytest.fixture(scope="module")
def point(orthodromic):
    return random_points(orthodromic, 1, seed=1, moving=True)[0]


def test_latitude_at_the_pole(orthodromic, point):
    x, u, p = point
    pole = orthodromic.initial_condition_vector(latitude=np.pi / 2)
    with pytest.raises(ins_errors.DomainError, match="latitude 90° is refused"):
        orthodromic.initial_state(pole, u, p)
    polar_state = x.copy()
    polar_state[:3] = [0.0, 0.0, 1.0]
    for evaluate in (orthodromic.state_matrix, orthodromic.output_matrix,
                     orthodromic.source_matrix, orthodromic.ideal_rhs):
        with pytest.raises(ins_errors.DomainError, match="divide by cos φ"):
            evaluate(polar_state, u, p)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_nan_or_infinite_values(orthodromic, point, bad):
    x, u, p = point
    x = x.copy()
    x[6] = bad
    with pytest.raises(ins_errors.DomainError, match="NaN or infinite"):
        orthodromic.state_matrix(x, u, p)
    with pytest.raises(ins_errors.DomainError, match="NaN or infinite"):
        orthodromic.source_vector(gyro_drift_x=bad)


def test_unknown_model_suggests_close_names():
    with pytest.raises(ins_errors.UnknownNameError, match="did you mean 'orthodromic'"):
        ins_errors.load_model("orthodromik")


def test_unknown_source_suggests_close_names(orthodromic):
    with pytest.raises(ins_errors.UnknownNameError, match="gyro_drift_x"):
        orthodromic.source_vector(gyro_drift_xx=1e-8)


def test_wrong_shaped_state(orthodromic, point):
    x, u, p = point
    with pytest.raises(ins_errors.ShapeError, match=r"state x must have shape \(8, \.\.\.\)"):
        orthodromic.state_matrix(x[:7], u, p)
    with pytest.raises(ins_errors.ShapeError, match="inputs u"):
        orthodromic.state_matrix(x, u[:, None][:3], p)


def test_negative_radius_is_rejected(orthodromic, point):
    x, u, _ = point
    with pytest.raises(ins_errors.DomainError, match="semi-major axis a must be positive"):
        orthodromic.state_matrix(x, u, orthodromic.parameter_vector(a=-1.0))
    with pytest.raises(ins_errors.DomainError, match="a \\+ h <= 0"):
        orthodromic.state_matrix(x, orthodromic.input_vector(h=-7e6), None)


@pytest.mark.parametrize(("model_name", "source"), [
    ("orthodromic", "gyro_drift_x=0.01deg/h"), ("free_azimuth", "gyro_drift_x=0.01deg/h"),
    ("strapdown_ned", "gyro_bias_x=0.01deg/h"),
    ("north_pointing", "gyro_drift_north=0.01deg/h")])
@pytest.mark.parametrize("motion", ["static", "great-circle"])
def test_latitude_near_a_pole_names_the_models_tolerance(capsys, tmp_path, model_name, source,
                                                        motion):
    """89.99999° (0.036″ from the pole) is refused in one line quoting the latitude given
    and how close to a pole the model's formulas are singular; that distance is the
    model's actual rule: a latitude 1 % farther from the pole is taken, 1 % nearer is
    not. These models need cos²φ > 1e-12, i.e. |φ| below 90° − asin(1e-6) rad (the
    north-pointing model asked cos φ > 1e-12 only, 2e-7″, and took 89.99995°, then
    stopped mid-run on an infinite velocity error)."""
    flight = ["--motion", motion]
    if model_name == "north_pointing" and motion != "static":  # no heading: a motion file
        (tmp_path / "east.csv").write_text("t,v_N,v_E\n0,0,100\n20,0,100\n40,0,100\n"
                                           "60,0,100\n")
        flight = ["--motion-file", str(tmp_path / "east.csv")]
    assert main(["compare", model_name, "--source", source, "--latitude", "89.99999deg",
                 *flight, "--duration", "60s", "--step", "10s"]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "latitude 89.99999° is refused" in line and "at ±90°" not in line, line
    within = re.search(r"singular within ([\d.]+)″ \(([\d.e+-]+) rad\) of a pole", line)
    assert within, line
    arcsec, rad = (float(v) for v in within.groups())
    assert arcsec == pytest.approx(np.degrees(np.arcsin(1e-6)) * 3600, rel=3e-3)  # 3 digits
    assert rad == pytest.approx(arcsec / 3600 * np.pi / 180, rel=1e-2)
    model = ins_errors.load_model(model_name)
    u = model.input_vector()
    for factor, taken in ((1.01, True), (0.99, False)):
        c = model.initial_condition_vector(latitude=np.pi / 2 - factor * np.arcsin(1e-6))
        if taken:
            model.initial_state(c, u)
        else:
            with pytest.raises(ins_errors.DomainError, match=r"singular within 0\.206″"):
                model.initial_state(c, u)


def test_cli_prints_one_line_not_a_traceback(capsys):
    assert main(["models", "orthodromikk"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("ins-errors: error: unknown model")
    assert "\n" not in err and "Traceback" not in err


def test_units_at_the_edge():
    from ins_errors.units import UnitError, parse_quantity

    assert parse_quantity("0.01 deg/h", "rad/s") == pytest.approx(np.radians(0.01) / 3600)
    assert parse_quantity("10 ug", "m/s**2") == pytest.approx(9.80665e-5)
    assert parse_quantity("20 arcsec", "rad") == pytest.approx(np.radians(20 / 3600))
    assert parse_quantity("100 ppm", "1") == pytest.approx(1e-4)
    assert parse_quantity(1e-5, "rad/s") == 1e-5  # a library caller's number is SI
    assert parse_quantity("0", "rad/s") == 0.0 and parse_quantity("3", "1") == 3.0
    with pytest.raises(UnitError, match=r"has no unit; give an angular rate, e\.g\. '1e-5 deg/h'"):
        parse_quantity("1e-5", "rad/s", "gyro_drift_x")  # text must say its unit
    with pytest.raises(UnitError, match="24 has no unit; give a time"):
        parse_quantity(24, "s", "run duration", numbers_are_si=False)  # a file's number too
    with pytest.raises(UnitError, match="do not convert to rad"):
        parse_quantity("0.1 m/s", "rad", "initial_tilt_x")
    with pytest.raises(UnitError, match="not a finite number"):
        parse_quantity("nan deg", "rad")


def test_plain_si_text_read_without_pint_equals_pint():
    """A plain number in the very SI unit asked for is read without pint (derive needs
    no registry): the same float pint's conversion gives, and the same errors."""
    from ins_errors.units import UnitError, _normalise, parse_quantity, registry

    ureg = registry()
    for text, unit in [("1e-4 rad", "rad"), ("0.1 m/s", "m/s"), ("  7 s ", "s"),
                       ("-3.5e-7 rad/s", "rad/s"), (".5 m", "m"), ("1E2 rad", "rad"),
                       ("123456789.123456789 m", "m"), ("2.5e-300 rad", "rad"), ("20 m", "m")]:
        by_pint = ureg.parse_expression(_normalise(text)).to(ureg.parse_units(unit)).magnitude
        assert parse_quantity(text, unit) == float(by_pint)  # to the bit
    with pytest.raises(UnitError, match="not a finite number"):
        parse_quantity("1e999 m", "m")
    with pytest.raises(UnitError, match="do not convert to m/s"):
        parse_quantity("0.1 m", "m/s")


def test_source_lookup_by_name(orthodromic):
    assert orthodromic.source("gyro_drift_z").display_unit == "deg/h"
    assert "000" in orthodromic.source_document


def test_ellipsoid_selection(orthodromic):
    import ins_errors

    a, e2, _ = orthodromic.parameter_vector(ellipsoid="wgs84")
    assert a == 6_378_137.0
    assert e2 == pytest.approx(2 / 298.257223563 - (1 / 298.257223563) ** 2)
    sphere = ins_errors.load_model("north_pointing")
    default = dict(zip([p.name for p in sphere.parameters], sphere.parameter_vector(),
                       strict=True))
    assert default["ecc2"] == 0.0  # the report's spherical Earth by default
    chosen = dict(zip([p.name for p in sphere.parameters],
                      sphere.parameter_vector(ellipsoid="krasovsky"), strict=True))
    assert chosen["R"] == 6_378_245.0 and chosen["ecc2"] > 0.006
    with pytest.raises(ins_errors.UnknownNameError, match="did you mean 'wgs84'"):
        orthodromic.parameter_vector(ellipsoid="wgs-84")


@pytest.mark.parametrize("written, first", [("gyro_drift", None), ("gyro_drift_w", None),
                                            ("gyro_drfit_z", "gyro_drift_z"),
                                            ("Gyro_Drift_Y", "gyro_drift_y")])
def test_did_you_mean_lists_the_closest_first_and_ties_in_the_models_order(written, first,
                                                                          capsys):
    """'gyro_drift' was answered with 'gyro_drift_z', 'gyro_drift_y', 'gyro_drift_x'
    (difflib's reverse order of equally close names): a name equally close to all three
    lists them as the model does; a closer one (a slip of two letters, another case)
    comes first, the others after it in the model's order."""
    from ins_errors.numeric.model import load_model

    assert main(["compare", "orthodromic", "--source", f"{written}=0.01deg/h"]) == 2
    err = capsys.readouterr().err
    listed = re.findall(r"'(gyro_drift_\w)'", err.partition("did you mean")[2])
    order = [s.name for s in load_model("orthodromic").sources
             if s.name.startswith("gyro_drift_")]
    assert order == ["gyro_drift_x", "gyro_drift_y", "gyro_drift_z"]
    assert listed == ([first] if first else []) + [n for n in order if n != first]
