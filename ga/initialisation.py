"""Random chromosomes (the chapter, 4 and Table 2): length uniform in [MIN_LENGTH, max_length], each gene a consequent
with probability `consequent_probability`, every field uniform over its values."""

from __future__ import annotations

import numpy as np

from soccer_lab.ga.genes import CONSEQUENT, GENE_DTYPE, GENE_WIDTH, KIND, MIN_LENGTH, PREMISE, GeneSpace


def random_chromosome(space: GeneSpace, max_length: int, consequent_probability: float,
                      rng: np.random.Generator) -> np.ndarray:
    length = int(rng.integers(MIN_LENGTH, max_length + 1))
    kinds = np.where(rng.random(length) < consequent_probability, CONSEQUENT, PREMISE)
    sizes = space.field_sizes[kinds]  # (length, GENE_WIDTH): each gene's field sizes for its kind
    chromosome = rng.integers(0, sizes).astype(GENE_DTYPE)
    chromosome[:, KIND] = kinds
    return chromosome.reshape(length, GENE_WIDTH)


def random_population(space: GeneSpace, size: int, max_length: int, consequent_probability: float,
                      rng: np.random.Generator) -> list[np.ndarray]:
    return [random_chromosome(space, max_length, consequent_probability, rng) for _ in range(size)]
