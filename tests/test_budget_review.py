"""The budget's design-review outputs: the Markdown report (``--report``) and the items
over the operating time (``--plot-time``).

The report is read back as Markdown tables and held against the ``--json`` of the same
run; the curves are held against the budget's rows at the check times and, on the
built-in spec's static base moved to the equator (where the east channel of a platform
INS at rest is a pure Schuler loop), against the textbook responses of an accelerometer
bias and a gyro drift.
"""

from __future__ import annotations

import json
import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

from ins_errors.analysis import budget as bd
from ins_errors.analysis import budget_report as rep
from ins_errors.analysis import budget_time as bt
from ins_errors.cli import main
from ins_errors.specs import default_spec_path, load_spec
from ins_errors.units import parse_quantity
from tests.test_budget_cli import NO_TILT as NO_TILT_SPEC

ROOT = Path(__file__).resolve().parent.parent


def write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text))
    return path


def tables(text: str) -> dict[str, list[dict[str, str]]]:
    """The Markdown tables of ``text``, by the heading above each (the first table
    under a heading), as rows of cells keyed by the header."""
    found: dict[str, list[dict[str, str]]] = {}
    heading, lines = "", text.splitlines()
    k = 0
    while k < len(lines):
        line = lines[k]
        if line.startswith("#"):
            heading = line.lstrip("#").strip()
        if line.startswith("| ") and heading not in found:
            block = []
            while k < len(lines) and lines[k].startswith("|"):
                block.append([c.strip() for c in lines[k].strip().strip("|").split(" | ")])
                k += 1
            assert set("".join(block[1])) <= set("-: "), block[1]   # the rule
            found[heading] = [dict(zip(block[0], row, strict=True)) for row in block[2:]]
            continue
        k += 1
    return found


def quantity(text: str, unit: str) -> float:
    """A table's "0.02578 deg" in SI (``unit``)."""
    return parse_quantity(text, unit, "table cell")


def duration(text: str) -> float:
    """A table's time ("1 h 5 min", "40 min", "90 s"), s."""
    parts = re.findall(r"([\d.]+) (h|min|s)\b", text)
    assert parts and " ".join(f"{n} {u}" for n, u in parts) == text, text
    return sum(float(n) * {"h": 3600.0, "min": 60.0, "s": 1.0}[u] for n, u in parts)


def value_of_limit(cell: str, unit: str) -> tuple[float, float]:
    value, limit = cell.split(" of ")
    return quantity(value, unit), quantity(limit, unit)


def run(argv: list[str], capsys, status: int = 0) -> tuple[dict, str]:
    assert main(argv) == status
    captured = capsys.readouterr()
    return json.loads(captured.out), captured.err


# ------------------------------------------------------------------------------------
# 1. --report: the numbers are the JSON's
# ------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def built_in(tmp_path_factory):
    """The built-in spec's report and the --json of the same run."""
    import contextlib
    import io

    folder = tmp_path_factory.mktemp("review")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["budget", "orthodromic", "--json", "--report",
                     str(folder / "budget.md")]) == 0
    return json.loads(out.getvalue()), (folder / "budget.md").read_text(encoding="utf-8")


def test_report_allocation_is_the_jsons(built_in):
    """Every source's row: its magnitude (to the 4 digits shown), fixed or free, binding
    item and time, largest share; the not-limited ones say why, as the terminal does."""
    data, text = built_in
    rows = tables(text)["Allocation"]
    assert [r["source"] for r in rows] == [s["label"] for s in data["sources"]]
    for row, source in zip(rows, data["sources"], strict=True):
        shown = row["magnitude (2σ)"]
        if source["magnitude"] is None:
            assert shown == "unconstrained"
        else:
            assert quantity(shown, source["unit"]) == pytest.approx(source["magnitude"],
                                                                    rel=5e-4)
        assert row["fixed or free"] == ("fixed" if source["fixed"] else "free")
        if source["binding_item"] is not None:
            item, time = row["binding item"].split(" at ")
            assert item == source["binding_item"]
            assert duration(time) == pytest.approx(3600 * source["binding_time_h"])
            percent, of = re.fullmatch(r"([\d.]+) % of (\w+)", row["largest share"]).groups()
            shares = source["largest_share"]
            assert of == max(shares, key=shares.get)
            assert float(percent) == pytest.approx(100 * shares[of], abs=5e-3)
        elif source["not_limited"] == "linear":
            assert row["binding item"] == ("not limited by this spec (linear model to "
                                           f"{source['linear_limit_display']})")
        else:
            assert row["binding item"] == "not limited on this motion"
    assert sum(r["magnitude (2σ)"] == "unconstrained" for r in rows) == 7


