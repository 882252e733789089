"""Model files with one of something: one error source, one (error) state, one output,
one input, one parameter, one initial condition; and with none of the optional ones.

The generated numpy functions of matrices (F, G, H, E) must keep both axes when a
dimension is 1: a model with one error source once got G and E of shape (ne,) instead of
(ne, 1), and ``compare`` crashed on ``E @ w``.

The references are textbook solutions, not the code's output:

* single-axis Schuler loop with an accelerometer bias b (δV' = −g ψ + b, ψ' = δV/R,
  zero initial errors): δV = (b/ω_s) sin ω_s t, ψ = (b/g)(1 − cos ω_s t), ω_s = √(g/R);
  for a random constant b of 1σ σ the standard deviations are these with b = σ (in
  absolute value);
* a velocity integrator damped towards a log's velocity with gain k and an accelerometer
  bias b (δV' = −k δV + b): δV = (b/k)(1 − e^{−kt}), one mode of eigenvalue −k; for a
  white accelerometer noise of density q, var δV = q²/(2k) (1 − e^{−2kt}).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from ins_errors import load_model
from ins_errors.cli import main
from tests.helpers import fresh_model_cache

R, G = 6_371_000.0, 9.80665
OMEGA = math.sqrt(G / R)
K = 1e-3  # 1/s: gain of the damped integrator
ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Generated code of model files goes to a fresh cache per test."""
    return fresh_model_cache(tmp_path, monkeypatch)


HEADER = '''
import sympy as sp

from ins_errors.modeling import (
    Mechanisation, ModelDefinition, Parameter, Variable, computed_symbols, error_source,
    error_states_of,
)

BIAS = error_source("accel_bias", "m/s**2", "ug", "constant", None, r"\\nabla",
                    "bias of the north accelerometer")
V_N = Variable("v_N", "m/s", "north velocity", "v_N")
V0 = Variable("v_N", "m/s", "initial north velocity", "v_{{N0}}")
STATES = (Variable("V", "m/s", "north velocity", "V"),)
(V,) = (v.symbol for v in STATES)
(V_c,) = computed_symbols(STATES)
'''

VELOCITY_LOOP = HEADER + '''
TILT = Variable("psi", "rad", "platform tilt about the west axis", r"\\psi")
INPUTS = (Variable("a_N", "m/s**2", "true north specific force", "a_N"),{height_input})
PARAMETERS = (Parameter("R", "m", "Earth radius", "R", 6371000.0),
              Parameter("g", "m/s**2", "gravity", "g", 9.80665))
a_N = INPUTS[0].symbol
radius = PARAMETERS[0].symbol{plus_height}
g = PARAMETERS[1].symbol
psi = TILT.symbol


def outputs(eq, state, inputs):
    return sp.Matrix([state[0]])


def build():
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    f = real.let("f", a_N * sp.cos(psi) - g * sp.sin(psi) + BIAS.symbol, "f")
    return ModelDefinition(
        name="velocity_loop", title="Schuler loop: velocity and tilt", source="test",
        states=STATES, error_states=error_states_of(STATES, [TILT]), real_states=[V_c, psi],
        inputs=INPUTS, parameters=PARAMETERS, sources=(BIAS,), outputs=(V_N,),
        initial_conditions=(V0,), ideal=ideal, real=real, ideal_rhs=sp.Matrix([a_N]),
        real_rhs=sp.Matrix([f, V_c / radius - V / radius]), output_map=outputs,
        initial_state=sp.Matrix([V0.symbol]), initial_real_state=sp.Matrix([V0.symbol, 0]))
'''

DAMPED = HEADER + '''
INPUTS = (Variable("a_N", "m/s**2", "true north specific force", "a_N"),)
PARAMETERS = (Parameter("k", "1/s", "damping gain towards the log", "k", 0.001),)
a_N, k = INPUTS[0].symbol, PARAMETERS[0].symbol
OUTPUTS = {outputs}


def outputs(eq, state, inputs):
    return {output_map}


def build():
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    return ModelDefinition(
        name="damped_integrator", title="velocity damped towards a log", source="test",
        states=STATES, error_states=error_states_of(STATES, []), real_states=[V_c],
        inputs=INPUTS, parameters=PARAMETERS, sources={sources}, outputs=OUTPUTS,
        initial_conditions=(V0,), ideal=ideal, real=real, ideal_rhs=sp.Matrix([a_N]),
        real_rhs=sp.Matrix([a_N + {bias} - k * (V_c - V)]), output_map=outputs,
        initial_state=sp.Matrix([V0.symbol]), initial_real_state=sp.Matrix([V0.symbol]))
'''

