"""Log–log plot of one source's validity sweep (matplotlib, Agg backend)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ins_errors.analysis.validity import SourceValidity
from ins_errors.output import save_figure

_COLOURS = {"static": "tab:blue", "great-circle": "tab:orange", "manoeuvre": "tab:green"}
_MARKERS = {"static": "o", "great-circle": "^", "manoeuvre": "D"}


def plot_validity(results: Sequence[SourceValidity], path: str | Path, title: str = "") -> Path:
    """Relative linear and refined residuals against the source's magnitude.

    A sweep that failed marks the magnitudes without a result with crosses along the top
    of the axes (its legend entry says from which magnitude), and its reason is written
    in the axes; so is the note of a sweep whose source is not excited (no error at any
    magnitude, e.g. through a damping gain at 0). The 1 % and 10 % magnitudes are
    triangles, hollow where read off the fitted line outside the sweep, and left out
    for an angle past half a turn (a size no angle error has).

    Parameters
    ----------
    results : sequence of SourceValidity
        The sweeps of one source (one per motion).
    path : str or Path
        Output file (png, pdf, svg).
    title : str
        Figure title.

    Returns
    -------
    Path
        The written file.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ins_errors.figure_layout import fixed_margins
    from ins_errors.units import format_readable, parse_quantity

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.set_xscale("log")
    ax.set_yscale("log")
    unit = results[0].display_unit if results else ""
    reasons = []
    for r in results:
        scale = 1.0 / parse_quantity(f"1 {r.display_unit}", r.unit)
        colour = _COLOURS.get(r.motion, "black")
        if r.failed:
            # crosses at the top of the axes (x in data, y in axes units)
            failed = np.array(r.failed_magnitudes) * scale
            where = (f"from {format_readable(r.failed_magnitudes[0], r.unit, r.display_unit, 3)}"
                     if r.magnitudes else "no magnitude ran")
            ax.plot(failed, np.full(failed.size, 0.96), ls="none", marker="x", ms=8,
                    mew=1.5, color=colour, transform=ax.get_xaxis_transform(),
                    label=f"{r.motion}: failed, {where}")
            reasons.append(f"{r.motion}: {r.failure.split(';')[0]}")
        if r.status == "not excited":
            reasons.append(f"{r.motion}: {r.note or 'not excited'}")
        if not r.linear_ratio:
            continue
        m = np.array(r.magnitudes) * scale
        lin = np.array(r.linear_ratio)
        ref = np.array(r.refined_ratio)
        marker = _MARKERS.get(r.motion, "o")
        ax.loglog(m[lin > 0], lin[lin > 0], marker=marker, ls="-", color=colour,
                  mfc="none", ms=7, label=f"{r.motion}: linear (slope {_slope(r.linear_slope)})")
        ax.loglog(m[ref > 0], ref[ref > 0], "s--", color=colour, alpha=0.6, ms=4,
                  label=f"{r.motion}: refined (slope {_slope(r.refined_slope)})")
        shown = [(level, getattr(r, key), r.extrapolated.get(key, ""))
                 for level, key in ((0.01, "magnitude_1pct"), (0.1, "magnitude_10pct"))
                 if getattr(r, key) is not None
                 and r.extrapolated.get(key, "") != "past half a turn"]
        open_ = " (open: extrapolated)" if any(how for *_, how in shown) else ""
        for k, (level, value, how) in enumerate(shown):
            ax.plot([value * scale], [level], marker="v", color=colour, ms=8,
                    mfc="none" if how else colour, ls="none",
                    label=f"{r.motion}: 1 %, 10 % magnitudes{open_}" if k == 0 else None)
        for level, key in ((0.01, "magnitude_1pct"), (0.1, "magnitude_10pct")):
            value, how = getattr(r, key), r.extrapolated.get(key, "")
            if value is not None and how == "past half a turn":
                reasons.append(f"{r.motion}: {level:.0%} only past half a turn, at "
                               f"{format_readable(value, r.unit, r.display_unit, 3)} on the "
                               "fitted line (no angle error is that large)")
    if not any(r.linear_ratio for r in results):
        ax.set_ylim(1e-3, 1.0)  # (no residual to show: the 1 % and 10 % lines only)
    if reasons:
        import textwrap

        failing = any(r.failed for r in results)
        ax.text(0.02, 0.04, "\n".join(textwrap.fill(t, 80) for t in reasons),
                transform=ax.transAxes, fontsize=6, va="bottom",
                color="tab:red" if failing else "black",
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})
    for level in (0.01, 0.1):
        ax.axhline(level, color="grey", lw=0.8, ls=":")
        ax.text(ax.get_xlim()[0], level, f" {level:.0%}", va="bottom", fontsize=7,
                color="grey")
    quantity = ", ".join(dict.fromkeys(r.quantity for r in results if r.quantity))
    ax.set_xlabel(f"magnitude [{unit}]")
    if not quantity:
        quantity = ("no magnitude ran" if results and all(r.status == "failed" for r in results)
                    else "not excited: no error" if any(r.status == "not excited"
                                                        for r in results) else "no error")
    ax.set_ylabel(f"|model − direct| / max |direct|  ({quantity})", fontsize=8)
    ax.grid(True, which="both", alpha=0.25)
    if ax.get_legend_handles_labels()[0]:  # (nothing drawn: no legend, no warning)
        ax.legend(fontsize=7, loc="best")
    ax.set_title(title, fontsize=9)
    # fixed margins fit the powers of ten and the labels (tight_layout measured every
    # tick label first: about one more drawing of the figure)
    fixed_margins(fig, left=0.85, right=0.15, bottom=0.6, top=0.34)
    return save_figure(fig, path, dpi=110)


def plot_title(model: str, source: str, hours: float, step: float, motions: Sequence[str],
               parameters: Mapping[str, Mapping[str, object]] | None = None,
               where: str = "") -> str:
    """The title of one source's plot: the model and source, then what the runs were
    (length, step, scheme, motions, the parameters set), so that plots of different
    maps can be told apart: ``"strapdown_ned: gyro_bias_z\n4 h runs, τ = 2 s, RK4;
    static; k_h1 = 0.0293 1/s, k_h2 = 0.000442 1/s^2"``.

    Parameters
    ----------
    model, source : str
        Names.
    hours : float
        Length of each run, h.
    step : float
        Integration step, s.
    motions : sequence of str
        The motions of the source's sweeps.
    parameters : mapping, optional
        The parameters set (:func:`~ins_errors.model_parameters.parameters_record`: name
        -> ``{"value": SI value, "unit": SI unit}``); none: ``model defaults``.
    where : str, optional
        Where the motions start, if not at their defaults (``"φ=30°"``), written after
        them.
    """
    from ins_errors.commands.models import parameter_text
    from ins_errors.units import format_duration

    given = ", ".join(f"{name} = {parameter_text(entry['value'], str(entry['unit']), 3)}"
                      for name, entry in (parameters or {}).items())
    return (f"{model}: {source}\n{format_duration(3600.0 * hours)} runs, τ = {step:g} s, "
            f"RK4; {', '.join(dict.fromkeys(motions)) or 'no motion'}"
            + (f", {where}" if where else "")
            + f"; {given or 'model defaults'}")


def _slope(value: float | None) -> str:
    return "–" if value is None else f"{value:.2f}"
