"""Replicates: an experiment at several seeds, each a whole experiment of its own, and the summary that calls
a verdict robust only when every replicate gives it."""

from __future__ import annotations

import csv

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.presets import ExperimentOptions
from soccer_lab.app.experiment.replicates import (VARIES, VERDICTS_FIGURE, VERDICTS_FILE, replicate_folder,
                                                  replicate_seeds, run_replicates, summarise)
from soccer_lab.app.experiment.report import REPORT_HTML, REPORT_MD, Report
from soccer_lab.app.experiment.verdicts import AGREES, DISAGREES, INCONCLUSIVE, TOO_SMALL, Assessment
from soccer_lab.app.experiment.runner import ExperimentError, run_experiment
from tests.app.test_experiment import csv_rows

TINY = ExperimentOptions(trials=2, population=6, generations=2, max_ticks=40, seed=7, replays=2)


def reports_with(verdicts_per_replicate: list[list[str]]) -> list[Report]:
    from soccer_lab.app.experiment.report import FINDINGS

    return [Report([(finding, Assessment("m", verdict, "t")) for finding, verdict in zip(FINDINGS, verdicts)], [])
            for verdicts in verdicts_per_replicate]


def test_a_verdict_is_robust_only_when_every_replicate_gives_it():
    rows, _ = summarise([0, 1, 2], reports_with([[AGREES, AGREES, DISAGREES, TOO_SMALL],
                                                 [AGREES, DISAGREES, DISAGREES, TOO_SMALL],
                                                 [AGREES, AGREES, DISAGREES, TOO_SMALL]]))
    assert [(r.summary, r.robust) for r in rows] == [("agrees in 3 of 3", AGREES), ("agrees in 2 of 3", VARIES),
                                                     ("agrees in 0 of 3", DISAGREES), ("agrees in 0 of 3", TOO_SMALL)]
    assert rows[1].verdicts == [AGREES, DISAGREES, AGREES]
    one, _ = summarise([5], reports_with([[INCONCLUSIVE]]))
    assert (one[0].summary, one[0].robust) == ("agrees in 0 of 1", INCONCLUSIVE)


def test_replicate_seeds_count_up_or_are_given():
    assert replicate_seeds(7, 3, None) == [7, 8, 9]
    assert replicate_seeds(7, None, [0, 913]) == [0, 913]
    assert replicate_seeds(7, 2, [0, 913]) == [0, 913]
    for replicates, seeds, message in [(3, [0, 913], "--replicates 3 but 2 --seeds"), (None, [1, 1], "each seed once"),
                                       (0, None, "--replicates: between 1 and 100")]:
        with pytest.raises(ExperimentError, match=message):
            replicate_seeds(0, replicates, seeds)


def test_each_replicate_is_the_experiment_at_its_seed_and_resumes(tmp_path):
    outcome = run_replicates("crossover", TINY, [7, 8], tmp_path / "replicates", LocalExecutor(2))
    assert (outcome.ran, outcome.skipped, outcome.trials) == (8, 0, 8)
    single = run_experiment("crossover", TINY.model_copy(update={"seed": 8}), tmp_path / "single", LocalExecutor(1))
    replicate = replicate_folder(tmp_path / "replicates", 8)
    assert csv_rows(replicate / "statistics.csv") == csv_rows(tmp_path / "single" / "statistics.csv")
    assert csv_rows(replicate / "bests.csv", drop=()) == csv_rows(tmp_path / "single" / "bests.csv", drop=())
    assert csv_rows(replicate_folder(tmp_path / "replicates", 7) / "statistics.csv") != csv_rows(
        replicate / "statistics.csv")
    assert (replicate / REPORT_MD).read_text() == (tmp_path / "single" / REPORT_MD).read_text()

    with (tmp_path / "replicates" / VERDICTS_FILE).open(newline="") as handle:
        (row,) = [r for r in csv.DictReader(handle) if r["preset"] == "crossover"]  # the preset's one finding
    assert (row["seed 7"], row["seed 8"], row["robust"]) == (TOO_SMALL, TOO_SMALL, TOO_SMALL)
    assert row["summary"] == "agrees in 0 of 2" and single.report.findings[-1][1].verdict != "agrees"
    markdown = (tmp_path / "replicates" / REPORT_MD).read_text()
    assert "| preset | chapter | claim | seed 7 | seed 8 | summary | robust verdict |" in markdown
    assert "seed-7/report.md, seed-8/report.md" in markdown and "not run" not in markdown
    assert "Smaller than the chapter's" in markdown  # the size, against the chapter's, as in every report
    assert (tmp_path / "replicates" / "figures" / VERDICTS_FIGURE).read_bytes().startswith(b"\x89PNG")
    assert (tmp_path / "replicates" / REPORT_HTML).read_text().count("data:image/png;base64,") == 1

    more = run_replicates("crossover", TINY, [7, 8, 9], tmp_path / "replicates", LocalExecutor(1))
    assert (more.ran, more.skipped) == (4, 8)  # a third replicate only adds its own trials
    with pytest.raises(ExperimentError, match="other options"):
        run_replicates("crossover", TINY.model_copy(update={"max_ticks": 50}), [7], tmp_path / "replicates",
                       LocalExecutor(1))


