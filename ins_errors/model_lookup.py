"""One answer to "which model did the user mean, and where is its generated code?".

Every command, scenario file and :func:`ins_errors.load_model` goes through
:func:`resolve`. A model is named in one of three ways:

* a built-in model name (``orthodromic``): its code ships in ``ins_errors.generated``
  (derived again into the cache when its model was edited since: see
  :mod:`ins_errors.builtin_packages`);
* a model file path (``./my_ins.py``; a scenario's ``model = "my_ins.py"`` is taken
  relative to the scenario file): a Python file written with :mod:`ins_errors.modeling`;
* the name of an installed entry point in the group ``ins_errors.models`` (a package's
  ``pyproject.toml``: ``[project.entry-points."ins_errors.models"] my_ins =
  "my_package.my_ins"``), pointing at a module with ``build()`` (or at ``build`` itself).

The generated code of a model file (or entry-point module) is identified by the SHA-256
of the file and by the fingerprint of the code that derives it
(:func:`~ins_errors.model_identity.derivation_code_sha256`). It is taken from
``<file folder>/<file stem>_generated/`` (what ``ins-errors derive FILE`` writes by
default) when that package records both, else from the user cache
(``$INS_ERRORS_CACHE/models`` or ``~/.cache/ins-errors/models``, folders
``<model>-<first 16 hex of the SHA-256 of both>``), where it is derived on first use (the
:data:`KEEP_VERSIONS` newest versions of each model are kept there). A stale package (the
model file was edited since, or another version of ins-errors derived it) is never used:
a notice says so (:func:`package_notice`: a :class:`RuntimeWarning`, one line on the
command line's stderr, once per process) and the code is regenerated in the cache. A
cache folder that cannot be written (mounted read-only) is still read; code it lacks is
derived into this user's private folder (:func:`ins_errors.numeric.cache.writable_store`),
said in one line.
"""

from __future__ import annotations

import glob
import hashlib
import importlib
import importlib.metadata
import importlib.util
import os
import re
import shutil
import sys
import warnings
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from types import ModuleType
from typing import Literal

from ins_errors.errors import (
    InsErrorsError,
    InsErrorsNotice,
    ModelDefinitionError,
    UnknownNameError,
    unknown_name,
)

ENTRY_POINT_GROUP = "ins_errors.models"
"""Entry-point group through which installed packages register models."""

KEEP_VERSIONS = 5
"""Versions of one model file kept in the cache (older ones are deleted as new ones come)."""

NEXT_TO_SUFFIX = "_generated"
"""``my_ins.py`` -> ``my_ins_generated/``: where ``ins-errors derive`` writes by default."""

_KEY = re.compile(r"(?P<spec>.+)@sha256:(?P<sha>[0-9a-f]{16})")
_RECORD = re.compile(r"^MODEL_FILE_SHA256 = '(?P<sha>[0-9a-f]{64})'$", re.M)
_CODE_RECORD = re.compile(r"^DERIVATION_CODE_SHA256 = '(?P<sha>[0-9a-f]{64})'$", re.M)


@dataclass(frozen=True)
class ModelRef:
    """A resolved model reference.

    Attributes
    ----------
    kind : {"builtin", "file", "entry_point"}
        How the model was named.
    spec : str
        Built-in name, absolute file path, or entry-point name.
    path : Path or None
        The model file (files and entry-point modules).
    sha256 : str or None
        SHA-256 of the model file.
    """

    kind: Literal["builtin", "file", "entry_point"]
    spec: str
    path: Path | None = None
    sha256: str | None = None

    @property
    def key(self) -> str:
        """A string :func:`resolve` maps back to this exact model version (used as the
        in-process cache key and by worker processes)."""
        if self.kind == "builtin":
            return self.spec
        return f"{self.spec}@sha256:{self.sha256[:16]}"

    @property
    def label(self) -> str:
        """How messages name the model source."""
        if self.kind == "file":
            return f"model file {self.path.name}"
        if self.kind == "entry_point":
            return f"model {self.spec!r} (entry point of {ENTRY_POINT_GROUP})"
        return f"model {self.spec!r}"


