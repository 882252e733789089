"""Refuse a real work that reads a true state where the computer has its own.

The real work is the navigation computer fed real sensors: it integrates its own
(computed) state ``x~`` and knows the true state ``x`` only through what the sensors
sense. A real-work equation of a computed state that reads the true ``lat`` and not
``lat_c`` (a one-character slip, ``navigator(real, [..., lat, ...])``) still reduces to
the ideal work, derives and runs, but the computed latitude's error then never feeds
back where the formula uses it: F lacks those terms, silently. :func:`check_true_state_reads`
finds it and raises one :class:`~ins_errors.errors.ModelDefinitionError` line naming the
equation or intermediate, the true state and the computed one it probably meant.

What is read on purpose stays silent:

* the rows of the states beyond the computed ones (platform angles): they are the
  platform's physics, which turns with the true motion (``dψ/dt = ω~ − ω + ε``);
* a true state read beside its computed counterpart (an external reference compared with
  the computed value, ``V_c − (V + δV_log)``; a sensor sensing the true gravity that the
  computer compensates at its own latitude);
* a true state that drops out when every error is zero (a vertical specific force of the
  true state times a platform angle: a sensor on the tilted platform);
* a real intermediate that the ideal work does not define (a sensor's model) is judged
  only where an equation uses it;
* the states named in :attr:`~ins_errors.modeling.ModelDefinition.reads_true_state` (a
  dead reckoning on a log velocity, a GNSS position).
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

from ins_errors.errors import ModelDefinitionError
from ins_errors.modeling import ModelDefinition
from ins_errors.symbolic.consistency import declared_uses, intermediate_dependence

STEP = "checking the definition"


def declared_states(d: ModelDefinition, label: str) -> set[str]:
    """The state names of ``d.reads_true_state``, checked.

    Raises
    ------
    ModelDefinitionError
        If it is not a list of state names.
    """
    declared = d.reads_true_state
    names = [v.name for v in d.states]
    if isinstance(declared, str) or not isinstance(declared, Iterable) \
            or not all(isinstance(name, str) for name in declared):
        raise ModelDefinitionError(
            f"{label}: reads_true_state: must be a list of state names (e.g. "
            f"[{names[0]!r}]), got {declared!r:.60} (step: {STEP})")
    unknown = [name for name in declared if name not in names]
    if unknown:
        raise ModelDefinitionError(
            f"{label}: reads_true_state: {', '.join(map(repr, unknown))} is not a state; "
            f"the states are {', '.join(names)} (step: {STEP})")
    return set(declared)


def true_state_reads(d: ModelDefinition, declared: set[str] = frozenset()
                     ) -> list[tuple[str, sp.Symbol, sp.Symbol, str]]:
    """Where the real work reads a true state whose computed counterpart it does not.

    Parameters
    ----------
    d : ModelDefinition
        A definition that passed :func:`~ins_errors.symbolic.consistency.check_definition`.
    declared : set of str
        State names read on purpose (not reported).

    Returns
    -------
    list of (str, sympy.Symbol, sympy.Symbol, str)
        One entry per finding, real intermediates (in definition order) first, then the
        equations (in state order): the quantity, the true state, its computed symbol and
        the advice of what to write.
    """
    n = len(d.states)
    computed = {x: c for x, c, v in zip(d.x, d.real_states[:n], d.states, strict=True)
                if v.name not in declared}
    depends = intermediate_dependence(d.ideal, d.real)
    errors_off = {**{s: sp.S.Zero for s in d.real_states[n:]}, **d.no_errors()}
    ideal_names = {definition.symbol.name for definition in d.ideal.definitions}
    real_of = {definition.symbol.name.removesuffix("_c"): definition.symbol
               for definition in d.real.definitions}

    def unpaired(expression: sp.Basic, candidates: Iterable[sp.Basic]) -> list[sp.Symbol]:
        """The true states of ``candidates`` read without their computed symbol, that stay
        in ``expression`` when every error is zero (in state order)."""
        used = declared_uses(expression, depends)
        found = [x for x in computed if x in candidates and computed[x] not in used]
        if not found:
            return []
        at_zero = d.expand(sp.Matrix([expression])).xreplace(errors_off).free_symbols
        return [x for x in found if x in at_zero]

    findings = []
    for definition in d.real.definitions:
        base = definition.symbol.name.removesuffix("_c")
        if base not in ideal_names:
            continue  # not the computer's own formula (a sensor's model): judged where used
        for x in unpaired(definition.expression, definition.expression.free_symbols):
            findings.append((f"real-work intermediate {definition.symbol}", x, computed[x],
                             f"write {computed[x]}"))
    names = [v.name for v in d.error_states]
    rows = [(d.real_rhs, "real-work equation (real_rhs)")]
    if d.small_angle_rhs is not None:
        rows.append((d.small_angle_rhs, "small-angle real-work equation (small_angle_rhs)"))
    ideal_symbols = {definition.symbol for definition in d.ideal.definitions}
    for matrix, what in rows:
        for i in range(n):
            row = matrix[i]
            for x in unpaired(row, declared_uses(row, depends)):
                quantity = f"{what} for {names[i]!r} (d{d.real_states[i]}/dt)"
                advice = f"write {computed[x]}"
                via = next((s for s in sorted(row.free_symbols, key=str)
                            if x in depends.get(s, ())), None)
                if x not in row.free_symbols and via in ideal_symbols:
                    quantity += f" (through the ideal-work intermediate {via})"
                    if via.name in real_of:
                        advice = (f"write the real work's {real_of[via.name]} in place of "
                                  f"the ideal work's {via}")
                elif x not in row.free_symbols and via is not None:
                    quantity += f" (through {via})"
                findings.append((quantity, x, computed[x], advice))
    return findings


def check_true_state_reads(d: ModelDefinition, label: str) -> None:
    """Refuse a real work that reads a true state where the computer has the computed one.

    Parameters
    ----------
    d : ModelDefinition
        A definition that passed :func:`~ins_errors.symbolic.consistency.check_definition`.
    label : str
        How the message names the model (``"model file my_ins.py (model 'my_ins')"``).

    Raises
    ------
    ModelDefinitionError
        One line naming the first equation or intermediate that does it (and how many
        more), the true state and the computed symbol it probably meant.
    """
    findings = true_state_reads(d, declared_states(d, label))
    if not findings:
        return
    quantity, x, x_c, advice = findings[0]
    more = len(findings) - 1
    also = (f"; the same in {more} more equation(s) and intermediate(s)" if more else "")
    raise ModelDefinitionError(
        f"{label}: {quantity}: reads the true state {x} where the computer has {x_c}: the "
        f"computer does not know the true value of a state it computes (the truth reaches "
        f"the real work only through the sensor inputs); {advice}, or, if the real work "
        f"senses the true {x} on purpose (an external reference such as a log or GNSS, or "
        f"what a sensor senses), declare it: ModelDefinition(..., "
        f"reads_true_state=[{x.name!r}]){also} (step: {STEP})")
