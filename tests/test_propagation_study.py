"""The 001 experiment: analytic vs linear numeric vs direct numeric, and physics checks."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest

from ins_errors.errors import DomainError, UnknownNameError
from ins_errors.studies.propagation import QUANTITIES, Experiment, run, write_report
from tests.helpers import assert_pictures_alike, one_blas_thread_for_references

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
    """The direct − linear gap is second order: relative to the error it is first order
    in the magnitude, so every source at half its magnitude halves it (measured: 0.5
    within 5e-4). The largest, 2.6 % (azimuth drift: its angles reach a few arcminutes
    in a day)."""
    e = result.experiment
    half = run(dataclasses.replace(
        e, gyro_drift=e.gyro_drift / 2, accel_bias=e.accel_bias / 2,
        velocity_error=e.velocity_error / 2, position_error=e.position_error / 2,
        level_error=e.level_error / 2, azimuth_error=e.azimuth_error / 2))
    checked = 0
    for c, h in zip(result.curves, half.curves, strict=True):
        assert c.source == h.source
        gap = c.agreement("direct", "linear")
        if np.all(np.isnan(gap)) or np.nanmax(gap) == 0.0:
            continue
        assert np.nanmax(gap) < 3e-2, c.source
        ratio = np.nanmax(h.agreement("direct", "linear")) / np.nanmax(gap)
        assert ratio == pytest.approx(0.5, abs=5e-3), c.source
        checked += 1
    assert checked >= 10


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


def test_summary_has_a_key_to_the_report_symbols(tmp_path, result):
    """dN is the longitude error (a student read it as "north"): summary.md keys every
    symbol of its tables to the quantity, the error state and the unit, and the key
    agrees with the model's own description of each state and with the columns' units."""
    from ins_errors import load_model

    text = write_report(result, tmp_path, sources=["gyro_drift_north"]).read_text()
    key = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:5]]
           for line in text.splitlines()
           if line.startswith("| ") and line.count("|") == 5 and "`" in line
           and "|" not in line.split("|")[1]}
    model = load_model("north_pointing")
    described = {s.name: s.description for s in model.error_states}
    columns = text.split("Values at the end of the run")[1].splitlines()[2]
    for symbol in ("dVx", "dVy", "dL", "dN", "Qx", "Qy", "Qz"):
        quantity, state, unit = key[symbol]
        state = state.strip("`")
        assert f"{symbol}, {unit}" in columns
        words = described[state].split("(")[0].strip()
        assert words.split()[-1] in quantity, (symbol, quantity, described[state])
    assert key["dN"][1] == "`delta_longitude`" and "longitude" in key["dN"][0]
    assert key["dL"][1] == "`delta_latitude`" and "latitude" in key["dL"][0]
    assert text.index("| symbol | quantity |") < text.index("| source | analytic")


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


def test_summary_says_the_integration_error_is_relative_and_to_what(result):
    """The table's integration error is a ratio (the estimate over max |linear numeric|,
    as the agreement): the summary printed it bare, as if it were in some unit."""
    text = result.summary_markdown()
    header = next(line for line in text.splitlines() if line.startswith("| source |"))
    columns = [c.strip() for c in header.strip("|").split("|")]
    k = columns.index("integration error (relative)")
    assert "divided by the same max |linear numeric|" in text
    curve = result.curve("gyro_drift_east")
    row = next(line for line in text.splitlines() if line.startswith("| `gyro_drift_east`"))
    shown = float(row.strip("|").split("|")[k])
    ratio = np.nanmax(curve.integration_error / np.max(np.abs(curve.linear), axis=1))
    assert shown == pytest.approx(ratio, rel=0.01)


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
    # second order: largest 6.7 % (a day of 0.1 °/h second-integrator offset), measured
    assert np.nanmax(day.agreement("direct", "linear")) < 0.08
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
    assert "integration error (relative) |" in text and "Warnings:" not in text
    assert "/ max |direct|" in text  # what it is relative to
    # the navigation errors a lab report reads (latitude, longitude, north and east
    # velocity): the closed forms mapped by H of the static base follow the linear run's
    # own output errors, and the direct run follows both to second order
    assert day.navigation == ["delta_latitude", "delta_longitude", "delta_v_N", "delta_v_E"]
    for j in np.nonzero(excited)[0]:
        scale = np.max(np.abs(day.navigation_linear[:, j]), axis=1)
        live = scale > 0
        gap = np.max(np.abs(day.navigation_analytic[:, j] - day.navigation_linear[:, j]),
                     axis=1)
        assert np.all(gap[live] < 1e-6 * scale[live]), day.sources[j]
        gap = np.max(np.abs(day.navigation_direct[:, j] - day.navigation_linear[:, j]),
                     axis=1)
        assert np.all(gap[live] < 0.1 * scale[live]), day.sources[j]
    with pytest.raises(DomainError, match="90"):
        orthodromic_day(latitude=np.pi / 2)


def test_command_line(tmp_path, capsys):
    from ins_errors.cli import main

    assert main(["propagation", "--hours", "2", "--latitude", "49deg"]) == 0
    out = capsys.readouterr().out
    assert "latitude 49°" in out and "| `gyro_drift_up` |" in out
    assert main(["propagation", "--orthodromic", "--hours", "1", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "orthodromic_day.md").read_text()
    assert "not excited" in text
    # source 000's task runs at the 50° of the other source-000 commands, not at the 39°
    # read from source 001's partly legible latitude
    assert "Static base at latitude 50°" in text
    # plots as the 001 run writes them: one per source the day run excites, none (and
    # why) for the gains whose input is zero at rest
    from ins_errors.studies.propagation import ORTHODROMIC_MAGNITUDES

    drawn = sorted(p.stem for p in tmp_path.glob("*.png"))
    assert "accel_scale_error_x" not in drawn and len(drawn) >= 19
    assert set(drawn) < set(ORTHODROMIC_MAGNITUDES)
    for name in drawn:
        assert f"![{name}]({name}.png)" in text
        assert (tmp_path / f"{name}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "No plot for " in text and "`accel_scale_error_x`" in text.split("No plot for ")[1]
    assert f"and {len(drawn)} plots" in capsys.readouterr().out
    capsys.readouterr()
    assert main(["propagation", "--latitude=-90deg"]) == 2
    assert "--latitude -90° is at or beyond a pole" in capsys.readouterr().err
    assert main(["propagation", "--drift", "0.1 m/s"]) == 2
    assert "--drift" in capsys.readouterr().err
    with pytest.raises(SystemExit) as usage:   # refused by its option type, as argparse does
        main(["propagation", "--hours", "0"])
    assert usage.value.code == 2
    assert "--hours: must be a positive number of hours, got 0" in capsys.readouterr().err


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
            # a finer rectangle step, or RK4 when that step needs more than a run may take
            assert any(("τ = 20 s, rectangle method" in w
                        or "use RK4 (--method rk4" in w)
                       and "s would " in w for w in c.warnings), c.source
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
    assert any("integration error too large" in w for w in row["warnings"])
    assert main(["propagation", "--hours", "1"]) == 0
    out = capsys.readouterr().out
    assert "integration error (relative) |" in out and "Warnings:" not in out


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


# --------------------------------------------------------------------------------------
# A new user's probe: labels, the reduced-vs-full measure, hemispheres, zero magnitudes,
# the gravity behind the orthodromic periods. References computed here, independently of
# the closed forms: matrix exponentials of the static-base error equations written out.
# --------------------------------------------------------------------------------------
G0, R0 = 9.80665, 6_371_000.0
_ROWS = {  # error source -> (kind, state row) of the 7 error states of QUANTITIES
    "gyro_drift_east": ("input", 4), "gyro_drift_north": ("input", 5),
    "gyro_drift_up": ("input", 6), "accel_bias_east": ("input", 0),
    "accel_bias_north": ("input", 1), "initial_velocity_error_east": ("initial", 0),
    "initial_velocity_error_north": ("initial", 1), "initial_latitude_error": ("initial", 2),
    "initial_longitude_error": ("initial", 3), "initial_tilt_east": ("initial", 4),
    "initial_tilt_north": ("initial", 5), "initial_azimuth_error": ("initial", 6)}


def _static_base_matrix(latitude: float, foucault: bool) -> np.ndarray:
    """Textbook north-pointing static-base error equations (δv_E, δv_N, δφ, δλ, α_E, α_N,
    α_U); ``foucault=False`` drops the two ±2Ω sin φ δv terms as the report does."""
    s, c = U * np.sin(latitude), U * np.cos(latitude)
    k = 2 * s if foucault else 0.0
    return np.array([
        [0, k, 0, 0, 0, -G0, 0],
        [-k, 0, 0, 0, G0, 0, 0],
        [0, 1 / R0, 0, 0, 0, 0, 0],
        [1 / (R0 * np.cos(latitude)), 0, 0, 0, 0, 0, 0],
        [0, -1 / R0, 0, 0, 0, s, -c],
        [1 / R0, 0, -s, 0, -s, 0, 0],
        [np.tan(latitude) / R0, 0, c, 0, c, 0, 0]])


def _expm_curves(latitude: float, source: str, magnitude: float, times, foucault: bool):
    """Error states over ``times`` for one source alone, by scipy's expm; shape (7, T).
    (The sign of an input does not matter to the comparisons below.)"""
    from scipy.linalg import expm

    kind, row = _ROWS[source]
    m = np.zeros((8, 8))
    m[:7, :7] = _static_base_matrix(latitude, foucault)
    start = np.zeros(8)
    start[7] = 1.0
    if kind == "input":
        m[row, 7] = magnitude
    else:
        start[row] = magnitude
    return np.stack([(expm(m * t) @ start)[:7] for t in times], axis=1)


@functools.cache
def _two_hours(latitude_deg: float):
    return run(Experiment(latitude=float(np.radians(latitude_deg)), duration=7200.0))


def test_end_of_run_table_is_labelled_with_the_duration(tmp_path, capsys, monkeypatch):
    """`--hours 2 --out D`: D/summary.md labels the end values 2 h, and they are the
    values at 2 h (the last sample, t = 7200 s). (The plots are not drawn: this test
    reads the table only; the README's `propagation --hours 24 --out` and the plot tests
    above draw them.)"""
    from ins_errors.cli import main
    from ins_errors.studies import propagation

    drawn = []
    monkeypatch.setattr(propagation, "plot", lambda result, folder, sources=None: (
        drawn.append(sources) or []))
    assert main(["propagation", "--hours", "2", "--out", str(tmp_path / "D")]) == 0
    assert drawn == [None]  # every source's plot asked for
    capsys.readouterr()
    text = (tmp_path / "D" / "summary.md").read_text()
    assert "Values at the end of the run, 2 h (direct numeric):" in text
    assert "24-hour" not in text
    result = _two_hours(39.0)
    assert result.times[-1] == 7200.0
    table = text.split("Values at the end of the run, 2 h (direct numeric):")[1]
    row = next(line for line in table.splitlines() if line.startswith("| `gyro_drift_up`"))
    dlon = float(row.split("|")[5])  # dN, arcmin
    assert dlon == pytest.approx(np.degrees(result.curve("gyro_drift_up").direct[
        _q("delta_longitude"), -1]) * 60, rel=1e-3)


@pytest.mark.parametrize("latitude_deg", [0.0, 39.0, -45.0])
def test_reduced_vs_full_against_matrix_exponentials(latitude_deg):
    """Per quantity, |reduced − full| / max|full| against the same figure from expm of the
    two F matrices; quantities the reduced model leaves at zero are named, not counted.
    At the equator the two matrices are one: every figure is 0, nothing is missing."""
    result = _two_hours(latitude_deg)
    latitude = float(np.radians(latitude_deg))
    weight = np.array([1 / np.sqrt(G0 * R0)] * 2 + [1.0] * 5)
    with one_blas_thread_for_references():
        references = [[_expm_curves(latitude, c.source, c.magnitude, result.times, foucault)
                       for foucault in (True, False)] for c in result.curves]
    for c, (full, reduced) in zip(result.curves, references, strict=True):
        size_f, size_r = np.max(np.abs(full), axis=1), np.max(np.abs(reduced), axis=1)
        gap = np.max(np.abs(reduced - full), axis=1)
        source_size = np.max(np.concatenate([size_f, size_r]) * np.tile(weight, 2))
        present_f = size_f * weight > 1e-9 * source_size  # a looser floor of our own
        present_r = size_r * weight > 1e-9 * source_size
        names = [q[1] for q in QUANTITIES]
        got = c.reduced_vs_full()
        assert got.lacking == tuple(n for n, f, r in zip(names, present_f, present_r,
                                                         strict=True) if f and not r)
        assert got.extra == ()
        shared = present_f & present_r
        assert np.array_equal(np.isfinite(got.relative), shared), c.source
        if latitude_deg == 0.0:
            assert np.all(gap == 0.0)  # the two matrices are equal
            assert np.all(got.relative[shared] == 0.0), c.source
            assert got.worst() == 0.0 and got.worst_quantity() is None
            continue
        expected = gap[shared] / size_f[shared]
        assert got.relative[shared] == pytest.approx(expected, rel=1e-5, abs=1e-9), c.source
    text = result.summary_markdown()
    if latitude_deg == 0.0:
        assert "1.00e+00" not in text and "inf h" not in text
        assert text.count("| 0 (same to rounding) | – |") == 12
        assert "No Foucault rotation at 0°" in text and "Schuler split vanishes" in text
        assert "Foucault period (" not in text
    else:
        theta = np.degrees(U * abs(np.sin(latitude)) * 7200.0)
        assert f"turned by θ = {theta:.3g}°" in text
        assert "shorter than half a Foucault period" in text
        assert "reaches about 2" not in text
        row = next(line for line in text.splitlines()
                   if line.startswith("| `accel_bias_east` |"))
        assert row.endswith("| dVy, dL, Qx |")


def test_reduced_vs_full_reaches_two_after_half_a_foucault_period(result):
    """24 h at 39° (> half the 38-h Foucault period): the swing of the full model is in
    opposite phase to the reduced one's, the along-swing quantity differs by about 2."""
    c = result.curve("accel_bias_east")
    got = c.reduced_vs_full()
    assert got.relative[_q("delta_v_E")] == pytest.approx(2.0, abs=0.05)
    assert got.lacking == ("dVy", "dL", "Qx")
    assert "reaches about 2 on this run" in result.summary_markdown()


