"""docs/api.md stays true: its Python blocks run, in order, in one namespace (as the
cells of one notebook, from the repository root, as the page's relative paths are),
every ``# shape (a, b)`` comment is the shape of what its line computes, and the comment
of a ``print`` is what it prints."""

from __future__ import annotations

import ast
import contextlib
import io
import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGE = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
BLOCKS = re.findall(r"^```python\n(.*?)^```", PAGE, re.M | re.S)
SHAPE = re.compile(r"#\s*shape (\([\d, ]*\))")


def _shape_claims(block: str) -> list[tuple[str, tuple[int, ...]]]:
    """(expression, shape) of every line with a ``# shape (...)`` comment: the target of
    an assignment, or the expression the line evaluates (whose shape it is; of
    ``a.shape``, the value itself)."""
    claims = []
    for line in block.splitlines():
        found = SHAPE.search(line)
        if found is None:
            continue
        code = line[:found.start()].strip()
        statement = ast.parse(code).body[0]
        target = (statement.targets[0] if isinstance(statement, ast.Assign)
                  else statement.value)
        claims.append((ast.unparse(target), ast.literal_eval(found.group(1))))
    return claims


def _printed_claims(block: str) -> list[str]:
    """The comment of every line that prints."""
    return [line.split("  # ", 1)[1].strip() for line in block.splitlines()
            if line.strip().startswith("print(") and "  # " in line]


def test_the_page_shows_every_task():
    assert len(BLOCKS) >= 10
    code = "\n".join(BLOCKS)
    for name in ("load_model", "state_matrix", "static_profile", "great_circle_profile",
                 "manoeuvre_profile", "read_motion_file", "simulate", "compare(",
                 "static_system", "system_from_trajectory", "propagate", "static_modes",
                 "transfer_functions", "check_matrices", "parse_quantity", "warn=False"):
        assert name in code, name
    assert sum(len(_shape_claims(b)) for b in BLOCKS) >= 8
    assert sum(len(_printed_claims(b)) for b in BLOCKS) >= 2


def test_the_blocks_run_and_state_true_shapes(monkeypatch):
    monkeypatch.chdir(ROOT)
    namespace: dict = {}
    for number, block in enumerate(BLOCKS, 1):
        printed = io.StringIO()
        try:
            with contextlib.redirect_stdout(printed):
                exec(compile(block, f"docs/api.md block {number}", "exec"), namespace)
        except Exception as error:  # pragma: no cover - the failure message
            pytest.fail(f"docs/api.md block {number}: {type(error).__name__}: {error}")
        lines = printed.getvalue().splitlines()
        for claim in _printed_claims(block):
            assert claim in lines, f"block {number} does not print {claim!r}: {lines}"
        for expression, shape in _shape_claims(block):
            value = eval(expression, namespace)
            got = value if expression.endswith(".shape") else np.shape(value)
            assert got == shape, f"block {number}: {expression}"
