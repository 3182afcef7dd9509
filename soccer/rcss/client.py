"""UDP clients for rcssserver: one player and the offline trainer, in synch mode.

Protocol facts (tests/rcss/transcripts/NOTES.md): init goes to the well-known port (6000 player, 6001
trainer); every later message goes to the address the replies came from; every datagram ends in NUL.
In synch mode each cycle ends with `(think)`; the server then waits for `(done)` from the player and,
while its eye is on, from the trainer. Every wait has a deadline, so a silent server gives an
RcssError within seconds instead of a hang.

The server waits SERVER_WAIT for a cycle's (done), then steps on without it. A (done) sent later would
count for whichever cycle the server is in by then, and every answer after it would be one cycle late.
So a session answers a cycle only within ANSWER_WITHIN of reading it; a client that took longer (a
stall, or the pause between two evaluations) answers nothing, reads what the server sent meanwhile,
and takes up the next cycle that arrives.

The server steps only when the client has answered, so the client spends as little as it can per
cycle: each socket is non-blocking and connected to the server's reply port after init, a read that
finds a datagram queued costs one system call, and a client with nothing to read sleeps in poll()
until the server sends (never a busy wait). A session waits on the trainer, whose (think) the server
sends last, so it wakes about once a cycle and finds the player's messages already queued. The
player's commands and its (done) travel in one datagram (the server reads a datagram as a list of
commands).
"""

from __future__ import annotations

import math
import select
import socket
import time
from collections import deque
from dataclasses import dataclass, field

from soccer_lab.soccer.rcss.errors import (RcssCommandError, RcssConfigError, RcssNoServerError, RcssRefusedError,
                                           RcssTimeoutError)
from soccer_lab.soccer.rcss.messages import (ErrorReply, Hear, Message, Ok, PlayerInit, See, SeeGlobal, SenseBody,
                                             ServerParamMessage, Think, TrainerInit, parse_message)
from soccer_lab.soccer.rcss.params import ServerParams

PROTOCOL_VERSION = 19
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PLAYER_PORT = 6000
DEFAULT_SERVER = f"{DEFAULT_HOST}:{DEFAULT_PLAYER_PORT}"
DEFAULT_TEAM = "SoccerLab"
DATAGRAM_SIZE = 8192
SERVER_WAIT = 1.25  # seconds rcssserver waits for a cycle's (done) (stadium.cpp: 25 x 50 ms)
ANSWER_WITHIN = SERVER_WAIT - 0.15  # to answer a cycle in time, with room for the datagram's trip


@dataclass(frozen=True)
class Timeouts:
    """Seconds. A server that withholds a cycle for a missing (done) waits 1.25 s, so `cycle` > 1.25."""

    connect: float = 2.0
    cycle: float = 3.0


def parse_server(address: str) -> tuple[str, int]:
    """'HOST:PORT' (or 'HOST', port 6000) -> (host, port); ValueError with a clear message."""
    host, _, port_text = address.rpartition(":") if ":" in address else (address, "", str(DEFAULT_PLAYER_PORT))
    try:
        port = int(port_text)
    except ValueError:
        raise ValueError(f"bad server address {address!r}: expected HOST:PORT, e.g. 127.0.0.1:6000") from None
    if not host or not 0 < port < 65535:
        raise ValueError(f"bad server address {address!r}: expected HOST:PORT, e.g. 127.0.0.1:6000")
    return host, port