BARE = HEADER + '''

def outputs(eq, state, inputs):
    return sp.Matrix([state[0]])


def build():
    ideal, real = Mechanisation(), Mechanisation(computed=True)
    return ModelDefinition(
        name="bare_integrator", title="velocity integrator at rest", source="test",
        states=STATES, error_states=error_states_of(STATES, []), real_states=[V_c],
        inputs=(), parameters=(), sources=(BIAS,), outputs=(V_N,), initial_conditions=(),
        ideal=ideal, real=real, ideal_rhs=sp.Matrix([0]), real_rhs=sp.Matrix([BIAS.symbol]),
        output_map=outputs, initial_state=sp.Matrix([0]), initial_real_state=sp.Matrix([0]))
'''


def velocity_loop(tmp_path: Path, height: bool = False) -> Path:
    """Schuler loop of velocity and tilt (no latitude); with ``height``, an input h."""
    path = tmp_path / ("velocity_loop_h.py" if height else "velocity_loop.py")
    path.write_text(VELOCITY_LOOP.format(
        height_input=' Variable("h", "m", "height", "h")' if height else "",
        plus_height=" + INPUTS[1].symbol" if height else ""), encoding="utf-8")
    return path


def damped(tmp_path: Path, outputs: bool = True, sources: bool = True,
           empty: str = "sp.zeros(0, 1)") -> Path:
    """One state, one error state, one input, one parameter, one initial condition."""
    path = tmp_path / "damped.py"
    path.write_text(DAMPED.format(
        outputs="(V_N,)" if outputs else "()",
        output_map="sp.Matrix([state[0]])" if outputs else empty,
        sources="(BIAS,)" if sources else "()",
        bias="BIAS.symbol" if sources else "0"), encoding="utf-8")
    return path


def one_source_tutorial(tmp_path: Path) -> Path:
    """The tutorial's Schuler loop with the accelerometer bias its only error source."""
    text = SCHULER.read_text(encoding="utf-8")
    for old, new in [
        ('    error_source("gyro_drift", "rad/s", "deg/h", "constant", None, r"\\varepsilon",\n'
         '                 "constant drift of the gyro about the west axis"),\n', ""),
        ('    error_source("initial_tilt", "rad", "arcsec", "initial", None, r"\\psi_0",\n'
         '                 "platform tilt about west when navigation starts"),\n', ""),
        ("drift, bias, tilt0 = (v.symbol for v in SOURCES)",
         "(bias,) = (v.symbol for v in SOURCES)\ndrift = tilt0 = 0"),
    ]:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "one_source.py"
    path.write_text(text, encoding="utf-8")
    return path


def _static_run(model, seconds: float, b: float, tau: float = 10.0):
    from ins_errors.numeric import trajectories as tr
    from ins_errors.numeric.simulate import simulate

    trajectory = tr.trajectory(model, tr.static_profile(math.radians(50)), seconds, tau)
    return trajectory, simulate(model, trajectory, {"accel_bias": b}, method="rk4",
                                record_interval=60.0, parts=("real", "linear"))


# --------------------------------------------------------------------------------------
# the generated matrices keep their shape
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("build", [velocity_loop, damped, one_source_tutorial])
def test_generated_matrices_keep_every_axis_of_length_one(build, tmp_path):
    model = load_model(str(build(tmp_path)))
    ne, nw, ny = len(model.error_states), len(model.sources), len(model.outputs)
    assert nw == 1
    x, u, p = (np.zeros(len(model.states)), np.zeros(len(model.inputs)),
               model.parameter_vector())
    c = np.zeros(len(model.initial_conditions))
    expected = {"state_matrix": (ne, ne), "source_matrix": (ne, nw),
                "output_matrix": (ny, ne), "initial_error_matrix": (ne, nw)}
    for name, shape in expected.items():
        args = (c, u, p) if name == "initial_error_matrix" else (x, u, p)
        assert model.numpy.__dict__[name](*args).shape == shape, name
        batch = [np.repeat(a[:, None], 4, 1) for a in args]  # trailing batch axis
        assert model.numpy.__dict__[name](*batch).shape == (*shape, 4), name
        casadi = np.asarray(model.casadi.function(name)(*args))
        assert casadi.shape == shape, name
    # the accelerometer bias enters the velocity equation with weight 1
    assert model.source_matrix(x, u, p)[0, 0] == 1.0


