"""Which rules make a player play: rule usage over games of SimpleSoccer.

The games are one GameBatch (N games of the same rulebase, one seed each). After every step the
games that made a decision this tick (a finishing game's last step only closes its books) are read:
each rule's strength, the action performed and its parameters. Per rule that gives how often it
fired (strength above 0), how often it won (it fired and its action was performed, so it took part
in the decision: its strength and output set count in the action's support and mean of maximum),
how often it decided (it was the strongest rule of the performed action, the first among equals:
the rule the UI highlights), and its mean strength over the ticks it fired. Per action: the ticks
it was performed; and the ticks the player hunted (no rule fired).

With `record`, every decision is also kept (game, tick, action, parameters, and the player's and
ball's position the decision was made from), so two rulebases' games can be compared tick for tick.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import GameBatch, GameResult


@dataclass(frozen=True)
class RuleUsage:
    fired: int  # ticks its strength was above 0
    won: int  # ticks it fired and its action was performed
    decided: int  # ticks it was the performed action's strongest rule (the first among equals)
    mean_strength: float | None  # over the ticks it fired; None when it never fired


@dataclass(frozen=True)
class Usage:
    rulebase: Rulebase
    seeds: tuple[int, ...]
    ticks: int  # decisions made, over all games
    rules: tuple[RuleUsage, ...]  # in rulebase order
    actions: dict[str, int]  # ticks each action was performed, every action of the vocabulary
    hunt: int  # ticks no rule fired (the player hunted)
    results: tuple[GameResult, ...]  # per game, in seed order

    @property
    def hunt_share(self) -> float:
        return self.hunt / self.ticks if self.ticks else 0.0


@dataclass(frozen=True)
class Decisions:
    """Every decision of a batch's games: row k is game[k]'s decision at tick[k], in playing order."""

    game: np.ndarray  # int64[K]
    tick: np.ndarray  # int64[K], from 0
    action: np.ndarray  # int64[K], NO_ACTION = hunt
    values: np.ndarray  # float64[K, n_outputs]: the parameters the skill was given
    pose: np.ndarray  # float64[K, 5]: player x, y, facing, ball x, y the decision was made from

    def first_difference(self, other: "Decisions") -> tuple[int, int] | None:
        """(game, tick) of the first decision, in game then tick order, where the two differ bit for
        bit (a game lasting longer differs at its first extra tick); None when they are identical."""
        a, b = self._rows(), other._rows()
        common = min(len(a), len(b))
        same = (a[:common] == b[:common]).all(axis=1)
        if not same.all():
            k = int(np.argmin(same))
            return min((int(a[k, 0]), int(a[k, 1])), (int(b[k, 0]), int(b[k, 1])))
        if len(a) == len(b):
            return None
        longer = a if len(a) > common else b
        return int(longer[common, 0]), int(longer[common, 1])

    def _rows(self) -> np.ndarray:
        """One int64 row per decision, in game then tick order; floats by their bits."""
        order = np.lexsort((self.tick, self.game))
        columns = (self.game[:, None], self.tick[:, None], self.action[:, None], self.values.view(np.int64),
                   self.pose.view(np.int64))
        return np.hstack(columns)[order]


def measure_usage(rulebase: Rulebase, seeds: Sequence[int], config: GameConfig, vocabulary: Vocabulary,
                  record: bool = False) -> tuple[Usage, Decisions | None]:
    """Play one game per seed with `rulebase` (one batch) and count what its rules did."""
    if not len(rulebase):
        raise ValueError("a rulebase needs at least one rule to be played")
    batch = GameBatch([rulebase] * len(seeds), list(seeds), config, vocabulary)
    counter = _UsageCounter(rulebase, vocabulary)
    rows: list[tuple[np.ndarray, ...]] = []
    state, seen, decision = batch.state, batch.observation, batch.decision  # updated in place by step()
    while not batch.finished:
        before = state.ticks.copy()
        batch.step()
        games = np.flatnonzero(state.ticks > before)
        if not len(games):
            continue
        counter.add(decision.strengths[games, : len(rulebase)], decision.action[games])
        if record:
            pose = np.column_stack([seen.player_x, seen.player_y, seen.facing, seen.ball_x, seen.ball_y])
            rows.append((games, before[games], decision.action[games].copy(), decision.values[games].copy(),
                         pose[games]))
    counter.count()
    usage = counter.usage(rulebase, tuple(seeds), tuple(batch.results()))
    return usage, (_decisions(rows, vocabulary) if record else None)


class _UsageCounter:
    """Counts ticks in chunks: a few large numpy operations instead of several per tick."""

    CHUNK = 20_000  # decisions buffered before they are counted
    CHUNK_CELLS = 2_000_000  # at most this many (decision, rule) strengths buffered: 16 MB, whatever the rules

    def __init__(self, rulebase: Rulebase, vocabulary: Vocabulary):
        self.vocabulary = vocabulary
        self._strengths: list[np.ndarray] = []
        self._actions: list[np.ndarray] = []
        self._buffered = 0
        self.rule_action = np.array([vocabulary.action_names.index(r.consequent.action) for r in rulebase],
                                    dtype=np.int64)
        n = len(rulebase)
        self.fired = np.zeros(n, dtype=np.int64)
        self.won = np.zeros(n, dtype=np.int64)
        self.decided = np.zeros(n, dtype=np.int64)
        self.strength = np.zeros(n)
        self.performed = np.zeros(len(vocabulary.action_names), dtype=np.int64)
        self.hunt = 0
        self.ticks = 0

    def add(self, strengths: np.ndarray, actions: np.ndarray) -> None:
        """One tick of some games: strengths[g, r] of their rules, the action each performed."""
        self._strengths.append(strengths.copy())
        self._actions.append(actions.copy())
        self._buffered += len(actions)
        if self._buffered >= self.CHUNK or self._buffered * len(self.rule_action) >= self.CHUNK_CELLS:
            self.count()

    def count(self) -> None:
        """Count the buffered ticks."""
        if not self._actions:
            return
        strengths, actions = np.concatenate(self._strengths), np.concatenate(self._actions)
        self._strengths, self._actions, self._buffered = [], [], 0
        fired = strengths > 0.0
        of_performed = self.rule_action[None, :] == actions[:, None]
        self.fired += fired.sum(axis=0)
        self.won += (fired & of_performed).sum(axis=0)
        self.strength += strengths.sum(axis=0)  # a rule that did not fire adds 0
        acted = actions != NO_ACTION
        # argmax gives the first maximum: the rule that set the action's support first
        strongest = np.where(of_performed, strengths, -1.0).argmax(axis=1)
        np.add.at(self.decided, strongest[acted], 1)
        self.performed += np.bincount(actions[acted], minlength=len(self.performed))
        self.hunt += int((~acted).sum())
        self.ticks += len(actions)

    def usage(self, rulebase: Rulebase, seeds: tuple[int, ...], results: tuple[GameResult, ...]) -> Usage:
        rules = tuple(
            RuleUsage(int(f), int(w), int(d), float(s / f) if f else None)
            for f, w, d, s in zip(self.fired, self.won, self.decided, self.strength)
        )
        actions = {a: int(n) for a, n in zip(self.vocabulary.action_names, self.performed)}
        return Usage(rulebase, seeds, self.ticks, rules, actions, self.hunt, results)


def _decisions(rows: list[tuple[np.ndarray, ...]], vocabulary: Vocabulary) -> Decisions:
    if not rows:
        n_outputs = len(vocabulary.output_names)
        return Decisions(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64),
                         np.zeros((0, n_outputs)), np.zeros((0, 5)))
    return Decisions(*(np.concatenate(column) for column in zip(*rows)))
