"""Matches from Python, as `soccer-lab match` plays them: two players on one pitch, each match two halves
from one start with the sides swapped at half time (docs/research/matches.md)."""

from __future__ import annotations

from typing import Any

from soccer_lab.rules import Rules, _game_config, rulebase_of
from soccer_lab.soccer.match_table import Half, Match, Matches, Record, table_of

__all__ = ["match", "Matches", "Match", "Half", "Record"]

DEFAULT_MATCHES = 5
DEFAULT_SEED = 0


def match(a: Rules, b: Rules, matches: int = DEFAULT_MATCHES, seed: int = DEFAULT_SEED, see_opponent: bool = False,
          **game: Any) -> Matches:
    """Play `matches` matches of A against B, match i (from 0) from a random start drawn with seed + i, each
    in two halves with the sides swapped, and return the table and each match. `see_opponent`: play in the
    vocabulary with the opponent as a third object (rules may then name Opponent). `game`: GameConfig's
    options (max_ticks, goal_cap, idle_ticks, skills, noise, count_touches), per half; pydantic's
    ValidationError (a ValueError) names a bad value.

    >>> import soccer_lab as sl
    >>> played = sl.match(sl.example("striker"), sl.example("demo"), matches=2, seed=0, max_ticks=300)
    >>> [m.seed for m in played.matches]
    [0, 1]
    >>> played == sl.match(sl.example("striker"), sl.example("demo"), matches=2, seed=0, max_ticks=300)
    True
    """
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.match import play_matches

    for name, value, least in (("matches", matches, 1), ("seed", seed, 0)):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise ValueError(f"{name}: a whole number of at least {least}, not {value!r}")
    vocabulary = Vocabulary.with_opponent() if see_opponent else Vocabulary.default()
    players = rulebase_of(a, vocabulary), rulebase_of(b, vocabulary)
    results = play_matches(*players, [seed + i for i in range(matches)], _game_config(game), vocabulary)
    return table_of(results)
