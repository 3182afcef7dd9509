"""Relative distance/direction (rcssserver convention) and the +-45 degree view."""

import pytest

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.perception import normalize_angle, perceive, relative_position

C = WorldConfig().constants()


def test_right_is_positive_when_facing_plus_x():
    assert relative_position(0.0, 0.0, 0.0, 0.0, 5.0) == pytest.approx((5.0, 90.0))
    assert relative_position(0.0, 0.0, 0.0, 0.0, -5.0) == pytest.approx((5.0, -90.0))
    assert relative_position(1.0, 1.0, 90.0, 4.0, 5.0)[0] == pytest.approx(5.0)


def test_direction_is_relative_to_facing():
    _, direction = relative_position(0.0, 0.0, 170.0, -10.0, -1.0)  # target at about -174.3 degrees
    assert direction == pytest.approx(normalize_angle(-174.2894 - 170.0), abs=1e-3)
    assert -180.0 < direction <= 180.0


@pytest.mark.parametrize("angle, expected", [(190.0, -170.0), (-180.0, 180.0), (540.0, 180.0), (-30.0, -30.0)])
def test_normalize_angle(angle, expected):
    assert normalize_angle(angle) == pytest.approx(expected)


def test_in_and_out_of_view():
    # player at the centre facing +x: goal (52.5, 0) straight ahead; ball 44 degrees right: visible
    bd, bdir, ball_seen, gd, gdir, goal_seen = perceive(0.0, 0.0, 0.0, 10.0, 10.0 * 0.9657, C)
    assert ball_seen and goal_seen
    assert gd == pytest.approx(52.5) and gdir == pytest.approx(0.0)
    assert bdir == pytest.approx(44.0, abs=0.01)
    # 46 degrees left: not visible; facing away from the goal: goal not visible
    _, bdir, ball_seen, _, gdir, goal_seen = perceive(0.0, 0.0, 180.0, -10.0, 10.0 * 1.0355, C)
    assert bdir == pytest.approx(-46.0, abs=0.01)
    assert not ball_seen and not goal_seen and gdir == pytest.approx(180.0)
