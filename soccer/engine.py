"""The batched SimpleSoccer engine: every game of a population in one pymunk Space, one numba kernel
per tick over all live games (docs/design.md explains the data layout).

Per tick: `tick_kernel` (reading and writing the bodies' positions and velocities where Chipmunk
keeps them, soccer/world.py), remove finished games, `space.step(tick_seconds)`. The kernel's
steps, each a numba function: `close_step` (the step just made: player-ball collision, goal and
restart, statistics, end conditions), `perceive_step`, `decide_step` (the game's own fuzzy
controller, `soccer_lab.fuzzy.batched.decide`), `act_step` (the skill's body command) and `physics_step` (the
command applied to velocities, noise).
Actions given from outside (soccer/gym, `GameBatch.act`) take `act_kernel` and `close_kernel`: the
same steps, in the same order, the decide step left out.
A single game is a batch of one: there is one code path. A game's result does not depend on its batch
(soccer/world.py says how): games sharing a seed share a pitch slot and so play in separate spaces,
each stepped in turn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Sequence

import numba
import numpy as np
from numba.core import cgutils
from numba.extending import intrinsic

from soccer_lab.fuzzy.batched import NO_ACTION, CompiledRulebases, Scratch, VocabularyTables, compile_rulebases, decide
from soccer_lab.fuzzy.rule import POWER, Rulebase
from soccer_lab.fuzzy.rule import DIRECTION as DIRECTION_OUTPUT
from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig, WorldConstants
from soccer_lab.soccer.fitness import fitness
from soccer_lab.soccer.perception import BALL, DIRECTION, DISTANCE, GOAL, perceive
from soccer_lab.soccer.physics import cap_speed, dash, decay, is_kickable, kick, separate, turn
from soccer_lab.soccer.random_stream import seed_states, uniform
from soccer_lab.soccer.skills import (DASH, HUNT, KICK, LEFT, RIGHT, TURN, goal_direction_for_skills, skill_command,
                                      skill_set_flags, skill_table)
from soccer_lab.soccer.world import Pitches, World

RUNNING, MAX_TICKS, GOAL_CAP, IDLE = 0, 1, 2, 3
NO_OUTCOME = -1  # Decision.outcome before a game's first tick, or of the tick before new controllers
END_REASONS = ("running", "max-ticks", "goal-cap", "idle")


class GameRules(NamedTuple):
    """GameConfig's per-tick rules in the flat form the kernel takes."""

    max_ticks: int
    goal_cap: int
    idle_ticks: int
    idle_distance: float
    noise: bool
    assisted_skills: bool
    goal_in_view_only: bool  # the `sighted` skill set: the skills know the goal only while it is seen
    count_touches: bool  # a player-ball collision counts as a kick (GameConfig.count_touches)

    @classmethod
    def from_config(cls, config: GameConfig) -> "GameRules":
        return cls(config.max_ticks, config.goal_cap, config.idle_ticks, config.idle_distance, config.noise,
                   *skill_set_flags(config.skills), config.count_touches)


class VocabularyLayout(NamedTuple):
    """Where SimpleSoccer's quantities sit in a vocabulary, found by name: the perceived inputs and
    objects, the outputs the skills read, and the skill of each action (soccer/skills.py)."""

    ball_distance: int
    ball_direction: int
    goal_distance: int
    goal_direction: int
    ball: int
    goal: int
    direction: int
    power: int
    skills: np.ndarray  # int64[n_actions]: skill id of each vocabulary action

    @classmethod
    def from_vocabulary(cls, vocabulary: Vocabulary) -> "VocabularyLayout":
        """VocabularyError when the vocabulary lacks an object or input perception gives, or has an
        action the skills cannot perform."""
        inputs, objects = vocabulary.input_names, vocabulary.objects
        for obj in (BALL, GOAL):
            if obj not in objects or not {DISTANCE, DIRECTION} <= set(objects[obj]):
                raise VocabularyError(f"SimpleSoccer perceives {BALL} and {GOAL}, each as a {DISTANCE} and a "
                                      f"{DIRECTION}: the vocabulary has no {obj} {DISTANCE} and {DIRECTION}")
        return cls(
            inputs.index(objects[BALL][DISTANCE]),
            inputs.index(objects[BALL][DIRECTION]),
            inputs.index(objects[GOAL][DISTANCE]),
            inputs.index(objects[GOAL][DIRECTION]),
            vocabulary.object_names.index(BALL),
            vocabulary.object_names.index(GOAL),
            vocabulary.output_names.index(DIRECTION_OUTPUT),
            vocabulary.output_names.index(POWER),
            skill_table(vocabulary),
        )


