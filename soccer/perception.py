"""What the player perceives: exact relative distance and direction of an object, and whether it
lies within the view cone. Directions follow rcssserver: degrees relative to the player's facing,
negative = to its left (y grows to the player's right when it faces +x)."""

from __future__ import annotations

import math

import numba

# What is perceived, as a vocabulary names it: two objects, each read as a distance and a direction
# (the keys of Vocabulary.objects[object]). The engine finds their inputs in a vocabulary by these names.
BALL, GOAL = "BALL", "GOAL"
DISTANCE, DIRECTION = "distance", "direction"


@numba.njit(cache=True)
def normalize_angle(degrees):
    """The same angle in (-180, 180]."""
    a = degrees % 360.0  # in [0, 360)
    return a - 360.0 if a > 180.0 else a


@numba.njit(cache=True)
def relative_position(x, y, facing, target_x, target_y):
    """(distance, direction) of a target seen from a player at (x, y) facing `facing` degrees."""
    dx = target_x - x
    dy = target_y - y
    distance = math.sqrt(dx * dx + dy * dy)
    if distance == 0.0:
        return 0.0, 0.0
    return distance, normalize_angle(math.degrees(math.atan2(dy, dx)) - facing)


@numba.njit(cache=True)
def in_view(direction, view_half_angle):
    return abs(direction) <= view_half_angle


@numba.njit(cache=True)
def perceive(x, y, facing, ball_x, ball_y, constants):
    """(ball distance, ball direction, ball visible, goal distance, goal direction, goal visible);
    the goal is the centre of the goal mouth the player attacks."""
    ball_distance, ball_direction = relative_position(x, y, facing, ball_x, ball_y)
    goal_distance, goal_direction = relative_position(x, y, facing, constants.half_length, 0.0)
    return (
        ball_distance,
        ball_direction,
        in_view(ball_direction, constants.view_half_angle),
        goal_distance,
        goal_direction,
        in_view(goal_direction, constants.view_half_angle),
    )
