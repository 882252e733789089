"""What a budget tells an engineer: JSON numbers that say their σ level and shape, tables
and charts that state their operating time, magnitudes and units, a spec the fixed
sources exceed still broken down by source, and hints that fit a budget spec."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from ins_errors.analysis import budget as bd
from ins_errors.analysis import budget_report as rep
from ins_errors.cli import main
from ins_errors.specs import HOUR, load_spec

ROOT = Path(__file__).resolve().parent.parent
DEG = np.pi / 180

FLIGHT = """
    title = "two hours on a great circle"
    sigma_level = 2
    operating_time = "2 h"
    step = "60 s"
    [motion]
    kind = "great_circle"
    latitude = "50 deg"
    longitude = "30 deg"
    heading = "45 deg"
    height = "10 km"
    speed = "250 m/s"
    [items.position_error]
    value = "1.85 km/h"
    times = ["1 h", "2 h"]
    [items.ground_speed_error]
    value = "0.8 m/s"
    every = "30 min"
    [items.vertical_error]
    value = "30 arcsec"
    every = "30 min"
    [items.heading_drift]
    value = "0.02 deg/h"
    times = ["2 h"]
    [sources.gyro_drift_z]
    fixed = "0.008 deg/h"
"""

EXCEEDED = """
    title = "bought parts too poor"
    sigma_level = 2
    operating_time = "2 h"
    step = "60 s"
    [motion]
    kind = "static"
    latitude = "50 deg"
    [items.position_error]
    value = "3.7 km/h"
    times = ["1 h"]
    [sources.gyro_drift_x]
    fixed = "0.5 deg/h"
    [sources.accel_bias_x]
    fixed = "2 mg"
"""


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


@pytest.fixture(scope="module")
def flight(orthodromic, tmp_path_factory):
    """The flight's spec file, its allocation and a fresh evaluation of every row at the
    allocated magnitudes (the independent propagation the shares are checked against)."""
    path = write(tmp_path_factory.mktemp("flight"), FLIGHT)
    spec = load_spec(path)
    allocation = bd.allocate(bd.unit_budget(orthodromic, spec))
    budget = allocation.budget
    names = [s.name for s in budget.sources]
    limited = np.flatnonzero(np.isfinite(allocation.sigma))
    evaluation = bd.evaluate(orthodromic, spec,
                             {names[j]: float(allocation.sigma[j]) for j in limited})
    return path, allocation, evaluation


def _json(capsys, argv: list[str], status: int = 0) -> dict:
    assert main([*argv, "--json"]) == status
    return json.loads(capsys.readouterr().out)


# ------------------------------------------------------------------------------------
# 1. JSON numbers that say what they are
# ------------------------------------------------------------------------------------
def test_json_shares_at_the_worst_time_are_the_tables(flight, capsys):
    """'largest_share' was over every check time while the table gives the share at the
    item's worst time (fixed gyro_drift_z on the position: 9.5 % against 0.33 % on the
    8-h flight), and the table's figure was not in the JSON. Now 'share_at_worst_time'
    is it: the fresh evaluation's share at the row with the largest total ratio."""
    path, allocation, evaluation = flight
    data = _json(capsys, ["budget", "orthodromic", "--spec", str(path)])
    rows = evaluation.rows
    shares = evaluation.contributions / np.array([(r.limit / 2) ** 2 for r in rows])[:, None]
    used = shares.sum(1)
    source = next(s for s in data["sources"] if s["name"] == "gyro_drift_z")
    j = list(evaluation.sources).index("gyro_drift_z")
    differs = False
    for item in data["items"]:
        idx = [i for i, r in enumerate(rows) if r.item == item["name"]]
        worst = idx[int(np.argmax(used[idx]))]
        assert item["worst_time_h"] == pytest.approx(rows[worst].time / HOUR)
        assert item["share_used"] == pytest.approx(used[worst], rel=1e-9)
        assert item["ratio"] == pytest.approx(evaluation.ratios[worst], rel=1e-9)
        assert source["share_at_worst_time"][item["name"]] == pytest.approx(
            shares[worst, j], rel=1e-9, abs=1e-15)
        assert source["largest_share"][item["name"]] == pytest.approx(
            shares[idx, j].max(), rel=1e-9, abs=1e-15)
        differs |= shares[idx, j].max() > 2 * shares[worst, j]
    assert differs   # the two keys answer different questions on this flight
    # the table prints the same figure
    table = rep.contribution_table(allocation).splitlines()
    line = next(x for x in table if x.startswith("gyro_drift_z "))
    printed = [float(v) for v in line.split()[1:]]
    assert printed == pytest.approx([100 * source["share_at_worst_time"][i["name"]]
                                     for i in data["items"]], abs=0.006)


