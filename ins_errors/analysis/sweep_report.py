"""What a sweep store says: its points' labels, worst ratios, failures, tables and plots.

Read-only views of a sweep's dataset (as :func:`~ins_errors.analysis.sweep.run_sweep`
or :func:`~ins_errors.analysis.sweep.merge_shards` return it, or as read back from its
store), and the checks of a requested figure made before any point runs.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ins_errors.analysis.store import failure_reasons
from ins_errors.analysis.sweep import (
    FIGURES,
    Parameter,
    SweepError,
    SweepSpec,
    number_text,
)
from ins_errors.errors import unknown_name
from ins_errors.figure_layout import text_width, wrap_to_width


def swept_names(dataset) -> list[str]:
    """Per-point coordinates that label the grid: the parameters in file order, then
    ``case`` and ``draw``."""
    return list(json.loads(dataset.attrs.get("swept", "[]")))


def model_parameters(dataset) -> dict[str, dict[str, object]]:
    """The model parameters the sweep set (its scenario's ``[parameters]``), as stored.

    Returns
    -------
    dict of str to dict
        Name -> ``{"value": SI value, "unit": SI unit}``, as
        :func:`ins_errors.model_parameters.parameters_record` gives it; empty when none
        was set (also for a store written before the record existed, whose fingerprint
        then says none was set).
    """
    return json.loads(dataset.attrs.get("parameters", "{}"))


def point_label(dataset, k: int) -> str:
    """Point ``k``'s swept values as the scenario wrote them, e.g.
    ``latitude = 70 deg, case 2, draw 5``."""
    parts = []
    for name in swept_names(dataset):
        value = dataset[name].values[k]
        if name == "case":
            parts.append(f"case {int(value) + 1}")
        elif name == "draw":
            parts.append(f"draw {int(value)}")
        else:
            attrs = dataset[name].attrs
            parameter = Parameter(name, "", attrs.get("units", "1"), (),
                                  attrs.get("display_unit", attrs.get("units", "1")))
            parts.append(f"{name} = {parameter.text(float(value))}")
    return ", ".join(parts)


def failures(dataset) -> list[dict]:
    """The points that failed: index, swept values (SI, as :func:`summary`), their label
    as written (``"label"``) and the one-line reason (``"reason"``), in point order."""
    rows = []
    numbers = point_numbers(dataset)
    for k, reason in enumerate(failure_reasons(dataset)):
        if not reason:
            continue
        row: dict[str, Any] = {"point": numbers[k]}
        for name in swept_names(dataset):
            value = dataset[name].values[k]
            row[name] = int(value) if name in ("case", "draw") else float(value)
        row["label"] = point_label(dataset, k)
        row["reason"] = reason
        rows.append(row)
    return rows


def failures_text(dataset, limit: int = 10) -> str:
    """One line per failed point (the first ``limit``, then how many more), or empty
    text when none failed."""
    rows = failures(dataset)
    if not rows:
        return ""
    from ins_errors.output import failure_list

    points = dataset.sizes["point"]
    return failure_list(f"{len(rows)} of {points} point{'s' if points != 1 else ''} failed "
                        "(stored without results; --retry-failed runs them again):",
                        [f"point {r['point']} ({r['label'] or 'the point'}): {r['reason']}"
                         for r in rows], limit)


def judged_quantities(dataset) -> list[str] | None:
    """The quantities a sweep's worst ratios judge (its scenario's ``[outputs]
    quantities``), or None: every quantity (also for a store made before the list was
    recorded)."""
    text = dataset.attrs.get("judged_quantities")
    try:
        judged = json.loads(text) if isinstance(text, str) else None
    except ValueError:
        return None
    return [str(q) for q in judged] if isinstance(judged, list) else None


def _judged(dataset) -> np.ndarray:
    """Per point and quantity: 1 where the quantity is excited and judged, shape (P, Q)."""
    excited = dataset["excited"].values == 1
    judged = judged_quantities(dataset)
    if judged is None:
        return excited
    names = [str(q) for q in dataset["quantity"].values]
    return excited & np.array([q in judged for q in names])


def point_numbers(dataset) -> list[int]:
    """Each point's number in the whole sweep (of a shard's points too), shape (P,)."""
    if "point" in dataset.coords:
        return [int(k) for k in dataset["point"].values]
    return list(range(dataset.sizes["point"]))


def _worst(dataset, curve: str) -> tuple[np.ndarray, list[str | None]]:
    """Per point: the largest ratio of a curve to the direct run over the judged,
    excited quantities (NaN when none is), and that quantity's name."""
    ratio = np.where(_judged(dataset), dataset[f"{curve}_ratio"].values, -np.inf)
    k = np.argmax(ratio, axis=1)
    best = ratio[np.arange(len(k)), k]
    names = [str(dataset["quantity"].values[j]) if np.isfinite(b) else None
             for j, b in zip(k, best, strict=True)]
    return np.where(np.isfinite(best), best, np.nan), names


