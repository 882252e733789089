r"""The names a ``@convention`` hand file writes: looked up as written, and the messages
for one that means nothing there.

A name is looked up in the columns the parser read it at, before any arithmetic
(``0*Xi`` has no ``Xi`` once SymPy multiplied it out). A name that means nothing is
refused in one line naming the line and column, the close names (the file's spellings
with what they stand for), what the file calls the latitude or the Earth rate where the
name is one of their usual spellings, the convention's states and the model's error
sources as the model writes them (:func:`check_names_written`). A left-hand side that is
the rate of a named quantity whose error is a state (``dot(v_N)``) is pointed to the
error's row (:func:`true_rate_hint`).
"""

from __future__ import annotations

import sympy as sp

from ins_errors.errors import InsErrorsError, close_names

LATITUDE_SPELLINGS = ("phi", "varphi", "Phi", "B", "latitude")
"""How texts write the latitude where a ``@convention`` file reads ``lat`` (``L`` in
LaTeX): told so when such a name is unknown."""

EARTH_RATE_WORDS = ("omega_ie", "omega_e", "Omega_e", "earth_rate")
"""Other spellings of the Earth rate: told that it is ``U`` when unknown."""

LISTED_SOURCES = 12
"""Error sources an unknown-name message lists at most (the rest: ``ins-errors models``)."""


def check_names_written(hand, known: set[str], states: list[str], model, notation) -> None:
    """Refuse the first name a row, definition or bias line uses that means nothing in
    the file, before any arithmetic: ``0*Xi`` has no ``Xi`` once SymPy multiplied it
    out, yet it is a name the file wrote (the parser keeps every name it read, with its
    column: :attr:`~ins_errors.checker.parse.HandEquation.columns`).

    The message names the line and column, the names close to it (the file's spellings
    with what they stand for: ``Delta_v_N (dv_N)``), what the file calls the latitude or
    the Earth rate where the name is one of their usual spellings, the convention's
    states and the model's error sources as it writes them.

    Parameters
    ----------
    hand : HandFile
        Read with the convention's notation.
    known : set of str
        Every name a line may use (states, sources, named quantities and parameters,
        definitions, up components, ``e``).
    states : list of str
        The convention's states.
    model : ins_errors.numeric.model.Model
        For its error sources and their LaTeX.
    notation : Notation
        The file's spellings (suggested with what they stand for).

    Raises
    ------
    InsErrorsError
        ``FILE, line L, column C: unknown name 'X'...`` (one line).
    """
    for eq in hand.equations:
        left = eq.lhs if isinstance(eq.lhs, sp.Symbol) else eq.lhs.args[0]
        for name, column in sorted(eq.columns.items(), key=lambda item: item[1]):
            if name in known or name == getattr(left, "name", None):
                continue
            where = (f" in the definition of {left.name}" if isinstance(eq.lhs, sp.Symbol)
                     else "")
            raise InsErrorsError(
                f"{hand.name}, line {eq.line}, column {column}: unknown name {name!r}"
                f"{where}"
                + unknown_name_hint(name, known, states, model, notation,
                                    hand.format == "latex"))


def unknown_name_hint(name: str, known: set[str], states: list[str], model, notation,
                      latex: bool) -> str:
    """What follows ``unknown name 'X'`` in a ``@convention`` file's message: names
    close to it, the latitude's or Earth rate's name here, the states and the model's
    error sources as it writes them (see :func:`check_names_written`)."""
    spelled = {k: v for k, v in notation.spellings.items() if v in known}
    candidates = [*states, *(s.name for s in model.sources), *sorted(known - set(states)),
                  *sorted(spelled)]
    if name in LATITUDE_SPELLINGS and "lat" in known:
        out = (f": the latitude is {'L' if latex else 'lat'} in a @convention file"
               + (" (\\varphi and \\phi read as phi, the name of the φ-angle vector)"
                  if latex else ""))
    elif name in EARTH_RATE_WORDS and "U" in known:
        out = ": the Earth rate is U" + (" (or \\Omega)" if latex else "")
    else:
        close = close_names(name, list(dict.fromkeys(candidates)), cutoff=0.6)
        shown = [f"{c!r} ({spelled[c]})" if c in spelled and c not in known else repr(c)
                 for c in close]
        out = f"; did you mean {', '.join(shown)}?" if shown else ""
    rates = [s for s in model.sources if s.kind == "constant"] or list(model.sources)
    listed = [f"{s.latex} ({s.name})" if latex else s.name for s in rates[:LISTED_SOURCES]]
    more = (f", ... ({len(rates)} in all: ins-errors models {model.name})"
            if len(rates) > LISTED_SOURCES else "")
    return (f"{out} (states: {', '.join(states)}; error sources of the model"
            f"{', as it writes them' if latex else ''}: {', '.join(listed)}{more}; named "
            "quantities and definitions NAME = expression: docs/hand_check.md)")


ERROR_OF_QUANTITY = {"lat": "dlat", "h": "dh", **{f"v_{a}": f"dv_{a}" for a in "NED"}}
"""Named quantities whose error is a state of a convention (where it has that state)."""


def true_rate_hint(lhs: sp.Expr, states: list[str]) -> str:
    """``; v_N is the true north velocity, ... dot(dv_N)`` for a left side that is the
    rate of a named quantity whose error is a state; '' otherwise."""
    from ins_errors.checker.convention_equations import QUANTITIES
    from ins_errors.checker.parse import DOT

    if not (isinstance(lhs, sp.Function) and lhs.func == DOT
            and isinstance(lhs.args[0], sp.Symbol)):
        return ""
    name = lhs.args[0].name
    error = ERROR_OF_QUANTITY.get(name)
    if error not in states:
        return ""
    return (f"; {name} is the true {QUANTITIES[name].split(',')[0]}, a named quantity: the "
            f"row of its error is dot({error})")
