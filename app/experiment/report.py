"""The report: for each finding of the chapter's section 6 (RoboCupSoccer 6.1, SimpleSoccer 6.2-6.5), our
measured figure and a verdict computed from the statistics table, with the statistical test named
(report.md and report.html).

Tests (scipy.stats), at significance level ALPHA, on per-trial values (one value per trial, so the
trials are the independent samples):
- a claimed difference or its absence between settings: Kruskal-Wallis H (3+ settings) or
  Mann-Whitney U (2 settings; one-sided where the chapter names a direction);
- a claimed change within runs (first vs last generation of the same trial): Wilcoxon signed-rank, one-sided;
- a claimed trend along the run: Spearman rank correlation of the trial-averaged curve with the generation;
- a claimed difference in consistency: Brown-Forsythe (Levene's test about the median).
"No difference" claims agree when the test finds none. Claims about a level (e.g. "plateaus around 0.75")
have no test; the tolerance used is stated.

A shrunk run is judged only where it can tell: with fewer than MIN_TRIALS trials per setting (below it
the rank tests cannot reach p < ALPHA, and "no difference" is absence of evidence), or a smaller
population, fewer generations or shorter games than the chapter's Table 2 control (its findings
describe runs of that size), a finding's verdict is "too small to judge", with the size it needs; what
was measured is still shown. The report's header states the run's size against the chapter's.

The questions the chapter leaves open (its future work) are answered in "Beyond the chapter"
(app/experiment/beyond.py), under the same rules.
"""

from __future__ import annotations

import base64
import html
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import numpy as np
from scipy import stats

from soccer_lab.app.experiment.beyond import BEYOND_INTRODUCTION, QUESTIONS, assess_questions
from soccer_lab.app.experiment.figures import Figure, write_figures
from soccer_lab.app.experiment.presets import ANSWERED_NAMES, MATCHES, ROBOCUP, Preset
from soccer_lab.app.experiment.table import BestsTable, StatisticsTable
from soccer_lab.app.experiment.verdicts import (ALPHA, AGREES, DISAGREES, INCONCLUSIVE, MIN_TRIALS, NOT_RUN, POWER,
                                                TOO_SMALL, VERDICTS, Assessment, _best_so_far, _detectable_text, _final,
                                                _groups, _medians, _p_between, smaller_than_chapter, too_small)

GOAL_SCORING = 0.5  # fitness of one goal: at or below it a player scores (Table 1)
PLATEAU_LEVEL, PLATEAU_TOLERANCE = 0.75, 0.10  # 6.2: average fitness plateaus "around 0.75"
LENGTH_SHARE, LENGTH_TOLERANCE = 2 / 3, 0.10  # 6.4.1, 6.4.5: chromosome length settles at "about 2/3" of the maximum
EARLY_SHARE = 0.2  # 6.2: "very few generations": within the first fifth of the run (5 of 25)
LATE_START_SHARE = 0.10  # 6.4.4: "after the tenth generation" of 100
EARLY_BEST_SHARE = 0.15  # 6.4.4: "the first 10 to 15 generations" of 100
FLAT_IMPROVEMENT = 0.02  # fitness units: a smaller improvement of the average is "not significant" (6.4.4)
EQUAL_BEST = 0.01  # fitness units: two best fitnesses this close are "equal" (6.4.4)
CONSTANT_CHANGE = 0.15  # relative change under which a gene pool is "reasonably constant" (6.4.5)
POOL_INITIAL, POOL_PLATEAU_END = 0.05, 0.40  # 6.4.5: constant "for close to 40 [of 100] generations after an initial decrease"
ROBOCUP_PLATEAU_TOLERANCE = 0.10  # 6.1: the average "plateaus towards a fitness of 0.5" in some trials
ROBOCUP_MOST_GOALS, MOST_GOALS_TOLERANCE = 3, 1  # 6.1: "the maximum number of goals scored by any individual was 3"
SEVERAL_GOALS = ("goals_2", "goals_3", "goals_4", "goals_more")  # statistics columns: shares scoring 2 or more
GOAL_CLASSES = (("goals_1", 1), ("goals_2", 2), ("goals_3", 3), ("goals_4", 4), ("goals_more", 5))
REPORT_MD, REPORT_HTML = "report.md", "report.html"
# A trial's outcome, read from its last generation's average fitness: the measured reason behind most
# disagreements (the settings tables show it). At or above NEVER_KICKING nearly nobody kicks (a kicker
# scores at most ~0.77, Table 1); at or below SCORERS_SPREAD goal scorers have spread through the
# population, where the chapter's SimpleSoccer plateau stays around 0.75 (6.2).
NEVER_KICKING, SCORERS_SPREAD = 0.95, 0.60
WHY_PAGE = "docs/research/calibration.md#why-the-disagreements"  # the docs page that measured why they disagree


@dataclass(frozen=True)
class Finding:
    preset: str
    where: str  # section and figure of the chapter
    claim: str
    assess: Callable[[StatisticsTable, Preset], Assessment]


@dataclass(frozen=True)
class Report:
    findings: list[tuple[Finding, Assessment]]
    figures: list[Figure]

    answers: list = field(default_factory=list)  # (soccer_lab.app.experiment.beyond.Question, Assessment)

    def verdicts(self) -> dict[str, int]:
        counts = {v: 0 for v in VERDICTS}
        for _, assessment in self.findings:
            counts[assessment.verdict] += 1
        return counts

    def no_difference_agreements(self) -> int:
        """Agreements that are "no significant difference found": absence of evidence, not evidence."""
        return sum(a.verdict == AGREES and a.no_difference_found for _, a in self.findings)

    def judged_smaller(self) -> int:
        return sum(bool(a.smaller) for _, a in self.findings)


