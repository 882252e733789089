"""Unit messages speak the user's words, and the keyboard's angle signs are read.

A probe (an instructor whose students type quantities) found messages naming this
package's own unit names (``mg_n``, ``g_n``, ``ppm_ins``, ``'gee0' is not defined``),
``5'`` refused with suggestions that were themselves invalid (``'5' deg'``), ``1 gal``
read as the US gallon, and ``--duration "-30 min"`` told to be "non-negative" where zero
is refused too. The expected values below come from the units' definitions (a minute of
arc is 1/60 degree, the galileo 1 cm/s², standard gravity 9.80665 m/s²), not from the
code under test.
"""

from __future__ import annotations

import json
import math
import re

import pytest

from ins_errors.cli import main
from ins_errors.units import UnitError, parse_quantity

DEG = math.pi / 180
ARCMIN = DEG / 60
ARCSEC = ARCMIN / 60
G = 9.80665   # standard gravity, m/s² (the definition of g)

INTERNAL = re.compile(r"g_n|_gee|\bgee|ppm_ins|_ins\b")
"""Names the package gives the units library, never meant for a reader."""


def _refusal(text: str, unit: str) -> str:
    with pytest.raises(UnitError) as info:
        parse_quantity(text, unit, "value")
    line = str(info.value)
    assert "\n" not in line
    return line


@pytest.mark.parametrize(("text", "unit", "written", "kind"), [
    ("1 mg", "rad/s", "mg (milli-g, an acceleration)", "rad/s (an angular rate)"),
    ("1e-4 g", "rad", "g (standard gravity, an acceleration)", "rad (an angle)"),
    ("10 ppm", "rad/s", "ppm (a plain number or ratio)", "rad/s (an angular rate)"),
    ("10 µg", "rad", "µg (micro-g, an acceleration)", "rad (an angle)"),
    ("10 ug", "m", "ug (micro-g, an acceleration)", "m (a length)"),
    ("1 mg/h", "rad/s", "mg / h (mg: milli-g;", "rad/s (an angular rate)"),
    ("1 g0", "rad", "g0 (standard gravity, an acceleration)", "rad (an angle)"),
    ("1 deg/h", "m/s**2", "deg / h (an angular rate)", "m/s**2 (an acceleration)"),
])
def test_another_dimension_is_named_in_the_users_words(text, unit, written, kind):
    line = _refusal(text, unit)
    assert f"{text!r} has units of {written}" in line, line
    assert f"do not convert to {kind}" in line, line
    assert not INTERNAL.search(line), line


@pytest.mark.parametrize(("text", "unit"), [("10 ppm", "rad"), ("3 g0", "1"),
                                            ("1 g2", "m/s**2"), ("1 ppm2", "1")])
def test_no_other_refusal_names_an_internal_unit(text, unit):
    line = _refusal(text, unit)
    assert not INTERNAL.search(line), line


def test_standard_gravity_written_g0_is_read():
    """pint's own name for standard gravity; the g-to-gravity rewrite used to turn it
    into the unknown 'gee0'."""
    assert parse_quantity("1 g0", "m/s**2") == pytest.approx(G, rel=1e-15)


@pytest.mark.parametrize(("text", "value"), [
    ("5'", 5 * ARCMIN), ('20"', 20 * ARCSEC), ("20''", 20 * ARCSEC),
    ("-5'", -5 * ARCMIN), ("0.5'", 0.5 * ARCMIN), ("1e1'", 10 * ARCMIN),
    ("5′", 5 * ARCMIN), ("20″", 20 * ARCSEC),
])
def test_keyboard_minute_and_second_signs_are_angles(text, value):
    assert parse_quantity(text, "rad", "value") == pytest.approx(value, rel=1e-14)


