"""Playing SimpleSoccer games from Python, as `soccer-lab play` does: the same seeds give the same games."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from soccer_lab.app.cli.play import DEFAULT_GAMES, DEFAULT_SEED
from soccer_lab.app.rule_inspection import seeds_from
from soccer_lab.rules import Rules, _game_config, rulebase_of


@dataclass(frozen=True)
class Game:
    """How one game went: its start's seed, goals scored, kicks, ticks played, why it ended ("max-ticks",
    "goal-cap" or "idle") and its fitness (lower is better; the chapter's Table 1)."""

    seed: int
    goals: int
    kicks: int
    ticks: int
    end_reason: str
    fitness: float
    min_ball_goal_distance: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def play(rules: Rules, games: int = DEFAULT_GAMES, seed: int = DEFAULT_SEED, **game: Any) -> list[Game]:
    """Play `games` SimpleSoccer games, game i (from 0) from a random start drawn with seed + i, and return
    how each went. `game`: GameConfig's options (max_ticks, goal_cap, idle_ticks, fitness, skills, noise,
    count_touches), as `soccer-lab play`'s; pydantic's ValidationError (a ValueError) names a bad value.

    >>> import soccer_lab as sl
    >>> played = sl.play(sl.example("demo"), games=3, seed=0, max_ticks=400)
    >>> [g.seed for g in played]
    [0, 1, 2]
    >>> played == sl.play(sl.example("demo"), games=3, seed=0, max_ticks=400)  # one seed, one game
    True
    """
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.engine import play_games

    if isinstance(games, bool) or not isinstance(games, int) or games < 1:
        raise ValueError(f"games: a whole number of at least 1, not {games!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed: a whole number of at least 0, not {seed!r}")
    rulebase = rulebase_of(rules)
    seeds = seeds_from(seed, games)
    results = play_games([rulebase] * games, seeds, _game_config(game), SOCCER_VOCABULARY)
    return [Game(s, r.goals, r.kicks, r.ticks, r.end_reason, r.fitness, r.min_ball_goal_distance)
            for s, r in zip(seeds, results)]
