"""Where am I? Position and facing from the flags in a see message, and the goal from there.

The landmark table is rcssserver's standard one (landmarkreader.cpp): +x towards (g r), +y towards
the `b` ("bottom") flags. Localisation fits a rotation and a translation that carry the flags'
observed positions (relative to the head) onto their known global positions, by weighted least
squares in closed form (2D Procrustes). Weights are 1/distance^2 because the server's distance
quantisation and direction rounding both grow with distance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from soccer.rcss.messages import See
from soccer.rcss.params import DEFAULT_WORLD

# rcssserver's pitch is WorldConfig's default one (soccer/config.py); the penalty areas and the flags
# beyond the lines are rcssserver's too, and only localisation needs them.
PITCH_HALF_LENGTH = DEFAULT_WORLD.pitch_length / 2
PITCH_HALF_WIDTH = DEFAULT_WORLD.pitch_width / 2
GOAL_HALF_WIDTH = DEFAULT_WORLD.goal_width / 2
PENALTY_AREA_LENGTH = 16.5
PENALTY_AREA_HALF_WIDTH = 20.16
PENALTY_AREA_X = PITCH_HALF_LENGTH - PENALTY_AREA_LENGTH
OUTER_FLAG_OFFSET = 5.0  # the flags beyond the touch and goal lines
OUR_GOAL = (PITCH_HALF_LENGTH, 0.0)  # side l attacks (g r)


def _landmarks() -> dict[str, tuple[float, float]]:
    x, y = PITCH_HALF_LENGTH, PITCH_HALF_WIDTH
    table = {
        "f c": (0.0, 0.0), "f c t": (0.0, -y), "f c b": (0.0, y),
        "f l t": (-x, -y), "f l b": (-x, y), "f r t": (x, -y), "f r b": (x, y),
        "g l": (-x, 0.0), "g r": (x, 0.0),
        "f g l t": (-x, -GOAL_HALF_WIDTH), "f g l b": (-x, GOAL_HALF_WIDTH),
        "f g r t": (x, -GOAL_HALF_WIDTH), "f g r b": (x, GOAL_HALF_WIDTH),
        "f p l t": (-PENALTY_AREA_X, -PENALTY_AREA_HALF_WIDTH), "f p l c": (-PENALTY_AREA_X, 0.0),
        "f p l b": (-PENALTY_AREA_X, PENALTY_AREA_HALF_WIDTH),
        "f p r t": (PENALTY_AREA_X, -PENALTY_AREA_HALF_WIDTH), "f p r c": (PENALTY_AREA_X, 0.0),
        "f p r b": (PENALTY_AREA_X, PENALTY_AREA_HALF_WIDTH),
        "f t 0": (0.0, -y - OUTER_FLAG_OFFSET), "f b 0": (0.0, y + OUTER_FLAG_OFFSET),
        "f l 0": (-x - OUTER_FLAG_OFFSET, 0.0), "f r 0": (x + OUTER_FLAG_OFFSET, 0.0),
    }
    for n in (10, 20, 30, 40, 50):
        table[f"f t l {n}"] = (-n, -y - OUTER_FLAG_OFFSET)
        table[f"f t r {n}"] = (n, -y - OUTER_FLAG_OFFSET)
        table[f"f b l {n}"] = (-n, y + OUTER_FLAG_OFFSET)
        table[f"f b r {n}"] = (n, y + OUTER_FLAG_OFFSET)
    for n in (10, 20, 30):
        table[f"f l t {n}"] = (-x - OUTER_FLAG_OFFSET, -n)
        table[f"f l b {n}"] = (-x - OUTER_FLAG_OFFSET, n)
        table[f"f r t {n}"] = (x + OUTER_FLAG_OFFSET, -n)
        table[f"f r b {n}"] = (x + OUTER_FLAG_OFFSET, n)
    return {name: (float(px), float(py)) for name, (px, py) in table.items()}


LANDMARKS: dict[str, tuple[float, float]] = _landmarks()


def normalise_angle(degrees: float) -> float:
    """The same angle in [-180, 180)."""
    return (degrees + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class Pose:
    x: float
    y: float
    body: float  # global body direction, degrees (atan2 convention, +y = bottom)

    def relative(self, x: float, y: float) -> tuple[float, float]:
        """(distance, direction relative to the body in [-180, 180)) of a global point."""
        dx, dy = x - self.x, y - self.y
        return math.hypot(dx, dy), normalise_angle(math.degrees(math.atan2(dy, dx)) - self.body)

    def to_global(self, distance: float, direction: float) -> tuple[float, float]:
        """The global point at `distance` and body-relative `direction`."""
        angle = math.radians(self.body + direction)
        return self.x + distance * math.cos(angle), self.y + distance * math.sin(angle)


def localise(see: See, head_angle: float = 0.0) -> Pose | None:
    """The pose that best explains the landmarks in view, or None with fewer than two of them."""
    points = []
    for seen in see.flags:
        landmark = LANDMARKS.get(seen.key)
        if landmark is None or not seen.in_view or math.isnan(seen.distance):
            continue
        angle = math.radians(seen.direction)
        local = (seen.distance * math.cos(angle), seen.distance * math.sin(angle))
        points.append((local, landmark, 1.0 / max(seen.distance, 1.0) ** 2))
    if len(points) < 2:
        return None
    total = sum(w for _, _, w in points)
    lx = sum(w * l[0] for l, _, w in points) / total
    ly = sum(w * l[1] for l, _, w in points) / total
    gx = sum(w * g[0] for _, g, w in points) / total
    gy = sum(w * g[1] for _, g, w in points) / total
    cross = dot = 0.0
    for (px, py), (qx, qy), w in points:
        px, py, qx, qy = px - lx, py - ly, qx - gx, qy - gy
        dot += w * (px * qx + py * qy)
        cross += w * (px * qy - py * qx)
    head = math.atan2(cross, dot)
    cos_h, sin_h = math.cos(head), math.sin(head)
    x = gx - (cos_h * lx - sin_h * ly)
    y = gy - (sin_h * lx + cos_h * ly)
    return Pose(x, y, normalise_angle(math.degrees(head) - head_angle))


def goal_relative(pose: Pose) -> tuple[float, float]:
    """(distance, direction) of the centre of the goal we attack, from the pose."""
    return pose.relative(*OUR_GOAL)
