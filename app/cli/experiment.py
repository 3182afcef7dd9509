"""`soccer-lab experiment PRESET`: the chapter's study (its section 6) with one command: the SimpleSoccer
presets on local processes or Ray, `robocup` (and `transfer`) on rcssservers; the experiments beyond it;
at several seeds (--replicates, --seeds) to tell robust verdicts from lucky ones."""

from __future__ import annotations

from contextlib import ExitStack
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from soccer_lab.app.cli.common import fail
from soccer_lab.app.cli.play import config_from_options, option_help, rcss_addresses, server_options
from soccer_lab.app.experiment.executors import EXECUTOR_NAMES, LOCAL, RAY, ExecutorError, RcssExecutor, make_executor
from soccer_lab.app.experiment.presets import (ALL, ALL_PLUS, CHAPTER_GENERATIONS, CHOICES, DEFAULT_TRIALS,
                                               INITIAL_TRIALS, LONG_GENERATIONS, ROBOCUP, TRANSFER, TRANSFER_TRIALS,
                                               ExperimentOptions)
from soccer_lab.soccer.config import SKILL_SET_NAMES
from soccer_lab.soccer.rcss.errors import RcssError

if TYPE_CHECKING:  # the runner (the GA, the report's statistics and figures) is imported when an experiment runs
    from soccer_lab.app.experiment.replicates import ReplicatesOutcome
    from soccer_lab.app.experiment.runner import ExperimentOutcome
    from soccer_lab.app.experiment.transfer import TransferOutcome

DEFAULT_OUT_FOLDER = "experiments"
ServerOption, RcssserverOption, ServersOption = server_options(f"For the {ROBOCUP} and {TRANSFER} presets")