def test_a_one_column_matrix_is_emitted_as_a_matrix_and_a_vector_must_be_a_column():
    from ins_errors.symbolic.codegen import Argument, FunctionSpec, emit_numpy_function, prepare

    a = sp.Symbol("a", real=True)
    column = sp.Matrix([a, 2 * a])
    namespace = {}
    for name, matrix in (("as_matrix", True), ("as_vector", False)):
        spec = FunctionSpec(name, [Argument("v", [a], "")], column, "", "", matrix=matrix)
        exec("import numpy as _np\n_m = _np\ndef _as_vector(v, n, *_):\n"
             "    return _np.asarray(v, dtype=float)\n"
             + emit_numpy_function(prepare(spec)), namespace)
    assert namespace["as_matrix"](np.array([3.0])).shape == (2, 1)
    assert namespace["as_vector"](np.array([3.0])).shape == (2,)
    np.testing.assert_array_equal(namespace["as_matrix"](np.array([3.0]))[:, 0], [3.0, 6.0])
    with pytest.raises(ValueError, match="one column"):
        FunctionSpec("f", [Argument("v", [a], "")], sp.Matrix([[a, a]]), "", "")


# --------------------------------------------------------------------------------------
# compare, covariance, modes, check on the small models
# --------------------------------------------------------------------------------------
def test_schuler_loop_with_one_source_direct_and_linear_runs(tmp_path):
    model = load_model(str(velocity_loop(tmp_path)))
    b = 1e-3  # m/s², about 100 µg
    _, run = _static_run(model, 2 * 3600.0, b)
    for errors in (run.direct_errors(), run.linear_errors()):
        t = errors.times
        velocity = b / OMEGA * np.sin(OMEGA * t)
        tilt = b / G * (1 - np.cos(OMEGA * t))
        np.testing.assert_allclose(errors["delta_v_N"][:, 0], velocity, rtol=0,
                                   atol=1e-6 * b / OMEGA)
        np.testing.assert_allclose(errors["psi"][:, 0], tilt, rtol=0, atol=1e-6 * b / G)


def test_tutorial_loop_with_one_source_compares(tmp_path, capsys):
    path = one_source_tutorial(tmp_path)
    assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "3",
                 "--step", "10s", "--method", "rk4", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    rows = {row["quantity"]: row for row in result["cases"][0]["metrics"]}
    b = 100e-6 * G
    # latitude error and tilt swing between 0 and 2b/g; velocity error peaks at b/ω_s
    for name, peak in (("delta_latitude", 2 * b / G), ("psi", 2 * b / G),
                       ("delta_v_N", b / OMEGA)):
        assert rows[name]["max_direct"] == pytest.approx(peak, rel=1e-3), name
        assert 0 < rows[name]["linear_ratio"] < 1e-6, rows[name]


def test_covariance_of_one_source_on_the_schuler_loop(tmp_path):
    from ins_errors.analysis import covariance as cv
    from ins_errors.numeric.linear_system import system_from_trajectory

    model = load_model(str(velocity_loop(tmp_path)))
    trajectory, _ = _static_run(model, 3 * 3600.0, 0.0)
    system = system_from_trajectory(model, trajectory)
    sigma = 1e-3
    cov = cv.propagate(system, [cv.SourceStatistics("accel_bias", "constant", sigma)],
                       cv.state_and_output_functionals(model, system))
    t, std = cov.times, cov.std
    np.testing.assert_allclose(std[:, cov.index("delta_v_N")],
                               sigma / OMEGA * np.abs(np.sin(OMEGA * t)), rtol=0,
                               atol=1e-9 * sigma / OMEGA)
    np.testing.assert_allclose(std[:, cov.index("psi")], sigma / G * (1 - np.cos(OMEGA * t)),
                               rtol=0, atol=1e-9 * sigma / G)


