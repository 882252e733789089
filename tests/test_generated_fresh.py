"""generated/ is what `make derive` writes, and writing it is deterministic.

Regenerates into a temporary folder under a fixed hash seed and compares byte for byte
with the committed tree, which `make derive` wrote under a random seed: a difference is
either a stale tree or output that depends on set ordering (nondeterminism).

Re-deriving costs about half a minute of CPU, so a successful check is remembered (in
the user's cache folder) under two fingerprints: of every input of `make derive` (the
files under derive/, ins_errors/, examples/, pyproject.toml, and the Python and SymPy
versions) and of the generated tree itself. When both are unchanged since a successful
check, the result would be the same and the derive is skipped; any change to either
(an edited model, a hand-edited generated file) derives again. ``INS_ERRORS_REDERIVE=1``
always derives.
"""

from __future__ import annotations

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


def _derive_into(folder: Path, seed: str) -> subprocess.Popen:
    env = dict(os.environ, PYTHONHASHSEED=seed)
    return subprocess.Popen([sys.executable, "-m", "derive", "--out", str(folder)], cwd=ROOT,
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


INPUTS = ("derive", "ins_errors", "examples", "pyproject.toml")
"""What `make derive` reads (a superset: any change here derives again)."""


def _digest(paths: list[Path], extra: str = "") -> str:
    h = hashlib.sha256(extra.encode())
    for path in paths:
        h.update(str(path.relative_to(ROOT)).encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def fingerprints() -> tuple[str, str]:
    """(inputs, generated tree) fingerprints of this checkout."""
    inputs = []
    for name in INPUTS:
        target = ROOT / name
        found = sorted(target.rglob("*")) if target.is_dir() else [target]
        inputs += [p for p in found if p.is_file() and "__pycache__" not in p.parts]
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
    run = _derive_into(tmp_path, "12345")
    _out, err = run.communicate(timeout=600)
    assert run.returncode == 0, err
    fresh, committed = _files(tmp_path), _files(GENERATED)
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
    """The memo is keyed so that editing a model or a generated file derives again."""
    import tests.test_generated_fresh as module

    root = tmp_path / "checkout"
    for name in ("derive", "ins_errors/models", "examples", "generated/m"):
        (root / name).mkdir(parents=True)
    (root / "pyproject.toml").write_text("[project]\n")
    model = root / "ins_errors" / "models" / "m.py"
    model.write_text("x = 1\n")
    out = root / "generated" / "m" / "numpy_model.py"
    out.write_text("y = 2\n")
    monkeypatch.setattr(module, "ROOT", root)
    monkeypatch.setattr(module, "GENERATED", root / "generated")
    first = fingerprints()
    model.write_text("x = 1  # edited\n")
    second = fingerprints()
    out.write_text("y = 3\n")
    third = fingerprints()
    assert first[0] != second[0] and first[1] == second[1]
    assert second[0] == third[0] and second[1] != third[1]
