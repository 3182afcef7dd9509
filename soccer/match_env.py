"""`MatchEnv`: one match, tick by tick, for the UI (soccer/env.py's SoccerEnv, for two players). Each half
is a MatchBatch of one half, played through the same kernel as `play_matches` (a half alone plays as in a
batch with others), so what the UI shows is the match the table counts, bit for bit. No rendering here.

Player A is on the left in the first half and on the right in the second (soccer/match.py); positions
and facings are given in the pitch's frame (the left player's: x toward the goal it attacks), what each
player perceived and decided in its own frame, as its rules saw it.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numba
import numpy as np

from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig, WorldConstants
from soccer_lab.soccer.engine import NO_OUTCOME, Observation, VocabularyLayout, body_vectors, plain
from soccer_lab.soccer.env import TRAIL_LENGTH
from soccer_lab.soccer.match import (HALVES, HalfResult, HalfState, MatchBatch, MatchPitches, MatchResult,
                                     OpponentLayout, PlayerState, perceive_side)
from soccer_lab.soccer.outcome import Outcome

A, B = 0, 1  # the players, as MatchResult counts them


@dataclass(frozen=True)
class PlayerMind:
    """What one player perceived for its latest decision (at a kick-off: the one about to be made) and what
    it decided, in its own frame."""

    visible: dict[str, bool]  # object -> in view
    inputs: dict[str, float | None]  # input -> crisp value (None: out of view)
    strengths: tuple[float, ...]  # every rule's strength at the last decision (0 before the first)
    action: str | None  # the selected action (None: no rule fired, the player hunted)
    outcome: Outcome | None  # what the decision's skill did and why (None before the first decision)


@dataclass(frozen=True)
class MatchState:
    """The match at one tick. `players`, `facings` and `minds` are (A's, B's); `goals` and `kicks` are the
    match's so far (both halves). Positions in metres, facings in degrees, in the pitch's frame."""

    half: int  # 1 or 2
    tick: int  # ticks played in this half
    a_on_left: bool  # A attacks +x (the first half) or -x (the second)
    players: tuple[tuple[float, float], tuple[float, float]]
    facings: tuple[float, float]
    ball: tuple[float, float]
    ball_trail: tuple[tuple[float, float], ...]  # this half's, oldest first, ending with the ball's position
    minds: tuple[PlayerMind, PlayerMind]
    goals: tuple[int, int]
    kicks: tuple[int, int]
    half_over: bool  # this half has ended (the next step kicks off the second half, or the match is over)
    end_reason: str  # why this half ended ("running" while it plays)
    done: bool  # both halves played
    result: MatchResult | None  # once done: what play_matches gives for this seed


@numba.njit(cache=True)
def observe_kernel(pitches, halves, players, observation, layout, opponent, constants):
    """Perception alone, for both players of every live half: a half's first observation, the very one its first
    tick perceives again (soccer/engine.py's observe_kernel, for a match). The named tuples arrive as plain ones."""
    pitches, halves, players = MatchPitches(*pitches), HalfState(*halves), PlayerState(*players)
    observation, layout = Observation(*observation), VocabularyLayout(*layout)
    opponent, constants = OpponentLayout(*opponent), WorldConstants(*constants)
    for h in range(halves.done.shape[0]):
        if halves.done[h]:
            continue
        ox, oy = pitches.offsets[h, 0], pitches.offsets[h, 1]
        left, right = body_vectors(pitches.players[h, 0]), body_vectors(pitches.players[h, 1])
        ball = body_vectors(pitches.ball[h])
        lx, ly, rx, ry, bx, by = left[0] - ox, left[1] - oy, right[0] - ox, right[1] - oy, ball[0] - ox, ball[1] - oy
        perceive_side(2 * h, 1.0, (lx, ly), (rx, ry), (bx, by), players, observation, layout, opponent, constants)
        perceive_side(2 * h + 1, -1.0, (rx, ry), (lx, ly), (bx, by), players, observation, layout, opponent,
                      constants)


class MatchEnv:
    """reset(seed) -> state at the first half's kick-off; step() -> state plays one tick (the step after
    the first half's end kicks off the second half, sides swapped)."""

    def __init__(self, a: Rulebase, b: Rulebase, config: GameConfig = GameConfig(),
                 vocabulary: Vocabulary = SOCCER_VOCABULARY):
        self.rulebases = (a, b)
        self.config = config
        self.vocabulary = vocabulary
        self.seed = 0
        self._half = 1  # the half on the pitch
        self._played: list[HalfResult] = []  # the halves played out
        self._batch: MatchBatch | None = None
        self._trail: deque[tuple[float, float]] = deque(maxlen=TRAIL_LENGTH)
        self._trail_tick: int | None = None
        self._bodies: tuple[tuple[float, float], ...] = ()  # left, right, ball: the last seen in the space

    def reset(self, seed: int) -> MatchState:
        self.seed = int(seed)
        self._played = []
        self._kick_off(1)
        return self.state

    def _kick_off(self, half: int) -> None:
        """Half `half` from the match's start: A on the left in the first, on the right in the second."""
        a, b = self.rulebases
        self._half = half
        batch = MatchBatch([(a, b) if half == 1 else (b, a)], [self.seed], self.config, self.vocabulary)
        observe_kernel(*(plain(part) for part in (batch.world.match_pitches, batch.state, batch.players,
                                                  batch.observation, batch.layout, batch.opponent)),
                       batch.constants)
        self._batch = batch
        self._trail.clear()
        self._trail_tick = None
        self._bodies = ()

    def step(self) -> MatchState:
        """One tick; at the first half's end (shown for one step) the second half's kick-off; once done, nothing."""
        batch = self._batch
        if batch is None:
            raise RuntimeError("call reset(seed) before step()")
        if not batch.finished:
            self._positions()  # the bodies leave the space with the half's last step: keep where they were
            batch.step()
            if batch.finished:
                self._played.append(batch.result(0))
        elif self._half < HALVES:
            self._kick_off(self._half + 1)
        return self.state

    @property
    def done(self) -> bool:
        return len(self._played) == HALVES

    @property
    def state(self) -> MatchState:
        batch = self._batch
        if batch is None:
            raise RuntimeError("call reset(seed) first")
        a_side, b_side = (0, 1) if self._half == 1 else (1, 0)
        left, right, ball = self._positions()
        tick = int(batch.state.ticks[0])
        if tick != self._trail_tick:  # once a tick: the trail is the half's last TRAIL_LENGTH ticks' path
            self._trail.append(ball)
            self._trail_tick = tick
        bodies = (left, right)
        # the right player's facing is kept in its own frame, the pitch turned half a turn
        facings = tuple(float(batch.players.facing[side]) + 180.0 * side for side in (a_side, b_side))
        halves = self._played + ([] if batch.finished else [batch.result(0)])
        return MatchState(
            half=self._half, tick=tick, a_on_left=self._half == 1,
            players=(bodies[a_side], bodies[b_side]), facings=facings, ball=ball, ball_trail=tuple(self._trail),
            minds=(self._mind(a_side, self.rulebases[A]), self._mind(b_side, self.rulebases[B])),
            goals=_totals(halves, "goals"), kicks=_totals(halves, "kicks"),
            half_over=batch.finished, end_reason=batch.result(0).end_reason, done=self.done,
            result=MatchResult(self.seed, tuple(self._played)) if self.done else None)

    def _positions(self) -> tuple[tuple[float, float], ...]:
        """The left player's, the right player's and the ball's, in the pitch frame (the last seen in the space
        once the half has left it)."""
        world = self._batch.world
        if world.pitches.player[0] != 0:
            ox, oy = world.pitches.offsets[0]
            left, _, ball, _, right, _ = world.objects(0)
            self._bodies = tuple((float(body.position.x - ox), float(body.position.y - oy))
                                 for body in (left, right, ball))
        return self._bodies

    def _mind(self, side: int, rulebase: Rulebase) -> PlayerMind:
        batch, vocabulary = self._batch, self.vocabulary
        seen, decided = batch.observation, batch.decision
        action_index = int(decided.action[side])
        action = vocabulary.action_names[action_index] if action_index != NO_ACTION else None
        return PlayerMind(
            visible={o: bool(seen.visible[side, i]) for i, o in enumerate(vocabulary.object_names)},
            inputs={n: None if np.isnan(v) else float(v) for n, v in zip(vocabulary.input_names, seen.inputs[side])},
            strengths=tuple(float(s) for s in decided.strengths[side, : len(rulebase)]),
            action=action,
            outcome=None if decided.outcome[side] == NO_OUTCOME else Outcome(
                action, int(decided.command[side]), float(decided.command_value[side]),
                float(decided.command_direction[side]), int(decided.outcome[side])),
        )


def _totals(halves: list[HalfResult], field: str) -> tuple[int, int]:
    """(A's, B's) of `field` over the halves in order (A on the left in the first, the right in the second)."""
    return (sum(getattr(h, field)[i % 2] for i, h in enumerate(halves)),
            sum(getattr(h, field)[1 - i % 2] for i, h in enumerate(halves)))
