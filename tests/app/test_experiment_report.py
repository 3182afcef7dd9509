"""The report's verdicts come from the data: fabricated statistics with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from soccer_lab.app.experiment.presets import ExperimentOptions, preset
from soccer_lab.app.experiment.report import REPORT_HTML, REPORT_MD, write_report
from soccer_lab.app.experiment.verdicts import AGREES, DISAGREES, NOT_RUN, TOO_SMALL
from soccer_lab.app.experiment.table import COLUMNS, StatisticsTable

OPTIONS = ExperimentOptions(trials=10)  # the chapter's size: its findings can be judged


def fabricated(preset_name: str, curves: dict[str, dict[str, np.ndarray]]) -> list[dict]:
    """Rows for `preset_name`: curves[setting][column] is trials x generations; other columns are plain."""
    rows = []
    for setting, columns in curves.items():
        trials, generations = next(iter(columns.values())).shape
        for trial in range(trials):
            for generation in range(generations):
                row = {c: 0.0 for c in COLUMNS}
                row.update(preset=preset_name, setting=setting, trial=trial, seed=trial, algorithm="ga",
                           generation=generation, evaluations=20 * (generation + 1), goals_0=1.0,
                           unique_consequent_genes=100.0)
                row.update({column: float(values[trial, generation]) for column, values in columns.items()})
                rows.append(row)
    return rows


def falling(start: float, end: float, rng: np.random.Generator, trials: int = 10, generations: int = 10,
            noise: float = 0.02, spread: float = 0.0) -> np.ndarray:
    """A falling curve per trial, with noise per generation and a trial-to-trial offset of size `spread`."""
    offsets = rng.normal(0, spread, (trials, 1)) if spread else 0.0
    return np.linspace(start, end, generations) + rng.normal(0, noise, (trials, generations)) + offsets


def verdict(report, claim_start: str) -> str:
    (assessment,) = [a for f, a in report.findings if f.claim.startswith(claim_start)]
    return assessment.verdict


@pytest.fixture
def random_preset():
    return preset("random", OPTIONS)


def test_ga_no_better_than_random_search_says_so(tmp_path, random_preset):
    rng = np.random.default_rng(1)
    same = {"best": falling(0.6, 0.55, rng), "mean": falling(0.9, 0.85, rng)}  # the GA does exactly as well
    table = StatisticsTable(fabricated("random", {"GA": same, "random search": same}))
    report = write_report(table, [random_preset], tmp_path)
    assert verdict(report, "The GA finds better individuals") == DISAGREES
    assert verdict(report, "The GA improves its population") == DISAGREES
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "the GA is not significantly better than random search" in markdown
    assert "Mann-Whitney U, one-sided (GA lower)" in markdown
    assert verdict(report, "The population average fitness improves") == NOT_RUN  # initial not run
    assert not [f for f, _ in report.findings if f.preset == "robocup"]  # the other study's findings
    assert "rcssserver" not in markdown and len(report.findings) == 25


def test_ga_clearly_better_than_random_search_agrees(tmp_path, random_preset):
    rng = np.random.default_rng(2)
    ga = {"best": falling(0.5, 0.1, rng, noise=0.005), "mean": falling(0.9, 0.7, rng)}
    search = {"best": falling(0.6, 0.45, rng, noise=0.01, spread=0.1), "mean": falling(0.9, 0.9, rng)}
    table = StatisticsTable(fabricated("random", {"GA": ga, "random search": search}))
    report = write_report(table, [random_preset], tmp_path)
    assert verdict(report, "The GA finds better individuals") == AGREES
    assert verdict(report, "The GA finds them more consistently") == AGREES
    assert verdict(report, "Random search still finds goal-scoring") == AGREES  # its best reach 0.5
    assert (tmp_path / REPORT_HTML).read_text().count("data:image/png;base64,") == 2


def test_a_real_difference_between_settings_contradicts_a_no_difference_claim(tmp_path):
    rng = np.random.default_rng(3)
    crossover = preset("crossover", OPTIONS)
    curves = {"one-point": {"mean": falling(0.9, 0.6, rng), "best": falling(0.6, 0.3, rng)},
              "two-point": {"mean": falling(0.9, 0.8, rng), "best": falling(0.6, 0.5, rng)}}
    report = write_report(StatisticsTable(fabricated("crossover", curves)), [crossover], tmp_path)
    assert verdict(report, "One-point and two-point crossover") == DISAGREES

    alike = {"one-point": {"mean": falling(0.9, 0.7, rng), "best": falling(0.6, 0.4, rng)},
             "two-point": {"mean": falling(0.9, 0.7, rng), "best": falling(0.6, 0.4, rng)}}
    report = write_report(StatisticsTable(fabricated("crossover", alike)), [crossover], tmp_path)
    assert verdict(report, "One-point and two-point crossover") == AGREES


def test_too_few_trials_are_too_small_to_judge_and_say_what_they_need(tmp_path):
    rng = np.random.default_rng(4)
    crossover = preset("crossover", OPTIONS)
    alike = {s: {"mean": falling(0.9, 0.7, rng, trials=2), "best": falling(0.6, 0.4, rng, trials=2)}
             for s in ("one-point", "two-point")}
    report = write_report(StatisticsTable(fabricated("crossover", alike)), [crossover], tmp_path)
    (assessment,) = [a for f, a in report.findings if f.preset == "crossover"]
    assert assessment.verdict == TOO_SMALL and assessment.needs == "5 trials per setting, our minimum (here 2)"
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "| too small to judge (needs 5 trials per setting, our minimum (here 2)) |" in markdown


@pytest.mark.parametrize("shrunk, needs", [
    ({"population": 20}, "population 200 (here 20)"),
    ({"generations": 3}, "generations 25 (here 3)"),
    ({"max_ticks": 300}, "game length 1000 (here 300)"),
    ({"trials": 3, "population": 50, "generations": 10},
     "5 trials per setting, our minimum (here 3), population 200 (here 50), generations 25 (here 10)"),
])
def test_a_shrunk_run_never_disagrees_it_is_too_small_with_the_size_it_needs(tmp_path, shrunk, needs):
    """Data that would contradict the chapter at its size is "too small to judge" in a smaller run, the
    measured value still shown, and the report's header states the run's size against the chapter's."""
    rng = np.random.default_rng(7)
    trials = shrunk.get("trials", 10)
    scoring = {"Table 2": {"mean": falling(0.95, 0.45, rng, trials=trials),
                           "best": falling(0.6, 0.3, rng, trials=trials)}}
    table = StatisticsTable(fabricated("initial", scoring))
    if trials >= 5:
        assert verdict(write_report(table, [preset("initial", OPTIONS)], tmp_path),
                       "The average fitness plateaus around 0.75") == DISAGREES  # at the chapter's size
    small = preset("initial", ExperimentOptions(**{"trials": 10, **shrunk}))
    report = write_report(table, [small], tmp_path)
    assessments = [a for f, a in report.findings if f.preset == "initial"]
    assert {a.verdict for a in assessments} == {TOO_SMALL} and {a.needs for a in assessments} == {needs}
    assert report.verdicts()[TOO_SMALL] == 5 and report.verdicts()[DISAGREES] == 0
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "final average fitness 0.4" in markdown  # what was measured is still shown
    assert "(the chapter's: 200, 25, 1000)" in markdown and "Smaller than the chapter's in: " in markdown
    assert needs.split(", our minimum")[-1].lstrip(", ") in markdown