def test_report_items_are_the_jsons(built_in):
    """Each item at its worst time and every check time: value, limit and ratio as in
    the JSON, all met; the spec is described as the JSON and the file name say."""
    data, text = built_in
    found = tables(text)
    worst = found["Spec items at the allocated magnitudes"]
    assert [r["item"] for r in worst] == [i["name"] for i in data["items"]]
    for row, item in zip(worst, data["items"], strict=True):
        value, limit = value_of_limit(row["value of limit"], item["unit"])
        assert value == pytest.approx(item["value"], rel=5e-4)
        assert limit == pytest.approx(item["limit"], rel=5e-4)
        assert float(row["ratio"]) == pytest.approx(item["ratio"], abs=5e-4)
        assert duration(row["worst time"]) == pytest.approx(3600 * item["worst_time_h"])
        assert row["status"] == "met"
    every = found["Every check time"]
    assert len(every) == len(data["rows"]) == 119
    for row, json_row in zip(every, data["rows"], strict=True):
        assert row["item"] == json_row["item"]
        assert duration(row["time"]) == pytest.approx(3600 * json_row["time_h"])
        value, _ = value_of_limit(row["value of limit"], json_row["unit"])
        assert value == pytest.approx(json_row["value"], rel=5e-4)
        assert row["status"] == "met"
    head = text.split("## Allocation")[0]
    for words in ("# Error budget: product 802m (lab manual 000, appendix)",
                  "- **spec**: the built-in 802m spec", "- **model**: orthodromic",
                  f"- **motion**: {data['motion']}", "- **operating time**: 8 h (analysis "
                  "step 60 s)", "- **σ level**: 2σ", f"- **allocation rule**: {data['rule']}",
                  "- **result**: met"):
        assert words in head, words
    notes = text.split("## Notes and warnings")[1]
    assert "not limited on this motion: accel_scale_error_x, accel_scale_error_y" in notes
    assert rep.unlimited_note(data) in notes


def test_report_of_an_exceeded_spec_shows_it_exceeded(tmp_path, capsys):
    """The x gyro fixed at 0.5 deg/h breaks both items of the example spec: the report
    says SPEC EXCEEDED, shows each item exceeded at as many check times as the JSON's
    rows are, every such row exceeded, the fixed source's share above 100 %, and the
    warning that --monte-carlo was skipped, as the JSON's warnings hold it."""
    spec = str(ROOT / "examples" / "specs" / "gyro_drift_fixed.toml")
    report = tmp_path / "exceeded.md"
    data, err = run(["budget", "orthodromic", "--spec", spec, "--json", "--report",
                     str(report), "--monte-carlo", "2"], capsys, status=1)
    text = report.read_text(encoding="utf-8")
    assert "- **result**: SPEC EXCEEDED: the fixed sources alone use up 15 of 17" in text
    found = tables(text)
    worst = found["Spec items at the fixed sources alone"]
    for row, item in zip(worst, data["items"], strict=True):
        rows = [r for r in data["rows"] if r["item"] == item["name"]]
        over = sum(r["exceeded"] for r in rows)
        assert over and row["status"] == f"exceeded at {over} of {len(rows)} check times"
        value, limit = value_of_limit(row["value of limit"], item["unit"])
        assert value > limit and value == pytest.approx(item["value"], rel=5e-4)
        assert float(row["ratio"]) == pytest.approx(item["ratio"], abs=5e-4)
        assert float(row["ratio"]) > 1
    for row, json_row in zip(found["Every check time"], data["rows"], strict=True):
        assert row["status"] == ("exceeded" if json_row["ratio"] > 1 else "met")
    [fixed] = found["Allocation"]
    shares = data["sources"][0]["largest_share"]
    assert fixed["source"] == "gyro_drift_x" and fixed["fixed or free"] == "fixed"
    assert fixed["largest share"] == f"{100 * max(shares.values()):.0f} % of position_error"
    assert "initial_tilt_x, initial_tilt_y" in text.split("## Spec items")[0]
    # items exceeded at their check times: no word of between them, the rows say it
    assert all(item["between_checks"] is None for item in data["items"])
    [warning] = data["warnings"]
    assert warning.startswith("--monte-carlo skipped") and f"- {warning}" in text
    assert f"ins-errors: warning: {warning}" in err