class GameState(NamedTuple):
    """Every game's own bookkeeping, one entry (row) per game g."""

    done: np.ndarray  # bool[n]
    facing: np.ndarray  # float64[n]: the player's facing in degrees (the engine keeps it; pymunk bodies never spin)
    last_player: np.ndarray  # float64[n, 2]: the player's position when it last decided (to close the step)
    last_ball: np.ndarray  # float64[n, 2]
    min_distance: np.ndarray  # float64[n]: closest approach of the ball to the goal centre so far
    ticks: np.ndarray  # int64[n]: ticks played (decisions made)
    goals: np.ndarray  # int64[n]
    kicks: np.ndarray  # int64[n]
    idle: np.ndarray  # int64[n]: consecutive ticks without moving nor kicking
    kicked: np.ndarray  # bool[n]: the last tick's command was a kick
    last_side: np.ndarray  # int64[n]: LEFT or RIGHT, where the player last saw the ball (the hunt turns there)
    end_reason: np.ndarray  # int64[n]: index into END_REASONS
    streams: np.ndarray  # uint64[n]: each game's splitmix64 random stream (soccer/random_stream.py)


class Observation(NamedTuple):
    """What each game's player perceived for its latest decision; a new batch has already perceived
    for the first one (as Gymnasium's reset returns the first observation). Positions are in the
    game's own pitch coordinates (metres, centre origin)."""

    player_x: np.ndarray  # float64[n]
    player_y: np.ndarray  # float64[n]
    facing: np.ndarray  # float64[n], degrees
    ball_x: np.ndarray  # float64[n]
    ball_y: np.ndarray  # float64[n]
    inputs: np.ndarray  # float64[n, n_inputs], in the vocabulary's input order; NaN when the object is out of view
    visible: np.ndarray  # bool[n, n_objects], in the vocabulary's object order


class Decision(NamedTuple):
    """Each game's latest decision (before the first tick: no rule fired, strengths 0)."""

    action: np.ndarray  # int64[n]: the vocabulary's action index, NO_ACTION when no rule fired (the hunt)
    values: np.ndarray  # float64[n, n_outputs]: the action's output values (the defaults where it uses none)
    strengths: np.ndarray  # float64[n, max_rules]: every rule's strength (0 past the game's own rules)
    # What the skill then did (soccer/skills.py, worded by soccer/outcome.py): the body command it sent
    # (kind NONE/TURN/DASH/KICK, its moment or power, a kick's direction) and why (the outcome code).
    command: np.ndarray  # int64[n]
    command_value: np.ndarray  # float64[n]
    command_direction: np.ndarray  # float64[n]
    outcome: np.ndarray  # int64[n]


@dataclass(frozen=True)
class GameResult:
    fitness: float
    goals: int
    kicks: int
    ticks: int
    min_ball_goal_distance: float
    end_reason: str


@dataclass(frozen=True)
class GameTrace:
    """One game tick by tick, as the player saw and decided (before the tick's command took effect)."""

    player_x: np.ndarray
    player_y: np.ndarray
    facing: np.ndarray  # degrees
    ball_x: np.ndarray
    ball_y: np.ndarray
    visible: np.ndarray  # bool[T, 2]: ball, goal
    inputs: np.ndarray  # float[T, 4] in the vocabulary's input order; NaN when the object is out of view
    strengths: np.ndarray  # float[T, rules]
    action: np.ndarray  # int[T]: vocabulary action index, -1 = the default hunt
    direction: np.ndarray  # float[T]: the selected action's direction value
    power: np.ndarray  # float[T]
    goals: np.ndarray  # int[T]: goals scored before this tick
    vocabulary: Vocabulary  # the one the game was played in: it names `action` and orders `inputs`
    command: np.ndarray  # int[T]: the body command the skill sent (soccer/skills.py NONE/TURN/DASH/KICK)
    command_value: np.ndarray  # float[T]: its moment or power
    command_direction: np.ndarray  # float[T]: a kick's direction, relative to the facing
    outcome: np.ndarray  # int[T]: why the skill gave that command (soccer/skills.py, soccer/outcome.py)

    def __len__(self) -> int:
        return len(self.action)


# ---- kernels ----------------------------------------------------------------------------------


@intrinsic
def borrowed(typingctx, value):
    """`value` (an array, or a tuple of arrays and scalars, nested) as views of the same memory that
    hold no reference. Numba counts references to an array each time a variable or an inlined step's
    argument takes it, with an atomic instruction each: in the tick kernel hundreds per game and tick,
    a fifth of the kernel's time (measured). A view without a reference (no meminfo, as `numba.carray`
    makes) skips the count. Valid only while the call that made it runs, the caller holding the
    arrays: a kernel never returns or keeps a borrowed view."""
    def codegen(context, builder, signature, args):
        return _without_reference(context, builder, value, args[0])
    return value(value), codegen


