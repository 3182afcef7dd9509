"""Verdicts and the statistics they are judged by, shared by the chapter's findings (report.py) and the
questions past the chapter (beyond.py): what a verdict is (`Assessment`), per-trial values, the tests
between settings, the smallest difference a test could have detected, and how a run's size compares with
the chapter's."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from soccer_lab.app.experiment.presets import Preset
from soccer_lab.app.experiment.table import StatisticsTable

ALPHA = 0.05
POWER = 0.8  # for the smallest difference a "no difference" test could have detected
RANK_EFFICIENCY = 3 / np.pi  # rank tests' efficiency against the t test on normal data: their trials count 0.955x
MIN_TRIALS = 5  # our minimum: the fewest per setting at which the rank tests used can reach p < ALPHA
VALUE_DECIMALS = 10  # per-trial values are compared at this precision (see _settled)
AGREES, DISAGREES, INCONCLUSIVE, NOT_RUN = "agrees", "disagrees", "inconclusive", "not run"
TOO_SMALL = "too small to judge"
VERDICTS = (AGREES, DISAGREES, INCONCLUSIVE, TOO_SMALL, NOT_RUN)


@dataclass(frozen=True)
class Assessment:
    measured: str
    verdict: str
    test: str
    needs: str = ""  # for TOO_SMALL: the size the finding needs, against this run's
    reason: str = ""  # for DISAGREES: what this run's data show instead, in words
    no_difference_found: bool = False  # an agreement that is the absence of a significant difference
    smaller: str = ""  # judged at a smaller size than the chapter's: in which dimensions

    @property
    def shown(self) -> str:
        """The verdict as the report prints it, with the smaller size it was judged at."""
        if self.verdict == TOO_SMALL:
            return f"{TOO_SMALL} (needs {self.needs})"
        shown = self.verdict.upper() if self.verdict == DISAGREES else self.verdict
        return f"{shown} (at a smaller size than the chapter's: {self.smaller})" if self.smaller else shown


# ---- per-trial values ------------------------------------------------------------------------------
def _settled(values: np.ndarray) -> np.ndarray:
    """Running means of equal fitnesses can differ in the last bits (0.05 vs 0.05000000000000001); rank tests
    would read those as differences, so per-trial values are compared at VALUE_DECIMALS decimals."""
    return np.round(np.asarray(values, dtype=float), VALUE_DECIMALS)


def _final(column: str):
    return lambda table, preset, setting: _settled(table.final(preset.name, setting, column))


def _best_so_far(table: StatisticsTable, preset: Preset, setting: str) -> np.ndarray:
    return _settled(table.best_so_far(preset.name, setting))


def _groups(table: StatisticsTable, preset: Preset, values) -> dict[str, np.ndarray]:
    return {setting: values(table, preset, setting) for setting in table.settings(preset.name)}


def _medians(groups: dict[str, np.ndarray]) -> str:
    return "; ".join(f"{setting}: {np.median(v):.3f}" for setting, v in groups.items()) + " (median over trials)"


def _p_between(groups: dict[str, np.ndarray], alternative: str = "two-sided") -> tuple[float, str]:
    samples = list(groups.values())
    name = "Mann-Whitney U" if len(samples) == 2 else "Kruskal-Wallis H"
    pooled = np.concatenate(samples)
    if np.all(pooled == pooled[0]):  # every value identical: no difference at all (the tests are undefined)
        return 1.0, name
    if len(samples) == 2:
        return float(stats.mannwhitneyu(*samples, alternative=alternative).pvalue), name
    return float(stats.kruskal(*samples).pvalue), name


def detectable_difference(groups: dict[str, np.ndarray]) -> tuple[float, float, int]:
    """The smallest difference between two settings' means that the test could have detected with
    probability POWER at ALPHA (two-sided) with these trials: the two-sample normal approximation, the
    trials counted at the rank test's efficiency. (difference in the measure's units, in pooled
    within-setting standard deviations, trials per setting)."""
    trials = min(len(v) for v in groups.values())
    z = stats.norm.ppf(1 - ALPHA / 2) + stats.norm.ppf(POWER)
    in_deviations = float(z * np.sqrt(2 / (trials * RANK_EFFICIENCY)))
    pooled = float(np.sqrt(np.mean([np.var(v, ddof=1) for v in groups.values()]))) if trials > 1 else float("nan")
    return in_deviations * pooled, in_deviations, trials


def _detectable_text(name: str, groups: dict[str, np.ndarray]) -> str:
    difference, in_deviations, trials = detectable_difference(groups)
    return (f"with {trials} trials per setting it could have detected a difference of about {difference:.3f} in "
            f"{name} between two settings ({in_deviations:.2f} standard deviations; alpha {ALPHA}, power {POWER})")


def _chapter_trials(table: StatisticsTable, preset: Preset) -> int:
    return min((len(table.trials(preset.name, s)) for s in table.settings(preset.name)), default=0)


def too_small(table: StatisticsTable, preset: Preset) -> str:
    """What the run lacks to judge the preset's findings ("" when nothing): our minimum of MIN_TRIALS
    trials per setting, and the chapter's population, generations and game length."""
    trials = _chapter_trials(table, preset)
    lacking = [f"{MIN_TRIALS} trials per setting, our minimum (here {trials})"] if trials < MIN_TRIALS else []
    return ", ".join(lacking + preset.size.shortfalls(preset.chapter_size))


def smaller_than_chapter(table: StatisticsTable, preset: Preset) -> str:
    """Every dimension in which the run is smaller than the chapter's ("" when none): trials per
    setting (the chapter's 20 for its initial trials, 10 otherwise), population, generations, game length."""
    trials = _chapter_trials(table, preset)
    fewer = ([f"{trials} trials per setting (the chapter's {preset.chapter_trials})"]
             if trials < preset.chapter_trials else [])
    return ", ".join(fewer + preset.size.shortfalls(preset.chapter_size))
