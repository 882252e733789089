"""Reports of an error budget: JSON summary, text tables and stacked plots.

The numbers come from :mod:`ins_errors.analysis.budget`; this module only presents them
(plots with matplotlib's Agg backend).
"""

from __future__ import annotations

import numpy as np

from ins_errors.analysis.budget import (
    HOUR,
    ITEM_DISPLAY,
    ITEM_SI,
    Allocation,
    display,
    format_time,
)
from ins_errors.output import require_matplotlib, save_figure


def report(allocation: Allocation) -> dict:
    """A JSON-ready summary: rule, sources with magnitudes and binding rows, spec rows."""
    budget = allocation.budget
    spec = budget.spec
    contributions = allocation.contributions()
    allowed = budget.allowed_variances
    values = spec.sigma_level * np.sqrt(contributions.sum(1))
    sources = []
    for j, s in enumerate(budget.sources):
        row = allocation.binding_row(j)
        magnitude = allocation.magnitudes[j]
        sources.append({
            "name": s.name,
            "statistics": s.statistics,
            "magnitude": None if not np.isfinite(magnitude) else float(magnitude),
            "unit": s.unit,
            "display": display(magnitude, s.unit, s.display_unit),
            "fixed": s.fixed is not None,
            "weight": s.weight,
            "binding_item": None if row is None else row.item,
            "binding_time_h": None if row is None else row.time / HOUR,
            "binding_component": None if row is None else row.component,
            "share_at_binding": None if row is None else float(
                contributions[allocation.binding[j], j] / allowed[allocation.binding[j]]),
        })
    rows = [{"item": r.item, "time_h": r.time / HOUR, "component": r.component,
             "limit": r.limit, "value": float(v), "ratio": float(v / r.limit),
             "display": f"{display(v, ITEM_SI[r.item], ITEM_DISPLAY[r.item])} of "
                        f"{display(r.limit, ITEM_SI[r.item], ITEM_DISPLAY[r.item])}"}
            for r, v in zip(budget.rows, values, strict=True)]
    return {
        "spec": spec.title, "sigma_level": spec.sigma_level,
        "motion": budget.system.labels.get("trajectory", ""),
        "rule": ("equal share of each item's variance per free source (weighted), fixed "
                 "sources first" + (f"; then scaled by {allocation.fill_factor:.6g} in "
                                    "variance (fill)" if spec.fill else "")),
        "sources": sources, "rows": rows,
    }


def table(allocation: Allocation) -> str:
    """Plain-text report: allocated magnitudes, binding items, worst row of each item."""
    data = report(allocation)
    spec = allocation.budget.spec
    k = f"{spec.sigma_level:g}σ"
    lines = [f"Error budget: {data['spec']} ({k}), {data['motion']}",
             f"Rule: {data['rule']}.", "",
             f"{'source':<36} {'allowed (' + k + ')':>22}  binding item",
             "-" * 86]
    for s in data["sources"]:
        if s["binding_item"] is None:
            bind = "fixed" if s["fixed"] else "not limited on this motion"
        else:
            comp = f" [{s['binding_component']}]" if s["binding_component"] else ""
            bind = f"{s['binding_item']}{comp} at {format_time(s['binding_time_h'] * HOUR)}"
        lines.append(f"{s['name']:<36} {s['display']:>22}  {bind}")
    lines += ["", f"Spec rows at the allocated magnitudes (worst time of each item, {k}):",
              f"{'item':<22} {'time':>10}  {'value of limit':<34} {'ratio':>6}", "-" * 78]
    for item in spec.items:
        rows = [r for r in data["rows"] if r["item"] == item.name]
        worst = max(rows, key=lambda r: r["ratio"])
        lines.append(f"{item.name:<22} {format_time(worst['time_h'] * HOUR):>10}  "
                     f"{worst['display']:<34} "
                     f"{worst['ratio']:>6.3f}")
    return "\n".join(lines)


def contribution_table(allocation: Allocation, top: int = 10) -> str:
    """Percent of each item's allowed variance used by each source (worst time)."""
    budget = allocation.budget
    contributions = allocation.contributions() / budget.allowed_variances[:, None]
    items = budget.spec.items
    worst = []
    for item in items:
        idx = [i for i, r in enumerate(budget.rows) if r.item == item.name]
        worst.append(idx[int(np.argmax(contributions[idx].sum(1)))])
    header = f"{'source':<36}" + "".join(f"{it.name[:16]:>17}" for it in items)
    lines = ["Share of each item's allowed variance (%), at its worst time:", header,
             "-" * len(header)]
    order = np.argsort(-contributions[worst].max(0))
    for j in order[:top]:
        lines.append(f"{budget.sources[j].name:<36}" + "".join(
            f"{100 * contributions[r, j]:>17.2f}" for r in worst))
    if len(order) > top:
        rest = order[top:]
        lines.append(f"{'(' + str(len(rest)) + ' others)':<36}" + "".join(
            f"{100 * contributions[r, rest].sum():>17.2f}" for r in worst))
    lines.append(f"{'total':<36}" + "".join(f"{100 * contributions[r].sum():>17.2f}"
                                            for r in worst))
    return "\n".join(lines)


