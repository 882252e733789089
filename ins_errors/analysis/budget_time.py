"""Every spec item over the operating time at the budget's magnitudes (``--plot-time``).

The curves are read from the propagation the allocation itself was made from
(:attr:`~ins_errors.analysis.budget.UnitBudget.item_variances`, every grid time), by the
same :func:`~ins_errors.analysis.budget.item_lines` that gives the spec rows: at a check
time a curve is the row's value, number for number. Nothing is propagated again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ins_errors.analysis.budget import (
    RATE_ITEMS,
    Allocation,
    BudgetError,
    display,
    format_time,
    item_cep_parts,
    item_lines,
)
from ins_errors.analysis.budget_cep import cep
from ins_errors.figure_layout import fixed_margins, text_height, text_width, wrap_to_width
from ins_errors.output import require_matplotlib, save_figure
from ins_errors.specs import HOUR
from ins_errors.units import parse_quantity


@dataclass(frozen=True)
class ItemCurve:
    """One spec item (one component of an item checked ``"each"``) over the grid.

    Attributes
    ----------
    item : str
        The spec item's name.
    component : str
        ``""`` for an item whose components are combined (rss), else the component.
    unit : str
        SI unit of ``values`` and ``limit``.
    limit : float
        The item's limit at the spec's σ level, SI.
    times : numpy.ndarray, shape (nt,)
        Grid times, s (a rate item, error / t, from the first step on).
    values : numpy.ndarray, shape (nt,)
        The item at the spec's σ level at every time, SI (a CEP item's CEP).
    check_times : numpy.ndarray, shape (nc,)
        The spec's check times of the item, s.
    check_values : numpy.ndarray, shape (nc,)
        ``values`` at the check times: the budget's rows.
    """

    item: str
    component: str
    unit: str
    limit: float
    times: np.ndarray
    values: np.ndarray
    check_times: np.ndarray
    check_values: np.ndarray


def item_curves(allocation: Allocation) -> list[ItemCurve]:
    """Every spec item at every grid time of the operating time, at the spec's σ level.

    Parameters
    ----------
    allocation : Allocation
        The magnitudes (an allocation, or the fixed sources alone of a spec they
        exceed: :func:`~ins_errors.analysis.budget_report.fixed_allocation`); sources
        not limited (σ = inf) are left out, as in the rows.

    Returns
    -------
    list of ItemCurve
        In the spec's order of items (components in the model's order).

    Raises
    ------
    BudgetError
        When the budget kept no per-time variances (a hand-made ``UnitBudget``).
    """
    budget = allocation.budget
    spec = budget.spec
    if budget.item_variances is None:
        raise BudgetError("this budget kept no variances over time: make it with "
                          "unit_budget")
    times = np.asarray(budget.system.times, dtype=float)
    if len(times) != budget.item_variances.shape[0]:
        raise BudgetError("the budget's variances over time do not match its grid")
    sigma = np.where(np.isfinite(allocation.sigma), allocation.sigma, 0.0)
    k = spec.sigma_level
    curves = []
    for item in spec.items:
        index = np.arange(len(times))
        if item.name in RATE_ITEMS:   # error / t: from the first step on
            index = index[times > 0]
        checks = np.array(item.times, dtype=float)
        at = np.array([round(t / budget.system.step) for t in checks], dtype=int) - index[0]
        if item.combine == "cep":   # the CEP of the sources' 2×2 covariances
            north, _, cross = item_cep_parts(item, budget.item_names,
                                             budget.item_variances, index, times[index])
            [(_, unit)] = item_lines(item, budget.item_names, budget.item_variances, index,
                                     times[index])
            total, north = (unit * sigma**2).sum(1), (north * sigma**2).sum(1)
            values = cep(north, total - north, (cross * sigma**2).sum(1))   # as the rows
            curves.append(ItemCurve(item.name, "", item.kind.unit, item.value,
                                    times[index], values, checks, values[at]))
            continue
        for component, unit in item_lines(item, budget.item_names, budget.item_variances,
                                          index, times[index]):
            values = k * np.sqrt((unit * sigma**2).sum(1))
            curves.append(ItemCurve(item.name, component, item.kind.unit, item.value,
                                    times[index], values, checks, values[at]))
    return curves


def above_between_checks(curve: ItemCurve) -> tuple[float, float] | None:
    """Where a curve is above its limit between its check times and beyond its worst
    check, or None.

    The spec checks an item at its check times only, so an allocation meets it there;
    between them the error may still pass the limit (a height error that peaks between
    two checks five minutes apart). The span looked at is from the first check time to
    the last, where the spec does look; before the first check a rate item's error / t
    is large by construction (an initial error over a few seconds).

    Returns
    -------
    (float, float) or None
        The time, s, and the value, SI at the spec's σ level, of the curve's largest
        value in that span, when it is above both the limit and the largest value at
        the check times.
    """
    inside = ((curve.times >= curve.check_times.min() - 1e-9)
              & (curve.times <= curve.check_times.max() + 1e-9))
    if not inside.any():
        return None
    i = int(np.argmax(np.where(inside, curve.values, -np.inf)))
    value = float(curve.values[i])
    if value > curve.limit and value > curve.check_values.max() * (1 + 1e-9):
        return float(curve.times[i]), value
    return None


LOG_DECADES = 1.5
"""A panel's value axis is logarithmic where its curve and limit span more than this many
decades (a rate item's error / t from the first step, an initial error that a later one
dwarfs): on a linear axis the part near the limit would be a flat line at 0."""


def time_unit(seconds: float) -> tuple[str, float]:
    """The unit a time axis spanning ``seconds`` reads best in, and seconds per unit:
    h from 2 h, min from 2 min, else s."""
    if seconds >= 2 * HOUR:
        return "h", HOUR
    if seconds >= 120:
        return "min", 60.0
    return "s", 1.0



SPARSE_CHECKS = 40
"""Up to this many check times are drawn as full-size markers; more get smaller ones, so
that an item checked every minute for hours is a curve, not a bar of dots."""


def _check_marker_size(count: int) -> float:
    """Marker size (points) of an item's ``count`` check times."""
    return 3.5 if count <= SPARSE_CHECKS else max(1.0, 3.5 * (SPARSE_CHECKS / count) ** 0.5)


