"""The ten mid-level skills and the default hunt, free of pymunk.

Three skill sets (`GameConfig.skills`): `strict`, where KICK, KICKTOWARDGOAL, DRIBBLETOWARDGOAL and
DRIBBLE kick when the ball is kickable and otherwise do nothing (as rcssserver's kick does);
`assisted`, where the last three fall back to GOTOBALL when the ball is out of reach (so one rule
"if <anything> then KickTowardGoal High" is a whole striker); and `sighted`, `strict` for a player
that knows where the goal is only while it sees it (the chapter, 2.2: SimpleSoccer players "are only
aware of the location of the ball and the goal if they are in the player's field of vision"), so
RUNTOWARDGOAL, KICKTOWARDGOAL and DRIBBLETOWARDGOAL do nothing while the goal is out of view.

A skill turns the selected action's direction and power values, what the player perceives and its
own state into ONE rcssserver body command `(kind, value, direction)` and an outcome code:
TURN (value = moment), DASH (value = power), KICK (value = power, direction relative to the facing)
or NONE. The SimpleSoccer engine applies it with soccer/physics.py; the rcssserver client sends it as
`(turn m)`, `(dash p)`, `(kick p d)`. Under `strict` and `assisted` skills steer by the goal's known
position (the caller passes its direction computed from the player's own pose), even when the goal is
out of view; under `sighted` the caller passes NaN for a goal out of view.

Every skill also says why it gave its command (`Outcome` codes below, soccer/outcome.py words them): a
kick that could not happen and why, a turn made before a dash, the hunt's turn. The engine keeps that
code for every tick, so the UI explains what the player did, not only what it decided.

Skills have ids of their own (SKILL_TURN ... SKILL_DONOTHING, HUNT), fixed here. A vocabulary names
actions in whatever order it likes; `skill_table` maps each of its action indices to the skill of the
same name, and refuses a vocabulary with an action no skill performs or whose parameters are not the
ones the skill reads. The kernels take that table as data, so no vocabulary order is frozen in code.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from soccer_lab.fuzzy.rule import DIRECTION, POWER
from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError

from soccer_lab.soccer.physics import clamp, kickable_distance

NONE, TURN, DASH, KICK = 0, 1, 2, 3  # body command kinds

# The skills: the action each performs (by name) and the action parameters it reads. Index = skill id.
SKILLS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("TURN", (DIRECTION,)),
    ("DASH", (POWER,)),
    ("KICK", (DIRECTION, POWER)),
    ("RUNTOWARDGOAL", (POWER,)),
    ("RUNTOWARDBALL", (POWER,)),
    ("GOTOBALL", (POWER,)),
    ("KICKTOWARDGOAL", (POWER,)),
    ("DRIBBLETOWARDGOAL", (POWER,)),
    ("DRIBBLE", (DIRECTION, POWER)),
    ("DONOTHING", ()),
)
(SKILL_TURN, SKILL_DASH, SKILL_KICK, SKILL_RUNTOWARDGOAL, SKILL_RUNTOWARDBALL, SKILL_GOTOBALL, SKILL_KICKTOWARDGOAL,
 SKILL_DRIBBLETOWARDGOAL, SKILL_DRIBBLE, SKILL_DONOTHING) = range(len(SKILLS))
HUNT = -1  # what the player does when no rule fired

LEFT, RIGHT = -1, 1  # side where the ball was last seen

# Why a skill gave its command (soccer/outcome.py words each). ACTED: the skill's own command.
(ACTED, HUNT_BALL, HUNT_LAST_SEEN, TURN_FIRST, BALL_OUT_OF_VIEW, NOT_KICKABLE, GOAL_OUT_OF_VIEW, AT_BALL,
 NO_DASH_NEEDED, NOTHING) = range(10)
FETCHING = 16  # added to the code: an `assisted` kicking skill going to the ball first (GOTOBALL's reasons)


def skill_table(vocabulary: Vocabulary) -> np.ndarray:
    """int64[n_actions]: the skill id of each of the vocabulary's actions, matched by name.
    VocabularyError when an action has no skill or uses other parameters than its skill reads."""
    reads = dict(SKILLS)
    ids = {name: skill for skill, (name, _) in enumerate(SKILLS)}
    problems = []
    for action, uses in vocabulary.actions.items():
        if action not in reads:
            problems.append(f"no skill performs {action}")
        elif set(uses) != set(reads[action]):
            problems.append(f"{action} uses {', '.join(uses) or 'no parameter'} but its skill reads "
                            f"{', '.join(reads[action]) or 'none'}")
    if problems:
        raise VocabularyError(f"the soccer skills cannot play this vocabulary: {'; '.join(problems)} "
                              f"(the skills are {', '.join(ids)})")
    return np.array([ids[action] for action in vocabulary.action_names], dtype=np.int64)


def skill_set_flags(skills: str) -> tuple[bool, bool]:
    """A skill set's two switches: (assisted, goal_in_view_only), as `skill_command` and
    `goal_direction_for_skills` take them."""
    return skills == "assisted", skills == "sighted"


@numba.njit(cache=True)
def goal_direction_for_skills(goal_direction, goal_seen, goal_in_view_only):
    """The goal direction the skills steer by: the one worked out from the player's pose, or NaN (not
    known) when the skills know the goal only in view (`sighted`) and it is out of view."""
    if goal_in_view_only and not goal_seen:
        return math.nan
    return goal_direction


@numba.njit(cache=True)
def turn_toward(direction, speed, constants, outcome):
    """TURN whose moment, after the server's inertia, actually makes `direction` (as far as max_moment allows)."""
    moment = clamp(direction * (1.0 + constants.inertia_moment * speed), -constants.max_moment, constants.max_moment)
    return TURN, moment, 0.0, outcome


