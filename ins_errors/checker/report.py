"""Render a :class:`~ins_errors.checker.compare.CheckReport`: Markdown, terminal, JSON.

Everything here is deterministic (no dates, no machine paths), so a report regenerated
from unchanged inputs is byte-identical.
"""

from __future__ import annotations

import math
import re
from typing import Any

from ins_errors.checker import classify as cl
from ins_errors.checker.classify import Finding
from ins_errors.checker.compare import CheckReport, EquationResult
from ins_errors.checker.effect import HOURS
from ins_errors.checker.growth import growth_text
from ins_errors.checker.matrix_report import below, length_text
from ins_errors.markdown_cells import one_line
from ins_errors.markdown_cells import table_cell as _cell

UNCHECKED = ("error sources the model's side of these lines has and the file never "
             "mentions (taken as zero on both sides, not checked): ")
"""Terminal line naming :attr:`CheckReport.unchecked_sources`."""


def _size(value: float) -> str:
    if math.isinf(value):
        return "—"
    return f"{value:.2g}"


def _code(text: str) -> str:
    return f"`{_cell(text)}`" if text else ""


STATUSES = ("agrees", "agrees up to dropped small terms", "agrees up to declared drops",
            "mistake", "hand-only definition", "tautology", "input error")
"""Every status an equation form can have (:class:`~ins_errors.checker.compare.EquationResult`)."""

COMPARED = STATUSES[:4]
"""The statuses of forms compared with the model."""


def status_key(status: str) -> str:
    """The JSON key of a status: ``"agrees up to declared drops"`` ->
    ``"agrees_up_to_declared_drops"``, ``"hand-only definition"`` ->
    ``"hand_only_definition"``."""
    return status.replace("-", "_").replace(" ", "_")


def summary_counts(report: CheckReport) -> dict[str, Any]:
    """The summary of ``check --json``, the same keys whatever was found.

    Returns
    -------
    dict
        ``equations_by_status``: number of checked equation forms with each status of
        :data:`STATUSES` (snake_case keys, 0 when none); ``findings``: number of findings
        by class (``mistakes``, of them ``root_mistakes`` and ``knock_on_mistakes``;
        ``declared_drops``, ``dropped_small_terms``); ``input_problems``: number of
        lines that could not be read. An undeclared dropped variation
        (:attr:`~ins_errors.checker.compare.CheckReport.omissions`) of the class mistake
        is one root mistake (its findings, knock-ons); ``undeclared_drops`` counts them
        all. The other half of a pair (:mod:`~ins_errors.checker.line_pairs`) is
        counted with the finding that names it, not again.
    """
    by_status = dict.fromkeys(map(status_key, STATUSES), 0)
    for result in report.results:
        key = status_key(result.status)
        by_status[key] = by_status.get(key, 0) + 1  # a status added later still counts
    extra = sum(1 for o in report.omissions if o.is_mistake)
    mistakes, roots = len(report.mistakes) + extra, len(report.root_mistakes) + extra
    return {
        "equations_by_status": by_status,
        "findings": {
            "mistakes": mistakes,
            "root_mistakes": roots,
            "knock_on_mistakes": mistakes - roots,
            "declared_drops": sum(1 for _, f in report.findings if f.severity == cl.DECLARED),
            "dropped_small_terms": sum(1 for _, f in report.findings
                                       if f.severity == cl.DROPPED and not f.merged),
            "undeclared_drops": len(report.omissions),
        },
        "input_problems": len(report.problems),
    }


def summary_line(report: CheckReport) -> str:
    """One line: what was checked and what was found."""
    c = summary_counts(report)
    by_status, found = c["equations_by_status"], c["findings"]
    compared = sum(by_status[status_key(s)] for s in COMPARED)
    agree_small = (by_status["agrees_up_to_dropped_small_terms"]
                   + by_status["agrees_up_to_declared_drops"])
    return (f"{report.hand_name}: {_count(compared, 'equation form')} compared with model "
            f"{report.model!r}: {by_status['agrees']} agree, {agree_small} agree up to "
            f"dropped terms, {by_status['mistake']} with mistakes "
            f"({_count(found['root_mistakes'], 'root mistake')}, "
            f"{_count(found['knock_on_mistakes'], 'knock-on finding')}, "
            f"{_count(found['declared_drops'], 'declared drop')}, "
            f"{_count(found['dropped_small_terms'], 'dropped small term')}"
            + (f", {_count(found['undeclared_drops'], 'undeclared dropped variation')}"
               if found["undeclared_drops"] else "")
            + f"); {_count(c['input_problems'], 'input problem')}")


