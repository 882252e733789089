"""Structured variations kept on disk (:mod:`ins_errors.symbolic.variation_store`) are
the lines a fresh computation gives, node for node, and are never read for another
definition or other code."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys

import pytest
import sympy as sp

from ins_errors.models import definition
from ins_errors.symbolic import variation, variation_store
from ins_errors.symbolic.shared_trees import SharedTrees


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """An empty cache folder and no lines kept in the process."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    monkeypatch.setattr(variation, "_STRUCTURED", {})
    return tmp_path / "variations"


def _fresh(d):
    with SharedTrees().differentiating() as trees:
        return variation._structured_variation(d, trees)


def _nodes(expr: sp.Basic) -> list:
    """Every node in pre-order: its class, and for atoms their name or value and
    assumptions."""
    return [(type(node), node.assumptions0 if node.is_Symbol else None,
             str(node) if not node.args else None) for node in sp.preorder_traversal(expr)]


def _no_computing(monkeypatch):
    def refuse(d, trees):
        raise AssertionError("computed although stored")

    monkeypatch.setattr(variation, "_structured_variation", refuse)


def test_stored_lines_equal_fresh_ones_node_for_node(scratch, monkeypatch):
    model = "north_pointing"  # radicals, fractions and trigonometry in its coefficients
    fresh = _fresh(definition(model))
    variation.structured_variation(definition(model))  # computed and stored
    assert len(list(scratch.glob(f"{model}_*.pickle"))) == 1
    monkeypatch.setattr(variation, "_STRUCTURED", {})
    _no_computing(monkeypatch)
    loaded = variation.structured_variation(definition(model))
    assert len(loaded) == len(fresh)
    for a, b in zip(loaded, fresh, strict=True):
        assert (a.name, a.kind, a.latex) == (b.name, b.kind, b.latex)
        for x, y in ((a.lhs, b.lhs), (a.rhs, b.rhs)):
            assert x == y
            assert sp.srepr(x) == sp.srepr(y)
            assert _nodes(x) == _nodes(y)


def test_a_changed_definition_or_code_is_a_new_key(scratch, monkeypatch):
    d = definition("north_pointing")
    stored = variation.structured_variation(d)
    # the same model with its first real-work right-hand side doubled
    rhs = d.real_rhs.copy()
    rhs[0] = 2 * rhs[0]
    changed = dataclasses.replace(d, real_rhs=rhs)
    assert variation_store.key(changed) != variation_store.key(d)
    lines = variation.structured_variation(changed)
    assert [line.rhs for line in lines] == [line.rhs for line in _fresh(changed)]
    assert [line.rhs for line in lines] != [line.rhs for line in stored]
    # other code: the stored file is not read
    monkeypatch.setattr(variation, "_STRUCTURED", {})
    old = variation_store.key(d)
    monkeypatch.setattr(variation_store, "code_version", lambda: "other code")
    assert variation_store.key(d) != old
    assert variation_store.load(variation_store.key(d)) is None
    calls = []
    compute = variation._structured_variation
    monkeypatch.setattr(variation, "_structured_variation",
                        lambda d, trees: calls.append(1) or compute(d, trees))
    variation.structured_variation(definition("north_pointing"))
    assert calls == [1]


def test_a_damaged_file_is_computed_afresh(scratch, monkeypatch):
    d = definition("north_pointing")
    expected = [line.rhs for line in variation.structured_variation(d)]
    (path,) = scratch.glob("north_pointing_*.pickle")
    path.write_bytes(b"not a pickle")
    monkeypatch.setattr(variation, "_STRUCTURED", {})
    with pytest.warns(RuntimeWarning, match="is damaged .* varying the model again"):
        assert [line.rhs for line in variation.structured_variation(d)] == expected
    assert variation_store.load(path.stem) is not None  # stored again


def test_the_key_is_the_same_in_another_process():
    """Another process (another hash seed) finds the lines this one stored."""
    code = ("from ins_errors.models import definition\n"
            "from ins_errors.symbolic.variation_store import key\n"
            "print(key(definition('north_pointing')))\n")
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, check=True).stdout.strip()
    assert out == variation_store.key(definition("north_pointing"))
