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
from dataclasses import dataclass, replace

import numpy as np

from ins_errors.errors import unknown_name


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


@dataclass(frozen=True)
class BiasState:
    """A model error source carried as a state of the hand model (a *bias state*).

    A filter's 15-state F has the gyro and accelerometer biases as states: their columns
    hold what the model's G holds for those sources, their rows the bias's own dynamics,
    ``ḃ = D b``: zero for a random constant, ``−1/τ`` for a first-order Gauss–Markov
    bias of correlation time τ.

    Attributes
    ----------
    name : str
        The model's error-source name (``gyro_bias_x``).
    unit : str
        Its SI unit.
    description : str
        Its meaning.
    tau : float or None
        Correlation time of a first-order Gauss–Markov bias, s; None for a random
        constant.
    """

    name: str
    unit: str
    description: str
    tau: float | None = None

    @property
    def rate(self) -> float:
        """D, the bias's own rate: 0 (constant) or −1/τ (Gauss–Markov), 1/s."""
        return 0.0 if self.tau is None else -1.0 / self.tau

    @property
    def statistics(self) -> str:
        """``random constant`` or ``Gauss–Markov, τ = 3600 s``."""
        return ("random constant" if self.tau is None
                else f"Gauss–Markov, τ = {self.tau:.6g} s")


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
        the identity (the model's own states). ``T`` may have fewer rows than columns
        when the model's error state has a direction the convention does not see (the
        norm of an attitude quaternion): then ``T⁺`` (pseudo-inverse) replaces ``T⁻¹``.
    rate : callable or None
        ``(x, xdot, p) -> Ṫ`` (same shape; ``xdot`` the ideal flow, shape (n, K)) when the
        convention gives it exactly; otherwise it is computed by central differences
        along the ideal flow.
    vertical : tuple of str
        States of the vertical channel (held in the effect propagation: undamped, it
        diverges with a time constant of about 9.5 min).
    lift : callable or None
        ``(x, p) -> L``, shape (ne, nz, K), with ``T L = I``: the model error state of a
        convention state, on the model's own state manifold. Given, it replaces ``T⁺``
        (a direction-cosine matrix has six directions the convention does not see, and
        the model's equations keep its errors off them: see
        :mod:`ins_errors.checker.strapdown_description`).
    validate : callable or None
        ``(model, x, u, p) -> None``: raises one line when the convention cannot carry
        the model along states ``x`` (n, K) (called by :meth:`matrices`).
    biases : tuple of BiasState
        Error sources carried as states after the convention's own (:meth:`with_biases`):
        the last ``len(biases)`` entries of ``states``. The derived model in the
        augmented states is ``[[F_c, G_c[:, b]], [0, D]]``, and those sources have no
        column of G (:func:`ins_errors.checker.matrix.derived_in_convention`).
    """

    name: str
    description: str
    states: tuple[State, ...]
    transform: Callable[[np.ndarray, np.ndarray], np.ndarray] | None
    rate: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = None
    vertical: tuple[str, ...] = ()
    lift: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
    validate: Callable | None = None
    biases: tuple[BiasState, ...] = ()

    @property
    def names(self) -> list[str]:
        """State names, in order."""
        return [s.name for s in self.states]

    def with_biases(self, biases: tuple[BiasState, ...]) -> Convention:
        """This convention with ``biases`` as further states (after its own)."""
        base = self.base
        return replace(base, states=base.states + tuple(State(b.name, b.unit, b.description)
                                                        for b in biases),
                       biases=tuple(biases))

    @property
    def base(self) -> Convention:
        """The convention without bias states."""
        if not self.biases:
            return self
        return replace(self, states=self.states[:len(self.states) - len(self.biases)],
                       biases=())

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
        if self.validate is not None:
            self.validate(model, x, u, p)
        flow = model.numpy.ideal_rhs(x, u, p)
        if self.rate is not None:
            return (np.moveaxis(self.transform(x, p), -1, 0),
                    np.moveaxis(self.rate(x, flow, p), -1, 0))

        def at(shift: float) -> np.ndarray:
            return np.moveaxis(self.transform(x + shift * flow, p), -1, 0)

        def central(step: float) -> np.ndarray:
            return (at(step) - at(-step)) / (2 * step)

        step = RATE_STEP
        rate = (4 * central(step / 2) - central(step)) / 3
        return at(0.0), rate

    def position(self, nav: dict[str, np.ndarray]) -> np.ndarray:
        """(3, nz, K): north, east, down position error (m) per unit of each state."""
        return _readout(self.names, nav, _POSITION)

    def attitude(self, nav: dict[str, np.ndarray]) -> np.ndarray:
        """(3, nz, K): attitude error about north, east, down (rad) per unit of each state.

        The attitude error is that of the computed attitude relative to the true NED
        frame (the φ-angle, or the platform angles α); for a ψ-angle convention it is
        ψ + δθ, δθ = (δλ cos φ, −δφ, −δλ sin φ) the rotation of the computed frame.
        """
        out = _readout(self.names, nav, _ATTITUDE)
        if any(n.startswith("psi_") for n in self.names):
            out += _readout(self.names, nav, _THETA)
        return out


RATE_STEP = 0.02
"""Time step of the central differences giving Ṫ, s (Richardson-extrapolated: O(step⁴))."""


# --------------------------------------------------------------------------------------
# Position and attitude read out of state names
# --------------------------------------------------------------------------------------
def _r_n(nav):
    return nav["R_N"] + nav["height"]


def _r_e_cos(nav):
    return (nav["R_E"] + nav["height"]) * np.cos(nav["latitude"])


def _one(nav):
    return np.ones_like(nav["latitude"])


def _minus_one(nav):
    return -np.ones_like(nav["latitude"])


_POSITION = {
    # name: [(axis N=0 E=1 D=2, metres per unit of the state)]
    "delta_latitude": [(0, _r_n)], "dlat": [(0, _r_n)], "delta_lat": [(0, _r_n)],
    "delta_longitude": [(1, _r_e_cos)], "dlon": [(1, _r_e_cos)], "delta_lon": [(1, _r_e_cos)],
    "dh": [(2, _minus_one)], "delta_h": [(2, _minus_one)],
    "dr_N": [(0, _one)], "dr_E": [(1, _one)], "dr_D": [(2, _one)],
}
_ATTITUDE = {
    # name: [(axis, rad per unit)]; the platform angles α and north_pointing's ψ are ENU
    **{f"{a}_{axis}": [(k, _one)] for a in ("phi", "psi") for k, axis in enumerate("NED")},
    "psi_U": [(2, _minus_one)], "alpha_U": [(2, _minus_one)],
    "alpha_E": [(1, _one)], "alpha_N": [(0, _one)],
}


def _inv_r_n(nav):
    return -1.0 / (nav["R_N"] + nav["height"])


def _inv_r_e(nav):
    return 1.0 / (nav["R_E"] + nav["height"])


def _tan_r_e(nav):
    return -np.tan(nav["latitude"]) / (nav["R_E"] + nav["height"])


def _cos(nav):
    return np.cos(nav["latitude"])


def _minus_sin(nav):
    return -np.sin(nav["latitude"])


def _minus(nav):
    return -np.ones_like(nav["latitude"])


# δθ = (δλ cos φ, −δφ, −δλ sin φ) in NED, from each position state (name: [(axis, factor)])
_THETA = {
    "delta_latitude": [(1, _minus)], "dlat": [(1, _minus)],
    "delta_longitude": [(0, _cos), (2, _minus_sin)], "dlon": [(0, _cos), (2, _minus_sin)],
    "dr_N": [(1, _inv_r_n)], "dr_E": [(0, _inv_r_e), (2, _tan_r_e)],
}


def _readout(names: list[str], nav: dict[str, np.ndarray], table: dict) -> np.ndarray:
    k = nav["latitude"].shape[-1]
    out = np.zeros((3, len(names), k))
    for j, name in enumerate(names):
        for axis, factor in table.get(name, []):
            out[axis, j] += factor(nav)
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


def _north_pointing() -> dict[str, Convention]:
    return {"psi": Convention(
        "psi", "ψ-angle: platform attitude relative to the computer frame (Benson 1975)",
        (*_NP_COMMON,
         State("psi_E", "rad", "ψ-angle about east (platform vs computer frame)"),
         State("psi_N", "rad", "ψ-angle about north"),
         State("psi_U", "rad", "ψ-angle about up")),
        _north_pointing_psi)}


def _strapdown() -> dict[str, Convention]:
    """``strapdown_ned``'s conventions (:func:`strapdown_conventions`), T from
    :mod:`ins_errors.models.strapdown_conventions` and ``T⁺`` for the quaternion."""
    from ins_errors.models import strapdown_conventions as sc

    def functions(conv):
        # (n, K) states -> (nz, ne, K), in one CasADi call each
        return (lambda x, p, c=conv: sc.transform_matrix(c, x, p),
                lambda x, f, p, c=conv: sc.transform_rate(c, x, f, p), None)

    return strapdown_conventions(functions)


def strapdown_conventions(functions: Callable) -> dict[str, Convention]:
    """The φ/ψ/modified-velocity conventions of :mod:`ins_errors.models.strapdown_conventions`,
    each with the position in NED metres (``NAME``) or as latitude/longitude/height
    (``NAME_geodetic``), for a model whose maps ``functions(convention) -> (transform,
    rate, lift[, validate])`` gives (``lift`` None: ``T⁺``)."""
    from ins_errors.models import strapdown_conventions as sc

    descriptions = {
        "phi": "φ-angle (attitude error in the true NED frame), δv in NED",
        "psi": "ψ-angle (attitude error relative to the computed frame), velocity error in "
               "the computed frame (Benson 1975)",
        "phi_modified": "φ-angle with the modified velocity error δu = δv + φ × v "
                        "(Scherzinger & Reid)",
        "psi_modified": "ψ-angle with the modified velocity error δu",
    }
    out = {}
    for name in sc.CONVENTIONS:
        for position, suffix, where in (("ned", "", "position in NED metres"),
                                        ("geodetic", "_geodetic",
                                         "position as latitude, longitude, height")):
            conv = sc.convention(name, position)
            states = tuple(State(n, sc.UNITS[n], _state_text(n)) for n in conv.names)
            transform, rate, lift, *validate = functions(conv)
            out[name + suffix] = Convention(
                name + suffix, f"{descriptions.get(name, name)}; {where}", states,
                transform, rate,
                vertical=tuple(n for n in conv.names
                               if n in ("dv_D", "dvc_D", "du_D", "dr_D", "dh")),
                lift=lift, validate=validate[0] if validate else None)
    return out


_VOCABULARY_TEXT = {
    "phi": "φ-angle: attitude error in the true NED frame",
    "psi": "ψ-angle: attitude error relative to the computed NED frame",
    "dv": "velocity error in NED",
    "dvc": "velocity error in the computed frame, δv + δθ × v",
    "du": "modified velocity error δv + φ × v (Scherzinger & Reid)",
    "dr": "position error in NED",
    "dlat": "latitude error", "dlon": "longitude error", "dh": "height error (up)",
}


def _state_text(name: str) -> str:
    """Meaning of a strapdown vocabulary name (``psi_N`` -> ψ-angle ..., north)."""
    if name in _VOCABULARY_TEXT:
        return _VOCABULARY_TEXT[name]
    base, _, axis = name.rpartition("_")
    return f"{_VOCABULARY_TEXT.get(base, base)}, {dict(N='north', E='east', D='down')[axis]}"

REGISTRY = {"north_pointing": _north_pointing, "strapdown_ned": _strapdown}
"""Builders of each model's conventions beyond its own states (``model``)."""


def own_convention(model) -> Convention:
    """The model's own error states as a convention (``T = I``)."""
    states = tuple(State(s.name, s.unit, s.description) for s in model.error_states)
    vertical = tuple(s.name for s in states if s.name in ("delta_h", "delta_v_D"))
    return Convention("model", f"the model's own error states ({model.name})", states,
                      None, vertical=vertical)


def conventions(model) -> dict[str, Convention]:
    """Every convention of ``model``, by name (``model`` first): its own, and those of
    :data:`REGISTRY`, or for a strapdown model that describes itself by its outputs (a
    model file), ``strapdown_ned``'s (:mod:`ins_errors.checker.strapdown_description`)."""
    builder = REGISTRY.get(model.name)
    if builder is not None:
        return {"model": own_convention(model), **builder()}
    from ins_errors.checker import strapdown_description

    if strapdown_description.describes(model):
        return {"model": own_convention(model), **strapdown_description.conventions(model)}
    return {"model": own_convention(model)}


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
