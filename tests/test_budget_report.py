"""Budget tables and plots: the rows they name, and the rows adding up to the totals."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ins_errors.analysis import budget as bd
from ins_errors.analysis import budget_contributions as bc
from ins_errors.analysis import budget_report as rep
from ins_errors.cli import main
from ins_errors.specs import HOUR, default_spec_path, load_spec


@pytest.fixture(scope="module")
def outputs_802m(orthodromic):
    allocation = bd.allocate(bd.unit_budget(orthodromic, load_spec(default_spec_path())))
    return bc.output_contributions(orthodromic, allocation, [HOUR, 8 * HOUR])


@pytest.mark.parametrize("top", [3, 10])
def test_output_rows_add_up_to_the_total(outputs_802m, top):
    """The named rows and the "(N others)" row combine in rss to the total row, and
    every error's two largest contributors are named (with 10 rows of 19 sources)."""
    data = outputs_802m
    for it in range(len(data["times_h"])):
        rows = rep.output_rows(data, it, top)
        labels = [label for label, _ in rows]
        count = len(data["sources"]) - top
        assert labels[-2:] == [f"({count} others)", "total (rss)"]
        assert len(set(labels[:-2])) == top
        listed = np.array([values for _, values in rows[:-1]])
        total = rows[-1][1]
        assert np.sqrt((listed**2).sum(0)) == pytest.approx(total, rel=1e-12)
        assert total == pytest.approx(np.sqrt((data["std"][it] ** 2).sum(-1)), rel=1e-12)
        if top == 10:
            std = data["std"][it]                                     # (q, s)
            second = np.sort(std, axis=1)[:, -2]
            named = [data["sources"].index(label) for label in labels[:-2]]
            unnamed = np.delete(std, named, axis=1)
            assert np.all(unnamed.max(1) <= second * (1 + 1e-9))


def test_output_table_prints_the_others_row(outputs_802m):
    """At 1 h the north position column's printed rows (4 digits) add up to its total."""
    lines = rep.output_table(outputs_802m).splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("---")) + 1
    end = next(i for i, line in enumerate(lines) if line.startswith("total (rss)")) + 1
    assert end - start == 12 and lines[end - 2].startswith("(9 others) ")
    quantities = outputs_802m["quantities"]
    column = quantities.index("delta_r_N") - len(quantities)
    values = [float(line.split()[column]) for line in lines[start:end]]
    assert np.sqrt(np.sum(np.square(values[:-1]))) == pytest.approx(values[-1], rel=2e-3)


def test_selection_names_each_columns_largest_sources():
    """Source 3 is the largest of a column where every other source is small: named
    although its share is below sources large only in the first column."""
    shares = np.array([[0.30, 0.25, 0.25, 0.00, 0.10, 0.10],
                       [0.01, 0.02, 0.01, 0.90, 0.03, 0.03]])
    named, others = rep.select_sources(shares, 2)
    assert named.tolist() == [3, 0] and others.tolist() == [1, 2, 4, 5]
    named, others = rep.select_sources(shares, 3)     # round 2: larger share first
    assert named.tolist() == [3, 0, 1] and others.tolist() == [2, 4, 5]
    named, others = rep.select_sources(shares, 5)      # one left over: all named
    assert sorted(named.tolist()) == list(range(6)) and not others.size
    # sources with no share anywhere (not limited) are neither named nor among the
    # others: a "(N others)" row of zeros said nothing
    named, others = rep.select_sources(np.array([[0.5, 0.0, 0.3, 0.0, 0.2]]), 1)
    assert named.tolist() == [0] and others.tolist() == [2, 4]
    named, others = rep.select_sources(np.array([[0.5, 0.0, 0.5, 0.0]]), 1)
    assert named.tolist() == [0, 2] and not others.size   # one left over: named


