"""generated/ is what `make derive` writes, and writing it is deterministic.

Regenerates into a temporary folder under a fixed hash seed and compares byte for byte
with the committed tree, which `make derive` wrote under a random seed: a difference is
either a stale tree or output that depends on set ordering (nondeterminism).

Re-deriving costs about half a minute of CPU, so a successful check is remembered (in
the user's cache folder) under two fingerprints: of every input of `make derive` and of
the generated tree itself. When both are unchanged since a successful check, the result
would be the same and the derive is skipped; any change to either (an edited model, a
hand-edited generated file) derives again. ``INS_ERRORS_REDERIVE=1`` always derives.

The inputs are the derive program and what it can import (:func:`derive_inputs`: every
project module reached from ``derive/__main__.py`` through any import statement, even one
inside a function, and the model definitions it loads by name), the project's data
files, examples/ (model files and hand derivations it checks), pyproject.toml, and the
Python and SymPy versions. Editing the simulation, analysis or command-line code derives
nothing. Every derive this test runs notes the files each of its processes imported
(the forked workers too) and fails if a project file among them is not an input (a
module imported by a name computed at run time belongs in :data:`INPUT_FOLDERS`). A
clean checkout (CI) has no memo and always derives.
"""

from __future__ import annotations

import ast
import difflib
import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import sympy

from ins_errors.numeric import cache

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and "__pycache__" not in p.parts}


IMPORTS_NOTED = """
import json, multiprocessing.util, os, sys
from concurrent.futures import ProcessPoolExecutor
out, noted = sys.argv[1], sys.argv[2]

def note():  # the project files this process imported, one line per process
    files = sorted({os.path.abspath(m.__file__) for m in list(sys.modules.values())
                    if getattr(m, "__file__", None)})
    with open(noted, "a", encoding="utf-8") as handle:
        handle.write(json.dumps(files) + "\\n")

def in_worker():
    multiprocessing.util.Finalize(None, note, exitpriority=100)  # runs as a worker ends

class NotingPool(ProcessPoolExecutor):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, initializer=in_worker, **kwargs)

from derive.__main__ import main  # first, as `python -m derive` (it sets up SymPy)
import derive.pipeline
derive.pipeline.ProcessPoolExecutor = NotingPool
code = main(["--out", out])
note()
sys.exit(code)
"""
"""``python -m derive --out OUT`` that also notes the files every process of it (the
forked workers too) imported, into the file NOTED."""


