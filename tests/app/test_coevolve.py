"""Co-evolution against a hall of fame from the command line, the run's folder and the web API: the run keeps its
hall settings in run.json, lineage names each generation's opponents, one seed fixes the run (resumed or not), and
bad options are refused in one line."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from soccer_lab.app.runs.outputs import LineageFile
from soccer_lab.app.runs.run import Run, RunSettings
from soccer_lab.ga.config import CoevolutionConfig, GAConfig
from soccer_lab.ga.lineage import record_opponents
from soccer_lab.soccer.config import GameConfig
from tests.app.api_client import SHORT_GAMES, TINY_GA, api_client, wait_for

REPOSITORY = Path(__file__).resolve().parents[2]
STRIKER = REPOSITORY / "soccer" / "data" / "examples" / "striker.rules"
SOCCER_LAB = Path(sys.executable).parent / "soccer-lab"
EVOLVE = ["--population-size", "8", "--generations", "3", "--max-ticks", "100", "--workers", "1", "--seed", "1"]
SETTINGS = RunSettings.build(GAConfig(population_size=8, max_generations=4, seed=2, workers=1),
                             GameConfig(max_ticks=100), coevolve={"hall_size": 2, "hall_sample": 2})


def run_command(*args: object) -> subprocess.CompletedProcess:
    return subprocess.run([str(SOCCER_LAB), *map(str, args)], capture_output=True, text=True, timeout=600)


def test_evolve_coevolve_keeps_the_hall_in_run_json_and_lineage_names_each_generations_opponents(tmp_path):
    done = run_command("evolve", *EVOLVE, "--coevolve", "--hall-size", "2", "--hall-sample", "2", "--out",
                       tmp_path / "run")
    assert done.returncode == 0, done.stderr
    assert "matches against the hall of fame" in done.stdout
    run = Run.open(tmp_path / "run")
    assert run.settings.coevolve == CoevolutionConfig(hall_size=2, hall_sample=2)
    assert RunSettings.from_dict(run.settings.to_dict()) == run.settings  # a resumed run co-evolves the same
    opponents = {g: record_opponents(line) for g, line in LineageFile.read(run.folder.lineage).items()}
    assert opponents[0] == ["the built-in demo"]
    assert opponents[1] == ["the built-in demo", "best of generation 0"]
    assert len(opponents[2]) == 2 and all(label in ("the built-in demo", "best of generation 0", "best of generation 1")
                                          for label in opponents[2])
    shown = run_command("lineage", tmp_path / "run", "--generation", "2")
    assert shown.returncode == 0, shown.stderr
    assert f"gen   2: {', '.join(opponents[2])}" in shown.stdout and "gen   0: the built-in demo" in shown.stdout
    import soccer_lab as sl

    api = sl.evolve(population_size=8, generations=3, seed=1, max_ticks=100, workers=1,
                    coevolve={"hall_size": 2, "hall_sample": 2}, out=tmp_path / "api")
    cli = sl.open_run(tmp_path / "run")
    assert [{k: v for k, v in row.items() if k != "wall_time"} for row in api.statistics] == \
        [{k: v for k, v in row.items() if k != "wall_time"} for row in cli.statistics]  # Python's API, the same run
    from soccer_lab.app.lineage.family_tree import RunLineage
    from soccer_lab.app.web.ui.panels.lineage import lineage_html

    lineage = RunLineage.from_folder(tmp_path / "run")
    shown_in_the_app = lineage_html(lineage.family_tree(lineage.place(2)), 1)  # the Lineage tab's view
    assert f'data-generation="2">gen 2: {", ".join(opponents[2])}</div>' in shown_in_the_app
    with_opponent = run_command("evolve", *EVOLVE, "--coevolve", "--opponent", STRIKER, "--out", tmp_path / "striker")
    assert with_opponent.returncode == 0, with_opponent.stderr
    first = record_opponents(LineageFile.read(tmp_path / "striker" / "lineage.jsonl")[0])
    assert first == ["the opponent given (run.json)"]


def play(folder: Path, stop_after: int | None = None):
    run = Run.create(SETTINGS, folder) if not (folder / "run.json").exists() else Run.open(folder)
    stop = threading.Event()

    def stopping(stats, population):
        if stats.generation == stop_after:
            stop.set()

    with run.evaluator() as evaluate:
        return run.play(evaluate, callbacks=[stopping], stop=stop)


def test_one_seed_fixes_a_coevolution_run_stopped_and_resumed_or_not(tmp_path):
    whole = play(tmp_path / "whole")
    part = play(tmp_path / "part", stop_after=1)
    assert len(part.history) == 2
    resumed = play(tmp_path / "part")
    for name in ("statistics.csv", "lineage.jsonl"):
        lines = [(tmp_path / folder / name).read_text().splitlines() for folder in ("whole", "part")]
        if name == "statistics.csv":  # but for the wall time
            lines = [[line.rsplit(",", 1)[0] for line in file] for file in lines]
        assert lines[0] == lines[1]
    assert [s.best for s in resumed.history] == [s.best for s in whole.history]
    assert (tmp_path / "whole" / "best.rules").read_text() == (tmp_path / "part" / "best.rules").read_text()


@pytest.mark.parametrize("args, fragment", [
    (["--hall-size", "3"], "--hall-size: with --coevolve only"),
    (["--coevolve", "--hall-sample", "0"], "--hall-sample"),
    (["--coevolve", "--env", "rcss", "--server", "localhost:6000"], "--coevolve"),
])
def test_evolve_refuses_bad_coevolution_options_in_one_line(args, fragment, tmp_path):
    done = run_command("evolve", *EVOLVE, *args, "--out", tmp_path / "run")
    assert done.returncode == 2 and fragment in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "run").exists()


def test_the_web_api_starts_a_coevolution_run_and_refuses_bad_hall_settings(tmp_path):
    with api_client(tmp_path) as client:
        response = client.post("/api/runs", json={"ga": TINY_GA, "game": SHORT_GAMES,
                                                  "coevolve": {"hall_size": 2, "hall_sample": 1}})
        assert response.status_code == 201, response.text
        run = response.json()
        assert run["config"]["coevolve"] == {"hall_size": 2, "hall_sample": 1}
        done = wait_for(lambda: (r := client.get(f"/api/runs/{run['id']}").json())["status"] != "running" and r,
                        what="the run to finish")
        assert done["status"] == "finished", done
        tree = client.get(f"/api/runs/{run['id']}/lineage").json()
        assert {"generation": 0, "opponents": ["the built-in demo"]} in tree["opponents"]
        for body in ({"coevolve": {"hall_size": 2, "hall_sample": 0}}, {"coevolve": {"members": 3}},
                     {"coevolve": {"hall_size": 2}, "env": "rcss", "ga": {**TINY_GA, "workers": 1}},
                     {"coevolve": {"hall_size": 2}, "algorithm": "random-search"}):
            refused = client.post("/api/runs", json={"ga": TINY_GA, **body})
            assert refused.status_code == 422, (body, refused.text)
        assert json.dumps(refused.json()).count("Traceback") == 0


def test_a_students_coevolution_run_counts_its_matches_against_the_class_bound_and_keeps_them():
    from soccer_lab.app.runs.manager import RunStateError
    from soccer_lab.app.web.classroom.settings import ClassSettings

    bound = ClassSettings(max_run_games=5_000)
    small = RunSettings.build({"population_size": 100, "max_generations": 4, "workers": 2},
                              coevolve={"hall_sample": 3})  # 100 x 4 x 3 matches x 2 halves = 2,400
    kept = bound.check_student_run(small)
    assert kept.coevolve == small.coevolve and kept.ga.workers == 1
    alone = RunSettings.build({"population_size": 600, "max_generations": 4})  # 2,400 games alone
    assert bound.check_student_run(alone).coevolve is None
    with pytest.raises(RunStateError, match="14,400 games .*6 match halves x 1 games per evaluation.* 5,000"):
        bound.check_student_run(RunSettings.build({"population_size": 600, "max_generations": 4},
                                                  coevolve={"hall_sample": 3}))  # 14,400 halves


@pytest.mark.parametrize("coevolve", [None, {"hall_size": 2, "hall_sample": 2}], ids=["fixed opponent", "co-evolved"])
def test_a_match_runs_recording_replays_each_generations_best_in_the_half_the_ga_scored(tmp_path, coevolve):
    from soccer_lab.soccer.examples import example
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.match import MatchTrace, play_matches
    from tests.app.test_recording import columns

    striker = example("striker")
    settings = RunSettings.build(GAConfig(population_size=6, max_generations=2, seed=4, workers=1),
                                 GameConfig(max_ticks=80), opponent=striker.text, coevolve=coevolve)
    run = Run.create(settings, tmp_path / "run")
    with run.evaluator() as evaluate:
        result = run.play(evaluate)
    game = run.best_game
    assert isinstance(game.trace, MatchTrace) and len(game.trace) == game.result.ticks + 1
    # generation 0 played the fixed opponent, or the founder it gave the hall: its best's replay is the very
    # first half the GA scored it on (one opponent, one match: the match's seed is the evaluation's own)
    from soccer_lab.app.runs.outputs import GenerationBestsFile
    from soccer_lab.ga.codec import ChromosomeCodec

    first = dict(GenerationBestsFile.read(run.folder.generation_bests))[0]
    scored = play_matches(ChromosomeCodec(SOCCER_VOCABULARY).decode(first.chromosome), striker.rulebase(SOCCER_VOCABULARY),
                          [first.first_seed], settings.game, SOCCER_VOCABULARY)[0].halves[0]
    goals = columns(run.folder.recording, "/replay/generation_0/score/goals")
    assert len(goals["tick"]) == scored.ticks + 1 and goals["Scalars:scalars"][-1] == [float(scored.goals[0])]
    for generation in range(2):
        ball = columns(run.folder.recording, f"/replay/generation_{generation}/ball")
        opponent = columns(run.folder.recording, f"/replay/generation_{generation}/opponent")
        assert ball["tick"] and ball["tick"] == opponent["tick"]
