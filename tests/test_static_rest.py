"""A model file whose inputs the motion generators cannot set (a strapdown INS fed body
rates and specific forces) runs on a static base solved from its own equations.

References: the strapdown truth's static signals of ``strapdown_ned`` (body rate = the
Earth rate in body axes, specific force = −gravity), written independently of the
generic solution; and the textbook static responses of a strapdown INS: an accelerometer
bias b tilts it as (b/g)(1 − cos ω_s t) with the velocity error (b/ω_s) sin ω_s t,
ω_s = √(g/R) (at the equator, where no Foucault term mixes the channels), and a vertical
gyro bias ε turns the heading error as ε t.
"""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.cli import main
from ins_errors.models.earth import normal_gravity
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric import trajectories as tr
from ins_errors.numeric.compare import compare
from ins_errors.numeric.static_rest import static_rest

FIXTURE = Path(__file__).resolve().parents[1] / "examples" / "strapdown" / "strapdown_sphere.py"
MICRO_G = 9.80665e-6  # m/s² (the ug of the tables)
DEG_PER_H = np.radians(1.0) / 3600.0  # rad/s


@pytest.fixture(scope="module")
def sphere():
    return load_model(str(FIXTURE))


@pytest.mark.parametrize("lat, heading, h, k_h1", [(50, 0, 0, 0.0), (-33, 117, 2500, 0.03),
                                                   (80, 300, -100, 0.0)])
def test_strapdown_ned_rest_is_the_strapdown_truths(lat, heading, h, k_h1):
    model = load_model("strapdown_ned")
    p = model.parameter_vector(k_h1=k_h1)
    profile = tr.static_profile(np.radians(lat), np.radians(30), np.radians(heading), h)
    truth = st.trajectory(model, st.flight_from_profile(profile), 100.0, 10.0, p)
    x, u, c, _ = static_rest(model, profile.latitude, profile.longitude, profile.heading,
                             h, p)
    U = model.parameter_vector()[model.index("parameters", "U")]
    gamma = normal_gravity(profile.latitude, h, *p[[0, 1, 3, 4, 5]])
    # independent closed form: level body turned by the heading ψ about down
    psi, phi = profile.heading, profile.latitude
    turn = np.array([[np.cos(psi), -np.sin(psi), 0], [np.sin(psi), np.cos(psi), 0],
                     [0, 0, 1]])
    earth_rate = turn.T @ [U * np.cos(phi), 0.0, -U * np.sin(phi)]
    for reference in (truth.start_inputs, np.r_[earth_rate, 0, 0, -gamma, h]):
        assert np.abs(u[:3] - reference[:3]).max() <= 1e-12 * U
        assert np.abs(u[3:6] - reference[3:6]).max() <= 1e-12 * gamma
        assert u[6] == pytest.approx(reference[6], abs=1e-9)  # h_ref = the true height
    np.testing.assert_allclose(x, truth.start_state, rtol=0, atol=1e-13 * (1 + abs(h)))
    np.testing.assert_allclose(c, truth.initial_conditions, rtol=0, atol=1e-15)


def test_compare_of_a_strapdown_model_file_runs_at_rest(capsys):
    """The researcher's command: exit 2 ('cannot set input omega_x') before."""
    status = main(["compare", str(FIXTURE), "--source", "gyro_bias_x=0.01deg/h", "--hours",
                   "3", "--step", "10s", "--no-refined", "--json", "--no-progress"])
    report = json.loads(capsys.readouterr().out)
    assert status == 0
    assert report["truth_used"] == "static"
    assert report["motion"].startswith("static base at φ=50°")


