"""``ins-errors transfer`` on the command line: text, --json, --plot and bad input.

The numbers are checked against the textbook Schuler loop (ω_s² = g/R with the model's
g = 9.80665 m/s² and R = 6371 km): a constant accelerometer bias ∇ tilts the platform by
∇/g on average (100 µg: 1e-4 rad = 0.3438′), with the Schuler period 2π√(R/g) = 84.41 min.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from ins_errors.cli import main
from tests.test_cli_json import strict_json

ROOT = Path(__file__).resolve().parent.parent
SCHULER = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
R, G = 6_371_000.0, 9.80665


def test_text_says_the_convention_the_factored_form_and_the_long_run(capsys):
    assert main(["transfer", SCHULER, "--source", "accel_bias=100ug", "--output", "psi",
                 "--output", "v_N"]) == 0
    out = capsys.readouterr().out
    assert "Y(s) = b·W(s)/s" in out and "Y(s) = b·W(s))" in out  # both conventions said
    assert "#### accel_bias → psi: order 2 of 3 (cancelled: integrator)" in out
    # 1/R per m/s² = 1.5696e-7 rad/(m/s²)/s²: in arcmin per µg, 5.2916e-09
    gain = 1 / R * (180 * 60 / math.pi) * 9.80665e-6
    assert f"W(s) = {gain:.4e} [arcmin/ug/s²] · 1 / (s² + ({math.sqrt(G / R):.4e})²)" in out
    assert "| Schuler | period 84.41 min |" in out
    tilt = 100e-6 * 180 * 60 / math.pi  # ∇/g in arcmin
    assert f"psi oscillates about {tilt:.4g} arcmin" in out
    assert "v_N oscillates about 0 m/s" in out


def test_json_keys_and_values(capsys):
    assert main(["transfer", SCHULER, "--source", "accel_bias=100ug", "--source",
                 "gyro_drift", "--output", "psi", "--output", "latitude", "--json"]) == 0
    text = capsys.readouterr().out
    assert text.startswith('{\n  "schema_version": 2,')
    data = strict_json(text)
    assert data["model"] == "schuler_loop" and "Y(s) = b·W(s)/s" in data["convention"]
    assert [(p["source"], p["output"]) for p in data["pairs"]] == [
        ("accel_bias", "psi"), ("accel_bias", "latitude"), ("gyro_drift", "psi"),
        ("gyro_drift", "latitude")]
    tilt = data["pairs"][0]
    assert tilt["gain"] == pytest.approx(1 / R, rel=1e-12)
    assert tilt["magnitude"] == pytest.approx(100 * 9.80665e-6, rel=1e-12)
    assert tilt["long_run"]["kind"] == "constant"
    assert tilt["long_run"]["value"] == pytest.approx(1e-4, rel=1e-10)  # ∇/g, rad
    assert [p["name"] for p in tilt["poles"]] == ["Schuler"]
    assert tilt["poles"][0]["period_s"] == pytest.approx(2 * math.pi * math.sqrt(R / G))
    drift = data["pairs"][3]
    assert drift["source_display_unit"] == "deg/h" and drift["magnitude"] == pytest.approx(
        math.radians(1) / 3600, rel=1e-12)  # one display unit by default
    assert (drift["long_run"]["kind"], drift["long_run"]["power"]) == ("power", 1)
    assert drift["long_run"]["coefficient"] == pytest.approx(-1.0, rel=1e-10)


def test_plot_writes_a_png(tmp_path, capsys):
    path = tmp_path / "bode" / "w.png"
    assert main(["transfer", "north_pointing", "--source", "accel_bias_north", "--source",
                 "initial_azimuth_error", "--latitude", "45deg", "--plot", str(path)]) == 0
    assert f"plot written to {path}" in capsys.readouterr().out
    data = path.read_bytes()
    assert data.startswith(b"\x89PNG\r\n\x1a\n") and len(data) > 20_000
    from matplotlib.image import imread

    height, width = imread(path).shape[:2]
    assert width > 600 and height > 500
    # with --json the path goes to standard error, the JSON stays clean
    assert main(["transfer", "north_pointing", "--source", "accel_bias_north", "--json",
                 "--plot", str(tmp_path / "again.png")]) == 0
    captured = capsys.readouterr()
    assert strict_json(captured.out)["pairs"] and "again.png" in captured.err


@pytest.mark.parametrize("argv, words", [
    (["north_pointing"], "give at least one --source NAME"),
    (["north_pointing", "--source", "accel_bias_nort"], "did you mean 'accel_bias_north'"),
    (["north_pointing", "--source", "accel_bias_north", "--output", "latitud"],
     "unknown output or error state of north_pointing 'latitud'"),
    (["north_pointing", "--source", "accel_bias_north", "--latitude", "90deg"], "pole"),
    (["north_pointing", "--source", "accel_bias_north", "--latitude", "-90deg"], "pole"),
    (["north_pointing", "--source", "accel_bias_north", "--latitude", "nan"], "finite"),
    (["north_pointing", "--source", "accel_bias_north=nan"], "finite"),
    (["north_pointing", "--source", "accel_bias_north="], "expected NAME or NAME=VALUE"),
    (["north_pointing", "--source", "accel_bias_north", "--source", "accel_bias_north"],
     "given twice"),
    (["north_pointing", "--source", "accel_bias_north", "--plot", "w.txt"], "image format"),
    (["north_pointing", "--source", "accel_bias_north", "-p", "R=-1m"], "positive"),
    ([SCHULER, "--source", "accel_bias", "--heading", "10deg"], "heading"),
])
def test_bad_input_is_one_line_exit_2(argv, words, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["transfer", *argv]) == 2
    captured = capsys.readouterr()
    assert not captured.out
    assert captured.err.startswith("ins-errors: error: ") and captured.err.count("\n") == 1
    assert words in captured.err
    assert not list(tmp_path.iterdir())  # nothing written


def test_a_base_where_no_reduction_agrees_with_f_is_refused(capsys, monkeypatch):
    """The refusal path (F too ill-conditioned at the base) with the limit set so that
    even a good reduction misses it: one line naming the pair, exit 2."""
    monkeypatch.setattr("ins_errors.analysis.transfer.REFUSE_LIMIT", -1.0)
    assert main(["transfer", "north_pointing", "--source", "gyro_drift_east", "--output",
                 "latitude"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "gyro_drift_east → latitude of north_pointing" in err
    assert "cannot be resolved" in err


def test_a_refusal_says_why_and_the_nearest_latitude_that_resolves_the_pair(capsys,
                                                                         monkeypatch):
    """A refusal away from a pole blamed the pole ('near a pole … tan φ' at 30°): it says
    what the base tells of the cause and the nearest latitude (0.01°, 0.1°, 1° either
    side) at which the command resolves the same pair, checked by resolving it there."""
    import ins_errors.analysis.transfer as transfer

    original = transfer.transfer_at_base

    def refusing_at_30(model, modes, sources, outputs=None, magnitudes=None):
        if abs(modes.latitude - math.radians(30.0)) < 1e-12:
            raise transfer.UnresolvedPairError(model.name, modes, sources[0], outputs[0], 0.5)
        return original(model, modes, sources, outputs, magnitudes)

    monkeypatch.setattr(transfer, "transfer_at_base", refusing_at_30)
    argv = ["transfer", "strapdown_ned", "--source", "accel_bias_x", "--output", "v_E"]
    assert main([*argv, "--latitude", "30deg"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "accel_bias_x → v_E of strapdown_ned" in err
    assert "near the pole" not in err and "tan φ" not in err
    assert "too close to tell apart" in err
    assert err.rstrip().endswith("the same pair is resolved at --latitude 30.01deg")
    assert main([*argv, "--latitude", "30.01deg"]) == 0  # as advised
    capsys.readouterr()
    # near the pole, refused everywhere: the pole is the cause, and no latitude helps
    monkeypatch.setattr(transfer, "REFUSE_LIMIT", -1.0)
    assert main([*argv, "--latitude", "89.99deg"]) == 2
    err = capsys.readouterr().err
    assert "near the pole F's entries grow as tan φ" in err
    assert err.rstrip().endswith("nor is it within 1° of this latitude on either side")


SUPERSCRIPT_DIGITS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def _pint_unit(shown: str) -> str:
    """A gain unit as the text writes it (``1/s³``, ``(m/s)/arcmin·s``) for pint."""
    powers = re.sub(r"s([⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+)",
                    lambda m: f"s**({m.group(1).translate(SUPERSCRIPT_DIGITS)})", shown)
    return powers.replace("·", "*")


def test_a_unit_equal_above_and_below_cancels(capsys, monkeypatch, tmp_path):
    """An output in the source's unit gives a gain in 1/s^n, not arcmin/arcmin/s^n: the
    azimuth error reaches the latitude through the tilt (Ω), g and two integrations,
    in 1/s³; and the unit written is still the gain's: the SI gain read back from the
    display value and unit by pint (the product's registry), for every pair (W = 0 included)."""
    import ins_errors.output as output
    from ins_errors.units import registry

    figures = []
    monkeypatch.setattr(output, "save_figure", lambda fig, path, dpi: figures.append(fig)
                        or path)
    sources = ["initial_azimuth_error", "initial_latitude_error", "initial_longitude_error",
               "initial_velocity_error_north", "gyro_drift_east"]
    argv = ["transfer", "north_pointing", "--output", "latitude", "--output", "v_N",
            "--json", "--plot", str(tmp_path / "w.png")]
    for source in sources:
        argv += ["--source", source]
    assert main(argv) == 0
    pairs = strict_json(capsys.readouterr().out)["pairs"]
    same = 0
    for pair in pairs:
        unit = pair["gain_display_unit"]
        power = pair["relative_degree"] - (pair["source_kind"] == "initial")
        si = f"({pair['output_unit']})/({pair['source_unit']})/s**({power})"
        read = registry().Quantity(pair["gain_display"], _pint_unit(unit)).to(si)
        assert read.magnitude == pytest.approx(pair["gain"], rel=1e-9, abs=0.0), unit
        if pair["source_display_unit"] == pair["output_display_unit"]:
            same += 1
            assert pair["source_display_unit"] not in unit
            assert re.fullmatch(r"1(/s[²³⁴⁵⁶⁷⁸⁹]?)?|s", unit), unit
            assert f"[{unit}]" in pair["factored"] or pair["gain"] == 0
    assert same == 4  # three arcmin → latitude, m/s → v_N
    azimuth = next(p for p in pairs if (p["source"], p["output"]) == (
        "initial_azimuth_error", "latitude"))
    assert azimuth["gain_display_unit"] == "1/s³" and "[1/s³]" in azimuth["factored"]
    # the Bode plot's |W| of an initial velocity error in v_N: a response's transform, s
    labels = [line.get_label() for line in figures[-1].axes[0].get_lines()]
    assert "initial_velocity_error_north → v_N [s]" in labels