def _without_reference(context, builder, typ, value):
    if isinstance(typ, numba.types.Array):
        array = context.make_array(typ)(context, builder, value=value)
        array.meminfo = cgutils.get_null_value(array.meminfo.type)
        return array._getvalue()
    if isinstance(typ, numba.types.BaseTuple):
        for i, member in enumerate(typ):
            view = _without_reference(context, builder, member, builder.extract_value(value, i))
            value = builder.insert_value(value, view, i)
    return value


@intrinsic
def _doubles_at(typingctx, address):
    # the memory address (an integer) as a pointer to float64s, for numba.carray
    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(signature.return_type))
    return numba.types.CPointer(numba.types.float64)(numba.types.uint64), codegen


@numba.njit(cache=True, inline="always")
def body_vectors(address):
    """A body's (x, y, vx, vy) in pymunk units (global metres, metres per second), as an array over
    Chipmunk's own memory at `address` (soccer/world.py, `vectors_address`). Like a borrowed view it
    holds no reference: the World keeps the body."""
    return numba.carray(_doubles_at(address), 4)


@numba.njit(cache=True)
def start_positions(states, constants):
    """Start of a game (the chapter, 5.1): player uniform in its own half, ball at rest on the centre line."""
    n = states.shape[0]
    player = np.empty((n, 2))
    ball = np.empty((n, 2))
    for g in range(n):
        player[g, 0] = uniform(states, g, -constants.half_length, 0.0)
        player[g, 1] = uniform(states, g, -constants.half_width, constants.half_width)
        ball[g, 0] = 0.0
        ball[g, 1] = uniform(states, g, -constants.half_width, constants.half_width)
    return player, ball


@numba.njit(cache=True)
def _noisy(states, g, vx, vy, rand):
    """rcssserver's velocity noise: each component +- rand x speed, uniformly."""
    spread = rand * math.sqrt(vx * vx + vy * vy)
    return vx + uniform(states, g, -spread, spread), vy + uniform(states, g, -spread, spread)


# The steps are inlined into tick_kernel (as separate calls, each copying the named tuples it is given,
# the tick ran 20% slower), and each first binds the arrays it uses to locals, by name: reaching into
# a named tuple again inside an expression or a call costs numba reference counting every time.


@numba.njit(cache=True, inline="always")
def local_positions(g, player, ball, pitches):
    """Game g's player and ball in its pitch's own coordinates (metres, centre origin)."""
    offsets = pitches.offsets
    ox, oy = offsets[g, 0], offsets[g, 1]
    return player[0] - ox, player[1] - oy, ball[0] - ox, ball[1] - oy


@numba.njit(cache=True, inline="always")
def close_step(g, px, py, bx, by, player, ball, pitches, state, constants, rules):
    """The books of the step just made: rcssserver's player-ball collision (see WorldConfig), goal and
    restart, closest approach, idleness, end conditions. Returns the positions after the collision
    and restart, and whether the game ended now."""
    c = constants
    offsets = pitches.offsets
    facing, last_player, last_ball, min_distance = state.facing, state.last_player, state.last_ball, state.min_distance
    kicked, idle, goals, ticks, kicks = state.kicked, state.idle, state.goals, state.ticks, state.kicks
    end_reason, done, streams = state.end_reason, state.done, state.streams
    ox, oy = offsets[g, 0], offsets[g, 1]
    px, py, bx, by, collided = separate(px, py, bx, by, facing[g], c)
    if collided:
        player[0] = ox + px
        player[1] = oy + py
        ball[0] = ox + bx
        ball[1] = oy + by
        for body in (player, ball):
            body[2] *= c.collision_rebound
            body[3] *= c.collision_rebound
        if rules.count_touches:
            kicks[g] += 1
    scored = False
    if last_ball[g, 0] <= c.half_length < bx:
        t = (c.half_length - last_ball[g, 0]) / (bx - last_ball[g, 0])
        scored = abs(last_ball[g, 1] + t * (by - last_ball[g, 1])) < c.goal_half_width
    dxg = bx - c.half_length
    min_distance[g] = min(min_distance[g], math.sqrt(dxg * dxg + by * by))
    dxp = px - last_player[g, 0]
    dyp = py - last_player[g, 1]
    if kicked[g] or math.sqrt(dxp * dxp + dyp * dyp) > rules.idle_distance:
        idle[g] = 0
    else:
        idle[g] += 1
    if scored:
        goals[g] += 1
        bx = 0.0
        by = uniform(streams, g, -c.half_width, c.half_width)
        ball[0] = ox + bx
        ball[1] = oy + by
        ball[2] = 0.0
        ball[3] = 0.0
    reason = RUNNING
    if goals[g] >= rules.goal_cap:
        reason = GOAL_CAP
    elif ticks[g] >= rules.max_ticks:
        reason = MAX_TICKS
    elif idle[g] >= rules.idle_ticks:
        reason = IDLE
    if reason != RUNNING:
        end_reason[g] = reason
        done[g] = True
        for body in (player, ball):
            body[2] = 0.0
            body[3] = 0.0
    return px, py, bx, by, reason != RUNNING


