"""An Euler-angle strapdown model file near gimbal lock (pitch ±90°), as a probe flew it.

* A motion whose start is beyond the model's own initial domain (pitch 89.994°) ended in a
  numpy broadcasting traceback: the batched initial-state check built its one-line message
  from the unbatched parameter vector. It is now the model's own domain line, exit 2.
* A climb whose true pitch reaches the boundary (cos²θ = 1e-6, θ = 89.9427°) was blamed
  on "a mode of F at the start ... `ins-errors modes` names the mode"; the flight itself
  takes the model out of its domain, at the time an independent computation of the
  true pitch gives. On a moving base the growth words no longer send the user to
  ``modes``, which analyses the static base only.
* A height beyond ±100 km was refused because "the models' gravity" fails there, though a
  model file may have a constant g; and ``--height 101km`` printed its figures twice.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import ins_errors
from ins_errors.cli import main
from ins_errors.errors import DomainError

MODEL = Path(__file__).parent / "models" / "euler_angle_ins.py"
LOCK = math.acos(1e-3)
"""rad: the pitch where the fixture's domain cos²θ > 1e-6 ends (89.9427°)."""
CLIMB = 100.0
"""m/s: the climb rate of the motion files (h = 100 t)."""


def _without_pitch_domain(folder: Path) -> Path:
    """The fixture without its pitch condition (the lines marked ``# pitch domain``)."""
    text = MODEL.read_text(encoding="utf-8")
    kept = [line for line in text.splitlines() if not line.endswith("# pitch domain")]
    assert len(kept) == len(text.splitlines()) - 2
    path = folder / "euler_no_pitch_domain.py"
    path.write_text("\n".join(kept).replace('name="euler_angle_ins"',
                                            'name="euler_no_pitch_domain"') + "\n",
                    encoding="utf-8")
    return path


def _motion_file(path: Path, north, end: float = 140.0) -> Path:
    """A climb at CLIMB m/s with north speed ``north(t)`` (m/s), samples every 2 s to
    ``end`` (s)."""
    t = np.arange(0.0, end + 1.0, 2.0)
    rows = ["t,v_N,v_E,h"] + [f"{ti:g},{north(ti):.12g},0,{CLIMB * ti:g}" for ti in t]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def _pitch(north: float) -> float:
    """True pitch (rad) of the climb at north speed ``north``: the flight-path angle."""
    return math.atan2(CLIMB, north)


def _one_line_error(capsys, argv) -> str:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    return err.removeprefix("ins-errors: error: ").strip()


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_the_batched_initial_check_refuses_gimbal_lock_like_the_unbatched_one():
    """The unbatched call refused pitch 89.999° with the model's domain line; the batched
    one (c, u of shape (n, 1), one parameter vector (np,)) raised numpy's ValueError."""
    model = ins_errors.load_model(str(MODEL))
    assert math.degrees(LOCK) < 89.999
    c = model.initial_condition_vector(latitude=np.radians(50.0), pitch=np.radians(89.999))
    u = np.zeros(len(model.inputs))
    w = np.zeros(len(model.sources))
    with pytest.raises(DomainError) as unbatched:
        model.initial_state(c, u)
    with pytest.raises(DomainError) as batched:
        model.initial_real_state(c[:, None], u[:, None], w[:, None], model.parameter_vector())
    for caught in (unbatched, batched):
        assert str(caught.value).endswith(": initial pitch at gimbal lock"), caught.value
    # a batch of three starts, the last at gimbal lock, against inputs of shape (nu, 1)
    fine = model.initial_condition_vector(latitude=np.radians(50.0), pitch=np.radians(89.9))
    starts = np.stack([fine, fine, c], axis=1)
    with pytest.raises(DomainError, match="initial pitch at gimbal lock"):
        model.initial_error_matrix(starts, u[:, None], model.parameter_vector())
    model.initial_error_matrix(starts[:, :2], u[:, None], model.parameter_vector())
    # the pole's line (which quotes the batched point's latitude) still works batched
    pole = model.initial_condition_vector(latitude=np.radians(90.0))
    with pytest.raises(DomainError, match=r"latitude 90° is refused"):
        model.initial_real_state(pole[:, None], u[:, None], w[:, None],
                                 model.parameter_vector())


