"""Reports of an error budget: JSON summary, text tables and stacked plots.

The numbers come from :mod:`ins_errors.analysis.budget`; this module only presents them
(plots with matplotlib's Agg backend).
"""

from __future__ import annotations

import re

import numpy as np

from ins_errors.analysis.budget import (
    ITEM_DISPLAY,
    RATE_ITEMS,
    Allocation,
    SpecExceededError,
    display,
    format_time,
)
from ins_errors.figure_layout import fixed_margins, text_height, text_width, wrap_to_width
from ins_errors.output import require_matplotlib, save_figure
from ins_errors.specs import HOUR
from ins_errors.units import format_quantity, format_readable, readable_angle_unit

TIE_DIGITS = 9
"""Sizes that agree to this many significant digits of the largest rank as equal."""


def largest_first(sizes: np.ndarray) -> np.ndarray:
    """Indices of ``sizes`` (1-D) from the largest down; equal sizes keep their order.

    "Equal" is to :data:`TIE_DIGITS` significant digits of the largest size: an
    equal-share allocation gives many sources exactly the same share in exact
    arithmetic, and their computed shares differ only by rounding, which would otherwise
    decide the order of the rows (and which sources a table lumps into "others") and
    change it with the last bit of any computation. Ties are listed in the model's order
    of its sources.
    """
    sizes = np.asarray(sizes, dtype=float)
    largest = float(np.max(np.abs(sizes))) if sizes.size else 0.0
    key = np.round(sizes / largest, TIE_DIGITS) if largest > 0 else sizes
    return np.argsort(-key, kind="stable")


def select_sources(shares: np.ndarray, top: int) -> tuple[np.ndarray, np.ndarray]:
    """The sources a table or plot names, and the rest it lumps into "(N others)".

    One rule for every table and plot of a budget, by rank within each column (a spec
    item, or an error at a time): name every column's largest source, then every
    column's second largest, and so on, until ``top`` are named; in the round that
    reaches ``top`` the larger shares go first. So each column's k largest sources are
    named for the largest k the room allows, whichever column they are large in.
    Shares that agree to :data:`TIE_DIGITS` significant digits are ties, ranked in the
    order of the sources; sources with no share anywhere (not limited, or fixed at 0)
    are neither named nor counted among the others.

    Parameters
    ----------
    shares : numpy.ndarray, shape (columns, sources)
        Share of each column's variance from each source (fractions of the column's
        total, or of its allowed variance).
    top : int
        Most sources named; all are named when at most one would be left over.

    Returns
    -------
    named : numpy.ndarray of int
        Named sources, largest share in any column first.
    others : numpy.ndarray of int
        The rest with a share somewhere, in the given order (empty when all are named).
    """
    shares = np.atleast_2d(np.asarray(shares, dtype=float))
    count = shares.shape[1]
    largest = shares.max(0) if shares.size else np.zeros(count)
    active = np.flatnonzero(largest > 0)
    if active.size <= top + 1:
        return active[largest_first(largest[active])], np.array([], dtype=int)
    ranked = [largest_first(column) for column in shares]
    named: list[int] = []
    for k in range(count):
        nominated: dict[int, float] = {}
        for column, order in zip(shares, ranked, strict=True):
            j = int(order[k])
            if column[j] > 0 and j not in named:
                nominated[j] = max(nominated.get(j, 0.0), float(column[j]))
        if nominated:
            keys = list(nominated)
            named += [keys[i] for i in largest_first(np.array(list(nominated.values())))]
        if len(named) >= top:
            break
    chosen = np.sort(np.array(named[:top], dtype=int))
    others = np.setdiff1d(active, chosen)
    return chosen[largest_first(largest[chosen])], others


def item_rows(budget) -> dict[str, list[int]]:
    """Spec item name -> the indices of its rows in ``budget.rows`` (its check times and
    components), in the spec's order."""
    return {item.name: [i for i, r in enumerate(budget.rows) if r.item == item.name]
            for item in budget.spec.items}


def worst_rows(allocation: Allocation) -> list[int]:
    """Each spec item's row (index into the budget's rows) with the largest total share
    of its allowed variance: the item's worst time (and component)."""
    budget = allocation.budget
    used = allocation.shares().sum(1)
    return [idx[int(np.argmax(used[idx]))] for idx in item_rows(budget).values()]


_NUMBER = re.compile(r"\s*[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?\s*")


def written_unit(item) -> str:
    """The unit a spec item's limit was written in (``"30 arcsec"`` -> ``"arcsec"``), in
    which the tables show its limit and its values; where the text has no unit that
    converts back, the unit the limit's size reads best in.

    Parameters
    ----------
    item : ins_errors.specs.SpecItem
    """
    si = item.kind.unit
    text = str(item.text)
    number = _NUMBER.match(text)
    unit = text[number.end():].strip() if number else ""
    if unit:
        try:
            format_quantity(item.value, si, unit)
            return unit
        except Exception:  # any text the unit library cannot take back
            pass
    return readable_angle_unit(item.value, ITEM_DISPLAY.get(item.name, si), down=True)


def motion_values(spec) -> dict:
    """The spec's motion as numbers (SI: rad, m, m/s), with its kind."""
    m = spec.motion
    values = {"kind": m.kind, "latitude_rad": m.latitude, "longitude_rad": m.longitude,
              "heading_rad": m.heading, "height_m": m.height}
    if m.kind != "static":
        values["speed_m_s"] = m.speed
    return values


def _header(budget, fill_factor: float) -> dict:
    """The keys every budget JSON starts with: the spec, its σ level, operating time,
    step, fill factor and motion (as text and as values)."""
    spec = budget.spec
    return {"spec": spec.title, "sigma_level": spec.sigma_level,
            "operating_time_h": spec.operating_time / HOUR, "step_s": spec.step,
            "fill": spec.fill, "fill_factor": fill_factor,
            "motion": budget.system.labels.get("trajectory", ""),
            "motion_values": motion_values(spec)}


