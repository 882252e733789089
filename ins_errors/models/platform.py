r"""Kinematics of a gyro-stabilised platform relative to the trihedron it should hold.

Every platform model (orthodromic, north-pointing, free-azimuth, geodetic-vertical) has
the same instrument part: a platform turning at the rate its gyros are torqued with
(commanded rate through the correction loop, plus drift), and accelerometers on it that
see the true specific force resolved on the platform axes. This module writes that part
once, in two forms:

``"exact"`` (the default truth of a direct run)
    The platform's attitude relative to the reference trihedron is the rotation
    ``C = R_z(α_z) R_y(α_y) R_x(α_x)`` (platform axes → trihedron axes; the angles are
    the z-y-x Euler angles of the platform). The specific force on the platform axes is
    ``f^p = Cᵀ f`` exactly, and the angles obey the exact Euler kinematics of the
    relative rate ``ω_rel = ω_platform − Cᵀ ω_trihedron``:

    .. math::

       \dot\alpha_x = ω_x + \tan α_y (\sin α_x ω_y + \cos α_x ω_z), \quad
       \dot\alpha_y = \cos α_x ω_y − \sin α_x ω_z, \quad
       \dot\alpha_z = (\sin α_x ω_y + \cos α_x ω_z) / \cos α_y.

    Any attitude is represented except α_y = ±90° (the Euler angles' singular point),
    so large tilts and azimuth errors up to ±180° run without approximation.

``"small_angle"`` (the source documents' form)
    ``f^p = f − α × f`` and ``α̇ = α × ω_trihedron + (ω_platform − ω_trihedron)``: the
    first-order expansion of the exact form around α = 0. The linear error equations
    are identical for both forms; the second-order (refined) terms of the exact form
    include the rotation's own second-order terms.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

PLATFORM_FORMS: tuple[str, ...] = ("exact", "small_angle")
"""Names of the platform forms; ``"exact"`` is the default truth."""


def _check(form: str) -> None:
    if form not in PLATFORM_FORMS:
        from ins_errors.errors import unknown_name

        raise unknown_name("platform form", form, PLATFORM_FORMS)


def _axis_rotations(alpha: Sequence[sp.Expr]) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """``R_x(α_x)``, ``R_y(α_y)``, ``R_z(α_z)``: the three plane rotations of ``C``."""
    ax, ay, az = alpha
    rx = sp.Matrix([[1, 0, 0], [0, sp.cos(ax), -sp.sin(ax)], [0, sp.sin(ax), sp.cos(ax)]])
    ry = sp.Matrix([[sp.cos(ay), 0, sp.sin(ay)], [0, 1, 0], [-sp.sin(ay), 0, sp.cos(ay)]])
    rz = sp.Matrix([[sp.cos(az), -sp.sin(az), 0], [sp.sin(az), sp.cos(az), 0], [0, 0, 1]])
    return rx, ry, rz


def platform_to_reference(alpha: Sequence[sp.Expr]) -> sp.Matrix:
    """``C = R_z(α_z) R_y(α_y) R_x(α_x)``: platform axes → reference-trihedron axes."""
    rx, ry, rz = _axis_rotations(alpha)
    return rz * ry * rx


def on_platform(alpha: Sequence[sp.Expr], vector: Sequence[sp.Expr],
                form: str = "exact") -> list[sp.Expr]:
    """A vector given on the reference-trihedron axes, resolved on the platform axes.

    Parameters
    ----------
    alpha : sequence of 3 sympy.Expr
        Platform angles (α_x, α_y, α_z), rad.
    vector : sequence of 3 sympy.Expr
        Components on the trihedron axes (e.g. the true specific force, m/s²).
    form : {"exact", "small_angle"}

    Returns
    -------
    list of 3 sympy.Expr
        Components on the platform axes.
    """
    _check(form)
    v = sp.Matrix(vector)
    if form == "small_angle":
        return list(v - sp.Matrix(alpha).cross(v))
    # Cᵀ v as three plane rotations in turn (fewer operations than forming C)
    rx, ry, rz = _axis_rotations(alpha)
    return list(rx.T * (ry.T * (rz.T * v)))


def platform_rates(alpha: Sequence[sp.Expr], platform_rate: Sequence[sp.Expr],
                   reference_rate: Sequence[sp.Expr], form: str = "exact") -> list[sp.Expr]:
    """Time derivatives of the platform angles.

    Parameters
    ----------
    alpha : sequence of 3 sympy.Expr
        Platform angles (α_x, α_y, α_z), rad.
    platform_rate : sequence of 3 sympy.Expr
        Absolute rate of the platform on its own axes (torquing command through the
        correction loop, plus gyro drift), rad/s.
    reference_rate : sequence of 3 sympy.Expr
        Absolute rate of the reference trihedron on its own axes, rad/s.
    form : {"exact", "small_angle"}

    Returns
    -------
    list of 3 sympy.Expr
        (α̇_x, α̇_y, α̇_z), rad/s.
    """
    _check(form)
    ay = alpha[1]
    wp, wt = sp.Matrix(platform_rate), sp.Matrix(reference_rate)
    if form == "small_angle":
        return list(sp.Matrix(alpha).cross(wt) + (wp - wt))
    # q = R_x ω_rel = R_x ω_platform − R_yᵀ R_zᵀ ω_trihedron (R_x Cᵀ = R_yᵀ R_zᵀ): the
    # same rates as written in the module docstring, in fewer operations
    rx, ry, rz = _axis_rotations(alpha)
    q = rx * wp - ry.T * (rz.T * wt)
    return [q[0] + sp.tan(ay) * q[2], q[1], q[2] / sp.cos(ay)]