def worst_integration_ratio(dataset) -> np.ndarray:
    """Per point: worst over the judged, excited quantities of integration error /
    max |direct| (NaN where nothing is excited), shape (P,)."""
    excited = _judged(dataset)
    peak = dataset["max_direct"].values
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(excited & (peak > 0), dataset["integration_error"].values / peak,
                         -np.inf)
    best = np.max(ratio, axis=1) if ratio.size else np.full(len(ratio), -np.inf)
    return np.where(np.isfinite(best), best, np.nan)


def summary(dataset) -> list[dict]:
    """Per grid point: its labels, its failure reason (``None`` unless it failed; its
    numbers are then ``None``), worst linear (refined) ratio and max errors, SI."""
    rows = []
    labels = swept_names(dataset)
    quantities = [str(q) for q in dataset["quantity"].values]
    worst_linear, linear_names = _worst(dataset, "linear")
    integration = worst_integration_ratio(dataset)
    refined = "refined_ratio" in dataset
    if refined:
        worst_refined, refined_names = _worst(dataset, "refined")
    reasons = failure_reasons(dataset)
    numbers = point_numbers(dataset)
    for k in range(dataset.sizes["point"]):
        row: dict[str, Any] = {"point": numbers[k]}
        for name in labels:
            value = dataset[name].values[k]
            row[name] = int(value) if name in ("case", "draw") else float(value)
        row["failure"] = reasons[k] or None
        row["worst_linear_ratio"] = _number(worst_linear[k])
        row["worst_linear_quantity"] = linear_names[k]
        if refined:
            row["worst_refined_ratio"] = _number(worst_refined[k])
            row["worst_refined_quantity"] = refined_names[k]
        row["max_direct"] = {q: _number(v) for q, v in
                             zip(quantities, dataset["max_direct"].values[k], strict=True)}
        row["linear_ratio"] = {q: _number(v) for q, v in
                               zip(quantities, dataset["linear_ratio"].values[k], strict=True)}
        row["integration_error"] = {q: _number(v) for q, v in zip(
            quantities, dataset["integration_error"].values[k], strict=True)}
        row["worst_integration_error_ratio"] = _number(integration[k])
        rows.append(row)
    return rows


def over_draws(dataset) -> list[dict]:
    """Monte Carlo statistics per grid point: over its draws, the RMS and the largest of
    each quantity's max |direct error| (SI) and the largest worst linear/direct ratio.

    Empty when the sweep has no draws. A draw that failed is not left out: the statistics
    of its grid point are ``None`` (unknown) and ``failed_draws`` counts and names it.
    """
    labels = [n for n in swept_names(dataset) if n != "draw"]
    if "draw" not in swept_names(dataset):
        return []
    quantities = [str(q) for q in dataset["quantity"].values]
    peaks = dataset["max_direct"].values
    worst = _worst(dataset, "linear")[0]
    reasons = failure_reasons(dataset)
    draw = dataset["draw"].values
    groups: dict[tuple, list[int]] = {}
    for k in range(dataset.sizes["point"]):
        key = tuple(float(dataset[n].values[k]) for n in labels)
        groups.setdefault(key, []).append(k)
    rows = []
    for key, members in groups.items():
        block = peaks[members]
        row: dict[str, Any] = dict(zip(labels, key, strict=True))
        row["draws"] = len(members)
        row["failed_draws"] = [int(draw[k]) for k in members if reasons[k]]
        row["rms_max_direct"] = {q: _number(v) for q, v in
                                 zip(quantities, np.sqrt(np.mean(block**2, axis=0)),
                                     strict=True)}
        row["largest_max_direct"] = {q: _number(v) for q, v in
                                     zip(quantities, np.max(block, axis=0), strict=True)}
        row["largest_worst_linear_ratio"] = (
            None if row["failed_draws"] else _number(np.nanmax(worst[members])))
        rows.append(row)
    return rows


