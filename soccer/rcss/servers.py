"""rcssservers that soccer-lab starts itself.

`ServerPool(executable, count)` is a context manager: it starts `count` servers, each on free ports
(player P, trainer P+1, online coach P+2) in its own scratch folder (rcssserver writes `./~/.rcssserver/`
into its working folder), with the options trials need, waits until each answers, and stops every one
when the block ends, by its own PID and process group, also on Ctrl+C or an exception. Servers outlive
nothing else either: each runs in its own process group (a terminal's Ctrl+C reaches soccer-lab, which
stops them in order), an atexit hook stops any still running when the interpreter exits, SIGTERM to
soccer-lab ends the block like Ctrl+C, and on Linux each server gets SIGKILL from the kernel when the
thread that started it dies (prctl PR_SET_PDEATHSIG), so even `kill -9` of soccer-lab leaves none behind.
Start and stop a pool in the same thread: that thread is the servers' parent for PR_SET_PDEATHSIG.
"""

from __future__ import annotations

import atexit
import ctypes
import ctypes.util
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import threading
import time
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping, Sequence

from soccer_lab.soccer.rcss.client import DEFAULT_HOST
from soccer_lab.soccer.rcss.errors import RcssError

EXECUTABLE_NAME = "rcssserver"
EXECUTABLE_VARIABLE = "RCSSSERVER"  # an environment variable naming the executable
# What trials need (docs/robocup/index.md): the server steps when the clients say (done); the offline trainer
# places ball and player while the referees still announce goals and out-of-play; nothing is logged;
# the clock never reaches half time (a negative half_time switches the referee's time keeping off);
# no offside, free-kick faults, extra time or penalties to end a trial early.
TRIAL_OPTIONS: dict[str, str] = {
    "server::synch_mode": "true",
    "server::auto_mode": "false",
    "server::coach": "true",
    "server::coach_w_referee": "true",
    "server::game_logging": "false",
    "server::text_logging": "false",
    "server::half_time": "-1",
    "server::use_offside": "false",
    "server::forbid_kick_off_offside": "false",
    "server::free_kick_faults": "false",
    "server::nr_extra_halfs": "0",
    "server::penalty_shoot_outs": "false",
}
# The server's noise switched off (NOTES: movement, turn, kick and ball noise; wind). rcssserver seeds its
# noise from the clock and takes no seed, so only without it does a trial play the same twice. Heterogeneous
# player types stay random, but our player is type 0, and see's quantisation is deterministic.
NOISELESS_OPTIONS: dict[str, str] = {
    "server::player_rand": "0",
    "server::ball_rand": "0",
    "server::kick_rand": "0",
    "server::wind_none": "true",
}


def noise_options(noise: bool) -> dict[str, str]:
    """The options (beyond TRIAL_OPTIONS) of servers for trials with or without the server's noise."""
    return {} if noise else dict(NOISELESS_OPTIONS)
LOG_FILE = "rcssserver.log"
MAX_SERVERS = 32  # each server wants about a core while it plays
START_ATTEMPTS = 5  # another program may take the free ports between our choice and the server's bind
READY_SECONDS = 10.0
STOP_SECONDS = 5.0  # after SIGTERM (the server saves its results and exits), before SIGKILL
PROBE = b"(soccer-lab-probe)\x00"  # answered with (error unknown_command) by a running server, harmlessly


class RcssLaunchError(RcssError):
    """An rcssserver that cannot be found or started; one line for the user."""


def find_rcssserver(explicit: str | os.PathLike | None = None) -> Path:
    """The executable: `explicit` (a path, or a name on PATH), else $RCSSSERVER, else `rcssserver` on PATH."""
    wanted = explicit if explicit is not None else os.environ.get(EXECUTABLE_VARIABLE) or EXECUTABLE_NAME
    where = "" if explicit is not None else f" (from ${EXECUTABLE_VARIABLE})" if os.environ.get(EXECUTABLE_VARIABLE) else ""
    found = shutil.which(str(wanted))
    if found is None:
        path = Path(wanted)
        problem = "is not executable" if path.is_file() else "does not exist" if os.sep in str(wanted) else "is not on PATH"
        raise RcssLaunchError(f"no rcssserver: {str(wanted)!r}{where} {problem}")
    return Path(found).resolve()


