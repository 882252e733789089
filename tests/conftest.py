"""Shared fixtures."""

from __future__ import annotations

import gc
import getpass
import os
import shutil
import sys
import tempfile
from pathlib import Path

import pytest

from tests.helpers import QUIET_DASK

for _name, _value in QUIET_DASK.items():  # before anything imports Dask
    os.environ.setdefault(_name, _value)

import ins_errors  # noqa: E402

MODEL_FILES = (*sorted(Path(__file__).parent.glob("models/*.py")),
               *(Path(__file__).parents[1] / "examples" / name for name in (
                   "own_model/schuler_loop.py", "strapdown/ecef_strapdown.py",
                   "strapdown/strapdown_sphere.py")))
"""The model files the tests fly: derived into the cache before any test runs."""


@pytest.fixture(scope="session", autouse=True)
def _model_files_derived() -> None:
    """Derive the tests' model files once per worker before its first test: a model
    file's first use in a cache says "deriving model file ..." on stderr, which a test
    reading a command's one-line refusal would otherwise read first whenever it happens
    to be that first use (a cold cache, a new version of the derivation code). About
    0.2 s with the cache warm, a few seconds cold."""
    from ins_errors.numeric.model import load_model

    for path in MODEL_FILES:
        load_model(str(path))


@pytest.fixture(scope="session")
def orthodromic() -> ins_errors.Model:
    return ins_errors.load_model("orthodromic")


@pytest.fixture(scope="session")
def orthodromic_error_model(orthodromic):
    """The in-memory SymPy variation of the orthodromic model (a few seconds)."""
    from ins_errors.symbolic.variation import vary

    return vary(orthodromic.symbolic)


@pytest.fixture(scope="session")
def example_reports() -> dict:
    """Report folders written by ``ins-errors run examples/NAME.toml --out DIR`` in this
    session, by example file name: the README's commands (test_docs_commands.py) write
    them, the example checks (test_scenarios.py) read them instead of running the same
    example again (and run it themselves when it is not there)."""
    return {}


@pytest.fixture(scope="session")
def spheroid_study_hour() -> tuple[int, str]:
    """Exit status and standard output of ``ins-errors study spheroid --hours 1 --json``,
    run once for the tests that read it (tests/test_cli_json.py checks its table,
    tests/test_geodetic_vertical.py its integration-error estimate)."""
    import contextlib
    import io

    from ins_errors.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = main(["study", "spheroid", "--hours", "1", "--json"])
    return status, out.getvalue()


def compiled_temporary_files() -> Path | None:
    """Where byte-code of the files in pytest's temporary folders goes, or None.

    With a byte-code prefix (the Makefile sets ``PYTHONPYCACHEPREFIX`` inside the virtual
    environment) Python mirrors every imported file's folder below it, including the
    model files, wheels and scripts the tests write to pytest's temporary folders: new
    folders every session, which pytest's own clean-up of old temporary folders leaves
    behind (~1 MB per session).
    """
    if not sys.pycache_prefix:
        return None
    try:
        user = getpass.getuser()
    except Exception:  # pytest's own fallback when the user cannot be found
        user = "unknown"
    root = os.environ.get("PYTEST_DEBUG_TEMPROOT") or tempfile.gettempdir()
    parts = (Path(root).resolve() / f"pytest-of-{user}").parts
    return Path(sys.pycache_prefix, *parts[1:])


def pytest_sessionstart(session) -> None:
    """Byte-code of earlier sessions' temporary files is removed (see
    :func:`compiled_temporary_files`); the package's own byte-code is kept. Done once, by
    the main process (not by pytest-xdist's workers, which start while another may
    already be writing there)."""
    if hasattr(getattr(session, "config", None), "workerinput"):
        return
    mirror = compiled_temporary_files()
    if mirror is not None:
        shutil.rmtree(mirror, ignore_errors=True)


def pytest_collection_finish(session) -> None:
    """Fewer and cheaper garbage collections for the rest of the session.

    The suite builds large SymPy trees and keeps many of them (the per-process caches of
    the variation and the checker): the cyclic collector's full passes scanned them again
    and again (~6 % of the symbolic tests' CPU, 2.7 s in 42 s). What exists once the tests
    are collected is frozen (never scanned again), and the youngest generation is
    collected every 20 000 net allocations instead of 700. When garbage is collected
    changes no result.
    """
    gc.collect()
    gc.freeze()
    gc.set_threshold(20_000, 20, 20)
