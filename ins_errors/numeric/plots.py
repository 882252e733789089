"""Overlaid direct / linear / refined error curves (matplotlib, Agg backend).

Angles are drawn in arc minutes, angular rates in deg/h, velocities in m/s, time in
hours; the conversion goes through the units library. The residuals of angles are
differences on the circle (:func:`~ins_errors.numeric.compare.residual`), as in the
tables.

The vertical range of each panel is set by the direct and linear curves (and, on the
right, by the refined residual up to the size of the direct error): a refined run that
ran away (:func:`~ins_errors.numeric.compare.add_refined_warnings`) is clipped at the
axes, which say so in the panel and in the legend, instead of flattening the other
curves to a line at zero.
"""

from __future__ import annotations

import math
import textwrap
import threading
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ins_errors.errors import name_list
from ins_errors.figure_layout import (
    LEGEND_ROW,
    common_time_range,
    fixed_title,
    legend_below,
    share_time_axis,
)
from ins_errors.numeric.compare import Comparison, residual
from ins_errors.numeric.envelope import column_envelopes
from ins_errors.output import save_figure

DPI = 100
"""Resolution of the comparison figures, dots per inch."""


def _scale(unit: str) -> tuple[float, str]:
    from ins_errors.units import display_scale

    return display_scale(unit)


def shared_quantities(comparisons: Sequence[Comparison]) -> list[str]:
    """Quantities excited in any of the cases, in the model's order (all if none is).

    Plotting every case with this one list keeps the panel layout the same across cases.
    """
    if not comparisons:
        return []
    names = [m.quantity for m in comparisons[0].metrics]
    excited = {m.quantity for c in comparisons for m in c.excited}
    return [q for q in names if q in excited] or names


def plot_comparison(comparison: Comparison, path: str | Path,
                    quantities: Sequence[str] | None = None, title: str = "") -> Path:
    """Save one row per quantity: the curves (left) and their residuals (right).

    The left panel overlays the direct, linear and refined errors; at the scale of the
    errors they are usually indistinguishable, so the right panel draws what the study
    is about: linear − direct and refined − direct (the sign of the tables and
    warnings; for an angle, on the circle), on their own scale. The left panel's range
    is the direct and linear curves', the right one's the linear residual's and the
    refined residual's up to the size of the largest direct error: a refined curve
    beyond is clipped, and the panel and the legend say so.

    Parameters
    ----------
    comparison : Comparison
        One compared case.
    path : str or Path
        Output file (``.png``, ``.pdf``, ``.svg``: whatever matplotlib writes).
    quantities : sequence of str, optional
        Quantities to draw, one row each (default: every excited quantity, else all;
        pass :func:`shared_quantities` of all cases to keep the layout fixed).
    title : str
        Figure title (default: the case label).

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    InsErrorsError
        If a quantity is unknown or the file cannot be written.
    """
    return plot_comparisons([comparison], [path], quantities, [title])[0]


def plot_comparisons(comparisons: Sequence[Comparison], paths: Sequence[str | Path],
                     quantities: Sequence[str] | None = None,
                     titles: Sequence[str] | None = None) -> list[Path]:
    """Save one :func:`plot_comparison` figure per case, drawing the panels only once.

    The cases share one figure whose curves, limits and title are replaced case by
    case: the files are the same as drawing each case afresh, without building every
    panel and tick again (most of matplotlib's cost for these many-panel figures). The
    last figures are kept for the next call with the same panels (quantities, units,
    refined curves or not) and matplotlib settings, e.g. the next report of a session.

    Parameters
    ----------
    comparisons : sequence of Comparison
        The cases.
    paths : sequence of str or Path
        One output file per case.
    quantities : sequence of str, optional
        Quantities to draw, one row each, for every case (default: per case, as
        :func:`plot_comparison`).
    titles : sequence of str, optional
        One figure title per case (an empty title: the case label).

    Returns
    -------
    list of Path
        The written files.

    Raises
    ------
    InsErrorsError
        If a quantity is unknown or a file cannot be written.
    """
    import matplotlib

    matplotlib.use("Agg")

    titles = list(titles) if titles is not None else [""] * len(comparisons)
    written, figure = [], None
    try:
        for comparison, path, title in zip(comparisons, paths, titles, strict=True):
            shown = (shared_quantities([comparison]) if quantities is None
                     else name_list(quantities, "quantities"))
            for q in shown:
                comparison.metric(q)  # raises a one-line error for unknown names
            layout = _ComparisonFigure.layout_of(comparison, shown)
            if figure is None or figure.layout != layout:
                if figure is not None:
                    _SPARE_FIGURES.keep(figure)
                figure = _SPARE_FIGURES.take(layout) or _ComparisonFigure(comparison, shown)
            figure.show(comparison, title or comparison.label)
            written.append(save_figure(figure.fig, path, dpi=DPI, close=False))
    except BaseException:
        figure = None  # (a figure left half-drawn is not kept)
        raise
    finally:
        if figure is not None:
            _SPARE_FIGURES.keep(figure)
    return written


