"""The ECEF strapdown example for model authors, and what ``models FILE`` says of a file.

``examples/strapdown/ecef_strapdown.py`` is Groves' Earth-fixed mechanisation (WGS-84,
point mass + J2 gravity, geodetic outputs by Bowring's formula) written as a model file.
Its derived error model, carried into Groves' own ECEF error states (``psi_ecef``), must
be Groves' ECEF error equations with the gradient of the file's gravity, here from
finite differences of an own numpy gravity; its navigation outputs must return the
navigation quantities its initial state was made from. ``ins-errors models FILE`` says
whether a file is a strapdown INS with the φ/ψ conventions, and if not what it lacks
(a researcher had to find out with ``check --list-conventions``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "strapdown" / "ecef_strapdown.py"
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"

POINTS = [
    # at rest at 50° N, heading 30°: gravity and the Earth rate only
    ({"latitude": np.radians(50.0), "longitude": np.radians(30.0),
      "heading": np.radians(30.0)}, {}),
    # moving, banked and pitched at 10 km in the south, turning and accelerating
    ({"latitude": np.radians(-35.0), "longitude": np.radians(140.0), "height": 10_000.0,
      "v_N0": 120.0, "v_E0": -200.0, "v_D0": 5.0, "roll": np.radians(20.0),
      "pitch": np.radians(-5.0), "heading": np.radians(250.0)},
     {"omega_x": 0.01, "omega_y": -0.02, "omega_z": 0.03, "f_x": 0.5, "f_y": -0.3,
      "f_z": -9.7}),
]


def _skew(w) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _gravity(r: np.ndarray, a: float, mu: float, j2: float, rate: float) -> np.ndarray:
    """Gravitation of a point mass with J2 plus the centrifugal acceleration, ECEF, m/s²."""
    x, y, z = r
    size = np.linalg.norm(r)
    k, zeta = 1.5 * j2 * a**2 / size**2, 5.0 * z**2 / size**2
    gravitation = -mu / size**3 * np.array([x * (1 + k * (1 - zeta)),
                                            y * (1 + k * (1 - zeta)),
                                            z * (1 + k * (3 - zeta))])
    return gravitation + rate**2 * np.array([x, y, 0.0])


def _groves(C: np.ndarray, r: np.ndarray, f_b: np.ndarray, p: dict) -> tuple:
    """Groves' ECEF error equations (2013, section 14.2.3), with his sign of ψ^e:
    ψ̇ = −Ω ψ + C δω, δv̇ = −[(C f)×] ψ − 2Ω δv + Γ δr + C δf, δṙ = δv; Γ = ∂g/∂r by
    central differences over ±1 m."""
    omega = _skew([0.0, 0.0, p["omega_ie"]])
    gamma = np.column_stack([
        (_gravity(r + step, p["a"], p["mu"], p["J2"], p["omega_ie"])
         - _gravity(r - step, p["a"], p["mu"], p["J2"], p["omega_ie"])) / 2.0
        for step in np.eye(3)])
    F = np.zeros((9, 9))
    F[0:3, 0:3] = -omega
    F[3:6, 0:3] = -_skew(C @ f_b)
    F[3:6, 3:6] = -2.0 * omega
    F[3:6, 6:9] = gamma
    F[6:9, 3:6] = np.eye(3)
    G = np.zeros((9, 6))
    G[0:3, 0:3] = C
    G[3:6, 3:6] = C
    return F, G


@pytest.mark.parametrize("conditions, inputs", POINTS, ids=["rest", "moving"])
def test_the_ecef_example_carries_groves_error_equations(conditions, inputs):
    from ins_errors import load_model
    from ins_errors.conventions import error_matrices

    model = load_model(str(EXAMPLE))
    p = model.parameter_vector()
    named = {info.name: float(v) for info, v in zip(model.parameters, p, strict=True)}
    u = model.input_vector(**inputs)
    c = model.initial_condition_vector(**conditions)
    x = model.initial_state(c, u, p)
    em = error_matrices(model, "psi_ecef", x[:, None], u[:, None], p)
    assert em.states == ("psi_X", "psi_Y", "psi_Z", "dv_X", "dv_Y", "dv_Z",
                         "dr_X", "dr_Y", "dr_Z")
    assert em.sources == tuple(f"{kind}_bias_{axis}" for kind in ("gyro", "accel")
                               for axis in "xyz")
    F_ref, G_ref = _groves(x[:9].reshape(3, 3), x[12:15], u[3:6], named)
    for i in range(3):  # block by block: the gravity gradient is 1e-6 of its rows' f×ψ
        rows = np.abs(F_ref[3 * i:3 * i + 3]).max()
        for j in range(3):
            block = np.s_[3 * i:3 * i + 3, 3 * j:3 * j + 3]
            size = np.abs(F_ref[block]).max()
            tolerance = 1e-7 * size if size else 1e-9 * rows
            np.testing.assert_allclose(em.F[0][block], F_ref[block], rtol=0, atol=tolerance,
                                       err_msg=f"F block {i}, {j}")
    np.testing.assert_allclose(em.G[0], G_ref, rtol=0, atol=1e-12)
    # the outputs (Bowring's latitude and height, NED velocity, Euler angles) return the
    # navigation quantities the state was made from
    out = dict(zip((o.name for o in model.outputs), model.outputs_of(x, u, p), strict=True))
    given = {info.name: float(v) for info, v in zip(model.initial_conditions, c, strict=True)}
    for name, key in (("latitude", "latitude"), ("longitude", "longitude"),
                      ("roll", "roll"), ("pitch", "pitch"), ("heading", "heading")):
        wrapped = (out[name] - given[key] + np.pi) % (2 * np.pi) - np.pi
        assert abs(wrapped) < 1e-12, (name, out[name], given[key])
    assert abs(out["height"] - given["height"]) < 1e-6
    for axis in "NED":
        assert abs(out[f"v_{axis}"] - given[f"v_{axis}0"]) < 1e-9


def test_models_says_whether_a_file_is_a_strapdown_ins(capsys):
    assert main(["models", str(EXAMPLE)]) == 0
    lines = capsys.readouterr().out.splitlines()
    [line] = [w for w in lines if w.startswith("strapdown INS:")]
    assert line.startswith("strapdown INS: yes, it flies the strapdown motions")
    assert "psi_ecef" in line and "phi," in line and "--list-conventions" in line
    assert main(["models", str(EXAMPLE), "--json"]) == 0
    status = json.loads(capsys.readouterr().out)["strapdown"]
    assert status["recognised"] is True and status["lacks"] == []
    assert "psi_ecef" in status["conventions"] and "model" not in status["conventions"]
    # the tutorial's single-axis Schuler loop is no strapdown INS: one line with what
    # it lacks (its outputs are latitude and v_N, its input a_N, its tilt a state of
    # the real work only)
    assert main(["models", str(SCHULER)]) == 0
    lines = capsys.readouterr().out.splitlines()
    [line] = [w for w in lines if w.startswith("strapdown INS:")]
    assert line.startswith("strapdown INS: no, so no strapdown motions and no φ/ψ "
                           "conventions; it lacks ")
    for word in ("the outputs longitude, height (or h), v_E", "the inputs omega_x, "
                 "omega_y, omega_z, f_x, f_y, f_z", "one error state per state"):
        assert word in line, (word, line)
    assert "latitude," not in line and "v_N," not in line and "Earth radius" not in line
    assert main(["models", str(SCHULER), "--json"]) == 0
    status = json.loads(capsys.readouterr().out)["strapdown"]
    assert status["recognised"] is False and len(status["lacks"]) == 3
    assert status["conventions"] == []
    # a built-in platform model: the strapdown requirements are beside the point
    assert main(["models", "orthodromic"]) == 0
    assert "strapdown INS" not in capsys.readouterr().out


def test_the_ecef_example_is_shown_on_the_examples_pages():
    pages = ((ROOT / "examples" / "strapdown" / "README.md").read_text(encoding="utf-8")
             + (ROOT / "examples" / "README.md").read_text(encoding="utf-8"))
    for command in ("ins-errors models examples/strapdown/ecef_strapdown.py",
                    "ins-errors matrices examples/strapdown/ecef_strapdown.py",
                    "--convention psi_ecef",
                    "ins-errors compare examples/strapdown/ecef_strapdown.py"):
        assert command in pages, command
    assert "(strapdown/ecef_strapdown.py)" in pages or "(ecef_strapdown.py)" in pages
