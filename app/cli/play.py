"""`soccer-lab play RULEBASE`: play games from seeded random starts and print how each went.

Also home of the game options (`--fitness`, `--max-ticks`, ...) that `evolve` shares, and of
`config_from_options`, which turns a pydantic validation error into one line naming the option.
"""

from __future__ import annotations

from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Iterator, Optional

import typer
from pydantic import BaseModel, ValidationError

from soccer_lab.app.cli.common import fail
from soccer_lab.app.runs.environments import ENVIRONMENTS, RCSS, SIMPLE, checked_env, checked_servers
from soccer_lab.app.web.validation import describe_problems
from soccer_lab.soccer.config import FITNESS_NAMES, SKILL_SET_NAMES, GameConfig
from soccer_lab.soccer.rcss.servers import EXECUTABLE_VARIABLE, MAX_SERVERS

if TYPE_CHECKING:  # soccer_lab.soccer.rcss.trial compiles the player's kernels: imported only when rcss is used
    from soccer_lab.soccer.rcss.trial import TrialConfig

DEFAULT_GAMES = 5
DEFAULT_SEED = 0
GAME_PANEL = "Game"
ENV_PANEL = "Environment"


def _default(model: type[BaseModel], field: str) -> Any:
    return model.model_fields[field].default


def option_help(model: type[BaseModel], field: str, text: str) -> str:
    """Help text ending with the model's default: the model is the one place defaults live."""
    return f"{text} (default: {_default(model, field)})"


def option_name(field: str, renamed: dict[str, str]) -> str:
    return "--" + renamed.get(field, field.replace("_", "-"))


def config_from_options(model: type[BaseModel], values: dict[str, Any], renamed: dict[str, str] | None = None):
    """`model(**values)` without the options left unset; a validation error exits with one line
    naming the command-line option (`--population-size: Input should be ...`)."""
    renamed = renamed or {}
    try:
        return model(**{field: value for field, value in values.items() if value is not None})
    except ValidationError as exc:
        fail(describe_problems(exc.errors(), where=lambda location: option_name(str(location[0]), renamed)
                               if location else ""))


# The game options, shared with `evolve` and `random-search`: unset (None) means the GameConfig default.
FitnessOption = Annotated[Optional[str], typer.Option(
    "--fitness", help=option_help(GameConfig, "fitness", f"Fitness function: {', '.join(FITNESS_NAMES)}."),
    show_default=False, rich_help_panel=GAME_PANEL)]
MaxTicksOption = Annotated[Optional[int], typer.Option(
    "--max-ticks", help=option_help(GameConfig, "max_ticks", "Ticks (100 ms) a game lasts at most."),
    show_default=False, rich_help_panel=GAME_PANEL)]
GoalCapOption = Annotated[Optional[int], typer.Option(
    "--goal-cap", help=option_help(GameConfig, "goal_cap", "A game ends when this many goals are scored."),
    show_default=False, rich_help_panel=GAME_PANEL)]
IdleTicksOption = Annotated[Optional[int], typer.Option(
    "--idle-ticks", help=option_help(GameConfig, "idle_ticks",
                                     "A game ends after this many ticks without moving or kicking."),
    show_default=False, rich_help_panel=GAME_PANEL)]
NoiseOption = Annotated[Optional[bool], typer.Option(
    "--noise/--no-noise", help=option_help(GameConfig, "noise", "rcssserver-like movement noise; on rcssserver "
                                           "the server's own noise, on unless --no-noise (servers without it play a "
                                           "trial the same every time)."),
    show_default=False, rich_help_panel=GAME_PANEL)]

SkillsOption = Annotated[Optional[str], typer.Option(
    "--skills", help=option_help(GameConfig, "skills", f"Skill set: {', '.join(SKILL_SET_NAMES)} (strict: the "
                                 "kicking skills do nothing with the ball out of reach; assisted: they fetch it; "
                                 "sighted: strict, and the goal skills act only while the goal is in view)."),
    show_default=False, rich_help_panel=GAME_PANEL)]


CountTouchesOption = Annotated[Optional[bool], typer.Option(
    "--count-touches/--no-count-touches", help=option_help(
        GameConfig, "count_touches", "Count every tick the player's body pushes the ball as a kick (the fitness's "
        "ball movement), not only the kicks that reach it."),
    show_default=False, rich_help_panel=GAME_PANEL)]


def game_config(**options: Any) -> GameConfig:
    """GameConfig from the game options given by name (fitness, max_ticks, ..., count_touches); unset (None)
    ones keep GameConfig's defaults."""
    return config_from_options(GameConfig, options)


# The environment options, shared with `evolve` and `random-search`.
EnvOption = Annotated[Optional[str], typer.Option(
    "--env", help=f"Where games are played: {' or '.join(ENVIRONMENTS)} (SimpleSoccer or a real rcssserver; with "
    f"{RCSS} the game options left unset take the chapter's RoboCup trial settings, see docs/robocup/index.md). "
    f"(default: {SIMPLE})",
    show_default=False, rich_help_panel=ENV_PANEL)]
