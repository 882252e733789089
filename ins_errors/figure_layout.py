"""Cheap layout for figures of stacked panels: fixed margins and one time axis.

Two matplotlib conveniences cost most of a many-panel figure's drawing time:

* ``tight_layout`` measures every tick label of every panel (about one extra draw of the
  figure) to choose the margins; margins fixed in inches, wide enough for the labels
  these figures have, give the same picture without the measuring pass;
* ``sharex=True`` makes every panel visit all its siblings on each limit update and each
  draw (the tick labels of every sibling are laid out again for each panel). Panels that
  plot against the same times get the same range by construction; :func:`share_time_axis`
  then hides the inner time labels as ``sharex`` would.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable


def fixed_margins(fig, left: float, right: float, bottom: float, top: float,
                  wspace: float = 0.0, hspace: float = 0.0) -> None:
    """Place the panels with margins and gaps given in inches.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (its size is read now: set it first).
    left, right, bottom, top : float
        Distance of the panel grid from each figure edge, in inches.
    wspace, hspace : float
        Gap between two columns / two rows of panels, in inches.
    """
    width, height = fig.get_size_inches()
    columns, rows = _grid_shape(fig)
    panel_width = (width - left - right - (columns - 1) * wspace) / columns
    panel_height = (height - bottom - top - (rows - 1) * hspace) / rows
    fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height,
                        top=1 - top / height, wspace=wspace / panel_width,
                        hspace=hspace / panel_height)


LEGEND_ROW = 0.3
"""Inches a one-row legend under the panels (:func:`legend_below`) adds to the bottom
margin."""


def legend_below(ax, fontsize: float, handles=None, above: float = 0.04):
    """A one-row legend centred under the panel column of ``ax``, in the figure's bottom
    margin (:data:`LEGEND_ROW` inches of it), where it hides no curve.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        A panel of the column (its x extent centres the legend).
    fontsize : float
        Points.
    handles : list of matplotlib.artist.Artist, optional
        The entries (default: the labelled artists of ``ax``).
    above : float
        Height of the legend's lower edge over the figure's bottom edge, inches.

    Returns
    -------
    matplotlib.legend.Legend
    """
    from matplotlib.transforms import blended_transform_factory

    if handles is None:
        handles = ax.get_legend_handles_labels()[0]
    where = blended_transform_factory(ax.transAxes, ax.figure.dpi_scale_trans)
    return ax.legend(handles=handles, fontsize=fontsize, ncol=len(handles),
                     loc="lower center", bbox_to_anchor=(0.5, above),
                     bbox_transform=where, frameon=False)


def _grid_shape(fig) -> tuple[int, int]:
    for ax in fig.axes:
        spec = ax.get_subplotspec()
        if spec is not None:
            rows, columns = spec.get_gridspec().get_geometry()
            return columns, rows
    return 1, 1


def share_time_axis(axes) -> None:
    """Hide the time tick labels of every panel but those of the bottom row.

    Parameters
    ----------
    axes : numpy.ndarray of matplotlib.axes.Axes, shape (rows,) or (rows, columns)
        The panels, as ``plt.subplots`` returns them.

    Notes
    -----
    Call :func:`common_time_range` after the curves are in, so that every panel spans
    the same times (a panel whose curve ends early in NaNs included).
    """
    grid = axes.reshape(len(axes), -1)
    for ax in grid[:-1].flat:
        ax.xaxis.set_tick_params(which="both", labelbottom=False)
        ax.xaxis.offsetText.set_visible(False)
        _skip_hidden_label_layout(ax.xaxis)


def _skip_hidden_label_layout(axis) -> None:
    """Spare an axis whose tick labels are hidden the work of laying them out.

    Its labels are still formatted on every draw and measured to place the (empty) axis
    label below them; neither shows. No formatter and a fixed place for the axis label
    draw the same pixels.
    """
    from matplotlib.ticker import NullFormatter

    if len(axis.axes.get_shared_x_axes().get_siblings(axis.axes)) == 1:
        axis.set_major_formatter(NullFormatter())  # (shared axes share one formatter)
    axis.set_label_coords(0.5, 0.0)


def fixed_title(ax, text: str, **options) -> None:
    """``ax.set_title`` at the top of the panel, without matplotlib's search on every
    draw for tick labels or an offset text above the panel that the title should clear
    (use it when nothing is drawn there, or the title's ``pad`` already clears it)."""
    ax.set_title(text, y=1.0, **options)


def common_time_range(axes: Iterable) -> None:
    """Give every panel the union of their autoscaled time ranges, as ``sharex`` would."""
    axes = list(axes)
    lows, highs = zip(*(ax.get_xlim() for ax in axes), strict=True)
    for ax in axes:
        ax.set_xlim(min(lows), max(highs), auto=None)


def text_width(texts: Iterable[str], size: float) -> float:
    """Width of the widest line of ``texts`` at ``size`` points in the default font.

    Measured from the glyphs, without drawing anything; a line holding two or more
    ``$`` is measured as mathtext, as matplotlib would draw it.

    Parameters
    ----------
    texts : iterable of str
        Texts; each may hold several lines (``\\n``).
    size : float
        Font size, points.

    Returns
    -------
    float
        Width, inches (0 for no text).
    """
    import matplotlib

    rc = matplotlib.rcParams
    fonts = repr([rc[k] for k in _FONT_KEYS])
    return max((_measure_line(line, size) if line.count("$") >= 2
                else _line_width(line, size, fonts)
                for text in texts for line in text.split("\n") if line),
               default=0.0) / 72


FONT_FAMILY_SETTINGS = ("font.family", "font.sans-serif", "font.serif", "font.monospace",
                        "font.cursive", "font.fantasy")
"""matplotlib settings that decide which font a family name (or the default) resolves to."""

_FONT_KEYS = (*FONT_FAMILY_SETTINGS, "font.style", "font.variant", "font.weight",
              "font.stretch", "text.kerning_factor")
"""Settings a default-font line's width depends on, besides its text and size."""


@functools.lru_cache(maxsize=4096)
def _line_width(line: str, size: float, fonts: str) -> float:
    """:func:`_measure_line`, kept: matplotlib shapes a line to measure it (~0.4 ms, more
    for long lines), and the same lines are measured again (``fonts``, the font settings
    in force, is part of the key; mathtext, which has settings of its own, is not kept)."""
    return _measure_line(line, size)


def _measure_line(line: str, size: float) -> float:
    """Width of one line at ``size`` points in the default font, points."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    return text_to_path.get_text_width_height_descent(
        line, FontProperties(size=size), ismath=line.count("$") >= 2)[0]


def text_height(text: str, size: float) -> float:
    """Height of the lines of ``text`` at ``size`` points, inches (matplotlib's line
    spacing of 1.2, rounded up)."""
    return 1.2 * size * (text.count("\n") + 1) / 72


def wrap_to_width(text: str, size: float, width: float) -> str:
    """``text`` with every line wider than ``width`` inches at ``size`` points broken at
    spaces (lines that fit are kept as they are)."""
    import textwrap

    lines = []
    for line in text.split("\n"):
        chars = len(line)
        while chars > 10 and text_width([textwrap.fill(line, chars)], size) > width:
            chars = int(chars * 0.9)
        lines.append(textwrap.fill(line, chars) if chars < len(line) else line)
    return "\n".join(lines)