def _number(value: float) -> float | None:
    value = float(value)
    return value if np.isfinite(value) else None


def table(dataset, quantities: Sequence[str] | None = None, limit: int = 40) -> str:
    """Plain-text table: one row per grid point (at most ``limit``)."""
    labels = swept_names(dataset)
    all_quantities = [str(q) for q in dataset["quantity"].values]
    if quantities is None:
        excited = dataset["excited"].values.any(axis=0)
        quantities = [q for q, e in zip(all_quantities, excited, strict=True)
                      if e and q.startswith("delta_")][:3]
    from ins_errors.units import display_scale

    scales = {q: display_scale(str(u)) for q, u in
              zip(all_quantities, dataset["quantity_unit"].values, strict=True)}
    shown = {}
    for name in labels:
        unit = dataset[name].attrs.get("display_unit", "")
        shown[name] = f"{name} [{unit}]" if unit and unit != "1" else name
    head = [*shown.values(), "worst linear ratio", "quantity", "integ. err/err",
            *(f"max {q} [{scales[q][1]}]" for q in quantities)]
    rows = []
    worst, names = _worst(dataset, "linear")
    integration = worst_integration_ratio(dataset)
    reasons = failure_reasons(dataset)
    for k in range(min(dataset.sizes["point"], limit)):
        cells = []
        for name in labels:
            value = float(dataset[name].values[k])
            attrs = dataset[name].attrs
            unit, display = attrs.get("units", "1"), attrs.get("display_unit", "1")
            cells.append(number_text(Parameter(name, "", unit, (), display).shown(value)))
        if reasons[k]:
            rows.append([*cells, "failed", *(["–"] * (len(head) - len(cells) - 1))])
            continue
        cells += [f"{worst[k]:.3e}" if np.isfinite(worst[k]) else "–", names[k] or "–",
                  f"{integration[k]:.1e}" if np.isfinite(integration[k]) else "–"]
        for q in quantities:
            value = dataset["max_direct"].values[k, all_quantities.index(q)]
            cells.append(f"{value * scales[q][0]:.4g}")
        rows.append(cells)
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h)
              for i, h in enumerate(head)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    if dataset.sizes["point"] > limit:
        lines.append(f"... {dataset.sizes['point'] - limit} more points (--json for all)")
    lines.append(TABLE_KEY)
    return "\n".join(lines)


LINEAR_RATIO = "max|linear − direct| / max|direct|"
"""What a linear ratio is (``linear_ratio`` of the store and of ``compare``): the largest
difference of the linear run from the direct run over the largest direct error of one
quantity (not linear ÷ direct, which is near 1 where the linear model is good)."""

TABLE_KEY = (f"worst linear ratio: {LINEAR_RATIO} of the quantity named (the largest over "
             "the judged quantities)\ninteg. err/err: the estimated integration error over "
             "max|direct| (the largest over the judged quantities)")
"""The lines under :func:`table` that say what its ratio columns are."""


