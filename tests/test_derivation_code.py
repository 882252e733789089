"""A model file's generated code is keyed by the code that derives it, too.

The generated package of a model file follows from the file and from the version of
ins-errors that derived it (the variation, the code generation, the definition checks).
Its cache key and its record hold both, so a package derived by another version is
derived again (a RuntimeWarning, one line on the command line's stderr), never run; an
unchanged installation reuses it. The fingerprint of the derivation code is checked
against copies of the package's sources: it follows a change of the code and nothing
outside it.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ins_errors import InsErrorsNotice, load_model
from ins_errors.cli import main
from ins_errors.model_identity import (
    DERIVATION_MODULES,
    DERIVATION_PACKAGES,
    NOT_DERIVATION,
    derivation_code_sha256,
    derivation_digest,
    derivation_sources,
)
from ins_errors.numeric.model import _file_model
from tests.helpers import fresh_model_cache

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
OTHER_CODE = hashlib.sha256(b"another version of ins-errors").hexdigest()


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Generated code of model files goes to a fresh cache per test."""
    yield fresh_model_cache(tmp_path, monkeypatch)
    _file_model.cache_clear()


@pytest.fixture
def derivations(monkeypatch):
    """Folders the model-file machinery derived into, in order (a counting wrapper)."""
    import ins_errors.derive.package as package

    written, original = [], package.write_package

    def counting(d, target, *args, **kwargs):
        written.append(Path(target))
        return original(d, target, *args, **kwargs)

    monkeypatch.setattr(package, "write_package", counting)
    return written


def _model_file(tmp_path: Path) -> Path:
    path = tmp_path / "my_ins.py"
    shutil.copy(SCHULER, path)
    return path


def _load(path: Path):
    _new_process()
    return load_model(str(path))


def _new_process() -> None:
    """As a new command would: no model loaded, no notice given yet."""
    from ins_errors import model_lookup

    _file_model.cache_clear()
    model_lookup._NOTICES_GIVEN.clear()


def _notices(caught) -> list[str]:
    """The texts of the machine notices ``pytest.warns`` recorded."""
    return [str(w.message) for w in caught if issubclass(w.category, InsErrorsNotice)]


def _other_derivation_code(monkeypatch) -> None:
    """As after an upgrade or a fix of ins-errors: its derivation code has another
    fingerprint."""
    monkeypatch.setattr("ins_errors.model_identity.derivation_code_sha256", lambda: OTHER_CODE)


def _recorded_code(folder: Path) -> str:
    init = (folder / "__init__.py").read_text(encoding="utf-8")
    return ast.literal_eval(init.split("DERIVATION_CODE_SHA256 = ", 1)[1].splitlines()[0])


