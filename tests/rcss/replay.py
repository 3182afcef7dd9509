"""Recorded rcssserver conversations, and a loopback server that replays them.

A transcript line is `>P msg` / `<P msg` (sent / received by the player), `>T msg` / `<T msg` (the
trainer); `#` lines are annotations. `ReplayServer` plays the server's side on 127.0.0.1 (ephemeral
ports): it sends the recorded `<` lines in order and, at each recorded `(init ...)`, `(done)` and
`(bye)` of a client, waits until the client under test sends the same, keeping what else the client
sent that cycle. The client's own commands may differ from the recording (the server's answers do
not depend on them in the replay), so only these anchors synchronise. A datagram may hold several
commands, as the real server allows (the player sends its commands and `(done)` together). Like the real server, replies
come from a port other than the init port, and anything but init sent to the init port is answered
with `(error only_init_allowed_on_init_port)`.
"""

from __future__ import annotations

import select
import socket
import threading
from dataclasses import dataclass, field
from pathlib import Path

PLAYER, TRAINER = "P", "T"
ANCHORS = ("(done)", "(bye)")


@dataclass(frozen=True)
class Line:
    number: int  # 1-based line in the file
    sent: bool  # True: the client sent it (`>`); False: the server did (`<`)
    role: str  # PLAYER or TRAINER
    text: str


def read_transcript(path: str | Path) -> list[Line]:
    lines = []
    for number, raw in enumerate(Path(path).read_text().splitlines(), start=1):
        if len(raw) < 3 or raw[0] not in "<>" or raw[1] not in (PLAYER, TRAINER):
            continue  # annotation or blank
        text = raw[3:].split("    [", 1)[0].rstrip()  # drop "    [sent WITHOUT trailing NUL]" notes
        lines.append(Line(number, raw[0] == ">", raw[1], text))
    return lines


def with_fresh_start(lines: list[Line]) -> list[Line]:
    """The recording as a client that starts each trial fresh (soccer/rcss/trial.py, Trial.fresh_start) meets
    it: the recorded client placed ball and player in its first cycle, ours first sends (recover), a change
    to before_kick_off and the ball to the centre spot, and places them one cycle later. So after the first
    cycle's (done)s comes a cycle the recording lacks, as a real server answers it: the acknowledgements
    (and the referee's announcement), the clock still at 0, no see (the placing cycle has none). The
    recorded acknowledgements that follow answer commands our client has sent by then or never sends
    (it ignores an ok it did not ask for). Inserted lines carry the number of the (done) they follow."""
    first_sense_body = next(l.text for l in lines if not l.sent and l.role == PLAYER and l.text.startswith("(sense_body"))
    team = next((l.text.split("(init ", 1)[1].split(" ", 1)[0] for l in lines
                 if l.sent and l.role == PLAYER and l.text.startswith("(init ")), "LabTeam")
    done = next(i for i, l in enumerate(lines) if l.sent and l.role == TRAINER and l.text == "(done)")
    number = lines[done].number
    received = [(TRAINER, "(ok eye on)"), (TRAINER, "(ok ear on)"), (TRAINER, "(ok recover)"),
                (TRAINER, "(hear referee 0 before_kick_off)"), (PLAYER, "(hear 0 referee before_kick_off)"),
                (TRAINER, "(ok change_mode)"), (TRAINER, "(ok move)"), (PLAYER, first_sense_body),
                (TRAINER, f'(see_global 0 ((g r) 52.5 0) ((g l) -52.5 0) ((b) 0 0 0 0) ((p "{team}" 1) -15 0 0 0 0 0))'),
                (PLAYER, "(think)"), (TRAINER, "(think)")]
    inserted = [Line(number, False, role, text) for role, text in received]
    inserted += [Line(number, True, PLAYER, "(done)"), Line(number, True, TRAINER, "(done)")]
    return lines[:done + 1] + inserted + lines[done + 1:]


@dataclass
class ReplayLog:
    """What the client did: per role, the commands sent in each cycle (cycle = anchors so far)."""

    commands: dict[str, list[list[str]]] = field(default_factory=lambda: {PLAYER: [[]], TRAINER: [[]]})
    init_port_misuse: list[str] = field(default_factory=list)
    left_at: int | None = None  # transcript line at which the client sent (bye) instead of (done)
    finished: bool = False  # the whole script was played
    error: str | None = None


