"""README stays true: every model, error source and output is listed with its units,
and the tour's Python snippet runs."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import ins_errors

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")
MODELS_PAGE = (ROOT / "docs" / "models.md").read_text(encoding="utf-8")


@pytest.mark.parametrize("name", ins_errors.available_models())
def test_readme_lists_every_source_and_output_with_units(name):
    model = ins_errors.load_model(name)
    assert f"| `{name}` |" in README.split("## Models", 1)[1], "README's model table"
    section = MODELS_PAGE.split(f"\n## `{name}`", 1)[1].split("\n## ", 1)[0]
    for source in model.sources:
        assert re.search(rf"\| `{source.name}` \| {re.escape(source.unit)} \| "
                         rf"{re.escape(source.display_unit)} \|", section), source.name
    for output in model.outputs:
        assert f"`{output.name}` ({output.unit})" in section, output.name


def test_readme_starts_with_the_two_setup_commands():
    first_block = README.split("```sh", 1)[1].split("```", 1)[0]
    assert "make derive" in first_block and "make test" in first_block


def test_api_snippet_runs():
    """The snippet runs, and the shapes its comments state are the arrays' shapes."""
    import re

    snippet = README.split("## The API at a glance", 1)[1].split("```python", 1)[1]
    snippet = snippet.split("```", 1)[0]
    namespace: dict = {}
    exec(compile(snippet, "README.md", "exec"), namespace)
    stated = {m.group(1): tuple(int(k) for k in m.group(2).split(","))
              for m in re.finditer(r"^(\w+) = .*# \((\d+, \d+)\)", snippet, re.M)}
    assert stated == {"F": (11, 11), "G": (11, 26), "H": (7, 11)}
    for name, shape in stated.items():
        assert namespace[name].shape == shape, name
    model = namespace["model"]
    assert (len(model.error_states), len(model.sources), len(model.outputs)) == (11, 26, 7)
    assert namespace["x"].shape == (8,)  # six direction cosines, V_ξ, V_η


def test_closed_forms_snippet_runs_and_says_which_models_have_them():
    section = README.split("### Transfer functions and closed forms (static base)", 1)[1]
    section = section.split("\n## ", 1)[0]
    exec(compile(section.split("```python", 1)[1].split("```", 1)[0], "README.md", "exec"),
         {})
    from ins_errors.symbolic.static_base import SETUPS

    named = [name for name in ins_errors.available_models() if f"`{name}`" in
             section.split("```python", 1)[0]]
    assert sorted(named) == sorted(SETUPS)


LINK = re.compile(r"\]\(([^)\s]+)\)")


@pytest.mark.parametrize("page", [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")),
                                  *sorted((ROOT / "examples").glob("**/README.md"))],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_reach_files(page):
    """Every relative link of the README, docs/ and the examples' pages names a file or
    folder that exists, taken from the page's own folder (the pages moved between folders)."""
    text = page.read_text(encoding="utf-8")
    targets = [t.split("#", 1)[0] for t in LINK.findall(text)
               if not t.startswith(("http://", "https://", "#", "mailto:"))]
    missing = [t for t in targets if t and not (page.parent / t).exists()]
    assert not missing, f"{page.name}: {missing}"
