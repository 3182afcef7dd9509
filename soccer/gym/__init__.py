"""SimpleSoccer as a Gymnasium environment (docs/research/gymnasium.md), "soccer_lab/SimpleSoccer-v0".

Gymnasium is an optional extra (`pip install 'soccer-lab[gymnasium]'`): only this subpackage needs it.
Gymnasium registers the environment itself through the package's "gymnasium.envs" entry point (it calls
`register_envs` when it is imported), so `gymnasium.make("soccer_lab/SimpleSoccer-v0")` works without
importing soccer-lab first; importing this package registers it too.
"""

from __future__ import annotations

import gymnasium

ENV_ID = "soccer_lab/SimpleSoccer-v0"


def register_envs() -> None:
    """Register SimpleSoccer with Gymnasium (once: the entry point and an import may both ask)."""
    if ENV_ID not in gymnasium.registry:
        gymnasium.register(ENV_ID, entry_point="soccer_lab.soccer.gym.env:SimpleSoccerEnv",
                           vector_entry_point="soccer_lab.soccer.gym.vector:SimpleSoccerVectorEnv")


register_envs()
