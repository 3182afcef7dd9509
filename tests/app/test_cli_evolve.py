"""`soccer-lab evolve`, `random-search` and `play` driven through the real CLI (tiny runs, short games)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from soccer_lab.app.runs import recording
from soccer_lab.app.cli import app
from soccer_lab.fuzzy.export import rulebase_from_json
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.statistics import NOT_MEASURED, GenerationStats
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_game

VOCABULARY = Vocabulary.default()

TINY = ["--population-size", "8", "--generations", "3", "--max-ticks", "60", "--workers", "1", "--seed", "5"]
DETERMINISTIC = [name for name in GenerationStats.field_names() if name != "wall_time"]


def run(*args: str):
    return CliRunner().invoke(app, [str(a) for a in args])


def statistics(folder: Path) -> list[dict[str, str]]:
    with (folder / "statistics.csv").open(newline="") as handle:
        return [{k: row[k] for k in DETERMINISTIC} for row in csv.DictReader(handle)]


def assert_one_line_error(result, *fragments: str) -> None:
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.output
    for fragment in fragments:
        assert fragment in lines[0]


@pytest.fixture(scope="module")
def evolved(tmp_path_factory) -> tuple[Path, object]:
    folder = tmp_path_factory.mktemp("runs") / "tiny"
    return folder, run("evolve", *TINY, "--out", folder)


def test_evolve_writes_every_output(evolved):
    folder, result = evolved
    assert result.exit_code == 0, result.output
    for name in ("best.rules", "best.json", "statistics.csv", "checkpoint", "run.rrd", "run.json"):
        assert (folder / name).is_file(), name
    rows = statistics(folder)
    assert [int(r["generation"]) for r in rows] == [0, 1, 2]
    assert [int(r["evaluations"]) for r in rows] == [8, 16, 24]
    with (folder / "statistics.csv").open() as handle:
        assert next(csv.reader(handle)) == list(GenerationStats.field_names())
    # The best rulebase, as text and as JSON, is one and the same and what the summary prints.
    text_rules = parse_rulebase((folder / "best.rules").read_text(), VOCABULARY)
    json_rules, _ = rulebase_from_json((folder / "best.json").read_text())
    assert text_rules == json_rules and len(text_rules) > 0
    assert "best fitness" in result.output and f"outputs in {folder}" in result.output
    first_rule = (folder / "best.rules").read_text().splitlines()[0]
    assert f"  {first_rule}" in result.output
    assert json.loads((folder / "run.json").read_text())["game"]["max_ticks"] == 60


def test_the_best_fitness_reported_is_the_lowest_of_the_run(evolved):
    folder, result = evolved
    best = min(float(r["best"]) for r in statistics(folder))
    assert f"best fitness {best:.4f}" in result.output


def test_same_seed_same_run(evolved, tmp_path):
    folder, _ = evolved
    again = run("evolve", *TINY, "--out", tmp_path / "again")
    assert again.exit_code == 0, again.output
    assert statistics(tmp_path / "again") == statistics(folder)
    assert (tmp_path / "again" / "best.rules").read_text() == (folder / "best.rules").read_text()


def test_the_summary_prints_the_seed_that_replays_the_run(evolved, tmp_path):
    """The CLI keeps seed 0 by default (unlike the UI and the API, which draw one), and always says it."""
    _, result = evolved
    assert "seed 5 (--seed 5 replays this run bit for bit)" in result.output
    default = run("evolve", *TINY[:-2], "--generations", "1", "--out", tmp_path / "default")
    assert default.exit_code == 0, default.output
    assert "seed 0 (--seed 0 replays" in default.output


def test_evolve_with_rule_wise_uniform_crossover(evolved, tmp_path):
    folder, _ = evolved
    result = run("evolve", *TINY, "--crossover", "uniform", "--out", tmp_path / "uniform")
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "uniform" / "run.json").read_text())["ga"]["crossover"] == "uniform"
    rows = statistics(tmp_path / "uniform")
    assert [int(r["evaluations"]) for r in rows] == [8, 16, 24]
    assert rows[0] == statistics(folder)[0]  # the same initial population, then other children
    assert rows[1:] != statistics(folder)[1:]


def read_recording(path: Path) -> dict[str, dict]:
    """entity path -> {timelines (of its temporal data), static (has static data), columns as python lists},
    read with rerun's own RRD reader."""
    from rerun.chunk import RrdReader

    entities: dict[str, dict] = {}
    for chunk in RrdReader(path).stream():
        batch = chunk.to_record_batch().to_pydict()
        entry = entities.setdefault(chunk.entity_path, {"timelines": set(), "static": False, "columns": {}})
        if chunk.is_static:
            entry["static"] = True
        else:
            entry["timelines"] |= set(chunk.timeline_names)
        for column, values in batch.items():
            entry["columns"].setdefault(column, []).extend(values)
    return entities