def between_checks(allocation: Allocation) -> dict[str, dict | None]:
    """Where each spec item passes its limit between its check times, at the
    allocation's magnitudes (an allocation, or the fixed sources alone).

    The budget checks an item at its check times only, and an allocation meets it
    there: between them the error may still pass the limit (the initial vertical
    velocity error a height item checked every 5 min allows at 5 min, which the
    vertical channel turns into five times the limit within the first minute). The
    curves are the propagation the rows are read from, at every grid time
    (:func:`~ins_errors.analysis.budget_time.item_curves`), looked at from an item's
    first check time to its last (:func:`~ins_errors.analysis.budget_time.
    above_between_checks`).

    Returns
    -------
    dict
        For every item name, None when the item stays within its limit between its
        check times, is exceeded at one of them already (the fixed sources alone of a
        spec they exceed: its rows say so), or the budget kept no variances over time;
        else its largest
        value there: ``{"time_h", "component", "value", "ratio", "display"}`` (SI at
        the spec's σ level; ``display`` "value of limit" in the unit the spec wrote the
        limit in, as the rows show it). Of an item checked ``"each"``, the component
        that passes its limit by the largest ratio.
    """
    from ins_errors.analysis.budget_time import above_between_checks, item_curves

    spec = allocation.budget.spec
    found: dict[str, dict | None] = {item.name: None for item in spec.items}
    if allocation.budget.item_variances is None:
        return found
    curves = item_curves(allocation)
    exceeded = {c.item for c in curves if np.any(c.check_values > c.limit * (1 + 1e-9))}
    for curve in curves:
        if curve.item in exceeded:   # the rows say so already
            continue
        peak = above_between_checks(curve)
        if peak is None:
            continue
        t, value = peak
        ratio = value / curve.limit
        if found[curve.item] is None or ratio > found[curve.item]["ratio"]:
            item = spec.item(curve.item)
            unit = written_unit(item)
            found[curve.item] = {
                "time_h": t / HOUR, "component": curve.component, "value": value,
                "ratio": ratio, "display": f"{display(value, item.kind.unit, unit)} of "
                                           f"{display(item.value, item.kind.unit, unit)}"}
    return found


def checks_text(times: list[float]) -> str:
    """An item's check times, s, as a sentence says them: ``every 5 min from the start
    to 20 min``, ``at 0 h, 15 min and 20 min``, ``at 1 h only``."""
    if len(times) == 1:
        return f"at {format_time(times[0])} only"
    gaps = np.diff(times)
    if len(times) >= 3 and np.allclose(gaps, gaps[0], rtol=1e-9, atol=1e-6):
        start = "the start" if times[0] == 0 else format_time(times[0])
        return f"every {format_time(gaps[0])} from {start} to {format_time(times[-1])}"
    if len(times) <= 5:
        return ("at " + ", ".join(format_time(t) for t in times[:-1])
                + f" and {format_time(times[-1])}")
    return f"at {len(times)} times from {format_time(times[0])} to {format_time(times[-1])}"


def between_checks_warnings(data: dict) -> list[str]:
    """One warning per item that passes its limit between its check times, from a
    report's JSON (:func:`report`, :func:`exceeded_report`): the item, its largest value
    there against the limit, when, how the spec checks it and the cure."""
    k = f"{data['sigma_level']:g}σ"
    at = magnitudes_words(data)
    lines = []
    for item in data["items"]:
        peak = item.get("between_checks")
        if not peak:
            continue
        if item["name"] in RATE_ITEMS:
            cure = "check it more often (a shorter every)"
        else:
            cure = (f"check it more often, or at every analysis step to allocate on the "
                    f"whole run (every = \"{format_time(data['step_s'])}\")")
        lines.append(
            f"{_item_label(item['name'], peak['component'])} passes its limit between "
            f"its check times: {peak['display']} "
            f"({'CEP' if item.get('combine') == 'cep' else k}) at "
            f"{format_time(peak['time_h'] * HOUR)}, {peak['ratio']:.3g} times the limit, "
            f"at {at}; the spec checks it "
            f"{checks_text([t * HOUR for t in item['check_times_h']])} and the budget "
            f"looks there only: {cure}")
    return lines


def _items_json(budget, rows: list[dict], shares: np.ndarray,
                between: dict[str, dict | None]) -> list[dict]:
    """Each spec item at its worst row (the spec-rows table's line): limit as written
    and in SI, worst time and component, value and ratio at the spec's σ level, the
    share of the allowed variance used there (``shares``: (rows, sources) fractions of
    each row's allowed variance) and where it passes its limit between its check times
    (``between``, :func:`between_checks`)."""
    out = []
    for item in budget.spec.items:
        idx = [i for i, r in enumerate(budget.rows) if r.item == item.name]
        i = max(idx, key=lambda r: rows[r]["ratio"])
        out.append({"name": item.name, "limit": item.value, "limit_text": str(item.text),
                    "unit": item.kind.unit, "sigma_level": budget.spec.sigma_level,
                    "combine": item.combine, "check_times_h": [t / HOUR for t in item.times],
                    "worst_time_h": rows[i]["time_h"],
                    "worst_component": rows[i]["component"],
                    "value": rows[i]["value"], "ratio": rows[i]["ratio"],
                    "exceeded": any(rows[r]["exceeded"] for r in idx),
                    "share_used": float(shares[i].sum()),
                    "between_checks": between[item.name]})
    return out


