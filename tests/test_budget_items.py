"""Budget items a design review needs beside the 802m ones: an absolute horizontal
position limit, the height error, the absolute heading error; the standard manoeuvre as
a spec's motion; vertical-channel sources a spec without a height item bounds only
through the horizontal items; a source both fixed and weighted.

References (independent of the code under test):

* a level gyro's drift ε on a static base without Earth rotation (north_pointing with
  U = 0) drives the pure Schuler loop: position error R·ε·(t − sin(ω_s t)/ω_s), ω_s =
  √(g/R), exactly;
* the azimuth gyro's drift ε turns the heading as the component of ε along the Earth's
  axis grows and the rest rotates with the Earth: ε·(sin²φ·t + cos²φ·sin(Ωt)/Ω) (the
  ψ-angle solution, which the Schuler couplings leave within 2e-4 over 20 min);
* an initial height error δh0 of an undamped vertical channel grows as
  δh0·cosh(ω_v t), ω_v² = −∂γ/∂h = (2γ/a)(1 + f + m − 2f sin²φ) (WGS-84 normal
  gravity); with the damping gains k1, k2 the height obeys δḧ + k1 δḣ + (k2 − ω_v²) δh
  = 0 from δḣ(0) = −k1 δh0; a vertical accelerometer bias b gives, undamped,
  (b/ω_v²)(cosh ω_v t − 1).
"""

from __future__ import annotations

import json
import math
import re
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from ins_errors import load_model
from ins_errors.analysis import budget as bd
from ins_errors.cli import main
from ins_errors.errors import InsErrorsError
from ins_errors.specs import HOUR, load_spec, spec_parameters

DEG = math.pi / 180
OMEGA = 7.292115e-5


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def rows_of(evaluation, item: str) -> list[tuple[float, float]]:
    """(time, value) of an item's rows."""
    return [(r.time, float(v)) for r, v in zip(evaluation.rows, evaluation.values,
                                               strict=True) if r.item == item]


@pytest.fixture(scope="module")
def north_pointing():
    return load_model("north_pointing")


@pytest.fixture(scope="module")
def strapdown():
    return load_model("strapdown_ned")


def wgs84_vertical(latitude: float) -> float:
    """ω_v² = −∂γ/∂h of WGS-84 normal gravity at the surface, 1/s²."""
    a, e2, f, m = 6_378_137.0, 0.00669437999014, 1 / 298.257223563, 0.00344978650684
    s2 = math.sin(latitude) ** 2
    gamma = 9.7803253359 * (1 + 0.00193185265241 * s2) / math.sqrt(1 - e2 * s2)
    return 2 * gamma / a * (1 + f + m - 2 * f * s2)


# ------------------------------------------------------------------------------------
# Absolute position
# ------------------------------------------------------------------------------------
SCHULER = """
    sigma_level = 2
    operating_time = "2 h"
    step = "60 s"
    [motion]
    latitude = "50 deg"
    [items.position_error_absolute]
    value = "2 km"
    every = "10 min"
    [parameters]
    U = "0 rad/s"
"""


@pytest.mark.parametrize("gyro", ["gyro_drift_east", "gyro_drift_north"])
def test_absolute_position_of_a_level_gyro_drift_is_the_schuler_ramp(north_pointing, tmp_path,
                                                                     gyro):
    spec = load_spec(write(tmp_path, SCHULER))
    p = north_pointing.parameter_vector(**spec_parameters(spec, north_pointing))
    eps = 0.01 * DEG / HOUR
    evaluation = bd.evaluate(north_pointing, spec, {gyro: eps}, p=p)
    R, g = 6_371_000.0, 9.80665
    w = math.sqrt(g / R)
    rows = rows_of(evaluation, "position_error_absolute")
    assert [t for t, _ in rows] == [600.0 * k for k in range(13)]   # from the start
    for t, value in rows:   # 2σ of the distance itself, not divided by t
        assert value == pytest.approx(2 * R * eps * (t - math.sin(w * t) / w), rel=1e-9)


