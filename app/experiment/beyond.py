"""Beyond the chapter: the questions its text leaves for future work, each answered from the data of its
preset (app/experiment/presets.py), with the test named, under the report's rules (ALPHA, too small to
judge below the chapter's size).

- uniform-crossover (6.4.4): does a far more disruptive crossover change the performance? Kruskal-Wallis
  H over the three crossovers on the final average, the run's best and the best re-played.
- rule-pressure (6.4.1, 6.4.5): is the pressure for more rules or for shorter rules, and what happens at
  the bound? Per maximum length, Wilcoxon signed-rank (two-sided) on each trial's change, from a quarter
  of the run to its end, of valid rules per chromosome and of premises per valid rule.
- games-per-evaluation (5.2): are players evolved on the mean of 5 games more robust, at equal games
  played? Mann-Whitney U (two-sided) on the bests re-played on fresh starts, and on how much worse they
  play there than the GA saw (its optimism).
- restarts (6.4.4, Luke): do several short runs beat one long run at equal evaluations? Mann-Whitney U
  (two-sided) on the bests re-played, and on the run's best as the GA saw it.
Every answer is "no significant difference" unless a test finds one (p < ALPHA).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy import stats

from soccer_lab.app.experiment.presets import LONG_GENERATIONS, RESTARTS, Preset
from soccer_lab.app.experiment.table import BestsTable, StatisticsTable
from soccer_lab.app.experiment.verdicts import (ALPHA, NOT_RUN, TOO_SMALL, Assessment, _best_so_far, _final, _groups,
                                                _medians, _p_between, _settled, too_small)

NO_DIFFERENCE = "no significant difference"
RULES_FROM_SHARE = 0.25  # rule counts compared from here (after the first generations' rise) to the end
AT_THE_BOUND = 0.90  # valid rules at this share of genes / 2 or more: at their bound
BEYOND_INTRODUCTION = (
    "Experiments the chapter names as future work, answered from this run's data. Each answer comes with the "
    f"test that gave it (at significance level {ALPHA}, two-sided); a difference the test does not find is "
    f"'{NO_DIFFERENCE}'. Each trial's best is also re-played on fresh starts: its true quality, where the GA saw "
    "one noisy game (or the mean of the few it survived).")


@dataclass(frozen=True)
class Question:
    preset: str
    where: str  # the chapter's words that leave it open
    question: str
    answer: Callable[[StatisticsTable, BestsTable, Preset], Assessment]


def _replayed(bests: BestsTable, preset: Preset) -> dict[str, np.ndarray]:
    return {s: _settled(bests.column(preset.name, s, "replay_fitness")) for s in bests.settings(preset.name)}


def _optimism(bests: BestsTable, preset: Preset) -> dict[str, np.ndarray]:
    """How much worse each best plays on fresh starts than the GA saw."""
    return {s: _settled(bests.column(preset.name, s, "replay_fitness") - bests.column(preset.name, s, "fitness_seen"))
            for s in bests.settings(preset.name)}


def _which_better(groups: dict[str, np.ndarray], p: float) -> str:
    """"X better" (lower fitness) when the test found a difference, else no difference."""
    if p >= ALPHA:
        return NO_DIFFERENCE
    return f"{min(groups, key=lambda s: np.median(groups[s]))} better"


# ---- the questions ----------------------------------------------------------------------------------
def _uniform_crossover(table: StatisticsTable, bests: BestsTable, preset: Preset) -> Assessment:
    measures = {"final average": _groups(table, preset, _final("mean")),
                "run's best": _groups(table, preset, _best_so_far), "best re-played": _replayed(bests, preset)}
    measured, tests, different = [], [], {}
    for name, groups in measures.items():
        p, test = _p_between(groups)
        measured.append(f"{name}: {_medians(groups)}")
        tests.append(f"{test} on {name}, p = {p:.3g}")
        if p < ALPHA:
            different[name] = np.median(groups["uniform"]) < np.median(
                np.concatenate([v for s, v in groups.items() if s != "uniform"]))
    if not different:
        answer = NO_DIFFERENCE
    elif len(set(different.values())) > 1:
        answer = "mixed: uniform better on " + ", ".join(n for n, better in different.items() if better)
    else:
        answer = f"uniform {'better' if next(iter(different.values())) else 'worse'} ({', '.join(different)})"
    return Assessment(" | ".join(measured), answer, "; ".join(tests))


def _rule_pressure(table: StatisticsTable, bests: BestsTable, preset: Preset) -> Assessment:
    answers, measured, tests = [], [], []
    for setting in table.settings(preset.name):
        rules = table.curves(preset.name, setting, "valid_rules_mean")
        with np.errstate(divide="ignore", invalid="ignore"):
            premises_per_rule = table.curves(preset.name, setting, "premises_mean") / rules
        bound = table.curves(preset.name, setting, "genes_mean") / 2
        start = round(RULES_FROM_SHARE * rules.shape[1])
        more, p_more = _changed(rules[:, start], rules[:, -1])
        shorter, p_shorter = _changed(premises_per_rule[:, -1], premises_per_rule[:, start])
        share = float(np.median(rules[:, -1] / bound[:, -1]))
        kind = {(True, True): "more and shorter rules", (True, False): "more rules",
                (False, True): "shorter rules", (False, False): "neither"}[more, shorter]
        answers.append(f"{setting}: {kind}" + (" (at the bound)" if share >= AT_THE_BOUND else ""))
        measured.append(f"{setting}: valid rules {np.median(rules[:, start]):.1f} -> {np.median(rules[:, -1]):.1f}, "
                        f"premises per rule {np.nanmedian(premises_per_rule[:, start]):.2f} -> "
                        f"{np.nanmedian(premises_per_rule[:, -1]):.2f}, at {share:.0%} of the bound (genes / 2)")
        tests.append(f"{setting}: rules p = {p_more:.3g}, premises per rule p = {p_shorter:.3g}")
    return Assessment("; ".join(measured), "; ".join(answers),
                      f"Wilcoxon signed-rank, two-sided, each trial from generation "
                      f"{round(RULES_FROM_SHARE * LONG_GENERATIONS)} of {LONG_GENERATIONS} (or the same share) to "
                      f"the last: " + "; ".join(tests) + f"; 'at the bound' from {AT_THE_BOUND:.0%} of genes / 2")


def _changed(before: np.ndarray, after: np.ndarray) -> tuple[bool, float]:
    """Whether `after` is significantly above `before` over the trials (Wilcoxon, two-sided), and p."""
    with np.errstate(invalid="ignore"):  # a trial without valid rules has no premises per rule (inf - inf)
        change = _settled(after - before)
    change = change[np.isfinite(change)]
    if len(change) == 0 or np.all(change == 0):
        return False, 1.0
    p = float(stats.wilcoxon(change).pvalue)
    return bool(p < ALPHA and np.median(change) > 0), p


def _games_per_evaluation(table: StatisticsTable, bests: BestsTable, preset: Preset) -> Assessment:
    quality, optimism = _replayed(bests, preset), _optimism(bests, preset)
    p_quality, test = _p_between(quality)
    p_optimism, _ = _p_between(optimism)
    spread = {s: bests.column(preset.name, s, "replay_fitness_std") for s in quality}
    answer = _which_better(quality, p_quality)
    measured = (f"best re-played: {_medians(quality)} | re-played minus as seen: {_medians(optimism)} | "
                f"std over the fresh starts: {_medians(spread)}")
    return Assessment(measured, answer, f"{test}, two-sided, on the best re-played, p = {p_quality:.3g}; on "
                                        f"re-played minus as seen, p = {p_optimism:.3g}")


def _restarts(table: StatisticsTable, bests: BestsTable, preset: Preset) -> Assessment:
    quality, seen = _replayed(bests, preset), _groups(table, preset, _best_so_far)
    p_quality, test = _p_between(quality)
    p_seen, _ = _p_between(seen)
    measured = f"best re-played: {_medians(quality)} | run's best as the GA saw it: {_medians(seen)}"
    return Assessment(measured, _which_better(quality, p_quality),
                      f"{test}, two-sided, on the best re-played, p = {p_quality:.3g}; on the run's best as seen, "
                      f"p = {p_seen:.3g}")


QUESTIONS: tuple[Question, ...] = (
    Question("uniform-crossover", "6.4.4", "\"It is not clear from this data if a much more disruptive crossover "
             "method, such as uniform crossover, would significantly affect the performance\": does rule-wise "
             "uniform crossover differ from one- and two-point?", _uniform_crossover),
    Question("rule-pressure", "6.4.1, 6.4.5", "\"Whether the pressure is for more rules or shorter rules\", and "
             "\"the effect of reaching the upper bound\" (half the chromosome length): over 100 generations, do "
             "valid rules per chromosome rise, premises per rule fall, at each maximum length?", _rule_pressure),
    Question("games-per-evaluation", "5.2", "Players evolved on the average of five games \"may be more robust\" "
             "than on a single game: at equal games played, which plays better on fresh starts?",
             _games_per_evaluation),
    Question("restarts", "6.4.4", f"Luke: \"performing many shorter experiments is likely to produce better "
             f"results than a single very long experiment\": {RESTARTS} runs of a quarter the generations "
             f"against one long run, at equal evaluations, which finds the better player?", _restarts),
)


def assess_questions(table: StatisticsTable, bests: BestsTable, presets: list[Preset],
                     questions: tuple[Question, ...] = QUESTIONS) -> list[tuple[Question, Assessment]]:
    """The questions of the presets run; "too small to judge" below the chapter's size, "not run"
    without bests (trials from before they were kept)."""
    by_name = {p.name: p for p in presets}
    results = []
    for question in questions:
        preset = by_name.get(question.preset)
        if preset is None:
            continue
        if not bests.settings(preset.name):
            results.append((question, Assessment("-", NOT_RUN, "no bests.csv rows for this preset")))
            continue
        assessment = question.answer(table, bests, preset)
        lacking = too_small(table, preset)
        results.append((question, Assessment(assessment.measured, TOO_SMALL, assessment.test, lacking)
                        if lacking else assessment))
    return results
