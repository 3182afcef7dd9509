"""A linguistic variable: a universe of discourse and its terms."""

from __future__ import annotations

from dataclasses import dataclass

from soccer_lab.fuzzy.term import Term


@dataclass(frozen=True)
class LinguisticVariable:
    name: str
    minimum: float
    maximum: float
    terms: tuple[Term, ...]
    unit: str = ""

    def __post_init__(self) -> None:
        if not self.minimum < self.maximum:
            raise ValueError(f"variable {self.name}: empty universe [{self.minimum}, {self.maximum}]")
        for term in self.terms:
            if term.a < self.minimum or term.d > self.maximum:
                raise ValueError(f"variable {self.name}: term {term.name} leaves the universe")

    @property
    def term_names(self) -> tuple[str, ...]:
        return tuple(t.name for t in self.terms)

    def term(self, name: str) -> Term:
        for t in self.terms:
            if t.name == name:
                return t
        raise KeyError(f"variable {self.name} has no term {name}")

    def index(self, name: str) -> int:
        return self.term_names.index(name)

    def clamp(self, x: float) -> float:
        return min(max(x, self.minimum), self.maximum)

    def fuzzify(self, x: float) -> dict[str, float]:
        x = self.clamp(x)
        return {t.name: t.membership(x) for t in self.terms}
