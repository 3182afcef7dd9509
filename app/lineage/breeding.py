"""One breeding, step by step, for teaching: two parents' chromosomes, the crossover's cut points (the GA's
own operators, ga/crossover.py), the two children, and optionally a mutation of each child gene by gene
(ga/mutation.py). Seeded: the same parents, operator and seed give the same children, so a class can
repeat it. The UI's Breeding tab and POST /api/breed show it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from soccer_lab.app.lineage.family_tree import describe_change
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.crossover import CROSSOVERS
from soccer_lab.ga.genes import MIN_LENGTH
from soccer_lab.ga.mutation import mutate
from soccer_lab.ga.notation import CompactNotation
from soccer_lab.ga.provenance import Mutation, Splice

DEFAULT_MUTATION_RATE = GAConfig().mutation_rate  # the chapter's Table 2


class BreedingError(ValueError):
    """Parents that cannot be bred (too short) or a crossover that does not exist."""


@dataclass(frozen=True)
class Parent:
    name: str
    chromosome: np.ndarray


@dataclass(frozen=True)
class Child:
    splice: Splice  # how the crossover made it from the two parents
    crossed: np.ndarray  # its chromosome after the crossover
    mutation: Mutation | None  # the mutation that followed, if any
    chromosome: np.ndarray  # its final chromosome


@dataclass(frozen=True)
class Breeding:
    parents: tuple[Parent, Parent]
    crossover: str
    seed: int
    children: tuple[Child, Child]


def breed(a: Parent, b: Parent, crossover: str, seed: int, vocabulary: Vocabulary, *,
          mutation_rate: float | None = None, max_length: int = GAConfig().max_length) -> Breeding:
    """Cross `a` and `b` with `crossover` ("one-point" or "two-point"), from `seed`; with a `mutation_rate`,
    then mutate each child (every gene hit with that chance, at least one), as the GA mutates."""
    if crossover not in CROSSOVERS:
        raise BreedingError(f"crossover: expected {' or '.join(CROSSOVERS)}, not {crossover!r}")
    for parent in (a, b):
        if len(parent.chromosome) < MIN_LENGTH:
            raise BreedingError(f"{parent.name} has {len(parent.chromosome)} gene; a parent needs at least {MIN_LENGTH}")
    rng = np.random.default_rng(seed)
    space = ChromosomeCodec(vocabulary).space
    pair = (a.chromosome, b.chromosome)
    children = []
    for splice in CROSSOVERS[crossover](*pair, max_length, rng):
        crossed = splice.apply(pair[0], pair)
        mutation = mutate(crossed, mutation_rate, space, rng) if mutation_rate else None
        children.append(Child(splice, crossed, mutation, mutation.apply(crossed, ()) if mutation else crossed))
    return Breeding((a, b), crossover, seed, (children[0], children[1]))


@dataclass(frozen=True)
class GeneCell:
    """A gene as the breeding view shows it: compact notation, the parent it came from (0 or 1), and
    what a mutation changed in it."""

    compact: str
    parent: int
    mutated: str | None = None


class BreedingDescription:
    """The breeding in the words and notation the views show."""

    def __init__(self, breeding: Breeding, vocabulary: Vocabulary):
        self.breeding = breeding
        self.vocabulary = vocabulary
        self.notation = CompactNotation(vocabulary)
        self.codec = ChromosomeCodec(vocabulary)

    def parent_genes(self, slot: int) -> list[str]:
        return [self.notation.format_gene(row) for row in self.breeding.parents[slot].chromosome.tolist()]

    def cuts(self, slot: int) -> tuple[int, ...]:
        """Where the crossover cut parent `slot` (after these genes)."""
        return self.breeding.children[0].splice.cuts[slot]

    def child_genes(self, child: int, *, mutated: bool) -> list[GeneCell]:
        """A child's genes after the crossover (`mutated` False) or after its mutation too."""
        made = self.breeding.children[child]
        chromosome = made.chromosome if mutated else made.crossed
        sources = [slot for slot, start, stop in made.splice.segments for _ in range(start, stop)]
        changes: dict[int, list[str]] = {}
        if mutated and made.mutation is not None:
            for gene, column, old, new in made.mutation.changes:
                changes.setdefault(gene, []).append(describe_change(made.crossed, gene, (column, old, new),
                                                                    self.vocabulary))
        return [GeneCell(self.notation.format_gene(row), sources[gene], "; ".join(changes[gene]) if gene in changes
                         else None) for gene, row in enumerate(chromosome.tolist())]

    def segments(self, child: int) -> list[tuple[int, int, int]]:
        """(parent, first gene, last gene), 1-based, of each stretch a child took from its parents."""
        return [(slot, start + 1, stop) for slot, start, stop in self.breeding.children[child].splice.segments]

    def rulebase(self, chromosome: np.ndarray) -> Rulebase:
        return self.codec.decode(chromosome)

    def rules(self, chromosome: np.ndarray) -> list[str]:
        return [format_rule(rule, self.vocabulary) for rule in self.codec.decode(chromosome)]

    def changes(self, child: int) -> list[str]:
        """What the mutation changed in a child, gene by gene, in words and compact notation."""
        made = self.breeding.children[child]
        if made.mutation is None:
            return []
        return [f"{describe_change(made.crossed, gene, (column, old, new), self.vocabulary)}: "
                f"{self.notation.format_gene(made.crossed[gene].tolist())} → "
                f"{self.notation.format_gene(made.chromosome[gene].tolist())}"
                for gene, column, old, new in made.mutation.changes]