def test_json_numbers_name_their_sigma_level_units_and_axes(flight, capsys):
    """Every number carries its σ level (a source's magnitude at the spec's kσ and at
    1σ, the rows at kσ, the --at breakdown at 1σ), the --at arrays their axes, and the
    run its operating time, step, fill factor and motion as values."""
    path, _, _ = flight
    data = _json(capsys, ["budget", "orthodromic", "--spec", str(path), "--at", "1 h, 2 h"])
    assert data["sigma_level"] == 2
    assert data["operating_time_h"] == 2 and data["step_s"] == 60
    assert data["fill"] is False and data["fill_factor"] == 1
    assert data["motion_values"] == pytest.approx(
        {"kind": "great_circle", "latitude_rad": 50 * DEG, "longitude_rad": 30 * DEG,
         "heading_rad": 45 * DEG, "height_m": 10_000.0, "speed_m_s": 250.0})
    for s in data["sources"]:
        assert s["magnitude_sigma_level"] == 2
        if s["magnitude"] is not None:
            assert s["magnitude"] == pytest.approx(2 * s["magnitude_1sigma"], rel=1e-15)
    fixed = next(s for s in data["sources"] if s["name"] == "gyro_drift_z")
    assert fixed["magnitude_1sigma"] == pytest.approx(0.004 * DEG / HOUR, rel=1e-12)
    for r in data["rows"]:
        assert r["sigma_level"] == 2
        assert r["unit"] == {"position_error": "m/s", "ground_speed_error": "m/s",
                             "vertical_error": "rad", "heading_drift": "rad/s"}[r["item"]]
    vertical = next(i for i in data["items"] if i["name"] == "vertical_error")
    assert vertical["limit_text"] == "30 arcsec"
    assert vertical["limit"] == pytest.approx(30 / 3600 * DEG, rel=1e-12)
    c = data["contributions"]
    assert c["sigma_level"] == 1 and c["magnitudes"] == "the allocated magnitudes"
    assert c["axes"] == {"std": ["times_h", "quantities", "sources"],
                         "total": ["times_h", "quantities"]}
    shape = [len(c[axis]) for axis in c["axes"]["std"]]
    assert list(np.shape(c["std"])) == shape == [2, len(c["units"]), len(c["sources"])]
    assert list(np.shape(c["total"])) == shape[:2]
    # fill: every free magnitude grows by √(fill_factor), the fixed one stays, and the
    # tightest row is then met exactly
    filled = _json(capsys, ["budget", "orthodromic", "--spec", str(path), "--fill"])
    assert filled["fill"] is True and filled["fill_factor"] > 1
    for plain, grown in zip(data["sources"], filled["sources"], strict=True):
        if plain["magnitude"] is not None:
            factor = 1 if plain["fixed"] else np.sqrt(filled["fill_factor"])
            assert grown["magnitude"] == pytest.approx(factor * plain["magnitude"],
                                                       rel=1e-9)
    assert max(r["ratio"] for r in filled["rows"]) == pytest.approx(1, rel=1e-9)