def command_name(model) -> str:
    """How a command line names ``model`` (e.g. in "`ins-errors modes ...` names the
    mode"): a built-in's name, a model file's path (relative to the working folder unless
    that climbs more than two folders: ``my_ins.py``, not ``my_ins``, which no command
    finds), an entry point's name."""
    match = _KEY.fullmatch(str(getattr(model, "key", "") or ""))
    if match is None:
        return model.name
    path = Path(match["spec"])
    if not path.is_absolute():  # an entry point's name
        return match["spec"]
    relative = os.path.relpath(path)
    return relative if relative.count("..") <= 2 else str(path)


# --------------------------------------------------------------------------------------
# Resolution
# --------------------------------------------------------------------------------------
def builtin_names() -> tuple[str, ...]:
    """Names of the built-in models (those with code in ``ins_errors.generated``)."""
    return tuple(importlib.import_module("ins_errors.generated").MODELS)


def _entry_points() -> dict[str, importlib.metadata.EntryPoint]:
    return {ep.name: ep for ep in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP)}


def entry_point_names() -> tuple[str, ...]:
    """Names of the models installed packages register (group ``ins_errors.models``)."""
    return tuple(sorted(_entry_points()))


def _looks_like_path(spec: str) -> bool:
    return spec.endswith(".py") or "/" in spec or os.sep in spec


def _entry_point_file(name: str) -> Path:
    ep = _entry_points()[name]
    module_name = ep.value.split(":", 1)[0].strip()
    try:
        found = importlib.util.find_spec(module_name)
    except (ImportError, ValueError):
        found = None
    if found is None or not found.origin or not found.origin.endswith(".py"):
        raise ModelDefinitionError(f"model {name!r}: entry point {ep.value!r} of "
                                   f"{ENTRY_POINT_GROUP} names no Python module file")
    return Path(found.origin)


def resolve(spec: str, relative_to: str | Path | None = None) -> ModelRef:
    """Resolve a model name, model file path or entry-point name.

    Parameters
    ----------
    spec : str
        ``"orthodromic"``, ``"./my_ins.py"``, an entry-point name, or a
        :attr:`ModelRef.key`.
    relative_to : path, optional
        Folder a relative file path is taken from (a scenario file's folder); default:
        the current folder.

    Raises
    ------
    UnknownNameError
        For a name that is neither built in nor registered (with close names).
    ModelDefinitionError
        For a model file that does not exist, or that changed since ``spec`` (a key)
        was made.
    """
    spec = str(spec)
    expected = None
    match = _KEY.fullmatch(spec)
    if match:
        spec, expected = match["spec"], match["sha"]
    builtins = builtin_names()
    if spec in builtins:
        return ModelRef("builtin", spec)
    from ins_errors.model_identity import model_sha256

    if _looks_like_path(spec) or Path(spec).is_file():
        from ins_errors.user_paths import user_path

        path = user_path(spec)
        if relative_to is not None and not path.is_absolute():
            path = Path(relative_to) / path
        looked = (f" (looked in {str(Path(relative_to))!r})" if relative_to is not None
                  else "")
        if path.is_dir():
            raise ModelDefinitionError(f"model file {spec!r} is a folder, not a Python file"
                                       f"{looked}: give the .py file that defines build()")
        if not path.is_file():
            raise ModelDefinitionError(f"model file {spec!r} not found{looked}")
        ref = ModelRef("file", str(path.resolve()), path.resolve(), model_sha256(path))
    elif spec in _entry_points():
        path = _entry_point_file(spec)
        ref = ModelRef("entry_point", spec, path, model_sha256(path))
    else:
        error = unknown_name("model", spec, [*builtins, *entry_point_names()])
        folder = (f"; {spec!r} is a folder, not a model file" if Path(spec).is_dir()
                  else "")
        raise UnknownNameError(f"{error} (or a model file, e.g. ./my_ins.py){folder}")
    if expected is not None and not ref.sha256.startswith(expected):
        raise ModelDefinitionError(f"{ref.label} changed while in use (its generated code "
                                   "was made from another version); run again")
    return ref


