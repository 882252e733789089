"""Byte-code that the suite's temporary files leave below the byte-code prefix is removed
at the start of the next session; the byte-code of the package is kept."""

from __future__ import annotations

import getpass
import sys
import tempfile

from tests import conftest


def test_byte_code_of_temporary_files_is_removed_and_the_packages_kept(tmp_path,
                                                                       monkeypatch):
    prefix, temporary = tmp_path / "pycache", tmp_path / "scratch"
    monkeypatch.setattr(sys, "pycache_prefix", str(prefix))
    monkeypatch.setattr(tempfile, "tempdir", str(temporary))
    monkeypatch.delenv("PYTEST_DEBUG_TEMPROOT", raising=False)
    monkeypatch.setattr(getpass, "getuser", lambda: "someone")
    mirror = conftest.compiled_temporary_files()
    assert mirror == prefix.joinpath(*temporary.resolve().parts[1:], "pytest-of-someone")
    old = mirror / "pytest-7" / "model.cpython-311.pyc"
    # a checkout that itself sits in the temporary folder keeps its byte-code
    checkout = prefix.joinpath(*temporary.resolve().parts[1:], "clone", "ins_errors",
                               "units.cpython-311.pyc")
    package = prefix / "src" / "ins_errors" / "units.cpython-311.pyc"
    for path in (old, package, checkout):
        path.parent.mkdir(parents=True)
        path.write_bytes(b"compiled")
    conftest.pytest_sessionstart(None)
    assert not mirror.exists()
    assert package.read_bytes() == checkout.read_bytes() == b"compiled"


def test_a_test_worker_leaves_the_byte_code_to_the_main_process(tmp_path, monkeypatch):
    """pytest-xdist's workers start while another may be writing there: only the main
    process (no ``workerinput``) removes."""
    from types import SimpleNamespace

    monkeypatch.setattr(sys, "pycache_prefix", str(tmp_path / "pycache"))
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "scratch"))
    monkeypatch.delenv("PYTEST_DEBUG_TEMPROOT", raising=False)
    written = conftest.compiled_temporary_files() / "pytest-3" / "model.cpython-311.pyc"
    written.parent.mkdir(parents=True)
    written.write_bytes(b"compiled")
    worker = SimpleNamespace(config=SimpleNamespace(workerinput={"workerid": "gw1"}))
    conftest.pytest_sessionstart(worker)
    assert written.exists()
    conftest.pytest_sessionstart(SimpleNamespace(config=SimpleNamespace()))
    assert not written.exists()


def test_nothing_is_removed_without_a_prefix(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "pycache_prefix", None)
    assert conftest.compiled_temporary_files() is None
    conftest.pytest_sessionstart(None)   # nothing to do, no error
