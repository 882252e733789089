"""The identity of a model file's generated code: a hash of the file and its siblings.

A model file may import modules that sit next to it (``from my_constants import ...``);
those are part of its identity, so editing any of them makes the generated code stale.
This module only reads and hashes files: naming a model (:mod:`ins_errors.model_lookup`)
needs its identity in every process, while importing the model file itself, and with it
SymPy (about 0.4 s CPU), is needed only where its code is derived
(:mod:`ins_errors.model_files`).

The generated code also follows from the code that derives it: :func:`derivation_code_sha256`
is a fingerprint of that code (the bytes of every module of :data:`DERIVATION_PACKAGES` and
:data:`DERIVATION_MODULES`, and the versions of Python and SymPy), recorded in each
generated package of a model file and part of its cache key, so that a package derived by
another version of ins-errors is derived again rather than run.

A built-in model's identity is the files of ``ins_errors/models/`` its definition is read
from (:func:`builtin_source_files`): ``make derive`` records their hashes in its package
(:func:`builtin_record`), and loading the model compares them with the files as they are
(:func:`changed_builtin_sources`, :mod:`ins_errors.builtin_packages`).
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import sys
from collections.abc import Mapping
from functools import cache
from pathlib import Path

from ins_errors.errors import InsErrorsError


def file_sha256(path: Path) -> str:
    """SHA-256 (hex) of a model file's bytes: the identity of its generated code."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as error:
        raise InsErrorsError(f"cannot read model file {str(path)!r}: {error.strerror}") from None


def _sibling_imports(path: Path) -> list[Path]:
    """Files next to ``path`` that it imports by absolute name (``x.py``, ``x/*.py``)."""
    try:
        tree = ast.parse(path.read_bytes())
    except (OSError, SyntaxError, ValueError):
        return []  # unreadable or not Python: the import step reports it
    heads = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            heads.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            heads.add(node.module.split(".")[0])
    found = []
    for head in sorted(heads):
        module, package = path.parent / f"{head}.py", path.parent / head
        if module.is_file():
            found.append(module)
        elif (package / "__init__.py").is_file():
            found += sorted(package.rglob("*.py"))
    return found


def source_files(path: Path) -> list[Path]:
    """The model file, then the modules next to it that it imports (recursively)."""
    first = Path(path).resolve()
    seen, todo = [first], [first]
    while todo:
        for found in _sibling_imports(todo.pop()):
            found = found.resolve()
            if found not in seen:
                seen.append(found)
                todo.append(found)
    return [first, *sorted(seen[1:])]


def model_sha256(path: Path) -> str:
    """Identity of a model file's generated code: SHA-256 of the file alone, or of the
    file and the sibling modules it imports (names and bytes, in a fixed order)."""
    files = source_files(path)
    if len(files) == 1:
        return file_sha256(path)
    digest = hashlib.sha256()
    for file in files:
        try:
            digest.update(file.name.encode() + b"\0" + file.read_bytes() + b"\0")
        except OSError as error:
            raise InsErrorsError(f"cannot read {str(file)!r}: {error.strerror}") from None
    return digest.hexdigest()


# --------------------------------------------------------------------------------------
# The code that derives a model file
# --------------------------------------------------------------------------------------
DERIVATION_PACKAGES = ("ins_errors.derive", "ins_errors.symbolic", "ins_errors.models")
"""Packages every module of which is derivation code: the code writer (``derive/`` in a
checkout), the variation, code generation and definition checks, and the built-in models
with the Earth and platform formulas a model file imports or builds on."""

DERIVATION_MODULES = ("ins_errors.modeling", "ins_errors.model_files",
                      "ins_errors.model_identity", "ins_errors.model_lookup",
                      "ins_errors.units", "ins_errors.errors")
"""Further modules a derivation runs: the modelling API, the import and check of a model
file, its identity and the record and banner written with its package, the units of the
dimension checks and the messages of refusals."""

