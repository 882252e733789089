"""Overlaid direct / linear / refined error curves (matplotlib, Agg backend).

Angles are drawn in arc minutes, angular rates in deg/h, velocities in m/s, time in
hours; the conversion goes through the units library.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ins_errors.numeric.compare import Comparison
from ins_errors.output import save_figure

DISPLAY_UNITS: dict[str, str] = {"rad": "arcmin", "rad/s": "deg/h", "m/s": "m/s", "m": "m",
                                 "1": "1"}
"""Unit each SI unit is plotted in."""


def _scale(unit: str) -> tuple[float, str]:
    from ins_errors.units import parse_quantity

    shown = DISPLAY_UNITS.get(unit, unit)
    if shown == unit:
        return 1.0, unit
    return 1.0 / parse_quantity(f"1 {shown}", unit), shown


def plot_comparison(comparison: Comparison, path: str | Path,
                    quantities: Sequence[str] | None = None, title: str = "") -> Path:
    """Save a grid of plots, one per quantity, with the three curves overlaid.

    Parameters
    ----------
    comparison : Comparison
        One compared case.
    path : str or Path
        Output file (``.png``, ``.pdf``, ``.svg``: whatever matplotlib writes).
    quantities : sequence of str, optional
        Quantities to draw (default: every excited quantity, else all).
    title : str
        Figure title (default: the case label).

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    InsErrorsError
        If the file cannot be written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if quantities is None:
        quantities = [m.quantity for m in comparison.excited] or [
            m.quantity for m in comparison.metrics]
    for q in quantities:
        comparison.metric(q)  # raises a one-line error for unknown names
    n = len(quantities)
    cols = 2 if n > 1 else 1
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.0 * cols, 2.6 * rows), squeeze=False,
                             sharex=True)
    hours = comparison.times / 3600.0
    for ax, q in zip(axes.flat, quantities, strict=False):
        scale, unit = _scale(comparison.metric(q).unit)
        ax.plot(hours, comparison.direct[q] * scale, color="black", lw=1.6, label="direct")
        ax.plot(hours, comparison.linear[q] * scale, color="tab:orange", lw=1.0, ls="--",
                label="linear")
        if comparison.refined:
            ax.plot(hours, comparison.refined[q] * scale, color="tab:blue", lw=1.0, ls=":",
                    label="refined")
        ax.set_ylabel(f"{q} [{unit}]", fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.tick_params(labelsize=7)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("time [h]", fontsize=8)
    axes.flat[0].legend(fontsize=7, loc="best")
    fig.suptitle(title or comparison.label, fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=110)

