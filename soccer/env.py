"""`SoccerEnv`: one game, Gymnasium-style, for the UI. It is a batch of one through the same engine as
evolution, so what the UI shows is exactly what the GA scored. No rendering here. The Gymnasium
environment proper, with an agent's actions, is soccer/gym/."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.engine import END_REASONS, NO_OUTCOME, GameBatch
from soccer_lab.soccer.outcome import Outcome

TRAIL_LENGTH = 60  # ticks of the ball's path kept for the trail (6 s): a shot long past fades away


@dataclass(frozen=True)
class SoccerState:
    tick: int
    player: tuple[float, float]
    facing: float  # degrees; 0 = +x (toward the goal), positive = turned to the right
    ball: tuple[float, float]
    ball_trail: tuple[tuple[float, float], ...]  # oldest first, ending with the ball's position
    # What the player perceived for its latest decision; after reset, for the first one, about to be made.
    visible: dict[str, bool]  # object -> in view
    inputs: dict[str, float | None]  # input -> crisp value (None: out of view)
    strengths: tuple[float, ...]  # every rule's strength at the last decision (0 before the first)
    action: str | None  # the last selected action (None: no rule fired, the player hunted)
    parameters: dict[str, float]  # the selected action's outputs it uses
    outcome: Outcome | None  # what the last decision's skill did and why (None before the first decision)
    idle: int  # consecutive ticks the player neither moved nor kicked (the game ends at config.idle_ticks)
    goals: int
    kicks: int
    done: bool
    end_reason: str
    fitness: float | None  # once done


class SoccerEnv:
    """reset(seed) -> state, with the first observation; step() -> state plays one tick with the
    player's own controller."""

    def __init__(self, rulebase: Rulebase, config: GameConfig = GameConfig(),
                 vocabulary: Vocabulary = SOCCER_VOCABULARY):
        self.config = config
        self.vocabulary = vocabulary
        self.rulebase = rulebase
        self._batch: GameBatch | None = None
        self._trail: deque[tuple[float, float]] = deque(maxlen=TRAIL_LENGTH)
        self._trail_tick: int | None = None  # the tick of the trail's newest point
        self._seed = 0

    def set_rulebase(self, rulebase: Rulebase) -> SoccerState:
        """Swap the controller; the running game goes on where it is."""
        self.rulebase = rulebase
        if self._batch is None:
            return self.reset(self._seed)
        self._batch.set_rulebases([rulebase])
        return self.state

    def reset(self, seed: int) -> SoccerState:
        self._seed = int(seed)
        self._batch = GameBatch([self.rulebase], [self._seed], self.config, self.vocabulary)
        self._trail.clear()
        self._trail_tick = None
        return self.state

    def step(self) -> SoccerState:
        if self._batch is None:
            raise RuntimeError("call reset(seed) before step()")
        self._batch.step()
        return self.state

    @property
    def state(self) -> SoccerState:
        batch = self._batch
        if batch is None:
            raise RuntimeError("call reset(seed) first")
        vocabulary, game, seen, decided = batch.vocabulary, batch.state, batch.observation, batch.decision
        player, ball = self._positions()
        tick = int(game.ticks[0])
        if tick != self._trail_tick:  # once a tick, resting or not: the trail is the last TRAIL_LENGTH ticks' path
            self._trail.append(ball)
            self._trail_tick = tick
        action_index = int(decided.action[0])
        action = vocabulary.action_names[action_index] if action_index != NO_ACTION else None
        uses = vocabulary.actions[action] if action else ()
        done = bool(game.done[0])
        return SoccerState(
            tick=tick,
            player=player,
            facing=float(game.facing[0]),
            ball=ball,
            ball_trail=tuple(self._trail),
            visible={o: bool(seen.visible[0, i]) for i, o in enumerate(vocabulary.object_names)},
            inputs={n: None if np.isnan(v) else float(v) for n, v in zip(vocabulary.input_names, seen.inputs[0])},
            strengths=tuple(float(s) for s in decided.strengths[0, : len(self.rulebase)]),
            action=action,
            parameters={o: float(decided.values[0, vocabulary.output_names.index(o)]) for o in uses},
            outcome=None if decided.outcome[0] == NO_OUTCOME else Outcome(
                action, int(decided.command[0]), float(decided.command_value[0]),
                float(decided.command_direction[0]), int(decided.outcome[0])),
            idle=int(game.idle[0]),
            goals=int(game.goals[0]),
            kicks=int(game.kicks[0]),
            done=done,
            end_reason=END_REASONS[game.end_reason[0]],
            fitness=batch.result(0).fitness if done else None,
        )

    def _positions(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """Current local positions (from pymunk, or the last known ones once the game left the space)."""
        batch = self._batch
        ox, oy = batch.world.pitches.offsets[0]
        if batch.world.pitches.player[0] == 0:
            seen = batch.observation
            return (float(seen.player_x[0]), float(seen.player_y[0])), (float(seen.ball_x[0]), float(seen.ball_y[0]))
        player, _, ball, _ = batch.world.objects(0)
        return ((player.position.x - ox, player.position.y - oy), (ball.position.x - ox, ball.position.y - oy))
