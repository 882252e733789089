"""The fingerprint of the code that writes and builds a compiled loop's C source.

A compiled library is cached under a complete description of what its C source is
written from (:func:`ins_errors.numeric.integrators._functions_key`): the CasADi
functions, the loop's settings, the compiler, its flags and the CPU, and the version of
the Python code that turns them into C text and builds it. That version is this
module's :func:`fingerprint`: the syntax trees of :data:`ROOTS` and of every definition
of the project they use, followed through the modules (a function they call, a constant
or C template they format, a class they instantiate), less :data:`OTHERS`. Docstrings,
comments, annotations and layout are not part of a syntax tree, so editing them (or any
code the roots do not reach) leaves every cached library valid, while any change to what
writes the C text or runs the compiler makes new keys.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import sys
from collections.abc import Iterator, Mapping
from functools import cache

ROOTS: dict[str, tuple[str, ...]] = {
    "ins_errors.numeric.integrators": (
        "compile_library", "compile_source", "_functions_key", "CompiledLoop.__init__",
        "CompiledLoop._build", "CompiledLoop._frozen_probed"),
}
"""Where the C text of a compiled library is written and built (module: qualified names);
``_frozen_probed`` chooses the numbers a time-invariant loop's C is written with."""

OTHERS: frozenset[str] = frozenset({
    # run-time bookkeeping: where the library goes, what is said, how it is called
    "ins_errors.numeric.integrators:_writable",
    "ins_errors.numeric.integrators:cache_directory",
    "ins_errors.numeric.integrators:_vm_notice",
    "ins_errors.numeric.integrators:NativeFunction",
    "ins_errors.numeric.integrators:Signature",
    "ins_errors.numeric.integrators:_SizedRun",
    "ins_errors.numeric.integrators:VirtualFunction",
    "ins_errors.numeric.integrators:CompiledLoop._virtual",
    "ins_errors.numeric.integrators:check_method",
    "ins_errors.numeric.integrators:worker_count",
    "ins_errors.numeric.integrators:StepError",
    "ins_errors.numeric.cache",
    "ins_errors.errors",
    "ins_errors.progress",
    # their results are in the key as values: the compiler's path, the CPU's identity
    "ins_errors.numeric.integrators:_compiler",
    "ins_errors.numeric.integrators:_cpu_identity",
    # the fingerprint itself
    "ins_errors.numeric.integrators:_writer_version",
})
"""Definitions (``module:name``) and whole modules the roots use that do not decide the C
text or its build."""

_PACKAGE = "ins_errors"


def _source(module: str, sources: Mapping[str, str]) -> str | None:
    if module in sources:
        return sources[module]
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
        return None
    with open(spec.origin, encoding="utf-8") as handle:
        return handle.read()


def _is_module(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


class _Module:
    """The top-level definitions of one module and the project modules it imports."""

    def __init__(self, name: str, text: str):
        self.name = name
        self.definitions: dict[str, ast.AST] = {}
        self.imported: dict[str, tuple[str, str | None]] = {}   # alias -> (module, name)
        for node in ast.parse(text).body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                self.definitions[node.name] = node
                if isinstance(node, ast.ClassDef):
                    for item in node.body:
                        if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                            self.definitions[f"{node.name}.{item.name}"] = item
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                for target in targets:
                    for leaf in ast.walk(target):
                        if isinstance(leaf, ast.Name):
                            self.definitions[leaf.id] = node
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                self.imported.update(_imports(node))


def _imports(node: ast.Import | ast.ImportFrom) -> Iterator[tuple[str, tuple[str, str | None]]]:
    """``alias -> (module, name)`` of a project import (name None: a module)."""
    if isinstance(node, ast.Import):
        for alias in node.names:
            if alias.name.split(".")[0] == _PACKAGE:
                yield alias.asname or alias.name, (alias.name, None)
        return
    if node.level or not node.module or node.module.split(".")[0] != _PACKAGE:
        return
    for alias in node.names:
        full = f"{node.module}.{alias.name}"
        yield alias.asname or alias.name, ((full, None) if _is_module(full)
                                           else (node.module, alias.name))


def _bare(node: ast.AST) -> list[ast.AST]:
    """The nodes of ``node``'s tree, docstrings and annotations removed (in place)."""
    for item in ast.walk(node):
        body = getattr(item, "body", None)
        if (isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
                and body and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)):
            item.body = body[1:] or [ast.Pass()]
        if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
            item.returns = None
        if isinstance(item, ast.arg):
            item.annotation = None
        if isinstance(item, ast.AnnAssign):
            item.annotation = ast.Constant(None)
    return list(ast.walk(node))


