"""Evolution runs in the background, for the API and the UI.

Each run is a thread playing one `soccer_lab.app.runs.run.Run` (the GA or random search, on SimpleSoccer or on real
rcssservers: the same orchestrator as the command line) in its folder `<data_dir>/runs/<id>`. After
every generation the run's folder is brought up to date (checkpoint, statistics.csv, best rules, the
rerun recording); then its statistics and best individual go to the store (one transaction) and
listeners hear about it; within a generation they hear its progress after every chunk of evaluations.
A stop is obeyed between two chunks (about a second), abandoning the generation in progress. A run
stopped, crashed or cut off by the app ending keeps every finished generation and resumes from its
checkpoint, finishing as the uninterrupted run would.

In classroom mode (`queue_runs`) a run started while every core is busy is queued (app/runs/queue.py:
round-robin across pupils, one run per pupil at a time) and starts when a core comes free; outside it the
desk user is told at once, since they can stop one of their own runs. A run started without a seed draws a
fresh one (soccer_lab.ga.config.fresh_seed), recorded with its settings.
"""

from __future__ import annotations

import logging
import shutil
import threading
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable, Sequence

from soccer_lab.app.runs.environments import SIMPLE
from soccer_lab.app.runs.listeners import Listeners
from soccer_lab.app.paths import RUNS_FOLDER
from soccer_lab.app.runs.run import Run, RunSettings
from soccer_lab.app.runs.queue import QueuedRun, QueuePlace, RunPace, RunQueue, budget_ticks
from soccer_lab.app.runs.outputs import generation_best, lineage_line
from soccer_lab.app.store import NotFound, RunRecord, RunStatus, Store
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig, fresh_seed
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.notation import format_compact
from soccer_lab.ga.result import STOPPED
from soccer_lab.ga.state import GA
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.rcss.client import parse_server
from soccer_lab.soccer.rcss.errors import RcssError
from soccer_lab.soccer.rcss.trial import TrialConfig

log = logging.getLogger(__name__)

MAX_CONCURRENT_RUNS = 2  # the GA is CPU-bound; more runs than cores only slows every one of them
# A run obeys a stop between two chunks of evaluations (well under a second for SimpleSoccer, one trial for
# rcssserver): waiting longer only delays the answer of a run that is stuck
STOP_WAIT_SECONDS = 10.0
SHUTDOWN_WAIT_SECONDS = 2.0  # serve exits within 3 s of Ctrl+C or SIGTERM; runs are marked interrupted first
SAMPLED_PLAYERS = 12  # the best players of each generation that listeners (the population view) receive
QUEUE_POLL_SECONDS = 0.05  # how often wait() looks whether a queued run has started


class RunStateError(ValueError):
    """An action the run's state does not allow (resume a running run, start one too many...)."""


@dataclass(frozen=True)
class SampledPlayer:
    """One player of a finished generation, decoded and ready to play."""

    rulebase: Rulebase
    fitness: float
    index: int = 0  # its place in its generation (ga/lineage.py): where its family tree starts


@dataclass(frozen=True)
class GenerationProgress:
    """How far the generation being evaluated is: `evaluated` of its `population` individuals."""

    generation: int
    evaluated: int
    population: int


@dataclass(frozen=True)
class RunEvent:
    """What listeners hear: a finished generation (stats set, with `players`: its best SAMPLED_PLAYERS
    playable individuals, best first), the progress within a generation (`progress` set) or a status change."""

    run_id: int
    status: RunStatus
    stats: dict[str, Any] | None = None
    best_fitness: float | None = None
    players: tuple[SampledPlayer, ...] = ()
    progress: GenerationProgress | None = None


def sample_players(population: Sequence[Individual], codec: ChromosomeCodec,
                   count: int = SAMPLED_PLAYERS) -> tuple[SampledPlayer, ...]:
    """The `count` best individuals with at least one valid rule (an invalid ruleset is never played),
    best first; among equals, population order. Only these are decoded: the run is not slowed."""
    sampled = []
    for index in sorted(range(len(population)), key=lambda i: population[i].fitness):
        rulebase = codec.decode(population[index].chromosome)
        if len(rulebase):
            sampled.append(SampledPlayer(rulebase, population[index].fitness, index))
            if len(sampled) == count:
                break
    return tuple(sampled)


Listener = Callable[[RunEvent], None]


