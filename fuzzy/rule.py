"""Rules and rulebases: what the GA evolves, the parser reads and the engines evaluate."""

from __future__ import annotations

from dataclasses import dataclass

AND, OR = "AND", "OR"
CONNECTORS = (AND, OR)
# A consequent's parameter fields; a vocabulary's outputs are exactly these (fuzzy/vocabulary.py checks it).
DIRECTION, POWER = "direction", "power"
PARAMETERS = (DIRECTION, POWER)


@dataclass(frozen=True)
class Premise:
    """`OBJECT is [not] TERM`, e.g. Premise("BALL", "NEAR", negated=True) = Ball is not Near."""

    object: str
    term: str
    negated: bool = False


@dataclass(frozen=True)
class Consequent:
    """(Action, Direction|None, Power|None): one term (or None) per name in PARAMETERS. A field the
    action does not use is kept but ignored."""

    action: str
    direction: str | None = None
    power: str | None = None


@dataclass(frozen=True)
class Rule:
    """Premises combined strictly left to right: connectors[i] joins the running degree of
    premises[0..i] with premises[i+1]. So len(connectors) == len(premises) - 1."""

    premises: tuple[Premise, ...]
    connectors: tuple[str, ...]
    consequent: Consequent

    def __post_init__(self) -> None:
        if not self.premises:
            raise ValueError("a rule needs at least one premise")
        if len(self.connectors) != len(self.premises) - 1:
            raise ValueError("a rule needs exactly one connector between consecutive premises")
        for c in self.connectors:
            if c not in CONNECTORS:
                raise ValueError(f"unknown connector {c!r}")


@dataclass(frozen=True)
class Rulebase:
    """An ordered tuple of rules (order matters: it breaks ties between actions)."""

    rules: tuple[Rule, ...]

    def __len__(self) -> int:
        return len(self.rules)

    def __iter__(self):
        return iter(self.rules)
