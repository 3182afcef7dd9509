"""Single-allele mutation (the chapter, 4 and Table 2): each gene is hit with probability `rate`, at least one gene;
a hit changes one field of the gene to a different valid value. A gene never changes kind."""

from __future__ import annotations

import numpy as np

from soccer_lab.ga.genes import KIND, GeneSpace
from soccer_lab.ga.provenance import Mutation


def mutate(chromosome: np.ndarray, rate: float, space: GeneSpace, rng: np.random.Generator) -> Mutation:
    """The changes a mutation of `chromosome` makes (ga/provenance.py); `mutation.apply(chromosome, ())` is the
    mutated copy, and `chromosome` itself is left untouched."""
    hits = np.flatnonzero(rng.random(len(chromosome)) < rate)
    if hits.size == 0:
        hits = rng.integers(0, len(chromosome), size=1)
    changes = []
    for gene in hits.tolist():
        kind = chromosome[gene, KIND]
        column = int(rng.choice(space.mutable_columns[kind]))
        size = int(space.field_sizes[kind, column])
        old = int(chromosome[gene, column])
        # A non-zero shift modulo the field size: uniform over the other values.
        changes.append((gene, column, old, (old + int(rng.integers(1, size))) % size))
    return Mutation(tuple(changes))