def test_a_lone_source_is_allowed_the_absolute_limit_at_its_worst_time(north_pointing,
                                                                        tmp_path):
    """Every other source left out: the drift's allowance (2σ) is the limit over the
    Schuler ramp's largest value on the check times (2 h)."""
    others = "".join(f"[sources.{s.name}]\ninclude = false\n" for s in north_pointing.sources
                     if s.name != "gyro_drift_east")
    spec = load_spec(write(tmp_path, textwrap.dedent(SCHULER) + others))
    p = north_pointing.parameter_vector(**spec_parameters(spec, north_pointing))
    allocation = bd.allocate(bd.unit_budget(north_pointing, spec, p=p))
    R, w, t = 6_371_000.0, math.sqrt(9.80665 / 6_371_000.0), 2 * HOUR
    [magnitude] = allocation.magnitudes
    assert magnitude == pytest.approx(2000.0 / (R * (t - math.sin(w * t) / w)), rel=1e-9)
    assert allocation.binding_row(0).label == "position_error_absolute at 2 h"


# ------------------------------------------------------------------------------------
# Absolute heading
# ------------------------------------------------------------------------------------
HEADING = """
    sigma_level = 1
    operating_time = "20 min"
    step = "10 s"
    [motion]
    latitude = "{latitude} deg"
    [items.heading_error]
    value = "1 deg"
    every = "2 min"
    from = "0 min"
    [items.heading_drift]
    value = "1 deg/h"
    times = ["20 min"]
"""


@pytest.mark.parametrize("name, gyro, latitude", [("north_pointing", "gyro_drift_up", 50),
                                                  ("strapdown_ned", "gyro_bias_z", 45)])
def test_heading_error_of_the_azimuth_gyro_drift(name, gyro, latitude, tmp_path):
    model = load_model(name)
    spec = load_spec(write(tmp_path, HEADING.format(latitude=latitude)))
    eps, phi = 1.0 * DEG / HOUR, latitude * DEG
    evaluation = bd.evaluate(model, spec, {gyro: eps})
    rows = rows_of(evaluation, "heading_error")
    assert len(rows) == 11 and rows[0] == (0.0, 0.0)
    for t, value in rows[1:]:
        reference = eps * (math.sin(phi) ** 2 * t + math.cos(phi) ** 2
                           * math.sin(OMEGA * t) / OMEGA)
        assert value == pytest.approx(reference, rel=5e-4)
    # at first the heading error is the drift times the time
    assert rows[1][1] == pytest.approx(eps * 120.0, rel=1e-4)


def test_heading_error_keeps_the_initial_azimuth_error_the_drift_removes(north_pointing,
                                                                         tmp_path):
    spec = load_spec(write(tmp_path, HEADING.format(latitude=50)))
    error = 10 / 60 * DEG
    evaluation = bd.evaluate(north_pointing, spec, {"initial_azimuth_error": error})
    [(t0, start), *_] = rows_of(evaluation, "heading_error")
    assert (t0, start) == (0.0, pytest.approx(error, rel=1e-12))
    # the drift rate over 20 min excludes it: what is left is its slow turning by the
    # Earth rate and the Schuler loop, far below 10 arcmin / 20 min = 30 deg/h
    [(_, drift)] = rows_of(evaluation, "heading_drift")
    assert drift < 1e-2 * error / 1200.0


# ------------------------------------------------------------------------------------
# Height
# ------------------------------------------------------------------------------------
HEIGHT = """
    sigma_level = 1
    operating_time = "20 min"
    step = "10 s"
    [motion]
    latitude = "45 deg"
    [items.height_error]
    value = "100 m"
    every = "2 min"
    from = "0 min"
"""


