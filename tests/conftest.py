"""Shared fixtures."""

from __future__ import annotations

import gc
import os

import pytest

from tests.helpers import QUIET_DASK

for _name, _value in QUIET_DASK.items():  # before anything imports Dask
    os.environ.setdefault(_name, _value)

import ins_errors  # noqa: E402


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


def pytest_collection_finish(session) -> None:
    """Fewer and cheaper garbage collections for the rest of the session.

    The suite builds large SymPy trees and keeps many of them (the per-process caches of
    the variation and the checker): the cyclic collector's full passes scanned them again
    and again (~6 % of the symbolic tests' CPU, 2.7 s in 42 s). What exists once the tests
    are collected is frozen (never scanned again), and the youngest generation is
    collected every 20 000 net allocations instead of 700. When garbage is collected
    changes no result.
    """
    gc.collect()
    gc.freeze()
    gc.set_threshold(20_000, 20, 20)