# ---- claim shapes -----------------------------------------------------------------------------------
def no_difference(*measures: tuple[str, Callable]) -> Callable[[StatisticsTable, Preset], Assessment]:
    """The chapter claims the varied parameter makes no significant difference to each measure."""
    def assess(table: StatisticsTable, preset: Preset) -> Assessment:
        measured, tests, detectable, reasons = [], [], [], []
        for name, values in measures:
            groups = _groups(table, preset, values)
            p, test = _p_between(groups)
            measured.append(f"{name}: {_medians(groups)}")
            tests.append(f"{test} on {name}, p = {p:.3g}")
            detectable.append(_detectable_text(name, groups))
            if p < ALPHA:
                reasons.append(_spread_reason(name, groups, p))
        text = " | ".join(measured)
        if reasons:
            return Assessment(text, DISAGREES, "; ".join(tests) + f": a significant difference (p < {ALPHA})",
                              reason="; ".join(reasons))
        return Assessment(text, AGREES, "; ".join(tests) + f": no significant difference (p >= {ALPHA}); "
                          + "; ".join(detectable), no_difference_found=True)
    return assess


def _spread_reason(name: str, groups: dict[str, np.ndarray], p: float) -> str:
    """Which settings differ, e.g. "final average is lowest at 15% (0.801) and highest at 1% (0.912), p = 0.01"."""
    medians = {s: float(np.median(v)) for s, v in groups.items()}
    low, high = min(medians, key=medians.get), max(medians, key=medians.get)
    return (f"{name} is lowest at {low} ({medians[low]:.3f}) and highest at {high} ({medians[high]:.3f}), "
            f"medians over trials, p = {p:.3g}")


def _shape(curve: np.ndarray, what: str) -> str:
    """A curve in words, e.g. "unique premise genes fall from 136 to 104 by generation 3, then regrow to 117"."""
    curve = curve[~np.isnan(curve)]
    low, high = int(np.argmin(curve)), int(np.argmax(curve))
    first, last = curve[0], curve[-1]
    for turn, verb, back in ((low, "fall", "regrow"), (high, "rise", "fall back")):
        if 0 < turn < len(curve) - 1 and abs(curve[turn] - last) > 0.25 * abs(curve[turn] - first):
            return (f"{what} {verb} from {first:.3g} to {curve[turn]:.3g} by generation {turn}, then {back} to "
                    f"{last:.3g} (mean over trials)")
    return f"{what} go from {first:.3g} to {last:.3g} over {len(curve)} generations (mean over trials)"


def _outcomes_reason(table: StatisticsTable, preset: Preset) -> str:
    """The two ways a run leaves the chapter's plateau: the measured reason behind most disagreements."""
    final = np.concatenate([table.final(preset.name, s, "mean") for s in table.settings(preset.name)])
    return (f"in this run {int(np.sum(final >= NEVER_KICKING))} of {len(final)} trials never spread kicking (final "
            f"average >= {NEVER_KICKING}) and {int(np.sum(final <= SCORERS_SPREAD))} were taken over by goal scorers "
            f"(<= {SCORERS_SPREAD}), where the chapter's populations plateau around {PLATEAU_LEVEL}")


def improves(column: str | tuple[str, ...], what: str, increase: bool) -> Callable[[StatisticsTable, Preset], Assessment]:
    """The chapter claims `column` (or the sum of several) rises (or falls) from the first to the last
    generation, in every setting."""
    columns = (column,) if isinstance(column, str) else column

    def assess(table: StatisticsTable, preset: Preset) -> Assessment:
        measured, tests, verdicts = [], [], []
        for setting in table.settings(preset.name):
            curves = sum(table.curves(preset.name, setting, c) for c in columns)
            start, end = curves[:, 0], np.array([row[~np.isnan(row)][-1] for row in curves])
            change = end - start if increase else start - end
            p = _wilcoxon_greater(change)
            measured.append(f"{setting}: {np.median(start):.3f} -> {np.median(end):.3f}")
            tests.append(f"{setting} p = {p:.3g}")
            if np.median(change) <= 0:
                verdicts.append(DISAGREES)
            elif p < ALPHA:
                verdicts.append(AGREES)
            else:
                verdicts.append(INCONCLUSIVE)
        verdict = DISAGREES if DISAGREES in verdicts else INCONCLUSIVE if INCONCLUSIVE in verdicts else AGREES
        test = f"Wilcoxon signed-rank, one-sided, first vs last generation of each trial: {'; '.join(tests)}"
        wrong = [s for s, v in zip(table.settings(preset.name), verdicts) if v == DISAGREES]
        reason = "; ".join(f"at {s}: " + _shape(np.nanmean(sum(table.curves(preset.name, s, c) for c in columns),
                                                            axis=0), what) for s in wrong)
        return Assessment(f"{what} (median first -> last): {'; '.join(measured)}", verdict, test, reason=reason)
    return assess


