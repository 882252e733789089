"""The --at breakdown shows every navigation error of every model: its position as metres
north and east, its velocity, its height where it has one, its attitude (a platform
model's angles, a strapdown model's roll, pitch and heading).

north_pointing's latitude, longitude and velocity outputs are error states of their own
(H reads each state alone), as a strapdown model's velocities are: the breakdown once
took the functionals after the computed states' errors only, which left north_pointing
with its three platform angles and a strapdown model without its velocities.

The value check: a north accelerometer bias b on a static base at φ = −35°, alone, moves
the north-pointing INS north by Δr_N = R δφ, from the linear error equations the spec
samples, integrated exactly (the matrix exponential of F augmented with the bias's
column of G), and, to the Foucault approximation (the Earth rate's coupling of the
azimuth left out), by the textbook Schuler response b/ω_s² (1 − cos ω_s t cos(Ω sin φ t)).
"""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent
SPHERE_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"

PLATFORM_NAVIGATION = ["delta_r_N", "delta_r_E", "delta_v_N", "delta_v_E"]
STRAPDOWN_NAVIGATION = ["delta_r_N", "delta_r_E", "delta_height", "delta_v_N", "delta_v_E",
                        "delta_v_D", "delta_roll", "delta_pitch", "delta_heading"]
EXPECTED = {
    "orthodromic": ["alpha_x", "alpha_y", "alpha_z", "delta_heading", *PLATFORM_NAVIGATION],
    "north_pointing": ["alpha_E", "alpha_N", "alpha_U", *PLATFORM_NAVIGATION],
    "free_azimuth": ["alpha_x", "alpha_y", "alpha_z", "delta_heading", *PLATFORM_NAVIGATION],
    "geodetic_vertical": ["alpha_x", "alpha_y", "alpha_z", *PLATFORM_NAVIGATION],
    "strapdown_ned": STRAPDOWN_NAVIGATION,
    "sphere file": STRAPDOWN_NAVIGATION,
}
"""Navigation errors each model's breakdown must show (position, height, velocity,
attitude; the platform models' angles are their attitude), among what else it shows."""

UNITS = {"delta_r_N": "m", "delta_r_E": "m", "delta_height": "m", "delta_v_N": "m/s",
         "delta_v_E": "m/s", "delta_v_D": "m/s"}

AT_REST = """
    title = "an hour at rest"
    sigma_level = 1
    operating_time = "1 h"
    step = "60 s"
    [motion]
    kind = "static"
    latitude = "-35 deg"
    [items.position_error_absolute]
    value = "10 km"
"""


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def contributions(argv: list[str], capsys, status: int = 0) -> dict:
    assert main(argv) == status
    return json.loads(capsys.readouterr().out)["contributions"]


@pytest.mark.parametrize("model", list(EXPECTED))
def test_every_model_shows_every_navigation_error(model, tmp_path, capsys):
    """Each built-in model and a strapdown model file: the breakdown at 1 h holds the
    position north and east in metres, the velocity, a strapdown INS's height and
    vertical velocity, the attitude, each once, and at rest for an hour every source
    together moves the position and the velocity (not a column of zeros)."""
    name = str(SPHERE_FILE) if model == "sphere file" else model
    c = contributions(["budget", name, "--spec", str(write(tmp_path, AT_REST)), "--at",
                       "1 h", "--json"], capsys)
    quantities = c["quantities"]
    assert len(set(quantities)) == len(quantities)
    missing = [q for q in EXPECTED[model] if q not in quantities]
    assert not missing, f"{model}: {missing} not shown (shown: {quantities})"
    assert "delta_latitude" not in quantities and "delta_longitude" not in quantities
    for q, unit in UNITS.items():
        if q in EXPECTED[model]:
            assert c["units"][quantities.index(q)] == unit, q
    for q in PLATFORM_NAVIGATION:
        assert c["total"][0][quantities.index(q)] > 0, q


