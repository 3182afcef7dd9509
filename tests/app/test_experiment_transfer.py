"""The transfer study (app/experiment/transfer.py): its plan shares trials with the initial and robocup
presets, its findings follow the data, and shrunk on real servers it plays the sources' best players in
both environments, seeds rcssserver runs with their last populations, reuses the robocup preset's runs
and resumes."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.experiment.presets import ExperimentOptions, preset, trial_seed
from soccer_lab.app.experiment.verdicts import AGREES, DISAGREES
from soccer_lab.app.experiment.table import StatisticsTable
from soccer_lab.app.experiment.runner import read_runs
from soccer_lab.app.experiment.transfer import (FOLDER, PLAYERS_FILE, RANDOM_START, RCSS, REPORT_MD, SEEDED, SIMPLE,
                                                STARTS, STATISTICS_FILE, TRANSFER, assess, start_seeds, transfer_plan)
from tests.app.test_experiment_report import fabricated, falling

SHRUNK = ["--trials", "2", "--population", "6", "--generations", "2", "--max-ticks", "80", "--seed", "4",
          "--no-noise", "--skills", "assisted"]


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_the_plan_reuses_the_initial_presets_runs_as_sources_and_the_robocup_presets_as_random_starts():
    options = ExperimentOptions(trials=3)
    plan = transfer_plan(options)
    initial, robocup = preset("initial", options).settings[0], preset("robocup", options).settings[0]
    assert plan.source.key == initial.key and plan.random_start.key == robocup.key
    assert plan.seeded.key != robocup.key and plan.seeded.ga == robocup.ga and plan.seeded.trial == robocup.trial
    specs = plan.specs
    assert len(specs) == 6 and [s.setting.label for s in specs[:2]] == [SEEDED, RANDOM_START]
    assert all(s.seed == trial_seed(options.seed, robocup, s.trial) for s in specs)  # the robocup trials' seeds
    assert start_seeds(options, 1) == start_seeds(options, 1) != start_seeds(options, 2)
    assert len(set(start_seeds(options, 1))) == STARTS


def players_rows(simple_goals: list[float], server_goals: list[float]) -> list[dict]:
    rows = []
    for source, (simple, server) in enumerate(zip(simple_goals, server_goals)):
        for environment, goals in ((SIMPLE, simple), (RCSS, server)):
            rows += [{"source": source, "environment": environment, "start": s, "seed": s, "goals": goals,
                      "kicks": 2, "ticks": 100, "fitness": 0.5} for s in range(3)]
    return rows


def test_the_findings_follow_the_data(tmp_path):
    plan = transfer_plan(ExperimentOptions(trials=8))
    rng = np.random.default_rng(5)
    ranked = players_rows([1, 2, 3, 4, 5, 6, 7, 8], [1, 2, 3, 4, 5, 6, 7, 8.5])
    seeded_better = StatisticsTable(fabricated(TRANSFER, {
        SEEDED: {"mean": falling(0.6, 0.4, rng, trials=8), "best": falling(0.3, 0.1, rng, trials=8)},
        RANDOM_START: {"mean": falling(1.0, 0.8, rng, trials=8), "best": falling(0.9, 0.5, rng, trials=8)}}))
    assert [verdict for _, _, verdict, _ in assess(plan, seeded_better, ranked)] == [AGREES] * 4
    lost = players_rows([1, 2, 3, 4, 5, 6, 7, 8], [0, 0, 0, 0.1, 0, 0, 0, 0])
    same = StatisticsTable(fabricated(TRANSFER, {SEEDED: {"mean": falling(1.0, 0.8, rng, trials=8)},
                                                 RANDOM_START: {"mean": falling(1.0, 0.8, rng, trials=8)}}))
    findings = assess(plan, same, lost)
    assert findings[0][2] == DISAGREES and "0.00" in findings[0][1]  # goals lost on the server
    assert findings[2][2] != AGREES  # seeding made no difference


def test_a_shrunken_transfer_on_two_servers_reuses_robocup_runs_and_resumes(rcssserver, tmp_path):
    folder = tmp_path / "study"
    servers = ["--rcssserver", rcssserver, "--servers", "2", "--out", folder, "--no-library"]
    robocup = run("experiment", "robocup", *SHRUNK, *servers)
    assert robocup.exit_code == 0, robocup.output
    random_runs = {path: path.stat().st_mtime_ns for path in (folder / "trials").glob("*.csv")}
    assert len(random_runs) == 2

    result = run("experiment", TRANSFER, *SHRUNK, *servers)
    assert result.exit_code == 0, result.output
    assert "4 rcssserver runs (2 run now)" in result.output  # the random starts were the robocup preset's
    assert {path: path.stat().st_mtime_ns for path in random_runs} == random_runs
    with (folder / FOLDER / PLAYERS_FILE).open(newline="") as handle:
        players = list(csv.DictReader(handle))
    assert len(players) == 2 * 2 * STARTS
    assert {(r["source"], r["environment"]) for r in players} == {(s, e) for s in "01" for e in (SIMPLE, RCSS)}
    assert all(int(r["ticks"]) <= 80 for r in players)
    assert any(int(r["kicks"]) > 0 for r in players if r["environment"] == RCSS)  # assisted players reach the ball
    table = StatisticsTable.read(folder / STATISTICS_FILE)
    assert table.settings(TRANSFER) == [SEEDED, RANDOM_START]
    for trial in (0, 1):  # a seeded run's generation 0 is its source's last population, unchanged
        source = json.loads((folder / FOLDER / f"source-{trial}.json").read_text())
        lengths = [len(chromosome) for chromosome in source["population"]]  # genes
        seeded = [row for row in table.rows if row["setting"] == SEEDED and row["trial"] == trial]
        assert seeded[0]["genes_mean"] == pytest.approx(np.mean(lengths))
    report = (folder / REPORT_MD).read_text()
    assert "broad similarity in the results" in report and "Riley's thesis" in report
    assert "2 GA runs of Table 2 at population 6 x 2 generations in SimpleSoccer" in report  # shrunk, and says so
    assert report.count("| inconclusive |") == 3  # two players, two runs a side: too few for the tests
    for name in ("players", "mean_fitness", "best_fitness"):
        assert (folder / "figures" / f"transfer-{name}.png").read_bytes().startswith(b"\x89PNG")

    kept = (folder / FOLDER / PLAYERS_FILE).read_bytes()
    again = run("experiment", TRANSFER, *SHRUNK, *servers)
    assert again.exit_code == 0 and "(0 run now)" in again.output
    assert (folder / FOLDER / PLAYERS_FILE).read_bytes() == kept  # finished players are not played again
    transfers = [entry for entry in read_runs(folder) if entry["preset"] == TRANSFER]  # each invocation timed
    assert [(entry["ran"], entry["skipped"]) for entry in transfers] == [(2, 2), (0, 4)]
    assert transfers[0]["seconds"] > 0 and len(transfers[0]["load_average_before"]) == 3

    # the docs' record of it says what was played: 2 sources (the manifest keeps no --trials), 6 x 2, 80 cycles
    from scripts.robocup_results import options_of, transfer_record

    assert options_of(folder).trial().max_ticks == 80
    record = transfer_record(folder, images=tmp_path / "images")
    assert record["sources"] == 2 and record["size"] == {"population": 6, "generations": 2}
    assert record["wall_time_seconds"] == pytest.approx(sum(entry["seconds"] for entry in transfers))
