"""Up components of a hand model's states, read as the convention's down components.

A convention's states are north-east-down triples (``phi_N``, ``phi_E``, ``phi_D``); a
researcher working in east-north-up writes ``phi_U``, ``dv_U``. An equation file
(``@convention``) reads ``phi_U`` as ``-phi_D``
(:func:`~ins_errors.checker.convention_equations.up_components`); the matrix check does
the same here for a hand-coded F and G: the state ``X_U`` is ``-X_D``, so with
S = diag(±1) (−1 at each up state) the hand's matrices in the convention are S F S and
S G, the order of the states kept. An entry of F changes sign where exactly one of its
row and column is an up state; a finding is named in the convention's names, with the
entry as the hand wrote it beside it (:func:`as_written`). No SymPy.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ins_errors.errors import InsErrorsError


def up_names(names: Sequence[str]) -> dict[str, str]:
    """``{X_U: X_D}`` for every triple ``X_N``, ``X_E``, ``X_D`` of ``names`` whose
    ``X_U`` is not itself one of them (``phi_U`` -> ``phi_D``, ``dv_U`` -> ``dv_D``)."""
    out: dict[str, str] = {}
    for name in names:
        prefix, _, axis = name.rpartition("_")
        if (prefix and axis == "D" and f"{prefix}_N" in names and f"{prefix}_E" in names
                and f"{prefix}_U" not in names):
            out[f"{prefix}_U"] = name
    return out


def down_names(states: Sequence[str], names: Sequence[str], where: str
               ) -> tuple[list[str], dict[str, str]]:
    """The hand's ``states`` in the convention's ``names``, and ``{X_D: X_U}`` of each
    up component read as its down one.

    Raises
    ------
    InsErrorsError
        When the hand has both ``X_U`` and ``X_D`` (one state, ``X_U = -X_D``).
    """
    ups = up_names(names)
    written = {ups[s]: s for s in states if s in ups}
    for down, up in written.items():
        if down in states:
            raise InsErrorsError(f"{where}: states {up!r} and {down!r} are one state "
                                 f"({up} = -{down}): give one of them")
    return [ups.get(s, s) for s in states], written


def flip(states: Sequence[str], written: dict[str, str], F: dict[str, np.ndarray],
         G: dict[str, np.ndarray]) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """S F S and S G on every motion: the rows and columns of the up states (``states``
    already in the convention's names, ``written`` from :func:`down_names`) negated.
    F (K, n, n) and G (K, n, m) by motion label; new arrays, the given ones untouched."""
    s = np.array([-1.0 if name in written else 1.0 for name in states])
    return ({k: f * s[:, None] * s[None, :] for k, f in F.items()},
            {k: g * s[:, None] for k, g in G.items()})


def in_convention(hand, names: Sequence[str]):
    """A :class:`~ins_errors.checker.matrix_input.HandMatrices` with its up states read
    as the convention's down states (signs flipped), and ``{X_D: X_U}`` of those; the
    hand itself and ``{}`` when it has none."""
    states, written = down_names(hand.states, names, hand.name)
    if not written:
        return hand, {}
    F, G = flip(states, written, hand.F, hand.G)
    return replace(hand, states=states, F=F, G=G), written


def as_written(matrix: str, row: str, column: str, written: dict[str, str]) -> str:
    """``" (your F[phi_U, dlat], sign flipped)"`` for an entry whose row or column the
    hand wrote as an up component (``written``: ``{X_D: X_U}``), ``""`` otherwise; a
    column of G is a source, never flipped."""
    row_up = row in written
    column_up = matrix == "F" and column in written
    if not (row_up or column_up):
        return ""
    flipped = row_up != column_up
    return (f" (your {matrix}[{written.get(row, row)}, "
            f"{written.get(column, column) if matrix == 'F' else column}], "
            f"{'sign flipped' if flipped else 'same sign'})")


def written_text(written: dict[str, str]) -> str:
    """``"phi_U = -phi_D, dv_U = -dv_D"``: the up components read, for a report."""
    return ", ".join(f"{up} = -{down}" for down, up in written.items())


__all__ = ["as_written", "down_names", "flip", "in_convention", "up_names", "written_text"]