def report(allocation: Allocation) -> dict:
    """A JSON-ready summary of an allocation (every number in SI, with its σ level
    beside it; see docs/scenarios.md, "The budget's JSON").

    Top level: the spec, ``sigma_level`` k, ``operating_time_h``, ``step_s``, ``fill``
    and ``fill_factor`` (the common variance factor of ``fill``, 1 without it), the
    motion as text and as ``motion_values``, the rule; ``sources`` (magnitude at kσ and
    at 1σ, the binding row, each item's share of its allowed variance at the item's
    worst time, ``share_at_worst_time``, and over all its check times,
    ``largest_share``; ``not_limited``: ``"motion"`` when no spec row depends on the
    source, ``"linear"`` when its share lies beyond the linear model, else null;
    ``linear_limit``, its largest size within the linear model at kσ, SI, or null);
    ``items`` (each item's worst row: the spec-rows table) and ``rows`` (every item at
    every check time and component).
    """
    budget = allocation.budget
    spec = budget.spec
    shares = allocation.shares()                                         # (rows, sources)
    values = allocation.values
    rows_of = item_rows(budget)
    worst = dict(zip(rows_of, worst_rows(allocation), strict=True))
    sources = []
    levels = allocation.levels
    linear = budget.linear_limits * levels
    beyond = (np.zeros(len(budget.sources), dtype=bool) if allocation.beyond_linear is None
              else allocation.beyond_linear)
    for j, s in enumerate(budget.sources):
        row = allocation.binding_row(j)
        magnitude = allocation.magnitudes[j]
        finite = bool(np.isfinite(magnitude))
        bounded = bool(np.isfinite(linear[j]))
        not_limited = (None if finite or s.fixed is not None
                       else "linear" if beyond[j] else "motion")
        sources.append({
            "name": s.name,
            "label": s.label,
            "statistics": s.statistics,
            "magnitude": float(magnitude) if finite else None,
            "magnitude_sigma_level": float(levels[j]),
            "magnitude_1sigma": float(allocation.sigma[j]) if finite else None,
            "unit": s.unit,
            "display": display(magnitude, s.unit, s.display_unit),
            "fixed": s.fixed is not None,
            "weight": s.weight,
            "not_limited": not_limited,
            "linear_limit": float(linear[j]) if bounded else None,
            "linear_limit_display": (format_readable(float(linear[j]), s.unit,
                                                     s.display_unit)
                                     if bounded else None),
            "binding_item": None if row is None else row.item,
            "binding_time_h": None if row is None else row.time / HOUR,
            "binding_component": None if row is None else row.component,
            "share_at_binding": None if row is None else float(
                shares[allocation.binding[j], j]),
            "share_at_worst_time": {name: float(shares[r, j]) for name, r in worst.items()},
            "largest_share": {name: float(max(shares[r, j] for r in idx))
                              for name, idx in rows_of.items()},
        })
    # met by construction: a ratio above 1 by more than rounding would be a fault
    rows = _rows_json(budget, values, values > np.array([r.limit for r in budget.rows])
                      * (1 + 1e-9))
    return {
        **_header(budget, allocation.fill_factor),
        "exceeded": any(r["exceeded"] for r in rows),
        "rule": _RULE + _cep_rule(spec) + (f"; then scaled by {allocation.fill_factor:.6g} "
                                           f"in variance (fill)" if spec.fill else ""),
        "sources": sources,
        "items": _items_json(budget, rows, shares, between_checks(allocation)),
        "rows": rows,
    }


_RULE = "equal share of each item's variance per free source (weighted), fixed sources first"


def _cep_rule(spec) -> str:
    """What the rule shares of a CEP item (``combine = "cep"``), or ""."""
    if not any(item.combine == "cep" for item in spec.items):
        return ""
    return ("; of a CEP item, the north + east variance of a circular error of that CEP, "
            "(limit / 0.8326)², which meets it whatever the error ellipse's shape")


def _rows_json(budget, values: np.ndarray, exceeded: np.ndarray) -> list[dict]:
    """The spec rows of a report: value (SI, at the spec's σ level; a CEP row's CEP)
    against the limit, both shown in the unit the spec wrote the limit in
    (:func:`written_unit`), a CEP row's display ending in ``CEP``."""
    spec = budget.spec
    units = {item.name: written_unit(item) for item in spec.items}

    def shown(r, value: float) -> str:
        return display(value, spec.item(r.item).kind.unit, units[r.item])

    return [{"item": r.item, "time_h": r.time / HOUR, "component": r.component,
             "limit": r.limit, "value": float(v), "unit": spec.item(r.item).kind.unit,
             "sigma_level": spec.sigma_level, "ratio": float(v / r.limit),
             "exceeded": bool(over),
             "display": f"{shown(r, v)} of {shown(r, r.limit)}{' CEP' if r.cep else ''}"}
            for r, v, over in zip(budget.rows, values, exceeded, strict=True)]


def fixed_allocation(error: SpecExceededError) -> Allocation:
    """The fixed sources alone, as an allocation (the free ones get nothing: σ = inf,
    left out of contributions): what the --at breakdown and the plot of a spec the
    fixed sources exceed are drawn from."""
    budget = error.budget
    sigma = np.array([np.inf if s.fixed is None else s.fixed for s in budget.sources])
    return Allocation(budget, sigma, np.full(len(budget.sources), -1), 1.0)


def exceeded_report(error: SpecExceededError) -> dict:
    """JSON-ready report of a spec the fixed sources alone use up: ``exceeded`` true, the
    fixed sources (each with its ``largest_share`` of every item's allowed variance
    over the item's check times, above 1 where it alone exceeds the item), every row
    with the fixed sources' value and its ratio to the limit (``exceeded`` on the rows
    used up), each item's worst row, and the free sources, which get no magnitude."""
    budget = error.budget
    fixed = [j for j, s in enumerate(budget.sources) if s.fixed is not None]
    rows = _rows_json(budget, error.values, error.used_up)
    fixed_only = fixed_allocation(error)
    shares = fixed_only.shares()
    rows_of = item_rows(budget)
    return {
        **_header(budget, 1.0),
        "exceeded": True,
        "rule": _RULE + _cep_rule(budget.spec) + "; the fixed sources alone use up the "
                                                 "spec, so nothing is allocated",
        "sources": [{"name": s.name, "label": s.label, "statistics": s.statistics,
                     "magnitude": float(s.fixed * s.sigma_level),
                     "magnitude_sigma_level": s.sigma_level,
                     "magnitude_1sigma": float(s.fixed), "unit": s.unit,
                     "display": display(s.fixed * s.sigma_level, s.unit, s.display_unit),
                     "fixed": True,
                     "largest_share": {name: float(max(shares[r, j] for r in idx))
                                       for name, idx in rows_of.items()}}
                    for j, s in ((j, budget.sources[j]) for j in fixed)],
        "free_sources": [s.label for s in budget.sources if s.fixed is None],
        "items": _items_json(budget, rows, shares, between_checks(fixed_only)),
        "rows": rows,
    }


