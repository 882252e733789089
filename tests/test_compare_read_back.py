"""``compare`` and ``run`` refuse a model whose outputs do not read back its initial-state map.

An ENU researcher's model file read its output heading as +yaw while its initial-state
map set yaw = −heading: ``check`` refused it, ``compare`` ran with exit 0 and reported
δheading with the wrong sign. Here the tutorial's Schuler loop with the same kind of
slip, its output v_N = −V while its map sets V = v_N0: at a static base v_N0 = 0 and the
run's own start would hide it, so the check also reads back a shifted start. The
unaltered file runs.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ins_errors.cli import main
from tests.helpers import edited_model_file

ROOT = Path(__file__).resolve().parents[1]
LOOP = ROOT / "examples" / "own_model" / "schuler_loop.py"


@pytest.fixture(scope="module")
def slipped(tmp_path_factory) -> Path:
    """The Schuler loop with its output v_N of the opposite sign to its initial state's."""
    return edited_model_file(LOOP, tmp_path_factory.mktemp("model"),
                             "return sp.Matrix([latitude, velocity])",
                             "return sp.Matrix([latitude, -velocity])", "schuler_sign")


def _one_line(capsys) -> str:
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = [line for line in captured.err.splitlines() if "deriving model file" not in line]
    assert len(lines) == 1, captured.err
    return lines[0]


def test_compare_refuses_an_output_that_does_not_read_back_its_initial_state(slipped,
                                                                             capsys):
    args = ["-s", "accel_bias=100ug", "--hours", "1", "--step", "10s", "--no-progress"]
    assert main(["compare", str(slipped), *args]) == 2
    line = _one_line(capsys)
    assert "output 'v_N' does not read back what its initial-state map was given" in line
    assert "1.5 m/s given, -1.5 m/s read back" in line
    assert main(["compare", str(LOOP), *args, "--json"]) == 0  # the file as written runs
    capsys.readouterr()


def test_run_refuses_it_too(slipped, tmp_path, capsys):
    scenario = tmp_path / "slip.toml"
    scenario.write_text(f"""title = "slip"
model = "{slipped.as_posix()}"
[motion]
kind = "static"
latitude = "50 deg"
[run]
duration = "1 h"
step = "10 s"
[[case]]
accel_bias = "100 ug"
""", encoding="utf-8")
    assert main(["run", str(scenario), "--out", str(tmp_path / "out"), "--no-progress"]) == 2
    assert "does not read back what its initial-state map was given" in _one_line(capsys)
