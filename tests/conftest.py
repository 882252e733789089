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
