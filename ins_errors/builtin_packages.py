"""Which generated package a built-in model runs: the shipped one, or a fresh one.

``make derive`` records in each built-in model's package (``generated/<name>/``, shipped
as ``ins_errors.generated``) the SHA-256 of every file the model's definition is read
from (:func:`~ins_errors.model_identity.builtin_record`: its module in
``ins_errors/models/`` and the Earth and platform formulas it builds on). Loading the
model compares them with the files as they are now (:func:`stale_sources`: a few files
hashed, about 0.1 ms, no SymPy). A package whose model was edited since is never run,
as a model file's stale ``<name>_generated/`` is not: a notice says so (a
:class:`RuntimeWarning`, which the command line prints as one line; once per process,
not again in its worker processes: :func:`~ins_errors.model_lookup.package_notice`), and
the edited model is derived into the user cache (``$INS_ERRORS_CACHE/models`` or
``~/.cache/ins-errors/models``, folder ``<name>-<16 hex>``, derived on first use and
kept for next time; :data:`~ins_errors.model_lookup.KEEP_VERSIONS` versions of each
model). The shipped package is never rewritten by a run: ``make derive`` updates it.

A package without the record (written before ins-errors recorded it) is used as it is.
Edits of the derivation code itself (``ins_errors/symbolic/``, ``derive/``,
``ins_errors/modeling.py``) are not looked for here: ``tests/test_generated_fresh.py``
derives everything again and finds them.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import shutil
from functools import cache
from pathlib import Path
from types import ModuleType

from ins_errors.errors import InsErrorsError, ModelDefinitionError
from ins_errors.model_identity import SOURCES_RECORD, changed_builtin_sources


def shipped_package(name: str) -> ModuleType:
    """The metadata module of the built-in model's shipped package
    (``ins_errors.generated.<name>``)."""
    return importlib.import_module(f"ins_errors.generated.{name}")


def stale_sources(meta: ModuleType) -> list[str]:
    """The sources of a built-in model (labels, ``models/north_pointing.py``) that
    changed since its package ``meta`` was derived; empty when it is up to date or
    records no hashes."""
    recorded = getattr(meta, SOURCES_RECORD, None)
    return changed_builtin_sources(recorded) if isinstance(recorded, dict) else []


def _key(name: str) -> str:
    """16 hex digits of the SHA-256 of the model's sources and of the derivation code:
    the end of its cache folder's name."""
    from ins_errors.model_identity import builtin_record, derivation_code_sha256

    sources = builtin_record(name)[SOURCES_RECORD]
    text = "\n".join([f"built-in {name}", *(f"{k} {v}" for k, v in sources.items()),
                      derivation_code_sha256()])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _definition(name: str):
    """The edited model's checked definition (as a model file's: one line on error)."""
    from ins_errors.model_files import build_definition
    from ins_errors.models import MODEL_MODULES

    module_name = MODEL_MODULES[name]
    path = Path(importlib.util.find_spec(module_name).origin)
    label = f"model {name!r} (ins_errors/models/{path.name})"
    try:
        module = importlib.import_module(module_name)
    except SyntaxError as error:
        raise ModelDefinitionError(f"{label}: line {error.lineno}: SyntaxError: "
                                   f"{error.msg} (step: importing the module)") from None
    except Exception as error:  # an edited model: whatever it raised, in one line
        raise ModelDefinitionError(f"{label}: {type(error).__name__}: {error} "
                                   "(step: importing the module)") from None
    return build_definition(module, label, path)


def _derive(name: str, folder: Path) -> None:
    """Derive the edited built-in model into the cache folder ``folder`` (a package put
    there meanwhile by another process is kept and used)."""
    from ins_errors.derive.package import write_package
    from ins_errors.model_identity import builtin_record
    from ins_errors.model_lookup import package_damage

    origin = (f"ins-errors from ins_errors/models/{name}.py, edited since `make derive`",
              "Run `make derive` to update generated/.")
    d = _definition(name)
    try:
        write_package(d, folder, origin, builtin_record(name), replace=False)
    except (InsErrorsError, OSError) as error:
        if folder.is_dir() and package_damage(folder) is None:
            return  # another process wrote the same package meanwhile
        if isinstance(error, InsErrorsError):
            raise
        raise InsErrorsError(f"cannot write the model cache {str(folder)!r}: "
                             f"{error.strerror}") from None