def _count(n: int, thing: str) -> str:
    """``"1 root mistake"``, ``"3 root mistakes"``."""
    return f"{n} {thing}{'s' * (n != 1)}"


def _effect(f: Finding) -> str:
    """``"1 h: 28.3 km, 918″ (initial psi); 24 h: 1.2 km, 3.4″ (static base)"`` or empty:
    the worst single case at each time (named when above rounding), a figure at or
    below its rounding floor as ``< floor``, exponential growth as such, a propagation
    that overflows floating point as that."""
    e = f.effect
    if not e:
        return ""
    if "note" in e:
        return e["note"]
    parts = []
    for hours in HOURS:
        tag = f"{int(hours)}h"
        if e.get(f"exponential_{tag}"):
            parts.append(f"{int(hours)} h: "
                         + growth_text(e["e_folding_s"], e.get("growing_mode")))
            continue
        if e.get(f"overflow_{tag}"):
            parts.append(f"{int(hours)} h: overflows (the propagation passes 1e308)")
            continue
        position, attitude = e[f"position_{tag}"], e[f"attitude_{tag}"]
        floor_p = e.get(f"position_floor_{tag}", 0.0)
        floor_a = e.get(f"attitude_floor_{tag}", 0.0)
        text = (f"{int(hours)} h: "
                + ("position n/a" if position is None
                   else length_text(position) if position > floor_p else below(floor_p, "m"))
                + ", "
                + ("attitude n/a" if attitude is None
                   else _angle(attitude) if attitude > floor_a
                   else below(math.degrees(floor_a) * 3600, "″")))
        cases = [c for c in (e.get(f"position_case_{tag}"), e.get(f"attitude_case_{tag}"))
                 if c]
        if cases:
            text += f" ({'; '.join(dict.fromkeys(cases))})"
        parts.append(text)
    text = "; ".join(parts) + f" ({e['point']})"
    if e.get("largest_point"):  # much larger where the coefficient differs less
        figure = (growth_text(e["largest_e_folding_s"], e.get("largest_growing_mode"))
                  if e.get("largest_24h") is None
                  else length_text(e["largest_24h"]) if e["largest_what"] == "position"
                  else _angle(e["largest_24h"]))
        text += f"; larger at {e['largest_point']}: 24 h: {figure}"
    return text


def _angle(radians: float) -> str:
    return f"{math.degrees(radians) * 3600:.3g}″"


def _finding_rows(pairs: list[tuple[EquationResult, Finding]], roots: bool = False
                  ) -> list[str]:
    rows = ["| line | equation | quantity | what | class | size | at | hand coefficient | "
            "model coefficient | explanation | effect on the error (position, attitude) |",
            "|---:|---|---|---|---|---:|---|---|---|---|---|"]
    for result, f in pairs:
        detail = f.detail
        if roots and f.roots:
            detail = f"from {', '.join(f.roots)}" + (f"; {detail}" if detail else "")
        rows.append(f"| {result.equation.line} | {_code(result.label)} | {_code(f.quantity)} | "
                    f"{f.kind} | {f.severity} | {_size(f.size)} | {f.point} | {_code(f.hand)} | "
                    f"{_code(f.model)} | {_cell(detail)} | {_cell(_effect(f))} |")
    return rows


def omission_groups(report: CheckReport) -> list[tuple]:
    """Each undeclared dropped variation with the findings it explains, in file order:
    (:class:`~ins_errors.checker.classify.Omission`, [(result, finding), ...])."""
    return [(o, [(r, f) for r, f in report.findings
                 if f.role == cl.KNOCK_ON and o.reference in f.roots])
            for o in report.omissions]


