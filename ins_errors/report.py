"""Write a scenario's results as a report folder: Markdown, HTML, plots and JSON.

The folder holds ``report.md`` (tables, plots, and the model's error equations as used),
``report.html`` (the same as one self-contained page: formulas as MathML, plots
embedded, nothing loaded from the network), one ``case_<k>.png`` per case,
``results.json`` (metrics, SI) and the curves themselves as ``curves.csv`` and
``curves.mat`` (see :mod:`ins_errors.export`).
"""

from __future__ import annotations

import base64
import html
import mimetypes
import re
from functools import lru_cache
from importlib import resources
from pathlib import Path

from ins_errors.json_output import dumps
from ins_errors.markdown_cells import one_line, table_cell
from ins_errors.model_parameters import parameters_record, parameters_used
from ins_errors.numeric.model import Model, load_model
from ins_errors.output import OutputFolder
from ins_errors.scenario import ScenarioResult
from ins_errors.units import format_duration

_MATH = re.compile(r"\$\$(.+?)\$\$", re.S)
_INLINE_MATH = re.compile(r"(?<!\$)\$([^$\n]+?)\$(?!\$)")
_LINK = re.compile(r'(<a [^>]*href=")([^"]*)(")')
_SCHEME = re.compile(r"^([^:/?#]*):")
_SAFE_SCHEMES = ("http", "https", "mailto")


def _safe_link(match: re.Match) -> str:
    """A link's tag, its target ``#`` if it has a scheme other than http(s) or mailto
    (``javascript:``, also written with entities or blanks, as a browser reads it)."""
    target = re.sub(r"[\x00-\x20]", "", html.unescape(match.group(2)))
    scheme = _SCHEME.match(target)
    if scheme is None or scheme.group(1).lower() in _SAFE_SCHEMES:
        return match.group(0)
    return f"{match.group(1)}#{match.group(3)}"


def _equations_document(model: Model) -> str:
    """The generated error_equations.md of a model, without its banner and title."""
    text = (model.folder / "error_equations.md" if model.folder is not None else
            resources.files("ins_errors.generated").joinpath(model.name, "error_equations.md"))
    body = text.read_text(encoding="utf-8")
    body = re.sub(r"^<!--.*?-->\s*", "", body, flags=re.S)
    return re.sub(r"^# .*\n", "", body, count=1)


def _run_line(result) -> str:
    """``"orthodromic: great circle ...; 168 h, τ = 1 s, rk4"``: the model, motion and
    run of a report's plots (as ``compare`` titles its own)."""
    s = result.scenario
    return (f"{load_model(s.model).name}: {result.motion_description}; "
            f"{format_duration(s.duration)}, τ = {s.step:g} s, {s.method}")


def report_markdown(result: ScenarioResult, plots: list[str]) -> str:
    """The report as Markdown."""
    from ins_errors.numeric.compare import markdown_summary, markdown_table

    s = result.scenario
    model = load_model(s.model)
    comparisons = result.comparisons
    lines = [f"# {one_line(s.title)}", ""]
    if s.description:
        lines += [s.description, ""]
    lines += [
        "| setting | value |", "|---|---|",
        f"| model | `{table_cell(model.name)}` |",
        f"| motion | {table_cell(result.motion_description)} |",
        f"| duration | {format_duration(s.duration)} |",
        f"| step τ | {s.step:g} s ({'rectangle method' if s.method == 'euler' else 'RK4'}) |",
        f"| recorded every | {s.record:g} s |",
        *([f"| platform | {'exact rotation' if s.platform == 'exact' else 'small-angle matrix'} |"]
          if has_platform_variants(model) else []),
        f"| Earth model | {table_cell(s.ellipsoid or 'model default')} |",
        f"| parameters | {_parameters_text(model, s)} |",
        f"| truth | {truth_text(s.truth, result.truth_used)} |",
        "",
        "Direct = real-work minus ideal-work run; linear = the derived first-order error "
        "equations along the same motion; refined = with the second-order terms. A ratio is "
        "the largest difference from the direct run divided by the largest direct error; "
        "the worst ratios are taken over the quantities marked *judged*: each one whose "
        "direct error is above the rounding floor of its unit and which the linear model "
        "moves at first order (*2nd order*: it gives 0 there). "
        + integration_runs_text(result.comparisons, s.step),
        "",
        "## Summary", "",
        markdown_summary(comparisons),
    ]
    for k, (comparison, plot) in enumerate(zip(comparisons, plots, strict=True), 1):
        lines += [f"## Case {k}: {table_cell(comparison.label)}", "", f"![case {k}]({plot})", "",
                  markdown_table(_selected(comparison, s.quantities))]
    lines += ["## Equations used", "", _equations_document(model)]
    return "\n".join(lines) + "\n"