def test_a_motion_starting_beyond_gimbal_lock_is_refused_in_one_line(in_tmp, capsys):
    """A vertical climb with 1 cm/s north: pitch atan(100/0.01) = 89.9943° at the start,
    beyond the model's initial domain (89.9427°)."""
    assert _pitch(0.01) > LOCK
    _motion_file(in_tmp / "steep.csv", lambda t: 0.01)
    err = _one_line_error(capsys, ["compare", str(MODEL), "--motion-file", "steep.csv",
                                   "--latitude", "50deg", "--duration", "1min", "--step",
                                   "0.5s", "--source", "gyro_bias_x=0.01deg/h"])
    assert err.endswith("initial pitch at gimbal lock"), err
    # the line says where the value came from, not the library function that read it
    assert "the motion starts outside the" in err and "initial_real_state" not in err, err


def _ramp(t: float) -> float:
    """North speed (m/s) falling by 8 mm/s per second from 1 m/s to 5 cm/s: the pitch
    passes the lock where v_N = 100 cos θ / sin θ ≈ 0.1 m/s, at t ≈ 112.5 s."""
    return max(1.0 - 0.008 * t, 0.05)


def _crossing(north) -> float:
    """Time (s) the true pitch of the climb passes LOCK (bisection on the formula)."""
    lo, hi = 0.0, 140.0
    assert _pitch(north(lo)) < LOCK < _pitch(north(hi))
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _pitch(north(mid)) < LOCK else (lo, mid)
    return lo


def _interval(err: str, step: float = 0.5) -> tuple[float, float]:
    """The times (s) between which the message says the run left its domain."""
    found = re.search(r"between t = ([\d.]+) s and ([\d.]+) s", err)
    if found:
        return float(found[1]), float(found[2])
    found = re.search(r" at t = ([\d.]+) s", err)   # every step recorded
    assert found, err
    return float(found[1]) - step, float(found[1])


@pytest.mark.parametrize("source", ["gyro_bias_x=0.01deg/h", "gyro_bias_x=0"])
def test_a_flight_through_gimbal_lock_is_named_as_the_cause(in_tmp, capsys, source):
    """The probe's words blamed a mode of F at the start and sent him to `modes`, though
    the error-free run leaves the domain too: the flight is named, at the crossing time
    of the true pitch atan2(100, v_N(t)) (112.5 s; linear v_N between samples)."""
    _motion_file(in_tmp / "ramp.csv", _ramp)
    err = _one_line_error(capsys, ["compare", str(MODEL), "--motion-file", "ramp.csv",
                                   "--latitude", "50deg", "--duration", "130s", "--step",
                                   "0.5s", "--source", source])
    assert err.startswith("the flight takes the euler_angle_ins model out of its domain"), err
    assert "pitch at ±90°: Euler-angle gimbal lock" in err
    assert "ideal (error-free) system" in err
    assert "a mode" not in err and "ins-errors modes" not in err, err
    assert "likely cause" not in err, err
    t0, t1 = _interval(err)
    assert t0 - 1.0 <= _crossing(_ramp) <= t1 + 1.0, (t0, t1, _crossing(_ramp))


def _near(t: float) -> float:
    """North speed (m/s) falling from 1 m/s to a floor of 0.1025 m/s at t ≈ 112 s: the true
    pitch stops at atan(100/0.1025) = 89.9413°, just inside the lock (cos²θ = 1.05e-6)."""
    return max(_ramp(t), 0.1025)