def ordered(report: CheckReport) -> list[tuple[str, list[tuple[EquationResult, Finding]]]]:
    """The findings top-down: each root mistake with its knock-ons, declared drops, drops
    (the findings of an undeclared dropped variation are under it:
    :func:`omission_groups`)."""
    groups = []
    for result, f in report.root_mistakes:
        groups.append(("root", [(result, f)]))
    shown = set()
    out = []
    for _, pairs in groups:
        result, f = pairs[0]
        key = id(result)
        knock = [] if key in shown else report.knock_ons(result)
        shown.add(key)
        out.append(("root", [(result, f), *report.merged_with(result, f), *knock]))
    grouped = {o.reference for o in report.omissions}
    orphans = [(r, f) for r, f in report.findings if f.role == cl.KNOCK_ON and f.is_mistake
               and not any(r2.reference in f.roots for r2, _ in report.root_mistakes)
               and not grouped & set(f.roots)]
    if orphans:
        out.append(("knock-on", orphans))
    out.append(("declared", [(r, f) for r, f in report.findings if f.severity == cl.DECLARED]))
    out.append(("dropped", [(r, f) for r, f in report.findings if f.severity == cl.DROPPED
                            and not grouped & set(f.roots) and not f.merged]))
    return out


def status_notes(r: EquationResult) -> str:
    """The notes of one equation form in the reports' equation-by-equation table: its
    findings (kind, quantity, class, size, roots of a knock-on), then its own notes."""
    notes = "; ".join(r.notes)
    if r.findings:
        kinds = ", ".join(
            (f"{f.kind} ({f.severity}, {_size(f.size)}" if f.quantity.startswith("(")
             else f"{f.kind} on {f.quantity} ({f.severity}, {_size(f.size)}")
            + (f", from {' and '.join(f.roots)})" if f.role == cl.KNOCK_ON and f.roots
               else ")")
            for f in r.findings)
        notes = kinds + (f"; {notes}" if notes else "")
    return notes


SIZE_MEANING = (
    "the discrepancy over the largest term of the model's side of its equation, each term "
    "being its coefficient times the typical magnitude of its error quantity (the largest "
    "ratio over the reference points)")
"""What a finding's *size* is: said once, in the reports' prose (:func:`how_compared`)
and in the terminal's legend (:func:`legend`)."""

EFFECT_MEANING = (
    "what it changes in the horizontal position error and the attitude error after 1 h "
    "and 24 h, in the worst single case (`source X`: the file's error source X alone, "
    "`initial X`: error state X alone at the start, each at its typical magnitude), at the "
    "reference point in parentheses (`< x`: at or below the rounding floor x; *larger at*: "
    "a point where the 24-h figure is larger)")
"""What a finding's *effect* is (as :data:`SIZE_MEANING`)."""

_MARKS = re.compile(r"\*\*|\*|`")


def legend(report: CheckReport) -> list[str]:
    """The terminal report's legend: what *size* and *effect* mean
    (:data:`SIZE_MEANING`, :data:`EFFECT_MEANING`, the reports' own words without their
    Markdown marks) and what each reference point named in the findings is (the
    reports' table of reference points)."""
    rows = [f"size (column): {_MARKS.sub('', SIZE_MEANING)}"]
    if any(f.effect for _, f in report.findings):
        rows.append(f"effect (under a finding): {_MARKS.sub('', EFFECT_MEANING)}")
    if report.points:
        rows.append("reference points: " + "; ".join(f"{p.label} = {p.description}"
                                                     for p in report.points))
    return rows


def how_compared(threshold: float) -> str:
    """The paragraph of a report that says how the sides were compared and what the
    classes mean, in Markdown (``**bold**``, ``*emphasis*``, ```code```: the LaTeX report
    converts it)."""
    return (
        "Each equation's two sides are brought to a linear combination of the error states "
        "and error sources, the hand side through the file's own definitions and the model "
        f"side through the mechanical variation. A finding's *size* is {SIZE_MEANING}; a "
        "wrong term the hand adds does not make another finding small. *What* the "
        "difference is (omitted term, wrong "
        "coefficient, wrong symbol or index, wrong sign, wrong function, wrong exponent) "
        "and *how much it matters* are two separate axes: a term present but wrong is a "
        "**mistake** whatever its size (*mistake, small effect* below the threshold "
        f"{threshold:g}); only an omitted small term is a **dropped small term**, "
        "and an omission the file declares (`@neglect`) a **declared drop**. A *knock-on* "
        "finding disappears once the definitions its line uses are corrected: it is listed "
        f"under its root. A finding's *effect* is {EFFECT_MEANING}.")