def test_docs_describe_the_budget_json():
    """docs/json.md (the page of every command's JSON keys) names the keys an engineer
    reads numbers from, with their σ."""
    text = " ".join((ROOT / "docs" / "json.md").read_text().split())
    for key in ("magnitude_1sigma", "magnitude_sigma_level", "share_at_worst_time",
                "largest_share", "operating_time_h", "step_s", "fill_factor",
                "motion_values", "`axes`", "limit_text", "share_used"):
        assert key in text, key


# ------------------------------------------------------------------------------------
# 2. A grid too large at rest is refused before any work
# ------------------------------------------------------------------------------------
def test_a_static_grid_too_large_is_refused_up_front(tmp_path, capsys, monkeypatch):
    """A month at 0.01 s at rest ran 33 s to 8 GB and died in numpy (exit 1, a
    traceback); a moving base was refused by a memory check. The same check now refuses
    the static base, in one line, before its motion is built."""
    from ins_errors.analysis import covariance
    from ins_errors.numeric import linear_system, trajectories

    spec = write(tmp_path, """
        sigma_level = 2
        operating_time = "30 d"
        step = "0.01 s"
        [motion]
        kind = "static"
        latitude = "50 deg"
        [items.position_error]
        value = "3.7 km/h"
        every = "1 h"
    """)
    monkeypatch.setattr(linear_system, "physical_memory", lambda: 16e9)
    for module, name in ((trajectories, "trajectory"), (bd, "static_system"),
                         (covariance, "static_system")):
        monkeypatch.setattr(module, name, lambda *a, **k: pytest.fail("built"))
    assert main(["budget", "orthodromic", "--spec", str(spec)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"at {30 * 86400 * 100 + 1:,} grid times need about" in err
    assert "choose a step of at least" in err


def test_the_memory_check_estimates_the_peak_a_static_budget_reaches(tmp_path, monkeypatch):
    """The refusal's estimate is of the peak, not of the arrays kept (those were half of
    it, so a grid just inside the limit could still exhaust the memory): the peak of the
    arrays a budget on 6 h at 1 s allocates (numpy's allocations, traced), after a first
    run has made everything kept between runs."""
    import tracemalloc

    from ins_errors.numeric import linear_system
    from ins_errors.numeric.model import load_model

    model = load_model("orthodromic")
    spec = load_spec(write(tmp_path, """
        sigma_level = 1
        operating_time = "6 h"
        step = "1 s"
        [motion]
        kind = "static"
        latitude = "50 deg"
        [items.ground_speed_error]
        value = "4 m/s"
        every = "1 h"
    """))
    bd.unit_budget(model, spec)
    tracemalloc.start()
    try:
        bd.unit_budget(model, spec)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    monkeypatch.setattr(linear_system, "physical_memory", lambda: 1.0)  # always refused
    with pytest.raises(linear_system.LinearSystemError) as refused:
        linear_system.check_grid_memory(model, 6 * 3600 + 1, 1.0)
    number, unit = str(refused.value).split("need about ")[1].split()[:2]
    estimate = float(number) * {"kB": 1e3, "MB": 1e6, "GB": 1e9}[unit.rstrip(",")]  # bytes
    assert 0.6 * estimate < peak < 1.3 * estimate


# ------------------------------------------------------------------------------------
# 3. A spec the fixed sources exceed: what still makes sense is made
# ------------------------------------------------------------------------------------
def test_exceeded_spec_breaks_down_the_fixed_sources(tmp_path, capsys):
    """--at, --plot-at and --plot were skipped silently when the fixed sources alone
    exceed the spec. Now the --at breakdown of the fixed sources is printed (its
    position errors give the table's exceeded position value: 2σ rss of north and east
    over the hour), both charts are written and named, and --monte-carlo, which checks
    an allocation there is none of, is skipped with one line saying why."""
    spec = write(tmp_path, EXCEEDED)
    plot, plot_at = tmp_path / "b.png", tmp_path / "at.png"
    argv = ["budget", "orthodromic", "--spec", str(spec), "--at", "1 h", "--plot",
            str(plot), "--plot-at", str(plot_at), "--monte-carlo", "5"]
    assert main(argv) == 1
    captured = capsys.readouterr()
    out = captured.out
    assert "SPEC EXCEEDED" in out
    assert "Contributions to the navigation errors at 1 h (1σ, at the fixed sources alone" \
        in out
    assert f"plot written to {plot}" in out and f"plot written to {plot_at}" in out
    assert plot.stat().st_size > 0 and plot_at.stat().st_size > 0
    [line] = captured.err.strip().splitlines()
    assert "--monte-carlo skipped" in line and "fixed sources alone exceed" in line
    data = _json(capsys, argv, status=1)
    c = data["contributions"]
    assert c["sources"] == ["gyro_drift_x", "accel_bias_x"]
    north, east = (c["total"][0][c["quantities"].index(q)] for q in ("delta_r_N", "delta_r_E"))
    [row] = data["rows"]
    assert 2 * np.hypot(north, east) / HOUR == pytest.approx(row["value"], rel=1e-9)
    assert row["ratio"] > 1 and any("--monte-carlo skipped" in w for w in data["warnings"])


# ------------------------------------------------------------------------------------
# 4. Hints that fit a budget spec
# ------------------------------------------------------------------------------------
def test_a_model_with_none_of_the_items_is_not_told_to_remove_them(capsys):
    """The Schuler loop was told to copy the spec without every one of its item tables,
    which leaves a spec that is refused; now it is told that none of the items fits."""
    from ins_errors.numeric.model import load_model

    loop = str(ROOT / "examples" / "own_model" / "schuler_loop.py")
    load_model(loop)  # derived first (a fresh cache says so on stderr)
    capsys.readouterr()
    assert main(["budget", loop]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "without its" not in line and "leave them out" not in line
    assert "all the items of the built-in 802m spec" in line
    assert "a spec needs at least one item its model can check" in line
    assert "cannot be budgeted" in line


def test_a_model_that_cannot_fly_the_spec_motion_is_told_the_spec_way_out(tmp_path,
                                                                          capsys):
    """A budget spec has no motion file: the hint names the static base in the spec."""
    spec = write(tmp_path, FLIGHT.replace("gyro_drift_z", "gyro_drift_up"), "np.toml")
    assert main(["budget", "north_pointing", "--spec", str(spec)]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "motion file of" not in line and "has no motion file" in line
    assert f'set kind = "static" in {spec}\'s [motion]' in line   # the path as typed
    assert line.endswith("leave out its heading and speed")
    # the way out works
    fixed = write(tmp_path, FLIGHT.replace("gyro_drift_z", "gyro_drift_up")
                  .replace('"great_circle"', '"static"').replace('heading = "45 deg"', "")
                  .replace('speed = "250 m/s"', ""), "np_static.toml")
    assert main(["budget", "north_pointing", "--spec", str(fixed)]) == 0
    capsys.readouterr()


# ------------------------------------------------------------------------------------
# 5. Charts
# ------------------------------------------------------------------------------------
def _capture(monkeypatch) -> dict:
    captured: dict = {}
    monkeypatch.setattr(rep, "save_figure",
                        lambda fig, path, dpi: captured.setdefault("figs", []).append(fig))
    return captured


def test_allocation_chart_draws_the_fixed_sources(flight, monkeypatch):
    """The fixed source (the instrument bought) was left out of the chart; it is drawn
    first, labelled fixed, hatched, with its largest share of every item as the bars."""
    _, allocation, evaluation = flight
    captured = _capture(monkeypatch)
    rep.plot(allocation, "b.png")
    left = captured["figs"][0].axes[0]
    labels = [t.get_text() for t in left.get_yticklabels()]
    assert labels[0] == "gyro_drift_z  = 0.008 deg/h (fixed)"   # the top row
    budget = allocation.budget
    j = list(evaluation.sources).index("gyro_drift_z")
    shares = evaluation.contributions[:, j] / budget.allowed_variances
    for i, item in enumerate(budget.spec.items):
        rows = [r for r, row in enumerate(budget.rows) if row.item == item.name]
        bar = left.containers[i][0]   # the first bar drawn: the top row
        assert bar.get_width() == pytest.approx(100 * shares[rows].max(), rel=1e-9)
        assert bar.get_hatch() == rep.FIXED_HATCH
        assert all(not b.get_hatch() for b in list(left.containers[i])[1:])


def test_contribution_chart_others_and_title(flight, monkeypatch, tmp_path, capsys):
    """The grey "others" block (0.75) was nearly the colour of a source (tab20's light
    grey, 0.78): it is now unlike every source's colour; the chart has a title naming
    the spec, the motion and the σ; its file is named on the terminal as --plot's is."""
    from matplotlib.colors import to_rgba

    rng = np.random.default_rng(3)
    std = rng.uniform(0.1, 1, (1, 4, 30))
    data = {"std": std, "total": np.sqrt((std**2).sum(-1)), "times_h": [1.0],
            "sources": [f"s{j}" for j in range(30)], "quantities": ["a", "b", "c", "d"],
            "units": ["m"] * 4}
    captured = _capture(monkeypatch)
    rep.plot_outputs(data, "x.png")
    ax = captured["figs"][0].axes[0]
    others = next(c for c in ax.containers if c.get_label() == "others")
    shade = np.array(to_rgba(others[0].get_facecolor()))
    for c in ax.containers:
        if c is not others:
            assert np.abs(np.array(to_rgba(c[0].get_facecolor())) - shade).max() > 0.15
    assert others[0].get_hatch()
    path, _, _ = flight
    argv = ["budget", "orthodromic", "--spec", str(path), "--at", "1 h", "--plot-at",
            str(tmp_path / "at.png")]
    assert main(argv) == 0
    assert f"plot written to {tmp_path / 'at.png'}" in capsys.readouterr().out
    title = captured["figs"][-1]._suptitle.get_text()
    assert "two hours on a great circle" in title and "great circle from φ=50°" in title
    assert "1σ (the spec's items are 2σ)" in title and "allocated magnitudes" in title


# ------------------------------------------------------------------------------------
# 6. Tables
# ------------------------------------------------------------------------------------
def test_tables_state_time_step_magnitudes_and_the_written_units(flight, capsys):
    """The header states the operating time and the step; the --at tables say they use
    the allocated (filled) magnitudes; a limit written "30 arcsec" reads "30 arcsec" (was
    "0.5 arcmin"), its value converted into it; positions in --at are metres north and
    east."""
    path, _, _ = flight
    assert main(["budget", "orthodromic", "--spec", str(path), "--at", "1 h", "--fill"]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert lines[1] == "Operating time 2 h, analysis step 60 s."
    line = next(x for x in lines if x.startswith("vertical_error "))
    value, unit, of, limit, limit_unit = line.split()[-6:-1]
    assert (unit, of, limit, limit_unit) == ("arcsec", "of", "30", "arcsec")
    assert 0 < float(value) <= 30 * (1 + 1e-6)   # filled: the tightest item is met exactly
    assert "Contributions to the navigation errors at 1 h (1σ, at the allocated " \
           "magnitudes, filled (×" in out
    header = next(x for x in lines if x.startswith("source (1σ)"))
    assert "Δr_N m" in header and "Δr_E m" in header and "Δlatitude" not in header


def test_each_component_table_names_the_worst_component(tmp_path, capsys):
    """With combine = "each" the spec-rows line names the component that is worst."""
    spec = write(tmp_path, FLIGHT.replace('value = "1.85 km/h"',
                                          'value = "1.85 km/h"\n    combine = "each"'))
    data = _json(capsys, ["budget", "orthodromic", "--spec", str(spec)])
    rows = [r for r in data["rows"] if r["item"] == "position_error"]
    worst = max(rows, key=lambda r: r["ratio"])
    assert worst["component"] in ("north", "east")
    assert main(["budget", "orthodromic", "--spec", str(spec)]) == 0
    out = capsys.readouterr().out
    assert any(x.startswith(f"position_error [{worst['component']}] ")
               for x in out.splitlines())


def test_at_beyond_the_operating_time_names_it_before_any_work(flight, capsys,
                                                                monkeypatch):
    """'--at 9 h' on an 8-h spec said "not on the 60 s analysis grid within the
    operating time" without naming it, after the whole propagation."""
    path, _, _ = flight
    monkeypatch.setattr(bd, "unit_budget", lambda *a, **k: pytest.fail("propagated"))
    assert main(["budget", "orthodromic", "--spec", str(path), "--at", "3 h"]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "--at: time 3 h is outside the spec's operating time, 0 to 2 h" in line
    assert main(["budget", "orthodromic", "--spec", str(path), "--at", "90 s"]) == 2
    [line] = capsys.readouterr().err.strip().splitlines()
    assert "90 s is not on the spec's 60 s analysis grid" in line and "0 to 2 h" in line


def test_monte_carlo_table_reads_the_vertical_in_the_specs_unit(tmp_path, capsys):
    """The Monte Carlo table showed the vertical error in deg while the spec rows above
    it (and the spec) use arcsec: now the same unit, the numbers the JSON's converted."""
    spec = write(tmp_path, FLIGHT.replace('kind = "great_circle"', 'kind = "static"')
                 .replace('heading = "45 deg"', "").replace('speed = "250 m/s"', ""))
    argv = ["budget", "orthodromic", "--spec", str(spec), "--monte-carlo", "2",
            "--mc-duration", "30 min", "--mc-step", "1 s", "--engine", "serial"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    rows = [x.split() for x in out.splitlines() if x.startswith("vertical_error at ")]
    assert rows and all(r[5] == "arcsec" and r[7] == "arcsec" for r in rows)
    data = _json(capsys, argv)
    mc = data["monte_carlo"]
    assert mc["sigma_level"] == 2
    first = next(r for r in mc["rows"] if r["item"] == "vertical_error")
    assert first["unit"] == "rad" and first["sigma_level"] == 2
    assert float(rows[0][4]) == pytest.approx(first["covariance"] / DEG * 3600, rel=1e-3)


def test_an_exceeded_budget_with_shares_decades_apart_is_drawn_on_a_log_axis(
        tmp_path, capsys, monkeypatch):
    """A sizing probe's MEMS IMU used 1e7 % of a spec beside sources using 1e-3 %: on the
    linear share axis every bar but the largest was invisible. Where the shares span more
    than LOG_SHARES the axis is logarithmic and each source's bar length is its share."""
    from ins_errors.analysis import budget_report

    figures = []
    monkeypatch.setattr(budget_report, "save_figure",
                        lambda fig, path, dpi=None: figures.append(fig))
    spec = write(tmp_path, EXCEEDED.replace('fixed = "2 mg"', 'fixed = "0.02 ug"'))
    assert main(["budget", "orthodromic", "--spec", str(spec), "--plot",
                 str(tmp_path / "b.png")]) == 1
    capsys.readouterr()
    left = figures[-1].axes[0]
    assert left.get_xscale() == "log"
    widths = sorted(p.get_width() for p in left.patches if p.get_width() > 0)
    assert widths[-1] / widths[0] > budget_report.LOG_SHARES
    low, high = left.get_xlim()
    assert low <= widths[0] and widths[-1] < high
    right = figures[-1].axes[1]  # the one item's value / limit: far beyond 1
    ratios = [p.get_width() for p in right.patches]
    assert right.get_xscale() == ("log" if max(ratios) > budget_report.LOG_RATIOS
                                  else "linear")
    # within a few decades the axis stays linear
    figures.clear()
    assert main(["budget", "orthodromic", "--spec", str(write(tmp_path, EXCEEDED)),
                 "--plot", str(tmp_path / "c.png")]) == 1
    assert figures[-1].axes[0].get_xscale() == "linear"
