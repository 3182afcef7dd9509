"""Evolution runs in the background, for the API and the UI.

Each run is a thread driving `ga.algorithms.evolve` (or `resume`) with the SimpleSoccer evaluator or,
for env "rcss", with trials on real rcssservers (one at a time per server, in parallel over the servers).
After every generation the GA checkpoints into the run's folder; then its statistics and best
individual go to the store (one transaction), the folder's statistics.csv and best.rules are
updated, the run's rerun recording grows, and listeners hear about it. A run stopped, crashed or
cut off by the app ending keeps every finished generation and resumes from its checkpoint.
"""

from __future__ import annotations

import logging
import shutil
import threading
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Sequence

from pydantic import ValidationError

from app.environments import RCSS, SIMPLE, checked_env, checked_servers, checked_workers
from app.paths import RUNS_FOLDER
from app.recording import RunRecorder
from app.run_outputs import RunFolder, RunOutputs
from app.store import NotFound, RunRecord, RunStatus, Store
from fuzzy.parser import parse_rulebase
from fuzzy.printer import format_rulebase
from fuzzy.rule import Rulebase
from fuzzy.vocabulary import Vocabulary
from ga.algorithms import evolve, resume
from ga.checkpoint import load_checkpoint
from ga.codec import ChromosomeCodec
from ga.config import GAConfig
from ga.evaluation import Evaluator
from ga.individual import Individual
from ga.notation import format_compact
from ga.result import STOPPED
from soccer.config import GameConfig
from soccer.evaluate import SimpleSoccerEvaluator
from soccer.rcss.client import parse_server
from soccer.rcss.errors import RcssError
from soccer.rcss.trial import TrialConfig

log = logging.getLogger(__name__)

MAX_CONCURRENT_RUNS = 2  # the GA is CPU-bound; more runs than cores only slows every one of them
STOP_WAIT_SECONDS = 30.0
SAMPLED_PLAYERS = 12  # the best players of each generation that listeners (the population view) receive


class RunStateError(ValueError):
    """An action the run's state does not allow (resume a running run, start one too many...)."""


@dataclass(frozen=True)
class SampledPlayer:
    """One player of a finished generation, decoded and ready to play."""

    rulebase: Rulebase
    fitness: float


@dataclass(frozen=True)
class RunEvent:
    """What listeners hear: a finished generation (stats set, with `players`: its best SAMPLED_PLAYERS
    playable individuals, best first) or a status change."""

    run_id: int
    status: RunStatus
    stats: dict[str, Any] | None = None
    best_fitness: float | None = None
    players: tuple[SampledPlayer, ...] = ()


def sample_players(population: Sequence[Individual], codec: ChromosomeCodec,
                   count: int = SAMPLED_PLAYERS) -> tuple[SampledPlayer, ...]:
    """The `count` best individuals with at least one valid rule (an invalid ruleset is never played),
    best first; among equals, population order. Only these are decoded: the run is not slowed."""
    sampled = []
    for individual in sorted(population, key=lambda individual: individual.fitness):
        rulebase = codec.decode(individual.chromosome)
        if len(rulebase):
            sampled.append(SampledPlayer(rulebase, individual.fitness))
            if len(sampled) == count:
                break
    return tuple(sampled)


Listener = Callable[[RunEvent], None]


