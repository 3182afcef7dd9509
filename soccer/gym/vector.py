"""`SimpleSoccerVectorEnv`: many SimpleSoccer games as one Gymnasium VectorEnv, all in one `GameBatch`
(one pymunk space for every sub-environment, one numba kernel call per tick for all of them, as
evolution plays), "soccer_lab/SimpleSoccer-v0" made with `gymnasium.make_vec(..., vectorization_mode=
"vector_entry_point")`.

Autoreset: Gymnasium's default, NEXT_STEP. The step that ends a sub-environment's game returns its last
observation with terminated or truncated set; the next step ignores that sub-environment's action,
starts its next game (from a seed drawn from the environment's generator) and returns that game's first
observation, reward 0. Each sub-environment's game is the one `play_game(rulebase, seed)` plays from
its seed (a game does not depend on its batch: soccer/world.py); `infos["seed"]` gives the seeds of the
games begun, `infos["result"]` each finished game's GameResult.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.engine import GameBatch
from soccer_lab.soccer.gym.env import GAME_SEED_BOUND, NO_CONTROLLER, REWARDS, end_flags
from soccer_lab.soccer.gym.render import PitchPicture
from soccer_lab.soccer.gym.spaces import SoccerSpaces


class SimpleSoccerVectorEnv(VectorEnv):
    metadata = {"render_modes": ["rgb_array"], "render_fps": 10, "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int, config: GameConfig = GameConfig(), vocabulary: Vocabulary = SOCCER_VOCABULARY,
                 render_mode: str | None = None, reward: str = "goals"):
        if num_envs < 1:
            raise ValueError(f"num_envs must be at least 1, got {num_envs}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        if reward not in REWARDS:
            raise ValueError(f"reward must be one of {', '.join(REWARDS)}, got {reward!r}")
        self.num_envs, self.config, self.vocabulary = num_envs, config, vocabulary
        self.render_mode, self.reward = render_mode, reward
        self.spaces = SoccerSpaces.of(vocabulary, config.world)
        self.single_observation_space, self.single_action_space = self.spaces.observation, self.spaces.action
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.batch: GameBatch | None = None
        self.game_seeds = np.zeros(num_envs, dtype=np.uint64)
        self._ended = np.zeros(num_envs, dtype=np.bool_)  # the last step ended these games: they restart next
        self._picture = PitchPicture(config.world) if render_mode else None

    def reset(self, *, seed: int | Sequence[int] | None = None, options: dict[str, Any] | None = None):
        """seed: an int s (sub-environment i plays the game of seed s + i, as `soccer-lab play --seed s
        --games n` numbers them), one seed per sub-environment, or None (drawn)."""
        # the generator for later games' seeds: seeded by the int, or the first of the list
        first = seed if seed is None or isinstance(seed, (int, np.integer)) else next(iter(seed), None)
        super().reset(seed=None if first is None else int(first))
        seeds = self._first_seeds(seed)
        self.batch = GameBatch([NO_CONTROLLER] * self.num_envs, seeds, self.config, self.vocabulary)
        self.game_seeds[:] = seeds
        self._ended[:] = False
        return self._observations(), {"seed": np.array(seeds, dtype=object),
                                      "_seed": np.ones(self.num_envs, dtype=np.bool_)}

    def _first_seeds(self, seed: int | Sequence[int] | None) -> list[int]:
        if seed is None:
            return [self._draw_seed() for _ in range(self.num_envs)]
        if isinstance(seed, (int, np.integer)):
            return [int(seed) + i for i in range(self.num_envs)]
        if len(seed) != self.num_envs:
            raise ValueError(f"{len(seed)} seeds for {self.num_envs} sub-environments")
        return [int(s) for s in seed]

    def _draw_seed(self) -> int:
        return int(self.np_random.integers(GAME_SEED_BOUND))

    def step(self, actions):
        batch = self.batch
        if batch is None:
            raise RuntimeError("call reset() first")
        state, restarting = batch.state, self._ended.copy()
        goals = state.goals.copy()
        batch.act(*self.spaces.engine_actions(actions, self.num_envs))
        ended = state.done & ~restarting
        terminated, truncated = end_flags(state.end_reason, ended)
        infos: dict[str, Any] = {}
        rewards = self._rewards(goals, ended, infos)
        if restarting.any():
            self._restart(np.flatnonzero(restarting), infos)
        self._ended = ended
        return self._observations(), rewards, terminated, truncated, infos

    def _rewards(self, goals_before: np.ndarray, ended: np.ndarray, infos: dict[str, Any]) -> np.ndarray:
        """This step's rewards (REWARDS); the results of the games it ended go into infos["result"]."""
        batch = self.batch
        rewards = (batch.state.goals - goals_before).astype(np.float64) if self.reward == "goals" \
            else np.zeros(self.num_envs)
        if ended.any():
            results = np.full(self.num_envs, None, dtype=object)
            for g in np.flatnonzero(ended):
                results[g] = batch.result(int(g))
                if self.reward == "fitness":
                    rewards[g] = 1.0 - results[g].fitness
            infos["result"], infos["_result"] = results, ended.copy()
        return rewards

    def _restart(self, games: np.ndarray, infos: dict[str, Any]) -> None:
        seeds = np.full(self.num_envs, None, dtype=object)
        for g in games:
            seeds[g] = self._draw_seed()
            self.batch.restart(int(g), seeds[g])
            self.game_seeds[g] = seeds[g]
        mask = np.zeros(self.num_envs, dtype=np.bool_)
        mask[games] = True
        infos["seed"], infos["_seed"] = seeds, mask

    def _observations(self) -> dict[str, np.ndarray]:
        seen = self.batch.observation
        return self.spaces.observations(seen.inputs, seen.visible)

    def render(self) -> tuple[np.ndarray, ...] | None:
        """One picture per sub-environment, as SyncVectorEnv gives them."""
        if self._picture is None or self.batch is None:
            return None
        seen, facing = self.batch.observation, self.batch.state.facing
        return tuple(self._picture.draw((seen.player_x[g], seen.player_y[g]), float(facing[g]),
                                        (seen.ball_x[g], seen.ball_y[g])) for g in range(self.num_envs))