def _item_label(item: str, component: str) -> str:
    """An item with the component of its worst row (``position_error [east]``)."""
    return f"{item} [{component}]" if component else item


def time_line(data: dict) -> str:
    """The operating time and the analysis step, one line."""
    return (f"Operating time {format_time(data['operating_time_h'] * HOUR)}, analysis "
            f"step {data['step_s']:g} s.")


def item_summaries(data: dict) -> list[dict]:
    """Each spec item's line of the tables, from a report's JSON (:func:`report`,
    :func:`exceeded_report`): its worst row (largest ratio), labelled with its
    component, and how many of its rows are exceeded.

    Returns
    -------
    list of dict
        ``{"label", "time", "display", "ratio", "exceeded", "checks", "between",
        "status"}``: the item (with its worst component), its worst time as text,
        "value of limit" as the rows show it, the ratio, how many of its rows are
        exceeded, of how many, where it passes its limit between its check times (text,
        or None: :func:`between_checks`), and ``"met"`` or ``"exceeded at N of M check
        times"``, which says so too (``"met at its check times only; between them 151 m
        of 30 m at 50 s (5.03 times the limit)"``).
    """
    lines = []
    for item in data["items"]:
        rows = [r for r in data["rows"] if r["item"] == item["name"]]
        worst = max(rows, key=lambda r: r["ratio"])
        count = sum(r["exceeded"] for r in rows)
        status = f"exceeded at {count} of {len(rows)} check times" if count else "met"
        peak = item.get("between_checks")
        between = None
        if peak:
            between = (f"{peak['display']} at {format_time(peak['time_h'] * HOUR)} "
                       f"({peak['ratio']:.3g} times the limit)")
            status += ("; " if count else " at its check times only; ") + \
                f"between them {between}"
        lines.append({"label": _item_label(item["name"], worst["component"]),
                      "time": format_time(worst["time_h"] * HOUR),
                      "display": worst["display"], "ratio": worst["ratio"],
                      "exceeded": count, "checks": len(rows), "between": between,
                      "status": status})
    return lines


def between_lines(data: dict) -> list[str]:
    """The lines under a text table of items that name the items passing their limits
    between their check times (the warnings say more)."""
    passing = [line for line in item_summaries(data) if line["between"]]
    return [f"! {line['label']} between its check times: {line['between']}; see the "
            f"warning" for line in passing]


def exceeded_line(data: dict) -> str:
    """The sentence that says a spec is exceeded by its fixed sources (how many rows
    and items they use up), from :func:`exceeded_report`."""
    over = [r for r in data["rows"] if r["exceeded"]]
    return (f"SPEC EXCEEDED: the fixed sources alone use up {len(over)} of "
            f"{len(data['rows'])} spec rows, in {len({r['item'] for r in over})} of "
            f"{len(data['items'])} items; nothing is left for the free sources.")


NOT_ALLOCATED = "not allocated (the fixed sources alone exceed the spec)"
"""What a free source of an exceeded spec gets, in every output."""


def exceeded_table(data: dict) -> str:
    """Plain text of :func:`exceeded_report`: each item the fixed sources use up, at its
    worst time (and component), by how much, and the fixed sources."""
    k = f"{data['sigma_level']:g}σ"
    lines = [f"Error budget: {data['spec']} ({k}), {data['motion']}", time_line(data),
             exceeded_line(data), "",
             f"{'item':<28} {'worst time':>10}  {'value of limit':<34} {'ratio':>6}  "
             "times exceeded", "-" * 98]
    for line in item_summaries(data):
        mark = f"{line['exceeded']} of {line['checks']}" if line["exceeded"] else "met"
        lines.append(f"{line['label']:<28} {line['time']:>10}  {line['display']:<34} "
                     f"{line['ratio']:>6.3f}  {mark}")
    lines += between_lines(data)
    lines += ["", f"Fixed sources ({levels_note(data)}): "
              + ", ".join(f"{s['label']} {shown_magnitude(s, data['sigma_level'])}"
                          for s in data["sources"])]
    return "\n".join(lines)


def shown_magnitude(source: dict, k: float) -> str:
    """A source's magnitude as a table shows it (its ``display``), with its σ level
    after it where that is not the spec's k (a 1σ datasheet bias in a 3σ spec); a
    white-noise density, which has no σ level, is shown as it is."""
    text = source["display"].strip()
    level = source.get("magnitude_sigma_level", k)
    if source.get("statistics") == "white" or level == k or text == "unconstrained":
        return text
    return f"{text} ({level:g}σ)"


def _bar_magnitude(source: dict, k: float) -> str:
    """A source's magnitude as the allocation chart labels its bars: as the tables show
    it (:func:`shown_magnitude`), a white-noise density tagged ``(1σ)`` where the spec's
    level is not 1σ (the caption says the magnitudes are at the spec's level, and the
    chart has no room for :data:`WHITE_NOTE`)."""
    text = shown_magnitude(source, k)
    if source.get("statistics") == "white" and k != 1 and text != "unconstrained":
        return f"{text} (1σ)"
    return text


WHITE_NOTE = "white-noise densities as given, 1σ: a density has no σ level"
"""Said beside the magnitudes of a source list that holds a white-noise density."""


def levels_note(data: dict) -> str:
    """The σ level of the magnitudes of a source list: the spec's k, and that a
    white-noise density is read and shown as given (it has no σ level) when the list
    has one."""
    k = f"{data['sigma_level']:g}σ"
    if any(s.get("statistics") == "white" for s in data["sources"]):
        return f"{k}; {WHITE_NOTE}"
    return k


