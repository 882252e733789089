"""The report folder: a self-contained HTML page and the curves as CSV and MATLAB files.

The curves read back from curves.csv and curves.mat must be the very curves of the
comparison (to the digits written), and the page must need nothing from the network.
"""

from __future__ import annotations

import csv
from contextlib import contextmanager
from dataclasses import replace

import numpy as np
import pytest

from ins_errors.report import write_report
from ins_errors.scenario import load_scenario, run_scenario
from tests.helpers import assert_pictures_alike

SCENARIO = """title = "two drifts, 20 min"
model = "orthodromic"
[run]
duration = "20 min"
step = "1 s"
record = "60 s"
[[case]]
gyro_drift_x = "0.01 deg/h"
[[case]]
accel_bias_y = "50 ug"
[outputs]
quantities = ["alpha_y", "delta_v_N"]   # in the tables and plots; the curve files hold all
"""


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    scenario_file = folder / "s.toml"
    scenario_file.write_text(SCENARIO, encoding="utf-8")
    result = run_scenario(load_scenario(scenario_file))
    write_report(result, folder / "out")
    return result, folder / "out"


def test_html_is_self_contained(report):
    _, folder = report
    page = (folder / "report.html").read_text(encoding="utf-8")
    assert "<script" not in page and "https://" not in page  # no CDN, no MathJax
    assert page.count("<math") > 20 and "$$" not in page  # every formula as MathML
    assert page.count("data:image/png;base64,") == 2  # both plots embedded



def test_report_md_prose_has_no_tex_left(report):
    """The model's modelling choices the report shows were written with TeX exponents
    (``(1 − e² sin²φ)^{3/2}``), shown raw by Markdown: outside code spans and $...$
    formulas no caret or braced subscript is left."""
    import re

    from tests.test_notes_markdown import _prose

    _, folder = report
    text = (folder / "report.md").read_text(encoding="utf-8")
    assert "R_N = (a + h)(1 − e²)/√(1 − e² sin²φ)³" in text  # the model's notes are in it
    leftovers = re.findall(r".{0,20}(?:\^|_\{).{0,12}", _prose(text))
    assert not leftovers, leftovers


def test_kept_mathml_is_the_converters_text_and_keeps_display_apart():
    """The MathML of a formula is kept per process: the text the converter gives for the
    same LaTeX and display mode, and a display formula is not an inline one."""
    from ins_errors import report

    formulas = [r"\dot{\alpha}_x = -\omega_\eta + \varepsilon_x", r"\frac{b}{g}", r"\nosuchmacro x"]
    for latex in formulas:
        for display in (True, False):
            first = report._mathml(latex, display)
            assert report._mathml(latex, display) == first
            assert first == report._mathml.__wrapped__(latex, display)
    assert report._mathml(r"\frac{b}{g}", True) != report._mathml(r"\frac{b}{g}", False)

def test_curves_csv_holds_every_curve_of_every_case(report):
    result, folder = report
    with open(folder / "curves.csv", encoding="utf-8", newline="") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    first = result.comparisons[0]
    assert header[:2] == ["case", "t [s]"]
    assert "delta_latitude.direct [rad]" in header and "alpha_x.refined [rad]" in header
    assert body.shape[0] == sum(len(c.times) for c in result.comparisons)
    for k, comparison in enumerate(result.comparisons, 1):
        mine = body[body[:, 0] == k]
        np.testing.assert_array_equal(mine[:, 1], comparison.times)
        column = header.index("delta_v_N.linear [m/s]")
        np.testing.assert_array_equal(mine[:, column], comparison.linear["delta_v_N"])
    assert np.abs(first.direct["alpha_y"]).max() > 0  # a drift about x tilts about y
    # written row by row to the file, the bytes of the text curves_csv returns
    from ins_errors.export import curves_csv

    assert (folder / "curves.csv").read_bytes() == curves_csv(result.comparisons).encode()


def test_curves_mat_reads_back(report):
    from scipy.io import loadmat

    result, folder = report
    data = loadmat(folder / "curves.mat", squeeze_me=True, struct_as_record=False)
    np.testing.assert_array_equal(data["t_s"], result.comparisons[0].times)
    case = data["case_2"]
    np.testing.assert_array_equal(case.direct.delta_v_E, result.comparisons[1].direct["delta_v_E"])
    np.testing.assert_array_equal(case.refined.alpha_x, result.comparisons[1].refined["alpha_x"])
    assert data["units"].delta_v_E == "m/s"
    assert list(data["labels"]) == [c.label for c in result.comparisons]


def test_files_get_the_usual_permissions(report):
    """Written through a private temporary file, yet with the mode open() would give."""
    import os

    _, folder = report
    mask = os.umask(0o022)
    os.umask(mask)
    for name in ("report.md", "curves.mat", "case_1.png"):
        assert (folder / name).stat().st_mode & 0o777 == 0o666 & ~mask, name