def improves_then_plateaus(column: str, what: str) -> Callable[[StatisticsTable, Preset], Assessment]:
    """The chapter claims `column` falls steadily, then plateaus: three tests, one a part. Falls: first vs
    last generation (Wilcoxon). Steadily: the trial-averaged curve's first half trends down (Spearman).
    Then plateaus: each trial gains less in its second half than in its first (Wilcoxon, paired)."""
    falls = improves(column, what, increase=False)

    def assess(table: StatisticsTable, preset: Preset) -> Assessment:
        overall = falls(table, preset)
        curves = np.concatenate([table.curves(preset.name, s, column) for s in table.settings(preset.name)])
        middle = curves.shape[1] // 2
        if middle < 2:
            return Assessment(overall.measured, TOO_SMALL, overall.test, "4 generations to tell a plateau")
        mean = np.nanmean(curves, axis=0)
        rho, p_steady = _spearman(mean[:middle + 1])
        last = np.array([row[~np.isnan(row)][-1] for row in curves])
        early, late = curves[:, 0] - curves[:, middle], curves[:, middle] - last
        p_plateau = _wilcoxon_greater(early - late)
        parts = {"falls": overall.verdict,
                 "steadily": _direction_verdict(rho < 0, p_steady),
                 "then plateaus": _direction_verdict(np.median(early - late) > 0, p_plateau)}
        verdict = (DISAGREES if DISAGREES in parts.values() else INCONCLUSIVE if INCONCLUSIVE in parts.values()
                   else AGREES)
        measured = (f"{overall.measured}; gain in the first half {np.median(early):.3f}, in the second "
                    f"{np.median(late):.3f} (medians over trials)")
        test = (f"falls: {overall.test}; steadily: Spearman rank correlation of the mean curve with the generation, "
                f"first half, rho = {rho:+.2f}, p = {p_steady:.3g}; then plateaus: Wilcoxon signed-rank, one-sided, "
                f"first-half gain > second-half gain, p = {p_plateau:.3g}. Parts: "
                + ", ".join(f"{part} {v}" for part, v in parts.items()))
        failed = [part for part, v in parts.items() if v == DISAGREES]
        failing = f"the part {failed[0]} fails" if len(failed) == 1 else f"the parts {' and '.join(failed)} fail"
        reason = f"{failing}: {_shape(mean, what)}" if failed else ""
        return Assessment(measured, verdict, test, reason=reason)
    return assess


def _spearman(part: np.ndarray) -> tuple[float, float]:
    if np.ptp(part) == 0 or np.isnan(part).any() or len(part) < 3:  # flat or gapped: no trend
        return 0.0, 1.0
    rho, p = stats.spearmanr(np.arange(len(part)), part)
    return float(rho), float(p)


def _wilcoxon_greater(differences: np.ndarray) -> float:
    try:
        with np.errstate(divide="ignore", invalid="ignore"):  # a handful of trials: no normal approximation
            return float(stats.wilcoxon(differences, alternative="greater").pvalue)
    except ValueError:  # no difference at all
        return 1.0


def _direction_verdict(right_way: bool, p: float) -> str:
    return AGREES if right_way and p < ALPHA else DISAGREES if not right_way else INCONCLUSIVE


def trend(column: str, what: str, rising: bool, from_share: float = 0.0,
          untested: str = "") -> Callable[[StatisticsTable, Preset], Assessment]:
    """The chapter claims a steady rise (fall) of the trial-averaged curve from `from_share` of the run on;
    `untested`: the part of the claim a trend cannot test, said in the verdict's test."""
    def assess(table: StatisticsTable, preset: Preset) -> Assessment:
        curve = np.nanmean(table.curves(preset.name, table.settings(preset.name)[0], column), axis=0)
        part = curve[int(from_share * len(curve)):]
        if len(part) < MIN_TRIALS:
            return Assessment(f"{what}: {len(part)} generations", TOO_SMALL, "Spearman rank correlation",
                              f"{MIN_TRIALS} generations in the part tested (here {len(part)})")
        if np.ptp(part) == 0 or np.isnan(part).any():  # a flat (or gapped) curve has no rank correlation: no trend
            rho, p = 0.0, 1.0
        else:
            rho, p = (float(value) for value in stats.spearmanr(np.arange(len(part)), part))
        measured = f"{what}: {part[0]:.1f} -> {part[-1]:.1f}, Spearman rho = {rho:+.2f}"
        right_way = rho > 0 if rising else rho < 0
        verdict = AGREES if right_way and p < ALPHA else DISAGREES if not right_way else INCONCLUSIVE
        scope = f" from generation {int(from_share * len(curve))}" if from_share else ""
        note = f" (tests the trend only: {untested} is not tested)" if untested else ""
        reason = _shape(part, what) if verdict == DISAGREES else ""
        return Assessment(measured, verdict, f"Spearman rank correlation with the generation{scope}, p = {p:.3g}{note}",
                          reason=reason)
    return assess


# ---- the individual claims --------------------------------------------------------------------------
def _plateau_level(table: StatisticsTable, preset: Preset) -> Assessment:
    final = np.concatenate([table.final(preset.name, s, "mean") for s in table.settings(preset.name)])
    level = float(np.median(final))
    agrees = abs(level - PLATEAU_LEVEL) <= PLATEAU_TOLERANCE
    return Assessment(f"final average fitness {level:.3f} (median over {len(final)} trials)",
                      AGREES if agrees else DISAGREES, f"no test (a level): agreement within +-{PLATEAU_TOLERANCE}")


def _early_goal_scorers(table: StatisticsTable, preset: Preset) -> Assessment:
    curves = np.concatenate([table.curves(preset.name, s, "best") for s in table.settings(preset.name)])
    firsts = [int(np.argmax(curve <= GOAL_SCORING)) if np.any(curve <= GOAL_SCORING) else None for curve in curves]
    found = [f for f in firsts if f is not None]
    limit = max(1, round(EARLY_SHARE * curves.shape[1]))
    measured = (f"a goal scorer (best <= {GOAL_SCORING}) in {len(found)} of {len(firsts)} trials"
                + (f", first at generation {np.median(found):.0f} (median)" if found else ""))
    agrees = len(found) > len(firsts) / 2 and np.median(found) < limit
    return Assessment(measured, AGREES if agrees else DISAGREES,
                      f"no test: agreement if most trials find one before generation {limit}")