NO_TILT = '    title = "vertical at rest"\n' + NO_TILT_SPEC  # (test_budget_cli's spec)


def test_report_monte_carlo_is_the_jsons_and_is_reproducible(tmp_path, capsys,
                                                             monkeypatch):
    """The Monte Carlo check's table holds the JSON's rows (the spec's unit, the
    ratio, – where the covariance is 0, with the terminal's note); the report names
    the spec as typed (a relative path), holds no folder of this machine and no
    date, and the same run writes it again byte for byte."""
    monkeypatch.chdir(tmp_path)
    write(tmp_path, NO_TILT, "specs/no tilt.toml")
    argv = ["budget", "orthodromic", "--spec", "specs/no tilt.toml", "--monte-carlo", "3",
            "--mc-step", "1 s", "--mc-duration", "20 min", "--engine", "serial", "--json",
            "--report", "out/review.md"]
    data, _ = run(argv, capsys)
    text = (tmp_path / "out" / "review.md").read_text(encoding="utf-8")
    mc = data["monte_carlo"]
    for line in rep.monte_carlo_lines(mc):
        assert f"- {line}." in text
    assert "3 runs of 20 min at 1 s (euler, seed 0)" in text
    rows = tables(text)["Monte Carlo check"]
    assert [r["row"] for r in rows] == [r["row"] for r in mc["rows"]]
    for row, json_row in zip(rows, mc["rows"], strict=True):
        for key in ("covariance", "monte_carlo"):
            cell = row["covariance" if key == "covariance" else "Monte Carlo"]
            assert cell.endswith(" arcsec")   # the unit the spec's limit is written in
            assert quantity(cell, "rad") == pytest.approx(json_row[key], rel=5e-4,
                                                          abs=1e-15)
        if json_row["ratio"] is None:
            assert row["ratio"] == "–"
        else:
            assert float(row["ratio"]) == pytest.approx(json_row["ratio"], abs=5e-4)
    assert rows[0]["ratio"] == "–" and f"–: {rep.NO_RATIO}." in text
    assert "- **spec**: specs/no tilt.toml" in text
    assert str(tmp_path) not in text and str(ROOT) not in text
    assert not re.search(r"(?<![\w.])/\w", text)   # no absolute path of any folder
    assert not re.search(r"\b\d{4}-\d\d-\d\d\b|\d\d:\d\d:\d\d", text)
    run(argv, capsys)
    assert (tmp_path / "out" / "review.md").read_text(encoding="utf-8") == text


