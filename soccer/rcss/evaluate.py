"""The GA's evaluator on real servers: `RcssEvaluator(servers)(rulebases, seeds) -> [TrialResult]`.

Trials on one server run one after another (one player, one trainer, synch mode); several servers
(on several ports or hosts) play in parallel, one thread each, taking the next trial from a shared
queue. Each server keeps its session open across calls, so connecting costs once per run. Results
come back in the order of the rulebases; each trial's placements come from its own seed.
"""

from __future__ import annotations

import queue
import threading
from typing import Sequence

from fuzzy.rule import Rulebase
from soccer.rcss.client import DEFAULT_SERVER, DEFAULT_TEAM, Session, Timeouts, parse_server
from soccer.rcss.player import load_compiled_skills
from soccer.rcss.trial import TrialConfig, TrialResult, run_trial


class RcssEvaluator:
    def __init__(
        self,
        servers: Sequence[str] = (DEFAULT_SERVER,),
        config: TrialConfig = TrialConfig(),
        team: str = DEFAULT_TEAM,
        timeouts: Timeouts = Timeouts(),
        trainer_ports: Sequence[int | None] | None = None,
    ):
        if not servers:
            raise ValueError("at least one server is needed, e.g. 127.0.0.1:6000")
        for server in servers:
            parse_server(server)  # a bad address fails here, before any trial
        self.servers = list(servers)
        self.trainer_ports = list(trainer_ports) if trainer_ports is not None else [None] * len(self.servers)
        self.config = config
        self.team = team
        self.timeouts = timeouts
        self._sessions: dict[int, Session] = {}

    def _session(self, index: int) -> Session:
        session = self._sessions.get(index)
        if session is None:
            load_compiled_skills()  # before the server waits for the player
            session = Session(self.servers[index], self.trainer_ports[index], self.team, self.timeouts)
            session.open()
            self._sessions[index] = session
        return session

    def connect(self) -> None:
        """Open every server's session now, so that a missing server fails before a run starts."""
        for index in range(len(self.servers)):
            self._session(index)

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[TrialResult]:
        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds")
        work: queue.Queue[int] = queue.Queue()
        for index in range(len(rulebases)):
            work.put(index)
        results: list[TrialResult | None] = [None] * len(rulebases)
        failures: list[Exception] = []  # the first is raised here, in the caller's thread

        def serve(server_index: int) -> None:
            try:
                while not failures:
                    try:
                        index = work.get_nowait()
                    except queue.Empty:
                        return
                    results[index] = run_trial(self._session(server_index), rulebases[index], seeds[index], self.config)
            except Exception as exc:  # not only RcssError: a failure must never leave a result missing
                failures.append(exc)
                self._drop(server_index)

        threads = [threading.Thread(target=serve, args=(i,), daemon=True) for i in range(len(self.servers))]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        if failures:
            raise failures[0]
        return results  # type: ignore[return-value]

    def _drop(self, index: int) -> None:
        session = self._sessions.pop(index, None)
        if session is not None:
            session.close()

    def close(self) -> None:
        for index in list(self._sessions):
            self._drop(index)

    def __enter__(self) -> "RcssEvaluator":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
