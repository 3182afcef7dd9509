"""The batched SimpleSoccer engine: every game of a population in one pymunk Space,
one numba kernel per tick over all live games.

Per tick: read every body's position and velocity with `pymunk.batch`, run `tick_kernel` (the previous
step's bookkeeping: player-ball collision, goal, restart, statistics, end conditions; then perception,
the game's own fuzzy controller via `fuzzy.batched.decide`, the skill, the physics), write the bodies
back, remove finished games, `space.step(tick_seconds)`. A single game is a batch of one: there is one
code path. A game's result does not depend on its batch (soccer/world.py says how): games sharing a
seed share a pitch slot and so play in separate spaces, one kernel call and one step each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Sequence

import numba
import numpy as np
import pymunk
import pymunk.batch

from fuzzy.batched import NO_ACTION, compile_rulebases, decide
from fuzzy.rule import POWER, Rulebase
from fuzzy.rule import DIRECTION as DIRECTION_OUTPUT
from fuzzy.vocabulary import Vocabulary, VocabularyError
from soccer.config import SOCCER_VOCABULARY, GameConfig, WorldConstants
from soccer.fitness import fitness
from soccer.perception import BALL, DIRECTION, DISTANCE, GOAL, perceive
from soccer.physics import cap_speed, dash, decay, is_kickable, kick, separate, turn
from soccer.random_stream import seed_states, uniform
from soccer.skills import DASH, HUNT, KICK, LEFT, RIGHT, TURN, skill_command, skill_table
from soccer.world import World

RUNNING, MAX_TICKS, GOAL_CAP, IDLE = 0, 1, 2, 3
END_REASONS = ("running", "max-ticks", "goal-cap", "idle")
_FIELDS = pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.VELOCITY


class GameRules(NamedTuple):
    """GameConfig's per-tick rules in the flat form the kernel takes."""

    max_ticks: int
    goal_cap: int
    idle_ticks: int
    idle_distance: float
    noise: bool
    assisted_skills: bool

    @classmethod
    def from_config(cls, config: GameConfig) -> "GameRules":
        return cls(config.max_ticks, config.goal_cap, config.idle_ticks, config.idle_distance, config.noise,
                   config.skills == "assisted")


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

    def __len__(self) -> int:
        return len(self.action)


# ---- kernels ----------------------------------------------------------------------------------


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


