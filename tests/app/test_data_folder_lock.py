"""One server per data folder (issue 36): a second serve on a folder in use refuses in one line naming the
first (PID, address) and leaves its running run alone; a folder whose serve was SIGKILLed is usable at once."""

from __future__ import annotations

import json
import signal
import subprocess
import sys

import pytest

from soccer_lab.app.paths import LOCK_FILE, DataFolderInUse, DataFolderLock
from tests.app.test_serve_lifecycle import Serve, free_port, run_status, wait_for

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="flock and the serve lifecycle are tested on Linux")
# generation 0 lasts seconds: the second serve starts while it runs
LONG_GA = {"population_size": 3000, "max_generations": 50, "seed": 3, "workers": 1}


def serve_arguments(data_dir, port: int, ui_port: int) -> list[str]:
    return [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", str(data_dir),
            "--port", str(port), "--ui-port", str(ui_port)]


def ports() -> dict[str, int]:
    return {"--port": free_port(), "--ui-port": free_port()}


def test_second_lock_on_a_folder_names_the_holder(tmp_path):
    with DataFolderLock(tmp_path, "http://127.0.0.1:1234"):
        with pytest.raises(DataFolderInUse) as refused:
            DataFolderLock(tmp_path, "http://127.0.0.1:5678")
        assert "http://127.0.0.1:1234" in str(refused.value) and "PID" in str(refused.value)
        assert "\n" not in str(refused.value)
    with DataFolderLock(tmp_path, "http://127.0.0.1:5678"):  # released: usable again
        assert json.loads((tmp_path / LOCK_FILE).read_text())["address"] == "http://127.0.0.1:5678"


def test_second_serve_on_a_folder_in_use_refuses_and_leaves_its_running_run_alone(tmp_path):
    first = Serve(tmp_path, ports())
    try:
        run = first.post("/api/runs", json={"name": "long", "ga": LONG_GA})
        assert run.status_code == 201, run.text
        run_id = run.json()["id"]
        wait_for(lambda: first.get(f"/api/runs/{run_id}").json()["status"] == "running", what="the run to start")
        second = subprocess.run(serve_arguments(tmp_path, free_port(), free_port()), capture_output=True,
                                text=True, timeout=120)
        assert second.returncode != 0
        lines = second.stderr.strip().splitlines()
        assert len(lines) == 1, second.stderr
        assert f"PID {first.process.pid}" in lines[0] and first.api in lines[0], lines[0]
        # the probe's fault: the second serve marked the running run interrupted, so a resume ran it twice
        assert run_status(tmp_path, run_id) == "running"
        assert first.get(f"/api/runs/{run_id}").json()["status"] == "running"
    finally:
        first.stop()


def test_folder_of_a_sigkilled_serve_is_usable_at_once(tmp_path):
    first = Serve(tmp_path, ports())
    first.process.send_signal(signal.SIGKILL)
    first.process.wait(30)
    again = Serve(tmp_path, ports())  # at once: no stale lock to wait out or remove
    try:
        assert again.get("/api/server").status_code == 200
        assert json.loads((tmp_path / LOCK_FILE).read_text())["pid"] == again.process.pid
    finally:
        again.process.send_signal(signal.SIGTERM)
        again.process.wait(30)
        again.stop()
