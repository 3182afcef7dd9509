"""The experiments beyond the chapter: their presets at full size and shrunk, what a trial of restarts or of
several games per evaluation really runs, each trial's best re-played on fresh starts, and the answers in
the report's "Beyond the chapter" section."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from soccer_lab.app.experiment.beyond import NO_DIFFERENCE, assess_questions
from soccer_lab.app.experiment.executors import LocalExecutor
from soccer_lab.app.experiment.figures import FIGURES_FOLDER
from soccer_lab.app.experiment.presets import (ALL, ALL_PLUS, BEYOND_NAMES, PRESET_NAMES, ExperimentOptions, preset,
                                               presets)
from soccer_lab.app.experiment.report import REPORT_MD, write_report
from soccer_lab.app.experiment.verdicts import TOO_SMALL
from soccer_lab.app.experiment.runner import (BESTS_FILE, MANIFEST, TRIALS_FOLDER, ExperimentError, TrialSpec, plan,
                                              run_experiment, run_trial)
from soccer_lab.app.experiment.table import BEST_COLUMNS, BestsTable, StatisticsTable
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.ga.algorithms import evolve
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.engine import play_games
from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator
from tests.app.test_experiment_report import fabricated, falling

FULL = ExperimentOptions()
TINY = ExperimentOptions(trials=2, population=6, generations=3, max_ticks=60, seed=7, replays=4)


# ---- presets ---------------------------------------------------------------------------------------
def test_the_presets_beyond_the_chapter_at_full_size():
    uniform = preset("uniform-crossover", FULL)
    assert [s.ga.crossover for s in uniform.settings] == ["one-point", "two-point", "uniform"]
    crossover = preset("crossover", FULL)
    assert [s.key for s in uniform.settings[:2]] == [s.key for s in crossover.settings]  # shared trials

    pressure = preset("rule-pressure", FULL)
    assert [(s.ga.max_length, s.ga.max_generations, s.ga.selection) for s in pressure.settings] == [
        (25, 100, "elitist"), (64, 100, "elitist"), (128, 100, "elitist")]
    assert pressure.settings[1].key == preset("long", FULL).settings[0].key  # Table 2's length: the long trials

    one, five = preset("games-per-evaluation", FULL).settings
    assert (one.games_per_evaluation, five.games_per_evaluation) == (1, 5)
    assert (one.ga.max_generations, five.ga.max_generations) == (125, 25)
    assert one.games == five.games == 25_000 and five.evaluations == 5_000  # equal games played
    assert one.ga.selection == five.ga.selection == "roulette"  # Table 2, where the chapter raised it

    restarts, single = preset("restarts", FULL).settings
    assert (restarts.restarts, restarts.ga.max_generations) == (4, 25)
    assert (single.restarts, single.ga.max_generations) == (1, 100)
    assert restarts.evaluations == single.evaluations == 20_000
    assert single.key == preset("long", FULL).settings[0].key
    assert all(preset(name, FULL).trials == 10 for name in BEYOND_NAMES)
    assert all("true_quality" in p.figures for p in presets(ALL_PLUS, FULL))


def test_all_plus_is_all_and_the_presets_beyond_it():
    assert [p.name for p in presets(ALL_PLUS, FULL)] == [*PRESET_NAMES, *BEYOND_NAMES]
    assert not set(BEYOND_NAMES) & {p.name for p in presets(ALL, FULL)}
    assert len(plan(ALL_PLUS, TINY).specs) < len(plan(ALL_PLUS, TINY).memberships)  # shared with all's


@pytest.mark.parametrize("population, generations", [(20, 5), (40, 2)])
def test_shrinking_keeps_each_comparison_fair(population, generations):
    options = ExperimentOptions(population=population, generations=generations)
    one, five = preset("games-per-evaluation", options).settings
    assert one.games == five.games and one.ga.max_generations == 5 * five.ga.max_generations == 5 * generations
    restarts, single = preset("restarts", options).settings
    assert restarts.evaluations == single.evaluations and restarts.ga.max_generations == generations
    assert restarts.label == f"4 x {generations} generations" and single.label == f"1 x {4 * generations} generations"
    assert {s.ga.max_generations for s in preset("rule-pressure", options).settings} == {4 * generations}
    assert {s.ga.population_size for p in BEYOND_NAMES for s in preset(p, options).settings} == {population}
    assert {s.ga.max_length for s in preset("rule-pressure", options).settings} == {25, 64, 128}  # not scaled


def test_only_new_settings_change_their_keys():
    """games per evaluation and restarts enter a setting's key only when set, so the chapter's trial files
    keep their names."""
    table_2 = preset("initial", FULL).settings[0]
    assert table_2.key.startswith("ga-p200-g25-") and "x" not in table_2.key.split("-")[2]
    one, five = preset("games-per-evaluation", FULL).settings
    restarts = preset("restarts", FULL).settings[0]
    assert "-k5-" in five.key and "-k" not in one.key and "-g25x4-" in restarts.key
    assert len({table_2.key, five.key, restarts.key}) == 3


# ---- what a trial runs ------------------------------------------------------------------------------
PLAYING = TINY.model_copy(update={"population": 10, "max_ticks": 400})  # long enough games that players kick


def tiny_spec(name: str, label_index: int, options: ExperimentOptions = PLAYING) -> TrialSpec:
    (spec,) = [m.spec for m in plan(name, options).memberships
               if m.spec.trial == 0 and m.setting == preset(name, options).settings[label_index].label]
    return spec


def test_a_trial_of_restarts_is_independent_runs_one_after_another():
    spec = tiny_spec("restarts", 0)
    result = run_trial(spec)
    generations = spec.setting.ga.max_generations
    assert [row["generation"] for row in result.rows] == list(range(4 * generations))
    assert [row["evaluations"] for row in result.rows] == [10 * (g + 1) for g in range(4 * generations)]
    first = evolve(spec.config, SimpleSoccerEvaluator(spec.game, SOCCER_VOCABULARY), SOCCER_VOCABULARY)
    assert [row["mean"] for row in result.rows[:generations]] == [s.mean for s in first.history]  # restart 0
    later = [row["genes_mean"] for row in result.rows[generations:2 * generations]]
    assert later != [s.genes_mean for s in first.history]  # restart 1 has its own seed
    assert result.best["fitness_seen"] == min(row["best"] for row in result.rows)
    assert result.best["generation"] == next(r["generation"] for r in result.rows
                                             if r["best"] == result.best["fitness_seen"])


def test_five_games_per_evaluation_are_what_the_trial_plays():
    spec = tiny_spec("games-per-evaluation", 1, PLAYING.model_copy(update={"skills": "assisted"}))  # players score
    assert spec.game.games_per_evaluation == 5 and spec.game.max_ticks == 400
    rows = run_trial(spec).rows
    game = GameConfig(max_ticks=400, skills="assisted")
    five = SimpleSoccerEvaluator(game.model_copy(update={"games_per_evaluation": 5}), SOCCER_VOCABULARY)
    direct = evolve(spec.config, five, SOCCER_VOCABULARY)
    assert [(r["mean"], r["best"]) for r in rows] == [(s.mean, s.best) for s in direct.history]
    assert min(r["best"] for r in rows) < 1.0
    single = evolve(spec.config, SimpleSoccerEvaluator(game, SOCCER_VOCABULARY), SOCCER_VOCABULARY)
    assert [r["mean"] for r in rows] != [s.mean for s in single.history]


def test_the_best_is_replayed_on_fresh_starts_one_game_each():
    spec = tiny_spec("games-per-evaluation", 1, PLAYING.model_copy(update={"replays": 6}))
    result = run_trial(spec)
    best = result.best
    assert best["replays"] == 6 and best["evaluations_seen"] >= 1
    seeds = spec.replay_seeds()
    assert len(set(seeds)) == 6 and spec.seed not in seeds
    rulebase = ChromosomeCodec(SOCCER_VOCABULARY).decode(np.array(best["chromosome"], dtype=np.int8).reshape(-1, 5))
    assert best["rule_text"] == format_rulebase(rulebase, SOCCER_VOCABULARY)
    games = play_games([rulebase] * 6, seeds, GameConfig(max_ticks=400), SOCCER_VOCABULARY) if len(rulebase) else []
    fitness = [g.fitness for g in games] or [1.0] * 6
    assert best["replay_fitness"] == pytest.approx(np.mean(fitness))
    assert best["replay_fitness_std"] == pytest.approx(np.std(fitness))


# ---- end to end, shrunk ----------------------------------------------------------------------------------
@pytest.mark.parametrize("name", BEYOND_NAMES)
def test_a_shrunk_preset_beyond_the_chapter_answers_too_small_with_its_figures(tmp_path, name):
    outcome = run_experiment(name, TINY, tmp_path, LocalExecutor(1))
    chosen = preset(name, TINY)
    with (tmp_path / BESTS_FILE).open(newline="") as handle:
        bests = list(csv.DictReader(handle))
    assert list(bests[0]) == list(BEST_COLUMNS)
    assert len(bests) == chosen.trials * len(chosen.settings) and {b["replays"] for b in bests} == {"4"}
    for kind in chosen.figures:
        assert (tmp_path / FIGURES_FOLDER / f"{name}-{kind}.png").read_bytes().startswith(b"\x89PNG")
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "## Beyond the chapter" in markdown and f"({name})" in markdown
    ((question, answer),) = outcome.report.answers
    assert question.preset == name and answer.verdict == TOO_SMALL
    assert "needs 5 trials per setting, our minimum (here 2), population 200 (here 6)" in answer.shown
    assert "its best re-played on 4 fresh starts (median)" in markdown
    assert outcome.report.findings == []  # no finding of the chapter belongs to these presets



def test_a_preset_beyond_into_the_chapters_folder_runs_only_its_new_trials(tmp_path):
    """The chapter's crossover comparison first, then uniform crossover into the same folder: the second run
    plays only the uniform trials (one- and two-point are the crossover preset's) and keeps the finding."""
    first = run_experiment("crossover", TINY, tmp_path, LocalExecutor(1))
    more = run_experiment("uniform-crossover", TINY, tmp_path, LocalExecutor(1))
    assert (first.ran, first.skipped) == (2 * TINY.trials, 0)
    assert (more.ran, more.skipped) == (TINY.trials, 2 * TINY.trials)
    with (tmp_path / BESTS_FILE).open(newline="") as handle:
        assert sorted({row["setting"] for row in csv.DictReader(handle)}) == ["one-point", "two-point", "uniform"]
    assert [q.preset for q, _ in more.report.answers] == ["uniform-crossover"]


def test_all_plus_after_all_plans_only_the_settings_beyond_it():
    """Trial files are named by configuration, so all-plus into an all folder runs only what all lacks:
    uniform crossover, rule pressure at 25 and 128, both games-per-evaluation settings, the restarts."""
    all_trials = {spec.name for spec in plan(ALL, FULL).specs}
    new = [spec for spec in plan(ALL_PLUS, FULL).specs if spec.name not in all_trials]
    assert sorted({spec.setting.label for spec in new}) == sorted(
        ["uniform", "25", "128", "1 game", "5 games", "4 x 25 generations"])
    assert len(new) == 6 * 10  # 10 trials each

# ---- the answers, from fabricated data of known answer ------------------------------------------------------
def bests_rows(name: str, values: dict[str, np.ndarray], seen: dict[str, np.ndarray] | None = None) -> BestsTable:
    rows = []
    for setting, replayed in values.items():
        for trial, value in enumerate(replayed):
            rows.append({"preset": name, "setting": setting, "trial": trial, "seed": trial, "algorithm": "ga",
                         "generation": 3, "fitness_seen": (seen or values)[setting][trial] - 0.1,
                         "evaluations_seen": 1, "replays": 100, "replay_fitness": value,
                         "replay_fitness_std": 0.1, "replay_goals": 1.0, "replay_scoring": 0.5})
    return BestsTable(rows)


def answer(name: str, curves: dict, bests: BestsTable, options: ExperimentOptions = ExperimentOptions(trials=10)):
    chosen = preset(name, options)
    ((_, assessment),) = assess_questions(StatisticsTable(fabricated(name, curves)), bests, [chosen])
    return assessment


def test_restarts_answer_which_finds_the_better_player():
    rng = np.random.default_rng(1)
    curves = {s: {"best": falling(0.6, 0.3, rng), "mean": falling(0.9, 0.7, rng)}
              for s in ("4 x 25 generations", "1 x 100 generations")}
    better = bests_rows("restarts", {"4 x 25 generations": rng.normal(0.30, 0.02, 10),
                                     "1 x 100 generations": rng.normal(0.45, 0.02, 10)})
    assert answer("restarts", curves, better).verdict == "4 x 25 generations better"
    alike = bests_rows("restarts", {s: rng.normal(0.4, 0.05, 10) for s in curves})
    assert answer("restarts", curves, alike).verdict == NO_DIFFERENCE
    small = answer("restarts", curves, better, ExperimentOptions(trials=10, population=50))
    assert small.verdict == TOO_SMALL and small.needs == "population 200 (here 50)"


def test_games_per_evaluation_answers_on_fresh_starts_not_on_what_the_ga_saw():
    rng = np.random.default_rng(2)
    curves = {s: {"best": falling(0.6, 0.3, rng), "mean": falling(0.9, 0.7, rng)} for s in ("1 game", "5 games")}
    robust = bests_rows("games-per-evaluation", {"1 game": rng.normal(0.55, 0.02, 10),
                                                 "5 games": rng.normal(0.40, 0.02, 10)})
    assessment = answer("games-per-evaluation", curves, robust)
    assert assessment.verdict == "5 games better"
    assert "Mann-Whitney U, two-sided, on the best re-played" in assessment.test


def test_uniform_crossover_answer_names_the_direction():
    rng = np.random.default_rng(3)
    worse = {"one-point": {"mean": falling(0.9, 0.6, rng), "best": falling(0.6, 0.3, rng)},
             "two-point": {"mean": falling(0.9, 0.6, rng), "best": falling(0.6, 0.3, rng)},
             "uniform": {"mean": falling(0.9, 0.8, rng), "best": falling(0.6, 0.3, rng)}}
    bests = bests_rows("uniform-crossover", {s: rng.normal(0.5, 0.02, 10) for s in worse})
    assert answer("uniform-crossover", worse, bests).verdict == "uniform worse (final average)"
    alike = {s: {"mean": falling(0.9, 0.6, rng), "best": falling(0.6, 0.3, rng)} for s in worse}
    assert answer("uniform-crossover", alike, bests).verdict == NO_DIFFERENCE


def test_rule_pressure_tells_more_rules_from_shorter_rules_and_the_bound():
    generations = 20
    noise = np.random.default_rng(4).normal(0, 0.01, (10, generations))
    ramp = np.tile(np.linspace(0, 1, generations), (10, 1)) + noise
    curves = {
        # more rules, each as long: premises grow with them, the length stays far from the bound
        "25": {"valid_rules_mean": 4 + 4 * ramp, "premises_mean": 3 * (4 + 4 * ramp),
               "genes_mean": np.full_like(ramp, 60)},
        # as many rules, each shorter
        "64": {"valid_rules_mean": np.full_like(ramp, 8), "premises_mean": 8 * (3 - 2 * ramp),
               "genes_mean": np.full_like(ramp, 40)},
        # more and shorter rules, reaching genes / 2
        "128": {"valid_rules_mean": 10 + 10 * ramp, "premises_mean": (10 + 10 * ramp) * (2 - ramp),
                "genes_mean": np.full_like(ramp, 40)},
    }
    bests = bests_rows("rule-pressure", {s: np.full(10, 0.5) for s in curves})
    assessment = answer("rule-pressure", curves, bests)
    assert assessment.verdict == "25: more rules; 64: shorter rules; 128: more and shorter rules (at the bound)"
    assert "128: valid rules" in assessment.measured and "at 100% of the bound" in assessment.measured


def test_the_report_shows_each_answer_with_its_test(tmp_path):
    rng = np.random.default_rng(5)
    curves = {s: {"best": falling(0.6, 0.3, rng), "mean": falling(0.9, 0.7, rng)}
              for s in ("4 x 25 generations", "1 x 100 generations")}
    bests = bests_rows("restarts", {s: rng.normal(0.4, 0.05, 10) for s in curves})
    restarts = preset("restarts", ExperimentOptions(trials=10))
    report = write_report(StatisticsTable(fabricated("restarts", curves)), [restarts], tmp_path, bests)
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "| chapter | question | answer here | measured here | test |" in markdown
    assert f"| {NO_DIFFERENCE} |" in markdown and "Luke" in markdown
    assert (tmp_path / FIGURES_FOLDER / "restarts-true_quality.png").is_file()
    assert report.answers[0][1].verdict == NO_DIFFERENCE


def test_a_folder_from_before_bests_were_kept_still_resumes(tmp_path):
    """A folder made before --replays (no "replays" in its manifest, trials without a best player file) is
    resumed, not refused: its finished trials are kept, bests.csv holds the trials that have a best."""
    run_experiment("crossover", TINY, tmp_path, LocalExecutor(1))
    manifest = json.loads((tmp_path / MANIFEST).read_text())
    del manifest["replays"]
    (tmp_path / MANIFEST).write_text(json.dumps(manifest))
    next((tmp_path / TRIALS_FOLDER).glob("*.best.json")).unlink()
    again = run_experiment("crossover", TINY, tmp_path, LocalExecutor(1))
    assert (again.ran, again.skipped) == (0, 2 * TINY.trials)
    with (tmp_path / BESTS_FILE).open(newline="") as handle:
        assert len(list(csv.DictReader(handle))) == 2 * TINY.trials - 1
    with pytest.raises(ExperimentError, match=r"other options \(max_ticks\)"):
        run_experiment("crossover", TINY.model_copy(update={"max_ticks": 61}), tmp_path, LocalExecutor(1))
