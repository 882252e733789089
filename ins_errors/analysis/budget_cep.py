r"""Circular error probable of a normal horizontal position error (``combine = "cep"``).

The CEP of a zero-mean normal error :math:`x \in \mathbb{R}^2` of covariance
:math:`P = \begin{pmatrix} \sigma_N^2 & c \\ c & \sigma_E^2 \end{pmatrix}` is the radius
r with :math:`P(|x| < r) = 1/2`. With :math:`\lambda_1 \ge \lambda_2 \ge 0` the
eigenvalues of P (the squared half-axes of the error ellipse; the north-east cross term c
turns the ellipse and changes these lengths too, so the CEP needs c as well as the
diagonal) and :math:`z_1, z_2` independent standard
normals,

.. math::

    P(|x| < r) = P(\lambda_1 z_1^2 + \lambda_2 z_2^2 < r^2)
    = 2\int_0^{r/\sqrt{\lambda_2}} \varphi(z)\,
      \operatorname{erf}\sqrt{\frac{r^2 - \lambda_2 z^2}{2\lambda_1}}\,dz,

a one-dimensional integral of smooth functions (:func:`inside_probability`; the
substitution :math:`z = (r/\sqrt{\lambda_2}) \sin u` removes the square root's end point,
and beyond nine standard deviations :math:`\varphi` is below 1e-18). The CEP is its root
in r (:func:`cep`), found by bisection between the two bounds every ellipse lies within:
:data:`CEP_PER_SIGMA_LINE` :math:`\sqrt{\lambda_1}` (a line, :math:`\lambda_2 = 0`: the
median of :math:`|z_1|`) and :data:`CEP_PER_SIGMA_CIRCLE` :math:`\sqrt{\lambda_1}` (a
circle of that radius).

Two properties the budget relies on: the CEP scales with the magnitudes (P scaled by
s² scales it by s, exactly: it depends on :math:`\lambda_2/\lambda_1` and
:math:`\sqrt{\lambda_1}` alone), and it grows with P in the Loewner order (Anderson's
theorem: a larger covariance puts less probability in any centred disc), so a bound on
the covariance bounds it. Against DRMS :math:`= \sqrt{\sigma_N^2 + \sigma_E^2}` it lies
between :data:`CEP_PER_DRMS_LINE` DRMS (a line) and :data:`CEP_PER_DRMS_CIRCLE` DRMS (a
circle): the familiar 0.8326·DRMS holds for a circular error only.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import erf, erfinv

CEP_PER_SIGMA_CIRCLE = math.sqrt(2.0 * math.log(2.0))
"""1.1774: the CEP of a circular normal error per its σ on each axis (1 − e^(−r²/2σ²) =
1/2)."""

CEP_PER_SIGMA_LINE = math.sqrt(2.0) * float(erfinv(0.5))
"""0.6745: the CEP of an error along one line per its σ (the median of |z|)."""

CEP_PER_DRMS_CIRCLE = CEP_PER_SIGMA_CIRCLE / math.sqrt(2.0)
"""0.8326 = √(ln 2): CEP / DRMS of a circular error, the largest over all ellipses."""

CEP_PER_DRMS_LINE = CEP_PER_SIGMA_LINE
"""0.6745: CEP / DRMS of an error along one line, the smallest."""

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(64)
_TAIL = 9.0
"""Standard deviations beyond which the normal density (1e-18) adds nothing."""

_BISECTIONS = 53
"""Halvings of the bracket [0.6745, 1.1774] √λ₁: to its last bit."""


def _axes(north, east, cross) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues λ₁ ≥ λ₂ ≥ 0 of [[north, cross], [cross, east]], elementwise."""
    north, east, cross = (np.asarray(v, dtype=float) for v in (north, east, cross))
    mean = 0.5 * (north + east)
    spread = np.hypot(0.5 * (north - east), cross)
    return np.maximum(mean + spread, 0.0), np.clip(mean - spread, 0.0, None)


