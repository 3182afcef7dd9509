"""Per-generation statistics (the quantities of the chapter's Figs. 8-31): they drive the live plots, the rerun log, the store and the figures."""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np

from soccer_lab.ga.diversity import gene_codes, genotypic_diversity
from soccer_lab.ga.genes import CONSEQUENT, KIND, PREMISE, composition
from soccer_lab.ga.individual import Individual

GOAL_BINS = 5  # shares of 0, 1, .., GOAL_BINS - 1 goals, then one share for more
NOT_MEASURED = 0  # distinct_behaviours when the run plays no behaviour seeds (a population always plays one way)


@dataclass(frozen=True)
class GenerationStats:
    generation: int
    best: float  # fitness = each individual's running mean; lower is better
    mean: float
    worst: float
    std: float
    goals_0: float  # share of the population scoring 0 goals in this generation's evaluation
    goals_1: float
    goals_2: float
    goals_3: float
    goals_4: float
    goals_more: float
    genes_mean: float
    genes_std: float
    premises_mean: float
    premises_std: float
    rules_mean: float  # consequent genes
    rules_std: float
    valid_rules_mean: float  # consequents with at least one premise
    valid_rules_std: float
    unique_premise_genes: int
    unique_consequent_genes: int
    unique_genes: int
    distinct_chromosomes: int  # diversity (ga/diversity.py): different gene sequences
    distinct_rules: int  # different rules in the population's rule sets
    rule_set_distance: float  # mean Jaccard distance between two individuals' rule sets
    distinct_behaviours: int  # distinct outcomes on the run's behaviour seeds; NOT_MEASURED without them
    evaluations: int  # so far in the run
    wall_time: float  # seconds since the run started: the one non-deterministic figure

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "GenerationStats":
        """Statistics as saved; those of runs from before a statistic existed read it as ADDED_LATER says."""
        return cls(**{f.name: data[f.name] if f.name in data or f.name not in ADDED_LATER else ADDED_LATER[f.name]
                      for f in fields(cls)})

    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))


# Statistics that checkpoints and statistics.csv files of older runs lack, with the value they read as.
ADDED_LATER: dict[str, Any] = {"distinct_chromosomes": 0, "distinct_rules": 0, "rule_set_distance": 0.0,
                               "distinct_behaviours": NOT_MEASURED}


def generation_stats(generation: int, population: list[Individual], evaluations: int, wall_time: float,
                     behaviours: int = NOT_MEASURED) -> GenerationStats:
    fitness = np.array([ind.fitness for ind in population])
    goals = np.minimum([ind.goals for ind in population], GOAL_BINS)
    goal_shares = np.bincount(goals, minlength=GOAL_BINS + 1) / len(population)
    counts = np.array([(len(ind.chromosome), *composition(ind.chromosome)) for ind in population], dtype=float)
    genes, premises, rules, valid_rules = counts.T
    pool = np.concatenate([ind.chromosome for ind in population])
    codes = gene_codes(pool)
    unique_premises = len(np.unique(codes[pool[:, KIND] == PREMISE]))
    unique_consequents = len(np.unique(codes[pool[:, KIND] == CONSEQUENT]))
    return GenerationStats(
        generation, float(fitness.min()), float(fitness.mean()), float(fitness.max()), float(fitness.std()),
        *map(float, goal_shares),
        float(genes.mean()), float(genes.std()), float(premises.mean()), float(premises.std()),
        float(rules.mean()), float(rules.std()), float(valid_rules.mean()), float(valid_rules.std()),
        unique_premises, unique_consequents, unique_premises + unique_consequents,
        *genotypic_diversity([ind.chromosome for ind in population]), behaviours,
        evaluations, wall_time,
    )
