"""The GA's evaluator on real servers: `RcssEvaluator(servers)(rulebases, seeds) -> [TrialResult]`.

Trials on one server run one after another (one player, one trainer, synch mode); several servers
(on several ports or hosts) play in parallel, each taking the next trial as it finishes one. Each
server keeps its session open across calls, so connecting costs once per run. Results come back in
the order of the rulebases; each trial's placements come from its own seed.

A server steps only when its client has answered, so the client's own work per cycle (reading the
messages, perceiving, the fuzzy decision) counts as much as the server's: one Python process serving
two servers would share one interpreter between them. So with several servers each gets a client
process of its own (`_client_process`), and with one the trials run in the caller's process.
"""

from __future__ import annotations

import multiprocessing
import signal
import sys
from multiprocessing.connection import Connection, wait
from typing import Sequence

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.soccer.rcss.client import DEFAULT_SERVER, DEFAULT_TEAM, Session, Timeouts, parse_server
from soccer_lab.soccer.rcss.errors import RcssError
from soccer_lab.soccer.rcss.player import load_compiled_skills
from soccer_lab.soccer.rcss.trial import TrialConfig, TrialResult, run_trial


class RcssEvaluator:
    def __init__(
        self,
        servers: Sequence[str] = (DEFAULT_SERVER,),
        config: TrialConfig = TrialConfig(),
        team: str = DEFAULT_TEAM,
        timeouts: Timeouts = Timeouts(),
        trainer_ports: Sequence[int | None] | None = None,
        trace: bool = False,
    ):
        """With `trace`, every trial is traced and `traced` holds the generation's results by (rulebase,
        seed), traces included: where a run finds its generation bests' trials to replay."""
        if not servers:
            raise ValueError("at least one server is needed, e.g. 127.0.0.1:6000")
        for server in servers:
            parse_server(server)  # a bad address fails here, before any trial
        self.servers = list(servers)
        self.trainer_ports = list(trainer_ports) if trainer_ports is not None else [None] * len(self.servers)
        self.config = config
        self.team = team
        self.timeouts = timeouts
        self.trace = trace
        self.traced: dict[tuple[Rulebase, int], TrialResult] = {}
        self._sessions: dict[int, Session] = {}  # one server: its session, in this process
        self._clients: dict[int, tuple[multiprocessing.process.BaseProcess, Connection]] = {}  # several

    def _session(self, index: int) -> Session:
        session = self._sessions.get(index)
        if session is None:
            load_compiled_skills()  # before the server waits for the player
            session = Session(self.servers[index], self.trainer_ports[index], self.team, self.timeouts)
            session.open()
            self._sessions[index] = session
        return session

    def _start_clients(self) -> None:
        """A client process for every server that has none, started together (each takes seconds to
        import and load the compiled skills); returns when every session is open, or raises the first error."""
        starting = [index for index in range(len(self.servers)) if index not in self._clients]
        for index in starting:
            ours, theirs = multiprocessing.Pipe()
            process = multiprocessing.get_context("spawn").Process(
                target=_client_process, daemon=True, name=f"rcss client {self.servers[index]}",
                args=(theirs, self.servers[index], self.trainer_ports[index], self.team, self.timeouts, self.config,
                      self.trace))
            process.start()
            theirs.close()
            self._clients[index] = (process, ours)
        failures = []
        for index in starting:
            try:
                self._answer(index)  # the session is open, or its error is raised
            except Exception as exc:
                failures.append(exc)
        if failures:
            raise failures[0]

    def _answer(self, index: int) -> TrialResult | None:
        """What server `index`'s client process sent back; its error is raised here."""
        try:
            kind, value = self._clients[index][1].recv()
        except (EOFError, OSError):
            self._drop(index)
            raise RcssError(f"the client process for rcssserver at {self.servers[index]} ended unexpectedly") from None
        if kind == "error":
            self._drop(index)
            raise value
        return value

    def connect(self) -> None:
        """Open every server's session now, so that a missing server fails before a run starts."""
        if len(self.servers) == 1:
            self._session(0)
        else:
            self._start_clients()

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[TrialResult]:
        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds")
        results = self._play(rulebases, seeds)
        if self.trace:
            self.traced.update(zip(zip(rulebases, seeds), results))
        warn_if_late(results)
        return results

    @property
    def chunk_size(self) -> int:
        """Trials per chunk of a generation (ga/evaluation.py): one round over the servers, so that a stop
        waits for one trial at most."""
        return len(self.servers)

    def start_generation(self) -> None:
        """A generation starts (ga/evaluation.py says so before its first chunk): `traced` holds its
        trials only, from now on."""
        self.traced = {}

    def _play(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[TrialResult]:
        if len(self.servers) == 1:
            try:
                return [run_trial(self._session(0), r, s, self.config, self.trace) for r, s in zip(rulebases, seeds)]
            except Exception:  # a session that failed is not reused
                self._drop(0)
                raise
        results: list[TrialResult | None] = [None] * len(rulebases)
        pending = iter(range(len(rulebases)))
        playing: dict[Connection, tuple[int, int]] = {}  # client -> (server, trial)

        def play_next(server: int) -> None:
            trial = next(pending, None)
            if trial is not None:
                connection = self._clients[server][1]
                connection.send((rulebases[trial], seeds[trial]))
                playing[connection] = (server, trial)

        self._start_clients()
        try:
            for server in range(min(len(self.servers), len(rulebases))):
                play_next(server)
            while playing:
                for connection in wait(list(playing)):
                    server, trial = playing.pop(connection)  # type: ignore[arg-type]
                    results[trial] = self._answer(server)
                    play_next(server)
        except BaseException:  # a failure or Ctrl+C: the clients still playing would answer a later call
            for server, _ in list(playing.values()):
                self._drop(server)
            raise
        return results  # type: ignore[return-value]

    def _drop(self, index: int) -> None:
        session = self._sessions.pop(index, None)
        if session is not None:
            session.close()
        client = self._clients.pop(index, None)
        if client is not None:
            process, connection = client
            connection.close()  # the process sees the end of its pipe and closes its session
            process.join(timeout=5)
            if process.is_alive():
                process.kill()
                process.join()

    def close(self) -> None:
        for index in list(self._sessions) + list(self._clients):
            self._drop(index)

    def __enter__(self) -> "RcssEvaluator":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def warn_if_late(results: Sequence[TrialResult]) -> None:
    """One line on stderr when the player missed cycles: the machine was too busy to answer the server within
    its 1.25 s, so the server stepped on without the player's commands (the trials are not what they seem)."""
    late = sum(result.late_cycles for result in results)
    if late:
        cycles = sum(result.ticks for result in results)
        print(f"warning: the player answered {late} of {cycles} rcssserver cycles too late (a busy machine): "
              "the server stepped on without its commands", file=sys.stderr, flush=True)


def _client_process(connection: Connection, server: str, trainer_port: int | None, team: str, timeouts: Timeouts,
                    config: TrialConfig, trace: bool) -> None:
    """One server's client: opens its session, answers ("ok", None), then plays each (rulebase, seed) it
    receives and answers ("ok", result) or ("error", exception); ends when the pipe closes."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C is the caller's to handle: it closes the pipe
    session = None
    try:
        load_compiled_skills()  # before the server waits for the player
        session = Session(server, trainer_port, team, timeouts)
        session.open()
        connection.send(("ok", None))
        while True:
            try:
                rulebase, seed = connection.recv()
            except (EOFError, OSError):
                return
            connection.send(("ok", run_trial(session, rulebase, seed, config, trace)))
    except Exception as exc:  # not only RcssError: the caller must hear of every failure
        try:
            connection.send(("error", exc))
        except (OSError, EOFError):  # the caller is gone
            pass
        except Exception:  # an exception that does not pickle: its message does
            connection.send(("error", RcssError(str(exc))))
    finally:
        if session is not None:
            session.close()
