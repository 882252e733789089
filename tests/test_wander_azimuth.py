"""A wander-azimuth strapdown INS as a model file (tests/models/wander_azimuth.py): its
wander angle is a state that no navigation quantity sets (turning its position matrix
about the vertical and counter-turning its attitude and velocity changes no output).

References, independent of the code under test:

* ``strapdown_ned`` on the same WGS-84 Earth, normal gravity and static base: its own
  hand-written maps into the φ/ψ conventions give the same F and G as the wander model
  carried into them through its equations (the wander angle drops out);
* the textbook ψ-angle model of examples/strapdown/psi_model.py (Benson 1975).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.checker.conventions import conventions
from ins_errors.cli import main
from ins_errors.models import strapdown_conventions as sc
from ins_errors.numeric import strapdown_truth as st

ROOT = Path(__file__).resolve().parents[1]
WANDER = ROOT / "tests" / "models" / "wander_azimuth.py"
PSI_MODEL = ROOT / "examples" / "strapdown" / "psi_model.py"
STATIC = st.static(np.radians(50.0), np.radians(30.0), 0.0, heading=np.radians(30.0))


@pytest.fixture(scope="module")
def wander():
    return load_model(str(WANDER))


def _static(model, p=None):
    """States and inputs (n, 3), (nu, 3) of the static base."""
    run = st.trajectory(model, STATIC, 120.0, 60.0, p=p)
    x = np.repeat(run.truth[:, :1], 3, axis=1)
    return np.ascontiguousarray(x), np.ascontiguousarray(run.inputs_at(np.arange(3))), run


@pytest.mark.parametrize("name", ["phi", "psi", "phi_modified"])
def test_the_wander_model_in_a_convention_is_strapdown_ned_on_the_static_base(wander, name):
    p = wander.parameter_vector(alpha0=0.7)
    x, u, _ = _static(wander, p)
    conv = conventions(wander)[name]
    T, T_dot = conv.matrices(wander, x, p, u)  # refused before: 'PYx' leaves the span
    L = np.moveaxis(conv.lift(x, p), -1, 0)
    F = np.moveaxis(wander.state_matrix(x, u, p), -1, 0)
    G = np.moveaxis(wander.source_matrix(x, u, p), -1, 0)
    F_mine, G_mine = (T_dot + T @ F) @ L, T @ G
    ned = load_model("strapdown_ned")
    x_n, u_n, run = _static(ned)
    F_ned, G_ned = (np.moveaxis(m, -1, 0) for m in
                    sc.convention_matrices(ned, name, x_n, u_n, run.parameters))
    scale = np.abs(F_ned).max(axis=2, keepdims=True)  # per row (rows of mixed units)
    assert (np.abs(F_mine - F_ned) / scale).max() < 1e-9
    columns = [ned.index("sources", s.name) for s in wander.sources]
    np.testing.assert_allclose(G_mine, G_ned[:, :, columns], rtol=0,
                               atol=1e-12 * np.abs(G_ned).max())


def test_the_textbook_psi_model_checked_against_the_wander_model_on_the_static_base(wander):
    from ins_errors.checker.check_motions import Motion
    from ins_errors.checker.matrix import check_matrices
    from ins_errors.checker.navigation import navigation_arrays

    run = st.trajectory(wander, STATIC, 3600.0, 60.0)
    steps = np.arange(run.n_steps + 1)
    x = np.ascontiguousarray(np.repeat(run.truth[:, :1], steps.size, axis=1))
    u = np.ascontiguousarray(run.inputs_at(steps))
    motion = Motion("static", STATIC.description, run.times, x, u, run.parameters,
                    navigation_arrays(wander, x, u, run.parameters))
    report = check_matrices(str(WANDER), f"{PSI_MODEL}:psi_model", "psi", hours=1.0,
                            motion_list=[motion])
    findings = {(f.row, f.column): f for f in report.findings}
    assert not [k for k, f in findings.items() if f.severity == "mistake"], findings
    # the textbook's sphere: its gravity gradients g/R, 2g/R (R = a) and no change of
    # gravity with latitude: small terms only
    assert set(findings) == {("dvc_D", "dr_N"), ("dvc_D", "dr_D"), ("dvc_N", "dr_N"),
                             ("dvc_E", "dr_E")}


def test_a_budget_runs_on_the_wander_model(capsys):
    status = main(["budget", str(WANDER), "-p", "k1=0.0293/s", "-p", "k2=4.42e-4/s^2",
                   "--json"])
    report = json.loads(capsys.readouterr().out)
    assert status == 0
    items = {row["item"] for row in report["rows"]}
    assert {"vertical_error", "heading_drift"} <= items


BARO_LOOP_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"


def test_the_budget_refuses_a_state_it_cannot_read_in_its_own_words(tmp_path, capsys,
                                                                    monkeypatch):
    from tests.test_strapdown_description import BARO_LOOP

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = BARO_LOOP_FILE.read_text(encoding="utf-8")
    for old, new in BARO_LOOP:
        text = text.replace(old, new)
    path = tmp_path / "third_order.py"
    path.write_text(text, encoding="utf-8")
    status = main(["budget", str(path)])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    assert "'z' changes with the navigation errors" in err[0]
    assert "attitude items (vertical_error, heading_error, heading_drift)" in err[0]
    assert "--convention" not in err[0] and "hand model" not in err[0]


def test_a_model_on_another_earth_than_its_flight_keeps_its_refusal(tmp_path, capsys,
                                                                    monkeypatch):
    # its latitude moves 1 % slower than the flight's: a navigation quantity, not a state
    # no navigation quantity sets
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # a throw-away model
    text = BARO_LOOP_FILE.read_text(encoding="utf-8")
    old = "v[0] / r, v[1] / (r * sp.cos(lat))"
    assert text.count(old) == 1
    path = tmp_path / "slow_latitude.py"
    path.write_text(text.replace(old, "v[0] / (1.01 * r), v[1] / (r * sp.cos(lat))"),
                    encoding="utf-8")
    status = main(["compare", str(path), "--motion", "great-circle", "--hours", "0.1",
                   "--source", "gyro_bias_x=0.01deg/h"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("ins-errors: deriving")]
    assert status == 2 and len(err) == 1, err
    assert "cannot follow the flight: no inputs make its 'lat' move" in err[0]
