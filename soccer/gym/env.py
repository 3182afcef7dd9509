"""`SimpleSoccerEnv`: one SimpleSoccer game as a Gymnasium environment, "soccer_lab/SimpleSoccer-v0".

The game is a batch of one of the engine evolution plays (soccer/engine.py), driven by `GameBatch.act`:
each step is one 100 ms tick with the agent's action in place of the fuzzy controller's decision, so a
rulebase acting through `FuzzyPolicy` plays exactly the game `play_game(rulebase, seed)` plays.
Spaces: soccer/gym/spaces.py. Rewards: `REWARDS`. An episode ends as the game does: the goal cap and
the idle limit end it (terminated: the task's own rules), the time limit cuts it (truncated).
`reset(seed=s)` starts the game `soccer-lab play --seed s` plays first; a reset without a seed draws
the game's seed from the environment's own generator (seeded by the last seeded reset).
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.engine import END_REASONS, MAX_TICKS, GameBatch
from soccer_lab.soccer.gym.render import PitchPicture
from soccer_lab.soccer.gym.spaces import SoccerSpaces

# "goals": +1 for each goal the step scored (the chapter's fitness is decided by goals first).
# "fitness": 0 until the last step, then 1 - the game's fitness (GameConfig.fitness, the chapter's
# Equations 1-3, lower is better, 1.0 = the ball never kicked): an agent maximising it minimises the
# very number evolution minimises.
REWARDS = ("goals", "fitness")
GAME_SEED_BOUND = 2**63  # an unseeded reset's game seed is drawn below this
NO_CONTROLLER = Rulebase(())  # the batch's own controllers are never asked: the agent acts


def end_flags(end_reasons: np.ndarray, done: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(terminated, truncated) of games by their engine end reasons: the time limit truncates, the goal
    cap and the idle limit terminate."""
    truncated = done & (end_reasons == MAX_TICKS)
    return done & ~truncated, truncated


class SimpleSoccerEnv(gymnasium.Env):
    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, config: GameConfig = GameConfig(), vocabulary: Vocabulary = SOCCER_VOCABULARY,
                 render_mode: str | None = None, reward: str = "goals"):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        if reward not in REWARDS:
            raise ValueError(f"reward must be one of {', '.join(REWARDS)}, got {reward!r}")
        self.config, self.vocabulary, self.render_mode, self.reward = config, vocabulary, render_mode, reward
        self.spaces = SoccerSpaces.of(vocabulary, config.world)
        self.observation_space, self.action_space = self.spaces.observation, self.spaces.action
        self.batch: GameBatch | None = None
        self.game_seed: int | None = None
        self._picture = PitchPicture(config.world) if render_mode else None

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self.game_seed = int(seed) if seed is not None else int(self.np_random.integers(GAME_SEED_BOUND))
        self.batch = GameBatch([NO_CONTROLLER], [self.game_seed], self.config, self.vocabulary)
        return self._observation(), self._info()

    def step(self, action):
        batch = self.batch
        if batch is None or batch.finished:
            raise RuntimeError("the game is over (or never began): call reset() first")
        goals = int(batch.state.goals[0])
        batch.act(*self.spaces.engine_actions(action, 1))
        done = batch.finished
        reward = float(batch.state.goals[0] - goals) if self.reward == "goals" else \
            (1.0 - batch.result(0).fitness if done else 0.0)
        terminated, truncated = end_flags(batch.state.end_reason, batch.state.done)
        return self._observation(), reward, bool(terminated[0]), bool(truncated[0]), self._info()

    def render(self):
        if self._picture is None or self.batch is None:
            return None
        seen = self.batch.observation
        return self._picture.draw((seen.player_x[0], seen.player_y[0]), float(self.batch.state.facing[0]),
                                  (seen.ball_x[0], seen.ball_y[0]))

    def _observation(self) -> dict[str, np.ndarray]:
        seen = self.batch.observation
        observation = self.spaces.observations(seen.inputs[:1], seen.visible[:1])
        return {name: value[0] for name, value in observation.items()}

    def _info(self) -> dict[str, Any]:
        """The game as the referee sees it (not what the player perceives): where player and ball are
        (the observation's moment: after the step, or where the game ended), its counts and end."""
        batch, seen = self.batch, self.batch.observation
        info = {"seed": self.game_seed, "tick": int(batch.state.ticks[0]), "goals": int(batch.state.goals[0]),
                "kicks": int(batch.state.kicks[0]), "player": (float(seen.player_x[0]), float(seen.player_y[0])),
                "facing": float(batch.state.facing[0]), "ball": (float(seen.ball_x[0]), float(seen.ball_y[0])),
                "end_reason": END_REASONS[batch.state.end_reason[0]]}
        if batch.finished:
            info["result"] = batch.result(0)
        return info
