"""Typed rcssserver messages (protocol version 19).

`parse_message(datagram)` returns one of the classes below; a message kind we do not use is kept as
`Other` (never an error), a malformed one raises RcssParseError naming it. The formats were checked
against the transcripts in tests/rcss/transcripts (see NOTES.md there): player and trainer `hear` differ in
the order of time and sender; see objects carry 2 to 4 numbers (and more for players).

The messages of every cycle (think, sense_body, see, see_global) are flat lists of `(NAME VALUES)` or
`((NAME) VALUES)` items: regular expressions read them straight into their classes, 3-4 times faster
than the s-expression reader, which reads every other message. A client answers the server after each
cycle, so this is time the server waits.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import NamedTuple

from soccer.rcss.errors import RcssParseError
from soccer.rcss.sexp import clean, parse

REFEREE = "referee"
_GOAL_MODE = re.compile(r"^goal_([lr])_(\d+)$")
_OBJECT = re.compile(r"\(\(([^()]*)\) ([^()]*)\)")  # ((NAME PARTS) VALUES) in see and see_global
_FIELD = re.compile(r"\((\w+) ([^()]*)\)")  # (NAME VALUES) in sense_body, nested ones included
# sense_body's counts of executed commands (the server counts a kick only when it reached the ball)
COUNTERS = ("kick", "dash", "turn", "say", "turn_neck", "catch", "move", "change_view", "change_focus")
THINK = "(think)"


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


def _checked_balance(text: str, kind: str) -> None:
    if text.count("(") != text.count(")") or not text.endswith(")"):
        raise RcssParseError(f"malformed {kind} message: unbalanced parentheses in {text[:80]!r}")


def _numbers_and_flags(values: str, what: str) -> tuple[list[float], list[str]]:
    """An item's numbers, and the flags after them (see_global's `k` for a player who just kicked)."""
    tokens = values.split()
    try:
        return [float(token) for token in tokens], []
    except ValueError:  # flags (only players have them)
        split = next((i for i, token in enumerate(tokens) if token[0].isalpha()), len(tokens))
    try:
        return [float(token) for token in tokens[:split]], tokens[split:]
    except ValueError:
        raise RcssParseError(f"expected numbers for {what}, got {values!r}") from None


def _time(text: str, kind: str) -> int:
    try:
        return int(text[len(kind) + 2:text.index(" ", len(kind) + 2)])
    except ValueError:
        raise RcssParseError(f"malformed {kind} message: no time in {text[:60]!r}") from None


def _sense_body(text: str) -> SenseBody:
    _checked_balance(text, "sense_body")
    fields = dict(_FIELD.findall(text))
    try:
        view_quality, view_width = fields["view_mode"].split()
        speed, speed_direction = _numbers_and_flags(fields["speed"], "speed")[0]
        (head_angle,) = _numbers_and_flags(fields["head_angle"], "head_angle")[0]
        counters = {name: int(fields[name]) for name in COUNTERS if name in fields}
    except (KeyError, ValueError) as exc:
        raise RcssParseError(f"malformed sense_body: missing or bad {exc}") from None
    return SenseBody(_time(text, "sense_body"), view_quality, view_width, speed, speed_direction, head_angle,
                     counters)


def _seen_objects(text: str) -> list[tuple[tuple[str, ...], list[float], list[str]]]:
    """(name parts, numbers, flags) of every ((NAME) VALUES) item; quoted team names lose their quotes."""
    return [(tuple(name.replace('"', "").split()), *_numbers_and_flags(values, f"({name})"))
            for name, values in _OBJECT.findall(text)]


def _see(text: str) -> See:
    _checked_balance(text, "see")
    objects = []
    for name, numbers, _ in _seen_objects(text):
        if len(numbers) == 1:  # far objects: direction only
            objects.append(SeenObject(name, math.nan, numbers[0]))
        elif len(numbers) >= 4:
            objects.append(SeenObject(name, *numbers[:4]))
        elif len(numbers) >= 2:
            objects.append(SeenObject(name, numbers[0], numbers[1]))
        else:
            raise RcssParseError(f"malformed see object ({' '.join(name)}) without numbers")
    return See(_time(text, "see"), tuple(objects))


def _see_global(text: str) -> SeeGlobal:
    _checked_balance(text, "see_global")
    ball = None
    players = []
    for name, numbers, flags in _seen_objects(text):
        if name == ("b",) and len(numbers) >= 2:
            ball = GlobalObject(*numbers[:4])
        elif name[0] == "p" and len(name) >= 3 and len(numbers) >= 6:
            try:
                unum = int(name[2])
            except ValueError:
                raise RcssParseError(f"malformed see_global player ({' '.join(name)})") from None
            players.append(GlobalPlayer(name[1], unum, *numbers[:6], kicked="k" in flags))
    return SeeGlobal(_time(text, "see_global"), ball, tuple(players))


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
    text = clean(datagram)
    if text == THINK:
        return Think()
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
