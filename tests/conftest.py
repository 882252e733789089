"""Shared fixtures."""

from __future__ import annotations

import pytest

import ins_errors


@pytest.fixture(scope="session")
def orthodromic() -> ins_errors.Model:
    return ins_errors.load_model("orthodromic")


@pytest.fixture(scope="session")
def orthodromic_error_model(orthodromic):
    """The in-memory SymPy variation of the orthodromic model (a few seconds)."""
    from ins_errors.symbolic.variation import vary

    return vary(orthodromic.symbolic)


@pytest.fixture(scope="session")
def example_reports() -> dict:
    """Report folders written by ``ins-errors run examples/NAME.toml --out DIR`` in this
    session, by example file name: the README's commands (test_docs_commands.py) write
    them, the example checks (test_scenarios.py) read them instead of running the same
    example again (and run it themselves when it is not there)."""
    return {}
