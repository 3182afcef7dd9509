"""Where evaluations are played: SimpleSoccer, or trials on real rcssservers (spec 5). The rules for
choosing one, shared by the command line and the app's runs."""

from __future__ import annotations

from typing import Literal, Sequence

from soccer.rcss.client import DEFAULT_SERVER, parse_server

SIMPLE, RCSS = "simple", "rcss"
ENVIRONMENTS = (SIMPLE, RCSS)
EnvName = Literal["simple", "rcss"]
# On rcss the GA evaluates in one process: trials run in parallel over the servers (threads), and a
# worker process per server would open a second player and trainer on each.
RCSS_WORKERS = 1


def checked_env(env: str) -> str:
    if env not in ENVIRONMENTS:
        raise ValueError(f"expected {' or '.join(ENVIRONMENTS)}, got {env!r}")
    return env


def checked_servers(env: str, servers: Sequence[str] | None) -> list[str]:
    """The servers an rcss run plays on (each HOST:PORT checked; none given: the default server);
    [] for SimpleSoccer, which takes none. ValueError with one line otherwise."""
    if checked_env(env) == SIMPLE:
        if servers:
            raise ValueError(f"servers are for env {RCSS} only")
        return []
    chosen = list(servers or [DEFAULT_SERVER])
    addresses = [parse_server(server) for server in chosen]
    if len(set(addresses)) < len(addresses):
        raise ValueError(f"a server is listed twice in {', '.join(chosen)}: each needs its own port")
    return chosen


def checked_workers(env: str, workers: int) -> int:
    if env == RCSS and workers != RCSS_WORKERS:
        raise ValueError(f"with env {RCSS} the GA runs {RCSS_WORKERS} worker; trials run in parallel over "
                         "the servers instead: add a server for each")
    return workers
