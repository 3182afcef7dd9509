"""`soccer-lab experiment`: presets at the chapter's sizes, shrunken experiments end to end, determinism
across executors, resume after a real kill, and CLI errors."""

from __future__ import annotations

import csv
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.figures import FIGURES_FOLDER
from soccer_lab.app.experiment.presets import ALL, PRESET_NAMES, ExperimentOptions, preset, presets, trial_seed
from soccer_lab.app.experiment.report import REPORT_HTML, REPORT_MD
from soccer_lab.app.experiment.runner import STATISTICS_FILE, TrialFolder, plan, run_experiment
from soccer_lab.app.experiment.table import COLUMNS
from soccer_lab.ga.state import GA, RANDOM_SEARCH

TINY = ExperimentOptions(trials=2, population=6, generations=3, max_ticks=60, seed=7)
FULL = ExperimentOptions()


def csv_rows(path: Path, drop: tuple[str, ...] = ("wall_time",)) -> list[dict[str, str]]:
    """The rows without wall_time: the one statistic that measures the machine, not the run."""
    with path.open(newline="") as handle:
        return [{k: v for k, v in row.items() if k not in drop} for row in csv.DictReader(handle)]


# ---- presets ---------------------------------------------------------------------------------------
def test_full_size_presets_follow_the_chapter():
    initial = preset("initial", FULL)
    assert initial.trials == 20
    control = initial.settings[0].ga
    assert (control.population_size, control.max_generations, control.max_length, control.selection,
            control.crossover, control.mutation_rate, control.mutation_probability,
            control.crossover_probability) == (200, 25, 64, "roulette", "one-point", 0.10, 0.35, 0.8)
    assert [s.ga.max_length for s in preset("max-length", FULL).settings] == [25, 50, 64, 75, 100]
    assert [s.evaluations for s in preset("population", FULL).settings] == [10_000] * 4
    assert [s.ga.population_size for s in preset("population", FULL).settings] == [50, 100, 200, 500]
    assert [s.ga.selection for s in preset("selection", FULL).settings] == ["roulette", "tournament", "elitist"]
    assert [s.ga.mutation_rate for s in preset("mutation", FULL).settings] == [0.05, 0.10, 0.15, 0.20, 0.25]
    assert {s.ga.selection for p in ("crossover", "mutation", "long") for s in preset(p, FULL).settings} == {"elitist"}
    assert preset("long", FULL).settings[0].ga.max_generations == 100
    ga, search = preset("random", FULL).settings
    assert (ga.algorithm, search.algorithm) == (GA, RANDOM_SEARCH)
    assert ga.evaluations == search.evaluations == 20_000 and search.ga.population_size == 500
    assert all(p.trials == 10 for p in presets(ALL, FULL) if p.name != "initial")
    assert all(s.ga.target_fitness == 0 for p in presets(ALL, FULL) for s in p.settings)


def test_shrinking_keeps_the_study_in_proportion():
    shrunk = ExperimentOptions(population=20, generations=5)
    assert preset("initial", shrunk).settings[0].evaluations == 100
    assert len({s.evaluations for s in preset("population", shrunk).settings}) <= 2  # rounding aside, equal budgets
    assert preset("long", shrunk).settings[0].ga.max_generations == 20
    ga, search = preset("random", shrunk).settings
    assert ga.evaluations == search.evaluations == 400


def test_trial_seeds_are_stable_distinct_and_shared_by_equal_settings():
    roulette = preset("selection", FULL).settings[0]
    assert roulette.key == preset("initial", FULL).settings[0].key  # the Table 2 control is one setting
    seeds = {trial_seed(0, s, t) for p in presets(ALL, FULL) for s in p.settings for t in range(3)}
    distinct_settings = {s.key for p in presets(ALL, FULL) for s in p.settings}
    assert len(seeds) == 3 * len(distinct_settings)
    assert trial_seed(0, roulette, 1) == trial_seed(0, roulette, 1) != trial_seed(1, roulette, 1)
    all_plan = plan(ALL, TINY)
    assert len(all_plan.specs) < len(all_plan.memberships)  # shared trials run once


def test_unknown_preset_names_the_choices():
    with pytest.raises(KeyError, match="choose one of initial, max-length"):
        preset("bogus", FULL)


# ---- end to end --------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", PRESET_NAMES)
def test_a_shrunken_preset_writes_statistics_figures_and_report(tmp_path, name):
    outcome = run_experiment(name, TINY, tmp_path, LocalExecutor(1))
    rows = csv_rows(tmp_path / STATISTICS_FILE, drop=())
    assert list(rows[0]) == list(COLUMNS)
    chosen = preset(name, TINY)
    expected = sum(chosen.trials * s.ga.max_generations for s in chosen.settings)
    assert len(rows) == expected
    assert {r["setting"] for r in rows} == {s.label for s in chosen.settings}
    for kind in chosen.figures:
        png = tmp_path / FIGURES_FOLDER / f"{name}-{kind}.png"
        assert png.read_bytes().startswith(b"\x89PNG")
    markdown, page = (tmp_path / REPORT_MD).read_text(), (tmp_path / REPORT_HTML).read_text()
    assert f"figures/{name}-{chosen.figures[0]}.png" in markdown
    assert page.count("data:image/png;base64,") == len(chosen.figures)
    assessed = [a for f, a in outcome.report.findings if f.preset == name]
    assert assessed and all(a.verdict != "not run" for a in assessed)
    assert all(f.claim in markdown for f, _ in outcome.report.findings if f.preset == name)
    for spec in outcome.plan.specs:  # each trial's statistics also went to its rerun recording
        assert TrialFolder(tmp_path).recording(spec).stat().st_size > 0