def _prune(current: Path) -> None:
    """Keep the newest versions of ``current``'s model derived from edited sources."""
    from ins_errors.model_lookup import KEEP_VERSIONS

    name = current.name.rsplit("-", 1)[0]
    versions = []
    for folder in current.parent.glob(f"{name}-*"):
        try:
            if (folder != current and folder.is_dir() and folder.name.rsplit("-", 1)[0] == name
                    and SOURCES_RECORD in (folder / "__init__.py").read_text("utf-8")):
                versions.append(folder)
        except OSError:
            continue
    versions.sort(key=lambda f: f.stat().st_mtime, reverse=True)
    for old in versions[KEEP_VERSIONS - 1:]:
        shutil.rmtree(old, ignore_errors=True)


def fresh_folder(name: str, changed: list[str]) -> Path:
    """The cache folder of the built-in model ``name`` derived from its sources as they
    are now, deriving it there if needed; says that the shipped package is stale
    (:func:`~ins_errors.model_lookup.package_notice`; ``changed``: the labels of the
    edited sources).

    Raises
    ------
    ModelDefinitionError
        If the edited model has a mistake (one line naming it and the step).
    InsErrorsError
        If the cache cannot be written.
    """
    from ins_errors.model_lookup import (
        models_cache_directory,
        package_damage,
        package_notice,
    )
    from ins_errors.numeric.cache import store_folders, writable_store

    edited = ", ".join(f"ins_errors/{label}" for label in changed)
    stale = f"generated/{name}/ is stale ({edited} changed since `make derive`)"
    key = _key(name)
    subject = f"stale generated/{name}/ {key}"   # in any words: a worker does not repeat it
    for store in store_folders(models_cache_directory()):  # read-only: + private place
        folder = store / f"{name}-{key}"
        if folder.is_dir() and package_damage(folder) is None:
            package_notice(f"{stale}; using the up-to-date code in the cache (`make "
                           "derive` updates generated/)", subject)
            return folder
    folder = writable_store(models_cache_directory()) / f"{name}-{key}"
    if folder.exists():  # damaged: made again
        shutil.rmtree(folder, ignore_errors=True)
    package_notice(f"{stale}; deriving it again into the cache (`make derive` updates "
                   "generated/)", subject)
    _derive(name, folder)
    _prune(folder)
    return folder


@cache
def _cached_model(name: str, changed: tuple[str, ...], sources: str):
    """The :class:`~ins_errors.numeric.model.Model` of the edited built-in model (once
    per process and version of its sources, ``sources``)."""
    from ins_errors.model_lookup import load_module
    from ins_errors.numeric.model import Model

    folder = fresh_folder(name, list(changed))
    prefix = f"_ins_errors_builtin_{name}_{sources[:16]}"
    meta = load_module(folder / "__init__.py", prefix)
    numpy_module = load_module(folder / "numpy_model.py", f"{prefix}_numpy")
    casadi_module = load_module(folder / "casadi_model.py", f"{prefix}_casadi")
    return Model(name, meta=meta, numpy_module=numpy_module,
                 casadi_loader=lambda: casadi_module, folder=folder)


def builtin_model(name: str):
    """The :class:`~ins_errors.numeric.model.Model` of the built-in model ``name``: its
    shipped package when it is up to date, else (a notice: :func:`fresh_folder`) its code
    derived from the edited sources in the cache."""
    from ins_errors.numeric.model import Model

    meta = shipped_package(name)
    changed = stale_sources(meta)
    if not changed:
        return Model(name, meta=meta)
    from ins_errors.model_identity import builtin_record

    sources = hashlib.sha256(repr(builtin_record(name)).encode()).hexdigest()
    return _cached_model(name, tuple(changed), sources)