def test_one_state_model_runs_and_its_covariance_and_mode_are_first_order(tmp_path, capsys):
    from ins_errors.analysis import covariance as cv
    from ins_errors.numeric.linear_system import system_from_trajectory

    path = damped(tmp_path)
    model = load_model(str(path))
    b = 1e-3
    trajectory, run = _static_run(model, 3 * 3600.0, b)
    for errors in (run.direct_errors(), run.linear_errors()):
        expected = b / K * (1 - np.exp(-K * errors.times))
        np.testing.assert_allclose(errors["delta_v_N"][:, 0], expected, rtol=1e-9, atol=0)
    # white accelerometer noise of density q: var δV = q²/(2k) (1 − e^{−2kt})
    q = 1e-4  # m/s² √s
    system = system_from_trajectory(model, trajectory)
    cov = cv.propagate(system, [cv.SourceStatistics("accel_bias", "white", q)],
                       cv.state_and_output_functionals(model, system))
    expected = q**2 / (2 * K) * (1 - np.exp(-2 * K * cov.times))
    np.testing.assert_allclose(cov.variance[:, cov.index("delta_V")], expected, rtol=1e-9,
                               atol=1e-30)
    # its one mode: λ = −k, time constant 1/k
    assert main(["modes", str(path), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    (mode,) = result["modes"]
    assert mode["eigenvalue"]["real"] == pytest.approx(-K, rel=1e-12)
    assert mode["time_constant_s"] == pytest.approx(1 / K, rel=1e-12)
    assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "1",
                 "--step", "10s"]) == 0


def test_check_a_hand_file_of_the_small_models(tmp_path, capsys):
    loop = velocity_loop(tmp_path)
    right = tmp_path / "right.txt"
    right.write_text("dot(delta_V) = -g*psi + accel_bias\ndot(psi) = delta_V/R\n",
                     encoding="utf-8")
    wrong = tmp_path / "wrong.txt"
    wrong.write_text("dot(delta_V) = -g*psi + accel_bias\ndot(psi) = -delta_V/R\n",
                     encoding="utf-8")
    assert main(["check", str(loop), str(right)]) == 0
    capsys.readouterr()
    assert main(["check", str(loop), str(wrong)]) == 1
    out = capsys.readouterr().out
    assert "wrong sign" in out and "grows exponentially" in out
    one_state = tmp_path / "one_state.txt"
    one_state.write_text("dot(delta_V) = -k*delta_V + accel_bias\n", encoding="utf-8")
    assert main(["check", str(damped(tmp_path)), str(one_state)]) == 0


# --------------------------------------------------------------------------------------
# descriptions of a run of a model without latitude
# --------------------------------------------------------------------------------------
def test_static_base_of_a_model_without_latitude_reads_well(tmp_path, capsys):
    from ins_errors.numeric import trajectories as tr

    for path, expected in ((velocity_loop(tmp_path), "static base"),
                           (velocity_loop(tmp_path, height=True), "static base, h=0 m")):
        model = load_model(str(path))
        trajectory = tr.trajectory(model, tr.static_profile(0.5), 60.0, 10.0)
        assert trajectory.description == expected
        assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "0.1",
                     "--step", "10s"]) == 0
        assert f"### velocity_loop: {expected}; " in capsys.readouterr().out
    # a model that uses every reference keeps the full description
    orthodromic = load_model("orthodromic")
    trajectory = tr.trajectory(orthodromic, tr.static_profile(0.5, 0.25, 0.0, 10.0), 60.0, 10.0)
    assert trajectory.description == "static base at φ=28.65°, λ=14.32°, χ=0°, h=10 m"


# --------------------------------------------------------------------------------------
# no outputs, no error sources
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("empty", ["sp.zeros(0, 1)", "sp.Matrix([])"])
def test_a_model_without_outputs(empty, tmp_path, capsys):
    path = damped(tmp_path, outputs=False, empty=empty)
    assert main(["models", str(path)]) == 0
    assert "outputs:\n  (none)\n" in capsys.readouterr().out
    assert main(["modes", str(path), "--json"]) == 0
    (mode,) = json.loads(capsys.readouterr().out)["modes"]
    assert mode["eigenvalue"]["real"] == pytest.approx(-K, rel=1e-12)
    # nothing a run could report: one line, exit 2
    assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "1",
                 "--step", "10s"]) == 2
    err = capsys.readouterr().err.strip()
    assert "has no outputs and no platform angles" in err and len(err.splitlines()) == 1


def test_a_model_without_inputs_parameters_and_initial_conditions(tmp_path, capsys):
    path = tmp_path / "bare.py"
    path.write_text(BARE, encoding="utf-8")
    assert main(["compare", str(path), "--source", "accel_bias=100ug", "--hours", "1",
                 "--step", "10s", "--json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)["cases"][0]["metrics"]
    assert row["quantity"] == "delta_v_N"
    assert row["max_direct"] == pytest.approx(100e-6 * G * 3600.0, rel=1e-12)  # b t


def test_a_model_without_error_sources_is_refused_in_one_line(tmp_path, capsys):
    path = damped(tmp_path, sources=False)
    assert main(["models", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "sources: the model has no error source" in err and len(err.splitlines()) == 1