def draws_table(dataset, quantities: Sequence[str] | None = None) -> str:
    """Plain-text table of :func:`over_draws` (empty text without draws)."""
    from ins_errors.units import display_scale

    rows = over_draws(dataset)
    if not rows:
        return ""
    names = [str(q) for q in dataset["quantity"].values]
    units = dict(zip(names, (str(u) for u in dataset["quantity_unit"].values), strict=True))
    if quantities is None:
        quantities = [q for q in names if q.startswith("delta_")
                      and any(r["largest_max_direct"][q] for r in rows)][:3]
    labels = [n for n in swept_names(dataset) if n != "draw"]
    shown = []
    for name in labels:
        unit = dataset[name].attrs.get("display_unit", "1")
        shown.append(f"{name} [{unit}]" if unit != "1" else name)
    any_failed = any(row["failed_draws"] for row in rows)
    head = [*shown, "draws", *(["failed"] if any_failed else []),
            "largest worst linear ratio",
            *(f"RMS max {q} [{display_scale(units[q])[1]}]" for q in quantities)]
    body = []
    for row in rows:
        cells = []
        for name in labels:
            attrs = dataset[name].attrs
            parameter = Parameter(name, "", attrs.get("units", "1"), (),
                                  attrs.get("display_unit", "1"))
            cells.append(number_text(parameter.shown(row[name])))
        ratio = row["largest_worst_linear_ratio"]
        cells += [str(row["draws"]), *([str(len(row["failed_draws"]))] if any_failed else []),
                  "–" if ratio is None else f"{ratio:.3e}"]
        for q in quantities:
            value = row["rms_max_direct"][q]
            cells.append("–" if value is None else f"{value * display_scale(units[q])[0]:.4g}")
        body.append(cells)
    widths = [max(len(h), *(len(r[i]) for r in body)) for i, h in enumerate(head)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in body]
    return "\n".join(lines)


def check_figure(figure: str, quantities: Sequence[str], refined: bool) -> None:
    """Refuse a figure name (:data:`FIGURES`) a sweep cannot plot.

    Parameters
    ----------
    figure : str
    quantities : sequence of str
        The sweep's error quantities.
    refined : bool
        Whether it runs the refined model.

    Raises
    ------
    SweepError, UnknownNameError
        One line naming the figure and the problem.
    """
    kind, _, quantity = figure.partition(":")
    if figure not in ("worst_linear_ratio", "worst_refined_ratio") and (
            kind not in ("max_direct", "linear_ratio", "refined_ratio") or not quantity):
        raise unknown_name("figure", figure, FIGURES)
    if "refined" in kind and not refined:
        raise SweepError(f"figure {figure!r}: the sweep runs without the refined model "
                         "([run] refined = false)")
    if quantity and quantity not in quantities:
        raise unknown_name("error quantity", quantity, quantities)


def check_against(against: Sequence[str], swept: Sequence[str]) -> list[str]:
    """The swept parameters a plot is drawn against (one or two of ``swept``).

    Raises
    ------
    SweepError, UnknownNameError
    """
    names = [name.strip() for name in against]
    if not 1 <= len(names) <= 2:
        raise SweepError("--against takes one or two swept parameters, e.g. latitude,heading")
    for name in names:
        if name not in swept:
            raise unknown_name("swept parameter", name, swept)
    if len(set(names)) != len(names):
        raise SweepError(f"--against names {names[0]} twice")
    return names


def scenario_swept_names(scenario) -> list[str]:
    """The names that will label a scenario's sweep points (as :func:`swept_names` reads
    them from its store): the parameters in file order, then ``case`` and ``draw``."""
    spec: SweepSpec = scenario.sweep
    return ([p.name for p in spec.parameters]
            + (["case"] if len(scenario.cases) > 1 else [])
            + (["draw"] if spec.draws else []))


def figure_values(dataset, figure: str) -> tuple[np.ndarray, str]:
    """Per-point values of a figure (see :data:`FIGURES`) and its axis label (errors in
    the display units of :data:`ins_errors.units.DISPLAY_UNITS`)."""
    names = [str(q) for q in dataset["quantity"].values]
    check_figure(figure, names, "refined_ratio" in dataset)
    if figure in ("worst_linear_ratio", "worst_refined_ratio"):
        curve = figure.split("_")[1]
        return _worst(dataset, curve)[0], f"worst {curve} ratio\n{_ratio_words(curve)}"
    kind, _, quantity = figure.partition(":")
    from ins_errors.units import display_scale

    j = names.index(quantity)
    scale, unit = (display_scale(str(dataset["quantity_unit"].values[j]))
                   if kind == "max_direct" else (1.0, "1"))
    values = dataset[kind].values[:, j] * scale
    if kind == "max_direct":
        return values, f"max |{quantity}| [{unit}]"
    curve = kind.split("_")[0]
    return values, f"{quantity} {curve} ratio\n{_ratio_words(curve)}"


