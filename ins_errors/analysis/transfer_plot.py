"""The Bode plot of ``ins-errors transfer --plot``: |W(iω)| and its phase, pair by pair.

Each pair's magnitude is drawn in the output's display unit per the source's display
unit (an initial error's W carries one second more), over the band of the model's modes
(:func:`~ins_errors.analysis.transfer.frequency_band`), with a vertical line at the
frequency of every named mode a pair has as a pole; the upper axis gives the period.
Pairs differ by colour and line style; a curve identical to an earlier one (a drift of
1 deg/h and a tilt of 1 arcsec: 1 deg/h = 1 arcsec/s) is drawn dashed and wider over it
and its legend entry says so; the legend sits below the axes, in columns.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ins_errors.analysis.transfer import TransferFunctions

POINTS = 2000
"""Frequencies drawn, log-spaced over the band."""

DPI = 110

LINE_STYLES = ("-", "--", "-.", ":")
"""Line styles cycled after the colours (pairs 11 to 20 dashed, ...)."""


def _label(pair) -> str:
    """``"accel_bias → v_N [(m/s)/ug]"``: the pair and the unit of its |W(iω)| (an
    initial error's W is a response's transform: one second more, ``[s]`` where the
    output's unit is the source's)."""
    from ins_errors.analysis.transfer_text import ratio_unit

    unit = ratio_unit(pair.output_display, pair.source_display)
    if pair.source_kind == "initial":
        unit = "s" if unit == "1" else f"{unit}·s"
    return f"{pair.source} → {pair.output} [{unit}]"


def plot_bode(result: TransferFunctions, path: str | Path, title: str | None = None) -> Path:
    """Draw every non-zero pair's |W(iω)| and phase and write the figure.

    Parameters
    ----------
    result : TransferFunctions
        The pairs.
    path : str or Path
        Output file (png, pdf, svg).
    title : str, optional
        Figure title (default: the model and the base).

    Returns
    -------
    Path
        The written file.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ins_errors.figure_layout import fixed_margins
    from ins_errors.output import save_figure

    low, high = result.band
    omega = np.geomspace(low, high, POINTS)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.0, 6.6),
                                      gridspec_kw={"height_ratios": [2, 1]})
    drawn = [p for p in result.pairs if not p.is_zero]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    curves: list[tuple[np.ndarray, str]] = []
    for k, pair in enumerate(drawn):
        value = pair(1j * omega)
        output_factor, source_size = pair.display_factors
        magnitude = np.abs(value) * output_factor * source_size
        # colour × line style: no two of 40 pairs alike
        style = {"color": colours[k % len(colours)],
                 "ls": LINE_STYLES[(k // len(colours)) % len(LINE_STYLES)], "lw": 1.2}
        label = _label(pair)
        same = next((name for curve, name in curves
                     if np.allclose(curve, value * output_factor * source_size,
                                    rtol=1e-6, atol=0.0)), None)
        if same is not None:  # drawn dashed and wider over the first: both show
            style.update(ls=(0, (2, 2)), lw=2.4)
            label += f" (the same curve as {same})"
        curves.append((value * output_factor * source_size, f"{pair.source} → {pair.output}"))
        top.loglog(omega, magnitude, label=label, **style)
        phase = np.degrees(np.angle(value))
        phase[phase < -179.999] += 360.0  # a negative real W at +180°, not flickering
        bottom.semilogx(omega, phase, **{**style, "lw": style["lw"] * 0.85})
    if not drawn:
        top.text(0.5, 0.5, "W(s) = 0 for every pair: nothing to draw", ha="center",
                 transform=top.transAxes)
    labels = _mode_labels(result)
    placed = _label_sides(labels, low, high)
    for k, ((rate, _), (right, text)) in enumerate(zip(labels, placed, strict=True)):
        for ax in (top, bottom):
            ax.axvline(rate, color="grey", lw=0.8, ls=":")
        # horizontal labels at staggered heights, each beside its own line
        top.text(rate * (LABEL_GAP if right else 1 / LABEL_GAP), 0.97 - 0.065 * (k % 6), text,
                 va="top", ha="left" if right else "right", fontsize=7, color="dimgrey",
                 transform=top.get_xaxis_transform(),
                 bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1})
    for ax in (top, bottom):
        ax.set_xlim(low, high)
        ax.grid(True, which="both", alpha=0.25)
    top.set_ylabel("|W(iω)|  (output / source, display units)", fontsize=9)
    bottom.set_ylabel("phase of W(iω) [deg]", fontsize=9)
    bottom.set_ylim(-190, 190)
    bottom.set_yticks([-180, -90, 0, 90, 180])
    bottom.set_xlabel("ω [rad/s]")
    top.tick_params(labelbottom=False)
    period = top.secondary_xaxis("top", functions=(_period_h, _period_h))
    period.set_xlabel("period 2π/ω [h]", fontsize=9)
    columns = 1 if len(drawn) <= 6 else 2 if len(drawn) <= 24 else 3
    rows = -(-len(drawn) // columns)
    legend_height = 0.16 * rows + 0.2 if drawn else 0.0  # inches, below the axes
    if drawn:
        fig.set_size_inches(8.0, 6.6 + legend_height)
        bottom.legend(*top.get_legend_handles_labels(), fontsize=7, ncol=columns,
                      loc="upper center", bbox_to_anchor=(0.5, -0.32), frameon=False)
    modes = result.modes
    top.set_title(title or f"{modes.model}: transfer functions W(iω), {modes.base}",
                  fontsize=9, pad=28)
    fixed_margins(fig, left=0.9, right=0.25, bottom=0.55 + legend_height, top=0.75,
                  hspace=0.15)
    return save_figure(fig, path, dpi=DPI)


LABEL_GAP = 1.04
"""A mode's label starts this factor of ω beside its line."""

AXES_WIDTH_PT = (8.0 - 0.9 - 0.25) * 72
"""The axes' width, points (the figure's 8 in less its fixed margins)."""

LABEL_CHAR_PT = 0.55 * 7
"""About how wide one character of a 7 pt label is, points."""


def _label_sides(labels: list[tuple[float, str]], low: float, high: float
                 ) -> list[tuple[bool, str]]:
    """For each (|λ|, label), where to write it: (True to write it right of its line,
    False left; the text, broken before its time onto a second line where one line
    does not fit). The side is the one where the text (about :data:`LABEL_CHAR_PT` a
    character) stays inside the axes and crosses the fewest other modes' lines, on one
    line if it can, ties going away from the nearest other line (then towards the
    middle): a label never sits among other modes' lines when a side free of them
    exists (strapdown_ned's vertical channel, right of the Schuler pair, is labelled
    right of its own line, not left of it beside theirs)."""
    span = np.log(high / low)
    rates = [rate for rate, _ in labels]
    out = []
    for rate, text in labels:
        at = np.log(rate / low)
        others = [np.log(r / low) for r in rates if r != rate]
        forms = [text] + ([text.replace(", ", ",\n", 1)] if ", " in text else [])
        choices = []
        for lines, form in enumerate(forms):
            longest = max(len(line) for line in form.split("\n"))
            width = np.log(LABEL_GAP) + longest * LABEL_CHAR_PT / AXES_WIDTH_PT * span
            for right in (True, False):
                lo, hi = (at, at + width) if right else (at - width, at)
                outside = lo < 0 or hi > span
                crossed = sum(lo <= x <= hi for x in others)
                nearest = min((abs(x - at) for x in others if (x > at) == right),
                              default=np.inf)
                middle = (at < span / 2) == right
                choices.append(((outside, crossed, lines, -nearest, not middle),
                                (right, form)))
        out.append(min(choices, key=lambda c: c[0])[1])
    return out


def _mode_labels(result: TransferFunctions) -> list[tuple[float, str]]:
    """(|λ|, label) of each named mode a pair has as a pole, by increasing |λ|; modes at
    the same |λ| (the growing and decaying vertical channel) share one label."""
    from ins_errors.time_text import duration_text

    labels: list[list] = []
    for mode in sorted(result.named_modes(), key=lambda m: abs(m.eigenvalue)):
        rate = abs(mode.eigenvalue)
        time = duration_text(mode.period_s if mode.period_s else 1 / rate)
        if labels and rate <= labels[-1][0] * 1.005:
            labels[-1][1].append(mode.name)
            continue
        labels.append([rate, [mode.name], time])
    return [(rate, f"{_joined(names)}, {time}") for rate, names, time in labels]


def _joined(names: list[str]) -> str:
    """``"vertical channel (growing / decaying)"`` for names that differ only in their
    bracket; else the names joined by " / "."""
    heads = {name.split(" (")[0] for name in names}
    if len(names) > 1 and len(heads) == 1 and all(n.endswith(")") and " (" in n
                                                  for n in names):
        inner = " / ".join(n.split(" (", 1)[1][:-1] for n in names)
        return f"{heads.pop()} ({inner})"
    return " / ".join(names)


def _period_h(x):
    """ω (rad/s) <-> period (h): its own inverse."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return 2 * np.pi / x / 3600.0