def _derive_into(folder: Path, seed: str, noted: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONHASHSEED=seed)
    return subprocess.Popen([sys.executable, "-c", IMPORTS_NOTED, str(folder), str(noted)],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


INPUT_FOLDERS = ("derive", "ins_errors/models", "examples")
"""Read whole: the derive program, the model definitions it imports by name, and the
model files and hand derivations it checks."""

PACKAGES = ("ins_errors", "derive")


def _module_file(root: Path, name: str) -> Path | None:
    path = root.joinpath(*name.split("."))
    for candidate in (path / "__init__.py", path.with_suffix(".py")):
        if candidate.is_file():
            return candidate
    return None


def _imported_names(path: Path, name: str) -> set[str]:
    """Project modules named by any import statement of the file (also in functions);
    ``from a import b`` names both ``a`` and ``a.b`` (b may be a module)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    names = set()
    for node in ast.walk(ast.parse(path.read_bytes())):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parent + ([base] if base else []))
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return {n for n in names if n.split(".")[0] in PACKAGES}


def derive_inputs(root: Path) -> list[Path]:
    """The project's files `make derive` reads, sorted: the modules reached from
    ``derive/__main__.py`` by following every import statement (with their packages),
    everything under :data:`INPUT_FOLDERS`, every file of the package that is not
    Python (data), and pyproject.toml."""
    found: dict[str, Path] = {}
    waiting = ["derive.__main__"]
    while waiting:
        name = waiting.pop()
        path = None if name in found else _module_file(root, name)
        if path is None:
            continue
        found[name] = path
        parts = name.split(".")
        waiting += [".".join(parts[:k]) for k in range(1, len(parts))]
        waiting += _imported_names(path, name)
    files = set(found.values())
    for folder in INPUT_FOLDERS:
        files.update(p for p in (root / folder).rglob("*") if p.is_file())
    files.update(p for p in (root / "ins_errors").rglob("*")
                 if p.is_file() and p.suffix not in (".py", ".pyc"))
    files.add(root / "pyproject.toml")
    return sorted(p for p in files if p.is_file() and "__pycache__" not in p.parts)


def _digest(paths: list[Path], extra: str = "") -> str:
    h = hashlib.sha256(extra.encode())
    for path in paths:
        h.update(str(path.relative_to(ROOT)).encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def fingerprints() -> tuple[str, str]:
    """(inputs, generated tree) fingerprints of this checkout."""
    inputs = derive_inputs(ROOT)
    versions = f"{sys.version}|{sympy.__version__}"
    outputs = [GENERATED / name for name in _files(GENERATED)]
    return _digest(inputs, versions), _digest(outputs)


def _memo() -> Path:
    return cache.directory() / "verified-generated.json"


def _verified() -> list[list[str]]:
    try:
        return json.loads(_memo().read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []


def _remember(pair: tuple[str, str]) -> None:
    known = [*[p for p in _verified() if tuple(p) != pair][-20:], list(pair)]
    try:
        _memo().parent.mkdir(parents=True, exist_ok=True)
        _memo().write_text(json.dumps(known), encoding="utf-8")
    except OSError:
        pass  # no memo: the next run derives again


def test_generated_is_fresh_and_deterministic(tmp_path):
    pair = fingerprints()
    if not os.environ.get("INS_ERRORS_REDERIVE") and list(pair) in _verified():
        return  # these inputs gave exactly this tree in a full check before
    noted = tmp_path / "imported.jsonl"
    run = _derive_into(tmp_path / "generated", "12345", noted)
    _out, err = run.communicate(timeout=600)
    assert run.returncode == 0, err
    # the memo's key holds every project file the derive imported (else an edit of one
    # would not derive again): a module imported by name must be in INPUT_FOLDERS
    imported = {Path(f) for line in noted.read_text("utf-8").splitlines()
                for f in json.loads(line)}
    project = {f for f in imported if f.is_relative_to(ROOT) and
               f.parts[len(ROOT.parts)] in PACKAGES}
    if (os.cpu_count() or 1) > 1:   # derive forks workers: their notes are there too
        assert len(noted.read_text("utf-8").splitlines()) >= 2
    missing = sorted(str(f.relative_to(ROOT)) for f in project - set(derive_inputs(ROOT)))
    assert not missing, f"derive imports files its fingerprint does not hold: {missing}"
    fresh, committed = _files(tmp_path / "generated"), _files(GENERATED)
    problems = []
    for name in sorted(set(fresh) | set(committed)):
        if fresh.get(name) != committed.get(name):
            diff = difflib.unified_diff(
                committed.get(name, b"").decode(errors="replace").splitlines(),
                fresh.get(name, b"").decode(errors="replace").splitlines(),
                f"generated/{name} (committed)", f"generated/{name} (fresh)", lineterm="", n=1)
            problems.append("\n".join(list(diff)[:40]))
    assert not problems, "generated/ is stale: run `make derive`\n" + "\n".join(problems)
    _remember(pair)


def test_fingerprints_see_an_edited_input_and_an_edited_output(tmp_path, monkeypatch):
    """The memo is keyed so that editing a model, a module derive imports (even inside a
    function) or a generated file derives again, and editing other code does not."""
    import tests.test_generated_fresh as module

    root = tmp_path / "checkout"
    for name in ("derive", "ins_errors/models", "ins_errors/numeric", "examples",
                 "generated/m"):
        (root / name).mkdir(parents=True)
    (root / "pyproject.toml").write_text("[project]\n")
    files = {"derive/__init__.py": "", "ins_errors/__init__.py": "",
             "ins_errors/numeric/__init__.py": "",
             "derive/__main__.py": "from .steps import run\n",
             "derive/steps.py": "def run():\n    from ins_errors.numeric import helper\n",
             "ins_errors/numeric/helper.py": "h = 1\n",
             "ins_errors/numeric/simulation.py": "s = 1\n",
             "ins_errors/models/m.py": "x = 1\n", "generated/m/numpy_model.py": "y = 2\n"}
    for name, text in files.items():
        (root / name).write_text(text)
    monkeypatch.setattr(module, "ROOT", root)
    monkeypatch.setattr(module, "GENERATED", root / "generated")

    def edited(name: str) -> tuple[str, str]:
        before = fingerprints()
        (root / name).write_text(files[name] + "# edited\n")
        after = fingerprints()
        (root / name).write_text(files[name])
        assert fingerprints() == before
        return before, after

    for name in ("ins_errors/models/m.py", "ins_errors/numeric/helper.py",
                 "derive/steps.py", "pyproject.toml"):
        if name == "pyproject.toml":
            files[name] = "[project]\n"
        before, after = edited(name)
        assert before[0] != after[0] and before[1] == after[1], name
    before, after = edited("ins_errors/numeric/simulation.py")
    assert before == after                      # not imported by derive
    before, after = edited("generated/m/numpy_model.py")
    assert before[0] == after[0] and before[1] != after[1]
