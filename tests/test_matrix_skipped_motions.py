"""The matrix check (and a ``@convention`` file's check) of a model that cannot fly some
of the checker's motions: a wander-azimuth INS whose wander angle is fixed in its
initial-state map (tests/models/wander_azimuth.py with the literal α₀ = 0.5 for the
parameter ``alpha0``), so that no parameter carries it when it moves with the path off a
meridian (α̇ = λ̇ sin φ): it flies the static base only. The check runs on the motions it
can fly and lists the others with the one-line refusal of their flight; only that refusal
skips a motion. The wander model itself, whose ``alpha0`` the flights carry, flies all
three.

Reference, independent of the code under test: the static base flown here directly by
the strapdown flight generator and checked through the Python API with
``motion_list=[static]`` (the check on the motions given, as before).
"""

from __future__ import annotations

import io
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from ins_errors.checker import check_motions, motion_store
from ins_errors.cli import main
from ins_errors.errors import DomainError
from ins_errors.json_output import dumps
from ins_errors.numeric import cache
from ins_errors.numeric import strapdown_truth as st
from ins_errors.numeric.model import load_model
from ins_errors.numeric.trajectories import (
    EarthParameterError,
    MotionError,
    PathDependentStateError,
)

ROOT = Path(__file__).resolve().parents[1]
WANDER = ROOT / "tests" / "models" / "wander_azimuth.py"
PSI_MODEL = f"{ROOT / 'examples' / 'strapdown' / 'psi_model.py'}:psi_model"
PHI_FILE = ROOT / "examples" / "strapdown" / "phi_attitude.txt"
STATIC = st.static(np.radians(50.0), np.radians(30.0), 0.0, heading=np.radians(30.0))
WANDER_REASON = "moves along a state that no navigation quantity sets (such as a wander angle)"


@pytest.fixture(scope="module")
def fixed(tmp_path_factory) -> Path:
    """The wander model with its wander angle fixed in its initial-state map."""
    text = WANDER.read_text(encoding="utf-8")
    old = 'C_wn = turn_z(S["alpha0"])'
    assert text.count(old) == 1
    path = tmp_path_factory.mktemp("fixed") / "wander_fixed_angle.py"
    path.write_text(text.replace(old, "C_wn = turn_z(sp.Rational(1, 2))").replace(
        'name="wander_azimuth"', 'name="wander_fixed_angle"'), encoding="utf-8")
    return path


def _static_motion(model, hours: float = check_motions.HOURS,
                   step: float = check_motions.STEP) -> check_motions.Motion:
    """The static base of the check, flown here by the strapdown flight generator."""
    from ins_errors.checker.navigation import navigation_arrays

    run = st.trajectory(model, STATIC, hours * 3600.0, step)
    steps = np.arange(run.n_steps + 1)
    x = np.ascontiguousarray(np.repeat(run.truth[:, :1], steps.size, axis=1))
    u = np.ascontiguousarray(run.inputs_at(steps))
    return check_motions.Motion("static", STATIC.description, run.times, x, u,
                                run.parameters, navigation_arrays(model, x, u, run.parameters))


def _labels(skipped: list[str]) -> list[str]:
    return [text.split(":", 1)[0] for text in skipped]


def test_the_wander_models_matrix_check_flies_all_three_motions(capsys):
    # its wander angle starts at the parameter alpha0, which the flights carry
    status = main(["check", str(WANDER), "--matrix", PSI_MODEL, "--convention", "psi",
                   "--json"])
    shown = json.loads(capsys.readouterr().out)
    assert status == 0 == shown["exit_status"]
    assert [m["label"] for m in shown["motions"]] == ["static", "cruise", "manoeuvre"]
    assert shown["skipped_motions"] == []
    # the textbook ψ model on a sphere against WGS-84: small terms only, now also those
    # of flight (the transport rate's Earth)
    assert not [f for f in shown["findings"] if f["severity"] == "mistake"]
    assert len(shown["findings"]) > 4


