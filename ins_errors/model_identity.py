"""The identity of a model file's generated code: a hash of the file and its siblings.

A model file may import modules that sit next to it (``from my_constants import ...``);
those are part of its identity, so editing any of them makes the generated code stale.
This module only reads and hashes files: naming a model (:mod:`ins_errors.model_lookup`)
needs its identity in every process, while importing the model file itself, and with it
SymPy (about 0.4 s CPU), is needed only where its code is derived
(:mod:`ins_errors.model_files`).
"""

from __future__ import annotations

import ast
import hashlib
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