def generation_bests(folder: Path) -> list[tuple[int, object]]:
    from soccer_lab.app.runs.outputs import GenerationBestsFile

    return GenerationBestsFile.read(folder / "generation_bests.jsonl")


def test_recording_reads_back_with_every_statistic_and_each_generations_replay(evolved):
    folder, _ = evolved
    entities = read_recording(folder / "run.rrd")
    rows = statistics(folder)
    for name in GenerationStats.field_names():
        if name == "generation":
            continue
        entity = "/" + recording.statistic_entity(name)
        if name == "distinct_behaviours":  # a run without behaviour seeds measures none: no series is drawn
            assert all(int(row[name]) == NOT_MEASURED for row in rows)
            assert "Scalars:scalars" not in entities.get(entity, {}).get("columns", {})
            continue
        assert entities[entity]["timelines"] == {"generation"}, entity
        assert entities[entity]["columns"]["generation"] == [0, 1, 2]
        if name != "wall_time":
            assert [v[0] for v in entities[entity]["columns"]["Scalars:scalars"]] == pytest.approx(
                [float(r[name]) for r in rows])
    histogram = entities["/statistics/goal_histogram"]["columns"]["BarChart:values"]
    assert len(histogram) == 3
    assert histogram[0][0]["buffer"] == pytest.approx([float(rows[0][b]) for b in recording.GOAL_BINS])
    spread = entities["/statistics/chromosome_spread/genes"]["columns"]["Scalars:scalars"]
    assert spread[1] == pytest.approx([float(rows[1]["genes_mean"]) - float(rows[1]["genes_std"]),
                                       float(rows[1]["genes_mean"]) + float(rows[1]["genes_std"])])
    # One pitch for every replay; each generation's best player's first game on the tick timeline.
    assert entities["/replay/pitch"]["static"] and entities["/replay/pitch"]["timelines"] == set()
    bests = generation_bests(folder)
    assert [generation for generation, _ in bests] == [0, 1, 2]
    config = GameConfig(max_ticks=60)
    for generation, best in bests:
        assert best.fitness == pytest.approx(float(rows[generation]["best"]))
        game = f"/replay/generation_{generation}"
        for moving in ("player", "ball", "player/view_cone", "player/facing"):
            assert entities[f"{game}/{moving}"]["timelines"] == {"tick", "generation"}, moving
        ball = entities[f"{game}/ball"]["columns"]
        assert set(ball["generation"]) == {generation}
        # The game the GA scored: its rulebase from its seed, played again here, is the recorded one.
        result, trace = play_game(ChromosomeCodec(Vocabulary.default()).decode(best.chromosome), best.first_seed, config)
        assert ball["tick"] == list(range(len(trace)))
        recorded = np.array([p[0] for p in ball["Points2D:positions"]], dtype=np.float32)  # rerun keeps float32
        np.testing.assert_array_equal(recorded, np.column_stack([trace.ball_x, trace.ball_y]).astype(np.float32))
        if best.evaluations == 1:
            assert result.fitness == pytest.approx(best.fitness)


