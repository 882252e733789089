"""examples/own_model/README.md stays true: its code excerpts are the model file's own
lines, and the files, numbers and messages it quotes are what the tools produce.

(That every command of the page and of the README runs with the stated exit status is
tests/test_docs_commands.py's job; here the commands whose output the page describes run
again with assertions on that output.)"""

from __future__ import annotations

import os
import re
import shlex
from pathlib import Path

import pytest

from ins_errors.cli import main
from tests.helpers import fresh_model_cache

ROOT = Path(__file__).resolve().parent.parent
FOLDER = ROOT / "examples" / "own_model"
PAGE = (FOLDER / "README.md").read_text(encoding="utf-8")
MODEL = (FOLDER / "schuler_loop.py").read_text(encoding="utf-8")
COMMAND = re.compile(r"^\$ ins-errors (.+?)(?:\s+#\s*exit (\d+))?$", re.M)
COMMANDS = COMMAND.findall(PAGE)
README_SECTION = (ROOT / "README.md").read_text(encoding="utf-8").split(
    "## Bring your own model", 1)[1].split("\n## ", 1)[0]
DESCRIBED = [c for c in COMMANDS
             if c[0].startswith(("derive", "check")) or "accel_bias=100ug" in c[0]]


@pytest.fixture
def workspace(tmp_path, monkeypatch):
    """A fresh folder with examples/ linked in, and a private model cache."""

    (tmp_path / "out").mkdir()
    os.symlink(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    fresh_model_cache(tmp_path, monkeypatch)
    return tmp_path


def test_the_page_covers_list_derive_compare_check():
    verbs = [line.split()[0] for line, _ in COMMANDS]
    assert {"models", "derive", "compare", "check"} <= set(verbs), verbs


@pytest.mark.parametrize("line, status", DESCRIBED, ids=[c[0][:60] for c in DESCRIBED])
def test_tutorial_command(line, status, workspace, capsys):
    assert main(shlex.split(line)) == int(status or 0), capsys.readouterr().err
    out = capsys.readouterr().out
    assert out.strip()
    if line.startswith("derive"):
        names = sorted(p.name for p in (workspace / "out" / "own").iterdir())
        assert names == ["__init__.py", "casadi_model.py", "error_equations.md",
                         "numpy_model.py"]
        listing = (workspace / "out" / "own" / "error_equations.md").read_text(encoding="utf-8")
        for quoted in (r"\Delta \tilde{f} = \nabla - g \psi", r"\Delta \omega = \frac{\Delta V}{R}",
                       r"\dot{\psi} = \Delta \omega + \varepsilon"):
            assert quoted in listing, quoted
    if line.startswith("compare") and "accel_bias=100ug" in line:
        # the numbers the page quotes: 2b/g tilt, b/ω_s velocity error
        assert re.search(r"`psi` \| arcmin \| 6\.875e-01", out), out  # 2e-4 rad
        assert re.search(r"`delta_v_N` \| m/s \| 7\.904e-01", out), out
    if line.startswith("check") and line.endswith(".tex"):
        assert "3 agree" in out and "0 with mistakes" in out, out
    if line.startswith("check") and "wrong" in line:
        # the one wrong sign, on line 5, in the term of delta_V, and nothing else
        assert re.search(r"^\s+5\s+dot\(psi\)\s+delta_V\s+wrong sign\s+mistake", out, re.M), out
        assert "2 agree" in out and "1 with mistakes" in out, out


def test_code_excerpts_are_the_model_files_own_lines():
    blocks = re.findall(r"```python\n(.*?)```", PAGE, re.S)
    assert len(blocks) >= 3
    for block in blocks:
        assert block in MODEL, block[:80]


def test_quoted_mistake_message_is_what_derive_prints(tmp_path, capsys, monkeypatch):
    quoted = PAGE.split("no equation for 'psi'", 1)[0].rsplit("\n\n", 1)[1]
    quoted = " ".join((quoted + "no equation for 'psi' (step: checking the definition)")
                      .split())
    model = tmp_path / "my_ins.py"
    model.write_text(MODEL.replace("real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])",
                                   "real_rhs = sp.Matrix([f, omega_c])"), encoding="utf-8")
    monkeypatch.setattr("ins_errors.model_lookup.models_cache_directory",
                        lambda: tmp_path / "cache")
    assert main(["derive", str(model), "--out", str(tmp_path / "pkg")]) == 2
    assert capsys.readouterr().err.strip() == quoted


def test_readme_section_names_are_the_public_api():
    import ins_errors.modeling as modeling

    for name in re.findall(r"^\| `(\w+)", README_SECTION, re.M):
        assert name in modeling.__all__, name
