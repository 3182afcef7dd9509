"""`soccer-lab match A B`: two rulebases on one pitch, each match two halves with the sides swapped."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from soccer_lab.app.cli.common import fail
from soccer_lab.app.cli.play import (CountTouchesOption, GoalCapOption, IdleTicksOption, MaxTicksOption, NoiseOption,
                                     SkillsOption, game_config)

if TYPE_CHECKING:
    from soccer_lab.soccer.match_table import Matches

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
) -> None:
    """Play A against B in SimpleSoccer: each match two halves from one random start, A on the left (attacking +x)
    in the first half and on the right in the second; print each player's wins, draws, losses and goals. The game
    options apply to each half; a half also ends when both players have been idle for --idle-ticks."""
    from soccer_lab.app.rulebase_files import RulebaseFileError, load_rulebase
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.match import play_matches
    from soccer_lab.soccer.match_table import table_of

    config = game_config(max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks, noise=noise, skills=skills,
                         count_touches=count_touches)
    vocabulary = Vocabulary.with_opponent() if see_opponent else Vocabulary.default()
    try:
        players = [load_rulebase(path, vocabulary) for path in (a, b)]
    except RulebaseFileError as exc:
        fail(str(exc))
    table = table_of(play_matches(*players, [seed + i for i in range(matches)], config, vocabulary))
    if as_json:
        typer.echo(json.dumps({"players": {"A": str(a), "B": str(b)}, "seed": seed, **table.to_dict()}, indent=2))
    else:
        _print_table(table, a, b)


def _print_table(table: "Matches", a: Path, b: Path) -> None:
    names = [a.name, b.name]
    width = max(len("player"), *(len(n) for n in names))
    row = "{:<2} {:<%d} {:>5} {:>6} {:>7} {:>10} {:>14}" % width
    typer.echo(row.format("", "player", "wins", "draws", "losses", "goals for", "goals against"))
    for label, name, record in zip("AB", names, (table.a, table.b)):
        typer.echo(row.format(label, name, record.wins, record.draws, record.losses, record.goals_for,
                              record.goals_against))