def test_resume_finishes_a_killed_run_as_the_uninterrupted_one(evolved, tmp_path, monkeypatch):
    folder, _ = evolved
    killed = tmp_path / "killed"
    original = recording.RunRecorder.on_generation

    def killed_after_generation_1(self, stats, population=None):
        original(self, stats, population)
        if stats.generation == 1:
            raise KeyboardInterrupt

    monkeypatch.setattr(recording.RunRecorder, "on_generation", killed_after_generation_1)
    interrupted = run("evolve", *TINY, "--out", killed)
    assert interrupted.exit_code == 130
    assert f"soccer-lab evolve --resume {killed}" in interrupted.output
    assert [r["generation"] for r in statistics(killed)] == ["0", "1"]
    monkeypatch.setattr(recording.RunRecorder, "on_generation", original)

    resumed = run("evolve", "--resume", killed)
    assert resumed.exit_code == 0, resumed.output
    assert statistics(killed) == statistics(folder)
    assert (killed / "best.rules").read_text() == (folder / "best.rules").read_text()
    recorded, uninterrupted = read_recording(killed / "run.rrd"), read_recording(folder / "run.rrd")
    assert recorded["/statistics/fitness/best"]["columns"]["generation"] == [0, 1, 2]
    # The generations before the kill are replayed again from generation_bests.jsonl: the same games.
    assert [(g, b.to_dict()) for g, b in generation_bests(killed)] == \
        [(g, b.to_dict()) for g, b in generation_bests(folder)]
    for generation in (0, 1, 2):
        ball = f"/replay/generation_{generation}/ball"
        assert recorded[ball]["columns"]["Points2D:positions"] == uninterrupted[ball]["columns"]["Points2D:positions"]


def test_random_search_has_the_same_outputs(tmp_path):
    folder = tmp_path / "random"
    result = run("random-search", "--population-size", "6", "--generations", "2", "--max-ticks", "40",
                 "--workers", "1", "--out", folder)
    assert result.exit_code == 0, result.output
    for name in ("best.rules", "best.json", "statistics.csv", "checkpoint", "run.rrd"):
        assert (folder / name).is_file(), name
    assert [r["evaluations"] for r in statistics(folder)] == ["6", "12"]
    assert json.loads((folder / "run.json").read_text())["algorithm"] == "random-search"


@pytest.mark.parametrize("args, fragments", [
    (["--population-size", "1"], ["--population-size", "greater than or equal to 2"]),
    (["--generations", "0"], ["--generations"]),
    (["--selection", "best"], ["--selection", "'best'"]),
    (["--mutation-rate", "1.5"], ["--mutation-rate"]),
    (["--fitness", "speed"], ["--fitness", "'speed'"]),
    (["--max-ticks", "0"], ["--max-ticks"]),
    (["--population-size", "many"], ["--population-size", "valid integer"]),
    (["--no-such-option"], ["No such option: --no-such-option"]),
])
def test_evolve_rejects_bad_options_in_one_line(args, fragments, tmp_path):
    assert_one_line_error(run("evolve", *args, "--out", tmp_path / "run"), *fragments)
    assert not (tmp_path / "run").exists()


def test_evolve_refuses_to_overwrite_a_run(evolved):
    folder, _ = evolved
    assert_one_line_error(run("evolve", *TINY, "--out", folder), "already holds a run", "--resume")


def test_resume_rejects_bad_folders_and_extra_options(evolved, tmp_path):
    folder, _ = evolved
    assert_one_line_error(run("evolve", "--resume", tmp_path / "nowhere"), "is not a run folder")
    assert_one_line_error(run("evolve", "--resume", folder, "--generations", "9"), "drop --generations")
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "run.json").write_text((folder / "run.json").read_text())
    (broken / "checkpoint").write_text("{not json")
    assert_one_line_error(run("evolve", "--resume", broken), "cannot read checkpoint")


