"""A sweep on a real multi-process Dask cluster survives a worker killed mid-sweep.

The cluster is started as a user would start one on several machines: a
``dask scheduler`` process and two ``dask worker`` processes (no nanny, so a
killed worker stays dead), all on 127.0.0.1 with free ports. One worker is
killed (SIGKILL) while it runs a chunk; the sweep must still return every point,
equal to a serial run. The processes are always stopped at the end.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from presliding.sweep import sweep

ROOT = Path(__file__).resolve().parents[2]
GRID = {"ratio": np.linspace(0.1, 0.9, 7), "velocity": np.linspace(-2.0, 3.0, 11)}
#: Seconds each chunk takes, so that a worker is surely busy when it is killed.
CHUNK_SECONDS = 0.25


def surface(ratio, velocity):
    return np.sin(3 * ratio) * np.exp(-0.1 * velocity**2) + ratio * velocity


def slow_surface(ratio, velocity):
    """`surface`, taking CHUNK_SECONDS per chunk (module level: importable by the workers)."""
    time.sleep(CHUNK_SECONDS)
    return surface(ratio, velocity)


def _warm() -> bool:
    """Run on each worker: importing this module imports presliding too."""
    import presliding.sweep  # noqa: F401

    return True


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _wait_for(predicate, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise TimeoutError(f"{what} within {timeout:g} s")
        time.sleep(0.05)


class Cluster:
    """``dask scheduler`` and ``dask worker`` processes on 127.0.0.1, stopped on exit."""

    def __init__(self, folder: Path, n_workers: int = 2) -> None:
        self.folder = folder
        self.n_workers = n_workers
        self.procs: dict[str, subprocess.Popen] = {}
        self.address = ""
        self.env = {
            **os.environ,
            "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
            "DASK_DISTRIBUTED__WORKER__DAEMON": "False",
        }

    def _start(self, name: str, *args: str) -> subprocess.Popen:
        log = open(self.folder / f"{name}.log", "wb")  # noqa: SIM115 - closed with the process
        proc = subprocess.Popen(
            [sys.executable, "-m", "dask", *args],
            stdout=log, stderr=subprocess.STDOUT, env=self.env, cwd=self.folder,
            start_new_session=True,
        )  # fmt: skip
        log.close()
        self.procs[name] = proc
        return proc

    def __enter__(self) -> Cluster:
        try:
            for attempt in range(3):  # a free port can be taken before the scheduler binds it
                port, info = _free_port(), self.folder / f"scheduler-{attempt}.json"
                proc = self._start(
                    "scheduler", "scheduler", "--host", "127.0.0.1", "--port", str(port),
                    "--no-dashboard", "--scheduler-file", str(info),
                )  # fmt: skip
                _wait_for(lambda: info.exists() or proc.poll() is not None, 60, "a scheduler")  # noqa: B023
                if proc.poll() is None:
                    self.address = json.loads(info.read_text())["address"]
                    break
            else:
                raise RuntimeError("the scheduler did not start: " + self.log("scheduler"))
            for i in range(self.n_workers):
                self._start(
                    f"worker-{i}", "worker", self.address, "--host", "127.0.0.1",
                    "--nthreads", "1", "--no-nanny", "--no-dashboard", "--name", f"worker-{i}",
                    "--death-timeout", "60",
                )  # fmt: skip
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def log(self, name: str) -> str:
        path = self.folder / f"{name}.log"
        return path.read_text(errors="replace")[-3000:] if path.exists() else ""

    def kill(self, name: str) -> None:
        self.procs[name].send_signal(signal.SIGKILL)
        self.procs[name].wait(timeout=30)

    def stop(self) -> None:
        """Workers first, then the scheduler: SIGTERM, and SIGKILL after 10 s."""
        names = sorted(self.procs, key=lambda n: n == "scheduler")
        for name in names:
            if self.procs[name].poll() is None:
                self.procs[name].terminate()
        for name in names:
            try:
                self.procs[name].wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.procs[name].kill()
                self.procs[name].wait(timeout=10)


def test_a_worker_killed_mid_sweep_leaves_a_complete_result(tmp_path):
    distributed = pytest.importorskip("distributed")
    serial = sweep(surface, GRID, n_workers=1, chunk_size=7)
    with Cluster(tmp_path) as cluster:
        client = distributed.Client(cluster.address, set_as_default=False, timeout=60)
        try:
            client.wait_for_workers(2, timeout=90)
            # workers that have imported presliding and this module, as a running cluster has
            assert set(client.run(_warm).values()) == {True}
            names = {w["name"]: a for a, w in client.scheduler_info()["workers"].items()}
            victim = names["worker-1"]
            outcome: dict[str, object] = {}

            def run() -> None:
                try:
                    outcome["result"] = sweep(slow_surface, GRID, client, chunk_size=7, retries=2)
                except BaseException as exc:  # reported below
                    outcome["error"] = exc

            thread = threading.Thread(target=run)
            thread.start()
            # kill the worker while it runs a chunk, with other chunks still to come
            _wait_for(lambda: client.processing().get(victim), 60, "a chunk on the worker")
            time.sleep(CHUNK_SECONDS / 2)
            cluster.kill("worker-1")
            thread.join(timeout=180)
            assert not thread.is_alive(), "the sweep did not finish"
            remaining = client.nthreads()
        finally:
            client.close(timeout=30)
    assert "error" not in outcome, outcome.get("error")
    res = outcome["result"]
    assert victim not in remaining and len(remaining) == 1  # the worker really died
    assert res.backend == "dask" and res.n_chunks == 11
    assert res.status == "ok" and not res.failed.any(), res.message
    np.testing.assert_array_equal(res.values, serial.values)
