"""The refined run, angle residuals and what a comparison says about them.

* The refined run integrates the truncated quadratic error equations, which can run
  away where the direct run stays bounded: the comparison warns, and the plot keeps the
  direct and linear curves' range (the refined curve clipped, and said to be).
* The refined run reads its outputs through the exact output map: at t = 0 it is the
  exact initial error (the second-order expansion of the heading's atan2 gave
  ψ + ψ³/12 for a heading error ψ).
* Residuals of angles are differences on the circle: a linear longitude error wrapped
  past 180° beside a direct one that is not read 301° apart, not 59°.
* A negligible integration-error estimate is called rounding only when the runs at three
  steps show it is; a true step error (confirmed by a run at a 16 times smaller step)
  is called one.

References are independent of the code under test: the exact initial heading error
(the source's value), differences on the circle written with complex exponentials, a
run at a much smaller step.
"""

from __future__ import annotations

import numpy as np
import pytest

import ins_errors
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import compare, markdown_summary

DEG = np.pi / 180.0
ARCMIN = DEG / 60.0
DAMPED = {"k_h1": 0.0293, "k_h2": 4.42e-4}  # a 300-s vertical loop, damping 0.7


@pytest.fixture(scope="module")
def strapdown() -> ins_errors.Model:
    return ins_errors.load_model("strapdown_ned")


@pytest.fixture(scope="module")
def runaway(strapdown):
    """A 10 °/h azimuth gyro bias over 24 h, damped vertical channel, τ = 2 s: the
    refined run runs away (its height error reached 2,200 km), the direct one does not."""
    p = strapdown.parameter_vector(**DAMPED)
    motion = tr.trajectory(strapdown, tr.static_profile(50 * DEG, 30 * DEG), 24 * 3600.0,
                           2.0, p=p)
    (comparison,) = compare(strapdown, motion, [{"gyro_bias_z": 10 * DEG / 3600.0}],
                            record_interval=60.0, integration_error=False,
                            validity_threshold=None, warn=False)
    return comparison


def test_a_refined_run_that_runs_away_is_warned_of(runaway):
    # the direct run stays bounded: a few hundred m/s and tens of metres
    assert np.max(np.abs(runaway.direct["delta_v_E"])) < 300.0
    assert np.max(np.abs(runaway.direct["delta_height"])) < 50.0
    # the refined run leaves that range by orders of magnitude
    assert np.max(np.abs(runaway.refined["delta_height"])) > 1e5
    assert runaway.worst_refined.refined_ratio > 100.0
    (warning,) = [w for w in runaway.warnings if "refined" in w]
    assert warning.startswith("the refined (second-order) run diverged from about ")
    assert "its quadratic terms are beyond their range here" in warning
    assert "trust the direct run" in warning
    assert runaway.refined_warning == "diverged"
    # from the time its residual first exceeds the direct error's size: after the first
    # hours, where it followed the direct run, and before the end
    assert 5 * 3600.0 < runaway.refined_departure < 20 * 3600.0
    early = runaway.times < 4 * 3600.0
    for q in ("delta_v_N", "delta_v_E", "delta_height"):
        d, r = runaway.direct[q][early], runaway.refined[q][early]
        assert np.max(np.abs(r - d)) < 0.05 * np.max(np.abs(d)), q
    record = runaway.to_dict()  # what --json and results.json give
    assert record["refined_warning"] == "diverged"
    assert record["refined_departure_s"] == runaway.refined_departure
    assert warning in record["warnings"]
    assert warning in markdown_summary([runaway])


def test_a_small_source_gets_no_refined_warning(strapdown):
    """0.01 °/h on the same channel: the refined residual is far below the linear one."""
    p = strapdown.parameter_vector(**DAMPED)
    motion = tr.trajectory(strapdown, tr.static_profile(50 * DEG, 30 * DEG), 6 * 3600.0,
                           2.0, p=p)
    (c,) = compare(strapdown, motion, [{"gyro_bias_z": 0.01 * DEG / 3600.0}],
                   record_interval=60.0, integration_error=False, validity_threshold=None,
                   warn=False)
    assert c.refined_warning is None and not any("refined" in w for w in c.warnings)
    assert all(m.refined_difference < 0.1 * m.linear_difference for m in c.excited)