def test_a_run_at_the_chapters_size_says_so_in_its_header(tmp_path):
    rng = np.random.default_rng(8)
    kicking = {"Table 2": {"mean": falling(0.95, 0.76, rng, trials=20), "best": falling(0.6, 0.3, rng, trials=20)}}
    write_report(StatisticsTable(fabricated("initial", kicking)), [preset("initial", ExperimentOptions())], tmp_path)
    markdown = (tmp_path / REPORT_MD).read_text()
    assert ("Size: Table 2's control at population 200, 25 generations, games of 1000 ticks (the chapter's: 200, "
            "25, 1000); 20 trials per setting (the chapter's: 20 for its initial trials, 10 otherwise)") in markdown
    assert "Smaller than the chapter's" not in markdown and TOO_SMALL not in markdown.split("Each verdict")[0]


def test_the_average_fitness_plateau_level_is_measured(tmp_path):
    rng = np.random.default_rng(5)
    initial = preset("initial", OPTIONS)
    kicking = {"Table 2": {"mean": falling(0.95, 0.76, rng), "best": falling(0.6, 0.3, rng)}}
    report = write_report(StatisticsTable(fabricated("initial", kicking)), [initial], tmp_path)
    assert verdict(report, "The average fitness plateaus around 0.75") == AGREES
    assert verdict(report, "The population average fitness improves") == AGREES
    scoring = {"Table 2": {"mean": falling(0.95, 0.45, rng), "best": falling(0.6, 0.3, rng)}}
    report = write_report(StatisticsTable(fabricated("initial", scoring)), [initial], tmp_path)
    assert verdict(report, "The average fitness plateaus around 0.75") == DISAGREES