@numba.njit(cache=True)
def tick_kernel(
    bodies, layer, game_layer, player_slot, ball_slot, offsets, done, facing, last_player, last_ball, min_distance,
    ticks, goals, kicks, idle, kicked, last_side, end_reason, states,
    inputs, visible, action, values, strengths, observed,
    rulebases, scratch, layout, constants, rules,
):
    """One tick for every live game in space `layer`; returns how many games finished now.
    The step just made is first closed: player-ball collision (rcssserver's, see WorldConfig), goal
    and restart, statistics, end conditions.
    bodies[row] = (x, y, vx, vy) in pymunk units (global metres, metres per second); game g's rows are
    player_slot[g] and ball_slot[g]. `scratch` = decide's work arrays (degrees, support, first_rule,
    cut_lo, cut_hi)."""
    c = constants
    dt = c.tick_seconds
    degrees, support, first_rule, cut_lo, cut_hi = scratch
    finished = 0
    for g in range(done.shape[0]):
        if done[g] or game_layer[g] != layer:
            continue
        ps = player_slot[g]
        bs = ball_slot[g]
        ox = offsets[g, 0]
        oy = offsets[g, 1]
        px = bodies[ps, 0] - ox
        py = bodies[ps, 1] - oy
        bx = bodies[bs, 0] - ox
        by = bodies[bs, 1] - oy

        if ticks[g] > 0:  # bookkeeping of the step just made
            px, py, bx, by, collided = separate(px, py, bx, by, facing[g], c)
            if collided:
                bodies[ps, 0] = ox + px
                bodies[ps, 1] = oy + py
                bodies[bs, 0] = ox + bx
                bodies[bs, 1] = oy + by
                for row in (ps, bs):
                    bodies[row, 2] *= c.collision_rebound
                    bodies[row, 3] *= c.collision_rebound
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
                by = uniform(states, g, -c.half_width, c.half_width)
                bodies[bs, 0] = ox + bx
                bodies[bs, 1] = oy + by
                bodies[bs, 2] = 0.0
                bodies[bs, 3] = 0.0
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
                finished += 1
                for row in (ps, bs):
                    bodies[row, 2] = 0.0
                    bodies[row, 3] = 0.0
                continue

        # the tick: velocities decay (rcssserver does it at the end of the previous cycle), perceive, decide, act
        pvx, pvy = decay(bodies[ps, 2] * dt, bodies[ps, 3] * dt, c.player_decay)
        bvx, bvy = decay(bodies[bs, 2] * dt, bodies[bs, 3] * dt, c.ball_decay)
        f = facing[g]
        ball_distance, ball_direction, ball_seen, goal_distance, goal_direction, goal_seen = perceive(
            px, py, f, bx, by, c)
        x = inputs[g]
        x[layout.ball_distance] = ball_distance if ball_seen else np.nan
        x[layout.ball_direction] = ball_direction if ball_seen else np.nan
        x[layout.goal_distance] = goal_distance if goal_seen else np.nan
        x[layout.goal_direction] = goal_direction if goal_seen else np.nan
        seen = visible[g]
        seen[layout.ball] = ball_seen
        seen[layout.goal] = goal_seen
        chosen, _ = decide(g, x, seen, *rulebases, degrees, support, first_rule, strengths[g], cut_lo, cut_hi,
                           values[g])
        action[g] = chosen
        observed[g, 0] = px
        observed[g, 1] = py
        observed[g, 2] = f
        observed[g, 3] = bx
        observed[g, 4] = by
        if ball_seen:
            last_side[g] = LEFT if ball_direction < 0.0 else RIGHT
        speed = math.sqrt(pvx * pvx + pvy * pvy)
        kickable = is_kickable(ball_distance, c)
        skill = HUNT if chosen == NO_ACTION else layout.skills[chosen]
        kind, value, direction = skill_command(
            skill, values[g, layout.direction], values[g, layout.power], ball_seen, ball_distance, ball_direction,
            goal_direction, kickable, last_side[g], speed, rules.assisted_skills, c)
        kicked[g] = False
        if kind == TURN:
            if rules.noise:
                value *= 1.0 + uniform(states, g, -c.player_rand, c.player_rand)
            facing[g] = turn(f, value, speed, c)
        elif kind == DASH:
            pvx, pvy = dash(pvx, pvy, f, value, c)
        elif kind == KICK and kickable:
            bvx, bvy = kick(bvx, bvy, value, direction, f, ball_distance, ball_direction, c)
            kicks[g] += 1
            kicked[g] = True
        if rules.noise:
            pvx, pvy = cap_speed(*_noisy(states, g, pvx, pvy, c.player_rand), c.player_speed_max)
            bvx, bvy = cap_speed(*_noisy(states, g, bvx, bvy, c.ball_rand), c.ball_speed_max)
        bodies[ps, 2] = pvx / dt
        bodies[ps, 3] = pvy / dt
        bodies[bs, 2] = bvx / dt
        bodies[bs, 3] = bvy / dt
        last_player[g, 0] = px
        last_player[g, 1] = py
        last_ball[g, 0] = bx
        last_ball[g, 1] = by
        ticks[g] += 1
    return finished


# ---- the batch --------------------------------------------------------------------------------