NOT_DERIVATION = ("ins_errors.checker", "ins_errors.conventions", "ins_errors.numeric.cache",
                  "ins_errors.output", "ins_errors.user_paths")
"""Project modules (and packages) the derivation code imports whose code does not decide
what a model file's package holds or whether it is refused: the checker (reports on the
hand derivations of built-in models, written by ``make derive`` only), the conventions'
F and G of any model (:mod:`ins_errors.conventions`, built on the checker, imported by
:mod:`ins_errors.models.strapdown_conventions` when it is asked for another model),
the cache folders' bookkeeping, the writing of files (:mod:`ins_errors.output`: their
permissions) and the spelling of a path (``~``, :mod:`ins_errors.user_paths`). Every
other project module a derivation module imports belongs in :data:`DERIVATION_PACKAGES`
or :data:`DERIVATION_MODULES` (tests/test_derivation_code.py checks this)."""


def _folder(package: str, locations: Mapping[str, Path]) -> Path:
    """The folder of a package (of a copy given in ``locations``, else the imported one)."""
    parent, _, child = package.rpartition(".")
    if package in locations:
        return Path(locations[package])
    if parent in locations:
        return Path(locations[parent]) / child
    spec = importlib.util.find_spec(package)  # imports the parents only
    if spec is None or not spec.submodule_search_locations:
        raise InsErrorsError(f"cannot find the package {package} of ins-errors "
                             "(a broken installation)")
    return Path(next(iter(spec.submodule_search_locations)))


def derivation_sources(locations: Mapping[str, Path] | None = None) -> list[tuple[str, Path]]:
    """The files of the code that derives a model file: ``(label, file)`` sorted by label.

    Parameters
    ----------
    locations : mapping, optional
        Package name (``"ins_errors"``, ``"ins_errors.derive"``) -> folder of a copy to
        read instead of the imported package (tests). A checkout keeps ``derive/`` outside
        ``ins_errors/``; a wheel ships it as ``ins_errors/derive/``.

    Returns
    -------
    list of (str, Path)
        The module name relative to its package's folder (``ins_errors.derive/steps.py``,
        the same in a checkout and a wheel) and the file.
    """
    locations = locations or {}
    found = []
    for package in DERIVATION_PACKAGES:
        folder = _folder(package, locations)
        found += [(f"{package}/{path.relative_to(folder).as_posix()}", path)
                  for path in folder.rglob("*.py") if "__pycache__" not in path.parts]
    for module in DERIVATION_MODULES:
        package, _, name = module.rpartition(".")
        found.append((f"{package}/{name}.py", _folder(package, locations) / f"{name}.py"))
    return sorted(found)


def _sympy_version() -> str:
    """SymPy's version read from its files (importing SymPy takes ~0.4 s)."""
    spec = importlib.util.find_spec("sympy")
    try:
        text = (Path(spec.origin).parent / "release.py").read_text(encoding="utf-8")
    except (AttributeError, TypeError, OSError):
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("sympy")
        except PackageNotFoundError:
            return "none"
    return " ".join(text.split())


def derivation_digest(locations: Mapping[str, Path] | None = None) -> str:
    """SHA-256 (hex) of the code that derives a model file: the label and bytes of each
    file of :func:`derivation_sources`, then the versions of Python and SymPy.

    Any change to those files (code, docstrings or comments alike) is a new digest:
    over-approximating costs a derivation, missing a change would run stale code.
    """
    digest = hashlib.sha256()
    try:
        for label, path in derivation_sources(locations):
            digest.update(label.encode() + b"\0" + path.read_bytes() + b"\0")
    except OSError as error:
        raise InsErrorsError("cannot read the derivation code of ins-errors "
                             f"({error.filename}: {error.strerror})") from None
    digest.update(f"{sys.version}|sympy {_sympy_version()}".encode())
    return digest.hexdigest()


@cache
def derivation_code_sha256() -> str:
    """:func:`derivation_digest` of the installed ins-errors, made once per process
    (about 2 ms: a few dozen files read and hashed)."""
    return derivation_digest()


