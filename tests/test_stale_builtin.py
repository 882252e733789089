"""A built-in model edited since `make derive` is never run on its stale generated code.

``make derive`` records in each built-in model's package the SHA-256 of the files its
definition is read from; loading the model compares them with the files as they are.
The tests edit a copy of the package laid out as a wheel installs it (generated/ and
derive/ inside ins_errors/), so the checkout's generated/ is never touched: an edited
model says so in one line and runs its own derivation (from the cache), and the shipped
package stays as it was.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
GRAVITY_LINE = "STANDARD_GRAVITY = EARTH_STANDARD_GRAVITY\n"
"""north_pointing's default g (9.80665 m/s²): the line the tests edit."""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """A copy of the package as a wheel lays it out: ins_errors/ with generated/ and
    derive/ inside."""
    root = tmp_path_factory.mktemp("site")
    ignore = shutil.ignore_patterns("__pycache__")
    shutil.copytree(ROOT / "ins_errors", root / "ins_errors", ignore=ignore)
    shutil.copytree(ROOT / "generated", root / "ins_errors" / "generated", ignore=ignore)
    shutil.copytree(ROOT / "derive", root / "ins_errors" / "derive", ignore=ignore)
    return root


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and "__pycache__" not in p.parts}


def _ins_errors(site: Path, cache: Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(site), INS_ERRORS_CACHE=str(cache),
               PYTHONDONTWRITEBYTECODE="1")
    env.pop("PYTHONPYCACHEPREFIX", None)  # the copy's modules: compiled, not cached
    return subprocess.run([sys.executable, "-m", "ins_errors", *args], cwd=site, env=env,
                          capture_output=True, text=True, timeout=600)


def _eigenvalues(run: subprocess.CompletedProcess) -> np.ndarray:
    modes = json.loads(run.stdout)["modes"]
    return np.array(sorted(m["eigenvalue"]["imag"] for m in modes))


def test_an_edited_builtin_model_says_so_and_runs_its_own_derivation(site, tmp_path):
    source = site / "ins_errors" / "models" / "north_pointing.py"
    original = source.read_text(encoding="utf-8")
    assert original.count(GRAVITY_LINE) == 1
    shipped = _files(site / "ins_errors" / "generated")
    cache = tmp_path / "cache"
    try:
        source.write_text(original.replace(GRAVITY_LINE, "STANDARD_GRAVITY = 9.0\n"),
                          encoding="utf-8")
        first = _ins_errors(site, cache, "models", "north_pointing", "--json")
        edited = _ins_errors(site, cache, "modes", "north_pointing", "--json")
    finally:
        source.write_text(original, encoding="utf-8")
    assert first.returncode == 0, first.stderr
    stale = ("ins-errors: generated/north_pointing/ is stale (ins_errors/models/"
             "north_pointing.py changed since `make derive`); ")
    assert first.stderr.splitlines() == [
        stale + "deriving it again into the cache (`make derive` updates generated/)"]
    g = [p for p in json.loads(first.stdout)["parameters"] if p["name"] == "g"]
    assert g[0]["default"] == 9.0                      # the edited value, not 9.80665
    assert edited.returncode == 0, edited.stderr
    assert edited.stderr.splitlines() == [
        stale + "using the up-to-date code in the cache (`make derive` updates generated/)"]
    # the reference: the shipped code of the unedited model with g = 9 m/s² given
    given = _ins_errors(site, cache, "modes", "north_pointing", "-p", "g=9m/s^2", "--json")
    assert given.returncode == 0 and "stale" not in given.stderr, given.stderr
    np.testing.assert_allclose(_eigenvalues(edited), _eigenvalues(given), rtol=1e-12)
    # the Schuler frequency √(g/R) moved with g: the periods are not the old ones
    schuler = [m for m in json.loads(edited.stdout)["modes"] if m["name"].startswith("Schuler")]
    assert schuler and all(m["period_s"] > 5000 for m in schuler)   # 84 min at 9.80665
    assert _files(site / "ins_errors" / "generated") == shipped   # never rewritten by a run


def test_a_broken_edit_of_a_builtin_model_is_one_line(site, tmp_path):
    source = site / "ins_errors" / "models" / "north_pointing.py"
    original = source.read_text(encoding="utf-8")
    lines = original.splitlines(keepends=True)
    number = lines.index(GRAVITY_LINE) + 1
    try:
        source.write_text(original.replace(GRAVITY_LINE, "STANDARD_GRAVITY = 9.0 +\n"),
                          encoding="utf-8")
        run = _ins_errors(site, tmp_path / "cache", "models", "north_pointing")
    finally:
        source.write_text(original, encoding="utf-8")
    assert run.returncode == 2
    problem = run.stderr.splitlines()[-1]
    assert problem.startswith("ins-errors: error: model 'north_pointing' (ins_errors/models/"
                              f"north_pointing.py): line {number}: SyntaxError"), run.stderr
    assert "Traceback" not in run.stderr


PROBE = """
import importlib, json, sys
from ins_errors.models import MODEL_MODULES
found = {}
for name, module in MODEL_MODULES.items():
    for loaded in [m for m in sys.modules if m.startswith(("ins_errors.models.",
                                                           "ins_errors.modeling"))]:
        del sys.modules[loaded]   # each model's imports from none imported yet
    importlib.import_module(module).build()
    found[name] = sorted(m.__file__ for key, m in sys.modules.items()
                         if key.startswith("ins_errors.models.") and m.__file__)
print(json.dumps(found))
"""
"""Build each built-in model's definition afresh; print the files of ins_errors/models/
each imported."""


def test_each_builtin_package_records_every_file_its_definition_imports():
    from ins_errors.builtin_packages import shipped_package, stale_sources
    from ins_errors.models import model_names

    run = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                         timeout=300, check=True)
    found = json.loads(run.stdout)
    assert sorted(found) == sorted(model_names())
    for name, files in found.items():
        meta = shipped_package(name)
        imported = {Path(f).resolve().relative_to(ROOT / "ins_errors").as_posix()
                    for f in files}
        assert set(meta.MODEL_SOURCES_SHA256) == imported, name   # no more, no fewer
        assert stale_sources(meta) == [], name   # and generated/ is up to date


def test_derive_of_a_builtin_writes_the_record_and_names_its_wall_time(tmp_path, capsys):
    """``ins-errors derive BUILTIN --out DIR`` writes the package `make derive` writes,
    the record of its sources included; its JSON names its one time by its unit."""
    from ins_errors.cli import main

    out = tmp_path / "north_pointing"
    assert main(["derive", "north_pointing", "--out", str(out), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert "seconds" not in result and result["wall_time_s"] > 0
    assert result["model_file_sha256"] is None and result["derivation_code_sha256"] is None
    for name in ("numpy_model.py", "casadi_model.py", "error_equations.md"):
        assert (out / name).read_bytes() == (ROOT / "generated" / "north_pointing" /
                                             name).read_bytes(), name
    shipped = (ROOT / "generated" / "north_pointing" / "__init__.py").read_text("utf-8")
    written = (out / "__init__.py").read_text("utf-8")
    assert written.startswith(shipped)   # then the seal of its files' hashes
    assert "MODEL_SOURCES_SHA256 = {'models/earth.py': '" in shipped
