"""What the player did this tick, drawn on the pitch: the skill's body command as an arrow (a kick from
the ball, a dash along the facing, a turn as an arc) or, for a command that could not happen, a red
dashed line to what was missing (the ball out of reach, the goal out of view), with a short label.

While a game plays, the pitch changes only where nodes stand and which are shown, never a node's
content: viser's client applies a pose or a visibility in the frame that receives it, but a label's
text and a line's points through React, frames later (the pitch trailed the panels). So every mark is
made of a few of a fixed set of shapes (mark_shapes), built once in a local frame (from the origin
along +x) and placed by position and heading: an arrow's shaft and an arc are runs of 1, 2, 4 ...
steps laid end to end, then a head. The label is one of a fixed set of words (LABELS): it carries no
number, the arrow's length and the arc's angle do (to ARROW_STEP and TURN_STEP), and the Inference
panel and the projector band write it.

Geometry only, in world metres and degrees (x toward the attacked goal, +y the player's right); pitch.py
draws it. The sentence that explains the same tick in full is soccer/outcome.py's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from soccer_lab.app.web.ui import style
from soccer_lab.soccer.env import SoccerState
from soccer_lab.soccer.skills import (AT_BALL, DASH, GOAL_OUT_OF_VIEW, HUNT_BALL, HUNT_LAST_SEEN, KICK, NO_DASH_NEEDED,
                                      NOT_KICKABLE, NOTHING, TURN)

ARC_RADIUS = 4.5  # metres: a turn's arc around the player
ARC_STEP = 15.0  # degrees: an arc's segments
HEAD = 1.6  # metres: an arrow head's sides
DASH_SCALE = 0.09  # metres of arrow per unit of dash power (plus the player's drawn radius)
KICK_SCALE = 0.16  # metres of arrow per unit of kick power
DASH_GAP = 1.2  # metres: the gaps of a dashed line
MAX_POWER = 100.0  # rcssserver's: longer commands are drawn as long as this
MAX_TURN = 180.0  # degrees
ARROW_STEP = 0.5  # metres: an arrow's length is drawn to this
TURN_STEP = 5.0  # degrees: an arc's angle is drawn to this
DASHED_RUNS = 6  # a dashed line is made of runs of 1, 2, 4 ... 32 dashes: up to 151 m, past any pitch's diagonal
KICK_BASE = 2.0  # metres: a kick's arrow without power
DASH_BASE = style.PLAYER_DRAW_RADIUS + 1.0
WORDS = {AT_BALL: "stands at the ball", NO_DASH_NEEDED: "drifts onto the ball", NOTHING: "does nothing"}  # why no command
NOT_KICKABLE_WORDS, GOAL_OUT_OF_VIEW_WORDS = "no kick: ball out of reach", "goal not in view"
NO_COMMAND_WORDS = "no command"
LABELS = ("kick", "dash", "turn", "hunt: turn", NOT_KICKABLE_WORDS, GOAL_OUT_OF_VIEW_WORDS, *WORDS.values(),
          NO_COMMAND_WORDS)


@dataclass(frozen=True)
class PlacedShape:
    """One of mark_shapes(), its origin at `at` (world metres), its +x turned to `heading` (degrees); `mirrored`:
    flipped across its x axis first (a turn to the left is a turn to the right's mirror)."""

    shape: str
    at: tuple[float, float]
    heading: float
    mirrored: bool = False


@dataclass(frozen=True)
class CommandMark:
    shapes: tuple[PlacedShape, ...]
    label: str  # one of LABELS
    label_at: tuple[float, float]  # world metres, inside the field


def command_mark(state: SoccerState, goal: tuple[float, float], field: tuple[float, float, float, float]) -> CommandMark | None:
    """The mark of `state`'s last command; None before the first decision. `goal`: the attacked goal's
    centre; `field`: (x0, x1, y0, y1), the grass the label stays on."""
    outcome = state.outcome
    if outcome is None:
        return None
    px, py = state.player
    facing = state.facing
    why = outcome.why
    if outcome.kind == KICK:
        length = KICK_BASE + KICK_SCALE * _power(outcome.value)
        shapes, label = _arrow("kick", state.ball, facing + outcome.direction, length), "kick"
    elif outcome.kind == DASH:
        length = DASH_BASE + DASH_SCALE * _power(outcome.value)
        shapes, label = _arrow("dash", state.player, facing, length), "dash"
    elif outcome.kind == TURN:
        shapes = _arc(state.player, facing, outcome.value)
        label = "hunt: turn" if why in (HUNT_BALL, HUNT_LAST_SEEN) else "turn"
    elif why == NOT_KICKABLE:
        shapes, label = _dashed(state.player, state.ball), NOT_KICKABLE_WORDS
    elif why == GOAL_OUT_OF_VIEW:
        shapes, label = _dashed(state.player, goal), GOAL_OUT_OF_VIEW_WORDS
    else:
        shapes, label = (), WORDS.get(why, NO_COMMAND_WORDS)
    return CommandMark(shapes, label, label_place(px, py, label, field))


def _power(value: float) -> float:
    return min(max(value, 0.0), MAX_POWER)


def _runs(steps: int) -> list[int]:
    """The runs, largest first, of 1, 2, 4 ... steps that add up to `steps`: a mark of any size from a few shapes."""
    return [run for run in reversed(range(steps.bit_length())) if steps & (1 << run)]


def _arrow(kind: str, start: tuple[float, float], heading: float, length: float) -> tuple[PlacedShape, ...]:
    """The shaft's runs end to end from `start`, the head at the tip."""
    shaft, tip = _end_to_end(f"{kind}_shaft", start, heading, round(length / ARROW_STEP), ARROW_STEP)
    return (*shaft, PlacedShape(f"{kind}_head", tip, heading))


def _arc(centre: tuple[float, float], facing: float, turn: float) -> tuple[PlacedShape, ...]:
    """The commanded turn's arc, ending at `facing`: the state's facing is the one after the tick (an arc
    starting there drew a second turn past the one made). Its runs turn about the player, one after another."""
    steps = round(min(abs(turn), MAX_TURN) / TURN_STEP)
    sign = -1.0 if turn < 0 else 1.0
    at, heading, shapes = (float(centre[0]), float(centre[1])), facing - sign * steps * TURN_STEP, []
    for run in _runs(steps):
        shapes.append(PlacedShape(f"turn_arc_{run}", at, heading, mirrored=turn < 0))
        heading += sign * (1 << run) * TURN_STEP
    return (*shapes, PlacedShape("turn_head", at, facing, mirrored=turn < 0))


def _dashed(start: tuple[float, float], end: tuple[float, float]) -> tuple[PlacedShape, ...]:
    """Dashes from `end` back toward `start`, whole dash periods: the player's end, where a part period is
    left, lies under the player's body."""
    (ax, ay), (bx, by) = start, end
    periods = min(round(math.hypot(bx - ax, by - ay) / (2 * DASH_GAP)), 2 ** DASHED_RUNS - 1)
    back = math.degrees(math.atan2(ay - by, ax - bx))
    return _end_to_end("dashes", end, back, periods, 2 * DASH_GAP)[0]


def _end_to_end(prefix: str, start: tuple[float, float], heading: float, steps: int,
                step: float) -> tuple[tuple[PlacedShape, ...], tuple[float, float]]:
    """The runs of `steps` steps of `step` metres (shapes `prefix`_run) laid end to end from `start` along
    `heading`, and where the last one ends."""
    along = _direction(heading)
    at, shapes = np.asarray(start, dtype=np.float64), []
    for run in _runs(steps):
        shapes.append(PlacedShape(f"{prefix}_{run}", (float(at[0]), float(at[1])), heading))
        at = at + (1 << run) * step * along
    return tuple(shapes), (float(at[0]), float(at[1]))


def mark_shapes() -> dict[str, tuple[np.ndarray, tuple[int, int, int]]]:
    """Every shape a mark is made of, by name: (float[N, 2, 2] world metres in the shape's own frame, colour)."""
    shapes = {}
    for kind, longest, colour in (("kick", KICK_BASE + KICK_SCALE * MAX_POWER, style.KICK_MARK),
                                  ("dash", DASH_BASE + DASH_SCALE * MAX_POWER, style.DASH_MARK)):
        for run in range(round(longest / ARROW_STEP).bit_length()):
            shapes[f"{kind}_shaft_{run}"] = (np.array([[(0.0, 0.0), ((1 << run) * ARROW_STEP, 0.0)]]), colour)
        shapes[f"{kind}_head"] = (head_segments(), colour)
    for run in range(round(MAX_TURN / TURN_STEP).bit_length()):
        shapes[f"turn_arc_{run}"] = (arc_segments((1 << run) * TURN_STEP), style.TURN_MARK)
    # the head at the arc's end: the tip on the arc, pointing the way it runs (+y)
    shapes["turn_head"] = (rotated(head_segments(), 90.0) + np.array([ARC_RADIUS, 0.0]), style.TURN_MARK)
    for run in range(DASHED_RUNS):
        shapes[f"dashes_{run}"] = (dash_segments(1 << run), style.REFUSED_MARK)
    return shapes


def head_segments() -> np.ndarray:
    """An arrow head with its tip at the origin, pointing along +x."""
    return np.array([[(0.0, 0.0), -HEAD * _direction(-30.0)], [(0.0, 0.0), -HEAD * _direction(30.0)]])


def rotated(segments: np.ndarray, degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return segments @ np.array([[c, s], [-s, c]])


def arc_segments(turn: float) -> np.ndarray:
    """An arc around the origin at ARC_RADIUS from +x to `turn` degrees (toward +y), a segment per ARC_STEP."""
    angles = np.linspace(0.0, turn, max(1, math.ceil(turn / ARC_STEP)) + 1)
    points = ARC_RADIUS * np.stack([np.cos(np.radians(angles)), np.sin(np.radians(angles))], axis=1)
    return np.stack([points[:-1], points[1:]], axis=1)


def dash_segments(periods: int) -> np.ndarray:
    """`periods` dashes along +x from the origin, each DASH_GAP long and followed by a gap as long."""
    starts = 2 * DASH_GAP * np.arange(periods)
    return np.stack([np.stack([starts, np.zeros(periods)], axis=1),
                     np.stack([starts + DASH_GAP, np.zeros(periods)], axis=1)], axis=1)


def label_half_width(label: str) -> float:
    """Metres from the label's centre to its side, as drawn."""
    return 0.5 * len(label) * style.COMMAND_LABEL_CHARACTER * style.COMMAND_LABEL_HEIGHT


def label_place(px: float, py: float, label: str, field: tuple[float, float, float, float]) -> tuple[float, float]:
    """Above the player (screen up = world -y), kept whole on the grass: the label's bottom centre."""
    x0, x1, y0, y1 = field
    room = label_half_width(label)
    x = min(max(px, x0 + room), x1 - room)
    y = py - style.PLAYER_DRAW_RADIUS - 1.0
    if y < y0 + style.COMMAND_LABEL_HEIGHT:  # no room above: below the player
        y = py + style.PLAYER_DRAW_RADIUS + 1.0 + style.COMMAND_LABEL_HEIGHT
    return x, min(y, y1 - 0.5)


def _direction(degrees: float) -> np.ndarray:
    radians = math.radians(degrees)
    return np.array([math.cos(radians), math.sin(radians)])
