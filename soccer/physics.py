"""rcssserver's body commands applied to velocities and facing (docs/research/index.md, "The model"). Velocities are in metres
per tick, angles in degrees; pymunk then moves the bodies and resolves contacts. Each function is
one server formula, so the tests check them against hand-computed values."""

from __future__ import annotations

import math

import numba

from soccer_lab.soccer.perception import normalize_angle


@numba.njit(cache=True)
def clamp(value, low, high):
    return min(max(value, low), high)


@numba.njit(cache=True)
def cap_speed(vx, vy, speed_max):
    speed = math.sqrt(vx * vx + vy * vy)
    if speed > speed_max:
        scale = speed_max / speed
        return vx * scale, vy * scale
    return vx, vy


@numba.njit(cache=True)
def decay(vx, vy, factor):
    return vx * factor, vy * factor


@numba.njit(cache=True)
def turn(facing, moment, speed, constants):
    """Facing after a turn command: the moment actually made is moment / (1 + inertia_moment x speed)."""
    moment = clamp(moment, -constants.max_moment, constants.max_moment)
    return normalize_angle(facing + moment / (1.0 + constants.inertia_moment * speed))


@numba.njit(cache=True)
def dash(vx, vy, facing, power, constants):
    """Velocity after a dash: acceleration power x dash_power_rate along the facing, then the speed cap."""
    power = clamp(power, -constants.max_power, constants.max_power)
    accel = min(power * constants.dash_power_rate, constants.player_accel_max)
    rad = math.radians(facing)
    return cap_speed(vx + accel * math.cos(rad), vy + accel * math.sin(rad), constants.player_speed_max)


@numba.njit(cache=True)
def kickable_distance(constants):
    return constants.player_size + constants.ball_size + constants.kickable_margin


@numba.njit(cache=True)
def is_kickable(ball_distance, constants):
    return ball_distance <= kickable_distance(constants)


@numba.njit(cache=True)
def kick_acceleration(power, direction, facing, ball_distance, ball_direction, constants):
    """(ax, ay) a kick gives the ball: power x kick_power_rate x (1 - 0.25 angle/180 - 0.25 gap/margin),
    capped at ball_accel_max, toward `direction` relative to the facing. `ball_direction` is where the
    ball lies relative to the facing; the gap is the distance between the two bodies' surfaces."""
    power = clamp(power, 0.0, constants.max_power)
    gap = max(ball_distance - constants.player_size - constants.ball_size, 0.0)
    efficiency = 1.0 - 0.25 * abs(ball_direction) / 180.0 - 0.25 * gap / constants.kickable_margin
    accel = min(power * constants.kick_power_rate * efficiency, constants.ball_accel_max)
    rad = math.radians(facing + clamp(direction, -constants.max_moment, constants.max_moment))
    return accel * math.cos(rad), accel * math.sin(rad)


@numba.njit(cache=True)
def kick(ball_vx, ball_vy, power, direction, facing, ball_distance, ball_direction, constants):
    """Ball velocity after a kick (then the ball's speed cap)."""
    ax, ay = kick_acceleration(power, direction, facing, ball_distance, ball_direction, constants)
    return cap_speed(ball_vx + ax, ball_vy + ay, constants.ball_speed_max)


# Extra gap left between separated bodies: rcssserver uses 1e-10 m, but our pitches sit near 2**20 m
# where positions are 2**-32 m apart, so a gap that small could be rounded away when written back.
COLLISION_GAP = 1e-6


@numba.njit(cache=True)
def separate(px, py, bx, by, facing, constants):
    """rcssserver's player-ball collision (Stadium::calcCollPos): if the bodies overlap, both move to
    (player_size + ball_size) / 2 + COLLISION_GAP from their midpoint along the line of centres.
    Returns (px, py, bx, by, collided); bodies at the same point part along the player's facing
    (rcssserver picks a random angle), the ball ahead."""
    return part(px, py, bx, by, constants.player_size + constants.ball_size, facing)


@numba.njit(cache=True)
def part(ax, ay, bx, by, reach, facing):
    """Two round bodies whose centres are closer than `reach` (the sum of their radii) moved apart
    from their midpoint as rcssserver does (`separate`); a player against the ball, or against the
    other player of a match (soccer/match.py). Bodies at the same point part along `facing`, b ahead."""
    dx = bx - ax
    dy = by - ay
    distance = math.sqrt(dx * dx + dy * dy)
    if distance >= reach:
        return ax, ay, bx, by, False
    if distance > 0.0:
        ux = dx / distance
        uy = dy / distance
    else:
        rad = math.radians(facing)
        ux = math.cos(rad)
        uy = math.sin(rad)
    mx = 0.5 * (ax + bx)
    my = 0.5 * (ay + by)
    half = 0.5 * reach + COLLISION_GAP
    return mx - half * ux, my - half * uy, mx + half * ux, my + half * uy, True
