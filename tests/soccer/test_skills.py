"""Each skill and the hunt in a scripted situation."""

import math

import pytest

from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.skills import (ACTED, AT_BALL, BALL_OUT_OF_VIEW, DASH, FETCHING, GOAL_OUT_OF_VIEW, HUNT,
                                      HUNT_BALL, HUNT_LAST_SEEN, KICK, LEFT, NO_DASH_NEEDED, NONE, NOT_KICKABLE,
                                      NOTHING, RIGHT, TURN_FIRST, SKILL_DASH, SKILL_DONOTHING, SKILL_DRIBBLE,
                                      SKILL_DRIBBLETOWARDGOAL, SKILL_GOTOBALL, SKILL_KICK, SKILL_KICKTOWARDGOAL,
                                      SKILL_RUNTOWARDBALL, SKILL_RUNTOWARDGOAL, SKILL_TURN, TURN, skill_command)

C = WorldConfig().constants()


def command(skill, **situation):
    """The body command (kind, value, direction); `outcome` gives why."""
    return skill_command(*_arguments(skill, **situation))[:3]


def outcome(skill, **situation):
    """Why the skill gave its command (soccer/skills.py's outcome code)."""
    return skill_command(*_arguments(skill, **situation))[3]


def _arguments(skill, direction=0.0, power=55.0, ball_visible=True, ball_distance=10.0, ball_direction=0.0,
               goal_direction=0.0, kickable=False, last_side=LEFT, speed=0.0, assisted=True):
    return (skill, direction, power, ball_visible, ball_distance, ball_direction, goal_direction, kickable,
            last_side, speed, assisted, C)


def test_turn_and_dash_pass_their_value():
    assert command(SKILL_TURN, direction=-30.0) == (TURN, -30.0, 0.0)
    assert command(SKILL_DASH, power=70.0) == (DASH, 70.0, 0.0)


def test_kick_only_when_kickable():
    assert command(SKILL_KICK, direction=20.0, power=80.0, kickable=True) == (KICK, 80.0, 20.0)
    assert command(SKILL_KICK, direction=20.0, power=80.0) == (NONE, 0.0, 0.0)


def test_run_toward_goal_turns_then_dashes_and_steers_by_known_goal():
    kind, moment, _ = command(SKILL_RUNTOWARDGOAL, goal_direction=120.0, speed=0.1)  # goal behind: out of view
    assert kind == TURN and moment == pytest.approx(120.0 * 1.5)  # compensates the inertia: 1 + 5 x 0.1
    assert command(SKILL_RUNTOWARDGOAL, goal_direction=9.0, power=40.0) == (DASH, 40.0, 0.0)


def test_run_toward_ball_and_hunt_when_unseen():
    assert command(SKILL_RUNTOWARDBALL, ball_direction=-25.0)[:2] == (TURN, -25.0)
    assert command(SKILL_RUNTOWARDBALL, ball_direction=5.0, power=90.0) == (DASH, 90.0, 0.0)
    assert command(SKILL_RUNTOWARDBALL, ball_visible=False, last_side=RIGHT)[:2] == (TURN, 45.0)


def test_go_to_ball_slows_down_near_ball_and_stops_when_kickable():
    assert command(SKILL_GOTOBALL, power=100.0, ball_distance=20.0) == (DASH, 100.0, 0.0)
    stop = C.player_size + C.ball_size + C.kickable_margin / 2  # 0.735 m
    kind, power, _ = command(SKILL_GOTOBALL, power=100.0, ball_distance=1.5, speed=0.2)
    assert kind == DASH and power == pytest.approx((1.5 - stop - 0.2) / 0.006)
    assert command(SKILL_GOTOBALL, ball_distance=0.9, kickable=True) == (NONE, 0.0, 0.0)


def test_kick_toward_goal_and_dribbles():
    assert command(SKILL_KICKTOWARDGOAL, power=100.0, goal_direction=-12.0, kickable=True) == (KICK, 100.0, -12.0)
    assert command(SKILL_DRIBBLETOWARDGOAL, power=50.0, goal_direction=7.0, kickable=True) == (KICK, 15.0, 7.0)
    assert command(SKILL_DRIBBLE, direction=-40.0, power=50.0, kickable=True) == (KICK, 15.0, -40.0)
    for action in (SKILL_KICKTOWARDGOAL, SKILL_DRIBBLETOWARDGOAL, SKILL_DRIBBLE):  # not kickable: GOTOBALL
        assert command(action, power=60.0, ball_distance=20.0) == (DASH, 60.0, 0.0)