SECTION_TITLES = {"knock-on": "Knock-on findings whose root is not a mistake",
                  "declared": "Declared drops", "dropped": "Other small drops"}
"""Headings of the finding groups after the root mistakes (:func:`ordered`'s kinds)."""


def scope_text(scope: str) -> str:
    """The report's paragraph on a file's ``@scope``, in the reports' inline Markdown
    (as :func:`how_compared`)."""
    return (f"**Scope.** The file limits itself to the motion class *{scope}* "
            "(`@scope`): it is compared there only.")


def omission_text(omission) -> str:
    """What an undeclared dropped variation's heading is followed by (inline Markdown)."""
    return ("One simplification explains every finding below: the model's side with these "
            "variations dropped agrees with the file on them. Largest size "
            f"{_size(omission.size)} at {omission.point}; an omission the file does not "
            f"declare is judged by its size. "
            + (f"Every one of them is 0 at rest: moving-base terms a static-base derivation "
               f"leaves out, which `{cl.SCOPE_STATIC}` declares." if omission.at_rest
               else f"Declared, it would read `{omission.neglect}`."))


def out_of_scope_text(sources: list[str]) -> str:
    """The sentence naming the error sources a file never mentions (inline Markdown)."""
    return ("Error sources the file never mentions (zero on both sides): "
            + ", ".join(f"`{s}`" for s in sources) + ".")


FROM_MODEL_TEXT = (
    "Variations the lines below use before (or without) the file defining them; for those "
    "lines the model's variation stands in on the hand side, so these variations are not "
    "checked there (a definition later in the file is checked on its own line):")
"""Introduces the list of variations the model stood in for (plain text)."""


