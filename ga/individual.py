"""One member of the population: a chromosome and the running mean of its evaluations."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ga.genes import GENE_DTYPE, GENE_WIDTH


@dataclass(frozen=True, eq=False)
class Individual:
    """Fitness is noisy (every game starts from a fresh random position), so an individual that
    survives unchanged into the next generation is evaluated again and averages its evaluations
    (docs/research/index.md, "The model": noisy fitness). `goals` is the goal count of its latest evaluation;
    `first_seed` the game seed of its first one (a game depends only on rulebase and seed, so that game can be replayed exactly)."""

    chromosome: np.ndarray
    evaluations: int = 0
    fitness_sum: float = 0.0
    goals: int = 0
    first_seed: int | None = None

    def __post_init__(self) -> None:
        self.chromosome.flags.writeable = False  # shared between generations: never edited in place

    @property
    def fitness(self) -> float:
        """Mean fitness over its evaluations (lower is better); infinity before the first one."""
        return self.fitness_sum / self.evaluations if self.evaluations else math.inf

    def evaluated(self, fitness: float, goals: int, seed: int | None = None) -> "Individual":
        first_seed = self.first_seed if self.first_seed is not None else seed
        return Individual(self.chromosome, self.evaluations + 1, self.fitness_sum + fitness, goals, first_seed)

    def to_dict(self) -> dict[str, Any]:
        return {"chromosome": self.chromosome.tolist(), "evaluations": self.evaluations,
                "fitness_sum": self.fitness_sum, "goals": self.goals, "first_seed": self.first_seed}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Individual":
        chromosome = np.array(data["chromosome"], dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH)
        first_seed = data.get("first_seed")
        return cls(chromosome, int(data["evaluations"]), float(data["fitness_sum"]), int(data["goals"]),
                   None if first_seed is None else int(first_seed))
