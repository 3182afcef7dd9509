"""SimpleSoccer as a Gymnasium environment (docs/research/gymnasium.md), "soccer_lab/SimpleSoccer-v0".

Gymnasium is an optional extra (`pip install 'soccer-lab[gymnasium]'`): only this subpackage needs it.
Importing this package registers the environment: Gymnasium 1.x loads no plugins from package entry points,
so `import soccer_lab.soccer.gym` comes first, or the id names the module to import,
`gymnasium.make("soccer_lab.soccer.gym:soccer_lab/SimpleSoccer-v0")`.
"""

from __future__ import annotations

import gymnasium

ENV_ID = "soccer_lab/SimpleSoccer-v0"


def register_envs() -> None:
    """Register SimpleSoccer with Gymnasium (once, however often this package is imported)."""
    if ENV_ID not in gymnasium.registry:
        gymnasium.register(ENV_ID, entry_point="soccer_lab.soccer.gym.env:SimpleSoccerEnv",
                           vector_entry_point="soccer_lab.soccer.gym.vector:SimpleSoccerVectorEnv")


register_envs()