@pytest.mark.parametrize("option, target, words", [
    ("--report", "budget.txt", "the budget's report is Markdown, so end the name with "
                               ".md, not .txt"),
    ("--report", "budget", "the budget's report is Markdown, so end the name with .md"),
    ("--report", "taken/budget.md", "'taken' is a file, not a folder"),
    ("--plot-time", "time.csv", "its suffix .csv is not an image format"),
    ("--plot-time", "taken/time.png", "'taken' is a file, not a folder"),
])
def test_report_and_plot_time_names_are_refused_before_any_work(
        tmp_path, capsys, monkeypatch, option, target, words):
    """A report that is not Markdown, or either output where it cannot be written:
    one line naming it, exit 2, nothing on standard output, and no covariance
    propagated first."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken").write_text("a file")
    monkeypatch.setattr(bd, "unit_budget", lambda *a, **k: pytest.fail("propagated"))
    assert main(["budget", "orthodromic", option, target]) == 2
    captured = capsys.readouterr()
    assert not captured.out and captured.err.count("\n") == 1
    assert captured.err.startswith("ins-errors: error: ") and words in captured.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken"]


# ------------------------------------------------------------------------------------
# 2. --plot-time: the curves are the budget's values
# ------------------------------------------------------------------------------------
def test_curves_at_the_check_times_are_the_budget_rows(built_in, orthodromic):
    """At every check time each item's curve is the row the budget reports (the
    --json run's), to rounding; the curves cover the grid (a rate item from its first
    step)."""
    data, _ = built_in
    allocation = bd.allocate(bd.unit_budget(orthodromic, load_spec(default_spec_path())))
    curves = bt.item_curves(allocation)
    assert [c.item for c in curves] == [i["name"] for i in data["items"]]
    for curve in curves:
        rows = [r for r in data["rows"] if r["item"] == curve.item]
        assert curve.check_times == pytest.approx([3600 * r["time_h"] for r in rows])
        assert curve.check_values == pytest.approx([r["value"] for r in rows], rel=1e-12)
        at = np.searchsorted(curve.times, curve.check_times)
        assert np.array_equal(curve.values[at], curve.check_values)
        first = 60.0 if curve.item in bd.RATE_ITEMS else 0.0
        assert curve.times[0] == first and curve.times[-1] == 8 * 3600
        assert np.all(np.diff(curve.times) == pytest.approx(60.0))


def test_each_component_is_a_curve_of_its_own(tmp_path):
    """With combine = "each" the north and east position errors are two curves, each
    equal to its own rows."""
    text = default_spec_path().read_text().replace(
        'value = "3.7 km/h"', 'value = "3.7 km/h"\ncombine = "each"')
    spec = load_spec(write(tmp_path, text))
    allocation = bd.allocate(bd.unit_budget("orthodromic", spec))
    data = rep.report(allocation)
    curves = [c for c in bt.item_curves(allocation) if c.item == "position_error"]
    assert [c.component for c in curves] == ["north", "east"]
    for curve in curves:
        rows = [r for r in data["rows"] if r["item"] == "position_error"
                and r["component"] == curve.component]
        assert curve.check_values == pytest.approx([r["value"] for r in rows], rel=1e-12)


def test_plot_time_draws_the_curves_in_the_limits_unit(built_in, monkeypatch, tmp_path,
                                                       capsys):
    """The command draws every item's curve in the unit its limit is written in, the
    limit as a line at its value, the check times on the curve; the position rate,
    which spans decades from the first minute on, on a log axis."""
    captured: dict = {}
    monkeypatch.setattr(bt, "save_figure",
                        lambda fig, path, dpi: captured.setdefault("fig", fig))
    assert main(["budget", "orthodromic", "--plot-time", str(tmp_path / "t.png")]) == 0
    assert "plot written to" in capsys.readouterr().out
    axes = captured["fig"].axes
    data, _ = built_in
    units = {"position_error": ("km/h", "m/s"), "ground_speed_error": ("m/s", "m/s"),
             "vertical_error": ("deg", "rad"), "heading_drift": ("deg/h", "rad/s")}
    for ax, item in zip(axes, data["items"], strict=True):
        shown, si = units[item["name"]]
        assert ax.get_ylabel() == shown
        curve, checks = ax.get_lines()[:2]
        rows = [r for r in data["rows"] if r["item"] == item["name"]]
        factor = quantity(f"1 {shown}", si)
        assert checks.get_ydata() * factor == pytest.approx([r["value"] for r in rows],
                                                           rel=1e-9)
        assert checks.get_xdata() == pytest.approx([r["time_h"] for r in rows])
        limit = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
        assert limit[0].get_ydata()[0] * factor == pytest.approx(item["limit"])
        assert ax.get_yscale() == ("log" if item["name"] == "position_error" else "linear")
        assert len(curve.get_xdata()) >= 480
    assert axes[-1].get_xlabel() == "time since the start, h"


def test_a_curve_above_its_limit_between_checks_is_found():
    """Checked every 5 min, an error that peaks at 3× the limit in between is met at
    every check: the place between them is found; before the first check, and a
    curve whose largest value is a check's, are not."""
    times = np.arange(0, 1201.0, 10.0)
    values = 10.0 + 20.0 * np.exp(-((times - 150.0) / 40.0) ** 2) * 3
    checks = np.array([0.0, 300.0, 600.0, 900.0, 1200.0])
    at = np.searchsorted(times, checks)
    curve = bt.ItemCurve("height_error", "", "m", 30.0, times, values, checks, values[at])
    assert all(curve.check_values < 30.0)
    t, value = bt.above_between_checks(curve)
    assert t == 150.0 and value == pytest.approx(70.0)
    late = bt.ItemCurve("height_error", "", "m", 30.0, times, values, checks[1:],
                        values[at[1:]])
    assert bt.above_between_checks(late) is None