def _value_range(ax, curves: Sequence[np.ndarray]) -> tuple[float, float] | None:
    """The vertical range autoscaling gives ``ax`` for the finite values of ``curves``
    alone (their extremes, made non-singular by the axis' locator, widened by the axes'
    margin), or None when there is none."""
    finite = [c[np.isfinite(c)] for c in curves]
    finite = [c for c in finite if c.size]
    if not finite:
        return None
    locator = ax.yaxis.get_major_locator()
    low, high = locator.nonsingular(min(float(c.min()) for c in finite),
                                    max(float(c.max()) for c in finite))
    margin = ax.margins()[1] * (high - low)
    return locator.view_limits(low - margin, high + margin)


def _off_axes(curve: np.ndarray, limits: tuple[float, float]) -> str:
    """The panel's note when the refined ``curve`` leaves the vertical ``limits``:
    ``"refined beyond the axes (to 1.05e+05)"``, or ``""``."""
    low, high = limits
    finite = curve[np.isfinite(curve)]
    beyond = finite[(finite < low) | (finite > high)]
    if finite.size < curve.size:
        return "refined beyond the axes (not finite)"
    if not beyond.size:
        return ""
    far = float(beyond[np.argmax(np.abs(beyond))])
    return f"refined beyond the axes (to {far:.3g})"


class _SpareFigures:
    """The last few comparison figures of this process, for calls with the same panels.

    A figure is taken out while it is drawn (another thread gets a new one) and kept
    with the matplotlib settings it was built with: it is reused only under the same.
    """

    size = 2
    """Figures kept (each holds its drawing buffer, ~8 MB for ten rows)."""

    def __init__(self):
        self.figures: list[_ComparisonFigure] = []
        self.lock = threading.Lock()

    def take(self, layout: tuple) -> _ComparisonFigure | None:
        """A kept figure with these panels and today's settings, removed from the store."""
        import matplotlib

        settings = dict(matplotlib.rcParams)
        with self.lock:
            for k, figure in enumerate(self.figures):
                if figure.layout == layout and figure.settings == settings:
                    return self.figures.pop(k)
        return None

    def keep(self, figure: _ComparisonFigure) -> None:
        """Keep ``figure`` for a later call (the oldest kept ones beyond ``size`` go)."""
        with self.lock:
            self.figures.append(figure)
            while len(self.figures) > self.size:
                self.figures.pop(0)


_SPARE_FIGURES = _SpareFigures()


DAYS_FROM = 7 * 86400.0
"""Runs at least this long (s) are plotted against days, shorter ones against hours."""