def test_a_flight_to_the_edge_is_named_when_the_errors_only_tip_it_over(in_tmp, capsys):
    """The true pitch stays inside; a pitch gyro bias of 0.1°/h (pitch error 4.8e-7 rad
    per second, 5e-5 rad after 100 s) takes the real system over: the motion did most of
    the way (cos²θ from 1e-4 to about 1e-6), and the message says so."""
    assert _pitch(_near(140.0)) < LOCK
    _motion_file(in_tmp / "near.csv", _near)
    err = _one_line_error(capsys, ["compare", str(MODEL), "--motion-file", "near.csv",
                                   "--latitude", "50deg", "--duration", "130s", "--step",
                                   "0.5s", "--source", "gyro_bias_y=0.1deg/h"])
    assert err.startswith("the flight takes the euler_angle_ins model to the edge of its "
                          "domain"), err
    assert "real system: pitch at ±90°" in err and "names the mode" not in err, err
    start, there = (float(v) for v in re.search(
        r"from ([\d.e+-]+) at the start to ([\d.e+-]+) there", err).groups())
    # the model's margin cos²θ − 1e-6 of the true pitch at the start and where it left
    assert start == pytest.approx(math.cos(_pitch(1.0)) ** 2 - 1e-6, rel=2e-3)
    t0, t1 = _interval(err)
    assert math.cos(_pitch(_near(t1))) ** 2 - 1e-6 <= there <= (
        math.cos(_pitch(_near(t0))) ** 2 - 1e-6)


def test_the_growth_warning_of_a_moving_start_does_not_point_to_modes(in_tmp, capsys):
    """Without the pitch condition the model runs through a climb steepening from 84° to
    89.992° (v_N = 10 e^(−t/87.5 s) m/s, the probe's); its F at the start of the climb
    (tan θ ≈ 10) has a mode growing ×e in about a minute that the static base (`modes`,
    pitch 0: only Schuler, Foucault and Earth-rate oscillations) does not have: the
    warning names its rate as F's at the motion's start and does not say `modes` names
    it."""
    model = _without_pitch_domain(in_tmp)
    _motion_file(in_tmp / "steepening.csv", lambda t: 10.0 * math.exp(-t / 87.5), 600.0)
    assert main(["compare", str(model), "--motion-file", "steepening.csv", "--latitude",
                 "50deg", "--duration", "10min", "--step", "0.5s", "--no-refined",
                 "--source", "gyro_bias_x=0.01deg/h"]) == 0
    out = capsys.readouterr().out
    warnings = [line for line in out.splitlines() if "grow exponentially" in line]
    assert warnings, out
    for line in warnings:
        assert "F at the motion's start (of its moving start state" in line, line
        assert "`ins-errors modes" not in line, line
    found = re.search(r"×e every ([\d.]+) (s|min)", warnings[0])
    e_folding = float(found[1]) * (60.0 if found[2] == "min" else 1.0)
    # modes (the static base) shows no mode growing at anything like that rate
    assert main(["modes", str(model), "--latitude", "50deg", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    fastest = max(e["real"] for e in report["eigenvalues"])
    assert fastest < 1e-3 / e_folding, (fastest, e_folding)


@pytest.mark.parametrize("height, once", [("101km", True), ("1000km", False)])
def test_the_height_refusal_is_true_for_any_model_and_says_its_figures_once(
        in_tmp, capsys, height, once):
    """The fixture has a constant g: the refusal may not say its gravity fails. At 101 km
    the series' figures (1.6e-5 and 0.15 %, WGS-84 a) equal the limit's and are said once;
    at 1000 km both are given, the limit's as such."""
    err = _one_line_error(capsys, ["compare", str(MODEL), "--height", height,
                                   "--duration", "1min", "--source",
                                   "gyro_bias_x=0.01deg/h"])
    assert "the models' gravity holds" not in err
    assert "whatever the model" in err and "which the built-in models use" in err, err
    assert err.count("0.0016 %") == 1 and err.count("0.15 %") == 1, err
    assert ("at the limit" in err) is not once, err
    if not once:
        a, h = 6_378_137.0, 1e6
        x = h / a
        series = (1 - 2 * x + 3 * x * x) * (1 + x) ** 2 - 1    # against a²/(a + h)²
        assert f"{100 * series:.2g} % off the inverse-square law" in err
