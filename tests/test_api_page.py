"""docs/api.md stays true: its Python blocks run, in order, in one namespace (as the
cells of one notebook, from the repository root, as the page's relative paths are),
every ``# shape (a, b)`` comment is the shape of what its line computes, and the comment
of a ``print`` is what it prints."""

from __future__ import annotations

from pathlib import Path

from tests.page_blocks import printed_claims, python_blocks, run_blocks, shape_claims

ROOT = Path(__file__).resolve().parent.parent
PAGE = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
BLOCKS = python_blocks(PAGE)


def test_the_page_shows_every_task():
    assert len(BLOCKS) >= 10
    code = "\n".join(BLOCKS)
    for name in ("load_model", "state_matrix", "static_profile", "great_circle_profile",
                 "manoeuvre_profile", "read_motion_file", "simulate", "compare(",
                 "static_system", "system_from_trajectory", "propagate", "static_modes",
                 "transfer_functions", "check_matrices", "parse_quantity", "warn=False"):
        assert name in code, name
    assert sum(len(shape_claims(b)) for b in BLOCKS) >= 8
    assert sum(len(printed_claims(b)) for b in BLOCKS) >= 2


def test_the_blocks_run_and_state_true_shapes(monkeypatch):
    monkeypatch.chdir(ROOT)
    run_blocks(BLOCKS, "docs/api.md")
