"""Running an experiment: plan the trials, run the unfinished ones on an executor, write each finished
trial atomically to trials/<setting key>-<trial>.csv (with its rerun recording and its best player,
.best.json, beside it), then assemble statistics.csv, bests.csv, the figures and the report.

A trial's best player (the lowest running mean it saw: one noisy game, or the mean of the few games it
survived) is re-played on `replays` fresh starts when the trial ends: its true quality, in bests.csv
beside the fitness the GA saw. A trial of several restarts runs its GA that many times (seeds derived
from the trial's), its statistics one run after another, its best the best of their bests.

Every invocation appends a line to runs.jsonl (when it started, its wall time, the trials it ran and
skipped, the load average before and after): a resumed experiment's wall time is the sum of its lines.

Resuming is running again into the same folder: finished trial files are read, not recomputed. The
folder's manifest.json records the options that fix the trials' results; another experiment with
the same options (say `all` after `selection`) reuses the trials they share. A trial on rcssserver
(hours at the chapter's size), and a co-evolved trial of the matches preset, also checkpoints its GA after
every generation into trials/<setting key>-<trial>.checkpoint and continues from there.
"""

from __future__ import annotations

import csv
import json
import os
import time
from dataclasses import dataclass, replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Iterable, Protocol


from soccer_lab.app.experiment.presets import (RCSS_TRIAL, ROBOCUP, ExperimentOptions, Preset, Setting, presets,
                                               trial_seed)
from soccer_lab.app.experiment.table import ALGORITHM, PRESET, SEED, SETTING, TRIAL, BestsTable, StatisticsTable
from soccer_lab.app.experiment.trial_result import TrialResult, best_record, crowd_file, derived_seeds
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.evaluation import Evaluator
from soccer_lab.ga.state import GA
from soccer_lab.soccer.config import GameConfig

MANIFEST = "manifest.json"
TRIALS_FOLDER = "trials"
STATISTICS_FILE = "statistics.csv"
BESTS_FILE = "bests.csv"
RUNS_LOG = "runs.jsonl"
# options recorded since the first folders: a folder from before them holds trials all of whose other options match
OPTIONS_ADDED_SINCE = {"replays", RCSS_TRIAL}
RESTART_KEY, REPLAY_KEY = 1, 2  # SeedSequence spawn keys: a restart's seed, the replays' seeds


class ExperimentError(ValueError):
    """A folder or option problem, one line for the user."""


@dataclass(frozen=True)
class TrialSpec:
    """Everything a worker needs to run one trial, and nothing else (it is pickled to the worker)."""

    setting: Setting
    trial: int
    seed: int
    game: GameConfig  # the setting's games (games per evaluation included)
    replays: int = 1  # fresh starts the trial's best is re-played on
    checkpoint: Path | None = None  # where the GA checkpoints each generation (trials on rcssserver)

    @property
    def name(self) -> str:
        return f"{self.setting.key}-{self.trial}"

    @property
    def config(self) -> GAConfig:
        return self.setting.ga.model_copy(update={"seed": self.seed})

    def configs(self) -> list[GAConfig]:
        """One per restart: the trial's seed, then seeds derived from it."""
        seeds = [self.seed, *derived_seeds(self.seed, RESTART_KEY, self.setting.restarts - 1)]
        return [self.setting.ga.model_copy(update={"seed": seed}) for seed in seeds]

    def replay_seeds(self) -> list[int]:
        return derived_seeds(self.seed, REPLAY_KEY, self.replays)


def run_trial(spec: TrialSpec, evaluate: Evaluator | None = None) -> TrialResult:
    """One whole GA (or random search) run, or one per restart; then its best re-played. Runs in a
    worker process or Ray task with SimpleSoccer games, or with `evaluate` (trials on rcssservers) in
    this process; continues from the spec's checkpoint when there is one."""
    from soccer_lab.ga.algorithms import evolve, random_search, resume
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator

    if spec.setting.coevolve is not None:  # the matches preset's co-evolved trials
        from soccer_lab.app.experiment.matches import run_coevolution_trial

        return run_coevolution_trial(spec)

    evaluate = evaluate or SimpleSoccerEvaluator(spec.game, SOCCER_VOCABULARY)
    if spec.checkpoint is not None and spec.checkpoint.is_file():
        results = [resume(spec.checkpoint, evaluate)]
    else:
        run = evolve if spec.setting.algorithm == GA else random_search
        results = [run(config, evaluate, SOCCER_VOCABULARY, checkpoint=spec.checkpoint) for config in spec.configs()]
    rows = _one_after_another([[stats.to_dict() for stats in result.history] for result in results])
    best = min(results, key=lambda result: result.best.fitness)  # first of equals
    # replays are single games: on rcssserver the trials' own evaluator, else one game per start
    replay = evaluate if spec.setting.trial is not None else SimpleSoccerEvaluator(
        spec.game.model_copy(update={"games_per_evaluation": 1}), SOCCER_VOCABULARY)
    return TrialResult(rows, best_record(best, rows, replay, spec.replay_seeds()))


