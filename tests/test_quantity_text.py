"""A quantity's text is one number followed by one unit, with the angle's own power.

pint multiplies whatever is written side by side and counts radians as dimensionless,
so ``"45 deg 30 arcmin"`` used to be 45·30 deg·arcmin = 0.00685 rad (a latitude of
0.39°) and ``"45 deg^2"`` 0.0137 rad, both passing the dimension check. Such texts are
refused with one line naming the text and the problem, through the units layer, the
command line, scenario files and accuracy-spec files; the forms users write (rates per
hour, random walks per √h or √Hz, micro-g, arcminutes, reciprocal seconds) still parse
to the values computed here from the units' definitions.
"""

from __future__ import annotations

import math
import textwrap

import pytest

from ins_errors.cli import main
from ins_errors.units import UnitError, parse_quantity

DEG = math.pi / 180
ARCMIN = DEG / 60
ARCSEC = ARCMIN / 60
HOUR = 3600.0
G = 9.80665   # standard gravity, m/s² (the definition of the unit g)

LEGITIMATE = [
    ("0.01 deg/h", "rad/s", 0.01 * DEG / HOUR),
    ("0.01deg/h", "rad/s", 0.01 * DEG / HOUR),
    ("0.01deg/sqrt(h)", "rad/s**0.5", 0.01 * DEG / math.sqrt(HOUR)),
    ("0.05 deg/h^0.5", "rad/s**0.5", 0.05 * DEG / math.sqrt(HOUR)),
    ("0.05 deg/h**0.5", "(rad/s)*s**0.5", 0.05 * DEG / math.sqrt(HOUR)),
    ("0.05 deg/√h", "rad/s**0.5", 0.05 * DEG / math.sqrt(HOUR)),
    ("3 deg*h^(-1/2)", "rad/s**0.5", 3 * DEG / math.sqrt(HOUR)),
    ("100 ug", "m/s**2", 100e-6 * G),
    ("1e-4 g", "m/s**2", 1e-4 * G),
    ("1e-4*g", "m/s**2", 1e-4 * G),
    ("10 ug/sqrt(Hz)", "m/s**1.5", 10e-6 * G),
    ("10 ug/√Hz", "(m/s**2)*s**0.5", 10e-6 * G),
    ("5 arcmin", "rad", 5 * ARCMIN),
    ("-5 arcmin", "rad", -5 * ARCMIN),
    ("20 arcsec", "rad", 20 * ARCSEC),
    ("45.5 deg", "rad", 45.5 * DEG),
    ("250 m/s", "m/s", 250.0),
    ("900 km/h", "m/s", 250.0),
    ("2 h", "s", 2 * HOUR),
    ("1/3600 Hz", "1/s", 1 / HOUR),
    ("0.0293 1/s", "1/s", 0.0293),
    ("100 ppm", "1", 1e-4),
    ("0.5 1", "1", 0.5),          # the unit one, as a parameter record writes it
    ("3", "1", 3.0),
    ("0", "rad", 0.0),
    ("6 rpm", "rad/s", 6 * 2 * math.pi / 60),   # a revolution is an angle, 2π rad
]


@pytest.mark.parametrize(("text", "unit", "expected"), LEGITIMATE,
                         ids=[f"{t}->{u}" for t, u, _ in LEGITIMATE])
def test_the_forms_users_write_parse(text, unit, expected):
    assert parse_quantity(text, unit, "value") == pytest.approx(expected, rel=1e-12, abs=0)


SIDE_BY_SIDE = [
    ("45deg 30arcmin", "'45.5 deg'"),
    ("45 deg 30 arcmin", "'45.5 deg'"),
    ("5arcmin 30arcsec", "'5.5 arcmin'"),
    ("-45 deg 30 arcmin", "'-45.5 deg'"),        # the sign is the whole angle's
    ("45 deg 30 arcmin 36 arcsec", "'45.51 deg'"),
    ("45deg 0.5", "'45 deg'"),                    # no second unit: the family's example
    ("2*3 deg", "'2 deg'"),
    ("45 deg 1 arcmin", "'45.01666667 deg'"),
    ("1/3600 Hz 2", None),
]


@pytest.mark.parametrize(("text", "suggestion"), SIDE_BY_SIDE)
def test_a_second_number_is_refused_not_multiplied(text, suggestion):
    unit = "1/s" if "Hz" in text else "rad"
    with pytest.raises(UnitError) as info:
        parse_quantity(text, unit, "motion latitude")
    line = str(info.value)
    assert "\n" not in line
    assert line.startswith(f"motion latitude: {text!r} has a second number"), line
    assert "give one number followed by one unit" in line
    if suggestion:
        assert f"e.g. {suggestion}" in line, line


@pytest.mark.parametrize(("text", "unit", "words"), [
    ("45 deg^2", "rad", "an angle squared, where rad needs an angle"),
    ("45 deg**2", "rad", "an angle squared"),
    ("45 deg²", "rad", "an angle squared"),
    ("45 deg*arcmin", "rad", "an angle squared"),
    ("1 deg/h*deg", "rad/s", "an angle squared, where rad/s needs an angle"),
    ("10 Hz", "rad/s", "no angle, where rad/s needs an angle"),
    ("5 deg", "1", "an angle, where 1 needs no angle"),
])
def test_an_angle_to_another_power_is_refused(text, unit, words):
    """pint converts all of these (a radian is dimensionless to it); the power of the
    angle in the unit is what tells them apart."""
    with pytest.raises(UnitError, match="has units of") as info:
        parse_quantity(text, unit, "value")
    assert words in str(info.value) and "\n" not in str(info.value)


