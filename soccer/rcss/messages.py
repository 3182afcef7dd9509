"""Typed rcssserver messages (protocol version 19), built from the s-expression reader.

`parse_message(datagram)` returns one of the classes below; a message kind we do not use is kept as
`Other` (never an error), a malformed one raises RcssParseError naming it. The formats were checked
against the transcripts in tests/rcss/transcripts (see NOTES.md there): player and trainer `hear` differ in
the order of time and sender; see objects carry 2 to 4 numbers (and more for players).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from soccer.rcss.errors import RcssParseError
from soccer.rcss.sexp import clean, parse

REFEREE = "referee"
_GOAL_MODE = re.compile(r"^goal_([lr])_(\d+)$")


@dataclass(frozen=True)
class PlayerInit:
    """`(init l 1 before_kick_off)`: our side, uniform number and the current play mode."""

    side: str
    unum: int
    play_mode: str


@dataclass(frozen=True)
class TrainerInit:
    """`(init ok)` on the trainer port."""


@dataclass(frozen=True)
class ServerParamMessage:
    values: dict[str, int | float | str]


@dataclass(frozen=True)
class PlayerParamMessage:
    """Kept raw: heterogeneous player settings we do not use."""

    values: dict[str, int | float | str]


@dataclass(frozen=True)
class PlayerTypeMessage:
    """Kept raw; our player is type 0, whose values equal server_param's."""

    values: dict[str, int | float | str]


@dataclass(frozen=True)
class Think:
    """`(think)`: the server waits for our commands and `(done)` (synch mode)."""


@dataclass(frozen=True)
class Ok:
    """`(ok COMMAND ...)`: COMMAND names the command being acknowledged."""

    command: str
    details: tuple = ()


@dataclass(frozen=True)
class ErrorReply:
    reason: str


@dataclass(frozen=True)
class WarningReply:
    reason: str


@dataclass(frozen=True)
class Hear:
    """`(hear T sender message)` (player) or `(hear sender T message)` (trainer); same object."""

    time: int
    sender: str | int | float
    message: str

    @property
    def from_referee(self) -> bool:
        return self.sender == REFEREE

    @property
    def goal(self) -> tuple[str, int] | None:
        """(side, that side's score) for a referee's `goal_l_N` / `goal_r_N`, else None."""
        match = _GOAL_MODE.match(self.message) if self.from_referee else None
        return (match.group(1), int(match.group(2))) if match else None


@dataclass(frozen=True)
class SenseBody:
    time: int
    view_quality: str
    view_width: str
    speed: float  # |v| after decay, quantised
    speed_direction: float  # degrees relative to the head
    head_angle: float
    counters: dict[str, int] = field(default_factory=dict)  # kick, dash, turn, ...: executed commands

    @property
    def kick_count(self) -> int:
        return self.counters.get("kick", 0)


@dataclass(frozen=True)
class SeenObject:
    """One object in a see: name parts such as ('f', 'r', 'b'), distance (m), direction (deg, from
    the head, negative = left) and, when reported, distance and direction change."""

    name: tuple
    distance: float
    direction: float
    distance_change: float | None = None
    direction_change: float | None = None

    @property
    def key(self) -> str:
        return " ".join(str(part) for part in self.name)

    @property
    def in_view(self) -> bool:
        """Upper-case names ((B), (F), (G), (P)) are near objects outside the view cone."""
        return not str(self.name[0]).isupper()


@dataclass(frozen=True)
class See:
    time: int
    objects: tuple[SeenObject, ...]

    def find(self, key: str) -> SeenObject | None:
        for seen in self.objects:
            if seen.key == key:
                return seen
        return None

    @property
    def ball(self) -> SeenObject | None:
        """The ball in the view cone, or None."""
        return self.find("b")

    @property
    def flags(self) -> tuple[SeenObject, ...]:
        """Flags and goals in view: the landmarks localisation uses."""
        return tuple(s for s in self.objects if s.name[0] in ("f", "g"))


@dataclass(frozen=True)
class GlobalObject:
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0


@dataclass(frozen=True)
class GlobalPlayer:
    team: str
    unum: int
    x: float
    y: float
    vx: float
    vy: float
    body: float  # degrees, global
    neck: float
    kicked: bool  # the trailing `k`: the player kicked in the last step


@dataclass(frozen=True)
class SeeGlobal:
    time: int
    ball: GlobalObject | None
    players: tuple[GlobalPlayer, ...]

    def player(self, team: str, unum: int) -> GlobalPlayer | None:
        for p in self.players:
            if p.team == team and p.unum == unum:
                return p
        return None


