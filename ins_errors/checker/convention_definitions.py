r"""Definitions of a ``@convention`` hand file: ``NAME = expression`` lines.

A textbook defines intermediate quantities before it writes the error equations::

    Omega = U
    rho_N = v_E/(R_E + h)                      # a coefficient (the transport rate)
    dlat = dr_N/(R_N + h)                      # a combination of states
    domega_en_N = dv_E/(R_E + h) + v_E*dr_D/(R_E + h)**2
    dot(phi_N) = ... + domega_en_N - (Omega*sin(lat) + ...)*...

A definition's right-hand side uses the named quantities of the reference motion, the
convention's states, the model's error sources and definitions of earlier lines. It is
either a *coefficient* (no state or source: a function of the motion) or a *combination*
of states and sources (linear in them, with no part free of them); it is substituted,
recursively and in file order, into every later row (:func:`expand`). The rows'
coefficients that a definition contributes to are traced (:func:`provenance`), so that a
finding can name the definition's line as well as the row's.

A definition's name is its own: it is not a state, an error source, a named quantity
or a name of vector lines, and a spelling the file's notation gives the name (``Omega``
for ``U``, ``L`` for ``lat``) gives way to it; a name that is the file's spelling of a
state or source (``Delta_v_N``) is refused. Every refusal is one line naming the line.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ins_errors.errors import InsErrorsError


@dataclass(frozen=True)
class Definition:
    r"""One ``NAME = expression`` line of a ``@convention`` file.

    Attributes
    ----------
    name : str
        The name the rows use (after the file's spellings: ``\delta L`` is ``Delta_lat``).
    line : int
        Its line in the file.
    text : str
        The line as written (whitespace collapsed).
    written : sympy.Expr
        The right-hand side as written (earlier definitions by name).
    expr : sympy.Expr
        The right-hand side in states, sources and named quantities only.
    """

    name: str
    line: int
    text: str
    written: sp.Expr
    expr: sp.Expr

    @property
    def label(self) -> str:
        """``rho_N, line 7``: how a finding names it."""
        return f"{self.name}, line {self.line}"


def defined_names(raw, notation, reserved: dict[str, str], spelled_kinds: dict[str, str],
                  name: str):
    """The names the file defines, and its notation with their spellings given way.

    Parameters
    ----------
    raw : HandFile
        The file read without spellings (every name as written).
    notation : Notation
        The convention's spellings (:func:`~ins_errors.checker.convention_equations.
        convention_notation`).
    reserved : dict
        Name -> what it is (``"a state of the convention"``, ...): names a definition may
        not take.
    spelled_kinds : dict
        Name of a state or error source -> what it is: a spelling that ends there may
        not be taken either.
    name : str
        File name, for messages.

    Returns
    -------
    notation : Notation
        A copy without the spellings of the defined names.
    names : dict
        Name as written -> name the rows use (the file's other spellings applied, such as
        ``Delta_L`` -> ``Delta_lat``).

    Raises
    ------
    InsErrorsError
        A definition of a reserved name or of a spelling of a state or source.
    """
    from ins_errors.checker.notation import Notation
    from ins_errors.checker.parse import canonical_name

    written = [(eq.line, eq.lhs.name) for eq in raw.equations
               if isinstance(eq.lhs, sp.Symbol)]
    for line, text in written:
        where = f"{name}, line {line}"
        target = notation.spellings.get(text)
        if text in reserved:
            raise InsErrorsError(_clash(where, text, text, reserved[text]))
        if target is not None and target in spelled_kinds:
            raise InsErrorsError(
                f"{where}: left-hand side {text!r} is this file's spelling of "
                f"{target!r}, {spelled_kinds[target]}; a definition (NAME = expression) "
                "needs a name of its own")
    own = {text for _, text in written}
    kept = Notation(aliases=dict(notation.aliases), sources=dict(notation.sources),
                    spellings={k: v for k, v in notation.spellings.items() if k not in own},
                    latex_primes=dict(notation.latex_primes))
    names = {}
    for line, text in written:
        spelled = canonical_name(text, kept)
        if not isinstance(spelled, sp.Symbol):
            continue
        if spelled.name in reserved:
            raise InsErrorsError(_clash(f"{name}, line {line}", text, spelled.name,
                                        reserved[spelled.name]))
        names[text] = spelled.name
    return kept, names


def _clash(where: str, text: str, name: str, what: str) -> str:
    shown = repr(text) if text == name else f"{text!r} ({name})"
    if what.startswith("a state"):
        hint = f"its row is written dot({name}) = ..., and a definition"
    elif what.startswith("an error source"):
        hint = (f"a bias state's line is dot({name}) = ..., and a definition")
    else:
        hint = "a definition"
    return (f"{where}: left-hand side {shown} is {what}: {hint} (NAME = expression) needs "
            "a name that is no state, error source, named quantity or vector")


def read_definitions(hand, known: set[str], variables: list[str]) -> dict[str, Definition]:
    """The definitions of a parsed ``@convention`` file, in file order.

    Parameters
    ----------
    hand : HandFile
        The file read with its spellings; its equations with a symbol on the left are
        the definitions (rows have ``dot(STATE)``).
    known : set of str
        States, error sources and named quantities.
    variables : list of str
        States and error sources (what a combination is linear in).

    Raises
    ------
    InsErrorsError
        A second definition of a name, a chain, an unknown name, a definition used
        before its line, a cycle, a definition not linear in the states and sources or
        mixing a coefficient with them; one line naming the line.
    """
    written = {eq.lhs.name: eq for eq in hand.equations if isinstance(eq.lhs, sp.Symbol)}
    out: dict[str, Definition] = {}
    symbols = [sp.Symbol(v) for v in variables]
    for eq in hand.equations:
        if not isinstance(eq.lhs, sp.Symbol):
            continue
        name, where = eq.lhs.name, f"{hand.name}, line {eq.line}"
        if name in out:
            raise InsErrorsError(f"{where}: second definition of {name} (first on line "
                                 f"{out[name].line})")
        if len(eq.forms) != 1:
            raise InsErrorsError(f"{where}: one right-hand side per definition")
        rhs = eq.forms[0]
        for s in sorted(rhs.free_symbols, key=str):
            if s.name == name:
                raise InsErrorsError(f"{where}: {name} is defined in terms of itself")
            if s.name in out or s.name in known:
                continue
            if s.name in written:
                raise InsErrorsError(_used_early(where, f"{name} = ...", s.name, written,
                                                 name))
            raise InsErrorsError(f"{where}: unknown name {s.name!r} in the definition of "
                                 f"{name} (states, error sources, named quantities and "
                                 "definitions of earlier lines: docs/hand_check.md)")
        expr = rhs.xreplace({sp.Symbol(d.name): d.expr for d in out.values()})
        _linear_or_coefficient(where, name, expr, symbols)
        out[name] = Definition(name, eq.line, eq.text, rhs, expr)
    return out


def _used_early(where: str, what: str, used: str, written: dict, current: str | None
                ) -> str:
    """Message for a definition used on a line before its own (or a cycle)."""
    later = written[used]
    if current is not None and _depends(used, current, written, set()):
        return (f"{where}: {current} and {used} are defined in terms of each other "
                f"(lines {written[current].line} and {later.line})")
    return f"{where}: {what} uses {used} before its definition on line {later.line}"


def _depends(name: str, target: str, written: dict, seen: set[str]) -> bool:
    """Whether the definition ``name`` uses ``target``, directly or through others."""
    if name in seen or name not in written:
        return False
    seen.add(name)
    names = {s.name for form in written[name].forms for s in form.free_symbols}
    return target in names or any(_depends(n, target, written, seen) for n in names)


def _linear_or_coefficient(where: str, name: str, expr: sp.Expr, symbols: list[sp.Symbol]
                           ) -> None:
    """Refuse a definition that is neither a coefficient nor a combination of states."""
    held = expr.free_symbols & set(symbols)
    if not held:
        return
    for s in sorted(held, key=str):
        c = sp.diff(expr, s)
        if c.free_symbols & set(symbols):
            raise InsErrorsError(f"{where}: {name} is not linear in the states and error "
                                 f"sources (coefficient of {s} is {c})")
    rest = sp.simplify(expr.subs({s: 0 for s in held}))
    if rest != 0:
        raise InsErrorsError(
            f"{where}: {name} mixes a coefficient ({rest}) with states or error sources: "
            "a definition is either a coefficient (no state or source) or a combination "
            "of states and sources (linear, no part without one)")


def expand(expr: sp.Expr, line: int, what: str, definitions: dict[str, Definition],
           name: str) -> sp.Expr:
    """``expr`` (of line ``line``) with every definition substituted.

    Raises
    ------
    InsErrorsError
        A definition of a later line: ``NAME, line L: WHAT uses rho_N before its
        definition on line M``.
    """
    used = {s.name for s in expr.free_symbols} & set(definitions)
    for d in sorted(used, key=lambda n: definitions[n].line):
        if definitions[d].line > line:
            raise InsErrorsError(f"{name}, line {line}: {what} uses {d} before its "
                                 f"definition on line {definitions[d].line}")
    return expr.xreplace({sp.Symbol(d): definitions[d].expr for d in used})


def provenance(expr: sp.Expr, definitions: dict[str, Definition], variables: list[str]
               ) -> dict[str, tuple[str, ...]]:
    """Which definitions each coefficient of ``expr`` comes through.

    Each definition used (directly or through another) is substituted times a marker;
    a coefficient that depends on a marker comes (at least in part) through that
    definition.

    Returns
    -------
    dict
        Variable (state or source) -> names of the definitions its coefficient uses, in
        file order; variables whose coefficient uses none are left out.
    """
    used: set[str] = set()
    todo = [s.name for s in expr.free_symbols if s.name in definitions]
    while todo:
        d = todo.pop()
        if d not in used:
            used.add(d)
            todo += [s.name for s in definitions[d].written.free_symbols
                     if s.name in definitions]
    if not used:
        return {}
    order = sorted(used, key=lambda n: definitions[n].line)
    markers = {d: sp.Dummy(f"via_{d}") for d in order}
    marked: dict[sp.Symbol, sp.Expr] = {}
    for d in order:
        marked[sp.Symbol(d)] = markers[d] * definitions[d].written.xreplace(marked)
    whole = expr.xreplace(marked)
    out = {}
    for v in variables:
        held = sp.diff(whole, sp.Symbol(v)).free_symbols
        through = tuple(d for d in order if markers[d] in held)
        if through:
            out[v] = through
    return out