def test_report_interrupted_while_curves_mat_is_written_is_rewritten_without_force(
        report, tmp_path, monkeypatch):
    """Ctrl-C while curves.mat is written: the run is taken back (the folder it made is
    gone, no half report is left), the same report folder is written again without
    --force, and holds exactly the new report's files afterwards."""
    from ins_errors import export
    from ins_errors.output import MANIFEST

    result, _ = report
    out = tmp_path / "out"

    def interrupted(comparisons, path):
        raise KeyboardInterrupt

    monkeypatch.setattr(export, "save_curves_mat", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_report(result, out)
    assert not out.exists()
    monkeypatch.undo()
    one_case = replace(result, comparisons=result.comparisons[:1])
    write_report(one_case, out)  # not refused; the second case's plot is removed
    assert sorted(p.name for p in out.iterdir()) == sorted([
        MANIFEST, "case_1.png", "curves.csv", "curves.mat", "report.html", "report.md",
        "results.json"])


def test_case_plots_equal_fresh_plain_matplotlib_figures(report, tmp_path, monkeypatch):
    """The report draws its cases in one reused figure (curves, limits, title replaced)
    whose panels share their time range by construction (not matplotlib's sharex, which
    made every panel visit its siblings on each update), whose inner rows' hidden time
    labels are neither formatted nor measured and whose column titles keep a fixed place.
    Each file must be byte for byte the figure drawn afresh for that case alone with
    matplotlib's own ``sharex=True``, formatting, label placement and title search: also
    when one curve stops early (NaN) and the others set the range, and across a change
    of layout (a case without refined curves needs other panels), and in a later call
    that takes the figure an earlier call kept. Each case is drawn once each way: the
    reused figure is checked against all shortcuts undone at once."""
    import matplotlib.pyplot as plt

    from ins_errors import figure_layout
    from ins_errors.numeric import plots

    result, _ = report
    first, second = result.comparisons
    cut = {q: v.copy() for q, v in first.direct.items()}
    cut["alpha_y"][len(first.times) // 2:] = np.nan
    # the second refills the first's figure; the third needs a new layout
    cases = [second, replace(first, direct=cut), replace(first, refined={})]
    shown = ["alpha_y", "delta_v_N"]
    titles = ["second", "", "no refined curves"]
    ours = plots.plot_comparisons(cases, [tmp_path / f"ours{k}.png" for k in range(3)],
                                  quantities=shown, titles=titles)
    assert ours[0].read_bytes() != ours[1].read_bytes()
    kept = list(plots._SPARE_FIGURES.figures)
    again = plots.plot_comparisons([second], [tmp_path / "again.png"], quantities=shown,
                                   titles=titles[:1])[0]
    assert plots._SPARE_FIGURES.figures[-1] in kept  # the first call's figure, redrawn
    assert again.read_bytes() == ours[0].read_bytes()
    fresh = plots._SpareFigures()
    fresh.size = 0  # every plain figure built afresh, none kept
    monkeypatch.setattr(plots, "_SPARE_FIGURES", fresh)
    subplots = plt.subplots
    monkeypatch.setattr(plt, "subplots", lambda *a, **k: subplots(*a, **k, sharex=True))
    monkeypatch.setattr(figure_layout, "_skip_hidden_label_layout", lambda axis: None)
    monkeypatch.setattr(plots, "fixed_title", lambda ax, text, **o: ax.set_title(text, **o))
    for k, (case, title) in enumerate(zip(cases, titles, strict=True)):
        plain = plots.plot_comparison(case, tmp_path / f"plain{k}.png", quantities=shown,
                                      title=title)
        assert ours[k].read_bytes() == plain.read_bytes(), k


def test_a_long_title_is_wrapped_within_the_comparison_figure(report):
    # the standard manoeuvre's description ran off both edges of the figure
    from ins_errors.numeric import plots
    from ins_errors.numeric.motion_spec import STANDARD_MANOEUVRE

    result, _ = report
    comparison = result.comparisons[0]
    figure = plots._ComparisonFigure(comparison, ["alpha_y", "delta_v_N"])
    title = f"{comparison.label}\nmodel: {STANDARD_MANOEUVRE} from φ=50°, λ=30°; 2 h, τ = 1 s"
    figure.show(comparison, title)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(figure.fig)  # (a kept figure has no canvas until it is saved)
    with _as_saved(figure.fig, plots.DPI) as fig:
        assert fig._suptitle.get_text().count("\n") >= 2  # the long line was wrapped
        assert _sticking_out(fig) == (False, False, False, False)


def _sticking_out(fig) -> tuple[bool, bool, bool, bool]:
    """Whether anything drawn passes the left, bottom, right or top edge of the figure."""
    box = fig.get_tightbbox(fig.canvas.get_renderer())  # inches
    width, height = fig.get_size_inches()
    return bool(box.x0 < 0), bool(box.y0 < 0), bool(box.x1 > width), bool(box.y1 > height)


@contextmanager
def _as_saved(fig, dpi: float):
    """The figure at the resolution and drawing settings ``save_figure`` gives its file,
    for measuring its layout instead of writing it (the figure is closed afterwards)."""
    import matplotlib
    import matplotlib.pyplot as plt

    from ins_errors.output import DRAWING_RC

    fig.set_dpi(dpi)
    try:
        with matplotlib.rc_context(DRAWING_RC):
            yield fig
    finally:
        plt.close(fig)


def test_study_figures_fit_their_fixed_margins(tmp_path, monkeypatch):
    """The study and validity figures use fixed margins (no tight_layout): with the
    widest tick labels plain formatting gives (-0.00025 and the like; 12500 km; 1e-12 as
    a power of ten), nothing may stick out of the figure, and the inner panels must not
    label the time axis."""
    from types import SimpleNamespace

    from ins_errors.studies import methodological, spheroid_error

    seen = []

    def check(fig, path, dpi):  # (the layout as saved; no file is needed)
        with _as_saved(fig, dpi):
            seen.append((_sticking_out(fig), [bool(ax.xaxis.get_ticklabels())  # (visible)
                                              for ax in fig.axes if ax.get_visible()]))
        return path

    for module in (methodological, spheroid_error):
        monkeypatch.setattr(module, "save_figure", check)
    times = np.linspace(0.0, 24 * 3600.0, 49)
    wave = np.sin(times / 5000.0)[:, None]
    names = ["delta_latitude", "delta_longitude", "delta_v_N", "delta_v_E", "alpha_x",
             "alpha_y", "alpha_z", "delta_heading"]
    curves = {n: -2.5e-4 * wave / 6371.0 for n in names}  # -0.00025 km and the like
    study = SimpleNamespace(study=SimpleNamespace(name="wide", description="labels", task=3),
                            motion="a static base", times=times, direct=curves,
                            linear=curves, latitude=np.zeros(times.size))
    methodological.plot(study, tmp_path / "study.png")
    grow = np.linspace(0.0, 1.0, times.size)[:, None] * np.ones((1, 8))
    errors = np.stack([grow, grow]) * 12500e3 / 6378245.0  # 12500 km and the like
    angles = [30, 90, 150, 225]  # as the survey flies them, from two latitudes
    flights = SimpleNamespace(times=times, start=np.radians([[0] * 4 + [60] * 4, [0] * 8,
                                                             angles * 2]),
                              direct=errors, printed=errors * 0.5, completed=errors,
                              km=lambda e: np.stack([e[0], e[1] * 0.0]) * 6378.245)
    spheroid_error.plot(flights, tmp_path / "flights.png")
    for few in ([30, 90], [90]):  # narrow figures: the title and legend must still fit
        spheroid_error.plot(SimpleNamespace(
            times=times, start=np.radians([[0] * len(few) + [60] * len(few),
                                           [0] * 2 * len(few), few * 2]),
            direct=errors[:, :, :2 * len(few)], printed=errors[:, :, :2 * len(few)] * 0.5,
            completed=errors[:, :, :2 * len(few)], km=flights.km),
            tmp_path / f"flights{len(few)}.png")
    assert seen == [((False,) * 4, [False, False, False, True]),
                    ((False,) * 4, [False] * 4 + [True] * 4),
                    ((False,) * 4, [False, False, True, True]),
                    ((False,) * 4, [False, True])]
    from ins_errors.analysis import validity_plot
    from ins_errors.analysis.validity import SourceValidity

    monkeypatch.setattr(validity_plot, "save_figure", check)
    magnitudes = list(np.logspace(-3, 3, 7))
    sweep = SourceValidity("gyro_drift_x", "great-circle", "rad/s", "deg/h",
                           [m * 4.8e-9 for m in magnitudes], "alpha_z",
                           linear_ratio=list(np.logspace(-5, 0, 7)),
                           refined_ratio=list(np.logspace(-12, -2, 7)), linear_slope=1.0,
                           refined_slope=2.0, magnitude_1pct=4.8e-9)
    validity_plot.plot_validity([sweep], tmp_path / "validity.png", "a title")
    assert seen[-1] == ((False,) * 4, [True])


def test_spheroid_figure_defines_the_names_of_its_panel_titles(tmp_path, monkeypatch):
    """The panels are titled "φ0 = 20°, N0 = 90°": the figure itself says what φ0 and
    N0 are (N0 was defined nowhere on it)."""
    from types import SimpleNamespace

    from ins_errors.studies import spheroid_error

    texts = []

    def keep(fig, path, dpi):
        texts.append([t.get_text() for t in fig.texts]
                     + [ax.get_title() for ax in fig.axes if ax.get_visible()])
        return path

    monkeypatch.setattr(spheroid_error, "save_figure", keep)
    times = np.linspace(0.0, 3600.0, 13)
    errors = np.stack([np.ones((13, 2)), np.ones((13, 2))]) * 1e-4
    flights = SimpleNamespace(times=times, start=np.radians([[20, 20], [0, 0], [30, 90]]),
                              direct=errors, printed=errors, completed=errors,
                              km=lambda e: e * 6378.245)
    spheroid_error.plot(flights, tmp_path / "f.png")
    [shown] = texts
    assert "φ0 = 20°, N0 = 90°" in shown
    words = " ".join(t.replace("\n", " ") for t in shown)
    assert "N0: orthodrome angle at the start" in words
    assert "φ0: geocentric start latitude" in words


def _legends_on_panels(fig) -> list[str]:
    """The legends that lie on a panel (where they hide curves), by their first entry;
    an empty list also when there is no legend is refused by the callers."""
    renderer = fig.canvas.get_renderer()
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend()] + fig.legends
    assert legends
    width, height = fig.get_size_inches() * fig.dpi
    found = []
    for legend in legends:
        box = legend.get_window_extent(renderer)
        assert box.x0 >= 0 and box.y0 >= 0 and box.x1 <= width and box.y1 <= height
        if any(box.overlaps(ax.bbox) for ax in fig.axes if ax.get_visible()):
            found.append(legend.get_texts()[0].get_text())
    return found


def test_legends_of_the_report_and_propagation_figures_hide_no_curve(report, tmp_path,
                                                                      monkeypatch):
    """The legends sat inside the top panels, over dense Schuler oscillations: they
    are under the panels now, clear of every panel, inside the figure."""
    from ins_errors.numeric import plots
    from ins_errors.output import OutputFolder
    from ins_errors.studies import propagation

    seen = []

    def check(fig, path, dpi, **options):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)  # (a kept figure has no canvas until it is saved)
        with _as_saved(fig, dpi):
            fig.draw_without_rendering()
            seen.append(_legends_on_panels(fig))
            assert _sticking_out(fig) == (False, False, False, False)
        return path

    monkeypatch.setattr(plots, "save_figure", check)
    result, _ = report
    for case in (result.comparisons[0], replace(result.comparisons[0], refined={})):
        plots._SPARE_FIGURES.figures.clear()
        plots.plot_comparison(case, tmp_path / "case.png", quantities=["alpha_y"])
    experiment = propagation.run(propagation.Experiment(duration=2 * 3600.0))
    monkeypatch.setattr(OutputFolder, "save_figure",
                        lambda self, fig, name, dpi, close: check(fig, name, dpi))
    propagation.plot(experiment, OutputFolder(tmp_path / "p"), ["gyro_drift_east"])
    assert seen == [[], [], []]


