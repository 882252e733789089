"""Exit status 3: the command finished, some points (``sweep``) or sweeps (``validity``)
failed on their own input; 2 stays for a command that did not run (bad input).

Both gave 2 before, so a CI job or a SLURM script could not tell "finished, some points
failed" from "a typo, nothing ran". Run as a shell runs the command (the process's own
exit status, as a batch system reads it).
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.helpers import FLIGHT_10_MIN

pytest.importorskip("zarr")  # the sweep store needs the 'distributed' extra (in 'dev')

ROOT = Path(__file__).resolve().parent.parent

FLIGHT = FLIGHT_10_MIN + """[sweep]
latitude = ["10 deg", "89.5 deg"]
"""
"""A flight due north at 250 m/s for 10 min: from 10° N it stays far from the pole; from
89.5° N it reaches the pole after 0.5° of meridian, about 56 km, 222 s."""

POLE_ARRIVAL_S = math.radians(0.5) * 6371e3 / 250.0
"""When the flight from 89.5° N reaches the pole, on a sphere of the Earth's mean radius
(the ellipsoid's meridian near the pole is 0.4 % longer): 222.4 s."""


def _ins_errors(folder: Path, *argv: str) -> subprocess.CompletedProcess:
    """``ins-errors ARGV...`` in ``folder``, as a shell runs it."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(
        os.pathsep)
    return subprocess.run([sys.executable, "-m", "ins_errors", *argv], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=600)


def _did_not_run(done: subprocess.CompletedProcess, *named: str) -> None:
    """Status 2, one line on stderr naming the problem, nothing on stdout."""
    assert done.returncode == 2, done.stderr
    assert done.stdout == "" and done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith("ins-errors: error: ")
    for text in named:
        assert text in done.stderr, done.stderr


def _points_in(store: Path) -> int:
    from ins_errors.analysis.store import points_done

    return points_done(store)


def test_a_sweep_with_a_failing_point_exits_3_and_bad_input_exits_2(tmp_path):
    """The flight from 89.5° N reaches the pole (at the time it takes to fly there, to a
    step); the other point runs, the store holds both, the failed one is listed on
    stderr (one line) and under "failed": status 3. A typo'd option and an unknown source
    name exit 2 before anything is written."""
    (tmp_path / "s.toml").write_text(textwrap.dedent(FLIGHT), encoding="utf-8")
    done = _ins_errors(tmp_path, "sweep", "s.toml", "--engine", "serial", "--store",
                       "s.zarr", "--no-progress", "--json")
    assert done.returncode == 3, done.stderr
    (failed,) = json.loads(done.stdout)["failed"]
    assert failed["point"] == 1 and failed["label"] == "latitude = 89.5 deg"
    lines = done.stderr.splitlines()
    assert lines[-2] == ("ins-errors: 1 of 2 points failed (stored without results; "
                         "--retry-failed runs them again):")
    assert lines[-1] == f"  point 1 (latitude = 89.5 deg): {failed['reason']}"
    arrival = float(re.search(r"at t = ([0-9.]+) s", failed["reason"]).group(1))
    assert POLE_ARRIVAL_S - 5.0 <= arrival <= POLE_ARRIVAL_S + 10.0, failed["reason"]
    assert _points_in(tmp_path / "s.zarr") == 2   # finished: the store is complete

    typo = _ins_errors(tmp_path, "sweep", "s.toml", "--enigne", "serial", "--store",
                       "typo.zarr", "--no-progress")
    _did_not_run(typo, "--enigne")
    (tmp_path / "unknown.toml").write_text(
        textwrap.dedent(FLIGHT).replace("accel_bias_x =", "acel_bias_x ="), encoding="utf-8")
    unknown = _ins_errors(tmp_path, "sweep", "unknown.toml", "--engine", "serial",
                          "--store", "unknown.zarr", "--no-progress")
    _did_not_run(unknown, "unknown source", "'acel_bias_x'")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml", "s.zarr", "unknown.toml"]


def test_shards_of_an_array_job_exit_3_with_a_failed_point_and_merge(tmp_path):
    """The SLURM array of docs/cluster.md in small: shard 2 of 2 holds the point over the
    pole and exits 3 with its store complete; the merge (after any, not after ok) joins
    both and exits 3 too, listing the failed point."""
    (tmp_path / "s.toml").write_text(textwrap.dedent(FLIGHT), encoding="utf-8")
    statuses = [_ins_errors(tmp_path, "sweep", "s.toml", "--engine", "serial", "--shard",
                            f"{i}/2", "--store", f"part_{i}.zarr", "--no-progress")
                for i in (1, 2)]
    assert [s.returncode for s in statuses] == [0, 3], statuses[1].stderr
    assert "point 1 (latitude = 89.5 deg)" in statuses[1].stderr.splitlines()[-1]
    merged = _ins_errors(tmp_path, "sweep", "s.toml", "--merge", "part_1.zarr",
                         "part_2.zarr", "--store", "all.zarr", "--json")
    assert merged.returncode == 3, merged.stderr
    report = json.loads(merged.stdout)
    assert (report["points"], report["merged"]) == (2, 2)
    assert [f["point"] for f in report["failed"]] == [1]
    assert merged.stderr.splitlines()[-1].startswith("  point 1 (latitude = 89.5 deg): ")
    assert _points_in(tmp_path / "all.zarr") == 2


VALIDITY = ["validity", "strapdown_ned", "--motion", "static", "--hours", "1", "--step",
            "30s", "--engine", "serial", "--no-progress"]
"""strapdown_ned's undamped vertical channel grows ×e every 9.5 min: over 1 h an up
accelerometer bias of some 10 mg takes the direct run out of the model's domain."""


def test_a_validity_map_with_a_failing_sweep_exits_3_and_bad_input_exits_2(tmp_path):
    """The up accelerometer bias's sweep fails at its largest magnitudes, the gyro bias's
    runs: the map finishes, lists the failed sweep on stderr (one line after a header)
    and under "failed", status 3. A typo'd option and an unknown source exit 2."""
    done = _ins_errors(tmp_path, *VALIDITY, "-s", "accel_bias_z", "-s", "gyro_bias_x",
                       "--json")
    assert done.returncode == 3, done.stderr
    report = json.loads(done.stdout)
    assert [r["source"] for r in report["sources"]] == ["accel_bias_z", "gyro_bias_x"]
    (failed,) = report["failed"]
    assert failed["source"] == "accel_bias_z" and "left its domain" in failed["reason"]
    assert not report["sources"][1]["failure"]
    header, line = done.stderr.strip().splitlines()
    assert header.startswith("ins-errors: 1 of 2 validity sweeps failed")
    assert line.startswith("  accel_bias_z on the static motion: ")

    _did_not_run(_ins_errors(tmp_path, *VALIDITY, "--sorce", "accel_bias_z"), "--sorce")
    _did_not_run(_ins_errors(tmp_path, *VALIDITY, "-s", "accel_bias_q"),
                 "unknown source", "'accel_bias_q'")
    assert list(tmp_path.iterdir()) == []


def test_the_readme_lists_status_3_apart_from_2():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = " ".join(readme.split("Exit status of every command", 1)[1]
                       .split("python -m ins_errors", 1)[0].split())
    two = section.split("* **2**", 1)[1].split("* **", 1)[0]
    three = section.split("* **3**", 1)[1].split("* **", 1)[0]
    assert "bad input" in two and "failed" not in two, two
    assert "sweep" in three and "validity" in three and "failed" in three, three


@pytest.mark.parametrize("command", ["sweep", "validity"])
def test_the_help_says_failed_points_exit_3_and_bad_input_2(command, capsys):
    from ins_errors.cli import main

    with pytest.raises(SystemExit) as stop:
        main([command, "--help"])
    assert stop.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "exits with status 3 (bad input to the command itself exits 2" in text, text
