"""Trials on rcssservers across a Ray cluster: every node runs rcssservers of its own.

`ClusterServers(cluster, trial)` is an evaluator as `soccer_lab.soccer.rcss.evaluate.RcssEvaluator` is (rulebases and
seeds in, TrialResults out, in order), for `evolve --env rcss --executor ray` and `experiment robocup
--executor ray`. On each alive node of the cluster it places `servers_per_node` Ray actors (default: one
per CPU of the node), pinned to that node; each actor starts one rcssserver there with soccer-lab's own
launcher (soccer/rcss/servers.py: the executable from the node's $RCSSSERVER or PATH, or the path
given, which must then hold on every node), opens one player and trainer on it, and plays the trials
it is handed, one at a time. The GA stays on the driver; each generation's trials go to whichever
server is free. A trial's course depends only on its rulebase, seed and the server's noise
(soccer/rcss/trial.py), so without noise the results are those of the same run on local servers, bit
for bit, however the trials were spread.

No server outlives its actor: an actor stops its server when the evaluator closes (the run ends, fails
or is interrupted with Ctrl+C), and the server dies with the actor's process otherwise (the launcher's
parent-death signal), which Ray ends when the driver goes or the node's Ray stops. An actor that dies
mid-run (its node killed) is dropped and its trial played again on another server; the run fails only
when no server is left.
"""

from __future__ import annotations

import os
from collections import Counter
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

from soccer_lab.app.experiment.executors import RayExecutor, RcssExecutor
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.soccer.rcss.errors import RcssError

if TYPE_CHECKING:
    from soccer_lab.soccer.rcss.trial import TrialConfig, TrialResult

READY_SECONDS = 120.0  # a node imports soccer-lab and compiles the player's kernels before its server answers
CLOSE_SECONDS = 10.0
Announce = Callable[[str], None]


class ClusterError(RcssError):
    """No server on the cluster (none could start, or every one is gone): one line for the user."""


@dataclass(frozen=True)
class RayCluster:
    """Where a run's servers are: the Ray cluster at `address` (None: a Ray started here), with
    `servers_per_node` rcssservers on each node (None: one per CPU of the node), started from `rcssserver`
    (None: each node's $RCSSSERVER, else PATH)."""

    address: str | None = None
    servers_per_node: int | None = None
    rcssserver: str | None = None


class ServerActor:
    """One rcssserver on the actor's node and a session on it (a Ray actor: `ray.remote(ServerActor)`).
    Ray runs an actor's methods one at a time in the thread that created it, the thread the launcher ties
    the server's life to."""

    def __init__(self, rcssserver: str | None, trial: "TrialConfig", trace: bool):
        self.rcssserver, self.trial, self.trace = rcssserver, trial, trace
        self.pool = self.session = None

    def open(self) -> dict[str, Any]:
        """Start the server and connect; where it runs (node, address, pid, and the actor's own pid: `worker`).
        Raises RcssError (a launch failure names the node)."""
        import ray

        from soccer_lab.soccer.rcss.client import Session
        from soccer_lab.soccer.rcss.player import load_compiled_skills
        from soccer_lab.soccer.rcss.servers import RcssLaunchError, ServerPool, noise_options

        node = ray.util.get_node_ip_address()
        try:
            self.pool = ServerPool(self.rcssserver, 1, noise_options(self.trial.noise)).start()
        except RcssLaunchError as exc:
            raise RcssLaunchError(f"on Ray node {node}: {exc}") from None
        load_compiled_skills()  # before the server waits for the player
        self.session = Session(self.pool.addresses[0])
        self.session.open()
        server = self.pool.servers[0]
        return {"node": node, "address": server.address, "pid": server.pid, "worker": os.getpid()}

    def play(self, rulebase: Rulebase, seed: int) -> "TrialResult":
        from soccer_lab.soccer.rcss.trial import run_trial

        return run_trial(self.session, rulebase, seed, self.trial, self.trace)

    def close(self) -> None:
        if self.session is not None:
            self.session.close()
        if self.pool is not None:
            self.pool.stop()
        self.pool = self.session = None

    __ray_shutdown__ = close  # Ray calls it when it ends the actor gracefully (its driver gone, say)