def test_accelerometer_bias_gives_the_schuler_tilt(sphere):
    p = sphere.parameter_vector()
    g, R = p[sphere.index("parameters", "g")], p[sphere.index("parameters", "R")]
    w_s, b = np.sqrt(g / R), 100 * MICRO_G
    traj = tr.trajectory(sphere, tr.static_profile(0.0), 3 * 3600.0, 10.0, p)
    (case,) = compare(sphere, traj, [{"accel_bias_x": b}], record_interval=60.0,
                      integration_error=False, validity_threshold=None, refined=False)
    t = case.times
    tilt = b / g * (1 - np.cos(w_s * t))  # body x north: the pitch error
    speed = b / w_s * np.sin(w_s * t)
    for run in (case.direct, case.linear):
        assert np.abs(run["delta_pitch"] - tilt).max() <= 1e-4 * b / g
        assert np.abs(run["delta_v_N"] - speed).max() <= 1e-4 * b / w_s
    assert np.abs(case.direct["delta_pitch"]).max() == pytest.approx(2 * b / g, rel=1e-3)


def test_vertical_gyro_bias_turns_the_heading(sphere):
    eps = 0.01 * DEG_PER_H
    traj = tr.trajectory(sphere, tr.static_profile(np.radians(45)), 3600.0, 10.0)
    (case,) = compare(sphere, traj, [{"gyro_bias_z": eps}], record_interval=60.0,
                      integration_error=False, validity_threshold=None, refined=False)
    t = case.times[1:]
    heading = case.direct["delta_heading"][1:]
    assert np.abs(heading / (eps * t) - 1).max() < 0.02


RESTLESS = '''
import sympy as sp
from ins_errors.modeling import (Mechanisation, ModelDefinition, Parameter, Variable,
                                 computed_symbols, error_source, error_states_of)

STATES = (Variable("spin", "rad", "an angle that turns at rest", "s"),
          Variable("v", "m/s", "velocity", "v"))
INPUTS = (Variable("f", "m/s**2", "specific force", "f"),)
PARAMETERS = (Parameter("U", "rad/s", "rate", "U", 7e-5),)
SOURCES = (error_source("bias", "m/s**2", "ug", "constant", None, "b", "bias"),)
OUTPUTS = (Variable("latitude", "rad", "angle", "s"),)
CONDITIONS = (Variable("latitude", "rad", "start angle", "s_0"),
              Variable("{velocity}", "{unit}", "start velocity", "v_0"))


def build():
    s, v = (x.symbol for x in STATES)
    f, U, b = INPUTS[0].symbol, PARAMETERS[0].symbol, SOURCES[0].symbol
    start = sp.Matrix([CONDITIONS[0].symbol, CONDITIONS[1].symbol{scale}])
    return ModelDefinition(
        name="restless", title="t", source="t", states=STATES,
        error_states=error_states_of(STATES, ()), real_states=computed_symbols(STATES),
        inputs=INPUTS, parameters=PARAMETERS, sources=SOURCES, outputs=OUTPUTS,
        initial_conditions=CONDITIONS, ideal=Mechanisation(),
        real=Mechanisation(computed=True), ideal_rhs=sp.Matrix([U, f]),
        real_rhs=sp.Matrix([U, f + b]), output_map=lambda eq, x, u: sp.Matrix([x[0]]),
        initial_state=start, initial_real_state=start)
'''


@pytest.mark.parametrize("velocity, unit, scale, said", [
    ("v0", "m/s", "", "no constant input holds 'spin' still"),
    ("w0", "m", " * U", "cannot set the initial condition(s) w0")])
def test_no_rest_is_refused_in_one_line(velocity, unit, scale, said, tmp_path, capsys,
                                       monkeypatch):
    """A state that moves whatever the inputs (dspin/dt = U), or an initial condition a
    static base cannot fill, is one line naming it."""
    # the throw-away model's code goes to a cache of its own (the example file's code and
    # loops above are kept in the user's cache, as the documented commands keep them)
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))
    path = tmp_path / "restless.py"
    path.write_text(textwrap.dedent(RESTLESS.format(velocity=velocity, unit=unit, scale=scale)),
                    encoding="utf-8")
    status = main(["compare", str(path), "--source", "bias=1ug", "--hours", "1", "--step",
                   "10s"])
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert status == 2 and said in err, err
