"""Everything `make derive` writes, all or nothing.

One job per model writes its folder and, on a full run, the model's transfer-function
documents (:mod:`derive.transfer_functions`, in the same process, so the model is
built once) and the documents that other steps register for it in
:data:`EXTRA_STEPS` (reports regenerated with the code, e.g. the checker's report on
the manual's printed equations, which reuses the model's structured variation). The
jobs are independent and run in one pool of forked workers, longest first; the output
does not depend on the order.

Everything is written into a temporary folder next to the target; the target is
replaced only when every step has succeeded. A failing step raises :class:`DeriveError`
with one line naming the model and the step, and the target is left as it was.
"""

from __future__ import annotations

import importlib
import os
import shutil
import tempfile
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path

from ins_errors.errors import unknown_name
from ins_errors.model_identity import builtin_record
from ins_errors.models import definition, model_names
from ins_errors.output import open_modes
from ins_errors.symbolic.consistency import check_definition
from ins_errors.symbolic.static_base import SETUPS
from ins_errors.symbolic.true_state_reads import check_true_state_reads

from .hand_check_report import write_hand_check_reports
from .model_files import ModelSummary, write_model
from .steps import step
from .transfer_functions import write_transfer_functions

EXTRA_STEPS: list[tuple[str, Callable[[Path], None]]] = [
    ("orthodromic", write_hand_check_reports)]
"""(model, callable ``step(generated_root)``): run on a full run, in the model's job
after its own files (the model's derivation is then at hand in that process)."""

_LONGEST_FIRST = ("orthodromic", "north_pointing")
"""Models whose jobs take longest (their transfer functions): started first."""


def _write_one(name: str, root: Path, documents: bool) -> ModelSummary:
    with step(name, "build the definition"):
        model = definition(name)
    check_definition(model)  # the checks a researcher's model file gets, one line each
    check_true_state_reads(model, f"model {name!r}")
    # the hashes of the model's sources: a run finds the package stale when they change
    summary = write_model(model, root, record=builtin_record(name))
    if documents and name in SETUPS:
        with step(name, "transfer functions"):
            write_transfer_functions(root, name)
    for model, extra in EXTRA_STEPS if documents else ():
        if model == name:
            _run_extra(extra, root)
    return summary


def _run_extra(extra: Callable[[Path], None], root: Path) -> None:
    with step("all models", extra.__name__.removeprefix("write_").replace("_", " ")):
        extra(root)


def _preload(names: list[str], documents: bool) -> None:
    """Import once, before forking, the SymPy modules every worker would import itself.

    Its tensor module (``Add`` looks for tensor sums) and code-generation nodes (the
    code printers) in every job; its unit system (``simplify`` looks for quantities:
    about 0.12 s) where two or more jobs run static analyses.
    """
    modules = ["sympy.codegen.ast", "sympy.tensor.tensor"]
    if documents and sum(name in SETUPS for name in names) > 1:
        modules.append("sympy.physics.units")
    for module in modules:
        importlib.import_module(module)


def _run_jobs(names: list[str], root: Path, documents: bool) -> list[ModelSummary]:
    """Every model's job (with its extra steps if ``documents``); both cores if there are."""
    workers = min(len(names), os.cpu_count() or 1)
    if workers <= 1:
        return [_write_one(name, root, documents) for name in names]
    _preload(names, documents)
    first = [n for n in _LONGEST_FIRST if n in names]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        jobs: dict[str, Future] = {
            name: pool.submit(_write_one, name, root, documents)
            for name in first}
        jobs.update({name: pool.submit(_write_one, name, root, documents)
                     for name in names if name not in jobs})
        return [jobs[name].result() for name in names]


def derive_all(root: Path, models: list[str] | None = None) -> list[ModelSummary]:
    """Write every (or the named) model's generated files under ``root``, all or nothing.

    The files are written into a temporary folder beside ``root`` (a copy of ``root``
    when only some models are named) that replaces ``root`` once every step succeeded.

    Raises
    ------
    DeriveError
        One line naming the model and the failed step; ``root`` is unchanged.
    """
    names = models or model_names()
    for name in names:  # before anything is written
        if name not in model_names():
            raise unknown_name("model", name, model_names())
    root = Path(root)
    root.parent.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=f".{root.name}-derive-", dir=root.parent))
    try:
        os.chmod(work, open_modes()[1])  # becomes generated/: not private as mkdtemp's
        if models is not None and root.is_dir():
            shutil.copytree(root, work, dirs_exist_ok=True,
                            ignore=shutil.ignore_patterns("__pycache__"))
        init = work / "__init__.py"
        init.write_text('"""Generated code of every model (written by `make derive`)."""\n\n'
                        f"MODELS = {tuple(model_names())!r}\n", encoding="utf-8")
        summaries = _run_jobs(names, work, documents=models is None)
        _replace(root, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return summaries


def _replace(root: Path, work: Path) -> None:
    """Put ``work`` in the place of ``root`` (two renames on the same file system)."""
    old = None
    if root.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{root.name}-old-", dir=root.parent))
        old.rmdir()
        root.rename(old)
    try:
        work.rename(root)
    except OSError:
        if old is not None:
            old.rename(root)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