def binding_text(source: dict) -> str:
    """What limits a source, as the tables say it: its binding item (with the component
    and time), ``fixed``, or why the spec does not limit it."""
    if source.get("binding_item") is None:
        if source["fixed"]:
            return "fixed"
        if source.get("not_limited") == "linear":
            return ("not limited by this spec (linear model to "
                    f"{source['linear_limit_display']})")
        return "not limited on this motion"
    comp = f" [{source['binding_component']}]" if source["binding_component"] else ""
    return (f"{source['binding_item']}{comp} at "
            f"{format_time(source['binding_time_h'] * HOUR)}")


def unlimited_note(data: dict) -> str:
    """The line naming the free sources the budget gives no magnitude: not limited on
    this motion, not limited by this spec (their share lies beyond the linear model),
    or, where the fixed sources alone exceed the spec, not allocated; "" when none.

    Parameters
    ----------
    data : dict
        :func:`report`'s JSON (of an allocation or of the fixed sources alone), or
        :func:`exceeded_report`'s.
    """
    free = data.get("free_sources")
    if free is None:
        free = [s["label"] for s in data["sources"]
                if s["binding_item"] is None and not s["fixed"]]
    if not free:
        return ""
    if data.get("exceeded"):
        return f"{NOT_ALLOCATED}: {', '.join(free)}"
    kinds = {s["label"]: s.get("not_limited") for s in data["sources"]}
    unseen = [name for name in free if kinds[name] != "linear"]
    linear = [name for name in free if kinds[name] == "linear"]
    return "; ".join(
        [f"not limited on this motion: {', '.join(unseen)}"] * bool(unseen)
        + [f"not limited by this spec (their share lies beyond the linear model): "
           f"{', '.join(linear)}"] * bool(linear))


CEP_WORDS = "CEP items: the radius holding 50 %"
"""What a CEP row's value is, beside the spec's σ level (a CEP has none)."""


def table(data: dict) -> str:
    """Plain-text report of :func:`report`'s JSON: allocated magnitudes, binding items,
    worst row of each item (with its component when the item's components are checked
    each on its own)."""
    k = f"{data['sigma_level']:g}σ"
    lines = [f"Error budget: {data['spec']} ({k}), {data['motion']}", time_line(data),
             f"Rule: {data['rule']}.", "",
             f"{'source':<36} {'allowed (' + k + ')':>22}  binding item",
             "-" * 86]
    for s in data["sources"]:
        shown = shown_magnitude(s, data["sigma_level"])
        lines.append(f"{s['label']:<36} {shown:>22}  {binding_text(s)}")
    if any(s["statistics"] == "white" for s in data["sources"]):
        lines.append(f"({WHITE_NOTE})")
    cep = (f" ({CEP_WORDS})"
           if any(item.get("combine") == "cep" for item in data["items"]) else "")
    lines += ["", f"Spec rows at {magnitudes_words(data)} (worst time of each item, {k}{cep}; "
              "limits as the spec writes them):",
              f"{'item':<28} {'time':>10}  {'value of limit':<34} {'ratio':>6}", "-" * 84]
    for line in item_summaries(data):
        lines.append(f"{line['label']:<28} {line['time']:>10}  {line['display']:<34} "
                     f"{line['ratio']:>6.3f}")
    lines += between_lines(data)
    return "\n".join(lines)


NO_RATIO = ("the covariance is 0 at this row (no source of the budget reaches "
            "it), so Monte Carlo / covariance is undefined")
"""Said of a Monte Carlo row whose covariance value is zero."""


def monte_carlo_lines(mc: dict) -> list[str]:
    """The sentences over the Monte Carlo check's table (``data["monte_carlo"]``): the
    runs, their step and method, the σ level compared and the sampling error; the
    integration error of the rectangle method where it was estimated."""
    lines = [f"Direct Monte Carlo: {mc['runs']} runs of "
             f"{format_time(mc['duration_h'] * HOUR)} at {mc['step_s']:g} s "
             f"({mc['method']}, seed {mc['seed']}), sample {mc['sigma_level']:g}σ vs "
             f"covariance; sampling error ±{100 * mc['relative_sampling_error']:.1f} % "
             "(1σ)"]
    estimate = mc.get("integration_error")
    if estimate:
        lines.append(f"integration error of the rectangle method: up to "
                     f"{100 * estimate['largest']:.2g} % on a row (Richardson: the first "
                     f"{estimate['runs']} runs again at {estimate['step_s']:g} s, "
                     f"{100 * estimate['extra_steps']:.2g} % more steps)")
    return lines


def monte_carlo_cells(mc: dict, spec) -> tuple[list[str], list[list[str]]]:
    """The Monte Carlo check's table as text cells: the header and one row per spec row
    (its label, the covariance's and the runs' values in the unit the spec wrote the
    item's limit in, the integration error where estimated, the ratio; ``–`` for a
    ratio or an error that is undefined, :data:`NO_RATIO`).

    Parameters
    ----------
    mc : dict
        ``data["monte_carlo"]`` of the budget's JSON.
    spec : ins_errors.specs.Spec
    """
    estimate = bool(mc.get("integration_error"))
    header = ["row", "covariance", "Monte Carlo", *(["integration"] * estimate), "ratio"]
    rows = []
    for r in mc["rows"]:
        item = spec.item(r["item"])   # as the spec rows: the limit's own unit
        unit, shown = item.kind.unit, written_unit(item)
        cells = [r["row"], display(r["covariance"], unit, shown),
                 display(r["monte_carlo"], unit, shown)]
        if estimate:   # the scheme's bias of the Monte Carlo value
            error = r.get("integration_error")
            cells.append("–" if error is None else f"{100 * error:+.2g}%")
        cells.append("–" if r["ratio"] is None else f"{r['ratio']:.3f}")
        rows.append(cells)
    return header, rows


