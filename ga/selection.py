"""Parent selection (spec 3.2). Fitness is minimised; each function returns population indices."""

from __future__ import annotations

import numpy as np

# Roulette weights are 1/fitness: a perfect fitness of 0 would weigh infinitely, so floor it.
FITNESS_FLOOR = 1e-9


def roulette(fitness: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """Draw `count` indices with probability proportional to 1/fitness."""
    weights = 1.0 / np.maximum(fitness, FITNESS_FLOOR)
    return rng.choice(len(fitness), size=count, p=weights / weights.sum())


def tournament(fitness: np.ndarray, count: int, rng: np.random.Generator, size: int = 2,
               selector: float = 0.75) -> np.ndarray:
    """Each winner: `size` entrants drawn uniformly; the best wins with probability `selector`,
    else the second best with probability `selector`, and so on; the worst takes what remains."""
    entrants = rng.integers(0, len(fitness), size=(count, size))
    ranked = np.take_along_axis(entrants, np.argsort(fitness[entrants], axis=1, kind="stable"), axis=1)
    # Rank r wins when the first r "does the better win?" draws fail and draw r succeeds.
    better_wins = rng.random((count, size - 1)) < selector
    rank = np.where(better_wins.any(axis=1), better_wins.argmax(axis=1), size - 1)
    return ranked[np.arange(count), rank]


def elite(fitness: np.ndarray, count: int) -> np.ndarray:
    """The `count` best, best first (ties keep population order)."""
    return np.argsort(fitness, kind="stable")[:count]
