"""Write one model's generated files: metadata, numpy module, CasADi module, equations.

No numerics happen here: the symbolic machinery derives, this module prints.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.codegen import (
    CASADI_TAN,
    Argument,
    FunctionSpec,
    emit_casadi_builder,
    emit_numpy_function,
    prepare,
)
from ins_errors.symbolic.consistency import unseen_sources
from ins_errors.symbolic.documents import error_equations_markdown
from ins_errors.symbolic.shared_trees import SharedTrees
from ins_errors.symbolic.variation import ErrorModel, second_order_of, vary

from .steps import step


def header(model: ModelDefinition, markdown: bool = False,
           origin: tuple[str, str] | None = None) -> str:
    """The do-not-edit banner of every generated file (no timestamps, no paths).

    ``origin`` is ``(written by, how to regenerate)`` for a model outside the package;
    the default names the built-in model module and `make derive`.
    """
    module = f"ins_errors/models/{model.name}.py"
    written, again = origin or (f"`make derive` (python -m derive) from {module}",
                                "Edit the model definition and run `make derive` again.")
    lines = ["GENERATED FILE: do not edit by hand.", f"Written by {written}.", again]
    if markdown:
        return "<!--\n" + "\n".join(lines) + "\n-->\n"
    return "".join(f"# {line}\n" for line in lines)


def function_specs(em: ErrorModel) -> list[FunctionSpec]:
    """Every numeric function emitted for a model."""
    d = em.definition
    x = Argument("x", d.x, "ideal-work (true) state, SI units")
    xr = Argument("xr", d.real_states, real_state_description(d))
    u = Argument("u", d.u, "true-motion inputs, SI units")
    p = Argument("p", d.p, "model parameters, SI units")
    w = Argument("w", d.w, "error-source magnitudes, SI units")
    xe = Argument("xe", d.xe, "error state xr - (x, 0)")
    c = Argument("c", d.c, "initial navigation conditions, SI units")
    small_angle = []
    if d.small_angle_rhs is not None:
        small_rhs = d.expand(d.small_angle_rhs)
        small_angle = [
            FunctionSpec("real_rhs_small_angle", [xr, x, u, w, p], small_rhs,
                         "Real-work equations with the source's small-angle platform: dxr/dt.",
                         "time derivative of the real-work state"),
            FunctionSpec("second_order_small_angle", [x, u, p, xe, w],
                         second_order_of(d, small_rhs),
                         "Second-order term of the error equations of the small-angle "
                         "platform.", "1/2 (xe, w)' Hessian (xe, w) per equation")]
    return [
        FunctionSpec("ideal_rhs", [x, u, p], em.ideal_rhs,
                     "Ideal-work equations: dx/dt.", "time derivative of the true state"),
        FunctionSpec("real_rhs", [xr, x, u, w, p], em.real_rhs,
                     "Real-work equations: dxr/dt "
                     + ("(needs the true state x for the platform)."
                        if em.real_rhs.free_symbols & set(d.x)
                        else "(x is not used: the signature all models share)."),
                     "time derivative of the real-work state"),
        *small_angle,
        FunctionSpec("outputs", [x, u, p], em.outputs,
                     "Navigation outputs of a state (true or computed part of xr).",
                     "outputs in SI units"),
        FunctionSpec("state_matrix", [x, u, p], em.state_matrix,
                     "State matrix F of the linear error equations.", "F", matrix=True),
        FunctionSpec("source_matrix", [x, u, p], em.source_matrix,
                     "Error-source matrix G of the linear error equations.", "G",
                     matrix=True),
        FunctionSpec("output_matrix", [x, u, p], em.output_matrix,
                     "Output matrix H: output errors = H xe to first order.", "H",
                     matrix=True),
        FunctionSpec("second_order", [x, u, p, xe, w], em.second_order,
                     "Second-order term of the error equations (refined model).",
                     "1/2 (xe, w)' Hessian (xe, w) per equation"),
        FunctionSpec("initial_state", [c, u, p], em.initial_state,
                     "True initial state from navigation initial conditions.", "x(0)"),
        FunctionSpec("initial_real_state", [c, u, w, p], em.initial_real_state,
                     "Real-work initial state, initial-error sources applied.", "xr(0)"),
        FunctionSpec("initial_error_matrix", [c, u, p], em.initial_error_matrix,
                     "First-order map from error sources to the initial error state.",
                     "E: xe(0) = E w", matrix=True),
        FunctionSpec("domain_margins", [x, u, p],
                     sp.Matrix([expr for expr, _ in d.domain] or [1]),
                     "Margins that must be positive for the formulas to hold (see DOMAIN).",
                     "one margin per condition of DOMAIN"),
        FunctionSpec("initial_domain_margins", [c, u, p],
                     sp.Matrix([expr for expr, _ in d.initial_domain] or [1]),
                     "Margins that must be positive for the initial conditions.",
                     "one margin per condition of INITIAL_DOMAIN"),
    ]


def real_state_description(d: ModelDefinition) -> str:
    """What the real-work state ``xr`` of ``d``'s generated functions holds, for their
    docstrings: the computed states in ``x``'s order, then the extra error states (zero in
    ideal work) by name, or that there are none (a strapdown INS)."""
    extra = d.extra_error_states
    head = f"real-work state: the {len(d.states)} computed states in the order of x"
    if not extra:
        return head + ", no further state"
    names = ", ".join(v.name for v in extra)
    if extra == d.platform_angles:
        return f"{head}, then the platform angles {names} (rad)"
    units = ", ".join(f"{v.name} ({v.unit})" for v in extra)
    return f"{head}, then the states zero in ideal work: {units}"


def _metadata(d: ModelDefinition, record: dict[str, object] | None = None) -> str:
    def rows(variables, extra=(), when_set=()):
        out = []
        for v in variables:
            fields = {"name": v.name, "unit": v.unit, "description": v.description,
                      "latex": v.latex}
            fields.update({k: getattr(v, k) for k in extra})
            fields.update({k: getattr(v, k) for k in when_set if getattr(v, k)})
            out.append("    " + repr(fields) + ",")
        return "\n".join(out)

    return "\n".join([
        f'"""Generated metadata of the model {d.name!r}: {d.title}."""',
        "",
        f"NAME = {d.name!r}",
        f"TITLE = {d.title!r}",
        f"SOURCE = {d.source!r}",
        "STATES = (", rows(d.states), ")",
        "ERROR_STATES = (", rows(d.error_states), ")",
        "INPUTS = (", rows(d.inputs), ")",
        # a damping gain's flag and example only where set (Info's defaults elsewhere)
        "PARAMETERS = (", rows(d.parameters, ("default",),
                               ("damping_gain", "example", "example_gives")), ")",
        "SOURCES = (", rows(d.sources, ("kind", "display_unit", "factor")), ")",
        "OUTPUTS = (", rows(d.outputs), ")",
        "INITIAL_CONDITIONS = (", rows(d.initial_conditions), ")",
        f"DOMAIN = {tuple(message for _, message in d.domain)!r}",
        f"INITIAL_DOMAIN = {tuple(message for _, message in d.initial_domain)!r}",
        # only where a model explains a mode (the other packages stay as they were)
        *([f"MODE_NOTES = {dict(d.mode_notes)!r}"] if d.mode_notes else []),
        *(f"{key} = {value!r}" for key, value in (record or {}).items()),
        "",
    ])


NUMPY_PRELUDE = '''
import numpy as _np

_m = _np


def _as_vector(value, length, name, function):
    array = _np.asarray(value, dtype=float)
    if array.ndim == 0 or array.shape[0] != length:
        raise ValueError(f"{function}: argument {name} must have shape ({length}, ...), "
                         f"got {array.shape}")
    return array
'''

_CASADI_PRELUDE = '''
import functools

import casadi as _m


def function(name):
    """The casadi.Function called ``name`` (built once, then cached)."""
    try:
        builder = _BUILDERS[name]
    except KeyError:
        raise KeyError(f"no generated CasADi function {name!r}; known: "
                       f"{', '.join(_BUILDERS)}") from None
    return _cached(builder)


@functools.cache
def _cached(builder):
    return builder()
'''


@dataclass
class ModelSummary:
    """Figures printed by ``make derive`` for one model."""

    name: str
    states: int
    error_states: int
    sources: int
    outputs: int
    operations: int
    seconds: float


SUMMARY_KEY = ("errors: error states, the length of xe in ẋe = F xe + G w",
               "ops: SymPy's operation count of the generated numeric functions after "
               "common-subexpression elimination (their size)")
"""The lines under :func:`summary_table` that say what its less obvious columns are."""


def summary_table(summaries: list[ModelSummary]) -> list[str]:
    """The lines ``make derive`` and ``ins-errors derive`` print: one row per model
    (its states, error states, error sources, outputs, operation count and seconds),
    then the lines of :data:`SUMMARY_KEY`."""
    lines = [f"{'model':<20}{'states':>7}{'errors':>7}{'sources':>8}{'outputs':>8}"
             f"{'ops':>8}{'seconds':>9}"]
    lines += [f"{s.name:<20}{s.states:>7}{s.error_states:>7}{s.sources:>8}{s.outputs:>8}"
              f"{s.operations:>8}{s.seconds:>9.2f}" for s in summaries]
    return [*lines, *SUMMARY_KEY]


def write_model(d: ModelDefinition, root: Path, origin: tuple[str, str] | None = None,
                record: dict[str, object] | None = None) -> ModelSummary:
    """Derive and write ``root/<model>/`` for one model definition.

    Parameters
    ----------
    d : ModelDefinition
        The model.
    root : Path
        Folder that receives ``<model>/``.
    origin : (str, str), optional
        Banner lines for a model outside the package (see :func:`header`).
    record : dict, optional
        Extra ``NAME = value`` lines of the metadata module, written as ``repr(value)``
        (the model file's hash; a built-in model's hashes of its sources, a dict).
    """
    start = time.perf_counter()
    with step(d.name, "vary (first- and second-order error equations)"):
        em = vary(d)
    for line in unseen_sources(d, em.source_matrix, em.initial_error_matrix):
        print(f"ins-errors: warning: {line}", file=sys.stderr)
    prepared = []
    trees = SharedTrees()  # the functions share subtrees (and their free symbols)
    for spec in function_specs(em):
        with step(d.name, f"generate numeric code of {spec.name}"):
            prepared.append(prepare(spec, trees))
    folder = root / d.name
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "__init__.py").write_text(header(d, origin=origin) + _metadata(d, record),
                                        encoding="utf-8")
    numpy_src = [header(d, origin=origin),
                 f'"""numpy functions of the model {d.name!r} (broadcasting)."""', NUMPY_PRELUDE]
    numpy_src += ["\n" + emit_numpy_function(p) + "\n" for p in prepared]
    names = [p.spec.name for p in prepared]
    numpy_src.append(f"\nFUNCTIONS = {tuple(names)!r}\n")
    (folder / "numpy_model.py").write_text("\n".join(numpy_src), encoding="utf-8")
    casadi_src = [header(d, origin=origin), f'"""CasADi SX functions of the model {d.name!r}."""',
                  _CASADI_PRELUDE + CASADI_TAN]
    casadi_src += ["\n" + emit_casadi_builder(p) + "\n" for p in prepared]
    builders = ", ".join(f"{n!r}: _build_{n}" for n in names)
    casadi_src.append(f"\n_BUILDERS = {{{builders}}}\nFUNCTIONS = {tuple(names)!r}\n")
    (folder / "casadi_model.py").write_text("\n".join(casadi_src), encoding="utf-8")
    with step(d.name, "write the equations document"):
        document = error_equations_markdown(d)
    (folder / "error_equations.md").write_text(header(d, markdown=True, origin=origin) + "\n"
                                               + document, encoding="utf-8")
    return ModelSummary(d.name, len(d.states), len(d.error_states), len(d.sources),
                        len(d.outputs), sum(p.operations for p in prepared),
                        time.perf_counter() - start)
