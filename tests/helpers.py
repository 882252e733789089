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
