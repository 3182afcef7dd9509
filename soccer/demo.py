"""The built-in demo rulebase (soccer/data/demo.rules): the player the app shows first."""

from __future__ import annotations

from pathlib import Path

from fuzzy.parser import parse_rulebase
from fuzzy.rule import Rulebase
from fuzzy.vocabulary import Vocabulary
from soccer.config import SOCCER_VOCABULARY

DEMO_RULES_FILE = Path(__file__).parent / "data" / "demo.rules"


def demo_rules_text() -> str:
    return DEMO_RULES_FILE.read_text()


def demo_rulebase(vocabulary: Vocabulary = SOCCER_VOCABULARY) -> Rulebase:
    return parse_rulebase(demo_rules_text(), vocabulary)
