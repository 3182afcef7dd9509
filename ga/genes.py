"""Int-coded messy genes (the chapter, section 4, Figs. 6 and 7).

A chromosome is an (n, GENE_WIDTH) int8 numpy array, one row per gene: column KIND says
premise or consequent, the other columns hold field indices into a GeneSpace. Integer rows
keep the operators vectorised and the whole population cheap to copy, count and store.

premise row:     (PREMISE,    object, qualifier, term, connector)
consequent row:  (CONSEQUENT, action, direction, power, 0)
A consequent's Null direction (power) is the index one past the last direction (power).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from soccer_lab.fuzzy import rule
from soccer_lab.fuzzy.rule import CONNECTORS
from soccer_lab.fuzzy.vocabulary import Vocabulary

GENE_WIDTH = 5
GENE_DTYPE = np.int8
KIND = 0
PREMISE, CONSEQUENT = 0, 1
OBJECT, QUALIFIER, TERM, CONNECTOR = 1, 2, 3, 4  # premise columns
ACTION, DIRECTION, POWER = 1, 2, 3  # consequent columns
IS, IS_NOT = 0, 1
QUALIFIERS = ("IS", "IS NOT")
MIN_LENGTH = 2  # one premise and one consequent: the smallest valid ruleset
# What each column of a gene holds, by kind (for people: mutation reports, the lineage and breeding views).
FIELD_NAMES = {PREMISE: ("kind", "object", "qualifier", "term", "connector"),
               CONSEQUENT: ("kind", "action", "direction", "power", "unused")}


@dataclass(frozen=True)
class GeneSpace:
    """The values every gene field can take, from a vocabulary, in the vocabulary's order."""

    objects: tuple[str, ...]
    terms: tuple[str, ...]  # premise terms: distance terms, then direction terms
    actions: tuple[str, ...]
    directions: tuple[str, ...]
    powers: tuple[str, ...]
    connectors: tuple[str, ...] = CONNECTORS

    @classmethod
    def from_vocabulary(cls, vocabulary: Vocabulary) -> "GeneSpace":
        return cls(
            objects=vocabulary.object_names,
            terms=vocabulary.premise_terms,
            actions=vocabulary.action_names,
            directions=vocabulary.output_variable(rule.DIRECTION).term_names,
            powers=vocabulary.output_variable(rule.POWER).term_names,
        )

    @property
    def null_direction(self) -> int:
        return len(self.directions)

    @property
    def null_power(self) -> int:
        return len(self.powers)

    @cached_property
    def field_sizes(self) -> np.ndarray:
        """field_sizes[kind, column]: how many values the column takes (column KIND: the two kinds)."""
        sizes = np.ones((2, GENE_WIDTH), dtype=np.int64)
        sizes[:, KIND] = 2
        sizes[PREMISE, [OBJECT, QUALIFIER, TERM, CONNECTOR]] = (
            len(self.objects), len(QUALIFIERS), len(self.terms), len(self.connectors))
        sizes[CONSEQUENT, [ACTION, DIRECTION, POWER]] = (
            len(self.actions), len(self.directions) + 1, len(self.powers) + 1)
        return sizes

    @cached_property
    def mutable_columns(self) -> tuple[np.ndarray, np.ndarray]:
        """Per kind, the field columns a single-allele mutation can change (those with 2+ values)."""
        return tuple(
            np.array([c for c in range(KIND + 1, GENE_WIDTH) if self.field_sizes[kind, c] > 1])
            for kind in (PREMISE, CONSEQUENT)
        )

    def value_name(self, kind: int, column: int, value: int) -> str:
        """The name a gene field's value stands for, e.g. (PREMISE, TERM, 1) -> "VERYNEAR"; "NULL" for a
        consequent's Null direction or power."""
        values = {
            PREMISE: {OBJECT: self.objects, QUALIFIER: QUALIFIERS, TERM: self.terms, CONNECTOR: self.connectors},
            CONSEQUENT: {ACTION: self.actions, DIRECTION: self.directions, POWER: self.powers},
        }[kind][column]
        return values[value] if value < len(values) else "NULL"

    def check(self, chromosome: np.ndarray) -> None:
        """Raise ValueError unless every gene of the chromosome is in range."""
        if chromosome.ndim != 2 or chromosome.shape[1] != GENE_WIDTH:
            raise ValueError(f"a chromosome is an (n, {GENE_WIDTH}) array, got shape {chromosome.shape}")
        kinds = chromosome[:, KIND]
        if np.any((kinds != PREMISE) & (kinds != CONSEQUENT)):
            raise ValueError("gene kind out of range")
        limits = self.field_sizes[kinds.astype(np.int64)]
        if np.any(chromosome < 0) or np.any(chromosome >= limits):
            raise ValueError("gene field out of range")


def composition(chromosome: np.ndarray) -> tuple[int, int, int]:
    """(premises, rules, valid rules). A consequent closes a valid rule exactly when the gene
    before it is a premise, since premises accumulate until the next consequent."""
    kinds = chromosome[:, KIND]
    consequents = kinds == CONSEQUENT
    valid = consequents[1:] & (kinds[:-1] == PREMISE)
    return int(len(kinds) - consequents.sum()), int(consequents.sum()), int(valid.sum())
