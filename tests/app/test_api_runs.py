"""Evolution runs through the API: start, statistics arriving, stop, resume, restart of the app."""

from __future__ import annotations

import csv
import json
import threading

from typer.testing import CliRunner

from soccer_lab.app.cli import app as cli_app
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.run import RunSettings
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import RunStatus, Store
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.statistics import GenerationStats
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.rcss.trial import TrialConfig
from tests.app.api_client import SHORT_GAMES, TINY_GA, api_client, wait_for

VOCABULARY = Vocabulary.default()

LONG_GA = {**TINY_GA, "max_generations": 10_000}  # runs until stopped


def finished(client, run_id: int) -> dict | None:
    run = client.get(f"/api/runs/{run_id}").json()
    return run if run["status"] != "running" else None


def test_small_run_reports_statistics_best_and_recording(tmp_path):
    with api_client(tmp_path) as client:
        response = client.post("/api/runs", json={"name": "tiny", "ga": TINY_GA, "game": SHORT_GAMES})
        assert response.status_code == 201
        run = response.json()
        assert run["status"] == "running" and run["config"]["ga"]["population_size"] == 4
        assert run["config"]["game"]["max_ticks"] == 40

        done = wait_for(lambda: finished(client, run["id"]), what="the run to finish")
        assert done["status"] == "finished" and done["generations"] == 2 and done["error"] is None

        statistics = client.get(f"/api/runs/{run['id']}/statistics").json()
        assert [row["generation"] for row in statistics] == [0, 1]
        assert statistics[-1]["evaluations"] == 8
        assert all(0.0 <= row["best"] <= row["mean"] <= row["worst"] <= 1.0 for row in statistics)

        best = client.get(f"/api/runs/{run['id']}/best").json()
        assert best["fitness"] == done["best_fitness"] == min(row["best"] for row in statistics)
        parse_rulebase(best["rules"], VOCABULARY)  # the best is stored as valid rule text
        assert best["chromosome"].startswith("(")

        assert done["recording"].endswith(f"/api/runs/{run['id']}/recording.rrd")
        recording = client.get(done["recording"])
        assert recording.status_code == 200 and recording.content[:4] == b"RRF2"
        assert [r["id"] for r in client.get("/api/runs").json()] == [run["id"]]

        conflict = client.post(f"/api/runs/{run['id']}/resume")
        assert conflict.status_code == 409 and "nothing to resume" in conflict.json()["detail"]
        assert client.post(f"/api/runs/{run['id']}/stop").status_code == 409


def test_out_of_range_parameters_are_refused_and_no_run_starts(tmp_path):
    with api_client(tmp_path) as client:
        for body in (
            {"ga": {"population_size": 1}},
            {"ga": {"mutation_rate": 1.5}},
            {"ga": {"selection": "lottery"}},
            {"game": {"max_ticks": 0}},
            {"game": {"fitness": "style points"}},
            {"ga": {"populationsize": 10}},
        ):
            response = client.post("/api/runs", json=body)
            assert response.status_code == 422, body
            assert next(iter(body)) in response.json()["detail"]
        assert client.get("/api/runs").json() == []


def test_stop_keeps_generations_and_restart_finds_everything_resumable(tmp_path):
    with api_client(tmp_path) as client:
        saved = client.post("/api/rulebases", json={"name": "kept", "text": "if Ball is At then Kick Straight High"})
        run = client.post("/api/runs", json={"ga": LONG_GA, "game": SHORT_GAMES}).json()
        wait_for(lambda: client.get(f"/api/runs/{run['id']}").json()["generations"] >= 2, what="two generations")
        stopped = client.post(f"/api/runs/{run['id']}/stop").json()
        assert stopped["status"] == "stopped" and stopped["resumable"] and stopped["generations"] >= 2
        kept_generations = stopped["generations"]

    # The next app on the same data folder finds the rulebase and the run with its statistics.
    with api_client(tmp_path) as client:
        assert client.get(f"/api/rulebases/{saved.json()['id']}").json() == saved.json()
        again = client.get(f"/api/runs/{run['id']}").json()
        assert again["status"] == "stopped" and again["generations"] == kept_generations

        resumed = client.post(f"/api/runs/{run['id']}/resume")
        assert resumed.status_code == 200 and resumed.json()["status"] == "running"
        wait_for(lambda: client.get(f"/api/runs/{run['id']}").json()["generations"] > kept_generations,
                 what="a generation after the resume")
        client.post(f"/api/runs/{run['id']}/stop")
        generations = [row["generation"] for row in client.get(f"/api/runs/{run['id']}/statistics").json()]
        assert generations == list(range(len(generations)))  # continued where it stopped, no gap


