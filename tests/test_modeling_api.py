"""The public authoring API: built-in models need nothing but ``ins_errors.modeling``."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import ins_errors.modeling as modeling
from ins_errors.errors import InsErrorsError
from ins_errors.models import MODEL_MODULES

MODELS_DIR = Path(modeling.__file__).parent / "models"


@pytest.mark.parametrize("name", sorted(MODEL_MODULES))
def test_builtin_models_import_only_the_public_api(name):
    tree = ast.parse((MODELS_DIR / f"{name}.py").read_text(encoding="utf-8"))
    project_imports = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("ins_errors"):
            project_imports.add(node.module)
        elif isinstance(node, ast.Import):
            project_imports.update(a.name for a in node.names if a.name.startswith("ins_errors"))
    assert project_imports == {"ins_errors.modeling"}, project_imports


def test_all_names_exist_and_are_documented():
    for name in modeling.__all__:
        obj = getattr(modeling, name)
        if callable(obj):
            assert obj.__doc__, name


def test_intermediate_defined_twice_is_a_user_error():
    eq = modeling.Mechanisation()
    eq.let("r", 1, "r")
    with pytest.raises(InsErrorsError, match="defined twice"):
        eq.let("r", 2, "r")


def test_computed_symbols_follow_the_computed_mechanisation_naming():
    v = modeling.Variable("v", "m/s", "velocity", "v")
    real = modeling.Mechanisation(computed=True)
    assert modeling.computed_symbols([v]) == [real.let("v", 0, "v")]
