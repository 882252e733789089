"""Scenario files: one TOML file describes a whole error study; one command runs it.

A scenario names the model, the true motion, the run (duration, step, scheme), one or
more *cases* (sets of error sources with units) and the quantities the reader wants.
Every value with a unit is read by :mod:`ins_errors.units`. Example::

    title = "Lab task 1, factor 5: drift of a horizontal gyro"
    model = "orthodromic"

    [motion]                 # see ins_errors.numeric.motion_spec
    kind = "static"
    latitude = "50 deg"

    [run]
    duration = "24 h"
    step = "1 s"             # integration step τ
    record = "60 s"
    method = "rk4"           # default; or "euler" (the manual's rectangle method)
    refined = true           # also the second-order model
    platform = "exact"       # or "small_angle" (the source documents' platform matrix)
    validity_threshold = 0.05  # warn when linear − direct exceeds 5 % of the error
    ellipsoid = "wgs84"      # default: the model's own Earth
    truth = "auto"           # moving truth: "fine", "interpolated" or "auto" (default)

    [[case]]
    label = "0.01 deg/h about x"      # optional
    gyro_drift_x = "0.01 deg/h"

    [outputs]
    quantities = ["alpha_y", "delta_latitude", "delta_v_N"]   # default: every excited one
                             # (the summary's worst ratios and the warnings judge these)

    [parameters]             # optional: model parameters with units (ins-errors models MODEL)
    k_h1 = "0.0047 1/s"      # e.g. strapdown_ned's vertical damping gains (default 0)

:func:`run_scenario` returns the comparisons; :mod:`ins_errors.report` writes them as a
report folder (Markdown, HTML, plots, JSON).
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ins_errors.errors import InsErrorsError, unknown_name
from ins_errors.units import parse_quantity

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

class ScenarioError(InsErrorsError):
    """A scenario file that cannot be read or does not describe a valid run."""


@dataclass
class Case:
    """One set of error sources (SI values) with a label."""

    label: str
    sources: dict[str, float]


@dataclass
class Scenario:
    """A parsed scenario (all values SI).

    Attributes
    ----------
    title, description : str
        Shown at the top of the report.
    model : str
        Model name.
    motion : dict
        Motion description for :func:`~ins_errors.numeric.motion_spec.motion_profile`.
    duration, step, record : float
        Seconds.
    method : str
        ``"rk4"`` (default) or ``"euler"`` (the rectangle method).
    refined : bool
        Run the second-order model too.
    platform : str
        Platform kinematics of the direct run: ``"exact"`` or ``"small_angle"``.
    validity_threshold : float
        Linear/direct ratio above which a case is warned about.
    ellipsoid : str or None
        Earth model for the parameters (``None``: the model's default).
    truth : str
        How a moving truth is computed: ``"auto"`` (default), ``"interpolated"`` or
        ``"fine"`` (see :func:`ins_errors.numeric.trajectories.trajectory`).
    parameters : dict of str to float
        Model parameters set by the file's ``[parameters]`` table, SI (the others keep
        their defaults; see :mod:`ins_errors.model_parameters`).
    cases : list of Case
        Error-source sets, each run as its own case.
    quantities : list of str or None
        Quantities to show; ``None`` for every excited one.
    base : Path
        Folder of the scenario file (relative paths are taken from here).
    file : str
        The scenario file as the user gave it (the path typed on the command line), the
        name messages give it.
    sweep : SweepSpec or None
        The ``[sweep]`` table (:mod:`ins_errors.analysis.sweep`), run by
        ``ins-errors sweep``; ``ins-errors run`` refuses a file that has one.
    """

    title: str
    model: str
    motion: dict[str, Any]
    duration: float
    step: float
    record: float
    method: str = "rk4"
    refined: bool = True
    platform: str = "exact"
    validity_threshold: float = 0.05
    ellipsoid: str | None = None
    truth: str = "auto"
    parameters: dict[str, float] = field(default_factory=dict)
    cases: list[Case] = field(default_factory=list)
    quantities: list[str] | None = None
    description: str = ""
    base: Path = Path(".")
    file: str = ""
    sweep: Any = None  # ins_errors.analysis.sweep.SweepSpec of a [sweep] table


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file.

    Raises
    ------
    ScenarioError, UnknownNameError, UnitError
        One line naming the file as given (``path``, its folder included), the key and
        what is wrong.
    """
    from ins_errors.model_parameters import check_source
    from ins_errors.numeric.model import load_model

    where = os.fspath(path)  # as the user typed it, for messages
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8-sig"))  # -sig: a BOM is no TOML
    except OSError as error:
        raise ScenarioError(f"cannot read scenario {where!r}: {error.strerror}") from None
    except UnicodeDecodeError:
        raise ScenarioError(f"{where}: not a text file (not UTF-8): expected a TOML "
                            "scenario") from None
    except tomllib.TOMLDecodeError as error:
        raise ScenarioError(f"{where}: not valid TOML: {error}") from None
    from ins_errors.scenario_schema import validate

    checked = validate(data, where)  # the shape: tables, keys, types, names of choices
    # a model file is taken relative to the scenario file
    try:
        model = load_model(checked.model, relative_to=path.parent)
    except InsErrorsError as error:   # named with the file the reader is to fix
        raise type(error)(f"{where}: {error}") from None
    run = checked.run
    from ins_errors.numeric.integrators import record_stride, step_count

    # a motion file's run lasts the file's length unless [run] duration says otherwise
    file_length = ("duration" not in run.model_fields_set
                   and str(dict(data.get("motion", {})).get("kind")) == "file")
    try:
        duration = parse_quantity(run.duration, "s", "duration", numbers_are_si=False)
        step = parse_quantity(run.step, "s", "step", numbers_are_si=False)
        record = parse_quantity(run.record, "s", "record", numbers_are_si=False)
        for name, value in (("duration", duration), ("step", step), ("record", record)):
            if not value > 0:
                raise ScenarioError(f"{name} must be positive, got {value:g} s")
        # refuse a grid the run cannot take (absurd step counts included) before any run
        if not file_length:  # checked below, once the file is read
            record_stride(record, step, step_count(duration, step, "duration"))
    except InsErrorsError as error:
        raise type(error)(f"{where} [run] {error}") from None
    cases = []
    for k, raw in enumerate(data["case"], start=1):
        label = str(raw.get("label", ""))
        sources = {}
        for name, value in raw.items():
            if name == "label":
                continue
            try:
                info = model.sources[model.index("sources", name)]
                sources[name] = check_source(info, parse_quantity(
                    value, info.unit, name, numbers_are_si=False), value)
            except InsErrorsError as error:
                raise type(error)(f"{where} [[case]] {k}: {error}") from None
        if not sources:
            raise ScenarioError(f"{where}: case {k} names no error source")
        label = label or ", ".join(f"{n} = {raw[n]}" for n in sources)
        cases.append(Case(label, sources))
    from ins_errors.model_parameters import parse_parameters

    parameters = parse_parameters(model, checked.parameters or {},
                                  f"{where} [parameters]", numbers_are_si=False)
    try:
        model.parameter_vector(ellipsoid=run.ellipsoid, **parameters)  # before any run
    except InsErrorsError as error:
        raise type(error)(f"{where}: {error}") from None
    quantities = checked.outputs.quantities
    if quantities is not None:
        from ins_errors.numeric.simulate import error_quantities

        known = error_quantities(model)[0]
        for q in quantities:
            if q not in known:
                raise unknown_name(f"quantity in {where} [outputs]", str(q), known)
    from ins_errors.numeric.motion_spec import motion_profile, refuse_unused_heading

    motion = dict(data.get("motion", {}))
    if isinstance(motion.get("file"), str):  # '~' as on the command line, for every reader
        from ins_errors.user_paths import expand_user

        motion["file"] = expand_user(motion["file"])
    try:
        profile = motion_profile(motion, base=path.parent, model=model)  # before any run
    except InsErrorsError as error:
        raise type(error)(f"{where} [motion]: {error}") from None
    if motion.get("heading") is not None:
        refuse_unused_heading(model, profile, f"{where} [motion] heading")
    if file_length:
        from ins_errors.numeric.motion_spec import file_duration

        duration = file_duration(profile, step)
        if "record" not in run.model_fields_set:  # as compare's: divides the run
            n_steps = step_count(duration, step, "duration")
            stride = max(1, min(n_steps, int(record / step + 1e-9)))
            while n_steps % stride:
                stride -= 1
            record = stride * step
        try:
            record_stride(record, step, step_count(duration, step, "duration"))
        except InsErrorsError as error:
            raise type(error)(f"{where} [run] {error} (the duration is the motion file's "
                              f"length, {duration:g} s, as [run] gives none)") from None
    sweep = None
    if "sweep" in data:
        from ins_errors.analysis.sweep import parse_sweep

        sweep = parse_sweep(data["sweep"], model, where, cases=len(cases))
    return Scenario(
        title=str(data.get("title", path.stem)),
        description=str(data.get("description", "")),
        model=model.key,
        motion=dict(motion),
        duration=duration,
        step=step,
        record=record,
        method=run.method,
        refined=run.refined,
        platform=run.platform,
        validity_threshold=float(run.validity_threshold),
        ellipsoid=run.ellipsoid,
        truth=run.truth,
        parameters=parameters,
        cases=cases,
        quantities=list(quantities) if quantities is not None else None,
        base=path.parent,
        file=where,
        sweep=sweep,
    )