def _high_scorers(table: StatisticsTable, preset: Preset) -> Assessment:
    settings = table.settings(preset.name)
    most = max(float(np.nanmax(table.curves(preset.name, s, "goals_more"))) for s in settings)
    best = min(float(np.nanmin(table.curves(preset.name, s, "best"))) for s in settings)
    measured = f"largest share scoring more than 4 goals {most:.1%}; lowest best fitness {best:.3f}"
    return Assessment(measured, AGREES if most > 0 else DISAGREES, "no test: agreement if any individual scored > 4")


def _few_scorers(table: StatisticsTable, preset: Preset) -> Assessment:
    final = np.concatenate([table.final(preset.name, s, "goals_0") for s in table.settings(preset.name)])
    share = float(np.median(final))
    return Assessment(f"share scoring no goal in the last generation {share:.1%} (median over trials)",
                      AGREES if share > 0.5 else DISAGREES, "no test: agreement if most of the population scores none")


def _towards_goal_scoring(table: StatisticsTable, preset: Preset) -> Assessment:
    final = np.concatenate([table.final(preset.name, s, "mean") for s in table.settings(preset.name)])
    near = int(np.sum(final <= GOAL_SCORING + ROBOCUP_PLATEAU_TOLERANCE))
    return Assessment(f"{near} of {len(final)} trials end with an average fitness within {ROBOCUP_PLATEAU_TOLERANCE} "
                      f"of {GOAL_SCORING} (lowest {np.min(final):.3f}, median {np.median(final):.3f})",
                      AGREES if near >= 1 else DISAGREES,
                      f"no test (a level): agreement if at least one trial ends at or below "
                      f"{GOAL_SCORING + ROBOCUP_PLATEAU_TOLERANCE:.2f}")


def _most_goals(table: StatisticsTable, preset: Preset) -> Assessment:
    settings = table.settings(preset.name)
    scored = [goals for column, goals in GOAL_CLASSES
              if any(np.nanmax(table.curves(preset.name, s, column)) > 0 for s in settings)]
    most = max(scored, default=0)
    shown = "more than 4" if most > 4 else str(most)
    agrees = abs(most - ROBOCUP_MOST_GOALS) <= MOST_GOALS_TOLERANCE
    return Assessment(f"the most goals any individual scored: {shown}", AGREES if agrees else DISAGREES,
                      f"no test: agreement within {ROBOCUP_MOST_GOALS} +- {MOST_GOALS_TOLERANCE} goals")


def _length_share(table: StatisticsTable, preset: Preset) -> Assessment:
    maxima = {s.label: s.ga.max_length for s in preset.settings}
    shares = {s: float(np.median(table.final(preset.name, s, "genes_mean"))) / maxima[s]
              for s in table.settings(preset.name)}
    agrees = all(abs(v - LENGTH_SHARE) <= LENGTH_TOLERANCE for v in shares.values())
    measured = "final length / maximum: " + "; ".join(f"{s}: {v:.2f}" for s, v in shares.items())
    return Assessment(measured, AGREES if agrees else DISAGREES,
                      f"no test (a level): agreement within {LENGTH_SHARE:.2f} +- {LENGTH_TOLERANCE}")


