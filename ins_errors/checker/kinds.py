"""The names of what a difference is and how much it matters (no SymPy needed).

Shared by the equation checker (:mod:`~ins_errors.checker.classify`, which explains
them) and the matrix check (:mod:`~ins_errors.checker.matrix`), which imports only this
module so that ``ins-errors check MODEL --matrix`` does not load SymPy.
"""

from __future__ import annotations

OMITTED = "omitted term"
EXTRA = "extra term"
SIGN = "wrong sign"
COEFFICIENT = "wrong coefficient"
SYMBOL = "wrong symbol or index"
FUNCTION = "wrong function"
EXPONENT = "wrong exponent"
NOT_ERROR = "not an error quantity"
LEFT_SIDE = "left-hand side without Δ"
DEFINITION = "wrong definition"
KINDS = (OMITTED, EXTRA, SIGN, COEFFICIENT, SYMBOL, FUNCTION, EXPONENT, NOT_ERROR,
         LEFT_SIDE, DEFINITION)
"""What a difference can be."""

MISTAKE = "mistake"
SMALL_MISTAKE = "mistake, small effect"
DROPPED = "dropped small term"
DECLARED = "declared drop"
SEVERITIES = (MISTAKE, SMALL_MISTAKE, DROPPED, DECLARED)
"""How much it matters; the first two are mistakes."""


def severity(kind: str, size: float, threshold: float) -> str:
    """Severity of a finding: omissions of small terms are drops, everything else a mistake."""
    if size >= threshold:
        return MISTAKE
    return DROPPED if kind == OMITTED else SMALL_MISTAKE
