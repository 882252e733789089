"""The Python API as a notebook user holds it (a probe persona working in Jupyter).

* the error curves a simulation returns read like a mapping from quantity name to its
  curves (``in``, iteration, ``keys()``, ``items()``); an integer key was a TypeError
  from inside difflib;
* a Model (hence a Simulation, closed forms ...) pickles, so it can be sent to a
  process pool's workers: it was "cannot pickle 'module' object"; the copy is the same
  model (a model file's exact version) and gives the same bits;
* ``load_model`` takes a loaded Model back as it is (it said "unknown model <Model ...>").
"""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import ins_errors
from ins_errors.errors import UnknownNameError
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.simulate import simulate

TANGENT_PLANE = str(Path(__file__).resolve().parent / "models" / "tangent_plane_ins.py")


@pytest.fixture(scope="module")
def run():
    model = ins_errors.load_model("orthodromic")
    trajectory = tr.trajectory(model, tr.static_profile(np.radians(50.0)), 600.0, 10.0)
    return simulate(model, trajectory, [{"gyro_drift_x": 1e-7}, {"accel_bias_y": 1e-4}],
                    record_interval=60.0)


def test_error_curves_read_as_a_mapping(run):
    curves = run.direct_errors()
    assert "alpha_y" in curves and "alpha_q" not in curves and 0 not in curves
    assert list(curves) == curves.names == curves.keys() and len(curves) == len(curves.names)
    for k, (name, values) in enumerate(curves.items()):
        assert values is curves.values[k] or np.array_equal(values, curves[name])
        assert values.shape == (len(curves.times), 2)
    with pytest.raises(UnknownNameError, match="unknown error quantity '0'; known: alpha_x"):
        curves[0]


@pytest.mark.parametrize("name", ["orthodromic", TANGENT_PLANE])
def test_a_model_pickles_as_the_same_model(name):
    model = ins_errors.load_model(name)
    copy = pickle.loads(pickle.dumps(model))
    assert copy.key == model.key and [s.name for s in copy.sources] == [
        s.name for s in model.sources]
    p, u = model.parameter_vector(), np.zeros(len(model.inputs))
    x = model.initial_state(model.initial_condition_vector(), u, p)
    assert np.array_equal(copy.state_matrix(x, u, p), model.state_matrix(x, u, p))
    assert ins_errors.load_model(model) is model


def test_a_simulation_pickles_with_its_model_and_the_same_curves(run):
    copy = pickle.loads(pickle.dumps(run))
    assert copy.model.key == run.model.key
    assert np.array_equal(copy.direct_errors().values, run.direct_errors().values)
    assert np.array_equal(copy.linear_errors().values, run.linear_errors().values)
