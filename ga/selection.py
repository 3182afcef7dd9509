"""Parent selection. Fitness is minimised; each function returns population indices."""

from __future__ import annotations

import numpy as np

# Inverse weights are 1/fitness: a perfect fitness of 0 would weigh infinitely, so floor it.
FITNESS_FLOOR = 1e-9


def roulette_weights(fitness: np.ndarray, weighting: str) -> np.ndarray:
    """The chapter names only "roulette wheel"; minimised fitness needs a transform to a weight.
    `linear`: 1 - fitness, so a player that never kicked (1.0) weighs nothing and a 10-goal player
    (0.05) weighs 0.95 / 0.5 = 1.9x a player that moved the ball to the goal mouth (0.5).
    `inverse`: 1 / fitness, so the 10-goal player weighs 20x a player that never kicked."""
    if weighting == "linear":
        return np.clip(1.0 - fitness, 0.0, None)
    if weighting == "inverse":
        return 1.0 / np.maximum(fitness, FITNESS_FLOOR)
    raise ValueError(f"unknown roulette weighting {weighting!r}; expected linear or inverse")


def roulette(fitness: np.ndarray, count: int, rng: np.random.Generator, weighting: str) -> np.ndarray:
    """Draw `count` indices with probability proportional to their weight (`roulette_weights`); when
    every weight is 0 (nobody kicked, under `linear`) every individual is equally likely."""
    weights = roulette_weights(fitness, weighting)
    total = weights.sum()
    if total <= 0.0:
        return rng.integers(0, len(fitness), size=count)
    return rng.choice(len(fitness), size=count, p=weights / total)


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