@pytest.mark.parametrize("action", [SKILL_KICK, SKILL_KICKTOWARDGOAL, SKILL_DRIBBLETOWARDGOAL, SKILL_DRIBBLE])
def test_strict_kicking_skills_do_nothing_with_the_ball_out_of_reach(action):
    assert command(action, power=60.0, ball_distance=20.0, assisted=False) == (NONE, 0.0, 0.0)
    assert command(action, power=60.0, ball_visible=False, assisted=False) == (NONE, 0.0, 0.0)
    kind, power, _ = command(action, power=60.0, ball_distance=0.9, kickable=True, assisted=False)
    assert kind == KICK and power > 0.0  # kickable: the same kick as assisted
    assert command(action, power=60.0, ball_distance=0.9, kickable=True, assisted=False) == command(
        action, power=60.0, ball_distance=0.9, kickable=True, assisted=True)


@pytest.mark.parametrize("action", [SKILL_RUNTOWARDGOAL, SKILL_KICKTOWARDGOAL, SKILL_DRIBBLETOWARDGOAL])
def test_goal_skills_do_nothing_when_the_goal_is_unknown(action):
    """`sighted`: the caller passes NaN for a goal out of view, and the skills that need it do nothing,
    even with the ball at the player's feet; with the goal known they act as under `strict`."""
    unknown = command(action, power=60.0, ball_distance=0.9, kickable=True, goal_direction=math.nan, assisted=False)
    assert unknown == (NONE, 0.0, 0.0)
    known = command(action, power=60.0, ball_distance=0.9, kickable=True, goal_direction=5.0, assisted=False)
    assert known[0] in (KICK, DASH) and known[1] > 0.0


def test_goal_free_skills_do_not_need_the_goal():
    for action, expected in ((SKILL_DRIBBLE, KICK), (SKILL_KICK, KICK), (SKILL_GOTOBALL, DASH)):
        kickable = expected == KICK
        args = dict(direction=-40.0, power=60.0, ball_distance=0.9 if kickable else 20.0, kickable=kickable,
                    assisted=False)
        assert command(action, goal_direction=math.nan, **args) == command(action, goal_direction=5.0, **args)
        assert command(action, goal_direction=math.nan, **args)[0] == expected


def test_do_nothing():
    assert command(SKILL_DONOTHING, kickable=True) == (NONE, 0.0, 0.0)


def test_hunt_faces_visible_ball_else_turns_toward_last_side():
    assert command(HUNT, ball_direction=30.0)[:2] == (TURN, 30.0)
    assert command(HUNT, ball_visible=False)[:2] == (TURN, -45.0)  # never seen: left
    assert command(HUNT, ball_visible=False, last_side=RIGHT)[:2] == (TURN, 45.0)
    assert command(HUNT, ball_visible=False, kickable=True)[0] == TURN  # never dashes nor kicks


def test_every_command_says_why():
    """The outcome code: what the UI words (soccer/outcome.py) to explain a tick."""
    assert outcome(SKILL_DASH) == ACTED
    assert outcome(HUNT, ball_direction=30.0) == HUNT_BALL
    assert outcome(HUNT, ball_visible=False) == HUNT_LAST_SEEN
    assert outcome(SKILL_RUNTOWARDBALL, ball_direction=-25.0) == TURN_FIRST
    assert outcome(SKILL_RUNTOWARDBALL, ball_visible=False) == BALL_OUT_OF_VIEW
    assert outcome(SKILL_GOTOBALL, ball_distance=0.9, kickable=True) == AT_BALL
    assert outcome(SKILL_GOTOBALL, ball_distance=0.74, speed=0.2) == NO_DASH_NEEDED
    assert outcome(SKILL_KICK, ball_distance=20.0) == NOT_KICKABLE
    assert outcome(SKILL_KICKTOWARDGOAL, ball_distance=20.0, assisted=False) == NOT_KICKABLE
    assert outcome(SKILL_KICKTOWARDGOAL, kickable=True, goal_direction=math.nan, assisted=False) == GOAL_OUT_OF_VIEW
    assert outcome(SKILL_RUNTOWARDGOAL, goal_direction=math.nan) == GOAL_OUT_OF_VIEW
    assert outcome(SKILL_DONOTHING, kickable=True) == NOTHING
    # assisted kicking skills out of reach: GOTOBALL's own reasons, marked as fetching the ball
    assert outcome(SKILL_KICKTOWARDGOAL, power=60.0, ball_distance=20.0) == ACTED + FETCHING
    assert outcome(SKILL_DRIBBLE, ball_direction=40.0) == TURN_FIRST + FETCHING
