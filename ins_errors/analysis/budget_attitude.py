"""The attitude errors a budget reads: platform angles, or a strapdown INS's φ-angle.

A platform INS's vertical error and heading drift are its platform error angles (the
models name them ``alpha_x/y/z`` or ``alpha_E/N/U``); a strapdown INS (``strapdown_ned``,
or a model file that describes itself, :mod:`~ins_errors.checker.strapdown_description`)
has none, and its attitude error is read as the φ-angle (north, east, down) of the
variation of its body-to-navigation matrix: rows T_φ applied to its error states in the
covariance (:func:`attitude_rows`) and to real − ideal in the direct runs
(:func:`direct_attitude`).
"""

from __future__ import annotations

import numpy as np

from ins_errors.analysis.covariance import LinearSystem

PLATFORM_ANGLE_NAMES = (("alpha_x", "alpha_y", "alpha_z"), ("alpha_E", "alpha_N", "alpha_U"))
"""Names the models give their two level and one azimuth platform error angles."""


def platform_angles(model) -> tuple[str, str, str]:
    """The model's (level, level, azimuth) platform error-angle names."""
    states = {s.name for s in model.error_states}
    for names in PLATFORM_ANGLE_NAMES:
        if set(names) <= states:
            return names
    from ins_errors.analysis.budget import BudgetError

    raise BudgetError(f"model {model.name} has no platform error angles named like "
                      f"{', '.join(PLATFORM_ANGLE_NAMES[0])}")


def has_attitude(model) -> bool:
    """True when the model's attitude error can be read: platform error angles
    (:data:`PLATFORM_ANGLE_NAMES`), or a strapdown INS's φ-angle."""
    from ins_errors.checker.strapdown_description import is_strapdown

    states = {s.name for s in model.error_states}
    return any(set(names) <= states for names in PLATFORM_ANGLE_NAMES) or is_strapdown(model)


def _reads_phi(model) -> bool:
    """True when the attitude error is a strapdown INS's φ-angle (no platform angles)."""
    from ins_errors.checker.strapdown_description import is_strapdown

    states = {s.name for s in model.error_states}
    return is_strapdown(model) and not any(set(names) <= states
                                           for names in PLATFORM_ANGLE_NAMES)


PHI_AXES = ("north", "east", "down")
"""Components of a strapdown INS's φ-angle, in the order of its rows."""


def phi_rows(model, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """A strapdown INS's φ-angle rows ``T_φ(x)`` along ideal states ``x``.

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
        A strapdown INS with the φ-angle convention (``strapdown_ned``, or a model file
        that describes itself by its outputs).
    x : numpy.ndarray, shape (n, K)
        Ideal states.
    p : numpy.ndarray, shape (np,)
        Parameters.

    Returns
    -------
    numpy.ndarray, shape (3, K, ne)
        North, east and down φ (rad) per SI unit of each error state at each of the K
        states: φ = T_φ(x) δx, exact to first order.
    """
    from ins_errors.checker.conventions import conventions

    T = conventions(model)["phi"].transform(np.ascontiguousarray(x), p)
    return np.stack([np.asarray(T[k]).T for k in range(len(PHI_AXES))])


def attitude_rows(model, system: LinearSystem) -> list[tuple[str, np.ndarray]]:
    """(label, row) of the level, level and azimuth attitude errors, rad: rows (K+1, n)
    of the error state, the platform angles' unit rows, or a strapdown INS's φ-angle
    rows ``T_φ(x)`` along the ideal states (exact to first order, :func:`phi_rows`)."""
    K1, n = len(system.times), system.F.shape[-1]
    states = [s.name for s in model.error_states]
    if not _reads_phi(model):
        rows = []
        for name in platform_angles(model):
            row = np.zeros((K1, n))
            row[:, states.index(name)] = 1.0
            rows.append((f"about {name[6:]}", row))
        return rows
    from ins_errors.checker.conventions import conventions

    x = np.broadcast_to(system.x, (system.x.shape[0], K1))
    phi = conventions(model)["phi"]
    if phi.validate is not None:  # a strapdown model file the φ-angle can carry
        phi.validate(model, np.ascontiguousarray(x), np.ascontiguousarray(
            np.broadcast_to(system.u, (system.u.shape[0], K1))), system.p)
    T = phi_rows(model, x, system.p)
    return [(f"about {axis}", T[k]) for k, axis in enumerate(PHI_AXES)]


PHI_QUANTITIES = tuple(f"phi_{axis}" for axis in "NED")
"""Names of a strapdown INS's φ-angle among the error quantities of its direct runs
(:func:`direct_attitude`)."""


def direct_attitude(model, ideal: np.ndarray, real: np.ndarray, p: np.ndarray
                    ) -> tuple[tuple[str, ...], np.ndarray]:
    """The attitude error of direct runs for the budget's attitude items, beyond the
    quantities every run reports: a strapdown INS's φ-angle (:data:`PHI_QUANTITIES`),
    the same rows as the covariance's (:func:`attitude_rows`) applied to the runs'
    error state ``δx = x_real − x_ideal`` along their own ideal states; nothing for a
    model with platform angles (reported by every run already).

    Parameters
    ----------
    model : ins_errors.numeric.model.Model
    ideal : numpy.ndarray, shape (n, R + 1, B)
        Ideal states at the recorded samples (the same motion for every draw).
    real : numpy.ndarray, shape (ne, R + 1, B)
        Real-work states (computed states, then the platform angles if any).
    p : numpy.ndarray, shape (np,)
        Parameters of the runs.

    Returns
    -------
    names : tuple of str
    values : numpy.ndarray, shape (len(names), R + 1, B)
        rad.
    """
    if not _reads_phi(model):
        return (), np.zeros((0, *ideal.shape[1:]))
    n = ideal.shape[0]
    error = np.concatenate([real[:n] - ideal, real[n:]])   # (ne, R + 1, B)
    T = phi_rows(model, ideal[:, :, 0], p)                 # (3, R + 1, ne)
    return PHI_QUANTITIES, np.einsum("kte,etb->ktb", T, error)


def attitude_quantities(model) -> tuple[str, str, str]:
    """The direct runs' error quantities of the level, level and azimuth attitude
    errors, in the order of :func:`attitude_rows` (whose labels are ``about`` and each
    name's axis): the platform angles, or a strapdown INS's φ-angle."""
    return PHI_QUANTITIES if _reads_phi(model) else platform_angles(model)


def attitude_label(model, name: str) -> str:
    """The row label (``"about x"``, ``"about north"``) of attitude quantity ``name``."""
    if name in PHI_QUANTITIES:
        return f"about {PHI_AXES[PHI_QUANTITIES.index(name)]}"
    return f"about {name[6:]}"
