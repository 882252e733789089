"""`make derive` is all or nothing: a failing step leaves the target as it was."""

from __future__ import annotations

import gc
from pathlib import Path

import pytest

import derive.model_files
import derive.pipeline
from derive.__main__ import main
from derive.pipeline import derive_all
from derive.steps import DeriveError


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


@pytest.fixture
def target(tmp_path):
    root = tmp_path / "generated"
    (root / "north_pointing").mkdir(parents=True)
    (root / "north_pointing" / "numpy_model.py").write_text("# the old file\n")
    (root / "keep.md").write_text("kept\n")
    return root


def _broken_vary(d):
    raise ZeroDivisionError("division by zero in a broken model")


@pytest.mark.parametrize("where, step", [("definition", "build the definition"),
                                         ("vary", "vary (first- and second-order")])
def test_a_failing_step_is_one_line_and_changes_nothing(target, monkeypatch, capsys, where,
                                                        step):
    before = _snapshot(target)
    if where == "definition":
        monkeypatch.setattr(derive.pipeline, "definition",
                            lambda name: (_ for _ in ()).throw(NameError("name 'x' is not "
                                                                          "defined")))
    else:
        monkeypatch.setattr(derive.model_files, "vary", _broken_vary)
    with pytest.raises(DeriveError) as caught:
        derive_all(target, ["north_pointing"])
    message = str(caught.value)
    assert "\n" not in message and "north_pointing" in message and step in message
    assert _snapshot(target) == before
    assert sorted(p.name for p in target.parent.iterdir()) == ["generated"]  # no leftovers
    # the command line: one line on stderr, status 2
    threshold, enabled = gc.get_threshold(), gc.isenabled()
    status = main(["--out", str(target), "--model", "north_pointing"])
    _out, err = capsys.readouterr()
    assert status == 2 and err.count("\n") == 1 and err.startswith("derive: error: model")
    # main's GC setting (off for the run) does not leak into the caller
    assert gc.get_threshold() == threshold and gc.isenabled() == enabled
    assert _snapshot(target) == before


def test_a_partial_derive_replaces_only_its_model(target):
    derive_all(target, ["north_pointing"])
    after = _snapshot(target)
    assert after["keep.md"] == b"kept\n"
    assert b"GENERATED FILE" in after["north_pointing/numpy_model.py"]
    assert sorted(p.name for p in target.parent.iterdir()) == ["generated"]