# ------------------------------------------------------------------------------------
# 3. The curves against the textbook
# ------------------------------------------------------------------------------------
EQUATOR_G = 9.7803253359
"""Normal gravity at the equator, m/s² (Somigliana, GRS 80 / WGS 84): the specific force
a platform at rest there measures."""

KRASOVSKY_A = 6378245.0
"""The Krasovsky ellipsoid's semi-major axis, m (the orthodromic model's default): at
the equator the east radius of curvature R_E is a."""


@pytest.mark.parametrize("source", ["accel_bias_y", "gyro_drift_x"])
def test_equator_curves_follow_the_schuler_textbook_forms(tmp_path, orthodromic, source):
    """The built-in 802m spec with its static base moved to the equator and one source
    allocated: there the east channel (tilt about north, east velocity, longitude) of
    a platform at rest is a Schuler loop of ω_s = √(g/R) alone (no Foucault or Earth-rate
    coupling). At the allocated magnitude b (2σ), from rest:

    * an east accelerometer bias: position b/ω_s² (1 − cos ω_s t), velocity
      b/ω_s sin ω_s t, tilt b/g (1 − cos ω_s t);
    * a north gyro drift: position R b (t − sin ω_s t / ω_s), velocity
      R b (1 − cos ω_s t), tilt b/ω_s sin ω_s t;

    the position item being a rate, position / t. The curves are those over 8 h."""
    text = default_spec_path().read_text().replace('latitude = "50 deg"',
                                                   'latitude = "0 deg"')
    assert 'latitude = "0 deg"' in text
    text += "".join(f"\n[sources.{s.name}]\ninclude = false\n"
                    for s in orthodromic.sources if s.name != source)
    allocation = bd.allocate(bd.unit_budget(orthodromic, load_spec(write(tmp_path, text))))
    j = [s.name for s in allocation.budget.sources].index(source)
    b = allocation.magnitudes[j]                 # 2σ, SI
    assert np.isfinite(b) and allocation.levels[j] == 2
    g, R = EQUATOR_G, KRASOVSKY_A
    w = np.sqrt(g / R)
    curves = {c.item: c for c in bt.item_curves(allocation)}
    if source == "accel_bias_y":
        textbook = {"position_error": lambda t: b / w**2 * (1 - np.cos(w * t)) / t,
                    "ground_speed_error": lambda t: b / w * np.abs(np.sin(w * t)),
                    "vertical_error": lambda t: b / g * (1 - np.cos(w * t))}
    else:
        textbook = {"position_error": lambda t: R * b * (t - np.sin(w * t) / w) / t,
                    "ground_speed_error": lambda t: R * b * (1 - np.cos(w * t)),
                    "vertical_error": lambda t: b / w * np.abs(np.sin(w * t))}
    for item, curve in curves.items():
        if item == "heading_drift":   # the azimuth: not in the east channel
            assert np.max(curve.values) <= 1e-9 * curve.limit
            continue
        expected = textbook[item](curve.times)
        assert np.max(np.abs(curve.values - expected)) <= 1e-8 * np.max(expected), item


UAV_SPEC = ROOT / "examples" / "specs" / "uav_strapdown.toml"