NORTH_POINTING = """
    title = "north-pointing INS at rest"
    sigma_level = 1
    operating_time = "4 h"
    step = "60 s"
    [motion]
    kind = "static"
    latitude = "-35 deg"
    [items.position_error_absolute]
    value = "10 km"
    [sources.gyro_drift_east]
    fixed = "0.01 deg/h"
    [sources.accel_bias_north]
    fixed = "50 ug"
"""


def test_north_pointing_shows_its_position_and_velocity(tmp_path, capsys, monkeypatch):
    """The users' spec: --at "1 h, 2 h" showed the three platform angles alone, and the
    --plot-at chart three tilt bars; both show the position north and east (m) and the
    velocity beside the angles."""
    from ins_errors.analysis import budget_report as rep

    captured: dict = {}
    monkeypatch.setattr(rep, "save_figure",
                        lambda fig, path, dpi=None: captured.setdefault("fig", fig))
    spec = str(write(tmp_path, NORTH_POINTING))
    c = contributions(["budget", "north_pointing", "--spec", spec, "--at", "1 h, 2 h",
                       "--plot-at", str(tmp_path / "at.png"), "--json"], capsys)
    assert c["quantities"] == EXPECTED["north_pointing"]
    for axis in captured["fig"].axes[:2]:   # one panel per time
        labels = [t.get_text().split("\n")[0] for t in axis.get_xticklabels()]
        assert labels == ["alpha_E", "alpha_N", "alpha_U", "Δr_N", "Δr_E", "Δv_N", "Δv_E"]
    assert main(["budget", "north_pointing", "--spec", spec, "--at", "1 h"]) == 0
    header = [line for line in capsys.readouterr().out.splitlines()
              if line.startswith("source (1σ)")][-1]
    assert header.split()[2:] == ["alpha_E", "arcmin", "alpha_N", "arcmin", "alpha_U",
                                  "arcmin", "Δr_N", "m", "Δr_E", "m", "Δv_N", "m/s", "Δv_E",
                                  "m/s"]


def test_an_accelerometer_bias_moves_north_pointing_north_as_the_equations_do(
        tmp_path, capsys):
    """accel_bias_north fixed at 50 µg: its Δr_N at 1 h in the breakdown is R δφ of
    the spec's own linear error equations integrated exactly for that source alone
    (expm of [[F, g_b], [0, 0]], F constant at rest), to 1e-9, and the textbook's
    Foucault-modulated Schuler response to 0.5 % (the approximation leaves out the
    azimuth's Earth-rate coupling: 0.2 % here)."""
    from scipy.linalg import expm

    from ins_errors.analysis import budget as bd
    from ins_errors.numeric.model import load_model
    from ins_errors.specs import load_spec

    path = write(tmp_path, NORTH_POINTING)
    c = contributions(["budget", "north_pointing", "--spec", str(path), "--at", "1 h",
                       "--json"], capsys)
    budget_value = c["std"][0][c["quantities"].index("delta_r_N")][
        c["sources"].index("accel_bias_north")]

    model = load_model("north_pointing")
    system = bd.spec_system(model, load_spec(path))
    assert system.F.ndim == 2 and system.G.ndim == 2   # at rest: constant
    n = system.F.shape[0]
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n] = system.F
    augmented[:n, n] = system.G[:, list(system.source_names).index("accel_bias_north")]
    b = 50e-6 * 9.80665                        # 50 µg, 1σ (the spec is 1σ), m/s²
    t = 3600.0
    x = expm(augmented * t)[:n, n] * b
    R, g = 6371000.0, 9.80665                  # north_pointing's sphere and gravity
    lat = [s.name for s in model.error_states].index("delta_latitude")
    assert budget_value == pytest.approx(R * abs(x[lat]), rel=1e-9)

    w = np.sqrt(g / R)
    foucault = 7.292115e-5 * np.sin(np.radians(-35.0))
    textbook = b / w**2 * (1 - np.cos(w * t) * np.cos(foucault * t))
    assert budget_value == pytest.approx(textbook, rel=5e-3)
