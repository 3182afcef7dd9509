"""scripts/robocup_disagreement.py's parts that need no server (what a study's folder records of its high scorers,
which players are replayed) and the docs hook that shows its file (docs/hooks/robocup_pages.py). The replays
themselves are the script's run; the trial options they use are tested on real servers
(tests/rcss/test_real_server.py)."""

from __future__ import annotations

import json

import numpy as np

from soccer_lab.app.experiment.presets import ExperimentOptions
from soccer_lab.app.experiment.runner import MANIFEST
from soccer_lab.app.experiment.table import StatisticsTable
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from tests.app.test_experiment_report import fabricated
from tests.app.test_robocup_results import ROOT, load, pages

script = load(ROOT / "scripts" / "robocup_disagreement.py", "robocup_disagreement_script")


def test_the_study_summary_reads_each_generations_most_goals_from_its_best_fitness(tmp_path):
    # 3 trials x 4 generations, population 20: best fitness 1 / (2 goals) for a scorer, above 0.5 for none
    best = np.array([[1.0, 0.5, 0.25, 0.1], [0.9, 0.8, 0.5, 0.125], [1.0, 1.0, 0.95, 0.9]])
    more = np.zeros((3, 4))
    more[0, 3] = 0.05  # one of 20 scored more than 4
    four = np.zeros((3, 4))
    four[1, 3] = 0.1
    shares = {"best": best, "goals_1": np.where(best == 0.5, 0.05, 0.0), "goals_4": four, "goals_more": more}
    rows = fabricated("robocup", {"Table 2": shares})
    (tmp_path / MANIFEST).write_text(json.dumps(ExperimentOptions(population=20, generations=4).identity()))
    (tmp_path / "statistics.csv").write_text(StatisticsTable(rows).to_csv())
    study = script.study_summary(tmp_path)
    assert [t["most_goals_by_generation"] for t in study["trials"]] == [[0, 1, 2, 5], [0, 0, 1, 4], [0, 0, 0, 0]]
    assert study["most_goals"] == 5 and study["trials_by_most_goals"] == {"0": 1, "1": 0, "2": 0, "3": 0, "4": 1, "5": 1}
    assert (study["evaluations_4_goals"], study["evaluations_more_than_4"], study["evaluations"]) == (2, 1, 240)
    # the trials run again: those whose first scorer of more than 3 came first
    assert [t["trial"] for t in script.choose_trials(study, 2)] == [0, 1]


def rulebase(power: str) -> Rulebase:
    return parse_rulebase(f"if Ball is At then KickTowardGoal {power}", SOCCER_VOCABULARY)


def test_the_players_are_each_trials_highest_scorers_in_turn_distinct_and_never_empty():
    a, b, c, d = (rulebase(p) for p in ("Low", "MediumPower", "High", "VeryHigh"))
    found = [(6, 9, 1, a), (6, 9, 2, a), (5, 9, 1, b), (5, 9, 3, c), (4, 0, 2, d), (7, 0, 1, Rulebase(())),
             (2, 0, 0, b), (3, 0, 1, rulebase("VeryLow"))]
    chosen = script.choose_players(found, [9, 0], 4)
    assert [(p["trial"], p["generation"], p["goals_seen"]) for p in chosen] == [(9, 1, 6), (0, 2, 4), (9, 1, 5), (9, 3, 5)]
    assert chosen[0]["rules"] == "if Ball is At then KickTowardGoal Low"
    more = script.choose_players(found, [9, 0], 10)  # past the high scorers: the highest of the rest
    assert [p["goals_seen"] for p in more] == [6, 4, 5, 5, 3]


def record() -> dict:
    condition = lambda name, factor, goals: {
        "name": name, "factor": factor, "condition": f"{name} changed", "options": {}, "goals": goals,
        "most_goals": int(np.max(goals)), "mean_goals": float(np.mean(goals)), "share_more_than_3": 0.5,
        "share_more_than_4": 0.25, "agrees": abs(int(np.max(goals)) - 3) <= 1, "ends": {"time": 3, "out of play": 1},
        "late_cycles": 0, "cycles": 4000, "seconds": 5.0, "mean_kicks": 12.5}
    trial = {"trial": 9, "seed": 1, "most_goals_by_generation": [1, 5], "evaluations_4_goals": 7,
             "evaluations_more_than_4": 2, "most_goals": 5}
    return {"recorded": "2026-01-01", "command": "scripts/robocup_disagreement.py study", "seed": 0, "starts": 2,
            "start_seeds": [1, 2], "servers": 2, "chapter_most_goals": 3, "tolerance": 1,
            "study": {"folder": "study", "population": 20, "generations": 2, "evaluations": 40, "most_goals": 5,
                      "trials_by_most_goals": {"5": 1}, "evaluations_4_goals": 7, "evaluations_more_than_4": 2,
                      "trials": [trial]},
            "players": {"how": "found again", "generations": 2, "seconds": 1.0,
                        "trials_run_again": [{"trial": 9, "seed": 1, "most_goals_by_generation": [1, 6],
                                              "study_most_goals_by_generation": [1, 5], "evaluations_4_goals": 3,
                                              "evaluations_more_than_4": 1}],
                        "players": [{"trial": 9, "generation": 1, "goals_seen": 6, "rules": "if Ball is At then Dash"}] * 2},
            "conditions": [condition("study", "none", [[6, 5], [2, 1]]), condition("slow", "restart", [[3, 4], [1, 0]]),
                           condition("late", "late answers", [[1, 0], [0, 0]]),
                           condition("both", "both", [[3, 1], [0, 0]])],
            "finished": True, "wall_time_seconds": 90.0, "load_average_before": [1.0, 1.0, 1.0],
            "load_average_after": [2.0, 1.5, 1.0], "cores": 2}


def test_the_page_shows_the_measured_conditions_or_says_nothing_was_measured(tmp_path):
    page = f"# Disagreement\n\n{pages.DISAGREEMENT_MARKER}\n"
    assert "Not measured yet: `nice -n 19 .venv/bin/python scripts/robocup_disagreement.py FOLDER`" in pages.render(
        page, results=tmp_path)
    (tmp_path / "disagreement.json").write_text(json.dumps(record()))
    shown = pages.render(page, results=tmp_path)
    assert pages.DISAGREEMENT_MARKER not in shown
    assert "the most goals any individual scored was 5; 1 of its 1 GA trials had an individual scoring more than 3" in shown
    assert "trial 9: 1 6 / 1 5" in shown
    assert "| `study` | study changed | 3.50 | 6 | 50% | 25% | DISAGREES (more) | 12.5 | 3 time, 1 out of play |" in shown
    assert "| `slow` | slow changed | 2.00 | 4 | 50% | 25% | agrees |" in shown
    assert "| `late` | late changed | 0.25 | 1 | 50% | 25% | DISAGREES (fewer) |" in shown
    assert ("Of the single changes (most goals in brackets), `slow` (4) brings the most goals to within 1 of the "
            "chapter's 3; but some trials score more than 3 under it; `late` (1) stops nearly all scoring.") in shown


def test_the_conclusion_names_the_changes_that_leave_no_trial_above_the_chapters_most():
    measured = record()
    jitter = dict(measured["conditions"][2], name="jitter", goals=[[3, 2], [1, 0]], most_goals=3, agrees=True)
    measured["conditions"].insert(3, jitter)
    assert pages.disagreement_markdown(measured).count(
        "Of the single changes (most goals in brackets), `slow` (4) and `jitter` (3) bring the most goals to within 1 of "
        "the chapter's 3; only under `jitter` (3) does no trial score more than 3; `late` (1) stops nearly all "
        "scoring.") == 1