# --------------------------------------------------------------------------------------
# the packages
# --------------------------------------------------------------------------------------
def test_a_package_beside_the_file_derived_by_other_code_is_derived_again(
        tmp_path, monkeypatch, capsys, derivations, private_cache):
    path = _model_file(tmp_path)
    beside = tmp_path / "my_ins_generated"
    assert main(["derive", str(path)]) == 0
    assert derivations == [beside]
    assert _recorded_code(beside) == derivation_code_sha256()
    capsys.readouterr()
    assert _load(path).folder == beside and capsys.readouterr().err == ""

    _other_derivation_code(monkeypatch)
    with pytest.warns(RuntimeWarning) as caught:
        model = _load(path)
    assert _notices(caught) == ["ins-errors: my_ins_generated/ was derived by another "
                                "version of ins-errors; deriving again into the cache"]
    assert capsys.readouterr().err == ""   # the API's: a warning, not stderr
    assert derivations[1:] == [model.folder] and model.folder.parent == private_cache
    assert _recorded_code(model.folder) == OTHER_CODE
    assert _recorded_code(beside) != OTHER_CODE  # the user's folder is left alone

    # the next command (an unchanged installation) reuses the cache, still saying why
    _new_process()
    assert main(["models", str(path)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["ins-errors: my_ins_generated/ was derived by another version of "
                   "ins-errors; using the up-to-date code in the cache"]
    assert _load(path).folder == model.folder and len(derivations) == 2

    assert main(["derive", str(path)]) == 0  # refreshing the folder: silent again
    assert _recorded_code(beside) == OTHER_CODE
    capsys.readouterr()
    assert _load(path).folder == beside and capsys.readouterr().err == ""
    assert len(derivations) == 3


def test_a_cached_package_derived_by_other_code_is_derived_again(
        tmp_path, monkeypatch, capsys, derivations, private_cache):
    path = _model_file(tmp_path)
    first = _load(path).folder
    assert derivations == [first] and first.parent == private_cache
    assert "first use" in capsys.readouterr().err
    assert _load(path).folder == first and len(derivations) == 1  # reused, silently
    assert capsys.readouterr().err == ""

    _other_derivation_code(monkeypatch)
    second = _load(path).folder
    err = capsys.readouterr().err.strip().splitlines()   # progress, as the first use
    assert err == ["ins-errors: deriving model file my_ins.py again: its cached code was "
                   "derived by another version of ins-errors (cached for next time)"]
    assert second != first and derivations == [first, second]
    assert _recorded_code(second) == OTHER_CODE
    assert _load(path).folder == second and len(derivations) == 2
    assert capsys.readouterr().err == ""


def test_a_package_without_the_fingerprint_is_derived_again(tmp_path, capsys, derivations):
    """A package written before ins-errors recorded its derivation code cannot tell
    which code wrote it: it is stale."""
    path = _model_file(tmp_path)
    beside = tmp_path / "my_ins_generated"
    assert main(["derive", str(path)]) == 0
    init = beside / "__init__.py"
    text = init.read_text(encoding="utf-8")
    init.write_text("".join(line for line in text.splitlines(keepends=True)
                            if not line.startswith("DERIVATION_CODE_SHA256")),
                    encoding="utf-8")
    with pytest.warns(RuntimeWarning, match="was derived by another version of ins-errors"):
        model = _load(path)
    assert model.folder != beside and len(derivations) == 2


def test_a_built_in_model_package_records_no_fingerprint(tmp_path, capsys):
    """`make derive`'s packages stay what they were (generated/ is compared byte for
    byte by test_generated_fresh); `derive NAME --out` writes the same."""
    out = tmp_path / "schuler"
    assert main(["derive", "north_pointing", "--out", str(out)]) == 0
    capsys.readouterr()
    init = (out / "__init__.py").read_text(encoding="utf-8")
    assert "DERIVATION_CODE_SHA256" not in init and "MODEL_FILE_SHA256" not in init


# --------------------------------------------------------------------------------------
# the fingerprint
# --------------------------------------------------------------------------------------
def test_the_fingerprint_is_the_same_in_another_process():
    code = ("import sys, time\n"
            "from ins_errors.model_identity import derivation_code_sha256\n"
            "print(derivation_code_sha256())\n"
            "print('sympy' in sys.modules)\n")
    env = dict(os.environ, PYTHONHASHSEED="271")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, cwd=ROOT, timeout=120, check=True)
    value, imported_sympy = run.stdout.split()
    assert value == derivation_code_sha256() == derivation_digest()
    assert imported_sympy == "False"  # cheap: read and hashed, nothing imported


def _copy(tmp_path: Path) -> dict[str, Path]:
    """A copy of the package's sources: ``locations`` for :func:`derivation_digest`."""
    locations = {}
    for package in ("ins_errors", "ins_errors.derive"):
        folder = Path(next(iter(importlib.util.find_spec(package).submodule_search_locations)))
        locations[package] = tmp_path / package
        shutil.copytree(folder, locations[package],
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "generated",
                                                      "derive"))
    return locations


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert old in text, old
    path.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_the_fingerprint_follows_the_derivation_code(tmp_path):
    locations = _copy(tmp_path)
    installed = derivation_code_sha256()
    assert derivation_digest(locations) == installed

    # code outside the derivation (the command line, the simulation) does not count
    _edit(locations["ins_errors"] / "cli.py", "def main(", "def main_(")
    _edit(locations["ins_errors"] / "numeric" / "model.py", "import", "import  ")
    assert derivation_digest(locations) == installed

    seen = {installed}
    edits = [
        # the code writer: the banner of every generated file
        (locations["ins_errors.derive"] / "model_files.py", "do not edit by hand",
         "do not edit"),
        # the variation
        (locations["ins_errors"] / "symbolic" / "variation.py", "def ", "def  "),
        # the definition checks
        (locations["ins_errors"] / "symbolic" / "consistency.py", "def ", "def  "),
        # the modelling API and its Earth formulas
        (locations["ins_errors"] / "modeling.py", "def ", "def  "),
        (locations["ins_errors"] / "models" / "earth.py", "def ", "def  "),
        # a docstring that is output: a built-in model's notes (its module docstring)
        (locations["ins_errors"] / "models" / "north_pointing.py", "Modelling choices",
         "Modelling choices (edited)"),
    ]
    for path, old, new in edits:
        _edit(path, old, new)
        value = derivation_digest(locations)
        assert value not in seen, path
        seen.add(value)
    (locations["ins_errors"] / "symbolic" / "new_step.py").write_text("X = 1\n", "utf-8")
    assert derivation_digest(locations) not in seen  # a module added to the machinery


def _project_imports(path: Path, module: str) -> set[str]:
    """Project modules (or packages) named by any import statement of the file."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    names = set()
    for node in ast.walk(ast.parse(path.read_bytes())):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
            if base == "ins_errors":  # from ins_errors import units
                names.update(f"{base}.{alias.name}" for alias in node.names)
            else:
                names.add(base)
    return {name for name in names if name.split(".")[0] == "ins_errors"}


def test_the_fingerprint_holds_every_module_the_derivation_code_imports():
    """A project module that derivation code imports (at any level, also inside a
    function) is derivation code itself, unless NOT_DERIVATION names it: a module added
    to the machinery cannot be left out of the fingerprint unnoticed."""
    sources = derivation_sources()
    held = {label.removesuffix(".py").removesuffix("/__init__").replace("/", ".")
            for label, _ in sources}
    assert set(DERIVATION_MODULES) <= held
    assert {"ins_errors.derive.model_files", "ins_errors.symbolic.codegen",
            "ins_errors.models.platform"} <= held

    def covered(name: str) -> bool:
        return (name in held or name in DERIVATION_PACKAGES
                or any(name == other or name.startswith(other + ".")
                       for other in NOT_DERIVATION))

    missing = sorted({f"{name} (imported by {label})" for label, path in sources
                      for name in _project_imports(path, label.removesuffix(".py")
                                                   .removesuffix("/__init__")
                                                   .replace("/", "."))
                      if not covered(name)})
    assert not missing, missing
