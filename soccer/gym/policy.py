"""`FuzzyPolicy`: the chapter's fuzzy controller as a policy over SimpleSoccerEnv's observations.

It decides with the very kernel the engine's tick calls (soccer_lab.fuzzy.batched), on the inputs perception gave
(the observation's unseen inputs are NaN again, as the engine holds them), so a rulebase acting through
the environment plays exactly the game `soccer-lab play` plays (tests/soccer/test_gym.py checks bit
for bit)."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from soccer_lab.fuzzy.batched import compile_rulebases, decide_batch
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, WorldConfig
from soccer_lab.soccer.gym.spaces import SoccerSpaces


class FuzzyPolicy:
    """policy(observation) -> action. Given one rulebase it decides for every observation with it; given
    a sequence, row i of a batch of observations (a vector environment's) is decided by rulebase i."""

    def __init__(self, rulebases: Rulebase | Sequence[Rulebase], vocabulary: Vocabulary = SOCCER_VOCABULARY,
                 world: WorldConfig = WorldConfig()):
        rulebases = [rulebases] if isinstance(rulebases, Rulebase) else list(rulebases)
        self.players = len(rulebases)
        self.compiled = compile_rulebases(rulebases, vocabulary)
        self.spaces = SoccerSpaces.of(vocabulary, world)

    def __call__(self, observation: dict) -> dict[str, np.ndarray]:
        single = np.ndim(observation["visible"]) == 1
        inputs, visible = self.spaces.engine_inputs(observation)
        rows = inputs.shape[0]
        if self.players not in (1, rows):
            raise ValueError(f"{rows} observations for {self.players} rulebases: give one rulebase or one per row")
        players = np.zeros(rows, dtype=np.int64) if self.players == 1 else np.arange(rows, dtype=np.int64)
        actions, _, values = decide_batch(self.compiled, inputs, visible, players)
        action = self.spaces.actions(actions, values)
        if single:
            return {"skill": np.int64(action["skill"][0]), "parameters": action["parameters"][0]}
        return action
