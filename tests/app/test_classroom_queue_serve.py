"""The run queue in the real `soccer-lab serve --class` (issue 35): more pupils press Start than the machine
runs at once, every Start is answered 201, the runs the cores cannot take yet wait as `queued` with their
place, each run plays in a game process of serve's, and every one finishes with its own seed."""

from __future__ import annotations

import re
import time

import httpx
import psutil

from tests.app.test_classroom_serve import ADDRESS, CODE, Served, pytestmark  # noqa: F401 - the module's skip

RUN = {"ga": {"population_size": 20, "max_generations": 3}, "game": {"max_ticks": 300}}


def pupil(served: Served, name: str) -> httpx.Client:
    client = httpx.Client(base_url=served.url, timeout=60, headers={"X-Soccer-Lab": "1"})
    assert client.post("/api/class/join", json={"code": CODE, "name": name}).status_code == 200
    return client


def test_every_start_is_honoured_in_turn_on_serve_s_game_processes(tmp_path):
    served = Served(tmp_path)
    try:
        at_once = int(served._wait_for(r"  runs\s+(\d+) at once, the others queued in turn").group(1))
        games = psutil.Process(served.process.pid).children(recursive=True)
        assert len(games) >= at_once  # the game processes, started with serve
        pupils = [pupil(served, f"Pupil {index}") for index in range(at_once + 2)]
        started = [client.post("/api/runs", json=RUN) for client in pupils]
        assert [answer.status_code for answer in started] == [201] * len(pupils)
        statuses = [answer.json()["status"] for answer in started]
        assert statuses.count("queued") == 2 and statuses[:at_once] == ["running"] * at_once
        assert [answer.json()["queue"]["position"] for answer in started[at_once:]] == [1, 2]
        runs = [answer.json()["id"] for answer in started]
        deadline = time.monotonic() + 600
        while time.monotonic() < deadline:
            records = [client.get(f"/api/runs/{run}").json() for client, run in zip(pupils, runs)]
            if all(record["status"] not in ("queued", "running") for record in records):
                break
            time.sleep(0.5)
        assert [record["status"] for record in records] == ["finished"] * len(pupils), records
        seeds = {record["config"]["ga"]["seed"] for record in records}
        assert len(seeds) == len(pupils)  # every pupil breeds their own players
        assert all(re.search(r"seed \d+$", record["name"]) for record in records)
    finally:
        served.stop()