def contribution_table(allocation: Allocation, top: int = 10) -> str:
    """Percent of each item's allowed variance used by each source (worst time)."""
    budget = allocation.budget
    contributions = allocation.shares()
    items = budget.spec.items
    worst = worst_rows(allocation)
    widths = [max(17, len(it.name) + 2) for it in items]
    header = f"{'source':<36}" + "".join(f"{it.name:>{w}}" for it, w in zip(items, widths,
                                                                             strict=True))
    lines = ["Share of each item's allowed variance (%), at its worst time:", header,
             "-" * len(header)]
    named, rest = select_sources(contributions[worst], top)
    def line(label: str, values) -> str:
        return f"{label:<36}" + "".join(f"{100 * v:>{w}.2f}"
                                        for v, w in zip(values, widths, strict=True))

    for j in named:
        lines.append(line(budget.sources[j].label, [contributions[r, j] for r in worst]))
    if rest.size:
        lines.append(line(f"({rest.size} others)",
                          [contributions[r, rest].sum() for r in worst]))
    lines.append(line("total", [contributions[r].sum() for r in worst]))
    return "\n".join(lines)


FIXED_HATCH = "////"
"""Hatching of a fixed source's bars in :func:`plot` (the instrument already bought)."""


LOG_SHARES = 1000.0
"""An exceeded budget's share axis is logarithmic where its largest share is more than
this many times its smallest (positive) one."""

LOG_RATIOS = 100.0
"""An exceeded budget's value/limit axis is logarithmic where its largest ratio is more
than this many times its smallest (or than 1, the limit)."""


def plot(allocation: Allocation, path: str, top: int = 40) -> None:
    """Save the budget as two readable bar charts.

    Left: one group of bars per fixed or limited source, labelled with its name and its
    magnitude in display units (``gyro_drift_x ≤ 0.0063 deg/h`` allowed,
    ``gyro_drift_z = 0.008 deg/h (fixed)``): one bar per spec item (coloured as the item
    on the right), the largest share of that item's allowed variance the source takes
    at any of its check times, so it shows where each source is used, not only the item
    that binds it (named after the bars; by the equal-share rule every source takes the
    same share of its binding item). The fixed sources come first, hatched
    (:data:`FIXED_HATCH`), above a line; the allocated ones are grouped by binding
    item, then sorted by binding time and share. Right: each spec item's worst value at
    these magnitudes as a fraction of its limit. Sources the motion does not limit are
    named under the chart. An allocation of the fixed sources alone (a spec they exceed,
    :func:`fixed_allocation`) draws them against the spec, with a line at 100 % of the
    allowed variance, and names the free sources as not allocated.

    Parameters
    ----------
    allocation : Allocation
        The allocated budget.
    path : str
        Image file to write (format from the suffix, e.g. ``budget.png``).
    top : int
        Most allocated sources drawn (the largest shares); every fixed source is drawn.
    """
    require_matplotlib()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = report(allocation)
    spec = allocation.budget.spec
    exceeded = bool(data.get("exceeded"))
    k = f"{spec.sigma_level:g}σ"
    items = [item.name for item in spec.items]
    limited = [s for s in data["sources"] if s["binding_item"] is not None]
    limited = [limited[i] for i in
               largest_first(np.array([s["share_at_binding"] for s in limited]))[:top]]
    rank = {s["label"]: r for r, s in enumerate(limited)}
    limited.sort(key=lambda s: (items.index(s["binding_item"]), s["binding_time_h"],
                                rank[s["label"]]))
    fixed = [s for s in data["sources"] if s["fixed"]]
    drawn = fixed + limited
    free = [s["label"] for s in data["sources"]
            if s["binding_item"] is None and not s["fixed"]]
    colours = {name: plt.get_cmap("tab10")(n % 10) for n, name in enumerate(items)}
    width, height = 13.0, 0.32 * max(len(drawn), len(items)) + 2.2
    fig, (left, right) = plt.subplots(1, 2, figsize=(width, height),
                                      gridspec_kw={"width_ratios": [2.2, 1]})
    y = np.arange(len(drawn))[::-1]
    # largest percent of each item's allowed variance over its times, (sources, items)
    used = np.array([[100 * (s.get("largest_share") or {s["binding_item"]:
                                                        s["share_at_binding"]}).get(n, 0.0)
                      for n in items] for s in drawn]).reshape(len(drawn), len(items))
    thick = 0.8 / len(items)
    for i, name in enumerate(items):
        bars = left.barh(y + (len(items) - 1) / 2 * thick - i * thick, used[:, i],
                         height=thick, color=colours[name], label=name)
        for bar in bars[:len(fixed)]:
            bar.set_hatch(FIXED_HATCH)
            bar.set_edgecolor("white")
            bar.set_linewidth(0)
    level = spec.sigma_level
    sources = ([f"{s['label']}  = {_bar_magnitude(s, level)} (fixed)" for s in fixed]
               + [f"{s['label']}  ≤ {_bar_magnitude(s, level)}" for s in limited])
    left.set_yticks(y, sources, fontsize=8)
    if fixed and limited:
        left.axhline(y[len(fixed) - 1] - 0.5, color="k", lw=0.8, ls=":")
    longest = used.max(1) if used.size else np.zeros(0)
    largest = max(float(longest.max()) if longest.size else 0.0, 1e-9)
    positive = used[used > 0]
    if exceeded and positive.size and largest > LOG_SHARES * positive.min():
        # fixed sources far beyond the spec (a MEMS IMU: 1e7 %) beside ones within it: on a
        # linear axis every bar but the largest was invisible
        low = 10.0 ** np.floor(np.log10(positive.min()))
        high = largest * 16
        left.set_xscale("log")
        left.set_xlim(low, high)
        start = low  # where a source with no share has its note

        def place(value: float) -> float:
            return float(np.log(max(value, low) / low) / np.log(high / low))
    else:
        left.set_xlim(0, largest * 1.6)
        start = 0.0

        def place(value: float) -> float:
            return value / (largest * 1.6)
    notes = []
    for n, (yy, s, end) in enumerate(zip(y, drawn, longest, strict=True)):
        if n < len(fixed):
            text = "  fixed (bought)"
        else:
            when = format_time(s["binding_time_h"] * HOUR)
            text = f"  bound by {s['binding_item']} at {when}"
        left.text(max(end, start), yy, text, va="center", fontsize=7)
        notes.append((place(end), text_width([text], 7)))
    if exceeded and largest >= 100:
        left.axvline(100.0, color="k", lw=1, ls="--")
    left.set_title("the fixed sources alone, and where they use the spec" if exceeded else
                   "allowed (or fixed) magnitude of each source, and where it is used"
                   if fixed else "allowed magnitude of each source, and where it is used",
                   fontsize=10)
    left.grid(True, axis="x", alpha=0.3)
    worst = []
    for name in items:
        rows = [r for r in data["rows"] if r["item"] == name]
        worst.append(max(rows, key=lambda r: r["ratio"]))
    yi = np.arange(len(items))[::-1]
    right.barh(yi, [r["ratio"] for r in worst], color=[colours[n] for n in items])
    right.axvline(1.0, color="k", lw=1, ls="--")
    checks = [f"{_item_label(n, r.get('component', ''))}\n{r['display']} at "
              f"{format_time(r['time_h'] * HOUR)}" for n, r in zip(items, worst, strict=True)]
    right.set_yticks(yi, checks, fontsize=8)
    ratios = np.array([r["ratio"] for r in worst])
    small = ratios[ratios > 0].min(initial=np.inf)
    if exceeded and ratios.max() > LOG_RATIOS * min(small, 1.0):
        # an item exceeded 27× beside one exceeded 39 000×: linear, the first had no bar
        right.set_xscale("log")
        right.set_xlim(10.0 ** np.floor(np.log10(min(small, 1.0) / 2)), 3 * ratios.max())
    else:
        right.set_xlim(0, max(1.15, 1.1 * ratios.max()))
    right.set_xlabel(f"worst value / limit ({k})")
    right_title = ("spec items at the fixed sources alone" if exceeded else
                   "spec items at these magnitudes")
    right.grid(True, axis="x", alpha=0.3)
    # fixed margins from the labels' measured widths (no tight_layout: it draws the
    # figure once more only to measure it); all sizes in inches
    note = ""
    if free:
        import textwrap

        note = wrap_to_width(textwrap.fill(unlimited_note(data), 170), 7, width - 0.3)
        fig.text(0.1 / width, 0.1 / height, note, fontsize=7, va="bottom")
    heading = wrap_to_width(f"Error budget: {spec.title}{' — SPEC EXCEEDED' if exceeded else ''}"
                            f"\n{data['motion']}", 10, width - 0.4)
    fig.suptitle(heading, fontsize=10, y=1 - 0.1 / height, va="top")
    margin, ticks = 0.12, 7 / 72  # edge clearance; tick length + pad
    left_margin = margin + text_width(sources, 8) + ticks
    gap = margin + 0.2 + text_width(checks, 8) + ticks
    share = 2.2 / 3.2  # of the panels' width that is the left panel's
    for _ in range(4):  # the bar notes (after the bars) may need a wider gap
        panel = (width - left_margin - 0.3 - gap) * share
        over = max((f * panel + w - panel for f, w in notes), default=0.0)
        gap = margin + 0.2 + text_width(checks, 8) + ticks + max(0.0, over)
    levels = (f"{k} magnitudes, white-noise densities 1σ, as labelled"
              if k != "1σ" and any(s.get("statistics") == "white" for s in drawn)
              else f"{k} magnitudes as labelled")
    xlabel = (f"largest share of each item's allowed variance over its check times, % "
              f"({levels}; hatched: fixed; colours: the items on the right)" if fixed else
              f"largest share of each item's allowed variance over its check times, % "
              f"({levels}; colours: the items on the right)")
    if text_width([xlabel], 10) > panel:
        xlabel = xlabel.replace(" (", "\n(")
    left.set_xlabel(xlabel)
    # the right panel's title on two lines when the labels leave the panel narrow
    right_title = wrap_to_width(right_title, 10, panel / share - panel)
    right.set_title(right_title, fontsize=10)
    top = 0.1 + text_height(heading, 10) + 0.12 + text_height(right_title, 10) + 6 / 72
    bottom = (margin + ticks + text_height("0", 10) + 4 / 72
              + text_height(xlabel, 10) + (text_height(note, 7) + 0.1 if note else 0))
    fixed_margins(fig, left=left_margin, right=0.3, bottom=bottom, top=top, wspace=gap)
    save_figure(fig, path, dpi=110)


