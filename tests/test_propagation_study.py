"""The 001 experiment: analytic vs linear numeric vs direct numeric, and physics checks."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest

from ins_errors.errors import DomainError, UnknownNameError
from ins_errors.studies.propagation import QUANTITIES, Experiment, run, write_report
from tests.helpers import assert_pictures_alike

U = 7.292115e-5


@pytest.fixture(scope="module")
def result():
    return run()


def _q(name: str) -> int:
    return [q[0] for q in QUANTITIES].index(name)


def test_analytic_equals_linear_numeric_for_every_source(result):
    assert len(result.curves) == 12
    for c in result.curves:
        assert np.nanmax(c.agreement("analytic", "linear")) < 1e-6, c.source


def test_direct_follows_linear_to_second_order(result):
    for c in result.curves:
        gap = c.agreement("direct", "linear")
        if np.all(np.isnan(gap)):
            continue
        # the largest angles are a few arcminutes: second-order gaps of a few percent
        assert np.nanmax(gap) < 5e-2, c.source


def test_polar_gyro_drift_gives_the_textbook_longitude_drift(result):
    """After 24 h (≈ a sidereal day) δλ ≈ −ε t (cos φ for north, sin φ for up drift)."""
    e = result.experiment
    t = result.times[-1]
    for source, factor in (("gyro_drift_north", np.cos(e.latitude)),
                           ("gyro_drift_up", np.sin(e.latitude))):
        dlon = result.curve(source).direct[_q("delta_longitude"), -1]
        assert dlon == pytest.approx(-e.gyro_drift * t * factor, rel=2e-2), source


def test_bias_tilt_and_schuler_period(result):
    """A north bias tilts the platform by −∇/g on average, swinging to −2∇/g."""
    e = result.experiment
    c = result.curve("accel_bias_north")
    tilt = c.analytic[_q("alpha_E")]
    first = result.times <= 2 * np.pi * np.sqrt(6_371_000.0 / 9.80665)
    assert np.min(tilt[first]) == pytest.approx(-2 * e.accel_bias / 9.80665, rel=2e-2)
    assert result.periods["report_reduced"]["Schuler"] / 60 == pytest.approx(84.4, abs=0.05)


def test_reduced_model_is_good_early_and_wrong_after_a_day(result):
    """Dropping the Foucault terms turns the Schuler swing by Ω sin φ·t: negligible in
    the first half hour, a sign flip on the scale of a day (Foucault half-period 19 h)."""
    c = result.curve("accel_bias_east")
    k = _q("delta_v_E")
    early = result.times <= 1800.0
    scale = np.max(np.abs(c.analytic[k]))
    drift = U * np.sin(result.experiment.latitude) * 1800.0
    assert np.max(np.abs(c.reduced[k, early] - c.analytic[k, early])) / scale < 2 * drift
    assert c.agreement("reduced", "analytic")[k] > 1.0


def test_summary_and_plots(tmp_path, result):
    summary = write_report(result, tmp_path, sources=["gyro_drift_north"])
    text = summary.read_text()
    assert "| `initial_azimuth_error` |" in text
    assert "Schuler" in text
    png = tmp_path / "gyro_drift_north.png"
    assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(UnknownNameError, match="gyro_drift_north"):
        result.curve("gyro_drift_nort")


def test_plots_equal_fresh_shared_axis_figures_and_fit_the_figure(tmp_path, result,
                                                                   monkeypatch):
    """The sources share one reused figure (curves, ranges and title redone per source)
    whose panels share their time range by construction, not through matplotlib's
    sharex (which lays out every sibling's tick labels again for each panel), and whose
    panel titles keep a fixed place (no search for an offset text to clear: a
    power-of-ten multiplier sits at the right end). Each file after the first must be
    byte for byte that source drawn alone in a figure built with ``sharex=True`` and
    matplotlib's own title placement, after first sources whose flat or tiny curves
    fixed the panels' ranges and showed multipliers. The fixed margins must hold every
    label: nothing drawn may stick out of the figure (the last source has the widest tick
    labels, -0.025 and 0.000), nor may a multiplier overlap its panel's title."""
    from dataclasses import replace

    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    from ins_errors import figure_layout
    from ins_errors.output import OutputFolder
    from ins_errors.studies.propagation import plot

    up = result.curve("gyro_drift_up")
    tiny = replace(up, source="gyro_drift_east", **{  # values of 1e-9: multipliers show
        run: getattr(up, run) * 1e-9 for run in ("direct", "linear", "analytic", "reduced")})
    shown = replace(result, curves=[tiny, *result.curves[1:]])
    assert result.curves[0].source == "gyro_drift_east"
    names = ["gyro_drift_east", "initial_longitude_error", "gyro_drift_up",
             "initial_velocity_error_north"]
    checked = []

    def save(self, fig, name, **options):
        if name in ("gyro_drift_east.png", f"{names[-1]}.png"):
            renderer = fig.canvas.get_renderer()
            box = fig.get_tightbbox(renderer).transformed(fig.dpi_scale_trans.inverted())
            width, height = fig.get_size_inches()
            clear = []
            for ax in fig.axes:
                multiplier = ax.yaxis.offsetText
                title = [t for t in ax.get_children() if isinstance(t, Text)
                         and t.get_text() == ax.get_title(loc="left")]
                if multiplier.get_text():
                    clear.append(not multiplier.get_window_extent(renderer).overlaps(
                        title[0].get_window_extent(renderer)))
            checked.append((box.x0 < 0, box.y0 < 0, box.x1 > width, box.y1 > height, clear))
        return save_figure(self, fig, name, **options)

    save_figure = OutputFolder.save_figure
    monkeypatch.setattr(OutputFolder, "save_figure", save)
    together = plot(shown, OutputFolder(tmp_path / "together"), names)
    assert checked == [(False, False, False, False, [True] * 7),  # every panel: 1e-9
                       (False, False, False, False, [])]
    monkeypatch.setattr(OutputFolder, "save_figure", save_figure)
    subplots = plt.subplots
    monkeypatch.setattr(plt, "subplots", lambda *a, **k: subplots(*a, **k, sharex=True))
    monkeypatch.setattr(figure_layout, "fixed_title",
                        lambda ax, text, **o: ax.set_title(text, **o))
    for k, name in enumerate(names[2:], 2):
        alone = plot(result, OutputFolder(tmp_path / name), [name])[0]
        assert together[k].read_bytes() == alone.read_bytes(), name
    assert together[1].read_bytes() != together[2].read_bytes()


def test_long_record_drawn_from_its_envelope_covers_the_same_pixels(tmp_path, result,
                                                                    monkeypatch):
    """Six hours recorded every second (21 601 samples: smooth curves with a ripple
    and one-sample spikes) draws its solid curves through the column envelope: the
    picture of every sample drawn (antialiased edges may differ by a few levels). The
    dashed and dotted curves stay whole: their pattern runs along the drawn length,
    which a reduction changes (their dots would move)."""
    from dataclasses import replace

    from ins_errors.output import OutputFolder
    from ins_errors.studies import propagation

    times = np.arange(21_601.0)
    ripple = np.sin(2 * np.pi * times / 1500.0)
    source = result.curve("gyro_drift_up")

    def fine(curves):  # the record at 1 s, with a ripple and two spikes on top
        out = np.array([np.interp(times, result.times, row) for row in curves])
        out += 0.05 * np.abs(out).max(axis=1, keepdims=True) * ripple
        out[:, 5_000] *= 1.5
        out[:, 17_001] *= -1.0
        return out

    long = replace(result, times=times, curves=[replace(source, **{
        run: fine(getattr(source, run)) for run in ("direct", "linear", "analytic",
                                                    "reduced")})])
    reduced = propagation.plot(long, OutputFolder(tmp_path / "reduced"))[0]
    monkeypatch.setattr(propagation, "column_envelopes",
                        lambda x, curves, columns: [(x, y) for y in curves])
    full = propagation.plot(long, OutputFolder(tmp_path / "full"))[0]
    # (none here; all four curves through the envelope: ~1500)
    assert_pictures_alike(reduced, full)


def test_bad_experiments_give_one_line_errors():
    with pytest.raises(DomainError, match="±90"):
        run(Experiment(latitude=np.pi / 2))
    with pytest.raises(DomainError, match="duration"):
        run(Experiment(duration=-1.0))
    with pytest.raises(DomainError, match="finite"):
        run(Experiment(gyro_drift=float("nan")))


def test_orthodromic_day_numeric_vs_analytic():
    """Source 000, task 4: every factor over 24 h; closed forms = linear numeric."""
    from ins_errors.studies.propagation import orthodromic_day

    day = orthodromic_day()
    excited = day.excited()
    assert excited.sum() >= 19  # gains on zero static-base rates are not excited
    assert np.nanmax(day.agreement("analytic", "linear")) < 1e-6
    assert np.nanmax(day.agreement("direct", "linear")) < 0.1
    for j in np.nonzero(~excited)[0]:  # numerics of an unexcited factor: round-off
        assert np.max(np.abs(day.linear[:, j])) < 1e-15, day.sources[j]
    text = day.summary_markdown()
    assert "not excited" in text and "`gyro_drift_z`" in text
    # the step-doubling estimate agrees with the closed forms' verdict on the linear run
    # (agreement's worst state may be one the estimate leaves out as barely excited, so
    # it only bounds the estimate from above there)
    true = day.agreement("analytic", "linear")
    close = 0
    for j in np.nonzero(excited & (true > 1e-10))[0]:
        assert day.integration[j] / true[j] < 2.0, day.sources[j]
        close += bool(day.integration[j] / true[j] > 0.5)
        assert not day.warnings[j], day.sources[j]
    assert close >= 12
    assert "integration error |" in text and "Warnings:" not in text
    with pytest.raises(DomainError, match="90"):
        orthodromic_day(latitude=np.pi / 2)


def test_command_line(tmp_path, capsys):
    from ins_errors.cli import main

    assert main(["propagation", "--hours", "2", "--latitude", "49deg"]) == 0
    out = capsys.readouterr().out
    assert "latitude 49°" in out and "| `gyro_drift_up` |" in out
    assert main(["propagation", "--orthodromic", "--hours", "1", "--out", str(tmp_path)]) == 0
    assert "not excited" in (tmp_path / "orthodromic_day.md").read_text()
    capsys.readouterr()
    assert main(["propagation", "--latitude=-90deg"]) == 2
    assert "±90" in capsys.readouterr().err
    assert main(["propagation", "--drift", "0.1 m/s"]) == 2
    assert "--drift" in capsys.readouterr().err
    assert main(["propagation", "--hours", "0"]) == 2


def test_default_run_estimates_a_small_integration_error(result):
    """RK4 at 10 s: the estimate matches the closed forms' verdict on the linear run
    (analytic vs linear numeric is that run's true integration error) and gives no warning."""
    for c in result.curves:
        true = c.agreement("analytic", "linear")
        if np.all(np.isnan(true)) or np.nanmax(true) < 1e-10:
            continue
        assert 0.5 < c.integration_share() / np.nanmax(true) < 2.0, c.source
        assert not c.warnings, c.source


def test_coarse_rectangle_run_estimates_its_true_error_and_warns():
    """Rectangle method at τ = 20 s over 2 h: the step-doubling estimate of every
    quantity is within a factor 2 of its true error, measured against an RK4 run at
    10 s (whose own error is ~1e-9 relative), and the run warns naming a finer step."""
    reference = run(Experiment(duration=7200.0))
    coarse = run(Experiment(duration=7200.0, method="euler", step=20.0))
    checked = 0
    for c, r in zip(coarse.curves, reference.curves, strict=True):
        true = np.max(np.abs(c.direct - r.direct), axis=1)
        scale = np.max(np.abs(r.direct), axis=1)
        used = true > 1e-3 * scale
        ratio = c.integration_error[used] / true[used]
        assert np.all((ratio > 0.5) & (ratio < 2.0)), (c.source, ratio)
        checked += int(used.sum())
        if np.any(used):
            assert any("rectangle method with τ = 20 s is too coarse" in w
                       and "would do" in w for w in c.warnings), c.source
    assert checked > 50
    assert "Warnings:" in coarse.summary_markdown()


def test_command_line_reports_the_integration_error(capsys):
    import json

    from ins_errors.cli import main

    assert main(["propagation", "--hours", "1", "--method", "euler", "--step", "20s",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["method"] == "euler"
    row = next(s for s in data["sources"] if s["source"] == "accel_bias_north")
    assert row["integration_error"] > 1e-3 and set(row["integration_error_si"]) == {
        q[0] for q in QUANTITIES}
    assert any("too coarse" in w for w in row["warnings"])
    assert main(["propagation", "--hours", "1"]) == 0
    out = capsys.readouterr().out
    assert "integration error |" in out and "Warnings:" not in out


def _same_bits(a, b) -> bool:
    """Equal to the last bit: arrays by dtype, shape and bytes, containers item by item."""
    if isinstance(a, np.ndarray):
        return (isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape
                and a.tobytes() == b.tobytes())
    if dataclasses.is_dataclass(a):
        return type(a) is type(b) and all(_same_bits(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(map(_same_bits, a, b))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same_bits(a[k], b[k]) for k in a)
    if isinstance(a, float):
        return np.float64(a).tobytes() == np.float64(b).tobytes()
    return a == b


def test_compiled_runs_give_the_bits_of_the_virtual_machine(monkeypatch):
    """The study's runs use the compiled (cached) loops: the experiment and the day run,
    each with its step-doubling estimate, give the numbers, warnings and summaries the
    CasADi virtual machine gives, to the last bit."""
    from ins_errors.studies import propagation

    compiled = (run(Experiment(duration=7200.0, method="euler", step=20.0)),
                propagation.orthodromic_day(duration=7200.0))
    for name in ("simulate", "add_integration_errors"):
        monkeypatch.setattr(propagation, name, functools.partial(
            getattr(propagation, name), jit=False))
    virtual = (run(Experiment(duration=7200.0, method="euler", step=20.0)),
               propagation.orthodromic_day(duration=7200.0))
    for a, b in zip(compiled, virtual, strict=True):
        assert _same_bits(a, b)
        assert a.summary_markdown() == b.summary_markdown()
