"""The built wheel works outside the source tree, generated code included.

The snippets run with the installed wheel first on ``sys.path`` from folders outside the
source tree, all in one fresh interpreter (its start-up and the package's import are most
of a snippet's cost); each test asserts on its own snippet's exit status and output,
captured separately.
"""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _build_system() -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    with open(ROOT / "pyproject.toml", "rb") as handle:
        return tomllib.load(handle)["build-system"]


def _has_build_requirements() -> bool:
    """Whether this environment already meets pyproject.toml's build requirements."""
    from importlib.metadata import PackageNotFoundError, version

    from packaging.requirements import Requirement

    for text in _build_system()["requires"]:
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
    if _has_build_requirements():
        # the build requirements at hand: pyproject.toml's build backend called directly
        # in a fresh interpreter, as pip's wheel build without isolation calls it (pip's
        # isolated environment installs setuptools afresh on every run, and pip's own
        # start-up costs twice the build)
        backend = _build_system()["build-backend"]
        command = [sys.executable, "-c", f"import importlib, sys; importlib.import_module("
                   f"{backend!r}).build_wheel(sys.argv[1])", str(dist)]
    else:
        command = [sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w",
                   str(dist), str(ROOT)]
    build = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    assert build.returncode == 0, build.stderr[-2000:]
    (wheel,) = dist.glob("ins_errors-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "ins_errors/generated/orthodromic/numpy_model.py" in names
    assert "ins_errors/generated/orthodromic/error_equations.md" in names
    assert "ins_errors/data/802m.toml" in names
    assert (wheel.name.endswith("-py3-none-any.whl")
            and not any(name.endswith((".so", ".pyd", ".pth")) for name in names))
    # a pure-Python wheel installs by unpacking it into the target (what pip does for it,
    # besides the command scripts, which these tests do not use)
    target = tmp_path_factory.mktemp("site")
    zipfile.ZipFile(wheel).extractall(target)
    return target


DRIVER = """
import contextlib, io, json, os, sys, traceback
results = {}
for name, folder, code in json.loads(sys.argv[1]):
    os.chdir(folder)
    out, err, status = io.StringIO(), io.StringIO(), 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            exec(code, {"__name__": "__main__"})
        except SystemExit as stop:
            status = stop.code if isinstance(stop.code, int) else int(stop.code is not None)
        except BaseException:
            traceback.print_exc()
            status = 1
    results[name] = [status, out.getvalue(), err.getvalue()]
sys.stdout.write(json.dumps(results))
"""
"""Runs snippets one after the other in one process outside the source tree, each in its
own folder: (exit status, stdout, stderr) of each, by name, as JSON on stdout."""


def _run_outside(target: Path, snippets: list[tuple[str, Path, str]],
                 cwd: Path) -> dict[str, tuple[int, str, str]]:
    """Run ``snippets`` (name, folder, code) with the installed wheel first on the path,
    in one fresh interpreter (one start-up and import of the package for all of them)."""
    import json

    env = dict(os.environ, PYTHONPATH=str(target))
    done = subprocess.run([sys.executable, "-c", DRIVER,
                           json.dumps([(n, str(f), c) for n, f, c in snippets])],
                          cwd=cwd, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    return {name: tuple(result) for name, result in json.loads(done.stdout).items()}


def _folder(root: Path, name: str, files: dict[str, str]) -> Path:
    folder = root / name
    folder.mkdir()
    for file, text in files.items():
        (folder / file).write_text(text, encoding="utf-8")
    return folder


SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
NO_PLOTS = {"run": ["run", "drift.toml", "--out", "rep"],
            "compare": ["compare", "orthodromic", "-s", "gyro_drift_x=0.01deg/h", "--plot",
                        "d.png"]}
"""Commands run from the installed wheel as if it were installed without matplotlib."""
HIDDEN_MATPLOTLIB = """import sys
from ins_errors.cli import main
sys.modules["matplotlib"] = None  # the plots extra absent: import matplotlib fails
try:
    sys.exit(main({argv!r}))
finally:
    del sys.modules["matplotlib"]  # the snippets after this one draw
"""
"""A snippet running ``argv`` where ``import matplotlib`` raises ImportError. These run
first in the fresh interpreter, before any snippet has imported matplotlib."""
DRIFT = ('model = "orthodromic"\n[run]\nduration = "2 h"\nstep = "2 s"\n'
         '[outputs]\nquantities = ["alpha_x", "delta_latitude"]\n'
         '[[case]]\ngyro_drift_y = "0.01 deg/h"\n')


@pytest.fixture(scope="module")
def outside(installed_wheel, tmp_path_factory) -> dict[str, tuple[int, str, str]]:
    """The tests' snippets run with the installed wheel outside the source tree (one
    process for all: each test below asserts on its own snippet's status and output)."""
    root = tmp_path_factory.mktemp("outside")
    no_plots = _folder(root, "no_plots", {"drift.toml": (
        'model = "orthodromic"\n[run]\nduration = "2 h"\n'
        '[[case]]\ngyro_drift_y = "0.01 deg/h"\n')})
    snippets = [
        *((f"no plots: {name}", no_plots, HIDDEN_MATPLOTLIB.format(argv=argv))
          for name, argv in NO_PLOTS.items()),
        ("models", _folder(root, "models", {}), (
            "import numpy as np, ins_errors\n"
            f"assert ins_errors.__file__.startswith({str(installed_wheel)!r}), "
            "ins_errors.__file__\n"
            "m = ins_errors.load_model('orthodromic')\n"
            "c = m.initial_condition_vector(latitude=0.7)\n"
            "x = m.initial_state(c, m.input_vector())\n"
            "print(m.state_matrix(x, m.input_vector(a_zeta=9.8)).shape)\n")),
        ("command line", _folder(root, "cli", {}),
         "import sys; from ins_errors.cli import main; "
         "sys.exit(main(['models', 'orthodromic']))"),
        ("scenario", _folder(root, "scenario", {"drift.toml": DRIFT}),
         "import sys; from ins_errors.cli import main; "
         "sys.exit(main(['run', 'drift.toml', '--out', 'rep', '--no-progress']))"),
        ("spec", _folder(root, "spec", {}),
         "import sys; from ins_errors.specs import default_spec_path; "
         "p = default_spec_path(); print(p); sys.exit(0 if p.exists() else 1)"),
        ("derive", _folder(root, "derive", {
            "schuler_loop.py": SCHULER.read_text(encoding="utf-8")}),
         "import sys; from ins_errors.cli import main; "
         "sys.exit(main(['derive', 'schuler_loop.py']) "
         "or main(['models', 'schuler_loop.py']))"),
    ]
    results = _run_outside(installed_wheel, snippets, root)
    return {name: (*results[name], folder) for name, folder, _ in snippets}


def test_wheel_loads_models_without_the_source_tree(outside):
    status, out, err, _ = outside["models"]
    assert status == 0, err
    assert out.strip() == "(11, 11)"


def test_wheel_command_line(outside):
    status, out, err, _ = outside["command line"]
    assert status == 0, err
    assert "gyro_drift_x" in out


def test_wheel_runs_a_scenario(outside):
    status, _out, err, folder = outside["scenario"]
    assert status == 0, err
    report = (folder / "rep" / "report.md").read_text(encoding="utf-8")
    assert "## Equations used" in report and "\\dot{\\alpha}_x" in report


def test_wheel_budget_uses_the_built_in_spec(outside, installed_wheel):
    from ins_errors.specs import default_spec_path, load_spec

    assert load_spec(default_spec_path())  # the source tree's copy parses
    status, out, err, _ = outside["spec"]
    assert status == 0, out + err
    assert out.startswith(str(installed_wheel))


def test_wheel_derives_a_model_file(outside):
    """`ins-errors derive FILE` needs the code writer, which ships as ins_errors.derive."""
    status, out, err, folder = outside["derive"]
    assert status == 0, err
    assert "initial_tilt" in out and err == ""  # found next to the file
    assert (folder / "schuler_loop_generated" / "casadi_model.py").is_file()
    # the installed code writer (ins_errors/derive/ in the wheel) is in the fingerprint of
    # the derivation code the package records, the same as this source tree's
    from ins_errors.model_identity import derivation_digest

    init = (folder / "schuler_loop_generated" / "__init__.py").read_text(encoding="utf-8")
    tree = derivation_digest({"ins_errors": ROOT / "ins_errors",
                              "ins_errors.derive": ROOT / "derive"})
    assert f"DERIVATION_CODE_SHA256 = {tree!r}" in init


def test_wheel_without_plots_extra_says_so_before_computing(outside):
    """Installed without matplotlib: one line naming the extra, no folder, no traceback
    (both commands run where matplotlib cannot be imported, before anything drew)."""
    for name in NO_PLOTS:
        status, out, err, folder = outside[f"no plots: {name}"]
        assert status == 2, err
        assert err.strip().splitlines() == [
            "ins-errors: error: " + err.split("ins-errors: error: ", 1)[1].strip()]
        assert "install ins-errors[plots]" in err and not out
    assert not (folder / "rep").exists() and not (folder / "d.png").exists()