def test_undamped_height_error_grows_as_cosh(strapdown, tmp_path):
    spec = load_spec(write(tmp_path, HEIGHT))
    w = math.sqrt(wgs84_vertical(45 * DEG))
    evaluation = bd.evaluate(strapdown, spec, {"initial_position_error_D": 10.0})
    rows = rows_of(evaluation, "height_error")
    assert rows[0] == (0.0, pytest.approx(10.0, rel=1e-12))
    for t, value in rows:   # the Coriolis coupling with the level channels: < 1e-3
        assert value == pytest.approx(10.0 * math.cosh(w * t), rel=1e-3)
    assert rows[-1][1] > 41.0    # cosh(1200 s · 1.76e-3/s) = 4.16


def test_damped_height_error_follows_the_second_order_loop(strapdown, tmp_path):
    spec = load_spec(write(tmp_path, HEIGHT))
    k1, k2 = 0.0293, 4.42e-4   # a 300-s loop, damping 0.7
    p = strapdown.parameter_vector(k_h1=k1, k_h2=k2)
    loop = np.array([[0.0, 1.0], [wgs84_vertical(45 * DEG) - k2, -k1]])
    for source, start in (("initial_position_error_D", [10.0, -k1 * 10.0]),
                          ("initial_velocity_error_D", [0.0, -10.0])):
        rows = rows_of(bd.evaluate(strapdown, spec, {source: 10.0}, p=p), "height_error")
        reference = [abs((expm(loop * t) @ np.array(start))[0]) for t, _ in rows]
        # within 2e-4 of the largest (the Coriolis coupling with the level channels)
        assert [v for _, v in rows] == pytest.approx(reference, abs=2e-4 * max(reference))
        assert rows[-1][1] < 1e-3 * max(reference)   # the loop has settled after 20 min


def test_an_error_limit_holds_from_the_start_where_the_error_is_the_initial_error(
        strapdown, tmp_path):
    """At t = 0 the height error is the initial height error itself. A limit on the
    height (a distance, not a rate) checked every 5 min from 5 min let a damped loop
    remove the initial error before the first check: the example spec's 30-m height
    item allowed an initial height error of 610 m. Its grid now starts at 0, where the
    allowance cannot exceed the limit, and the allocated 1σ height error is within it at
    every check time including the start."""
    text = HEIGHT.replace('value = "100 m"', 'value = "30 m"').replace(
        'every = "2 min"\n    from = "0 min"', 'every = "5 min"')
    spec = load_spec(write(tmp_path, text))
    assert spec.item("height_error").times[0] == 0.0
    p = strapdown.parameter_vector(k_h1=0.0293, k_h2=4.42e-4)
    allocation = bd.allocate(bd.unit_budget(strapdown, spec, p=p))
    names = [s.name for s in allocation.budget.sources]
    j = names.index("initial_position_error_D")
    allowed = float(allocation.sigma[j])
    # at t = 0 the height error is the initial height error itself (unit sensitivity):
    # its equal share of the 30-m limit among the N free sources is 30 m/√N, bound there
    free = int(np.isfinite(allocation.sigma).sum())
    assert allowed == pytest.approx(30.0 / math.sqrt(free), rel=1e-9)
    row = allocation.budget.rows[allocation.binding[j]]
    assert (row.item, row.time) == ("height_error", 0.0)
    evaluation = bd.evaluate(strapdown, spec, {"initial_position_error_D": allowed}, p=p)
    assert rows_of(evaluation, "height_error")[0] == (0.0, pytest.approx(allowed, rel=1e-12))


