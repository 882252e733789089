"""Formula (10) of source 004 against a direct simulation over the spheroid.

Source 004 argues that an inertial vertical that holds the geodetic vertical and
dead-reckons with the spherical formulas (9) (variable radius R = a(1 − c sin²B))
computes the *geocentric* orthodromic coordinates Φ1, Λ1 instead of the geodetic ones
Φ = Φ1 + ν1, Λ = Λ1 + ν2/cos Φ, so that its coordinate error is (10):

    ΔΦ = c sin 2B cos N − ν1⁰,    ΔΛ = −c sin 2B sin N / cos Φ,

"purely geometric, reaching 22 km". Here this is checked by a direct simulation that
does not use the paper's formulas for the truth:

* truth: the vehicle flies at constant ground speed along the orthodrome taken as a
  central section of the ellipsoid (the plane of the start frame's ξ¹, ζ¹ axes), in the
  Earth-fixed frame ξ0η0ζ0 of the paper (η0 along the rotation axis); position,
  velocity and acceleration are exact (analytic derivatives of the section);
* the platform is on the exact geodetic vertical (ellipsoid normal); its horizontal axes
  are those of the orthodromic spherical coordinates (Φ, Λ) *of the normal* (the exact
  meaning of (5)); the accelerometers read j = r̈ + 2ω × ṙ − g on those axes (normal
  gravity has no horizontal component on the level ellipsoid);
* the computer is the ideal work of the generated model ``geodetic_vertical`` (formulas
  (9) and the dead reckoning), started from the exact coordinates and velocity;
* the error is the true geodetic (Φ, Λ) minus the computed one, compared with (10) as
  printed and with (10) completed by the start term −ν2⁰/cos Φ0 of ΔΛ that the print
  lacks and with μ of (4) in every term (so that, as the direct error, it is zero at
  t = 0).

:func:`correction_rate_error` checks the paper's other claim, that the rates (9) keep
the platform on the geodetic vertical, against the exact rate of the geodetic frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from ins_errors.errors import DomainError, InsErrorsError
from ins_errors.models.earth import EARTH_RATE, ELLIPSOIDS
from ins_errors.numeric.compare import Comparison, integration_errors_by_reruns, metrics_of
from ins_errors.numeric.integrators import record_stride, step_count
from ins_errors.numeric.model import load_model
from ins_errors.numeric.simulate import ErrorCurves
from ins_errors.output import save_figure


class SpheroidStudyError(InsErrorsError):
    """Bad arguments for the spheroid-error study."""


def flattening_constant(a: float, b: float) -> float:
    """c = (a² − b²)/(a² + b²)."""
    return (a * a - b * b) / (a * a + b * b)


def krasovsky_axes() -> tuple[float, float]:
    """Semi-axes (a, b) of the Krasovsky ellipsoid, m."""
    e = ELLIPSOIDS["krasovsky"]
    return e.semi_major_axis, e.semi_major_axis * (1.0 - e.flattening)


def mu(B: np.ndarray, c: float) -> np.ndarray:
    """(4): deflection of the normal from the radius, μ = c sin 2B − ½ c² sin 4B, rad."""
    return c * np.sin(2 * B) - 0.5 * c**2 * np.sin(4 * B)


def formula_10(B: np.ndarray, N: np.ndarray, Phi: np.ndarray, c: float,
               B0: float | np.ndarray = 0.0, N0: float | np.ndarray = 0.0,
               Phi0: float | np.ndarray = 0.0, start_term: bool = False):
    """Coordinate error (10): (ΔΦ, ΔΛ), rad, true minus computed.

    Parameters
    ----------
    B, N, Phi : numpy.ndarray
        Current geodetic latitude, orthodrome angle and orthodromic latitude, rad.
    c : float
        Flattening constant (a² − b²)/(a² + b²).
    B0, N0, Phi0 : float or numpy.ndarray
        The same at the start point (for ν1⁰ and the optional start term of ΔΛ).
    start_term : bool
        The completed form: add −ν2⁰/cos Φ0 to ΔΛ (the print has no start term in ΔΛ)
        and take μ of (4) in the current terms as in the start terms, so that the error
        is zero at the start (the print's c sin 2B is the first term of (4); beside the
        start terms' μ(B0) it would leave ½c² sin 4B0 at t = 0, 35 m at 20°).
    """
    nu1_0 = mu(B0, c) * np.cos(N0)
    current = mu(B, c) if start_term else c * np.sin(2 * B)
    d_phi = current * np.cos(N) - nu1_0
    d_lam = -current * np.sin(N) / np.cos(Phi)
    if start_term:
        d_lam = d_lam - (-mu(B0, c) * np.sin(N0)) / np.cos(Phi0)
    return d_phi, d_lam


def formula_10_maximum(a: float | None = None, b: float | None = None,
                       points: int = 721) -> dict[str, float]:
    """Largest coordinate error of (10) over latitudes and orthodrome angles (ν1⁰ = 0).

    Returns
    -------
    dict
        ``"dPhi_km"`` (max |ΔΦ| a), ``"dLam_km"`` (max |ΔΛ cos Φ| a), ``"total_km"``
        (max of the displacement √(ΔΦ² + (ΔΛ cos Φ)²) a), with the latitude (deg) where
        the displacement peaks.
    """
    if a is None or b is None:
        a, b = krasovsky_axes()
    _check_axes(a, b)
    c = flattening_constant(a, b)
    B, N = np.meshgrid(np.linspace(-np.pi / 2, np.pi / 2, points),
                       np.linspace(0, 2 * np.pi, points))
    d_phi, d_lam = formula_10(B, N, np.zeros_like(B), c)
    total = np.hypot(d_phi, d_lam)  # Φ = 0: along the orthodrome
    k = np.unravel_index(np.argmax(total), total.shape)
    return {"dPhi_km": float(np.abs(d_phi).max() * a / 1000),
            "dLam_km": float(np.abs(d_lam).max() * a / 1000),
            "total_km": float(total.max() * a / 1000),
            "latitude_deg": float(np.degrees(abs(B[k])))}


def _check_axes(a: float, b: float) -> None:
    if not (np.isfinite(a) and np.isfinite(b)) or a <= 0 or b <= 0:
        raise DomainError(f"ellipsoid semi-axes must be positive, got a={a}, b={b}")
    if b > a:
        raise DomainError(f"semi-minor axis b={b} exceeds the semi-major axis a={a}")


# --------------------------------------------------------------------------------------
# Direct simulation
# --------------------------------------------------------------------------------------
def _start_frames(lat0: np.ndarray, lon0: np.ndarray, angle0: np.ndarray) -> np.ndarray:
    """Table (1) (orthonormal reading), shape (B, 3, 3): rows ξ¹, η¹, ζ¹ on ξ0, η0, ζ0."""
    s, c = np.sin, np.cos
    rows = [
        [c(lon0) * c(angle0) + s(lon0) * s(lat0) * s(angle0), c(lat0) * s(angle0),
         s(lat0) * c(lon0) * s(angle0) - s(lon0) * c(angle0)],
        [s(lon0) * s(lat0) * c(angle0) - c(lon0) * s(angle0), c(lat0) * c(angle0),
         c(lon0) * s(lat0) * c(angle0) + s(lon0) * s(angle0)],
        [s(lon0) * c(lat0), -s(lat0), c(lon0) * c(lat0)],
    ]
    return np.array(rows, dtype=float).transpose(2, 0, 1)


def _table2(Phi: np.ndarray, Lam: np.ndarray) -> np.ndarray:
    s, c = np.sin, np.cos
    z = np.zeros_like(Phi)
    rows = [[c(Lam), z, -s(Lam)],
            [s(Lam) * s(Phi), c(Phi), c(Lam) * s(Phi)],
            [s(Lam) * c(Phi), -s(Phi), c(Lam) * c(Phi)]]
    return np.array(rows).transpose(2, 0, 1)


_row_sum = np.add.reduce
"""``np.sum`` (the same reduction, so the same bits) without its Python wrapper: the
flights' right-hand side sums rows of a few numbers about a dozen times a call."""


@dataclass
class _Section:
    """Central section of the ellipsoid in the plane of ξ¹, ζ¹ (one per flight)."""

    n: np.ndarray  # (B, 3, 3)
    q: np.ndarray  # (3,) diagonal of the ellipsoid's quadratic form on ξ0, η0, ζ0
    speed: np.ndarray  # (B,)
    omega: float

    def _first_order(self, lam1: np.ndarray):
        """The terms of :meth:`kinematics` that Λ̇1 needs: d, d1, qv, q1, ρ, ρ', r', |r'|
        and Λ̇1."""
        xi1, zeta1 = self.n[:, 0, :], self.n[:, 2, :]
        sl, cl = np.sin(lam1)[:, None], np.cos(lam1)[:, None]
        d = sl * xi1 + cl * zeta1
        d1 = cl * xi1 - sl * zeta1
        Q = self.q
        qv = _row_sum(d * d * Q, axis=1)
        q1 = 2 * _row_sum(d1 * d * Q, axis=1)
        rho = qv**-0.5
        rho1 = -0.5 * qv**-1.5 * q1
        r1 = rho1[:, None] * d + rho[:, None] * d1
        norm1 = np.sqrt(_row_sum(r1 * r1, axis=1))  # numpy's norm, without its checks
        return d, d1, qv, q1, rho, rho1, r1, norm1, self.speed / norm1

    def angle_rate(self, lam1: np.ndarray) -> np.ndarray:
        """Λ̇1 at section angle Λ1, shape (B,), rad/s (the value :meth:`kinematics` gives)."""
        return self._first_order(lam1)[-1]

    def kinematics(self, lam1: np.ndarray):
        """r, ṙ, r̈ (Earth frame) and Λ̇1 at section angle Λ1, each (B, 3) / (B,)."""
        d, d1, qv, q1, rho, rho1, r1, norm1, lam_dot = self._first_order(lam1)
        q2 = 2 * (-qv + _row_sum(d1 * d1 * self.q, axis=1))
        rho2 = 0.75 * qv**-2.5 * q1**2 - 0.5 * qv**-1.5 * q2
        r = rho[:, None] * d
        r2 = rho2[:, None] * d + 2 * rho1[:, None] * d1 - rho[:, None] * d
        lam_ddot = -self.speed * _row_sum(r1 * r2, axis=1) / norm1**3 * lam_dot
        v = r1 * lam_dot[:, None]
        acc = r2 * (lam_dot**2)[:, None] + r1 * lam_ddot[:, None]
        return r, v, acc, lam_dot

    def repeated(self, times: int) -> _Section:
        """The same flights ``times`` over (batch index = repeat × B + flight): one call
        evaluates several section angles per flight. The frames keep their memory layout
        (:func:`_start_frames` gives a transposed view, C-ordered for a single flight):
        numpy's ``einsum`` adds its terms in an order that follows the layout, so the same
        layout gives the same bits."""
        if self.n.flags.c_contiguous:
            frames = np.tile(self.n, (times, 1, 1))
        else:
            frames = np.tile(self.n.transpose(1, 2, 0), (1, 1, times)).transpose(2, 0, 1)
        return _Section(frames, self.q, np.tile(self.speed, times), self.omega)

    def geodetic(self, r: np.ndarray):
        """Normal, its orthodromic (Φ, Λ), the geodetic axes (B, 3, 3), B and N."""
        normal = r * self.q
        normal /= np.sqrt(_row_sum(normal * normal, axis=1, keepdims=True))
        s = np.einsum("bij,bj->bi", self.n, normal)
        Phi = np.arctan2(-s[:, 1], np.hypot(s[:, 0], s[:, 2]))
        Lam = np.arctan2(s[:, 0], s[:, 2])
        axes = np.einsum("bij,bjk->bik", _table2(Phi, Lam), self.n)  # m_ij
        lat = np.arcsin(np.clip(-axes[:, 2, 1], -1, 1))
        N = np.arctan2(axes[:, 0, 1], axes[:, 1, 1])
        return Phi, Lam, axes, lat, N

    def measurements(self, lam1: np.ndarray, gravity: float):
        """Model inputs (j_ξ, j_η, j_ζ, V_ζ), shape (4, B), true (Φ, Λ, W, B, N), Λ̇1."""
        r, v, acc, lam_dot = self.kinematics(lam1)
        Phi, Lam, axes, lat, N = self.geodetic(r)
        # k × v for k = (0, ω, 0) (η0 along the Earth's angular velocity), with the
        # operations of numpy's cross product (the zero terms kept: the same signed zeros)
        w, vx, vy, vz = self.omega, v[:, 0], v[:, 1], v[:, 2]
        k_v = np.empty_like(v)
        k_v[:, 0] = w * vz - 0.0 * vy
        k_v[:, 1] = 0.0 * vx - 0.0 * vz
        k_v[:, 2] = 0.0 * vy - w * vx
        specific = acc + 2 * k_v
        j_xi = _row_sum(specific * axes[:, 0], axis=1)
        j_eta = _row_sum(specific * axes[:, 1], axis=1)
        W = np.stack([_row_sum(v * axes[:, 0], axis=1), _row_sum(v * axes[:, 1], axis=1)])
        V_zeta = _row_sum(v * axes[:, 2], axis=1)
        u = np.stack([j_xi, j_eta, np.full_like(j_xi, gravity), V_zeta])
        return u, (Phi, Lam, W, lat, N), lam_dot


@dataclass
class FlightErrors:
    """Direct and formula-(10) coordinate errors along a batch of flights.

    Attributes
    ----------
    times : numpy.ndarray, shape (T,)
        s.
    start : numpy.ndarray, shape (3, F)
        Geocentric start latitude φ0, longitude λ0, orthodrome angle N0 per flight, rad.
    latitude, orthodrome_angle : numpy.ndarray, shape (T, F)
        True geodetic latitude B and orthodrome angle N, rad.
    direct : numpy.ndarray, shape (2, T, F)
        True minus computed (Φ, Λ), rad.
    printed, completed : numpy.ndarray, shape (2, T, F)
        (10) as printed, and with the start term of ΔΛ, rad.
    Phi : numpy.ndarray, shape (T, F)
        True geodetic orthodromic latitude, rad.
    a : float
        Semi-major axis used to express errors in km.
    integration_error : numpy.ndarray, shape (2, F), optional
        Estimated integration error of (ΔΦ, ΔΛ) per flight, rad (step doubling, see
        :func:`integration_errors`); None when not estimated.
    warnings : list of str
        Integration-error warnings, one line each.
    flights : list of dict
        Set by :func:`survey`: one row per flight of its table, SI (see there).
    """

    times: np.ndarray
    start: np.ndarray
    latitude: np.ndarray
    orthodrome_angle: np.ndarray
    direct: np.ndarray
    printed: np.ndarray
    completed: np.ndarray
    Phi: np.ndarray
    a: float
    integration_error: np.ndarray | None = None
    warnings: list[str] = field(default_factory=list)
    flights: list[dict] = field(default_factory=list)

    def km(self, errors: np.ndarray) -> np.ndarray:
        """(ΔΦ a, ΔΛ a cos Φ) in km, shape (2, T, F)."""
        return np.stack([errors[0] * self.a, errors[1] * self.a * np.cos(self.Phi)]) / 1000

    def mismatch_km(self, against: str = "completed") -> np.ndarray:
        """Largest |direct − (10)| over the flight (both coordinates), km, shape (F,)."""
        ref = self.completed if against == "completed" else self.printed
        return np.abs(self.km(self.direct - ref)).max(axis=(0, 1))

    def largest_km(self) -> np.ndarray:
        """Largest direct displacement √(ΔΦ² + (ΔΛ cos Φ)²) a over each flight, km."""
        return np.hypot(*self.km(self.direct)).max(axis=0)


def simulate_flights(start_latitudes, start_longitudes, orthodrome_angles, duration: float,
                     speed: float = 250.0, step: float = 5.0, record_interval: float = 300.0,
                     a: float | None = None, b: float | None = None,
                     gravity: float = 9.81, closed_loop: bool = False) -> FlightErrors:
    """Fly the spherical-formula system along central-section orthodromes; compare with (10).

    Parameters
    ----------
    start_latitudes, start_longitudes, orthodrome_angles : array_like, shape (F,)
        Geocentric latitude φ0, longitude λ0 and orthodrome angle N0 of each start, rad.
    duration, step, record_interval : float
        Flight time, RK4 step and recording interval, s.
    speed : float
        Ground speed, m/s.
    a, b : float, optional
        Semi-axes, m (default Krasovsky).
    gravity : float
        Vertical specific force fed to the model (unused by its horizontal channels).
    closed_loop : bool
        False (the paper's setting): the coefficients of (9) and of the dead reckoning
        (B, N, Φ in R, tg Φ, the Coriolis terms) are taken at the true position, so only
        the geometric error remains. True: the computer uses its own computed position,
        as the model's ideal work does; the coordinate error then also feeds back through
        the Coriolis corrections (2 W ω sin B) and grows beyond (10).
    """
    if a is None or b is None:
        a, b = krasovsky_axes()
    _check_axes(a, b)
    lat0, lon0, ang0 = (np.atleast_1d(np.asarray(v, dtype=float)) for v in
                        (start_latitudes, start_longitudes, orthodrome_angles))
    lat0, lon0, ang0 = np.broadcast_arrays(lat0, lon0, ang0)
    if np.any(np.abs(lat0) >= np.pi / 2 - 1e-9):
        raise DomainError("start latitude at ±90°: the orthodrome angle is undefined at a pole")
    n_steps = step_count(duration, step)
    if n_steps == 0:
        raise SpheroidStudyError(f"duration must be positive, got {duration}")
    stride = record_stride(record_interval, step, n_steps)
    model = load_model("geodetic_vertical")
    flights = lat0.size
    p = np.stack([model.parameter_vector(a=a, e2=1 - (b / a) ** 2, orth_latitude=la,
                                         orth_longitude=lo, orth_angle=an)
                  for la, lo, an in zip(lat0, lon0, ang0, strict=True)], axis=1)
    section = _Section(_start_frames(lat0, lon0, ang0), np.array([a**-2, b**-2, a**-2]),
                       np.full(flights, float(speed)), EARTH_RATE)
    c = flattening_constant(a, b)
    rhs_model = model.numpy.ideal_rhs

    def rhs(y, u, Phi, Lam):
        """The model's dx/dt at its state y (closed loop) or at the true (Φ, Λ) with y's
        velocity (the paper's setting)."""
        state = y if closed_loop else np.vstack([Phi, Lam, y[2:]])
        return rhs_model(state, u, p)

    records = n_steps // stride + 1
    out = {k: np.empty((records, flights)) for k in ("Phi", "Lam", "Phi_c", "Lam_c", "B", "N")}
    # Λ1 obeys its own equation (Λ̇1 depends on Λ1 alone) and the measurements depend on
    # Λ1 alone: per block of steps, Λ1 is stepped first (the RK4 of the whole state
    # (Λ1, model state) row by row, so the same bits), the measurements at every stage
    # are evaluated at once, and only the model's equations step one by one.
    y = None  # the model's state (start: the true geodetic coordinates and velocity)
    lam = np.zeros(flights)
    for first in range(0, n_steps, _BLOCK_STEPS):
        steps = min(_BLOCK_STEPS, n_steps - first)
        angles, lam = _stage_angles(section, lam, steps, step)
        u, (Phi, Lam, W, B, N), _ = section.repeated(4 * steps + 1).measurements(
            angles.ravel(), gravity)
        u = u.reshape(4, 4 * steps + 1, flights)
        Phi, Lam, B, N = (v.reshape(4 * steps + 1, flights) for v in (Phi, Lam, B, N))
        if y is None:
            y = np.vstack([Phi[0], Lam[0], W[:, :flights]])
            start_state = (B[0].copy(), N[0].copy(), Phi[0].copy())
            _record(out, 0, y, Phi[0], Lam[0], B[0], N[0])

        for k in range(steps):
            row = 4 * k
            k1 = rhs(y, u[:, row], Phi[row], Lam[row])
            k2 = rhs(y + 0.5 * step * k1, u[:, row + 1], Phi[row + 1], Lam[row + 1])
            k3 = rhs(y + 0.5 * step * k2, u[:, row + 2], Phi[row + 2], Lam[row + 2])
            k4 = rhs(y + step * k3, u[:, row + 3], Phi[row + 3], Lam[row + 3])
            y = y + step / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            if (first + k + 1) % stride == 0:
                row += 4
                _record(out, (first + k + 1) // stride, y, Phi[row], Lam[row], B[row], N[row])
    if not all(np.all(np.isfinite(v)) for v in out.values()):
        raise DomainError("the simulated flight left the domain (NaN): does it pass a pole?")
    wrap = lambda angle: (angle + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
    direct = np.stack([out["Phi"] - out["Phi_c"], wrap(out["Lam"] - out["Lam_c"])])
    B0, N0, Phi0 = start_state
    printed = np.stack(formula_10(out["B"], out["N"], out["Phi"], c, B0, N0, Phi0))
    completed = np.stack(formula_10(out["B"], out["N"], out["Phi"], c, B0, N0, Phi0,
                                    start_term=True))
    times = np.arange(records) * stride * step
    return FlightErrors(times, np.stack([lat0, lon0, ang0]), out["B"], out["N"], direct,
                        printed, completed, out["Phi"], a)


_BLOCK_STEPS = 512
"""Steps of :func:`simulate_flights` whose measurements are evaluated in one call."""


def _stage_angles(section: _Section, lam: np.ndarray, steps: int, step: float):
    """Λ1 at the four RK4 stages of ``steps`` steps from ``lam`` (rows 4 k + stage) and
    after the last step (last row), shape (4 steps + 1, B), and Λ1 after the last step."""
    rate = section.angle_rate
    angles = np.empty((4 * steps + 1, lam.size))
    for k in range(steps):
        k1 = rate(lam)
        lam2 = lam + 0.5 * step * k1
        k2 = rate(lam2)
        lam3 = lam + 0.5 * step * k2
        k3 = rate(lam3)
        lam4 = lam + step * k3
        k4 = rate(lam4)
        angles[4 * k:4 * k + 4] = lam, lam2, lam3, lam4
        lam = lam + step / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    angles[-1] = lam
    return angles, lam


def _record(out: dict[str, np.ndarray], j: int, y: np.ndarray, Phi, Lam, B, N) -> None:
    """Record j: true (Φ, Λ, B, N) and the computed (Φ, Λ) (the model state's first rows)."""
    for key, value in (("Phi", Phi), ("Lam", Lam), ("Phi_c", y[0]), ("Lam_c", y[1]),
                       ("B", B), ("N", N)):
        out[key][j] = value


@cache
def _formula_9():
    """The correction rates (9) of the model ``geodetic_vertical`` as a numpy function
    ``f(x, u, p)`` (lambdified once: the expansion is the same for every flight)."""
    import sympy as sp

    from ins_errors.models import definition

    d = definition("geodetic_vertical")
    named = {df.symbol.name: df.symbol for df in d.ideal.definitions}
    rates = sp.Matrix([d.ideal.expand(named[n]) for n in ("Omega_xi", "Omega_eta",
                                                            "Omega_zeta")])
    return sp.lambdify([d.x, d.u, d.p], rates, "numpy")


def correction_rate_error(start_latitude: float, start_longitude: float,
                          orthodrome_angle: float, section_angles, speed: float = 250.0,
                          a: float | None = None, b: float | None = None) -> np.ndarray:
    """Platform correction rates (9) minus the true absolute rate of the geodetic frame.

    The paper states that with the full formulas (9) the platform holds the geodetic
    vertical. Here the rates (9) of the model ``geodetic_vertical`` (its symbolic
    definition, evaluated at the true position and velocity) are compared with the
    absolute angular rate of the exact geodetic frame along the central-section flight
    (central differences of its axes, plus the Earth rate).

    Parameters
    ----------
    start_latitude, start_longitude, orthodrome_angle : float
        Geocentric φ0, λ0 and N0 of the orthodrome, rad.
    section_angles : array_like, shape (K,)
        Points of the flight: geocentric orthodromic longitudes Λ1, rad.
    speed : float
        Ground speed, m/s.

    Returns
    -------
    numpy.ndarray, shape (3, K)
        Ω(9) − Ω_true on ξ, η, ζ, rad/s.
    """
    if a is None or b is None:
        a, b = krasovsky_axes()
    _check_axes(a, b)
    formula_9 = _formula_9()
    model = load_model("geodetic_vertical")
    p = model.parameter_vector(a=a, e2=1 - (b / a) ** 2, orth_latitude=start_latitude,
                               orth_longitude=start_longitude, orth_angle=orthodrome_angle)
    one = np.ones(1)
    section = _Section(_start_frames(start_latitude * one, start_longitude * one,
                                     orthodrome_angle * one), np.array([a**-2, b**-2, a**-2]),
                       speed * one, EARTH_RATE)

    def axes(lam1: float) -> np.ndarray:
        r, *_ = section.kinematics(np.array([lam1]))
        return section.geodetic(r)[2][0]

    out = []
    h = 1e-5
    for lam1 in np.atleast_1d(np.asarray(section_angles, dtype=float)):
        M = axes(lam1)
        *_, lam_dot = section.kinematics(np.array([lam1]))
        K = (axes(lam1 + h) - axes(lam1 - h)) / (2 * h) @ M.T * lam_dot[0]
        true_rate = np.array([K[1, 2], -K[0, 2], K[0, 1]]) + EARTH_RATE * M[:, 1]
        u, (Phi, Lam, W, _B, _N), _ = section.measurements(np.array([lam1]), 9.81)
        x = np.array([Phi[0], Lam[0], W[0, 0], W[1, 0]])
        out.append(np.asarray(formula_9(x, u[:, 0], p), dtype=float).ravel() - true_rate)
    return np.array(out).T


SURVEY_RECORD_STEPS = 60
"""Steps between two recorded samples of :func:`survey` when that divides the run."""


def survey_stride(n_steps: int) -> int:
    """Recording stride of :func:`survey`: the recording interval follows the step.

    Every :data:`SURVEY_RECORD_STEPS` steps when that divides the run; otherwise (a coarse
    step, e.g. 300 s over 2 h) the largest divisor of the step count that leaves at least
    six recorded intervals (every step for a run of fewer than twelve steps).

    Parameters
    ----------
    n_steps : int
        Steps of the run.

    Returns
    -------
    int
        Steps between two recorded samples; it divides ``n_steps``.
    """
    if n_steps % SURVEY_RECORD_STEPS == 0:
        return SURVEY_RECORD_STEPS
    cap = max(1, min(SURVEY_RECORD_STEPS, n_steps // 6))
    return max(d for d in range(1, cap + 1) if n_steps % d == 0)


def survey(latitudes_deg=(0.0, 20.0, 45.0, 60.0), angles_deg=(30.0, 90.0, 150.0, 225.0),
           duration: float = 6 * 3600.0, speed: float = 250.0, step: float = 10.0
           ) -> tuple[FlightErrors, list[str]]:
    """Flights from several latitudes along several orthodrome angles; report lines.

    The table's rows are also kept as numbers in the result's ``flights``, one dict per
    flight: ``start_latitude_rad``, ``orthodrome_angle_rad`` (start), ``geometric_max_m``
    (largest direct displacement), ``mismatch_completed_max_m`` and
    ``mismatch_printed_max_m`` (largest |direct − (10)| completed / as printed, either
    coordinate), ``closed_loop_max_m`` (largest displacement with the coefficients at the
    computed position), ``integration_error_rad`` ([ΔΦ, ΔΛ], or None).
    """
    la, an = np.meshgrid(np.radians(latitudes_deg), np.radians(angles_deg), indexing="ij")
    stride = survey_stride(step_count(duration, step))
    result = simulate_flights(la.ravel(), np.zeros(la.size), an.ravel(), duration, speed, step,
                              record_interval=stride * step)
    integration = integration_errors(result, duration, speed, step, stride)
    if all(len(c.metrics) == 2 for c in integration):
        result.integration_error = np.array([[m.integration_error for m in c.metrics]
                                             for c in integration]).T
    result.warnings = [w for c in integration for w in c.warnings]
    closed = simulate_flights(la.ravel(), np.zeros(la.size), an.ravel(), duration, speed, step,
                              record_interval=stride * step, closed_loop=True)
    worst = result.mismatch_km("completed")
    worst_printed = result.mismatch_km("printed")
    largest = result.largest_km()
    closed_largest = closed.largest_km()
    peak = formula_10_maximum()
    lines = [
        f"formula (10), ν1⁰ = 0: max |ΔΦ| a = {peak['dPhi_km']:.2f} km, max displacement "
        f"{peak['total_km']:.2f} km at B = ±{peak['latitude_deg']:.1f}° (paper: about 22 km; "
        "this is the current-point term of (10) alone)",
        f"direct simulation, {speed:g} m/s for {duration / 3600:g} h, step {step:g} s "
        "(errors in km; 'geometric': coefficients of (9) at the true position, as in the "
        "paper; 'closed loop': at the computed position)",
        "φ0: geocentric start latitude; N0: the paper's orthodrome angle at the start "
        "(n32 = −sin φ0): from a northern start, 0° and 180° start along the parallel, 90° "
        "toward the equator, 270° toward the pole",
        "   φ0°     N0°   geometric   |direct − (10) completed|   |direct − (10) printed|"
        "   closed loop",
    ]
    for k in range(la.size):
        result.flights.append({
            "start_latitude_rad": float(result.start[0, k]),
            "orthodrome_angle_rad": float(result.start[2, k]),
            "geometric_max_m": float(largest[k] * 1000),
            "mismatch_completed_max_m": float(worst[k] * 1000),
            "mismatch_printed_max_m": float(worst_printed[k] * 1000),
            "closed_loop_max_m": float(closed_largest[k] * 1000),
            "integration_error_rad": (None if result.integration_error is None else
                                      [float(e) for e in result.integration_error[:, k]])})
        lines.append(f"  {np.degrees(result.start[0, k]):5.1f}  "
                     f"{np.degrees(result.start[2, k]):6.1f}   {largest[k]:9.3f}   "
                     f"{worst[k]:24.3f}   {worst_printed[k]:23.3f}   {closed_largest[k]:11.3f}")
    lines.append(f"largest geometric error over all flights {largest.max():.2f} km (current-"
                 "point term plus the start-point term of the completed (10); the paper's "
                 "≈ 22 km bounds the current-point term alone, so a long flight can exceed it); "
                 f"worst mismatch with completed (10) {worst.max():.3f} km; "
                 f"closed loop up to {closed_largest.max():.2f} km")
    lines += integration_lines(result, integration)
    deg_h = np.pi / 180 / 3600
    rate = max(np.abs(correction_rate_error(lat, 0.0, ang, np.linspace(0, 0.6, 7), speed)).max()
               for lat, ang in zip(la.ravel(), an.ravel(), strict=True))
    lines.append(f"correction rates (9) vs the true rate of the geodetic frame: up to "
                 f"{rate / deg_h:.3f} °/h at {speed:g} m/s (R is not a radius of curvature: "
                 "the platform does not hold the geodetic vertical exactly)")
    return result, lines


def integration_errors(result: FlightErrors, duration: float, speed: float, step: float,
                       stride: int, a: float | None = None,
                       b: float | None = None) -> list[Comparison]:
    """The direct flights' integration error, per flight, estimated as ``compare`` does.

    The flights are flown again at τ/2 or 2τ (every recorded sample on the other grid)
    and at a third step for the observed order of RK4, by
    :func:`ins_errors.numeric.compare.integration_errors_by_reruns` (the machinery of
    ``compare``), formula (10) completed playing the part of the linear model: each
    flight's comparison gets the integration error of ΔΦ and ΔΛ (rad) and a warning
    when it exceeds 10 % of |direct − (10)| or 1 % of the error, or when the estimate
    is not reliable at this step (observed order far from 4), with a step that would do.

    Parameters
    ----------
    result : FlightErrors
        The flights at ``step``, recorded every ``stride`` steps.
    duration, speed, step : float
        As given to :func:`simulate_flights`, s, m/s, s.
    stride : int
        Recording stride of ``result``.
    a, b : float, optional
        Semi-axes of the flights, m (default Krasovsky).
    """
    n_steps = step_count(duration, step)
    fine = (_curves(result, result.direct), _curves(result, result.completed))
    comparisons = [Comparison(f"flight {k}", {}, metrics_of(fine[0], fine[1], None, k),
                              result.times, {}, {}, {})
                   for k in range(result.start.shape[1])]

    def rerun(factor: float, every: int) -> tuple[ErrorCurves, ErrorCurves]:
        steps = 2 * n_steps if factor < 1 else n_steps // factor
        again = simulate_flights(result.start[0], result.start[1], result.start[2],
                                 steps * factor * step, speed, factor * step,
                                 record_interval=every * factor * step, a=a, b=b)
        return _curves(again, again.direct), _curves(again, again.completed)

    integration_errors_by_reruns(comparisons, fine, n_steps, step, stride, "rk4", rerun)
    return comparisons


def _curves(result: FlightErrors, values: np.ndarray) -> ErrorCurves:
    return ErrorCurves(["delta_Phi", "delta_Lambda"], ["rad", "rad"], result.times, values)


def integration_lines(result: FlightErrors, comparisons: list[Comparison]) -> list[str]:
    """Report lines: the largest integration error beside the mismatch with (10)."""
    errors = [m.integration_error for c in comparisons for m in c.metrics
              if m.integration_error is not None]
    if not errors:
        return [w for c in comparisons for w in c.warnings][:1]
    km = max(errors) * result.a / 1000
    lines = [f"integration error of the direct flights (step doubling): up to {km:.2g} km, "
             f"beside a worst mismatch with completed (10) of "
             f"{result.mismatch_km('completed').max():.3g} km"]
    warned = [(k, c.warnings) for k, c in enumerate(comparisons) if c.warnings]
    if warned:
        k, warnings = warned[0]
        lines.append(f"warning ({len(warned)} of {len(comparisons)} flights; flight from "
                     f"φ0 = {np.degrees(result.start[0, k]):.4g}°, N0 = "
                     f"{np.degrees(result.start[2, k]):.4g}°): {warnings[0]}")
    return lines


PLOT_FLOOR_KM = 0.05
"""Smallest y range of a panel of :func:`plot`, km: errors below it (rounding, ~1e-15 km
where a coordinate is not excited) are drawn flat, not blown up into a diverging curve."""


ANGLE_CAPTION = ("N0: orthodrome angle at the start, between the geographic meridian and "
                 "the orthodromic one (source 004's N)")
"""How :func:`plot` defines the N0 of its panel titles."""


def plot(result: FlightErrors, path: str | Path) -> Path:
    """Save every flight's displacement: direct simulation against formula (10).

    One panel per flight (rows: start latitude, columns: orthodrome angle, as
    :func:`survey` flies them), each with the displacement √(ΔΦ² + (ΔΛ cos Φ)²)·a in km
    of the direct simulation, of (10) with the start-point term and of (10) as printed.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ins_errors.figure_layout import (
        common_time_range,
        fixed_margins,
        share_time_axis,
        text_width,
        wrap_to_width,
    )

    hours = result.times / 3600
    direct, printed, completed = (np.hypot(*result.km(e)) for e in
                                  (result.direct, result.printed, result.completed))
    latitudes = sorted(set(np.round(np.degrees(result.start[0]), 6)))
    angles = sorted(set(np.round(np.degrees(result.start[2]), 6)))
    rows, cols = len(latitudes), len(angles)
    # no sharex and no tight_layout (each lays out every panel's tick labels again,
    # see ins_errors.figure_layout): every flight has the same times, and fixed margins
    # fit the labels
    width = 3.0 * cols + 0.6
    fig, axes = plt.subplots(rows, cols, figsize=(width, 2.1 * rows + 1.2), squeeze=False)
    share_time_axis(axes)
    # a narrow figure (few angles) breaks the title into lines and stacks the legend
    title = wrap_to_width(f"004: spherical-formula reckoning over the Krasovsky spheroid, every "
                  f"flight ({direct.shape[1]}): direct simulation vs formula (10)\n"
                  f"φ0: geocentric start latitude; {ANGLE_CAPTION}", 10, width - 0.3)
    names = ["direct simulation", "(10) completed (start term of ΔΛ)", "(10) as printed"]
    ncol = 3 if text_width(names, 8) * 3 + 3 * 3.8 * 8 / 72 < width - 0.3 else 1
    fixed_margins(fig, left=0.7, right=0.15, bottom=0.9 + (0.3 if ncol == 1 else 0.0),
                  top=max(0.9, 0.6 + 1.2 * 10 / 72 * (title.count("\n") + 1)),
                  wspace=0.5, hspace=0.38)
    for ax in axes.flat:
        ax.set_visible(False)
    for f in range(direct.shape[1]):
        r = latitudes.index(np.round(np.degrees(result.start[0, f]), 6))
        c = angles.index(np.round(np.degrees(result.start[2, f]), 6))
        ax = axes[r, c]
        ax.set_visible(True)
        ax.plot(hours, direct[:, f], color="black", lw=1.6, label=names[0])
        ax.plot(hours, completed[:, f], "--", color="tab:orange", lw=1.0, label=names[1])
        ax.plot(hours, printed[:, f], ":", color="tab:blue", lw=1.0, label=names[2])
        top = max(PLOT_FLOOR_KM, float(np.nanmax([direct[:, f], completed[:, f],
                                                  printed[:, f]])) * 1.08)
        ax.set_ylim(0, top)
        ax.ticklabel_format(axis="y", useOffset=False, style="plain")
        ax.grid(True, alpha=0.3)
        ax.tick_params(labelsize=7)
        ax.set_title(f"φ0 = {latitudes[r]:g}°, N0 = {angles[c]:g}°", fontsize=8)
        if c == 0:
            ax.set_ylabel("displacement, km", fontsize=8)
        if r == rows - 1:
            ax.set_xlabel("time, h", fontsize=8)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=8)
    fig.suptitle(title, fontsize=10)
    common_time_range(ax for ax in axes.flat if ax.get_visible())
    return save_figure(fig, path, dpi=100)