def _overlapping(fig) -> list[tuple[str, str]]:
    """Texts of a drawn figure that overlap another text, or a panel not their own.

    Texts: every visible tick label within its axis' limits, axis labels, offset texts,
    titles, texts on the panels and on the figure (suptitle included), and the figure's
    legends. Returned as pairs of the texts' strings (a panel as "panel").
    """
    renderer = fig.canvas.get_renderer()
    texts, panels = [], []
    for ax in (a for a in fig.axes if a.get_visible()):
        panels.append((ax, ax.bbox))
        owned = [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label,
                 ax.xaxis.offsetText, ax.yaxis.offsetText, *ax.texts]
        for axis in (ax.xaxis, ax.yaxis):
            low, high = sorted(axis.get_view_interval())
            slack = (high - low) * 1e-9
            locs = axis.get_majorticklocs()
            for tick, loc in zip(axis.get_major_ticks(len(locs)), locs, strict=True):
                if low - slack <= loc <= high + slack:
                    owned += [tick.label1, tick.label2]
        texts += [(ax, t.get_text(), t.get_window_extent(renderer)) for t in owned
                  if t.get_visible() and t.get_text().strip()]
    texts += [(None, t.get_text(), t.get_window_extent(renderer)) for t in fig.texts
              if t.get_visible() and t.get_text().strip()]
    texts += [(None, "legend", legend.get_window_extent(renderer)) for legend in fig.legends]

    def meet(a, b) -> bool:  # by more than a pixel each way
        return min(a.x1, b.x1) - max(a.x0, b.x0) > 1 and min(a.y1, b.y1) - max(a.y0, b.y0) > 1

    found = [(s, z) for k, (_, s, a) in enumerate(texts) for _, z, b in texts[k + 1:]
             if meet(a, b)]
    found += [(s, "panel") for owner, s, a in texts for ax, b in panels
              if ax is not owner and meet(a, b)]
    return found


