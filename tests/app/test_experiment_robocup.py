"""The `robocup` preset: the chapter's RoboCup initial trials (Table 2 on rcssserver, Figs. 8-10) at the
chapter's size, and shrunken on real servers that soccer-lab starts: statistics, figures, the RoboCup
findings in the report, and resuming within a trial."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.experiment.figures import FIGURES_FOLDER
from soccer_lab.app.experiment.presets import ExperimentOptions, preset, presets
from soccer_lab.app.experiment.report import REPORT_MD, write_report
from soccer_lab.app.experiment.verdicts import AGREES, DISAGREES, NOT_RUN
from soccer_lab.app.experiment.runner import STATISTICS_FILE
from soccer_lab.app.experiment.table import StatisticsTable
from soccer_lab.ga.checkpoint import load_checkpoint
from tests.app.test_experiment_report import fabricated, falling, verdict

# 2 trials of Table 2 shrunk to 4 x 5 (5 generations: the fewest a trend test takes), 60-cycle trials.
SHRUNK = ["--trials", "2", "--population", "4", "--generations", "5", "--max-ticks", "60", "--seed", "1",
          "--replays", "2"]


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_the_preset_is_table_2_on_rcssserver_at_the_chapters_size():
    robocup = preset("robocup", ExperimentOptions())
    assert robocup.trials == 20 and robocup.per_trial
    (setting,) = robocup.settings
    assert setting.ga == preset("initial", ExperimentOptions()).settings[0].ga  # Table 2
    assert (setting.trial.max_ticks, setting.trial.idle_ticks, setting.trial.fitness) == (1200, 100, "robocup-composite")
    assert setting.key != preset("initial", ExperimentOptions()).settings[0].key  # never shared with SimpleSoccer
    assert robocup.figures == ("mean_fitness", "best_fitness", "goal_histogram", "true_quality")
    assert "robocup" not in [p.name for p in presets("all", ExperimentOptions())]
    assert preset("robocup", ExperimentOptions(max_ticks=300)).settings[0].trial.max_ticks == 300


def test_trial_options_added_later_keep_the_studies_trial_files_named_as_they_were():
    """A setting's key names its trial files: options added to TrialConfig after a study ran leave it out while
    they keep their defaults (so the study still finds its trials), and change it when set."""
    from dataclasses import replace

    (setting,) = preset("robocup", ExperimentOptions()).settings
    # the full study's trial files (docs/robocup/full-study.md), named before behaviour seeds, the restart
    # and the answer delays existed
    assert setting.key == "ga-rcss-p200-g25-28cb37aa54"
    counting = replace(setting, ga=setting.ga.model_copy(update={"behaviour_seeds": 2}))
    assert counting.key == setting.key  # counting behaviours does not change the evolution
    changed = [replace(setting, trial=setting.trial.model_copy(update=change)).key
               for change in ({"restart": "server"}, {"answer_delay": 1}, {"answer_delay_spread": 2})]
    assert len({setting.key, *changed}) == 4


@pytest.mark.parametrize("given", [{}, {"max_ticks": 1000}, {"max_ticks": 1200}, {"noise": False},
                                   {"noise": True}, {"max_ticks": 300, "noise": False, "population": 20}])
def test_a_manifest_records_the_rcssserver_trials_as_they_were_played(given, tmp_path):
    """Left unset, max_ticks and noise mean the chapter's RoboCup values (1200 cycles, the server's noise), given
    they mean what they say: the manifest tells the two apart, and reads back as the options that were given."""
    from soccer_lab.app.experiment.presets import RCSS_TRIAL
    from soccer_lab.app.experiment.runner import ExperimentError, prepare_folder

    options = ExperimentOptions(**given)
    identity = options.identity(on_servers=True)
    assert identity[RCSS_TRIAL] == {"max_ticks": options.trial().max_ticks, "noise": options.trial().noise}
    read_back = ExperimentOptions.from_identity(identity)
    assert read_back.trial() == options.trial() and read_back.game() == options.game()
    assert read_back.identity(on_servers=True) == identity
    prepare_folder(tmp_path, identity)
    prepare_folder(tmp_path, read_back.identity(on_servers=True))  # the same trials: resumes
    if options.trial().max_ticks == 1200:  # `--max-ticks 1000` is not the default's 1200 cycles, though recorded
        with pytest.raises(ExperimentError, match=r"other options \(max_ticks, rcss_trial\)|other options \(rcss_trial\)"):
            prepare_folder(tmp_path, options.model_copy(update={"max_ticks": 1000}).identity(on_servers=True))


def test_a_folder_made_before_its_manifest_recorded_the_rcssserver_trials_still_resumes(tmp_path):
    from soccer_lab.app.experiment.runner import MANIFEST, prepare_folder

    (tmp_path / MANIFEST).write_text(json.dumps(ExperimentOptions().identity()))
    prepare_folder(tmp_path, ExperimentOptions().identity(on_servers=True))


def robocup_rows(rng, *, final_mean: float, most_goals_column: str) -> list[dict]:
    """Fabricated robocup statistics: 10 trials x 10 generations, the average falling to `final_mean`, a
    scorer from generation 1, the share scoring none falling and the share scoring 2+ rising, and some
    individual in the class `most_goals_column` in the last generation."""
    generations = np.linspace(0, 1, 10)
    none = np.tile(0.9 - 0.5 * generations, (10, 1)) + rng.normal(0, 0.01, (10, 10))
    two = np.tile(0.02 + 0.2 * generations, (10, 1)) + rng.normal(0, 0.005, (10, 10))
    curves = {"mean": falling(0.95, final_mean, rng), "best": np.full((10, 10), 0.25), "goals_0": none,
              "goals_1": 0.08 + 0 * none, "goals_2": two}
    curves["best"][:, 0] = 0.9
    marked = np.zeros((10, 10))
    marked[:, -1] = 0.01
    curves[most_goals_column] = curves.get(most_goals_column, 0 * none) + marked
    return fabricated("robocup", {"Table 2": curves})


def test_the_robocup_findings_follow_the_data(tmp_path):
    rng = np.random.default_rng(3)
    robocup = preset("robocup", ExperimentOptions(trials=10))
    like_the_chapter = robocup_rows(rng, final_mean=0.55, most_goals_column="goals_3")
    report = write_report(StatisticsTable(like_the_chapter), [robocup], tmp_path)
    for claim in ("On rcssserver the population average", "On rcssserver the average fitness plateaus",
                  "On rcssserver good", "On rcssserver more players", "On rcssserver players learn",
                  "On rcssserver no individual"):
        assert verdict(report, claim) == AGREES, claim
    unlike = robocup_rows(rng, final_mean=0.85, most_goals_column="goals_more")
    report = write_report(StatisticsTable(unlike), [robocup], tmp_path)
    assert verdict(report, "On rcssserver the average fitness plateaus") == DISAGREES
    assert verdict(report, "On rcssserver no individual") == DISAGREES


@pytest.mark.parametrize("arguments, message", [
    (["robocup", "--workers", "2"], "--workers: robocup plays its trials on rcssservers"),
    (["robocup", "--executor", "ray", "--server", "127.0.0.1:6000"], "--server names servers you run"),
    (["robocup", "--address", "127.0.0.1:6379"], "--address needs --executor ray"),
    (["robocup", "--executor", "slurm"], "--executor: unknown executor 'slurm'"),
    (["robocup", "--count-touches"], "--count-touches: robocup plays its trials on rcssservers"),
    (["initial", "--servers", "2"], "--servers: for the robocup and transfer presets only"),
    (["robocup", "--server", "127.0.0.1:6000", "--servers", "2"], "--server names servers you run"),
    (["robocup", "--rcssserver", "/no/such/rcssserver"], "no rcssserver: '/no/such/rcssserver' does not exist"),
])
def test_bad_options_are_one_line(arguments, message, tmp_path):
    result = run("experiment", *arguments, "--out", tmp_path / "x", "--no-library")
    assert result.exit_code == 2, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith("error: ") and message in line


def test_a_shrunken_robocup_on_two_servers_resumes_inside_a_trial(rcssserver, tmp_path, monkeypatch):
    folder = tmp_path / "robocup"
    trials = folder / "trials"
    import soccer_lab.ga.algorithms

    save = soccer_lab.ga.algorithms.save_checkpoint

    def interrupted_after_two_generations(path, state):  # Ctrl+C once a trial's second generation is kept
        save(path, state)
        if len(state.history) == 2:
            raise KeyboardInterrupt

    command = ["experiment", "robocup", *SHRUNK, "--rcssserver", rcssserver, "--servers", "2", "--out", folder,
               "--no-library"]
    monkeypatch.setattr(soccer_lab.ga.algorithms, "save_checkpoint", interrupted_after_two_generations)
    stopped = run(*command)
    assert stopped.exit_code == 130, stopped.output
    assert "started 2 rcssservers: 127.0.0.1:" in stopped.output
    (checkpoint,) = trials.glob("*.checkpoint")
    assert not list(trials.glob("*.csv"))
    kept = [stats.to_dict() for stats in load_checkpoint(checkpoint).history]

    monkeypatch.setattr(soccer_lab.ga.algorithms, "save_checkpoint", save)
    result = run(*command)
    assert result.exit_code == 0, result.output
    assert not checkpoint.exists()
    with (folder / STATISTICS_FILE).open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 2 * 5 and {row["preset"] for row in rows} == {"robocup"}
    assert all(0.0 < float(row["best"]) <= float(row["mean"]) <= 1.0 for row in rows)
    resumed = [row for row in rows if row["trial"] == checkpoint.stem.rsplit("-", 1)[1]]
    for row, before in zip(resumed[:2], kept):  # the trial went on from its checkpoint, not from the start
        assert (float(row["mean"]), float(row["best"]), int(row["evaluations"])) == (
            before["mean"], before["best"], before["evaluations"])
    for kind in ("mean_fitness", "best_fitness", "goal_histogram"):
        assert (folder / FIGURES_FOLDER / f"robocup-{kind}.png").read_bytes().startswith(b"\x89PNG")
    report = (folder / REPORT_MD).read_text()
    assert "RoboCup initial trials" in report and "(chapter Fig. 8)" in report and "(chapter Fig. 10)" in report
    robocup_findings = [line for line in report.splitlines() if line.startswith("| 6.1")]
    assert len(robocup_findings) == 6 and not any(f"| {NOT_RUN} |" in line for line in robocup_findings)
