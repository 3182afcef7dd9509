"""One member of the population: a chromosome and the running mean of its evaluations."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from soccer_lab.ga.genes import GENE_DTYPE, GENE_WIDTH
from soccer_lab.ga.provenance import Birth


@dataclass(frozen=True, eq=False)
class Individual:
    """Fitness is noisy (every game starts from a fresh random position), so an individual that
    survives unchanged into the next generation is evaluated again and averages its evaluations
    (docs/research/index.md, "The model": noisy fitness). `goals` is the goal count of its latest evaluation;
    `first_seed` the game seed of its first one (a game depends only on rulebase and seed, so that game can be
    replayed exactly). `birth`: how it entered its generation (ga/provenance.py; None where it was not recorded:
    made outside a run, or read from a checkpoint older than provenance); an individual passed on unchanged
    enters the next one `born` anew."""

    chromosome: np.ndarray
    evaluations: int = 0
    fitness_sum: float = 0.0
    goals: int = 0
    first_seed: int | None = None
    birth: Birth | None = None

    def __post_init__(self) -> None:
        self.chromosome.flags.writeable = False  # shared between generations: never edited in place

    @property
    def fitness(self) -> float:
        """Mean fitness over its evaluations (lower is better); infinity before the first one."""
        return self.fitness_sum / self.evaluations if self.evaluations else math.inf

    def evaluated(self, fitness: float, goals: int, seed: int | None = None) -> "Individual":
        first_seed = self.first_seed if self.first_seed is not None else seed
        return Individual(self.chromosome, self.evaluations + 1, self.fitness_sum + fitness, goals, first_seed,
                          self.birth)

    def born(self, birth: Birth | None) -> "Individual":
        """The same individual (chromosome, running mean, first game) entering a generation by `birth`."""
        return Individual(self.chromosome, self.evaluations, self.fitness_sum, self.goals, self.first_seed, birth)

    def to_dict(self) -> dict[str, Any]:
        return {"chromosome": self.chromosome.tolist(), "evaluations": self.evaluations,
                "fitness_sum": self.fitness_sum, "goals": self.goals, "first_seed": self.first_seed,
                "birth": None if self.birth is None else self.birth.to_dict()}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "Individual":
        chromosome = np.array(data["chromosome"], dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH)
        first_seed = data.get("first_seed")
        birth = data.get("birth")
        return cls(chromosome, int(data["evaluations"]), float(data["fitness_sum"]), int(data["goals"]),
                   None if first_seed is None else int(first_seed), None if birth is None else Birth.from_dict(birth))
