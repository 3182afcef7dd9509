"""The pitch as an RGB image (numpy only: soccer does not depend on the app's drawing), for
`render_mode="rgb_array"`. Seen from above, +x (the attacked goal) to the right, +y (the player's
right when it attacks) downward."""

from __future__ import annotations

import math

import numpy as np

from soccer_lab.soccer.config import WorldConfig

PIXELS_PER_METRE = 5
MARGIN = 4.0  # metres drawn around the pitch: the net and a ball in it
GRASS, LINE, NET, BALL, PLAYER, FACING = (30, 120, 50), (235, 235, 235), (200, 200, 200), (250, 250, 250), \
    (30, 80, 200), (250, 210, 40)
LINE_WIDTH = 0.4  # metres
BODY_SCALE = 3.0  # ball and player drawn this many times their size, to be seen at this scale


class PitchPicture:
    """Draws one world's pitch; `draw(player, facing, ball)` gives a fresh uint8[height, width, 3]."""

    def __init__(self, world: WorldConfig):
        self.world = world
        self.width = int(round((world.pitch_length + 2 * MARGIN) * PIXELS_PER_METRE))
        self.height = int(round((world.pitch_width + 2 * MARGIN) * PIXELS_PER_METRE))
        rows, columns = np.mgrid[0:self.height, 0:self.width]
        # each pixel's centre in pitch metres
        self._x = (columns + 0.5) / PIXELS_PER_METRE - MARGIN - world.pitch_length / 2
        self._y = (rows + 0.5) / PIXELS_PER_METRE - MARGIN - world.pitch_width / 2
        self._background = self._pitch()

    def _pitch(self) -> np.ndarray:
        w, x, y = self.world, self._x, self._y
        hl, hw, gw = w.pitch_length / 2, w.pitch_width / 2, w.goal_width / 2
        image = np.empty((self.height, self.width, 3), dtype=np.uint8)
        image[:] = GRASS
        inside = (abs(x) <= hl + LINE_WIDTH / 2) & (abs(y) <= hw + LINE_WIDTH / 2)
        boundary = inside & ((abs(abs(x) - hl) <= LINE_WIDTH / 2) | (abs(abs(y) - hw) <= LINE_WIDTH / 2))
        halfway = abs(x) <= LINE_WIDTH / 2
        circle = abs(np.hypot(x, y) - 9.15) <= LINE_WIDTH / 2
        image[boundary | (inside & (halfway | circle))] = LINE
        net = (x > hl) & (x <= hl + w.goal_depth) & (abs(y) <= gw)
        image[net] = NET
        return image

    def draw(self, player: tuple[float, float], facing: float, ball: tuple[float, float]) -> np.ndarray:
        image = self._background.copy()
        size = BODY_SCALE * self.world.player_size
        heading = math.radians(facing)
        tip = (player[0] + 2 * size * math.cos(heading), player[1] + 2 * size * math.sin(heading))
        image[_segment(self._x, self._y, player, tip) <= LINE_WIDTH] = FACING  # sticks out of the body
        image[np.hypot(self._x - player[0], self._y - player[1]) <= size] = PLAYER
        image[np.hypot(self._x - ball[0], self._y - ball[1]) <= BODY_SCALE * 2 * self.world.ball_size] = BALL
        return image


def _segment(x: np.ndarray, y: np.ndarray, a: tuple[float, float], b: tuple[float, float]) -> np.ndarray:
    """Each pixel's distance to the segment a-b."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = np.clip(((x - a[0]) * dx + (y - a[1]) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
    return np.hypot(x - (a[0] + t * dx), y - (a[1] + t * dy))
