"""Typed rcssserver messages (protocol version 19).

`parse_message(datagram)` returns one of the classes below; a message kind we do not use is kept as
`Other` (never an error), a malformed one raises RcssParseError naming it (a see's or see_global's
objects when they are read, see below). The formats were checked
against the transcripts in tests/rcss/transcripts (see NOTES.md there): player and trainer `hear` differ in
the order of time and sender; see objects carry 2 to 4 numbers (and more for players).

The messages of every cycle (think, sense_body, see, see_global) are flat lists of `(NAME VALUES)` or
`((NAME) VALUES)` items: regular expressions read them straight into their classes, many times faster
than the s-expression reader, which reads every other message. A client answers the server after each
cycle, so this is time the server waits; so each is read only as far as it is used: a sense_body for
the fields the player uses, a see (20 to 40 objects) for the ball and the landmarks localisation needs
straight from its text (`See.objects` reads every object when first asked for), a see_global for its
players when asked for.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import NamedTuple

from soccer_lab.soccer.rcss.errors import RcssParseError
from soccer_lab.soccer.rcss.sexp import clean, parse

REFEREE = "referee"
_GOAL_MODE = re.compile(r"^goal_([lr])_(\d+)$")
_OBJECT = re.compile(r"\(\(([^()]*)\) ([^()]*)\)")  # ((NAME PARTS) VALUES) in see and see_global
# What the player uses of a sense_body (the fields come in this order, stamina between view_mode and speed)
_SENSE_BODY = re.compile(r"\(sense_body (\d+) \(view_mode (\w+) (\w+)\).*?"
                         r"\(speed ([^\s()]+) ([^\s()]+)\) \(head_angle ([^\s()]+)\) \(kick (\d+)\)")
_BALL = re.compile(r"\(\(b\) ([^()]*)\)")  # the ball in view (see) or on the field (see_global)
_NEAR_BALL = re.compile(r"\(\(B\) ([^()]*)\)")  # the ball out of view but within visible_distance
_LANDMARK = re.compile(r"\(\(([fg] [^()]*)\) ([^\s()]+) ([^\s()]+)")  # a flag or goal in view, with a distance
_GLOBAL_PLAYER = re.compile(r"\(\((p [^()]*)\) ([^()]*)\)")
THINK = "(think)"
THINK_DATAGRAM = b"(think)\x00"


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


THINK_MESSAGE = Think()  # twice a cycle: one instance serves them all


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


class SenseBody(NamedTuple):
    """What the player uses of its own state, every cycle (the message says more: stamina, the other
    command counts, ...). A NamedTuple, as the other per-cycle values: cheaper to make than a frozen
    dataclass."""

    time: int
    view_quality: str
    view_width: str
    speed: float  # |v| after decay, quantised
    speed_direction: float  # degrees relative to the head
    head_angle: float
    kick_count: int = 0  # kicks executed so far (the server counts a kick only when it reached the ball)


class SeenObject(NamedTuple):
    """One object in a see: name parts such as ('f', 'r', 'b'), distance (m), direction (deg, from
    the head, negative = left) and, when reported, distance and direction change. (A NamedTuple: a
    see holds 20 to 40 of them, every second cycle.)"""

    name: tuple[str, ...]
    distance: float
    direction: float
    distance_change: float | None = None
    direction_change: float | None = None

    @property
    def key(self) -> str:
        return " ".join(self.name)

    @property
    def in_view(self) -> bool:
        """Upper-case names ((B), (F), (G), (P)) are near objects outside the view cone."""
        return not str(self.name[0]).isupper()


class See:
    """`(see T ((NAME) VALUES) ...)`, kept as its text: the player reads the ball, the near ball and the
    landmarks straight from it; `objects` reads every object, when first asked for (and raises
    RcssParseError then if one is malformed)."""

    def __init__(self, time: int, text: str):
        self.time = time
        self.text = text
        self._objects: tuple[SeenObject, ...] | None = None

    @property
    def objects(self) -> tuple[SeenObject, ...]:
        if self._objects is None:
            self._objects = _seen_objects(self.text)
        return self._objects

    def find(self, key: str) -> SeenObject | None:
        for seen in self.objects:
            if seen.key == key:
                return seen
        return None

    @property
    def ball(self) -> SeenObject | None:
        """The ball in the view cone, or None."""
        return _first(_BALL, self.text, ("b",))

    @property
    def near_ball(self) -> SeenObject | None:
        """The ball out of the view cone but within visible_distance (`(B)`), or None."""
        return _first(_NEAR_BALL, self.text, ("B",))

    @property
    def flags(self) -> tuple[SeenObject, ...]:
        """Flags and goals in view: the landmarks localisation uses."""
        return tuple(s for s in self.objects if s.name[0] in ("f", "g"))

    def landmarks(self) -> list[tuple[str, float, float]]:
        """(name, distance, direction) of every flag and goal in view that has a distance, in the order
        seen: what localisation reads."""
        try:
            return [(name, float(distance), float(direction)) for name, distance, direction in _LANDMARK.findall(self.text)]
        except ValueError:
            raise RcssParseError(f"malformed see: a landmark without numbers in {self.text[:80]!r}") from None


class GlobalObject(NamedTuple):
    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0


class GlobalPlayer(NamedTuple):
    team: str
    unum: int
    x: float
    y: float
    vx: float
    vy: float
    body: float  # degrees, global
    neck: float
    kicked: bool  # the trailing `k`: the player kicked in the last step


class SeeGlobal:
    """`(see_global T ((NAME) VALUES) ...)`, kept as its text (as See): the ball and the players are
    read when first asked for (and raise RcssParseError then if malformed)."""

    def __init__(self, time: int, text: str):
        self.time = time
        self.text = text
        self._players: tuple[GlobalPlayer, ...] | None = None

    @property
    def ball(self) -> GlobalObject | None:
        match = _BALL.search(self.text)
        if match is None:
            return None
        numbers = _numbers_and_flags(match.group(1), "(b)")[0]
        return GlobalObject(*numbers[:4]) if len(numbers) >= 2 else None

    @property
    def players(self) -> tuple[GlobalPlayer, ...]:
        if self._players is None:
            players = (_global_player(name, values) for name, values in _GLOBAL_PLAYER.findall(self.text))
            self._players = tuple(player for player in players if player is not None)
        return self._players

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


def _checked_balance(text: str, kind: str) -> None:
    if text.count("(") != text.count(")") or not text.endswith(")"):
        raise RcssParseError(f"malformed {kind} message: unbalanced parentheses in {text[:80]!r}")


def _numbers_and_flags(values: str, what: str) -> tuple[list[float], list[str]]:
    """An item's numbers, and the flags after them (see_global's `k` for a player who just kicked)."""
    tokens = values.split()
    split = len(tokens)
    while split and tokens[split - 1][0].isalpha():  # flags (only players have them)
        split -= 1
    try:
        return [float(token) for token in tokens[:split]], tokens[split:]
    except ValueError:
        raise RcssParseError(f"expected numbers for {what}, got {values!r}") from None


def _time(text: str, kind: str) -> int:
    """The time after `(KIND `, up to the first object or, in a see of nothing (`(see 870522)`: the player
    faces off the pitch), the closing parenthesis."""
    start = len(kind) + 2
    end = min((i for i in (text.find(" ", start), text.find(")", start)) if i >= 0), default=-1)
    try:
        return int(text[start:end])
    except ValueError:
        raise RcssParseError(f"malformed {kind} message: no time in {text[:60]!r}") from None


def _sense_body(text: str) -> SenseBody:
    _checked_balance(text, "sense_body")
    match = _SENSE_BODY.match(text)
    if match is None:
        raise RcssParseError(f"malformed sense_body: no view_mode, speed, head_angle or kick in {text[:80]!r}")
    time, view_quality, view_width, speed, speed_direction, head_angle, kicks = match.groups()
    try:
        return SenseBody(int(time), view_quality, view_width, float(speed), float(speed_direction), float(head_angle),
                         int(kicks))
    except ValueError:
        raise RcssParseError(f"malformed sense_body: bad speed or head_angle in {text[:80]!r}") from None


def _seen(name: tuple[str, ...], numbers: list[float]) -> SeenObject:
    if len(numbers) == 1:  # far objects: direction only
        return SeenObject(name, math.nan, numbers[0])
    if len(numbers) >= 4:
        return SeenObject(name, *numbers[:4])
    if len(numbers) >= 2:
        return SeenObject(name, numbers[0], numbers[1])
    raise RcssParseError(f"malformed see object ({' '.join(name)}) without numbers")


def _first(pattern: re.Pattern, text: str, name: tuple[str, ...]) -> SeenObject | None:
    """The first object `pattern` finds in a see's text (one without parts to its name)."""
    match = pattern.search(text)
    return _seen(name, _numbers_and_flags(match.group(1), f"({name[0]})")[0]) if match else None