def test_a_unit_without_a_number_is_refused():
    for text in ("deg", "deg 45", ""):
        with pytest.raises(UnitError, match="does not start with a number"):
            parse_quantity(text, "rad", "motion latitude")
    with pytest.raises(UnitError, match="cannot read 'four'"):   # pint names the word
        parse_quantity("four", "rad", "motion latitude")


PROBE = {  # the new-user probe's command lines: each ran, with a wrong number
    "latitude-deg-arcmin": ["--latitude", "45deg 30arcmin"],
    "latitude-squared": ["--latitude", "45 deg^2"],
    "latitude-times-half": ["--latitude", "45deg 0.5"],
    "azimuth-arcmin-arcsec": ["-s", "initial_azimuth_error=5arcmin 30arcsec"],
}


@pytest.mark.parametrize("change", PROBE.values(), ids=PROBE.keys())
def test_the_command_line_refuses_in_one_line(change, capsys):
    argv = ["compare", "north_pointing", "-s", "gyro_drift_north=0.1deg/h", "--hours", "1",
            "--step", "10s", *change]
    assert main(argv) == 2
    captured = capsys.readouterr()
    (line,) = captured.err.strip().splitlines()
    assert line.startswith("ins-errors: error: ") and repr(change[1].split("=")[-1]) in line
    assert "second number" in line or "an angle squared" in line, line
    assert captured.out == ""   # nothing was run


SPEC = """\
    title = "probe"
    sigma_level = 1
    operating_time = "1 h"
    step = "60 s"
    [motion]
    kind = "static"
    latitude = "{latitude}"
    [items.vertical_error]
    value = "30 arcsec"
    every = "10 min"
    from = "0 h"
"""


def test_a_spec_file_refuses_two_numbers(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(textwrap.dedent(SPEC.format(latitude="45 deg 30 arcmin")))
    assert main(["budget", "north_pointing", "--spec", str(spec)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "motion.latitude: '45 deg 30 arcmin' has a second number (30)" in line, line
    assert "e.g. '45.5 deg'" in line


def test_a_scenario_file_refuses_an_angle_squared(tmp_path, capsys):
    scenario = tmp_path / "s.toml"
    scenario.write_text(textwrap.dedent("""\
        model = "north_pointing"
        [motion]
        kind = "static"
        latitude = "45 deg^2"
        [run]
        duration = "1 h"
        step = "10 s"
        [[case]]
        gyro_drift_north = "0.1 deg/h"
    """))
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "'45 deg^2' has units of deg ** 2, an angle squared" in line, line
    assert not (tmp_path / "out").exists()


def test_a_spec_latitude_near_a_pole_is_refused_as_compare_refuses_it(tmp_path, capsys):
    """89.99999° is 0.036″ from the pole, inside the 1e-6 rad (0.206″) within which the
    north-pointing model's formulas are singular: the budget said nothing and allowed
    an initial azimuth error of 1.6e7 arcmin. It now gives the line compare gives."""
    spec = tmp_path / "spec.toml"
    spec.write_text(textwrap.dedent(SPEC.format(latitude="89.99999 deg")))
    assert main(["budget", "north_pointing", "--spec", str(spec)]) == 2
    (budget_line,) = capsys.readouterr().err.strip().splitlines()
    assert main(["compare", "north_pointing", "-s", "gyro_drift_north=0.1deg/h",
                 "--latitude", "89.99999deg", "--hours", "1", "--step", "10s"]) == 2
    (compare_line,) = capsys.readouterr().err.strip().splitlines()
    assert budget_line == compare_line
    assert "latitude 89.99999° is refused" in budget_line
    assert "singular within 0.206″ (1e-06 rad) of a pole" in budget_line


@pytest.mark.parametrize(("value", "display", "shown"), [
    (30 * DEG, "arcmin", "30 deg"),       # not 1800 arcmin
    (-2 * DEG, "arcsec", "-2 deg"),       # up two steps
    (90 * ARCSEC, "arcsec", "1.5 arcmin"),
    (30 * ARCMIN, "arcmin", "30 arcmin"),  # below 60 of its unit: as displayed
    (0.5 * ARCMIN, "arcmin", "0.5 arcmin"),
    (0.01 * DEG / HOUR, "deg/h", "0.01 deg/h"),  # not an angle: unchanged
])
def test_a_label_shows_an_angle_in_the_unit_its_size_reads_in(value, display, shown):
    from ins_errors.units import format_readable

    unit = "rad/s" if display == "deg/h" else "rad"
    assert format_readable(value, unit, display) == shown


def test_a_comparison_names_a_large_initial_heading_error_in_degrees(capsys):
    """The case label of an initial azimuth error given as 30 deg (displayed in arcmin)."""
    assert main(["compare", "geodetic_vertical", "--source", "initial_azimuth_error=30 deg",
                 "--hours", "0.1", "--step", "10 s"]) == 0
    out = capsys.readouterr().out
    assert "initial_azimuth_error = 30 deg" in out
    assert "1800 arcmin" not in out


@pytest.mark.parametrize(("value", "display", "shown"), [
    (ARCMIN, "deg", "arcmin"),            # a limit of 1 arcmin, not 0.01667 deg
    (2 * ARCSEC, "deg", "arcsec"),        # down two steps
    (0.1 * DEG, "deg", "deg"),            # 0.1 of the unit still reads in it
    (120 * DEG, "arcsec", "deg"),
])
def test_a_limit_reads_in_the_angle_unit_of_its_size(value, display, shown):
    from ins_errors.units import readable_angle_unit

    assert readable_angle_unit(value, display, down=True) == shown
