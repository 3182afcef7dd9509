"""`soccer-lab experiment PRESET`: the chapter's study (its section 6) with one command: the SimpleSoccer
presets on local processes or Ray, `robocup` on rcssservers."""

from __future__ import annotations

from contextlib import ExitStack
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from app.cli.common import fail
from app.cli.play import (RcssserverOption, ServerOption, ServersOption, config_from_options, option_help,
                          rcss_addresses)
from app.experiment.executors import EXECUTOR_NAMES, LOCAL, ExecutorError, RcssExecutor, make_executor
from app.experiment.presets import (CHAPTER_GENERATIONS, CHOICES, DEFAULT_TRIALS, INITIAL_TRIALS, LONG_GENERATIONS,
                                    ROBOCUP, ExperimentOptions)
from soccer.config import SKILL_SET_NAMES
from soccer.rcss.errors import RcssError

if TYPE_CHECKING:  # the runner (the GA, the report's statistics and figures) is imported when an experiment runs
    from app.experiment.runner import ExperimentOutcome

DEFAULT_OUT_FOLDER = "experiments"


def experiment_command(
    preset: Annotated[str, typer.Argument(help=f"One of: {', '.join(CHOICES)}.", show_default=False)],
    trials: Annotated[Optional[int], typer.Option(
        "--trials", help=f"Trials per setting. (default: the chapter's, {DEFAULT_TRIALS}; {INITIAL_TRIALS} for "
        f"initial and {ROBOCUP})", show_default=False)] = None,
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
    skills: Annotated[Optional[str], typer.Option(
        "--skills", help=option_help(ExperimentOptions, "skills", f"Skill set: {', '.join(SKILL_SET_NAMES)}."),
        show_default=False)] = None,
    noise: Annotated[Optional[bool], typer.Option(
        "--noise/--no-noise", help=option_help(ExperimentOptions, "noise", "rcssserver-like movement noise."),
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
        "--out", help="Output folder; running again into it resumes. (default: experiments/PRESET-seedN)",
        show_default=False)] = None,
    workers: Annotated[Optional[int], typer.Option(
        "--workers", min=1, help=f"Trials run at once. (default: all cores; not for {ROBOCUP})",
        show_default=False)] = None,
    executor: Annotated[Optional[str], typer.Option(
        "--executor", help=f"Where trials run: {' or '.join(EXECUTOR_NAMES)}. (default: {LOCAL}; {ROBOCUP} plays "
        "on rcssservers)", show_default=False)] = None,
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
    """Reproduce the chapter's experiments: statistics.csv, figures, report.md and report.html."""
    if preset not in CHOICES:
        fail(f"unknown preset {preset!r}; choose one of {', '.join(CHOICES)}")
    options: ExperimentOptions = config_from_options(ExperimentOptions, {
        "trials": trials, "population": population, "generations": generations, "max_ticks": max_ticks,
        "seed": seed, "skills": skills, "noise": noise, "count_touches": count_touches,
        "roulette_weighting": roulette_weighting})
    folder = out or Path(DEFAULT_OUT_FOLDER) / f"{preset}-seed{options.seed}"
    _check_where_trials_run(preset, {"--server": server, "--rcssserver": rcssserver, "--servers": servers},
                            {"--executor": executor, "--workers": workers, "--address": address, "--noise": noise,
                             "--count-touches": count_touches})
    from app.experiment.runner import ExperimentError, run_experiment

    try:
        with ExitStack() as stack:
            if preset == ROBOCUP:
                runner = RcssExecutor(stack.enter_context(rcss_addresses(server, rcssserver, servers)))
            else:
                runner = make_executor(executor or LOCAL, workers=workers, address=address)
            progress = stack.enter_context(ExperimentProgress(preset))
            outcome = run_experiment(preset, options, folder, runner, progress=progress)
    except (ExecutorError, ExperimentError) as exc:
        fail(str(exc))
    except RcssError as exc:
        fail(f"{exc}; finished trials and generations are kept: run the same command again to resume")
    except KeyboardInterrupt:
        kept = "finished trials (and the generations of the trial under way)" if preset == ROBOCUP else "finished trials"
        typer.echo(f"\ninterrupted; {kept} are kept: run the same command again to resume", err=True)
        raise typer.Exit(130)
    if library:
        _record(preset, options, outcome, data_dir)
    _summary(outcome)


def _check_where_trials_run(preset: str, rcss_options: dict[str, object], local_options: dict[str, object]) -> None:
    """robocup plays on rcssservers (the rcss options), every other preset SimpleSoccer on the executor (the
    local options)."""
    given = [option for option, value in (local_options if preset == ROBOCUP else rcss_options).items()
             if value is not None]
    if given and preset == ROBOCUP:
        fail(f"{', '.join(given)}: {ROBOCUP} plays its trials on rcssservers (--servers sets how many, the noise and "
             "the count of kicks are the server's), not SimpleSoccer on an executor")
    if given:
        fail(f"{', '.join(given)}: for the {ROBOCUP} preset only (the others play SimpleSoccer)")


class ExperimentProgress:
    """One bar for the whole experiment, counted in evaluations (trials differ in size)."""

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


def _record(preset: str, options: ExperimentOptions, outcome: "ExperimentOutcome", data_dir: Path | None) -> None:
    from app.experiment.library import library_summary
    from app.paths import DATABASE_FILE, default_data_dir
    from app.store import Store, StoreError

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


def _summary(outcome: "ExperimentOutcome") -> None:
    trials = len(outcome.plan.specs)
    typer.echo(f"{trials} trials ({outcome.ran} run, {outcome.skipped} already finished) in {outcome.seconds:.1f} s")
    typer.echo("verdicts: " + ", ".join(f"{n} {v}" for v, n in outcome.report.verdicts().items() if n))
    typer.echo(f"outputs in {outcome.folder}: statistics.csv, report.md, report.html, "
               f"{len(outcome.report.figures)} figures, trials/ (per-trial CSV and .rrd)")