def _roulette_unstable(table: StatisticsTable, preset: Preset) -> Assessment:
    def wobble(setting: str) -> np.ndarray:  # generation-to-generation movement of the best, second half
        curves = table.curves(preset.name, setting, "best")
        half = max(0, min(curves.shape[1] // 2, curves.shape[1] - 2))  # a shrunk run keeps one change at least
        return np.nanmean(np.abs(np.diff(curves[:, half:], axis=1)), axis=1)

    groups = {s: wobble(s) for s in table.settings(preset.name)}
    others = np.concatenate([v for s, v in groups.items() if s != "roulette"])
    p = float(stats.mannwhitneyu(groups["roulette"], others, alternative="greater").pvalue)
    measured = "mean |change of best per generation|, second half: " + _medians(groups)
    return Assessment(measured, AGREES if p < ALPHA else DISAGREES,
                      f"Mann-Whitney U, one-sided, roulette vs the others, p = {p:.3g}")


def _elitist_like_tournament(table: StatisticsTable, preset: Preset) -> Assessment:
    groups = {s: table.final(preset.name, s, "best") for s in ("tournament", "elitist")}
    p, test = _p_between(groups)
    measured = f"final best: {_medians(groups)}"
    test = f"{test}, two-sided, p = {p:.3g}"
    if p < ALPHA:
        return Assessment(measured, DISAGREES, test + f": a significant difference (p < {ALPHA})",
                          reason=_spread_reason("final best", groups, p))
    return Assessment(measured, AGREES, test + f": no significant difference; {_detectable_text('final best', groups)}",
                      no_difference_found=True)


def _best_mutation_rate(table: StatisticsTable, preset: Preset) -> Assessment:
    groups = _groups(table, preset, _final("best"))
    lowest = min(groups, key=lambda s: np.median(groups[s]))
    p, test = _p_between(groups)
    significance = "significant" if p < ALPHA else "not significant"
    return Assessment(f"lowest final best fitness at {lowest}; {_medians(groups)}",
                      AGREES if lowest == "15%" else DISAGREES, f"{test} on final best fitness, p = {p:.3g} ({significance})")


def _flat_after_ten(table: StatisticsTable, preset: Preset) -> Assessment:
    curves = table.curves(preset.name, table.settings(preset.name)[0], "mean")
    tenth = max(1, round(LATE_START_SHARE * curves.shape[1]))
    gains = curves[:, tenth] - np.array([row[~np.isnan(row)][-1] for row in curves])
    flat = int(np.sum(gains < FLAT_IMPROVEMENT))
    return Assessment(f"{flat} of {len(gains)} trials improve their average by less than {FLAT_IMPROVEMENT} "
                      f"after generation {tenth}", AGREES if flat > len(gains) / 2 else DISAGREES,
                      "no test: agreement if more than half the trials")


def _early_best(table: StatisticsTable, preset: Preset) -> Assessment:
    curves = table.curves(preset.name, table.settings(preset.name)[0], "best")
    early = max(1, round(EARLY_BEST_SHARE * curves.shape[1]))
    gaps = np.nanmin(curves[:, :early], axis=1) - np.nanmin(curves, axis=1)
    equal = int(np.sum(gaps <= EQUAL_BEST))
    return Assessment(f"{equal} of {len(gaps)} trials reach their best (within {EQUAL_BEST}) in the first {early} "
                      f"generations", AGREES if equal >= 0.8 * len(gaps) else DISAGREES,
                      "no test: agreement if at least 80% of the trials ('almost every case')")


def _consequent_pool(table: StatisticsTable, preset: Preset) -> Assessment:
    curve = np.nanmean(table.curves(preset.name, table.settings(preset.name)[0], "unique_consequent_genes"), axis=0)
    start, end = max(1, round(POOL_INITIAL * len(curve))), max(1, round(POOL_PLATEAU_END * len(curve)))
    dropped = curve[start] < curve[0]
    change = abs(curve[end] - curve[start]) / curve[start]
    agrees = dropped and change <= CONSTANT_CHANGE
    return Assessment(f"unique consequent genes {curve[0]:.0f} -> {curve[start]:.0f} (generation {start}) -> "
                      f"{curve[end]:.0f} (generation {end}), change {change:.0%}", AGREES if agrees else DISAGREES,
                      f"no test: agreement if it drops first, then changes by at most {CONSTANT_CHANGE:.0%}")


def _ga_better(column_values, what: str) -> Callable[[StatisticsTable, Preset], Assessment]:
    def assess(table: StatisticsTable, preset: Preset) -> Assessment:
        ga, search = table.settings(preset.name)
        groups = {ga: column_values(table, preset, ga), search: column_values(table, preset, search)}
        p, _ = _p_between(groups, alternative="less")
        measured = f"{what}: {_medians(groups)}"
        if p < ALPHA:
            return Assessment(measured, AGREES, f"Mann-Whitney U, one-sided (GA lower), p = {p:.3g}")
        return Assessment(measured, DISAGREES, f"Mann-Whitney U, one-sided (GA lower), p = {p:.3g}: "
                                               f"the GA is not significantly better than random search")
    return assess


def _ga_consistent(table: StatisticsTable, preset: Preset) -> Assessment:
    ga, search = table.settings(preset.name)
    a, b = _best_so_far(table, preset, ga), _best_so_far(table, preset, search)
    with np.errstate(divide="ignore", invalid="ignore"):  # undefined when the deviations do not vary
        p = float(stats.levene(a, b, center="median").pvalue)
    p = 1.0 if np.isnan(p) else p
    measured = f"std of the runs' best fitness: {ga} {np.std(a):.3f}; {search} {np.std(b):.3f}"
    test = f"Brown-Forsythe (Levene, median-centred), p = {p:.3g}"
    if np.std(a) >= np.std(b):
        return Assessment(measured, DISAGREES, test)
    return Assessment(measured, AGREES if p < ALPHA else INCONCLUSIVE, test)


def _random_finds_scorers(table: StatisticsTable, preset: Preset) -> Assessment:
    search = table.settings(preset.name)[-1]
    best = table.best_so_far(preset.name, search)
    found = int(np.sum(best <= GOAL_SCORING))
    return Assessment(f"{found} of {len(best)} random-search trials find a goal scorer (best <= {GOAL_SCORING})",
                      AGREES if found >= len(best) / 2 else DISAGREES,
                      "no test: agreement if at least half the trials ('with some consistency')")


FINDINGS: tuple[Finding, ...] = (
    Finding("robocup", "6.1, Fig. 8", "On rcssserver the population average fitness improves steadily.",
            trend("mean", "average fitness (mean over trials)", rising=False)),
    Finding("robocup", "6.1, Fig. 8", "On rcssserver the average fitness plateaus towards 0.5 (goal scoring) in "
            "some trials.",
            _towards_goal_scoring),
    Finding("robocup", "6.1, Fig. 9", "On rcssserver good (goal-scoring) individuals are found after very few "
            "generations.",
            _early_goal_scorers),
    Finding("robocup", "6.1, Fig. 10", "On rcssserver more players learn to score goals over the generations.",
            improves("goals_0", "share of the population scoring no goal", increase=False)),
    Finding("robocup", "6.1, Fig. 10", "On rcssserver players learn to score more goals: the share scoring 2 or "
            "more rises.",
            improves(SEVERAL_GOALS, "share of the population scoring 2 or more goals", increase=True)),
    Finding("robocup", "6.1, Fig. 10", "On rcssserver no individual scores many goals: the most by any "
            "individual was 3.",
            _most_goals),
    Finding("initial", "6.2, Fig. 11", "The population average fitness improves steadily, then plateaus.",
            improves_then_plateaus("mean", "average fitness")),
    Finding("initial", "6.2, Fig. 11", "The average fitness plateaus around 0.75 (ball kicking), not near 0.5 "
            "(goal scoring).", _plateau_level),
    Finding("initial", "6.2, Fig. 12", "Good (goal-scoring) individuals are found after very few generations.",
            _early_goal_scorers),
    Finding("initial", "6.2, Fig. 13", "Some individuals score more than 4 goals (the best scored 10).", _high_scorers),
    Finding("initial", "6.2, Fig. 13", "The population's goal scoring stays little developed: most individuals "
            "score none.", _few_scorers),
    Finding("max-length", "6.4.1, Figs. 14-15", "The maximum chromosome length makes no significant difference to "
            "the average or the best fitness.", no_difference(("final average", _final("mean")),
                                                              ("run's best", _best_so_far))),
    Finding("max-length", "6.4.1, Fig. 16", "The average chromosome length settles at about 2/3 of the maximum.",
            _length_share),
    Finding("max-length", "6.4.1, Fig. 17", "Valid rules per chromosome rise in every setting.",
            improves("valid_rules_mean", "valid rules per chromosome", increase=True)),
    Finding("population", "6.4.2, Figs. 18-19", "At equal evaluations, population size makes no significant "
            "difference to the average or the best fitness.", no_difference(("final average", _final("mean")),
                                                                            ("run's best", _best_so_far))),
    Finding("selection", "6.4.3, Fig. 20", "The selection method is not a significant determinant of the average "
            "fitness.", no_difference(("final average", _final("mean")))),
    Finding("selection", "6.4.3, Fig. 21", "Elitist selection gives best fitness similar to tournament selection.",
            _elitist_like_tournament),
    Finding("selection", "6.4.3, Fig. 21", "Roulette-wheel selection gives a less stable best fitness.",
            _roulette_unstable),
    Finding("crossover", "6.4.4, Figs. 22-23", "One-point and two-point crossover do not differ meaningfully in "
            "average or best fitness.", no_difference(("final average", _final("mean")), ("final best", _final("best")))),
    Finding("mutation", "6.4.4, Fig. 24", "The mutation rate has only a marginal effect on the average fitness.",
            no_difference(("final average", _final("mean")))),
    Finding("mutation", "6.4.4, Fig. 25", "A mutation rate of 15% gives the best fitness.", _best_mutation_rate),
    Finding("long", "6.4.4, Fig. 26", "For more than half the trials the average fitness does not improve "
            "significantly after the tenth generation.", _flat_after_ten),
    Finding("long", "6.4.4, Fig. 27", "In almost every trial an individual of the first 10-15 generations reaches "
            "the best fitness seen in 100 generations.", _early_best),
    Finding("long", "6.4.5, Fig. 28", "Chromosome length does not grow uncontrollably: it plateaus at about 2/3 of "
            "the maximum.", _length_share),
    Finding("long", "6.4.5, Fig. 28", "Rules per chromosome keep growing, still increasing after 100 generations.",
            trend("rules_mean", "rules per chromosome (second half)", rising=True, from_share=0.5)),
    Finding("long", "6.4.5, Fig. 29", "The pool of unique premise genes falls slowly but steadily.",
            trend("unique_premise_genes", "unique premise genes", rising=False, untested="'slowly'")),
    Finding("long", "6.4.5, Fig. 29", "The pool of unique consequent genes stays reasonably constant for ~40 "
            "generations after an initial decrease.", _consequent_pool),
    Finding("random", "6.5, Fig. 31", "The GA finds better individuals than random search.",
            _ga_better(_best_so_far, "run's best fitness")),
    Finding("random", "6.5, Fig. 31", "The GA finds them more consistently (it is more robust).", _ga_consistent),
    Finding("random", "6.5", "Random search still finds goal-scoring individuals, with some consistency.",
            _random_finds_scorers),
    Finding("random", "6.5, Fig. 30", "The GA improves its population's average fitness; random search does not.",
            _ga_better(_final("mean"), "final average fitness")),
)


def _study(preset_name: str) -> str:
    """The chapter's two studies: its RoboCup trials (6.1) and its SimpleSoccer study (6.2-6.5)."""
    return "rcssserver" if preset_name == ROBOCUP else "SimpleSoccer"


def assess_findings(table: StatisticsTable, presets: list[Preset]) -> list[tuple[Finding, Assessment]]:
    """Every finding of the study the presets belong to, assessed from the table ("not run" when its
    preset is not in it; "too small to judge" when the run is smaller than it needs); the other study's
    findings are left out (`experiment all` is the whole SimpleSoccer study, `experiment robocup` the
    RoboCup trials). Presets beyond the chapter alone have no findings of it."""
    by_name = {p.name: p for p in presets}
    studies = {_study(p.name) for p in presets if p.name not in ANSWERED_NAMES}
    present = set(table.presets())
    results = []
    for finding in FINDINGS:
        if _study(finding.preset) not in studies:
            continue
        if finding.preset in present and finding.preset in by_name:
            results.append((finding, judged(finding.assess, table, by_name[finding.preset])))
        else:
            results.append((finding, Assessment("-", NOT_RUN, "-")))
    return results


def judged(assess: Callable[[StatisticsTable, Preset], Assessment], table: StatisticsTable,
           preset: Preset) -> Assessment:
    """The assessment, or "too small to judge" (what was measured kept) when the run is smaller than
    the finding needs."""
    assessment = assess(table, preset)
    lacking = too_small(table, preset)
    if lacking:
        return Assessment(assessment.measured, TOO_SMALL, assessment.test, lacking)
    if assessment.verdict == DISAGREES and not assessment.reason:
        assessment = replace(assessment, reason=_outcomes_reason(table, preset))
    return replace(assessment, smaller=smaller_than_chapter(table, preset))


# ---- writing --------------------------------------------------------------------------------------
METHOD = (f"Each verdict is computed from statistics.csv. Tests use one value per trial, at significance "
          f"level {ALPHA}: Kruskal-Wallis H (3+ settings) or Mann-Whitney U (2 settings) for differences between "
          f"settings; Wilcoxon signed-rank for a change from the first to the last generation of the same trials; "
          f"Spearman rank correlation for a trend along the run; Brown-Forsythe for a difference in consistency. "
          f"A claimed absence of difference agrees when no significant difference is found, and says the smallest "
          f"difference its test could have detected with its trials (alpha {ALPHA}, power {POWER}): absence of "
          f"evidence, counted apart in the summary. A claim of several parts (\"improves steadily, then "
          f"plateaus\") is tested part by part, or its test says which part it tested. A run with fewer than "
          f"{MIN_TRIALS} trials per setting (our minimum), or smaller than the chapter's Table 2 control "
          f"(population, generations, game length), is too small to judge: such verdicts say the size they need; "
          f"a run judged with fewer trials than the chapter's (20 for its initial trials, 10 otherwise) says so "
          f"beside each verdict. Each disagreement is followed by the reason this run's data show, with the docs "
          f"page that measured why ({WHY_PAGE}). Claims about a level name their tolerance. Each "
          f"setting's table counts the trials whose population never learned to kick (final average at or above "
          f"{NEVER_KICKING}) and those taken over by goal scorers (at or below {SCORERS_SPREAD}): the two ways a "
          f"run leaves the chapter's plateau around {PLATEAU_LEVEL}, and the measured reason behind most "
          f"disagreements.")


def write_report(table: StatisticsTable, presets: list[Preset], folder: Path,
                 bests: BestsTable | None = None) -> Report:
    """Figures, report.md and report.html into `folder`; `bests` (bests.csv) adds each trial's best as
    the GA saw it and re-played, and the answers beyond the chapter."""

    bests = bests or BestsTable([])
    present = [p for p in presets if p.name in table.presets()]
    figures = {p.name: write_figures(table, p, folder, bests) for p in present}
    questions = QUESTIONS
    for preset in (p for p in present if p.name == MATCHES):  # its questions are answered by matches played now
        from soccer_lab.app.experiment.matches import matches_questions, write_matches_figures

        asked, study = matches_questions(folder, preset, bests)
        figures[preset.name] += write_matches_figures(study, folder)
        questions += asked
    report = Report(assess_findings(table, presets), [f for p in present for f in figures[p.name]],
                    assess_questions(table, bests, present, questions))
    blocks = _blocks(table, bests, present, figures, report)
    (folder / REPORT_MD).write_text(_markdown(blocks))
    (folder / REPORT_HTML).write_text(_html(blocks, folder))
    return report


def run_size(table: StatisticsTable, bests: BestsTable, presets: list[Preset]) -> str:
    """The run's size against the chapter's, for the report's header."""
    if not presets:
        return "Nothing run."
    size, chapter = presets[0].size, presets[0].chapter_size
    trials = sorted({len(table.trials(p.name, s)) for p in presets for s in table.settings(p.name)})
    replays = sorted({int(row["replays"]) for row in bests.rows})
    trials_text = str(trials[0]) if len(trials) == 1 else f"{trials[0]}-{trials[-1]}"
    text = (f"Size: Table 2's control at population {size.population}, {size.generations} generations, games of "
            f"{size.max_ticks} ticks (the chapter's: {chapter.population}, {chapter.generations}, "
            f"{chapter.max_ticks}); {trials_text} trials per setting (the chapter's: 20 for its initial trials, "
            f"10 otherwise)")
    if replays:
        text += f"; each trial's best re-played on {', '.join(map(str, replays))} fresh starts"
    smaller = list(dict.fromkeys(filter(None, (smaller_than_chapter(table, p) for p in presets))))
    if smaller:
        text += f". Smaller than the chapter's in: {'; '.join(smaller)}"
        if any(too_small(table, p) for p in presets):
            text += (f"; below our minimum ({MIN_TRIALS} trials per setting) or the chapter's population, generations "
                     f"or game length a finding is '{TOO_SMALL}', with the size it needs")
        text += "; every other verdict says it was judged at a smaller size"
    return text + "."


def _blocks(table: StatisticsTable, bests: BestsTable, presets: list[Preset], figures: dict[str, list[Figure]],
            report: Report) -> list:
    counts = report.verdicts()
    blocks: list = [("h1", "soccer-lab: the chapter's experiments"),
                    ("p", run_size(table, bests, presets)),
                    ("p", _verdict_summary(report, counts)),
                    ("p", METHOD)]
    chapter = [p for p in presets if p.name not in ANSWERED_NAMES]
    beyond = [p for p in presets if p.name in ANSWERED_NAMES]
    for preset in chapter:
        blocks.append(("h2", f"{preset.title} ({preset.name})"))
        blocks += _preset_blocks(table, bests, preset, figures[preset.name])
        findings = [(f, a) for f, a in report.findings if f.preset == preset.name]
        if findings:
            blocks.append(("h3", "Findings"))
            blocks.append(("table", ["chapter", "claim", "measured here", "verdict", "test"],
                           [[f.where, f.claim, a.measured, a.shown, a.test] for f, a in findings]))
            blocks += [("p", f"Why {f.where} disagrees (\"{f.claim}\"): {a.reason}. Measured why: {WHY_PAGE}")
                       for f, a in findings if a.verdict == DISAGREES]
    if beyond:

        blocks += [("h2", "Beyond the chapter"), ("p", BEYOND_INTRODUCTION)]
        for preset in beyond:
            blocks.append(("h3", f"{preset.title} ({preset.name})"))
            if preset.name == MATCHES:
                from soccer_lab.app.experiment.matches import MATCHES_INTRODUCTION

                blocks.append(("p", MATCHES_INTRODUCTION))
            blocks += _preset_blocks(table, bests, preset, figures[preset.name])
            answers = [(q, a) for q, a in report.answers if q.preset == preset.name]
            blocks.append(("table", ["chapter", "question", "answer here", "measured here", "test"],
                           [[q.where, q.question, a.shown + (f": {a.reason}" if a.reason else ""), a.measured,
                             a.test] for q, a in answers]))
    skipped = [f for f, a in report.findings if a.verdict == NOT_RUN]
    if skipped:
        blocks.append(("h2", "Findings not assessed (their preset was not run)"))
        blocks.append(("table", ["preset", "chapter", "claim"], [[f.preset, f.where, f.claim] for f in skipped]))
    return blocks


def _verdict_summary(report: Report, counts: dict[str, int]) -> str:
    text = "Verdicts: " + (", ".join(f"{n} {v}" for v, n in counts.items() if n) or "none")
    if counts[AGREES]:
        text += (f". Of the {counts[AGREES]} agreements, {report.no_difference_agreements()} are 'no significant "
                 f"difference found' (absence of evidence; each states the smallest difference its test could detect)")
    if report.judged_smaller():
        text += f". {report.judged_smaller()} verdicts were judged at a smaller size than the chapter's"
    return text + "."


def _preset_blocks(table: StatisticsTable, bests: BestsTable, preset: Preset, figures: list[Figure]) -> list:
    """The preset's settings table (with its trials' bests, re-played, when known) and its figures."""
    replays = {int(row["replays"]) for row in bests.rows}
    rows = []
    for setting in table.settings(preset.name):
        trials = len(table.trials(preset.name, setting))
        row = [setting, str(trials), str(table.curves(preset.name, setting, "generation").shape[1]),
               str(int(table.evaluations(preset.name, setting)[-1])),
               f"{np.median(table.final(preset.name, setting, 'mean')):.3f}",
               f"{np.median(table.final(preset.name, setting, 'best')):.3f}",
               f"{np.median(table.best_so_far(preset.name, setting)):.3f}"]
        if replays:
            quality = bests.column(preset.name, setting, "replay_fitness")
            row.append(f"{np.median(quality):.3f}" if len(quality) else "-")
        rows.append(row + _outcomes(table.final(preset.name, setting, "mean")))
    quality = [f"its best re-played on {'/'.join(map(str, sorted(replays)))} fresh starts (median)"] if replays else []
    blocks: list = [("table", [preset.varied, "trials", "generations", "evaluations", "final average (median)",
                               "final best (median)", "run's best (median)", *quality,
                               f"trials where kicking never spread (final average >= {NEVER_KICKING})",
                               f"trials taken over by goal scorers (final average <= {SCORERS_SPREAD})"], rows)]
    return blocks + [("figure", f.path, f.caption) for f in figures]


def _outcomes(final_means: np.ndarray) -> list[str]:
    trials = len(final_means)
    return [f"{int(np.sum(final_means >= NEVER_KICKING))} of {trials}",
            f"{int(np.sum(final_means <= SCORERS_SPREAD))} of {trials}"]


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _markdown(blocks: list) -> str:
    lines = []
    for block in blocks:
        kind = block[0]
        if kind in ("h1", "h2", "h3"):
            lines += ["#" * int(kind[1]) + " " + block[1], ""]
        elif kind == "p":
            lines += [block[1], ""]
        elif kind == "table":
            header, rows = block[1], block[2]
            lines.append("| " + " | ".join(header) + " |")
            lines.append("|" + "---|" * len(header))
            lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
            lines.append("")
        elif kind == "figure":
            lines += [f"![{block[2]}]({block[1].as_posix()})", ""]
    return "\n".join(lines)


STYLE = ("body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
         "table{border-collapse:collapse;margin:1em 0;font-size:0.9em}td,th{border:1px solid #ccc;padding:4px 8px;"
         "vertical-align:top}th{background:#f3f3f3}figure{margin:1em 0}img{max-width:100%}"
         ".agrees{color:#1a7f37;font-weight:bold}.DISAGREES{color:#c62828;font-weight:bold}"
         ".inconclusive{color:#8a6d00}")


def _html(blocks: list, folder: Path) -> str:
    """Self-contained: the figures are inlined as base64 PNG."""
    parts = ["<!doctype html><html><head><meta charset='utf-8'><title>soccer-lab experiment report</title>",
             f"<style>{STYLE}</style></head><body>"]
    for block in blocks:
        kind = block[0]
        if kind in ("h1", "h2", "h3", "p"):
            parts.append(f"<{kind}>{html.escape(block[1])}</{kind}>")
        elif kind == "table":
            header, rows = block[1], block[2]
            parts.append("<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>")
            for row in rows:
                parts.append("<tr>" + "".join(f"<td class='{html.escape(c.split(' ')[0])}'>{html.escape(c)}</td>"
                                              for c in row) + "</tr>")
            parts.append("</table>")
        elif kind == "figure":
            data = base64.b64encode((folder / block[1]).read_bytes()).decode()
            parts.append(f"<figure><img alt='{html.escape(block[2])}' src='data:image/png;base64,{data}'>"
                         f"<figcaption>{html.escape(block[2])}</figcaption></figure>")
    parts.append("</body></html>")
    return "\n".join(parts)
