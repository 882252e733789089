"""Random admissible points and consistent inputs for the physics tests."""

from __future__ import annotations

import numpy as np

import ins_errors


def static_inputs(model: ins_errors.Model, x: np.ndarray, p: np.ndarray, h: float = 0.0,
                  g: float = 9.81) -> np.ndarray:
    """Inputs that keep the ideal velocities constant at state x (V̇ = 0)."""
    u = model.input_vector(a_zeta=g, h=h)
    rates = model.numpy.ideal_rhs(x, u, p)
    u[0], u[1] = -rates[6], -rates[7]
    return u


def random_points(model: ins_errors.Model, count: int, seed: int, moving: bool):
    """Random admissible (x, u, p) triples, static base or moving."""
    rng = np.random.default_rng(seed)
    p = model.parameter_vector()
    points = []
    for _ in range(count):
        c = model.initial_condition_vector(
            latitude=np.radians(rng.uniform(-80, 80)),
            longitude=np.radians(rng.uniform(-180, 180)),
            heading=np.radians(rng.uniform(-180, 180)),
            v_N=rng.uniform(-300, 300) if moving else 0.0,
            v_E=rng.uniform(-300, 300) if moving else 0.0,
        )
        h = rng.uniform(0, 12000) if moving else rng.uniform(0, 500)
        u = model.input_vector(h=h)
        x = model.initial_state(c, u, p)
        if moving:
            u = model.input_vector(a_xi=rng.uniform(-5, 5), a_eta=rng.uniform(-5, 5),
                                   a_zeta=rng.uniform(7, 13), V_zeta=rng.uniform(-20, 20), h=h)
        else:
            u = static_inputs(model, x, p, h=h)
        points.append((x, u, p))
    return points


def central_difference(f, at: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """Jacobian of ``f`` at ``at`` by central differences, one step per component."""
    columns = []
    for j, step in enumerate(steps):
        delta = np.zeros_like(at)
        delta[j] = step
        columns.append((f(at + delta) - f(at - delta)) / (2 * step))
    return np.stack(columns, axis=1)


def row_relative_error(approx: np.ndarray, exact: np.ndarray) -> float:
    """Largest row-wise error relative to the row's largest entry (zero rows must match)."""
    worst = 0.0
    for a_row, e_row in zip(approx, exact, strict=True):
        scale = np.abs(e_row).max()
        if scale == 0:
            assert np.abs(a_row).max() < 1e-12
            continue
        worst = max(worst, np.abs(a_row - e_row).max() / scale)
    return worst


def source_steps(model: ins_errors.Model) -> np.ndarray:
    """Finite-difference step per error source, by its SI unit."""
    scale = {"rad": 1e-6, "rad/s": 1e-9, "m/s**2": 1e-6, "m/s": 1e-3, "1": 1e-6}
    return np.array([scale[s.unit] for s in model.sources])