@numba.njit(cache=True, inline="always")
def perceive_step(g, px, py, bx, by, state, observation, layout, constants):
    """What game g's player perceives from where it stands, into observation[g]; returns perception's
    (ball distance, ball direction, ball visible, goal distance, goal direction, goal visible)."""
    facing, inputs, visible = state.facing, observation.inputs, observation.visible
    player_x, player_y, seen_facing = observation.player_x, observation.player_y, observation.facing
    ball_x, ball_y = observation.ball_x, observation.ball_y
    f = facing[g]
    perceived = perceive(px, py, f, bx, by, constants)
    ball_distance, ball_direction, ball_seen, goal_distance, goal_direction, goal_seen = perceived
    inputs[g, layout.ball_distance] = ball_distance if ball_seen else np.nan
    inputs[g, layout.ball_direction] = ball_direction if ball_seen else np.nan
    inputs[g, layout.goal_distance] = goal_distance if goal_seen else np.nan
    inputs[g, layout.goal_direction] = goal_direction if goal_seen else np.nan
    visible[g, layout.ball] = ball_seen
    visible[g, layout.goal] = goal_seen
    player_x[g] = px
    player_y[g] = py
    seen_facing[g] = f
    ball_x[g] = bx
    ball_y[g] = by
    return perceived


@numba.njit(cache=True, inline="always")
def decide_step(g, observation, decision, rulebases, scratch):
    """Game g's fuzzy controller on its observation, into decision[g]; returns the action (NO_ACTION: hunt)."""
    inputs, visible = observation.inputs, observation.visible
    actions, values, strengths = decision.action, decision.values, decision.strengths
    action, _ = decide(g, inputs[g], visible[g], rulebases, scratch, strengths[g], values[g])
    actions[g] = action
    return action


@numba.njit(cache=True, inline="always")
def act_step(g, action, perceived, speed, state, decision, layout, constants, rules):
    """The body command (kind, value, direction) the action's skill gives, and whether the ball is kickable;
    the command and why the skill gave it are kept in decision[g]."""
    last_side, values, skills = state.last_side, decision.values, layout.skills
    commands, command_values, command_directions, outcomes = (decision.command, decision.command_value,
                                                              decision.command_direction, decision.outcome)
    ball_distance, ball_direction, ball_seen, _, goal_direction, goal_seen = perceived
    goal_direction = goal_direction_for_skills(goal_direction, goal_seen, rules.goal_in_view_only)
    if ball_seen:
        last_side[g] = LEFT if ball_direction < 0.0 else RIGHT
    kickable = is_kickable(ball_distance, constants)
    skill = HUNT if action == NO_ACTION else skills[action]
    kind, value, direction, outcome = skill_command(
        skill, values[g, layout.direction], values[g, layout.power], ball_seen, ball_distance, ball_direction,
        goal_direction, kickable, last_side[g], speed, rules.assisted_skills, constants)
    commands[g] = kind
    command_values[g] = value
    command_directions[g] = direction
    outcomes[g] = outcome
    return kind, value, direction, kickable


@numba.njit(cache=True, inline="always")
def physics_step(g, command, perceived, velocities, positions, player, ball, state, constants, rules):
    """The command applied to game g's facing and (already decayed) velocities, noise, the velocities
    written back for pymunk's step; the positions kept to close the step."""
    c = constants
    dt = c.tick_seconds
    facing, kicked, kicks, streams = state.facing, state.kicked, state.kicks, state.streams
    last_player, last_ball, ticks = state.last_player, state.last_ball, state.ticks
    kind, value, direction, kickable = command
    ball_distance, ball_direction = perceived[0], perceived[1]
    pvx, pvy, bvx, bvy = velocities
    f = facing[g]
    kicked[g] = False
    if kind == TURN:
        if rules.noise:
            value *= 1.0 + uniform(streams, g, -c.player_rand, c.player_rand)
        facing[g] = turn(f, value, math.sqrt(pvx * pvx + pvy * pvy), c)
    elif kind == DASH:
        pvx, pvy = dash(pvx, pvy, f, value, c)
    elif kind == KICK and kickable:
        bvx, bvy = kick(bvx, bvy, value, direction, f, ball_distance, ball_direction, c)
        kicks[g] += 1
        kicked[g] = True
    if rules.noise:
        pvx, pvy = cap_speed(*_noisy(streams, g, pvx, pvy, c.player_rand), c.player_speed_max)
        bvx, bvy = cap_speed(*_noisy(streams, g, bvx, bvy, c.ball_rand), c.ball_speed_max)
    player[2] = pvx / dt
    player[3] = pvy / dt
    ball[2] = bvx / dt
    ball[3] = bvy / dt
    px, py, bx, by = positions
    last_player[g, 0] = px
    last_player[g, 1] = py
    last_ball[g, 0] = bx
    last_ball[g, 1] = by
    ticks[g] += 1


