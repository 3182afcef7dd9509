"""Stand-ins for rcssserver in the app's tests: servers that replay one recorded trial each, and a
server that never answers."""

from __future__ import annotations

import re
import socket
from contextlib import ExitStack, contextmanager
from typing import Iterator

from soccer_lab.soccer.rcss.client import DEFAULT_TEAM
from tests.rcss.replay import Line, ReplayServer, read_transcript, with_fresh_start
from tests.rcss.conftest import GOALS, OUT_OF_PLAY, TRANSCRIPTS, player_thinks, without_error_probes

# The recorded trials: 3 goals in 451 cycles (fitness 1/6), and a kick-in after 12 cycles with one kick
# (robocup-composite 1 - 1/24). A GA generation of two rulebases plays one trial on each server.
GOALS_CYCLES = player_thinks(without_error_probes(read_transcript(GOALS))) - 1 if GOALS.exists() else 0
GOALS_FITNESS = 1 / 6
KICK_IN_FITNESS = 1 - 1 / 24
COACH_PORT = re.compile(r"\(coach_port \d+\)")
RECORDED_TEAM = '"LabTeam"'  # as the transcripts' see_global names the player's team


def replay_server(path) -> ReplayServer:
    """A server replaying `path`; its server_param names the replay's own trainer port, and its see_global
    our client's team (a real server names the team the player gave in its init; the recording's player
    gave RECORDED_TEAM)."""
    lines = with_fresh_start(without_error_probes(read_transcript(path)))
    server = ReplayServer(lines, client_timeout=30.0)  # a client process starts in seconds on a busy machine
    coach_port = f"(coach_port {server.trainer_port})"
    team = f'"{DEFAULT_TEAM}"'
    server.lines = [Line(l.number, l.sent, l.role, COACH_PORT.sub(coach_port, l.text).replace(RECORDED_TEAM, team))
                    for l in lines]
    return server


@contextmanager
def two_recorded_trials() -> Iterator[tuple[ReplayServer, ReplayServer]]:
    """The goals server and the kick-in server, running."""
    with ExitStack() as stack:
        yield stack.enter_context(replay_server(GOALS)), stack.enter_context(replay_server(OUT_OF_PLAY))


@contextmanager
def silent_server() -> Iterator[str]:
    """HOST:PORT of a socket that takes init messages and never answers (a server that hangs)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(("127.0.0.1", 0))
        yield f"127.0.0.1:{sock.getsockname()[1]}"


def transcripts_missing() -> str | None:
    return None if GOALS.exists() and OUT_OF_PLAY.exists() else f"rcssserver transcripts not found in {TRANSCRIPTS}"