def _seen_objects(text: str) -> tuple[SeenObject, ...]:
    """Every ((NAME) VALUES) item of a see; quoted team names lose their quotes."""
    return tuple(_seen(tuple(name.replace('"', "").split()), _numbers_and_flags(values, f"({name})")[0])
                 for name, values in _OBJECT.findall(text))


def _see(text: str) -> See:
    _checked_balance(text, "see")
    return See(_time(text, "see"), text)


def _global_player(name: str, values: str) -> GlobalPlayer | None:
    """A player with its team, number and six numbers; None for one named or placed less fully."""
    parts = name.replace('"', "").split()
    numbers, flags = _numbers_and_flags(values, f"({name})")
    if len(parts) < 3 or len(numbers) < 6:
        return None
    try:
        unum = int(parts[2])
    except ValueError:
        raise RcssParseError(f"malformed see_global player ({name})") from None
    return GlobalPlayer(parts[1], unum, *numbers[:6], kicked="k" in flags)


def _see_global(text: str) -> SeeGlobal:
    _checked_balance(text, "see_global")
    return SeeGlobal(_time(text, "see_global"), text)


def _pairs(items: list) -> dict:
    """`(name value)` pairs of server_param and friends; a pair with several values keeps a tuple."""
    values = {}
    for item in items:
        if isinstance(item, list) and item and isinstance(item[0], str):
            values[item[0]] = item[1] if len(item) == 2 else tuple(item[1:])
    return values


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
    if datagram == THINK_DATAGRAM:
        return THINK_MESSAGE
    text = clean(datagram)
    if text == THINK:
        return THINK_MESSAGE
    if text.startswith("(sense_body "):
        return _sense_body(text)
    if text.startswith("(see "):
        return _see(text)
    if text.startswith("(see_global "):
        return _see_global(text)
    body = parse(text)
    if not body or not isinstance(body[0], str):
        raise RcssParseError(f"message without a kind: {text[:60]!r}")
    kind = body[0]
    try:
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
        raise RcssParseError(f"malformed {kind} message: {text[:80]!r}") from exc
    return Other(kind, body)
