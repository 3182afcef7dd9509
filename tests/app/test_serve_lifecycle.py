"""`soccer-lab serve` as an operator meets it: SIGTERM (or Ctrl+C) mid-generation marks the running run
interrupted and exits within seconds; after `kill -9` nothing it started is left behind, and a new serve
on the same ports starts and finds the run resumable."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import httpx
import psutil
import pytest

from soccer_lab.app.paths import DATABASE_FILE

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="children die with serve through prctl (Linux)")
# Generations of a few seconds each: a signal lands inside one however fast the machine is.
BIG_GA = {"population_size": 3000, "max_generations": 50, "seed": 3, "workers": 2}  # serve's children: the workers
EXIT_WITHIN = 10.0  # seconds; the target is 3 (benchmarks/stop_latency.py measures it): this is a sanity bound


def free_port() -> int:
    import socket

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wait_for(condition, timeout: float = 120.0, what: str = "condition"):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := condition():
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


class Serve:
    """A `soccer-lab serve` process on given ports and data folder."""

    def __init__(self, data_dir: Path, ports: dict[str, int]):
        arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", str(data_dir)]
        for option, port in ports.items():
            arguments += [option, str(port)]
        self.api = f"http://127.0.0.1:{ports['--port']}"
        self.process = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        wait_for(lambda: self._answers() or self.process.poll() is not None, what="serve to answer")
        assert self.process.poll() is None, self.process.stdout.read()

    def _answers(self) -> bool:
        try:
            return httpx.get(f"{self.api}/api/server", timeout=2).status_code == 200
        except httpx.HTTPError:
            return False

    def post(self, path: str, **kwargs) -> httpx.Response:
        return httpx.post(f"{self.api}{path}", headers={"Content-Type": "application/json"}, timeout=30, **kwargs)

    def get(self, path: str) -> httpx.Response:
        return httpx.get(f"{self.api}{path}", timeout=30)

    def start_run_mid_generation(self) -> int:
        run = self.post("/api/runs", json={"name": "big", "ga": BIG_GA})
        assert run.status_code == 201, run.text
        run_id = run.json()["id"]
        wait_for(lambda: (self.get(f"/api/runs/{run_id}").json().get("progress") or {}).get("evaluated"),
                 what="the first chunk of generation 0")
        return run_id

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(30)


def run_status(data_dir: Path, run_id: int) -> str:
    with sqlite3.connect(data_dir / DATABASE_FILE) as connection:
        return connection.execute("SELECT status FROM runs WHERE id = ?", (run_id,)).fetchone()[0]


@pytest.fixture
def ports():
    return {"--port": free_port(), "--ui-port": free_port()}


def test_sigterm_mid_generation_marks_the_run_interrupted_and_exits_quickly(tmp_path, ports):
    serve = Serve(tmp_path, ports)
    try:
        run_id = serve.start_run_mid_generation()
        sent = time.monotonic()
        serve.process.send_signal(signal.SIGTERM)
        serve.process.wait(60)
        took = time.monotonic() - sent
    finally:
        serve.stop()
    assert serve.process.returncode == 0, serve.process.stdout.read()
    assert run_status(tmp_path, run_id) == "interrupted"
    assert took < EXIT_WITHIN, f"serve took {took:.1f} s to exit after SIGTERM"


def test_after_sigkill_nothing_is_left_and_serve_restarts_on_the_same_ports(tmp_path, ports):
    serve = Serve(tmp_path, ports)
    try:
        run_id = serve.start_run_mid_generation()
        children = psutil.Process(serve.process.pid).children(recursive=True)
        assert children, "serve started no child (the run's worker processes)"
        serve.process.send_signal(signal.SIGKILL)
        serve.process.wait(30)
        gone, alive = psutil.wait_procs(children, timeout=15)
        assert not alive, [(p.pid, p.name()) for p in alive]
    finally:
        serve.stop()
    again = Serve(tmp_path, ports)  # the same ports: free again
    try:
        record = again.get(f"/api/runs/{run_id}").json()
        assert record["status"] == "interrupted" and record["resumable"]
        assert again.get("/api/server").json()["viewer"] == f"http://127.0.0.1:{ports['--port']}/viewer/"
    finally:
        again.process.send_signal(signal.SIGTERM)
        again.process.wait(30)
        again.stop()