def test_angle_residuals_are_differences_on_the_circle(runaway):
    """The linear longitude error crosses 180° (at about 20.5 h) while the direct one
    stays near −124°: the plain difference reached 301°, a ratio of 2.42."""
    d, lin = runaway.direct["delta_longitude"], runaway.linear["delta_longitude"]
    plain = np.max(np.abs(lin - d))
    assert plain > np.pi  # the linear curve wrapped, the direct one did not
    on_circle = np.max(np.abs(np.angle(np.exp(1j * (lin - d)))))
    m = runaway.metric("delta_longitude")
    assert m.linear_difference == pytest.approx(on_circle, rel=1e-12)
    assert m.linear_ratio == pytest.approx(on_circle / np.max(np.abs(d)), rel=1e-12)
    assert m.linear_ratio < 1.0
    for q in ("delta_latitude", "delta_longitude", "delta_roll", "delta_pitch",
              "delta_heading"):
        d, r = runaway.direct[q], runaway.refined[q]
        expected = np.max(np.abs(np.angle(np.exp(1j * (r - d)))))
        assert runaway.metric(q).refined_difference == pytest.approx(expected, rel=1e-12), q
        assert runaway.metric(q).refined_difference <= np.pi


def test_the_plot_keeps_the_direct_and_linear_range_and_says_where_refined_leaves_it(
        runaway, tmp_path):
    from ins_errors.numeric import plots

    path = plots.plot_comparison(runaway, tmp_path / "runaway.png")
    assert path.stat().st_size > 0
    figure = plots._SPARE_FIGURES.figures[-1]
    # the refined curves are drawn up to where the run diverged, not after
    drawn = runaway.times <= runaway.refined_departure
    assert 0 < drawn.sum() < drawn.size
    beyond = []
    for (q, scale, _), (left, right) in zip(figure.lines, figure.axes, strict=True):
        d, lin = runaway.direct[q] * scale, runaway.linear[q] * scale
        low, high = left.get_ylim()
        # the direct and linear curves fill the panel (no refined curve swamping it)
        assert low <= min(d.min(), lin.min()) and high >= max(d.max(), lin.max()), q
        assert high - low < 1.2 * np.ptp(np.concatenate([d, lin])), q
        circle = runaway.metric(q).unit == "rad"

        def off(curve, d=runaway.direct[q], circle=circle, scale=scale):
            gap = curve - d
            return np.abs(np.angle(np.exp(1j * gap)) if circle else gap) * scale

        lin_res, ref_res = off(runaway.linear[q]), off(runaway.refined[q])[drawn]
        low, high = right.get_ylim()
        assert high - low < 2.3 * max(lin_res.max(), np.abs(d).max()), q
        beyond.append(ref_res.max() > max(abs(low), abs(high)))
    for (_, right_note), clipped in zip(figure.notes, beyond, strict=True):
        assert right_note.get_text().startswith("refined beyond the axes (to ") == clipped
        assert (right_note.get_text() == "") != clipped
    (right_legend_entry,) = [t.get_text() for t in figure.legends[1].get_texts()
                             if t.get_text().startswith("refined")]
    cut = f"diverged: not drawn after {runaway.refined_departure / 3600:.3g} h"
    clipped = (f"; clipped: leaves the axes in {sum(beyond)} of {len(figure.lines)} panels"
               if any(beyond) else "")
    assert right_legend_entry == f"refined − direct ({cut}{clipped})"


def test_a_good_refined_run_is_not_clipped(strapdown, tmp_path):
    from ins_errors.numeric import plots

    motion = tr.trajectory(strapdown, tr.static_profile(50 * DEG, 30 * DEG), 3600.0, 2.0,
                           p=strapdown.parameter_vector(**DAMPED))
    (c,) = compare(strapdown, motion, [{"initial_heading_error": 1 * DEG}],
                   record_interval=60.0, integration_error=False, validity_threshold=None,
                   warn=False)
    plots.plot_comparison(c, tmp_path / "good.png")
    figure = plots._SPARE_FIGURES.figures[-1]
    assert all(note.get_text() == "" for row in figure.notes for note in row)
    texts = {t.get_text() for legend in figure.legends for t in legend.get_texts()}
    assert {"refined", "refined − direct"} <= texts