def experiment_command(
    preset: Annotated[str, typer.Argument(
        help=f"One of: {', '.join((*CHOICES, TRANSFER))}. {ALL}: the chapter's SimpleSoccer study; {ALL_PLUS}: it "
        "and the experiments beyond it.", show_default=False)],
    trials: Annotated[Optional[int], typer.Option(
        "--trials", help=f"Trials per setting. (default: the chapter's, {DEFAULT_TRIALS}; {INITIAL_TRIALS} for "
        f"initial and {ROBOCUP}; {TRANSFER_TRIALS} for {TRANSFER})", show_default=False)] = None,
    population: Annotated[Optional[int], typer.Option(
        "--population", help=option_help(ExperimentOptions, "population",
                                         "Table 2's population size; every setting scales with it."),
        show_default=False)] = None,
    generations: Annotated[Optional[int], typer.Option(
        "--generations", help=option_help(
            ExperimentOptions, "generations",
            f"Table 2's generations; every setting scales with it (long: {LONG_GENERATIONS // CHAPTER_GENERATIONS}x)."),
        show_default=False)] = None,
    max_ticks: Annotated[Optional[int], typer.Option(
        "--max-ticks", help=option_help(ExperimentOptions, "max_ticks", "Ticks a game lasts at most "
                                        f"({ROBOCUP}: server cycles, default the chapter's 1200)."),
        show_default=False)] = None,
    seed: Annotated[Optional[int], typer.Option(
        "--seed", help=option_help(ExperimentOptions, "seed", "Experiment seed; each trial's seed derives from it."),
        show_default=False)] = None,
    replicates: Annotated[Optional[int], typer.Option(
        "--replicates", help="Run the experiment at this many seeds (--seed, --seed + 1, ...), each in OUT/seed-S, "
        "and report each finding's verdict per replicate and whether it is robust. (default: 1)",
        show_default=False)] = None,
    seeds: Annotated[Optional[str], typer.Option(
        "--seeds", help="Replicates at these experiment seeds, comma-separated (e.g. 0,913), instead of counting "
        "up from --seed.", show_default=False)] = None,
    replays: Annotated[Optional[int], typer.Option(
        "--replays", help=option_help(ExperimentOptions, "replays",
                                      "Fresh starts each trial's best is re-played on (its true quality)."),
        show_default=False)] = None,
    skills: Annotated[Optional[str], typer.Option(
        "--skills", help=option_help(ExperimentOptions, "skills", f"Skill set: {', '.join(SKILL_SET_NAMES)}."),
        show_default=False)] = None,
    noise: Annotated[Optional[bool], typer.Option(
        "--noise/--no-noise", help=option_help(ExperimentOptions, "noise", "rcssserver-like movement noise "
                                               f"({ROBOCUP}: the servers' own, on unless --no-noise)."),
        show_default=False)] = None,
    count_touches: Annotated[Optional[bool], typer.Option(
        "--count-touches/--no-count-touches", help=option_help(
            ExperimentOptions, "count_touches", "Count every tick the player's body pushes the ball as a kick."),
        show_default=False)] = None,
    roulette_weighting: Annotated[Optional[str], typer.Option(
        "--roulette-weighting", help=option_help(ExperimentOptions, "roulette_weighting",
                                                 "Roulette weight: linear (1 - fitness) or inverse (1 / fitness)."),
        show_default=False)] = None,
    out: Annotated[Optional[Path], typer.Option(
        "--out", help="Output folder; running again into it resumes. (default: experiments/PRESET-seedN, with "
        "replicates experiments/PRESET-seedsN-M)", show_default=False)] = None,
    workers: Annotated[Optional[int], typer.Option(
        "--workers", min=1, help=f"Trials run at once. (default: all cores; not for {ROBOCUP})",
        show_default=False)] = None,
    executor: Annotated[Optional[str], typer.Option(
        "--executor", help=f"Where trials run: {' or '.join(EXECUTOR_NAMES)}. (default: {LOCAL}; {ROBOCUP}: "
        "rcssservers on this machine, or with ray on every node of the cluster)", show_default=False)] = None,
    address: Annotated[Optional[str], typer.Option(
        "--address", help="Ray cluster address (with --executor ray); default: start Ray here.",
        show_default=False)] = None,
    library: Annotated[bool, typer.Option(
        "--library/--no-library", help="Record the experiment in the app's library.")] = True,
    data_dir: Annotated[Optional[Path], typer.Option(
        "--data-dir", help="The app's data folder whose library records the experiment (as for serve). "
        "(default: $SOCCER_LAB_DATA, else the per-user data folder)", show_default=False)] = None,
    server: ServerOption = None,
    rcssserver: RcssserverOption = None,
    servers: ServersOption = None,
) -> None:
    """Reproduce the chapter's experiments: statistics.csv, figures, report.md and report.html (transfer:
    transfer.md and transfer.html)."""
    if preset not in (*CHOICES, TRANSFER):
        fail(f"unknown preset {preset!r}; choose one of {', '.join((*CHOICES, TRANSFER))}")
    on_servers = preset in (ROBOCUP, TRANSFER)
    options: ExperimentOptions = config_from_options(ExperimentOptions, {
        "trials": trials, "population": population, "generations": generations, "max_ticks": max_ticks,
        "seed": seed, "skills": skills, "noise": noise, "count_touches": count_touches,
        "roulette_weighting": roulette_weighting, "replays": replays})
    replicate_seeds = _replicate_seeds(options.seed, replicates, seeds)
    if replicate_seeds is not None and preset == TRANSFER:
        fail(f"--replicates, --seeds: not for {TRANSFER} (its sources are the {ROBOCUP} preset's runs at --seed)")
    if replicate_seeds is None:
        folder = out or Path(DEFAULT_OUT_FOLDER) / f"{preset}-seed{options.seed}"
    else:
        folder = out or Path(DEFAULT_OUT_FOLDER) / f"{preset}-seeds{'-'.join(map(str, replicate_seeds))}"
    _check_where_trials_run(preset, {"--server": server, "--rcssserver": rcssserver, "--servers": servers},
                            {"--workers": workers, "--count-touches": count_touches})
    from soccer_lab.app.experiment.runner import ExperimentError, run_experiment
    from soccer_lab.app.experiment.transfer import run_transfer

    try:
        with ExitStack() as stack:
            if on_servers:
                runner = _robocup_runner(stack, options, executor, address, server, rcssserver, servers)
            else:
                runner = make_executor(executor or LOCAL, workers=workers, address=address)
            progress = stack.enter_context(ExperimentProgress(preset))
            if preset == TRANSFER:
                transfer = run_transfer(options, folder, runner, progress=progress)
            elif replicate_seeds is None:
                outcome = run_experiment(preset, options, folder, runner, progress=progress)
            else:
                from soccer_lab.app.experiment.replicates import run_replicates

                outcome = run_replicates(preset, options, replicate_seeds, folder, runner, progress=progress)
    except (ExecutorError, ExperimentError) as exc:
        fail(str(exc))
    except RcssError as exc:
        fail(f"{exc}; finished trials and generations are kept: run the same command again to resume")
    except KeyboardInterrupt:
        kept = "finished trials (and the generations of the trial under way)" if on_servers else "finished trials"
        typer.echo(f"\ninterrupted; {kept} are kept: run the same command again to resume", err=True)
        raise typer.Exit(130)
    if preset == TRANSFER:
        _transfer_summary(transfer)
        return
    if library:
        _record(preset, options, outcome, data_dir)
    _summary(outcome)