def to_markdown(report: CheckReport, source: str | None = None) -> str:
    """The Markdown report.

    Parameters
    ----------
    report : CheckReport
    source : str, optional
        How the report was produced (e.g. "`make derive` from examples/...") for the
        header line; omitted when None.
    """
    lines = [f"# Check of `{one_line(report.hand_name)}` against the `{report.model}` model",
             ""]
    if source:
        lines += [f"Generated by {source}. Do not edit: regenerate.", ""]
    lines += [
        f"**Result.** {summary_line(report)}.",
        "",
        f"**Typical magnitudes.** {report.magnitudes}.",
        "",
        how_compared(report.threshold),
        "",
    ]
    if report.scope:
        lines += [scope_text(report.scope), ""]
    if report.scope_advice:
        lines += [f"**Static base?** {report.scope_advice}", ""]
    if report.declarations:
        lines += ["**Declared simplifications.** " + "; ".join(report.declarations) + ".", ""]
    lines += ["## Root mistakes and their knock-on effects", ""]
    groups = ordered(report)
    roots = [pairs for kind, pairs in groups if kind == "root"]
    if not roots:
        lines += ["None.", ""]
    for pairs in roots:
        result, f = pairs[0]
        lines += [f"### Line {result.equation.line}: `{_cell(result.label)}` — {f.kind} on "
                  f"`{_cell(f.quantity)}` ({f.severity})", ""]
        explanation = f.detail or "the coefficients differ"
        lines += [f"{explanation}. Hand `{_cell(f.hand)}`, model `{_cell(f.model)}`; size "
                  f"{_size(f.size)} at {f.point}." + (f" Effect: {_effect(f)}." if f.effect
                                                      else ""), ""]
        merged = [(r, g) for r, g in pairs[1:] if g.merged]
        if merged:
            lines += ["The other half of this finding:", ""]
            lines += _finding_rows(merged)
            lines.append("")
        if len(pairs) > 1 + len(merged):
            lines += ["Knock-on findings:", ""]
            lines += _finding_rows(pairs[1 + len(merged):])
            lines.append("")
    if report.omissions:
        lines += ["## Undeclared dropped variations", ""]
    for omission, pairs in omission_groups(report):
        lines += [f"### {_cell(omission.title[0].upper() + omission.title[1:])} "
                  f"({omission.severity})", ""]
        lines += [_cell(omission_text(omission)), "", "Its findings:", ""]
        lines += _finding_rows(pairs)
        lines.append("")
    for kind, pairs in groups:
        if kind == "root":
            continue
        if kind == "knock-on" and not pairs:
            continue
        lines += [f"## {SECTION_TITLES[kind]}", ""]
        lines += _finding_rows(pairs, roots=True) if pairs else ["None."]
        lines.append("")
    if report.idle_declarations:
        lines += ["Declared simplifications that explain no finding: "
                  + "; ".join(report.idle_declarations) + ".", ""]
    lines += ["## Equation by equation", ""]
    for index, title in enumerate(report.sections):
        results = [r for r in report.results if r.equation.section == index]
        if not results:
            continue
        lines += [f"### {title}", "", "| line | equation | compared with | status | notes |",
                  "|---:|---|---|---|---|"]
        for r in results:
            lines.append(f"| {r.equation.line} | {_code(r.label)} | {_cell(r.target)} | "
                         f"{r.status} | {_cell(status_notes(r))} |")
        lines.append("")
    lines += ["## How the comparison was made", "", "Reference points:", "",
              "| point | motion |", "|---|---|"]
    lines += [f"| {_cell(p.label)} | {_cell(p.description)} |" for p in report.points]
    if report.skipped_motions:
        lines += ["", "Motions not flown: " + "; ".join(report.skipped_motions) + "."]
    lines += ["", "Error quantities and their typical magnitudes:", "",
              "| quantity | unit | typical magnitude | stands for |", "|---|---|---|---|"]
    lines += [f"| `{b.name}` | {b.unit} | {b.magnitude_text} | "
              f"{', '.join(f'`{s}`' for s in b.stands_for)} |" for b in report.basis]
    if report.out_of_scope:
        lines += ["", out_of_scope_text(report.out_of_scope)]
    if report.from_model:
        lines += ["", FROM_MODEL_TEXT, ""]
        lines += [f"- `{k}` (needed by lines {', '.join(map(str, v))})"
                  for k, v in report.from_model.items()]
    if report.unused:
        lines += ["", "Hand-only definitions no line uses: " + ", ".join(report.unused) + "."]
    lines += ["", "## Input problems", ""]
    lines += [f"- {p}" for p in report.problems] if report.problems else ["None."]
    return "\n".join(lines) + "\n"


QUANTITY_COLUMN = (18, 32)
"""Narrowest and widest quantity column of the terminal table (characters): as wide as
its longest entry within these (``delta_v_N -> delta_v_E`` whole, not ``delta_v_N ->
delta``)."""


def _terminal_row(result: EquationResult, f: Finding, indent: str = "",
                  quantity: int = QUANTITY_COLUMN[0]) -> list[str]:
    head = (f"{indent}{result.equation.line:>4}  {result.label[:22]:<22} "
            f"{f.quantity[:quantity]:<{quantity}} {f.kind[:24]:<24} {f.severity:<21} "
            f"{_size(f.size)}")
    explanation = f.detail
    if f.roots and f.role == cl.KNOCK_ON:
        explanation = f"from {', '.join(f.roots)}" + (f"; {explanation}" if explanation
                                                       else "")
    out = [head]
    if explanation:
        out.append(f"{indent}      {explanation}")
    if f.effect:
        out.append(f"{indent}      effect: {_effect(f)}")
    return out


