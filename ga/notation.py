"""The chapter's compact chromosome notation (Figs. 6 and 7), both ways.

`(B,N,O) (B,nF,A) (G,N,A) (RB,n,L)`: a premise gene is (object, [n]term, connector), a
consequent gene is (action, direction|n, power|n). The first field tells the kind (objects and
actions have disjoint abbreviations); the position of a field tells which names it reads, so
`M` is MediumDistant in a premise and MediumPower in a consequent, and `n` prefixing a term
means not while `n` alone means Null. The abbreviations are the vocabulary's (its data file holds
them beside the names they abbreviate).
"""

from __future__ import annotations

import re

import numpy as np

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.genes import (ACTION, CONNECTOR, CONSEQUENT, DIRECTION, GENE_DTYPE, GENE_WIDTH, IS, IS_NOT, KIND,
                                 OBJECT, POWER, PREMISE, QUALIFIER, TERM, GeneSpace)

NOT = "n"  # prefixes a premise term
NULL = "n"  # an empty consequent field
FIELDS_PER_GENE = 3
NOT_NOTE = f", each optionally prefixed by {NOT} for not"
NULL_NOTE = f", or {NULL} for Null"

_GENE = re.compile(r"\s*\(([^()]*)\)\s*")


class NotationError(ValueError):
    pass


class CompactNotation:
    """Reads and writes chromosomes over a vocabulary's genes, with its abbreviations."""

    def __init__(self, vocabulary: Vocabulary):
        self.space = space = GeneSpace.from_vocabulary(vocabulary)
        self.abbreviations = vocabulary.abbreviations
        self.objects = self._reader("object", space.objects)
        self.terms = self._reader("term", space.terms)
        self.connectors = self._reader("connector", space.connectors)
        self.actions = self._reader("action", space.actions)
        self.directions = self._reader("direction", space.directions)
        self.powers = self._reader("power", space.powers)
        if set(self.objects) & set(self.actions):
            raise NotationError("object and action abbreviations must differ: the first field tells the kind")

    def _reader(self, field: str, names: tuple[str, ...]) -> dict[str, int]:
        missing = [n for n in names if n not in self.abbreviations]
        if missing:
            raise NotationError(f"no abbreviation for {field} {', '.join(missing)}")
        reader = {self.abbreviations[n]: i for i, n in enumerate(names)}
        if len(reader) != len(names):
            raise NotationError(f"two {field}s share an abbreviation")
        return reader

    # ---- writing --------------------------------------------------------------------------
    def format(self, chromosome: np.ndarray) -> str:
        return " ".join(self.format_gene(gene) for gene in chromosome.tolist())

    def format_gene(self, gene: list[int]) -> str:
        s, short = self.space, self.abbreviations
        if gene[KIND] == PREMISE:
            negation = NOT if gene[QUALIFIER] == IS_NOT else ""
            fields = (short[s.objects[gene[OBJECT]]], negation + short[s.terms[gene[TERM]]],
                      short[s.connectors[gene[CONNECTOR]]])
        else:
            fields = (short[s.actions[gene[ACTION]]], self._abbreviation_or_null(s.directions, gene[DIRECTION]),
                      self._abbreviation_or_null(s.powers, gene[POWER]))
        return "(" + ",".join(fields) + ")"

    def _abbreviation_or_null(self, names: tuple[str, ...], index: int) -> str:
        return self.abbreviations[names[index]] if index < len(names) else NULL

    # ---- reading --------------------------------------------------------------------------
    def parse(self, text: str) -> np.ndarray:
        genes, position = [], 0
        while position < len(text):
            match = _GENE.match(text, position)
            if match is None:
                if not text[position:].strip():
                    break
                found = text[position:].lstrip()[:12]
                column = len(text) - len(text[position:].lstrip()) + 1
                raise NotationError(f"column {column}: expected a gene like (B,N,O) or (RB,n,L), found {found!r}")
            try:
                genes.append(self.parse_gene(match.group(1)))
            except NotationError as exc:
                raise NotationError(f"gene {len(genes) + 1} ({match.group(1)}) at column "
                                    f"{match.start(1)}: {exc}") from None
            position = match.end()
        if not genes:
            raise NotationError("empty chromosome: expected genes like (B,N,O) (RB,n,L)")
        return np.array(genes, dtype=GENE_DTYPE)

    def parse_gene(self, inside: str) -> list[int]:
        fields = [f.strip() for f in inside.split(",")]
        if len(fields) != FIELDS_PER_GENE:
            raise NotationError(f"a gene has {FIELDS_PER_GENE} comma-separated fields, found {len(fields)}")
        first, second, third = fields
        gene = [0] * GENE_WIDTH
        if first in self.objects:
            negated = second.startswith(NOT) and second[len(NOT):] in self.terms
            term = second[len(NOT):] if negated else second
            gene[KIND], gene[OBJECT] = PREMISE, self.objects[first]
            gene[QUALIFIER] = IS_NOT if negated else IS
            gene[TERM] = _read(self.terms, term, "term", NOT_NOTE)
            gene[CONNECTOR] = _read(self.connectors, third, "connector")
        elif first in self.actions:
            gene[KIND], gene[ACTION] = CONSEQUENT, self.actions[first]
            gene[DIRECTION] = (self.space.null_direction if second == NULL
                               else _read(self.directions, second, "direction", NULL_NOTE))
            gene[POWER] = self.space.null_power if third == NULL else _read(self.powers, third, "power", NULL_NOTE)
        else:
            raise NotationError(f"unknown object or action {first!r} "
                                f"(expected one of {', '.join([*self.objects, *self.actions])})")
        return gene


def _read(reader: dict[str, int], word: str, what: str, note: str = "") -> int:
    if word not in reader:
        raise NotationError(f"unknown {what} {word!r} (expected one of {', '.join(reader)}{note})")
    return reader[word]


def parse_compact(text: str, vocabulary: Vocabulary) -> np.ndarray:
    """`parse_compact("(B,N,O) (RB,n,L)", vocabulary)` -> chromosome array; NotationError says what is wrong where."""
    return CompactNotation(vocabulary).parse(text)


def format_compact(chromosome: np.ndarray, vocabulary: Vocabulary) -> str:
    return CompactNotation(vocabulary).format(chromosome)