# ---- play ------------------------------------------------------------------------------------
@pytest.fixture
def demo_file(tmp_path) -> Path:
    path = tmp_path / "demo.rules"
    from soccer_lab.app.rulebase_files import rulebase_text

    path.write_text(rulebase_text(demo_rulebase(), VOCABULARY))
    return path


def test_play_prints_one_line_per_game_and_the_mean(demo_file):
    result = run("play", demo_file, "--games", "3", "--seed", "11", "--max-ticks", "150")
    assert result.exit_code == 0, result.output
    lines = result.output.strip().splitlines()
    assert lines[0].split() == ["game", "seed", "goals", "kicks", "ticks", "fitness"]
    games = [line.split() for line in lines[1:4]]
    assert [g[:2] for g in games] == [["1", "11"], ["2", "12"], ["3", "13"]]
    from soccer_lab.soccer.config import GameConfig

    config = GameConfig(max_ticks=150)
    for game in games:  # each line is that seed's game, as the engine plays it
        expected, _ = play_game(demo_rulebase(), int(game[1]), config, trace=False)
        assert game[2:] == [str(expected.goals), str(expected.kicks), str(expected.ticks), f"{expected.fitness:.4f}"]
    mean = lines[4].split()
    assert mean[0] == "mean"
    assert float(mean[-1]) == pytest.approx(sum(float(g[5]) for g in games) / 3, abs=1e-4)


def test_play_reads_json_and_writes_replays(demo_file, tmp_path):
    from soccer_lab.app.rulebase_files import rulebase_json

    as_json = tmp_path / "demo.json"
    as_json.write_text(rulebase_json(demo_rulebase(), VOCABULARY))
    rrd = tmp_path / "games.rrd"
    result = run("play", as_json, "--games", "2", "--max-ticks", "40", "--rrd", rrd)
    assert result.exit_code == 0, result.output
    from_text = run("play", demo_file, "--games", "2", "--max-ticks", "40")
    assert result.output.splitlines()[:4] == from_text.output.splitlines()[:4]
    entities = read_recording(rrd)
    for game in ("game_1", "game_2"):
        assert entities[f"/{game}/pitch"]["timelines"] == set()
        assert entities[f"/{game}/ball"]["timelines"] == {"tick"}


@pytest.mark.parametrize("content, fragments", [
    ("if Ball is Nearr then Turn Left\n", ["line 1, column 12", "Nearr"]),
    ('{"format": "soccer-lab-rulebase", "version": 1, "rules": 3}', ["rules: expected a list"]),
    ("# only a comment\n", ["holds no rule"]),
])
def test_play_rejects_bad_files_in_one_line(content, fragments, tmp_path):
    path = tmp_path / "bad.rules"
    path.write_text(content)
    assert_one_line_error(run("play", path), str(path), *fragments)


def test_play_rejects_missing_files_and_bad_options(demo_file, tmp_path):
    assert_one_line_error(run("play", tmp_path / "none.rules"), "no such file")
    assert_one_line_error(run("play", demo_file, "--games", "0"), "--games")
    assert_one_line_error(run("play", demo_file, "--rrd", tmp_path / "no" / "x.rrd"), "does not exist")


def test_the_progress_bar_follows_the_generation_in_progress():
    """The CLI's second bar: players evaluated of the population, reset for each new generation (issue 22)."""
    from types import SimpleNamespace

    from soccer_lab.app.cli.evolve import GenerationProgress

    bar = GenerationProgress(3)
    bar.on_progress(100, 250)
    within = bar.progress.tasks[bar.within]
    assert (within.completed, within.total, within.description) == (100, 250, "generation 0")
    bar.on_generation(SimpleNamespace(generation=0, best=0.5, mean=0.7))
    within = bar.progress.tasks[bar.within]
    assert (within.completed, within.description) == (0, "generation 1")
    assert bar.progress.tasks[bar.task].completed == 1