def test_height_needs_a_height_output(orthodromic, tmp_path, capsys):
    path = write(tmp_path, HEIGHT)
    assert main(["budget", "orthodromic", "--spec", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "height_error" in err and "no output height" in err


# ------------------------------------------------------------------------------------
# Values and default times
# ------------------------------------------------------------------------------------
@pytest.mark.parametrize("item, value, words", [
    ("position_error", "3.7 km", r"position_error is a rate.*\[items.position_error_absolute\]"),
    ("position_error_absolute", "3.7 km/h",
     r"position_error_absolute is an absolute limit.*\[items.position_error\]"),
    ("heading_drift", "0.5 deg", r"\[items.heading_error\]"),
    ("heading_error", "0.1 deg/h", r"\[items.heading_drift\]"),
    ("height_error", "1 deg", "do not convert to m"),
    ("height_error", "-3 m", "must be > 0"),
])
def test_a_value_in_the_other_items_dimension_names_it(tmp_path, item, value, words):
    text = f"""
        operating_time = "2 h"
        [items.{item}]
        value = "{value}"
        times = ["1 h"]
    """
    with pytest.raises(InsErrorsError, match=words) as info:
        load_spec(write(tmp_path, text))
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("operating_time, step, times", [
    ("1 h", "60 s", [0.0, 900.0, 1800.0, 2700.0, 3600.0]),
    ("40 min", "60 s", [0.0, 900.0, 1800.0, 2400.0]),
    ("10 min", "7 s", [0.0, 595.0]),     # the last grid time within the operating time
])
def test_absolute_items_are_checked_every_quarter_hour_and_at_the_end(tmp_path,
                                                                      operating_time, step,
                                                                      times):
    """An item that limits the error itself is checked from the start, where the error
    is the initial error (docs/scenarios.md), every 15 min and at the end (the start,
    0 steps of the grid, was once left out as if it were off the grid)."""
    text = f"""
        operating_time = "{operating_time}"
        step = "{step}"
        [items.position_error_absolute]
        value = "1 km"
        [items.height_error]
        value = "50 m"
        [items.heading_error]
        value = "0.5 deg"
    """
    spec = load_spec(write(tmp_path, text))
    for item in spec.items:
        assert list(item.times) == pytest.approx(times)


# ------------------------------------------------------------------------------------
# Fixed and weighted
# ------------------------------------------------------------------------------------
def test_a_fixed_source_with_a_weight_is_refused(tmp_path, capsys):
    text = """
        operating_time = "2 h"
        [items.position_error]
        value = "3.7 km/h"
        [sources.gyro_drift_x]
        fixed = "0.01 deg/h"
        weight = 3
    """
    path = write(tmp_path, text)
    assert main(["budget", "orthodromic", "--spec", str(path)]) == 2
    captured = capsys.readouterr()
    assert not captured.out and captured.err.count("\n") == 1
    assert "sources.gyro_drift_x" in captured.err and "fixed or weight" in captured.err
    # either one alone is a budget
    for drop in ('fixed = "0.01 deg/h"\n', "weight = 3\n"):
        write(tmp_path, text.replace(drop, ""))
        assert main(["budget", "orthodromic", "--spec", str(path)]) == 0
        capsys.readouterr()


# ------------------------------------------------------------------------------------
# The standard manoeuvre
# ------------------------------------------------------------------------------------
MANOEUVRE = """
    sigma_level = 1
    operating_time = "{time}"
    step = "{step}"
    [motion]
    kind = "{kind}"
    latitude = "50 deg"
    heading = "90 deg"
    height = "1000 m"
    {speed}
    [items.ground_speed_error]
    value = "2 m/s"
    every = "10 min"
"""


@pytest.mark.parametrize("name, time, step, scale", [
    ("orthodromic", "2 h", "60 s", "accel_scale_error_x"),
    ("strapdown_ned", "30 min", "10 s", "accel_scale_error_x"),
])
def test_a_scale_factor_is_limited_on_the_manoeuvre_and_not_at_rest(tmp_path, name, time,
                                                                    step, scale):
    model = load_model(name)
    results = {}
    for kind, speed in (("static", ""), ("manoeuvre", 'speed = "200 m/s"')):
        path = write(tmp_path, MANOEUVRE.format(time=time, step=step, kind=kind, speed=speed),
                     f"{kind}.toml")
        spec = load_spec(path)
        allocation = bd.allocate(bd.unit_budget(model, spec))
        j = [s.name for s in allocation.budget.sources].index(scale)
        results[kind] = allocation.magnitudes[j]
        motion = allocation.budget.system.labels.get("trajectory", "")
        assert ("standard manoeuvre" in motion) == (kind == "manoeuvre")
    assert results["static"] == np.inf
    # the turns and the speed-up give the accelerometer a specific force of up to
    # V·ψ̇ ≈ 200 m/s · 90°/600 s ≈ 0.5 m/s² to misread: a small-error allowance
    assert 1e-5 < results["manoeuvre"] < 0.1


def test_manoeuvre_legs_of_the_spec_are_flown(orthodromic, tmp_path):
    text = MANOEUVRE.format(time="30 min", step="60 s", kind="manoeuvre",
                            speed='speed = "200 m/s"') + textwrap.dedent("""
        [[motion.legs]]
        duration = "10 min"
        turn = "90 deg"
        [[motion.legs]]
        duration = "5 min"
        speed = "240 m/s"
    """)
    spec = load_spec(write(tmp_path, text))
    assert [leg["duration"] for leg in spec.motion.legs] == ["600.0 s", "300.0 s"]
    trajectory = bd.spec_trajectory(orthodromic, spec)
    assert "manoeuvring flight of 2 legs" in trajectory.description
    # the second leg speeds up from 200 to 240 m/s and then the flight goes on at 240
    outputs = orthodromic.numpy.outputs(trajectory.truth, trajectory.inputs,
                                        trajectory.parameters)
    names = [o.name for o in orthodromic.outputs]
    speed = np.hypot(outputs[names.index("v_N")], outputs[names.index("v_E")])
    assert speed[0] == pytest.approx(200.0, rel=1e-6)
    assert speed[-1] == pytest.approx(240.0, rel=1e-4)


@pytest.mark.parametrize("change, words", [
    ('kind = "manoeuvre"\n    latitude', r"motion.speed must be > 0 for a manoeuvre"),
    ('kind = "static"\n    legs = [{duration = "1 min"}]\n    latitude',
     r"motion.legs apply to kind = 'manoeuvre'"),
    ('kind = "manoeuvre"\n    speed = "9 m/s"\n    legs = [{duration = "1 kg"}]\n    latitude',
     r"motion.legs: leg duration: '1 kg'.* s"),
    ('kind = "manoeuvre"\n    speed = "9 m/s"\n    legs = [{duration = "-1 min"}]\n    latitude',
     r"leg 1's duration must be > 0, got '-1 min'"),
    ('kind = "manoeuvre"\n    speed = "9 m/s"\n    legs = [{turns = "9 deg"}]\n    latitude',
     r"'turns'; did you mean 'turn'"),
    ('kind = "manouevre"\n    latitude', r"manoeuvre"),
])
def test_bad_manoeuvres_are_one_line(tmp_path, capsys, change, words):
    text = """
        operating_time = "1 h"
        [motion]
        latitude = "50 deg"
        [items.ground_speed_error]
        value = "2 m/s"
    """.replace("latitude = \"50 deg\"", change + ' = "50 deg"')
    path = write(tmp_path, text)
    assert main(["budget", "orthodromic", "--spec", str(path)]) == 2
    captured = capsys.readouterr()
    assert not captured.out and captured.err.count("\n") == 1
    assert re.search(words, captured.err), captured.err


# ------------------------------------------------------------------------------------
# Vertical-channel sources without a height item
# ------------------------------------------------------------------------------------
UAV = """
    sigma_level = 1
    operating_time = "10 min"
    step = "1 s"
    [motion]
    kind = "great_circle"
    latitude = "45 deg"
    heading = "90 deg"
    height = "1000 m"
    speed = "40 m/s"
    [items.position_error]
    value = "15 km/h"
    times = ["5 min", "10 min"]
    [items.ground_speed_error]
    value = "5 m/s"
    every = "1 min"
"""
VERTICAL = ["accel_bias_z", "accel_scale_error_z", "initial_velocity_error_D",
            "initial_position_error_D"]


def test_vertical_sources_bound_only_horizontally_are_named(strapdown, tmp_path, capsys):
    path = write(tmp_path, UAV)
    assert main(["budget", "strapdown_ned", "--spec", str(path), "--fill", "--json"]) == 0
    captured = capsys.readouterr()
    [note] = [w for w in json.loads(captured.out)["warnings"] if "height_error" in w]
    assert f"ins-errors: warning: {note}\n" in captured.err
    assert note.startswith("the spec has no height_error item: " + ", ".join(VERTICAL[:-1])
                           + f" and {VERTICAL[-1]} act mainly on the height")
    # the height error their allowances give together, read by a height item
    data = json.loads(captured.out)
    sigma = {s["name"]: s["magnitude"] for s in data["sources"] if s["name"] in VERTICAL}
    spec = load_spec(write(tmp_path, UAV + '[items.height_error]\nvalue = "1 m"\n'
                           'every = "1 s"\n', "height.toml"))
    height = max(v for _, v in rows_of(bd.evaluate(strapdown, spec, sigma), "height_error"))
    assert height > 10e3    # kilometres: the spec says nothing about the height
    shown = float(re.search(r"height error of ([\d.]+) km", note).group(1))
    assert shown * 1e3 == pytest.approx(height, rel=1e-3)


def test_a_vertical_accelerometer_alone_is_named_with_its_cosh_height(strapdown, tmp_path):
    """Only accel_bias_z and a level gyro allocated: the line names the accelerometer
    alone, with its undamped height (b/ω_v²)(cosh ω_v t − 1) at its allowance."""
    keep = {"accel_bias_z", "gyro_bias_x"}
    others = "".join(f"[sources.{s.name}]\ninclude = false\n" for s in strapdown.sources
                     if s.name not in keep)
    spec = load_spec(write(tmp_path, textwrap.dedent(UAV) + others))
    allocation = bd.allocate(bd.unit_budget(strapdown, spec))
    note = bd.vertical_channel_note(strapdown, allocation)
    assert "no height_error item: accel_bias_z acts mainly on the height" in note
    assert "gyro_bias_x" not in note
    b = allocation.magnitudes[[s.name for s in allocation.budget.sources].index("accel_bias_z")]
    w2 = wgs84_vertical(45 * DEG)
    reference = b / w2 * (math.cosh(math.sqrt(w2) * 600.0) - 1)
    shown = float(re.search(r"height error of ([\d.]+) (k?m)", note).group(1))
    unit = 1e3 if " km at" in note else 1.0
    assert shown * unit == pytest.approx(reference, rel=2e-3)
    assert note.endswith("at 10 min); add [items.height_error] to bound it")


def test_no_line_with_a_height_item_or_without_a_vertical_channel(strapdown, orthodromic,
                                                                  tmp_path):
    spec = load_spec(write(tmp_path, UAV + '[items.height_error]\nvalue = "100 m"\n'))
    assert bd.vertical_channel_note(strapdown, bd.allocate(bd.unit_budget(strapdown, spec))
                                    ) is None
    spec = load_spec(write(tmp_path, UAV.replace("1 s", "60 s"), "platform.toml"))
    assert bd.vertical_channel_note(orthodromic, bd.allocate(
        bd.unit_budget(orthodromic, spec))) is None


def test_an_exponentially_growing_channel_is_left_to_the_growth_warning(strapdown,
                                                                          tmp_path,
                                                                          monkeypatch):
    """Undamped over 8 h (50 e-foldings of √(R/2g) = 9.5 min) the growing mode swamps
    every source's height error, so nearly every source would be named: the growth
    warning alone speaks, naming the damping gains."""
    spec = load_spec(write(tmp_path, """
        operating_time = "8 h"
        [motion]
        latitude = "50 deg"
        [items.position_error]
        value = "3.7 km/h"
        [items.ground_speed_error]
        value = "4 m/s"
    """))
    budget = bd.unit_budget(strapdown, spec)
    allocation = bd.allocate(budget)
    assert "grow exponentially" in bd.growth_warning(strapdown, budget)
    assert bd.vertical_channel_note(strapdown, allocation) is None
    monkeypatch.setattr(bd, "growth_warning", lambda *args: None)
    named = bd.vertical_channel_note(strapdown, allocation).split(": ", 1)[1]
    assert named.count(", ") >= 15 and "gyro_bias_x" in named


def test_direct_runs_read_the_absolute_items_as_the_covariance(tmp_path, capsys):
    """200 direct (nonlinear) runs at the allocated magnitudes give each absolute item's
    1σ within three sampling errors (5 % each) of the covariance's."""
    text = UAV.split("[items.position_error]")[0] + textwrap.dedent("""
        [items.position_error_absolute]
        value = "2.5 km"
        [items.height_error]
        value = "100 m"
        [items.heading_error]
        value = "1 deg"
    """)
    path = write(tmp_path, text)
    assert main(["budget", "strapdown_ned", "--spec", str(path), "--monte-carlo", "200",
                 "--mc-step", "0.1 s", "--engine", "serial", "--json"]) == 0
    mc = json.loads(capsys.readouterr().out)["monte_carlo"]
    rows = {r["item"]: r["ratio"] for r in mc["rows"]}
    assert set(rows) == {"position_error_absolute", "height_error", "heading_error"}
    for item, ratio in rows.items():
        assert abs(ratio - 1) < 3 * mc["relative_sampling_error"], item


def test_sea_units_read_as_nautical_miles_and_knots(tmp_path):
    """docs/scenarios.md names `nmi` and `kn`/`knot` for a marine INS's spec: 1 nmi =
    1852 m and 1 kn = 1852 m/h exactly (international definitions)."""
    spec = load_spec(write(tmp_path, """
        sigma_level = 1
        operating_time = "2 h"
        step = "60 s"
        [motion]
        latitude = "50 deg"
        [items.position_error_absolute]
        value = "1 nmi"
        [items.position_error]
        value = "2 nmi/h"
        [items.ground_speed_error]
        value = "0.5 knot"
    """))
    assert spec.item("position_error_absolute").value == 1852.0
    assert spec.item("position_error").value == pytest.approx(2 * 1852.0 / 3600, rel=1e-15)
    assert spec.item("ground_speed_error").value == pytest.approx(0.5 * 1852.0 / 3600,
                                                                  rel=1e-15)


def test_a_mode_of_f_at_the_start_of_a_moving_base_is_checked_along_it(orthodromic,
                                                                       strapdown, tmp_path):
    """A 30-h budget of orthodromic on an eastbound great circle warned that its errors
    grow exponentially (×e every 9.2 h: a real eigenvalue of F at the start, along
    delta_V_eta) although the equations never follow it along the motion (the compare
    probe's week stayed bounded). The transition matrix over the operating time has no
    eigenvalue growing at half that rate, so no warning; strapdown_ned's undamped
    vertical channel on a great circle still warns, its transition growth being the
    textbook √(2g/R)."""
    from ins_errors.numeric.linear_system import growth_rate, transition_growth

    great_circle = """
        operating_time = "30 h"
        step = "60 s"
        [motion]
        kind = "great_circle"
        latitude = "50 deg"
        longitude = "30 deg"
        heading = "90 deg"
        height = "5000 m"
        speed = "250 m/s"
        [items.position_error]
        value = "3.7 km/h"
    """
    budget = bd.unit_budget(orthodromic, load_spec(write(tmp_path, great_circle)))
    F0 = budget.system.F[0]
    assert growth_rate(F0) * 30 * 3600 > 3            # the frozen mode alone would warn
    assert transition_growth(budget.system) < 0.1 * growth_rate(F0)
    assert bd.growth_warning(orthodromic, budget) is None
    short = great_circle.replace('"30 h"', '"2 h"').replace('"60 s"', '"10 s"')
    budget = bd.unit_budget(strapdown, load_spec(write(tmp_path, short, "s.toml")))
    assert transition_growth(budget.system) == pytest.approx(
        math.sqrt(wgs84_vertical(math.radians(50.0))), rel=0.02)
    assert "grow exponentially" in bd.growth_warning(strapdown, budget)
