"""The built wheel works outside the source tree, generated code included."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _has_build_requirements() -> bool:
    """Whether this environment already meets pyproject.toml's build requirements."""
    from importlib.metadata import PackageNotFoundError, version

    from packaging.requirements import Requirement

    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    with open(ROOT / "pyproject.toml", "rb") as handle:
        requires = tomllib.load(handle)["build-system"]["requires"]
    for text in requires:
        requirement = Requirement(text)
        try:
            if not requirement.specifier.contains(version(requirement.name), prereleases=True):
                return False
        except PackageNotFoundError:
            return False
    return True


@pytest.fixture(scope="module")
def installed_wheel(tmp_path_factory) -> Path:
    dist = tmp_path_factory.mktemp("dist")
    # with the build requirements at hand, skip pip's isolated build environment (it
    # installs setuptools afresh on every run: most of the build's time)
    isolation = ["--no-build-isolation"] if _has_build_requirements() else []
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps",
                            *isolation, "-w", str(dist), str(ROOT)], capture_output=True,
                           text=True)
    assert build.returncode == 0, build.stderr[-2000:]
    (wheel,) = dist.glob("ins_errors-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "ins_errors/generated/orthodromic/numpy_model.py" in names
    assert "ins_errors/generated/orthodromic/error_equations.md" in names
    assert "ins_errors/data/802m.toml" in names
    target = tmp_path_factory.mktemp("site")
    install = subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps",
                              "--target", str(target), str(wheel)], capture_output=True, text=True)
    assert install.returncode == 0, install.stderr[-2000:]
    return target


def _run_outside(target: Path, code: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(target))
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True,
                          text=True)


def test_wheel_loads_models_without_the_source_tree(installed_wheel, tmp_path):
    code = (
        "import numpy as np, ins_errors\n"
        f"assert ins_errors.__file__.startswith({str(installed_wheel)!r}), ins_errors.__file__\n"
        "m = ins_errors.load_model('orthodromic')\n"
        "c = m.initial_condition_vector(latitude=0.7)\n"
        "x = m.initial_state(c, m.input_vector())\n"
        "print(m.state_matrix(x, m.input_vector(a_zeta=9.8)).shape)\n"
    )
    result = _run_outside(installed_wheel, code, tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "(11, 11)"


def test_wheel_command_line(installed_wheel, tmp_path):
    code = "import sys; from ins_errors.cli import main; sys.exit(main(['models', 'orthodromic']))"
    result = _run_outside(installed_wheel, code, tmp_path)
    assert result.returncode == 0, result.stderr
    assert "gyro_drift_x" in result.stdout


def test_wheel_runs_a_scenario(installed_wheel, tmp_path):
    scenario = tmp_path / "drift.toml"
    scenario.write_text('model = "orthodromic"\n[run]\nduration = "2 h"\nstep = "2 s"\n'
                        '[outputs]\nquantities = ["alpha_x", "delta_latitude"]\n'
                        '[[case]]\ngyro_drift_y = "0.01 deg/h"\n', encoding="utf-8")
    code = ("import sys; from ins_errors.cli import main; "
            "sys.exit(main(['run', 'drift.toml', '--out', 'rep', '--no-progress']))")
    result = _run_outside(installed_wheel, code, tmp_path)
    assert result.returncode == 0, result.stderr
    report = (tmp_path / "rep" / "report.md").read_text(encoding="utf-8")
    assert "## Equations used" in report and "\\dot{\\alpha}_x" in report


def test_wheel_budget_uses_the_built_in_spec(installed_wheel, tmp_path):
    from ins_errors.specs import default_spec_path, load_spec

    assert load_spec(default_spec_path())  # the source tree's copy parses
    code = ("import sys; from ins_errors.specs import default_spec_path; "
            "p = default_spec_path(); print(p); sys.exit(0 if p.exists() else 1)")
    result = _run_outside(installed_wheel, code, tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.startswith(str(installed_wheel))


def test_wheel_derives_a_model_file(installed_wheel, tmp_path):
    """`ins-errors derive FILE` needs the code writer, which ships as ins_errors.derive."""
    model = ROOT / "examples" / "own_model" / "schuler_loop.py"
    (tmp_path / "schuler_loop.py").write_text(model.read_text(encoding="utf-8"),
                                              encoding="utf-8")
    code = ("import sys; from ins_errors.cli import main; "
            "sys.exit(main(['derive', 'schuler_loop.py']) "
            "or main(['models', 'schuler_loop.py']))")
    result = _run_outside(installed_wheel, code, tmp_path)
    assert result.returncode == 0, result.stderr
    assert "initial_tilt" in result.stdout and result.stderr == ""  # found next to the file
    assert (tmp_path / "schuler_loop_generated" / "casadi_model.py").is_file()


def test_wheel_without_plots_extra_says_so_before_computing(installed_wheel, tmp_path):
    """Installed without matplotlib: one line naming the extra, no folder, no traceback."""
    scenario = tmp_path / "drift.toml"
    scenario.write_text('model = "orthodromic"\n[run]\nduration = "2 h"\n[[case]]\n'
                        'gyro_drift_y = "0.01 deg/h"\n', encoding="utf-8")
    for argv in (["run", "drift.toml", "--out", "rep"],
                 ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--plot", "d.png"]):
        code = ("import sys; sys.modules['matplotlib'] = None  # as if the extra were absent\n"
                f"from ins_errors.cli import main; sys.exit(main({argv!r}))")
        result = _run_outside(installed_wheel, code, tmp_path)
        assert result.returncode == 2, result.stderr
        assert result.stderr.strip().splitlines() == [
            "ins-errors: error: " + result.stderr.split("ins-errors: error: ", 1)[1].strip()]
        assert "install ins-errors[plots]" in result.stderr and not result.stdout
    assert not (tmp_path / "rep").exists() and not (tmp_path / "d.png").exists()