class StoreWriter:
    """GA callback writing each generation's statistics, best individual and lineage record to the store."""

    def __init__(self, store: Store, run_id: int, codec: ChromosomeCodec, notify: Callable[[RunEvent], None]):
        self.store = store
        self.run_id = run_id
        self.codec = codec
        self.notify = notify
        self.opponents: list[str] | None = None  # whom the generation under way is scored against (co-evolution)

    def on_opponents(self, generation: int, members: list[Any]) -> None:
        self.opponents = [member.label for member in members]

    def on_generation(self, stats: Any, population: list[Individual]) -> None:
        self._record(stats.to_dict(), generation_best(population), sample_players(population, self.codec),
                     lineage_line(stats.generation, population, self.opponents))

    def restore(self, history: list[dict[str, Any]], best: Individual | None, lineage: dict[int, str]) -> None:
        """On resume: the generations the checkpoint holds but the store missed (the app ended
        between the GA's checkpoint and this callback), with the run's best so far and their lineage
        records (lineage.jsonl's lines, by generation)."""
        stored = {row["generation"] for row in self.store.statistics(self.run_id)}
        for row in history:
            if row["generation"] not in stored and best is not None:
                self._record(row, best, lineage=lineage.get(row["generation"]))

    def _record(self, stats: dict[str, Any], best: Individual, players: tuple[SampledPlayer, ...] = (),
                lineage: str | None = None) -> None:
        rules = format_rulebase(self.codec.decode(best.chromosome), self.codec.vocabulary)
        compact = format_compact(best.chromosome, self.codec.vocabulary)
        self.store.record_generation(self.run_id, stats, rules, compact, best.fitness, lineage)
        self.notify(RunEvent(self.run_id, RunStatus.RUNNING, stats, best.fitness, players))


class ProgressWatcher:
    """GA callback keeping the progress within the generation being evaluated, and telling listeners."""

    def __init__(self, run_id: int, generation: int, notify: Callable[[RunEvent], None]):
        self.run_id = run_id
        self.notify = notify
        self.first = generation  # a resumed run's first generation this time
        self.current = GenerationProgress(generation, 0, 0)

    def played(self) -> int:
        """Generations finished since the run (re)started."""
        return self.current.generation - self.first

    def on_progress(self, evaluated: int, population: int) -> None:
        self.current = GenerationProgress(self.current.generation, evaluated, population)
        self.notify(RunEvent(self.run_id, RunStatus.RUNNING, progress=self.current))

    def on_generation(self, stats: Any, population: Any = None) -> None:
        self.current = GenerationProgress(stats.generation + 1, 0, 0)


@dataclass
class _ActiveRun:
    thread: threading.Thread
    servers: frozenset[tuple[str, int]]  # the rcssservers it plays on: one run at a time on each
    owner: int | None = None  # the student who started it (classroom mode)
    stop: threading.Event = field(default_factory=threading.Event)
    stop_status: RunStatus = RunStatus.STOPPED  # what a stop means: the user's stop, or the app ending
    watcher: ProgressWatcher | None = None
    started: float = field(default_factory=time.monotonic)
    expected_seconds: float = 0.0  # the queue's estimate of its length, for the places of the runs waiting
    generations: int = 1  # it may play (its max_generations)
    budget: int = 0  # the game-ticks it may play (app/runs/queue.py)

    def remaining(self, now: float) -> float:
        """Seconds it still needs: from its own pace once it has finished a generation, else the estimate."""
        elapsed = now - self.started
        played = self.watcher.played() if self.watcher is not None else 0
        if played <= 0:
            return max(0.0, self.expected_seconds - elapsed)
        return elapsed * max(0, self.generations - self.watcher.current.generation) / played

    def seconds_per_tick(self, now: float) -> float | None:
        """Its pace so far (None before its first generation): the load of the machine as it is now."""
        played = self.watcher.played() if self.watcher is not None else 0
        return (now - self.started) / (self.budget * played / self.generations) if played > 0 else None


