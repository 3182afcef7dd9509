"""The pictures the pitch is made of, drawn once with matplotlib (Agg, no display): the field with its
markings, goal and net; the player (disc and facing line); the ball; the view cone.

The browser shows each as one flat textured quad. Browsers without a GPU (a school's old laptop, a
headless test) draw WebGL in software, where one unlit quad costs a fraction of lit meshes and
thick lines; the whole pitch then draws in a few milliseconds a frame, so every tick can be shown.
Coordinates are the simulator's (metres, x toward the attacked goal, +y to the player's right, drawn
downwards as on the screen).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle, Wedge

from soccer_lab.app.pitch_markings import CENTRE_CIRCLE_RADIUS, GOAL_AREA, PENALTY_AREA
from soccer_lab.app.web.ui import style

CIRCLE_SEGMENTS = 96
NET_MESH = 0.7  # metres between the net's strings


@dataclass(frozen=True)
class Picture:
    """RGBA pixels (row 0 at the picture's -y edge) covering `size` metres centred on `centre`."""

    pixels: np.ndarray  # uint8[H, W, 4]
    centre: tuple[float, float]
    size: tuple[float, float]  # width along x, height along y


def _segments(points: list[tuple[float, float]], closed: bool = False) -> list[tuple[tuple, tuple]]:
    pairs = list(zip(points, points[1:]))
    if closed:
        pairs.append((points[-1], points[0]))
    return pairs


def _circle(cx: float, cy: float, radius: float) -> list[tuple[float, float]]:
    return [(cx + radius * math.cos(2 * math.pi * i / CIRCLE_SEGMENTS),
             cy + radius * math.sin(2 * math.pi * i / CIRCLE_SEGMENTS)) for i in range(CIRCLE_SEGMENTS + 1)]


def marking_segments(geometry, both_goals: bool = False) -> np.ndarray:
    """Every painted line and the goal's outline (`both_goals`: both ends', a match's) as segments float[N, 2, 2]
    (world metres)."""
    hl, hw = geometry.half_length, geometry.half_width
    pairs = _segments([(-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw)], closed=True)
    pairs += [((0.0, -hw), (0.0, hw))]
    pairs += _segments(_circle(0.0, 0.0, CENTRE_CIRCLE_RADIUS))
    for side in (-1.0, 1.0):
        for depth, width in (PENALTY_AREA, GOAL_AREA):
            line, inner = side * hl, side * (hl - depth)
            pairs += _segments([(line, -width / 2), (inner, -width / 2), (inner, width / 2), (line, width / 2)])
    goal, depth = geometry.goal_half_width, geometry.goal_depth
    for end in (1.0, -1.0) if both_goals else (1.0,):
        pairs += _segments([(end * hl, -goal), (end * (hl + depth), -goal), (end * (hl + depth), goal),
                            (end * hl, goal)])
    return np.array(pairs, dtype=np.float64)


def net_segments(geometry, both_goals: bool = False) -> np.ndarray:
    """The net's strings inside the goal (`both_goals`: both ends'), float[N, 2, 2] (world metres)."""
    hl, goal, depth = geometry.half_length, geometry.goal_half_width, geometry.goal_depth
    pairs = []
    for end in (1.0, -1.0) if both_goals else (1.0,):
        pairs += [((end * (hl + d), -goal), (end * (hl + d), goal)) for d in np.arange(NET_MESH, depth, NET_MESH)]
        pairs += [((end * hl, y), (end * (hl + depth), y)) for y in np.arange(-goal + NET_MESH, goal, NET_MESH)]
    return np.array(pairs, dtype=np.float64)


class _Canvas:
    """A matplotlib canvas whose data coordinates are metres over [x0, x1] x [y0, y1], +y downwards."""

    def __init__(self, x0: float, x1: float, y0: float, y1: float, pixels_per_metre: float):
        self.x0, self.x1, self.y0, self.y1 = x0, x1, y0, y1
        self.pixels_per_metre = pixels_per_metre
        dpi = 100
        self.figure = Figure(figsize=((x1 - x0) * pixels_per_metre / dpi, (y1 - y0) * pixels_per_metre / dpi), dpi=dpi)
        self.figure.patch.set_alpha(0.0)
        FigureCanvasAgg(self.figure)
        self.axes = self.figure.add_axes((0, 0, 1, 1))
        self.axes.set_axis_off()
        self.axes.set_xlim(x0, x1)
        self.axes.set_ylim(y1, y0)  # +y (the player's right) down, as seen from above

    def points(self, metres: float) -> float:
        """A width in metres as matplotlib's points."""
        return metres * self.pixels_per_metre * 72 / self.figure.dpi

    def picture(self) -> Picture:
        self.figure.canvas.draw()
        pixels = np.asarray(self.figure.canvas.buffer_rgba()).copy()
        centre = ((self.x0 + self.x1) / 2, (self.y0 + self.y1) / 2)
        return Picture(pixels, centre, (self.x1 - self.x0, self.y1 - self.y0))


def solid_picture(rgb: tuple[int, int, int]) -> np.ndarray:
    """Pixels of one opaque colour (viser stretches them over a quad, or the canvas's background)."""
    return np.tile(np.array([*rgb, 255], np.uint8), (2, 2, 1))


def _hex(rgb: tuple[int, int, int], alpha: float = 1.0) -> tuple[float, float, float, float]:
    return (rgb[0] / 255, rgb[1] / 255, rgb[2] / 255, alpha)


@functools.cache  # the same for every tab: drawn once
def field_picture(geometry, pixels_per_metre: float = style.FIELD_PIXELS_PER_METRE,
                  both_goals: bool = False) -> Picture:
    """Grass with mown stripes, the markings, the goal with its net and posts (`both_goals`: a match's pitch, a
    goal at each end)."""
    margin = style.PITCH_MARGIN
    hl, hw = geometry.half_length, geometry.half_width
    back = geometry.goal_depth if both_goals else 0.0
    canvas = _Canvas(-hl - back - margin, hl + geometry.goal_depth + margin, -hw - margin, hw + margin,
                     pixels_per_metre)
    axes = canvas.axes
    axes.add_patch(Rectangle((canvas.x0, canvas.y0), canvas.x1 - canvas.x0, canvas.y1 - canvas.y0,
                             color=_hex(style.GRASS), linewidth=0))
    stripe = 2 * hl / style.GRASS_STRIPES
    for i in range(0, style.GRASS_STRIPES, 2):
        axes.add_patch(Rectangle((-hl + i * stripe, -hw), stripe, 2 * hw, color=_hex(style.GRASS_STRIPE), linewidth=0))
    axes.add_collection(LineCollection(net_segments(geometry, both_goals), colors=[_hex(style.GOAL_NET)],
                                       linewidths=canvas.points(style.NET_LINE_WIDTH)))
    axes.add_collection(LineCollection(marking_segments(geometry, both_goals), colors=[_hex(style.LINE)],
                                       linewidths=canvas.points(style.LINE_WIDTH), capstyle="round"))
    for x in (hl, -hl) if both_goals else (hl,):
        for y in (-geometry.goal_half_width, geometry.goal_half_width):
            axes.add_patch(Circle((x, y), style.POST_DRAW_RADIUS, color=_hex(style.LINE), linewidth=0))
    return canvas.picture()


@functools.cache  # the same for every tab: drawn once
def player_picture(pixels_per_metre: float = style.BODY_PIXELS_PER_METRE,
                   colour: tuple[int, int, int] = style.PLAYER) -> Picture:
    """The player seen from above, facing +x: a disc (of `colour`) with a white line from its centre toward its
    front."""
    radius = style.PLAYER_DRAW_RADIUS
    reach = radius * style.FACING_LINE_REACH
    canvas = _Canvas(-reach, reach, -reach, reach, pixels_per_metre)
    canvas.axes.add_patch(Circle((0, 0), radius, color=_hex(colour), linewidth=0))
    canvas.axes.plot([0, reach - style.LINE_WIDTH], [0, 0], color=_hex(style.PLAYER_FACING),
                     linewidth=canvas.points(radius * 0.35), solid_capstyle="round")
    return canvas.picture()


@functools.cache  # the same for every tab: drawn once
def ball_picture(pixels_per_metre: float = style.BODY_PIXELS_PER_METRE) -> Picture:
    radius = style.BALL_DRAW_RADIUS
    canvas = _Canvas(-radius, radius, -radius, radius, pixels_per_metre)
    canvas.axes.add_patch(Circle((0, 0), radius * 0.97, color=_hex(style.BALL), linewidth=0))
    return canvas.picture()


@functools.cache  # the same for every tab: drawn once
def cone_picture(half_angle: float, colour: tuple[int, int, int],
                 pixels_per_metre: float = style.CONE_PIXELS_PER_METRE) -> Picture:
    """The view: a fan of `half_angle` degrees each side of +x, from the player's centre."""
    length = style.VIEW_CONE_LENGTH
    half = math.radians(half_angle)
    back = min(0.0, length * math.cos(half))
    side = length if half_angle >= 90.0 else length * math.sin(half)
    canvas = _Canvas(back, length, -side, side, pixels_per_metre)
    canvas.axes.add_patch(Wedge((0, 0), length, -half_angle, half_angle,
                                color=_hex(colour, style.VIEW_CONE_OPACITY), linewidth=0))
    return canvas.picture()