def output_rows(data: dict, it: int, top: int = 10) -> list[tuple[str, np.ndarray]]:
    """Rows of the table of :mod:`~ins_errors.analysis.budget_contributions` at its ``it``-th time.

    The named sources (:func:`select_sources` on the shares of each error's variance),
    then ``"(N others)"`` with the root sum of squares of the rest, then ``"total
    (rss)"``: the rows before the total combine in rss to it.

    Returns
    -------
    list of (str, numpy.ndarray of shape (quantities,))
        Label and 1σ values in the display units.
    """
    std, total = np.asarray(data["std"][it]), np.asarray(data["total"][it])  # (q, s), (q,)
    variance = std**2
    named, rest = select_sources((variance / np.maximum(total**2, 1e-300)[:, None]), top)
    rows = [(data["sources"][j], std[:, j]) for j in named]
    if rest.size:
        rows.append((f"({rest.size} others)", np.sqrt(variance[:, rest].sum(1))))
    rows.append(("total (rss)", total))
    return rows


def magnitudes_note(allocation: Allocation, fixed_only: bool = False) -> str:
    """Which magnitudes a breakdown of the navigation errors uses, for its title and the
    JSON: the allocated ones (after ``fill``'s factor), or (``fixed_only``: a spec the
    fixed sources exceed, :func:`fixed_allocation`) the fixed sources alone."""
    if fixed_only:
        return "the fixed sources alone, as nothing is allocated"
    if not np.any(allocation.binding >= 0):  # every source fixed (or not limited)
        return GIVEN
    if allocation.budget.spec.fill:
        return (f"the allocated magnitudes, filled (×{allocation.fill_factor:.4g} in "
                "variance)")
    return "the allocated magnitudes"


GIVEN = "the given magnitudes"
"""The magnitudes a budget's rows are at when it allocates none: every source is fixed
(or, free, is not limited by the spec)."""


