"""Lineage as a run records it (the run folder's lineage.jsonl, the store's lineage table) and as the CLI
and the API show it: every child of a SimpleSoccer run rebuilt from the records, a resumed run's records
the same as an uninterrupted run's, `soccer-lab lineage` (text, SVG, DOT, one-line errors), the JSON API
(family tree, SVG, population, breeding) and its 4xx answers."""

from __future__ import annotations

import json
import threading
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.lineage.family_tree import RunLineage, tree_data
from soccer_lab.app.runs.run import Run, RunSettings
from soccer_lab.app.runs.outputs import LineageFile
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.checkpoint import load_checkpoint
from soccer_lab.ga import lineage as ga_lineage
from soccer_lab.ga.lineage import RecordedPopulation, read_generation_record
from soccer_lab.ga.provenance import rebuild
from tests.app.api_client import SHORT_GAMES, api_client, wait_for

VOCABULARY = Vocabulary.default()
GA = {"population_size": 16, "max_generations": 5, "max_length": 24, "seed": 3, "selection": "elitist",
      "target_fitness": 0.0, "workers": 1}
GAME = {"max_ticks": 150, "idle_ticks": 60}



def cli(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def play(folder: Path, stop_after: int | None = None) -> Run:
    """A run in `folder` (continued when it holds one), stopped after generation `stop_after`."""
    run = Run.open(folder) if (folder / "checkpoint").exists() else Run.create(RunSettings.build(GA, GAME), folder)
    stop = threading.Event()
    callbacks = [] if stop_after is None else [lambda stats, population: stats.generation == stop_after and stop.set()]
    with run.evaluator() as evaluate:
        run.play(evaluate, callbacks=callbacks, stop=stop)
    return run


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("lineage") / "run"
    play(path)
    return path


def records(folder: Path) -> list[tuple[int, list]]:
    return [read_generation_record(json.loads(line)) for line in LineageFile.read(folder / "lineage.jsonl").values()]


def test_the_run_folder_records_every_generation_and_every_child_rebuilds(folder):
    written = records(folder)
    assert [g for g, _ in written] == list(range(GA["max_generations"]))
    kinds = set()
    for (_, parents), (_, children) in zip(written, written[1:]):
        for child in children:
            kinds.add(child.birth.kind)
            assert np.array_equal(rebuild(child.birth, [parents[p].chromosome for p in child.birth.parents]),
                                  child.chromosome)
    assert {"elite", "splice"} <= kinds
    final = load_checkpoint(folder / "checkpoint").population
    assert [i.to_dict() for i in written[-1][1]] == [i.to_dict() for i in final]


def test_a_resumed_run_writes_the_records_of_the_uninterrupted_one(folder, tmp_path):
    stopped = tmp_path / "stopped"
    play(stopped, stop_after=1)
    assert len(records(stopped)) == 2
    # A kill between the checkpoint and the record of generation 1: the resume writes it from the checkpoint.
    lines = (stopped / "lineage.jsonl").read_text().splitlines()
    (stopped / "lineage.jsonl").write_text(lines[0] + "\n" + lines[1][:40])
    play(stopped)
    assert (stopped / "lineage.jsonl").read_text() == (folder / "lineage.jsonl").read_text()


# ---- the CLI ----------------------------------------------------------------------------------
def test_the_cli_shows_the_best_so_far_with_its_ancestors_and_rules(folder, tmp_path):
    lineage = RunLineage.from_folder(folder)
    view = lineage.family_tree(lineage.place())
    result = cli("lineage", folder, "--svg", tmp_path / "tree.svg", "--dot", tmp_path / "tree.dot")
    assert result.exit_code == 0, result.output
    assert result.output.startswith(view.title())
    assert "back to generation 0" in result.output
    for rule in view.rules:
        assert f"[{rule.letter}] {rule.text}" in result.output and rule.summary in result.output
    svg = ElementTree.parse(tmp_path / "tree.svg").getroot()
    ancestors = svg.findall(".//{http://www.w3.org/2000/svg}g[@class='ancestor']")
    assert len(ancestors) == len(view.tree.ancestors)
    dot = (tmp_path / "tree.dot").read_text()
    assert dot.startswith("digraph family_tree {") and dot.count(" -> ") == sum(
        len(a.parents) for a in view.tree.ancestors.values())


def test_the_cli_follows_any_player_as_far_back_as_asked(folder):
    result = cli("lineage", folder, "--generation", 4, "--index", 5, "--generations", 2)
    assert result.exit_code == 0, result.output
    assert result.output.startswith("Generation 4, individual #5")
    assert "back to generation 2" in result.output and "gen   1" not in result.output
    best = cli("lineage", folder, "-g", 3)
    population = records(folder)[3][1]
    index = min(range(len(population)), key=lambda i: population[i].fitness)
    assert best.output.startswith(f"Generation 3, individual #{index}")


@pytest.mark.parametrize(("args", "message"), [
    (["--generation", 9], "the run has generations 0 to 4, not 9"),
    (["--generation", 1, "--index", 16], "generation 1 has individuals 0 to 15, not 16"),
    (["--index", 2], "an individual's index needs its generation"),
    (["--generations", -1], "--generations"),
])
def test_the_cli_refuses_bad_players_in_one_line(folder, args, message):
    result = cli("lineage", folder, *args)
    assert result.exit_code == 2 and result.output.count("\n") == 1 and message in result.output, result.output


def test_the_cli_refuses_a_folder_without_lineage_in_one_line(folder, tmp_path):
    for path, message in ((tmp_path / "nothing", "is not a run folder"), (tmp_path / "old", "no lineage records")):
        path.mkdir()
        if path.name == "old":
            (path / "run.json").write_text((folder / "run.json").read_text())
        result = cli("lineage", path)
        assert result.exit_code == 2 and result.output.count("\n") == 1 and message in result.output, result.output
    result = cli("lineage", folder, "--svg", tmp_path / "missing" / "tree.svg")
    assert result.exit_code == 2 and "cannot write" in result.output.splitlines()[-1]


def test_a_run_resumed_from_before_lineage_shows_its_recorded_generations(folder, tmp_path):
    import shutil

    resumed = tmp_path / "resumed"
    shutil.copytree(folder, resumed)
    lines = (folder / "lineage.jsonl").read_text().splitlines(keepends=True)
    (resumed / "lineage.jsonl").write_text("".join(lines[2:]))  # generations 0 and 1 played unrecorded
    result = cli("lineage", resumed, "--generation", 4)
    assert result.exit_code == 0, result.output
    assert "back to generation 2" in result.output and "gen   1" not in result.output
    assert "gen   2" in result.output
    result = cli("lineage", resumed, "--generation", 1)
    assert result.exit_code == 2 and "generation 1 has no lineage record" in result.output, result.output


# ---- the store and the API --------------------------------------------------------------------
@pytest.fixture(scope="module")
def api(tmp_path_factory):
    with api_client(tmp_path_factory.mktemp("api")) as client:
        run = client.post("/api/runs", json={"ga": {**GA, "max_generations": 4}, "game": SHORT_GAMES}).json()["id"]
        wait_for(lambda: client.get(f"/api/runs/{run}").json()["status"] == "finished", what="the run")
        yield client, run


def test_the_store_holds_the_run_folders_records(api):
    client, run = api
    store = client.app.state.store
    folder = Path(store.get_run(run).folder)
    for generation, line in LineageFile.read(folder / "lineage.jsonl").items():
        assert store.lineage_record(run, generation) == json.loads(line)


def test_the_api_tree_is_the_clis(api):
    client, run = api
    folder = Path(client.app.state.store.get_run(run).folder)
    tree = client.get(f"/api/runs/{run}/lineage").json()
    lineage = RunLineage.from_folder(folder)
    assert tree == json.loads(json.dumps(tree_data(lineage.family_tree(lineage.place()))))
    assert tree["player"] == tree["best_so_far"]
    assert tree["ancestors"][0]["generation"] == tree["player"]["generation"]  # newest first
    some = client.get(f"/api/runs/{run}/lineage", params={"generation": 3, "index": 2, "generations": 1}).json()
    assert some["player"] == {"generation": 3, "index": 2} and some["oldest_generation"] == 2
    assert {a["generation"] for a in some["ancestors"]} <= {2, 3}
    svg = client.get(f"/api/runs/{run}/lineage.svg", params={"generation": 3, "index": 2})
    assert svg.headers["content-type"].startswith("image/svg+xml")
    assert ElementTree.fromstring(svg.text).tag == "{http://www.w3.org/2000/svg}svg"


def test_the_api_pages_through_a_population(api):
    client, run = api
    page = client.get(f"/api/runs/{run}/population", params={"generation": 2, "offset": 10, "limit": 4}).json()
    assert (page["size"], page["offset"], [i["index"] for i in page["individuals"]]) == (16, 10, [10, 11, 12, 13])
    record = client.app.state.store.lineage_record(run, 2)["individuals"][10]
    assert page["individuals"][0]["record"] == record["birth"]
    assert page["individuals"][0]["chromosome"].startswith("(")


def test_a_record_read_in_place_is_the_record_parsed_whole(folder, monkeypatch):
    """Only the individuals read are parsed: the whole record never is (json.loads refuses here)."""
    lines = LineageFile.read(folder / "lineage.jsonl").values()
    whole = [read_generation_record(json.loads(line))[1] for line in lines]
    monkeypatch.setattr(ga_lineage.json, "loads", lambda *args, **kwargs: pytest.fail("parsed the whole record"))
    for line, parsed in zip(lines, whole):
        in_place = RecordedPopulation.from_text(line)
        assert in_place.fitnesses() == [i.fitness for i in parsed]
        assert [i.to_dict() for i in in_place[::-1]] == [i.to_dict() for i in parsed[::-1]]


def test_lineage_requests_decode_only_the_players_they_show(api, monkeypatch):
    """The probe: a lineage request decoded every individual of every generation it read (3.4 s for a
    17 MB run of population 10,000)."""
    client, run = api
    decoded = []
    real = ga_lineage._individual
    monkeypatch.setattr(ga_lineage, "_individual", lambda row: decoded.append(row) or real(row))
    tree = client.get(f"/api/runs/{run}/lineage", params={"generations": 1}).json()
    assert 0 < len(decoded) <= len(tree["ancestors"])
    decoded.clear()
    page = client.get(f"/api/runs/{run}/population", params={"generation": 2, "offset": 3, "limit": 2}).json()
    assert len(page["individuals"]) == 2 and len(decoded) == 2


def test_the_api_breeds_step_by_step_and_the_seed_repeats_it(api):
    client, run = api
    body = {"parents": [{"run_id": run, "generation": 3, "index": 0},
                        {"text": "if Ball is Near then KickTowardGoal High\nif Ball is Far then GoToBall High"}],
            "crossover": "two-point", "seed": 11, "mutation_rate": 0.3}
    first = client.post("/api/breed", json=body)
    assert first.status_code == 200, first.text
    bred = first.json()
    assert bred == client.post("/api/breed", json=body).json()  # seeded: the same again
    a, b = bred["parents"]
    assert len(a["cuts"]) == 2 and len(b["cuts"]) == 2 and b["chromosome"] == ["(B,N,A)", "(KG,n,H)", "(B,F,A)", "(GB,n,H)"]
    for child in bred["children"]:
        taken = [gene for s in child["segments"] for gene in bred["parents"][s["parent"]]["chromosome"][s["first"] - 1:s["last"]]]
        assert [g["compact"] for g in child["crossed"]] == taken  # the stretches of its parents, in order
        assert len(child["mutations"]) == sum(g["mutated"] is not None for g in child["chromosome"]) >= 1
    unmutated = client.post("/api/breed", json={**body, "mutation_rate": None}).json()
    assert all(c["mutations"] == [] and c["chromosome"] == c["crossed"] for c in unmutated["children"])


@pytest.mark.parametrize(("path", "params", "status", "message"), [
    ("/api/runs/99/lineage", {}, 404, "no run with id 99"),
    ("/api/runs/{run}/lineage", {"generation": 9}, 404, "the run has generations 0 to 3, not 9"),
    ("/api/runs/{run}/lineage", {"generation": 1, "index": 99}, 404, "individuals 0 to 15, not 99"),
    ("/api/runs/{run}/lineage", {"index": 1}, 404, "needs its generation"),
    ("/api/runs/{run}/lineage", {"generations": -1}, 422, "generations"),
    ("/api/runs/{run}/lineage.svg", {"generation": "x"}, 422, "generation"),
    ("/api/runs/{run}/population", {}, 422, "generation"),
    ("/api/runs/{run}/population", {"generation": 1, "limit": 100000}, 422, "limit"),
])
def test_the_api_answers_bad_lineage_requests_with_4xx(api, path, params, status, message):
    client, run = api
    response = client.get(path.format(run=run), params=params)
    assert response.status_code == status and message in response.json()["detail"], response.text


@pytest.mark.parametrize(("parents", "status", "message"), [
    ([{"run_id": 1, "generation": 1}, {"text": "if Ball is Near then Kick"}], 422, "give exactly one of"),
    ([{"rulebase_id": 5}, {"text": "if Ball is Near then KickTowardGoal High"}], 404, "no rulebase with id 5"),
    ([{"text": "if Ball is Near"}, {"text": "if Ball is Near then KickTowardGoal High"}], 422, "invalid rule text"),
    ([{"text": ""}, {"text": "if Ball is Near then KickTowardGoal High"}], 422, "at least 2"),
    ([{"text": "if Ball is Near then KickTowardGoal High"}], 422, "parents"),
])
def test_the_api_refuses_parents_it_cannot_breed(api, parents, status, message):
    client, _ = api
    response = client.post("/api/breed", json={"parents": parents})
    assert response.status_code == status and message in response.json()["detail"], response.text


def test_a_database_from_before_lineage_gains_the_table_and_keeps_its_runs(tmp_path):
    import sqlite3

    from soccer_lab.app.store import MIGRATIONS, SCHEMA_VERSION, NotFound, Store

    path = tmp_path / "old.sqlite3"
    connection = sqlite3.connect(path)
    for statement in MIGRATIONS[0]:
        connection.execute(statement)
    connection.execute("INSERT INTO runs (name, config, status, created, folder) VALUES ('old', '{}', 'finished', "
                       "'2024-01-01', 'runs/1')")
    connection.execute("PRAGMA user_version = 1")
    connection.commit()
    connection.close()
    store = Store(path)
    assert store.schema_version == SCHEMA_VERSION  # every migration since applied
    assert store.get_run(1).name == "old"
    with pytest.raises(NotFound, match="run 1 has no lineage record of generation 0"):
        store.lineage_record(1, 0)
    store.record_generation(1, {"generation": 0, "best": 1.0}, "", "", 1.0, lineage='{"generation": 0}')
    assert store.lineage_record(1, 0) == {"generation": 0}
    store.delete_run(1)  # the records go with their run
    assert store._query("SELECT COUNT(*) FROM lineage")[0][0] == 0
    store.close()


def test_statistics_saved_before_diversity_still_read(tmp_path):
    import csv

    from soccer_lab.app.experiment.table import COLUMNS, StatisticsTable
    from soccer_lab.ga.statistics import ADDED_LATER, GenerationStats

    older = [c for c in COLUMNS if c not in ADDED_LATER]
    path = tmp_path / "statistics.csv"
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=older)
        writer.writeheader()
        writer.writerow({c: "study" if c in ("preset", "setting", "algorithm") else 0 for c in older})
    table = StatisticsTable.read(path)
    assert table.rows[0]["distinct_behaviours"] == 0 and table.curves("study", "study", "best").shape == (1, 1)
    stats = GenerationStats.from_dict({c: 0 for c in older if c in GenerationStats.field_names()})
    assert (stats.distinct_chromosomes, stats.rule_set_distance) == (0, 0.0)
