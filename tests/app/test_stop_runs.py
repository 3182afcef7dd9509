"""Stop means stop (issue 22): the API's stop is obeyed mid-generation, generation 0 of a big population
included; the run leaves 'running', its thread ends, every finished generation stays, and a run stopped
mid-generation and resumed finishes as the uninterrupted one. Progress within a generation is served."""

from __future__ import annotations

import csv
import threading

from soccer_lab.app.runs.run import Run, RunSettings
from tests.app.api_client import SHORT_GAMES, api_client, wait_for

# Generation 0 of this population takes many seconds here: a stop obeyed only between generations would
# keep the run going long past the sanity bound below.
BIG = {"population_size": 5000, "max_generations": 5, "seed": 5}


def progress(client, run_id):
    return client.get(f"/api/runs/{run_id}").json()["progress"]


def test_a_stop_in_generation_0_of_a_big_population_is_obeyed_and_resumable(tmp_path):
    with api_client(tmp_path) as client:
        run_id = client.post("/api/runs", json={"ga": BIG}).json()["id"]
        seen = wait_for(lambda: (p := progress(client, run_id)) and p["evaluated"] and p, what="progress in gen 0")
        assert seen["generation"] == 0 and seen["population"] == BIG["population_size"]
        assert 0 < seen["evaluated"] < BIG["population_size"]
        stopped = client.post(f"/api/runs/{run_id}/stop")  # answers once the run has ended (at most 10 s)
        assert stopped.status_code == 200
        record = stopped.json()
        assert record["status"] == "stopped" and record["resumable"]  # left 'running' before the answer
        assert record["generations"] == 0 and record["progress"] is None
        assert not client.app.state.runs.is_active(run_id)  # its thread has ended

        resumed = client.post(f"/api/runs/{run_id}/resume").json()
        assert resumed["status"] == "running"
        wait_for(lambda: (p := progress(client, run_id)) and p["evaluated"], what="progress after the resume")
        assert client.post(f"/api/runs/{run_id}/stop").json()["status"] == "stopped"


def test_a_stop_mid_generation_keeps_every_finished_generation(tmp_path):
    ga = {"population_size": 400, "max_generations": 40, "max_length": 16, "seed": 2}
    with api_client(tmp_path) as client:
        run_id = client.post("/api/runs", json={"ga": ga, "game": SHORT_GAMES}).json()["id"]
        wait_for(lambda: client.get(f"/api/runs/{run_id}").json()["generations"] >= 2, what="two generations")
        record = client.post(f"/api/runs/{run_id}/stop").json()
        assert record["status"] == "stopped" and 2 <= record["generations"] < ga["max_generations"]
        rows = client.get(f"/api/runs/{run_id}/statistics").json()
        assert [row["generation"] for row in rows] == list(range(record["generations"]))


def statistics(folder):
    with open(folder / "statistics.csv", newline="") as file:
        return [{k: v for k, v in row.items() if k != "wall_time"} for row in csv.DictReader(file)]


class StopInGeneration:
    """Callback: sets `stop` after the first chunk of generation `generation`."""

    def __init__(self, generation: int):
        self.generation, self.finished = generation, 0
        self.stop = threading.Event()

    def on_progress(self, evaluated, population):
        if self.finished == self.generation:
            self.stop.set()

    def on_generation(self, stats, population):
        self.finished = stats.generation + 1


def test_a_run_stopped_mid_generation_and_resumed_finishes_as_the_uninterrupted_one(tmp_path):
    settings = RunSettings.build({"population_size": 250, "max_generations": 3, "max_length": 16, "seed": 9},
                                 SHORT_GAMES)
    whole = Run.create(settings, tmp_path / "whole")
    with whole.evaluator() as evaluate:
        whole.play(evaluate)
    stopped = Run.create(settings, tmp_path / "stopped")
    stopper = StopInGeneration(1)
    with stopped.evaluator() as evaluate:
        result = stopped.play(evaluate, callbacks=[stopper], stop=stopper.stop)
    assert result.stop_reason == "stopped" and len(result.history) == 1
    assert [row["generation"] for row in statistics(tmp_path / "stopped")] == ["0"]
    resumed = Run.open(tmp_path / "stopped")
    with resumed.evaluator() as evaluate:
        resumed.play(evaluate)
    assert statistics(tmp_path / "stopped") == statistics(tmp_path / "whole")
    assert (tmp_path / "stopped" / "best.rules").read_text() == (tmp_path / "whole" / "best.rules").read_text()
