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
from functools import partial

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
    hold : callable or None
        For a convention whose states mix the vertical channel into every velocity and
        position state (Earth-fixed states), so that ``vertical`` cannot name it:
        ``(navigation) -> (Q, c)``, each (K, n, n) over the convention's own n states
        (bias states not included). The effect propagation holds the vertical channel
        by ``F -> Q F Q + c``, ``G -> Q G``: exactly the propagation of a local-level
        convention with its vertical states held, read back in these states
        (:mod:`ins_errors.checker.held_channel`). ``hold_text`` names what is held.
    hold_text : str
        What ``hold`` holds, for the reports.
    frame : callable or None
        ``(x, p) -> (T, L)``, shapes (9, ne, K) and (ne, 9, K): the φ-angle, NED velocity
        and NED position errors (``phi_N/E/D``, ``dv_N/E/D``, ``dr_N/E/D``, rad, m/s, m)
        of each of the convention's own states, and a lift with ``T L = I``. Given for
        states whose names say nothing of position or attitude (the own error states of a
        strapdown INS: an ECEF position, a direction-cosine matrix, a quaternion): its
        :meth:`position` and :meth:`attitude` are then read through ``T``, and its
        vertical channel (``dv_D``, ``dr_D``, no state of its own) is held through it in
        the effect propagation
        (:func:`~ins_errors.checker.held_channel.vertical_projector`).
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
    hold: Callable[[dict], tuple[np.ndarray, np.ndarray]] | None = None
    hold_text: str = ""
    frame: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None

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

    def position(self, nav: dict[str, np.ndarray], x: np.ndarray | None = None,
                 p: np.ndarray | None = None) -> np.ndarray:
        """(3, nz, K): north, east, down position error (m) per unit of each state.

        Read from the states' names, or through :attr:`frame` at the ideal states ``x``
        (n, K) and parameters ``p`` where the convention has one (both must then be
        given).
        """
        if self.frame is not None:
            return self._framed(x, p)[6:9]
        return _readout(self.names, nav, _POSITION)

    def attitude(self, nav: dict[str, np.ndarray], x: np.ndarray | None = None,
                 p: np.ndarray | None = None) -> np.ndarray:
        """(3, nz, K): attitude error about north, east, down (rad) per unit of each state.

        The attitude error is that of the computed attitude relative to the true NED
        frame (the φ-angle, or the platform angles α); for a ψ-angle convention it is
        ψ + δθ, δθ = (δλ cos φ, −δφ, −δλ sin φ) the rotation of the computed frame.
        Through :attr:`frame` (at ``x``, ``p``) where the convention has one.
        """
        if self.frame is not None:
            return self._framed(x, p)[0:3]
        out = _readout(self.names, nav, _ATTITUDE)
        if any(n.startswith("psi_") for n in self.names):
            out += _readout(self.names, nav, _THETA)
        return out


    def _framed(self, x: np.ndarray | None, p: np.ndarray | None) -> np.ndarray:
        """:attr:`frame`'s ``T`` (9, nz, K), zero columns for the bias states."""
        if x is None or p is None:
            raise ValueError(f"convention {self.name!r} reads position and attitude "
                             "through its frame: give the ideal states and parameters")
        T = np.asarray(self.frame(x, p)[0], dtype=float)
        out = np.zeros((9, len(self.states), T.shape[-1]))
        out[:, :T.shape[1]] = T
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
NORTH_POSITION = frozenset(name for name, axes in _POSITION.items()
                           if [axis for axis, _ in axes] == [0])
"""Position error states along north (latitude error, north metres)."""
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


def _c_en(nav, row: int, column: int) -> np.ndarray:
    """Entry (row, column) of C_e^n (ECEF → NED) at the navigation solution, over K."""
    lat, lon = nav["latitude"], nav["longitude"]
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    zero = np.zeros_like(lat)
    rows = ((-sl * co, -sl * so, cl), (-so, co, zero), (-cl * co, -cl * so, -sl))
    return rows[row][column]


def _ecef_tables() -> tuple[dict, dict, dict]:
    """Readouts of the ECEF states (:data:`_POSITION`, :data:`_ATTITUDE`, :data:`_THETA`
    entries): δr^n = C_e^n δr^e; φ = −C_e^n ψ^e + δθ (Groves' sign of ψ^e), δθ of the NED
    position error C_e^n δr^e."""
    position, attitude, theta = {}, {}, {}
    for j, axis in enumerate("XYZ"):
        position[f"dr_{axis}"] = [(i, lambda nav, i=i, j=j: _c_en(nav, i, j))
                                  for i in range(3)]
        attitude[f"psi_{axis}"] = [(i, lambda nav, i=i, j=j: -_c_en(nav, i, j))
                                   for i in range(3)]
        theta[f"dr_{axis}"] = [
            (axis_of, lambda nav, f=factor, i=i, j=j: f(nav) * _c_en(nav, i, j))
            for i, ned in enumerate(("dr_N", "dr_E")) for axis_of, factor in _THETA[ned]]
    return position, attitude, theta


