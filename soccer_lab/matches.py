"""Matches from Python, as `soccer-lab match` plays them: two players on one pitch, each match two halves
from one start with the sides swapped at half time (docs/research/matches.md), in SimpleSoccer or on a real
rcssserver (`env="rcss"`: two of our clients, one per side)."""

from __future__ import annotations

from contextlib import ExitStack
from os import PathLike
from typing import Any, Sequence

from soccer_lab.app.runs.environments import RCSS, SIMPLE, checked_env
from soccer_lab.rules import Rules, _game_config, rulebase_of
from soccer_lab.soccer.match_table import Half, Match, Matches, Record, table_of

__all__ = ["match", "Matches", "Match", "Half", "Record"]

DEFAULT_MATCHES = 5
DEFAULT_SEED = 0


def match(a: Rules, b: Rules, matches: int = DEFAULT_MATCHES, seed: int = DEFAULT_SEED, see_opponent: bool = False,
          env: str = SIMPLE, server: str | None = None, rcssserver: str | PathLike | None = None,
          **game: Any) -> Matches:
    """Play `matches` matches of A against B, match i (from 0) from a random start drawn with seed + i, each
    in two halves with the sides swapped, and return the table and each match. `see_opponent`: play in the
    vocabulary with the opponent as a third object (rules may then name Opponent; SimpleSoccer only). `game`:
    GameConfig's options (max_ticks, goal_cap, idle_ticks, skills, noise, count_touches), per half; pydantic's
    ValidationError (a ValueError) names a bad value.

    `env="rcss"` plays on a real rcssserver: the one at `server` ("HOST:PORT", run with
    server::synch_mode=true server::coach_w_referee=true), else one started (and stopped) from `rcssserver`
    (default $RCSSSERVER, else rcssserver on PATH). Its ticks are server cycles, `noise` is the server's (on
    by default) and `restart_wait_cycles` is also taken; an rcssserver that cannot be reached or started
    raises soccer_lab.soccer.rcss.errors.RcssError with one line saying why.

    >>> import soccer_lab as sl
    >>> played = sl.match(sl.example("striker"), sl.example("demo"), matches=2, seed=0, max_ticks=300)
    >>> [m.seed for m in played.matches]
    [0, 1]
    >>> played == sl.match(sl.example("striker"), sl.example("demo"), matches=2, seed=0, max_ticks=300)
    True
    """
    from soccer_lab.fuzzy.vocabulary import Vocabulary

    for name, value, least in (("matches", matches, 1), ("seed", seed, 0)):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise ValueError(f"{name}: a whole number of at least {least}, not {value!r}")
    try:
        checked_env(env)
    except ValueError as exc:
        raise ValueError(f"env: {exc}") from None
    if env == SIMPLE and (server is not None or rcssserver is not None):
        raise ValueError('server and rcssserver: for env="rcss" only')
    if env == RCSS and see_opponent:
        raise ValueError('see_opponent: SimpleSoccer only, not with env="rcss"')
    vocabulary = Vocabulary.with_opponent() if see_opponent else Vocabulary.default()
    players = rulebase_of(a, vocabulary), rulebase_of(b, vocabulary)
    seeds = [seed + i for i in range(matches)]
    if env == RCSS:
        return table_of(_play_on_rcss(players, seeds, server, rcssserver, game))
    from soccer_lab.soccer.match import play_matches

    return table_of(play_matches(*players, seeds, _game_config(game), vocabulary))


def _play_on_rcss(players: tuple, seeds: Sequence[int], server: str | None, rcssserver: str | PathLike | None,
                  game: dict[str, Any]) -> list:
    from soccer_lab.soccer.rcss.match import RcssMatchConfig, play_rcss_matches
    from soccer_lab.soccer.rcss.match_session import MatchSession
    from soccer_lab.soccer.rcss.player import load_compiled_skills
    from soccer_lab.soccer.rcss.servers import ServerPool, noise_options

    unknown = sorted(set(game) - set(RcssMatchConfig.model_fields))
    if unknown:
        raise TypeError(f"unknown rcssserver match option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                        f"expected {', '.join(RcssMatchConfig.model_fields)}")
    config = RcssMatchConfig(**game)
    with ExitStack() as stack:
        if server is None:
            server = stack.enter_context(ServerPool(rcssserver, 1, noise_options(config.noise))).addresses[0]
        load_compiled_skills()  # before the server waits for the players
        session = stack.enter_context(MatchSession(server))
        session.open()
        return play_rcss_matches(session, *players, seeds, config)