def _one_after_another(histories: list[list[dict[str, Any]]]) -> list[dict[str, Any]]:
    """Restarts' statistics as one run: generations, evaluations and wall time carry on."""
    rows: list[dict[str, Any]] = []
    for history in histories:
        before = rows[-1] if rows else {"generation": -1, "evaluations": 0, "wall_time": 0.0}
        rows += [{**row, "generation": before["generation"] + 1 + row["generation"],
                  "evaluations": before["evaluations"] + row["evaluations"],
                  "wall_time": before["wall_time"] + row["wall_time"]} for row in history]
    return rows


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
    memberships = [Membership(p.name, setting.label, TrialSpec(
        setting, trial, trial_seed(options.seed, setting, trial),
        game.model_copy(update={"games_per_evaluation": setting.games_per_evaluation}), options.replays))
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

    def best(self, spec: TrialSpec) -> Path:
        return self.path / f"{spec.name}.best.json"

    def finished(self, spec: TrialSpec) -> bool:
        return self.statistics(spec).is_file()

    def write(self, spec: TrialSpec, result: TrialResult) -> None:
        from soccer_lab.app.runs.recording import RunRecorder

        rows = result.rows
        recorder = RunRecorder(self.recording(spec), history=rows)
        recorder.close()
        _write_atomically(self.best(spec), json.dumps(result.best, indent=1))
        temporary = self.statistics(spec).with_suffix(".csv.tmp")
        with temporary.open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]), lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)
        temporary.replace(self.statistics(spec))  # the file exists only once whole: it marks the trial done
        self.checkpoint(spec).unlink(missing_ok=True)
        crowd_file(self.checkpoint(spec)).unlink(missing_ok=True)

    def read(self, spec: TrialSpec) -> list[dict[str, str]]:
        with self.statistics(spec).open(newline="") as handle:
            return list(csv.DictReader(handle))

    def read_best(self, spec: TrialSpec) -> dict[str, Any]:
        return json.loads(self.best(spec).read_text())


class Progress(Protocol):
    def update(self, completed: int, total: int, *, skipped: int = 0) -> None: ...


@dataclass(frozen=True)
class ExperimentOutcome:
    folder: Path
    plan: Plan
    table: StatisticsTable
    report: Any  # soccer_lab.app.experiment.report.Report
    ran: int  # trials computed now
    skipped: int  # trials found finished
    seconds: float

    @property
    def trials(self) -> int:
        return len(self.plan.specs)