def test_budget_and_sweep_figures_fit_their_fixed_margins(tmp_path, monkeypatch):
    """The budget figures and the sweep figure use fixed margins measured from their
    labels (no tight_layout): with the longest labels the product makes (the longest
    source names and magnitudes, many sources, long titles, units with superscripts,
    wide tick labels and offsets) and with short ones, nothing may stick out of the
    figure and no text may overlap another or lie on another panel."""
    from types import SimpleNamespace

    from ins_errors import output
    from ins_errors.analysis import budget_report, sweep_report

    seen = []

    def check(fig, path, dpi):  # (the layout as saved; no file is needed)
        with _as_saved(fig, dpi):
            fig.draw_without_rendering()
            seen.append((path.name, _sticking_out(fig), _overlapping(fig)))
        return path

    monkeypatch.setattr(output, "save_figure", check)
    monkeypatch.setattr(budget_report, "save_figure", check)
    names = ["velocity_integrator_gain_error_eta", "position_integrator_gain_error_Phi",
             "initial_velocity_error_north", "correction_gain_error_z", "gyro_drift_x"]
    items = ["position_error", "ground_speed_error", "vertical_error", "heading_drift"]
    long_title = ("product 802m with every source of the strapdown model, a title written "
                  "out at length by its author (lab manual 000, appendix, table 3) ") * 2
    long_motion = ("great circle from φ=-45.25°, λ=-170.5°, heading χ=359.75°, h=12500 m, "
                   "at 250 m/s, turning at the waypoints of the route file") * 2

    def budget(count, free, title, motion, display, when):
        sources = [{"name": f"{names[j % len(names)]}_{j}"[:36], "display": display,
                    "binding_item": items[j % 4], "binding_time_h": when,
                    "share_at_binding": 0.02 + 0.3 * (j == 1), "fixed": False}
                   for j in range(count)]
        sources += [{"name": n, "binding_item": None, "fixed": False} for n in free]
        # sources the spec fixes are drawn too, first, labelled "(fixed)"
        sources += [{"name": f"{names[j % len(names)]}_f{j}"[:36], "display": display,
                     "binding_item": None, "fixed": True,
                     "largest_share": {n: 0.05 * (i + 1) for i, n in enumerate(items)}}
                    for j in range(count // 20)]
        for source in sources:  # a source's row label is its name (one kind of part)
            source["label"] = source["name"]
        rows = [{"item": n, "ratio": 0.1 + 0.3 * i, "time_h": when,
                 "display": f"{display} of {display}"} for i, n in enumerate(items)]
        monkeypatch.setattr(budget_report, "report", lambda allocation: {
            "sources": sources, "rows": rows, "motion": motion})
        spec = SimpleNamespace(title=title, sigma_level=2.0,
                               items=[SimpleNamespace(name=n) for n in items])
        return SimpleNamespace(budget=SimpleNamespace(spec=spec))

    budget_report.plot(budget(60, names * 8, long_title, long_motion, "-1.235e-05 deg/h",
                              23.99), tmp_path / "budget_long.png")
    budget_report.plot(budget(1, [], "802m", "static", "1 ug", 1.0),
                       tmp_path / "budget_short.png")
    for times, quantities in (([1.0, 2.0, 24.0], 12), ([1.0], 3)):
        sources = [f"{names[j % len(names)]}_{j}" for j in range(30)]
        std = np.random.default_rng(1).uniform(0.5, 1, (len(times), quantities, 31))
        std[..., -1] = 12345.6789
        budget_report.plot_outputs({
            "std": std[..., :-1], "total": std[..., -1], "times_h": times, "sources": sources,
            "quantities": ["delta_r_E", "delta_v_N", "alpha_z"] * (quantities // 3),
            "units": ["m", "m/s²", "deg/h"] * (quantities // 3)},
            tmp_path / f"outputs_{len(times)}.png",
            title=f"Contributions to the navigation errors: {long_title}\n{long_motion}\n"
                  "1σ (the spec's items are 2σ), at the allocated magnitudes")

    wide = "velocity_integrator_gain_error_eta"

    class Dataset(dict):
        attrs: dict

    dataset = Dataset({
        wide: SimpleNamespace(attrs={"units": "m/s²"}, values=np.repeat(
            np.linspace(-123456.789, 123456.789, 40), 40)),
        "heading": SimpleNamespace(attrs={"units": "deg"}, values=np.tile(
            np.linspace(-179.5, 179.5, 40), 40)),
        "latitude": SimpleNamespace(attrs={"units": "deg"}, values=np.zeros(1600))})
    dataset.attrs = {"title": long_title, "swept": f'["{wide}", "heading", "latitude"]'}
    label = f"max |{wide}| [m/s²]"
    for values in (np.linspace(1e-9, 3e-9, 1600), np.linspace(-123456.7, 1e6, 1600)):
        monkeypatch.setattr(sweep_report, "figure_values",
                            lambda data, figure, v=values: (v, label))
        sweep_report.plot(dataset, "max_direct:x", [wide], tmp_path / "sweep_line.png")
        sweep_report.plot(dataset, "max_direct:x", [wide, "heading"], tmp_path / "sweep_map.png")
    assert [s for s in seen if s[1:] != ((False,) * 4, [])] == []
    assert len(seen) == 8


def _day_of_seconds():
    """A day recorded every second: a random walk with two one-sample spikes."""
    rng = np.random.default_rng(7)
    t = np.arange(86_401.0)
    y = np.cumsum(rng.normal(size=t.size))
    y[5_000] += 900.0
    y[70_001] -= 1200.0
    return t, y


def test_column_envelope_keeps_every_columns_extremes():
    """Per column of the drawing, the reduced curve has the very smallest and largest
    sample of the full curve (no peak is lost), keeps the first and last sample, and
    keeps whole a curve with NaN gaps or one already short."""
    from ins_errors.numeric.envelope import column_envelopes

    t, y = _day_of_seconds()
    columns = 890
    (tr, yr), (tn, yn) = column_envelopes(t, [y, np.where(t > 80_000, np.nan, y)],
                                          columns)
    assert tr.size <= 4 * columns and tr.size < t.size / 20
    kept = np.searchsorted(t, tr)
    np.testing.assert_array_equal(t[kept], tr)  # samples of the curve, in order
    np.testing.assert_array_equal(y[kept], yr)
    assert (tr[0], tr[-1]) == (t[0], t[-1])
    column = np.minimum((t * columns / t[-1]).astype(int), columns - 1)
    mine = column[kept]
    for k in range(columns):
        assert yr[mine == k].max() == y[column == k].max(), k
        assert yr[mine == k].min() == y[column == k].min(), k
    assert yr.max() == y[5_000] and yr.min() == y[70_001]  # the spikes
    assert tn is t and yn.size == t.size  # NaN gaps: drawn as they are
    short = column_envelopes(t[:3000], [y[:3000]], columns)[0]
    assert short[0].size == 3000


def test_long_curve_drawn_from_its_envelope_covers_the_same_pixels(tmp_path):
    """A day at 1 s drawn through its envelope and through every sample: the same
    picture (solid lines; antialiased edges may differ by a few levels)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    from ins_errors.numeric.envelope import column_envelopes
    from ins_errors.output import save_figure

    t, y = _day_of_seconds()
    pictures = []
    for columns in (0, 2 * 400):  # 0: every sample
        fig, ax = plt.subplots(figsize=(5, 2.5))
        fig.subplots_adjust(left=0.1, right=0.9)  # 4 inches at 100 dpi: 400 columns
        ax.plot(*column_envelopes(t / 3600, [y], columns)[0], lw=1.0)
        ax.set_xlim(0, 24)
        path = save_figure(fig, tmp_path / f"{columns}.png", dpi=100)
        with Image.open(path) as image:
            pictures.append(np.asarray(image.convert("L"), dtype=int))
    full, reduced = pictures
    assert full.shape == reduced.shape
    differ = np.abs(full - reduced)
    assert (differ > 64).sum() <= 0.001 * full.size, (differ > 64).sum()


def test_long_comparison_figure_covers_the_pixels_of_every_sample(report, tmp_path,
                                                                  monkeypatch):
    """A comparison recorded every second for six hours (21 601 samples: smooth curves
    with a ripple and one-sample spikes) draws its solid curves (direct, residuals)
    through their column envelope and its dashed and dotted ones (linear, refined)
    whole, whose dash pattern a reduction would move: the picture of every sample
    drawn (antialiased edges may differ by a few levels)."""
    from ins_errors.numeric import plots

    result, _ = report
    first = result.comparisons[0]
    times = np.arange(21_601.0)
    ripple = np.sin(2 * np.pi * times / 1500.0)

    def fine(curves, factor):  # the record at 1 s, with a ripple and two spikes on top
        out = {}
        for q, values in curves.items():
            v = np.interp(times / 18.0, first.times, values)  # the 20 min over 6 h
            v = v + 0.05 * np.abs(v).max() * ripple * factor
            v[5_000] *= 1.5
            v[17_001] *= -1.0
            out[q] = v
        return out

    long = replace(first, times=times, direct=fine(first.direct, 1.0),
                   linear=fine(first.linear, 0.9), refined=fine(first.refined, 0.95))
    shown = ["alpha_y", "delta_v_N"]
    reduced = plots.plot_comparison(long, tmp_path / "reduced.png", quantities=shown)
    monkeypatch.setattr(plots, "column_envelopes",
                        lambda x, curves, columns: [(x, y) for y in curves])
    full = plots.plot_comparison(long, tmp_path / "full.png", quantities=shown)
    # (none here; the dashed and dotted curves through the envelope too: 59)
    assert_pictures_alike(reduced, full)


def test_save_figure_after_tight_layout_writes_the_bytes_of_a_plain_savefig(tmp_path):
    """``save_figure`` skips the extra layout pass a ``tight_layout()`` placeholder
    causes: the file must still be the one matplotlib's own ``savefig`` writes (with
    the same settings), and the figure keeps its placeholder (a later colorbar still
    sees the tight layout's rules)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    from ins_errors.output import DRAWING_RC, PNG_ZLIB_RLE, save_figure

    fig, axes = plt.subplots(2, 1, figsize=(4, 4))
    axes[0].plot([0, 1, 2], [3e-7, 1e-6, -2e-7])
    axes[1].plot([0, 1, 2], [1e4, 3e5, 2e4])
    axes[1].set_xlabel("time, h")
    fig.suptitle("a title")
    fig.tight_layout()
    engine = fig.get_layout_engine()
    assert isinstance(engine, PlaceHolderLayoutEngine)
    plain = tmp_path / "plain.png"
    with matplotlib.rc_context(DRAWING_RC):
        fig.savefig(plain, dpi=60, pil_kwargs={"compress_type": PNG_ZLIB_RLE})
    ours = save_figure(fig, tmp_path / "ours.png", close=False, dpi=60)
    assert ours.read_bytes() == plain.read_bytes()
    assert fig.get_layout_engine() is engine
    plt.close(fig)


def test_png_files_hold_the_pixels_of_matplotlibs_default_png(tmp_path):
    """``save_figure`` writes PNGs with a faster zlib strategy: the decoded picture must be
    the one of matplotlib's default PNG (drawn with the same settings), pixel for pixel,
    in a file not much larger."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    from ins_errors.output import DRAWING_RC, save_figure

    fig, ax = plt.subplots(figsize=(5, 3))
    t = np.linspace(0.0, 24.0, 500)
    ax.plot(t, np.sin(2 * np.pi * t / 1.4), label="direct")
    ax.plot(t, 0.9 * np.sin(2 * np.pi * t / 1.4), ls="--", label="linear")
    ax.grid(True, alpha=0.3)
    ax.legend()
    default = tmp_path / "default.png"
    with matplotlib.rc_context(DRAWING_RC):
        fig.savefig(default, dpi=80)
    ours = save_figure(fig, tmp_path / "ours.png", dpi=80)
    with Image.open(default) as a, Image.open(ours) as b:
        assert a.mode == b.mode == "RGBA" and a.size == b.size
        assert np.array_equal(np.asarray(a), np.asarray(b))
        assert a.info.get("Software") == b.info.get("Software")  # matplotlib's own metadata
    assert ours.read_bytes() != default.read_bytes()  # (the faster strategy is in use)
    assert ours.stat().st_size < 1.3 * default.stat().st_size


def test_kept_text_layouts_write_the_bytes_of_a_plain_savefig(tmp_path):
    """``save_figure`` keeps text layouts (each text's box between its measurements and
    drawing, each string's glyph placement and size per font and size, across figures)
    and updates each axis' ticks once per drawing of it: its files must be byte for byte
    matplotlib's own ``savefig`` with the same settings of a twin figure (its own
    renderer and matplotlib's caches), for a figure saved three times with new limits,
    tick labels and titles and two labels whose font size changes in place; with shared
    time axes, multi-line, rotated, wrapped, mathtext and non-ASCII texts, an offset text
    and a legend. Afterwards matplotlib's methods are its own again."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import ft2font
    from matplotlib.axis import Axis
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.text import Text

    from ins_errors import text_layouts
    from ins_errors.output import DRAWING_RC, PNG_ZLIB_RLE, save_figure

    def methods():
        return [Text._get_layout, RendererAgg.get_text_width_height_descent, Axis.draw,
                Axis._update_ticks,
                *(getattr(ft2font.FT2Font, name, None) for name in ("_layout", "set_size",
                                                                   "clear"))]

    values = np.array([3e-7, 1e-6, -2e-7])

    def figure():
        # (saved at the figure's own resolution, a figure keeps its renderer, and the
        # layouts measured with it, from one save to the next)
        fig, axes = plt.subplots(2, 1, figsize=(4, 4), dpi=60, sharex=True)
        line, = axes[0].plot([0, 1, 2], values, label="direct")
        axes[0].legend(loc="best", fontsize=7)
        axes[0].set_ylabel("alpha_y\n[arcmin]")
        axes[0].set_title("error curves", loc="left")
        fig.subplots_adjust(left=0.3, hspace=0.6)
        axes[1].plot([0, 1, 2], [1e4, 3e5, 2e4], label="− linear")
        axes[1].set_xlabel(r"time, h ($\tau$ = 1 s)")
        axes[1].set_title("a title long enough to be wrapped at the figure's edge, twice "
                          "over", wrap=True, fontsize=9)
        return fig, axes, line

    before = methods()
    text_layouts._boxes.clear()
    twins = [figure(), figure()]
    for k, (scale, title) in enumerate(((1.0, "φ = 39°"), (1e3, "m/s², second"),
                                        (1e3, "m/s², second"))):
        for fig, axes, line in twins:
            line.set_ydata(values * scale)
            axes[0].relim()
            axes[0].autoscale_view()
            fig.suptitle(title)
            if k == 2:
                for text in (axes[0].yaxis.label, axes[0]._left_title):
                    text.set_fontsize(14)  # (changes its font properties in place)
        (ours, _, _), (plain, _, _) = twins
        saved = save_figure(ours, tmp_path / f"ours{k}.png", close=False, dpi=60)
        with matplotlib.rc_context(DRAWING_RC):
            plain.savefig(tmp_path / f"plain{k}.png", dpi=60,
                          pil_kwargs={"compress_type": PNG_ZLIB_RLE})
        assert saved.read_bytes() == (tmp_path / f"plain{k}.png").read_bytes(), k
    for fig, _, _ in twins:
        plt.close(fig)
    assert len(text_layouts._boxes) > 10 and text_layouts._measures  # (they were kept)
    if hasattr(ft2font.FT2Font, "_layout"):
        assert text_layouts._glyphs
    assert methods() == before


def _ticking_clock(monkeypatch):
    """Make every reading of the wall clock a different time (a write one second later)."""
    import itertools
    import time

    ticks = itertools.count()
    monkeypatch.setattr(time, "asctime", lambda *a: f"Tue Dec  1 08:00:{next(ticks):02d} 2026")


def test_curves_mat_is_the_same_bytes_for_the_same_curves(report, tmp_path, monkeypatch):
    """No write time in the file: the same run gives the same curves.mat, byte for byte
    (scipy's header says "Created on: <now>"), and it still loads."""
    from scipy.io import loadmat

    from ins_errors.export import save_curves_mat

    result, folder = report
    _ticking_clock(monkeypatch)
    save_curves_mat(result.comparisons, tmp_path / "a.mat")
    save_curves_mat(result.comparisons, tmp_path / "b.mat")
    first = (tmp_path / "a.mat").read_bytes()
    assert first == (tmp_path / "b.mat").read_bytes() == (folder / "curves.mat").read_bytes()
    assert first.startswith(b"MATLAB 5.0 MAT-file, written by ins-errors ")
    data = loadmat(tmp_path / "a.mat", squeeze_me=True, struct_as_record=False)
    np.testing.assert_array_equal(data["case_1"].direct.alpha_y,
                                  result.comparisons[0].direct["alpha_y"])


def test_written_mat_samples_are_the_same_bytes_each_time(tmp_path, monkeypatch):
    from scipy.io import loadmat

    from ins_errors.checker.check_motions import motions
    from ins_errors.checker.matrix_input import write_samples
    from ins_errors.numeric.model import load_model

    ms = motions(load_model("strapdown_ned"), hours=1.0, step=600.0)
    _ticking_clock(monkeypatch)
    write_samples(tmp_path / "a.mat", ms)
    write_samples(tmp_path / "b.mat", ms)
    assert (tmp_path / "a.mat").read_bytes() == (tmp_path / "b.mat").read_bytes()
    data = loadmat(tmp_path / "a.mat")
    np.testing.assert_array_equal(data["t_static"].ravel(), ms[0].times)


@pytest.mark.parametrize("step, halved", [("20 s", True), ("10 s", False)])
def test_report_names_the_step_of_the_integration_error_runs_it_made(step, halved, tmp_path,
                                                                     monkeypatch):
    """report.md said "a second run at twice the step" also where the runs at half the
    step were made (an odd number of steps between two recorded samples)."""
    from ins_errors.numeric import accuracy
    from ins_errors.report import report_markdown

    made = []
    real_halved, real_coarsened = accuracy.halved, accuracy.coarsened
    monkeypatch.setattr(accuracy, "halved",
                        lambda t, m: made.append(t.tau / 2) or real_halved(t, m))
    monkeypatch.setattr(accuracy, "coarsened",
                        lambda t: made.append(2 * t.tau) or real_coarsened(t))
    scenario_file = tmp_path / "s.toml"
    scenario_file.write_text(SCENARIO.replace('step = "1 s"', f'step = "{step}"'),
                             encoding="utf-8")
    result = run_scenario(load_scenario(scenario_file))
    text = report_markdown(result, ["a.png", "b.png"])
    sentence = text[text.index("The integration error"):].split("\n")[0]
    tau = float(step.split()[0])
    assert made[0] == (tau / 2 if halved else 2 * tau)  # the pair's other run
    assert ("half the step" in sentence) is halved
    assert ("twice the step" in sentence) is not halved
    assert f"{made[0]:g} s" in sentence


@pytest.mark.parametrize("run, fail_at, made", [
    (("1 s", "1 s", "1 s"), None, []),       # a single step: no rerun at all
    (("2 s", "1 s", "2 s"), None, [2.0]),    # too short for a third run at 4τ
    (("20 min", "10 s", "60 s"), 40.0, [20.0]),  # the third run (at 4τ) fails
])
def test_report_names_only_the_integration_error_runs_that_were_completed(
        run, fail_at, made, tmp_path, monkeypatch):
    """report.md rebuilt compare's choice of reruns from the step and the recording
    interval, and named runs at half or twice the step (and a third for the order) also
    where the run has a single step, is too short for the third run, or a rerun failed."""
    from ins_errors.errors import InsErrorsError
    from ins_errors.numeric import accuracy
    from ins_errors.report import report_markdown

    real_coarsened = accuracy.coarsened

    def coarsened(t):
        if fail_at is not None and 2 * t.tau == fail_at:
            raise InsErrorsError(f"the run at {fail_at:g} s leaves the domain")
        return real_coarsened(t)

    monkeypatch.setattr(accuracy, "coarsened", coarsened)
    duration, step, record = run
    text = (SCENARIO.replace('duration = "20 min"', f'duration = "{duration}"')
            .replace('step = "1 s"', f'step = "{step}"')
            .replace('record = "60 s"', f'record = "{record}"'))
    scenario_file = tmp_path / "s.toml"
    scenario_file.write_text(text, encoding="utf-8")
    result = run_scenario(load_scenario(scenario_file))
    text = report_markdown(result, ["a.png", "b.png"])
    sentence = text[text.index("The integration error"):].split("\n")[0]
    assert all(list(c.integration_steps) == made for c in result.comparisons)
    assert all(c.to_dict()["integration_rerun_steps_s"] == made for c in result.comparisons)
    if not made:
        assert "not estimated" in sentence and "the step" not in sentence
        assert any("single step" in w for w in result.comparisons[0].warnings)
    else:
        assert f"twice the step ({made[0]:g} s" in sentence
        assert "a third" not in sentence and "half the step" not in sentence


def test_the_residual_panels_draw_model_minus_direct_as_labelled(report):
    # the tables and warnings say "linear − direct"; the panels drew and named
    # direct − linear. A linear curve above the direct one by a known ramp must show as
    # that positive ramp, under the tables' name
    from ins_errors.numeric import plots

    result, _ = report
    comparison = result.comparisons[0]
    ramp = np.linspace(0.0, 1.0, comparison.times.size)
    shifted = replace(comparison,
                      linear={q: v + 1e-6 * ramp for q, v in comparison.direct.items()},
                      refined={q: v - 2e-6 * ramp for q, v in comparison.direct.items()})
    figure = plots._ComparisonFigure(shifted, ["alpha_y", "delta_v_N"])
    figure.show(shifted, "signs")
    for (_, panel), (_, scale, row) in zip(figure.axes, figure.lines, strict=True):
        residuals = {line.get_label(): line.get_ydata() for line in row if line.axes is panel}
        assert set(residuals) == {"linear − direct", "refined − direct"}
        linear, refined = residuals["linear − direct"], residuals["refined − direct"]
        assert linear.min() >= -1e-9 * scale and linear.max() == pytest.approx(1e-6 * scale)
        assert refined.max() <= 1e-9 * scale and refined.min() == pytest.approx(-2e-6 * scale)


def test_large_curves_are_announced_with_their_size(report, tmp_path, monkeypatch):
    """A week at a 1-s record wrote 0.4 GB of curves.csv in silence, taking eight times
    the runs (the long-flight probe). From export.LARGE_OUTPUT bytes on (lowered here),
    writing them is announced with a size near the file's own."""
    import warnings

    from ins_errors import export
    from ins_errors.output import OutputFolder

    result, _ = report
    monkeypatch.setattr(export, "LARGE_OUTPUT", 1.0)
    folder = OutputFolder(tmp_path / "big")
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        export.write_curves(folder, result.comparisons)
    folder.finish()
    (note,) = [str(w.message) for w in seen if "curves.csv" in str(w.message)]
    assert note.startswith("ins-errors: note: writing about ")
    announced = float(note.split("about ")[1].split(" MB")[0]) * 1e6
    actual = (tmp_path / "big" / "curves.csv").stat().st_size
    assert announced == pytest.approx(actual, rel=0.35)
    monkeypatch.setattr(export, "LARGE_OUTPUT", 200e6)
    assert export.large_output_note(result.comparisons) is None


def test_a_week_long_run_is_plotted_against_days(tmp_path):
    """A 720-h run was drawn against 0...700 h (the long-flight probe); from a week on the
    time axis is in days, and a shorter run's stays in hours (the same figure, reused)."""
    import matplotlib.image as mpimg

    from ins_errors import load_model
    from ins_errors.numeric import plots
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import compare

    model = load_model("orthodromic")

    def drawn(hours: float):
        motion = tr.trajectory(model, tr.static_profile(np.radians(50.0)), hours * 3600.0,
                               60.0)
        (case,) = compare(model, motion, [{"gyro_drift_x": 1e-7}], record_interval=3600.0,
                          integration_error=False, validity_threshold=None, refined=False,
                          warn=False)
        path = tmp_path / f"{hours:g}.png"
        plots.plot_comparison(case, path, ["alpha_y"])
        assert mpimg.imread(path).shape[0] > 100
        figure = plots._SPARE_FIGURES.figures[-1]
        axis = figure.axes[-1, 0]
        return axis.get_xlabel(), axis.get_xlim()[1]

    label, end = drawn(8 * 24.0)
    assert label == "time [d]" and 7.5 < end < 9
    label, end = drawn(24.0)
    assert label == "time [h]" and 20 < end < 26


def test_a_reports_plots_name_the_model_motion_and_run(report, tmp_path):
    """A run's case plots were titled with the scenario's title and the case alone; a
    plot taken out of its folder did not say what was flown (the long-flight probe).
    They now carry compare's line: model, motion, duration, step and scheme."""
    from ins_errors.numeric import plots

    result, _ = report
    write_report(result, tmp_path / "again")
    title = plots._SPARE_FIGURES.figures[-1].title.get_text().replace("\n", " ")
    assert result.motion_description.split(" ")[0] in title
    assert result.scenario.model in title and "τ = " in title
    assert "; 20 min, τ = " in title  # the scenario's 20 min, not "0.333333 h"
