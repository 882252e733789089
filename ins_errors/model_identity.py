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
