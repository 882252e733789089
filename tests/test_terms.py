"""Term sizes along a trajectory, checked against hand-computable terms."""

from __future__ import annotations

import numpy as np
import pytest

from ins_errors.numeric.terms import droppable_terms, term_sizes
from tests.helpers import static_inputs


def test_term_sizes_at_static_base(orthodromic):
    model = orthodromic
    p = model.parameter_vector()
    c = model.initial_condition_vector(latitude=np.radians(45), heading=0.0)
    x = model.initial_state(c, model.input_vector(), p)
    u = static_inputs(model, x, p)
    X, Uu = np.repeat(x[:, None], 3, axis=1), np.repeat(u[:, None], 3, axis=1)
    xe = np.zeros((11, 3))
    xe[model.index("error_states", "delta_V_eta")] = [0.0, 1.0, 0.5]  # m/s
    w = model.source_vector(gyro_drift_x=np.radians(0.01) / 3600)
    sizes = {(s.equation, s.term): s for s in term_sizes(model, X, Uu, xe, w, p)}
    drift = sizes[("alpha_x", "G[gyro_drift_x]")]
    assert drift.peak == pytest.approx(np.radians(0.01) / 3600, rel=1e-12)
    # ΔV_η = 1 m/s tilts the commanded rate by 1/R_η ≈ 1/6.37e6 rad/s
    transport = sizes[("alpha_x", "F[delta_V_eta]")]
    assert transport.peak == pytest.approx(1 / 6.37e6, rel=5e-3)
    assert transport.relative == 1.0  # the largest term of that equation
    small = droppable_terms(term_sizes(model, X, Uu, xe, w, p), threshold=1.0)
    assert ("alpha_x", "G[gyro_drift_x]") in {(s.equation, s.term) for s in small}
