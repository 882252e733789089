"""The hand check of a researcher's own platform model: a short-range INS on a rotating flat
Earth (tests/models/tangent_plane_ins.py) whose position is x/y in metres (no latitude or
longitude output, its origin latitude phi0 a parameter) and whose error states include
two damping integrators q_E, q_N in m/s² besides the platform angles.

The effects (JSON: 6 significant digits) are checked against an independent propagation:
the model's F and G from its generated code at the static base (at rest at the origin,
a = 0), SciPy's matrix exponential of the augmented system over 1 h and 24 h, each error
state and each source alone at its Schuler-consistent size, the hand's slip put into F by
hand here.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent
MODEL = ROOT / "models" / "tangent_plane_ins.py"
EQUATIONS = ROOT / "data" / "tangent_plane_equations.txt"
R, G, THETA = 6_371_000.0, 9.80665, 1e-4
ARCSEC = math.pi / 180 / 3600
# the Schuler relations of the declared attitude error θ, by SI unit
SIZE = {"rad": THETA, "m/s": math.sqrt(G * R) * THETA, "m": R * THETA, "m/s**2": G * THETA,
        "rad/s": math.sqrt(G / R) * THETA, "1": THETA}
DAMPED = {"c_v": 2e-3, "c_i": 1e-6}
DAMPED_OPTIONS = ["-p", "c_i=1e-6/s^2", "-p", "c_v=2e-3/s"]
Q_ROW_WRONG = ("# the integrator row with a factor-2 slip\n"
               "dot(q_E) = 2*c_i*delta_V_E - c_i*vref_bias_E\n")


def _reference(slip, hours: float, parameters: dict | None = None) -> tuple[float, float]:
    """Largest change over the cases (each error state, each source alone) of the
    horizontal position |(Δx_E, Δx_N)| (m) and of the platform angles |α| (rad) after
    ``hours``, hand (``slip(F)`` changes F in place) minus model, at the static base."""
    from ins_errors import load_model

    model = load_model(str(MODEL))
    names = [s.name for s in model.error_states]
    p = model.parameter_vector(**(parameters or {}))
    x, u = np.zeros(len(model.states)), np.zeros(len(model.inputs))
    f, g = model.state_matrix(x, u, p), model.source_matrix(x, u, p)
    start = np.array([SIZE[s.unit] for s in model.error_states])
    drive = g * np.array([SIZE[s.unit] for s in model.sources])
    n, m = f.shape[0], drive.shape[1]
    hand = f.copy()
    slip(hand, names)
    responses = []
    for matrix in (hand, f):
        a = np.zeros((n + m, n + m))
        a[:n, :n], a[:n, n:] = matrix, drive
        responses.append((expm(a * hours * 3600.0) @ np.diag(np.append(start, np.ones(m))))[:n])
    diff = responses[0] - responses[1]
    position = [names.index("delta_x_E"), names.index("delta_x_N")]
    angles = [names.index(a) for a in ("alpha_E", "alpha_N", "alpha_U")]
    return (float(np.linalg.norm(diff[position], axis=0).max()),
            float(np.linalg.norm(diff[angles], axis=0).max()))


def _check(capsys, *arguments: str, status: int = 1) -> tuple[dict, str]:
    assert main(["check", *arguments, "--json"]) == status
    data = json.loads(capsys.readouterr().out)
    assert main(["check", *arguments]) == status
    return data, capsys.readouterr().out


def _effects(data: dict) -> dict[str, dict]:
    """Effect of each root finding by its line and quantity."""
    return {f"{e['line']} {f['quantity']}": f["effect"] for e in data["equations"]
            for f in e["findings"] if f.get("effect")}


def _effect_lines(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip().startswith("effect:")]


def test_position_effect_in_metres_of_a_model_without_latitude(capsys):
    """Was "0 m" (JSON 0.0) for every finding: the position was read from latitude and
    longitude outputs only. The dropped centrifugal term U² δx_E moves the position
    11.8 m in 1 h and 284 m in 24 h (the probe's own propagation)."""
    data, text = _check(capsys, str(MODEL), str(EQUATIONS))
    effects = _effects(data)
    dropped = effects["7 delta_x_E"]
    assert dropped["point"] == "static base"

    def drop(f, names):
        f[names.index("delta_V_E"), names.index("delta_x_E")] = 0.0
    for hours in (1.0, 24.0):
        position, attitude = _reference(drop, hours)
        tag = f"{int(hours)}h"
        assert dropped[f"position_{tag}"] == pytest.approx(position, rel=1e-5)
        assert dropped[f"attitude_{tag}"] == pytest.approx(attitude, rel=1e-5)
    assert dropped["position_1h"] == pytest.approx(11.8, abs=0.05)
    assert dropped["position_24h"] == pytest.approx(284, abs=0.5)
    assert _effect_lines(text)[0].startswith("effect: 1 h: 11.8 m, ")
    assert "24 h: 284 m, " in _effect_lines(text)[0]
    # the other drop, U² sin²φ0 δx_N, likewise
    def drop_north(f, names):
        f[names.index("delta_V_N"), names.index("delta_x_N")] = 0.0
    position, _ = _reference(drop_north, 24.0)
    assert effects["8 delta_x_N"]["position_24h"] == pytest.approx(position, rel=1e-5)
    # every effect has a position figure: no false zero
    for effect in effects.values():
        for tag in ("1h", "24h"):
            assert effect[f"position_{tag}"] > effect[f"position_floor_{tag}"] > 0


def test_integrator_states_are_no_attitude():
    """Only the extra error states in rad are platform angles; the damping integrators
    q_E, q_N (m/s²) are extra error states, not attitude."""
    from ins_errors.model_lookup import definition_of, resolve

    d = definition_of(resolve(str(MODEL)))
    assert [v.name for v in d.platform_angles] == ["alpha_E", "alpha_N", "alpha_U"]
    assert [v.name for v in d.extra_error_states] == ["alpha_E", "alpha_N", "alpha_U",
                                                      "q_E", "q_N"]


@pytest.fixture
def q_row(tmp_path) -> Path:
    path = tmp_path / "q_row_wrong.txt"
    path.write_text(Q_ROW_WRONG, encoding="utf-8")
    return path


def test_an_integrator_slip_is_sized_by_the_platform_angles(capsys, q_row):
    """The slip 2·c_i in q̇_E said 152″ after 1 h (the integrators counted as attitude);
    the platform angles change 9.64e-5 rad = 19.9″ (the probe's propagation)."""
    data, text = _check(capsys, str(MODEL), str(q_row), *DAMPED_OPTIONS)
    (effect,) = _effects(data).values()

    def slip(f, names):
        f[names.index("q_E"), names.index("delta_V_E")] *= 2.0
    for hours in (1.0, 24.0):
        position, attitude = _reference(slip, hours, DAMPED)
        tag = f"{int(hours)}h"
        assert effect[f"attitude_{tag}"] == pytest.approx(attitude, rel=1e-5)
        assert effect[f"position_{tag}"] == pytest.approx(position, rel=1e-5)
    assert effect["attitude_1h"] == pytest.approx(9.64e-5, rel=1e-3)
    assert "19.9″" in _effect_lines(text)[0]


def _variant(tmp_path: Path, name: str, *replacements: tuple[str, str]) -> Path:
    """A copy of the model file with its text replaced (each replacement must apply)."""
    text = MODEL.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / f"{name}.py"
    path.write_text(text.replace('name="tangent_plane_ins"', f'name="{name}"'),
                    encoding="utf-8")
    return path


NORTH_OUT = 'Variable("x_N", "m", "north position", "x_N"),'
EAST_OUT = 'Variable("x_E", "m", "east position", "x_E"),'
OUTPUT_MAP = "return sp.Matrix([x_E, x_N, V_E, V_N])"


def test_position_is_read_by_what_the_outputs_are_not_by_their_names(tmp_path, capsys, q_row):
    """Outputs renamed (p_1 north first, p_2 east negated: "west") give the same position
    figures; a model whose outputs hold no position in metres, or one whose only metre
    outputs are not north and east (a position along a rotated axis), says "position n/a"
    (JSON null), never 0, and keeps its attitude figure."""
    reference, text = _check(capsys, str(MODEL), str(q_row), *DAMPED_OPTIONS)
    (expected,) = _effects(reference).values()
    renamed = _variant(tmp_path, "renamed",
                       (EAST_OUT + "\n    " + NORTH_OUT,
                        'Variable("p_1", "m", "north", "p_1"),\n'
                        '    Variable("p_2", "m", "west", "p_2"),'),
                       (OUTPUT_MAP, "return sp.Matrix([x_N, -x_E, V_E, V_N])"))
    data, _ = _check(capsys, str(renamed), str(q_row), *DAMPED_OPTIONS)
    (effect,) = _effects(data).values()
    for key in ("position_1h", "position_24h", "attitude_1h", "attitude_24h"):
        assert effect[key] == pytest.approx(expected[key], rel=1e-5), key
    # checked on the static base only, the outputs are still what they are
    scoped = tmp_path / "scoped.txt"
    scoped.write_text("@scope static base\n" + Q_ROW_WRONG, encoding="utf-8")
    data, _ = _check(capsys, str(renamed), str(scoped), *DAMPED_OPTIONS)
    (effect,) = _effects(data).values()
    assert [p["label"] for p in data["points"]] == ["static base"]
    assert effect["position_24h"] == pytest.approx(expected["position_24h"], rel=1e-5)
    for name, replacements in (
            ("velocity_only", ((EAST_OUT, ""), (NORTH_OUT, ""),
                               (OUTPUT_MAP, "return sp.Matrix([V_E, V_N])"))),
            ("rotated", ((OUTPUT_MAP, "return sp.Matrix([x_E + x_N, x_N - x_E, V_E, V_N])"),))):
        path = _variant(tmp_path, name, *replacements)
        data, text = _check(capsys, str(path), str(q_row), *DAMPED_OPTIONS)
        (effect,) = _effects(data).values()
        for tag in ("1h", "24h"):
            assert effect[f"position_{tag}"] is None, (name, effect)
            assert effect[f"position_floor_{tag}"] is None
            assert effect[f"attitude_{tag}"] == pytest.approx(expected[f"attitude_{tag}"],
                                                              rel=1e-5)
        line = _effect_lines(text)[0]
        assert line.startswith("effect: 1 h: position n/a, 19.9″"), (name, line)
        assert " 0 m" not in line


def test_origin_latitude_at_a_pole_is_refused_as_compare_refuses_it(capsys):
    """check ran at phi0 = 90° and printed effects of 6e15″; compare, modes and budget
    refuse it in one line (the model's own domain), and so does check now."""
    assert main(["compare", str(MODEL), "-p", "phi0=90deg",
                 "--source", "gyro_drift_E=0.01deg/h"]) == 2
    compare = capsys.readouterr().err.strip().splitlines()
    assert main(["check", str(MODEL), str(EQUATIONS), "-p", "phi0=90deg"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.strip().splitlines() == compare
    assert compare == ["ins-errors: error: parameters of tangent_plane_ins: origin latitude "
                       "phi0 at a pole"]
    # inside the domain the check runs (one root mistake per slip)
    assert main(["check", str(MODEL), str(EQUATIONS), "-p", "phi0=89deg"]) == 1


def _great_circle_track(distance: float) -> float:
    """Track (deg) of the great circle leaving (50°, 30°) at 60° after ``distance`` m on a
    6371 km sphere: the reverse of the bearing back to the start (spherical trigonometry)."""
    lat1, lon1, bearing = map(math.radians, (50.0, 30.0, 60.0))
    delta = distance / R
    lat2 = math.asin(math.sin(lat1) * math.cos(delta)
                     + math.cos(lat1) * math.sin(delta) * math.cos(bearing))
    lon2 = lon1 + math.atan2(math.sin(bearing) * math.sin(delta) * math.cos(lat1),
                             math.cos(delta) - math.sin(lat1) * math.sin(lat2))
    back = math.atan2(math.sin(lon1 - lon2) * math.cos(lat1),
                      math.cos(lat2) * math.sin(lat1)
                      - math.sin(lat2) * math.cos(lat1) * math.cos(lon1 - lon2))
    return (math.degrees(back) + 180.0) % 360.0


def test_reference_points_say_what_they_are_for_a_model_without_latitude(capsys, q_row):
    """They said "φ 50°, λ 30°, heading 30°" (and "h 10 km") for a model that takes none
    of them, whatever its phi0: it sits at rest at its origin, or flies 250 m/s at the
    cruise points' tracks."""
    for options in ([], ["-p", "phi0=20deg"]):
        data, _ = _check(capsys, str(MODEL), str(q_row), *DAMPED_OPTIONS, *options)
        points = {p["label"]: p["description"] for p in data["points"]}
        assert list(points) == ["static base", "cruise 0 km", "cruise 2000 km",
                                "cruise 4000 km"]
        for description in points.values():
            for word in ("φ", "λ", "heading", "h 10 km", "h 0", "height input"):
                assert word not in description, (word, description)
            assert "the model takes no latitude, longitude or height" in description
        assert points["static base"].startswith("static base, at rest")
        assert points["cruise 0 km"].startswith("cruise, 250 m/s, track 60°")
        for km in (2000, 4000):
            track = _great_circle_track(km * 1e3)
            assert points[f"cruise {km} km"].startswith(f"cruise, 250 m/s, track {track:.4g}°")
            assert f"the track {km} km along the great circle" in points[f"cruise {km} km"]


def test_no_height_note_for_a_model_with_a_height_initial_condition(capsys, tmp_path):
    """strapdown_sphere.py takes its height as an initial condition (no height input): its
    points said "(the model has no height input)", at h 10 km too. free_azimuth, with
    neither, still says so."""
    hand = tmp_path / "sphere_h.txt"
    hand.write_text("dot(delta_h) = -delta_v_D\n", encoding="utf-8")
    sphere = ROOT.parent / "examples" / "strapdown" / "strapdown_sphere.py"
    data, text = _check(capsys, str(sphere), str(hand), status=0)
    descriptions = [p["description"] for p in data["points"]]
    assert any("h 10 km" in d for d in descriptions)
    assert not any("height" in d for d in descriptions), descriptions
    assert "no height input" not in text
    from ins_errors.checker.reference import reference_points
    from ins_errors.model_lookup import definition_of, resolve

    for name, note in (("free_azimuth", True), ("strapdown_ned", False),
                       ("north_pointing", False)):
        points = reference_points(definition_of(resolve(name))).points
        assert all(("(the model has no height input)" in p.description) == note
                   for p in points), name


def test_a_matrix_check_of_a_platform_model_says_what_works(capsys, tmp_path):
    """--matrix was refused with ~900 characters of strapdown requirements (roll, pitch,
    omega_x, f_x, ...); --list-conventions offered "bias states ... in any convention" to
    a model no convention works for."""
    matrix = tmp_path / "my_F.py"
    matrix.write_text("import numpy as np\nSTATES = ['delta_V_E']\n"
                      "def F(nav, imu):\n    return np.zeros((1, 1))\n", encoding="utf-8")
    assert main(["check", str(MODEL), "--matrix", f"{matrix}:F"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and len(err[0]) < 450, err
    for word in ("'tangent_plane_ins'", "platform model", "north_pointing",
                 "as an equation file", "docs/matrix_check.md"):
        assert word in err[0], (word, err[0])
    for word in ("strapdown", "roll", "omega_x", "f_x", "IMU inputs"):
        assert word not in err[0], (word, err[0])
    # the way out it names works: an equation file in the model's own error states
    assert main(["check", str(MODEL), str(EQUATIONS)]) == 1
    capsys.readouterr()
    assert main(["check", str(MODEL), "--list-conventions"]) == 0
    out = capsys.readouterr().out
    assert "bias states" not in out and "any convention" not in out
    assert "no convention" in out and "equation file" in out
    assert "  q_E (m/s**2): damping integrator, east" in out
    assert main(["check", str(MODEL), "--list-conventions", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["conventions"] == [] and data["bias_states"] == []
    assert [s["name"] for s in data["equation_file_states"]] == [
        "delta_V_E", "delta_V_N", "delta_x_E", "delta_x_N", "alpha_E", "alpha_N", "alpha_U",
        "q_E", "q_N"]
    # a model with a navigation description keeps its conventions and bias states
    assert main(["check", "north_pointing", "--list-conventions"]) == 0
    assert "bias states" in capsys.readouterr().out
