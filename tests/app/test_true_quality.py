"""A best player's true quality (app/runs/true_quality.py) stands beside the one-game fitness the GA saw: in
evolve's progress and summary, run.json, `lineage`, and an experiment's bests; every player is re-played
on the same seeded starts, so two players' figures compare."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.rulebase_files import load_rulebase
from soccer_lab.app.runs.true_quality import TRUE_QUALITY_STARTS, TrueQuality, common_seeds, simple_soccer_replayer
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig

TINY = ["--population-size", "8", "--generations", "3", "--max-ticks", "60", "--workers", "1"]
GAME = GameConfig(max_ticks=60)


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def evolved(tmp_path_factory) -> tuple[Path, str]:
    folder = tmp_path_factory.mktemp("runs") / "tiny"
    result = run("evolve", *TINY, "--seed", "5", "--out", folder)
    assert result.exit_code == 0, result.output
    return folder, result.output


def test_every_player_is_replayed_on_the_same_seeded_starts():
    assert common_seeds() == common_seeds()
    assert len(set(common_seeds())) == TRUE_QUALITY_STARTS
    assert common_seeds(5) == common_seeds()[:5]


def test_evolve_summary_states_true_quality_beside_the_one_game_fitness(evolved):
    folder, output = evolved
    record = json.loads((folder / "run.json").read_text())["best"]
    quality = TrueQuality.from_dict(record["true_quality"])
    assert f"best fitness {record['fitness_seen']:.4f}" in output
    assert f"best player's true quality: {quality.text()}" in output
    assert f"on {TRUE_QUALITY_STARTS} fresh starts" in output
    assert "re-played" in output.split("best fitness")[0]  # the progress line says it too


def test_run_json_true_quality_is_the_best_replayed_on_the_common_starts(evolved):
    folder, _ = evolved
    stored = TrueQuality.from_dict(json.loads((folder / "run.json").read_text())["best"]["true_quality"])
    again = simple_soccer_replayer(GAME, SOCCER_VOCABULARY)(load_rulebase(folder / "best.rules"))
    assert stored == again


def test_resumed_run_keeps_its_best_and_true_quality(evolved, tmp_path):
    folder, _ = evolved
    longer = tmp_path / "longer"
    assert run("evolve", *TINY[:2], "--generations", "2", *TINY[4:], "--seed", "5", "--out", longer).exit_code == 0
    before = json.loads((longer / "run.json").read_text())["best"]
    resumed = run("evolve", "--resume", longer)
    assert resumed.exit_code == 0, resumed.output
    assert "true quality: re-played on" in resumed.output
    after = json.loads((longer / "run.json").read_text())["best"]
    if after["fitness_seen"] == before["fitness_seen"]:
        assert after["generation"] == before["generation"] and after["true_quality"] == before["true_quality"]


def test_lineage_states_the_players_true_quality(evolved):
    folder, _ = evolved
    result = run("lineage", folder)
    assert result.exit_code == 0, result.output
    stored = TrueQuality.from_dict(json.loads((folder / "run.json").read_text())["best"]["true_quality"])
    assert f"true quality of this player: {stored.text()}" in result.output


def test_run_json_without_a_best_record_reads_as_unknown(tmp_path):
    from soccer_lab.app.runs.outputs import RunFolder

    folder = RunFolder.create(tmp_path / "old", {"algorithm": "ga"})
    assert folder.best_quality() is None
    (tmp_path / "old" / "run.json").write_text('{"best": {"true_quality": {"starts": "x"}}}')
    assert folder.best_quality() is None


def test_the_apis_best_carries_its_true_quality_beside_the_one_game_fitness(tmp_path):
    from soccer_lab.app.runs.outputs import best_quality_of, replayed_note
    from tests.app.api_client import SHORT_GAMES, TINY_GA, api_client, wait_for

    with api_client(tmp_path) as client:
        run = client.post("/api/runs", json={"name": "tiny", "ga": TINY_GA, "game": SHORT_GAMES}).json()
        wait_for(lambda: client.get(f"/api/runs/{run['id']}").json()["status"] != "running",
                 what="the run to finish")
        best = client.get(f"/api/runs/{run['id']}/best").json()
    folder = next((tmp_path).rglob("run.json")).parent
    stored = best_quality_of(folder, best["fitness"])
    assert stored is not None and best["true_quality"] == stored.to_dict()
    assert best["true_quality"]["starts"] == TRUE_QUALITY_STARTS
    assert replayed_note(stored).startswith(f" (re-played on {TRUE_QUALITY_STARTS} fresh starts: ")
    assert best_quality_of(folder, best["fitness"] + 1.0) is None  # another player's fitness: not its quality


def test_the_evolve_tabs_best_so_far_and_loaded_best_say_their_true_quality(tmp_path):
    """"Load best so far" and the live status line once gave the one-game fitness alone."""
    import viser

    from soccer_lab.app.runs.outputs import RunFolder, best_record
    from soccer_lab.app.runs.manager import RunEvent, RunManager
    from soccer_lab.app.store import RunStatus, Store
    from soccer_lab.app.web.ui.panels.evolve import EvolvePanel
    from soccer_lab.ga.codec import ChromosomeCodec
    from soccer_lab.ga.individual import Individual
    from soccer_lab.ga.statistics import GenerationStats
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.soccer.demo import demo_rulebase
    from tests.app.test_ui_browser import free_port

    store = Store(tmp_path / "db.sqlite3")
    record = store.create_run("tiny", {"ga": {}}, tmp_path / "runs" / "{id}")
    chromosome = ChromosomeCodec(SOCCER_VOCABULARY).encode(demo_rulebase())
    best = Individual(chromosome, evaluations=1, fitness_sum=0.25, goals=1)
    stats = {**dict.fromkeys(GenerationStats.field_names(), 0), "generation": 0, "best": 0.25, "mean": 0.8}
    store.record_generation(record.id, stats, format_rulebase(demo_rulebase(), SOCCER_VOCABULARY), "(B,N,O)", 0.25)
    quality = simple_soccer_replayer(GAME, SOCCER_VOCABULARY)(demo_rulebase())
    folder = RunFolder.create(record.folder, {"algorithm": "ga"})
    folder.write_best_record(best_record(best, 0, quality))
    loaded = []
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        panel = EvolvePanel(server.gui, RunManager(store, tmp_path), store, on_load=lambda *a: loaded.append(a),
                            on_generation=lambda *_: None, on_run_ended=lambda *_: None, on_runs_changed=lambda: None)
        panel.run_id, panel.total_generations = record.id, 2
        panel._on_event(RunEvent(record.id, RunStatus.RUNNING, stats, 0.25))
        note = f"(re-played on {TRUE_QUALITY_STARTS} fresh starts: {quality.fitness:.3f} ± {quality.fitness_std:.3f})"
        assert f"best so far 0.250 {note}" in panel.status.content
        panel.load_best_so_far()
        assert loaded and f"fitness 0.250 {note}" in loaded[0][1]
    finally:
        server.stop()
        store.close()
