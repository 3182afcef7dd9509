"""`play`, `evolve`, `random-search`, `evolve --resume` and the API's rcss runs against real rcssservers:
servers the user runs (`--server HOST:PORT`; here started by the tests), a server killed in the middle of
a run, and a run whose soccer-lab process is killed and then resumed."""

from __future__ import annotations

import csv
import json
import re
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.soccer.rcss.servers import ServerPool
from tests.app.api_client import api_client, wait_for
from tests.rcss.conftest import CHASER
from tests.rcss.real_server import kill, rcssserver_children, wait_until_gone

SMALL_RUN = ["--population-size", "4", "--generations", "2", "--max-length", "16", "--max-ticks", "80", "--seed", "3"]
SOCCER_LAB = Path(sys.executable).with_name("soccer-lab")  # the installed script, run as a user would


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def generations(folder: Path) -> list[int]:
    with (folder / "statistics.csv").open(newline="") as handle:
        return [int(row["generation"]) for row in csv.DictReader(handle)]


def servers_option(pool: ServerPool) -> list[str]:
    return [part for address in pool.addresses for part in ("--server", address)]


@pytest.fixture
def striker(tmp_path) -> Path:
    path = tmp_path / "striker.rules"
    path.write_text(CHASER)
    return path


def started_pids(output: str) -> list[int]:
    """The PIDs in the command's "started N rcssservers: HOST:PORT (pid P), ..." line."""
    (line,) = [line for line in output.splitlines() if line.startswith("started ")]
    return [int(part.split(")")[0]) for part in line.split("(pid ")[1:]]


def test_play_on_two_servers_soccer_lab_starts_and_stops(rcssserver, striker):
    result = run("play", striker, "--env", "rcss", "--rcssserver", rcssserver, "--servers", "2", "--games", "2",
                 "--max-ticks", "300", "--skills", "assisted")
    assert result.exit_code == 0, result.output
    pids = started_pids(result.output)
    assert len(pids) == 2 and wait_until_gone(pids, seconds=0.5) == []  # stopped before the command returned
    rows = [line.split() for line in result.output.splitlines() if line.split()[:1] in (["1"], ["2"])]
    assert [row[:2] for row in rows] == [["1", "0"], ["2", "1"]]
    assert all(int(row[2]) >= 1 and int(row[4]) == 300 for row in rows)  # goals, ticks


