"""Running an experiment: plan the trials, run the unfinished ones on an executor, write each finished
trial atomically to trials/<setting key>-<trial>.csv (with its rerun recording beside it), then
assemble statistics.csv, the figures and the report.

Resuming is running again into the same folder: finished trial files are read, not recomputed. The
folder's manifest.json records the options that fix the trials' results; another experiment with
the same options (say `all` after `selection`) reuses the trials they share. A trial on rcssserver
(hours at the chapter's size) also checkpoints its GA after every generation into
trials/<setting key>-<trial>.checkpoint and continues from there.
"""

from __future__ import annotations

import csv
import json
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Protocol

from app.experiment.presets import ExperimentOptions, Preset, Setting, presets, trial_seed
from app.experiment.table import ALGORITHM, PRESET, SEED, SETTING, TRIAL, StatisticsTable
from ga.config import GAConfig
from ga.evaluation import Evaluator
from ga.state import GA
from soccer.config import GameConfig

MANIFEST = "manifest.json"
TRIALS_FOLDER = "trials"
STATISTICS_FILE = "statistics.csv"


class ExperimentError(ValueError):
    """A folder or option problem, one line for the user."""


@dataclass(frozen=True)
class TrialSpec:
    """Everything a worker needs to run one trial, and nothing else (it is pickled to the worker)."""

    setting: Setting
    trial: int
    seed: int
    game: GameConfig
    checkpoint: Path | None = None  # where the GA checkpoints each generation (trials on rcssserver)

    @property
    def name(self) -> str:
        return f"{self.setting.key}-{self.trial}"

    @property
    def config(self) -> GAConfig:
        return self.setting.ga.model_copy(update={"seed": self.seed})


def run_trial(spec: TrialSpec, evaluate: Evaluator | None = None) -> list[dict[str, Any]]:
    """One whole GA (or random search) run; its statistics rows. Runs in a worker process or Ray task
    with SimpleSoccer games, or with `evaluate` (trials on rcssservers) in this process; continues from
    the spec's checkpoint when there is one."""
    from ga.algorithms import evolve, random_search, resume
    from soccer.config import SOCCER_VOCABULARY
    from soccer.evaluate import SimpleSoccerEvaluator

    evaluate = evaluate or SimpleSoccerEvaluator(spec.game, SOCCER_VOCABULARY)
    if spec.checkpoint is not None and spec.checkpoint.is_file():
        result = resume(spec.checkpoint, evaluate)
    else:
        run = evolve if spec.setting.algorithm == GA else random_search
        result = run(spec.config, evaluate, SOCCER_VOCABULARY, checkpoint=spec.checkpoint)
    return [stats.to_dict() for stats in result.history]


@dataclass(frozen=True)
class Membership:
    """One trial's place in a preset (a shared trial belongs to several)."""

    preset: str
    setting: str
    spec: TrialSpec


@dataclass(frozen=True)
class Plan:
    presets: list[Preset]
    memberships: list[Membership]

    @property
    def specs(self) -> list[TrialSpec]:
        """Each distinct trial once, in the order first met."""
        return list({m.spec.name: m.spec for m in self.memberships}.values())


def plan(preset_name: str, options: ExperimentOptions) -> Plan:
    chosen = presets(preset_name, options)
    game = options.game()
    memberships = [Membership(p.name, setting.label, TrialSpec(setting, trial, trial_seed(options.seed, setting, trial), game))
                   for p in chosen for setting in p.settings for trial in range(p.trials)]
    return Plan(chosen, memberships)


class TrialFolder:
    """trials/: one CSV (and one .rrd) per finished trial, each written atomically."""

    def __init__(self, root: Path):
        self.path = root / TRIALS_FOLDER
        self.path.mkdir(parents=True, exist_ok=True)

    def statistics(self, spec: TrialSpec) -> Path:
        return self.path / f"{spec.name}.csv"

    def recording(self, spec: TrialSpec) -> Path:
        return self.path / f"{spec.name}.rrd"

    def checkpoint(self, spec: TrialSpec) -> Path:
        return self.path / f"{spec.name}.checkpoint"

    def finished(self, spec: TrialSpec) -> bool:
        return self.statistics(spec).is_file()

    def write(self, spec: TrialSpec, rows: list[dict[str, Any]]) -> None:
        from app.recording import RunRecorder

        recorder = RunRecorder(self.recording(spec), history=rows)
        recorder.close()
        temporary = self.statistics(spec).with_suffix(".csv.tmp")
        with temporary.open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]), lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)
        temporary.replace(self.statistics(spec))  # the file exists only once whole: it marks the trial done
        self.checkpoint(spec).unlink(missing_ok=True)

    def read(self, spec: TrialSpec) -> list[dict[str, str]]:
        with self.statistics(spec).open(newline="") as handle:
            return list(csv.DictReader(handle))