def _replicate_seeds(seed: int, replicates: int | None, seeds: str | None) -> list[int] | None:
    """The replicates' seeds; None for one experiment at --seed (no --replicates nor --seeds)."""
    if replicates is None and seeds is None:
        return None
    from soccer_lab.app.experiment.replicates import replicate_seeds
    from soccer_lab.app.experiment.runner import ExperimentError

    try:
        given = None if seeds is None else [int(part) for part in seeds.split(",") if part.strip()]
    except ValueError:
        fail(f"--seeds: comma-separated whole numbers, e.g. 0,913 (got {seeds!r})")
    if given is not None and (not given or any(not 0 <= s < 2**63 for s in given)):
        fail("--seeds: one or more seeds in [0, 2^63)")
    try:
        return replicate_seeds(seed, replicates, given)
    except ExperimentError as exc:
        fail(str(exc))


def _robocup_runner(stack: ExitStack, options: ExperimentOptions, executor: str | None, address: str | None,
                    server: list[str] | None, rcssserver: Path | None, servers: int | None):
    """robocup's trials on this machine's servers (started here, or the --server's), or on servers every node of
    a Ray cluster starts (--executor ray: --servers per node, --rcssserver a path good on every node)."""
    if executor not in (None, LOCAL, RAY):
        fail(f"--executor: unknown executor {executor!r}; choose one of {', '.join(EXECUTOR_NAMES)}")
    if executor != RAY:
        if address is not None:
            fail("--address needs --executor ray")
        return RcssExecutor(stack.enter_context(rcss_addresses(server, rcssserver, servers, options.trial().noise)))
    if server:
        fail("--server names servers you run; with --executor ray every node starts its own (--servers per node)")
    from soccer_lab.app.runs.rcss_cluster import ClusterRcssExecutor, RayCluster

    cluster = RayCluster(address, servers, str(rcssserver) if rcssserver is not None else None)
    return ClusterRcssExecutor(cluster, announce=lambda line: typer.echo(line, err=True))


def _check_where_trials_run(preset: str, rcss_options: dict[str, object], local_options: dict[str, object]) -> None:
    """robocup and transfer play on rcssservers (the rcss options), every other preset SimpleSoccer on the
    executor (the local options)."""
    on_servers = preset in (ROBOCUP, TRANSFER)
    given = [option for option, value in (local_options if on_servers else rcss_options).items() if value is not None]
    if given and on_servers:
        fail(f"{', '.join(given)}: {preset} plays its trials on rcssservers (--servers sets how many, the count "
             "of kicks is the server's), not SimpleSoccer on worker processes")
    if given:
        fail(f"{', '.join(given)}: for the {ROBOCUP} and {TRANSFER} presets only (the others play SimpleSoccer)")


