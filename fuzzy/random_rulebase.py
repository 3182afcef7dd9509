"""Random rules and rulebases over a vocabulary, every draw from a numpy Generator the caller passes.

For benchmarks, property tests and demos; the GA has its own gene-level operators in `ga`.
"""

from __future__ import annotations

import numpy as np

from soccer_lab.fuzzy.rule import CONNECTORS, Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

MAX_PREMISES = 4
NULL_PROBABILITY = 0.2  # chance that a consequent field is Null
NEGATION_PROBABILITY = 0.3


def _pick(rng: np.random.Generator, options: tuple[str, ...]) -> str:
    return options[int(rng.integers(len(options)))]


def random_rule(rng: np.random.Generator, vocabulary: Vocabulary, max_premises: int = MAX_PREMISES) -> Rule:
    n = int(rng.integers(1, max_premises + 1))
    premises = tuple(
        Premise(_pick(rng, vocabulary.object_names), _pick(rng, vocabulary.premise_terms),
                bool(rng.random() < NEGATION_PROBABILITY))
        for _ in range(n)
    )
    connectors = tuple(_pick(rng, CONNECTORS) for _ in range(n - 1))
    fields = {
        output: None if rng.random() < NULL_PROBABILITY else _pick(rng, vocabulary.output_variable(output).term_names)
        for output in vocabulary.output_names
    }
    return Rule(premises, connectors, Consequent(_pick(rng, vocabulary.action_names), **fields))


def random_rulebase(rng: np.random.Generator, vocabulary: Vocabulary, rules: int = 10,
                    max_premises: int = MAX_PREMISES) -> Rulebase:
    return Rulebase(tuple(random_rule(rng, vocabulary, max_premises) for _ in range(rules)))
