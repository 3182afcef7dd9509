"""The matches preset (app/experiment/matches.py): its settings, its co-evolved trials' crowd share by generation,
its questions answered by matches between the trials' bests (the same folder, the same answers), with replicates;
and the answers' logic on fabricated data."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.figures import FIGURES_FOLDER
from soccer_lab.app.experiment.matches import (NO_DIFFERENCE, head_to_head, kiddie_soccer, matches_answers,
                                               matches_study)
from soccer_lab.app.experiment.presets import (ALL_PLUS, ALONE, COEVOLUTION, COEVOLVED, MATCHES, SEEING,
                                               ExperimentOptions, preset, presets)
from soccer_lab.app.experiment.replicates import VERDICTS_FILE, run_replicates
from soccer_lab.app.experiment.report import REPORT_MD
from soccer_lab.app.experiment.runner import TRIALS_FOLDER, plan, run_experiment
from soccer_lab.app.experiment.table import BestsTable
from soccer_lab.app.experiment.verdicts import TOO_SMALL

TINY = ExperimentOptions(trials=2, population=6, generations=3, max_ticks=80, seed=3, replays=2)


def test_the_matches_preset_shares_its_alone_trials_with_initial_and_stays_out_of_all_plus():
    full = preset(MATCHES, ExperimentOptions())
    alone, coevolved, seeing = full.settings
    assert [s.label for s in full.settings] == [ALONE, COEVOLVED, SEEING] and full.trials == 10
    assert alone.key == preset("initial", ExperimentOptions()).settings[0].key  # the chapter's Table 2 trials
    assert (coevolved.coevolve, seeing.coevolve) == (COEVOLUTION, COEVOLUTION)
    assert not coevolved.see_opponent and seeing.see_opponent and len({s.key for s in full.settings}) == 3
    assert coevolved.ga == alone.ga  # Table 2 in every setting: only whom it plays differs
    assert coevolved.games == 4 * COEVOLUTION.hall_sample * alone.games
    assert MATCHES not in {p.name for p in presets(ALL_PLUS, ExperimentOptions())}


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("matches")
    return run_experiment(MATCHES, TINY, folder, LocalExecutor(2)), folder


def test_a_shrunk_matches_run_records_the_crowd_share_and_answers_its_four_questions(tiny_run):
    outcome, folder = tiny_run
    answers = [(q.where, a) for q, a in outcome.report.answers if q.preset == MATCHES]
    assert [where for where, _ in answers] == [f"background ({letter})" for letter in "abcd"]
    assert all(a.verdict == TOO_SMALL and a.measured != "-" for _, a in answers)  # measured, not judged
    spec = next(s for s in plan(MATCHES, TINY).specs if s.setting.label == SEEING)
    record = json.loads((folder / TRIALS_FOLDER / f"{spec.name}.best.json").read_text())
    assert len(record["crowd_share"]) == TINY.generations and all(0 <= s <= 1 for s in record["crowd_share"])
    assert record["see_opponent"] is True and record["game"]["max_ticks"] == TINY.max_ticks
    for kind in ("crowd_share", "head_to_head", "mean_fitness"):
        assert (folder / FIGURES_FOLDER / f"{MATCHES}-{kind}.png").read_bytes().startswith(b"\x89PNG")
    markdown = (folder / REPORT_MD).read_text()
    assert "Does a co-evolved player beat the chapter's best" in markdown and "within 5 m of the ball" in markdown


def test_the_same_folder_gives_the_same_matches(tiny_run):
    _, folder = tiny_run
    chosen = preset(MATCHES, TINY)
    bests = BestsTable.read(folder / "bests.csv")
    first, again = matches_study(folder, chosen, bests), matches_study(folder, chosen, bests)
    assert len(first.against_demo) == len(first.coevolved_against_alone) == TINY.trials
    np.testing.assert_array_equal(first.against_demo, again.against_demo)
    np.testing.assert_array_equal(first.seeing_against_coevolved, again.seeing_against_coevolved)
    assert set(first.crowd) == {COEVOLVED, SEEING} and first.crowd[COEVOLVED].shape == (TINY.trials, TINY.generations)


def test_replicates_of_the_matches_preset_summarise_its_answers(tmp_path):
    outcome = run_replicates(MATCHES, TINY.model_copy(update={"trials": 1, "generations": 2}), [0, 1], tmp_path,
                             LocalExecutor(2))
    with (tmp_path / VERDICTS_FILE).open(newline="") as handle:
        rows = [row for row in csv.DictReader(handle) if row["preset"] == MATCHES]
    assert len(rows) == 4 and all(row["seed 0"] and row["seed 1"] for row in rows)
    assert len(outcome.replicates) == 2


# ---- the answers on fabricated data ----------------------------------------------------------------------
def test_head_to_head_says_who_wins_only_when_the_test_finds_it():
    wins = head_to_head(np.array([0.5, 1.0, 0.75, 1.5, 0.25, 2.0, 0.6, 0.9]), "co-evolved", "alone", 0.7, "4 each")
    assert wins.verdict == "yes: co-evolved beats alone" and "p = 0.00781" in wins.test and wins.reason
    loses = head_to_head(-np.array([0.5, 1.0, 0.75, 1.5, 0.25, 2.0, 0.6, 0.9]), "alone", "the demo", 0.1, "20")
    assert loses.verdict == "no: the demo beats alone"
    even = head_to_head(np.array([0.5, -1.0, 0.75, -1.5, 0.25, -0.3, 0.6, -0.9]), "seeing", "co-evolved", 0.5, "4")
    assert even.verdict == NO_DIFFERENCE and "could have detected a mean goal difference of about" in even.test
    assert even.no_difference_found


def test_kiddie_soccer_appears_and_passes_only_with_a_rise_then_a_fall():
    rng = np.random.default_rng(0)
    hump = 0.1 + 0.3 * np.sin(np.linspace(0, np.pi, 9)) + rng.uniform(0, 0.02, (8, 9))
    assert kiddie_soccer({COEVOLVED: hump}).verdict == "appears and passes"
    rising = np.linspace(0.1, 0.5, 9) + rng.uniform(0, 0.02, (8, 9))
    assert kiddie_soccer({COEVOLVED: rising}).verdict == "appears, does not pass"
    flat = 0.2 + rng.uniform(-0.05, 0.05, (8, 9))
    assert kiddie_soccer({COEVOLVED: flat}).verdict.startswith("no rise")


def test_an_empty_study_answers_not_run(tmp_path):
    chosen = preset(MATCHES, TINY)
    study = matches_study(tmp_path, chosen, BestsTable([]))
    assert not study.played
    assert {a.verdict for a in matches_answers(study).values()} == {"not run"}


KILLED_TRIAL = """
import sys, pickle
from soccer_lab.app.experiment.matches import run_coevolution_trial
run_coevolution_trial(pickle.loads(bytes.fromhex(sys.argv[1])))
"""


def test_a_killed_coevolved_trial_resumes_from_its_checkpoint_and_ends_as_the_uninterrupted_one(tmp_path):
    import os
    import pickle
    import signal
    import subprocess
    import sys
    import time
    from dataclasses import replace

    from soccer_lab.app.experiment.matches import run_coevolution_trial
    from soccer_lab.app.experiment.trial_result import crowd_file

    options = TINY.model_copy(update={"generations": 8})
    spec = next(s for s in plan(MATCHES, options).specs if s.setting.label == COEVOLVED)
    whole = run_coevolution_trial(replace(spec, checkpoint=tmp_path / "whole.checkpoint"))
    checkpoint = tmp_path / "killed.checkpoint"
    killed = replace(spec, checkpoint=checkpoint)
    process = subprocess.Popen([sys.executable, "-c", KILLED_TRIAL, pickle.dumps(killed).hex()])
    deadline = time.monotonic() + 300
    while not (checkpoint.is_file() and len(json.loads(checkpoint.read_text())["history"]) >= 2):
        assert process.poll() is None, "the trial ended before it could be killed"
        assert time.monotonic() < deadline, "no checkpoint of generation 1"
        time.sleep(0.01)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    assert len(json.loads(checkpoint.read_text())["history"]) < options.generations  # really mid-run
    assert crowd_file(checkpoint).is_file()
    resumed = run_coevolution_trial(killed)
    drop = ("wall_time",)
    assert [{k: v for k, v in row.items() if k not in drop} for row in resumed.rows] == \
        [{k: v for k, v in row.items() if k not in drop} for row in whole.rows]
    assert resumed.best["chromosome"] == whole.best["chromosome"]
    assert np.allclose(resumed.best["crowd_share"], whole.best["crowd_share"], equal_nan=True)
    assert len(resumed.best["crowd_share"]) == options.generations


def test_the_study_is_recorded_for_the_docs_with_how_far_it_got_and_its_answers(tiny_run, tmp_path):
    """scripts/matches_results.py's record and docs/hooks/matches_results.py's tables: an unfinished study says
    how far it got and shows the crowd share so far, a finished one its four answers."""
    import importlib.util
    import shutil
    from pathlib import Path

    def load(path: Path, name: str):
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    root = Path(__file__).resolve().parents[2]
    script = load(root / "scripts" / "matches_results.py", "matches_results_script")
    hook = load(root / "docs" / "hooks" / "matches_results.py", "matches_results_hook")
    _, folder = tiny_run
    record = script.matches_record(folder, "soccer-lab experiment matches --trials 2")
    assert record["complete"] and [a["where"] for a in record["answers"]] == [f"background ({x})" for x in "abcd"]
    assert set(record["crowd_share"]) == {COEVOLVED, SEEING}
    results = tmp_path / "matches.json"
    results.write_text(json.dumps(record))
    page = hook.render(f"{hook.RUN}\n\n{hook.ANSWERS}\n", results)
    assert "Finished." in page and "Kiddie soccer so far" in page and "Does seeing the opponent help" in page
    # the answers at more seeds (a --seeds run's verdicts.csv), per seed and robust
    replicates = tmp_path / "replicates"
    replicates.mkdir()
    (replicates / "verdicts.csv").write_text(
        "preset,chapter,claim,seed 1,seed 2,summary,robust\n"
        "matches,background (a),Does it?,no: the demo beats alone,no: the demo beats alone,2 of 2,no: the demo beats alone\n"
        "matches,background (b),Does it?,no significant difference,co-evolved wins,1 of 2,varies with the seed\n")
    record["replicates"] = script.replicates_record(replicates, "soccer-lab experiment matches --seeds 1,2")
    assert record["replicates"]["seeds"] == [1, 2]
    results.write_text(json.dumps(record))
    page = hook.render(f"{hook.ANSWERS}\n", results)
    assert "| background (b) | no significant difference | co-evolved wins | varies with the seed |" in page
    unfinished = tmp_path / "unfinished"
    shutil.copytree(folder, unfinished)
    next((unfinished / TRIALS_FOLDER).glob("*-coevolved-seeing-*-1.csv")).unlink()
    partial = script.matches_record(unfinished, "")
    assert not partial["complete"] and partial["answers"] == []
    assert {p["setting"]: p["finished"] for p in partial["progress"]}[SEEING] == 1
    results.write_text(json.dumps(partial))
    page = hook.render(f"{hook.RUN}\n\n{hook.ANSWERS}\n", results)
    assert "**Not finished**" in page and "No answers yet" in page