class RunManager:
    """Starts, stops and resumes runs; each run's folder is `<data_dir>/runs/<id>`."""

    def __init__(self, store: Store, data_dir: str | Path, *, max_concurrent_runs: int = MAX_CONCURRENT_RUNS,
                 rcssserver: str | Path | None = None, queue_runs: bool = False,
                 new_seed: Callable[[], int] = fresh_seed):
        """rcssserver: the executable of the servers rcss runs start (default $RCSSSERVER, else PATH): a
        setting of the app, never of a request. queue_runs: queue the runs that find every core busy
        (classroom mode) instead of refusing them. new_seed: the seed of a run started without one."""
        self.store = store
        self.runs_dir = Path(data_dir) / RUNS_FOLDER
        self.max_concurrent_runs = max_concurrent_runs
        self.rcssserver = str(rcssserver) if rcssserver is not None else None
        self._active: dict[int, _ActiveRun] = {}
        # every run thread until its very end: one that has left _active still writes its end status
        self._threads: set[threading.Thread] = set()
        self.queue_runs = queue_runs
        self.new_seed = new_seed
        self._queue = RunQueue()
        self.pace = RunPace()
        self._closing = False  # the app is ending: nothing queued starts any more
        # Where SimpleSoccer runs play their games: None, in the run's thread (and its workers); else a
        # function giving the evaluator that plays them elsewhere (app/runs/games.py: the class's game
        # processes, or Ray), one worker each
        self.remote_games: Callable[[Any], Any] | None = None
        self._listeners: Listeners[RunEvent] = Listeners("run")
        self._lock = threading.RLock()
        # Classroom mode: a student's run's settings as it may play them (app/web/classroom/settings.py), or
        # RunStateError saying which bound they pass
        self.student_bounds: Callable[[RunSettings], RunSettings] | None = None
        # Runs the previous app left 'running' were cut off: they resume from their checkpoints.
        self.interrupted_at_start = store.mark_interrupted()

    # ---- listeners ----------------------------------------------------------------------
    def add_listener(self, listener: Listener) -> Callable[[], None]:
        """Call `listener(event)` on every generation and status change (from the run's thread;
        keep it quick). Returns the function that removes it."""
        return self._listeners.add(listener)

    def _notify(self, event: RunEvent) -> None:
        self._listeners.notify(event)

    # ---- starting, stopping, resuming -----------------------------------------------------
    def start(
        self,
        name: str | None = None,
        ga: GAConfig | dict[str, Any] | None = None,
        game: GameConfig | dict[str, Any] | None = None,
        *,
        algorithm: str = GA,
        env: str = SIMPLE,
        servers: Sequence[str] | None = None,
        trial: TrialConfig | dict[str, Any] | None = None,
        start_servers: int | None = None,
        owner: int | None = None,
        opponent: str | None = None,
        coevolve: Any = None,
    ) -> RunRecord:
        """Start a new run of `algorithm` ("ga" or "random-search"), named `name` or, when None, by its
        settings. `ga`/`game`/`trial`: a GAConfig/GameConfig/TrialConfig or a dict of their fields (missing
        fields take the chapter's defaults). env "rcss" plays trials, with ga.workers 1, on `servers`
        (HOST:PORT, servers the user runs) or on `start_servers` (default 1) servers the run starts
        itself. Invalid values raise ValueError before anything is saved; a server another run plays on, or
        no rcssserver to start, raises RunStateError. `owner`: the student starting it (classroom mode), whose
        run is bounded by `student_bounds` and who runs one at a time. `opponent` (rule text): every evaluation a
        match against that player; `coevolve` (CoevolutionConfig or its fields): matches against a hall of fame
        founded by the opponent or the built-in demo."""
        settings = RunSettings.build(self._seeded(ga), game, env, servers, trial, algorithm, start_servers,
                                     opponent, coevolve)
        with self._lock:
            settings = self._placed(self._with_executable(self._check_student(owner, settings)))
            queued = self._must_queue()
            self._check_servers_free(settings)
            record = self.store.create_run(name if name is not None else settings.default_name(),
                                           settings.to_dict(), self.runs_dir / "{id}", owner=owner,
                                           status=RunStatus.QUEUED if queued else RunStatus.RUNNING)
            self._enqueue(record, settings, False) if queued else self._launch(record, settings, resume_run=False)
        return record

    def resume(self, run_id: int) -> RunRecord:
        """Continue a stopped, failed or interrupted run from its last checkpoint (from the start
        when it finished no generation)."""
        with self._lock:
            record = self.store.get_run(run_id)
            if run_id in self._active or run_id in self._queue:
                raise RunStateError(f"run {run_id} is {record.status}")
            if not record.status.resumable:
                raise RunStateError(f"run {run_id} is {record.status}: there is nothing to resume")
            settings = RunSettings.from_dict(record.config)
            settings = self._placed(self._with_executable(self._check_student(record.owner, settings)))
            queued = self._must_queue()
            self._check_servers_free(settings)
            record = self.store.set_run_status(run_id, RunStatus.QUEUED if queued else RunStatus.RUNNING)
            self._enqueue(record, settings, True) if queued else self._launch(record, settings, resume_run=True)
        return record

    def stop(self, run_id: int, *, wait: float = STOP_WAIT_SECONDS) -> RunRecord:
        """Ask a run to stop (it abandons the generation in progress between two chunks of evaluations) and
        wait (up to `wait` s) for it. A queued run is taken out of the queue (stopped: resuming it queues it
        again)."""
        record = self.store.get_run(run_id)
        with self._lock:
            if self._queue.remove(run_id) is not None:
                return self._left_queue(run_id, RunStatus.STOPPED)
        active = self._active.get(run_id)
        if active is None:
            raise RunStateError(f"run {run_id} is not running (it is {record.status})")
        active.stop.set()
        active.thread.join(wait)
        return self.store.get_run(run_id)

    def interrupt_all(self) -> None:
        """Ask every run to stop as 'interrupted' (resumable when the app starts again), marked so in the
        store at once: the app is ending. Returns without waiting (safe in a signal handler's thread)."""
        with self._lock:
            self._closing = True
            active = dict(self._active)
            waiting = self._queue.clear()
        for queued in waiting:
            self._left_queue(queued.record.id, RunStatus.INTERRUPTED)
        for run_id, run in active.items():
            run.stop_status = RunStatus.INTERRUPTED
            run.stop.set()
            try:
                self.store.set_run_status(run_id, RunStatus.INTERRUPTED)
            except NotFound:
                pass

    def shutdown(self, *, wait: float = SHUTDOWN_WAIT_SECONDS) -> None:
        """interrupt_all, then give the runs' threads `wait` s in all to end (they are daemon threads: one
        still busy ends with the process, its last checkpoint kept)."""
        self.interrupt_all()
        deadline = time.monotonic() + wait
        with self._lock:
            threads = list(self._threads)
        for thread in threads:
            thread.join(max(0.0, deadline - time.monotonic()))

    def progress(self, run_id: int) -> GenerationProgress | None:
        """How far a running run's current generation is; None when it is not running."""
        active = self._active.get(run_id)
        return active.watcher.current if active is not None and active.watcher is not None else None

    def is_active(self, run_id: int) -> bool:
        return run_id in self._active

    def is_pending(self, run_id: int) -> bool:
        """Running or queued: a run Stop applies to."""
        return run_id in self._active or self._is_queued(run_id)

    def _is_queued(self, run_id: int) -> bool:
        with self._lock:  # the queue changes in the runs' threads
            return run_id in self._queue

    def queue_place(self, run_id: int) -> QueuePlace | None:
        """A queued run's place in the queue with its estimates; None when it is not queued."""
        with self._lock:
            if run_id not in self._queue:
                return None
            now = time.monotonic()
            busy_for = [run.remaining(now) for run in self._active.values()]
            return self._queue.places(busy_for, self.max_concurrent_runs, self._live_pace(now))[run_id]

    def _live_pace(self, now: float) -> RunPace:
        """The running runs' own pace once they have finished a generation (the machine's load now: a class's
        first estimates came from a quiet machine's pace and were minutes short on a busy one), else the
        finished runs'."""
        live = [pace for run in self._active.values() if (pace := run.seconds_per_tick(now)) is not None]
        return RunPace(sum(live) / len(live)) if live else self.pace

    def wait(self, run_id: int, timeout: float | None = None) -> RunRecord:
        """Block until the run's thread ends (or `timeout` s), a queued run's included; its record."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while self._is_queued(run_id) and (deadline is None or time.monotonic() < deadline):
            time.sleep(QUEUE_POLL_SECONDS)
        active = self._active.get(run_id)
        if active is not None:
            active.thread.join(None if deadline is None else max(0.0, deadline - time.monotonic()))
        # a run that has just left the active runs writes its end status a moment later
        while (record := self.store.get_run(run_id)).status.pending and not self.is_pending(run_id) \
                and (deadline is None or time.monotonic() < deadline):
            time.sleep(QUEUE_POLL_SECONDS)
        return record

    def delete(self, run_id: int) -> None:
        """Forget a run that is not running: its rows, and its folder when that lies inside this
        manager's runs folder (a folder recorded elsewhere is never touched)."""
        with self._lock:  # not while it starts or resumes
            if self.is_pending(run_id):
                raise RunStateError(f"run {run_id} is {self.store.get_run(run_id).status}; stop it first")
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

    def pitch_game(self, run_id: int) -> GameConfig:
        """The SimpleSoccer game the UI plays a run's players in (RunSettings.pitch_game). ValueError when
        the stored settings no longer validate."""
        return RunSettings.from_dict(self.store.get_run(run_id).config).pitch_game

    def best_rulebase(self, run_id: int) -> Rulebase:
        """The best individual so far (also while the run goes on), ready to play."""
        return parse_rulebase(self.store.best_individual(run_id).rules, SOCCER_VOCABULARY)

    def _seeded(self, ga: GAConfig | dict[str, Any] | None) -> GAConfig | dict[str, Any]:
        """`ga` with a fresh seed when it names none (a GAConfig names one when it was given)."""
        if isinstance(ga, GAConfig):
            return ga if "seed" in ga.model_fields_set else ga.model_copy(update={"seed": self.new_seed()})
        ga = dict(ga or {})
        return ga if ga.get("seed") is not None else {**ga, "seed": self.new_seed()}

    def _check_student(self, owner: int | None, settings: RunSettings) -> RunSettings:
        if owner is None:
            return settings
        self._check_one_each(owner)
        return settings if self.student_bounds is None else self.student_bounds(settings)

    def _check_one_each(self, owner: int) -> None:
        """A pupil's second Start while their run waits or plays is refused, saying where that run is: it
        keeps its place (replacing it would send an impatient double press to the back of the queue)."""
        for run_id, active in self._active.items():
            if active.owner == owner:
                raise RunStateError(f"your run #{run_id} is running: stop it first to start another "
                                    "(one run at a time each)")
        for queued in self._queue:
            if queued.owner == owner:
                run_id = queued.record.id
                raise RunStateError(f"your run #{run_id} is queued ({describe_place(self.queue_place(run_id))}): "
                                    "stop it first to start another (one run at a time each)")

    def _must_queue(self) -> bool:
        """Whether a run must wait for a core: every core busy (or runs already waiting, so that none jumps
        the queue). Outside classroom mode RunStateError instead: the desk user stops one of theirs."""
        if len(self._active) < self.max_concurrent_runs and not len(self._queue):
            return False
        if self.queue_runs:
            return True
        raise RunStateError(
            f"{len(self._active)} runs are already running (the limit is {self.max_concurrent_runs}); stop one first"
        )

    def _enqueue(self, record: RunRecord, settings: RunSettings, resume_run: bool) -> None:
        self._queue.push(QueuedRun(record, settings, resume_run))
        self._notify(RunEvent(record.id, RunStatus.QUEUED))

    def _left_queue(self, run_id: int, status: RunStatus) -> RunRecord:
        """A queued run taken out of the queue before it started (stopped, or the app ending)."""
        record = self.store.set_run_status(run_id, status)  # a queued run cannot be deleted: it is there
        self._notify(RunEvent(run_id, status))
        self._tell_places()
        return record

    def _start_queued(self) -> None:
        """Start queued runs, in turn, while a core is free (after a run ends)."""
        with self._lock:
            started = False
            while not self._closing and len(self._active) < self.max_concurrent_runs:
                queued = self._queue.pop()
                if queued is None:
                    break
                self._start_one(queued)
                started = True
        if started:
            self._tell_places()

    def _start_one(self, queued: QueuedRun) -> None:
        run_id = queued.record.id
        try:
            self._check_servers_free(queued.settings)
            record = self.store.set_run_status(run_id, RunStatus.RUNNING)
        except NotFound:  # deleted meanwhile
            return
        except RunStateError as exc:  # a teacher's rcssserver run whose server another run took meanwhile
            self.store.set_run_status(run_id, RunStatus.FAILED, str(exc))
            self._notify(RunEvent(run_id, RunStatus.FAILED))
            return
        self._launch(record, queued.settings, resume_run=queued.resume_run)

    def _tell_places(self) -> None:
        """Every queued run moved up: its listeners hear it (the pupil's tab shows the new place)."""
        with self._lock:
            waiting = [queued.record.id for queued in self._queue]
        for run_id in waiting:
            self._notify(RunEvent(run_id, RunStatus.QUEUED))

    def _with_executable(self, settings: RunSettings) -> RunSettings:
        """Settings that start servers get the app's rcssserver, checked now (RunStateError when there is none)."""
        if not settings.start_servers:
            return settings
        from soccer_lab.soccer.rcss.servers import RcssLaunchError, find_rcssserver

        try:
            executable = find_rcssserver(self.rcssserver)
        except RcssLaunchError as exc:
            raise RunStateError(f"start_servers: {exc} (start the app with serve --rcssserver PATH, or give "
                                "the servers you run)") from None
        return settings.with_started_servers(settings.start_servers, str(executable))

    def _placed(self, settings: RunSettings) -> RunSettings:
        """Games played elsewhere (game processes, Ray): the run is one worker, its chunks sent one at a time."""
        if self.remote_games is None or settings.env != SIMPLE or settings.ga.workers == 1:
            return settings
        return replace(settings, ga=settings.ga.model_copy(update={"workers": 1}))

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
        self._active[record.id] = _ActiveRun(thread, frozenset(parse_server(server) for server in settings.servers),
                                             owner=record.owner, expected_seconds=self.pace.seconds(settings),
                                             generations=settings.ga.max_generations, budget=budget_ticks(settings))
        self._threads.add(thread)
        self._notify(RunEvent(record.id, RunStatus.RUNNING))
        thread.start()

    # ---- the run's thread -----------------------------------------------------------------
    def _run(self, record: RunRecord, settings: RunSettings, resume_run: bool) -> None:
        try:
            self._play_to_the_end(record, settings, resume_run)
        finally:
            with self._lock:
                self._threads.discard(threading.current_thread())

    def _play_to_the_end(self, record: RunRecord, settings: RunSettings, resume_run: bool) -> None:
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
            if status is RunStatus.FINISHED and not resume_run:
                self._observe_pace(active, settings)
            try:
                self.store.set_run_status(record.id, status, error)
            except NotFound:  # deleted meanwhile
                return
            finally:
                self._start_queued()
            self._notify(RunEvent(record.id, status))

    def _observe_pace(self, active: _ActiveRun, settings: RunSettings) -> None:
        """A finished run's seconds per budget tick, for the queue's estimates (its generations played of
        those it might have: a run reaching its target fitness stops early)."""
        played = active.watcher.current.generation if active.watcher is not None else settings.ga.max_generations
        ticks = budget_ticks(settings) * min(played, settings.ga.max_generations) // settings.ga.max_generations
        self.pace.observe(time.monotonic() - active.started, ticks)

    def _evolve(self, record: RunRecord, settings: RunSettings, stop: threading.Event, resume_run: bool) -> str:
        """Play the run to its end or until `stop`; the GA's stop reason."""
        run = Run(settings, record.folder)
        writer = StoreWriter(self.store, record.id, ChromosomeCodec(run.vocabulary), self._notify)
        state = run.saved_state() if resume_run else None
        if state is not None:
            writer.restore([stats.to_dict() for stats in state.history], state.best, run.lineage_lines(state))
        watcher = ProgressWatcher(record.id, len(state.history) if state else 0, self._notify)
        self._active[record.id].watcher = watcher
        with run.evaluator(announce=lambda line: log.info("run %s: %s", record.id, line)) as evaluate:
            if self.remote_games is not None and settings.env == SIMPLE:
                evaluate = self.remote_games(evaluate)
            return run.play(evaluate, callbacks=[writer, watcher], stop=stop).stop_reason


def describe_place(place: QueuePlace | None) -> str:
    """A queued run's place for a pupil, e.g. "3rd in line of 12, starts in about 2 min, then plays about 40 s"."""
    if place is None:
        return "starting now"
    return (f"{ordinal(place.position)} in line of {place.queued}, starts in about {about(place.wait_seconds)}, "
            f"then plays about {about(place.run_seconds)}")


def ordinal(number: int) -> str:
    suffix = "th" if 10 <= number % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(number % 10, "th")
    return f"{number}{suffix}"


def about(seconds: float) -> str:
    """A rough duration a pupil reads at a glance: "10 s", "2 min"."""
    if seconds < 60:
        return f"{max(5, round(seconds / 5) * 5)} s"
    return f"{round(seconds / 60)} min"
