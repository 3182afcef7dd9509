"""One evolution run, from the command line or from the app: its settings and its folder.

`Run.evaluator()` opens the evaluator of the settings' environment (SimpleSoccer games or rcssserver
trials, app/runs/environments.py); `Run.play` then plays the GA or random search with the folder's callbacks (statistics.csv,
best.rules/best.json, the rerun recording; the GA checkpoints into the folder after every generation),
plus the caller's own (the CLI's progress bar, the app's store). A folder with a checkpoint continues
from it, and finishes exactly as the uninterrupted run would. The settings are written to the folder's
run.json in the same form the app stores them, so any run folder can be continued by either.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, ContextManager, Iterable, Literal, Sequence

from pydantic import ValidationError

from soccer_lab.app.runs.environments import (RCSS, SIMPLE, Announce, Environment, RcssTrials, Replay,
                                              SimpleSoccerGames, checked_behaviour_seeds, checked_env, checked_opponent,
                                              checked_servers, checked_start_servers, checked_workers)
from soccer_lab.app.paths import DataFolderInUse
from soccer_lab.app.runs.lease import RunLease
from soccer_lab.app.runs.recording import RunRecorder
from soccer_lab.app.runs.outputs import (GenerationBestsFile, LineageFile, Replayer, RunFolder, RunFolderError,
                                         RunOutputs, generation_best, lineage_line)
from soccer_lab.app.runs.true_quality import TrueQuality, simple_soccer_replayer
from soccer_lab.app.web.validation import describe_problems
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import Callback, evolve, random_search, resume
from soccer_lab.ga.checkpoint import load_checkpoint
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import CoevolutionConfig, GAConfig
from soccer_lab.ga.evaluation import Evaluator
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.result import RunResult
from soccer_lab.ga.state import ALGORITHMS, GA, RANDOM_SEARCH, RunState
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.rcss.trial import TrialConfig

if TYPE_CHECKING:
    from soccer_lab.app.runs.rcss_cluster import RayCluster

AlgorithmName = Literal["ga", "random-search"]  # soccer_lab.ga.state's GA and RANDOM_SEARCH, for the API's schema


@dataclass(frozen=True)
class RunSettings:
    """Everything a run needs to be played (or resumed): the algorithm (the GA or random search), the
    GA's parameters and where evaluations play: SimpleSoccer games (`game`) or, for env "rcss", trials
    (`trial`) on `servers` the user runs or on `start_servers` servers the run starts from `rcssserver`
    (the executable where the run plays: never stored)."""

    ga: GAConfig = GAConfig()
    game: GameConfig = GameConfig()
    env: str = SIMPLE
    servers: tuple[str, ...] = ()
    trial: TrialConfig = TrialConfig()
    algorithm: str = GA
    start_servers: int = 0
    rcssserver: str | None = field(default=None, compare=False)
    cluster: "RayCluster | None" = field(default=None, compare=False)  # servers on a Ray cluster's nodes
    opponent: str | None = None  # SimpleSoccer only: rule text of the fixed player each evaluation is a match against
    # SimpleSoccer only: co-evolve against a hall of fame of earlier bests, founded by `opponent` or the built-in demo
    coevolve: CoevolutionConfig | None = None

    @classmethod
    def build(
        cls,
        ga: GAConfig | dict[str, Any] | None = None,
        game: GameConfig | dict[str, Any] | None = None,
        env: str = SIMPLE,
        servers: Sequence[str] | None = None,
        trial: TrialConfig | dict[str, Any] | None = None,
        algorithm: str = GA,
        start_servers: int | None = None,
        opponent: str | None = None,
        coevolve: CoevolutionConfig | dict[str, Any] | None = None,
    ) -> "RunSettings":
        """Validated settings (an rcss run given no servers starts one); ValueError naming
        each bad parameter (pydantic's ValidationError, a ValueError, for bad GA parameters: the caller
        names the fields its own way)."""
        if algorithm not in ALGORITHMS:
            raise ValueError(f"algorithm: expected {' or '.join(ALGORITHMS)}, got {algorithm!r}")
        ga = ga if isinstance(ga, GAConfig) else GAConfig(**(ga or {}))
        try:
            game = game if isinstance(game, GameConfig) else GameConfig(**(game or {}))
        except ValidationError as exc:
            raise ValueError(f"invalid game parameters: {describe_problems(exc.errors())}") from None
        try:
            trial = trial if isinstance(trial, TrialConfig) else TrialConfig(**(trial or {}))
        except ValidationError as exc:
            raise ValueError(f"invalid trial parameters: {describe_problems(exc.errors())}") from None
        try:
            coevolve = coevolve if coevolve is None or isinstance(coevolve, CoevolutionConfig) else \
                CoevolutionConfig(**coevolve)
        except (TypeError, ValidationError) as exc:
            problems = describe_problems(exc.errors()) if isinstance(exc, ValidationError) else str(exc)
            raise ValueError(f"invalid co-evolution parameters: {problems}") from None
        if coevolve is not None and (env != SIMPLE or algorithm != GA):
            raise ValueError("coevolve: co-evolution is a GA run in SimpleSoccer")
        checked = {}  # each checked once: the opponent's rules are parsed once
        for where, check in (("env", lambda: checked_env(env)), ("servers", lambda: checked_servers(env, servers)),
                             ("start_servers", lambda: checked_start_servers(env, servers, start_servers)),
                             ("ga.workers", lambda: checked_workers(env, ga.workers)),
                             ("ga.behaviour_seeds", lambda: checked_behaviour_seeds(env, ga.behaviour_seeds)),
                             ("opponent", lambda: checked_opponent(env, opponent))):
            try:
                checked[where] = check()
            except ValueError as exc:
                raise ValueError(f"{where}: {exc}") from None
        return cls(ga, game, env, tuple(checked["servers"]), trial, algorithm, checked["start_servers"],
                   opponent=checked["opponent"], coevolve=coevolve)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "RunSettings":
        """Settings as stored (run.json, the app's store); runs from before env existed played SimpleSoccer,
        from before algorithm was stored the GA."""
        return cls.build(data.get("ga"), data.get("game"), data.get("env", SIMPLE), data.get("servers"),
                         data.get("trial"), data.get("algorithm", GA), data.get("start_servers") or None,
                         data.get("opponent"), data.get("coevolve"))

    def to_dict(self) -> dict[str, Any]:
        return {"algorithm": self.algorithm, "ga": self.ga.model_dump(), "env": self.env,
                **self.environment.settings()}

    @property
    def environment(self) -> Environment:
        if self.env == RCSS:
            return RcssTrials(self.servers, self.trial, self.start_servers, self.rcssserver, self.cluster)
        return SimpleSoccerGames(self.game, self.opponent, self.coevolve)

    @property
    def pitch_game(self) -> GameConfig:
        """The SimpleSoccer game the UI plays this run's players in (its pitch and population view): the
        run's own game, or for an rcss run SimpleSoccer's with the trial's skill set (the server's noise and
        kick counting have no SimpleSoccer setting to carry over)."""
        if self.env == RCSS:
            return GameConfig(skills=self.trial.skills)
        return self.game

    def with_servers(self, servers: Sequence[str]) -> "RunSettings":
        """The same rcss run on other servers the user runs (a resumed run may play on other servers or ports)."""
        return replace(self, servers=tuple(checked_servers(self.env, servers)), start_servers=0)

    def with_started_servers(self, count: int | None = None, rcssserver: str | None = None) -> "RunSettings":
        """The same rcss run on `count` servers it starts itself (default: as many as before, or 1), from
        `rcssserver`."""
        count = count or self.start_servers or 1
        return replace(self, servers=(), start_servers=checked_start_servers(self.env, (), count),
                       rcssserver=rcssserver)

    def on_cluster(self, cluster: "RayCluster") -> "RunSettings":
        """The same rcss run on servers on every node of a Ray cluster (app/runs/rcss_cluster.py)."""
        return replace(self, servers=(), start_servers=checked_start_servers(self.env, (), self.start_servers or 1),
                       cluster=cluster)

    def default_name(self) -> str:
        """What the run is, e.g. "GA 200x25 roulette/inverse assisted seed 0" or "random search 200x25 ..."."""
        size = f"{self.ga.population_size}x{self.ga.max_generations}"
        if self.algorithm == RANDOM_SEARCH:
            method = f"random search {size}"
        else:
            selection = self.ga.selection
            if selection in ("roulette", "elitist"):  # the two that weigh individuals for the roulette
                selection += f"/{self.ga.roulette_weighting}"
            method = f"GA {size} {selection}"
        if self.env == RCSS:
            return f"{method} {self.trial.skills} on rcssserver seed {self.ga.seed}"
        return f"{method} {self.game.skills} seed {self.ga.seed}"


class Run:
    """One run in its folder: `play` starts it, or continues it from the folder's checkpoint."""

    def __init__(self, settings: RunSettings, folder: str | Path):
        self.settings = settings
        self.folder = RunFolder(Path(folder))
        self.vocabulary = SOCCER_VOCABULARY  # what a new run's rules are made of (a resumed run keeps its own)
        self.best_game: Replay | None = None  # after play: the best player's first game, where it can be replayed
        self.outputs: RunOutputs | None = None  # while and after it plays

    @classmethod
    def create(cls, settings: RunSettings, folder: str | Path) -> "Run":
        """A new run; RunFolderError when the folder already holds one. The folder is made when the run
        plays, once its evaluator is ready (so a missing server leaves no folder behind)."""
        run = cls(settings, folder)
        if run.folder.manifest.exists():
            raise RunFolderError(f"{run.folder.path} already holds a run (use --resume {run.folder.path} to continue it)")
        return run

    @classmethod
    def open(cls, folder: str | Path) -> "Run":
        """The run a folder holds, to continue from its checkpoint. RunFolderError (no run, no checkpoint,
        unreadable settings) with one line."""
        opened = RunFolder.open(folder)
        try:
            settings = RunSettings.from_dict(opened.read_manifest())
        except ValueError as exc:
            raise RunFolderError(f"{opened.manifest}: {exc}") from None
        return cls(settings, opened.path)

    def saved_state(self) -> RunState | None:
        """The GA's state after the last finished generation, or None before the first (CheckpointError
        for a damaged checkpoint)."""
        return load_checkpoint(self.folder.checkpoint) if self.folder.checkpoint.is_file() else None

    def evaluator(self, announce: Announce | None = None) -> ContextManager[Evaluator]:
        """The evaluator `play` scores with, open for the run's length: `with run.evaluator() as evaluate:`.
        A missing rcssserver fails here, within seconds, before anything is written. `announce` hears
        what the environment started (the rcssservers, with their PIDs)."""
        return self.settings.environment.evaluator(announce)

    def play(self, evaluate: Evaluator, callbacks: Iterable[Callback] = (),
             stop: threading.Event | None = None) -> RunResult:
        """Play the run to its end (or until `stop`, within the generation in progress); the GA's result.
        The environment's failures (a server gone...) and KeyboardInterrupt propagate; every finished
        generation is kept and the run can be continued."""
        with self._lease():
            return self._play(evaluate, callbacks, stop)

    def refuse_if_played_elsewhere(self) -> None:
        """RunFolderError (one line) when another process plays this run: a resume says so before it starts
        anything (`play` takes the lease for good)."""
        self._lease().release()

    def _lease(self) -> RunLease:
        """The run's lease, held while it plays: RunFolderError (one line) when another process plays it."""
        try:
            self.folder.path.mkdir(parents=True, exist_ok=True)
            return RunLease(self.folder.path)
        except DataFolderInUse as exc:
            raise RunFolderError(str(exc)) from None
        except OSError as exc:
            raise RunFolderError(f"cannot create run folder {self.folder.path}: {exc.strerror or exc}") from exc

    def _play(self, evaluate: Evaluator, callbacks: Iterable[Callback], stop: threading.Event | None) -> RunResult:
        if not self.folder.manifest.exists():
            RunFolder.create(self.folder.path, self.settings.to_dict())
        state = self.saved_state()
        history = [stats.to_dict() for stats in state.history] if state else []
        vocabulary = state.vocabulary if state else self.vocabulary
        bests = self._generation_bests(state)
        outputs = RunOutputs(self.folder, vocabulary, history=history, best=state.best if state else None,
                             generation_bests=bests, lineage=self.lineage_lines(state).values(),
                             replay=self._quality_replayer(vocabulary))
        self.outputs = outputs
        environment = self.settings.environment
        recorder = RunRecorder(self.folder.recording, history=history, world=environment.world)
        try:
            replays = GenerationReplays(environment, recorder, vocabulary, evaluate)
            for generation, best in bests:
                replays.replay(generation, best)
            everything = [outputs, recorder, replays, *callbacks]
            if state is not None:
                result = resume(self.folder.checkpoint, evaluate, callbacks=everything, stop=stop)
            else:
                algorithm = evolve if self.settings.algorithm == GA else random_search
                hall = environment.hall(vocabulary) if isinstance(environment, SimpleSoccerGames) else None
                extra = {"hall": hall} if hall is not None else {}
                result = algorithm(self.settings.ga, evaluate, vocabulary, callbacks=everything,
                                   checkpoint=self.folder.checkpoint, stop=stop, **extra)
            if result.best is not None:  # None: stopped before its first generation finished
                outputs.write_best(result.best_rulebase)
                self.best_game = replays.game_of(result.best)
        finally:
            recorder.close()
        return result

    @property
    def best_quality(self) -> TrueQuality | None:
        """The best so far re-played on the common fresh starts (None before the first generation, on rcssserver)."""
        return self.outputs.best_quality if self.outputs is not None else self.folder.best_quality()

    def _quality_replayer(self, vocabulary: Vocabulary) -> Replayer | None:
        """Re-plays a best on app/runs/true_quality.py's common starts, one SimpleSoccer game each (against an
        opponent, one match each), in one batch (none on rcssserver: there N trials would cost minutes)."""
        if self.settings.env != SIMPLE:
            return None
        return simple_soccer_replayer(self.settings.game, vocabulary, opponent=self.settings.environment.fixed_opponent)

    def lineage_lines(self, state: RunState | None) -> dict[int, str]:
        """lineage.jsonl's line of each finished generation: those the file holds for the generations the
        checkpoint holds, and the last one from the checkpoint when the run was killed before writing it.
        A generation missing from the file (a run from before lineage was recorded) stays missing."""
        if state is None:
            return {}
        finished = len(state.history)
        lines = {g: line for g, line in LineageFile.read(self.folder.lineage).items() if g < finished}
        drawn = [member.label for member in state.hall.drawn] if state.hall is not None else None
        lines.setdefault(finished - 1, lineage_line(finished - 1, state.population, drawn))
        return dict(sorted(lines.items()))

    def _generation_bests(self, state: RunState | None) -> list[tuple[int, Individual]]:
        """Each finished generation's best, from generation_bests.jsonl: the lines of the generations the
        checkpoint holds (a killed run may have written one more), and the last generation's best from
        the checkpoint when the run was killed before writing its line."""
        if state is None:
            return []
        finished = len(state.history)
        bests = [(g, best) for g, best in GenerationBestsFile.read(self.folder.generation_bests) if g < finished]
        if not any(g == finished - 1 for g, _ in bests):
            bests.append((finished - 1, generation_best(state.population)))
        return bests