@numba.njit(cache=True)
def tick_kernel(pitches, state, observation, decision, rulebases, scratch, layout, constants, rules):
    """One tick for every live game (of every space); returns how many games finished now. Game g's
    bodies are read and written where Chipmunk keeps them (`body_vectors`). The named tuples arrive
    as plain ones (see `plain`) and are named again here, as borrowed views (see `borrowed`)."""
    pitches, state, observation = borrowed(pitches), borrowed(state), borrowed(observation)
    decision, rulebases, scratch, layout = borrowed(decision), borrowed(rulebases), borrowed(scratch), borrowed(layout)
    pitches, state, observation, decision = Pitches(*pitches), GameState(*state), Observation(*observation), \
        Decision(*decision)
    rulebases = CompiledRulebases(*(rulebases[:-1] + (VocabularyTables(*rulebases[-1]),)))
    scratch, layout = Scratch(*scratch), VocabularyLayout(*layout)
    constants, rules = WorldConstants(*constants), GameRules(*rules)
    dt = constants.tick_seconds
    done, ticks = state.done, state.ticks
    player_at, ball_at = pitches.player, pitches.ball
    finished = 0
    for g in range(done.shape[0]):
        if done[g]:
            continue
        player, ball = body_vectors(player_at[g]), body_vectors(ball_at[g])
        px, py, bx, by = local_positions(g, player, ball, pitches)
        if ticks[g] > 0:
            px, py, bx, by, ended = close_step(g, px, py, bx, by, player, ball, pitches, state, constants, rules)
            if ended:
                finished += 1
                continue
        # velocities decay first (rcssserver does it at the end of the previous cycle)
        pvx, pvy = decay(player[2] * dt, player[3] * dt, constants.player_decay)
        bvx, bvy = decay(ball[2] * dt, ball[3] * dt, constants.ball_decay)
        perceived = perceive_step(g, px, py, bx, by, state, observation, layout, constants)
        action = decide_step(g, observation, decision, rulebases, scratch)
        command = act_step(g, action, perceived, math.sqrt(pvx * pvx + pvy * pvy), state, decision, layout,
                           constants, rules)
        physics_step(g, command, perceived, (pvx, pvy, bvx, bvy), (px, py, bx, by), player, ball, state,
                     constants, rules)
    return finished


@numba.njit(cache=True)
def observe_kernel(pitches, state, observation, layout, constants, games):
    """Perception alone for the given (new, live) games: a game's first observation, the very one its
    first tick perceives again. The named tuples arrive as plain ones (see `plain`)."""
    pitches, state, observation = Pitches(*pitches), GameState(*state), Observation(*observation)
    layout, constants = VocabularyLayout(*layout), WorldConstants(*constants)
    done, player_at, ball_at = state.done, pitches.player, pitches.ball
    for g in games:
        if not done[g]:
            player, ball = body_vectors(player_at[g]), body_vectors(ball_at[g])
            px, py, bx, by = local_positions(g, player, ball, pitches)
            perceive_step(g, px, py, bx, by, state, observation, layout, constants)


# Actions given from outside (soccer/gym): `act_kernel`, pymunk's step, then `close_kernel` play one tick
# as `tick_kernel` does, its decide step replaced by the given actions. The tick kernel closes a step at
# the start of the next tick; here it is closed at once, so the caller sees the outcome and the next
# observation before it chooses the next action. The order of the steps, and so every result, is the same.


@numba.njit(cache=True)
def act_kernel(pitches, state, observation, decision, layout, constants, rules, actions, values):
    """Every live game's given action (a vocabulary action index, NO_ACTION: the hunt) and output values,
    acted on from the game's latest observation: tick_kernel's act and physics steps. The named tuples
    arrive as plain ones (see `plain`)."""
    pitches, state, observation = borrowed(pitches), borrowed(state), borrowed(observation)
    decision, layout = borrowed(decision), borrowed(layout)
    pitches, state, observation, decision = Pitches(*pitches), GameState(*state), Observation(*observation), \
        Decision(*decision)
    layout, constants, rules = VocabularyLayout(*layout), WorldConstants(*constants), GameRules(*rules)
    dt = constants.tick_seconds
    done, facing, player_at, ball_at = state.done, state.facing, pitches.player, pitches.ball
    # the positions the observation was perceived at, exactly (re-read from the bodies they may differ
    # by the rounding of the pitch offset)
    player_x, player_y, ball_x, ball_y = observation.player_x, observation.player_y, observation.ball_x, \
        observation.ball_y
    chosen, chosen_values = decision.action, decision.values
    for g in range(done.shape[0]):
        if done[g]:
            continue
        player, ball = body_vectors(player_at[g]), body_vectors(ball_at[g])
        px, py, bx, by = player_x[g], player_y[g], ball_x[g], ball_y[g]
        pvx, pvy = decay(player[2] * dt, player[3] * dt, constants.player_decay)
        bvx, bvy = decay(ball[2] * dt, ball[3] * dt, constants.ball_decay)
        perceived = perceive(px, py, facing[g], bx, by, constants)
        chosen[g] = actions[g]
        chosen_values[g, :] = values[g, :]
        command = act_step(g, actions[g], perceived, math.sqrt(pvx * pvx + pvy * pvy), state, decision, layout,
                           constants, rules)
        physics_step(g, command, perceived, (pvx, pvy, bvx, bvy), (px, py, bx, by), player, ball, state,
                     constants, rules)