def test_each_setting_counts_the_trials_that_left_the_plateau_and_how(tmp_path):
    """The measured reason behind a disagreement: trials where nobody learned to kick, trials taken over
    by goal scorers, per setting."""
    rng = np.random.default_rng(6)
    selection = preset("selection", OPTIONS)
    ends = np.array([0.99] * 7 + [0.75, 0.5, 0.3])  # 7 never kicked, 1 plateaued, 2 taken over
    mixed = np.linspace(1.0, ends, 10).T  # trials x generations, from 1.0 to each end
    curves = {s: {"mean": mixed, "best": falling(0.6, 0.3, rng)} for s in ("roulette", "tournament", "elitist")}
    write_report(StatisticsTable(fabricated("selection", curves)), [selection], tmp_path)
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "trials where kicking never spread (final average >= 0.95)" in markdown
    assert markdown.count("| 7 of 10 | 2 of 10 |") == 3


def test_fitness_equal_but_for_float_noise_is_no_difference():
    """Running means of equal fitnesses differ in the last bits; rank tests must not call that a difference."""
    import numpy as np

    from soccer_lab.app.experiment.verdicts import _p_between, _settled

    noisy = {"50": _settled(np.array([0.05] * 9 + [0.1 / 2])), "500": _settled(np.array([0.05 + 1e-17] * 10)),
             "100": _settled(np.array([sum([0.05] * 3) / 3] * 10))}
    assert _p_between(noisy)[0] == 1.0
    assert _p_between({"ga": noisy["50"], "random": noisy["500"]}, alternative="less")[0] == 1.0
    different = {"a": np.array([0.05] * 10), "b": np.array([0.25] * 10)}
    assert _p_between(different)[0] < 0.05


def test_a_flat_curve_has_no_trend_and_says_so_without_warnings(tmp_path):
    """Rules per chromosome that stop changing: no rank correlation exists, so the claim of a rise
    disagrees with rho 0, and scipy is never asked for an undefined correlation."""
    import warnings

    from soccer_lab.app.experiment.report import trend

    long = preset("long", OPTIONS)
    flat = {"100 generations": {"rules_mean": np.full((10, 10), 15.0), "mean": np.full((10, 10), 0.7)}}
    table = StatisticsTable(fabricated("long", flat))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assessment = trend("rules_mean", "rules per chromosome (second half)", rising=True, from_share=0.5)(table, long)
    assert assessment.verdict == DISAGREES
    assert "15.0 -> 15.0, Spearman rho = +0.00" in assessment.measured
    rising = {"100 generations": {"rules_mean": np.tile(np.linspace(10, 20, 10), (10, 1))}}
    assessment = trend("rules_mean", "rules", rising=True)(StatisticsTable(fabricated("long", rising)), long)
    assert assessment.verdict == AGREES


