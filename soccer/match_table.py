"""A match series' outcome as people read it (`soccer-lab match`, `soccer_lab.match`): each player's wins, draws,
losses and goals, and every match half by half. No numba here: the API's types import without the engine."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any


@dataclass(frozen=True)
class Record:
    """One player's line of the table: matches won, drawn and lost, goals scored and conceded."""

    wins: int = 0
    draws: int = 0
    losses: int = 0
    goals_for: int = 0
    goals_against: int = 0

    def after(self, scored: int, conceded: int) -> "Record":
        won, lost = scored > conceded, scored < conceded
        return Record(self.wins + won, self.draws + (not won and not lost), self.losses + lost,
                      self.goals_for + scored, self.goals_against + conceded)


@dataclass(frozen=True)
class Half:
    """One half of a match: which player played on the left ("A" or "B"), each side's goals and kicks
    (left, right), ticks played and why it ended ("max-ticks", "goal-cap" or "idle")."""

    left: str
    goals: tuple[int, int]
    kicks: tuple[int, int]
    ticks: int
    end_reason: str


@dataclass(frozen=True)
class Match:
    """One match: its start's seed, the goals of A and B over both halves, the winner ("A", "B" or
    "draw") and its two halves (A on the left in the first)."""

    seed: int
    goals: tuple[int, int]
    winner: str
    halves: tuple[Half, Half]


@dataclass(frozen=True)
class Matches:
    """The table (each player's Record) and every match, in seed order."""

    a: Record
    b: Record
    matches: list[Match] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form `soccer-lab match --json` prints."""
        return asdict(self)


def table_of(results: list) -> Matches:
    """The table and matches of MatchResults (soccer/match.py, A against B)."""
    record_a, record_b, played = Record(), Record(), []
    for result in results:
        goals_a, goals_b = result.goals
        record_a, record_b = record_a.after(goals_a, goals_b), record_b.after(goals_b, goals_a)
        halves = tuple(Half(left, h.goals, h.kicks, h.ticks, h.end_reason) for left, h in zip("AB", result.halves))
        played.append(Match(result.seed, result.goals, result.winner, halves))
    return Matches(record_a, record_b, played)
