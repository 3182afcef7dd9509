"""A player's true quality: its fitness re-played on fresh starts, beside the one noisy figure the GA saw.

The GA keeps the player with the lowest running mean, often one lucky game; re-played on N starts its
mean and spread say how good it is. Runs re-play every player on the same N seeded starts
(`common_seeds`), so two players' figures compare; an experiment re-plays each trial's best on starts
derived from the trial's seed (app/experiment/runner.py). Both use `replayed_quality`: one home.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.ga.config import SEED_BOUND
from soccer_lab.ga.evaluation import Evaluation, Evaluator

if TYPE_CHECKING:
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.config import GameConfig

TRUE_QUALITY_STARTS = 20  # fresh starts a run's best is re-played on (cost measured by benchmarks/true_quality.py)
COMMON_STARTS_SEED = 37  # the seeded starts every run's players share


@dataclass(frozen=True)
class TrueQuality:
    """Mean and spread over `starts` single games from fresh starts."""

    starts: int
    fitness: float
    fitness_std: float
    goals: float  # mean goals a game
    scoring: float  # share of the games with a goal

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any) -> "TrueQuality | None":
        """The quality stored in run.json or the store; None for a missing or damaged entry."""
        try:
            return cls(int(data["starts"]), float(data["fitness"]), float(data["fitness_std"]),
                       float(data["goals"]), float(data["scoring"]))
        except (KeyError, TypeError, ValueError):
            return None

    def text(self) -> str:
        """e.g. 're-played on 20 fresh starts: fitness 0.823 (std 0.101), 0.33 goals a game, scores in 25%'"""
        return (f"re-played on {self.starts} fresh starts: fitness {self.fitness:.3f} (std {self.fitness_std:.3f}), "
                f"{self.goals:.2f} goals a game, scores in {self.scoring:.0%}")


def common_seeds(count: int = TRUE_QUALITY_STARTS) -> list[int]:
    """The seeded starts every run's players are re-played on: the same for every player and run."""
    state = np.random.SeedSequence(COMMON_STARTS_SEED).generate_state(count, np.uint64)
    return [int(value) % SEED_BOUND for value in state]


def replayed_quality(rulebase: Rulebase, replay: Evaluator, seeds: Sequence[int]) -> TrueQuality:
    """`rulebase` played once from each seed, in one batch (`replay` must play one game per evaluation)."""
    return replayed_qualities([rulebase], replay, seeds)[0]


def replayed_qualities(rulebases: Sequence[Rulebase], replay: Evaluator, seeds: Sequence[int]) -> list[TrueQuality]:
    """Each of `rulebases` played once from each seed, all in one batch (the population view's players)."""
    with Evaluation(replay) as evaluation:
        scores = evaluation([rulebase for rulebase in rulebases for _ in seeds], list(seeds) * len(rulebases))
    fitness = np.array([score.fitness for score in scores]).reshape(len(rulebases), len(seeds))
    goals = np.array([score.goals for score in scores]).reshape(len(rulebases), len(seeds))
    return [TrueQuality(len(seeds), float(f.mean()), float(f.std()), float(g.mean()), float(np.mean(g > 0)))
            for f, g in zip(fitness, goals)]


def simple_soccer_replayer(game: "GameConfig", vocabulary: "Vocabulary", starts: int = TRUE_QUALITY_STARTS,
                           opponent: Rulebase | None = None) -> Callable[[Rulebase], TrueQuality]:
    """A player's true quality in `game`'s SimpleSoccer: one game from each common start, in one batch; against
    an `opponent`, one match (soccer/match.py) from each."""
    from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator
    from soccer_lab.soccer.match import MatchEvaluator

    one = game.model_copy(update={"games_per_evaluation": 1})
    replay = SimpleSoccerEvaluator(one, vocabulary) if opponent is None else MatchEvaluator(opponent, one, vocabulary)
    seeds = common_seeds(starts)
    return lambda rulebase: replayed_quality(rulebase, replay, seeds)


def simple_soccer_batch_replayer(game: "GameConfig", vocabulary: "Vocabulary", starts: int = TRUE_QUALITY_STARTS
                                 ) -> Callable[[Sequence[Rulebase]], list[TrueQuality]]:
    """Several players' true quality in `game`'s SimpleSoccer, on the common starts, in one batch."""
    from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator

    replay = SimpleSoccerEvaluator(game.model_copy(update={"games_per_evaluation": 1}), vocabulary)
    seeds = common_seeds(starts)
    return lambda rulebases: replayed_qualities(rulebases, replay, seeds)
