"""One server per data folder (issue 36): a second serve on a folder in use refuses in one line naming the
first (PID, address) and leaves its running run alone; a folder whose serve was SIGKILLed is usable at once.
One process per run: `evolve --resume` of a run a serve plays refuses in one line naming it; a run whose
player was SIGKILLed is resumable at once."""

from __future__ import annotations

import json
import signal
import subprocess
import sys

import pytest

from soccer_lab.app.paths import LOCK_FILE, DataFolderInUse, DataFolderLock
from soccer_lab.app.runs.lease import RunLease
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


# a run that plays generation after generation for minutes: its checkpoint is there within seconds
ENDLESS_GA = {"population_size": 20, "max_generations": 100_000, "seed": 3, "workers": 1}


def test_evolve_resume_of_a_run_a_serve_plays_refuses_naming_the_serve(tmp_path):
    """The probe's fault by another door: `evolve --resume` on the serve's run folder ran the run a second time,
    both processes writing its checkpoint and statistics."""
    first = Serve(tmp_path, ports())
    try:
        run = first.post("/api/runs", json={"ga": ENDLESS_GA, "game": {"max_ticks": 100}})
        assert run.status_code == 201, run.text
        run_id = run.json()["id"]
        wait_for(lambda: len(first.get(f"/api/runs/{run_id}/statistics").json()) >= 2, what="two generations")
        folder = tmp_path / "runs" / str(run_id)
        assert (folder / "checkpoint").is_file()
        resume = subprocess.run([sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "evolve",
                                 "--resume", str(folder)], capture_output=True, text=True, timeout=300)
        assert resume.returncode == 2, resume.stderr
        lines = resume.stderr.strip().splitlines()
        assert len(lines) == 1 and f"soccer-lab serve (PID {first.process.pid})" in lines[0], resume.stderr
        assert first.get(f"/api/runs/{run_id}").json()["status"] == "running"
        generations = [row["generation"] for row in first.get(f"/api/runs/{run_id}/statistics").json()]
        assert generations == list(range(len(generations)))  # no generation played twice
    finally:
        first.stop()


def test_a_run_leased_by_a_sigkilled_process_is_resumable_at_once(tmp_path):
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from soccer_lab.app.runs.lease import RunLease; "
                               "lease = RunLease(sys.argv[1]); print('held', flush=True); time.sleep(300)",
                               str(tmp_path), "evolve"], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(DataFolderInUse) as refused:
            RunLease(tmp_path)
        assert f"soccer-lab evolve (PID {holder.pid})" in str(refused.value), str(refused.value)
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait(30)
    with RunLease(tmp_path):  # the kernel released it with the process
        pass