def integration_runs_text(comparisons, step: float) -> str:
    """The sentence of the report on the runs the integration-error estimate made: the
    steps compare recorded as completed
    (:attr:`~ins_errors.numeric.compare.Comparison.integration_steps`), the pair's other
    run first, then the one that gives the scheme's observed order.

    Parameters
    ----------
    comparisons : sequence of Comparison
        The scenario's cases (one batch: the same reruns for each).
    step : float
        Step τ of the scenario's runs, s.
    """
    made: list[float] = []
    for comparison in comparisons:
        made += [s for s in comparison.integration_steps if s not in made]
    refined = any(m.refined_integration_error is not None
                  for comparison in comparisons for m in comparison.metrics)
    curves = "direct, linear and refined" if refined else "direct and linear"
    start = f"The integration error of the {curves} curves"
    if not made:
        return (f"{start} is not estimated: no run at another step was made or completed "
                "(the cases' warnings say why).")
    names = {0.5: "half the step", 2.0: "twice the step", 4.0: "four times the step"}
    other = made[0]
    runs = f"the same runs at {names.get(other / step, 'another step')} ({other:g} s"
    runs += (f"; a third at {made[1]:g} s gives the scheme's observed order)"
             if len(made) > 1 else "; no third run gave the scheme's observed order)")
    return f"{start} is estimated by {runs} (Richardson) and shown beside the differences."


def truth_text(setting: str, used: str) -> str:
    """The truth setting and, where the library chose, the truth it chose (``auto
    (interpolated)``; a static base is exact whatever the setting)."""
    if not used or used == setting:
        return setting
    return f"{setting} ({'static base: exact' if used == 'static' else used})"


def has_platform_variants(model: Model) -> bool:
    """True for a model with a platform whose kinematics a run chooses (exact rotation or
    the source documents' small-angle matrix); a strapdown model has none."""
    return model.has_small_angle_platform


def _used(model: Model, scenario) -> dict[str, dict[str, object]]:
    """Every parameter's value in the scenario's runs (SI, with unit)."""
    p = model.parameter_vector(ellipsoid=scenario.ellipsoid, **scenario.parameters)
    return parameters_used(model, p)


def _parameters_text(model: Model, scenario) -> str:
    """Every parameter's value in the run (SI; an angle in degrees), the ones the scenario
    set marked."""
    from ins_errors.commands.models import parameter_text

    shown = []
    for name, entry in _used(model, scenario).items():
        mark = " (set)" if name in scenario.parameters else ""
        shown.append(f"`{name}` = {parameter_text(entry['value'], entry['unit'])}{mark}")
    given = "the Earth model and model defaults" if scenario.ellipsoid else "model defaults"
    return ", ".join(shown) + (f" (the others: {given})" if scenario.parameters
                               else f" ({given})")


def _selected(comparison, quantities):
    if quantities is None:
        return comparison
    from dataclasses import replace

    return replace(comparison, metrics=[comparison.metric(q) for q in quantities])


@lru_cache(maxsize=2048)
def _mathml(latex: str, display: bool) -> str:
    """LaTeX to MathML (latex2mathml), or the escaped LaTeX in ``<code>`` if it fails.

    Kept per process: the reports of one session repeat the same model equations
    (~2.5 ms CPU each to convert), and the text depends on nothing but the arguments.
    """
    from latex2mathml.converter import convert

    try:
        return convert(latex, display="block" if display else "inline")
    except Exception:  # latex2mathml raises several types on macros it does not know
        code = f"<code>{html.escape(latex)}</code>"
        return f"<div>{code}</div>" if display else code


def _embedded_images(body: str, folder: Path | None) -> str:
    """Replace ``<img src="name.png">`` of files in ``folder`` by data URIs."""
    if folder is None:
        return body

    def inline(match: re.Match) -> str:
        path = folder / html.unescape(match.group(2))
        if "/" in match.group(2) or not path.is_file():
            return match.group(0)
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        kind = mimetypes.guess_type(path.name)[0] or "application/octet-stream"
        return f'{match.group(1)}data:{kind};base64,{data}"'

    return re.sub(r'(<img [^>]*src=")([^"]+)"', inline, body)


