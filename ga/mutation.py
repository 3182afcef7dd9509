"""Single-allele mutation (the chapter, 4 and Table 2): each gene is hit with probability `rate`, at least one gene;
a hit changes one field of the gene to a different valid value. A gene never changes kind."""

from __future__ import annotations

import numpy as np

from ga.genes import KIND, GeneSpace


def mutate(chromosome: np.ndarray, rate: float, space: GeneSpace, rng: np.random.Generator) -> np.ndarray:
    """A mutated copy; `chromosome` itself is left untouched."""
    mutant = chromosome.copy()
    hits = np.flatnonzero(rng.random(len(mutant)) < rate)
    if hits.size == 0:
        hits = rng.integers(0, len(mutant), size=1)
    for gene in hits:
        kind = mutant[gene, KIND]
        column = rng.choice(space.mutable_columns[kind])
        size = space.field_sizes[kind, column]
        # A non-zero shift modulo the field size: uniform over the other values.
        mutant[gene, column] = (mutant[gene, column] + rng.integers(1, size)) % size
    return mutant
