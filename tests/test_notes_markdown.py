"""A model's modelling choices are shown readably where Markdown shows them.

The notes of a model's docstring are printed at the top of its generated
``error_equations.md`` and, through it, in every report.md (``ins-errors run``). Written
in Unicode prose, they carried a few TeX spellings (``(1 − e² sin²φ)^{3/2}``, ``f^p``,
``C_b^n``, ``Σ_{j≠i}``) that Markdown shows as their raw characters: a caret or a
braced subscript outside a code span or a formula is such a leftover.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = sorted((ROOT / "generated").glob("*/error_equations.md"))


def _prose(markdown: str) -> str:
    """The text Markdown shows as written: code spans and $...$ formulas taken out."""
    text = re.sub(r"`+[^`]*`+", " ", markdown)
    text = re.sub(r"\$\$.*?\$\$", " ", text, flags=re.S)
    return re.sub(r"\$[^$\n]+\$", " ", text)


def _notes(document: str) -> str:
    match = re.search(r"^## Modelling choices\n(.*?)(?=^## )", document, re.M | re.S)
    return match.group(1) if match else ""


def test_the_generated_documents_have_notes():
    assert len(DOCUMENTS) >= 5
    assert sum(bool(_notes(d.read_text(encoding="utf-8"))) for d in DOCUMENTS) >= 5


@pytest.mark.parametrize("document", DOCUMENTS, ids=[d.parent.name for d in DOCUMENTS])
def test_modelling_choices_have_no_tex_left_in_their_prose(document):
    prose = _prose(_notes(document.read_text(encoding="utf-8")))
    leftovers = re.findall(r".{0,20}(?:\^|_\{).{0,12}", prose)
    assert not leftovers, leftovers


def test_the_meridian_radius_reads_as_the_prime_verticals_companion():
    """The exponent 3/2 is written with the root the prime-vertical radius beside it uses:
    R_N = R(1 − e²)/√(1 − e² sin²φ)³ next to R_E = R/√(1 − e² sin²φ)."""
    for name in ("north_pointing", "orthodromic"):
        notes = _notes((ROOT / "generated" / name / "error_equations.md").read_text(
            encoding="utf-8"))
        assert "(1 − e²)/√(1 − e² sin²φ)³" in notes
