"""The validity warning of ``compare`` says what its own measurements show.

When linear − direct exceeds the threshold, the cases run again at smaller magnitudes to
find where the ratio would be 1 %. First-order theory has the ratio fall in proportion
to the magnitude. Where it does not fall (a direct error with a part that the sources
do not scale), no magnitude brings it to 1 %, and the warning must say so instead of
naming a magnitude "where it would be 1 %" beside its own measurement of 100 % there (an
ECEF model whose real work dropped the centrifugal term:
"it would be 1 % at 0.005× the magnitudes (… the ratio measured there: 100.00%)").
A run with every source at zero whose direct errors still move has no source to name.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from ins_errors.cli import main
from ins_errors.numeric.compare import Comparison, Metric, add_validity_warnings

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
G = 9.80665
LEVEL = 1e-5 * G
"""m/s²: the size of the saturating accelerometer term of :func:`_saturating_model`."""
KNEE = 1e-12 * G
"""m/s²: the bias at which that term reaches half its size."""


def _saturating_model(tmp_path: Path) -> Path:
    """The tutorial's Schuler loop whose accelerometer error is the bias b plus a term
    LEVEL · b² / (b² + KNEE²): zero at b = 0 (the real work reduces to the ideal work)
    and smooth, but at any bias above KNEE it is LEVEL, whatever the bias: a part of the
    error the bias does not scale, which the linear model (slope 0 at b = 0) does not see."""
    text = SCHULER.read_text(encoding="utf-8")
    old = "g * sp.sin(psi) + bias,"
    assert old in text
    text = text.replace(old, "g * sp.sin(psi) + bias + 1e-5 * g * bias**2 "
                             "/ (bias**2 + (1e-12 * g)**2),")
    path = tmp_path / "saturating_loop.py"
    path.write_text(text, encoding="utf-8")
    return path


def _compare(path: Path, source: str, capsys) -> dict:
    assert main(["compare", str(path), "--source", source, "--hours", "1", "--step", "60s",
                 "--no-refined", "--json"]) == 0
    [case] = json.loads(capsys.readouterr().out)["cases"]
    return case


def _ratio(bias: float) -> float:
    """linear − direct over direct for the saturating loop at a bias (m/s²): the loop is
    linear in its accelerometer error, the direct run's is b + s(b), the linear's b."""
    extra = LEVEL * bias**2 / (bias**2 + KNEE**2)
    return extra / (bias + extra)


def test_a_ratio_that_does_not_fall_with_the_magnitudes_gets_no_one_percent_magnitude(
        tmp_path, capsys):
    bias = 100e-6 * G
    case = _compare(_saturating_model(tmp_path), "accel_bias=100ug", capsys)
    assert math.isclose(case["worst_linear_ratio"], _ratio(bias), rel_tol=1e-4)  # 1/11
    [words] = [w for w in case["warnings"] if "valid" in w]
    # no magnitude is promised: none exists
    assert case["one_percent_scale"] is None
    assert "it would be 1 %" not in words and "measured there" not in words
    assert words.startswith("linear model not valid at any magnitude measured")
    assert "9.1% of" in words and "threshold 5%" in words
    # the smallest factor measured, and the ratio there, are those of the model
    found = re.search(r"the worst ratio is still ([\d.]+)% at ([\d.e+-]+)× the magnitudes "
                      r"\(accel_bias = ([\d.e+-]+) ug\)", words)
    assert found, words
    ratio, factor, shown = float(found[1]) / 100, float(found[2]), float(found[3])
    assert factor <= 0.1 and math.isclose(shown, 100 * factor, rel_tol=1e-2)
    assert math.isclose(ratio, _ratio(factor * bias), rel_tol=1e-3), (ratio, factor)
    # first order would have it near ratio × factor there: said, so the contrast is seen
    first = re.search(r"fall with them to about ([\d.e+-]+)%", words)
    assert first and math.isclose(float(first[1]) / 100, _ratio(bias) * factor, rel_tol=1e-2)
    for word in ("does not shrink with the sources", "without a source",
                 "reduce to the ideal-work ones when every error source is zero"):
        assert word in words, word
    # against a ratio that falls: the tutorial loop's exact cos ψ, sin ψ at a 30° tilt
    # is beyond 5 %, and the warning names about where it is 1 %, a step from a
    # measurement near it
    case = _compare(SCHULER, "initial_tilt=30deg", capsys)
    [words] = [w for w in case["warnings"] if "valid" in w]
    assert words.startswith("linear model beyond its validity")
    assert "it would be 1 % at about" in words
    assert 0.05 < case["one_percent_scale"] < 1
    found = re.search(r"from ([\d.]+)% measured at ([\d.e+-]+)×", words)
    assert found and 0.8 <= float(found[1]) <= 1.25, words


def _unexcited_case(sources: dict[str, float]) -> Comparison:
    """A case whose linear errors stay zero while its direct latitude error grows to
    9.46 arcmin over 30 min (an ECEF INS whose real work lacks the centrifugal term)."""
    times = np.linspace(0.0, 1800.0, 31)
    peak = math.radians(9.46 / 60)
    direct = peak * (times / times[-1]) ** 2
    metric = Metric("delta_latitude", "rad", peak, peak, 1.0, None, None, True)
    return Comparison("case", sources, [metric], times, {"delta_latitude": direct},
                      {"delta_latitude": 0 * direct}, {})


def test_a_run_without_error_input_names_no_empty_source():
    case = _unexcited_case({})
    add_validity_warnings([case], sim=None)  # nothing to run again: no simulation needed
    [words] = case.warnings
    assert "does not see" not in words and " : " not in words and "see :" not in words
    for word in ("no error input", "every error source is zero", "delta_latitude reaches "
                 "9.46 arcmin", "without a source", "real work does not reduce to the "
                 "ideal work"):
        assert word in words, (word, words)
    # a source that is set but unseen is still named
    case = _unexcited_case({"accel_bias_x": 1e-4})
    add_validity_warnings([case], sim=None)
    assert case.warnings[0].startswith("the linear model does not see accel_bias_x: ")
