"""The ten mid-level skills (spec 4.2) and the default hunt (4.3), free of pymunk.

Two skill sets (`GameConfig.skills`): `strict`, where KICK, KICKTOWARDGOAL, DRIBBLETOWARDGOAL and
DRIBBLE kick when the ball is kickable and otherwise do nothing (as rcssserver's kick does), and
`assisted`, where the last three fall back to GOTOBALL when the ball is out of reach (so one rule
"if <anything> then KickTowardGoal High" is a whole striker).

A skill turns the selected action, its direction and power values, what the player perceives and its
own state into ONE rcssserver body command `(kind, value, direction)`:
TURN (value = moment), DASH (value = power), KICK (value = power, direction relative to the facing)
or NONE. The SimpleSoccer engine applies it with soccer/physics.py; the rcssserver client sends it as
`(turn m)`, `(dash p)`, `(kick p d)`. Skills steer by the goal's known position (the caller passes its
direction computed from the player's own pose), even when the goal is out of view.
"""

from __future__ import annotations

import numba

from fuzzy.batched import NO_ACTION
from fuzzy.vocabulary import Vocabulary

from soccer.physics import clamp, kickable_distance

NONE, TURN, DASH, KICK = 0, 1, 2, 3
HUNT = NO_ACTION  # the action index the engine passes when no rule fired

_ACTIONS = Vocabulary.default().action_names
# Action indices as the vocabulary orders them (numba freezes these module globals at compile time).
A_TURN = _ACTIONS.index("TURN")
A_DASH = _ACTIONS.index("DASH")
A_KICK = _ACTIONS.index("KICK")
A_RUNTOWARDGOAL = _ACTIONS.index("RUNTOWARDGOAL")
A_RUNTOWARDBALL = _ACTIONS.index("RUNTOWARDBALL")
A_GOTOBALL = _ACTIONS.index("GOTOBALL")
A_KICKTOWARDGOAL = _ACTIONS.index("KICKTOWARDGOAL")
A_DRIBBLETOWARDGOAL = _ACTIONS.index("DRIBBLETOWARDGOAL")
A_DRIBBLE = _ACTIONS.index("DRIBBLE")
A_DONOTHING = _ACTIONS.index("DONOTHING")

LEFT, RIGHT = -1, 1  # side where the ball was last seen
SKILL_SETS = ("strict", "assisted")  # GameConfig.skills; the kernel takes `assisted` as a flag


@numba.njit(cache=True)
def turn_toward(direction, speed, constants):
    """TURN whose moment, after the server's inertia, actually makes `direction` (as far as max_moment allows)."""
    moment = clamp(direction * (1.0 + constants.inertia_moment * speed), -constants.max_moment, constants.max_moment)
    return TURN, moment, 0.0


@numba.njit(cache=True)
def hunt(ball_visible, ball_direction, last_ball_side, speed, constants):
    """Face the ball if it is visible, else turn hunt_turn degrees toward where it was last seen."""
    if ball_visible:
        return turn_toward(ball_direction, speed, constants)
    return turn_toward(last_ball_side * constants.hunt_turn, speed, constants)


@numba.njit(cache=True)
def run_toward(direction, power, speed, constants):
    if abs(direction) > constants.turn_threshold:
        return turn_toward(direction, speed, constants)
    return DASH, power, 0.0


@numba.njit(cache=True)
def go_to_ball(power, ball_visible, ball_distance, ball_direction, kickable, last_ball_side, speed, constants):
    """RUNTOWARDBALL that stops when kickable and dashes no harder than needed to stop the player
    halfway into the kickable margin (so it does not overrun the ball)."""
    if kickable:
        return NONE, 0.0, 0.0
    if not ball_visible:
        return hunt(ball_visible, ball_direction, last_ball_side, speed, constants)
    if abs(ball_direction) > constants.turn_threshold:
        return turn_toward(ball_direction, speed, constants)
    stop_distance = kickable_distance(constants) - 0.5 * constants.kickable_margin
    needed = (ball_distance - stop_distance - speed) / constants.dash_power_rate
    dash_power = min(power, needed)
    if dash_power <= 0.0:
        return NONE, 0.0, 0.0
    return DASH, dash_power, 0.0


@numba.njit(cache=True)
def skill_command(action, direction, power, ball_visible, ball_distance, ball_direction, goal_direction,
                  kickable, last_ball_side, speed, assisted, constants):
    """The body command for `action` (HUNT when no rule fired). `ball_*` is the perceived ball (valid when
    ball_visible), `goal_direction` the goal centre's direction from the player's own pose, `kickable`
    whether the ball is within kicking distance, `speed` the player's current speed (m/tick), `assisted`
    whether the kicking skills fetch the ball first (the `assisted` skill set) or do nothing (`strict`)."""
    if action == HUNT:
        return hunt(ball_visible, ball_direction, last_ball_side, speed, constants)
    if action == A_TURN:
        return TURN, direction, 0.0
    if action == A_DASH:
        return DASH, power, 0.0
    if action == A_KICK:
        if kickable:
            return KICK, power, direction
        return NONE, 0.0, 0.0
    if action == A_RUNTOWARDGOAL:
        return run_toward(goal_direction, power, speed, constants)
    if action == A_RUNTOWARDBALL:
        if ball_visible:
            return run_toward(ball_direction, power, speed, constants)
        return hunt(ball_visible, ball_direction, last_ball_side, speed, constants)
    if action == A_KICKTOWARDGOAL or action == A_DRIBBLETOWARDGOAL or action == A_DRIBBLE:
        if kickable:
            if action == A_KICKTOWARDGOAL:
                return KICK, power, goal_direction
            if action == A_DRIBBLETOWARDGOAL:
                return KICK, power * constants.dribble_power_fraction, goal_direction
            return KICK, power * constants.dribble_power_fraction, direction
        if not assisted:
            return NONE, 0.0, 0.0
        return go_to_ball(power, ball_visible, ball_distance, ball_direction, kickable, last_ball_side, speed,
                          constants)
    if action == A_GOTOBALL:
        return go_to_ball(power, ball_visible, ball_distance, ball_direction, kickable, last_ball_side, speed,
                          constants)
    return NONE, 0.0, 0.0  # DONOTHING
