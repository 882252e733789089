"""Runs on a local Dask cluster of 2 workers give the single-process results bit for bit,
also when a worker is killed in the middle of a sweep.

The cluster is started with docs/cluster.md's own commands (``dask scheduler``, ``dask
worker``) on 127.0.0.1 only and is shut down at the end of the module.
"""

from __future__ import annotations

import contextlib
import json
import os
import shlex
import signal
import socket
import subprocess
import sys
import textwrap
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")
pytest.importorskip("zarr")

from ins_errors.analysis import covariance as cv
from ins_errors.analysis import monte_carlo as mc
from ins_errors.analysis import sweep as sw
from ins_errors.analysis import sweep_report as sr
from ins_errors.numeric import trajectories as tr
from ins_errors.scenario import load_scenario
from tests.helpers import QUIET_DASK

SCENARIO = """
title = "great circle, drawn biases"
model = "orthodromic"
[motion]
kind = "great-circle"
latitude = "50 deg"
heading = "30 deg"
speed = "250 m/s"
[run]
duration = "10 min"
step = "1 s"
record = "60 s"
refined = false
[[case]]
gyro_drift_x = "0.01 deg/h"
[sweep]
latitude = ["20 deg", "45 deg"]
heading = ["0 deg", "60 deg"]
draws = 2
seed = 11
[sweep.random]
accel_bias_x = "100 ug"
accel_bias_y = "100 ug"
"""


ROOT = Path(__file__).resolve().parent.parent
CLUSTER_PAGE = (ROOT / "docs" / "cluster.md").read_text(encoding="utf-8")


def cluster_commands() -> list[str]:
    """docs/cluster.md's cluster recipe: scheduler, worker and sweep lines."""
    section = CLUSTER_PAGE.split("On a cluster, with Dask's own commands", 1)[1]
    block = section.split("```text\n", 1)[1].split("```", 1)[0]
    return [line.split(" #")[0].strip() for line in block.splitlines() if line.strip()]


@dataclass
class Cluster:
    scheduler_address: str
    sweep: list[str]


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def listening_addresses(started) -> set[str]:
    """Addresses the started processes and their children listen on."""
    import psutil

    found = set()
    for process in started:
        root = psutil.Process(process.pid)
        for member in [root, *root.children(recursive=True)]:
            for connection in member.net_connections(kind="inet"):
                if connection.status == psutil.CONN_LISTEN:
                    found.add(connection.laddr.ip)
    return found


@pytest.fixture(scope="module")
def cluster():
    """A scheduler and a worker of 2 processes, started with docs/cluster.md's commands (on
    127.0.0.1 and a free port) and stopped at the end of the module."""
    from distributed import Client

    dask = Path(sys.executable).with_name("dask")
    if not dask.exists():
        pytest.skip("the dask command is not installed next to this Python")
    scheduler, worker, sweep = cluster_commands()
    port = _free_port()
    address = f"127.0.0.1:{port}"
    local = ["--host", "127.0.0.1", "--dashboard-address", "127.0.0.1:0"]
    assert scheduler.startswith("dask scheduler") and worker.startswith("dask worker")
    commands = [
        [str(dask), *shlex.split(scheduler.replace("8786", str(port)))[1:], *local],
        [str(dask), *shlex.split(worker.replace("SCHEDULER-HOST:8786", address))[1:], *local],
    ]
    started = []
    try:
        for command in commands:   # the worker retries until the scheduler listens
            started.append(subprocess.Popen(command, stdout=subprocess.DEVNULL,
                                            stderr=subprocess.DEVNULL,
                                            start_new_session=True,
                                            env={**os.environ, **QUIET_DASK}))
        deadline = time.monotonic() + 60
        while True:
            try:
                with Client(f"tcp://{address}", timeout="5s") as client:
                    client.wait_for_workers(2, timeout=60)
                break
            except OSError:
                if time.monotonic() > deadline or started[0].poll() is not None:
                    raise
                time.sleep(0.5)
        assert listening_addresses(started) == {"127.0.0.1"}
        yield Cluster(f"tcp://{address}",
                      shlex.split(sweep.replace("SCHEDULER-HOST:8786", address))[1:])
    finally:
        for process in reversed(started):    # worker first, then the scheduler
            with contextlib.suppress(ProcessLookupError):
                os.killpg(process.pid, signal.SIGTERM)
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()


def worker_pids(local) -> dict[str, int]:
    """Process id of every worker (through a short-lived client)."""
    from distributed import Client

    with Client(local.scheduler_address, timeout="10s") as client:
        return client.run(os.getpid)


@pytest.fixture(scope="module")
def scenario(tmp_path_factory):
    path = tmp_path_factory.mktemp("sweep") / "s.toml"
    path.write_text(textwrap.dedent(SCENARIO))
    return load_scenario(path)


@pytest.fixture(scope="module")
def serial(scenario, tmp_path_factory):
    """The reference: every point in this process."""
    store = tmp_path_factory.mktemp("serial") / "serial.zarr"
    return sw.run_sweep(scenario, store, engine="serial").dataset


def same(a, b) -> None:
    assert sorted(a.data_vars) == sorted(b.data_vars)
    for name in a.data_vars:
        if a[name].dtype.kind in "fiu":
            assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name
        else:  # text (failure reasons): another string type from NetCDF than from Zarr
            assert list(map(str, a[name].values)) == list(map(str, b[name].values)), name
    assert int(a["done"].sum()) == a.sizes["point"]


