"""What the budget's words say of its numbers: the σ level of a white-noise density on
the allocation chart, and which magnitudes the tables are at when nothing is allocated."""

from __future__ import annotations

import json
import re
import textwrap

import numpy as np
import pytest

from ins_errors.analysis import budget_report
from ins_errors.cli import main

NOISE_SPEC = """
title = "free noise"
sigma_level = 3
operating_time = "4 h"
step = "60 s"
[motion]
kind = "static"
latitude = "45 deg"
longitude = "0 deg"
[items.position_error_absolute]
value = "6 km"
every = "30 min"
[items.ground_speed_error]
value = "3 m/s"
every = "10 min"
[sources.gyro_drift_east]
kind = "white"
[sources.accel_bias_north]
kind = "white"
[sources.gyro_drift_north]
kind = "markov"
tau = "1 h"
"""

TO_DISPLAY = {"(rad/s)*s**0.5": np.degrees(1.0) * 60.0,   # deg/√h
              "(m/s**2)*s**0.5": 1 / 9.80665e-6}           # ug/√Hz
"""SI noise density -> the unit the chart labels it in (1 rad/√s = 180/π · 60 deg/√h)."""


def test_the_allocation_chart_tags_white_noise_densities_as_1_sigma(tmp_path, monkeypatch,
                                                                    capsys):
    """The caption said "3σ magnitudes as labelled" over a white density's bar, whose
    number is the 1σ density (a density has no σ level; the tables say so): its bar is
    tagged (1σ), its number is the allocated 1σ density, and the caption says it."""
    spec = tmp_path / "noise.toml"
    spec.write_text(textwrap.dedent(NOISE_SPEC))
    figures = []
    monkeypatch.setattr(budget_report, "save_figure",
                        lambda figure, path, **kw: figures.append(figure))
    assert main(["budget", "north_pointing", "--spec", str(spec), "--plot",
                 str(tmp_path / "b.png"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    [figure] = figures
    left = figure.axes[0]
    labels = [t.get_text() for t in left.get_yticklabels()]
    white = 0
    for source in data["sources"]:
        if source["binding_item"] is None:
            continue
        [label] = [t for t in labels if t.startswith(source["label"] + "  ")]
        if source["statistics"] == "white":
            white += 1
            assert label.endswith(" (1σ)"), label
            number = float(re.search(r"≤ (\S+)", label).group(1))
            density = source["magnitude_1sigma"] * TO_DISPLAY[source["unit"]]
            assert number == pytest.approx(density, rel=1e-3)
        else:
            assert "1σ" not in label, label
    assert white == 2
    assert "3σ magnitudes, white-noise densities 1σ, as labelled" in " ".join(
        left.get_xlabel().split())
    import matplotlib.pyplot as plt

    plt.close(figure)


@pytest.mark.parametrize("source, given, density, datasheet", [
    ("gyro_drift_east", "0.01 deg/h", "(rad/s)*s**0.5", "0.01 deg/sqrt(h)"),
    ("accel_bias_north", "10 ug", "(m/s**2)*s**0.5", "10 ug/sqrt(Hz)"),
    ("gyro_drift_east", "0.01", "(rad/s)*s**0.5", "0.01 deg/sqrt(h)")])
def test_a_white_source_given_a_bias_suggests_a_datasheet_density(tmp_path, capsys, source,
                                                                  given, density, datasheet):
    """kind = "white" with fixed = "0.01 deg/h" was answered "give a quantity in units of
    (rad/s)*s**0.5, e.g. '0.01 (rad/s)*s**0.5'": the suggestions are now what a
    datasheet quotes (deg/√h for a gyro, µg/√Hz for an accelerometer), each of them
    read back as a density."""
    from ins_errors.units import parse_quantity

    spec = tmp_path / "white.toml"
    spec.write_text(textwrap.dedent(f"""
        sigma_level = 3
        operating_time = "1 h"
        [motion]
        kind = "static"
        latitude = "45 deg"
        [items.position_error_absolute]
        value = "6 km"
        [sources.{source}]
        kind = "white"
        fixed = "{given}"
    """))
    assert main(["budget", "north_pointing", "--spec", str(spec)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"sources.{source}.fixed" in err
    suggested = re.findall(r"'([^']+)'", err.partition("e.g.")[2])
    assert suggested[0] == datasheet and "s**0.5" not in err.partition("; give")[2]
    number = float(given.split()[0])
    for text in suggested:
        assert parse_quantity(text, density, "x") > 0
    # the first is the datasheet's unit of the number given: 1 deg/√h = π/180/60 rad/√s
    expected = {"(rad/s)*s**0.5": np.radians(number) / 60,
                "(m/s**2)*s**0.5": number * 9.80665e-6}[density]
    assert parse_quantity(suggested[0], density, "x") == pytest.approx(expected)


FIXED_SPEC = """
title = "fixed only"
sigma_level = 3
operating_time = "4 h"
step = "60 s"
[motion]
kind = "static"
latitude = "45 deg"
[items.heading_error]
value = "5 deg"
[sources.gyro_drift_up]
fixed = "0.01 deg/h"
"""


def test_a_budget_of_fixed_sources_says_its_rows_are_at_the_given_magnitudes(tmp_path,
                                                                              capsys):
    """Every source fixed, nothing is allocated: the tables and the report said "at the
    allocated magnitudes". The rows are at the magnitudes the spec gives: the heading
    error of a 0.01 °/h (3σ) azimuth drift ε at rest is ε sin(Ωt)/Ω (the Earth rate
    turns it into level tilt), 0.033° after 4 h."""
    from ins_errors.models import definition

    names = [s.name for s in definition("north_pointing").sources]
    spec = tmp_path / "fixed.toml"
    spec.write_text(textwrap.dedent(FIXED_SPEC) + "".join(
        f"[sources.{name}]\ninclude = false\n" for name in names if name != "gyro_drift_up"))
    report = tmp_path / "fixed.md"
    assert main(["budget", "north_pointing", "--spec", str(spec), "--at", "1h,4h",
                 "--report", str(report)]) == 0
    out = capsys.readouterr().out
    text = out + report.read_text(encoding="utf-8")
    assert "allocated magnitudes" not in text
    assert "Spec rows at the given magnitudes" in out
    assert out.count("(1σ, at the given magnitudes)") == 2   # the two --at tables
    assert "## Spec items at the given magnitudes" in text
    assert "check times, at the given magnitudes" in text
    heading = float(re.search(r"heading_error\s+4 h\s+(\S+) deg of 5 deg", out).group(1))
    earth, t = 7.292115e-5, 4 * 3600.0
    assert heading == pytest.approx(0.01 * np.sin(earth * t) / (earth * 3600), rel=0.02)