@numba.njit(cache=True)
def close_kernel(pitches, state, observation, layout, constants, rules):
    """After pymunk's step: every live game's step closed (tick_kernel's close step) and its next
    observation perceived. Returns how many games finished now."""
    pitches, state, observation = borrowed(pitches), borrowed(state), borrowed(observation)
    layout = borrowed(layout)
    pitches, state, observation = Pitches(*pitches), GameState(*state), Observation(*observation)
    layout, constants, rules = VocabularyLayout(*layout), WorldConstants(*constants), GameRules(*rules)
    done, ticks, player_at, ball_at = state.done, state.ticks, pitches.player, pitches.ball
    finished = 0
    for g in range(done.shape[0]):
        if done[g] or ticks[g] == 0:
            continue
        player, ball = body_vectors(player_at[g]), body_vectors(ball_at[g])
        px, py, bx, by = local_positions(g, player, ball, pitches)
        px, py, bx, by, ended = close_step(g, px, py, bx, by, player, ball, pitches, state, constants, rules)
        finished += ended
        # also at the end: a Gymnasium episode's last observation shows where it ended
        perceive_step(g, px, py, bx, by, state, observation, layout, constants)
    return finished


# ---- the batch --------------------------------------------------------------------------------


def plain(value: tuple) -> tuple:
    """A named tuple, with the named tuples in it, as plain tuples. Numba's dispatcher types plain
    tuples in C at every call but named ones in Python (measured: 4x slower per field), which cost
    every tick tens of microseconds; the kernel names them again."""
    return tuple(plain(v) if isinstance(v, tuple) else v for v in value)


class KernelArguments(NamedTuple):
    """A batch's named tuples in the plain form the kernels take, kept by name between ticks."""

    pitches: tuple
    state: tuple
    observation: tuple
    decision: tuple
    rulebases: tuple
    scratch: tuple
    layout: tuple
    constants: tuple
    rules: tuple



