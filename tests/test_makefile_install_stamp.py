"""The Makefile's install step: redone when the packaging files' contents change, kept when
only their dates do (a fresh clone beside a virtual environment restored from a CI cache)."""

import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
INPUTS = ("Makefile", "pyproject.toml", "setup.py")


def _planned(folder: Path) -> list[str]:
    """The commands ``make venv`` would run in ``folder`` (a dry run: nothing installed)."""
    done = subprocess.run(["make", "-n", "venv"], cwd=folder, capture_output=True, text=True,
                          check=True)
    return [line for line in done.stdout.splitlines()
            if line.strip() and not line.startswith("make")]  # not "make: Nothing to be done"


@pytest.fixture
def checkout(tmp_path: Path) -> Path:
    if shutil.which("make") is None:
        pytest.skip("make is not installed")
    for name in INPUTS:
        shutil.copy2(ROOT / name, tmp_path / name)
    planned = _planned(tmp_path)
    assert any("pip install" in line for line in planned)  # nothing installed yet
    [stamp] = [line.split()[1] for line in planned if line.startswith("touch ")]
    (tmp_path / stamp).parent.mkdir(parents=True)
    (tmp_path / stamp).touch()  # as the install would leave it
    return tmp_path


def test_newer_packaging_files_with_the_same_contents_install_nothing(checkout: Path):
    later = time.time() + 3600
    for name in INPUTS:
        os.utime(checkout / name, (later, later))
    assert _planned(checkout) == []


def test_a_changed_dependency_list_installs_again(checkout: Path):
    with open(checkout / "pyproject.toml", "a") as file:
        file.write("\n# a changed pin\n")
    planned = _planned(checkout)
    assert any("pip install" in line for line in planned)
    assert planned[0].startswith("rm -f .venv/.installed")  # the old stamp goes first
