"""A splitmix64 stream per game: each game draws from its own seed, so its result never depends on
which batch it is played in (docs/design.md, "A game does not depend on its batch")."""

from __future__ import annotations

import numba
import numpy as np

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_S30, _S27, _S31, _S11 = np.uint64(30), np.uint64(27), np.uint64(31), np.uint64(11)
_UNIT = 1.0 / 9007199254740992.0  # 2**-53
SEED_MASK = (1 << 64) - 1


def mix64(value: int) -> int:
    """splitmix64's output for state `value` (any Python int): a well-spread 64-bit hash."""
    z = (int(value) + int(_GOLDEN)) & SEED_MASK
    z = ((z ^ (z >> int(_S30))) * int(_MIX1)) & SEED_MASK
    z = ((z ^ (z >> int(_S27))) * int(_MIX2)) & SEED_MASK
    return z ^ (z >> int(_S31))


def seed_states(seeds) -> np.ndarray:
    """One uint64 stream state per seed (any Python int)."""
    return np.array([int(s) & SEED_MASK for s in seeds], dtype=np.uint64)


@numba.njit(cache=True)
def next_uniform(states, g):
    """Advance game g's stream; a float in [0, 1)."""
    z = states[g] + _GOLDEN
    states[g] = z
    z = (z ^ (z >> _S30)) * _MIX1
    z = (z ^ (z >> _S27)) * _MIX2
    z = z ^ (z >> _S31)
    return float(z >> _S11) * _UNIT


@numba.njit(cache=True)
def uniform(states, g, low, high):
    return low + (high - low) * next_uniform(states, g)