def uav_with_a_hole(tmp_path: Path) -> Path:
    """The example UAV spec with its height checked every 5 min, as it once was: the
    initial vertical velocity error the height item then allows at 5 min gives five
    times the limit within the first minute, between the first two checks."""
    text = UAV_SPEC.read_text()
    assert text.count('every = "1 min"') == 1
    return write(tmp_path, text.replace('every = "1 min"', 'every = "5 min"'), "hole.toml")


def test_a_height_peak_between_checks_is_the_at_breakdowns(tmp_path):
    """The curve between the checks (off the check times) is the --at breakdown's
    height error, a propagation of its own (every state and output, at the allocated
    magnitudes), and it is the peak the budget reports between the checks."""
    from ins_errors.analysis.budget_contributions import output_contributions
    from ins_errors.numeric.model import load_model
    from ins_errors.specs import spec_parameters

    model = load_model("strapdown_ned")
    spec = load_spec(uav_with_a_hole(tmp_path))
    p = model.parameter_vector(**spec_parameters(spec, model, []))
    allocation = bd.allocate(bd.unit_budget(model, spec, p=p))
    [height] = [c for c in bt.item_curves(allocation) if c.item == "height_error"]
    assert np.all(height.check_values <= height.limit)
    t, value = bt.above_between_checks(height)
    assert 0 < t < 300 and value > 3 * height.limit
    outputs = output_contributions(model, allocation, [t])
    q = outputs["quantities"].index("delta_height")
    assert outputs["units"][q] == "m"
    assert value == pytest.approx(outputs["total"][0][q], rel=1e-9)   # the spec is 1σ
    std = outputs["std"][0][q]
    assert outputs["sources"][int(np.argmax(std))] == "initial_velocity_error_D"
    peak = rep.between_checks(allocation)["height_error"]
    assert peak["time_h"] * 3600 == t and peak["value"] == value
    assert all(v is None for k, v in rep.between_checks(allocation).items()
               if k != "height_error")


def test_a_height_peak_between_checks_is_warned_of_everywhere(tmp_path, capsys):
    """The spec with the hole is met at every check time (exit 0), but the budget says
    where it is not: one warning on stderr, in --json's warnings and the item's
    between_checks, in the terminal's items table and in the report's result, status
    and notes."""
    spec = str(uav_with_a_hole(tmp_path))
    report = tmp_path / "hole.md"
    data, err = run(["budget", "strapdown_ned", "--spec", spec, "--json", "--report",
                     str(report)], capsys)
    [warning] = [w for w in data["warnings"] if "between its check times" in w]
    assert f"ins-errors: warning: {warning}" in err
    [height] = [i for i in data["items"] if i["name"] == "height_error"]
    peak = height["between_checks"]
    assert peak["ratio"] > 3 and peak["ratio"] == pytest.approx(peak["value"] / 30.0)
    assert not height["exceeded"] and height["ratio"] <= 1
    assert warning.startswith(f"height_error passes its limit between its check times: "
                              f"{peak['display']} (1σ) at 50 s")
    assert "every 5 min from the start to 20 min" in warning
    assert 'every = "10 s"' in warning   # the analysis step: the whole run
    assert all(i["between_checks"] is None for i in data["items"] if i is not height)
    text = report.read_text(encoding="utf-8")
    assert f"- {warning}" in text
    assert "above the limit between the check times: height_error" in text
    # the spec's gains, written as -p takes them (1/s^2, not SymPy's 1/s**2)
    assert "k_h1 = 0.0293 1/s; k_h2 = 0.000442 1/s^2" in text
    row = {r["item"]: r for r in tables(text)["Spec items at the allocated magnitudes"]}
    assert row["height_error"]["status"].startswith(
        f"met at its check times only; between them {peak['display']} at 50 s")
    assert main(["budget", "strapdown_ned", "--spec", spec]) == 0
    out = capsys.readouterr().out
    assert f"! height_error between its check times: {peak['display']} at 50 s" in out


