"""The derived linear model carried into a researcher's convention along a motion.

``ż = (Ṫ + T F) T⁻¹ z + T G w`` (:mod:`~ins_errors.checker.conventions`), with the lift
onto the model's own state manifold where the convention sees fewer directions than the
model has states, and bias states appended where the convention carries error sources as
states. Also which damping gains left at 0 hide terms from a check
(:func:`unchecked_gains`).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace

import numpy as np

from ins_errors.checker.check_motions import Motion
from ins_errors.checker.conventions import Convention, convention


def unchecked_gains(model, convention_name: str, rows: Iterable[str], motion: Motion
                    ) -> list[str]:
    """The model's damping gains (``Parameter(..., damping_gain=True)``) at 0 in
    ``motion.p`` that enter the given rows of the derived model in the convention: the
    terms they multiply are 0 there, so a check of those rows does not see them.

    A gain enters a row when setting it to 1 (SI) alone changes the row of F or G at the
    motion's first sample (the ideal motion is the same: a damping loop closes on a
    difference that is 0 in ideal work).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    convention_name : str
        The convention of the rows (``model``: the model's own error states).
    rows : iterable of str
        State names of the convention the check compares (others are ignored).
    motion : Motion
        A motion of :func:`motions`, with the parameters the check used.

    Returns
    -------
    list of str
        The gains' names, in the model's order.
    """
    p = np.asarray(motion.p, dtype=float)
    zero = [k for k, info in enumerate(model.parameters)
            if info.damping_gain and p[..., k].flat[0] == 0]
    conv = convention(model, convention_name)
    wanted = [conv.names.index(r) for r in rows if r in conv.names]
    if not zero or not wanted:
        return []
    first = replace(motion, times=motion.times[:1], x=motion.x[:, :1], u=motion.u[:, :1],
                    navigation={}, kept={})
    base_f, base_g = _derived_in_convention(model, conv, first)
    found = []
    for k in zero:
        probe = p.copy()
        probe[..., k] = 1.0
        f, g = _derived_in_convention(model, conv, replace(first, p=probe, kept={}))
        if (np.any(f[:, wanted] != base_f[:, wanted])
                or np.any(g[:, wanted] != base_g[:, wanted])):
            found.append(model.parameters[k].name)
    return found


# --------------------------------------------------------------------------------------
# Derived model in the convention
# --------------------------------------------------------------------------------------
def derived_in_convention(model, conv: Convention, motion: Motion
                          ) -> tuple[np.ndarray, np.ndarray]:
    """The derived F and G carried into ``conv``: shapes (K, nz, nz) and (K, nz, nw).

    Kept on the motion for the next check of the same model in the same convention
    (read-only arrays).
    """
    key = ("derived", model.key, conv.name, conv.biases)
    if key not in motion.kept:
        F, G = (_with_bias_states(model, conv, *derived_in_convention(model, conv.base, motion))
                if conv.biases else _derived_in_convention(model, conv, motion))
        F.setflags(write=False)
        G.setflags(write=False)
        motion.kept[key] = (F, G)
    return motion.kept[key]


def _with_bias_states(model, conv: Convention, F: np.ndarray, G: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """The derived model with ``conv.biases`` as states: ``[[F, G[:, b]], [0, D]]``.

    Parameters
    ----------
    conv : Convention
        With bias states (:meth:`~ins_errors.checker.conventions.Convention.with_biases`).
    F, G : ndarray, shapes (K, nz, nz) and (K, nz, nw)
        The derived model in ``conv.base``.

    Returns
    -------
    F, G : ndarray, shapes (K, nz + nb, nz + nb) and (K, nz + nb, nw)
        A bias state's column of F is its source's column of G, its row is ``ḃ = D b``
        (D = 0 for a random constant, −1/τ for a Gauss–Markov bias); its source's column
        of G is zero (the source enters through the state, not as an input).
    """
    src_names = [s.name for s in model.sources]
    columns = [src_names.index(b.name) for b in conv.biases]
    k, nz, nw = G.shape
    nb = len(columns)
    Fa = np.zeros((k, nz + nb, nz + nb))
    Fa[:, :nz, :nz] = F
    Fa[:, :nz, nz:] = G[:, :, columns]
    Fa[:, np.arange(nz, nz + nb), np.arange(nz, nz + nb)] = [b.rate for b in conv.biases]
    Ga = np.zeros((k, nz + nb, nw))
    Ga[:, :nz, :] = G
    Ga[:, :, columns] = 0.0
    return Fa, Ga


def _derived_in_convention(model, conv: Convention, motion: Motion
                           ) -> tuple[np.ndarray, np.ndarray]:
    F = np.moveaxis(model.state_matrix(motion.x, motion.u, motion.p), -1, 0)
    G = np.moveaxis(model.source_matrix(motion.x, motion.u, motion.p), -1, 0)
    if conv.transform is None:
        return F, G
    T, T_dot = conv.matrices(model, motion.x, motion.p, motion.u)
    if conv.lift is not None:  # onto the model's own state manifold (T L = I)
        Fz = (T_dot + T @ F) @ np.moveaxis(conv.lift(motion.x, motion.p), -1, 0)
    elif T.shape[1] == T.shape[2]:
        Fz = np.swapaxes(np.linalg.solve(np.swapaxes(T, 1, 2),
                                         np.swapaxes(T_dot + T @ F, 1, 2)), 1, 2)
    else:  # a direction of x_e the convention does not see (quaternion norm): T⁺
        Fz = (T_dot + T @ F) @ np.linalg.pinv(T)
    return Fz, T @ G