def magnitudes_words(data: dict) -> str:
    """Which magnitudes the rows of a report's JSON (:func:`report`,
    :func:`exceeded_report`) are at: the fixed sources alone where they exceed the spec,
    :data:`GIVEN` where nothing is allocated (every source fixed: "allocated" said of
    magnitudes the spec file gave), else the allocated magnitudes."""
    if "free_sources" in data:
        return "the fixed sources alone"
    if not any(s["binding_item"] is not None and not s["fixed"] for s in data["sources"]):
        return GIVEN
    return "the allocated magnitudes"


def output_table(data: dict, top: int = 10) -> str:
    """Text table of the contributions at chosen times
    (:mod:`~ins_errors.analysis.budget_contributions`; 1σ per source, largest first); its
    titles name the magnitudes (``data["magnitudes"]``, :func:`magnitudes_note`) when
    given."""
    lines = []
    note = data.get("magnitudes")
    for it, t in enumerate(data["times_h"]):
        names = [f"{q.replace('delta_', 'Δ')} {u}"
                 for q, u in zip(data["quantities"], data["units"], strict=True)]
        widths = [max(12, len(n) + 2) for n in names]
        header = f"{'source (1σ)':<34}" + "".join(f"{n:>{w}}"
                                                  for n, w in zip(names, widths, strict=True))
        at = f" (1σ, at {note})" if note else ""
        lines += [f"Contributions to the navigation errors at {format_time(t * HOUR)}{at}:",
                  header,
                  "-" * len(header)]
        for label, values in output_rows(data, it, top):
            lines.append(f"{label:<34}" + "".join(f"{_number(v, 4):>{w}}"
                                                  for v, w in zip(values, widths, strict=True)))
        lines.append("")
    return "\n".join(lines).rstrip()


def _number(value: float, digits: int) -> str:
    """``value`` to ``digits`` significant digits, whole numbers up to 1e7 without an
    exponent (a position error of 33560 m, not 3.356e+04 m)."""
    if 10**digits <= abs(value) < 1e7:
        return f"{value:.0f}"
    return f"{value:.{digits}g}"


OTHERS_STYLE = {"color": "white", "edgecolor": "black", "hatch": "////", "linewidth": 0.6}
"""How the "others" block of :func:`plot_outputs` is drawn: white, hatched and outlined,
unlike any source's colour (tab20 has two greys; a grey block read as one of them)."""


def plot_outputs(data: dict, path: str, top: int = 19, title: str | None = None) -> None:
    """Stacked bars of the contributions at chosen times
    (:mod:`~ins_errors.analysis.budget_contributions`): share of each error's variance.

    One panel per chosen time; each bar is one platform angle or output error, split
    into the sources' shares of its variance (the bar's label gives its 1σ total), so
    every bar adds up to 1. The named sources are chosen by :func:`select_sources`
    over every bar of every panel, at most ``top`` of them (19: the distinct colours of
    the palette); the rest make one hatched "others" block (:data:`OTHERS_STYLE`).
    ``title``: the figure's heading (spec, motion, σ and magnitudes), over the panels.
    """
    require_matplotlib()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    std, total = np.asarray(data["std"]), np.asarray(data["total"])   # (t, q, s), (t, q)
    variance = std**2
    shares = variance / np.maximum(variance.sum(-1, keepdims=True), 1e-300)
    shown, rest = select_sources(shares.reshape(-1, shares.shape[-1]), top)
    colours = plt.get_cmap("tab20")
    times = data["times_h"]
    width = 12.0
    heading_text = wrap_to_width(title, 11, width - 0.4) if title else ""
    heading = text_height(heading_text, 11) + 0.12 if title else 0.0
    height = 3.2 * len(times) + 1.2 + heading
    fig, axes = plt.subplots(len(times), 1, figsize=(width, height), squeeze=False)
    if heading_text:
        fig.suptitle(heading_text, fontsize=11, y=1 - 0.1 / height, va="top")
    x = np.arange(len(data["quantities"]))
    labels = []
    for it, (ax, t) in enumerate(zip(axes[:, 0], times, strict=True)):
        bottom = np.zeros(len(x))
        for c, j in enumerate(shown):
            ax.bar(x, shares[it, :, j], bottom=bottom, color=colours(c % 20),
                   label=data["sources"][j])
            bottom += shares[it, :, j]
        if rest.size:
            ax.bar(x, shares[it][:, rest].sum(-1), bottom=bottom, label="others",
                   **OTHERS_STYLE)
        labels = [f"{q.replace('delta_', 'Δ')}\n{_number(v, 3)} {u}" for q, u, v in
                  zip(data["quantities"], data["units"], total[it], strict=True)]
        ax.set_xticks(x, labels, fontsize=7)
        ax.set_ylabel("share of variance")
        ax.set_title(f"t = {format_time(t * HOUR)} (1σ totals under the bars)", fontsize=10)
        ax.set_ylim(0, 1.0)
    handles, names = axes[0][0].get_legend_handles_labels()
    # fixed margins (no tight_layout, which draws the figure once more to measure it):
    # the legend's columns as many as fit the width (at most 5), its rows under the
    # panels; all sizes in inches
    em = 8 / 72  # the legend's font size
    column = text_width(names, 8) + (2.0 + 0.8 + 2.0) * em  # handle, pad, spacing
    ncol = int(max(1, min(5, (width - 0.3 - 2 * em) // column)))
    fig.legend(handles, names, loc="lower center", ncol=ncol, fontsize=8)
    rows = -(-len(names) // ncol)
    legend = (rows * 1.2 + (rows - 1) * 0.5 + 2 * 0.4 + 0.5) * em + 0.05
    ticks = 7 / 72 + text_height("\n", 7)  # tick length + pad, two-line labels
    title = text_height("t", 10) + 6 / 72
    fixed_margins(fig, left=0.12 + text_height("share", 10) + 4 / 72
                  + text_width(["0.0", "1.0"], 10) + 7 / 72,
                  right=0.2, top=0.12 + heading + title, bottom=legend + 0.15 + ticks,
                  hspace=ticks + 0.2 + title)
    save_figure(fig, path, dpi=120)