def _ratio_words(curve: str) -> str:
    """What the ratio of a curve (``"linear"``, ``"refined"``) to the direct run is:
    :data:`LINEAR_RATIO`, or the same of the refined run."""
    return LINEAR_RATIO.replace("linear", curve)


BAR_WIDTH, BAR_PAD = 0.18, 0.25
"""Width of the colour bar of :func:`plot` and its gap from the panel, inches."""


def _tick_labels(axis) -> tuple[list[str], str]:
    """The tick labels an axis will draw at its current limits, and its offset text
    (from its locator and formatter, without drawing)."""
    low, high = sorted(axis.get_view_interval())
    span = (high - low) * 1e-9
    locs = [v for v in axis.get_majorticklocs() if low - span <= v <= high + span]
    formatter = axis.get_major_formatter()
    return formatter.format_ticks(locs), formatter.get_offset()


def _fixed_margins(figure_, ax, bar, heading: str) -> None:
    """Place the panel (and colour bar) with margins that fit its labels and title.

    Sizes in inches: tick labels measured at their formatted values, a line of text
    1.2 × its size high. Replaces ``tight_layout``, which draws the figure once more
    only to measure it.
    """
    width, height = figure_.get_size_inches()
    size = 10 / 72  # the default font size, inches
    ticks = 7 / 72  # tick length + pad
    # the axis labels' lines (a ratio's label says what it is on a second line)
    ylines = ax.get_ylabel().count("\n") + 1
    blines = bar.ax.get_ylabel().count("\n") + 1 if bar is not None else 0
    for _ in range(2):  # the tick labels chosen for the panel's first size, then its own
        ylabels, yoffset = _tick_labels(ax.yaxis)
        xlabels, xoffset = _tick_labels(ax.xaxis)
        blabels, boffset = _tick_labels(bar.ax.yaxis) if bar is not None else ([], "")
        left = 0.12 + 1.2 * size * ylines + 4 / 72 + text_width(ylabels, 10) + ticks
        bottom = 0.12 + 1.2 * size * 2 + 4 / 72 + ticks + (1.2 * size if xoffset else 0.0)
        right = 0.15 + text_width(xlabels[-1:], 10) / 2
        if bar is not None:  # the bar, its tick labels and its label right of the panel
            labels = 0.12 + 1.2 * size * blines + 4 / 72 + text_width(blabels, 10) + ticks
            right = max(right, labels + BAR_WIDTH + BAR_PAD)
        title = wrap_to_width(heading, 10, width - left - right)  # (over the panel only)
        ax.set_title(title, fontsize=10)
        top = 0.12 + 1.2 * size * (title.count("\n") + 1) + 6 / 72 + (
            1.2 * size + 0.05 if yoffset or boffset else 0.0)
        if bar is not None:
            bar.ax.set_position(((width - right + BAR_PAD) / width, bottom / height,
                                 BAR_WIDTH / width, (height - top - bottom) / height))
        ax.set_position((left / width, bottom / height, (width - left - right) / width,
                         (height - top - bottom) / height))


MAX_GRID_TICKS = 12
"""A colour map's axis with at most this many grid values has a tick at each of them."""


def cell_edges(values: Sequence[float]) -> np.ndarray:
    """Cell edges of a colour map over sorted grid values: each value inside its cell.

    Inner edges lie halfway between neighbouring values; the outer cells reach as far
    beyond the first and last values as their halfway edges lie inside, so the first and
    last values sit in the middle of their cells (an evenly spaced grid: every value),
    under their ticks (with edges at the first and last values, a 2 x 2 map drew each
    value at a corner of its cell). A single
    value gets a cell of ±5 % of its size (±0.5 at 0).

    Parameters
    ----------
    values : sequence of float, shape (n,)
        Increasing grid values, in the axis's unit.

    Returns
    -------
    numpy.ndarray, shape (n + 1,)
    """
    v = np.asarray(values, dtype=float)
    if v.size == 1:
        half = 0.05 * abs(v[0]) or 0.5
        return np.array([v[0] - half, v[0] + half])
    inner = (v[1:] + v[:-1]) / 2
    return np.concatenate([[2 * v[0] - inner[0]], inner, [2 * v[-1] - inner[-1]]])