@dataclass
class ScenarioResult:
    """What a scenario run produced."""

    scenario: Scenario
    motion_description: str
    comparisons: list  # list[Comparison]
    truth_used: str = ""
    """:attr:`~ins_errors.numeric.trajectories.Trajectory.truth_kind` of the run."""


def run_scenario(scenario: Scenario, progress: bool = False) -> ScenarioResult:
    """Integrate the truth, then direct, linear (and refined) runs for every case."""
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.compare import CheckedRatio, compare
    from ins_errors.numeric.model import load_model
    from ins_errors.numeric.motion_spec import motion_profile

    model = load_model(scenario.model)
    profile = motion_profile(scenario.motion, base=scenario.base, model=model)
    p = model.parameter_vector(ellipsoid=scenario.ellipsoid, **scenario.parameters)
    trajectory = tr.trajectory(model, profile, scenario.duration, scenario.step, p=p,
                               progress=progress, truth=scenario.truth)
    where = f"{scenario.file} " if scenario.file else ""
    given = {name: (f"{where}[motion] {name}", str(scenario.motion[name]))
             for name in ("latitude", "longitude", "height", "heading")
             if scenario.motion.get(name) is not None}
    tr.refuse_unused_references(model, trajectory, given,
                                setting='[parameters] {name} = "{value}"')
    comparisons = compare(model, trajectory, [c.sources for c in scenario.cases],
                          method=scenario.method, record_interval=scenario.record,
                          refined=scenario.refined, progress=progress,
                          platform=scenario.platform,
                          validity_threshold=CheckedRatio(scenario.validity_threshold),
                          quantities=scenario.quantities, warn=False)
    for comparison, case in zip(comparisons, scenario.cases, strict=True):
        comparison.label = case.label
        # notes about the motion (a strapdown INS flying a noisy motion file)
        comparison.warnings.extend(getattr(trajectory, "notes", ()))
    return ScenarioResult(scenario, trajectory.description, comparisons, trajectory.truth_kind)