def test_the_example_uav_spec_holds_its_height_between_checks(capsys):
    """The example checks the height every minute: no item of it passes its limit
    between its check times, so the budget warns of none, and its curves stay within
    their limits over the whole run."""
    data, err = run(["budget", "strapdown_ned", "--spec", str(UAV_SPEC), "--json"], capsys)
    assert "between its check times" not in err
    assert not [w for w in data["warnings"] if "between its check times" in w]
    assert all(item["between_checks"] is None for item in data["items"])
    assert not data["exceeded"]


def test_a_height_peak_between_checks_is_the_vertical_channels_textbook_response(
        tmp_path, capsys):
    """A spec that allocates the initial vertical velocity error alone, on the height
    checked every 5 min, static base: the damped vertical channel is the textbook one,

        δv̇_E = 2Ω cos φ δv_D,  δv̇_D = −2Ω cos φ δv_E + (k₂ + ∂γ/∂h) δh,
        δḣ = −δv_D − k₁ δh,

    (the Coriolis pair shifts the tail of the response by 0.2 % at 5 min), with ∂γ/∂h
    the WGS 84 free-air gradient −2γ₀/a (1 + f + m − 2f sin²φ) + 6γ₀h/a². The source
    takes the whole allowed variance where it binds, at 5 min: its allowance is
    30 m / |δh(5 min)| per m/s, and the peak between the checks is that times the
    largest |δh| on the 10-s grid, 27 times the limit at 50 s."""
    from scipy.linalg import expm

    from ins_errors.numeric.model import load_model

    model = load_model("strapdown_ned")
    text = """
        title = "initial vertical velocity, height checked every 5 min"
        sigma_level = 1
        operating_time = "20 min"
        step = "10 s"
        [motion]
        kind = "static"
        latitude = "45 deg"
        height = "1000 m"
        [items.height_error]
        value = "30 m"
        every = "5 min"
        [parameters]
        k_h1 = "0.0293 1/s"
        k_h2 = "4.42e-4 1/s**2"
    """ + "".join(f"[sources.{s.name}]\ninclude = false\n" for s in model.sources
                  if s.name != "initial_velocity_error_D")
    data, err = run(["budget", "strapdown_ned", "--spec", str(write(tmp_path, text)),
                     "--json"], capsys)
    # WGS 84 (NIMA TR8350.2): a, f, γ_e, Somigliana's k, m = ω²a²b/GM; Earth rate
    a, f, gamma_e, k, m = (6378137.0, 1 / 298.257223563, 9.7803253359,
                           0.00193185265241, 0.00344978600308)
    earth_rate = 7.292115e-5
    lat, h, k1, k2 = np.radians(45.0), 1000.0, 0.0293, 4.42e-4
    s2 = np.sin(lat) ** 2
    gamma0 = gamma_e * (1 + k * s2) / np.sqrt(1 - f * (2 - f) * s2)
    gradient = -2 * gamma0 / a * (1 + f + m - 2 * f * s2) + 6 * gamma0 * h / a**2
    c = 2 * earth_rate * np.cos(lat)
    A = np.array([[0.0, c, 0.0], [-c, 0.0, k2 + gradient], [0.0, -1.0, -k1]])
    times = np.arange(0.0, 1201.0, 10.0)
    dh = np.abs([(expm(A * t) @ [0.0, 1.0, 0.0])[2] for t in times])  # per m/s of δv_D(0)
    allowed = 30.0 / dh[times == 300.0][0]
    [source] = [s for s in data["sources"] if s["magnitude"] is not None]
    assert source["name"] == "initial_velocity_error_D"
    assert source["binding_time_h"] * 3600 == 300.0
    assert source["magnitude"] == pytest.approx(allowed, rel=1e-3)
    peak = data["items"][0]["between_checks"]
    inside = (times > 0) & (times < 300)
    assert peak["time_h"] * 3600 == times[inside][np.argmax(dh[inside])] == 50.0
    assert peak["value"] == pytest.approx(allowed * dh[times == 50.0][0], rel=1e-3)
    assert peak["ratio"] == pytest.approx(dh[times == 50.0][0] / dh[times == 300.0][0],
                                          rel=1e-3)
    assert "height_error passes its limit between its check times" in err
