"""generated/ is what `make derive` writes, and writing it is deterministic.

Regenerates into a temporary folder under a fixed hash seed and compares byte for byte
with the committed tree, which `make derive` wrote under a random seed: a difference is
either a stale tree or output that depends on set ordering (nondeterminism).
"""

from __future__ import annotations

import difflib
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and "__pycache__" not in p.parts}


def _derive_into(folder: Path, seed: str) -> subprocess.Popen:
    env = dict(os.environ, PYTHONHASHSEED=seed)
    return subprocess.Popen([sys.executable, "-m", "derive", "--out", str(folder)], cwd=ROOT,
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_generated_is_fresh_and_deterministic(tmp_path):
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
