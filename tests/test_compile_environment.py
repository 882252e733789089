"""Where a compile puts its temporary files, and what a full disk is called.

A CI probe stopped only the main process during a cold compile: the compiler ran on and
left its assembly files (about 350 kB each) in the system's temporary folder. And a
full disk under the cache was reported as "no working C compiler". Both are checked
here with stand-in compilers (shell scripts given as ``$CC``) and real compiles.
"""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import pytest

from ins_errors.numeric import integrators


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """An empty cache and a process that has given no compiler notice yet."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("INS_ERRORS_NO_JIT", raising=False)
    monkeypatch.setattr(integrators, "_NOTICE_GIVEN", False)
    return tmp_path


def _stand_in(folder: Path, body: str) -> Path:
    script = folder / "cc"
    script.write_text("#!/bin/sh\n" + body)
    script.chmod(0o755)
    return script


def test_the_compiler_keeps_its_temporary_files_in_the_compile_scratch_folder(
        fresh, monkeypatch):
    real = shutil.which("cc") or shutil.which("gcc")
    if real is None:
        pytest.skip("no C compiler")
    said = fresh / "tmpdir.txt"
    monkeypatch.setenv("CC", str(_stand_in(fresh, f'echo "$TMPDIR" > {said}\n'
                                                   f'exec {real} "$@"\n')))
    library = integrators.compile_source("int probe_tmpdir(void) { return 7; }\n",
                                         integrators.IEEE_FLAGS)
    assert library is not None and library.exists()   # the compile itself still works
    tmpdir = Path(said.read_text().strip())
    # inside the loops' folder, in the compile's own scratch folder (deleted since)
    assert tmpdir.parent == library.parent
    assert tmpdir.name.startswith("tmp") and not tmpdir.exists()


@pytest.mark.parametrize("how", ["the assembler says so", "the compiler cannot start"])
def test_a_full_disk_is_not_called_a_missing_compiler(fresh, monkeypatch, how):
    if how == "the assembler says so":
        monkeypatch.setenv("CC", str(_stand_in(
            fresh, 'echo "/tmp/ccX.s: Fatal error: can\'t write 12 bytes to section '
                   '.text: No space left on device" >&2\nexit 1\n')))
    else:
        import errno
        import os

        monkeypatch.setenv("CC", str(_stand_in(fresh, "exit 0\n")))

        def full(*args, **kwargs):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

        monkeypatch.setattr(integrators.subprocess, "run", full)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert integrators.compile_source("int probe_full(void) { return 1; }\n") is None
    [notice] = [str(w.message) for w in caught]
    assert notice.startswith("ins-errors: no space left on the device of ")
    assert str(fresh / "cache") in notice
    assert "No space left on device" in notice
    assert "no working C compiler" not in notice
    assert notice.endswith("compiled loops run in the CasADi virtual machine instead "
                           "(slower, same results)")