# --------------------------------------------------------------------------------------
# Definitions
# --------------------------------------------------------------------------------------
@cache
def _definition(ref: ModelRef):
    from ins_errors.model_files import build_definition, import_model_file

    if ref.kind == "builtin":
        from ins_errors.models import definition

        return definition(ref.spec)
    if ref.kind == "file":
        d = build_definition(import_model_file(ref.path), ref.label, ref.path)
    else:
        ep = _entry_points()[ref.spec]
        try:
            target = ep.load()
        except Exception as error:  # a package's code: report whatever it raised
            raise ModelDefinitionError(f"{ref.label}: {type(error).__name__}: {error} "
                                       "(step: importing the module)") from None
        module = target if isinstance(target, ModuleType) else _Builder(target)
        d = build_definition(module, ref.label, ref.path)
        if d.name != ref.spec:
            raise ModelDefinitionError(f"{ref.label}: builds the model {d.name!r}; register "
                                       "the entry point under the model's own name")
    if d.name in builtin_names():
        raise ModelDefinitionError(f"{ref.label}: model name {d.name!r} is taken by a "
                                   "built-in model; choose another name in build()")
    return d


class _Builder:
    """Adapter: an entry point naming ``build`` itself instead of its module."""

    def __init__(self, build):
        self.build = build


def definition_of(ref: ModelRef):
    """The checked :class:`~ins_errors.modeling.ModelDefinition` of a resolved model."""
    return _definition(ref)


# --------------------------------------------------------------------------------------
# Generated code
# --------------------------------------------------------------------------------------
def models_cache_directory() -> Path:
    """Where the generated code of model files is kept (``$INS_ERRORS_CACHE/models`` or
    the user cache folder next to the compiled loops)."""
    from ins_errors.numeric.cache import store_directory

    return store_directory("models")


def next_to(path: Path) -> Path:
    """The default package folder of a model file: ``<stem>_generated/`` beside it."""
    return path.with_name(path.stem + NEXT_TO_SUFFIX)


def recorded_hashes(folder: Path) -> tuple[str | None, str | None]:
    """``(model-file hash, derivation-code fingerprint)`` a generated package records;
    None for what it does not record (no such package, or one written before
    ins-errors recorded the fingerprint)."""
    try:
        text = (folder / "__init__.py").read_text(encoding="utf-8")
    except OSError:
        return None, None
    match, code = _RECORD.search(text), _CODE_RECORD.search(text)
    return (match["sha"] if match else None), (code["sha"] if code else None)


def recorded_sha256(folder: Path) -> str | None:
    """The model-file hash a generated package records, or None (no such package)."""
    return recorded_hashes(folder)[0]


def current_hashes(ref: ModelRef) -> tuple[str, str]:
    """What an up-to-date package of ``ref`` records: the model file's hash and the
    fingerprint of this installation's derivation code."""
    from ins_errors.model_identity import derivation_code_sha256

    return ref.sha256, derivation_code_sha256()


def cache_key(ref: ModelRef) -> str:
    """The end of the cache folder name of ``ref``'s package: 16 hex digits of the
    SHA-256 of the model file's hash and the derivation code's fingerprint."""
    both = "\n".join(current_hashes(ref))
    return hashlib.sha256(both.encode()).hexdigest()[:16]


def package_record(ref: ModelRef) -> tuple[tuple[str, str], dict[str, str]]:
    """Banner lines and metadata record of the generated package of a model file."""
    origin = (f"`ins-errors derive` from the model file {ref.path.name}",
              f"Edit {ref.path.name} and run `ins-errors derive` again.")
    sha, code = current_hashes(ref)
    return origin, {"MODEL_FILE": ref.path.name, "MODEL_FILE_SHA256": sha,
                    "DERIVATION_CODE_SHA256": code}


def _say(message: str) -> None:
    """Say on stderr, as progress, that a model file is being derived (a version the cache
    does not hold yet); a stale or damaged package is a notice: :func:`package_notice`."""
    print(f"ins-errors: {message}", file=sys.stderr)