@pytest.mark.parametrize("heading", [10.0, 30.0])
def test_the_refined_outputs_start_at_the_exact_initial_error(strapdown, heading):
    """The refined run starts from the exact initial difference; its heading at t = 0
    read ψ + ψ³/12 through the second-order output map (0.174975 rad for 10°)."""
    motion = tr.trajectory(strapdown, tr.static_profile(50 * DEG, 30 * DEG), 600.0, 1.0)
    (c,) = compare(strapdown, motion, [{"initial_heading_error": heading * DEG}],
                   record_interval=10.0, integration_error=False, validity_threshold=None,
                   warn=False)
    assert c.refined["delta_heading"][0] == pytest.approx(heading * DEG, abs=4e-16)
    for q in c.direct:
        assert c.refined[q][0] == pytest.approx(c.direct[q][0], abs=1e-15), q
    # over the 10 minutes the refined residual is of third order: far below the linear
    m = c.metric("delta_heading")
    assert m.refined_difference < 0.01 * m.linear_difference


def test_the_refined_outputs_start_at_the_exact_initial_error_on_a_platform(orthodromic):
    """The orthodromic model's latitude, longitude and heading from direction cosines:
    at t = 0 the refined errors are the exact initial errors too."""
    motion = tr.trajectory(orthodromic, tr.static_profile(50 * DEG, 30 * DEG), 600.0, 1.0)
    errors = {"initial_heading_error": 20 * DEG, "initial_latitude_error": 30 * ARCMIN,
              "initial_longitude_error": 40 * ARCMIN}
    (c,) = compare(orthodromic, motion, [errors], record_interval=10.0,
                   integration_error=False, validity_threshold=None, warn=False)
    assert c.refined["delta_latitude"][0] == pytest.approx(30 * ARCMIN, abs=1e-15)
    assert c.refined["delta_longitude"][0] == pytest.approx(40 * ARCMIN, abs=1e-15)


def test_a_negligible_step_error_is_not_called_rounding(strapdown):
    """A 1-h manoeuvre at τ = 4 s, recorded every 20 s: the estimate (below 1e-6 of the
    error) is the scheme's error, as a run at τ = 0.25 s shows; the summary called it
    rounding."""
    from ins_errors.commands import motion_from_options
    from ins_errors.numeric.simulate import simulate

    profile = motion_from_options({"kind": "manoeuvre"}, model=strapdown)
    p = strapdown.parameter_vector(**DAMPED)
    sources = {"initial_heading_error": 2 * DEG, "gyro_bias_x": 0.1 * DEG / 3600.0}
    motion = tr.trajectory(strapdown, profile, 3600.0, 4.0, p=p)
    (c,) = compare(strapdown, motion, [sources], record_interval=20.0, refined=False,
                   validity_threshold=None, warn=False)
    fine = simulate(strapdown, tr.trajectory(strapdown, profile, 3600.0, 0.25, p=p),
                    [sources], record_interval=20.0, parts=("real",)).direct_errors()
    q = "delta_latitude"
    m = c.metric(q)
    true = np.max(np.abs(c.direct[q] - fine[q][:, 0]))
    assert m.direct_integration_error == pytest.approx(true, rel=0.1)
    assert true / m.max_direct < 1e-6  # negligible, but not rounding
    assert c.integration_negligible and not c.integration_at_rounding
    assert c.negligible_cause == "step error"
    summary = markdown_summary([c])
    assert "| < 1e-06 (negligible step error) |" in summary and "(rounding)" not in summary
    record = c.to_dict()
    assert record["integration_error_negligible"] is True
    assert record["integration_error_at_rounding"] is False
    assert record["integration_error_below_relevant"] == "step error"