class Endpoint:
    """One UDP conversation with the server: init to the well-known port, then with the reply port."""

    def __init__(self, role: str, host: str, port: int, timeouts: Timeouts, where: str | None = None):
        self.role = role
        self.init_address = (host, port)
        self.where = where or f"{host}:{port}"  # the server, as errors name it
        self.timeouts = timeouts
        self.socket = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.socket.bind(("0.0.0.0", 0))
        self.socket.setblocking(False)
        self._poll = select.poll()
        self._poll.register(self.socket, select.POLLIN)
        self._held: bytes | None = None  # a datagram read ahead by more_waiting()

    def send(self, text: str) -> None:
        try:
            self.socket.send(text.encode("ascii") + b"\x00")
        except OSError as exc:
            raise self._gone(exc) from None

    def receive(self, deadline: float, waiting_for: str) -> Message:
        """The next message; RcssTimeoutError when none arrives by `deadline` (time.monotonic())."""
        data, self._held = self._held, None
        while data is None:
            data = self._read()
            if data is None and not self._poll.poll(max(math.ceil((deadline - time.monotonic()) * 1000), 0)):
                raise RcssTimeoutError(
                    f"{self.role}: rcssserver at {self.where} sent nothing for {self.timeouts.cycle:g} s "
                    f"while we waited for {waiting_for} (did the server quit?)"
                )
        return parse_message(data)

    def more_waiting(self) -> bool:
        """A datagram is already queued (the server has moved on to another cycle)."""
        if self._held is None:
            self._held = self._read()
        return self._held is not None

    def _read(self) -> bytes | None:
        """A queued datagram, or None."""
        try:
            return self.socket.recv(DATAGRAM_SIZE)
        except BlockingIOError:
            return None
        except OSError as exc:
            raise self._gone(exc) from None

    def _gone(self, error: OSError) -> RcssNoServerError:
        if isinstance(error, ConnectionRefusedError):  # the kernel's answer to a datagram sent to a closed port
            return RcssNoServerError(f"{self.role}: rcssserver at {self.where} is gone: its port refuses messages "
                                     "(did the server quit?)")
        return RcssNoServerError(f"{self.role}: cannot talk to rcssserver at {self.where}: {error}")

    def initialise(self, text: str) -> Message:
        """Send init and return the first reply, then talk only with the port it came from;
        RcssNoServerError when nobody answers in time."""
        try:
            self.socket.sendto(text.encode("ascii") + b"\x00", self.init_address)
        except OSError as exc:  # e.g. a host name that does not resolve
            raise RcssNoServerError(f"{self.role}: cannot reach rcssserver at {self.where}: {exc}") from None
        if not self._poll.poll(self.timeouts.connect * 1000):
            raise RcssNoServerError(
                f"{self.role}: no reply from rcssserver at {self.where} within {self.timeouts.connect:g} s "
                "(is it running, on this host and port?)"
            )
        try:
            data, source = self.socket.recvfrom(DATAGRAM_SIZE)
        except OSError as exc:
            raise RcssNoServerError(f"{self.role}: cannot talk to rcssserver at {self.where}: {exc}") from None
        self.socket.connect(source)  # after init the server answers from a port of its own for this client
        return parse_message(data)

    def close(self) -> None:
        self.socket.close()


@dataclass
class PlayerCycle:
    """What the player received during one cycle, up to and including (think)."""

    sense_body: SenseBody
    see: See | None = None
    hears: list[Hear] = field(default_factory=list)


@dataclass
class TrainerCycle:
    see_global: SeeGlobal | None = None
    hears: list[Hear] = field(default_factory=list)