class ReplayServer:
    def __init__(self, lines: list[Line], client_timeout: float = 10.0, stop_before_line: int | None = None):
        self.lines = lines
        self.client_timeout = client_timeout
        self.stop_before_line = stop_before_line  # simulate a server that dies there
        self.log = ReplayLog()
        self.sockets = {}
        for name in ("P init", "T init", "P", "T"):
            sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            sock.bind(("127.0.0.1", 0))
            self.sockets[name] = sock
        self.clients: dict[str, tuple[str, int]] = {}
        self._queued: dict[str, list[str]] = {PLAYER: [], TRAINER: []}  # commands received, not yet matched
        self._thread = threading.Thread(target=self._run, name="rcss-replay", daemon=True)

    @property
    def player_port(self) -> int:
        return self.sockets["P init"].getsockname()[1]

    @property
    def trainer_port(self) -> int:
        return self.sockets["T init"].getsockname()[1]

    @property
    def server(self) -> str:
        return f"127.0.0.1:{self.player_port}"

    def __enter__(self) -> "ReplayServer":
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._thread.join(timeout=self.client_timeout + 5)
        for sock in self.sockets.values():
            sock.close()

    def wait(self) -> ReplayLog:
        self._thread.join(timeout=self.client_timeout + 5)
        return self.log

    # ---- the server's side ------------------------------------------------------------------
    def _run(self) -> None:
        try:
            for line in self.lines:
                if self.stop_before_line is not None and line.number >= self.stop_before_line:
                    return
                if not line.sent:
                    self.sockets[line.role].sendto(line.text.encode("ascii") + b"\x00", self.clients[line.role])
                elif line.text.startswith("(init"):
                    self._await_init(line)
                elif line.text in ANCHORS:
                    if not self._await_anchor(line):
                        return
            self.log.finished = True
        except Exception as exc:  # reported to the test through the log, never lost in the thread
            self.log.error = f"line {line.number}: {exc}"

    def _receive(self, role: str, waiting_for: str) -> tuple[str, tuple[str, int], bool]:
        """(text, source, came to the init port) of the next datagram for `role`."""
        session, init = self.sockets[role], self.sockets[f"{role} init"]
        ready, _, _ = select.select([session, init], [], [], self.client_timeout)
        if not ready:
            raise TimeoutError(f"client {role} sent nothing for {self.client_timeout} s; expected {waiting_for}")
        sock = init if init in ready else session
        data, source = sock.recvfrom(65536)
        return data.rstrip(b"\x00").decode("ascii"), source, sock is init

    def _await_init(self, line: Line) -> None:
        text, source, to_init_port = self._receive(line.role, line.text)
        if not to_init_port or not text.startswith("(init"):
            raise AssertionError(f"expected {line.text} on the init port, got {text!r}")
        self.clients[line.role] = source

    def _await_anchor(self, line: Line) -> bool:
        while True:
            if not self._queued[line.role]:
                text, source, to_init_port = self._receive(line.role, line.text)
                if to_init_port:
                    self.log.init_port_misuse.append(text)
                    self.sockets[f"{line.role} init"].sendto(b"(error only_init_allowed_on_init_port)\x00", source)
                    continue
                self._queued[line.role].extend(commands_in(text))
            text = self._queued[line.role].pop(0)
            if text == line.text:
                self.log.commands[line.role].append([])
                return True
            if text == "(bye)":
                self.log.left_at = line.number
                return False
            if text in ANCHORS:
                raise AssertionError(f"expected {line.text} from {line.role}, got {text}")
            self.log.commands[line.role][-1].append(text)


def commands_in(datagram: str) -> list[str]:
    """The top-level `(...)` commands of a datagram, in order."""
    commands, depth, start = [], 0, 0
    for index, character in enumerate(datagram):
        if character == "(":
            start, depth = (index if depth == 0 else start), depth + 1
        elif character == ")":
            depth -= 1
            if depth == 0:
                commands.append(datagram[start:index + 1])
    return commands
