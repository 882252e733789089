"""Collecting the error curves of a long run needs memory for the curves, not ten records.

The curves are evaluated piece by piece along the recorded samples; the reference here
evaluates the generated output maps on the whole record at once (the previous code path,
written out independently), and the two must agree bit for bit. Memory is measured with
tracemalloc (numpy reports its buffers to it), so the bounds are deterministic.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from ins_errors.numeric import simulate as simulate_module
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import comparisons_of
from ins_errors.numeric.simulate import simulate

DEG = np.pi / 180.0
CASES = [{"accel_bias_x": 5e-4, "gyro_drift_y": 1e-7}, {"initial_azimuth_error": 2e-3},
         {"accel_bias_y": 1e-3}]


def _whole_record_curves(sim, part: str) -> np.ndarray:
    """The curves with every output map evaluated on the whole record at once."""
    model, n, p = sim.model, len(sim.model.states), sim.trajectory.parameters
    if sim.recorded_inputs is not None:
        u = sim.recorded_inputs[:, :, None]
    else:
        u = sim.trajectory.inputs_at(np.arange(sim.ideal.shape[1]) * sim.stride)[:, :, None]
    if part == "direct":
        dy = model.numpy.outputs(sim.real[:n], u, p) - model.numpy.outputs(sim.ideal, u, p)
        platform = sim.real[n:]
    elif part == "linear":
        e = sim.linear
        dy = np.einsum("ij...,j...->i...", model.numpy.output_matrix(sim.ideal, u, p), e)
        platform = e[n:]
    else:  # refined: the exact output map at the ideal state plus the error
        e = sim.refined
        dy = model.numpy.outputs(sim.ideal + e[:n], u, p) - model.numpy.outputs(sim.ideal, u, p)
        platform = e[n:]
    angles = [k for k, o in enumerate(model.outputs) if o.unit == "rad"]
    dy[angles] = (dy[angles] + np.pi) % (2 * np.pi) - np.pi
    return np.concatenate([platform, dy])


@pytest.mark.parametrize("motion", ["static", "great_circle"])
@pytest.mark.parametrize("values", [4096, 100])
def test_curves_in_pieces_equal_the_whole_record_bit_for_bit(orthodromic, monkeypatch,
                                                              motion, values):
    """Pieces of 4096 values (the default) and of 100 (32 samples of 3 cases: 113 pieces,
    a ragged last one of 17) give exactly the curves of the whole record."""
    monkeypatch.setattr(simulate_module, "CURVE_VALUES", values)
    profile = (tr.static_profile(50 * DEG) if motion == "static" else
               tr.great_circle_profile(50 * DEG, 30 * DEG, 90 * DEG, 250.0))
    traj = tr.trajectory(orthodromic, profile, 3600.0, 0.5)
    sim = simulate(orthodromic, traj, CASES, record_interval=1.0)
    pieces = [rows.stop - rows.start for rows in sim._pieces()]
    assert len(pieces) > (1 if values == 4096 else 100)
    assert values == 4096 or pieces[-1] < pieces[0]  # a ragged last piece
    for part in ("direct", "linear", "refined"):
        curves = getattr(sim, f"{part}_errors")()
        assert np.array_equal(curves.values, _whole_record_curves(sim, part)), part
        assert curves.times.shape == (3601,) and curves.times[-1] == 3600.0


def test_collecting_the_curves_of_a_long_static_run_needs_about_one_record(orthodromic):
    """48 h at a 1-s record, 2 cases, refined: the curves (30 of the 41 recorded rows)
    plus one piece's temporaries. Evaluating the output maps on the whole record made
    about 60 temporaries and H (7 × 11 rows) the size of the record: 7.5 records."""
    traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG), 48 * 3600.0, 1.0)
    sim = simulate(orthodromic, traj, CASES[:2], record_interval=1.0)
    record = sum(a.nbytes for a in (sim.ideal, sim.real, sim.linear, sim.refined))
    assert record > 100e6
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        comparisons = comparisons_of(sim, ["a", "b"])
        kept, peak = (m - base for m in tracemalloc.get_traced_memory())
    finally:
        tracemalloc.stop()
    curves = sum(v.nbytes for c in comparisons for d in (c.direct, c.linear, c.refined)
                 for v in d.values())
    assert curves == pytest.approx(30 / 41 * record)
    assert kept < curves + 2e6
    assert peak < 0.9 * record, f"peak {peak / 1e6:.0f} MB for a {record / 1e6:.0f}-MB record"
    assert peak - curves < 0.15 * record


def test_curves_are_computed_once_and_shared_read_only(orthodromic):
    """compare's integration-error step asks for the direct and linear curves again: it
    gets the same, read-only, arrays, and nothing is computed or allocated a second
    time."""
    traj = tr.trajectory(orthodromic, tr.static_profile(50 * DEG), 6 * 3600.0, 1.0)
    sim = simulate(orthodromic, traj, CASES, record_interval=1.0)
    first = [sim.direct_errors(), sim.linear_errors(), sim.refined_errors()]
    tracemalloc.start()
    try:
        again = [sim.direct_errors(), sim.linear_errors(), sim.refined_errors()]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert all(a is b for a, b in zip(first, again, strict=True)) and peak < 10_000
    assert first[1].times is first[0].times
    for curves in first:
        with pytest.raises(ValueError, match="read-only"):
            curves.values[0, 0, 0] = 1.0
        with pytest.raises(ValueError, match="read-only"):
            curves["delta_latitude"][:] = 0.0
