"""What the player did this tick, drawn on the pitch: the skill's body command as an arrow (a kick from
the ball, a dash along the facing, a turn as an arc) or, for a command that could not happen, a red
dashed line to what was missing (the ball out of reach, the goal out of view), with a short label.

Geometry only, in world metres (x toward the attacked goal, +y the player's right); pitch.py draws it.
The sentence that explains the same tick in full is soccer/outcome.py's.
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
ARC_STEPS = 12
HEAD = 1.6  # metres: an arrow head's sides
DASH_SCALE = 0.09  # metres of arrow per unit of dash power (plus the player's drawn radius)
KICK_SCALE = 0.16  # metres of arrow per unit of kick power
DASH_GAP = 1.2  # metres: the gaps of a dashed line


@dataclass(frozen=True)
class CommandMark:
    segments: np.ndarray  # float[N, 2, 2]: world metres
    colour: tuple[int, int, int]
    label: str
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
        heading = facing + outcome.direction
        segments = _arrow(state.ball, heading, 2.0 + KICK_SCALE * outcome.value)
        mark = (segments, style.KICK_MARK, f"kick {outcome.value:.0f}")
    elif outcome.kind == DASH:
        segments = _arrow(state.player, facing, style.PLAYER_DRAW_RADIUS + 1.0 + DASH_SCALE * outcome.value)
        mark = (segments, style.DASH_MARK, f"dash {outcome.value:.0f}")
    elif outcome.kind == TURN:
        hunting = why in (HUNT_BALL, HUNT_LAST_SEEN)
        segments = _arc(state.player, facing, outcome.value)
        mark = (segments, style.TURN_MARK, f"{'hunt: ' if hunting else ''}turn {outcome.value:+.0f}°")
    elif why == NOT_KICKABLE:
        mark = (_dashed(state.player, state.ball), style.REFUSED_MARK, "no kick: ball out of reach")
    elif why == GOAL_OUT_OF_VIEW:
        mark = (_dashed(state.player, goal), style.REFUSED_MARK, "goal not in view")
    else:
        words = {AT_BALL: "stands at the ball", NO_DASH_NEEDED: "drifts onto the ball", NOTHING: "does nothing"}
        mark = (np.zeros((0, 2, 2)), style.REFUSED_MARK, words.get(why, outcome.command_text()))
    segments, colour, label = mark
    return CommandMark(segments, colour, label, label_place(px, py, label, field))


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


def _arrow(start: tuple[float, float], heading: float, length: float) -> np.ndarray:
    origin = np.asarray(start, dtype=np.float64)
    tip = origin + length * _direction(heading)
    left = tip - HEAD * _direction(heading - 30.0)
    right = tip - HEAD * _direction(heading + 30.0)
    return np.array([[origin, tip], [tip, left], [tip, right]])


def _arc(centre: tuple[float, float], facing: float, turn: float) -> np.ndarray:
    """An arc from the facing to the facing after the turn, with a head at its end."""
    c = np.asarray(centre, dtype=np.float64)
    angles = np.linspace(facing, facing + turn, ARC_STEPS + 1)
    points = np.array([c + ARC_RADIUS * _direction(a) for a in angles])
    segments = list(np.stack([points[:-1], points[1:]], axis=1))
    tangent = angles[-1] + (90.0 if turn >= 0 else -90.0)  # the way the arc runs at its end
    tip = points[-1]
    segments += [np.array([tip, tip - HEAD * _direction(tangent - 30.0)]),
                 np.array([tip, tip - HEAD * _direction(tangent + 30.0)])]
    return np.array(segments)


def _dashed(start: tuple[float, float], end: tuple[float, float]) -> np.ndarray:
    a, b = np.asarray(start, dtype=np.float64), np.asarray(end, dtype=np.float64)
    length = float(np.linalg.norm(b - a))
    if length < 1e-9:
        return np.zeros((0, 2, 2))
    dashes = max(1, int(length / (2 * DASH_GAP)))
    step = (b - a) / (2 * dashes)
    return np.array([[a + 2 * i * step, a + (2 * i + 1) * step] for i in range(dashes)])