def test_generation_axes_tick_whole_generations_and_histogram_bars_sit_on_them():
    """A 3-generation run used to tick 0.25, 0.5, ... with the goal histogram's bars beside the ticks."""
    from soccer_lab.app.experiment.figures import draw_figure

    rng = np.random.default_rng(9)
    initial = preset("initial", ExperimentOptions(trials=2, generations=3))
    table = StatisticsTable(fabricated("initial", {"Table 2": {
        "mean": falling(0.9, 0.8, rng, trials=2, generations=3),
        "best": falling(0.6, 0.5, rng, trials=2, generations=3),
        "goals_0": np.full((2, 3), 0.7), "goals_1": np.full((2, 3), 0.3)}}))
    for kind in ("mean_fitness", "best_fitness", "goal_histogram", "composition", "gene_pools"):
        figure, _ = draw_figure(kind, table, initial)
        (axes,) = figure.axes
        figure.canvas.draw()
        ticks = [t for t in axes.get_xticks() if axes.get_xlim()[0] <= t <= axes.get_xlim()[1]]
        assert ticks and all(float(t).is_integer() for t in ticks), (kind, ticks)
    figure, _ = draw_figure("goal_histogram", table, initial)
    bars = figure.axes[0].patches
    assert sorted({round(bar.get_x() + bar.get_width() / 2, 9) for bar in bars}) == [0, 1, 2]  # centred on each
    assert max(bar.get_y() + bar.get_height() for bar in bars) == pytest.approx(100)  # stacked to the whole population


def test_fewer_trials_than_the_chapter_is_said_beside_each_verdict_and_in_the_summary(tmp_path):
    """A run judged with 10 trials of the chapter's 20 (initial) once read "agrees" with no word of it."""
    rng = np.random.default_rng(9)
    kicking = {"Table 2": {"mean": falling(0.95, 0.76, rng), "best": falling(0.6, 0.3, rng)}}
    report = write_report(StatisticsTable(fabricated("initial", kicking)), [preset("initial", OPTIONS)], tmp_path)
    smaller = "10 trials per setting (the chapter's 20)"
    assert all(a.smaller == smaller for f, a in report.findings if f.preset == "initial")
    markdown = (tmp_path / REPORT_MD).read_text()
    assert f"Smaller than the chapter's in: {smaller}" in markdown
    assert f"(at a smaller size than the chapter's: {smaller})" in markdown
    assert f"{report.judged_smaller()} verdicts were judged at a smaller size" in markdown
    assert "(the chapter's: 20 for its initial trials, 10 otherwise)" in markdown


def test_no_difference_states_the_smallest_difference_its_test_could_detect(tmp_path):
    from soccer_lab.app.experiment.verdicts import detectable_difference

    rng = np.random.default_rng(10)
    crossover = preset("crossover", OPTIONS)
    alike = {s: {"mean": falling(0.9, 0.7, rng), "best": falling(0.6, 0.4, rng)} for s in ("one-point", "two-point")}
    report = write_report(StatisticsTable(fabricated("crossover", alike)), [crossover], tmp_path)
    (assessment,) = [a for f, a in report.findings if f.preset == "crossover"]
    assert assessment.verdict == AGREES and assessment.no_difference_found
    finals = {s: alike[s]["mean"][:, -1] for s in alike}
    difference, deviations, trials = detectable_difference(finals)
    assert trials == 10 and 1.2 < deviations < 1.35  # (1.96 + 0.84) * sqrt(2 / (10 * 0.955))
    assert f"could have detected a difference of about {difference:.3f} in final average" in assessment.test
    markdown = (tmp_path / REPORT_MD).read_text()
    assert f"Of the {report.verdicts()[AGREES]} agreements, {report.no_difference_agreements()} are 'no significant" \
           in markdown and report.no_difference_agreements() == 1


def test_then_plateaus_is_tested_not_only_first_against_last(tmp_path):
    rng = np.random.default_rng(11)
    initial = preset("initial", ExperimentOptions(trials=10, generations=25))
    generations = np.arange(25)
    plateauing = 0.76 + 0.2 * np.exp(-generations / 4) + rng.normal(0, 0.005, (10, 25))
    accelerating = 0.96 - 0.2 * (generations / 24) ** 3 + rng.normal(0, 0.005, (10, 25))  # falls faster at the end
    claim = "The population average fitness improves steadily, then plateaus"
    for curve, expected in ((plateauing, AGREES), (accelerating, DISAGREES)):
        table = StatisticsTable(fabricated("initial", {"Table 2": {"mean": curve, "best": curve - 0.3}}))
        report = write_report(table, [initial], tmp_path)
        (assessment,) = [a for f, a in report.findings if f.claim.startswith(claim)]
        assert assessment.verdict == expected, assessment.test
        assert "then plateaus: Wilcoxon signed-rank" in assessment.test
    assert "then plateaus fails" in assessment.reason