class GenerationReplays:
    """Callback replaying each generation's best player's game into the recording: the game of its first
    evaluation (individuals keep that game's seed). A SimpleSoccer game depends only on rulebase and seed,
    so it is played again, one game a generation. An rcssserver trial cannot be played again the same, so
    the evaluator traces every trial (`evaluate.traced`: the last generation's, by rulebase and seed) and
    each living individual's first trial is kept while it lives (about 70 KB a trial). A best that an
    earlier generation already had (an elite, say) is the same game: it is logged again, not played again."""

    def __init__(self, environment: Environment, recorder: RunRecorder, vocabulary: Vocabulary,
                 evaluate: Evaluator | None = None):
        self.environment = environment
        self.recorder = recorder
        self.vocabulary = vocabulary
        self.evaluate = evaluate
        self.codec = ChromosomeCodec(vocabulary)
        self.games: dict[tuple[bytes, int], Replay] = {}
        self.first_trials: dict[tuple[bytes, int], Replay] = {}  # traced first evaluations of the living
        self.opponents: list[Any] = []  # co-evolution: the generation's opponents (the hall members drawn)

    def on_opponents(self, generation: int, members: list[Any]) -> None:
        self.opponents = [self.codec.decode(member.chromosome) for member in members]

    def on_generation(self, stats: Any, population: list[Individual]) -> None:
        self._keep_first_trials(population)
        self.replay(stats.generation, generation_best(population))

    def _keep_first_trials(self, population: list[Individual]) -> None:
        traced = getattr(self.evaluate, "traced", None)
        if not traced:
            return
        living = {}
        for individual in population:
            key = (individual.chromosome.tobytes(), individual.first_seed)
            if key in self.first_trials:
                living[key] = self.first_trials[key]
            elif individual.evaluations == 1:  # its first evaluation was this generation's
                result = traced.get((self.codec.decode(individual.chromosome), individual.first_seed))
                if result is not None and result.trace is not None:
                    living[key] = Replay(individual.first_seed, result, result.trace)
        self.first_trials = living

    def replay(self, generation: int, individual: Individual) -> None:
        game = self.game_of(individual)
        if game is not None:
            self.recorder.log_generation_replay(generation, game.trace, game.result)

    def game_of(self, individual: Individual) -> Replay | None:
        """The individual's first game; None where it cannot be replayed (an rcss trial not traced in this
        process, no valid rule to play, a checkpoint from before individuals kept their seed)."""
        if individual.first_seed is None:
            return None
        key = (individual.chromosome.tobytes(), individual.first_seed)
        if key not in self.games:
            game = self.first_trials.get(key) or self._played_again(individual)
            if game is None:
                return None
            self.games[key] = game
        return self.games[key]

    def _played_again(self, individual: Individual) -> Replay | None:
        rulebase = self.codec.decode(individual.chromosome)
        if not len(rulebase):
            return None
        if isinstance(self.environment, SimpleSoccerGames) and self.environment.coevolve is not None:
            # its first evaluation's opponents are known only when it was this generation's (a resumed run's
            # earlier generations were played before the hall members were heard)
            opponents = self.opponents if individual.evaluations == 1 else []
            return self.environment.replay(rulebase, individual.first_seed, self.vocabulary, opponents)
        return self.environment.replay(rulebase, individual.first_seed, self.vocabulary)
