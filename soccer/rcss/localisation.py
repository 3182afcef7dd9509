"""Where am I? Position and facing from the flags in a see message, and the goal from there.

The landmark table is rcssserver's standard one (landmarkreader.cpp): +x towards (g r), +y towards
the `b` ("bottom") flags. Localisation fits a rotation and a translation that carry the flags'
observed positions (relative to the head) onto their known global positions, by weighted least
squares in closed form (2D Procrustes). Weights are 1/distance^2 because the server's distance
quantisation and direction rounding both grow with distance.

Localisation runs on every see (every second cycle) while the server waits, so a numba kernel reads the
landmarks straight from the see's text and fits them: it reads the plain decimals rcssserver writes
exactly as Python's float() does (digits / 10^k is one correctly rounded division), and leaves a see
with any other number to `See.landmarks()` and the same fit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from soccer_lab.soccer.rcss.messages import See
from soccer_lab.soccer.rcss.params import DEFAULT_WORLD

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


def _name_key(name: str) -> int:
    """A landmark's name (at most 8 characters) as one number: its bytes, first byte lowest."""
    return int.from_bytes(name.encode("ascii"), "little")


_KEYS = np.array(sorted(_name_key(name) for name in LANDMARKS), dtype=np.uint64)
_POSITIONS = np.array([LANDMARKS[name] for name in sorted(LANDMARKS, key=_name_key)])
assert max(map(len, LANDMARKS)) <= 8 and len(_KEYS) == len(set(_KEYS.tolist()))


def normalise_angle(degrees: float) -> float:
    """The same angle in [-180, 180)."""
    return (degrees + 180.0) % 360.0 - 180.0


class Pose(NamedTuple):
    """Where the player is and which way its body faces (made every cycle: a NamedTuple is cheap)."""

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

    def turned_half(self) -> "Pose":
        """The same pose in the pitch turned half a turn: the right side's own frame, in which it attacks +x
        as side l does (flag names are global, so localisation gives the pose in side l's frame)."""
        return Pose(-self.x, -self.y, normalise_angle(self.body + 180.0))


def localise(see: See, head_angle: float = 0.0) -> Pose | None:
    """The pose that best explains the landmarks in view, or None with fewer than two of them."""
    count, x, y, head = _localise_text(np.frombuffer(see.text.encode("ascii"), dtype=np.uint8), _KEYS, _POSITIONS)
    if count == IRREGULAR:  # a number other than a plain decimal: read the general way
        sightings = [(*LANDMARKS[name], distance, direction) for name, distance, direction in see.landmarks()
                     if name in LANDMARKS]
        count = len(sightings)
        if count >= 2:
            x, y, head = _fit(np.array(sightings))
    if count < 2:
        return None
    return Pose(x, y, normalise_angle(head - head_angle))


IRREGULAR = -1  # _localise_text met a number it does not read
_OPEN, _CLOSE, _SPACE, _MINUS, _POINT, _ZERO = (ord(c) for c in "() -.0")
_EXACT_DIGITS = 15  # an integer of up to 15 digits is exact in a float64, and so is 10^k for k <= 22
_POWERS_OF_TEN = np.array([10.0 ** k for k in range(_EXACT_DIGITS + 1)])


@numba.njit(cache=True)
def _localise_text(text, keys, positions):
    """(sightings, x, y, head direction in degrees) from a see's ASCII bytes: every `((NAME) DISTANCE
    DIRECTION ...)` whose NAME is a landmark, fitted when there are two or more. Sightings is IRREGULAR
    when one of their numbers is not a plain decimal."""
    length = text.shape[0]
    sightings = np.empty((length // 8 + 1, 4))  # an item takes more than 8 characters
    n = 0
    i = 0
    while i + 1 < length:
        if text[i] != _OPEN or text[i + 1] != _OPEN:
            i += 1
            continue
        start = end = i + 2
        while end < length and text[end] != _CLOSE:
            end += 1
        i = end + 1
        if end - start > 8:
            continue
        key = np.uint64(0)
        for j in range(end - start):
            key |= np.uint64(text[start + j]) << np.uint64(8 * j)
        k = np.searchsorted(keys, key)
        if k == keys.shape[0] or keys[k] != key:
            continue
        distance, i, status = _number(text, i)
        if status == 0:
            direction, i, status = _number(text, i)
        if status == IRREGULAR:
            return IRREGULAR, 0.0, 0.0, 0.0
        if status == 0:  # a landmark with its distance (a far one has only a direction)
            sightings[n, 0], sightings[n, 1] = positions[k, 0], positions[k, 1]
            sightings[n, 2], sightings[n, 3] = distance, direction
            n += 1
    if n < 2:
        return n, 0.0, 0.0, 0.0
    x, y, head = _fit(sightings[:n])
    return n, x, y, head


@numba.njit(cache=True)
def _number(text, i):
    """(value, index after it, status) of the number after the space at text[i]: status 0 when read,
    1 when there is none (a ')' instead), IRREGULAR when it is not a plain decimal of up to 15 digits."""
    length = text.shape[0]
    if i >= length or text[i] != _SPACE:
        return 0.0, i, 1 if i < length and text[i] == _CLOSE else IRREGULAR
    i += 1
    negative = i < length and text[i] == _MINUS
    if negative:
        i += 1
    digits = decimals = 0
    point = False
    mantissa = 0
    while i < length and text[i] != _SPACE and text[i] != _CLOSE:
        c = text[i]
        if c == _POINT and not point:
            point = True
        elif _ZERO <= c <= _ZERO + 9:
            mantissa = mantissa * 10 + (c - _ZERO)
            digits += 1
            decimals += point
        else:
            return 0.0, i, IRREGULAR
        i += 1
    if digits == 0 or digits > _EXACT_DIGITS or i == length:
        return 0.0, i, IRREGULAR
    value = mantissa / _POWERS_OF_TEN[decimals]
    return -value if negative else value, i, 0


@numba.njit(cache=True)
def _fit(sightings):
    """(x, y, head direction in degrees) from rows (landmark x, landmark y, distance, direction)."""
    n = sightings.shape[0]
    local = np.empty((n, 2))
    weight = np.empty(n)
    for i in range(n):
        distance = sightings[i, 2]
        angle = math.radians(sightings[i, 3])
        local[i, 0] = distance * math.cos(angle)
        local[i, 1] = distance * math.sin(angle)
        weight[i] = 1.0 / max(distance, 1.0) ** 2
    total = lx = ly = gx = gy = 0.0
    for i in range(n):  # the weighted centroids of both point sets, each sum in the order seen
        total += weight[i]
        lx += weight[i] * local[i, 0]
        ly += weight[i] * local[i, 1]
        gx += weight[i] * sightings[i, 0]
        gy += weight[i] * sightings[i, 1]
    lx, ly, gx, gy = lx / total, ly / total, gx / total, gy / total
    cross = dot = 0.0
    for i in range(n):
        px, py, qx, qy = local[i, 0] - lx, local[i, 1] - ly, sightings[i, 0] - gx, sightings[i, 1] - gy
        dot += weight[i] * (px * qx + py * qy)
        cross += weight[i] * (px * qy - py * qx)
    head = math.atan2(cross, dot)
    cos_h, sin_h = math.cos(head), math.sin(head)
    return gx - (cos_h * lx - sin_h * ly), gy - (sin_h * lx + cos_h * ly), math.degrees(head)


def goal_relative(pose: Pose) -> tuple[float, float]:
    """(distance, direction) of the centre of the goal we attack, from the pose."""
    return pose.relative(*OUR_GOAL)