def test_each_disagreement_is_explained_under_it_from_the_runs_data(tmp_path):
    rng = np.random.default_rng(12)
    long = preset("long", OPTIONS)
    generations = np.arange(100)
    regrowing = 136 - 30 * np.minimum(generations, 3) / 3 + 0.15 * np.maximum(generations - 3, 0)
    curves = {"unique_premise_genes": regrowing + rng.normal(0, 0.5, (10, 100)),
              "mean": falling(0.95, 0.8, rng, generations=100), "best": falling(0.6, 0.4, rng, generations=100)}
    report = write_report(StatisticsTable(fabricated("long", {"100 generations": curves})), [long], tmp_path)
    (assessment,) = [a for f, a in report.findings if f.claim.startswith("The pool of unique premise genes")]
    assert assessment.verdict == DISAGREES
    assert "'slowly' is not tested" in assessment.test
    assert "by generation 3, then regrow" in assessment.reason
    markdown = (tmp_path / REPORT_MD).read_text()
    assert "Why 6.4.5, Fig. 29 disagrees" in markdown
    assert "docs/research/calibration.md#why-the-disagreements" in markdown
    disagreements = [f for f, a in report.findings if a.verdict == DISAGREES]
    assert markdown.count("Measured why: ") == len(disagreements) and all(a.reason for f, a in report.findings
                                                                          if a.verdict == DISAGREES)


@pytest.mark.parametrize("name", ["initial", "max-length", "long"])
def test_legends_stand_beside_the_data_and_axes_say_means_or_medians(name):
    """Legends once covered the initial goal histogram and the max-length chromosome lengths; curves were
    means over trials beside tables of medians, unlabelled."""
    from soccer_lab.app.experiment.figures import DRAWERS, draw_figure

    rng = np.random.default_rng(13)
    chosen = preset(name, OPTIONS)
    curves = {"mean": falling(0.9, 0.8, rng), "best": falling(0.6, 0.5, rng), "goals_0": np.full((10, 10), 0.7),
              "goals_1": np.full((10, 10), 0.3), "genes_mean": falling(20, 40, rng),
              "valid_rules_mean": falling(2, 6, rng), "unique_premise_genes": falling(130, 110, rng)}
    table = StatisticsTable(fabricated(name, {s.label: curves for s in chosen.settings}))
    for kind in (k for k in chosen.figures if k in DRAWERS):
        figure, _ = draw_figure(kind, table, chosen)
        (axes,) = figure.axes
        figure.canvas.draw()
        legend, plot = axes.get_legend(), axes.get_window_extent()
        assert legend is None or legend.get_window_extent().x0 >= plot.x1, f"{name} {kind}: the legend covers the data"
        label = axes.get_ylabel()
        assert any(word in label for word in ("median over trials", "mean over trials", "averaged over trials",
                                              "each trial")), f"{name} {kind}: {label!r}"


def test_a_fitness_figure_ends_at_the_median_its_table_gives(tmp_path):
    from soccer_lab.app.experiment.figures import draw_figure

    rng = np.random.default_rng(14)
    crossover = preset("crossover", OPTIONS)
    skewed = {s: {"mean": falling(0.9, 0.8, rng) ** 3, "best": falling(0.6, 0.5, rng)}
              for s in ("one-point", "two-point")}
    table = StatisticsTable(fabricated("crossover", skewed))
    figure, _ = draw_figure("mean_fitness", table, crossover)
    for line in figure.axes[0].lines:
        assert line.get_ydata()[-1] == pytest.approx(np.median(table.final("crossover", line.get_label(), "mean")))
