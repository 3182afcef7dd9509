"""The built-in demo rulebase (soccer/data/examples/demo.rules): the player the app shows first."""

from __future__ import annotations

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from soccer_lab.soccer.examples import DEMO, example


def demo_rules_text() -> str:
    return example(DEMO).text


def demo_rulebase(vocabulary: Vocabulary = SOCCER_VOCABULARY) -> Rulebase:
    return example(DEMO).rulebase(vocabulary)
