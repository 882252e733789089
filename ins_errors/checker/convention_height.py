r"""``@neglect h`` in a ``@convention`` file: the height held at 0 on both sides.

As in a file of the model's own equations (docs/hand_check.md, *Neglecting a
quantity*), the part of an entry's difference (hand − derived) that vanishes with the
height at 0 on both sides is a declared drop: the file's rows are evaluated along each
motion as written and with the named quantities at h = 0, the derived model along the
motion and along its copy with the model's height state at 0 (:func:`at_zero_height`);
the difference of the two differences is the declared term of the entry
(:func:`height_terms`), which :func:`~ins_errors.checker.matrix.check_matrices` compares
as any declared term.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ins_errors.errors import InsErrorsError


def held_heights(hand, definitions: dict) -> list[tuple[int, int, str]]:
    """The ``@neglect h`` items of a ``@convention`` file: (declaration index, line,
    item text) of each item that is the height ``h`` (not a definition of the file's):
    the height held at 0 from that line on, on both sides (:func:`at_zero_height`), as
    in a file of the model's own equations (docs/hand_check.md, *Neglecting a
    quantity*)."""
    if "h" in definitions:
        return []
    return [(k, d.line, text) for k, d in enumerate(hand.declarations)
            for item, text in zip(d.items, d.texts, strict=True) if item == sp.Symbol("h")]


AT_ZERO_HEIGHT = ("at zero height",)
"""Key of :attr:`~ins_errors.checker.check_motions.Motion.kept` under which a motion keeps
its copy at zero height (:func:`at_zero_height`)."""


def at_zero_height(model, motion, where: str):
    """``motion`` with the height held at 0: the model's state (or input) that is the
    navigation height set to 0 at every sample, the navigation (ω_en, gravity, ...)
    computed again from it; the other states and inputs as they are. The derived model
    along it is the model with h = 0 (its R + h is R), as the plain check's ``@neglect
    h`` holds h at 0 on the model's side. Kept on the motion for the next check.

    Raises
    ------
    InsErrorsError
        The model's height is no single state or input (``where``: the ``@neglect``
        line, for the message).
    """
    from ins_errors.checker.check_motions import Motion
    from ins_errors.checker.navigation import navigation_arrays

    if AT_ZERO_HEIGHT in motion.kept:
        return motion.kept[AT_ZERO_HEIGHT]
    height = np.asarray(motion.navigation["height"], dtype=float)
    if not np.any(height):
        motion.kept[AT_ZERO_HEIGHT] = motion
        return motion
    found = [(which, k) for which, array in (("x", motion.x), ("u", motion.u))
             for k in range(np.shape(array)[0])
             if np.allclose(array[k], height, rtol=1e-12, atol=1e-9)]
    level = None
    if len(found) == 1:
        which, k = found[0]
        x, u = np.array(motion.x, dtype=float), np.array(motion.u, dtype=float)
        (x if which == "x" else u)[k] = 0.0
        navigation = navigation_arrays(model, x, u, motion.p)
        if np.allclose(navigation["height"], 0.0, atol=1e-9):
            level = Motion(motion.label, motion.description, motion.times, x, u, motion.p,
                           navigation)
    if level is None:
        raise InsErrorsError(
            f"{where}: the height of model {model.name!r} is not one of its states or "
            "inputs, so it cannot be held at 0 along the motions; write R + h (R_N + h, "
            "R_E + h) as the model has it, or leave the approximation to the findings (a "
            "dropped small term below the threshold)")
    motion.kept[AT_ZERO_HEIGHT] = level
    return level


def height_terms(terms: dict, label: str, row: str, states: list[str],
                  used: list[str], dF: np.ndarray, dG: np.ndarray) -> None:
    """Add to ``terms`` ((matrix, row, column) -> {motion label: values}) the part of each
    entry's difference (hand − derived) of ``row`` along one motion that vanishes with the
    height held at 0 on both sides, as the plain check's ``@neglect h`` declares it:
    ``dF``, ``dG`` (shapes (K, n) and (K, len(used))) are that difference less the same
    difference at h = 0."""
    for j, column in enumerate(states):
        terms.setdefault(("F", row, column), {})[label] = dF[:, j]
    for j, column in enumerate(used):
        terms.setdefault(("G", row, column), {})[label] = dG[:, j]