def to_terminal(report: CheckReport, width: int = 100) -> str:
    """The findings top-down (roots with their knock-ons, declared drops, small drops),
    each with its explanation, under the typical magnitudes and a short legend
    (:func:`legend`), and the summary line."""
    narrow, wide = QUANTITY_COLUMN
    q = min(wide, max([narrow] + [len(f.quantity) for _, f in report.findings]))
    header = (f"{'line':>4}  {'equation':<22} {'quantity':<{q}} {'what':<24} {'class':<21} "
              "size")
    rows = [f"typical magnitudes: {report.magnitudes}", *legend(report)]
    if report.scope:
        rows.append(f"scope: {report.scope}")
    if report.skipped_motions:
        rows.append("motions not flown: " + "; ".join(report.skipped_motions))
    rows += [header, "-" * min(width, len(header) + 8)]
    titles = {"root": "root mistake", "knock-on": "knock-on findings",
              "declared": "declared drops", "dropped": "other small drops"}
    groups = ordered(report)
    split = sum(1 for kind, _ in groups if kind == "root")
    for kind, pairs in groups[:split]:
        result, f = pairs[0]
        rows.append(f"[{titles[kind]}]")
        rows += _terminal_row(result, f, quantity=q)
        for r, g in pairs[1:]:
            rows += _terminal_row(r, g, indent="    ", quantity=q)
    for omission, pairs in omission_groups(report):  # after the roots, before the drops
        rows.append(f"[undeclared dropped variation, {omission.severity}, size "
                    f"{_size(omission.size)}]")
        rows.append(f"      {omission.title}")
        rows.append(f"      declare it with: {omission.advice}")
        for r, g in pairs:
            rows += _terminal_row(r, g, indent="    ", quantity=q)
    for kind, pairs in groups[split:]:
        if pairs:
            rows.append(f"[{titles[kind]}]")
            for r, g in pairs:
                rows += _terminal_row(r, g, quantity=q)
    if not report.findings:
        rows.append("  (no discrepancies)")
    for text in report.idle_declarations:
        rows.append(f"declaration explains nothing: {text}")
    if report.scope_advice:
        rows.append(f"static base? {report.scope_advice.replace('`', '')}")
    if report.unchecked_sources:
        rows.append(UNCHECKED + ", ".join(report.unchecked_sources))
    for problem in report.problems:
        rows.append(f"input: {problem}")
    rows.append(summary_line(report))
    return "\n".join(rows)


def to_json(report: CheckReport) -> dict[str, Any]:
    """A JSON-serialisable view of the report."""
    def finding(f: Finding) -> dict[str, Any]:
        return {"quantity": f.quantity, "kind": f.kind, "class": f.severity,
                # 9 significant digits: sizes are measured in floating point, and forms
                # of the same equation (LaTeX, text) may differ in the last bits
                "size": None if math.isinf(f.size) else float(f"{f.size:.9g}"),
                "point": f.point, "role": f.role, "roots": list(f.roots),
                "hand": f.hand, "model": f.model, "detail": f.detail,
                "effect": {k: (float(f"{v:.6g}") if isinstance(v, float) else v)
                           for k, v in f.effect.items()},
                "pair": (None if not f.pair
                         else {"line": f.pair[0], "quantity": f.pair[1], "merged": f.merged})}

    return {
        "model": report.model,
        "file": report.hand_name,
        "format": report.hand_format,
        "threshold": report.threshold,
        "exit_status": report.exit_status,
        "summary": summary_counts(report),
        "equations": [{"line": r.equation.line, "column": r.equation.column,
                       "section": report.sections[r.equation.section],
                       "equation": r.label, "compared_with": r.target, "status": r.status,
                       "notes": r.notes, "findings": [finding(f) for f in r.findings]}
                      for r in report.results],
        "problems": [{"line": p.line, "column": p.column, "message": p.message}
                     for p in report.problems],
        "points": [{"label": p.label, "description": p.description} for p in report.points],
        "basis": [{"name": b.name, "unit": b.unit, "magnitude": b.magnitude,
                   "stands_for": list(b.stands_for)} for b in report.basis],
        "out_of_scope": report.out_of_scope,
        "unchecked_sources": report.unchecked_sources,
        "from_model": report.from_model,
        "magnitudes": report.magnitudes,
        "scope": report.scope,
        "skipped_motions": report.skipped_motions,
        "declarations": report.declarations,
        "idle_declarations": report.idle_declarations,
        "scope_advice": report.scope_advice or None,
        "omissions": [{"reference": o.reference, "variations": list(o.variations),
                       "quantities": list(o.quantities), "along": list(o.along),
                       "lines": list(o.lines), "class": o.severity,
                       "size": float(f"{o.size:.9g}"), "point": o.point,
                       "description": o.title, "neglect": o.neglect,
                       "at_rest": o.at_rest}
                      for o in report.omissions],
    }
