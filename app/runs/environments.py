"""Where evaluations are played: SimpleSoccer games, or trials on real rcssservers. The rules for choosing
one, and the environment objects a run plays with (app/runs/run.py), shared by the command line and the app.

An environment gives a run its evaluator (a context manager: it may hold connections, or servers it
started, for the run's length), says which exceptions mean "the environment failed" (the run stops with
that message and stays resumable), how many GA worker processes it allows, and replays a player's game
for the recording when it can.
"""

from __future__ import annotations

import os
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Iterator, Literal, NamedTuple, Sequence

from soccer_lab.soccer.config import GameConfig, WorldConfig
from soccer_lab.soccer.rcss.client import parse_server
from soccer_lab.soccer.rcss.servers import MAX_SERVERS

if TYPE_CHECKING:
    from soccer_lab.app.runs.rcss_cluster import RayCluster
    from soccer_lab.fuzzy.rule import Rulebase
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.ga.config import CoevolutionConfig
    from soccer_lab.ga.evaluation import Evaluator
    from soccer_lab.ga.hall_of_fame import HallOfFame
    from soccer_lab.soccer.engine import GameResult, GameTrace
    from soccer_lab.soccer.rcss.trial import TrialConfig

SIMPLE, RCSS = "simple", "rcss"
ENVIRONMENTS = (SIMPLE, RCSS)
EnvName = Literal["simple", "rcss"]
# On rcss the GA evaluates in one process: trials run in parallel over the servers (threads), and a
# worker process per server would open a second player and trainer on each.
RCSS_WORKERS = 1
Announce = Callable[[str], None]  # where an environment says what it started (the CLI's stderr, the app's log)


class Replay(NamedTuple):
    """A player's game tick by tick, as the GA scored it."""

    seed: int  # the game's own seed
    result: "GameResult"
    trace: "GameTrace"


def checked_env(env: str) -> str:
    if env not in ENVIRONMENTS:
        raise ValueError(f"expected {' or '.join(ENVIRONMENTS)}, got {env!r}")
    return env


def checked_servers(env: str, servers: Sequence[str] | None) -> list[str]:
    """The servers the user runs that an rcss run plays on (each HOST:PORT checked); [] for
    SimpleSoccer, which takes none. ValueError with one line otherwise."""
    if checked_env(env) == SIMPLE:
        if servers:
            raise ValueError(f"servers are for env {RCSS} only")
        return []
    chosen = list(servers or [])
    addresses = [parse_server(server) for server in chosen]
    if len(set(addresses)) < len(addresses):
        raise ValueError(f"a server is listed twice in {', '.join(chosen)}: each needs its own port")
    return chosen


def checked_start_servers(env: str, servers: Sequence[str] | None, start_servers: int | None) -> int:
    """How many rcssservers a run starts itself: `start_servers`, or 1 when neither they nor servers the
    user runs are given; 0 with servers (or for SimpleSoccer). ValueError with one line otherwise."""
    if checked_env(env) == SIMPLE:
        if start_servers:
            raise ValueError(f"started servers are for env {RCSS} only")
        return 0
    if servers and start_servers:
        raise ValueError("give the servers you run or how many soccer-lab starts, not both")
    if servers:
        return 0
    count = 1 if start_servers is None else start_servers
    if not 1 <= count <= MAX_SERVERS:
        raise ValueError(f"between 1 and {MAX_SERVERS} servers, not {count}")
    return count


def opponent_rulebase(text: str) -> "Rulebase":
    """The opponent of a run played against one, from its rule text (ValueError naming what is wrong)."""
    from soccer_lab.fuzzy.parser import parse_rulebase
    from soccer_lab.soccer.config import SOCCER_VOCABULARY

    rulebase = parse_rulebase(text, SOCCER_VOCABULARY)
    if not len(rulebase):
        raise ValueError("the opponent has no rule")
    return rulebase


def checked_opponent(env: str, opponent: str | None) -> str | None:
    """A fixed opponent's rule text as the printer writes it (None: no opponent); SimpleSoccer only. ValueError
    with one line otherwise."""
    if opponent is None:
        return None
    if checked_env(env) != SIMPLE:
        raise ValueError(f"matches against an opponent are played in SimpleSoccer, not with env {RCSS}")
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.soccer.config import SOCCER_VOCABULARY

    return format_rulebase(opponent_rulebase(opponent), SOCCER_VOCABULARY)