def _inside(ratio: np.ndarray, m: np.ndarray) -> np.ndarray:
    """P(z₁² + m z₂² < ratio²), elementwise (ratio = r/√λ₁, m = λ₂/λ₁ in [0, 1])."""
    ratio, m = np.broadcast_arrays(np.asarray(ratio, float), np.asarray(m, float))
    out = np.empty(ratio.shape)
    line = m <= 0.0
    out[line] = erf(ratio[line] / math.sqrt(2.0))
    reach = np.divide(ratio, np.sqrt(m), out=np.full(ratio.shape, np.inf), where=~line)
    near = ~line & (reach <= _TAIL)
    if near.any():   # z = reach sin u, u in [0, π/2]: r² − m z² = r² cos² u, no root
        r, end = ratio[near][:, None], reach[near][:, None]
        u = 0.25 * np.pi * (_NODES + 1.0)
        inner = (erf(r * np.cos(u) / math.sqrt(2.0)) * np.exp(-0.5 * (end * np.sin(u)) ** 2)
                 * end * np.cos(u))
        out[near] = 0.25 * np.pi * (inner @ _WEIGHTS) * math.sqrt(2.0 / np.pi)
    far = ~line & ~near
    if far.any():    # z in [0, 9]: the density ends the integral before the root
        r, mm = ratio[far][:, None], m[far][:, None]
        z = 0.5 * _TAIL * (_NODES + 1.0)
        inner = erf(np.sqrt(np.clip(r**2 - mm * z**2, 0.0, None) / 2.0)) * np.exp(-0.5 * z**2)
        out[far] = 0.5 * _TAIL * (inner @ _WEIGHTS) * math.sqrt(2.0 / np.pi)
    return np.clip(out, 0.0, 1.0)


def inside_probability(radius, north, east, cross) -> np.ndarray:
    """Probability that a zero-mean normal horizontal error lies within ``radius``.

    Parameters
    ----------
    radius : float or numpy.ndarray
        m (or any length unit, the covariance's square root's).
    north, east : float or numpy.ndarray
        Variances of the north and east components, unit².
    cross : float or numpy.ndarray
        Their covariance, unit² (|cross| ≤ √(north · east)).

    Returns
    -------
    numpy.ndarray
        P(|x| < radius), broadcast over the arguments; 1 where the error is zero and
        the radius positive.
    """
    major, minor = _axes(north, east, cross)
    radius = np.asarray(radius, dtype=float)
    radius, major, minor = np.broadcast_arrays(radius, major, minor)
    out = np.where(radius > 0, 1.0, 0.0)
    live = major > 0
    if live.any():
        out = out.astype(float)
        out[live] = _inside(radius[live] / np.sqrt(major[live]),
                            minor[live] / major[live])
    return out


def cep(north, east, cross) -> np.ndarray:
    """CEP of a zero-mean normal horizontal error: the radius holding it with
    probability 1/2.

    Parameters
    ----------
    north, east : float or numpy.ndarray
        Variances of the north and east components, unit² (broadcast together).
    cross : float or numpy.ndarray
        Their covariance, unit².

    Returns
    -------
    numpy.ndarray
        The CEP, unit, to about 1e-15 relative; 0 where the error is zero. It scales
        with the square root of the covariance exactly and grows with it (module
        docstring).
    """
    major, minor = _axes(north, east, cross)
    out = np.zeros(major.shape)
    live = major > 0
    if not live.any():
        return out
    m = minor[live] / major[live]
    low = np.full(m.shape, CEP_PER_SIGMA_LINE)
    high = np.full(m.shape, CEP_PER_SIGMA_CIRCLE)
    for _ in range(_BISECTIONS):
        middle = 0.5 * (low + high)
        below = _inside(middle, m) < 0.5
        low = np.where(below, middle, low)
        high = np.where(below, high, middle)
    out[live] = 0.5 * (low + high) * np.sqrt(major[live])
    return out
