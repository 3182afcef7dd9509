"""What a finished (or stopped) run hands back."""

from __future__ import annotations

from dataclasses import dataclass

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.statistics import GenerationStats

TARGET_REACHED, GENERATIONS_DONE, STOPPED = "target reached", "max generations", "stopped"


@dataclass(frozen=True)
class RunResult:
    config: GAConfig
    vocabulary: Vocabulary
    history: list[GenerationStats]
    population: list[Individual]  # the last evaluated generation
    # best running mean seen in the run: chromosome, fitness, evaluations, goals; None (and best_rulebase
    # None) only for a run stopped before its first generation finished
    best: Individual | None
    best_rulebase: Rulebase | None
    stop_reason: str  # TARGET_REACHED, GENERATIONS_DONE or STOPPED

    @property
    def evaluations(self) -> int:
        return self.history[-1].evaluations if self.history else 0