def _split_periods(latitude: float, g: float, radius: float) -> tuple[float, float]:
    """Longer and shorter Foucault-split Schuler periods, s, from g and R."""
    w_u = U * abs(np.sin(latitude))
    w_bar = np.sqrt(g / radius + w_u**2)
    return 2 * np.pi / (w_bar - w_u), 2 * np.pi / (w_bar + w_u)


def test_foucault_split_labels_do_not_swap_south_of_the_equator(capsys):
    """'Schuler − Foucault' is the longer period at +45° and at −45° (same values), in
    the table, the JSON keys and the orthodromic day run."""
    import json

    from ins_errors.cli import main
    from ins_errors.studies.propagation import orthodromic_day

    longer, shorter = _split_periods(np.radians(45.0), G0, R0)
    assert longer / 60 == pytest.approx(87.99, abs=0.01)
    for latitude in ("45deg", "-45deg"):
        assert main(["propagation", "--hours", "0.5", f"--latitude={latitude}",
                     "--json"]) == 0
        periods = json.loads(capsys.readouterr().out)["periods_s"]["full"]
        assert periods["Schuler − Foucault"] == pytest.approx(longer, rel=1e-9), latitude
        assert periods["Schuler + Foucault"] == pytest.approx(shorter, rel=1e-9), latitude
        assert main(["propagation", "--hours", "0.5", f"--latitude={latitude}"]) == 0
        text = capsys.readouterr().out
        assert f"| full | Schuler − Foucault | {longer / 60:.2f} |" in text, latitude
        assert f"| full | Schuler + Foucault | {shorter / 60:.2f} |" in text, latitude
    south = orthodromic_day(latitude=float(np.radians(-45.0)), duration=600.0)
    assert south.periods["Schuler − Foucault"] > south.periods["Schuler + Foucault"]
    assert (south.periods["Schuler − Foucault"], south.periods["Schuler + Foucault"]) == \
        pytest.approx(_split_periods(np.radians(-45.0), south.gravity, south.radius),
                      rel=1e-9)