def plot(allocation: Allocation, path: str, top: int = 14) -> None:
    """Stacked bars: share of each item's allowed variance per source at each check time.

    Parameters
    ----------
    allocation : Allocation
    path : str
        Image file to write (format from the suffix, e.g. ``budget.png``).
    top : int
        Sources shown individually (the rest are summed as "others").
    """
    require_matplotlib()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    budget = allocation.budget
    shares = allocation.contributions() / budget.allowed_variances[:, None]
    order = np.argsort(-shares.max(0))
    shown, rest = order[:top], order[top:]
    items = budget.spec.items
    fig, axes = plt.subplots(1, len(items), figsize=(4.2 * len(items), 4.6), squeeze=False)
    colours = plt.get_cmap("tab20")
    for ax, item in zip(axes[0], items, strict=True):
        idx = [i for i, r in enumerate(budget.rows) if r.item == item.name]
        labels = [f"{budget.rows[i].time / HOUR:g}" + (f"\n{budget.rows[i].component}"
                                                       if budget.rows[i].component else "")
                  for i in idx]
        x = np.arange(len(idx))
        bottom = np.zeros(len(idx))
        for c, j in enumerate(shown):
            ax.bar(x, shares[idx, j], bottom=bottom, color=colours(c % 20),
                   label=budget.sources[j].name)
            bottom += shares[idx, j]
        if rest.size:
            ax.bar(x, shares[idx][:, rest].sum(1), bottom=bottom, color="0.75", label="others")
        ax.axhline(1.0, color="k", lw=1, ls="--")
        every = max(1, len(idx) // 9)
        ax.set_xticks(x[::every], labels[::every], fontsize=8)
        ax.set_xlabel("check time, h")
        ax.set_title(f"{item.name}\n≤ {item.text} ({budget.spec.sigma_level:g}σ)", fontsize=10)
        ax.set_ylim(0, 1.1)
    axes[0][0].set_ylabel("share of allowed variance")
    handles, names = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=min(5, len(names)), fontsize=8)
    fig.suptitle(f"Error budget: {budget.spec.title}", fontsize=11)
    fig.tight_layout(rect=(0, 0.12, 1, 0.95))
    save_figure(fig, path, dpi=120)


def output_table(data: dict, top: int = 10) -> str:
    """Text table of :func:`output_contributions` (1σ per source, largest first)."""
    lines = []
    for it, t in enumerate(data["times_h"]):
        std = data["std"][it]
        header = f"{'source (1σ)':<34}" + "".join(
            f"{(q.replace('delta_', 'Δ') + ' ' + u)[:15]:>16}"
            for q, u in zip(data["quantities"], data["units"], strict=True))
        lines += [f"Contributions to the navigation errors at {t:g} h:", header,
                  "-" * len(header)]
        order = np.argsort(-(std[:, :-1] / np.maximum(std[:, -1:], 1e-300)).max(0))
        for j in order[:top]:
            lines.append(f"{data['sources'][j]:<34}" + "".join(f"{v:>16.4g}"
                                                               for v in std[:, j]))
        lines.append(f"{'total (rss)':<34}" + "".join(f"{v:>16.4g}" for v in std[:, -1]))
        lines.append("")
    return "\n".join(lines).rstrip()


def plot_outputs(data: dict, path: str, top: int = 14) -> None:
    """Stacked bars of :func:`output_contributions`: share of each error's variance.

    One panel per chosen time; each bar is one platform angle or output error, split
    into the sources' shares of its variance (the bar's label gives its 1σ total).
    """
    require_matplotlib()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    std = data["std"]                                   # (t, q, s + 1)
    variance = std[..., :-1] ** 2
    shares = variance / np.maximum(variance.sum(-1, keepdims=True), 1e-300)
    order = np.argsort(-shares.max(axis=(0, 1)))
    shown, rest = order[:top], order[top:]
    colours = plt.get_cmap("tab20")
    times = data["times_h"]
    fig, axes = plt.subplots(len(times), 1, figsize=(12, 3.2 * len(times) + 1.2),
                             squeeze=False)
    x = np.arange(len(data["quantities"]))
    for it, (ax, t) in enumerate(zip(axes[:, 0], times, strict=True)):
        bottom = np.zeros(len(x))
        for c, j in enumerate(shown):
            ax.bar(x, shares[it, :, j], bottom=bottom, color=colours(c % 20),
                   label=data["sources"][j])
            bottom += shares[it, :, j]
        if rest.size:
            ax.bar(x, shares[it][:, rest].sum(-1), bottom=bottom, color="0.75",
                   label="others")
        labels = [f"{q.replace('delta_', 'Δ')}\n{v:.3g} {u}" for q, u, v in
                  zip(data["quantities"], data["units"], std[it, :, -1], strict=True)]
        ax.set_xticks(x, labels, fontsize=7)
        ax.set_ylabel("share of variance")
        ax.set_title(f"t = {t:g} h (1σ totals under the bars)", fontsize=10)
        ax.set_ylim(0, 1.0)
    handles, names = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=5, fontsize=8)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    save_figure(fig, path, dpi=120)
