"""The GA's evaluator: rulebases in, one GameResult each out."""

from __future__ import annotations

from dataclasses import dataclass
from statistics import fmean
from typing import Sequence

import numpy as np

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.engine import GameResult, play_games

# Games per chunk of a generation: a batch of this many games plays in well under a second at the default
# max_ticks and holds a few MB, so a stop is obeyed quickly and memory is bounded (benchmarks/stop_latency.py)
CHUNK_GAMES = 100


def game_seeds(seed: int, games: int) -> list[int]:
    """The seeds of an evaluation's games: the seed itself for one game, else derived from it."""
    if games == 1:
        return [seed]
    return [int(s) for s in np.random.SeedSequence(seed & ((1 << 128) - 1)).generate_state(games, np.uint64)]


@dataclass(frozen=True)
class SimpleSoccerEvaluator:
    """Plays every rulebase in one batch. With games_per_evaluation = k > 1 each rulebase plays k games
    from seeds derived from its own seed, and its result is their mean (goals, kicks, ticks and fitness
    averaged; the closest approach is the minimum; end_reason is the first game's)."""

    config: GameConfig = GameConfig()
    vocabulary: Vocabulary = SOCCER_VOCABULARY  # the rulebases' vocabulary (the GA's)

    @property
    def chunk_size(self) -> int:
        """Rulebases per chunk when the GA plays a generation in chunks (ga/evaluation.py): CHUNK_GAMES games."""
        return max(1, CHUNK_GAMES // self.config.games_per_evaluation)

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[GameResult]:
        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds: need one seed per rulebase")
        k = self.config.games_per_evaluation
        if k == 1:
            return play_games(list(rulebases), list(seeds), self.config, self.vocabulary)
        all_seeds = [s for seed in seeds for s in game_seeds(int(seed), k)]
        results = play_games([r for r in rulebases for _ in range(k)], all_seeds, self.config, self.vocabulary)
        return [_mean(results[i * k:(i + 1) * k]) for i in range(len(rulebases))]


def _mean(games: list[GameResult]) -> GameResult:
    return GameResult(
        fitness=fmean(g.fitness for g in games),
        goals=fmean(g.goals for g in games),
        kicks=fmean(g.kicks for g in games),
        ticks=fmean(g.ticks for g in games),
        min_ball_goal_distance=min(g.min_ball_goal_distance for g in games),
        end_reason=games[0].end_reason,
    )
