"""Real rcssservers for the tests: where the executable is, and fixtures that start servers (free ports,
scratch folders, stopped by PID after the test) with soccer-lab's own launcher.

The executable: $RCSSSERVER, else `rcssserver` on PATH, else `shared/rcss/server/bin/rcssserver` in the
repository's folder or any folder above it (where the team's CI keeps a prebuilt server). Without one, the
tests that need it skip and say what to install or set.
"""

from __future__ import annotations

import os
import signal
import time
from contextlib import ExitStack
from pathlib import Path
from typing import Callable, Iterator, Mapping

import pytest

from soccer_lab.soccer.rcss.servers import (EXECUTABLE_VARIABLE, RcssLaunchError, RcssServerProcess, ServerPool,
                                            find_rcssserver)

REPOSITORY = Path(__file__).resolve().parents[2]
SHARED_SERVER = Path("shared/rcss/server/bin/rcssserver")
NO_SERVER = (f"no rcssserver: install the RoboCup soccer simulator's rcssserver 19 and put it on PATH, or set "
             f"{EXECUTABLE_VARIABLE}=/path/to/rcssserver")

StartServers = Callable[..., ServerPool]


def rcssserver_executable() -> Path | None:
    if os.environ.get(EXECUTABLE_VARIABLE):
        return find_rcssserver()  # a variable naming nothing is a mistake to report, not a reason to skip
    try:
        return find_rcssserver()
    except RcssLaunchError:
        pass
    for folder in (REPOSITORY, *REPOSITORY.parents):
        candidate = folder / SHARED_SERVER
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    return None


@pytest.fixture(scope="session")
def rcssserver() -> Path:
    """The rcssserver executable (the test skips without one)."""
    executable = rcssserver_executable()
    if executable is None:
        pytest.skip(NO_SERVER)
    return executable


@pytest.fixture
def start_servers(rcssserver: Path) -> Iterator[StartServers]:
    """`start_servers(count=1, options=None)`: a started ServerPool; every pool stops after the test."""
    with ExitStack() as stack:
        def start(count: int = 1, options: Mapping[str, str] | None = None) -> ServerPool:
            return stack.enter_context(ServerPool(rcssserver, count, options))

        yield start


def process_exists(pid: int) -> bool:
    """True while `pid` is a live (not zombie) process."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return False
    return state != "Z"


def wait_until_gone(pids: list[int], seconds: float = 10.0) -> list[int]:
    """The pids still alive after waiting up to `seconds` for them to end."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        alive = [pid for pid in pids if process_exists(pid)]
        if not alive:
            return []
        time.sleep(0.05)
    return [pid for pid in pids if process_exists(pid)]


def rcssserver_children() -> set[int]:
    """PIDs of the live rcssserver processes this process started."""
    children = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            name, rest = stat.read_text().split(") ", 1)
        except (FileNotFoundError, ProcessLookupError, ValueError):
            continue
        state, parent = rest.split()[:2]
        if name.endswith("(rcssserver") and int(parent) == os.getpid() and state != "Z":
            children.add(int(stat.parent.name))
    return children


def kill(server: RcssServerProcess) -> None:
    """Kill a server the way a crash would: SIGKILL, no goodbye."""
    try:
        os.kill(server.pid, signal.SIGKILL)
    except ProcessLookupError:  # already gone (a test's teardown may have stopped it first)
        pass
    server.process.wait(10)


def connected_players(server: RcssServerProcess) -> int:
    """How many players connected to this server, from its log (the server prints one line each)."""
    log = (server.folder / "rcssserver.log").read_text(errors="replace")
    return log.count("A new (v19) player")