class PlayerClient:
    def __init__(self, host: str, port: int, team: str = DEFAULT_TEAM, timeouts: Timeouts = Timeouts()):
        self.team = team
        self.endpoint = Endpoint("player", host, port, timeouts)
        self.timeouts = timeouts
        self.side = ""
        self.unum = 0
        self.params: ServerParams | None = None
        self.answer_by = 0.0  # time.monotonic() by which the cycle last read must be answered
        self._sense_body: SenseBody | None = None  # the cycle being read
        self._see: See | None = None
        self._hears: list[Hear] = []

    def connect(self) -> PlayerCycle:
        """Init, read the server's parameters, and return the first cycle (time 0, before kick-off)."""
        reply = self.endpoint.initialise(f"(init {self.team} (version {PROTOCOL_VERSION}))")
        if isinstance(reply, ErrorReply):
            raise RcssRefusedError(f"player: rcssserver refused init: {reply.reason}")
        if not isinstance(reply, PlayerInit):
            raise RcssRefusedError(f"player: unexpected reply to init: {reply!r}"[:200])
        self.side, self.unum = reply.side, reply.unum
        return self.read_cycle()

    def read_cycle(self) -> PlayerCycle:
        """Messages up to the newest (think). A server_param on the way sets `params` (and is checked).
        Later cycles queued behind a (think) (the server stepped on without us) are read on to the
        newest; its age is then unknown, so `answer_by` says it cannot be answered."""
        deadline = time.monotonic() + self.timeouts.cycle
        skipped = False
        while True:
            message = self.endpoint.receive(deadline, "(think)")
            if not isinstance(message, Think):
                self._take(message)
            elif self.endpoint.more_waiting():
                skipped = True
            elif self._sense_body is None:
                raise RcssConfigError("player: (think) without sense_body; is the server in synch mode?")
            else:
                cycle = PlayerCycle(self._sense_body, self._see, self._hears)
                self._sense_body, self._see, self._hears = None, None, []
                self.answer_by = 0.0 if skipped else time.monotonic() + ANSWER_WITHIN
                return cycle

    def read_backlog(self) -> None:
        """Read what is queued (cycles the server went through without us); their hears go with the next
        cycle read."""
        while self.endpoint.more_waiting():
            message = self.endpoint.receive(time.monotonic(), "queued messages")
            if not isinstance(message, Think):
                self._take(message)

    def _take(self, message: Message) -> None:
        if isinstance(message, SenseBody):
            self._sense_body, self._see = message, None  # a see follows its cycle's sense_body
        elif isinstance(message, See):
            self._see = message
        elif isinstance(message, Hear):
            self._hears.append(message)
        elif isinstance(message, ServerParamMessage):
            self.params = ServerParams.from_message(message.values)
            self.params.check_usable()
        elif isinstance(message, ErrorReply):
            raise RcssCommandError(f"player: rcssserver rejected a command: {message.reason}")

    def act(self, commands: list[str]) -> None:
        """This cycle's body commands, then (done), in one datagram."""
        self.endpoint.send("".join(commands) + "(done)")

    def bye(self) -> None:
        self.endpoint.send("(bye)")

    def close(self) -> None:
        self.endpoint.close()


class TrainerClient:
    """The offline trainer: places ball and player, sets play modes, sees everything (eye on)."""

    def __init__(self, host: str, port: int, timeouts: Timeouts = Timeouts(), server: str | None = None):
        """`server`: the server's player address, for errors to name it as the user gave it."""
        self.endpoint = Endpoint("trainer", host, port, timeouts, f"{server} (trainer port {port})" if server else None)
        self.timeouts = timeouts
        self.pending: deque[str] = deque()  # commands awaiting (ok ...), oldest first
        self._cycle = TrainerCycle()  # the cycle being read

    def connect(self) -> None:
        reply = self.endpoint.initialise(f"(init (version {PROTOCOL_VERSION}))")
        if isinstance(reply, ErrorReply):
            raise RcssRefusedError(
                f"trainer: rcssserver refused the offline trainer ({reply.reason}); "
                "start it with server::coach=true server::coach_w_referee=true"
            )
        if not isinstance(reply, TrainerInit):
            raise RcssRefusedError(f"trainer: unexpected reply to init: {reply!r}"[:200])

    def command(self, text: str) -> None:
        """Send a command that the server acknowledges with (ok NAME ...)."""
        self.pending.append(text)
        self.endpoint.send(text)

    def move_ball(self, x: float, y: float) -> None:
        """The ball at rest at (x, y): rcssserver's coach takes 2 numbers (velocity 0) or 5 for the ball."""
        self.command(f"(move (ball) {x:.4f} {y:.4f})")

    def move_player(self, team: str, unum: int, x: float, y: float, body: float) -> None:
        self.command(f"(move (player {team} {unum}) {x:.4f} {y:.4f} {body:.2f} 0 0)")

    def change_mode(self, mode: str) -> None:
        self.command(f"(change_mode {mode})")

    def done(self) -> None:
        self.endpoint.send("(done)")

    def watch(self) -> None:
        """Eye and ear on (sent with the next done): every object seen, the referee heard."""
        self.command("(eye on)")
        self.command("(ear on)")

    def stop_watching(self) -> None:
        """Ear and eye off before leaving, so the server does not free-run; a server already gone is no matter."""
        try:
            self.endpoint.send("(ear off)")
            self.endpoint.send("(eye off)")
        except RcssNoServerError:
            pass

    def read_cycle(self) -> TrainerCycle:
        """Messages up to the newest (think) (as the player's); every pending command must have been
        acknowledged. The server acknowledges a command before the (think) that follows it: a (think)
        with commands pending is an older cycle's (the client fell behind), so reading goes on."""
        deadline = time.monotonic() + self.timeouts.cycle
        while True:
            try:
                message = self.endpoint.receive(deadline, "(think)")
            except RcssTimeoutError:
                if self.pending:
                    raise RcssCommandError(  # named as the other timeouts: a server killed mid-trial lands here too
                        f"trainer: rcssserver at {self.endpoint.where} did not answer {self.pending[0]} within "
                        f"{self.timeouts.cycle:g} s (did the server quit?)") from None
                raise
            if not isinstance(message, Think):
                self._take(message)
            elif not self.pending and not self.endpoint.more_waiting():
                cycle, self._cycle = self._cycle, TrainerCycle()
                return cycle

    def read_backlog(self) -> None:
        """Read what is queued (as the player's); hears and acknowledgements are kept."""
        while self.endpoint.more_waiting():
            message = self.endpoint.receive(time.monotonic(), "queued messages")
            if not isinstance(message, Think):
                self._take(message)

    def _take(self, message: Message) -> None:
        if isinstance(message, SeeGlobal):
            self._cycle.see_global = message
        elif isinstance(message, Hear):
            self._cycle.hears.append(message)
        elif isinstance(message, Ok):
            self._acknowledge(message.command)
        elif isinstance(message, ErrorReply):
            command = self.pending[0] if self.pending else "a command"
            raise RcssCommandError(f"trainer: rcssserver rejected {command}: {message.reason}")

    def _acknowledge(self, name: str) -> None:
        for index, command in enumerate(self.pending):
            if command[1:].split(" ", 1)[0].rstrip(")") == name:
                del self.pending[index]
                return
        # an ok we did not ask for (another tool talking to this trainer): nothing to match

    def close(self) -> None:
        self.endpoint.close()


