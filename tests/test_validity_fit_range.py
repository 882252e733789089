"""A validity map says over which magnitudes each slope is fitted, and when the fitted
points follow no single power law (their neighbouring slopes far apart), so that a
refined slope of 2.4 is not read as "second order plus a bit"."""

import itertools
import json
import math

import pytest

from ins_errors.cli import main

COMMAND = ["validity", "strapdown_ned", "-s", "initial_heading_error", "--motion", "static",
           "--hours", "1", "--step", "2s", "--engine", "serial"]


def _neighbour_slopes(magnitudes, ratios, low, high):
    """Slopes between neighbouring points from ``low`` to ``high``, from the raw ratios."""
    points = [(m, r) for m, r in zip(magnitudes, ratios, strict=True)
              if low * (1 - 1e-12) <= m <= high * (1 + 1e-12)]
    return [math.log(r2 / r1) / math.log(m2 / m1)
            for (m1, r1), (m2, r2) in itertools.pairwise(points)]


def test_the_heading_errors_refined_fit_is_said_to_average_different_powers(tmp_path,
                                                                           capsys):
    assert main([*COMMAND, "--out", str(tmp_path)]) == 0
    [row] = json.loads((tmp_path / "results.json").read_text())["sources"]
    out = capsys.readouterr().out
    for which in ("linear", "refined"):
        fit = row[f"{which}_fit"]
        low, high = fit["magnitudes"]
        assert low in row["magnitudes"] and high in row["magnitudes"] and low < high
        slopes = _neighbour_slopes(row["magnitudes"], row[f"{which}_ratio"], low, high)
        assert fit["local_slopes"] == pytest.approx([min(slopes), max(slopes)], rel=1e-12)
        # the fitted slope lies among them (a least-squares line through the points)
        assert min(slopes) < row[f"{which}_slope"] < max(slopes)
    refined = row["refined_fit"]["local_slopes"]
    assert refined[1] - refined[0] > 1  # the floor near 1e-7 m of δh and the 4th order
    assert "the refined slope 2.44 is a line through points from 3 arcmin to 15 deg" in out
    assert f"run from {refined[0]:.2f} to {refined[1]:.2f}" in out
    linear = row["linear_fit"]["local_slopes"]
    assert linear[1] - linear[0] < 1 and "the linear slope" not in out  # one power law