def node_servers(node_cpus: float, per_node: int | None) -> tuple[int, float]:
    """(servers on a node, CPUs each actor asks for): one per CPU by default; more than the node's CPUs share
    them, so that every actor can be placed."""
    count = per_node or max(1, int(node_cpus))
    return count, min(1.0, node_cpus / count)


class ClusterServers:
    """The evaluator on a Ray cluster's servers (see the module). Ray must be initialised (RayExecutor)."""

    def __init__(self, cluster: RayCluster, trial: "TrialConfig", trace: bool = False,
                 announce: Announce | None = None):
        import ray

        self.ray = ray
        self.cluster = cluster
        self.trial = trial
        self.trace = trace
        self.announce = announce
        self.traced: dict[tuple[Rulebase, int], TrialResult] = {}
        self.actors: list[Any] = []
        self.places: list[dict[str, Any]] = []  # where each actor's server runs
        self.played: Counter[str] = Counter()  # trials played, by server address

    def connect(self) -> None:
        """One actor per server on every alive node, each with its server started and connected; ClusterError
        when none could start (the first failure's message)."""
        from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

        remote = self.ray.remote(ServerActor)
        for node in self.ray.nodes():
            if not node.get("Alive"):
                continue
            count, cpus = node_servers(node.get("Resources", {}).get("CPU", 1.0), self.cluster.servers_per_node)
            placed = NodeAffinitySchedulingStrategy(node["NodeID"], soft=False)
            self.actors += [remote.options(num_cpus=cpus, scheduling_strategy=placed, max_restarts=0,
                                           max_task_retries=0).remote(self.cluster.rcssserver, self.trial, self.trace)
                            for _ in range(count)]
        opened = [actor.open.remote() for actor in self.actors]
        ready, _ = self.ray.wait(opened, num_returns=len(opened), timeout=READY_SECONDS)
        places, failures = {}, []
        for actor, ref in zip(list(self.actors), opened):
            try:
                places[id(actor)] = self.ray.get(ref, timeout=0) if ref in ready else None
            except Exception as exc:  # noqa: BLE001 - a launch failure on one node; the others may play
                failures.append(_message(exc))
                places[id(actor)] = None
        for actor in [a for a in self.actors if places[id(a)] is None]:
            self._drop(actor)
        self.places = [places[id(actor)] for actor in self.actors]
        if not self.actors:
            why = failures[0] if failures else f"no rcssserver answered within {READY_SECONDS:g} s"
            self.close()
            raise ClusterError(f"no rcssserver started on the Ray cluster: {why}")
        if self.announce is not None:
            self.announce(describe(self.places) + (f"; {len(failures)} failed: {failures[0]}" if failures else ""))

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list["TrialResult"]:
        from soccer_lab.soccer.rcss.evaluate import warn_if_late

        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds")
        if not self.actors:
            self.connect()
        results = self._play(rulebases, seeds)
        if self.trace:
            self.traced.update(zip(zip(rulebases, seeds), results))
        warn_if_late(results)
        return results

    @property
    def chunk_size(self) -> int:
        """Trials per chunk of a generation (ga/evaluation.py): one round over the cluster's servers, as
        RcssEvaluator's, so that a stop waits for one trial per server at most (the servers start here)."""
        if not self.actors:
            self.connect()
        return len(self.actors)

    def start_generation(self) -> None:
        """A generation starts (ga/evaluation.py says so): `traced` holds its trials only, from now on."""
        self.traced = {}

    def _play(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list["TrialResult"]:
        """Each free actor takes the next trial; a trial whose actor died goes back to the queue."""
        from ray.exceptions import RayActorError, RayTaskError

        results: list[TrialResult | None] = [None] * len(rulebases)
        queue = list(range(len(rulebases)))
        playing: dict[Any, tuple[Any, int]] = {}  # ref -> (actor, trial)
        free = list(self.actors)
        while queue or playing:
            while queue and free:
                actor, trial = free.pop(0), queue.pop(0)
                playing[actor.play.remote(rulebases[trial], seeds[trial])] = (actor, trial)
            if not playing:
                raise ClusterError("every rcssserver of the Ray cluster is gone (its nodes or actors died)")
            (ref,), _ = self.ray.wait(list(playing), num_returns=1)
            actor, trial = playing.pop(ref)
            try:
                results[trial] = self.ray.get(ref)
                self.played[self.places[self.actors.index(actor)]["address"]] += 1
            except RayActorError as exc:
                self._lost(actor, exc)
                queue.insert(0, trial)
                continue
            except RayTaskError as exc:  # the trial failed on its server: the run fails as on local servers
                cause = _cause(exc)
                raise (cause if isinstance(cause, RcssError) else RcssError(_message(exc))) from None
            free.append(actor)
        return results  # type: ignore[return-value]

    def _lost(self, actor: Any, error: Exception) -> None:
        index = self.actors.index(actor)
        place = self.places[index]
        self.actors.pop(index)
        self.places.pop(index)
        if self.announce is not None:
            where = f"{place['address']} on node {place['node']}" if place else "an rcssserver"
            self.announce(f"lost {where} ({_message(error)[:120]}); {len(self.actors)} servers left, its trial "
                          "plays again on another")

    def _drop(self, actor: Any) -> None:
        self.actors.remove(actor)
        try:
            self.ray.kill(actor)
        except Exception:  # noqa: BLE001 - already gone
            pass

    def close(self) -> None:
        """Every actor stops its server, then is ended (its server dies with it if it could not)."""
        actors, self.actors, self.places = self.actors, [], []
        closing = [actor.close.remote() for actor in actors]
        if closing:
            self.ray.wait(closing, num_returns=len(closing), timeout=CLOSE_SECONDS)
        for actor in actors:
            try:
                self.ray.kill(actor)
            except Exception:  # noqa: BLE001 - already gone
                pass

    def __enter__(self) -> "ClusterServers":
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


def describe(places: Sequence[dict[str, Any]]) -> str:
    """One line naming the servers by node, e.g. for a command's stderr."""
    nodes: dict[str, list[str]] = {}
    for place in places:
        nodes.setdefault(place["node"], []).append(f"{place['address']} (pid {place['pid']})")
    listed = "; ".join(f"node {node}: {', '.join(servers)}" for node, servers in nodes.items())
    return f"started {len(places)} rcssserver{'s' if len(places) != 1 else ''} on {len(nodes)} Ray " \
           f"node{'s' if len(nodes) != 1 else ''}: {listed}"


def _cause(error: BaseException) -> BaseException:
    """The actor's own exception behind a Ray error (a RayTaskError carries it), else the error."""
    cause = getattr(error, "cause", None)
    return cause if isinstance(cause, BaseException) else error


def _message(error: BaseException) -> str:
    """One line: the first of the actor's own exception's message."""
    lines = str(_cause(error)).strip().splitlines()
    return lines[0] if lines else type(error).__name__




class ClusterRcssExecutor(RcssExecutor):
    """The `robocup` experiment's trials on a Ray cluster's rcssservers: as RcssExecutor (one GA trial after
    another, each generation's evaluations spread over the servers), with Ray started (or joined) for the
    experiment's length."""

    def __init__(self, cluster: RayCluster, announce: Announce | None = None):
        super().__init__(())
        self.cluster, self.announce = cluster, announce
        self.ray = RayExecutor(cluster.address)  # ExecutorError now when Ray is missing

    def __enter__(self) -> "ClusterRcssExecutor":
        self.ray.__enter__()
        return self

    def __exit__(self, *exc_info: object) -> None:
        try:
            super().__exit__(*exc_info)
        finally:
            self.ray.__exit__(*exc_info)

    def _new_evaluator(self, trial: "TrialConfig") -> ClusterServers:  # type: ignore[override]
        return ClusterServers(self.cluster, trial, announce=self.announce)
