"""The one definition of a ``@convention`` file that several findings come through.

A wrong definition (``dOm_N = -U*cos(lat)*dlat`` for ``-U*sin(lat)*dlat``) reaches every
row that uses it, so the matrix check finds one wrong entry per row, each naming the
definitions its entry comes through (``via dOm_N, line 10``). Read line by line these
are separate mistakes; what they share is the definition. A definition is named as
their cause when at least two findings come through it, more than half of the entries
it reaches differ (a radius ``r = R + h`` that thirty entries use, two of them wrong,
is no cause), and no other definition that all of them come through is closer to them
(one that uses it, ``dK_N = 2*dOm_N + ...``, reaches fewer findings). A finding whose
detail names a slip of sin and cos (:func:`~ins_errors.checker.ratio_names.trig_name`,
seen where that term is the whole entry, at rest) says what is wrong in it, and the
definition is checked to hold the function named.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import sympy as sp

from ins_errors.checker.kinds import MISTAKE, SMALL_MISTAKE

SWAP = re.compile(r"(sin|cos|tan) φ written where (sin|cos|tan) φ belongs")
"""A function slip of the latitude said in a finding's detail."""


@dataclass(frozen=True)
class Cause:
    """A definition several findings come through.

    Attributes
    ----------
    name : str
        The definition's name.
    line : int
        Its line.
    entries : tuple of str
        The findings' entries (``F[phi_N, dlat]``), in the report's order.
    reached : int
        How many entries of the rows it reaches (differing or not).
    slip : str
        What is wrong in it where a finding says (``cos where sin belongs``), or ``""``.
    """

    name: str
    line: int
    entries: tuple[str, ...]
    reached: int
    slip: str = ""

    @property
    def text(self) -> str:
        """``the definition of dOm_N (line 10) has cos where sin belongs; it reaches
        F[phi_N, dlat] and F[dv_D, dlat] (2 of the 3 entries it reaches differ)``."""
        head = (f"the definition of {self.name} (line {self.line}) "
                + (f"has {self.slip}" if self.slip else "is what these findings share"))
        listed = (", ".join(self.entries[:-1]) + f" and {self.entries[-1]}"
                  if len(self.entries) > 1 else self.entries[0])
        return (f"{head}; it reaches {listed} ({len(self.entries)} of the {self.reached} "
                "entries it reaches differ)")


def causes(check) -> list[Cause]:
    """The definitions of a :class:`~ins_errors.checker.convention_equations.
    ConventionCheck` that findings share as their cause (see the module docstring),
    in file order."""
    findings = [f for f in check.report.findings if f.severity in (MISTAKE, SMALL_MISTAKE)]
    through: dict[str, list] = {}
    for f in findings:
        for d in check.via_of(f):
            through.setdefault(d.name, []).append(f)
    reached: dict[str, int] = {}
    for columns in check.via.values():
        for names in columns.values():
            for name in names:
                reached[name] = reached.get(name, 0) + 1
    candidates = {name: group for name, group in through.items()
                  if len(group) >= 2 and 2 * len(group) > reached.get(name, 0)}
    out = []
    for name, group in candidates.items():
        entries = {id(f) for f in group}
        # a definition between it and the findings that all of them come through
        # names them better only if it reaches them all; otherwise this one is the cause
        if any(other != name and entries <= {id(f) for f in g2}
               and _uses(check.definitions[other], name) for other, g2 in candidates.items()):
            continue
        d = check.definitions[name]
        out.append(Cause(name, d.line, tuple(f.entry for f in group), reached[name],
                         _slip(d, group)))
    return sorted(out, key=lambda c: c.line)


def _uses(definition, name: str) -> bool:
    """Whether a definition's right-hand side as written names ``name``."""
    return any(s.name == name for s in definition.written.free_symbols)


def _slip(definition, group) -> str:
    """``cos where sin belongs`` when a finding of the group says so and the definition
    holds that function (of any argument), else ``""``."""
    functions = {f.func.__name__ for f in definition.expr.atoms(sp.sin, sp.cos, sp.tan)}
    for f in group:
        found = SWAP.search(f.detail)
        if found and found.group(1) in functions:
            return f"{found.group(1)} where {found.group(2)} belongs"
    return ""


__all__ = ["Cause", "causes"]