def test_plot_bars_add_up_and_name_the_largest(outputs_802m, tmp_path, monkeypatch):
    """Every stacked bar sums to 1; with more sources than colours the grey block is
    the rest's share, and no named source is absent from a bar it tops."""
    captured = {}
    monkeypatch.setattr(rep, "save_figure", lambda fig, path, dpi: captured.update(fig=fig))
    rep.plot_outputs(outputs_802m, str(tmp_path / "x.png"))
    fig = captured["fig"]
    names = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "others" not in names and len(names) == len(outputs_802m["sources"])
    for ax in fig.axes:
        heights = np.zeros(len(outputs_802m["quantities"]))
        for container in ax.containers:
            heights += [bar.get_height() for bar in container]
        assert heights == pytest.approx(1.0, rel=1e-12)
    rng = np.random.default_rng(3)
    std = rng.uniform(0.1, 1, (1, 4, 30))
    std[0, 2, 29] = 50.0                      # the only large source of error 2
    data = {"std": std, "total": np.sqrt((std**2).sum(-1)), "times_h": [1.0],
            "sources": [f"s{j}" for j in range(30)], "quantities": ["a", "b", "c", "d"],
            "units": ["m"] * 4}
    rep.plot_outputs(data, str(tmp_path / "y.png"), top=5)
    ax = captured["fig"].axes[0]
    labels = [c.get_label() for c in ax.containers]
    assert labels[-1] == "others" and "s29" in labels and len(labels) == 6
    shares = std[0] ** 2 / (std[0] ** 2).sum(-1, keepdims=True)
    named = [int(label[1:]) for label in labels[:-1]]
    grey = [bar.get_height() for bar in ax.containers[-1]]
    assert grey == pytest.approx(np.delete(shares, named, axis=1).sum(1), rel=1e-12)


def test_json_contributions_are_labelled(capsys):
    assert main(["budget", "orthodromic", "--at", "1 h", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)["contributions"]
    std, total = np.array(data["std"]), np.array(data["total"])
    assert std.shape == (1, len(data["quantities"]), len(data["sources"]))
    assert total.shape == (1, len(data["quantities"]))
    assert total == pytest.approx(np.sqrt((std**2).sum(-1)), rel=1e-12)


def test_tables_keep_whole_names_and_times():
    """No header cut short; a time that went through hours and back reads as hours."""
    assert bd.format_time(7800.000000000001) == "2 h 10 min"
    assert bd.format_time(2.1666666666666665 * HOUR) == "2 h 10 min"
    assert bd.format_time(90.0) == "90 s" and bd.format_time(90.5) == "90.5 s"
    data = {"times_h": [1.0], "quantities": ["delta_latitude", "delta_v_N"],
            "units": ["arcmin", "m/s"], "sources": ["a", "b"],
            "std": np.array([[[3.0, 4.0], [1.0, 0.0]]]), "total": np.array([[5.0, 1.0]])}
    header = rep.output_table(data).splitlines()[1]
    assert header.split() == ["source", "(1σ)", "Δlatitude", "arcmin", "Δv_N", "m/s"]


def test_share_table_keeps_whole_item_names(orthodromic, tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text('operating_time = "1 h"\n[motion]\nlatitude = "45 deg"\n'
                    '[items.ground_speed_error]\nvalue = "4 m/s"\n'
                    '[items.heading_drift]\nvalue = "0.1 deg/h"\n')
    allocation = bd.allocate(bd.unit_budget(orthodromic, load_spec(spec)))
    lines = rep.contribution_table(allocation).splitlines()
    assert lines[1].split() == ["source", "ground_speed_error", "heading_drift"]
    assert lines[-1].split()[0] == "total" and len(lines[-1]) == len(lines[1])


def test_allocation_plot_shows_each_sources_share_of_every_item(orthodromic, tmp_path,
                                                                  monkeypatch, capsys):
    """The left panel's bars are each source's largest share of each item's allowed
    variance, recomputed here by a fresh propagation at the allocated magnitudes: the
    binding item's bar is the equal share 1/n, the others show where else it is used."""
    allocation = bd.allocate(bd.unit_budget(orthodromic, load_spec(default_spec_path())))
    budget = allocation.budget
    names = [s.name for s in budget.sources]
    limited = np.flatnonzero(np.isfinite(allocation.sigma))
    evaluation = bd.evaluate(orthodromic, budget.spec,
                             {names[j]: float(allocation.sigma[j]) for j in limited})
    shares = evaluation.contributions / budget.allowed_variances[:, None]
    captured = {}
    monkeypatch.setattr(rep, "save_figure", lambda fig, path, dpi: captured.update(fig=fig))
    rep.plot(allocation, str(tmp_path / "b.png"))
    left = captured["fig"].axes[0]
    labels = [t.get_text().split()[0] for t in left.get_yticklabels()]
    items = [item.name for item in budget.spec.items]
    assert [c.get_label() for c in left.containers] == items
    for i, item in enumerate(items):
        rows = [r for r, row in enumerate(budget.rows) if row.item == item]
        bars = [bar.get_width() for bar in left.containers[i]]
        expected = [100 * shares[rows, names.index(n)].max() for n in labels]
        assert bars == pytest.approx(expected, rel=1e-9, abs=1e-12)
        for n, width in zip(labels, bars, strict=True):
            if budget.rows[allocation.binding[names.index(n)]].item == item:
                assert width == pytest.approx(100 / limited.size, rel=1e-9)
    assert sorted(labels) == sorted(names[j] for j in limited)