@pytest.mark.parametrize(("text", "total"), [
    ("1°30'", "1.5 deg"), ("1°30′", "1.5 deg"), ("1° 30′", "1.5 deg"),
    ("-45°30'", "-45.5 deg"), ("5'30\"", "5.5 arcmin"),
])
def test_degrees_minutes_seconds_are_refused_with_their_sum(text, total):
    """As '45 deg 30 arcmin' is: the parts side by side are never added up silently."""
    line = _refusal(text, "rad")
    assert "second number (30)" in line and f"e.g. '{total}'" in line, line


@pytest.mark.parametrize(("text", "unit"), [
    ("5", "rad"), ("5*2", "rad"), ("1/4", "rad/s"), ("1 mg", "rad/s"), ("1 gal", "rad"),
    ("45 deg^2", "rad"), ("10 Hz", "rad/s"), ("1 deg", "m/s**2"), ("3 kg", "m"),
    ("5'", "m"), ('20"', "s"),
])
def test_every_suggested_example_is_accepted(text, unit):
    line = _refusal(text, unit)
    examples = re.findall(r"'([^']*)'", line.split("e.g. ", 1)[1])
    assert examples, line
    for example in examples:
        parse_quantity(example, unit, "example")   # raises if the suggestion is invalid


@pytest.mark.parametrize(("text", "value"), [
    ("1 gal", 0.01), ("1 Gal", 0.01), ("980.665 gal", G), ("50 mgal", 50e-5),
    ("50 mGal", 50e-5), ("3 µgal", 3e-8), ("3 ugal", 3e-8),
])
def test_gal_is_the_galileo(text, value):
    """1 Gal = 1 cm/s² (CGS); a gallon is never an acceleration."""
    assert parse_quantity(text, "m/s**2", "value") == pytest.approx(value, rel=1e-14)


@pytest.mark.parametrize(("text", "unit", "value"), [
    ("0.15 deg/rt-hr", "rad/s**0.5", math.radians(0.15) / 60),  # 1/√h = 1/60 /√s
    ("0.15 deg/rthr", "rad/s**0.5", math.radians(0.15) / 60),
    ("0.05 m/s/rt-h", "m/s**1.5", 0.05 / 60),
    ("30 ug/rt-Hz", "m/s**1.5", 30e-6 * G),
    ("1 mG", "m/s**2", 1e-3 * G), ("2 G", "m/s**2", 2 * G), ("50 uG", "m/s**2", 50e-6 * G),
    ("50 µG", "m/s**2", 50e-6 * G),
])
def test_datasheet_spellings_are_read(text, unit, value):
    """A sizing probe's datasheet units: 'deg/rt-hr' was the rontometric ton, 'mG' the
    milligauss; an IMU datasheet means a square root and the gravity unit."""
    assert parse_quantity(text, unit, "value") == pytest.approx(value, rel=1e-14)


def test_a_gallon_is_refused_as_a_volume():
    line = _refusal("1 gallon", "m/s**2")
    assert "has units of gallon (a volume)" in line, line
    assert "has units of gal," not in line


def _cli_line(argv: list[str], capsys) -> str:
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.strip().splitlines()
    assert line.startswith("ins-errors: error: ")
    return line


BASE = ["compare", "north_pointing", "--hours", "1", "--step", "10s"]


@pytest.mark.parametrize(("option", "text"), [
    ("--duration", "-30 min"), ("--duration", "0 min"), ("--record", "-5 s"),
    ("--record", "0 s"),
])
def test_a_time_that_is_not_positive_is_refused_as_not_positive(option, text, capsys):
    argv = [*BASE, "-s", "gyro_drift_north=0.1deg/h", option, text]
    if option == "--duration":
        argv.remove("--hours")
        argv.remove("1")
    line = _cli_line(argv, capsys)
    assert f"{option} must be positive, got {text!r}" in line, line
    assert "non-negative" not in line


def test_the_command_line_reads_the_keyboard_signs(capsys):
    for source, value in (("initial_azimuth_error=5'", 5 * ARCMIN),
                          ('initial_azimuth_error=20"', 20 * ARCSEC)):
        assert main([*BASE, "--json", "-s", source]) == 0
        (case,) = json.loads(capsys.readouterr().out)["cases"]
        assert case["sources"]["initial_azimuth_error"] == pytest.approx(value, rel=1e-14)