def server_options(when: str) -> tuple[Any, Any, Any]:
    """The --server, --rcssserver and --servers options, their help starting with `when` they apply
    ("With --env rcss", or for `experiment` "For the robocup and transfer presets")."""
    server = Annotated[Optional[list[str]], typer.Option(
        "--server", help=f"{when}: an rcssserver you run, as HOST:PORT (its player port; run it with "
        "server::synch_mode=true server::coach_w_referee=true). Repeat for several servers: trials run on them in "
        "parallel, one at a time on each. (default: soccer-lab starts --servers servers itself)",
        show_default=False, rich_help_panel=ENV_PANEL)]
    rcssserver = Annotated[Optional[Path], typer.Option(
        "--rcssserver", help=f"{when}: the rcssserver executable soccer-lab starts its servers from (each on "
        "free ports, in a scratch folder, with the options trials need; all stopped when the command ends). "
        f"(default: ${EXECUTABLE_VARIABLE}, else rcssserver on PATH)", show_default=False, rich_help_panel=ENV_PANEL)]
    servers = Annotated[Optional[int], typer.Option(
        "--servers", min=1, max=MAX_SERVERS, help=f"{when}: how many rcssservers soccer-lab starts; trials run "
        "on them in parallel (on a Ray cluster: on each node). (default: 1; on a Ray cluster one per CPU of each "
        "node)", show_default=False, rich_help_panel=ENV_PANEL)]
    return server, rcssserver, servers


ServerOption, RcssserverOption, ServersOption = server_options(f"With --env {RCSS}")


def chosen_env(env: str | None, servers: list[str] | None, simple_only: dict[str, Any],
               rcss_only: dict[str, Any] | None = None) -> str:
    """--env checked against the other options: --server and `rcss_only` ({"--servers": value}, None = not
    given) need rcss; `simple_only` ({"--count-touches": value}) are refused with rcss rather than silently
    ignored."""
    env = SIMPLE if env is None else env
    try:
        checked_env(env)
    except ValueError as exc:
        fail(f"--env: {exc}")
    needing_rcss = (["--server"] if servers else []) + [o for o, value in (rcss_only or {}).items() if value is not None]
    if env == SIMPLE and needing_rcss:
        fail(f"{', '.join(needing_rcss)} need{'s' if len(needing_rcss) == 1 else ''} --env {RCSS}")
    given = [option for option, value in simple_only.items() if value is not None]
    if env == RCSS and given:
        fail(f"{', '.join(given)}: SimpleSoccer only, not with --env {RCSS}")
    return env


def rcss_executable(servers: list[str] | None, rcssserver: Path | None, count: int | None) -> Path | None:
    """The rcssserver executable to start servers from (checked now), or None for the --server's the user
    runs."""
    if servers:
        if rcssserver is not None or count is not None:
            fail("--server names servers you run; --rcssserver and --servers start servers: give one or the other")
        return None
    from soccer_lab.soccer.rcss.servers import RcssLaunchError, find_rcssserver

    try:
        return find_rcssserver(rcssserver)
    except RcssLaunchError as exc:
        fail(f"{exc}: give --rcssserver PATH (see docs/robocup/index.md), or --server HOST:PORT for a server "
             "you run")


@contextmanager
def rcss_addresses(servers: list[str] | None, rcssserver: Path | None, count: int | None,
                   noise: bool = True) -> Iterator[list[str]]:
    """The HOST:PORTs trials play on: the --server's the user runs, or `count` (default 1) servers soccer-lab
    starts from `rcssserver` (default $RCSSSERVER, else PATH), with or without their noise, and stops when
    the block ends."""
    executable = rcss_executable(servers, rcssserver, count)
    if executable is None:
        yield rcss_servers(servers)
        return
    from soccer_lab.soccer.rcss.servers import RcssLaunchError, ServerPool, describe, noise_options

    with ExitStack() as stack:
        try:
            pool = stack.enter_context(ServerPool(executable, count or 1, noise_options(noise)))
        except RcssLaunchError as exc:
            fail(str(exc))
        typer.echo(describe(pool.servers), err=True)
        yield pool.addresses


def rcss_servers(servers: list[str] | None) -> list[str]:
    """The --server addresses (checked now, before any connection), or the default server."""
    try:
        return checked_servers(RCSS, servers)
    except ValueError as exc:
        fail(f"--server: {exc}")


def trial_config(**options: Any) -> "TrialConfig":
    """rcssserver trials (the chapter's, 5.3) from the game options they share with SimpleSoccer (fitness,
    max_ticks, goal_cap, idle_ticks, skills) given by name; unset ones keep TrialConfig's (the chapter's)."""
    from soccer_lab.soccer.rcss.trial import TrialConfig

    return config_from_options(TrialConfig, options)