def test_without_a_server_or_an_executable_says_how_to_give_one(striker, monkeypatch, tmp_path):
    monkeypatch.delenv("RCSSSERVER", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    result = run("play", striker, "--env", "rcss")
    assert result.exit_code == 2
    assert result.output.strip() == ("error: no rcssserver: 'rcssserver' is not on PATH: give --rcssserver PATH "
                                     "(see docs/robocup/index.md), or --server HOST:PORT for a server you run")


def test_play_on_two_servers_the_user_runs(start_servers, striker):
    pool = start_servers(2)
    result = run("play", striker, "--env", "rcss", *servers_option(pool), "--games", "2", "--max-ticks", "300",
                 "--skills", "assisted")
    assert result.exit_code == 0, result.output
    rows = [line.split() for line in result.output.splitlines()[1:3]]
    assert [row[:2] for row in rows] == [["1", "0"], ["2", "1"]]
    assert all(int(row[2]) >= 1 and int(row[4]) == 300 for row in rows)  # goals, ticks


@pytest.fixture(scope="module")
def evolved(rcssserver, tmp_path_factory) -> tuple[Path, object, list[str]]:
    folder = tmp_path_factory.mktemp("live") / "run"
    with ServerPool(rcssserver, 2) as pool:
        result = run("evolve", "--env", "rcss", *servers_option(pool), *SMALL_RUN, "--out", folder)
        return folder, result, pool.addresses


def test_evolve_on_two_servers(evolved):
    folder, result, addresses = evolved
    assert result.exit_code == 0, result.output
    assert generations(folder) == [0, 1]
    manifest = json.loads((folder / "run.json").read_text())
    assert manifest["env"] == "rcss" and manifest["servers"] == addresses and manifest["trial"]["max_ticks"] == 80
    with (folder / "statistics.csv").open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert all(0.0 < float(row["best"]) <= float(row["mean"]) <= 1.0 for row in rows)
    assert "best fitness" in result.output and (folder / "best.rules").is_file()


def test_evolve_on_two_servers_soccer_lab_starts_and_stops(rcssserver, tmp_path):
    folder = tmp_path / "run"
    result = run("evolve", "--env", "rcss", "--rcssserver", rcssserver, "--servers", "2", *SMALL_RUN, "--out", folder)
    assert result.exit_code == 0, result.output
    pids = started_pids(result.output)
    assert len(pids) == 2 and wait_until_gone(pids, seconds=0.5) == []
    assert generations(folder) == [0, 1]
    manifest = json.loads((folder / "run.json").read_text())
    assert (manifest["servers"], manifest["start_servers"]) == ([], 2) and "rcssserver" not in manifest
    assert f"soccer-lab play {folder / 'best.rules'} --env rcss --rcssserver {rcssserver} --servers 2" in result.output


def test_random_search_on_a_server_soccer_lab_starts(rcssserver, tmp_path, monkeypatch):
    monkeypatch.setenv("RCSSSERVER", str(rcssserver))  # found there, as on PATH: no option needed
    folder = tmp_path / "random"
    result = run("random-search", "--env", "rcss", "--population-size", "3", "--generations", "1", "--max-ticks", "60",
                 "--out", folder)
    assert result.exit_code == 0, result.output
    assert len(started_pids(result.output)) == 1
    assert generations(folder) == [0]
    assert json.loads((folder / "run.json").read_text())["algorithm"] == "random-search"


def test_a_server_killed_mid_run_is_one_line_and_the_finished_generations_stay(start_servers, tmp_path):
    pool = start_servers()
    folder = tmp_path / "run"

    def kill_after_first_generation() -> None:
        wait_for(lambda: (folder / "checkpoint").exists(), timeout=120, what="generation 0")
        kill(pool.servers[0])

    threading.Thread(target=kill_after_first_generation, daemon=True).start()
    result = run("evolve", "--env", "rcss", *servers_option(pool), *SMALL_RUN[:2], "--generations", "20",
                 *SMALL_RUN[4:], "--out", folder)
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    error = result.output.strip().splitlines()[-1]  # after the progress bar: one line
    # the player or the trainer finds out first: its cycle timed out, or its port was closed
    assert re.match(rf"error: (player|trainer): rcssserver at {pool.addresses[0]}\b", error), error
    assert error.endswith(f"(did the server quit?); continue with: soccer-lab evolve --resume {folder}")
    kept = generations(folder)
    assert kept and kept == list(range(len(kept))) and len(kept) < 20

    again = start_servers()  # resume on another server
    resumed = run("evolve", "--resume", folder, *servers_option(again))
    assert resumed.exit_code == 0, resumed.output
    assert generations(folder) == list(range(20))


def test_a_killed_run_leaves_no_server_and_resumes_to_its_end(rcssserver, tmp_path):
    folder, log = tmp_path / "run", tmp_path / "stderr.txt"
    with log.open("w") as stderr:
        process = subprocess.Popen([str(SOCCER_LAB), "evolve", "--env", "rcss", "--rcssserver", str(rcssserver),
                                    *SMALL_RUN[:2], "--generations", "4", *SMALL_RUN[4:], "--out", str(folder)],
                                   stdout=subprocess.DEVNULL, stderr=stderr)
    try:
        wait_for(lambda: (folder / "checkpoint").exists() or process.poll() is not None, timeout=120,
                 what="generation 0")
        process.send_signal(signal.SIGKILL)  # no clean-up of its own: the kernel ends its servers
    finally:
        process.wait(30)
    assert process.returncode == -signal.SIGKILL, log.read_text()
    pids = started_pids(log.read_text())
    assert len(pids) == 1 and wait_until_gone(pids) == []
    kept = generations(folder)
    assert 1 <= len(kept) < 4
    resumed = run("evolve", "--resume", folder, "--rcssserver", rcssserver)  # a new server, as many as before
    assert resumed.exit_code == 0, resumed.output
    assert f"resuming {folder} after generation {kept[-1]}" in resumed.output
    assert generations(folder) == [0, 1, 2, 3]


def ended(client, run_id: int) -> dict | None:
    record = client.get(f"/api/runs/{run_id}").json()
    return record if record["status"] != "running" else None


def test_an_api_run_on_two_servers_it_starts_finishes_and_stops_them(rcssserver, tmp_path):
    before = rcssserver_children()
    with api_client(tmp_path, rcssserver=rcssserver) as client:
        response = client.post("/api/runs", json={
            "env": "rcss", "start_servers": 2, "trial": {"max_ticks": 80},
            "ga": {"population_size": 4, "max_generations": 2, "max_length": 16, "seed": 3, "workers": 1}})
        assert response.status_code == 201, response.json()
        assert response.json()["config"]["start_servers"] == 2
        done = wait_for(lambda: ended(client, response.json()["id"]), timeout=180, what="the run to end")
        assert done["status"] == "finished" and done["error"] is None and done["generations"] == 2
    assert rcssserver_children() == before


def test_an_api_run_on_two_servers_the_user_runs_finishes(start_servers, tmp_path):
    pool = start_servers(2)
    with api_client(tmp_path) as client:
        response = client.post("/api/runs", json={
            "env": "rcss", "servers": pool.addresses, "trial": {"max_ticks": 80},
            "ga": {"population_size": 4, "max_generations": 2, "max_length": 16, "seed": 3, "workers": 1}})
        assert response.status_code == 201, response.json()
        done = wait_for(lambda: ended(client, response.json()["id"]), timeout=180, what="the run to end")
        assert done["status"] == "finished" and done["error"] is None and done["generations"] == 2
        assert 0.0 < done["best_fitness"] <= 1.0
        statistics = client.get(f"/api/runs/{done['id']}/statistics").json()
        assert [row["generation"] for row in statistics] == [0, 1]

