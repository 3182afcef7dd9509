"""`soccer-lab match A B`: two rulebases on one pitch, each match two halves with the sides swapped; in SimpleSoccer
or (`--env rcss`) on a real rcssserver, two of our clients one per side."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from soccer_lab.app.cli.common import fail
from soccer_lab.app.cli.play import (ENV_PANEL, CountTouchesOption, GoalCapOption, IdleTicksOption, MaxTicksOption,
                                     NoiseOption, RcssserverOption, SkillsOption, chosen_env, config_from_options,
                                     game_config, rcss_addresses)
from soccer_lab.app.runs.environments import ENVIRONMENTS, RCSS, SIMPLE

if TYPE_CHECKING:
    from soccer_lab.fuzzy.rule import Rulebase
    from soccer_lab.soccer.match import MatchResult
    from soccer_lab.soccer.match_table import Matches

MatchEnvOption = Annotated[Optional[str], typer.Option(
    "--env", help=f"Where the matches are played: {' or '.join(ENVIRONMENTS)} (SimpleSoccer, or a real rcssserver with "
    "two of our clients, one per side, set up by its trainer; see docs/research/matches.md). (default: "
    f"{SIMPLE})", show_default=False, rich_help_panel=ENV_PANEL)]
MatchServerOption = Annotated[Optional[list[str]], typer.Option(
    "--server", help=f"With --env {RCSS}: an rcssserver you run, as HOST:PORT (its player port; run it with "
    "server::synch_mode=true server::coach_w_referee=true, and no other players on it). One: a match plays on one "
    "server. (default: soccer-lab starts one itself)", show_default=False, rich_help_panel=ENV_PANEL)]


def match_command(
    a: Annotated[Path, typer.Argument(metavar="A", help="Player A's rulebase file: rule text (.rules) or JSON (.json).",
                                      show_default=False)],
    b: Annotated[Path, typer.Argument(metavar="B", help="Player B's rulebase file.", show_default=False)],
    matches: Annotated[int, typer.Option("--matches", "-n", min=1, help="Matches to play (each two halves).")] = 5,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Seed of the first match's start; match i uses seed + i.")]
    = 0,
    as_json: Annotated[bool, typer.Option("--json", help="Print the table and every match as JSON.")] = False,
    see_opponent: Annotated[bool, typer.Option(
        "--see-opponent", help="Players perceive the opponent as a third object (rules may name Opponent).")] = False,
    max_ticks: MaxTicksOption = None,
    goal_cap: GoalCapOption = None,
    idle_ticks: IdleTicksOption = None,
    noise: NoiseOption = None,
    skills: SkillsOption = None,
    count_touches: CountTouchesOption = None,
    env: MatchEnvOption = None,
    server: MatchServerOption = None,
    rcssserver: RcssserverOption = None,
) -> None:
    """Play A against B in SimpleSoccer (or on rcssserver): each match two halves from one random start, A on the
    left (attacking +x) in the first half and on the right in the second; print each player's wins, draws, losses
    and goals. The game options apply to each half; a half also ends when both players have been idle for
    --idle-ticks. On rcssserver the ticks are server cycles and the server's noise is on unless --no-noise."""
    from soccer_lab.app.rulebase_files import RulebaseFileError, load_rulebase
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.match_table import table_of

    env = chosen_env(env, server, {"--see-opponent": see_opponent or None, "--count-touches": count_touches},
                     {"--rcssserver": rcssserver})
    if server and len(server) > 1:
        fail("--server: a match plays on one server; give it once")
    options = dict(max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks, noise=noise, skills=skills)
    vocabulary = Vocabulary.with_opponent() if see_opponent else Vocabulary.default()
    try:
        players = [load_rulebase(path, vocabulary) for path in (a, b)]
    except RulebaseFileError as exc:
        fail(str(exc))
    seeds = [seed + i for i in range(matches)]
    if env == RCSS:
        results = _play_on_rcss(*players, seeds, server, rcssserver, options)
    else:
        from soccer_lab.soccer.match import play_matches

        results = play_matches(*players, seeds, game_config(**options, count_touches=count_touches), vocabulary)
    table = table_of(results)
    if as_json:
        typer.echo(json.dumps({"players": {"A": str(a), "B": str(b)}, "seed": seed, "env": env, **table.to_dict()},
                              indent=2))
    else:
        _print_table(table, a, b)


def _play_on_rcss(a: "Rulebase", b: "Rulebase", seeds: list[int], server: list[str] | None, rcssserver: Path | None,
                  options: dict) -> list["MatchResult"]:
    """The matches on the --server the user runs, or on one rcssserver soccer-lab starts (and stops)."""
    from soccer_lab.soccer.rcss.errors import RcssError
    from soccer_lab.soccer.rcss.match import RcssMatchConfig, play_rcss_matches
    from soccer_lab.soccer.rcss.match_session import MatchSession
    from soccer_lab.soccer.rcss.player import load_compiled_skills

    config = config_from_options(RcssMatchConfig, options)
    with rcss_addresses(server, rcssserver, None, config.noise) as (address,):
        try:
            load_compiled_skills()  # before the server waits for the players
            with MatchSession(address) as session:
                session.open()
                return play_rcss_matches(session, a, b, seeds, config)
        except RcssError as exc:
            fail(str(exc))


def _print_table(table: "Matches", a: Path, b: Path) -> None:
    names = [a.name, b.name]
    width = max(len("player"), *(len(n) for n in names))
    row = "{:<2} {:<%d} {:>5} {:>6} {:>7} {:>10} {:>14}" % width
    typer.echo(row.format("", "player", "wins", "draws", "losses", "goals for", "goals against"))
    for label, name, record in zip("AB", names, (table.a, table.b)):
        typer.echo(row.format(label, name, record.wins, record.draws, record.losses, record.goals_for,
                              record.goals_against))
