"""`soccer-lab evolve` and `soccer-lab random-search`: one run from the terminal, with a progress bar,
a summary, and its outputs in a run folder (app/runs/outputs.py); `evolve --resume RUN_DIR` continues
a killed run (either kind) from its checkpoint. Evaluations play SimpleSoccer games or, with
`--env rcss`, trials on real rcssservers. The run itself is app/runs/run.py's `Run`, as in the app."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import TYPE_CHECKING, Annotated, Any, Callable, Optional

import typer

from soccer_lab.app.cli.common import fail
from soccer_lab.app.cli.play import (ENV_PANEL, GAME_PANEL, CountTouchesOption, EnvOption, FitnessOption,
                                     GoalCapOption, IdleTicksOption, MaxTicksOption, NoiseOption, RcssserverOption,
                                     ServerOption, ServersOption, SkillsOption, chosen_env, config_from_options,
                                     game_config, option_help, option_name, rcss_executable, rcss_servers,
                                     trial_config)
from soccer_lab.app.runs.environments import RCSS, RCSS_WORKERS, SIMPLE, checked_workers, default_workers
from soccer_lab.app.experiment.executors import LOCAL, RAY
from soccer_lab.app.words import plural
from soccer_lab.ga.config import CoevolutionConfig, GAConfig
from soccer_lab.soccer.config import GameConfig

if TYPE_CHECKING:  # the run's machinery (numpy, numba, rerun) is imported when a run starts, not for --help
    from soccer_lab.app.runs.rcss_cluster import RayCluster
    from soccer_lab.app.runs.run import Run, RunSettings
    from soccer_lab.app.runs.outputs import RunFolder
    from soccer_lab.app.runs.true_quality import TrueQuality
    from soccer_lab.ga.result import RunResult

GA_PANEL = "Genetic algorithm"
RUN_PANEL = "Run"
# GAConfig fields whose option is not simply --field-name.
RENAMED = {"max_generations": "generations"}


def _ga_option(field: str, text: str, kind: Any) -> Any:
    return Annotated[Optional[kind], typer.Option(
        option_name(field, RENAMED), help=option_help(GAConfig, field, text),
        show_default=False, rich_help_panel=GA_PANEL)]


PopulationSize = _ga_option("population_size", "Individuals per generation.", int)
Generations = _ga_option("max_generations", "Generations evaluated, the initial one included.", int)
MaxLength = _ga_option("max_length", "Maximum genes per chromosome.", int)
ConsequentProbability = _ga_option("consequent_probability", "Chance that an initial gene is a consequent.", float)
Crossover = _ga_option("crossover", "Crossover: one-point or two-point (cut-and-splice), or uniform (rule by rule).",
                       str)
CrossoverProbability = _ga_option("crossover_probability", "Chance that a pair of parents is crossed.", float)
MutationProbability = _ga_option("mutation_probability", "Chance that a child is mutated.", float)
MutationRate = _ga_option("mutation_rate", "Chance that each gene of a mutated child is hit.", float)
Selection = _ga_option("selection", "roulette, tournament or elitist.", str)
RouletteWeighting = _ga_option("roulette_weighting", "Roulette weight (roulette and elitist selection): linear "
                               "(1 - fitness) or inverse (1 / fitness).", str)
TournamentSize = _ga_option("tournament_size", "Entrants per tournament.", int)
TournamentSelector = _ga_option("tournament_selector", "Chance that the better entrant wins a tournament.", float)
EliteFraction = _ga_option("elite_fraction", "Share of the population copied unchanged (elitist).", float)
TargetFitness = _ga_option("target_fitness", "Stop once the best fitness reaches this.", float)
Seed = _ga_option("seed", "Seed of the whole run: the same seed gives the same run, bit for bit (the summary "
                  "prints it; the UI and the API draw a fresh one when none is given).", int)
BehaviourSeeds = _ga_option("behaviour_seeds", "K: each generation, every new chromosome also plays K common seeds "
                            "so statistics.csv counts the distinct ways the population plays (costs K games per new "
                            "chromosome; 0: off). SimpleSoccer only.", int)
Workers = Annotated[Optional[int], typer.Option(
    "--workers", help="Evaluation processes; results do not depend on it. Not with --env rcss: there the GA "
    "evaluates in this one process and trials run in parallel over the servers instead (--servers, or the "
    "--server's; one server per parallel trial). (default: all cores; 1 with --env rcss)",
    show_default=False, rich_help_panel=GA_PANEL)]
GamesPerEvaluation = Annotated[Optional[int], typer.Option(
    "--games-per-evaluation", help=option_help(GameConfig, "games_per_evaluation",
                                               "Games an evaluation averages, from different starts."),
    show_default=False, rich_help_panel="Game")]
Executor = Annotated[Optional[str], typer.Option(
    "--executor", help="With --env rcss: where the servers run: local (this machine) or ray (every node of a Ray "
    "cluster starts its own, from its $RCSSSERVER or PATH unless --rcssserver names a path good on every node; "
    "--servers is then per node, default one per CPU). (default: local)", show_default=False,
    rich_help_panel=ENV_PANEL)]
Address = Annotated[Optional[str], typer.Option(
    "--address", help="With --executor ray: the Ray cluster's address. (default: start Ray here)",
    show_default=False, rich_help_panel=ENV_PANEL)]
Out = Annotated[Optional[Path], typer.Option(
    "--out", help="Run folder for the outputs. (default: runs/<timestamp>)", show_default=False,
    rich_help_panel=RUN_PANEL)]
Opponent = Annotated[Optional[Path], typer.Option(
    "--opponent", metavar="FILE", help="Evolve against this fixed player (a rulebase file): each evaluation is a "
    "match against it, two halves with the sides swapped, scored by the chapter's composite carried over to goal "
    "difference (docs/research/matches.md). SimpleSoccer only.", show_default=False, rich_help_panel=GAME_PANEL)]
Coevolve = Annotated[bool, typer.Option(
    "--coevolve", help="Co-evolve: score each player over matches against members of a hall of fame of earlier "
    "generations' bests (generation 0 plays the --opponent, else the built-in demo, which stays in the hall). "
    "SimpleSoccer only.", rich_help_panel=GAME_PANEL)]
HallSize = Annotated[Optional[int], typer.Option(
    "--hall-size", metavar="K", help=option_help(CoevolutionConfig, "hall_size", "With --coevolve: the last K "
                                                 "distinct generation bests the hall keeps, beside its founder."),
    show_default=False, rich_help_panel=GAME_PANEL)]
HallSample = Annotated[Optional[int], typer.Option(
    "--hall-sample", metavar="M", help=option_help(CoevolutionConfig, "hall_sample", "With --coevolve: hall members "
                                                   "each generation is scored against, a match each (drawn with the "
                                                   "run's seed)."),
    show_default=False, rich_help_panel=GAME_PANEL)]
Resume = Annotated[Optional[Path], typer.Option(
    "--resume", help="Continue the killed run in this folder (with its own settings; an rcss run may be given "
    "other servers: --server's, or --rcssserver and --servers).", show_default=False,
    rich_help_panel=RUN_PANEL)]


def evolve_command(
    population_size: PopulationSize = None, generations: Generations = None, max_length: MaxLength = None,
    consequent_probability: ConsequentProbability = None, crossover: Crossover = None,
    crossover_probability: CrossoverProbability = None, mutation_probability: MutationProbability = None,
    mutation_rate: MutationRate = None, selection: Selection = None, roulette_weighting: RouletteWeighting = None,
    tournament_size: TournamentSize = None, tournament_selector: TournamentSelector = None,
    elite_fraction: EliteFraction = None, target_fitness: TargetFitness = None, seed: Seed = None,
    workers: Workers = None, behaviour_seeds: BehaviourSeeds = None, fitness: FitnessOption = None,
    games_per_evaluation: GamesPerEvaluation = None,
    max_ticks: MaxTicksOption = None, goal_cap: GoalCapOption = None, idle_ticks: IdleTicksOption = None,
    noise: NoiseOption = None, skills: SkillsOption = None, count_touches: CountTouchesOption = None,
    env: EnvOption = None, server: ServerOption = None,
    rcssserver: RcssserverOption = None, servers: ServersOption = None, executor: Executor = None,
    address: Address = None, opponent: Opponent = None, coevolve: Coevolve = False, hall_size: HallSize = None,
    hall_sample: HallSample = None, out: Out = None, resume_dir: Resume = None,
) -> None:
    """Evolve a goal-scoring rulebase with the messy-coded GA (defaults: the chapter's Table 2)."""
    options = dict(locals())  # first: the options are the function's locals
    from soccer_lab.ga.state import GA

    if not options["coevolve"]:
        options["coevolve"] = None  # not given (a flag's False), so --resume does not refuse it
    if resume_dir is not None:
        # The servers may change: a resumed rcss run can use other servers (or ports) than before.
        given = [f"--{name.replace('_', '-')}" for name, value in options.items()
                 if value is not None and name not in ("resume_dir", *WHERE_SERVERS_RUN)]
        if given:
            fail(f"--resume continues a run with its own settings; drop {', '.join(given)}")
        _resume(resume_dir, server, rcssserver, servers, _cluster(executor, address, server, rcssserver, servers))
    else:
        _start(GA, options)


def random_search_command(
    population_size: PopulationSize = None, generations: Generations = None, max_length: MaxLength = None,
    consequent_probability: ConsequentProbability = None, target_fitness: TargetFitness = None, seed: Seed = None,
    workers: Workers = None, behaviour_seeds: BehaviourSeeds = None, fitness: FitnessOption = None,
    games_per_evaluation: GamesPerEvaluation = None,
    max_ticks: MaxTicksOption = None, goal_cap: GoalCapOption = None, idle_ticks: IdleTicksOption = None,
    noise: NoiseOption = None, skills: SkillsOption = None, count_touches: CountTouchesOption = None,
    env: EnvOption = None, server: ServerOption = None,
    rcssserver: RcssserverOption = None, servers: ServersOption = None, executor: Executor = None,
    address: Address = None, out: Out = None,
) -> None:
    """The baseline: spend the same evaluations on fresh random rulebases (population x generations),
    with the same statistics and outputs as evolve. Continue a killed one with `evolve --resume`."""
    options = dict(locals())  # first: the options are the function's locals
    from soccer_lab.ga.state import RANDOM_SEARCH

    _start(RANDOM_SEARCH, options)


# ---- where evaluations play -------------------------------------------------------------------
WHERE_SERVERS_RUN = ("server", "rcssserver", "servers", "executor", "address")


def _cluster(executor: str | None, address: str | None, servers: list[str] | None, rcssserver: Path | None,
             count: int | None) -> "RayCluster | None":
    """The Ray cluster whose nodes run the servers (--executor ray), or None for this machine's."""
    if executor not in (None, LOCAL, RAY):
        fail(f"--executor: unknown executor {executor!r}; choose one of {LOCAL}, {RAY}")
    if executor != RAY:
        if address is not None:
            fail("--address needs --executor ray")
        return None
    if servers:
        fail("--server names servers you run; with --executor ray every node starts its own (--servers per node)")
    from soccer_lab.app.runs.rcss_cluster import RayCluster

    return RayCluster(address, count, str(rcssserver) if rcssserver is not None else None)


def _settings(algorithm: str, options: dict[str, Any]) -> "RunSettings":
    """The run the options ask for, each checked with a message naming its option (before the run's
    machinery is imported: a bad option is refused at once)."""
    game_options = {name: options.pop(name) for name in ("fitness", "max_ticks", "goal_cap", "idle_ticks", "skills",
                                                         "noise")}  # noise: SimpleSoccer's, or the server's
    simple_options = {name: options.pop(name) for name in ("count_touches", "games_per_evaluation")}
    env = chosen_env(options.pop("env"), options.get("server"),
                     {option_name(name, {}): value for name, value in simple_options.items()},
                     {"--rcssserver": options.get("rcssserver"), "--servers": options.get("servers")})
    servers = options.pop("server")
    rcssserver, count = options.pop("rcssserver"), options.pop("servers")
    executor, address = options.pop("executor"), options.pop("address")
    if env == SIMPLE and executor is not None:
        fail(f"--executor: for --env {RCSS} only (SimpleSoccer evaluations run on this machine's cores: --workers)")
    cluster = _cluster(executor, address, servers, rcssserver, count)
    for name in ("out", "resume_dir"):
        options.pop(name, None)
    opponent = _opponent_text(options.pop("opponent", None), env)
    coevolve = _coevolution(options.pop("coevolve", None), options.pop("hall_size", None),
                            options.pop("hall_sample", None), env)
    options["max_generations"] = options.pop("generations")
    if env == SIMPLE:
        if options["workers"] is None:
            options["workers"] = default_workers()
        where = {"game": game_config(**game_options, **simple_options), "opponent": opponent, "coevolve": coevolve}
    else:
        if options["workers"] is not None:
            try:
                checked_workers(RCSS, options["workers"])
            except ValueError as exc:
                fail(f"--workers: {exc}")
        options["workers"] = RCSS_WORKERS
        trial = trial_config(**game_options)
        executable = rcss_executable(servers, rcssserver, count) if cluster is None else None  # found on the nodes
        where = {"env": RCSS, "trial": trial, "servers": tuple(rcss_servers(servers)) if servers else (),
                 "start_servers": 0 if servers else count or 1,
                 "rcssserver": str(executable) if executable else None, "cluster": cluster}
    ga = config_from_options(GAConfig, options, RENAMED)
    from soccer_lab.app.runs.run import RunSettings

    return RunSettings(ga, algorithm=algorithm, **where)


def _coevolution(coevolve: bool | None, hall_size: int | None, hall_sample: int | None,
                 env: str) -> CoevolutionConfig | None:
    """--coevolve's hall of fame (None: not co-evolving); --hall-size and --hall-sample need it."""
    if not coevolve:
        given = [name for name, value in (("--hall-size", hall_size), ("--hall-sample", hall_sample)) if value is not None]
        if given:
            fail(f"{', '.join(given)}: with --coevolve only")
        return None
    if env != SIMPLE:
        fail(f"--coevolve: matches are played in SimpleSoccer, not with --env {RCSS}")
    return config_from_options(CoevolutionConfig, {"hall_size": hall_size, "hall_sample": hall_sample})


def _opponent_text(path: Path | None, env: str) -> str | None:
    """The --opponent file's rules as text (run.json keeps them, so a resumed run plays the same opponent)."""
    if path is None:
        return None
    if env != SIMPLE:
        fail(f"--opponent: matches are played in SimpleSoccer, not with --env {RCSS}")
    from soccer_lab.app.rulebase_files import RulebaseFileError, load_rulebase
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.soccer.config import SOCCER_VOCABULARY

    try:
        return format_rulebase(load_rulebase(path), SOCCER_VOCABULARY)
    except RulebaseFileError as exc:
        fail(f"--opponent: {exc}")


# ---- running ---------------------------------------------------------------------------------
def _start(algorithm: str, options: dict[str, Any]) -> None:
    out = options["out"]
    settings = _settings(algorithm, options)
    from soccer_lab.app.runs.run import Run
    from soccer_lab.app.runs.outputs import RunFolderError, default_run_dir

    try:
        run = Run.create(settings, out or default_run_dir())
    except RunFolderError as exc:
        fail(str(exc))
    _drive(run, history=[])


def _resume(path: Path, servers: list[str] | None, rcssserver: Path | None, count: int | None,
            cluster: "RayCluster | None") -> None:
    from soccer_lab.app.runs.run import Run
    from soccer_lab.app.runs.outputs import RunFolderError
    from soccer_lab.ga.checkpoint import CheckpointError

    try:
        run = Run.open(path)
        run.refuse_if_played_elsewhere()
        state = run.saved_state()
    except (RunFolderError, CheckpointError) as exc:
        fail(str(exc))
    given = [option for option, value in (("--server", servers), ("--rcssserver", rcssserver), ("--servers", count))
             if value]
    if cluster is not None:
        given.append("--executor")
    if run.settings.env == SIMPLE and given:
        fail(f"{', '.join(given)}: the run in {run.folder.path} plays SimpleSoccer, not on rcssserver")
    if cluster is not None:
        run.settings = run.settings.on_cluster(cluster)
    elif servers:
        rcss_executable(servers, rcssserver, count)  # refuses --server with --rcssserver/--servers
        run.settings = run.settings.with_servers(rcss_servers(servers))
    elif run.settings.env == RCSS and (run.settings.start_servers or rcssserver or count):
        executable = rcss_executable(None, rcssserver, count)
        run.settings = run.settings.with_started_servers(count, str(executable))
    _drive(run, history=[stats.to_dict() for stats in state.history])


def _drive(run: "Run", *, history: list[dict]) -> None:
    """Play the run with a progress bar, then print the summary. Ctrl-C and a failing environment end it
    with a line saying how to continue."""
    from soccer_lab.app.runs.outputs import RunFolderError
    from soccer_lab.ga.state import GA

    settings, folder = run.settings, run.folder
    label = "evolving" if settings.algorithm == GA else "random search"
    try:
        with run.evaluator(announce=lambda line: typer.echo(line, err=True)) as evaluate:
            if history:
                typer.echo(f"resuming {folder.path} after generation {len(history) - 1}", err=True)
            with GenerationProgress(settings.ga.max_generations, last=history[-1] if history else None,
                                    label=label, quality=lambda: run.best_quality) as progress:
                result = run.play(evaluate, callbacks=[progress])
    except RunFolderError as exc:
        fail(str(exc))
    except KeyboardInterrupt:
        typer.echo(f"\ninterrupted; continue with: soccer-lab evolve --resume {folder.path}", err=True)
        raise typer.Exit(130)
    except settings.environment.failures as exc:
        resumable = f"; continue with: soccer-lab evolve --resume {folder.path}" if folder.checkpoint.exists() else ""
        fail(f"{exc}{resumable}")
    _summary(run, result)


class GenerationProgress:
    """A progress bar over generations showing the best and mean fitness (and the best so far re-played
    on fresh starts), and a second one over the evaluations of the generation in progress (on stderr)."""

    def __init__(self, total: int, *, last: dict[str, Any] | None = None, label: str = "evolving",
                 quality: Callable[[], "TrueQuality | None"] = lambda: None):
        """last: the statistics of the last finished generation, when resuming; quality: the best so far's
        true quality, read after each generation."""
        self.quality = quality
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        self.progress = Progress(
            TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
            TextColumn("{task.fields[detail]}"), TimeElapsedColumn(),
            console=Console(stderr=True),
        )
        self.task = self.progress.add_task(label, total=total, completed=0, detail="best -  mean -")
        self.within = self.progress.add_task("generation 0", total=None, completed=0, detail="evaluated")
        if last is not None:
            self.on_generation(SimpleNamespace(**last))

    def on_progress(self, evaluated: int, population: int) -> None:
        self.progress.update(self.within, completed=evaluated, total=population)

    def __enter__(self) -> "GenerationProgress":
        self.progress.start()
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.progress.stop()

    def on_generation(self, stats: Any, population: Any = None) -> None:
        self.progress.update(self.task, completed=stats.generation + 1,
                             detail=f"best {stats.best:.4f}{_replayed_detail(self.quality())}  mean {stats.mean:.4f}")
        self.progress.reset(self.within, description=f"generation {stats.generation + 1}", total=None)


def _replayed_detail(quality: "TrueQuality | None") -> str:
    """' (re-played 0.823 ± 0.101 on 20 starts)' beside the best the GA saw; '' when not re-played."""
    if quality is None:
        return ""
    return f" (re-played {quality.fitness:.4f} ± {quality.fitness_std:.4f} on {quality.starts} starts)"


def _summary(run: "Run", result: "RunResult") -> None:
    from soccer_lab.app.rulebase_files import rulebase_text

    folder, best = run.folder, result.best
    typer.echo(f"{len(result.history)} generations, {result.evaluations} evaluations ({result.stop_reason}), "
               f"{result.history[-1].wall_time:.1f} s")
    # the CLI keeps seed 0 by default (a researcher's command line reruns as it ran); either way it says it
    typer.echo(f"seed {run.settings.ga.seed} (--seed {run.settings.ga.seed} replays this run bit for bit)")
    typer.echo(f"best fitness {best.fitness:.4f} (mean of {best.evaluations} evaluation"
               f"{'s' if best.evaluations != 1 else ''}; {best.goals} goal{'s' if best.goals != 1 else ''} "
               f"in its latest game)")
    quality = run.best_quality
    typer.echo(f"best player's true quality: {quality.text()}" if quality is not None else
               "best player's true quality: not re-played (on rcssserver N trials would cost minutes)")
    typer.echo(_replay_line(run))
    typer.echo(f"best rules ({len(result.best_rulebase)}):")
    for line in rulebase_text(result.best_rulebase, result.vocabulary).splitlines():
        typer.echo(f"  {line}")
    typer.echo(f"outputs in {folder.path}: {', '.join(p.name for p in _outputs(folder))}")


def _match_replay_line(run: "Run") -> str:
    """Where a match run's best player's first match is (its first half in the recording), and how to play it."""
    game = run.best_game
    if run.settings.coevolve is not None:
        founder = "the --opponent" if run.settings.opponent else "soccer/data/examples/demo.rules"
        line = (f"each evaluation was matches against the hall of fame (lineage.jsonl names each generation's "
                f"opponents): soccer-lab match {run.folder.best_rules} {founder} plays the best against the first")
    else:
        line = (f"each evaluation was a match against the opponent: soccer-lab match {run.folder.best_rules} "
                "OPPONENT.rules plays the best against it")
    if game is None:
        return line + "\nthe best player's first match cannot be replayed (whom it played was not heard: the run was resumed)"
    trace = game.trace
    return line + (f"\nreplay of the first half of the best player's first match (seed {game.seed}) in the recording: "
                   f"{int(trace.goals[-1][0])}-{int(trace.goals[-1][1])}, {plural(game.result.kicks, 'kick')}, "
                   f"{plural(game.result.ticks, 'tick')}")


def _replay_line(run: "Run") -> str:
    game, rcss = run.best_game, run.settings.env == RCSS
    played = "trial" if rcss else "game"
    if run.settings.coevolve is not None or run.settings.opponent:
        return _match_replay_line(run)
    if game is None:
        why = ("it was not traced in this process: the run was resumed" if rcss
               else "its seed was not kept by the run it comes from")
        line = f"the best player's first {played} cannot be replayed ({why})"
    else:
        result = game.result
        line = (f"replay of the best player's first {played} (seed {game.seed}) in the recording: "
                f"{plural(result.goals, 'goal')}, {plural(result.kicks, 'kick')}, {plural(result.ticks, 'tick')}, "
                f"fitness {result.fitness:.4f}")
    if rcss:
        settings = run.settings
        servers = " ".join(f"--server {server}" for server in settings.servers)
        if settings.start_servers:  # those it started are gone: play starts its own
            executable = f"--rcssserver {settings.rcssserver} " if settings.rcssserver else ""
            servers = f"{executable}--servers {settings.start_servers}"
        line += f"\nplay the best on rcssserver: soccer-lab play {run.folder.best_rules} --env {RCSS} {servers}"
    return line


def _outputs(folder: "RunFolder") -> list[Path]:
    return [p for p in (folder.best_rules, folder.best_json, folder.statistics, folder.lineage, folder.checkpoint,
                        folder.recording, folder.manifest) if p.exists()]