def writer_code(sources: Mapping[str, str] | None = None) -> dict[str, str]:
    """The code that writes and builds the C: ``{"module:name": syntax tree dump}`` of
    :data:`ROOTS` and every project definition they reach, less :data:`OTHERS`.

    Parameters
    ----------
    sources : mapping, optional
        Module name -> source text to use instead of the installed file (tests).
    """
    sources = sources or {}
    modules: dict[str, _Module | None] = {}

    def module(name: str) -> _Module | None:
        if name not in modules:
            text = _source(name, sources)
            modules[name] = None if text is None else _Module(name, text)
        return modules[name]

    code: dict[str, str] = {}
    queue = [(m, name) for m, names in ROOTS.items() for name in names]
    while queue:
        name, qualified = queue.pop()
        key = f"{name}:{qualified}"
        if key in code or key in OTHERS or name in OTHERS:
            continue
        where = module(name)
        if where is None:
            continue
        node = where.definitions.get(qualified)
        if node is None:
            continue
        nodes = _bare(node)
        code[key] = ast.dump(node, include_attributes=False)
        local = dict(where.imported)
        for item in nodes:
            if isinstance(item, (ast.Import, ast.ImportFrom)):
                for alias, target in _imports(item):
                    local[alias] = target
                    if target[1] is not None:
                        queue.append(target)
        cls = qualified.split(".")[0] if "." in qualified else None
        for item in nodes:
            if isinstance(item, ast.Name):
                if item.id in where.definitions:
                    queue.append((name, item.id))
                elif item.id in local and local[item.id][1] is not None:
                    queue.append(local[item.id])   # type: ignore[arg-type]
            elif isinstance(item, ast.Attribute) and isinstance(item.value, ast.Name):
                owner = item.value.id
                if owner in local and local[owner][1] is None:
                    queue.append((local[owner][0], item.attr))
                elif cls and owner == "self" and f"{cls}.{item.attr}" in where.definitions:
                    queue.append((name, f"{cls}.{item.attr}"))
    return dict(sorted(code.items()))


def fingerprint(sources: Mapping[str, str] | None = None) -> str:
    """SHA-256 of :func:`writer_code` (hex)."""
    return _digest(writer_code(sources))


def _digest(code: Mapping[str, str]) -> str:
    digest = hashlib.sha256()
    for key, dump in code.items():
        digest.update(key.encode() + b"\x00" + dump.encode() + b"\x00")
    return digest.hexdigest()


MEMO_MODULES = ("ins_errors.numeric.writer_key", "ins_errors.numeric.integrators",
                "ins_errors.numeric.carried_trig")
"""The modules whose texts name a fingerprint kept on disk (:func:`installed_fingerprint`)."""


def _text_hash(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


@cache
def installed_fingerprint() -> str:
    """:func:`fingerprint` of the code this process imported, made once per process.

    Reading the syntax trees takes ~50 ms, so the result is also kept as a note of the
    cache folder (:func:`ins_errors.numeric.cache.write_note`) under the hash of the
    texts of :data:`MEMO_MODULES` (and the Python version, which shapes the trees), with
    the hashes of any other module it read, checked on reading (~1 ms). A folder that
    cannot be read or written only costs the time.
    """
    from ins_errors.numeric import cache as disk

    texts = {m: _source(m, {}) or "" for m in MEMO_MODULES}
    name = "writer_" + _text_hash(sys.version + "".join(texts[m] for m in MEMO_MODULES))[:24]
    note = disk.read_note(name)
    if note is not None:
        lines = note.split("\n")
        value, others = lines[0], [line.split(" ") for line in lines[1:] if line]
        if len(value) == 64 and all(len(o) == 2 and _text_hash(_source(o[0], {}) or "") == o[1]
                                    for o in others):
            return value
    code = writer_code()
    value = _digest(code)
    visited = sorted({key.split(":")[0] for key in code} - set(MEMO_MODULES))
    lines = [value, *(f"{m} {_text_hash(_source(m, {}) or '')}" for m in visited)]
    disk.write_note(name, "\n".join(lines) + "\n")
    return value
