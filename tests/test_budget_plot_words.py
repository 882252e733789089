"""The budget's time plot and text report: an item checked at hundreds of times stays a
readable curve (smaller markers), and a spec with CEP items says what they are in the
title and the rows' heading (a CEP has no σ level)."""

from pathlib import Path

from ins_errors.analysis.budget_time import SPARSE_CHECKS, _check_marker_size
from ins_errors.commands.budget import _level_words
from ins_errors.specs import load_spec

ROOT = Path(__file__).resolve().parent.parent


def test_many_check_times_get_smaller_markers_down_to_a_floor():
    sizes = [_check_marker_size(n) for n in (1, SPARSE_CHECKS, 2 * SPARSE_CHECKS, 481, 10**6)]
    assert sizes[0] == sizes[1] > sizes[2] > sizes[3] >= sizes[4] == 1.0


def test_a_cep_spec_says_what_its_cep_items_are():
    assert _level_words(load_spec(ROOT / "examples" / "specs" / "aircraft_cep.toml")) == (
        "1σ (CEP items: the radius holding 50 %)")
    assert _level_words(load_spec(ROOT / "examples" / "specs" / "uav_strapdown.toml")) == "1σ"


def test_the_text_report_says_what_its_cep_rows_are(capsys):
    from ins_errors.cli import main

    spec = ROOT / "examples" / "specs" / "aircraft_cep.toml"
    assert main(["budget", "strapdown_ned", "--spec", str(spec), "--no-progress"]) == 0
    [line] = [text for text in capsys.readouterr().out.splitlines()
              if text.startswith("Spec rows at")]
    assert "(worst time of each item, 1σ (CEP items: the radius holding 50 %);" in line