NOTICES_GIVEN_VARIABLE = "INS_ERRORS_PACKAGE_NOTICES_GIVEN"
"""The notices of :func:`package_notice` a process has given (16 hex digits each,
separated by spaces), set in its environment as it gives them: the worker processes it
starts afterwards (a process pool, a local Dask cluster) do not give them again."""

_NOTICES_GIVEN: set[str] = set()


def package_notice(message: str, about: str | None = None) -> None:
    """Say that a generated package is stale or damaged (``message``, after
    ``ins-errors: ``): an :class:`~ins_errors.errors.InsErrorsNotice` (a
    :class:`RuntimeWarning`), which the command line prints as this one line and the
    Python API can filter or record (:mod:`warnings`).

    Given once per process for each subject ``about`` (default: the message; the stale
    package and the version it is stale against, so that a worker that finds the fresh
    code in the cache does not say it in other words), and not in a worker process of a
    process that has given it (:data:`NOTICES_GIVEN_VARIABLE`). It is about the machine,
    not the results: ``--fail-on-warning`` does not count it.
    """
    key = hashlib.sha256((about or message).encode()).hexdigest()[:16]
    if key in _NOTICES_GIVEN:
        return
    _NOTICES_GIVEN.add(key)
    given = os.environ.get(NOTICES_GIVEN_VARIABLE, "").split()
    if key in given:
        import multiprocessing

        if multiprocessing.parent_process() is not None:
            return  # a worker: the process that started it has said so
    else:
        os.environ[NOTICES_GIVEN_VARIABLE] = " ".join([*given, key])
    warnings.warn(f"ins-errors: {message}", InsErrorsNotice, stacklevel=2)


FILES_RECORD = "GENERATED_FILES"
"""Name of the record, in a package's ``__init__.py``, of its other files' lengths and
hashes (:func:`seal_package`)."""

_FILE_ROW = re.compile(r"^    '(?P<name>[A-Za-z0-9_.]+)': \((?P<size>\d+), "
                       r"'(?P<sha>[0-9a-f]{64})'\),$", re.M)


def seal_package(folder: Path) -> None:
    """Record, at the end of the generated package ``folder``'s ``__init__.py``, the
    length and SHA-256 of each of its other files (:data:`FILES_RECORD`), then seal the
    ``__init__.py`` itself (:func:`ins_errors.numeric.cache.sealed`), so that
    :func:`package_damage` finds a package cut short or altered before it is used.
    Called on the package in its scratch folder, before it is renamed into place.

    Raises
    ------
    OSError
        If a file cannot be read or written.
    """
    from ins_errors.numeric.cache import sealed

    init = folder / "__init__.py"
    rows = []
    for path in sorted(folder.iterdir()):
        if path.is_file() and path.name != init.name:
            data = path.read_bytes()
            rows.append(f"    {path.name!r}: ({len(data)}, "
                        f"{hashlib.sha256(data).hexdigest()!r}),\n")
    text = init.read_text(encoding="utf-8").rstrip("\n") + "\n"
    text += (f"\n# the other files of this package, checked before it is used: name: "
             f"(bytes, SHA-256)\n{FILES_RECORD} = {{\n{''.join(rows)}}}\n")
    init.write_bytes(sealed(text.encode("utf-8")))


def package_damage(folder: Path) -> str | None:
    """Why the generated package ``folder`` (sealed by :func:`seal_package`) cannot be
    used: its ``__init__.py`` is not sealed whole, or another file is missing or differs
    from the length and hash recorded there (``"numpy_model.py is cut short or
    altered"``); None when it is complete. Reads and hashes every file (~1 ms for the
    strapdown model's 0.4 MB)."""
    from ins_errors.numeric.cache import unsealed

    try:
        text = unsealed((folder / "__init__.py").read_bytes())
    except OSError:
        return "__init__.py cannot be read"
    record = None if text is None else text.decode("utf-8", "replace").partition(
        f"\n{FILES_RECORD} = {{\n")[2]
    if not record:
        return "__init__.py is cut short or altered"
    for row in _FILE_ROW.finditer(record):
        try:
            data = (folder / row["name"]).read_bytes()
        except OSError:
            return f"{row['name']} is missing"
        if len(data) != int(row["size"]) or hashlib.sha256(data).hexdigest() != row["sha"]:
            return f"{row['name']} is cut short or altered"
    return None


