"""Read a researcher's model file: import it, call ``build()``, check the definition.

A model file is a Python file written with :mod:`ins_errors.modeling` that defines a
function ``build()`` returning a :class:`~ins_errors.modeling.ModelDefinition`. It may
import modules that sit next to it (``from my_constants import ...``); those are part of
its identity: :func:`~ins_errors.model_identity.model_sha256` hashes the file and every
such module, so editing any of them makes the generated code stale. Any
failure (a Python exception while importing the file or running ``build()``, a
definition that does not pass :func:`~ins_errors.symbolic.consistency.check_definition`,
a real work reading a true state where the computer has its own,
:func:`~ins_errors.symbolic.true_state_reads.check_true_state_reads`)
becomes one :class:`~ins_errors.errors.ModelDefinitionError` line that names the file,
the model, the quantity and the step.
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
import traceback
from pathlib import Path
from types import ModuleType

from ins_errors.errors import InsErrorsError, ModelDefinitionError
from ins_errors.model_identity import source_files
from ins_errors.modeling import ModelDefinition


def _frames(error: BaseException, path: Path) -> list[traceback.FrameSummary]:
    return [f for f in traceback.extract_tb(error.__traceback__)
            if Path(f.filename).resolve() == path.resolve()]


def _where(error: BaseException, path: Path) -> str:
    """``line N`` of the deepest traceback frame inside the model file, if any."""
    frames = _frames(error, path)
    return f"line {frames[-1].lineno}: " if frames else ""


def _line_text(error: BaseException, path: Path | None) -> str:
    """The source of the deepest line of the model file in the traceback, quoted and
    cut to 80 characters (``'ideal_rhs = sp.Matrix(...)': ``), or empty."""
    frames = _frames(error, path) if path is not None else []
    text = (frames[-1].line or "").strip() if frames else ""
    if not text:
        return ""
    return f"{text if len(text) <= 80 else text[:77] + '...'!r}: "


def _matrix_argument(error: BaseException) -> object:
    """What the model file gave to the ``sp.Matrix(...)`` call that raised ``error`` (the
    one argument of SymPy's ``_handle_creation_inputs``), or None."""
    tb = error.__traceback__
    while tb is not None:
        frame = tb.tb_frame
        if frame.f_code.co_name == "_handle_creation_inputs" \
                and "sympy" in frame.f_code.co_filename:
            args = frame.f_locals.get("args")
            return args[0] if isinstance(args, tuple) and len(args) == 1 else None
        tb = tb.tb_next
    return None


def _one_line(error: BaseException, path: Path | None = None) -> str:
    if isinstance(error, SystemExit):  # sys.exit(...) would end ins-errors itself
        return f"called sys.exit({error.code!r})"
    from ins_errors.symbolic.consistency import mixed_entries

    mixed = mixed_entries(_matrix_argument(error)) if isinstance(error, ValueError) else None
    if mixed:  # SymPy says only "mismatched dimensions"
        return f"{_line_text(error, path)}sp.Matrix(...) got {mixed}"
    text = str(error).strip().splitlines()
    return f"{type(error).__name__}: {text[0] if text else ''}".rstrip(": ")


def import_model_file(path: Path) -> ModuleType:
    """Import ``path`` as a fresh module (never taken from ``sys.modules``).

    Raises
    ------
    ModelDefinitionError
        If the file does not exist, is not Python, or raises while being imported.
    """
    path = Path(path)
    if path.is_dir():
        raise ModelDefinitionError(f"model file {str(path)!r} is a folder, not a Python "
                                   "file (give the .py file that defines build())")
    if not path.is_file():
        raise ModelDefinitionError(f"model file {str(path)!r} not found")
    if path.suffix != ".py":
        raise ModelDefinitionError(f"model file {str(path)!r} must be a Python file (.py)")
    digest = hashlib.sha256(str(path.resolve()).encode()).hexdigest()[:12]
    module_name = f"_ins_errors_model_file_{digest}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise ModelDefinitionError(f"model file {path.name}: cannot be imported")
    folder = path.resolve().parent
    heads = {f.relative_to(folder).parts[0].removesuffix(".py") for f in source_files(path)[1:]}
    for name in [n for n in sys.modules if n.split(".")[0] in heads]:
        del sys.modules[name]  # a module next to the file may have been edited: import afresh
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module  # dataclasses and pickling look modules up here
    sys.path.insert(0, str(folder))  # the file may import modules next to it
    try:
        spec.loader.exec_module(module)
    except SyntaxError as error:
        sys.modules.pop(module_name, None)
        raise ModelDefinitionError(f"model file {path.name}: line {error.lineno}: "
                                   f"SyntaxError: {error.msg} (step: importing the file)") from None
    except (Exception, SystemExit) as error:  # a researcher's code: whatever it raised
        # (sys.exit() in the file is its error too, not the command's exit status)
        sys.modules.pop(module_name, None)
        raise ModelDefinitionError(f"model file {path.name}: {_where(error, path)}"
                                   f"{_one_line(error, path)} (step: importing the file)") from None
    finally:
        if str(folder) in sys.path:
            sys.path.remove(str(folder))
    return module


def build_definition(module: ModuleType, label: str, path: Path | None = None) -> ModelDefinition:
    """Call ``module.build()`` and check what it returns.

    Parameters
    ----------
    module : module
        An imported model file or model module.
    label : str
        How messages name it (``"model file my_ins.py"``).
    path : Path, optional
        The file, to name the line of an exception raised in it.
    """
    build = getattr(module, "build", None)
    if not callable(build):
        raise ModelDefinitionError(f"{label}: defines no function build() returning a "
                                   "ModelDefinition (step: building the definition)")
    try:
        definition = build()
    except InsErrorsError as error:
        where = _where(error, path) if path is not None else ""
        raise ModelDefinitionError(f"{label}: {where}{error} "
                                   "(step: building the definition)") from None
    except (Exception, SystemExit) as error:  # a researcher's code: whatever it raised
        where = _where(error, path) if path is not None else ""
        raise ModelDefinitionError(f"{label}: {where}{_one_line(error, path)} "
                                   "(step: building the definition)") from None
    if not isinstance(definition, ModelDefinition):
        raise ModelDefinitionError(f"{label}: build() returned {type(definition).__name__}, "
                                   "not a ModelDefinition (step: building the definition)")
    if not isinstance(definition.name, str):
        raise ModelDefinitionError(f"{label}: the model's name must be a str, got "
                                   f"{type(definition.name).__name__} {definition.name!r:.40} "
                                   "(step: building the definition)")
    if not definition.name.isidentifier():
        raise ModelDefinitionError(f"{label}: model name {definition.name!r} is not a Python "
                                   "identifier (step: building the definition)")
    from ins_errors.symbolic.consistency import (
        check_definition,
        check_dimensions,
        check_reduces_to_ideal,
        check_units,
    )
    from ins_errors.symbolic.true_state_reads import check_true_state_reads

    named = f"{label} (model {definition.name!r})"
    # units before the reduction: a term in the wrong unit in the real work alone is
    # named as that, not as a residual of the reduction
    check_definition(definition, named, reduction=False)
    check_units(definition, named)
    check_dimensions(definition, named)
    check_reduces_to_ideal(definition, named)
    check_true_state_reads(definition, named)
    return definition


def load_model_file(path: Path) -> ModelDefinition:
    """Import a model file, build its definition and check it.

    Parameters
    ----------
    path : Path
        A ``.py`` file defining ``build()``.

    Returns
    -------
    ModelDefinition

    Raises
    ------
    ModelDefinitionError
        One line naming the file, the model, the quantity and the step.
    """
    path = Path(path)
    return build_definition(import_model_file(path), f"model file {path.name}", path)