def test_monte_carlo_of_200_draws_on_two_workers_is_bit_identical(cluster, orthodromic):
    local = cluster
    motion = tr.trajectory(orthodromic, tr.static_profile(np.radians(50.0)), 600.0, 1.0)
    sources = [cv.SourceStatistics("gyro_drift_y", "constant", 1e-7),
               cv.SourceStatistics("accel_bias_x", "constant", 1e-4)]
    one = mc.direct_monte_carlo(orthodromic, motion, sources, 200, seed=4, batch=25,
                                engine="serial", record_interval=60.0, progress=False)
    spread = mc.direct_monte_carlo(orthodromic, motion, sources, 200, seed=4, batch=25,
                                   scheduler=local.scheduler_address, record_interval=60.0,
                                   progress=False)
    assert np.array_equal(one.sources, spread.sources)
    assert np.array_equal(one.values, spread.values)
    # the draws are what they claim: 200 normal values of the stated 1σ
    bias = one.sources[[s.name for s in orthodromic.sources].index("accel_bias_x")]
    assert np.std(bias) == pytest.approx(1e-4, rel=4 * mc.sampling_error(200))


def test_sweep_on_two_workers_and_in_a_pool_is_bit_identical(cluster, scenario, serial,
                                                             tmp_path):
    local = cluster
    on_dask = sw.run_sweep(scenario, tmp_path / "dask.zarr",
                           scheduler=local.scheduler_address)
    assert on_dask.engine.engine == "dask" and on_dask.engine.workers == 2
    same(serial, on_dask.dataset)
    in_pool = sw.run_sweep(scenario, tmp_path / "pool.nc", engine="pool", workers=2)
    same(serial, in_pool.dataset)


def test_scheduler_named_in_the_scenario_file(cluster, tmp_path):
    path = tmp_path / "named.toml"
    path.write_text(textwrap.dedent(SCENARIO).replace(
        "draws = 2", f"scheduler = {cluster.scheduler_address!r}\ndraws = 1"))
    result = sw.run_sweep(load_scenario(path), tmp_path / "named.zarr")
    assert result.engine.where == f"Dask scheduler {cluster.scheduler_address}"
    assert result.computed == 4


def test_killed_worker_still_gives_the_complete_identical_sweep(cluster, scenario, serial,
                                                                tmp_path):
    local = cluster
    before = worker_pids(local)
    killed = []

    def kill_one(index: int) -> None:
        if not killed:
            address, pid = sorted(before.items())[0]
            os.kill(pid, signal.SIGKILL)
            killed.append(address)

    result = sw.run_sweep(scenario, tmp_path / "killed.zarr",
                          scheduler=local.scheduler_address, on_result=kill_one)
    assert killed and result.computed == result.points == 8
    same(serial, result.dataset)
    # the nanny started a fresh worker process in place of the killed one
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        after = worker_pids(local)
        if len(after) == 2 and set(after.values()) != set(before.values()):
            break
        time.sleep(0.2)
    assert len(after) == 2 and set(after.values()) != set(before.values())


def test_readme_sweep_on_the_cluster(cluster, tmp_path, monkeypatch, capsys):
    """docs/cluster.md's sweep line, run against the scheduler started from that page."""
    from ins_errors.cli import main

    os.symlink(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    assert main([*cluster.sweep, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["computed"] == data["points"] == 9 and "tcp://127.0.0.1" in data["engine"]
    assert main([*cluster.sweep, "--json"]) == 0       # again: everything read back
    again = json.loads(capsys.readouterr().out)
    assert (again["computed"], again["reused"]) == (0, 9)
    assert again["summary"] == data["summary"]


def test_validity_map_on_the_cluster_equals_one_process(cluster, orthodromic):
    from ins_errors.analysis.validity import validity_map, validity_tasks

    tasks = validity_tasks(orthodromic, ["static"], ["gyro_drift_x", "accel_bias_y"],
                           hours=1.0, step=10.0, factors=(1.0, 10.0, 100.0))
    here = validity_map(tasks, engine="serial")
    there = validity_map(tasks, scheduler=cluster.scheduler_address)
    assert [r.to_dict() for r in here] == [r.to_dict() for r in there]
    assert [r.source for r in there] == ["gyro_drift_x", "accel_bias_y"]


def test_a_point_over_the_pole_fails_alone_on_the_cluster(cluster, tmp_path):
    """On Dask as in one process: the point that reaches the pole (north from 89.5° N at
    250 m/s, about 220 s) is stored with the same reason and no data, the other runs."""
    path = tmp_path / "pole.toml"
    path.write_text(textwrap.dedent(SCENARIO).split("[sweep]")[0].replace(
        '"30 deg"', '"0 deg"') + "[sweep]\nlatitude = ['89.5 deg', '20 deg']\n")
    here = sw.run_sweep(load_scenario(path), tmp_path / "here.zarr", engine="serial")
    there = sw.run_sweep(load_scenario(path), tmp_path / "there.zarr",
                         scheduler=cluster.scheduler_address)
    assert here.failed == there.failed == [0] and there.engine.failed == 1
    assert there.engine.computed == 1
    [failed] = sr.failures(there.dataset)
    assert failed["reason"].startswith("the true motion leaves the model's domain")
    assert sr.failures(here.dataset) == [failed]
    same(here.dataset, there.dataset)
