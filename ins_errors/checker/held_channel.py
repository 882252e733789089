"""Effects of a matrix check in states that mix the vertical channel into every velocity
and position state (Earth-fixed states: δv^e, δr^e).

The effect propagation (:mod:`~ins_errors.checker.matrix_effects`) holds the undamped
vertical channel (×e every 9.5 min: after a day it would swamp every other difference)
by zeroing the rows and columns of the states that are it (``dv_D``, ``dr_D``). In ECEF
states no state is the vertical channel, so a convention with a
:attr:`~ins_errors.checker.conventions.Convention.hold` gives, along a motion, ``Q`` and
``c`` with which ``F -> Q F Q + c`` and ``G -> Q G`` is exactly the held propagation of
the local-level convention (ψ-angle states with dvc_D and dr_D held), read back in its
own states. Both models are carried so and then propagated as usual, with their own
initial errors and sources as the cases; the effect of a finding alone is the derived
model with only that entry replaced by the hand's, *then* held (holding first would
spread the change over other entries).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ins_errors.checker.check_motions import Motion
from ins_errors.checker.conventions import Convention
from ins_errors.checker.growth import hours_tag
from ins_errors.checker.matrix_effects import EFFECT_HOURS, AloneEffect, _alone, propagate_effects

if TYPE_CHECKING:
    from ins_errors.checker.matrix import MatrixReport, _Sampled


def holdable(states: list[str], conv: Convention) -> bool:
    """True when the hold of ``conv`` can be applied to a hand model in ``states``: each
    triple of the convention's own states it mixes (``Q`` or ``c`` couples its members)
    is in ``states`` whole or not at all."""
    n = len(conv.base.names)
    present = [name in states for name in conv.base.names]
    for start in range(0, n, 3):
        block = present[start:start + 3]
        if any(block) and not all(block):
            return False
    return True


def _operators(conv: Convention, motion: Motion, rows: list[int]
               ) -> tuple[np.ndarray, np.ndarray]:
    """``Q`` and ``c`` of the hold on ``motion``, restricted to the convention states
    ``rows`` (bias states: identity and zero)."""
    Q9, c9 = conv.hold(motion.navigation)
    k, n = Q9.shape[0], len(conv.names)
    n_base = Q9.shape[1]
    Q = np.zeros((k, n, n))
    c = np.zeros((k, n, n))
    Q[:, :n_base, :n_base], c[:, :n_base, :n_base] = Q9, c9
    Q[:, n_base:, n_base:] = np.eye(n - n_base)
    return Q[:, rows][:, :, rows], c[:, rows][:, :, rows]


def _held(F: np.ndarray, G: np.ndarray | None, Q: np.ndarray, c: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray | None]:
    return Q @ F @ Q + c, (None if G is None else Q @ G)


def effects(report: MatrixReport, sampled: _Sampled, conv: Convention, model,
            motion_list: list[Motion]) -> None:
    """Fill ``report.effects``, ``report.finding_effects`` (``report.vertical_effects``
    stays empty: no row is the vertical channel) with the vertical channel held through
    ``conv.hold``; ``report.held`` names what is held.

    A hand model with part of a mixed triple (``dv_X`` without ``dv_Z``) cannot be held
    so: its effects are left out, and ``report.held`` says why.
    """
    from ins_errors.checker.matrix import _Sampled

    if not holdable(report.states, conv):
        report.held = [f"effects not propagated: the hand's states hold part of a triple "
                       f"of {conv.name} ({conv.hold_text} cannot be held)"]
        return
    free = replace(conv, vertical=())
    names = conv.names
    hand_rows = [names.index(s) for s in report.states]
    everything = list(range(len(names)))
    held = _Sampled({}, {}, {}, {})
    operators = {}
    for motion in motion_list:
        label = motion.label
        Q, c = _operators(conv, motion, hand_rows)
        held.Fh[label], G = _held(sampled.Fh[label], sampled.Gh.get(label), Q, c)
        if G is not None:
            held.Gh[label] = G
        operators[label] = _operators(conv, motion, everything)
        held.Fz[label], held.Gz[label] = _held(sampled.Fz[label], sampled.Gz[label],
                                               *operators[label])
    report.effects = propagate_effects(report, held, free, model, motion_list)
    report.held = [conv.hold_text]  # (propagate_effects lists the named vertical states)
    report.finding_effects = _alone_effects(report, sampled, held, operators, free, model,
                                            motion_list)


def _alone_effects(report: MatrixReport, sampled: _Sampled, held: _Sampled,
                   operators: dict, conv: Convention, model, motion_list: list[Motion]
                   ) -> dict[str, AloneEffect]:
    """Each finding alone: the derived model with only that entry replaced by the hand's,
    held, against the held derived model, after 24 h (as
    :func:`~ins_errors.checker.matrix_effects.finding_effects`): the largest change over
    the hand's initial errors and sources, on each motion."""
    from ins_errors.checker.matrix import _Sampled

    hours = EFFECT_HOURS[-1]
    tag = hours_tag(hours)
    names = conv.names
    src_names = [s.name for s in model.sources]
    whole = replace(report, states=list(names), findings=[])
    cases = ({f"initial {s}" for s in report.states}
             | {f"source {s}" for s in report.sources})
    out = {}
    for f in report.findings:
        i = names.index(f.row)
        a = report.states.index(f.row)
        rows = []
        for motion in motion_list:
            label = motion.label
            F2, G2 = sampled.Fz[label].copy(), sampled.Gz[label]
            if f.matrix == "F":
                F2[:, i, names.index(f.column)] = (
                    sampled.Fh[label][:, a, report.states.index(f.column)]
                    if f.column in report.states else 0.0)
            else:
                G2 = G2.copy()
                G2[:, i, src_names.index(f.column)] = (
                    sampled.Gh[label][:, a, report.sources.index(f.column)])
            F2, G2 = _held(F2, G2, *operators[label])
            changed = _Sampled({label: F2}, {label: G2[:, :, [src_names.index(s)
                                                             for s in report.sources]]},
                               {label: held.Fz[label]}, {label: held.Gz[label]})
            found = [e for e in propagate_effects(whole, changed, conv, model, [motion],
                                                  hours=(hours,))
                     if e.case in cases]
            if not found:
                continue
            # (None: the hand's states hold no position, or no attitude)
            position = [e.position_difference for e in found]
            attitude = [e.attitude_difference for e in found]
            largest = None if position[0] is None else max(position)
            growth = {f"position_{tag}": largest,
                      f"position_floor_{tag}": found[0].position_floor}
            if found[0].e_folding is not None:
                growth.update(e_folding_s=found[0].e_folding,
                              growing_mode=found[0].growing_mode)
                growth[f"exponential_{tag}"] = found[0].exponential
            rows.append((label, growth[f"position_{tag}"],
                         None if attitude[0] is None else max(attitude),
                         found[0].position_floor, found[0].attitude_floor, growth))
        if rows:
            out[f.entry] = _alone(rows)
    return out