def test_run_cut_off_by_the_app_ending_is_interrupted_then_resumes_to_the_end(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    # Hold the run inside its first generation's listener until the stop is asked for, so that the
    # stop lands mid-run however fast the machine is.
    first_generation, stop_asked = threading.Event(), threading.Event()

    def hold_first_generation(event):
        if event.stats is not None and event.stats["generation"] == 0:
            first_generation.set()
            stop_asked.wait(30)

    runs.add_listener(hold_first_generation)
    record = runs.start("cut off", {**TINY_GA, "max_generations": 4}, SHORT_GAMES)
    assert first_generation.wait(60), "the first generation never arrived"
    runs.stop(record.id, wait=0)
    stop_asked.set()
    runs.wait(record.id, timeout=60)
    kept = len(store.statistics(record.id))
    assert 1 <= kept < 4
    # As if the process had died mid-run: its row still says running.
    store.set_run_status(record.id, RunStatus.RUNNING)
    store.close()

    with api_client(tmp_path) as client:
        interrupted = client.get(f"/api/runs/{record.id}").json()
        assert interrupted["status"] == "interrupted" and interrupted["resumable"]
        assert interrupted["generations"] == kept
        client.post(f"/api/runs/{record.id}/resume")
        done = wait_for(lambda: finished(client, record.id), what="the resumed run to finish")
        assert done["status"] == "finished"
        generations = [row["generation"] for row in client.get(f"/api/runs/{record.id}/statistics").json()]
        assert generations == [0, 1, 2, 3]


def test_listeners_hear_generations_and_status_and_best_rulebase_plays(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    events = []
    remove = runs.add_listener(events.append)
    record = runs.start("listened", TINY_GA, SHORT_GAMES)
    runs.wait(record.id, timeout=120)
    remove()
    generations = [e.stats["generation"] for e in events if e.stats is not None]
    assert generations == [0, 1]
    assert events[0].status is RunStatus.RUNNING and events[-1].status is RunStatus.FINISHED
    assert format_rulebase(runs.best_rulebase(record.id), VOCABULARY) == store.best_individual(record.id).rules
    store.close()


def test_too_many_concurrent_runs_is_a_conflict(tmp_path):
    with api_client(tmp_path, max_concurrent_runs=1) as client:
        first = client.post("/api/runs", json={"ga": LONG_GA, "game": SHORT_GAMES}).json()
        second = client.post("/api/runs", json={"ga": TINY_GA, "game": SHORT_GAMES})
        assert second.status_code == 409 and "already running" in second.json()["detail"]
        client.post(f"/api/runs/{first['id']}/stop")
        assert [r["id"] for r in client.get("/api/runs").json()] == [first["id"]]


def test_rename_and_delete_a_run_and_its_files(tmp_path):
    with api_client(tmp_path) as client:
        run = client.post("/api/runs", json={"name": "first name", "ga": LONG_GA, "game": SHORT_GAMES}).json()
        folder = tmp_path / "runs" / str(run["id"])
        wait_for(lambda: client.get(f"/api/runs/{run['id']}").json()["generations"] >= 1, what="a generation")
        renamed = client.patch(f"/api/runs/{run['id']}", json={"name": "  striker trial  "})
        assert renamed.status_code == 200 and renamed.json()["name"] == "striker trial"
        assert renamed.json()["status"] == "running"  # renaming a running run is fine
        busy = client.delete(f"/api/runs/{run['id']}")
        assert busy.status_code == 409 and "stop it first" in busy.json()["detail"]
        assert (folder / "checkpoint").is_file()

        client.post(f"/api/runs/{run['id']}/stop")
        for body, where in (({"name": ""}, "name"), ({"name": "x" * 201}, "name"), ({"title": "x"}, "title"), ({}, "name")):
            refused = client.patch(f"/api/runs/{run['id']}", json=body)
            assert refused.status_code == 422 and where in refused.json()["detail"], body
        assert client.get(f"/api/runs/{run['id']}").json()["name"] == "striker trial"

        assert client.delete(f"/api/runs/{run['id']}").status_code == 204
        assert not folder.exists() and (tmp_path / "runs").is_dir()
        for path in (f"/api/runs/{run['id']}", f"/api/runs/{run['id']}/statistics", f"/api/runs/{run['id']}/best"):
            assert client.get(path).status_code == 404
        again = client.delete(f"/api/runs/{run['id']}")
        assert again.status_code == 404 and again.json()["detail"] == f"no run with id {run['id']}"
        assert client.patch("/api/runs/424242", json={"name": "x"}).status_code == 404


def test_deleting_a_run_never_touches_files_outside_the_data_folder(tmp_path):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (outside / "precious.txt").write_text("keep me")
    data = tmp_path / "data"
    store = Store(data / DATABASE_FILE)
    (data / "runs").mkdir()
    escaping_link = data / "runs" / "link"
    escaping_link.symlink_to(outside, target_is_directory=True)
    ids = [store.create_run(name, {}, folder).id
           for name, folder in (("recorded outside", outside), ("link out", escaping_link),
                                ("the runs folder itself", data / "runs"), ("dotted", data / "runs" / ".." / ".."))]
    store.set_run_status(ids[0], RunStatus.STOPPED)
    store.close()
    with api_client(data) as client:
        for run_id in ids:
            assert client.delete(f"/api/runs/{run_id}").status_code == 204
        assert client.get("/api/runs").json() == []
    assert (outside / "precious.txt").read_text() == "keep me"
    assert escaping_link.is_symlink() and (data / DATABASE_FILE).is_file()


def test_random_search_in_the_app_is_the_command_lines_run_bit_for_bit(tmp_path):
    with api_client(tmp_path / "data") as client:
        run = client.post("/api/runs", json={"algorithm": "random-search", "ga": TINY_GA, "game": SHORT_GAMES}).json()
        assert run["config"]["algorithm"] == "random-search"
        assert run["name"] == f"random search 4x2 {GameConfig().skills} seed 7"  # named by what it is
        done = wait_for(lambda: finished(client, run["id"]), what="the random search to finish")
        assert done["status"] == "finished"
        statistics = client.get(f"/api/runs/{run['id']}/statistics").json()
    folder = tmp_path / "data" / "runs" / str(run["id"])
    settings = {k: v for k, v in json.loads((folder / "run.json").read_text()).items() if k != "best"}
    assert settings == run["config"]  # the settings, as the CLI writes them (beside them: the best's true quality)

    cli = tmp_path / "cli"
    result = CliRunner().invoke(cli_app, [
        "random-search", "--population-size", "4", "--generations", "2", "--max-length", "16", "--seed", "7",
        "--max-ticks", "40", "--idle-ticks", "20", "--workers", "1", "--out", str(cli)])
    assert result.exit_code == 0, result.output
    with (cli / "statistics.csv").open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    deterministic = [name for name in GenerationStats.field_names() if name != "wall_time"]
    assert [[float(row[name]) for name in deterministic] for row in rows] == \
        [[float(row[name]) for name in deterministic] for row in statistics]
    assert (cli / "best.rules").read_text() == (folder / "best.rules").read_text()


def test_a_run_is_named_by_its_settings_unless_named(tmp_path):
    with api_client(tmp_path) as client:
        ga = {**TINY_GA, "selection": "tournament"}
        unnamed = client.post("/api/runs", json={"ga": ga, "game": SHORT_GAMES}).json()
        assert unnamed["name"] == f"GA 4x2 tournament {GameConfig().skills} seed 7"
        named = client.post("/api/runs", json={"name": "my striker", "ga": TINY_GA, "game": SHORT_GAMES}).json()
        assert named["name"] == "my striker"
        for run in (unnamed, named):
            wait_for(lambda: finished(client, run["id"]), what="the runs to finish")
    weighting = GAConfig().roulette_weighting
    assert RunSettings.build({"selection": "elitist"}).default_name() == \
        f"GA 200x25 elitist/{weighting} {GameConfig().skills} seed 0"
    assert RunSettings.build(env="rcss").default_name() == \
        f"GA 200x25 roulette/{weighting} {TrialConfig().skills} on rcssserver seed 0"


def test_a_runs_players_are_watched_in_the_game_they_were_evaluated_in(tmp_path):
    game = {**SHORT_GAMES, "skills": "assisted", "count_touches": True, "noise": True}
    assert RunSettings.build(game=game).pitch_game == GameConfig(**game)
    # An rcss run's players are watched in SimpleSoccer with the trial's skill set: the server's own
    # noise and kick count have no SimpleSoccer setting to carry over.
    assert RunSettings.build(env="rcss", trial={"skills": "strict"}).pitch_game == GameConfig(skills="strict")
    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    record = runs.start("assisted", TINY_GA, game)
    runs.wait(record.id, timeout=120)
    assert runs.pitch_game(record.id) == GameConfig(**game)
    store.close()


def test_generations_are_numbered_from_0_alike_in_the_api_the_csv_and_the_recording(tmp_path):
    from rerun.chunk import RrdReader

    with api_client(tmp_path) as client:
        first = client.post("/api/runs", json={"ga": TINY_GA, "game": SHORT_GAMES}).json()
        second = client.post("/api/runs", json={"ga": {**TINY_GA, "seed": 8}, "game": SHORT_GAMES}).json()
        for run in (first, second):
            wait_for(lambda: finished(client, run["id"]), what="the runs to finish")
        assert [r["id"] for r in client.get("/api/runs").json()] == [second["id"], first["id"]]  # newest first
        api = [row["generation"] for row in client.get(f"/api/runs/{first['id']}/statistics").json()]
        best = client.get(f"/api/runs/{first['id']}/best").json()["generation"]
    folder = tmp_path / "runs" / str(first["id"])
    with (folder / "statistics.csv").open(newline="") as handle:
        csv_generations = [int(row["generation"]) for row in csv.DictReader(handle)]
    lines = [json.loads(line) for line in (folder / "generation_bests.jsonl").read_text().splitlines()]
    bests = [line["generation"] for line in lines]
    codec = ChromosomeCodec(Vocabulary.default())
    playable = {line["generation"] for line in lines if len(codec.decode(Individual.from_dict(line).chromosome))}
    recorded, replayed = [], set()
    for chunk in RrdReader(folder / "run.rrd").stream():
        if chunk.entity_path == "/statistics/fitness/best" and not chunk.is_static:
            recorded += chunk.to_record_batch().to_pydict()["generation"]
        if chunk.entity_path.startswith("/replay/generation_") and chunk.entity_path.endswith("/ball"):
            replayed |= set(chunk.to_record_batch().to_pydict()["generation"])
    assert api == csv_generations == bests == recorded == [0, 1]  # 0 = the evaluated initial population
    assert replayed == playable and best in (0, 1)  # a best without a valid rule is never played
