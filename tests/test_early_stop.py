"""A long run that leaves its domain early is refused soon after, not at its end.

The compiled loop runs a static base in about ``RUN_PIECES`` pieces and a moving one in
pieces of ``STREAM_STEPS`` steps; the records are checked after every piece. The steps
integrated are counted at the loop's only entry into compiled code
(``CompiledLoop._advance_group``); the refusal of a run that stopped early is compared
with the refusal of the same run made in one piece (checked only at its end, as every
run was before), and the records of runs that stay in their domain with those of the
same run in one piece, bit for bit.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.errors import DomainError
from ins_errors.numeric import integrators as integ
from ins_errors.numeric import simulate as sm
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr

HOURS = 24.0


class Steps(dict):
    """Steps integrated by each group of cases (``{group: steps}``) and the number of
    calls into the compiled loop."""

    calls = 0


@pytest.fixture
def steps(monkeypatch):
    """Steps the error runs integrate, counted where their compiled loop is entered (a
    moving truth's own loop is left out)."""
    counted = Steps()
    original, make = integ.CompiledLoop._advance_group, sm._loop
    runs = set()

    def counting(self, functions, carry, n_rec, stream, states, margins, g):
        if id(self) in runs:
            counted[g] = counted.get(g, 0) + n_rec * self.record_every
            counted.calls += 1
        return original(self, functions, carry, n_rec, stream, states, margins, g)

    def loop(*args):
        made = make(*args)
        runs.add(id(made))
        return made

    monkeypatch.setattr(integ.CompiledLoop, "_advance_group", counting)
    monkeypatch.setattr(sm, "_loop", loop)
    return counted


def _unstable_static(tau: float = 1.0):
    """strapdown_ned at rest with a sign slip in its altitude damping (k_h1 < 0): the
    vertical channel grows ×e every ~97 s and the real run overflows after ~0.6 h."""
    model = load_model("strapdown_ned")
    # a sign slip in the damping, as a model written with one would have (the parameter
    # check refuses a negative gain given as a value: set in the vector itself)
    p = model.parameter_vector()
    p[model.index("parameters", "k_h1")] = -0.01
    return model, st.trajectory(model, st.static(np.radians(50.0)), HOURS * 3600.0, tau, p=p)


def _refusal(*args, **kwargs) -> str:
    with pytest.raises(DomainError) as caught:
        sm.simulate(*args, **kwargs)
    return str(caught.value)


def _left_at(message: str) -> float:
    """The end of the recording interval in which the run left its domain, s."""
    return float(re.search(r"left its domain (?:at|between) t = .*?([\d.e+]+) s \(",
                           message).group(1))


def test_a_static_run_that_overflows_early_stops_soon_after(steps, monkeypatch):
    model, motion = _unstable_static()
    sources = [{"accel_bias_z": 1e-4}]
    early = _refusal(model, motion, sources, record_interval=60.0, parts=("real", "linear"))
    done = sum(steps.values())
    left = _left_at(early)
    assert left < 3600.0 and "became NaN or infinite" in early and "\n" not in early
    # it ran past the departure, by at most one piece (1/RUN_PIECES of the run, rounded up
    # to whole compiled chunks of 32 records), and not much more
    assert left <= done * motion.tau <= left + 2 * 32 * 60.0
    assert done < motion.n_steps / 10
    # the refusal of the whole run checked at its end only (one piece): the same line
    monkeypatch.setattr(integ, "RUN_PIECES", 1)
    steps.clear()
    whole = _refusal(model, motion, sources, record_interval=60.0, parts=("real", "linear"))
    assert sum(steps.values()) == motion.n_steps
    assert whole == early


def test_a_threaded_batch_stops_at_the_first_departure_of_any_case(steps, monkeypatch):
    """Two groups of cases in two threads: the group whose case leaves first stops the
    other at the end of that piece, and the refusal names the first departure of all
    cases, as when every case runs to the end."""
    model, motion = _unstable_static()
    monkeypatch.setenv("INS_ERRORS_THREADS", "2")
    # no source: stays at rest; the larger bias leaves earlier than the smaller one
    sources = [{}, {"accel_bias_z": 1e-4}, {}, {"accel_bias_z": 1e-1}]
    kwargs = {"record_interval": 60.0, "parts": ("real", "linear", "refined")}
    early = _refusal(model, motion, sources, **kwargs)
    assert set(steps) == {0, 1}
    assert max(steps.values()) < motion.n_steps / 10
    monkeypatch.setattr(integ, "RUN_PIECES", 1)
    steps.clear()
    whole = _refusal(model, motion, sources, **kwargs)
    assert steps == {0: motion.n_steps, 1: motion.n_steps}
    assert whole == early
    alone = _refusal(model, motion, [{"accel_bias_z": 1e-1}], **kwargs)
    assert _left_at(whole) == _left_at(alone) < _left_at(
        _refusal(model, motion, [{"accel_bias_z": 1e-4}], **kwargs))


def test_a_streamed_run_that_leaves_early_stops_soon_after(steps):
    """A day's great circle streamed in pieces of STREAM_STEPS steps: a platform tilted
    past the small-angle limit within minutes ends the run (and the making of its true
    motion) there; the refusal is the one of a run that ends shortly after."""
    model = load_model("orthodromic")
    profile = tr.great_circle_profile(np.radians(50), np.radians(30), np.radians(40), 250.0)
    kwargs = {"record_interval": 10.0, "parts": ("real", "linear"),
              "platform": "small_angle"}
    sources = [{"gyro_drift_y": 1e-3}]
    motion = tr.trajectory(model, profile, HOURS * 3600.0, 1.0, stream=True)
    early = _refusal(model, motion, sources, **kwargs)
    done = sum(steps.values())
    assert done < motion.n_steps / 10
    assert _left_at(early) <= done * motion.tau <= _left_at(early) + sm.STREAM_STEPS
    short = tr.trajectory(model, profile, 3600.0, 1.0, stream=True)
    assert _refusal(model, short, sources, **kwargs) == early


def _records(sim: sm.Simulation) -> list[np.ndarray]:
    return [sim.ideal, sim.real, sim.linear, sim.refined]


@pytest.mark.parametrize("threads", ["1", "2"])
def test_a_run_in_the_domain_records_the_same_bits_in_many_pieces_as_in_one(
        steps, monkeypatch, threads):
    monkeypatch.setenv("INS_ERRORS_THREADS", threads)
    model = load_model("strapdown_ned")
    w0 = 2 * np.pi / 300.0
    p = model.parameter_vector(k_h1=2 * 0.7 * w0, k_h2=w0**2 + 2 * 9.80665 / 6_371_000.0)
    motion = st.trajectory(model, st.static(np.radians(50.0)), 4 * 3600.0, 1.0, p=p)
    sources = [{"accel_bias_z": 1e-4, "gyro_bias_x": 1e-7}, {"initial_heading_error": 1e-3}]
    runs, calls = [], []
    for pieces in (1, 10**6):   # one piece; pieces of one compiled chunk (32 records)
        monkeypatch.setattr(integ, "RUN_PIECES", pieces)
        steps.clear()
        steps.calls = 0
        runs.append(sm.simulate(model, motion, sources, record_interval=10.0))
        assert set(steps.values()) == {motion.n_steps}
        calls.append(steps.calls / len(steps))
    assert calls == [1, 1440 // 32]   # 1440 records: 45 chunks of 32
    one, many = runs
    assert all(np.array_equal(a, b) for a, b in zip(_records(one), _records(many),
                                                    strict=True))
