"""State conventions a hand-coded error model may be written in.

A researcher's F is written in *their* error states (ψ-angles instead of platform angles,
position in metres instead of latitude...). A :class:`Convention` is a linear change of
error states ``z = T(x, p) x_e`` from the model's own error states ``x_e`` at the ideal
state ``x``; it carries the derived linear model into the researcher's states exactly:

    ż = (Ṫ + T F) T⁻¹ z + T G w,

``Ṫ`` being the derivative of ``T`` along the ideal motion (computed here by central
differences along the model's own ideal flow, with Richardson extrapolation; ``T`` must
depend on the state and parameters only). A convention also reads position (NED metres)
and attitude (rad) errors out of its states, for the propagation report.

Every model has the convention ``model`` (its own error states, ``T = I``). Models add
theirs in :data:`REGISTRY`. The names of a convention's states are its *vocabulary*: a
hand-coded model lists its states (any subset, any order) from it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ins_errors.errors import InsErrorsError, unknown_name


@dataclass(frozen=True)
class State:
    """One error state of a convention.

    Attributes
    ----------
    name : str
        Vocabulary name (what a hand model lists).
    unit : str
        SI unit.
    description : str
        Meaning.
    """

    name: str
    unit: str
    description: str


Readout = Callable[[dict[str, np.ndarray]], np.ndarray]
"""Navigation arrays (trailing axis K) -> matrix (3, nz, K)."""


@dataclass(frozen=True)
class Convention:
    """A set of error states related linearly to a model's own error states.

    Attributes
    ----------
    name : str
        Name given to ``--convention``.
    description : str
        One line.
    states : tuple of State
        The vocabulary, in the order of ``T``'s rows.
    transform : callable or None
        ``(x, p) -> T`` with ``x`` shape (n, K), ``T`` shape (nz, ne, K); ``None`` means
        the identity (the model's own states).
    position : callable
        Navigation arrays -> (3, nz, K): north, east, down position error in metres per
        unit of each state.
    attitude : callable
        Navigation arrays -> (3, nz, K): attitude error about north, east, down (rad) per
        unit of each state (the angle the convention calls attitude error).
    """

    name: str
    description: str
    states: tuple[State, ...]
    transform: Callable[[np.ndarray, np.ndarray], np.ndarray] | None
    position: Readout
    attitude: Readout

    @property
    def names(self) -> list[str]:
        """State names, in order."""
        return [s.name for s in self.states]

    def matrices(self, model, x: np.ndarray, p: np.ndarray, u: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
        """``T`` and ``Ṫ`` along states ``x`` (n, K) with inputs ``u`` (nu, K).

        Returns
        -------
        T, T_dot : numpy.ndarray, shape (K, nz, ne)
        """
        k = x.shape[-1]
        ne = len(model.error_states)
        if self.transform is None:
            eye = np.broadcast_to(np.eye(ne), (k, ne, ne))
            return eye, np.zeros((k, ne, ne))
        flow = model.numpy.ideal_rhs(x, u, p)

        def at(shift: float) -> np.ndarray:
            return np.moveaxis(self.transform(x + shift * flow, p), -1, 0)

        def central(step: float) -> np.ndarray:
            return (at(step) - at(-step)) / (2 * step)

        step = RATE_STEP
        rate = (4 * central(step / 2) - central(step)) / 3
        return at(0.0), rate


RATE_STEP = 0.02
"""Time step of the central differences giving Ṫ, s (Richardson-extrapolated: O(step⁴))."""


# --------------------------------------------------------------------------------------
# Readouts shared by the platform conventions of the north-pointing model
# --------------------------------------------------------------------------------------
def _north_pointing_position(nav: dict[str, np.ndarray]) -> np.ndarray:
    """δN = (R_N + h) δφ, δE = (R_E + h) cos φ δλ (states 2 and 3)."""
    k = nav["latitude"].shape[-1]
    out = np.zeros((3, 7, k))
    out[0, 2] = nav["R_N"] + nav["height"]
    out[1, 3] = (nav["R_E"] + nav["height"]) * np.cos(nav["latitude"])
    return out


def _north_pointing_attitude(nav: dict[str, np.ndarray]) -> np.ndarray:
    """Angles about (E, N, U) in states 4..6 -> (N, E, D)."""
    k = nav["latitude"].shape[-1]
    out = np.zeros((3, 7, k))
    out[0, 5], out[1, 4], out[2, 6] = 1.0, 1.0, -1.0
    return out


def _north_pointing_psi(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """ψ = α − δθ, δθ = (−δφ, δλ cos φ, δλ sin φ) about (E, N, U): the angle from the
    computer frame (geographic frame at the computed position) to the platform."""
    lat = x[2]
    k = lat.shape[-1]
    T = np.repeat(np.eye(7)[:, :, None], k, axis=2)
    T[4, 2] = 1.0
    T[5, 3] = -np.cos(lat)
    T[6, 3] = -np.sin(lat)
    return T


_NP_COMMON = (
    State("delta_v_E", "m/s", "east velocity error"),
    State("delta_v_N", "m/s", "north velocity error"),
    State("delta_latitude", "rad", "latitude error"),
    State("delta_longitude", "rad", "longitude error"),
)

REGISTRY: dict[str, dict[str, Convention]] = {
    "north_pointing": {
        "psi": Convention(
            "psi", "ψ-angle: platform attitude relative to the computer frame (Benson 1975)",
            (*_NP_COMMON,
             State("psi_E", "rad", "ψ-angle about east (platform vs computer frame)"),
             State("psi_N", "rad", "ψ-angle about north"),
             State("psi_U", "rad", "ψ-angle about up")),
            _north_pointing_psi, _north_pointing_position, _north_pointing_attitude),
    },
}
"""Conventions of each model beyond its own states (``model``)."""

_MODEL_READOUTS: dict[str, tuple[Readout, Readout]] = {
    "north_pointing": (_north_pointing_position, _north_pointing_attitude),
}


def own_convention(model) -> Convention:
    """The model's own error states as a convention (``T = I``)."""
    if model.name not in _MODEL_READOUTS:
        raise InsErrorsError(f"model {model.name!r} has no position/attitude readout for "
                             "hand-coded matrices")
    position, attitude = _MODEL_READOUTS[model.name]
    states = tuple(State(s.name, s.unit, s.description) for s in model.error_states)
    return Convention("model", f"the model's own error states ({model.name})", states,
                      None, position, attitude)


def conventions(model) -> dict[str, Convention]:
    """Every convention of ``model``, by name (``model`` first)."""
    return {"model": own_convention(model), **REGISTRY.get(model.name, {})}


def convention(model, name: str) -> Convention:
    """The convention ``name`` of ``model``.

    Raises
    ------
    UnknownNameError
        For a name the model does not have (close names are suggested).
    """
    known = conventions(model)
    if name not in known:
        raise unknown_name(f"convention of {model.name}", name, known)
    return known[name]
