"""Matches (docs/research/matches.md): two players and one ball on one pitch, each attacking the other's goal, batched
in one pymunk Space as games are (soccer/engine.py, whose steps this reuses; docs/research/matches.md).

Sides follow rcssserver: the left player attacks +x, the right player -x. Each player lives in its own
frame: the right player's is the pitch turned half a turn ((x, y) -> (-x, -y), velocities likewise),
as rcssserver shows the right team the field, so perception, skills and body commands are the
single-player ones and a rulebase plays the same from either side. A match is two halves from one
start (player A on the left in the first half, player B in the second; the start itself, drawn from
the match's seed, is the same in both), so neither player has the better half.

Per tick, for each live half: close the step just made (the ball against each player, then the two
players against each other, all resolved as rcssserver does, as the single-player engine resolves
player and ball; goals at both ends; idleness), then each player perceives, decides and acts in its
own frame (left first), the two kicks' accelerations are summed as rcssserver sums them, noise, and
the velocities are written back for pymunk's step. A half ends at max ticks, when either player
reaches the goal cap, or when both players have been idle for the idle limit at once (one player
idling while the other plays on is part of the match).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Sequence

import numba
import numpy as np

from soccer_lab.fuzzy.batched import NO_ACTION, CompiledRulebases, Scratch, VocabularyTables, compile_rulebases
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary, VocabularyError
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig, WorldConfig, WorldConstants
from soccer_lab.soccer.engine import (END_REASONS, GOAL_CAP, IDLE, MAX_TICKS, NO_OUTCOME, RUNNING, Decision,
                                      GameResult, GameRules, Observation, VocabularyLayout, act_step, body_vectors,
                                      borrowed, decide_step, perceive_step, plain)
from soccer_lab.soccer.evaluate import CHUNK_GAMES, game_seeds
from soccer_lab.soccer.fitness import WORST_FITNESS, goals_fitness
from soccer_lab.soccer.perception import DIRECTION, DISTANCE, in_view, relative_position
from soccer_lab.soccer.physics import cap_speed, dash, decay, kick_acceleration, part, separate, turn
from soccer_lab.soccer.random_stream import seed_states, uniform
from soccer_lab.soccer.skills import DASH, KICK, LEFT, TURN
from soccer_lab.soccer.world import PitchOutline, World, vectors_address

OPPONENT = "OPPONENT"  # the object an opponent-seeing vocabulary names (fuzzy/data/opponent_vocabulary.json)
HALVES = 2
# "Kiddie soccer" (both players chasing the ball): a tick counts as crowded when both players are within this
# many metres of the ball (the vocabulary's Near peaks at 4 m and ends at 8 m)
CROWD_DISTANCE = 5.0


class OpponentLayout(NamedTuple):
    """Where the opponent sits in a vocabulary: its distance and direction inputs and its object;
    -1 in a vocabulary without it (the chapter's: the player does not see its opponent)."""

    distance: int
    direction: int
    object: int

    @classmethod
    def from_vocabulary(cls, vocabulary: Vocabulary) -> "OpponentLayout":
        kinds = vocabulary.objects.get(OPPONENT)
        if kinds is None:
            return cls(-1, -1, -1)
        if not {DISTANCE, DIRECTION} <= set(kinds):
            raise VocabularyError(f"the {OPPONENT} object is perceived as a {DISTANCE} and a {DIRECTION}")
        inputs = vocabulary.input_names
        return cls(inputs.index(kinds[DISTANCE]), inputs.index(kinds[DIRECTION]),
                   vocabulary.object_names.index(OPPONENT))


class MatchPitches(NamedTuple):
    """Where each half h is, as the kernel reads it (soccer/world.py's Pitches, with two players)."""

    players: np.ndarray  # uint64[n, 2]: the addresses of the left and right player's (x, y, vx, vy)
    ball: np.ndarray  # uint64[n]
    offsets: np.ndarray  # float64[n, 2]


class HalfState(NamedTuple):
    """Each half's own bookkeeping, one row per half h; positions in the pitch's frame (the left's)."""

    done: np.ndarray  # bool[n]
    ticks: np.ndarray  # int64[n]
    end_reason: np.ndarray  # int64[n]: index into END_REASONS
    last_players: np.ndarray  # float64[n, 4]: left x, y, right x, y when they last decided
    last_ball: np.ndarray  # float64[n, 2]
    streams: np.ndarray  # uint64[n]: the half's splitmix64 stream (its match's seed)
    crowded: np.ndarray  # int64[n]: ticks both players were within CROWD_DISTANCE of the ball


class PlayerState(NamedTuple):
    """Each player's bookkeeping, row p = 2 h + side (0 left, 1 right); angles in its own frame."""

    facing: np.ndarray  # float64[2n], degrees
    last_side: np.ndarray  # int64[2n]: where the player last saw the ball (the hunt turns there)
    goals: np.ndarray  # int64[2n]
    kicks: np.ndarray  # int64[2n]
    idle: np.ndarray  # int64[2n]
    kicked: np.ndarray  # bool[2n]
    min_distance: np.ndarray  # float64[2n]: closest approach of the ball to the goal it attacks


@dataclass(frozen=True)
class HalfResult:
    """One half: each side's goals, kicks and closest approach of the ball to the goal it attacks
    (left, right), the ticks played and why it ended."""

    goals: tuple[int, int]
    kicks: tuple[int, int]
    min_ball_goal_distance: tuple[float, float]
    ticks: int
    end_reason: str
    crowded: int = 0  # ticks both players were within CROWD_DISTANCE of the ball

    @property
    def crowd_share(self) -> float:
        """The share of the half's ticks both players were near the ball (0 for a half of no tick)."""
        return self.crowded / self.ticks if self.ticks else 0.0


# ---- kernel ----------------------------------------------------------------------------------


@numba.njit(cache=True)
def match_starts(states, constants):
    """The start of a match, in each player's own frame: each player uniform in its own half (as a
    game's), the ball at rest on the centre line; (first player, second player, ball y)."""
    n = states.shape[0]
    first, second, ball_y = np.empty((n, 2)), np.empty((n, 2)), np.empty(n)
    for h in range(n):
        for start in (first, second):
            start[h, 0] = uniform(states, h, -constants.half_length, 0.0)
            start[h, 1] = uniform(states, h, -constants.half_width, constants.half_width)
        ball_y[h] = uniform(states, h, -constants.half_width, constants.half_width)
    return first, second, ball_y


@numba.njit(cache=True, inline="always")
def scored(last_x, last_y, x, y, c):
    """Whether the ball, moving from (last_x, last_y) to (x, y) in a player's own frame, entered the
    goal that player attacks (the engine's close step's test)."""
    if last_x <= c.half_length < x:
        t = (c.half_length - last_x) / (x - last_x)
        return abs(last_y + t * (y - last_y)) < c.goal_half_width
    return False


@numba.njit(cache=True, inline="always")
def rebound(body, factor):
    body[2] *= factor
    body[3] *= factor


@numba.njit(cache=True, inline="always")
def _near(x, y, bx, by):
    return (x - bx) * (x - bx) + (y - by) * (y - by) <= CROWD_DISTANCE * CROWD_DISTANCE


@numba.njit(cache=True, inline="always")
def close_half(h, positions, bodies, offset, halves, players, constants, rules):
    """The books of the step just made (the engine's close step for two players): collisions, goals at
    both ends and the restart, closest approaches, idleness, the end. Returns the positions after the
    collisions and restart (pitch frame), and whether the half ended now."""
    c = constants
    left, right, ball = bodies
    ox, oy = offset
    facing, goals, kicks, idle, kicked = players.facing, players.goals, players.kicks, players.idle, players.kicked
    min_distance = players.min_distance
    last_players, last_ball, streams = halves.last_players, halves.last_ball, halves.streams
    lx, ly, rx, ry, bx, by = positions
    lx, ly, bx, by, left_touch = separate(lx, ly, bx, by, facing[2 * h], c)
    rx, ry, bx, by, right_touch = separate(rx, ry, bx, by, facing[2 * h + 1] + 180.0, c)  # its facing, pitch frame
    lx, ly, rx, ry, bumped = part(lx, ly, rx, ry, 2.0 * c.player_size, facing[2 * h])
    if left_touch or right_touch or bumped:
        for body, x, y in ((left, lx, ly), (right, rx, ry), (ball, bx, by)):
            body[0] = ox + x
            body[1] = oy + y
        if left_touch or bumped:
            rebound(left, c.collision_rebound)
        if right_touch or bumped:
            rebound(right, c.collision_rebound)
        if left_touch or right_touch:
            rebound(ball, c.collision_rebound)
        if rules.count_touches:
            kicks[2 * h] += left_touch
            kicks[2 * h + 1] += right_touch
    lbx, lby = last_ball[h, 0], last_ball[h, 1]
    scorer = -1
    if scored(lbx, lby, bx, by, c):
        scorer = 2 * h
    elif scored(-lbx, -lby, -bx, -by, c):
        scorer = 2 * h + 1
    for side in range(2):
        p, s = 2 * h + side, 1.0 - 2.0 * side
        dxg, dyg = s * bx - c.half_length, s * by
        min_distance[p] = min(min_distance[p], math.sqrt(dxg * dxg + dyg * dyg))
        x, y = (lx, ly) if side == 0 else (rx, ry)
        dx, dy = x - last_players[h, 2 * side], y - last_players[h, 2 * side + 1]
        idle[p] = 0 if kicked[p] or math.sqrt(dx * dx + dy * dy) > rules.idle_distance else idle[p] + 1
    if _near(lx, ly, bx, by) and _near(rx, ry, bx, by):
        halves.crowded[h] += 1
    if scorer >= 0:
        goals[scorer] += 1
        bx = 0.0
        by = uniform(streams, h, -c.half_width, c.half_width)
        ball[0] = ox + bx
        ball[1] = oy + by
        ball[2] = 0.0
        ball[3] = 0.0
    reason = RUNNING
    if max(goals[2 * h], goals[2 * h + 1]) >= rules.goal_cap:
        reason = GOAL_CAP
    elif halves.ticks[h] >= rules.max_ticks:
        reason = MAX_TICKS
    elif min(idle[2 * h], idle[2 * h + 1]) >= rules.idle_ticks:
        reason = IDLE
    if reason != RUNNING:
        halves.end_reason[h] = reason
        halves.done[h] = True
        for body in (left, right, ball):
            body[2] = 0.0
            body[3] = 0.0
    return (lx, ly, rx, ry, bx, by), reason != RUNNING


@numba.njit(cache=True, inline="always")
def perceive_side(p, s, own, other, ball, players, observation, layout, opponent, constants):
    """What player p (sign s: 1 left, -1 right) perceives in its own frame, into observation[p]: the
    engine's perception, and the opponent when the vocabulary has it. Returns perception's tuple."""
    px, py, bx, by = s * own[0], s * own[1], s * ball[0], s * ball[1]
    perceived = perceive_step(p, px, py, bx, by, players, observation, layout, constants)
    if opponent.object >= 0:
        inputs, visible, facing = observation.inputs, observation.visible, players.facing
        distance, direction = relative_position(px, py, facing[p], s * other[0], s * other[1])
        seen = in_view(direction, constants.view_half_angle)
        inputs[p, opponent.distance] = distance if seen else np.nan
        inputs[p, opponent.direction] = direction if seen else np.nan
        visible[p, opponent.object] = seen
    return perceived


@numba.njit(cache=True, inline="always")
def command_side(p, s, command, perceived, velocity, players, streams, h, constants, rules):
    """Player p's body command applied in its own frame: its facing, its new (decayed) velocity and the
    acceleration its kick gives the ball, both back in the pitch frame."""
    c = constants
    facing, kicks, kicked = players.facing, players.kicks, players.kicked
    kind, value, direction, kickable = command
    vx, vy = s * velocity[0], s * velocity[1]
    kicked[p] = False
    ax, ay = 0.0, 0.0
    if kind == TURN:
        if rules.noise:
            value *= 1.0 + uniform(streams, h, -c.player_rand, c.player_rand)
        facing[p] = turn(facing[p], value, math.sqrt(vx * vx + vy * vy), c)
    elif kind == DASH:
        vx, vy = dash(vx, vy, facing[p], value, c)
    elif kind == KICK and kickable:
        ax, ay = kick_acceleration(value, direction, facing[p], perceived[0], perceived[1], c)
        kicks[p] += 1
        kicked[p] = True
    return s * vx, s * vy, s * ax, s * ay


@numba.njit(cache=True, inline="always")
def noisy(streams, h, vx, vy, rand, speed_max):
    """rcssserver's velocity noise (the engine's), then the speed cap."""
    spread = rand * math.sqrt(vx * vx + vy * vy)
    return cap_speed(vx + uniform(streams, h, -spread, spread), vy + uniform(streams, h, -spread, spread), speed_max)


@numba.njit(cache=True)
def match_kernel(pitches, halves, players, observation, decision, rulebases, scratch, layout, opponent, constants,
                 rules):
    """One tick of every live half; returns how many halves finished now. The named tuples arrive as
    plain ones and are named again as borrowed views (soccer/engine.py, `plain` and `borrowed`)."""
    pitches, halves, players, observation = borrowed(pitches), borrowed(halves), borrowed(players), \
        borrowed(observation)
    decision, rulebases, scratch, layout = borrowed(decision), borrowed(rulebases), borrowed(scratch), borrowed(layout)
    pitches, halves, players = MatchPitches(*pitches), HalfState(*halves), PlayerState(*players)
    observation, decision = Observation(*observation), Decision(*decision)
    rulebases = CompiledRulebases(*(rulebases[:-1] + (VocabularyTables(*rulebases[-1]),)))
    scratch, layout, opponent = Scratch(*scratch), VocabularyLayout(*layout), OpponentLayout(*opponent)
    constants, rules = WorldConstants(*constants), GameRules(*rules)
    c = constants
    dt = c.tick_seconds
    done, ticks, streams = halves.done, halves.ticks, halves.streams
    last_players, last_ball = halves.last_players, halves.last_ball
    players_at, ball_at, offsets = pitches.players, pitches.ball, pitches.offsets
    moves = np.empty((2, 4))  # per side: its velocity and the ball's acceleration from its kick, pitch frame
    finished = 0
    for h in range(done.shape[0]):
        if done[h]:
            continue
        left, right, ball = body_vectors(players_at[h, 0]), body_vectors(players_at[h, 1]), body_vectors(ball_at[h])
        ox, oy = offsets[h, 0], offsets[h, 1]
        positions = (left[0] - ox, left[1] - oy, right[0] - ox, right[1] - oy, ball[0] - ox, ball[1] - oy)
        if ticks[h] > 0:
            positions, ended = close_half(h, positions, (left, right, ball), (ox, oy), halves, players, c, rules)
            if ended:
                finished += 1
                continue
        lx, ly, rx, ry, bx, by = positions
        # velocities decay first (rcssserver does it at the end of the previous cycle)
        left_v = decay(left[2] * dt, left[3] * dt, c.player_decay)
        right_v = decay(right[2] * dt, right[3] * dt, c.player_decay)
        bvx, bvy = decay(ball[2] * dt, ball[3] * dt, c.ball_decay)
        for side in range(2):
            p, s = 2 * h + side, 1.0 - 2.0 * side
            own, other, velocity = ((lx, ly), (rx, ry), left_v) if side == 0 else ((rx, ry), (lx, ly), right_v)
            perceived = perceive_side(p, s, own, other, (bx, by), players, observation, layout, opponent, c)
            action = decide_step(p, observation, decision, rulebases, scratch)
            speed = math.sqrt(velocity[0] * velocity[0] + velocity[1] * velocity[1])
            command = act_step(p, action, perceived, speed, players, decision, layout, c, rules)
            moves[side, 0], moves[side, 1], moves[side, 2], moves[side, 3] = command_side(
                p, s, command, perceived, velocity, players, streams, h, c, rules)
        # both kicks push the ball together (rcssserver sums the accelerations, then caps them)
        ax, ay = cap_speed(moves[0, 2] + moves[1, 2], moves[0, 3] + moves[1, 3], c.ball_accel_max)
        bvx, bvy = cap_speed(bvx + ax, bvy + ay, c.ball_speed_max)
        for side, body in ((0, left), (1, right)):
            vx, vy = moves[side, 0], moves[side, 1]
            if rules.noise:
                vx, vy = noisy(streams, h, vx, vy, c.player_rand, c.player_speed_max)
            body[2] = vx / dt
            body[3] = vy / dt
        if rules.noise:
            bvx, bvy = noisy(streams, h, bvx, bvy, c.ball_rand, c.ball_speed_max)
        ball[2] = bvx / dt
        ball[3] = bvy / dt
        last_players[h, 0], last_players[h, 1], last_players[h, 2], last_players[h, 3] = lx, ly, rx, ry
        last_ball[h, 0], last_ball[h, 1] = bx, by
        ticks[h] += 1
    return finished


# ---- the batch --------------------------------------------------------------------------------


class MatchWorld(World):
    """The shared space(s) of matches: each half on a pitch with a goal at both ends (PitchOutline.of_match),
    at its seed's slot, with a second player; `match_pitches` is where the kernel finds the bodies."""

    def __init__(self, config: WorldConfig, seeds: Sequence[int]):
        super().__init__(config, seeds, PitchOutline.of_match(config))
        self.match_pitches = MatchPitches(np.zeros((len(seeds), 2), dtype=np.uint64), self.pitches.ball,
                                          self.pitches.offsets)

    def add_half(self, half: int, left_xy: tuple[float, float], right_xy: tuple[float, float],
                 ball_xy: tuple[float, float]) -> None:
        self.add_game(half, left_xy, ball_xy)
        ox, oy = self.pitches.offsets[half]
        layer = self.pitches.layer[half]
        body, shape = self._pitch_spaces[layer].take_body(self._player_kind, ox + right_xy[0], oy + right_xy[1])
        self.spaces[layer].add(body, shape)
        self._objects[half] += (body, shape)
        self.match_pitches.players[half] = (self.pitches.player[half], vectors_address(body))

    def remove_game(self, game: int) -> None:
        if self._pitch[game] is None:
            return
        layer = self.pitches.layer[game]
        body, shape = self._objects[game][4:]
        self.spaces[layer].remove(body, shape)
        self._pitch_spaces[layer].give_back_body(self._player_kind, body, shape)
        self._objects[game] = self._objects[game][:4]
        self.match_pitches.players[game] = 0
        super().remove_game(game)


class MatchBatch:
    """Halves of matches played together, tick by tick: half h has its left and right player's rulebases
    and its match's seed (soccer/engine.py's GameBatch, for two players a pitch). Players' rows (p = 2 h +
    side) index `players`, `observation` (in each player's own frame) and `decision`."""

    def __init__(self, pairs: Sequence[tuple[Rulebase, Rulebase]], seeds: Sequence[int], config: GameConfig,
                 vocabulary: Vocabulary):
        if len(pairs) != len(seeds):
            raise ValueError(f"{len(pairs)} pairs of rulebases but {len(seeds)} seeds: need one seed per half")
        n = len(pairs)
        self.config, self.vocabulary, self.halves = config, vocabulary, n
        self.constants: WorldConstants = config.world.constants()
        self.rules = GameRules.from_config(config)
        self.layout = VocabularyLayout.from_vocabulary(vocabulary)
        self.opponent = OpponentLayout.from_vocabulary(vocabulary)
        streams = seed_states(seeds)
        first, second, ball_y = match_starts(streams, self.constants)
        self.world = MatchWorld(config.world, seeds)
        left, right = first, -second  # the right player's own frame is the pitch turned half a turn
        for h in range(n):
            self.world.add_half(h, tuple(left[h]), tuple(right[h]), (0.0, float(ball_y[h])))
        self.state = HalfState(
            done=np.zeros(n, dtype=np.bool_), ticks=np.zeros(n, dtype=np.int64), end_reason=np.zeros(n, dtype=np.int64),
            last_players=np.concatenate([left, right], axis=1), last_ball=np.stack([np.zeros(n), ball_y], axis=1),
            streams=streams, crowded=np.zeros(n, dtype=np.int64))
        hl = self.constants.half_length
        self.players = PlayerState(
            facing=np.zeros(2 * n),  # every player starts facing the goal it attacks
            last_side=np.full(2 * n, LEFT, dtype=np.int64), goals=np.zeros(2 * n, dtype=np.int64),
            kicks=np.zeros(2 * n, dtype=np.int64), idle=np.zeros(2 * n, dtype=np.int64),
            kicked=np.zeros(2 * n, dtype=np.bool_), min_distance=np.repeat(np.hypot(hl, ball_y), 2))
        inputs, objects, outputs = (len(names) for names in (vocabulary.input_names, vocabulary.object_names,
                                                             vocabulary.output_names))
        self.observation = Observation(
            player_x=np.zeros(2 * n), player_y=np.zeros(2 * n), facing=np.zeros(2 * n), ball_x=np.zeros(2 * n),
            ball_y=np.zeros(2 * n), inputs=np.full((2 * n, inputs), np.nan),
            visible=np.zeros((2 * n, objects), dtype=np.bool_))
        self.compiled = compile_rulebases([rulebase for pair in pairs for rulebase in pair], vocabulary)
        self.decision = Decision(
            action=np.full(2 * n, NO_ACTION, dtype=np.int64), values=np.zeros((2 * n, outputs)),
            strengths=np.zeros((2 * n, max(self.compiled.max_rules, 1))), command=np.zeros(2 * n, dtype=np.int64),
            command_value=np.zeros(2 * n), command_direction=np.zeros(2 * n),
            outcome=np.full(2 * n, NO_OUTCOME, dtype=np.int64))
        self._arguments = tuple(plain(part_) for part_ in (
            self.world.match_pitches, self.state, self.players, self.observation, self.decision, self.compiled,
            Scratch.for_rulebases(self.compiled), self.layout, self.opponent, self.constants, self.rules))
        self._live = n

    @property
    def finished(self) -> bool:
        return self._live == 0

    def step(self) -> None:
        """One tick of every live half (a finished half's last call only closes its books)."""
        if self._live == 0:
            return
        finished = match_kernel(*self._arguments)
        if finished:
            self._live -= finished
            for h in np.flatnonzero(self.state.done & (self.world.pitches.player != 0)):
                self.world.remove_game(int(h))
        for layer in self.world.occupied_layers():
            self.world.spaces[layer].step(self.constants.tick_seconds)

    def run(self) -> list[HalfResult]:
        while self._live:
            self.step()
        return self.results()

    def result(self, h: int) -> HalfResult:
        p, s = self.players, self.state
        left, right = 2 * h, 2 * h + 1
        return HalfResult(goals=(int(p.goals[left]), int(p.goals[right])),
                          kicks=(int(p.kicks[left]), int(p.kicks[right])),
                          min_ball_goal_distance=(float(p.min_distance[left]), float(p.min_distance[right])),
                          ticks=int(s.ticks[h]), end_reason=END_REASONS[s.end_reason[h]],
                          crowded=int(s.crowded[h]))

    def results(self) -> list[HalfResult]:
        return [self.result(h) for h in range(self.halves)]


@dataclass(frozen=True)
class MatchResult:
    """A match between players A and B from one seed: A on the left in the first half, on the right in
    the second. `goals` are (A's, B's) over both halves."""

    seed: int
    halves: tuple[HalfResult, HalfResult]

    @property
    def goals(self) -> tuple[int, int]:
        first, second = self.halves
        return first.goals[0] + second.goals[1], first.goals[1] + second.goals[0]

    @property
    def winner(self) -> str:
        """"A", "B" or "draw"."""
        a, b = self.goals
        return "A" if a > b else "B" if b > a else "draw"


def play_matches(a: Rulebase, b: Rulebase, seeds: Sequence[int], config: GameConfig,
                 vocabulary: Vocabulary) -> list[MatchResult]:
    """One match of A against B per seed (both halves of all of them in one batch); results in seed order."""
    if not seeds:
        return []
    halves = MatchBatch([(a, b), (b, a)] * len(seeds), [s for s in seeds for _ in range(HALVES)], config,
                        vocabulary).run()
    return [MatchResult(seed, (halves[2 * i], halves[2 * i + 1])) for i, seed in enumerate(seeds)]


# ---- the fitness of a player over matches against a fixed opponent ------------------------------


def match_fitness(goal_difference: int, kicks: int, min_ball_goal_distance: float, field_length: float) -> float:
    """The chapter's simple composite (soccer/fitness.py) carried over to goal difference; lower is better.
    A win by d goals scores 1 / (2 d), as d goals scored alone do. Otherwise a player that kicked scores in
    [0.5, 1): a quarter of the ball's closest approach to the goal it attacks over the field length (the
    chapter's Equation 3 at half weight) plus a quarter of 1 - 1 / (1 - d) (0 for a draw, toward 1 for a
    heavy loss). A player that never kicked scores 1.0, the chapter's "no ball movement"."""
    if goal_difference > 0:
        return goals_fitness(goal_difference)
    if kicks == 0:
        return WORST_FITNESS
    margin = 1.0 - 1.0 / (1 - goal_difference)
    return 0.5 + (min(min_ball_goal_distance / field_length, 1.0) + margin) / 4.0


@dataclass(frozen=True)
class MatchEvaluator:
    """The GA's evaluator (soccer/evaluate.py's, for matches): each rulebase plays one match (two halves,
    the sides swapped) against the fixed `opponent` from its seed, k matches from seeds derived from it
    with games_per_evaluation = k, all in one batch. Its GameResult: `match_fitness` over its matches' goal
    difference, kicks and closest approach; goals and kicks its own (a mean over k); ticks the halves'
    total (mean); end_reason the first half's."""

    opponent: Rulebase
    config: GameConfig = GameConfig()
    vocabulary: Vocabulary = SOCCER_VOCABULARY

    @property
    def chunk_size(self) -> int:
        """Rulebases per chunk of a generation: as many halves as a chunk of games has games."""
        return max(1, CHUNK_GAMES // (HALVES * self.config.games_per_evaluation))

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[GameResult]:
        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds: need one seed per rulebase")
        k = self.config.games_per_evaluation
        pairs, match_seeds = [], []
        for rulebase, seed in zip(rulebases, seeds):
            for match_seed in game_seeds(int(seed), k):
                pairs += [(rulebase, self.opponent), (self.opponent, rulebase)]
                match_seeds += [match_seed] * HALVES
        halves = MatchBatch(pairs, match_seeds, self.config, self.vocabulary).run() if pairs else []
        per_player = HALVES * k
        return [self._result(halves[i * per_player:(i + 1) * per_player]) for i in range(len(rulebases))]

    def _result(self, halves: list[HalfResult]) -> GameResult:
        """The player's result over its halves (the player is on the left in even halves, right in odd)."""
        scored = sum(h.goals[i % 2] for i, h in enumerate(halves))
        conceded = sum(h.goals[1 - i % 2] for i, h in enumerate(halves))
        kicks = sum(h.kicks[i % 2] for i, h in enumerate(halves))
        distance = min(h.min_ball_goal_distance[i % 2] for i, h in enumerate(halves))
        k = len(halves) // HALVES
        return GameResult(fitness=match_fitness(scored - conceded, kicks, distance, self.config.world.pitch_length),
                          goals=scored / k if k > 1 else scored, kicks=kicks / k if k > 1 else kicks,
                          ticks=sum(h.ticks for h in halves) / k if k > 1 else sum(h.ticks for h in halves),
                          min_ball_goal_distance=distance, end_reason=halves[0].end_reason)


@dataclass(frozen=True)
class HallEvaluator:
    """The GA's evaluator against several opponents (co-evolution: the opponents drawn from a hall of fame,
    ga/hall_of_fame.py, set each generation with `against`): each rulebase plays one match against each
    opponent (k with games_per_evaluation = k), from seeds derived from its own, all in one batch. Its
    fitness is the mean over the opponents of `match_fitness` against each (so each opponent weighs the same:
    a big win against a weak one does not hide a loss against a strong one); goals and kicks its own, a mean
    per match; ticks a mean per match; the closest approach the minimum; end_reason the first half's."""

    opponents: tuple[Rulebase, ...] = ()
    config: GameConfig = GameConfig()
    vocabulary: Vocabulary = SOCCER_VOCABULARY

    def against(self, opponents: Sequence[Rulebase]) -> "HallEvaluator":
        return HallEvaluator(tuple(opponents), self.config, self.vocabulary)

    @property
    def chunk_size(self) -> int:
        """Rulebases per chunk of a generation: as many halves as a chunk of games has games."""
        matches = max(1, len(self.opponents)) * self.config.games_per_evaluation
        return max(1, CHUNK_GAMES // (HALVES * matches))

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int]) -> list[GameResult]:
        if len(rulebases) != len(seeds):
            raise ValueError(f"{len(rulebases)} rulebases but {len(seeds)} seeds: need one seed per rulebase")
        if not self.opponents:
            raise ValueError("a hall of fame evaluator needs at least one opponent (see `against`)")
        k = self.config.games_per_evaluation
        pairs, match_seeds = [], []
        for rulebase, seed in zip(rulebases, seeds):
            derived = game_seeds(int(seed), k * len(self.opponents))
            for j, opponent in enumerate(self.opponents):
                for match_seed in derived[j * k:(j + 1) * k]:
                    pairs += [(rulebase, opponent), (opponent, rulebase)]
                    match_seeds += [match_seed] * HALVES
        halves = MatchBatch(pairs, match_seeds, self.config, self.vocabulary).run() if pairs else []
        per_player = HALVES * k * len(self.opponents)
        return [self._result(halves[i * per_player:(i + 1) * per_player]) for i in range(len(rulebases))]

    def _result(self, halves: list[HalfResult]) -> GameResult:
        """The player's result over its halves, HALVES * k against each opponent in turn (the player on the
        left in even halves, on the right in odd ones)."""
        per_opponent = len(halves) // len(self.opponents)
        fitnesses = []
        for j in range(len(self.opponents)):
            mine = halves[j * per_opponent:(j + 1) * per_opponent]
            scored = sum(h.goals[i % 2] for i, h in enumerate(mine))
            conceded = sum(h.goals[1 - i % 2] for i, h in enumerate(mine))
            kicks = sum(h.kicks[i % 2] for i, h in enumerate(mine))
            distance = min(h.min_ball_goal_distance[i % 2] for i, h in enumerate(mine))
            fitnesses.append(match_fitness(scored - conceded, kicks, distance, self.config.world.pitch_length))
        matches = len(halves) // HALVES
        return GameResult(fitness=sum(fitnesses) / len(fitnesses),
                          goals=sum(h.goals[i % 2] for i, h in enumerate(halves)) / matches,
                          kicks=sum(h.kicks[i % 2] for i, h in enumerate(halves)) / matches,
                          ticks=sum(h.ticks for h in halves) / matches,
                          min_ball_goal_distance=min(h.min_ball_goal_distance[i % 2] for i, h in enumerate(halves)),
                          end_reason=halves[0].end_reason)


# ---- one half traced, for a recording's replay --------------------------------------------------------
@dataclass(frozen=True)
class MatchTrace:
    """One half tick by tick in the pitch's frame (the left player's), as each tick began: each player's
    position and facing (degrees), the ball, each side's goals so far."""

    left: np.ndarray  # float[T, 3]: x, y, facing
    right: np.ndarray  # float[T, 3]
    ball: np.ndarray  # float[T, 2]
    goals: np.ndarray  # int[T, 2]: left's, right's

    def __len__(self) -> int:
        return len(self.ball)


def traced_half(left: Rulebase, right: Rulebase, seed: int, config: GameConfig,
                vocabulary: Vocabulary) -> tuple[HalfResult, MatchTrace]:
    """The first half of the match from `seed` (`left` on the left), played alone (so as in any batch) and
    traced tick by tick."""
    batch = MatchBatch([(left, right)], [seed], config, vocabulary)
    rows = []
    while not batch.finished:
        left_body, _, ball_body, _, right_body, _ = batch.world.objects(0)
        ox, oy = batch.world.pitches.offsets[0]
        facing = batch.players.facing
        rows.append((left_body.position.x - ox, left_body.position.y - oy, facing[0],
                     right_body.position.x - ox, right_body.position.y - oy, (facing[1] + 180.0) % 360.0,
                     ball_body.position.x - ox, ball_body.position.y - oy, batch.players.goals[0],
                     batch.players.goals[1]))
        batch.step()
    table = np.array(rows, dtype=float).reshape(-1, 10)
    return batch.result(0), MatchTrace(table[:, 0:3], table[:, 3:6], table[:, 6:8], table[:, 8:10].astype(np.int64))