class GameBatch:
    """Games of N players (each its own rulebase and seed) played together, tick by tick.

    What the outside reads (numpy arrays, row g = game g, updated in place by every `step`):
    `state` (GameState: goals, kicks, ticks, done, end reasons, ...), `observation` (Observation: what
    each player perceived for its latest decision, already filled for the first one when the batch is
    built) and `decision` (Decision: the selected action, its output values and every rule's strength).
    `compiled` holds the players' rulebases as the kernel reads them (soccer_lab.fuzzy.batched), `layout` where
    SimpleSoccer's quantities sit in the vocabulary, `world` the pymunk spaces."""

    def __init__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int], config: GameConfig,
                 vocabulary: Vocabulary):
        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds: need one seed per game")
        self.config = config
        self.vocabulary = vocabulary
        self.constants: WorldConstants = config.world.constants()
        self.rules = GameRules.from_config(config)
        self.layout = VocabularyLayout.from_vocabulary(vocabulary)
        n = len(rulebases)
        self.games = n
        streams = seed_states(seeds)
        player, ball = start_positions(streams, self.constants)
        self.world = World(config.world, seeds)
        for g in range(n):
            self.world.add_game(g, tuple(player[g]), tuple(ball[g]))

        goal_dx = ball[:, 0] - self.constants.half_length
        self.state = GameState(
            done=np.zeros(n, dtype=np.bool_),
            facing=np.zeros(n),  # every player starts facing +x, the goal it attacks
            last_player=player.copy(),
            last_ball=ball.copy(),
            min_distance=np.sqrt(goal_dx * goal_dx + ball[:, 1] * ball[:, 1]),
            ticks=np.zeros(n, dtype=np.int64),
            goals=np.zeros(n, dtype=np.int64),
            kicks=np.zeros(n, dtype=np.int64),
            idle=np.zeros(n, dtype=np.int64),
            kicked=np.zeros(n, dtype=np.bool_),
            last_side=np.full(n, LEFT, dtype=np.int64),
            end_reason=np.zeros(n, dtype=np.int64),
            streams=streams,
        )
        self.observation = Observation(
            player_x=np.zeros(n), player_y=np.zeros(n), facing=np.zeros(n), ball_x=np.zeros(n), ball_y=np.zeros(n),
            inputs=np.full((n, len(vocabulary.input_names)), np.nan),
            visible=np.zeros((n, len(vocabulary.object_names)), dtype=np.bool_),
        )
        self.decision = Decision(action=np.full(n, NO_ACTION, dtype=np.int64),
                                 values=np.zeros((n, len(vocabulary.output_names))), strengths=np.zeros((n, 1)),
                                 command=np.zeros(n, dtype=np.int64), command_value=np.zeros(n),
                                 command_direction=np.zeros(n), outcome=np.full(n, NO_OUTCOME, dtype=np.int64))
        self.set_rulebases(rulebases)
        self._live = n
        self._acted: bool | None = None  # played by `act` (True) or by `step` (False): never both
        a = self._arguments
        observe_kernel(a.pitches, a.state, a.observation, a.layout, a.constants, np.arange(n))

    def set_rulebases(self, rulebases: Sequence[Rulebase]) -> None:
        """Give the players (new) controllers; the games go on where they are."""
        if len(rulebases) != self.games:
            raise ValueError(f"need {self.games} rulebases, got {len(rulebases)}")
        self.compiled: CompiledRulebases = compile_rulebases(list(rulebases), self.vocabulary)
        # The last tick's outcome was the old controllers' doing: it no longer explains the decision shown
        self.decision = self.decision._replace(strengths=np.zeros((self.games, max(self.compiled.max_rules, 1))),
                                               outcome=np.full(self.games, NO_OUTCOME, dtype=np.int64))
        self._arguments = KernelArguments(
            pitches=plain(self.world.pitches), state=plain(self.state), observation=plain(self.observation),
            decision=plain(self.decision), rulebases=plain(self.compiled),
            scratch=plain(Scratch.for_rulebases(self.compiled)), layout=plain(self.layout),
            constants=plain(self.constants), rules=plain(self.rules))

    @property
    def finished(self) -> bool:
        return self._live == 0

    def step(self) -> None:
        """One tick of every live game (a finished game's last call only closes its books)."""
        if self._live == 0:
            return
        self._played_by(acted=False)
        a = self._arguments
        finished = tick_kernel(a.pitches, a.state, a.observation, a.decision, a.rulebases, a.scratch, a.layout,
                               a.constants, a.rules)
        self._remove_finished(finished)
        self._step_spaces()

    def act(self, actions: np.ndarray, values: np.ndarray) -> None:
        """One tick of every live game with its action given from outside instead of its controller's:
        actions int64[n] (a vocabulary action index, NO_ACTION: the hunt), values float64[n, n_outputs]
        (the action's output values); rows of finished games are ignored. The tick is closed at once:
        `state` holds its goals and end, `observation` the next one (soccer/gym plays through this)."""
        self._played_by(acted=True)
        a = self._arguments
        act_kernel(a.pitches, a.state, a.observation, a.decision, a.layout, a.constants, a.rules,
                   np.ascontiguousarray(actions, dtype=np.int64), np.ascontiguousarray(values, dtype=np.float64))
        self._step_spaces()
        self._remove_finished(close_kernel(a.pitches, a.state, a.observation, a.layout, a.constants, a.rules))

    def restart(self, g: int, seed: int) -> None:
        """Game g begins a new game from `seed` (a vector environment's reset of one sub-environment),
        played as `play_game(rulebase, seed)` plays it; the other games go on. Only for a batch played
        by `act`: the new game has no controller."""
        self._played_by(acted=True)
        if not self.state.done[g]:
            self._live -= 1
        streams = self.state.streams[g:g + 1]  # a view: start_positions draws from game g's own stream
        streams[0] = seed_states([seed])[0]
        player, ball = start_positions(streams, self.constants)
        self.world.restart_game(g, seed, tuple(player[0]), tuple(ball[0]))
        _reset_row(self.state, self.decision, g, player[0], ball[0], self.constants.half_length)
        self._live += 1
        a = self._arguments
        observe_kernel(a.pitches, a.state, a.observation, a.layout, a.constants, np.array([g]))

    def _played_by(self, acted: bool) -> None:
        # `step` closes the previous tick when the next begins, `act` at once: mixed, a tick would close twice
        if self._acted is None:
            self._acted = acted
        elif self._acted != acted:
            raise RuntimeError("a batch is played either by step() (its controllers) or by act() (given "
                               "actions), not both")

    def _remove_finished(self, finished: int) -> None:
        if finished:
            self._live -= finished
            world = self.world
            for g in np.flatnonzero(self.state.done & (world.pitches.player != 0)):
                world.remove_game(int(g))

    def _step_spaces(self) -> None:
        world = self.world
        for layer in world.occupied_layers():
            world.spaces[layer].step(self.constants.tick_seconds)

    def run(self) -> list[GameResult]:
        while self._live:
            self.step()
        return self.results()

    def result(self, g: int) -> GameResult:
        s = self.state
        goals, kicks, ticks = int(s.goals[g]), int(s.kicks[g]), int(s.ticks[g])
        distance = float(s.min_distance[g])
        return GameResult(
            fitness=fitness(self.config.fitness, goals, kicks, ticks, distance, self.config.world.pitch_length),
            goals=goals,
            kicks=kicks,
            ticks=ticks,
            min_ball_goal_distance=distance,
            end_reason=END_REASONS[s.end_reason[g]],
        )

    def results(self) -> list[GameResult]:
        return [self.result(g) for g in range(self.games)]