class Session:
    """A player and the trainer on one server, stepping cycle by cycle in synch mode."""

    def __init__(
        self,
        server: str = DEFAULT_SERVER,
        trainer_port: int | None = None,
        team: str = DEFAULT_TEAM,
        timeouts: Timeouts = Timeouts(),
    ):
        host, port = parse_server(server)
        self.server = server
        self.player = PlayerClient(host, port, team, timeouts)
        self._trainer_address = (host, trainer_port)
        self.trainer: TrainerClient | None = None
        self.last_player_cycle: PlayerCycle | None = None
        self.time = 0
        self.late_cycles = 0  # cycles read too late to answer (the server stepped on without our commands)

    @property
    def params(self) -> ServerParams:
        if self.player.params is None:
            raise RcssConfigError("player: rcssserver sent no server_param after init")
        return self.player.params

    def open(self) -> PlayerCycle:
        """Connect player then trainer; the trainer turns its eye and ear on (sent with the next done)."""
        try:
            first = self.player.connect()
            params = self.params
            host, port = self._trainer_address
            self.trainer = TrainerClient(host, port or params.coach_port, self.player.timeouts, self.server)
            self.trainer.connect()
        except BaseException:
            self.close()
            raise
        self.trainer.watch()
        self.last_player_cycle = first
        return first

    def step(self, player_commands: list[str]) -> tuple[PlayerCycle, TrainerCycle]:
        """Send this cycle's commands and both (done)s; return what arrived by the next (think). Past
        `answer_by` the commands are dropped: the server has stepped on (or is about to), and the next
        cycle it sends on its own is returned instead."""
        assert self.trainer is not None, "open() the session first"
        if time.monotonic() <= self.player.answer_by:
            self.player.act(player_commands)
            self.trainer.done()
        else:
            self.late_cycles += 1
            self.player.read_backlog()
            self.trainer.read_backlog()
        trainer_cycle = self.trainer.read_cycle()  # the server sends the trainer's (think) last
        player_cycle = self.player.read_cycle()
        self.last_player_cycle = player_cycle
        self.time = player_cycle.sense_body.time
        return player_cycle, trainer_cycle

    def close(self) -> None:
        """Leave politely: ear and eye off first so the server does not free-run, then bye."""
        if self.trainer is not None:
            self.trainer.stop_watching()
        try:
            self.player.bye()
            if self.trainer is not None:
                self.trainer.done()
        except RcssNoServerError:
            pass
        self.player.close()
        if self.trainer is not None:
            self.trainer.close()

    def __enter__(self) -> "Session":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
