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


def test_text_where_a_number_is_needed_is_one_typed_line():
    """A notebook user types "0.01 deg/h" where the API takes SI numbers: a numpy
    TypeError (SourceStatistics) and a bare float() ValueError (budget.evaluate) became
    the library's own one-line error saying how to convert the text."""
    from ins_errors.analysis import budget as bd
    from ins_errors.analysis.covariance import CovarianceError, SourceStatistics
    from ins_errors.specs import default_spec_path, load_spec

    with pytest.raises(CovarianceError,
                       match=r"sigma takes one real number .*parse_quantity\(text, unit\)"):
        SourceStatistics("gyro_drift_x", "constant", "0.01 deg/h")
    with pytest.raises(CovarianceError, match="tau takes one real number"):
        SourceStatistics("gyro_drift_x", "markov", 1e-7, [3600.0, 7200.0])
    spec = load_spec(default_spec_path())
    with pytest.raises(CovarianceError, match="'gyro_drift_x': sigma takes one real number"):
        bd.evaluate("orthodromic", spec, {"gyro_drift_x": "0.01 deg/h"})
    # a model name is taken where a Model is (as simulate and static_modes take it)
    by_name = bd.evaluate("orthodromic", spec, {"gyro_drift_x": 4.8e-8})
    by_model = bd.evaluate(ins_errors.load_model("orthodromic"), spec,
                           {"gyro_drift_x": 4.8e-8})
    assert np.array_equal(by_name.values, by_model.values)


def test_an_unknown_casadi_function_names_the_known_ones():
    model = ins_errors.load_model("orthodromic")
    with pytest.raises(KeyError, match=r"'state_matrx'; known: .*state_matrix"):
        model.casadi.function("state_matrx")


def test_labels_are_one_per_case(run):
    """Three labels for one case were taken without a word (the extra ones dropped)."""
    from ins_errors.errors import ShapeError
    from ins_errors.numeric.compare import compare

    with pytest.raises(ShapeError, match=r"labels must be one per case \(1\), got 3 labels"):
        compare(run.model, run.trajectory, [{"gyro_drift_x": 1e-7}], labels=["a", "b", "c"])
    with pytest.raises(ShapeError, match="got a string"):
        compare(run.model, run.trajectory, [{"gyro_drift_x": 1e-7}], labels="a")
    (case,) = compare(run.model, run.trajectory, [{"gyro_drift_x": 1e-7}], labels=["a"],
                      record_interval=60.0, integration_error=False, validity_threshold=None)
    assert case.label == "a"


def test_the_static_base_is_the_same_in_every_api():
    """static_system took a_ζ = 9.81 m/s² where compare, run and static_modes take the
    normal gravity of the model's Earth at the site (9.8107 at 50°): the Schuler periods
    of its F and of the modes table differed by 0.04 %. The default is now the motion
    generators' own; an explicit gravity is still taken."""
    from ins_errors.analysis.modes import static_modes
    from ins_errors.numeric.linear_system import static_system

    model = ins_errors.load_model("orthodromic")
    latitude = np.radians(50.0)
    start = tr.trajectory(model, tr.static_profile(latitude), 1.0, 1.0).start_inputs
    system = static_system(model, latitude)
    k = model.index("inputs", "a_zeta")
    assert system.u[k, 0] == start[k] and abs(start[k] - 9.8107) < 1e-4
    modes = static_modes(model, latitude)
    F = system.F[..., 0] if system.F.ndim == 3 else system.F

    def frequencies(eigenvalues):  # the oscillations' (Schuler ± Foucault, Earth)
        imag = np.abs(np.asarray(eigenvalues).imag)
        return np.sort(imag[imag > 1e-9])

    np.testing.assert_allclose(frequencies(np.linalg.eigvals(F)),
                               frequencies(modes.eigenvalues), rtol=1e-9)
    assert static_system(model, latitude, gravity=9.81).u[k, 0] == 9.81


def test_degrees_given_as_radians_are_shown_as_given():
    """A notebook user passing 50 (meaning degrees) read "motion latitude 2864.79° is at
    or beyond a pole"; the radians given are now beside it. An angle within one turn
    (what the command line converts from degrees) is said in degrees alone."""
    from ins_errors.numeric.trajectories import MotionError

    with pytest.raises(MotionError, match=r"motion latitude 2864\.79° \(50 rad\) is at"):
        tr.static_profile(50.0)
    with pytest.raises(MotionError, match=r"longitude 1718\.87° \(30 rad\) is outside"):
        tr.great_circle_profile(np.radians(50.0), 30.0, np.radians(40.0), 250.0)
    with pytest.raises(MotionError, match=r"motion latitude 95° is at or beyond"):
        tr.static_profile(np.radians(95.0))