@pytest.mark.parametrize("source", ["gyro_drift_north=1 mg", "gyro_drift_north=10 ppm",
                                    "gyro_drift_north=1e-4 g", "gyro_drift_north=1 gal",
                                    "gyro_drift_north=1 g0"])
def test_the_command_line_names_the_users_unit(source, capsys):
    line = _cli_line([*BASE, "-s", source], capsys)
    assert repr(source.split("=")[1]) in line and "an angular rate" in line, line
    assert not INTERNAL.search(line) and "not defined" not in line, line


@pytest.mark.parametrize("unit", ["1/s**2", "1/s", "m/s**2", "rad", "1", "m", "rad/s"])
def test_a_suggested_value_reads_back_as_the_number_it_was_made_from(unit):
    """A hint's example is typed as -p and TOML take it ('2e-3/s^2', not SymPy's
    '2e-3 1/s**2') and keeps its number's SI meaning: a model file's example '0.5' for an
    angle was suggested as '0.5 deg', 57 times smaller than the 0.5 rad it was."""
    from ins_errors.symbolic.consistency import typed_example
    from ins_errors.units import typed_value

    for suggestion in (typed_value("2e-3", unit), typed_example("2e-3", unit)):
        assert "**" not in suggestion
        assert parse_quantity(suggestion, unit) == pytest.approx(2e-3, rel=1e-15)


def test_a_sweep_grid_value_without_its_unit_is_told_the_typed_form(tmp_path, capsys):
    spec = tmp_path / "gain.toml"
    spec.write_text('model = "strapdown_ned"\n[motion]\nkind = "static"\nlatitude = "50 deg"\n'
                    '[run]\nduration = "1 min"\nstep = "10 s"\n[[case]]\n'
                    'accel_bias_z = "100 ug"\n[sweep]\nk_h2 = ["1e-3/s^2", "2e-3"]\n',
                    encoding="utf-8")
    assert main(["sweep", str(spec), "--store", str(tmp_path / "s.zarr")]) == 2
    err = capsys.readouterr().err
    assert "needs a unit, e.g. '2e-3/s^2'" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("model", ["strapdown_ned", "orthodromic"])
def test_the_model_listing_writes_units_as_they_are_typed(model, capsys):
    """`ins-errors models NAME` wrote SymPy's '[m/s**2]'; a reader copies the unit into
    -p or a TOML file, so it is written as they take it ('m/s^2'), and every unit shown
    reads back as the model's SI unit."""
    from ins_errors.numeric.model import load_model

    assert main(["models", model]) == 0
    out = capsys.readouterr().out
    assert "**" not in out
    m = load_model(model)
    for info in (*m.sources, *m.parameters, *m.error_states):
        shown = re.search(rf"^  {re.escape(info.name)} +\[([^\]]+)\]", out, re.M).group(1)
        typed = "1" if shown == "1" else f"1 {shown}"
        assert parse_quantity(typed, info.unit) == pytest.approx(1.0, rel=1e-15), shown


@pytest.mark.parametrize("text", ["100mug", "100 mug/s", "3 mg/h"])
def test_a_mass_read_from_a_g_symbol_is_called_a_mass_in_grams(text):
    """'100mug' is pint's microgram (mu + g): it was glossed 'micro-g, a mass', which
    contradicts itself; a gram read as a mass is named so, with how micro-g is written.
    A milli-g per hour (not a mass) keeps its milli-g gloss."""
    with pytest.raises(UnitError) as refused:
        parse_quantity(text, "m/s**2", "accel_bias_x")
    message = str(refused.value)
    if "mg/h" in text:
        assert "mg: milli-g" in message and "gram" not in message
        return
    assert "micro-g" not in message.split("written")[0]
    assert "microgram" in message and "written g, mg or ug" in message