class ExperimentProgress:
    """One bar for the whole experiment, counted in the games (or evaluations) its trials play: they differ in
    size."""

    def __init__(self, preset: str):
        from rich.console import Console
        from rich.progress import (BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn,
                                   TimeRemainingColumn)

        self.progress = Progress(TextColumn("[bold]experiment {task.description}"), BarColumn(),
                                 TaskProgressColumn(), TextColumn("{task.fields[note]}"), TimeElapsedColumn(),
                                 TimeRemainingColumn(), console=Console(stderr=True))
        self.task = self.progress.add_task(preset, total=None, note="")

    def __enter__(self) -> "ExperimentProgress":
        self.progress.start()
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.progress.stop()

    def update(self, completed: int, total: int, *, skipped: int = 0) -> None:
        note = f"({skipped} finished trials skipped)" if skipped else ""
        self.progress.update(self.task, completed=completed, total=total, note=note)


def _record(preset: str, options: ExperimentOptions, outcome: "ExperimentOutcome | ReplicatesOutcome",
            data_dir: Path | None) -> None:
    """In the library: one experiment, or replicates as one entry (their summary report above them)."""
    from soccer_lab.app.experiment.library import library_summary
    from soccer_lab.app.paths import DATABASE_FILE, default_data_dir
    from soccer_lab.app.store import Store, StoreError

    try:
        folder = data_dir or default_data_dir()
        folder.mkdir(parents=True, exist_ok=True)
        store = Store(folder / DATABASE_FILE)
        try:
            store.record_experiment(preset, outcome.folder.resolve(), library_summary(options, outcome))
        finally:
            store.close()
    except StoreError as exc:
        typer.echo(f"warning: not recorded in the library: {exc}", err=True)


def _transfer_summary(outcome: "TransferOutcome") -> None:
    from soccer_lab.app.experiment.transfer import REPORT_HTML, REPORT_MD, STATISTICS_FILE

    typer.echo(f"{len(outcome.plan.specs)} rcssserver runs ({outcome.ran} run now) and {len(outcome.players)} player "
               f"games in {outcome.seconds:.1f} s")
    for claim, measured, verdict, _ in outcome.findings:
        typer.echo(f"{verdict}: {claim} ({measured})")
    typer.echo(f"outputs in {outcome.folder}: {REPORT_MD}, {REPORT_HTML}, {STATISTICS_FILE}, "
               f"{len(outcome.figures)} figures, transfer/ (sources and players.csv)")


def _summary(outcome: "ExperimentOutcome | ReplicatesOutcome") -> None:
    trials = outcome.trials
    typer.echo(f"{trials} trials ({outcome.ran} run, {outcome.skipped} already finished) in {outcome.seconds:.1f} s")
    typer.echo("verdicts: " + (", ".join(f"{n} {v}" for v, n in outcome.report.verdicts().items() if n) or "none"))
    if hasattr(outcome.report, "no_difference_agreements") and outcome.report.verdicts()["agrees"]:
        typer.echo(f"of the agreements, {outcome.report.no_difference_agreements()} are 'no significant difference "
                   f"found' (each says the smallest difference its test could detect: report.md)")
    if hasattr(outcome, "replicates"):
        typer.echo(f"outputs in {outcome.folder}: report.md, report.html, verdicts.csv (each finding per replicate), "
                   f"and seed-S/ per replicate (statistics.csv, bests.csv, report, figures, trials/)")
        return
    typer.echo(f"outputs in {outcome.folder}: statistics.csv, bests.csv, report.md, report.html, "
               f"{len(outcome.report.figures)} figures, trials/ (per-trial CSV, .rrd and best player)")