@numba.njit(cache=True)
def hunt(ball_visible, ball_direction, last_ball_side, speed, constants):
    """Face the ball if it is visible, else turn hunt_turn degrees toward where it was last seen."""
    if ball_visible:
        return turn_toward(ball_direction, speed, constants, HUNT_BALL)
    return turn_toward(last_ball_side * constants.hunt_turn, speed, constants, HUNT_LAST_SEEN)


@numba.njit(cache=True)
def search_ball(last_ball_side, speed, constants):
    """A skill that needs the ball, which is out of view: the hunt's turn toward where it was last seen."""
    return turn_toward(last_ball_side * constants.hunt_turn, speed, constants, BALL_OUT_OF_VIEW)


@numba.njit(cache=True)
def run_toward(direction, power, speed, constants):
    if abs(direction) > constants.turn_threshold:
        return turn_toward(direction, speed, constants, TURN_FIRST)
    return DASH, power, 0.0, ACTED


@numba.njit(cache=True)
def go_to_ball(power, ball_visible, ball_distance, ball_direction, kickable, last_ball_side, speed, constants):
    """RUNTOWARDBALL that stops when kickable and dashes no harder than needed to stop the player
    halfway into the kickable margin (so it does not overrun the ball)."""
    if kickable:
        return NONE, 0.0, 0.0, AT_BALL
    if not ball_visible:
        return search_ball(last_ball_side, speed, constants)
    if abs(ball_direction) > constants.turn_threshold:
        return turn_toward(ball_direction, speed, constants, TURN_FIRST)
    stop_distance = kickable_distance(constants) - 0.5 * constants.kickable_margin
    needed = (ball_distance - stop_distance - speed) / constants.dash_power_rate
    dash_power = min(power, needed)
    if dash_power <= 0.0:
        return NONE, 0.0, 0.0, NO_DASH_NEEDED
    return DASH, dash_power, 0.0, ACTED


@numba.njit(cache=True)
def skill_command(skill, direction, power, ball_visible, ball_distance, ball_direction, goal_direction,
                  kickable, last_ball_side, speed, assisted, constants):
    """The body command `(kind, value, direction, outcome)` of `skill` (a skill id, HUNT when no rule
    fired) with the selected action's `direction` and `power` values; `outcome` says why (ACTED ...
    NOTHING, plus FETCHING). `ball_*` is the perceived ball (valid when ball_visible), `goal_direction`
    the goal centre's direction from the player's own pose, `kickable` whether the ball is within
    kicking distance, `speed` the player's current speed (m/tick), `assisted` whether the kicking skills
    fetch the ball first (the `assisted` skill set) or do nothing (`strict`).
    A NaN `goal_direction` means the player does not know where the goal is (`sighted`, goal out of
    view): the skills that need it do nothing."""
    goal_known = not math.isnan(goal_direction)
    if skill == HUNT:
        return hunt(ball_visible, ball_direction, last_ball_side, speed, constants)
    if skill == SKILL_TURN:
        return TURN, direction, 0.0, ACTED
    if skill == SKILL_DASH:
        return DASH, power, 0.0, ACTED
    if skill == SKILL_KICK:
        if kickable:
            return KICK, power, direction, ACTED
        return NONE, 0.0, 0.0, NOT_KICKABLE
    if skill == SKILL_RUNTOWARDGOAL:
        if not goal_known:
            return NONE, 0.0, 0.0, GOAL_OUT_OF_VIEW
        return run_toward(goal_direction, power, speed, constants)
    if skill == SKILL_RUNTOWARDBALL:
        if ball_visible:
            return run_toward(ball_direction, power, speed, constants)
        return search_ball(last_ball_side, speed, constants)
    if skill == SKILL_KICKTOWARDGOAL or skill == SKILL_DRIBBLETOWARDGOAL or skill == SKILL_DRIBBLE:
        if kickable and skill != SKILL_DRIBBLE and not goal_known:
            return NONE, 0.0, 0.0, GOAL_OUT_OF_VIEW
        if kickable:
            if skill == SKILL_KICKTOWARDGOAL:
                return KICK, power, goal_direction, ACTED
            if skill == SKILL_DRIBBLETOWARDGOAL:
                return KICK, power * constants.dribble_power_fraction, goal_direction, ACTED
            return KICK, power * constants.dribble_power_fraction, direction, ACTED
        if not assisted:
            return NONE, 0.0, 0.0, NOT_KICKABLE
        kind, value, kick_direction, outcome = go_to_ball(power, ball_visible, ball_distance, ball_direction,
                                                          kickable, last_ball_side, speed, constants)
        return kind, value, kick_direction, outcome + FETCHING
    if skill == SKILL_GOTOBALL:
        return go_to_ball(power, ball_visible, ball_distance, ball_direction, kickable, last_ball_side, speed,
                          constants)
    return NONE, 0.0, 0.0, NOTHING  # SKILL_DONOTHING
