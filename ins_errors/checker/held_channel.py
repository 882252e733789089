"""The vertical channel held in the effect propagation of a matrix check, for states that
have no vertical-channel state of their own.

The effect propagation (:mod:`~ins_errors.checker.matrix_effects`) holds the undamped
vertical channel (×e every 9.5 min: after a day it would swamp every other difference).
A convention that names its vertical states (``dv_D``, ``dr_D``) has them held by index:
their rows and columns are zeroed. Two kinds of states mix the vertical channel into
several states instead, and are held here, through one operator pair per motion
(:class:`Hold`): the propagated ``A`` becomes ``P A P + D`` (``P`` the states' projector
off the vertical channel, ``D`` what keeps the error off it as ``P`` turns along the
motion):

* **Earth-fixed states** (``psi_ecef``: ψ^e, δv^e, δr^e), a convention with a
  :attr:`~ins_errors.checker.conventions.Convention.hold`: ``P = Q = T⁻¹ P_l T`` and
  ``D = c = T⁻¹ (P_l W P_l − W) T`` (``T`` the map to the ψ-angle states, ``P_l`` zeroing
  dvc_D and dr_D, ``W = Ṫ T⁻¹``), which is exactly the held propagation of the ψ-angle
  convention read back in the Earth-fixed states. The cases start from the hand's own
  initial errors as they are (``initial dv_X``: its vertical part is held at its start).
* **A strapdown model's own states** (``model``: a quaternion, a direction-cosine matrix,
  C_b^e, v^e, r^e), a convention with a
  :attr:`~ins_errors.checker.conventions.Convention.frame`: ``P = I − W (V W)⁺ V`` (``V``
  the frame's ``dv_D`` and ``dr_D`` rows, ``W`` their lift) and ``D = Ṗ P``
  (:func:`vertical_projector`); the cases start from ``P x``: the φ-angle propagation
  with ``dv_D`` and ``dr_D`` held.

Everything else (the cases, the readouts, the effect of each finding alone, what is not
assessed) is the propagation of :mod:`~ins_errors.checker.matrix_effects`, the same for
every convention: a finding's entry is replaced in the derived model first and the
result is held after (holding first would spread the change over other entries).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ins_errors.checker.check_motions import Motion
from ins_errors.checker.conventions import Convention

HELD_THROUGH_FRAME = ("the down velocity and position of the states (dv_D, dr_D of the phi "
                      "convention)")
"""What the report names as held for a model's own states held through its φ-angle
frame (:func:`vertical_projector`)."""


@dataclass(frozen=True)
class Hold:
    """The vertical channel held through operators on one motion: the propagated
    ``A`` becomes ``P A P + D``.

    Attributes
    ----------
    P : numpy.ndarray, shape (K, n, n)
        Projector of the states propagated off the vertical channel, at each sample;
        the sources after the states (in an augmented ``A``) are not touched.
    D : numpy.ndarray, shape (K, n, n)
        What keeps the error off the vertical channel as ``P`` turns along the motion,
        1/s (``Ṗ P``, or the Earth-fixed hold's ``c``).
    project_start : bool
        Whether a propagation starts from ``P x`` (the vertical part of an initial error
        taken out) instead of ``x`` (held at its start).
    """

    P: np.ndarray
    D: np.ndarray
    project_start: bool

    def _padded(self, size: int) -> tuple[np.ndarray, np.ndarray]:
        k, n, _ = self.P.shape
        P, D = np.zeros((k, size, size)), np.zeros((k, size, size))
        P[:] = np.eye(size)
        P[:, :n, :n], D[:, :n, :n] = self.P, self.D
        return P, D

    def held(self, A: np.ndarray) -> np.ndarray:
        """``P A P + D`` of an augmented ``A`` (K, n + m, n + m; the states first), SI."""
        P, D = self._padded(A.shape[-1])
        return P @ A @ P + D

    def held_states(self, F: np.ndarray) -> np.ndarray:
        """``P F P + D`` of the states' own ``F`` (K, n, n), SI."""
        return self.P @ F @ self.P + self.D

    def start(self, scale: np.ndarray) -> np.ndarray | None:
        """What a propagation of :meth:`held` in scaled variables (``scale``: every
        state's and source's magnitude) starts from: ``P`` at the first sample, scaled;
        None where it starts from the cases as they are."""
        if not self.project_start:
            return None
        P, _ = self._padded(scale.size)
        return P[0] * (1 / scale)[:, None] * scale[None, :]


def holds(conv: Convention) -> bool:
    """Whether ``conv``'s vertical channel is held here (through operators), not by
    the index of vertical states it names."""
    return conv.hold is not None or (conv.frame is not None and not conv.vertical)


def held_text(conv: Convention) -> str:
    """What the reports name as held for a convention :func:`holds` holds."""
    return conv.hold_text if conv.hold is not None else HELD_THROUGH_FRAME


def not_holdable(states: list[str], conv: Convention) -> str | None:
    """Why the vertical channel of a hand model in ``states`` cannot be held, or None.

    An Earth-fixed hold mixes the members of each triple of the convention's own states
    (``dv_X``, ``dv_Y``, ``dv_Z``): a hand model with part of a triple cannot be held
    so, and gets no effects (they would be swamped by the vertical channel).
    """
    if conv.hold is None:
        return None
    present = [name in states for name in conv.base.names]
    for start in range(0, len(present), 3):
        block = present[start:start + 3]
        if any(block) and not all(block):
            return (f"effects not propagated: the hand's states hold part of a triple of "
                    f"{conv.name} ({conv.hold_text} cannot be held)")
    return None


def hold_on(conv: Convention, motion: Motion, rows: list[int], model) -> Hold | None:
    """The :class:`Hold` of the convention states ``rows`` on ``motion``; None for a
    convention that names its vertical states (held by index) or has no frame."""
    if conv.hold is not None:
        return _earth_fixed(conv, motion, rows)
    return vertical_projector(conv, motion, rows, model)


def _earth_fixed(conv: Convention, motion: Motion, rows: list[int]) -> Hold:
    """``Q`` and ``c`` of :attr:`~ins_errors.checker.conventions.Convention.hold` on
    ``motion``, restricted to the convention states ``rows`` (bias states: identity and
    zero)."""
    Q9, c9 = conv.hold(motion.navigation)
    k, n, n_base = Q9.shape[0], len(conv.names), Q9.shape[1]
    Q, c = np.zeros((k, n, n)), np.zeros((k, n, n))
    Q[:, :n_base, :n_base], c[:, :n_base, :n_base] = Q9, c9
    Q[:, n_base:, n_base:] = np.eye(n - n_base)
    return Hold(Q[:, rows][:, :, rows], c[:, rows][:, :, rows], project_start=False)


def vertical_projector(conv: Convention, motion: Motion, rows: list[int], model
                       ) -> Hold | None:
    """The vertical channel of a model's own states, held through
    :attr:`~ins_errors.checker.conventions.Convention.frame`.

    A state vector ``x`` of the convention's states ``rows`` has a down velocity and a
    down position ``V x`` (``V`` the rows ``dv_D``, ``dr_D`` of the frame's ``T``); its
    vertical part is ``W (V W)⁺ V x``, ``W`` the lift of those two (the model error state
    of a unit ``dv_D`` or ``dr_D``). ``P = I − W (V W)⁺ V`` takes it out. Propagating
    ``y' = (P A P + Ṗ P) y`` from ``P x`` is, where ``x`` spans the frame, exactly the
    propagation of the φ-angle states with ``dv_D`` and ``dr_D`` held (their rows and
    columns zeroed): the vertical channel neither grows (undamped, ×e every 9.5 min)
    nor feeds the rest. ``Ṗ`` along the ideal flow by central differences (Richardson
    extrapolated, the step of :data:`~ins_errors.checker.conventions.RATE_STEP`).

    Returns
    -------
    Hold or None
        None for a convention that names its vertical states (they are held by index)
        or has no frame.
    """
    from ins_errors.checker.conventions import RATE_STEP

    if conv.frame is None or conv.vertical:
        return None
    x, p = motion.x, motion.p
    flow = np.asarray(model.numpy.ideal_rhs(x, motion.u, p), dtype=float)
    n_base = len(conv.base.states)

    def projector(shift: float) -> np.ndarray:
        T, L = conv.frame(x + shift * flow, p)
        V = np.zeros((x.shape[-1], 2, len(rows)))
        W = np.zeros((x.shape[-1], len(rows), 2))
        for j, r in enumerate(rows):
            if r < n_base:  # a bias state has no vertical part
                V[:, :, j] = np.moveaxis(T[[5, 8], r], -1, 0)
                W[:, j, :] = np.moveaxis(L[r, [5, 8]], -1, 0)
        return np.eye(len(rows)) - W @ np.linalg.pinv(V @ W) @ V

    def central(step: float) -> np.ndarray:
        return (projector(step) - projector(-step)) / (2 * step)

    P = projector(0.0)
    P_dot = (4 * central(RATE_STEP / 2) - central(RATE_STEP)) / 3
    return Hold(P, P_dot @ P, project_start=True)