# --------------------------------------------------------------------------------------
# The sources of a built-in model
# --------------------------------------------------------------------------------------
MODELS_PACKAGE = "ins_errors.models"
"""The package of the built-in models' definitions: the files of a built-in model's
identity are its modules (:func:`builtin_source_files`)."""

_FOLLOWED = ("ins_errors.modeling",)
"""Modules outside :data:`MODELS_PACKAGE` whose imports are followed to the model
modules they read (the authoring API reads the Earth and platform formulas)."""


def _package_folder() -> Path:
    """The folder of the ``ins_errors`` package (this module's)."""
    return Path(__file__).resolve().parent


def _module_file(package: Path, module: str) -> Path | None:
    """The file of the project module ``module`` (``ins_errors.models.earth``), if any."""
    path = package.joinpath(*module.split(".")[1:])
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _imported_modules(path: Path, module: str) -> set[str]:
    """Modules named by the import statements of ``path`` (also inside functions);
    ``from a import b`` names ``a`` and ``a.b`` (b may be a module); none for a file
    that is not Python (an edit in progress: importing it says what is wrong)."""
    package = module.rpartition(".")[0]
    names = set()
    try:
        tree = ast.parse(path.read_bytes())
    except (SyntaxError, ValueError):
        return names
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return names


def builtin_source_files(name: str) -> dict[str, Path]:
    """The files a built-in model's definition is read from: its module in
    ``ins_errors/models/`` and the modules of that folder it imports, directly or through
    :data:`_FOLLOWED` (``earth.py``, ``platform.py``); label (``models/earth.py``, the
    path inside the package) -> file, sorted by label. The registry
    ``models/__init__.py`` is not one of them.

    Raises
    ------
    UnknownNameError
        If ``name`` is not a built-in model.
    """
    from ins_errors.errors import unknown_name
    from ins_errors.models import MODEL_MODULES

    if name not in MODEL_MODULES:
        raise unknown_name("model", name, MODEL_MODULES)
    package = _package_folder()
    found: dict[str, Path] = {}
    waiting, seen = [MODEL_MODULES[name]], set()
    while waiting:
        module = waiting.pop()
        path = None if module in seen else _module_file(package, module)
        seen.add(module)
        if path is None:
            continue
        if module.startswith(MODELS_PACKAGE + ".") and path.name != "__init__.py":
            found[path.relative_to(package).as_posix()] = path
        waiting += [m for m in _imported_modules(path, module)
                    if m.startswith(MODELS_PACKAGE + ".") or m in _FOLLOWED]
    return dict(sorted(found.items()))


SOURCES_RECORD = "MODEL_SOURCES_SHA256"
"""Name of the record, in a built-in model's generated ``__init__.py``, of the SHA-256 of
each file its definition is read from (:func:`builtin_source_files`)."""


def builtin_record(name: str) -> dict[str, dict[str, str]]:
    """The record ``make derive`` writes into a built-in model's package
    (:data:`SOURCES_RECORD`: label -> SHA-256 of each of :func:`builtin_source_files`),
    checked whenever the model is loaded (:func:`changed_builtin_sources`)."""
    return {SOURCES_RECORD: {label: file_sha256(path)
                             for label, path in builtin_source_files(name).items()}}


def changed_builtin_sources(recorded: Mapping[str, str]) -> list[str]:
    """The labels of ``recorded`` (``MODEL_SOURCES_SHA256`` of a built-in model's
    package) whose file now differs from its recorded SHA-256 or is missing: empty when
    the package is up to date. Reads and hashes a few files (about 0.1 ms; no SymPy)."""
    package = _package_folder()
    changed = []
    for label, sha in recorded.items():
        try:
            data = (package / label).read_bytes()
        except OSError:
            changed.append(label)
            continue
        if hashlib.sha256(data).hexdigest() != sha:
            changed.append(label)
    return changed
