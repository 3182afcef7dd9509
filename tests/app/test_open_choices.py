"""The choices the chapter leaves open (skill set, roulette weighting, noise, whether body pushes count as
kicks) as options of the CLI (play, evolve, random-search, experiment), the API and the experiment
options: each reaches the games or the GA it names, and a bad value is one line (CLI) or a 422 (API)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.experiment.presets import ExperimentOptions
from soccer_lab.app.experiment.runner import plan
from soccer_lab.ga.config import GAConfig
from soccer_lab.soccer.config import GameConfig
from tests.app.api_client import SHORT_GAMES, TINY_GA, api_client, wait_for

# "Kick toward the goal whenever the ball is in view": a striker only if the skill fetches the ball.
KICKER = "if Ball is VeryFar or Ball is not VeryFar then KickTowardGoal High\n"
# "Run at the ball whenever it is in view": it never kicks, it shoves the ball along with its body.
CHASER = "if Ball is VeryFar or Ball is not VeryFar then RunTowardBall High\n"
TINY = ["--population-size", "10", "--generations", "3", "--max-ticks", "150", "--workers", "1", "--seed", "3"]


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def table_rows(output: str) -> list[list[str]]:
    """The per-game rows of `play`'s table: game, seed, goals, kicks, ticks, fitness."""
    return [line.split() for line in output.strip().splitlines()[1:-1]]


def assert_one_line_error(result, *fragments: str) -> None:
    assert result.exit_code == 2, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith("error: ")
    for fragment in fragments:
        assert fragment in line


@pytest.fixture
def kicker(tmp_path) -> Path:
    path = tmp_path / "kicker.rules"
    path.write_text(KICKER)
    return path


def test_play_skills_decide_whether_kicking_skills_fetch_the_ball(kicker):
    assisted = run("play", kicker, "--games", "3", "--skills", "assisted")
    strict = run("play", kicker, "--games", "3", "--skills", "strict")
    assert assisted.exit_code == 0 and strict.exit_code == 0, assisted.output + strict.output
    assert all(int(row[2]) >= 1 for row in table_rows(assisted.output))  # goals
    assert all(row[3] == "0" and row[5] == "1.0000" for row in table_rows(strict.output))  # no kick, fitness 1.0


def test_play_count_touches_counts_the_chasers_pushes_as_kicks(tmp_path):
    chaser = tmp_path / "chaser.rules"
    chaser.write_text(CHASER)
    kicks_only = run("play", chaser, "--games", "2", "--max-ticks", "300")
    touches = run("play", chaser, "--games", "2", "--max-ticks", "300", "--count-touches")
    assert kicks_only.exit_code == 0 and touches.exit_code == 0, kicks_only.output + touches.output
    assert all(row[3] == "0" and row[5] == "1.0000" for row in table_rows(kicks_only.output))
    assert all(int(row[3]) > 0 and 0.5 < float(row[5]) < 0.8 for row in table_rows(touches.output))
    assert_one_line_error(run("play", chaser, "--count-touches", "--env", "rcss"), "--count-touches",
                          "SimpleSoccer only")


def test_evolve_records_and_uses_the_skills_and_the_roulette_weighting(tmp_path):
    runs = {}
    for skills, weighting in (("assisted", "inverse"), ("assisted", "linear"), ("strict", "linear")):
        folder = tmp_path / f"{skills}-{weighting}"
        result = run("evolve", *TINY, "--skills", skills, "--roulette-weighting", weighting, "--out", folder)
        assert result.exit_code == 0, result.output
        manifest = json.loads((folder / "run.json").read_text())
        assert manifest["game"]["skills"] == skills and manifest["ga"]["roulette_weighting"] == weighting
        with (folder / "statistics.csv").open(newline="") as handle:
            runs[skills, weighting] = [json.dumps({k: v for k, v in row.items() if k != "wall_time"})
                                       for row in csv.DictReader(handle)]
    # Same seed, so the same generation 0; the weighting changes who breeds, the skills what they do.
    assert runs["assisted", "inverse"][0] == runs["assisted", "linear"][0] != runs["strict", "linear"][0]
    assert runs["assisted", "inverse"][1:] != runs["assisted", "linear"][1:]


def test_random_search_takes_the_skill_set_and_counting_touches(tmp_path):
    folder = tmp_path / "search"
    result = run("random-search", "--population-size", "6", "--generations", "1", "--max-ticks", "40",
                 "--workers", "1", "--skills", "strict", "--count-touches", "--out", folder)
    assert result.exit_code == 0, result.output
    game = json.loads((folder / "run.json").read_text())["game"]
    assert game["skills"] == "strict" and game["count_touches"] is True


