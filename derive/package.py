"""Write the generated package of one model into a folder, all-or-nothing.

Used by ``ins-errors derive FILE --out DIR`` and by the model-file cache: the package is
written into a scratch folder next to ``DIR`` and renamed into place only when every
file is complete, so a failure (a mistake in the model, an interrupted run) leaves
``DIR`` as it was and no half-written folder behind.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from ins_errors.errors import InsErrorsError
from ins_errors.modeling import ModelDefinition

from .model_files import ModelSummary, write_model
from .pipeline import _replace as replace_folder

BANNER_FIRST_LINE = "# GENERATED FILE: do not edit by hand."
"""First line of every generated Python file (how a generated package is recognised)."""


def is_generated_package(folder: Path) -> bool:
    """True if ``folder`` holds a package written by ins-errors (safe to replace)."""
    init = folder / "__init__.py"
    try:
        with init.open(encoding="utf-8") as handle:
            return handle.readline().rstrip("\n") == BANNER_FIRST_LINE
    except OSError:
        return False


def _seal(folder: Path) -> None:
    """:func:`ins_errors.model_lookup.seal_package` of ``folder``; nothing where the
    ins-errors imported predates sealed packages (a checkout's ``derive/`` run with
    another checkout's package, which checks none)."""
    try:
        from ins_errors.model_lookup import seal_package
    except ImportError:
        return
    seal_package(folder)


def write_package(d: ModelDefinition, target: Path, origin: tuple[str, str] | None = None,
                  record: dict[str, object] | None = None, replace: bool = True) -> ModelSummary:
    """Derive ``d`` and write its package (metadata, numpy, CasADi, Markdown) as ``target``,
    the files' lengths and hashes recorded in its sealed ``__init__.py``
    (:func:`ins_errors.model_lookup.seal_package`: a package cut short or altered is
    found before it is used).

    Parameters
    ----------
    d : ModelDefinition
        The model.
    target : Path
        Folder that becomes the package (``target/__init__.py``, ``numpy_model.py``,
        ``casadi_model.py``, ``error_equations.md``). An existing generated package
        there is replaced; any other non-empty folder is refused.
    origin, record
        Passed to :func:`write_model` (banner lines, extra metadata such as the hash of
        the model file).
    replace : bool
        Replace a generated package already at ``target`` (default); False: a package
        put there meanwhile (another process writing the same one) is kept, and this
        one dropped with an error (the caller uses that one).

    Returns
    -------
    ModelSummary

    Raises
    ------
    InsErrorsError
        If ``target`` is a file or a folder with other content, or cannot be written;
        :class:`~ins_errors.errors.ModelDefinitionError` if deriving fails. In every
        case ``target`` is left as it was.
    """
    target = Path(target)
    if target.exists() and not target.is_dir():
        raise InsErrorsError(f"output {str(target)!r} exists and is not a folder")
    if target.is_dir() and any(target.iterdir()) and not is_generated_package(target):
        raise InsErrorsError(f"output folder {str(target)!r} is not empty and holds no "
                             "generated package: choose another --out")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        scratch = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    except OSError as error:
        raise InsErrorsError(f"cannot write to {str(target.parent)!r}: "
                             f"{error.strerror}") from None
    try:
        summary = write_model(d, scratch, origin=origin, record=record)
        _seal(scratch / d.name)   # checked before every use (package_damage)
        if replace:
            replace_folder(target, scratch / d.name)
        else:   # one rename: fails where a non-empty folder is
            (scratch / d.name).rename(target)
    except OSError as error:
        raise InsErrorsError(f"cannot write {str(target)!r}: {error.strerror}") from None
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return summary