_ECEF_POSITION, _ECEF_ATTITUDE, _ECEF_THETA = _ecef_tables()
_POSITION.update(_ECEF_POSITION)
_ATTITUDE.update(_ECEF_ATTITUDE)
_THETA.update(_ECEF_THETA)


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
        "psi", "ψ-angle: platform attitude relative to the computer frame (Benson 1975), "
               "ψ = α − δθ, δθ = (−δφ, δλ cos φ, δλ sin φ) about east, north, up; errors "
               "computed − true",
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
        "phi": "φ-angle (attitude error in the true NED frame, C̃_b^n = (I − [φ×]) C_b^n), "
               "δv = ṽ − v in NED",
        "psi": "ψ-angle (attitude error relative to the computed frame, ψ = φ − δθ, the "
               "sign of φ), velocity error in the computed frame (Benson 1975)",
        "phi_modified": "φ-angle with the modified velocity error δu = δv + φ × v "
                        "(Scherzinger & Reid)",
        "psi_modified": "ψ-angle with the modified velocity error δu",
    }
    forms = [(name, position, suffix, f"{descriptions.get(name, name)}; {where}")
             for name in sc.CONVENTIONS
             for position, suffix, where in (("ned", "", "position in NED metres"),
                                             ("geodetic", "_geodetic",
                                              "position as latitude, longitude, height"))]
    forms += [(name, "ecef", "", EARTH_FIXED_TEXT[name]) for name in sc.EARTH_FIXED]
    out = {}
    for name, position, suffix, description in forms:
        conv = sc.convention(name, position)
        states = tuple(State(n, sc.UNITS[n], _state_text(n)) for n in conv.names)
        transform, rate, lift, *validate = functions(conv)
        earth_fixed = position == "ecef"
        out[name + suffix] = Convention(
            name + suffix, description, states, transform, rate,
            vertical=tuple(n for n in conv.names
                           if n in ("dv_D", "dvc_D", "du_D", "dr_D", "dh")),
            lift=lift, validate=validate[0] if validate else None,
            hold=ecef_hold if earth_fixed else None,
            hold_text=ECEF_HOLD_TEXT if earth_fixed else "")
    return out


ECEF_HOLD_TEXT = "the vertical (down) components of δv^e and δr^e"
"""What the effect propagation of an Earth-fixed convention holds (:func:`ecef_hold`)."""


