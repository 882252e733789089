"""Named, listed simplifications of an error model: terms a hand derivation drops.

A simplification is a list of entries (equation, variable) of the state matrix F that
are set to zero, each with the reason a source document gives for dropping it. Applying
one returns the reduced matrix *and* the list of the dropped terms with their values, so
a document can print exactly what the reduced model lacks.

Registered simplifications (:data:`SIMPLIFICATIONS`):

``report_reduced`` (model ``north_pointing``, source 001)
    The lab report's static-base model: the two Foucault cross-coupling terms
    ±2Ω sin φ δv of the velocity-error equations are dropped ("this simplifies the
    solution without hindering an understanding of its main characteristics"); the
    vertical channel is ignored (the model has none to drop).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from ins_errors.errors import InsErrorsError, unknown_name


class SimplificationError(InsErrorsError):
    """A simplification that does not fit the matrix it is applied to."""


@dataclass(frozen=True)
class DroppedTerm:
    """One term of the error equations that a simplification removes.

    Attributes
    ----------
    equation : str
        Error-state name whose time derivative loses the term.
    variable : str
        Error-state name the term multiplies.
    reason : str
        Why the source drops it.
    """

    equation: str
    variable: str
    reason: str


@dataclass(frozen=True)
class Simplification:
    """A named list of dropped terms of one model's state matrix.

    Attributes
    ----------
    name : str
        Registry name.
    model : str
        Model it applies to.
    title : str
        One line.
    source : str
        Where the simplification comes from.
    terms : tuple of DroppedTerm
    notes : str
        Simplifications with no matrix entry (e.g. a channel the model does not have).
    """

    name: str
    model: str
    title: str
    source: str
    terms: tuple[DroppedTerm, ...]
    notes: str = ""

    def apply(self, F: sp.Matrix, error_states: Sequence[str]
              ) -> tuple[sp.Matrix, list[tuple[DroppedTerm, sp.Expr]]]:
        """Zero the listed entries of ``F``.

        Parameters
        ----------
        F : sympy.Matrix, shape (ne, ne)
            State matrix (any point: moving or static base).
        error_states : sequence of str
            Error-state names in the order of F's rows.

        Returns
        -------
        reduced : sympy.Matrix
        dropped : list of (DroppedTerm, sympy.Expr)
            Each dropped term with the coefficient it had in ``F``.

        Raises
        ------
        SimplificationError
            If a named state does not exist or a listed term is already zero (the
            simplification would silently change nothing).
        """
        names = list(error_states)
        reduced = F.copy()
        dropped = []
        for term in self.terms:
            for name in (term.equation, term.variable):
                if name not in names:
                    raise unknown_name(f"error state of {self.model}", name, names)
            i, j = names.index(term.equation), names.index(term.variable)
            value = reduced[i, j]
            if value == 0:
                raise SimplificationError(
                    f"simplification {self.name!r}: the term {term.variable} in "
                    f"d({term.equation})/dt is already zero")
            dropped.append((term, value))
            reduced[i, j] = 0
        return reduced, dropped


_FOUCAULT = ("Foucault cross-coupling (Coriolis term wrongly compensated with the "
             "velocity error): dropped by the report to keep the solution simple")

SIMPLIFICATIONS: dict[str, Simplification] = {
    "report_reduced": Simplification(
        name="report_reduced",
        model="north_pointing",
        title="Report's reduced static-base model (Foucault cross-couplings dropped)",
        source="001, section 5.2-5.3 and the F matrix of section III",
        terms=(
            DroppedTerm("delta_v_E", "delta_v_N", _FOUCAULT),
            DroppedTerm("delta_v_N", "delta_v_E", _FOUCAULT),
        ),
        notes="The vertical channel is ignored; the model has no vertical channel, so "
              "nothing else is dropped.",
    ),
}
"""Registry of simplifications by name."""


def simplification(name: str) -> Simplification:
    """Look up a registered simplification (one-line error with suggestions if unknown)."""
    if name not in SIMPLIFICATIONS:
        raise unknown_name("simplification", name, SIMPLIFICATIONS)
    return SIMPLIFICATIONS[name]

