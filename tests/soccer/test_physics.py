"""rcssserver formulas against hand-computed values (docs/research/index.md, "The model")."""

import math

import pytest

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.physics import (COLLISION_GAP, cap_speed, dash, decay, is_kickable, kick, kick_acceleration,
                                       separate, turn)

C = WorldConfig().constants()


def test_dash_accelerates_power_times_rate_along_the_facing():
    vx, vy = dash(0.0, 0.0, 90.0, 50.0, C)
    assert vx == pytest.approx(0.0, abs=1e-12)
    assert vy == pytest.approx(50 * 0.006)  # facing 90 degrees = +y, the player's right when it faced +x


def test_dash_is_capped_at_player_speed_max():
    vx, vy = dash(1.0, 0.0, 0.0, 100.0, C)  # 1.0 + 0.6 > 1.05
    assert (vx, vy) == pytest.approx((1.05, 0.0))


def test_decay_multiplies_velocity():
    assert decay(1.0, -0.5, C.player_decay) == pytest.approx((0.4, -0.2))
    assert decay(2.0, 0.0, C.ball_decay) == pytest.approx((1.88, 0.0))


def test_turn_is_reduced_by_inertia_with_speed():
    assert turn(0.0, 60.0, 0.0, C) == pytest.approx(60.0)
    assert turn(0.0, 60.0, 0.5, C) == pytest.approx(60.0 / (1 + 5 * 0.5))  # 17.142857...
    assert turn(170.0, 30.0, 0.0, C) == pytest.approx(-160.0)  # wraps into (-180, 180]
    assert turn(0.0, 500.0, 0.0, C) == pytest.approx(180.0)  # moment clipped to max_moment


def test_kick_power_falls_with_angle_and_gap():
    # ball straight ahead, touching the player: full efficiency, 50 x 0.027 = 1.35
    ax, ay = kick_acceleration(50.0, 0.0, 0.0, 0.385, 0.0, C)
    assert (ax, ay) == pytest.approx((1.35, 0.0))
    # ball 90 degrees off and 0.35 m gap: 1 - 0.25*90/180 - 0.25*0.35/0.7 = 0.75
    ax, ay = kick_acceleration(50.0, 0.0, 0.0, 0.385 + 0.35, 90.0, C)
    assert ax == pytest.approx(1.35 * 0.75)
    # direction is relative to the facing
    ax, ay = kick_acceleration(50.0, -90.0, 90.0, 0.385, 0.0, C)
    assert (ax, ay) == pytest.approx((1.35, 0.0), abs=1e-12)


def test_kick_acceleration_capped_and_ball_speed_capped():
    ax, _ = kick_acceleration(100.0, 0.0, 0.0, 0.385, 0.0, C)
    assert ax == pytest.approx(2.7)  # 100 x 0.027 = 2.7 = ball_accel_max
    vx, vy = kick(2.0, 0.0, 100.0, 0.0, 0.0, 0.385, 0.0, C)
    assert (vx, vy) == pytest.approx((3.0, 0.0))  # ball_speed_max


def test_cap_speed_keeps_direction():
    vx, vy = cap_speed(3.0, 4.0, 1.0)
    assert (vx, vy) == pytest.approx((0.6, 0.8))
    assert math.hypot(*cap_speed(0.3, 0.4, 1.0)) == pytest.approx(0.5)


def test_kickable_within_player_ball_and_margin():
    assert is_kickable(0.3 + 0.085 + 0.7, C)
    assert not is_kickable(0.3 + 0.085 + 0.7001, C)


def test_overlapping_player_and_ball_part_from_their_midpoint_along_the_line_of_centres():
    # rcssserver's calcCollPos: centres 0.2 m apart (reach 0.385), midpoint (10.1, -3): each ends
    # 0.1925 + gap from it, the ball on its own side
    px, py, bx, by, collided = separate(10.0, -3.0, 10.2, -3.0, 0.0, C)
    assert collided
    assert (px, bx) == pytest.approx((10.1 - 0.1925 - COLLISION_GAP, 10.1 + 0.1925 + COLLISION_GAP), abs=1e-12)
    assert py == by == -3.0
    px, py, bx, by, _ = separate(0.0, 0.0, 0.06, 0.08, 0.0, C)  # 3-4-5 direction
    assert (bx - px, by - py) == pytest.approx((0.6 * (0.385 + 2 * COLLISION_GAP), 0.8 * (0.385 + 2 * COLLISION_GAP)))


def test_separate_leaves_apart_bodies_alone_and_parts_coincident_ones_along_the_facing():
    assert separate(0.0, 0.0, 0.386, 0.0, 0.0, C) == (0.0, 0.0, 0.386, 0.0, False)
    px, py, bx, by, collided = separate(1.0, 1.0, 1.0, 1.0, 90.0, C)
    assert collided and px == pytest.approx(1.0) and bx == pytest.approx(1.0)
    assert by - py == pytest.approx(0.385 + 2 * COLLISION_GAP)  # ball ahead of a player facing +y