def generated_folder(ref: ModelRef) -> Path:
    """The folder with up-to-date generated code of a model file, deriving it if needed.

    A package is checked whole before it is used (:func:`package_damage`): a damaged
    one is said (:func:`package_notice`) and derived again in its place, never imported.

    Raises
    ------
    ModelDefinitionError
        If the model file has a mistake (nothing is written then).
    InsErrorsError
        If ``<stem>_generated/`` is damaged and cannot be written again (one line naming
        the folder and the cure).
    """
    beside = next_to(ref.path)
    current = current_hashes(ref)
    recorded = recorded_hashes(beside)
    if recorded == current:
        damage = package_damage(beside)
        if damage is None:
            return beside
        return _derive_again(ref, beside, damage)
    stale = None
    if recorded[0] is not None:
        stale = (f"{beside.name}/ is stale ({ref.path.name} or a file it imports changed "
                 "since it was derived)" if recorded[0] != current[0] else
                 f"{beside.name}/ was derived by another version of ins-errors")
    # the subject of the stale notice: this package against this version (a worker
    # that finds the code derived by its parent does not say it again in other words)
    subject = f"stale {beside} {recorded} {current}"
    cached, damaged = _cached_package(ref)
    if cached is not None:
        if stale:
            package_notice(f"{stale}; using the up-to-date code in the cache", subject)
        return cached
    from ins_errors.numeric.cache import writable_store

    # a read-only cache's private place, found before the SymPy work
    folder = writable_store(models_cache_directory())
    d = definition_of(ref)
    cached = folder / f"{d.name}-{cache_key(ref)}"
    if cached.exists() and package_damage(cached) is not None:
        _discard(cached)   # damaged: made again below
    if damaged is not None:
        package_notice(f"the cached code {str(damaged[0])!r} is damaged ({damaged[1]}) "
                       f"and is not used; deriving {ref.label} again")
    elif stale:
        package_notice(f"{stale}; deriving again into the cache", subject)
    elif _derived_by_other_code(ref):   # as the first use: progress, not a notice
        _say(f"deriving {ref.label} again: its cached code was derived by another version "
             "of ins-errors (cached for next time)")
    else:
        _say(f"deriving {ref.label} (first use of this version; cached for next time)")
    origin, record = package_record(ref)
    try:
        # never over a package another process has put there meanwhile (it may be
        # importing it): that one is used instead
        write_derived(ref, d, cached, origin, record, replace=False)
    except (InsErrorsError, OSError) as error:
        if recorded_hashes(cached) == current and package_damage(cached) is None:
            return cached  # another process wrote the same package meanwhile
        if isinstance(error, InsErrorsError):
            raise
        raise InsErrorsError(f"cannot write the model cache {str(cached)!r}: "
                             f"{error.strerror}") from None
    _prune(cached)
    return cached


def _derive_again(ref: ModelRef, beside: Path, damage: str) -> Path:
    """Derive the damaged up-to-date package ``beside`` (``<stem>_generated/``) again in
    its place, said (:func:`package_notice`); a one-line error naming the folder and the cure where
    it cannot be written."""
    def refused(why: str) -> InsErrorsError:
        return InsErrorsError(f"the generated package {str(beside)!r} is damaged ({damage}) "
                              f"and cannot be written again ({why}): delete the folder, or "
                              f"run `ins-errors derive {ref.path.name}` where it can be "
                              "written")

    writable = os.W_OK | os.X_OK
    if (not os.access(beside.parent, writable) or not os.access(beside, writable)
            or os.path.ismount(beside)):
        raise refused("read-only")   # before the SymPy work
    package_notice(f"{beside.name}/ is damaged ({damage}); deriving it again",
                   f"damaged {beside} {damage}")
    d = definition_of(ref)
    origin, record = package_record(ref)
    try:
        write_derived(ref, d, beside, origin, record)
    except ModelDefinitionError:
        raise
    except (InsErrorsError, OSError) as error:
        if recorded_hashes(beside) == current_hashes(ref) and package_damage(beside) is None:
            return beside  # another process wrote it meanwhile
        raise refused(str(error)) from None
    return beside