def free_port_triple(host: str = DEFAULT_HOST) -> int:
    """A port P with P, P+1 and P+2 free for UDP right now (player, trainer, online coach)."""
    for _ in range(100):
        with ExitStack() as stack:
            first = stack.enter_context(socket.socket(socket.AF_INET, socket.SOCK_DGRAM))
            first.bind((host, 0))
            port = first.getsockname()[1]
            if port + 2 >= 65536:
                continue
            try:
                for offset in (1, 2):
                    stack.enter_context(socket.socket(socket.AF_INET, socket.SOCK_DGRAM)).bind((host, port + offset))
            except OSError:
                continue
            return port
    raise RcssLaunchError("no three consecutive free UDP ports found for an rcssserver")


# ---- the parent-death guard (Linux) ---------------------------------------------------------------
PR_SET_PDEATHSIG = 1
_libc_name = ctypes.util.find_library("c")
_prctl = getattr(ctypes.CDLL(_libc_name, use_errno=True), "prctl", None) if _libc_name else None


def die_with_parent(parent: int):
    """preexec_fn for the server: the kernel sends SIGKILL when the starting thread dies; if the parent
    is already gone (it died between fork and here), exit at once. Resolved before the fork: the child
    only calls into libc."""
    if _prctl is None:
        return None

    def guard() -> None:
        _prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:
            os._exit(1)

    return guard


# ---- one server --------------------------------------------------------------------------------------
@dataclass(eq=False)  # identity: the set of live servers holds them
class RcssServerProcess:
    """One running rcssserver: its process, ports and scratch folder."""

    process: subprocess.Popen
    port: int
    folder: Path
    host: str = DEFAULT_HOST

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    @property
    def pid(self) -> int:
        return self.process.pid

    @property
    def running(self) -> bool:
        return self.process.poll() is None

    def log_tail(self, lines: int = 3) -> str:
        try:
            text = (self.folder / LOG_FILE).read_text(errors="replace")
        except OSError:
            return ""
        useful = [line.strip() for line in text.splitlines() if line.strip()]
        return " / ".join(useful[-lines:])

    def stop(self) -> None:
        """SIGTERM to its process group, SIGKILL if it has not exited within STOP_SECONDS; then remove
        its scratch folder."""
        if self.running:
            _signal_group(self.process, signal.SIGTERM)
            try:
                self.process.wait(STOP_SECONDS)
            except subprocess.TimeoutExpired:
                _signal_group(self.process, signal.SIGKILL)
                self.process.wait()
        shutil.rmtree(self.folder, ignore_errors=True)


def _signal_group(process: subprocess.Popen, number: int) -> None:
    try:
        os.killpg(process.pid, number)  # its own group (process_group=0): the server and nothing else of ours
    except ProcessLookupError:
        pass


class _LiveServers:
    """Every server this process started and has not stopped: stopped at interpreter exit."""

    def __init__(self) -> None:
        self._servers: set[RcssServerProcess] = set()
        self._lock = threading.Lock()
        atexit.register(self.stop_all)

    def add(self, server: RcssServerProcess) -> None:
        with self._lock:
            self._servers.add(server)

    def discard(self, server: RcssServerProcess) -> None:
        with self._lock:
            self._servers.discard(server)

    def stop_all(self) -> None:
        with self._lock:
            servers, self._servers = list(self._servers), set()
        for server in servers:
            server.stop()


_LIVE = _LiveServers()


def launch_server(executable: Path, options: Mapping[str, str] = TRIAL_OPTIONS,
                  host: str = DEFAULT_HOST) -> RcssServerProcess:
    """Start one rcssserver on free ports in a new scratch folder (not yet waited for)."""
    port = free_port_triple(host)
    folder = Path(tempfile.mkdtemp(prefix="soccer-lab-rcssserver-"))
    arguments = [f"server::port={port}", f"server::coach_port={port + 1}", f"server::olcoach_port={port + 2}",
                 *(f"{name}={value}" for name, value in options.items())]
    with (folder / LOG_FILE).open("wb") as log:
        try:
            process = subprocess.Popen([str(executable), *arguments], cwd=folder, stdin=subprocess.DEVNULL,
                                       stdout=log, stderr=subprocess.STDOUT, process_group=0,
                                       preexec_fn=die_with_parent(os.getpid()))
        except OSError as exc:
            shutil.rmtree(folder, ignore_errors=True)
            raise RcssLaunchError(f"cannot start rcssserver {executable}: {exc.strerror or exc}") from None
    server = RcssServerProcess(process, port, folder, host)
    _LIVE.add(server)
    return server


