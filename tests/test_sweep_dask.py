"""`lagcli sweep --scheduler`: the same summary from a Dask cluster on the loopback
interface (a scheduler and two worker processes started and stopped here), and no run
lost when a worker is killed mid-sweep (Dask runs its tasks again elsewhere)."""
from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import lagcli

from conftest import spec_path

pytest.importorskip("distributed")
pytestmark = pytest.mark.skipif(__import__("shutil").which("cc") is None,
                                reason="no C compiler (cc): lagcli sweep runs the compiled driver")
DASK = Path(sys.executable).with_name("dask")
START_TIMEOUT = 120.0      # a hang guard, not a timing assertion


def _start(args, log: Path, env) -> subprocess.Popen:
    return subprocess.Popen([str(DASK), *args], stdout=log.open("w"), stderr=subprocess.STDOUT, env=env,
                            start_new_session=True)


def _stop(proc: subprocess.Popen) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGTERM)
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """(address, [worker processes], log folder) of a scheduler and two single-threaded workers."""
    if not DASK.exists():
        pytest.skip("the dask command is not installed")
    base = tmp_path_factory.mktemp("dask")
    env = {**os.environ, "XDG_CACHE_HOME": str(base / "worker-cache")}
    info = base / "scheduler.json"
    procs = [_start(["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                     "--scheduler-file", str(info)], base / "scheduler.log", env)]
    try:
        address = _wait_for(lambda: info.exists() and json.loads(info.read_text() or "{}").get("address"))
        workers = [_start(["worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard",
                           "--host", "127.0.0.1", "--name", f"w{k}"], base / f"worker{k}.log", env)
                   for k in range(2)]
        procs += workers
        from distributed import Client

        with Client(address, timeout="60s", set_as_default=False) as client:
            client.wait_for_workers(2, timeout=START_TIMEOUT)
        yield address, workers, base
    finally:
        for proc in reversed(procs):
            _stop(proc)


def _wait_for(condition):
    deadline = time.monotonic() + START_TIMEOUT
    while time.monotonic() < deadline:
        with contextlib.suppress(ValueError, OSError):
            value = condition()
            if value:
                return value
        time.sleep(0.2)
    raise RuntimeError("the Dask scheduler did not start")


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


GRID = {"theta1": (-3, 3, 5), "theta2": (-3, 3, 4)}


def test_dask_sweep_equals_the_local_sweep_row_for_row(cluster, tmp_path):
    address, _, _ = cluster
    system = lagcli.load(spec_path("double_pendulum"))
    options = dict(t_end=2.0, exceed={"theta2": 3.141592653589793})
    local = system.sweep(grid=GRID, output=str(tmp_path / "local.csv"), **options)
    remote = system.sweep(grid=GRID, output=str(tmp_path / "dask.csv"), scheduler=address, **options)
    assert (tmp_path / "local.csv").read_bytes() == (tmp_path / "dask.csv").read_bytes()
    assert remote.csv == local.csv and len(remote.csv.splitlines()) == 21


def test_killing_a_worker_mid_sweep_loses_no_run(cluster, tmp_path):
    address, workers, logs = cluster
    system = lagcli.load(spec_path("double_pendulum"))
    grid = {"theta1": (-3, 3, 8), "theta2": (-3, 3, 5)}
    local = system.sweep(grid=grid, t_end=3.0, workers=2, output=str(tmp_path / "local.csv"))
    killed = []

    @contextlib.contextmanager
    def kill_after_first_chunk(total):
        def update(done):
            if not killed:
                os.killpg(workers[0].pid, signal.SIGKILL)
                killed.append(done)
        yield update

    from lagcli.sweep import SweepOptions, make_plan, sweep
    from lagcli.sweep.driver import number

    plan = make_plan([f"{k}={number(a)}:{number(b)}:{n}" for k, (a, b, n) in grid.items()])
    result = sweep(system, plan, SweepOptions(t_end=3.0, workers=2, scheduler=address,
                                              output=str(tmp_path / "dask.csv")),
                   progress=kill_after_first_chunk)
    assert killed and killed[0] < 40 and workers[0].wait(timeout=30) is not None
    assert result.csv == local.csv
    assert "name: w0" in _wait_for(lambda: "Remove worker" in (logs / "scheduler.log").read_text()
                                   and (logs / "scheduler.log").read_text())
    assert (tmp_path / "dask.csv").read_bytes() == (tmp_path / "local.csv").read_bytes()