@dataclass(frozen=True)
class RunSettings:
    """Everything a run needs to be played (or resumed): the GA's parameters and where evaluations play:
    SimpleSoccer games (`game`) or, for env "rcss", trials (`trial`) on `servers`."""

    ga: GAConfig
    game: GameConfig
    env: str = SIMPLE
    servers: tuple[str, ...] = ()
    trial: TrialConfig = TrialConfig()

    @classmethod
    def build(
        cls,
        ga: GAConfig | dict[str, Any] | None = None,
        game: GameConfig | dict[str, Any] | None = None,
        env: str = SIMPLE,
        servers: Sequence[str] | None = None,
        trial: TrialConfig | dict[str, Any] | None = None,
    ) -> "RunSettings":
        """Validated settings (an rcss run without servers plays on the default one); ValueError naming
        each bad parameter."""
        ga = ga if isinstance(ga, GAConfig) else GAConfig.from_values(ga or {})
        try:
            game = game if isinstance(game, GameConfig) else GameConfig(**(game or {}))
        except ValidationError as exc:
            problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors())
            raise ValueError(f"invalid game parameters: {problems}") from None
        try:
            trial = trial if isinstance(trial, TrialConfig) else TrialConfig(**(trial or {}))
        except (TypeError, ValueError) as exc:
            raise ValueError(f"invalid trial parameters: {exc}") from None
        for where, check in (("env", lambda: checked_env(env)), ("servers", lambda: checked_servers(env, servers)),
                             ("ga.workers", lambda: checked_workers(env, ga.workers))):
            try:
                check()
            except ValueError as exc:
                raise ValueError(f"{where}: {exc}") from None
        return cls(ga, game, env, tuple(checked_servers(env, servers)), trial)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "RunSettings":
        """Settings as stored; runs from before env existed played SimpleSoccer."""
        return cls.build(data.get("ga"), data.get("game"), data.get("env", SIMPLE), data.get("servers"),
                         data.get("trial"))

    def to_dict(self) -> dict[str, Any]:
        settings = {"ga": self.ga.model_dump(), "game": self.game.model_dump(), "env": self.env}
        if self.env == RCSS:
            settings.update(servers=list(self.servers), trial=asdict(self.trial))
        return settings

    @contextmanager
    def evaluator(self) -> Iterator[Evaluator]:
        """The run's evaluator, closed (its server sessions left) when the run ends."""
        if self.env == SIMPLE:
            yield SimpleSoccerEvaluator(self.game)
            return
        from soccer.rcss.evaluate import RcssEvaluator

        with RcssEvaluator(self.servers, self.trial) as evaluate:
            yield evaluate


class StoreWriter:
    """GA callback writing each generation's statistics and best individual to the store."""

    def __init__(self, store: Store, run_id: int, codec: ChromosomeCodec, notify: Callable[[RunEvent], None]):
        self.store = store
        self.run_id = run_id
        self.codec = codec
        self.notify = notify

    def on_generation(self, stats: Any, population: list[Individual]) -> None:
        best = min(population, key=lambda individual: individual.fitness)
        self._record(stats.to_dict(), best, sample_players(population, self.codec))

    def restore(self, history: list[dict[str, Any]], best: Individual | None) -> None:
        """On resume: the generations the checkpoint holds but the store missed (the app ended
        between the GA's checkpoint and this callback), with the run's best so far."""
        stored = {row["generation"] for row in self.store.statistics(self.run_id)}
        for row in history:
            if row["generation"] not in stored and best is not None:
                self._record(row, best)

    def _record(self, stats: dict[str, Any], best: Individual, players: tuple[SampledPlayer, ...] = ()) -> None:
        rules = format_rulebase(self.codec.decode(best.chromosome), self.codec.vocabulary)
        compact = format_compact(best.chromosome, self.codec.vocabulary)
        self.store.record_generation(self.run_id, stats, rules, compact, best.fitness)
        self.notify(RunEvent(self.run_id, RunStatus.RUNNING, stats, best.fitness, players))


@dataclass
class _ActiveRun:
    thread: threading.Thread
    servers: frozenset[tuple[str, int]]  # the rcssservers it plays on: one run at a time on each
    stop: threading.Event = field(default_factory=threading.Event)
    stop_status: RunStatus = RunStatus.STOPPED  # what a stop means: the user's stop, or the app ending