def consecutive_seeds(seed: int, games: int) -> list[int]:
    """Game i (from 0) starts from seed + i, so any one game can be replayed alone."""
    return [seed + i for i in range(games)]


def play_command(
    rulebase: Annotated[Path, typer.Argument(
        metavar="RULEBASE", help="Rulebase file: rule text (.rules) or JSON (.json).", show_default=False)],
    games: Annotated[int, typer.Option("--games", "-n", min=1, help="Games to play.")] = DEFAULT_GAMES,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Seed of the first game's start; game i uses seed + i.")]
    = DEFAULT_SEED,
    rrd: Annotated[Optional[Path], typer.Option(
        "--rrd", help="Write every game's replay to this rerun file (on rcssserver: where the server put player and "
                      "ball, cycle by cycle).", show_default=False)] = None,
    fitness: FitnessOption = None,
    max_ticks: MaxTicksOption = None,
    goal_cap: GoalCapOption = None,
    idle_ticks: IdleTicksOption = None,
    noise: NoiseOption = None,
    skills: SkillsOption = None,
    count_touches: CountTouchesOption = None,
    env: EnvOption = None,
    server: ServerOption = None,
    rcssserver: RcssserverOption = None,
    servers: ServersOption = None,
) -> None:
    """Play RULEBASE in SimpleSoccer (or on rcssserver) from seeded random starts; print goals, kicks, ticks and fitness."""
    from soccer_lab.app.runs.recording import log_replay
    from soccer_lab.app.rulebase_files import RulebaseFileError, load_rulebase
    from soccer_lab.soccer.engine import play_game, play_games

    env = chosen_env(env, server, {"--count-touches": count_touches}, {"--rcssserver": rcssserver, "--servers": servers})
    config = game_config(fitness=fitness, max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks,
                         noise=noise if env == SIMPLE else None, skills=skills, count_touches=count_touches)
    try:
        player = load_rulebase(rulebase)
    except RulebaseFileError as exc:
        fail(str(exc))
    seeds = consecutive_seeds(seed, games)
    stream = _open_replay_file(rrd) if rrd is not None else None
    if env == RCSS:  # a trial's replay is its trace: where the trainer's see_global put player and ball
        from soccer_lab.soccer.rcss.params import ServerParams

        trial = trial_config(fitness=fitness, max_ticks=max_ticks, goal_cap=goal_cap, idle_ticks=idle_ticks,
                             skills=skills, noise=noise)
        with rcss_addresses(server, rcssserver, servers, trial.noise) as addresses:
            results = _play_on_rcss(player, seeds, addresses, trial, trace=stream is not None)
        traces, world = [result.trace for result in results], ServerParams().world
    elif stream is None:
        results, traces, world = play_games([player] * games, seeds, config), [], config.world
    else:
        played = [play_game(player, game_seed, config, trace=True) for game_seed in seeds]
        results, traces, world = [result for result, _ in played], [trace for _, trace in played], config.world
    _print_table(seeds, results)
    if stream is not None:
        for number, trace in enumerate(traces, start=1):
            log_replay(stream, trace, world, entity=f"game_{number}")
        stream.flush()
        stream.disconnect()  # writes the file's footer
        typer.echo(f"replays written to {rrd} (open with: rerun {rrd})")


def _play_on_rcss(player, seeds: list[int], servers: list[str], trial: "TrialConfig", trace: bool) -> list[Any]:
    """Trials on real servers, in parallel over the servers (each with its trace when `trace`)."""
    from soccer_lab.soccer.rcss.errors import RcssError
    from soccer_lab.soccer.rcss.evaluate import RcssEvaluator

    try:
        with RcssEvaluator(servers, trial, trace=trace) as evaluate:
            return evaluate([player] * len(seeds), seeds)
    except RcssError as exc:
        fail(str(exc))


def _open_replay_file(path: Path):
    if path.is_dir():
        fail(f"--rrd: {path} is a folder")
    if not path.parent.is_dir():
        fail(f"--rrd: folder {path.parent} does not exist")
    from soccer_lab.app.runs.recording import open_stream

    return open_stream(path)


def _print_table(seeds: list[int], results: list[Any]) -> None:
    seed_width = max(len("seed"), *(len(str(s)) for s in seeds))
    row = "{:>5} {:>%d} {:>6} {:>6} {:>6} {:>8}" % seed_width
    typer.echo(row.format("game", "seed", "goals", "kicks", "ticks", "fitness"))
    for number, (game_seed, result) in enumerate(zip(seeds, results), start=1):
        typer.echo(row.format(number, game_seed, result.goals, result.kicks, result.ticks, f"{result.fitness:.4f}"))
    count = len(results)
    typer.echo(row.format(
        "mean", "",
        f"{sum(r.goals for r in results) / count:.2f}", f"{sum(r.kicks for r in results) / count:.1f}",
        f"{sum(r.ticks for r in results) / count:.0f}", f"{sum(r.fitness for r in results) / count:.4f}",
    ))