def ecef_hold(nav: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """``(Q, c)`` of :attr:`Convention.hold` for the Earth-fixed states (ψ^e, δv^e, δr^e).

    Their map to the ψ-angle states (ψ, dvc, dr) is ``T_l = blockdiag(−C_e^n, C_e^n,
    C_e^n)`` with ``Ṫ_l T_l⁻¹ = W = −I ⊗ [ω_en^n×]``; that convention holds dvc_D and dr_D
    (``P`` zeroes them). Its held propagation ``ẏ = P F_l P y``, ``F_l = W + T_l F T_l⁻¹``,
    read back through ``z = T_l⁻¹ y``, is ``ż = (Q F Q + c) z`` with ``Q = T_l⁻¹ P T_l``
    (identity on ψ^e; ``I − d dᵀ`` on δv^e and δr^e, ``d`` the local down in ECEF) and
    ``c = T_l⁻¹ (P W P − W) T_l``.

    Parameters
    ----------
    nav : dict
        Navigation description along a motion (latitude, longitude, ``omega_en_n``; (K,)
        and (3, K)).

    Returns
    -------
    Q, c : numpy.ndarray, shape (K, 9, 9)
    """
    C = np.moveaxis(np.array([[_c_en(nav, i, j) for j in range(3)] for i in range(3)]),
                    -1, 0)  # (K, 3, 3) C_e^n
    k = C.shape[0]
    w = np.asarray(nav["omega_en_n"], dtype=float).T  # (K, 3)
    W = np.zeros((k, 3, 3))
    W[:, 0, 1], W[:, 0, 2], W[:, 1, 2] = w[:, 2], -w[:, 1], w[:, 0]  # −[ω×]
    W -= np.swapaxes(W, 1, 2)
    P = np.diag([1.0, 1.0, 0.0])
    Ct = np.swapaxes(C, 1, 2)
    Q3 = Ct @ P @ C
    c3 = Ct @ (P @ W @ P - W) @ C
    Q, c = np.zeros((k, 9, 9)), np.zeros((k, 9, 9))
    Q[:, 0:3, 0:3] = np.eye(3)
    for b in (slice(3, 6), slice(6, 9)):
        Q[:, b, b], c[:, b, b] = Q3, c3
    return Q, c


EARTH_FIXED_TEXT = {
    "psi_ecef": "Earth-fixed (ECEF) error states of Groves (2013, ch. 14): attitude error "
                "ψ^e with C̃_b^e = (I + [ψ^e×]) C_b^e, δv^e, δr^e",
}
"""Descriptions of the Earth-fixed conventions
(:data:`ins_errors.models.strapdown_conventions.EARTH_FIXED`)."""


_VOCABULARY_TEXT = {
    "phi": "φ-angle: attitude error in the true NED frame",
    "psi": "ψ-angle: attitude error relative to the computed NED frame",
    "dv": "velocity error in NED",
    "dvc": "velocity error in the computed frame, δv + δθ × v",
    "du": "modified velocity error δv + φ × v (Scherzinger & Reid)",
    "dr": "position error in NED",
    "dlat": "latitude error", "dlon": "longitude error", "dh": "height error (up)",
}
_ECEF_TEXT = {
    "psi": "attitude error in ECEF, Groves' sign C̃_b^e = (I + [ψ×]) C_b^e (= −C_n^e ψ)",
    "dv": "ECEF velocity error δv^e (= C_n^e dvc)",
    "dr": "ECEF position error δr^e (= C_n^e dr)",
}
_AXIS_TEXT = {"N": "north", "E": "east", "D": "down", "X": "X (λ = 0 on the equator)",
              "Y": "Y (λ = 90° E on the equator)", "Z": "Z (north pole)"}


def _state_text(name: str) -> str:
    """Meaning of a strapdown vocabulary name (``psi_N`` -> ψ-angle ..., north)."""
    if name in _VOCABULARY_TEXT:
        return _VOCABULARY_TEXT[name]
    base, _, axis = name.rpartition("_")
    text = (_ECEF_TEXT if axis in "XYZ" else _VOCABULARY_TEXT).get(base, base)
    return f"{text}, {_AXIS_TEXT[axis]}"

REGISTRY = {"north_pointing": _north_pointing, "strapdown_ned": _strapdown}
"""Builders of each model's conventions beyond its own states (``model``)."""


def own_convention(model, phi: Convention | None = None) -> Convention:
    """The model's own error states as a convention (``T = I``); with ``phi`` (the
    model's φ-angle convention, position in NED metres), position and attitude are read
    through it and the vertical channel is held through it (:attr:`Convention.frame`)."""
    states = tuple(State(s.name, s.unit, s.description) for s in model.error_states)
    vertical = tuple(s.name for s in states if s.name in ("delta_h", "delta_v_D"))
    return Convention("model", f"the model's own error states ({model.name})", states,
                      None, vertical=vertical,
                      frame=None if phi is None else partial(_phi_frame, phi))


def _phi_frame(phi: Convention, x: np.ndarray, p: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """:attr:`Convention.frame` of a model's own states: ``T`` of its φ-angle convention
    ``phi`` and its lift (``T⁺`` where it has none)."""
    T = phi.transform(x, p)
    if phi.lift is not None:
        return T, phi.lift(x, p)
    return T, np.moveaxis(np.linalg.pinv(np.moveaxis(T, -1, 0)), 0, -1)


def conventions(model) -> dict[str, Convention]:
    """Every convention of ``model``, by name (``model`` first): its own, and those of
    :data:`REGISTRY`, or for a strapdown model that describes itself by its outputs (a
    model file), ``strapdown_ned``'s (:mod:`ins_errors.checker.strapdown_description`)."""
    builder = REGISTRY.get(model.name)
    if builder is None:
        from ins_errors.checker import strapdown_description

        if not strapdown_description.describes(model):
            return {"model": own_convention(model)}
        builder = partial(strapdown_description.conventions, model)
    others = builder()
    # a strapdown INS's own states (a quaternion, a direction-cosine matrix, an ECEF
    # position) read position and attitude through its φ-angle convention
    return {"model": own_convention(model, others.get("phi")), **others}


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