@dataclass(frozen=True)
class Other:
    """A message kind we do not use (e.g. change_player_type, clang); kept, never an error."""

    kind: str
    body: list


Message = (
    PlayerInit | TrainerInit | ServerParamMessage | PlayerParamMessage | PlayerTypeMessage | Think | Ok | ErrorReply
    | WarningReply | Hear | SenseBody | See | SeeGlobal | Other
)


def _pairs(items: list) -> dict:
    """`(name value)` pairs of server_param and friends; a pair with several values keeps a tuple."""
    values = {}
    for item in items:
        if isinstance(item, list) and item and isinstance(item[0], str):
            values[item[0]] = item[1] if len(item) == 2 else tuple(item[1:])
    return values


def _number(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise RcssParseError(f"expected a number for {what}, got {value!r}")
    return float(value)


def _sense_body(body: list) -> SenseBody:
    fields = {item[0]: item[1:] for item in body[2:] if isinstance(item, list) and item}
    try:
        view = fields["view_mode"]
        speed = fields["speed"]
        counters = {name: int(v[0]) for name, v in fields.items() if len(v) == 1 and isinstance(v[0], int)}
        return SenseBody(
            time=int(body[1]),
            view_quality=str(view[0]),
            view_width=str(view[1]),
            speed=_number(speed[0], "speed"),
            speed_direction=_number(speed[1], "speed direction"),
            head_angle=_number(fields["head_angle"][0], "head_angle"),
            counters=counters,
        )
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        raise RcssParseError(f"malformed sense_body: missing or bad {exc}") from exc


def _seen_object(item: list) -> SeenObject:
    if not isinstance(item, list) or len(item) < 3 or not isinstance(item[0], list):
        raise RcssParseError(f"malformed see object {item!r}")
    numbers = [_number(v, "see object") for v in item[1:] if not isinstance(v, str)]
    if len(numbers) == 1:  # far objects: direction only
        return SeenObject(tuple(item[0]), float("nan"), numbers[0])
    return SeenObject(
        tuple(item[0]),
        numbers[0],
        numbers[1],
        numbers[2] if len(numbers) > 3 else None,
        numbers[3] if len(numbers) > 3 else None,
    )


def _see_global(body: list) -> SeeGlobal:
    ball = None
    players = []
    for item in body[2:]:
        name, values = item[0], item[1:]
        if name == ["b"]:
            ball = GlobalObject(*(_number(v, "ball") for v in values[:4]))
        elif name and name[0] == "p":
            numbers = [_number(v, "player") for v in values[:6]]
            players.append(
                GlobalPlayer(str(name[1]), int(name[2]), *numbers, kicked="k" in values[6:])
            )
    return SeeGlobal(int(body[1]), ball, tuple(players))


def _hear(body: list) -> Hear:
    if len(body) < 4:
        raise RcssParseError(f"malformed hear {body!r}")
    if isinstance(body[1], int):  # player: (hear TIME SENDER MESSAGE)
        time, sender = body[1], body[2]
    else:  # trainer: (hear SENDER TIME MESSAGE)
        sender, time = body[1], body[2]
    message = body[3]
    return Hear(int(time), sender, message if isinstance(message, str) else str(message))


def parse_message(datagram: bytes | str) -> Message:
    """Parse one datagram from rcssserver into a typed message."""
    body = parse(datagram)
    if not body or not isinstance(body[0], str):
        raise RcssParseError(f"message without a kind: {clean(datagram)[:60]!r}")
    kind = body[0]
    try:
        if kind == "think":
            return Think()
        if kind == "sense_body":
            return _sense_body(body)
        if kind == "see":
            return See(int(body[1]), tuple(_seen_object(item) for item in body[2:]))
        if kind == "see_global":
            return _see_global(body)
        if kind == "hear":
            return _hear(body)
        if kind == "init":
            if body[1:] == ["ok"]:
                return TrainerInit()
            return PlayerInit(str(body[1]), int(body[2]), str(body[3]))
        if kind == "ok":
            return Ok(str(body[1]), tuple(body[2:]))
        if kind == "error":
            return ErrorReply(" ".join(str(part) for part in body[1:]))
        if kind == "warning":
            return WarningReply(" ".join(str(part) for part in body[1:]))
        if kind == "server_param":
            return ServerParamMessage(_pairs(body[1:]))
        if kind == "player_param":
            return PlayerParamMessage(_pairs(body[1:]))
        if kind == "player_type":
            return PlayerTypeMessage(_pairs(body[1:]))
    except (IndexError, TypeError, ValueError) as exc:
        raise RcssParseError(f"malformed {kind} message: {clean(datagram)[:80]!r}") from exc
    return Other(kind, body)