class RunManager:
    """Starts, stops and resumes runs; each run's folder is `<data_dir>/runs/<id>`."""

    def __init__(self, store: Store, data_dir: str | Path, *, max_concurrent_runs: int = MAX_CONCURRENT_RUNS):
        self.store = store
        self.runs_dir = Path(data_dir) / RUNS_FOLDER
        self.max_concurrent_runs = max_concurrent_runs
        self._active: dict[int, _ActiveRun] = {}
        self._listeners: list[Listener] = []
        self._lock = threading.RLock()
        # Runs the previous app left 'running' were cut off: they resume from their checkpoints.
        self.interrupted_at_start = store.mark_interrupted()

    # ---- listeners ----------------------------------------------------------------------
    def add_listener(self, listener: Listener) -> Callable[[], None]:
        """Call `listener(event)` on every generation and status change (from the run's thread;
        keep it quick). Returns the function that removes it."""
        with self._lock:
            self._listeners.append(listener)

        def remove() -> None:
            with self._lock:
                if listener in self._listeners:
                    self._listeners.remove(listener)

        return remove

    def _notify(self, event: RunEvent) -> None:
        with self._lock:
            listeners = list(self._listeners)
        for listener in listeners:
            try:
                listener(event)
            except Exception:  # a broken listener (a closed browser tab) must not end the run
                log.exception("run listener failed")

    # ---- starting, stopping, resuming -----------------------------------------------------
    def start(
        self,
        name: str,
        ga: GAConfig | dict[str, Any] | None = None,
        game: GameConfig | dict[str, Any] | None = None,
        *,
        env: str = SIMPLE,
        servers: Sequence[str] | None = None,
        trial: TrialConfig | dict[str, Any] | None = None,
    ) -> RunRecord:
        """Start a new evolution. `ga`/`game`/`trial`: a GAConfig/GameConfig/TrialConfig or a dict of
        their fields (missing fields take the chapter's defaults). env "rcss" plays trials on `servers`
        (HOST:PORT; default 127.0.0.1:6000) with ga.workers 1. Invalid values raise ValueError before
        anything is saved; a server another run plays on raises RunStateError."""
        settings = RunSettings.build(ga, game, env, servers, trial)
        with self._lock:
            self._check_capacity()
            self._check_servers_free(settings)
            record = self.store.create_run(name, settings.to_dict(), self.runs_dir / "{id}")
            self._launch(record, settings, resume_run=False)
        return record

    def resume(self, run_id: int) -> RunRecord:
        """Continue a stopped, failed or interrupted run from its last checkpoint (from the start
        when it finished no generation)."""
        with self._lock:
            record = self.store.get_run(run_id)
            if run_id in self._active:
                raise RunStateError(f"run {run_id} is running")
            if not record.status.resumable:
                raise RunStateError(f"run {run_id} is {record.status}: there is nothing to resume")
            settings = RunSettings.from_dict(record.config)
            self._check_capacity()
            self._check_servers_free(settings)
            record = self.store.set_run_status(run_id, RunStatus.RUNNING)
            self._launch(record, settings, resume_run=True)
        return record

    def stop(self, run_id: int, *, wait: float = STOP_WAIT_SECONDS) -> RunRecord:
        """Ask a run to stop after its current generation and wait (up to `wait` s) for it."""
        record = self.store.get_run(run_id)
        active = self._active.get(run_id)
        if active is None:
            raise RunStateError(f"run {run_id} is not running (it is {record.status})")
        active.stop.set()
        active.thread.join(wait)
        return self.store.get_run(run_id)

    def shutdown(self, *, wait: float = STOP_WAIT_SECONDS) -> None:
        """Stop every run as 'interrupted' (resumable when the app starts again)."""
        with self._lock:
            active = list(self._active.values())
        for run in active:
            run.stop_status = RunStatus.INTERRUPTED
            run.stop.set()
        for run in active:
            run.thread.join(wait)

    def is_active(self, run_id: int) -> bool:
        return run_id in self._active

    def wait(self, run_id: int, timeout: float | None = None) -> RunRecord:
        """Block until the run's thread ends (or `timeout` s); its record."""
        active = self._active.get(run_id)
        if active is not None:
            active.thread.join(timeout)
        return self.store.get_run(run_id)

    def delete(self, run_id: int) -> None:
        """Forget a run that is not running: its rows, and its folder when that lies inside this
        manager's runs folder (a folder recorded elsewhere is never touched)."""
        with self._lock:  # not while it starts or resumes
            if run_id in self._active:
                raise RunStateError(f"run {run_id} is running; stop it first")
            folder = Path(self.store.get_run(run_id).folder)
            self.store.delete_run(run_id)
        if self._owns(folder):
            shutil.rmtree(folder, ignore_errors=True)  # the rows are gone: a leftover file harms no one

    def _owns(self, folder: Path) -> bool:
        """`folder` is a real folder strictly inside the runs folder (symbolic links resolved)."""
        try:
            root = self.runs_dir.resolve(strict=True)
            resolved = folder.resolve(strict=True)
        except (OSError, RuntimeError):
            return False
        return resolved != root and resolved.is_relative_to(root) and not folder.is_symlink() and resolved.is_dir()

    def best_rulebase(self, run_id: int) -> Rulebase:
        """The best individual so far (also while the run goes on), ready to play."""
        return parse_rulebase(self.store.best_individual(run_id).rules, Vocabulary.default())

    def _check_capacity(self) -> None:
        if len(self._active) >= self.max_concurrent_runs:
            raise RunStateError(
                f"{len(self._active)} runs are already running (the limit is {self.max_concurrent_runs}); stop one first"
            )

    def _check_servers_free(self, settings: RunSettings) -> None:
        wanted = {parse_server(server) for server in settings.servers}
        for run_id, active in self._active.items():
            if shared := wanted & active.servers:
                host, port = min(shared)
                raise RunStateError(f"run {run_id} is playing on rcssserver {host}:{port}; "
                                    "a server plays one run at a time")

    def _launch(self, record: RunRecord, settings: RunSettings, *, resume_run: bool) -> None:
        thread = threading.Thread(
            target=self._run, args=(record, settings, resume_run), name=f"run-{record.id}", daemon=True
        )
        self._active[record.id] = _ActiveRun(thread, frozenset(parse_server(server) for server in settings.servers))
        self._notify(RunEvent(record.id, RunStatus.RUNNING))
        thread.start()

    # ---- the run's thread -----------------------------------------------------------------
    def _run(self, record: RunRecord, settings: RunSettings, resume_run: bool) -> None:
        active = self._active[record.id]
        status, error = RunStatus.FINISHED, None
        try:
            if self._evolve(record, settings, active.stop, resume_run) == STOPPED:
                status = active.stop_status
        except Exception as exc:  # the run fails; the app and every finished generation stay
            if isinstance(exc, RcssError):  # the server's doing (gone, refused...): its message says it all
                log.warning("run %s failed: %s", record.id, exc)
            else:
                log.exception("run %s failed", record.id)
            status, error = RunStatus.FAILED, f"{type(exc).__name__}: {exc}"
        finally:
            with self._lock:
                self._active.pop(record.id, None)
            try:
                self.store.set_run_status(record.id, status, error)
            except NotFound:  # deleted meanwhile
                return
            self._notify(RunEvent(record.id, status))

    def _evolve(self, record: RunRecord, settings: RunSettings, stop: threading.Event, resume_run: bool) -> str:
        """Play the run to its end or until `stop`; the GA's stop reason."""
        folder = RunFolder(Path(record.folder))
        folder.path.mkdir(parents=True, exist_ok=True)
        vocabulary = Vocabulary.default()
        codec = ChromosomeCodec(vocabulary)
        writer = StoreWriter(self.store, record.id, codec, self._notify)
        from_checkpoint = resume_run and folder.checkpoint.is_file()
        if from_checkpoint:
            state = load_checkpoint(folder.checkpoint)
            history = [stats.to_dict() for stats in state.history]
            writer.restore(history, state.best)
            recorder = RunRecorder(folder.recording, history=history)
            outputs = RunOutputs(folder, state.vocabulary, history=history, best=state.best)
        else:
            recorder = RunRecorder(folder.recording)
            outputs = RunOutputs(folder, vocabulary)
        try:
            callbacks = (writer, outputs, recorder)
            with settings.evaluator() as evaluate:
                if from_checkpoint:
                    result = resume(folder.checkpoint, evaluate, callbacks=callbacks, stop=stop)
                else:
                    result = evolve(settings.ga, evaluate, vocabulary, callbacks=callbacks,
                                    checkpoint=folder.checkpoint, stop=stop)
        finally:
            recorder.close()
        return result.stop_reason
