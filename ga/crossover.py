"""Cut-and-splice crossover (the chapter, 4): parents may differ in length, so each gets its own cut points.

Cuts fall strictly inside a parent (between genes 1..n-1), so every head and tail is non-empty and
children keep at least MIN_LENGTH genes. Children longer than `max_length` are truncated.
"""

from __future__ import annotations

import numpy as np

from ga.genes import MIN_LENGTH


def one_point(a: np.ndarray, b: np.ndarray, max_length: int,
              rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """child 1 = head of a + tail of b, child 2 = head of b + tail of a."""
    i, j = _cuts(a, 1, rng)[0], _cuts(b, 1, rng)[0]
    return (np.concatenate((a[:i], b[j:]))[:max_length],
            np.concatenate((b[:j], a[i:]))[:max_length])


def two_point(a: np.ndarray, b: np.ndarray, max_length: int,
              rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The middle segments, between each parent's two cuts, are swapped."""
    i1, i2 = _cuts(a, 2, rng)
    j1, j2 = _cuts(b, 2, rng)
    return (np.concatenate((a[:i1], b[j1:j2], a[i2:]))[:max_length],
            np.concatenate((b[:j1], a[i1:i2], b[j2:]))[:max_length])


def _cuts(parent: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    if len(parent) < MIN_LENGTH:
        raise ValueError(f"crossover needs parents of at least {MIN_LENGTH} genes, got {len(parent)}")
    return np.sort(rng.integers(1, len(parent), size=count))


CROSSOVERS = {"one-point": one_point, "two-point": two_point}