def plot_time(allocation: Allocation, path: str, title: str) -> None:
    """Each spec item's value over the operating time, one panel per item.

    One panel per item, in the unit the spec wrote its limit in
    (:func:`~ins_errors.analysis.budget_report.written_unit`), its limit a horizontal
    line: a reviewer reads each error as the spec states it, and the gap between the
    curve and the line is the margin, in the item's own terms. A single panel of value /
    limit would show the margins on one scale, but in no unit, and a rate item's error /
    t, which starts large (an initial position error over the first minute), would set
    its range for every item. The panels share the time axis (h, min or s as the
    operating time suits, :func:`time_unit`); a panel whose curve and limit span more
    than :data:`LOG_DECADES` decades has a logarithmic value axis. The check times are
    marked on the curve (the item is checked there only), the worst one named with its
    value and its ratio to the limit, and where the curve is above the limit between
    the check times (:func:`above_between_checks`) that place is marked too. An item
    checked ``"each"`` draws one curve per component.

    Parameters
    ----------
    allocation : Allocation
        The magnitudes (:func:`item_curves`).
    path : str
        Image file (png, pdf, svg, ...).
    title : str
        The figure's heading (spec, motion, σ level and the magnitudes used).
    """
    require_matplotlib()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullFormatter

    from ins_errors.analysis.budget_report import written_unit

    budget = allocation.budget
    spec = budget.spec
    curves = item_curves(allocation)
    k = f"{spec.sigma_level:g}σ"
    span = float(budget.system.times[-1])
    unit_name, per = time_unit(span)
    items = list(spec.items)
    width = 10.0
    panel = 2.3
    heading = wrap_to_width(title, 10, width - 0.4)
    top = 0.12 + text_height(heading, 10) + 0.15 + text_height("t", 10) + 6 / 72
    bottom = 0.12 + 7 / 72 + 2 * text_height("0", 9) + 0.1
    gap = 0.25 + text_height("t", 10) + 6 / 72   # room for the next panel's title
    height = top + bottom + panel * len(items) + gap * (len(items) - 1)
    fig, axes = plt.subplots(len(items), 1, figsize=(width, height), squeeze=False)
    axes = axes[:, 0]
    colours = plt.get_cmap("tab10")
    labels = []
    for ax, item in zip(axes, items, strict=True):
        shown = written_unit(item)
        level = "CEP" if item.combine == "cep" else k   # a CEP has no σ level
        scale = 1.0 / parse_quantity(f"1 {shown}", item.kind.unit, "unit")
        mine = [c for c in curves if c.item == item.name]
        limit = item.value * scale
        drawn = [limit]
        worst = None
        for n, curve in enumerate(mine):
            colour = colours(n % 10)
            name = curve.component or f"{item.name}"
            ax.plot(curve.times / per, curve.values * scale, color=colour, lw=1.4,
                    label=f"{name} ({level})")
            ax.plot(curve.check_times / per, curve.check_values * scale, "o",
                    ms=_check_marker_size(len(curve.check_times)),
                    color=colour, label=f"check times ({len(curve.check_times)})"
                    if n == 0 else None, zorder=3, clip_on=False)
            drawn += list(curve.values * scale)
            between = above_between_checks(curve)
            if between is not None:   # met at the checks only: say where it is not
                t, value = between
                ax.plot([t / per], [value * scale], "x", ms=8, mew=2, color="crimson",
                        zorder=4, label=f"above the limit between checks: "
                                        f"{value * scale:.4g} {shown} at {format_time(t)}")
            i = int(np.argmax(curve.check_values))
            if worst is None or curve.check_values[i] > worst[1]:
                worst = (curve.check_times[i], curve.check_values[i], curve.component)
        ax.axhline(limit, color="crimson", ls="--", lw=1.2,
                   label=f"limit {display(item.value, item.kind.unit, shown)} ({level})")
        if worst is not None:
            t, value, component = worst
            where = f" ({component})" if component else ""
            ax.plot([t / per], [value * scale], "o", ms=8, mfc="none", mec="k", mew=1.2,
                    zorder=4, clip_on=False,
                    label=f"worst check{where}: {value * scale:.4g} {shown} at "
                          f"{format_time(t)}, {value / item.value:.3g} of the limit")
        positive = np.array(drawn)[np.array(drawn) > 0]
        if positive.size and positive.max() > 10**LOG_DECADES * positive.min():
            ax.set_yscale("log")
            # plain numbers at 1, 2 and 5 of every decade (not 2×10¹, nor one label a
            # decade, which a span of two decades would leave with one or two labels)
            ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
            ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            ax.yaxis.set_minor_formatter(NullFormatter())
        else:
            ax.set_ylim(0, max(positive.max() if positive.size else 1.0, limit) * 1.12)
        rate = " (a rate: the error / t)" if item.name in RATE_ITEMS else ""
        ax.set_title(f"{item.name}{rate}", fontsize=10, loc="left")
        ax.set_ylabel(shown)
        ax.set_xlim(0, span / per)
        ax.xaxis.set_major_locator(MaxNLocator(steps=[1, 2, 5, 10]))  # 5 min, not 2.5
        ax.grid(True, alpha=0.3)
        ax.grid(True, which="minor", alpha=0.1)
        legend = ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                           borderaxespad=0.0, frameon=False)
        labels += [text.get_text() for text in legend.get_texts()]
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    axes[-1].set_xlabel(f"time since the start, {unit_name}")
    fig.suptitle(heading, fontsize=10, y=1 - 0.1 / height, va="top")
    left = 0.15 + text_height("m", 10) + 4 / 72 + text_width(["0.0001"], 10) + 7 / 72
    right = 0.2 + text_width(labels, 7) + 0.6   # the legends, beside the panels
    fixed_margins(fig, left=left, right=right, bottom=bottom, top=top, hspace=gap)
    save_figure(fig, path, dpi=110)
