"""The error budget as a Markdown report for a design review (``budget --report``).

Everything in it is read from the budget's JSON (:func:`~ins_errors.analysis.
budget_report.report` or :func:`~ins_errors.analysis.budget_report.exceeded_report`,
with the warnings, parameters and Monte Carlo check the command adds): the same numbers
as ``--json`` and the terminal tables, in the same words where the terminal says the
same thing (:mod:`~ins_errors.analysis.budget_report` writes those sentences once). The
report is deterministic: no date, no timing, and the spec named as it was typed.
"""

from __future__ import annotations

from ins_errors.analysis.budget_report import (
    NO_RATIO,
    NOT_ALLOCATED,
    WHITE_NOTE,
    binding_text,
    exceeded_line,
    format_time,
    item_summaries,
    levels_note,
    magnitudes_words,
    monte_carlo_cells,
    monte_carlo_lines,
    shown_magnitude,
    unlimited_note,
)
from ins_errors.markdown_cells import one_line, table_cell
from ins_errors.specs import HOUR

SUFFIXES = (".md", ".markdown")
"""Suffixes a ``--report`` file may have (the report is Markdown)."""


def _table(header: list[str], rows: list[list[str]], right: set[int] = frozenset()) -> list[str]:
    """A Markdown table: user text escaped (:func:`~ins_errors.markdown_cells.table_cell`),
    the columns in ``right`` aligned right (numbers)."""
    rule = ["---:" if c in right else "---" for c in range(len(header))]
    return ["| " + " | ".join(table_cell(cell) for cell in line) + " |"
            for line in [header, rule, *rows]] if rows else []


def _largest_share(source: dict) -> str:
    """A source's largest share of any item's allowed variance over its check times, %,
    and the item (``5.26 % of position_error``); ``–`` without one."""
    shares = source.get("largest_share") or {}
    if not shares or max(shares.values()) <= 0:
        return "–"
    item = max(shares, key=shares.get)   # the first item on a tie
    percent = 100 * shares[item]
    return f"{percent:.2f} % of {item}" if percent < 100 else f"{percent:.0f} % of {item}"


def _parameters(data: dict) -> str:
    """The model parameters the run set (SI), or that the defaults were kept."""
    given = data.get("parameters") or {}
    if not given:
        return "the model's defaults"
    from ins_errors.commands.models import parameter_text

    return "; ".join(f"{name} = {parameter_text(p['value'], p['unit'], 6)}"
                     for name, p in given.items())


def markdown(data: dict, spec, spec_name: str, model_name: str) -> str:
    """The budget's Markdown report.

    Sections: the spec (file as typed, model, motion, operating time and step, σ level,
    rule, parameters, the result); the allocation (every source's allowed or fixed
    magnitude at its σ level in the unit its datasheet or the spec quotes, fixed or
    free, the item binding it, its largest share of an item's allowed variance); every
    item at its worst check time against its limit (ratio, met or exceeded), then every
    check time; the notes and warnings the terminal gives; the Monte Carlo check where
    it was run.

    Parameters
    ----------
    data : dict
        The budget's JSON as ``--json`` prints it (with ``warnings``, ``parameters``
        and, after ``--monte-carlo``, ``monte_carlo``).
    spec : ins_errors.specs.Spec
        The spec (the units its items' limits are written in).
    spec_name : str
        The spec as the user named it (:func:`~ins_errors.specs.spec_label`).
    model_name : str
        The model as the user named it.

    Returns
    -------
    str
        The document, ending in a newline.
    """
    k = f"{data['sigma_level']:g}σ"
    exceeded = "free_sources" in data   # the fixed sources alone use up the spec
    result = (exceeded_line(data) if exceeded else
              "met: every item is within its limit at each of its check times, at "
              + magnitudes_words(data))
    passing = [i["name"] for i in data["items"] if i.get("between_checks")]
    if passing:   # the spec is met where it looks: say where it is not
        result += (f"; above the limit between the check times: {', '.join(passing)} "
                   f"(see the warnings)")
    lines = [f"# Error budget: {one_line(data['spec'])}", ""]
    lines += [f"- **{key}**: {one_line(value)}" for key, value in [
        ("spec", spec_name), ("model", model_name), ("motion", data["motion"]),
        ("operating time", f"{format_time(data['operating_time_h'] * HOUR)} (analysis "
                           f"step {data['step_s']:g} s)"),
        ("σ level", f"{k}: every limit, value and magnitude below is {k} unless it says "
                    "otherwise"),
        ("allocation rule", data["rule"]),
        ("model parameters", _parameters(data)),
        ("result", result)]]
    lines += ["", "## Allocation", ""]
    lines.append(f"Magnitudes at {levels_note(data)}, in the units the spec or the "
                 "model's datasheet quotes them; the largest share is of one item's "
                 "allowed variance, (limit / k)², over the item's check times.")
    lines.append("")
    rows = [[s["label"], shown_magnitude(s, data["sigma_level"]),
             "fixed" if s["fixed"] else "free", "–" if s["fixed"] else binding_text(s),
             _largest_share(s)] for s in data["sources"]]
    lines += _table(["source", f"magnitude ({k})", "fixed or free", "binding item",
                     "largest share"], rows, right={1, 4})
    if exceeded and data["free_sources"]:   # one line, not a row each
        lines += ["", f"The free sources are {NOT_ALLOCATED}: "
                      f"{', '.join(data['free_sources'])}."]
    at = magnitudes_words(data)
    lines += ["", f"## Spec items at {at}", "",
              f"Each item at its worst check time ({k}; limits as the spec writes them).",
              ""]
    lines += _table(["item", "worst time", "value of limit", "ratio", "status"],
                    [[s["label"], s["time"], s["display"], f"{s['ratio']:.3f}",
                      s["status"]] for s in item_summaries(data)], right={1, 3})
    lines += ["", "### Every check time", ""]
    each = any(r["component"] for r in data["rows"])   # a column only where one is
    lines += _table(["item", "time", *["component"] * each, "value of limit", "ratio",
                     "status"],
                    [[r["item"], format_time(r["time_h"] * HOUR),
                      *[r["component"] or "–"] * each, r["display"], f"{r['ratio']:.3f}",
                      "exceeded" if r["exceeded"] else "met"] for r in data["rows"]],
                    right={1, 3 + each})
    notes = list(data.get("warnings", []))
    unlimited = unlimited_note(data)
    if unlimited and not exceeded:   # an exceeded spec's are under its table
        notes.append(unlimited)
    if any(s.get("statistics") == "white" for s in data["sources"]):
        notes.append(WHITE_NOTE)
    lines += ["", "## Notes and warnings", ""]
    lines += [f"- {one_line(note)}" for note in notes] or ["None."]
    mc = data.get("monte_carlo")
    if mc is not None:
        lines += ["", "## Monte Carlo check", ""]
        lines += [f"- {line}." for line in monte_carlo_lines(mc)]
        lines.append("")
        header, cells = monte_carlo_cells(mc, spec)
        lines += _table(header, cells, right=set(range(1, len(header))))
        if any(r["ratio"] is None for r in mc["rows"]):
            lines += ["", f"–: {NO_RATIO}."]
    return "\n".join(lines) + "\n"