def test_a_fixed_wander_angles_matrix_check_runs_on_the_static_base_saying_why_not_the_others(
        tmp_path, capsys, fixed):
    from ins_errors.checker.matrix import check_matrices
    from ins_errors.checker.matrix_report import to_json

    command = ["check", str(fixed), "--matrix", PSI_MODEL, "--convention", "psi"]
    status = main([*command, "--json"])
    shown = json.loads(capsys.readouterr().out)
    # the textbook model on a sphere differs from the wander model's WGS-84 only in small
    # terms (tests/test_wander_azimuth.py): no mistake, exit 0
    assert status == 0 == shown["exit_status"]
    assert [m["label"] for m in shown["motions"]] == ["static"]
    assert _labels(shown["skipped_motions"]) == ["cruise", "manoeuvre"]
    assert all(WANDER_REASON in text and "\n" not in text for text in shown["skipped_motions"])
    # the same check on the static base alone, given through the API
    alone = check_matrices(str(fixed), PSI_MODEL, "psi",
                           motion_list=[_static_motion(load_model(str(fixed)))])
    assert alone.skipped_motions == []
    expected = json.loads(dumps(to_json(alone)))
    for key in ("findings", "effects", "compared", "held", "magnitudes"):
        assert shown[key] == expected[key], key
    assert len(shown["findings"]) == 4 and shown["effects"]

    report = tmp_path / "r.md"
    assert main([*command, "--report", str(report)]) == 0
    out = capsys.readouterr().out.splitlines()
    not_flown = [line for line in out if line.startswith("motion not flown: ")]
    assert _labels([line.removeprefix("motion not flown: ") for line in not_flown]) == [
        "cruise", "manoeuvre"]
    assert all(WANDER_REASON in line for line in not_flown)
    markdown = report.read_text(encoding="utf-8")
    assert "Motions not flown (the model cannot follow them):" in markdown
    assert "* `cruise`: model 'wander_fixed_angle' cannot fly this flight" in markdown


def test_a_convention_file_on_a_fixed_wander_angle_runs_on_the_static_base(tmp_path, capsys,
                                                                           fixed):
    status = main(["check", str(fixed), str(PHI_FILE), "--json"])
    shown = json.loads(capsys.readouterr().out)
    assert status == shown["exit_status"] == 0
    assert [m["label"] for m in shown["motions"]] == ["static"]
    assert _labels(shown["skipped_motions"]) == ["cruise", "manoeuvre"]
    # a file about a motion the model cannot fly is refused in one line saying why
    scoped = tmp_path / "cruise_only.txt"
    scoped.write_text("@scope cruise\n" + PHI_FILE.read_text(encoding="utf-8"),
                      encoding="utf-8")
    assert main(["check", str(fixed), str(scoped)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'@scope cruise' is the cruise motion" in err[0]
    assert WANDER_REASON in err[0]


@pytest.mark.parametrize("error", [DomainError("NaN along the flight"),
                                   EarthParameterError("radius of metres"),
                                   MotionError("no inputs make its 'lat' move as the "
                                               "flight does")])
def test_only_a_refusal_to_follow_a_flight_skips_it(monkeypatch, error):
    model = load_model("strapdown_ned")
    p = model.parameter_vector()
    real = st.trajectory

    def failing(on: str, raised: Exception):
        def trajectory(model, flight, *args, **kwargs):
            if flight.description.startswith(on):
                raise raised
            return real(model, flight, *args, **kwargs)
        return trajectory

    monkeypatch.setattr(st, "trajectory",
                        failing("great circle",
                                PathDependentStateError("cannot follow the cruise")))
    flown, skipped = check_motions._fly(model, 0.5, 600.0, p)
    assert [label for label, _, _ in flown] == ["static", "manoeuvre"]
    assert skipped == ["cruise: cannot follow the cruise"]
    # any other error of a moving flight, and the static base's refusal, stop the check
    monkeypatch.setattr(st, "trajectory", failing("great circle", error))
    with pytest.raises(type(error)):
        check_motions._fly(model, 0.5, 600.0, p)
    monkeypatch.setattr(st, "trajectory",
                        failing(STATIC.description[:6], MotionError("no rest")))
    with pytest.raises(MotionError, match="no rest"):
        check_motions._fly(model, 0.5, 600.0, p)


def test_stored_motions_keep_the_motions_not_flown(tmp_path, monkeypatch, fixed):
    key = load_model(str(fixed)).key
    monkeypatch.setattr(motion_store, "folder", lambda: tmp_path / "motions")
    fly = check_motions._motions.__wrapped__  # past the per-process cache
    flown, skipped = fly(key, 1.0, 600.0, None)
    (stored,) = (tmp_path / "motions").glob("*.npz")
    read, skipped_read = fly(key, 1.0, 600.0, None)
    assert [m.label for m in flown] == [m.label for m in read] == ["static"]
    assert skipped_read == skipped and _labels(list(skipped)) == ["cruise", "manoeuvre"]
    assert np.array_equal(read[0].x, flown[0].x)
    # a file holding the flown motions without those not flown is no motion set (a
    # whole, sealed file: not one found damaged)
    with np.load(io.BytesIO(cache.unsealed(stored.read_bytes()))) as data:
        partial = {k: data[k] for k in data.files if k != "skipped"}
    written = io.BytesIO()
    np.savez(written, **partial)
    cache.write_entry(stored, written.getvalue())
    with warnings.catch_warnings():
        warnings.simplefilter("error")   # not said to be damaged
        assert motion_store.load(stored.stem) is None


def test_strapdown_ned_flies_all_three_motions():
    flown, skipped = check_motions.flown_motions(load_model("strapdown_ned"), 0.5, 600.0)
    assert [m.label for m in flown] == ["static", "cruise", "manoeuvre"] and skipped == []
