"""``ins-errors budget MODEL``: error budget of a model against an accuracy spec."""

from __future__ import annotations

import argparse
import sys

from ins_errors.json_output import emit
from ins_errors.user_paths import expand_user


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "budget", help="allocate allowed error magnitudes against an accuracy spec",
        description="Propagate every error source's covariance through the model's linear "
                    "error equations along the spec's motion, split each spec item's "
                    "variance among the sources (equal shares unless the spec weights or "
                    "fixes some), report the allowed magnitudes and the item binding each "
                    "source, and optionally check the result with direct Monte Carlo runs.")
    parser.add_argument("model", nargs="?",
                        help="model name (e.g. orthodromic) or model file (my_ins.py)")
    parser.add_argument("--schema", action="store_true",
                        help="print the JSON Schema of accuracy-spec files (for editors) "
                             "and exit")
    parser.add_argument("--spec", type=expand_user,
                        help="spec file (TOML with units); default: the built-in 802m spec")
    parser.add_argument("--parameter", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="model parameter with unit, as for 'ins-errors compare', e.g. "
                             "strapdown_ned's k_h1=0.0047/s (repeatable; used by the "
                             "covariance and the Monte Carlo runs; overrides the spec's "
                             "[parameters])")
    parser.add_argument("--plot", type=expand_user, metavar="PNG",
                        help="write a chart of the allocation: each source's allowed "
                             "magnitude (or the spec's fixed one, hatched) with its largest "
                             "share of every item (the binding one named), and every item's "
                             "worst value against its limit")
    parser.add_argument("--plot-time", type=expand_user, metavar="PNG",
                        help="write every spec item's value over the operating time at the "
                             "allocated magnitudes (the fixed sources alone where they "
                             "exceed the spec), one panel per item in the unit of its "
                             "limit, the limit as a line and the check times marked")
    parser.add_argument("--report", type=expand_user, metavar="FILE.md",
                        help="write a Markdown report for a design review: the spec, every "
                             "source's magnitude and binding item, every item against its "
                             "limit, the notes and warnings, and the --monte-carlo check")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.add_argument("--no-progress", action="store_true",
                        help="never show progress (the covariance propagation's status and "
                             "the --monte-carlo runs' bar)")
    parser.add_argument("--fill", action="store_true",
                        help="scale the free sources until the tightest item is met exactly")
    parser.add_argument("--monte-carlo", type=int, metavar="N",
                        help="also run N direct simulations at the allocated magnitudes "
                             "(random constants only: not with a spec that makes a source "
                             "white or Gauss-Markov noise)")
    parser.add_argument("--mc-duration", help="with --monte-carlo: length of each run "
                                              "(default 1 h, or the spec's operating time "
                                              "if shorter)")
    parser.add_argument("--mc-step",
                        help="with --monte-carlo: integration step of the runs (default "
                             "0.01 s, 100 Hz)")
    parser.add_argument("--seed", type=int, help="with --monte-carlo: random seed of the "
                                                 "runs (default 0)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run the Monte Carlo tasks on a running Dask scheduler, e.g. "
                             "tcp://HOST:8786 (default: a local cluster of this machine's "
                             "cores, or a process pool without Dask)")
    parser.add_argument("--engine", choices=("auto", "dask", "pool", "serial"),
                        help="where the Monte Carlo tasks run (default: "
                                             "dask when installed, else a process pool)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="workers of the local cluster or pool (default: CPU cores)")
    parser.add_argument("--at", metavar="TIMES",
                        help="comma-separated times (e.g. '1 h, 8 h'): per-source 1σ "
                             "contributions, at the allocated magnitudes, to every "
                             "navigation error at those times (positions in metres north "
                             "and east)")
    parser.add_argument("--plot-at", type=expand_user, metavar="PNG",
                        help="with --at: write a stacked plot of those contributions")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from ins_errors.analysis import budget as bd
    from ins_errors.analysis import budget_report as rep
    from ins_errors.checker.strapdown_description import UnspannedStateError
    from ins_errors.errors import InsErrorsError
    from ins_errors.model_parameters import parameters_record
    from ins_errors.numeric.model import load_model
    from ins_errors.specs import SpecError, default_spec_path, load_spec, spec_parameters

    if args.schema:
        from ins_errors.spec_schema import json_schema

        print(json_schema(), end="")
        return 0
    if args.model is None:
        raise SpecError("budget needs a MODEL (or --schema)")
    if args.plot or args.plot_at or args.plot_time:
        from ins_errors.output import require_matplotlib

        require_matplotlib("--plot")
    if args.plot_at and not args.at:
        raise SpecError("--plot-at needs --at TIMES")
    _check_monte_carlo_options(args)
    times = _at_times(args.at) if args.at is not None else None
    from ins_errors.output import check_figure

    for target in (args.plot, args.plot_at, args.plot_time):
        if target:
            check_figure(target)
    if args.report is not None:
        _check_report(args.report)
    model = load_model(args.model)
    path = args.spec or default_spec_path()
    if args.spec is None and not path.exists():
        raise SpecError("no --spec given and the built-in 802m spec is missing")
    spec = load_spec(path)
    if times is not None:   # before any work
        from ins_errors.analysis.budget_contributions import check_times

        check_times(spec, times)
    parameters = spec_parameters(spec, model, args.parameter)
    p = model.parameter_vector(**parameters)
    if args.fill:
        spec = replace(spec, fill=True)
    if args.monte_carlo is not None:   # before the covariance is computed
        from ins_errors.analysis.monte_carlo import refuse_noise_sources

        refuse_noise_sources([(s.name, s.statistics) for s in bd.resolve_sources(model, spec)],
                             "--monte-carlo")
        mc_duration(spec, args)
    from ins_errors.progress import stage

    with stage(f"propagating the covariance of {len(model.sources)} sources",
               enabled=not args.no_progress):
        try:
            unit = bd.unit_budget(model, spec, p=p)
        except UnspannedStateError as unspanned:  # its words are the matrix check's
            raise InsErrorsError(unspanned.budget_message()) from None
        growth = bd.growth_warning(model, unit)
        warnings = [] if growth is None else [growth]
        try:
            allocation = bd.allocate(unit)
        except bd.SpecExceededError as exceeded:
            _warn(warnings)
            _linear_warning(unit, exceeded.values, warnings)
            return _report_exceeded(args, model, exceeded,
                                    parameters_record(model, parameters), warnings, times)
        refusal = bd.growth_refusal(allocation)
        if refusal is not None:   # the growth's line says it all: no warning before it
            raise bd.BudgetError(refusal)
        _warn(warnings)
        _linear_warning(unit, allocation.values, warnings)
        vertical = bd.vertical_channel_note(model, allocation)
        if vertical is not None:
            print(f"ins-errors: warning: {vertical}", file=sys.stderr)
            warnings.append(vertical)
    data = rep.report(allocation)
    data["parameters"] = parameters_record(model, parameters)
    data["warnings"] = warnings
    _between_warnings(data)
    if args.plot:
        rep.plot(allocation, args.plot)
    if args.plot_time:
        _plot_time(allocation, args.plot_time)
    if args.monte_carlo is not None:
        data["monte_carlo"], mc_seconds, estimate_seconds = _monte_carlo(
            model, spec, allocation, args, p)
        mc = data["monte_carlo"]
        estimate = mc.get("integration_error")
        if estimate and estimate["largest"] > mc["relative_sampling_error"]:
            from ins_errors.numeric.accuracy import typable_step

            # the rectangle method's error is proportional to the step: half the sampling
            # error at most, with a step that divides the analysis step
            _, better = typable_step(mc["step_s"] * mc["relative_sampling_error"]
                                     / (2.0 * estimate["largest"]), spec.step)
            text = (f"the Monte Carlo runs' integration error (up to "
                    f"{100 * estimate['largest']:.2g} % on a row) exceeds their sampling "
                    f"error (±{100 * mc['relative_sampling_error']:.2g} %): the ratios "
                    f"measure the rectangle method as much as the covariance; run them "
                    f"with a smaller step, e.g. --mc-step \"{better} s\"")
            print(f"ins-errors: warning: {text}", file=sys.stderr)
            data["warnings"].append(text)
    outputs = None
    if times is not None:
        outputs = _contributions(model, allocation, times, args.plot_at, data)
    _write_report(args, data, spec)
    if args.json:
        emit(data, ensure_ascii=False)
        return 0
    print(rep.table(data))
    print()
    print(rep.contribution_table(allocation))
    if outputs is not None:
        print()
        print(rep.output_table(outputs))
    _announce(args)
    if args.monte_carlo is not None:
        mc = data["monte_carlo"]
        print()
        print("\n".join(rep.monte_carlo_lines(mc)))
        header, rows = rep.monte_carlo_cells(mc, spec)
        widths = [40, 16, 16, *([11] * (len(header) == 5)), 7]
        for cells in [header, *rows]:
            print(f"{cells[0]:<{widths[0]}} " + " ".join(
                f"{cell:>{w}}" for cell, w in zip(cells[1:], widths[1:], strict=True)))
        if any(r["ratio"] is None for r in mc["rows"]):
            print(f"–: {rep.NO_RATIO}")
        # on the terminal only: the JSON is reproducible
        print(f"({mc_seconds:.1f} s, and {estimate_seconds:.1f} s for the integration "
              "error)" if mc.get("integration_error") else f"({mc_seconds:.1f} s)")
    return 0


def _warn(warnings: list[str]) -> None:
    """Print the warnings gathered so far on stderr, one line each."""
    for text in warnings:
        print(f"ins-errors: warning: {text}", file=sys.stderr)


def _linear_warning(budget, values, warnings: list[str]) -> None:
    """Warn (stderr and ``warnings``) when a reported figure lies beyond the linear
    error model (:func:`~ins_errors.analysis.budget.linear_range_warning`)."""
    from ins_errors.analysis import budget as bd

    text = bd.linear_range_warning(budget, values)
    if text is not None:
        print(f"ins-errors: warning: {text}", file=sys.stderr)
        warnings.append(text)


def _between_warnings(data: dict) -> None:
    """Warn (stderr and ``data["warnings"]``) of every item that passes its limit
    between its check times (:func:`~ins_errors.analysis.budget_report.
    between_checks_warnings`)."""
    from ins_errors.analysis import budget_report as rep

    for text in rep.between_checks_warnings(data):
        print(f"ins-errors: warning: {text}", file=sys.stderr)
        data["warnings"].append(text)


def _report_exceeded(args: argparse.Namespace, model, exceeded, parameters: dict,
                     warnings: list[str], times: list[float] | None) -> int:
    """A spec the fixed sources alone use up: the rows with their ratios (JSON or
    text), exit status 1 (the answer is "exceeded"; 2 stays for bad input).

    What still makes sense is made from the fixed sources alone: the --at breakdown
    (which bought part breaks the spec) and its --plot-at, the --plot chart and the
    --plot-time curves against the spec, the --report; --monte-carlo, which checks an
    allocation, is skipped with one line saying so.
    """
    from ins_errors.analysis import budget_report as rep

    data = {**rep.exceeded_report(exceeded), "parameters": parameters, "warnings": warnings}
    _between_warnings(data)
    fixed = rep.fixed_allocation(exceeded)
    if args.monte_carlo is not None:
        text = ("--monte-carlo skipped: the fixed sources alone exceed the spec, so there "
                "is no allocation for direct runs to check")
        print(f"ins-errors: warning: {text}", file=sys.stderr)
        data["warnings"].append(text)
    if args.plot:
        rep.plot(fixed, args.plot)
    if args.plot_time:
        _plot_time(fixed, args.plot_time, fixed_only=True)
    outputs = None
    if times is not None:
        outputs = _contributions(model, fixed, times, args.plot_at, data, fixed_only=True)
    _write_report(args, data, exceeded.budget.spec)
    if args.json:
        emit(data, ensure_ascii=False)
        return 1
    print(rep.exceeded_table(data))
    if outputs is not None:
        print()
        print(rep.output_table(outputs))
    _announce(args)
    return 1


def _contributions(model, allocation, times: list[float], plot_at: str | None,
                   data: dict, fixed_only: bool = False) -> dict:
    """The --at breakdown (:mod:`~ins_errors.analysis.budget_contributions`),
    labelled with the magnitudes it uses, its σ level and its arrays' axes; drawn to
    ``plot_at`` if given; put in ``data["contributions"]`` as JSON."""
    from ins_errors.analysis import budget_report as rep
    from ins_errors.analysis.budget_contributions import output_contributions

    budget = allocation.budget
    outputs = output_contributions(model, allocation, times)
    outputs["magnitudes"] = rep.magnitudes_note(allocation, fixed_only)
    if plot_at:
        k = budget.spec.sigma_level
        level = "1σ" if k == 1 else f"1σ (the spec's items are {k:g}σ)"
        rep.plot_outputs(outputs, plot_at, title=(
            f"Contributions to the navigation errors: {budget.spec.title}\n"
            f"{budget.system.labels.get('trajectory', '')}\n"
            f"{level}, at {outputs['magnitudes']}"))
    data["contributions"] = {
        **outputs, "sigma_level": 1.0,
        "axes": {"std": ["times_h", "quantities", "sources"],
                 "total": ["times_h", "quantities"]},
        "std": outputs["std"].tolist(), "total": outputs["total"].tolist()}
    return outputs


def _announce(args: argparse.Namespace) -> None:
    """Name the files written (text output only)."""
    written = [target for target in (args.plot, args.plot_at, args.plot_time) if target]
    if written or args.report:
        print()
    for target in written:
        print(f"plot written to {target}")
    if args.report:
        print(f"report written to {args.report}")


def _check_report(path: str) -> None:
    """Refuse, before any work, a --report name that is not Markdown or cannot be
    written (one line each)."""
    from pathlib import Path

    from ins_errors.analysis.budget_markdown import SUFFIXES
    from ins_errors.output import OutputError, check_file, shown

    suffix = Path(path).suffix
    if suffix.lower() not in SUFFIXES:
        instead = f", not {suffix}" if suffix else ""
        raise OutputError(f"cannot write the report {shown(path)}: the budget's report is "
                          f"Markdown, so end the name with .md{instead} (e.g. --report "
                          f"budget.md)")
    check_file(path)


def _write_report(args: argparse.Namespace, data: dict, spec) -> None:
    """Write --report: the Markdown of ``data`` (the JSON --json prints)."""
    if args.report is None:
        return
    from ins_errors.analysis.budget_markdown import markdown
    from ins_errors.output import write_text
    from ins_errors.specs import spec_label

    write_text(args.report, markdown(data, spec, spec_label(spec), args.model))


def _plot_time(allocation, path: str, fixed_only: bool = False) -> None:
    """Write --plot-time: every item over the operating time
    (:func:`~ins_errors.analysis.budget_time.plot_time`), titled with the spec, the
    motion, the σ level and the magnitudes used."""
    from ins_errors.analysis import budget_report as rep
    from ins_errors.analysis.budget_time import plot_time

    budget = allocation.budget
    spec = budget.spec
    exceeded = " — SPEC EXCEEDED" if fixed_only else ""
    plot_time(allocation, path, title=(
        f"Spec items over the operating time: {spec.title}{exceeded}\n"
        f"{budget.system.labels.get('trajectory', '')}\n"
        f"{_level_words(spec)}, at {rep.magnitudes_note(allocation, fixed_only)}"))


def _level_words(spec) -> str:
    """The spec's level in a title: ``kσ``, and what CEP items are (a CEP has no σ)."""
    from ins_errors.analysis.budget_report import CEP_WORDS

    level = f"{spec.sigma_level:g}σ"
    if any(item.combine == "cep" for item in spec.items):
        level += f" ({CEP_WORDS})"
    return level


MC_DEFAULTS = {"mc_duration": "1 h", "mc_step": "0.01 s", "seed": 0, "engine": "auto",
               "scheduler": None, "workers": None}
"""The Monte Carlo options and their values when --monte-carlo is given without them."""


def _check_monte_carlo_options(args: argparse.Namespace) -> None:
    """Refuse Monte Carlo options without --monte-carlo, and a count below 2; fill in
    the defaults of the ones not given."""
    from ins_errors.specs import SpecError

    given = [name for name in MC_DEFAULTS if getattr(args, name) is not None]
    if args.monte_carlo is None:
        if given:
            option = "--" + given[0].replace("_", "-")
            raise SpecError(f"{option} applies to the Monte Carlo runs: add --monte-carlo N")
        return
    if args.monte_carlo < 2:
        raise SpecError(f"--monte-carlo needs at least 2 runs, got {args.monte_carlo}")
    if args.workers is not None and args.workers < 1:
        raise SpecError(f"--workers must be at least 1, got {args.workers}")
    args.mc_defaulted = [name for name in MC_DEFAULTS if name not in given]
    for name, value in MC_DEFAULTS.items():
        if getattr(args, name) is None:
            setattr(args, name, value)


def _at_times(text: str) -> list[float]:
    """The times of --at, s (comma-separated, each with a unit)."""
    from ins_errors.specs import SpecError
    from ins_errors.units import parse_quantity

    parts = [t.strip() for t in text.split(",")]
    if not any(parts):
        raise SpecError(f"--at needs times with units, e.g. '1 h, 8 h'; got {text!r}")
    return [parse_quantity(t, "s", "--at") for t in parts if t]


def mc_duration(spec, args: argparse.Namespace) -> float:
    """The length of the Monte Carlo runs, s: --mc-duration checked against the spec.

    Raises
    ------
    SpecError
        A duration that is not > 0, not a whole number of analysis steps, longer than the
        operating time, or that ends before the spec's first row (the runs would check
        nothing: an empty table once).
    """
    from ins_errors.analysis import budget as bd
    from ins_errors.numeric.integrators import whole_steps
    from ins_errors.specs import SpecError
    from ins_errors.units import parse_quantity

    duration = parse_quantity(args.mc_duration, "s", "--mc-duration")
    if "mc_duration" in getattr(args, "mc_defaulted", ()):
        duration = min(duration, spec.operating_time)  # a spec shorter than the default
    if duration <= 0:
        raise SpecError(f"--mc-duration must be positive, got {args.mc_duration!r}")
    grid = spec.step
    if whole_steps(duration, grid) is None or duration > spec.operating_time:
        raise SpecError(f"--mc-duration must be a whole number of the spec's {grid:g} s "
                        f"analysis steps, at most the operating time "
                        f"({bd.format_time(spec.operating_time)}); got {args.mc_duration!r}")
    first, item = min((t, i.name) for i in spec.items for t in i.times)
    if duration < first * (1 - 1e-12):
        raise SpecError(f"--mc-duration {args.mc_duration!r} ends before the spec's first "
                        f"row ({item} at {bd.format_time(first)}): the runs would check no "
                        f"row; give at least {bd.format_time(first)}")
    return duration


def _monte_carlo(model, spec, allocation, args, p) -> tuple[dict, float]:
    """The Monte Carlo check of an allocation (JSON-ready; no wall-clock time in it, so
    identical runs give identical JSON) and the seconds its runs took."""
    import time

    import numpy as np

    from ins_errors.analysis import budget as bd
    from ins_errors.analysis import budget_report as rep
    from ins_errors.analysis.monte_carlo import direct_monte_carlo, sampling_error
    from ins_errors.numeric.integrators import whole_steps
    from ins_errors.specs import SpecError
    from ins_errors.units import parse_quantity

    duration = mc_duration(spec, args)
    step = parse_quantity(args.mc_step, "s", "--mc-step")
    if step <= 0:
        raise SpecError(f"--mc-step must be positive, got {args.mc_step!r}")
    grid = spec.step
    if whole_steps(grid, step) is None:
        raise SpecError(f"--mc-step must divide the spec's {grid:g} s analysis step; got "
                        f"{args.mc_step!r}")
    budget = allocation.budget
    sigma = {s.name: float(v) for s, v in zip(budget.sources, allocation.sigma, strict=True)
             if np.isfinite(v)}
    statistics = [st for st in budget.statistics(np.array([sigma.get(s.name, 0.0)
                                                           for s in budget.sources]))
                  if st.sigma > 0]
    trajectory = bd.spec_trajectory(model, spec, tau=step, duration=duration, p=p)
    start = time.perf_counter()
    errors = direct_monte_carlo(model, trajectory, statistics, args.monte_carlo,
                                seed=args.seed, record_interval=spec.step,
                                engine=args.engine, scheduler=args.scheduler,
                                workers=args.workers, progress=not args.no_progress)
    seconds = time.perf_counter() - start
    start = time.perf_counter()
    integration = _integration_error(model, spec, budget, errors, statistics, args, p, step,
                                     duration)
    extra = time.perf_counter() - start
    rows, values = bd.direct_rows(model, budget, errors)
    predicted = bd.evaluate(model, spec, sigma, p=p)
    lookup = {(r.item, r.time, r.component): v for r, v in zip(predicted.rows,
                                                               predicted.values, strict=True)}
    out = []
    for row, value in zip(rows, values, strict=True):
        cov = lookup[(row.item, row.time, row.component)]
        out.append({"row": row.label, "item": row.item, "time_h": row.time / 3600,
                    "unit": spec.item(row.item).kind.unit, "sigma_level": spec.sigma_level,
                    "covariance": float(cov), "monte_carlo": float(value),
                    "ratio": float(value / cov) if cov > 0 else None})
        if cov <= 0:
            out[-1]["note"] = rep.NO_RATIO
        if integration is not None:
            error = integration["rows"].get((row.item, row.time, row.component))
            out[-1]["integration_error"] = error
    result = {"runs": args.monte_carlo, "seed": args.seed, "sigma_level": spec.sigma_level,
              "duration_h": duration / 3600, "step_s": step,
              "method": "euler", "relative_sampling_error": sampling_error(args.monte_carlo),
              "rows": out}
    if integration is not None:
        result["integration_error"] = {k: v for k, v in integration.items() if k != "rows"}
    return result, seconds, extra


MC_ESTIMATE_RUNS = 16
"""Runs (the first ones) repeated at another step to estimate the integration error."""


def _integration_error(model, spec, budget, errors, statistics, args, p, step: float,
                       duration: float) -> dict | None:
    """Integration error of the direct runs' spec rows by step doubling.

    The first :data:`MC_ESTIMATE_RUNS` draws (all when fewer) run again at 2τ (at τ/2
    when 2τ does not divide the recording interval) and the Richardson estimate
    (:func:`ins_errors.analysis.budget.integration_errors`) gives each row's relative
    bias from the scheme. Returns None for a run of one recorded step.
    """
    import numpy as np

    from ins_errors.analysis import budget as bd
    from ins_errors.analysis.monte_carlo import DirectErrors, direct_monte_carlo
    from ins_errors.numeric.integrators import whole_steps

    stride = whole_steps(spec.step, step)
    if duration < 2 * spec.step or stride is None:
        return None
    factor = 2 if stride % 2 == 0 else 0.5
    count = min(args.monte_carlo, MC_ESTIMATE_RUNS)
    trajectory = bd.spec_trajectory(model, spec, tau=factor * step, duration=duration, p=p)
    other = direct_monte_carlo(model, trajectory, statistics, count, seed=args.seed,
                               record_interval=spec.step, engine="serial", progress=False)
    first = DirectErrors(errors.times, errors.names, errors.values[..., :count],
                         errors.sources[:, :count])
    rows, relative = bd.integration_errors(model, budget, first, other, factor)
    known = relative[np.isfinite(relative)]
    largest = float(np.max(np.abs(known))) if known.size else 0.0
    return {"runs": count, "step_s": factor * step,
            "extra_steps": count / args.monte_carlo / factor,
            "largest": largest,
            "rows": {(r.item, r.time, r.component): (float(v) if np.isfinite(v) else None)
                     for r, v in zip(rows, relative, strict=True)}}
