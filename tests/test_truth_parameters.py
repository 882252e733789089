"""A true motion is compiled once for every value of a parameter it never reads.

The truth's compiled functions have the model parameters written into their C code and
are cached on their values; a damping gain, which the true motion never reads (it is
the ideal work's, steered by the motion), made a gain sweep along a moving base compile
a truth per gain value. Checked on a damped platform INS (tests/models/damped_ins.py,
gains k_v and k_p) flying a sampled motion: one compiled truth loop for three gains, the
same truth to the last bit, and the gains' own effect on the errors intact.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ins_errors import load_model
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate

DAMPED = Path(__file__).resolve().parent / "models" / "damped_ins.py"


def _profile() -> tr.Profile:
    t = np.linspace(0.0, 1200.0, 41)
    v_n = 150.0 + 20.0 * np.sin(2 * np.pi * t / 600.0)
    v_e = 60.0 * np.cos(2 * np.pi * t / 900.0)
    return tr.sampled_profile(t, v_n, v_e, np.radians(47.0), np.radians(8.0), 0.0, 500.0)


def test_a_gain_sweep_along_a_moving_base_flies_one_compiled_truth():
    model = load_model(str(DAMPED))
    names = [p.name for p in model.parameters]
    mask = tr._truth_parameter_mask(model.key, "geographic")
    assert not mask[names.index("k_v")] and not mask[names.index("k_p")]
    assert all(mask[i] for i, n in enumerate(names) if n not in ("k_v", "k_p"))
    tr._truth_loop.cache_clear()
    flights, runs = [], []
    for k_v in (0.0, 1e-3, 4e-3):
        p = model.parameter_vector(k_v=k_v)
        flight = tr.trajectory(model, _profile(), 1200.0, 0.5, p=p, stream=False)
        flights.append(flight)
        runs.append(simulate(model, flight, {model.sources[0].name: 1e-3}, method="rk4",
                             record_interval=60.0, parts=("real",)))
    assert tr._truth_loop.cache_info().currsize == 1    # one truth for the three gains
    for flight in flights[1:]:
        assert np.array_equal(flight.truth.view(np.int64), flights[0].truth.view(np.int64))
        assert np.array_equal(flight.inputs.view(np.int64), flights[0].inputs.view(np.int64))
    # ... and the gains still act where they belong: the error runs differ
    first = runs[0].direct_errors()
    for run in runs[1:]:
        other = run.direct_errors()
        assert any(not np.allclose(first[q], other[q], rtol=1e-6, atol=0) for q in first)