def plot(dataset, figure: str, against: Sequence[str], path: str | Path) -> Path | None:
    """Plot a figure against one (line) or two (colour map) swept parameters.

    Points that differ in the other swept labels are reduced to their maximum (the worst
    case over them), which the title says. A colour map has one cell around each grid
    value (:func:`cell_edges`); dots mark the grid points.

    Returns
    -------
    pathlib.Path or None
        The file written; None, and no file, when no point has a value of the figure
        (every point failed, see :func:`nothing_to_plot`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = swept_names(dataset)
    against = check_against(against, labels)
    values, title = figure_values(dataset, figure)
    axes = []
    for name in against:
        attrs = dataset[name].attrs
        parameter = Parameter(name, "", attrs.get("units", "1"), (),
                              attrs.get("display_unit", attrs.get("units", "1")))
        shown = np.array([parameter.shown(v) for v in dataset[name].values])
        axes.append((name, parameter.display_unit, shown))
    others = [n for n in labels if n not in against]
    keys = [tuple(a[2][k] for a in axes) for k in range(len(values))]
    reduced: dict[tuple, float] = {}
    for key, value in zip(keys, values, strict=True):
        if np.isfinite(value):
            reduced[key] = max(reduced.get(key, -np.inf), float(value))
    if not reduced:  # (was an IndexError of cell_edges, the table never printed)
        return None
    figure_, ax = plt.subplots(figsize=(7.0, 4.5))
    bar = None
    if len(axes) == 1:
        xs = sorted(reduced)
        ax.plot([x[0] for x in xs], [reduced[x] for x in xs], "o-")
        ax.set_xlabel(f"{axes[0][0]} [{axes[0][1]}]")
        ax.set_ylabel(title)
    else:
        xs = sorted({k[0] for k in reduced})
        ys = sorted({k[1] for k in reduced})
        grid_ = np.full((len(ys), len(xs)), np.nan)
        for (x, y), v in reduced.items():
            grid_[ys.index(y), xs.index(x)] = v
        # each value inside its cell; ticks (when few) and dots mark the values run
        mesh = ax.pcolormesh(cell_edges(xs), cell_edges(ys), grid_, shading="flat")
        ax.plot([x for x, _ in reduced], [y for _, y in reduced], "k.", markersize=4,
                clip_on=False, zorder=3)  # the edge points drawn whole
        for values_, axis in ((xs, ax.xaxis), (ys, ax.yaxis)):
            if len(values_) <= MAX_GRID_TICKS:
                axis.set_ticks(values_)
        # on an axes of its own, placed by _fixed_margins
        bar = figure_.colorbar(mesh, cax=figure_.add_axes((0.9, 0.1, 0.02, 0.8)),
                               label=title)
        ax.set_xlabel(f"{axes[0][0]} [{axes[0][1]}]")
        ax.set_ylabel(f"{axes[1][0]} [{axes[1][1]}]")
    heading = dataset.attrs.get("title", "sweep")
    if others:
        heading += f"\n(max over {', '.join(others)})"
    ax.grid(True, alpha=0.3)
    _fixed_margins(figure_, ax, bar, heading)
    from ins_errors.output import save_figure

    return save_figure(figure_, path, dpi=120)  # atomic, parent folders created


def nothing_to_plot(dataset, figure: str, path: str | Path) -> str:
    """The one line saying why :func:`plot` wrote nothing: no point has a value of
    ``figure`` (every point failed, or the figure is undefined at each)."""
    points = dataset.sizes["point"]
    why = ("every point failed" if len(failures(dataset)) == points
           else f"{figure} is undefined at each point run")
    return f"nothing to plot, {path} not written: {why}"