def test_same_seed_same_statistics_whatever_the_number_of_workers(tmp_path):
    run_experiment("crossover", TINY, tmp_path / "serial", LocalExecutor(1))
    run_experiment("crossover", TINY, tmp_path / "parallel", LocalExecutor(2))
    assert csv_rows(tmp_path / "serial" / STATISTICS_FILE) == csv_rows(tmp_path / "parallel" / STATISTICS_FILE)
    other = TINY.model_copy(update={"seed": 8})
    run_experiment("crossover", other, tmp_path / "other", LocalExecutor(1))
    assert csv_rows(tmp_path / "serial" / STATISTICS_FILE) != csv_rows(tmp_path / "other" / STATISTICS_FILE)


def test_ray_gives_the_same_statistics_as_local_processes(tmp_path):
    ray = pytest.importorskip("ray", reason="Ray is not installed: pip install -e '.[test]' (or '.[ray]')")
    from soccer_lab.app.experiment.executors import RayExecutor

    run_experiment("crossover", TINY, tmp_path / "local", LocalExecutor(1))
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        run_experiment("crossover", TINY, tmp_path / "ray", RayExecutor())
    finally:
        ray.shutdown()
    assert csv_rows(tmp_path / "local" / STATISTICS_FILE) == csv_rows(tmp_path / "ray" / STATISTICS_FILE)


def test_a_killed_experiment_resumes_skipping_finished_trials(tmp_path):
    options = TINY.model_copy(update={"trials": 6, "population": 12, "generations": 4, "max_ticks": 200})
    folder = tmp_path / "killed"
    command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "experiment", "initial",
               "--trials", "6", "--population", "12", "--generations", "4", "--max-ticks", "200", "--seed", "7",
               "--workers", "1", "--out", str(folder), "--no-library"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    trials = folder / "trials"
    deadline = time.monotonic() + 120
    while len(list(trials.glob("*.csv"))) < 2 and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.05)
    process.send_signal(signal.SIGKILL)
    process.wait()
    finished = {p: p.stat().st_mtime_ns for p in trials.glob("*.csv")}
    assert 2 <= len(finished) < 6, "the kill should land mid-experiment"
    assert not (folder / STATISTICS_FILE).exists()

    outcome = run_experiment("initial", options, folder, LocalExecutor(1))
    assert (outcome.skipped, outcome.ran) == (len(finished), 6 - len(finished))
    assert all(path.stat().st_mtime_ns == mtime for path, mtime in finished.items())
    run_experiment("initial", options, tmp_path / "whole", LocalExecutor(1))
    assert csv_rows(folder / STATISTICS_FILE) == csv_rows(tmp_path / "whole" / STATISTICS_FILE)


# ---- command line --------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def cli():
    return CliRunner()


def test_cli_runs_a_preset_and_records_it_in_the_library(cli, tmp_path, monkeypatch):
    monkeypatch.setenv("SOCCER_LAB_DATA", str(tmp_path / "data"))
    result = cli.invoke(app, ["experiment", "crossover", "--trials", "2", "--population", "6", "--generations", "2",
                              "--max-ticks", "40", "--workers", "1", "--out", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert "4 trials (4 run, 0 already finished)" in result.output
    from soccer_lab.app.paths import DATABASE_FILE
    from soccer_lab.app.store import Store

    store = Store(tmp_path / "data" / DATABASE_FILE)
    (record,) = store.list_experiments()
    store.close()
    assert record.preset == "crossover" and record.summary["trials"] == 4
    assert "figures/crossover-best_fitness.png" in record.summary["figures"]
    again = cli.invoke(app, ["experiment", "crossover", "--trials", "2", "--population", "6", "--generations", "2",
                             "--max-ticks", "40", "--workers", "1", "--out", str(tmp_path / "out"), "--no-library"])
    assert "4 trials (0 run, 4 already finished)" in again.output
    elsewhere = cli.invoke(app, ["experiment", "crossover", "--trials", "2", "--population", "6", "--generations", "2",
                                 "--max-ticks", "40", "--workers", "1", "--out", str(tmp_path / "out"),
                                 "--data-dir", str(tmp_path / "other")])
    assert elsewhere.exit_code == 0, elsewhere.output
    store = Store(tmp_path / "other" / DATABASE_FILE)
    assert [r.preset for r in store.list_experiments()] == ["crossover"]
    store.close()


@pytest.mark.parametrize("arguments, message", [
    (["bogus"], "error: unknown preset 'bogus'; choose one of initial"),
    (["initial", "--trials", "0"], "error: --trials: Input should be greater than or equal to 1"),
    (["initial", "--executor", "slurm"], "error: unknown executor 'slurm'; choose one of local, ray"),
    (["initial", "--address", "10.0.0.1:6379"], "error: --address needs --executor ray"),
])
def test_cli_bad_input_is_one_line_with_status_2(cli, tmp_path, arguments, message):
    result = cli.invoke(app, ["experiment", *arguments, "--out", str(tmp_path / "x"), "--no-library"])
    assert result.exit_code == 2
    (line,) = result.output.strip().splitlines()
    assert line.startswith(message)


def test_cli_refuses_a_folder_of_other_options(cli, tmp_path):
    base = ["experiment", "crossover", "--trials", "1", "--population", "4", "--generations", "1", "--max-ticks", "20",
            "--workers", "1", "--out", str(tmp_path), "--no-library"]
    assert cli.invoke(app, base).exit_code == 0
    result = cli.invoke(app, [*base, "--seed", "3"])
    assert result.exit_code == 2
    assert "holds an experiment with other options (seed)" in result.output
