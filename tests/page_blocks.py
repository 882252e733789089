"""Run the Python blocks of a documentation page (docs/api.md, docs/generated.md) as the
cells of one notebook, and check what their comments claim.

Every ```python block runs, in order, in one namespace (so a block may use what an
earlier one made); a comment ``# shape (a, b)`` on a line is checked against the shape of
what that line computes (the assignment's target, or the expression; of ``a.shape``, the
value itself), and the comment of a line that prints (``print(...)  # text``) must be one
of the lines it printed.
"""

from __future__ import annotations

import ast
import contextlib
import io
import re

import numpy as np
import pytest

PYTHON_BLOCK = re.compile(r"^```python\n(.*?)^```", re.M | re.S)
SHAPE = re.compile(r"#\s*shape (\([\d, ]*\))")


def python_blocks(page: str) -> list[str]:
    """The ```python blocks of a page's text, in order."""
    return PYTHON_BLOCK.findall(page)


def shape_claims(block: str) -> list[tuple[str, tuple[int, ...]]]:
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


def printed_claims(block: str) -> list[str]:
    """The comment of every line that prints."""
    return [line.split("  # ", 1)[1].strip() for line in block.splitlines()
            if line.strip().startswith("print(") and "  # " in line]


def run_blocks(blocks: list[str], page: str, namespace: dict | None = None) -> dict:
    """Run ``blocks`` of ``page`` (its name, for messages) in one namespace, in the
    current folder; fail the test at the first block that raises, does not print what
    a comment says, or makes an array of another shape than its comment. Returns the
    namespace."""
    namespace = {} if namespace is None else namespace
    for number, block in enumerate(blocks, 1):
        printed = io.StringIO()
        try:
            with contextlib.redirect_stdout(printed):
                exec(compile(block, f"{page} block {number}", "exec"), namespace)
        except Exception as error:  # pragma: no cover - the failure message
            pytest.fail(f"{page} block {number}: {type(error).__name__}: {error}")
        lines = printed.getvalue().splitlines()
        for claim in printed_claims(block):
            assert claim in lines, f"{page} block {number} does not print {claim!r}: {lines}"
        for expression, shape in shape_claims(block):
            value = eval(expression, namespace)
            got = value if expression.endswith(".shape") else np.shape(value)
            assert got == shape, f"{page} block {number}: {expression} is {got}, not {shape}"
    return namespace
