"""Chromosome <-> Rulebase.

Decoding reads left to right: premises accumulate until a consequent closes a rule. A rule with
no premises is skipped, trailing premises form no rule; the connector of the last premise before
a consequent is ignored. An empty Rulebase means the ruleset is invalid.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from soccer_lab.fuzzy.rule import Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.genes import (ACTION, CONNECTOR, CONSEQUENT, DIRECTION, GENE_DTYPE, GENE_WIDTH, IS, IS_NOT, KIND,
                                 OBJECT, POWER, PREMISE, QUALIFIER, TERM, GeneSpace)

# Encoding must write some connector on a rule's last premise; decoding ignores it.
UNUSED_CONNECTOR = 0


class ChromosomeCodec:
    def __init__(self, vocabulary: Vocabulary):
        self.vocabulary = vocabulary
        self.space = GeneSpace.from_vocabulary(vocabulary)
        # Genes repeat a lot across a population: share one Premise/Consequent object per code.
        self._premise = lru_cache(maxsize=None)(self._make_premise)
        self._consequent = lru_cache(maxsize=None)(self._make_consequent)

    def decode(self, chromosome: np.ndarray) -> Rulebase:
        rules, premises, connectors = [], [], []
        for gene in chromosome.tolist():
            if gene[KIND] == PREMISE:
                premises.append(self._premise(gene[OBJECT], gene[QUALIFIER], gene[TERM]))
                connectors.append(self.space.connectors[gene[CONNECTOR]])
            else:
                if premises:
                    rules.append(Rule(tuple(premises), tuple(connectors[:-1]),
                                      self._consequent(gene[ACTION], gene[DIRECTION], gene[POWER])))
                premises, connectors = [], []
        return Rulebase(tuple(rules))

    def encode(self, rulebase: Rulebase) -> np.ndarray:
        """The shortest chromosome that decodes to `rulebase` (ValueError for a name outside the vocabulary)."""
        s = self.space
        genes = []
        for rule in rulebase:
            connectors = [s.connectors.index(c) for c in rule.connectors] + [UNUSED_CONNECTOR]
            for premise, connector in zip(rule.premises, connectors):
                genes.append((PREMISE, s.objects.index(premise.object), IS_NOT if premise.negated else IS,
                              s.terms.index(premise.term), connector))
            c = rule.consequent
            genes.append((CONSEQUENT, s.actions.index(c.action),
                          s.null_direction if c.direction is None else s.directions.index(c.direction),
                          s.null_power if c.power is None else s.powers.index(c.power), 0))
        return np.array(genes, dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH)

    def _make_premise(self, obj: int, qualifier: int, term: int) -> Premise:
        return Premise(self.space.objects[obj], self.space.terms[term], negated=qualifier == IS_NOT)

    def _make_consequent(self, action: int, direction: int, power: int) -> Consequent:
        s = self.space
        return Consequent(s.actions[action],
                          s.directions[direction] if direction < len(s.directions) else None,
                          s.powers[power] if power < len(s.powers) else None)
