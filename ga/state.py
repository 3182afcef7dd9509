"""The full state of a run after a generation: what a checkpoint holds and a resume continues from."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from soccer_lab.ga.config import GAConfig

if TYPE_CHECKING:  # annotations only: the algorithm names above are read where numpy is not wanted (CLI help)
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.ga.hall_of_fame import HallOfFame
    from soccer_lab.ga.individual import Individual
    from soccer_lab.ga.statistics import GenerationStats

GA, RANDOM_SEARCH = "ga", "random-search"
ALGORITHMS = (GA, RANDOM_SEARCH)


@dataclass(frozen=True)
class RunState:
    algorithm: str  # GA or RANDOM_SEARCH
    config: GAConfig
    vocabulary: Vocabulary
    population: list[Individual]  # the last evaluated generation (empty before generation 0)
    rng_state: dict[str, Any]  # the run's Generator, after the last generation's draws
    history: list[GenerationStats]
    best: Individual | None  # best running mean seen so far (kept when a later mean is only equal)
    hall: HallOfFame | None = None  # co-evolution's opponents (ga/hall_of_fame.py); None: a fixed evaluation

    @property
    def evaluations(self) -> int:
        return self.history[-1].evaluations if self.history else 0

    @property
    def wall_time(self) -> float:
        return self.history[-1].wall_time if self.history else 0.0
