"""Everything `make derive` writes, in order.

Model files first (one folder per model), then the documents that other steps register
in :data:`EXTRA_STEPS` (reports that are regenerated with the code, e.g. the checker's
report on the manual's printed equations).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from derive.hand_check_report import write_hand_check_reports
from derive.model_files import ModelSummary, write_model
from derive.transfer_functions import write_transfer_functions
from ins_errors.errors import unknown_name
from ins_errors.models import definition, model_names

EXTRA_STEPS: list[Callable[[Path], None]] = [write_transfer_functions, write_hand_check_reports]
"""Callables ``step(generated_root)`` run after every model has been written."""


def _write_one(name: str, root: Path) -> ModelSummary:
    return write_model(definition(name), root)


def _write_models(names: list[str], root: Path) -> list[ModelSummary]:
    """Write each model's folder; models are independent, so use every core."""
    workers = min(len(names), os.cpu_count() or 1)
    if workers <= 1:
        return [_write_one(name, root) for name in names]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        return list(pool.map(_write_one, names, [root] * len(names)))


def derive_all(root: Path, models: list[str] | None = None) -> list[ModelSummary]:
    """Write every (or the named) model's generated files under ``root``."""
    names = models or model_names()
    for name in names:  # before anything is written
        if name not in model_names():
            raise unknown_name("model", name, model_names())
    root.mkdir(parents=True, exist_ok=True)
    init = root / "__init__.py"
    init.write_text('"""Generated code of every model (written by `make derive`)."""\n\n'
                    f"MODELS = {tuple(model_names())!r}\n", encoding="utf-8")
    summaries = _write_models(names, root)
    if models is None:
        for step in EXTRA_STEPS:
            step(root)
    return summaries
