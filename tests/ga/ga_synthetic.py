"""A cheap deterministic stand-in for the soccer evaluator (ga never imports soccer).

"Goals" = rules that kick toward goal on a positive ball premise, plus 0 or 1 drawn from the game
seed: noisy like a game, but the same (rulebase, seed) always gives the same result.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from soccer_lab.fuzzy.rule import Rulebase

GOAL_CAP = 10


@dataclass(frozen=True)
class SyntheticResult:
    fitness: float
    goals: int


@dataclass(frozen=True)
class SyntheticEvaluator:
    delay: float = 0.0  # seconds per call, to give a test time to kill a run mid-way
    chunk_size: int | None = None  # rulebases per chunk of a generation (None: soccer_lab.ga.evaluation's default)

    def __call__(self, rulebases: list[Rulebase], seeds: list[int]) -> list[SyntheticResult]:
        time.sleep(self.delay)
        return [play(rulebase, seed) for rulebase, seed in zip(rulebases, seeds)]


def play(rulebase: Rulebase, seed: int) -> SyntheticResult:
    scoring_rules = sum(
        rule.consequent.action == "KICKTOWARDGOAL"
        and any(p.object == "BALL" and not p.negated for p in rule.premises)
        for rule in rulebase
    )
    goals = min(GOAL_CAP, scoring_rules + int(np.random.default_rng(seed).integers(0, 2)))
    return SyntheticResult(1 / (2 * goals) if goals else 1.0, goals)


@dataclass(frozen=True)
class RecordingEvaluator:
    """Remembers, in this process, every rulebase it was asked to play."""

    played: list

    def __call__(self, rulebases, seeds):
        self.played.extend(rulebases)
        return [play(rulebase, seed) for rulebase, seed in zip(rulebases, seeds)]