@pytest.mark.parametrize("command, args, fragments", [
    ("evolve", ["--skills", "lazy"], ["--skills", "'lazy'"]),
    ("evolve", ["--roulette-weighting", "square"], ["--roulette-weighting", "'square'"]),
    ("random-search", ["--skills", "lazy"], ["--skills", "'lazy'"]),
    ("play", ["--skills", "lazy"], ["--skills", "'lazy'"]),
    ("experiment", ["initial", "--skills", "lazy"], ["--skills", "'lazy'"]),
    ("experiment", ["initial", "--roulette-weighting", "square"], ["--roulette-weighting", "'square'"]),
])
def test_bad_choices_are_one_line(command, args, fragments, kicker, tmp_path):
    target = [kicker] if command == "play" else []
    out = [] if command == "play" else ["--out", tmp_path / "out"]
    extra = ["--no-library"] if command == "experiment" else []
    assert_one_line_error(run(command, *target, *args, *out, *extra), *fragments)
    assert not (tmp_path / "out").exists()


def test_experiment_options_reach_every_trial():
    options = ExperimentOptions(trials=1, population=4, generations=2, skills="strict", noise=True,
                                count_touches=True, roulette_weighting="linear")
    specs = plan("all", options).specs
    assert {(spec.game.skills, spec.game.noise, spec.game.count_touches) for spec in specs} == {("strict", True, True)}
    assert {spec.setting.ga.roulette_weighting for spec in specs} == {"linear"}
    other = plan("all", options.model_copy(update={"roulette_weighting": "inverse"})).specs
    assert {s.name for s in specs}.isdisjoint(s.name for s in other)  # other trials, not reused ones


def test_experiment_defaults_are_the_game_and_ga_defaults():
    options = ExperimentOptions()
    assert options.game().skills == GameConfig().skills and options.game().noise == GameConfig().noise
    assert options.game().count_touches == GameConfig().count_touches
    assert options.roulette_weighting == GAConfig().roulette_weighting


def test_experiment_refuses_a_folder_of_another_skill_set(tmp_path):
    base = ["experiment", "crossover", "--trials", "1", "--population", "4", "--generations", "1", "--max-ticks",
            "20", "--workers", "1", "--out", tmp_path, "--no-library"]
    first = run(*base, "--skills", "assisted")
    assert first.exit_code == 0, first.output
    assert json.loads((tmp_path / "manifest.json").read_text())["skills"] == "assisted"
    refused = run(*base, "--skills", "strict")
    assert refused.exit_code == 2 and "holds an experiment with other options (skills)" in refused.output


def test_api_publishes_validates_and_runs_the_choices(tmp_path):
    with api_client(tmp_path) as client:
        vocabulary = client.get("/api/vocabulary").json()
        assert vocabulary["game_defaults"]["skills"] == GameConfig().skills
        assert vocabulary["game_defaults"]["noise"] == GameConfig().noise
        assert vocabulary["game_defaults"]["count_touches"] == GameConfig().count_touches
        assert vocabulary["ga_defaults"]["roulette_weighting"] == GAConfig().roulette_weighting
        for body, field in (({"game": {"skills": "lazy"}}, "skills"),
                            ({"ga": {"roulette_weighting": "square"}}, "roulette_weighting"),
                            ({"game": {"count_touches": "sometimes"}}, "count_touches"),
                            ({"env": "rcss", "ga": {"workers": 1}, "trial": {"skills": "lazy"}}, "skills")):
            response = client.post("/api/runs", json=body)
            assert response.status_code == 422 and field in response.json()["detail"]
        response = client.post("/api/runs", json={"ga": {**TINY_GA, "roulette_weighting": "linear"},
                                                   "game": {**SHORT_GAMES, "skills": "strict", "count_touches": True}})
        assert response.status_code == 201, response.text
        run_id = response.json()["id"]
        done = wait_for(lambda: (r := client.get(f"/api/runs/{run_id}").json())["status"] != "running" and r,
                        what="the run to finish")
        assert done["status"] == "finished"
        assert done["config"]["game"]["skills"] == "strict" and done["config"]["ga"]["roulette_weighting"] == "linear"
        assert done["config"]["game"]["count_touches"] is True