def markdown_to_html(text: str, title: str, images: Path | None = None) -> str:
    """Render Markdown (with tables and $$ math) to one self-contained HTML page.

    Formulas become MathML (read by every current browser, no script, no network);
    images found in the folder ``images`` are embedded as data URIs, so the page can be
    mailed or opened offline on its own. HTML written in the Markdown (a case label
    ``a<b & c>d`` or ``<script>...``: the reports hold no HTML of their own) is shown as
    text, never run or read as markup, and a link other than http(s), mailto or a
    relative one (``javascript:...``) loses its target.
    """
    import markdown

    math: list[str] = []

    def keep(match: re.Match, display: bool) -> str:
        math.append(_mathml(match.group(1).strip(), display))
        return f"MATHPLACEHOLDER{len(math) - 1}END"

    protected = _MATH.sub(lambda m: keep(m, True), text)
    protected = _INLINE_MATH.sub(lambda m: keep(m, False), protected)
    converter = markdown.Markdown(extensions=["tables", "fenced_code"])
    converter.preprocessors.deregister("html_block")  # raw HTML: escaped as text
    converter.inlinePatterns.deregister("html")
    body = _LINK.sub(_safe_link, converter.convert(protected))
    body = re.sub(r"MATHPLACEHOLDER(\d+)END", lambda m: math[int(m.group(1))], body)
    body = _embedded_images(body, images)
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<title>{html.escape(title)}</title>\n"
        "<style>body{font-family:sans-serif;max-width:70em;margin:2em auto;"
        "padding:0 1em}table{border-collapse:collapse}td,th{border:1px solid #ccc;"
        "padding:2px 6px;font-size:90%}img{max-width:100%}math[display=block]"
        "{margin:0.6em 0;overflow-x:auto}</style>\n</head>\n<body>\n"
        f"{body}\n</body>\n</html>\n"
    )


def write_report(result: ScenarioResult, folder: str | Path, force: bool = False,
                 progress: bool = True) -> Path:
    """Write the report folder and return the path of ``report.md``.

    Parameters
    ----------
    result : ScenarioResult
        What :func:`~ins_errors.scenario.run_scenario` returned.
    folder : str or Path
        The report folder (see :class:`~ins_errors.output.OutputFolder`: an earlier
        report there is replaced, stale files of it removed; a folder of someone else's
        files is refused unless ``force``).
    force : bool
        Write into a non-empty folder that ins-errors did not write.
    progress : bool
        Show a one-line status (what is being written, elapsed time) while the plots,
        the pages and the curve files are written; on a terminal only, and only for a
        part that takes more than half a second (a week's curves: over a minute).

    Raises
    ------
    InsErrorsError
        If the folder cannot be written or must not be.
    """
    from ins_errors.export import write_curves
    from ins_errors.numeric.plots import plot_comparisons, shared_quantities
    from ins_errors.progress import stage

    with OutputFolder(folder, force=force) as out:   # taken back if it stops
        plots = [f"case_{k}.png" for k in range(1, len(result.comparisons) + 1)]
        with stage(f"drawing {plots[0] if len(plots) == 1 else f'{len(plots)} plots'} in "
                   f"{out.path}", enabled=progress):
            plot_comparisons(result.comparisons, [out.file(name) for name in plots],
                             quantities=result.scenario.quantities
                             or shared_quantities(result.comparisons),
                             titles=[f"{result.scenario.title}\n{c.label}\n"
                                     f"{_run_line(result)}" for c in result.comparisons])
        with stage(f"writing report.md, report.html and results.json in {out.path}",
                   enabled=progress):
            text = report_markdown(result, plots)
            out.write_text("report.md", text)
            out.write_text("report.html", markdown_to_html(text, result.scenario.title, out.path))
            model = load_model(result.scenario.model)
            summary = {"title": result.scenario.title, "model": model.name,
                       "motion": result.motion_description, "duration_s": result.scenario.duration,
                       "step_s": result.scenario.step, "record_s": result.scenario.record,
                       "method": result.scenario.method, "truth": result.scenario.truth,
                       "truth_used": result.truth_used,
                       "parameters": parameters_record(model, result.scenario.parameters),
                       "parameters_used": _used(model, result.scenario),
                       "units": "SI: rad, rad/s, m/s, m, s; every value below is in SI",
                       "curves": {"csv": "curves.csv", "mat": "curves.mat"},
                       "cases": [c.to_dict() for c in result.comparisons]}
            out.write_text("results.json", dumps(summary) + "\n")
        with stage(f"writing curves.csv and curves.mat in {out.path}", enabled=progress):
            write_curves(out, result.comparisons)
    return out.path / "report.md"
