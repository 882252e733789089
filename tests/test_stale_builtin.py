"""A built-in model edited since `make derive` is never run on its stale generated code.

``make derive`` records in each built-in model's package the SHA-256 of the files its
definition is read from; loading the model compares them with the files as they are.
The tests edit a copy of the package laid out as a wheel installs it (generated/ and
derive/ inside ins_errors/), so the checkout's generated/ is never touched: an edited
model says so in one line and runs its own derivation (from the cache), and the shipped
package stays as it was. The notice is a RuntimeWarning (the Python API catches or
filters it; the command line prints its one line), given once: not again by the worker
processes of a sweep, and not counted by ``--fail-on-warning``.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import sys
import textwrap
from collections.abc import Iterator
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
    return _python(site, cache, "-m", "ins_errors", *args)


def _python(site: Path, cache: Path, *args: str) -> subprocess.CompletedProcess:
    """Python run on the copy ``site`` with the model cache ``cache``."""
    env = dict(os.environ, PYTHONPATH=str(site), INS_ERRORS_CACHE=str(cache),
               PYTHONDONTWRITEBYTECODE="1")
    env.pop("PYTHONPYCACHEPREFIX", None)  # the copy's modules: compiled, not cached
    return subprocess.run([sys.executable, *args], cwd=site, env=env,
                          capture_output=True, text=True, timeout=600)


@contextlib.contextmanager
def _edited_gravity(site: Path) -> Iterator[None]:
    """north_pointing's default g set to 9 m/s² in the copy, for the block."""
    source = site / "ins_errors" / "models" / "north_pointing.py"
    original = source.read_text(encoding="utf-8")
    assert original.count(GRAVITY_LINE) == 1
    try:
        source.write_text(original.replace(GRAVITY_LINE, "STANDARD_GRAVITY = 9.0\n"),
                          encoding="utf-8")
        yield
    finally:
        source.write_text(original, encoding="utf-8")


STALE = ("ins-errors: generated/north_pointing/ is stale (ins_errors/models/"
         "north_pointing.py changed since `make derive`); ")
"""How the notice of the edited north_pointing begins."""


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
    assert first.stderr.splitlines() == [
        STALE + "deriving it again into the cache (`make derive` updates generated/)"]
    g = [p for p in json.loads(first.stdout)["parameters"] if p["name"] == "g"]
    assert g[0]["default"] == 9.0                      # the edited value, not 9.80665
    assert edited.returncode == 0, edited.stderr
    assert edited.stderr.splitlines() == [
        STALE + "using the up-to-date code in the cache (`make derive` updates generated/)"]
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


# --------------------------------------------------------------------------------------
# the notice: a warning, given once
# --------------------------------------------------------------------------------------
API_PROBE = """
import json, warnings
import pytest
import ins_errors
from ins_errors.builtin_packages import _cached_model

with pytest.warns(ins_errors.InsErrorsNotice) as caught:
    model = ins_errors.load_model("north_pointing")
_cached_model.cache_clear()   # loaded again in this process: the notice is not repeated
with warnings.catch_warnings(record=True) as again:
    warnings.simplefilter("always")
    ins_errors.load_model("north_pointing")
notices = [w for w in caught if issubclass(w.category, ins_errors.InsErrorsNotice)]
print(json.dumps({"caught": [str(w.message) for w in notices],
                  "again": [str(w.message) for w in again],
                  "g": model.parameter_vector()[model.index("parameters", "g")]}))
"""
"""Load the edited north_pointing from the Python API under pytest.warns, then again."""

FILTERED_PROBE = """
import warnings
warnings.filterwarnings("ignore", message="ins-errors: .* is stale", category=RuntimeWarning)
import ins_errors
model = ins_errors.load_model("north_pointing")
print(model.parameter_vector()[model.index("parameters", "g")])
"""
"""Load it with the notice filtered out by its words (as docs/cache.md shows; the model
files' test filters every warning: tests/test_package_notices.py)."""


def test_the_notice_of_a_stale_builtin_is_a_warning_the_api_catches_or_filters(site,
                                                                              tmp_path):
    """Was: printed on stderr, which no warnings filter or pytest.warns reaches."""
    cache = tmp_path / "cache"
    with _edited_gravity(site):
        caught = _python(site, cache, "-c", API_PROBE)
        filtered = _python(site, cache, "-c", FILTERED_PROBE)
    assert caught.returncode == 0, caught.stderr
    assert caught.stderr == ""    # recorded by pytest.warns: nothing printed
    said = json.loads(caught.stdout)
    assert said["caught"] == [
        STALE + "deriving it again into the cache (`make derive` updates generated/)"]
    assert said["again"] == []    # once per process
    assert said["g"] == 9.0       # the edited model ran, not the shipped 9.80665
    assert filtered.returncode == 0, filtered.stderr
    assert filtered.stderr == "" and float(filtered.stdout) == 9.0


SWEEP = """
title = "stale model on workers"
model = "north_pointing"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "10 min"
step = "10 s"
record = "60 s"
[[case]]
accel_bias_north = "100 ug"
[sweep]
latitude = ["10 deg", "30 deg", "60 deg"]
"""

SPAWNED_POOL = """
import multiprocessing, sys
multiprocessing.get_all_start_methods = lambda: ["spawn"]   # as on Windows
from ins_errors.cli import main
sys.exit(main(sys.argv[1:]))
"""
"""The command line with the process pool's workers started afresh (``spawn``), so that
each loads the model itself instead of inheriting it from a ``fork``."""


def test_a_sweep_on_workers_says_the_stale_builtin_once(site, tmp_path):
    """Was: each Dask worker (and each spawned pool worker) loaded the model and said
    the line again (three lines for two workers)."""
    scenario = tmp_path / "sweep.toml"
    scenario.write_text(textwrap.dedent(SWEEP), encoding="utf-8")
    cache = tmp_path / "cache"
    common = ["--workers", "2", "--no-progress"]
    with _edited_gravity(site):
        runs = {
            "dask": _ins_errors(site, cache, "sweep", str(scenario), "--engine", "dask",
                                "--store", str(tmp_path / "dask.zarr"), *common),
            "pool": _ins_errors(site, cache, "sweep", str(scenario), "--engine", "pool",
                                "--store", str(tmp_path / "pool.zarr"), *common),
            "spawned pool": _python(site, cache, "-c", SPAWNED_POOL, "sweep", str(scenario),
                                    "--engine", "pool", "--store",
                                    str(tmp_path / "spawned.zarr"), *common)}
    for engine, run in runs.items():
        assert run.returncode == 0, (engine, run.stderr)
        assert "3 to compute" in run.stderr, (engine, run.stderr)
        stale = [line for line in run.stderr.splitlines() if "is stale" in line]
        assert len(stale) == 1 and stale[0].startswith(STALE), (engine, run.stderr)
    assert "deriving it again" in runs["dask"].stderr   # the first run derived it


def test_fail_on_warning_does_not_count_the_stale_notice(site, tmp_path):
    """The results are those of the edited model: the notice is about the checkout."""
    cache = tmp_path / "cache"
    compare = ["compare", "north_pointing", "--source", "initial_azimuth_error=1arcmin",
               "--hours", "2", "--step", "10s", "--no-progress"]
    with _edited_gravity(site):
        run = _ins_errors(site, cache, *compare, "--fail-on-warning")
    assert run.returncode == 0, run.stderr
    assert run.stderr.splitlines() == [
        STALE + "deriving it again into the cache (`make derive` updates generated/)"]
