"""Size of every term of the error equations along a trajectory.

A hand derivation keeps some terms and drops others. Which may be dropped depends on
how big each term is along the motion of interest: this module evaluates every linear
term ``F_ij xe_j`` and ``G_ik w_k`` of each error equation, plus the whole second-order
term, along sampled trajectories, and ranks them against the largest term of the same
equation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ins_errors.numeric.model import Model


@dataclass(frozen=True)
class TermSize:
    """How big one term of one error equation gets along a trajectory.

    Attributes
    ----------
    equation : str
        Error-state name whose derivative the term belongs to.
    term : str
        ``"F[alpha_x]"`` (state term), ``"G[gyro_drift_x]"`` (source term) or
        ``"second order"`` (the whole quadratic remainder).
    peak : float
        Largest absolute value along the trajectory, in the equation's unit per second.
    relative : float
        ``peak`` divided by the largest ``peak`` of that equation's linear terms.
    """

    equation: str
    term: str
    peak: float
    relative: float


def term_sizes(model: Model, x: np.ndarray, u: np.ndarray, xe: np.ndarray, w: np.ndarray,
               p: np.ndarray | None = None) -> list[TermSize]:
    """Rank the terms of every error equation along a trajectory.

    Parameters
    ----------
    model : Model
        Loaded model.
    x : numpy.ndarray, shape (n, N)
        True states along the trajectory.
    u : numpy.ndarray, shape (m, N)
        Inputs along the trajectory.
    xe : numpy.ndarray, shape (ne, N)
        Error states along the trajectory (from a linear or direct run).
    w : numpy.ndarray, shape (nw,)
        Error-source magnitudes, SI.
    p : numpy.ndarray, shape (np,), optional
        Parameters; the model's defaults when omitted.

    Returns
    -------
    list of TermSize
        Every nonzero term, grouped by equation, largest first within each equation.
    """
    p = model.parameter_vector() if p is None else np.asarray(p, float)
    x, u, xe = (np.atleast_2d(np.asarray(a, float)) for a in (x, u, xe))
    w = np.asarray(w, float)
    # validate once on the whole trajectory (domain, shapes, NaN)
    F = model.state_matrix(x, u, p)               # (ne, ne, N)
    G = model.source_matrix(x, u, p)              # (ne, nw, N)
    S = model.second_order(x, u, xe, w[:, None], p)  # (ne, N)
    state_terms = np.abs(F * xe[None, :, :]).max(axis=2)    # (ne, ne)
    source_terms = np.abs(G * w[None, :, None]).max(axis=2)  # (ne, nw)
    second = np.abs(S).max(axis=1)
    sizes: list[TermSize] = []
    for i, equation in enumerate(model.error_states):
        rows = [(f"F[{s.name}]", state_terms[i, j]) for j, s in enumerate(model.error_states)]
        rows += [(f"G[{s.name}]", source_terms[i, k]) for k, s in enumerate(model.sources)]
        largest = max((value for _, value in rows), default=0.0) or 1.0
        rows.append(("second order", second[i]))
        for label, value in sorted(rows, key=lambda r: -r[1]):
            if value > 0:
                sizes.append(TermSize(equation.name, label, float(value), float(value / largest)))
    return sizes


def droppable_terms(sizes: list[TermSize], threshold: float = 1e-3) -> list[TermSize]:
    """The terms smaller than ``threshold`` times the largest term of their equation."""
    return [s for s in sizes if s.relative < threshold]