def prepare_folder(folder: Path, identity: dict[str, Any]) -> None:
    """Create the folder, or check that the one there holds trials of the same options (their `identity`)."""
    manifest = folder / MANIFEST
    if manifest.is_file():
        try:
            recorded = json.loads(manifest.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise ExperimentError(f"cannot read {manifest}: {exc}") from None
        # an option added since the folder was made does not change the trials it holds
        identity = {k: v for k, v in identity.items() if k in recorded or k not in OPTIONS_ADDED_SINCE}
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
    """Run every unfinished trial; (ran, skipped). Progress counts games over the whole experiment."""
    return run_trials_in([(experiment, folder)], executor, progress)


def run_trials_in(experiments: Iterable[tuple[Plan, Path]], executor: Any,
                  progress: Progress | None = None) -> tuple[int, int]:
    """run_trials for several experiments (one per replicate) on one executor, so no core waits for the
    last trial of one before the next begins. They run one after another (an interrupted run leaves whole
    replicates), each's trials longest first, so no long trial is left alone at the end while other cores
    idle."""
    specs, pending, folders, order = [], [], {}, {}
    for index, (experiment, folder) in enumerate(experiments):
        trials = TrialFolder(folder)
        for spec in experiment.specs:
            specs.append(spec)
            if not trials.finished(spec):
                # long trials (on rcssserver, co-evolved) are checkpointed after every generation
                long = spec.setting.trial is not None or spec.setting.coevolve is not None
                pending.append(replace(spec, checkpoint=trials.checkpoint(spec)) if long else spec)
                folders[spec.name, spec.seed] = trials  # a trial's seed differs between replicates
                order[spec.name, spec.seed] = index
    pending.sort(key=lambda spec: (order[spec.name, spec.seed], -spec.setting.games))
    total = sum(spec.setting.games for spec in specs)
    completed = total - sum(spec.setting.games for spec in pending)
    skipped = len(specs) - len(pending)
    if progress is not None:
        progress.update(completed, total, skipped=skipped)
    for spec, result in executor.map_unordered(run_trial, pending):
        folders[spec.name, spec.seed].write(spec, result)
        completed += spec.setting.games
        if progress is not None:
            progress.update(completed, total, skipped=skipped)
    return len(pending), skipped


def assemble(experiment: Plan, folder: Path) -> StatisticsTable:
    """statistics.csv from the trial files: every generation of every trial of every preset."""
    trials = TrialFolder(folder)
    rows = []
    for membership in experiment.memberships:
        rows.extend({**_keys(membership), **row} for row in trials.read(membership.spec))
    table = StatisticsTable(rows)
    _write_atomically(folder / STATISTICS_FILE, table.to_csv())
    return StatisticsTable.read(folder / STATISTICS_FILE)  # typed as any reader of the CSV sees it


def assemble_bests(experiment: Plan, folder: Path) -> BestsTable:
    """bests.csv from the trial files: each trial's best player, the fitness the GA saw, its replays."""
    trials = TrialFolder(folder)
    table = BestsTable([{**_keys(m), **trials.read_best(m.spec)} for m in experiment.memberships
                        if trials.best(m.spec).is_file()])  # none for trials from before bests were kept
    _write_atomically(folder / BESTS_FILE, table.to_csv())
    return BestsTable.read(folder / BESTS_FILE)


def _keys(membership: Membership) -> dict[str, Any]:
    spec = membership.spec
    return {PRESET: membership.preset, SETTING: membership.setting, TRIAL: spec.trial, SEED: spec.seed,
            ALGORITHM: spec.setting.algorithm}


def run_experiment(preset_name: str, options: ExperimentOptions, folder: Path, executor: Any, *,
                   progress: Progress | None = None) -> ExperimentOutcome:
    """Plan, run what is unfinished, assemble statistics.csv, then write figures and the report."""
    from soccer_lab.app.experiment.report import write_report

    clock = RunClock()
    experiment = plan(preset_name, options)
    prepare_folder(folder, options.identity(on_servers=preset_name == ROBOCUP))
    with executor:
        ran, skipped = run_trials(experiment, folder, executor, progress)
    table = assemble(experiment, folder)
    report = write_report(table, experiment.presets, folder, assemble_bests(experiment, folder))
    seconds = clock.log(folder, preset_name, options, [options.seed], ran, skipped)
    return ExperimentOutcome(folder, experiment, table, report, ran, skipped, seconds)


class RunClock:
    """One invocation's wall time and the machine's load around it, logged to the folder's runs.jsonl."""

    def __init__(self) -> None:
        self.started = datetime.now(timezone.utc).isoformat(timespec="seconds")
        self.load_before = [round(x, 2) for x in os.getloadavg()]
        self.start = time.perf_counter()

    def log(self, folder: Path, preset_name: str, options: ExperimentOptions, seeds: list[int], ran: int,
            skipped: int) -> float:
        seconds = time.perf_counter() - self.start
        entry = {"preset": preset_name, "seeds": seeds, "trials": options.trials,  # None: the chapter's
                 "started": self.started, "seconds": round(seconds, 1),
                 "ran": ran, "skipped": skipped, "load_average_before": self.load_before,
                 "load_average_after": [round(x, 2) for x in os.getloadavg()], "cores": os.cpu_count()}
        with (folder / RUNS_LOG).open("a") as handle:
            handle.write(json.dumps(entry) + "\n")
        return seconds


def read_runs(folder: Path) -> list[dict[str, Any]]:
    """runs.jsonl's entries, oldest first (none for a folder from before it was kept)."""
    log = folder / RUNS_LOG
    return [json.loads(line) for line in log.read_text().splitlines() if line.strip()] if log.is_file() else []


def _write_atomically(path: Path, text: str) -> None:
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text)
    temporary.replace(path)