def test_zero_magnitude_is_refused_in_one_line(capsys):
    """A zero source has no ratio to study: one line, exit 2, no warning, no nan rows."""
    from ins_errors.cli import main

    assert main(["propagation", "--hours", "0.5", "--drift", "0deg/h"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1 and "--drift is zero" in captured.err
    assert "Warning" not in captured.err and "nan" not in captured.err
    assert main(["propagation", "--hours", "0.5", "--level", "0 arcsec"]) == 2
    assert "--level is zero" in capsys.readouterr().err
    with pytest.raises(DomainError, match="gyro_drift is zero"):
        run(Experiment(gyro_drift=0.0, duration=600.0))


def test_orthodromic_output_states_the_gravity_and_radius_of_its_periods(capsys):
    """The orthodromic static base uses a_ζ = normal gravity by the WGS-84 Somigliana
    formula on the model's sphere (e² = 0), 9.7878 m/s² at 39°, and the Krasovsky a:
    the output says so, and its periods follow by hand from the stated values."""
    import json
    import re

    from ins_errors.cli import main

    latitude = np.radians(39.0)
    gamma = 9.7803253359 * (1 + 0.00193185265241 * np.sin(latitude) ** 2)  # WGS-84, e²=0
    assert main(["propagation", "--orthodromic", "--latitude", "39deg", "--hours", "0.5"]) == 0
    text = capsys.readouterr().out
    stated = re.search(r"from a_ζ = ([0-9.]+) m/s², R = ([0-9.]+) m and Ω = [0-9.e-]+ "
                       r"rad/s\. a_ζ is ([^;]*); R is ([^.]*)\.", text)
    assert stated, text[:600]
    g, radius = float(stated.group(1)), float(stated.group(2))
    assert g == pytest.approx(gamma, rel=1e-6) and radius == 6_378_245.0
    assert "Somigliana" in stated.group(3) and "e² = 0" in stated.group(3)
    assert "Krasovsky" in stated.group(4)
    longer, shorter = _split_periods(latitude, g, radius)
    assert f"Schuler − Foucault {longer / 60:.2f} min" in text
    assert f"Schuler + Foucault {shorter / 60:.2f} min" in text
    assert f"{longer / 60:.2f}" == "87.72"  # not 87.64: that is g = 9.80665
    assert f"{_split_periods(latitude, G0, radius)[0] / 60:.2f}" == "87.64"
    assert "over 0.5 h" in text and "over a day" not in text
    assert main(["propagation", "--orthodromic", "--latitude", "39deg", "--hours", "0.5",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["gravity_m_s2"] == pytest.approx(gamma, rel=1e-12)
    assert data["radius_m"] == 6_378_245.0