def founder_rulebase(opponent: str | None) -> "Rulebase":
    """A co-evolution run's first opponent: the given player, else the built-in demo."""
    if opponent:
        return opponent_rulebase(opponent)
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.examples import example

    return example("demo").rulebase(SOCCER_VOCABULARY)


def founder_label(opponent: str | None) -> str:
    return "the opponent given (run.json)" if opponent else "the built-in demo"


def default_workers() -> int:
    """Worker processes of a SimpleSoccer run when not told (the CLI and the UI alike): every core, within
    GAConfig's limit."""
    from soccer_lab.ga.config import GAConfig

    limit = next(bound.le for bound in GAConfig.model_fields["workers"].metadata if hasattr(bound, "le"))
    return min(os.cpu_count() or 1, limit)


def checked_workers(env: str, workers: int) -> int:
    if env == RCSS and workers != RCSS_WORKERS:
        raise ValueError(f"with env {RCSS} the GA runs {RCSS_WORKERS} worker; trials run in parallel over "
                         "the servers instead: add a server for each")
    return workers


def checked_behaviour_seeds(env: str, seeds: int) -> int:
    """Behavioural diversity plays extra games through the run's evaluator: an rcss run's evaluator keeps the
    traces of its latest trials for the recording, which those games would replace."""
    if env == RCSS and seeds:
        raise ValueError(f"behavioural diversity is measured in SimpleSoccer runs only, not with env {RCSS}")
    return seeds


@dataclass(frozen=True)
class SimpleSoccerGames:
    """Evaluations are SimpleSoccer games, played in this process or in the GA's worker processes; with an
    `opponent` (its rule text), matches against that fixed player (soccer/match.py, MatchEvaluator); with
    `coevolve`, matches against a hall of fame of earlier bests founded by the opponent, or the built-in demo
    (ga/hall_of_fame.py, HallEvaluator)."""

    game: GameConfig = GameConfig()
    opponent: str | None = None
    coevolve: "CoevolutionConfig | None" = None
    env: ClassVar[str] = SIMPLE
    failures: ClassVar[tuple[type[Exception], ...]] = ()  # nothing outside this process can fail

    def settings(self) -> dict[str, Any]:
        return {"game": self.game.model_dump(), **({"opponent": self.opponent} if self.opponent else {}),
                **({"coevolve": self.coevolve.model_dump()} if self.coevolve is not None else {})}

    def hall(self, vocabulary: "Vocabulary") -> "HallOfFame | None":
        """A new co-evolution run's hall of fame, holding its founder (None: not co-evolving)."""
        if self.coevolve is None:
            return None
        from soccer_lab.ga.codec import ChromosomeCodec
        from soccer_lab.ga.hall_of_fame import founded_hall

        founder = ChromosomeCodec(vocabulary).encode(founder_rulebase(self.opponent))
        return founded_hall(founder, founder_label(self.opponent), self.coevolve.hall_size, self.coevolve.hall_sample)

    @property
    def fixed_opponent(self) -> "Rulebase | None":
        """Whom the run's players are re-played against for their true quality: the fixed opponent, or a
        co-evolution run's founder; None for single-player games."""
        if self.coevolve is not None:
            return founder_rulebase(self.opponent)
        return opponent_rulebase(self.opponent) if self.opponent else None

    @property
    def world(self) -> WorldConfig:
        """Where replays are drawn."""
        return self.game.world

    @contextmanager
    def evaluator(self, announce: Announce | None = None) -> Iterator["Evaluator"]:
        from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator

        if self.coevolve is not None:
            from soccer_lab.soccer.match import HallEvaluator

            yield HallEvaluator(config=self.game)
        elif self.opponent:
            from soccer_lab.soccer.match import MatchEvaluator

            yield MatchEvaluator(opponent_rulebase(self.opponent), self.game)
        else:
            yield SimpleSoccerEvaluator(self.game)

    def replay(self, rulebase: "Rulebase", seed: int, vocabulary: "Vocabulary",
               opponents: Sequence["Rulebase"] = ()) -> Replay | None:
        """The first game of the evaluation played from `seed` (its first of k games): a game depends only on
        rulebase and seed, so this is the very game the GA scored. Against an opponent, the first half of the
        evaluation's first match (against the first of the hall's `opponents` drawn, co-evolving; None without
        them), the player on the left: the very half the GA scored."""
        if self.opponent or self.coevolve is not None:
            return self._match_replay(rulebase, seed, vocabulary, opponents)
        from soccer_lab.soccer.engine import play_game
        from soccer_lab.soccer.evaluate import game_seeds

        first_game = game_seeds(seed, self.game.games_per_evaluation)[0]
        return Replay(first_game, *play_game(rulebase, first_game, self.game, trace=True, vocabulary=vocabulary))

    def _match_replay(self, rulebase: "Rulebase", seed: int, vocabulary: "Vocabulary",
                      opponents: Sequence["Rulebase"]) -> Replay | None:
        from soccer_lab.soccer.engine import GameResult
        from soccer_lab.soccer.evaluate import game_seeds
        from soccer_lab.soccer.match import match_fitness, traced_half

        if self.coevolve is None:
            opponents = [opponent_rulebase(self.opponent)]
        if not opponents:
            return None  # co-evolving, and whom it played is not known here
        first_match = game_seeds(seed, self.game.games_per_evaluation * (len(opponents) if self.coevolve else 1))[0]
        half, trace = traced_half(rulebase, opponents[0], first_match, self.game, vocabulary)
        fitness = match_fitness(half.goals[0] - half.goals[1], half.kicks[0], half.min_ball_goal_distance[0],
                                self.game.world.pitch_length)
        return Replay(first_match, GameResult(fitness, half.goals[0], half.kicks[0], half.ticks,
                                              half.min_ball_goal_distance[0], half.end_reason), trace)