class _ComparisonFigure:
    """The panels of :func:`plot_comparison` for one layout, refilled case by case."""

    def __init__(self, comparison: Comparison, quantities: list[str]):
        import matplotlib
        import matplotlib.pyplot as plt

        self.layout = self.layout_of(comparison, quantities)
        self.settings = dict(matplotlib.rcParams)
        n = len(quantities)
        # every panel plots against the same times, so their time ranges agree without
        # sharex (sharing makes each axis visit all its siblings on every limit update
        # and draw: ~20 % of the figure's time with 20 panels); as sharex would, only the
        # bottom row labels the time ticks
        fig, axes = plt.subplots(n, 2, figsize=(11.0, 1.75 * n + 1.5 + LEGEND_ROW),
                                 squeeze=False)
        plt.close(fig)  # (pyplot forgets it; the figure is still drawn and saved)
        share_time_axis(axes)
        self.fig, self.axes, self.lines = fig, axes, []
        self.notes = []  # per row: the texts saying a refined curve leaves the axes
        for (curves, residuals), q in zip(axes, quantities, strict=True):
            scale, unit = _scale(comparison.metric(q).unit)
            row = [curves.plot([], [], color="black", lw=1.6, label="direct")[0],
                   curves.plot([], [], color="tab:orange", lw=1.0, ls="--",
                               label="linear")[0],
                   residuals.plot([], [], color="tab:orange", lw=1.0,
                                  label="linear − direct")[0]]
            if comparison.refined:
                row += [curves.plot([], [], color="tab:blue", lw=1.0, ls=":",
                                    label="refined")[0],
                        residuals.plot([], [], color="tab:blue", lw=1.0,
                                       label="refined − direct")[0]]
            self.lines.append((q, scale, row))
            self.notes.append([ax.text(0.99, 0.95, "", transform=ax.transAxes, ha="right",
                                       va="top", fontsize=6, color="tab:blue",
                                       bbox={"facecolor": "white", "edgecolor": "none",
                                             "alpha": 0.9, "pad": 1.0}, zorder=5)
                               for ax in (curves, residuals)])
            curves.set_ylabel(f"{q}\n[{unit}]", fontsize=8)
            residuals.set_ylabel(f"residual [{unit}]", fontsize=8)
            for ax in (curves, residuals):
                ax.grid(True, alpha=0.3)
                ax.tick_params(labelsize=7)
                ax.ticklabel_format(axis="y", useOffset=False)
        # (the pad clears the residuals' offset text, e.g. 1e-6)
        fixed_title(axes[0, 0], "error curves", fontsize=9, pad=14)
        fixed_title(axes[0, 1], "residuals: what the linear / refined models miss",
                    fontsize=9, pad=14)
        for ax in axes[-1]:
            ax.set_xlabel("time [h]", fontsize=8)
        # under each column: inside the top panels they hid dense curves
        self.legends = [legend_below(axes[-1, column], 7, handles=[
            line for line in self.lines[0][2] if line.axes is axes[0, column]])
            for column in (0, 1)]
        # fixed margins in inches (tight_layout measured every tick label: seconds a figure)
        width, height = fig.get_size_inches()
        self.title = fig.suptitle("", fontsize=9, y=1 - 0.1 / height, va="top")
        # characters of a title line that fit the width (9-pt text, ~0.55 em a character)
        self.title_characters = int((width - 0.3) * 72 / (0.55 * 9))
        fig.subplots_adjust(left=1.0 / width, right=1 - 0.15 / width,
                            bottom=(0.55 + LEGEND_ROW) / height,
                            top=1 - 1.0 / height, wspace=0.95 / (width / 2),
                            hspace=0.4 / 1.75)
        self.columns = 2 * math.ceil(axes[0, 0].get_position().width * width * DPI)

    @staticmethod
    def layout_of(comparison: Comparison, quantities: Sequence[str]) -> tuple:
        """What the panels depend on: the quantities, their units, refined curves or not."""
        return (tuple(quantities), tuple(comparison.metric(q).unit for q in quantities),
                bool(comparison.refined))

    def show(self, comparison: Comparison, title: str) -> None:
        """Put one case's curves, limits and title in the figure."""
        # a run of a week or more reads in days
        days = comparison.times[-1] >= DAYS_FROM if len(comparison.times) else False
        hours = comparison.times / (86400.0 if days else 3600.0)
        for ax in self.axes[-1]:
            ax.set_xlabel("time [d]" if days else "time [h]", fontsize=8)
        clipped = [0, 0]  # panels whose refined curve leaves the axes, per column
        # a refined run that diverged is drawn up to where it did (what follows is its
        # runaway, which says nothing more and hides the other curves)
        departure = (comparison.refined_departure
                     if comparison.refined_warning == "diverged" else None)
        drawn = (comparison.times <= departure if departure is not None
                 else np.ones(len(comparison.times), dtype=bool))
        for (q, scale, row), notes, (left, right) in zip(self.lines, self.notes, self.axes,
                                                         strict=True):
            unit = comparison.metric(q).unit
            d = comparison.direct[q]
            direct = d * scale
            linear = comparison.linear[q] * scale
            curves = [direct, linear, residual(comparison.linear[q], d, unit) * scale]
            if comparison.refined:
                refined = comparison.refined[q] * scale
                curves += [np.where(drawn, c, np.nan) for c in (
                    refined, residual(comparison.refined[q], d, unit) * scale)]
            # the solid lines' paths keep, per half pixel column, each curve's first,
            # last, smallest and largest sample: the same picture, cheaper for long
            # records; the dashed and dotted ones (linear, refined) are drawn whole:
            # their pattern runs along the drawn length, which a reduction changes
            solid = [line.get_linestyle() == "-" for line in row]
            reduced = iter(column_envelopes(
                hours, [c for c, s in zip(curves, solid, strict=True) if s], self.columns))
            for line, values, is_solid in zip(row, curves, solid, strict=True):
                line.set_data(*(next(reduced) if is_solid else (hours, values)))
            for ax in (left, right):
                ax.relim()
                ax.autoscale_view()
            # the ranges: direct and linear on the left; on the right the linear
            # residual, and the refined one up to the direct error's size
            size = float(np.max(np.abs(direct[np.isfinite(direct)]), initial=0.0))
            ranges = [_value_range(left, curves[:2]), _value_range(
                right, curves[2:3] + ([np.clip(curves[4], -size, size)]
                                      if comparison.refined else []))]
            for k, (ax, note, span) in enumerate(zip((left, right), notes, ranges,
                                                      strict=True)):
                if span is not None:
                    ax.set_ylim(*span)
                text = ""
                if comparison.refined:
                    text = _off_axes(curves[3 + k][drawn], ax.get_ylim())
                    clipped[k] += bool(text)
                note.set_text(text)
        cut = ([] if departure is None else
               [f"diverged: not drawn after {departure / (86400.0 if days else 3600.0):.3g} "
                f"{'d' if days else 'h'}"])
        for legend, count, name in zip(self.legends, clipped, ("refined", "refined − direct"),
                                       strict=True):
            said = cut + ([f"clipped: leaves the axes in {count} of {len(self.lines)} "
                           "panels"] if count else [])
            for entry in legend.get_texts():
                if entry.get_text().startswith(name):
                    entry.set_text(f"{name} ({'; '.join(said)})" if said else name)
        # one time range for all panels, as a shared axis would give (a panel whose curve
        # is cut short by NaNs still spans the whole run)
        common_time_range(self.axes.flat)
        # a long motion description is wrapped, not cut at the figure's edges
        self.title.set_text("\n".join(textwrap.fill(line, self.title_characters)
                                       for line in title.split("\n")))
