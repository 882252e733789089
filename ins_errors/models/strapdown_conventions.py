r"""Exact maps from the ``strapdown_ned`` error state to the conventions of the literature.

The model's own error state is ``e = (δq0..δq3, δv_N, δv_E, δv_D, δφ, δλ, δh)``, the
difference computed − true of its state. Researchers write their F in other variables;
this module gives, at any true state ``x``, the matrix ``T(x)`` (9 × 10) with
``e_c = T(x) e`` to first order, its rate ``Ṫ`` along the motion, and from them the
linear model in the convention:

    ė_c = F_c e_c + G_c w,   F_c = (T F + Ṫ) T⁺,   G_c = T G,

``T⁺`` the pseudo-inverse (the quaternion error keeps ``q · δq = 0``, the one direction
T does not see, so the map is exact, not an approximation).

State vocabulary (public names; a convention is one attitude, one velocity and one
position triple, always in the order attitude, velocity, position):

========================  ==========================================================
``phi_N, phi_E, phi_D``    φ-angle, rad: attitude error in the *true* NED frame,
                           ``C̃_b^n = (I − [φ×]) C_b^n`` (Titterton & Weston's sign)
``psi_N, psi_E, psi_D``    ψ-angle, rad: attitude error relative to the *computed* NED
                           frame, ``ψ = φ − δθ`` with ``δθ = (δλ cos φ, −δφ, −δλ sin φ)``
                           the rotation of the computed frame from the true one
                           (Benson 1975: φ = ψ + δθ)
``dv_N, dv_E, dv_D``       velocity error δv = ṽ − v, m/s, components in NED
``dvc_N, dvc_E, dvc_D``    velocity error in the computed frame, ``δv + δθ × v``, m/s
                           (the ψ-angle model's velocity error, ṽ − C_n^c v)
``du_N, du_E, du_D``       modified velocity error of Scherzinger & Reid (1994),
                           ``δu = δv + φ × v``, m/s: the error of the body-frame
                           velocity resolved in NED, ``C_b^n (C̃_b^nᵀ ṽ − C_b^nᵀ v)``;
                           with it the specific force drops out of the velocity-error
                           equation (f × φ is replaced by −g × φ)
``dr_N, dr_E, dr_D``       position error in NED metres, ``((R_N + h) δφ,
                           (R_E + h) cos φ δλ, −δh)``
``dlat, dlon, dh``         position error as latitude (rad), longitude (rad), height (m)
``psi_X, psi_Y, psi_Z``    attitude error resolved in ECEF (X to λ = 0 on the equator,
                           Z to the north pole), rad, with *Groves' sign*
                           ``C̃_b^e = (I + [ψ^e×]) C_b^e`` (Groves 2013, δψ^e_eb): the
                           opposite sign of φ and ψ above. The ECEF frame does not move
                           with the position error, so this one angle is the ψ-angle
                           rotated, ``ψ^e = −C_n^e ψ``
``dv_X, dv_Y, dv_Z``       error of the ECEF velocity ``v^e = C_n^e v``, m/s, in ECEF:
                           ``C_n^e (δv + δθ × v) = C_n^e dvc``
``dr_X, dr_Y, dr_Z``       error of the ECEF position vector, m: ``C_n^e dr``
========================  ==========================================================

Named conventions (:data:`CONVENTIONS`): ``phi`` (φ, δv), ``psi`` (ψ, δv in the computed
frame), ``phi_modified`` (φ, δu), ``psi_modified`` (ψ, δu); each with the position as
``"ned"`` metres (default) or ``"geodetic"`` (δφ, δλ, δh). In Earth-fixed states
(:data:`EARTH_FIXED`): ``psi_ecef`` (ψ^e, δv^e, δr^e), the states of an ECEF-mechanised
INS's error model (Groves 2013, ch. 14, section 14.2.3). The ECEF rows are computed
exactly, by differentiating ``C_n^e(φ, λ)`` and the ECEF position of the geodetic
coordinates, not from the closed forms above (which tests check them against).

Example
-------
>>> import numpy as np
>>> from ins_errors import load_model
>>> from ins_errors.models import strapdown_conventions as sc
>>> model = load_model("strapdown_ned")
>>> p = model.parameter_vector()
>>> c = model.initial_condition_vector(latitude=np.radians(45))
>>> x = model.initial_state(c, model.input_vector(), p)
>>> u = model.input_vector(omega_x=7.292115e-5 * np.cos(np.radians(45)),
...                        omega_z=-7.292115e-5 * np.sin(np.radians(45)), f_z=-9.806)
>>> F_c, G_c = sc.convention_matrices(model, "phi", x, u, p)
>>> sc.state_names("phi")[:3]
('phi_N', 'phi_E', 'phi_D')
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from ins_errors.errors import unknown_name

ATTITUDE = {"phi": ("phi_N", "phi_E", "phi_D"), "psi": ("psi_N", "psi_E", "psi_D"),
            "psi_ecef": ("psi_X", "psi_Y", "psi_Z")}
VELOCITY = {"dv": ("dv_N", "dv_E", "dv_D"), "dvc": ("dvc_N", "dvc_E", "dvc_D"),
            "du": ("du_N", "du_E", "du_D"), "dv_ecef": ("dv_X", "dv_Y", "dv_Z")}
POSITION = {"ned": ("dr_N", "dr_E", "dr_D"), "geodetic": ("dlat", "dlon", "dh"),
            "ecef": ("dr_X", "dr_Y", "dr_Z")}

UNITS = {**{n: "rad" for names in ATTITUDE.values() for n in names},
         **{n: "m/s" for names in VELOCITY.values() for n in names},
         "dr_N": "m", "dr_E": "m", "dr_D": "m", "dlat": "rad", "dlon": "rad", "dh": "m",
         "dr_X": "m", "dr_Y": "m", "dr_Z": "m"}
"""SI unit of every vocabulary name."""

VOCABULARY: tuple[str, ...] = tuple(UNITS)
"""Every state name a convention can use."""


@dataclass(frozen=True)
class Convention:
    """Attitude, velocity and position variables of one error-model convention."""

    attitude: str
    velocity: str
    position: str = "ned"

    @property
    def names(self) -> tuple[str, ...]:
        """The nine state names, attitude first."""
        return (*ATTITUDE[self.attitude], *VELOCITY[self.velocity], *POSITION[self.position])


CONVENTIONS: dict[str, tuple[str, str]] = {
    "phi": ("phi", "dv"),
    "psi": ("psi", "dvc"),
    "phi_modified": ("phi", "du"),
    "psi_modified": ("psi", "du"),
}
"""Named conventions: attitude and velocity variables."""

EARTH_FIXED: dict[str, tuple[str, str, str]] = {"psi_ecef": ("psi_ecef", "dv_ecef", "ecef")}
"""Named conventions in Earth-fixed (ECEF) states: attitude, velocity and position
variables (their position has one form, ECEF metres)."""


def convention(name: str, position: str = "ned") -> Convention:
    """The :class:`Convention` called ``name`` with position as ``"ned"`` or ``"geodetic"``
    (a name of :data:`EARTH_FIXED` has its own, ``"ecef"``; ``position`` is then
    ``"ned"``, the default, or ``"ecef"``).

    Raises
    ------
    UnknownNameError
        For an unknown convention or position form (close names are suggested).
    """
    if name in EARTH_FIXED:
        if position not in ("ned", "ecef"):
            raise unknown_name(f"position-error form of {name}", position, ["ecef"])
        return Convention(*EARTH_FIXED[name])
    if name not in CONVENTIONS:
        raise unknown_name("error-model convention", name, {**CONVENTIONS, **EARTH_FIXED})
    if position not in ("ned", "geodetic"):
        raise unknown_name("position-error form", position, ("ned", "geodetic"))
    attitude, velocity = CONVENTIONS[name]
    return Convention(attitude, velocity, position)


def state_names(name: str, position: str = "ned") -> tuple[str, ...]:
    """State names of a named convention, in order."""
    return convention(name, position).names


# --------------------------------------------------------------------------------------
# The map T(x) (CasADi, exact derivatives)
# --------------------------------------------------------------------------------------
def _dcm(q):
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    return ca.vertcat(
        ca.horzcat(q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)),
        ca.horzcat(2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)),
        ca.horzcat(2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2))


def _skew(v):
    return ca.vertcat(ca.horzcat(0, -v[2], v[1]), ca.horzcat(v[2], 0, -v[0]),
                      ca.horzcat(-v[1], v[0], 0))


def _blocks(x, p):
    """Rows of T for every vocabulary triple, as CasADi (3, 10) blocks."""
    q, v, lat, h = x[0:4], x[4:7], x[7], x[9]
    C = _dcm(q)
    # φ: [φ×] = −δC Cᵀ (skew part), linear in δq
    cols = []
    for k in range(4):
        dC = ca.jacobian(ca.vec(C), q)[:, k].reshape((3, 3))
        A = -dC @ C.T
        S = (A - A.T) / 2
        cols.append(ca.vertcat(S[2, 1], S[0, 2], S[1, 0]))
    phi_q = ca.horzcat(*cols)  # (3, 4)
    Z33, Z34 = ca.SX.zeros(3, 3), ca.SX.zeros(3, 4)
    I3 = ca.SX.eye(3)
    return convention_blocks(ca.horzcat(phi_q, Z33, Z33), ca.horzcat(Z34, I3, Z33),
                             ca.horzcat(Z34, Z33, I3), lat, x[8], h, v, p[0], p[1])


def _c_ne(lat, lon):
    """C_n^e (NED → ECEF) at geodetic latitude and longitude (CasADi, 3 × 3)."""
    sl, cl, so, co = ca.sin(lat), ca.cos(lat), ca.sin(lon), ca.cos(lon)
    return ca.vertcat(ca.horzcat(-sl * co, -so, -cl * co), ca.horzcat(-sl * so, co, -cl * so),
                      ca.horzcat(cl, 0, -sl))


@cache
def _earth_fixed() -> ca.Function:
    """``(φ, λ, h, a, e2) -> (C_n^e, ε_φ, ε_λ, J_r)``: C_n^e; the rotation (ECEF
    components, rad per rad) of the NED frame per unit change of latitude and of
    longitude, the axial vectors of ``(∂C_n^e/∂φ) C_e^n`` and ``(∂C_n^e/∂λ) C_e^n``
    (skew-symmetric, as C stays orthonormal); and ``J_r = ∂r^e/∂(φ, λ, h)`` (3 × 3, m per
    rad and m/m) of the ECEF position on the ellipsoid (a, e2): exact derivatives."""
    lat, lon, h, a, e2 = (ca.SX.sym(n) for n in ("lat", "lon", "h", "a", "e2"))
    C = _c_ne(lat, lon)
    axial = []
    for angle in (lat, lon):
        W = ca.jacobian(ca.vec(C), angle).reshape((3, 3)) @ C.T
        axial.append(ca.vertcat(W[2, 1], W[0, 2], W[1, 0]))
    r_e = a / ca.sqrt(1 - e2 * ca.sin(lat) ** 2)  # prime-vertical radius
    r = ca.vertcat((r_e + h) * ca.cos(lat) * ca.cos(lon), (r_e + h) * ca.cos(lat) * ca.sin(lon),
                   (r_e * (1 - e2) + h) * ca.sin(lat))
    return ca.Function("earth_fixed", [lat, lon, h, a, e2],
                       [C, *axial, ca.jacobian(r, ca.vertcat(lat, lon, h))])


def convention_blocks(phi, dv, position, lat, lon, h, v, a, e2) -> dict:
    """Rows of T for every vocabulary triple from the rows of three error quantities.

    Parameters
    ----------
    phi, dv, position : casadi.SX, shape (3, ne)
        The φ-angle (N, E, D), the NED velocity error and the position error (δφ, δλ,
        δh) per model error state.
    lat, lon, h, v, a, e2 : casadi.SX
        True geodetic latitude, longitude, height and NED velocity (3,), semi-major axis
        and eccentricity².

    Returns
    -------
    dict of str to casadi.SX
        (3, ne) rows of every name of :data:`ATTITUDE`, :data:`VELOCITY`, :data:`POSITION`.
    """
    w2 = 1 - e2 * ca.sin(lat) ** 2
    R_N = a * (1 - e2) / (w2 * ca.sqrt(w2))
    R_E = a / ca.sqrt(w2)
    # δθ = (δλ cos φ, −δφ, −δλ sin φ), in (δφ, δλ, δh)
    theta_pos = ca.vertcat(ca.horzcat(0, ca.cos(lat), 0), ca.horzcat(-1, 0, 0),
                           ca.horzcat(0, -ca.sin(lat), 0))
    theta = theta_pos @ position
    cross_v = -_skew(v)  # a × v = −[v×] a
    ned = ca.diag(ca.vertcat(R_N + h, (R_E + h) * ca.cos(lat), -1)) @ position
    # Earth-fixed: C_b^e = C_n^e C_b^n, v^e = C_n^e v, r^e(φ, λ, h); ε^e the rotation of
    # the NED frame at the computed position from the true one (ECEF components)
    C, eps_lat, eps_lon, J_r = _earth_fixed()(lat, lon, h, a, e2)
    eps = eps_lat @ position[0, :] + eps_lon @ position[1, :]
    return {
        "phi": phi,
        "psi": phi - theta,
        "dv": dv,
        "dvc": dv + cross_v @ theta,
        "du": dv + cross_v @ phi,
        "ned": ned,
        "geodetic": position,
        # Groves' sign: C̃_b^e C_b^eᵀ = I + [ψ^e×] = C_n^e(r̃) (I − [φ×]) C_e^n(r)
        "psi_ecef": eps - C @ phi,
        # δ(C_n^e v) = C_n^e δv + ε^e × (C_n^e v)
        "dv_ecef": C @ dv - _skew(C @ v) @ eps,
        "ecef": J_r @ position,  # = C_n^e dr (a test checks it)
    }


N_STATES = 10
"""Length of the ``strapdown_ned`` state (q0..q3, v_N, v_E, v_D, lat, lon, h)."""


@cache
def _functions(conv: Convention) -> tuple[ca.Function, ca.Function]:
    x = ca.SX.sym("x", N_STATES)
    xdot = ca.SX.sym("xdot", N_STATES)
    p = ca.SX.sym("p", 2)  # a, e2: the first two model parameters
    blocks = _blocks(x, p)
    T = ca.vertcat(blocks[conv.attitude], blocks[conv.velocity], blocks[conv.position])
    T_dot = (ca.jacobian(ca.vec(T), x) @ xdot).reshape(T.shape)
    return (ca.Function("transform", [x, p], [T]),
            ca.Function("transform_rate", [x, xdot, p], [T_dot]))


def _conv(name: str | Convention, position: str) -> Convention:
    return name if isinstance(name, Convention) else convention(name, position)


def _side_by_side(out, x: np.ndarray) -> np.ndarray:
    """A CasADi result as an array: (rows, 10) at one state ``x`` (10,); at K states
    ``x`` (10, K), which CasADi evaluates side by side and returns side by side
    (rows, 10 K), as (rows, 10, K)."""
    out = np.asarray(out)
    if x.ndim == 1:
        return out
    return np.moveaxis(out.reshape(out.shape[0], x.shape[1], -1), 1, 2)


def transform_matrix(name: str | Convention, x, p, position: str = "ned") -> np.ndarray:
    """``T(x)``, shape (9, 10): convention state = T × model error state (first order).

    Parameters
    ----------
    name : str or Convention
        A name of :data:`CONVENTIONS` or a :class:`Convention`.
    x : numpy.ndarray, shape (10,) or (10, K)
        True state of ``strapdown_ned`` (or K of them: ``T`` is then (9, 10, K), from one
        CasADi call).
    p : numpy.ndarray, shape (8,)
        Model parameters.
    position : {"ned", "geodetic"}
        Position form (ignored when ``name`` is a Convention).
    """
    x = np.asarray(x, dtype=float)
    return _side_by_side(_functions(_conv(name, position))[0](x, np.asarray(p)[:2]), x)


def transform_rate(name: str | Convention, x, xdot, p, position: str = "ned") -> np.ndarray:
    """``dT/dt = Σ_k ∂T/∂x_k ẋ_k`` along the true motion (exact derivatives).

    Parameters
    ----------
    x, xdot : numpy.ndarray, shape (10,) or (10, K)
        True state and its time derivative (the model's ``ideal_rhs``); for K samples
        the result is (9, 10, K), as :func:`transform_matrix`.
    p : numpy.ndarray
        Model parameters (``a``, ``e2`` first).
    """
    x = np.asarray(x, dtype=float)
    return _side_by_side(_functions(_conv(name, position))[1](x, xdot, np.asarray(p)[:2]),
                         x)


def convention_matrices(model, name: str | Convention, x, u, p,
                        position: str = "ned") -> tuple[np.ndarray, np.ndarray]:
    """F and G of the linear error model written in a convention.

    For ``strapdown_ned`` the maps of this module; for any other model (a strapdown model
    file, whatever the order of its states and parameters)
    :func:`ins_errors.conventions.error_matrices`, whose layout, (K, 9, 9), is here
    turned into this function's, (9, 9, K).

    Parameters
    ----------
    model : Model
        A loaded model: ``strapdown_ned`` (its ``state_matrix``, ``source_matrix`` and
        ``ideal_rhs`` are used), or one that has the convention
        (``ins-errors check MODEL --list-conventions``).
    name : str or Convention
        Convention (see :data:`CONVENTIONS`).
    x, u, p : numpy.ndarray
        True state (10,), inputs (7,) and parameters (8,); or K samples at once, states
        (10, K) and inputs (7, K) (one call instead of K: CasADi and the model evaluate
        all columns together).
    position : {"ned", "geodetic"}
        Position form.

    Returns
    -------
    F_c : numpy.ndarray, shape (9, 9) or (9, 9, K)
        ``(T F + Ṫ) T⁺``; rows and columns in the order of :func:`state_names`.
    G_c : numpy.ndarray, shape (9, nw) or (9, nw, K)
        ``T G``; columns are the model's error sources.

    Raises
    ------
    InsErrorsError
        For another model: one line for a convention it does not have or arrays of the
        wrong shape (:func:`~ins_errors.conventions.error_matrices`).
    """
    conv = _conv(name, position)
    if getattr(model, "name", None) != "strapdown_ned":
        return _any_model(model, conv, x, u, p)
    x = np.asarray(x, dtype=float)
    if x.ndim == 2:
        return _convention_matrices_along(model, conv, x, np.asarray(u, dtype=float), p)
    T = transform_matrix(conv, x, p)
    T_dot = transform_rate(conv, x, model.ideal_rhs(x, u, p), p)
    F = model.state_matrix(x, u, p)
    G = model.source_matrix(x, u, p)
    T_plus = np.linalg.pinv(T)
    return (T @ F + T_dot) @ T_plus, T @ G


def checker_name(conv: Convention) -> str:
    """The name of ``conv`` among a model's conventions (``psi_geodetic``, ``psi_ecef``)."""
    for name, parts in EARTH_FIXED.items():
        if (conv.attitude, conv.velocity, conv.position) == parts:
            return name
    for name, parts in CONVENTIONS.items():
        if (conv.attitude, conv.velocity) == parts:
            return name + ("_geodetic" if conv.position == "geodetic" else "")
    raise unknown_name("convention", f"{conv.attitude}/{conv.velocity}/{conv.position}",
                       [*CONVENTIONS, *EARTH_FIXED])


def _any_model(model, conv: Convention, x, u, p) -> tuple[np.ndarray, np.ndarray]:
    """:func:`convention_matrices` of a model other than ``strapdown_ned``, through
    :func:`ins_errors.conventions.error_matrices` (a single sample: ``x`` (n,))."""
    from ins_errors.conventions import error_matrices

    x = np.asarray(x, dtype=float)
    u = np.asarray(u, dtype=float)
    one = x.ndim == 1
    F, G = error_matrices(model, checker_name(conv), x[:, None] if one else x,
                          u[:, None] if one and u.ndim == 1 else u, p)[:2]
    F, G = np.moveaxis(F, 0, -1), np.moveaxis(G, 0, -1)
    return (F[..., 0], G[..., 0]) if one else (F, G)


def _convention_matrices_along(model, conv: Convention, x: np.ndarray, u: np.ndarray, p
                               ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`convention_matrices` at the K columns of ``x`` (10, K) and ``u`` (7, K)."""
    T = np.moveaxis(transform_matrix(conv, x, p), -1, 0)
    T_dot = np.moveaxis(transform_rate(conv, x, model.ideal_rhs(x, u, p), p), -1, 0)
    F = np.moveaxis(model.state_matrix(x, u, p), -1, 0)
    G = np.moveaxis(model.source_matrix(x, u, p), -1, 0)
    T_plus = np.linalg.pinv(T)
    return (np.moveaxis((T @ F + T_dot) @ T_plus, 0, -1), np.moveaxis(T @ G, 0, -1))


def to_convention(name: str | Convention, x, e, p, position: str = "ned") -> np.ndarray:
    """Convention state of model error states ``e`` at true states ``x``.

    Parameters
    ----------
    x : numpy.ndarray, shape (10, K)
        True states.
    e : numpy.ndarray, shape (10, K) or (10, K, B)
        Model error states (e.g. a simulation's ``real[:, k] − ideal[:, k]`` or a linear
        run).

    Returns
    -------
    numpy.ndarray, shape (9, K) or (9, K, B)
    """
    fn = _functions(_conv(name, position))[0]
    x = np.asarray(x, dtype=float)
    ae2 = np.asarray(p)[:2]
    T = np.stack([np.asarray(fn(x[:, k], ae2)) for k in range(x.shape[1])], axis=-1)
    return np.einsum("ijk,jk...->ik...", T, np.asarray(e, dtype=float))
