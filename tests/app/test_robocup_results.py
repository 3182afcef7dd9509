"""scripts/robocup_results.py and the docs hook that shows its files (docs/hooks/robocup_pages.py): a robocup
study's folder, finished or stopped part-way, becomes docs/results/robocup/study.json (its size, wall time and
the six findings over its finished trials) and its Figs. 8-10 in docs/images/robocup/, and the RoboCup
guide's pages show that file's figures, or say that nothing was recorded."""

from __future__ import annotations

import csv
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from soccer_lab.app.experiment.presets import ROBOCUP, ExperimentOptions, preset
from soccer_lab.app.experiment.report import assess_findings
from soccer_lab.app.experiment.runner import MANIFEST, TrialFolder, plan
from soccer_lab.app.experiment.table import STATISTIC_COLUMNS, StatisticsTable
from tests.app.test_experiment_robocup import robocup_rows

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "robocup_results.py"


def load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


results = load(SCRIPT, "robocup_results_script")
pages = load(ROOT / "docs" / "hooks" / "robocup_pages.py", "robocup_pages_hook")
OPTIONS = ExperimentOptions(population=20, generations=10)  # robocup_rows' size; 1200-cycle trials, as the CLI's


def stopped_study(folder: Path, finished: int) -> list[dict]:
    """A robocup folder as `experiment robocup --population 20 --generations 10` leaves it when stopped after
    `finished` of its 20 trials: manifest and finished trial files (fabricated statistics). Their rows."""
    rows = robocup_rows(np.random.default_rng(5), final_mean=0.55, most_goals_column="goals_3")
    folder.mkdir()
    (folder / MANIFEST).write_text(json.dumps(OPTIONS.identity()))
    trials = TrialFolder(folder)
    kept = []
    for membership in plan(ROBOCUP, OPTIONS).memberships[:finished]:
        trial = membership.spec.trial  # robocup_rows has 10 trials: the second ten repeat them
        trial_rows = [dict(row, trial=trial, wall_time=30.0 * (row["generation"] + 1) + trial)
                      for row in rows if row["trial"] == trial % 10]
        with trials.statistics(membership.spec).open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=STATISTIC_COLUMNS, extrasaction="ignore")
            writer.writeheader()
            writer.writerows(trial_rows)
        kept += trial_rows
    (folder / "trials" / "unrelated-0.checkpoint").write_text("a trial under way is not a finished one")
    return kept


def test_a_study_stopped_part_way_is_recorded_with_its_size_wall_time_findings_and_figures(tmp_path):
    kept = stopped_study(tmp_path / "study", finished=7)
    images = tmp_path / "images"
    record = results.study_record(tmp_path / "study", images, command="soccer-lab experiment robocup --servers 2")
    assert (record["trials_finished"], record["trials_planned"]) == (7, 20)
    assert (record["population"], record["generations"], record["max_cycles"], record["server_noise"]) == (
        20, 10, 1200, True)
    last = [row["wall_time"] for row in kept if row["generation"] == 9]
    assert record["trial_wall_time_seconds"] == last and record["wall_time_seconds"] == round(sum(last), 1)
    assert record["evaluations"] == 7 * 200
    expected = assess_findings(StatisticsTable(kept), [preset(ROBOCUP, OPTIONS)])
    assert [(f["claim"], f["verdict"], f["measured"]) for f in record["findings"]] == [
        (f.claim, a.verdict, a.measured) for f, a in expected if f.preset == ROBOCUP]
    assert len(record["findings"]) == 6
    for figure in record["figures"]:
        assert (images / Path(figure["file"]).name).read_bytes().startswith(b"\x89PNG")
    assert [Path(f["file"]).name for f in record["figures"]] == [
        "robocup-mean_fitness.png", "robocup-best_fitness.png", "robocup-goal_histogram.png"]

    shown = pages.study_markdown(record, page_depth=1)
    assert "**Run part-way:** 7 of the 20 GA trials of population 20 x 10 generations" in shown
    assert "the findings below are those of the 7 finished trials".lower() in shown.lower()
    assert "`soccer-lab experiment robocup --servers 2`" in shown
    assert "![RoboCup initial trials (Table 2 on rcssserver): population average fitness (chapter Fig. 8)]" \
           "(../images/robocup/robocup-mean_fitness.png)" in shown
    assert shown.count("| 6.1, Fig.") == 6


def test_the_pages_show_the_recorded_files_or_say_nothing_was_recorded(tmp_path):
    stopped_study(tmp_path / "study", finished=20)
    record = results.study_record(tmp_path / "study", tmp_path / "images")
    assert record["trials_finished"] == 20 == record["trials_planned"]
    results.write(record, "study", tmp_path / "results")
    page = f"# Study\n\n{pages.STUDY_MARKER}\n\n## Transfer\n\n{pages.TRANSFER_MARKER}\n"
    shown = pages.render(page, page_depth=1, results=tmp_path / "results")
    assert "**Run to the end:** 20 of the 20 GA trials" in shown and pages.STUDY_MARKER not in shown
    assert "Transfer\n\nNot recorded yet: run the study, then `python scripts/robocup_results.py FOLDER` (it writes " \
           "docs/results/robocup/transfer.json)." in shown


def test_a_folder_without_a_finished_trial_is_one_line(tmp_path):
    stopped_study(tmp_path / "study", finished=0)
    for folder in (tmp_path / "study", tmp_path / "nothing"):
        done = subprocess.run([sys.executable, str(SCRIPT), str(folder)], capture_output=True, text=True, cwd=ROOT)
        assert done.returncode == 2, done.stderr
        (line,) = done.stderr.strip().splitlines()
        assert line.startswith("error: ") and str(folder) in line


def test_a_shrunk_transfer_study_says_so_above_its_findings():
    record = {"recorded": "2026-12-04", "folder": "transfer-small", "command": "soccer-lab experiment transfer",
              "sources": 5, "starts": 20, "load_average": [1.0, 1.5, 2.0], "size": {"population": 50,
              "generations": 10}, "wall_time_seconds": 900.0, "findings": [], "figures": []}
    shown = pages.transfer_markdown(record)
    assert shown.startswith("**Shrunk:** population 50 × 10 generations in every part, against the chapter's "
                            "200 × 25")
    assert "; wall time 15 min)." in shown
    full = pages.transfer_markdown({**record, "size": {"population": 200, "generations": 25}})
    assert not full.startswith("**Shrunk")


def test_transfer_only_refuses_a_folder_without_a_finished_transfer_study(tmp_path):
    stopped_study(tmp_path / "study", finished=2)
    done = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "study"), "--transfer-only"],
                          capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 2 and "no finished transfer study" in done.stderr
