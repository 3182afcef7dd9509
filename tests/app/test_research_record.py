"""The research guide's measured tables: what scripts/research_figures.py --record reads from a replicates
folder (progress against the plan, each invocation's wall time and load, verdicts and answers once
finished), and how docs/hooks/research_results.py shows it, finished or not."""

from __future__ import annotations

import csv
import importlib.util
import json
from pathlib import Path

import pytest

from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.presets import ExperimentOptions
from soccer_lab.app.experiment.replicates import VERDICTS_FILE, replicate_folder, run_replicates
from soccer_lab.app.experiment.runner import RUNS_LOG, read_runs

ROOT = Path(__file__).resolve().parents[2]
TINY = ExperimentOptions(trials=2, population=6, generations=2, max_ticks=40, seed=7, replays=2)
COMMAND = "soccer-lab experiment restarts --seeds 7,8 --trials 2 --population 6"


def load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


script = load(ROOT / "scripts" / "research_figures.py", "research_figures")
hook = load(ROOT / "docs" / "hooks" / "research_results.py", "research_results")
PAGE = f"# Page\n\n{hook.RUN}\n\n{hook.VERDICTS}\n\n{hook.ANSWERS}\n"


@pytest.fixture(scope="module")
def study(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("study") / "restarts"
    run_replicates("restarts", TINY, [7, 8], folder, LocalExecutor(1))
    run_replicates("restarts", TINY, [7, 8], folder, LocalExecutor(1))  # resumed: nothing left to run
    return folder


def test_each_invocation_logs_its_wall_time_trials_and_load(study):
    first, again = read_runs(study)
    assert (first["preset"], first["seeds"], first["trials"], first["ran"], first["skipped"]) == (
        "restarts", [7, 8], 2, 8, 0)
    assert (again["ran"], again["skipped"]) == (0, 8)
    assert first["seconds"] > again["seconds"] >= 0 and first["cores"] >= 1
    assert len(first["load_average_before"]) == len(first["load_average_after"]) == 3
    assert len((study / RUNS_LOG).read_text().splitlines()) == 2


def test_a_finished_study_is_recorded_with_its_verdicts_and_answers(study, tmp_path):
    path = script.record_study(study, COMMAND, tmp_path)
    record = json.loads(path.read_text())
    assert (record["command"], record["seeds"], record["complete"]) == (COMMAND, [7, 8], True)
    assert record["size"]["population"] == 6 and record["size"]["replays"] == 2
    assert [(p["experiment"], p["seed"], p["finished"], p["trials"]) for p in record["progress"]] == [
        ("restarts", 7, 4, 4), ("restarts", 8, 4, 4)]
    assert record["runs"] == read_runs(study)
    with (study / VERDICTS_FILE).open(newline="") as handle:
        assert record["verdicts"] == list(csv.DictReader(handle))
    assert [(a["preset"], a["seed"]) for a in record["answers"]] == [("restarts", 7), ("restarts", 8)]
    assert all(a["answer"].startswith("too small to judge (needs") and "Mann-Whitney U" in a["test"]
               for a in record["answers"])

    page = hook.render(PAGE, path)
    assert "Command: `soccer-lab experiment restarts --seeds 7,8" in page and "Finished." in page
    assert "| restarts | 8 | 4 of 4 |" in page
    assert "| restarts seeds 7,8 |" in page and "Wall time, all invocations:" in page
    assert record["verdicts"][0]["claim"].replace("|", "\\|") in page
    assert record["answers"][1]["measured"].replace("|", "\\|") in page
    assert "generated: research" not in page


def test_an_unfinished_study_says_how_far_it_got_and_shows_no_verdict(study, tmp_path):
    unfinished = tmp_path / "unfinished"
    for source in study.rglob("*"):
        if source.is_file() and source.name != VERDICTS_FILE:
            target = unfinished / source.relative_to(study)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(source.read_bytes())
    (unfinished / RUNS_LOG).unlink()  # a folder from before the log: progress against `all` and `all-plus`
    trial = sorted((replicate_folder(unfinished, 8) / "trials").glob("*.csv"))[0]
    trial.unlink()
    record = script.study_record(unfinished, "")
    assert record["complete"] is False and record["verdicts"] == [] and record["runs"] == []
    assert {p["experiment"] for p in record["progress"]} == {"all", "all-plus"}
    assert all(p["finished"] < p["trials"] for p in record["progress"])
    (tmp_path / "study.json").write_text(json.dumps(record))
    page = hook.render(PAGE, tmp_path / "study.json")
    assert "**Not finished**" in page and "No verdicts yet" in page and "No answers yet" in page
    assert "No invocation of this folder finished" in page


def test_nothing_recorded_says_how_to_record_it(tmp_path):
    page = hook.render(PAGE, tmp_path / "missing.json")
    assert page.count(hook.NOT_RECORDED) == 3
    assert hook.render("# no markers", tmp_path / "missing.json") == "# no markers"


def test_the_verdicts_open_with_the_chapters_findings_counted_by_robust_verdict(tmp_path):
    row = {"preset": "initial", "chapter": "6.2", "claim": "c", "seed 0": "agrees", "seed 1": "agrees",
           "summary": "agrees in 2 of 2"}
    rows = [{**row, "robust": "agrees"}, {**row, "robust": "agrees"}, {**row, "robust": "varies with the seed"},
            {**row, "preset": "restarts", "robust": "no significant difference"}]  # a question, not a finding
    page = hook.verdicts_section({"verdicts": rows, "seeds": [0, 1]})
    assert page.startswith("The chapter's 3 findings at 2 seeds: **2** agrees, **1** varies with the seed.\n\n|")
    assert not hook.verdicts_section({"verdicts": rows[3:], "seeds": [0, 1]}).startswith("The chapter's")


def test_seeds_judged_again_are_merged_with_the_seeds_whose_verdicts_are_current(tmp_path):
    """Seeds 1 and 2 of the three-seed study were judged with the verdict tests of the day before: re-run into
    a folder of their own, they replace those seeds' verdicts, and seed 0's (current), the questions beyond the
    chapter and every invocation are kept from the earlier record; summary and robust verdict are counted again."""
    finding = {"preset": "max-length", "chapter": "6.4.1, Fig. 16", "claim": "settles at about 2/3"}
    question = {"preset": "restarts", "chapter": "beyond", "claim": "do restarts help?", "seed 0": "no difference",
                "seed 1": "no difference", "seed 2": "no difference", "summary": "'no difference' in 3 of 3",
                "robust": "no difference"}

    def run(seeds):
        return {"preset": "all", "seeds": seeds, "started": "2026-12-04T12:38:51+00:00", "seconds": 60.0, "ran": 2,
                "skipped": 0, "load_average_before": [0.5, 0.2, 0.1], "load_average_after": [2.0, 2.0, 2.0],
                "cores": 2}

    def progress(experiment, seed):
        return {"experiment": experiment, "seed": seed, "trials": 2, "finished": 2, "games": 10, "games_finished": 10}

    size = {"population": 200, "generations": 25, "max_ticks": 1000, "replays": 100}
    earlier = {"folder": "all-x3", "recorded": "2026-12-04T14:09:21+00:00", "command": "experiment all-plus",
               "size": size, "seeds": [0, 1, 2], "complete": True,
               "progress": [progress(e, s) for e in ("all", "all-plus") for s in (0, 1, 2)],
               "runs": [run([0, 1, 2])],
               "verdicts": [{**finding, "seed 0": "agrees", "seed 1": "disagrees", "seed 2": "disagrees",
                             "summary": "agrees in 1 of 3", "robust": "varies with the seed"}, question],
               "answers": [{"preset": "restarts", "where": "beyond", "seed": s, "question": "do restarts help?",
                            "answer": "no difference", "measured": "0.1 vs 0.1", "test": "Mann-Whitney U"}
                           for s in (0, 1, 2)]}
    new = {"folder": "all-s12", "recorded": "2026-12-05T15:00:00+00:00", "command": "experiment all --seeds 1,2",
           "size": size, "seeds": [1, 2], "complete": True, "progress": [progress("all", s) for s in (1, 2)],
           "runs": [run([1, 2])],
           "verdicts": [{**finding, "seed 1": "agrees", "seed 2": "agrees", "summary": "agrees in 2 of 2",
                         "robust": "agrees"}], "answers": []}
    merged = script.merged_record(new, earlier)
    assert merged["seeds"] == [0, 1, 2] and merged["complete"] and merged["folder"] == "all-s12 + all-x3"
    assert merged["verdicts"] == [{**finding, "seed 0": "agrees", "seed 1": "agrees", "seed 2": "agrees",
                                   "summary": "agrees in 3 of 3", "robust": "agrees"}, question]
    assert [(p["experiment"], p["seed"]) for p in merged["progress"]] == [
        ("all", 0), ("all", 1), ("all", 2), ("all-plus", 0), ("all-plus", 1), ("all-plus", 2)]
    assert merged["runs"] == earlier["runs"] + new["runs"] and merged["answers"] == earlier["answers"]
    assert "all --seeds 1,2; the rest kept from all-x3 (recorded 2026-12-04" in merged["command"]
    (tmp_path / "study.json").write_text(json.dumps(merged))
    page = hook.render(PAGE, tmp_path / "study.json")
    assert ("| max-length | 6.4.1, Fig. 16 | settles at about 2/3 | agrees | agrees | agrees | agrees in 3 of 3 |"
            in page)
    grid = script.verdict_grid(merged, tmp_path / "images")
    assert grid.stat().st_size > 0