def test_replicates_on_ray_match_local_processes(tmp_path):
    ray = pytest.importorskip("ray")
    from soccer_lab.app.experiment.executors import RayExecutor

    run_replicates("crossover", TINY, [7, 8], tmp_path / "local", LocalExecutor(1))
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        run_replicates("crossover", TINY, [7, 8], tmp_path / "ray", RayExecutor())
    finally:
        ray.shutdown()
    for seed in (7, 8):
        assert csv_rows(replicate_folder(tmp_path / "local", seed) / "statistics.csv") == csv_rows(
            replicate_folder(tmp_path / "ray", seed) / "statistics.csv")


# ---- command line ----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def cli():
    return CliRunner()


SHRUNK = ["--trials", "2", "--population", "6", "--generations", "2", "--max-ticks", "40", "--replays", "2",
          "--workers", "1"]


def test_cli_runs_replicates_and_records_them_as_one_experiment(cli, tmp_path, monkeypatch):
    monkeypatch.setenv("SOCCER_LAB_DATA", str(tmp_path / "data"))
    result = cli.invoke(app, ["experiment", "crossover", *SHRUNK, "--seeds", "3,913", "--out", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert "8 trials (8 run, 0 already finished)" in result.output
    assert "verdicts: 1 robust: too small to judge" in result.output
    assert {p.name for p in (tmp_path / "out").iterdir()} >= {"seed-3", "seed-913", REPORT_MD, VERDICTS_FILE}
    from soccer_lab.app.paths import DATABASE_FILE
    from soccer_lab.app.store import Store

    store = Store(tmp_path / "data" / DATABASE_FILE)
    (record,) = store.list_experiments()
    store.close()
    assert record.summary["seeds"] == [3, 913] and record.summary["trials"] == 8
    assert record.summary["figures"] == [f"figures/{VERDICTS_FIGURE}"]

    counted = cli.invoke(app, ["experiment", "crossover", *SHRUNK, "--seed", "3", "--replicates", "2", "--no-library",
                               "--out", str(tmp_path / "counted")])
    assert counted.exit_code == 0, counted.output
    assert {p.name for p in (tmp_path / "counted").iterdir() if p.is_dir()} == {"seed-3", "seed-4", "figures"}


@pytest.mark.parametrize("arguments, message", [
    (["--seeds", "1,x"], "error: --seeds: comma-separated whole numbers, e.g. 0,913 (got '1,x')"),
    (["--seeds", "1,2", "--replicates", "3"], "error: --replicates 3 but 2 --seeds"),
    (["--replicates", "0"], "error: --replicates: between 1 and 100"),
    (["--seeds", "-1"], "error: --seeds: one or more seeds in [0, 2^63)"),
    (["--replays", "0"], "error: --replays: Input should be greater than or equal to 1"),
])
def test_cli_bad_replicates_are_one_line_with_status_2(cli, tmp_path, arguments, message):
    result = cli.invoke(app, ["experiment", "crossover", *arguments, "--out", str(tmp_path / "x"), "--no-library"])
    assert result.exit_code == 2, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith(message)


def test_help_names_only_options_the_command_has(cli):
    result = cli.invoke(app, ["experiment", "--help"])
    assert result.exit_code == 0
    text = " ".join(result.output.split())  # as read, whatever the wrapping
    assert "--env" not in text  # `experiment` has no --env: its servers are for the robocup preset
    assert text.count("For the robocup and transfer presets:") == 3
    for named in ("--replicates", "--seeds", "--replays", "uniform-crossover", "games-per-evaluation", "all-plus"):
        assert named in text


def test_the_verdict_grid_never_labels_two_rows_alike():
    """Rows of the grid once repeated "initial 6.2, Fig. 11" for the two findings of that figure."""
    from soccer_lab.app.experiment.replicates import Row, row_labels
    from soccer_lab.app.experiment.report import FINDINGS

    rows = [Row(f.preset, f.where, f.claim, ["agrees"] * 3, "agrees in 3 of 3", "agrees") for f in FINDINGS]
    labels = row_labels(rows)
    assert len(set(labels)) == len(labels) == len(FINDINGS)
    twins = [Row("initial", "6.2, Fig. 11", "The same claim", ["agrees"], "agrees in 1 of 1", "agrees")] * 2
    assert len(set(row_labels(twins))) == 2


def test_the_verdict_grid_keeps_its_row_labels_and_legend_in_the_picture(tmp_path, monkeypatch):
    """With a claim in each row label the grid kept its old width: the labels and the legend were cut off."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from soccer_lab.app.experiment import replicates
    from soccer_lab.app.experiment.replicates import Row, _verdict_figure

    drawn = []

    class Kept(replicates.MatplotlibFigure):
        def savefig(self, *args, **kwargs):
            drawn.append(self)
            return super().savefig(*args, **kwargs)

    monkeypatch.setattr(replicates, "MatplotlibFigure", Kept)
    claim = "The pool of unique premise genes falls slowly but steadily over the generations, then levels off."
    rows = [Row("max-length", f"6.4.{i}, Figs. 14-15", claim, ["agrees", "disagrees", "agrees"], "agrees in 2 of 3",
                replicates.VARIES) for i in range(25)]
    _verdict_figure(tmp_path, [0, 1, 2], rows)
    figure = drawn[0]
    renderer = FigureCanvasAgg(figure).get_renderer()
    width = figure.get_size_inches()[0] * figure.dpi
    axes = figure.axes[0]
    for label in axes.get_yticklabels():
        assert label.get_window_extent(renderer).x0 >= 0, label.get_text()
    assert axes.get_legend().get_window_extent(renderer).x1 <= width