@dataclass(frozen=True)
class RcssTrials:
    """Evaluations are trials on real rcssservers, one at a time per server, in parallel over the servers
    (threads in this process: the GA itself runs with one worker): the `servers` the user runs, or
    `start_servers` servers the run starts itself from the `rcssserver` executable (default
    $RCSSSERVER, else PATH; not stored with the settings: it is wherever the run is played), or servers
    on every node of a Ray `cluster` (app/runs/rcss_cluster.py; not stored either)."""

    servers: tuple[str, ...]
    trial: "TrialConfig"
    start_servers: int = 0
    rcssserver: str | None = field(default=None, compare=False)
    cluster: "RayCluster | None" = field(default=None, compare=False)
    env: ClassVar[str] = RCSS

    @property
    def failures(self) -> tuple[type[Exception], ...]:
        from soccer_lab.app.experiment.executors import ExecutorError
        from soccer_lab.soccer.rcss.errors import RcssError

        return (RcssError, ExecutorError)

    def settings(self) -> dict[str, Any]:
        return {"servers": list(self.servers), "start_servers": self.start_servers, "trial": self.trial.model_dump()}

    @property
    def world(self) -> WorldConfig:
        """Where replays are drawn: rcssserver's own pitch (the default server parameters)."""
        from soccer_lab.soccer.rcss.params import ServerParams

        return ServerParams().world

    @contextmanager
    def evaluator(self, announce: Announce | None = None) -> Iterator["Evaluator"]:
        """Connected to every server up front: a missing server fails here, within seconds, before the run.
        Servers the run starts live as long as the evaluator (they are stopped when it closes)."""
        from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
        from soccer_lab.soccer.rcss.servers import ServerPool, describe, noise_options

        with ExitStack() as stack:
            if self.cluster is not None:
                yield self._cluster_evaluator(stack, announce)
                return
            servers = list(self.servers)
            if self.start_servers:
                pool = stack.enter_context(ServerPool(self.rcssserver, self.start_servers, noise_options(self.trial.noise)))
                servers = pool.addresses
                if announce is not None:
                    announce(describe(pool.servers))
            evaluate = stack.enter_context(RcssEvaluator(servers, self.trial, trace=True))
            evaluate.connect()
            yield evaluate

    def _cluster_evaluator(self, stack: ExitStack, announce: Announce | None) -> "Evaluator":
        from soccer_lab.app.experiment.executors import RayExecutor
        from soccer_lab.app.runs.rcss_cluster import ClusterServers

        stack.enter_context(RayExecutor(self.cluster.address))
        evaluate = stack.enter_context(ClusterServers(self.cluster, self.trial, trace=True, announce=announce))
        evaluate.connect()
        return evaluate

    def replay(self, rulebase: "Rulebase", seed: int, vocabulary: "Vocabulary") -> Replay | None:
        """None: a trial cannot be played again the same (the server has noise of its own, and another
        trial would hold a server). The evaluator traces every trial instead (`traced`), and a run keeps each
        living individual's first trial to replay (app/runs/run.py, GenerationReplays)."""
        return None


Environment = SimpleSoccerGames | RcssTrials