def _reset_row(state: GameState, decision: Decision, g: int, player: np.ndarray, ball: np.ndarray,
               half_length: float) -> None:
    """Game g's bookkeeping as a new batch starts it (GameBatch.__init__), its stream already seeded."""
    for name in ("done", "kicked"):
        getattr(state, name)[g] = False
    for name in ("facing", "ticks", "goals", "kicks", "idle", "end_reason"):
        getattr(state, name)[g] = 0
    state.last_player[g] = player
    state.last_ball[g] = ball
    goal_dx = ball[0] - half_length
    state.min_distance[g] = np.sqrt(goal_dx * goal_dx + ball[1] * ball[1])
    state.last_side[g] = LEFT
    decision.action[g] = NO_ACTION
    decision.values[g] = 0.0
    decision.strengths[g] = 0.0
    decision.command[g] = 0
    decision.command_value[g] = 0.0
    decision.command_direction[g] = 0.0
    decision.outcome[g] = NO_OUTCOME


def play_games(rulebases: Sequence[Rulebase], seeds: Sequence[int], config: GameConfig = GameConfig(),
               vocabulary: Vocabulary = SOCCER_VOCABULARY) -> list[GameResult]:
    """Play one game per (rulebase, seed), all in one batch; results in the same order."""
    if not rulebases:
        return []
    return GameBatch(rulebases, seeds, config, vocabulary).run()


def play_game(rulebase: Rulebase, seed: int, config: GameConfig = GameConfig(), trace: bool = True,
              vocabulary: Vocabulary = SOCCER_VOCABULARY) -> tuple[GameResult, GameTrace | None]:
    """One game (a batch of one) and, when `trace`, what happened at every tick."""
    batch = GameBatch([rulebase], [seed], config, vocabulary)
    rows: list[tuple] = []
    while not batch.finished:
        before = int(batch.state.ticks[0])
        batch.step()
        if trace and batch.state.ticks[0] > before:
            seen, decided = batch.observation, batch.decision
            rows.append((seen.player_x[0], seen.player_y[0], seen.facing[0], seen.ball_x[0], seen.ball_y[0],
                         seen.visible[0].copy(), seen.inputs[0].copy(), decided.strengths[0, : len(rulebase)].copy(),
                         int(decided.action[0]), decided.values[0].copy(), int(batch.state.goals[0]),
                         int(decided.command[0]), float(decided.command_value[0]),
                         float(decided.command_direction[0]), int(decided.outcome[0])))
    result = batch.result(0)
    if not trace:
        return result, None
    return result, _trace(rows, batch.layout, len(rulebase), vocabulary)


def _trace(rows: list[tuple], layout: VocabularyLayout, rules: int, vocabulary: Vocabulary) -> GameTrace:
    columns = list(zip(*rows)) if rows else [()] * 15
    (player_x, player_y, facing, ball_x, ball_y, visible, inputs, strengths, action, values, goals, command,
     command_value, command_direction, outcome) = columns
    values = np.array(values).reshape(len(rows), len(vocabulary.output_names))
    return GameTrace(
        player_x=np.array(player_x, dtype=np.float64),
        player_y=np.array(player_y, dtype=np.float64),
        facing=np.array(facing, dtype=np.float64),
        ball_x=np.array(ball_x, dtype=np.float64),
        ball_y=np.array(ball_y, dtype=np.float64),
        visible=np.array(visible, dtype=np.bool_).reshape(len(rows), len(vocabulary.object_names)),
        inputs=np.array(inputs, dtype=np.float64).reshape(len(rows), len(vocabulary.input_names)),
        strengths=np.array(strengths, dtype=np.float64).reshape(len(rows), rules),
        action=np.array(action, dtype=np.int64),
        direction=values[:, layout.direction],
        power=values[:, layout.power],
        goals=np.array(goals, dtype=np.int64),
        vocabulary=vocabulary,
        command=np.array(command, dtype=np.int64),
        command_value=np.array(command_value, dtype=np.float64),
        command_direction=np.array(command_direction, dtype=np.float64),
        outcome=np.array(outcome, dtype=np.int64),
    )