def _discard(folder: Path) -> None:
    """Remove the damaged package ``folder``: renamed aside first (one step), so that no
    process finds it half deleted."""
    import tempfile

    try:
        aside = Path(tempfile.mkdtemp(prefix=f".{folder.name}.damaged-", dir=folder.parent))
        folder.rename(aside / folder.name)
    except OSError:
        return  # gone meanwhile, or not ours to remove: writing over it says so
    shutil.rmtree(aside, ignore_errors=True)


def write_derived(ref: ModelRef, d, out: Path, origin, record, replace: bool = True):
    """Derive ``d`` (the definition of ``ref``) into the package folder ``out``:
    :func:`ins_errors.derive.package.write_package`, whose errors name the model file
    (``replace``: whether a package already at ``out`` is replaced, else kept and the
    new one dropped, an error).

    Returns
    -------
    The summary ``write_package`` returns.

    Raises
    ------
    ModelDefinitionError
        One line naming the file (for a model file): a SymPy failure in the derivation,
        or an expression nested too deeply for SymPy's recursive walks (a RecursionError).
    """
    from ins_errors.derive.package import write_package

    try:
        return write_package(d, out, origin, record, replace=replace)
    except RecursionError:  # SymPy's printers and simplification recurse per level
        raise ModelDefinitionError(f"{ref.label} (model {d.name!r}): an expression is too "
                                   "deeply nested for SymPy (RecursionError while deriving "
                                   "its code): name its inner parts as intermediate "
                                   "quantities with let()") from None
    except InsErrorsError as error:
        if ref.path is not None and ref.path.name not in str(error):  # the file to fix
            raise type(error)(f"{ref.label}: {error}") from None
        raise


def _cached_package(ref: ModelRef) -> tuple[Path | None, tuple[Path, str] | None]:
    """The cached package of this version of a model file, derived by this version of
    the derivation code, if there is one; and, when there is none, the first such
    package found damaged (:func:`package_damage`) with what is wrong with it.

    Found by the key its folder name ends with and its record, not by the model's name:
    the name is known only once the file is imported and its ``build()`` has run (with
    SymPy, about 0.5 s CPU), which a process that only runs the generated code does not
    need. An entry point's package must bear the entry point's name (the model's own
    name, else :func:`definition_of` refuses it).
    """
    from ins_errors.numeric.cache import store_folders

    name = glob.escape(ref.spec) if ref.kind == "entry_point" else "*"
    current = current_hashes(ref)
    damaged = None
    for store in store_folders(models_cache_directory()):  # read-only: + private place
        try:
            candidates = sorted(store.glob(f"{name}-{cache_key(ref)}"))
        except OSError:
            continue
        for folder in candidates:
            if recorded_hashes(folder) != current:
                continue
            damage = package_damage(folder)
            if damage is None:
                return folder, None
            damaged = damaged or (folder, damage)
    return None, damaged


def _derived_by_other_code(ref: ModelRef) -> bool:
    """True if the cache holds a package of this version of the model file derived by
    other derivation code (read only when deriving, to say why)."""
    try:
        folders = list(models_cache_directory().glob("*-*"))
    except OSError:
        return False
    return any(recorded_sha256(folder) == ref.sha256 for folder in folders)


def _prune(current: Path) -> None:
    """Keep the :data:`KEEP_VERSIONS` newest cached versions of ``current``'s model."""
    name = current.name.rsplit("-", 1)[0]
    versions = [f for f in current.parent.glob(f"{name}-*")
                if f.is_dir() and f != current and f.name.rsplit("-", 1)[0] == name
                and recorded_sha256(f) is not None]
    versions.sort(key=lambda f: f.stat().st_mtime, reverse=True)
    for old in versions[KEEP_VERSIONS - 1:]:
        shutil.rmtree(old, ignore_errors=True)


def load_module(path: Path, name: str) -> ModuleType:
    """Import one generated file under a private module name."""
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise InsErrorsError(f"cannot import generated file {str(path)!r}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module
