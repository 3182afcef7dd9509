"""Runs on rcssserver through the API: env, servers and trial accepted and checked, a dead server
failing the run with its message, one server per run, and a run completing on replayed trials."""

from __future__ import annotations

import threading
import pytest

from soccer_lab.app.runs.run import RunSettings
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.rcss.errors import RcssTimeoutError
from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
from soccer_lab.soccer.rcss.trial import TrialConfig
from tests.app.api_client import TINY_GA, api_client, wait_for
from tests.app.rcss_fakes import GOALS_CYCLES, GOALS_FITNESS, silent_server, transcripts_missing, two_recorded_trials

VOCABULARY = Vocabulary.default()

ONE_GENERATION = {**TINY_GA, "population_size": 2, "max_generations": 1, "seed": 0}


def ended(client, run_id: int) -> dict | None:
    run = client.get(f"/api/runs/{run_id}").json()
    return run if run["status"] != "running" else None


def test_a_run_against_a_dead_server_fails_with_the_servers_message(tmp_path):
    with api_client(tmp_path) as client, silent_server() as server:
        response = client.post("/api/runs", json={"ga": ONE_GENERATION, "env": "rcss", "servers": [server]})
        assert response.status_code == 201, response.json()
        run = response.json()
        assert run["config"]["env"] == "rcss" and run["config"]["servers"] == [server]
        assert run["config"]["trial"] == TrialConfig().model_dump()  # the chapter's RoboCup trials
        done = wait_for(lambda: ended(client, run["id"]), timeout=30, what="the run to fail")
        assert done["status"] == "failed" and done["generations"] == 0
        assert done["error"] == (f"RcssNoServerError: player: no reply from rcssserver at {server} within 2 s "
                                 "(is it running, on this host and port?)")


@pytest.mark.parametrize("body, message", [
    ({"env": "robocup"}, "env: Input should be 'simple' or 'rcss'"),
    ({"env": "rcss", "servers": ["localhost:port"]}, "servers: bad server address 'localhost:port'"),
    ({"env": "rcss", "servers": ["127.0.0.1:6000", "127.0.0.1:6000"]}, "a server is listed twice"),
    ({"servers": ["127.0.0.1:6000"]}, "servers: servers are for env rcss only"),
    ({"env": "rcss", "ga": {"workers": 2}}, "ga.workers: with env rcss the GA runs 1 worker"),
    ({"env": "rcss", "trial": {"max_ticks": 0}}, "trial.max_ticks: Input should be greater than 0"),
    ({"env": "rcss", "trial": {"fitness": "style points"}}, "trial.fitness: Input should be"),
    ({"env": "rcss", "trial": {"count_touches": True}}, "trial.count_touches: Extra inputs are not permitted"),
    ({"env": "rcss", "trial": {"noise": "loud"}}, "trial.noise: Input should be a valid boolean"),
    ({"env": "rcss", "servers": ["127.0.0.1:6000"], "start_servers": 2}, "start_servers: give the servers you run "
                                                                          "or how many soccer-lab starts, not both"),
    ({"start_servers": 2}, "start_servers: started servers are for env rcss only"),
    ({"env": "rcss", "start_servers": 0}, "start_servers: Input should be greater than or equal to 1"),
])
def test_bad_environment_settings_are_refused_and_no_run_starts(body, message, tmp_path):
    with api_client(tmp_path) as client:
        response = client.post("/api/runs", json=body)
        assert response.status_code == 422 and message in response.json()["detail"], response.json()
        assert client.get("/api/runs").json() == []


def test_settings_default_to_one_started_server_and_old_records_keep_theirs():
    rcss = RunSettings.build(env="rcss")
    assert (rcss.servers, rcss.start_servers, rcss.trial) == ((), 1, TrialConfig())
    assert RunSettings.from_dict(rcss.to_dict()) == rcss
    assert "rcssserver" not in rcss.with_started_servers(2, "/opt/rcssserver").to_dict()  # never stored
    old = RunSettings.from_dict({"ga": TINY_GA, "game": {"max_ticks": 40}})  # stored before env existed
    assert old.env == "simple" and old.servers == () and "servers" not in old.to_dict()
    before = RunSettings.from_dict({"ga": TINY_GA, "env": "rcss", "servers": ["127.0.0.1:6000"],
                                    "trial": {"max_cycles": 300, "idle_cycles": 50}})  # stored before start_servers
    assert (before.servers, before.start_servers, before.trial.max_ticks, before.trial.idle_ticks) == (
        ("127.0.0.1:6000",), 0, 300, 50)


def test_a_run_that_starts_servers_needs_an_rcssserver(tmp_path, monkeypatch):
    monkeypatch.delenv("RCSSSERVER", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    with api_client(tmp_path) as client:
        response = client.post("/api/runs", json={"env": "rcss", "start_servers": 2, "ga": ONE_GENERATION})
        assert response.status_code == 409
        assert response.json()["detail"] == ("start_servers: no rcssserver: 'rcssserver' is not on PATH (start the app "
                                             "with serve --rcssserver PATH, or give the servers you run)")
        assert client.get("/api/runs").json() == []


def test_a_server_plays_one_run_at_a_time(tmp_path, monkeypatch):
    release = threading.Event()

    def held(self, rulebases, seeds):  # a server busy with a trial until the test lets go
        release.wait(30)
        raise RcssTimeoutError("released by the test")

    monkeypatch.setattr(RcssEvaluator, "connect", lambda self: None)  # the servers answer...
    monkeypatch.setattr(RcssEvaluator, "__call__", held)
    with api_client(tmp_path) as client:
        body = {"ga": ONE_GENERATION, "env": "rcss", "servers": ["127.0.0.1:6100", "127.0.0.1:6101"]}
        first = client.post("/api/runs", json=body).json()
        again = client.post("/api/runs", json={**body, "servers": ["127.0.0.1:6101"]})
        assert again.status_code == 409
        assert again.json()["detail"] == (f"run {first['id']} is playing on rcssserver 127.0.0.1:6101; "
                                          "a server plays one run at a time")
        other = client.post("/api/runs", json={**body, "servers": ["127.0.0.1:6102"]})
        assert other.status_code == 201
        release.set()
        for run_id in (first["id"], other.json()["id"]):
            done = wait_for(lambda: ended(client, run_id), timeout=30, what="the held runs to end")
            assert done["status"] == "failed" and done["error"] == "RcssTimeoutError: released by the test"


def test_a_run_on_two_replayed_servers_finishes_with_the_better_trial_as_best(tmp_path):
    reason = transcripts_missing()
    if reason:
        pytest.skip(reason)
    with api_client(tmp_path) as client, two_recorded_trials() as (goals, kick_in):
        run = client.post("/api/runs", json={
            "ga": ONE_GENERATION, "env": "rcss", "servers": [goals.server, kick_in.server],
            "trial": {"max_ticks": GOALS_CYCLES},
        }).json()
        done = wait_for(lambda: ended(client, run["id"]), timeout=60, what="the run to finish")
        assert done["status"] == "finished" and done["error"] is None and done["generations"] == 1
        assert done["best_fitness"] == pytest.approx(GOALS_FITNESS)
        best = client.get(f"/api/runs/{run['id']}/best").json()
        assert len(parse_rulebase(best["rules"], VOCABULARY)) > 0
        assert goals.wait().error is None and kick_in.wait().error is None