def start_servers(executable: Path, count: int, options: Mapping[str, str] = TRIAL_OPTIONS,
                  host: str = DEFAULT_HOST, ready_seconds: float = READY_SECONDS) -> list[RcssServerProcess]:
    """Start `count` servers at once and wait until each answers. A server whose ports another program
    took meanwhile is started again on others; any other failure stops them all (RcssLaunchError)."""
    servers: list[RcssServerProcess] = []
    wanted = count
    try:
        for _ in range(START_ATTEMPTS):
            launched = [launch_server(executable, options, host) for _ in range(wanted)]  # from this thread
            ready = _wait_until_ready(launched, ready_seconds)
            servers += [server for server, answered in zip(launched, ready) if answered]
            failed = [server for server, answered in zip(launched, ready) if not answered]
            if not failed:
                return servers
            problems = [server.log_tail() or f"exit status {server.process.returncode}" for server in failed]
            for server in failed:
                stop_server(server)
            if not all("Error initializing sockets" in problem for problem in problems):
                raise RcssLaunchError(f"rcssserver {executable} did not start: {problems[0]}")
            wanted = len(failed)
        raise RcssLaunchError(f"rcssserver {executable} did not start: its ports were taken {START_ATTEMPTS} times")
    except BaseException:
        for server in servers:
            stop_server(server)
        raise


def stop_server(server: RcssServerProcess) -> None:
    server.stop()
    _LIVE.discard(server)


def _wait_until_ready(servers: Sequence[RcssServerProcess], seconds: float) -> list[bool]:
    """For each server, True once it answers on its player port; False if it exits or stays silent."""
    ready = [False] * len(servers)
    deadline = time.monotonic() + seconds
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.settimeout(0.02)
        while time.monotonic() < deadline:
            waiting = [i for i, server in enumerate(servers) if not ready[i] and server.running]
            if not waiting:
                break
            for i in waiting:
                probe.sendto(PROBE, (servers[i].host, servers[i].port))
            try:
                while True:
                    _, (_, port) = probe.recvfrom(256)
                    ready = [r or s.port == port for r, s in zip(ready, servers)]
            except OSError:  # a timeout, or a port refused: the rest are not bound yet
                pass
    return ready


class ServerPool:
    """`count` rcssservers started together (in parallel) and stopped together."""

    def __init__(self, executable: str | os.PathLike | None = None, count: int = 1,
                 options: Mapping[str, str] | None = None, host: str = DEFAULT_HOST):
        if not 1 <= count <= MAX_SERVERS:
            raise ValueError(f"between 1 and {MAX_SERVERS} servers, not {count}")
        self.executable = find_rcssserver(executable)
        self.count = count
        self.options = {**TRIAL_OPTIONS, **(options or {})}
        self.host = host
        self.servers: list[RcssServerProcess] = []
        self._previous_sigterm = None

    @property
    def addresses(self) -> list[str]:
        """HOST:PORT of each server's player port, as `--server` takes them."""
        return [server.address for server in self.servers]

    def start(self) -> "ServerPool":
        self.servers = start_servers(self.executable, self.count, self.options, self.host)
        return self

    def stop(self) -> None:
        servers, self.servers = self.servers, []
        for server in servers:
            stop_server(server)

    def __enter__(self) -> "ServerPool":
        self._catch_sigterm()
        try:
            return self.start()
        except BaseException:
            self._restore_sigterm()
            raise

    def __exit__(self, *exc_info: object) -> None:
        try:
            self.stop()
        finally:
            self._restore_sigterm()

    def _catch_sigterm(self) -> None:
        """SIGTERM (e.g. `kill`) ends the block like Ctrl+C, so the servers are stopped; only when this is
        the main thread and nobody else handles SIGTERM."""
        if threading.current_thread() is threading.main_thread() and signal.getsignal(signal.SIGTERM) == signal.SIG_DFL:
            self._previous_sigterm = signal.signal(signal.SIGTERM, _interrupt)

    def _restore_sigterm(self) -> None:
        if self._previous_sigterm is not None:
            signal.signal(signal.SIGTERM, self._previous_sigterm)
            self._previous_sigterm = None


def _interrupt(number: int, frame: object) -> None:
    raise KeyboardInterrupt(f"signal {number}")


def describe(servers: Sequence[RcssServerProcess]) -> str:
    """One line naming the servers, e.g. for a command's stderr."""
    listed = ", ".join(f"{server.address} (pid {server.pid})" for server in servers)
    return f"started {len(servers)} rcssserver{'s' if len(servers) != 1 else ''}: {listed}"