class Progress(Protocol):
    def update(self, completed: int, total: int, *, skipped: int = 0) -> None: ...


@dataclass(frozen=True)
class ExperimentOutcome:
    folder: Path
    plan: Plan
    table: StatisticsTable
    report: Any  # app.experiment.report.Report
    ran: int  # trials computed now
    skipped: int  # trials found finished
    seconds: float


def prepare_folder(folder: Path, options: ExperimentOptions) -> None:
    """Create the folder, or check that the one there holds trials of the same options."""
    manifest = folder / MANIFEST
    identity = options.identity()
    if manifest.is_file():
        try:
            recorded = json.loads(manifest.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise ExperimentError(f"cannot read {manifest}: {exc}") from None
        if recorded != identity:
            differing = sorted(k for k in set(recorded) | set(identity) if recorded.get(k) != identity.get(k))
            raise ExperimentError(f"{folder} holds an experiment with other options ({', '.join(differing)}); "
                                  f"use another --out or the same options")
        return
    if folder.exists() and not folder.is_dir():
        raise ExperimentError(f"{folder} is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ExperimentError(f"cannot create {folder}: {exc.strerror or exc}") from None
    _write_atomically(manifest, json.dumps(identity, indent=2, sort_keys=True))


def run_trials(experiment: Plan, folder: Path, executor: Any, progress: Progress | None = None) -> tuple[int, int]:
    """Run every unfinished trial; (ran, skipped). Progress counts evaluations over the whole experiment."""
    trials = TrialFolder(folder)
    specs = experiment.specs
    pending = [spec if spec.setting.trial is None else replace(spec, checkpoint=trials.checkpoint(spec))
               for spec in specs if not trials.finished(spec)]
    # Longest first, so no long trial is left alone at the end while other cores idle.
    pending.sort(key=lambda spec: -spec.setting.evaluations)
    total = sum(spec.setting.evaluations for spec in specs)
    completed = total - sum(spec.setting.evaluations for spec in pending)
    skipped = len(specs) - len(pending)
    if progress is not None:
        progress.update(completed, total, skipped=skipped)
    for spec, rows in executor.map_unordered(run_trial, pending):
        trials.write(spec, rows)
        completed += spec.setting.evaluations
        if progress is not None:
            progress.update(completed, total, skipped=skipped)
    return len(pending), skipped


def assemble(experiment: Plan, folder: Path) -> StatisticsTable:
    """statistics.csv from the trial files: every generation of every trial of every preset."""
    trials = TrialFolder(folder)
    rows = []
    for membership in experiment.memberships:
        spec = membership.spec
        keys = {PRESET: membership.preset, SETTING: membership.setting, TRIAL: spec.trial, SEED: spec.seed,
                ALGORITHM: spec.setting.algorithm}
        rows.extend({**keys, **row} for row in trials.read(spec))
    table = StatisticsTable(rows)
    _write_atomically(folder / STATISTICS_FILE, table.to_csv())
    return StatisticsTable.read(folder / STATISTICS_FILE)  # typed as any reader of the CSV sees it


def run_experiment(preset_name: str, options: ExperimentOptions, folder: Path, executor: Any, *,
                   progress: Progress | None = None) -> ExperimentOutcome:
    """Plan, run what is unfinished, assemble statistics.csv, then write figures and the report."""
    from app.experiment.report import write_report

    started = time.perf_counter()
    experiment = plan(preset_name, options)
    prepare_folder(folder, options)
    with executor:
        ran, skipped = run_trials(experiment, folder, executor, progress)
    table = assemble(experiment, folder)
    report = write_report(table, experiment.presets, folder)
    return ExperimentOutcome(folder, experiment, table, report, ran, skipped, time.perf_counter() - started)


def _write_atomically(path: Path, text: str) -> None:
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text)
    temporary.replace(path)