class GameBatch:
    """Games of N players (each its own rulebase and seed) played together, tick by tick."""

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
        self.states = seed_states(seeds)
        player, ball = start_positions(self.states, self.constants)
        self.world = World(config.world, seeds)
        for g in range(n):
            self.world.add_game(g, tuple(player[g]), tuple(ball[g]))
        self.world.index_bodies()

        self.done = np.zeros(n, dtype=np.bool_)
        self.facing = np.zeros(n)  # every player starts facing +x, the goal it attacks
        self.last_player = player.copy()
        self.last_ball = ball.copy()
        goal_dx = ball[:, 0] - self.constants.half_length
        self.min_distance = np.sqrt(goal_dx * goal_dx + ball[:, 1] * ball[:, 1])
        self.ticks = np.zeros(n, dtype=np.int64)
        self.goals = np.zeros(n, dtype=np.int64)
        self.kicks = np.zeros(n, dtype=np.int64)
        self.idle = np.zeros(n, dtype=np.int64)
        self.kicked = np.zeros(n, dtype=np.bool_)
        self.last_side = np.full(n, LEFT, dtype=np.int64)
        self.end_reason = np.zeros(n, dtype=np.int64)
        self.inputs = np.full((n, len(vocabulary.input_names)), np.nan)
        self.visible = np.zeros((n, len(vocabulary.object_names)), dtype=np.bool_)
        self.action = np.full(n, NO_ACTION, dtype=np.int64)
        self.values = np.zeros((n, len(vocabulary.output_names)))
        self.set_rulebases(rulebases)
        self.observed = np.zeros((n, 5))  # player x, y, facing, ball x, y at the last decision
        self._buffers = [pymunk.batch.Buffer() for _ in self.world.spaces]
        self._live = n

    def set_rulebases(self, rulebases: Sequence[Rulebase]) -> None:
        """Give the players (new) controllers; the games go on where they are."""
        if len(rulebases) != self.games:
            raise ValueError(f"need {self.games} rulebases, got {len(rulebases)}")
        self.compiled = compile_rulebases(list(rulebases), self.vocabulary)
        self._rulebase_args = self.compiled.kernel_args()
        tables = self.compiled.tables
        width = max(self.compiled.max_rules, 1)
        n_actions = tables.action_uses.shape[0]
        self._scratch = (np.empty(tables.term_input.size), np.empty(n_actions), np.empty(n_actions, dtype=np.int64),
                         np.empty(width), np.empty(width))
        self.strengths = np.zeros((self.games, width))

    @property
    def finished(self) -> bool:
        return self._live == 0

    def step(self) -> None:
        """One tick of every live game (a finished game's last call only closes its books)."""
        if self._live == 0:
            return
        world = self.world
        finished = 0
        for layer, (space, buffer) in enumerate(zip(world.spaces, self._buffers)):
            buffer.clear()
            pymunk.batch.get_space_bodies(space, _FIELDS, buffer)
            bodies = np.frombuffer(buffer.float_buf(), dtype=np.float64).reshape(-1, 4)
            finished += tick_kernel(
                bodies, layer, world.layer, world.player_slot, world.ball_slot, world.offsets, self.done, self.facing,
                self.last_player, self.last_ball, self.min_distance, self.ticks, self.goals, self.kicks, self.idle,
                self.kicked, self.last_side, self.end_reason, self.states, self.inputs, self.visible, self.action,
                self.values, self.strengths, self.observed, self._rulebase_args, self._scratch, self.layout,
                self.constants, self.rules)
            pymunk.batch.set_space_bodies(space, _FIELDS, buffer)
        if finished:
            self._live -= finished
            for g in np.flatnonzero(self.done & (world.player_slot >= 0)):
                world.remove_game(int(g))
            world.index_bodies()
        if self._live:
            for space in world.spaces:
                space.step(self.constants.tick_seconds)

    def run(self) -> list[GameResult]:
        while self._live:
            self.step()
        return self.results()

    def result(self, g: int) -> GameResult:
        goals, kicks, ticks = int(self.goals[g]), int(self.kicks[g]), int(self.ticks[g])
        distance = float(self.min_distance[g])
        return GameResult(
            fitness=fitness(self.config.fitness, goals, kicks, ticks, distance),
            goals=goals,
            kicks=kicks,
            ticks=ticks,
            min_ball_goal_distance=distance,
            end_reason=END_REASONS[self.end_reason[g]],
        )

    def results(self) -> list[GameResult]:
        return [self.result(g) for g in range(self.games)]


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
        before = int(batch.ticks[0])
        batch.step()
        if trace and batch.ticks[0] > before:
            goals = int(batch.goals[0])
            rows.append((batch.observed[0].copy(), batch.visible[0].copy(), batch.inputs[0].copy(),
                         batch.strengths[0, : len(rulebase)].copy(), int(batch.action[0]), batch.values[0].copy(),
                         goals))
    result = batch.result(0)
    if not trace:
        return result, None
    return result, _trace(rows, batch.layout, len(rulebase), batch.vocabulary)


def _trace(rows: list[tuple], layout: VocabularyLayout, rules: int, vocabulary: Vocabulary) -> GameTrace:
    inputs = len(vocabulary.input_names)
    observed = np.array([r[0] for r in rows]).reshape(-1, 5)
    values = np.array([r[5] for r in rows]).reshape(len(rows), -1)
    return GameTrace(
        player_x=observed[:, 0],
        player_y=observed[:, 1],
        facing=observed[:, 2],
        ball_x=observed[:, 3],
        ball_y=observed[:, 4],
        visible=np.array([r[1] for r in rows], dtype=np.bool_).reshape(len(rows), -1),
        inputs=np.array([r[2] for r in rows]).reshape(len(rows), inputs),
        strengths=np.array([r[3] for r in rows]).reshape(len(rows), rules),
        action=np.array([r[4] for r in rows], dtype=np.int64),
        direction=values[:, layout.direction] if len(rows) else np.zeros(0),
        power=values[:, layout.power] if len(rows) else np.zeros(0),
        goals=np.array([r[6] for r in rows], dtype=np.int64),
        vocabulary=vocabulary,
    )
